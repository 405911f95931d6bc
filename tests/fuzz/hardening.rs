//! Hardening regressions (issue #10 and the design/profile parts of #18): inputs that used
//! to hang, crash or be accepted silently. Hangs are run in a child process (the built
//! binary) under a generous time limit: the test asserts the outcome (a clear error or a
//! correct result), the limit only turns a regression into a failure instead of a stuck CI.

use skinpath::skin::dbsc_skin::{DEFAULT_MAX_WORK, DbscSkinOptions, skin_dbsc};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::support;
use support::{EXAMPLES, ROOT, example};

/// Generous, a hang guard and not a speed test: the campaign called "no answer in 30 s" a
/// hang. The slowest case (the degree-1 stroke) takes about 4 s in a debug build on an idle
/// machine (the dev profile's opt-level 1); tests run in parallel on 2 shared cores, which
/// other builds can slow tenfold, so the guard waits 120 s.
const CHILD_LIMIT: Duration = Duration::from_secs(120);

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("skinpath-hardening-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// What a child run produced.
struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs the binary with `args`, killing it after [`CHILD_LIMIT`] (then the test fails).
fn run_limited(args: &[&str]) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut stdout = String::new();
            let mut stderr = String::new();
            child
                .stdout
                .take()
                .unwrap()
                .read_to_string(&mut stdout)
                .unwrap();
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut stderr)
                .unwrap();
            return Run {
                code: status.code(),
                stdout,
                stderr,
            };
        }
        if start.elapsed() > CHILD_LIMIT {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("skinpath {args:?} still running after {CHILD_LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn examples_stay_well_inside_the_work_budget() {
    let opts = DbscSkinOptions::default();
    let mut most = 0;
    for name in EXAMPLES {
        let d = example(name);
        for (i, c) in d.strokes().unwrap().iter().enumerate() {
            let mut o = opts;
            let s = match skin_dbsc(c, &o) {
                Ok(s) => s,
                Err(_) => {
                    o.allow_global_overlap = true;
                    skin_dbsc(c, &o).unwrap()
                }
            };
            println!("{name} stroke {i}: {} refinement steps", s.work);
            most = most.max(s.work);
        }
    }
    println!("most: {most} of {DEFAULT_MAX_WORK}");
    assert!(most < DEFAULT_MAX_WORK / 4, "{most}");
}

/// A design with one stroke body, written to `dir/name`.
fn stroke_design(dir: &Path, name: &str, body: &str) -> String {
    write(
        dir,
        name,
        &format!("version = 1\n\n[[stroke]]\nname = \"s\"\n{body}\n"),
    )
}

fn assert_clean_error(r: &Run, needles: &[&str]) {
    assert_eq!(r.code, Some(2), "stdout {}\nstderr {}", r.stdout, r.stderr);
    assert!(!r.stderr.contains("panicked"), "{}", r.stderr);
    for n in needles {
        assert!(r.stderr.contains(n), "missing `{n}` in: {}", r.stderr);
    }
}

fn assert_ok(r: &Run) {
    assert_eq!(r.code, Some(0), "stdout {}\nstderr {}", r.stdout, r.stderr);
}

/// The four hangs of the bad-input campaign: each now ends quickly with a result or a
/// clear error.
#[test]
fn former_hangs_end_with_a_result_or_a_clear_error() {
    let dir = tmpdir("hangs");
    let out = dir.join("out.json");
    let out = out.to_str().unwrap();
    // A degree-1 stroke of 4 disks: outlined.
    let f = stroke_design(
        &dir,
        "deg1.toml",
        "degree = 1\ndisks = [[10.0, 0.0, 2.0], [10.648, 6.442, 2.841], [7.700, 9.854, 2.909], \
         [3.952, 8.632, 2.141]]",
    );
    assert_ok(&run_limited(&["outline", &f, "-o", out]));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out).unwrap()).unwrap();
    assert!(doc.to_string().contains("contours"), "{doc}");
    // First two disks nearly coincide: refused, naming the stroke and the disk.
    let f = stroke_design(
        &dir,
        "near.toml",
        "disks = [[1e-15, 0, 2], [0, 0, 2], [10, 5, 2], [20, 0, 2]]",
    );
    assert_clean_error(
        &run_limited(&["outline", &f, "-o", out]),
        &[
            "near.toml: stroke 0 \"s\", disk 1:",
            "nearly repeats",
            "remove one",
        ],
    );
    // A closed degree-2 stroke out and back along a line.
    let f = stroke_design(
        &dir,
        "outback.toml",
        "degree = 2\nclosed = true\ndisks = [[0, 0, 1], [10, 0, 1], [20, 0, 1], [10, 0, 1.5]]",
    );
    let r = run_limited(&["outline", &f, "-o", out]);
    assert!(r.code == Some(0) || r.code == Some(2), "{}", r.stderr);
    if r.code == Some(2) {
        assert_clean_error(&r, &["outback.toml", "stroke \"s\""]);
    }
    // A coordinate of 1e38.
    let f = stroke_design(
        &dir,
        "big.toml",
        "disks = [[0, 0, 2], [1e38, 0, 2], [10, 5, 2], [20, 0, 2]]",
    );
    assert_clean_error(
        &run_limited(&["outline", &f, "-o", out]),
        &["big.toml: stroke 0 \"s\", disk 1:", "beyond ±10000000"],
    );
}

