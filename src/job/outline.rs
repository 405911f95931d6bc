//! Outlines of a whole design: per stroke the spine, the envelope (with caps), the
//! intersection-free outline of the chosen method, reference circles and markers; per
//! circle sequence its skin outline.

use super::JobError;
use super::progress::{ProgressFn, Stage, report};
use crate::dbsc::flatten::{flatten, flatten_disks};
use crate::dbsc::{DiskBSpline, LoopReport, Side, find_loops};
use crate::design::{Design, OutlineMethod};
use crate::emit::outline::{
    CircleRole, ContourRole, Marker, MarkerKind, OutlineContour, OutlineDoc, RefCircle,
    StrokeOutline,
};
use crate::geom::{Circle, DVec2, Path};
use crate::skin::coverage::Uncovered;
use crate::skin::dbsc_skin::{DbscSkinError, DbscSkinOptions, ReportBounds, SegmentReport};
use crate::skin::re::{self, Branch, Interp, Touch};
use crate::skin::{SkinOptions, outline_circles};
use crate::toolpath::region::Region;

pub(crate) mod cache;
pub(crate) mod repair;
pub use repair::{SkinFallback, SkinRepair, SkinSplit};

pub use crate::skin::re::outline::{ReOutline, ReOutlineError, re_offsets, sequence_touches};

/// Options of an outline job.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct OutlineOptions {
    /// Which outline to draw: skin, raw envelope, RE or MPH skin.
    pub method: OutlineMethod,
    /// Flattening tolerance of every drawn contour (design units).
    pub tolerance: f64,
    /// ε of the skin approximation of disk B-splines (kruppa-2023 Sec. 4).
    pub epsilon: f64,
    /// Draw the control disks.
    pub control_disks: bool,
    /// Also draw the inner and outer offsets at this distance (role `offset`).
    pub offset: Option<f64>,
    /// How tight the per-segment error bounds of disk B-spline skins are
    /// ([`ItemOutline::segments`]): tight for the outline document, the decided ones where
    /// only the contours are used (building toolpaths).
    pub report: ReportBounds,
}

impl Default for OutlineOptions {
    fn default() -> Self {
        OutlineOptions {
            method: OutlineMethod::Skin,
            tolerance: crate::geom::tol::FLATTEN * 10.0,
            epsilon: crate::geom::tol::SKIN_EPSILON,
            control_disks: false,
            offset: None,
            report: ReportBounds::Tight,
        }
    }
}

/// The exact outline of one stroke or circle sequence, with what was found on the way.
#[derive(Clone, Debug)]
pub struct ItemOutline {
    /// The stroke's or circle sequence's name.
    pub name: String,
    /// Closed, non-intersecting contours: outer counter-clockwise, inner clockwise.
    pub contours: Vec<Path>,
    /// The circles the skin touches (knot circles and inserted circles for strokes).
    pub circles: Vec<Circle>,
    /// Envelope loops and spans without an envelope (strokes only).
    pub loops: Option<LoopReport>,
    /// Per-segment approximation report (strokes, skin method only), with the error bounds
    /// [`OutlineOptions::report`] asks for.
    pub segments: Vec<SegmentReport>,
    /// The stroke overlaps itself (its spine crosses itself): `contours` are the boundary
    /// of the union, flattened within the outline tolerance.
    pub self_overlap: bool,
    /// Where the skin outline left part of the stroke outside (by more than ε plus the
    /// flattening): the deepest-reaching disk. `contours` are then the union of the
    /// stroke's disks (`toolpath::ops::swept_disks`), flattened within the
    /// outline tolerance, instead of the skin.
    pub disk_union: Option<Uncovered>,
    /// What was done where the stroke could not be skinned as one piece: splits, pieces
    /// built on the union of their disks, and the outline's deviation from the disks
    /// (its repair). `None` for a stroke skinned as it is.
    pub repair: Option<SkinRepair>,
    /// A stroke that a build cuts only along its spine (every operation selecting it is a
    /// `line`) is not skinned (`spine_only_outline`): `contours` is then empty and this is
    /// the box (min, max) of its disks, for the job's bounds. `None` for every outline made.
    pub spine_box: Option<(DVec2, DVec2)>,
}

/// Parameter tolerance of loop detection: roots of τ± located to 1e-10 of the parameter.
const LOOP_PARAM_TOL: f64 = 1e-10;

