//! Parameter intervals without a real envelope: ‖q′(t)‖² − r′(t)² ≤ 0 (wu-2021 eq. 8).
//!
//! On each knot span the discriminant D(t) = x′² + y′² − r′² is a polynomial of degree
//! 2(p − 1). It is built exactly from the Taylor coefficients of q′ and r′ at the span's
//! midpoint, converted to Bernstein form on the span, its roots isolated by de Casteljau
//! subdivision with the Bernstein sign-change (variation-diminishing) bound — no sign change
//! in the coefficients means no root, exactly one change means exactly one simple root — and
//! each isolated root refined by Brent's method. The sign of D between consecutive roots
//! decides which pieces have no envelope. Intervals are merged across spans and reported
//! unclamped; on closed curves an interval touching the seam is reported as two pieces, one
//! ending at the domain's end and one starting at its start.
//!
//! Isolated zeros where D touches 0 without changing sign (a double root) are not reported:
//! there the envelope passes continuously through the limit point q − r r′ q′/‖q′‖².

use super::DiskBSpline;
use crate::geom::bernstein::{self, Step, Visitor, binom};

/// Subdivision depth cap: after 48 halvings an isolating box is 2⁻⁴⁸ of its span, below
/// any useful parameter tolerance; a box still holding several sign changes there is a
/// (near-)multiple root and is taken as one root at its midpoint.
const MAX_DEPTH: u32 = 48;

/// Cap on the subdivision boxes of one span's root isolation (the depth cap bounds a path,
/// not the tree: noise-level coefficients change sign in every box). Once reached, every
/// box still open is taken as a root at its midpoint, as at the depth cap.
const MAX_BOXES: usize = 20_000;

/// Relative size below which all Bernstein coefficients of D count as zero on a span
/// (D ≡ 0: ‖q′‖ = |r′| throughout, no envelope on the whole span).
const ZERO_REL: f64 = 1e-13;

/// The maximal parameter intervals (t0, t1), t0 < t1, on which ‖q′‖² − r′² ≤ 0, i.e. where
/// the DBSC has no real envelope (wu-2021 eq. 8), sorted and merged across knot spans.
/// Interval ends are roots of the discriminant located to within `tol` in t.
pub fn no_envelope_intervals(c: &DiskBSpline, tol: f64) -> Vec<(f64, f64)> {
    let bps = c.breakpoints();
    let mut out: Vec<(f64, f64)> = Vec::new();
    for w in bps.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a || b.is_nan() || a.is_nan() {
            continue;
        }
        for iv in span_intervals(c, a, b, tol) {
            match out.last_mut() {
                Some(last) if iv.0 <= last.1 + tol.max(0.0) => last.1 = last.1.max(iv.1),
                _ => out.push(iv),
            }
        }
    }
    out
}

/// Bernstein coefficients on [a, b] (u = (t − a)/(b − a)) of D(t) = ‖q′‖² − r′², exact up
/// to rounding: Taylor coefficients of (x′, y′, r′) at the span midpoint, squared, shifted
/// to u and converted from the power basis (Farouki–Rajan: b_i = Σ_{j≤i} C(i,j)/C(n,j) a_j).
pub fn discriminant_bernstein(c: &DiskBSpline, a: f64, b: f64) -> Vec<f64> {
    let p = c.degree();
    let m = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    // Orders 1..=p of (x, y, r) at m: Taylor coefficients of the derivative curve.
    let d = c.curve().derivs(m, p);
    let mut fact = 1.0;
    let mut cx = Vec::with_capacity(p);
    let mut cy = Vec::with_capacity(p);
    let mut cr = Vec::with_capacity(p);
    for (j, v) in d.iter().skip(1).enumerate() {
        if j > 0 {
            fact *= j as f64;
        }
        // Coefficient of s^j with s = t − m, pre-scaled by h^j (s = h σ, σ ∈ [−1, 1]).
        let hj = h.powi(j as i32);
        cx.push(v.x / fact * hj);
        cy.push(v.y / fact * hj);
        cr.push(v.z / fact * hj);
    }
    let n = 2 * (p - 1);
    // Power coefficients in σ.
    let mut sig = vec![0.0; n + 1];
    for i in 0..p {
        for j in 0..p {
            sig[i + j] += cx[i] * cx[j] + cy[i] * cy[j] - cr[i] * cr[j];
        }
    }
    // σ = 2u − 1: power coefficients in u.
    let mut pu = vec![0.0; n + 1];
    for (k, &sk) in sig.iter().enumerate() {
        // (2u − 1)^k = Σ_j C(k, j) 2^j u^j (−1)^{k−j}.
        for (j, pj) in pu.iter_mut().enumerate().take(k + 1) {
            let sign = if (k - j) % 2 == 0 { 1.0 } else { -1.0 };
            *pj += sk * binom(k, j) * 2f64.powi(j as i32) * sign;
        }
    }
    (0..=n)
        .map(|i| (0..=i).map(|j| binom(i, j) / binom(n, j) * pu[j]).sum())
        .collect()
}

