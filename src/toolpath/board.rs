//! One backboard around a whole sign: the pieces of a backboard region (one per word or
//! letter when they lie apart) joined by straight bridges ([`bridged`]), and mounting holes
//! at a fixed inset from the board's edge ([`mounting_points`]), and convex corners rounded
//! to a radius ([`rounded`]).
//!
//! Bridges follow a minimum spanning tree of the pieces (Kruskal, shortest gaps first;
//! Cormen et al., *Introduction to Algorithms*, 3rd ed., §23.2), each along the shortest
//! segment between its two pieces, as the disk of radius w/2 swept along that segment
//! extended by w into both pieces. The bridged board is closed by the inner corner radius ρ
//! like the board itself, (B ⊕ D_ρ) ⊖ D_ρ. Everything a bridge or the closing adds lies
//! outside the board it starts from, which holds every point within the margin of the
//! items and channels, so the board's edge keeps its margin from every channel.

use super::ops;
use super::region::Region;
use crate::geom::DVec2;
use crate::geom::interop::flatten_pline;
use cavalier_contours::polyline::{PlineSource, Polyline};

/// Default smallest width of a bridge between two pieces of a backboard, in millimetres:
/// about two board margins of the shipped neon presets (5–6 mm), so a bridge is as
/// sturdy as the band of board around a letter.
pub const BRIDGE_WIDTH_MM: f64 = 10.0;

/// Default inset of mounting holes from the board's edge, in millimetres.
pub const MOUNTING_INSET_MM: f64 = 8.0;

/// Smallest wall of board, in millimetres, left between a mounting hole and any channel
/// or item outline.
pub const MOUNTING_WALL_MM: f64 = 2.0;

/// Bisection steps of [`rounded`]'s growth: the board grows at most rc/2⁶ more than it
/// must.
pub const ROUND_GROWTH_STEPS: usize = 6;

/// The board with every convex corner of radius at least `rc` and every concave one at
/// least `rho`, holding `board` (so every channel keeps its margin):
/// B′ = ((B ⊕ D_g) ∘ D_rc) • D_rho, the opening (X ⊖ D_rc) ⊕ D_rc (Serra 1982, *Image
/// Analysis and Mathematical Morphology*, ch. II: an opened set is the union of the disks of
/// radius rc inside it, so its convex corners are arcs of radius ≥ rc) of the board grown by
/// the least g ∈ [0, rc] (bisection, [`ROUND_GROWTH_STEPS`]) for which it still holds the
/// board shrunk by `tol`, then closed by `rho`. g = rc always holds: (B ⊕ D_rc) ∘ D_rc =
/// (B • D_rc) ⊕ D_rc ⊇ B. Where the margin's own corners are at least rc round, g = 0 and
/// the board is unchanged within `tol`. Returns the board and g.
pub fn rounded(board: &Region, rc: f64, rho: f64, tol: f64, eps: f64) -> (Region, f64) {
    if rc <= 0.0 || board.contours.is_empty() {
        return (board.clone(), 0.0);
    }
    let must = board.offset(-tol, eps);
    let open = |g: f64| {
        let r = board.offset(g, eps).offset(-rc, eps).offset(rc, eps);
        r.holds(&must).then_some(r)
    };
    let (mut lo, mut hi) = (0.0, rc);
    let mut best = match open(0.0) {
        Some(r) => return (ops::backboard(&[r], 0.0, rho, tol, eps), 0.0),
        None => None,
    };
    for _ in 0..ROUND_GROWTH_STEPS {
        let mid = 0.5 * (lo + hi);
        match open(mid) {
            Some(r) => {
                hi = mid;
                best = Some(r);
            }
            None => lo = mid,
        }
    }
    let r = best.unwrap_or_else(|| (board.offset(rc, eps).offset(-rc, eps)).offset(rc, eps));
    (ops::backboard(&[r], 0.0, rho, tol, eps), hi)
}

