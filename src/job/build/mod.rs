//! From a design and a machine profile to an ordered toolpath: each `[[operation]]` of the
//! design (or, with none, the default operations: per item for a drawing, see
//! [`crate::design::default_operations`], else one profile of every outline) becomes
//! operation geometry ([`crate::toolpath::ops`], [`crate::toolpath::line`]) and is planned
//! into cuts ([`crate::toolpath::plan`]).
//!
//! Defaults where the design is silent, as a shop CAM would choose them:
//! - profile side: on the line for lasers, outside for routers (the part keeps its size);
//! - line depth on a router: [`LINE_DEPTH_MM`] with the profile's V-bit, else its cutter;
//! - hairline width (a drawing's strokes cut as lines when no operation is given):
//!   max(kerf or tool diameter, [`HAIRLINE_MM`]);
//! - feed: half the machine's slower XY maximum; power: 100 %;
//! - router depth per pass: the tool diameter (a conservative full-width step);
//! - backboard margin 5 mm (scaled to the design's units), inner corner radius = tool radius;
//! - concentric and pocket stepover: 40 % of the tool diameter.
//!
//! Stroke attributes (`[stroke.attributes]`, values per control disk blended like the
//! radius, wu-2021 eq. 18) reach the moves of a V-carve along the stroke's spine: at every
//! spine sample t the move takes power(t)/100 (percent → fraction) and feed(t) (design
//! units per minute) instead of the operation's values; a router takes z = −depth(t),
//! still capped by `max_depth`, instead of −r(t)·cot(θ/2), and clears no flat bottom
//! (the cap's flat region follows the radius, not the attribute). A laser V-carve
//! engraves along the spine at z = 0 with the attribute power and feed. On G-code lasers
//! the `power` and `feed` attributes also drive profile, fill and channel cuts: each piece of
//! a cut takes the value at the nearest spine parameter (`attributes_on_moves`).

mod backboard;
mod channel;
mod ctx;
mod fill;
mod holes;
mod line;
mod place;
mod pockets;
mod profile;
mod scale;
mod vcarve;

pub use place::{Place, PlaceAt, Placement, place_job};
pub use scale::{fit_scale, outline_bounds, scaled_design};

use super::JobError;
use super::outline::re_interp;
use super::outline::{ItemOutline, OutlineOptions, design_outlines_with};
use super::progress::{ProgressFn, Stage, report};
use super::re_route::{RouteNote, re_items};
use super::tolerances::{Tolerances, laser_arcs};
use crate::design::{Design, Operation, OperationKind, OutlineMethod};
use crate::geom::DVec2;
use crate::machine::{MachineKind, Profile};
use crate::par::prelude::*;
use crate::skin::dbsc_skin::ReportBounds;
use crate::toolpath::arc_merge::merge_lines;
use crate::toolpath::plan::{Geometry, OpSpec, PlanStats, plan};
use crate::toolpath::{OperationKind as TpKind, Toolpath};
use ctx::{Ctx, OpAt};
use std::sync::Mutex;

/// Options of a build.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct BuildOptions {
    /// Arc fitting and flattening tolerance of the toolpath (design units).
    pub tolerance: f64,
    /// Skin approximation ε (design units).
    pub epsilon: f64,
    /// The skin route of profiles and backboards where an operation does not name one
    /// (`skin`: Bézier skin and general offsets; `re`/`mph`: exact MAT offsets, see
    /// the exact MAT offsets of the RE/MPH skins). With `re`/`mph` the items' outlines are their RE/MPH skins.
    pub method: OutlineMethod,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            tolerance: crate::geom::tol::FLATTEN * 10.0,
            epsilon: crate::geom::tol::SKIN_EPSILON,
            method: OutlineMethod::Skin,
        }
    }
}

