//! Arc fitting: cubic Béziers to G1 chains of circular arcs (biarcs) within a tolerance.
//!
//! A biarc joins P0 (unit tangent T0) to P1 (unit tangent T1) by two arcs meeting with a
//! common tangent at a joint J. With equal tangent lengths d on both sides (the classic
//! choice), ‖(P1 − d T1) − (P0 + d T0)‖ = 2d gives ‖v‖² − 2d v·(T0 + T1) + 2d²(T0·T1 − 1) = 0
//! with v = P1 − P0, and
//! J = ½(P0 + d T0 + P1 − d T1). A segment whose error exceeds the tolerance is split at
//! its parameter midpoint and fitted again.
//!
//! The error is verified, not assumed: [`max_deviation`] bounds the Hausdorff distance
//! between curve and biarc from above, on pieces refined by bisection until the bound
//! proves the tolerance, by the smaller of two bounds: a first-order one from exact
//! point-to-arc distances at the piece's ends plus a Lipschitz argument (the cubic's speed
//! is bounded by 3 × its longest control-polygon leg), and a second-order one from the
//! piece's convex hull (its control points) against one line or arc of the chain whose
//! nearest-point formula holds on the whole hull ([`hull_distance_bound`]). The first needs
//! pieces about 2·tol long; the second, pieces whose hull lies within tol of the chain,
//! which on a fit within tol is a few per arc.

use crate::geom::hull::{arc_hull_bound, segment_hull_bound};
use crate::geom::tol::{DISTANCE_FLATTEN, LENGTH_ACCURACY};
use crate::geom::{Aabb, Arc, CubicBez, DVec2, Line, PathSeg, perp};

/// Evenly spread points of the curve whose distances [`max_deviation`] tries first.
const PRE_SAMPLES: usize = 16;

/// Deepest recursion of the split-and-refit loop: 2^16 pieces per cubic at most.
const MAX_DEPTH: u32 = 16;

/// The arc from `p` leaving with unit tangent `t` and ending at `q`, or a line when `q` is
/// straight ahead within `straight_tol` (sagitta-like deviation).
pub fn arc_from_tangent(p: DVec2, t: DVec2, q: DVec2, straight_tol: f64) -> PathSeg {
    let chord = q - p;
    let n = perp(t);
    let h = n.dot(chord);
    let len2 = chord.length_squared();
    if len2 == 0.0 {
        return PathSeg::Line(Line::new(p, q));
    }
    // Deviation of the arc's midpoint from the chord: sagitta s = r(1 − cos(θ/2)) where the
    // tangent–chord angle is θ/2; a tiny h means a nearly straight arc.
    let sin_half = h / len2.sqrt();
    let sagitta_estimate = 0.5 * len2.sqrt() * (sin_half.abs() / 2.0);
    if sagitta_estimate <= straight_tol * 1e-3 || h.abs() < 1e-300 {
        return PathSeg::Line(Line::new(p, q));
    }
    let r = len2 / (2.0 * h);
    let center = p + n * r;
    let ccw = r > 0.0;
    PathSeg::Arc(Arc::from_center_points(center, p, q, ccw))
}

