//! The RE/MPH route of `build` (issue 14): exact MAT offsets as tool paths.
//!
//! - Random admissible circle sequences: the RE-route profile lies at distance δ from the
//!   RE skin (the exact distance to the union of its MAT disks), within the biarc fitting
//!   tolerance, never inside; the G-code of a design made of the sequence passes the checker.
//! - The examples: the RE and Bézier routes' profile regions differ by at most the two
//!   skins' Hausdorff distance plus the tolerances (geo boolean differences).
//! - `build --method re|mph` on every example and every G-code profile exits cleanly (the
//!   build checks its program and refuses one with errors) and names its routes.

use geo::{Area, BooleanOps, Buffer};
use glam::DVec2;
use proptest::prelude::*;
use skinpath::design::{Design, OutlineMethod};
use skinpath::geom::{Circle, Path};
use skinpath::job::build::{BuildOptions, build_toolpath};
use skinpath::job::check::check_config;
use skinpath::job::outline::{OutlineOptions, design_outlines};
use skinpath::job::re_route::re_items;
use skinpath::machine::builtin_profile;
use skinpath::skin::mat_offset::region_distance;
use skinpath::skin::re::Interp;
use skinpath::toolpath::ops::{self, ProfileSide};
use skinpath::toolpath::re_route::mat_profile;
use skinpath::toolpath::region::Region;
use std::process::Command;

use crate::support;
use support::EXAMPLES;

/// Biarc fitting tolerance of the tests (mm).
const TOL: f64 = 0.01;

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

/// Open sequences inside the router's work area: steps longer than the radius changes.
fn sequence() -> impl Strategy<Value = Vec<Circle>> {
    prop::collection::vec((-0.7f64..0.7, 9.0f64..16.0, 2.5f64..7.0), 3..6).prop_map(|steps| {
        let mut dir = 0.3f64;
        let mut p = DVec2::ZERO;
        let cs: Vec<Circle> = steps
            .iter()
            .map(|&(turn, len, r)| {
                dir += turn;
                p += len * DVec2::new(dir.cos(), dir.sin());
                Circle::new(p, r)
            })
            .collect();
        // Moved so that the lowest circle edge sits 30 mm inside the work area's corner.
        let lo = cs.iter().fold(DVec2::splat(f64::INFINITY), |m, c| {
            m.min(c.c - DVec2::splat(c.r))
        });
        cs.iter()
            .map(|c| Circle::new(c.c - lo + DVec2::splat(30.0), c.r))
            .collect()
    })
}

fn samples(paths: &[Path], per_seg: usize) -> Vec<DVec2> {
    let mut v = Vec::new();
    for p in paths {
        for s in &p.segs {
            for k in 0..=per_seg {
                v.push(s.eval(k as f64 / per_seg as f64));
            }
        }
    }
    v
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    #[test]
    fn re_route_is_at_delta_and_checks_clean(cs in sequence(), ph in any::<bool>()) {
        let method = if ph { "mph" } else { "re" };
        let design = design_of(&cs, method);
        let profile = builtin_profile("grbl-router").unwrap().unwrap();
        // Build-wide method: the items' outlines (the checker's design boundary) are then
        // the RE/MPH skins themselves, not the Bézier skins the route does not follow.
        let opts = BuildOptions {
            tolerance: TOL,
            method: if ph { OutlineMethod::Mph } else { OutlineMethod::Re },
            ..BuildOptions::default()
        };
        let built = build_toolpath(&design, &profile, &opts);
        prop_assume!(built.is_ok());
        let built = built.unwrap();
        prop_assume!(built.routes.iter().all(|r| r.route == method));
        // The same paths from the library, against the exact distance to the skin.
        let interp = if ph { Interp::PhQuintic } else { Interp::Cubic };
        let oo = OutlineOptions { tolerance: TOL, ..OutlineOptions::default() };
        let outlines = design_outlines(&design, &oo).unwrap();
        let items = re_items(&design, &[], &outlines, interp, &oo);
        let item = items[0].as_ref().unwrap();
        let r = profile.default_tool().unwrap().radius();
        let paths = mat_profile(&item.skin, ProfileSide::Outside, r, TOL).unwrap();
        for q in samples(&paths, 8) {
            let d = region_distance(&item.skin, q).unwrap();
            prop_assert!(d > 0.0 && (d - r).abs() <= TOL + 1e-9, "{q}: {d} vs {r}");
        }
        // The machine program passes the checker without errors.
        let g = skinpath::emit::gcode(
            &built.toolpath,
            &profile,
            &skinpath::emit::GcodeOptions {
                job: "random".into(),
                input_units: skinpath::machine::Units::Mm,
                tolerance: TOL * 0.1,
                check_work_area: true,
            },
        )
        .unwrap();
        let mut cfg = check_config(&profile, r);
        cfg.gouge_tolerance = cfg.gouge_tolerance.max(2.0 * TOL + 1e-3 + cfg.flatten_tolerance);
        let bounds = skinpath::job::check::design_boundaries(&built.outlines, true, TOL, 1.0);
        let report = skinpath::sim::check_text(skinpath::sim::Backend::Builtin, &g, &cfg, &bounds);
        prop_assert_eq!(report.errors(), 0, "{}", report);
    }
}

