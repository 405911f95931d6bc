//! Fitting a stroke to a subpath: runs between corners, each interpolated by a disk
//! B-spline through evenly spaced samples until it stays within the tolerance.

use super::*;
use crate::par::prelude::*;

/// Points of a subpath closer than `tol · MERGE_FRACTION` to the point kept before them are
/// merged into it (repeated points, zero-length segments, digitiser noise): the cleaned line
/// stays within that distance of the drawn one.
pub(super) const MERGE_FRACTION: f64 = 0.1;

/// A corner whose point lies within `tol · JITTER_FRACTION` of the chord between the
/// points [`JITTER_REACH`]·tol before and after it along the path is pen jitter, not a
/// corner: the turn is invisible at the tolerance's scale. A true corner turning by θ with
/// legs that long lies JITTER_REACH·tol·sin(θ/2) from that chord: over half the tolerance
/// for every θ above 14.4°.
pub(super) const JITTER_FRACTION: f64 = 0.5;

/// A run's fit is done once it strays at most `FIT_TARGET`·tol from the run (a margin
/// below the tolerance the import promises).
const FIT_TARGET: f64 = 0.9;

/// How far along the path (in tolerances) the jitter test looks on each side of a corner.
pub(super) const JITTER_REACH: f64 = 4.0;

/// A turn sharper than this inside a drawn segment, measured over chords of
/// [`JITTER_REACH`]·tol on each side of a flattened point, is a corner that the path's nodes
/// do not show (the cusp of a cubic, the hairpins of a hatch drawn as one curve): a curve
/// turning that much within 2·JITTER_REACH·tol has a radius of curvature of about the
/// tolerance's scale, and no spline through evenly spaced samples follows it.
pub(super) const CUSP_ANGLE_DEG: f64 = 90.0;

/// The point reached walking from `i` along `pts` by `step` (±1) until `len` of arc length
/// is covered (wrapping when `closed`; an open path's end when it comes first); `None` when
/// a closed path is shorter than `len`.
fn walk(pts: &[DVec2], closed: bool, i: usize, step: isize, len: f64) -> Option<usize> {
    let m = pts.len();
    let mut j = i;
    let mut walked = 0.0;
    for _ in 0..m {
        let next = j as isize + step;
        let next = if closed {
            next.rem_euclid(m as isize - 1) as usize
        } else if next < 0 || next >= m as isize {
            return Some(j);
        } else {
            next as usize
        };
        walked += pts[j].distance(pts[next]);
        j = next;
        if walked >= len {
            return Some(j);
        }
    }
    None
}

/// Mark the cusps of a cleaned subpath as nodes ([`CUSP_ANGLE_DEG`]), for a subpath whose
/// fit strays beyond the tolerance without them (whether any was marked is returned): every flattened point
/// whose turn over the chords [`JITTER_REACH`]·tol long on each side exceeds the angle,
/// sharpest first, keeping those farther than JITTER_REACH·tol along the path from a node or
/// cusp already turning that much (one corner per bend). The node's angle is that turn, so
/// the corner angle of the import decides as for the path's own nodes.
pub(super) fn mark_cusps(sp: &mut Subpath, tol: f64) -> bool {
    let m = sp.pts.len();
    if m < 3 {
        return false;
    }
    let (pts, closed) = (&sp.pts, sp.closed);
    let len = JITTER_REACH * tol;
    let limit = CUSP_ANGLE_DEG.to_radians();
    let mut arc = Vec::with_capacity(m);
    arc.push(0.0);
    for w in pts.windows(2) {
        arc.push(arc.last().copied().unwrap_or(0.0) + w[0].distance(w[1]));
    }
    let total = arc[m - 1];
    let apart = |i: usize, k: usize| {
        let d = (arc[i] - arc[k]).abs();
        if closed { d.min(total - d) } else { d }
    };
    let last = if closed { m - 1 } else { m };
    let mut cands: Vec<(usize, f64)> = (0..last)
        .filter_map(|i| {
            let a = walk(pts, closed, i, -1, len)?;
            let b = walk(pts, closed, i, 1, len)?;
            if a == i || b == i {
                return None;
            }
            let t = turn(pts[i] - pts[a], pts[b] - pts[i]);
            (t > limit).then_some((i, t))
        })
        .collect();
    if cands.is_empty() {
        return false;
    }
    cands.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut taken: std::collections::BTreeSet<usize> = sp
        .nodes
        .iter()
        .filter(|n| n.1 > limit)
        .map(|n| n.0)
        .collect();
    let mut added = Vec::new();
    for (i, t) in cands {
        let before = taken.range(..=i).next_back().or(taken.last());
        let after = taken.range(i..).next().or(taken.first());
        if [before, after]
            .into_iter()
            .flatten()
            .all(|&k| apart(i, k) > len)
        {
            taken.insert(i);
            added.push((i, t));
        }
    }
    let any = !added.is_empty();
    for (i, t) in added {
        match sp.nodes.binary_search_by(|n| n.0.cmp(&i)) {
            Ok(k) => sp.nodes[k].1 = sp.nodes[k].1.max(t),
            Err(k) => sp.nodes.insert(k, (i, t)),
        }
    }
    any
}

