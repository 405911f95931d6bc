//! Root finding on a bracket: Brent's method (zeroin; Brent 1973, ch. 4), which keeps the
//! bracket of bisection and the speed of inverse quadratic interpolation; and golden-section
//! search for the minimum of a unimodal function on a bracket (Kiefer 1953).

/// Iteration cap of Brent's method: it converges in far fewer; the cap only guards against
/// a non-positive tolerance.
const MAX_BRENT_ITERS: usize = 200;

/// Brent's method (zeroin) for a root of `f` in [a, b] with f(a) = fa, f(b) = fb of
/// opposite signs, to within `tol`.
pub fn brent_with(f: impl Fn(f64) -> f64, a: f64, b: f64, fa: f64, fb: f64, tol: f64) -> f64 {
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..MAX_BRENT_ITERS {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol.max(0.0);
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            // Inverse quadratic interpolation or secant.
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
    }
    b
}

/// Brent's method on a bracket [a, b] with f(a) f(b) ≤ 0, to an interval of width `tol`.
/// Returns the best root estimate.
pub fn brent(f: impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let (fa, fb) = (f(a), f(b));
    brent_with(f, a, b, fa, fb, tol)
}

/// 1/φ = (√5 − 1)/2 correctly rounded: the factor by which golden-section search shrinks its
/// bracket a step.
pub const INV_PHI: f64 = 0.618_033_988_749_894_8;

/// Which side golden-section search keeps when its two inner values are equal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tie {
    /// Keep [a, d] (as for f(c) < f(d)).
    Left,
    /// Keep [c, b] (as for f(c) > f(d)).
    Right,
}

/// Golden-section search (Kiefer 1953) for a minimum of a unimodal function on a bracket
/// [a, b]: inner points c = b − r(b − a), d = a + r(b − a) with r = 1/φ; keep [a, d] when
/// f(c) < f(d), [c, b] when f(c) > f(d), and the side [`Tie`] names when they are equal.
/// Each step reuses one inner point and evaluates f once. The search stops before a step
/// when |b − a| ≤ `tol` (a negative tolerance runs every step) or after `max_steps` steps.
/// A maximum is found as the minimum of −f (negation is exact, so ties keep their side).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Golden {
    /// Bracket width at which the search stops.
    pub tol: f64,
    /// Most steps.
    pub max_steps: usize,
    /// The side kept on equal inner values.
    pub tie: Tie,
    /// The shrink factor r, [`INV_PHI`] unless set by [`Golden::with_ratio`].
    pub ratio: f64,
}

/// The final bracket of a [`Golden`] search: a < c < d < b with the values at the inner
/// points.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct GoldenBracket {
    /// Left end.
    pub a: f64,
    /// Right end.
    pub b: f64,
    /// Left inner point, b − r(b − a).
    pub c: f64,
    /// f(c).
    pub fc: f64,
    /// Right inner point, a + r(b − a).
    pub d: f64,
    /// f(d).
    pub fd: f64,
}

impl GoldenBracket {
    /// The midpoint (a + b)/2 of the bracket.
    #[must_use]
    pub fn mid(&self) -> f64 {
        0.5 * (self.a + self.b)
    }
}

impl Golden {
    /// A search to bracket width `tol` in at most `max_steps` steps, ties kept on `tie`'s side.
    #[must_use]
    pub const fn new(tol: f64, max_steps: usize, tie: Tie) -> Golden {
        Golden {
            tol,
            max_steps,
            tie,
            ratio: INV_PHI,
        }
    }

    /// The same search with another floating-point value of 1/φ (the bracket a caller's
    /// results were computed with, such as (√5 − 1)/2 evaluated in f64, one ulp above
    /// [`INV_PHI`]).
    #[must_use]
    pub const fn with_ratio(self, ratio: f64) -> Golden {
        Golden { ratio, ..self }
    }

    /// The search on [a, b] for an `f` that may fail; its error ends the search.
    pub fn min_with<E>(
        &self,
        mut f: impl FnMut(f64) -> Result<f64, E>,
        a: f64,
        b: f64,
    ) -> Result<GoldenBracket, E> {
        let r = self.ratio;
        let (mut a, mut b) = (a, b);
        let mut c = b - r * (b - a);
        let mut d = a + r * (b - a);
        let (mut fc, mut fd) = (f(c)?, f(d)?);
        for _ in 0..self.max_steps {
            if (b - a).abs() <= self.tol {
                break;
            }
            if fc < fd || (fc == fd && self.tie == Tie::Left) {
                b = d;
                d = c;
                fd = fc;
                c = b - r * (b - a);
                fc = f(c)?;
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + r * (b - a);
                fd = f(d)?;
            }
        }
        Ok(GoldenBracket { a, b, c, fc, d, fd })
    }

