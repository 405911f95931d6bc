//! Golden neon builds of a sans sign with accents and an ampersand (issue 41, tests):
//! `skinpath text "Crème & Brûlée" --font sans --height 18 --neon`, built with default
//! flags on grbl-router and grbl-laser: exit 0, no findings, checked clean by `check`,
//! one wire hole per open run end and one per closed run, the accent marks warned about
//! as runs shorter than the cut unit, and the program equal to tests/golden within
//! [`common::GOLDEN_TOL`] (`SKINPATH_BLESS=1` rewrites).

mod common;

use common::{assert_golden, skinpath, tmpdir};

#[test]
fn sans_sign_with_accents_and_ampersand_builds_clean_and_matches_the_golden() {
    let dir = tmpdir("neon-golden-sans");
    let design = dir.join("creme.toml");
    let d = design.to_str().unwrap();
    let t = skinpath(&[
        "text",
        "Cr\u{e8}me & Br\u{fb}l\u{e9}e",
        "--font",
        "sans",
        "--height",
        "18",
        "--neon",
        "-o",
        d,
    ]);
    assert!(t.status.success(), "{}", String::from_utf8_lossy(&t.stderr));
    for machine in ["grbl-router", "grbl-laser"] {
        let out = dir.join(format!("creme-{machine}.gcode"));
        let o = out.to_str().unwrap();
        let b = skinpath(&["build", d, "--machine", machine, "-o", o, "--json"]);
        assert!(
            b.status.success(),
            "{machine}: {}",
            String::from_utf8_lossy(&b.stderr)
        );
        let summary: serde_json::Value = serde_json::from_slice(&b.stdout).unwrap();
        assert_eq!(
            summary["findings"].as_array().map(Vec::len),
            Some(0),
            "{machine}"
        );
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
        let c = skinpath(&["check", o, "--machine", machine]);
        assert!(
            c.status.success(),
            "{machine}: {}",
            String::from_utf8_lossy(&c.stdout)
        );
        let got = std::fs::read_to_string(&out).unwrap();
        assert_golden(&got, &format!("creme_sans.{machine}.gcode"), machine);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
