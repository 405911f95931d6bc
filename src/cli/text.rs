//! `skinpath text "OPEN" --height 80 --width 8 -o open.toml`: a design with one `[[text]]`
//! element, placed so that the lettering starts `--margin` in from the origin.

use super::io;
use anyhow::{Context, Result, bail};
use skinpath::Design;
use skinpath::design::text::{Align, Font, Kerning, layout_problem};
use skinpath::design::{FlexPreset, Format, MAX_COORD, Neon, Operation, Text, Units};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The text; `\n` (a backslash and n) starts a new line.
    text: String,
    /// Output design file (.toml or .json).
    #[arg(short, long)]
    output: PathBuf,
    /// Cap height (baseline to cap line), mm.
    #[arg(long, default_value_t = 40.0)]
    height: f64,
    /// Stroke width (neon flex or bit width), mm [default: 4; with --neon the flex width].
    #[arg(long)]
    width: Option<f64>,
    /// Font: sans (Hershey Roman Simplex) or script (joining letters); both have printable
    /// ASCII and the Latin-1 letters (é, ü, ñ, ß, ç, å, ...).
    #[arg(long, default_value = "sans", value_parser = ["sans", "script"])]
    font: String,
    /// Alignment of the lines.
    #[arg(long, default_value = "left", value_parser = ["left", "centre", "center", "right"])]
    align: String,
    /// Extra space between letters, mm.
    #[arg(long)]
    letter_spacing: Option<f64>,
    /// Baseline to baseline, in multiples of the height.
    #[arg(long)]
    line_spacing: Option<f64>,
    /// Kerning: auto (letter pairs such as AV, To, LT moved together from the glyphs'
    /// strokes) or none (advance widths only).
    #[arg(long, default_value = "auto", value_parser = ["auto", "none"])]
    kerning: String,
    /// Distance of the lettering (its strokes' edges) from the x and y axes, mm: room for a
    /// backboard or an outside cut without leaving the machine's work area.
    #[arg(long, default_value_t = 10.0)]
    margin: f64,
    /// Name of the text element (its strokes are NAME/...).
    #[arg(long, default_value = "text")]
    name: String,
    /// A neon sign: a `[neon]` table for this flex (6mm or 8mm; bare --neon: 6mm) and the
    /// channel, wire holes and backboard operations, sized by the flex.
    #[arg(long, num_args = 0..=1, default_missing_value = "6mm", value_parser = ["6mm", "8mm"])]
    neon: Option<String>,
}

/// Stroke width without --neon, mm.
const DEFAULT_WIDTH_MM: f64 = 4.0;

/// The operations of a neon sign, in cutting order: the channel for the flex, the wire
/// holes where runs end, the backboard around it all. Their sizes come from the `[neon]`
/// table when the design is loaded.
const NEON_OPERATIONS: [&str; 3] = ["channel", "holes", "backboard"];

/// The `[neon]` table and operations for the flex `preset` (`"6mm"` or `"8mm"`).
fn neon_parts(preset: &str) -> Result<(Neon, Vec<Operation>)> {
    let flex = if preset == "8mm" {
        FlexPreset::Mm8
    } else {
        FlexPreset::Mm6
    };
    let neon = Neon {
        flex: Some(flex),
        ..Neon::default()
    };
    let ops = NEON_OPERATIONS
        .iter()
        .map(|k| {
            toml::from_str::<Operation>(&format!("kind = \"{k}\""))
                .with_context(|| format!("the built-in {k} operation does not load"))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((neon, ops))
}

pub fn run(a: Args) -> Result<u8> {
    let format = Format::from_file_name(&a.output.display().to_string()).with_context(|| {
        format!(
            "{}: the output must end in .toml or .json",
            a.output.display()
        )
    })?;
    let neon = a.neon.as_deref().map(neon_parts).transpose()?;
    let width = match (&a.width, &neon) {
        (Some(w), _) => *w,
        (None, Some((n, _))) => n.flex(Units::Mm).width,
        (None, None) => DEFAULT_WIDTH_MM,
    };
    let mut t = Text::new(&a.name, &a.text.replace("\\n", "\n"), a.height, width);
    t.font = if a.font == "script" {
        Font::Script
    } else {
        Font::Sans
    };
    t.align = Some(match a.align.as_str() {
        "centre" | "center" => Align::Centre,
        "right" => Align::Right,
        _ => Align::Left,
    });
    t.letter_spacing = a.letter_spacing;
    t.line_spacing = a.line_spacing;
    t.kerning = (a.kerning == "none").then_some(Kerning::None);
    // Every option is checked before any layout, and named in the error (the design the
    // command writes is an implementation detail).
    if let Some(p) = t.problem() {
        bail!("{}: {}", option_of(p.key), p.message);
    }
    if !(a.margin.is_finite() && (0.0..=MAX_COORD).contains(&a.margin)) {
        bail!(
            "--margin: {} must be a distance from 0 to {MAX_COORD}",
            a.margin
        );
    }
    // Place the lettering's lower-left corner (stroke radius included) `margin` from the
    // origin, so it builds inside any machine's work area without --place.
    let r = 0.5 * width;
    let (min_x, min_y) = t
        .spine_layout(false)
        .iter()
        .flat_map(|(_, _, p)| p.iter().flatten())
        .fold((f64::INFINITY, f64::INFINITY), |(x, y), p| {
            (x.min(p.x), y.min(p.y))
        });
    if !(min_x.is_finite() && min_y.is_finite()) {
        bail!("the text has no visible character");
    }
    t.at = Some([a.margin + r - min_x, a.margin + r - min_y]);
    if let Some(p) = layout_problem(&t.spine_layout(true), r) {
        bail!(
            "{}: {} (--height, --line-spacing, --letter-spacing and --margin set its size)",
            option_of(p.key),
            p.message
        );
    }
    let design = Design {
        text: vec![t],
        operation: neon
            .as_ref()
            .map(|(_, ops)| ops.clone())
            .unwrap_or_default(),
        neon: neon.map(|(n, _)| n),
        ..Design::empty(&a.output.display().to_string())
    };
    let body = design.to_string_as(format)?;
    // What is written must load (and so build): check it before writing.
    skinpath::design::from_str(&body, format, &a.output.display().to_string())?;
    io::write_atomic(&a.output, body.as_bytes())
        .with_context(|| format!("writing {}", a.output.display()))?;
    Ok(0)
}

/// The option or argument of `skinpath text` that sets the `[[text]]` key `key`.
fn option_of(key: &str) -> &'static str {
    match key {
        "height" => "--height",
        "width" => "--width",
        "letter_spacing" => "--letter-spacing",
        "line_spacing" => "--line-spacing",
        "at" => "--margin",
        _ => "the text",
    }
}
