//! B-spline basis functions and their derivatives (Cox–de Boor recursion in the triangular
//! form of Piegl & Tiller, algorithms A2.1–A2.3).

/// The knot span index i with u_i ≤ t < u_{i+1}, clamped to [p, n] (n + 1 control values),
/// so that t at the right end of the domain falls in the last non-empty span.
/// Binary search: O(log n).
pub fn find_span(knots: &[f64], degree: usize, n_ctrl: usize, t: f64) -> usize {
    let n = n_ctrl - 1;
    if t >= knots[n + 1] {
        // Last non-empty span at the right end of the domain.
        let mut i = n;
        while i > degree && knots[i] >= knots[n + 1] {
            i -= 1;
        }
        return i;
    }
    if t <= knots[degree] {
        let mut i = degree;
        while i < n && knots[i + 1] <= knots[degree] {
            i += 1;
        }
        return i;
    }
    let (mut lo, mut hi) = (degree, n + 1);
    let mut mid = (lo + hi) / 2;
    while t < knots[mid] || t >= knots[mid + 1] {
        if t < knots[mid] {
            hi = mid;
        } else {
            lo = mid;
        }
        mid = (lo + hi) / 2;
    }
    mid
}

/// The p + 1 non-zero basis functions N_{span−p,p}(t) .. N_{span,p}(t) (P&T A2.2).
pub fn basis_funs(knots: &[f64], degree: usize, span: usize, t: f64) -> Vec<f64> {
    with_basis_funs(knots, degree, span, t, <[f64]>::to_vec)
}

/// [`basis_funs`] handed to `f` without heap allocation for degrees below [`STACK_P1`]:
/// point evaluation ([`crate::spline::BSpline::eval`]) calls this for every point.
pub fn with_basis_funs<R>(
    knots: &[f64],
    degree: usize,
    span: usize,
    t: f64,
    f: impl FnOnce(&[f64]) -> R,
) -> R {
    let p1 = degree + 1;
    if p1 <= STACK_P1 {
        let mut n = [0.0; STACK_P1];
        let mut left = [0.0; STACK_P1];
        let mut right = [0.0; STACK_P1];
        basis_core(knots, degree, span, t, &mut n, &mut left, &mut right);
        f(&n[..p1])
    } else {
        let mut n = vec![0.0; p1];
        let mut left = vec![0.0; p1];
        let mut right = vec![0.0; p1];
        basis_core(knots, degree, span, t, &mut n, &mut left, &mut right);
        f(&n)
    }
}

/// P&T A2.2 into `n` with scratch `left`, `right` (each at least p + 1 long).
fn basis_core(
    knots: &[f64],
    p: usize,
    span: usize,
    t: f64,
    n: &mut [f64],
    left: &mut [f64],
    right: &mut [f64],
) {
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let den = right[r + 1] + left[j - r];
            let temp = if den != 0.0 { n[r] / den } else { 0.0 };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
}

/// Derivatives of orders 0..=k of the p + 1 non-zero basis functions at t (P&T A2.3):
/// `ders[d][j]` = N^{(d)}_{span−p+j,p}(t). Orders above p are zero.
pub fn ders_basis_funs(
    knots: &[f64],
    degree: usize,
    span: usize,
    t: f64,
    k: usize,
) -> Vec<Vec<f64>> {
    with_ders_basis_funs(knots, degree, span, t, k, |d| {
        d.chunks(degree + 1).map(<[f64]>::to_vec).collect()
    })
}

/// Degrees below this (and derivative orders below [`STACK_ORDERS`]) keep the work of
/// [`with_ders_basis_funs`] on the stack.
const STACK_P1: usize = 8;
/// See [`STACK_P1`].
const STACK_ORDERS: usize = 4;

