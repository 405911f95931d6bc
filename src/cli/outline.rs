//! `skinpath outline DESIGN -o OUT`: the outline drawing (SVG) or document (JSON).

use super::io;
use anyhow::{Context, Result, bail};
use skinpath::Stage;
use skinpath::design::OutlineMethod;
use skinpath::job::Timings;
use skinpath::job::{OutlineOptions, outline_document_with};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The design file (.toml or .json).
    design: PathBuf,
    /// Output file: .svg for a drawing, .json for the outline document.
    #[arg(short, long)]
    output: PathBuf,
    /// Outline method: skin (intersection-free, default), envelope (the raw boundary), re
    /// (rational-envelope skin of the circles) or mph (Minkowski-PH skin).
    #[arg(long, value_parser = ["skin", "envelope", "re", "mph"])]
    method: Option<String>,
    /// Flattening tolerance of the drawn contours, in design units.
    #[arg(long)]
    tolerance: Option<f64>,
    /// Skin approximation accuracy ε, in design units.
    #[arg(long)]
    epsilon: Option<f64>,
    /// Also draw the inner and outer offsets at this distance (design units).
    #[arg(long)]
    offset: Option<f64>,
    /// Also draw the control disks.
    #[arg(long)]
    control_disks: bool,
    /// Print the wall time of each stage (read, skin, emit, write) as a table on stderr.
    #[arg(long)]
    timings: bool,
}

pub fn run(a: Args) -> Result<u8> {
    let ext = io::extension(&a.output);
    if ext != "svg" && ext != "json" {
        bail!(
            "{}: the output must end in .svg or .json",
            a.output.display()
        );
    }
    io::refuse_overwriting_inputs(&a.output, &[&a.design])?;
    let mut timings = Timings::default();
    let text = timings.time(Stage::Read, || io::read_text(&a.design))?;
    let design = timings.time(Stage::Read, || {
        skinpath::design::load(&text, &a.design.display().to_string())
    })?;
    let mut opts = OutlineOptions::default();
    if let Some(o) = &design.outline {
        if let Some(m) = o.method {
            opts.method = m;
        }
        if let Some(t) = o.tolerance {
            opts.tolerance = t;
        }
    }
    if let Some(m) = a.method.as_deref() {
        opts.method = match m {
            "envelope" => OutlineMethod::Envelope,
            "re" => OutlineMethod::Re,
            "mph" => OutlineMethod::Mph,
            _ => OutlineMethod::Skin,
        };
    }
    if let Some(t) = a.tolerance {
        opts.tolerance = t;
    }
    if let Some(e) = a.epsilon {
        opts.epsilon = e;
    }
    opts.control_disks = a.control_disks;
    opts.offset = a.offset;
    let offset = a.offset.map(|d| ("--offset", d));
    for (name, v) in [("--tolerance", opts.tolerance), ("--epsilon", opts.epsilon)]
        .into_iter()
        .chain(offset)
    {
        if !(v.is_finite() && v > 0.0) {
            bail!("{name} must be a positive number, got {v}");
        }
    }
    let bar = super::progress::Bar::new();
    let on_progress = |p: skinpath::Progress| bar.show(p);
    let doc = timings.time(Stage::Skin, || {
        outline_document_with(&design, &opts, bar.active().then_some(&on_progress))
    });
    bar.finish();
    let doc = doc?;
    let body = timings.time(Stage::Emit, || {
        if ext == "svg" {
            doc.to_svg()
        } else {
            doc.to_json()
        }
    });
    timings.time(Stage::Write, || {
        io::write_atomic(&a.output, body.as_bytes())
            .with_context(|| format!("writing {}", a.output.display()))
    })?;
    if a.timings {
        eprint!("{}", timings.table());
    }
    Ok(0)
}
