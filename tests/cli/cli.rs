//! Integration tests of the `skinpath` command line: every command run as a process in a
//! temporary directory, its outputs parsed (gcode, roxmltree, dxf, serde_json) and checked
//! for numbers and structure, never for float text. Golden files under tests/golden/
//! (`SKINPATH_BLESS=1 cargo test --test cli` rewrites them).

use serde_json::Value as Json;
use skinpath::geom::DVec2;
use skinpath::geom::segments_intersect;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::support;
use support::{EXAMPLES, ROOT, example_path, skinpath, tmpdir};

/// Golden comparison tolerance for coordinates (mm or inch), per the task.
const GOLDEN_TOL: f64 = 1e-3;
/// SVG width/height (mm) against the viewBox size: half of the 0.001 mm the drawing's
/// size is written to.
const SVG_SIZE_TOL: f64 = 5e-4;

// ---------------------------------------------------------------------------------------
// helpers

fn code(o: &Output) -> i32 {
    o.status.code().unwrap_or(-1)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[track_caller]
fn expect_ok(o: &Output, what: &str) {
    assert_eq!(
        code(o),
        0,
        "{what}: exit {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        stderr(o)
    );
}

/// A machine profile read independently of the crate (toml::Value).
struct Profile {
    kind: String,
    area: [[f64; 2]; 3],
    safe_z: Option<f64>,
    rapid_off: Option<String>,
    laser_mode: Option<String>,
    decimals: i64,
    toml: toml::Value,
}

fn profile(name: &str) -> Profile {
    let text = std::fs::read_to_string(
        Path::new(ROOT)
            .join("machines")
            .join(format!("{name}.toml")),
    )
    .unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    let axis = |a: &str| {
        let r = v["work_area"][a].as_array().unwrap();
        [r[0].as_float().unwrap(), r[1].as_float().unwrap()]
    };
    Profile {
        kind: v["kind"].as_str().unwrap().to_string(),
        area: [axis("x"), axis("y"), axis("z")],
        safe_z: v.get("router").map(|r| r["safe_z"].as_float().unwrap()),
        rapid_off: v
            .get("laser")
            .and_then(|l| l.get("rapid_off"))
            .map(|x| x.as_str().unwrap().to_string()),
        laser_mode: v
            .get("laser")
            .and_then(|l| l.get("mode"))
            .map(|x| x.as_str().unwrap().to_string()),
        decimals: v
            .get("gcode")
            .and_then(|g| g.get("decimals"))
            .and_then(|d| d.as_integer())
            .unwrap_or(3),
        toml: v,
    }
}

/// G-code words of one line (letter, number), comments `( )` and `;` removed.
fn words(line: &str) -> Vec<(char, f64)> {
    let mut clean = String::new();
    let mut depth = 0;
    for c in line.chars() {
        match c {
            ';' if depth == 0 => break,
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if depth == 0 => clean.push(c),
            _ => {}
        }
    }
    let b: Vec<char> = clean.chars().filter(|c| !c.is_whitespace()).collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let l = b[i].to_ascii_uppercase();
        i += 1;
        let start = i;
        while i < b.len() && (b[i].is_ascii_digit() || b[i] == '.' || b[i] == '-' || b[i] == '+') {
            i += 1;
        }
        let num: String = b[start..i].iter().collect();
        let v: f64 = num
            .parse()
            .unwrap_or_else(|_| panic!("bad number after {l} in {line:?}"));
        out.push((l, v));
    }
    out
}

/// Numbers and letters of an SVG path `d` (commands as tokens, numbers parsed).
fn path_tokens(d: &str) -> Vec<Result<f64, char>> {
    let mut out = Vec::new();
    let mut num = String::new();
    let flush = |num: &mut String, out: &mut Vec<Result<f64, char>>| {
        if !num.is_empty() {
            out.push(Ok(num.parse::<f64>().unwrap()));
            num.clear();
        }
    };
    for c in d.chars() {
        if c.is_ascii_alphabetic() && c != 'e' && c != 'E' {
            flush(&mut num, &mut out);
            out.push(Err(c));
        } else if c == ',' || c.is_whitespace() {
            flush(&mut num, &mut out);
        } else if c == '-' && !num.is_empty() && !num.ends_with(['e', 'E']) {
            flush(&mut num, &mut out);
            num.push(c);
        } else {
            num.push(c);
        }
    }
    flush(&mut num, &mut out);
    out
}

/// "123.4mm" -> 123.4
fn mm(attr: Option<&str>) -> f64 {
    let a = attr.expect("attribute present");
    let n = a
        .strip_suffix("mm")
        .unwrap_or_else(|| panic!("{a:?} not in mm"));
    n.trim().parse().unwrap()
}

/// Width and height in mm equal the viewBox size; returns (w, h).
#[track_caller]
fn check_svg_mm(doc: &roxmltree::Document) -> (f64, f64) {
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let w = mm(root.attribute("width"));
    let h = mm(root.attribute("height"));
    let vb: Vec<f64> = root
        .attribute("viewBox")
        .unwrap()
        .split([' ', ','])
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect();
    assert_eq!(vb.len(), 4);
    assert!(w > 0.0 && h > 0.0);
    // width/height may be written rounded to 0.001 mm.
    assert!(
        (vb[2] - w).abs() <= SVG_SIZE_TOL,
        "width {w} vs viewBox {vb:?}"
    );
    assert!(
        (vb[3] - h).abs() <= SVG_SIZE_TOL,
        "height {h} vs viewBox {vb:?}"
    );
    (w, h)
}

