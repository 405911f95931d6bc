//! Interior points of the region of a DBSC (wu-2021 eq. 12).
//!
//! P±(t, u) = q + (u r / L) (± √(L − u² r′²) q′⊥ − u r′ q′), L = ‖q′‖², u ∈ [0, 1]: the
//! point where the circle of radius u r(t) touches the envelope of the family of circles
//! ⟨q(t); u r(t)⟩. u = 0 is the centre q(t), u = 1 the envelope b±(t) (eq. 9). The two
//! identities ‖P − q‖ = u r and (P − q)·q′ = −u² r r′ characterise it.

use super::{DiskBSpline, Side};
use crate::geom::{DVec2, perp};

/// P±(t, u) of wu-2021 eq. 12 (`Side::Left` is P⁺). `None` where the scaled family has no
/// real envelope, L − u² r′² < 0 (at u = 0 only where q′ = 0), or u is outside [0, 1].
pub fn interior_point(c: &DiskBSpline, side: Side, t: f64, u: f64) -> Option<DVec2> {
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let d = c.derivs(t, 1);
    let (q, r) = d[0];
    let (q1, r1) = d[1];
    let l = q1.length_squared();
    let disc = l - u * u * r1 * r1;
    if disc < 0.0 || l == 0.0 {
        return None;
    }
    Some(q + (u * r / l) * (side.sign() * disc.sqrt() * perp(q1) - u * r1 * q1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::tangent::tests::dbsc_strategy;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn interior_identities(c in dbsc_strategy(), s in 0.0f64..=1.0, u in 0.0f64..=1.0) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let d = c.derivs(t, 1);
            let (q, r) = d[0];
            let (q1, r1) = d[1];
            for side in [Side::Left, Side::Right] {
                let Some(p) = interior_point(&c, side, t, u) else {
                    prop_assert!(q1.length_squared() < u * u * r1 * r1 || q1 == DVec2::ZERO);
                    continue;
                };
                let scale = r.max(1.0) * (q1.length() + r1.abs()).max(1.0);
                prop_assert!(((p - q).length() - u * r).abs() <= 1e-12 * r.max(1.0));
                prop_assert!(((p - q).dot(q1) + u * u * r * r1).abs() <= 1e-10 * scale);
                // Left of the travel direction for P⁺, right for P⁻.
                prop_assert!(crate::geom::cross(q1, p - q) * side.sign() >= -1e-12 * scale);
            }
        }

        #[test]
        fn ends_are_centre_and_envelope(c in dbsc_strategy(), s in 0.0f64..=1.0) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            for side in [Side::Left, Side::Right] {
                if let Some(p) = interior_point(&c, side, t, 0.0) {
                    prop_assert_eq!(p, c.center(t));
                }
                if let Some(e) = c.envelope(side, t) {
                    let p = interior_point(&c, side, t, 1.0).unwrap();
                    prop_assert!((p - e.point).length() <= 1e-12 * c.radius(t).max(1.0) * 10.0);
                }
            }
        }
    }
}
