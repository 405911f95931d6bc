//! DXF (AutoCAD R12, `AC1009`): one layer per operation, one `POLYLINE` per contour with
//! `VERTEX` bulges (bulge = tan(θ/4), θ the signed sweep of the arc to the next vertex),
//! closed flag (70 = 1) on closed contours, `$INSUNITS` = 4 (mm). Arcs are split into pieces
//! of at most 120° so every bulge stays below tan(30°) and full circles survive.

use super::geometry::{CutContour, Seg, bounds, contours, split_arc, validate};
use super::laser_svg::{SVG_MAX_SWEEP, color_of};
use super::{EmitError, check_tolerance, fnum};
use crate::machine::OperationColors;
use crate::toolpath::Toolpath;
use glam::DVec2;
use std::fmt::Write;

/// Options of [`dxf`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct DxfOptions {
    /// Layer colours (mapped to the nearest AutoCAD colour index); white/black otherwise.
    pub colors: Option<OperationColors>,
    /// Largest arc radius mismatch accepted, and the gap under which a contour is closed (mm).
    pub tolerance: f64,
}

impl Default for DxfOptions {
    fn default() -> Self {
        DxfOptions {
            colors: None,
            tolerance: crate::geom::tol::FLATTEN,
        }
    }
}

/// One polyline vertex: position and the bulge of the segment that leaves it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Vertex position (mm).
    pub p: DVec2,
    /// DXF bulge of the segment leaving the vertex: tan(sweep / 4), 0 for a line.
    pub bulge: f64,
}

/// The vertices of a contour and whether it is closed (the closing vertex dropped, its
/// segment's bulge on the last vertex).
pub fn polyline(c: &CutContour, close_tol: f64) -> (Vec<Vertex>, bool) {
    let mut vs = vec![Vertex {
        p: c.start,
        bulge: 0.0,
    }];
    let mut from = c.start;
    for s in &c.segs {
        match *s {
            Seg::Line { to } => vs.push(Vertex { p: to, bulge: 0.0 }),
            Seg::Arc { to, center, sweep } => {
                let pts = split_arc(from, to, center, sweep, SVG_MAX_SWEEP);
                let b = (sweep / pts.len() as f64 / 4.0).tan();
                for p in pts {
                    if let Some(last) = vs.last_mut() {
                        last.bulge = b;
                    }
                    vs.push(Vertex { p, bulge: 0.0 });
                }
            }
        }
        from = s.to();
    }
    let closed = c.is_closed(close_tol) && vs.len() > 2;
    if closed {
        vs.pop();
    }
    (vs, closed)
}

/// AutoCAD colour index nearest to `#rrggbb` among the seven basic colours.
fn aci(hex: &str) -> u8 {
    let v = u32::from_str_radix(hex.trim_start_matches('#'), 16).unwrap_or(0);
    let rgb = [(v >> 16) & 255, (v >> 8) & 255, v & 255].map(|c| c as f64);
    const BASIC: [(u8, [f64; 3]); 7] = [
        (1, [255.0, 0.0, 0.0]),
        (2, [255.0, 255.0, 0.0]),
        (3, [0.0, 255.0, 0.0]),
        (4, [0.0, 255.0, 255.0]),
        (5, [0.0, 0.0, 255.0]),
        (6, [255.0, 0.0, 255.0]),
        (7, [0.0, 0.0, 0.0]),
    ];
    let mut best = (7, f64::INFINITY);
    for (i, c) in BASIC {
        let d = (0..3).map(|k| (c[k] - rgb[k]).powi(2)).sum::<f64>();
        if d < best.1 {
            best = (i, d);
        }
    }
    best.0
}

/// A layer name DXF readers accept: letters, digits, `-` and `_`; unique per operation.
pub fn layer_name(index: usize, name: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .take(40)
        .collect();
    format!("OP{index}_{clean}")
}

fn pair(out: &mut String, code: u16, value: &str) {
    let _ = write!(out, "{code:>3}\n{value}\n");
}