/// Degenerate but legal strokes: 2 and 3 points, collinear disks, a zero-length spine
/// span (same centre, other radius) and a 2-disk line.
#[test]
fn degenerate_strokes_work() {
    let dir = tmpdir("degenerate");
    let out = dir.join("out.json");
    let out = out.to_str().unwrap();
    for (name, body) in [
        (
            "three_points",
            "points = [[0, 0, 1], [5, 3, 1.5], [10, 0, 1]]",
        ),
        ("two_points", "points = [[0, 0, 1], [10, 0, 2]]"),
        ("two_disks", "disks = [[0, 0, 1], [10, 0, 2]]"),
        (
            "collinear",
            "disks = [[0, 0, 1], [5, 0, 1], [10, 0, 1], [15, 0, 1], [20, 0, 1]]",
        ),
    ] {
        let f = stroke_design(&dir, &format!("{name}.toml"), body);
        let r = run_limited(&["outline", &f, "-o", out]);
        assert_ok(&r);
    }
    // A zero-length span of the spine: clear error or result, never a hang.
    let f = stroke_design(
        &dir,
        "zero.toml",
        "disks = [[0, 0, 1], [0, 0, 2], [10, 0, 1], [20, 0, 1]]",
    );
    let r = run_limited(&["outline", &f, "-o", out]);
    assert!(r.code == Some(0) || r.code == Some(2), "{}", r.stderr);
    assert!(!r.stderr.contains("panicked"), "{}", r.stderr);
}

/// Crashes and silent acceptances of the campaign: each a clear error at load time.
#[test]
fn former_crashes_are_clear_errors() {
    let dir = tmpdir("crashes");
    let out = dir.join("out.json");
    let out = out.to_str().unwrap();
    let f = write(
        &dir,
        "degmax.json",
        r#"{"version": 1, "stroke": [{"name": "d", "degree": 18446744073709551615,
            "fit": "approximate", "control_disks": 4,
            "points": [[0, 0, 1], [5, 3, 1.5], [10, 0, 1], [15, 2, 1.2]]}]}"#,
    );
    assert_clean_error(
        &run_limited(&["outline", &f, "-o", out]),
        &["stroke 0 \"d\", key `degree`", "outside 1..=10"],
    );
    let f = stroke_design(
        &dir,
        "four.toml",
        "disks = [[0, 0, 2, 7], [10, 5, 2], [20, 0, 2], [30, 4, 1.5]]",
    );
    assert_clean_error(
        &run_limited(&["outline", &f, "-o", out]),
        &["four.toml:5:", "exactly 3 numbers"],
    );
    let f = write(&dir, "empty.toml", "version = 1\n");
    assert_clean_error(
        &run_limited(&[
            "build",
            &f,
            "-m",
            "grbl-router",
            "-o",
            dir.join("e.nc").to_str().unwrap(),
        ]),
        &["empty.toml", "no [[stroke]]"],
    );
    let base = "disks = [[0, 0, 2], [10, 5, 3], [20, 0, 2], [30, 4, 1.5]]\n";
    for (op, key) in [
        ("kind = \"profile\"\npasses = 1000000000", "passes"),
        (
            "kind = \"profile\"\ntabs = { count = 1000000000, width = 2, height = 1 }",
            "tabs.count",
        ),
        (
            "kind = \"profile\"\ntabs = { count = 100000, width = 2, height = 1 }",
            "tabs.count",
        ),
        ("kind = \"vcarve\"\nangle = 60\ndepth = 1e300", "depth"),
        (
            "kind = \"vcarve\"\nangle = 60\npasses = 4294967295",
            "passes",
        ),
        ("kind = \"fill\"\nspacing = 1\nfeed = 1e300", "feed"),
    ] {
        let f = stroke_design(&dir, "op.toml", &format!("{base}\n[[operation]]\n{op}"));
        assert_clean_error(
            &run_limited(&[
                "build",
                &f,
                "-m",
                "grbl-router",
                "-o",
                dir.join("o.nc").to_str().unwrap(),
            ]),
            &["op.toml: operation 0 (", &format!("key `{key}`")],
        );
    }
}

