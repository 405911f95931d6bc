//! Intersection tests on curves (not on sample points): cubic–cubic, cubic self-intersection,
//! and all intersections within a [`Path`] or between two paths.
//!
//! Method: recursive Bézier subdivision with bounding-box pruning (the control polygon's
//! box contains a cubic; an arc of sweep ≤ π lies within its sagitta of its chord); boxes
//! are grown by `tol/2`. A pair of pieces that are both flat within `tol/2` is decided on the
//! chords with the exact predicates of [`crate::geom::predicates`]: the chords cross
//! (exactly), or their distance is at most the two flatnesses plus `tol`.
//!
//! Guarantees for a tolerance `tol`:
//! - curves that come within `tol` of each other are reported (so every true intersection
//!   is; a hit lies within 2·tol of it), except within the zone of a shared end of adjacent
//!   segments (the joint itself): [`JOINT_ZONE`]·tol, widened at a sharp kink to
//!   `JOINT_ZONE·tol / sin φ` (φ the angle between the two curves leaving the joint), at
//!   most [`JOINT_ZONE_MAX`]·tol;
//! - curves farther apart than 3·tol are never reported.
//!
//! Tangency: curves that touch without crossing are reported as a contact (like a
//! crossing); lifted off by more than 3·tol they are not. Adjacent segments that double back
//! along each other (a cusp with overlap) are reported; a G1 or kinked joint alone is not.

use crate::geom::predicates::{line_intersection, segments_intersect};
use crate::geom::{Arc, CubicBez, DVec2, Line, Path, PathSeg};
use std::f64::consts::PI;

/// Deepest subdivision: 2⁻⁶⁰ of a curve's size is far below any useful tolerance; a pair
/// still unresolved there is reported (conservative).
const MAX_DEPTH: u32 = 60;

/// Pieces lying entirely within `JOINT_ZONE·tol` of a shared end of two adjacent segments
/// are the joint itself and are not tested against each other: beyond it, a G1 continuation
/// (pieces of size ≤ 2·tol at distance ≥ tol) no longer looks like a contact.
pub const JOINT_ZONE: f64 = 4.0;

/// Widest joint zone, in units of `tol`. Two curves leaving a joint at an angle φ < 90° (a
/// kink turning by 180° − φ) stay within `s·sin φ` of each other at a distance `s` from it,
/// so a fixed zone would report the kink itself as a contact: a grown board's concave
/// corner turning by 167° (φ = 13°) came within `tol` at 4.4·tol from the corner
/// (`examples/gallery/neon_open.toml`, `tol` = eps/1000). The zone is therefore
/// `JOINT_ZONE·tol / sin φ`, but at most this: a sharper kink (φ below asin(4/64) ≈ 3.6°)
/// is reported as the curves doubling back along each other.
pub const JOINT_ZONE_MAX: f64 = 64.0;

/// A shared end of two adjacent curves whose neighbourhood is not tested.
#[derive(Clone, Copy, Debug)]
struct Joint {
    /// Parameter of the joint on the first curve.
    ta: f64,
    /// Parameter of the joint on the second curve.
    tb: f64,
    /// The joint.
    point: DVec2,
    /// Pieces lying entirely within this distance of `point` are not tested.
    zone: f64,
}

impl Joint {
    /// The joint of `a`'s end (`ta` = 1) with `b`'s start (`tb` = 0), or of `a`'s start with
    /// `b`'s end (`ta` = 0, `tb` = 1), with its zone from the angle φ between the two curves'
    /// directions away from it: cos φ = u·v for unit directions u, v; the zone is
    /// `JOINT_ZONE·tol / sin φ` for φ < 90°, clamped to [`JOINT_ZONE`, `JOINT_ZONE_MAX`]·tol.
    fn between(a: &PathSeg, ta: f64, b: &PathSeg, tb: f64, tol: f64) -> Joint {
        let point = if ta == 1.0 { a.end() } else { a.start() };
        let u = leaving(a, ta == 1.0);
        let v = leaving(b, tb == 1.0);
        let sin = if u.dot(v) <= 0.0 {
            1.0
        } else {
            u.perp_dot(v).abs()
        };
        let factor = if sin * JOINT_ZONE_MAX > JOINT_ZONE {
            JOINT_ZONE / sin
        } else {
            JOINT_ZONE
        };
        Joint {
            ta,
            tb,
            point,
            zone: factor * tol,
        }
    }

    /// A G1 joint (the halves of a split curve).
    fn smooth(ta: f64, tb: f64, point: DVec2, tol: f64) -> Joint {
        Joint {
            ta,
            tb,
            point,
            zone: JOINT_ZONE * tol,
        }
    }
}

/// Unit direction in which `seg` leaves its end (`at_end`) or its start, pointing away from
/// that end along the curve (zero for a curve of zero length). A cubic whose first control
/// point coincides with its end leaves along the next distinct one.
fn leaving(seg: &PathSeg, at_end: bool) -> DVec2 {
    let d = match *seg {
        PathSeg::Line(l) => {
            if at_end {
                l.p0 - l.p1
            } else {
                l.p1 - l.p0
            }
        }
        PathSeg::Arc(a) => {
            if at_end {
                -a.tangent(1.0)
            } else {
                a.tangent(0.0)
            }
        }
        PathSeg::Cubic(c) => {
            let (e, rest) = if at_end {
                (c.p3, [c.p2, c.p1, c.p0])
            } else {
                (c.p0, [c.p1, c.p2, c.p3])
            };
            rest.iter()
                .map(|&q| q - e)
                .find(|d| *d != DVec2::ZERO)
                .unwrap_or(DVec2::ZERO)
        }
    };
    d.normalize_or_zero()
}

/// At most this many hits are collected per pair of segments (overlapping curves would
/// otherwise report one hit per leaf).
const MAX_HITS_PER_PAIR: usize = 64;

/// Work bound of one search (one pair of segments, or one cubic's self-intersection test):
/// at most this many pairs of pieces are visited. With `tol` > 0 a pair is decided once
/// both pieces are flat within tol/2, which takes about log₄(size²/tol) halvings, so
/// ordinary input needs a few thousand visits; a zero, tiny or non-finite tolerance (or
/// two long curves running within a few tol of each other) could otherwise visit up to
/// 4^`MAX_DEPTH` pairs. A search that runs out of budget reports one conservative hit
/// at the first piece it could not decide, as the depth limit does, so callers turn it into
/// their intersection error (naming the stroke) instead of hanging.
pub const MAX_VISITS_PER_SEARCH: usize = 1 << 20;