/// The DXF of `tp` (design units, mm).
pub fn dxf(tp: &Toolpath, opts: &DxfOptions) -> Result<String, EmitError> {
    check_tolerance("tolerance", opts.tolerance)?;
    validate(tp, opts.tolerance)?;
    let cs = contours(tp);
    let (lo, hi) = bounds(&cs, &[]).unwrap_or((DVec2::ZERO, DVec2::ZERO));
    let mut o = String::new();
    pair(&mut o, 0, "SECTION");
    pair(&mut o, 2, "HEADER");
    pair(&mut o, 9, "$ACADVER");
    pair(&mut o, 1, "AC1009");
    pair(&mut o, 9, "$INSUNITS");
    pair(&mut o, 70, "4");
    pair(&mut o, 9, "$MEASUREMENT");
    pair(&mut o, 70, "1");
    for (name, p) in [("$EXTMIN", lo), ("$EXTMAX", hi)] {
        pair(&mut o, 9, name);
        pair(&mut o, 10, &fnum(p.x));
        pair(&mut o, 20, &fnum(p.y));
        pair(&mut o, 30, "0");
    }
    pair(&mut o, 0, "ENDSEC");
    // Tables: the CONTINUOUS line type and one layer per operation.
    pair(&mut o, 0, "SECTION");
    pair(&mut o, 2, "TABLES");
    pair(&mut o, 0, "TABLE");
    pair(&mut o, 2, "LTYPE");
    pair(&mut o, 70, "1");
    pair(&mut o, 0, "LTYPE");
    pair(&mut o, 2, "CONTINUOUS");
    pair(&mut o, 70, "0");
    pair(&mut o, 3, "Solid line");
    pair(&mut o, 72, "65");
    pair(&mut o, 73, "0");
    pair(&mut o, 40, "0");
    pair(&mut o, 0, "ENDTAB");
    pair(&mut o, 0, "TABLE");
    pair(&mut o, 2, "LAYER");
    pair(&mut o, 70, &tp.operations.len().to_string());
    for (i, op) in tp.operations.iter().enumerate() {
        let color = opts
            .colors
            .as_ref()
            .map_or(7, |c| aci(color_of(c, op.kind)));
        pair(&mut o, 0, "LAYER");
        pair(&mut o, 2, &layer_name(i, &op.name));
        pair(&mut o, 70, "0");
        pair(&mut o, 62, &color.to_string());
        pair(&mut o, 6, "CONTINUOUS");
    }
    pair(&mut o, 0, "ENDTAB");
    pair(&mut o, 0, "ENDSEC");
    pair(&mut o, 0, "SECTION");
    pair(&mut o, 2, "ENTITIES");
    for c in &cs {
        let layer = layer_name(c.op, &tp.operations[c.op].name);
        let (vs, closed) = polyline(c, opts.tolerance);
        pair(&mut o, 0, "POLYLINE");
        pair(&mut o, 8, &layer);
        pair(&mut o, 66, "1");
        pair(&mut o, 10, "0");
        pair(&mut o, 20, "0");
        pair(&mut o, 30, "0");
        pair(&mut o, 70, if closed { "1" } else { "0" });
        for v in vs {
            pair(&mut o, 0, "VERTEX");
            pair(&mut o, 8, &layer);
            pair(&mut o, 10, &fnum(v.p.x));
            pair(&mut o, 20, &fnum(v.p.y));
            pair(&mut o, 30, "0");
            if v.bulge != 0.0 {
                pair(&mut o, 42, &fnum(v.bulge));
            }
        }
        pair(&mut o, 0, "SEQEND");
        pair(&mut o, 8, &layer);
    }
    pair(&mut o, 0, "ENDSEC");
    pair(&mut o, 0, "EOF");
    Ok(o)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aci_of_basic_colours() {
        assert_eq!(aci("#ff0000"), 1);
        assert_eq!(aci("#0000ff"), 5);
        assert_eq!(aci("#000000"), 7);
        assert_eq!(aci("#00e000"), 3);
    }

    #[test]
    fn layer_names_are_clean_and_unique() {
        assert_eq!(layer_name(2, "outer cut/1"), "OP2_outer_cut_1");
        assert_ne!(layer_name(0, "a"), layer_name(1, "a"));
    }
}