/// The outer contours of `board` that no other contour of it encloses: its pieces.
pub fn pieces(board: &Region) -> Vec<&Polyline<f64>> {
    let outer: Vec<&Polyline<f64>> = board.contours.iter().filter(|c| c.area() > 0.0).collect();
    outer
        .iter()
        .enumerate()
        .filter(|&(i, c)| {
            let Some(v) = c.iter_vertexes().next() else {
                return false;
            };
            !outer
                .iter()
                .enumerate()
                .any(|(j, o)| j != i && o.winding_number(v.pos()) != 0)
        })
        .map(|(_, c)| *c)
        .collect()
}

/// Closest points of two polylines (vertices of each against the segments of the other:
/// exact for chains that do not cross): `(distance, point on a, point on b)`.
fn closest(a: &[DVec2], b: &[DVec2]) -> (f64, DVec2, DVec2) {
    let mut best = (f64::INFINITY, DVec2::ZERO, DVec2::ZERO);
    let mut try_side = |pts: &[DVec2], chain: &[DVec2], swap: bool| {
        for &p in pts {
            for s in chain.windows(2) {
                let q = nearest_on_segment(p, s[0], s[1]);
                let d = p.distance(q);
                if d < best.0 {
                    best = if swap { (d, q, p) } else { (d, p, q) };
                }
            }
        }
    };
    try_side(a, b, false);
    try_side(b, a, true);
    best
}

/// The point of segment [s0, s1] nearest to `p`: s0 + clamp(t, 0, 1)·(s1 − s0) with
/// t = (p − s0)·(s1 − s0)/|s1 − s0|².
fn nearest_on_segment(p: DVec2, s0: DVec2, s1: DVec2) -> DVec2 {
    let d = s1 - s0;
    let l2 = d.length_squared();
    if l2 == 0.0 {
        return s0;
    }
    s0 + d * ((p - s0).dot(d) / l2).clamp(0.0, 1.0)
}

/// A closed ring's points (flattened within `tol`) with the first point repeated at the end.
fn ring_points(c: &Polyline<f64>, tol: f64) -> Vec<DVec2> {
    let mut pts = flatten_pline(c, tol);
    if let Some(&first) = pts.first() {
        pts.push(first);
    }
    pts
}

/// The board `board` with its pieces joined into one by bridges of width `width`
/// (minimum spanning tree over the gaps, see the module docs), closed by the inner corner
/// radius `rho` ([`ops::backboard`] with margin 0). Returns the board and the bridges'
/// centre segments. A board of one piece, or `width` ≤ 0, is returned as it is. Up to
/// `pieces` rounds are taken should an offset split the result again.
pub fn bridged(
    board: &Region,
    width: f64,
    rho: f64,
    tol: f64,
    eps: f64,
) -> (Region, Vec<(DVec2, DVec2)>) {
    let mut out = board.clone();
    let mut segments = Vec::new();
    let rounds = pieces(board).len();
    for _ in 0..rounds {
        let parts: Vec<Vec<DVec2>> = pieces(&out).iter().map(|c| ring_points(c, tol)).collect();
        if parts.len() < 2 || width <= 0.0 {
            break;
        }
        let bridges = spanning_bridges(&parts);
        let mut regions = vec![out.clone()];
        for &(a, b) in &bridges {
            let u = (b - a).try_normalize().unwrap_or(DVec2::X);
            let spine = [a - u * width, b + u * width];
            regions.push(ops::swept_region(&spine, false, width / 2.0, tol));
        }
        segments.extend(bridges);
        out = ops::backboard(&regions, 0.0, rho, tol, eps);
    }
    (out, segments)
}

/// The bridges of a minimum spanning tree of `parts` (closed point rings): Kruskal's
/// algorithm over every pair's shortest gap, shortest first, with a union–find of the
/// parts. Returns each bridge's end points (on its two parts).
fn spanning_bridges(parts: &[Vec<DVec2>]) -> Vec<(DVec2, DVec2)> {
    let mut edges = Vec::new();
    for i in 0..parts.len() {
        for j in i + 1..parts.len() {
            let (d, a, b) = closest(&parts[i], &parts[j]);
            edges.push((d, i, j, a, b));
        }
    }
    edges.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    let mut root: Vec<usize> = (0..parts.len()).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    let mut out = Vec::new();
    for (_, i, j, a, b) in edges {
        let (ri, rj) = (find(&mut root, i), find(&mut root, j));
        if ri != rj {
            root[ri] = rj;
            out.push((a, b));
        }
    }
    out
}

