//! Parameters of data points (uniform, chord length, centripetal; P&T eq. 9.4–9.6,
//! wu-2021 eq. 16) and the breakpoints of closed fits that follow them.

use super::{Components, FitError};

/// How data points are given parameters (P&T Sec. 9.2.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Parametrization {
    /// Equally spaced parameters.
    Uniform,
    /// Accumulated chord length t_i = t_{i−1} + ‖Q_i − Q_{i−1}‖ (wu-2021 eq. 16, P&T eq. 9.5).
    #[default]
    ChordLength,
    /// Accumulated square roots of the chord lengths (Lee's centripetal model, P&T eq. 9.6):
    /// follows sharp turns more tightly than chord length.
    Centripetal,
}

pub(super) fn check_finite<P: Components>(points: &[P]) -> Result<(), FitError> {
    for (index, q) in points.iter().enumerate() {
        if !(0..P::DIM).all(|k| q.get(k).is_finite()) {
            return Err(FitError::NotFinite { index });
        }
    }
    Ok(())
}

/// Parameters of the data points, normalised to [0, 1] (P&T eq. 9.4–9.6; chord length is
/// wu-2021 eq. 16). Open data gives m values t_0 = 0 < … < t_{m−1} = 1. Closed data gives
/// m + 1 values: the last, t_m = 1, belongs to the closing chord Q_{m−1} → Q_0 (the caller
/// does not repeat Q_0), so the period is [0, 1].
///
/// Errors: fewer than 2 points, non-finite points, and for chord length and centripetal a
/// zero chord between consecutive points (cyclically for closed data), naming the pair.
pub fn parameters<P: Components>(
    points: &[P],
    kind: Parametrization,
    closed: bool,
) -> Result<Vec<f64>, FitError> {
    let m = points.len();
    if m < 2 {
        return Err(FitError::TooFewPoints { need: 2, got: m });
    }
    check_finite(points)?;
    let chords = if closed { m } else { m - 1 };
    let mut acc = vec![0.0];
    let mut sum = 0.0;
    for i in 0..chords {
        let next = (i + 1) % m;
        let step = match kind {
            Parametrization::Uniform => 1.0,
            Parametrization::ChordLength | Parametrization::Centripetal => {
                let d = (points[next] - points[i]).norm();
                if d == 0.0 {
                    return Err(FitError::ZeroChord { index: i, next });
                }
                if kind == Parametrization::Centripetal {
                    d.sqrt()
                } else {
                    d
                }
            }
        };
        sum += step;
        acc.push(sum);
    }
    for t in acc.iter_mut() {
        *t /= sum;
    }
    // Exact end value, whatever the rounding of the sum.
    if let Some(last) = acc.last_mut() {
        *last = 1.0;
    }
    Ok(acc)
}

/// Breakpoints u_0 < … < u_n of one period of a closed fit with n = `n_ctrl` distinct control
/// values through data at `params` (m + 1 values, the last closing the period; see
/// [`parameters`]). The periodic analogue of P&T eq. 9.68–9.69: with the data parameters
/// extended periodically (t_{i+m} = t_i + period) and linearly interpolated in the index,
/// u_j = T(j·m/n − δ), where δ = 0 for odd degree (breakpoints at data) and δ = ½ for even
/// degree (data at span middles; even-degree periodic interpolation at the knots is
/// singular for even m, e.g. p = 2 on uniform knots). For n = m and odd p the breaks are
/// the data parameters themselves, as in wu-2021 eq. 16; for even p the domain then starts
/// half a chord before t_0 (C is periodic, so it still passes through Q_i at t_i).
pub fn closed_breaks(params: &[f64], n_ctrl: usize, degree: usize) -> Vec<f64> {
    let m = params.len().saturating_sub(1);
    if m == 0 || n_ctrl == 0 {
        return params.to_vec();
    }
    let period = params[m] - params[0];
    let ext = |k: isize| -> f64 {
        params[k.rem_euclid(m as isize) as usize] + k.div_euclid(m as isize) as f64 * period
    };
    let delta = if degree.is_multiple_of(2) { 0.5 } else { 0.0 };
    let mut breaks: Vec<f64> = (0..n_ctrl)
        .map(|j| {
            let s = (j * m) as f64 / n_ctrl as f64 - delta;
            let i = s.floor();
            let a = s - i;
            let i = i as isize;
            if a == 0.0 {
                ext(i)
            } else {
                (1.0 - a) * ext(i) + a * ext(i + 1)
            }
        })
        .collect();
    breaks.push(breaks[0] + period);
    breaks
}

pub(super) fn check_params(params: &[f64], expected: usize) -> Result<(), FitError> {
    if params.len() != expected {
        return Err(FitError::ParameterCount {
            expected,
            got: params.len(),
        });
    }
    for (index, &value) in params.iter().enumerate() {
        let decreasing = index > 0 && value < params[index - 1];
        if !value.is_finite() || decreasing {
            return Err(FitError::Parameter { index, value });
        }
    }
    if params.len() >= 2 && params[params.len() - 1] <= params[0] {
        let index = params.len() - 1;
        return Err(FitError::Parameter {
            index,
            value: params[index],
        });
    }
    Ok(())
}
