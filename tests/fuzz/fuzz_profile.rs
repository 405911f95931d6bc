//! Fuzz target: the machine profile parser and validation. See tests/support/fuzz.rs.

use crate::support;
use skinpath::machine::Profile;
use support::fuzz::{cases, corpus, fuzz};

#[test]
fn fuzz_machine_profiles() {
    let seeds = corpus("machines", &["toml"]);
    let s = fuzz("profile", &seeds, cases(400), |t| {
        match Profile::from_toml(t, "fuzz.toml") {
            Ok(p) => {
                // What validation promises the emitters: usable tool sizes.
                for tool in &p.tools {
                    let r = tool.radius() * p.units.mm_per_unit();
                    assert!((0.0005..=500.0).contains(&r), "{tool:?}");
                }
                true
            }
            Err(e) => {
                assert!(e.to_string().starts_with("fuzz.toml"), "{e}");
                false
            }
        }
    });
    assert!(s.accepted >= seeds.len());
}
