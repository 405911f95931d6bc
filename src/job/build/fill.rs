//! `fill` operations: hatching or concentric rings inside the union of the selected items,
//! refused before any is made when the spacing would make too many.

use super::super::JobError;
use super::ctx::union_paths_with_sources;
use super::ctx::{Ctx, MILL, OpAt, op_err, spec};
use crate::design::FillPattern;
use crate::design::Operation;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::ops;
use crate::toolpath::plan::{Geometry, OpSpec};

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

/// The spec of a `fill` operation.
pub(super) fn specs(ctx: &Ctx, at: OpAt, op: &Operation) -> Result<Vec<OpSpec>, JobError> {
    let OpAt {
        index,
        design_index,
        items,
        name,
    } = at;
    let eps = ctx.tol.offset;
    let tool = ctx.tool(&MILL);
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
                let mut p = ops::hatch(&inner, angle, spacing, alternate, ctx.tol.fit);
                if cross {
                    p.extend(ops::hatch(
                        &inner,
                        angle + std::f64::consts::FRAC_PI_2,
                        spacing,
                        alternate,
                        ctx.tol.fit,
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
    Ok(vec![s])
}
