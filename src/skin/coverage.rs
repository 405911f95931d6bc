//! How deep a stroke's disks reach outside the region its outline bounds.
//!
//! A skin (kruppa-2023 Sec. 4) touches every circle of its sequence and, where the
//! Hausdorff bound meets ε, lies within ε of the envelope, so the region it bounds holds
//! every disk c(t) = (q(t), r(t)) up to ε. Where no admissible insertion is left (a
//! hairpin, a bend sharper than the disks allow) phase 3 stops with the bound unmet, and the
//! outline may cut through the stroke. This module measures by how much, so that a job can
//! refuse or replace such an outline instead of cutting a board through its channel.
//!
//! For a disk (q, r) and the region Ω bounded by closed polygons (even-odd rule), the depth
//! by which the disk leaves Ω is
//!
//! depth = r − d(q, ∂Ω) when q ∈ Ω, and r + d(q, ∂Ω) otherwise,
//!
//! positive exactly when part of the disk lies outside Ω. [`uncovered`] returns the
//! deepest sample. The inside test is the exact winding number of
//! [`crate::geom::predicates`], summed over the edges that the ray from the centre can
//! cross; the distance to the boundary is the nearest edge's. Both queries run on a grid of
//! the edges' boxes ([`BoxGrid`]): about O(S + V) for S disk samples and V polygon
//! vertices of evenly sized edges, where scanning every edge costs O(S·V).

use crate::geom::predicates::edge_winding;
use crate::geom::{Aabb, Circle, DVec2, Line};
use crate::skin::box_grid::BoxGrid;

/// The deepest-reaching disk sample outside a skin's region: where the skin leaves a disk
/// uncovered.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Uncovered {
    /// How far the disk reaches outside the region (design units; ≤ 0 when it lies inside).
    pub depth: f64,
    /// Curve parameter of the disk.
    pub t: f64,
    /// Centre of the disk.
    pub at: DVec2,
}

/// The disk sample reaching deepest outside the region bounded by the closed `polygons`
/// (last vertex joined to the first, even-odd rule): the maximum over `disks` of the depth
/// in the module docs. `None` when there are no disks. With no polygons every disk lies
/// outside: the depth is infinite.
pub fn uncovered(disks: &[(f64, Circle)], polygons: &[Vec<DVec2>]) -> Option<Uncovered> {
    let edges: Vec<(DVec2, DVec2)> = polygons
        .iter()
        .flat_map(|p| (0..p.len()).map(move |i| (p[i], p[(i + 1) % p.len()])))
        .collect();
    let grid = BoxGrid::new(
        edges
            .iter()
            .map(|&(a, b)| Aabb::from_corners(a, b))
            .collect(),
    );
    // Consecutive disks are near each other: each search starts at the previous one's edge.
    let mut last = None;
    disks
        .iter()
        .map(|&(t, d)| {
            // The winding number's parity from the edges the ray can cross (the others
            // contribute 0 to the sum of `edge_winding`).
            let mut winding = 0i32;
            grid.ray_items(d.c, |i| {
                winding += edge_winding(edges[i].0, edges[i].1, d.c)
            });
            let inside = winding % 2 != 0;
            let (dist, at) = grid.nearest(d.c, f64::NEG_INFINITY, last, |i| {
                Line::new(edges[i].0, edges[i].1).distance(d.c)
            });
            last = at;
            let depth = if inside { d.r - dist } else { d.r + dist };
            Uncovered { depth, t, at: d.c }
        })
        .max_by(|a, b| a.depth.total_cmp(&b.depth))
}