fn to_geo(paths: &[Path], tol: f64) -> geo::MultiPolygon<f64> {
    Region::from_paths(paths, tol).to_geo(tol)
}

/// Largest distance from the points of `a` to the polylines of `b` (both flattened).
fn directed(a: &[Path], b: &[Path], tol: f64) -> f64 {
    let fb: Vec<Vec<DVec2>> = b.iter().map(|p| p.flatten(tol)).collect();
    let mut worst = 0.0f64;
    for p in a {
        for q in p.flatten(tol) {
            let d = fb
                .iter()
                .flat_map(|poly| {
                    (0..poly.len()).map(move |i| {
                        skinpath::geom::Line::new(poly[i], poly[(i + 1) % poly.len()]).distance(q)
                    })
                })
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    worst
}

#[test]
fn re_and_bezier_routes_differ_by_the_skin_distance() {
    let r = 1.5;
    for name in ["circles", "ring_o", "brush", "loop", "snake", "neon_word"] {
        let path = format!("{}/examples/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        let design = skinpath::design::load(&text, &path).unwrap();
        let oo = OutlineOptions {
            tolerance: TOL,
            ..OutlineOptions::default()
        };
        let outlines = design_outlines(&design, &oo).unwrap();
        let strokes = design.strokes().unwrap();
        for interp in [Interp::Cubic, Interp::PhQuintic] {
            let items = re_items(&design, &strokes, &outlines, interp, &oo);
            for (o, it) in outlines.iter().zip(&items) {
                let Ok(it) = it else { continue };
                // The skins' distance (both directions, flattened within TOL).
                let e = directed(&o.contours, &it.outline, TOL).max(directed(
                    &it.outline,
                    &o.contours,
                    TOL,
                ));
                let bez = ops::profile(
                    &Region::from_paths(&o.contours, TOL),
                    ProfileSide::Outside,
                    r,
                    TOL * 0.1,
                );
                let Ok(re) = mat_profile(&it.skin, ProfileSide::Outside, r, TOL) else {
                    continue;
                };
                let (a, b) = (to_geo(&bez, TOL), to_geo(&re, TOL));
                let bound = e + 3.0 * TOL;
                // Each region lies within the other grown by the bound: nothing is left of
                // the difference once the other is grown.
                let a_out = a.difference(&b.buffer(bound)).unsigned_area();
                let b_out = b.difference(&a.buffer(bound)).unsigned_area();
                assert!(
                    a_out < 1e-6 * a.unsigned_area() && b_out < 1e-6 * b.unsigned_area(),
                    "{name}/{} {interp:?}: skins {e:.4} apart, regions leave {a_out} and {b_out}",
                    o.name
                );
                eprintln!("{name}/{}: {interp:?} skins {e:.4} apart", o.name);
            }
        }
    }
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
    let profile = builtin_profile("grbl-router").unwrap().unwrap();
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
    let opts = BuildOptions {
        method: OutlineMethod::Skin,
        ..BuildOptions::default()
    };
    let built = build_toolpath(&design_of(&cs, "skin"), &profile, &opts).unwrap();
    assert_eq!(built.routes[0].route, "skin");
}
