//! One Bernstein kernel for polynomials on [0, 1]: evaluation and subdivision by de
//! Casteljau, conversion from the power basis, sign variation, root isolation by
//! subdivision and positivity proofs.
//!
//! A polynomial of degree n is given by its Bernstein coefficients b₀ … bₙ,
//! f(u) = Σ bᵢ C(n, i) (1 − u)ⁿ⁻ⁱ uⁱ. Two properties carry every guaranteed result here
//! (Farouki and Rajan 1987; used by kruppa-2023 Sec. 3 for τ± and by
//! re-mph-skinning-flexible-kruppa-2021 Sec. 4.1–4.2, "Bézier–Bernstein representation"):
//! * convex hull: min bᵢ ≤ f(u) ≤ max bᵢ on [0, 1], so all bᵢ > 0 proves f > 0;
//! * variation diminishing: the number of roots in (0, 1) is at most, and of the same
//!   parity as, the number of sign changes of (bᵢ); no change means no root, exactly one
//!   change with opposite end values means exactly one simple root.
//!
//! Nothing here allocates per subdivision step: evaluation works on a stack array (up to
//! [`INLINE`] coefficients), splits write into caller buffers, and [`subdivide`] keeps all
//! pending pieces in one arena that grows only with the depth of the walk.

use crate::geom::roots::brent;

/// Coefficient count up to which evaluation needs no heap buffer (degree 63; the largest
/// polynomial of the crate, P = A² − s²B² of a quintic span, has degree 32).
pub const INLINE: usize = 64;

/// Coefficient count of the small stack buffer (degree ≤ 7: span polynomials of strokes).
pub const SMALL: usize = 8;

/// Binomial coefficient C(n, k) as f64 (0 for k > n); exact while the product's steps
/// C(n, i)·(n − i) stay below 2⁵³ (every n ≤ 54). Read from a table for n < `INLINE`
/// (products of Bernstein polynomials take three per coefficient pair), else computed.
pub fn binom(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    match BINOM.get(n) {
        Some(row) => row[k],
        None => binom_product(n, k),
    }
}

/// C(n, k), k ≤ n, as the product Π (n − i)/(i + 1) over i < min(k, n − k), in this order.
const fn binom_product(n: usize, k: usize) -> f64 {
    let k = if k < n - k { k } else { n - k };
    let mut acc = 1.0;
    let mut i = 0;
    while i < k {
        acc = acc * (n - i) as f64 / (i + 1) as f64;
        i += 1;
    }
    acc
}

/// [`binom_product`] for n < [`INLINE`], evaluated at compile time (IEEE arithmetic, the
/// same values as at run time).
static BINOM: [[f64; INLINE]; INLINE] = {
    let mut t = [[0.0; INLINE]; INLINE];
    let mut n = 0;
    while n < INLINE {
        let mut k = 0;
        while k <= n {
            t[n][k] = binom_product(n, k);
            k += 1;
        }
        n += 1;
    }
    t
};

/// Bernstein coefficients on [0, 1] of the polynomial Σ aₖ uᵏ (power basis, ascending) of
/// the same degree: bᵢ = Σ_{k≤i} C(i, k)/C(n, k) aₖ (Farouki–Rajan 1987, eq. 7).
pub fn from_power(a: &[f64]) -> Vec<f64> {
    let mut b = vec![0.0; a.len()];
    from_power_into(a, &mut b);
    b
}

/// [`from_power`] written into `out` (its first `a.len()` entries), for callers that keep
/// the coefficients on the stack.
pub fn from_power_into(a: &[f64], out: &mut [f64]) {
    let n = a.len().saturating_sub(1);
    let outs = out.iter_mut().enumerate().take(a.len());
    match POWER_RATIO.get(n) {
        // The same quotients, read from the table.
        Some(rows) => {
            for (i, o) in outs {
                *o = (0..=i).map(|k| rows[i][k] * a[k]).sum();
            }
        }
        None => {
            for (i, o) in outs {
                *o = (0..=i).map(|k| binom(i, k) / binom(n, k) * a[k]).sum();
            }
        }
    }
}

