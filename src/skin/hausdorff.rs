//! Hausdorff distance between a skin segment and its envelope segment (kruppa-2023 eqs.
//! 20–21) with guaranteed lower and upper bounds.
//!
//! Method: branch and bound with second-order enclosures. For a C² curve y on [t0, t1] every
//! point lies within (t1 − t0)²·M₂/8 of its chord (M₂ ≥ sup‖y″‖), because the interpolation
//! error e(λ) = ∫ G(λ, μ) y″ dμ has a non-negative Green's function with ∫G ≤ Δt²/8. So
//! * the distance of a point x to y restricted to [t0, t1] is at least
//!   dist(x, chord) − Δt² M₂/8 (lower bound) and at most ‖x − y(t_i)‖ (upper bound);
//! * for a piece [s0, s1] of the other curve x whose ends have near points y(t0), y(t1),
//!   sup_s d(x(s), y) ≤ max(‖x(s0) − y(t0)‖, ‖x(s1) − y(t1)‖) + (Δs² M₂ˣ + Δt² M₂ʸ)/8, since
//!   the norm of the linearly matched difference is convex; near jumps of the nearest point
//!   the constant matching y(t0) (or y(t1)) is used instead.
//!
//! M₂ of a cubic on [s0, s1] is max(‖C″(s0)‖, ‖C″(s1)‖) (C″ is linear, its norm convex).
//! M₂ of the envelope q± = q + r m± is enclosed by interval arithmetic on second-order jets of
//! m± = (−r′q′ + σ s q′⊥)/‖q′‖², s = √(‖q′‖² − r′²) (wu-2021 eq. 9), fed with ranges of the
//! span polynomials q′, q″, q‴, r, r′, r″, r‴ taken from their Bernstein coefficients on the
//! sub-interval (convex hull property). Every bound is rigorous up to floating-point
//! rounding; refinement stops when upper − lower ≤ the requested gap.
//!
//! The matching bound needs near points, not nearest ones: any y(t) gives an upper bound of
//! d(x, Y). So every bound first tries a matching-bound search whose near points come from
//! a few Gauss–Newton foot-point steps, with a certified point-distance search (the lower
//! bound) only where it can settle the question: none for "D_H ≤ ε − gap" (which the full
//! search would decide the same way), one at the farthest sample for "D_H > ε", one or two
//! for the gap of the final report. Only when that fails does the full search run, with a
//! point-distance search at every sample of X.

use crate::dbsc::{Bern, DiskBSpline, EnvelopePoint, Side, SpanPoly, envelope_of_jet};
use crate::geom::bernstein;
use crate::geom::{CubicBez, DVec2, Line};
use std::borrow::Cow;
use std::cell::OnceCell;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Initial pieces per curve piece before refinement: enough to separate the branches of a
/// looping envelope without wasting work on smooth ones.
const INITIAL_SPLITS: usize = 8;

/// Cap on branch-and-bound nodes per directed distance: the bounds stay valid when it is
/// hit, only the gap may stay wider than asked (reported through the result).
const MAX_NODES: usize = 20_000;

/// Cap on nodes of one point-to-curve distance.
const MAX_POINT_NODES: usize = 4_000;

/// Cap on all refinement steps (directed nodes plus point-distance nodes, both directions)
/// of one Hausdorff bound. Without it the two caps above multiply (80 million steps, minutes
/// of work) on envelopes whose second-derivative bound is infinite (kinks of degree-1
/// strokes, points where ‖q′‖ ≈ |r′|). Smooth skin segments need a few thousand steps; the
/// bounds stay valid when the cap is hit, only the gap stays wider than asked.
pub const MAX_BOUND_WORK: usize = 200_000;

/// Parameter intervals narrower than this are not split further (they are leaves whose
/// bounds are kept as they are): bisection below it only reaches floating-point noise,
/// where the second-order enclosure (Δt²·M₂/8) may be 0·∞ = NaN.
const MIN_SPLIT_WIDTH: f64 = 1e-12;

/// A refinement budget shared by the loops of one or several Hausdorff bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Work {
    /// Refinement steps still allowed.
    pub left: usize,
    /// Refinement steps spent so far.
    pub spent: usize,
}

impl Work {
    /// A budget of `steps` refinement steps.
    pub fn new(steps: usize) -> Work {
        Work {
            left: steps,
            spent: 0,
        }
    }
    /// Spends one step; false when the budget is exhausted.
    fn take(&mut self) -> bool {
        if self.left == 0 {
            return false;
        }
        self.left -= 1;
        self.spent += 1;
        true
    }
}

/// A bound that is NaN (0·∞ on an interval of zero width) read as "no information".
fn or_inf(x: f64) -> f64 {
    if x.is_nan() { f64::INFINITY } else { x }
}

/// Errors of the Hausdorff bounds.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HausdorffError {
    /// The requested gap between the bounds is not positive and finite.
    #[error("gap {0} must be positive and finite")]
    Gap(f64),
    /// The envelope interval is empty or leaves the curve's domain.
    #[error("envelope interval [{t_a}, {t_b}] is empty or outside the domain [{lo}, {hi}]")]
    Interval {
        /// Start of the requested envelope interval.
        t_a: f64,
        /// End of the requested envelope interval.
        t_b: f64,
        /// Start of the DBSC domain.
        lo: f64,
        /// End of the DBSC domain.
        hi: f64,
    },
    /// The envelope does not exist at a parameter: there ‖q′‖ ≤ |r′| and m± of wu-2021 eq. 9 is not
    /// real.
    #[error("no real envelope at t = {t} (‖q′‖ ≤ |r′|)")]
    NoEnvelope {
        /// The DBSC parameter where the envelope is missing.
        t: f64,
    },
}

/// Guaranteed bounds lower ≤ D_H ≤ upper.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct HausdorffBounds {
    /// Lower bound of the Hausdorff distance (model units).
    pub lower: f64,
    /// Upper bound of the Hausdorff distance (model units); a segment meets ε when this is ≤ ε.
    pub upper: f64,
}

impl HausdorffBounds {
    /// Width of the enclosure, `upper − lower`.
    pub fn gap(&self) -> f64 {
        self.upper - self.lower
    }
}

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

/// A closed real interval.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Iv {
    lo: f64,
    hi: f64,
}

impl Iv {
    fn new(lo: f64, hi: f64) -> Iv {
        Iv { lo, hi }
    }
    fn pt(x: f64) -> Iv {
        Iv::new(x, x)
    }
    fn add(self, o: Iv) -> Iv {
        Iv::new(self.lo + o.lo, self.hi + o.hi)
    }
    fn sub(self, o: Iv) -> Iv {
        Iv::new(self.lo - o.hi, self.hi - o.lo)
    }
    /// The product's range: the least and greatest of the four end products (each
    /// comparison picks one of its operands; the operands here are finite).
    fn mul(self, o: Iv) -> Iv {
        let (a, b, c, d) = (
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        );
        let min = |x: f64, y: f64| if x < y { x } else { y };
        let max = |x: f64, y: f64| if x > y { x } else { y };
        Iv::new(min(min(a, b), min(c, d)), max(max(a, b), max(c, d)))
    }
    /// k·x: the ends scaled, swapped when k < 0.
    fn scale(self, k: f64) -> Iv {
        if k >= 0.0 {
            Iv::new(self.lo * k, self.hi * k)
        } else {
            Iv::new(self.hi * k, self.lo * k)
        }
    }
    /// 1/x; NaN-free only when 0 ∉ x (callers check `positive`).
    fn recip(self) -> Iv {
        Iv::new(1.0 / self.hi, 1.0 / self.lo)
    }
    fn sqrt(self) -> Iv {
        Iv::new(self.lo.max(0.0).sqrt(), self.hi.max(0.0).sqrt())
    }
    fn positive(self) -> bool {
        self.lo > 0.0
    }
    fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }
    fn clip_unit(self) -> Iv {
        Iv::new(self.lo.max(-1.0), self.hi.min(1.0))
    }
}

/// A second-order jet (f, f′, f″) of interval enclosures.
#[derive(Clone, Copy, Debug)]
struct Jet {
    v: Iv,
    d1: Iv,
    d2: Iv,
}

