//! `skinpath text`, `skinpath init` and the text layout measured on the built strokes
//! (issue 12 items 4 and 5, and its "Done when").

use skinpath::design::load;
use skinpath::design::text::smooth;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_skinpath")
}

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("skinpath-text-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(args: &[&str], files: &[&Path]) -> std::process::Output {
    let mut c = Command::new(bin());
    c.args(args);
    for f in files {
        c.arg(f);
    }
    c.output().unwrap()
}

/// Build `design` on `machine` with default flags and check the program with the same
/// profile and no flags.
fn build_and_check(design: &Path, machine: &str, dir: &Path) {
    let ext = if machine == "svg-laser" {
        "svg"
    } else {
        "gcode"
    };
    let out = dir.join(format!("out-{machine}.{ext}"));
    let b = Command::new(bin())
        .arg("build")
        .arg(design)
        .args(["--machine", machine, "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        b.status.success(),
        "{} on {machine}: {}",
        design.display(),
        String::from_utf8_lossy(&b.stderr)
    );
    if ext == "gcode" {
        let c = Command::new(bin())
            .arg("check")
            .arg(&out)
            .args(["--machine", machine])
            .output()
            .unwrap();
        assert!(
            c.status.success(),
            "{} on {machine}: {}",
            design.display(),
            String::from_utf8_lossy(&c.stdout)
        );
    }
}

#[test]
fn open_sign_from_a_fresh_start_builds_clean_on_the_router() {
    let dir = tmp("open");
    let design = dir.join("open.toml");
    let t = run(&["text", "OPEN", "-o"], &[&design]);
    assert!(t.status.success(), "{}", String::from_utf8_lossy(&t.stderr));
    build_and_check(&design, "grbl-router", &dir);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn words_in_both_fonts_build_and_check() {
    let dir = tmp("words");
    // Script words on a router (outside cuts around loops that nearly close) need the
    // union of overlapping strokes (issue 12 item 2): lasers here, all three for sans.
    for (word, font, machines) in [
        (
            "Neon 42!",
            "sans",
            &["grbl-laser", "grbl-router", "svg-laser"][..],
        ),
        ("Bar & Grill", "script", &["grbl-laser", "svg-laser"][..]),
    ] {
        let design = dir.join(format!("{font}.toml"));
        let t = run(
            &[
                "text", word, "--font", font, "--height", "25", "--width", "3", "-o",
            ],
            &[&design],
        );
        assert!(t.status.success(), "{}", String::from_utf8_lossy(&t.stderr));
        for m in machines {
            build_and_check(&design, m, &dir);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Channels along lettering on routers: the strokes of a word overlap (retraced strokes of
/// the script font, corner pieces, joins), their union is a dense polygon, and cavalier's
/// first clearing ring of it cut across a letter's counter with one long chord (seen as
/// dozens of crossings on script "neon", "Hello" and sans "mmm", "LOVE"). The first ring is
/// checked now as the later ones are, and every such word builds and checks clean.
#[test]
fn words_with_channels_build_and_check_on_routers() {
    let dir = tmp("channels");
    for (word, font, machine) in [
        ("neon", "script", "grbl-router"),
        ("Hello", "script", "linuxcnc-router"),
        ("mmm", "sans", "linuxcnc-router"),
        ("LOVE", "sans", "linuxcnc-router"),
    ] {
        let design = word_design(
            &dir,
            &format!("{font}-{word}"),
            &[word, "--font", font, "--height", "60"],
            "\n[[operation]]\nkind = \"channel\"\nwidth = 8.5\ndepth = 12.0\nstep_down = 3.0\n",
        );
        build_and_check(&design, machine, &dir);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Words on a laser-cut backboard: the board comes out in pieces with 2.4 mm gaps between
/// letters (the two l's of "Hello", the m's of "mmm"), and a lead-in (radius 3, on the
/// waste side, into the gap) crossed the piece beyond, or the lead of the piece beyond.
/// Leads now stay clear of the operation's other contours and of the leads run before.
#[test]
fn lettering_on_a_laser_backboard_builds_and_checks() {
    let dir = tmp("board");
    for word in ["Hello", "mmm"] {
        let design = word_design(
            &dir,
            word,
            &[word, "--height", "80"],
            &board_operations(5.0),
        );
        build_and_check(&design, "grbl-laser", &dir);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `skinpath text TEXT_ARGS -o DIR/NAME.toml`, with `operations` (TOML) appended: the
/// design's path.
fn word_design(dir: &Path, name: &str, text_args: &[&str], operations: &str) -> PathBuf {
    let design = dir.join(format!("{name}.toml"));
    let mut args = vec!["text"];
    args.extend_from_slice(text_args);
    args.push("-o");
    let t = run(&args, &[&design]);
    assert!(t.status.success(), "{}", String::from_utf8_lossy(&t.stderr));
    let mut text = std::fs::read_to_string(&design).unwrap();
    text.push_str(operations);
    std::fs::write(&design, text).unwrap();
    design
}

/// A channel of `width` along the strokes (10 deep in two passes) and a backboard (margin
/// 12, 15 deep in three passes, four tabs, lead-in radius 3).
fn board_operations(width: f64) -> String {
    format!(
        "\n[[operation]]\nkind = \"channel\"\nwidth = {width:?}\ndepth = 10.0\nstep_down = 5.0\n\
         \n[[operation]]\nkind = \"backboard\"\nmargin = 12.0\ndepth = 15.0\npasses = 3\n\
         tabs = {{ count = 4, width = 6.0, height = 2.0 }}\nlead_in = 3.0\n",
    )
}

/// Words with wide channels on a routed backboard. Script "Hello" and "Quiz" (and "coffee"):
/// the channels' clearing rings cut across letters' counters with single chords (rings
/// must now keep apart from the channel's walls) and crossed the board's holes. Sans "mmm"
/// on linuxcnc-router (inches): the board's lead-out, tangent at the contour's start,
/// crossed the first pass 0.2 mm on, where the contour turned sharply toward the waste.
#[test]
fn lettering_with_wide_channels_on_a_routed_backboard_builds_and_checks() {
    let dir = tmp("routed-board");
    for (font, word, machine) in [
        ("sans", "mmm", "linuxcnc-router"),
        ("script", "Hello", "grbl-router"),
        ("script", "Quiz", "grbl-router"),
    ] {
        let design = word_design(
            &dir,
            word,
            &[word, "--font", font, "--height", "80", "--width", "4"],
            &board_operations(10.0),
        );
        build_and_check(&design, machine, &dir);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Lettering cut out around in two passes with arc leads. Sans "mmm" on marlin-laser: an
/// outline started next to a 5 µm arc, which rounding to 1 µm turned 8°, and the last
/// pass's lead-out crossed both passes there. Leads now start next to segments long enough
/// for the rounding.
#[test]
fn lettering_cut_out_with_leads_builds_and_checks() {
    let dir = tmp("cut-out-leads");
    for (font, word) in [("sans", "mmm"), ("script", "Quiz")] {
        let design = word_design(
            &dir,
            word,
            &[word, "--font", font, "--height", "40", "--width", "4"],
            "\n[[operation]]\nkind = \"profile\"\nside = \"outside\"\ndepth = 3.0\n\
             passes = 2\nlead_in = 2.0\n",
        );
        for machine in ["marlin-laser", "grbl-laser", "grbl-router"] {
            build_and_check(&design, machine, &dir);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A fill of 4 mm lettering with the 1/4" bit of linuxcnc-router cuts nothing: the refusal
/// names the operation and the reason instead of "add strokes" (the strokes are there).
#[test]
fn a_fill_narrower_than_the_tool_is_named() {
    let dir = tmp("fill");
    let design = word_design(
        &dir,
        "hello",
        &["Hello", "--height", "30"],
        "\n[[operation]]\nkind = \"fill\"\ndepth = 2.0\nspacing = 1.5\n",
    );
    let out = dir.join("out.gcode");
    let b = Command::new(bin())
        .arg("build")
        .arg(&design)
        .args(["--machine", "linuxcnc-router", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&b.stderr);
    assert_eq!(b.status.code(), Some(2), "{err}");
    assert!(
        err.contains("[[operation]] 1 (fill 1) came out empty") && err.contains("narrower than"),
        "{err}"
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn open_at_80_mm_measures_80_mm_cap_line_to_baseline() {
    let dir = tmp("measure");
    let design = dir.join("open.toml");
    let t = run(
        &["text", "OPEN", "--height", "80", "--width", "8", "-o"],
        &[&design],
    );
    assert!(t.status.success());
    let d = load(&std::fs::read_to_string(&design).unwrap(), "open.toml").unwrap();
    // Extent of the spines (the centre lines the flex follows), sampled densely: the
    // straight letters E and N run exactly from baseline to cap line; the smooth spines of
    // the O and of the P's bowl lie within the fit tolerance of Hershey's polylines, so
    // their tops and bottoms are within that of the cap line and the baseline.
    const TOLERANCE: f64 = 0.05;
    let round_tolerance = 2.0 * smooth::FIT_TOLERANCE * 80.0 / 21.0;
    let extent = |pick: &dyn Fn(&str) -> bool| {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (s, c) in d.stroke.iter().zip(d.strokes().unwrap()) {
            if !pick(&s.name) {
                continue;
            }
            let (a, b) = c.domain();
            for i in 0..=400 {
                let y = c.center(a + (b - a) * i as f64 / 400.0).y;
                lo = lo.min(y);
                hi = hi.max(y);
            }
        }
        hi - lo
    };
    let straight = extent(&|n: &str| n.contains(":E/") || n.contains(":N/"));
    assert!(
        (straight - 80.0).abs() <= TOLERANCE,
        "cap line to baseline {straight}"
    );
    for letter in [":O/", ":P/"] {
        let round = extent(&|n: &str| n.contains(letter));
        assert!((round - 80.0).abs() <= round_tolerance, "{letter} {round}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn init_writes_a_starter_that_builds_and_refuses_to_overwrite() {
    let dir = tmp("init");
    let design = dir.join("design.toml");
    let o = run(&["init", "-o"], &[&design]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&design).unwrap();
    assert!(
        text.lines()
            .filter(|l| l.trim_start().starts_with('#'))
            .count()
            > 10
    );
    for m in ["grbl-laser", "grbl-router", "svg-laser"] {
        build_and_check(&design, m, &dir);
    }
    let again = run(&["init", "-o"], &[&design]);
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("exists"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_text_names_the_character() {
    let dir = tmp("bad");
    let design = dir.join("bad.toml");
    let o = run(&["text", "caf\u{20ac}", "-o"], &[&design]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("character 3") && e.contains("sans"), "{e}");
    assert!(!design.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