/// Clean a subpath within the tolerance `tol` before fitting: merge points closer than
/// [`MERGE_FRACTION`]·tol to the one before (keeping the last point), close an open subpath
/// whose ends are within `tol` (a path drawn back to its start, as pens and exporters leave
/// it, is a closed stroke), demote corners that are pen jitter ([`JITTER_FRACTION`]):
/// the distance of the corner from the chord through the points [`JITTER_REACH`]·tol
/// before and after it along the path).
pub(super) fn clean(sp: &mut Subpath, tol: f64) {
    let merge = MERGE_FRACTION * tol;
    let n = sp.pts.len();
    let mut keep: Vec<usize> = Vec::with_capacity(n);
    for i in 0..n {
        match keep.last() {
            Some(&k) if sp.pts[i].distance(sp.pts[k]) <= merge => {
                if i + 1 == n && keep.len() > 1 {
                    // Keep the end point; drop the near point before it.
                    keep.pop();
                    keep.push(i);
                }
            }
            _ => keep.push(i),
        }
    }
    if keep.len() < n {
        // New index of every old point: the kept point it merged into.
        let mut new_of = vec![0usize; n];
        let mut k = 0;
        for (i, slot) in new_of.iter_mut().enumerate() {
            while k + 1 < keep.len() && keep[k + 1] <= i {
                k += 1;
            }
            *slot = k;
        }
        let mut nodes: Vec<(usize, f64)> = Vec::with_capacity(sp.nodes.len());
        for &(i, a) in &sp.nodes {
            let j = new_of[i.min(n - 1)];
            match nodes.last_mut() {
                Some(last) if last.0 == j => last.1 = last.1.max(a),
                _ => nodes.push((j, a)),
            }
        }
        sp.nodes = nodes;
        if sp.times.len() == n {
            sp.times = keep.iter().map(|&i| sp.times[i]).collect();
        }
        sp.pts = keep.iter().map(|&i| sp.pts[i]).collect();
    }
    let m = sp.pts.len();
    if !sp.closed && m >= 4 && sp.pts[0].distance(sp.pts[m - 1]) <= tol {
        // Drawn back to its start: closed, the last point made the first exactly.
        let first = sp.pts[1] - sp.pts[0];
        let last = sp.pts[m - 1] - sp.pts[m - 2];
        sp.pts[m - 1] = sp.pts[0];
        sp.closed = true;
        if let Some(n0) = sp.nodes.first_mut() {
            n0.1 = turn(last, first);
        }
    }
    // Pen jitter: corners without a visible turn at the tolerance's scale.
    let m = sp.pts.len();
    if m < 3 {
        return;
    }
    let pts = &sp.pts;
    let closed = sp.closed;
    let reach = |i: usize, step: isize| walk(pts, closed, i, step, JITTER_REACH * tol);
    for node in sp.nodes.iter_mut() {
        if node.1 == 0.0 {
            continue;
        }
        let (Some(a), Some(b)) = (reach(node.0, -1), reach(node.0, 1)) else {
            continue;
        };
        if a == node.0 || b == node.0 {
            continue;
        }
        let chord = crate::geom::Line::new(pts[a], pts[b]);
        let d = chord
            .eval(chord.nearest_t(pts[node.0]))
            .distance(pts[node.0]);
        if d < JITTER_FRACTION * tol {
            node.1 = 0.0;
        }
    }
}