/// The biarc from (p0, t0) to (p1, t1), unit tangents; `None` when the construction
/// degenerates (d ≤ 0: the tangents point away from each other).
pub fn biarc(p0: DVec2, t0: DVec2, p1: DVec2, t1: DVec2, tol: f64) -> Option<[PathSeg; 2]> {
    let v = p1 - p0;
    let t = t0 + t1;
    let vv = v.length_squared();
    let vt = v.dot(t);
    let a = 2.0 * (t0.dot(t1) - 1.0);
    let d = if a.abs() < 1e-12 {
        // Parallel equal tangents: ‖v‖² − 2d v·t = 0 with t = 2 t1: d = ‖v‖² / (4 v·t1).
        let den = 4.0 * v.dot(t1);
        if den <= 0.0 {
            return None;
        }
        vv / den
    } else {
        // a d² − 2 vt d + vv = 0 with a < 0: the positive root (vt − √(vt² − a vv)) / a.
        let disc = vt * vt - a * vv;
        if disc < 0.0 {
            return None;
        }
        (vt - disc.sqrt()) / a
    };
    if d.is_nan() || d <= 0.0 || !d.is_finite() {
        return None;
    }
    let j = 0.5 * (p0 + d * t0 + p1 - d * t1);
    let first = arc_from_tangent(p0, t0, j, tol);
    // The second arc is built backwards from p1 with the reversed tangent.
    let second = arc_from_tangent(p1, -t1, j, tol).reversed();
    Some([first, second])
}

/// An upper bound of dist(x, `seg`) over the convex hull of `hull` (any order), or `None`:
/// a line by `segment_hull_bound` (the distance to a segment is convex); an arc of sweep
/// at most π by `arc_hull_bound` where the hull lies in its sector (exactly, no slack);
/// `None` for wider arcs, for hulls outside the sector and for cubic elements.
pub fn hull_distance_bound(hull: &[DVec2], seg: &PathSeg) -> Option<f64> {
    match seg {
        PathSeg::Line(l) => Some(segment_hull_bound(l, hull)),
        PathSeg::Arc(a) if a.sweep.abs() <= std::f64::consts::PI => {
            arc_hull_bound(a.center, a.radius, a.p0(), a.p1(), a.sweep > 0.0, hull, 0.0)
        }
        _ => None,
    }
}

/// The convex hull's corners of the piece [a, b] of `seg`: a line piece's ends; an arc
/// piece of sweep at most π/2 lies in the triangle of its ends and the meeting point of
/// its end tangents, at r / cos(φ/2) from the centre on the bisector. `None` for wider arc
/// pieces and for cubics.
fn piece_hull(seg: &PathSeg, a: f64, b: f64) -> Option<Vec<DVec2>> {
    match seg {
        PathSeg::Line(_) => Some(vec![seg.eval(a), seg.eval(b)]),
        PathSeg::Arc(arc) => {
            let sweep = (b - a) * arc.sweep;
            if sweep.is_nan() || sweep.abs() > std::f64::consts::FRAC_PI_2 {
                return None;
            }
            let mid = arc.start + (a + 0.5 * (b - a)) * arc.sweep;
            let apex = arc.center + DVec2::from_angle(mid) * (arc.radius / (0.5 * sweep).cos());
            Some(vec![seg.eval(a), apex, seg.eval(b)])
        }
        PathSeg::Cubic(_) => None,
    }
}

fn seg_distance(s: &PathSeg, p: DVec2) -> f64 {
    match s {
        PathSeg::Line(l) => l.distance(p),
        PathSeg::Arc(a) => a.distance(p),
        PathSeg::Cubic(c) => polyline_distance(&c.flatten(DISTANCE_FLATTEN), p),
    }
}

/// Distance from `p` to the polyline `pts`.
pub fn polyline_distance(pts: &[DVec2], p: DVec2) -> f64 {
    pts.windows(2)
        .map(|w| Line::new(w[0], w[1]).distance(p))
        .fold(f64::INFINITY, f64::min)
}

/// Upper bound on ‖C′(t)‖ for a cubic: 3 × the longest control-polygon leg (the hodograph
/// is a quadratic Bézier with control points 3(P_{i+1} − P_i), inside their convex hull).
pub fn speed_bound(c: &CubicBez) -> f64 {
    3.0 * (c.p1 - c.p0)
        .length()
        .max((c.p2 - c.p1).length())
        .max((c.p3 - c.p2).length())
}

/// Finest resolution the deviation bound refines to: pieces whose Lipschitz slack is below
/// `tol / BOUND_RESOLUTION` are not split further.
const BOUND_RESOLUTION: f64 = 64.0;

