//! `skinpath outline --method re|mph [--offset δ]` on the example designs: the outline
//! contours are closed and free of intersections (exact segment tests), touch every circle
//! of the sequence without cutting into any, and the offsets lie at distance δ from the
//! outline, the inner one absent where the stroke is thinner than δ.

use glam::DVec2;
use serde_json::Value;
use skinpath::geom::segments_intersect;
use std::path::PathBuf;
use std::process::Command;

/// Tolerance passed to `--tolerance` (design units, mm).
const TOL: f64 = 0.01;

struct Item {
    name: String,
    outline: Vec<Vec<DVec2>>,
    closed: Vec<bool>,
    offsets: Vec<Vec<DVec2>>,
    circles: Vec<(DVec2, f64)>,
    markers: usize,
}

fn run(design: &str, method: &str, offset: Option<f64>) -> Vec<Item> {
    let out: PathBuf = std::env::temp_dir().join(format!(
        "outline_re_{}_{method}_{}_{}.json",
        design.replace(['/', '.'], "_"),
        offset.map_or("none".to_string(), |d| format!("{d}")),
        std::process::id()
    ));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_skinpath"));
    cmd.arg("outline")
        .arg(format!("{}/{design}", env!("CARGO_MANIFEST_DIR")))
        .arg("-o")
        .arg(&out)
        .args(["--method", method, "--tolerance", &TOL.to_string()]);
    if let Some(d) = offset {
        cmd.args(["--offset", &d.to_string()]);
    }
    let st = cmd.output().unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let _ = std::fs::remove_file(&out);
    let pts = |c: &Value| -> Vec<DVec2> {
        c["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| DVec2::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect()
    };
    v["strokes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let mut it = Item {
                name: s["name"].as_str().unwrap().to_string(),
                outline: vec![],
                closed: vec![],
                offsets: vec![],
                circles: vec![],
                markers: s["markers"].as_array().map_or(0, |m| m.len()),
            };
            for c in s["contours"].as_array().unwrap() {
                match c["role"].as_str().unwrap() {
                    "outline" => {
                        it.outline.push(pts(c));
                        it.closed.push(c["closed"].as_bool().unwrap());
                    }
                    "offset" => it.offsets.push(pts(c)),
                    _ => {}
                }
            }
            for c in s["circles"].as_array().into_iter().flatten() {
                let role = c["role"].as_str().unwrap();
                if role == "circle" || role == "knot-circle" {
                    let p = &c["center"];
                    it.circles.push((
                        DVec2::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()),
                        c["radius"].as_f64().unwrap(),
                    ));
                }
            }
            it
        })
        .collect()
}

fn segs(c: &[DVec2]) -> impl Iterator<Item = (usize, DVec2, DVec2)> + '_ {
    (0..c.len()).map(move |i| (i, c[i], c[(i + 1) % c.len()]))
}

fn seg_dist(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let l = d.length_squared();
    let t = if l > 0.0 {
        ((p - a).dot(d) / l).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + t * d)
}

fn dist_to(p: DVec2, cs: &[Vec<DVec2>]) -> f64 {
    cs.iter()
        .flat_map(|c| segs(c))
        .map(|(_, a, b)| seg_dist(p, a, b))
        .fold(f64::INFINITY, f64::min)
}

/// Exact crossing test of every pair of non-adjacent segments of the closed polylines.
fn crossings(cs: &[Vec<DVec2>]) -> Vec<(usize, usize, usize, usize)> {
    let mut out = vec![];
    for (ci, a) in cs.iter().enumerate() {
        for (cj, b) in cs.iter().enumerate().skip(ci) {
            for (i, p0, p1) in segs(a) {
                for (j, q0, q1) in segs(b) {
                    if ci == cj {
                        let n = a.len();
                        if j <= i || j == i + 1 || (i == 0 && j == n - 1) {
                            continue;
                        }
                    }
                    if p0.max(p1).cmplt(q0.min(q1)).any() || q0.max(q1).cmplt(p0.min(p1)).any() {
                        continue;
                    }
                    if segments_intersect(p0, p1, q0, q1) {
                        out.push((ci, i, cj, j));
                    }
                }
            }
        }
    }
    out
}

