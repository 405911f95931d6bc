//! `skinpath build DESIGN --machine NAME|PATH [-o OUT]`: machine output from a design.
//!
//! The output format follows the extension (.gcode/.nc/.ngc/.tap G-code, .svg laser SVG,
//! .dxf DXF) or `--format`. G-code is read back by the checker before it is written; a
//! program with findings of error severity is refused unless `--write-unchecked` is given.

use super::io;
use anyhow::{Context, Result, bail};
use skinpath::emit::{
    DxfOptions, GcodeOptions, LaserSvgOptions, dxf, gcode_with_origins, laser_svg,
};
use skinpath::job::build::{
    BuildOptions, Place, build_toolpath, fit_scale, outline_bounds, place_job, scaled_design,
};
use skinpath::job::check::{check_config, design_boundaries};
use skinpath::machine::{MachineKind, Profile, builtin_profile};
use skinpath::sim::{Backend, Severity, check_text};
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The design file (.toml or .json).
    design: PathBuf,
    /// Machine profile: a shipped name (see `skinpath machines`) or a path to a .toml.
    #[arg(short, long)]
    machine: String,
    /// Output file (.gcode, .nc, .ngc, .tap, .svg or .dxf); default: the design's name in the
    /// current folder, with .gcode for G-code machines and .svg for SVG laser profiles.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Output format, when the extension does not say it.
    #[arg(long, value_parser = ["gcode", "svg", "dxf"])]
    format: Option<String>,
    /// Arc fitting tolerance of the toolpath, in design units.
    #[arg(long)]
    tolerance: Option<f64>,
    /// Skin approximation accuracy ε, in design units.
    #[arg(long)]
    epsilon: Option<f64>,
    /// Skin route of profiles and backboards: `skin` (Bézier skin, general offsets), `re` or
    /// `mph` (exact MAT offsets of RE/MPH skins). An operation's own `method` wins.
    #[arg(long, value_parser = ["skin", "re", "mph"], default_value = "skin")]
    method: String,
    /// Also write a preview here: .svg or .png drawing, or .html player (see `preview`);
    /// written only together with the output, and never to the output's own path.
    #[arg(long)]
    preview: Option<PathBuf>,
    /// Where the job goes on the machine (G-code, laser SVG and DXF alike): `lower-left`
    /// (the default) puts the job's lower-left corner, tool paths included, at the work
    /// area's lower-left corner plus `--margin`; `center` centres it in the work area;
    /// `design` keeps the design's coordinates.
    #[arg(long, value_parser = ["design", "lower-left", "center"], default_value = "lower-left")]
    place: String,
    /// Distance from the work area's corner with `--place lower-left`, in design units.
    #[arg(long, default_value_t = 0.0)]
    margin: f64,
    /// Scale the design's strokes and circles by this factor before building (channel
    /// widths, hole diameters, depths and margins stay as written).
    #[arg(long)]
    scale: Option<f64>,
    /// Scale the design uniformly (aspect kept) so the job fits W x H design units, e.g.
    /// `--fit 200x150`.
    #[arg(long, value_name = "WxH")]
    fit: Option<String>,
    /// Print the summary (operations, lengths, bounds, placement, time, findings) as JSON.
    #[arg(long)]
    json: bool,
    /// Write the G-code even when the checker finds errors. It may then gouge the part,
    /// leave the laser or spindle on during a rapid, or leave the machine's travel.
    #[arg(long)]
    write_unchecked: bool,
}

/// A shipped profile by name, or a user's profile file.
pub fn load_profile(spec: &str) -> Result<Profile> {
    if let Some(p) = builtin_profile(spec) {
        return Ok(p?);
    }
    let path = Path::new(spec);
    if path.exists() {
        let text = io::read_text(path)?;
        return Ok(Profile::from_toml(&text, &path.display().to_string())?);
    }
    bail!("no machine profile named {spec:?} (see `skinpath machines`) and no such file")
}

