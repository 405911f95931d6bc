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
//! [`crate::geom::predicates`]. Cost: O(S·V) for S disk samples and V polygon vertices.

use crate::geom::predicates::winding_number;
use crate::geom::{Circle, DVec2, Line};

/// The deepest-reaching disk sample of [`uncovered`].
#[derive(Clone, Copy, Debug, PartialEq)]
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
    let edges: Vec<Line> = polygons
        .iter()
        .flat_map(|p| (0..p.len()).map(move |i| Line::new(p[i], p[(i + 1) % p.len()])))
        .collect();
    disks
        .iter()
        .map(|&(t, d)| {
            let inside = polygons.iter().map(|p| winding_number(p, d.c)).sum::<i32>() % 2 != 0;
            let dist = edges
                .iter()
                .map(|e| e.distance(d.c))
                .fold(f64::INFINITY, f64::min);
            let depth = if inside { d.r - dist } else { d.r + dist };
            Uncovered { depth, t, at: d.c }
        })
        .max_by(|a, b| a.depth.total_cmp(&b.depth))
}

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
}
