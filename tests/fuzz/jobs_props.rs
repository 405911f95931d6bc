//! Jobs that never fail a user (issue 11), through the library: position and scale
//! invariance of the build on every example, and random designs (sharp bends, near
//! contacts, crossings, random channel widths, holes and backboards) on a router and a laser
//! profile: every build either succeeds and passes the checker as `check --machine` would
//! run it, or fails with a message that names the design file and what went wrong.
//!
//! The random designs come from a fixed seed (a SplitMix64 stream), so CI sees the same
//! cases on every run. `SKINPATH_RANDOM_BUILDS=N` runs N cases (CI: [`CI_CASES`]), and
//! `SKINPATH_RANDOM_SEED=S` picks another stream for long local runs; the test prints the
//! counts of successes and of each kind of failure.

use skinpath::design::{Design, Operation, OperationKind, load};
use skinpath::emit::{GcodeOptions, gcode};
use skinpath::job::build::{
    BuildOptions, BuildResult, Place, build_toolpath, place_job, scaled_design,
};
use skinpath::job::check::check_config;
use skinpath::machine::{Profile, Units, builtin_profile};
use skinpath::sim::{Backend, Severity, check_text};
use std::collections::BTreeMap;

use crate::support;
use support::rng::Rng;
use support::{EXAMPLES, example};

/// Random builds per profile in CI.
const CI_CASES: usize = 6;

fn profile(name: &str) -> Profile {
    builtin_profile(name).unwrap().unwrap()
}

/// Per operation (machine order): name, number of cuts, cut length; and the xy bounds.
fn summary(b: &BuildResult) -> (Vec<(String, usize, f64)>, [f64; 4]) {
    let ops = b
        .toolpath
        .operations
        .iter()
        .map(|op| {
            let single = skinpath::toolpath::Toolpath {
                operations: vec![op.clone()],
            };
            let s = single.stats(glam::DVec2::ZERO);
            (op.name.clone(), op.cuts.len(), s.cut_length)
        })
        .collect();
    let s = b.toolpath.stats(glam::DVec2::ZERO);
    (
        ops,
        [s.bbox_min[0], s.bbox_min[1], s.bbox_max[0], s.bbox_max[1]],
    )
}

/// The design moved by `d` (strokes and circles; operations have no coordinates).
fn translated(design: &Design, d: [f64; 2]) -> Design {
    let mut out = design.clone();
    let mv = |v: &mut [f64; 3]| {
        v[0] += d[0];
        v[1] += d[1];
    };
    for s in &mut out.stroke {
        for list in [&mut s.disks, &mut s.points].into_iter().flatten() {
            list.iter_mut().for_each(mv);
        }
    }
    for c in &mut out.circles {
        c.circles.iter_mut().for_each(mv);
    }
    out
}

/// Every length of the design and of the profile's tools scaled by `f`: geometry (through
/// [`scaled_design`]) and the operations' physical sizes too, so the whole job is similar.
fn scaled_job(design: &Design, profile: &Profile, f: f64) -> (Design, Profile) {
    let mut d = scaled_design(design, f);
    let s = |v: &mut Option<f64>| {
        if let Some(x) = v {
            *x *= f;
        }
    };
    for op in &mut d.operation {
        for v in [
            &mut op.step_down,
            &mut op.depth,
            &mut op.lead_in,
            &mut op.width,
            &mut op.margin,
            &mut op.min_inner_radius,
            &mut op.diameter,
            &mut op.spacing,
            &mut op.max_depth,
        ] {
            s(v);
        }
        if let Some(t) = &mut op.tabs {
            t.width *= f;
            t.height *= f;
        }
    }
    if let Some(o) = &mut d.outline
        && let Some(t) = &mut o.tolerance
    {
        *t *= f;
    }
    let mut p = profile.clone();
    for t in &mut p.tools {
        t.diameter *= f;
        t.kerf *= f;
        t.tip_diameter *= f;
    }
    (d, p)
}

