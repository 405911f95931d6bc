//! `holes` operations: a hole at the ends of open strokes and circle sequences (with a
//! `[neon]` table, at the ends of each flex run), drilled or circled by the tool.

use super::super::JobError;
use super::super::tolerances::SAME_POINT_REL;
use super::ctx::spine_of;
use super::ctx::{Ctx, MILL, OpAt, op_err, spec};
use crate::design::HoleAt;
use crate::design::Operation;
use crate::geom::DVec2;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::ops::{self, Hole};
use crate::toolpath::plan::{Geometry, OpSpec};

/// The specs of a `holes` operation: the drilled holes, then the circled ones.
pub(super) fn specs(ctx: &Ctx, at: OpAt, op: &Operation) -> Result<Vec<OpSpec>, JobError> {
    let OpAt {
        index,
        design_index,
        items,
        name,
    } = at;
    let tool = ctx.tool(&MILL);
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
            super::super::neon::run_hole_points(ctx.design, &ctx.strokes, runs, at, &strokes);
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
            let tol = SAME_POINT_REL * (1.0 + p.length());
            if ctx.design.is_corner(p) || points.iter().any(|q: &DVec2| q.distance(p) <= tol) {
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
    Ok(v)
}
