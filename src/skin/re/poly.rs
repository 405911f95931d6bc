//! Univariate polynomials on [0, 1]: power basis for algebra, Bernstein basis for root
//! isolation and positivity certificates (re-mph-skinning-flexible Sec. 4.1–4.2: roots of f
//! "by Bézier–Bernstein representation"; positivity (17) proved on Bernstein coefficients).
//! Evaluation, subdivision and proofs are the shared kernel [`crate::geom::bernstein`].

use crate::geom::bernstein::{self, Step, Visitor};
use crate::geom::roots::brent_with;

/// A polynomial in the power basis, coefficients in ascending order (`c[k]` of tᵏ).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Poly {
    /// Coefficients in ascending order: `c[k]` multiplies tᵏ.
    pub c: Vec<f64>,
}

/// Deepest subdivision level for root isolation and positivity proofs: 2⁻⁴⁰ of the unit
/// interval is below the parameter resolution any caller asks for.
const MAX_DEPTH: u32 = 40;

impl Poly {
    /// The polynomial with power-basis coefficients `c`, ascending.
    pub fn new(c: Vec<f64>) -> Self {
        Poly { c }
    }

    /// The constant polynomial `a`.
    pub fn constant(a: f64) -> Self {
        Poly { c: vec![a] }
    }

    /// Nominal degree (`len − 1`; trailing zeros are kept).
    pub fn degree(&self) -> usize {
        self.c.len().saturating_sub(1)
    }

    /// Value at `t` (Horner).
    pub fn eval(&self, t: f64) -> f64 {
        self.c.iter().rev().fold(0.0, |acc, &a| acc * t + a)
    }

    /// The derivative (the constant 0 for a constant).
    pub fn deriv(&self) -> Poly {
        if self.c.len() <= 1 {
            return Poly::constant(0.0);
        }
        Poly::new(
            self.c
                .iter()
                .enumerate()
                .skip(1)
                .map(|(k, &a)| k as f64 * a)
                .collect(),
        )
    }

    /// The sum (as long as the longer operand).
    pub fn add(&self, o: &Poly) -> Poly {
        let n = self.c.len().max(o.c.len());
        Poly::new(
            (0..n)
                .map(|k| self.c.get(k).copied().unwrap_or(0.0) + o.c.get(k).copied().unwrap_or(0.0))
                .collect(),
        )
    }

    /// The difference `self − o`.
    pub fn sub(&self, o: &Poly) -> Poly {
        self.add(&o.scale(-1.0))
    }

    /// Every coefficient times `s`.
    pub fn scale(&self, s: f64) -> Poly {
        Poly::new(self.c.iter().map(|a| a * s).collect())
    }

    /// The product (the constant 0 when either has no coefficients).
    pub fn mul(&self, o: &Poly) -> Poly {
        if self.c.is_empty() || o.c.is_empty() {
            return Poly::constant(0.0);
        }
        let mut c = vec![0.0; self.c.len() + o.c.len() - 1];
        mul_add_into(&self.c, &o.c, &mut c);
        Poly::new(c)
    }

    /// Bernstein coefficients on [0, 1] of the same degree:
    /// bᵢ = Σ_{k≤i} C(i,k)/C(n,k) aₖ ([`bernstein::from_power`]).
    pub fn to_bernstein(&self) -> Vec<f64> {
        bernstein::from_power(&self.c)
    }

    /// Runs `f` on [`Self::to_bernstein`]'s coefficients, kept on the stack
    /// ([`bernstein::with_from_power`]).
    pub fn with_bernstein<R>(&self, f: impl FnOnce(&[f64]) -> R) -> R {
        bernstein::with_from_power(&self.c, f)
    }

