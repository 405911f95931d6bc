//! Unit tests of the checker's front: whole programs through [`super::check_text`].

use super::*;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn never_panics_on_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let r = check_text(Backend::Builtin, &text, &CheckConfig::default(), &[]);
        prop_assert!(r.exit_code() <= 2);
        let c = check_text(Backend::LinuxCnc, &text, &CheckConfig::default(), &[]);
        prop_assert!(c.exit_code() <= 2);
    }

    #[test]
    fn never_panics_on_gcode_like(text in "([GMXYZIJKRFSPN]{1,2}[-+]?[0-9]{0,3}(\\.[0-9]{0,3})?[ ;()*%/\n]?){0,60}") {
        let r = check_text(Backend::Builtin, &text, &CheckConfig::default(), &[]);
        prop_assert!(r.exit_code() <= 2);
        let _ = r.to_string();
    }
}

#[test]
fn coincident_contours_are_checked_in_linear_time() {
    // 2,000 coincident square contours (about 200 KB of G-code).
    let mut src = String::from("G21 G90 F1000 S500\n");
    for _ in 0..2000 {
        src += "G0 X10.000 Y10.000\nM4\nG1 X20.000 Y10.000\nG1 X20.000 Y20.000\n\
                G1 X10.000 Y20.000\nG1 X10.000 Y10.000\nM5\n";
    }
    src += "M2\n";
    assert!(src.len() > 180_000);
    let r = check_text(Backend::Builtin, &src, &CheckConfig::default(), &[]);
    // One rapid to the start, then four cuts per square (the later rapids have length 0).
    assert_eq!(r.stats.motions, 1 + 2000 * 4);
    // Coincident contours do not cross: nothing to report, and no blow-up on the way.
    assert_eq!(r.errors(), 0, "{r}");
}

#[test]
fn unusable_inputs() {
    let cfg = CheckConfig::default();
    assert_eq!(check_text(Backend::Builtin, "", &cfg, &[]).exit_code(), 2);
    assert_eq!(
        check_text(Backend::Builtin, "\0\u{1}binary\0", &cfg, &[]).exit_code(),
        2
    );
    let ok = check_text(Backend::Builtin, "G0 X1\nM2\n", &cfg, &[]);
    assert_eq!(ok.exit_code(), 0, "{ok}");
}

/// The check of `src` with the default configuration and loop budget `budget`.
fn check_with_budget(src: &str, budget: u64) -> Report {
    let cfg = CheckConfig {
        max_loop_iterations: budget,
        ..CheckConfig::default()
    };
    check_text(Backend::Builtin, src, &cfg, &[])
}

fn count(r: &Report, id: &str) -> usize {
    r.findings.iter().filter(|f| f.id == id).count()
}

const BUDGET: u64 = 5_000;

// Hostile programs: loops, huge contours and deep nesting stop with a finding naming the
// line instead of running out of time, memory or stack.

#[test]
fn arc_turns_count_against_the_loop_budget() {
    // 2,000 full circles of P1000: 999 extra turns each, so the budget runs out within
    // the sixth arc (5 · 999 < 5,000 < 6 · 999) and the rest is not interpreted.
    let mut src = String::from("G21 G90 F100\nG0 X0 Y0 Z0\n");
    for _ in 0..2000 {
        src += "G2 X0 Y0 I1 J0 P1000\n";
    }
    src += "M2\n";
    let r = check_with_budget(&src, BUDGET);
    assert_eq!(count(&r, "loop-limit"), 1, "{r}");
    // (The G0 to where the program starts is no move.)
    assert_eq!(r.stats.motions, 5);
    let want = 5.0 * 1000.0 * std::f64::consts::TAU;
    assert!((r.stats.cut_length - want).abs() < 1e-6 * want, "{r}");
    // In XZ the chords are moves: those beyond one turn's count, so a P1000 arc of 419,000
    // chords stops at once instead of creating them.
    let xz = "G21 G90 F100\nG0 X0 Y0 Z0\nG18\nG2 X0 Z0 I1 K0 P1000\nM2\n";
    let r = check_with_budget(xz, BUDGET);
    assert_eq!(count(&r, "loop-limit"), 1, "{r}");
    assert!(r.stats.motions <= 2, "{r}");
    // One XZ turn is free: its chords are made.
    let one = "G21 G90 F100\nG0 X0 Y0 Z0\nG18\nG2 X0 Z0 I1 K0\nM2\n";
    let r = check_with_budget(one, BUDGET);
    assert_eq!(count(&r, "loop-limit"), 0, "{r}");
    let chords = (std::f64::consts::TAU / interp::CHORD_ANGLE).ceil() as usize;
    assert_eq!(r.stats.motions, chords);
}

