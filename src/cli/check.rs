//! `skinpath check PROGRAM [--machine P] [--dialect D] [--design D] [--json] [--timings]
//! [--backend builtin|linuxcnc]`. Exit status 0 when clean, 1 when a check fails, 2 when the
//! input is unusable or the backend fails (rs274 not installed, stopped at its limit). With
//! `--json` every outcome is a JSON report on standard output, those of exit 2 included:
//! `usable` false, the error as `reason` and as the one finding ([`failure_report`]).
//! With `--design` whose `[[output]]` tables name machines and no `--machine`, the profile
//! is that of the output the program is (`--only NAME`, else the output whose file name
//! is the program's).

use super::build::load_profile;
use super::files;
use super::io;
use anyhow::{Context, Result, bail};
use skinpath::design::HAIRLINE_MM;
use skinpath::job::{OutlineOptions, design_outlines};
use skinpath::job::{check_config, design_boundaries, operations_of, part_outlines};
use skinpath::sim::{Backend, CheckConfig, CheckedLoader, Dialect, InterpOptions};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The G-code program.
    program: PathBuf,
    /// Machine profile (shipped name or .toml path) for travel, feed and power limits.
    #[arg(short, long)]
    machine: Option<String>,
    /// Design the program cuts: the tool must keep its radius from the outlines.
    #[arg(long)]
    design: Option<PathBuf>,
    /// With --design whose `[[output]]` tables name machines: the output the program is
    /// (its machine is the profile unless --machine is given). Default: the output whose
    /// file name (`file`, with the design's stem) is the program's.
    #[arg(long, requires = "design")]
    only: Option<String>,
    /// With --design: the outlined shapes are parts to cut around (outside), or only the
    /// distance matters (either).
    #[arg(long, value_parser = ["outside", "either"], default_value = "outside")]
    keep: String,
    /// Tool radius (half the kerf for lasers), machine units; default from the profile.
    #[arg(long)]
    tool_radius: Option<f64>,
    /// Contours may cross each other (channels crossing on purpose).
    #[arg(long)]
    allow_crossings: bool,
    /// Interpreter: builtin, or LinuxCNC's rs274 (needs the linuxcnc-uspace package).
    #[arg(long, value_parser = ["builtin", "linuxcnc"], default_value = "builtin")]
    backend: String,
    /// How the controller reads the program: generic, linuxcnc, grbl, marlin, smoothie
    /// (default: the machine profile's dialect, else generic).
    #[arg(long, value_parser = ["generic", "linuxcnc", "grbl", "marlin", "smoothie"])]
    dialect: Option<String>,
    /// LinuxCNC tool table (.tbl) for M6/G43 tool length offsets.
    #[arg(long)]
    tool_table: Option<PathBuf>,
    /// Folders searched for called subroutine files `NAME.ngc` (after the program's folder).
    #[arg(long)]
    sub_path: Vec<PathBuf>,
    /// Most processor time rs274 may use (seconds) with `--backend linuxcnc` (a limit on
    /// work: a busy machine stretches the wall time, not this).
    #[arg(long, default_value_t = 20.0)]
    rs274_timeout: f64,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
    /// Print the wall time of each stage (read, interpret, checks, estimate, report) on
    /// standard error, or as `timings` in the JSON report with --json.
    #[arg(long)]
    timings: bool,
}

/// The JSON report with the stage timings beside its keys.
#[derive(serde::Serialize)]
struct TimedReport<'a> {
    #[serde(flatten)]
    report: &'a skinpath::Report,
    timings: &'a Timings,
}