/// Work bound of [`max_deviation`]: at most this many pieces are examined in each of its
/// two directions (curve to chain, chain to curve). Bisection down to the resolution
/// `tol / BOUND_RESOLUTION` needs up to about 6·L/tol pieces to prove a fit (L the
/// curve's length; the speed bound of a piece is about 3× its length and must drop to
/// 2·tol), which an ordinary fit (L/tol ≲ 10⁵) stays inside; a cubic very long against `tol` runs out instead of hanging, and the bound
/// is then unproven ([`f64::INFINITY`]), so [`fit_cubic`] splits the cubic and tries again
/// on halves (down to `MAX_DEPTH`).
pub const MAX_BOUND_PIECES: usize = 1 << 20;

/// Decides whether the Hausdorff distance between the cubic `c` and the chain `segs` is at
/// most `tol`: a result ≤ `tol` is a guaranteed upper bound of that distance (refined until
/// it proves `≤ tol` or reaches a resolution of `tol / BOUND_RESOLUTION`); a result > `tol`
/// means it is not proven: either a point of one curve lies farther than `tol` from the
/// other (the result is then that point's distance, a lower bound, and the refinement stops
/// there), or the resolution bound exceeds `tol`, or [`f64::INFINITY`] when `tol` is not a
/// positive finite number or the refinement needs more than [`MAX_BOUND_PIECES`] pieces.
///
/// Curve to chain: f(s) = dist(C(s), chain) is Lipschitz with constant M = speed bound of
/// the sub-cubic on [a, b] (reparametrised to [0, 1]), so on that piece
/// f ≤ min(f(a) + M s, f(b) + M (1 − s)) ≤ (f(a) + f(b) + M) / 2; pieces are bisected
/// until the bound holds. Chain to curve: the same on each line or arc against a flattening
/// of the curve within tol/8 (distance to a set is 1-Lipschitz along the arc length L:
/// bound (g(a) + g(b) + L)/2 + tol/8).
pub fn max_deviation(c: &CubicBez, segs: &[PathSeg], tol: f64) -> f64 {
    max_deviation_within(c, segs, tol, MAX_BOUND_PIECES)
}

