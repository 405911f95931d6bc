//! B-splines of any degree p ≥ 1 on clamped, unclamped and periodic (closed) knot vectors.
//!
//! A [`BSpline`] is generic over its control values ([`Vector`]: `f64` radii, `DVec2`
//! points, `DVec3` disks as (x, y, r) — the cyclographic view of a disk B-spline), so one
//! implementation serves the centre, the radius and every attribute channel of a
//! disk B-spline curve (wu-2021 eq. 1–2).
//!
//! Conventions (Piegl & Tiller, *The NURBS Book*): n + 1 control values P_0..P_n and m + 1
//! knots u_0..u_m with m = n + p + 1; the curve C(t) = Σ N_{i,p}(t) P_i lives on the domain
//! [u_p, u_{n+1}]. Closed curves are stored unclamped with the first p control values
//! repeated at the end and uniform knot spacing around the wrap, so C is C^{p−1} across the
//! seam and evaluation wraps t into the domain.
//!
//! Complexity: evaluation O(p²) per point (de Boor), knot insertion O(n + p).

pub(crate) mod basis;
pub(crate) mod curve;
pub(crate) mod fit;
pub(crate) mod knots;

pub use basis::ders_basis_funs;
#[cfg(test)]
pub use basis::find_span;
pub use curve::BSpline;

use glam::{DVec2, DVec3};
use std::ops::{Add, Mul, Sub};

/// Control values a B-spline can blend: a real vector space over f64.
pub trait Vector:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self> + std::fmt::Debug
{
    /// The zero vector.
    const ZERO: Self;
    /// Euclidean norm, for tolerances and tests.
    fn norm(self) -> f64;
}

impl Vector for f64 {
    const ZERO: Self = 0.0;
    fn norm(self) -> f64 {
        self.abs()
    }
}

impl Vector for DVec2 {
    const ZERO: Self = DVec2::ZERO;
    fn norm(self) -> f64 {
        self.length()
    }
}

impl Vector for DVec3 {
    const ZERO: Self = DVec3::ZERO;
    fn norm(self) -> f64 {
        self.length()
    }
}

/// Errors of B-spline construction and fitting.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SplineError {
    /// The degree is 0.
    #[error("degree must be at least 1, got {0}")]
    Degree(usize),
    /// Fewer than degree + 1 control values.
    #[error("degree {degree} needs at least {need} control values, got {got}")]
    TooFewControl {
        /// The degree p.
        degree: usize,
        /// Control values needed (p + 1).
        need: usize,
        /// Control values given.
        got: usize,
    },
    /// The knot count is not n + p + 1.
    #[error("knot vector has {got} knots, expected {expected} (control values + degree + 1)")]
    KnotCount {
        /// How many were given.
        got: usize,
        /// How many were expected.
        expected: usize,
    },
    /// The knot vector decreases.
    #[error("knot vector decreases at index {index} ({prev} > {next})")]
    KnotDecreasing {
        /// Index of the knot.
        index: usize,
        /// The knot before it.
        prev: f64,
        /// The knot after it, smaller than `prev`.
        next: f64,
    },
    /// A knot is NaN or infinite.
    #[error("knot {index} is not finite ({value})")]
    KnotNotFinite {
        /// Index of the knot.
        index: usize,
        /// The knot value.
        value: f64,
    },
    /// The domain [u_p, u_{n+1}] is empty.
    #[error("knot vector has an empty domain [{lo}, {hi}]")]
    EmptyDomain {
        /// Lower end of the domain.
        lo: f64,
        /// Upper end of the domain.
        hi: f64,
    },
    /// A knot repeats more than p + 1 times.
    #[error("knot {value} has multiplicity {mult}, more than degree + 1 = {max}")]
    KnotMultiplicity {
        /// The knot value.
        value: f64,
        /// Its multiplicity.
        mult: usize,
        /// The largest multiplicity allowed (degree + 1).
        max: usize,
    },
    /// Evaluation outside the curve's domain.
    #[error("parameter {t} outside the domain [{lo}, {hi}]")]
    OutOfDomain {
        /// The parameter.
        t: f64,
        /// Lower end of the domain.
        lo: f64,
        /// Upper end of the domain.
        hi: f64,
    },
    /// Fitting failed (message of the fitting error).
    #[error("fitting: {0}")]
    Fit(String),
}
