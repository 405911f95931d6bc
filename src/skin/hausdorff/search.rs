//! The branch-and-bound searches: point distance (lower bound), matching bound (upper
//! bound) and the directed Hausdorff distance built from both.

use super::{BoundedCurve, HausdorffBounds, HausdorffError, Work, or_inf};
use super::{INITIAL_SPLITS, MAX_NODES, MAX_POINT_NODES, MIN_SPLIT_WIDTH};
use crate::geom::{DVec2, Line};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A foot-point step shorter than this fraction of the parameter interval has converged
/// (it moves the point by about that fraction of the curve).
const FOOT_CONVERGED: f64 = 1e-9;

/// A node: parameter interval with a key for the heap.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    key: f64,
    t0: f64,
    t1: f64,
    p0: DVec2,
    p1: DVec2,
    /// For directed nodes: near-point data at the ends (distance bound and parameter).
    u0: f64,
    u1: f64,
    n0: f64,
    n1: f64,
    /// The second-derivative bounds the key was computed with: M₂ of the bisected curve on
    /// [t0, t1] and, for matching nodes, M₂ of Y between the ends' near points u0, u1.
    m2x: f64,
    m2y: f64,
    /// Whether `m2x` and `m2y` are this node's own bounds. A child of a bisection starts
    /// with its parent's: the supremum over a sub-interval is at most that over the
    /// interval, so its key is a valid bound, only looser. It computes its own (the
    /// searches' largest cost, [`BoundedCurve::d2_bound`]) only when it reaches the top of
    /// the heap, and many children never do before a search ends. The top node is always
    /// refined before it is read, so (the bounds nest, test `second_derivative_bounds_nest`)
    /// the heap's top key is the one an eager computation would have there: every
    /// decision, bisection and returned bound stays the same.
    own: bool,
}

impl Node {
    /// The near-point data of a directed node's ends (upper bounds only).
    fn ends(&self) -> (PointDist, PointDist) {
        let end = |upper, t| PointDist {
            lower: 0.0,
            upper,
            t,
        };
        (end(self.n0, self.u0), end(self.n1, self.u1))
    }
}

impl PartialEq for Node {
    fn eq(&self, o: &Self) -> bool {
        self.key == o.key
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    fn cmp(&self, o: &Self) -> Ordering {
        self.key.total_cmp(&o.key)
    }
}

/// Bounds of d(x, Y) and a parameter of Y where the upper bound is attained.
#[derive(Clone, Copy, Debug)]
pub(super) struct PointDist {
    lower: f64,
    upper: f64,
    t: f64,
}

pub(super) fn initial_grid(c: &dyn BoundedCurve) -> Vec<f64> {
    grid_of(c, INITIAL_SPLITS)
}

/// Parameters splitting each piece of `c` into `n` equal parts (piece ends included once).
pub(super) fn grid_of(c: &dyn BoundedCurve, n: usize) -> Vec<f64> {
    let pieces = c.pieces();
    let mut ts = Vec::with_capacity(pieces.len() * (n + 1));
    for (a, b) in pieces {
        for i in 0..n {
            ts.push(a + (b - a) * i as f64 / n as f64);
        }
        if ts.last() != Some(&b) {
            ts.push(b);
        }
    }
    ts.dedup();
    ts
}

/// The curve Y of one directed distance with its initial grid and the second-derivative
/// bound of each grid window, computed once: every point-distance search of the directed
/// bound (one per sample of X) starts from all windows of the grid.
pub(super) struct Target<'a> {
    c: &'a dyn BoundedCurve,
    /// The initial grid (parameter, point).
    grid: Vec<(f64, DVec2)>,
    /// Per grid window: M₂ of Y on it ([`BoundedCurve::d2_bound`]), or `None` when the
    /// window lies in no single piece.
    windows: Vec<Option<f64>>,
}

