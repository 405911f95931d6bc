//! Merged arc output of MAT offsets: the exact offset curves
//! x±d = y + (r + d) m± (re-skinning-cnc eq. 13, trimmed as in [`super::inner_offset`] and
//! [`super::outer_offset`]) as few G1-joined circular arcs as the greedy search finds, each
//! with a deviation from the exact curve bounded by the tolerance.
//!
//! # Hulls of the exact curve
//!
//! Each curve piece is sampled adaptively (points and unit tangents of the exact curve, in
//! the direction of travel). A sample interval from P (tangent Tₐ) to Q (tangent T_b) has a
//! triangle hull when both tangents make an angle below 90° with the chord
//! u = (Q − P)/‖Q − P‖ and lie on opposite sides of it (cross(u, Tₐ)·cross(u, T_b) ≤ 0, no
//! inflection seen at the ends); its apex
//!
//!   X = P + s Tₐ,  s = ‖Q − P‖ sin β / sin(α + β)   (α = ∠(Tₐ, u), β = ∠(u, T_b))
//!
//! is the meeting point of the two end tangents. An interval is kept when X lies at most
//! `tol`/8 from the chord and the sample at the parameter midpoint M passes the same test
//! on both halves with the tangent turning one way from P through M to Q; it is then kept
//! as its two halves (P, M) and (M, Q) with their own, smaller triangles. A convex arc whose
//! tangent turns by less than π lies in the triangle of its chord and its end tangents.
//!
//! An interval that fails these tests but is nearly straight (an inflection, or tangents
//! equal up to rounding) is kept when all three sampled tangents make angles below ψ/2 < π/8
//! with the chord: if the tangent stays within ψ of the chord, the curve lies in the rhombus
//! of P, Q and M' ± (‖Q − P‖/2) tan ψ · n (M' the chord's midpoint, n its normal), whose
//! half-height must be at most `tol`/8. Every other interval is bisected.
//!
//! So under the hypothesis that within each kept interval the curvature keeps its sign
//! (triangles) or the tangent stays within ψ of the chord (rhombi) — checked at three
//! tangents, not proved between them — the whole exact curve lies in the union of the hulls.
//!
//! # The deviation bound of an arc
//!
//! A candidate arc of the circle (C, R) from P to Q with sweep below π bounds the
//! Hausdorff distance between the exact curve from P to Q and the arc by
//!
//!   e = max over the hulls H between P and Q of max( max_{v ∈ vert(H)} ‖v − C‖ − R,
//!                                                   R − dist(C, H) ),
//!
//! provided every hull vertex lies in the sector of the arc (between the rays C→P and C→Q).
//! ‖· − C‖ is convex, so its maximum over a hull is at a vertex and its minimum is the
//! distance from C to the hull (0 when C is inside). Every curve point is then in the
//! sector and within e of the circle, so within e of the arc; conversely the curve is
//! connected from the ray through P to the ray through Q inside the sector's band of width
//! 2e around the circle, so it crosses every ray in between, at a point within e of the arc
//! point on that ray. A line (in place of an arc whose sagitta is below `tol`·1e-4) is
//! bounded by the largest distance of a hull vertex to the segment (a convex function);
//! the other direction follows as for arcs, up to the angle (below 4·10⁻⁴ `tol`/length)
//! between the line and the arc it replaces. Rounding is not accounted for (its relative
//! size is 1e-15).
//!
//! # Merging
//!
//! Within a run of pieces where the exact curve is G1 (pieces that meet with equal
//! tangents: segment joins of the skin), the chain is built greedily from the current
//! sample: the biarc (two arcs with a common tangent at their joint, equal tangent lengths)
//! from the current sample to a later one, tangent to the exact curve at both, is bounded
//! arc by arc as above after splitting each hull by the arcs' common normal line at the
//! joint (each arc lies on its own side of that line, and the line is the ray from either
//! centre through the joint). The farthest sample whose biarc is within `tol` is found by
//! galloping and then binary search on the sample index (first trying the previous biarc's
//! reach), run on the samples alone (a sample farther than `tol` from the biarc makes the
//! bound exceed `tol`); the hulls are then bounded for the biarc found, and the search
//! repeated below it with the bound only when that fails. So each biarc replaces as many
//! osculating-circle pieces as the tolerance allows; consecutive arcs of one circle are
//! merged into one. Every joint is G1: between the two arcs of a biarc by construction,
//! between biarcs and at the cap arcs because each biarc ends with the exact curve's
//! tangent. Runs break only at corners of the offset (trim points r = δ, cut loops); the cap
//! arcs are kept as they are (they are exact).

use super::{MatOffset, MatOffsetError, Piece};
use crate::geom::hull::{arc_hull_bound, segment_hull_bound};
use crate::geom::{Arc, DVec2, Line, Path, PathSeg, cross, perp};
use crate::skin::re::Branch;

/// Below this |2(t₀·t₁ − 1)| the biarc's quadratic in d degenerates (parallel unit tangents)
/// and its linear root is taken.
const PARALLEL_TANGENTS: f64 = 1e-12;

/// Two arcs lie on one circle when centres and radii agree within this fraction of the
/// radius (their union is one arc).
const SAME_CIRCLE_REL: f64 = 1e-12;

/// Margin (radians) added to the doubled turning angle before it is compared with π/4, so
/// round-off does not decide the comparison.
const ANGLE_MARGIN: f64 = 1e-12;

