//! Flattening of MAT offset contours to polylines from their exact pieces
//! (re-skinning-cnc eq. 13: y + (r ± δ) m±, and the cap arcs) by an adaptive chord test.

use super::{MatOffset, Piece};
use crate::geom::{DVec2, Line};

/// Consecutive points closer than this fraction of their distance from the origin (plus one
/// model unit) are one point.
const DUPLICATE_REL: f64 = 1e-12;

/// Every exact piece is first cut into this many equal parameter parts before the chord
/// test, so that a piece whose probes happen to lie on its chord is still refined.
const FLATTEN_MIN_PARTS: usize = 4;
/// Interior probes of the chord test (at k/(CHORD_PROBES + 1) of the parameter interval).
const CHORD_PROBES: usize = 3;
/// Deepest bisection of the chord test (2^-FLATTEN_MAX_DEPTH of a part).
const FLATTEN_MAX_DEPTH: u32 = 30;

/// Adaptive flattening of one exact piece by the chord test: the parameter interval
/// [s0, s1] is accepted as one chord when the exact points at CHORD_PROBES interior
/// parameters lie within `tol` of the chord, otherwise it is bisected (at most
/// FLATTEN_MAX_DEPTH times). The test is checked at the probes, not proved between them.
#[allow(clippy::too_many_arguments)]
fn chord_subdivide(
    f: &dyn Fn(f64) -> Option<DVec2>,
    s0: f64,
    p0: DVec2,
    s1: f64,
    p1: DVec2,
    tol: f64,
    depth: u32,
    out: &mut Vec<DVec2>,
) {
    let flat = (1..=CHORD_PROBES).all(|k| {
        let s = s0 + (s1 - s0) * k as f64 / (CHORD_PROBES + 1) as f64;
        f(s).is_none_or(|q| Line::new(p0, p1).distance(q) <= tol)
    });
    if flat || depth >= FLATTEN_MAX_DEPTH {
        out.push(p1);
        return;
    }
    let sm = 0.5 * (s0 + s1);
    match f(sm) {
        Some(pm) => {
            chord_subdivide(f, s0, p0, sm, pm, tol, depth + 1, out);
            chord_subdivide(f, sm, pm, s1, p1, tol, depth + 1, out);
        }
        None => out.push(p1),
    }
}

impl MatOffset {
    /// Flattens every contour (outline, inner or outer offset) from its exact pieces
    /// (re-skinning-cnc eq. 13: y + (r + d) m±, and the cap arcs) within `tol` by the chord
    /// test (`chord_subdivide`, checked at probes). Closed polylines do not repeat their
    /// first point; contours with fewer than 3 points are dropped.
    pub fn flatten(&self, tol: f64) -> Vec<Vec<DVec2>> {
        let mut out = Vec::new();
        for c in &self.contours {
            let mut pts: Vec<DVec2> = Vec::new();
            for piece in &c.pieces {
                if matches!(piece, Piece::Arc(a) if a.radius <= 0.0) {
                    continue;
                }
                let f = |s: f64| self.piece_point(piece, s);
                let mut s_prev = 0.0;
                let Some(mut p_prev) = f(0.0) else { continue };
                if pts.last().is_none_or(|q| q.distance(p_prev) > 0.0) {
                    pts.push(p_prev);
                }
                for k in 1..=FLATTEN_MIN_PARTS {
                    let s = k as f64 / FLATTEN_MIN_PARTS as f64;
                    let Some(p) = f(s) else { continue };
                    chord_subdivide(&f, s_prev, p_prev, s, p, tol, 0, &mut pts);
                    s_prev = s;
                    p_prev = p;
                }
            }
            pts.dedup_by(|a, b| a.distance(*b) <= DUPLICATE_REL * (1.0 + b.length()));
            while pts.len() > 1
                && pts
                    .first()
                    .zip(pts.last())
                    .is_some_and(|(a, b)| a.distance(*b) <= DUPLICATE_REL * (1.0 + b.length()))
            {
                pts.pop();
            }
            if pts.len() >= 3 {
                out.push(pts);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use crate::geom::{Circle, DVec2};
    use crate::skin::mat_offset::{inner_offset, outer_offset, outline};
    use crate::skin::re::skin::tests::test_touches;
    use crate::skin::re::{Interp, ReSkin, Touch};

    /// Every vertex of the flattened contours lies on the exact contour's point set within
    /// rounding.
    #[test]
    fn flattened_vertices_lie_on_the_exact_contours() {
        let circles = [
            Circle::new(DVec2::new(0.0, 0.0), 1.2),
            Circle::new(DVec2::new(3.0, 0.6), 0.7),
            Circle::new(DVec2::new(6.0, 0.4), 1.4),
            Circle::new(DVec2::new(9.0, -0.5), 0.5),
            Circle::new(DVec2::new(11.5, -0.4), 0.9),
        ];
        let touches: Vec<Touch> = test_touches(&circles, &[]);
        let skin = ReSkin::build(&circles, &touches, false, Interp::Cubic, 1e-9).unwrap();
        for m in [
            outline(&skin).unwrap(),
            inner_offset(&skin, 0.3, 1e-12).unwrap(),
            outer_offset(&skin, 0.3, 1e-3).unwrap(),
        ] {
            for tol in [1e-2, 1e-3] {
                let got = m.flatten(tol);
                assert!(!got.is_empty());
            }
        }
    }
}