impl Ctx<'_> {
    /// Radius at every point of a subpath: half the stroke width, or the widths spread
    /// evenly along its length.
    pub(super) fn radii(
        &self,
        pts: &[DVec2],
        width_mm: f64,
        widths: Option<&[f64]>,
        scale: f64,
    ) -> Vec<f64> {
        let Some(w) = widths else {
            return vec![0.5 * width_mm; pts.len()];
        };
        let mut s = vec![0.0];
        for q in pts.windows(2) {
            s.push(s.last().copied().unwrap_or(0.0) + q[0].distance(q[1]));
        }
        let total = s.last().copied().unwrap_or(0.0).max(f64::MIN_POSITIVE);
        let k = (w.len() - 1) as f64;
        s.iter()
            .map(|&si| {
                let u = (si / total * k).clamp(0.0, k);
                let i = (u.floor() as usize).min(w.len() - 2);
                let f = u - i as f64;
                0.5 * ((1.0 - f) * w[i] + f * w[i + 1]) * scale * MM_PER_PX
            })
            .collect()
    }

    /// The stroke of one subpath: runs between corners, each interpolated through enough
    /// evenly spaced points to stay within the tolerance; the reason it is skipped when a
    /// run has zero length or no interpolant through its samples builds.
    pub(super) fn fit_subpath(
        &mut self,
        name: &str,
        sp: &Subpath,
        radii: &[f64],
    ) -> Result<(Stroke, f64), &'static str> {
        let limit = self.opts.corner_angle.to_radians();
        let mut cuts: Vec<usize> = sp
            .nodes
            .iter()
            .filter(|&&(i, a)| a > limit && (sp.closed || (i > 0 && i + 1 < sp.pts.len())))
            .map(|&(i, _)| i)
            .collect();
        cuts.sort_unstable();
        cuts.dedup();
        let n = sp.pts.len();
        let mut pts = sp.pts.clone();
        let mut rs = radii.to_vec();
        if sp.closed {
            // The last point repeats the first.
            pts.pop();
            rs.pop();
            cuts.retain(|&c| c < n - 1);
            if cuts.len() == 1 {
                // One corner on a closed path: also cut half-way round, so no piece starts
                // and ends at the same point.
                let m = pts.len();
                let c = (cuts[0] + m / 2) % m;
                cuts.push(c);
                cuts.sort_unstable();
            }
        }
        let m = pts.len();
        if m < 2 {
            return Err(ZERO_LENGTH);
        }
        // Runs as inclusive index ranges (wrapping for closed paths).
        let runs: Vec<Vec<usize>> = if cuts.is_empty() {
            vec![(0..m).collect()]
        } else if sp.closed {
            (0..cuts.len())
                .map(|k| {
                    let (a, b) = (cuts[k], cuts[(k + 1) % cuts.len()]);
                    let len = if b > a { b - a } else { m - a + b };
                    (0..=len).map(|j| (a + j) % m).collect()
                })
                .collect()
        } else {
            let mut b = vec![0];
            b.extend(&cuts);
            b.push(m - 1);
            b.windows(2).map(|w| (w[0]..=w[1]).collect()).collect()
        };
        let whole_closed = sp.closed && cuts.is_empty();
        let mut points: Vec<[f64; 3]> = Vec::new();
        let mut worst = 0.0f64;
        let mut corners = Vec::new();
        // The runs are fitted independently (in parallel), then joined in order; the
        // first run that fails in that order decides the error.
        let (file, tol) = (self.file, self.opts.tolerance);
        let fits: Vec<RunFit> = runs
            .par_iter()
            .map(|run| {
                let rp: Vec<DVec2> = run.iter().map(|&i| pts[i]).collect();
                let rr: Vec<f64> = run.iter().map(|&i| rs[i]).collect();
                fit_run(file, tol, name, &rp, &rr, whole_closed)
            })
            .collect();
        for (k, fit) in fits.into_iter().enumerate() {
            let (fit, dev) = fit?;
            worst = worst.max(dev);
            if k > 0 {
                corners.push(points.len() - 1);
                points.extend_from_slice(&fit[1..]);
            } else {
                points.extend_from_slice(&fit);
            }
        }
        let mut s = Stroke::from_disks(name, Vec::new());
        s.disks = None;
        if sp.closed && !cuts.is_empty() {
            points.pop(); // back at the first corner
            corners.insert(0, 0);
            s.closed = true;
        } else if whole_closed {
            s.closed = true;
        }
        s.degree = 3.min(points.len() - 1).max(1);
        s.points = Some(points);
        s.corners = if corners.is_empty() {
            None
        } else {
            Some(corners)
        };
        // Each run built on its own; the stroke interpolates all of them in one system.
        s.to_dbsc(self.file, 0).map_err(|_| NO_INTERPOLANT)?;
        Ok((s, worst))
    }
}

