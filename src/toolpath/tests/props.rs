//! Geometric properties of the toolpath operations on the shipped examples (and rotated,
//! scaled copies of their regions), each checked against an independent computation:
//! profiles against exact point-to-polyline distances and geo's `Buffer`, hatch lines
//! against `Region::contains`, concentric rings against exact segment predicates, V-carve
//! depths against r·cot(θ/2), and ordering against containment of the traced cuts.

use super::*;
use crate::geom::segments_intersect;
use crate::job::{BuildOptions, build_toolpath};
use crate::machine::builtin_profile;
use crate::toolpath::OperationKind;
use crate::toolpath::ops::{ProfileSide, concentric, hatch, profile};
use crate::toolpath::region::Region;
use geo::{Area, Buffer};
use glam::DVec2;
use std::f64::consts::PI;

/// Arc fitting tolerance of the regions.
const TOL: f64 = 1e-2;
/// Flattening tolerance of the checks (sagitta of the chords of arcs).
const FLAT: f64 = 1e-3;

/// Each example's regions, plus a copy of the first region rotated by 0.7 rad and scaled
/// by 1.7; computed once (skinning the examples dominates the run time) and shared by the
/// tests.
fn cases() -> &'static [(String, Region)] {
    static CASES: std::sync::OnceLock<Vec<(String, Region)>> = std::sync::OnceLock::new();
    CASES.get_or_init(|| {
        let mut out = Vec::new();
        for ex in EXAMPLES {
            let rs = regions(ex, TOL);
            if let Some((n, r)) = rs.first() {
                out.push((format!("{ex}/{n} rotated+scaled"), similar(r, 0.7, 1.7)));
            }
            out.extend(rs.into_iter().map(|(n, r)| (format!("{ex}/{n}"), r)));
        }
        out
    })
}

fn geo_buffer_area(r: &Region, delta: f64) -> f64 {
    // Round joins with angle step φ = √(8·tol/|δ|): chord sagitta ≤ tol.
    let phi = (8.0 * FLAT / delta.abs()).sqrt().min(1.0);
    let style = geo::algorithm::buffer::BufferStyle::new(delta)
        .line_join(geo::algorithm::buffer::LineJoin::Round(phi));
    r.to_geo(FLAT).buffer_with_style(style).unsigned_area()
}

#[test]
fn profiles_sit_at_the_tool_radius() {
    let rt = 1.0;
    for (name, region) in cases() {
        let outline = flat_rings(region, FLAT);
        for (side, sign) in [(ProfileSide::Outside, 1.0), (ProfileSide::Inside, -1.0)] {
            let paths = profile(region, side, rt, 1e-6);
            if side == ProfileSide::Outside {
                assert!(!paths.is_empty(), "{name}: no outside profile");
            }
            let mut worst: f64 = 0.0;
            for p in &paths {
                let pts = p.flatten(FLAT);
                // At most ~100 samples per path keep the exact distances cheap.
                for &q in pts.iter().step_by((pts.len() / 100).max(1)) {
                    worst = worst.max((rings_distance(&outline, q) - rt).abs());
                }
            }
            // Two flattenings within FLAT each, and the offset's joining tolerance.
            assert!(
                worst < 3.0 * FLAT,
                "{name} {side:?}: max |d − r| = {worst:e}"
            );
            // Area of the offset region (arcs exact) against geo's buffer of the flattening.
            let moved = region.offset(sign * rt, 1e-6);
            let ours = moved.area();
            let theirs = geo_buffer_area(region, sign * rt);
            let rel = (ours - theirs).abs() / theirs.max(1e-12);
            if theirs > 0.0 {
                assert!(
                    rel < 1e-3,
                    "{name} {side:?}: area {ours} vs geo buffer {theirs} (rel {rel:e})"
                );
            } else {
                assert!(ours.abs() < 1e-9, "{name} {side:?}: geo empty, ours {ours}");
            }
        }
    }
}

/// Perpendicular coordinate of a point for hatch lines at `angle`.
fn across(p: DVec2, angle: f64) -> f64 {
    let (s, c) = angle.sin_cos();
    -s * p.x + c * p.y
}