/// Runs `f` on [`from_power`]'s coefficients of `a`, kept on the stack when
/// `a.len() ≤ INLINE` ([`with_scratch`]).
pub fn with_from_power<R>(a: &[f64], f: impl FnOnce(&[f64]) -> R) -> R {
    with_scratch(a.len(), |b| {
        from_power_into(a, b);
        f(b)
    })
}

/// Degree below which [`from_power`] reads its quotients C(i, k)/C(n, k) from a table (r²
/// of a quintic RE segment has degree 12).
const POWER_TABLE: usize = 16;

/// C(i, k)/C(n, k) for k ≤ i ≤ n < [`POWER_TABLE`], as [`from_power`] would divide them
/// ([`binom_product`] quotients, evaluated at compile time with the same IEEE operations).
static POWER_RATIO: [[[f64; POWER_TABLE]; POWER_TABLE]; POWER_TABLE] = {
    let mut t = [[[0.0; POWER_TABLE]; POWER_TABLE]; POWER_TABLE];
    let mut n = 0;
    while n < POWER_TABLE {
        let mut i = 0;
        while i <= n {
            let mut k = 0;
            while k <= i {
                t[n][i][k] = binom_product(i, k) / binom_product(n, k);
                k += 1;
            }
            i += 1;
        }
        n += 1;
    }
    t
};

/// Runs `f` on a scratch slice of length `n` holding a copy of `b` (a stack array when
/// `n ≤ INLINE`).
fn with_copy<R>(b: &[f64], f: impl FnOnce(&mut [f64]) -> R) -> R {
    let n = b.len();
    // Span polynomials of cubic strokes have 4 coefficients: a small array spares the
    // zeroing of the large one.
    if n <= SMALL {
        let mut w = [0.0f64; SMALL];
        w[..n].copy_from_slice(b);
        f(&mut w[..n])
    } else if n <= INLINE {
        let mut w = [0.0f64; INLINE];
        w[..n].copy_from_slice(b);
        f(&mut w[..n])
    } else {
        let mut w = b.to_vec();
        f(&mut w)
    }
}

/// Runs `f` on a zeroed scratch slice of length `n` (on the stack when `n ≤ INLINE`).
fn with_scratch<R>(n: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    if n <= SMALL {
        f(&mut [0.0f64; SMALL][..n])
    } else if n <= INLINE {
        f(&mut [0.0f64; INLINE][..n])
    } else {
        f(&mut vec![0.0; n])
    }
}

/// One de Casteljau level in place: wᵢ ← (1 − u) wᵢ + u wᵢ₊₁ for i < `len` − 1.
#[inline]
fn casteljau_step(w: &mut [f64], len: usize, u: f64) {
    for i in 0..len - 1 {
        w[i] = w[i] * (1.0 - u) + w[i + 1] * u;
    }
}

/// f(u) by de Casteljau's algorithm (numerically stable on [0, 1]); 0 for no coefficients.
pub fn eval(b: &[f64], u: f64) -> f64 {
    if b.is_empty() {
        return 0.0;
    }
    with_copy(b, |w| {
        let n = w.len();
        for r in 1..n {
            casteljau_step(w, n - r + 1, u);
        }
        w[0]
    })
}

/// f(u) in O(n) operations, for root polishing, where [`eval`]'s O(n²) de Casteljau steps
/// dominate: with v = 1 − u, f(u) = vⁿ Σ bᵢ C(n, i) (u/v)ⁱ for u ≤ ½ and
/// uⁿ Σ bᵢ C(n, i) (v/u)ⁿ⁻ⁱ above, each sum by Horner's rule in a ratio ≤ 1. Its rounding
/// error is bounded like de Casteljau's, by a small multiple of n·ε·Σ |bᵢ| Bᵢⁿ(u)
/// (Horner's bound on Σ |bᵢ| C(n, i) rⁱ, times vⁿ or uⁿ). 0 for no coefficients.
pub fn eval_horner(b: &[f64], u: f64) -> f64 {
    let Some(n) = b.len().checked_sub(1) else {
        return 0.0;
    };
    let v = 1.0 - u;
    // n fits i32: a polynomial of 2³¹ coefficients is not a span polynomial.
    let pow = |x: f64| x.powi(n as i32);
    if u <= 0.5 {
        let r = u / v;
        let sum = (0..=n)
            .rev()
            .fold(0.0, |acc, i| acc * r + b[i] * binom(n, i));
        sum * pow(v)
    } else {
        let r = v / u;
        let sum = (0..=n).fold(0.0, |acc, i| acc * r + b[i] * binom(n, i));
        sum * pow(u)
    }
}