/// Wall time per stage of one `check` run, in seconds.
#[derive(Default, serde::Serialize)]
struct Timings {
    /// Reading the file and decoding it as text.
    read: f64,
    /// Interpreting the G-code (with `--backend linuxcnc`: running rs274 and reading its
    /// output).
    interpret: f64,
    /// The checks on the cut contours (intersections, gouges).
    checks: f64,
    /// The per-move checks (bounds, rapids, feeds, program end), statistics and the time
    /// estimate, in one pass over the moves beside another stage: interpreting (builtin
    /// backend), or the contour checks (LinuxCNC backend).
    estimate: f64,
    /// Assembling and writing the report.
    report: f64,
    /// Wall time from the end of interpreting to the report (the contour checks, and the
    /// per-move work where it did not overlap the interpreting).
    #[serde(skip)]
    after_interpret: f64,
}

/// Finding id of a report whose backend stopped at its limit (rs274's processor time or
/// output size, or the wall-clock safeguard).
pub const BACKEND_LIMIT: &str = "backend-limit";
/// Finding id of a report whose backend failed otherwise (rs274 not installed, killed, no
/// output, its folder unwritable).
pub const BACKEND_ERROR: &str = "backend-error";
/// Finding id of a report on input that could not be used (file unreadable, bad profile,
/// design or tool table).
pub const INPUT_ERROR: &str = "input-error";

/// Checks as `a` says. With `--json` an error is a JSON report too ([`failure_report`]),
/// printed here, with exit status [`super::EXIT_UNUSABLE`].
pub fn run(a: Args) -> Result<u8> {
    match checked(&a) {
        Err(e) if a.json => {
            let report = failure_report(&a, &e);
            crate::print_stdout(&format!("{}\n", serde_json::to_string_pretty(&report)?))?;
            Ok(super::EXIT_UNUSABLE)
        }
        r => r,
    }
}

/// The report of a check that could not run: not usable, the error as its reason and as its
/// one finding, whose id tells a backend stopped at its limit ([`BACKEND_LIMIT`]) from one
/// that failed ([`BACKEND_ERROR`]) and from unusable input ([`INPUT_ERROR`]).
fn failure_report(a: &Args, e: &anyhow::Error) -> skinpath::sim::Report {
    use skinpath::sim::Rs274Error;
    let id = match e.downcast_ref::<Rs274Error>() {
        Some(Rs274Error::Timeout(_) | Rs274Error::OutputTooLarge(_) | Rs274Error::Stalled(_)) => {
            BACKEND_LIMIT
        }
        Some(_) => BACKEND_ERROR,
        None => INPUT_ERROR,
    };
    let message = super::chain(e);
    let mut report = skinpath::sim::Report::default();
    report.backend = if a.backend == "linuxcnc" {
        Backend::LinuxCnc.name()
    } else {
        Backend::Builtin.name()
    };
    report.usable = false;
    report.reason = Some(message.clone());
    report.findings = vec![skinpath::sim::Finding::new(
        id,
        skinpath::sim::Severity::Error,
        message,
    )];
    report
}

/// The profile of the `[[output]]` of `--design` the program is (module docs of `--only`),
/// when --machine is not given; `None` for a design without outputs.
fn output_profile(a: &Args) -> Result<Option<skinpath::Profile>> {
    let (Some(d), None) = (&a.design, &a.machine) else {
        return Ok(None);
    };
    let dtext = io::read_text(d)?;
    let file = d.display().to_string();
    let design = skinpath::design::load(&dtext, &file)?;
    if design.output.is_empty() {
        if let Some(n) = &a.only {
            bail!("{file}: --only {n}: the design has no [[output]] tables");
        }
        return Ok(None);
    }
    let names: Vec<&str> = design.output.iter().map(|o| o.name.as_str()).collect();
    let stem = super::build::job_name(d);
    let ext = io::extension(&a.program);
    let program = a
        .program
        .file_name()
        .map(|s| s.to_string_lossy().into_owned());
    let found = match &a.only {
        Some(n) => design
            .output
            .iter()
            .find(|o| &o.name == n)
            .with_context(|| {
                format!(
                    "{file}: --only {n}: no [[output]] of that name; the design's outputs are {}",
                    names.join(", ")
                )
            })?,
        None => (design.output.iter())
            .find(|o| Some(o.file_name(&stem, &ext)) == program)
            .with_context(|| {
                format!(
                    "{file}: the design's outputs ({}) name their machines: say which one {} is \
                     with --only NAME, or give --machine",
                    names.join(", "),
                    a.program.display()
                )
            })?,
    };
    let dir = d
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let (p, _) = super::build_outputs::output_profile(&found.machine, &dir)
        .with_context(|| format!("{file}: [[output]] \"{}\"", found.name))?;
    Ok(Some(p))
}