impl<'a> Target<'a> {
    fn new(c: &'a dyn BoundedCurve) -> Result<Self, HausdorffError> {
        let grid: Vec<(f64, DVec2)> = initial_grid(c)
            .into_iter()
            .map(|t| c.point(t).map(|p| (t, p)))
            .collect::<Result<_, _>>()?;
        let pieces = c.pieces();
        let windows = grid
            .windows(2)
            .map(|w| {
                let (t0, t1) = (w[0].0, w[1].0);
                let inside = t1 > t0 && pieces.iter().any(|&(a, b)| t0 >= a && t1 <= b);
                inside.then(|| c.d2_bound(t0, t1))
            })
            .collect();
        Ok(Target { c, grid, windows })
    }
}

/// How far a curve on [t0, t1] with M₂ ≥ sup‖y″‖ there may stray from its chord:
/// (t1 − t0)²·M₂/8 (+∞ for no information).
pub(super) fn slack(t0: f64, t1: f64, m2: f64) -> f64 {
    or_inf((t1 - t0).powi(2) * m2 / 8.0)
}

/// d(x, Y) to within `tol` by best-first branch and bound on Y's chords, starting from the
/// windows of Y's initial grid. `heap` is a buffer reused across calls (cleared here).
pub(super) fn point_distance(
    x: DVec2,
    y: &Target,
    hint: Option<f64>,
    tol: f64,
    work: &mut Work,
    heap: &mut BinaryHeap<Node>,
) -> Result<PointDist, HausdorffError> {
    let grid = &y.grid;
    let mut best = PointDist {
        lower: 0.0,
        upper: f64::INFINITY,
        t: grid.first().map(|g| g.0).unwrap_or(0.0),
    };
    let upd = |t: f64, p: DVec2, best: &mut PointDist| {
        let d = x.distance(p);
        if d < best.upper {
            best.upper = d;
            best.t = t;
        }
    };
    if let Some(h) = hint {
        upd(h, y.c.point(h)?, &mut best);
    }
    heap.clear();
    let lb_e = |e: f64, p0: DVec2, p1: DVec2| {
        let l = Line::new(p0, p1).distance(x) - e;
        if l.is_nan() { f64::NEG_INFINITY } else { l }
    };
    // Smallest lower bound of the leaves (nodes too narrow to split).
    let mut leaf_lower = f64::INFINITY;
    for (w, e) in grid.windows(2).zip(&y.windows) {
        let (t0, p0) = w[0];
        let (t1, p1) = w[1];
        upd(t0, p0, &mut best);
        upd(t1, p1, &mut best);
        let Some(m2) = *e else {
            continue;
        };
        let key = lb_e(slack(t0, t1, m2), p0, p1);
        let mut nd = node(-key, t0, t1, p0, p1);
        nd.m2x = m2;
        heap.push(nd);
    }
    let mut count = 0;
    while let Some(mut nd) = heap.pop() {
        if !nd.own {
            // Its own slack; pruned when that puts it past the best distance.
            nd.m2x = y.c.d2_bound(nd.t0, nd.t1);
            nd.own = true;
            let l = lb_e(slack(nd.t0, nd.t1, nd.m2x), nd.p0, nd.p1);
            if l < best.upper - tol {
                nd.key = -l;
                heap.push(nd);
            }
            continue;
        }
        let l = -nd.key;
        if l >= best.upper - tol || count >= MAX_POINT_NODES || !work.take() {
            // Pruned nodes had lower bounds ≥ upper − tol; the heap's minimum is l.
            best.lower = l.min(best.upper - tol).min(leaf_lower).max(0.0);
            return Ok(best);
        }
        count += 1;
        let tm = 0.5 * (nd.t0 + nd.t1);
        if !(nd.t1 - nd.t0 > MIN_SPLIT_WIDTH && tm > nd.t0 && tm < nd.t1) {
            leaf_lower = leaf_lower.min(l);
            continue;
        }
        let pm = y.c.point(tm)?;
        upd(tm, pm, &mut best);
        for (a, pa, b, pb) in [(nd.t0, nd.p0, tm, pm), (tm, pm, nd.t1, nd.p1)] {
            let key = lb_e(slack(a, b, nd.m2x), pa, pb);
            if key < best.upper - tol {
                let mut child = node(-key, a, b, pa, pb);
                (child.m2x, child.own) = (nd.m2x, false);
                heap.push(child);
            }
        }
    }
    best.lower = (best.upper - tol).min(leaf_lower).max(0.0);
    Ok(best)
}