    /// From Bernstein coefficients on [0, 1]: aₖ = C(n,k) Σ_{i≤k} (−1)^{k−i} C(k,i) bᵢ.
    pub fn from_bernstein(b: &[f64]) -> Poly {
        if b.is_empty() {
            return Poly::constant(0.0);
        }
        let n = b.len() - 1;
        Poly::new(
            (0..=n)
                .map(|k| {
                    let s: f64 = (0..=k)
                        .map(|i| {
                            let sg = if (k - i) % 2 == 0 { 1.0 } else { -1.0 };
                            sg * binom(k, i) * b[i]
                        })
                        .sum();
                    binom(n, k) * s
                })
                .collect(),
        )
    }

    /// Largest |coefficient| (a scale for relative tests).
    pub fn norm_inf(&self) -> f64 {
        self.c.iter().fold(0.0, |m, a| m.max(a.abs()))
    }

    /// Real roots in [0, 1] to parameter accuracy `tol`, ascending, by Bernstein subdivision
    /// (the variation-diminishing property: no sign change of the Bernstein coefficients on
    /// an interval ⇒ no root there) and Brent's method ([`brent_with`]) on intervals whose
    /// coefficients change sign exactly once (then exactly one simple root lies inside).
    /// Roots of even multiplicity are found where subdivision reaches width `tol` with
    /// coefficients that still change sign or vanish within `zero_tol` (absolute, in units
    /// of the polynomial's values).
    pub fn roots_01(&self, tol: f64, zero_tol: f64) -> Vec<f64> {
        let mut roots = Roots {
            tol: tol.max(MIN_ROOT_TOL),
            zero_tol,
            out: Vec::new(),
        };
        self.with_bernstein(|b| bernstein::subdivide(b, &mut roots));
        let mut out = roots.out;
        out.sort_by(f64::total_cmp);
        // Leaves of one multiple root come in chains `tol` apart: report each chain's middle.
        let mut merged: Vec<f64> = Vec::new();
        let mut start = 0;
        for k in 0..out.len() {
            let last_of_chain = k + 1 == out.len() || out[k + 1] - out[k] > 2.0 * tol;
            if last_of_chain {
                merged.push(0.5 * (out[start] + out[k]));
                start = k + 1;
            }
        }
        merged
    }
}

pub use crate::geom::bernstein::{Positivity, binom};

/// Least root tolerance of [`Poly::roots_01`] on [0, 1]: about the resolution of f64 there.
const MIN_ROOT_TOL: f64 = 1e-15;

/// Adds the product of the power-basis coefficients `a` and `b` into `out` (at least
/// `a.len() + b.len() − 1` long): `out[i + j] += a[i]·b[j]`, i then j ascending, so each
/// `out[k]` sums its terms in ascending i (the order of [`Poly::mul`]). Two rows are added
/// per pass over `out`: row by row, each pass's vectorised loads straddle the stores of
/// the pass before, shifted by one entry, and wait for them (store forwarding fails).
pub fn mul_add_into(a: &[f64], b: &[f64], out: &mut [f64]) {
    let nb = b.len();
    if nb == 0 {
        return;
    }
    let mut rows = a.chunks_exact(2);
    let mut i = 0;
    for pair in rows.by_ref() {
        let (x0, x1) = (pair[0], pair[1]);
        // Rows i and i + 1 in one pass: out[k] gets a[i]·b[k − i], then a[i + 1]·b[k − i − 1].
        if let Some(o) = out.get_mut(i) {
            *o += x0 * b[0];
        }
        for (j, o) in out.iter_mut().skip(i + 1).take(nb).enumerate() {
            let t = if j + 1 < nb { *o + x0 * b[j + 1] } else { *o };
            *o = t + x1 * b[j];
        }
        i += 2;
    }
    if let [x] = rows.remainder() {
        for (y, o) in b.iter().zip(out.iter_mut().skip(i)) {
            *o += x * y;
        }
    }
}

/// Value of a Bernstein polynomial at local parameter `s` (de Casteljau,
/// [`bernstein::eval`]).
#[cfg(test)]
pub fn bern_eval(b: &[f64], s: f64) -> f64 {
    bernstein::eval(b, s)
}

