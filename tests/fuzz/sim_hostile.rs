//! Hostile programs for `check` (issue #40, items 1–5 and 7): each used to abort on memory,
//! overflow the stack, keep millions of findings, print `cut NaN mm` with exit 0, run for
//! minutes or hang. The library cases run in-process and assert on the findings; the files
//! that are not files run the CLI as a child under a generous limit (a hang guard, not a
//! speed test).

use skinpath::sim::{Backend, CheckConfig, Report, check_text, files, interp, ngc};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::support;
use support::tmpdir;

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

fn feeds(src: &str, budget: u64) -> usize {
    let cfg = CheckConfig {
        max_loop_iterations: budget,
        ..CheckConfig::default()
    };
    let p = interp::interpret_with(src, &cfg, &interp::Options { load_sub: None });
    p.motions
        .iter()
        .filter(|m| m.kind == skinpath::sim::MotionKind::Feed)
        .count()
}

/// Every total of the report is a finite number (no NaN or infinity leaks).
fn assert_finite(r: &Report) {
    let s = &r.stats;
    let t = &s.time;
    for v in [
        s.cut_length,
        s.rapid_length,
        t.total,
        t.feed,
        t.rapid,
        t.dwell,
    ] {
        assert!(v.is_finite(), "{r}");
    }
    for p in s.bbox.iter().flatten().flatten() {
        assert!(p.is_finite(), "{r}");
    }
}

const BUDGET: u64 = 5_000;

#[test]
fn canned_cycle_repeats_count_against_the_loop_budget() {
    // G81 L1e9: a hole per repeat, each after the first counting one iteration, so the
    // budget B drills B + 1 holes (one feed each) and stops with a loop-limit error.
    let src = "G21 G90 F100\nG0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 L1000000000\nM2\n";
    let r = check_with_budget(src, BUDGET);
    assert_eq!(count(&r, "loop-limit"), 1, "{r}");
    assert_eq!(r.findings[0].lines, vec![3]);
    assert_eq!(r.exit_code(), 1);
    assert_eq!(feeds(src, BUDGET), BUDGET as usize + 1);
    // Within the budget nothing is reported: L5 drills five holes.
    let ok = "G21 G90 F100\nG0 X0 Y0 Z5\nG91 G81 X1 Y1 Z-1 R-4 L5\nG90 G80\nM2\n";
    assert_eq!(feeds(ok, BUDGET), 5);
    assert_eq!(count(&check_with_budget(ok, BUDGET), "loop-limit"), 0);
}

#[test]
fn pecks_count_against_the_loop_budget() {
    // G83 with Q 1e-7 over 11 mm: 1.1e8 pecks; each after the first counts.
    let src = "G21 G90 F100\nG0 X0 Y0 Z5\nG83 X1 Y1 Z-10 R1 Q0.0000001\nM2\n";
    let r = check_with_budget(src, BUDGET);
    assert_eq!(count(&r, "loop-limit"), 1, "{r}");
    assert_eq!(feeds(src, BUDGET), BUDGET as usize + 1);
    // Q3 over 11 mm: ceil(11 / 3) = 4 pecks, within any budget.
    let ok = "G21 G90 F100\nG0 X0 Y0 Z5\nG83 X1 Y1 Z-10 R1 Q3\nG80\nM2\n";
    assert_eq!(feeds(ok, BUDGET), 4);
}

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
    let per =
        skinpath::geom::Arc::new(skinpath::geom::DVec2::ZERO, 1e5, 0.0, std::f64::consts::TAU)
            .chords_for_tolerance(cfg.flatten_tolerance);
    let max = skinpath::sim::checks::contours::MAX_CONTOUR_SEGMENTS;
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

