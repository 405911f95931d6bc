//! Layers of a sign (issue 41 item 8): a design's `[[output]]` tables build one program per
//! output, each for its own machine and checked with it, written as a set or not at all.
//! Every run is a child process; the signal test waits under a generous kill limit and
//! asserts outcomes (exit status, files), never how long a run took.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};
use support::{CHILD_LIMIT, OPEN_SIGN_OUTPUTS, OpenSignCuts, skinpath, tmpdir, wait_limited};

/// The "OPEN" sign ([`support::open_sign`]) with its routed operations' widths and depths
/// set, and `outputs` appended.
fn sign(outputs: &str) -> String {
    let cuts = OpenSignCuts {
        channel_width: 6.5,
        channel_depth: 10.0,
        hole_diameter: 4.0,
        hole_depth: 12.0,
        board_depth: 12.0,
    };
    support::open_sign(Some(&cuts), outputs)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn json(o: &Output) -> serde_json::Value {
    assert_eq!(o.status.code(), Some(0), "{}", text(o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Cut length per toolpath operation name in a `build --json` summary.
fn cut_lengths(summary: &serde_json::Value) -> Vec<(String, f64)> {
    summary["operations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| {
            (
                o["name"].as_str().unwrap().to_string(),
                o["cut_length"].as_f64().unwrap(),
            )
        })
        .collect()
}

#[test]
fn two_outputs_write_both_programs_and_each_checks_clean_with_its_profile() {
    let d = tmpdir("outputs-two");
    let design = write(&d, "sign.toml", &sign(OPEN_SIGN_OUTPUTS));
    let o = skinpath(&["build", s(&design), "-o", s(&d.join("sign.nc")), "--json"]);
    let j = json(&o);
    let router = d.join("sign.router.gcode");
    let laser = d.join("sign.laser.gcode");
    assert_eq!(
        listing(&d),
        ["sign.laser.gcode", "sign.router.gcode", "sign.toml"],
        "{}",
        text(&o)
    );
    for (file, machine) in [(&router, "grbl-router"), (&laser, "grbl-laser")] {
        let c = skinpath(&["check", s(file), "--machine", machine]);
        assert_eq!(c.status.code(), Some(0), "{machine}: {}", text(&c));
    }
    let outs = j["outputs"].as_array().unwrap();
    assert_eq!(outs.len(), 2);
    assert_eq!(outs[0]["name"], "router");
    assert_eq!(outs[0]["machine"], "grbl-router");
    assert_eq!(outs[0]["file"], s(&router));
    assert_eq!(outs[0]["operations"], serde_json::json!([1, 2, 3]));
    assert_eq!(outs[1]["name"], "laser");
    assert_eq!(outs[1]["operations"], serde_json::json!([4]));
    assert_eq!(outs[1]["summary"]["machine"], "grbl-laser");
    // The router drills the wire holes of the bill of materials; the face has none.
    assert!(outs[0]["summary"]["neon"]["holes"].as_u64().unwrap() > 0);
    assert_eq!(outs[1]["summary"]["neon"]["holes"], 0);
    // Second method: each output cuts exactly what the same operations cut in a single
    // build of the whole design for its machine (same design context, same lengths).
    for (k, machine) in [(0, "grbl-router"), (1, "grbl-laser")] {
        let whole = tmpdir("outputs-whole");
        let plain = write(&whole, "whole.toml", &sign(""));
        let w = json(&skinpath(&[
            "build",
            s(&plain),
            "--machine",
            machine,
            "-o",
            s(&whole.join("w.gcode")),
            "--json",
        ]));
        let all = cut_lengths(&w);
        let mine = cut_lengths(&outs[k]["summary"]);
        assert!(!mine.is_empty());
        for (name, len) in &mine {
            let (_, l) = all.iter().find(|(n, _)| n == name).unwrap();
            assert!(
                (len - l).abs() <= 1e-9 * l.max(1.0),
                "{machine} {name}: {len} vs {l}"
            );
        }
        // The router output leaves the face out, the laser output everything but it.
        let expected = if k == 0 { all.len() - 1 } else { 1 };
        assert_eq!(mine.len(), expected, "{machine}: {mine:?} of {all:?}");
    }
}

#[test]
fn a_failing_output_writes_no_output_and_leaves_no_temporary_file() {
    // The laser face builds; the router output then fails (its second operation asks for
    // the raw envelope, which cannot be cut): neither program is written, older files stay
    // as they were.
    let bad_op = r#"
[[operation]]
name = "raw"
kind = "profile"
method = "envelope"

[[output]]
name = "laser"
machine = "grbl-laser"
operations = ["face"]

[[output]]
name = "router"
machine = "grbl-router"
operations = ["channels", "raw"]
"#;
    let bad_profile =
        OPEN_SIGN_OUTPUTS.replace("machine = \"grbl-laser\"", "machine = \"no-such-laser\"");
    let cases: [(&str, &str, &[&str]); 2] = [
        (
            bad_op,
            "sign.laser.gcode",
            &[
                "output \"router\" (machine grbl-router)",
                "[[operation]] 5 (profile)",
                "envelope",
            ],
        ),
        (
            &bad_profile,
            "sign.router.gcode",
            &["[[output]] \"laser\"", "no-such-laser"],
        ),
    ];
    for (outputs, old, wanted) in cases {
        let d = tmpdir("outputs-fail");
        let design = write(&d, "sign.toml", &sign(outputs));
        write(&d, old, "an older program\n");
        let o = skinpath(&[
            "build",
            s(&design),
            "-o",
            s(&d.join("sign.gcode")),
            "--preview",
            s(&d.join("p.svg")),
        ]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        let err = String::from_utf8_lossy(&o.stderr);
        for w in wanted {
            assert!(err.contains(w), "missing {w:?} in {err}");
        }
        let mut expected = vec![old.to_string(), "sign.toml".to_string()];
        expected.sort();
        assert_eq!(listing(&d), expected, "{}", text(&o));
        assert_eq!(
            std::fs::read_to_string(d.join(old)).unwrap(),
            "an older program\n"
        );
    }
}

#[test]
fn output_files_and_command_line_are_checked_before_anything_is_built() {
    let d = tmpdir("outputs-refused");
    let same_file = OPEN_SIGN_OUTPUTS.replace(
        "operations = [\"face\"]",
        "operations = [\"face\"]\nfile = \"{stem}.router.{ext}\"",
    );
    let unknown_ext = OPEN_SIGN_OUTPUTS.replace(
        "operations = [\"face\"]",
        "operations = [\"face\"]\nfile = \"{stem}.{name}.txt\"",
    );
    let two = write(&d, "two.toml", &sign(OPEN_SIGN_OUTPUTS));
    let plain = write(&d, "plain.toml", &sign(""));
    let cases: Vec<(Vec<String>, Vec<&str>)> = vec![
        (
            vec![s(&write(&d, "same.toml", &sign(&same_file))).into()],
            vec![
                "[[output]] \"laser\"",
                "o.router.gcode",
                "as [[output]] \"router\" does",
            ],
        ),
        (
            vec![s(&write(&d, "ext.toml", &sign(&unknown_ext))).into()],
            vec!["[[output]] \"laser\"", "from .txt"],
        ),
        (
            vec![s(&two).into(), "--machine".into(), "grbl-router".into()],
            vec!["[[output]] tables (router, laser)", "--only NAME"],
        ),
        (
            vec![s(&two).into(), "--only".into(), "face".into()],
            vec!["--only face", "router, laser"],
        ),
        (
            vec![s(&two).into(), "--format".into(), "dxf".into()],
            vec!["--format dxf", "file"],
        ),
        (
            vec![s(&plain).into()],
            vec!["--machine is required", "no [[output]]"],
        ),
        (
            vec![
                s(&plain).into(),
                "--machine".into(),
                "grbl-router".into(),
                "--only".into(),
                "router".into(),
            ],
            vec!["--only", "has none"],
        ),
    ];
    let before = listing(&d);
    for (args, wanted) in cases {
        let mut all: Vec<&str> = vec!["build"];
        all.extend(args.iter().map(String::as_str));
        let out = d.join("o.gcode");
        all.extend(["-o", s(&out)]);
        let o = Command::new(env!("CARGO_BIN_EXE_skinpath"))
            .args(&all)
            .current_dir(&d)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{all:?}: {}", text(&o));
        let err = String::from_utf8_lossy(&o.stderr);
        for w in wanted {
            assert!(err.contains(w), "{all:?}: missing {w:?} in {err}");
        }
        assert_eq!(listing(&d), before, "{all:?}");
    }
}

#[test]
fn only_builds_the_named_outputs_and_fit_scales_every_output_alike() {
    let d = tmpdir("outputs-only");
    let design = write(&d, "sign.toml", &sign(OPEN_SIGN_OUTPUTS));
    let j = json(&skinpath(&[
        "build",
        s(&design),
        "--only",
        "laser",
        "-o",
        s(&d.join("x.gcode")),
        "--json",
    ]));
    assert_eq!(j["files"], serde_json::json!([s(&d.join("x.laser.gcode"))]));
    assert_eq!(listing(&d), ["sign.toml", "x.laser.gcode"]);
    // --fit: each output alone fits at its own scale; together they take the smaller one,
    // and both still fit.
    let (w, h) = (120.0, 60.0);
    let fit = format!("{w}x{h}");
    let scale_of = |v: &serde_json::Value| v["summary"]["placement"]["scale"].as_f64().unwrap();
    let alone: Vec<f64> = ["router", "laser"]
        .iter()
        .map(|name| {
            let j = json(&skinpath(&[
                "build",
                s(&design),
                "--only",
                name,
                "--fit",
                &fit,
                "-o",
                s(&d.join("alone.gcode")),
                "--json",
            ]));
            scale_of(&j["outputs"][0])
        })
        .collect();
    assert!(alone[0] != alone[1], "{alone:?}");
    let j = json(&skinpath(&[
        "build",
        s(&design),
        "--fit",
        &fit,
        "-o",
        s(&d.join("both.gcode")),
        "--json",
    ]));
    let smaller = alone[0].min(alone[1]);
    for o in j["outputs"].as_array().unwrap() {
        assert_eq!(scale_of(o), smaller, "{}", o["name"]);
        let b = &o["summary"]["bounds"];
        let size = |k: usize| b["max"][k].as_f64().unwrap() - b["min"][k].as_f64().unwrap();
        assert!(
            size(0) <= w && size(1) <= h,
            "{}: {} x {}",
            o["name"],
            size(0),
            size(1)
        );
    }
}

#[test]
fn a_signal_during_the_write_leaves_neither_program_nor_temporary_files() {
    // The laser's file is a FIFO no reader opens: the run waits there after the router's
    // program went to its temporary file, and SIGTERM ends it with nothing written.
    let d = tmpdir("outputs-signal");
    let outputs = OPEN_SIGN_OUTPUTS.replace(
        "operations = [\"face\"]",
        "operations = [\"face\"]\nfile = \"face.fifo.gcode\"",
    );
    let design = write(&d, "sign.toml", &sign(&outputs));
    let fifo = d.join("face.fifo.gcode");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let child = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .arg("build")
        .arg(&design)
        .current_dir(&d)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let temporaries = || {
        listing(&d)
            .into_iter()
            .filter(|n| n.starts_with(".skinpath-tmp-"))
            .collect::<Vec<_>>()
    };
    let start = Instant::now();
    while temporaries().is_empty() {
        assert!(start.elapsed() < CHILD_LIMIT, "no temporary file was made");
        std::thread::sleep(Duration::from_millis(10));
    }
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let status = wait_limited(child, "skinpath");
    assert_eq!(status.code(), Some(143), "{status:?}");
    assert_eq!(temporaries(), Vec::<String>::new());
    assert_eq!(listing(&d), ["face.fifo.gcode", "sign.toml"]);
}

#[test]
fn the_neon_starter_layers_build_and_check_clean_when_taken_in() {
    let d = tmpdir("outputs-starter");
    let starter = d.join("design.toml");
    let o = skinpath(&["init", "--neon", "-o", s(&starter)]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    // Take the layers in: every line from the first commented-out table on loses its `# `.
    let written = std::fs::read_to_string(&starter).unwrap();
    let at = written
        .find("# [[operation]]")
        .expect("the commented layers");
    let mut taken = written[..at].to_string();
    for line in written[at..].lines() {
        taken.push_str(
            line.strip_prefix("# ")
                .unwrap_or(line.trim_start_matches('#')),
        );
        taken.push('\n');
    }
    std::fs::write(&starter, taken).unwrap();
    let b = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(["build", "design.toml"])
        .current_dir(&d)
        .output()
        .unwrap();
    assert_eq!(b.status.code(), Some(0), "{}", text(&b));
    for (file, machine) in [
        ("design.router.gcode", "grbl-router"),
        ("design.face.gcode", "grbl-laser"),
    ] {
        let c = skinpath(&["check", s(&d.join(file)), "--machine", machine]);
        assert_eq!(c.status.code(), Some(0), "{file}: {}", text(&c));
    }
}

#[test]
fn a_profile_file_is_read_from_the_design_folder() {
    let d = tmpdir("outputs-profile-file");
    let sub = d.join("sub");
    std::fs::create_dir_all(&sub).unwrap();
    let shipped = Path::new(support::ROOT).join("machines/grbl-laser.toml");
    std::fs::copy(&shipped, sub.join("my-laser.toml")).unwrap();
    let outputs =
        OPEN_SIGN_OUTPUTS.replace("machine = \"grbl-laser\"", "machine = \"my-laser.toml\"");
    write(&sub, "sign.toml", &sign(&outputs));
    // Run from the folder above: the relative profile path is the design's, not the cwd's.
    let o = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(["build", "sub/sign.toml", "--only", "laser", "--json"])
        .current_dir(&d)
        .output()
        .unwrap();
    let j = json(&o);
    assert_eq!(j["files"], serde_json::json!(["sign.laser.gcode"]));
    let c = skinpath(&[
        "check",
        s(&d.join("sign.laser.gcode")),
        "--machine",
        s(&sub.join("my-laser.toml")),
    ]);
    assert_eq!(c.status.code(), Some(0), "{}", text(&c));
}

#[test]
fn an_output_too_large_for_its_machine_is_refused_from_its_own_operations() {
    // 400 mm of stroke on a 300 x 180 mm router: the output's backboard goes around every
    // item, so the design's extent alone refuses it (before the build), naming the output.
    let d = tmpdir("outputs-too-large");
    let design = write(
        &d,
        "long.toml",
        r#"version = 1
[[stroke]]
name = "bar"
disks = [[0.0, 0.0, 3.0], [400.0, 0.0, 3.0]]
[[operation]]
name = "board"
kind = "backboard"
depth = 3.0
[[output]]
name = "router"
machine = "grbl-router"
operations = ["board"]
"#,
    );
    let o = skinpath(&["build", s(&design), "-o", s(&d.join("long.gcode"))]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("output \"router\" (machine grbl-router)"),
        "{err}"
    );
    assert!(err.contains("the job is at least"), "{err}");
    assert_eq!(listing(&d), ["long.toml"]);
}