/// (f(u), f′(u), f″(u)) by de Casteljau's algorithm: the last three levels hold the
/// derivatives, f″ = n(n − 1)(w₀ − 2w₁ + w₂) on the level of three points and
/// f′ = n(v₁ − v₀) on the level of two: the k + 1 points left after n − k steps are
/// wⱼ = Σᵢ bᵢ₊ⱼ Bᵢⁿ⁻ᵏ(u), so Δᵏw₀ = Σᵢ Δᵏbᵢ Bᵢⁿ⁻ᵏ(u) = f⁽ᵏ⁾(u) (n − k)!/n!. Zeros for no
/// coefficients.
pub fn eval_d2(b: &[f64], u: f64) -> [f64; 3] {
    let n = b.len();
    match n {
        0 => return [0.0; 3],
        1 => return [b[0], 0.0, 0.0],
        _ => {}
    }
    // Cubic spans: the same steps on a fixed-size copy, which the compiler unrolls.
    if let Ok(c) = <[f64; CUBIC]>::try_from(b) {
        return eval_d2_in(&mut { c }, u);
    }
    with_copy(b, |w| eval_d2_in(w, u))
}

/// Coefficient count of a cubic, the degree of most strokes: [`eval_d2`] and [`sub_into`]
/// run their loops on arrays of this size, with the same operations in the same order (the
/// same results, bit for bit) but unrolled.
const CUBIC: usize = 4;

/// [`eval_d2`] on a copy `w` (≥ 2 coefficients) it may overwrite.
#[inline(always)]
fn eval_d2_in(w: &mut [f64], u: f64) -> [f64; 3] {
    let n = w.len();
    // Reduce to three points (two for degree 1).
    for r in 1..n.saturating_sub(2) {
        casteljau_step(w, n - r + 1, u);
    }
    let deg = (n - 1) as f64;
    let d2 = if n >= 3 {
        let d2 = deg * (deg - 1.0) * (w[0] - 2.0 * w[1] + w[2]);
        casteljau_step(w, 3, u);
        d2
    } else {
        0.0
    };
    let d1 = deg * (w[1] - w[0]);
    [w[0] * (1.0 - u) + w[1] * u, d1, d2]
}

/// De Casteljau split at `u` in place: `work` (the coefficients on [0, 1] on entry) ends
/// as the piece on [u, 1] and `left` receives the piece on [0, u], both reparametrised to
/// [0, 1]. `left.len()` must equal `work.len()`.
pub fn split_in_place(work: &mut [f64], u: f64, left: &mut [f64]) {
    let n = work.len();
    for (r, l) in left.iter_mut().enumerate().take(n) {
        *l = work[0];
        casteljau_step(work, n - r, u);
    }
}

/// The piece of `b` on [u0, u1] ⊂ [0, 1], reparametrised to [0, 1], written to `out`
/// (`out.len() == b.len()`): a split at u0 keeps the right part, a split of that at
/// (u1 − u0)/(1 − u0) keeps the left part.
pub fn sub_into(b: &[f64], u0: f64, u1: f64, out: &mut [f64]) {
    if let (Ok(c), Ok(o)) = (
        <&[f64; CUBIC]>::try_from(b),
        <&mut [f64; CUBIC]>::try_from(&mut *out),
    ) {
        *o = sub_array(c, u0, u1);
        return;
    }
    with_scratch(b.len(), |w| sub_in(b, u0, u1, out, w));
}

/// [`sub_into`] for a polynomial of fixed length `N` (its loops unrolled).
#[inline(always)]
pub fn sub_array<const N: usize>(b: &[f64; N], u0: f64, u1: f64) -> [f64; N] {
    let (mut out, mut w) = ([0.0; N], [0.0; N]);
    sub_in(b, u0, u1, &mut out, &mut w);
    out
}