#[test]
fn hatch_lines_lie_inside_and_alternate() {
    let spacing = 0.7;
    for (name, region) in cases() {
        let scale = (region.area().abs()).sqrt();
        let spacing = spacing * (scale / 40.0).max(0.2);
        let rings = flat_rings(region, FLAT);
        for angle in [0.0, 0.5, PI / 2.0] {
            let lines = hatch(region, angle, spacing, true, FLAT);
            assert!(!lines.is_empty(), "{name}: no hatch at {angle}");
            let dir = DVec2::from_angle(angle);
            for l in lines.iter().step_by((lines.len() / 30).max(1)) {
                let (a, b) = (l.segs[0].start(), l.segs[0].end());
                for i in 1..20 {
                    let p = a.lerp(b, i as f64 / 20.0);
                    assert!(
                        region.contains(p),
                        "{name} {angle}: hatch point {p} outside"
                    );
                }
                // Ends on the boundary's flattening: inside, or within the sagitta.
                for p in [a, b] {
                    let d = rings_distance(&rings, p);
                    assert!(region.contains(p) || d < 2.0 * FLAT, "{name}: end {p} out");
                }
                // Along the hatch direction (either way).
                assert!(((b - a).normalize().dot(dir)).abs() > 1.0 - 1e-9);
            }
            // Alternate: scanline k runs +dir when k is even, −dir when odd.
            let y0 = lines
                .iter()
                .map(|l| across(l.segs[0].start(), angle))
                .fold(f64::INFINITY, f64::min);
            for l in &lines {
                let k = ((across(l.segs[0].start(), angle) - y0) / spacing).round() as i64;
                let fwd = (l.segs[0].end() - l.segs[0].start()).dot(dir) > 0.0;
                assert_eq!(fwd, k % 2 == 0, "{name} {angle}: scanline {k}");
            }
            // Without alternation every line runs +dir.
            for l in hatch(region, angle, spacing, false, FLAT) {
                assert!((l.segs[0].end() - l.segs[0].start()).dot(dir) > 0.0);
            }
        }
    }
}

#[test]
fn cross_hatch_adds_the_perpendicular_set() {
    let laser = builtin_profile("grbl-laser").unwrap();
    let mut d = super::example("brush");
    d.operation
        .retain(|o| o.kind == crate::design::OperationKind::Fill);
    d.operation[0].spacing = Some(1.0);
    let angle = d.operation[0].angle.unwrap_or(0.0).to_radians();
    let count = |d: &crate::design::Design| {
        let b = build_toolpath(d, &laser, &BuildOptions::default()).unwrap();
        let op = &b.toolpath.operations[0];
        assert_eq!(op.kind, OperationKind::Fill);
        let (mut along, mut perp) = (0, 0);
        for c in &op.cuts {
            let t = trace_xy(c, 1e-3);
            let v = (t[t.len() - 1] - t[0]).normalize();
            let u = DVec2::from_angle(angle);
            if v.dot(u).abs() > 1.0 - 1e-9 {
                along += 1;
            } else if v.dot(u).abs() < 1e-9 {
                perp += 1;
            } else {
                panic!("hatch cut along neither direction: {v}");
            }
        }
        (along, perp)
    };
    let (a0, p0) = count(&d);
    assert!(a0 > 0);
    assert_eq!(p0, 0, "single hatch has no perpendicular lines");
    d.operation[0].cross_hatch = Some(true);
    let (a1, p1) = count(&d);
    assert_eq!(a1, a0, "cross-hatch keeps the first set");
    assert!(p1 > 0, "cross-hatch adds the perpendicular set");
}

