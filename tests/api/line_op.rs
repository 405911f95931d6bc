//! The `line` operation (issue 39, Build item 2): a drawing's lines are cut once along
//! their centre line, and `check` with the profile and no flags lets line cuts cross.
//!
//! Programs are read back with the `gcode` crate (an independent parser); cut lengths are
//! compared with lengths computed independently: a spine's arc length by Simpson's rule on
//! ‖q′(t)‖, and svg2gcode's `shapes.svg` against its drawn length computed from the element
//! attributes (tests/line_data/README.md).

use crate::support;

use ::gcode::{Code, Value};
use glam::{DVec2, DVec3};
use std::path::Path;
use support::rng::Rng;
use support::{skinpath, tmpdir};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn num(v: &Value) -> f64 {
    match v {
        Value::Literal(x) => *x as f64,
        _ => panic!("non-literal value {v:?}"),
    }
}

/// A run of cutting moves between two non-cutting ones: its points (arcs flattened finely),
/// its length (arcs by radius × sweep) and its depths.
#[derive(Debug, Default)]
struct Run {
    points: Vec<DVec2>,
    length: f64,
    z: Vec<f64>,
}

/// The cut runs of a program read with the `gcode` crate (its numbers are f32: compare
/// within 1e-6 relative). Laser (`laser`): moves with the
/// beam on (M3/M4 and S > 0); router: feed moves in the plane below z = 0. Plunges and
/// retracts end a run.
fn runs(src: &str, laser: bool) -> Vec<Run> {
    let prog = ::gcode::parse(src).unwrap_or_else(|e| panic!("gcode crate rejects: {e:?}"));
    let (mut pos, mut s, mut on, mut motion) = (DVec3::ZERO, 0.0, false, 0u32);
    let mut out = Vec::new();
    let mut cur: Option<Run> = None;
    for b in &prog.blocks {
        let mut words: Vec<(char, f64)> = b
            .word_addresses
            .iter()
            .map(|w| (w.letter.to_ascii_uppercase(), num(&w.value)))
            .collect();
        for code in &b.codes {
            let args = match code {
                Code::General(g) => {
                    if g.number.major() <= 3 {
                        motion = g.number.major();
                    }
                    &g.args
                }
                Code::Miscellaneous(m) => {
                    match m.number.major() {
                        3 | 4 => on = true,
                        5 => on = false,
                        _ => {}
                    }
                    &m.args
                }
                _ => continue,
            };
            words.extend(
                args.iter()
                    .map(|a| (a.letter.to_ascii_uppercase(), num(&a.value))),
            );
        }
        let get = |c: char| words.iter().find(|w| w.0 == c).map(|w| w.1);
        if let Some(v) = get('S') {
            s = v;
        }
        let (x, y, z) = (get('X'), get('Y'), get('Z'));
        if x.is_none() && y.is_none() && z.is_none() {
            continue;
        }
        let to = DVec3::new(x.unwrap_or(pos.x), y.unwrap_or(pos.y), z.unwrap_or(pos.z));
        let planar = to.z == pos.z;
        let cutting = motion >= 1 && planar && if laser { on && s > 0.0 } else { to.z < 0.0 };
        if cutting {
            let run = cur.get_or_insert_with(|| Run {
                points: vec![pos.truncate()],
                ..Run::default()
            });
            let (a, b) = (pos.truncate(), to.truncate());
            if motion >= 2 {
                let c = a + DVec2::new(get('I').unwrap_or(0.0), get('J').unwrap_or(0.0));
                let r = a.distance(c);
                let a0 = (a - c).to_angle();
                let mut sw = (b - c).to_angle() - a0;
                let tau = std::f64::consts::TAU;
                if motion == 3 {
                    while sw <= 0.0 {
                        sw += tau;
                    }
                } else {
                    while sw >= 0.0 {
                        sw -= tau;
                    }
                }
                run.length += r * sw.abs();
                let n = 64;
                for k in 1..=n {
                    let t = a0 + sw * k as f64 / n as f64;
                    run.points.push(c + r * DVec2::from_angle(t));
                }
            } else {
                run.length += a.distance(b);
                run.points.push(b);
            }
            run.z.push(to.z);
        } else if let Some(r) = cur.take() {
            out.push(r);
        }
        pos = to;
    }
    out.extend(cur);
    out
}

