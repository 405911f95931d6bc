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

use super::JobError;
use super::outline::re_interp;
use super::outline::{ItemOutline, OutlineOptions, design_outlines_with};
use super::progress::{ProgressFn, Stage, report};
use super::re_route::{ReItem, RouteNote, RouteRefusal, re_backboard, re_items, re_profile};
use crate::dbsc::DiskBSpline;
use crate::design::{
    Design, FillPattern, HAIRLINE_MM, HoleAt, LineBoundaries, Operation, OperationKind,
    OutlineMethod, ProfileSide, Selection, Tags,
};
use crate::geom::{DVec2, Path};
use crate::machine::{MachineKind, Profile, Tool, ToolKind};
use crate::par::prelude::*;
use crate::skin::dbsc_skin::ReportBounds;
use crate::skin::re::Interp;
use crate::spline::BSpline;
use crate::toolpath::arc_merge::merge_lines;
use crate::toolpath::board;
use crate::toolpath::cut::{Lead, Tabs};
use crate::toolpath::ops::{self, Hole};
use crate::toolpath::plan::{AttrPolyline, Geometry, OpSpec, PlanStats, plan};
use crate::toolpath::re_route::SegCounts;
use crate::toolpath::region::Region;
use crate::toolpath::swept::swept_arc_region;
use crate::toolpath::{OperationKind as TpKind, Toolpath};
use glam::DVec3;
use std::collections::HashMap;
use std::sync::Mutex;

/// Options of a build.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildOptions {
    /// Arc fitting and flattening tolerance of the toolpath (design units).
    pub tolerance: f64,
    /// Skin approximation ε (design units).
    pub epsilon: f64,
    /// The skin route of profiles and backboards where an operation does not name one
    /// (`skin`: Bézier skin and general offsets; `re`/`mph`: exact MAT offsets, see
    /// [`super::re_route`]). With `re`/`mph` the items' outlines are their RE/MPH skins.
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

/// Flattening tolerance of unions that are merged into arcs afterwards, as a fraction of the
/// build tolerance ([`crate::toolpath::arc_merge`]). The chords are within this fraction of
/// the exact outline and the merged arcs within the rest, (1 − fraction)·tol, of the chords,
/// so the cut stays within the build tolerance. An arc through a flattened arc's vertices is
/// within the chords' sagitta of them, which must stay below the merge's share for the arc
/// to pass: at a third for the chords, two thirds for the merge, every such run passes with
/// room to spare.
const ARC_UNION_FRACTION: f64 = 1.0 / 3.0;

/// Stepover of concentric clearing as a fraction of the tool diameter.
const STEPOVER: f64 = 0.4;
/// Default backboard margin in millimetres.
const BACKBOARD_MARGIN_MM: f64 = 5.0;
/// Depth (mm) of a router's `line` operation that sets no `depth`: a shallow engraving, as
/// a pen-plotter line or a scribed mark; with a 60° V-bit the groove is
/// 2·0.2·tan 30° ≈ 0.23 mm wide.
pub const LINE_DEPTH_MM: f64 = 0.2;
/// Depth (mm) of the profiles of a design without operations on a router.
pub const DEFAULT_PROFILE_DEPTH_MM: f64 = 3.0;
/// Spacing of V-carve samples along the spine, in millimetres: the chord sagitta
/// s²/(8ρ) stays below 8 µm wherever the spine's curvature radius ρ ≥ 1 mm.
const VCARVE_STEP_MM: f64 = 0.25;

/// The result of a build.
#[derive(Clone, Debug)]
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
    /// The neon bill of materials, for a design with a `[neon]` table ([`super::neon`]).
    pub neon: Option<super::neon::NeonBom>,
    /// What the build could not cut as drawn (features narrower than the tool), in
    /// operation order.
    pub warnings: Vec<BuildWarning>,
}

/// Something the build could not cut as drawn.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BuildWarning {
    /// The operation's name in the toolpath (e.g. "profile 1").
    pub operation: String,
    /// The item it concerns.
    pub item: String,
    /// What happened, in words.
    pub message: String,
}

struct Ctx<'a> {
    design: &'a Design,
    profile: &'a Profile,
    strokes: Vec<DiskBSpline>,
    /// Index in `design.stroke` (and `strokes`) of each stroke, by name.
    stroke_index: HashMap<&'a str, usize>,
    /// Layer and colour of each stroke and shape, by name.
    tags: HashMap<&'a str, Tags<'a>>,
    outlines: Vec<ItemOutline>,
    tol: f64,
    /// Design units per millimetre.
    per_mm: f64,
    /// Design units per profile unit (tool sizes and feeds are in the profile's units).
    k: f64,
    /// The build's default route.
    method: OutlineMethod,
    /// RE/MPH skins of every item, per interpolant used by the build.
    re: Vec<(Interp, Vec<Result<ReItem, RouteRefusal>>)>,
    /// Route notes with the number of the operation that took them (operations are built
    /// in parallel; the notes are put in operation order at the end).
    routes: Mutex<Vec<(usize, RouteNote)>>,
    /// The flex and its runs, for a design with a `[neon]` table.
    neon: Option<(crate::design::Flex, Vec<super::neon::Run>)>,
    /// Per outline, the stroke it is a translated copy of and the translation, where its
    /// outline is that stroke's translated ([`super::outline::cache`]).
    copy_of: Vec<Option<(usize, DVec2)>>,
    /// Per outline its region, made once when first asked for.
    regions: Vec<std::sync::OnceLock<Region>>,
    /// Warnings with the number of the operation that gave them.
    warnings: Mutex<Vec<(usize, BuildWarning)>>,
}

impl Ctx<'_> {
    /// Records the route operation `index` took.
    fn note_route(&self, index: usize, note: RouteNote) {
        self.routes
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push((index, note));
    }
}

fn op_err(ctx: &Ctx, index: usize, op: &Operation, message: impl Into<String>) -> JobError {
    JobError::Operation {
        file: ctx.design.file.clone(),
        index,
        kind: op.kind.as_str().to_string(),
        message: message.into(),
    }
}