/// [`sub_into`] with a scratch slice `w` of the same length.
#[inline(always)]
fn sub_in(b: &[f64], u0: f64, u1: f64, out: &mut [f64], w: &mut [f64]) {
    let n = b.len();
    out.copy_from_slice(b);
    // `out` becomes the piece on [u0, 1]; the left part is not needed.
    for r in 0..n {
        casteljau_step(out, n - r, u0);
    }
    if u0 >= 1.0 {
        return;
    }
    let s = (u1 - u0) / (1.0 - u0);
    w.copy_from_slice(out);
    for (r, o) in out.iter_mut().enumerate() {
        *o = w[0];
        casteljau_step(w, n - r, s);
    }
}

/// The derivative d/du in place: the first `len − 1` entries become n (bᵢ₊₁ − bᵢ) with
/// n = `len − 1`; returns the new length (a constant's derivative is the zero constant).
pub fn deriv_in_place(b: &mut [f64]) -> usize {
    let n = b.len().saturating_sub(1);
    if n == 0 {
        if let Some(x) = b.first_mut() {
            *x = 0.0;
        }
        return b.len();
    }
    for i in 0..n {
        b[i] = n as f64 * (b[i + 1] - b[i]);
    }
    n
}

/// [min, max] of the coefficients: an enclosure of f on [0, 1] (convex hull property).
pub fn range(b: &[f64]) -> (f64, f64) {
    b.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

/// Sign changes of the coefficient sequence, zeros skipped: an upper bound of the number
/// of roots in (0, 1) with the same parity (variation diminishing).
pub fn sign_changes(b: &[f64]) -> usize {
    let mut last = 0.0f64;
    let mut n = 0;
    for &x in b {
        if x != 0.0 {
            if last != 0.0 && (x > 0.0) != (last > 0.0) {
                n += 1;
            }
            last = x;
        }
    }
    n
}

/// What a [`Visitor`] wants done with the piece it was shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Done with this piece.
    Keep,
    /// Split it at its midpoint and visit the left half, then the right half.
    Split,
    /// Stop the whole walk.
    Halt,
}

/// The policy of a subdivision walk ([`subdivide`]).
pub trait Visitor {
    /// Called for each piece: its coefficients (reparametrised to [0, 1]), its interval
    /// [u0, u1] of the original parameter and its depth (0 for [0, 1]).
    fn visit(&mut self, b: &[f64], u0: f64, u1: f64, depth: u32) -> Step;
    /// Called right after a piece is split at `um`, before its halves are visited.
    fn split(&mut self, _left: &[f64], _right: &[f64], _um: f64) {}
}

/// Depth-first binary subdivision of `b` at midpoints, left half first, driven by `v`.
/// All pending pieces live in one arena (at most depth + 2 pieces), so a split costs no
/// heap allocation once the arena has grown to the walk's depth. The whole polynomial is
/// visited before the arena exists: a walk that ends there (no sign change, a positivity
/// proved at once) allocates nothing.
pub fn subdivide(b: &[f64], v: &mut impl Visitor) {
    let n = b.len();
    if n == 0 || v.visit(b, 0.0, 1.0, 0) != Step::Split {
        return;
    }
    let mut arena: Vec<f64> = Vec::with_capacity(n * 16);
    arena.extend_from_slice(b);
    let mut stack: Vec<(f64, f64, u32)> = Vec::with_capacity(16);
    split_top(&mut arena, &mut stack, n, (0.0, 1.0, 0), v);
    while let Some((u0, u1, depth)) = stack.pop() {
        let off = stack.len() * n;
        match v.visit(&arena[off..off + n], u0, u1, depth) {
            Step::Halt => return,
            Step::Keep => arena.truncate(off),
            Step::Split => split_top(&mut arena, &mut stack, n, (u0, u1, depth), v),
        }
    }
}

/// Splits the piece (`u0`, `u1`, `depth`) at the arena's top (the slot of `stack.len()`)
/// into its halves: the right one stays in this slot, the left one sits above it, and
/// both are pushed, left last (visited first).
fn split_top(
    arena: &mut Vec<f64>,
    stack: &mut Vec<(f64, f64, u32)>,
    n: usize,
    (u0, u1, depth): (f64, f64, u32),
    v: &mut impl Visitor,
) {
    let off = stack.len() * n;
    arena.resize(off + 2 * n, 0.0);
    let (right, left) = arena[off..].split_at_mut(n);
    split_in_place(right, 0.5, left);
    let um = 0.5 * (u0 + u1);
    v.split(left, right, um);
    stack.push((um, u1, depth + 1));
    stack.push((u0, um, depth + 1));
}