/// Why mounting holes could not be placed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MountingError {
    /// Fewer places than holes at the inset, clear of the channels and items.
    #[error(
        "only {found} of {count} mounting holes fit {inset} from the board's edge with a wall \
         of {wall} to every channel and outline: lower the count or the inset, or widen the margin"
    )]
    TooFew {
        /// Holes asked for.
        count: usize,
        /// Holes placed.
        found: usize,
        /// The inset asked for.
        inset: f64,
        /// The wall kept to channels and outlines.
        wall: f64,
    },
}

/// Mounting holes asked of a board.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mounting {
    /// Number of holes.
    pub count: usize,
    /// Hole diameter.
    pub diameter: f64,
    /// Distance of each hole's centre from the board's edge.
    pub inset: f64,
    /// Smallest wall of board between a hole and any channel or item outline.
    pub wall: f64,
}

/// Centres of `m.count` mounting holes of `m.diameter`, each `m.inset` from the edge of
/// `board` (on the contours of the board shrunk by the inset) and at least diameter/2 +
/// wall from every region of `keep_out` (channels, item outlines), and holes diameter +
/// wall apart.
/// Places: the candidate nearest to each target in turn, the targets being the corners
/// of the board's bounding box — 1: top centre; 2: top left, top right; 3: those and the
/// bottom centre; 4: the four corners — and beyond four, the candidate farthest from
/// the holes already placed (farthest-point sampling). Candidates are spaced a quarter of
/// the diameter (at least `tol`) along the inset contours; `eps` is the offsets' tolerance.
pub fn mounting_points(
    board: &Region,
    keep_out: &[Region],
    m: Mounting,
    tol: f64,
    eps: f64,
) -> Result<Vec<DVec2>, MountingError> {
    let Mounting {
        count,
        diameter,
        inset,
        wall,
    } = m;
    let step = (diameter / 4.0).max(tol);
    let inner = board.offset(-inset, eps);
    let blocked = Region::union(keep_out, tol).offset(diameter / 2.0 + wall, eps);
    let mut candidates = Vec::new();
    for c in &inner.contours {
        let pts = ring_points(c, tol);
        for s in pts.windows(2) {
            let n = ((s[0].distance(s[1]) / step).ceil() as usize).max(1);
            for k in 0..n {
                let p = s[0].lerp(s[1], k as f64 / n as f64);
                if !blocked.contains(p) && board.contains(p) {
                    candidates.push(p);
                }
            }
        }
    }
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for c in &board.contours {
        for p in flatten_pline(c, tol) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    let mid = (lo.x + hi.x) / 2.0;
    let targets: Vec<DVec2> = match count {
        1 => vec![DVec2::new(mid, hi.y)],
        2 => vec![DVec2::new(lo.x, hi.y), hi],
        3 => vec![DVec2::new(lo.x, hi.y), hi, DVec2::new(mid, lo.y)],
        _ => vec![DVec2::new(lo.x, hi.y), hi, lo, DVec2::new(hi.x, lo.y)],
    };
    let apart = diameter + wall;
    let mut chosen: Vec<DVec2> = Vec::new();
    for k in 0..count {
        let free = candidates
            .iter()
            .copied()
            .filter(|p| chosen.iter().all(|q| q.distance(*p) >= apart));
        let pick = match targets.get(k) {
            Some(&t) => free.min_by(|a, b| a.distance(t).total_cmp(&b.distance(t))),
            None => free.max_by(|a, b| {
                let far = |p: &DVec2| {
                    chosen
                        .iter()
                        .map(|q| q.distance(*p))
                        .fold(f64::INFINITY, f64::min)
                };
                far(a).total_cmp(&far(b))
            }),
        };
        match pick {
            Some(p) => chosen.push(p),
            None => {
                return Err(MountingError::TooFew {
                    count,
                    found: chosen.len(),
                    inset,
                    wall,
                });
            }
        }
    }
    Ok(chosen)
}
