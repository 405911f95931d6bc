//! Fuzz target: the G-code interpreter and checker through their public API
//! (`sim::check_text`), seeded with the simulator corpus. See tests/support/fuzz.rs.

use crate::support;
use skinpath::job::check::check_config;
use skinpath::machine::builtin_profile;
use skinpath::sim::{Backend, check_text};
use support::fuzz::{cases, corpus, fuzz};

#[test]
fn fuzz_gcode_checker() {
    let seeds = corpus("tests/sim_corpus", &["nc", "gcode", "ngc"]);
    assert!(!seeds.is_empty());
    let profiles = ["grbl-router", "grbl-laser", "linuxcnc-router"];
    let cfgs: Vec<_> = profiles
        .iter()
        .map(|n| {
            let p = builtin_profile(n).unwrap().unwrap();
            let r = p.default_tool().map(|t| t.radius()).unwrap_or(0.0);
            check_config(&p, r)
        })
        .collect();
    let mut k = 0;
    fuzz("gcode", &seeds, cases(300), |t| {
        k += 1;
        let cfg = &cfgs[k % cfgs.len()];
        let r = check_text(Backend::Builtin, t, cfg, &[]);
        // The report renders, and counts what it lists.
        let _ = r.to_string();
        r.errors() == 0
    });
}
