//! `[neon] round_bends` and `min_run_length` (issue 41 items 2 and 4): a hairpin too narrow
//! for the radius warned about and left as drawn; short runs warned about, and made marks
//! on request. The V corner and the 1 mm hairpin against their closed-form fillets are unit
//! tests of the library's `job::neon` (src/job/neon/tests.rs).

use crate::support;

use skinpath::design::{Design, load};
use skinpath::job::{BuildOptions, build_toolpath};
use skinpath::machine::builtin_profile;
use support::{skinpath_in, tmpdir};

/// Flex minimum radius of the tests (mm).
const R: f64 = 5.0;

fn design(body: &str, extra: &str) -> Design {
    let text = format!(
        "version = 1\nunits = \"mm\"\n[neon]\nmin_bend_radius = {R}\n{extra}\n{body}\n[[operation]]\nkind = \"channel\"\n[[operation]]\nkind = \"holes\"\n"
    );
    load(&text, "round.toml").unwrap()
}

#[test]
fn a_hairpin_too_narrow_for_the_radius_is_warned_about_and_cut_as_drawn() {
    // A U two millimetres wide: no arc of radius 5 fits between its legs.
    let u = "[[stroke]]\nname = \"u\"\npoints = [[0, 50, 1], [0, 0, 1], [2, 0, 1], [2, 50, 1]]\ncorners = [1, 2]\n";
    let dir = tmpdir("neon-round-u");
    let mut programs = Vec::new();
    for extra in ["", "round_bends = true"] {
        let text = format!(
            "version = 1\nunits = \"mm\"\n[neon]\nmin_bend_radius = {R}\n{extra}\n{u}\n[[operation]]\nkind = \"channel\"\n"
        );
        std::fs::write(dir.join("u.toml"), text).unwrap();
        let o = skinpath_in(
            &[
                "build",
                "u.toml",
                "--machine",
                "grbl-router",
                "-o",
                "u.gcode",
                "--json",
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let round: Vec<_> = j["neon"]["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "round")
            .collect();
        if extra.is_empty() {
            assert!(round.is_empty());
            assert!(j["neon"]["runs"][0].get("rounded_bends").is_none());
        } else {
            assert_eq!(round.len(), 2, "one per corner: {round:?}");
            assert!(round[0]["message"].as_str().unwrap().contains("too short"));
            assert_eq!(j["neon"]["runs"][0]["rounded_bends"], 0);
        }
        programs.push(std::fs::read_to_string(dir.join("u.gcode")).unwrap());
    }
    assert_eq!(
        programs[0], programs[1],
        "nothing rounded: the same program"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 100 mm stroke and a 4 mm accent mark 20 mm away.
const WORD_AND_MARK: &str = "[[stroke]]\nname = \"word\"\ndisks = [[0, 0, 1], [100, 0, 1]]\n[[stroke]]\nname = \"mark\"\ndisks = [[48, 20, 1], [52, 20, 1]]\n";

#[test]
fn runs_shorter_than_the_cut_unit_are_warned_about_and_marks_on_request() {
    let b = |extra: &str| {
        let d = design(WORD_AND_MARK, extra);
        build_toolpath(
            &d,
            &builtin_profile("grbl-router").unwrap(),
            &BuildOptions::default(),
        )
        .unwrap()
        .neon
        .unwrap()
    };
    let plain = b("");
    assert_eq!(plain.runs.len(), 2);
    assert!(plain.holes > 2, "the mark is drilled too");
    let short: Vec<_> = plain
        .warnings
        .iter()
        .filter(|w| w.kind == "short")
        .collect();
    assert_eq!(short.len(), 1, "{:?}", plain.warnings);
    assert!(
        short[0].message.contains("\"mark\""),
        "{}",
        short[0].message
    );
    assert!(short[0].message.contains("4.00 mm"), "{}", short[0].message);
    assert!(
        short[0].message.contains("25.00 mm"),
        "{}",
        short[0].message
    );
    let marked = b("min_run_length = 10");
    assert_eq!(marked.runs.len(), 1, "the mark is no flex run");
    assert_eq!(marked.runs[0].strokes, vec!["word".to_string()]);
    assert_eq!(marked.holes, 2, "no wire holes for the mark");
    assert_eq!(marked.marks.len(), 1);
    assert!((marked.marks[0].length_mm - 4.0).abs() <= 1e-9);
    assert!((marked.total_length_mm - 100.0).abs() <= 1e-9);
    assert!(marked.warnings.iter().all(|w| w.kind != "short"));
    let e = load(
        "version = 1\n[neon]\nmin_run_length = -1\n[[stroke]]\nname = \"s\"\ndisks = [[0, 0, 1], [9, 9, 1]]\n",
        "bad.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("[neon] min_run_length"), "{e}");
}
