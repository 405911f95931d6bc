//! Linear solvers of the fits: collocation matrices, totally positive band systems
//! (de Boor & Pinkus 1977), cyclic band systems with a Woodbury correction, dense LU, and
//! the normal equations of least squares by Cholesky (P&T eq. 9.63–9.67).

use super::{Components, FitError, FitSystem, SINGULAR_PIVOT_RATIO};
use crate::spline::basis::{basis_funs, find_span};
use nalgebra::{Cholesky, DMatrix, LU};

/// The collocation matrix A_{ij} = N_j(t_i) (rows = `params`, `n_cols` columns). For a
/// closed curve the `n_cols + p` stored basis functions wrap: stored index k adds to column
/// k mod n_cols.
pub(super) fn collocation(
    knots: &[f64],
    degree: usize,
    n_stored: usize,
    n_cols: usize,
    params: &[f64],
) -> DMatrix<f64> {
    let mut a = DMatrix::zeros(params.len(), n_cols);
    for (i, &t) in params.iter().enumerate() {
        let span = find_span(knots, degree, n_stored, t);
        for (j, v) in basis_funs(knots, degree, span, t).into_iter().enumerate() {
            a[(i, (span - degree + j) % n_cols)] += v;
        }
    }
    a
}

pub(super) fn rhs<P: Components>(points: &[P]) -> DMatrix<f64> {
    DMatrix::from_fn(points.len(), P::DIM, |i, k| points[i].get(k))
}

pub(super) fn to_points<P: Components>(x: &DMatrix<f64>) -> Vec<P> {
    (0..x.nrows())
        .map(|i| {
            let mut v = P::ZERO;
            for k in 0..P::DIM {
                v.set(k, x[(i, k)]);
            }
            v
        })
        .collect()
}

pub(super) fn pivot_ratio(diag: impl Iterator<Item = f64>) -> f64 {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for d in diag {
        lo = lo.min(d.abs());
        hi = hi.max(d.abs());
    }
    if hi > 0.0 { lo / hi } else { 0.0 }
}

/// Solve B X = R for a square band matrix given by rows: row i holds `rows[i]` (all of one
/// width w) for columns start[i]..start[i] + w − 1 (entries past the last column are zero),
/// with start[i] non-decreasing and the diagonal inside every row's band. Gaussian
/// elimination without pivoting keeps every row inside its band: O(m·w²) time, O(m·w)
/// memory. It is stable for totally positive B (de Boor & Pinkus 1977), which B-spline
/// collocation matrices of consecutive basis functions at increasing parameters are
/// (Karlin); the Schoenberg–Whitney condition puts non-zeros on the diagonal.
pub(super) fn band_solve(
    start: &[usize],
    mut rows: Vec<Vec<f64>>,
    r: &DMatrix<f64>,
    system: FitSystem,
) -> Result<DMatrix<f64>, FitError> {
    let m = start.len();
    let w = rows.first().map_or(0, Vec::len);
    let singular = |ratio| FitError::Singular {
        system,
        size: m,
        ratio,
    };
    let banded = rows.len() == m
        && r.nrows() == m
        && (0..m).all(|i| {
            rows[i].len() == w
                && start[i] <= i
                && i < start[i] + w
                && (i == 0 || start[i - 1] <= start[i])
        });
    if !banded {
        return Err(singular(0.0));
    }
    let mut x = r.clone();
    for k in 0..m {
        let pivot = rows[k][k - start[k]];
        if pivot == 0.0 || !pivot.is_finite() {
            return Err(singular(0.0));
        }
        let mut i = k + 1;
        while i < m && start[i] <= k {
            let f = rows[i][k - start[i]] / pivot;
            if f != 0.0 {
                for c in k..start[k] + w {
                    let v = rows[k][c - start[k]];
                    rows[i][c - start[i]] -= f * v;
                }
                for d in 0..x.ncols() {
                    let v = x[(k, d)];
                    x[(i, d)] -= f * v;
                }
            }
            i += 1;
        }
    }
    let ratio = pivot_ratio((0..m).map(|k| rows[k][k - start[k]]));
    if ratio.is_nan() || ratio < SINGULAR_PIVOT_RATIO {
        return Err(singular(ratio));
    }
    for k in (0..m).rev() {
        let row = &rows[k];
        for d in 0..x.ncols() {
            let mut acc = x[(k, d)];
            for c in k + 1..(start[k] + w).min(m) {
                acc -= row[c - start[k]] * x[(c, d)];
            }
            x[(k, d)] = acc / row[k - start[k]];
        }
    }
    Ok(x)
}

