//! Winding numbers of many points about one closed polyline (lines and arcs), through an
//! index of its segments by height.
//!
//! The winding number of a closed polyline about a point is a sum over its segments of a
//! signed crossing count (Sunday's crossing form of the winding number, with arcs counted
//! against their chord and their circular segment). [`winding_term`] is that per-segment
//! term exactly as cavalier_contours' `PlineSource::winding_number` computes it (the same
//! floating-point predicates in the same order), so [`WindingIndex::winding`] gives the
//! same integer as cavalier for every point, on the boundary too. A term can be non-zero
//! only where the point's height lies in the segment's height range (the chord's, or the
//! arc's, which holds its circular segment), so the index lists each segment in the
//! horizontal slabs its range covers, widened by [`RANGE_WIDENING`] for rounding, and a
//! query walks one slab.
//!
//! Cost: O(n) to build for n segments (at most [`MAX_ENTRIES_PER_SEGMENT`]·n slab entries),
//! O(1 + k) per query for the k segments listed in the point's slab, instead of O(n).

use super::slabs::Slabs;
use crate::geom::{Aabb, DVec2};
use cavalier_contours::core::math::{Vector2, is_left, is_left_or_equal};
use cavalier_contours::polyline::{PlineSource, PlineVertex, Polyline};

/// Relative widening of each segment's height range (relative to its heights and an arc's
/// radius r): far above the rounding of the arc bounds and of the in-circle test (a few
/// ulps of r, which grows as 1/bulge for flat arcs), so the slabs list every segment whose
/// term may be non-zero.
pub const RANGE_WIDENING: f64 = 1e-9;

/// Bound on the mean number of slabs a segment is listed in: the slab count is halved
/// until the entries fit (a tall zigzag would otherwise list every segment in every slab).
pub const MAX_ENTRIES_PER_SEGMENT: usize = 4;

/// The term of segment `v1`→`v2` in the winding number of its closed polyline about
/// `point`: +1 for an upward crossing with the point on the left, −1 for a downward one
/// with the point on the right, arcs counted by their chord corrected for the circular
/// segment between chord and arc. The formula and predicates of cavalier_contours'
/// `winding_number`, segment by segment.
pub fn winding_term(v1: PlineVertex<f64>, v2: PlineVertex<f64>, point: Vector2<f64>) -> i32 {
    if v1.bulge_is_zero() {
        return if v1.y <= point.y {
            i32::from(v2.y > point.y && is_left(v1.pos(), v2.pos(), point))
        } else {
            -i32::from(v2.y <= point.y && !is_left(v1.pos(), v2.pos(), point))
        };
    }
    let ccw = v1.bulge_is_pos();
    let left = if ccw {
        is_left(v1.pos(), v2.pos(), point)
    } else {
        is_left_or_equal(v1.pos(), v2.pos(), point)
    };
    // The supporting circle compared without its centre or radius (scaled by 16·bulge²).
    let inside = || {
        let (dx, dy, b) = (v2.x - v1.x, v2.y - v1.y, v1.bulge);
        let b2 = b * b;
        let (offset, scale) = (1.0 - b2, 2.0 * b);
        let x = scale * (2.0 * point.x - v1.x - v2.x) + dy * offset;
        let y = scale * (2.0 * point.y - v1.y - v2.y) - dx * offset;
        let r = 1.0 + b2;
        x * x + y * y < (dx * dx + dy * dy) * r * r
    };
    // The point in the circular segment beside a chord it does not cross, x strictly
    // between the ends in the order `lo` < x < `hi`.
    let between = |lo: f64, hi: f64| lo < point.x && point.x < hi;
    if v1.y <= point.y {
        if v2.y > point.y {
            // Upward crossing of the chord.
            match (ccw, left) {
                (true, true) => 1,
                (true, false) => i32::from(inside()),
                (false, true) => i32::from(!inside()),
                (false, false) => 0,
            }
        } else if ccw && !left && between(v2.x, v1.x) && inside() {
            // Chord below the point.
            1
        } else if !ccw && left && between(v1.x, v2.x) && inside() {
            -1
        } else {
            0
        }
    } else if v2.y <= point.y {
        // Downward crossing of the chord.
        match (ccw, left) {
            (true, true) => 0,
            (true, false) => -i32::from(!inside()),
            (false, true) => -i32::from(inside()),
            (false, false) => -1,
        }
    } else if ccw && !left && between(v1.x, v2.x) && inside() {
        // Chord above the point.
        1
    } else if !ccw && left && between(v2.x, v1.x) && inside() {
        -1
    } else {
        0
    }
}

