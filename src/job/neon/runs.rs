//! Flex runs: the strokes' spines chained into pieces of flex where their ends meet
//! ([`runs`]), their lengths ([`run_length`]), the runs too short for flex made marks
//! ([`split_marks`]), and the holes at their ends ([`run_hole_points`]).

use super::spine_length;
use crate::dbsc::DiskBSpline;
use crate::design::neon::{Flex, strokes_named};
use crate::design::{Design, HoleAt};
use crate::geom::{DVec2, cross};

/// One stroke of a run, as the run passes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Leg {
    /// Index of the stroke in the design.
    pub stroke: usize,
    /// The run passes the stroke from its end to its start.
    pub reversed: bool,
}

/// A run: its legs in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// The run's name (`[[neon.run]]` name, else `run N`).
    pub name: String,
    /// The strokes it passes, in order.
    pub legs: Vec<Leg>,
    /// The run returns to its start (a closed stroke, or a chain whose ends meet).
    pub closed: bool,
}

impl Leg {
    pub(super) fn entry(&self, curves: &[DiskBSpline]) -> (DVec2, f64) {
        let c = &curves[self.stroke];
        let (lo, hi) = c.domain();
        let t = if self.reversed { hi } else { lo };
        (c.center(t), t)
    }

    pub(super) fn exit(&self, curves: &[DiskBSpline]) -> (DVec2, f64) {
        let c = &curves[self.stroke];
        let (lo, hi) = c.domain();
        let t = if self.reversed { lo } else { hi };
        (c.center(t), t)
    }

    /// Unit tangent in the run's direction at parameter `t` (zero where q′ = 0).
    pub(super) fn direction(&self, curves: &[DiskBSpline], t: f64) -> DVec2 {
        let d = curves[self.stroke].derivs(t, 1)[1].0.normalize_or_zero();
        if self.reversed { -d } else { d }
    }
}

impl Run {
    /// Start point of the run (the seam of a closed run).
    pub fn start(&self, curves: &[DiskBSpline]) -> DVec2 {
        self.legs[0].entry(curves).0
    }

    /// End point of the run.
    pub fn end(&self, curves: &[DiskBSpline]) -> DVec2 {
        self.legs[self.legs.len() - 1].exit(curves).0
    }
}

/// A stroke end: (stroke index, true for the end at the domain's upper bound).
type End = (usize, bool);

/// The runs of `design` (module docs); `curves[i]` is the curve of `design.stroke[i]`.
pub fn runs(design: &Design, curves: &[DiskBSpline], flex: &Flex) -> Vec<Run> {
    let n = curves.len();
    let neon = design.neon.clone().unwrap_or_default();
    let mut used = vec![false; n];
    // (first stroke index, run) pairs, sorted at the end.
    let mut out: Vec<(usize, Option<String>, Vec<Leg>, bool)> = Vec::new();
    for r in &neon.run {
        let ids: Vec<usize> = r
            .strokes
            .iter()
            .flat_map(|s| strokes_named(design, s))
            .filter(|&i| i < n && !used[i])
            .collect();
        if ids.is_empty() {
            continue;
        }
        for &i in &ids {
            used[i] = true;
        }
        let legs = chain(&ids, curves);
        let closed = if legs.len() == 1 {
            curves[legs[0].stroke].is_closed()
        } else {
            legs[legs.len() - 1]
                .exit(curves)
                .0
                .distance(legs[0].entry(curves).0)
                <= flex.join_tolerance
        };
        let first = *ids.iter().min().unwrap_or(&0);
        out.push((first, r.name.clone(), legs, closed));
    }
    for i in 0..n {
        if !used[i] && curves[i].is_closed() {
            used[i] = true;
            out.push((
                i,
                None,
                vec![Leg {
                    stroke: i,
                    reversed: false,
                }],
                true,
            ));
        }
    }
    let open: Vec<usize> = (0..n).filter(|&i| !used[i]).collect();
    let partner = pair_ends(
        design,
        &open,
        curves,
        flex,
        neon.break_at.as_deref().unwrap_or(&[]),
    );
    for &s in &open {
        if used[s] {
            continue;
        }
        // Walk backwards from s's start to a free end (or around a cycle back to s).
        let (mut cur, mut entry_is_end) = (s, false);
        let mut steps = 0;
        let mut cycle = false;
        while let Some(&(p, p_end)) = partner.get(&(cur, entry_is_end)) {
            steps += 1;
            // Leaving stroke p through its other end backwards.
            if p == s || steps > open.len() {
                cycle = p == s;
                if cycle {
                    // Start the cycle at s itself.
                    cur = s;
                    entry_is_end = false;
                }
                break;
            }
            cur = p;
            entry_is_end = !p_end;
        }
        let mut legs = Vec::new();
        let (mut at, mut enter_end) = (cur, entry_is_end);
        loop {
            if used[at] {
                break;
            }
            used[at] = true;
            legs.push(Leg {
                stroke: at,
                reversed: enter_end,
            });
            match partner.get(&(at, !enter_end)) {
                Some(&(q, q_end)) => {
                    at = q;
                    enter_end = q_end;
                }
                None => break,
            }
        }
        let first = legs.iter().map(|l| l.stroke).min().unwrap_or(s);
        out.push((first, None, legs, cycle));
    }
    out.sort_by_key(|(first, ..)| *first);
    out.into_iter()
        .enumerate()
        .map(|(k, (_, name, legs, closed))| Run {
            name: name.unwrap_or_else(|| format!("run {}", k + 1)),
            legs,
            closed,
        })
        .collect()
}

