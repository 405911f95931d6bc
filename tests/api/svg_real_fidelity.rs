//! Fidelity of real drawings (issue 39, Tests): public SVG files nobody here made
//! (tests/svg_real: svg2gcode, MIT; tests/svg_real_vpype: vpype, MIT; tests/skin_data: AxiDraw
//! handwriting, GPL-2.0) are built with default flags on a laser and a router (`--fit` only
//! where the art is larger than the work area), and every program
//!
//! - checks clean with the same profile and no flags, and reads cleanly in LinuxCNC's
//!   `rs274` (`check --backend linuxcnc`, when rs274 is installed);
//! - keeps every visible part of the drawing: each visible stroke and fill boundary has a
//!   cut within half its width + the tool radius + [`SLACK_MM`]: the outside of the ink and
//!   every visible boundary between two colours inside it (a later fill on an earlier one
//!   of another colour: the default operations cut those as lines), not a boundary between
//!   fills of one colour, nor a stroke's part whose disk overlaps another profiled stroke
//!   (the profile cuts around the union). A knockout narrower than the tool (mean width
//!   2·area/perimeter, kurbo's, below the tool diameter) is not owed a cut when the build
//!   warned about it with that width. The drawing is read by
//!   usvg's tree and flattened by kurbo here, not by skinpath's import (no fitting, no
//!   paint model of ours): a sample is visible unless a later fill (opacity ≥ ½) covers it
//!   by its own fill rule; the page background (a first fill covering the page) is no ink.
//!   The cuts are read back from the G-code (G1/G2/G3 with the beam on, or below z = 0);
//! - cuts a hairline drawing once: a laser's cut length is within 1.5× the drawn length;
//! - honours a knockout: no cut lies inside a white fill farther than the tool radius +
//!   [`SLACK_MM`] from its boundary, except near art painted after it.

use crate::support;

use glam::DVec2;
use kurbo::{BezPath, PathEl, Point, Shape};
use rstar::PointDistance;
use rstar::RTree;
use rstar::primitives::{GeomWithData, Line as RLine};
use std::path::{Path, PathBuf};
use support::{skinpath, tmpdir};

/// Allowance on top of half a stroke's width and the tool radius (the 0.3 mm).
const SLACK_MM: f64 = 0.3;

/// Millimetres per SVG user unit at 96 px per inch (CSS).
const MM_PER_PX: f64 = 25.4 / 96.0;

/// Relative agreement asked of the build's reported mean width of a feature narrower than
/// the tool with the one computed here (both 2·area/perimeter, of differently flattened
/// outlines), plus [`WIDTH_SLACK_MM`].
const WIDTH_AGREEMENT: f64 = 0.02;

/// Absolute allowance on that agreement (the build prints three decimals).
const WIDTH_SLACK_MM: f64 = 0.01;

/// Spacing of the samples along the drawing, mm.
const SAMPLE_MM: f64 = 0.5;

/// Strokes at most this wide are hairlines (the default line/shape threshold).
const HAIRLINE_MM: f64 = 1.0;

/// A centre segment of a stroke wider than a hairline: (mark index, half width).
type WideSegment = GeomWithData<RLine<[f64; 2]>, (usize, f64)>;

/// One painted element, in paint order, in millimetres (y up, as the design).
struct Mark {
    path: BezPath,
    /// Half the stroke width (mm); `None` for a fill.
    half: Option<f64>,
    nonzero: bool,
    /// Opacity of the paint times its groups'.
    opacity: f64,
    white: bool,
    /// The paint's colour (none for gradients and patterns).
    color: Option<(u8, u8, u8)>,
}

fn walk(g: &usvg::Group, opacity: f64, height: f64, out: &mut Vec<Mark>) {
    let opacity = opacity * f64::from(g.opacity().get());
    for node in g.children() {
        match node {
            usvg::Node::Group(g) => walk(g, opacity, height, out),
            usvg::Node::Path(p) if p.is_visible() => {
                let t = p.abs_transform();
                let scale = ((t.sx * t.sy - t.kx * t.ky).abs() as f64).sqrt();
                let path = to_mm(p.data(), t, height);
                let white = |paint: &usvg::Paint| matches!(paint, usvg::Paint::Color(c) if (c.red, c.green, c.blue) == (255, 255, 255));
                let color = |paint: &usvg::Paint| match paint {
                    usvg::Paint::Color(c) => Some((c.red, c.green, c.blue)),
                    _ => None,
                };
                if let Some(f) = p.fill() {
                    out.push(Mark {
                        path: path.clone(),
                        half: None,
                        nonzero: f.rule() == usvg::FillRule::NonZero,
                        opacity: opacity * f64::from(f.opacity().get()),
                        white: white(f.paint()),
                        color: color(f.paint()),
                    });
                }
                if let Some(s) = p.stroke() {
                    out.push(Mark {
                        path,
                        half: Some(0.5 * f64::from(s.width().get()) * scale * MM_PER_PX),
                        nonzero: true,
                        opacity: opacity * f64::from(s.opacity().get()),
                        white: white(s.paint()),
                        color: color(s.paint()),
                    });
                }
            }
            _ => {}
        }
    }
}

