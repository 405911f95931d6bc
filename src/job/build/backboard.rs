//! `backboard` operations: a board around the selected items at the margin (channels
//! included), bridged into one piece, corners rounded, with mounting holes.

use super::super::JobError;
use super::super::re_route::{RouteRefusal, re_backboard};
use super::super::tolerances::SAME_RADIUS_REL;
use super::channel::channel_regions;
use super::ctx::{Ctx, MILL, OpAt, op_err, spec};
use crate::design::Operation;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::board;
use crate::toolpath::cut::Lead;
use crate::toolpath::ops::{self, Hole};
use crate::toolpath::plan::{Geometry, OpSpec};
use crate::toolpath::region::Region;

/// Default backboard margin in millimetres.
const BACKBOARD_MARGIN_MM: f64 = 5.0;

/// The specs of a `backboard` operation: its mounting holes (drilled and circled) first,
/// then the board's outline.
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
    let mut regions = ctx.item_regions(&items);
    let margin = op.margin.unwrap_or(BACKBOARD_MARGIN_MM * ctx.per_mm);
    let rho = op.min_inner_radius.unwrap_or(r);
    // The board carries every channel cut into it at the margin: a channel wider
    // than its stroke (a flex channel with its clearance) is part of what the
    // margin is measured from.
    let channels = channel_regions(ctx, &items);
    let channel_outside = !channels.is_empty()
        && !Region::union(&regions, ctx.tol.fit)
            .offset(ctx.tol.fit, eps)
            .contains_samples_of(&channels);
    if channel_outside {
        regions.extend(channels);
    }
    let board = ops::backboard(&regions, margin, rho, ctx.tol.fit, eps);
    // One board around the whole sign: pieces that lie apart are bridged.
    let bridge = op
        .bridge_width
        .unwrap_or(board::BRIDGE_WIDTH_MM * ctx.per_mm);
    let (board, bridges) = board::bridged(&board, bridge, rho, ctx.tol.fit, eps);
    let corner = op.corner_radius.unwrap_or(0.0);
    let (board, _) = board::rounded(&board, corner, rho, ctx.tol.fit, eps);
    let general = || ops::profile(&board, ops::ProfileSide::Outside, r, eps);
    let paths = ctx.routed(index, op, &name, &items, general, |its| match its {
        _ if channel_outside => Err(RouteRefusal::ChannelOutside),
        _ if !bridges.is_empty() => Err(RouteRefusal::Bridged(bridges.len())),
        _ if corner > 0.0 => Err(RouteRefusal::Rounded(corner)),
        [(_, it)] if (rho - r).abs() <= SAME_RADIUS_REL * (1.0 + r) => {
            re_backboard(it, margin + r, ctx.tol.fit)
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
        let points = board::mounting_points(&board, &regions, mounting, ctx.tol.fit, eps)
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
                let mut s = spec(ctx, design_index, label, TpKind::Holes, op, geometry, tool);
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
    Ok(v)
}