/// Two nodes meet at a joint when their points agree within this fraction of the distance
/// from the origin (plus one model unit).
const G1_JOINT_REL: f64 = 1e-9;

/// Equal parameter parts of every piece before the adaptive sampling.
const MIN_PARTS: usize = 4;
/// Deepest bisection of a sample interval (2^-MAX_DEPTH of a part): an interval that is
/// still not accepted there (singular points) is unproved and becomes a chord.
const MAX_DEPTH: u32 = 24;
/// Largest distance of a hull's apex from its chord, as a fraction of the tolerance.
const APEX_FRACTION: f64 = 0.125;
/// A line replaces an arc whose sagitta is below this fraction of the tolerance.
const STRAIGHT_FRACTION: f64 = 1e-4;
/// Pieces meet G1 when their tangents differ by less than this angle (radians) and their
/// points by less than this fraction of the point's magnitude (plus one).
const G1_ANGLE: f64 = 1e-7;
/// Tangent angles (sines) below this are rounding: an interval whose end tangents are both
/// within it of the chord is taken as the chord, and a turn this small is no inflection.
const FLAT_SIN: f64 = 1e-12;
/// Relative margin of the early rejection of a rhombus hull ([`flat_hull`]), far above the
/// rounding of the angles it skips.
const FLAT_REJECT_MARGIN: f64 = 1e-9;
/// Most samples per piece: beyond, intervals are no longer bisected but unproved (bounds the
/// work on user data whatever the tolerance).
const MAX_NODES: usize = 1 << 18;
/// Relative rounding slack of the sector and segment containment tests.
const CONTAIN_EPS: f64 = 1e-9;

/// A sample of the exact curve: point and unit tangent in the direction of travel (`None`
/// where the speed is zero or not finite).
#[derive(Clone, Copy, Debug)]
struct Node {
    p: DVec2,
    d: Option<DVec2>,
}

/// What is known of the curve between two consecutive samples.
#[derive(Clone, Copy, Debug)]
enum Hull {
    /// The curve is the chord (both tangents along it).
    Seg,
    /// The curve lies in the triangle of the chord and this apex.
    Tri(DVec2),
    /// The curve lies in the rhombus of the chord's ends and these two vertices (a nearly
    /// straight interval, possibly with an inflection).
    Quad(DVec2, DVec2),
    /// Nothing proved (bisection depth reached, or a singular point): emitted as a chord.
    Unproved,
}

/// Result of [`MatOffset::to_merged_arc_paths`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MergedArcs {
    /// Closed paths of arcs and lines, one per contour.
    pub paths: Vec<Path>,
    /// Largest deviation bound (module docs) over the emitted arcs and lines (model units);
    /// cap arcs are exact and count 0.
    pub bound: f64,
    /// Chords emitted over unproved sample intervals (their deviation is not bounded).
    pub unproved: usize,
    /// Samples of the exact curves taken.
    pub samples: usize,
}

/// The hull of the interval between `a` and `b`, or `None` when the end tangents do not
/// show a convex arc turning by less than π (the interval must be refined).
fn hull(a: &Node, b: &Node) -> Option<Hull> {
    let v = b.p - a.p;
    let l = v.length();
    if l == 0.0 || !l.is_finite() {
        return Some(Hull::Seg);
    }
    let u = v / l;
    let (da, db) = (a.d?, b.d?);
    let (sa, ca) = (cross(u, da), u.dot(da));
    let (sb, cb) = (cross(u, db), u.dot(db));
    if ca <= 0.0 || cb <= 0.0 {
        return None;
    }
    if sa.abs() <= FLAT_SIN && sb.abs() <= FLAT_SIN {
        return Some(Hull::Seg);
    }
    if sa * sb > 0.0 {
        return None;
    }
    // With unit vectors sin α = |sa|, cos α = ca (likewise β), so
    // sin(α + β) = |sa| cb + ca |sb|.
    let s = l * sb.abs() / (sa.abs() * cb + ca * sb.abs());
    let x = a.p + s * da;
    x.is_finite().then_some(Hull::Tri(x))
}

/// Distance of the hull's apex from its chord (0 for a segment).
fn apex_height(a: &Node, b: &Node, h: &Hull) -> f64 {
    match h {
        Hull::Quad(x, _) | Hull::Tri(x) => {
            let v = b.p - a.p;
            let l = v.length();
            if l > 0.0 {
                cross(v / l, *x - a.p).abs()
            } else {
                0.0
            }
        }
        _ => 0.0,
    }
}

/// The vertices of interval `k`'s hull.
fn hull_verts(nodes: &[Node], hulls: &[Hull], k: usize) -> Option<([DVec2; 4], usize)> {
    let (a, b) = (nodes.get(k)?.p, nodes.get(k + 1)?.p);
    match hulls.get(k)? {
        Hull::Seg => Some(([a, b, b, b], 2)),
        Hull::Tri(x) => Some(([a, *x, b, b], 3)),
        Hull::Quad(x, y) => Some(([a, *x, b, *y], 4)),
        Hull::Unproved => None,
    }
}

/// A circular arc (centre `c`, radius `r`, turning counter-clockwise when `sig` > 0) or a
/// line from `p` to `q`, with its unit end tangent.
#[derive(Clone, Copy, Debug)]
struct Shape {
    p: DVec2,
    q: DVec2,
    d_end: DVec2,
    circle: Option<(DVec2, f64, f64)>,
}