/// Position independence (issue 11, item 2): the toolpath of a design moved by
/// (10000, −5000) is the toolpath moved, and of a design scaled by 1000 (tools too) the
/// toolpath scaled, within the output rounding (1e-3 mm, scaled with the job) and the
/// build tolerance on lengths. Every example, on a router and a laser profile.
#[test]
fn translation_and_scale_invariance_on_every_example() {
    let opts = BuildOptions::default();
    for name in EXAMPLES {
        let mut design = example(name);
        // A design without operations gets a default profile 3 mm deep: a physical default
        // that does not scale with the design, so state it to scale it below.
        if design.operation.is_empty() {
            let mut op = Operation::new(OperationKind::Profile);
            op.depth = Some(3.0);
            design.operation.push(op);
        }
        for machine in ["grbl-laser", "grbl-router"] {
            let p = profile(machine);
            let base = match build_toolpath(&design, &p, &opts) {
                Ok(b) => b,
                // The brush engraving has no depth for a router: refused the same way
                // wherever it is (checked by the CLI test of every example).
                Err(e) => {
                    assert!(machine == "grbl-router" && name == "brush", "{name}: {e}");
                    continue;
                }
            };
            let (ops0, b0) = summary(&base);
            // Moved.
            let d = [10000.0, -5000.0];
            let moved = build_toolpath(&translated(&design, d), &p, &opts)
                .unwrap_or_else(|e| panic!("{name} moved on {machine}: {e}"));
            let (ops1, b1) = summary(&moved);
            assert_eq!(ops0.len(), ops1.len(), "{name} on {machine}");
            for ((n0, c0, l0), (n1, c1, l1)) in ops0.iter().zip(&ops1) {
                assert_eq!((n0, c0), (n1, c1), "{name} moved on {machine}");
                assert!(
                    (l0 - l1).abs() <= 1e-4 * l0.max(1.0),
                    "{name} moved on {machine}, {n0}: length {l0} vs {l1}"
                );
            }
            for k in 0..4 {
                let want = b0[k] + d[k % 2];
                assert!(
                    (b1[k] - want).abs() <= 1e-3,
                    "{name} moved on {machine}: bound {k} {} vs {want}",
                    b1[k]
                );
            }
            // Scaled by 1000, tolerances with it.
            let f = 1000.0;
            let (sd, sp) = scaled_job(&design, &p, f);
            let sopts = BuildOptions {
                tolerance: opts.tolerance * f,
                epsilon: opts.epsilon * f,
                ..opts
            };
            let big = build_toolpath(&sd, &sp, &sopts)
                .unwrap_or_else(|e| panic!("{name} scaled on {machine}: {e}"));
            let (ops2, b2) = summary(&big);
            assert_eq!(ops0.len(), ops2.len(), "{name} scaled on {machine}");
            for ((n0, c0, l0), (n2, c2, l2)) in ops0.iter().zip(&ops2) {
                assert_eq!((n0, c0), (n2, c2), "{name} scaled on {machine}");
                assert!(
                    (l0 * f - l2).abs() <= 1e-4 * (l0 * f).max(1.0),
                    "{name} scaled on {machine}, {n0}: length {} vs {l2}",
                    l0 * f
                );
            }
            for k in 0..4 {
                assert!(
                    (b2[k] - f * b0[k]).abs() <= 1e-3 * f,
                    "{name} scaled on {machine}: bound {k} {} vs {}",
                    b2[k],
                    f * b0[k]
                );
            }
        }
    }
}

/// A random design: 1–4 strokes of 4–7 points with sharp bends (turns up to 170°), some
/// started near or across another stroke, radii 1–5 mm; a channel of random width, holes
/// at the ends and a backboard with random margin, corner radius and tabs.
fn random_design(rng: &mut Rng) -> String {
    let mut t = String::from("version = 1\nunits = \"mm\"\n");
    let n = 1 + rng.below(4);
    let mut ends: Vec<[f64; 2]> = Vec::new();
    let r = rng.range(1.0, 5.0);
    for k in 0..n {
        let m = 4 + rng.below(4);
        let mut p = match (ends.last(), rng.below(3)) {
            // Start near another stroke's end (a near contact or a junction).
            (Some(e), 0) => [e[0] + rng.range(-r, r), e[1] + rng.range(-r, r)],
            _ => [rng.range(10.0, 110.0), rng.range(10.0, 110.0)],
        };
        let mut heading = rng.range(0.0, std::f64::consts::TAU);
        let mut pts = Vec::new();
        for _ in 0..m {
            pts.push(format!("[{:.3}, {:.3}, {r:.3}]", p[0], p[1]));
            heading += rng.range(-2.97, 2.97) * if rng.below(3) == 0 { 1.0 } else { 0.3 };
            let step = rng.range(2.0 * r, 30.0);
            p = [p[0] + step * heading.cos(), p[1] + step * heading.sin()];
        }
        ends.push(p);
        t += &format!(
            "[[stroke]]\nname = \"s{k}\"\npoints = [{}]\n",
            pts.join(", ")
        );
    }
    let width = rng.range(2.0, 14.0);
    t += &format!(
        "[[operation]]\nkind = \"channel\"\nwidth = {width:.3}\ndepth = {:.2}\nstep_down = 2.0\n",
        rng.range(1.0, 8.0)
    );
    if rng.below(2) == 0 {
        t += &format!(
            "[[operation]]\nkind = \"holes\"\ndiameter = {:.3}\ndepth = {:.2}\n",
            rng.range(1.0, 9.0),
            rng.range(1.0, 10.0)
        );
    }
    if rng.below(2) == 0 {
        t += &format!(
            "[[operation]]\nkind = \"backboard\"\nmargin = {:.3}\nmin_inner_radius = {:.3}\n\
             depth = {:.2}\n",
            rng.range(1.0, 15.0),
            rng.range(0.5, 8.0),
            rng.range(1.0, 10.0)
        );
        if rng.below(2) == 0 {
            t += &format!(
                "tabs = {{ count = {}, width = {:.2}, height = 1.0 }}\n",
                1 + rng.below(5),
                rng.range(1.0, 6.0)
            );
        }
    }
    t
}