fn checked(a: &Args) -> Result<u8> {
    let mut timings = Timings::default();
    let profile = match &a.machine {
        Some(m) => Some(load_profile(m)?),
        None => output_profile(a)?,
    };
    let (mut cfg, tool_r) = match profile {
        Some(p) => {
            let r = p.default_tool().map(|t| t.radius()).unwrap_or(0.0);
            let mut c = check_config(&p, r);
            c.tool_table = p
                .tools
                .iter()
                .enumerate()
                .map(|(i, t)| skinpath::sim::ToolEntry::new(i as u32 + 1, 2.0 * t.radius()))
                .collect();
            (c, r)
        }
        None => (CheckConfig::default(), 0.0),
    };
    if let Some(d) = &a.dialect {
        cfg.dialect = Dialect::from_name(d).context("unknown dialect")?;
    }
    if let Some(t) = &a.tool_table {
        let ttext = io::read_text(t)?;
        cfg.tool_table = skinpath::sim::parse_tool_table(&ttext)
            .map_err(|e| anyhow::anyhow!("{}: {e}", t.display()))?;
    }
    cfg.tool_radius = a.tool_radius.unwrap_or(tool_r);
    cfg.allow_crossings = a.allow_crossings;
    let bounds = match &a.design {
        Some(d) => {
            let dtext = io::read_text(d)?;
            let design = skinpath::design::load(&dtext, &d.display().to_string())?;
            let outlines = design_outlines(&design, &OutlineOptions::default())?;
            // Only the parts are kept off: items the design cuts into (channels, lines,
            // pockets, …) are not (the tool radius and HAIRLINE_MM are in mm).
            let per_mm = 1.0 / design.units.mm_per_unit();
            let hairline = (2.0 * cfg.tool_radius * cfg.units.to_mm()).max(HAIRLINE_MM) * per_mm;
            let ops = operations_of(&design, hairline);
            let laser = cfg.kind == skinpath::sim::MachineKind::Laser;
            let parts = part_outlines(&design, &ops, &outlines, laser);
            design_boundaries(
                &parts,
                a.keep == "outside",
                cfg.flatten_tolerance.max(1e-3),
                design.units.mm_per_unit(),
            )
        }
        None => Vec::new(),
    };
    let mut dirs: Vec<PathBuf> = a
        .program
        .parent()
        .map(|p| vec![p.to_path_buf()])
        .unwrap_or_default();
    dirs.extend(a.sub_path.iter().cloned());
    let loader = CheckedLoader(|name: &str| find_sub(&dirs, name));
    let opts = InterpOptions::with_loader(&loader);
    // Only a regular file is read (a FIFO would hang, /dev/zero never ends).
    let size = files::regular_file_size(&a.program)
        .with_context(|| format!("cannot read {}", a.program.display()))?;
    let stream = cfg
        .stream
        .unwrap_or(size > skinpath::sim::STREAM_ABOVE_BYTES)
        && a.backend == "builtin";
    if stream {
        // Streaming route: reading, interpreting and the per-move checks overlap (all in
        // `interpret`); `checks` is the contact test after the last move.
        let clock = Instant::now();
        let file = std::fs::File::open(&a.program)
            .with_context(|| format!("cannot read {}", a.program.display()))?;
        let (mut report, utf8) = skinpath::sim::check_stream(Box::new(file), &cfg, &bounds, &opts)
            .with_context(|| format!("cannot check {}", a.program.display()))?;
        timings.interpret = clock.elapsed().as_secs_f64();
        report.backend = Backend::Builtin.name();
        if report.usable {
            report.findings.splice(0..0, utf8);
        }
        return write_report(a, &report, &mut timings, Instant::now());
    }
    let clock = Instant::now();
    let bytes = files::read_regular(&a.program, skinpath::sim::STREAM_ABOVE_BYTES.max(size))
        .with_context(|| format!("cannot read {}", a.program.display()))?;
    let (text, decode_findings) = skinpath::sim::decode(&bytes);
    timings.read = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let linuxcnc = a.backend == "linuxcnc" && !text.trim().is_empty();
    let rs274_out = if linuxcnc {
        let timeout = Duration::from_secs_f64(a.rs274_timeout.clamp(0.1, 3600.0));
        let mut opts = skinpath::sim::Rs274Options::default();
        opts.timeout = timeout;
        opts.sub_dirs = dirs.clone();
        opts.tool_table = a.tool_table.clone();
        // Line-numbered, so rs274's findings carry the file's line numbers.
        let numbered = skinpath::sim::number_lines(&text);
        skinpath::sim::run_rs274(&numbered, &opts)?.combined()
    } else {
        String::new()
    };
    let (backend, input): (Backend, &str) = if linuxcnc {
        (Backend::LinuxCnc, &rs274_out)
    } else {
        (Backend::Builtin, &text)
    };
    let (mut report, times) = skinpath::sim::check_text_timed(backend, input, &cfg, &bounds, &opts);
    drop(rs274_out);
    drop(text);
    drop(bytes);
    // With --backend linuxcnc, interpreting includes running rs274.
    timings.interpret = clock.elapsed().as_secs_f64() - times.total + times.interpret;
    (timings.checks, timings.estimate) = (times.contours, times.moves);
    timings.after_interpret = times.total - times.interpret;
    let clock = Instant::now();
    if report.usable {
        report.findings.splice(0..0, decode_findings);
    }
    write_report(a, &report, &mut timings, clock)
}