impl Shape {
    fn seg(&self) -> PathSeg {
        match self.circle {
            Some((c, _, sig)) => {
                PathSeg::Arc(Arc::from_center_points(c, self.p, self.q, sig > 0.0))
            }
            None => PathSeg::Line(Line::new(self.p, self.q)),
        }
    }
}

/// The arc leaving `p` with unit tangent `d` and ending at `q` (sweep below π), or the line p q when the arc's sagitta (‖q − p‖/2)·tan(φ/2), φ = ∠(d, q − p),
/// is at most `tol`·STRAIGHT_FRACTION (the line's start tangent then differs from `d` by φ).
fn arc_from(p: DVec2, d: DVec2, q: DVec2, tol: f64) -> Option<Shape> {
    let v = q - p;
    let l2 = v.length_squared();
    let l = l2.sqrt();
    if l == 0.0 || !l.is_finite() || d.dot(v) <= 0.0 {
        return None;
    }
    let u = v / l;
    let h = perp(d).dot(v);
    // With d a unit vector, sin φ = |h|/l and cos φ = d·v/l, so
    // tan(φ/2) = sin φ / (1 + cos φ) = |h| / (l + d·v).
    if 0.5 * l * h.abs() / (l + d.dot(v)) <= STRAIGHT_FRACTION * tol {
        return Some(Shape {
            p,
            q,
            d_end: u,
            circle: None,
        });
    }
    let rs = l2 / (2.0 * h);
    let c = p + rs * perp(d);
    let r = rs.abs();
    if !(c.is_finite() && r > 0.0) {
        return None;
    }
    Some(Shape {
        p,
        q,
        d_end: 2.0 * d.dot(u) * u - d,
        circle: Some((c, r, h.signum())),
    })
}

/// The deviation bound (module docs) of the convex polygon `verts` (a part of the curve's
/// hull) against `sh` ([`arc_hull_bound`], [`segment_hull_bound`]): `None` when a vertex
/// lies outside the arc's sector.
fn poly_bound(sh: &Shape, verts: &[DVec2]) -> Option<f64> {
    match sh.circle {
        Some((c, r, sig)) => arc_hull_bound(c, r, sh.p, sh.q, sig > 0.0, verts, CONTAIN_EPS),
        None => Some(segment_hull_bound(&Line::new(sh.p, sh.q), verts)),
    }
}

/// The part of the convex polygon `verts` where (x − j)·t ≤ 0 (`behind`) or ≥ 0.
fn clip(verts: &[DVec2], j: DVec2, t: DVec2, behind: bool) -> ([DVec2; 6], usize) {
    // A convex polygon of at most 4 vertices clipped by a half-plane has at most 5.
    let s = if behind { -1.0 } else { 1.0 };
    let side = |x: DVec2| s * (x - j).dot(t);
    let mut out = [DVec2::ZERO; 6];
    let mut n = 0;
    let m = verts.len();
    for k in 0..m {
        let (a, b) = (verts[k], verts[(k + 1) % m]);
        let (sa, sb) = (side(a), side(b));
        if sa >= 0.0 && n < 6 {
            out[n] = a;
            n += 1;
        }
        if (sa >= 0.0) != (sb >= 0.0) && n < 6 {
            out[n] = a + (b - a) * (sa / (sa - sb));
            n += 1;
        }
    }
    (out, n)
}

/// The biarc (module docs: equal tangent lengths) from `nodes[i]` to `nodes[j]`, tangent to
/// the exact curve at both ends, with its joint J and the unit tangent there, when every
/// sample between lies within `tol` of it ([`nodes_within`], a necessary condition of
/// [`biarc_bound`]).
fn biarc_near(nodes: &[Node], i: usize, j: usize, tol: f64) -> Option<Biarc> {
    let (a, b) = (nodes.get(i)?, nodes.get(j)?);
    let (p0, t0, p1, t1) = (a.p, a.d?, b.p, b.d?);
    let v = p1 - p0;
    let vv = v.length_squared();
    let vt = v.dot(t0 + t1);
    let qa = 2.0 * (t0.dot(t1) - 1.0);
    // ‖v‖² − 2d v·(t0 + t1) + 2d²(t0·t1 − 1) = 0: the positive root.
    let d = if qa.abs() < PARALLEL_TANGENTS {
        vv / (2.0 * vt)
    } else {
        (vt - (vt * vt - qa * vv).max(0.0).sqrt()) / qa
    };
    if !(d.is_finite() && d > 0.0) {
        return None;
    }
    let jt = 0.5 * (p0 + d * t0 + p1 - d * t1);
    let first = arc_from(p0, t0, jt, tol)?;
    let second = arc_from(jt, first.d_end, p1, tol)?;
    let tj = first.d_end;
    if !nodes_within(nodes.get(i..=j)?, &first, &second, jt, tj, tol) {
        return None;
    }
    Some(([first, second], jt, tj))
}

/// A biarc of [`biarc_near`]: its two arcs, its joint J and the unit tangent there.
type Biarc = ([Shape; 2], DVec2, DVec2);