/// The lowest and highest height of the arc `v1`→`v2` (bulge b = tan(θ/4) for the signed
/// sweep θ, counter-clockwise when positive) and its radius r = |chord|·(1 + b²)/(4|b|), with
/// the centre at the chord's middle plus perp(chord)·(1 − b²)/(4b). The arc reaches its
/// circle's top (bottom) where the sweep passes the angle π/2 (3π/2). Computed here rather
/// than by cavalier's `seg_bounding_box`, whose sign tests on the end radii miss the
/// extremes of arcs sweeping more than a half turn (bulge > 1).
fn arc_height_range(v1: PlineVertex<f64>, v2: PlineVertex<f64>) -> (f64, f64, f64) {
    let b = v1.bulge;
    let (cx, cy) = (v2.x - v1.x, v2.y - v1.y);
    let k = (1.0 - b) * (1.0 + b) / (4.0 * b);
    let centre = (v1.x + 0.5 * cx - cy * k, v1.y + 0.5 * cy + cx * k);
    let r = cx.hypot(cy) * (1.0 + b * b) / (4.0 * b.abs());
    let sweep = 4.0 * b.atan();
    let start = (v1.y - centre.1).atan2(v1.x - centre.0);
    let tau = std::f64::consts::TAU;
    let swept = |angle: f64| {
        let from_start = if sweep > 0.0 {
            angle - start
        } else {
            start - angle
        };
        from_start.rem_euclid(tau) <= sweep.abs()
    };
    let (mut lo, mut hi) = (v1.y.min(v2.y), v1.y.max(v2.y));
    if swept(0.25 * tau) {
        hi = hi.max(centre.1 + r);
    }
    if swept(0.75 * tau) {
        lo = lo.min(centre.1 - r);
    }
    (lo, hi, if r.is_finite() { r } else { 0.0 })
}

/// The lowest and highest x of the arc `v1`→`v2`: [`arc_height_range`] of the arc turned a
/// quarter turn counter-clockwise, (x, y) ↦ (−y, x), which is exact in floating point and
/// keeps the sense (and so the bulge) of the arc; its heights are the original x.
fn arc_width_range(v1: PlineVertex<f64>, v2: PlineVertex<f64>) -> (f64, f64, f64) {
    let turn = |v: PlineVertex<f64>| PlineVertex::new(-v.y, v.x, v.bulge);
    arc_height_range(turn(v1), turn(v2))
}

/// The range `lo..=hi` (with the arc's radius `r`, 0 for a line) widened by
/// [`RANGE_WIDENING`]·(hi − lo + r + |lo| + |hi|).
fn widened((lo, hi, r): (f64, f64, f64)) -> (f64, f64) {
    let w = RANGE_WIDENING * (hi - lo + r + lo.abs() + hi.abs());
    (lo - w, hi + w)
}

/// The segments of one closed polyline listed by horizontal slab (see the module docs).
#[derive(Clone, Debug)]
pub struct WindingIndex {
    /// The segments' start and end vertices.
    segs: Vec<(PlineVertex<f64>, PlineVertex<f64>)>,
    /// Segment numbers by slab of their widened height ranges.
    slabs: Slabs,
    /// The box of the segments' widened x and height ranges (arcs' extremes included):
    /// lowest corner, highest corner; None without segments.
    bounds: Option<([f64; 2], [f64; 2])>,
}