/// What went wrong with one stroke or circle sequence (see [`JobError::Item`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ItemError {
    /// Envelope loop detection failed.
    #[error(transparent)]
    Loops(#[from] crate::dbsc::LoopError),
    /// The stroke's skin failed; `hint` names the disks and what to change ("" or "; ...").
    #[error("{source}{hint}")]
    Skin {
        /// Why the skin failed.
        source: DbscSkinError,
        /// Which disks to change and how ("" or "; ...").
        hint: String,
    },
    /// The circle sequence's skin failed.
    #[error(transparent)]
    Circles(#[from] crate::skin::SkinError),
    /// The RE/MPH outline failed.
    #[error(transparent)]
    Re(#[from] ReOutlineError),
}

fn item_err(design: &Design, item: &'static str, name: &str, e: impl Into<ItemError>) -> JobError {
    JobError::Item {
        file: design.file.clone(),
        item,
        name: name.to_string(),
        source: Box::new(e.into()),
    }
}

/// The skin outline of one stroke (kruppa-2023 Sec. 4) with its loop report. A stroke that
/// cannot be skinned as it is, or whose skin cuts into it by more than [`miss_limit`], is
/// split at the failing place and its pieces skinned again, a piece that still fails being
/// built on the union of its disks ([`repair`]); only an envelope loop search that fails is
/// an error.
pub fn stroke_outline(
    design: &Design,
    name: &str,
    c: &DiskBSpline,
    opts: &OutlineOptions,
) -> Result<ItemOutline, JobError> {
    let loops = find_loops(c, LOOP_PARAM_TOL).map_err(|e| item_err(design, "stroke", name, e))?;
    let skin_opts = DbscSkinOptions {
        epsilon: opts.epsilon,
        report: opts.report,
        loop_tol: LOOP_PARAM_TOL,
        ..DbscSkinOptions::default()
    };
    let failure = match repair::skin_piece(c, &skin_opts, Some(&loops)) {
        Ok((sk, self_overlap)) => {
            let contours = repair::skin_contours(&sk, self_overlap, opts.tolerance);
            // Where phase 3 stopped with ε far from met, the skin can cut through the
            // stroke (a hairpin): measure it.
            match repair::missed(c, &contours, opts.tolerance, miss_limit(opts)) {
                None => {
                    return Ok(ItemOutline {
                        name: name.to_string(),
                        contours,
                        circles: sk.circles,
                        loops: Some(loops),
                        segments: sk.report,
                        self_overlap,
                        disk_union: None,
                        repair: None,
                        spine_box: None,
                    });
                }
                Some(u) => repair::Failure0::Missed(u),
            }
        }
        Err(e) => repair::Failure0::Error(e),
    };
    let r = repair::repair(c, failure, &skin_opts, opts.tolerance, miss_limit(opts));
    let disk_union = r
        .repair
        .fallbacks
        .iter()
        .filter_map(|f| f.missed)
        .max_by(|a, b| a.depth.total_cmp(&b.depth));
    Ok(ItemOutline {
        name: name.to_string(),
        contours: r.contours,
        circles: r.circles,
        loops: Some(loops),
        segments: r.segments,
        self_overlap: r.self_overlap,
        disk_union,
        repair: Some(r.repair),
        spine_box: None,
    })
}

/// The outline of a stroke that a build cuts only along its spine (`line` operations):
/// no skin, no contours, only the box of its disks ([`ItemOutline::spine_box`]) for the
/// job's bounds. The box is that of the disks sampled by [`flatten_disks`] (centre and
/// radius within `tol` of the linear interpolation between samples), so it lies within
/// 2·`tol` of the exact box min/max over t of q(t) ∓ r(t).
pub fn spine_only_outline(name: &str, c: &DiskBSpline, tol: f64) -> ItemOutline {
    let (lo, hi) = flatten_disks(c, tol).iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), (_, d)| {
            (
                lo.min(d.c - DVec2::splat(d.r)),
                hi.max(d.c + DVec2::splat(d.r)),
            )
        },
    );
    ItemOutline {
        name: name.to_string(),
        contours: Vec::new(),
        circles: Vec::new(),
        loops: None,
        segments: Vec::new(),
        self_overlap: false,
        disk_union: None,
        repair: None,
        spine_box: (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi)),
    }
}

