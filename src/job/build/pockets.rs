//! Pockets: the clearing operations' paths and points grouped into the connected areas
//! they clear together, so that the planner and the checker allow their crossings.

use super::ctx::{Ctx, MILL};
use crate::geom::{DVec2, Path};
use crate::par::prelude::*;
use crate::toolpath::OperationKind as TpKind;
use crate::toolpath::ops;
use crate::toolpath::plan::{Geometry, OpSpec};
use crate::toolpath::region::Region;

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
pub(super) fn assign_pockets(ctx: &Ctx, specs: &mut [OpSpec]) {
    let radius = |s: &OpSpec| {
        if s.kind == TpKind::VCarve {
            0.0
        } else {
            ctx.radius(ctx.tool(&MILL))
        }
    };
    let reach = |r: f64| r.max(ctx.tol.fit);
    let eps = ctx.tol.offset;
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
        let r = reach(radius(s)).max(0.5 * spacing + ctx.tol.fit);
        match &s.geometry {
            Geometry::Paths(paths) => {
                for (k, p) in paths.iter().enumerate() {
                    reps.push((si, k, p.start().unwrap_or_default()));
                    let print = if p.closed {
                        Print::Closed(p)
                    } else {
                        Print::Swept(p.flatten(ctx.tol.fit))
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
                        Region::from_paths(std::slice::from_ref(*p), ctx.tol.fit).offset(*r, eps);
                    // A ring that encloses no area on its own (one traversed clockwise, a
                    // ring around an island, or one that touches itself) still clears the
                    // tool's disk swept along it.
                    if grown.is_empty() {
                        ops::swept_region(&p.flatten(ctx.tol.fit), true, *r, ctx.tol.fit)
                    } else {
                        grown
                    }
                }
                Print::Swept(pts) => ops::swept_region(pts, false, *r, ctx.tol.fit),
            };
            fp.to_geo(ctx.tol.fit)
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
            Geometry::AttrPolylines3(l) => l.len(),
        };
        if s.groups.len() != n {
            s.groups = vec![None; n];
        }
        s.groups[k] = g;
    }
}
