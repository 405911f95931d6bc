//! `skinpath build DESIGN --machine NAME|PATH -o OUT`: machine output from a design.
//!
//! The output format follows the extension (.gcode/.nc/.ngc/.tap G-code, .svg laser SVG,
//! .dxf DXF) or `--format`. G-code is read back by the checker before it is written; a
//! program with findings of error severity is refused unless `--write-unchecked` is given.

use super::io;
use anyhow::{Context, Result, bail};
use skinpath::emit::{DxfOptions, GcodeOptions, LaserSvgOptions, dxf, gcode, laser_svg};
use skinpath::job::build::{BuildOptions, build_toolpath};
use skinpath::job::check::{check_config, design_boundaries};
use skinpath::machine::{MachineKind, Profile, builtin_profile};
use skinpath::sim::{Backend, check_text};
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The design file (.toml or .json).
    design: PathBuf,
    /// Machine profile: a shipped name (see `skinpath machines`) or a path to a .toml.
    #[arg(short, long)]
    machine: String,
    /// Output file (.gcode, .nc, .ngc, .tap, .svg or .dxf).
    #[arg(short, long)]
    output: PathBuf,
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
    /// Also write a preview SVG of the toolpath (cuts solid, rapids dashed) here.
    #[arg(long)]
    preview: Option<PathBuf>,
    /// Where the job goes on the machine: `design` keeps the design's coordinates;
    /// `lower-left` moves the job's lower-left corner (tool paths included) to the work
    /// area's lower-left corner plus `--margin` (and one unit of the last decimal, so
    /// rounding cannot push an arc over the edge).
    #[arg(long, value_parser = ["design", "lower-left"], default_value = "design")]
    place: String,
    /// Distance from the work area's corner with `--place lower-left`, in design units.
    #[arg(long, default_value_t = 0.0)]
    margin: f64,
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

fn format_of(a: &Args) -> Result<String> {
    if let Some(f) = &a.format {
        return Ok(f.clone());
    }
    Ok(match io::extension(&a.output).as_str() {
        "gcode" | "nc" | "ngc" | "tap" | "g" => "gcode".into(),
        "svg" => "svg".into(),
        "dxf" => "dxf".into(),
        other => bail!(
            "{}: cannot tell the output format from .{other}; use --format gcode|svg|dxf",
            a.output.display()
        ),
    })
}

pub fn run(a: Args) -> Result<u8> {
    let format = format_of(&a)?;
    let mut inputs: Vec<&Path> = vec![&a.design];
    let machine_path = PathBuf::from(&a.machine);
    if machine_path.exists() {
        inputs.push(&machine_path);
    }
    io::refuse_overwriting_inputs(&a.output, &inputs)?;
    if let Some(p) = &a.preview {
        io::refuse_overwriting_inputs(p, &inputs)?;
    }
    let profile = load_profile(&a.machine)?;
    let text = io::read_text(&a.design)?;
    let design = skinpath::design::load(&text, &a.design.display().to_string())?;
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
    let mut built = build_toolpath(&design, &profile, &opts)?;
    if a.place == "lower-left" {
        // Design units per profile unit: work area corners are in the profile's units.
        let k = profile.units.mm_per_unit() / design.units.mm_per_unit();
        let s = built.toolpath.stats(glam::DVec2::ZERO);
        // One unit of the program's last decimal more, so that coordinate rounding cannot
        // put an arc's extreme point a hair outside the work area.
        let decimals = profile.gcode_settings().map(|g| g.decimals).unwrap_or(3);
        let inset = 10f64.powi(-(decimals as i32)) * k;
        let target = glam::DVec2::new(profile.work_area.x.min(), profile.work_area.y.min()) * k
            + glam::DVec2::splat(a.margin + inset);
        let d = target - glam::DVec2::new(s.bbox_min[0], s.bbox_min[1]);
        built.toolpath = built.toolpath.translated(d);
        for o in &mut built.outlines {
            for p in &mut o.contours {
                *p = p.translated(d);
            }
        }
        println!("placed: moved by ({:.3}, {:.3})", d.x, d.y);
    }
    let units = match design.units {
        skinpath::design::Units::Mm => skinpath::machine::Units::Mm,
        skinpath::design::Units::Inch => skinpath::machine::Units::Inch,
    };
    let job = a
        .design
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "skinpath".into());
    let body = match format.as_str() {
        "gcode" => {
            if profile.kind == MachineKind::Svg {
                bail!(
                    "profile {:?} is for SVG/DXF upload; choose a G-code profile or write .svg/.dxf",
                    profile.name
                );
            }
            let g = gcode(
                &built.toolpath,
                &profile,
                &GcodeOptions {
                    job: job.clone(),
                    input_units: units,
                    tolerance: opts.tolerance * 0.1,
                    check_work_area: true,
                },
            )?;
            // Read the program back and check it before it reaches a machine.
            let tool_r = profile.default_tool().map(|t| t.radius()).unwrap_or(0.0);
            let mut cfg = check_config(&profile, tool_r);
            // The tool path may come closer to the design than the tool radius by the
            // errors this build allows itself: arc fitting of the outline and the boundary's
            // flattening (each `tolerance`, in design units), coordinate rounding and the
            // checker's own arc flattening.
            let k = design.units.mm_per_unit() / profile.units.mm_per_unit();
            let decimals = profile.gcode_settings().map(|g| g.decimals).unwrap_or(3);
            cfg.gouge_tolerance = cfg.gouge_tolerance.max(
                2.0 * opts.tolerance * k + 10f64.powi(-(decimals as i32)) + cfg.flatten_tolerance,
            );
            // Pockets, fills, holes and carvings overlap other cuts by design; only a job of
            // profiles must keep its contours apart.
            cfg.allow_crossings = design.operation.iter().any(|o| {
                !matches!(
                    o.kind,
                    skinpath::design::OperationKind::Profile
                        | skinpath::design::OperationKind::Backboard
                )
            });
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
            let report = check_text(Backend::Builtin, &g, &cfg, &bounds);
            if report.errors() > 0 {
                eprintln!("{report}");
                if !a.write_unchecked {
                    bail!(
                        "the checker found {} error(s) in the program; nothing was written \
                         (--write-unchecked writes it anyway, at the risk named above)",
                        report.errors()
                    );
                }
                eprintln!("skinpath: warning: writing a program that failed its checks");
            }
            print_summary(&built.toolpath, &profile, Some(report.stats.time.total));
            g
        }
        "svg" => {
            let s = laser_svg(
                &built.toolpath,
                &profile,
                &LaserSvgOptions {
                    job: job.clone(),
                    ..LaserSvgOptions::default()
                },
            )?;
            print_summary(&built.toolpath, &profile, None);
            s
        }
        _ => {
            let d = dxf(
                &built.toolpath,
                &DxfOptions {
                    colors: profile.svg.as_ref().map(|s| s.colors.clone()),
                    ..DxfOptions::default()
                },
            )?;
            print_summary(&built.toolpath, &profile, None);
            d
        }
    };
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
    if let Some(p) = &a.preview {
        let svg = skinpath::emit::preview_svg(
            &built.toolpath,
            &skinpath::emit::PreviewOptions::default(),
        )?;
        io::write_atomic(p, svg.as_bytes()).with_context(|| format!("writing {}", p.display()))?;
    }
    io::write_atomic(&a.output, body.as_bytes())
        .with_context(|| format!("writing {}", a.output.display()))?;
    println!("wrote {}", a.output.display());
    Ok(0)
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
