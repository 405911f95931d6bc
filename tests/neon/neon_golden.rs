//! Golden neon builds of a sans sign with accents and an ampersand (issue 41, tests):
//! `skinpath text "Crème & Brûlée" --font sans --height 18 --neon`, built with default
//! flags on grbl-router and grbl-laser: exit 0, no findings, checked clean by `check`,
//! one wire hole per open run end and one per closed run, the accent marks warned about
//! as runs shorter than the cut unit, and the program equal to tests/golden within
//! [`support::GOLDEN_TOL`] (`SKINPATH_BLESS=1` rewrites).

use crate::support;

#[test]
fn sans_sign_with_accents_and_ampersand_builds_clean_and_matches_the_golden() {
    let built = support::neon_text_matches_golden(
        "Cr\u{e8}me & Br\u{fb}l\u{e9}e",
        "sans",
        "18",
        "creme_sans",
    );
    for (machine, summary) in built {
        let neon = &summary["neon"];
        let runs = neon["runs"].as_array().unwrap();
        let ends: u64 = runs
            .iter()
            .map(|r| if r["closed"] == true { 1 } else { 2 })
            .sum();
        assert_eq!(
            neon["holes"].as_u64(),
            Some(ends),
            "{machine}: holes at run ends"
        );
        // The grave of è and the acute of é are runs of their own, a few mm long.
        let short: Vec<&str> = neon["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "short")
            .map(|w| w["message"].as_str().unwrap())
            .collect();
        for mark in ["text/2:ue8/1", "text/12:ue9/1"] {
            assert!(
                short.iter().any(|m| m.contains(mark)),
                "{machine}: {mark} in {short:?}"
            );
        }
    }
}