/// [`max_deviation`] with at most `budget` pieces in each direction.
fn max_deviation_within(c: &CubicBez, segs: &[PathSeg], tol: f64, budget: usize) -> f64 {
    let dist = |p: DVec2| {
        segs.iter()
            .map(|s| seg_distance(s, p))
            .fold(f64::INFINITY, f64::min)
    };
    if !(tol > 0.0 && tol.is_finite()) {
        return f64::INFINITY;
    }
    let floor = tol / BOUND_RESOLUTION;
    // A chain that misses the curve mostly misses it at a few evenly spread points: those
    // are tried before the bisection, which would first go deep into one half.
    if let Some(far) = (1..PRE_SAMPLES)
        .map(|i| dist(c.eval(i as f64 / PRE_SAMPLES as f64)))
        .find(|&d| d > tol)
    {
        return far;
    }
    // Curve to chain, by adaptive bisection on the parameter.
    let mut worst: f64 = 0.0;
    let mut stack = vec![(0.0, 1.0, dist(c.p0), dist(c.p3))];
    let mut pieces = 0usize;
    while let Some((a, b, fa, fb)) = stack.pop() {
        pieces += 1;
        if pieces > budget {
            return f64::INFINITY;
        }
        // A point of the curve farther than tol from the chain: not within tol.
        if fa.max(fb) > tol {
            return fa.max(fb);
        }
        let sub = c.subsegment(a, b);
        let m = speed_bound(&sub);
        let mut bound = 0.5 * (fa + fb + m);
        if bound > tol {
            let hull = sub.points();
            bound = segs
                .iter()
                .filter_map(|s| hull_distance_bound(&hull, s))
                .fold(bound, f64::min);
        }
        if bound <= tol || m <= floor {
            worst = worst.max(bound);
        } else {
            let mid = 0.5 * (a + b);
            let fm = dist(c.eval(mid));
            stack.push((a, mid, fa, fm));
            stack.push((mid, b, fm, fb));
        }
    }
    // Chain to curve.
    let flat = c.flatten(tol / 8.0);
    // A chord whose box lies more than tol from a piece's hull box bounds the piece's
    // distance by more than tol: it cannot prove the piece, so only chords near it are
    // tried (the bound stays the minimum of bounds, each valid on its own).
    let chord_boxes: Vec<Aabb> = (flat.windows(2))
        .map(|w| Aabb::from_corners(w[0], w[1]))
        .collect();
    // The distance to the flattening, chord by chord, skipping a chord whose box is no
    // nearer than the nearest chord so far (the same minimum as `polyline_distance`);
    // the scan starts at the chord nearest the previous point, which the bisection keeps
    // close.
    let hint = std::cell::Cell::new(0usize);
    let gdist = |p: DVec2| {
        let n = chord_boxes.len();
        let mut best = f64::INFINITY;
        let mut at = hint.get();
        for k in 0..n {
            let i = (hint.get() + k) % n;
            if chord_boxes[i].distance_squared(p) >= best * best {
                continue;
            }
            let d = Line::new(flat[i], flat[i + 1]).distance(p);
            if d < best {
                best = d;
                at = i;
            }
        }
        hint.set(at);
        best + tol / 8.0
    };
    for s in segs {
        let len = s.length(LENGTH_ACCURACY);
        let mut stack = vec![(0.0, 1.0, gdist(s.eval(0.0)), gdist(s.eval(1.0)))];
        let mut pieces = 0usize;
        while let Some((a, b, ga, gb)) = stack.pop() {
            pieces += 1;
            if pieces > budget {
                return f64::INFINITY;
            }
            // g overestimates the distance to the curve by at most tol/4 (the flattening's
            // tol/8 both ways): a point of the chain farther than tol from the curve.
            let lower = ga.max(gb) - 0.25 * tol;
            if lower > tol {
                return lower;
            }
            let l = (b - a) * len;
            let mut bound = 0.5 * (ga + gb + l);
            if bound > tol
                && let Some(hull) = piece_hull(s, a, b)
            {
                let near = Aabb::from_points(&hull).grow(tol);
                bound = flat
                    .windows(2)
                    .zip(&chord_boxes)
                    .filter(|(_, b)| b.intersects(&near))
                    .filter_map(|(w, _)| {
                        hull_distance_bound(&hull, &PathSeg::Line(Line::new(w[0], w[1])))
                    })
                    .map(|d| d + tol / 8.0)
                    .fold(bound, f64::min);
            }
            if bound <= tol || l <= floor {
                worst = worst.max(bound);
            } else {
                let mid = 0.5 * (a + b);
                let gm = gdist(s.eval(mid));
                stack.push((a, mid, ga, gm));
                stack.push((mid, b, gm, gb));
            }
        }
    }
    worst
}

fn unit_tangent_start(c: &CubicBez) -> Option<DVec2> {
    [c.p1 - c.p0, c.p2 - c.p0, c.p3 - c.p0]
        .into_iter()
        .find(|v| v.length_squared() > 0.0)
        .map(DVec2::normalize)
}

fn unit_tangent_end(c: &CubicBez) -> Option<DVec2> {
    [c.p3 - c.p2, c.p3 - c.p1, c.p3 - c.p0]
        .into_iter()
        .find(|v| v.length_squared() > 0.0)
        .map(DVec2::normalize)
}

