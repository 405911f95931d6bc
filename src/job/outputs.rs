//! The outputs of one design ([`crate::design::output`]): one checked [`Job`] per
//! `[[output]]`, each with its own machine profile and format and only its own operations
//! (the others stay design context, see [`super::build::build_toolpath_placed`]).
//!
//! All outputs are built at one scale, so that the layers of a sign match: with
//! [`Scale::Fit`] every output is first fitted on its own, then the ones fitted larger than
//! the smallest fit are rebuilt at that scale ([`Scale::By`]). A job's extent is its fixed
//! part (tool offsets, margins) plus the scale times the art's extent, so an output that
//! fits at its own scale also fits at any smaller one. Placement (`--place`, `--margin`)
//! applies to each output in its own machine's work area.

use super::JobError;
use super::checked::{Job, JobOptions, JobOutput, OutputFormat, Scale};
use crate::design::{Design, Output};
use crate::machine::Profile;

/// One output to build: the design's `[[output]]` table, its machine profile (loaded by the
/// caller, which knows about files) and the format of its file.
#[derive(Clone, Copy, Debug)]
pub struct OutputJob<'a> {
    /// The `[[output]]` table.
    pub output: &'a Output,
    /// Its machine profile.
    pub profile: &'a Profile,
    /// The program to write.
    pub format: OutputFormat,
}

/// The job name of an output in its program's header: `NAME.OUTPUT`.
#[must_use]
pub fn job_name(name: &str, output: &Output) -> String {
    format!("{name}.{}", output.name)
}

/// Builds, places, writes and checks every output of `design` (in the order given) with
/// `options` (its `format` is each output's own, its `name` the job's, see [`job_name`]).
/// The first output that fails ends the run: the error names it
/// ([`JobError::Output`]), and nothing of the others is returned, so that a caller writes
/// the outputs as a set or not at all.
pub fn run_outputs(
    design: &Design,
    outputs: &[OutputJob<'_>],
    options: JobOptions<'_>,
) -> Result<Vec<JobOutput>, JobError> {
    let run = |oj: &OutputJob<'_>, scale: Scale| -> Result<JobOutput, JobError> {
        let name = job_name(options.name, oj.output);
        let job = Job {
            design,
            profile: oj.profile,
            options: JobOptions {
                format: oj.format,
                name: &name,
                scale,
                ..options
            },
        };
        let only = oj.output.operations_of(design);
        job.run_of(only.as_deref()).map_err(|e| JobError::Output {
            output: oj.output.name.clone(),
            machine: oj.profile.name.clone(),
            source: Box::new(e),
        })
    };
    let mut built = outputs
        .iter()
        .map(|oj| run(oj, options.scale))
        .collect::<Result<Vec<_>, _>>()?;
    if let Scale::Fit { .. } = options.scale {
        let common = (built.iter())
            .map(|b| b.placement.scale)
            .fold(f64::INFINITY, f64::min);
        for (oj, b) in outputs.iter().zip(built.iter_mut()) {
            if b.placement.scale != common {
                *b = run(oj, Scale::By(common))?;
            }
        }
    }
    Ok(built)
}
