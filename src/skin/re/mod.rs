//! Rational-envelope (RE) and Minkowski-PH (MPH) skins of circle sequences
//! (re-skinning-cnc: Kruppa 2021, FITEE; re-mph-skinning-flexible: Kruppa, Kunkli, Hoffmann
//! 2021, Mathematics).
//!
//! Circles map to cyclographic points pᵢ = (oᵢ, rᵢ) ∈ R^{2,1} ([`cyclographic`]); tangent
//! vectors are reconstructed from fixed touching points ([`tangents`]); between consecutive
//! circles an RE curve ȳ(t) = (x + f x′⊥, f‖x′‖) is built from a planar Hermite interpolant
//! x (cubic, or a PH quintic for MPH skins, [`mph`]) and a polynomial f ([`re_curve`]);
//! its envelopes are rational. [`detect`] finds envelope intersections (Theorem 1,
//! Corollary 1), [`eliminate`] removes them by tuning uᵢ or raising f to a quartic.

pub(crate) mod cyclographic;
pub(crate) mod detect;
pub(crate) mod eliminate;
pub(crate) mod mph;
pub(crate) mod outline;
pub(crate) mod poly;
pub(crate) mod re_curve;
pub(crate) mod skin;
pub(crate) mod tangents;

pub use re_curve::{Branch, Interp, ReCurve};
pub use skin::ReSkin;
pub use tangents::Touch;

use thiserror::Error;

/// Errors of RE/MPH skin construction; each names the circle or the circle pair.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum ReError {
    /// Fewer than 2 circles (the count is given).
    #[error("an RE skin needs at least 2 circles, got {0}")]
    TooFewCircles(usize),
    /// The number of [`Touch`] entries differs from the number of circles.
    #[error("{touches} touching-point entries for {circles} circles")]
    TouchCount {
        /// Number of touching-point entries.
        touches: usize,
        /// Number of circles.
        circles: usize,
    },
    /// A circle with a non-finite centre or radius, or a radius ≤ 0.
    #[error("circle {index}: centre and radius must be finite and the radius positive")]
    BadCircle {
        /// Index of the circle.
        index: usize,
    },
    /// A circle or segment index is out of range.
    #[error("index {index} out of range")]
    BadIndex {
        /// The index given.
        index: usize,
    },
    /// A given touching point is farther from its circle than the tolerance.
    #[error("circle {index}: touching point is {off} away from the circle")]
    TouchOffCircle {
        /// Index of the circle.
        index: usize,
        /// Distance of the point from the circle (model units).
        off: f64,
    },
    /// The two fixed touching points of a circle coincide, so they give no tangent.
    #[error("circle {index}: the left and right touching points coincide")]
    TouchPointsCoincide {
        /// Index of the circle.
        index: usize,
    },
    /// The free parameter u is outside (0, π).
    #[error("circle {index}: free parameter u = {u} is not in (0, π)")]
    BadU {
        /// Index of the circle.
        index: usize,
        /// The value given.
        u: f64,
    },
    /// u can be set only on a [`Touch::Flexible`] circle.
    #[error("circle {index}: touching point is fixed on both sides (no free u)")]
    NotFlexible {
        /// Index of the circle.
        index: usize,
    },
    /// Two circles of a pair are concentric: they have no radical line (re-skinning-cnc eq. 12).
    #[error("circles {i} and {j} are concentric: no radical line for the tangent length")]
    Concentric {
        /// First circle of the pair.
        i: usize,
        /// Second circle of the pair.
        j: usize,
    },
    /// A touching point of a pair lies on its radical line: the Hermite tangent has length 0.
    #[error("circles {i} and {j}: a touching point lies on the radical line (zero tangent)")]
    ZeroTangent {
        /// First circle of the pair.
        i: usize,
        /// Second circle of the pair.
        j: usize,
    },
    /// The Hermite data of a pair admit no RE curve.
    #[error("circles {i} and {j}: degenerate Hermite data (singular PH interpolant or t·v = 0)")]
    Degenerate {
        /// First circle of the pair.
        i: usize,
        /// Second circle of the pair.
        j: usize,
    },
}