/// One intersection of two curves: parameters on each and the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Parameter of the hit on the first curve, in [0, 1].
    pub ta: f64,
    /// Parameter of the hit on the second curve, in [0, 1] (for a self-intersection of one cubic,
    /// the second parameter on the same curve).
    pub tb: f64,
    /// The intersection point (for a contact, a point between the two curves).
    pub point: DVec2,
}

/// An intersection between segments `a` and `b` of a path (or of two paths); `a == b` for
/// a self-intersection of one cubic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathHit {
    /// Index of the segment in the first path.
    pub a: usize,
    /// Index of the segment in the second path (`a` itself for a self-intersection of a cubic).
    pub b: usize,
    /// The intersection, `ta` on segment `a` and `tb` on segment `b`.
    pub hit: Hit,
}

/// A sub-curve of a segment with its parameter range in the segment, with its ends,
/// flatness and box computed once (a piece meets many others in a search, and an arc's
/// ends cost a sine and a cosine each).
#[derive(Clone, Copy, Debug)]
struct Piece {
    geom: Geom,
    t0: f64,
    t1: f64,
    ends: (DVec2, DVec2),
    /// Upper bound of the distance of the curve from its chord segment.
    flat: f64,
    bbox: BBox,
}

#[derive(Clone, Copy, Debug)]
enum Geom {
    Cubic(CubicBez),
    Arc(Arc),
}

/// Distance bound of an arc from its chord: the sagitta r·(1 − cos(|sweep|/2)) up to a half
/// turn, the diameter beyond.
fn arc_flatness(a: &Arc) -> f64 {
    let s = a.sweep.abs();
    if s <= PI {
        a.radius * (1.0 - (0.5 * s).cos())
    } else {
        2.0 * a.radius
    }
}

impl Piece {
    fn new(geom: Geom, t0: f64, t1: f64) -> Piece {
        match geom {
            Geom::Cubic(c) => Piece {
                geom,
                t0,
                t1,
                ends: (c.p0, c.p3),
                flat: c.flatness(),
                bbox: c.control_bbox().into(),
            },
            Geom::Arc(a) => Piece::arc(a, t0, t1, (a.p0(), a.p1()), arc_flatness(&a)),
        }
    }

    /// The piece of arc `a` with its end points and [`arc_flatness`] already known (the
    /// halves of a split share the middle point and their sweep).
    fn arc(a: Arc, t0: f64, t1: f64, ends: (DVec2, DVec2), flat: f64) -> Piece {
        let (p, q) = ends;
        let g = DVec2::splat(flat);
        Piece {
            geom: Geom::Arc(a),
            t0,
            t1,
            ends,
            flat,
            bbox: (p.min(q) - g, p.max(q) + g),
        }
    }

    fn of(seg: &PathSeg) -> Piece {
        let geom = match *seg {
            PathSeg::Line(l) => {
                let d = (l.p1 - l.p0) / 3.0;
                Geom::Cubic(CubicBez::new(l.p0, l.p0 + d, l.p1 - d, l.p1))
            }
            PathSeg::Cubic(c) => Geom::Cubic(c),
            PathSeg::Arc(a) => Geom::Arc(a),
        };
        Piece::new(geom, 0.0, 1.0)
    }

    fn ends(&self) -> (DVec2, DVec2) {
        self.ends
    }

    /// Upper bound of the distance of the curve from its chord segment.
    fn flatness(&self) -> f64 {
        self.flat
    }

    fn bbox(&self) -> (DVec2, DVec2) {
        self.bbox
    }

    fn within(&self, p: DVec2, rad: f64) -> bool {
        let (lo, hi) = self.bbox();
        [lo, hi, DVec2::new(lo.x, hi.y), DVec2::new(hi.x, lo.y)]
            .iter()
            .all(|q| q.distance(p) <= rad)
    }

    fn size(&self) -> f64 {
        let (lo, hi) = self.bbox();
        (hi - lo).length()
    }

    fn split(&self) -> (Piece, Piece) {
        let tm = 0.5 * (self.t0 + self.t1);
        match self.geom {
            Geom::Cubic(c) => {
                let (a, b) = c.split(0.5);
                (
                    Piece::new(Geom::Cubic(a), self.t0, tm),
                    Piece::new(Geom::Cubic(b), tm, self.t1),
                )
            }
            Geom::Arc(a) => {
                // The first half starts where this piece does and ends where the second
                // starts (both at the angle start + h): one point and one sagitta computed.
                let h = 0.5 * a.sweep;
                let (a0, a1) = (
                    Arc::new(a.center, a.radius, a.start, h),
                    Arc::new(a.center, a.radius, a.start + h, h),
                );
                let (mid, flat) = (a1.p0(), arc_flatness(&a0));
                (
                    Piece::arc(a0, self.t0, tm, (self.ends.0, mid), flat),
                    Piece::arc(a1, tm, self.t1, (mid, a1.p1()), flat),
                )
            }
        }
    }

    fn touches_param(&self, t: f64) -> bool {
        self.t0 == t || self.t1 == t
    }

    /// The cone at the piece's end at parameter `t` (its start when `t == t0`) that holds
    /// the whole piece: apex, axis (a unit direction) and the angles of its bounding rays
    /// from the axis, counter-clockwise positive. A cubic lies in the convex hull of its
    /// control points, so in the cone the other three span from the end; an arc of sweep
    /// below π lies between its tangent at the end and its chord. `None` when the
    /// directions span π or more (a piece turning back on itself) or the piece is a point.
    fn cone(&self, t: f64) -> Option<Cone> {
        let at_start = self.t0 == t;
        let (apex, dirs) = match self.geom {
            Geom::Cubic(c) if at_start => (c.p0, [c.p1 - c.p0, c.p2 - c.p0, c.p3 - c.p0]),
            Geom::Cubic(c) => (c.p3, [c.p2 - c.p3, c.p1 - c.p3, c.p0 - c.p3]),
            Geom::Arc(a) => {
                if a.sweep.abs() >= PI {
                    return None;
                }
                let (p, q) = if at_start {
                    (self.ends.0, self.ends.1)
                } else {
                    (self.ends.1, self.ends.0)
                };
                // The tangent leaving the apex along the arc: ±(p − centre)⊥.
                let r = p - a.center;
                let turn = if at_start { a.sweep } else { -a.sweep };
                let tangent = turn.signum() * DVec2::new(-r.y, r.x);
                (p, [tangent, q - p, q - p])
            }
        };
        let axis = dirs
            .iter()
            .copied()
            .find(|d| *d != DVec2::ZERO)?
            .normalize();
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for d in dirs.iter().filter(|d| **d != DVec2::ZERO) {
            let th = axis.perp_dot(*d).atan2(axis.dot(*d));
            lo = lo.min(th);
            hi = hi.max(th);
        }
        (hi - lo < PI && axis.is_finite()).then_some(Cone { apex, axis, lo, hi })
    }
}

