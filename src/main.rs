//! The `skinpath` command: parse arguments, run the subcommand, map errors to exit codes.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
