//! Tests of the `skinpath` binary: verbs, flags, exit codes, messages, files written and
//! the limits of a run (every run is a child process).
//!
//! One test binary; each module was once a file of its own under tests/.

#[path = "../support/mod.rs"]
mod support;

mod api_cli;
mod check_cli;
mod cli;
mod cli_limits;
mod jobs_cli;
mod outputs_cli;
mod preview_cli;
mod text_cli;
