//! Skinning: intersection-free outlines from circle sequences and disk B-splines.
//!
//! The entry points: [`skin_dbsc`] skins a disk B-spline within ε (kruppa-2023 Sec. 4) and
//! reports the certified error per segment ([`DbscSkin`]); [`skin_circles`] and
//! [`outline_circles`] skin an admissible sequence of circles ([`check_admissible`]). The
//! rational-envelope route ([`ReSkin`], [`Interp`]) and its offsets are what the
//! toolpath stage uses for the `re`/`mph` outline methods.

pub(crate) mod admissible;
pub(crate) mod bezier;
pub(crate) mod bits_hash;
pub(crate) mod box_grid;
pub(crate) mod coverage;
pub(crate) mod dbsc_skin;
pub(crate) mod hausdorff;
pub(crate) mod mat_offset;
pub(crate) mod outline;
pub(crate) mod re;
pub(crate) mod touching;

pub use admissible::{AdmissibilityOptions, Condition, SkinError, check_admissible};
pub use bezier::{SkinOptions, Skins, bezier_skins, skin_circles, skin_segment};
pub use coverage::{Uncovered, uncovered};
pub use dbsc_skin::{
    CircleUse, DEFAULT_INTERSECT_TOL, DEFAULT_LOOP_TOL, DEFAULT_MAX_WORK, DbscSkin, DbscSkinError,
    DbscSkinOptions, Phase, ReportBounds, SegmentReport, check_knot_circles, skin_dbsc,
};
pub use hausdorff::{HausdorffBounds, HausdorffError, hausdorff_skin_envelope, hausdorff_within};
pub use mat_offset::{MatOffsetError, region_distance};
pub use outline::{Outline, outline_circles};
pub use re::outline::{ReOutline, ReOutlineError};
pub use re::{Branch, Interp, ReError, ReSkin, Touch};
pub use touching::{Apollonius, TouchingPoints, touching_points, triplet_touching};
