//! The `skinpath` command: parse arguments, run the subcommand, map errors to exit codes.

#![forbid(unsafe_code)]

mod cli;

/// Writes `text` to standard output. A closed pipe (`skinpath inspect --json | head -c 10`)
/// is not an error: the reader has what it wanted, so the rest is dropped quietly (the
/// standard `println!` would panic on it).
pub(crate) fn print_stdout(text: &str) -> std::io::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r,
    }
}

fn main() -> std::process::ExitCode {
    cli::run()
}