fn points(c: &Json) -> Vec<DVec2> {
    let mut pts: Vec<DVec2> = c["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| DVec2::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    pts.dedup();
    pts
}

/// Segments of a polyline (closing segment added when closed and not repeated).
fn segments(pts: &[DVec2], closed: bool) -> Vec<(DVec2, DVec2)> {
    let mut v: Vec<(DVec2, DVec2)> = pts.windows(2).map(|w| (w[0], w[1])).collect();
    if closed && pts.len() > 2 && pts[0] != pts[pts.len() - 1] {
        v.push((pts[pts.len() - 1], pts[0]));
    }
    v
}

fn bbox_overlap(a: (DVec2, DVec2), b: (DVec2, DVec2)) -> bool {
    a.0.min(a.1).x <= b.0.max(b.1).x
        && b.0.min(b.1).x <= a.0.max(a.1).x
        && a.0.min(a.1).y <= b.0.max(b.1).y
        && b.0.min(b.1).y <= a.0.max(a.1).y
}

/// Exact self-intersection test of one polyline: pairs of non-adjacent segments that meet.
fn self_hits(segs: &[(DVec2, DVec2)], closed: bool) -> Vec<(usize, usize)> {
    let n = segs.len();
    let mut hits = Vec::new();
    for i in 0..n {
        for j in i + 2..n {
            if closed && i == 0 && j == n - 1 {
                continue; // adjacent through the closing vertex
            }
            let (a, b) = (segs[i], segs[j]);
            if bbox_overlap(a, b) && segments_intersect(a.0, a.1, b.0, b.1) {
                hits.push((i, j));
            }
        }
    }
    hits
}

fn cross_hits(a: &[(DVec2, DVec2)], b: &[(DVec2, DVec2)]) -> usize {
    let mut n = 0;
    for &x in a {
        for &y in b {
            if bbox_overlap(x, y) && segments_intersect(x.0, x.1, y.0, y.1) {
                n += 1;
            }
        }
    }
    n
}

// ---------------------------------------------------------------------------------------
// 1. README's first command

#[test]
fn readme_first_command() {
    let d = tmpdir("readme");
    let out = d.join("OUT.gcode");
    let prev = d.join("P.svg");
    let o = skinpath(&[
        "build",
        "examples/neon_word.toml",
        "--machine",
        "grbl-router",
        "-o",
        s(&out),
        "--place",
        "lower-left",
        "--margin",
        "5",
        "--preview",
        s(&prev),
    ]);
    expect_ok(&o, "README build");
    assert!(out.is_file() && prev.is_file());
    gcode::parse(&std::fs::read_to_string(&out).unwrap()).expect("program parses");
    let svg = std::fs::read_to_string(&prev).unwrap();
    roxmltree::Document::parse(&svg).expect("preview parses");
}

// ---------------------------------------------------------------------------------------
// 2. outline

fn outline_json(name: &str, dir: &Path, extra: &[&str]) -> Json {
    let out = dir.join(format!("{name}.json"));
    let ex = example_path(name);
    let mut args = vec!["outline", &ex, "-o", s(&out)];
    args.extend_from_slice(extra);
    let o = skinpath(&args);
    expect_ok(&o, &format!("outline {name} json"));
    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
}

#[test]
fn outline_every_example_svg_and_json() {
    let d = tmpdir("outline");
    for name in EXAMPLES {
        // SVG drawing in mm.
        let svg = d.join(format!("{name}.svg"));
        let o = skinpath(&["outline", &example_path(name), "-o", s(&svg)]);
        expect_ok(&o, &format!("outline {name} svg"));
        let text = std::fs::read_to_string(&svg).unwrap();
        let doc = roxmltree::Document::parse(&text).unwrap();
        check_svg_mm(&doc);
        assert!(
            doc.descendants().any(|n| n.has_tag_name("path")),
            "{name}: no path in the drawing"
        );

        // JSON contract.
        let j = outline_json(name, &d, &[]);
        assert_eq!(j["units"].as_str(), Some("mm"), "{name}");
        let design: toml::Value =
            toml::from_str(&std::fs::read_to_string(example_path(name)).unwrap()).unwrap();
        let n_circle_seqs = design
            .get("circles")
            .and_then(|c| c.as_array())
            .map_or(0, |a| a.len());
        let n_strokes = design
            .get("stroke")
            .and_then(|c| c.as_array())
            .map_or(0, |a| a.len());
        let strokes = j["strokes"].as_array().unwrap();
        assert_eq!(
            strokes.len(),
            n_strokes + n_circle_seqs,
            "{name}: stroke count"
        );
        let mut all_outlines: Vec<(String, Vec<(DVec2, DVec2)>)> = Vec::new();
        for st in strokes {
            let sname = st["name"].as_str().unwrap();
            let contours = st["contours"].as_array().unwrap();
            let is_circles = design
                .get("circles")
                .and_then(|c| c.as_array())
                .is_some_and(|a| a.iter().any(|c| c["name"].as_str() == Some(sname)));
            let roles: Vec<&str> = contours
                .iter()
                .map(|c| c["role"].as_str().unwrap())
                .collect();
            if is_circles {
                assert!(
                    roles.iter().all(|r| *r == "outline"),
                    "{name}/{sname}: {roles:?}"
                );
            } else {
                for want in ["spine", "envelope", "outline"] {
                    assert!(
                        roles.contains(&want),
                        "{name}/{sname}: no {want} in {roles:?}"
                    );
                }
            }
            assert!(roles.contains(&"outline"), "{name}/{sname}");
            for c in contours {
                assert!(c["closed"].is_boolean());
                assert!(c["points"].as_array().unwrap().len() >= 2);
                if c["role"] == "outline" {
                    assert_eq!(
                        c["closed"].as_bool(),
                        Some(true),
                        "{name}/{sname}: open outline"
                    );
                    let pts = points(c);
                    assert!(pts.iter().all(|p| p.is_finite()));
                    let segs = segments(&pts, true);
                    let hits = self_hits(&segs, true);
                    assert!(
                        hits.is_empty(),
                        "{name}/{sname}: outline crosses itself at segments {:?}",
                        &hits[..hits.len().min(5)]
                    );
                    all_outlines.push((sname.to_string(), segs));
                }
            }
        }
        // Outline contours of one stroke never meet each other (a ring's inner and outer).
        for i in 0..all_outlines.len() {
            for k in i + 1..all_outlines.len() {
                // Strokes of the 大 and the seahorse's fin overlap on purpose; the letters
                // of the neon word and the circle sequences stand apart.
                let apart = matches!(name, "neon_word" | "circles");
                if apart || all_outlines[i].0 == all_outlines[k].0 {
                    let n = cross_hits(&all_outlines[i].1, &all_outlines[k].1);
                    assert_eq!(
                        n, 0,
                        "{name}: outline contours of {} and {} meet",
                        all_outlines[i].0, all_outlines[k].0
                    );
                }
            }
        }
        let has_loop_marker = strokes.iter().any(|st| {
            st["markers"]
                .as_array()
                .is_some_and(|m| m.iter().any(|m| m["kind"] == "loop"))
        });
        if name == "loop" {
            assert!(has_loop_marker, "loop example has no loop marker");
        }
        if name == "brush" || name == "ring_o" || name == "snake" {
            assert!(!has_loop_marker, "{name} has a loop marker");
        }
    }
}

#[test]
fn outline_envelope_method_has_no_outline_role() {
    let d = tmpdir("envelope");
    for name in ["loop", "brush", "ring_o"] {
        let j = outline_json(name, &d, &["--method", "envelope"]);
        for st in j["strokes"].as_array().unwrap() {
            let roles: Vec<&str> = st["contours"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c["role"].as_str().unwrap())
                .collect();
            assert!(!roles.contains(&"outline"), "{name}: {roles:?}");
            assert!(roles.contains(&"envelope"), "{name}: {roles:?}");
        }
    }
}

#[test]
fn loop_outline_is_loop_free_where_envelope_loops() {
    // The right envelope of the hairpin crosses itself; the skin outline must not.
    let d = tmpdir("loopenv");
    let j = outline_json("loop", &d, &["--method", "envelope"]);
    let st = &j["strokes"][0];
    let mut env_hits = 0;
    for c in st["contours"].as_array().unwrap() {
        if c["role"] == "envelope" {
            let pts = points(c);
            env_hits += self_hits(&segments(&pts, false), false).len();
        }
    }
    assert!(env_hits > 0, "the hairpin's envelope should cross itself");
}

// ---------------------------------------------------------------------------------------
// 3. inspect

fn control_radii(name: &str) -> Vec<(String, Vec<f64>)> {
    let v: toml::Value =
        toml::from_str(&std::fs::read_to_string(example_path(name)).unwrap()).unwrap();
    v.get("stroke")
        .and_then(|s| s.as_array())
        .map(|a| {
            a.iter()
                .map(|st| {
                    let key = if st.get("disks").is_some() {
                        "disks"
                    } else {
                        "points"
                    };
                    let r = st[key]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|d| {
                            d[2].as_float()
                                .or(d[2].as_integer().map(|i| i as f64))
                                .unwrap()
                        })
                        .collect();
                    (st["name"].as_str().unwrap().to_string(), r)
                })
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn inspect_reports_loops_and_consistent_numbers() {
    for name in ["loop", "brush", "ring_o", "snake"] {
        let o = skinpath(&["inspect", &example_path(name), "--json"]);
        expect_ok(&o, &format!("inspect {name} --json"));
        let j: Json = serde_json::from_slice(&o.stdout).unwrap();
        let radii = control_radii(name);
        let strokes = j["strokes"].as_array().unwrap();
        assert_eq!(strokes.len(), radii.len());
        for (st, (sname, rs)) in strokes.iter().zip(&radii) {
            assert_eq!(st["name"].as_str(), Some(sname.as_str()));
            let len = st["spine_length"].as_f64().unwrap();
            assert!(len > 0.0, "{name}: spine length {len}");
            let rr = st["radius_range"].as_array().unwrap();
            let (lo, hi) = (rr[0].as_f64().unwrap(), rr[1].as_f64().unwrap());
            let cmin = rs.iter().cloned().fold(f64::INFINITY, f64::min);
            let cmax = rs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            // A B-spline radius stays in the convex hull of its control radii (for points
            // given as interpolation targets the hull may be wider: only check disks).
            assert!(lo > 0.0 && lo <= hi, "{name}: {lo}..{hi}");
            if name != "snake" {
                assert!(
                    lo >= cmin - 1e-9 && hi <= cmax + 1e-9,
                    "{name}: radius {lo}..{hi} outside control {cmin}..{cmax}"
                );
            }
            assert_eq!(st["disks"].as_u64().unwrap() as usize, rs.len(), "{name}");
            let loops = st["loops"].as_array().unwrap();
            match name {
                "loop" => {
                    assert_eq!(loops.len(), 1, "{name}: {loops:?}");
                    assert_eq!(loops[0]["side"].as_str(), Some("right"));
                    let t = loops[0]["t"].as_array().unwrap();
                    let (t0, t1) = (t[0].as_f64().unwrap(), t[1].as_f64().unwrap());
                    assert!(0.0 < t0 && t0 < t1 && t1 < 1.0, "{t0}..{t1}");
                    // The hairpin is symmetric about its apex at t = 0.5.
                    assert!((t0 + t1 - 1.0).abs() < 1e-6, "{t0}..{t1} not symmetric");
                }
                _ => assert!(loops.is_empty(), "{name}: loops {loops:?}"),
            }
        }
        // Text form says the same.
        let o = skinpath(&["inspect", &example_path(name)]);
        expect_ok(&o, &format!("inspect {name}"));
        let text = String::from_utf8_lossy(&o.stdout);
        let loop_lines = text
            .lines()
            .filter(|l| l.trim_start().starts_with("envelope loop:"))
            .count();
        assert_eq!(loop_lines, usize::from(name == "loop"), "{name}:\n{text}");
        if name == "loop" {
            assert!(text.contains("Right") || text.contains("right"), "{text}");
        }
    }
}

// ---------------------------------------------------------------------------------------
// 4. build G-code for every G-code profile

/// The points of an arc (start `s`, end `e`, clockwise for G2) where it reaches its
/// extreme X or Y: the quarter-circle points inside its sweep. Centre from I/J offsets
/// or, with R, on the side of the chord given by the direction and the sign of R.
fn arc_extremes(s: [f64; 3], e: [f64; 3], cw: bool, ij: [f64; 2], r: Option<f64>) -> Vec<[f64; 2]> {
    use std::f64::consts::{PI, TAU};
    let (sx, sy, ex, ey) = (s[0], s[1], e[0], e[1]);
    let (cx, cy) = match r {
        Some(r) => {
            let (dx, dy) = (ex - sx, ey - sy);
            let d = dx.hypot(dy);
            if d == 0.0 {
                return Vec::new();
            }
            let h = (r * r - d * d / 4.0).max(0.0).sqrt();
            // Left normal of the chord; the centre is left for CCW with R > 0.
            let sign = if cw { -1.0 } else { 1.0 } * r.signum();
            (
                (sx + ex) / 2.0 - sign * h * dy / d,
                (sy + ey) / 2.0 + sign * h * dx / d,
            )
        }
        None => (sx + ij[0], sy + ij[1]),
    };
    let rad = (sx - cx).hypot(sy - cy);
    let a0 = (sy - cy).atan2(sx - cx);
    let a1 = (ey - cy).atan2(ex - cx);
    let mut sweep = if cw {
        (a0 - a1).rem_euclid(TAU)
    } else {
        (a1 - a0).rem_euclid(TAU)
    };
    if sweep == 0.0 {
        sweep = TAU;
    }
    let mut out = Vec::new();
    for k in 0..4 {
        let th = k as f64 * PI / 2.0;
        let along = if cw {
            (a0 - th).rem_euclid(TAU)
        } else {
            (th - a0).rem_euclid(TAU)
        };
        if along <= sweep {
            out.push([cx + rad * th.cos(), cy + rad * th.sin()]);
        }
    }
    out
}

#[test]
fn arc_extremes_of_known_arcs() {
    // CCW half circle from (1,0) to (-1,0) about the origin passes (0,1) only (plus ends).
    let e = arc_extremes([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], false, [-1.0, 0.0], None);
    assert!(
        e.iter()
            .any(|p| (p[0]).abs() < 1e-12 && (p[1] - 1.0).abs() < 1e-12)
    );
    assert!(!e.iter().any(|p| (p[1] + 1.0).abs() < 1e-12));
    // The same chord clockwise passes (0,-1).
    let e = arc_extremes([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], true, [-1.0, 0.0], None);
    assert!(e.iter().any(|p| (p[1] + 1.0).abs() < 1e-12));
    // R format: quarter arc (1,0) -> (0,1), CCW, R 1: centre at the origin, no bulge past
    // the ends; with R -1 the long way round about (1,1), through (2,1) and (1,2).
    let e = arc_extremes([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], false, [0.0; 2], Some(1.0));
    assert!(
        e.iter()
            .all(|p| p[0] >= -1e-9 && p[1] >= -1e-9 && p[0].hypot(p[1]) <= 1.0 + 1e-9),
        "{e:?}"
    );
    let e = arc_extremes(
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        false,
        [0.0; 2],
        Some(-1.0),
    );
    for want in [[2.0, 1.0], [1.0, 2.0]] {
        assert!(
            e.iter()
                .any(|p| (p[0] - want[0]).abs() < 1e-9 && (p[1] - want[1]).abs() < 1e-9),
            "{e:?}"
        );
    }
    // Clockwise with R 1 from (1,0) to (0,1): centre (1,1) short way, through no extreme
    // beyond the square [0,1]^2.
    let e = arc_extremes([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], true, [0.0; 2], Some(1.0));
    assert!(
        e.iter().all(|p| p[0] <= 1.0 + 1e-9 && p[1] <= 1.0 + 1e-9),
        "{e:?}"
    );
}

struct Sim {
    violations: Vec<String>,
    /// Smallest X and Y reached, arcs' bulges included.
    min_xy: [f64; 2],
    /// Smallest X and Y of the move end points.
    min_end: [f64; 2],
    moves: usize,
    cut_moves: usize,
}

/// Replays a program: tool state (M3/M4/M5), modal motion, position; checks laser-off
/// rapids (profiles that turn the beam off with M5), router rapids above safe_z, the work
/// area and the tool off at the end.
fn replay(text: &str, p: &Profile) -> Sim {
    let mut v = Vec::new();
    let mut on = false;
    let mut mode = 0u32;
    let mut pos = [f64::NAN; 3];
    let mut ended_off = None;
    let (mut moves, mut cut_moves) = (0, 0);
    let mut min_xy = [f64::INFINITY; 2];
    let mut min_end = [f64::INFINITY; 2];
    let eps = 1e-6;
    for (ln, line) in text.lines().enumerate() {
        let ln = ln + 1;
        let w = words(line);
        let mut dwell = false;
        let mut new = pos;
        let mut has_axis = false;
        let mut has_xy = false;
        let (mut ij, mut rword) = ([0.0f64; 2], None);
        for &(l, x) in &w {
            match l {
                'G' => match x as u32 {
                    0..=3 if x.fract() == 0.0 => mode = x as u32,
                    4 => dwell = true,
                    _ => {}
                },
                'M' => match x as u32 {
                    3 | 4 => {
                        on = true;
                        if let Some(m) = &p.laser_mode {
                            let want = if m == "dynamic" { 4 } else { 3 };
                            if x as u32 != want {
                                v.push(format!("line {ln}: M{x} for {m} laser mode"));
                            }
                        }
                    }
                    5 => on = false,
                    2 | 30 => ended_off = Some(!on),
                    _ => {}
                },
                'X' => {
                    new[0] = x;
                    has_axis = true;
                    has_xy = true;
                }
                'Y' => {
                    new[1] = x;
                    has_axis = true;
                    has_xy = true;
                }
                'Z' => {
                    new[2] = x;
                    has_axis = true;
                }
                'I' => ij[0] = x,
                'J' => ij[1] = x,
                'R' => rword = Some(x),
                _ => {}
            }
        }
        if dwell || !has_axis {
            continue;
        }
        moves += 1;
        // An XY rapid from an unknown position counts as moving.
        let xy_moves = has_xy && !(new[0] == pos[0] && new[1] == pos[1]);
        if mode == 0 {
            if on && p.rapid_off.as_deref() == Some("m5") {
                v.push(format!("line {ln}: G0 with the laser on"));
            }
            if let Some(sz) = p.safe_z {
                // Both the start and the end height of an XY rapid must be safe.
                let z = pos[2].min(new[2]);
                if xy_moves && (z.is_nan() || z < sz - eps) {
                    v.push(format!("line {ln}: G0 XY at z {z} below safe_z {sz}"));
                }
            }
        } else {
            cut_moves += 1;
            if p.kind == "laser"
                && !on
                && p.toml["laser"]
                    .get("needs_on_command")
                    .and_then(|b| b.as_bool())
                    != Some(false)
            {
                v.push(format!("line {ln}: G{mode} cut with the laser off"));
            }
        }
        for (a, &c) in new.iter().enumerate() {
            if c.is_finite() && !(c >= p.area[a][0] - eps && c <= p.area[a][1] + eps) {
                v.push(format!(
                    "line {ln}: axis {a} at {c} outside {:?}",
                    p.area[a]
                ));
            }
        }
        if (mode == 2 || mode == 3) && pos[0].is_finite() && pos[1].is_finite() {
            for q in arc_extremes(pos, new, mode == 2, ij, rword) {
                min_xy = [min_xy[0].min(q[0]), min_xy[1].min(q[1])];
                for (a, (&c, range)) in q.iter().zip(&p.area).enumerate() {
                    // The centre is rebuilt from rounded words: allow the rounding.
                    let slack = eps + 2.0 * 10f64.powi(-(p.decimals as i32));
                    if !(c >= range[0] - slack && c <= range[1] + slack) {
                        v.push(format!(
                            "line {ln}: arc reaches axis {a} at {c} outside {range:?}"
                        ));
                    }
                }
            }
        }
        min_xy = [min_xy[0].min(new[0]), min_xy[1].min(new[1])];
        min_end = [min_end[0].min(new[0]), min_end[1].min(new[1])];
        pos = new;
    }
    match ended_off {
        Some(true) => {}
        Some(false) => v.push("program ends (M2/M30) with the tool on".into()),
        None if on => v.push("program ends with the tool on".into()),
        None => {}
    }
    Sim {
        violations: v,
        min_xy,
        min_end,
        moves,
        cut_moves,
    }
}

fn build(name: &str, machine: &str, out: &Path) -> Output {
    skinpath(&[
        "build",
        &example_path(name),
        "--machine",
        machine,
        "-o",
        s(out),
        "--place",
        "lower-left",
        "--margin",
        "5",
    ])
}

fn build_and_verify(machine: &str, names: &[&str]) {
    let d = tmpdir(machine);
    let p = profile(machine);
    for name in names {
        let out = d.join(format!("{name}.gcode"));
        let o = build(name, machine, &out);
        expect_ok(&o, &format!("build {name} on {machine}"));
        let text = std::fs::read_to_string(&out).unwrap();
        if let Err(e) = gcode::parse(&text) {
            panic!("{name} on {machine}: gcode crate rejects the program: {e:?}");
        }
        let sim = replay(&text, &p);
        assert!(
            sim.cut_moves > 0 && sim.moves > sim.cut_moves / 2,
            "{name} on {machine}"
        );
        assert!(
            sim.violations.is_empty(),
            "{name} on {machine}: {:?}",
            &sim.violations[..sim.violations.len().min(8)]
        );
        // build = check: what build wrote passes `check --machine` with no other flag
        // (pockets that cross on purpose are marked in the program).
        let c = skinpath(&["check", s(&out), "--machine", machine]);
        expect_ok(&c, &format!("check {name} on {machine}"));
        // Placed at the lower-left corner plus the margin (profile units; margin in mm):
        // the end points reach it (arcs may bulge further: see place_lower_left_with_arcs).
        let k = if p.toml["units"].as_str() == Some("inch") {
            1.0 / 25.4
        } else {
            1.0
        };
        let q = 2.0 * 10f64.powi(-(p.decimals as i32));
        for a in 0..2 {
            let want = p.area[a][0] + 5.0 * k;
            assert!(
                sim.min_end[a] >= want - q && sim.min_end[a] <= want + 2.0 * k,
                "{name} on {machine}: axis {a} end points reach {}, placed at {want}",
                sim.min_end[a]
            );
        }
    }
}

#[test]
fn build_grbl_laser() {
    build_and_verify("grbl-laser", &["brush", "loop", "ring_o", "circles"]);
}

#[test]
fn build_grbl_router() {
    build_and_verify("grbl-router", &["loop", "ring_o"]);
}

#[test]
fn build_grbl_router_gouge_margin() {
    build_and_verify("grbl-router", &["circles", "snake"]);
}

#[test]
fn build_self_crossing_and_neon_designs() {
    // gclef crosses itself (outlined by a union); neon_word has channels, holes, a backboard.
    build_and_verify("grbl-router", &["neon_word"]);
    build_and_verify("grbl-laser", &["gclef", "neon_word"]);
}

#[test]
fn place_lower_left_with_arcs() {
    // --margin 0: the tool's lowest X and Y, arcs included, sit on the corner: inside the
    // work area, and no further in than the placement's inset of two units of the last
    // decimal plus the √2 units that rounding can move an arc's extreme.
    let d = tmpdir("place0");
    for (name, machine) in [("loop", "grbl-router"), ("brush", "grbl-laser")] {
        let out = d.join(format!("{name}.gcode"));
        let o = skinpath(&[
            "build",
            &example_path(name),
            "--machine",
            machine,
            "-o",
            s(&out),
            "--place",
            "lower-left",
            "--margin",
            "0",
        ]);
        expect_ok(&o, &format!("{name} on {machine} at margin 0"));
        let p = profile(machine);
        let sim = replay(&std::fs::read_to_string(&out).unwrap(), &p);
        let q = 4.0 * 10f64.powi(-(p.decimals as i32));
        for a in 0..2 {
            let inside = sim.min_xy[a] - p.area[a][0];
            assert!(
                (0.0..=q).contains(&inside),
                "{name}: axis {a} {}",
                sim.min_xy[a]
            );
        }
    }
}

#[test]
fn build_marlin_laser() {
    build_and_verify("marlin-laser", &["brush", "loop", "ring_o"]);
}

#[test]
fn build_linuxcnc_router() {
    build_and_verify("linuxcnc-router", &["loop", "ring_o", "circles"]);
}

#[test]
fn build_smoothie_laser() {
    build_and_verify("smoothie-laser", &["brush", "ring_o", "circles"]);
}

#[test]
fn build_too_big_for_the_machine_fails_cleanly() {
    let d = tmpdir("toobig");
    // snake is 265 mm long, marlin's bed 220 mm (X); seahorse 190 mm tall, grbl-router 180
    // mm deep (Y).
    for (name, machine, area) in [
        ("snake", "marlin-laser", "220.0 x 220.0 mm"),
        ("seahorse", "grbl-router", "300.0 x 180.0 mm"),
    ] {
        let out = d.join(format!("{name}.gcode"));
        let o = build(name, machine, &out);
        assert_eq!(code(&o), 2, "{name} on {machine}: {}", stderr(&o));
        let e = stderr(&o);
        // The job's size, the area's size and the option that fixes it.
        assert!(e.contains("the job is"), "{e}");
        assert!(e.contains("work area") && e.contains(area), "{e}");
        assert!(e.contains("--fit"), "{e}");
        assert!(!out.exists(), "{name} on {machine}: output written");
        let leftovers: Vec<_> = std::fs::read_dir(&d).unwrap().collect();
        assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    }
}

#[test]
fn router_design_without_depth_is_refused() {
    let d = tmpdir("depth");
    let out = d.join("b.gcode");
    let o = build("brush", "grbl-router", &out);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("brush.toml") && stderr(&o).contains("depth"));
    assert!(!out.exists());
}

// ---------------------------------------------------------------------------------------
// 5. golden files

fn golden_dir() -> PathBuf {
    Path::new(ROOT).join("tests").join("golden")
}

fn bless() -> bool {
    std::env::var("SKINPATH_BLESS").is_ok_and(|v| v == "1")
}

fn compare_gcode(got: &str, want: &str, what: &str) {
    let g: Vec<Vec<(char, f64)>> = got.lines().map(words).filter(|w| !w.is_empty()).collect();
    let w: Vec<Vec<(char, f64)>> = want.lines().map(words).filter(|w| !w.is_empty()).collect();
    assert_eq!(
        g.len(),
        w.len(),
        "{what}: {} blocks, golden {}",
        g.len(),
        w.len()
    );
    for (i, (a, b)) in g.iter().zip(&w).enumerate() {
        let la: String = a.iter().map(|x| x.0).collect();
        let lb: String = b.iter().map(|x| x.0).collect();
        assert_eq!(la, lb, "{what}: block {i}: letters differ");
        for (x, y) in a.iter().zip(b) {
            assert!(
                (x.1 - y.1).abs() <= GOLDEN_TOL,
                "{what}: block {i}: {}{} vs golden {}{}",
                x.0,
                x.1,
                y.0,
                y.1
            );
        }
    }
}

fn svg_paths(text: &str) -> Vec<(String, Vec<Result<f64, char>>)> {
    let doc = roxmltree::Document::parse(text).unwrap();
    doc.descendants()
        .filter(|n| n.has_tag_name("path"))
        .map(|n| {
            (
                n.attribute("stroke").unwrap_or("").to_string(),
                path_tokens(n.attribute("d").unwrap_or("")),
            )
        })
        .collect()
}

fn compare_svg(got: &str, want: &str, what: &str) {
    let g = svg_paths(got);
    let w = svg_paths(want);
    assert_eq!(g.len(), w.len(), "{what}: path count");
    for (i, (a, b)) in g.iter().zip(&w).enumerate() {
        assert_eq!(a.0, b.0, "{what}: path {i} stroke");
        assert_eq!(a.1.len(), b.1.len(), "{what}: path {i} token count");
        for (x, y) in a.1.iter().zip(&b.1) {
            match (x, y) {
                (Ok(x), Ok(y)) => {
                    assert!(
                        (x - y).abs() <= GOLDEN_TOL,
                        "{what}: path {i}: {x} vs golden {y}"
                    )
                }
                _ => assert_eq!(x, y, "{what}: path {i}: commands differ"),
            }
        }
    }
    let dg = roxmltree::Document::parse(got).unwrap();
    let dw = roxmltree::Document::parse(want).unwrap();
    let (a, b) = (check_svg_mm(&dg), check_svg_mm(&dw));
    assert!(
        (a.0 - b.0).abs() <= GOLDEN_TOL && (a.1 - b.1).abs() <= GOLDEN_TOL,
        "{what}: size"
    );
}

fn golden(name: &str, machine: &str, ext: &str) {
    let d = tmpdir("golden");
    let out = d.join(format!("{name}.{ext}"));
    let o = build(name, machine, &out);
    expect_ok(&o, &format!("build {name} on {machine}"));
    let got = std::fs::read_to_string(&out).unwrap();
    let gpath = golden_dir().join(format!("{name}.{machine}.{ext}"));
    if bless() {
        std::fs::create_dir_all(golden_dir()).unwrap();
        std::fs::write(&gpath, &got).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&gpath)
        .unwrap_or_else(|_| panic!("{} missing: run with SKINPATH_BLESS=1", gpath.display()));
    let what = format!("{name} on {machine}");
    if ext == "svg" {
        compare_svg(&got, &want, &what);
    } else {
        compare_gcode(&got, &want, &what);
    }
}

#[test]
fn golden_neon_word_grbl_router() {
    golden("neon_word", "grbl-router", "gcode");
}

#[test]
fn golden_ring_o_grbl_router() {
    golden("ring_o", "grbl-router", "gcode");
}

#[test]
fn golden_brush_grbl_laser() {
    golden("brush", "grbl-laser", "gcode");
}

#[test]
fn golden_ring_o_svg_laser() {
    golden("ring_o", "svg-laser", "svg");
}

#[test]
fn golden_loop_marlin_laser() {
    golden("loop", "marlin-laser", "gcode");
}

#[test]
fn golden_ring_o_linuxcnc_router() {
    golden("ring_o", "linuxcnc-router", "gcode");
}

#[test]
fn golden_circles_smoothie_laser() {
    golden("circles", "smoothie-laser", "gcode");
}

#[test]
fn golden_brush_svg_laser_lightburn() {
    golden("brush", "svg-laser-lightburn", "svg");
}

#[test]
fn golden_comparison_detects_a_change() {
    // The comparators must fail on a coordinate moved by more than the tolerance and pass
    // within it.
    let a = "G0 X1.000 Y2.000\nG1 X3 Y4 F100\n";
    let within = "G0 X1.0004 Y2\nG1 X3 Y4 F100\n";
    let beyond = "G0 X1.002 Y2\nG1 X3 Y4 F100\n";
    compare_gcode(within, a, "within");
    assert!(std::panic::catch_unwind(|| compare_gcode(beyond, a, "beyond")).is_err());
    let t = path_tokens("M 1 2 L3,-4e-1 A 5 5 0 0 1 -6.5-7");
    assert_eq!(
        t,
        vec![
            Err('M'),
            Ok(1.0),
            Ok(2.0),
            Err('L'),
            Ok(3.0),
            Ok(-0.4),
            Err('A'),
            Ok(5.0),
            Ok(5.0),
            Ok(0.0),
            Ok(0.0),
            Ok(1.0),
            Ok(-6.5),
            Ok(-7.0)
        ]
    );
}

// ---------------------------------------------------------------------------------------
// 6. laser SVG and DXF

fn svg_colours(machine: &str, name: &str) {
    let d = tmpdir("svgcol");
    let p = profile(machine);
    let colours = p.toml["svg"]["colors"].as_table().unwrap();
    let width = p.toml["svg"]["stroke_width"].as_float().unwrap();
    let out = d.join(format!("{name}.svg"));
    let o = build(name, machine, &out);
    expect_ok(&o, &format!("build {name} on {machine}"));
    let text = std::fs::read_to_string(&out).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let (w, h) = check_svg_mm(&doc);
    assert!(w <= p.area[0][1] - p.area[0][0] + 1e-9 && h <= p.area[1][1] - p.area[1][0] + 1e-9);
    let mut groups = 0;
    for g in doc.descendants().filter(|n| n.has_tag_name("g")) {
        let Some(kind) = g.attribute("data-kind") else {
            continue;
        };
        groups += 1;
        let want = colours[&kind.to_lowercase()].as_str().unwrap();
        assert_eq!(
            g.attribute("stroke"),
            Some(want),
            "{name} on {machine}: {kind}"
        );
        let sw: f64 = g.attribute("stroke-width").unwrap().parse().unwrap();
        assert!((sw - width).abs() < 1e-12, "{sw} vs {width}");
        let paths: Vec<_> = g.descendants().filter(|n| n.has_tag_name("path")).collect();
        assert!(!paths.is_empty());
        for path in paths {
            if let Some(c) = path.attribute("stroke") {
                assert_eq!(c, want);
            }
            for x in path_tokens(path.attribute("d").unwrap())
                .into_iter()
                .flatten()
            {
                assert!(x.is_finite());
            }
        }
    }
    let design: toml::Value =
        toml::from_str(&std::fs::read_to_string(example_path(name)).unwrap()).unwrap();
    let n_ops = design
        .get("operation")
        .and_then(|o| o.as_array())
        .map_or(1, |a| a.len());
    assert_eq!(
        groups, n_ops,
        "{name} on {machine}: one group per operation"
    );
}

#[test]
fn laser_svg_colours_from_profile() {
    for machine in ["svg-laser", "svg-laser-lightburn"] {
        for name in ["brush", "ring_o"] {
            svg_colours(machine, name);
        }
    }
}

#[test]
fn dxf_output_mm_and_closed() {
    let d = tmpdir("dxf");
    let out = d.join("ring.dxf");
    let o = build("ring_o", "svg-laser", &out);
    expect_ok(&o, "build ring_o dxf");
    let text = std::fs::read_to_string(&out).expect("dxf written");
    let drawing = support::dxf::load(&text);
    assert_eq!(drawing.insunits, Some(4), "millimetres");
    let total = drawing.polylines.len();
    let closed = drawing.polylines.iter().filter(|p| p.1).count();
    assert!(drawing.polylines.iter().all(|p| p.2.len() >= 3));
    // A ring cut outside: two closed contours (outer and inner boundary).
    assert_eq!(total, 2, "polylines");
    assert_eq!(closed, 2, "closed polylines");
}

// ---------------------------------------------------------------------------------------
// 7. errors

const GOOD_STROKE: &str = "version = 1\nunits = \"mm\"\n\n[[stroke]]\nname = \"s1\"\ndegree = 3\n\
    disks = [[0.0, 0.0, 2.0], [10.0, 5.0, 3.0], [20.0, 0.0, 2.0], [30.0, 4.0, 1.5]]\n\n\
    [[stroke]]\nname = \"bad\"\ndegree = 3\n";

#[test]
fn design_errors_name_file_stroke_and_index() {
    let d = tmpdir("errors");
    let cases: [(&str, &str, &[&str]); 4] = [
        (
            "neg",
            "disks = [[0.0, 0.0, 2.0], [10.0, 5.0, 3.0], [20.0, 0.0, -2.0], [30.0, 4.0, 1.5]]\n",
            &["stroke 1", "\"bad\"", "disk 2", "radius"],
        ),
        (
            "unknown",
            "disks = [[0.0, 0.0, 2.0], [10.0, 5.0, 3.0], [20.0, 0.0, 2.0], [30.0, 4.0, 1.5]]\n\
             colour = \"red\"\n",
            &["unknown.toml:13:1", "colour"],
        ),
        (
            "knots",
            "disks = [[0.0, 0.0, 2.0], [10.0, 5.0, 3.0], [20.0, 0.0, 2.0], [30.0, 4.0, 1.5]]\n\
             knots = [0, 0, 0, 1, 1, 1]\n",
            &["stroke 1", "\"bad\"", "knots", "6", "8"],
        ),
        (
            "few",
            "disks = [[0.0, 0.0, 2.0]]\n",
            &["stroke 1", "\"bad\"", "at least 2 disks, got 1"],
        ),
    ];
    for (tag, tail, needles) in cases {
        let design = d.join(format!("{tag}.toml"));
        std::fs::write(&design, format!("{GOOD_STROKE}{tail}")).unwrap();
        for (cmd, out) in [
            ("build", d.join(format!("{tag}.gcode"))),
            ("outline", d.join(format!("{tag}.svg"))),
        ] {
            let o = if cmd == "build" {
                skinpath(&[
                    "build",
                    s(&design),
                    "--machine",
                    "grbl-laser",
                    "-o",
                    s(&out),
                ])
            } else {
                skinpath(&["outline", s(&design), "-o", s(&out)])
            };
            assert_eq!(code(&o), 2, "{tag} {cmd}: {}", stderr(&o));
            let e = stderr(&o);
            assert!(
                e.contains(&format!("{tag}.toml")),
                "{tag} {cmd}: file not named: {e}"
            );
            for n in needles {
                assert!(e.contains(n), "{tag} {cmd}: {n:?} missing in {e}");
            }
            assert!(!out.exists(), "{tag} {cmd}: output written");
        }
        let o = skinpath(&["inspect", s(&design)]);
        assert_eq!(code(&o), 2, "{tag} inspect");
    }
}

#[test]
fn output_equal_to_input_is_refused() {
    let d = tmpdir("samefile");
    let design = d.join("ring.toml");
    std::fs::copy(example_path("ring_o"), &design).unwrap();
    let before = std::fs::read(&design).unwrap();
    // Same file through a different spelling of the path.
    let alias = d.join(".").join("ring.toml");
    for args in [
        vec!["outline", s(&design), "-o", s(&alias), "--format"],
        vec![
            "build",
            s(&design),
            "--machine",
            "grbl-laser",
            "-o",
            s(&alias),
            "--format",
            "gcode",
        ],
        vec![
            "build",
            s(&design),
            "--machine",
            "grbl-laser",
            "-o",
            "x.gcode",
            "--preview",
            s(&design),
        ],
    ] {
        // outline has no --format: drop it (the .toml extension is then refused anyway).
        let args: Vec<&str> = if args[0] == "outline" {
            args[..4].to_vec()
        } else {
            args
        };
        let o = skinpath(&args);
        assert_eq!(code(&o), 2, "{args:?}");
        assert_eq!(
            std::fs::read(&design).unwrap(),
            before,
            "{args:?}: input changed"
        );
    }
    assert!(!Path::new(ROOT).join("x.gcode").exists());
    // A JSON design named like the output format.
    let jdesign = d.join("ring.json");
    let o = skinpath(&["outline", &example_path("ring_o"), "-o", s(&jdesign)]);
    expect_ok(&o, "outline json");
    let jbefore = std::fs::read(&jdesign).unwrap();
    let o = skinpath(&["outline", s(&jdesign), "-o", s(&jdesign)]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("input"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&jdesign).unwrap(), jbefore);
}

#[test]
fn failing_runs_leave_no_file_and_keep_old_outputs() {
    let d = tmpdir("nofile");
    let out = d.join("x.gcode");
    let o = skinpath(&[
        "build",
        &example_path("ring_o"),
        "--machine",
        "no-such-machine",
        "-o",
        s(&out),
    ]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("no-such-machine"));
    assert!(!out.exists());
    // A pre-existing output stays byte for byte when the run fails.
    let old = b"G0 X0 Y0\n(old program)\n".to_vec();
    std::fs::write(&out, &old).unwrap();
    let bad = d.join("bad.toml");
    std::fs::write(&bad, format!("{GOOD_STROKE}disks = [[0.0, 0.0, 2.0]]\n")).unwrap();
    let o = skinpath(&["build", s(&bad), "--machine", "grbl-laser", "-o", s(&out)]);
    assert_eq!(code(&o), 2);
    assert_eq!(std::fs::read(&out).unwrap(), old);
    let o = skinpath(&[
        "build",
        &example_path("snake"),
        "--machine",
        "marlin-laser",
        "-o",
        s(&out),
        "--place",
        "lower-left",
    ]);
    assert_eq!(code(&o), 2);
    assert_eq!(std::fs::read(&out).unwrap(), old);
    let names: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(
        sorted,
        vec!["bad.toml", "x.gcode"],
        "stray files: {names:?}"
    );
}

// ---------------------------------------------------------------------------------------
// 8. check and machines

#[test]
fn check_clean_crossing_and_garbage() {
    let d = tmpdir("check");
    let clean = d.join("clean.gcode");
    std::fs::write(
        &clean,
        "G21 G90\nG0 X0 Y0\nM3 S100\nG1 X10 Y0 F1000\nG1 X10 Y10\nG1 X0 Y10\nG1 X0 Y0\nM5\nM2\n",
    )
    .unwrap();
    let o = skinpath(&["check", s(&clean)]);
    expect_ok(&o, "check clean");
    let o = skinpath(&["check", s(&clean), "--json"]);
    expect_ok(&o, "check clean --json");
    let j: Json = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["findings"].as_array().unwrap().len(), 0);
    assert!((j["stats"]["cut_length"].as_f64().unwrap() - 40.0).abs() < 1e-9);

    // A bow tie: the segment of line 5 crosses the one of line 7 at (5, 5).
    let cross = d.join("cross.gcode");
    std::fs::write(
        &cross,
        "G21 G90\n(bow tie)\nG0 X0 Y0\nM3 S100\nG1 X10 Y10 F1000\nG1 X10 Y0\nG1 X0 Y10\nG1 X0 Y0\nM5\nM2\n",
    )
    .unwrap();
    let o = skinpath(&["check", s(&cross)]);
    assert_eq!(code(&o), 1);
    let o = skinpath(&["check", s(&cross), "--json"]);
    assert_eq!(code(&o), 1);
    let j: Json = serde_json::from_slice(&o.stdout).unwrap();
    let f: Vec<&Json> = j["findings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["id"] == "self-intersection")
        .collect();
    assert_eq!(f.len(), 1, "{j}");
    let mut lines: Vec<u64> = f[0]["lines"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_u64().unwrap())
        .collect();
    lines.sort();
    assert_eq!(lines, vec![5, 7]);
    let at = &f[0]["at"][0];
    assert!(
        (at[0].as_f64().unwrap() - 5.0).abs() < 1e-9
            && (at[1].as_f64().unwrap() - 5.0).abs() < 1e-9
    );

    // Binary and garbage input: unusable.
    let bin = d.join("bin.gcode");
    std::fs::write(&bin, [0u8, 159, 146, 150, 0xff, 0xfe, 1, 2, 3]).unwrap();
    let o = skinpath(&["check", s(&bin)]);
    assert_eq!(code(&o), 2, "binary: {}", stderr(&o));
    let junk = d.join("junk.gcode");
    std::fs::write(&junk, "this is not gcode at all $$$ !!\n").unwrap();
    let o = skinpath(&["check", s(&junk)]);
    assert_eq!(code(&o), 2, "junk");
    let o = skinpath(&["check", s(&d.join("missing.gcode"))]);
    assert_eq!(code(&o), 2, "missing file");
}

#[test]
fn machines_lists_all_profiles() {
    let o = skinpath(&["machines"]);
    expect_ok(&o, "machines");
    let text = String::from_utf8_lossy(&o.stdout);
    let mut shipped: Vec<String> = std::fs::read_dir(Path::new(ROOT).join("machines"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    shipped.sort();
    assert_eq!(shipped.len(), 7);
    let listed: Vec<&str> = text
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .filter(|w| shipped.iter().any(|s| s == w))
        .collect();
    let mut l2: Vec<String> = listed.iter().map(|s| s.to_string()).collect();
    l2.sort();
    assert_eq!(l2, shipped);
    for name in &shipped {
        let kind = profile(name).kind;
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap();
        assert_eq!(
            line.split_whitespace().nth(1),
            Some(kind.as_str()),
            "{line}"
        );
    }
}

#[test]
fn replay_flags_planted_faults() {
    // The G-code replay must catch each fault it checks for.
    let marlin = profile("marlin-laser");
    let ok = "G21 G90\nG0 X10 Y10\nM3 I1 S100\nG1 X20 Y10 F600\nM5\nG0 X30 Y30\nM5\n";
    assert!(
        replay(ok, &marlin).violations.is_empty(),
        "{:?}",
        replay(ok, &marlin).violations
    );
    let rapid_on = "G21 G90\nG0 X10 Y10\nM3 I1 S100\nG1 X20 Y10 F600\nG0 X30 Y30\nM5\n";
    let v = replay(rapid_on, &marlin).violations;
    assert!(
        v.iter()
            .any(|m| m.contains("line 5") && m.contains("laser on")),
        "{v:?}"
    );
    let left_on = "G21 G90\nG0 X10 Y10\nM3 I1 S100\nG1 X20 Y10 F600\n";
    assert!(
        replay(left_on, &marlin)
            .violations
            .iter()
            .any(|m| m.contains("tool on"))
    );
    let outside = "G21 G90\nG0 X10 Y10\nM3 I1 S100\nG1 X230 Y10 F600\nM5\n";
    assert!(
        replay(outside, &marlin)
            .violations
            .iter()
            .any(|m| m.contains("line 4"))
    );
    // An arc whose end points are inside but whose bulge leaves the bed (x < 0).
    let bulge = "G21 G90\nG0 X1 Y10\nM3 I1 S100\nG2 X1 Y20 I4 J5 F600\nM5\n";
    let v = replay(bulge, &marlin).violations;
    assert!(v.iter().any(|m| m.contains("arc reaches axis 0")), "{v:?}");
    let grbl_laser = profile("grbl-laser");
    let m3 = "G21 G90\nG0 X10 Y10\nM3 S100\nG1 X20 Y10 F600\nM5\nM2\n";
    assert!(
        replay(m3, &grbl_laser)
            .violations
            .iter()
            .any(|m| m.contains("dynamic"))
    );
    let router = profile("grbl-router");
    let low = "G21 G90\nG0 Z5\nX10 Y10\nM3 S12000\nG1 Z-1 F200\nG1 X20\nG0 X40\nG0 Z5\nM5\nM30\n";
    let v = replay(low, &router).violations;
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(v[0].contains("line 7") && v[0].contains("safe_z"), "{v:?}");
    let ends_on = "G21 G90\nG0 Z5\nX10 Y10\nM3 S12000\nG1 Z-1 F200\nG0 Z5\nM30\n";
    assert!(
        replay(ends_on, &router)
            .violations
            .iter()
            .any(|m| m.contains("M2/M30"))
    );
}

#[test]
fn every_example_is_listed() {
    let mut names: Vec<String> = std::fs::read_dir(Path::new(ROOT).join("examples"))
        .unwrap()
        .filter_map(|e| {
            let p = e.ok()?.path();
            (p.extension()? == "toml").then(|| p.file_stem()?.to_str().map(String::from))?
        })
        .collect();
    names.sort();
    assert_eq!(names, EXAMPLES.to_vec());
}

#[test]
fn build_without_output_writes_the_design_name_here() {
    // No -o: the design's name in the current folder, .gcode for a G-code machine, .svg for
    // an SVG laser profile; the G-code passes `check` as usual.
    let dir = tmpdir("default-output");
    for (machine, name) in [
        ("grbl-router", "neon_word.gcode"),
        ("svg-laser", "neon_word.svg"),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_skinpath"))
            .current_dir(&dir)
            .args(["build", &example_path("neon_word"), "--machine", machine])
            .output()
            .unwrap();
        expect_ok(&o, machine);
        assert!(dir.join(name).is_file(), "{machine}: no {name}");
    }
    expect_ok(
        &skinpath(&[
            "check",
            s(&dir.join("neon_word.gcode")),
            "--machine",
            "grbl-router",
        ]),
        "check",
    );
}