/// A run's samples [x, y, r] and how far their stroke strays, or why none builds.
type RunFit = Result<(Vec<[f64; 3]>, f64), &'static str>;

/// Points [x, y, r] whose interpolant stays within the tolerance of the run `pts`
/// (both ways), or the closest that builds, and the distance reached.
pub(super) fn fit_run(
    file: &str,
    tolerance: f64,
    name: &str,
    pts: &[DVec2],
    radii: &[f64],
    closed: bool,
) -> RunFit {
    let mut s = vec![0.0];
    for q in pts.windows(2) {
        s.push(s.last().copied().unwrap_or(0.0) + q[0].distance(q[1]));
    }
    if closed {
        s.push(s.last().copied().unwrap_or(0.0) + pts[pts.len() - 1].distance(pts[0]));
    }
    let total = s.last().copied().unwrap_or(0.0);
    if total <= 0.0 {
        return Err(ZERO_LENGTH);
    }
    let mut ring: Vec<DVec2> = pts.to_vec();
    let mut ring_r = radii.to_vec();
    if closed {
        ring.push(pts[0]);
        ring_r.push(radii[0]);
    }
    let at = |u: f64| -> [f64; 3] {
        let i = s.partition_point(|&v| v <= u).clamp(1, s.len() - 1);
        let (a, b) = (s[i - 1], s[i]);
        let f = if b > a { (u - a) / (b - a) } else { 0.0 };
        let p = ring[i - 1].lerp(ring[i], f);
        let r = ring_r[i - 1] + f * (ring_r[i] - ring_r[i - 1]);
        // usvg keeps f32 coordinates: digits past 1e-6 mm are noise.
        [p.x, p.y, r].map(|v| (v * ROUND).round() / ROUND)
    };
    let run = Polyline::new(&ring);
    let target = FIT_TARGET * tolerance;
    let sample = |count: usize| -> Vec<[f64; 3]> {
        if closed {
            (0..count)
                .map(|j| at(total * j as f64 / count as f64))
                .collect()
        } else {
            (0..count)
                .map(|j| at(total * j as f64 / (count - 1) as f64))
                .collect()
        }
    };
    let mut count = if closed { 8 } else { 2 };
    let mut tried = Vec::new();
    loop {
        let samples = sample(count);
        // The last try is measured in full; the others only until they are known to
        // miss the target.
        let last = count >= MAX_RUN_POINTS;
        let bound = if last { f64::INFINITY } else { target };
        let dev = deviation(file, name, &samples, &run, &ring_r, closed, bound);
        // A fit that does not build (a singular interpolation system) is never kept.
        // Every earlier try missed the target, so one that meets it is the best.
        if dev.is_finite() && dev <= target {
            return Ok((samples, dev));
        }
        tried.push(count);
        if last {
            break;
        }
        count = if count == 2 { 4 } else { 2 * count - 1 };
    }
    // None met the target: the closest that builds, each try measured in full.
    let mut best: Option<(Vec<[f64; 3]>, f64)> = None;
    for count in tried {
        let samples = sample(count);
        let dev = deviation(file, name, &samples, &run, &ring_r, closed, f64::INFINITY);
        if dev.is_finite() && best.as_ref().is_none_or(|b| dev < b.1) {
            best = Some((samples, dev));
        }
    }
    best.ok_or(NO_INTERPOLANT)
}

