//! `skinpath build DESIGN --machine NAME|PATH [-o OUT]`: machine output from a design.
//!
//! The output format follows the extension (.gcode/.nc/.ngc/.tap G-code, .svg laser SVG,
//! .dxf DXF) or `--format`. G-code is read back by the checker before it is written; a
//! program with findings of error severity is refused unless `--write-unchecked` is given.
//! A design with `[[output]]` tables is built without `--machine`, one program per output
//! ([`super::build_outputs`]).

use super::io;
use anyhow::{Context, Result, bail};
use skinpath::job::{BuildOptions, Place};
use skinpath::job::{Job, JobError, JobOptions, JobOutput, OutputFormat, Scale, Stage, Timings};
use skinpath::machine::{MachineKind, Profile, builtin_profile};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The design file (.toml or .json).
    pub(super) design: PathBuf,
    /// Machine profile: a shipped name (see `skinpath machines`) or a path to a .toml.
    /// Required, unless the design has `[[output]]` tables: they name their machines, and
    /// `--machine` is then refused (build one output with `--only NAME`).
    #[arg(short, long)]
    pub(super) machine: Option<String>,
    /// With `[[output]]` tables: build only the outputs of these names (repeat the option
    /// or separate names by commas); they are written as a set as all outputs are.
    #[arg(long, value_name = "NAME", value_delimiter = ',')]
    pub(super) only: Vec<String>,
    /// Output file (.gcode, .nc, .ngc, .tap, .svg or .dxf); default: the design's name in the
    /// current folder, with .gcode for G-code machines and .svg for SVG laser profiles.
    /// With `[[output]]` tables: the folder and file stem of every output's file (or a
    /// folder), `STEM.NAME.gcode` or `.svg`.
    #[arg(short, long)]
    pub(super) output: Option<PathBuf>,
    /// Output format, when the extension does not say it.
    #[arg(long, value_parser = ["gcode", "svg", "dxf"])]
    pub(super) format: Option<String>,
    /// Arc fitting tolerance of the toolpath, in design units.
    #[arg(long)]
    pub(super) tolerance: Option<f64>,
    /// Skin approximation accuracy ε, in design units.
    #[arg(long)]
    pub(super) epsilon: Option<f64>,
    /// Skin route of profiles and backboards: `skin` (Bézier skin, general offsets), `re` or
    /// `mph` (exact MAT offsets of RE/MPH skins). An operation's own `method` wins.
    #[arg(long, value_parser = ["skin", "re", "mph"], default_value = "skin")]
    pub(super) method: String,
    /// Also write a preview here: .svg or .png drawing, or .html player (see `preview`);
    /// written only together with the output, and never to the output's own path.
    #[arg(long)]
    pub(super) preview: Option<PathBuf>,
    /// Also write the neon bill of materials (flex runs, lengths, cut lengths, bend radii)
    /// as CSV here; needs a `[neon]` table, and is written only together with the output.
    #[arg(long, value_name = "FILE.csv")]
    pub(super) bom: Option<PathBuf>,
    /// Where the job goes on the machine (G-code, laser SVG and DXF alike): `lower-left`
    /// (the default) puts the job's lower-left corner, tool paths included, at the work
    /// area's lower-left corner plus `--margin`; `center` centres it in the work area;
    /// `design` keeps the design's coordinates.
    #[arg(long, value_parser = ["design", "lower-left", "center"], default_value = "lower-left")]
    pub(super) place: String,
    /// Distance from the work area's corner with `--place lower-left`, in design units.
    #[arg(long, default_value_t = 0.0)]
    pub(super) margin: f64,
    /// Scale the design's strokes and circles by this factor before building (channel
    /// widths, hole diameters, depths and margins stay as written).
    #[arg(long)]
    pub(super) scale: Option<f64>,
    /// Scale the design uniformly (aspect kept) so the job fits W x H design units, e.g.
    /// `--fit 200x150`.
    #[arg(long, value_name = "WxH")]
    pub(super) fit: Option<String>,
    /// Print the summary (operations, lengths, bounds, placement, time, findings) as JSON.
    #[arg(long)]
    pub(super) json: bool,
    /// Write the G-code even when the checker finds errors. It may then gouge the part,
    /// leave the laser or spindle on during a rapid, or leave the machine's travel.
    #[arg(long)]
    pub(super) write_unchecked: bool,
    /// Print the wall time of each stage (read, skin, toolpath, place, emit, check, write):
    /// a table on stderr, or a "timings" object (seconds) in the `--json` summary.
    #[arg(long)]
    pub(super) timings: bool,
}

