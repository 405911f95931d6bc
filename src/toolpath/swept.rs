//! The region a disk of radius r sweeps along a path of lines and arcs, bounded by lines
//! and arcs exactly: S = {p : dist(p, spine) ≤ r}.
//!
//! The boundary of S is made of points at distance r from the spine: pieces of the two
//! parallel offsets at ±r that stay at distance ≥ r from the whole spine (cavalier_contours'
//! polyline offset with self-intersection handling, which also clips an open spine's
//! offsets at the circles of radius r about its two ends), and, for an open spine, arcs of
//! those two end circles. The pieces are oriented with S on their left: the right offset
//! (−r) forward, the left one (+r) backward; an end circle counter-clockwise about its
//! centre, split where pieces end on it and where it crosses the other end circle, and
//! kept where it lies at distance r from the spine (not inside the region, as where the two
//! end disks overlap or an end lies in the channel). They are then chained end to start
//! into closed contours. Outer contours come out counter-clockwise and holes (a spine that closes on itself, an
//! "e" or an "o") clockwise, as [`Region`] wants them.
//!
//! Against the polygon of [`super::ops::swept_region`] (the spine flattened, joins and caps
//! flattened), a channel's boundary has a handful of arcs per spine arc instead of hundreds
//! of chords, so the channel's clearing offsets and its G-code are smaller by about as
//! much. The result is checked before it is used ([`swept_arc_region`] returns `None`
//! otherwise): every contour closed, the region simple and well nested, every boundary
//! vertex at distance r from the spine and every spine vertex inside.
//!
//! Cost: two offsets of the spine, O(n log n) in its segments, and the checks, O(n·m) for
//! the distances of the m boundary vertices to the n spine segments.

use super::region::{MEET_FRACTION, Region};
use super::rings::degenerate;
use crate::geom::{DVec2, interop};
use cavalier_contours::polyline::{
    PlineCreation, PlineOffsetOptions, PlineSource, PlineSourceMut, PlineVertex, Polyline,
};
use std::f64::consts::{PI, TAU};

/// Boundary vertices may lie this many `eps` nearer to or farther from the spine than r
/// (cavalier's offset and slice-joining accuracy is `eps`).
const DISTANCE_SLACK_EPS: f64 = 4.0;

/// The swept region of `spine` (open or closed, lines and arcs) by a disk of radius `r`,
/// with the exact lines and arcs of its boundary (module docs), or `None` when the
/// construction does not give a sound region (the caller then flattens). `eps` is the
/// position accuracy of the offsets.
pub fn swept_arc_region(spine: &Polyline<f64>, r: f64, eps: f64) -> Option<Region> {
    let positive = |x: f64| x > 0.0 && x.is_finite();
    if spine.vertex_count() < 2 || !positive(r) || !positive(eps) {
        return None;
    }
    // Centred, as Region::offset does: cavalier compares absolute differences.
    let alone = Region {
        contours: vec![spine.clone()],
    };
    let centre = alone.center();
    let moved = alone.translated(-centre).contours.pop()?;
    let opts = PlineOffsetOptions {
        handle_self_intersects: true,
        pos_equal_eps: eps * 0.1,
        offset_dist_eps: eps,
        ..PlineOffsetOptions::new()
    };
    let mut pieces: Vec<Polyline<f64>> = moved.parallel_offset_opt(-r, &opts);
    for mut left in moved.parallel_offset_opt(r, &opts) {
        left.invert_direction_mut();
        pieces.push(left);
    }
    let ends = if moved.is_closed() {
        Vec::new()
    } else {
        let first = moved.get(0)?;
        let last = moved.last()?;
        vec![DVec2::new(first.x, first.y), DVec2::new(last.x, last.y)]
    };
    let contours = chain(pieces, &moved, &ends, r, eps)?;
    let region = Region { contours };
    sound(&region, &moved, r, eps).then(|| region.translated(centre))
}

fn start_of(pl: &Polyline<f64>) -> DVec2 {
    pl.get(0).map_or(DVec2::NAN, |v| interop::vertex_point(&v))
}

fn end_of(pl: &Polyline<f64>) -> DVec2 {
    pl.last().map_or(DVec2::NAN, |v| interop::vertex_point(&v))
}