/// Machine profiles with tool sizes that used to exhaust memory or panic, and preambles
/// that would end the program or start the spindle.
#[test]
fn bad_profiles_are_refused_before_any_work() {
    let dir = tmpdir("profiles");
    let design = format!("{ROOT}/examples/brush.toml");
    let router = std::fs::read_to_string(format!("{ROOT}/machines/grbl-router.toml")).unwrap();
    let cases: Vec<(String, &str)> = vec![
        (
            router.replace("diameter = 3.175", "diameter = 1e-9"),
            "tools[0].diameter",
        ),
        (
            router.replace("diameter = 3.175", "diameter = 1e308"),
            "tools[0].diameter",
        ),
        (
            router.replace("diameter = 3.175", "diameter = 1e-308"),
            "tools[0].diameter",
        ),
        (
            router.replace("preamble = \"\"", "preamble = \"M2\""),
            "gcode.preamble",
        ),
        (
            router.replace("postamble = \"\"", "postamble = \"M3 S1000\""),
            "gcode.postamble",
        ),
    ];
    for (k, (text, key)) in cases.iter().enumerate() {
        let p = write(&dir, &format!("p{k}.toml"), text);
        assert_clean_error(
            &run_limited(&[
                "build",
                &design,
                "-m",
                &p,
                "-o",
                dir.join("o.nc").to_str().unwrap(),
            ]),
            &[&format!("p{k}.toml"), &format!("key `{key}`")],
        );
    }
    let r = run_limited(&[
        "build",
        &design,
        "-m",
        "grbl-router",
        "-o",
        dir.join("o.nc").to_str().unwrap(),
        "--place",
        "lower-left",
        "--margin",
        "nan",
    ]);
    assert_clean_error(&r, &["--margin must be a finite"]);
}

/// `inspect --json | head -c 10`: the reader goes away; skinpath ends quietly.
#[test]
fn closed_stdout_pipe_ends_quietly() {
    for args in [vec!["inspect", "--json"], vec!["inspect"], vec!["machines"]] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_skinpath"));
        cmd.args(&args);
        if args[0] == "inspect" {
            cmd.arg(format!("{ROOT}/examples/gclef.toml"));
        }
        let mut child = cmd
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Close the read end before anything is written: every write fails with EPIPE.
        drop(child.stdout.take());
        let mut stderr = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut stderr)
            .unwrap();
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(0), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

/// Identical input, identical bytes: outlines and G-code of two examples, run twice.
#[test]
fn repeated_runs_are_byte_identical() {
    let dir = tmpdir("repeat");
    for name in ["brush", "calligraphy"] {
        let design = format!("{ROOT}/examples/{name}.toml");
        let mut outs = Vec::new();
        for k in 0..2 {
            let o = dir.join(format!("{name}{k}.json"));
            assert_ok(&run_limited(&[
                "outline",
                &design,
                "-o",
                o.to_str().unwrap(),
            ]));
            let g = dir.join(format!("{name}{k}.nc"));
            assert_ok(&run_limited(&[
                "build",
                &design,
                "-m",
                "grbl-laser",
                "-o",
                g.to_str().unwrap(),
                "--place",
                "lower-left",
            ]));
            outs.push((std::fs::read(o).unwrap(), std::fs::read(g).unwrap()));
        }
        assert!(!outs[0].0.is_empty() && !outs[0].1.is_empty());
        assert!(outs[0] == outs[1], "{name}: runs differ");
    }
}

/// Property tests draw from a fixed seed (.cargo/config.toml sets PROPTEST_RNG_SEED for
/// every test binary cargo runs; a value in the environment overrides it).
#[test]
fn proptest_seed_is_fixed() {
    use proptest::test_runner::{Config, RngSeed};
    assert!(
        matches!(Config::default().rng_seed, RngSeed::Fixed(_)),
        "PROPTEST_RNG_SEED is not set: run the tests through cargo (see .cargo/config.toml)"
    );
}
