//! The build context ([`Ctx`]): the design, the machine profile, the items' outlines and
//! regions, the tolerances by role, and what every operation kind asks of them (the
//! items an operation selects, its tool, feeds and power, the route of a profile, the
//! [`OpSpec`] of its geometry).

use super::super::JobError;
use super::super::neon::Run;
use super::super::outline::ItemOutline;
use super::super::outline::re_interp;
use super::super::re_route::{ReItem, RouteNote, RouteRefusal};
use super::super::tolerances::{Tolerances, tool_of};
use super::{BuildWarning, DEFAULT_PROFILE_DEPTH_MM};
use crate::dbsc::DiskBSpline;
use crate::design::{Design, Operation, OperationKind, OutlineMethod, Selection, Tags};
use crate::geom::{DVec2, Path};
use crate::machine::{MachineKind, Profile, Tool, ToolKind};
use crate::par::prelude::*;
use crate::skin::re::Interp;
use crate::spline::BSpline;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::cut::{Lead, Tabs};
use crate::toolpath::plan::{Geometry, OpSpec};
use crate::toolpath::re_route::SegCounts;
use crate::toolpath::region::Region;
use std::collections::HashMap;
use std::sync::Mutex;

/// Tools that cut along or inside an outline: a router's end mills, a laser's beam.
pub(super) const MILL: [ToolKind; 3] = [ToolKind::Endmill, ToolKind::Ballnose, ToolKind::Beam];
/// Tools a router engraves a line with: a V-bit when it has one, else a cutter.
pub(super) const ENGRAVE: [ToolKind; 3] = [ToolKind::Vbit, ToolKind::Endmill, ToolKind::Ballnose];

/// One operation being built: where it is in the design and what it selects.
pub(super) struct OpAt {
    /// Its number in messages (0-based; shown 1-based).
    pub index: usize,
    /// Its index in the design (none for a default operation of a design without any).
    pub design_index: Option<usize>,
    /// The items it selects ([`Ctx::selected`]).
    pub items: Vec<usize>,
    /// Its name in the toolpath ("profile 1").
    pub name: String,
}

/// Everything the operations of one build share.
pub(super) struct Ctx<'a> {
    pub(super) design: &'a Design,
    pub(super) profile: &'a Profile,
    pub(super) strokes: Vec<DiskBSpline>,
    /// Index in `design.stroke` (and `strokes`) of each stroke, by name.
    pub(super) stroke_index: HashMap<&'a str, usize>,
    /// Layer and colour of each stroke and shape, by name.
    pub(super) tags: HashMap<&'a str, Tags<'a>>,
    pub(super) outlines: Vec<ItemOutline>,
    pub(super) tol: Tolerances,
    /// Design units per millimetre.
    pub(super) per_mm: f64,
    /// Design units per profile unit (tool sizes and feeds are in the profile's units).
    pub(super) k: f64,
    /// The build's default route.
    pub(super) method: OutlineMethod,
    /// RE/MPH skins of every item, per interpolant used by the build.
    pub(super) re: Vec<(Interp, Vec<Result<ReItem, RouteRefusal>>)>,
    /// Route notes with the number of the operation that took them (operations are built
    /// in parallel; the notes are put in operation order at the end).
    pub(super) routes: Mutex<Vec<(usize, RouteNote)>>,
    /// The flex and its runs, for a design with a `[neon]` table.
    pub(super) neon: Option<(crate::design::Flex, Vec<Run>)>,
    /// Per outline, the stroke it is a translated copy of and the translation, where its
    /// outline is that stroke's translated ([`super::super::outline::cache`]).
    pub(super) copy_of: Vec<Option<(usize, DVec2)>>,
    /// Per outline its region, made once when first asked for.
    pub(super) regions: Vec<std::sync::OnceLock<Region>>,
    /// Warnings with the number of the operation that gave them.
    pub(super) warnings: Mutex<Vec<(usize, BuildWarning)>>,
}

impl Ctx<'_> {
    /// Records the route operation `index` took.
    pub(super) fn note_route(&self, index: usize, note: RouteNote) {
        self.routes
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push((index, note));
    }
}

