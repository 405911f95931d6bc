//! The envelope tangent in closed form (wu-2021 eqs. 10–11, corrected).
//!
//! With L = ‖q′‖² = x′² + y′², s = √(L − r′²), g = q′·q″ = x′x″ + y′y″ and
//! κ = q′ × q″ = x′y″ − y′x″, differentiating eq. 9, b± = q + (r/L)(± s q′⊥ − r′ q′), and
//! writing q″ = (g/L) q′ + (κ/L) q′⊥ and q″⊥ = (g/L) q′⊥ − (κ/L) q′ gives
//!
//! b±′ = A± q′ + B± q′⊥,
//! A± = 1 − r′²/L ∓ r s κ / L² − r (r″ L − r′ g) / L²,
//! B± = ± r′ s / L − r r′ κ / L² ± r r′ (r′ g − r″ L) / (s L²).
//!
//! Corrections to the printed equations (checked by dimension and by the tests below, which
//! compare with [`DiskBSpline::envelope`]'s quotient-rule derivative and with finite
//! differences): the OCR'd "y″³x′ − x″³y′" is the cross product κ = x′y″ − y′x″; the factor
//! multiplying it in A is r s/L² (the printed r √(1 − r′²/L)/L² has an extra 1/√L), in B it
//! is −r r′/L² for both sides (printed: + r r′/L^{5/2}); the last term of B is
//! ± r r′ (r′ g − r″ L)/(s L²) (printed: (2 r r′² g − r′ r″ L)/(L² s), a stray 2 and a
//! missing r); and "r′√(x′² + y′²) − r′²" is r′ √(x′² + y′² − r′²).

use super::{DiskBSpline, Side};
use crate::geom::{DVec2, cross, perp};

/// The coefficients (A±, B±) of b±′ = A± q′ + B± q′⊥ (wu-2021 eqs. 10–11 as corrected in
/// the module docs). `None` where no real envelope exists (‖q′‖² − r′² ≤ 0).
pub fn envelope_tangent_coeffs(c: &DiskBSpline, side: Side, t: f64) -> Option<(f64, f64)> {
    let d = c.derivs(t, 2);
    let (_, r) = d[0];
    let (q1, r1) = d[1];
    let (q2, r2) = d[2];
    let l = q1.length_squared();
    let disc = l - r1 * r1;
    if disc.is_nan() || disc <= 0.0 || l == 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let sg = side.sign();
    let g = q1.dot(q2);
    let kappa = cross(q1, q2);
    let l2 = l * l;
    let a = 1.0 - r1 * r1 / l - sg * r * s * kappa / l2 - r * (r2 * l - r1 * g) / l2;
    let b = sg * r1 * s / l - r * r1 * kappa / l2 + sg * r * r1 * (r1 * g - r2 * l) / (s * l2);
    Some((a, b))
}