/// Prints `report` as `a` asks (text or JSON, with timings) and returns the exit status;
/// `clock` started when the report stage did.
fn write_report(
    a: &Args,
    report: &skinpath::Report,
    timings: &mut Timings,
    clock: Instant,
) -> Result<u8> {
    let text = if a.json && a.timings {
        timings.report = clock.elapsed().as_secs_f64();
        serde_json::to_string_pretty(&TimedReport { report, timings })?
    } else if a.json {
        serde_json::to_string_pretty(report)?
    } else {
        report.to_string()
    };
    crate::print_stdout(&format!("{text}\n"))?;
    timings.report = clock.elapsed().as_secs_f64();
    if a.timings && !a.json {
        let t = &timings;
        eprintln!(
            "timings: read {:.3} s, interpret {:.3} s, contour checks {:.3} s, move checks \
             with estimate {:.3} s (beside the interpreting or the contour checks), report \
             {:.3} s, total {:.3} s",
            t.read,
            t.interpret,
            t.checks,
            t.estimate,
            t.report,
            t.read + t.interpret + t.after_interpret + t.report
        );
    }
    Ok(report.exit_code() as u8)
}

/// `NAME.ngc` (any case of the name) in the first folder of `dirs` that holds it: its text,
/// or why it cannot be read (not a regular file, larger than
/// [`files::MAX_SUB_FILE_BYTES`]).
fn find_sub(dirs: &[PathBuf], name: &str) -> Result<Option<String>, String> {
    for d in dirs {
        for cand in [
            format!("{name}.ngc"),
            format!("{}.ngc", name.to_uppercase()),
        ] {
            let p = d.join(cand);
            match files::read_regular(&p, files::MAX_SUB_FILE_BYTES) {
                Ok(b) => return Ok(Some(String::from_utf8_lossy(&b).into_owned())),
                Err(files::FileError::Io { source, .. })
                    if source.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => return Err(e.to_string()),
            }
        }
    }
    Ok(None)
}