/// The deviation bound of `biarc` (from `nodes[i]` to `nodes[j]`, [`biarc_near`]) against
/// the hulls between, when it is ≤ `tol`.
///
/// The joint J splits the plane by the common normal line of the two arcs: the first arc
/// lies where (x − J)·t_J ≤ 0, the second where it is ≥ 0, so each hull is clipped by
/// these half-planes and each part bounded against its own arc; the ray from each centre
/// through J is that line, so the sector tests of the two arcs meet there.
fn biarc_bound(
    nodes: &[Node],
    hulls: &[Hull],
    i: usize,
    j: usize,
    biarc: &Biarc,
    tol: f64,
) -> Option<f64> {
    let ([first, second], jt, tj) = biarc;
    let (jt, tj) = (*jt, *tj);
    let mut bound: f64 = 0.0;
    for k in i..j {
        let (vs, n) = hull_verts(nodes, hulls, k)?;
        let verts = &vs[..n];
        // A hull strictly on one side of the joint's line is its own part there (what
        // `clip` returns for it) and has no part on the other side.
        let (mut behind, mut ahead) = (true, true);
        for v in verts {
            let s = (*v - jt).dot(tj);
            behind &= s < 0.0;
            ahead &= s > 0.0;
        }
        if behind || ahead {
            let sh = if behind { &first } else { &second };
            bound = bound.max(poly_bound(sh, verts)?);
        } else {
            for (sh, behind) in [(&first, true), (&second, false)] {
                let (part, m) = clip(verts, jt, tj, behind);
                if m > 0 {
                    bound = bound.max(poly_bound(sh, &part[..m])?);
                }
            }
        }
        if bound > tol {
            return None;
        }
    }
    Some(bound)
}

/// Whether every sample point lies within `tol` of the biarc (`first` where
/// (x − J)·t_J ≤ 0, `second` elsewhere, as `clip` splits the hulls): a cheap necessary
/// condition of [`biarc_bound`]. Each sample is a vertex of a hull part bounded
/// against that arc, and the part's bound is at least the sample's distance to the circle
/// (max_v ‖v − C‖ − R on one side, R − dist(C, hull) ≥ R − ‖x − C‖ on the other) or to
/// the line; so a sample farther than `tol` rejects the candidate before any hull is
/// bounded.
fn nodes_within(
    nodes: &[Node],
    first: &Shape,
    second: &Shape,
    jt: DVec2,
    tj: DVec2,
    tol: f64,
) -> bool {
    nodes.iter().all(|n| {
        let sh = if (n.p - jt).dot(tj) <= 0.0 {
            first
        } else {
            second
        };
        let dev = match sh.circle {
            Some((c, r, _)) => ((n.p - c).length_squared().sqrt() - r).abs(),
            None => Line::new(sh.p, sh.q).distance(n.p),
        };
        dev <= tol
    })
}

/// Appends `sh`'s segment, merged with the previous arc when both lie on one circle (the
/// union of two arcs of one circle meeting end to start is one arc with the summed sweep).
fn push_merged(out: &mut Vec<PathSeg>, sh: &Shape) {
    let seg = sh.seg();
    if let (Some(PathSeg::Arc(prev)), PathSeg::Arc(a)) = (out.last(), &seg) {
        let same = prev.center.distance(a.center) <= SAME_CIRCLE_REL * (1.0 + a.radius)
            && (prev.radius - a.radius).abs() <= SAME_CIRCLE_REL * a.radius
            && prev.sweep * a.sweep > 0.0
            && (prev.sweep + a.sweep).abs() < std::f64::consts::PI;
        if same {
            let merged = Arc::new(prev.center, prev.radius, prev.start, prev.sweep + a.sweep);
            if let Some(last) = out.last_mut() {
                *last = PathSeg::Arc(merged);
            }
            return;
        }
    }
    out.push(seg);
}

/// Adaptive sampling of one exact piece (module docs): appends the samples after `n0`
/// (which the caller has pushed) and the hull of every interval.
#[allow(clippy::too_many_arguments)]
fn refine(
    ev: &dyn Fn(f64) -> Option<Node>,
    u0: f64,
    n0: Node,
    u1: f64,
    n1: Node,
    budget: f64,
    depth: u32,
    nodes: &mut Vec<Node>,
    hulls: &mut Vec<Hull>,
) {
    let um = 0.5 * (u0 + u1);
    let nm = ev(um);
    if let (Some(h), Some(nm)) = (hull(&n0, &n1), nm)
        && apex_height(&n0, &n1, &h) <= budget
        && let (Some(h0), Some(h1)) = (hull(&n0, &nm), hull(&nm, &n1))
        && monotone(&n0, &nm, &n1)
    {
        hulls.extend([h0, h1]);
        nodes.extend([nm, n1]);
        return;
    }
    if let Some(nm) = nm
        && let Some(h) = flat_hull(&n0, &nm, &n1, budget)
    {
        hulls.push(h);
        nodes.push(n1);
        return;
    }
    match nm {
        Some(nm) if depth < MAX_DEPTH && nodes.len() < MAX_NODES => {
            refine(ev, u0, n0, um, nm, budget, depth + 1, nodes, hulls);
            refine(ev, um, nm, u1, n1, budget, depth + 1, nodes, hulls);
        }
        _ => {
            hulls.push(Hull::Unproved);
            nodes.push(n1);
        }
    }
}