/// The envelope tangent b±′(t) = A± q′ + B± q′⊥ (wu-2021 eqs. 10–11, corrected; see the
/// module docs). `None` where no real envelope exists.
pub fn envelope_tangent(c: &DiskBSpline, side: Side, t: f64) -> Option<DVec2> {
    let (a, b) = envelope_tangent_coeffs(c, side, t)?;
    let q1 = c.derivs(t, 1)[1].0;
    Some(a * q1 + b * perp(q1))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geom::Circle;
    use proptest::prelude::*;

    /// Random open or closed DBSCs of degree 1..=4 (shared by the sibling test modules).
    pub(crate) fn dbsc_strategy() -> impl Strategy<Value = DiskBSpline> {
        dbsc_strategy_in(1..=4, 0..=4, 20.0, 0.2..3.0)
    }

    /// Random open or closed DBSCs: degree in `degrees`, `extra` disks beyond degree + 1,
    /// centres in [−xy, xy)², radii in `r`.
    pub(crate) fn dbsc_strategy_in(
        degrees: std::ops::RangeInclusive<usize>,
        extra: std::ops::RangeInclusive<usize>,
        xy: f64,
        r: std::ops::Range<f64>,
    ) -> impl Strategy<Value = DiskBSpline> {
        (degrees, extra, any::<bool>()).prop_flat_map(move |(p, extra, closed)| {
            let n = p + 1 + extra;
            proptest::collection::vec((-xy..xy, -xy..xy, r.clone()), n).prop_map(move |v| {
                let disks: Vec<Circle> = v
                    .iter()
                    .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
                    .collect();
                if closed {
                    DiskBSpline::closed(p, &disks, None).unwrap()
                } else {
                    DiskBSpline::open(p, &disks, None).unwrap()
                }
            })
        })
    }

    proptest! {
        #[test]
        fn closed_form_matches_quotient_rule(c in dbsc_strategy(), s in 0.0f64..=1.0) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            for side in [Side::Left, Side::Right] {
                let e = c.envelope(side, t);
                let d = envelope_tangent(&c, side, t);
                prop_assert_eq!(e.is_some(), d.is_some());
                if let (Some(e), Some(d)) = (e, d) {
                    // Both blow up like 1/s near the no-envelope boundary: compare relatively
                    // to the size of the terms involved.
                    let (a, b) = envelope_tangent_coeffs(&c, side, t).unwrap();
                    let q1 = c.derivs(t, 1)[1].0.length();
                    let scale = (a.abs() + b.abs() + 1.0) * q1.max(1.0);
                    prop_assert!((e.deriv - d).length() <= 1e-9 * scale, "{} vs {}", e.deriv, d);
                }
            }
        }

        #[test]
        fn closed_form_matches_central_differences(c in dbsc_strategy(), s in 0.02f64..0.98) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let k = c.curve().knots();
            let span = crate::spline::find_span(k, c.degree(), c.curve().ctrl().len(), t);
            let h = 1e-6 * (k[span + 1] - k[span]);
            prop_assume!(t - h > k[span] && t + h < k[span + 1]);
            let q1 = c.derivs(t, 1)[1].0.length_squared();
            prop_assume!(c.envelope_discriminant(t) > 1e-3 * q1);
            for side in [Side::Left, Side::Right] {
                let (Some(d), Some(a), Some(b)) = (
                    envelope_tangent(&c, side, t),
                    c.envelope(side, t + h),
                    c.envelope(side, t - h),
                ) else {
                    continue;
                };
                let fd = (a.point - b.point) / (2.0 * h);
                let scale = d.length().max(q1.sqrt()).max(1.0);
                // Condition of the formula: the envelope's derivatives grow like powers of
                // κ = ‖q′‖ / s, s = √(‖q′‖² − r′²) (wu-2021 eq. 9 divides by s), and the
                // central difference's truncation error h²·‖b‴‖/6 with them; the tolerance
                // scales with κ² (1 far from the no-envelope set, at most 1000 at the
                // assumed distance disc > 1e-3 ‖q′‖²).
                let kappa2 = q1 / c.envelope_discriminant(t);
                prop_assert!(
                    (fd - d).length() <= 1e-5 * scale * kappa2,
                    "fd {} d {} κ² {}",
                    fd,
                    d,
                    kappa2
                );
            }
        }
    }

    /// A centre circle of radius ρ at unit angular speed with constant radius R: the left
    /// envelope is the circle of radius ρ − R (centre curve turning left), so
    /// b+′ = (1 − R/ρ) q′, i.e. A = 1 − R/ρ, B = 0; the right one has A = 1 + R/ρ.
    #[test]
    fn constant_radius_circle_closed_form() {
        let (rho, rr) = (5.0, 1.5);
        let n = 12;
        let disks: Vec<Circle> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                Circle::new(rho * DVec2::new(a.cos(), a.sin()), rr)
            })
            .collect();
        // A closed quadratic through these control points is not exactly a circle, so
        // compare with the curvature of the actual centre curve instead: A± = 1 ∓ R κ_c
        // with κ_c = κ / ‖q′‖³ the signed curvature (r′ = r″ = 0 in the formulas).
        let c = DiskBSpline::closed(3, &disks, None).unwrap();
        for i in 0..20 {
            let t = i as f64 / 20.0;
            let d = c.derivs(t, 2);
            let kc = cross(d[1].0, d[2].0) / d[1].0.length().powi(3);
            let (a, b) = envelope_tangent_coeffs(&c, Side::Left, t).unwrap();
            assert!((a - (1.0 - rr * kc)).abs() < 1e-12, "{a} {kc}");
            assert!(b.abs() < 1e-12);
            let (a, b) = envelope_tangent_coeffs(&c, Side::Right, t).unwrap();
            assert!((a - (1.0 + rr * kc)).abs() < 1e-12);
            assert!(b.abs() < 1e-12);
            assert!(kc > 0.9 / rho && kc < 1.2 / rho);
        }
    }
}