/// The root policy of [`Poly::roots_01`] on [`bernstein::subdivide`]: zero end
/// coefficients are roots; a piece without sign change whose coefficients are all clear of
/// `zero_tol` has none; one change with opposite end values is one simple root, found by
/// Brent's method on the piece's Bernstein form ([`bernstein::eval_horner`]) to `tol`;
/// pieces still undecided at width `tol` (or depth [`MAX_DEPTH`]) report their midpoint
/// when they change sign or nearly vanish there.
struct Roots {
    tol: f64,
    zero_tol: f64,
    out: Vec<f64>,
}

impl Visitor for Roots {
    fn visit(&mut self, b: &[f64], a: f64, c: f64, depth: u32) -> Step {
        let (first, last) = (b[0], b[b.len() - 1]);
        if first == 0.0 {
            self.out.push(a);
        }
        if last == 0.0 {
            self.out.push(c);
        }
        let inner = if b.len() > 2 {
            &b[1..b.len() - 1]
        } else {
            &[][..]
        };
        let all_pos = b.iter().all(|&x| x >= 0.0) && inner.iter().any(|&x| x > 0.0);
        let all_neg = b.iter().all(|&x| x <= 0.0) && inner.iter().any(|&x| x < 0.0);
        let changes = bernstein::sign_changes(b);
        if changes == 0
            && (all_pos || all_neg || b.iter().all(|&x| x != 0.0))
            && b.iter().all(|&x| x.abs() > self.zero_tol)
        {
            return Step::Keep;
        }
        if changes == 1 && first != 0.0 && last != 0.0 && (first > 0.0) != (last > 0.0) {
            // Exactly one simple root: Brent's method on the piece's Bernstein form, to
            // `tol` in the global parameter.
            let s = brent_with(
                |s| bernstein::eval_horner(b, s),
                0.0,
                1.0,
                first,
                last,
                self.tol / (c - a),
            );
            self.out.push(a + s * (c - a));
            return Step::Keep;
        }
        if c - a <= self.tol || depth >= MAX_DEPTH {
            let m = bernstein::eval(b, 0.5);
            if changes > 0 || m.abs() <= self.zero_tol {
                self.out.push(0.5 * (a + c));
            }
            return Step::Keep;
        }
        // A coefficient exactly zero at the split point is reported by both halves; merged
        // by the caller.
        Step::Split
    }
}

/// Proves p > 0 on [0, 1] by Bernstein subdivision ([`bernstein::prove_positive`]): a
/// polynomial whose Bernstein coefficients on an interval are all positive is positive
/// there (convex hull property). Refutes it with a witness when the end coefficient of a
/// piece (a curve value) is ≤ 0. `max_depth` bounds the subdivision (pieces ≥
/// 2^−max_depth wide).
pub fn prove_positive(p: &Poly, max_depth: u32) -> Positivity {
    p.with_bernstein(|b| bernstein::prove_positive(b, max_depth))
}