/// Fit the cubic `c` by lines and arcs within `tol` (Hausdorff distance, verified as in the
/// module docs). Consecutive pieces are G1 except where the cubic itself turns sharply
/// (zero-length tangent); the chain starts at c.p0 and ends at c.p3 exactly.
pub fn fit_cubic(c: &CubicBez, tol: f64) -> Vec<PathSeg> {
    let mut out = Vec::new();
    fit_rec(c, tol, 0, &mut out);
    out
}

fn fit_rec(c: &CubicBez, tol: f64, depth: u32, out: &mut Vec<PathSeg>) {
    // A flat piece is a line.
    if 0.75 * c.flatness() <= tol * 0.5 {
        out.push(PathSeg::Line(Line::new(c.p0, c.p3)));
        return;
    }
    if let (Some(t0), Some(t1)) = (unit_tangent_start(c), unit_tangent_end(c))
        && let Some(pair) = biarc(c.p0, t0, c.p3, t1, tol)
        && (depth >= MAX_DEPTH || max_deviation(c, &pair, tol) <= tol)
    {
        out.extend_from_slice(&pair);
        return;
    }
    if depth >= MAX_DEPTH {
        out.push(PathSeg::Line(Line::new(c.p0, c.p3)));
        return;
    }
    let (a, b) = c.split(0.5);
    fit_rec(&a, tol, depth + 1, out);
    fit_rec(&b, tol, depth + 1, out);
}