/// Open interpolation A X = B with A_{ij} = N_{j,p}(t_i): row i is non-zero only in
/// columns span_i − p..=span_i, a totally positive band matrix ([`band_solve`]).
pub(super) fn solve_open_band(
    knots: &[f64],
    degree: usize,
    params: &[f64],
    b: &DMatrix<f64>,
) -> Result<DMatrix<f64>, FitError> {
    let m = params.len();
    let mut start = Vec::with_capacity(m);
    let mut rows = Vec::with_capacity(m);
    for &t in params {
        let span = find_span(knots, degree, m, t);
        start.push(span - degree);
        rows.push(basis_funs(knots, degree, span, t));
    }
    band_solve(&start, rows, b, FitSystem::OpenInterpolation)
}

/// Closed interpolation A X = B with the cyclic collocation matrix of the wrapped basis
/// (n = m distinct control values, m + p stored basis functions), in O(m·p² + p³) instead
/// of dense LU's O(m³). Columns are shifted by c = ⌊p/2⌋ so that the band part
/// B (stored basis functions c..c + m − 1, consecutive, hence totally positive, with the
/// data centred in their supports) carries the diagonal; the entries of the other stored
/// functions wrap into at most p corner columns J, A = B + U·S_Jᵀ with U = those columns
/// and S_J the selector of J. Woodbury: B Y = R, B Z = U, then
/// X = Y − Z (I + Z_J)⁻¹ Y_J. Returns an error where a factor is singular or the data do
/// not sit one per span; the caller then falls back to dense LU.
pub(super) fn solve_closed_band(
    knots: &[f64],
    degree: usize,
    params: &[f64],
    b: &DMatrix<f64>,
) -> Result<DMatrix<f64>, FitError> {
    let (m, p) = (params.len(), degree);
    let system = FitSystem::ClosedInterpolation;
    let c = (p / 2) as isize;
    let mut start = Vec::with_capacity(m);
    let mut rows = Vec::with_capacity(m);
    // Corner entries (row, column, value) of A − B.
    let mut corner: Vec<(usize, usize, f64)> = Vec::new();
    for (i, &t) in params.iter().enumerate() {
        let span = find_span(knots, p, m + p, t);
        let s = (span - p) as isize - c;
        let first = s.max(0) as usize;
        let mut row = vec![0.0; p + 1];
        for (j, v) in basis_funs(knots, p, span, t).into_iter().enumerate() {
            let col = s + j as isize;
            if col >= 0 && (col as usize) < m {
                row[col as usize - first] = v;
            } else if v != 0.0 {
                corner.push((i, col.rem_euclid(m as isize) as usize, v));
            }
        }
        start.push(first);
        rows.push(row);
    }
    let mut cols: Vec<usize> = corner.iter().map(|e| e.1).collect();
    cols.sort_unstable();
    cols.dedup();
    let k = cols.len();
    let dim = b.ncols();
    // Right-hand sides [R | U].
    let mut rhs = DMatrix::zeros(m, dim + k);
    rhs.columns_mut(0, dim).copy_from(b);
    for &(i, col, v) in &corner {
        if let Ok(jj) = cols.binary_search(&col) {
            rhs[(i, dim + jj)] += v;
        }
    }
    let yz = band_solve(&start, rows, &rhs, system)?;
    let mut x = yz.columns(0, dim).into_owned();
    if k > 0 {
        let z = yz.columns(dim, k);
        let cap = DMatrix::from_fn(k, k, |a, bb| {
            z[(cols[a], bb)] + if a == bb { 1.0 } else { 0.0 }
        });
        let yj = DMatrix::from_fn(k, dim, |a, d| x[(cols[a], d)]);
        let wv = solve_lu(cap, &yj, system)?;
        x -= z * wv;
    }
    // Undo the column shift: column col holds control value (col + c) mod m.
    let mut out = DMatrix::zeros(m, dim);
    for col in 0..m {
        let j = (col as isize + c).rem_euclid(m as isize) as usize;
        out.row_mut(j).copy_from(&x.row(col));
    }
    Ok(out)
}