#[test]
fn a_line_of_a_million_repeated_words_keeps_only_the_findings_shown() {
    let src = format!("G21 F100\nG1 {}\nM2\n", "X1 ".repeat(1_000_000));
    let cfg = CheckConfig::default();
    let p = interp::interpret_with(&src, &cfg, &interp::Options { load_sub: None });
    // At most the cap kept per id; the rest counted.
    let kept = p
        .diagnostics
        .iter()
        .filter(|d| d.id == "duplicate-word")
        .count();
    assert_eq!(kept, cfg.max_findings_per_check);
    assert_eq!(
        p.diagnostics_dropped,
        vec![("duplicate-word", 999_999 - cfg.max_findings_per_check)]
    );
    let r = check_text(Backend::Builtin, &src, &cfg, &[]);
    // The duplicates and the line's length (over LinuxCNC's 255 characters).
    assert_eq!(r.errors_in_all(), 999_999 + 1, "{r}");
    assert_eq!(
        r.suppressed,
        vec![(
            "duplicate-word".to_string(),
            999_999 - cfg.max_findings_per_check
        )]
    );
}

#[test]
fn non_finite_and_overflowing_arcs_and_moves_are_errors() {
    for (src, id) in [
        (
            "G21 G90 F100\nG0 X0 Y0\nG2 X1 Y0 R[10**300]\nM2\n",
            "invalid-arc",
        ),
        (
            "G21 G90 F100\nG0 X0 Y0\nG2 X1 Y0 I[10**300] J0\nM2\n",
            "invalid-arc",
        ),
        (
            "G21 G90 F100\nG0 X0 Y0\nG2 X1 Y0 R100000000\nM2\n",
            "invalid-arc",
        ),
        (
            "G21 G91 F100\nG1 X[10**308]\nG1 X[10**308]\nM2\n",
            "invalid-value",
        ),
        (
            "G21 G90 F100\nG1 X[0-10**154]\nG1 X[10**154]\nM2\n",
            "invalid-value",
        ),
    ] {
        let r = check_with_budget(src, BUDGET);
        assert!(count(&r, id) >= 1, "{src}: {r}");
        assert_eq!(r.exit_code(), 1, "{src}");
        assert_finite(&r);
    }
    // A large radius within the limit is an arc: its length is the closed form r·θ with
    // θ = 2·asin(c / 2r) for the chord c = 1.
    let r = check_with_budget("G21 G90 F100\nG0 X0 Y0\nG2 X1 Y0 R1000000\nM2\n", BUDGET);
    assert_eq!(count(&r, "invalid-arc"), 0, "{r}");
    let want = 2.0 * 1e6 * (0.5f64 / 1e6).asin();
    assert!((r.stats.cut_length - want).abs() < 1e-9, "{r}");
}

/// 10⁵ short moves in rows, one line crossing them all, and optionally one far move.
fn rows_and_far_move(far: bool) -> String {
    let mut s = String::from("G21 G90 F100 S1000 M3\nG0 X0 Y0\n");
    for i in 0..100_000 {
        s += &format!(
            "G1 X{:.3} Y{:.3}\n",
            (i % 300) as f64 * 0.1,
            (i / 300) as f64 * 0.1
        );
    }
    s += "G1 X15 Y-1\n";
    if far {
        s += "G1 X1000000000\n";
    }
    s + "M5\nM2\n"
}

#[test]
fn a_far_move_among_many_short_ones_changes_no_finding() {
    // The far move at y = −1 meets nothing but its neighbour: the findings are those of
    // the program without it (the grid used to be sized by the bounding box it spans).
    let cfg = CheckConfig::default();
    let near = check_text(Backend::Builtin, &rows_and_far_move(false), &cfg, &[]);
    let far = check_text(Backend::Builtin, &rows_and_far_move(true), &cfg, &[]);
    let contacts = |r: &Report| {
        let shown: Vec<_> = r
            .findings
            .iter()
            .filter(|f| f.id == "self-intersection")
            .map(|f| (f.lines.clone(), f.at.clone()))
            .collect();
        let more = r
            .suppressed
            .iter()
            .find(|s| s.0 == "self-intersection")
            .map(|s| s.1);
        (shown, more)
    };
    let (shown, more) = contacts(&near);
    assert!(shown.len() + more.unwrap_or(0) > 300, "{near}");
    assert_eq!(contacts(&far), (shown, more));
    // The far move is reported for what it is: out of the work area.
    assert!(
        far.findings.iter().any(|f| f.id == "out-of-bounds"),
        "{far}"
    );
}