pub(super) fn op_err(
    ctx: &Ctx,
    index: usize,
    op: &Operation,
    message: impl Into<String>,
) -> JobError {
    JobError::Operation {
        file: ctx.design.file.clone(),
        index,
        kind: op.kind.as_str().to_string(),
        message: message.into(),
    }
}

impl Ctx<'_> {
    /// Whether the machine is a laser (of either kind), not a router.
    pub(super) fn laser(&self) -> bool {
        !matches!(self.profile.kind, MachineKind::Router)
    }

    /// The items an operation applies to, in item order: those its `strokes`, `layers` or
    /// `colors` name, all when it gives none ([`Selection`]).
    pub(super) fn selected(&self, op: &Operation) -> Vec<usize> {
        let sel = Selection::of(op);
        (0..self.outlines.len())
            .filter(|&i| self.selects(&sel, &self.outlines[i].name))
            .collect()
    }

    /// Whether `sel` selects the item named `name` (by its name, layer or colour).
    pub(super) fn selects(&self, sel: &Selection, name: &str) -> bool {
        let tags = self.tags.get(name).copied().unwrap_or_default();
        sel.selects(name, tags)
    }

    /// Per stroke of the design, whether `ops` cut it only along its spine: some operation
    /// selects it and every one that does is a `line` ([`line_paths`]). Such a stroke needs
    /// no skin ([`super::super::outline::spine_only_outline`]).
    pub(super) fn spine_only(&self, ops: &[Operation]) -> Vec<bool> {
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

    /// The operations of a design without any ([`super::super::check::operations_of`]: a drawing
    /// item by item, hairlines as lines; any other design one profile around the union of
    /// everything). Router profiles are [`DEFAULT_PROFILE_DEPTH_MM`] deep.
    pub(super) fn default_ops(&self) -> Vec<Operation> {
        let mut ops = super::super::check::operations_of(self.design, self.tol.hairline);
        for op in &mut ops {
            if !self.laser() && op.kind == OperationKind::Profile {
                op.depth = Some(DEFAULT_PROFILE_DEPTH_MM * self.per_mm);
            }
        }
        ops
    }

    /// The region of each item's outline (arcs fitted within the build tolerance), made in
    /// parallel and kept in order.
    pub(super) fn item_regions(&self, items: &[usize]) -> Vec<Region> {
        items
            .par_iter()
            .map(|&i| self.item_region(i).clone())
            .collect()
    }

    /// The region of item `i`'s outline, made once: a copy's is its original's, translated.
    pub(super) fn item_region(&self, i: usize) -> &Region {
        self.regions[i].get_or_init(|| match self.copy_of.get(i).copied().flatten() {
            Some((r, d)) => self.item_region(r).translated(d),
            None => Region::from_paths(&self.outlines[i].contours, self.tol.fit),
        })
    }

    pub(super) fn region(&self, items: &[usize]) -> Region {
        union_of(&self.item_regions(items), self.tol.union)
    }

    /// The first tool of one of the `want` kinds, else the profile's first tool.
    pub(super) fn tool(&self, want: &[ToolKind]) -> Option<&Tool> {
        tool_of(self.profile, want)
    }

    /// Refuses a router operation the machine cannot cut: one without `depth` (a V-carve
    /// and a line have defaults) and one the profile has no tool for ([`Ctx::tool_for`];
    /// a V-carve finds its angle itself). A laser cuts any.
    pub(super) fn router_can_cut(&self, index: usize, op: &Operation) -> Result<(), JobError> {
        if self.laser() {
            return Ok(());
        }
        let depth_optional = matches!(op.kind, OperationKind::Vcarve | OperationKind::Line);
        if op.depth.is_none() && !depth_optional {
            return Err(op_err(self, index, op, "a router operation needs `depth`"));
        }
        let want: &[ToolKind] = match op.kind {
            OperationKind::Line => &ENGRAVE,
            _ => &MILL,
        };
        if !matches!(op.kind, OperationKind::Vcarve) {
            self.tool_for(index, op, want)?;
        }
        Ok(())
    }

    /// The tool for operation `index`: on a router one of the `want` kinds must exist (a
    /// router cannot cut without a cutter, and compensating by a V-bit's shank for an end
    /// mill's cut would gouge); a laser may have no tool entry (kerf 0).
    pub(super) fn tool_for(
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
    pub(super) fn default_power(&self) -> f64 {
        match &self.profile.laser {
            Some(l) if self.laser() => l.default_power() / 100.0,
            _ => 1.0,
        }
    }

    /// Air assist of an operation: its own `air_assist`, else the laser profile's default.
    pub(super) fn air_assist(&self, op: &Operation) -> bool {
        op.air_assist.unwrap_or_else(|| {
            self.profile
                .laser
                .as_ref()
                .is_some_and(|l| l.air_assist && self.laser())
        })
    }

    /// Compensation radius of `tool` in design units (0 without a tool).
    pub(super) fn radius(&self, tool: Option<&Tool>) -> f64 {
        tool.map(|t| t.radius() * self.k).unwrap_or(0.0)
    }

    pub(super) fn default_feed(&self) -> f64 {
        0.5 * self.profile.max_feed.x.min(self.profile.max_feed.y) * self.k
    }

    /// The paths of a profile or backboard by the operation's route: the MAT route
    /// (`exact`, given each selected item's name and RE/MPH skin) when the operation or the
    /// build asks for re/mph and every item has an exact skin, otherwise `general`; the
    /// route taken and the reason for a fallback are noted for the build summary.
    pub(super) fn routed(
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

    pub(super) fn plunge_feed(&self) -> f64 {
        self.profile
            .router
            .as_ref()
            .map(|r| r.plunge_feed * self.k)
            .unwrap_or_else(|| self.default_feed())
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) fn spec(
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
pub(super) fn union_paths_with_sources(
    ctx: &Ctx,
    items: &[usize],
    f: impl Fn(&Region) -> Vec<Path>,
) -> (Vec<Path>, Vec<String>) {
    let regions = ctx.item_regions(items);
    let paths = f(&union_of(&regions, ctx.tol.union));
    let sources = attribute(ctx, items, &regions, &paths);
    (paths, sources)
}

/// The union of `regions` within `tol`; a single region as it is.
pub(super) fn union_of(regions: &[Region], tol: f64) -> Region {
    match regions {
        [one] => one.clone(),
        _ => Region::union(regions, tol),
    }
}

/// The item each path comes from: the item `items[k]` of the first of `regions` that holds
/// the path's first point, or of the nearest one (`items` and `regions` pair up). Regions
/// whose bounding box (arcs included) misses the point are not asked.
pub(super) fn attribute(
    ctx: &Ctx,
    items: &[usize],
    regions: &[Region],
    paths: &[Path],
) -> Vec<String> {
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
pub(super) fn box_distance(lo: DVec2, hi: DVec2, q: DVec2) -> f64 {
    (lo - q).max(q - hi).max(DVec2::ZERO).length()
}

/// Index of the region whose vertices come nearest to `q` (the first of equals); regions
/// whose box (`boxes`, holding their vertices) is farther than the best so far are skipped.
pub(super) fn nearest_region(
    regions: &[Region],
    boxes: &[Option<(DVec2, DVec2)>],
    q: DVec2,
) -> usize {
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

pub(super) fn spine_of<'a>(ctx: &'a Ctx, item: usize) -> Option<&'a DiskBSpline> {
    let name = ctx.outlines[item].name.as_str();
    ctx.stroke_index.get(name).map(|&k| &ctx.strokes[k])
}

/// The attribute curves of the stroke behind outline item `item` (none for circle
/// sequences): each channel's control values blended with the stroke's own basis,
/// a(t) = Σ N_i(t)·a_i (wu-2021 eq. 18), so an attribute follows the disks like the radius.
#[derive(Default)]
pub(super) struct StrokeAttributes {
    /// Power in percent of the machine's maximum.
    pub(super) power: Option<BSpline<f64>>,
    /// Depth below the surface (positive, design units).
    pub(super) depth: Option<BSpline<f64>>,
    /// Feed in design units per minute.
    pub(super) feed: Option<BSpline<f64>>,
}

pub(super) fn stroke_attributes(
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
