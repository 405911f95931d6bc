//! Cut ordering: inner contours before the contours that enclose them, always; then short
//! travel by nearest neighbour (with the entry point of each closed contour chosen as its
//! point nearest to the tool) improved by 2-opt moves that respect the precedence.
//!
//! Complexity: precedence O(n log n + k · m) for n contours of m points (an R-tree of the
//! boxes finds the k pairs whose boxes nest; only those get containment tests); nearest
//! neighbour over an
//! R-tree of the boxes of the paths free to go (those whose inner paths are done), each
//! step visiting the paths in order of box distance until the box is farther than the best
//! entry found: O(n log n + n · c · m) for c paths visited a step (a few for a hatch's rows
//! or a drawing's strokes; all n for paths nested like onion rings around the tool); 2-opt
//! over blocks of at most [`MAX_2OPT_BLOCK`] paths, O(n · MAX_2OPT_BLOCK) per sweep (O(n²)
//! up to that many paths), at most `MAX_2OPT_SWEEPS` sweeps and at most `MAX_2OPT_WORK`
//! pair tests in all, and only up to [`MAX_NEAREST_PATHS`] paths: a fine hatch fill or a
//! large drawing is ordered by nearest neighbour alone. No loop here refines: each ends after a
//! number of steps fixed by n and these constants.

use crate::geom::index::PolygonWinding;
use crate::geom::tol::LENGTH_ACCURACY;
use crate::geom::{Aabb, Arc, DVec2, Line, Path, PathSeg, interop};
use rstar::RTree;
use rstar::primitives::{GeomWithData, Rectangle};

/// Least travel a 2-opt move must save to be made (model units): moves that only reorder
/// rounding are not taken, so the sweeps end.
const MIN_2OPT_GAIN: f64 = 1e-12;

/// Upper bound on 2-opt improvement sweeps; improvement stalls far earlier.
const MAX_2OPT_SWEEPS: usize = 50;

/// Upper bound on 2-opt pair tests over all sweeps (≈ 1 s of work): a sweep over m paths
/// tests Σₐ (min(B, m − a) − 1) pairs for blocks of at most B = [`MAX_2OPT_BLOCK`] paths
/// (m(m − 1)/2 up to B paths), so the number of sweeps is also limited to
/// `MAX_2OPT_WORK` divided by that.
const MAX_2OPT_WORK: usize = 200_000_000;

/// Longest block of consecutive paths a 2-opt move reverses: a sweep tests at most this
/// many pairs per path, O(n) per sweep instead of O(n²). Jobs of up to this many paths
/// see every pair as before.
pub const MAX_2OPT_BLOCK: usize = 1_000;

/// Most paths of one operation whose nearest-neighbour order is improved by 2-opt; more
/// are ordered by nearest neighbour alone (a 2-opt sweep is O(n²)).
pub const MAX_NEAREST_PATHS: usize = 5_000;

/// Travel figures of an ordering.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrderStats {
    /// Travel (tool up) length in the input order, each path entered at its own start.
    pub travel_input: f64,
    /// Travel length in the chosen order.
    pub travel_ordered: f64,
}

/// `before[j]` lists the paths that must come before path j: those inside closed path j,
/// in increasing order. A path whose vertices all lie inside polygon j also lies inside j's
/// vertex box, so only the paths whose boxes lie in j's box are tested (found through an
/// R-tree of the boxes); their vertices are tested through a slab index of polygon j
/// (`PolygonWinding`, the exact even-odd test in O(1 + k) per vertex).
pub fn precedence(paths: &[Path], tol: f64) -> Vec<Vec<usize>> {
    let polys: Vec<Vec<DVec2>> = paths.iter().map(|p| p.flatten(tol)).collect();
    let boxes: Vec<Aabb> = polys.iter().map(Aabb::from_points).collect();
    // The boxes of the non-empty paths; the paths whose boxes lie in box j (edges included)
    // are the candidates inside path j.
    let tree: RTree<BoxEntry> = RTree::bulk_load(
        (0..paths.len())
            .filter(|&i| !polys[i].is_empty())
            .map(|i| BoxEntry::new(interop::rectangle(boxes[i]), i))
            .collect(),
    );
    (0..paths.len())
        .map(|j| {
            if !paths[j].closed || polys[j].len() < 3 {
                return Vec::new();
            }
            let mut inner: Vec<usize> = tree
                .locate_in_envelope(interop::envelope(boxes[j]))
                .map(|e| e.data)
                .filter(|&i| i != j)
                .collect();
            if inner.is_empty() {
                return inner;
            }
            inner.sort_unstable();
            let w = PolygonWinding::new(&polys[j]);
            inner.retain(|&i| polys[i].iter().all(|&p| w.inside_even_odd(p)));
            inner
        })
        .collect()
}