fn format_of(a: &Args, output: &Path) -> Result<String> {
    if let Some(f) = &a.format {
        return Ok(f.clone());
    }
    Ok(match io::extension(output).as_str() {
        "gcode" | "nc" | "ngc" | "tap" | "g" => "gcode".into(),
        "svg" => "svg".into(),
        "dxf" => "dxf".into(),
        other => bail!(
            "{}: cannot tell the output format from .{other}; use --format gcode|svg|dxf",
            output.display()
        ),
    })
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

/// What to change for each kind of checker finding in a program `build` made.
fn advice(id: &str) -> &'static str {
    match id {
        "self-intersection" => {
            "the cut folds onto itself where the outline offset by the tool radius \
             collapses: move the stroke's disks apart there, widen the channel or use a \
             smaller tool, and please report the design"
        }
        "contour-crossing" => {
            "two cuts that must stay apart cross: move the strokes apart, or give the \
             operations `strokes = [...]` so they do not both cut here"
        }
        "gouge" => {
            "the tool comes nearer the design than its radius: lower --tolerance or use a \
             smaller tool"
        }
        "out-of-bounds" => "use --place lower-left or --place center, or --fit to scale down",
        "feed-out-of-range" => "set the operation's `feed` within the machine's range",
        "power-out-of-range" => "set the operation's `power` within 0..=100 percent",
        _ => "see the finding's id in `skinpath check --help`",
    }
}