impl WindingIndex {
    /// The index of `pl`; an open polyline or one of fewer than two vertices winds 0 times
    /// about every point, as in cavalier.
    pub fn new(pl: &Polyline<f64>) -> WindingIndex {
        let segs: Vec<_> = if pl.is_closed() && pl.vertex_count() >= 2 {
            pl.iter_segments().collect()
        } else {
            Vec::new()
        };
        let ranges: Vec<(f64, f64)> = segs
            .iter()
            .map(|&(v1, v2)| {
                widened(if v1.bulge_is_zero() {
                    (v1.y.min(v2.y), v1.y.max(v2.y), 0.0)
                } else {
                    arc_height_range(v1, v2)
                })
            })
            .collect();
        let widths = segs.iter().map(|&(v1, v2)| {
            widened(if v1.bulge_is_zero() {
                (v1.x.min(v2.x), v1.x.max(v2.x), 0.0)
            } else {
                arc_width_range(v1, v2)
            })
        });
        let finite = segs
            .iter()
            .all(|(v, _)| v.x.is_finite() && v.y.is_finite() && v.bulge.is_finite());
        let bounds = widths
            .zip(&ranges)
            .fold(None, |acc, ((x0, x1), &(y0, y1))| {
                let (lo, hi) = acc.unwrap_or(([x0, y0], [x1, y1]));
                Some((
                    [lo[0].min(x0), lo[1].min(y0)],
                    [hi[0].max(x1), hi[1].max(y1)],
                ))
            });
        // Non-finite coordinates: no box is claimed.
        let bounds = bounds.map(|b| {
            if finite && b.0.iter().chain(&b.1).all(|c| c.is_finite()) {
                b
            } else {
                ([f64::NEG_INFINITY; 2], [f64::INFINITY; 2])
            }
        });
        WindingIndex {
            segs,
            slabs: Slabs::new(&ranges, MAX_ENTRIES_PER_SEGMENT),
            bounds,
        }
    }

    /// A box outside which the polyline winds 0 times about every point (None: it winds 0
    /// times about every point; an infinite box when a coordinate is not finite): the
    /// segments' x and height ranges, arcs' extremes included, each widened by
    /// `RANGE_WIDENING`. Below or above it no term is non-zero (the slabs); left or right
    /// of it every term has its value for a point at infinity on that side: the chord tests
    /// `is_left` have a true cross product of at least the widening times the chord's
    /// height, far above their rounding, and a point beyond the arc's own extent is outside
    /// its circular segment; those values sum to 0 since a closed polyline crosses every
    /// height upward as often as downward.
    #[must_use]
    pub fn bounds(&self) -> Option<Aabb> {
        (self.bounds).map(|(lo, hi)| Aabb::new(DVec2::from_array(lo), DVec2::from_array(hi)))
    }