fn to_mm(data: &usvg::tiny_skia_path::Path, t: usvg::Transform, height: f64) -> BezPath {
    let map = |q: usvg::tiny_skia_path::Point| {
        let x = (t.sx * q.x + t.kx * q.y + t.tx) as f64;
        let y = (t.ky * q.x + t.sy * q.y + t.ty) as f64;
        Point::new(x * MM_PER_PX, (height - y) * MM_PER_PX)
    };
    let mut b = BezPath::new();
    for seg in data.segments() {
        use usvg::tiny_skia_path::PathSegment as S;
        match seg {
            S::MoveTo(q) => b.move_to(map(q)),
            S::LineTo(q) => b.line_to(map(q)),
            S::QuadTo(a, c) => b.quad_to(map(a), map(c)),
            S::CubicTo(a, c, d) => b.curve_to(map(a), map(c), map(d)),
            S::Close => b.close_path(),
        }
    }
    b
}

/// The marks of an SVG file in paint order, the page background (a first fill covering the
/// page) left out.
fn marks(svg: &Path) -> Vec<Mark> {
    let text = std::fs::read_to_string(svg).unwrap();
    let tree = usvg::Tree::from_str(&text, &usvg::Options::default()).unwrap();
    let height = tree.size().height() as f64;
    let width = tree.size().width() as f64;
    let mut out = Vec::new();
    walk(tree.root(), 1.0, height, &mut out);
    if let Some(first) = out.first()
        && first.half.is_none()
    {
        let b = first.path.bounding_box();
        let t = 0.05;
        if b.x0 <= t && b.y0 <= t && b.x1 >= width * MM_PER_PX - t && b.y1 >= height * MM_PER_PX - t
        {
            out.remove(0);
        }
    }
    out.retain(|m| m.opacity >= 0.1);
    out
}

fn inside(m: &Mark, p: Point) -> bool {
    let w = m.path.winding(p);
    if m.nonzero { w != 0 } else { w % 2 != 0 }
}

/// Points every [`SAMPLE_MM`] along the path's subpaths (closed ones closed), flattened by
/// kurbo within 0.01 mm.
fn samples(path: &BezPath) -> Vec<Vec<Point>> {
    let mut lines: Vec<Vec<Point>> = Vec::new();
    let mut start = Point::ZERO;
    kurbo::flatten(path.iter(), 0.01, |el| match el {
        PathEl::MoveTo(p) => {
            start = p;
            lines.push(vec![p]);
        }
        PathEl::LineTo(p) => lines.last_mut().unwrap().push(p),
        PathEl::ClosePath => lines.last_mut().unwrap().push(start),
        _ => unreachable!("flatten gives lines"),
    });
    lines
        .into_iter()
        .map(|l| {
            let mut out = vec![l[0]];
            for w in l.windows(2) {
                let n = ((w[0].distance(w[1]) / SAMPLE_MM).ceil() as usize).max(1);
                out.extend((1..=n).map(|k| w[0].lerp(w[1], k as f64 / n as f64)));
            }
            out
        })
        .collect()
}

