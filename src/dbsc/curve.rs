//! The [`DiskBSpline`] type: evaluation of centre, radius, envelope (wu-2021 eq. 9) and the
//! envelope's tangent.

use super::DbscError;
use crate::geom::{Circle, DVec2, perp};
use crate::spline::BSpline;
use glam::DVec3;

/// Which envelope: `Left` is wu-2021's b⁺ (q′⊥ term added), `Right` is b⁻.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// b⁺: the envelope on the left of the direction of travel (serialised `"left"`).
    Left,
    /// b⁻: the envelope on the right of the direction of travel (serialised `"right"`).
    Right,
}

impl Side {
    /// +1 for left, −1 for right: the sign of the q′⊥ term.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }

    /// The opposite side.
    pub fn other(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }
}

/// A point of one envelope with its derivative and the unit vector m = (q± − q)/r.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopePoint {
    /// q±(t) = q(t) + r(t) m±(t), the envelope point (wu-2021 eq. 9).
    pub point: DVec2,
    /// dq±/dt.
    pub deriv: DVec2,
    /// m± with q± = q + r m±, ‖m±‖ = 1, m±·q′ = −r′.
    pub m: DVec2,
}

/// A disk B-spline curve: degree, knots, control disks, closed flag.
#[derive(Clone, Debug, PartialEq)]
pub struct DiskBSpline {
    /// (x, y, r) control values.
    curve: BSpline<DVec3>,
}

fn check_disks(disks: &[Circle]) -> Result<(), DbscError> {
    for (index, d) in disks.iter().enumerate() {
        if !(d.c.x.is_finite() && d.c.y.is_finite() && d.r.is_finite()) {
            return Err(DbscError::NotFinite { index });
        }
        if d.r <= 0.0 {
            return Err(DbscError::Radius { index, radius: d.r });
        }
    }
    Ok(())
}

fn to_xyr(disks: &[Circle]) -> Vec<DVec3> {
    disks
        .iter()
        .map(|d| DVec3::new(d.c.x, d.c.y, d.r))
        .collect()
}

impl DiskBSpline {
    /// An open DBSC on explicit knots (n + p + 1 of them) or, with `None`, clamped uniform
    /// knots on [0, 1].
    pub fn open(
        degree: usize,
        disks: &[Circle],
        knots: Option<Vec<f64>>,
    ) -> Result<Self, DbscError> {
        check_disks(disks)?;
        let ctrl = to_xyr(disks);
        let curve = match knots {
            Some(k) => BSpline::new(degree, k, ctrl)?,
            None => BSpline::clamped_uniform(degree, ctrl)?,
        };
        Ok(DiskBSpline { curve })
    }

    /// A closed DBSC through the cyclic control disks, with the period's n + 1 breakpoints
    /// or, with `None`, uniform breakpoints on [0, 1].
    pub fn closed(
        degree: usize,
        disks: &[Circle],
        breaks: Option<&[f64]>,
    ) -> Result<Self, DbscError> {
        check_disks(disks)?;
        let ctrl = to_xyr(disks);
        let curve = match breaks {
            Some(b) => BSpline::closed_with_breaks(degree, ctrl, b)?,
            None => BSpline::closed_uniform(degree, ctrl)?,
        };
        Ok(DiskBSpline { curve })
    }

    /// Wrap an (x, y, r) B-spline. Radii of the control values are not checked here, so
    /// derived curves (knot insertion, offsets) may pass through this.
    pub fn from_curve(curve: BSpline<DVec3>) -> Self {
        DiskBSpline { curve }
    }

    /// The underlying (x, y, r) B-spline.
    pub fn curve(&self) -> &BSpline<DVec3> {
        &self.curve
    }

    /// The degree p of the centre and radius B-splines.
    pub fn degree(&self) -> usize {
        self.curve.degree()
    }

    /// True for a closed (periodic) DBSC.
    pub fn is_closed(&self) -> bool {
        self.curve.is_closed()
    }

    /// The parameter domain [u_p, u_{n+1}] as (start, end).
    pub fn domain(&self) -> (f64, f64) {
        self.curve.domain()
    }

    /// The distinct knots of the domain (span boundaries), ends included.
    pub fn breakpoints(&self) -> Vec<f64> {
        self.curve.breakpoints()
    }

    /// The control disks (for closed curves, without the wrapped copies).
    pub fn control_disks(&self) -> Vec<Circle> {
        let c = self.curve.ctrl();
        let n = if self.is_closed() {
            c.len() - self.degree()
        } else {
            c.len()
        };
        c[..n]
            .iter()
            .map(|v| Circle::new(v.truncate(), v.z))
            .collect()
    }

