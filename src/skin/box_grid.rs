//! A uniform grid over axis-aligned boxes, for the nearest-item and ray-crossing queries of
//! [`crate::skin::coverage`].
//!
//! Each item is listed in every cell its box overlaps (compressed rows: one offset table
//! and one index list). [`BoxGrid::nearest`] visits the cells in square rings of growing
//! Chebyshev index distance k from the query point's cell: every point of a ring-k cell
//! lies at least (k − 1)·h from the query point (h the cell side), and every item's
//! distance is at least the distance to its box, so the search stops once (k − 1)·h, or
//! a box's distance, exceeds the best distance found by more than [`PRUNE_SLACK`]·h: the
//! minimum is that over all items (Samet, "Foundations of Multidimensional and Metric
//! Data Structures", 2006, §4.1.2, incremental nearest neighbour on a grid).

use crate::geom::{Aabb, DVec2};

/// Margin, in cell sides, by which a lower bound must exceed the best distance before the
/// items behind it are skipped: far above the rounding of a distance, so an item whose
/// computed distance ties the minimum is never skipped for a bound rounded up.
const PRUNE_SLACK: f64 = 1e-9;

/// Cells per item at most (beside a small constant): the grid's side h is at least
/// √(area / (this · n)) and (longest side) / (this · n), so the grid has at most about
/// 3 · this · n cells for n items.
const CELLS_PER_ITEM: f64 = 4.0;

/// Items by the grid cells their boxes overlap.
pub(crate) struct BoxGrid {
    origin: DVec2,
    h: f64,
    nx: i64,
    ny: i64,
    /// Start of cell c's items in `items` (row-major, one more entry than cells).
    start: Vec<u32>,
    /// Item indices, by cell.
    items: Vec<u32>,
    /// The item boxes.
    boxes: Vec<Aabb>,
}