/// Stepover of concentric clearing as a fraction of the tool diameter.
const STEPOVER: f64 = 0.4;
/// Depth (mm) of a router's `line` operation that sets no `depth`: a shallow engraving, as
/// a pen-plotter line or a scribed mark; with a 60° V-bit the groove is
/// 2·0.2·tan 30° ≈ 0.23 mm wide.
pub const LINE_DEPTH_MM: f64 = 0.2;
/// Depth (mm) of the profiles of a design without operations on a router.
pub const DEFAULT_PROFILE_DEPTH_MM: f64 = 3.0;
/// Longest piece (mm) a laser cut is split into where stroke attributes set its power and
/// feed ([`crate::toolpath::attrs`]; at least [`crate::toolpath::attrs::PIECE_TOLERANCES`]
/// tolerances).
const ATTR_PIECE_MM: f64 = 0.5;

/// The result of a build.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct BuildResult {
    /// The toolpath in design units.
    pub toolpath: Toolpath,
    /// Planning statistics per operation.
    pub stats: Vec<PlanStats>,
    /// Outlines of the design's items (for gouge checks and previews); the skins' segment
    /// reports carry the bounds that decided ε ([`ReportBounds::Decided`]), not tight ones.
    pub outlines: Vec<ItemOutline>,
    /// The route each profile and backboard took (skin, re or mph) and why.
    pub routes: Vec<RouteNote>,
    /// Wall time spent building the RE/MPH skins of the items (seconds; 0 without them).
    pub re_skin_seconds: f64,
    /// The neon bill of materials, for a design with a `[neon]` table (see [`NeonBom`](super::NeonBom)).
    pub neon: Option<super::neon::NeonBom>,
    /// What the build could not cut as drawn (features narrower than the tool), in
    /// operation order.
    pub warnings: Vec<BuildWarning>,
}

/// Something the build could not cut as drawn.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct BuildWarning {
    /// The operation's name in the toolpath (e.g. "profile 1").
    pub operation: String,
    /// The item it concerns.
    pub item: String,
    /// What happened, in words.
    pub message: String,
}

/// The specs of one operation; `design_index` is its index in the design (none for the
/// default profile of a design without operations), `index` the number used in messages.
fn operation_specs(
    ctx: &Ctx,
    index: usize,
    design_index: Option<usize>,
    op: &Operation,
) -> Result<Vec<OpSpec>, JobError> {
    ctx.router_can_cut(index, op)?;
    let at = OpAt {
        index,
        design_index,
        items: ctx.selected(op),
        name: format!("{} {}", op.kind.as_str(), index + 1),
    };
    match op.kind {
        OperationKind::Line => line::specs(ctx, at, op),
        OperationKind::Profile => profile::specs(ctx, at, op),
        OperationKind::Channel => channel::specs(ctx, at, op),
        OperationKind::Backboard => backboard::specs(ctx, at, op),
        OperationKind::Holes => holes::specs(ctx, at, op),
        OperationKind::Fill => fill::specs(ctx, at, op),
        OperationKind::Vcarve => vcarve::specs(ctx, at, op),
    }
}

