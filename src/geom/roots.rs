//! Root finding on a bracket: Brent's method (zeroin; Brent 1973, ch. 4), which keeps the
//! bracket of bisection and the speed of inverse quadratic interpolation.

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_of_closed_forms() {
        // cos x = x at 0.739085133215160…; x³ − 2x − 5 at 2.0945514815423265 (Wallis).
        let r = brent(|x| x.cos() - x, 0.0, 1.0, 1e-14);
        assert!((r - 0.739_085_133_215_160_6).abs() < 1e-13);
        let w = brent(|x| x * x * x - 2.0 * x - 5.0, 2.0, 3.0, 1e-14);
        assert!((w - 2.094_551_481_542_326_5).abs() < 1e-13);
    }
}