    /// The search on [a, b] for an `f` that cannot fail.
    pub fn min(&self, mut f: impl FnMut(f64) -> f64, a: f64, b: f64) -> GoldenBracket {
        match self.min_with(|x| Ok::<f64, std::convert::Infallible>(f(x)), a, b) {
            Ok(g) => g,
            Err(never) => match never {},
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`INV_PHI`] is 1/φ correctly rounded: φ·INV_PHI = 1 and φ − 1 = 1/φ within an ulp;
    /// (√5 − 1)/2 evaluated in f64 is the next double up.
    #[test]
    fn inverse_golden_ratio_is_correctly_rounded() {
        let computed = 0.5 * (5f64.sqrt() - 1.0);
        assert_eq!(computed, f64::from_bits(INV_PHI.to_bits() + 1));
        let phi = 1.0 + INV_PHI;
        assert!((phi * INV_PHI - 1.0).abs() <= f64::EPSILON);
    }

    /// The minimum of (x − 0.3)² on [0, 1] and of cos on [2, 4] (at π), to the tolerance;
    /// the bracket shrinks by 1/φ a step, so n steps leave (1/φ)ⁿ of it. At a smooth
    /// extremum f changes by O(δ²) over δ, so values of size 1 locate it to about √ε ≈ 1.5e-8.
    #[test]
    fn finds_minima_of_closed_forms() {
        let g = Golden::new(1e-12, 200, Tie::Right).min(|x| (x - 0.3) * (x - 0.3), 0.0, 1.0);
        assert!((g.mid() - 0.3).abs() < 1e-9, "{g:?}");
        assert!(g.b - g.a <= 1e-12);
        let g = Golden::new(-1.0, 40, Tie::Left).min(f64::cos, 2.0, 4.0);
        assert!((g.b - g.a - 2.0 * INV_PHI.powi(40)).abs() < 1e-12, "{g:?}");
        assert!((g.mid() - std::f64::consts::PI).abs() < 1e-7);
        // A maximum as the minimum of −f: sin on [0, 3] at π/2.
        let g = Golden::new(1e-10, 200, Tie::Left).min(|x| -x.sin(), 0.0, 3.0);
        assert!((g.mid() - std::f64::consts::FRAC_PI_2).abs() < 1e-7);
    }

    /// On a constant the tie rule alone decides: Left shrinks to a, Right to b.
    #[test]
    fn ties_keep_the_named_side() {
        let l = Golden::new(1e-9, 200, Tie::Left).min(|_| 1.0, 0.0, 1.0);
        let r = Golden::new(1e-9, 200, Tie::Right).min(|_| 1.0, 0.0, 1.0);
        assert!(l.b < 1e-8 && r.a > 1.0 - 1e-8, "{l:?} {r:?}");
    }

    #[test]
    fn an_error_of_f_ends_the_search() {
        let g = Golden::new(-1.0, 50, Tie::Left);
        // The minimum of x lies left: no point beyond the first right inner point is asked.
        let r = g.min_with(|x| if x > 0.7 { Err(x) } else { Ok(x) }, 0.0, 1.0);
        assert!(r.is_ok_and(|g| g.b < 1e-9));
        let r = g.min_with(|x| if x < 0.5 { Err(x) } else { Ok(-x) }, 0.0, 1.0);
        assert!(r.is_err());
    }

    #[test]
    fn finds_roots_of_closed_forms() {
        // cos x = x at 0.739085133215160…; x³ − 2x − 5 at 2.0945514815423265 (Wallis).
        let r = brent(|x| x.cos() - x, 0.0, 1.0, 1e-14);
        assert!((r - 0.739_085_133_215_160_6).abs() < 1e-13);
        let w = brent(|x| x * x * x - 2.0 * x - 5.0, 2.0, 3.0, 1e-14);
        assert!((w - 2.094_551_481_542_326_5).abs() < 1e-13);
    }
}