/// Counter-clockwise angle from `a` to `b` about `c`, in [0, 2π).
fn ccw_angle(c: DVec2, a: DVec2, b: DVec2) -> f64 {
    let (u, v) = (a - c, b - c);
    u.perp_dot(v).atan2(u.dot(v)).rem_euclid(TAU)
}

/// Chains the oriented pieces into closed contours (module docs). Closed pieces are
/// contours already; the open ones and the [`cap_arcs`] are joined end to start, each end to
/// the nearest start within `eps`. `None` when an end has no start to go on with.
fn chain(
    pieces: Vec<Polyline<f64>>,
    spine: &Polyline<f64>,
    ends: &[DVec2],
    r: f64,
    eps: f64,
) -> Option<Vec<Polyline<f64>>> {
    let (mut contours, mut open): (Vec<_>, Vec<_>) = pieces
        .into_iter()
        .filter(|p| p.vertex_count() >= 2)
        .partition(|p| p.is_closed());
    let caps = cap_arcs(&open, spine, ends, r, eps)?;
    open.extend(caps);
    let starts: Vec<DVec2> = open.iter().map(start_of).collect();
    let stops: Vec<DVec2> = open.iter().map(end_of).collect();
    let mut used = vec![false; open.len()];
    for first in 0..open.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let mut ring = open[first].clone();
        ring.set_is_closed(true);
        let mut cur = first;
        loop {
            let end = stops[cur];
            let (next, _) = (0..open.len())
                .filter(|&j| !used[j] || j == first)
                .map(|j| (j, starts[j].distance(end)))
                .filter(|&(_, d)| d <= eps)
                .min_by(|a, b| a.1.total_cmp(&b.1))?;
            ring.remove_last();
            if next == first {
                break;
            }
            used[next] = true;
            for v in open[next].iter_vertexes() {
                ring.add_vertex(v);
            }
            cur = next;
        }
        contours.push(ring);
    }
    Some(contours)
}

/// The parts of the end circles (centres `ends`, radius `r`) that bound the swept region,
/// each counter-clockwise about its centre. A circle is split where pieces end on it
/// (within `eps`) and where it crosses the other end circle; a part is kept when its
/// midpoint lies at distance r from the spine (within the slack), not nearer: the rest
/// lies inside the region. `None` when a circle has no split point (the spine is shorter
/// than the offsets can resolve).
fn cap_arcs(
    open: &[Polyline<f64>],
    spine: &Polyline<f64>,
    ends: &[DVec2],
    r: f64,
    eps: f64,
) -> Option<Vec<Polyline<f64>>> {
    let mut arcs = Vec::new();
    let slack = DISTANCE_SLACK_EPS * eps;
    for (i, &c) in ends.iter().enumerate() {
        let mut split: Vec<DVec2> = open
            .iter()
            .flat_map(|p| [start_of(p), end_of(p)])
            .filter(|p| (p.distance(c) - r).abs() <= eps)
            .collect();
        for (j, &o) in ends.iter().enumerate() {
            let d = c.distance(o);
            if j != i && d > 0.0 && d < 2.0 * r {
                let u = (o - c) / d;
                let h = (r * r - 0.25 * d * d).max(0.0).sqrt();
                let m = 0.5 * (c + o);
                split.push(m + h * u.perp());
                split.push(m - h * u.perp());
            }
        }
        let angle = |p: &DVec2| (p.y - c.y).atan2(p.x - c.x);
        split.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
        split.dedup_by(|a, b| a.distance(*b) <= eps);
        if split.is_empty() {
            return None;
        }
        for k in 0..split.len() {
            let (from, to) = (split[k], split[(k + 1) % split.len()]);
            let turn = ccw_angle(c, from, to);
            let sweep = if turn > 0.0 { turn } else { TAU };
            let (sn, cs) = (0.5 * sweep).sin_cos();
            let v = from - c;
            let mid = c + DVec2::new(cs * v.x - sn * v.y, sn * v.x + cs * v.y);
            let on_boundary = spine
                .closest_point(interop::vector2(mid), eps * 0.1)
                .is_some_and(|cp| cp.distance >= r - slack);
            if on_boundary {
                let mut arc = Polyline::with_capacity(3, false);
                arc.add(from.x, from.y, 0.0);
                push_cap(&mut arc, c, from, sweep);
                arc.add(to.x, to.y, 0.0);
                arcs.push(arc);
            }
        }
    }
    Some(arcs)
}

