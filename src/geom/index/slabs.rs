//! Items with a height range listed by horizontal slab, for queries "which items may matter
//! at height y": point-in-polygon and winding-number tests, where only the edges whose
//! height range holds the point's height contribute.
//!
//! The slab of a height v is ⌊(v − y₀)·k⌋ (clamped to the slabs), a monotone function of v
//! in floating point (correctly rounded subtraction and multiplication are monotone), so an
//! item whose closed range [lo, hi] holds y is listed in y's slab: no widening is needed
//! for the ranges given.
//!
//! Cost: O(n) to build for n items (at most `max_entries_per_item`·n + 64 entries: the
//! slab count starts at n and is halved until the entries fit), O(1 + k) per query for the
//! k items listed in the slab.

use crate::geom::DVec2;
use crate::geom::predicates::edge_winding;

/// Item numbers listed by slab of height.
#[derive(Clone, Debug)]
pub struct Slabs {
    /// Lower edge of the first slab.
    y0: f64,
    /// Slabs per unit height; 0 for a single slab (non-finite or flat ranges).
    per_y: f64,
    /// Slab k lists `entries[starts[k]..starts[k + 1]]`.
    starts: Vec<u32>,
    /// Item numbers, slab by slab.
    entries: Vec<u32>,
}

impl Slabs {
    /// The slabs of items with the closed height ranges `ranges` (lo ≤ hi), each listed in
    /// every slab its range meets; about `max_entries_per_item` entries per item at most.
    pub fn new(ranges: &[(f64, f64)], max_entries_per_item: usize) -> Slabs {
        let (y0, y1) = ranges
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                (a.min(r.0), b.max(r.1))
            });
        let n = ranges.len();
        let finite = y0.is_finite() && y1.is_finite() && y1 > y0;
        // Non-finite or flat: one slab holding every item.
        let mut slabs = if finite { n.max(1) } else { 1 };
        let per_y = |slabs: usize| {
            if finite {
                slabs as f64 / (y1 - y0)
            } else {
                0.0
            }
        };
        let span = |per_y: f64, (lo, hi): (f64, f64), slabs: usize| {
            let k = |y: f64| (((y - y0) * per_y) as usize).min(slabs - 1);
            (k(lo), k(hi).max(k(lo)))
        };
        while slabs > 1 {
            let total: usize = ranges
                .iter()
                .map(|&r| {
                    let (a, b) = span(per_y(slabs), r, slabs);
                    b - a + 1
                })
                .sum();
            if total <= max_entries_per_item * n + 64 {
                break;
            }
            slabs /= 2;
        }
        let py = per_y(slabs);
        let mut counts = vec![0u32; slabs + 1];
        for &r in ranges {
            let (a, b) = span(py, r, slabs);
            for c in &mut counts[a..=b] {
                *c += 1;
            }
        }
        let mut starts = Vec::with_capacity(slabs + 1);
        let mut acc = 0u32;
        for &c in &counts[..slabs] {
            starts.push(acc);
            acc += c;
        }
        starts.push(acc);
        let mut fill = starts.clone();
        let mut entries = vec![0u32; acc as usize];
        for (i, &r) in ranges.iter().enumerate() {
            let (a, b) = span(py, r, slabs);
            for f in &mut fill[a..=b] {
                entries[*f as usize] = i as u32;
                *f += 1;
            }
        }
        Slabs {
            y0,
            per_y: py,
            starts,
            entries,
        }
    }

    /// Number of entries (an item listed in k slabs counts k times).
    #[cfg(test)]
    pub fn entries(&self) -> usize {
        self.entries.len()
    }

    /// The items listed in the slab of height `y`: every item whose range holds `y`, and
    /// others. Empty for a NaN height and for heights below or above every range.
    pub fn at(&self, y: f64) -> &[u32] {
        let slabs = self.starts.len() - 1;
        let k = if self.per_y == 0.0 {
            0
        } else {
            let s = (y - self.y0) * self.per_y;
            if s.is_nan() || s < 0.0 || s >= slabs as f64 + 1.0 {
                return &[];
            }
            (s as usize).min(slabs - 1)
        };
        let (a, b) = (self.starts[k] as usize, self.starts[k + 1] as usize);
        &self.entries[a..b]
    }
}