impl Ctx<'_> {
    /// A G-code laser whose profile writes arcs (`arcs` other than "none").
    fn laser_arcs(&self) -> bool {
        self.laser()
            && (self.profile.gcode.as_ref())
                .is_some_and(|g| g.arcs != crate::machine::ArcFormat::None)
    }

    /// Flattening tolerance of the union of several outlines: the build tolerance, or
    /// [`ARC_UNION_FRACTION`] of it where the lines are merged into arcs afterwards
    /// ([`Ctx::laser_arcs`]), so that the chords' sagittas leave room for the merge.
    fn union_tol(&self) -> f64 {
        if self.laser_arcs() {
            ARC_UNION_FRACTION * self.tol
        } else {
            self.tol
        }
    }

    fn laser(&self) -> bool {
        !matches!(self.profile.kind, MachineKind::Router)
    }

    /// The items an operation applies to, in item order: those its `strokes`, `layers` or
    /// `colors` name, all when it gives none ([`Selection`]).
    fn selected(&self, op: &Operation) -> Vec<usize> {
        let sel = Selection::of(op);
        (0..self.outlines.len())
            .filter(|&i| self.selects(&sel, &self.outlines[i].name))
            .collect()
    }

    /// Whether `sel` selects the item named `name` (by its name, layer or colour).
    fn selects(&self, sel: &Selection, name: &str) -> bool {
        let tags = self.tags.get(name).copied().unwrap_or_default();
        sel.selects(name, tags)
    }

    /// Per stroke of the design, whether `ops` cut it only along its spine: some operation
    /// selects it and every one that does is a `line` ([`line_paths`]). Such a stroke needs
    /// no skin ([`super::outline::spine_only_outline`]).
    fn spine_only(&self, ops: &[Operation]) -> Vec<bool> {
        let sels: Vec<(OperationKind, Selection)> =
            ops.iter().map(|op| (op.kind, Selection::of(op))).collect();
        (self.design.stroke.iter())
            .map(|s| {
                let mut kinds = (sels.iter())
                    .filter(|(_, sel)| self.selects(sel, &s.name))
                    .map(|(k, _)| *k)
                    .peekable();
                kinds.peek().is_some() && kinds.all(|k| k == OperationKind::Line)
            })
            .collect()
    }

    /// Width at or below which a stroke of a design without operations is a hairline, cut
    /// once along its spine: max(kerf or tool diameter, [`HAIRLINE_MM`]) in design units
    /// (a stroke no wider than the tool cannot have both edges cut).
    fn hairline(&self) -> f64 {
        let tool = self.tool(&[ToolKind::Endmill, ToolKind::Ballnose, ToolKind::Beam]);
        (2.0 * self.radius(tool)).max(HAIRLINE_MM * self.per_mm)
    }

    /// The operations of a design without any ([`super::check::operations_of`]: a drawing
    /// item by item, hairlines as lines; any other design one profile around the union of
    /// everything). Router profiles are [`DEFAULT_PROFILE_DEPTH_MM`] deep.
    fn default_ops(&self) -> Vec<Operation> {
        let mut ops = super::check::operations_of(self.design, self.hairline());
        for op in &mut ops {
            if !self.laser() && op.kind == OperationKind::Profile {
                op.depth = Some(DEFAULT_PROFILE_DEPTH_MM * self.per_mm);
            }
        }
        ops
    }

    /// The region of each item's outline (arcs fitted within the build tolerance), made in
    /// parallel and kept in order.
    fn item_regions(&self, items: &[usize]) -> Vec<Region> {
        items
            .par_iter()
            .map(|&i| self.item_region(i).clone())
            .collect()
    }

    /// The region of item `i`'s outline, made once: a copy's is its original's, translated.
    fn item_region(&self, i: usize) -> &Region {
        self.regions[i].get_or_init(|| match self.copy_of.get(i).copied().flatten() {
            Some((r, d)) => self.item_region(r).translated(d),
            None => Region::from_paths(&self.outlines[i].contours, self.tol),
        })
    }

    fn region(&self, items: &[usize]) -> Region {
        union_of(&self.item_regions(items), self.union_tol())
    }

    fn tool(&self, want: &[ToolKind]) -> Option<&Tool> {
        self.profile
            .tools
            .iter()
            .find(|t| want.contains(&t.kind))
            .or(self.profile.tools.first())
    }

    /// The tool for operation `index`: on a router one of the `want` kinds must exist (a
    /// router cannot cut without a cutter, and compensating by a V-bit's shank for an end
    /// mill's cut would gouge); a laser may have no tool entry (kerf 0).
    fn tool_for(
        &self,
        index: usize,
        op: &Operation,
        want: &[ToolKind],
    ) -> Result<Option<&Tool>, JobError> {
        if self.laser() {
            return Ok(self.tool(want));
        }
        match self.profile.tools.iter().find(|t| want.contains(&t.kind)) {
            Some(t) => Ok(Some(t)),
            None => {
                let kinds: Vec<String> = want
                    .iter()
                    .map(|k| format!("{k:?}").to_lowercase())
                    .collect();
                let have: Vec<String> = self
                    .profile
                    .tools
                    .iter()
                    .map(|t| format!("{} ({:?})", t.name, t.kind).to_lowercase())
                    .collect();
                Err(op_err(
                    self,
                    index,
                    op,
                    format!(
                        "machine profile \"{}\" has no tool that fits a {} on a router \
                         (it needs a [[tools]] entry of kind {}; the profile has {}): add one \
                         to the profile",
                        self.profile.name,
                        op.kind.as_str(),
                        kinds.join(" or "),
                        if have.is_empty() {
                            "no tools".to_string()
                        } else {
                            have.join(", ")
                        }
                    ),
                ))
            }
        }
    }

    /// Power (fraction) of an operation that sets none: the laser profile's documented
    /// `default_power` ([`crate::machine::LaserSettings::default_power`], percent), full
    /// spindle speed on a router.
    fn default_power(&self) -> f64 {
        match &self.profile.laser {
            Some(l) if self.laser() => l.default_power() / 100.0,
            _ => 1.0,
        }
    }

    /// Air assist of an operation: its own `air_assist`, else the laser profile's default.
    fn air_assist(&self, op: &Operation) -> bool {
        op.air_assist.unwrap_or_else(|| {
            self.profile
                .laser
                .as_ref()
                .is_some_and(|l| l.air_assist && self.laser())
        })
    }

    /// Compensation radius of `tool` in design units (0 without a tool).
    fn radius(&self, tool: Option<&Tool>) -> f64 {
        tool.map(|t| t.radius() * self.k).unwrap_or(0.0)
    }

    fn default_feed(&self) -> f64 {
        0.5 * self.profile.max_feed.x.min(self.profile.max_feed.y) * self.k
    }

    /// The paths of a profile or backboard by the operation's route: the MAT route
    /// (`exact`, given each selected item's name and RE/MPH skin) when the operation or the
    /// build asks for re/mph and every item has an exact skin, otherwise `general`; the
    /// route taken and the reason for a fallback are noted for the build summary.
    fn routed(
        &self,
        index: usize,
        op: &Operation,
        name: &str,
        items: &[usize],
        general: impl FnOnce() -> Vec<Path>,
        exact: impl FnOnce(&[(&str, &ReItem)]) -> Result<Vec<Path>, RouteRefusal>,
    ) -> Result<Vec<Path>, JobError> {
        let method = op.method.unwrap_or(self.method);
        let clock = std::time::Instant::now();
        let note = |route: &str, detail: String, paths: &[Path]| RouteNote {
            operation: name.to_string(),
            route: route.to_string(),
            detail,
            counts: SegCounts::of(paths),
            seconds: clock.elapsed().as_secs_f64(),
        };
        let Some(interp) = re_interp(method) else {
            let paths = general();
            let n = note("skin", "Bézier skin, general offset".into(), &paths);
            self.note_route(index, n);
            return Ok(paths);
        };
        let route = if interp == Interp::Cubic { "re" } else { "mph" };
        let table = self
            .re
            .iter()
            .find(|(i, _)| *i == interp)
            .map(|(_, t)| t)
            .ok_or_else(|| op_err(self, index, op, "no RE/MPH skins were built"))?;
        let mut its = Vec::new();
        let mut why = None;
        for &i in items {
            match table.get(i) {
                Some(Ok(it)) => its.push((self.outlines[i].name.as_str(), it)),
                Some(Err(e)) => {
                    why = Some(format!("{}: {e}", self.outlines[i].name));
                    break;
                }
                None => why = Some(RouteRefusal::NoSkin.to_string()),
            }
        }
        // The reason goes into the route note, which is text.
        let result = match why {
            Some(w) => Err(w),
            None if its.is_empty() => Err(RouteRefusal::NoItems.to_string()),
            None => exact(&its).map_err(|e| e.to_string()),
        };
        let (paths, n) = match result {
            Ok(p) => {
                let d = format!("exact MAT offset of {} {route} skin(s)", its.len());
                let n = note(route, d, &p);
                (p, n)
            }
            Err(w) => {
                let p = general();
                let n = note("skin", format!("{route} route not taken: {w}"), &p);
                (p, n)
            }
        };
        self.note_route(index, n);
        Ok(paths)
    }

    fn plunge_feed(&self) -> f64 {
        self.profile
            .router
            .as_ref()
            .map(|r| r.plunge_feed * self.k)
            .unwrap_or_else(|| self.default_feed())
    }
}

#[allow(clippy::too_many_arguments)]
fn spec(
    ctx: &Ctx,
    index: Option<usize>,
    name: String,
    kind: TpKind,
    op: &Operation,
    geometry: Geometry,
    tool: Option<&Tool>,
) -> OpSpec {
    let laser = ctx.laser();
    let depth = if laser { 0.0 } else { op.depth.unwrap_or(0.0) };
    let passes = op.passes.unwrap_or(1).max(1) as usize;
    let step_down = op.step_down.unwrap_or_else(|| {
        if depth > 0.0 && op.passes.is_some() {
            depth / passes as f64
        } else {
            tool.map(|t| t.diameter * ctx.k)
                .filter(|d| *d > 0.0)
                .unwrap_or(depth.max(1.0))
        }
    });
    let tool_d = 2.0 * ctx.radius(tool);
    OpSpec {
        name,
        kind,
        geometry,
        sources: Vec::new(),
        groups: Vec::new(),
        design_index: index,
        air_assist: ctx.air_assist(op),
        depth,
        step_down,
        repeat: if laser { passes } else { 1 },
        feed: op.feed.unwrap_or_else(|| ctx.default_feed()),
        plunge_feed: ctx.plunge_feed(),
        power: op
            .power
            .map(|p| p / 100.0)
            .unwrap_or_else(|| ctx.default_power()),
        tabs: op.tabs.as_ref().map(|t| Tabs {
            count: t.count as usize,
            width: t.width + tool_d,
            height: t.height,
        }),
        lead: match op.lead_in {
            Some(l) if l > 0.0 => Lead::Arc(l),
            _ => Lead::None,
        },
        dwell: ctx
            .profile
            .laser
            .as_ref()
            .map(|l| l.pierce_dwell)
            .unwrap_or(0.0),
    }
}

/// The paths `f` makes of the union of the items' regions (strokes that touch or cross make
/// one region: one fill, not two overlapping ones), each attributed to the first item whose
/// region holds its first point, or the nearest one.
fn union_paths_with_sources(
    ctx: &Ctx,
    items: &[usize],
    f: impl Fn(&Region) -> Vec<Path>,
) -> (Vec<Path>, Vec<String>) {
    let regions = ctx.item_regions(items);
    let paths = f(&union_of(&regions, ctx.union_tol()));
    let sources = attribute(ctx, items, &regions, &paths);
    (paths, sources)
}

/// Refuses a fill whose spacing would make more than [`ops::MAX_HATCH_LINES`] hatch lines
/// in one direction ([`ops::hatch_line_count`]) or more than [`ops::MAX_FILL_RINGS`]
/// concentric rings ([`ops::ring_count_bound`]) across its items, before any is made.
fn fill_count_check(
    ctx: &Ctx,
    index: usize,
    op: &Operation,
    items: &[usize],
    angle: f64,
    spacing: f64,
) -> Result<(), JobError> {
    let regions = ctx.item_regions(items);
    let (count, limit, what) = match op.pattern.unwrap_or_default() {
        FillPattern::Hatch => {
            let mut n = ops::hatch_line_count(&regions, angle, spacing);
            if op.cross_hatch.unwrap_or(false) {
                let across = angle + std::f64::consts::FRAC_PI_2;
                n = n.max(ops::hatch_line_count(&regions, across, spacing));
            }
            (n, ops::MAX_HATCH_LINES, "hatch lines in one direction")
        }
        FillPattern::Concentric => (
            ops::ring_count_bound(&regions, spacing),
            ops::MAX_FILL_RINGS,
            "concentric rings",
        ),
    };
    if count > limit as f64 {
        return Err(op_err(
            ctx,
            index,
            op,
            format!(
                "fill with spacing {spacing} would make about {count:.0} {what}, more than \
                 the limit {limit}: give a larger spacing"
            ),
        ));
    }
    Ok(())
}

