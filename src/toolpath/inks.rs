//! The visible boundaries between inks: where two differently coloured painted areas meet
//! inside a drawing, or a later item lies on an earlier one (the painter's algorithm, SVG
//! 1.1 §3.3), each boundary once.
//!
//! Items come in paint order, each a region with an ink (equal inks look alike). The top
//! item at a point q is the last one whose region holds q. A piece of item i's boundary is
//! an inner visible boundary owned by i when, probing at distance δ on both sides along its
//! normal n (q± = p ± δ·n), one side's top item is i itself (the boundary is not hidden by
//! a later item) and the other side's is an earlier item j < i of another ink. So:
//! - a boundary with nothing on its other side (the outside of the union, or a hole in it:
//!   a knockout) is not inner: a profile of the union cuts it;
//! - two abutting items share one boundary: the later owns it, the earlier's copy (whose
//!   other side is the later item) is dropped, so it is cut once;
//! - the parts of an item's boundary that a later item covers are hidden;
//! - boundaries between items of one ink are not seen.
//!
//! δ ([`PROBE_FRACTION`] of the tolerance) exceeds the gaps between boundaries that meet
//! only within rounding (the import rounds to 10⁻⁶ mm; polygon booleans snap) and the
//! sagitta of the flattening, so coincident edges are read as one. The classification of a
//! segment can change only where some boundary crosses one of its two probe lines (the
//! segment moved by ±δ·n), so those crossings split it into pieces that are each decided
//! by their midpoint: no feature is missed, whatever its size. Consecutive kept pieces join
//! into runs; open runs shorter than the tolerance (corners where three items meet), or a
//! longer minimum the caller gives, are dropped.
//!
//! Cost: each segment asks an R-tree of the segments for those within δ of it, and each
//! probe the items whose boxes hold it, each through a winding index of its contours
//! ([`crate::geom::index::WindingIndex`], O(1 + k) a query): O((n + k) log n) for n segments.

use super::region::Region;
use crate::geom::index::WindingIndex;
use crate::geom::interop::{self, flatten_pline};
use crate::geom::{Aabb, DVec2};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

/// Probe distance δ as a fraction of the tolerance (see the module docs); the boundaries
/// are flattened within [`FLATTEN_FRACTION`] of it, which δ exceeds.
pub const PROBE_FRACTION: f64 = 0.5;

/// Flattening tolerance of the boundaries as a fraction of the tolerance: below δ, so a
/// probe from a chord lands on the side of the arc it is meant for.
pub const FLATTEN_FRACTION: f64 = 0.25;

/// Dropped stretches of a boundary shorter than this fraction of the tolerance between two
/// kept ones are kept (`bridge_gaps`): a reflex corner hides a few δ of its edges from
/// the probes (δ·cot(θ/2) for an inner turn θ, 2δ at a right angle; 4 tolerances cover turns
/// down to about 15°).
pub const BRIDGE_FRACTION: f64 = 4.0;

/// One painted item, in paint order.
#[derive(Clone, Debug)]
pub struct Painted<'a> {
    /// Its area.
    pub region: &'a Region,
    /// Its ink: items of equal ink are painted alike.
    pub ink: usize,
}

/// A run of an inner visible boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    /// The item (index in paint order) whose boundary it is.
    pub item: usize,
    /// Its points; a closed run's first point is not repeated at its end.
    pub points: Vec<DVec2>,
    /// Whether the run is a whole contour.
    pub closed: bool,
}

type Boxed = GeomWithData<Rectangle<[f64; 2]>, usize>;

/// A segment's box with its (item, contour, index of its first point).
type BoxedSegment = GeomWithData<Rectangle<[f64; 2]>, (usize, usize, usize)>;

/// The flattened contours of the items and what asks them where a point lies.
struct Inks<'a> {
    items: &'a [Painted<'a>],
    /// Per item, per contour: its ring (first point not repeated).
    rings: Vec<Vec<Vec<DVec2>>>,
    /// Per item, per contour: its winding index.
    windings: Vec<Vec<WindingIndex>>,
    /// Every segment (item, contour, index of its first point) by its box.
    segments: RTree<BoxedSegment>,
    /// Every item by its box.
    boxes: RTree<Boxed>,
}