/// How far the closed `polygons` reach outside the region swept by `disks` (a disk family
/// sampled in order, centre and radius linear between consecutive samples, as
/// [`crate::dbsc::flatten::flatten_disks`] gives it): the largest distance from a boundary
/// point p to that region, max(0, min over consecutive pairs of [`hull_distance`]), over
/// the vertices and points spaced at most `step` apart along every edge (the distance is
/// 1-Lipschitz, so the sampling misses at most `step`/2). With `depth` of [`uncovered`] it
/// bounds the two-sided deviation of an outline from its stroke: every point of a disk
/// lies within `depth` of the region, every boundary point within this of a disk. Pairs
/// are searched on a grid of their boxes ([`BoxGrid::nearest`]: a pair is at least as far
/// as its box, which holds its swept disks). Returns the distance and the
/// boundary point where it is largest: (0, origin) when there are no polygons; infinite
/// when there are no disks.
pub fn excess(disks: &[Circle], polygons: &[Vec<DVec2>], step: f64) -> (f64, DVec2) {
    if disks.is_empty() {
        let at = polygons.iter().flatten().next().copied();
        return at.map_or((0.0, DVec2::ZERO), |p| (f64::INFINITY, p));
    }
    let pairs: Vec<(Circle, Circle)> = if disks.len() == 1 {
        vec![(disks[0], disks[0])]
    } else {
        disks.windows(2).map(|w| (w[0], w[1])).collect()
    };
    let disk_box = |d: &Circle| Aabb::new(d.c - DVec2::splat(d.r), d.c + DVec2::splat(d.r));
    let grid = BoxGrid::new(
        pairs
            .iter()
            .map(|(a, b)| disk_box(a).union(disk_box(b)))
            .collect(),
    );
    // The distance of p, or any value at most `floor` once it is known not to exceed it
    // (the early break of Taha & Hanbury 2015, "An efficient algorithm for calculating the
    // exact Hausdorff distance", §3: a point nearer than the largest distance so far cannot
    // change the maximum, so its search stops there).
    // Consecutive samples are near each other: each search starts at the previous one's
    // pair.
    let mut last = None;
    let mut dist = |p: DVec2, floor: f64| -> f64 {
        let (d, at) = grid.nearest(p, floor, last, |i| {
            hull_distance(p, &pairs[i].0, &pairs[i].1)
        });
        last = at;
        d.max(0.0)
    };
    let mut worst = (0.0f64, DVec2::ZERO);
    for poly in polygons {
        let n = poly.len();
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let pieces = if step > 0.0 {
                ((a.distance(b) / step).ceil() as usize).clamp(1, MAX_EDGE_SAMPLES)
            } else {
                1
            };
            for k in 0..pieces {
                let p = a.lerp(b, k as f64 / pieces as f64);
                let d = dist(p, worst.0);
                if d > worst.0 {
                    worst = (d, p);
                }
            }
        }
    }
    worst
}

/// Signed distance from `p` to the region swept by the disk from `a` to `b` with centre
/// and radius linear in s ∈ [0, 1]: f(s) = ‖p − c(s)‖ − r(s) is convex in s; with u = b − a,
/// k = (r_b − r_a)/‖u‖ (|k| < 1, else one disk holds the other and the nearer of the two
/// decides), h the distance of p from the line and t₀ its foot's parameter, f′(s) = 0 at
/// s* = t₀ + k·h / (‖u‖·√(1 − k²)), clamped to [0, 1].
pub fn hull_distance(p: DVec2, a: &Circle, b: &Circle) -> f64 {
    let u = b.c - a.c;
    let l = u.length();
    let disk = |d: &Circle| p.distance(d.c) - d.r;
    let k = (b.r - a.r) / l;
    if l <= 0.0 || k.abs() >= 1.0 {
        return disk(a).min(disk(b));
    }
    let t0 = (p - a.c).dot(u) / (l * l);
    let h = crate::geom::cross(u, p - a.c).abs() / l;
    let s = (t0 + k * h / (l * (1.0 - k * k).sqrt())).clamp(0.0, 1.0);
    p.distance(a.c + s * u) - (a.r + s * (b.r - a.r))
}

/// Cap on the samples [`excess`] takes along one edge (a guard against a `step` far below
/// the edge length; the bound then loosens to the edge length over this count).
const MAX_EDGE_SAMPLES: usize = 1 << 16;

#[cfg(test)]
mod tests {
    use super::*;

    fn square(h: f64) -> Vec<DVec2> {
        vec![
            DVec2::new(-h, -h),
            DVec2::new(h, -h),
            DVec2::new(h, h),
            DVec2::new(-h, h),
        ]
    }