/// A cone holding a piece that ends at its apex ([`Piece::cone`]): the rays at angles
/// `lo..=hi` (radians, |hi − lo| < π) from `axis`.
#[derive(Clone, Copy, Debug)]
struct Cone {
    apex: DVec2,
    axis: DVec2,
    lo: f64,
    hi: f64,
}

impl Cone {
    /// The smallest angle between a ray of `self` and a ray of `o` (in [0, π]), or `None`
    /// when the cones share a ray. The two angular intervals sit on the circle of
    /// directions; the answer is the smaller of the two gaps between them.
    fn gap(&self, o: &Cone) -> Option<f64> {
        use std::f64::consts::TAU;
        let beta = self.axis.perp_dot(o.axis).atan2(self.axis.dot(o.axis));
        // `o`'s interval in `self`'s angles, shifted to start in [lo, lo + 2π).
        let mut c0 = beta + o.lo;
        c0 = self.lo + (c0 - self.lo).rem_euclid(TAU);
        let c1 = c0 + (o.hi - o.lo);
        if c0 <= self.hi || c1 >= self.lo + TAU {
            return None;
        }
        Some((c0 - self.hi).min(self.lo + TAU - c1))
    }
}

/// True when the boxes overlap after growing each by `grow`.
fn boxes_overlap(a: (DVec2, DVec2), b: (DVec2, DVec2), grow: f64) -> bool {
    let g = 2.0 * grow;
    a.0.x <= b.1.x + g && b.0.x <= a.1.x + g && a.0.y <= b.1.y + g && b.0.y <= a.1.y + g
}

struct Search<'a> {
    tol: f64,
    /// Shared ends of the two curves to ignore (joints of adjacent segments).
    joints: &'a [Joint],
    hits: Vec<Hit>,
    /// Pairs of pieces visited so far (bounded by [`MAX_VISITS_PER_SEARCH`]).
    visits: usize,
    /// Settle pairs at a joint by [`Search::clear_of_joint`] (always, except in the tests
    /// that compare it with plain bisection).
    joint_cones: bool,
}

impl Search<'_> {
    fn at_joint(&self, a: &Piece, b: &Piece) -> bool {
        self.joints
            .iter()
            .any(|j| a.touches_param(j.ta) && b.touches_param(j.tb))
    }

    /// Whether `a` and `b`, which both end at the same (single) joint, can come within
    /// 3·tol of each other only inside its zone, so that the search below them cannot
    /// report anything (a pair is reported only where the curves come within 3·tol, and
    /// pieces inside the zone are skipped).
    ///
    /// Bound: `a` lies in a cone at its end A, `b` in one at its end B (‖A − B‖ = δ ≤ tol
    /// for a joint), and no ray of one makes an angle below γ with a ray of the other. A
    /// point x of `a` at distance s from A is at least s·sin γ' from B's cone moved to A
    /// (γ' = min(γ, π/2): the distance from a point to a convex cone), so at least
    /// s·sin γ' − δ from `b`. Outside the zone s > zone − ‖A − joint‖, so the condition is
    /// (zone − ‖A − joint‖)·sin γ' − δ > 3·tol, and the same for `b`. Near a joint this
    /// replaces the bisection down to the zone (log₂(size/zone) levels) by one test once
    /// the pieces' cones are narrow enough.
    fn clear_of_joint(&self, a: &Piece, b: &Piece) -> bool {
        let mut touched = self
            .joints
            .iter()
            .filter(|j| a.touches_param(j.ta) && b.touches_param(j.tb));
        let (Some(j), None) = (touched.next(), touched.next()) else {
            return false;
        };
        let (Some(ca), Some(cb)) = (a.cone(j.ta), b.cone(j.tb)) else {
            return false;
        };
        let Some(gamma) = ca.gap(&cb) else {
            return false;
        };
        let sin = gamma.min(0.5 * PI).sin();
        let delta = ca.apex.distance(cb.apex);
        let reach = 3.0 * self.tol;
        (j.zone - ca.apex.distance(j.point)) * sin - delta > reach
            && (j.zone - cb.apex.distance(j.point)) * sin - delta > reach
    }

    fn in_joint_zone(&self, a: &Piece, b: &Piece) -> bool {
        self.joints
            .iter()
            .any(|j| a.within(j.point, j.zone) || b.within(j.point, j.zone))
    }

    fn run(&mut self, a: &Piece, b: &Piece, depth: u32) {
        if self.hits.len() >= MAX_HITS_PER_PAIR
            || !boxes_overlap(a.bbox(), b.bbox(), 0.5 * self.tol)
            || self.in_joint_zone(a, b)
        {
            return;
        }
        let joint = self.at_joint(a, b);
        if joint && self.joint_cones && self.clear_of_joint(a, b) {
            return;
        }
        self.visits += 1;
        let (fa, fb) = (a.flatness(), b.flatness());
        if !joint && fa <= 0.5 * self.tol && fb <= 0.5 * self.tol {
            let ((p, q), (r, s)) = (a.ends(), b.ends());
            if segments_intersect(p, q, r, s)
                || Line::new(p, q).distance_to_line(&Line::new(r, s)) <= fa + fb + self.tol
            {
                let x = line_intersection(p, q, r, s)
                    .filter(|x| x.is_finite())
                    .unwrap_or(0.25 * (p + q + r + s));
                let u = Line::new(p, q).nearest_t(x);
                let v = Line::new(r, s).nearest_t(x);
                self.hits.push(Hit {
                    ta: a.t0 + u * (a.t1 - a.t0),
                    tb: b.t0 + v * (b.t1 - b.t0),
                    point: x,
                });
            }
            return;
        }
        if depth >= MAX_DEPTH || self.visits >= MAX_VISITS_PER_SEARCH {
            let (p, _) = a.ends();
            self.hits.push(Hit {
                ta: a.t0,
                tb: b.t0,
                point: p,
            });
            return;
        }
        let (a0, a1) = a.split();
        let (b0, b1) = b.split();
        for x in [&a0, &a1] {
            for y in [&b0, &b1] {
                self.run(x, y, depth + 1);
            }
        }
    }

    /// Self-intersections of one piece: a cubic whose hodograph lies in an open half-plane
    /// (u·(p1 − p0), u·(p2 − p1), u·(p3 − p2) > 0 for u the chord) is monotone along u,
    /// hence simple; otherwise split and test the halves against each other.
    fn run_self(&mut self, a: &Piece, depth: u32) {
        let Geom::Cubic(c) = a.geom else {
            return; // arcs of |sweep| < 2π are simple
        };
        let u = c.p3 - c.p0;
        let mono = [c.p1 - c.p0, c.p2 - c.p1, c.p3 - c.p2]
            .iter()
            .all(|d| d.dot(u) > 0.0);
        if mono || a.size() <= self.tol || depth >= MAX_DEPTH {
            return;
        }
        self.visits += 1;
        if self.visits >= MAX_VISITS_PER_SEARCH {
            let (p, _) = a.ends();
            self.hits.push(Hit {
                ta: a.t0,
                tb: a.t1,
                point: p,
            });
            return;
        }
        let (x, y) = a.split();
        self.run_self(&x, depth + 1);
        self.run_self(&y, depth + 1);
        let mut inner = Search {
            tol: self.tol,
            joints: &[Joint::smooth(x.t1, y.t0, x.ends().1, self.tol)],
            hits: Vec::new(),
            visits: self.visits,
            joint_cones: self.joint_cones,
        };
        inner.run(&x, &y, depth + 1);
        self.visits = inner.visits;
        self.hits.extend(inner.hits);
    }
}

