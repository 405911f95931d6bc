//! `skinpath check PROGRAM [--machine P] [--design D] [--json] [--backend builtin|linuxcnc]`.
//! Exit status 0 when clean, 1 when a check fails, 2 when the input is unusable.

use super::build::load_profile;
use super::io;
use anyhow::{Context, Result, bail};
use skinpath::job::check::{check_config, design_boundaries};
use skinpath::job::outline::{OutlineOptions, design_outlines};
use skinpath::sim::{Backend, CheckConfig, check_text};
use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};
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
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<u8> {
    let text = io::read_text(&a.program)?;
    let (mut cfg, tool_r) = match &a.machine {
        Some(m) => {
            let p = load_profile(m)?;
            let r = p.default_tool().map(|t| t.radius()).unwrap_or(0.0);
            (check_config(&p, r), r)
        }
        None => (CheckConfig::default(), 0.0),
    };
    cfg.tool_radius = a.tool_radius.unwrap_or(tool_r);
    cfg.allow_crossings = a.allow_crossings;
    let bounds = match &a.design {
        Some(d) => {
            let dtext = io::read_text(d)?;
            let design = skinpath::design::load(&dtext, &d.display().to_string())?;
            let outlines = design_outlines(&design, &OutlineOptions::default())?;
            design_boundaries(
                &outlines,
                a.keep == "outside",
                cfg.flatten_tolerance.max(1e-3),
                design.units.mm_per_unit(),
            )
        }
        None => Vec::new(),
    };
    let (backend, input) = if a.backend == "linuxcnc" {
        (Backend::LinuxCnc, run_rs274(&text)?)
    } else {
        (Backend::Builtin, text)
    };
    let report = check_text(backend, &input, &cfg, &bounds);
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!("{report}");
    }
    Ok(report.exit_code() as u8)
}

/// Longest time rs274 may take: it can loop forever on malformed input.
const RS274_TIMEOUT: Duration = Duration::from_secs(60);

/// Run LinuxCNC's stand-alone interpreter (`rs274 -n 0 -g`) on a line-numbered copy of the
/// program text ([`skinpath::sim::linuxcnc::number_lines`], so findings carry the file's
/// line numbers) and return its canonical commands. Stopped after [`RS274_TIMEOUT`].
fn run_rs274(text: &str) -> Result<String> {
    let dir = std::env::temp_dir().join(format!("skinpath-rs274-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let file = dir.join("program.ngc");
    std::fs::write(&file, skinpath::sim::linuxcnc::number_lines(text))
        .with_context(|| format!("cannot write {}", file.display()))?;
    let result = (|| -> Result<String> {
        let mut child = Command::new("rs274")
            .args(["-n", "0", "-g"])
            .arg(&file)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .context("cannot run rs274 (install the Debian package linuxcnc-uspace)")?;
        let stdout = child.stdout.take().context("rs274 has no output pipe")?;
        let reader = std::thread::spawn(move || {
            let mut s = String::new();
            let _ = std::io::BufReader::new(stdout).read_to_string(&mut s);
            s
        });
        let start = Instant::now();
        while child.try_wait()?.is_none() {
            if start.elapsed() > RS274_TIMEOUT {
                let _ = child.kill();
                let _ = child.wait();
                bail!("rs274 did not finish within {} s", RS274_TIMEOUT.as_secs());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let out = reader
            .join()
            .map_err(|_| anyhow::anyhow!("reading rs274 output failed"))?;
        if out.is_empty() {
            bail!("rs274 produced no output");
        }
        Ok(out)
    })();
    let _ = std::fs::remove_dir_all(&dir);
    result
}
