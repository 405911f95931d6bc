//! `skinpath check --timings`: the wall time of each stage, on standard error or as
//! `timings` in the JSON report, without changing the report itself.

mod common;

use common::{skinpath, tmpdir};

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
