//! Disk B-spline curves (DBSC): a centre B-spline with a B-spline radius (wu-2021).
//!
//! ⟨D⟩(t) = Σ N_{i,p}(t) ⟨p_i; r_i⟩ with centre q(t) = Σ N_{i,p} p_i and radius
//! r(t) = Σ N_{i,p} r_i. The control disks are blended as points (x, y, r) of R^{2,1}, the
//! cyclographic space of re-skinning-cnc, so one B-spline of `DVec3` carries both.
//!
//! Side convention: the `+` envelope is on the left of the direction of travel (wu-2021
//! eq. 9, with q′⊥ the counter-clockwise rotation of q′), the `−` envelope on the right.

mod curve;
mod fit;
mod loops;

pub use crate::spline::fit::Parametrization;
/// The centre–radius B-spline a [`DiskBSpline`] wraps ([`DiskBSpline::curve`],
/// [`DiskBSpline::from_curve`]) and its error: the spline module itself is crate-private.
pub use crate::spline::{BSpline, SplineError, Vector};
pub(crate) use curve::envelope_of_jet;
pub use curve::{DiskBSpline, EnvelopePoint, Side};
pub use fit::{DbscFitError, disk_parameters};
pub(crate) use loops::{Bern, SpanPoly};
pub use loops::{EnvelopeLoop, LoopError, LoopReport, brent, find_loops, lemma1};

/// Errors of disk B-spline construction and evaluation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DbscError {
    /// A control disk's radius is zero or negative (a disk ⟨C; r⟩ has r ∈ R⁺, wu-2021 eq. 1).
    #[error("control disk {index}: radius {radius} must be positive")]
    Radius {
        /// Index of the disk in the slice given to the constructor.
        index: usize,
        /// The offending radius, in the disks' length unit.
        radius: f64,
    },
    /// A control disk's centre or radius is NaN or infinite.
    #[error("control disk {index}: coordinate is not finite")]
    NotFinite {
        /// Index of the disk in the slice given to the constructor.
        index: usize,
    },
    /// The knots or degree were rejected by the underlying B-spline constructor.
    #[error(transparent)]
    Spline(#[from] SplineError),
}

pub(crate) mod attributes;
pub(crate) mod caps;
pub(crate) mod extend;
pub(crate) mod flatten;
pub(crate) mod interior;
pub(crate) mod no_envelope;
pub(crate) mod spine;
pub(crate) mod tangent;
pub(crate) mod tessellate;
pub(crate) mod transform;
pub use attributes::{AttributeError, AttributedDbsc};
pub use caps::{CapError, End, cap, caps};
pub use extend::{ExtendError, Extension, RadiusFairing, extend_g2};
pub use flatten::{FlatOutline, flatten, flatten_disks, flatten_envelope, flatten_spine};
pub use interior::interior_point;
pub use no_envelope::no_envelope_intervals;
pub use spine::spine_cubics;
pub use tangent::{envelope_tangent, envelope_tangent_coeffs};
pub use tessellate::{Mesh, Resolution, TessellateError, tessellate};
pub use transform::TransformError;

/// Fixtures shared by the tests of the modules that use disk B-splines.
#[cfg(test)]
pub(crate) mod test_util {
    use super::DiskBSpline;
    use crate::geom::{Circle, DVec2};

    /// An open DBSC of degree `p` on clamped uniform knots through control disks (x, y, r).
    pub(crate) fn open(p: usize, d: &[(f64, f64, f64)]) -> DiskBSpline {
        let disks: Vec<Circle> = d
            .iter()
            .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
            .collect();
        DiskBSpline::open(p, &disks, None).unwrap()
    }

    /// Control disks of a gentle S stroke, 30 mm long, radii 1–2 mm: no envelope loops
    /// (degree 3: three spans).
    pub(crate) fn s_stroke() -> Vec<(f64, f64, f64)> {
        vec![
            (0.0, 0.0, 1.0),
            (6.0, 3.0, 1.5),
            (12.0, 0.0, 2.0),
            (18.0, -3.0, 1.5),
            (24.0, 0.0, 1.2),
            (30.0, 2.0, 1.0),
        ]
    }
}