pub(super) fn node(key: f64, t0: f64, t1: f64, p0: DVec2, p1: DVec2) -> Node {
    Node {
        key,
        t0,
        t1,
        p0,
        p1,
        u0: 0.0,
        u1: 0.0,
        n0: 0.0,
        n1: 0.0,
        m2x: f64::INFINITY,
        m2y: f64::INFINITY,
        own: true,
    }
}

/// Upper bound of sup d(x(s), Y) over s ∈ [s0, s1] (inside one piece of X) from points
/// y(a.t), y(b.t) at distances ≤ a.upper, b.upper of the ends (any points of Y will do),
/// with M₂ˣ = `m2x` ≥ sup‖x″‖ on [s0, s1] and M₂ʸ = `m2y` ≥ sup‖y″‖ between a.t and b.t.
pub(super) fn match_bound(
    (s0, p0, a): (f64, DVec2, &PointDist),
    (s1, p1, b): (f64, DVec2, &PointDist),
    m2x: f64,
    m2y: f64,
) -> f64 {
    let ex = (s1 - s0).powi(2) * m2x / 8.0;
    let ey = (b.t - a.t).powi(2) * m2y / 8.0;
    let linear = or_inf(a.upper.max(b.upper) + or_inf(ex) + or_inf(ey));
    // Constant matching: ‖x(s) − y(t_i)‖ is convex along the chord of x, so at most
    // its larger end value, and ‖x(s1) − y(t0)‖ ≤ ‖x(s0) − y(t0)‖ + ‖x(s1) − x(s0)‖.
    let c = or_inf(a.upper.min(b.upper) + p1.distance(p0) + or_inf(ex));
    linear.min(c)
}

/// A node of X on [s0, s1] keyed by [`match_bound`] with M₂ˣ = `m2x`, M₂ʸ = `m2y`, with its
/// ends' near-point data.
pub(super) fn match_node_with(
    (s0, p0, a): (f64, DVec2, &PointDist),
    (s1, p1, b): (f64, DVec2, &PointDist),
    m2x: f64,
    m2y: f64,
) -> Node {
    let mut nd = node(
        match_bound((s0, p0, a), (s1, p1, b), m2x, m2y),
        s0,
        s1,
        p0,
        p1,
    );
    (nd.u0, nd.u1, nd.n0, nd.n1) = (a.t, b.t, a.upper, b.upper);
    (nd.m2x, nd.m2y) = (m2x, m2y);
    nd
}

/// A node of X on [s0, s1] keyed by [`match_bound`] with its own second-derivative bounds.
pub(super) fn match_node(
    xc: &dyn BoundedCurve,
    yc: &dyn BoundedCurve,
    (s0, p0, a): (f64, DVec2, &PointDist),
    (s1, p1, b): (f64, DVec2, &PointDist),
) -> Node {
    let (m2x, m2y) = (xc.d2_bound(s0, s1), yc.d2_bound_any(a.t, b.t));
    match_node_with((s0, p0, a), (s1, p1, b), m2x, m2y)
}

/// Matching node `nd` again with its own second-derivative bounds ([`Node::own`]).
pub(super) fn match_refined(xc: &dyn BoundedCurve, yc: &dyn BoundedCurve, nd: &Node) -> Node {
    let (d0, d1) = nd.ends();
    match_node(xc, yc, (nd.t0, nd.p0, &d0), (nd.t1, nd.p1, &d1))
}

/// The halves of matching node `nd` split at s (point p, near point d), keyed with `nd`'s
/// M₂ˣ and, when d.t lies between the ends' near points, its M₂ʸ (else the halves' own
/// M₂ʸ, since their Y intervals leave `nd`'s).
pub(super) fn match_children(
    yc: &dyn BoundedCurve,
    nd: &Node,
    (s, p, d): (f64, DVec2, &PointDist),
) -> [Node; 2] {
    let (d0, d1) = nd.ends();
    let inside = d.t >= nd.u0.min(nd.u1) && d.t <= nd.u0.max(nd.u1);
    let m2y = |a: f64, b: f64| {
        if inside {
            nd.m2y
        } else {
            yc.d2_bound_any(a, b)
        }
    };
    let mut halves = [
        match_node_with((nd.t0, nd.p0, &d0), (s, p, d), nd.m2x, m2y(nd.u0, d.t)),
        match_node_with((s, p, d), (nd.t1, nd.p1, &d1), nd.m2x, m2y(d.t, nd.u1)),
    ];
    for h in &mut halves {
        h.own = false;
    }
    halves
}