fn bbox(pts: &[DVec2]) -> (DVec2, DVec2) {
    pts.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

fn rings_cross(a: &[DVec2], b: &[DVec2]) -> bool {
    let (la, ha) = bbox(a);
    let (lb, hb) = bbox(b);
    if la.x > hb.x || lb.x > ha.x || la.y > hb.y || lb.y > ha.y {
        return false;
    }
    let (na, nb) = (a.len(), b.len());
    (0..na).any(|i| {
        let (p, q) = (a[i], a[(i + 1) % na]);
        let (lo, hi) = (p.min(q), p.max(q));
        if lo.x > hb.x || hi.x < lb.x || lo.y > hb.y || hi.y < lb.y {
            return false;
        }
        (0..nb).any(|j| segments_intersect(p, q, b[j], b[(j + 1) % nb]))
    })
}

#[test]
fn concentric_rings_never_cross_and_nest() {
    for (name, region) in cases() {
        let size = region.area().abs().sqrt();
        let (first, step) = (0.05 * size, 0.08 * size);
        let rings = concentric(region, first, step, step / 2.0, 1000, 1e-6);
        assert!(!rings.is_empty(), "{name}");
        let outline = flat_rings(region, FLAT);
        // Level of each ring: its distance to the outline is first + k·step.
        let flat: Vec<(usize, Vec<DVec2>)> = rings
            .iter()
            .map(|p| {
                let pts = p.flatten(1e-2 * size / 40.0);
                let d = rings_distance(&outline, pts[0]);
                let k = ((d - first) / step).round();
                assert!(
                    (d - first - k * step).abs() < 1e-3,
                    "{name}: ring at distance {d}"
                );
                (k as usize, pts)
            })
            .collect();
        for i in 0..flat.len() {
            for j in i + 1..flat.len() {
                assert!(
                    !rings_cross(&flat[i].1, &flat[j].1),
                    "{name}: rings {i} and {j} cross"
                );
            }
        }
        // Every ring of level k + 1 lies inside the region bounded by level k's rings.
        let max_k = flat.iter().map(|f| f.0).max().unwrap_or(0);
        for k in 0..max_k {
            let outer: Vec<&Vec<DVec2>> = flat.iter().filter(|f| f.0 == k).map(|f| &f.1).collect();
            for (_, pts) in flat.iter().filter(|f| f.0 == k + 1) {
                let inside = outer.iter().filter(|o| in_polygon(o, pts[0])).count();
                assert!(inside % 2 == 1, "{name}: ring of level {} outside", k + 1);
            }
        }
    }
}

#[test]
fn vcarve_depth_follows_the_radius_below_the_cap() {
    let router = builtin_profile("grbl-router").unwrap();
    let d = super::example("calligraphy");
    let strokes = d.strokes().unwrap();
    let op = d
        .operation
        .iter()
        .find(|o| o.kind == crate::design::OperationKind::Vcarve)
        .unwrap();
    let theta = op.angle.unwrap().to_radians();
    let cap = op.max_depth.unwrap();
    let b = build_toolpath(&d, &router, &BuildOptions::default()).unwrap();
    let carve = b
        .toolpath
        .operations
        .iter()
        .find(|o| o.kind == OperationKind::VCarve && !o.name.ends_with("flat"))
        .unwrap();
    let mut capped = 0;
    let mut total = 0;
    for cut in &carve.cuts {
        let k = d
            .stroke
            .iter()
            .position(|s| Some(&s.name) == cut.source.as_ref())
            .unwrap();
        let c = &strokes[k];
        let (lo, hi) = c.domain();
        let n = cut.moves.len() - 1;
        for (i, m) in cut.moves.iter().enumerate() {
            let t = lo + (hi - lo) * i as f64 / n as f64;
            assert!(
                c.center(t).distance(m.to.truncate()) < 1e-9,
                "spine sample {i}"
            );
            let want = -(c.radius(t) / (theta / 2.0).tan()).min(cap);
            assert!((m.to.z - want).abs() < 1e-12, "z {} vs {want}", m.to.z);
            capped += (want == -cap) as usize;
            total += 1;
        }
    }
    assert!(
        total > 100 && capped > 0 && capped < total,
        "{capped}/{total}"
    );
}

/// Builds an example with a router (falls back to the laser when the design's operations
/// have no depths).
fn build_example(name: &str) -> crate::job::BuildResult {
    let d = super::example(name);
    let router = builtin_profile("grbl-router").unwrap();
    let laser = builtin_profile("grbl-laser").unwrap();
    build_toolpath(&d, &router, &BuildOptions::default())
        .or_else(|_| build_toolpath(&d, &laser, &BuildOptions::default()))
        .unwrap()
}

#[test]
fn inner_contours_precede_enclosing_ones_on_every_example() {
    // gclef and neon_word are left out: see `gclef_and_neon_word_build_for_a_router`
    // (cavalier_contours panics there).
    let all = [
        "brush",
        "calligraphy",
        "circles",
        "loop",
        "ring_o",
        "seahorse",
        "snake",
    ];
    for ex in all {
        let b = build_example(ex);
        for op in &b.toolpath.operations {
            // Closed cuts: the trace returns to its first point on the contour.
            let closed: Vec<(usize, Vec<DVec2>)> = op
                .cuts
                .iter()
                .enumerate()
                .filter_map(|(i, c)| {
                    let t = trace_xy(c, 1e-2);
                    let on: Vec<DVec2> = t[1..].to_vec();
                    (on.len() > 3 && on[0].distance(on[on.len() - 1]) < 1e-6).then_some((i, on))
                })
                .collect();
            if closed.len() > 400 {
                continue;
            }
            for (i, a) in &closed {
                for (j, bpts) in &closed {
                    if i == j {
                        continue;
                    }
                    let a_in_b = a.iter().step_by(7).all(|p| in_polygon(bpts, *p))
                        && !a.iter().any(|p| bpts.contains(p));
                    if a_in_b {
                        assert!(i < j, "{ex} {}: cut {i} inside cut {j} but later", op.name);
                    }
                }
            }
        }
    }
}

#[test]
fn outline_area_checks_against_geo_on_rotated_copy() {
    // The rotated, scaled copy of a region has s² times its area, and its offset by s·r
    // has s² times the offset's area (similarity invariance of the offset).
    for ex in EXAMPLES {
        let (_, r) = regions(ex, TOL).remove(0);
        let s = 1.7;
        let q = similar(&r, 0.7, s);
        assert!((q.area() - s * s * r.area()).abs() < 1e-9 * r.area().abs() * s * s);
        let a = r.offset(0.8, 1e-6).area();
        let b = q.offset(0.8 * s, 1e-6).area();
        assert!(
            (b - s * s * a).abs() < 1e-6 * b.abs(),
            "{ex}: {b} vs {}",
            s * s * a
        );
    }
}

#[test]
fn gclef_and_neon_word_build_for_a_router() {
    for ex in ["gclef", "neon_word"] {
        let b = build_example(ex);
        assert!(!b.toolpath.operations.is_empty());
    }
}