impl Jet {
    fn add(self, o: Jet) -> Jet {
        Jet {
            v: self.v.add(o.v),
            d1: self.d1.add(o.d1),
            d2: self.d2.add(o.d2),
        }
    }
    fn sub(self, o: Jet) -> Jet {
        Jet {
            v: self.v.sub(o.v),
            d1: self.d1.sub(o.d1),
            d2: self.d2.sub(o.d2),
        }
    }
    fn scale(self, k: f64) -> Jet {
        Jet {
            v: self.v.scale(k),
            d1: self.d1.scale(k),
            d2: self.d2.scale(k),
        }
    }
    /// (fg)′ = f′g + fg′, (fg)″ = f″g + 2f′g′ + fg″.
    fn mul(self, o: Jet) -> Jet {
        Jet {
            v: self.v.mul(o.v),
            d1: self.d1.mul(o.v).add(self.v.mul(o.d1)),
            d2: self
                .d2
                .mul(o.v)
                .add(self.d1.mul(o.d1).scale(2.0))
                .add(self.v.mul(o.d2)),
        }
    }
    /// f², [`Self::mul`] of `self` by itself with each product taken once: the same
    /// intervals bit for bit (the two cross terms of a product are equal).
    fn sqr(self) -> Jet {
        let d1v = self.d1.mul(self.v);
        let d2v = self.d2.mul(self.v);
        Jet {
            v: self.v.mul(self.v),
            d1: d1v.add(d1v),
            d2: d2v.add(self.d1.mul(self.d1).scale(2.0)).add(d2v),
        }
    }
    /// g = 1/f: g′ = −f′ g², g″ = 2 f′² g³ − f″ g². Requires f > 0.
    fn recip(self) -> Jet {
        let g = self.v.recip();
        let g2 = g.mul(g);
        Jet {
            v: g,
            d1: self.d1.mul(g2).scale(-1.0),
            d2: self
                .d1
                .mul(self.d1)
                .mul(g2.mul(g))
                .scale(2.0)
                .sub(self.d2.mul(g2)),
        }
    }
    /// g = √f: g′ = f′/(2g), g″ = (f″ − 2g′²)/(2g). Requires f > 0.
    fn sqrt(self) -> Jet {
        let g = self.v.sqrt();
        let inv2g = g.scale(2.0).recip();
        let g1 = self.d1.mul(inv2g);
        Jet {
            v: g,
            d1: g1,
            d2: self.d2.sub(g1.mul(g1).scale(2.0)).mul(inv2g),
        }
    }
}