/// A shipped profile by name, or a user's profile file.
pub fn load_profile(spec: &str) -> Result<Profile> {
    match builtin_profile(spec) {
        Err(e) if e.is_unknown_builtin() => {}
        p => return Ok(p?),
    }
    let path = Path::new(spec);
    if path.exists() {
        let text = io::read_text(path)?;
        return Ok(Profile::from_toml(&text, &path.display().to_string())?);
    }
    bail!("no machine profile named {spec:?} (see `skinpath machines`) and no such file")
}

fn format_of(a: &Args, output: &Path) -> Result<OutputFormat> {
    if let Some(f) = &a.format {
        return OutputFormat::from_extension(f)
            .with_context(|| format!("--format {f}: expected gcode, svg or dxf"));
    }
    let ext = io::extension(output);
    match OutputFormat::from_extension(&ext) {
        Some(f) => Ok(f),
        None => bail!(
            "{}: cannot tell the output format from .{ext}; use --format gcode|svg|dxf",
            output.display()
        ),
    }
}

/// `--fit WxH` as two positive numbers.
fn parse_fit(s: &str) -> Result<(f64, f64)> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .with_context(|| format!("--fit {s:?}: expected WIDTHxHEIGHT, e.g. 200x150"))?;
    let w: f64 = w
        .trim()
        .parse()
        .with_context(|| format!("--fit {s:?}: bad width"))?;
    let h: f64 = h
        .trim()
        .parse()
        .with_context(|| format!("--fit {s:?}: bad height"))?;
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
        bail!("--fit {s:?}: width and height must be positive numbers");
    }
    Ok((w, h))
}

/// The output path when `-o` is not given: the design's file stem in the current folder,
/// with the profile's natural extension.
fn default_output(design: &Path, profile: &Profile) -> PathBuf {
    let stem = design.file_stem().unwrap_or(design.as_os_str());
    let ext = match profile.kind {
        MachineKind::Svg => "svg",
        MachineKind::Laser | MachineKind::Router => "gcode",
    };
    PathBuf::from(stem).with_extension(ext)
}

/// What both kinds of build take from the options alike: the skin and toolpath settings,
/// the placement and the scale, each checked.
pub(super) struct Settings {
    pub(super) build: BuildOptions,
    pub(super) place: Place,
    pub(super) scale: Scale,
}

/// The checked `--margin`, `--scale`, `--fit`, `--place`, `--tolerance`, `--epsilon` and
/// `--method`.
pub(super) fn settings(a: &Args) -> Result<Settings> {
    if !(a.margin.is_finite() && a.margin >= 0.0) {
        bail!(
            "--margin must be a finite, non-negative distance in design units, got {}",
            a.margin
        );
    }
    if let Some(s) = a.scale
        && !(s.is_finite() && s > 0.0)
    {
        bail!("--scale {s}: must be a positive number");
    }
    let fit = a.fit.as_deref().map(parse_fit).transpose()?;
    if fit.is_some() && a.scale.is_some() {
        bail!("--fit and --scale both set the scale: give one of them");
    }
    let place = match a.place.as_str() {
        "design" => Place::Design,
        "center" => Place::Center,
        _ => Place::LowerLeft,
    };
    let mut build = BuildOptions::default();
    if let Some(t) = a.tolerance {
        build.tolerance = t;
    }
    if let Some(e) = a.epsilon {
        build.epsilon = e;
    }
    build.method = match a.method.as_str() {
        "re" => skinpath::design::OutlineMethod::Re,
        "mph" => skinpath::design::OutlineMethod::Mph,
        _ => skinpath::design::OutlineMethod::Skin,
    };
    let scale = match (a.scale, fit) {
        (Some(s), _) => Scale::By(s),
        (None, Some((width, height))) => Scale::Fit { width, height },
        (None, None) => Scale::None,
    };
    Ok(Settings {
        build,
        place,
        scale,
    })
}

