//! The curves the bounds work on: a [`BoundedCurve`] gives pieces, points and an upper
//! bound of ‖x″‖ on a parameter interval; cubics and envelope segments implement it.

use super::HausdorffError;
use crate::dbsc::{Bern, DiskBSpline, EnvelopePoint, Side, SpanPoly, envelope_of_jet};
use crate::geom::bernstein;
use crate::geom::interval::{Interval, Jet};
use crate::geom::{CubicBez, DVec2};
use std::borrow::Cow;

/// A parametric plane curve for the bounds: pieces on which it is C², evaluation, and an
/// upper bound of ‖x″‖ on a parameter interval inside one piece.
pub trait BoundedCurve {
    /// Parameter intervals on which the curve is C² (in order, contiguous).
    fn pieces(&self) -> Vec<(f64, f64)>;
    /// The curve point at parameter `t`; an error where the curve does not exist (an envelope where
    /// ‖q′‖ ≤ |r′|).
    fn point(&self, t: f64) -> Result<DVec2, HausdorffError>;
    /// Upper bound of sup ‖x″(t)‖ on [t0, t1] ⊂ one piece (may be +∞).
    fn d2_bound(&self, t0: f64, t1: f64) -> f64;
    /// The curve point and first derivative at `t`, for the foot-point searches of the
    /// matching bounds (any parameter gives a valid bound; the derivative only helps to
    /// find a near one).
    fn point_tangent(&self, t: f64) -> Result<(DVec2, DVec2), HausdorffError>;
    /// Upper bound of sup ‖x″‖ on [t0, t1], which may cross pieces.
    fn d2_bound_any(&self, t0: f64, t1: f64) -> f64 {
        let (a, b) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        let mut m: f64 = 0.0;
        for (p0, p1) in self.pieces() {
            let (u0, u1) = (a.max(p0), b.min(p1));
            if u1 >= u0 {
                m = m.max(self.d2_bound(u0, u1));
            }
        }
        m
    }
}

impl BoundedCurve for CubicBez {
    fn pieces(&self) -> Vec<(f64, f64)> {
        vec![(0.0, 1.0)]
    }
    fn point(&self, t: f64) -> Result<DVec2, HausdorffError> {
        Ok(self.eval(t))
    }
    fn d2_bound(&self, t0: f64, t1: f64) -> f64 {
        self.deriv2(t0).length().max(self.deriv2(t1).length())
    }
    fn point_tangent(&self, t: f64) -> Result<(DVec2, DVec2), HausdorffError> {
        Ok((self.eval(t), self.deriv(t)))
    }
}

/// One side's envelope of a DBSC on [t_a, t_b].
#[derive(Clone, Debug)]
pub struct EnvelopeSegment<'a> {
    curve: &'a DiskBSpline,
    side: Side,
    /// The Bernstein forms of the knot spans meeting [t_a, t_b], in order.
    spans: Cow<'a, [SpanPoly]>,
    t_a: f64,
    t_b: f64,
}

impl<'a> EnvelopeSegment<'a> {
    /// The envelope on `side` of `curve` over [t_a, t_b], which must be a non-empty interval inside
    /// the curve's domain.
    pub fn new(
        curve: &'a DiskBSpline,
        side: Side,
        t_a: f64,
        t_b: f64,
    ) -> Result<Self, HausdorffError> {
        Self::check_interval(curve, t_a, t_b)?;
        let spans = curve
            .breakpoints()
            .windows(2)
            .filter(|w| w[1] > t_a && w[0] < t_b && w[1] > w[0])
            .map(|w| SpanPoly::new(curve, w[0], w[1]))
            .collect();
        Ok(EnvelopeSegment {
            curve,
            side,
            spans: Cow::Owned(spans),
            t_a,
            t_b,
        })
    }

    /// [`Self::new`] from the spans of the whole curve computed once
    /// ([`SpanPoly::all`]): the segment borrows the ones meeting [t_a, t_b] (the same
    /// spans `new` computes), so the many segments of one skinning share them.
    pub(crate) fn with_spans(
        curve: &'a DiskBSpline,
        all: &'a [SpanPoly],
        side: Side,
        t_a: f64,
        t_b: f64,
    ) -> Result<Self, HausdorffError> {
        Self::check_interval(curve, t_a, t_b)?;
        let first = all.partition_point(|s| s.b <= t_a);
        let end = first + all[first..].partition_point(|s| s.a < t_b);
        Ok(EnvelopeSegment {
            curve,
            side,
            spans: Cow::Borrowed(&all[first..end]),
            t_a,
            t_b,
        })
    }