/// Value of a Bernstein polynomial at u (de Casteljau, [`bernstein::eval`]).
pub(crate) fn bernstein_eval(coef: &[f64], u: f64) -> f64 {
    bernstein::eval(coef, u)
}

/// The isolation policy of the discriminant's roots on [`bernstein::subdivide`]: no sign
/// change ⇒ no crossing root (zero end coefficients are roots at the piece's ends), one
/// change with opposite end values ⇒ one simple root, refined by Brent on the whole span's
/// polynomial; otherwise split, down to `utol`, [`MAX_DEPTH`] or [`MAX_BOXES`].
struct Isolate<'a> {
    full: &'a [f64],
    utol: f64,
    boxes: usize,
    out: Vec<f64>,
}

impl Visitor for Isolate<'_> {
    fn visit(&mut self, coef: &[f64], u0: f64, u1: f64, depth: u32) -> Step {
        let n = coef.len();
        let changes = bernstein::sign_changes(coef);
        if changes == 0 {
            if coef[0] == 0.0 {
                self.out.push(u0);
            }
            if coef[n - 1] == 0.0 {
                self.out.push(u1);
            }
            return Step::Keep;
        }
        let (f0, f1) = (coef[0], coef[n - 1]);
        if changes == 1 && f0 != 0.0 && f1 != 0.0 && (f0 > 0.0) != (f1 > 0.0) {
            let full = self.full;
            self.out.push(crate::geom::roots::brent_with(
                |u| bernstein::eval(full, u),
                u0,
                u1,
                f0,
                f1,
                self.utol,
            ));
            return Step::Keep;
        }
        if depth >= MAX_DEPTH || u1 - u0 <= self.utol || self.boxes == 0 {
            self.out.push(0.5 * (u0 + u1));
            return Step::Keep;
        }
        self.boxes -= 1;
        Step::Split
    }
}