    #[test]
    fn depth_is_signed_distance_plus_radius() {
        let sq = vec![square(10.0)];
        // Inside, 3 from the right side: a disk of radius 1 is 2 inside, radius 5 reaches 2 out.
        let inner = [(0.0, Circle::new(DVec2::new(7.0, 0.0), 1.0))];
        assert!((uncovered(&inner, &sq).unwrap().depth + 2.0).abs() < 1e-12);
        let outer = [(0.5, Circle::new(DVec2::new(7.0, 0.0), 5.0))];
        let u = uncovered(&outer, &sq).unwrap();
        assert!((u.depth - 2.0).abs() < 1e-12);
        assert_eq!(u.t, 0.5);
        // Outside, 4 beyond the top: depth r + 4.
        let out = [(1.0, Circle::new(DVec2::new(0.0, 14.0), 1.5))];
        assert!((uncovered(&out, &sq).unwrap().depth - 5.5).abs() < 1e-12);
    }

    #[test]
    fn holes_count_as_outside_and_the_deepest_disk_wins() {
        // A 20 × 20 square with a 4 × 4 hole: a disk centred in the hole is outside by r + 2.
        let ring = vec![square(10.0), square(2.0)];
        let disks = [
            (0.0, Circle::new(DVec2::new(6.0, 0.0), 1.0)),
            (1.0, Circle::new(DVec2::ZERO, 0.5)),
        ];
        let u = uncovered(&disks, &ring).unwrap();
        assert_eq!(u.t, 1.0);
        assert!((u.depth - 2.5).abs() < 1e-12);
        assert!(uncovered(&[], &ring).is_none());
        assert_eq!(uncovered(&disks, &[]).unwrap().depth, f64::INFINITY);
    }

    /// A square of side 2h around one disk of radius h: the corners stick out by
    /// h(√2 − 1); edges sampled finely find that, vertices alone too (corners are vertices).
    #[test]
    fn excess_is_distance_to_the_union() {
        let d = [Circle::new(DVec2::ZERO, 2.0)];
        let (e, at) = excess(&d, &[square(2.0)], 0.01);
        assert!((e - 2.0 * (2f64.sqrt() - 1.0)).abs() < 1e-12, "{e}");
        assert_eq!(at.abs(), DVec2::splat(2.0));
        // Inside the disk: no excess. Two disks far apart with a bar between them: the
        // middle of the bar's edge is 5 from both centres (r = 1): 4, found by sampling only.
        assert_eq!(excess(&d, &[square(1.0)], 0.01).0, 0.0);
        // Two disks swept from one to the other (a capsule of radius 1): a bar 3 above the
        // axis is 2 outside it all along, found by sampling the edges.
        let two = [
            Circle::new(DVec2::new(-5.0, 0.0), 1.0),
            Circle::new(DVec2::new(5.0, 0.0), 1.0),
        ];
        let bar = vec![vec![
            DVec2::new(-5.0, 3.0),
            DVec2::new(5.0, 3.0),
            DVec2::new(5.0, 3.1),
            DVec2::new(-5.0, 3.1),
        ]];
        let (fine, _) = excess(&two, &bar, 0.01);
        assert!((fine - 2.1).abs() < 1e-12, "{fine}");
        assert_eq!(excess(&[], &bar, 0.1).0, f64::INFINITY);
        // The hull distance against a dense sampling of the swept disks (radius 1 to 3).
        let (a, b) = (
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(10.0, 2.0), 3.0),
        );
        for p in [
            DVec2::new(4.0, 8.0),
            DVec2::new(-3.0, -1.0),
            DVec2::new(12.0, -5.0),
        ] {
            let dense = (0..=20000)
                .map(|i| {
                    let s = i as f64 / 20000.0;
                    p.distance(a.c.lerp(b.c, s)) - (a.r + s * (b.r - a.r))
                })
                .fold(f64::INFINITY, f64::min);
            assert!((hull_distance(p, &a, &b) - dense).abs() < 1e-6, "{p}");
        }
    }
}
