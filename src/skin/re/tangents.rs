//! Tangent vectors of the cyclographic points from fixed touching points
//! (re-skinning-cnc eqs. 7–10; re-mph-skinning-flexible eqs. 9–11) and the planar Hermite
//! tangents at the touching points (re-skinning-cnc eqs. 11–12, mph eq. 12).

use super::ReError;
use super::cyclographic::rot_cw;
use crate::geom::{Circle, DVec2};
use glam::DVec3;

/// How a circle's touching points are given (the "combined" method of
/// re-mph-skinning-flexible Sec. 3.2 chooses per circle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Touch {
    /// Both touching points fixed (re-skinning-cnc Sec. 3.1): left `plus`, right `minus`.
    Fixed {
        /// Left touching point w⁺.
        plus: DVec2,
        /// Right touching point w⁻.
        minus: DVec2,
    },
    /// Only the left touching point fixed; `u` ∈ (0, π) picks the tangent on the
    /// semi-ellipse of mph eq. 10 and so the right touching point.
    Flexible {
        /// Left touching point w⁺.
        plus: DVec2,
        /// Free parameter u ∈ (0, π) of mph eq. 11.
        u: f64,
    },
}

impl Touch {
    /// The fixed left touching point w⁺.
    pub fn plus(&self) -> DVec2 {
        match *self {
            Touch::Fixed { plus, .. } | Touch::Flexible { plus, .. } => plus,
        }
    }
}

/// Tangent vector of circle `c` from both touching points, re-skinning-cnc eq. 10 as
/// printed: t = [r²/γ (W⁺_y − W⁻_y), r²/γ (W⁻_x − W⁺_x), −r] with γ of eq. 9.
/// Its planar part ends at Sᵢ of eqs. 7–8 (inverse of the chord midpoint Iᵢ). Returns
/// `None` when γ = 0 (chord through the centre: the tangent is horizontal).
#[cfg(test)]
pub fn tangent_eq10(c: &Circle, wp: DVec2, wm: DVec2) -> Option<DVec3> {
    let p = c.c;
    let gamma = p.x * (wm.y - wp.y) + p.y * (wp.x - wm.x) + wp.y * wm.x - wp.x * wm.y;
    if gamma == 0.0 {
        return None;
    }
    let k = c.r * c.r / gamma;
    Some(DVec3::new(k * (wp.y - wm.y), k * (wm.x - wp.x), -c.r))
}

/// Tangent vector of circle `c` (index `index` for errors) with touching points `wp`
/// (left) and `wm` (right), re-skinning-cnc eqs. 7–10 rescaled by γ/r² and oriented so
/// that eq. 2 returns q⁺ = W⁺: t = [(W⁺ − W⁻)⊥, −(M − o)·(W⁺ − W⁻)⊥ / r] with M the chord
/// midpoint (= Iᵢ). This is a non-zero multiple of eq. 10 and stays finite when the chord
/// passes through the centre (γ = 0, t horizontal). Always space-like for distinct points.
pub fn tangent_from_two(c: &Circle, index: usize, wp: DVec2, wm: DVec2) -> Result<DVec3, ReError> {
    let d = wp - wm;
    if d.length().is_nan() || d.length() <= crate::geom::tol::scaled(c.r) {
        return Err(ReError::TouchPointsCoincide { index });
    }
    let tp = rot_cw(d);
    let mid = 0.5 * (wp + wm);
    Ok(DVec3::new(tp.x, tp.y, -(mid - c.c).dot(tp) / c.r))
}

/// Tangent vector from one fixed touching point `wp` and the free parameter `u` ∈ (0, π)
/// (re-mph-skinning-flexible eq. 11):
/// t = cos u · (p∇ − w⁺, p_z) + sin u · ((w⁺ − p∇)⊥, 0). Space-like for every u ∈ (0, π):
/// ‖t∇‖² − t_z² = r² sin² u.
pub fn tangent_flexible(c: &Circle, index: usize, wp: DVec2, u: f64) -> Result<DVec3, ReError> {
    if !(u > 0.0 && u < std::f64::consts::PI) {
        return Err(ReError::BadU { index, u });
    }
    let a = c.c - wp;
    let b = rot_cw(wp - c.c);
    Ok(u.cos() * DVec3::new(a.x, a.y, c.r) + u.sin() * DVec3::new(b.x, b.y, 0.0))
}

/// The u of mph eq. 11 whose tangent is parallel to `t` (a tangent whose eq.-2 left
/// touching point is `wp`): t = a·(p∇ − w⁺, r) + b·((w⁺ − p∇)⊥, 0) with a = t_z/r,
/// b = t∇·(w⁺ − p∇)⊥/r², u = atan2(b, a). Converts a [`Touch::Fixed`] circle into a
/// [`Touch::Flexible`] one with the same touching points (the "combined" method).
pub fn u_of_tangent(c: &Circle, wp: DVec2, t: DVec3) -> Option<f64> {
    let a = t.z / c.r;
    let b = DVec2::new(t.x, t.y).dot(rot_cw(wp - c.c)) / (c.r * c.r);
    let u = b.atan2(a);
    (u > 0.0 && u < std::f64::consts::PI).then_some(u)
}

