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

use crate::dbsc::{DiskBSpline, Side};
use crate::geom::CubicBez;
use std::cell::OnceCell;

mod curves;
mod search;

pub use curves::{BoundedCurve, EnvelopeSegment};
use search::*;

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
#[non_exhaustive]
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
#[non_exhaustive]
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

/// How a bound against ε ([`hausdorff_within`]) may show D_H > ε.
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
    bounds_path(x, y, gap, threshold, work).map(|(h, _)| h)
}

/// [`bounds_impl`], and whether the quick proof of D_H ≤ ε − gap gave the bounds: that path
/// does not depend on the [`Rejection`], so the bounds of one rejection there are those of
/// every other (same curves, gap, ε, and a budget that does not run short).
fn bounds_path(
    x: &dyn BoundedCurve,
    y: &dyn BoundedCurve,
    gap: f64,
    threshold: Option<(f64, Rejection)>,
    work: &mut Work,
) -> Result<(HausdorffBounds, bool), HausdorffError> {
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
            let h = HausdorffBounds {
                lower: 0.0,
                upper: a.upper.max(b.upper),
            };
            return Ok((h, true));
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
                let h = HausdorffBounds {
                    lower: h.lower,
                    upper: h.upper.max(other),
                };
                return Ok((h, false));
            }
        }
    }
    let threshold = threshold.map(|t| t.0);
    let a = directed(x, y, gap, threshold, work)?;
    if threshold.is_some_and(|e| a.lower > e) {
        return Ok((a, false));
    }
    let b = directed(y, x, gap, threshold, work)?;
    let h = HausdorffBounds {
        lower: a.lower.max(b.lower),
        upper: a.upper.max(b.upper),
    };
    Ok((h, false))
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
    let env = EnvelopeSegment::new(curve, side, t_a, t_b)?;
    skin_envelope_bounds(skin, &env, gap, &mut Work::new(MAX_BOUND_WORK))
}

/// [`hausdorff_skin_envelope`] against an envelope segment already made, spending at most
/// `work.left` refinement steps (the bounds stay valid when the budget runs out, only their
/// gap may exceed `gap`).
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
    let env = EnvelopeSegment::new(curve, side, t_a, t_b)?;
    skin_envelope_within(
        skin,
        &env,
        (eps, Rejection::Quick),
        gap,
        &mut Work::new(MAX_BOUND_WORK),
    )
}

/// [`hausdorff_within`] against an envelope segment already made, with the way to show
/// D_H > ε, spending at most `work.left` refinement steps (the bounds stay valid when the
/// budget runs out, only their gap may exceed `gap`).
pub(crate) fn skin_envelope_within(
    skin: &CubicBez,
    env: &EnvelopeSegment,
    (eps, rejection): (f64, Rejection),
    gap: f64,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    bounds_impl(skin, env, gap, Some((eps, rejection)), work)
}

/// [`skin_envelope_within`], and whether its bounds are those of the quick proof of
/// D_H ≤ ε − gap, which every [`Rejection`] gives alike ([`bounds_path`]).
pub(crate) fn skin_envelope_within_path(
    skin: &CubicBez,
    env: &EnvelopeSegment,
    (eps, rejection): (f64, Rejection),
    gap: f64,
    work: &mut Work,
) -> Result<(HausdorffBounds, bool), HausdorffError> {
    bounds_path(skin, env, gap, Some((eps, rejection)), work)
}

#[cfg(test)]
mod tests {
    use super::curves::*;
    use super::*;
    use crate::dbsc::{Bern, SpanPoly};
    use crate::geom::DVec2;
    use proptest::prelude::*;

    use crate::dbsc::test_util::{open, s_stroke};

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
