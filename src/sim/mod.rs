//! Simulation backend: G-code interpreter, motion model, checks, time estimate, report.
//!
//! ```text
//! text ─► interp::interpret (builtin)      ─┐
//!         linuxcnc::parse_canon (rs274 out) ─┴► Program (motions in mm) ─► checks ─► Report
//! ```
//!
//! [`check`] runs everything on a [`Program`]; [`check_text`] reads G-code (builtin
//! backend) or rs274 canon output (LinuxCNC backend) first. On the builtin backend it never
//! stores the moves: they go from the interpreter to the checks in chunks, the checks
//! running beside it (`piped`, the same report as [`check`] of the stored program).
//! [`check_stream`] gives the same
//! report in bounded memory, reading the program line by line and checking each move as it
//! is read (the CLI's route for programs above [`STREAM_ABOVE_BYTES`]). For
//! [`Backend::LinuxCnc`], [`run_rs274`] runs LinuxCNC's `rs274 -n 0 -g` on
//! [`number_lines`]`(src)` (the one place the library starts a process) and [`load`] reads
//! its standard output.
//!
//! Laser rapids: GRBL in laser mode ($32=1) never fires the beam on G0, so G0 with M3/M4 and
//! S > 0 is harmless there and reported as a warning (`laser-on-rapid`); with
//! `grbl_laser_mode = false` (other dialects, or GRBL without laser mode) it is an error.
//!
//! Exit status for the CLI: [`Report::exit_code`] (0 clean, 1 error findings, 2 unusable
//! input).
//!
//! Module layering (imports only go down): findings (leaf) ← motion ← config ← time ←
//! report; the interpreter (`interp`, `ngc`), the checks and [`check`] sit on top. The CLI
//! times the stages through [`check_text_timed`].
//!
//! The public front is what this module re-exports; its submodules are internal.

pub(crate) mod checks;
pub(crate) mod config;
pub(crate) mod findings;
pub(crate) mod interp;
pub(crate) mod linuxcnc;
pub(crate) mod motion;
pub(crate) mod ngc;
pub(crate) mod piped;
pub(crate) mod report;
pub(crate) mod rs274;
pub(crate) mod stream;
pub(crate) mod temp;
pub(crate) mod time;
pub(crate) mod timeline;

pub use checks::{CheckFindings, DesignBoundary, KeepSide};
pub use config::{CheckConfig, Dialect, MachineKind, ToolEntry, parse_tool_table};
pub use findings::{Finding, Severity};
pub use interp::{CheckedLoader, LoadSub, Options as InterpOptions, ReadSeek, SubLoader};
pub use linuxcnc::{number_lines, parse_canon};
pub use motion::{
    Event, Motion, MotionKind, Motions, Program, ProgramEnd, Spindle, ToolState, Units,
};
pub use piped::{StageTimes, THREAD_ABOVE_BYTES};
pub use report::{Report, Stats};
pub use rs274::{Rs274Error, Rs274Options, Rs274Output, run as run_rs274};
pub use stream::{STREAM_ABOVE_BYTES, check_stream};
pub use temp::remove_left_behind;
pub use time::TimeEstimate;

/// Prefixes of the temporary files and folders the library makes in the system's temporary
/// folder (the streaming check's segment files, the LinuxCNC runner's working folder), each
/// followed by the making process's id and `-`: a signal handler removes its own by name,
/// [`remove_left_behind`] those of runs that were killed.
pub const TEMP_PREFIXES: [&str; 2] = [stream::TEMP_PREFIX, rs274::TMP_PREFIX];

/// Which interpreter reads the program.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Backend {
    /// The built-in RS274NGC interpreter on the G-code text.
    #[default]
    Builtin,
    /// [`parse_canon`] on the output of `rs274 -n 0 -g` ([`run_rs274`]).
    LinuxCnc,
}

impl Backend {
    /// The backend's name as the CLI spells it (`builtin`, `linuxcnc`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Backend::Builtin => "builtin",
            Backend::LinuxCnc => "linuxcnc",
        }
    }
}

/// Reads `text` with `backend` (G-code for Builtin, rs274 canon output for LinuxCnc).
#[must_use]
pub fn load(backend: Backend, text: &str, cfg: &CheckConfig) -> Program {
    load_with(backend, text, cfg, &InterpOptions::default())
}

/// [`load`] with interpreter options (the subroutine file loader).
#[must_use]
pub fn load_with(
    backend: Backend,
    text: &str,
    cfg: &CheckConfig,
    opts: &InterpOptions<'_>,
) -> Program {
    let mut prog = match backend {
        Backend::Builtin => interp::interpret_with(text, &cfg.in_mm(), opts),
        Backend::LinuxCnc => linuxcnc::parse_canon(text),
    };
    if backend == Backend::Builtin {
        prog.unusable = unusable_text(text);
    }
    prog
}

