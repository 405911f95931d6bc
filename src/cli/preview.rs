//! `skinpath preview INPUT -o OUT.svg|OUT.png|OUT.html [--machine NAME]`: a picture or a
//! player of a design (built in memory for the machine, design placement) or of any G-code
//! program (read by the simulator). `build --preview` writes the same previews.
//!
//! A design with `[[output]]` tables previews each output (`--only NAME[,NAME]`: some of
//! them) for its own machine with its own operations, as `build` builds it, into
//! `OUT-STEM.NAME.OUT-EXT` beside OUT, written as a set; `--machine` then previews the whole
//! design on that machine instead (every operation, as before).

use super::build::load_profile;
use super::io;
use anyhow::{Context, Result, bail};
use skinpath::BuildOptions;
use skinpath::design::ErrorKind;
use skinpath::emit::{
    HtmlOptions, PngOptions, Scene, SvgOptions, player_html, scene_png, scene_svg,
};
use skinpath::job::{scene_of_design, scene_of_program};
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// A design (.toml or .json), an SVG drawing (.svg, imported as `build` imports it) or
    /// a G-code program (any other extension).
    input: PathBuf,
    /// Output file: .svg (drawing), .png (the same drawing as an image) or .html (player).
    #[arg(short, long)]
    output: PathBuf,
    /// Machine profile: a shipped name (see `skinpath machines`) or a .toml path. Required
    /// for designs; for G-code it sets the work area, limits and the time estimate.
    #[arg(short, long)]
    machine: Option<String>,
    /// PNG width in pixels (the height follows the drawing).
    #[arg(long, conflicts_with = "dpi")]
    width: Option<u32>,
    /// PNG resolution in pixels per inch of the drawing's millimetre size.
    #[arg(long)]
    dpi: Option<f64>,
    /// Arc fitting tolerance of the toolpath, in design units (designs only).
    #[arg(long)]
    tolerance: Option<f64>,
    /// Skin approximation accuracy ε, in design units (designs only).
    #[arg(long)]
    epsilon: Option<f64>,
    /// Designs with `[[output]]` tables: preview only these outputs (comma-separated
    /// names), each for its machine; without --machine.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
}

/// The preview format named by a file's extension.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Format {
    Svg,
    Png,
    Html,
}

pub fn format_of(path: &Path) -> Result<Format> {
    Ok(match io::extension(path).as_str() {
        "svg" => Format::Svg,
        "png" => Format::Png,
        "html" | "htm" => Format::Html,
        other => bail!(
            "{}: a preview is .svg, .png or .html, not .{other}",
            path.display()
        ),
    })
}

/// The preview of `scene` in the format `path`'s extension names.
pub fn render(path: &Path, scene: &Scene, png: PngOptions) -> Result<Vec<u8>> {
    Ok(match format_of(path)? {
        Format::Svg => scene_svg(scene, &SvgOptions::default()).into_bytes(),
        Format::Png => scene_png(scene, &SvgOptions::default(), png)?,
        Format::Html => player_html(scene, &HtmlOptions::default())?.into_bytes(),
    })
}

/// Writes the preview of `scene` to `path` in the format its extension names.
pub fn write(path: &Path, scene: &Scene, png: PngOptions) -> Result<()> {
    let bytes = render(path, scene, png)?;
    io::write_atomic(path, &bytes).with_context(|| format!("writing {}", path.display()))
}

fn png_options(a: &Args) -> Result<PngOptions> {
    Ok(match (a.width, a.dpi) {
        (Some(w), _) => PngOptions::Width(w),
        (None, Some(d)) => PngOptions::Dpi(d),
        (None, None) => PngOptions::default(),
    })
}

