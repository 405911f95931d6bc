//! Skinning: intersection-free outlines from circle sequences and disk B-splines.
pub mod hausdorff;