impl BoxGrid {
    /// The grid over `boxes` (non-empty, finite boxes; others are listed nowhere and never
    /// returned). The cell side h is the largest of the mean box extent and the bounds of
    /// [`CELLS_PER_ITEM`], so the grid has O(n) cells and a box O(1) cells on average.
    pub(crate) fn new(boxes: Vec<Aabb>) -> BoxGrid {
        let valid = |b: &Aabb| !b.is_empty() && b.min.is_finite() && b.max.is_finite();
        let all = boxes
            .iter()
            .filter(|b| valid(b))
            .fold(Aabb::EMPTY, |a, b| a.union(*b));
        let n = boxes.len().max(1) as f64;
        let size = if all.is_empty() {
            DVec2::ZERO
        } else {
            all.size()
        };
        let mean = boxes
            .iter()
            .filter(|b| valid(b))
            .map(|b| b.size().max_element())
            .sum::<f64>()
            / n;
        let h = [
            mean,
            (size.x * size.y / (CELLS_PER_ITEM * n)).sqrt(),
            size.max_element() / (CELLS_PER_ITEM * n),
        ]
        .into_iter()
        .fold(0.0, f64::max);
        let h = if h > 0.0 && h.is_finite() { h } else { 1.0 };
        let origin = if all.is_empty() { DVec2::ZERO } else { all.min };
        let cells = |v: f64| ((v / h).floor() as i64 + 1).max(1);
        let (nx, ny) = (cells(size.x), cells(size.y));
        let mut g = BoxGrid {
            origin,
            h,
            nx,
            ny,
            start: vec![0; (nx * ny + 1) as usize],
            items: Vec::new(),
            boxes,
        };
        // Count, prefix sums, fill (the usual compressed-row build).
        for b in g.boxes.iter().filter(|b| valid(b)) {
            let (x0, y0, x1, y1) = g.span(b);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    g.start[(y * nx + x) as usize + 1] += 1;
                }
            }
        }
        for c in 1..g.start.len() {
            g.start[c] += g.start[c - 1];
        }
        let mut next = g.start.clone();
        g.items = vec![0; g.start[g.start.len() - 1] as usize];
        for (i, b) in g.boxes.iter().enumerate().filter(|(_, b)| valid(b)) {
            let (x0, y0, x1, y1) = g.span(b);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let c = (y * nx + x) as usize;
                    g.items[next[c] as usize] = i as u32;
                    next[c] += 1;
                }
            }
        }
        g
    }

    /// The cell of `p` (not clamped to the grid).
    fn cell(&self, p: DVec2) -> (i64, i64) {
        let q = (p - self.origin) / self.h;
        (q.x.floor() as i64, q.y.floor() as i64)
    }

    /// The cells a box overlaps, clamped to the grid: (x0, y0, x1, y1).
    fn span(&self, b: &Aabb) -> (i64, i64, i64, i64) {
        let (x0, y0) = self.cell(b.min);
        let (x1, y1) = self.cell(b.max);
        (
            x0.clamp(0, self.nx - 1),
            y0.clamp(0, self.ny - 1),
            x1.clamp(0, self.nx - 1),
            y1.clamp(0, self.ny - 1),
        )
    }

    fn cell_items(&self, x: i64, y: i64) -> &[u32] {
        let c = (y * self.nx + x) as usize;
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }

    /// The least `dist(i)` over all items, where `dist(i)` is at least the distance from `p`
    /// to box i (module docs), and an item where it is reached. Once the best is at most
    /// `floor` the search may stop with it (a value at most `floor`, not necessarily the
    /// least). `hint` (an item index, typically the answer for a nearby point) is tried
    /// first: the minimum is the same, found sooner. Infinite (and `None`) with no items.
    pub(crate) fn nearest(
        &self,
        p: DVec2,
        floor: f64,
        hint: Option<usize>,
        dist: impl Fn(usize) -> f64,
    ) -> (f64, Option<usize>) {
        let slack = PRUNE_SLACK * self.h;
        let (cx, cy) = self.cell(p);
        // Rings nearer than the grid hold no cells: start at the first that reaches it.
        let reach = |c: i64, n: i64| (-c).max(c - (n - 1)).max(0);
        let first = reach(cx, self.nx).max(reach(cy, self.ny));
        let last = (cx.max(self.nx - 1 - cx)).max(cy.max(self.ny - 1 - cy));
        let mut best = (f64::INFINITY, None);
        if let Some(i) = hint.filter(|&i| i < self.boxes.len()) {
            best = (dist(i), Some(i));
            if best.0 <= floor {
                return best;
            }
        }
        let visit = |x: i64, y: i64, best: &mut (f64, Option<usize>)| -> bool {
            if x < 0 || y < 0 || x >= self.nx || y >= self.ny {
                return false;
            }
            for &i in self.cell_items(x, y) {
                let i = i as usize;
                if self.boxes[i].distance(p) > best.0 + slack {
                    continue;
                }
                let d = dist(i);
                if d < best.0 {
                    *best = (d, Some(i));
                }
                if best.0 <= floor {
                    return true;
                }
            }
            false
        };
        for k in first..=last {
            if (k - 1) as f64 * self.h > best.0 + slack {
                break;
            }
            if k == 0 {
                if visit(cx, cy, &mut best) {
                    return best;
                }
                continue;
            }
            let (xa, xb) = ((cx - k).max(0), (cx + k).min(self.nx - 1));
            for x in xa..=xb {
                if visit(x, cy - k, &mut best) || visit(x, cy + k, &mut best) {
                    return best;
                }
            }
            let (ya, yb) = ((cy - k + 1).max(0), (cy + k - 1).min(self.ny - 1));
            for y in ya..=yb {
                if visit(cx - k, y, &mut best) || visit(cx + k, y, &mut best) {
                    return best;
                }
            }
        }
        best
    }

    /// Calls `f` once for every item whose box reaches the height of `p` and ends at or
    /// right of it (max.x ≥ p.x and min.y ≤ p.y ≤ max.y): among them every edge that the
    /// ray from `p` towards +x can cross. Order: by cell, then as listed.
    pub(crate) fn ray_items(&self, p: DVec2, mut f: impl FnMut(usize)) {
        let (cx, cy) = self.cell(p);
        if cy < 0 || cy >= self.ny || cx >= self.nx {
            return;
        }
        let from = cx.max(0);
        for x in from..self.nx {
            for &i in self.cell_items(x, cy) {
                let i = i as usize;
                let b = &self.boxes[i];
                // An item spanning several cells of the row: count it in its first one
                // from `from` on only.
                let first = self.cell(b.min).0.clamp(0, self.nx - 1).max(from);
                if first == x && b.max.x >= p.x && b.min.y <= p.y && p.y <= b.max.y {
                    f(i);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn boxes_of(pts: &[(f64, f64, f64, f64)]) -> Vec<Aabb> {
        pts.iter()
            .map(|&(x, y, w, h)| Aabb::new(DVec2::new(x, y), DVec2::new(x + w, y + h)))
            .collect()
    }

    proptest! {
        /// The grid's nearest box distance is the brute-force minimum, and the ray query
        /// lists exactly the boxes that reach p's height at or right of p, each once.
        #[test]
        fn nearest_and_ray_match_brute_force(
            raw in prop::collection::vec((-50.0..50.0f64, -50.0..50.0f64, 0.0..20.0f64, 0.0..3.0f64), 1..60),
            qs in prop::collection::vec((-80.0..80.0f64, -80.0..80.0f64), 1..20),
        ) {
            let boxes = boxes_of(&raw);
            let g = BoxGrid::new(boxes.clone());
            for (x, y) in qs {
                let p = DVec2::new(x, y);
                let brute = boxes.iter().map(|b| b.distance(p)).fold(f64::INFINITY, f64::min);
                let (got, at) = g.nearest(p, f64::NEG_INFINITY, None, |i| boxes[i].distance(p));
                prop_assert_eq!(got, brute);
                prop_assert_eq!(boxes[at.unwrap()].distance(p), brute);
                // Any hint gives the same minimum.
                let hinted = g.nearest(p, f64::NEG_INFINITY, Some(boxes.len() / 2), |i| boxes[i].distance(p));
                prop_assert_eq!(hinted.0, brute);
                let mut listed = Vec::new();
                g.ray_items(p, |i| listed.push(i));
                listed.sort_unstable();
                let want: Vec<usize> = (0..boxes.len())
                    .filter(|&i| {
                        let b = &boxes[i];
                        b.max.x >= p.x && b.min.y <= p.y && p.y <= b.max.y
                    })
                    .collect();
                prop_assert_eq!(listed, want);
            }
        }
    }

    /// Stopping at `floor` returns a value at most `floor`; no items give infinity.
    #[test]
    fn floor_and_empty() {
        let boxes = boxes_of(&[(0.0, 0.0, 1.0, 1.0), (10.0, 0.0, 1.0, 1.0)]);
        let g = BoxGrid::new(boxes.clone());
        let p = DVec2::new(5.0, 0.5);
        let d = |i: usize| boxes[i].distance(p);
        assert_eq!(g.nearest(p, f64::NEG_INFINITY, None, d), (4.0, Some(0)));
        assert!(g.nearest(p, 100.0, None, d).0 <= 100.0);
        // A hint at most `floor` is the answer at once; a farther hint gives way to the
        // nearest item.
        assert_eq!(g.nearest(p, 4.5, Some(0), d), (4.0, Some(0)));
        assert_eq!(g.nearest(p, f64::NEG_INFINITY, Some(1), d), (4.0, Some(0)));
        assert_eq!(g.nearest(p, 5.5, Some(1), d), (5.0, Some(1)));
        let e = BoxGrid::new(Vec::new());
        assert_eq!(e.nearest(p, 0.0, None, |_| 0.0), (f64::INFINITY, None));
    }
}
