//! Cyclographic points of circles and the envelope touching points of a tangent direction
//! (re-skinning-cnc eqs. 2 and 6; re-mph-skinning-flexible eqs. 2 and 8).
//!
//! Conventions of both papers: for n = (nx, ny, nz) ∈ R^{2,1} the projection is
//! n∇ = (nx, ny); for a plane vector the rotation is n⊥ = (ny, −nx) (clockwise, [`rot_cw`]).

use crate::geom::{Circle, DVec2};
use glam::DVec3;

/// The papers' rotation n⊥ = (ny, −nx): a quarter turn clockwise.
#[inline]
pub fn rot_cw(v: DVec2) -> DVec2 {
    DVec2::new(v.y, -v.x)
}

/// Projection n∇ = (nx, ny) of a point or vector of R^{2,1}.
#[inline]
pub fn proj(n: DVec3) -> DVec2 {
    DVec2::new(n.x, n.y)
}

/// Cyclographic image p = (oₓ, o_y, r) of a circle (re-skinning-cnc eq. 6, mph eq. 8).
#[inline]
pub fn cyclographic(c: &Circle) -> DVec3 {
    DVec3::new(c.c.x, c.c.y, c.r)
}

/// Minkowski squared norm ‖n∇‖² − n_z² of a vector of R^{2,1}: positive for space-like.
#[inline]
#[cfg(test)]
pub fn minkowski_sq(n: DVec3) -> f64 {
    n.x * n.x + n.y * n.y - n.z * n.z
}

/// Touching points q± of the envelope with the circle p for the tangent direction t
/// (re-skinning-cnc eq. 2): q± = p∇ − p_z (t_z t∇ ± t∇⊥ √(‖t∇‖² − t_z²)) / ‖t∇‖².
/// `q⁺` is on the left of the travel direction t∇. `None` unless t is space-like.
#[must_use]
pub fn touching_points(p: DVec3, t: DVec3) -> Option<(DVec2, DVec2)> {
    let tp = proj(t);
    let l = tp.length_squared();
    let disc = l - t.z * t.z;
    if disc.is_nan() || disc <= 0.0 || l.is_nan() || l <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let base = proj(p);
    let a = t.z * tp;
    let b = rot_cw(tp) * s;
    Some((base - p.z * (a + b) / l, base - p.z * (a - b) / l))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn horizontal_tangent_touches_sideways() {
        // A circle moving along +x with constant radius touches at ±y.
        let p = DVec3::new(1.0, 2.0, 0.5);
        let (qp, qm) = touching_points(p, DVec3::new(3.0, 0.0, 0.0)).unwrap();
        assert!((qp - DVec2::new(1.0, 2.5)).length() < 1e-15);
        assert!((qm - DVec2::new(1.0, 1.5)).length() < 1e-15);
    }

    #[test]
    fn touching_points_lie_on_circle_with_envelope_condition() {
        // The envelope condition (q − p∇)·t∇ = −p_z t_z (normal m has m·t∇ = −t_z).
        let p = DVec3::new(-0.3, 0.7, 1.3);
        for &t in &[
            DVec3::new(1.0, 0.2, 0.4),
            DVec3::new(-2.0, 1.0, -1.5),
            DVec3::new(0.1, -3.0, 2.0),
        ] {
            let (qp, qm) = touching_points(p, t).unwrap();
            for q in [qp, qm] {
                assert!(((q - proj(p)).length() - p.z).abs() < 1e-12);
                assert!(((q - proj(p)).dot(proj(t)) + p.z * t.z).abs() < 1e-12);
            }
            // q⁺ on the left of t∇.
            assert!(crate::geom::cross(proj(t), qp - proj(p)) > 0.0);
        }
        assert!(touching_points(p, DVec3::new(1.0, 0.0, 1.0)).is_none());
    }
}
