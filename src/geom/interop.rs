//! Conversions between geom's types (glam's [`DVec2`], [`Aabb`], [`Path`]) and those of the
//! crates geometry is handed to: cavalier_contours (`Vector2`, `Polyline`: offsets,
//! winding numbers), geo (`Coord`, `LineString`, `Polygon`: polygon booleans), rstar
//! (`AABB`, `Rectangle`: R-trees) and, with the `svg-import` feature, kurbo (`Point`: SVG
//! flattening). Every conversion is exact (coordinates copied, bulges
//! b = tan(θ/4) of cavalier's arcs turned into [`Arc`]s and back), so a value taken there
//! and back is the value itself.

use super::{Aabb, Arc, DVec2, Line, Path, PathSeg};
use cavalier_contours::core::math::Vector2;
use cavalier_contours::polyline::{
    PlineCreation, PlineSource, PlineSourceMut, PlineVertex, Polyline,
};

/// Largest arc sweep per polyline vertex: cavalier_contours keeps |bulge| ≤ 1 (a half
/// circle), so longer arcs are split.
const MAX_SWEEP_PER_VERTEX: f64 = std::f64::consts::PI;

/// A point as cavalier_contours' vector.
#[inline]
pub fn vector2(p: DVec2) -> Vector2<f64> {
    Vector2::new(p.x, p.y)
}

/// The position of a polyline vertex (its bulge dropped).
#[must_use]
#[inline]
pub fn vertex_point(v: &PlineVertex<f64>) -> DVec2 {
    DVec2::new(v.x, v.y)
}

/// A point as geo's coordinate.
#[must_use]
#[inline]
pub fn coord(p: DVec2) -> geo::Coord<f64> {
    geo::Coord { x: p.x, y: p.y }
}

/// A geo coordinate as a point.
#[must_use]
#[inline]
pub fn from_coord(c: geo::Coord<f64>) -> DVec2 {
    DVec2::new(c.x, c.y)
}

/// A closed ring (no repeated end point) as geo's closed line string (first point repeated
/// at the end, as geo's polygons hold their rings).
#[must_use]
pub fn ring_line_string(ring: impl IntoIterator<Item = DVec2>) -> geo::LineString<f64> {
    let mut pts: Vec<geo::Coord<f64>> = ring.into_iter().map(coord).collect();
    if let Some(&f) = pts.first() {
        pts.push(f);
    }
    geo::LineString::new(pts)
}

/// The points of a geo line string, the closing repeat of a closed one (first point equal
/// to the last, more than one point) dropped.
#[must_use]
pub fn ring_points(ls: &geo::LineString<f64>) -> Vec<DVec2> {
    let mut pts: Vec<DVec2> = ls.coords().map(|&c| from_coord(c)).collect();
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    pts
}

/// A box as rstar's envelope.
#[must_use]
#[inline]
pub fn envelope(b: Aabb) -> rstar::AABB<[f64; 2]> {
    rstar::AABB::from_corners(b.min.to_array(), b.max.to_array())
}

/// A box as rstar's rectangle primitive (an R-tree entry).
#[must_use]
#[inline]
pub fn rectangle(b: Aabb) -> rstar::primitives::Rectangle<[f64; 2]> {
    rstar::primitives::Rectangle::from_corners(b.min.to_array(), b.max.to_array())
}

/// Append the line or arc `seg` (starting where the polyline currently ends) as vertices:
/// a line as its start vertex (bulge 0), an arc as n = ⌈|sweep|/π⌉ vertices of bulge
/// tan(sweep/(4n)). Cubics append nothing (they become arcs first: `fit_cubic` in the
/// toolpath stage).
pub fn push_line_or_arc(pl: &mut Polyline<f64>, seg: &PathSeg) {
    match seg {
        PathSeg::Line(l) => pl.add(l.p0.x, l.p0.y, 0.0),
        PathSeg::Arc(a) => {
            let n = (a.sweep.abs() / MAX_SWEEP_PER_VERTEX).ceil().max(1.0) as usize;
            let part = a.sweep / n as f64;
            let bulge = (part / 4.0).tan();
            for i in 0..n {
                let p = a.eval(i as f64 / n as f64);
                pl.add(p.x, p.y, bulge);
            }
        }
        PathSeg::Cubic(_) => {}
    }
}

