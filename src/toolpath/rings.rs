//! Ring cleaning: what turns the rings a polygon boolean or an offset returns into rings a
//! tool can follow. Spikes (there-and-back excursions) and hairs are removed, repeated and
//! nearly collinear vertices dropped, rings traversed more than once reduced to one pass,
//! repeated rings dropped, and rings that enclose no width recognised.

use crate::geom::interop::{self, path_from_pline};
use crate::geom::{DVec2, PathSeg};
use cavalier_contours::polyline::{PlineCreation, PlineSource, PlineSourceMut, Polyline};

/// A closed ring without repeated points and without spikes: a vertex where the ring turns
/// back on itself (its two edges collinear and opposite, by the exact orientation
/// predicate) is removed, repeatedly, until none is left.
pub fn clean_ring(mut pts: Vec<DVec2>) -> Vec<DVec2> {
    loop {
        let n = pts.len();
        if n < 3 {
            return pts;
        }
        let mut removed = false;
        let mut out: Vec<DVec2> = Vec::with_capacity(n);
        for i in 0..n {
            let p = pts[(i + n - 1) % n];
            let v = pts[i];
            let q = pts[(i + 1) % n];
            let repeated = v == p;
            let spike =
                crate::geom::predicates::orient2d(p, v, q) == 0.0 && (p - v).dot(q - v) > 0.0;
            if (repeated || spike) && !removed {
                removed = true;
                continue;
            }
            out.push(v);
        }
        pts = out;
        if !removed {
            return pts;
        }
    }
}

/// A closed ring (no repeated end point) without vertices closer than `eps` to the last
/// kept one and without line–line vertices within `eps` of the chord of their neighbours
/// (nearly collinear or nearly back-tracking), repeatedly, so every edge of the result is
/// longer than `eps` and every turn moves the boundary by more than `eps`. Each removal
/// moves the boundary by less than `eps`. Spikes are removed by [`clean_ring`] first.
pub fn simplify_ring(pts: Vec<DVec2>, eps: f64) -> Vec<DVec2> {
    let mut pts = clean_ring(pts);
    loop {
        let n = pts.len();
        if n < 4 {
            return pts;
        }
        let mut keep = vec![true; n];
        let mut left = n;
        let mut prev = n - 1;
        for i in 0..n {
            // The last vertex's successor is the first: keep it when the first went.
            if left <= 3 || (i == n - 1 && !keep[0]) {
                break;
            }
            let (p, v, q) = (pts[prev], pts[i], pts[(i + 1) % n]);
            let chord = q - p;
            let len = chord.length();
            let near_chord = len > eps
                && (chord.perp_dot(v - p) / len).abs() < eps
                && (v - p).dot(chord) > 0.0
                && (q - v).dot(chord) > 0.0;
            if v.distance(p) < eps || near_chord {
                keep[i] = false;
                left -= 1;
            } else {
                prev = i;
            }
        }
        if left == n {
            return pts;
        }
        pts = clean_ring(
            pts.into_iter()
                .zip(keep)
                .filter_map(|(p, k)| k.then_some(p))
                .collect(),
        );
    }
}