/// One random build as `skinpath build` runs it (default placement, the checker as
/// `check --machine` configures it): Ok, or the error message.
fn random_build(text: &str, p: &Profile) -> Result<(), String> {
    let file = "random.toml";
    let design = load(text, file).map_err(|e| e.to_string())?;
    let opts = BuildOptions::default();
    let mut built = build_toolpath(&design, p, &opts).map_err(|e| e.to_string())?;
    place_job(&mut built, p, 1.0, Place::LowerLeft, 0.0, 2e-3, 1.0).map_err(|e| e.to_string())?;
    let g = gcode(
        &built.toolpath,
        p,
        &GcodeOptions {
            job: "random".into(),
            input_units: Units::Mm,
            tolerance: opts.tolerance * 0.1,
            check_work_area: true,
        },
    )
    .map_err(|e| e.to_string())?;
    let tool_r = p.default_tool().map(|t| t.radius()).unwrap_or(0.0);
    let report = check_text(Backend::Builtin, &g, &check_config(p, tool_r), &[]);
    let bad: Vec<String> = report
        .findings
        .iter()
        .filter(|f| f.severity > Severity::Info)
        .map(|f| format!("{} line {:?}: {}", f.id, f.lines, f.message))
        .collect();
    if bad.is_empty() {
        Ok(())
    } else {
        Err(format!("CHECK: {}", bad.join("; ")))
    }
}

/// The kind of a failure, for the tally: the checker's finding ids, or the error's gist.
fn kind(msg: &str) -> String {
    if let Some(rest) = msg.strip_prefix("CHECK: ") {
        let mut ids: Vec<&str> = rest
            .split("; ")
            .filter_map(|f| f.split_whitespace().next())
            .collect();
        ids.sort();
        ids.dedup();
        return format!("check: {}", ids.join("+"));
    }
    let gist = msg.split(": ").skip(1).collect::<Vec<_>>().join(": ");
    let words: Vec<&str> = gist.split_whitespace().take(7).collect();
    words.join(" ")
}

#[test]
fn random_designs_build_clean_or_fail_clearly() {
    let cases: usize = std::env::var("SKINPATH_RANDOM_BUILDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(CI_CASES);
    let seed: u64 = std::env::var("SKINPATH_RANDOM_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0011);
    let mut rng = Rng::new(seed);
    let mut tally: BTreeMap<String, usize> = BTreeMap::new();
    let mut check_failures = Vec::new();
    for case in 0..cases {
        let text = random_design(&mut rng);
        for machine in ["grbl-router", "grbl-laser"] {
            let p = profile(machine);
            match random_build(&text, &p) {
                Ok(()) => *tally.entry(format!("{machine}: ok")).or_default() += 1,
                Err(msg) => {
                    *tally
                        .entry(format!("{machine}: {}", kind(&msg)))
                        .or_default() += 1;
                    if msg.starts_with("CHECK") {
                        check_failures.push(format!("case {case} on {machine}: {msg}\n{text}"));
                    } else {
                        // A refused build names the design file and says what is wrong.
                        assert!(
                            msg.contains("random.toml") || msg.contains("--fit"),
                            "case {case} on {machine}: unclear error {msg}\n{text}"
                        );
                    }
                }
            }
        }
    }
    eprintln!("random builds: {cases} designs x 2 profiles, seed {seed:#x}");
    for (k, n) in &tally {
        eprintln!("  {n:5}  {k}");
    }
    assert!(
        check_failures.is_empty(),
        "{} builds did not check clean:\n{}",
        check_failures.len(),
        check_failures.join("\n\n")
    );
}