/// Solve the square system A X = B by LU with partial pivoting.
pub(super) fn solve_lu(
    a: DMatrix<f64>,
    b: &DMatrix<f64>,
    system: FitSystem,
) -> Result<DMatrix<f64>, FitError> {
    let size = a.nrows();
    let lu = LU::new(a);
    let ratio = pivot_ratio(lu.u().diagonal().iter().copied());
    let singular = FitError::Singular {
        system,
        size,
        ratio,
    };
    if ratio.is_nan() || ratio < SINGULAR_PIVOT_RATIO {
        return Err(singular);
    }
    lu.solve(b).ok_or(singular)
}

/// A stored basis function's control value in a least-squares fit: unknown number `i`, or
/// fixed (an interpolated end point).
pub(super) enum Slot<P> {
    Unknown(usize),
    Fixed(P),
}

/// Solve min Σ_i ‖Q_i − Σ_k N_k(t_i) P_k‖² over the unknown control values (`slot` maps a
/// stored basis index to its unknown or fixed value) by Cholesky of the normal equations
/// AᵀA X = AᵀR (P&T eq. 9.66), R_i = Q_i − Σ_fixed N_k(t_i) P_k (eq. 9.63). AᵀA and AᵀR are
/// accumulated row by row from the p + 1 non-zero basis functions, so A is never formed:
/// O(m·p² + n³) time, O(n²) memory.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_normal<P: Components>(
    knots: &[f64],
    degree: usize,
    n_stored: usize,
    params: &[f64],
    points: &[P],
    n_unknown: usize,
    slot: impl Fn(usize) -> Slot<P>,
    system: FitSystem,
) -> Result<DMatrix<f64>, FitError> {
    let mut ata = DMatrix::zeros(n_unknown, n_unknown);
    let mut atr = DMatrix::zeros(n_unknown, P::DIM);
    let mut unknown: Vec<(usize, f64)> = Vec::with_capacity(degree + 1);
    for (&t, &q) in params.iter().zip(points) {
        let span = find_span(knots, degree, n_stored, t);
        let mut r = q;
        unknown.clear();
        for (j, v) in basis_funs(knots, degree, span, t).into_iter().enumerate() {
            match slot(span - degree + j) {
                Slot::Unknown(i) => unknown.push((i, v)),
                Slot::Fixed(value) => r = r - value * v,
            }
        }
        for &(i, vi) in &unknown {
            for &(k, vk) in &unknown {
                ata[(i, k)] += vi * vk;
            }
            for d in 0..P::DIM {
                atr[(i, d)] += vi * r.get(d);
            }
        }
    }
    let singular = |ratio| FitError::Singular {
        system,
        size: n_unknown,
        ratio,
    };
    let chol = Cholesky::new(ata).ok_or(singular(0.0))?;
    // L_ii² are the pivots of AᵀA; the L_ii compare like the pivots of A.
    let ratio = pivot_ratio(chol.l_dirty().diagonal().iter().copied());
    if ratio.is_nan() || ratio < SINGULAR_PIVOT_RATIO {
        return Err(singular(ratio));
    }
    Ok(chol.solve(&atr))
}