/// Why G-code text cannot be used at all (empty, only blank lines, binary), if so.
fn unusable_text(text: &str) -> Option<String> {
    if text.trim().is_empty() {
        Some(if text.is_empty() {
            "the file is empty".into()
        } else {
            "the file holds only blank lines".into()
        })
    } else if memchr::memchr(0, text.as_bytes()).is_some() {
        Some("the file holds NUL bytes: it is binary, not G-code".into())
    } else {
        None
    }
}

/// Reads and checks `text`; see [`load`] and [`check`].
#[must_use]
pub fn check_text(
    backend: Backend,
    text: &str,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
) -> Report {
    check_text_with(backend, text, cfg, design, &InterpOptions::default())
}

/// [`check_text`] with interpreter options.
#[must_use]
pub fn check_text_with(
    backend: Backend,
    text: &str,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &InterpOptions<'_>,
) -> Report {
    check_text_timed(backend, text, cfg, design, opts).0
}

/// [`check_text_with`] and the wall time of its stages. The builtin backend takes the
/// moves as the interpreter produces them and never stores them (a route of its own, with
/// the report of [`check`] on the stored program); the LinuxCNC backend's output is read
/// into a [`Program`] first.
#[must_use]
pub fn check_text_timed(
    backend: Backend,
    text: &str,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &InterpOptions<'_>,
) -> (Report, StageTimes) {
    let (mut r, times) = match backend {
        Backend::Builtin => piped::check_builtin(text, cfg, design, opts),
        Backend::LinuxCnc => check_stored(backend, text, cfg, design, opts),
    };
    r.backend = backend.name();
    (r, times)
}

/// [`check_text_timed`] of the program read whole into a [`Program`], moves stored.
fn check_stored(
    backend: Backend,
    text: &str,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &InterpOptions<'_>,
) -> (Report, StageTimes) {
    let clock = std::time::Instant::now();
    let prog = load_with(backend, text, cfg, opts);
    let interpret = clock.elapsed().as_secs_f64();
    let (found, stats, [contours, moves]) = checks_and_stats(&prog, cfg, design);
    let report = assemble_found(&prog, cfg, found, stats);
    let times = StageTimes {
        interpret,
        contours,
        moves,
        total: clock.elapsed().as_secs_f64(),
    };
    (report, times)
}

/// Decodes a file's bytes as G-code text: a UTF-8 byte-order mark is skipped and invalid
/// UTF-8 is replaced (U+FFFD) with one warning naming the first lines where it occurs.
#[must_use]
pub fn decode(bytes: &[u8]) -> (std::borrow::Cow<'_, str>, Vec<Finding>) {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => (std::borrow::Cow::Borrowed(s), Vec::new()),
        Err(_) => {
            let mut lines = Vec::new();
            let mut total = 0usize;
            for (i, l) in bytes.split(|&b| b == b'\n').enumerate() {
                if std::str::from_utf8(l).is_err() {
                    total += 1;
                    if lines.len() < 10 {
                        lines.push(i + 1);
                    }
                }
            }
            let f = utf8_warning(lines, total);
            (String::from_utf8_lossy(bytes), vec![f])
        }
    }
}

/// The `invalid-utf8` warning: `total` lines held bytes that are not UTF-8, the first of
/// them (1-based, at most 10) in `lines`.
#[must_use]
pub fn utf8_warning(lines: Vec<usize>, total: usize) -> Finding {
    let more = if total > lines.len() {
        format!(" and {} more", total - lines.len())
    } else {
        String::new()
    };
    Finding::new(
        "invalid-utf8",
        Severity::Warning,
        format!(
            "bytes that are not UTF-8 were read as U+FFFD on {total} line(s){more} \
             (save the file as UTF-8 or ASCII)"
        ),
    )
    .lines(lines)
}

/// Runs every check and the time estimate on `prog`. `cfg` may be in inch; `design` is in
/// mm. Interpreter diagnostics come first, then the checks' findings, each check capped at
/// `cfg.max_findings_per_check` (the rest counted in `suppressed`).
#[must_use]
pub fn check(prog: &Program, cfg: &CheckConfig, design: &[DesignBoundary]) -> Report {
    let (found, stats, _) = checks_and_stats(prog, cfg, design);
    assemble_found(prog, cfg, found, stats)
}

/// [`assemble_with`] of what [`checks_and_stats`] found, the counts it gives as lower
/// bounds marked in [`Report::suppressed_at_least`].
#[must_use]
pub fn assemble_found(
    prog: &Program,
    cfg: &CheckConfig,
    found: CheckFindings,
    stats: Stats,
) -> Report {
    let mut r = assemble_with(prog, cfg, found.findings, stats, &found.dropped);
    r.suppressed_at_least = found
        .at_least
        .iter()
        .filter(|id| r.suppressed.iter().any(|s| s.0 == **id))
        .map(|id| id.to_string())
        .collect();
    r
}