/// Tolerances and caps of [`isolate_roots`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RootOptions {
    /// Parameter accuracy of each root (in u), and the width below which a piece with
    /// undecided sign changes is reported as one root at its midpoint.
    pub tol: f64,
    /// Subdivision depth cap.
    pub max_depth: u32,
    /// Cap on split pieces: the depth cap bounds a path, not the tree (a polynomial that
    /// is zero up to rounding changes sign in every piece). Once reached, every piece still
    /// open is reported at its midpoint, as at the depth cap.
    pub max_splits: usize,
}

/// Roots in (0, 1) of f given by `b`, ascending: pieces without a sign change are
/// discarded, a piece with exactly one change and opposite end values holds exactly one
/// root, refined by Brent's method on f to `opts.tol`; pieces narrower than `opts.tol` (or
/// at a cap) that are still undecided are reported once, at their midpoint, as is a zero
/// coefficient exactly at a split point. Roots closer than `opts.tol` are merged.
pub fn isolate_roots(b: &[f64], opts: &RootOptions) -> Vec<f64> {
    struct Iso<'a> {
        whole: &'a [f64],
        opts: RootOptions,
        splits: usize,
        out: Vec<f64>,
    }
    impl Visitor for Iso<'_> {
        fn visit(&mut self, f: &[f64], u0: f64, u1: f64, depth: u32) -> Step {
            let v = sign_changes(f);
            if v == 0 {
                return Step::Keep;
            }
            let (f0, f1) = (f[0], f[f.len() - 1]);
            if v == 1 && f0 != 0.0 && f1 != 0.0 && (f0 > 0.0) != (f1 > 0.0) {
                let whole = self.whole;
                self.out
                    .push(brent(|u| eval(whole, u), u0, u1, self.opts.tol));
                return Step::Keep;
            }
            if u1 - u0 <= self.opts.tol || depth >= self.opts.max_depth || self.splits == 0 {
                self.out.push(0.5 * (u0 + u1));
                return Step::Keep;
            }
            self.splits -= 1;
            Step::Split
        }
        fn split(&mut self, _left: &[f64], right: &[f64], um: f64) {
            if right[0] == 0.0 {
                self.out.push(um);
            }
        }
    }
    let mut iso = Iso {
        whole: b,
        opts: *opts,
        splits: opts.max_splits,
        out: Vec::new(),
    };
    subdivide(b, &mut iso);
    let mut out = iso.out;
    out.sort_by(f64::total_cmp);
    out.dedup_by(|a, b| (*a - *b).abs() <= opts.tol);
    out
}

/// Outcome of a positivity proof on [0, 1].
#[derive(Clone, Debug, PartialEq)]
pub enum Positivity {
    /// Every Bernstein coefficient on every piece of a subdivision is > 0: f > 0 on [0, 1].
    Proven {
        /// Pieces of the subdivision that proved it.
        pieces: usize,
    },
    /// f(t) ≤ 0 at this parameter (a witness).
    Fails {
        /// The witness parameter.
        t: f64,
        /// f(t), ≤ 0.
        value: f64,
    },
    /// Neither proved nor refuted down to the subdivision limit.
    Undecided,
}

