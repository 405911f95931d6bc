//! Fuzz target: the SVG importer (usvg parsing, units, transforms, `use`, shapes, fills and
//! strokes, the DBSC fit of each stroke's centre line). Every mutated file either imports to a
//! design that validates, builds its curves and writes itself back as TOML, or is refused
//! with a message that starts with the file's name; a panic is a crash. Seeds: the SVGs
//! shipped in examples/gallery and tests/golden and a few small drawings with the features
//! that are hard to get right. See tests/support/fuzz.rs for the mutator and the env variables.

use crate::support;
use skinpath::design::svg::{ImportOptions, import};
use support::fuzz::{Rng, Stats, cases, corpus, fuzz, run_one, seed};

/// Small drawings: nested transforms and `use`, units and a scaled viewBox, arcs, a filled
/// ring with a hole (evenodd), a Power-Stroke-like widths attribute, degenerate numbers.
const SEEDS: &[&str] = &[
    r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="100mm" height="50mm" viewBox="0 0 200 100"><defs><path id="p" d="M10 10 C 40 80 80 -20 120 40" stroke="black" stroke-width="4" fill="none"/></defs><g transform="translate(5 5) rotate(10)"><use xlink:href="#p" transform="scale(0.5)"/></g></svg>"##,
    r##"<svg xmlns="http://www.w3.org/2000/svg" width="4in" height="2in" viewBox="0 0 400 200"><path d="M20 100 A 60 40 30 1 1 200 100 L 380 20" stroke="#000" stroke-width="8" fill="none" data-skinpath-widths="2 6 3 1"/></svg>"##,
    r##"<svg xmlns="http://www.w3.org/2000/svg" width="80" height="80"><path fill-rule="evenodd" d="M0 0 H80 V80 H0 Z M20 20 H60 V60 H20 Z" fill="red"/><circle cx="40" cy="40" r="0.0001" fill="blue"/></svg>"##,
    r##"<svg xmlns="http://www.w3.org/2000/svg" width="10cm" height="10cm" viewBox="0 0 1e-3 1e-3"><line x1="0" y1="0" x2="1e-3" y2="1e-3" stroke="black" stroke-width="1e-5"/><polyline points="0,0 1e-4,0 1e-4,1e-4" stroke="black" stroke-width="2e-5" fill="none"/></svg>"##,
];

/// The check every input gets: an import is a design that builds its curves and writes
/// itself as TOML, names every skipped and warned element, or an error that starts with
/// the file's name. Returns whether the input was accepted.
fn check(text: &str) -> bool {
    let file = "fuzz.svg";
    match import(text, file, &ImportOptions::default()) {
        Ok(imp) => {
            imp.design
                .strokes()
                .expect("an imported design builds its strokes");
            imp.design.to_toml_string().expect("writes TOML");
            assert!(
                imp.skipped
                    .iter()
                    .chain(&imp.warnings)
                    .all(|s| !s.id.is_empty() && !s.reason.is_empty())
            );
            true
        }
        Err(e) => {
            assert!(e.to_string().starts_with(file), "{e}");
            false
        }
    }
}

const HEAD: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="100mm" height="100mm" viewBox="0 0 100 100">"#;

