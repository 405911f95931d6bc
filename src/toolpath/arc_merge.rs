//! Runs of lines merged into arcs (and longer lines) within a certified tolerance: what a
//! laser cuts along a flattened outline (the union of crossing strokes is a polygon) is
//! written as G2/G3 where the profile takes arcs, with far fewer moves.
//!
//! **Bound.** A run of vertices v_i..v_j is replaced by the arc of the circle (C, R) through
//! v_i, v_m (m the middle index) and v_j, from v_i to v_j with sweep below π, when
//!
//!   e = max over the run's segments S of max( max_{v ∈ S} ‖v − C‖ − R, R − dist(C, S) ) ≤ tol
//!
//! and every vertex lies in the arc's sector (`arc_hull_bound`, each segment its own
//! hull: ‖· − C‖ is convex, so its maximum over a segment is at an end and its minimum is
//! the distance from C to the segment). Every point of the run is then within e of the arc;
//! conversely the run joins the ray C→v_i to the ray C→v_j inside the sector's band of
//! half-width e around the circle, so it crosses every ray in between within e of the arc
//! point on it: the Hausdorff distance between run and arc is at most e (the argument of
//! [`crate::skin::mat_offset`]'s merged arcs, with segments for hulls). A run that is
//! straight within `tol` (every vertex within `tol` of the chord v_i v_j, which bounds the
//! distance from every segment, the distance to a segment being convex) becomes that chord.
//!
//! Chords of a flattened arc are within their sagitta of the arc through their ends, so a
//! polyline merges into arcs only where it was flattened finer than `tol` (the build
//! flattens unions at a third of the tolerance and merges within the other two thirds).
//!
//! **Search.** From each vertex the farthest end j is found by galloping and binary search
//! on j (success is assumed to shrink with j; each end found is certified by its own
//! bound), each test O(j − i): O(n log n) for a run of n segments. Arcs and cubics of the
//! path are kept as they are; only runs of consecutive lines are merged.

use crate::geom::hull::arc_hull_bound;
use crate::geom::{Arc, DVec2, Line, Path, PathSeg, cross};

/// Sector containment slack of the bound, as an angle (radians): rounding of points on the
/// sector's rays.
const CONTAIN_EPS: f64 = 1e-9;

/// Smallest radius of a merged arc, in tolerances: a circle narrower than that is a
/// handful of tiny segments (a sharp tip), which stay lines; the G-code writer refuses
/// arcs whose radius is within its tolerance.
const MIN_RADIUS_TOLS: f64 = 10.0;

/// Three points whose turn (cross product over the squared chord) is below this are taken
/// as straight: their circle would be wider than 1e9 chords.
const STRAIGHT_TURN: f64 = 1e-9;

/// The arc or line replacing the run `v[i..=j]` within `tol`, if there is one (module docs).
fn fit(v: &[DVec2], i: usize, j: usize, tol: f64) -> Option<PathSeg> {
    let (p, q) = (v[i], v[j]);
    let chord = Line::new(p, q);
    if v[i + 1..j].iter().all(|&x| chord.distance(x) <= tol) {
        return Some(PathSeg::Line(chord));
    }
    let m = v[(i + j) / 2];
    let turn = cross(m - p, q - m);
    if turn.abs() <= STRAIGHT_TURN * (q - p).length_squared() {
        return None;
    }
    let c = circumcenter(p, m, q)?;
    let r = (p - c).length();
    if r <= MIN_RADIUS_TOLS * tol {
        return None;
    }
    let ccw = turn > 0.0;
    let arc = Arc::from_center_points(c, p, q, ccw);
    if arc.sweep.is_nan() || arc.sweep.abs() >= std::f64::consts::PI {
        return None;
    }
    for k in i..j {
        let e = arc_hull_bound(c, r, p, q, ccw, &v[k..=k + 1], CONTAIN_EPS)?;
        if e > tol {
            return None;
        }
    }
    Some(PathSeg::Arc(arc))
}

