//! The RE/MPH route of `build` (issue 14): `build --method re|mph` on every example and
//! every G-code profile exits cleanly (the build checks its program and refuses one with
//! errors) and names its routes. The route's distance to the RE skin on random sequences
//! and its difference from the Bézier route on the examples are unit tests of the
//! library's `job::re_route`.

use glam::DVec2;
use skinpath::design::{Design, OutlineMethod};
use skinpath::geom::Circle;
use skinpath::job::{BuildOptions, build_toolpath};
use skinpath::machine::builtin_profile;
use std::process::Command;

use crate::support;
use support::EXAMPLES;

/// A design of one open circle sequence profiled outside by `method`.
fn design_of(cs: &[Circle], method: &str) -> Design {
    let list: Vec<String> = cs
        .iter()
        .map(|c| format!("[{}, {}, {}]", c.c.x, c.c.y, c.r))
        .collect();
    let text = format!(
        "version = 1\nunits = \"mm\"\n[[circles]]\nname = \"seq\"\nclosed = false\n\
         circles = [{}]\n[[operation]]\nkind = \"profile\"\nside = \"outside\"\n\
         depth = 2.0\nmethod = \"{method}\"\n",
        list.join(", ")
    );
    skinpath::design::load(&text, "random.toml").unwrap()
}

fn build_cli(example: &str, machine: &str, method: &str) -> String {
    build_cli_with(example, machine, method, &[])
}

fn build_cli_with(example: &str, machine: &str, method: &str, extra: &[&str]) -> String {
    let mut args = vec!["--place", "lower-left", "--margin", "5"];
    args.extend_from_slice(extra);
    let (ok, out, err) = try_build(example, machine, method, &args);
    assert!(ok, "{example} on {machine} --method {method}: {err}");
    out
}

/// Whether the build succeeded (build refuses a program that fails its own check, so a
/// success is a clean check), its stdout and its stderr.
fn try_build(example: &str, machine: &str, method: &str, extra: &[&str]) -> (bool, String, String) {
    let out = std::env::temp_dir().join(format!(
        "re_route_try_{example}_{machine}_{method}_{}.gcode",
        std::process::id()
    ));
    let o = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .arg("build")
        .arg(format!(
            "{}/examples/{example}.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .args(["--machine", machine, "-o"])
        .arg(&out)
        .args(["--method", method])
        .args(extra)
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&out);
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn build_method_re_on_every_example_and_profile() {
    // Every example on every G-code profile with default flags; a job larger than the work
    // area takes the `--fit` its message names, the laser engraving `brush` has no depth
    // for a router. Each build that succeeds has passed its own check.
    for ex in EXAMPLES {
        for m in [
            "grbl-laser",
            "grbl-router",
            "linuxcnc-router",
            "marlin-laser",
            "smoothie-laser",
        ] {
            let (mut ok, mut out, mut err) = try_build(ex, m, "re", &[]);
            if !ok && let Some(at) = err.find("--fit ") {
                let fit: String = err[at + 6..]
                    .chars()
                    .take_while(|c| c.is_ascii_digit() || *c == 'x' || *c == '.')
                    .collect();
                (ok, out, err) = try_build(ex, m, "re", &["--fit", &fit]);
            }
            out += &err;
            if ex == "brush" && m.ends_with("router") {
                assert!(!ok && out.contains("needs `depth`"), "{ex} {m}: {out}");
                continue;
            }
            assert!(ok, "{ex} on {m} --method re: {out}");
            // calligraphy is V-carved only: no profile or backboard to route.
            assert!(ex == "calligraphy" || out.contains("route "), "{ex}: {out}");
        }
    }
    for m in ["grbl-laser", "grbl-router", "linuxcnc-router"] {
        let out = build_cli("ring_o", m, "re");
        assert!(out.contains("route profile 1: re ("), "{m}: {out}");
    }
    let out = build_cli("circles", "linuxcnc-router", "mph");
    assert!(out.contains("route profile 1: mph ("), "{out}");
}

/// `build --json` names each operation's route with its segment counts and time, and the
/// time of the RE skins; the counts are those of the program's own arcs and lines.
#[test]
fn json_summary_reports_routes_with_counts_and_times() {
    let out = build_cli_with("ring_o", "grbl-laser", "re", &["--json"]);
    let j: serde_json::Value = serde_json::from_str(&out).expect("json summary");
    let routes = j["routes"].as_array().expect("routes");
    assert!(!routes.is_empty(), "{out}");
    for r in routes {
        assert_eq!(r["route"], "re", "{r}");
        assert!(
            r["arcs"].as_u64().unwrap() + r["lines"].as_u64().unwrap() > 0,
            "{r}"
        );
        assert!(r["seconds"].as_f64().unwrap() >= 0.0, "{r}");
    }
    assert!(j["re_skin_seconds"].as_f64().unwrap() > 0.0, "{out}");
    let skin = build_cli_with("ring_o", "grbl-laser", "skin", &["--json"]);
    let j: serde_json::Value = serde_json::from_str(&skin).expect("json summary");
    assert_eq!(j["re_skin_seconds"].as_f64(), Some(0.0));
    assert!(
        j["routes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|r| r["route"] == "skin")
    );
}

#[test]
fn operation_method_key_and_envelope_refused() {
    let cs = [
        Circle::new(DVec2::new(30.0, 30.0), 3.0),
        Circle::new(DVec2::new(42.0, 33.0), 5.0),
        Circle::new(DVec2::new(55.0, 30.0), 3.5),
    ];
    let profile = builtin_profile("grbl-router").unwrap();
    let built = build_toolpath(&design_of(&cs, "mph"), &profile, &BuildOptions::default()).unwrap();
    assert_eq!(built.routes.len(), 1);
    assert_eq!(built.routes[0].route, "mph");
    assert!(built.routes[0].counts.arcs > 0);
    let e = build_toolpath(
        &design_of(&cs, "envelope"),
        &profile,
        &BuildOptions::default(),
    );
    assert!(
        e.unwrap_err()
            .to_string()
            .contains("[[operation]] 1 (profile)")
    );
    let mut opts = BuildOptions::default();
    opts.method = OutlineMethod::Skin;
    let built = build_toolpath(&design_of(&cs, "skin"), &profile, &opts).unwrap();
    assert_eq!(built.routes[0].route, "skin");
}
