//! Limits of the command line (issue 40 items 6, 14–17, 19, 20; issue 43 item 1): signals
//! leave no temporary files, `text` names its options, text length, the early work-area
//! test, the fill's line limit, outputs that are not regular files, an unwritable stderr.
//! Every run is a child process under a generous kill limit ([`CHILD_LIMIT`]); the tests
//! assert outcomes (exit status, messages, files), never how long a run took.

use crate::support;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use support::{CHILD_LIMIT, tmpdir, wait_limited};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_skinpath")
}

/// Runs the binary with `args` (stdout and stderr captured through files, so a large
/// output cannot block the child): exit code and stderr.
fn run(args: &[&str], dir: &Path) -> (Option<i32>, String) {
    let err = dir.join(format!("stderr-{}", args.first().unwrap_or(&"")));
    let child = Command::new(bin())
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .unwrap();
    let status = wait_limited(child, &format!("{args:?}"));
    (status.code(), std::fs::read_to_string(&err).unwrap())
}

/// Polls until `found()` or [`CHILD_LIMIT`]; false on time-out.
fn poll(mut found: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < CHILD_LIMIT {
        if found() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    false
}

/// Names in `dir` starting with `prefix`.
fn entries(dir: &Path, prefix: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(prefix))
        .collect()
}

fn signal(pid: u32, sig: &str) {
    let s = Command::new("kill")
        .args([&format!("-{sig}"), &pid.to_string()])
        .status()
        .unwrap();
    assert!(s.success(), "kill -{sig} {pid}");
}

/// A square plate with a hatch fill `spacing` apart.
fn fill_design(dir: &Path, spacing: f64) -> PathBuf {
    let p = dir.join(format!("fill-{spacing}.toml"));
    std::fs::write(
        &p,
        format!(
            "version = 1\nunits = \"mm\"\n[[shape]]\nname = \"plate\"\n\
             contours = [[[0.0, 0.0], [40.0, 0.0], [40.0, 30.0], [0.0, 30.0]]]\n\
             [[operation]]\nkind = \"fill\"\nspacing = {spacing}\n"
        ),
    )
    .unwrap();
    p
}

fn is_fifo(p: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::metadata(p).unwrap().file_type().is_fifo()
}

