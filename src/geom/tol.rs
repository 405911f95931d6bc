//! Tolerance defaults, in model units (mm unless the design says inch).
//!
//! Library routines never read these implicitly: each approximate function takes its
//! tolerance as an argument, and callers (the CLI, tests) pass these defaults or their own.

/// Default flattening and fitting accuracy for output geometry: 1 µm is far below the
/// repeatability of hobby and shop CNC machines (≈ 10 µm) and laser spot sizes (≈ 80 µm).
pub const FLATTEN: f64 = 1e-3;

/// Default accuracy of the skin approximation of a disk B-spline (kruppa-2023 Sec. 4, ε):
/// 10 µm, the resolution at which a routed or lasered edge stops showing the difference.
pub const SKIN_EPSILON: f64 = 1e-2;

/// Relative tolerance for equalities of lengths derived from input coordinates: a few
/// hundred ulps of the coordinate magnitude, so tests hold from 1e-3 to 1e4 mm.
pub const RELATIVE: f64 = 1e-9;

/// Absolute tolerance scaled to a coordinate magnitude: `RELATIVE · max(1, scale)`.
#[inline]
pub fn scaled(scale: f64) -> f64 {
    RELATIVE * scale.abs().max(1.0)
}

/// Relative accuracy of the arc lengths the toolpath stage measures for bookkeeping (a
/// cubic's length by adaptive quadrature: splitting paths at a length, lead and tab
/// positions, travel): 1e-9, far below every output tolerance, so the length is exact for
/// every purpose it serves.
pub const LENGTH_ACCURACY: f64 = 1e-9;

/// Flattening accuracy of a cubic whose flattening stands in for the curve in a distance
/// (the distance of a point to a cubic as the distance to its polyline): 1e-9 model
/// units, far below every output tolerance.
pub const DISTANCE_FLATTEN: f64 = 1e-9;