/// Cut polylines of a program (arcs flattened every 2°): laser moves with the beam on
/// (M3/M4, S > 0), router feed moves below z = 0.
fn cuts(src: &str, laser: bool) -> Vec<Vec<DVec2>> {
    let (mut pos, mut z, mut s, mut on, mut motion) = (DVec2::ZERO, 0.0, 0.0, false, 0);
    let mut out: Vec<Vec<DVec2>> = Vec::new();
    let mut open = false;
    for line in src.lines() {
        let mut code = String::new();
        let mut depth = 0;
        for c in line.chars() {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                ';' if depth == 0 => break,
                _ if depth == 0 => code.push(c.to_ascii_uppercase()),
                _ => {}
            }
        }
        let mut words: Vec<(char, f64)> = Vec::new();
        let b = code.as_bytes();
        let mut i = 0;
        while i < b.len() {
            let c = b[i] as char;
            if c.is_ascii_alphabetic() {
                let j = (i + 1..b.len())
                    .find(|&j| {
                        !(b[j] as char == '.'
                            || b[j] as char == '-'
                            || b[j].is_ascii_digit()
                            || b[j] == b' ')
                    })
                    .unwrap_or(b.len());
                let v: String = code[i + 1..j].chars().filter(|c| *c != ' ').collect();
                if let Ok(v) = v.parse::<f64>() {
                    words.push((c, v));
                }
                i = j;
            } else {
                i += 1;
            }
        }
        let get = |c: char| words.iter().find(|w| w.0 == c).map(|w| w.1);
        for &(c, v) in &words {
            match (c, v as i64) {
                ('G', 0..=3) if v.fract() == 0.0 => motion = v as i64,
                ('M', 3 | 4) => on = true,
                ('M', 5) => on = false,
                _ => {}
            }
        }
        if let Some(v) = get('S') {
            s = v;
        }
        let (x, y, nz) = (get('X'), get('Y'), get('Z'));
        if x.is_none() && y.is_none() && nz.is_none() {
            continue;
        }
        let to = DVec2::new(x.unwrap_or(pos.x), y.unwrap_or(pos.y));
        let to_z = nz.unwrap_or(z);
        let cutting = motion >= 1 && to_z == z && if laser { on && s > 0.0 } else { to_z < 0.0 };
        if cutting {
            if !open {
                out.push(vec![pos]);
                open = true;
            }
            let run = out.last_mut().unwrap();
            if motion >= 2 {
                let c = pos + DVec2::new(get('I').unwrap_or(0.0), get('J').unwrap_or(0.0));
                let r = pos.distance(c);
                let a0 = (pos - c).to_angle();
                let tau = std::f64::consts::TAU;
                let mut sw = (to - c).to_angle() - a0;
                if motion == 3 {
                    while sw <= 0.0 {
                        sw += tau;
                    }
                } else {
                    while sw >= 0.0 {
                        sw -= tau;
                    }
                }
                let n = ((sw.abs() / 2f64.to_radians()).ceil() as usize).max(1);
                run.extend(
                    (1..=n).map(|k| c + r * DVec2::from_angle(a0 + sw * k as f64 / n as f64)),
                );
            } else {
                run.push(to);
            }
        } else {
            open = false;
        }
        pos = to;
        z = to_z;
    }
    out
}

struct Built {
    program: PathBuf,
    scale: f64,
    offset: DVec2,
    cut_length: f64,
    /// The messages of the build's `warnings`.
    warnings: Vec<String>,
}