/// Real roots in [0, 1] of the cubic a₀ + a₁t + a₂t² + a₃t³ in closed form (Cardano /
/// trigonometric form; re-mph-skinning-flexible Sec. 4.1: "the formula of Cardano"),
/// falling back to the quadratic or linear formula when the leading coefficients vanish
/// relative to `rel_tol` × the largest coefficient. Ascending; roots within `rel_tol` outside
/// [0, 1] are clamped in.
pub fn cubic_roots_01(p: &Poly, rel_tol: f64) -> Vec<f64> {
    let a = |k: usize| p.c.get(k).copied().unwrap_or(0.0);
    let scale = p.norm_inf();
    if scale == 0.0 {
        return Vec::new();
    }
    let (a0, a1, a2, a3) = (a(0), a(1), a(2), a(3));
    let mut roots = Vec::new();
    if a3.abs() <= rel_tol * scale {
        if a2.abs() <= rel_tol * scale {
            if a1.abs() > rel_tol * scale {
                roots.push(-a0 / a1);
            }
        } else {
            let disc = a1 * a1 - 4.0 * a2 * a0;
            if disc >= 0.0 {
                let q = -0.5 * (a1 + a1.signum() * disc.sqrt());
                if q != 0.0 {
                    roots.push(q / a2);
                    roots.push(a0 / q);
                } else {
                    roots.push(0.0);
                }
            }
        }
    } else {
        // Depressed cubic t = s − b/3: s³ + p s + q = 0.
        let (b, c, d) = (a2 / a3, a1 / a3, a0 / a3);
        let pp = c - b * b / 3.0;
        let qq = 2.0 * b * b * b / 27.0 - b * c / 3.0 + d;
        let disc = qq * qq / 4.0 + pp * pp * pp / 27.0;
        let shift = -b / 3.0;
        if disc > 0.0 {
            let sq = disc.sqrt();
            let u = (-qq / 2.0 + sq).cbrt();
            let v = (-qq / 2.0 - sq).cbrt();
            roots.push(u + v + shift);
        } else if pp == 0.0 {
            roots.push(shift);
        } else {
            let m = 2.0 * (-pp / 3.0).sqrt();
            let arg = (3.0 * qq / (pp * m)).clamp(-1.0, 1.0);
            let th = arg.acos() / 3.0;
            for k in 0..3 {
                roots.push(m * (th - 2.0 * std::f64::consts::PI * k as f64 / 3.0).cos() + shift);
            }
        }
        // One Newton step on the original cubic polishes cancellation errors.
        let dp = p.deriv();
        for r in roots.iter_mut() {
            let d = dp.eval(*r);
            if d != 0.0 {
                *r -= p.eval(*r) / d;
            }
        }
    }
    let mut out: Vec<f64> = roots
        .into_iter()
        .filter(|r| r.is_finite() && *r >= -rel_tol && *r <= 1.0 + rel_tol)
        .map(|r| r.clamp(0.0, 1.0))
        .collect();
    out.sort_by(f64::total_cmp);
    out.dedup_by(|x, y| (*x - *y).abs() <= rel_tol);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn from_roots(rs: &[f64], lead: f64) -> Poly {
        rs.iter().fold(Poly::constant(lead), |p, &r| {
            p.mul(&Poly::new(vec![-r, 1.0]))
        })
    }

    /// `out[i + j] += a[i]·b[j]` row by row: the order `mul_add_into` must keep.
    fn naive_product(a: &[f64], b: &[f64]) -> Vec<f64> {
        let mut c = vec![0.0; a.len() + b.len() - 1];
        for (i, x) in a.iter().enumerate() {
            for (j, y) in b.iter().enumerate() {
                c[i + j] += x * y;
            }
        }
        c
    }

    proptest! {
        #[test]
        fn products_sum_in_the_row_order_bit_for_bit(
            a in proptest::collection::vec(-1e3f64..1e3, 1..12),
            b in proptest::collection::vec(-1e3f64..1e3, 1..12),
        ) {
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let want = naive_product(&a, &b);
            prop_assert_eq!(bits(&Poly::new(a.clone()).mul(&Poly::new(b.clone())).c), bits(&want));
            // Into a longer buffer with something already in it.
            let mut out = vec![0.5; a.len() + b.len() + 2];
            mul_add_into(&a, &b, &mut out);
            let mut start = vec![0.5; a.len() + b.len() + 2];
            for (i, x) in a.iter().enumerate() {
                for (j, y) in b.iter().enumerate() {
                    start[i + j] += x * y;
                }
            }
            prop_assert_eq!(bits(&out), bits(&start));
        }
    }

    #[test]
    fn bernstein_round_trip_and_values() {
        let bern_split = |b: &[f64], s: f64| {
            let mut r = b.to_vec();
            let mut l = vec![0.0; b.len()];
            bernstein::split_in_place(&mut r, s, &mut l);
            (l, r)
        };
        let p = Poly::new(vec![0.3, -2.0, 5.0, 1.5, -0.7]);
        let b = p.to_bernstein();
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            assert!((bern_eval(&b, t) - p.eval(t)).abs() < 1e-13);
        }
        let q = Poly::from_bernstein(&b);
        for (a, c) in p.c.iter().zip(&q.c) {
            assert!((a - c).abs() < 1e-12);
        }
        let (l, r) = bern_split(&b, 0.3);
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            assert!((bern_eval(&l, s) - p.eval(0.3 * s)).abs() < 1e-13);
            assert!((bern_eval(&r, s) - p.eval(0.3 + 0.7 * s)).abs() < 1e-13);
        }
    }

    #[test]
    fn double_root_is_found() {
        let p = from_roots(&[0.4, 0.4, 0.9], 2.0);
        let r = p.roots_01(1e-10, 1e-12);
        assert_eq!(r.len(), 2, "{r:?}");
        assert!((r[0] - 0.4).abs() < 1e-5);
        assert!((r[1] - 0.9).abs() < 1e-9);
    }

    #[test]
    fn positivity_proof_and_refutation() {
        // (t − 0.5)² + 1e-4 > 0: needs subdivision near 0.5.
        let p = from_roots(&[0.5, 0.5], 1.0).add(&Poly::constant(1e-4));
        assert!(matches!(prove_positive(&p, 30), Positivity::Proven { .. }));
        let q = from_roots(&[0.5, 0.5], 1.0).add(&Poly::constant(-1e-4));
        match prove_positive(&q, 30) {
            Positivity::Fails { t, value } => {
                assert!(value <= 0.0 && q.eval(t) <= 0.0);
            }
            other => panic!("{other:?}"),
        }
    }

    proptest! {
        #[test]
        fn subdivision_roots_match_planted(
            rs in proptest::collection::vec(0.02f64..0.98, 1..5),
            lead in prop_oneof![-3.0f64..-0.5, 0.5f64..3.0],
            extra in 1.2f64..3.0,
        ) {
            let mut rs = rs;
            rs.sort_by(f64::total_cmp);
            prop_assume!(rs.windows(2).all(|w| w[1] - w[0] > 1e-3));
            // An extra root outside [0, 1] must not be reported.
            let mut all = rs.clone();
            all.push(extra);
            let p = from_roots(&all, lead);
            let found = p.roots_01(1e-12, 0.0);
            prop_assert_eq!(found.len(), rs.len());
            for (a, b) in found.iter().zip(&rs) {
                prop_assert!((a - b).abs() < 1e-8, "{} vs {}", a, b);
            }
        }

        #[test]
        fn cardano_matches_subdivision(
            c in proptest::collection::vec(-5.0f64..5.0, 4),
        ) {
            let p = Poly::new(c);
            prop_assume!(p.c[3].abs() > 1e-3);
            let a = cubic_roots_01(&p, 1e-12);
            let b = p.roots_01(1e-12, 1e-12);
            // Compare only roots not too close to the interval ends or to each other.
            let interior = |v: &Vec<f64>| v.iter().copied().filter(|t| *t > 1e-6 && *t < 1.0 - 1e-6).collect::<Vec<_>>();
            let (ai, bi) = (interior(&a), interior(&b));
            prop_assume!(ai.windows(2).all(|w| w[1] - w[0] > 1e-4));
            prop_assume!(p.deriv().roots_01(1e-9, 0.0).iter().all(|t| p.eval(*t).abs() > 1e-6));
            prop_assert_eq!(ai.len(), bi.len(), "{:?} {:?}", a, b);
            for (x, y) in ai.iter().zip(&bi) {
                prop_assert!((x - y).abs() < 1e-7);
            }
        }
    }
}