/// How far a disk of a stroke may reach outside its skin outline before the outline is
/// replaced by the union of the disks ([`ItemOutline::disk_union`]): ε, which the skin
/// meets wherever the Hausdorff bound holds, plus the flattening of the outline and of the
/// disks (one tolerance each), doubled for safety. Where a skin's bound stays unmet at a
/// sharp bend its smooth outline lies outside the disks (it rounds the inner corner), so
/// only outlines that cut into the stroke exceed this.
fn miss_limit(opts: &OutlineOptions) -> f64 {
    2.0 * (opts.epsilon + 2.0 * opts.tolerance)
}

/// The skin outline of one circle sequence.
pub fn circles_outline(
    design: &Design,
    name: &str,
    circles: &[Circle],
    closed: bool,
) -> Result<ItemOutline, JobError> {
    let o = outline_circles(circles, closed, &SkinOptions::default())
        .map_err(|e| item_err(design, "circle sequence", name, e))?;
    Ok(ItemOutline {
        name: name.to_string(),
        contours: o.contours,
        circles: circles.to_vec(),
        loops: None,
        segments: Vec::new(),
        self_overlap: false,
        disk_union: None,
        repair: None,
        spine_box: None,
    })
}

/// Exact outlines of every stroke and circle sequence of the design, in file order.
pub fn design_outlines(
    design: &Design,
    opts: &OutlineOptions,
) -> Result<Vec<ItemOutline>, JobError> {
    design_outlines_with(design, opts, None, &[])
}

/// [`design_outlines`], reporting [`Stage::Skin`] progress after every item. Items are
/// skinned in parallel (rayon) and collected in file order, the first error in file order,
/// so the result does not depend on the number of threads. A stroke that is a translated
/// copy of an earlier one takes that stroke's outline, translated ([`cache`]): each distinct
/// stroke is skinned once. A stroke marked in `spine_only` (per stroke, in file order;
/// missing entries are false) is cut only along its spine and gets
/// [`spine_only_outline`] instead of a skin; a copy takes its original's outline only when
/// neither is marked.
pub fn design_outlines_with(
    design: &Design,
    opts: &OutlineOptions,
    progress: Option<ProgressFn<'_>>,
    spine_only: &[bool],
) -> Result<Vec<ItemOutline>, JobError> {
    use crate::par::prelude::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let strokes = design.strokes()?;
    let sequences = design.circle_sequences();
    let total = strokes.len() + sequences.len();
    report(progress, Stage::Skin, 0, total);
    let done = AtomicUsize::new(0);
    let step = |r: Result<ItemOutline, JobError>| {
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        report(progress, Stage::Skin, n, total);
        r
    };
    let marked = |k: usize| spine_only.get(k).copied().unwrap_or(false);
    let outline_of = |k: usize, name: &str, c: &DiskBSpline| {
        if marked(k) {
            Ok(spine_only_outline(name, c, opts.tolerance))
        } else {
            stroke_outline(design, name, c, opts)
        }
    };
    let copy_of: Vec<Option<(usize, DVec2)>> = cache::copies(&strokes, opts.tolerance)
        .into_iter()
        .enumerate()
        .map(|(k, copy)| copy.filter(|&(r, _)| !marked(k) && !marked(r)))
        .collect();
    // The representatives' outlines (None for copies), then each copy from its
    // representative; a copy of a stroke that failed is skinned itself (its own error).
    let own: Vec<Option<Result<ItemOutline, JobError>>> =
        (design.stroke.par_iter().zip(&strokes).enumerate())
            .zip(&copy_of)
            .map(|((k, (s, c)), copy)| copy.is_none().then(|| step(outline_of(k, &s.name, c))))
            .collect();
    let copies: Vec<Option<Result<ItemOutline, JobError>>> =
        (design.stroke.par_iter().zip(&strokes).enumerate())
            .zip(&copy_of)
            .map(|((k, (s, c)), copy)| {
                copy.map(|(r, d)| match &own[r] {
                    Some(Ok(rep)) => step(Ok(rep.translated(d, &s.name))),
                    _ => step(outline_of(k, &s.name, c)),
                })
            })
            .collect();
    // Exactly one of the two is there for each stroke.
    let strokes: Vec<Result<ItemOutline, JobError>> = own
        .into_iter()
        .zip(copies)
        .filter_map(|(a, b)| a.or(b))
        .collect();
    let seqs = (design.circles.par_iter().zip(&sequences))
        .map(|(seq, circles)| step(circles_outline(design, &seq.name, circles, seq.closed)));
    let seqs: Vec<Result<ItemOutline, JobError>> = seqs.collect();
    let mut all: Vec<ItemOutline> = strokes.into_iter().chain(seqs).collect::<Result<_, _>>()?;
    all.extend(super::shapes::shape_outlines(design));
    Ok(all)
}