/// Stroke attributes on the moves of G-code lasers: on profile, fill and channel cuts the
/// `power` and `feed` attributes of the cut's stroke replace the operation's values,
/// evaluated at the nearest spine parameter and quantised
/// ([`crate::toolpath::attrs`]: pieces of at most [`ATTR_PIECE_MM`] or 50 tolerances, power in steps of 0.5 % of the
/// S range rounded up to whole S units, feed in steps of 0.5 % of the slower XY maximum).
/// V-carves carry their attributes already (sampled on the spine); SVG lasers and routers
/// keep the operation's values (an SVG has no per-move power; a spindle's speed is not a
/// stroke attribute).
fn attributes_on_moves(ctx: &Ctx, tp: &mut Toolpath) -> Result<(), JobError> {
    use crate::toolpath::attrs::{self, AttrField, AttrOptions};
    if !matches!(ctx.profile.kind, MachineKind::Laser) {
        return Ok(());
    }
    let mut fields = std::collections::BTreeMap::new();
    for i in 0..ctx.outlines.len() {
        let Some(c) = ctx::spine_of(ctx, i) else {
            continue;
        };
        let a = ctx::stroke_attributes(ctx, i, c)?;
        if a.power.is_some() || a.feed.is_some() {
            fields.insert(
                ctx.outlines[i].name.clone(),
                AttrField {
                    spine: c.clone(),
                    power_percent: a.power,
                    feed: a.feed,
                },
            );
        }
    }
    if fields.is_empty() {
        return Ok(());
    }
    // The emitter writes S with no decimals when the range reaches 100, else with three.
    let s_max = ctx.profile.power.max;
    let s_resolution = if s_max >= 100.0 { 1.0 } else { 0.001 };
    let max_feed = ctx.profile.max_feed.x.min(ctx.profile.max_feed.y) * ctx.k;
    let opts = AttrOptions {
        step: (ATTR_PIECE_MM * ctx.per_mm).max(attrs::PIECE_TOLERANCES * ctx.tol.fit),
        power_quantum: attrs::power_quantum(s_max, s_resolution),
        feed_quantum: (attrs::FEED_QUANTUM * max_feed).max(ctx.tol.fit),
        tol: ctx.tol.length,
    };
    for op in &mut tp.operations {
        if matches!(
            op.kind,
            TpKind::Profile | TpKind::Fill | TpKind::Channel | TpKind::Line
        ) {
            attrs::apply(op, &fields, &opts);
        }
    }
    Ok(())
}

/// Plan the whole design for `profile`, the tool starting at the design's origin (the
/// machine's origin when the job is placed at the design's coordinates, [`Place::Design`]).
pub fn build_toolpath(
    design: &Design,
    profile: &Profile,
    opts: &BuildOptions,
) -> Result<BuildResult, JobError> {
    build_toolpath_with(design, profile, opts, None)
}

/// [`build_toolpath`], reporting progress: [`Stage::Skin`] after every item outlined,
/// [`Stage::Toolpath`] after every operation turned into geometry and once planned.
pub fn build_toolpath_with(
    design: &Design,
    profile: &Profile,
    opts: &BuildOptions,
    progress: Option<ProgressFn<'_>>,
) -> Result<BuildResult, JobError> {
    build_toolpath_placed(design, profile, opts, None, progress, None)
}

