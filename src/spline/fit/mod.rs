//! Interpolation and least-squares fitting of B-splines (Piegl & Tiller, *The NURBS Book*,
//! Sec. 9.2.1 and 9.4.1; wu-2021 "Interpolation" and "Approximation", eq. 16).
//!
//! Data points Q_0..Q_{m−1} get parameters t_i ([`parameters`]: uniform, chord length as in
//! wu-2021 eq. 16, or centripetal), normalised to [0, 1]. The knots follow from the
//! parameters: open curves use clamped averaged knots (P&T eq. 9.8 for interpolation,
//! eq. 9.68–9.69 for least squares), closed curves use periodic knots whose breakpoints
//! follow the data ([`closed_breaks`]). The collocation matrix A_{ij} = N_{j,p}(t_i) is built
//! once and every component of the control values is solved with the same factorisation, so
//! one routine serves `f64`, `DVec2` and `DVec3` ((x, y, r) disks) data.
//!
//! Complexity: interpolation systems are banded. Open ones (bandwidth p, totally positive)
//! are solved without pivoting in O(m·p²); closed ones are cyclic (the wrapped basis
//! functions put ≤ p columns of entries in the corners) and are solved as the band part
//! plus a Woodbury correction of rank ≤ p, O(m·p² + p³), falling back to dense LU (O(m³))
//! only when that fails.
//! Least squares accumulates the normal equations from the non-zero basis functions in
//! O(m·p²) and factors them (dense, n × n) by Cholesky in O(n³) for n control values.
//!
//! The module is split by concern: `params` gives data points their parameters and closed
//! fits their breakpoints, `solve` holds the linear solvers (band, cyclic band with a
//! Woodbury correction, dense LU, normal equations), and this file the fitting API.

mod params;
mod solve;

pub use params::{Parametrization, closed_breaks, parameters};

use super::knots;
use super::{BSpline, SplineError, Vector};
use glam::{DVec2, DVec3};
use params::{check_finite, check_params};
use solve::{
    Slot, collocation, rhs, solve_closed_band, solve_lu, solve_normal, solve_open_band, to_points,
};

/// Relative pivot size below which a factorised system is reported as singular: the
/// smallest |pivot| of the LU (or Cholesky) factor divided by the largest. B-spline
/// collocation matrices whose parameters satisfy the Schoenberg–Whitney condition are well
/// conditioned (pivots of order 2^−p), so a ratio near machine precision only appears when
/// two rows coincide (repeated parameters) or a basis function sees no data.
pub const SINGULAR_PIVOT_RATIO: f64 = 1e-12;

/// Control values with numbered real components, so each component can be fitted
/// separately with one factorised system.
pub trait Components: Vector {
    /// Number of components.
    const DIM: usize;
    /// Component `i` (`i < DIM`; components beyond `DIM` read as 0).
    fn get(&self, i: usize) -> f64;
    /// Set component `i` (`i < DIM`; indices beyond `DIM` are ignored).
    fn set(&mut self, i: usize, v: f64);
}

impl Components for f64 {
    const DIM: usize = 1;
    fn get(&self, i: usize) -> f64 {
        if i == 0 { *self } else { 0.0 }
    }
    fn set(&mut self, i: usize, v: f64) {
        if i == 0 {
            *self = v;
        }
    }
}

impl Components for DVec2 {
    const DIM: usize = 2;
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => self.x,
            1 => self.y,
            _ => 0.0,
        }
    }
    fn set(&mut self, i: usize, v: f64) {
        match i {
            0 => self.x = v,
            1 => self.y = v,
            _ => {}
        }
    }
}

impl Components for DVec3 {
    const DIM: usize = 3;
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => self.x,
            1 => self.y,
            2 => self.z,
            _ => 0.0,
        }
    }
    fn set(&mut self, i: usize, v: f64) {
        match i {
            0 => self.x = v,
            1 => self.y = v,
            2 => self.z = v,
            _ => {}
        }
    }
}

/// Which system a fit had to solve; named in [`FitError::Singular`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitSystem {
    /// Interpolation of open data (clamped knots).
    OpenInterpolation,
    /// Interpolation of closed data (periodic knots).
    ClosedInterpolation,
    /// Least squares on open data (ends fixed).
    OpenLeastSquares,
    /// Least squares on closed data (periodic).
    ClosedLeastSquares,
}

impl std::fmt::Display for FitSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FitSystem::OpenInterpolation => "open interpolation",
            FitSystem::ClosedInterpolation => "closed interpolation",
            FitSystem::OpenLeastSquares => "open least-squares",
            FitSystem::ClosedLeastSquares => "closed least-squares",
        })
    }
}