/// One preview per output of `design` (those `--only` names, else all), each for its own
/// machine with its own operations, `OUT-STEM.NAME.OUT-EXT` beside `--output`, written as
/// a set (all or none).
fn outputs(
    a: &Args,
    design: &skinpath::Design,
    title: &str,
    opts: &BuildOptions,
    png: PngOptions,
) -> Result<u8> {
    let file = a.input.display().to_string();
    if let Some(n) = (a.only.iter()).find(|n| !design.output.iter().any(|o| &o.name == *n)) {
        let names: Vec<&str> = design.output.iter().map(|o| o.name.as_str()).collect();
        bail!(
            "{file}: --only {n}: no [[output]] of that name; the design's outputs are {}",
            names.join(", ")
        );
    }
    let design_dir = a
        .input
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let stem = a
        .output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = io::extension(&a.output);
    let sized = (format_of(&a.output)? == Format::Png).then_some(png);
    let (mut paths, mut bytes) = (Vec::new(), Vec::new());
    let mut lines = String::new();
    for o in (design.output.iter()).filter(|o| a.only.is_empty() || a.only.contains(&o.name)) {
        let at = || format!("{file}: [[output]] \"{}\"", o.name);
        let (profile, profile_file) = super::build_outputs::output_profile(&o.machine, &design_dir)
            .with_context(|| format!("{}: machine {:?}", at(), o.machine))?;
        let path = a.output.with_file_name(format!("{stem}.{}.{ext}", o.name));
        let mut inputs: Vec<&Path> = vec![&a.input];
        inputs.extend(profile_file.as_deref());
        io::refuse_overwriting_inputs(&path, &inputs)?;
        let only = o.operations_of(design);
        let scene = skinpath::job::scene_of_design_of(
            &format!("{title} {}", o.name),
            design,
            &profile,
            opts,
            sized,
            only.as_deref(),
        )
        .with_context(at)?;
        lines.push_str(&format!(
            "wrote {} (output {}, machine {}: {} moves, {} contours, {} findings, time {})\n",
            path.display(),
            o.name,
            profile.name,
            scene.motions.len(),
            scene.contours.len(),
            scene.findings.len(),
            skinpath::emit::hms(scene.total_time)
        ));
        bytes.push(render(&path, &scene, png)?);
        paths.push(path);
    }
    let set: Vec<(&Path, Vec<u8>)> = paths.iter().map(PathBuf::as_path).zip(bytes).collect();
    io::write_set(&set)?;
    crate::print_stdout(&lines)?;
    Ok(0)
}

pub fn run(a: Args) -> Result<u8> {
    let format = format_of(&a.output)?;
    let mut inputs: Vec<&Path> = vec![&a.input];
    let machine_path = a.machine.as_ref().map(PathBuf::from);
    if let Some(m) = machine_path.as_ref().filter(|m| m.exists()) {
        inputs.push(m);
    }
    io::refuse_overwriting_inputs(&a.output, &inputs)?;
    let png = png_options(&a)?;
    // A PNG's size is checked from the program's bounds before the checker runs.
    let sized = (format == Format::Png).then_some(png);
    let title = a
        .input
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "preview".into());
    let profile = a.machine.as_deref().map(load_profile).transpose()?;
    let text = io::read_text(&a.input)?;
    let file = a.input.display().to_string();
    // The file kind is the design loader's (`build` reads its input the same way): .toml,
    // .json and .svg are designs, anything else is a program.
    let scene = match skinpath::design::load(&text, &file) {
        Err(e) if e.kind == ErrorKind::UnknownFormat => {
            scene_of_program(&title, &text, profile.as_ref(), sized)?
        }
        design => {
            let design = design?;
            let mut opts = BuildOptions::default();
            if let Some(t) = a.tolerance {
                opts.tolerance = t;
            }
            if let Some(e) = a.epsilon {
                opts.epsilon = e;
            }
            if !a.only.is_empty() && design.output.is_empty() {
                bail!("{file}: --only names outputs, and the design has no [[output]] tables");
            }
            if !a.only.is_empty() && profile.is_some() {
                bail!("{file}: --only previews outputs on their own machines: leave out --machine");
            }
            if profile.is_none() && !design.output.is_empty() {
                return outputs(&a, &design, &title, &opts, png);
            }
            let Some(profile) = profile else {
                bail!(
                    "{file}: a design previews for a machine; add --machine NAME (see `skinpath \
                     machines`)"
                );
            };
            scene_of_design(&title, &design, &profile, &opts, sized)?
        }
    };
    write(&a.output, &scene, png)?;
    if let Some(f) = scene.stopped() {
        eprintln!(
            "skinpath: warning: {}: the simulator stopped reading the program ({f}); the \
             preview shows the moves before that point",
            a.input.display()
        );
    }
    crate::print_stdout(&format!(
        "wrote {} ({} moves, {} contours, {} findings, time {})\n",
        a.output.display(),
        scene.motions.len(),
        scene.contours.len(),
        scene.findings.len(),
        skinpath::emit::hms(scene.total_time)
    ))?;
    Ok(0)
}