fn refc(role: CircleRole, c: &Circle) -> RefCircle {
    RefCircle {
        role,
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
            kind: MarkerKind::Loop,
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
            kind: MarkerKind::NoEnvelope,
            at: [p.x, p.y],
            message: format!("no envelope for t in [{a:.6}, {b:.6}] (|q'| <= |r'|)"),
        });
    }
    m
}

fn flat(role: ContourRole, closed: bool, pts: &[DVec2]) -> OutlineContour {
    OutlineContour::new(role, closed, pts)
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
    let mut contours = vec![flat(ContourRole::Spine, false, &f.spine)];
    for piece in f.left.iter().chain(&f.right) {
        contours.push(flat(ContourRole::Envelope, false, piece));
    }
    for (_, cap) in &f.caps {
        contours.push(flat(ContourRole::Envelope, false, cap));
    }
    let mut circles = Vec::new();
    if let Some(item) = item {
        for p in &item.contours {
            contours.push(flat(ContourRole::Outline, true, &p.flatten(opts.tolerance)));
        }
        circles.extend(item.circles.iter().map(|k| refc(CircleRole::KnotCircle, k)));
    }
    if opts.control_disks {
        circles.extend(
            c.control_disks()
                .iter()
                .map(|k| refc(CircleRole::ControlDisk, k)),
        );
    }
    let mut markers = loop_markers(c, loops);
    if let Some(item) = item.filter(|i| i.self_overlap) {
        let at = item
            .contours
            .first()
            .and_then(|p| p.start())
            .unwrap_or(DVec2::ZERO);
        markers.push(Marker {
            kind: MarkerKind::SelfOverlap,
            at: [at.x, at.y],
            message: "the stroke crosses itself: the outline is the boundary of the union".into(),
        });
    }
    if let Some(r) = item.and_then(|i| i.repair.as_ref()) {
        for f in &r.fallbacks {
            markers.push(Marker {
                kind: MarkerKind::DiskUnion,
                at: [f.at.x, f.at.y],
                message: format!(
                    "t in [{:.6}, {:.6}] could not be skinned ({}): the outline there is the \
                     union of the stroke's disks",
                    f.t[0], f.t[1], f.reason
                ),
            });
        }
    } else if let Some(u) = item.and_then(|i| i.disk_union) {
        markers.push(Marker {
            kind: MarkerKind::DiskUnion,
            at: [u.at.x, u.at.y],
            message: format!(
                "the skin cut {:.3} into the stroke at t = {:.6} (no admissible circle left to \
                 meet ε = {}): the outline is the union of the stroke's disks",
                u.depth, u.t, opts.epsilon
            ),
        });
    }
    StrokeOutline {
        name: name.to_string(),
        contours,
        circles,
        markers,
    }
}

/// The interpolant of an RE-type method, `None` for the skin and envelope methods.
pub fn re_interp(method: OutlineMethod) -> Option<Interp> {
    match method {
        OutlineMethod::Re => Some(Interp::Cubic),
        OutlineMethod::Mph => Some(Interp::PhQuintic),
        OutlineMethod::Skin | OutlineMethod::Envelope => None,
    }
}

/// [`re::outline::re_outline`] with local envelope loops cut off by the non-zero-winding
/// union of the flattened envelopes ([`Region::from_overlapping_paths`], within `tol`).
pub fn re_outline(
    circles: &[Circle],
    touches: &[Touch],
    closed: bool,
    interp: Interp,
    tol: f64,
) -> Result<ReOutline, ReOutlineError> {
    re::outline::re_outline(circles, touches, closed, interp, tol, |cs| {
        let paths: Vec<Path> = cs.iter().map(|c| polyline_path(c)).collect();
        Region::from_overlapping_paths(&paths, tol)
            .paths()
            .iter()
            .map(|p| p.flatten(tol))
            .filter(|c| c.len() >= 3)
            .collect()
    })
}