/// Item 6: SIGINT during a streaming check (a program over 64 MiB) removes its
/// `.skinpath-check-*` files from the temporary folder and exits 130.
#[test]
fn sigint_during_a_large_check_leaves_no_temporary_files() {
    let dir = tmpdir("sigint");
    let tmp = dir.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let program = dir.join("big.ngc");
    {
        let mut f = std::io::BufWriter::new(std::fs::File::create(&program).unwrap());
        writeln!(f, "G21 G90\nG0 Z5\nG0 X0 Y0\nM3 S1000\nG1 Z-1 F100").unwrap();
        let mut written = 0u64;
        let mut i = 0u64;
        while written <= 66 << 20 {
            let line = format!(
                "G1 X{:.3} Y{:.3}\n",
                (i as f64 * 0.37) % 300.0,
                (i as f64 * 0.011) % 200.0
            );
            f.write_all(line.as_bytes()).unwrap();
            written += line.len() as u64;
            i += 1;
        }
        writeln!(f, "M5\nM30").unwrap();
    }
    let child = Command::new(bin())
        .arg("check")
        .arg(&program)
        .env("TMPDIR", &tmp)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = child.id();
    let started = poll(|| !entries(&tmp, ".skinpath-check-").is_empty());
    assert!(started, "the check made no temporary file");
    signal(pid, "INT");
    let status = wait_limited(child, "check big.ngc");
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_eq!(entries(&tmp, ".skinpath-check-"), Vec::<String>::new());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 6: SIGTERM while a write waits on a FIFO output (a reader that never comes)
/// removes the preview's `.skinpath-tmp-*` file and exits 143; nothing is written.
#[test]
fn sigterm_during_a_write_leaves_no_temporary_files() {
    let dir = tmpdir("sigterm");
    let design = fill_design(&dir, 1.0);
    let fifo = dir.join("out.gcode");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let child = Command::new(bin())
        .arg("build")
        .arg(&design)
        .args(["--machine", "grbl-laser", "--preview", "p.svg", "-o"])
        .arg(&fifo)
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = child.id();
    assert!(poll(|| !entries(&dir, ".skinpath-tmp-").is_empty()));
    signal(pid, "TERM");
    let status = wait_limited(child, "build onto a FIFO");
    assert_eq!(status.code(), Some(143), "{status:?}");
    assert_eq!(entries(&dir, ".skinpath-tmp-"), Vec::<String>::new());
    assert!(!dir.join("p.svg").exists());
    assert!(is_fifo(&fifo), "the FIFO was replaced");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 14: `skinpath text` names the option at fault, not the design it writes.
#[test]
fn text_errors_name_the_option() {
    let dir = tmpdir("text-options");
    let cases: [(&[&str], &[&str]); 5] = [
        (&["AV", "--line-spacing", "NaN"], &["--line-spacing", "NaN"]),
        (
            &["AV", "--height", "1e-300"],
            &["--height", "1e-300", "0.0021"],
        ),
        (&["AV", "--width", "1e-5"], &["--width", "1e-5", "0.0002"]),
        (&["漢字"], &["the text", "'漢' (U+6F22)", "'字' (U+5B57)"]),
        (
            &["AV", "--letter-spacing", "inf"],
            &["--letter-spacing", "inf"],
        ),
    ];
    for (args, want) in cases {
        let mut all = vec!["text"];
        all.extend_from_slice(args);
        all.extend(["-o", "t.toml"]);
        let (code, err) = run(&all, &dir);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        for w in want {
            assert!(err.contains(w), "{args:?}: {w:?} not in {err}");
        }
        assert!(
            !err.contains("t.toml") && !err.contains("key `"),
            "{args:?}: {err}"
        );
        assert!(!dir.join("t.toml").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 15: text longer than the limit is refused before any layout, by `text` and by a
/// design's loader (`inspect`), for one long line and for many lines.
#[test]
fn text_length_is_limited() {
    use skinpath::design::MAX_TEXT_CHARS;
    let dir = tmpdir("text-length");
    let long = "A".repeat(100_000);
    let (code, err) = run(&["text", &long, "-o", "t.toml"], &dir);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains(&format!("limit {MAX_TEXT_CHARS}")), "{err}");
    for (name, text) in [
        ("million", "A".repeat(1_000_000)),
        ("lines", "A\\n".repeat(100_000)),
    ] {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(
            &path,
            format!(
                "version = 1\nunits = \"mm\"\n[[text]]\nname = \"t\"\ntext = \"{text}\"\n\
                 height = 10.0\nwidth = 1.0\n"
            ),
        )
        .unwrap();
        let (code, err) = run(&["inspect", path.to_str().unwrap()], &dir);
        assert_eq!(code, Some(2), "{name}: {err}");
        assert!(
            err.contains(&format!("limit {MAX_TEXT_CHARS}")) && err.contains("text 0 \"t\""),
            "{name}: {err}"
        );
    }
    // At the limit the text is accepted.
    let at_limit = "A".repeat(MAX_TEXT_CHARS);
    let (code, err) = run(&["text", &at_limit, "-o", "t.toml"], &dir);
    assert_eq!(code, Some(0), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 16: a job whose design alone is wider than the work area is refused with the
/// work-area message (sizes, `--fit`) before it is built, and the estimate is a lower
/// bound: the refused width lies within the exact one `--place design` reports of a
/// smaller copy scaled back.
#[test]
fn work_area_is_checked_before_the_build() {
    let dir = tmpdir("work-area");
    let text = "ABCDEFGHIJ".repeat(100);
    let (code, err) = run(
        &[
            "text",
            &text,
            "--height",
            "10",
            "--width",
            "1",
            "-o",
            "long.toml",
        ],
        &dir,
    );
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = run(
        &[
            "build",
            "long.toml",
            "--machine",
            "grbl-router",
            "-o",
            "o.gcode",
        ],
        &dir,
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("the job is at least") && err.contains("larger than the work area"),
        "{err}"
    );
    assert!(err.contains("--fit 299x179"), "{err}");
    // The early width is no more than the letters' extent: 1000 letters of advance
    // between 5.7 and 10 mm (Hershey widths 12–21 units at 10/21 mm a unit, kerned).
    let w: f64 = err
        .split("at least ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    assert!((5_000.0..10_500.0).contains(&w), "{w}");
    assert!(!dir.join("o.gcode").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 43 item 1: a hatch spacing that would make more than the limit's lines is
/// refused before any line is made, naming the operation and the spacing; a fine spacing
/// within the limit builds and checks clean.
#[test]
fn fill_line_count_is_limited() {
    use skinpath::toolpath::MAX_HATCH_LINES;
    let dir = tmpdir("fill");
    let design = fill_design(&dir, 1e-4);
    let (code, err) = run(
        &[
            "build",
            design.to_str().unwrap(),
            "--machine",
            "grbl-laser",
            "-o",
            "f.gcode",
        ],
        &dir,
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("(fill)")
            && err.contains("spacing 0.0001")
            && err.contains(&format!("limit {MAX_HATCH_LINES}")),
        "{err}"
    );
    // 30 mm / 0.005 mm = 6 000 lines: more than the nearest-neighbour ordering takes,
    // kept in their boustrophedon order.
    let design = fill_design(&dir, 0.005);
    let (code, err) = run(
        &[
            "build",
            design.to_str().unwrap(),
            "--machine",
            "grbl-laser",
            "-o",
            "f.gcode",
        ],
        &dir,
    );
    assert_eq!(code, Some(0), "{err}");
    let program = std::fs::read_to_string(dir.join("f.gcode")).unwrap();
    let cuts = program.lines().filter(|l| l.starts_with("G1 X")).count();
    let nearest = skinpath::toolpath::MAX_NEAREST_PATHS;
    assert!(cuts > nearest && cuts <= 6_000, "{cuts}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 19: `-o /dev/null` and `-o FIFO` are written in place, never replaced by a
/// regular file; a folder is refused by name.
#[test]
fn non_regular_outputs_are_written_in_place() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tmpdir("devices");
    let design = fill_design(&dir, 1.0);
    let d = design.to_str().unwrap();
    let (code, err) = run(
        &[
            "build",
            d,
            "--machine",
            "grbl-laser",
            "--format",
            "gcode",
            "-o",
            "/dev/null",
        ],
        &dir,
    );
    assert_eq!(code, Some(0), "{err}");
    let null = std::fs::metadata("/dev/null").unwrap().file_type();
    assert!(null.is_char_device(), "/dev/null is no longer a device");
    let fifo = dir.join("pipe.gcode");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let (code, err) = run(
        &["build", d, "--machine", "grbl-laser", "-o", "pipe.gcode"],
        &dir,
    );
    assert_eq!(code, Some(0), "{err}");
    let text = reader.join().unwrap();
    assert!(
        text.contains("G1") && text.trim_end().ends_with("M2"),
        "{text}"
    );
    assert!(is_fifo(&fifo));
    std::fs::create_dir_all(dir.join("folder.gcode")).unwrap();
    let (code, err) = run(
        &["build", d, "--machine", "grbl-laser", "-o", "folder.gcode"],
        &dir,
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("folder.gcode: it is a folder"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 20: with stderr unwritable (`/dev/full`, a closed pipe) `import` and `build` still
/// write their output and exit 0.
#[test]
fn unwritable_stderr_does_not_stop_import_or_build() {
    let dir = tmpdir("stderr");
    let svg = dir.join("d.svg");
    std::fs::write(
        &svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="50mm" viewBox="0 0 100 50">
<path id="a" d="M10 10 L90 40" stroke="black" stroke-width="4" fill="none"/>
<text id="skipped" x="5" y="5">hi</text></svg>"#,
    )
    .unwrap();
    let design = fill_design(&dir, 1.0);
    for closed_pipe in [false, true] {
        let runs: [(&str, Vec<&str>); 2] = [
            ("d.toml", vec!["import", "d.svg", "-o", "d.toml"]),
            (
                "b.gcode",
                vec![
                    "build",
                    design.to_str().unwrap(),
                    "--machine",
                    "grbl-laser",
                    "--timings",
                    "-o",
                    "b.gcode",
                ],
            ),
        ];
        for (out, args) in runs {
            let _ = std::fs::remove_file(dir.join(out));
            let mut cmd = Command::new(bin());
            cmd.args(&args).current_dir(&dir).stdout(Stdio::null());
            let child = if closed_pipe {
                let mut c = cmd.stderr(Stdio::piped()).spawn().unwrap();
                drop(c.stderr.take());
                c
            } else {
                let full = std::fs::OpenOptions::new()
                    .write(true)
                    .open("/dev/full")
                    .unwrap();
                cmd.stderr(full).spawn().unwrap()
            };
            let status = wait_limited(child, &format!("{args:?}"));
            assert_eq!(status.code(), Some(0), "{args:?} closed pipe {closed_pipe}");
            assert!(dir.join(out).exists(), "{args:?}: {out} not written");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 17: a 9,999-point star (spikes 0.02 mm apart, far narrower than the 3.175 mm bit)
/// builds on the router and its program checks clean; its valleys are closed before the
/// outside offset (`toolpath::valleys`), which took minutes and a gigabyte.
#[test]
fn star_of_many_points_builds_on_the_router() {
    let dir = tmpdir("star");
    let n = 9_999;
    let pts: Vec<String> = (0..n)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / n as f64;
            let r = if i % 2 == 0 { 30.0 } else { 10.0 };
            format!("[{:.6}, {:.6}]", 40.0 + r * a.cos(), 40.0 + r * a.sin())
        })
        .collect();
    std::fs::write(
        dir.join("star.toml"),
        format!(
            "version = 1\nunits = \"mm\"\n[[shape]]\nname = \"star\"\ncontours = [[{}]]\n",
            pts.join(", ")
        ),
    )
    .unwrap();
    let (code, err) = run(
        &[
            "build",
            "star.toml",
            "--machine",
            "grbl-router",
            "-o",
            "s.gcode",
        ],
        &dir,
    );
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = run(&["check", "s.gcode", "--machine", "grbl-router"], &dir);
    assert_eq!(code, Some(0), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
