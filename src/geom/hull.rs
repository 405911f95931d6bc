//! Deviation bounds of a convex hull against a circle arc or a segment: if a curve lies in
//! the convex hull of a few points, the largest distance from the curve to the arc or
//! segment is at most the bound computed from those points alone. Used to prove fitting
//! tolerances (biarcs of cubics in [`crate::toolpath::biarc`], merged arcs of exact MAT
//! offsets in [`crate::skin::mat_offset`]) with a handful of pieces where a Lipschitz
//! bound needs pieces about as short as the tolerance.
//!
//! Cost: O(n²) per bound for n hull points (n ≤ 6 here); `point_hull_distance` tests
//! O(n³) triangles only when the point lies within the points' diameter of one of them.

use super::{DVec2, Line, cross};

/// Distance from `o` to the convex hull of `pts` (any order, any count; ∞ for none): 0 when
/// `o` lies in a triangle of three of them (the hull is the union of those triangles), else
/// the least distance to a segment between two of them (the hull's edges are among those
/// segments, and every such segment lies in the hull).
///
/// The triangles are tested only when `o` may lie in the hull: every hull point lies within
/// the diameter L (the longest distance between two points) of every point, so when the
/// nearest point is farther than L the hull cannot hold `o`. Distances are compared squared
/// and one square root taken: √ is monotone and correctly rounded, so the value is the
/// least of the segment distances [`Line::distance`] gives, bit for bit.
#[cfg(test)]
pub fn point_hull_distance(o: DVec2, pts: &[DVec2]) -> f64 {
    point_hull_distance_sq(o, pts, nearest_and_diameter_sq(o, pts)).sqrt()
}

/// (min_i ‖pts_i − o‖², max_ij ‖pts_i − pts_j‖²): the squared distance to the nearest point
/// and the squared diameter of `pts` ((∞, 0) for none).
fn nearest_and_diameter_sq(o: DVec2, pts: &[DVec2]) -> (f64, f64) {
    let (mut m2, mut l2) = (f64::INFINITY, 0.0f64);
    for (i, p) in pts.iter().enumerate() {
        m2 = m2.min((*p - o).length_squared());
        for q in &pts[i + 1..] {
            l2 = l2.max((*q - *p).length_squared());
        }
    }
    (m2, l2)
}

/// The square of `point_hull_distance`, given `nearest_and_diameter_sq(o, pts)`.
fn point_hull_distance_sq(o: DVec2, pts: &[DVec2], (m2, l2): (f64, f64)) -> f64 {
    let n = pts.len();
    let inside = |a: DVec2, b: DVec2, c: DVec2| {
        let (x, y, z) = (
            cross(b - a, o - a),
            cross(c - b, o - b),
            cross(a - c, o - c),
        );
        (x >= 0.0 && y >= 0.0 && z >= 0.0) || (x <= 0.0 && y <= 0.0 && z <= 0.0)
    };
    let may_hold = m2 <= l2;
    let mut best = m2;
    for i in 0..n {
        for j in i + 1..n {
            let seg = Line::new(pts[i], pts[j]);
            best = best.min((seg.eval(seg.nearest_t(o)) - o).length_squared());
            if may_hold {
                for k in j + 1..n {
                    if inside(pts[i], pts[j], pts[k]) {
                        return 0.0;
                    }
                }
            }
        }
    }
    best
}

/// Bound of the distance from the hull of `pts` to the arc of centre `c` and radius `r`
/// from `p` to `q` (sweep below π, counter-clockwise when `ccw`), or `None` when a point
/// lies outside the arc's sector by more than `contain_eps`·r² (in cross product, i.e. an
/// angle of about `contain_eps`) or the bound reaches the centre.
///
/// In the sector the nearest point of the arc is that of its circle, so the distance is
/// | |x − c| − r | ≤ max(max_v |v − c| − r, r − dist(c, hull)): |x − c| is convex (its
/// maximum over the hull is at a point) and at least the distance from c to the hull
/// (`point_hull_distance`). (A cheaper lower bound of that distance, √(m² − (L/2)²) from
/// the nearest point m and the longest edge L, holds only when c lies outside the hull:
/// for c at the centroid of an equilateral triangle it gives 0.29·L instead of 0.)
pub fn arc_hull_bound(
    c: DVec2,
    r: f64,
    p: DVec2,
    q: DVec2,
    ccw: bool,
    pts: &[DVec2],
    contain_eps: f64,
) -> Option<f64> {
    if r.is_nan() || r <= 0.0 || pts.is_empty() {
        return None;
    }
    let sig = if ccw { 1.0 } else { -1.0 };
    let (ra, rb) = (p - c, q - c);
    let eps = contain_eps * r * r;
    let mut far2 = 0.0f64;
    for w in pts {
        let x = *w - c;
        if sig * cross(ra, x) < -eps || sig * cross(x, rb) < -eps {
            return None;
        }
        far2 = far2.max(x.length_squared());
    }
    // max_v (‖v − c‖ − r), √ being monotone.
    let far = far2.sqrt() - r;
    // The inner term r − dist(c, hull) matters only above `far`. With the nearest point at
    // m > L (the diameter) c lies outside the hull and its nearest hull point is on an edge
    // between two points, so dist ≥ √(m² − (L/2)²) (see above): when r minus that is at
    // most `far`, the exact distance cannot change the result.
    let (m2, l2) = nearest_and_diameter_sq(c, pts);
    let lower_dist = if m2 > l2 {
        (m2 - 0.25 * l2).sqrt()
    } else {
        0.0
    };
    let inner = if r - lower_dist <= far {
        far
    } else {
        r - point_hull_distance_sq(c, pts, (m2, l2)).sqrt()
    };
    // The band of half-width `bound` around the circle must not reach the centre.
    Some(far.max(inner).max(0.0)).filter(|&e| e < r)
}