/// Error findings `skinpath check PROGRAM --machine M` (no other flag) reports in its
/// `--json` (a suppressed id always has shown findings), with the report.
fn check_errors(program: &Path, machine: &str) -> (usize, String) {
    let o = skinpath(&["check", s(program), "--machine", machine, "--json"]);
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| {
        panic!(
            "check --json: {e}: {text}\n{}",
            String::from_utf8_lossy(&o.stderr)
        )
    });
    let errors = v["findings"]
        .as_array()
        .unwrap_or_else(|| panic!("no findings in {text}"))
        .iter()
        .filter(|f| f["severity"] == "error")
        .count();
    assert_eq!(
        o.status.success(),
        errors == 0,
        "exit status vs findings: {text}"
    );
    (errors, text)
}

fn build(design: &Path, machine: &str, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["build", s(design), "--machine", machine, "-o", s(out)];
    args.extend_from_slice(extra);
    skinpath(&args)
}

fn expect_ok(o: &std::process::Output, what: &str) {
    assert!(
        o.status.success(),
        "{what}: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// svg2gcode's shapes.svg draws seven outlines with strokes 0.3–1 mm wide: built with
/// default flags it gives seven cuts on a laser (one per outline, not two edges each), the
/// cut length within 1.5× the drawn length (667.198 mm, computed independently: README in
/// tests/line_data), and the program checks clean on the same profile with no flags; on a
/// router the seven lines are engraved at the default shallow depth.
#[test]
fn shapes_svg_hairlines_are_cut_once() {
    const DRAWN_MM: f64 = 667.198;
    let dir = tmpdir("line-shapes");
    let svg = Path::new(support::ROOT).join("tests/line_data/shapes.svg");
    for (machine, laser) in [("grbl-laser", true), ("grbl-router", false)] {
        let out = dir.join(format!("shapes.{machine}.gcode"));
        let o = build(&svg, machine, &out, &[]);
        expect_ok(&o, &format!("build shapes.svg on {machine}"));
        let text = std::fs::read_to_string(&out).unwrap();
        let cuts = runs(&text, laser);
        assert_eq!(cuts.len(), 7, "{machine}: {} cuts", cuts.len());
        let len: f64 = cuts.iter().map(|r| r.length).sum();
        assert!(
            (0.98 * DRAWN_MM..=1.5 * DRAWN_MM).contains(&len),
            "{machine}: cut length {len} vs drawn {DRAWN_MM}"
        );
        if !laser {
            assert!(
                cuts.iter()
                    .flat_map(|r| &r.z)
                    .all(|&z| (z + 0.2).abs() < 1e-6)
            );
        }
        assert!(
            text.contains("(skinpath:group 0)"),
            "{machine}: no line mark"
        );
        let (errors, report) = check_errors(&out, machine);
        assert_eq!(errors, 0, "{machine}: {report}");
    }
}

/// Simpson's rule (composite, `n` even) of ‖q′(t)‖ over the stroke's domain: the spine's
/// arc length, independent of the biarc fit the cut is made of.
fn spine_length(design: &skinpath::design::Design, k: usize) -> f64 {
    let c = &design.strokes().unwrap()[k];
    let (lo, hi) = c.domain();
    let n = 20_000;
    let h = (hi - lo) / n as f64;
    let speed = |t: f64| c.derivs(t, 1)[1].0.length();
    let mut acc = speed(lo) + speed(hi);
    for i in 1..n {
        acc += if i % 2 == 1 { 4.0 } else { 2.0 } * speed(lo + i as f64 * h);
    }
    acc * h / 3.0
}

const CURVES: &str = r#"version = 1
[[stroke]]
name = "wave"
disks = [[0.0, 0.0, 0.2], [15.0, 12.0, 0.2], [30.0, -8.0, 0.2], [45.0, 10.0, 0.2], [60.0, 0.0, 0.2]]
[[stroke]]
name = "loop"
closed = true
disks = [[80.0, 0.0, 0.2], [100.0, 10.0, 0.2], [90.0, 30.0, 0.2], [70.0, 20.0, 0.2]]
[[operation]]
kind = "line"
"#;

/// A line cut follows each spine once: one cut per stroke, the open spine open (its ends
/// on the spine's ends, 60 mm apart), the closed one closed, each as long as the spine
/// (Simpson) within 0.1 %; a router engraves at the default 0.2 mm, or at `depth` in
/// `step_down` levels.
#[test]
fn line_cut_length_is_the_spine_length() {
    let dir = tmpdir("line-spine");
    let design_path = dir.join("curves.toml");
    std::fs::write(&design_path, CURVES).unwrap();
    let design = skinpath::design::load(CURVES, "curves.toml").unwrap();
    let want = [spine_length(&design, 0), spine_length(&design, 1)];
    for (machine, laser) in [("grbl-laser", true), ("grbl-router", false)] {
        let out = dir.join(format!("curves.{machine}.gcode"));
        expect_ok(&build(&design_path, machine, &out, &[]), machine);
        let text = std::fs::read_to_string(&out).unwrap();
        let mut cuts = runs(&text, laser);
        assert_eq!(cuts.len(), 2, "{machine}");
        // Placement moves the job: tell the cuts apart by their closedness.
        cuts.sort_by_key(|r| (r.points[0].distance(*r.points.last().unwrap()) < 1e-6) as u8);
        let (open, closed) = (&cuts[0], &cuts[1]);
        let ends = open.points[0].distance(*open.points.last().unwrap());
        assert!(
            (ends - 60.0).abs() < 2e-3,
            "{machine}: open ends {ends} apart"
        );
        for (run, want) in [(open, want[0]), (closed, want[1])] {
            assert!(
                (run.length - want).abs() <= 1e-3 * want,
                "{machine}: cut {} vs spine {want}",
                run.length
            );
        }
        if !laser {
            assert!(
                cuts.iter()
                    .flat_map(|r| &r.z)
                    .all(|&z| (z + 0.2).abs() < 1e-6)
            );
        }
        let (errors, report) = check_errors(&out, machine);
        assert_eq!(errors, 0, "{machine}: {report}");
    }
    // Router passes: depth 0.5 in steps of 0.25, each level a run of its own.
    let deep = CURVES.replace(
        "kind = \"line\"",
        "kind = \"line\"\ndepth = 0.5\nstep_down = 0.25",
    );
    let deep_path = dir.join("deep.toml");
    std::fs::write(&deep_path, deep).unwrap();
    let out = dir.join("deep.gcode");
    expect_ok(&build(&deep_path, "grbl-router", &out, &[]), "deep");
    let cuts = runs(&std::fs::read_to_string(&out).unwrap(), false);
    let mut levels: Vec<f64> = cuts.iter().flat_map(|r| r.z.clone()).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    assert_eq!(levels, [-0.5, -0.25]);
}

/// A grid of crossing hairlines, one of them crossing itself, cut as lines: the program
/// checks clean with the profile and no flags. The same strokes cut out as two profiles
/// that cross are still errors.
#[test]
fn crossing_lines_check_clean_crossing_profiles_do_not() {
    let dir = tmpdir("line-cross");
    let mut text = String::from("version = 1\n");
    for i in 0..6 {
        let v = 10.0 * i as f64;
        text += &format!(
            "[[stroke]]\nname = \"h{i}\"\ndisks = [[0.0, {v}, 0.1], [50.0, {v}, 0.1]]\n\
             [[stroke]]\nname = \"v{i}\"\ndisks = [[{v}, -5.0, 0.1], [{v}, 55.0, 0.1]]\n"
        );
    }
    // A cubic whose spine loops, crossing itself once.
    text += "[[stroke]]\nname = \"eight\"\n\
             disks = [[60.0, 0.0, 0.1], [95.0, 25.0, 0.1], [50.0, 25.0, 0.1], [85.0, 0.0, 0.1]]\n";
    let lines = format!("{text}[[operation]]\nkind = \"line\"\n");
    let path = dir.join("grid.toml");
    std::fs::write(&path, &lines).unwrap();
    for machine in ["grbl-laser", "grbl-router"] {
        let out = dir.join(format!("grid.{machine}.gcode"));
        expect_ok(&build(&path, machine, &out, &[]), machine);
        let (errors, report) = check_errors(&out, machine);
        assert_eq!(errors, 0, "{machine}: {report}");
        assert_eq!(
            runs(
                &std::fs::read_to_string(&out).unwrap(),
                machine == "grbl-laser"
            )
            .len(),
            13
        );
    }
    // Two profiles of crossing strokes: their cuts cross, and the checker says so.
    let profiles = format!(
        "{text}[[operation]]\nkind = \"profile\"\nstrokes = [\"h2\"]\n\
         [[operation]]\nkind = \"profile\"\nstrokes = [\"v2\"]\n"
    );
    let path = dir.join("profiles.toml");
    std::fs::write(&path, profiles).unwrap();
    let out = dir.join("profiles.gcode");
    let o = build(&path, "grbl-laser", &out, &["--write-unchecked"]);
    assert!(out.is_file(), "{}", String::from_utf8_lossy(&o.stderr));
    let (errors, report) = check_errors(&out, "grbl-laser");
    assert!(
        errors > 0 && report.contains("contour-crossing"),
        "{report}"
    );
}

/// 10⁴ short crossing hairlines (a drawing without operations whose strokes carry a
/// colour: the default operations cut them as lines) build and check clean on a laser.
/// Guarded against a hang: the CLI runs as a child killed after 300 s.
#[test]
fn ten_thousand_crossing_lines_build_and_check_clean() {
    let dir = tmpdir("line-many");
    let mut text = String::from("version = 1\n");
    let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
    let mut next = || rng.unit();
    for i in 0..10_000 {
        let (x, y) = (5.0 + 190.0 * next(), 5.0 + 140.0 * next());
        let a = std::f64::consts::TAU * next();
        let d = DVec2::from_angle(a) * 4.0;
        text += &format!(
            "[[stroke]]\nname = \"s{i}\"\ncolor = \"#000000\"\n\
             disks = [[{:.4}, {:.4}, 0.1], [{:.4}, {:.4}, 0.1]]\n",
            x,
            y,
            x + d.x,
            y + d.y
        );
    }
    let path = dir.join("many.toml");
    std::fs::write(&path, text).unwrap();
    let out = dir.join("many.gcode");
    let script = format!(
        "timeout 300 \"{}\" build \"{}\" --machine grbl-laser -o \"{}\"",
        env!("CARGO_BIN_EXE_skinpath"),
        s(&path),
        s(&out)
    );
    let o = std::process::Command::new("sh")
        .args(["-c", &script])
        .output()
        .unwrap();
    expect_ok(&o, "build 10^4 lines");
    let cuts = runs(&std::fs::read_to_string(&out).unwrap(), true);
    assert_eq!(cuts.len(), 10_000);
    let (errors, report) = check_errors(&out, "grbl-laser");
    assert_eq!(errors, 0, "{}", &report[..report.len().min(2000)]);
}

/// A hairline of a generated drawing (random polyline with a zero-length piece and turns
/// back, smoothed into cubics) whose spine sets off backwards and turns round within
/// 0.01 mm: its line cut used to hold an arc of radius 7·10⁻⁴ mm, and the emitter refused
/// the build ("arc radius … is not positive"). It builds on a laser and a router, the
/// program holds no arc as small as the build tolerance (I/J offsets read back), and it
/// checks clean with the same profile and no flags.
#[test]
fn hairlines_turning_round_build_without_tiny_arcs() {
    const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="170mm" height="120mm" viewBox="0 0 170 120"><path id="p7" d="M 73.957,98.302 C 73.957,98.302 73.957,98.300 73.957,98.302 C 73.956,98.304 72.242,98.673 73.954,98.314 C 75.666,97.955 82.885,96.430 84.229,96.146 C 85.573,95.863 84.194,96.707 82.018,96.613 C 79.843,96.518 72.984,95.752 71.177,95.580 C 69.370,95.408 71.383,97.516 71.177,95.580 C 70.971,93.644 70.147,85.901 69.941,83.965" fill="none" stroke="#000" stroke-width="0.2"/></svg>"##;
    let dir = tmpdir("line-turn");
    let svg = dir.join("turn.svg");
    std::fs::write(&svg, SVG).unwrap();
    for machine in ["grbl-laser", "grbl-router"] {
        let out = dir.join(format!("turn.{machine}.gcode"));
        let o = build(&svg, machine, &out, &[]);
        expect_ok(&o, &format!("build turn.svg on {machine}"));
        let text = std::fs::read_to_string(&out).unwrap();
        // Radius of every arc from its I and J words (the centre offset from its start).
        let mut smallest = f64::INFINITY;
        for line in text
            .lines()
            .filter(|l| l.starts_with("G2") || l.starts_with("G3"))
        {
            let word = |c: char| {
                (line.split_whitespace())
                    .find_map(|w| w.strip_prefix(c).and_then(|v| v.parse::<f64>().ok()))
            };
            if let (Some(i), Some(j)) = (word('I'), word('J')) {
                smallest = smallest.min(i.hypot(j));
            }
        }
        assert!(smallest > 0.01, "{machine}: an arc of radius {smallest}");
        let (errors, report) = check_errors(&out, machine);
        assert_eq!(errors, 0, "{machine}: {report}");
    }
}