/// Circles and touching points of a stroke for the RE route
/// ([`re::outline::stroke_re_input`] within the outline's ε).
pub fn stroke_re_input(
    c: &DiskBSpline,
    opts: &OutlineOptions,
) -> Result<(Vec<Circle>, Vec<Touch>, bool), ReOutlineError> {
    re::outline::stroke_re_input(c, opts.epsilon)
}

/// A closed polyline as a path of lines.
fn polyline_path(c: &[DVec2]) -> Path {
    let n = c.len();
    let segs = (0..n)
        .map(|i| crate::geom::PathSeg::Line(crate::geom::Line::new(c[i], c[(i + 1) % n])))
        .collect();
    Path::new(segs, true)
}

/// Inner and outer δ-offsets of closed outline paths by cavalier_contours (Region offset),
/// flattened within `tol`.
pub fn region_offsets(paths: &[Path], delta: f64, tol: f64) -> Vec<Vec<DVec2>> {
    let r = Region::from_paths(paths, tol);
    let mut out = Vec::new();
    for d in [-delta, delta] {
        for p in r.offset(d, tol).paths() {
            out.push(p.flatten(tol));
        }
    }
    out
}

fn re_markers(o: &ReOutline) -> Vec<Marker> {
    let mut m = Vec::new();
    for e in &o.intersections {
        let (i, j) = o
            .skin
            .segments
            .get(e.segment)
            .map(|s| (s.i, s.j))
            .unwrap_or((e.segment, e.segment + 1));
        m.push(Marker {
            kind: MarkerKind::ReIntersection,
            at: [e.point.x, e.point.y],
            message: format!(
                "circles {i} and {j}: the envelopes meet at t = {:.6} ({:?}) after elimination",
                e.t, e.kind
            ),
        });
    }
    for &(b, g0, g1) in &o.loops {
        let seg = (g0.floor().max(0.0) as usize).min(o.skin.segments.len().saturating_sub(1));
        let Some(sg) = o.skin.segments.get(seg) else {
            continue;
        };
        let t = (0.5 * (g0 + g1) - seg as f64).clamp(0.0, 1.0);
        let at = o.skin.envelope(seg, b, t).unwrap_or(DVec2::ZERO);
        let side = match b {
            Branch::Plus => "left",
            Branch::Minus => "right",
        };
        m.push(Marker {
            kind: MarkerKind::ReLoop,
            at: [at.x, at.y],
            message: format!(
                "circles {} and {}: the {side} envelope runs backwards (local loop, cut off by the union; offsets there are approximate)",
                sg.i, sg.j
            ),
        });
    }
    for &(i, j) in &o.failed_pairs {
        if o.intersections.iter().any(|e| {
            o.skin
                .segments
                .get(e.segment)
                .is_some_and(|s| s.i == i && s.j == j)
        }) {
            continue;
        }
        let at = o.skin.circles.get(i).map(|c| c.c).unwrap_or(DVec2::ZERO);
        m.push(Marker {
            kind: MarkerKind::ReIntersection,
            at: [at.x, at.y],
            message: format!("circles {i} and {j}: elimination failed (f not proved positive)"),
        });
    }
    m
}

/// RE/MPH drawing contours of one circle sequence: outline and (with `opts.offset`) the
/// offsets, plus markers.
fn re_contours(
    circles: &[Circle],
    touches: &[Touch],
    closed: bool,
    interp: Interp,
    opts: &OutlineOptions,
) -> Result<(Vec<OutlineContour>, Vec<Marker>), ReOutlineError> {
    let o = re_outline(circles, touches, closed, interp, opts.tolerance)?;
    let mut contours: Vec<OutlineContour> = o
        .contours
        .iter()
        .map(|c| flat(ContourRole::Outline, true, c))
        .collect();
    if let Some(delta) = opts.offset {
        for c in re_offsets(&o.skin, delta, opts.tolerance)? {
            contours.push(flat(ContourRole::Offset, true, &c));
        }
    }
    Ok((contours, re_markers(&o)))
}

