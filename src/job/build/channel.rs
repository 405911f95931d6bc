//! `channel` operations: a pocket of the operation's width along each selected stroke's
//! spine (a slot where the channel is the tool's width), and the channels' regions the
//! backboard carries.

use super::super::JobError;
use super::super::tolerances::Tolerances;
use super::STEPOVER;
use super::ctx::{Ctx, MILL, OpAt, op_err, spec};
use super::ctx::{attribute, spine_of};
use crate::dbsc::DiskBSpline;
use crate::design::Operation;
use crate::design::OperationKind;
use crate::geom::Path;
use crate::par::prelude::*;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::ops;
use crate::toolpath::plan::{Geometry, OpSpec};
use crate::toolpath::region::Region;
use crate::toolpath::swept::swept_arc_region;

/// The swept regions of the design's channel operations along the strokes among `items`
/// (the strokes a backboard carries), as polygons ([`channel_polygon`]): the board tests
/// their vertices and unions them with its outlines, which flattens them anyway.
pub(super) fn channel_regions(ctx: &Ctx, items: &[usize]) -> Vec<Region> {
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
    let eps = ctx.tol.offset;
    let arcs = crate::toolpath::line::spine_pline(c, ctx.tol.fit).and_then(|pline| {
        let region = swept_arc_region(&pline, width / 2.0, eps)?;
        Some((crate::toolpath::region::path_from_pline(&pline), region))
    });
    arcs.unwrap_or_else(|| channel_polygon(ctx, c, width))
}

/// A channel of `width` along a stroke's spine flattened within the build tolerance, and the
/// buffer of that polyline by width/2 (a polygon).
fn channel_polygon(ctx: &Ctx, c: &DiskBSpline, width: f64) -> (Path, Region) {
    let pts = crate::dbsc::flatten::flatten_spine(c, ctx.tol.fit);
    let region = ops::swept_region(&pts, c.is_closed(), width / 2.0, ctx.tol.fit);
    (Path::polyline(&pts, c.is_closed()), region)
}

/// A pocket without the posts of material narrower than a tool of radius `r`: the
/// morphological closing (R ⊕ D_r) ⊖ D_r (Serra, *Image Analysis and Mathematical
/// Morphology*, 1982, ch. II), the region grown and then shrunk by `r`. It contains R, and
/// every part of the complement it gives up is narrower than the tool's diameter (no disk
/// D_r fits in it); posts and notches a disk of radius `r` fits in stay. The offsets are
/// good to `tol.offset`; should they fail (a result that does not hold R's area within
/// `tol.fit` per unit of perimeter), R is kept as it is.
fn without_narrow_posts(region: &Region, r: f64, tol: &Tolerances) -> Region {
    if r <= 0.0 || region.is_empty() {
        return region.clone();
    }
    let closed = region.offset(r, tol.offset).offset(-r, tol.offset);
    if closed.is_empty() || closed.area() < region.area() - tol.fit * region.perimeter() {
        region.clone()
    } else {
        closed
    }
}

/// The spec of a `channel` operation.
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
    let region = Region::union_keeping_arcs(&regions, ctx.tol.fit);
    // Posts of material narrower than the tool (where strokes meet at sharp
    // angles) are cleared with the pocket: the tool could not leave them standing.
    let region = if laser {
        region
    } else {
        without_narrow_posts(&region, r, &ctx.tol)
    };
    let step = (STEPOVER * 2.0 * r).max(ctx.tol.fit);
    // A channel the tool's width (within the tolerance on each wall) is a slot: one
    // pass along each spine. Offsetting its region by r would leave a sliver ring
    // that folds onto itself.
    let slot = !laser && width - 2.0 * r <= 2.0 * ctx.tol.fit;
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
    Ok(vec![s])
}

#[cfg(test)]
mod tests {
    use super::super::super::tolerances::OFFSET_OF_FIT;
    use super::*;
    use crate::geom::DVec2;
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
        let eps = tol * OFFSET_OF_FIT;
        // Only `fit` and `offset` play a part here.
        let tols = Tolerances {
            skin: tol,
            fit: tol,
            offset: eps,
            length: tol,
            union: tol,
            merge: tol,
            hairline: 0.0,
        };
        let narrow = Region::from_paths(&[square(0.0, 0.0, 20.0), square(9.0, 9.0, 2.0)], tol);
        assert_eq!(post_areas(&narrow).len(), 1);
        let cleared = without_narrow_posts(&narrow, r, &tols);
        assert!(post_areas(&cleared).is_empty());
        assert!((cleared.area() - 400.0).abs() < 1e-6 * 400.0);

        let a = 6.0;
        let wide = Region::from_paths(&[square(0.0, 0.0, 20.0), square(7.0, 7.0, a)], tol);
        let kept = without_narrow_posts(&wide, r, &tols);
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