impl<'a> Inks<'a> {
    fn new(items: &'a [Painted<'a>], tol: f64) -> Self {
        let rings: Vec<Vec<Vec<DVec2>>> = items
            .iter()
            .map(|it| {
                (it.region.contours.iter())
                    .map(|c| {
                        let mut r = flatten_pline(c, tol * FLATTEN_FRACTION);
                        if r.len() > 1 && r.first() == r.last() {
                            r.pop();
                        }
                        r
                    })
                    .collect()
            })
            .collect();
        let windings = (items.iter())
            .map(|it| it.region.contours.iter().map(WindingIndex::new).collect())
            .collect();
        let mut segs = Vec::new();
        let mut boxes = Vec::new();
        for (i, item) in rings.iter().enumerate() {
            let mut all = Aabb::EMPTY;
            for (k, ring) in item.iter().enumerate() {
                for s in 0..ring.len() {
                    let (a, b) = (ring[s], ring[(s + 1) % ring.len()]);
                    let seg = Aabb::from_corners(a, b);
                    segs.push(GeomWithData::new(interop::rectangle(seg), (i, k, s)));
                    all = all.add_point(a);
                }
            }
            // Arcs bulge past their chords by less than the flattening tolerance.
            if all.min.x <= all.max.x {
                boxes.push(GeomWithData::new(interop::rectangle(all.grow(tol)), i));
            }
        }
        Inks {
            items,
            rings,
            windings,
            segments: RTree::bulk_load(segs),
            boxes: RTree::bulk_load(boxes),
        }
    }

    /// The last item (in paint order) whose region holds `q` (non-zero total winding).
    fn top(&self, q: DVec2) -> Option<usize> {
        let v = interop::vector2(q);
        self.boxes
            .locate_all_at_point(q.to_array())
            .map(|g| g.data)
            .filter(|&i| self.windings[i].iter().map(|w| w.winding(v)).sum::<i32>() != 0)
            .max()
    }

    /// Whether the piece of item `i`'s boundary at `p` (unit normal `n`) is an inner
    /// visible boundary that `i` owns (module docs).
    fn owned(&self, i: usize, p: DVec2, n: DVec2, delta: f64) -> bool {
        let (a, b) = (self.top(p + delta * n), self.top(p - delta * n));
        let other = match (a, b) {
            (Some(x), y) if x == i => y,
            (x, Some(y)) if y == i => x,
            _ => return false,
        };
        other.is_some_and(|j| j < i && self.items[j].ink != self.items[i].ink)
    }

    /// Parameters in (0, 1) along `a`→`b` where a segment other than this one (item `i`,
    /// contour `k`, index `s`) crosses one of its probe lines (the segment moved by ±δ·n),
    /// sorted.
    fn breaks(&self, (i, k, s): (usize, usize, usize), a: DVec2, b: DVec2, delta: f64) -> Vec<f64> {
        let d = b - a;
        let n = d.perp().normalize_or_zero();
        let pad = DVec2::splat(delta * 1.5);
        let env = AABB::from_corners(
            [a.min(b).x - pad.x, a.min(b).y - pad.y],
            [a.max(b).x + pad.x, a.max(b).y + pad.y],
        );
        let mut ts = Vec::new();
        for g in self.segments.locate_in_envelope_intersecting(env) {
            if g.data == (i, k, s) {
                continue;
            }
            let (j, kk, ss) = g.data;
            let ring = &self.rings[j][kk];
            let (c, e) = (ring[ss], ring[(ss + 1) % ring.len()]);
            for side in [delta, -delta] {
                let o = side * n;
                if let Some(t) = crossing(a + o, b + o, c, e) {
                    ts.push(t);
                }
            }
        }
        ts.retain(|t| *t > 0.0 && *t < 1.0);
        ts.sort_by(f64::total_cmp);
        ts
    }
}