/// Generous: a hang guard, not a speed test (each case ends in well under a second).
const CHILD_LIMIT: Duration = Duration::from_secs(120);

/// The CLI's exit code and output on `args`, killed after [`CHILD_LIMIT`] (then the test
/// fails).
fn run_limited(args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run skinpath");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let mut out = String::new();
            for s in [
                child.stdout.take().map(|s| Box::new(s) as Box<dyn Read>),
                child.stderr.take().map(|s| Box::new(s) as Box<dyn Read>),
            ]
            .into_iter()
            .flatten()
            {
                let mut s = s;
                let _ = s.read_to_string(&mut out);
            }
            return (status.code(), out);
        }
        if start.elapsed() > CHILD_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("skinpath {args:?} still running after {CHILD_LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A FIFO at `p`, or false when `mkfifo` is not available.
fn mkfifo(p: &Path) -> bool {
    Command::new("mkfifo")
        .arg(p)
        .status()
        .is_ok_and(|s| s.success())
}

#[test]
fn files_that_are_not_files_are_refused_at_once() {
    let d = tmpdir("not-files");
    let zero = d.join("zero.ngc");
    std::os::unix::fs::symlink("/dev/zero", &zero).expect("symlink");
    let lib = d.join("lib");
    std::fs::create_dir_all(&lib).expect("mkdir");
    std::os::unix::fs::symlink("/dev/zero", lib.join("zz.ngc")).expect("symlink");
    let caller = d.join("calls_zero.ngc");
    std::fs::write(&caller, "G21\nO<zz> call\nM2\n").expect("write");
    let caller = caller.to_string_lossy().into_owned();
    let lib_s = lib.to_string_lossy().into_owned();
    // The program itself: a symlink to /dev/zero.
    let (code, out) = run_limited(&["check", &zero.to_string_lossy()]);
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("not a regular file"), "{out}");
    // A subroutine file on the --sub-path: an o-word error on the call's line.
    let (code, out) = run_limited(&["check", &caller, "--sub-path", &lib_s]);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("line 2") && out.contains("zz.ngc: a character device, not a regular file"),
        "{out}"
    );
    if mkfifo(&d.join("fifo.ngc")) && mkfifo(&lib.join("ff.ngc")) {
        let (code, out) = run_limited(&["check", &d.join("fifo.ngc").to_string_lossy()]);
        assert_eq!(code, Some(2), "{out}");
        assert!(out.contains("FIFO"), "{out}");
        let calls_fifo = d.join("calls_fifo.ngc");
        std::fs::write(&calls_fifo, "G21\nO<ff> call\nM2\n").expect("write");
        let (code, out) =
            run_limited(&["check", &calls_fifo.to_string_lossy(), "--sub-path", &lib_s]);
        assert_eq!(code, Some(1), "{out}");
        assert!(out.contains("ff.ngc: a FIFO"), "{out}");
    } else {
        eprintln!("skipped the FIFO cases: mkfifo is not available");
    }
    // Too large a subroutine file: refused by size, not read.
    let big = files::MAX_SUB_FILE_BYTES + 1;
    let f = std::fs::File::create(lib.join("big.ngc")).expect("create");
    f.set_len(big).expect("sparse file");
    let calls_big = d.join("calls_big.ngc");
    std::fs::write(&calls_big, "G21\nO<big> call\nM2\n").expect("write");
    let (code, out) = run_limited(&["check", &calls_big.to_string_lossy(), "--sub-path", &lib_s]);
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("larger than"), "{out}");
    let _ = std::fs::remove_dir_all(&d);
}