/// Legs of an explicit run: `ids` in order, each passed in the direction that starts
/// nearest the previous one's exit (the first: the direction whose exit is nearest the
/// second stroke).
fn chain(ids: &[usize], curves: &[DiskBSpline]) -> Vec<Leg> {
    let ends = |i: usize| {
        let (lo, hi) = curves[i].domain();
        (curves[i].center(lo), curves[i].center(hi))
    };
    let mut legs: Vec<Leg> = Vec::with_capacity(ids.len());
    for (k, &i) in ids.iter().enumerate() {
        let (a, b) = ends(i);
        let reversed = match legs.last() {
            Some(prev) => {
                let p = prev.exit(curves).0;
                b.distance(p) < a.distance(p)
            }
            None => match ids.get(k + 1) {
                Some(&j) => {
                    let (c, d) = ends(j);
                    a.distance(c).min(a.distance(d)) < b.distance(c).min(b.distance(d))
                }
                None => false,
            },
        };
        legs.push(Leg {
            stroke: i,
            reversed,
        });
    }
    legs
}

/// Unit tangent pointing into stroke `i` from its end `e`.
fn inward(curves: &[DiskBSpline], (i, e): End) -> DVec2 {
    let c = &curves[i];
    let (lo, hi) = c.domain();
    let d = c.derivs(if e { hi } else { lo }, 1)[1]
        .0
        .normalize_or_zero();
    if e { -d } else { d }
}

/// Ends at most this far apart (relative to the coordinates' size) coincide: their join
/// has no gap, and among such joins the straightest is made first.
pub(super) const COINCIDE_REL: f64 = 1e-9;

/// The partner of every joined end among the open strokes `open` (module docs). Candidate
/// pairs are ends at most the join tolerance apart whose midpoint is not within the flex
/// width of a `break_at` point; they are taken greedily, each end at most once: first the
/// corners at which loading split a stroke (`NAME#k` end to `NAME#k+1` start, the pen's own
/// path), then coinciding ends before ends with a gap, nearer gaps first, and among equals
/// the smaller turning angle.
fn pair_ends(
    design: &Design,
    open: &[usize],
    curves: &[DiskBSpline],
    flex: &Flex,
    break_at: &[[f64; 2]],
) -> std::collections::HashMap<End, End> {
    let mut ends: Vec<(End, DVec2)> = Vec::with_capacity(2 * open.len());
    for &i in open {
        let (lo, hi) = curves[i].domain();
        ends.push(((i, false), curves[i].center(lo)));
        ends.push(((i, true), curves[i].center(hi)));
    }
    let corner_pair = |a: End, b: End| {
        let name = |i: usize| design.stroke[i].name.as_str();
        design.corners.iter().any(|c| {
            let (x, y) = (c.pieces[0].as_str(), c.pieces[1].as_str());
            (a.1 && !b.1 && name(a.0) == x && name(b.0) == y)
                || (b.1 && !a.1 && name(b.0) == x && name(a.0) == y)
        })
    };
    // Candidate pairs by a sweep in x.
    let mut order: Vec<usize> = (0..ends.len()).collect();
    order.sort_by(|&a, &b| ends[a].1.x.total_cmp(&ends[b].1.x));
    let tol = flex.join_tolerance;
    // (corner first, gap, turn, a, b)
    let mut pairs: Vec<(bool, f64, f64, usize, usize)> = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            let (pa, pb) = (ends[a].1, ends[b].1);
            if pb.x - pa.x > tol {
                break;
            }
            let gap = pa.distance(pb);
            let mid = 0.5 * (pa + pb);
            if gap > tol
                || break_at
                    .iter()
                    .any(|p| mid.distance(DVec2::from(*p)) <= flex.width)
            {
                continue;
            }
            // Arriving along −inward(a), leaving along inward(b): the turn between them.
            let da = -inward(curves, ends[a].0);
            let db = inward(curves, ends[b].0);
            let turn = cross(da, db).atan2(da.dot(db)).abs();
            let coincide = gap <= COINCIDE_REL * (1.0 + pa.length());
            let (x, y) = (a.min(b), a.max(b));
            let corner = corner_pair(ends[x].0, ends[y].0);
            pairs.push((!corner, if coincide { 0.0 } else { gap }, turn, x, y));
        }
    }
    pairs.sort_by(|p, q| {
        (p.0.cmp(&q.0))
            .then(p.1.total_cmp(&q.1))
            .then(p.2.total_cmp(&q.2))
            .then(p.3.cmp(&q.3))
            .then(p.4.cmp(&q.4))
    });
    let mut partner = std::collections::HashMap::new();
    for (_, _, _, a, b) in pairs {
        let (ea, eb) = (ends[a].0, ends[b].0);
        if partner.contains_key(&ea) || partner.contains_key(&eb) {
            continue;
        }
        partner.insert(ea, eb);
        partner.insert(eb, ea);
    }
    partner
}