/// The findings of [`check`] before capping (interpreter diagnostics, then every check's,
/// with the findings counted but not built, [`CheckFindings`]) and the [`stats`],
/// both empty when the program is unusable; also the wall seconds of the two sides below.
/// `cfg` may be in inch; `design` is in mm.
///
/// Two workers share the work in about equal parts: one runs the checks on the cut
/// contours, the other the per-move checks in the time estimate's pass over the moves. The findings are
/// those of every check in its order: the contour checks', then the per-move checks'.
#[must_use]
pub fn checks_and_stats(
    prog: &Program,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
) -> (CheckFindings, Stats, [f64; 2]) {
    if prog.unusable.is_some() {
        return (CheckFindings::default(), Stats::default(), [0.0; 2]);
    }
    let mm = cfg.in_mm();
    let ((contour, t_contours), ((moves, stats), t_moves)) = crate::par::join(
        || timed(|| checks::contour_findings(prog, &mm, design)),
        || {
            timed(|| {
                let mut pass = piped::MovePass::new(&mm);
                for m in &prog.motions {
                    pass.motion(&m);
                }
                pass.finish(prog)
            })
        },
    );
    let found = found_of(prog, checks::join(contour, moves));
    (found, stats, [t_contours, t_moves])
}

/// The findings of [`checks_and_stats`]: the interpreter's diagnostics, then `checks`.
fn found_of(prog: &Program, mut checks: CheckFindings) -> CheckFindings {
    checks
        .findings
        .splice(0..0, prog.diagnostics.iter().cloned());
    checks
        .dropped
        .splice(0..0, prog.diagnostics_dropped.iter().copied());
    checks
}

/// The value of `f` and the wall seconds it took.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let clock = std::time::Instant::now();
    let value = f();
    (value, clock.elapsed().as_secs_f64())
}

/// The report of [`check`] from the findings and the [`stats`] of [`checks_and_stats`]:
/// usability, and each check capped at `cfg.max_findings_per_check`.
#[must_use]
pub fn assemble(prog: &Program, cfg: &CheckConfig, all: Vec<Finding>, stats: Stats) -> Report {
    assemble_with(prog, cfg, all, stats, &[])
}

/// [`assemble`] of findings already capped: `dropped` counts, per id, findings left out of
/// `all` that came after the ones kept (the streaming route keeps at most the cap per id).
#[must_use]
pub fn assemble_with(
    prog: &Program,
    cfg: &CheckConfig,
    all: Vec<Finding>,
    stats: Stats,
    dropped: &[(&'static str, usize)],
) -> Report {
    let mm = cfg.in_mm();
    if let Some(reason) = &prog.unusable {
        return Report {
            backend: Backend::Builtin.name(),
            usable: false,
            reason: Some(reason.clone()),
            ..Default::default()
        };
    }
    let syntax = prog
        .diagnostics
        .iter()
        .filter(|d| d.id == "gcode-syntax")
        .count()
        + prog
            .diagnostics_dropped
            .iter()
            .filter(|d| d.0 == "gcode-syntax")
            .map(|d| d.1)
            .sum::<usize>();
    let usable = prog.words > 0 && syntax <= prog.words;
    let reason = (!usable).then(|| {
        if prog.words == 0 {
            "no G-code word could be read".to_string()
        } else {
            format!(
                "{syntax} syntax errors against {} words read: this is not G-code",
                prog.words
            )
        }
    });
    // At least one finding per id is kept, so a program with errors always shows one (and
    // exits 1) whatever the configured cap.
    let cap = mm.max_findings_per_check.max(1);
    let mut counts: Vec<(&'static str, usize)> = Vec::new();
    let mut findings = Vec::new();
    for f in all {
        let slot = match counts.iter_mut().find(|(id, _)| *id == f.id) {
            Some(s) => s,
            None => {
                counts.push((f.id, 0));
                let last = counts.len() - 1;
                &mut counts[last]
            }
        };
        slot.1 += 1;
        if slot.1 <= cap {
            findings.push(f);
        }
    }
    for &(id, n) in dropped {
        match counts.iter_mut().find(|(c, _)| *c == id) {
            Some(s) => s.1 += n,
            None => counts.push((id, n)),
        }
    }
    let suppressed = counts
        .into_iter()
        .filter(|&(_, n)| n > cap)
        .map(|(id, n)| (id.to_string(), n - cap))
        .collect();
    Report {
        backend: Backend::Builtin.name(),
        usable,
        reason,
        findings,
        suppressed,
        suppressed_at_least: Vec::new(),
        stats,
    }
}

/// Move count, cut and rapid lengths (helical lengths for arcs), bounds, time.
#[must_use]
pub fn stats(prog: &Program, cfg: &CheckConfig) -> Stats {
    let mut sum = report::StatsSum::new();
    // One pass over the moves: the estimate hands each to the sums.
    let time = time::estimate_each(&prog.motions, cfg, |m| sum.motion(m, m.bounds()));
    sum.finish(time)
}

#[cfg(test)]
mod tests;