/// A closed polyline without spikes: a vertex between two straight edges where the path
/// turns back on itself (the edges point in opposite directions and the excursion is
/// narrower than `eps`) is removed, and so are vertices within
/// `eps`·0.1 of the previous one, repeatedly. An arc whose sagitta is below `eps`·0.1
/// counts as straight here (it lies that close to its chord): an offset can leave a 1.4 µm
/// piece of a 5.4 mm arc and a line straight back along it; the edge that
/// replaces a removed spike vertex is then a line. Offsets can leave such zero-width
/// there-and-back excursions where two nearly coincident boundaries meet (seen at the
/// coincident end caps of the README's example strokes s1 and c1, a 0.02 mm spike); a tool
/// following one would retrace its own cut.
///
/// `hair` (≥ `eps`) is the widest excursion removed when its edges are longer than `eps`:
/// offsets also leave hairs, there-and-back excursions millimetres long and a few µm wide
/// where a channel ring pinches off (0.8 µm to 5.5 µm wide, several mm long), which the rounded program turns into a cut touching
/// itself. No tool clears anything by running into such a hair and back.
pub fn despike(pl: &Polyline<f64>, eps: f64, hair: f64) -> Polyline<f64> {
    use cavalier_contours::polyline::PlineVertex;
    type V = PlineVertex<f64>;
    let p = interop::vertex_point;
    // Whether `b` is removable between `a` and `c`.
    let removable = |a: &V, b: &V, c: &V| -> bool {
        if a.bulge == 0.0 && p(a).distance(p(b)) < eps * 0.1 {
            return true;
        }
        let (d0, d1) = (p(b) - p(a), p(c) - p(b));
        // Sagitta of an arc edge: chord/2·|bulge| (b = tan(θ/4), exact for |b| ≤ 1 within
        // a factor 2).
        let bent =
            |bulge: f64, chord: DVec2| bulge != 0.0 && chord.length() * bulge.abs() > 0.2 * eps;
        if bent(a.bulge, d0) || bent(b.bulge, d1) {
            return false;
        }
        // Width of the excursion: the distance of the far end of the shorter edge from the
        // longer edge's line (0 for an exact there-and-back).
        let long = d0.length().max(d1.length());
        let width = if long > 0.0 {
            d0.perp_dot(d1).abs() / long
        } else {
            0.0
        };
        d0.dot(d1) < 0.0 && (width < hair.max(eps) || long < eps)
    };
    // The edge from `a` that replaces a → b → c when b goes: a repeated vertex b passes its
    // own edge's bulge on; a spike's edges are straight (or tiny arcs), so the new edge is
    // a line.
    let straighten = |a: &mut V, b: &V| {
        a.bulge = if p(a).distance(p(b)) < eps * 0.1 && a.bulge == 0.0 {
            b.bulge
        } else {
            0.0
        };
    };
    let mut v: Vec<V> = Vec::with_capacity(pl.vertex_count());
    for x in pl.iter_vertexes() {
        v.push(x);
        while v.len() >= 3 {
            let k = v.len();
            if removable(&v[k - 3], &v[k - 2], &v[k - 1]) {
                let b = v[k - 2];
                straighten(&mut v[k - 3], &b);
                v.remove(k - 2);
            } else {
                break;
            }
        }
    }
    // The seam of the closed ring: the triples that wrap around.
    while v.len() > 3 {
        let k = v.len();
        if removable(&v[k - 2], &v[k - 1], &v[0]) {
            let b = v[k - 1];
            straighten(&mut v[k - 2], &b);
            v.pop();
        } else if removable(&v[k - 1], &v[0], &v[1]) {
            let b = v[0];
            straighten(&mut v[k - 1], &b);
            v.remove(0);
        } else if removable(&v[0], &v[1], &v[2]) {
            let b = v[1];
            straighten(&mut v[0], &b);
            v.remove(1);
        } else {
            break;
        }
    }
    let mut out = Polyline::with_capacity(v.len(), pl.is_closed());
    for x in v {
        out.add(x.x, x.y, x.bulge);
    }
    out
}

/// The closed polyline `pl` traversed once: when its vertices (positions within `eps`,
/// equal bulges) repeat with a period p that divides the vertex count, the first p
/// vertices. cavalier_contours' slice joining can return one ring traversed twice (a
/// channel would be cut twice round at one depth: "cut contour touches itself" along its
/// whole length).
///
/// The passes need not repeat vertex for vertex: the slices of one pass can be split at
/// other points than those of the next (a channel ring can go round two to seven times
/// with a different vertex count each pass, each pass 6e-4 from the last). So when the
/// ring comes back to its first vertex (within `near`) after vertex k, and every point of
/// the rest of the ring (flattened within `eps`) lies within `near` of the first loop
/// v₀…v_k, the rest only retraces the loop and the loop alone is returned. A figure eight
/// through v₀ keeps both lobes (its second lobe is far from the first). The search stops
/// unchanged after [`RETRACE_BUDGET`] point–segment distance tests.
pub fn single_traversal(pl: &Polyline<f64>, eps: f64, near: f64) -> Polyline<f64> {
    let once = periodic_traversal(pl, eps);
    if once.vertex_count() < pl.vertex_count() {
        return once;
    }
    retraced_traversal(pl, eps, near).unwrap_or(once)
}

/// Work limit of [`single_traversal`]'s retrace test (point–segment distances).
pub const RETRACE_BUDGET: usize = 50_000_000;

/// The first loop of `pl` when the rest of the ring retraces it (see [`single_traversal`]).
fn retraced_traversal(pl: &Polyline<f64>, eps: f64, near: f64) -> Option<Polyline<f64>> {
    let v: Vec<_> = pl.iter_vertexes().collect();
    let n = v.len();
    let p0 = DVec2::new(v.first()?.x, v[0].y);
    // The first return to v₀ (within `near`) after leaving it (beyond 2·`near`), closing a
    // loop of at least three vertices.
    let dist = |i: usize| DVec2::new(v[i].x, v[i].y).distance(p0);
    let away = (1..n).find(|&i| dist(i) > 2.0 * near)?;
    let k = (away.max(3)..n).find(|&i| dist(i) <= near)?;
    let ring = |from: usize, to: usize, closed: bool| {
        let mut out = Polyline::with_capacity(to - from, closed);
        for x in &v[from..to] {
            out.add(x.x, x.y, x.bulge);
        }
        out
    };
    let first = ring(0, k, true);
    // The rest, from v_k round to v₀ (open: its last segment ends at v₀).
    let mut rest = ring(k, n, false);
    rest.add(p0.x, p0.y, 0.0);
    retraces(&rest, &first, eps, near).then_some(first)
}