/// Centre of the circle through three points (None when they are collinear).
fn circumcenter(a: DVec2, b: DVec2, c: DVec2) -> Option<DVec2> {
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * cross(ab, ac);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let (l1, l2) = (ab.length_squared(), ac.length_squared());
    let x = (ac.y * l1 - ab.y * l2) / d;
    let y = (ab.x * l2 - ac.x * l1) / d;
    let o = a + DVec2::new(x, y);
    o.is_finite().then_some(o)
}

/// The farthest j in [i + 2, n] whose run fits (galloping, then binary search), with its
/// segment.
fn farthest(v: &[DVec2], i: usize, n: usize, tol: f64) -> Option<(usize, PathSeg)> {
    let mut lo = i + 2;
    if lo > n {
        return None;
    }
    let mut best = fit(v, i, lo, tol)?;
    let mut step = 1;
    let mut hi = n + 1;
    while lo < n {
        let j = (lo + step).min(n);
        match fit(v, i, j, tol) {
            Some(s) => {
                lo = j;
                best = s;
                step *= 2;
            }
            None => {
                hi = j;
                break;
            }
        }
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        match fit(v, i, mid, tol) {
            Some(s) => {
                lo = mid;
                best = s;
            }
            None => hi = mid,
        }
    }
    Some((lo, best))
}

/// The run of lines through `v` (at least two points) as merged segments, each within `tol`
/// of the run it replaces; lines keep the run's points, arcs meet them up to rounding (their
/// ends are recomputed from their angles).
fn merge_run(v: &[DVec2], tol: f64, out: &mut Vec<PathSeg>) {
    let n = v.len() - 1;
    let mut i = 0;
    while i < n {
        match farthest(v, i, n, tol) {
            Some((j, seg)) => {
                out.push(seg);
                i = j;
            }
            None => {
                out.push(PathSeg::Line(Line::new(v[i], v[i + 1])));
                i += 1;
            }
        }
    }
}