/// The union of `regions` within `tol`; a single region as it is.
fn union_of(regions: &[Region], tol: f64) -> Region {
    match regions {
        [one] => one.clone(),
        _ => Region::union(regions, tol),
    }
}

/// The item each path comes from: the item `items[k]` of the first of `regions` that holds
/// the path's first point, or of the nearest one (`items` and `regions` pair up). Regions
/// whose bounding box (arcs included) misses the point are not asked.
fn attribute(ctx: &Ctx, items: &[usize], regions: &[Region], paths: &[Path]) -> Vec<String> {
    let boxes: Vec<Option<(DVec2, DVec2)>> = (regions.iter())
        .map(|r| r.bounds().map(Into::into))
        .collect();
    paths
        .par_iter()
        .map(|p| {
            let q = p.start().unwrap_or_default();
            let k = (regions.iter().zip(&boxes))
                .position(|(r, b)| {
                    b.is_some_and(|(lo, hi)| box_distance(lo, hi, q) == 0.0) && r.contains(q)
                })
                .unwrap_or_else(|| nearest_region(regions, &boxes, q));
            items
                .get(k)
                .map(|&i| ctx.outlines[i].name.clone())
                .unwrap_or_default()
        })
        .collect()
}

/// Distance from `q` to the box [lo, hi] (0 inside).
fn box_distance(lo: DVec2, hi: DVec2, q: DVec2) -> f64 {
    (lo - q).max(q - hi).max(DVec2::ZERO).length()
}

/// Index of the region whose vertices come nearest to `q` (the first of equals); regions
/// whose box (`boxes`, holding their vertices) is farther than the best so far are skipped.
fn nearest_region(regions: &[Region], boxes: &[Option<(DVec2, DVec2)>], q: DVec2) -> usize {
    use cavalier_contours::polyline::PlineSource;
    let mut best = (0, f64::INFINITY);
    for (k, (r, b)) in regions.iter().zip(boxes).enumerate() {
        let Some((lo, hi)) = *b else { continue };
        if (lo - q).max(q - hi).max(DVec2::ZERO).length_squared() > best.1 {
            continue;
        }
        let d = r
            .contours
            .iter()
            .flat_map(|c| c.iter_vertexes())
            .map(|v| DVec2::new(v.x, v.y).distance_squared(q))
            .fold(f64::INFINITY, f64::min);
        if d < best.1 {
            best = (k, d);
        }
    }
    best.0
}

fn spine_of<'a>(ctx: &'a Ctx, item: usize) -> Option<&'a DiskBSpline> {
    let name = ctx.outlines[item].name.as_str();
    ctx.stroke_index.get(name).map(|&k| &ctx.strokes[k])
}

/// Whether the line `next` of stroke `to` continues the line `prev` of stroke `from` (the
/// open piece before it): the two are pieces of one stroke split at a corner
/// ([`Design::corners`]) and meet there exactly. Pieces with stroke attributes stay apart
/// (a cut takes the attributes of the stroke it names).
fn joins_at_corner(ctx: &Ctx, from: &str, to: &str, prev: &Path, next: &Path) -> bool {
    let plain = |n: &str| {
        (ctx.stroke_index.get(n)).is_some_and(|&k| ctx.design.stroke[k].attributes.is_empty())
    };
    !prev.closed
        && !next.closed
        && prev.end().is_some()
        && prev.end() == next.start()
        && ctx
            .design
            .corners
            .iter()
            .any(|c| c.pieces[0] == from && c.pieces[1] == to)
        && plain(from)
        && plain(to)
}

/// The paths a `line` operation cuts for item `item` ([`crate::toolpath::line`]): a
/// stroke's spine, a shape's contours, a circle sequence's centres.
fn line_paths(ctx: &Ctx, item: usize) -> Vec<Path> {
    use crate::toolpath::line::{polyline_path, spine_path};
    if let Some(c) = spine_of(ctx, item) {
        return vec![spine_path(c, ctx.tol)];
    }
    let name = &ctx.outlines[item].name;
    if let Some(sh) = ctx.design.shape.iter().find(|s| &s.name == name) {
        return sh
            .contours
            .iter()
            .filter_map(|ring| {
                let pts: Vec<DVec2> = ring.iter().map(|p| DVec2::new(p[0], p[1])).collect();
                polyline_path(&pts, true)
            })
            .collect();
    }
    ctx.design
        .circles
        .iter()
        .find(|c| &c.name == name)
        .and_then(|c| {
            let pts: Vec<DVec2> = c.circles.iter().map(|p| DVec2::new(p[0], p[1])).collect();
            polyline_path(&pts, c.closed)
        })
        .into_iter()
        .collect()
}

/// The contours of `region` (holes for an outside profile, material for an inside one)
/// that the tool of radius `r` cannot follow, each with a message: the offset of the
/// contour left no path inside it (the feature vanished: it is narrower than the tool),
/// or several (a waist narrower than the tool split it and is not cut). A contour's width
/// is given as its mean width 2·A/P (area over half the perimeter: the width of a thin
/// strip, the diameter of a disk). `paths` are the profile's paths: a hole's offsets run
/// counter-clockwise (region contours reversed), material's clockwise. A lobe lost
/// while the rest of the contour keeps one path is not caught.
fn lost_to_the_tool(
    region: &Region,
    side: ops::ProfileSide,
    r: f64,
    paths: &[Path],
    tol: f64,
) -> Vec<(Path, String)> {
    use cavalier_contours::core::math::Vector2;
    use cavalier_contours::polyline::PlineSource;
    let holes = side == ops::ProfileSide::Outside;
    let starts: Vec<(DVec2, bool)> = paths
        .iter()
        .filter_map(|p| {
            let area = crate::toolpath::region::pline_from_path(p, tol).area();
            Some((p.start()?, area > 0.0))
        })
        .collect();
    let mut out = Vec::new();
    for c in &region.contours {
        let area = c.area();
        if (area < 0.0) != holes {
            continue;
        }
        let inside = starts
            .iter()
            .filter(|(q, ccw)| {
                // Hole offsets are counter-clockwise once reversed, material's clockwise.
                *ccw == holes && c.winding_number(Vector2::new(q.x, q.y)) != 0
            })
            .count();
        if inside == 1 {
            continue;
        }
        let width = 2.0 * area.abs() / c.path_length();
        let what = if holes { "a hole" } else { "a part" };
        let Some(at) = c.iter_vertexes().next() else {
            continue;
        };
        let message = if inside == 0 {
            format!(
                "{what} near ({:.3}, {:.3}), {width:.3} wide on average (2·area/perimeter), is \
                 narrower than the tool ({:.3}): it is not cut",
                at.x,
                at.y,
                2.0 * r
            )
        } else {
            format!(
                "{what} near ({:.3}, {:.3}), {width:.3} wide on average, has a waist \
                 narrower than the tool ({:.3}): the tool cuts {inside} pieces of it and not \
                 the waist",
                at.x,
                at.y,
                2.0 * r
            )
        };
        out.push((crate::geom::interop::path_from_pline(c), message));
    }
    out
}

/// The inner visible boundaries of `items` ([`crate::toolpath::inks`]), per item that owns
/// them: the items painted in the order shapes, circle sequences, strokes (each in file
/// order: an SVG import keeps shapes as their visible areas and strokes on top of them),
/// items of one `color` as one ink (items without a colour as one more); open runs shorter
/// than a hairline ([`Ctx::hairline`]) are left out.
fn inner_boundary_paths(ctx: &Ctx, items: &[usize]) -> Vec<(usize, Vec<Path>)> {
    use crate::toolpath::inks::{Painted, inner_boundaries};
    use crate::toolpath::line::polyline_path;
    let rank = |i: usize| {
        let name = ctx.outlines[i].name.as_str();
        if spine_of(ctx, i).is_some() {
            2
        } else if ctx.design.circles.iter().any(|c| c.name == name) {
            1
        } else {
            0
        }
    };
    let mut order: Vec<usize> = items.to_vec();
    order.sort_by_key(|&i| (rank(i), i));
    let regions = ctx.item_regions(&order);
    let mut inks: HashMap<Option<String>, usize> = HashMap::new();
    let painted: Vec<Painted<'_>> = (order.iter().zip(&regions))
        .map(|(&i, region)| {
            let name = ctx.outlines[i].name.as_str();
            let color = (ctx.tags.get(name))
                .and_then(|t| t.color)
                .map(str::to_ascii_lowercase);
            let next = inks.len();
            let ink = *inks.entry(color).or_insert(next);
            Painted { region, ink }
        })
        .collect();
    // An open run shorter than a hairline (where a hatch line ends on an outline) is a dot
    // under the cut's own width: not a boundary anyone sees.
    let mut out: Vec<(usize, Vec<Path>)> = Vec::new();
    for b in inner_boundaries(&painted, ctx.tol, ctx.hairline()) {
        let item = order[b.item];
        let Some(path) = polyline_path(&b.points, b.closed) else {
            continue;
        };
        match out.last_mut() {
            Some((i, paths)) if *i == item => paths.push(path),
            _ => out.push((item, vec![path])),
        }
    }
    out
}

