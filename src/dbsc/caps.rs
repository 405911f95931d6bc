//! End caps of open strokes: arcs of the end circles joining the envelope ends
//! (wu-2021 Sec. "Computing points on the boundary": the end part is an arc whose centre is
//! the end point of the centre curve).
//!
//! The outline of an open stroke runs left envelope forwards, end cap, right envelope
//! backwards, start cap: a clockwise contour. So the start cap goes from the right
//! envelope's start point to the left envelope's start point around the back of the start
//! circle, and the end cap from the left end point to the right end point around the front
//! of the end circle; both arcs are clockwise (negative sweep).

use super::{DiskBSpline, Side};
use crate::geom::Arc;

/// Which end of an open stroke.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// The start of the domain, t = u_p.
    Start,
    /// The end of the domain, t = u_{n+1}.
    End,
}

/// Errors of cap construction.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CapError {
    /// The curve is closed, so it has no ends to cap.
    #[error("closed stroke has no end caps")]
    Closed,
    /// One envelope does not exist at the end (‖q′‖ ≤ |r′|, wu-2021 eq. 9), so the cap arc
    /// has no end points to join.
    #[error("no real envelope at the {end:?} of the stroke (t = {t}): ‖q′‖ ≤ |r′| there")]
    NoEnvelope {
        /// Which end.
        end: End,
        /// The end's curve parameter.
        t: f64,
    },
}

/// The cap arc at one end (see the module docs for its direction).
pub fn cap(c: &DiskBSpline, end: End) -> Result<Arc, CapError> {
    if c.is_closed() {
        return Err(CapError::Closed);
    }
    let (lo, hi) = c.domain();
    let t = match end {
        End::Start => lo,
        End::End => hi,
    };
    let left = c.envelope(Side::Left, t);
    let right = c.envelope(Side::Right, t);
    let (Some(left), Some(right)) = (left, right) else {
        return Err(CapError::NoEnvelope { end, t });
    };
    let centre = c.center(t);
    let (from, to) = match end {
        End::Start => (right.point, left.point),
        End::End => (left.point, right.point),
    };
    let mut arc = Arc::from_center_points(centre, from, to, false);
    // Radius from the stroke, not from the rounded envelope point.
    arc.radius = c.radius(t);
    Ok(arc)
}

/// Both caps: (start cap, end cap).
pub fn caps(c: &DiskBSpline) -> Result<(Arc, Arc), CapError> {
    Ok((cap(c, End::Start)?, cap(c, End::End)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Circle, DVec2};
    use proptest::prelude::*;

    fn open_strategy() -> impl Strategy<Value = DiskBSpline> {
        (1usize..=4, 0usize..=3).prop_flat_map(|(p, extra)| {
            proptest::collection::vec((-20.0f64..20.0, -20.0f64..20.0, 0.2f64..3.0), p + 1 + extra)
                .prop_map(move |v| {
                    let d: Vec<Circle> = v
                        .iter()
                        .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
                        .collect();
                    DiskBSpline::open(p, &d, None).unwrap()
                })
        })
    }

    #[test]
    fn straight_constant_radius_caps_are_half_circles() {
        let disks: Vec<Circle> = (0..4)
            .map(|i| Circle::new(DVec2::new(i as f64, 0.0), 0.5))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let (s, e) = caps(&c).unwrap();
        use std::f64::consts::PI;
        assert!((s.sweep + PI).abs() < 1e-12 && (e.sweep + PI).abs() < 1e-12);
        // Start cap: from (0, −0.5) around (−0.5, 0) to (0, 0.5).
        assert!((s.p0() - DVec2::new(0.0, -0.5)).length() < 1e-12);
        assert!((s.eval(0.5) - DVec2::new(-0.5, 0.0)).length() < 1e-12);
        assert!((s.p1() - DVec2::new(0.0, 0.5)).length() < 1e-12);
        // End cap: from (3, 0.5) around (3.5, 0) to (3, −0.5).
        assert!((e.p0() - DVec2::new(3.0, 0.5)).length() < 1e-12);
        assert!((e.eval(0.5) - DVec2::new(3.5, 0.0)).length() < 1e-12);
        assert!((e.p1() - DVec2::new(3.0, -0.5)).length() < 1e-12);
    }

    #[test]
    fn missing_envelope_and_closed_are_errors() {
        let disks = [
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(1.0, 0.0), 4.0),
        ];
        let c = DiskBSpline::open(1, &disks, None).unwrap();
        assert_eq!(
            cap(&c, End::Start),
            Err(CapError::NoEnvelope {
                end: End::Start,
                t: 0.0
            })
        );
        assert_eq!(
            caps(&c).unwrap_err(),
            CapError::NoEnvelope {
                end: End::Start,
                t: 0.0
            }
        );
        let c = DiskBSpline::closed(
            1,
            &[disks[0], disks[1], Circle::new(DVec2::new(0.0, 1.0), 1.0)],
            None,
        )
        .unwrap();
        assert_eq!(cap(&c, End::End), Err(CapError::Closed));
    }

    proptest! {
        /// Caps join the envelope ends, bulge away from the stroke (the middle of the start
        /// cap lies behind the start, that of the end cap ahead of the end), and run the same
        /// under reversal with the roles of the ends exchanged.
        #[test]
        fn caps_join_envelopes_and_point_outwards(c in open_strategy()) {
            let (lo, hi) = c.domain();
            let Ok((s, e)) = caps(&c) else {
                prop_assert!(c.envelope(Side::Left, lo).is_none() || c.envelope(Side::Left, hi).is_none());
                return Ok(());
            };
            let tol = 1e-9 * 40.0;
            prop_assert!((s.p0() - c.envelope(Side::Right, lo).unwrap().point).length() < tol);
            prop_assert!((s.p1() - c.envelope(Side::Left, lo).unwrap().point).length() < tol);
            prop_assert!((e.p0() - c.envelope(Side::Left, hi).unwrap().point).length() < tol);
            prop_assert!((e.p1() - c.envelope(Side::Right, hi).unwrap().point).length() < tol);
            prop_assert!(s.sweep < 0.0 && e.sweep < 0.0);
            let d0 = c.derivs(lo, 1)[1].0;
            let d1 = c.derivs(hi, 1)[1].0;
            prop_assert!((s.eval(0.5) - c.center(lo)).dot(d0) < 0.0);
            prop_assert!((e.eval(0.5) - c.center(hi)).dot(d1) > 0.0);
            // Reversal exchanges the caps.
            let rc = DiskBSpline::from_curve(c.curve().reversed());
            let (rs, re) = caps(&rc).unwrap();
            prop_assert!((rs.p0() - e.p0()).length() < tol && (rs.p1() - e.p1()).length() < tol);
            prop_assert!((re.p0() - s.p0()).length() < tol && (re.p1() - s.p1()).length() < tol);
            prop_assert!((rs.sweep - e.sweep).abs() < 1e-9);
        }
    }
}