/// Sets the arc of `sweep` (counter-clockwise, about `c`) from the polyline's last vertex
/// `from`, split into parts of at most a half turn (cavalier keeps |bulge| ≤ 1); the
/// caller adds the arc's end.
fn push_cap(pl: &mut Polyline<f64>, c: DVec2, from: DVec2, sweep: f64) {
    let parts = (sweep / PI).ceil().max(1.0) as usize;
    let part = sweep / parts as f64;
    let bulge = (part / 4.0).tan();
    let n = pl.vertex_count();
    if let Some(mut v) = pl.last() {
        v.bulge = bulge;
        pl.set_vertex(n - 1, v);
    }
    let (s, co) = part.sin_cos();
    let mut p = from - c;
    for _ in 1..parts {
        p = DVec2::new(co * p.x - s * p.y, s * p.x + co * p.y);
        pl.add_vertex(PlineVertex::new(c.x + p.x, c.y + p.y, bulge));
    }
}

/// The checks of the module docs: contours closed with width, the region simple and well
/// nested, boundary vertices at distance r from the spine, spine vertices inside.
fn sound(region: &Region, spine: &Polyline<f64>, r: f64, eps: f64) -> bool {
    if region.contours.is_empty()
        || (region.contours.iter()).any(|c| !c.is_closed() || degenerate(c, eps))
        || region.area() <= 0.0
    {
        return false;
    }
    let slack = DISTANCE_SLACK_EPS * eps;
    let at_r = region
        .contours
        .iter()
        .flat_map(|c| c.iter_vertexes())
        .all(|v| {
            spine
                .closest_point(v.pos(), eps * 0.1)
                .is_some_and(|cp| (cp.distance - r).abs() <= slack)
        });
    at_r && spine
        .iter_vertexes()
        .all(|v| region.contains(interop::vertex_point(&v)))
        && region.well_nested()
        && region.simple(eps * MEET_FRACTION)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::interop::pline_from_points;
    use crate::toolpath::ops::swept_region;
    use proptest::prelude::*;

    const EPS: f64 = 1e-4;

    /// A polyline with one arc of `sweep` about `c` of radius `rad`, from angle `a0`.
    fn arc_spine(c: DVec2, rad: f64, a0: f64, sweep: f64, closed: bool) -> Polyline<f64> {
        let parts = (sweep.abs() / PI).ceil() as usize;
        let part = sweep / parts as f64;
        let mut pl = Polyline::with_capacity(parts + 1, closed);
        let last = if closed { parts } else { parts + 1 };
        for k in 0..last {
            let a = a0 + part * k as f64;
            pl.add(c.x + rad * a.cos(), c.y + rad * a.sin(), (part / 4.0).tan());
        }
        pl
    }

    fn distance_to_polyline(p: DVec2, pts: &[DVec2]) -> f64 {
        pts.windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                p.distance(a + t * (b - a))
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn straight_spine_is_a_stadium_in_every_frame() {
        let r = 2.0;
        let exact = 4.0 * r * 5.0 + PI * r * r;
        let (s, c) = 0.7f64.sin_cos();
        for (shift, turn) in [(DVec2::ZERO, false), (DVec2::new(1e4, -3e3), true)] {
            for reverse in [false, true] {
                let mut pts = vec![DVec2::new(-5.0, 1.0), DVec2::new(5.0, 1.0)];
                if turn {
                    pts.iter_mut()
                        .for_each(|p| *p = DVec2::new(c * p.x - s * p.y, s * p.x + c * p.y));
                }
                pts.iter_mut().for_each(|p| *p += shift);
                if reverse {
                    pts.reverse();
                }
                let region = swept_arc_region(&pline_from_points(&pts, false), r, EPS).unwrap();
                assert_eq!(region.contours.len(), 1);
                assert_eq!(region.contours[0].vertex_count(), 4, "two sides, two caps");
                assert!(
                    (region.area() - exact).abs() < 1e-6 * exact,
                    "{}",
                    region.area()
                );
                assert!((region.perimeter() - (20.0 + 2.0 * PI * r)).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn arc_spine_area_is_length_times_width_plus_the_caps() {
        // A tube of half-width r along a curve of length L without overlap has area
        // 2rL; the two half-disk caps add πr².
        let (rad, r) = (10.0, 2.0);
        for sweep in [PI, -PI, 1.5 * PI] {
            let spine = arc_spine(DVec2::new(3.0, -2.0), rad, 0.3, sweep, false);
            let region = swept_arc_region(&spine, r, EPS).unwrap();
            let exact = 2.0 * r * rad * sweep.abs() + PI * r * r;
            assert_eq!(region.contours.len(), 1);
            assert!(
                (region.area() - exact).abs() < 1e-6 * exact,
                "{}",
                region.area()
            );
        }
    }

    #[test]
    fn closed_circle_spine_is_an_annulus() {
        let (rad, r) = (10.0, 2.0);
        for sweep in [TAU, -TAU] {
            let spine = arc_spine(DVec2::new(50.0, 7.0), rad, 0.0, sweep, true);
            let region = swept_arc_region(&spine, r, EPS).unwrap();
            assert_eq!(region.contours.len(), 2);
            let exact = 4.0 * PI * rad * r;
            assert!(
                (region.area() - exact).abs() < 1e-6 * exact,
                "{}",
                region.area()
            );
            assert!(!region.contains(DVec2::new(50.0, 7.0)));
            assert!(region.contains(DVec2::new(60.0, 7.0)));
        }
    }

    #[test]
    fn hook_whose_caps_overlap_encloses_a_hole() {
        // 330° of a circle of radius 5 with r = 2: the end disks overlap (their centres are
        // 2.59 apart), so the channel closes around the centre, 5 from the spine.
        let spine = arc_spine(DVec2::ZERO, 5.0, 0.0, 330f64.to_radians(), false);
        let region = swept_arc_region(&spine, 2.0, EPS).unwrap();
        assert_eq!(region.contours.len(), 2);
        assert!(!region.contains(DVec2::ZERO));
        let tol = 1e-5;
        let flat = crate::geom::interop::flatten_pline(&spine, tol);
        let polygon = swept_region(&flat, false, 2.0, tol);
        let slack = 4.0 * tol * region.perimeter();
        assert!(
            (region.area() - polygon.area()).abs() < slack,
            "{} vs {}",
            region.area(),
            polygon.area()
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Random polyline spines: where the construction succeeds, the region has the area
        /// of the flattened buffer (geo, a second method), the same area when the spine is
        /// reversed, and holds exactly the points within r of the spine (away from the
        /// boundary by the flattening tolerance).
        #[test]
        fn random_spines_match_the_buffer(
            pts in prop::collection::vec((-10.0f64..10.0, -10.0f64..10.0), 2..7),
            r in 0.3f64..4.0,
            probes in prop::collection::vec((-15.0f64..15.0, -15.0f64..15.0), 32),
        ) {
            let pts: Vec<DVec2> = pts.into_iter().map(|(x, y)| DVec2::new(x, y)).collect();
            prop_assume!(pts.windows(2).all(|w| w[0].distance(w[1]) > 0.1));
            let Some(region) = swept_arc_region(&pline_from_points(&pts, false), r, EPS) else {
                return Ok(());
            };
            let tol = 1e-4;
            let polygon = swept_region(&pts, false, r, tol);
            let slack = 10.0 * tol * region.perimeter();
            prop_assert!((region.area() - polygon.area()).abs() <= slack,
                "{} vs {}", region.area(), polygon.area());
            let back: Vec<DVec2> = pts.iter().rev().copied().collect();
            if let Some(rev) = swept_arc_region(&pline_from_points(&back, false), r, EPS) {
                prop_assert!((rev.area() - region.area()).abs() <= slack);
            }
            for (x, y) in probes {
                let p = DVec2::new(x, y);
                let d = distance_to_polyline(p, &pts);
                if (d - r).abs() > 1e-3 {
                    prop_assert_eq!(region.contains(p), d < r, "{:?} at {}", p, d);
                }
            }
        }
    }
}
