//! `skinpath import drawing.svg -o design.toml [--tolerance T] [--corner-angle DEG]`:
//! stroked SVG paths become strokes, filled ones shapes; every skipped element is listed on
//! stderr.

use super::io;
use anyhow::{Context, Result, bail};
use skinpath::design::{Format, HAIRLINE_MM, Operation, OperationKind, default_operations};
use skinpath::design::{ImportOptions, import};
use skinpath::job::DEFAULT_PROFILE_DEPTH_MM;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The SVG drawing.
    svg: PathBuf,
    /// Output design file (.toml or .json).
    #[arg(short, long)]
    output: PathBuf,
    /// Largest distance between a stroke's spine and the SVG centre line, mm.
    #[arg(long, default_value_t = skinpath::design::DEFAULT_IMPORT_TOLERANCE)]
    tolerance: f64,
    /// Turning angle in degrees above which a path node is kept as a corner.
    #[arg(long, default_value_t = skinpath::design::CORNER_ANGLE_DEG)]
    corner_angle: f64,
}

pub fn run(a: Args) -> Result<u8> {
    let out_name = a.output.display().to_string();
    let format = Format::from_file_name(&out_name)
        .with_context(|| format!("{out_name}: the output must end in .toml or .json"))?;
    if !(a.corner_angle.is_finite() && a.corner_angle > 0.0 && a.corner_angle < 180.0) {
        bail!(
            "--corner-angle must be between 0 and 180 degrees, got {}",
            a.corner_angle
        );
    }
    io::refuse_overwriting_inputs(&a.output, &[&a.svg])?;
    let text = io::read_text(&a.svg)?;
    let opts = ImportOptions::default()
        .with_tolerance(a.tolerance)
        .with_corner_angle(a.corner_angle);
    let imported = import(&text, &a.svg.display().to_string(), &opts)?;
    for s in &imported.skipped {
        eprintln!("skipped {}: {}", s.id, s.reason);
    }
    for w in &imported.warnings {
        eprintln!("warning: {}: {}", w.id, w.reason);
    }
    for line in found_per_layer_and_colour(&imported.design) {
        eprintln!("{line}");
    }
    let mut design = imported.design;
    design.file = out_name.clone();
    // The operations `build` would choose for this drawing, written out so that the user
    // sees and edits them: hairlines as lines, wider strokes and fills profiled (with the
    // router depth `build` gives a drawing without operations; lasers ignore depth).
    design.operation = default_operations(&design, HAIRLINE_MM / design.units.mm_per_unit());
    for op in &mut design.operation {
        if op.kind == OperationKind::Profile {
            op.depth = Some(DEFAULT_PROFILE_DEPTH_MM / design.units.mm_per_unit());
        }
        eprintln!("operation {}", describe(op));
    }
    let body = design.to_string_as(format)?;
    // What is written must load: check it before writing.
    skinpath::design::from_str(&body, format, &out_name)?;
    io::write_atomic(&a.output, body.as_bytes()).with_context(|| format!("writing {out_name}"))?;
    eprintln!(
        "imported {} stroke(s){}, {} skipped, spines within {:.4} mm of the SVG centre lines",
        design.stroke.len(),
        match design.shape.len() {
            0 => String::new(),
            n => format!(" and {n} filled shape(s)"),
        },
        imported.skipped.len(),
        imported.max_deviation
    );
    Ok(0)
}

/// An operation as `import` reports it: its kind and what it selects.
fn describe(op: &Operation) -> String {
    let list = |key: &str, v: &Option<Vec<String>>| {
        v.as_ref().map(|v| match v.len() {
            1 => format!("{key} = [\"{}\"]", v[0]),
            n => format!("{n} {key}"),
        })
    };
    let selects = [
        list("layers", &op.layers),
        list("colors", &op.colors),
        list("strokes", &op.strokes),
    ]
    .into_iter()
    .flatten()
    .collect::<Vec<_>>();
    let kind = match op.boundaries {
        Some(_) => format!("{} (boundaries between colours inside)", op.kind.as_str()),
        None => op.kind.as_str().to_string(),
    };
    match selects.is_empty() {
        true => format!("{kind}: every item"),
        false => format!("{kind}: {}", selects.join(", ")),
    }
}

/// One line per layer and colour: how many strokes (with their length along the points)
/// and filled shapes the import found there.
fn found_per_layer_and_colour(d: &skinpath::Design) -> Vec<String> {
    use std::collections::BTreeMap;
    // (strokes, their length in mm, shapes)
    let mut groups: BTreeMap<(String, String), (usize, f64, usize)> = BTreeMap::new();
    let key = |layer: &Option<String>, color: &Option<String>| {
        (
            layer
                .as_deref()
                .map_or("(no layer)".to_string(), |l| format!("layer \"{l}\"")),
            color
                .clone()
                .unwrap_or_else(|| "no solid colour".to_string()),
        )
    };
    for s in &d.stroke {
        let g = groups.entry(key(&s.layer, &s.color)).or_default();
        g.0 += 1;
        if let Some(p) = &s.points {
            g.1 += p
                .windows(2)
                .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                .sum::<f64>();
        }
    }
    for s in &d.shape {
        groups.entry(key(&s.layer, &s.color)).or_default().2 += 1;
    }
    groups
        .into_iter()
        .map(|((layer, color), (strokes, length, fills))| {
            format!("{layer}, {color}: {strokes} stroke(s) ({length:.1} mm), {fills} fill(s)")
        })
        .collect()
}
