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
//!
//! ## Embedding
//!
//! A whole checked build is one [`Job`]: a [`Design`] (loaded with [`design::load`], or
//! made in code with [`design_of_strokes`]) and a machine [`Profile`] in; the program, the
//! placed [`Toolpath`], the checker's [`Report`] and a [`Summary`] out. A
//! G-code program that fails its check is refused ([`JobError::Unchecked`]) unless
//! [`JobOptions::write_unchecked`] is set. The library writes no files.
//!
//! ```
//! use skinpath::geom::DVec2;
//! use skinpath::{Circle, DiskBSpline, Job, JobOptions, builtin_profile, design_of_strokes};
//!
//! // A stroke made in code: a cubic disk B-spline through five control disks (mm).
//! let disks: Vec<Circle> = [(0.0, 0.0, 2.0), (15.0, 12.0, 3.0), (30.0, 0.0, 2.5),
//!                           (45.0, -10.0, 3.5), (60.0, 5.0, 2.0)]
//!     .iter()
//!     .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
//!     .collect();
//! let wave = DiskBSpline::open(3, &disks, None)?;
//! let design = design_of_strokes("wave", &[("wave", &wave)], &[])?;
//! let profile = builtin_profile("grbl-router")?;
//!
//! let out = Job::new(&design, &profile, JobOptions::default()).run()?;
//! let report = out.report.as_ref().ok_or("G-code is always checked")?;
//! assert_eq!(report.errors(), 0);
//! assert!(out.program.lines().any(|l| l.starts_with("G1") || l.starts_with("G2")));
//! let summary = out.summary(&profile);
//! assert_eq!(summary.operations.len(), 1);
//! assert!(summary.cut_length > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// The library's own dependencies only: dev-dependencies (criterion, proptest, …) are linked
// into test targets that do not all use them.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]
// A library reports through its return values; printing is the command line's business.
#![deny(clippy::print_stdout, clippy::print_stderr)]

// `missing_docs` holds in every module.
pub mod dbsc;
pub mod design;
pub mod emit;
pub mod geom;
pub mod job;
pub mod machine;
mod par;
pub mod sim;
pub mod skin;
pub mod spline;
pub mod toolpath;
pub mod units;

// Dependencies of the `skinpath` binary only (argument parsing, error chains, progress
// bars, signal handling): the library does not use them, and `unused_crate_dependencies`
// would otherwise name them.
#[cfg(feature = "cli")]
use anyhow as _;
#[cfg(feature = "cli")]
use clap as _;
#[cfg(feature = "cli")]
use indicatif as _;
#[cfg(feature = "cli")]
use signal_hook as _;

pub use dbsc::DiskBSpline;
pub use design::Design;
pub use geom::Circle;
pub use job::build::{BuildOptions, Place};
pub use job::{
    Job, JobError, JobOptions, JobOutput, OutputFormat, Progress, Scale, Stage, Summary,
    design_of_strokes,
};
pub use machine::{Profile, builtin_profile};
pub use sim::Report;
pub use toolpath::Toolpath;