/// A hostile drawing built from `rng`: deep nesting, huge counts, DOCTYPE entities (and
/// bombs), external entities, many rules, duplicate ids, `use` chains, layered fills that
/// cover and knock each other out, images and text.
fn hostile(rng: &mut Rng) -> String {
    let mut body = String::new();
    let mut doctype = String::new();
    for _ in 0..1 + rng.below(4) {
        match rng.below(10) {
            0 => {
                // Nesting around or beyond the depth limit.
                let depth = *rng.pick(&[10, 200, 255, 257, 400, 5000]);
                body.push_str(&"<g>".repeat(depth));
                body.push_str(r#"<path d="M1 1 H50" stroke="black"/>"#);
                body.push_str(&"</g>".repeat(depth));
            }
            1 => {
                // Many elements, many with the same id.
                let n = *rng.pick(&[100, 1000, 5000]);
                for i in 0..n {
                    let id = if rng.below(2) == 0 {
                        "dup".to_string()
                    } else {
                        format!("e{i}")
                    };
                    body.push_str(&format!(
                        r#"<path id="{id}" d="M{} {} l{} {}" stroke="black"/>"#,
                        rng.range(0.0, 100.0),
                        rng.range(0.0, 100.0),
                        rng.range(-3.0, 3.0),
                        rng.range(-3.0, 3.0)
                    ));
                }
            }
            2 => {
                // Entities: plain, nested, a bomb of some levels, an external one.
                let levels = rng.below(9);
                let mut dtd = String::from(r#"<!ENTITY e0 "black">"#);
                for i in 1..=levels {
                    let refs: String = (0..10).map(|_| format!("&e{};", i - 1)).collect();
                    dtd.push_str(&format!(r#"<!ENTITY e{i} "{refs}">"#));
                }
                if rng.below(3) == 0 {
                    dtd.push_str(r#"<!ENTITY ext SYSTEM "/etc/passwd">"#);
                    body.push_str("<desc>&ext;</desc>");
                }
                doctype = format!("<!DOCTYPE svg [{dtd}]>");
                body.push_str(&format!(
                    r#"<path id="s" d="M0 0 H9" stroke="&e0;"/><desc>&e{levels};</desc>"#
                ));
            }
            3 => {
                // One long path, beyond or within the segment limit.
                let n = *rng.pick(&[50, 9_999, 10_001, 60_000]);
                let mut d = String::from("M0 0");
                for i in 0..n {
                    d.push_str(&format!(" L{} {}", (i % 2) * 10, i as f64 * 1e-3));
                }
                let paint = if rng.below(2) == 0 {
                    r#"stroke="black" fill="none""#
                } else {
                    r#"fill="red""#
                };
                body.push_str(&format!(r#"<path id="long" d="{d}" {paint}/>"#));
            }
            4 => {
                // Many CSS rules.
                let n = *rng.pick(&[10, 1999, 2001, 20_000]);
                let rules: String = (0..n).map(|i| format!(".c{i}{{stroke:red}}")).collect();
                body.push_str(&format!(
                    r#"<style>{rules}</style><path class="c3" d="M0 5 H9"/>"#
                ));
            }
            5 => {
                // `use` chains and a reference cycle.
                body.push_str(r##"<defs><path id="u0" d="M0 0 H5" stroke="black"/></defs>"##);
                for i in 1..50 {
                    body.push_str(&format!(
                        r##"<use id="u{i}" xlink:href="#u{}" x="0.5"/>"##,
                        i - 1
                    ));
                }
                body.push_str(
                    r##"<use id="c1" xlink:href="#c2"/><use id="c2" xlink:href="#c1"/>"##,
                );
            }
            6 => {
                // Layers of overlapping fills: colours, white knockouts, a page background.
                body.push_str(r##"<rect x="0" y="0" width="100" height="100" fill="#123456"/>"##);
                body.push_str(r#"<g inkscape:groupmode="layer" inkscape:label="L">"#);
                for _ in 0..rng.below(60) {
                    let fill = *rng.pick(&["black", "white", "#123456", "red", "#00f"]);
                    body.push_str(&format!(
                        r#"<circle cx="{}" cy="{}" r="{}" fill="{fill}"/>"#,
                        rng.range(0.0, 100.0),
                        rng.range(0.0, 100.0),
                        rng.range(0.0, 30.0)
                    ));
                }
                body.push_str("</g>");
            }
            7 => {
                // A self-crossing fill of random points.
                let n = *rng.pick(&[5, 50, 500, 3000]);
                let pts: String = (0..n)
                    .map(|_| format!("{},{} ", rng.range(0.0, 100.0), rng.range(0.0, 100.0)))
                    .collect();
                body.push_str(&format!(r#"<polygon id="x" points="{pts}" fill="black"/>"#));
            }
            8 => {
                // Things never read or not imported.
                body.push_str(r#"<image href="/dev/zero" width="5" height="5"/><image href="../../etc/passwd" width="5" height="5"/><text>t</text><path d="M0 0 L 5 zz" stroke="black"/>"#);
            }
            _ => {
                // Degenerate strokes: widths, closings, tiny and huge.
                let w = *rng.pick(&["0", "-5", "1e-9", "1e9", "nan", "0.1"]);
                body.push_str(&format!(
                    r#"<path d="M10 10 L10.00001 10 Z" stroke="black" stroke-width="{w}"/><path d="M0 0 L1e12 0" stroke="black" stroke-width="{w}"/>"#
                ));
            }
        }
    }
    format!(r#"<?xml version="1.0"?>{doctype}{HEAD}{body}</svg>"#)
}

/// Hostile structure (deep nesting, huge counts, DOCTYPE entities): a fixed number of
/// drawings from the fixed seed, each imported or refused with the file's name, in bounded
/// work (every count is checked before the work it would cost).
#[test]
fn fuzz_svg_hostile_structure() {
    let mut rng = Rng::new(seed("svg-hostile"));
    let mut stats = Stats::default();
    for _ in 0..cases(40) {
        let text = hostile(&mut rng);
        run_one("svg-hostile", &text, &mut stats, check);
    }
    println!("svg-hostile: {stats:?}");
    assert!(stats.accepted > 0, "{stats:?}");
    assert!(stats.accepted < stats.executions, "{stats:?}");
}

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
    seeds.extend(corpus("tests/svg_real", &["svg"]));
    let mut rng = Rng::new(seed("svg-seeds"));
    seeds.extend((0..4).map(|i| (format!("hostile{i}.svg"), hostile(&mut rng))));
    let s = fuzz("svg", &seeds, cases(150), check);
    // The gallery drawings import.
    assert!(s.accepted >= 2, "{s:?}");
}
