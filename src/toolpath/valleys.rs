//! Narrow valleys of a large region filled before the region is grown: the outward offset
//! of a shape with thousands of spikes closer together than the tool (a 9,999-point star
//! on a router) has raw offset segments that each cross hundreds of their neighbours, so
//! cavalier_contours' offset and geo's buffer both cost O(n²) intersections and took
//! minutes. A tool of radius δ cannot enter such a valley, and the offset of the region
//! with the valley closed by its chord differs from the exact one by a bounded amount.
//!
//! **Bound.** Let V be a concave vertex (a right turn of a contour with material on its
//! left) between its neighbours A and B, joined to them by lines, and T the triangle
//! A V B, which lies outside the material when the filled contour stays simple. With
//! Q = P ∪ T: Q ⊕ B_δ ⊇ P ⊕ B_δ (no gouge), and a point x within δ of T is within δ of
//! the edges AV, VB, or inside T (then within c/2 of them, c = |AB|), or within δ of the
//! chord AB on its outer side, where |xA| or |xB| ≤ √(δ² + c²/4). So Q ⊕ B_δ lies within
//! e(c) = √(δ² + c²/4) − δ ≤ c²/(8δ) beyond P ⊕ B_δ, and only triangles of original
//! vertices are filled (no two neighbours), so the bounds do not add up.

use super::region::{MEET_FRACTION, Region};
use crate::geom::DVec2;
use cavalier_contours::polyline::{PlineCreation, PlineSource, PlineSourceMut, Polyline};

/// Regions with fewer vertices than this are grown as they are: their offsets cost little,
/// and the outputs of ordinary designs stay as they were.
pub const VALLEY_FILL_MIN_VERTICES: usize = 2_000;

/// How far beyond the exact offset by `delta` the offset of a region with a valley closed
/// by a chord of length `chord` can reach: e(c) = √(δ² + c²/4) − δ (see the module docs).
pub fn fill_error(chord: f64, delta: f64) -> f64 {
    (delta * delta + 0.25 * chord * chord).sqrt() - delta
}

/// The region with every narrow valley closed (each concave vertex between line segments
/// whose chord gives [`fill_error`] ≤ `tol` for growing by `delta`, never two neighbours),
/// or `None` when nothing changes, the region is shrunk (`delta` ≤ 0), it has fewer than
/// [`VALLEY_FILL_MIN_VERTICES`] vertices, or the filled contours are not simple (within
/// [`MEET_FRACTION`]·`tol`). O(n) plus the simplicity test.
pub fn fill_narrow_valleys(region: &Region, delta: f64, tol: f64) -> Option<Region> {
    let vertices: usize = region.contours.iter().map(|c| c.vertex_count()).sum();
    if delta <= 0.0 || vertices < VALLEY_FILL_MIN_VERTICES {
        return None;
    }
    let mut changed = false;
    let contours: Vec<Polyline<f64>> = region
        .contours
        .iter()
        .map(|pl| {
            let vs: Vec<_> = pl.iter_vertexes().collect();
            let n = vs.len();
            if n < 4 {
                return pl.clone();
            }
            let mut keep = vec![true; n];
            let p = |i: usize| DVec2::new(vs[i].x, vs[i].y);
            for i in 0..n {
                let (a, b) = ((i + n - 1) % n, (i + 1) % n);
                // Neighbours stay: a filled triangle has original vertices only.
                if !keep[a] || !keep[b] {
                    continue;
                }
                if vs[a].bulge != 0.0 || vs[i].bulge != 0.0 {
                    continue;
                }
                let (pa, pv, pb) = (p(a), p(i), p(b));
                let concave = (pv - pa).perp_dot(pb - pv) < 0.0;
                if concave && fill_error(pa.distance(pb), delta) <= tol {
                    keep[i] = false;
                    changed = true;
                }
            }
            let mut out = Polyline::with_capacity(n, true);
            for (v, _) in vs.iter().zip(&keep).filter(|(_, k)| **k) {
                out.add(v.x, v.y, v.bulge);
            }
            out
        })
        .collect();
    if !changed {
        return None;
    }
    let filled = Region { contours };
    filled.simple(tol * MEET_FRACTION).then_some(filled)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::interop::{self, pline_from_points};

    /// A star of `n` points alternating between radii `outer` and `inner`.
    fn star(n: usize, outer: f64, inner: f64) -> Region {
        let pts: Vec<DVec2> = (0..n)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / n as f64;
                let r = if i % 2 == 0 { outer } else { inner };
                DVec2::new(r * a.cos(), r * a.sin())
            })
            .collect();
        Region::from_contours(vec![pline_from_points(&pts, true)])
    }

    #[test]
    fn error_bound_matches_its_series() {
        // e(c) = √(δ² + c²/4) − δ ≈ c²/(8δ) for c ≪ δ, and never more.
        for (c, d) in [(0.01, 1.5), (0.1, 3.0), (1.0, 1.0)] {
            let e = fill_error(c, d);
            assert!(e <= c * c / (8.0 * d) + 1e-15, "{c} {d}: {e}");
            assert!(
                e >= c * c / (8.0 * d) * (1.0 - c * c / (8.0 * d * d)),
                "{c} {d}: {e}"
            );
        }
    }

    /// The filled star holds the star, keeps its tips and loses its valleys, and its
    /// offset lies between the exact offset's bounds: every vertex of the offset of the
    /// filled star is at least δ and at most δ + tol from the star (distance to the star's
    /// edges, computed directly).
    #[test]
    fn star_valleys_are_filled_within_the_bound() {
        let (n, delta, tol) = (4_800, 1.5, 1e-3);
        let s = star(n, 30.0, 10.0);
        let f = fill_narrow_valleys(&s, delta, tol).expect("valleys filled");
        assert_eq!(f.contours[0].vertex_count(), n / 2);
        // The tips stay, the valley vertices lie inside the filled star.
        let sv: Vec<DVec2> = s.contours[0]
            .iter_vertexes()
            .map(|v| interop::vertex_point(&v))
            .collect();
        let fv: Vec<DVec2> = f.contours[0]
            .iter_vertexes()
            .map(|v| interop::vertex_point(&v))
            .collect();
        assert_eq!(fv, sv.iter().copied().step_by(2).collect::<Vec<_>>());
        assert!(sv.iter().skip(1).step_by(2).all(|&p| f.contains(p)));
        assert!(fill_narrow_valleys(&s, -delta, tol).is_none());
        assert!(fill_narrow_valleys(&star(100, 30.0, 10.0), delta, tol).is_none());
        let out = f.offset(delta, 1e-4);
        let edges: Vec<(DVec2, DVec2)> = {
            let v: Vec<DVec2> = s.contours[0]
                .iter_vertexes()
                .map(|v| interop::vertex_point(&v))
                .collect();
            (0..v.len()).map(|i| (v[i], v[(i + 1) % v.len()])).collect()
        };
        let dist = |q: DVec2| {
            edges
                .iter()
                .map(|&(a, b)| {
                    let t = ((q - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                    q.distance(a + t * (b - a))
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut checked = 0;
        for c in &out.contours {
            for v in c.iter_vertexes().step_by(7) {
                let d = dist(interop::vertex_point(&v));
                assert!(d >= delta - 1e-6 && d <= delta + tol + 1e-6, "{d}");
                checked += 1;
            }
        }
        assert!(checked > 50, "{checked}");
    }
}