fn check_outline(design: &str, method: &str) {
    let items = run(design, method, None);
    assert!(!items.is_empty());
    for it in &items {
        let ctx = format!("{design} {method} {}", it.name);
        assert!(!it.outline.is_empty(), "{ctx}: no outline");
        assert!(it.closed.iter().all(|c| *c), "{ctx}: open outline contour");
        assert!(it.outline.iter().all(|c| c.len() >= 3));
        let x = crossings(&it.outline);
        assert!(x.is_empty(), "{ctx}: crossings {:?}", &x[..x.len().min(5)]);
        assert_eq!(it.markers, 0, "{ctx}: intersections left");
        assert!(!it.circles.is_empty(), "{ctx}: no circles");
        for (k, &(c, r)) in it.circles.iter().enumerate() {
            // Touched: the outline comes to the circle.
            let d = dist_to(c, &it.outline) - r;
            assert!(
                d.abs() <= 10.0 * TOL,
                "{ctx}: circle {k} at {d} from the outline"
            );
            // Not cut: no outline point deeper than 10·TOL inside.
            for p in it.outline.iter().flatten() {
                let depth = r - p.distance(c);
                assert!(
                    depth <= 10.0 * TOL,
                    "{ctx}: circle {k}: {p} is {depth} inside"
                );
            }
        }
    }
}

fn check_offsets(design: &str, method: &str, delta: f64) {
    let items = run(design, method, Some(delta));
    for it in &items {
        let ctx = format!("{design} {method} δ={delta} {}", it.name);
        assert!(!it.offsets.is_empty(), "{ctx}: no offsets");
        // Each offset point is δ from the outline: the exact offset is, and both polylines
        // are within TOL of their exact curves (chord sagitta).
        for p in it.offsets.iter().flatten() {
            let d = dist_to(*p, &it.outline);
            assert!(
                (d - delta).abs() <= 2.0 * TOL + 1e-9,
                "{ctx}: offset point {p} at {d}"
            );
        }
        // The inner offset (points inside the material) exists exactly when some circle is
        // thicker than δ (the MAT radius exceeds δ there).
        let inner = it
            .offsets
            .iter()
            .flatten()
            .filter(|p| winding(**p, &it.outline) != 0)
            .count();
        let thick = it.circles.iter().any(|(_, r)| *r > delta + 2.0 * TOL);
        assert_eq!(inner > 0, thick, "{ctx}: {inner} inner offset points");
    }
}

/// Winding number of the closed polylines around `p`.
fn winding(p: DVec2, cs: &[Vec<DVec2>]) -> i32 {
    let mut w = 0;
    for (_, a, b) in cs.iter().flat_map(|c| segs(c)) {
        let side = (b - a).perp_dot(p - a);
        if a.y <= p.y && b.y > p.y && side > 0.0 {
            w += 1;
        } else if a.y > p.y && b.y <= p.y && side < 0.0 {
            w -= 1;
        }
    }
    w
}

#[test]
fn re_outline_of_circles_is_clean() {
    check_outline("examples/circles.toml", "re");
}

#[test]
fn mph_outline_of_circles_is_clean() {
    check_outline("examples/circles.toml", "mph");
}

#[test]
fn re_outline_of_brush_is_clean() {
    check_outline("examples/brush.toml", "re");
}

#[test]
fn mph_outline_of_brush_is_clean() {
    check_outline("examples/brush.toml", "mph");
}

#[test]
fn re_offsets_lie_at_delta() {
    check_offsets("examples/circles.toml", "re", 1.0);
    check_offsets("examples/brush.toml", "mph", 0.8);
}

#[test]
fn thick_offset_is_trimmed_where_thin() {
    // δ = 2 exceeds the comet's tail circles (r 1.5) and the brush's end circles; δ = 12
    // exceeds every circle of circles.toml, so no inner offset is left at all.
    check_offsets("examples/circles.toml", "mph", 2.0);
    check_offsets("examples/brush.toml", "re", 2.0);
    check_offsets("examples/circles.toml", "re", 12.0);
}

#[test]
fn skin_method_offsets_lie_at_delta() {
    check_offsets("examples/circles.toml", "skin", 1.0);
}

#[test]
fn bad_offset_is_refused() {
    let st = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .arg("outline")
        .arg(format!(
            "{}/examples/circles.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .args([
            "-o",
            "/tmp/outline_re_bad.json",
            "--method",
            "re",
            "--offset=-1",
        ])
        .output()
        .unwrap();
    assert!(!st.status.success());
}
