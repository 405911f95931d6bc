//! # skinpath
//!
//! Variable-width strokes to machine-ready toolpaths.
//!
//! A stroke is a disk B-spline curve ([`dbsc::DiskBSpline`]: a centre B-spline with a
//! B-spline radius) or a sequence of circles. Its raw boundary (the envelope) gets cusps and
//! self-intersecting loops at sharp bends; [`skin`] replaces it by skinning curves that touch
//! the same circles and never intersect. [`toolpath`] offsets and trims those outlines by the
//! tool radius or laser kerf and orders the cuts; [`emit`] writes G-code, laser SVG, DXF and
//! previews for a [`machine`] profile. [`sim`] reads G-code back (ours or any other tool's)
//! and checks it. Data flows one way:
//! `design → dbsc → skin → toolpath → emit`, with `sim` depending on `geom` and `machine` only.
//!
//! The library never panics on user data and never prints: every stage returns typed errors.

#![forbid(unsafe_code)]

pub mod dbsc;
pub mod design;
pub mod emit;
pub mod geom;
pub mod job;
pub mod machine;
pub mod sim;
pub mod skin;
pub mod spline;
pub mod toolpath;
pub mod units;
