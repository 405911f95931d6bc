//! `vcarve` operations: a V-bit along each selected stroke's spine at the depth its radius
//! (or its `depth` attribute) gives, with the flat bottom cleared where `max_depth` caps it;
//! a laser engraves the spine with the attribute power and feed.

use super::super::JobError;
use super::STEPOVER;
use super::ctx::{Ctx, OpAt, op_err, spec};
use super::ctx::{spine_of, stroke_attributes};
use crate::dbsc::DiskBSpline;
use crate::design::Operation;
use crate::machine::ToolKind;
use crate::spline::BSpline;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::ops;
use crate::toolpath::plan::AttrPolyline;
use crate::toolpath::plan::{Geometry, OpSpec};
use crate::toolpath::region::Region;
use glam::DVec3;

/// Spacing of V-carve samples along the spine, in millimetres: the chord sagitta
/// s²/(8ρ) stays below 8 µm wherever the spine's curvature radius ρ ≥ 1 mm.
const VCARVE_STEP_MM: f64 = 0.25;

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

/// The specs of a `vcarve` operation: the V-carve along the spines, then the flat clearing.
pub(super) fn specs(ctx: &Ctx, at: OpAt, op: &Operation) -> Result<Vec<OpSpec>, JobError> {
    let OpAt {
        index,
        design_index,
        items,
        name,
    } = at;
    let laser = ctx.laser();
    let eps = ctx.tol.offset;
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
            let region = Region::from_paths(&ctx.outlines[i].contours, ctx.tol.fit);
            let flat = ops::vcarve_flat_region(&region, angle, max_depth, eps);
            let w = 2.0 * max_depth * (angle / 2.0).tan();
            for p in ops::concentric(
                &flat,
                0.0,
                (STEPOVER * w).max(ctx.tol.fit),
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
    Ok(v)
}
