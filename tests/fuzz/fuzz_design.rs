//! Fuzz target: the design parser and validation (TOML and JSON), and the curves built from
//! every design that loads. See tests/support/fuzz.rs for the mutator and the env variables.

use crate::support;
use support::fuzz::{cases, corpus, fuzz};

fn accept(text: &str, file: &str) -> bool {
    match skinpath::design::load(text, file) {
        Ok(d) => {
            // A loaded design always builds its curves (validation promises it).
            d.strokes().expect("a loaded design builds its strokes");
            let _ = d.circle_sequences();
            // And writes itself back in both formats.
            d.to_toml_string().expect("writes TOML");
            d.to_json_string().expect("writes JSON");
            true
        }
        Err(e) => {
            // Every error names the file.
            assert!(e.to_string().starts_with(file), "{e}");
            false
        }
    }
}

#[test]
fn fuzz_design_toml() {
    let seeds = corpus("examples", &["toml"]);
    let s = fuzz("design-toml", &seeds, cases(300), |t| {
        accept(t, "fuzz.toml")
    });
    assert!(s.accepted >= seeds.len());
}

#[test]
fn fuzz_design_json() {
    let seeds: Vec<(String, String)> = corpus("examples", &["toml"])
        .into_iter()
        .map(|(n, t)| {
            let d = skinpath::design::load(&t, &n).unwrap();
            (n, d.to_json_string().unwrap())
        })
        .collect();
    let s = fuzz("design-json", &seeds, cases(300), |t| {
        accept(t, "fuzz.json")
    });
    assert!(s.accepted >= seeds.len());
}