/// Proves f > 0 on [0, 1] by subdivision: a piece whose coefficients are all positive is
/// positive (convex hull); the end coefficients of a piece are curve values, so one ≤ 0
/// refutes with a witness. Pieces are at least 2^−`max_depth` wide.
pub fn prove_positive(b: &[f64], max_depth: u32) -> Positivity {
    struct Pos {
        max_depth: u32,
        pieces: usize,
        result: Option<Positivity>,
    }
    impl Visitor for Pos {
        fn visit(&mut self, b: &[f64], a: f64, c: f64, d: u32) -> Step {
            let (first, last) = (b[0], b[b.len() - 1]);
            if first <= 0.0 {
                self.result = Some(Positivity::Fails { t: a, value: first });
                return Step::Halt;
            }
            if last <= 0.0 {
                self.result = Some(Positivity::Fails { t: c, value: last });
                return Step::Halt;
            }
            if b.iter().all(|&x| x > 0.0) {
                self.pieces += 1;
                return Step::Keep;
            }
            if d >= self.max_depth {
                self.result = Some(Positivity::Undecided);
                return Step::Halt;
            }
            Step::Split
        }
    }
    if b.is_empty() {
        return Positivity::Undecided;
    }
    let mut pos = Pos {
        max_depth,
        pieces: 0,
        result: None,
    };
    subdivide(b, &mut pos);
    pos.result
        .unwrap_or(Positivity::Proven { pieces: pos.pieces })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn binomial_table_is_the_run_time_product_and_pascals_triangle() {
        for n in 0..INLINE + 4 {
            for k in 0..=n {
                let run_time = binom_product(std::hint::black_box(n), std::hint::black_box(k));
                assert_eq!(binom(n, k).to_bits(), run_time.to_bits(), "C({n}, {k})");
                // Pascal's rule, exact while the product's steps stay below 2⁵³ (n ≤ 54).
                if n <= 54 && k > 0 && k < n {
                    assert_eq!(binom(n, k), binom(n - 1, k - 1) + binom(n - 1, k));
                }
            }
            assert_eq!(binom(n, n + 1), 0.0);
        }
        assert_eq!(binom(10, 3), 120.0);
    }

    #[test]
    fn power_ratio_table_is_the_run_time_quotient() {
        for (n, rows) in POWER_RATIO.iter().enumerate() {
            for (i, row) in rows.iter().enumerate().take(n + 1) {
                for (k, ratio) in row.iter().enumerate().take(i + 1) {
                    let run_time = binom_product(std::hint::black_box(i), k)
                        / binom_product(std::hint::black_box(n), k);
                    assert_eq!(ratio.to_bits(), run_time.to_bits());
                }
            }
        }
        // Degree 3 by hand: C(i, k)/C(3, k), so 1 + u maps to (1, 4/3, 5/3, 2).
        let b = from_power(&[1.0, 1.0, 0.0, 0.0]);
        for (x, y) in b.iter().zip([1.0, 4.0 / 3.0, 5.0 / 3.0, 2.0]) {
            assert!((x - y).abs() < 1e-15, "{b:?}");
        }
    }

    /// Power coefficients of lead · Π (u − rᵢ).
    fn from_roots(rs: &[f64], lead: f64) -> Vec<f64> {
        let mut c = vec![lead];
        for &r in rs {
            let mut n = vec![0.0; c.len() + 1];
            for (k, &a) in c.iter().enumerate() {
                n[k] -= r * a;
                n[k + 1] += a;
            }
            c = n;
        }
        c
    }

    fn horner(a: &[f64], u: f64) -> f64 {
        a.iter().rev().fold(0.0, |acc, &x| acc * u + x)
    }

    #[test]
    fn eval_split_sub_deriv_agree_with_power_form() {
        let a = [0.3, -2.0, 5.0, 1.5, -0.7];
        let b = from_power(&a);
        let mut left = [0.0; 5];
        let mut right = b.clone();
        split_in_place(&mut right, 0.3, &mut left);
        let mut piece = [0.0; 5];
        sub_into(&b, 0.2, 0.7, &mut piece);
        let mut d = b.clone();
        let m = deriv_in_place(&mut d);
        assert_eq!(m, 4);
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            assert!((eval(&b, s) - horner(&a, s)).abs() < 1e-13);
            assert!((eval(&left, s) - horner(&a, 0.3 * s)).abs() < 1e-13);
            assert!((eval(&right, s) - horner(&a, 0.3 + 0.7 * s)).abs() < 1e-13);
            assert!((eval(&piece, s) - horner(&a, 0.2 + 0.5 * s)).abs() < 1e-13);
            let da = [-2.0, 10.0, 4.5, -2.8];
            assert!((eval(&d[..m], s) - horner(&da, s)).abs() < 1e-12);
        }
        let (lo, hi) = range(&b);
        assert!(lo <= horner(&a, 0.5) && horner(&a, 0.5) <= hi);
        // More coefficients than the stack array: the heap path gives the same value.
        let big = from_power(&from_roots(&[0.5; 70], 1.0));
        assert!(eval(&big, 0.5).abs() < 1e-12 && eval(&big, 1.0) > 0.0);
    }

    proptest! {
        #[test]
        fn value_and_derivatives_match_the_power_form(
            a in proptest::collection::vec(-5.0f64..5.0, 1..12),
            u in 0.0f64..=1.0,
        ) {
            // f, f′, f″ of the power form by Horner against eval_d2 of the Bernstein form.
            let da: Vec<f64> = (1..a.len()).map(|k| k as f64 * a[k]).collect();
            let dda: Vec<f64> = (1..da.len()).map(|k| k as f64 * da[k]).collect();
            let [f, f1, f2] = eval_d2(&from_power(&a), u);
            let scale = a.iter().map(|x| x.abs()).sum::<f64>() * (a.len() * a.len()) as f64;
            prop_assert!((f - horner(&a, u)).abs() <= 1e-12 * scale);
            prop_assert!((f1 - horner(&da, u)).abs() <= 1e-11 * scale);
            prop_assert!((f2 - horner(&dda, u)).abs() <= 1e-10 * scale);
            prop_assert_eq!(f, eval(&from_power(&a), u));
        }

        #[test]
        fn horner_evaluation_matches_de_casteljau(
            b in proptest::collection::vec(-5.0f64..5.0, 1..20),
            u in 0.0f64..=1.0,
        ) {
            // Both within a few n·ε of Σ |bᵢ| Bᵢⁿ(u), which Σ |bᵢ| bounds.
            let scale = b.iter().map(|x| x.abs()).sum::<f64>() * b.len() as f64;
            let (h, c) = (eval_horner(&b, u), eval(&b, u));
            prop_assert!((h - c).abs() <= 1e-14 * scale, "{} vs {}", h, c);
        }
    }

    #[test]
    fn horner_evaluation_closed_forms() {
        // (1 − u)³ + u³ = 1 − 3u + 3u²: Bernstein (1, 0, 0, 1); its ends exactly.
        let b = [1.0, 0.0, 0.0, 1.0];
        for u in [0.0, 0.2, 0.5, 0.7, 1.0] {
            assert!((eval_horner(&b, u) - (1.0 - 3.0 * u + 3.0 * u * u)).abs() < 1e-15);
        }
        assert_eq!(eval_horner(&b, 0.0), 1.0);
        assert_eq!(eval_horner(&b, 1.0), 1.0);
        assert_eq!(eval_horner(&[], 0.3), 0.0);
        assert_eq!(eval_horner(&[2.5], 0.3), 2.5);
    }

    #[test]
    fn sign_changes_skip_zeros() {
        assert_eq!(sign_changes(&[1.0, 0.0, -1.0, 0.0, 2.0]), 2);
        assert_eq!(sign_changes(&[0.0, 0.0]), 0);
    }

    #[test]
    fn positivity_proof_and_refutation() {
        let p = from_power(&[0.25 + 1e-4, -1.0, 1.0]);
        assert!(matches!(prove_positive(&p, 30), Positivity::Proven { .. }));
        let q = from_power(&[0.25 - 1e-4, -1.0, 1.0]);
        match prove_positive(&q, 30) {
            Positivity::Fails { t, value } => assert!(value <= 0.0 && eval(&q, t) <= 0.0),
            other => panic!("{other:?}"),
        }
        assert_eq!(prove_positive(&q, 0), Positivity::Undecided);
    }

    proptest! {
        #[test]
        fn isolated_roots_match_planted(
            rs in proptest::collection::vec(0.02f64..0.98, 1..6),
            lead in prop_oneof![-3.0f64..-0.5, 0.5f64..3.0],
            extra in 1.2f64..3.0,
        ) {
            let mut rs = rs;
            rs.sort_by(f64::total_cmp);
            prop_assume!(rs.windows(2).all(|w| w[1] - w[0] > 1e-3));
            let mut all = rs.clone();
            all.push(extra);
            let b = from_power(&from_roots(&all, lead));
            let opts = RootOptions { tol: 1e-13, max_depth: 60, max_splits: 20_000 };
            let found = isolate_roots(&b, &opts);
            prop_assert_eq!(found.len(), rs.len(), "{:?} vs {:?}", found, rs);
            for (a, r) in found.iter().zip(&rs) {
                prop_assert!((a - r).abs() < 1e-9, "{} vs {}", a, r);
            }
        }
    }
}