/// Merges hits closer than 2·`tol` to each other.
fn dedup(hits: Vec<Hit>, tol: f64) -> Vec<Hit> {
    let mut out: Vec<Hit> = Vec::new();
    for h in hits {
        if !out.iter().any(|o| o.point.distance(h.point) <= 2.0 * tol) {
            out.push(h);
        }
    }
    out
}

fn pair_hits(a: &PathSeg, b: &PathSeg, joints: &[Joint], tol: f64) -> Vec<Hit> {
    pair_hits_with(a, b, joints, tol, true)
}

fn pair_hits_with(
    a: &PathSeg,
    b: &PathSeg,
    joints: &[Joint],
    tol: f64,
    joint_cones: bool,
) -> Vec<Hit> {
    let mut s = Search {
        tol,
        joints,
        hits: Vec::new(),
        visits: 0,
        joint_cones,
    };
    s.run(&Piece::of(a), &Piece::of(b), 0);
    dedup(s.hits, tol)
}

/// Intersections of two cubics within `tol` (module docs for the guarantees).
pub fn cubic_intersections(a: &CubicBez, b: &CubicBez, tol: f64) -> Vec<Hit> {
    pair_hits(&PathSeg::Cubic(*a), &PathSeg::Cubic(*b), &[], tol)
}

/// Self-intersections of one cubic within `tol` (a cubic has at most one loop; a cusp
/// alone is not reported).
pub fn cubic_self_intersections(c: &CubicBez, tol: f64) -> Vec<Hit> {
    let mut s = Search {
        tol,
        joints: &[],
        hits: Vec::new(),
        visits: 0,
        joint_cones: true,
    };
    s.run_self(&Piece::of(&PathSeg::Cubic(*c)), 0);
    dedup(s.hits, tol)
}

/// An axis-aligned box (min, max corners).
pub(crate) type BBox = (DVec2, DVec2);

/// Items per leaf of [`SeqBvh`].
const BVH_LEAF: usize = 8;

/// Bounding-volume hierarchy over boxes kept in sequence order: blocks of `BVH_LEAF`
/// consecutive boxes, then pairs of blocks, up to one root. Consecutive circles of a stroke
/// and consecutive segments of a connected path are spatially close, so the nodes stay
/// tight and a query costs O(log n + hits) whatever the shape's aspect ratio. (An R-tree
/// bulk-loaded with rstar's OMT splitting degrades on long thin strokes, whose boxes it
/// groups poorly; a uniform hash grid suits evenly spread items, not a stroke's chain.)
pub(crate) struct SeqBvh {
    boxes: Vec<BBox>,
    /// `levels[0]` covers leaf blocks; node j of level k covers nodes 2j, 2j+1 of k − 1.
    levels: Vec<Vec<BBox>>,
}

fn union(bs: &[BBox]) -> BBox {
    bs.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), (l, h)| (lo.min(*l), hi.max(*h)),
    )
}

fn overlap(a: &BBox, b: &BBox) -> bool {
    a.0.x <= b.1.x && b.0.x <= a.1.x && a.0.y <= b.1.y && b.0.y <= a.1.y
}

impl SeqBvh {
    pub(crate) fn new(boxes: Vec<BBox>) -> SeqBvh {
        let mut levels = Vec::new();
        let mut cur: Vec<BBox> = boxes.chunks(BVH_LEAF).map(union).collect();
        while cur.len() > 1 {
            let next = cur.chunks(2).map(union).collect();
            levels.push(cur);
            cur = next;
        }
        levels.push(cur);
        SeqBvh { boxes, levels }
    }

    /// Indices (ascending) of the boxes overlapping `q` (closed boxes), appended to `out`.
    pub(crate) fn query(&self, q: &BBox, out: &mut Vec<usize>) {
        let top = self.levels.len() - 1;
        for j in 0..self.levels[top].len() {
            self.visit(top, j, q, out);
        }
    }

