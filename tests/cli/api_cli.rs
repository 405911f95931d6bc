//! The command line over the library API: `--timings` of `build` and `outline` (shape only,
//! never values), and a closed stdout (`skinpath ... | head -c 10`) ends quietly with
//! status 0 instead of a panic.

use crate::support;

use std::process::{Command, Stdio};
use support::{ROOT, example_path, skinpath, tmpdir};

#[test]
fn build_timings_are_a_json_object_of_stages() {
    let d = tmpdir("api-timings");
    let out = d.join("w.gcode");
    let o = skinpath(&[
        "build",
        &example_path("neon_word"),
        "--machine",
        "grbl-router",
        "-o",
        out.to_str().unwrap(),
        "--json",
        "--timings",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let t = v["timings"].as_object().expect("a timings object");
    for stage in [
        "read", "skin", "toolpath", "place", "emit", "check", "write", "total",
    ] {
        let s = t.get(stage).and_then(|x| x.as_f64());
        assert!(s.is_some_and(|s| s >= 0.0), "no {stage} in {t:?}");
    }
    // Without --timings the summary has no timings (the JSON stays as it was).
    let o = skinpath(&[
        "build",
        &example_path("neon_word"),
        "--machine",
        "grbl-router",
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v.get("timings").is_none());
    assert!(
        o.stderr.is_empty(),
        "no progress bar when stderr is not a terminal"
    );
}

#[test]
fn timings_tables_go_to_stderr() {
    let d = tmpdir("api-timings-table");
    let gcode = d.join("w.gcode");
    let svg = d.join("w.svg");
    let runs: [Vec<&str>; 2] = [
        vec![
            "build",
            "--machine",
            "grbl-laser",
            "-o",
            gcode.to_str().unwrap(),
            "--timings",
        ],
        vec!["outline", "-o", svg.to_str().unwrap(), "--timings"],
    ];
    let design = example_path("snake");
    for mut args in runs {
        args.insert(1, &design);
        let o = skinpath(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let err = String::from_utf8_lossy(&o.stderr);
        let rows: Vec<&str> = err.lines().collect();
        assert_eq!(
            rows.first().map(|r| r.split_whitespace().next()),
            Some(Some("stage"))
        );
        assert_eq!(
            rows.last().and_then(|r| r.split_whitespace().next()),
            Some("total")
        );
        for want in ["read", "skin", "emit", "write"] {
            let row = rows.iter().find(|r| r.starts_with(want));
            let ms = row.and_then(|r| r.split_whitespace().nth(1)?.parse::<f64>().ok());
            assert!(ms.is_some(), "{args:?}: no {want} row in\n{err}");
        }
        assert!(!String::from_utf8_lossy(&o.stdout).contains("stage"));
    }
}

#[test]
fn a_closed_stdout_is_a_quiet_success() {
    let d = tmpdir("api-pipe");
    let out = d.join("w.gcode");
    let runs: [Vec<String>; 4] = [
        vec!["inspect".into(), example_path("neon_word"), "--json".into()],
        vec![
            "build".into(),
            example_path("neon_word"),
            "--machine".into(),
            "grbl-router".into(),
            "-o".into(),
            out.display().to_string(),
            "--json".into(),
        ],
        vec!["machines".into()],
        // The program the build above wrote, checked.
        vec![
            "check".into(),
            out.display().to_string(),
            "--machine".into(),
            "grbl-router".into(),
        ],
    ];
    for args in runs {
        // The reading end of stdout is closed before the command writes anything.
        let mut child = Command::new(env!("CARGO_BIN_EXE_skinpath"))
            .args(&args)
            .current_dir(ROOT)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
    }
}