/// Parameter accuracy of the nearest point on a cubic ([`crate::geom::CubicBez::nearest`]):
/// far below the snapping distance of entry points for any cubic shorter than a kilometre.
const CUBIC_NEAREST_ACCURACY: f64 = 1e-12;

/// The point of a line, arc or cubic nearest to `p`, as (parameter, distance).
fn nearest_on_seg(s: &PathSeg, p: DVec2) -> (f64, f64) {
    match s {
        PathSeg::Line(l) => {
            let t = l.nearest_t(p);
            (t, l.eval(t).distance(p))
        }
        PathSeg::Arc(a) => {
            // Angle of p relative to the arc start along the sweep, clamped to the arc.
            let ang = (p - a.center).to_angle();
            let rel = ((ang - a.start) * a.sweep.signum()).rem_euclid(2.0 * std::f64::consts::PI);
            let t = if rel <= a.sweep.abs() {
                rel / a.sweep.abs()
            } else if a.eval(0.0).distance(p) < a.eval(1.0).distance(p) {
                0.0
            } else {
                1.0
            };
            (t, a.eval(t).distance(p))
        }
        // Cubics are fitted to arcs before ordering; a path that keeps one gets its exact
        // nearest point.
        PathSeg::Cubic(c) => c.nearest(p, CUBIC_NEAREST_ACCURACY),
    }
}

fn split_seg(s: &PathSeg, t: f64) -> (PathSeg, PathSeg) {
    match s {
        PathSeg::Line(l) => {
            let m = l.eval(t);
            (
                PathSeg::Line(Line::new(l.p0, m)),
                PathSeg::Line(Line::new(m, l.p1)),
            )
        }
        PathSeg::Arc(a) => (
            PathSeg::Arc(Arc::new(a.center, a.radius, a.start, t * a.sweep)),
            PathSeg::Arc(Arc::new(
                a.center,
                a.radius,
                a.start + t * a.sweep,
                (1.0 - t) * a.sweep,
            )),
        ),
        PathSeg::Cubic(c) => {
            let (x, y) = c.split(t);
            (PathSeg::Cubic(x), PathSeg::Cubic(y))
        }
    }
}

/// `path` as it is cut when the tool comes from `pos`: a closed path rotated to start at
/// its point nearest `pos` (within `tol`), an open one from its nearer end.
fn entered_near(path: &Path, pos: DVec2, tol: f64) -> Path {
    if path.closed {
        rotate_to_nearest(path, pos, tol)
    } else {
        let (s, e) = ends(path);
        if e.distance(pos) < s.distance(pos) {
            path.reversed()
        } else {
            path.clone()
        }
    }
}

/// The closed path started at its point nearest to `p` (splitting a segment there; a split
/// within `eps` of a segment end uses that end).
pub fn rotate_to_nearest(path: &Path, p: DVec2, eps: f64) -> Path {
    if !path.closed || path.segs.is_empty() {
        return path.clone();
    }
    let (best, (t, _)) = path
        .segs
        .iter()
        .map(|s| nearest_on_seg(s, p))
        .enumerate()
        .fold(
            (0, (0.0, f64::INFINITY)),
            |a, b| if b.1.1 < a.1.1 { b } else { a },
        );
    let seg = &path.segs[best];
    let len = seg.length(LENGTH_ACCURACY);
    let mut segs = Vec::with_capacity(path.segs.len() + 1);
    if t * len <= eps {
        segs.extend_from_slice(&path.segs[best..]);
        segs.extend_from_slice(&path.segs[..best]);
    } else if (1.0 - t) * len <= eps {
        segs.extend_from_slice(&path.segs[best + 1..]);
        segs.extend_from_slice(&path.segs[..=best]);
    } else {
        let (a, b) = split_seg(seg, t);
        segs.push(b);
        segs.extend_from_slice(&path.segs[best + 1..]);
        segs.extend_from_slice(&path.segs[..best]);
        segs.push(a);
    }
    Path::new(segs, true)
}

