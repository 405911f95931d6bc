//! Knot vectors: construction (clamped, periodic) and validation.

use super::SplineError;

/// Clamped knots with uniform interior spacing on [0, 1] for `n_ctrl` control values.
pub fn clamped_uniform(degree: usize, n_ctrl: usize) -> Vec<f64> {
    let p = degree;
    let spans = n_ctrl - p;
    let mut k = vec![0.0; p + 1];
    for i in 1..spans {
        k.push(i as f64 / spans as f64);
    }
    k.extend(std::iter::repeat_n(1.0, p + 1));
    k
}

/// Clamped knots whose interior knots average the parameters `params` (P&T eq. 9.8), the
/// standard choice for interpolation and least squares through data at `params`.
pub fn clamped_averaged(degree: usize, n_ctrl: usize, params: &[f64]) -> Vec<f64> {
    let p = degree;
    let (a, b) = (params[0], params[params.len() - 1]);
    let mut k = vec![a; p + 1];
    let m = params.len();
    let n = n_ctrl;
    if n == m {
        // Interpolation: u_{j+p} = (1/p) Σ_{i=j}^{j+p−1} t_i, j = 1..n−p−1.
        for j in 1..(n - p) {
            let s: f64 = params[j..j + p].iter().sum();
            k.push(s / p as f64);
        }
    } else {
        // Approximation (P&T eq. 9.68–9.69): d = m / (n − p), u_{p+j} = (1−α) t_{i−1} + α t_i.
        let d = m as f64 / (n - p) as f64;
        for j in 1..(n - p) {
            let jd = j as f64 * d;
            let i = (jd.floor() as usize).min(m - 1).max(1);
            let alpha = jd - i as f64;
            k.push((1.0 - alpha) * params[i - 1] + alpha * params[i]);
        }
    }
    k.extend(std::iter::repeat_n(b, p + 1));
    k
}

/// Periodic knots from the n + 1 breakpoints u_0 < … < u_n of one period (n = number of
/// distinct control values): the spacing repeats with period u_n − u_0, and the result has
/// n + 2p + 1 knots, with domain [u_0, u_n].
pub fn periodic_from_breaks(degree: usize, breaks: &[f64]) -> Vec<f64> {
    let p = degree as isize;
    let n = (breaks.len() - 1) as isize;
    let period = breaks[n as usize] - breaks[0];
    // k_{p+i} = u_{i mod n} + ⌊i/n⌋·period for every integer i.
    (-p..=n + p)
        .map(|i| breaks[i.rem_euclid(n) as usize] + i.div_euclid(n) as f64 * period)
        .collect()
}

/// Check a knot vector for `n_ctrl` control values of degree `degree`.
pub fn validate(knots: &[f64], degree: usize, n_ctrl: usize) -> Result<(), SplineError> {
    if degree < 1 {
        return Err(SplineError::Degree(degree));
    }
    if n_ctrl < degree + 1 {
        return Err(SplineError::TooFewControl {
            degree,
            need: degree + 1,
            got: n_ctrl,
        });
    }
    let expected = n_ctrl + degree + 1;
    if knots.len() != expected {
        return Err(SplineError::KnotCount {
            got: knots.len(),
            expected,
        });
    }
    for (i, &v) in knots.iter().enumerate() {
        if !v.is_finite() {
            return Err(SplineError::KnotNotFinite { index: i, value: v });
        }
    }
    for i in 1..knots.len() {
        if knots[i] < knots[i - 1] {
            return Err(SplineError::KnotDecreasing {
                index: i,
                prev: knots[i - 1],
                next: knots[i],
            });
        }
    }
    let mut i = 0;
    while i < knots.len() {
        let mut j = i;
        while j + 1 < knots.len() && knots[j + 1] == knots[i] {
            j += 1;
        }
        let mult = j - i + 1;
        if mult > degree + 1 {
            return Err(SplineError::KnotMultiplicity {
                value: knots[i],
                mult,
                max: degree + 1,
            });
        }
        i = j + 1;
    }
    let (lo, hi) = (knots[degree], knots[n_ctrl]);
    if hi <= lo {
        return Err(SplineError::EmptyDomain { lo, hi });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamped_uniform_shape() {
        assert_eq!(
            clamped_uniform(3, 5),
            vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0]
        );
        assert!(validate(&clamped_uniform(3, 5), 3, 5).is_ok());
    }

    #[test]
    fn periodic_knots_repeat_spacing() {
        let breaks = [0.0, 1.0, 3.0, 4.0, 6.0];
        for p in 1..=6 {
            let k = periodic_from_breaks(p, &breaks);
            assert_eq!(k.len(), 4 + 2 * p + 1);
            assert!(validate(&k, p, 4 + p).is_ok(), "p={p}: {k:?}");
            let period = 6.0;
            for i in 0..k.len() - 4 {
                assert!(((k[i + 4] - k[i]) - period).abs() < 1e-12, "p={p} {k:?}");
            }
            assert_eq!(k[p], 0.0);
            assert_eq!(k[4 + p], 6.0);
        }
    }
}