/// `path` with each run of consecutive lines merged into arcs and longer lines, each within
/// `tol` of the lines it replaces (module docs); other segments are kept. The result is
/// within `tol` of `path` (Hausdorff distance) and starts and ends where it does.
pub fn merge_lines(path: &Path, tol: f64) -> Path {
    if tol.is_nan() || tol <= 0.0 {
        return path.clone();
    }
    let mut out: Vec<PathSeg> = Vec::with_capacity(path.segs.len());
    let mut run: Vec<DVec2> = Vec::new();
    let flush = |run: &mut Vec<DVec2>, out: &mut Vec<PathSeg>| {
        if run.len() >= 2 {
            merge_run(run, tol, out);
        }
        run.clear();
    };
    for s in &path.segs {
        match s {
            PathSeg::Line(l) => {
                if run.is_empty() {
                    run.push(l.p0);
                }
                run.push(l.p1);
            }
            other => {
                flush(&mut run, &mut out);
                out.push(*other);
            }
        }
    }
    flush(&mut run, &mut out);
    Path::new(out, path.closed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Distance from `q` to a dense flattening of `path`'s segments (lines exact).
    fn to_path(path: &Path, q: DVec2) -> f64 {
        path.segs
            .iter()
            .map(|s| match s {
                PathSeg::Line(l) => l.distance(q),
                PathSeg::Arc(a) => a.distance(q),
                PathSeg::Cubic(c) => (0..=256)
                    .map(|k| c.eval(k as f64 / 256.0).distance(q))
                    .fold(f64::INFINITY, f64::min),
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The Hausdorff distance both ways, sampled (64 points per segment).
    fn hausdorff(a: &Path, b: &Path) -> f64 {
        let one = |x: &Path, y: &Path| {
            x.segs
                .iter()
                .flat_map(|s| (0..=64).map(move |k| s.eval(k as f64 / 64.0)))
                .map(|q| to_path(y, q))
                .fold(0.0f64, f64::max)
        };
        one(a, b).max(one(b, a))
    }

    fn polyline(pts: &[DVec2], closed: bool) -> Path {
        Path::polyline(pts, closed)
    }

    #[test]
    fn a_flattened_circle_becomes_a_few_arcs() {
        // Chord sagitta r(1 − cos(π/n)) = 3.1e-4, below the tolerance: the bound of an arc
        // through the vertices is the sagitta (a coarser polyline cannot merge within 1e-3).
        let (r, n) = (10.0, 400);
        let pts: Vec<DVec2> = (0..n)
            .map(|k| DVec2::from_angle(k as f64 / n as f64 * std::f64::consts::TAU) * r)
            .collect();
        let p = polyline(&pts, true);
        let tol = 1e-3;
        let m = merge_lines(&p, tol);
        let arcs = m
            .segs
            .iter()
            .filter(|s| matches!(s, PathSeg::Arc(_)))
            .count();
        assert!(arcs >= 2 && m.segs.len() <= 6, "{} segments", m.segs.len());
        // Every arc lies on the circle.
        for s in &m.segs {
            if let PathSeg::Arc(a) = s {
                assert!((a.radius - r).abs() < 1e-9 && a.center.length() < 1e-9);
            }
        }
        assert!(hausdorff(&p, &m) <= tol + 1e-9);
        // Arcs on the circle and the chords left: between the polygon's length and 2πr.
        let len = m.length(1e-9);
        assert!(len >= p.length(1e-9) - 1e-9 && len <= std::f64::consts::TAU * r + 1e-9);
    }

    #[test]
    fn tiny_circles_stay_lines() {
        let pts: Vec<DVec2> = (0..40)
            .map(|k| DVec2::from_angle(k as f64 / 40.0 * std::f64::consts::TAU) * 0.05)
            .collect();
        let p = polyline(&pts, true);
        let m = merge_lines(&p, 0.01);
        assert!(m.segs.iter().all(|s| matches!(s, PathSeg::Line(_))));
        assert!(hausdorff(&p, &m) <= 0.01 + 1e-12);
    }

    #[test]
    fn straight_runs_become_one_line_and_corners_stay() {
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(3.0, 0.0),
            DVec2::new(3.0, 1.0),
            DVec2::new(3.0, 2.0),
        ];
        let m = merge_lines(&polyline(&pts, false), 1e-3);
        assert_eq!(m.segs.len(), 2);
        assert_eq!(m.start(), Some(pts[0]));
        assert_eq!(m.end(), Some(pts[5]));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Any polyline (wiggly arcs with noise, corners) merges within the tolerance of
        /// itself, measured independently by sampling both ways, and keeps its ends.
        #[test]
        fn merged_paths_stay_within_tolerance(
            r in 1.0f64..50.0,
            bumps in proptest::collection::vec((0.0f64..1.0, -0.02f64..0.02), 3..12),
            n in 8usize..120,
            tol in 1e-4f64..0.05,
            closed in any::<bool>(),
        ) {
            let pts: Vec<DVec2> = (0..n)
                .map(|k| {
                    let t = k as f64 / n as f64;
                    let b = &bumps[k % bumps.len()];
                    let rr = r * (1.0 + if b.0 < 0.3 { b.1 } else { 0.0 });
                    DVec2::from_angle(t * 5.0) * rr
                })
                .collect();
            let p = polyline(&pts, closed);
            let m = merge_lines(&p, tol);
            prop_assert!(m.segs.len() <= p.segs.len());
            let (a, b) = (m.start().unwrap_or_default(), p.start().unwrap_or_default());
            prop_assert!(a.distance(b) < 1e-9 * r);
            let h = hausdorff(&p, &m);
            prop_assert!(h <= tol * (1.0 + 1e-6) + 1e-9 * r, "distance {} > tol {}", h, tol);
            prop_assert!(m.max_gap() < 1e-9 * r);
        }
    }
}