/// The design's file stem, the job's name in program headers.
pub(super) fn job_name(design: &Path) -> String {
    design
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "skinpath".into())
}

/// Refuses `--bom` for a design without a `[neon]` table.
pub(super) fn check_bom(a: &Args, design: &skinpath::Design, file: &str) -> Result<()> {
    if a.bom.is_some() && design.neon.is_none() {
        bail!(
            "{file}: --bom needs a [neon] table in the design (the flex the bill of materials \
             is for): add `[neon]` with `flex = \"6mm\"` or `\"8mm\"`"
        );
    }
    Ok(())
}

pub fn run(a: Args) -> Result<u8> {
    let Some(machine) = a.machine.clone() else {
        return super::build_outputs::run(a);
    };
    let mut timings = Timings::default();
    let t_read = Instant::now();
    let profile = load_profile(&machine)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| default_output(&a.design, &profile));
    let format = format_of(&a, &output)?;
    let mut inputs: Vec<&Path> = vec![&a.design];
    let machine_path = PathBuf::from(&machine);
    if machine_path.exists() {
        inputs.push(&machine_path);
    }
    io::refuse_overwriting_inputs(&output, &inputs)?;
    if let Some(p) = &a.preview {
        io::refuse_overwriting_inputs(p, &inputs)?;
        if io::same_file(p, &output) {
            bail!(
                "--preview {} is the output file: give the preview its own name",
                p.display()
            );
        }
    }
    if let Some(p) = &a.bom {
        io::refuse_overwriting_inputs(p, &inputs)?;
        if io::same_file(p, &output) || a.preview.as_ref().is_some_and(|q| io::same_file(p, q)) {
            bail!(
                "--bom {} is another output of this run: give the bill of materials its own name",
                p.display()
            );
        }
    }
    let Settings {
        build,
        place,
        scale,
    } = settings(&a)?;
    let text = io::read_text(&a.design)?;
    let file = a.design.display().to_string();
    let (original, notes) = skinpath::design::load_noted(&text, &file)?;
    for n in &notes {
        eprintln!("{file}: {n}");
    }
    if !original.output.is_empty() {
        let names: Vec<&str> = original.output.iter().map(|o| o.name.as_str()).collect();
        bail!(
            "{file}: the design's [[output]] tables ({}) name their machines: leave out \
             --machine (build one of them with --only NAME)",
            names.join(", ")
        );
    }
    if !a.only.is_empty() {
        bail!("{file}: --only selects [[output]] tables, and the design has none");
    }
    check_bom(&a, &original, &file)?;
    timings.add(Stage::Read, t_read.elapsed());
    let name = job_name(&a.design);
    let bar = super::progress::Bar::new();
    let on_progress = |p: skinpath::job::Progress| bar.show(p);
    let mut options = JobOptions::default();
    options.build = build;
    options.place = place;
    options.margin = a.margin;
    options.scale = scale;
    options.format = format;
    options.name = &name;
    options.write_unchecked = a.write_unchecked;
    options.progress = bar.active().then_some(&on_progress);
    let job = Job::new(&original, &profile, options);
    let result = job.run();
    bar.finish();
    let out = match result {
        Ok(out) => out,
        Err(JobError::Unchecked {
            file,
            errors,
            explanations,
        }) => {
            for e in &explanations {
                eprintln!("{e}");
            }
            return Err(JobError::Unchecked {
                file,
                errors,
                explanations,
            }
            .into());
        }
        Err(e) => return Err(e.into()),
    };
    timings.extend(&out.timings);
    if !out.explanations.is_empty() {
        for e in &out.explanations {
            eprintln!("{e}");
        }
        eprintln!("skinpath: warning: writing a program that failed its checks");
    }
    let t_write = Instant::now();
    let mut outputs: Vec<(&Path, Vec<u8>)> = Vec::new();
    if let Some(p) = &a.preview {
        let scene = skinpath::job::scene_of_build(
            &name,
            &out.built.toolpath,
            &profile,
            out.design.units.mm_per_unit(),
            (format == OutputFormat::Gcode).then_some(out.program.as_str()),
            false,
        );
        outputs.push((p, super::preview::render(p, &scene, Default::default())?));
    }
    if let (Some(p), Some(bom)) = (&a.bom, &out.built.neon) {
        outputs.push((p, bom.to_csv().into_bytes()));
    }
    outputs.insert(0, (&output, out.program.clone().into_bytes()));
    io::write_set(&outputs)?;
    timings.add(Stage::Write, t_write.elapsed());
    let mut text = String::new();
    if a.json {
        let mut summary = out.summary(&profile);
        summary.outputs = outputs
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect();
        let mut v = serde_json::to_value(&summary)?;
        if a.timings
            && let Some(m) = v.as_object_mut()
        {
            m.insert("timings".into(), timings.to_json());
        }
        writeln!(text, "{}", serde_json::to_string_pretty(&v)?)?;
    } else {
        print_job(&mut text, &out, &profile, out.built.neon.as_ref())?;
        for (p, _) in &outputs {
            writeln!(text, "wrote {}", p.display())?;
        }
        if a.timings {
            eprint!("{}", timings.table());
        }
    }
    crate::print_stdout(&text)?;
    Ok(0)
}