#[test]
fn contour_checks_stop_at_their_segment_limit() {
    // Full circles of radius 10⁵ mm, each at a place of its own, flatten to about
    // 2·10⁴ chords each at the default 1 µm: a few hundred pass 2²³ segments. The checks
    // stop with a check-limit error on the line of the first circle left out.
    let cfg = CheckConfig::default();
    let per = crate::geom::Arc::new(crate::geom::DVec2::ZERO, 1e5, 0.0, std::f64::consts::TAU)
        .chords_for_tolerance(cfg.flatten_tolerance);
    let max = checks::contours::MAX_CONTOUR_SEGMENTS;
    let n = max / per + 2;
    let mut src = String::from("G21 G90 F100 S1000 M3\n");
    for k in 0..n {
        let x = 2.1e5 * k as f64;
        src += &format!("G0 X{x} Y0\nG2 X{x} Y0 I100000 J0\n");
    }
    src += "M5\nM2\n";
    let r = check_text(Backend::Builtin, &src, &cfg, &[]);
    let f = r.findings.iter().find(|f| f.id == "check-limit");
    // Circle k (0-based) is on line 2k + 3; the first left out is the one past the limit.
    let first_out = max / per;
    assert_eq!(
        f.map(|f| f.lines.clone()),
        Some(vec![2 * first_out + 3]),
        "{r}"
    );
    assert_eq!(r.exit_code(), 1);
}

#[test]
fn flat_sums_evaluate_and_deep_nesting_is_refused_with_the_line() {
    // 10⁵ terms: one flat chain, evaluated in a loop.
    let sum = vec!["1"; 100_000].join("+");
    let src = format!("G21 F100\n#1=[{sum}]\nG1 X#1\nM2\n");
    let r = check_with_budget(&src, BUDGET);
    assert_eq!(r.stats.bbox.map(|b| b[1][0]), Some(100_000.0), "{r}");
    // Mixed precedence in a long run: 1 + 2·3 repeated is 7 per group.
    let mixed = vec!["1+2*3"; 10_000].join("+");
    let src = format!("G21 F100\n#1=[{mixed}]\nG1 X#1\nM2\n");
    let r = check_with_budget(&src, BUDGET);
    assert_eq!(r.stats.bbox.map(|b| b[1][0]), Some(70_000.0), "{r}");
    // 3·10⁴ nested # indirections, unary minus signs, brackets: a syntax error naming
    // the line, no stack overflow.
    let deep = ngc::MAX_NESTING;
    for (k, value) in [
        format!("{}1", "#".repeat(30_000)),
        format!("[{}1]", "-".repeat(30_000)),
        format!("{}1{}", "[".repeat(30_000), "]".repeat(30_000)),
        format!("{}1{}", "[".repeat(deep + 1), "]".repeat(deep + 1)),
    ]
    .into_iter()
    .enumerate()
    {
        let src = format!("G21 F100\n#1=1\nG1 X{value}\nM2\n");
        let r = check_with_budget(&src, BUDGET);
        let nested = r.findings.iter().any(|f| {
            f.id == "gcode-syntax" && f.lines == vec![3] && f.message.contains("nested deeper")
        });
        assert!(nested, "case {k}: {r}");
    }
    // At the limit itself the value is read: 32 brackets and 32 minus signs in them.
    let half = deep / 2;
    let src = format!(
        "G21 F100\nG1 X{}{}2{}\nM2\n",
        "[".repeat(half),
        "-".repeat(half),
        "]".repeat(half)
    );
    let r = check_with_budget(&src, BUDGET);
    assert_eq!(r.stats.bbox.map(|b| b[1][0]), Some(2.0), "{r}");
    // One sign more is one level too deep.
    let src = format!(
        "G21 F100\nG1 X{}{}2{}\nM2\n",
        "[".repeat(half),
        "-".repeat(half + 1),
        "]".repeat(half)
    );
    assert_eq!(count(&check_with_budget(&src, BUDGET), "gcode-syntax"), 1);
}