/// How far the stroke through `samples` strays from the run (the polyline `run` with
/// radii `ring_r`; infinite when no stroke interpolates the samples): the largest distance from its spine to the run and from the run to its
/// spine, plus the largest radius error at the run's points (the radius at the spine
/// sample nearest each point against the point's radius). The sum bounds how far the
/// stroke's disks stray from the drawn ones. The measure stops as soon as it exceeds
/// `bound` (then the value returned is above `bound` but may be below the whole
/// measure); at or below `bound` it is exact.
pub(super) fn deviation(
    file: &str,
    name: &str,
    samples: &[[f64; 3]],
    run: &Polyline,
    ring_r: &[f64],
    closed: bool,
    bound: f64,
) -> f64 {
    let ring = run.pts;
    let mut st = Stroke::from_disks(name, Vec::new());
    st.disks = None;
    st.closed = closed;
    st.degree = 3.min(samples.len() - 1).max(1);
    st.points = Some(samples.to_vec());
    let Ok(c) = st.to_dbsc(file, 0) else {
        return f64::INFINITY;
    };
    let (lo, hi) = c.domain();
    let n = (samples.len() * 16).max(64);
    // A run of one width: the radius error is |r(t) − r| over the spine samples (those
    // nearest the run's points are among them), found without a nearest-point search.
    let uniform = ring_r.iter().all(|&r| r == ring_r[0]);
    let mut radius_error = 0.0f64;
    // From every spine sample (evaluated as the measure goes, so a try that misses stops
    // early): its distance to the run, and its radius against the run's radius at the
    // nearest point of the run.
    let mut disks: Vec<crate::geom::Circle> = Vec::with_capacity(n + 1);
    let mut a = 0.0f64;
    let mut hint = None;
    for k in 0..=n {
        let d = c.circle_at(lo + (hi - lo) * k as f64 / n as f64);
        disks.push(d);
        if uniform {
            radius_error = radius_error.max((d.r - ring_r[0]).abs());
        }
        // The nearest item is at most `near` away: when that cannot raise the maximum,
        // no search is needed.
        let skip = uniform
            && hint.is_some_and(|h| {
                let (near, j) = run.near_hint(d.c, h);
                hint = Some(j);
                near <= a
            });
        if !skip {
            let (dist, i, f) = run.nearest_from(d.c, hint);
            hint = Some(i);
            a = a.max(dist);
            if !uniform {
                let r = match ring_r.get(i + 1) {
                    Some(&r1) => ring_r[i] + f * (r1 - ring_r[i]),
                    None => ring_r[0],
                };
                radius_error = radius_error.max((d.r - r).abs());
            }
        }
        if a + radius_error > bound {
            return a + radius_error;
        }
    }
    let spine: Vec<DVec2> = disks.iter().map(|d| d.c).collect();
    // From every point of the run: its distance to the spine, and its radius against
    // the radius at the nearest spine sample.
    let curve = Polyline::new(&spine);
    let mut b = 0.0f64;
    let mut hint = None;
    for &q in ring {
        if let Some((near, j)) = hint.map(|h| curve.near_hint(q, h))
            && near <= a.max(b)
        {
            hint = Some(j);
            continue;
        }
        let (dist, i, _) = curve.nearest_from(q, hint);
        hint = Some(i);
        b = b.max(dist);
        if a.max(b) + radius_error > bound {
            return a.max(b) + radius_error;
        }
    }
    if !uniform {
        let samples = Polyline::points(&spine);
        let mut hint = None;
        for (&q, &r) in ring.iter().zip(ring_r) {
            let (_, j, _) = samples.nearest_from(q, hint);
            hint = Some(j);
            radius_error = radius_error.max((disks[j].r - r).abs());
        }
    }
    a.max(b) + radius_error
}

/// Items per leaf block of [`Polyline`]'s hierarchy.
const CHAIN_LEAF: usize = 8;

/// An axis-aligned box (min, max corners).
type Bounds = (DVec2, DVec2);

/// A polyline (or a chain of points) with a bounding-volume hierarchy in sequence order:
/// boxes of blocks of [`CHAIN_LEAF`] consecutive items, then of pairs of blocks, up to one
/// root, built in O(n) without sorting (consecutive items of a drawn line or a sampled
/// spine are close, so the boxes stay tight; see `geom::intersect::SeqBvh`). The nearest
/// item to a query is found by branch and bound on the box distances, started from a hint
/// (the item nearest the previous query of a coherent sequence), so a query costs
/// O(log n) box tests.
pub(super) struct Polyline<'a> {
    pts: &'a [DVec2],
    /// Whether the items are the segments `pts[i]..pts[i + 1]` (else the points).
    segments: bool,
    /// `levels[0]` bounds leaf blocks; node j of level k + 1 bounds nodes 2j, 2j + 1 of k.
    levels: Vec<Vec<Bounds>>,
}

/// Distance from `p` to the box `b` (0 inside).
fn box_distance(b: &Bounds, p: DVec2) -> f64 {
    let d = (b.0 - p).max(p - b.1).max(DVec2::ZERO);
    d.length()
}

impl<'a> Polyline<'a> {
    /// The polyline through `pts` (its items are the segments).
    pub(super) fn new(pts: &'a [DVec2]) -> Self {
        Self::build(pts, true)
    }

    /// The points `pts` themselves as items.
    pub(super) fn points(pts: &'a [DVec2]) -> Self {
        Self::build(pts, false)
    }

