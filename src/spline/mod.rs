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

pub mod basis;
pub mod curve;
pub mod fit;
pub mod knots;

pub use basis::{basis_funs, ders_basis_funs, find_span};
pub use curve::BSpline;
pub use knots::KnotKind;

use glam::{DVec2, DVec3};
use std::ops::{Add, Mul, Sub};

/// Control values a B-spline can blend: a real vector space over f64.
pub trait Vector:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self> + std::fmt::Debug
{
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
    #[error("degree must be at least 1, got {0}")]
    Degree(usize),
    #[error("degree {degree} needs at least {need} control values, got {got}")]
    TooFewControl {
        degree: usize,
        need: usize,
        got: usize,
    },
    #[error("knot vector has {got} knots, expected {expected} (control values + degree + 1)")]
    KnotCount { got: usize, expected: usize },
    #[error("knot vector decreases at index {index} ({prev} > {next})")]
    KnotDecreasing { index: usize, prev: f64, next: f64 },
    #[error("knot {index} is not finite ({value})")]
    KnotNotFinite { index: usize, value: f64 },
    #[error("knot vector has an empty domain [{lo}, {hi}]")]
    EmptyDomain { lo: f64, hi: f64 },
    #[error("knot {value} has multiplicity {mult}, more than degree + 1 = {max}")]
    KnotMultiplicity { value: f64, mult: usize, max: usize },
    #[error("parameter {t} outside the domain [{lo}, {hi}]")]
    OutOfDomain { t: f64, lo: f64, hi: f64 },
    #[error("fitting: {0}")]
    Fit(String),
}
