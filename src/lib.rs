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
//!
//! ## The public front
//!
//! What is public is what an embedder needs; everything else is internal to the crate and
//! may change in any release. The crate root re-exports the job's types ([`Job`],
//! [`JobOptions`], [`JobOutput`], [`JobError`], [`Summary`], [`BuildOptions`], …) and the
//! values a job takes and gives ([`Design`], [`Profile`], [`Toolpath`], [`Report`],
//! [`DiskBSpline`], [`BSpline`], [`Circle`]). Each public module offers its own API at its
//! root, with no public submodules:
//!
//! | module | what it offers |
//! |---|---|
//! | [`job`] | [`Job`], its options, results and progress; `check`, `outline`, `preview` and `inspect` of a design |
//! | [`design`] | the design model (format below), [`design::load`], import of SVG drawings, single-stroke text, the design errors |
//! | [`machine`] | machine profiles: [`Profile`], the shipped ones ([`builtin_profile`]), their errors |
//! | [`geom`] | geometry primitives: points ([`geom::DVec2`]), circles, lines, arcs, cubics, paths |
//! | [`dbsc`] | disk B-spline curves: construction, fitting, envelopes and their loops |
//! | [`skin`] | skinning curves of circle sequences and disk B-splines |
//! | [`toolpath`] | the toolpath model: operations, cuts, moves |
//! | [`emit`] | G-code, laser SVG, DXF and preview writers |
//! | [`sim`] | the G-code simulator and checker: [`Report`] and its findings |
//!
//! ## Features
//!
//! | feature | default | gives | pulls in |
//! |---|---|---|---|
//! | `cli` | on | the `skinpath` binary | clap, anyhow, indicatif, signal-hook |
//! | `png` | on | PNG previews | resvg (with its usvg), tiny-skia |
//! | `svg-import` | on | designs read from SVG drawings | usvg, roxmltree, simplecss, svgtypes, kurbo |
//! | `parallel` | on | skins, outlines and checks on rayon's thread pool (sequential without it, same results) | rayon |
//! | `internals` | off | `skinpath::internals`: the stages benches/ time; not a stable API | — |
//!
//! `cargo build --lib --no-default-features` is the toolpath library alone: designs from
//! TOML or JSON, jobs, G-code, laser SVG, DXF and SVG previews, and the checker.
//!

// The design-format reference (docs/design-format.md), with its doc test.
#![doc = include_str!("../docs/design-format.md")]
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
#[cfg(feature = "internals")]
#[doc(hidden)]
pub mod internals;
pub mod job;
pub mod machine;
mod par;
pub mod sim;
pub mod skin;
pub(crate) mod spline;
pub mod toolpath;
pub(crate) mod units;

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
// The benches' harness: a dependency only with `internals` (every `[[bench]]` requires it),
// so that a plain `cargo test` does not build it.
#[cfg(feature = "internals")]
use criterion as _;

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
// The B-spline a disk B-spline curve and its attribute channels are made of
// (`DiskBSpline::curve`, `design::attribute_curve`), and its construction error.
pub use spline::{BSpline, SplineError};
pub use toolpath::Toolpath;
