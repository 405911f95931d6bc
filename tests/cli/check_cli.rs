//! `skinpath check --timings`: the wall time of each stage, on standard error or as
//! `timings` in the JSON report, without changing the report itself.

use crate::support;

use support::{skinpath, tmpdir};

#[test]
fn timings_are_printed_per_stage() {
    let d = tmpdir("check-timings");
    let f = d.join("p.gcode");
    std::fs::write(
        &f,
        "G21 G90\nG0 X1 Y1\nM3 S1000\nG1 X2 Y1 F600\nG1 X2 Y2\nM5\nM2\n",
    )
    .expect("write");
    let p = f.to_string_lossy().into_owned();
    let plain = skinpath(&["check", &p]);
    let timed = skinpath(&["check", &p, "--timings"]);
    assert_eq!(plain.status.code(), timed.status.code());
    // The report is unchanged; the timings go to standard error.
    assert_eq!(plain.stdout, timed.stdout);
    let err = String::from_utf8_lossy(&timed.stderr);
    for stage in ["read", "interpret", "checks", "estimate", "report", "total"] {
        assert!(
            err.contains(&format!("{stage} ")),
            "{stage} missing in {err}"
        );
    }
    let json = skinpath(&["check", &p, "--json", "--timings"]);
    let v: serde_json::Value =
        serde_json::from_slice(&json.stdout).expect("check --json --timings gives JSON");
    for stage in ["read", "interpret", "checks", "estimate", "report"] {
        let t = v["timings"][stage].as_f64();
        assert!(t.is_some_and(|t| t >= 0.0), "{stage}: {v}");
    }
    // Everything else is the plain JSON report.
    let plain_json = skinpath(&["check", &p, "--json"]);
    let mut pv: serde_json::Value =
        serde_json::from_slice(&plain_json.stdout).expect("check --json gives JSON");
    let mut tv = v.clone();
    if let Some(o) = tv.as_object_mut() {
        o.remove("timings");
    }
    if let Some(o) = pv.as_object_mut() {
        o.remove("timings");
    }
    assert_eq!(tv, pv);
    let _ = std::fs::remove_dir_all(&d);
}

/// `--json` prints a JSON report when the input cannot be used at all (issue 42, item 4):
/// a missing program, an unknown machine profile. Not usable, the error as its reason and
/// its one `input-error` finding, exit 2; without `--json` the error stays on standard
/// error with the same status.
#[test]
fn json_report_when_the_input_is_unusable() {
    let d = tmpdir("check-json-unusable");
    let prog = d.join("p.gcode");
    std::fs::write(&prog, "G21 G90\nG0 X1 Y1\nM2\n").expect("write");
    let missing = d.join("missing.gcode").to_string_lossy().into_owned();
    let p = prog.to_string_lossy().into_owned();
    for args in [
        vec!["check", missing.as_str(), "--json"],
        vec![
            "check",
            p.as_str(),
            "--machine",
            "no-such-machine",
            "--json",
        ],
    ] {
        let o = skinpath(&args);
        let out = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {out}");
        let v: serde_json::Value = serde_json::from_str(&out).expect("a JSON report");
        assert_eq!(v["usable"], false, "{out}");
        assert_eq!(v["backend"], "builtin", "{out}");
        assert_eq!(v["findings"][0]["id"], "input-error", "{out}");
        assert_eq!(v["findings"].as_array().map(Vec::len), Some(1), "{out}");
        assert!(v["reason"].as_str().is_some_and(|r| !r.is_empty()), "{out}");
        let text = skinpath(&args[..args.len() - 1]);
        assert_eq!(text.status.code(), Some(2));
        assert!(text.stdout.is_empty());
        assert!(!text.stderr.is_empty());
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// `check --design` (a program built with `--place design`): the tool keeps its radius from
/// the design's parts only. A neon sign's
/// channels and holes cut into their strokes by design and are no gouges (thousands were
/// reported); the ring's outside profile keeps the ring a part, so claiming a tool larger
/// than the one that cut it finds the gouges it would make.
#[test]
fn design_gouges_are_judged_on_the_parts_only() {
    let d = tmpdir("check-design-parts");
    for (design, claimed_radius, gouges) in [
        ("examples/gallery/neon_open.toml", None, false),
        ("examples/ring_o.toml", None, false),
        ("examples/ring_o.toml", Some("4"), true),
    ] {
        let src = format!("{}/{design}", support::ROOT);
        let prog = d.join("p.gcode").to_string_lossy().into_owned();
        // In the design's coordinates, which the check compares with.
        let b = skinpath(&[
            "build",
            &src,
            "--machine",
            "grbl-router",
            "--place",
            "design",
            "-o",
            &prog,
        ]);
        assert!(
            b.status.success(),
            "{design}: {}",
            String::from_utf8_lossy(&b.stderr)
        );
        let mut args = vec!["check", &prog, "--machine", "grbl-router", "--design", &src];
        if let Some(r) = claimed_radius {
            args.extend(["--tool-radius", r]);
        }
        let c = skinpath(&args);
        let out = String::from_utf8_lossy(&c.stdout);
        assert_eq!(
            out.contains("[gouge]"),
            gouges,
            "{design} {claimed_radius:?}: {out}"
        );
        assert_eq!(c.status.success(), !gouges, "{design}: {out}");
    }
}
