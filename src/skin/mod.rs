//! Skinning: intersection-free outlines from circle sequences and disk B-splines.

pub mod admissible;
pub mod bezier;
pub(crate) mod bits_hash;
pub mod coverage;
pub mod dbsc_skin;
pub mod hausdorff;
pub mod mat_offset;
pub mod outline;
pub mod re;
pub mod region_mesh;
pub mod touching;

pub use admissible::{AdmissibilityOptions, Condition, SkinError, check_admissible};
pub use bezier::{SkinOptions, Skins, bezier_skins, skin_circles, skin_segment};
pub use outline::{Outline, outline_circles};
pub use touching::{Apollonius, TouchingPoints, touching_points, triplet_touching};