/// The swept regions of the design's channel operations along the strokes among `items`
/// (the strokes a backboard carries), as polygons ([`channel_polygon`]): the board tests
/// their vertices and unions them with its outlines, which flattens them anyway.
fn channel_regions(ctx: &Ctx, items: &[usize]) -> Vec<Region> {
    let mut spines = Vec::new();
    for op in &ctx.design.operation {
        let (OperationKind::Channel, Some(width)) = (op.kind, op.width) else {
            continue;
        };
        for i in ctx.selected(op).into_iter().filter(|i| items.contains(i)) {
            if let Some(c) = spine_of(ctx, i) {
                spines.push((c, width));
            }
        }
    }
    spines
        .par_iter()
        .map(|&(c, width)| channel_polygon(ctx, c, width).1)
        .collect()
}

/// A channel of `width` along a stroke's spine: the spine as lines and arcs, and the region
/// a disk of radius width/2 sweeps along it. Up to degree 3 the spine's cubic spans are
/// fitted by arcs within the build tolerance and the region is bounded by their exact
/// offsets ([`swept_arc_region`]); above, or where that region fails its checks, it is
/// [`channel_polygon`].
fn channel_swept(ctx: &Ctx, c: &DiskBSpline, width: f64) -> (Path, Region) {
    let eps = ctx.tol * 0.1;
    let arcs = crate::toolpath::line::spine_pline(c, ctx.tol).and_then(|pline| {
        let region = swept_arc_region(&pline, width / 2.0, eps)?;
        Some((crate::geom::interop::path_from_pline(&pline), region))
    });
    arcs.unwrap_or_else(|| channel_polygon(ctx, c, width))
}

/// A channel of `width` along a stroke's spine flattened within the build tolerance, and the
/// buffer of that polyline by width/2 (a polygon).
fn channel_polygon(ctx: &Ctx, c: &DiskBSpline, width: f64) -> (Path, Region) {
    let pts = crate::dbsc::flatten::flatten_spine(c, ctx.tol);
    let region = ops::swept_region(&pts, c.is_closed(), width / 2.0, ctx.tol);
    (Path::polyline(&pts, c.is_closed()), region)
}

/// A pocket without the posts of material narrower than a tool of radius `r`: the
/// morphological closing (R ⊕ D_r) ⊖ D_r (Serra, *Image Analysis and Mathematical
/// Morphology*, 1982, ch. II), the region grown and then shrunk by `r`. It contains R, and
/// every part of the complement it gives up is narrower than the tool's diameter (no disk
/// D_r fits in it); posts and notches a disk of radius `r` fits in stay. `eps` is the
/// offsets' position tolerance; should the offsets fail (a result that does not hold R's
/// area within `tol` per unit of perimeter), R is kept as it is.
fn without_narrow_posts(region: &Region, r: f64, tol: f64, eps: f64) -> Region {
    if r <= 0.0 || region.is_empty() {
        return region.clone();
    }
    let closed = region.offset(r, eps).offset(-r, eps);
    if closed.is_empty() || closed.area() < region.area() - tol * region.perimeter() {
        region.clone()
    } else {
        closed
    }
}

