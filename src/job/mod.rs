//! Whole jobs on a design: outlines of every stroke and circle sequence ([`outline`]) and
//! shape ([`shapes`]), and toolpaths for a machine ([`build`]). This is the only library module that walks a whole
//! design through the pipeline; the CLI adds files and terminals around it.

pub mod build;
pub mod check;
pub mod checked;
pub mod inspect;
pub mod neon;
pub mod outline;
pub mod outputs;
pub mod preview;
pub mod progress;
pub mod re_route;
pub mod shapes;
pub mod size;
pub mod tolerances;

pub use checked::{Job, JobOptions, JobOutput, OutputFormat, Scale, Summary, design_of_strokes};
pub use progress::{Progress, ProgressFn, Stage, Timings};

use crate::design::DesignError;

/// Errors of a job; each names the design file and the stroke or operation at fault.
#[derive(Debug, thiserror::Error)]
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
    /// One output of a design with `[[output]]` tables failed (see [`outputs`]); nothing
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
    /// [`checked::explain`]).
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