/// The text summary of one built job: placement, operations, lengths, time, skin notes,
/// the neon bill of materials `bom` (when given), routes, ordering and the check.
pub(super) fn print_job(
    text: &mut String,
    out: &JobOutput,
    profile: &Profile,
    bom: Option<&skinpath::job::NeonBom>,
) -> Result<()> {
    let placement = &out.placement;
    let scale = placement.scale;
    writeln!(
        text,
        "placed ({}): moved by ({:.3}, {:.3}); job x {:.3}..{:.3} y {:.3}..{:.3}{}",
        placement.place.as_str(),
        placement.offset[0],
        placement.offset[1],
        placement.min[0],
        placement.max[0],
        placement.min[1],
        placement.max[1],
        if scale != 1.0 {
            format!(", design scaled by {scale:.6}")
        } else {
            String::new()
        }
    )?;
    let time = out.report.as_ref().map(|r| r.stats.time.total);
    print_summary(text, &out.built.toolpath, profile, time)?;
    if out.built.re_skin_seconds > 0.0 {
        writeln!(
            text,
            "  re/mph skins: {:.1} ms",
            1e3 * out.built.re_skin_seconds
        )?;
    }
    for o in &out.built.outlines {
        if let Some(u) = o.disk_union {
            writeln!(
                text,
                "  outline {}: the skin cut {:.3} into the stroke near ({:.3}, {:.3}) (no \
                 admissible circle follows the bend); built on the union of its disks",
                o.name, u.depth, u.at.x, u.at.y
            )?;
        }
    }
    if let Some(bom) = bom {
        print_bom(text, bom)?;
    }
    let repaired: Vec<_> = (out.built.outlines.iter())
        .filter_map(|o| o.repair.as_ref().map(|r| (o, r)))
        .collect();
    for (o, r) in &repaired {
        writeln!(
            text,
            "  outline {}: split {} time(s), {} piece(s) on the union of their disks, within \
             {:.4} of its disks ({})",
            o.name,
            r.splits.len(),
            r.fallbacks.len(),
            r.deviation,
            r.splits
                .first()
                .map(|s| s.reason.as_str())
                .or_else(|| r.fallbacks.first().map(|f| f.reason.as_str()))
                .unwrap_or_default()
        )?;
    }
    if let Some((worst, r)) = repaired
        .iter()
        .max_by(|a, b| a.1.deviation.total_cmp(&b.1.deviation))
    {
        writeln!(
            text,
            "  skin: {} of {} stroke(s) could not be skinned as one piece: {} split(s), {} \
             piece(s) on disk unions; worst deviation {:.4} ({})",
            repaired.len(),
            out.design.stroke.len(),
            repaired.iter().map(|(_, r)| r.splits.len()).sum::<usize>(),
            repaired
                .iter()
                .map(|(_, r)| r.fallbacks.len())
                .sum::<usize>(),
            r.deviation,
            worst.name
        )?;
    }
    for w in &out.built.warnings {
        writeln!(text, "  warning ({}): {}", w.operation, w.message)?;
    }
    for r in &out.built.routes {
        writeln!(
            text,
            "  route {}: {} ({} arcs, {} lines, {:.1} ms; {})",
            r.operation,
            r.route,
            r.counts.arcs,
            r.counts.lines,
            1e3 * r.seconds,
            r.detail
        )?;
    }
    for s in &out.built.stats {
        if s.order.travel_input > 0.0 {
            writeln!(
                text,
                "  ordering {}: travel {:.1} -> {:.1} ({:.0} % of input order)",
                s.operation,
                s.order.travel_input,
                s.order.travel_ordered,
                100.0 * s.order.travel_ordered / s.order.travel_input
            )?;
        }
    }
    if let Some(r) = &out.report {
        writeln!(
            text,
            "check: {} errors, {} warnings",
            r.errors_in_all(),
            r.warnings_in_all()
        )?;
    }
    Ok(())
}