/// A checker finding of the program traced back to what the design says: the operation
/// (its kind, name and number in the design), the stroke and the place.
fn explain(
    f: &skinpath::sim::Finding,
    origins: &[skinpath::emit::LineOrigin],
    tp: &skinpath::toolpath::Toolpath,
    file: &str,
) -> String {
    // Every distinct operation and stroke among the finding's lines (a crossing has two).
    let mut whos: Vec<String> = Vec::new();
    for (oi, ci) in f
        .lines
        .iter()
        .filter_map(|&l| origins.get(l.wrapping_sub(1)).copied().flatten())
    {
        let Some(op) = tp.operations.get(oi) else {
            continue;
        };
        let mut w = match op.design_index {
            Some(d) => format!("[[operation]] {} ({})", d + 1, op.name),
            None => format!("the default {} (the design has no [[operation]])", op.name),
        };
        if let Some(src) = op.cuts.get(ci).and_then(|c| c.source.as_ref()) {
            w.push_str(&format!(", stroke \"{src}\""));
        }
        if !whos.contains(&w) {
            whos.push(w);
        }
    }
    let who = if whos.is_empty() {
        String::new()
    } else {
        format!("{}: ", whos.join(" and "))
    };
    let at =
        f.at.first()
            .map(|p| format!(" at x {:.3} y {:.3} z {:.3}", p[0], p[1], p[2]))
            .unwrap_or_default();
    let lines: Vec<String> = f.lines.iter().map(|l| l.to_string()).collect();
    format!(
        "{file}: {who}{} [{}]{at} (program line {}): {}",
        f.message,
        f.id,
        lines.join(", "),
        advice(f.id)
    )
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

pub fn run(a: Args) -> Result<u8> {
    let profile = load_profile(&a.machine)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| default_output(&a.design, &profile));
    let format = format_of(&a, &output)?;
    let mut inputs: Vec<&Path> = vec![&a.design];
    let machine_path = PathBuf::from(&a.machine);
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
    let text = io::read_text(&a.design)?;
    let file = a.design.display().to_string();
    let original = skinpath::design::load(&text, &file)?;
    let mut opts = BuildOptions::default();
    if let Some(t) = a.tolerance {
        opts.tolerance = t;
    }
    if let Some(e) = a.epsilon {
        opts.epsilon = e;
    }
    opts.method = match a.method.as_str() {
        "re" => skinpath::design::OutlineMethod::Re,
        "mph" => skinpath::design::OutlineMethod::Mph,
        _ => skinpath::design::OutlineMethod::Skin,
    };
    let mut scale = a.scale.unwrap_or(1.0);
    let mut design = if scale != 1.0 {
        scaled_design(&original, scale)
    } else {
        original.clone()
    };
    let mut built = build_toolpath(&design, &profile, &opts)?;
    if let Some((w, h)) = fit {
        // The outlines scale with the design, offsets and margins do not: a few rounds.
        for _ in 0..4 {
            let s = built.toolpath.stats(glam::DVec2::ZERO);
            let job =
                glam::DVec2::new(s.bbox_max[0] - s.bbox_min[0], s.bbox_max[1] - s.bbox_min[1]);
            if job.x <= w && job.y <= h && scale != 1.0 {
                break;
            }
            let Some((lo, hi)) = outline_bounds(&built.outlines, opts.tolerance) else {
                break;
            };
            let Some(f) = fit_scale(job, hi - lo, w, h) else {
                bail!(
                    "--fit {w}x{h}: the job's fixed parts (tool offsets, margins) alone are \
                     {:.1} x {:.1}; give a larger size",
                    job.x - (hi - lo).x,
                    job.y - (hi - lo).y
                );
            };
            // A hair smaller than exact, so the rounded program stays inside.
            scale *= f * (1.0 - 1e-6);
            design = scaled_design(&original, scale);
            built = build_toolpath(&design, &profile, &opts)?;
        }
    }
    let decimals = profile.gcode_settings().map(|g| g.decimals).unwrap_or(3);
    let k = profile.units.mm_per_unit() / design.units.mm_per_unit();
    // One unit of the program's last decimal, so that coordinate rounding cannot put an
    // arc's extreme point a hair outside the work area.
    let inset = 10f64.powi(-(decimals as i32)) * k;
    let placement = place_job(
        &mut built,
        &profile,
        design.units.mm_per_unit(),
        place,
        a.margin,
        inset,
        scale,
    )?;
    let units = match design.units {
        skinpath::design::Units::Mm => skinpath::machine::Units::Mm,
        skinpath::design::Units::Inch => skinpath::machine::Units::Inch,
    };
    let job = a
        .design
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "skinpath".into());
    let mut report = None;
    let body = match format.as_str() {
        "gcode" => {
            if profile.kind == MachineKind::Svg {
                bail!(
                    "profile {:?} is for SVG/DXF upload; choose a G-code profile or write .svg/.dxf",
                    profile.name
                );
            }
            let (g, origins) = gcode_with_origins(
                &built.toolpath,
                &profile,
                &GcodeOptions {
                    job: job.clone(),
                    input_units: units,
                    tolerance: opts.tolerance * 0.1,
                    check_work_area: true,
                },
            )?;
            // Read the program back and check it before it reaches a machine, exactly as
            // `skinpath check PROGRAM --machine SAME` will: same configuration, no
            // allowances (pockets mark their own intended crossings in the program).
            let tool_r = profile.default_tool().map(|t| t.radius()).unwrap_or(0.0);
            let mut cfg = check_config(&profile, tool_r);
            // With design boundaries the tool path may come closer to the design than the
            // tool radius by the errors this build allows itself: arc fitting of the outline
            // and the boundary's flattening (each `tolerance`, in design units), coordinate
            // rounding and the checker's own arc flattening.
            let kk = design.units.mm_per_unit() / profile.units.mm_per_unit();
            cfg.gouge_tolerance = cfg.gouge_tolerance.max(
                2.0 * opts.tolerance * kk + 10f64.powi(-(decimals as i32)) + cfg.flatten_tolerance,
            );
            let only_outside_profiles =
                design.operation.is_empty() && profile.kind == MachineKind::Router;
            let bounds = if only_outside_profiles {
                design_boundaries(
                    &built.outlines,
                    true,
                    opts.tolerance,
                    design.units.mm_per_unit(),
                )
            } else {
                Vec::new()
            };
            let r = check_text(Backend::Builtin, &g, &cfg, &bounds);
            if r.errors() > 0 {
                for f in r.findings.iter().filter(|f| f.severity == Severity::Error) {
                    eprintln!("{}", explain(f, &origins, &built.toolpath, &file));
                }
                if !a.write_unchecked {
                    bail!(
                        "{file}: the program failed {} check(s) (listed above with the operation \
                         and stroke that made each); nothing was written (--write-unchecked \
                         writes it anyway, at the risk named above)",
                        r.errors()
                    );
                }
                eprintln!("skinpath: warning: writing a program that failed its checks");
            }
            report = Some(r);
            g
        }
        "svg" => laser_svg(
            &built.toolpath,
            &profile,
            &LaserSvgOptions {
                job: job.clone(),
                ..LaserSvgOptions::default()
            },
        )?,
        _ => dxf(
            &built.toolpath,
            &DxfOptions {
                colors: profile.svg.as_ref().map(|s| s.colors.clone()),
                ..DxfOptions::default()
            },
        )?,
    };
    let body_text = body;
    let mut outputs: Vec<(&Path, Vec<u8>)> = Vec::new();
    if let Some(p) = &a.preview {
        let scene = super::preview::scene_of_build(
            &job,
            &built.toolpath,
            &profile,
            design.units.mm_per_unit(),
            (format == "gcode").then_some(body_text.as_str()),
            false,
        );
        outputs.push((p, super::preview::render(p, &scene, Default::default())?));
    }
    outputs.insert(0, (&output, body_text.into_bytes()));
    io::write_set(&outputs)?;
    let time = report.as_ref().map(|r| r.stats.time.total);
    if a.json {
        let v = summary_json(
            &built,
            &profile,
            &placement,
            time,
            report.as_ref(),
            &a,
            &output,
        );
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        println!(
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
        );
        print_summary(&built.toolpath, &profile, time);
        for r in &built.routes {
            println!(
                "  route {}: {} ({} arcs, {} lines; {})",
                r.operation, r.route, r.counts.arcs, r.counts.lines, r.detail
            );
        }
        for s in &built.stats {
            if s.order.travel_input > 0.0 {
                println!(
                    "  ordering {}: travel {:.1} -> {:.1} ({:.0} % of input order)",
                    s.operation,
                    s.order.travel_input,
                    s.order.travel_ordered,
                    100.0 * s.order.travel_ordered / s.order.travel_input
                );
            }
        }
        if let Some(r) = &report {
            println!("check: {} errors, {} warnings", r.errors(), r.warnings());
        }
        for (p, _) in &outputs {
            println!("wrote {}", p.display());
        }
    }
    Ok(0)
}

