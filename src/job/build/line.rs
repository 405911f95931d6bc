//! `line` operations: a stroke's spine, a shape's contours, a circle sequence's centres
//! cut along once ([`crate::toolpath::line`]), or the visible boundaries between inks
//! ([`crate::toolpath::inks`]); pieces of a stroke split at corners are joined back.

use super::super::JobError;
use super::LINE_DEPTH_MM;
use super::ctx::{Ctx, MILL, OpAt, spec};
use super::ctx::{ENGRAVE, spine_of};
use crate::design::LineBoundaries;
use crate::design::Operation;
use crate::geom::{DVec2, Path};
use crate::par::prelude::*;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::plan::{Geometry, OpSpec};
use std::collections::HashMap;

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
        return vec![spine_path(c, ctx.tol.fit)];
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
    for b in inner_boundaries(&painted, ctx.tol.fit, ctx.tol.hairline) {
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

/// The specs of a `line` operation: per selected item its paths, or the inner boundaries
/// between the items' inks; a router cuts [`LINE_DEPTH_MM`] deep unless `depth` says.
pub(super) fn specs(ctx: &Ctx, at: OpAt, op: &Operation) -> Result<Vec<OpSpec>, JobError> {
    let OpAt {
        index: _,
        design_index,
        items,
        name,
    } = at;
    let laser = ctx.laser();
    let tool = if laser {
        ctx.tool(&MILL)
    } else {
        ENGRAVE
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
    Ok(vec![s])
}