/// A polyline through `points` (no arcs), closed or open.
#[must_use]
pub fn pline_from_points(points: &[DVec2], closed: bool) -> Polyline<f64> {
    let mut pl = Polyline::with_capacity(points.len(), closed);
    for p in points {
        pl.add(p.x, p.y, 0.0);
    }
    pl
}

/// The lines and arcs of a polyline as a path (zero-length segments dropped).
#[must_use]
pub fn path_from_pline(pl: &Polyline<f64>) -> Path {
    let mut segs = Vec::with_capacity(pl.vertex_count());
    for (v1, v2) in pl.iter_segments() {
        let (p0, p1) = (vertex_point(&v1), vertex_point(&v2));
        if p0 == p1 {
            continue;
        }
        if v1.bulge == 0.0 {
            segs.push(PathSeg::Line(Line::new(p0, p1)));
        } else {
            segs.push(PathSeg::Arc(Arc::from_bulge(p0, p1, v1.bulge)));
        }
    }
    Path::new(segs, pl.is_closed())
}

/// Points of a polyline within `tol` (arcs flattened by sagitta, [`Arc::flatten`]).
#[must_use]
pub fn flatten_pline(pl: &Polyline<f64>, tol: f64) -> Vec<DVec2> {
    path_from_pline(pl).flatten(tol)
}

/// A point as kurbo's point.
#[cfg(feature = "svg-import")]
#[must_use]
#[inline]
pub fn kurbo_point(p: DVec2) -> kurbo::Point {
    kurbo::Point::new(p.x, p.y)
}

/// A kurbo point as a point.
#[cfg(feature = "svg-import")]
#[must_use]
#[inline]
pub fn from_kurbo_point(p: kurbo::Point) -> DVec2 {
    DVec2::new(p.x, p.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A closed path of a line (length √2) and a three-quarter arc goes to a polyline (the arc split at
    /// π per vertex: two vertices of bulge tan(3π/16)) and back unchanged.
    #[test]
    fn lines_and_arcs_survive_the_round_trip() {
        let arc = Arc::new(DVec2::new(1.0, 1.0), 1.0, -PI / 2.0, 1.5 * PI);
        let line = Line::new(DVec2::new(0.0, 1.0), arc.p0());
        let path = Path::new(vec![PathSeg::Line(line), PathSeg::Arc(arc)], true);
        let mut pl = Polyline::new_closed();
        for s in &path.segs {
            push_line_or_arc(&mut pl, s);
        }
        assert_eq!(pl.vertex_count(), 3);
        assert!((pl.at(1).bulge - (3.0 * PI / 16.0).tan()).abs() < 1e-15);
        let back = path_from_pline(&pl);
        assert_eq!(back.segs.len(), 3);
        let total: f64 = back.segs.iter().map(|s| s.length(1e-9)).sum();
        assert!((total - (2f64.sqrt() + 1.5 * PI)).abs() < 1e-12, "{total}");
        for q in flatten_pline(&pl, 1e-4).iter().skip(1) {
            let on_arc = (q.distance(arc.center) - 1.0).abs() < 1e-12;
            assert!(on_arc || line.distance(*q) < 1e-12, "{q}");
        }
    }

    #[test]
    fn points_and_rings_round_trip() {
        let p = DVec2::new(1.5, -2.25);
        assert_eq!(vector2(p).x, p.x);
        assert_eq!(vector2(p).y, p.y);
        assert_eq!(from_coord(coord(p)), p);
        let ring = vec![DVec2::ZERO, DVec2::X, DVec2::ONE];
        let ls = ring_line_string(ring.iter().copied());
        assert_eq!(ls.0.len(), 4);
        assert_eq!(ring_points(&ls), ring);
        let b = Aabb::from_points(&ring);
        assert_eq!(envelope(b).lower(), [0.0, 0.0]);
        assert_eq!(envelope(b).upper(), [1.0, 1.0]);
    }
}