/// The rhombus hull (module docs) of a nearly straight interval from `a` through `m` to
/// `b`: ψ is twice the largest angle of the three sampled tangents with the chord; the
/// curve, whose tangent is assumed to stay within ψ of the chord, lies in the rhombus
/// between the lines through both ends at angles ±ψ, of half-height (‖b − a‖/2)·tan ψ,
/// which must be at most `budget`.
fn flat_hull(a: &Node, m: &Node, b: &Node, budget: f64) -> Option<Hull> {
    let v = b.p - a.p;
    let l = v.length();
    if l == 0.0 || !l.is_finite() {
        return None;
    }
    let u = v / l;
    let ds = [a.d?, m.d?, b.d?];
    // tan ψ ≥ tan 2θ ≥ 2 |sin θ| for each tangent's angle θ with the chord, so the
    // half-height is at least l·|sin θ|: a tangent that already makes it exceed the
    // budget (with a margin far above rounding) rejects the interval without the angles.
    if ds
        .iter()
        .any(|d| l * cross(u, *d).abs() > budget * (1.0 + FLAT_REJECT_MARGIN))
    {
        return None;
    }
    let mut psi: f64 = 0.0;
    for d in ds {
        if u.dot(d) <= 0.0 {
            return None;
        }
        psi = psi.max(cross(u, d).atan2(u.dot(d)).abs());
    }
    let psi = 2.0 * psi + ANGLE_MARGIN;
    if psi >= std::f64::consts::FRAC_PI_4 {
        return None;
    }
    let h = 0.5 * l * psi.tan();
    if h > budget {
        return None;
    }
    let mid = a.p + 0.5 * v;
    let n = perp(u);
    Some(Hull::Quad(mid + h * n, mid - h * n))
}

/// Whether the tangent turns one way from `a` through `m` to `b` (no inflection seen at
/// the midpoint sample).
fn monotone(a: &Node, m: &Node, b: &Node) -> bool {
    match (a.d, m.d, b.d) {
        (Some(x), Some(y), Some(z)) => {
            let (c0, c1) = (cross(x, y), cross(y, z));
            c0 * c1 >= 0.0 || c0.abs() <= FLAT_SIN || c1.abs() <= FLAT_SIN
        }
        _ => false,
    }
}

/// A run of G1-joined samples, or a cap arc.
enum Elem {
    Run(Vec<Node>, Vec<Hull>),
    Cap(Arc),
}

fn g1(a: &Node, b: &Node) -> bool {
    let close = a.p.distance(b.p) <= G1_JOINT_REL * (1.0 + a.p.length());
    match (a.d, b.d) {
        (Some(x), Some(y)) => close && x.dot(y) > 0.0 && cross(x, y).abs() <= G1_ANGLE,
        _ => false,
    }
}

impl MatOffset {
    /// Samples of piece (segment, branch, t0 → t1) into `nodes`/`hulls` (module docs).
    #[allow(clippy::too_many_arguments)]
    fn sample_piece(
        &self,
        s: usize,
        b: Branch,
        t0: f64,
        t1: f64,
        tol: f64,
        nodes: &mut Vec<Node>,
        hulls: &mut Vec<Hull>,
    ) {
        let sign = if t1 < t0 { -1.0 } else { 1.0 };
        let ev = |u: f64| -> Option<Node> {
            let (p, d) = self.curve_point(s, b, t0 + u * (t1 - t0))?;
            let len = d.length();
            p.is_finite().then(|| Node {
                p,
                d: (len > 0.0 && len.is_finite()).then(|| sign * d / len),
            })
        };
        let Some(first) = ev(0.0) else { return };
        nodes.push(first);
        let (mut u_prev, mut n_prev) = (0.0, first);
        for k in 1..=MIN_PARTS {
            let u = k as f64 / MIN_PARTS as f64;
            let Some(n) = ev(u) else { continue };
            refine(
                &ev,
                u_prev,
                n_prev,
                u,
                n,
                APEX_FRACTION * tol,
                0,
                nodes,
                hulls,
            );
            (u_prev, n_prev) = (u, n);
        }
    }

    /// The runs and caps of every contour.
    fn elements(&self, tol: f64) -> Vec<Vec<Elem>> {
        self.contours
            .iter()
            .map(|c| {
                let mut out: Vec<Elem> = Vec::new();
                let mut run: (Vec<Node>, Vec<Hull>) = (Vec::new(), Vec::new());
                for p in &c.pieces {
                    match *p {
                        Piece::Arc(a) => {
                            if !run.0.is_empty() {
                                out.push(Elem::Run(
                                    std::mem::take(&mut run.0),
                                    std::mem::take(&mut run.1),
                                ));
                            }
                            if a.radius > 0.0 && a.sweep != 0.0 {
                                out.push(Elem::Cap(a));
                            }
                        }
                        Piece::Curve {
                            segment,
                            branch,
                            t0,
                            t1,
                        } => {
                            if t0 == t1 {
                                continue;
                            }
                            let (mut ns, mut hs) = (Vec::new(), Vec::new());
                            self.sample_piece(segment, branch, t0, t1, tol, &mut ns, &mut hs);
                            if ns.len() < 2 {
                                continue;
                            }
                            let joins = run.0.last().is_some_and(|l| g1(l, &ns[0]));
                            if joins {
                                run.0.pop();
                            } else if !run.0.is_empty() {
                                out.push(Elem::Run(
                                    std::mem::take(&mut run.0),
                                    std::mem::take(&mut run.1),
                                ));
                            }
                            run.0.extend(ns);
                            run.1.extend(hs);
                        }
                    }
                }
                if !run.0.is_empty() {
                    out.push(Elem::Run(run.0, run.1));
                }
                out
            })
            .collect()
    }