/// Cap on the refinement steps (bisections of X and point-distance searches) of one
/// [`match_search`]; beyond it the caller falls back to [`directed`].
pub(super) const MATCH_STEPS: usize = 48;

/// Initial pieces per curve piece of a [`match_search`]: fewer than the full search's
/// [`INITIAL_SPLITS`], since a sample costs only a foot-point search and the search
/// bisects where the bound is too large (4: a quarter less time on the examples than 8,
/// with the same decisions and report flags; 2 changes a report flag).
pub(super) const MATCH_SPLITS: usize = 4;

/// Gauss–Newton steps of [`foot_point`].
pub(super) const FOOT_STEPS: usize = 3;

/// A point of Y near x by a few Gauss–Newton steps t ← t + (x − y)·y′/‖y′‖² from `t`,
/// kept inside Y's parameter range `(lo, hi)`: `upper` is its distance (an upper bound of
/// d(x, Y)), `lower` is 0. `None` where Y cannot be evaluated.
pub(super) fn foot_point(
    x: DVec2,
    yc: &dyn BoundedCurve,
    (lo, hi): (f64, f64),
    t: f64,
) -> Option<PointDist> {
    let mut t = t.clamp(lo, hi);
    let mut best = PointDist {
        lower: 0.0,
        upper: f64::INFINITY,
        t,
    };
    for _ in 0..FOOT_STEPS {
        let (p, d) = yc.point_tangent(t).ok()?;
        let dist = x.distance(p);
        if dist < best.upper {
            best.upper = dist;
            best.t = t;
        }
        let dd = d.length_squared();
        let next = (t + (x - p).dot(d) / dd).clamp(lo, hi);
        if !(dd > 0.0 && next.is_finite()) || (next - t).abs() <= FOOT_CONVERGED * (hi - lo) {
            return Some(best);
        }
        t = next;
    }
    let dist = x.distance(yc.point(t).ok()?);
    if dist < best.upper {
        best.upper = dist;
        best.t = t;
    }
    Some(best)
}

/// What a [`match_search`] is to show about h(X → Y).
pub(super) enum Goal {
    /// h(X → Y) ≤ this value (an upper bound alone).
    Below(f64),
    /// h(X → Y) > this value, shown by a point-distance search on `y` at the sample whose
    /// near point is farthest (one try; the upper bound is the matching bound of the
    /// samples).
    Above(f64),
    /// Bounds with upper − lower ≤ `gap`; lower bounds from point-distance searches on `y`
    /// to within `ptol`.
    Gap { gap: f64, ptol: f64 },
}

/// The start of every [`match_search`] of X against Y: the samples of X on its grid with
/// their near points on Y, and the nodes between them. The searches of one pair of curves
/// (for several goals) share it instead of sampling again.
pub(super) struct MatchSeed {
    /// Y's parameter range.
    yd: (f64, f64),
    /// Samples of X: point, near-point data, whether its distance was certified.
    samples: Vec<(DVec2, PointDist, bool)>,
    heap: BinaryHeap<Node>,
}