fn offset_contours(paths: &[Path], delta: f64, opts: &OutlineOptions) -> Vec<OutlineContour> {
    region_offsets(paths, delta, opts.tolerance)
        .iter()
        .filter(|c| c.len() >= 3)
        .map(|c| flat(ContourRole::Offset, true, c))
        .collect()
}

/// The outline document of a design (what `skinpath outline` writes).
pub fn outline_document(design: &Design, opts: &OutlineOptions) -> Result<OutlineDoc, JobError> {
    outline_document_with(design, opts, None)
}

/// [`outline_document`], reporting [`Stage::Skin`] progress after every item.
pub fn outline_document_with(
    design: &Design,
    opts: &OutlineOptions,
    progress: Option<ProgressFn<'_>>,
) -> Result<OutlineDoc, JobError> {
    let strokes = design.strokes()?;
    let total = strokes.len() + design.circles.len();
    report(progress, Stage::Skin, 0, total);
    let mut doc = OutlineDoc {
        units: match design.units {
            crate::design::Units::Mm => "mm".into(),
            crate::design::Units::Inch => "inch".into(),
        },
        strokes: Vec::new(),
    };
    for (s, c) in design.stroke.iter().zip(&strokes) {
        let err = |e: ReOutlineError| item_err(design, "stroke", &s.name, e);
        let loops =
            find_loops(c, LOOP_PARAM_TOL).map_err(|e| item_err(design, "stroke", &s.name, e))?;
        let mut drawing = match (opts.method, re_interp(opts.method)) {
            (_, Some(interp)) => {
                let (circles, touches, closed) = stroke_re_input(c, opts).map_err(err)?;
                let mut d = stroke_drawing(&s.name, c, None, &loops, opts);
                let (cs, ms) =
                    re_contours(&circles, &touches, closed, interp, opts).map_err(err)?;
                d.contours.extend(cs);
                d.markers.extend(ms);
                d.circles
                    .extend(circles.iter().map(|k| refc(CircleRole::KnotCircle, k)));
                d
            }
            (OutlineMethod::Envelope, None) => {
                let mut d = stroke_drawing(&s.name, c, None, &loops, opts);
                if let Some(delta) = opts.offset {
                    let item = stroke_outline(design, &s.name, c, opts)?;
                    d.contours
                        .extend(offset_contours(&item.contours, delta, opts));
                }
                d
            }
            _ => {
                let item = stroke_outline(design, &s.name, c, opts)?;
                let mut d = stroke_drawing(&s.name, c, Some(&item), &loops, opts);
                if let Some(delta) = opts.offset {
                    d.contours
                        .extend(offset_contours(&item.contours, delta, opts));
                }
                d
            }
        };
        drawing.name = s.name.clone();
        doc.strokes.push(drawing);
        report(progress, Stage::Skin, doc.strokes.len(), total);
    }
    for (seq, circles) in design.circles.iter().zip(design.circle_sequences()) {
        let err = |e: ReOutlineError| item_err(design, "circle sequence", &seq.name, e);
        let (contours, markers) = match re_interp(opts.method) {
            Some(interp) => {
                let touches = sequence_touches(&circles, seq.closed)
                    .map_err(|e| err(ReOutlineError::Touching(e)))?;
                re_contours(&circles, &touches, seq.closed, interp, opts).map_err(err)?
            }
            None => {
                let item = circles_outline(design, &seq.name, &circles, seq.closed)?;
                let mut cs: Vec<OutlineContour> = item
                    .contours
                    .iter()
                    .map(|p| flat(ContourRole::Outline, true, &p.flatten(opts.tolerance)))
                    .collect();
                if let Some(delta) = opts.offset {
                    cs.extend(offset_contours(&item.contours, delta, opts));
                }
                (cs, Vec::new())
            }
        };
        doc.strokes.push(StrokeOutline {
            name: seq.name.clone(),
            contours,
            circles: circles
                .iter()
                .map(|k| refc(CircleRole::Circle, k))
                .collect(),
            markers,
        });
        report(progress, Stage::Skin, doc.strokes.len(), total);
    }
    doc.strokes
        .extend(super::shapes::shape_drawings(design, opts));
    Ok(doc)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skin::mat_offset;

    fn snake() -> Vec<Circle> {
        vec![
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(3.0, 1.0), 1.4),
            Circle::new(DVec2::new(6.0, 0.5), 0.8),
            Circle::new(DVec2::new(8.5, -1.5), 1.1),
            Circle::new(DVec2::new(11.0, -1.0), 0.6),
        ]
    }

    fn ring() -> Vec<Circle> {
        (0..8)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 8.0;
                Circle::new(
                    10.0 * DVec2::new(a.cos(), a.sin()),
                    2.0 + 0.5 * (k % 2) as f64,
                )
            })
            .collect()
    }

    fn transform(cs: &[Circle], rot: f64, scale: f64, rev: bool) -> Vec<Circle> {
        let (s, c) = rot.sin_cos();
        let mut v: Vec<Circle> = cs
            .iter()
            .map(|k| {
                let p = DVec2::new(c * k.c.x - s * k.c.y, s * k.c.x + c * k.c.y) * scale;
                Circle::new(p + DVec2::new(3.0, -2.0), k.r * scale)
            })
            .collect();
        if rev {
            v.reverse();
        }
        v
    }

    fn dist_poly(p: DVec2, c: &[DVec2]) -> f64 {
        (0..c.len())
            .map(|i| crate::geom::Line::new(c[i], c[(i + 1) % c.len()]).distance(p))
            .fold(f64::INFINITY, f64::min)
    }

    /// The flattened outline is within tol of the exact envelopes (dense samples of
    /// ReSkin::envelope, a second evaluation path), and passes through every touching
    /// point (piece ends are exact vertices).
    #[test]
    fn flattened_outline_follows_exact_envelopes() {
        for (cs0, closed) in [(snake(), false), (ring(), true)] {
            for (rot, scale, rev) in [(0.0, 1.0, false), (0.8, 4.0, false), (-2.1, 0.2, true)] {
                let cs = transform(&cs0, rot, scale, rev);
                let tol = 1e-3 * scale;
                for interp in [Interp::Cubic, Interp::PhQuintic] {
                    let touches = sequence_touches(&cs, closed).unwrap();
                    let o = re_outline(&cs, &touches, closed, interp, tol).unwrap();
                    assert_eq!(o.contours.len(), if closed { 2 } else { 1 });
                    // Before any loop cut: the flattened exact pieces themselves.
                    let flat = mat_offset::outline(&o.skin).unwrap().flatten(tol);
                    let all: Vec<DVec2> = flat.concat();
                    let near = |p: DVec2| {
                        flat.iter()
                            .map(|c| dist_poly(p, c))
                            .fold(f64::INFINITY, f64::min)
                    };
                    for s in 0..o.skin.segments.len() {
                        for k in 0..=200 {
                            let t = k as f64 / 200.0;
                            for b in [Branch::Plus, Branch::Minus] {
                                let p = o.skin.envelope(s, b, t).unwrap();
                                assert!(near(p) <= tol * 1.001, "{s} {t} {}", near(p));
                            }
                        }
                    }
                    for t in &touches {
                        let Touch::Fixed { plus, minus } = *t else {
                            panic!()
                        };
                        for w in [plus, minus] {
                            let d = all.iter().map(|q| q.distance(w)).fold(f64::MAX, f64::min);
                            assert!(d <= 1e-9 * scale, "touching point {w} missed by {d}");
                        }
                    }
                }
            }
        }
    }

    /// Open: one counter-clockwise contour; closed: outer counter-clockwise enclosing the
    /// clockwise inner one.
    #[test]
    fn contours_are_oriented() {
        let area = |c: &Vec<DVec2>| crate::geom::path::polygon_area(c);
        let o = re_outline(
            &snake(),
            &sequence_touches(&snake(), false).unwrap(),
            false,
            Interp::Cubic,
            1e-3,
        )
        .unwrap();
        assert!(area(&o.contours[0]) > 0.0);
        let o = re_outline(
            &ring(),
            &sequence_touches(&ring(), true).unwrap(),
            true,
            Interp::PhQuintic,
            1e-3,
        )
        .unwrap();
        let (a0, a1) = (area(&o.contours[0]), area(&o.contours[1]));
        let (a0, a1) = (a0.max(a1), a0.min(a1));
        assert!(a0 > 0.0 && a1 < 0.0 && a0 > -a1, "{a0} {a1}");
        // The ring between radii ~8 and ~12: area close to π(12.2² − 7.8²) within 20 %.
        let ring_area = std::f64::consts::PI * (12.25f64.powi(2) - 7.75f64.powi(2));
        assert!(((a0 + a1) / ring_area - 1.0).abs() < 0.2, "{}", a0 + a1);
    }

    /// The snake's right envelope loops near circle 2: the loop is reported and the outline
    /// is cut clean (no two non-adjacent polyline segments cross).
    #[test]
    fn envelope_loop_is_cut_and_reported() {
        let cs = snake();
        let o = re_outline(
            &cs,
            &sequence_touches(&cs, false).unwrap(),
            false,
            Interp::Cubic,
            1e-3,
        )
        .unwrap();
        assert!(!o.loops.is_empty());
        assert!(re_markers(&o).iter().any(|m| m.kind == MarkerKind::ReLoop));
        for c in &o.contours {
            let n = c.len();
            for i in 0..n {
                for j in i + 2..n {
                    if i == 0 && j == n - 1 {
                        continue;
                    }
                    assert!(!crate::geom::predicates::segments_intersect(
                        c[i],
                        c[(i + 1) % n],
                        c[j],
                        c[(j + 1) % n]
                    ));
                }
            }
        }
    }

    /// Offsets of the MAT route lie at δ from the outline (up to both flattenings) on a
    /// loop-free sequence (an arc of growing circles).
    #[test]
    fn re_offsets_at_delta() {
        let cs: Vec<Circle> = (0..6)
            .map(|k| {
                let a = 0.3 * k as f64;
                Circle::new(20.0 * DVec2::new(a.cos(), a.sin()), 1.0 + 0.4 * k as f64)
            })
            .collect();
        let tol = 1e-3;
        let o = re_outline(
            &cs,
            &sequence_touches(&cs, false).unwrap(),
            false,
            Interp::Cubic,
            tol,
        )
        .unwrap();
        assert!(o.loops.is_empty());
        for delta in [0.3, 0.9] {
            let offs = re_offsets(&o.skin, delta, tol).unwrap();
            assert!(offs.len() >= 2);
            for p in offs.iter().flatten() {
                let d = dist_poly(*p, &o.contours[0]);
                assert!(
                    (d - delta).abs() <= 2.0 * tol + 1e-9,
                    "δ {delta}: {p} at {d}; loops {:?}",
                    mat_offset::envelope_loops(&o.skin, 1e-9)
                );
            }
        }
    }

    const DESIGN: &str = r#"
