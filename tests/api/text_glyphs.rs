//! Every glyph of every shipped font (A–Z, a–z, 0–9, common punctuation and a sample of
//! the Latin-1 letters and signs) outlines
//! without error at heights 10, 40 and 150 mm and two stroke widths (issue 12).

use skinpath::design::Design;
use skinpath::design::text::{Font, Text};
use skinpath::job::outline::{OutlineOptions, design_outlines};

/// Letters, digits and the punctuation of signs and addresses.
const GLYPHS: &str = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789.,:;!?'\"-+&()/#@%*=$éÜñßçÅæÆØ¡¿«°";

/// Stroke widths as fractions of the cap height: a thin engraving line and a bold neon
/// tube (8 mm flex on 80 mm letters is 1/10).
const WIDTHS: [f64; 2] = [1.0 / 25.0, 1.0 / 9.0];
const HEIGHTS: [f64; 3] = [10.0, 40.0, 150.0];
/// Skin accuracy and flattening tolerance as a fraction of the cap height (0.025 mm at
/// 10 mm, 0.375 mm at 150 mm): the glyphs' shapes, not the accuracy, are under test, and
/// the run stays near a minute.
const REL_EPSILON: f64 = 2.5e-3;

fn design(text: Text) -> Design {
    // Parsed without validation: a design of text alone is laid out by `expand` (loading
    // refuses a design that is still empty).
    let mut d: Design = toml::from_str("version = 1\n").unwrap();
    d.file = "glyph.toml".into();
    d.text.push(text);
    d.expand().unwrap();
    d
}

#[test]
fn every_glyph_outlines_at_three_heights_and_two_widths() {
    let mut failures = Vec::new();
    let mut count = 0;
    for font in Font::ALL {
        for h in HEIGHTS {
            for w in WIDTHS {
                for c in GLYPHS.chars() {
                    let mut t = Text::new("g", &c.to_string(), h, w * h);
                    t.font = font;
                    let d = design(t);
                    // Accuracy relative to the letter size (the default ε of 0.01 mm on a
                    // 150 mm letter costs minutes of knot insertion and shows nothing).
                    let opts = OutlineOptions {
                        epsilon: REL_EPSILON * h,
                        tolerance: REL_EPSILON * h,
                        ..OutlineOptions::default()
                    };
                    count += 1;
                    if let Err(e) = design_outlines(&d, &opts) {
                        failures.push(format!("{} {c:?} h {h} w {}: {e}", font.as_str(), w * h));
                    }
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {count} failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