/// Length of a run (design units): its strokes' spine lengths ([`spine_length`], absolute
/// tolerance `tol` each) plus the straight gaps bridged between consecutive strokes (and
/// from the last back to the first of a closed chain), as in [`bom`].
pub fn run_length(run: &Run, curves: &[DiskBSpline], tol: f64) -> f64 {
    let n = run.legs.len();
    let mut len: f64 = run
        .legs
        .iter()
        .map(|l| spine_length(&curves[l.stroke], tol))
        .sum();
    for k in 0..n {
        let next = if k + 1 < n {
            run.legs[k + 1]
        } else if run.closed && n > 1 {
            run.legs[0]
        } else {
            continue;
        };
        let p = run.legs[k].exit(curves).0;
        let gap = p.distance(next.entry(curves).0);
        if gap > COINCIDE_REL * (1.0 + p.length()) {
            len += gap;
        }
    }
    len
}

/// The runs split by `[neon] min_run_length` (unset: none is a mark): (flex runs, marks
/// with their lengths, design units); `tol` is the length tolerance per stroke.
pub fn split_marks(
    design: &Design,
    curves: &[DiskBSpline],
    runs: Vec<Run>,
    tol: f64,
) -> (Vec<Run>, Vec<(Run, f64)>) {
    let Some(min) = design.neon.as_ref().and_then(|n| n.min_run_length) else {
        return (runs, Vec::new());
    };
    let mut flex = Vec::new();
    let mut marks = Vec::new();
    for r in runs {
        let len = run_length(&r, curves, tol);
        if len < min {
            marks.push((r, len));
        } else {
            flex.push(r);
        }
    }
    (flex, marks)
}

/// Where the holes of a holes operation go with a `[neon]` table: at the start and end of
/// every open run (`at`: both, start only, end only; a closed run: one hole at its seam),
/// when the stroke at that end is among `selected` stroke indices. Each point comes with
/// the name of its stroke; coincident points are drilled once.
pub fn run_hole_points(
    design: &Design,
    curves: &[DiskBSpline],
    runs: &[Run],
    at: HoleAt,
    selected: &[usize],
) -> Vec<(DVec2, String)> {
    let mut out: Vec<(DVec2, String)> = Vec::new();
    for run in runs {
        let first = run.legs[0].stroke;
        let last = run.legs[run.legs.len() - 1].stroke;
        let mut pts = Vec::new();
        if run.closed {
            pts.push((run.start(curves), first));
        } else {
            if matches!(at, HoleAt::Ends | HoleAt::Start) {
                pts.push((run.start(curves), first));
            }
            if matches!(at, HoleAt::Ends | HoleAt::End) {
                pts.push((run.end(curves), last));
            }
        }
        for (p, s) in pts {
            let tol = super::super::tolerances::SAME_POINT_REL * (1.0 + p.length());
            if selected.contains(&s) && !out.iter().any(|(q, _)| q.distance(p) <= tol) {
                out.push((p, design.stroke[s].name.clone()));
            }
        }
    }
    out
}
