//! Affine placement of a DBSC: translation, rotation, uniform scaling, mirroring.
//!
//! Similarities commute with the B-spline blend (affine invariance: Σ N_i = 1), and a
//! similarity with ratio |s| maps a disk ⟨p; r⟩ to ⟨S p; |s| r⟩, so each is applied to the
//! (x, y, r) control values and the mapped curve is exactly the mapped region. Mirroring
//! reverses orientation: the left envelope of the mirrored curve is the mirror image of the
//! right envelope of the original.

use super::DiskBSpline;
use crate::geom::{DVec2, Line};
use glam::DVec3;

/// Errors of transformations.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TransformError {
    /// The scale factor is zero, NaN or infinite; holds it.
    #[error("scale factor {0} must be finite and non-zero")]
    Scale(f64),
    /// The mirror line's two points coincide or are not finite, so it has no direction.
    #[error("mirror line has coincident end points")]
    DegenerateLine,
}

impl DiskBSpline {
    fn map_xyr(&self, f: impl Fn(DVec2, f64) -> (DVec2, f64)) -> DiskBSpline {
        DiskBSpline::from_curve(self.curve().map(|v| {
            let (p, r) = f(v.truncate(), v.z);
            DVec3::new(p.x, p.y, r)
        }))
    }

    /// The curve moved by `v`.
    pub fn translated(&self, v: DVec2) -> DiskBSpline {
        self.map_xyr(|p, r| (p + v, r))
    }

    /// The curve rotated by `angle` (radians, counter-clockwise) about `center`.
    pub fn rotated(&self, angle: f64, center: DVec2) -> DiskBSpline {
        let rot = DVec2::from_angle(angle);
        self.map_xyr(|p, r| (center + rot.rotate(p - center), r))
    }

    /// The curve scaled by `s` about `center`; radii scale by |s|. A negative `s` is a
    /// half-turn times |s| (orientation kept, sides not swapped).
    pub fn scaled(&self, s: f64, center: DVec2) -> Result<DiskBSpline, TransformError> {
        if !(s.is_finite() && s != 0.0) {
            return Err(TransformError::Scale(s));
        }
        Ok(self.map_xyr(|p, r| (center + s * (p - center), s.abs() * r)))
    }

    /// The curve reflected about the line through `line.p0` and `line.p1`. Orientation is
    /// reversed: the mirrored left envelope is the mirror of the original right one.
    pub fn mirrored(&self, line: Line) -> Result<DiskBSpline, TransformError> {
        let d = line.p1 - line.p0;
        let l2 = d.length_squared();
        if !(l2 > 0.0 && l2.is_finite()) {
            return Err(TransformError::DegenerateLine);
        }
        Ok(self.map_xyr(|p, r| (reflect(p, line.p0, d, l2), r)))
    }
}

/// Reflection of `p` about the line through `o` with direction `d` (‖d‖² = l2).
fn reflect(p: DVec2, o: DVec2, d: DVec2, l2: f64) -> DVec2 {
    let v = p - o;
    let along = d * (v.dot(d) / l2);
    o + 2.0 * along - v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::Side;
    use crate::dbsc::tangent::tests::dbsc_strategy;
    use proptest::prelude::*;

    fn check(
        a: &DiskBSpline,
        b: &DiskBSpline,
        f: impl Fn(DVec2) -> DVec2,
        rs: f64,
        swap: bool,
        tol: f64,
    ) -> Result<(), TestCaseError> {
        let (lo, hi) = a.domain();
        for i in 0..=16 {
            let t = lo + (hi - lo) * i as f64 / 16.0;
            prop_assert!((b.center(t) - f(a.center(t))).length() <= tol);
            prop_assert!((b.radius(t) - rs * a.radius(t)).abs() <= tol);
            for side in [Side::Left, Side::Right] {
                let other = if swap { side.other() } else { side };
                match (a.envelope(side, t), b.envelope(other, t)) {
                    (Some(ea), Some(eb)) => {
                        prop_assert!(
                            (eb.point - f(ea.point)).length() <= tol,
                            "{:?} t={}",
                            side,
                            t
                        );
                    }
                    (None, None) => {}
                    // Exactly at the no-envelope boundary rounding may tip either way.
                    _ => prop_assert!(
                        a.envelope_discriminant(t).abs()
                            <= 1e-9 * a.derivs(t, 1)[1].0.length_squared().max(1.0)
                    ),
                }
            }
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn envelope_commutes_with_placement(
            c in dbsc_strategy(),
            (vx, vy) in (-50.0f64..50.0, -50.0f64..50.0),
            angle in -7.0f64..7.0,
            s in prop_oneof![-4.0f64..-0.1, 0.1f64..4.0],
            (ox, oy, dx, dy) in (-10.0f64..10.0, -10.0f64..10.0, -1.0f64..1.0, -1.0f64..1.0),
        ) {
            let v = DVec2::new(vx, vy);
            let o = DVec2::new(ox, oy);
            let tol = 1e-9 * 100.0 * s.abs().max(1.0);
            check(&c, &c.translated(v), |p| p + v, 1.0, false, tol)?;
            let rot = DVec2::from_angle(angle);
            check(&c, &c.rotated(angle, o), |p| o + rot.rotate(p - o), 1.0, false, tol)?;
            check(&c, &c.scaled(s, o).unwrap(), |p| o + s * (p - o), s.abs(), false, tol)?;
            let d = DVec2::new(dx, dy);
            prop_assume!(d.length() > 0.05);
            let line = Line::new(o, o + d);
            let m = c.mirrored(line).unwrap();
            let refl = |p: DVec2| {
                let w = p - o;
                o + 2.0 * d * (w.dot(d) / d.length_squared()) - w
            };
            check(&c, &m, refl, 1.0, true, tol)?;
            // Mirroring twice is the identity.
            check(&c, &m.mirrored(line).unwrap(), |p| p, 1.0, false, tol)?;
        }
    }

    #[test]
    fn bad_parameters_are_errors() {
        let disks = [
            crate::geom::Circle::new(DVec2::ZERO, 1.0),
            crate::geom::Circle::new(DVec2::X, 1.0),
        ];
        let c = DiskBSpline::open(1, &disks, None).unwrap();
        assert_eq!(c.scaled(0.0, DVec2::ZERO), Err(TransformError::Scale(0.0)));
        assert!(c.scaled(f64::NAN, DVec2::ZERO).is_err());
        assert_eq!(
            c.mirrored(Line::new(DVec2::X, DVec2::X)),
            Err(TransformError::DegenerateLine)
        );
        // Mirror about the x axis of a stroke along it: radius unchanged, sides swapped.
        let m = c.mirrored(Line::new(DVec2::ZERO, DVec2::X)).unwrap();
        let l = m.envelope(Side::Left, 0.5).unwrap().point;
        assert!((l - DVec2::new(0.5, 1.0)).length() < 1e-15);
    }
}