/// The parameter t along p→q where it meets the segment c→e (both closed), or `None` when
/// they do not meet or are parallel.
fn crossing(p: DVec2, q: DVec2, c: DVec2, e: DVec2) -> Option<f64> {
    let (r, s) = (q - p, e - c);
    let den = r.perp_dot(s);
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let t = (c - p).perp_dot(s) / den;
    let u = (c - p).perp_dot(r) / den;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some(t)
}

/// The inner visible boundaries of `items` (in paint order), each once, within `tol`
/// (module docs): runs along the items' contours, each owned by the item whose contour it
/// follows. Open runs shorter than `min_open` (at least `tol`: corners where three items
/// meet) are left out; closed runs are always kept.
pub fn inner_boundaries(items: &[Painted<'_>], tol: f64, min_open: f64) -> Vec<Boundary> {
    let min_open = min_open.max(tol);
    let delta = tol * PROBE_FRACTION;
    let inks = Inks::new(items, tol);
    let mut out = Vec::new();
    for (i, rings) in inks.rings.iter().enumerate() {
        for (k, ring) in rings.iter().enumerate() {
            if ring.len() < 2 {
                continue;
            }
            // The ring's pieces in order: (start, end, kept).
            let mut pieces: Vec<(DVec2, DVec2, bool)> = Vec::new();
            for s in 0..ring.len() {
                let (a, b) = (ring[s], ring[(s + 1) % ring.len()]);
                if a == b {
                    continue;
                }
                let n = (b - a).perp().normalize();
                let mut ts = vec![0.0];
                ts.extend(inks.breaks((i, k, s), a, b, delta));
                ts.push(1.0);
                for w in ts.windows(2) {
                    if w[1] > w[0] {
                        let m = a.lerp(b, 0.5 * (w[0] + w[1]));
                        let keep = inks.owned(i, m, n, delta);
                        pieces.push((a.lerp(b, w[0]), a.lerp(b, w[1]), keep));
                    }
                }
            }
            bridge_gaps(&mut pieces, BRIDGE_FRACTION * tol);
            for (points, closed) in runs(&pieces) {
                let length: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
                if closed || length >= min_open {
                    out.push(Boundary {
                        item: i,
                        points: simplify(points),
                        closed,
                    });
                }
            }
        }
    }
    out
}

/// Marks kept the dropped stretches of a ring's pieces shorter than `gap` that lie between
/// kept ones (cyclically): near a reflex corner of an item, the probe off one edge falls
/// into the item across the other edge, so a few δ on either side of the corner read as
/// inside; the boundary goes on through the corner.
fn bridge_gaps(pieces: &mut [(DVec2, DVec2, bool)], gap: f64) {
    let n = pieces.len();
    let Some(kept) = pieces.iter().position(|p| p.2) else {
        return;
    };
    // Walk once around from a kept piece, collecting each dropped stretch.
    let mut k = 0;
    while k < n {
        let at = (kept + k) % n;
        if pieces[at].2 {
            k += 1;
            continue;
        }
        let mut len = 0.0;
        let mut m = k;
        while m < n && !pieces[(kept + m) % n].2 {
            let (a, b, _) = pieces[(kept + m) % n];
            len += a.distance(b);
            m += 1;
        }
        // `m < n`: a kept piece follows (the walk started on one, so both sides are kept).
        if m < n && len < gap {
            for j in k..m {
                pieces[(kept + j) % n].2 = true;
            }
        }
        k = m;
    }
}

/// The runs of consecutive kept pieces of a ring (cyclically), with whether a run is the
/// whole ring.
fn runs(pieces: &[(DVec2, DVec2, bool)]) -> Vec<(Vec<DVec2>, bool)> {
    if pieces.iter().all(|p| p.2) {
        return vec![(pieces.iter().map(|p| p.0).collect(), true)];
    }
    // Start after a dropped piece, so no run wraps past the start.
    let start = pieces.iter().position(|p| !p.2).unwrap_or(0) + 1;
    let mut out: Vec<(Vec<DVec2>, bool)> = Vec::new();
    let mut open = false;
    for k in 0..pieces.len() {
        let (a, b, keep) = pieces[(start + k) % pieces.len()];
        if keep {
            match out.last_mut() {
                Some((run, _)) if open => run.push(b),
                _ => out.push((vec![a, b], false)),
            }
        }
        open = keep;
    }
    out
}

/// The run without the points where it goes straight on (pieces of one segment split at
/// breaks that kept both sides).
fn simplify(points: Vec<DVec2>) -> Vec<DVec2> {
    let mut out: Vec<DVec2> = Vec::with_capacity(points.len());
    for p in points {
        if out.last() == Some(&p) {
            continue;
        }
        if let [.., u, v] = out[..]
            && (v - u).perp_dot(p - v) == 0.0
            && (v - u).dot(p - v) > 0.0
        {
            out.pop();
        }
        out.push(p);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::interop::pline_from_points;

    const TOL: f64 = 0.01;

    fn region(rings: &[Vec<DVec2>]) -> Region {
        Region::from_contours(rings.iter().map(|r| pline_from_points(r, true)).collect())
    }

    fn square(x: f64, y: f64, a: f64) -> Vec<DVec2> {
        vec![
            DVec2::new(x, y),
            DVec2::new(x + a, y),
            DVec2::new(x + a, y + a),
            DVec2::new(x, y + a),
        ]
    }

    fn circle(c: DVec2, r: f64, n: usize) -> Vec<DVec2> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                c + r * DVec2::new(t.cos(), t.sin())
            })
            .collect()
    }

    /// Length of the polyline `points`, closed back to its first point where `closed`.
    fn polyline_length(points: &[DVec2], closed: bool) -> f64 {
        let mut l: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
        if let (true, Some(first), Some(last)) = (closed, points.first(), points.last()) {
            l += last.distance(*first);
        }
        l
    }

    fn length(b: &Boundary) -> f64 {
        polyline_length(&b.points, b.closed)
    }

    /// Distance from `p` to the segment a→b.
    fn seg_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
        let d = b - a;
        let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
        p.distance(a + t * d)
    }

    /// Two abutting squares of different inks share one edge: one open run along it, of
    /// exactly the edge's length, owned by the later square; of one ink, nothing.
    #[test]
    fn abutting_squares_of_two_inks_share_one_edge_cut() {
        let (a, b) = (
            region(&[square(0.0, 0.0, 10.0)]),
            region(&[square(10.0, 2.0, 10.0)]),
        );
        let items = [
            Painted { region: &a, ink: 0 },
            Painted { region: &b, ink: 1 },
        ];
        let runs = inner_boundaries(&items, TOL, TOL);
        assert_eq!(runs.len(), 1, "{runs:?}");
        let r = &runs[0];
        assert_eq!(r.item, 1);
        assert!(!r.closed);
        // The shared edge is x = 10, y ∈ [2, 10]: 8 long.
        assert!((length(r) - 8.0).abs() < 1e-9, "{}", length(r));
        for p in &r.points {
            assert!((p.x - 10.0).abs() < 1e-12 && p.y >= 2.0 - 1e-12 && p.y <= 10.0 + 1e-12);
        }
        let same = [
            Painted { region: &a, ink: 3 },
            Painted { region: &b, ink: 3 },
        ];
        assert!(inner_boundaries(&same, TOL, TOL).is_empty());
    }

    /// A white knockout is a hole of the black square: its boundary is the union's, cut by
    /// the profile, not an inner boundary. A grey disk painted on the square instead is
    /// an inner boundary, cut once as a closed run along the whole circle.
    #[test]
    fn knockout_is_profiled_and_a_disk_on_top_is_one_closed_run() {
        let disk = circle(DVec2::new(5.0, 5.0), 2.0, 64);
        let mut hole = disk.clone();
        hole.reverse();
        let with_hole = region(&[square(0.0, 0.0, 10.0), hole]);
        assert!(
            inner_boundaries(
                &[Painted {
                    region: &with_hole,
                    ink: 0
                }],
                TOL,
                TOL
            )
            .is_empty()
        );
        let plate = region(&[square(0.0, 0.0, 10.0)]);
        let top = region(std::slice::from_ref(&disk));
        let items = [
            Painted {
                region: &plate,
                ink: 0,
            },
            Painted {
                region: &top,
                ink: 1,
            },
        ];
        let runs = inner_boundaries(&items, TOL, TOL);
        assert_eq!(runs.len(), 1, "{runs:?}");
        assert!(runs[0].closed && runs[0].item == 1);
        let perimeter = polyline_length(&disk, true);
        assert!((length(&runs[0]) - perimeter).abs() < 1e-9);
        // The disk cut out of the plate first (as the import's paint model writes it): the
        // plate's hole and the disk's edge coincide; still one run, the disk's.
        let items = [
            Painted {
                region: &with_hole,
                ink: 0,
            },
            Painted {
                region: &top,
                ink: 1,
            },
        ];
        let runs = inner_boundaries(&items, TOL, TOL);
        assert_eq!(runs.len(), 1, "{runs:?}");
        assert!(runs[0].closed && runs[0].item == 1);
        assert!((length(&runs[0]) - perimeter).abs() < 1e-9);
    }

    /// A later item hides the boundary under it: a square on a square on a plate of a third
    /// ink. Every kept point lies on a boundary where the visible ink changes, and the
    /// total equals the closed-form length of the visible inner boundaries.
    #[test]
    fn later_items_hide_the_boundaries_under_them() {
        let plate = region(&[square(0.0, 0.0, 30.0)]);
        let a = region(&[square(5.0, 5.0, 10.0)]);
        let b = region(&[square(10.0, 10.0, 10.0)]);
        let items = [
            Painted {
                region: &plate,
                ink: 0,
            },
            Painted { region: &a, ink: 1 },
            Painted { region: &b, ink: 2 },
        ];
        let runs = inner_boundaries(&items, TOL, TOL);
        let total: f64 = runs.iter().map(length).sum();
        // b: its whole perimeter 40; a: its perimeter 40 minus the 2·5 under b.
        assert!((total - 70.0).abs() < 1e-9, "{total} {runs:?}");
        for r in &runs {
            for p in &r.points {
                let on =
                    |sq: &[DVec2]| (0..4).any(|k| seg_distance(*p, sq[k], sq[(k + 1) % 4]) < 1e-12);
                assert!(on(&square(5.0, 5.0, 10.0)) || on(&square(10.0, 10.0, 10.0)));
                // Not inside b (hidden) unless on b's own boundary.
                let inside_b = p.x > 10.0 && p.x < 20.0 && p.y > 10.0 && p.y < 20.0;
                assert!(!inside_b, "{p}");
            }
        }
        // Nothing is cut twice: the runs' lengths add up to the visible boundary's length
        // (above), so no piece is counted twice.
        let b_runs: f64 = runs.iter().filter(|r| r.item == 2).map(length).sum();
        assert!((b_runs - 40.0).abs() < 1e-9);
    }

    /// An L (a reflex corner, and a sharp 20° notch) painted on a plate is one closed run
    /// along its whole boundary: the corners' few δ where the probes read the item on both
    /// sides are bridged.
    #[test]
    fn reflex_corners_do_not_split_the_run() {
        let plate = region(&[square(-10.0, -10.0, 40.0)]);
        let notch = 10.0f64.to_radians().tan() * 8.0;
        let l = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(10.0, 4.0),
            DVec2::new(4.0, 4.0),
            DVec2::new(4.0, 10.0),
            DVec2::new(2.0 + notch, 10.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(2.0 - notch, 10.0),
            DVec2::new(0.0, 10.0),
        ];
        let top = region(std::slice::from_ref(&l));
        let items = [
            Painted {
                region: &plate,
                ink: 0,
            },
            Painted {
                region: &top,
                ink: 1,
            },
        ];
        let runs = inner_boundaries(&items, TOL, TOL);
        assert_eq!(runs.len(), 1, "{runs:?}");
        assert!(runs[0].closed);
        let perimeter = polyline_length(&l, true);
        assert!((length(&runs[0]) - perimeter).abs() < 1e-9);
    }
}