    /// The contours as closed paths of as few G1-joined arcs (and lines where straight) as
    /// the greedy merging finds, each within `tol` of the exact offset curve by the bound
    /// of the module docs (re-skinning-cnc eq. 13 for the curve; the cap arcs kept exact).
    /// `tol` must be finite and positive.
    pub fn to_merged_arc_paths(&self, tol: f64) -> Result<MergedArcs, MatOffsetError> {
        super::check_tolerance(tol)?;
        let mut res = MergedArcs::default();
        for elems in self.elements(tol) {
            let mut segs: Vec<PathSeg> = Vec::new();
            for e in elems {
                match e {
                    Elem::Cap(a) => segs.push(PathSeg::Arc(a)),
                    Elem::Run(nodes, hulls) => {
                        res.samples += nodes.len();
                        merge_run(&nodes, &hulls, tol, &mut segs, &mut res);
                    }
                }
            }
            crate::geom::path::close_line_gaps(&mut segs);
            if !segs.is_empty() {
                res.paths.push(Path::new(segs, true));
            }
        }
        Ok(res)
    }
}

/// The largest j in (i, n] for which `f(j)` succeeds, with its result, searched by trying
/// i + `hint` first, then galloping and binary search (success is assumed to shrink with
/// j); `None` when `f(i + 1)` fails.
fn farthest<T>(
    i: usize,
    n: usize,
    hint: usize,
    mut f: impl FnMut(usize) -> Option<T>,
) -> Option<(usize, T)> {
    let mut best = f(i + 1)?;
    let (mut lo, mut hi) = (i + 1, n + 1);
    let guess = (i + hint).min(n);
    if guess > lo {
        match f(guess) {
            Some(c) => {
                lo = guess;
                best = c;
            }
            None => hi = guess,
        }
    }
    let mut step = hint.max(1);
    while hi == n + 1 && lo < n {
        let j = (lo + step).min(n);
        match f(j) {
            Some(c) => {
                lo = j;
                best = c;
                step *= 2;
            }
            None => hi = j,
        }
    }
    while hi - lo > 1 {
        let m = lo + (hi - lo) / 2;
        match f(m) {
            Some(c) => {
                lo = m;
                best = c;
            }
            None => hi = m,
        }
    }
    Some((lo, best))
}

/// The biarc from `nodes[i]` reaching farthest (to j ≤ `n`) within `tol` by its bound
/// ([`biarc_bound`]), with j; `hint` is the previous biarc's reach.
///
/// The search runs on the samples alone first ([`biarc_near`]: a biarc whose samples are
/// not all within `tol` cannot pass the bound), so the hulls are bounded only for the
/// biarc found there, and for shorter ones only when that bound fails: where the samples
/// are dense against `tol` (hull apexes within `tol`/8 of their chords) the two searches
/// end at the same sample or one apart.
fn farthest_biarc(
    nodes: &[Node],
    hulls: &[Hull],
    i: usize,
    n: usize,
    hint: usize,
    tol: f64,
) -> Option<(usize, ([Shape; 2], f64))> {
    let bounded =
        |j: usize, b: Biarc| biarc_bound(nodes, hulls, i, j, &b, tol).map(|bound| (b.0, bound));
    let (near, found) = farthest(i, n, hint, |j| biarc_near(nodes, i, j, tol))?;
    match bounded(near, found) {
        Some(c) => Some((near, c)),
        None if near > i + 1 => farthest(i, near - 1, near - 1 - i, |j| {
            bounded(j, biarc_near(nodes, i, j, tol)?)
        }),
        None => None,
    }
}