/// Build `svg` on `machine` with default flags, or `--fit` to the work area when the CLI
/// says the art is larger than it.
fn build(svg: &Path, machine: &str, dir: &Path) -> Built {
    let stem = svg.file_stem().unwrap().to_str().unwrap();
    let program = dir.join(format!("{stem}.{machine}.gcode"));
    let args = |fit: Option<&str>| {
        let mut a = vec![
            "build".to_string(),
            svg.to_str().unwrap().to_string(),
            "--machine".into(),
            machine.into(),
            "-o".into(),
            program.to_str().unwrap().to_string(),
            "--json".into(),
        ];
        if let Some(f) = fit {
            a.extend(["--fit".to_string(), f.to_string()]);
        }
        a
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        skinpath(&a)
    };
    let mut o = run(args(None));
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    if !o.status.success() && err.contains("larger than the work area") {
        let fit = err
            .split("--fit ")
            .nth(1)
            .and_then(|s| s.split_whitespace().next())
            .unwrap_or_else(|| panic!("no --fit advice: {err}"))
            .to_string();
        o = run(args(Some(&fit)));
    }
    assert!(
        o.status.success(),
        "{stem} on {machine}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let p = &v["placement"];
    Built {
        program,
        scale: p["scale"].as_f64().unwrap(),
        offset: DVec2::new(
            p["offset"][0].as_f64().unwrap(),
            p["offset"][1].as_f64().unwrap(),
        ),
        cut_length: v["cut_length"].as_f64().unwrap(),
        warnings: (v["warnings"].as_array().unwrap().iter())
            .map(|w| w["message"].as_str().unwrap().to_string())
            .collect(),
    }
}

/// `skinpath check PROGRAM --machine M` (no other flag) finds no error, and, when rs274
/// is installed, neither does the same check through LinuxCNC's interpreter (the pocket
/// marks of line cuts reach it as rs274's `COMMENT` lines).
fn check(program: &Path, machine: &str) {
    let p = program.to_str().unwrap();
    for backend in ["builtin", "linuxcnc"] {
        if backend == "linuxcnc"
            && std::process::Command::new("rs274")
                .arg("-h")
                .output()
                .is_err()
        {
            eprintln!("SKIPPED: rs274 (linuxcnc-uspace) is not installed");
            continue;
        }
        let o = skinpath(&[
            "check",
            p,
            "--machine",
            machine,
            "--backend",
            backend,
            "--json",
        ]);
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        let v: serde_json::Value =
            serde_json::from_str(&text).unwrap_or_else(|e| panic!("{p} {backend}: {e}: {text}"));
        let errors: Vec<&serde_json::Value> = v["findings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|f| f["severity"] == "error")
            .collect();
        assert!(errors.is_empty(), "{p} {backend}: {errors:?}");
    }
}

fn fidelity(svg: &Path) {
    let drawn = marks(svg);
    assert!(!drawn.is_empty(), "{svg:?}");
    let dir = tmpdir(&format!(
        "fidelity-{}",
        svg.file_stem().unwrap().to_str().unwrap()
    ));
    for (machine, laser, tool_r) in [
        ("grbl-laser", true, 0.04),
        ("grbl-router", false, 3.175 / 2.0),
    ] {
        let b = build(svg, machine, &dir);
        check(&b.program, machine);
        let src = std::fs::read_to_string(&b.program).unwrap();
        let runs = cuts(&src, laser);
        let segs: Vec<RLine<[f64; 2]>> = runs
            .iter()
            .flat_map(|r| {
                r.windows(2)
                    .map(|w| RLine::new([w[0].x, w[0].y], [w[1].x, w[1].y]))
            })
            .collect();
        assert!(!segs.is_empty(), "{svg:?} {machine}: no cut");
        let tree = RTree::bulk_load(segs);
        let to_machine = |p: Point| DVec2::new(p.x, p.y) * b.scale + b.offset;
        // Centre segments of the strokes wider than a hairline, with their half widths: where
        // the disk of a stroke's point overlaps another such stroke, the two are one region
        // of the union the profile cuts around, and the point's nearest cut may lie farther.
        let wide: RTree<WideSegment> = RTree::bulk_load(
            (drawn.iter().enumerate())
                .filter_map(|(j, l)| l.half.filter(|h| 2.0 * h > HAIRLINE_MM).map(|h| (j, l, h)))
                .flat_map(|(j, l, h)| {
                    samples(&l.path).into_iter().flat_map(move |line| {
                        line.windows(2)
                            .map(|w| {
                                GeomWithData::new(
                                    RLine::new([w[0].x, w[0].y], [w[1].x, w[1].y]),
                                    (j, h),
                                )
                            })
                            .collect::<Vec<_>>()
                    })
                })
                .collect(),
        );
        let widest = drawn.iter().filter_map(|l| l.half).fold(0.0, f64::max);
        let covered = |k: usize, p: Point, own: f64| {
            let reach = widest + own;
            wide.locate_within_distance([p.x, p.y], reach * reach)
                .any(|g| {
                    let r = g.data.1 + own;
                    g.data.0 != k && g.geom().distance_2(&[p.x, p.y]) < r * r
                })
        };
        let mut worst = (0.0f64, DVec2::ZERO);
        let mut hairline_length = 0.0;
        let mut all_hairlines = true;
        for (k, m) in drawn.iter().enumerate() {
            let half = m.half.unwrap_or(0.0) * b.scale;
            if m.half.is_some_and(|h| 2.0 * h <= HAIRLINE_MM) {
                hairline_length += m.path.perimeter(0.01) * b.scale;
            } else {
                all_hairlines = false;
            }
            let later: Vec<&Mark> = drawn[k + 1..]
                .iter()
                .filter(|l| l.half.is_none() && l.opacity >= 0.5)
                .collect();
            // Earlier ink fills of the same colour: a fill's boundary over one of them
            // separates nothing visible. Every other visible fill boundary is owed a cut.
            let same_ink: Vec<&Mark> = drawn[..k]
                .iter()
                .filter(|l| l.half.is_none() && !l.white && l.color == m.color)
                .collect();
            let earlier_ink: Vec<&Mark> = drawn[..k]
                .iter()
                .filter(|l| l.half.is_none() && !l.white)
                .collect();
            // A knockout narrower than the tool that the build warned about.
            // Design units, as the build reports it; the tool compares at the job's scale.
            let width = 2.0 * m.path.area().abs() / m.path.perimeter(0.001);
            let warned = m.white
                && m.half.is_none()
                && width * b.scale < 2.0 * tool_r
                && b.warnings.iter().any(|w| {
                    w.contains("narrower than the tool")
                        && w.split(" wide")
                            .next()
                            .and_then(|h| h.rsplit(' ').next())
                            .and_then(|x| x.parse::<f64>().ok())
                            .is_some_and(|x| {
                                (x - width).abs() <= WIDTH_AGREEMENT * width + WIDTH_SLACK_MM
                            })
                });
            if warned {
                eprintln!(
                    "{svg:?} on {machine}: a knockout {width:.3} wide is narrower than the tool, and the build says so"
                );
                continue;
            }
            for line in samples(&m.path) {
                for p in line {
                    if later.iter().any(|l| inside(l, p)) {
                        continue;
                    }
                    let owed = match (m.half, m.white) {
                        // Strokes are ink, white ones too (koch.svg: a white curve on a
                        // black page).
                        (Some(_), _) => true,
                        // A knockout's boundary is kept where it lies over earlier ink.
                        (None, true) => earlier_ink.iter().any(|l| inside(l, p)),
                        (None, false) => !same_ink.iter().any(|l| inside(l, p)),
                    };
                    if !owed || covered(k, p, m.half.unwrap_or(0.0)) {
                        continue;
                    }
                    let q = to_machine(p);
                    let d = tree
                        .nearest_neighbor_with_distance_2([q.x, q.y])
                        .map_or(f64::INFINITY, |(_, d2)| d2.sqrt());
                    let excess = d - (half + tool_r);
                    if excess > worst.0 {
                        worst = (excess, q);
                    }
                }
            }
        }
        assert!(
            worst.0 <= SLACK_MM,
            "{svg:?} on {machine}: a visible part of the drawing at {:?} lies {:.3} mm beyond half \
             its width + the tool radius from the nearest cut",
            worst.1,
            worst.0
        );
        if laser && all_hairlines {
            assert!(
                b.cut_length <= 1.5 * hairline_length,
                "{svg:?}: laser cut length {} for a drawn length of {hairline_length}",
                b.cut_length
            );
        }
        // Knockouts: no cut inside a white fill deeper than the tool radius + slack, except
        // near art painted after it.
        for (k, m) in drawn.iter().enumerate() {
            if !(m.white && m.half.is_none() && m.opacity >= 0.5) {
                continue;
            }
            let edge: Vec<DVec2> = samples(&m.path)
                .into_iter()
                .flatten()
                .map(to_machine)
                .collect();
            let later: Vec<DVec2> = drawn[k + 1..]
                .iter()
                .flat_map(|l| samples(&l.path).into_iter().flatten().map(to_machine))
                .collect();
            let near = |q: DVec2, pts: &[DVec2], r: f64| pts.iter().any(|e| e.distance(q) <= r);
            for q in runs.iter().flatten() {
                let design = (*q - b.offset) / b.scale;
                if !inside(m, Point::new(design.x, design.y)) {
                    continue;
                }
                let r = tool_r + SLACK_MM + SAMPLE_MM;
                assert!(
                    near(*q, &edge, r) || near(*q, &later, r + 0.5 * HAIRLINE_MM),
                    "{svg:?} on {machine}: a cut at {q:?} lies inside a knockout"
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn data(dir: &str, file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(dir)
        .join(file)
}

#[test]
fn svg2gcode_drawings_keep_their_visible_art() {
    for f in ["koch.svg", "Vanderbilt_Commodores_logo.svg", "shapes.svg"] {
        fidelity(&data("svg_real", f));
    }
}

#[test]
fn vpype_drawings_keep_their_visible_art() {
    for f in ["arc_with_rotate.svg", "plotter.svg", "voronoi.svg"] {
        fidelity(&data("svg_real_vpype", f));
    }
}

#[test]
fn axidraw_handwriting_keeps_its_visible_art() {
    for f in ["axidraw_signatures.svg", "axidraw_happy_birthday.svg"] {
        fidelity(&data("skin_data", f));
    }
}