/// The tangent of circle `index` for its [`Touch`], after checking that the given points
/// lie on the circle within `tol`.
pub fn tangent_for(c: &Circle, index: usize, touch: &Touch, tol: f64) -> Result<DVec3, ReError> {
    let check = |w: DVec2| {
        let off = c.signed_distance(w).abs();
        if off > tol {
            Err(ReError::TouchOffCircle { index, off })
        } else {
            Ok(())
        }
    };
    match *touch {
        Touch::Fixed { plus, minus } => {
            check(plus)?;
            check(minus)?;
            tangent_from_two(c, index, plus, minus)
        }
        Touch::Flexible { plus, u } => {
            check(plus)?;
            tangent_flexible(c, index, plus, u)
        }
    }
}

/// Signed distance of `w` from the radical line of `a` and `b` (the points of equal power
/// ‖z − oₐ‖² − rₐ² = ‖z − o_b‖² − r_b²). `None` for concentric circles.
pub fn radical_line_distance(a: &Circle, b: &Circle, w: DVec2) -> Option<f64> {
    let d = b.c - a.c;
    let l = d.length();
    if l.is_nan() || l <= 0.0 {
        return None;
    }
    // 2 z·d = ‖o_b‖² − ‖oₐ‖² − r_b² + rₐ²
    let rhs = b.c.length_squared() - a.c.length_squared() - b.r * b.r + a.r * a.r;
    Some((2.0 * w.dot(d) - rhs) / (2.0 * l))
}

/// Planar Hermite tangent at the left touching point `w` of circle `c`
/// (re-skinning-cnc eqs. 11–12): v = α (w − o)⊥ / ‖w − o‖, α = 2 dist(w, l) with `l` the
/// radical line of the pair (`a`, `b`) the segment joins.
pub fn hermite_tangent(c: &Circle, w: DVec2, a: &Circle, b: &Circle) -> Option<DVec2> {
    let alpha = 2.0 * radical_line_distance(a, b, w)?.abs();
    let n = w - c.c;
    let l = n.length();
    if l.is_nan() || l <= 0.0 {
        return None;
    }
    Some(alpha * rot_cw(n) / l)
}

#[cfg(test)]
mod tests {
    use super::super::cyclographic::{cyclographic, minkowski_sq, touching_points};
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn two_point_tangent_reproduces_touching_points(
            x in -10.0f64..10.0, y in -10.0f64..10.0, r in 0.1f64..5.0,
            a in 0.0f64..std::f64::consts::TAU, gap in 0.05f64..3.1,
        ) {
            let c = Circle::new(DVec2::new(x, y), r);
            let wp = c.point_at(a + gap);
            let wm = c.point_at(a - gap);
            let t = tangent_from_two(&c, 0, wp, wm).unwrap();
            prop_assert!(minkowski_sq(t) > 0.0, "space-like");
            let (qp, qm) = touching_points(cyclographic(&c), t).unwrap();
            prop_assert!((qp - wp).length() < 1e-9 * (1.0 + r));
            prop_assert!((qm - wm).length() < 1e-9 * (1.0 + r));
            // eq. 10 as printed is parallel to the oriented form.
            if let Some(t10) = tangent_eq10(&c, wp, wm) {
                prop_assert!(t10.cross(t).length() <= 1e-9 * t10.length() * t.length());
            }
        }

        #[test]
        fn flexible_tangent_keeps_left_point(
            x in -10.0f64..10.0, y in -10.0f64..10.0, r in 0.1f64..5.0,
            a in 0.0f64..std::f64::consts::TAU, u in 0.01f64..3.13,
        ) {
            let c = Circle::new(DVec2::new(x, y), r);
            let wp = c.point_at(a);
            let t = tangent_flexible(&c, 0, wp, u).unwrap();
            prop_assert!((minkowski_sq(t) - r * r * u.sin().powi(2)).abs() < 1e-9 * (1.0 + r * r));
            let (qp, qm) = touching_points(cyclographic(&c), t).unwrap();
            prop_assert!((qp - wp).length() < 1e-9 * (1.0 + r));
            prop_assert!((c.signed_distance(qm)).abs() < 1e-9 * (1.0 + r));
            // Round trip through a fixed pair.
            let t2 = tangent_from_two(&c, 0, qp, qm).unwrap();
            let u2 = u_of_tangent(&c, wp, t2).unwrap();
            prop_assert!((u2 - u).abs() < 1e-7, "{} vs {}", u2, u);
        }
    }

    #[test]
    fn flexible_rejects_u_outside_open_interval() {
        let c = Circle::new(DVec2::ZERO, 1.0);
        assert!(tangent_flexible(&c, 3, DVec2::Y, 0.0).is_err());
        assert!(tangent_flexible(&c, 3, DVec2::Y, std::f64::consts::PI).is_err());
    }

    #[test]
    fn radical_line_distance_equal_radii_is_bisector() {
        let a = Circle::new(DVec2::ZERO, 1.0);
        let b = Circle::new(DVec2::new(4.0, 0.0), 1.0);
        let d = radical_line_distance(&a, &b, DVec2::new(0.0, 1.0)).unwrap();
        assert!((d + 2.0).abs() < 1e-15);
        let v = hermite_tangent(&a, DVec2::new(0.0, 1.0), &a, &b).unwrap();
        assert!((v - DVec2::new(4.0, 0.0)).length() < 1e-15);
    }
}