impl MatchSeed {
    /// `None` when a curve has no piece or Y cannot be evaluated near a sample.
    pub(super) fn new(xc: &dyn BoundedCurve, yc: &dyn BoundedCurve) -> Option<MatchSeed> {
        let (xp, yp) = (xc.pieces(), yc.pieces());
        let xd = (xp.first()?.0, xp.last()?.1);
        let yd = (yp.first()?.0, yp.last()?.1);
        if xd.1.partial_cmp(&xd.0) != Some(Ordering::Greater) {
            return None;
        }
        // X and Y run over corresponding parameter ranges: a sample's search starts at the
        // proportional parameter of Y, a bisection's between its ends' near points.
        let map = |s: f64| yd.0 + (s - xd.0) / (xd.1 - xd.0) * (yd.1 - yd.0);
        let grid = grid_of(xc, MATCH_SPLITS);
        let mut samples = Vec::with_capacity(grid.len());
        let mut heap = BinaryHeap::with_capacity(grid.len());
        let mut prev: Option<(f64, DVec2, PointDist)> = None;
        for s in grid {
            let p = xc.point(s).ok()?;
            let d = foot_point(p, yc, yd, map(s))?;
            if let Some((s0, p0, d0)) = prev
                && s > s0
                && xp.iter().any(|&(a, b)| s0 >= a && s <= b)
            {
                heap.push(match_node(xc, yc, (s0, p0, &d0), (s, p, &d)));
            }
            samples.push((p, d, false));
            prev = Some((s, p, d));
        }
        Some(MatchSeed { yd, samples, heap })
    }
}

/// h(X → Y) by the matching bound ([`match_bound`]): samples of X with near points of Y
/// from [`foot_point`] (upper bounds of d(x, Y) only), the piece of X with the largest
/// bound bisected first, and for [`Goal::Gap`] a certified point-distance search only at
/// the sample whose near point is farthest, when that can close the gap. [`directed`] runs
/// one such search at every sample, most of its work. `None` when the goal is not reached
/// within [`MATCH_STEPS`] or Y cannot be evaluated where looked: the caller then runs
/// [`directed`].
pub(super) fn match_search(
    xc: &dyn BoundedCurve,
    yc: &dyn BoundedCurve,
    seed: &MatchSeed,
    goal: &Goal,
    work: &mut Work,
) -> Option<HausdorffBounds> {
    let yd = seed.yd;
    let mut pheap: BinaryHeap<Node> = BinaryHeap::new();
    if let Goal::Above(bound) = *goal {
        let (p, d, _) = seed
            .samples
            .iter()
            .max_by(|a, b| a.1.upper.total_cmp(&b.1.upper))?;
        if d.upper.partial_cmp(&bound) != Some(Ordering::Greater) || !work.take() {
            return None;
        }
        // Searched only until its lower bound passes the bound (or cannot).
        let tol = 0.5 * (d.upper - bound);
        let y = Target::new(yc).ok()?;
        let d = point_distance(*p, &y, Some(d.t), tol, work, &mut pheap).ok()?;
        let upper = seed.heap.peek()?.key;
        return (d.lower > bound).then_some(HausdorffBounds {
            lower: d.lower,
            upper: upper.max(d.lower),
        });
    }
    let mut heap = seed.heap.clone();
    // Only the gap's point-distance searches read the samples.
    let mut samples = matches!(goal, Goal::Gap { .. }).then(|| seed.samples.clone());
    let mut lower: f64 = 0.0;
    // Y's grid for point-distance searches, made on first use.
    let mut target: Option<Target> = None;
    let mut steps = 0;
    while let Some(nd) = heap.pop() {
        if !nd.own {
            heap.push(match_refined(xc, yc, &nd));
            continue;
        }
        let upper = nd.key;
        match *goal {
            Goal::Below(bound) => {
                if upper <= bound {
                    return Some(HausdorffBounds { lower, upper });
                }
                // A near point farther than the bound: give the proof up early.
                if nd.n0.max(nd.n1) > bound {
                    return None;
                }
            }
            Goal::Above(_) => return None,
            Goal::Gap { gap, .. } => {
                if upper <= lower + gap {
                    return Some(HausdorffBounds {
                        lower,
                        upper: upper.max(lower),
                    });
                }
            }
        }
        if steps >= MATCH_STEPS || !work.take() {
            return None;
        }
        steps += 1;
        if let Goal::Gap { gap, ptol } = *goal {
            let far = samples
                .iter_mut()
                .flatten()
                .filter(|s| !s.2)
                .max_by(|a, b| a.1.upper.total_cmp(&b.1.upper));
            if let Some(f) = far
                && f.1.upper > lower
                && upper - f.1.upper <= gap
            {
                if target.is_none() {
                    target = Some(Target::new(yc).ok()?);
                }
                let y = target.as_ref()?;
                let d = point_distance(f.0, y, Some(f.1.t), ptol, work, &mut pheap).ok()?;
                lower = lower.max(d.lower);
                f.2 = true;
                heap.push(nd);
                continue;
            }
        }
        let sm = 0.5 * (nd.t0 + nd.t1);
        if !(nd.t1 - nd.t0 > MIN_SPLIT_WIDTH && sm > nd.t0 && sm < nd.t1) {
            return None;
        }
        let pm = xc.point(sm).ok()?;
        let dm = foot_point(pm, yc, yd, 0.5 * (nd.u0 + nd.u1))?;
        if let Some(s) = samples.as_mut() {
            s.push((pm, dm, false));
        }
        heap.extend(match_children(yc, &nd, (sm, pm, &dm)));
    }
    None
}

