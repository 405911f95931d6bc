//! `profile` operations: around, inside or on the selected items' outlines (their union
//! where they overlap), by the skin or the exact MAT route, with a warning for every
//! feature the tool cannot follow.

use super::super::JobError;
use super::super::re_route::re_profile;
use super::super::tolerances::Tolerances;
use super::BuildWarning;
use super::ctx::attribute;
use super::ctx::{Ctx, MILL, OpAt, spec};
use crate::design::Operation;
use crate::design::ProfileSide;
use crate::geom::{DVec2, Path};
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::ops;
use crate::toolpath::plan::{Geometry, OpSpec};
use crate::toolpath::region::Region;

/// The contours of `region` (holes for an outside profile, material for an inside one)
/// that the tool of radius `r` cannot follow, each with a message: the offset of the
/// contour left no path inside it (the feature vanished: it is narrower than the tool),
/// or several (a waist narrower than the tool split it and is not cut). A contour's width
/// is given as its mean width 2·A/P (area over half the perimeter: the width of a thin
/// strip, the diameter of a disk). `paths` are the profile's paths: a hole's offsets run
/// counter-clockwise (region contours reversed), material's clockwise (flattened within
/// `tol.fit` to tell which). A lobe lost
/// while the rest of the contour keeps one path is not caught.
fn lost_to_the_tool(
    region: &Region,
    side: ops::ProfileSide,
    r: f64,
    paths: &[Path],
    tol: &Tolerances,
) -> Vec<(Path, String)> {
    use cavalier_contours::core::math::Vector2;
    use cavalier_contours::polyline::PlineSource;
    let holes = side == ops::ProfileSide::Outside;
    let starts: Vec<(DVec2, bool)> = paths
        .iter()
        .filter_map(|p| {
            let area = crate::toolpath::region::pline_from_path(p, tol.fit).area();
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
        out.push((crate::toolpath::region::path_from_pline(c), message));
    }
    out
}

/// The spec of a `profile` operation (side: the operation's, else on the line for a laser
/// and outside for a router).
pub(super) fn specs(ctx: &Ctx, at: OpAt, op: &Operation) -> Result<Vec<OpSpec>, JobError> {
    let OpAt {
        index,
        design_index,
        items,
        name,
    } = at;
    let laser = ctx.laser();
    let eps = ctx.tol.offset;
    let tool = ctx.tool(&MILL);
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
        re_profile(its, side, r, ctx.tol.fit)
    })?;
    let own = ctx.item_regions(&items);
    let sources = attribute(ctx, &items, &own, &paths);
    if side != ops::ProfileSide::On && r > 0.0 {
        let lost = lost_to_the_tool(region(), side, r, &paths, &ctx.tol);
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
    Ok(vec![s])
}