    fn check_interval(curve: &DiskBSpline, t_a: f64, t_b: f64) -> Result<(), HausdorffError> {
        let (lo, hi) = curve.domain();
        if !(t_a < t_b && t_a >= lo && t_b <= hi) {
            return Err(HausdorffError::Interval { t_a, t_b, lo, hi });
        }
        Ok(())
    }

    /// The envelope point at `t` from the Bernstein form of its span (the curve's own
    /// evaluation outside the spans, which [`Self::pieces`] never asks for).
    fn envelope(&self, t: f64) -> Result<EnvelopePoint, HausdorffError> {
        let jet = match self.spans.iter().find(|s| t >= s.a && t <= s.b) {
            Some(sp) => sp.jet(t),
            None => self.curve.curve().derivs_array::<3>(t),
        };
        envelope_of_jet(self.side, &jet).ok_or(HausdorffError::NoEnvelope { t })
    }
}

impl BoundedCurve for EnvelopeSegment<'_> {
    fn pieces(&self) -> Vec<(f64, f64)> {
        self.spans
            .iter()
            .map(|s| (s.a.max(self.t_a), s.b.min(self.t_b)))
            .collect()
    }
    fn point(&self, t: f64) -> Result<DVec2, HausdorffError> {
        self.envelope(t).map(|e| e.point)
    }
    fn point_tangent(&self, t: f64) -> Result<(DVec2, DVec2), HausdorffError> {
        self.envelope(t).map(|e| (e.point, e.deriv))
    }
    fn d2_bound(&self, t0: f64, t1: f64) -> f64 {
        let Some(sp) = self
            .spans
            .iter()
            .find(|s| t0 >= s.a && t1 <= s.b)
            .or_else(|| self.spans.iter().find(|s| t0 >= s.a && t0 <= s.b))
        else {
            return f64::INFINITY;
        };
        envelope_d2_bound(sp, self.side.sign(), t0.max(sp.a), t1.min(sp.b))
    }
    /// The trait's default over [`Self::pieces`], walking the spans without collecting them.
    fn d2_bound_any(&self, t0: f64, t1: f64) -> f64 {
        let (a, b) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        let mut m: f64 = 0.0;
        for s in self.spans.iter() {
            let (p0, p1) = (s.a.max(self.t_a), s.b.min(self.t_b));
            let (u0, u1) = (a.max(p0), b.min(p1));
            if u1 >= u0 {
                m = m.max(self.d2_bound(u0, u1));
            }
        }
        m
    }
}

/// Ranges of the t-derivatives 0..=3 of a span polynomial on [t0, t1]. Each derivative is
/// taken on the whole span (Bernstein coefficients n(bᵢ₊₁ − bᵢ), d/dt = d/du / h), then cut
/// to [t0, t1], whose coefficients enclose it (convex hull property). Cutting first and
/// differencing the piece's coefficients would divide their rounding errors by
/// (t1 − t0)ᵏ: on the narrow intervals bisection reaches, that error swamps the range and
/// the enclosure fails. Stack buffers for polynomials up to [`bernstein::SMALL`]
/// coefficients.
pub(super) fn deriv_ranges(b: &Bern, sp: &SpanPoly, t0: f64, t1: f64) -> [Interval; 4] {
    let n = b.0.len();
    if n > bernstein::SMALL {
        return deriv_ranges_heap(b, sp, t0, t1);
    }
    if let Ok(c) = <&[f64; 4]>::try_from(&b.0[..]) {
        return cubic_deriv_ranges(c, sp, t0, t1);
    }
    let mut bufs = [[0.0f64; bernstein::SMALL]; 2];
    let [d, piece] = &mut bufs;
    deriv_ranges_in(&b.0, sp, t0, t1, &mut d[..n], &mut piece[..n])
}

/// The span parameters u0 ≤ u1 in [0, 1] of [t0, t1].
pub(super) fn span_params(sp: &SpanPoly, t0: f64, t1: f64) -> (f64, f64) {
    let h = sp.b - sp.a;
    let u0 = ((t0 - sp.a) / h).clamp(0.0, 1.0);
    let u1 = ((t1 - sp.a) / h).clamp(0.0, 1.0);
    (u0.min(u1), u0.max(u1))
}