    /// The disk ⟨q(t); r(t)⟩.
    pub fn circle_at(&self, t: f64) -> Circle {
        let v = self.point(t);
        Circle::new(v.truncate(), v.z)
    }

    /// Centre q(t).
    pub fn center(&self, t: f64) -> DVec2 {
        self.circle_at(t).c
    }

    /// Radius r(t).
    pub fn radius(&self, t: f64) -> f64 {
        self.point(t).z
    }

    /// (q(t), r(t)) as one point of the curve: P&T A2.3 at order 0 on the stack
    /// ([`BSpline::derivs_array`]), the same arithmetic as [`BSpline::eval`] (A2.2) without
    /// its heap buffers (the skin and its measures evaluate circles millions of times).
    fn point(&self, t: f64) -> DVec3 {
        let [v] = self.curve.derivs_array::<1>(t);
        v
    }

    /// (q^{(k)}(t), r^{(k)}(t)) for k = 0..=order.
    pub fn derivs(&self, t: f64, order: usize) -> Vec<(DVec2, f64)> {
        self.curve
            .derivs(t, order)
            .into_iter()
            .map(|v| (v.truncate(), v.z))
            .collect()
    }

    /// ‖q′(t)‖² − r′(t)²: the envelope exists where this is positive (wu-2021 eq. 8).
    pub fn envelope_discriminant(&self, t: f64) -> f64 {
        let d = self.derivs(t, 1);
        d[1].0.length_squared() - d[1].1 * d[1].1
    }

    /// The envelope point q±(t) = q + r m±, m± = (−r′ q′ ± q′⊥ √(‖q′‖² − r′²)) / ‖q′‖²
    /// (wu-2021 eq. 9), and its derivative
    /// q±′ = q′ + r′ m± + r m±′ with m±′ obtained by differentiating the quotient:
    /// with L = ‖q′‖², s = √(L − r′²), s′ = (q′·q″ − r′r″)/s,
    /// m±′ = [(−r″q′ − r′q″ ± (q″⊥ s + q′⊥ s′)) L − (−r′q′ ± q′⊥ s) 2 q′·q″] / L².
    /// `None` where no real envelope exists (‖q′‖ ≤ |r′|).
    pub fn envelope(&self, side: Side, t: f64) -> Option<EnvelopePoint> {
        envelope_of_jet(side, &self.curve.derivs_array::<3>(t))
    }

    /// τ±(t) = q±′(t)·q′(t) (kruppa-2023 Sec. 3): the envelope runs along the centre curve
    /// where τ± > 0 and backwards (inside a loop) where τ± < 0. `None` without envelope.
    pub fn tau(&self, side: Side, t: f64) -> Option<f64> {
        let e = self.envelope(side, t)?;
        Some(e.deriv.dot(self.derivs(t, 1)[1].0))
    }
}