/// The no-envelope pieces of one span [a, b].
fn span_intervals(c: &DiskBSpline, a: f64, b: f64, tol: f64) -> Vec<(f64, f64)> {
    let coef = discriminant_bernstein(c, a, b);
    let scale = coef.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let d1 = c.curve().derivs(0.5 * (a + b), 1)[1];
    let mag = d1.x * d1.x + d1.y * d1.y + d1.z * d1.z;
    if scale <= ZERO_REL * mag.max(f64::MIN_POSITIVE) || scale == 0.0 {
        return vec![(a, b)];
    }
    let w = b - a;
    let mut iso = Isolate {
        full: &coef,
        utol: tol / w,
        boxes: MAX_BOXES,
        out: Vec::new(),
    };
    bernstein::subdivide(&coef, &mut iso);
    let roots = iso.out;
    let mut pts: Vec<f64> = Vec::with_capacity(roots.len() + 2);
    pts.push(0.0);
    pts.extend(roots.iter().map(|u| u.clamp(0.0, 1.0)));
    pts.push(1.0);
    pts.sort_by(f64::total_cmp);
    pts.dedup();
    let mut out: Vec<(f64, f64)> = Vec::new();
    for seg in pts.windows(2) {
        let (u0, u1) = (seg[0], seg[1]);
        if u1 <= u0 {
            continue;
        }
        if bernstein_eval(&coef, 0.5 * (u0 + u1)) <= 0.0 {
            let iv = (a + u0 * w, if u1 >= 1.0 { b } else { a + u1 * w });
            match out.last_mut() {
                Some(last) if last.1 >= iv.0 => last.1 = iv.1,
                _ => out.push(iv),
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::tangent::tests::dbsc_strategy;
    use crate::geom::{Circle, DVec2};
    use proptest::prelude::*;

    /// Single cubic span on [0, 1], x(t) = L t, y = 0,
    /// r(t) = 1 + A t − B (t − ½)³ / 3, so r′ = A − B (t − ½)² and
    /// D = L² − (A − B s²)², s = t − ½. With L = 1, A = 2, B = 16:
    /// D ≤ 0 ⇔ s² ≤ 1/16 or s² ≥ 3/16.
    fn bump(scale: f64) -> (DiskBSpline, Vec<(f64, f64)>) {
        let (l, a, bb) = (1.0, 2.0, 16.0);
        let r = |t: f64| 1.0 + a * t - bb * (t - 0.5f64).powi(3) / 3.0;
        let r1 = |t: f64| a - bb * (t - 0.5f64).powi(2);
        let rs = [
            r(0.0),
            r(0.0) + r1(0.0) / 3.0,
            r(1.0) - r1(1.0) / 3.0,
            r(1.0),
        ];
        let disks: Vec<Circle> = (0..4)
            .map(|i| Circle::new(DVec2::new(scale * l * i as f64 / 3.0, 0.0), scale * rs[i]))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let e = (3.0f64 / 16.0).sqrt();
        (c, vec![(0.0, 0.5 - e), (0.25, 0.75), (0.5 + e, 1.0)])
    }

    fn assert_close(got: &[(f64, f64)], want: &[(f64, f64)], tol: f64) {
        assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g.0 - w.0).abs() <= tol && (g.1 - w.1).abs() <= tol,
                "{got:?} vs {want:?}"
            );
        }
    }

    #[test]
    fn cubic_bump_closed_form() {
        for scale in [1.0, 1e-3, 250.0] {
            let (c, want) = bump(scale);
            assert_close(&no_envelope_intervals(&c, 1e-12), &want, 1e-10);
            // Same curve with extra knots: the spans change, the intervals do not.
            let k = c
                .curve()
                .insert_knot(0.3, 1)
                .unwrap()
                .insert_knot(0.25, 2)
                .unwrap();
            let ck = DiskBSpline::from_curve(k);
            assert_close(&no_envelope_intervals(&ck, 1e-12), &want, 1e-10);
            // Reversed: intervals mirror to 1 − t.
            let cr = DiskBSpline::from_curve(c.curve().reversed());
            let mut wr: Vec<(f64, f64)> = want.iter().map(|&(a, b)| (1.0 - b, 1.0 - a)).collect();
            wr.reverse();
            assert_close(&no_envelope_intervals(&cr, 1e-12), &wr, 1e-10);
        }
    }

    /// Degree 1: D is constant per span. Centre steps of 1 per span-length 1/3, radius
    /// steps 0, 2, 0 per span: only the middle span (‖q′‖ = 3 < |r′| = 6) has no envelope.
    #[test]
    fn polyline_middle_span() {
        let disks = [
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(1.0, 0.0), 1.0),
            Circle::new(DVec2::new(2.0, 0.0), 3.0),
            Circle::new(DVec2::new(3.0, 0.0), 3.0),
        ];
        let c = DiskBSpline::open(1, &disks, None).unwrap();
        assert_close(
            &no_envelope_intervals(&c, 1e-12),
            &[(1.0 / 3.0, 2.0 / 3.0)],
            1e-15,
        );
        // Radius step equal to the centre step: D ≡ 0 on that span, which counts.
        let disks = [disks[0], disks[1], Circle::new(DVec2::new(2.0, 0.0), 2.0)];
        let c = DiskBSpline::open(1, &disks, None).unwrap();
        assert_close(&no_envelope_intervals(&c, 1e-12), &[(0.5, 1.0)], 1e-15);
    }

    #[test]
    fn bernstein_form_matches_discriminant() {
        let (c, _) = bump(1.0);
        let coef = discriminant_bernstein(&c, 0.0, 1.0);
        assert_eq!(coef.len(), 5);
        for i in 0..=20 {
            let u = i as f64 / 20.0;
            assert!((bernstein_eval(&coef, u) - c.envelope_discriminant(u)).abs() < 1e-12);
        }
    }

    proptest! {
        #[test]
        fn constant_radius_has_no_intervals(c in dbsc_strategy(), r in 0.1f64..5.0) {
            let c = DiskBSpline::from_curve(c.curve().map(|v| glam::DVec3::new(v.x, v.y, r)));
            prop_assert!(no_envelope_intervals(&c, 1e-12).is_empty());
        }

        /// Dense samples agree with the intervals: clearly negative samples lie inside one,
        /// clearly positive ones outside all.
        #[test]
        fn intervals_agree_with_samples(c in dbsc_strategy(), grow in 0.0f64..30.0) {
            // Scale up radius variation so that intervals actually occur.
            let c = DiskBSpline::from_curve(c.curve().map(|v| glam::DVec3::new(v.x, v.y, v.z * (1.0 + grow))));
            let tol = 1e-10;
            let ivs = no_envelope_intervals(&c, tol);
            for w in ivs.windows(2) {
                prop_assert!(w[0].1 < w[1].0);
            }
            let (lo, hi) = c.domain();
            let bps = c.breakpoints();
            for i in 0..=400 {
                let t = lo + (hi - lo) * i as f64 / 400.0;
                if bps.contains(&t) {
                    continue; // one-sided derivatives differ at knots of low continuity
                }
                let d = c.envelope_discriminant(t);
                let mag = c.derivs(t, 1)[1].0.length_squared().max(1.0);
                let inside = ivs.iter().any(|&(a, b)| t >= a - tol && t <= b + tol);
                if d < -1e-6 * mag {
                    prop_assert!(inside, "t={} d={} ivs={:?}", t, d, ivs);
                }
                if d > 1e-6 * mag {
                    let strictly = ivs.iter().any(|&(a, b)| t > a + 1e-7 && t < b - 1e-7);
                    prop_assert!(!strictly, "t={} d={} ivs={:?}", t, d, ivs);
                }
            }
        }
    }
}