/// True when every point of `a` (flattened within `eps`) lies within `near` of `b`'s lines
/// and arcs; false beyond [`RETRACE_BUDGET`] point–segment tests.
fn retraces(a: &Polyline<f64>, b: &Polyline<f64>, eps: f64, near: f64) -> bool {
    let segs = path_from_pline(b).segs;
    let pts = path_from_pline(a).flatten(eps);
    if segs.len().saturating_mul(pts.len()) > RETRACE_BUDGET {
        return false;
    }
    pts.into_iter().all(|p| {
        segs.iter().any(|s| match s {
            PathSeg::Line(l) => l.distance(p) <= near,
            PathSeg::Arc(a) => a.distance(p) <= near,
            PathSeg::Cubic(_) => false,
        })
    })
}

/// `rings` without those that retrace an earlier one: the same orientation, and every
/// point of each within `near` of the other (`retraces`, points flattened within
/// `eps`). cavalier_contours can return one offset ring several times over (a channel
/// ring up to seven times, which would be cut seven times round at one depth).
pub fn drop_repeated_rings(rings: Vec<Polyline<f64>>, eps: f64, near: f64) -> Vec<Polyline<f64>> {
    let mut kept: Vec<(Polyline<f64>, f64, [f64; 4])> = Vec::with_capacity(rings.len());
    for r in rings {
        let area = r.area();
        let bb = match r.extents() {
            Some(e) => [e.min_x, e.min_y, e.max_x, e.max_y],
            None => [0.0; 4],
        };
        let repeat = kept.iter().any(|(k, ka, kb)| {
            (area > 0.0) == (*ka > 0.0)
                && bb.iter().zip(kb).all(|(x, y)| (x - y).abs() <= near + eps)
                && retraces(&r, k, eps, near)
                && retraces(k, &r, eps, near)
        });
        if !repeat {
            kept.push((r, area, bb));
        }
    }
    kept.into_iter().map(|(r, _, _)| r).collect()
}

/// [`single_traversal`]'s exact case: vertices repeating with a period that divides the
/// vertex count.
fn periodic_traversal(pl: &Polyline<f64>, eps: f64) -> Polyline<f64> {
    let n = pl.vertex_count();
    let v: Vec<_> = pl.iter_vertexes().collect();
    for p in 1..=n / 2 {
        if !n.is_multiple_of(p) {
            continue;
        }
        let periodic = (p..n).all(|i| {
            let (a, b) = (v[i], v[i - p]);
            (a.x - b.x).abs() <= eps && (a.y - b.y).abs() <= eps && a.bulge == b.bulge
        });
        if periodic {
            let mut out = Polyline::with_capacity(p, pl.is_closed());
            for x in &v[..p] {
                out.add(x.x, x.y, x.bulge);
            }
            return out;
        }
    }
    pl.clone()
}

