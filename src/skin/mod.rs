//! Skinning: intersection-free outlines from circle sequences and disk B-splines.
pub mod mat_offset;
pub mod re;