    fn build(pts: &'a [DVec2], segments: bool) -> Self {
        let mut chain = Polyline {
            pts,
            segments,
            levels: Vec::new(),
        };
        let items = chain.items();
        let mut cur: Vec<Bounds> = (0..items.div_ceil(CHAIN_LEAF))
            .map(|j| {
                let end = ((j + 1) * CHAIN_LEAF).min(items) - 1;
                let last = if segments { end + 1 } else { end };
                pts[j * CHAIN_LEAF..=last]
                    .iter()
                    .fold((pts[j * CHAIN_LEAF], pts[j * CHAIN_LEAF]), |b, &q| {
                        (b.0.min(q), b.1.max(q))
                    })
            })
            .collect();
        while cur.len() > 1 {
            let next = cur
                .chunks(2)
                .map(|c| c.iter().fold(c[0], |b, q| (b.0.min(q.0), b.1.max(q.1))))
                .collect();
            chain.levels.push(cur);
            cur = next;
        }
        chain.levels.push(cur);
        chain
    }

    /// Number of items: segments or points.
    fn items(&self) -> usize {
        if self.segments {
            self.pts.len().saturating_sub(1)
        } else {
            self.pts.len()
        }
    }

    /// Distance from `p` to item `i` and the parameter of the nearest point along it.
    fn item_distance(&self, i: usize, p: DVec2) -> (f64, f64) {
        if !self.segments {
            return (self.pts[i].distance(p), 0.0);
        }
        let seg = crate::geom::Line::new(self.pts[i], self.pts[i + 1]);
        let t = seg.nearest_t(p);
        (seg.eval(t).distance(p), t)
    }

    /// Distance from `p` to the polyline, the segment it is nearest to and the parameter
    /// along that segment (for one point: its distance, segment 0, parameter 0); for a
    /// chain of points: the distance to the nearest point, its index and 0.
    pub(super) fn nearest(&self, p: DVec2) -> (f64, usize, f64) {
        self.nearest_from(p, None)
    }

    /// [`Polyline::nearest`], the search bounded from the start by the distance to the
    /// item `hint` (the answer is the same with any hint, or none).
    pub(super) fn nearest_from(&self, p: DVec2, hint: Option<usize>) -> (f64, usize, f64) {
        let items = self.items();
        if items == 0 {
            return (
                self.pts.first().map_or(f64::INFINITY, |&q| p.distance(q)),
                0,
                0.0,
            );
        }
        let i = hint.filter(|&i| i < items).unwrap_or(0);
        let (d, t) = self.item_distance(i, p);
        let mut best = (d, i, t);
        let top = self.levels.len() - 1;
        for j in 0..self.levels[top].len() {
            self.descend(top, j, p, &mut best);
        }
        best
    }

    /// The least distance from `p` to the items `hint` − 1, `hint`, `hint` + 1 and the
    /// item at that distance: an upper bound of the distance [`Polyline::nearest_from`]
    /// finds (which starts from that item), without a search.
    pub(super) fn near_hint(&self, p: DVec2, hint: usize) -> (f64, usize) {
        let items = self.items();
        let mut best = (f64::INFINITY, hint);
        for i in hint.saturating_sub(1)..(hint + 2).min(items) {
            let d = self.item_distance(i, p).0;
            if d < best.0 {
                best = (d, i);
            }
        }
        best
    }

    /// Branch and bound below node `j` of level `k`: nodes farther than the best distance
    /// so far are pruned, the nearer child is visited first; ties keep the lower index.
    fn descend(&self, k: usize, j: usize, p: DVec2, best: &mut (f64, usize, f64)) {
        if box_distance(&self.levels[k][j], p) > best.0 {
            return;
        }
        if k == 0 {
            let end = ((j + 1) * CHAIN_LEAF).min(self.items());
            for i in j * CHAIN_LEAF..end {
                let (d, t) = self.item_distance(i, p);
                if d < best.0 || (d == best.0 && i < best.1) {
                    *best = (d, i, t);
                }
            }
            return;
        }
        let below = &self.levels[k - 1];
        let (a, b) = (2 * j, 2 * j + 1);
        if b >= below.len() {
            self.descend(k - 1, a, p, best);
        } else if box_distance(&below[b], p) < box_distance(&below[a], p) {
            self.descend(k - 1, b, p, best);
            self.descend(k - 1, a, p, best);
        } else {
            self.descend(k - 1, a, p, best);
            self.descend(k - 1, b, p, best);
        }
    }
}

#[cfg(test)]
mod tests;
