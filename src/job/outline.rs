//! Outlines of a whole design: per stroke the spine, the envelope (with caps), the
//! intersection-free outline of the chosen method, reference circles and markers; per
//! circle sequence its skin outline.

use super::JobError;
use crate::dbsc::flatten::flatten;
use crate::dbsc::{DiskBSpline, LoopReport, Side, find_loops};
use crate::design::{Design, OutlineMethod};
use crate::emit::outline::{Contour, Marker, OutlineDoc, RefCircle, StrokeOutline};
use crate::geom::{Circle, DVec2, Path};
use crate::skin::dbsc_skin::{DbscSkinError, DbscSkinOptions, SegmentReport, skin_dbsc};
use crate::skin::{SkinOptions, outline_circles};
use crate::toolpath::region::Region;

/// Options of an outline job.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineOptions {
    pub method: OutlineMethod,
    /// Flattening tolerance of every drawn contour (design units).
    pub tolerance: f64,
    /// ε of the skin approximation of disk B-splines (kruppa-2023 Sec. 4).
    pub epsilon: f64,
    /// Draw the control disks.
    pub control_disks: bool,
}

impl Default for OutlineOptions {
    fn default() -> Self {
        OutlineOptions {
            method: OutlineMethod::Skin,
            tolerance: crate::geom::tol::FLATTEN * 10.0,
            epsilon: crate::geom::tol::SKIN_EPSILON,
            control_disks: false,
        }
    }
}

/// The exact outline of one stroke or circle sequence, with what was found on the way.
#[derive(Clone, Debug)]
pub struct ItemOutline {
    pub name: String,
    /// Closed, non-intersecting contours: outer counter-clockwise, inner clockwise.
    pub contours: Vec<Path>,
    /// The circles the skin touches (knot circles and inserted circles for strokes).
    pub circles: Vec<Circle>,
    /// Envelope loops and spans without an envelope (strokes only).
    pub loops: Option<LoopReport>,
    /// Per-segment approximation report (strokes, skin method only).
    pub segments: Vec<SegmentReport>,
    /// The stroke overlaps itself (its spine crosses itself): `contours` are the boundary
    /// of the union, flattened within the outline tolerance.
    pub self_overlap: bool,
}

/// Parameter tolerance of loop detection: roots of τ± located to 1e-10 of the parameter.
const LOOP_PARAM_TOL: f64 = 1e-10;

fn item_err(design: &Design, item: &'static str, name: &str, message: String) -> JobError {
    JobError::Item {
        file: design.file.clone(),
        item,
        name: name.to_string(),
        message,
    }
}

/// The skin outline of one stroke (kruppa-2023 Sec. 4) with its loop report.
pub fn stroke_outline(
    design: &Design,
    name: &str,
    c: &DiskBSpline,
    opts: &OutlineOptions,
) -> Result<ItemOutline, JobError> {
    let loops = find_loops(c, LOOP_PARAM_TOL)
        .map_err(|e| item_err(design, "stroke", name, e.to_string()))?;
    let mut skin_opts = DbscSkinOptions {
        eps: opts.epsilon,
        ..DbscSkinOptions::default()
    };
    let fail = |e: DbscSkinError| item_err(design, "stroke", name, e.to_string());
    let (sk, self_overlap) = match skin_dbsc(c, &skin_opts) {
        Ok(sk) => (sk, false),
        // The spine crosses itself: skin it anyway and resolve the overlap by a union.
        Err(DbscSkinError::SelfIntersection { .. }) => {
            skin_opts.allow_global_overlap = true;
            (skin_dbsc(c, &skin_opts).map_err(fail)?, true)
        }
        Err(e) => return Err(fail(e)),
    };
    let contours = if self_overlap {
        Region::from_overlapping_paths(&sk.outline, opts.tolerance).paths()
    } else {
        sk.outline
    };
    Ok(ItemOutline {
        name: name.to_string(),
        contours,
        circles: sk.circles,
        loops: Some(loops),
        segments: sk.report,
        self_overlap,
    })
}

/// The skin outline of one circle sequence.
pub fn circles_outline(
    design: &Design,
    name: &str,
    circles: &[Circle],
    closed: bool,
) -> Result<ItemOutline, JobError> {
    let o = outline_circles(circles, closed, &SkinOptions::default())
        .map_err(|e| item_err(design, "circle sequence", name, e.to_string()))?;
    Ok(ItemOutline {
        name: name.to_string(),
        contours: o.contours,
        circles: circles.to_vec(),
        loops: None,
        segments: Vec::new(),
        self_overlap: false,
    })
}

