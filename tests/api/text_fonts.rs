//! The script sign's golden (the font unit tests are in src/design/fonts/tests.rs).

use crate::support;

#[test]
fn script_sign_with_accent_and_ampersand_builds_clean_and_matches_the_golden() {
    // `skinpath text "Café & Bar" --font script --height 22 --neon`, built with default
    // flags on the router and the laser: exit 0, no findings, checked clean by `check`
    // with the same profile, the program equal to the golden (SKINPATH_BLESS=1 rewrites).
    let built = support::neon_text_matches_golden("Caf\u{e9} & Bar", "script", "22", "cafe_script");
    for (machine, summary) in built {
        let runs = summary["neon"]["runs"].as_array().unwrap();
        assert!(!runs.is_empty(), "{machine}");
    }
}