    /// Calls `f(i, j)` once for every pair i < j of overlapping boxes (closed boxes), by a
    /// simultaneous descent of the hierarchy against itself: node pairs whose boxes miss are
    /// pruned together, so the whole self-join costs O(n + pairs) on coherent sequences
    /// instead of the n root-to-leaf queries of [`SeqBvh::query`].
    pub(crate) fn overlapping_pairs(&self, mut f: impl FnMut(usize, usize)) {
        let top = self.levels.len() - 1;
        if !self.levels[top].is_empty() {
            self.visit_pair(top, 0, 0, &mut f);
        }
    }

    /// Pairs of boxes under nodes `a` ≤ `b` of level `k` (module order: i < j).
    fn visit_pair(&self, k: usize, a: usize, b: usize, f: &mut impl FnMut(usize, usize)) {
        let level = &self.levels[k];
        if a != b && !overlap(&level[a], &level[b]) {
            return;
        }
        if k == 0 {
            let block = |j: usize| j * BVH_LEAF..((j + 1) * BVH_LEAF).min(self.boxes.len());
            for i in block(a) {
                let start = if a == b { i + 1 } else { block(b).start };
                for j in start..block(b).end {
                    if overlap(&self.boxes[i], &self.boxes[j]) {
                        f(i, j);
                    }
                }
            }
            return;
        }
        let below = self.levels[k - 1].len();
        let kids = |j: usize| 2 * j..(2 * j + 2).min(below);
        for ca in kids(a) {
            for cb in kids(b) {
                if ca <= cb {
                    self.visit_pair(k - 1, ca, cb, f);
                }
            }
        }
    }

    fn visit(&self, k: usize, j: usize, q: &BBox, out: &mut Vec<usize>) {
        if !overlap(&self.levels[k][j], q) {
            return;
        }
        if k == 0 {
            let end = ((j + 1) * BVH_LEAF).min(self.boxes.len());
            out.extend((j * BVH_LEAF..end).filter(|&i| overlap(&self.boxes[i], q)));
        } else {
            for c in [2 * j, 2 * j + 1] {
                if c < self.levels[k - 1].len() {
                    self.visit(k - 1, c, q, out);
                }
            }
        }
    }
}

fn seg_box(s: &PathSeg, tol: f64) -> BBox {
    let (lo, hi) = Piece::of(s).bbox();
    (lo - DVec2::splat(tol), hi + DVec2::splat(tol))
}

/// All intersections of the segments of `path` with each other within `tol`: cubic
/// self-intersections, intersections of non-adjacent segments, and points where adjacent
/// segments (consecutive, and last–first when closed) meet other than at their shared end.
/// Candidate pairs come from a bounding-volume hierarchy of segment boxes (`SeqBvh`).
/// Sorted by segment indices.
pub fn path_self_intersections(path: &Path, tol: f64) -> Vec<PathHit> {
    let segs = &path.segs;
    let mut out = Vec::new();
    for (i, s) in segs.iter().enumerate() {
        if let PathSeg::Cubic(c) = s {
            for hit in cubic_self_intersections(c, tol) {
                out.push(PathHit { a: i, b: i, hit });
            }
        }
    }
    let tree = SeqBvh::new(segs.iter().map(|s| seg_box(s, tol)).collect());
    tree.overlapping_pairs(|i, j| {
        let (s, t) = (&segs[i], &segs[j]);
        let joints = path_joints(path, i, j, tol);
        for hit in pair_hits(s, t, &joints, tol) {
            out.push(PathHit { a: i, b: j, hit });
        }
    });
    // The tree reports candidates in its own order.
    out.sort_by_key(|h| (h.a, h.b));
    out
}

/// The joints of segments `i < j` of `path`: consecutive segments whose ends meet within
/// `tol`, and the last and first of a closed path.
fn path_joints(path: &Path, i: usize, j: usize, tol: f64) -> Vec<Joint> {
    let (s, t) = (&path.segs[i], &path.segs[j]);
    let near = |p: DVec2, q: DVec2| p.distance(q) <= tol;
    let mut joints = Vec::new();
    if j == i + 1 && near(s.end(), t.start()) {
        joints.push(Joint::between(s, 1.0, t, 0.0, tol));
    }
    if path.closed && i == 0 && j + 1 == path.segs.len() && near(t.end(), s.start()) {
        joints.push(Joint::between(s, 0.0, t, 1.0, tol));
    }
    joints
}

/// Whether [`path_self_intersections`] of `path` would find anything in a pair of segments
/// of which at least one is marked in `changed` (or a marked cubic crossing itself): the
/// same pair tests (same order i < j, same joints), stopping at the first hit. Where every
/// pair of unmarked segments is known to be free of hits, this equals
/// `!path_self_intersections(path, tol).is_empty()`.
pub(crate) fn path_self_intersects_changed(path: &Path, tol: f64, changed: &[bool]) -> bool {
    let segs = &path.segs;
    let n = segs.len();
    let marked = |i: usize| changed.get(i).copied().unwrap_or(true);
    for (i, s) in segs.iter().enumerate() {
        if let PathSeg::Cubic(c) = s
            && marked(i)
            && !cubic_self_intersections(c, tol).is_empty()
        {
            return true;
        }
    }
    let tree = SeqBvh::new(segs.iter().map(|s| seg_box(s, tol)).collect());
    let mut near_ones = Vec::new();
    for i in (0..n).filter(|&i| marked(i)) {
        near_ones.clear();
        tree.query(&tree.boxes[i], &mut near_ones);
        for &o in &near_ones {
            // A pair of two marked segments is tested once, from its first segment.
            if o == i || (marked(o) && o < i) {
                continue;
            }
            let (i, j) = (i.min(o), i.max(o));
            let (s, t) = (&segs[i], &segs[j]);
            if !pair_hits(s, t, &path_joints(path, i, j, tol), tol).is_empty() {
                return true;
            }
        }
    }
    false
}

