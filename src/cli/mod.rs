//! The command line: one file per subcommand. This is the only place that touches files,
//! processes and the terminal; everything else is the library.

mod build;
mod build_outputs;
mod check;
mod files;
mod import;
mod init;
mod inspect;
pub mod io;
mod machines;
mod outline;
mod preview;
mod progress;
mod signals;
mod text;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// skinpath: variable-width strokes to intersection-free outlines and machine-ready
/// toolpaths.
#[derive(Parser, Debug)]
#[command(name = "skinpath", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Outline every stroke of a design: SVG drawing (.svg) or outline JSON (.json).
    Outline(outline::Args),
    /// Report on a design: knots, lengths, radii, envelope loops, skin approximation.
    Inspect(inspect::Args),
    /// Build machine output (G-code, laser SVG or DXF) from a design for a machine profile.
    Build(build::Args),
    /// Check a G-code program (from any tool) for faults; exit 1 when something fails.
    Check(check::Args),
    /// Preview a design (for a machine) or any G-code program: .svg, .png or .html player.
    Preview(preview::Args),
    /// List the machine profiles shipped with skinpath.
    Machines(machines::Args),
    /// Import an SVG drawing as a design: stroked paths become strokes.
    Import(import::Args),
    /// Write a design with single-stroke text (Hershey fonts).
    Text(text::Args),
    /// Write a commented starter design that builds as it is.
    Init(init::Args),
}

/// Exit status for input that cannot be used (bad file, bad design, bad options).
pub const EXIT_UNUSABLE: u8 = 2;

/// Parse the arguments, run the command, print errors a person can act on.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    signals::install();
    let result = match cli.command {
        Command::Outline(a) => outline::run(a),
        Command::Inspect(a) => inspect::run(a),
        Command::Build(a) => build::run(a),
        Command::Check(a) => check::run(a),
        Command::Machines(a) => machines::run(a),
        Command::Import(a) => import::run(a),
        Command::Text(a) => text::run(a),
        Command::Init(a) => init::run(a),
        Command::Preview(a) => preview::run(a),
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("skinpath: error: {}", chain(&e));
            ExitCode::from(EXIT_UNUSABLE)
        }
    }
}

/// The error and its causes, `outer: cause: cause`, as anyhow's `{:#}` prints them, except
/// that a cause whose text the message already holds is not repeated (typed library errors
/// show their source in their own message and keep it as `source()` for callers).
pub(crate) fn chain(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let m = cause.to_string();
        if !text.contains(&m) {
            text.push_str(": ");
            text.push_str(&m);
        }
    }
    text
}