/// The preview SVG of the toolpath (the one place that renders previews for `build`).
/// The `--json` summary.
fn summary_json(
    built: &skinpath::job::build::BuildResult,
    profile: &Profile,
    placement: &skinpath::job::build::Placement,
    time: Option<f64>,
    report: Option<&skinpath::sim::Report>,
    a: &Args,
    output: &Path,
) -> serde_json::Value {
    let s = built.toolpath.stats(glam::DVec2::ZERO);
    let ops: Vec<serde_json::Value> = built
        .toolpath
        .operations
        .iter()
        .map(|op| {
            let single = skinpath::toolpath::Toolpath {
                operations: vec![op.clone()],
            };
            let os = single.stats(glam::DVec2::ZERO);
            serde_json::json!({
                "name": op.name,
                "kind": format!("{:?}", op.kind).to_lowercase(),
                "design_index": op.design_index,
                "cuts": op.cuts.len(),
                "cut_length": os.cut_length,
                "air_assist": op.air_assist,
            })
        })
        .collect();
    serde_json::json!({
        "design": a.design.display().to_string(),
        "machine": profile.name,
        "outputs": std::iter::once(output).chain(a.preview.as_deref()).map(|p| p.display().to_string()).collect::<Vec<_>>(),
        "operations": ops,
        "cut_length": s.cut_length,
        "travel_length": s.travel_length,
        "bounds": { "min": s.bbox_min, "max": s.bbox_max },
        "placement": placement,
        "time": {
            "with_acceleration": time,
            "at_programmed_feeds": s.cut_time,
        },
        "findings": report.map(|r| r.findings.clone()).unwrap_or_default(),
    })
}

fn print_summary(tp: &skinpath::toolpath::Toolpath, profile: &Profile, time: Option<f64>) {
    let s = tp.stats(glam::DVec2::ZERO);
    println!("machine {} ({:?})", profile.name, profile.kind);
    for op in &tp.operations {
        println!("  {:24} {:4} cuts", op.name, op.cuts.len());
    }
    println!(
        "cut length {:.1}, travel {:.1}, bounds x {:.2}..{:.2} y {:.2}..{:.2} z {:.2}..{:.2}",
        s.cut_length,
        s.travel_length,
        s.bbox_min[0],
        s.bbox_max[0],
        s.bbox_min[1],
        s.bbox_max[1],
        s.bbox_min[2],
        s.bbox_max[2]
    );
    match time {
        Some(t) => println!("estimated time {} (with acceleration)", hms(t)),
        None => println!("time at programmed feeds {}", hms(s.cut_time)),
    }
}

fn hms(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
}
