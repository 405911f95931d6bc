//! Fuzz target: the SVG importer (usvg parsing, units, transforms, `use`, shapes, fills and
//! strokes, the DBSC fit of each stroke's centre line). Every mutated file either imports to a
//! design that validates, builds its curves and writes itself back as TOML, or is refused
//! with a message that starts with the file's name; a panic is a crash. Seeds: the SVGs
//! shipped in examples/gallery and tests/golden and a few small drawings with the features
//! that are hard to get right. See tests/fuzz_common for the mutator and the env variables.

mod fuzz_common;
use fuzz_common::{cases, corpus, fuzz};
use skinpath::design::svg::{ImportOptions, import};

/// Small drawings: nested transforms and `use`, units and a scaled viewBox, arcs, a filled
/// ring with a hole (evenodd), a Power-Stroke-like widths attribute, degenerate numbers.
const SEEDS: &[&str] = &[
    r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="100mm" height="50mm" viewBox="0 0 200 100"><defs><path id="p" d="M10 10 C 40 80 80 -20 120 40" stroke="black" stroke-width="4" fill="none"/></defs><g transform="translate(5 5) rotate(10)"><use xlink:href="#p" transform="scale(0.5)"/></g></svg>"##,
    r##"<svg xmlns="http://www.w3.org/2000/svg" width="4in" height="2in" viewBox="0 0 400 200"><path d="M20 100 A 60 40 30 1 1 200 100 L 380 20" stroke="#000" stroke-width="8" fill="none" data-skinpath-widths="2 6 3 1"/></svg>"##,
    r##"<svg xmlns="http://www.w3.org/2000/svg" width="80" height="80"><path fill-rule="evenodd" d="M0 0 H80 V80 H0 Z M20 20 H60 V60 H20 Z" fill="red"/><circle cx="40" cy="40" r="0.0001" fill="blue"/></svg>"##,
    r##"<svg xmlns="http://www.w3.org/2000/svg" width="10cm" height="10cm" viewBox="0 0 1e-3 1e-3"><line x1="0" y1="0" x2="1e-3" y2="1e-3" stroke="black" stroke-width="1e-5"/><polyline points="0,0 1e-4,0 1e-4,1e-4" stroke="black" stroke-width="2e-5" fill="none"/></svg>"##,
];

#[test]
fn fuzz_svg_import() {
    let mut seeds = corpus("examples/gallery", &["svg"]);
    seeds.extend(corpus("tests/golden", &["svg"]));
    seeds.extend(
        SEEDS
            .iter()
            .enumerate()
            .map(|(i, s)| (format!("seed{i}.svg"), s.to_string())),
    );
    let file = "fuzz.svg";
    let s = fuzz("svg", &seeds, cases(150), |text| {
        match import(text, file, &ImportOptions::default()) {
            Ok(imp) => {
                // An imported design is a valid design: its curves build and it writes itself.
                imp.design
                    .strokes()
                    .expect("an imported design builds its strokes");
                imp.design.to_toml_string().expect("writes TOML");
                true
            }
            Err(e) => {
                assert!(e.to_string().starts_with(file), "{e}");
                false
            }
        }
    });
    // The gallery drawings import.
    assert!(s.accepted >= 2, "{s:?}");
}
