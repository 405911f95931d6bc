//! A preview of a toolpath as SVG: cuts solid (coloured by operation kind), rapids and
//! travels dashed, a marker at the start of every cut. Page in mm, y up as in the design.

use super::geometry::{contours, validate};
use super::laser_svg::{PageFrame, color_of, path_data};
use super::{EmitError, check_tolerance, fnum, xml_escape};
use crate::machine::OperationColors;
use crate::toolpath::{MoveKind, Toolpath};
use glam::DVec2;
use std::fmt::Write;

/// Options of [`preview_svg`].
#[derive(Clone, Debug, PartialEq)]
pub struct PreviewOptions {
    /// Margin around the drawing, mm.
    pub margin: f64,
    /// Stroke width of cuts, mm (rapids are drawn at half of it).
    pub stroke_width: f64,
    /// Radius of the start markers, mm.
    pub marker_radius: f64,
    /// Draw rapids (dashed).
    pub rapids: bool,
    /// Colours per operation kind.
    pub colors: OperationColors,
    /// Largest arc radius mismatch accepted (mm).
    pub tolerance: f64,
}

impl Default for PreviewOptions {
    fn default() -> Self {
        PreviewOptions {
            margin: 2.0,
            stroke_width: 0.2,
            marker_radius: 0.5,
            rapids: true,
            colors: OperationColors {
                profile: "#d62728".into(),
                channel: "#1f77b4".into(),
                backboard: "#9467bd".into(),
                holes: "#ff7f0e".into(),
                fill: "#2c2c2c".into(),
                vcarve: "#17becf".into(),
            },
            tolerance: crate::geom::tol::FLATTEN,
        }
    }
}

/// Colour of rapid moves and start markers.
const RAPID_COLOR: &str = "#7f7f7f";
const START_COLOR: &str = "#2ca02c";

/// The rapid travels of `tp` as (from, to) pairs: the move to each cut's start from where
/// the previous cut ended, and rapids inside cuts. The first travel starts at the origin.
pub fn travels(tp: &Toolpath) -> Vec<(DVec2, DVec2)> {
    let mut out = Vec::new();
    let mut pos = DVec2::ZERO;
    for op in &tp.operations {
        for cut in &op.cuts {
            let s = cut.start.truncate();
            if s != pos {
                out.push((pos, s));
            }
            pos = s;
            for m in &cut.moves {
                if matches!(m.kind, MoveKind::Dwell { .. }) {
                    continue;
                }
                if m.kind == MoveKind::Rapid && m.to.truncate() != pos {
                    out.push((pos, m.to.truncate()));
                }
                pos = m.to.truncate();
            }
        }
    }
    out
}

/// The preview SVG of `tp`.
pub fn preview_svg(tp: &Toolpath, opts: &PreviewOptions) -> Result<String, EmitError> {
    check_tolerance("tolerance", opts.tolerance)?;
    for (name, v) in [
        ("margin", opts.margin),
        ("stroke_width", opts.stroke_width),
        ("marker_radius", opts.marker_radius),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(EmitError::InvalidOption {
                name,
                reason: format!("must be >= 0, got {v}"),
            });
        }
    }
    validate(tp, opts.tolerance)?;
    let cs = contours(tp);
    let trav = if opts.rapids { travels(tp) } else { Vec::new() };
    let starts: Vec<DVec2> = tp
        .operations
        .iter()
        .flat_map(|op| op.cuts.iter().map(|c| c.start.truncate()))
        .collect();
    let mut pts: Vec<DVec2> = trav.iter().flat_map(|(a, b)| [*a, *b]).collect();
    pts.extend(&starts);
    let frame = PageFrame::around(&cs, &pts, opts.margin + opts.marker_radius);
    let mut o = String::new();
    o.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n");
    let _ = writeln!(
        o,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{w}mm\" \
         height=\"{h}mm\" viewBox=\"0 0 {w} {h}\">",
        w = fnum(frame.width),
        h = fnum(frame.height)
    );
    let sw = fnum(opts.stroke_width);
    if !trav.is_empty() {
        let _ = writeln!(
            o,
            "<g id=\"rapids\" fill=\"none\" stroke=\"{RAPID_COLOR}\" stroke-width=\"{}\" \
             stroke-dasharray=\"{} {}\">",
            fnum(0.5 * opts.stroke_width),
            fnum(4.0 * opts.stroke_width),
            fnum(2.0 * opts.stroke_width)
        );
        for (a, b) in &trav {
            let (p, q) = (frame.map(*a), frame.map(*b));
            let _ = writeln!(
                o,
                "<line class=\"rapid\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/>",
                fnum(p.x),
                fnum(p.y),
                fnum(q.x),
                fnum(q.y)
            );
        }
        o.push_str("</g>\n");
    }
    for (oi, op) in tp.operations.iter().enumerate() {
        let color = color_of(&opts.colors, op.kind);
        let _ = writeln!(
            o,
            "<g id=\"op{oi}\" data-name=\"{}\" fill=\"none\" stroke=\"{color}\" \
             stroke-width=\"{sw}\" stroke-linecap=\"round\" stroke-linejoin=\"round\">",
            xml_escape(&op.name)
        );
        for ci in 0..op.cuts.len() {
            let parts: Vec<_> = cs.iter().filter(|c| c.op == oi && c.cut == ci).collect();
            if !parts.is_empty() {
                let d = path_data(&parts, &frame, opts.tolerance);
                let _ = writeln!(o, "<path class=\"cut\" id=\"op{oi}-cut{ci}\" d=\"{d}\"/>");
            }
        }
        o.push_str("</g>\n");
    }
    let _ = writeln!(
        o,
        "<g id=\"starts\" fill=\"{START_COLOR}\" stroke=\"none\">"
    );
    for s in &starts {
        let p = frame.map(*s);
        let _ = writeln!(
            o,
            "<circle class=\"start\" cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
            fnum(p.x),
            fnum(p.y),
            fnum(opts.marker_radius)
        );
    }
    o.push_str("</g>\n</svg>\n");
    Ok(o)
}