/// [`ders_basis_funs`] handed to `f` as one row-major slice (`ders[d·(p + 1) + j]`) without
/// heap allocation for degrees below 8 and orders below 4: point evaluation in the inner
/// loops of the Hausdorff bounds calls this millions of times.
pub fn with_ders_basis_funs<R>(
    knots: &[f64],
    degree: usize,
    span: usize,
    t: f64,
    k: usize,
    f: impl FnOnce(&[f64]) -> R,
) -> R {
    let p1 = degree + 1;
    if p1 <= STACK_P1 && k < STACK_ORDERS {
        let mut ndu = [0.0; STACK_P1 * STACK_P1];
        let mut a = [0.0; 2 * STACK_P1];
        let mut lr = [0.0; 2 * STACK_P1];
        let mut ders = [0.0; STACK_ORDERS * STACK_P1];
        let ders = &mut ders[..(k + 1) * p1];
        ders_core(knots, degree, span, t, k, &mut ndu, &mut a, &mut lr, ders);
        f(ders)
    } else {
        let mut ndu = vec![0.0; p1 * p1];
        let mut a = vec![0.0; 2 * p1];
        let mut lr = vec![0.0; 2 * p1];
        let mut ders = vec![0.0; (k + 1) * p1];
        ders_core(
            knots, degree, span, t, k, &mut ndu, &mut a, &mut lr, &mut ders,
        );
        f(&ders)
    }
}

