//! The `skinpath` command: parse arguments, run the subcommand, map errors to exit codes.

#![forbid(unsafe_code)]

/// `eprintln!` that never panics: the standard macro panics when stderr cannot be written
/// (`2>/dev/full`, a closed pipe), which ended `import` and `build` with status 101 before
/// they wrote their output. Messages on stderr are a courtesy; a failure to show one is
/// ignored. Defined before `mod cli` so that it replaces the standard macro in every module
/// of the command line.
macro_rules! eprintln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// `eprint!` that never panics (see [`eprintln!`]).
macro_rules! eprint {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($arg)*);
    }};
}

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