fn ends(p: &Path) -> (DVec2, DVec2) {
    (
        p.start().unwrap_or(DVec2::ZERO),
        p.end().unwrap_or(DVec2::ZERO),
    )
}

fn travel(order: &[Path], home: DVec2) -> f64 {
    let mut pos = home;
    let mut sum = 0.0;
    for p in order {
        let (s, e) = ends(p);
        sum += pos.distance(s);
        pos = e;
    }
    sum
}

/// A path's box in the R-tree of [`nearest_neighbour`], with the path's index.
type BoxEntry = GeomWithData<Rectangle<[f64; 2]>, usize>;

/// Relative slack of the R-tree walk's stopping test: its squared box distances are rounded
/// apart from [`Aabb::distance`], so the walk goes on a hair past the best entry and the test
/// that decides is `Aabb::distance`'s own.
const WALK_SLACK: f64 = 1e-9;

/// Nearest neighbour from `home` among the paths whose predecessors (`before`, the
/// precedence) are all done: the path whose entry ([`entered_near`]) is nearest the tool
/// comes next, the lower index on a tie. The candidates are the paths free to go, kept in
/// an R-tree of their `boxes` (which contain the paths): they are visited in order of box
/// distance until the box is farther than the best entry, which no path in it can beat.
fn nearest_neighbour(
    paths: &[Path],
    before: &[Vec<usize>],
    boxes: &[Aabb],
    home: DVec2,
    tol: f64,
) -> Vec<(usize, Path)> {
    let n = paths.len();
    let entry = |i: usize| BoxEntry::new(interop::rectangle(boxes[i]), i);
    let mut waiting: Vec<usize> = before.iter().map(Vec::len).collect();
    let mut after: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (j, b) in before.iter().enumerate() {
        for &k in b {
            after[k].push(j);
        }
    }
    let mut free = RTree::bulk_load((0..n).filter(|&i| waiting[i] == 0).map(entry).collect());
    let mut order = Vec::with_capacity(n);
    let mut pos = home;
    while free.size() > 0 {
        let mut best: Option<(usize, f64, Path)> = None;
        for (e, d2) in free.nearest_neighbor_iter_with_distance_2(pos.to_array()) {
            let i = e.data;
            if let Some(b) = &best {
                if d2.sqrt() > b.1 * (1.0 + WALK_SLACK) + WALK_SLACK {
                    break;
                }
                // The entry of path i is a point of it (or an end): no nearer than its box.
                if boxes[i].distance(pos) > b.1 {
                    continue;
                }
            }
            let cand = entered_near(&paths[i], pos, tol);
            let d = ends(&cand).0.distance(pos);
            if best
                .as_ref()
                .is_none_or(|b| d < b.1 || (d == b.1 && i < b.0))
            {
                best = Some((i, d, cand));
            }
        }
        let Some((i, _, p)) = best else { break };
        free.remove(&entry(i));
        for &j in &after[i] {
            waiting[j] -= 1;
            if waiting[j] == 0 {
                free.insert(entry(j));
            }
        }
        pos = ends(&p).1;
        order.push((i, p));
    }
    order
}