/// P&T A2.3 on row-major scratch of stride p + 1 (`ndu` (p + 1)², `a` and `lr` 2 (p + 1))
/// into `ders` ((k + 1)(p + 1)).
#[allow(clippy::too_many_arguments)]
fn ders_core(
    knots: &[f64],
    p: usize,
    span: usize,
    t: f64,
    k: usize,
    ndu: &mut [f64],
    a: &mut [f64],
    lr: &mut [f64],
    ders: &mut [f64],
) {
    let w = p + 1;
    let (left, right) = lr.split_at_mut(w);
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            // Lower triangle: knot differences.
            ndu[j * w + r] = right[r + 1] + left[j - r];
            let temp = if ndu[j * w + r] != 0.0 {
                ndu[r * w + j - 1] / ndu[j * w + r]
            } else {
                0.0
            };
            // Upper triangle: basis functions.
            ndu[r * w + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * w + j] = saved;
    }
    for j in 0..=p {
        ders[j] = ndu[j * w + p];
    }
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, w);
        a[0] = 1.0;
        for kk in 1..=k.min(p) {
            let mut d = 0.0;
            let rk = r as isize - kk as isize;
            let pk = p - kk;
            if r >= kk {
                let den = ndu[(pk + 1) * w + rk as usize];
                a[s2] = if den != 0.0 { a[s1] / den } else { 0.0 };
                d = a[s2] * ndu[rk as usize * w + pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                kk - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                let den = ndu[(pk + 1) * w + idx];
                a[s2 + j] = if den != 0.0 {
                    (a[s1 + j] - a[s1 + j - 1]) / den
                } else {
                    0.0
                };
                d += a[s2 + j] * ndu[idx * w + pk];
            }
            if r <= pk {
                let den = ndu[(pk + 1) * w + r];
                a[s2 + kk] = if den != 0.0 {
                    -a[s1 + kk - 1] / den
                } else {
                    0.0
                };
                d += a[s2 + kk] * ndu[r * w + pk];
            }
            ders[kk * w + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut fac = p as f64;
    for kk in 1..=k.min(p) {
        for v in &mut ders[kk * w..(kk + 1) * w] {
            *v *= fac;
        }
        fac *= (p - kk) as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn knots_strategy() -> impl Strategy<Value = (usize, Vec<f64>)> {
        (1usize..=5, 1usize..=8).prop_flat_map(|(p, inner)| {
            proptest::collection::vec(0.01f64..1.0, inner).prop_map(move |gaps| {
                let mut k = vec![0.0; p + 1];
                let mut acc = 0.0;
                for g in &gaps {
                    acc += g;
                    k.push(acc);
                }
                // Clamp the end: repeat the last knot p more times.
                for _ in 0..p {
                    k.push(acc);
                }
                (p, k)
            })
        })
    }

    proptest! {
        #[test]
        fn partition_of_unity_and_non_negative((p, k) in knots_strategy(), s in 0.0f64..=1.0) {
            let n_ctrl = k.len() - p - 1;
            let t = k[p] + s * (k[n_ctrl] - k[p]);
            let span = find_span(&k, p, n_ctrl, t);
            let n = basis_funs(&k, p, span, t);
            let sum: f64 = n.iter().sum();
            prop_assert!((sum - 1.0).abs() < 1e-12);
            prop_assert!(n.iter().all(|&v| v >= -1e-15));
            // Derivatives of the partition of unity vanish.
            let d = ders_basis_funs(&k, p, span, t, p);
            for (order, row) in d.iter().enumerate() {
                let s: f64 = row.iter().sum();
                if order == 0 {
                    prop_assert!((s - 1.0).abs() < 1e-12);
                } else {
                    let scale: f64 = row.iter().map(|v| v.abs()).sum::<f64>().max(1.0);
                    prop_assert!(s.abs() < 1e-9 * scale, "order {order} sum {s}");
                }
            }
            for j in 0..=p {
                prop_assert!((d[0][j] - n[j]).abs() < 1e-13);
            }
        }

        #[test]
        fn basis_derivative_matches_finite_difference((p, k) in knots_strategy(), s in 0.05f64..0.95) {
            let n_ctrl = k.len() - p - 1;
            let t = k[p] + s * (k[n_ctrl] - k[p]);
            let span = find_span(&k, p, n_ctrl, t);
            // Stay inside the span so the finite difference sees one polynomial piece.
            let h = 1e-6 * (k[span + 1] - k[span]);
            prop_assume!(t - h > k[span] && t + h < k[span + 1]);
            let d = ders_basis_funs(&k, p, span, t, 1);
            let np = basis_funs(&k, p, span, t + h);
            let nm = basis_funs(&k, p, span, t - h);
            for j in 0..=p {
                let fd = (np[j] - nm[j]) / (2.0 * h);
                prop_assert!((fd - d[1][j]).abs() < 1e-5 * d[1][j].abs().max(1.0), "j={j} fd={fd} d={}", d[1][j]);
            }
        }
    }

    #[test]
    fn single_span_is_bernstein() {
        // Clamped knots [0^4, 1^4]: N_{i,3} are the cubic Bernstein polynomials.
        let k = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        for i in 0..=20 {
            let t = i as f64 / 20.0;
            let span = find_span(&k, 3, 4, t);
            let n = basis_funs(&k, 3, span, t);
            let b = [
                (1.0 - t).powi(3),
                3.0 * t * (1.0 - t).powi(2),
                3.0 * t * t * (1.0 - t),
                t.powi(3),
            ];
            for j in 0..4 {
                assert!((n[j] - b[j]).abs() < 1e-15, "t={t} j={j}");
            }
        }
    }

    #[test]
    fn find_span_edges() {
        let k = [0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0];
        assert_eq!(find_span(&k, 2, 4, 0.0), 2);
        assert_eq!(find_span(&k, 2, 4, 0.5), 2);
        assert_eq!(find_span(&k, 2, 4, 1.0), 3);
        assert_eq!(find_span(&k, 2, 4, 2.0), 3);
    }

    /// Both sides of [`STACK_P1`] (stack and heap scratch): A2.2 against the zeroth row of
    /// A2.3, and the partition of unity.
    #[test]
    fn basis_funs_match_a2_3_on_stack_and_heap() {
        for p in 1..=2 * STACK_P1 {
            let mut k = vec![0.0; p + 1];
            k.extend((1..=4).map(|i| i as f64 * 0.7));
            k.extend(vec![2.8; p]);
            let n_ctrl = k.len() - p - 1;
            for i in 0..=40 {
                let t = 2.8 * i as f64 / 40.0;
                let span = find_span(&k, p, n_ctrl, t);
                let n = basis_funs(&k, p, span, t);
                let d = ders_basis_funs(&k, p, span, t, 0);
                assert_eq!(n.len(), p + 1);
                for (a, b) in n.iter().zip(&d[0]) {
                    assert!((a - b).abs() <= 1e-13, "p={p} t={t}: {a} vs {b}");
                }
                assert!((n.iter().sum::<f64>() - 1.0).abs() <= 1e-12);
            }
        }
    }
}