version = 1
units = "mm"
[outline]
method = "mph"
tolerance = 0.01
[[circles]]
name = "c1"
closed = false
circles = [[0.0, 0.0, 1.0], [3.0, 1.0, 1.4], [6.0, 0.5, 0.8], [8.5, -1.5, 1.1]]
"#;

    /// The design's [outline] method selects the MPH route; a bad sequence names itself.
    #[test]
    fn document_uses_design_method_and_names_errors() {
        let design = crate::design::load(DESIGN, "t.toml").unwrap();
        let method = design.outline.as_ref().and_then(|o| o.method).unwrap();
        assert_eq!(re_interp(method), Some(Interp::PhQuintic));
        let opts = OutlineOptions {
            method,
            tolerance: 0.01,
            offset: Some(0.2),
            ..OutlineOptions::default()
        };
        let doc = outline_document(&design, &opts).unwrap();
        let s = &doc.strokes[0];
        let n = |role: ContourRole| s.contours.iter().filter(|c| c.role == role).count();
        assert_eq!(n(ContourRole::Outline), 1);
        assert!(n(ContourRole::Offset) >= 2);
        // The MPH outline differs from the skin outline of the same circles.
        let skin = outline_document(
            &design,
            &OutlineOptions {
                method: OutlineMethod::Skin,
                ..opts
            },
        )
        .unwrap();
        assert_ne!(skin.strokes[0].contours, s.contours);
        // A circle inside its neighbour has no touching points: the error names the sequence.
        let bad = DESIGN.replace("[3.0, 1.0, 1.4]", "[0.1, 0.0, 0.2]");
        if let Ok(d) = crate::design::load(&bad, "t.toml") {
            let e = outline_document(&d, &opts).unwrap_err().to_string();
            assert!(e.contains("c1"), "{e}");
        }
    }
}
