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

pub mod cyclographic;
pub mod detect;
pub mod eliminate;
pub mod mph;
pub mod outline;
pub mod poly;
pub mod re_curve;
pub mod skin;
pub mod tangents;

pub use re_curve::{Branch, Frame, Interp, ReCurve};
pub use skin::{ReSkin, Segment};
pub use tangents::Touch;

use thiserror::Error;

/// Errors of RE/MPH skin construction; each names the circle or the circle pair.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ReError {
    #[error("an RE skin needs at least 2 circles, got {0}")]
    TooFewCircles(usize),
    #[error("{touches} touching-point entries for {circles} circles")]
    TouchCount { touches: usize, circles: usize },
    #[error("circle {index}: centre and radius must be finite and the radius positive")]
    BadCircle { index: usize },
    #[error("index {index} out of range")]
    BadIndex { index: usize },
    #[error("circle {index}: touching point is {off} away from the circle")]
    TouchOffCircle { index: usize, off: f64 },
    #[error("circle {index}: the left and right touching points coincide")]
    TouchPointsCoincide { index: usize },
    #[error("circle {index}: free parameter u = {u} is not in (0, π)")]
    BadU { index: usize, u: f64 },
    #[error("circle {index}: touching point is fixed on both sides (no free u)")]
    NotFlexible { index: usize },
    #[error("circles {i} and {j} are concentric: no radical line for the tangent length")]
    Concentric { i: usize, j: usize },
    #[error("circles {i} and {j}: a touching point lies on the radical line (zero tangent)")]
    ZeroTangent { i: usize, j: usize },
    #[error("circles {i} and {j}: degenerate Hermite data (singular PH interpolant or t·v = 0)")]
    Degenerate { i: usize, j: usize },
}
