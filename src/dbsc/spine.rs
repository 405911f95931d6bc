//! The spine q(t) of a DBSC as a path of cubic Béziers, one per knot span: exact (up to
//! rounding) for degree ≤ 3, where every span is a polynomial of degree ≤ 3.
//!
//! A span [a, b] is interpolated at s = 0, ⅓, ⅔, 1 (t = a + s·(b − a)); a cubic through
//! four points is unique, so for a polynomial span of degree ≤ 3 it is the span itself.
//! With y_k = q(a + k(b − a)/3), B(⅓) = (8P₀ + 12P₁ + 6P₂ + P₃)/27 and
//! B(⅔) = (P₀ + 6P₁ + 12P₂ + 8P₃)/27 give
//! P₁ = (−5y₀ + 18y₁ − 9y₂ + 2y₃)/6 and P₂ = (2y₀ − 9y₁ + 18y₂ − 5y₃)/6.
//! Consecutive spans share the evaluation q(b), so the path is joined exactly. Only
//! interior parameters and span ends are evaluated, so a C⁰ knot (multiplicity p) is
//! handled like any other.

use super::DiskBSpline;
use crate::geom::{CubicBez, Path, PathSeg};

/// Highest degree whose spans are cubics.
pub const MAX_CUBIC_DEGREE: usize = 3;

/// The spine as cubic Bézier pieces, one per non-empty knot span, closed for a closed
/// curve; `None` above degree `MAX_CUBIC_DEGREE` (a span is then no cubic).
pub fn spine_cubics(c: &DiskBSpline) -> Option<Path> {
    if c.degree() > MAX_CUBIC_DEGREE {
        return None;
    }
    let breaks = c.breakpoints();
    let segs = breaks
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let y = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0].map(|s| {
                if s == 1.0 {
                    c.center(b)
                } else {
                    c.center(a + s * (b - a))
                }
            });
            let p1 = (-5.0 * y[0] + 18.0 * y[1] - 9.0 * y[2] + 2.0 * y[3]) / 6.0;
            let p2 = (2.0 * y[0] - 9.0 * y[1] + 18.0 * y[2] - 5.0 * y[3]) / 6.0;
            PathSeg::Cubic(CubicBez::new(y[0], p1, p2, y[3]))
        })
        .collect();
    Some(Path::new(segs, c.is_closed()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Circle;
    use crate::geom::DVec2;
    use proptest::prelude::*;

    fn curve(degree: usize, closed: bool, pts: &[(f64, f64)]) -> DiskBSpline {
        let disks: Vec<Circle> = pts
            .iter()
            .map(|&(x, y)| Circle::new(DVec2::new(x, y), 1.0))
            .collect();
        if closed {
            DiskBSpline::closed(degree, &disks, None).unwrap()
        } else {
            DiskBSpline::open(degree, &disks, None).unwrap()
        }
    }

    /// Each piece evaluated at s equals the spline at a + s(b − a) (de Boor, a second
    /// method), for open and closed curves of degree 1 to 3.
    fn pieces_match(c: &DiskBSpline) -> Result<(), TestCaseError> {
        let path = spine_cubics(c).unwrap();
        let breaks = c.breakpoints();
        prop_assert_eq!(path.segs.len(), breaks.len() - 1);
        prop_assert_eq!(path.closed, c.is_closed());
        for (seg, w) in path.segs.iter().zip(breaks.windows(2)) {
            let PathSeg::Cubic(bez) = seg else {
                return Err(TestCaseError::fail("not a cubic"));
            };
            for k in 0..=16 {
                let s = k as f64 / 16.0;
                let t = w[0] + s * (w[1] - w[0]);
                let scale = 1.0 + c.center(t).length();
                prop_assert!((bez.eval(s) - c.center(t)).length() <= 1e-12 * scale);
            }
        }
        for pair in path.segs.windows(2) {
            prop_assert_eq!(pair[0].end(), pair[1].start());
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
        #[test]
        fn pieces_are_the_spans(
            degree in 1usize..=3,
            closed in any::<bool>(),
            pts in prop::collection::vec((-50.0f64..50.0, -50.0f64..50.0), 6..12),
        ) {
            pieces_match(&curve(degree, closed, &pts))?;
        }
    }

    #[test]
    fn above_cubic_there_are_no_cubic_pieces() {
        let pts: Vec<(f64, f64)> = (0..8).map(|i| (i as f64, (i * i) as f64)).collect();
        assert!(spine_cubics(&curve(4, false, &pts)).is_none());
        let line = spine_cubics(&curve(1, false, &pts)).unwrap();
        assert_eq!(line.start(), Some(DVec2::new(0.0, 0.0)));
        assert_eq!(line.end(), Some(DVec2::new(7.0, 49.0)));
    }
}
