//! The paths of a `line` operation: what a drawing's line is, as lines and arcs the tool
//! follows once (no offset: the tool centre is on the line).
//!
//! A stroke's line is its spine q(t) = Σ Nᵢ,ₚ(t) pᵢ: up to degree 3 its knot spans are
//! cubic Béziers ([`crate::dbsc::spine::spine_cubics`]) fitted by biarcs within the
//! tolerance ([`super::biarc::fit_cubic`], the fit every other cut uses); above degree 3 it
//! is flattened within the tolerance ([`crate::dbsc::flatten::flatten_spine`]). In a line
//! cut, a span whose fit needs an arc no larger than [`MIN_ARC_RADIUS_TOLS`] tolerances
//! (where the spine turns round within the tolerance: a pen that sets off backwards) is
//! flattened within the tolerance instead. An open spine stays open, a closed stroke's
//! spine is a closed cut.

use super::biarc::fit_cubic;
use super::region::pline_from_path;
use crate::dbsc::DiskBSpline;
use crate::geom::interop::path_from_pline;
use crate::geom::{CubicBez, DVec2, Line, Path, PathSeg};
use cavalier_contours::polyline::Polyline;

/// Smallest radius of an arc in a line cut, in tolerances. Near a cusp the biarc fit
/// halves the span until its arcs are as small as the tolerance or smaller (radius 3·10⁻⁴
/// mm at 0.01 mm); such an arc lies within its radius of its chord, so it carries no shape
/// the tolerance can tell, and the emitters refuse arcs whose radius is within their own
/// tolerance (0.1·tol, [`crate::emit::geometry::validate`]).
pub const MIN_ARC_RADIUS_TOLS: f64 = 1.0;

/// The spine of `c` as a polyline with arcs (bulges), within `tol` of q(t); `None` above
/// degree 3 (its spans are no cubics).
pub fn spine_pline(c: &DiskBSpline, tol: f64) -> Option<Polyline<f64>> {
    let cubics = crate::dbsc::spine::spine_cubics(c)?;
    Some(pline_from_path(&cubics, tol))
}

/// [`spine_pline`] for a line cut: every arc has a radius above
/// [`MIN_ARC_RADIUS_TOLS`]·`tol` ([`span_segments`]).
fn line_pline(c: &DiskBSpline, tol: f64) -> Option<Polyline<f64>> {
    let cubics = crate::dbsc::spine::spine_cubics(c)?;
    let segs = (cubics.segs.iter())
        .flat_map(|s| match s {
            PathSeg::Cubic(b) => span_segments(b, tol),
            other => vec![*other],
        })
        .collect();
    Some(pline_from_path(&Path::new(segs, cubics.closed), tol))
}

/// One cubic span of a spine as lines and arcs within `tol`: its biarc fit ([`fit_cubic`]),
/// or, where that fit has an arc of radius at most [`MIN_ARC_RADIUS_TOLS`]·`tol`, the span
/// flattened within `tol` ([`CubicBez::flatten`]) as lines.
fn span_segments(b: &CubicBez, tol: f64) -> Vec<PathSeg> {
    let fit = fit_cubic(b, tol);
    let tiny = |s: &PathSeg| matches!(s, PathSeg::Arc(a) if a.radius <= MIN_ARC_RADIUS_TOLS * tol);
    if !fit.iter().any(tiny) {
        return fit;
    }
    (b.flatten(tol).windows(2))
        .filter(|w| w[0] != w[1])
        .map(|w| PathSeg::Line(Line::new(w[0], w[1])))
        .collect()
}

/// The spine of `c` as lines and arcs within `tol` (module docs), open or closed as `c` is,
/// no arc of radius [`MIN_ARC_RADIUS_TOLS`]·`tol` or less: the path of a line cut.
pub fn spine_path(c: &DiskBSpline, tol: f64) -> Path {
    match line_pline(c, tol) {
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
    use crate::geom::roots::{Golden, Tie};
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
        let (a, b) = (t_at(k.saturating_sub(1)), t_at((k + 1).min(n)));
        let g = Golden::new(-1.0, 80, Tie::Right).min(|t| c.center(t).distance(p), a, b);
        c.center(g.mid()).distance(p)
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

    /// A span whose first control point lies behind its start (the pen sets off backwards
    /// and turns round within 0.01 mm: a span of a real hairline drawing, relative to its
    /// start): the plain biarc fit turns there on a half circle of radius 7·10⁻⁴, which the
    /// emitter refused ("arc radius … is not positive"); the line cut has no arc as small
    /// as the tolerance, stays within the tolerance of the spine (dense samples, golden
    /// section) and ends on the spine's ends. The same at ten times the size and tolerance.
    #[test]
    fn spines_turning_round_get_no_arcs_below_the_tolerance() {
        let span = [
            (0.0, 0.0),
            (-0.008_468_426_601, -0.002_222_333_610),
            (0.034_333_007_360, 0.005_870_514_453),
            (0.065_126_046_023, 0.012_025_866_128),
        ];
        for k in [1.0, 10.0] {
            let tol = 0.01 * k;
            let pts: Vec<(f64, f64)> = span.iter().map(|&(x, y)| (k * x, k * y)).collect();
            let c = curve(3, false, &pts);
            let radius = |s: &PathSeg| match s {
                PathSeg::Arc(a) => a.radius,
                _ => f64::INFINITY,
            };
            let cubics = crate::dbsc::spine::spine_cubics(&c).unwrap();
            let plain = (cubics.segs.iter())
                .flat_map(|s| match s {
                    PathSeg::Cubic(b) => fit_cubic(b, tol),
                    other => vec![*other],
                })
                .map(|s| radius(&s))
                .fold(f64::INFINITY, f64::min);
            assert!(plain <= 0.1 * tol, "plain fit: smallest arc {plain}");
            let p = spine_path(&c, tol);
            let smallest = p.segs.iter().map(radius).fold(f64::INFINITY, f64::min);
            assert!(smallest > tol, "smallest arc {smallest}");
            for q in p.flatten(tol * 0.01) {
                let d = distance_to_spine(&c, q);
                assert!(d <= tol * (1.0 + 1e-6), "{q} is {d} from the spine");
            }
            let (lo, hi) = c.domain();
            assert!(p.start().unwrap().distance(c.center(lo)) <= 1e-9);
            assert!(p.end().unwrap().distance(c.center(hi)) <= 1e-9);
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