/// [`deriv_ranges`] of a cubic: the steps of [`deriv_ranges_in`] (the same values) on
/// fixed-size arrays, which the compiler unrolls.
pub(super) fn cubic_deriv_ranges(c: &[f64; 4], sp: &SpanPoly, t0: f64, t1: f64) -> [Interval; 4] {
    let (u0, u1) = span_params(sp, t0, t1);
    let h = sp.b - sp.a;
    // bernstein::deriv_in_place, length by length.
    let d1 = [
        3.0 * (c[1] - c[0]),
        3.0 * (c[2] - c[1]),
        3.0 * (c[3] - c[2]),
    ];
    let d2 = [2.0 * (d1[1] - d1[0]), 2.0 * (d1[2] - d1[1])];
    let d3 = d2[1] - d2[0];
    let iv = |(lo, hi): (f64, f64), f: f64| Interval::new(lo * f, hi * f);
    let (f1, f2, f3) = (1.0 / h, 1.0 / h / h, 1.0 / h / h / h);
    [
        iv(bernstein::range(&bernstein::sub_array(c, u0, u1)), 1.0),
        iv(bernstein::range(&bernstein::sub_array(&d1, u0, u1)), f1),
        iv(bernstein::range(&bernstein::sub_array(&d2, u0, u1)), f2),
        iv((d3, d3), f3),
    ]
}

/// [`deriv_ranges`] with buffers `d` and `piece` as long as the polynomial `b`.
#[inline(always)]
pub(super) fn deriv_ranges_in(
    b: &[f64],
    sp: &SpanPoly,
    t0: f64,
    t1: f64,
    d: &mut [f64],
    piece: &mut [f64],
) -> [Interval; 4] {
    let (u0, u1) = span_params(sp, t0, t1);
    let h = sp.b - sp.a;
    d.copy_from_slice(b);
    let mut len = d.len();
    let mut out = [Interval::pt(0.0); 4];
    let mut f = 1.0;
    for (k, o) in out.iter_mut().enumerate() {
        if k > 0 {
            len = bernstein::deriv_in_place(&mut d[..len]);
            f /= h;
        }
        bernstein::sub_into(&d[..len], u0, u1, &mut piece[..len]);
        let (lo, hi) = bernstein::range(&piece[..len]);
        *o = Interval::new(lo * f, hi * f);
    }
    out
}

/// [`deriv_ranges`] for polynomials longer than the small stack buffer (strokes of degree
/// above 7).
pub(super) fn deriv_ranges_heap(b: &Bern, sp: &SpanPoly, t0: f64, t1: f64) -> [Interval; 4] {
    let (u0, u1) = span_params(sp, t0, t1);
    let h = sp.b - sp.a;
    let mut p = b.clone();
    let mut out = [Interval::pt(0.0); 4];
    let mut f = 1.0;
    for (k, o) in out.iter_mut().enumerate() {
        if k > 0 {
            p = p.deriv();
            f /= h;
        }
        let (lo, hi) = p.sub(u0, u1).range();
        *o = Interval::new(lo * f, hi * f);
    }
    out
}

/// Upper bound of ‖q±″‖ on [t0, t1] inside one span, by interval jets of
/// q±″ = q″ + r″ m + 2 r′ m′ + r m″ with m = (−r′q′ + σ s q′⊥)/L. +∞ when the enclosure of
/// s² = ‖q′‖² − r′² is not positive.
pub(super) fn envelope_d2_bound(sp: &SpanPoly, sigma: f64, t0: f64, t1: f64) -> f64 {
    let x = deriv_ranges(&sp.x, sp, t0, t1);
    let y = deriv_ranges(&sp.y, sp, t0, t1);
    let r = deriv_ranges(&sp.r, sp, t0, t1);
    let jet = |d: &[Interval; 4]| Jet {
        v: d[1],
        d1: d[2],
        d2: d[3],
    };
    let (ax, ay, b) = (jet(&x), jet(&y), jet(&r));
    let l = ax.sqr().add(ay.sqr());
    let s2 = l.sub(b.sqr());
    if !s2.v.positive() || !l.v.positive() {
        return f64::INFINITY;
    }
    let s = s2.sqrt();
    let inv_l = l.recip();
    // m = (−b a + σ s a⊥)/L with a⊥ = (−ay, ax).
    let mx = b.mul(ax).scale(-1.0).sub(s.mul(ay).scale(sigma)).mul(inv_l);
    let my = b.mul(ay).scale(-1.0).add(s.mul(ax).scale(sigma)).mul(inv_l);
    let comp = |q2: Interval, m: Jet| {
        q2.add(r[2].mul(m.v.clip_unit()))
            .add(r[1].mul(m.d1).scale(2.0))
            .add(r[0].mul(m.d2))
    };
    let (cx, cy) = (comp(x[2], mx), comp(y[2], my));
    let v = (cx.mag().powi(2) + cy.mag().powi(2)).sqrt();
    if v.is_finite() { v } else { f64::INFINITY }
}
