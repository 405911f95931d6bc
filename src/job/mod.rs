//! Whole jobs on a design: outlines of every stroke, circle sequence and shape
//! ([`design_outlines`], [`outline_document`]), toolpaths for a machine
//! ([`build_toolpath`]) placed in the work area ([`place_job`]), and the checked job the
//! binary runs ([`Job`]): scale, build, place, write the machine program and check it. This is the only library module that walks a whole
//! design through the pipeline; the CLI adds files and terminals around it.
//!
//! The items below are the module's public front; its submodules are internal.

pub(crate) mod build;
pub(crate) mod check;
pub(crate) mod checked;
pub(crate) mod inspect;
pub(crate) mod neon;
pub(crate) mod outline;
pub(crate) mod outputs;
pub(crate) mod preview;
pub(crate) mod progress;
pub(crate) mod re_route;
pub(crate) mod shapes;
pub(crate) mod size;
pub(crate) mod summary;
pub(crate) mod tolerances;

pub use build::{
    BuildOptions, BuildResult, BuildWarning, DEFAULT_PROFILE_DEPTH_MM, LINE_DEPTH_MM, Place,
    Placement, build_toolpath, outline_bounds, place_job, scaled_design,
};
pub use check::{check_config, design_boundaries, operations_of, part_outlines};
pub use checked::{Job, JobOptions, JobOutput, OutputFormat, Scale, design_of_strokes};
pub use inspect::{
    CirclesInfo, DesignInfo, LoopInfo, OutputInfo, SegmentInfo, StrokeInfo, inspect,
};
pub use neon::{
    CloseRuns, FlexSummary, Leg, MarkBom, NeonBom, NeonWarning, Run, RunBom, RunPlace, TightBend,
    runs,
};
pub use outline::{
    ItemError, ItemOutline, OutlineOptions, SkinFallback, SkinRepair, SkinSplit, design_outlines,
    outline_document, outline_document_with,
};
pub use outputs::{OutputJob, job_name, run_outputs};
pub use preview::{scene_of_build, scene_of_design, scene_of_design_of, scene_of_program};
pub use progress::{Progress, ProgressFn, Stage, Timings};
pub use re_route::RouteNote;
pub use summary::{
    Bounds, DiskUnionSummary, OperationSummary, RouteSummary, SkinRepairSummary, Summary,
    TimeSummary,
};

use crate::design::DesignError;

/// Errors of a job; each names the design file and the stroke or operation at fault.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JobError {
    /// The design could not be read or is invalid.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// A stroke or circle sequence could not be outlined; `source` says why.
    #[error("{file}: {item} \"{name}\": {source}")]
    Item {
        /// The design file.
        file: String,
        /// `stroke` or `circle sequence`.
        item: &'static str,
        /// The item's name.
        name: String,
        /// What went wrong.
        source: Box<outline::ItemError>,
    },
    /// `index` is the operation's index in the design (0-based; shown 1-based, as the
    /// n-th `[[operation]]` table of the file).
    #[error("{file}: [[operation]] {} ({kind}): {message}", index + 1)]
    Operation {
        /// The design file.
        file: String,
        /// The operation's index in the design (0-based).
        index: usize,
        /// The operation's kind.
        kind: String,
        /// What went wrong.
        message: String,
    },
    /// One output of a design with `[[output]]` tables failed (see [`run_outputs`]); nothing
    /// of any output is returned.
    #[error("output \"{output}\" (machine {machine}): {source}")]
    Output {
        /// The output's `name`.
        output: String,
        /// The name of its machine profile.
        machine: String,
        /// What went wrong.
        source: Box<JobError>,
    },
    /// Job options out of range (the message names the option).
    #[error("{0}")]
    Options(String),
    /// The machine program could not be written.
    #[error(transparent)]
    Emit(#[from] crate::emit::EmitError),
    /// The G-code program failed its check and [`JobOptions::write_unchecked`] is off;
    /// `explanations` trace every error finding back to the design (see
    /// `explain` in the checked job).
    #[error(
        "{file}: the program failed {errors} check(s) (listed above with the operation \
         and stroke that made each); nothing was written (--write-unchecked \
         writes it anyway, at the risk named above)"
    )]
    Unchecked {
        /// The design file.
        file: String,
        /// Number of error findings.
        errors: usize,
        /// Each error finding traced back to its operation and stroke.
        explanations: Vec<String>,
    },
}