/// Exact outlines of every stroke and circle sequence of the design, in file order.
pub fn design_outlines(
    design: &Design,
    opts: &OutlineOptions,
) -> Result<Vec<ItemOutline>, JobError> {
    let strokes = design.strokes()?;
    let mut out = Vec::new();
    for (s, c) in design.stroke.iter().zip(&strokes) {
        out.push(stroke_outline(design, &s.name, c, opts)?);
    }
    for (seq, circles) in design.circles.iter().zip(design.circle_sequences()) {
        out.push(circles_outline(design, &seq.name, &circles, seq.closed)?);
    }
    Ok(out)
}

fn refc(role: &str, c: &Circle) -> RefCircle {
    RefCircle {
        role: role.to_string(),
        center: [c.c.x, c.c.y],
        radius: c.r,
    }
}

fn loop_markers(c: &DiskBSpline, report: &LoopReport) -> Vec<Marker> {
    let mut m = Vec::new();
    for l in &report.loops {
        let side = match l.side {
            Side::Left => "left",
            Side::Right => "right",
        };
        let at = l
            .cusp_a
            .or(l.cusp_b)
            .unwrap_or_else(|| c.center(0.5 * (l.t_a + l.t_b)));
        m.push(Marker {
            kind: "loop".into(),
            at: [at.x, at.y],
            message: format!(
                "{side} envelope loops back for t in [{:.6}, {:.6}]",
                l.t_a, l.t_b
            ),
        });
    }
    for &(a, b) in &report.no_envelope {
        let p = c.center(0.5 * (a + b));
        m.push(Marker {
            kind: "no-envelope".into(),
            at: [p.x, p.y],
            message: format!("no envelope for t in [{a:.6}, {b:.6}] (|q'| <= |r'|)"),
        });
    }
    m
}

fn flat(role: &str, closed: bool, pts: &[DVec2]) -> Contour {
    Contour::new(role, closed, pts)
}

/// The drawing of one stroke: spine, envelope pieces with caps, and (skin method) the
/// outline contours and knot circles.
fn stroke_drawing(
    name: &str,
    c: &DiskBSpline,
    item: Option<&ItemOutline>,
    loops: &LoopReport,
    opts: &OutlineOptions,
) -> StrokeOutline {
    let f = flatten(c, opts.tolerance);
    let mut contours = vec![flat("spine", false, &f.spine)];
    for piece in f.left.iter().chain(&f.right) {
        contours.push(flat("envelope", false, piece));
    }
    for (_, cap) in &f.caps {
        contours.push(flat("envelope", false, cap));
    }
    let mut circles = Vec::new();
    if let Some(item) = item {
        for p in &item.contours {
            contours.push(flat("outline", true, &p.flatten(opts.tolerance)));
        }
        circles.extend(item.circles.iter().map(|k| refc("knot-circle", k)));
    }
    if opts.control_disks {
        circles.extend(c.control_disks().iter().map(|k| refc("control-disk", k)));
    }
    let mut markers = loop_markers(c, loops);
    if let Some(item) = item.filter(|i| i.self_overlap) {
        let at = item
            .contours
            .first()
            .and_then(|p| p.start())
            .unwrap_or(DVec2::ZERO);
        markers.push(Marker {
            kind: "self-overlap".into(),
            at: [at.x, at.y],
            message: "the stroke crosses itself: the outline is the boundary of the union".into(),
        });
    }
    StrokeOutline {
        name: name.to_string(),
        contours,
        circles,
        markers,
    }
}

/// The outline document of a design (what `skinpath outline` writes).
pub fn outline_document(design: &Design, opts: &OutlineOptions) -> Result<OutlineDoc, JobError> {
    let strokes = design.strokes()?;
    let mut doc = OutlineDoc {
        units: match design.units {
            crate::design::Units::Mm => "mm".into(),
            crate::design::Units::Inch => "inch".into(),
        },
        strokes: Vec::new(),
    };
    for (s, c) in design.stroke.iter().zip(&strokes) {
        let drawing = match opts.method {
            OutlineMethod::Envelope => {
                let loops = find_loops(c, LOOP_PARAM_TOL)
                    .map_err(|e| item_err(design, "stroke", &s.name, e.to_string()))?;
                stroke_drawing(&s.name, c, None, &loops, opts)
            }
            _ => {
                let item = stroke_outline(design, &s.name, c, opts)?;
                let loops = item.loops.clone().unwrap_or_default();
                stroke_drawing(&s.name, c, Some(&item), &loops, opts)
            }
        };
        doc.strokes.push(drawing);
    }
    for (seq, circles) in design.circles.iter().zip(design.circle_sequences()) {
        let item = circles_outline(design, &seq.name, &circles, seq.closed)?;
        doc.strokes.push(StrokeOutline {
            name: seq.name.clone(),
            contours: item
                .contours
                .iter()
                .map(|p| flat("outline", true, &p.flatten(opts.tolerance)))
                .collect(),
            circles: circles.iter().map(|k| refc("circle", k)).collect(),
            markers: Vec::new(),
        });
    }
    Ok(doc)
}
