//! Adaptive Gauss–Legendre quadrature with an absolute error target.
//!
//! A panel [a, b] is integrated by the 5-point Gauss–Legendre rule G₅ (exact for
//! polynomials of degree ≤ 9; Abramowitz & Stegun 25.4.29) and accepted when
//! |G₅[a, m] + G₅[m, b] − G₅[a, b]| ≤ tol_panel, m the midpoint; otherwise each half is
//! refined with half the tolerance. The difference between the panel and its halves
//! estimates the error of the coarser value, so the accepted (finer) sum is within the
//! target for smooth integrands; the depth is capped at [`MAX_DEPTH`] halvings.

/// Halvings allowed below the starting panel: 2⁻³⁰ of the interval is below any feature a
/// B-spline of design size resolves, and it bounds the work on a non-smooth integrand.
pub const MAX_DEPTH: u32 = 30;

/// Nodes of the 5-point Gauss–Legendre rule on [−1, 1].
const X5: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
/// Weights of the 5-point Gauss–Legendre rule.
const W5: [f64; 5] = [
    0.236_926_885_056_189,
    0.478_628_670_499_366,
    0.568_888_888_888_889,
    0.478_628_670_499_366,
    0.236_926_885_056_189,
];

/// G₅ on [a, b]: (b − a)/2 · Σ wᵢ f((a + b)/2 + (b − a)/2 · xᵢ).
pub fn gauss_legendre5(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let h = 0.5 * (b - a);
    let m = 0.5 * (a + b);
    h * X5
        .iter()
        .zip(W5)
        .map(|(&x, w)| w * f(m + h * x))
        .sum::<f64>()
}

/// ∫ₐᵇ f by adaptive G₅ (module docs) to the absolute error `tol` (> 0; a non-positive
/// `tol` refines to [`MAX_DEPTH`]).
pub fn integrate(f: &impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    if b <= a {
        return 0.0;
    }
    let whole = gauss_legendre5(f, a, b);
    refine(f, a, b, whole, tol, 0)
}

fn refine(f: &impl Fn(f64) -> f64, a: f64, b: f64, whole: f64, tol: f64, depth: u32) -> f64 {
    let m = 0.5 * (a + b);
    let l = gauss_legendre5(f, a, m);
    let r = gauss_legendre5(f, m, b);
    if depth >= MAX_DEPTH || (l + r - whole).abs() <= tol || !(l + r).is_finite() {
        l + r
    } else {
        refine(f, a, m, l, 0.5 * tol, depth + 1) + refine(f, m, b, r, 0.5 * tol, depth + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomials_up_to_degree_nine_are_exact() {
        // ∫₀² x⁹ dx = 2¹⁰/10.
        let v = gauss_legendre5(&|x: f64| x.powi(9), 0.0, 2.0);
        assert!((v - 102.4).abs() < 1e-10, "{v}");
    }

    #[test]
    fn quarter_circle_length_meets_the_tolerance() {
        // Arc length of (cos t, sin t)·R over [0, π/2] with a speed that is not constant:
        // t = s², so the integrand is R·2s on s ∈ [0, √(π/2)], length πR/2.
        let r = 7.0;
        let f = |s: f64| r * 2.0 * s;
        let v = integrate(&f, 0.0, (std::f64::consts::FRAC_PI_2).sqrt(), 1e-10);
        assert!((v - std::f64::consts::FRAC_PI_2 * r).abs() < 1e-9, "{v}");
        // A kink (|x − 1/3|) is resolved by refinement.
        let g = |x: f64| (x - 1.0 / 3.0).abs();
        let v = integrate(&g, 0.0, 1.0, 1e-9);
        let exact = 0.5 * (1.0f64 / 9.0 + 4.0 / 9.0);
        assert!((v - exact).abs() < 1e-8, "{v} vs {exact}");
    }
}