/// All intersections between a segment of `a` and a segment of `b` within `tol`
/// (`PathHit::a` indexes `a`, `PathHit::b` indexes `b`).
pub fn paths_intersections(a: &Path, b: &Path, tol: f64) -> Vec<PathHit> {
    let tree = SeqBvh::new(b.segs.iter().map(|s| seg_box(s, tol)).collect());
    let mut out = Vec::new();
    let mut js = Vec::new();
    for (i, s) in a.segs.iter().enumerate() {
        js.clear();
        tree.query(&seg_box(s, tol), &mut js);
        for &j in &js {
            for hit in pair_hits(s, &b.segs[j], &[], tol) {
                out.push(PathHit { a: i, b: j, hit });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    fn frames(c: &CubicBez) -> Vec<(CubicBez, f64, f64)> {
        // (transformed copy, rotation, scale)
        [(0.0, 1.0), (0.7, 1e-3), (-2.2, 1e4)]
            .iter()
            .map(|&(rot, s)| {
                let q = DVec2::from_angle(rot);
                let f = |p: DVec2| q.rotate(p) * s;
                (CubicBez::new(f(c.p0), f(c.p1), f(c.p2), f(c.p3)), rot, s)
            })
            .collect()
    }

    #[test]
    fn bvh_query_matches_brute_force() {
        // A coherent walk of boxes plus scattered ones; sizes 0 (points) to large.
        let mut boxes = Vec::new();
        let mut p = DVec2::ZERO;
        for i in 0..300 {
            let f = i as f64;
            p += DVec2::new((0.37 * f).cos(), (0.21 * f).sin());
            let h = DVec2::splat(0.5 + 0.4 * (1.3 * f).sin());
            boxes.push((p - h, p + h));
            if i % 7 == 0 {
                let q = DVec2::new((f * 12.9898).sin() * 40.0, (f * 78.233).sin() * 40.0);
                boxes.push((q, q + DVec2::splat(f * 0.01)));
            }
        }
        let bvh = SeqBvh::new(boxes.clone());
        for (k, q) in boxes.iter().enumerate().step_by(5) {
            let q = (q.0 - DVec2::splat(k as f64 * 0.01), q.1);
            let mut got = Vec::new();
            bvh.query(&q, &mut got);
            let want: Vec<usize> = (0..boxes.len())
                .filter(|&i| overlap(&boxes[i], &q))
                .collect();
            assert_eq!(got, want);
        }
        let mut pairs = Vec::new();
        bvh.overlapping_pairs(|i, j| pairs.push((i, j)));
        pairs.sort();
        let brute: Vec<(usize, usize)> = (0..boxes.len())
            .flat_map(|i| (i + 1..boxes.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| overlap(&boxes[i], &boxes[j]))
            .collect();
        assert_eq!(pairs, brute);
        let empty = SeqBvh::new(Vec::new());
        let mut got = Vec::new();
        empty.query(&boxes[0], &mut got);
        assert!(got.is_empty());
        empty.overlapping_pairs(|_, _| panic!("no boxes, no pairs"));
        let one = SeqBvh::new(vec![boxes[0]]);
        one.overlapping_pairs(|_, _| panic!("one box, no pairs"));
    }

    #[test]
    fn planted_crossing_is_found_in_all_frames() {
        // An S-curve and a line crossing it at three known points (roots of a cubic).
        let a = CubicBez::new(v(0.0, 0.0), v(1.0, 2.0), v(2.0, -2.0), v(3.0, 0.0));
        let b = CubicBez::new(v(-1.0, 0.0), v(0.5, 0.0), v(2.5, 0.0), v(4.0, 0.0));
        // y(t) = 6t(1−t)² − 6t²(1−t) = 6t(1−t)(1−2t): zeros at t = 0, ½, 1.
        for (fa, _, s) in frames(&a) {
            let fb = frames(&b).into_iter().find(|x| x.2 == s).unwrap().0;
            let tol = 1e-9 * s;
            let hits = cubic_intersections(&fa, &fb, tol);
            assert_eq!(hits.len(), 3, "{hits:?}");
            for t in [0.0, 0.5, 1.0] {
                let p = fa.eval(t);
                assert!(hits.iter().any(|h| h.point.distance(p) <= 4.0 * tol));
            }
            // Swapped and reversed operands give the same points.
            let back = cubic_intersections(&fb.reversed(), &fa.reversed(), tol);
            assert_eq!(back.len(), 3);
        }
    }

    #[test]
    fn disjoint_curves_are_not_reported() {
        let a = CubicBez::new(v(0.0, 0.0), v(1.0, 2.0), v(2.0, 2.0), v(3.0, 0.0));
        // The same arch lifted by a small gap: never closer than the gap.
        let gap = 1e-6;
        let b = CubicBez::new(
            v(0.0, gap),
            v(1.0, 2.0 + gap),
            v(2.0, 2.0 + gap),
            v(3.0, gap),
        );
        for (fa, rot, s) in frames(&a) {
            let q = DVec2::from_angle(rot);
            let f = |p: DVec2| q.rotate(p) * s;
            let fb = CubicBez::new(f(b.p0), f(b.p1), f(b.p2), f(b.p3));
            assert!(cubic_intersections(&fa, &fb, 1e-9 * s).is_empty());
            // Within tolerance they count as touching (documented conservative behaviour).
            assert!(!cubic_intersections(&fa, &fb, 2e-6 * s).is_empty());
            assert!(cubic_intersections(&fa, &fb, 0.3e-6 * s).is_empty());
        }
    }

    #[test]
    fn tangent_curves_touching_at_one_point() {
        // y = x² − 0 parabola arc and the line y = 0 touch at the origin (tangency).
        let par = CubicBez::new(
            v(-1.0, 1.0),
            v(-1.0 / 3.0, -1.0 / 3.0),
            v(1.0 / 3.0, -1.0 / 3.0),
            v(1.0, 1.0),
        );
        let line = CubicBez::new(v(-1.0, 0.0), v(-0.3, 0.0), v(0.3, 0.0), v(1.0, 0.0));
        let hits = cubic_intersections(&par, &line, 1e-9);
        assert!(!hits.is_empty());
        assert!(hits.iter().all(|h| h.point.length() < 1e-3));
        // Lifted off by 1e-3 (more than 3·tol): no contact.
        let up = CubicBez::new(v(-1.0, -1e-3), v(-0.3, -1e-3), v(0.3, -1e-3), v(1.0, -1e-3));
        assert!(cubic_intersections(&par, &up, 1e-9).is_empty());
    }

    #[test]
    fn work_bound_ends_an_undecidable_search_conservatively() {
        // Two arches 1e-12 apart with a tolerance of 1e-300: no piece ever becomes flat
        // within tol/2 and the boxes of about 2^40 pairs along the curves overlap, so an
        // unbounded subdivision would not end. The budget stops it and reports a hit.
        let a = CubicBez::new(v(0.0, 0.0), v(1.0, 2.0), v(2.0, 2.0), v(3.0, 0.0));
        let d = v(0.0, 1e-12);
        let b = CubicBez::new(a.p0 + d, a.p1 + d, a.p2 + d, a.p3 + d);
        let hits = cubic_intersections(&a, &b, 1e-300);
        assert!(!hits.is_empty());
        // At an ordinary tolerance they are one contact (well within the budget).
        assert!(!cubic_intersections(&a, &b, 1e-9).is_empty());
        let far = CubicBez::new(
            a.p0 + d * 1e9,
            a.p1 + d * 1e9,
            a.p2 + d * 1e9,
            a.p3 + d * 1e9,
        );
        assert!(cubic_intersections(&a, &far, 1e-9).is_empty());
    }

    #[test]
    fn cubic_loop_is_found() {
        // Symmetric loop: control points (0,0), (3,3), (−1,3)... crossing on the axis x = 1.
        let c = CubicBez::new(v(0.0, 0.0), v(3.0, 2.0), v(-1.0, 2.0), v(2.0, 0.0));
        for (fc, _, s) in frames(&c) {
            let hits = cubic_self_intersections(&fc, 1e-9 * s);
            assert_eq!(hits.len(), 1, "{hits:?}");
            // The double point: c(t) = c(1 − t) by symmetry about x = 1.
            let h = hits[0];
            let (t1, t2) = (h.ta.min(h.tb), h.ta.max(h.tb));
            assert!((t1 + t2 - 1.0).abs() < 1e-4, "{t1} {t2}");
            assert!(fc.eval(t1).distance(fc.eval(t2)) <= 1e-6 * s);
        }
        let arch = CubicBez::new(v(0.0, 0.0), v(1.0, 2.0), v(2.0, 2.0), v(3.0, 0.0));
        assert!(cubic_self_intersections(&arch, 1e-9).is_empty());
        // An S with an inflection: no loop.
        let s = CubicBez::new(v(0.0, 0.0), v(1.0, 2.0), v(2.0, -2.0), v(3.0, 0.0));
        assert!(cubic_self_intersections(&s, 1e-9).is_empty());
    }

    #[test]
    fn path_checks_adjacent_and_far_segments() {
        let sq = |pts: &[DVec2], closed: bool| {
            let n = pts.len();
            let m = if closed { n } else { n - 1 };
            Path::new(
                (0..m)
                    .map(|i| PathSeg::Line(Line::new(pts[i], pts[(i + 1) % n])))
                    .collect(),
                closed,
            )
        };
        let square = sq(&[v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)], true);
        assert!(path_self_intersections(&square, 1e-9).is_empty());
        // Bow tie: segments 0 and 2 cross at (0.5, 0.5).
        let bow = sq(&[v(0.0, 0.0), v(1.0, 1.0), v(1.0, 0.0), v(0.0, 1.0)], true);
        let h = path_self_intersections(&bow, 1e-9);
        assert_eq!(h.len(), 1);
        assert_eq!((h[0].a, h[0].b), (0, 2));
        assert!(h[0].hit.point.distance(v(0.5, 0.5)) < 1e-9);
        // A zigzag crossed by its own closing run: many hits, reported in segment order.
        let mut zig: Vec<DVec2> = (0..40)
            .map(|i| v(i as f64, if i % 2 == 0 { 0.0 } else { 1.0 }))
            .collect();
        zig.push(v(39.0, 0.5));
        zig.push(v(-1.0, 0.5));
        let h = path_self_intersections(&sq(&zig, false), 1e-9);
        assert!(h.len() >= 39, "{}", h.len());
        assert!(h.windows(2).all(|w| (w[0].a, w[0].b) <= (w[1].a, w[1].b)));
        // Doubling back: adjacent segments overlap beyond their shared end.
        let back = sq(&[v(0.0, 0.0), v(2.0, 0.0), v(1.0, 0.0)], false);
        assert!(!path_self_intersections(&back, 1e-9).is_empty());
        // A circle as two arcs plus a chord-crossing cubic.
        let a0 = Arc::new(v(0.0, 0.0), 1.0, 0.0, PI);
        let a1 = Arc::new(v(0.0, 0.0), 1.0, PI, PI);
        let disk = Path::new(vec![PathSeg::Arc(a0), PathSeg::Arc(a1)], true);
        assert!(path_self_intersections(&disk, 1e-9).is_empty());
        let through = Path::new(
            vec![PathSeg::Cubic(CubicBez::new(
                v(-2.0, 0.1),
                v(-1.0, 0.1),
                v(1.0, 0.1),
                v(2.0, 0.1),
            ))],
            false,
        );
        let h = paths_intersections(&disk, &through, 1e-9);
        assert_eq!(h.len(), 2, "{h:?}");
        let x = (1.0f64 - 0.01).sqrt();
        assert!(h.iter().any(|p| p.hit.point.distance(v(x, 0.1)) < 1e-8));
        assert!(h.iter().any(|p| p.hit.point.distance(v(-x, 0.1)) < 1e-8));
    }

    /// A closed ring with a sharp concave kink: a line down the y axis to the origin, then an
    /// arc leaving at angle `phi` from the line (turning by 180° − φ), curving back across the
    /// line at `cross` from the kink when `cross` is finite (clockwise arc of radius
    /// cross / (2 sin φ)), else curving away (counter-clockwise), closed by lines.
    fn kinked_ring(phi: f64, cross: Option<f64>, rot: f64, scale: f64, shift: DVec2) -> Path {
        let q = DVec2::from_angle(rot);
        let f = |p: DVec2| q.rotate(p) * scale + shift;
        let dir = v(-phi.sin(), phi.cos()); // leaving the kink
        let arc = match cross {
            // Centre to the right of the leaving direction; the arc re-crosses the y axis
            // after turning by 2φ; run it 0.3 rad further.
            Some(c) => {
                let r = c / (2.0 * phi.sin());
                let centre = v(dir.y, -dir.x) * r;
                let start = (-centre).to_angle();
                Arc::new(f(centre), r * scale, start + rot, -(2.0 * phi + 0.3))
            }
            None => {
                let r = 1.0;
                let centre = v(-dir.y, dir.x) * r;
                let start = (-centre).to_angle();
                Arc::new(f(centre), r * scale, start + rot, 0.5)
            }
        };
        let top = f(v(0.0, 3.0));
        let line = PathSeg::Line(Line::new(top, f(DVec2::ZERO)));
        let end = arc.p1();
        let far = f(v(-3.0, 4.0));
        Path::new(
            vec![
                line,
                PathSeg::Arc(arc),
                PathSeg::Line(Line::new(end, far)),
                PathSeg::Line(Line::new(far, top)),
            ],
            true,
        )
    }

    #[test]
    fn sharp_kinks_are_not_contacts_but_crossings_beyond_them_are() {
        let frames = [
            (0.0, 1.0, DVec2::ZERO),
            (0.7, 1e-2, v(1e4, -5e3)),
            (-2.3, 1e3, v(-3e3, 7e3)),
        ];
        for (rot, scale, shift) in frames {
            let tol = 1e-6 * scale;
            // (φ, crossing distance in units of tol, expect a hit)
            let cases = [
                (13f64.to_radians(), None, false), // neon_open's board corner
                (5f64.to_radians(), None, false),
                (60f64.to_radians(), None, false),
                (13f64.to_radians(), Some(40.0), true), // beyond the zone (17.8·tol)
                (5f64.to_radians(), Some(80.0), true),  // beyond the zone (45.9·tol)
                (2f64.to_radians(), None, true),        // below asin(4/64): doubling back
            ];
            for (phi, cross, want) in cases {
                let ring = kinked_ring(phi, cross.map(|c| c * 1e-6), rot, scale, shift);
                assert!(ring.max_gap() < 1e-9 * scale, "{ring:?}");
                let hits = path_self_intersections(&ring, tol);
                assert_eq!(
                    !hits.is_empty(),
                    want,
                    "φ = {:.1}°, cross {cross:?}, frame {rot} {scale}: {hits:?}",
                    phi.to_degrees()
                );
                if let Some(c) = cross {
                    // The crossing lies on the line, c from the kink.
                    let at = DVec2::from_angle(rot).rotate(v(0.0, c * 1e-6)) * scale + shift;
                    assert!(
                        hits.iter().any(|h| h.hit.point.distance(at) <= 4.0 * tol),
                        "{hits:?} not near {at}"
                    );
                }
            }
        }
    }

    /// Angle between two rays given by their angles, in [0, π].
    fn ray_angle(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(std::f64::consts::TAU);
        d.min(std::f64::consts::TAU - d)
    }

    /// A segment of the given kind (0 line, 1 arc, 2 cubic) ending (`at_end`) or starting
    /// at `j`, leaving it along `dir` (an angle) with length scale `len`, bending by
    /// `bend` (radians, for arcs and cubics).
    fn seg_at(kind: u8, j: DVec2, dir: f64, len: f64, bend: f64, at_end: bool) -> PathSeg {
        let u = DVec2::from_angle(dir);
        let seg = match kind {
            0 => PathSeg::Line(Line::new(j, j + len * u)),
            1 => {
                // Leaves j along u turning by `bend` over the arc (radius from the length).
                let sweep = if bend.abs() < 1e-3 { 1e-3 } else { bend };
                let r = len / sweep.abs();
                let centre = j + r * sweep.signum() * u.perp();
                let start = (j - centre).to_angle();
                PathSeg::Arc(Arc::new(centre, r, start, sweep))
            }
            _ => {
                let w = DVec2::from_angle(dir + bend);
                let p3 = j + len * (0.6 * u + 0.6 * w);
                PathSeg::Cubic(CubicBez::new(j, j + 0.4 * len * u, p3 - 0.3 * len * w, p3))
            }
        };
        if at_end { seg.reversed() } else { seg }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]

        /// The gap of two cones is the smallest angle between sampled rays of each (to the
        /// sampling step), and `None` exactly when the sampled rays meet.
        #[test]
        fn cone_gap_is_the_smallest_ray_angle(
            a in -3.2f64..3.2, alo in -1.5f64..0.0, ahi in 0.0f64..1.5,
            b in -3.2f64..3.2, blo in -1.5f64..0.0, bhi in 0.0f64..1.5,
        ) {
            let cone = |ax: f64, lo: f64, hi: f64| Cone {
                apex: DVec2::ZERO,
                axis: DVec2::from_angle(ax),
                lo,
                hi,
            };
            let (ca, cb) = (cone(a, alo, ahi), cone(b, blo, bhi));
            let n = 200;
            let mut brute = f64::INFINITY;
            for i in 0..=n {
                let ra = a + alo + (ahi - alo) * i as f64 / n as f64;
                for k in 0..=n {
                    let rb = b + blo + (bhi - blo) * k as f64 / n as f64;
                    brute = brute.min(ray_angle(ra, rb));
                }
            }
            let step = 3.0 / n as f64;
            match ca.gap(&cb) {
                Some(g) => proptest::prop_assert!((g - brute).abs() <= step, "{g} {brute}"),
                None => proptest::prop_assert!(brute <= step, "{brute}"),
            }
        }

        /// Settling pairs at a joint by their cones changes nothing: adjacent lines, arcs
        /// and cubics meeting at every angle (G1 continuations, kinks, doubling back), in
        /// three frames, give the same hits as plain bisection down to the joint zone.
        #[test]
        fn joint_cones_give_the_hits_of_plain_bisection(
            ka in 0u8..3, kb in 0u8..3,
            da in -3.2f64..3.2, turn in -3.2f64..3.2,
            la in 0.1f64..3.0, lb in 0.1f64..3.0,
            ba in -2.5f64..2.5, bb in -2.5f64..2.5,
            frame in 0usize..3, ltol in -9i32..-2,
        ) {
            let (scale, shift) = [(1.0, DVec2::ZERO), (1e-2, v(3e3, -1e3)), (1e3, v(-5e4, 2e4))][frame];
            let tol = 10f64.powi(ltol) * scale;
            let j = shift + v(0.3, -0.2) * scale;
            let a = seg_at(ka, j, da, la * scale, ba, true);
            let b = seg_at(kb, j, da + turn, lb * scale, bb, false);
            let joints = [Joint::between(&a, 1.0, &b, 0.0, tol)];
            let fast = pair_hits_with(&a, &b, &joints, tol, true);
            let plain = pair_hits_with(&a, &b, &joints, tol, false);
            proptest::prop_assert_eq!(fast, plain);
        }
    }
}