/// Winding numbers of many points about one closed polygon: the sum of
/// [`edge_winding`] over the edges listed in the point's slab, equal to
/// [`crate::geom::predicates::winding_number`] for every point (an edge's term is non-zero only
/// where the point's height lies in the edge's).
#[derive(Clone, Debug)]
pub struct PolygonWinding<'a> {
    poly: &'a [DVec2],
    slabs: Slabs,
}

/// Entries per edge the polygon index allows (see [`Slabs::new`]).
const POLYGON_ENTRIES_PER_EDGE: usize = 4;

impl<'a> PolygonWinding<'a> {
    /// The index of the closed polygon `poly` (last vertex joined to the first).
    pub fn new(poly: &'a [DVec2]) -> PolygonWinding<'a> {
        let n = poly.len();
        let ranges: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let (a, b) = (poly[i].y, poly[(i + 1) % n].y);
                (a.min(b), a.max(b))
            })
            .collect();
        PolygonWinding {
            poly,
            slabs: Slabs::new(&ranges, POLYGON_ENTRIES_PER_EDGE),
        }
    }

    /// The winding number of the polygon about `p`.
    pub fn winding(&self, p: DVec2) -> i32 {
        let n = self.poly.len();
        self.slabs
            .at(p.y)
            .iter()
            .map(|&i| {
                let i = i as usize;
                edge_winding(self.poly[i], self.poly[(i + 1) % n], p)
            })
            .sum()
    }

    /// Even-odd inside test ([`crate::geom::predicates::inside_even_odd`]).
    pub fn inside_even_odd(&self, p: DVec2) -> bool {
        self.winding(p) % 2 != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::predicates::winding_number;
    use proptest::prelude::*;

    #[test]
    fn empty_flat_and_nan() {
        assert_eq!(PolygonWinding::new(&[]).winding(DVec2::ZERO), 0);
        let flat = [DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(2.0, 0.0)];
        assert_eq!(PolygonWinding::new(&flat).winding(DVec2::new(0.5, 0.0)), 0);
        let sq = [
            DVec2::ZERO,
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        let w = PolygonWinding::new(&sq);
        assert_eq!(w.winding(DVec2::ONE), 1);
        assert_eq!(w.winding(DVec2::new(1.0, f64::NAN)), 0);
        assert_eq!(w.winding(DVec2::new(1.0, 5.0)), 0);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        /// Star-shaped and self-crossing polygons (vertices on a noisy circle, visited in a
        /// scrambled order), queried at random points, at vertices and at edge midpoints:
        /// the index gives the full sum's number every time.
        #[test]
        fn index_matches_the_full_sum(
            radii in proptest::collection::vec(0.2f64..3.0, 3..60),
            step in 1usize..7,
            queries in proptest::collection::vec((-4.0f64..4.0, -4.0f64..4.0), 1..40),
        ) {
            let n = radii.len();
            let poly: Vec<DVec2> = (0..n)
                .map(|i| {
                    let k = (i * step) % n;
                    let t = std::f64::consts::TAU * k as f64 / n as f64;
                    radii[k] * DVec2::new(t.cos(), t.sin())
                })
                .collect();
            let w = PolygonWinding::new(&poly);
            let mids = (0..n).map(|i| 0.5 * (poly[i] + poly[(i + 1) % n]));
            let pts = queries
                .iter()
                .map(|&(x, y)| DVec2::new(x, y))
                .chain(poly.iter().copied())
                .chain(mids);
            for p in pts {
                prop_assert_eq!(w.winding(p), winding_number(&poly, p), "{:?}", p);
            }
        }
    }
}
