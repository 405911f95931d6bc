//! The paths of a `line` operation: what a drawing's line is, as lines and arcs the tool
//! follows once (no offset: the tool centre is on the line).
//!
//! A stroke's line is its spine q(t) = Σ Nᵢ,ₚ(t) pᵢ: up to degree 3 its knot spans are
//! cubic Béziers ([`crate::dbsc::spine::spine_cubics`]) fitted by biarcs within the
//! tolerance ([`super::biarc::fit_cubic`], the fit every other cut uses); above degree 3 it
//! is flattened within the tolerance ([`crate::dbsc::flatten::flatten_spine`]). An open
//! spine stays open, a closed stroke's spine is a closed cut.

use super::region::{path_from_pline, pline_from_path};
use crate::dbsc::DiskBSpline;
use crate::geom::{DVec2, Path};
use cavalier_contours::polyline::Polyline;

/// The spine of `c` as a polyline with arcs (bulges), within `tol` of q(t); `None` above
/// degree 3 (its spans are no cubics).
pub fn spine_pline(c: &DiskBSpline, tol: f64) -> Option<Polyline<f64>> {
    let cubics = crate::dbsc::spine::spine_cubics(c)?;
    Some(pline_from_path(&cubics, tol))
}

/// The spine of `c` as lines and arcs within `tol` (module docs), open or closed as `c` is.
pub fn spine_path(c: &DiskBSpline, tol: f64) -> Path {
    match spine_pline(c, tol) {
        Some(pl) => path_from_pline(&pl),
        None => Path::polyline(&crate::dbsc::flatten::flatten_spine(c, tol), c.is_closed()),
    }
}

/// The polyline through `points` (a shape's contour, a circle sequence's centres), closed
/// when `closed`, with repeated consecutive points dropped; `None` with fewer than two
/// distinct points.
pub fn polyline_path(points: &[DVec2], closed: bool) -> Option<Path> {
    let mut pts: Vec<DVec2> = Vec::with_capacity(points.len());
    for &p in points {
        if pts.last() != Some(&p) {
            pts.push(p);
        }
    }
    if closed && pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    (pts.len() >= 2).then(|| Path::polyline(&pts, closed && pts.len() >= 3))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Circle, PathSeg};

    fn curve(degree: usize, closed: bool, pts: &[(f64, f64)]) -> DiskBSpline {
        let disks: Vec<Circle> = pts
            .iter()
            .map(|&(x, y)| Circle::new(DVec2::new(x, y), 0.1))
            .collect();
        if closed {
            DiskBSpline::closed(degree, &disks, None).unwrap()
        } else {
            DiskBSpline::open(degree, &disks, None).unwrap()
        }
    }

    /// Distance from `p` to the spine, by dense sampling of q(t) (a second method) refined
    /// by golden-section search on the best bracket.
    fn distance_to_spine(c: &DiskBSpline, p: DVec2) -> f64 {
        let (lo, hi) = c.domain();
        let n = 4000;
        let t_at = |k: usize| lo + (hi - lo) * k as f64 / n as f64;
        let k = (0..=n)
            .min_by(|&a, &b| {
                let da = c.center(t_at(a)).distance(p);
                let db = c.center(t_at(b)).distance(p);
                da.total_cmp(&db)
            })
            .unwrap();
        let (mut a, mut b) = (t_at(k.saturating_sub(1)), t_at((k + 1).min(n)));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..80 {
            let x1 = b - g * (b - a);
            let x2 = a + g * (b - a);
            if c.center(x1).distance(p) < c.center(x2).distance(p) {
                b = x2;
            } else {
                a = x1;
            }
        }
        c.center(0.5 * (a + b)).distance(p)
    }

    /// The path stays within the tolerance of the spine (every flattened point), starts and
    /// ends on the spine's ends, is open or closed as the stroke is, uses arcs for a
    /// curved cubic spine, and its length matches the spine's arc length (Simpson's rule on
    /// ‖q′‖ as the independent measure) within the fit's error.
    #[test]
    fn spine_path_follows_the_spine_within_tolerance() {
        let tol = 1e-3;
        for (degree, closed) in [(3, false), (2, false), (3, true), (5, false)] {
            let c = curve(
                degree,
                closed,
                &[
                    (0.0, 0.0),
                    (10.0, 8.0),
                    (20.0, -4.0),
                    (30.0, 6.0),
                    (36.0, 0.0),
                    (40.0, 9.0),
                ],
            );
            let p = spine_path(&c, tol);
            assert_eq!(p.closed, closed);
            for q in p.flatten(tol * 0.1) {
                let d = distance_to_spine(&c, q);
                assert!(d <= 1.05 * tol, "degree {degree}: {d} from the spine");
            }
            let (lo, hi) = c.domain();
            if !closed {
                assert!(p.start().unwrap().distance(c.center(lo)) <= 1e-9);
                assert!(p.end().unwrap().distance(c.center(hi)) <= 1e-9);
            }
            if degree <= 3 {
                assert!(p.segs.iter().any(|s| matches!(s, PathSeg::Arc(_))));
            }
            // Simpson's rule on |q'| (composite, 20 000 intervals).
            let n = 20_000;
            let h = (hi - lo) / n as f64;
            let speed = |t: f64| c.derivs(t, 1)[1].0.length();
            let mut s = speed(lo) + speed(hi);
            for k in 1..n {
                s += if k % 2 == 1 { 4.0 } else { 2.0 } * speed(lo + k as f64 * h);
            }
            let arclen = s * h / 3.0;
            let len = p.length(tol * 0.01);
            assert!(
                (len - arclen).abs() <= 1e-3 * arclen,
                "degree {degree}: path {len} vs spine {arclen}"
            );
        }
    }

    #[test]
    fn polylines_drop_repeats_and_need_two_points() {
        let a = DVec2::ZERO;
        let b = DVec2::new(1.0, 0.0);
        let c = DVec2::new(1.0, 1.0);
        assert!(polyline_path(&[a, a], false).is_none());
        let p = polyline_path(&[a, b, b, c, a], true).unwrap();
        assert!(p.closed);
        assert_eq!(p.segs.len(), 3);
        let open = polyline_path(&[a, b, c], false).unwrap();
        assert!(!open.closed);
        assert_eq!(open.segs.len(), 2);
    }
}