/// Ranges of the t-derivatives 0..=3 of a span polynomial on [t0, t1]. Each derivative is
/// taken on the whole span (Bernstein coefficients n(bᵢ₊₁ − bᵢ), d/dt = d/du / h), then cut
/// to [t0, t1], whose coefficients enclose it (convex hull property). Cutting first and
/// differencing the piece's coefficients would divide their rounding errors by
/// (t1 − t0)ᵏ: on the narrow intervals bisection reaches, that error swamps the range and
/// the enclosure fails. Stack buffers for polynomials up to [`bernstein::SMALL`]
/// coefficients.
fn deriv_ranges(b: &Bern, sp: &SpanPoly, t0: f64, t1: f64) -> [Iv; 4] {
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
fn span_params(sp: &SpanPoly, t0: f64, t1: f64) -> (f64, f64) {
    let h = sp.b - sp.a;
    let u0 = ((t0 - sp.a) / h).clamp(0.0, 1.0);
    let u1 = ((t1 - sp.a) / h).clamp(0.0, 1.0);
    (u0.min(u1), u0.max(u1))
}

/// [`deriv_ranges`] of a cubic: the steps of [`deriv_ranges_in`] (the same values) on
/// fixed-size arrays, which the compiler unrolls.
fn cubic_deriv_ranges(c: &[f64; 4], sp: &SpanPoly, t0: f64, t1: f64) -> [Iv; 4] {
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
    let iv = |(lo, hi): (f64, f64), f: f64| Iv::new(lo * f, hi * f);
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
fn deriv_ranges_in(
    b: &[f64],
    sp: &SpanPoly,
    t0: f64,
    t1: f64,
    d: &mut [f64],
    piece: &mut [f64],
) -> [Iv; 4] {
    let (u0, u1) = span_params(sp, t0, t1);
    let h = sp.b - sp.a;
    d.copy_from_slice(b);
    let mut len = d.len();
    let mut out = [Iv::pt(0.0); 4];
    let mut f = 1.0;
    for (k, o) in out.iter_mut().enumerate() {
        if k > 0 {
            len = bernstein::deriv_in_place(&mut d[..len]);
            f /= h;
        }
        bernstein::sub_into(&d[..len], u0, u1, &mut piece[..len]);
        let (lo, hi) = bernstein::range(&piece[..len]);
        *o = Iv::new(lo * f, hi * f);
    }
    out
}

/// [`deriv_ranges`] for polynomials longer than the small stack buffer (strokes of degree
/// above 7).
fn deriv_ranges_heap(b: &Bern, sp: &SpanPoly, t0: f64, t1: f64) -> [Iv; 4] {
    let (u0, u1) = span_params(sp, t0, t1);
    let h = sp.b - sp.a;
    let mut p = b.clone();
    let mut out = [Iv::pt(0.0); 4];
    let mut f = 1.0;
    for (k, o) in out.iter_mut().enumerate() {
        if k > 0 {
            p = p.deriv();
            f /= h;
        }
        let (lo, hi) = p.sub(u0, u1).range();
        *o = Iv::new(lo * f, hi * f);
    }
    out
}

/// Upper bound of ‖q±″‖ on [t0, t1] inside one span, by interval jets of
/// q±″ = q″ + r″ m + 2 r′ m′ + r m″ with m = (−r′q′ + σ s q′⊥)/L. +∞ when the enclosure of
/// s² = ‖q′‖² − r′² is not positive.
fn envelope_d2_bound(sp: &SpanPoly, sigma: f64, t0: f64, t1: f64) -> f64 {
    let x = deriv_ranges(&sp.x, sp, t0, t1);
    let y = deriv_ranges(&sp.y, sp, t0, t1);
    let r = deriv_ranges(&sp.r, sp, t0, t1);
    let jet = |d: &[Iv; 4]| Jet {
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
    let comp = |q2: Iv, m: Jet| {
        q2.add(r[2].mul(m.v.clip_unit()))
            .add(r[1].mul(m.d1).scale(2.0))
            .add(r[0].mul(m.d2))
    };
    let (cx, cy) = (comp(x[2], mx), comp(y[2], my));
    let v = (cx.mag().powi(2) + cy.mag().powi(2)).sqrt();
    if v.is_finite() { v } else { f64::INFINITY }
}

/// A node: parameter interval with a key for the heap.
#[derive(Clone, Copy, Debug)]
struct Node {
    key: f64,
    t0: f64,
    t1: f64,
    p0: DVec2,
    p1: DVec2,
    /// For directed nodes: near-point data at the ends (distance bound and parameter).
    u0: f64,
    u1: f64,
    n0: f64,
    n1: f64,
    /// The second-derivative bounds the key was computed with: M₂ of the bisected curve on
    /// [t0, t1] and, for matching nodes, M₂ of Y between the ends' near points u0, u1.
    m2x: f64,
    m2y: f64,
    /// Whether `m2x` and `m2y` are this node's own bounds. A child of a bisection starts
    /// with its parent's: the supremum over a sub-interval is at most that over the
    /// interval, so its key is a valid bound, only looser. It computes its own (the
    /// searches' largest cost, [`BoundedCurve::d2_bound`]) only when it reaches the top of
    /// the heap, and many children never do before a search ends. The top node is always
    /// refined before it is read, so (the bounds nest, test `second_derivative_bounds_nest`)
    /// the heap's top key is the one an eager computation would have there: every
    /// decision, bisection and returned bound stays the same.
    own: bool,
}

impl Node {
    /// The near-point data of a directed node's ends (upper bounds only).
    fn ends(&self) -> (PointDist, PointDist) {
        let end = |upper, t| PointDist {
            lower: 0.0,
            upper,
            t,
        };
        (end(self.n0, self.u0), end(self.n1, self.u1))
    }
}

impl PartialEq for Node {
    fn eq(&self, o: &Self) -> bool {
        self.key == o.key
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    fn cmp(&self, o: &Self) -> Ordering {
        self.key.total_cmp(&o.key)
    }
}

/// Bounds of d(x, Y) and a parameter of Y where the upper bound is attained.
#[derive(Clone, Copy, Debug)]
struct PointDist {
    lower: f64,
    upper: f64,
    t: f64,
}

fn initial_grid(c: &dyn BoundedCurve) -> Vec<f64> {
    grid_of(c, INITIAL_SPLITS)
}

/// Parameters splitting each piece of `c` into `n` equal parts (piece ends included once).
fn grid_of(c: &dyn BoundedCurve, n: usize) -> Vec<f64> {
    let pieces = c.pieces();
    let mut ts = Vec::with_capacity(pieces.len() * (n + 1));
    for (a, b) in pieces {
        for i in 0..n {
            ts.push(a + (b - a) * i as f64 / n as f64);
        }
        if ts.last() != Some(&b) {
            ts.push(b);
        }
    }
    ts.dedup();
    ts
}

/// The curve Y of one directed distance with its initial grid and the second-derivative
/// bound of each grid window, computed once: every point-distance search of the directed
/// bound (one per sample of X) starts from all windows of the grid.
struct Target<'a> {
    c: &'a dyn BoundedCurve,
    /// The initial grid (parameter, point).
    grid: Vec<(f64, DVec2)>,
    /// Per grid window: M₂ of Y on it ([`BoundedCurve::d2_bound`]), or `None` when the
    /// window lies in no single piece.
    windows: Vec<Option<f64>>,
}

impl<'a> Target<'a> {
    fn new(c: &'a dyn BoundedCurve) -> Result<Self, HausdorffError> {
        let grid: Vec<(f64, DVec2)> = initial_grid(c)
            .into_iter()
            .map(|t| c.point(t).map(|p| (t, p)))
            .collect::<Result<_, _>>()?;
        let pieces = c.pieces();
        let windows = grid
            .windows(2)
            .map(|w| {
                let (t0, t1) = (w[0].0, w[1].0);
                let inside = t1 > t0 && pieces.iter().any(|&(a, b)| t0 >= a && t1 <= b);
                inside.then(|| c.d2_bound(t0, t1))
            })
            .collect();
        Ok(Target { c, grid, windows })
    }
}

/// How far a curve on [t0, t1] with M₂ ≥ sup‖y″‖ there may stray from its chord:
/// (t1 − t0)²·M₂/8 (+∞ for no information).
fn slack(t0: f64, t1: f64, m2: f64) -> f64 {
    or_inf((t1 - t0).powi(2) * m2 / 8.0)
}

/// d(x, Y) to within `tol` by best-first branch and bound on Y's chords, starting from the
/// windows of Y's initial grid. `heap` is a buffer reused across calls (cleared here).
fn point_distance(
    x: DVec2,
    y: &Target,
    hint: Option<f64>,
    tol: f64,
    work: &mut Work,
    heap: &mut BinaryHeap<Node>,
) -> Result<PointDist, HausdorffError> {
    let grid = &y.grid;
    let mut best = PointDist {
        lower: 0.0,
        upper: f64::INFINITY,
        t: grid.first().map(|g| g.0).unwrap_or(0.0),
    };
    let upd = |t: f64, p: DVec2, best: &mut PointDist| {
        let d = x.distance(p);
        if d < best.upper {
            best.upper = d;
            best.t = t;
        }
    };
    if let Some(h) = hint {
        upd(h, y.c.point(h)?, &mut best);
    }
    heap.clear();
    let lb_e = |e: f64, p0: DVec2, p1: DVec2| {
        let l = Line::new(p0, p1).distance(x) - e;
        if l.is_nan() { f64::NEG_INFINITY } else { l }
    };
    // Smallest lower bound of the leaves (nodes too narrow to split).
    let mut leaf_lower = f64::INFINITY;
    for (w, e) in grid.windows(2).zip(&y.windows) {
        let (t0, p0) = w[0];
        let (t1, p1) = w[1];
        upd(t0, p0, &mut best);
        upd(t1, p1, &mut best);
        let Some(m2) = *e else {
            continue;
        };
        let key = lb_e(slack(t0, t1, m2), p0, p1);
        let mut nd = node(-key, t0, t1, p0, p1);
        nd.m2x = m2;
        heap.push(nd);
    }
    let mut count = 0;
    while let Some(mut nd) = heap.pop() {
        if !nd.own {
            // Its own slack; pruned when that puts it past the best distance.
            nd.m2x = y.c.d2_bound(nd.t0, nd.t1);
            nd.own = true;
            let l = lb_e(slack(nd.t0, nd.t1, nd.m2x), nd.p0, nd.p1);
            if l < best.upper - tol {
                nd.key = -l;
                heap.push(nd);
            }
            continue;
        }
        let l = -nd.key;
        if l >= best.upper - tol || count >= MAX_POINT_NODES || !work.take() {
            // Pruned nodes had lower bounds ≥ upper − tol; the heap's minimum is l.
            best.lower = l.min(best.upper - tol).min(leaf_lower).max(0.0);
            return Ok(best);
        }
        count += 1;
        let tm = 0.5 * (nd.t0 + nd.t1);
        if !(nd.t1 - nd.t0 > MIN_SPLIT_WIDTH && tm > nd.t0 && tm < nd.t1) {
            leaf_lower = leaf_lower.min(l);
            continue;
        }
        let pm = y.c.point(tm)?;
        upd(tm, pm, &mut best);
        for (a, pa, b, pb) in [(nd.t0, nd.p0, tm, pm), (tm, pm, nd.t1, nd.p1)] {
            let key = lb_e(slack(a, b, nd.m2x), pa, pb);
            if key < best.upper - tol {
                let mut child = node(-key, a, b, pa, pb);
                (child.m2x, child.own) = (nd.m2x, false);
                heap.push(child);
            }
        }
    }
    best.lower = (best.upper - tol).min(leaf_lower).max(0.0);
    Ok(best)
}

fn node(key: f64, t0: f64, t1: f64, p0: DVec2, p1: DVec2) -> Node {
    Node {
        key,
        t0,
        t1,
        p0,
        p1,
        u0: 0.0,
        u1: 0.0,
        n0: 0.0,
        n1: 0.0,
        m2x: f64::INFINITY,
        m2y: f64::INFINITY,
        own: true,
    }
}

/// Upper bound of sup d(x(s), Y) over s ∈ [s0, s1] (inside one piece of X) from points
/// y(a.t), y(b.t) at distances ≤ a.upper, b.upper of the ends (any points of Y will do),
/// with M₂ˣ = `m2x` ≥ sup‖x″‖ on [s0, s1] and M₂ʸ = `m2y` ≥ sup‖y″‖ between a.t and b.t.
fn match_bound(
    (s0, p0, a): (f64, DVec2, &PointDist),
    (s1, p1, b): (f64, DVec2, &PointDist),
    m2x: f64,
    m2y: f64,
) -> f64 {
    let ex = (s1 - s0).powi(2) * m2x / 8.0;
    let ey = (b.t - a.t).powi(2) * m2y / 8.0;
    let linear = or_inf(a.upper.max(b.upper) + or_inf(ex) + or_inf(ey));
    // Constant matching: ‖x(s) − y(t_i)‖ is convex along the chord of x, so at most
    // its larger end value, and ‖x(s1) − y(t0)‖ ≤ ‖x(s0) − y(t0)‖ + ‖x(s1) − x(s0)‖.
    let c = or_inf(a.upper.min(b.upper) + p1.distance(p0) + or_inf(ex));
    linear.min(c)
}

/// A node of X on [s0, s1] keyed by [`match_bound`] with M₂ˣ = `m2x`, M₂ʸ = `m2y`, with its
/// ends' near-point data.
fn match_node_with(
    (s0, p0, a): (f64, DVec2, &PointDist),
    (s1, p1, b): (f64, DVec2, &PointDist),
    m2x: f64,
    m2y: f64,
) -> Node {
    let mut nd = node(
        match_bound((s0, p0, a), (s1, p1, b), m2x, m2y),
        s0,
        s1,
        p0,
        p1,
    );
    (nd.u0, nd.u1, nd.n0, nd.n1) = (a.t, b.t, a.upper, b.upper);
    (nd.m2x, nd.m2y) = (m2x, m2y);
    nd
}

/// A node of X on [s0, s1] keyed by [`match_bound`] with its own second-derivative bounds.
fn match_node(
    xc: &dyn BoundedCurve,
    yc: &dyn BoundedCurve,
    (s0, p0, a): (f64, DVec2, &PointDist),
    (s1, p1, b): (f64, DVec2, &PointDist),
) -> Node {
    let (m2x, m2y) = (xc.d2_bound(s0, s1), yc.d2_bound_any(a.t, b.t));
    match_node_with((s0, p0, a), (s1, p1, b), m2x, m2y)
}

/// Matching node `nd` again with its own second-derivative bounds ([`Node::own`]).
fn match_refined(xc: &dyn BoundedCurve, yc: &dyn BoundedCurve, nd: &Node) -> Node {
    let (d0, d1) = nd.ends();
    match_node(xc, yc, (nd.t0, nd.p0, &d0), (nd.t1, nd.p1, &d1))
}

/// The halves of matching node `nd` split at s (point p, near point d), keyed with `nd`'s
/// M₂ˣ and, when d.t lies between the ends' near points, its M₂ʸ (else the halves' own
/// M₂ʸ, since their Y intervals leave `nd`'s).
fn match_children(
    yc: &dyn BoundedCurve,
    nd: &Node,
    (s, p, d): (f64, DVec2, &PointDist),
) -> [Node; 2] {
    let (d0, d1) = nd.ends();
    let inside = d.t >= nd.u0.min(nd.u1) && d.t <= nd.u0.max(nd.u1);
    let m2y = |a: f64, b: f64| {
        if inside {
            nd.m2y
        } else {
            yc.d2_bound_any(a, b)
        }
    };
    let mut halves = [
        match_node_with((nd.t0, nd.p0, &d0), (s, p, d), nd.m2x, m2y(nd.u0, d.t)),
        match_node_with((s, p, d), (nd.t1, nd.p1, &d1), nd.m2x, m2y(d.t, nd.u1)),
    ];
    for h in &mut halves {
        h.own = false;
    }
    halves
}

/// Cap on the refinement steps (bisections of X and point-distance searches) of one
/// [`match_search`]; beyond it the caller falls back to [`directed`].
const MATCH_STEPS: usize = 48;

/// Initial pieces per curve piece of a [`match_search`]: fewer than the full search's
/// [`INITIAL_SPLITS`], since a sample costs only a foot-point search and the search
/// bisects where the bound is too large (4: a quarter less time on the examples than 8,
/// with the same decisions and report flags; 2 changes a report flag).
const MATCH_SPLITS: usize = 4;

/// Gauss–Newton steps of [`foot_point`].
const FOOT_STEPS: usize = 3;

/// A point of Y near x by a few Gauss–Newton steps t ← t + (x − y)·y′/‖y′‖² from `t`,
/// kept inside Y's parameter range `(lo, hi)`: `upper` is its distance (an upper bound of
/// d(x, Y)), `lower` is 0. `None` where Y cannot be evaluated.
fn foot_point(x: DVec2, yc: &dyn BoundedCurve, (lo, hi): (f64, f64), t: f64) -> Option<PointDist> {
    let mut t = t.clamp(lo, hi);
    let mut best = PointDist {
        lower: 0.0,
        upper: f64::INFINITY,
        t,
    };
    for _ in 0..FOOT_STEPS {
        let (p, d) = yc.point_tangent(t).ok()?;
        let dist = x.distance(p);
        if dist < best.upper {
            best.upper = dist;
            best.t = t;
        }
        let dd = d.length_squared();
        let next = (t + (x - p).dot(d) / dd).clamp(lo, hi);
        // A step this small moves the point by ~1e-9 of the curve: converged.
        if !(dd > 0.0 && next.is_finite()) || (next - t).abs() <= 1e-9 * (hi - lo) {
            return Some(best);
        }
        t = next;
    }
    let dist = x.distance(yc.point(t).ok()?);
    if dist < best.upper {
        best.upper = dist;
        best.t = t;
    }
    Some(best)
}

/// What a [`match_search`] is to show about h(X → Y).
enum Goal {
    /// h(X → Y) ≤ this value (an upper bound alone).
    Below(f64),
    /// h(X → Y) > this value, shown by a point-distance search on `y` at the sample whose
    /// near point is farthest (one try; the upper bound is the matching bound of the
    /// samples).
    Above(f64),
    /// Bounds with upper − lower ≤ `gap`; lower bounds from point-distance searches on `y`
    /// to within `ptol`.
    Gap { gap: f64, ptol: f64 },
}

/// The start of every [`match_search`] of X against Y: the samples of X on its grid with
/// their near points on Y, and the nodes between them. The searches of one pair of curves
/// (for several goals) share it instead of sampling again.
struct MatchSeed {
    /// Y's parameter range.
    yd: (f64, f64),
    /// Samples of X: point, near-point data, whether its distance was certified.
    samples: Vec<(DVec2, PointDist, bool)>,
    heap: BinaryHeap<Node>,
}

impl MatchSeed {
    /// `None` when a curve has no piece or Y cannot be evaluated near a sample.
    fn new(xc: &dyn BoundedCurve, yc: &dyn BoundedCurve) -> Option<MatchSeed> {
        let (xp, yp) = (xc.pieces(), yc.pieces());
        let xd = (xp.first()?.0, xp.last()?.1);
        let yd = (yp.first()?.0, yp.last()?.1);
        if xd.1.partial_cmp(&xd.0) != Some(Ordering::Greater) {
            return None;
        }
        // X and Y run over corresponding parameter ranges: a sample's search starts at the
        // proportional parameter of Y, a bisection's between its ends' near points.
        let map = |s: f64| yd.0 + (s - xd.0) / (xd.1 - xd.0) * (yd.1 - yd.0);
        let grid = grid_of(xc, MATCH_SPLITS);
        let mut samples = Vec::with_capacity(grid.len());
        let mut heap = BinaryHeap::with_capacity(grid.len());
        let mut prev: Option<(f64, DVec2, PointDist)> = None;
        for s in grid {
            let p = xc.point(s).ok()?;
            let d = foot_point(p, yc, yd, map(s))?;
            if let Some((s0, p0, d0)) = prev
                && s > s0
                && xp.iter().any(|&(a, b)| s0 >= a && s <= b)
            {
                heap.push(match_node(xc, yc, (s0, p0, &d0), (s, p, &d)));
            }
            samples.push((p, d, false));
            prev = Some((s, p, d));
        }
        Some(MatchSeed { yd, samples, heap })
    }
}

/// h(X → Y) by the matching bound ([`match_bound`]): samples of X with near points of Y
/// from [`foot_point`] (upper bounds of d(x, Y) only), the piece of X with the largest
/// bound bisected first, and for [`Goal::Gap`] a certified point-distance search only at
/// the sample whose near point is farthest, when that can close the gap. [`directed`] runs
/// one such search at every sample, most of its work. `None` when the goal is not reached
/// within [`MATCH_STEPS`] or Y cannot be evaluated where looked: the caller then runs
/// [`directed`].
fn match_search(
    xc: &dyn BoundedCurve,
    yc: &dyn BoundedCurve,
    seed: &MatchSeed,
    goal: &Goal,
    work: &mut Work,
) -> Option<HausdorffBounds> {
    let yd = seed.yd;
    let mut pheap: BinaryHeap<Node> = BinaryHeap::new();
    if let Goal::Above(bound) = *goal {
        let (p, d, _) = seed
            .samples
            .iter()
            .max_by(|a, b| a.1.upper.total_cmp(&b.1.upper))?;
        if d.upper.partial_cmp(&bound) != Some(Ordering::Greater) || !work.take() {
            return None;
        }
        // Searched only until its lower bound passes the bound (or cannot).
        let tol = 0.5 * (d.upper - bound);
        let y = Target::new(yc).ok()?;
        let d = point_distance(*p, &y, Some(d.t), tol, work, &mut pheap).ok()?;
        let upper = seed.heap.peek()?.key;
        return (d.lower > bound).then_some(HausdorffBounds {
            lower: d.lower,
            upper: upper.max(d.lower),
        });
    }
    let mut heap = seed.heap.clone();
    // Only the gap's point-distance searches read the samples.
    let mut samples = matches!(goal, Goal::Gap { .. }).then(|| seed.samples.clone());
    let mut lower: f64 = 0.0;
    // Y's grid for point-distance searches, made on first use.
    let mut target: Option<Target> = None;
    let mut steps = 0;
    while let Some(nd) = heap.pop() {
        if !nd.own {
            heap.push(match_refined(xc, yc, &nd));
            continue;
        }
        let upper = nd.key;
        match *goal {
            Goal::Below(bound) => {
                if upper <= bound {
                    return Some(HausdorffBounds { lower, upper });
                }
                // A near point farther than the bound: give the proof up early.
                if nd.n0.max(nd.n1) > bound {
                    return None;
                }
            }
            Goal::Above(_) => return None,
            Goal::Gap { gap, .. } => {
                if upper <= lower + gap {
                    return Some(HausdorffBounds {
                        lower,
                        upper: upper.max(lower),
                    });
                }
            }
        }
        if steps >= MATCH_STEPS || !work.take() {
            return None;
        }
        steps += 1;
        if let Goal::Gap { gap, ptol } = *goal {
            let far = samples
                .iter_mut()
                .flatten()
                .filter(|s| !s.2)
                .max_by(|a, b| a.1.upper.total_cmp(&b.1.upper));
            if let Some(f) = far
                && f.1.upper > lower
                && upper - f.1.upper <= gap
            {
                if target.is_none() {
                    target = Some(Target::new(yc).ok()?);
                }
                let y = target.as_ref()?;
                let d = point_distance(f.0, y, Some(f.1.t), ptol, work, &mut pheap).ok()?;
                lower = lower.max(d.lower);
                f.2 = true;
                heap.push(nd);
                continue;
            }
        }
        let sm = 0.5 * (nd.t0 + nd.t1);
        if !(nd.t1 - nd.t0 > MIN_SPLIT_WIDTH && sm > nd.t0 && sm < nd.t1) {
            return None;
        }
        let pm = xc.point(sm).ok()?;
        let dm = foot_point(pm, yc, yd, 0.5 * (nd.u0 + nd.u1))?;
        if let Some(s) = samples.as_mut() {
            s.push((pm, dm, false));
        }
        heap.extend(match_children(yc, &nd, (sm, pm, &dm)));
    }
    None
}

/// The directed Hausdorff distance h(X → Y) = sup_x d(x, Y), bounded to `gap`; stops early
/// once the answer relative to `threshold` is decided (lower > threshold or upper ≤ it).
fn directed(
    xc: &dyn BoundedCurve,
    yc: &dyn BoundedCurve,
    gap: f64,
    threshold: Option<f64>,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    let ptol = 0.25 * gap;
    if threshold.is_none()
        && let Some(seed) = MatchSeed::new(xc, yc)
        && let Some(h) = match_search(xc, yc, &seed, &Goal::Gap { gap, ptol }, work)
    {
        return Ok(h);
    }
    let y = Target::new(yc)?;
    let mut pheap: BinaryHeap<Node> = BinaryHeap::new();
    let mut lower: f64 = 0.0;
    let mut heap: BinaryHeap<Node> = BinaryHeap::new();
    let xs = initial_grid(xc);
    let mut ends: Vec<(f64, DVec2, PointDist)> = Vec::with_capacity(xs.len());
    let mut hint = None;
    for &s in &xs {
        let p = xc.point(s)?;
        let d = point_distance(p, &y, hint, ptol, work, &mut pheap)?;
        hint = Some(d.t);
        lower = lower.max(d.lower);
        ends.push((s, p, d));
    }
    let xpieces = xc.pieces();
    // Largest upper bound of the leaves (nodes too narrow to split).
    let mut leaf_upper: f64 = 0.0;
    for w in ends.windows(2) {
        let ((s0, p0, d0), (s1, p1, d1)) = (w[0], w[1]);
        if s1 <= s0 || !xpieces.iter().any(|&(a, b)| s0 >= a && s1 <= b) {
            continue;
        }
        heap.push(match_node(xc, yc, (s0, p0, &d0), (s1, p1, &d1)));
    }
    let mut count = 0;
    while let Some(nd) = heap.pop() {
        if !nd.own {
            heap.push(match_refined(xc, yc, &nd));
            continue;
        }
        let upper = nd.key.max(leaf_upper);
        let decided = threshold.is_some_and(|e| lower > e || upper <= e);
        if upper <= lower + gap || decided || count >= MAX_NODES || !work.take() {
            return Ok(HausdorffBounds {
                lower,
                upper: upper.max(lower),
            });
        }
        count += 1;
        let sm = 0.5 * (nd.t0 + nd.t1);
        if !(nd.t1 - nd.t0 > MIN_SPLIT_WIDTH && sm > nd.t0 && sm < nd.t1) {
            leaf_upper = leaf_upper.max(nd.key);
            continue;
        }
        let pm = xc.point(sm)?;
        let hint = Some(0.5 * (nd.u0 + nd.u1));
        let dm = point_distance(pm, &y, hint, ptol, work, &mut pheap)?;
        lower = lower.max(dm.lower);
        heap.extend(match_children(yc, &nd, (sm, pm, &dm)));
    }
    Ok(HausdorffBounds {
        lower,
        upper: leaf_upper.max(lower),
    })
}

/// Bounds lower ≤ D_H(X, Y) ≤ upper of the Hausdorff distance (kruppa-2023 eq. 21) of two
/// bounded curves, refined until upper − lower ≤ `gap` (or a node cap is reached: the bounds
/// stay valid, the gap may be wider).
pub fn hausdorff_curves(
    x: &dyn BoundedCurve,
    y: &dyn BoundedCurve,
    gap: f64,
) -> Result<HausdorffBounds, HausdorffError> {
    bounds_impl(x, y, gap, None, &mut Work::new(MAX_BOUND_WORK))
}

/// How [`hausdorff_within_work`] may show D_H > ε.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rejection {
    /// By a point-distance search at the sample of either curve whose near point is
    /// farthest: cheap; the upper bound returned is then the matching bound of the samples
    /// of both directions.
    Quick,
    /// As `Quick`, without the other direction's matching bound: when D_H > ε is shown
    /// `upper` is +∞. For callers that only ask whether the segment meets ε (a pass of the
    /// skin's refinement); its decisions, and its bounds where D_H ≤ ε, are `Quick`'s.
    QuickLower,
    /// By the full search alone, with the bounds earlier versions returned (for callers
    /// that compare upper bounds of failing segments). When the first direction
    /// h(skin → envelope) already exceeds ε, `upper` bounds that direction only, not D_H.
    Full,
}

fn bounds_impl(
    x: &dyn BoundedCurve,
    y: &dyn BoundedCurve,
    gap: f64,
    threshold: Option<(f64, Rejection)>,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    if !(gap > 0.0 && gap.is_finite()) {
        return Err(HausdorffError::Gap(gap));
    }
    // Quick proof of D_H ≤ ε − gap by upper bounds alone. Below ε − gap the searches of
    // `directed` decide "≤ ε" as well (their lower bound never exceeds D_H, so they cannot
    // stop at a gap ≤ `gap` with upper > ε): the same decision, found cheaper.
    if let Some((eps, rejection)) = threshold {
        // Each direction's samples, taken once for all the searches below.
        let (xy, yx) = (OnceCell::new(), OnceCell::new());
        let search = |forward: bool, goal: &Goal, work: &mut Work| {
            let (p, q, cell) = if forward { (x, y, &xy) } else { (y, x, &yx) };
            let seed = cell.get_or_init(|| MatchSeed::new(p, q)).as_ref()?;
            match_search(p, q, seed, goal, work)
        };
        let below = Goal::Below(eps - gap);
        if eps - gap > 0.0
            && let Some(a) = search(true, &below, work)
            && let Some(b) = search(false, &below, work)
        {
            return Ok(HausdorffBounds {
                lower: 0.0,
                upper: a.upper.max(b.upper),
            });
        }
        // Quick proof of D_H > ε at the farthest sample of either direction.
        for forward in [true, false]
            .into_iter()
            .filter(|_| rejection != Rejection::Full)
        {
            if let Some(h) = search(forward, &Goal::Above(eps), work) {
                // With the other direction's matching bound `upper` bounds D_H too.
                let other = match rejection {
                    Rejection::Quick => search(!forward, &Goal::Below(f64::INFINITY), work)
                        .map_or(f64::INFINITY, |o| o.upper),
                    _ => f64::INFINITY,
                };
                return Ok(HausdorffBounds {
                    lower: h.lower,
                    upper: h.upper.max(other),
                });
            }
        }
    }
    let threshold = threshold.map(|t| t.0);
    let a = directed(x, y, gap, threshold, work)?;
    if threshold.is_some_and(|e| a.lower > e) {
        return Ok(a);
    }
    let b = directed(y, x, gap, threshold, work)?;
    Ok(HausdorffBounds {
        lower: a.lower.max(b.lower),
        upper: a.upper.max(b.upper),
    })
}

/// D_H between a skin segment and the `side` envelope of `curve` on [t_a, t_b]
/// (kruppa-2023 eq. 20), with upper − lower ≤ `gap`.
pub fn hausdorff_skin_envelope(
    skin: &CubicBez,
    curve: &DiskBSpline,
    side: Side,
    t_a: f64,
    t_b: f64,
    gap: f64,
) -> Result<HausdorffBounds, HausdorffError> {
    hausdorff_skin_envelope_work(
        skin,
        curve,
        side,
        t_a,
        t_b,
        gap,
        &mut Work::new(MAX_BOUND_WORK),
    )
}

/// [`hausdorff_skin_envelope`] spending at most `work.left` refinement steps (the bounds
/// stay valid when the budget runs out, only their gap may exceed `gap`).
pub fn hausdorff_skin_envelope_work(
    skin: &CubicBez,
    curve: &DiskBSpline,
    side: Side,
    t_a: f64,
    t_b: f64,
    gap: f64,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    let env = EnvelopeSegment::new(curve, side, t_a, t_b)?;
    skin_envelope_bounds(skin, &env, gap, work)
}

/// [`hausdorff_skin_envelope_work`] against an envelope segment already made.
pub(crate) fn skin_envelope_bounds(
    skin: &CubicBez,
    env: &EnvelopeSegment,
    gap: f64,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    bounds_impl(skin, env, gap, None, work)
}

/// Like [`hausdorff_skin_envelope`] but stops as soon as D_H ≤ `eps` or D_H > `eps` is
/// decided by the bounds (or their gap is ≤ `gap`): the test of kruppa-2023 Sec. 4.2.
pub fn hausdorff_within(
    skin: &CubicBez,
    curve: &DiskBSpline,
    side: Side,
    t_a: f64,
    t_b: f64,
    eps: f64,
    gap: f64,
) -> Result<HausdorffBounds, HausdorffError> {
    hausdorff_within_work(
        skin,
        curve,
        side,
        (t_a, t_b),
        (eps, Rejection::Quick),
        gap,
        &mut Work::new(MAX_BOUND_WORK),
    )
}

/// [`hausdorff_within`] on the span `(t_a, t_b)` with ε and the way to show D_H > ε,
/// spending at most `work.left` refinement steps (the bounds stay valid when the budget
/// runs out, only their gap may exceed `gap`).
pub fn hausdorff_within_work(
    skin: &CubicBez,
    curve: &DiskBSpline,
    side: Side,
    (t_a, t_b): (f64, f64),
    (eps, rejection): (f64, Rejection),
    gap: f64,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    let env = EnvelopeSegment::new(curve, side, t_a, t_b)?;
    skin_envelope_within(skin, &env, (eps, rejection), gap, work)
}

/// [`hausdorff_within_work`] against an envelope segment already made.
pub(crate) fn skin_envelope_within(
    skin: &CubicBez,
    env: &EnvelopeSegment,
    (eps, rejection): (f64, Rejection),
    gap: f64,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    bounds_impl(skin, env, gap, Some((eps, rejection)), work)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    use crate::dbsc::test_util::{open, s_stroke};

    /// An envelope segment borrowing the curve's spans is the segment `new` makes: the
    /// same pieces, points, tangents and second-derivative bounds, on intervals inside one
    /// span, across spans, at knots and over the whole domain (the degree-3 curve of six
    /// disks has three spans).
    #[test]
    fn shared_spans_give_the_same_segment() {
        let c = open(3, &s_stroke());
        let all = SpanPoly::all(&c);
        assert_eq!(all.len(), 3);
        let (lo, hi) = c.domain();
        let at = |f: f64| lo + f * (hi - lo);
        for (fa, fb) in [
            (0.0, 1.0),
            (0.1, 0.2),
            (0.2, 0.7),
            (1.0 / 3.0, 2.0 / 3.0),
            (0.9, 1.0),
        ] {
            let (ta, tb) = (at(fa), at(fb));
            for side in [Side::Left, Side::Right] {
                let own = EnvelopeSegment::new(&c, side, ta, tb).unwrap();
                let shared = EnvelopeSegment::with_spans(&c, &all, side, ta, tb).unwrap();
                assert_eq!(own.pieces(), shared.pieces(), "[{ta}, {tb}]");
                for k in 0..=8 {
                    let t = ta + (tb - ta) * k as f64 / 8.0;
                    assert_eq!(own.point_tangent(t).ok(), shared.point_tangent(t).ok());
                    let u = (t + tb) / 2.0;
                    let (d1, d2) = (own.d2_bound_any(t, u), shared.d2_bound_any(t, u));
                    assert!(d1 == d2 || (d1.is_nan() && d2.is_nan()), "{d1} {d2}");
                }
            }
        }
        assert!(EnvelopeSegment::with_spans(&c, &all, Side::Left, hi, lo).is_err());
    }

    fn line_cubic(a: DVec2, b: DVec2) -> CubicBez {
        CubicBez::new(a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b)
    }

    /// An exact circular arc, for closed-form tests.
    struct ArcCurve {
        c: DVec2,
        r: f64,
        a0: f64,
        a1: f64,
    }
    impl BoundedCurve for ArcCurve {
        fn pieces(&self) -> Vec<(f64, f64)> {
            vec![(0.0, 1.0)]
        }
        fn point(&self, t: f64) -> Result<DVec2, HausdorffError> {
            let a = self.a0 + t * (self.a1 - self.a0);
            Ok(self.c + self.r * DVec2::new(a.cos(), a.sin()))
        }
        fn d2_bound(&self, _: f64, _: f64) -> f64 {
            self.r * (self.a1 - self.a0).powi(2)
        }
        fn point_tangent(&self, t: f64) -> Result<(DVec2, DVec2), HausdorffError> {
            let (w, a) = (self.a1 - self.a0, self.a0 + t * (self.a1 - self.a0));
            Ok((
                self.c + self.r * DVec2::new(a.cos(), a.sin()),
                self.r * w * DVec2::new(-a.sin(), a.cos()),
            ))
        }
    }

    #[test]
    fn offset_line_closed_forms() {
        // Straight stroke of constant radius 1: the left envelope is y = 1, x ∈ [0, 3].
        let c = open(
            3,
            &[
                (0.0, 0.0, 1.0),
                (1.0, 0.0, 1.0),
                (2.0, 0.0, 1.0),
                (3.0, 0.0, 1.0),
            ],
        );
        let gap = 1e-6;
        for (scale, shift) in [(1.0, 0.0), (1.0, 0.01), (1.0, -0.3)] {
            let s = line_cubic(
                DVec2::new(0.0, 1.0 + shift),
                DVec2::new(3.0 * scale, 1.0 + shift),
            );
            let h = hausdorff_skin_envelope(&s, &c, Side::Left, 0.0, 1.0, gap).unwrap();
            let want = f64::abs(shift);
            assert!(
                h.lower <= want + 1e-12 && want <= h.upper + 1e-12,
                "{h:?} {want}"
            );
            assert!(h.gap() <= gap);
        }
        // Overhang: the cubic runs on to x = 3.4; D_H = √(0.4² + d²).
        let d = 0.05;
        let s = line_cubic(DVec2::new(0.0, 1.0 + d), DVec2::new(3.4, 1.0 + d));
        let h = hausdorff_skin_envelope(&s, &c, Side::Left, 0.0, 1.0, gap).unwrap();
        let want = (0.4f64 * 0.4 + d * d).sqrt();
        assert!(
            h.lower <= want + 1e-12 && want <= h.upper + 1e-12,
            "{h:?} {want}"
        );
        assert!(h.gap() <= gap);
        // Right side of a linearly growing stroke: the envelope is the outer common tangent
        // of the end circles, a straight segment.
        let c = open(1, &[(0.0, 0.0, 1.0), (4.0, 0.0, 2.0)]);
        let (e0, e1) = (
            c.envelope(Side::Right, 0.0).unwrap().point,
            c.envelope(Side::Right, 1.0).unwrap().point,
        );
        let n = crate::geom::perp(e1 - e0).normalize();
        let s = line_cubic(e0 + 0.02 * n, e1 + 0.02 * n);
        let h = hausdorff_skin_envelope(&s, &c, Side::Right, 0.0, 1.0, gap).unwrap();
        assert!(h.lower <= 0.02 + 1e-12 && 0.02 <= h.upper + 1e-12, "{h:?}");
        assert!(h.gap() <= gap);
    }

    #[test]
    fn quarter_circle_bezier_error() {
        // The standard cubic for a quarter of the unit circle, k = 4(√2 − 1)/3, deviates
        // radially by at most ≈ 2.7253e-4 r. The Hausdorff distance to the arc is that
        // maximum radial deviation; it is computed here independently by golden-section
        // search of ‖B(t)‖ on [0, 1/2] (unimodal by symmetry).
        for r in [1.0, 7.5] {
            let k = 4.0 * (2f64.sqrt() - 1.0) / 3.0 * r;
            let b = CubicBez::new(
                DVec2::new(r, 0.0),
                DVec2::new(r, k),
                DVec2::new(k, r),
                DVec2::new(0.0, r),
            );
            let f = |t: f64| b.eval(t).length() - r;
            let (mut lo, mut hi) = (0.0, 0.5);
            let g = (5f64.sqrt() - 1.0) / 2.0;
            for _ in 0..200 {
                let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
                if f(m1) < f(m2) {
                    lo = m1;
                } else {
                    hi = m2;
                }
            }
            let want = f(0.5 * (lo + hi));
            assert!((want / r - 2.7253e-4).abs() < 1e-7);
            let arc = ArcCurve {
                c: DVec2::ZERO,
                r,
                a0: 0.0,
                a1: std::f64::consts::FRAC_PI_2,
            };
            let gap = 1e-3 * want;
            let h = hausdorff_curves(&b, &arc, gap).unwrap();
            assert!(
                h.lower <= want * (1.0 + 1e-9) && want <= h.upper * (1.0 + 1e-9),
                "{h:?} {want}"
            );
            assert!(h.gap() <= gap);
        }
    }

    #[test]
    fn bad_arguments_are_errors() {
        let c = open(1, &[(0.0, 0.0, 1.0), (4.0, 0.0, 1.0)]);
        let s = line_cubic(DVec2::ZERO, DVec2::X);
        assert_eq!(
            hausdorff_skin_envelope(&s, &c, Side::Left, 0.0, 1.0, 0.0),
            Err(HausdorffError::Gap(0.0))
        );
        assert!(matches!(
            hausdorff_skin_envelope(&s, &c, Side::Left, 0.5, 0.5, 1e-3),
            Err(HausdorffError::Interval { .. })
        ));
        let g = open(1, &[(0.0, 0.0, 1.0), (1.0, 0.0, 4.0)]);
        assert!(matches!(
            hausdorff_skin_envelope(&s, &g, Side::Left, 0.0, 1.0, 1e-3),
            Err(HausdorffError::NoEnvelope { .. })
        ));
    }

    #[test]
    fn envelope_second_derivative_bound_holds() {
        // The interval bound must dominate finite-difference second derivatives.
        let c = open(
            3,
            &[
                (0.0, 0.0, 0.5),
                (2.0, 1.0, 0.9),
                (3.0, -1.0, 0.4),
                (5.0, 0.5, 0.7),
                (6.0, 0.0, 0.5),
            ],
        );
        for side in [Side::Left, Side::Right] {
            let e = EnvelopeSegment::new(&c, side, 0.0, 1.0).unwrap();
            for (a, b) in e.pieces() {
                let m = e.d2_bound(a, b);
                let h = 1e-4;
                for i in 1..20 {
                    let t = a + (b - a) * i as f64 / 20.0;
                    let f = |t: f64| e.point(t).unwrap();
                    let d2 = (f(t + h) - 2.0 * f(t) + f(t - h)) / (h * h);
                    assert!(d2.length() <= m * (1.0 + 1e-6) + 1e-4, "{d2} > {m}");
                }
            }
        }
    }

    /// Independent estimate: dense sampling of both directed distances with nearest points
    /// from dense samples refined by golden-section search.
    fn dense_estimate(x: &dyn BoundedCurve, y: &dyn BoundedCurve) -> f64 {
        let sample = |c: &dyn BoundedCurve| -> Vec<(f64, DVec2)> {
            let (a, b) = (c.pieces()[0].0, c.pieces().last().unwrap().1);
            (0..=400)
                .map(|i| {
                    let t = a + (b - a) * i as f64 / 400.0;
                    (t, c.point(t).unwrap())
                })
                .collect()
        };
        let (xs, ys) = (sample(x), sample(y));
        let near = |p: DVec2, c: &dyn BoundedCurve, s: &[(f64, DVec2)]| {
            let i = (0..s.len())
                .min_by(|&i, &j| p.distance(s[i].1).total_cmp(&p.distance(s[j].1)))
                .unwrap();
            let (mut lo, mut hi) = (s[i.saturating_sub(1)].0, s[(i + 1).min(s.len() - 1)].0);
            let g = (5f64.sqrt() - 1.0) / 2.0;
            let f = |t: f64| p.distance(c.point(t).unwrap());
            for _ in 0..60 {
                let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
                if f(m1) < f(m2) {
                    hi = m2;
                } else {
                    lo = m1;
                }
            }
            f(0.5 * (lo + hi)).min(p.distance(s[i].1))
        };
        let a = xs.iter().map(|&(_, p)| near(p, y, &ys)).fold(0.0, f64::max);
        let b = ys.iter().map(|&(_, p)| near(p, x, &xs)).fold(0.0, f64::max);
        a.max(b)
    }

    #[test]
    fn looping_envelope_bounds_bracket_dense_estimate() {
        // The inner envelope of a sharp bend has a swallowtail on [0.35, 0.64]; the nearest
        // points jump between its branches, which the constant-matching bound handles.
        let c = open(
            3,
            &[
                (0.0, 0.0, 0.8),
                (4.0, 0.0, 0.8),
                (5.0, 1.0, 0.8),
                (4.0, 2.0, 0.8),
                (0.0, 2.2, 0.8),
            ],
        );
        let env = EnvelopeSegment::new(&c, Side::Left, 0.25, 0.75).unwrap();
        let (a, b) = (env.point(0.25).unwrap(), env.point(0.75).unwrap());
        let m = env.point(0.5).unwrap();
        let s = CubicBez::new(a, a.lerp(m, 0.8), b.lerp(m, 0.8), b);
        let gap = 1e-3;
        let h = hausdorff_curves(&s, &env, gap).unwrap();
        let est = dense_estimate(&s, &env);
        assert!(
            h.lower <= est + 1e-7 && est <= h.upper + 1e-9,
            "{h:?} {est}"
        );
        assert!(h.gap() <= gap, "{h:?}");
        // Symmetric in its arguments.
        let g = hausdorff_curves(&env, &s, gap).unwrap();
        assert!(g.lower <= h.upper && h.lower <= g.upper);
    }

    /// A cubic stroke through disks `d` jittered about centres `spacing` apart along x, and
    /// the side `left` names.
    fn gentle_stroke(d: &[(f64, f64, f64)], spacing: f64, left: bool) -> (DiskBSpline, Side) {
        let disks: Vec<(f64, f64, f64)> = d
            .iter()
            .enumerate()
            .map(|(i, &(x, y, r))| (spacing * i as f64 + 0.3 * x, 0.5 * y, r))
            .collect();
        let side = if left { Side::Left } else { Side::Right };
        (open(3, &disks), side)
    }

    fn iv(a: f64, b: f64) -> Iv {
        Iv::new(a.min(b), a.max(b))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// The product and the scaled interval hold every product of their members, and
        /// their ends are products of ends (the tightest enclosure).
        #[test]
        fn interval_product_encloses_the_products(
            a in (-1e3f64..1e3, -1e3f64..1e3),
            b in (-1e3f64..1e3, -1e3f64..1e3),
            f in (0.0f64..=1.0, 0.0f64..=1.0),
            k in -5.0f64..5.0,
        ) {
            let (x, y) = (iv(a.0, a.1), iv(b.0, b.1));
            let p = x.mul(y);
            let ends = [x.lo * y.lo, x.lo * y.hi, x.hi * y.lo, x.hi * y.hi];
            prop_assert!(ends.contains(&p.lo) && ends.contains(&p.hi));
            let (u, v) = (x.lo + f.0 * (x.hi - x.lo), y.lo + f.1 * (y.hi - y.lo));
            prop_assert!(p.lo <= u * v && u * v <= p.hi, "{:?} {}", p, u * v);
            let s = x.scale(k);
            prop_assert!(s.lo <= s.hi && s.lo <= u * k && u * k <= s.hi);
            prop_assert_eq!(s, x.mul(Iv::pt(k)));
        }

        /// The square of a jet is its product with itself, bit for bit.
        #[test]
        fn jet_square_is_the_product_with_itself(
            v in (-1e3f64..1e3, -1e3f64..1e3),
            d1 in (-1e3f64..1e3, -1e3f64..1e3),
            d2 in (-1e3f64..1e3, -1e3f64..1e3),
        ) {
            let j = Jet { v: iv(v.0, v.1), d1: iv(d1.0, d1.1), d2: iv(d2.0, d2.1) };
            let (sq, m) = (j.sqr(), j.mul(j));
            prop_assert_eq!((sq.v, sq.d1, sq.d2), (m.v, m.d1, m.d2));
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]

        #[test]
        fn bounds_bracket_dense_estimate(
            d in proptest::collection::vec((-3.0f64..3.0, -3.0f64..3.0, 0.2f64..0.6), 4),
            jitter in proptest::collection::vec((-0.2f64..0.2, -0.2f64..0.2), 2),
            side_left in any::<bool>(),
        ) {
            // A gently curved stroke (centres along x), a cubic near its envelope.
            let (c, side) = gentle_stroke(&d, 4.0, side_left);
            let env = EnvelopeSegment::new(&c, side, 0.0, 1.0).unwrap();
            let p = |t: f64| env.point(t).unwrap();
            let (a, b) = (p(0.0), p(1.0));
            let s = CubicBez::new(
                a,
                p(1.0 / 3.0) + DVec2::new(jitter[0].0, jitter[0].1),
                p(2.0 / 3.0) + DVec2::new(jitter[1].0, jitter[1].1),
                b,
            );
            let gap = 1e-3;
            let h = hausdorff_curves(&s, &env, gap).unwrap();
            let est = dense_estimate(&s, &env);
            // The dense estimate is ≤ the truth up to its sampling resolution.
            prop_assert!(h.lower <= est + 1e-7, "{:?} est {}", h, est);
            prop_assert!(est <= h.upper + 1e-9, "{:?} est {}", h, est);
            prop_assert!(h.gap() <= gap, "{:?}", h);
            // Early-exit decisions agree with the full bounds.
            let eps = 0.5 * (h.lower + h.upper) + 0.01;
            let w = hausdorff_within(&s, &c, side, 0.0, 1.0, eps, gap).unwrap();
            prop_assert!(w.upper <= eps || w.lower > eps || w.gap() <= gap);
            prop_assert!(w.lower <= h.upper + 1e-12 && h.lower <= w.upper + 1e-12);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// The cubic path of the derivative ranges gives the generic path's values bit for
        /// bit, and every range holds the derivative at points of the interval.
        #[test]
        fn cubic_derivative_ranges_equal_the_generic_path(
            c in proptest::collection::vec(-10.0f64..10.0, 4),
            span in (-2.0f64..2.0, 0.01f64..3.0),
            f in (0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0),
        ) {
            let sp = SpanPoly {
                a: span.0,
                b: span.0 + span.1,
                x: Bern(c.clone()),
                y: Bern(c.clone()),
                r: Bern(c.clone()),
            };
            let (t0, t1) = (
                sp.a + span.1 * f.0.min(f.1),
                sp.a + span.1 * f.0.max(f.1),
            );
            let cubic = cubic_deriv_ranges(&[c[0], c[1], c[2], c[3]], &sp, t0, t1);
            let generic = deriv_ranges_in(&c, &sp, t0, t1, &mut [0.0; 4], &mut [0.0; 4]);
            prop_assert_eq!(cubic, generic);
            // Derivatives at a point of [t0, t1] by the power form of the cubic in t.
            let t = t0 + (t1 - t0) * f.2;
            let mut q = sp.x.clone();
            for (k, r) in cubic.iter().enumerate() {
                let v = q.eval((t - sp.a) / span.1) / span.1.powi(k as i32);
                let slack = 1e-9 * (1.0 + v.abs()) / span.1.powi(k as i32);
                prop_assert!(r.lo - slack <= v && v <= r.hi + slack, "k {k}: {v} ∉ {r:?}");
                q = q.deriv();
            }
        }

        /// The second-derivative bound of a sub-interval is at most that of the interval
        /// (Bernstein pieces of a sub-interval are convex combinations of the interval's
        /// coefficients and interval arithmetic is inclusion-monotone): what lets a child
        /// node start with its parent's bound ([`Node::own`]) and be popped no later than
        /// with its own.
        #[test]
        fn second_derivative_bounds_nest(
            d in proptest::collection::vec((-3.0f64..3.0, -3.0f64..3.0, 0.2f64..0.6), 4),
            cut in proptest::collection::vec((0.0f64..=1.0, 0.0f64..=1.0), 8),
            side_left in any::<bool>(),
        ) {
            let (c, side) = gentle_stroke(&d, 3.0, side_left);
            let env = EnvelopeSegment::new(&c, side, 0.0, 1.0).unwrap();
            let bez = CubicBez::new(
                DVec2::new(0.0, 0.0),
                DVec2::new(d[0].0, d[0].1),
                DVec2::new(d[1].0, d[1].1),
                DVec2::new(d[2].0, 4.0),
            );
            let curves: [&dyn BoundedCurve; 2] = [&env, &bez];
            for curve in curves {
                for (a, b) in curve.pieces() {
                    let (mut t0, mut t1) = (a, b);
                    let mut outer = curve.d2_bound(t0, t1);
                    // A chain of nested intervals, as bisections and foot points make them.
                    for &(f, g) in &cut {
                        let (u, v) = (t0 + (t1 - t0) * f.min(g), t0 + (t1 - t0) * f.max(g));
                        let inner = curve.d2_bound(u, v);
                        prop_assert!(
                            inner <= outer || outer.is_nan(),
                            "[{u}, {v}] ⊂ [{t0}, {t1}]: {inner} > {outer}"
                        );
                        (t0, t1, outer) = (u, v, inner);
                    }
                }
            }
        }
    }
}