/// True for a contour that encloses no width: fewer than two distinct vertices, or an area
/// below `eps`·perimeter (a circle of radius ρ has area/perimeter = ρ/2, so this keeps every
/// ring wider than about 2·eps and drops the zero-area slivers an offset can leave where
/// the input had nearly coincident vertices).
pub(crate) fn degenerate(pl: &Polyline<f64>, eps: f64) -> bool {
    use cavalier_contours::polyline::PlineSource;
    pl.vertex_count() < 2 || pl.area().abs() <= eps * pl.path_length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::interop::pline_from_points;

    fn square(x0: f64, y0: f64, s: f64) -> Polyline<f64> {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        pline_from_points(
            &[p(x0, y0), p(x0 + s, y0), p(x0 + s, y0 + s), p(x0, y0 + s)],
            true,
        )
    }

    #[test]
    fn spikes_and_repeats_are_cleaned() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        // Square with a there-and-back spike from (1,0) to (1,-1), and a repeated corner.
        let ring = vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, -1.0),
            p(1.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 2.0),
            p(2.0, 2.0),
            p(0.0, 2.0),
        ];
        let c = clean_ring(ring);
        assert_eq!(c.len(), 5, "{c:?}");
        assert!((crate::geom::path::polygon_area(&c) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn doubled_ring_is_traversed_once() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        let sq = [p(0.0, 0.0), p(2.0, 0.0), p(2.0, 2.0), p(0.0, 2.0)];
        let twice: Vec<DVec2> = sq.iter().chain(sq.iter()).copied().collect();
        let once = single_traversal(&pline_from_points(&twice, true), 1e-9, 1e-9);
        assert_eq!(once.vertex_count(), 4);
        assert!((once.area() - 4.0).abs() < 1e-12);
        // A ring that only passes one vertex twice (a figure eight) stays as it is.
        let eight = [
            p(0.0, 0.0),
            p(1.0, 1.0),
            p(2.0, 0.0),
            p(2.0, 2.0),
            p(1.0, 1.0),
            p(0.0, 2.0),
        ];
        let e = single_traversal(&pline_from_points(&eight, true), 1e-9, 1e-9);
        assert_eq!(e.vertex_count(), 6);
    }

    #[test]
    fn retraced_ring_with_other_vertices_is_traversed_once() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        // Three passes round a square; the later passes split the sides elsewhere (extra
        // vertices, one 1e-5 off the side), so no vertex period exists.
        let ring = [
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 2.0),
            p(0.0, 2.0),
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 2.0),
            p(0.7, 2.00001),
            p(0.0, 2.0),
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 1.3),
            p(2.0, 2.0),
            p(0.0, 2.0),
        ];
        let once = single_traversal(&pline_from_points(&ring, true), 1e-9, 1e-4);
        assert_eq!(once.vertex_count(), 4);
        assert!((once.area() - 4.0).abs() < 1e-12);
        // Beyond `near` the later pass is another path: the ring stays as it is.
        let kept = single_traversal(&pline_from_points(&ring, true), 1e-9, 1e-6);
        assert_eq!(kept.vertex_count(), ring.len());
        // A figure eight through its first vertex keeps both lobes.
        let eight = [
            p(0.0, 0.0),
            p(1.0, -1.0),
            p(2.0, 0.0),
            p(1.0, 1.0),
            p(0.0, 0.0),
            p(-1.0, -1.0),
            p(-2.0, 0.0),
            p(-1.0, 1.0),
        ];
        let e = single_traversal(&pline_from_points(&eight, true), 1e-9, 1e-3);
        assert_eq!(e.vertex_count(), 8);
    }

    #[test]
    fn repeated_rings_are_kept_once() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        let a = pline_from_points(&[p(0.0, 0.0), p(2.0, 0.0), p(2.0, 2.0), p(0.0, 2.0)], true);
        // The same ring from another start, a side split and 1e-5 off.
        let b = pline_from_points(
            &[
                p(2.0, 2.0),
                p(0.0, 2.0),
                p(0.0, 0.0),
                p(1.0, 1e-5),
                p(2.0, 0.0),
            ],
            true,
        );
        let mut hole = a.clone();
        hole.invert_direction_mut();
        let other = square(0.0, 0.0, 2.1);
        let kept = drop_repeated_rings(vec![a, b, hole, other], 1e-9, 1e-4);
        assert_eq!(
            kept.len(),
            3,
            "the copy goes; the hole and the larger square stay"
        );
        assert_eq!(kept[0].vertex_count(), 4);
        assert!(kept[1].area() < 0.0);
    }

    #[test]
    fn despike_removes_a_tiny_arc_and_the_line_back() {
        // A square whose corner (2, 0) has a 1e-4 long, nearly flat arc out and a line
        // straight back.
        let mut pl = Polyline::new_closed();
        pl.add(0.0, 0.0, 0.0);
        pl.add(2.0, 0.0, 1e-3);
        pl.add(2.0001, 0.0, 0.0);
        pl.add(2.0, 0.0, 0.0);
        pl.add(2.0, 2.0, 0.0);
        pl.add(0.0, 2.0, 0.0);
        let d = despike(&pl, 1e-3, 1e-3);
        assert_eq!(
            d.vertex_count(),
            4,
            "{:?}",
            d.iter_vertexes().collect::<Vec<_>>()
        );
        assert!(d.iter_vertexes().all(|v| v.bulge == 0.0));
        assert!((d.area() - 4.0).abs() < 1e-12);
    }

    #[test]
    fn despike_removes_hairs_narrower_than_given() {
        // A square with a hair 3 long out of its side x = 2, 8e-3 wide at its root.
        let p = |x: f64, y: f64| DVec2::new(x, y);
        let ring = [
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(5.0, 0.005),
            p(2.0, 0.008),
            p(2.0, 2.0),
            p(0.0, 2.0),
        ];
        let pl = pline_from_points(&ring, true);
        let d = despike(&pl, 1e-3, 1e-2);
        assert_eq!(d.vertex_count(), 5);
        assert!((d.area() - 4.0).abs() < 1e-12);
        assert_eq!(
            despike(&pl, 1e-3, 1e-3).vertex_count(),
            6,
            "wider than the hair limit"
        );
    }
}