/// Order `paths` for cutting from `home`: every path inside a closed path comes first;
/// closed paths start at their point nearest the tool; open paths may run reversed.
/// `tol` is the flattening tolerance for containment tests and the snapping distance for
/// entry points. Each result carries the index of its input path.
pub fn order_paths(paths: &[Path], home: DVec2, tol: f64) -> (Vec<(usize, Path)>, OrderStats) {
    let n = paths.len();
    let before = precedence(paths, tol);
    // Boxes of the flattenings, grown by the flattening tolerance so that they contain the
    // paths: no point of path i is nearer to the tool than `boxes[i].distance(pos)`.
    let boxes: Vec<Aabb> = (paths.iter())
        .map(|p| Aabb::from_points(&p.flatten(tol)).grow(tol))
        .collect();
    let travel_input = travel(paths, home);
    let order = nearest_neighbour(paths, &before, &boxes, home, tol);
    if n > MAX_NEAREST_PATHS {
        let travel_ordered = travel(
            &order.iter().map(|(_, p)| p.clone()).collect::<Vec<_>>(),
            home,
        );
        return (
            order,
            OrderStats {
                travel_input,
                travel_ordered,
            },
        );
    }
    let mut order = order;
    // 2-opt: reverse order[a..=b] (at most MAX_2OPT_BLOCK paths) when it shortens travel and
    // no precedence pair lies inside. `p` is the position of each path in `order`.
    let mut p = vec![0usize; n];
    for (k, (i, _)) in order.iter().enumerate() {
        p[*i] = k;
    }
    let m = order.len();
    let pairs_per_sweep = (0..m)
        .map(|a| MAX_2OPT_BLOCK.min(m - a) - 1)
        .sum::<usize>()
        .max(1);
    let sweeps = MAX_2OPT_SWEEPS.min(MAX_2OPT_WORK / pairs_per_sweep);
    // Start, end and closedness of each path in `order`, kept in step with it: the pair
    // tests read these instead of each path's segments.
    let mut at: Vec<(DVec2, DVec2, bool)> = order
        .iter()
        .map(|(_, p)| {
            let (s, e) = ends(p);
            (s, e, p.closed)
        })
        .collect();
    // After reversal a block is entered at its last path's reversed start (its end for
    // open paths, its start for closed ones) and left at its first path's reversed end.
    let rev_start = |&(s, e, closed): &(DVec2, DVec2, bool)| if closed { s } else { e };
    let rev_end = |&(s, e, closed): &(DVec2, DVec2, bool)| if closed { e } else { s };
    // Travel from each path's end to the next path's start (0 after the last), kept in step
    // with `at`: the part of a pair's old travel that does not depend on the block's start.
    let gap_at = |at: &[(DVec2, DVec2, bool)], b: usize| {
        if b + 1 < m {
            at[b].1.distance(at[b + 1].0)
        } else {
            0.0
        }
    };
    let mut gap: Vec<f64> = (0..m).map(|b| gap_at(&at, b)).collect();
    for _ in 0..sweeps {
        let mut improved = false;
        for a in 0..m {
            let prev_end = if a == 0 { home } else { at[a - 1].1 };
            let mut head = prev_end.distance(at[a].0);
            for b in a + 1..m.min(a + MAX_2OPT_BLOCK) {
                let old = head + gap[b];
                // new = enter + leave with leave ≥ 0, so new + 1e-12 ≥ enter + 1e-12 in
                // floating point as well: a block that cannot be entered cheaply enough is
                // skipped before its second distance is taken.
                let enter = prev_end.distance(rev_start(&at[b]));
                if enter + MIN_2OPT_GAIN >= old {
                    continue;
                }
                let next_start = (b + 1 < m).then(|| at[b + 1].0);
                let new = enter + next_start.map_or(0.0, |s| rev_end(&at[a]).distance(s));
                if new + MIN_2OPT_GAIN < old {
                    let blocked = order[a..=b]
                        .iter()
                        .any(|(j, _)| before[*j].iter().any(|&k| p[k] >= a && p[k] <= b));
                    if !blocked {
                        order[a..=b].reverse();
                        at[a..=b].reverse();
                        for (k, (i, _)) in order.iter().enumerate().take(b + 1).skip(a) {
                            p[*i] = k;
                        }
                        for (item, cached) in order[a..=b].iter_mut().zip(&mut at[a..=b]) {
                            if !item.1.closed {
                                item.1 = item.1.reversed();
                                let (s, e) = ends(&item.1);
                                *cached = (s, e, false);
                            }
                        }
                        let from = a.saturating_sub(1);
                        for (k, g) in gap.iter_mut().enumerate().take(b + 1).skip(from) {
                            *g = gap_at(&at, k);
                        }
                        head = prev_end.distance(at[a].0);
                        improved = true;
                    }
                }
            }
        }
        if !improved {
            break;
        }
    }
    let travel_ordered = travel(
        &order.iter().map(|(_, p)| p.clone()).collect::<Vec<_>>(),
        home,
    );
    (
        order,
        OrderStats {
            travel_input,
            travel_ordered,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::tests::square;
    use proptest::prelude::*;

    fn contains(outer: &Path, inner: &Path) -> bool {
        let poly = outer.flatten(1e-3);
        inner
            .flatten(1e-3)
            .iter()
            .all(|&p| crate::geom::predicates::inside_even_odd(&poly, p))
    }

    /// Beyond MAX_NEAREST_PATHS (nearest neighbour without 2-opt): a permutation, inner
    /// before outer, and on a hatch given in a scattered order the rows are cut one after
    /// the other, alternating ends, as a boustrophedon (travel: the row spacing a row).
    #[test]
    fn many_paths_are_ordered_by_nearest_neighbour_and_respect_precedence() {
        let n = MAX_NEAREST_PATHS + 10;
        let rows = n - 3;
        let mut paths: Vec<Path> = Vec::with_capacity(n);
        // Three nested squares, outermost first (the wrong order), then the rows of a
        // hatch, given in a scattered order (every 7th row modulo the count).
        for s in [30.0, 20.0, 10.0] {
            paths.push(square(DVec2::new(-100.0, 0.0), s));
        }
        assert!(!rows.is_multiple_of(7));
        for k in 0..rows {
            let y = ((k * 7) % rows) as f64 * 0.01;
            paths.push(Path::polyline(
                &[DVec2::new(0.0, y), DVec2::new(5.0, y)],
                false,
            ));
        }
        let (o, stats) = order_paths(&paths, DVec2::ZERO, 1e-3);
        let mut seen: Vec<usize> = o.iter().map(|(i, _)| *i).collect();
        let at = |i: usize| seen.iter().position(|&k| k == i).unwrap();
        assert!(at(2) < at(1) && at(1) < at(0));
        // The rows from y = 0 upwards, each entered at the end where the last one left.
        let lines: Vec<&Path> = o.iter().filter(|(i, _)| *i >= 3).map(|(_, p)| p).collect();
        let mut rise = 0.0;
        for w in lines.windows(2) {
            let (a, b) = (ends(w[0]), ends(w[1]));
            assert_eq!(a.1.x, b.0.x);
            rise += b.0.y - a.1.y;
        }
        assert!((rise - (rows - 1) as f64 * 0.01).abs() < 1e-6, "{rise}");
        // The hatch's travel: its rows' spacing, then to the squares and between them.
        let hatch: f64 = (rows - 1) as f64 * 0.01;
        assert!(
            stats.travel_ordered < hatch + 300.0,
            "{}",
            stats.travel_ordered
        );
        assert!(stats.travel_ordered < stats.travel_input / 100.0);
        seen.sort_unstable();
        assert_eq!(seen, (0..n).collect::<Vec<_>>());
    }

    #[test]
    fn inner_before_outer_even_when_outer_is_nearer() {
        let outer = square(DVec2::new(50.0, 50.0), 40.0);
        let inner = square(DVec2::new(50.0, 50.0), 5.0);
        let (o, _) = order_paths(&[outer.clone(), inner], DVec2::ZERO, 1e-3);
        assert_eq!(o[0].0, 1);
        assert!(contains(&o[1].1, &o[0].1));
    }

    #[test]
    fn rotation_keeps_the_contour() {
        let sq = square(DVec2::ZERO, 1.0);
        let r = rotate_to_nearest(&sq, DVec2::new(0.3, -5.0), 1e-9);
        assert!((r.start().unwrap() - DVec2::new(0.3, -1.0)).length() < 1e-12);
        assert!((r.length(LENGTH_ACCURACY) - 8.0).abs() < 1e-12);
        assert_eq!(r.max_gap(), 0.0);
    }

    /// More paths than MAX_2OPT_BLOCK: 2-opt over blocks keeps a permutation whose travel
    /// is at most the nearest neighbour's (each move shortens it), with the stats' travel
    /// that of the order returned.
    #[test]
    fn block_2opt_never_lengthens_the_nearest_neighbour_travel() {
        let n = MAX_2OPT_BLOCK + 300;
        // Short rows on a jittered grid, given in a scattered order.
        let paths: Vec<Path> = (0..n)
            .map(|k| {
                let q = (k * 37) % n;
                let (x, y) = ((q % 40) as f64 * 3.0, (q / 40) as f64 * 2.0);
                let dx = ((k * 7919) % 13) as f64 * 0.05;
                Path::polyline(
                    &[DVec2::new(x + dx, y), DVec2::new(x + dx + 1.0, y + 0.3)],
                    false,
                )
            })
            .collect();
        let boxes: Vec<Aabb> = (paths.iter())
            .map(|p| Aabb::from_points(&p.flatten(1e-3)))
            .collect();
        let before = vec![Vec::new(); n];
        let nn = nearest_neighbour(&paths, &before, &boxes, DVec2::ZERO, 1e-3);
        let nn_travel = travel(
            &nn.iter().map(|(_, p)| p.clone()).collect::<Vec<_>>(),
            DVec2::ZERO,
        );
        let (o, stats) = order_paths(&paths, DVec2::ZERO, 1e-3);
        let mut idx: Vec<usize> = o.iter().map(|(i, _)| *i).collect();
        idx.sort_unstable();
        assert_eq!(idx, (0..n).collect::<Vec<_>>());
        assert!(
            stats.travel_ordered <= nn_travel + 1e-9,
            "{} > {nn_travel}",
            stats.travel_ordered
        );
        let o: Vec<Path> = o.into_iter().map(|(_, p)| p).collect();
        assert!((stats.travel_ordered - travel(&o, DVec2::ZERO)).abs() < 1e-9);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// The precedence found through the R-tree is every pair a brute-force test of all
        /// pairs finds (vertices inside by the plain even-odd rule), in increasing order:
        /// squares of random sizes (equal ones too) and open lines.
        #[test]
        fn precedence_is_every_nested_pair(
            items in proptest::collection::vec(
                (0.0f64..60.0, 0.0f64..60.0, prop_oneof![Just(4.0), 0.5f64..30.0], 0u8..4),
                1..40,
            )
        ) {
            let paths: Vec<Path> = items
                .iter()
                .map(|&(x, y, s, kind)| {
                    let c = DVec2::new(x, y);
                    if kind == 0 {
                        Path::polyline(&[c, c + DVec2::new(s * 0.3, s * 0.1)], false)
                    } else {
                        square(c, s)
                    }
                })
                .collect();
            let got = precedence(&paths, 1e-3);
            for (j, pj) in paths.iter().enumerate() {
                let want: Vec<usize> = (0..paths.len())
                    .filter(|&i| i != j && pj.closed && contains(pj, &paths[i]))
                    .collect();
                prop_assert_eq!(&got[j], &want, "path {}", j);
            }
        }

        #[test]
        fn ordering_is_a_permutation_respecting_precedence(
            centers in proptest::collection::vec((0.0f64..200.0, 0.0f64..200.0), 1..25)
        ) {
            // Nested squares at some centres, loose squares elsewhere.
            let mut paths = Vec::new();
            for (k, &(x, y)) in centers.iter().enumerate() {
                paths.push(square(DVec2::new(x, y), 2.0));
                if k % 3 == 0 {
                    paths.push(square(DVec2::new(x, y), 4.0));
                }
            }
            let (o, stats) = order_paths(&paths, DVec2::ZERO, 1e-3);
            let mut idx: Vec<usize> = o.iter().map(|(i, _)| *i).collect();
            idx.sort();
            prop_assert_eq!(idx, (0..paths.len()).collect::<Vec<_>>());
            let o: Vec<Path> = o.into_iter().map(|(_, p)| p).collect();
            let total_in: f64 = paths.iter().map(|p| p.length(LENGTH_ACCURACY)).sum();
            let total_out: f64 = o.iter().map(|p| p.length(LENGTH_ACCURACY)).sum();
            prop_assert!((total_in - total_out).abs() < 1e-6 * total_in);
            for i in 0..o.len() {
                for j in 0..i {
                    prop_assert!(!contains(&o[j], &o[i]) || !o[j].closed, "{j} encloses later {i}");
                }
            }
            prop_assert!((stats.travel_ordered - travel(&o, DVec2::ZERO)).abs() < 1e-9);
        }
    }
}