/// The directed Hausdorff distance h(X → Y) = sup_x d(x, Y), bounded to `gap`; stops early
/// once the answer relative to `threshold` is decided (lower > threshold or upper ≤ it).
pub(super) fn directed(
    xc: &dyn BoundedCurve,
    yc: &dyn BoundedCurve,
    gap: f64,
    threshold: Option<f64>,
    work: &mut Work,
) -> Result<HausdorffBounds, HausdorffError> {
    let ptol = 0.25 * gap;
    if threshold.is_none()
        && let Some(seed) = MatchSeed::new(xc, yc)
        && let Some(h) = match_search(xc, yc, &seed, &Goal::Gap { gap, ptol }, work)
    {
        return Ok(h);
    }
    let y = Target::new(yc)?;
    let mut pheap: BinaryHeap<Node> = BinaryHeap::new();
    let mut lower: f64 = 0.0;
    let mut heap: BinaryHeap<Node> = BinaryHeap::new();
    let xs = initial_grid(xc);
    let mut ends: Vec<(f64, DVec2, PointDist)> = Vec::with_capacity(xs.len());
    let mut hint = None;
    for &s in &xs {
        let p = xc.point(s)?;
        let d = point_distance(p, &y, hint, ptol, work, &mut pheap)?;
        hint = Some(d.t);
        lower = lower.max(d.lower);
        ends.push((s, p, d));
    }
    let xpieces = xc.pieces();
    // Largest upper bound of the leaves (nodes too narrow to split).
    let mut leaf_upper: f64 = 0.0;
    for w in ends.windows(2) {
        let ((s0, p0, d0), (s1, p1, d1)) = (w[0], w[1]);
        if s1 <= s0 || !xpieces.iter().any(|&(a, b)| s0 >= a && s1 <= b) {
            continue;
        }
        heap.push(match_node(xc, yc, (s0, p0, &d0), (s1, p1, &d1)));
    }
    let mut count = 0;
    while let Some(nd) = heap.pop() {
        if !nd.own {
            heap.push(match_refined(xc, yc, &nd));
            continue;
        }
        let upper = nd.key.max(leaf_upper);
        let decided = threshold.is_some_and(|e| lower > e || upper <= e);
        if upper <= lower + gap || decided || count >= MAX_NODES || !work.take() {
            return Ok(HausdorffBounds {
                lower,
                upper: upper.max(lower),
            });
        }
        count += 1;
        let sm = 0.5 * (nd.t0 + nd.t1);
        if !(nd.t1 - nd.t0 > MIN_SPLIT_WIDTH && sm > nd.t0 && sm < nd.t1) {
            leaf_upper = leaf_upper.max(nd.key);
            continue;
        }
        let pm = xc.point(sm)?;
        let hint = Some(0.5 * (nd.u0 + nd.u1));
        let dm = point_distance(pm, &y, hint, ptol, work, &mut pheap)?;
        lower = lower.max(dm.lower);
        heap.extend(match_children(yc, &nd, (sm, pm, &dm)));
    }
    Ok(HausdorffBounds {
        lower,
        upper: leaf_upper.max(lower),
    })
}
