//! Fitting MAT offset contours with lines, cubic Béziers or circular arcs (re-skinning-cnc
//! Sec. 4: the exact offsets y + (r ± δ) m± of eq. 13 handed to G-code as G1/G2/G3), and
//! flattening them to polylines.

use super::{MatOffset, Piece};
use crate::geom::{Arc, PathSeg};
use crate::skin::re::Branch;
#[cfg(any(test, feature = "internals"))]
use {
    super::{MatOffsetError, check_tolerance},
    crate::geom::{CubicBez, DVec2, Line, Path},
};

/// Three points are collinear (a line, not an arc) when |(p₀ − p_m) × (p₁ − p_m)| is at most
/// this fraction of the chord²: a sagitta far below any tolerance.
#[cfg(any(test, feature = "internals"))]
const COLLINEAR_REL: f64 = 1e-12;

/// Samples at which a fitted piece is compared with the exact curve (interior points
/// k/CHECK_SAMPLES): the tolerance is verified there, not proved between them.
#[cfg(any(test, feature = "internals"))]
const CHECK_SAMPLES: usize = 16;

/// How a piece of exact curve is approximated.
#[cfg(any(test, feature = "internals"))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FitKind {
    Line,
    Cubic,
    Arc,
}

/// The circular arc through `p0`, `pm`, `p1` (a line when they are collinear to within
/// `eps` relative to the chord).
#[cfg(any(test, feature = "internals"))]
fn arc3(p0: DVec2, pm: DVec2, p1: DVec2) -> PathSeg {
    let a = pm - p0;
    let b = p1 - pm;
    let cr = crate::geom::cross(a, b);
    let chord = (p1 - p0).length();
    if cr.abs() <= COLLINEAR_REL * chord * chord {
        return PathSeg::Line(Line::new(p0, p1));
    }
    // Centre: intersection of the perpendicular bisectors of p0pm and pmp1.
    let m1 = 0.5 * (p0 + pm);
    let m2 = 0.5 * (pm + p1);
    let d1 = crate::geom::perp(a);
    let d2 = crate::geom::perp(b);
    let s = crate::geom::cross(m2 - m1, d2) / crate::geom::cross(d1, d2);
    let center = m1 + s * d1;
    PathSeg::Arc(Arc::from_center_points(center, p0, p1, cr > 0.0))
}
/// Deepest bisection of a piece when fitting.
#[cfg(any(test, feature = "internals"))]
const MAX_FIT_DEPTH: u32 = 30;

impl MatOffset {
    /// The contours as paths of cubic Béziers (Hermite fits of the exact curve, bisected
    /// until the parametric distance at CHECK_SAMPLES interior points is ≤ `tol`) and true
    /// arcs for caps.
    #[cfg(any(test, feature = "internals"))]
    pub fn to_cubic_paths(&self, tol: f64) -> Result<Vec<Path>, MatOffsetError> {
        self.to_paths(tol, FitKind::Cubic)
    }

    /// The contours as paths of line segments within `tol` (same test) and true arcs.
    #[cfg(any(test, feature = "internals"))]
    pub fn to_line_paths(&self, tol: f64) -> Result<Vec<Path>, MatOffsetError> {
        self.to_paths(tol, FitKind::Line)
    }

    /// The contours as paths of circular arcs (through the ends and the parameter midpoint
    /// of each piece, bisected until the distance of CHECK_SAMPLES interior points of the
    /// exact curve to the arc is ≤ `tol`) and the true cap arcs: ready for G2/G3 and for
    /// arc-and-line offsetting.
    #[cfg(any(test, feature = "internals"))]
    pub fn to_arc_paths(&self, tol: f64) -> Result<Vec<Path>, MatOffsetError> {
        self.to_paths(tol, FitKind::Arc)
    }

    /// `tol` must be positive and finite ([`MatOffsetError::BadTolerance`]): at 0 or NaN
    /// every piece would be bisected to depth MAX_FIT_DEPTH, 2³⁰ pieces each.
    #[cfg(any(test, feature = "internals"))]
    fn to_paths(&self, tol: f64, kind: FitKind) -> Result<Vec<Path>, MatOffsetError> {
        check_tolerance(tol)?;
        Ok(self
            .fitted_contours(
                |a| a.radius > 0.0,
                |segment, branch, t0, t1, segs| {
                    self.fit(segment, branch, t0, t1, tol, kind, 0, segs)
                },
            )
            .into_iter()
            .map(|segs| Path::new(segs, true))
            .collect())
    }

    /// The one walk over the contours' pieces that every fitting of a MAT offset shares
    /// (lines, cubics, arcs here; biarcs in `toolpath::re_route`): per contour, the cap arcs
    /// `keep_arc` accepts pushed as they are, and each exact curve piece (segment, branch,
    /// t0, t1) handed to `fit`, which appends its approximation.
    pub fn fitted_contours(
        &self,
        keep_arc: impl Fn(&Arc) -> bool,
        mut fit: impl FnMut(usize, Branch, f64, f64, &mut Vec<PathSeg>),
    ) -> Vec<Vec<PathSeg>> {
        self.contours
            .iter()
            .map(|c| {
                let mut segs = Vec::new();
                for p in &c.pieces {
                    match *p {
                        Piece::Arc(a) => {
                            if keep_arc(&a) {
                                segs.push(PathSeg::Arc(a));
                            }
                        }
                        Piece::Curve {
                            segment,
                            branch,
                            t0,
                            t1,
                        } => fit(segment, branch, t0, t1, &mut segs),
                    }
                }
                segs
            })
            .collect()
    }

    #[allow(clippy::too_many_arguments)]
    #[cfg(any(test, feature = "internals"))]
    fn fit(
        &self,
        s: usize,
        b: Branch,
        t0: f64,
        t1: f64,
        tol: f64,
        kind: FitKind,
        depth: u32,
        out: &mut Vec<PathSeg>,
    ) {
        let (Some((p0, d0)), Some((p1, d1))) =
            (self.curve_point(s, b, t0), self.curve_point(s, b, t1))
        else {
            return;
        };
        let h = t1 - t0;
        let seg = match kind {
            FitKind::Cubic => PathSeg::Cubic(CubicBez::hermite(p0, d0 * h, p1, d1 * h)),
            FitKind::Line => PathSeg::Line(Line::new(p0, p1)),
            FitKind::Arc => match self
                .curves
                .get(s)
                .and_then(|c| c.offset_point(b, self.d, t0 + 0.5 * h))
            {
                Some(pm) => arc3(p0, pm, p1),
                None => PathSeg::Line(Line::new(p0, p1)),
            },
        };
        let ok = depth >= MAX_FIT_DEPTH
            || (1..CHECK_SAMPLES).all(|k| {
                let u = k as f64 / CHECK_SAMPLES as f64;
                match self
                    .curves
                    .get(s)
                    .and_then(|c| c.offset_point(b, self.d, t0 + u * h))
                {
                    Some(q) => match seg {
                        PathSeg::Line(l) => l.distance(q) <= tol,
                        PathSeg::Arc(a) => a.distance(q) <= tol,
                        PathSeg::Cubic(_) => seg.eval(u).distance(q) <= tol,
                    },
                    None => true,
                }
            });
        if ok {
            out.push(seg);
        } else {
            let m = 0.5 * (t0 + t1);
            self.fit(s, b, t0, m, tol, kind, depth + 1, out);
            self.fit(s, b, m, t1, tol, kind, depth + 1, out);
        }
    }
}