/// Greedy merging of one run (module docs).
fn merge_run(
    nodes: &[Node],
    hulls: &[Hull],
    tol: f64,
    out: &mut Vec<PathSeg>,
    res: &mut MergedArcs,
) {
    let n = nodes.len().saturating_sub(1).min(hulls.len());
    let mut i = 0;
    let mut hint = 1;
    while i < n {
        let Some((j, (shapes, bound))) = farthest_biarc(nodes, hulls, i, n, hint, tol) else {
            // A chord over one interval: within tol/8 of a proved hull (APEX_FRACTION),
            // unbounded over an unproved one.
            let (a, b) = (nodes[i], nodes[i + 1]);
            match hulls[i] {
                Hull::Unproved => res.unproved += 1,
                h => res.bound = res.bound.max(apex_height(&a, &b, &h)),
            }
            out.push(PathSeg::Line(Line::new(a.p, b.p)));
            i += 1;
            continue;
        };
        res.bound = res.bound.max(bound);
        for sh in &shapes {
            push_merged(out, sh);
        }
        hint = j - i;
        i = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Circle;
    use crate::skin::mat_offset::tests::gentle;
    use crate::skin::mat_offset::{inner_offset, outer_offset, outline};
    use crate::skin::re::skin::tests::{test_touches, transform};
    use crate::skin::re::{Interp, ReSkin};
    use proptest::prelude::*;

    fn seg_dist(s: &PathSeg, p: DVec2) -> f64 {
        match s {
            PathSeg::Line(l) => l.distance(p),
            PathSeg::Arc(a) => a.distance(p),
            PathSeg::Cubic(_) => f64::INFINITY,
        }
    }

    /// Dense samples of every exact piece (independent of the hulls): per piece its
    /// bounding box and its points.
    fn dense(off: &MatOffset, per_piece: usize) -> Vec<(DVec2, DVec2, Vec<DVec2>)> {
        let mut v = Vec::new();
        for c in &off.contours {
            for p in &c.pieces {
                if matches!(p, Piece::Arc(a) if a.radius <= 0.0 || a.sweep == 0.0) {
                    continue;
                }
                let pts: Vec<DVec2> = (0..=per_piece)
                    .filter_map(|k| off.piece_point(p, k as f64 / per_piece as f64))
                    .collect();
                let lo = pts
                    .iter()
                    .fold(DVec2::splat(f64::INFINITY), |m, q| m.min(*q));
                let hi = pts
                    .iter()
                    .fold(DVec2::splat(f64::NEG_INFINITY), |m, q| m.max(*q));
                v.push((lo, hi, pts));
            }
        }
        v
    }

    /// Distance from `q` to the dense exact polylines (pieces whose box is farther than
    /// the best distance so far are skipped).
    fn to_exact(ex: &[(DVec2, DVec2, Vec<DVec2>)], q: DVec2) -> f64 {
        let mut best = f64::INFINITY;
        for (lo, hi, pts) in ex {
            let out = (*lo - q).max(q - *hi).max(DVec2::ZERO).length();
            if out >= best {
                continue;
            }
            for w in pts.windows(2) {
                best = best.min(Line::new(w[0], w[1]).distance(q));
            }
        }
        best
    }

    /// Checks merged arcs of `off` at `tol` against the exact curve both ways (dense
    /// samples), their continuity, and their count against the unmerged G1 fit (the
    /// bisected biarcs the MAT route emitted before); returns (merged, 3-point arcs,
    /// biarcs) counts (3-point arcs are not G1 and may be fewer).
    fn check(off: &MatOffset, tol: f64, scale: f64) -> (usize, usize, usize) {
        let m = off.to_merged_arc_paths(tol).unwrap();
        assert_eq!(m.unproved, 0, "unproved intervals");
        assert!(m.bound <= tol, "bound {} > {tol}", m.bound);
        assert_eq!(m.paths.len(), off.contours.len());
        // Sagitta of the dense polyline's chords: well below tol at 2000 samples per piece.
        let ex = dense(off, 2000);
        let slack = 1e-3 * tol + 1e-9 * scale;
        for path in &m.paths {
            assert!(path.max_gap() < 1e-9 * scale, "gap {}", path.max_gap());
            // Path → exact curve.
            for s in &path.segs {
                for k in 0..=16 {
                    let q = s.eval(k as f64 / 16.0);
                    let d = to_exact(&ex, q);
                    assert!(
                        d <= tol + slack,
                        "path point {q} (k = {k} of {s:?}) is {d} from the exact curve, d = {}",
                        off.d
                    );
                }
            }
        }
        // Exact curve → path.
        let all: Vec<&PathSeg> = m.paths.iter().flat_map(|p| &p.segs).collect();
        for (_, _, pts) in &ex {
            for q in pts.iter().step_by(4) {
                let d = all
                    .iter()
                    .map(|s| seg_dist(s, *q))
                    .fold(f64::INFINITY, f64::min);
                assert!(d <= tol + slack, "exact point {q} is {d} from the arcs");
            }
        }
        // G1 inside the chain: consecutive arcs (not caps) meet with equal tangents except
        // at the corners of the offset and the ends of runs.
        let merged: usize = m.paths.iter().map(|p| p.segs.len()).sum();
        let arcs3: usize = off
            .to_arc_paths(tol)
            .unwrap()
            .iter()
            .map(|p| p.segs.len())
            .sum();
        let biarcs: usize = crate::toolpath::re_route::biarc_paths(off, tol)
            .unwrap()
            .iter()
            .map(|p| p.segs.len())
            .sum();
        // Where some sample interval stays unproved the MAT route keeps the biarc fit
        // (toolpath::re_route::mat_profile), so the count is compared on tangent-continuous output.
        assert!(
            m.unproved > 0 || merged <= biarcs,
            "{merged} merged vs {biarcs} biarcs ({} unproved, {} samples, d = {}, tol {tol})",
            m.unproved,
            m.samples,
            off.d
        );
        (merged, arcs3, biarcs)
    }

    #[test]
    fn merged_arcs_are_within_tolerance_and_fewer() {
        for (rot, scale, rev) in [(0.0, 1.0, false), (1.1, 2.5, true)] {
            for interp in [Interp::Cubic, Interp::PhQuintic] {
                let cs = transform(&gentle(), rot, scale, DVec2::new(-2.0, 7.0), rev);
                let skin =
                    ReSkin::build(&cs, &test_touches(&cs, &[]), false, interp, 1e-9).unwrap();
                for tol in [1e-2 * scale, 1e-3 * scale] {
                    let offs = [
                        outline(&skin).unwrap(),
                        inner_offset(&skin, 0.6 * scale, 1e-12).unwrap(),
                        inner_offset(&skin, 0.2 * scale, 1e-12).unwrap(),
                        outer_offset(&skin, 0.3 * scale, 1e-12).unwrap(),
                        outer_offset(&skin, 1.5 * scale, 1e-12).unwrap(),
                    ];
                    for off in &offs {
                        check(off, tol, scale);
                    }
                }
            }
        }
    }

    /// The cubic RE skin of the `gentle` circles.
    fn gentle_skin() -> ReSkin {
        ReSkin::build(
            &gentle(),
            &test_touches(&gentle(), &[]),
            false,
            Interp::Cubic,
            1e-9,
        )
        .unwrap()
    }

    #[test]
    fn merged_arcs_are_g1_where_the_offset_is() {
        let skin = gentle_skin();
        let tangent = |s: &PathSeg, t: f64| match s {
            PathSeg::Arc(a) => a.tangent(t),
            PathSeg::Line(l) => (l.p1 - l.p0).normalize(),
            PathSeg::Cubic(_) => DVec2::ZERO,
        };
        // Offsets without corners (no trim point, no cut loop): every joint of the chain,
        // the cap joins included, is G1 to rounding.
        let offs = [
            outline(&skin).unwrap(),
            inner_offset(&skin, 0.2, 1e-12).unwrap(),
            outer_offset(&skin, 0.2, 1e-12).unwrap(),
        ];
        for off in &offs {
            assert!(off.trims.is_empty() && off.loops.is_empty());
            for tol in [1e-2, 1e-3] {
                let m = off.to_merged_arc_paths(tol).unwrap();
                for path in &m.paths {
                    let segs = &path.segs;
                    for k in 0..segs.len() {
                        let (a, b) = (
                            tangent(&segs[k], 1.0),
                            tangent(&segs[(k + 1) % segs.len()], 0.0),
                        );
                        let angle = cross(a, b).atan2(a.dot(b)).abs();
                        assert!(
                            angle < 1e-6,
                            "kink {angle} at {k} (d = {}, tol {tol})",
                            off.d
                        );
                    }
                }
            }
        }
    }

    /// f > 0 is proved before offsetting: an f that dips below 0 is refused with its
    /// witness; one whose minimum, 5·10⁻²⁰ at t₀ = 0.003 (in the middle of a depth-30 piece
    /// of width h = 2⁻³⁰, where the middle Bernstein coefficient is 5·10⁻²⁰ − h²/4 < 0), is
    /// below what the subdivision can separate from 0 is refused as undecided instead of
    /// offset through r ≈ 0.
    #[test]
    fn radius_proofs_refuse_what_they_cannot_prove() {
        use crate::skin::re::poly::Poly;
        let t0 = 0.003;
        let with_f = |c: Vec<f64>| {
            let mut skin = gentle_skin();
            std::sync::Arc::make_mut(&mut skin.segments[1].curve).f = Poly { c };
            skin
        };
        let dips = with_f(vec![t0 * t0 - 1e-9, -2.0 * t0, 1.0]);
        assert!(matches!(
            outline(&dips),
            Err(MatOffsetError::NonPositiveRadius { segment: 1, t }) if (t - t0).abs() < 1e-3
        ));
        let grazes = with_f(vec![t0 * t0 + 5e-20, -2.0 * t0, 1.0]);
        assert_eq!(
            inner_offset(&grazes, 0.2, 1e-12).err(),
            Some(MatOffsetError::UndecidedRadius { segment: 1 })
        );
        assert!(outline(&gentle_skin()).is_ok());
    }

    #[test]
    fn bad_tolerance_is_an_error() {
        let skin = gentle_skin();
        let off = inner_offset(&skin, 0.2, 1e-12).unwrap();
        // Every fit of the offset refuses it: at 0 or NaN each piece would be bisected
        // 2³⁰ times.
        let bad = |r: Result<Vec<crate::geom::Path>, MatOffsetError>| {
            matches!(r, Err(MatOffsetError::BadTolerance(_)))
        };
        for tol in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                off.to_merged_arc_paths(tol),
                Err(MatOffsetError::BadTolerance(_))
            ));
            assert!(bad(off.to_line_paths(tol)), "{tol}");
            assert!(bad(off.to_arc_paths(tol)), "{tol}");
            assert!(bad(off.to_cubic_paths(tol)), "{tol}");
            assert!(
                bad(crate::toolpath::re_route::biarc_paths(&off, tol)),
                "{tol}"
            );
        }
        assert!(off.to_line_paths(1e-3).is_ok_and(|p| !p.is_empty()));
    }

    /// Open sequences of 3–6 circles with turns and radius changes (fixed proptest seed,
    /// see .cargo/config.toml).
    fn sequence() -> impl Strategy<Value = Vec<Circle>> {
        crate::skin::mat_offset::global_tests::wandering(0.7, 2.0..4.0, 0.4..1.6, 0.3)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        #[test]
        fn merged_arcs_match_the_exact_offset(
            cs in sequence(),
            ph in any::<bool>(),
            delta in 0.1f64..1.2,
            tol_exp in 2.0f64..3.5,
        ) {
            let interp = if ph { Interp::PhQuintic } else { Interp::Cubic };
            let tol = 10f64.powf(-tol_exp);
            let Ok(skin) = ReSkin::build(&cs, &test_touches(&cs, &[]), false, interp, 1e-9)
            else {
                return Ok(());
            };
            // Skins whose envelopes cross or loop are not MAT-offset (the route refuses them).
            if super::super::envelope_loops(&skin, 1e-10).map_or(true, |l| !l.is_empty()) {
                return Ok(());
            }
            for off in [inner_offset(&skin, delta, 1e-12), outer_offset(&skin, delta, 1e-12)]
                .into_iter()
                .flatten()
            {
                check(&off, tol, 1.0);
            }
        }
    }
}