/// [`DiskBSpline::envelope`] from (x, y, r) and its first two derivatives at one parameter
/// (wu-2021 eq. 9 and its derivative, as documented there).
pub(crate) fn envelope_of_jet(side: Side, d: &[DVec3; 3]) -> Option<EnvelopePoint> {
    let (q, r) = (DVec2::new(d[0].x, d[0].y), d[0].z);
    let (q1, r1) = (DVec2::new(d[1].x, d[1].y), d[1].z);
    let (q2, r2) = (DVec2::new(d[2].x, d[2].y), d[2].z);
    let l = q1.length_squared();
    let disc = l - r1 * r1;
    if disc.is_nan() || disc <= 0.0 || l == 0.0 {
        return None;
    }
    let sg = side.sign();
    let s = disc.sqrt();
    let num = -r1 * q1 + sg * s * perp(q1);
    let m = num / l;
    let s1 = (q1.dot(q2) - r1 * r2) / s;
    let num1 = -r2 * q1 - r1 * q2 + sg * (perp(q2) * s + perp(q1) * s1);
    let m1 = (num1 * l - num * (2.0 * q1.dot(q2))) / (l * l);
    Some(EnvelopePoint {
        point: q + r * m,
        deriv: q1 + r1 * m + r * m1,
        m,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    use crate::dbsc::tangent::tests::dbsc_strategy;

    proptest! {
        #[test]
        fn envelope_invariants(c in dbsc_strategy(), s in 0.0f64..=1.0) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let d = c.derivs(t, 1);
            let (q, r) = d[0];
            let (q1, r1) = d[1];
            for side in [Side::Left, Side::Right] {
                if let Some(e) = c.envelope(side, t) {
                    // ‖q± − q‖ = r and (q± − q)·q′ = −r r′.
                    prop_assert!(((e.point - q).length() - r).abs() <= 1e-9 * r.max(1.0));
                    let scale = (r * q1.length()).max(r * r1.abs()).max(1.0);
                    prop_assert!(((e.point - q).dot(q1) + r * r1).abs() <= 1e-9 * scale);
                    prop_assert!((e.m.length() - 1.0).abs() <= 1e-12);
                    // Left is left of the travel direction.
                    let cr = crate::geom::cross(q1, e.point - q);
                    let lateral = r * (1.0 - r1 * r1 / q1.length_squared()).sqrt() * q1.length();
                    prop_assert!(cr * side.sign() >= -1e-9 * scale, "side {side:?}");
                    prop_assert!((cr.abs() - lateral).abs() <= 1e-7 * scale.max(lateral));
                }
            }
        }

        #[test]
        fn span_jets_match_de_boor(c in dbsc_strategy(), s in 0.0f64..=1.0) {
            // The Bernstein form of each span (Hausdorff bounds evaluate through it) against
            // the B-spline's own derivatives (P&T A2.3) at the same parameter.
            for sp in crate::dbsc::SpanPoly::all(&c) {
                let t = sp.a + s * (sp.b - sp.a);
                let jet = sp.jet(t);
                let de_boor = c.curve().derivs_array::<3>(t);
                let size = c.curve().ctrl().iter().map(|v| v.abs().max_element()).fold(1.0, f64::max);
                for (k, (a, b)) in jet.iter().zip(&de_boor).enumerate() {
                    let scale = size / (sp.b - sp.a).powi(k as i32);
                    prop_assert!((*a - *b).abs().max_element() <= 1e-9 * scale, "order {k}: {a} vs {b}");
                }
                if let (Some(e), Some(f)) = (envelope_of_jet(Side::Left, &jet), c.envelope(Side::Left, t)) {
                    prop_assert!((e.point - f.point).length() <= 1e-9 * size);
                }
            }
        }

        #[test]
        fn envelope_tangent_matches_finite_difference(c in dbsc_strategy(), s in 0.02f64..0.98) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let k = c.curve().knots();
            let span = crate::spline::find_span(k, c.degree(), c.curve().ctrl().len(), t);
            let h = 1e-6 * (k[span + 1] - k[span]);
            prop_assume!(t - h > k[span] && t + h < k[span + 1]);
            // Keep away from the no-envelope boundary, where q± has a square-root singularity.
            prop_assume!(c.envelope_discriminant(t) > 1e-3 * c.derivs(t, 1)[1].0.length_squared());
            for side in [Side::Left, Side::Right] {
                let (Some(e), Some(a), Some(b)) = (c.envelope(side, t), c.envelope(side, t + h), c.envelope(side, t - h)) else { continue };
                let fd = (a.point - b.point) / (2.0 * h);
                let scale = e.deriv.length().max(c.derivs(t, 1)[1].0.length()).max(1.0);
                prop_assert!((fd - e.deriv).length() <= 1e-5 * scale, "fd {fd} d {}", e.deriv);
            }
        }
    }

    #[test]
    fn constant_radius_line_has_parallel_envelopes() {
        let disks = [
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(1.0, 0.0), 1.0),
            Circle::new(DVec2::new(2.0, 0.0), 1.0),
            Circle::new(DVec2::new(3.0, 0.0), 1.0),
        ];
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            let l = c.envelope(Side::Left, t).unwrap();
            let r = c.envelope(Side::Right, t).unwrap();
            assert!((l.point.y - 1.0).abs() < 1e-15);
            assert!((r.point.y + 1.0).abs() < 1e-15);
            assert!((l.point.x - 3.0 * t).abs() < 1e-14);
            assert!(c.tau(Side::Left, t).unwrap() > 0.0);
        }
    }

    #[test]
    fn growing_disk_has_no_envelope() {
        // Centre moves by 1 while the radius grows by 3: ‖q′‖ < |r′| everywhere.
        let disks = [
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(1.0, 0.0), 4.0),
        ];
        let c = DiskBSpline::open(1, &disks, None).unwrap();
        assert!(c.envelope(Side::Left, 0.5).is_none());
        assert!(c.envelope_discriminant(0.5) < 0.0);
    }

    #[test]
    fn bad_disks_are_errors() {
        let disks = [
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(1.0, 0.0), -1.0),
        ];
        assert_eq!(
            DiskBSpline::open(1, &disks, None),
            Err(DbscError::Radius {
                index: 1,
                radius: -1.0
            })
        );
        let disks = [
            Circle::new(DVec2::new(f64::NAN, 0.0), 1.0),
            Circle::new(DVec2::new(1.0, 0.0), 1.0),
        ];
        assert_eq!(
            DiskBSpline::open(1, &disks, None),
            Err(DbscError::NotFinite { index: 0 })
        );
    }
}