/// Bound of the distance from the hull of `pts` to the segment `seg`: the distance to a
/// segment is convex, so its maximum over the hull is at one of the points.
pub fn segment_hull_bound(seg: &Line, pts: &[DVec2]) -> f64 {
    pts.iter().map(|w| seg.distance(*w)).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Arc;
    use proptest::prelude::*;

    fn pt() -> impl Strategy<Value = DVec2> {
        (-5.0f64..5.0, -5.0f64..5.0).prop_map(|(x, y)| DVec2::new(x, y))
    }

    #[test]
    fn point_hull_distance_matches_closed_forms() {
        let sq = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        assert_eq!(point_hull_distance(DVec2::new(1.0, 1.0), &sq), 0.0);
        // The same square listed out of order (a bow tie as a polygon).
        let mixed = [sq[0], sq[2], sq[1], sq[3]];
        assert_eq!(point_hull_distance(DVec2::new(1.0, 1.9), &mixed), 0.0);
        assert!((point_hull_distance(DVec2::new(5.0, 1.0), &sq) - 3.0).abs() < 1e-12);
        assert!((point_hull_distance(DVec2::new(3.0, 3.0), &sq) - 2f64.sqrt()).abs() < 1e-12);
        let seg = [DVec2::new(0.0, 0.0), DVec2::new(4.0, 0.0)];
        assert!((point_hull_distance(DVec2::new(1.0, -2.0), &seg) - 2.0).abs() < 1e-12);
        assert!(
            (point_hull_distance(DVec2::new(7.0, 4.0), &seg[..1]) - 65f64.sqrt()).abs() < 1e-12
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// The distance to the hull against geo's: its convex hull of the points and its
        /// Euclidean distance from the point to that polygon (0 inside).
        #[test]
        fn point_hull_distance_matches_geo(pts in proptest::collection::vec(pt(), 3..=6), o in pt()) {
            use geo::{ConvexHull, Distance, Euclidean, MultiPoint, Point};
            let mp: MultiPoint<f64> = pts.iter().map(|p| Point::new(p.x, p.y)).collect();
            let hull = mp.convex_hull();
            let want = Euclidean.distance(&Point::new(o.x, o.y), &hull);
            let got = point_hull_distance(o, &pts);
            prop_assert!((got - want).abs() <= 1e-9, "{got} vs geo {want}");
        }

        /// Where a bound is given, no point of the hull (the points, and random convex
        /// combinations of them) is farther from the arc or segment than it, by the arc's
        /// and segment's own distances (nearest point with the angle test).
        #[test]
        fn bounds_hold_on_the_hull(
            pts in proptest::collection::vec(pt(), 1..=6),
            c in pt(), r in 0.5f64..8.0, a in -3.2f64..3.2, sweep in -3.1f64..3.1,
            weights in proptest::collection::vec(proptest::collection::vec(0.0f64..1.0, 6), 64),
        ) {
            let arc = Arc::new(c, r, a, sweep);
            let line = Line::new(arc.p0(), arc.p1());
            let arc_b = arc_hull_bound(c, r, arc.p0(), arc.p1(), sweep > 0.0, &pts, 0.0);
            let seg_b = segment_hull_bound(&line, &pts);
            let mut xs: Vec<DVec2> = pts.clone();
            for w in &weights {
                let total: f64 = w[..pts.len()].iter().sum();
                if total > 0.0 {
                    xs.push(pts.iter().zip(w).fold(DVec2::ZERO, |s, (v, k)| s + *v * (*k / total)));
                }
            }
            for x in xs {
                if let Some(b) = arc_b {
                    prop_assert!(arc.distance(x) <= b + 1e-9, "{} > {b}", arc.distance(x));
                }
                prop_assert!(line.distance(x) <= seg_b + 1e-9);
            }
        }
    }
}