fn print_summary(
    text: &mut String,
    tp: &skinpath::Toolpath,
    profile: &Profile,
    time: Option<f64>,
) -> std::fmt::Result {
    let s = tp.stats(glam::DVec2::ZERO);
    writeln!(text, "machine {} ({:?})", profile.name, profile.kind)?;
    for op in &tp.operations {
        writeln!(text, "  {:24} {:4} cuts", op.name, op.cuts.len())?;
    }
    writeln!(
        text,
        "cut length {:.1}, travel {:.1}, bounds x {:.2}..{:.2} y {:.2}..{:.2} z {:.2}..{:.2}",
        s.cut_length,
        s.travel_length,
        s.bbox_min[0],
        s.bbox_max[0],
        s.bbox_min[1],
        s.bbox_max[1],
        s.bbox_min[2],
        s.bbox_max[2]
    )?;
    match time {
        Some(t) => writeln!(text, "estimated time {} (with acceleration)", hms(t)),
        None => writeln!(text, "time at programmed feeds {}", hms(s.cut_time)),
    }
}

/// Neon warnings printed in the text summary: a polyline font's word has dozens of
/// corners; past this many the summary says how many more `--json` lists.
const MAX_NEON_WARNINGS: usize = 40;

/// The neon bill of materials: one line per run, the totals and the warnings.
pub(super) fn print_bom(text: &mut String, bom: &skinpath::job::NeonBom) -> std::fmt::Result {
    writeln!(
        text,
        "neon: {} runs of {:.0} mm flex, {:.1} mm in total, order {:.0} mm (cut unit {:.0} \
         mm), {} wire holes",
        bom.runs.len(),
        bom.flex.width_mm,
        bom.total_length_mm,
        bom.total_cut_length_mm,
        bom.flex.cut_unit_mm,
        bom.holes
    )?;
    for r in &bom.runs {
        writeln!(
            text,
            "  {}{}: {} strokes, {:.1} mm (cut {:.0} mm), tightest bend {} at \"{}\" ({:.2}, \
             {:.2})",
            r.name,
            if r.closed { " (closed)" } else { "" },
            r.strokes.len(),
            r.length_mm,
            r.cut_length_mm,
            if r.min_bend_radius_mm.is_finite() {
                format!("{:.2} mm", r.min_bend_radius_mm)
            } else {
                "none (straight)".into()
            },
            r.at.stroke,
            r.at.x,
            r.at.y
        )?;
    }
    for w in bom.warnings.iter().take(MAX_NEON_WARNINGS) {
        writeln!(text, "  warning ({}): {}", w.kind, w.message)?;
    }
    if bom.warnings.len() > MAX_NEON_WARNINGS {
        writeln!(
            text,
            "  ... and {} more neon warnings (`--json` lists every one)",
            bom.warnings.len() - MAX_NEON_WARNINGS
        )?;
    }
    Ok(())
}

fn hms(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
}