    /// The winding number of the polyline about `p`: the value cavalier_contours'
    /// `winding_number` gives. A point above or below every range sees no segment whose
    /// term is non-zero, nor does a NaN height (every comparison in the terms is false).
    pub fn winding(&self, p: Vector2<f64>) -> i32 {
        if self.segs.is_empty() {
            return 0;
        }
        self.slabs
            .at(p.y)
            .iter()
            .map(|&i| {
                let (v1, v2) = self.segs[i as usize];
                winding_term(v1, v2, p)
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cavalier_contours::polyline::PlineSourceMut;
    use proptest::prelude::*;

    /// A closed polyline through `pts` with bulges `bulges` (cycled).
    fn pline(pts: &[(f64, f64)], bulges: &[f64]) -> Polyline<f64> {
        let mut pl = Polyline::new_closed();
        for (k, &(x, y)) in pts.iter().enumerate() {
            pl.add(x, y, bulges[k % bulges.len()]);
        }
        pl
    }

    /// The points a winding test should try: vertices, midpoints of chords, points on
    /// arcs, a grid over the box and beyond it.
    fn probes(pl: &Polyline<f64>) -> Vec<Vector2<f64>> {
        let mut out = Vec::new();
        for (v1, v2) in pl.iter_segments() {
            out.push(v1.pos());
            out.push((v1.pos() + v2.pos()).scale(0.5));
            if !v1.bulge_is_zero() {
                let mid = cavalier_contours::polyline::seg_midpoint(v1, v2);
                out.push(mid);
                out.push((mid + v1.pos()).scale(0.5));
            }
        }
        if let Some(b) = pl.extents() {
            for i in -2..=22 {
                for j in -2..=22 {
                    out.push(Vector2::new(
                        b.min_x + (b.max_x - b.min_x) * i as f64 / 20.0,
                        b.min_y + (b.max_y - b.min_y) * j as f64 / 20.0,
                    ));
                }
            }
        }
        out
    }

    #[test]
    fn a_square_and_a_circle_of_two_arcs() {
        let sq = pline(&[(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)], &[0.0]);
        let w = WindingIndex::new(&sq);
        assert_eq!(w.winding(Vector2::new(1.0, 1.0)), 1);
        assert_eq!(w.winding(Vector2::new(3.0, 1.0)), 0);
        assert_eq!(w.winding(Vector2::new(1.0, 5.0)), 0);
        let mut cw = sq.clone();
        cw.invert_direction_mut();
        assert_eq!(WindingIndex::new(&cw).winding(Vector2::new(1.0, 1.0)), -1);
        // Two half circles of radius 1 about the origin.
        let circle = pline(&[(-1.0, 0.0), (1.0, 0.0)], &[1.0]);
        let w = WindingIndex::new(&circle);
        assert_eq!(w.winding(Vector2::new(0.0, 0.9)), 1);
        assert_eq!(w.winding(Vector2::new(0.0, -0.9)), 1);
        assert_eq!(w.winding(Vector2::new(0.8, 0.8)), 0);
        assert_eq!(
            w.winding(Vector2::new(f64::NAN, 0.0)),
            circle.winding_number(Vector2::new(f64::NAN, 0.0))
        );
        // Open polylines wind 0 times.
        let mut open = sq.clone();
        open.set_is_closed(false);
        assert_eq!(WindingIndex::new(&open).winding(Vector2::new(1.0, 1.0)), 0);
    }

    /// The height range of arcs of either sense, minor and major (cavalier's own box misses
    /// the bottom of the first major arc below), against 2001 points along each arc.
    #[test]
    fn arc_height_ranges_hold_the_arc_and_no_more() {
        let ends = [
            ((-9.0, 8.0), (-7.0, 0.0)),
            ((0.0, 0.0), (3.0, 1.0)),
            ((1.0, 0.0), (-1.0, 0.0)),
        ];
        for ((x1, y1), (x2, y2)) in ends {
            for b in [-1.9, -1.0, -0.4, -1e-6, 1e-6, 0.4, 1.0, 1.42, 1.9] {
                let v1 = PlineVertex::new(x1, y1, b);
                let v2 = PlineVertex::new(x2, y2, 0.0);
                let (lo, hi, r) = arc_height_range(v1, v2);
                let (cx, cy) = (x2 - x1, y2 - y1);
                let k = (1.0 - b * b) / (4.0 * b);
                let c = (x1 + 0.5 * cx - cy * k, y1 + 0.5 * cy + cx * k);
                let a0 = (y1 - c.1).atan2(x1 - c.0);
                let sweep = 4.0 * f64::atan(b);
                let ys: Vec<f64> = (0..=2000)
                    .map(|i| c.1 + r * (a0 + sweep * i as f64 / 2000.0).sin())
                    .collect();
                let (slo, shi) = ys
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, z), &y| {
                        (a.min(y), z.max(y))
                    });
                let slack = 1e-9 * (1.0 + r) + r * (1.0 - (sweep / 2000.0).cos());
                assert!(
                    lo <= slo + 1e-9 * (1.0 + r) && slo - slack <= lo,
                    "b {b}: {lo} vs {slo}"
                );
                assert!(
                    shi <= hi + 1e-9 * (1.0 + r) && hi <= shi + slack,
                    "b {b}: {hi} vs {shi}"
                );
            }
        }
    }

    /// A tall zigzag of many segments: the slab count is reduced, and the answer stays.
    #[test]
    fn zigzags_keep_the_entries_bounded() {
        let mut pts: Vec<(f64, f64)> = (0..400)
            .map(|k| (k as f64 * 0.01, if k % 2 == 0 { 0.0 } else { 100.0 }))
            .collect();
        pts.push((4.0, -1.0));
        pts.push((0.0, -1.0));
        let pl = pline(&pts, &[0.0, 0.3, 0.0, -0.2]);
        let w = WindingIndex::new(&pl);
        assert!(w.slabs.entries() <= MAX_ENTRIES_PER_SEGMENT * w.segs.len() + 64 + w.segs.len());
        for p in probes(&pl) {
            assert_eq!(w.winding(p), pl.winding_number(p), "at {p:?}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

        /// Random closed polylines (self-crossing ones too) with lines and arcs of either
        /// sense, at random scales and offsets: the index gives cavalier's winding number
        /// at every probe, boundary points included.
        #[test]
        fn same_as_cavalier(
            pts in prop::collection::vec((-10i32..10, -10i32..10), 3..24),
            bulges in prop::collection::vec(prop_oneof![Just(0.0), -1.5f64..1.5], 1..6),
            scale in prop_oneof![Just(1.0), 1e-3f64..1e3],
            shift in (-1e3f64..1e3, -1e3f64..1e3),
        ) {
            let pts: Vec<(f64, f64)> = pts
                .iter()
                .map(|&(x, y)| (x as f64 * scale + shift.0, y as f64 * scale + shift.1))
                .collect();
            let pl = pline(&pts, &bulges);
            let w = WindingIndex::new(&pl);
            for p in probes(&pl) {
                prop_assert_eq!(w.winding(p), pl.winding_number(p), "at {:?}", p);
            }
        }

        /// Points just outside the box of `bounds` (a hair beyond each side, and at the
        /// heights and widths of every vertex and arc midpoint): cavalier winds 0 times
        /// about each. The box holds every vertex and every point sampled along the arcs.
        #[test]
        fn bounds_hold_every_winding(
            pts in prop::collection::vec((-10i32..10, -10i32..10), 3..24),
            bulges in prop::collection::vec(prop_oneof![Just(0.0), -1.9f64..1.9], 1..6),
            scale in prop_oneof![Just(1.0), 1e-3f64..1e3],
            shift in (-1e3f64..1e3, -1e3f64..1e3),
        ) {
            let pts: Vec<(f64, f64)> = pts
                .iter()
                .map(|&(x, y)| (x as f64 * scale + shift.0, y as f64 * scale + shift.1))
                .collect();
            let pl = pline(&pts, &bulges);
            let Aabb { min: lo, max: hi } = WindingIndex::new(&pl).bounds().expect("a closed polyline");
            let inside = |p: Vector2<f64>| {
                lo[0] <= p.x && p.x <= hi[0] && lo[1] <= p.y && p.y <= hi[1]
            };
            // Along every arc (cavalier's own arc points), and the vertices.
            for (v1, v2) in pl.iter_segments() {
                prop_assert!(inside(v1.pos()));
                if !v1.bulge_is_zero() {
                    let (_, c) = cavalier_contours::polyline::seg_arc_radius_and_center(v1, v2);
                    let a0 = (v1.y - c.y).atan2(v1.x - c.x);
                    let sweep = 4.0 * v1.bulge.atan();
                    let r = (v1.pos() - c).length();
                    for i in 0..=200 {
                        let a = a0 + sweep * i as f64 / 200.0;
                        let q = Vector2::new(c.x + r * a.cos(), c.y + r * a.sin());
                        // A sample may round a few ulps of r beyond the exact extreme.
                        let slack = 1e-12 * (r + q.x.abs() + q.y.abs());
                        prop_assert!(
                            lo[0] <= q.x + slack && q.x - slack <= hi[0]
                                && lo[1] <= q.y + slack && q.y - slack <= hi[1],
                            "arc point {:?} outside {:?}..{:?}", q, lo, hi
                        );
                    }
                }
            }
            let mut heights: Vec<f64> = pl.iter_vertexes().map(|v| v.y).collect();
            let mut widths: Vec<f64> = pl.iter_vertexes().map(|v| v.x).collect();
            heights.extend([lo[1], hi[1], 0.5 * (lo[1] + hi[1])]);
            widths.extend([lo[0], hi[0], 0.5 * (lo[0] + hi[0])]);
            let beyond = |a: f64, up: bool| {
                let step = 1e-12 * (1.0 + a.abs());
                if up { a + step } else { a - step }
            };
            for &y in &heights {
                for q in [Vector2::new(beyond(lo[0], false), y), Vector2::new(beyond(hi[0], true), y)] {
                    prop_assert_eq!(pl.winding_number(q), 0, "at {:?}", q);
                }
            }
            for &x in &widths {
                for q in [Vector2::new(x, beyond(lo[1], false)), Vector2::new(x, beyond(hi[1], true))] {
                    prop_assert_eq!(pl.winding_number(q), 0, "at {:?}", q);
                }
            }
        }
    }
}