/// The standard cubic of a quarter circle of radius `r` about the origin (k = 0.5523; it
/// deviates from the circle by 2.7e-4 r).
#[cfg(test)]
fn quarter_circle(r: f64) -> CubicBez {
    let k = 0.552_284_749_8;
    CubicBez::new(
        DVec2::new(r, 0.0),
        DVec2::new(r, k * r),
        DVec2::new(k * r, r),
        DVec2::new(0.0, r),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn pt() -> impl Strategy<Value = DVec2> {
        (-20.0f64..20.0, -20.0f64..20.0).prop_map(|(x, y)| DVec2::new(x, y))
    }

    /// Independent dense check: distance of many curve points to the chain.
    fn dense_error(c: &CubicBez, segs: &[PathSeg]) -> f64 {
        (0..=2000)
            .map(|i| {
                let p = c.eval(i as f64 / 2000.0);
                segs.iter()
                    .map(|s| seg_distance(s, p))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]
        #[test]
        fn biarc_error_within_tolerance(a in pt(), b in pt(), c in pt(), d in pt(), tol in 0.01f64..0.2) {
            let cub = CubicBez::new(a, b, c, d);
            let segs = fit_cubic(&cub, tol);
            prop_assert!(!segs.is_empty());
            prop_assert!((segs[0].start() - a).length() < 1e-9);
            prop_assert!((segs[segs.len() - 1].end() - d).length() < 1e-9);
            // Connected chain.
            for w in segs.windows(2) {
                prop_assert!((w[0].end() - w[1].start()).length() < 1e-9);
            }
            prop_assert!(dense_error(&cub, &segs) <= tol * (1.0 + 1e-9));
        }
    }

    #[test]
    fn biarc_joints_are_g1() {
        let cub = CubicBez::new(
            DVec2::new(0.0, 0.0),
            DVec2::new(10.0, 20.0),
            DVec2::new(20.0, -20.0),
            DVec2::new(30.0, 0.0),
        );
        let segs = fit_cubic(&cub, 0.01);
        let tangent = |s: &PathSeg, t: f64| match s {
            PathSeg::Line(l) => (l.p1 - l.p0).normalize(),
            PathSeg::Arc(a) => a.tangent(t),
            PathSeg::Cubic(c) => c.deriv(t).normalize(),
        };
        for w in segs.windows(2) {
            let t0 = tangent(&w[0], 1.0);
            let t1 = tangent(&w[1], 0.0);
            assert!(
                t0.dot(t1) > 1.0 - 1e-6,
                "kink between {:?} and {:?}",
                w[0],
                w[1]
            );
        }
    }

    #[test]
    fn quarter_circle_bezier_fits_with_one_biarc() {
        // The standard quarter-circle cubic (k = 0.5523) deviates from the circle by 2.7e-4 r;
        // with tolerance 1e-3 r one biarc must do.
        let r = 10.0;
        let c = quarter_circle(r);
        let segs = fit_cubic(&c, 1e-2);
        assert_eq!(segs.len(), 2);
        for s in &segs {
            match s {
                PathSeg::Arc(a) => assert!((a.radius - r).abs() < 0.05, "radius {}", a.radius),
                other => panic!("expected arcs, got {other:?}"),
            }
        }
    }
}

#[cfg(test)]
mod bound_tests {
    use super::*;

    #[test]
    fn deviation_bound_is_unproven_without_a_usable_tolerance_or_budget() {
        let c = CubicBez::new(
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(3.0, 0.0),
        );
        let chord = [PathSeg::Line(Line::new(c.p0, c.p3))];
        for tol in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(max_deviation(&c, &chord, tol), f64::INFINITY, "{tol}");
        }
        // A straight cubic on its own chord: its hull lies on the line, so even 1e-12 is
        // proven at once (the first-order bound alone would need ~10¹² pieces).
        let straight = CubicBez::new(
            DVec2::ZERO,
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(3.0, 0.0),
        );
        let line = [PathSeg::Line(Line::new(straight.p0, straight.p3))];
        assert!(max_deviation(&straight, &line, 1e-12) <= 1e-12);
        assert!(max_deviation(&straight, &line, 1e-3) <= 1e-3);
        // A budget too small for the refinement ends it, unproven.
        let fit = fit_cubic(&c, 1e-3);
        assert!(max_deviation_within(&c, &fit, 1e-3, MAX_BOUND_PIECES) <= 1e-3);
        assert_eq!(max_deviation_within(&c, &fit, 1e-3, 2), f64::INFINITY);
        // An ordinary request ends at the first point found farther than tol: a lower bound
        // of the true distance 1.5, above tol.
        let d = max_deviation(&c, &chord, 1e-3);
        assert!(d > 1e-3 && d <= 1.5 + 1e-12, "{d}");
        // A chain within tol gets a proven bound ≤ tol.
        let fit = fit_cubic(&c, 1e-3);
        assert!(max_deviation(&c, &fit, 1e-3) <= 1e-3);
        // The fit still ends (split down to MAX_DEPTH), with pieces joined end to end.
        let segs = fit_cubic(&c, 0.0);
        assert!(!segs.is_empty() && segs.len() <= 2 << MAX_DEPTH);
        assert!(segs[0].start().distance(c.p0) < 1e-9);
        assert!(segs[segs.len() - 1].end().distance(c.p3) < 1e-9);
        for w in segs.windows(2) {
            assert!(w[0].end().distance(w[1].start()) < 1e-9);
        }
    }
}

#[cfg(test)]
mod hull_tests {
    use super::*;

    /// The quarter-circle cubic against its biarc at 1e-2: the first-order bound alone
    /// needs pieces about tol long (a budget of 4096 pieces per direction, 2048 is not
    /// enough); with the hull bound 512 prove it.
    #[test]
    fn hull_bound_proves_a_fit_with_few_pieces() {
        let c = quarter_circle(10.0);
        let fit = fit_cubic(&c, 1e-2);
        assert!(max_deviation_within(&c, &fit, 1e-2, 512) <= 1e-2);
        // A fit of a wavy cubic, both directions.
        let w = CubicBez::new(
            DVec2::new(0.0, 0.0),
            DVec2::new(10.0, 20.0),
            DVec2::new(20.0, -20.0),
            DVec2::new(30.0, 0.0),
        );
        for tol in [1e-2, 1e-3] {
            let fit = fit_cubic(&w, tol);
            let whole = max_deviation(&w, &fit, tol);
            assert!(whole <= tol, "{whole}");
        }
    }
}