/// [`build_toolpath_with`] for a job that [`place_job`] will place as `at` says: the cut
/// order, the seams of closed contours and the travel figures are chosen from the machine's
/// origin where it will be (design coordinates: minus the placement's shift), so that they
/// are those of the machine and a design moved before placement builds the same program
/// once placed. With `at = None`, the design's origin ([`build_toolpath_with`]). The
/// toolpath is still in design coordinates: [`place_job`] moves it.
///
/// `only` lists the 0-based indices of the operations to build (an `[[output]]`'s, see
/// [`crate::design::output`]); `None`: every operation. The others still shape the build
/// as design context (a backboard keeps its margin from every channel, the neon runs use
/// the design's channel width); they are not cut.
pub fn build_toolpath_placed(
    design: &Design,
    profile: &Profile,
    opts: &BuildOptions,
    at: Option<PlaceAt>,
    progress: Option<ProgressFn<'_>>,
    only: Option<&[usize]>,
) -> Result<BuildResult, JobError> {
    let wanted = |i: &usize| only.is_none_or(|o| o.contains(i));
    if !(opts.tolerance > 0.0 && opts.epsilon > 0.0) {
        return Err(JobError::Options(format!(
            "tolerance ({}) and epsilon ({}) must be positive",
            opts.tolerance, opts.epsilon
        )));
    }
    let tol = Tolerances::new(opts, profile, design.units.mm_per_unit());
    // `[neon] round_bends`: the strokes follow the rounded spines from here on.
    let rounded = match &design.neon {
        Some(n) if n.round_bends == Some(true) => Some(super::neon::round_bends(
            design,
            &n.flex(design.units),
            tol.fit,
        )?),
        _ => None,
    };
    let design = rounded.as_ref().map_or(design, |r| &r.design);
    let outline_opts = OutlineOptions {
        epsilon: tol.skin,
        tolerance: tol.fit,
        // Toolpaths use the contours, not the skins' error numbers.
        report: ReportBounds::Decided,
        ..OutlineOptions::default()
    };
    let strokes = design.strokes()?;
    let mut methods = vec![opts.method];
    for (i, op) in design
        .operation
        .iter()
        .enumerate()
        .filter(|(i, _)| wanted(i))
    {
        if let Some(m) = op.method {
            if m == OutlineMethod::Envelope {
                return Err(JobError::Operation {
                    file: design.file.clone(),
                    index: i,
                    kind: op.kind.as_str().to_string(),
                    message: "method \"envelope\" draws the raw envelope and cannot be cut; \
                              use skin, re or mph"
                        .into(),
                });
            }
            methods.push(m);
        }
    }
    if opts.method == OutlineMethod::Envelope {
        return Err(JobError::Options(
            "--method envelope draws the raw envelope and cannot be cut; use skin, re or mph"
                .into(),
        ));
    }
    let mut ctx = Ctx {
        copy_of: Vec::new(),
        regions: Vec::new(),
        design,
        profile,
        stroke_index: (design.stroke.iter().enumerate())
            .map(|(k, s)| (s.name.as_str(), k))
            .collect(),
        tags: design.tags(),
        strokes,
        outlines: Vec::new(),
        tol,
        per_mm: 1.0 / design.units.mm_per_unit(),
        k: profile.units.mm_per_unit() / design.units.mm_per_unit(),
        method: opts.method,
        re: Vec::new(),
        routes: Mutex::new(Vec::new()),
        warnings: Mutex::new(Vec::new()),
        neon: None,
    };
    // Strokes that only `line` operations cut are not skinned (on the skin route: the
    // RE/MPH route makes every item's exact skin).
    let spine_only = if methods.iter().any(|&m| re_interp(m).is_some()) {
        Vec::new()
    } else if design.operation.is_empty() {
        ctx.spine_only(&ctx.default_ops())
    } else {
        let built: Vec<Operation> = (design.operation.iter().enumerate())
            .filter(|(i, _)| wanted(i))
            .map(|(_, op)| op.clone())
            .collect();
        ctx.spine_only(&built)
    };
    let strokes = &ctx.strokes;
    let mut outlines = design_outlines_with(design, &outline_opts, progress, &spine_only)?;
    let mut re = Vec::new();
    let clock = std::time::Instant::now();
    for interp in methods.iter().filter_map(|&m| re_interp(m)) {
        if !re.iter().any(|(i, _)| *i == interp) {
            let items = re_items(design, strokes, &outlines, interp, &outline_opts);
            re.push((interp, items));
        }
    }
    let re_skin_seconds = if re.is_empty() {
        0.0
    } else {
        clock.elapsed().as_secs_f64()
    };
    // With a build-wide RE/MPH route the items are their RE/MPH skins (fills, checks).
    if let Some((_, items)) =
        re_interp(opts.method).and_then(|interp| re.iter().find(|(i, _)| *i == interp))
    {
        for (o, it) in outlines.iter_mut().zip(items) {
            // A skin whose envelope loops keeps the Bézier outline: the RE outline is
            // then a flattened union with sharp corners where the loops were cut.
            match it {
                Ok(it) if it.loop_note.is_none() => o.contours = it.outline.clone(),
                _ => {}
            }
        }
    }
    // Copies share their original's outline only on the skin route (the RE/MPH route
    // replaced the outlines above), and only where both were skinned.
    let marked = |k: usize| spine_only.get(k).copied().unwrap_or(false);
    let copy_of = if re_interp(opts.method).is_none() {
        (super::outline::cache::copies(strokes, tol.fit).into_iter())
            .enumerate()
            .map(|(k, copy)| copy.filter(|&(r, _)| !marked(k) && !marked(r)))
            .collect()
    } else {
        Vec::new()
    };
    ctx.regions = outlines
        .iter()
        .map(|_| std::sync::OnceLock::new())
        .collect();
    ctx.copy_of = copy_of;
    ctx.outlines = outlines;
    ctx.re = re;
    let mut marks = Vec::new();
    if let Some(n) = &design.neon {
        let flex = n.flex(design.units);
        let runs = super::neon::runs(design, &ctx.strokes, &flex);
        let (runs, m) = super::neon::split_marks(design, &ctx.strokes, runs, ctx.tol.length);
        marks = m;
        ctx.neon = Some((flex, runs));
    }
    let mut specs = Vec::new();
    let n_ops = design.operation.len().max(1) + 1;
    report(progress, Stage::Toolpath, 0, n_ops);
    if design.operation.is_empty() {
        // Any design builds: the default operations (`Ctx::default_ops`).
        for (k, op) in ctx.default_ops().iter().enumerate() {
            specs.extend(operation_specs(&ctx, k, None, op)?);
        }
    }
    // Operations are independent: built in parallel, joined in order (the first error in
    // operation order is the one returned, as in a serial build).
    let done = std::sync::atomic::AtomicUsize::new(0);
    let built: Vec<Result<Vec<_>, JobError>> = (design.operation.par_iter().enumerate())
        .filter(|(i, _)| wanted(i))
        .map(|(i, op)| {
            let r = operation_specs(&ctx, i, Some(i), op);
            let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            report(progress, Stage::Toolpath, k + 1, n_ops);
            r
        })
        .collect();
    for b in built {
        specs.extend(b?);
    }
    if laser_arcs(profile) {
        // A laser cuts what was flattened (unions of crossing outlines are polygons) as
        // arcs where its G-code takes them: runs of lines merged within what the union's
        // flattening left of the tolerance, so that flattening and merge together stay
        // within it (chords within ARC_UNION_FRACTION·tol of the exact outline, arcs within
        // (1 − ARC_UNION_FRACTION)·tol of the chords).
        let merge_tol = ctx.tol.merge;
        for s in &mut specs {
            if let Geometry::Paths(paths) = &mut s.geometry {
                *paths = paths
                    .par_iter()
                    .map(|p| merge_lines(p, merge_tol))
                    .collect();
            }
        }
    }
    pockets::assign_pockets(&ctx, &mut specs);
    let neon = ctx.neon.as_ref().map(|(flex, runs)| {
        let holes = specs
            .iter()
            .filter(|s| s.kind == TpKind::Holes)
            .map(|s| match &s.geometry {
                Geometry::Points(p) => p.len(),
                Geometry::Paths(p) => p.len(),
                _ => 0,
            })
            .sum();
        let mut b = super::neon::bom(design, &ctx.strokes, runs, flex, ctx.tol.length, holes);
        b.set_marks(design, &marks);
        if let Some(r) = &rounded {
            b.set_rounding(&r.reports, r.warnings.clone());
        }
        b
    });
    let (mut toolpath, stats) = match at {
        Some(at) => place::plan_placed(&specs, profile, design.units.mm_per_unit(), at, &tol),
        None => plan(&specs, DVec2::ZERO, tol.fit),
    };
    attributes_on_moves(&ctx, &mut toolpath)?;
    report(progress, Stage::Toolpath, n_ops, n_ops);
    Ok(BuildResult {
        toolpath,
        stats,
        routes: {
            let mut r = ctx.routes.into_inner().unwrap_or_else(|e| e.into_inner());
            r.sort_by_key(|(i, _)| *i);
            r.into_iter().map(|(_, n)| n).collect()
        },
        re_skin_seconds,
        outlines: ctx.outlines,
        neon,
        warnings: {
            let mut w = ctx.warnings.into_inner().unwrap_or_else(|e| e.into_inner());
            w.sort_by_key(|(i, _)| *i);
            w.into_iter().map(|(_, w)| w).collect()
        },
    })
}