/// Errors of B-spline fitting.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The degree is 0.
    #[error("degree must be at least 1, got {0}")]
    Degree(usize),
    /// Too few data points for the degree.
    #[error("fitting needs at least {need} points, got {got}")]
    TooFewPoints {
        /// How many are needed.
        need: usize,
        /// How many were given.
        got: usize,
    },
    /// The number of control values is outside `min..=max`.
    #[error("{n_ctrl} control values requested, allowed {min}..={max}")]
    ControlCount {
        /// Requested number of control values.
        n_ctrl: usize,
        /// Least allowed (degree + 1).
        min: usize,
        /// Most allowed (the number of points).
        max: usize,
    },
    /// A data point has a non-finite component.
    #[error("point {index} is not finite")]
    NotFinite {
        /// Index of the offending point or parameter.
        index: usize,
    },
    /// Two consecutive points coincide, so chord-length parameters are undefined.
    #[error("points {index} and {next} coincide: zero chord length")]
    ZeroChord {
        /// Index of the offending point or parameter.
        index: usize,
        /// Index of the point that coincides with it.
        next: usize,
    },
    /// A given parameter is not finite or decreases.
    #[error("parameter {index} ({value}) is not finite or decreases")]
    Parameter {
        /// Index of the offending point or parameter.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// The number of given parameters is wrong.
    #[error("expected {expected} parameters, got {got}")]
    ParameterCount {
        /// How many were expected.
        expected: usize,
        /// How many were given.
        got: usize,
    },
    /// The fitting system is singular (pivot ratio below [`SINGULAR_PIVOT_RATIO`]).
    #[error("singular {system} system ({size}×{size}): pivot ratio {ratio:e}")]
    Singular {
        /// Which system.
        system: FitSystem,
        /// Its order.
        size: usize,
        /// Smallest over largest pivot magnitude.
        ratio: f64,
    },
    /// The fitted curve could not be built.
    #[error(transparent)]
    Spline(#[from] SplineError),
}

fn check_degree(degree: usize) -> Result<(), FitError> {
    if degree < 1 {
        Err(FitError::Degree(degree))
    } else {
        Ok(())
    }
}

/// The entry checks of every fit, in this order: the degree, at least p + 1 points, the
/// control count p + 1 ≤ `n_ctrl` ≤ m (least squares only), finite points, and the
/// parameters (m values open, m + 1 closed: the last closes the period). Returns m.
fn check_input<P: Components>(
    points: &[P],
    params: &[f64],
    degree: usize,
    closed: bool,
    n_ctrl: Option<usize>,
) -> Result<usize, FitError> {
    check_degree(degree)?;
    let m = points.len();
    if m < degree + 1 {
        return Err(FitError::TooFewPoints {
            need: degree + 1,
            got: m,
        });
    }
    if let Some(n_ctrl) = n_ctrl
        && (n_ctrl < degree + 1 || n_ctrl > m)
    {
        return Err(FitError::ControlCount {
            n_ctrl,
            min: degree + 1,
            max: m,
        });
    }
    check_finite(points)?;
    check_params(params, if closed { m + 1 } else { m })?;
    Ok(m)
}

/// Interpolate the data with a degree-`degree` B-spline, parameters chosen by `kind`
/// (see [`interpolate_with_params`]). Used by the tests only.
#[cfg(test)]
pub fn interpolate<P: Components>(
    points: &[P],
    degree: usize,
    closed: bool,
    kind: Parametrization,
) -> Result<BSpline<P>, FitError> {
    check_degree(degree)?;
    let params = parameters(points, kind, closed)?;
    interpolate_with_params(points, &params, degree, closed)
}

/// The B-spline C of degree p with C(t_i) = Q_i for every data point (P&T Sec. 9.2.1,
/// wu-2021 "Interpolation").
///
/// Open: `params` has one value per point (non-decreasing, first < last); m control values
/// on clamped knots averaging the parameters (P&T eq. 9.8), so C(t_0) = Q_0 and
/// C(t_{m−1}) = Q_{m−1}. Closed: `params` has m + 1 values (the last closes the period);
/// m distinct control values on the periodic knots of [`closed_breaks`]; the curve is
/// C^{p−1} everywhere, the seam included. Both systems are solved as band systems in
/// O(m·p²) (the closed one with a rank-≤p Woodbury correction; see the module docs).
///
/// Needs m ≥ p + 1 points. Repeated parameters make the system singular
/// ([`FitError::Singular`]).
pub fn interpolate_with_params<P: Components>(
    points: &[P],
    params: &[f64],
    degree: usize,
    closed: bool,
) -> Result<BSpline<P>, FitError> {
    let m = check_input(points, params, degree, closed, None)?;
    let b = rhs(points);
    if closed {
        let breaks = closed_breaks(params, m, degree);
        let knots = knots::periodic_from_breaks(degree, &breaks);
        knots::validate(&knots, degree, m + degree)?;
        let x = match solve_closed_band(&knots, degree, &params[..m], &b) {
            Ok(x) => x,
            Err(_) => {
                let a = collocation(&knots, degree, m + degree, m, &params[..m]);
                solve_lu(a, &b, FitSystem::ClosedInterpolation)?
            }
        };
        Ok(BSpline::closed_with_breaks(degree, to_points(&x), &breaks)?)
    } else {
        let knots = knots::clamped_averaged(degree, m, params);
        knots::validate(&knots, degree, m)?;
        let x = solve_open_band(&knots, degree, params, &b)?;
        Ok(BSpline::new(degree, knots, to_points(&x))?)
    }
}

/// Least-squares fit with `n_ctrl` control values, parameters chosen by `kind`
/// (see [`least_squares_with_params`]). Used by the tests only.
#[cfg(test)]
pub fn least_squares<P: Components>(
    points: &[P],
    n_ctrl: usize,
    degree: usize,
    closed: bool,
    kind: Parametrization,
) -> Result<BSpline<P>, FitError> {
    check_degree(degree)?;
    let params = parameters(points, kind, closed)?;
    least_squares_with_params(points, &params, n_ctrl, degree, closed)
}

/// The B-spline C of degree p with `n_ctrl` (distinct) control values minimising
/// Σ ‖Q_i − C(t_i)‖² (P&T Sec. 9.4.1, eq. 9.63–9.67; wu-2021 "Approximation").
///
/// Open: the end points are interpolated exactly (P_0 = Q_0, P_{n−1} = Q_{m−1}) and the
/// interior control values solve the normal equations on clamped knots placed by
/// P&T eq. 9.68–9.69; `params` has m values. Closed: periodic, no constraint, knots from
/// [`closed_breaks`]; `params` has m + 1 values. With n_ctrl = m both give the interpolant.
///
/// Needs p + 1 ≤ n_ctrl ≤ m. Cost O(m·p² + n³) (normal equations, dense Cholesky).
pub fn least_squares_with_params<P: Components>(
    points: &[P],
    params: &[f64],
    n_ctrl: usize,
    degree: usize,
    closed: bool,
) -> Result<BSpline<P>, FitError> {
    let m = check_input(points, params, degree, closed, Some(n_ctrl))?;
    let n = n_ctrl;
    if closed {
        let breaks = closed_breaks(params, n, degree);
        let knots = knots::periodic_from_breaks(degree, &breaks);
        knots::validate(&knots, degree, n + degree)?;
        let x = solve_normal(
            &knots,
            degree,
            n + degree,
            &params[..m],
            points,
            n,
            |k| Slot::Unknown(k % n),
            FitSystem::ClosedLeastSquares,
        )?;
        return Ok(BSpline::closed_with_breaks(degree, to_points(&x), &breaks)?);
    }
    let knots = knots::clamped_averaged(degree, n, params);
    knots::validate(&knots, degree, n)?;
    let (q0, qm) = (points[0], points[m - 1]);
    let mut ctrl = vec![q0; n];
    ctrl[n - 1] = qm;
    if n > 2 {
        // P&T Sec. 9.4.1: P_0 = Q_0 and P_{n−1} = Q_{m−1} are fixed, the interior control
        // values P_1..P_{n−2} fit the interior points Q_1..Q_{m−2}.
        let slot = |k: usize| match k {
            0 => Slot::Fixed(q0),
            k if k == n - 1 => Slot::Fixed(qm),
            k => Slot::Unknown(k - 1),
        };
        let x = solve_normal(
            &knots,
            degree,
            n,
            &params[1..m - 1],
            &points[1..m - 1],
            n - 2,
            slot,
            FitSystem::OpenLeastSquares,
        )?;
        for (c, v) in ctrl[1..n - 1].iter_mut().zip(to_points::<P>(&x)) {
            *c = v;
        }
    }
    Ok(BSpline::new(degree, knots, ctrl)?)
}

#[cfg(test)]
mod tests;