/// Parameter samples of a stroke's spine about `step` apart along its length.
fn spine_params(c: &DiskBSpline, step: f64) -> Vec<f64> {
    let (lo, hi) = c.domain();
    let coarse = 256;
    let len: f64 = (0..coarse)
        .map(|i| {
            let a = lo + (hi - lo) * i as f64 / coarse as f64;
            let b = lo + (hi - lo) * (i + 1) as f64 / coarse as f64;
            c.center(a).distance(c.center(b))
        })
        .sum();
    let n = ((len / step).ceil() as usize).clamp(8, 1 << 20);
    (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect()
}

/// The attribute curves of the stroke behind outline item `item` (none for circle
/// sequences): each channel's control values blended with the stroke's own basis,
/// a(t) = Σ N_i(t)·a_i (wu-2021 eq. 18), so an attribute follows the disks like the radius.
#[derive(Default)]
struct StrokeAttributes {
    /// Power in percent of the machine's maximum.
    power: Option<BSpline<f64>>,
    /// Depth below the surface (positive, design units).
    depth: Option<BSpline<f64>>,
    /// Feed in design units per minute.
    feed: Option<BSpline<f64>>,
}

fn stroke_attributes(
    ctx: &Ctx,
    item: usize,
    curve: &DiskBSpline,
) -> Result<StrokeAttributes, JobError> {
    let name = ctx.outlines[item].name.as_str();
    let Some(&k) = ctx.stroke_index.get(name) else {
        return Ok(StrokeAttributes::default());
    };
    let mut out = StrokeAttributes::default();
    for (channel, c) in ctx.design.stroke[k].attribute_curves(curve, &ctx.design.file, k)? {
        match channel {
            "power" => out.power = Some(c),
            "depth" => out.depth = Some(c),
            "feed" => out.feed = Some(c),
            _ => {}
        }
    }
    Ok(out)
}

/// The specs of one operation; `design_index` is its index in the design (none for the
/// default profile of a design without operations), `index` the number used in messages.
fn operation_specs(
    ctx: &Ctx,
    index: usize,
    design_index: Option<usize>,
    op: &Operation,
) -> Result<Vec<OpSpec>, JobError> {
    let items = ctx.selected(op);
    let laser = ctx.laser();
    let name = format!("{} {}", op.kind.as_str(), index + 1);
    let eps = ctx.tol * 0.1;
    let depth_optional = matches!(op.kind, OperationKind::Vcarve | OperationKind::Line);
    if !laser && op.depth.is_none() && !depth_optional {
        return Err(op_err(ctx, index, op, "a router operation needs `depth`"));
    }
    let mill = [ToolKind::Endmill, ToolKind::Ballnose, ToolKind::Beam];
    // A router engraves a line with a V-bit when it has one, else with a cutter.
    let engrave = [ToolKind::Vbit, ToolKind::Endmill, ToolKind::Ballnose];
    let want: &[ToolKind] = match op.kind {
        OperationKind::Line => &engrave,
        _ => &mill,
    };
    if !laser && !matches!(op.kind, OperationKind::Vcarve) {
        ctx.tool_for(index, op, want)?;
    }
    let out = match op.kind {
        OperationKind::Line => {
            let tool = if laser {
                ctx.tool(&mill)
            } else {
                engrave
                    .iter()
                    .find_map(|k| ctx.profile.tools.iter().find(|t| t.kind == *k))
            };
            // Per selected item its paths (independent fits: in parallel, kept in order),
            // or the visible boundaries between the items' inks.
            let per_item: Vec<(usize, Vec<Path>)> = match op.boundaries {
                Some(LineBoundaries::Inner) => inner_boundary_paths(ctx, &items),
                None => items.par_iter().map(|&i| (i, line_paths(ctx, i))).collect(),
            };
            let mut paths: Vec<Path> = Vec::new();
            let mut sources: Vec<String> = Vec::new();
            // The item of the last path's last piece.
            let mut last = "";
            for (i, ps) in per_item {
                let name = ctx.outlines[i].name.as_str();
                for p in ps {
                    // The pieces of a stroke split at corners are one line: joined.
                    match paths.last_mut() {
                        Some(prev) if joins_at_corner(ctx, last, name, prev, &p) => {
                            prev.segs.extend(p.segs);
                            let (a, b) = (prev.start(), prev.end());
                            prev.closed = a.zip(b).is_some_and(|(a, b)| a == b);
                        }
                        _ => {
                            paths.push(p);
                            sources.push(name.to_string());
                        }
                    }
                    last = name;
                }
            }
            let mut line_op = op.clone();
            if !laser && line_op.depth.is_none() {
                line_op.depth = Some(LINE_DEPTH_MM * ctx.per_mm);
            }
            let mut s = spec(
                ctx,
                design_index,
                name,
                TpKind::Line,
                &line_op,
                Geometry::Paths(paths),
                tool,
            );
            s.sources = sources;
            vec![s]
        }
        OperationKind::Profile => {
            let tool = ctx.tool(&mill);
            let r = ctx.radius(tool);
            let side = match op.side {
                Some(ProfileSide::On) => ops::ProfileSide::On,
                Some(ProfileSide::Inside) => ops::ProfileSide::Inside,
                Some(ProfileSide::Outside) => ops::ProfileSide::Outside,
                None if laser => ops::ProfileSide::On,
                None => ops::ProfileSide::Outside,
            };
            // Crossing strokes make one outline: profile the union when they overlap.
            let union = std::sync::OnceLock::new();
            let region = || union.get_or_init(|| ctx.region(&items));
            let general = || ops::profile(region(), side, r, eps);
            let paths = ctx.routed(index, op, &name, &items, general, |its| {
                re_profile(its, side, r, ctx.tol)
            })?;
            let own = ctx.item_regions(&items);
            let sources = attribute(ctx, &items, &own, &paths);
            if side != ops::ProfileSide::On && r > 0.0 {
                let lost = lost_to_the_tool(region(), side, r, &paths, ctx.tol);
                let owners = attribute(
                    ctx,
                    &items,
                    &own,
                    &lost.iter().map(|l| l.0.clone()).collect::<Vec<_>>(),
                );
                let mut w = ctx.warnings.lock().unwrap_or_else(|e| e.into_inner());
                for ((_, message), item) in lost.into_iter().zip(owners) {
                    w.push((
                        index,
                        BuildWarning {
                            operation: name.clone(),
                            item: item.clone(),
                            message: format!("\"{item}\": {message}"),
                        },
                    ));
                }
            }
            let mut s = spec(
                ctx,
                design_index,
                name,
                TpKind::Profile,
                op,
                Geometry::Paths(paths),
                tool,
            );
            s.sources = sources;
            vec![s]
        }
        OperationKind::Channel => {
            let tool = ctx.tool(&mill);
            let r = ctx.radius(tool);
            let width = op
                .width
                .ok_or_else(|| op_err(ctx, index, op, "a channel needs `width`"))?;
            if 2.0 * r > width {
                return Err(op_err(
                    ctx,
                    index,
                    op,
                    format!(
                        "the tool ({:.3} wide) is wider than the channel ({width})",
                        2.0 * r
                    ),
                ));
            }
            // Per selected stroke: its index, its spine and its channel region (the
            // strokes' spine fits are independent: made in parallel, kept in order).
            let swept: Vec<(usize, Path, Region)> = items
                .par_iter()
                .filter_map(|&i| spine_of(ctx, i).map(|c| (i, c)))
                .map(|(i, c)| {
                    let (spine, region) = channel_swept(ctx, c, width);
                    (i, spine, region)
                })
                .collect();
            if swept.is_empty() && !items.is_empty() {
                let names: Vec<String> = items
                    .iter()
                    .map(|&i| format!("\"{}\"", ctx.outlines[i].name))
                    .collect();
                return Err(op_err(
                    ctx,
                    index,
                    op,
                    format!(
                        "a channel follows stroke spines, and none of {} is a stroke (shapes \
                         and circle sequences have no spine): select strokes, or cut shapes \
                         with `profile` or `fill`",
                        names.join(", ")
                    ),
                ));
            }
            let regions: Vec<Region> = swept.iter().map(|(_, _, r)| r.clone()).collect();
            // Crossing and touching channels merge into one pocket (a T-junction is one
            // channel network).
            let region = Region::union_keeping_arcs(&regions, ctx.tol);
            // Posts of material narrower than the tool (where strokes meet at sharp
            // angles) are cleared with the pocket: the tool could not leave them standing.
            let region = if laser {
                region
            } else {
                without_narrow_posts(&region, r, ctx.tol, eps)
            };
            let step = (STEPOVER * 2.0 * r).max(ctx.tol);
            // A channel the tool's width (within the tolerance on each wall) is a slot: one
            // pass along each spine. Offsetting its region by r would leave a sliver ring
            // that folds onto itself.
            let slot = !laser && width - 2.0 * r <= 2.0 * ctx.tol;
            let (paths, sources) = if slot {
                swept
                    .iter()
                    .map(|(i, spine, _)| (spine.clone(), ctx.outlines[*i].name.clone()))
                    .unzip()
            } else {
                let paths = if laser {
                    ops::profile(&region, ops::ProfileSide::On, 0.0, eps)
                } else {
                    ops::concentric(&region, r, step, r, 10_000, eps)
                };
                let owners: Vec<usize> = swept.iter().map(|(i, _, _)| *i).collect();
                let sources = attribute(ctx, &owners, &regions, &paths);
                (paths, sources)
            };
            let mut s = spec(
                ctx,
                design_index,
                name,
                TpKind::Channel,
                op,
                Geometry::Paths(paths),
                tool,
            );
            s.sources = sources;
            vec![s]
        }
        OperationKind::Backboard => {
            let tool = ctx.tool(&mill);
            let r = ctx.radius(tool);
            let mut regions = ctx.item_regions(&items);
            let margin = op.margin.unwrap_or(BACKBOARD_MARGIN_MM * ctx.per_mm);
            let rho = op.min_inner_radius.unwrap_or(r);
            // The board carries every channel cut into it at the margin: a channel wider
            // than its stroke (a flex channel with its clearance) is part of what the
            // margin is measured from.
            let channels = channel_regions(ctx, &items);
            let channel_outside = !channels.is_empty()
                && !Region::union(&regions, ctx.tol)
                    .offset(ctx.tol, eps)
                    .contains_samples_of(&channels);
            if channel_outside {
                regions.extend(channels);
            }
            let board = ops::backboard(&regions, margin, rho, ctx.tol, eps);
            // One board around the whole sign: pieces that lie apart are bridged.
            let bridge = op
                .bridge_width
                .unwrap_or(board::BRIDGE_WIDTH_MM * ctx.per_mm);
            let (board, bridges) = board::bridged(&board, bridge, rho, ctx.tol, eps);
            let corner = op.corner_radius.unwrap_or(0.0);
            let (board, _) = board::rounded(&board, corner, rho, ctx.tol, eps);
            let general = || ops::profile(&board, ops::ProfileSide::Outside, r, eps);
            let paths = ctx.routed(index, op, &name, &items, general, |its| match its {
                _ if channel_outside => Err(RouteRefusal::ChannelOutside),
                _ if !bridges.is_empty() => Err(RouteRefusal::Bridged(bridges.len())),
                _ if corner > 0.0 => Err(RouteRefusal::Rounded(corner)),
                [(_, it)] if (rho - r).abs() <= 1e-12 * (1.0 + r) => {
                    re_backboard(it, margin + r, ctx.tol)
                }
                [_] => Err(RouteRefusal::CornerRadius { rho, r }),
                _ => Err(RouteRefusal::Union(its.len())),
            })?;
            let mut v = Vec::new();
            if let Some(m) = &op.mounting_holes {
                let mounting = board::Mounting {
                    count: m.count as usize,
                    diameter: m.diameter,
                    inset: m.inset.unwrap_or(board::MOUNTING_INSET_MM * ctx.per_mm),
                    wall: board::MOUNTING_WALL_MM * ctx.per_mm,
                };
                let points = board::mounting_points(&board, &regions, mounting, ctx.tol, eps)
                    .map_err(|e| op_err(ctx, index, op, format!("mounting_holes: {e}")))?;
                let (mut circles, mut drills) = (Vec::new(), Vec::new());
                for h in ops::holes(&points, m.diameter, r) {
                    match h {
                        Hole::Circle(p) => circles.push(p),
                        Hole::Drill(p) => drills.push(p),
                    }
                }
                // Cut before the board's outline frees it; no tabs in a hole.
                let geometries = [
                    (
                        format!("{name} mounting drill"),
                        drills.is_empty(),
                        Geometry::Points(drills),
                    ),
                    (
                        format!("{name} mounting holes"),
                        circles.is_empty(),
                        Geometry::Paths(circles),
                    ),
                ];
                for (label, empty, geometry) in geometries {
                    if !empty {
                        let mut s =
                            spec(ctx, design_index, label, TpKind::Holes, op, geometry, tool);
                        s.tabs = None;
                        s.lead = Lead::None;
                        v.push(s);
                    }
                }
            }
            v.push(spec(
                ctx,
                design_index,
                name,
                TpKind::Backboard,
                op,
                Geometry::Paths(paths),
                tool,
            ));
            v
        }
        OperationKind::Holes => {
            let tool = ctx.tool(&mill);
            let r = ctx.radius(tool);
            let d = op
                .diameter
                .ok_or_else(|| op_err(ctx, index, op, "holes need `diameter`"))?;
            let at = op.at.unwrap_or_default();
            let mut points = Vec::new();
            let mut sources = Vec::new();
            // With a `[neon]` table: one hole at each end of each flex run, never at a
            // join inside a run (the runs' strokes selected by the operation).
            if let Some((_, runs)) = &ctx.neon {
                let strokes: Vec<usize> = items
                    .iter()
                    .filter_map(|&i| {
                        let name = &ctx.outlines[i].name;
                        ctx.design.stroke.iter().position(|s| &s.name == name)
                    })
                    .collect();
                let holes =
                    super::neon::run_hole_points(ctx.design, &ctx.strokes, runs, at, &strokes);
                (points, sources) = holes.into_iter().unzip();
            }
            for &i in items.iter().filter(|_| ctx.neon.is_none()) {
                let ends: Vec<DVec2> = if let Some(c) = spine_of(ctx, i) {
                    if c.is_closed() {
                        continue;
                    }
                    let (lo, hi) = c.domain();
                    vec![c.center(lo), c.center(hi)]
                } else {
                    let k = ctx
                        .design
                        .circles
                        .iter()
                        .position(|s| s.name == ctx.outlines[i].name);
                    match k.map(|k| &ctx.design.circles[k]) {
                        Some(seq) if !seq.closed && !seq.circles.is_empty() => {
                            let f = seq.circles[0];
                            let l = seq.circles[seq.circles.len() - 1];
                            vec![DVec2::new(f[0], f[1]), DVec2::new(l[0], l[1])]
                        }
                        _ => continue,
                    }
                };
                let chosen: Vec<DVec2> = match at {
                    HoleAt::Ends => ends,
                    HoleAt::Start => vec![ends[0]],
                    HoleAt::End => vec![ends[1]],
                };
                for p in chosen {
                    // A corner joins two pieces of one stroke: not a stroke end. Strokes
                    // that end at the same point (a letter's stem and bowl) get one hole.
                    let tol = 1e-9 * (1.0 + p.length());
                    if ctx.design.is_corner(p)
                        || points.iter().any(|q: &DVec2| q.distance(p) <= tol)
                    {
                        continue;
                    }
                    points.push(p);
                    sources.push(ctx.outlines[i].name.clone());
                }
            }
            let mut circles = Vec::new();
            let mut circle_src = Vec::new();
            let mut drills = Vec::new();
            let mut drill_src = Vec::new();
            for (h, s) in ops::holes(&points, d, r).into_iter().zip(sources) {
                match h {
                    Hole::Circle(p) => {
                        circles.push(p);
                        circle_src.push(s);
                    }
                    Hole::Drill(p) => {
                        drills.push(p);
                        drill_src.push(s);
                    }
                }
            }
            let mut v = Vec::new();
            if !drills.is_empty() {
                let mut s = spec(
                    ctx,
                    design_index,
                    format!("{name} drill"),
                    TpKind::Holes,
                    op,
                    Geometry::Points(drills),
                    tool,
                );
                s.sources = drill_src;
                v.push(s);
            }
            if !circles.is_empty() {
                let mut s = spec(
                    ctx,
                    design_index,
                    name,
                    TpKind::Holes,
                    op,
                    Geometry::Paths(circles),
                    tool,
                );
                s.sources = circle_src;
                v.push(s);
            }
            v
        }
        OperationKind::Fill => {
            let tool = ctx.tool(&mill);
            let r = ctx.radius(tool);
            let spacing = op
                .spacing
                .ok_or_else(|| op_err(ctx, index, op, "a fill needs `spacing`"))?;
            let angle = op.angle.unwrap_or(0.0).to_radians();
            let alternate = op.alternate.unwrap_or(true);
            let cross = op.cross_hatch.unwrap_or(false);
            fill_count_check(ctx, index, op, &items, angle, spacing)?;
            // Touching and crossing strokes are filled as one region (their union).
            let (paths, sources) = union_paths_with_sources(ctx, &items, |region| {
                // Keep the tool inside: hatch the region shrunk by the tool radius.
                let inner = if r > 0.0 {
                    region.offset(-r, eps)
                } else {
                    region.clone()
                };
                match op.pattern.unwrap_or_default() {
                    FillPattern::Hatch => {
                        let mut p = ops::hatch(&inner, angle, spacing, alternate, ctx.tol);
                        if cross {
                            p.extend(ops::hatch(
                                &inner,
                                angle + std::f64::consts::FRAC_PI_2,
                                spacing,
                                alternate,
                                ctx.tol,
                            ));
                        }
                        p
                    }
                    FillPattern::Concentric => ops::concentric(
                        region,
                        r.max(spacing / 2.0),
                        spacing,
                        r.max(spacing / 2.0),
                        ops::MAX_FILL_RINGS,
                        eps,
                    ),
                }
            });
            let mut s = spec(
                ctx,
                design_index,
                name,
                TpKind::Fill,
                op,
                Geometry::Paths(paths),
                tool,
            );
            s.sources = sources;
            vec![s]
        }
        OperationKind::Vcarve => {
            let tool = ctx.tool(&[ToolKind::Vbit]);
            let angle = op
                .angle
                .or(tool.filter(|t| t.kind == ToolKind::Vbit).map(|t| t.angle))
                .ok_or_else(|| {
                    op_err(
                        ctx,
                        index,
                        op,
                        "a V-carve needs `angle` or a V-bit in the machine profile",
                    )
                })?
                .to_radians();
            let max_depth = op.max_depth.or(op.depth).unwrap_or(f64::INFINITY);
            let step = VCARVE_STEP_MM * ctx.per_mm;
            let mut lines = Vec::new();
            let mut sources = Vec::new();
            let mut flats = Vec::new();
            let mut flat_src = Vec::new();
            for &i in &items {
                let Some(c) = spine_of(ctx, i) else { continue };
                let attrs = stroke_attributes(ctx, i, c)?;
                let ts = spine_params(c, step);
                let points: Vec<DVec3> = ts
                    .iter()
                    .map(|&t| {
                        let q = c.center(t);
                        let z = if laser {
                            0.0
                        } else if let Some(d) = &attrs.depth {
                            -d.eval(t).max(0.0).min(max_depth)
                        } else {
                            ops::vcarve_depth(c.radius(t), angle, max_depth)
                        };
                        DVec3::new(q.x, q.y, z)
                    })
                    .collect();
                let sample = |curve: &Option<BSpline<f64>>, scale: f64| -> Vec<f64> {
                    curve
                        .as_ref()
                        .map(|a| ts.iter().map(|&t| a.eval(t) * scale).collect())
                        .unwrap_or_default()
                };
                lines.push(AttrPolyline {
                    points,
                    feed: sample(&attrs.feed, 1.0),
                    power: sample(&attrs.power, 0.01),
                });
                sources.push(ctx.outlines[i].name.clone());
                // A `depth` attribute sets the depth itself: the flat clearing at the cap
                // (derived from the radius) would cut deeper than the spine, so none.
                if !laser && max_depth.is_finite() && attrs.depth.is_none() {
                    let region = Region::from_paths(&ctx.outlines[i].contours, ctx.tol);
                    let flat = ops::vcarve_flat_region(&region, angle, max_depth, eps);
                    let w = 2.0 * max_depth * (angle / 2.0).tan();
                    for p in ops::concentric(
                        &flat,
                        0.0,
                        (STEPOVER * w).max(ctx.tol),
                        w / 2.0,
                        10_000,
                        eps,
                    ) {
                        flats.push(p);
                        flat_src.push(ctx.outlines[i].name.clone());
                    }
                }
            }
            let mut s = spec(
                ctx,
                design_index,
                name.clone(),
                TpKind::VCarve,
                op,
                Geometry::AttrPolylines3(lines),
                tool,
            );
            s.sources = sources;
            let mut v = vec![s];
            if !flats.is_empty() {
                let mut f = spec(
                    ctx,
                    design_index,
                    format!("{name} flat"),
                    TpKind::VCarve,
                    op,
                    Geometry::Paths(flats),
                    tool,
                );
                f.depth = max_depth;
                f.sources = flat_src;
                v.push(f);
            }
            v
        }
    };
    Ok(out)
}

/// True for operations that clear material inside an area (as opposed to cutting along a
/// line that must stay where it is): their paths may cross each other inside one pocket.
fn clears(kind: TpKind) -> bool {
    matches!(
        kind,
        TpKind::Channel | TpKind::Fill | TpKind::Holes | TpKind::VCarve
    )
}

/// The pocket of every path and point of the clearing operations ([`clears`]): the
/// footprints of all of them (closed paths: the enclosed area grown by the tool radius;
/// open paths and points: the tool's disk swept along them, at least the tolerance wide,
/// and for hatch lines at least half the hatch spacing, the strip each line clears)
/// are joined where they overlap, and each connected component is one pocket, numbered
/// from 1.
/// Paths of one pocket overlap only where all of them remove material, so their crossings
/// are intended; cuts of profiles and backboards keep no group and are checked strictly.
fn assign_pockets(ctx: &Ctx, specs: &mut [OpSpec]) {
    let radius = |s: &OpSpec| {
        if s.kind == TpKind::VCarve {
            0.0
        } else {
            ctx.radius(ctx.tool(&[ToolKind::Endmill, ToolKind::Ballnose, ToolKind::Beam]))
        }
    };
    let reach = |r: f64| r.max(ctx.tol);
    let eps = ctx.tol * 0.1;
    // Representative point and what the footprint of each path or point is made of:
    // a closed path grown by the reach, or the polyline (a point: a tiny one) swept by it.
    enum Print<'a> {
        Closed(&'a Path),
        Swept(Vec<DVec2>),
    }
    let mut reps: Vec<(usize, usize, DVec2)> = Vec::new();
    let mut inputs: Vec<(Print<'_>, f64)> = Vec::new();
    for (si, s) in specs.iter().enumerate() {
        if !clears(s.kind) {
            continue;
        }
        // Hatch lines of one fill clear the strip between them: half the spacing (and a
        // hair) joins neighbouring lines into one pocket.
        let spacing = s
            .design_index
            .and_then(|k| ctx.design.operation.get(k))
            .filter(|_| s.kind == TpKind::Fill)
            .and_then(|op| op.spacing)
            .unwrap_or(0.0);
        let r = reach(radius(s)).max(0.5 * spacing + ctx.tol);
        match &s.geometry {
            Geometry::Paths(paths) => {
                for (k, p) in paths.iter().enumerate() {
                    reps.push((si, k, p.start().unwrap_or_default()));
                    let print = if p.closed {
                        Print::Closed(p)
                    } else {
                        Print::Swept(p.flatten(ctx.tol))
                    };
                    inputs.push((print, r));
                }
            }
            Geometry::Points(points) => {
                for (k, &q) in points.iter().enumerate() {
                    reps.push((si, k, q));
                    inputs.push((Print::Swept(vec![q, q + DVec2::X * eps]), r));
                }
            }
            Geometry::Polylines3(lines) => {
                for (k, l) in lines.iter().enumerate() {
                    let pts: Vec<DVec2> = l.iter().map(|p| p.truncate()).collect();
                    if let Some(&q) = pts.first() {
                        reps.push((si, k, q));
                        inputs.push((Print::Swept(pts), r));
                    }
                }
            }
            Geometry::AttrPolylines3(lines) => {
                for (k, l) in lines.iter().enumerate() {
                    let pts: Vec<DVec2> = l.points.iter().map(|p| p.truncate()).collect();
                    if let Some(&q) = pts.first() {
                        reps.push((si, k, q));
                        inputs.push((Print::Swept(pts), r));
                    }
                }
            }
        }
    }
    if reps.is_empty() {
        return;
    }
    // Connected components of overlapping footprints (union-find on pairwise
    // intersection, bounding boxes first): every footprint on its own, no big boolean union
    // that one odd input could spoil. The footprints are independent: made in parallel.
    use geo::{BoundingRect, Intersects};
    let polys: Vec<geo::MultiPolygon<f64>> = inputs
        .par_iter()
        .map(|(print, r)| {
            let fp = match print {
                Print::Closed(p) => {
                    let grown =
                        Region::from_paths(std::slice::from_ref(*p), ctx.tol).offset(*r, eps);
                    // A ring that encloses no area on its own (one traversed clockwise, a
                    // ring around an island, or one that touches itself) still clears the
                    // tool's disk swept along it.
                    if grown.is_empty() {
                        ops::swept_region(&p.flatten(ctx.tol), true, *r, ctx.tol)
                    } else {
                        grown
                    }
                }
                Print::Swept(pts) => ops::swept_region(pts, false, *r, ctx.tol),
            };
            fp.to_geo(ctx.tol)
        })
        .collect();
    let boxes: Vec<Option<geo::Rect<f64>>> = polys.iter().map(|p| p.bounding_rect()).collect();
    let mut parent: Vec<usize> = (0..polys.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for i in 0..polys.len() {
        for j in i + 1..polys.len() {
            let (Some(a), Some(b)) = (boxes[i], boxes[j]) else {
                continue;
            };
            if !a.intersects(&b) || root(&mut parent, i) == root(&mut parent, j) {
                continue;
            }
            if polys[i].intersects(&polys[j]) {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    // Pocket numbers from 1 in order of first appearance.
    let mut numbers: Vec<Option<u32>> = vec![None; polys.len()];
    let mut next = 1u32;
    let mut pocket_of = |k: usize| -> Option<u32> {
        if polys[k].0.is_empty() {
            return None;
        }
        let r = root(&mut parent, k);
        Some(*numbers[r].get_or_insert_with(|| {
            next += 1;
            next - 1
        }))
    };
    for (n, (si, k, _)) in reps.into_iter().enumerate() {
        let g = pocket_of(n);
        let s = &mut specs[si];
        let n = match &s.geometry {
            Geometry::Paths(p) => p.len(),
            Geometry::Points(p) => p.len(),
            Geometry::Polylines3(l) => l.len(),
            Geometry::AttrPolylines3(l) => l.len(),
        };
        if s.groups.len() != n {
            s.groups = vec![None; n];
        }
        s.groups[k] = g;
    }
}

/// Stroke attributes on the moves of G-code lasers: on profile, fill and channel cuts the
/// `power` and `feed` attributes of the cut's stroke replace the operation's values,
/// evaluated at the nearest spine parameter and quantised
/// ([`crate::toolpath::attrs`]: pieces of at most 0.5 mm or 50 tolerances, power in steps of 0.5 % of the
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
        let Some(c) = spine_of(ctx, i) else { continue };
        let a = stroke_attributes(ctx, i, c)?;
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
        step: (0.5 * ctx.per_mm).max(attrs::PIECE_TOLERANCES * ctx.tol),
        power_quantum: attrs::power_quantum(s_max, s_resolution),
        feed_quantum: (attrs::FEED_QUANTUM * max_feed).max(ctx.tol),
        tol: ctx.tol * 1e-3,
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

/// How a job will be placed ([`place_job`]): what fixes the machine's origin in design
/// coordinates before the cut order is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaceAt {
    /// The placement asked for.
    pub place: Place,
    /// Distance from the work area's edges with [`Place::LowerLeft`] (design units).
    pub margin: f64,
    /// Rounding inset (design units): see [`place_job`].
    pub inset: f64,
}

/// Grid (design units) the placed toolpath's coordinates are snapped to when the placement
/// moves the job. A design moved by D before placement reaches the same placed coordinates
/// only within the rounding of numbers of size D (ulp(10⁴) ≈ 1.8·10⁻¹², a few of them per
/// built point); a number that prints at a rounding tie (an arc's centre offset `I` at
/// exactly x.xxx5: the job's box corner placed at the inset, plus a tool radius of 1.5875
/// mm) would print either way. On this grid both land on the same double, far below the
/// program's last decimal (10⁻³ mm, 10⁻⁴ in) and above that noise for moves up to 10⁶ units.
pub const PLACE_GRID: f64 = 1e-9;

/// Most plans of one build placed by [`build_toolpath_placed`]: the first from the
/// placement of the geometry, one more when leads move the placed job, a last when that
/// moved the leads again.
const MAX_PLACE_ROUNDS: usize = 3;

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
    // `[neon] round_bends`: the strokes follow the rounded spines from here on.
    let rounded = match &design.neon {
        Some(n) if n.round_bends == Some(true) => Some(super::neon::round_bends(
            design,
            &n.flex(design.units),
            opts.tolerance,
        )?),
        _ => None,
    };
    let design = rounded.as_ref().map_or(design, |r| &r.design);
    let outline_opts = OutlineOptions {
        epsilon: opts.epsilon,
        tolerance: opts.tolerance,
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
        tol: opts.tolerance,
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
        (super::outline::cache::copies(strokes, opts.tolerance).into_iter())
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
        let (runs, m) = super::neon::split_marks(design, &ctx.strokes, runs, ctx.tol * 1e-3);
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
    if ctx.laser_arcs() {
        // A laser cuts what was flattened (unions of crossing outlines are polygons) as
        // arcs where its G-code takes them: runs of lines merged within what the union's
        // flattening left of the tolerance, so that flattening and merge together stay
        // within it (chords within ARC_UNION_FRACTION·tol of the exact outline, arcs within
        // (1 − ARC_UNION_FRACTION)·tol of the chords).
        let merge_tol = (1.0 - ARC_UNION_FRACTION) * ctx.tol;
        for s in &mut specs {
            if let Geometry::Paths(paths) = &mut s.geometry {
                *paths = paths
                    .par_iter()
                    .map(|p| merge_lines(p, merge_tol))
                    .collect();
            }
        }
    }
    assign_pockets(&ctx, &mut specs);
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
        let mut b = super::neon::bom(design, &ctx.strokes, runs, flex, ctx.tol * 1e-3, holes);
        b.set_marks(design, &marks);
        if let Some(r) = &rounded {
            b.set_rounding(&r.reports, r.warnings.clone());
        }
        b
    });
    let (mut toolpath, stats) = match at {
        Some(at) => plan_placed(
            &specs,
            profile,
            design.units.mm_per_unit(),
            at,
            opts.tolerance,
        ),
        None => plan(&specs, DVec2::ZERO, opts.tolerance),
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

/// [`plan`] of `specs` from the machine's origin of a job placed as `at` says, in design
/// coordinates: minus the shift [`placement_offset`] gives the box of the specs' geometry
/// ([`Geometry::bounds`], the same whatever the order). Leads (`lead_in`) can reach past
/// that box and so move the placed job: while the shift of the planned toolpath's box
/// differs from the one planned from by more than `tol`, the job is planned again from it
/// (at most [`MAX_PLACE_ROUNDS`] plans). Every step moves with the design, so a design
/// moved before placement gets the same order.
fn plan_placed(
    specs: &[OpSpec],
    profile: &Profile,
    design_mm_per_unit: f64,
    at: PlaceAt,
    tol: f64,
) -> (Toolpath, Vec<PlanStats>) {
    let Some(crate::geom::Aabb { min: lo, max: hi }) =
        (specs.iter().filter_map(|s| s.geometry.bounds())).reduce(crate::geom::Aabb::union)
    else {
        return plan(specs, DVec2::ZERO, tol);
    };
    let offset_of = |lo, hi| placement_offset(lo, hi, profile, design_mm_per_unit, at);
    let mut offset = offset_of(lo, hi);
    let mut planned = plan(specs, -offset, tol);
    for _ in 1..MAX_PLACE_ROUNDS {
        let s = planned.0.stats(DVec2::ZERO);
        let (lo, hi) = (
            DVec2::from_slice(&s.bbox_min),
            DVec2::from_slice(&s.bbox_max),
        );
        if !(lo.is_finite() && hi.is_finite()) {
            break;
        }
        let next = offset_of(lo, hi);
        if next.distance(offset) <= tol {
            break;
        }
        offset = next;
        planned = plan(specs, -offset, tol);
    }
    planned
}

/// The shift [`place_job`] gives a job whose box is `lo..hi` (design units) on `profile`:
/// none at the design's coordinates; the box's lower-left corner to the work area's plus
/// `margin + inset`; the box's centre to the work area's.
pub fn placement_offset(
    lo: DVec2,
    hi: DVec2,
    profile: &Profile,
    design_mm_per_unit: f64,
    at: PlaceAt,
) -> DVec2 {
    let (a_lo, a_hi) = work_area_xy(profile, design_mm_per_unit);
    match at.place {
        Place::Design => DVec2::ZERO,
        Place::LowerLeft => a_lo + DVec2::splat(at.margin + at.inset) - lo,
        Place::Center => 0.5 * (a_lo + a_hi) - 0.5 * (lo + hi),
    }
}

/// The work area's corners in xy (lower-left, upper-right), in design units.
fn work_area_xy(profile: &Profile, design_mm_per_unit: f64) -> (DVec2, DVec2) {
    let k = profile.units.mm_per_unit() / design_mm_per_unit;
    let wa = &profile.work_area;
    (
        DVec2::new(wa.x.min(), wa.y.min()) * k,
        DVec2::new(wa.x.max(), wa.y.max()) * k,
    )
}

/// Where a built job goes on the machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Place {
    /// The design's own coordinates.
    Design,
    /// The job's lower-left corner (tool paths included) at the work area's lower-left
    /// corner plus the margin: what svg2gcode and LaserGRBL do, and the default.
    LowerLeft,
    /// The job's centre at the work area's centre.
    Center,
}

impl Place {
    /// The name on the command line (`--place`).
    pub fn as_str(self) -> &'static str {
        match self {
            Place::Design => "design",
            Place::LowerLeft => "lower-left",
            Place::Center => "center",
        }
    }
}

/// Where a job went: the shift applied, the job's size and where it lies, in design units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Placement {
    /// The placement asked for.
    pub place: Place,
    /// Shift added to every coordinate.
    pub offset: [f64; 2],
    /// Size of the job (tool paths included).
    pub size: [f64; 2],
    /// Lower-left and upper-right corner of the placed job.
    pub min: [f64; 2],
    /// Upper-right corner of the placed job.
    pub max: [f64; 2],
    /// The design's scale factor (`--scale` or `--fit`), 1 when unscaled.
    pub scale: f64,
}

/// The design with every stroke, circle sequence and text scaled by `f` about the origin:
/// centres and radii of disks, points and circles; height, stroke width, anchor and letter
/// spacing of `[[text]]` not yet laid out (a loaded design has its text as strokes); the
/// corners at which loading split strokes (so that piece ends there stay joints, not stroke
/// ends that get neon holes); the `[neon]` table's `break_at` points. Operation settings
/// (channel width, hole diameter, depths, margins, bridge width, mounting holes) and the
/// flex's sizes are physical sizes of tools and material and stay as written.
pub fn scaled_design(design: &Design, f: f64) -> Design {
    let mut d = design.clone();
    let sc = |v: &mut [f64; 3]| {
        for x in v.iter_mut() {
            *x *= f;
        }
    };
    for s in &mut d.stroke {
        for list in [&mut s.disks, &mut s.points].into_iter().flatten() {
            list.iter_mut().for_each(sc);
        }
    }
    for c in &mut d.circles {
        c.circles.iter_mut().for_each(sc);
    }
    for t in &mut d.text {
        t.height *= f;
        t.width *= f;
        if let Some(at) = &mut t.at {
            at.iter_mut().for_each(|x| *x *= f);
        }
        if let Some(s) = &mut t.letter_spacing {
            *s *= f;
        }
    }
    for c in &mut d.corners {
        c.at.iter_mut().for_each(|x| *x *= f);
    }
    d.shape.iter_mut().for_each(|s| s.scale(f));
    // Where runs break is a place in the artwork (the flex's sizes are not).
    if let Some(points) = d.neon.as_mut().and_then(|n| n.break_at.as_mut()) {
        for p in points.iter_mut() {
            p.iter_mut().for_each(|x| *x *= f);
        }
    }
    d
}

/// Bounding box (min, max) of the outlines of a build (with the box of the disks of a
/// stroke cut only along its spine, [`ItemOutline::spine_box`]), in design units.
pub fn outline_bounds(outlines: &[ItemOutline], tol: f64) -> Option<(DVec2, DVec2)> {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for p in outlines.iter().flat_map(|o| o.contours.iter()) {
        for q in p.flatten(tol) {
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    for (a, b) in outlines.iter().filter_map(|o| o.spine_box) {
        lo = lo.min(a);
        hi = hi.max(b);
    }
    (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
}

/// Moves the built job as `place` says and checks that it fits the work area of `profile`
/// (in xy). `margin` (design units) keeps the job that far from the area's edges with
/// [`Place::LowerLeft`]; `inset` (design units, two units of the program's last decimal) more
/// keeps rounding from pushing an arc's extreme over the edge. A job that does not fit
/// fails with its size, the area's size and the option that would help.
pub fn place_job(
    built: &mut BuildResult,
    profile: &Profile,
    design_mm_per_unit: f64,
    place: Place,
    margin: f64,
    inset: f64,
    scale: f64,
) -> Result<Placement, JobError> {
    let s = built.toolpath.stats(DVec2::ZERO);
    if s.cuts == 0 || !s.bbox_min[0].is_finite() || !s.bbox_max[0].is_finite() {
        // Operations that came out empty are named: their strokes exist, but what they
        // cut is narrower than the tool (a fill of thin lettering with a 1/4" bit).
        let empty: Vec<String> = built
            .toolpath
            .operations
            .iter()
            .filter(|o| o.cuts.is_empty())
            .map(super::checked::operation_label)
            .collect();
        let msg = if empty.is_empty() {
            "the design gives nothing to cut: add strokes, or operations that apply to them"
                .to_string()
        } else {
            format!(
                "the design gives nothing to cut: {} came out empty, what it cuts being \
                 narrower than the tool of profile \"{}\": use a smaller tool, wider strokes \
                 or another operation",
                empty.join(", "),
                profile.name
            )
        };
        return Err(JobError::Options(msg));
    }
    let lo = DVec2::new(s.bbox_min[0], s.bbox_min[1]);
    let hi = DVec2::new(s.bbox_max[0], s.bbox_max[1]);
    let size = hi - lo;
    let (a_lo, a_hi) = work_area_xy(profile, design_mm_per_unit);
    let units = if (design_mm_per_unit - 1.0).abs() < 1e-12 {
        "mm"
    } else {
        "in"
    };
    super::size::check_fits(
        size,
        false,
        profile,
        design_mm_per_unit,
        place,
        margin,
        inset,
        scale,
    )?;
    let at = PlaceAt {
        place,
        margin,
        inset,
    };
    let offset = placement_offset(lo, hi, profile, design_mm_per_unit, at);
    let (plo, phi) = (lo + offset, hi + offset);
    if place == Place::Design
        && (plo.x < a_lo.x || plo.y < a_lo.y || phi.x > a_hi.x || phi.y > a_hi.y)
    {
        return Err(JobError::Options(format!(
            "at the design's coordinates the job spans x {:.2}..{:.2}, y {:.2}..{:.2} {units}, \
             outside the work area of profile \"{}\" (x {:.1}..{:.1}, y {:.1}..{:.1}): use \
             --place lower-left (the default) or --place center",
            plo.x, phi.x, plo.y, phi.y, profile.name, a_lo.x, a_hi.x, a_lo.y, a_hi.y
        )));
    }
    if offset != DVec2::ZERO {
        // Snapped to the placement grid: a design moved before placement differs here by
        // its rounding only, and must print the same numbers.
        built.toolpath = built
            .toolpath
            .mapped_xy(|p| ((p + offset) / PLACE_GRID).round() * PLACE_GRID);
        for o in &mut built.outlines {
            for p in &mut o.contours {
                *p = p.translated(offset);
            }
            o.spine_box = o.spine_box.map(|(lo, hi)| (lo + offset, hi + offset));
        }
    }
    Ok(Placement {
        place,
        offset: offset.to_array(),
        size: size.to_array(),
        min: plo.to_array(),
        max: phi.to_array(),
        scale,
    })
}

/// The scale factor that makes the job fit `w` × `h` (design units): the outlines scale
/// with the design, the rest of the job (tool offsets, channel widths, backboard margins)
/// does not, so the factor is (w − extra_x)/outline_w (likewise in y), the smaller of the
/// two. `job` and `outline` are the sizes at the current scale.
pub fn fit_scale(job: DVec2, outline: DVec2, w: f64, h: f64) -> Option<f64> {
    let extra = job - outline;
    let sx = (w - extra.x) / outline.x;
    let sy = (h - extra.y) / outline.y;
    let s = sx.min(sy);
    (s.is_finite() && s > 0.0).then_some(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use cavalier_contours::polyline::PlineSource;

    /// The square [x, x + a] × [y, y + a] as a closed path.
    fn square(x: f64, y: f64, a: f64) -> Path {
        let pts = [
            DVec2::new(x, y),
            DVec2::new(x + a, y),
            DVec2::new(x + a, y + a),
            DVec2::new(x, y + a),
        ];
        Path::polyline(&pts, true)
    }

    /// Areas of the holes (posts of material) of a region.
    fn post_areas(region: &Region) -> Vec<f64> {
        region
            .contours
            .iter()
            .map(|c| c.area())
            .filter(|a| *a < 0.0)
            .map(|a| -a)
            .collect()
    }

    /// A post narrower than the tool is cleared with the pocket; a wider one stays, with
    /// its corners rounded by the tool: a square post of side a keeps a² − (4 − π)·r²
    /// (the opening of a square by a disk of radius r).
    #[test]
    fn narrow_posts_are_cleared_and_wide_ones_kept() {
        let (r, tol) = (1.5875, 1e-3);
        let eps = tol * 0.1;
        let narrow = Region::from_paths(&[square(0.0, 0.0, 20.0), square(9.0, 9.0, 2.0)], tol);
        assert_eq!(post_areas(&narrow).len(), 1);
        let cleared = without_narrow_posts(&narrow, r, tol, eps);
        assert!(post_areas(&cleared).is_empty());
        assert!((cleared.area() - 400.0).abs() < 1e-6 * 400.0);

        let a = 6.0;
        let wide = Region::from_paths(&[square(0.0, 0.0, 20.0), square(7.0, 7.0, a)], tol);
        let kept = without_narrow_posts(&wide, r, tol, eps);
        let posts = post_areas(&kept);
        assert_eq!(posts.len(), 1);
        let want = a * a - (4.0 - std::f64::consts::PI) * r * r;
        assert!(
            (posts[0] - want).abs() < 1e-6 * want,
            "{} vs {want}",
            posts[0]
        );
        // No post left is narrower than the tool: each one still holds a disk of radius r
        // (shrunk by r it is not empty).
        for c in kept.contours.iter().filter(|c| c.area() < 0.0) {
            let post = Region::from_contours(vec![c.clone()]);
            assert!(!post.offset(-(r - tol), eps).is_empty());
        }
    }
}
