//! The geometry of each operation: which paths the tool centre follows.
//!
//! Every function here is pure geometry on [`Region`]s and polylines; [`super::plan`] turns
//! the paths into cuts with depths, feeds and ordering.

use super::region::Region;
use crate::geom::interop::{self, flatten_pline};
use crate::geom::{Arc, Circle, DVec2, Line, Path, PathSeg};
use geo::Buffer;

/// Where a profile runs relative to the outline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileSide {
    /// On the line (lasers engraving or scoring; or a V-bit tracing).
    On,
    /// Outside, by the tool radius or half the kerf: the part keeps its size.
    Outside,
    /// Inside, by the tool radius: the hole keeps its size.
    Inside,
}

/// Profile paths of a region: the contours moved by the tool radius to the given side,
/// oriented for climb milling with a clockwise spindle (material on the right of travel).
/// `eps` is the offset joining tolerance.
pub fn profile(region: &Region, side: ProfileSide, tool_radius: f64, eps: f64) -> Vec<Path> {
    let moved = match side {
        ProfileSide::On => region.clone(),
        ProfileSide::Outside => region.offset_checked(tool_radius, eps, eps),
        ProfileSide::Inside => region.offset_checked(-tool_radius, eps, eps),
    };
    // Region contours have material on their left; reversing puts it on the right.
    moved.paths().iter().map(Path::reversed).collect()
}

/// A hole at a point: a circular path for the tool centre, or a plain drill when the tool
/// is as wide as the hole.
#[derive(Clone, Debug, PartialEq)]
pub enum Hole {
    /// A circular path for the tool centre.
    Circle(Path),
    /// A plain drill at the point.
    Drill(DVec2),
}

/// Holes of `diameter` at `points` for a tool of radius `tool_radius` (half the kerf for
/// lasers): the centre circle has radius d/2 − r, run clockwise (climb inside a hole).
pub fn holes(points: &[DVec2], diameter: f64, tool_radius: f64) -> Vec<Hole> {
    points
        .iter()
        .map(|&c| {
            let r = diameter / 2.0 - tool_radius;
            if r <= 1e-9 * diameter {
                Hole::Drill(c)
            } else {
                let a = Arc::new(c, r, 0.0, -2.0 * std::f64::consts::PI);
                // Two half arcs: a full circle as one arc has coincident ends.
                let (h1, h2) = (
                    Arc::new(c, r, 0.0, a.sweep / 2.0),
                    Arc::new(c, r, a.sweep / 2.0, a.sweep / 2.0),
                );
                Hole::Circle(Path::new(vec![PathSeg::Arc(h1), PathSeg::Arc(h2)], true))
            }
        })
        .collect()
}

/// Largest number of hatch lines of one fill direction: 20 000 lines are 400 mm of
/// material at 0.02 mm (photo engraving on a large laser bed), so a count beyond it is a
/// mistaken spacing (0.0001 mm), not work; the build's check of the lines' crossings
/// grows with their number. A fill is refused before any line is made, with an error
/// naming the operation, its spacing and this limit.
pub const MAX_HATCH_LINES: usize = 20_000;

/// Largest number of concentric rings of one fill: a fill whose bound ([`ring_count_bound`])
/// passes it is refused before any ring is made.
pub const MAX_FILL_RINGS: usize = 10_000;

/// The extents of `regions`' vertices across lines at `angle` (radians) and along them:
/// `(across, along)`, the spread of y and x after rotating by −angle. Arcs bulge past their
/// vertices by at most their sagitta, which an estimate of counts can ignore.
pub fn extents_at(regions: &[Region], angle: f64) -> (f64, f64) {
    use cavalier_contours::polyline::PlineSource;
    let (s, c) = angle.sin_cos();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for pl in regions.iter().flat_map(|r| &r.contours) {
        for v in pl.iter_vertexes() {
            let p = DVec2::new(c * v.x + s * v.y, -s * v.x + c * v.y);
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if lo.x > hi.x {
        return (0.0, 0.0);
    }
    (hi.y - lo.y, hi.x - lo.x)
}

/// The number of hatch lines [`hatch`] makes across `regions` at `angle`, `spacing` apart:
/// lines at lo + spacing·(k + ½) below hi, so ⌈extent / spacing − ½⌉ for the extent across
/// the lines ([`extents_at`]; exact for polygons, arcs may add a line); as a float, so
/// that an absurd spacing gives a large number rather than an overflow. O(vertices).
pub fn hatch_line_count(regions: &[Region], angle: f64, spacing: f64) -> f64 {
    (extents_at(regions, angle).0 / spacing - 0.5)
        .ceil()
        .max(0.0)
}

/// An upper bound on the number of concentric rings `spacing` apart in `regions`: half the
/// smaller side of their bounding box (a bound on the inradius) over the spacing.
pub fn ring_count_bound(regions: &[Region], spacing: f64) -> f64 {
    let (h, w) = extents_at(regions, 0.0);
    (0.5 * w.min(h) / spacing).ceil()
}

/// Hatch lines inside a region: lines at `angle` (radians) `spacing` apart, clipped to the
/// region (even–odd over all contours, so holes stay clear), every other line reversed when
/// `alternate`. Contours are flattened within `tol`. Lines start half a spacing in from the
/// region's extent so the first and last lines are not tangent to it. The caller bounds the
/// number of lines ([`hatch_line_count`], [`MAX_HATCH_LINES`]).
///
/// A scanline sweep: edges sorted by their lower end enter the active list when the line
/// reaches them and leave it once past their upper end, so the cost is
/// O(E log E + L · A + S log S) for E edges, L lines, A active edges per line and S
/// crossings, rather than O(L · E).
pub fn hatch(region: &Region, angle: f64, spacing: f64, alternate: bool, tol: f64) -> Vec<Path> {
    if spacing <= 0.0 {
        return Vec::new();
    }
    let (s, c) = angle.sin_cos();
    // Rotate by −angle so hatch lines are horizontal.
    let to_local = |p: DVec2| DVec2::new(c * p.x + s * p.y, -s * p.x + c * p.y);
    let to_world = |p: DVec2| DVec2::new(c * p.x - s * p.y, s * p.x + c * p.y);
    let polys: Vec<Vec<DVec2>> = region
        .contours
        .iter()
        .map(|pl| flatten_pline(pl, tol).into_iter().map(to_local).collect())
        .collect();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in polys.iter().flatten() {
        lo = lo.min(p.y);
        hi = hi.max(p.y);
    }
    if lo > hi {
        return Vec::new();
    }
    // Edges (a, b) as they run, sorted by their lower y; horizontal ones never cross.
    let mut edges: Vec<(DVec2, DVec2)> = polys
        .iter()
        .flat_map(|poly| (0..poly.len()).map(move |i| (poly[i], poly[(i + 1) % poly.len()])))
        .filter(|(a, b)| a.y != b.y)
        .collect();
    edges.sort_by(|e, f| e.0.y.min(e.1.y).total_cmp(&f.0.y.min(f.1.y)));
    let mut next_edge = 0;
    let mut active: Vec<(DVec2, DVec2)> = Vec::new();
    let mut out = Vec::new();
    let mut k = 0usize;
    let mut y = lo + spacing / 2.0;
    while y < hi {
        while next_edge < edges.len() && edges[next_edge].0.y.min(edges[next_edge].1.y) <= y {
            active.push(edges[next_edge]);
            next_edge += 1;
        }
        active.retain(|(a, b)| a.y.max(b.y) > y);
        let mut xs: Vec<f64> = Vec::new();
        for (a, b) in &active {
            // Half-open rule: count an edge when y is in [min, max).
            if (a.y <= y) != (b.y <= y) {
                xs.push(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
            }
        }
        xs.sort_by(f64::total_cmp);
        let reverse = alternate && k % 2 == 1;
        let mut pairs: Vec<(f64, f64)> = xs.chunks_exact(2).map(|w| (w[0], w[1])).collect();
        if reverse {
            pairs.reverse();
        }
        for (x0, x1) in pairs {
            if x1 - x0 <= 0.0 {
                continue;
            }
            let (a, b) = if reverse { (x1, x0) } else { (x0, x1) };
            let p0 = to_world(DVec2::new(a, y));
            let p1 = to_world(DVec2::new(b, y));
            out.push(Path::new(vec![PathSeg::Line(Line::new(p0, p1))], false));
        }
        k += 1;
        y = lo + spacing / 2.0 + k as f64 * spacing;
    }
    out
}

/// Concentric clearing: offsets of the region inward by `first`, then by `stepover` more
/// each time, outermost ring first (the ordering stage decides the cut order). A tool that
/// clears `reach` to each side of its path (its radius) needs no further ring once the
/// region shrunk by the last ring's offset plus `reach` is empty. At most `max_rings` rings.
///
/// **No sliver rings.** Where the region's inradius is only a little above a ring's offset
/// d, the offset R₋d has slivers: spurs whose two sides run a hair apart along a channel's
/// spine, which touch or cross once the output is rounded. Every ring after the first is
/// therefore checked against the morphological opening of R₋d by
/// δ = max(½(reach − stepover), [`SLIVER_EPS`]·eps), that is (R₋₍d+δ₎)₊δ: R₋d without its
/// parts narrower than 2δ. Where the opening's boundary is shorter by more than
/// [`SLIVER_LENGTH`]·δ (a sliver, or sharp corners), the ring is the opening; otherwise R₋d
/// itself, which keeps the ring free of the small arcs the opening puts at every vertex of
/// a flattened curve. (Length, not area: a sliver 0.01 wide and 4 long has almost none.)
/// The opening lies inside R₋d, so the tool stays where R₋d allows. Nothing is left uncut
/// when δ ≤ reach − stepover: after the ring at d − stepover the material left is
/// R₋₍d−stepover+reach₎ ⊆ R₋₍d+δ₎, which lies inside the opening, and the opening's points
/// farther than `reach` from its boundary lie in R₋₍d+reach₎, which the next ring takes
/// on. The first ring (the wall pass) is R₋first itself, so walls and corners are cut
/// exactly. A ring that is not sound, that is [simple](Region::simple) and
/// [held](Region::holds) by the region at every vertex and segment middle (cavalier_contours
/// can return one touching itself along an arc, which would cut across the counters of
/// script lettering with single chords), is replaced by its opening too, and an opening that is not sound is never used; where neither is, geo's
/// buffer makes the ring (flattened within [`BUFFER_TOL_EPS`]·eps). Cost: four offsets
/// of the region per ring (three of them side by side), two O(n log n) segment tests and
/// two winding tests through slab indexes.
pub fn concentric(
    region: &Region,
    first: f64,
    stepover: f64,
    reach: f64,
    max_rings: usize,
    eps: f64,
) -> Vec<Path> {
    let mut out = Vec::new();
    if stepover <= 0.0 {
        return out;
    }
    let delta = (0.5 * (reach - stepover)).max(SLIVER_EPS * eps);
    let mut d = first;
    for k in 0..max_rings {
        // The ring, its opening and the test for the last ring are independent offsets of
        // the region: computed side by side (rayon; the same regions as in turn).
        let ((plain, opening), last) = crate::par::join(
            || {
                crate::par::join(
                    || region.offset(-d, eps),
                    || (k > 0).then(|| region.offset(-(d + delta), eps).offset(delta, eps)),
                )
            },
            || region.offset(-(d + reach), eps).is_empty(),
        );
        let r = match opening {
            // The first ring has no opening to fall back on: it is checked as
            // `Region::offset_checked` checks (cavalier's offset of a dense flattened union
            // can cut across a hole with one long chord, seen on script lettering).
            None => region.checked_offset(plain, -d, eps, BUFFER_TOL_EPS * eps),
            Some(opened) => {
                let sliver = plain.perimeter() - opened.perimeter() > SLIVER_LENGTH * delta;
                let sound = |ring: &Region| region.sound_offset(ring, -d, eps);
                let plain_sound = sound(&plain);
                if (sliver || !plain_sound) && sound(&opened) {
                    opened
                } else if plain_sound {
                    plain
                } else {
                    region.buffered(-d, BUFFER_TOL_EPS * eps)
                }
            }
        };
        if r.is_empty() {
            break;
        }
        out.extend(r.paths().iter().map(Path::reversed));
        if last {
            break;
        }
        d += stepover;
    }
    out
}

/// Narrowest part a clearing ring keeps after the first, in units of the offset accuracy
/// `eps`, when the tool's reach leaves no room for a wider opening (stepover ≥ reach): 20
/// eps is twice the distance within which [`Region::offset`] treats two passes as one path,
/// so a kept part's sides stay apart after the output is rounded.
pub const SLIVER_EPS: f64 = 20.0;

/// Flattening tolerance of the buffered ring in [`concentric`], in units of the offset
/// accuracy `eps`: the build passes eps = tolerance / 10, so this is the build's tolerance.
pub const BUFFER_TOL_EPS: f64 = 10.0;

/// Length, in units of δ, by which a clearing ring's opening must be shorter than the ring
/// for the opening to replace it (see [`concentric`]). A spur loses both its sides, twice
/// its length, so spurs longer than δ/2 count; rounding a convex corner of interior angle
/// α shortens the boundary by 2δ(cot(α/2) − (π − α)/2), 0.43·δ at 90°, and the many nearly
/// straight vertices of a flattened curve almost nothing.
pub const SLIVER_LENGTH: f64 = 1.0;

/// The region swept by a disk of radius `half_width` along the polyline `spine` (a
/// channel's footprint), with round ends; the arcs of the buffer are flattened within
/// `tol`.
pub fn swept_region(spine: &[DVec2], closed: bool, half_width: f64, tol: f64) -> Region {
    if spine.len() < 2 || half_width <= 0.0 {
        return Region::default();
    }
    let mut coords: Vec<geo::Coord<f64>> = spine.iter().map(|&p| interop::coord(p)).collect();
    if closed {
        coords.push(coords[0]);
    }
    let ls = geo::LineString::new(coords);
    // geo's (i_overlay's) round joins take the angle step φ = L/R (L the chord length); a
    // chord over φ has sagitta R(1 − cos(φ/2)) ≈ Rφ²/8, so φ = √(8·tol/R) keeps it ≤ tol.
    let phi = (8.0 * tol / half_width).sqrt().min(1.0);
    let style = geo::algorithm::buffer::BufferStyle::new(half_width)
        .line_join(geo::algorithm::buffer::LineJoin::Round(phi))
        .line_cap(geo::algorithm::buffer::LineCap::Round(phi));
    Region::from_geo(&ls.buffer_with_style(style), tol)
}

/// The region swept by a disk that moves from each of `disks` to the next with centre and
/// radius linear in between: the union of the convex hulls of consecutive disks (the larger
/// disk alone where one holds the other). A hull is bounded by the two outer common
/// tangents, which touch disk (c, r) at c + r·n with n·u = (r₀ − r₁)/d for u the unit
/// vector from c₀ to c₁ and d their distance, and by the two arcs between them. Arcs are
/// flattened within `tol` by inscribed chords, so the region lies inside the exact one and
/// within `tol` of it. Every hull winds counter-clockwise, so the non-zero union
/// ([`Region::from_overlapping_rings`]) is their union; a closed family (last disk equal to
/// the first) leaves its hole open. Cost: one boolean union of n hulls.
pub fn swept_disks(disks: &[Circle], tol: f64) -> Region {
    let hulls: Vec<Vec<DVec2>> = match disks {
        [] => Vec::new(),
        [d] => vec![disk_ring(d, tol)],
        _ => disks
            .windows(2)
            .map(|w| hull_ring(&w[0], &w[1], tol))
            .collect(),
    };
    Region::from_overlapping_rings(hulls, tol)
}

/// A full circle as a counter-clockwise polygon inscribed within `tol`; a circle whose
/// radius is within `tol` (one chord would do) gets [`MIN_DISK_CHORDS`] chords, so that
/// every disk has an area in the union however small it is.
fn disk_ring(d: &Circle, tol: f64) -> Vec<DVec2> {
    let full = Arc::new(d.c, d.r, 0.0, std::f64::consts::TAU);
    let mut ring = if full.chords_for_tolerance(tol) < MIN_DISK_CHORDS {
        (0..=MIN_DISK_CHORDS)
            .map(|k| full.eval(k as f64 / MIN_DISK_CHORDS as f64))
            .collect()
    } else {
        full.flatten(tol)
    };
    ring.pop();
    ring
}

/// Fewest chords of a disk's polygon in [`swept_disks`]: a triangle, inscribed.
const MIN_DISK_CHORDS: usize = 3;

/// The convex hull of two disks as a counter-clockwise polygon (see [`swept_disks`]).
fn hull_ring(a: &Circle, b: &Circle, tol: f64) -> Vec<DVec2> {
    let d = a.c.distance(b.c);
    if d <= (a.r - b.r).abs() {
        return disk_ring(if a.r >= b.r { a } else { b }, tol);
    }
    let u = (b.c - a.c) / d;
    let s = (a.r - b.r) / d;
    let h = (1.0 - s * s).max(0.0).sqrt();
    let right = s * u - h * crate::geom::perp(u);
    let angle = |v: DVec2| v.y.atan2(v.x);
    // Counter-clockwise: along the right tangent to b, round b's far side to the left
    // tangent, back along it to a, round a's far side to the right tangent.
    let sweep_b = 2.0 * h.atan2(s);
    let mut ring = Arc::new(b.c, b.r, angle(right), sweep_b).flatten(tol);
    let left = s * u + h * crate::geom::perp(u);
    ring.extend(Arc::new(a.c, a.r, angle(left), std::f64::consts::TAU - sweep_b).flatten(tol));
    ring
}

/// A closed contour around the union of `regions` grown by `margin`, with every inner
/// (concave) corner rounded to at least `min_inner_radius` (a closing: grow by
/// margin + ρ, shrink by ρ). Only outer boundaries are kept: a backboard has no holes.
pub fn backboard(
    regions: &[Region],
    margin: f64,
    min_inner_radius: f64,
    tol: f64,
    eps: f64,
) -> Region {
    let union = Region::union(regions, tol);
    let closed = |grow: &dyn Fn(&Region, f64) -> Region| {
        grow(&grow(&union, margin + min_inner_radius), -min_inner_radius)
    };
    // Each offset is checked (simple and nested, else made by geo's buffer), and the board
    // must hold the union. cavalier_contours can split it along chords through the strokes
    // (the board of two crossing hairpins can come back as four rings); geo's buffer makes
    // the whole closing then.
    let grown = closed(&|r, d| r.offset_checked(d, eps, tol));
    let grown = if grown.holds(&union) {
        grown
    } else {
        closed(&|r, d| r.buffered(d, tol))
    };
    Region {
        contours: grown
            .contours
            .into_iter()
            .filter(|c| cavalier_contours::polyline::PlineSource::area(c) > 0.0)
            .collect(),
    }
}

/// The V-carve depth at half-width `r` for a V-bit of included angle `angle`:
/// z = −r·cot(θ/2), capped at `max_depth` (DESIGN "Toolpaths").
pub fn vcarve_depth(r: f64, angle: f64, max_depth: f64) -> f64 {
    -(r / (angle / 2.0).tan()).min(max_depth)
}

/// The part of an outline deeper than a V-bit's cap: points farther than
/// max_depth·tan(θ/2) from the boundary, cleared flat at the cap.
pub fn vcarve_flat_region(outline: &Region, angle: f64, max_depth: f64, eps: f64) -> Region {
    outline.offset(-max_depth * (angle / 2.0).tan(), eps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::interop::pline_from_points;
    use cavalier_contours::polyline::PlineSourceMut;
    use std::f64::consts::PI;

    /// Area of the convex hull of two disks (closed form): with cos α = (r₀ − r₁)/d, the
    /// sector of disk 0 outside the tangents spans 2π − 2α, that of disk 1 spans 2α, and
    /// the two right trapezoids between centres and tangent points have parallel sides r₀,
    /// r₁ and height d·sin α.
    fn hull_area(a: &Circle, b: &Circle) -> f64 {
        let d = a.c.distance(b.c);
        let alpha = ((a.r - b.r) / d).acos();
        a.r * a.r * (PI - alpha) + b.r * b.r * alpha + (a.r + b.r) * d * alpha.sin()
    }

    #[test]
    fn swept_disks_match_closed_forms_reversed_and_moved() {
        let tol = 1e-4;
        let a = Circle::new(DVec2::new(1.0, 2.0), 3.0);
        let b = Circle::new(DVec2::new(9.0, -4.0), 1.5);
        let area = swept_disks(&[a, b], tol).area();
        let exact = hull_area(&a, &b);
        let perimeter = 2.0 * PI * 3.0 + 20.0;
        assert!(
            area <= exact + 1e-9 && area >= exact - tol * perimeter,
            "{area} vs {exact}"
        );
        let back = swept_disks(&[b, a], tol).area();
        assert!((back - area).abs() <= tol * perimeter);
        let shift = DVec2::new(1e4, -5e3);
        let moved = [Circle::new(a.c + shift, a.r), Circle::new(b.c + shift, b.r)];
        assert!((swept_disks(&moved, tol).area() - area).abs() <= tol * perimeter);
        // One disk inside the other: the larger disk alone.
        let inner = Circle::new(DVec2::new(1.5, 2.0), 1.0);
        let one = swept_disks(&[a, inner], tol).area();
        assert!((one - PI * 9.0).abs() <= tol * 2.0 * PI * 3.0);
    }

    #[test]
    fn swept_disks_of_a_closed_ring_keep_the_hole() {
        // 64 disks of radius 1 on a circle of radius 10: an annulus 9..11 (up to the
        // straight chords between the centres, which move the inner edge by < 0.05).
        let n = 64;
        let disks: Vec<Circle> = (0..=n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                Circle::new(10.0 * DVec2::new(a.cos(), a.sin()), 1.0)
            })
            .collect();
        let r = swept_disks(&disks, 1e-3);
        assert_eq!(r.contours.len(), 2);
        assert!(!r.contains(DVec2::ZERO) && r.contains(DVec2::new(10.0, 0.0)));
        let annulus = PI * (121.0 - 81.0);
        assert!(
            (r.area() - annulus).abs() < 0.05 * 2.0 * PI * 10.0,
            "{}",
            r.area()
        );
    }

    fn square_region(s: f64) -> Region {
        Region::from_contours(vec![pline_from_points(
            &[
                DVec2::new(0.0, 0.0),
                DVec2::new(s, 0.0),
                DVec2::new(s, s),
                DVec2::new(0.0, s),
            ],
            true,
        )])
    }

    #[test]
    fn profile_outside_is_at_tool_radius() {
        let r = square_region(10.0);
        let paths = profile(&r, ProfileSide::Outside, 1.5, 1e-6);
        assert_eq!(paths.len(), 1);
        // Every point of the offset is 1.5 from the square (distance to its boundary).
        let sq = [
            DVec2::new(0.0, 0.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(10.0, 10.0),
            DVec2::new(0.0, 10.0),
        ];
        for p in paths[0].flatten(1e-4) {
            let d = (0..4)
                .map(|i| Line::new(sq[i], sq[(i + 1) % 4]).distance(p))
                .fold(f64::INFINITY, f64::min);
            assert!((d - 1.5).abs() < 1e-3, "{p} at {d}");
        }
        // Climb: clockwise around material.
        assert!(crate::geom::path::polygon_area(&paths[0].flatten(1e-3)) < 0.0);
    }

    #[test]
    fn hatch_sweep_matches_a_scan_of_every_edge_and_counts_its_lines() {
        // A star with a hole: each line's crossings by the sweep equal those of a plain
        // scan of every edge at the same y (the O(L·E) method the sweep replaced).
        let star: Vec<DVec2> = (0..40)
            .map(|i| {
                let a = i as f64 * PI / 20.0;
                let r = if i % 2 == 0 {
                    10.0
                } else {
                    4.0 + 0.1 * i as f64
                };
                DVec2::new(r * a.cos(), r * a.sin())
            })
            .collect();
        let hole: Vec<DVec2> = (0..7)
            .rev()
            .map(|i| {
                let a = i as f64 * 2.0 * PI / 7.0;
                DVec2::new(2.0 * a.cos(), 2.0 * a.sin())
            })
            .collect();
        let r = Region::from_contours(vec![
            pline_from_points(&star, true),
            pline_from_points(&hole, true),
        ]);
        let spacing = 0.37;
        let lines = hatch(&r, 0.0, spacing, false, 1e-3);
        let polys: Vec<Vec<DVec2>> = r.contours.iter().map(|c| flatten_pline(c, 1e-3)).collect();
        let lo = polys
            .iter()
            .flatten()
            .map(|p| p.y)
            .fold(f64::INFINITY, f64::min);
        let hi = polys
            .iter()
            .flatten()
            .map(|p| p.y)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut want = Vec::new();
        let mut k = 0;
        loop {
            let y = lo + spacing / 2.0 + k as f64 * spacing;
            if y >= hi {
                break;
            }
            let mut xs: Vec<f64> = Vec::new();
            for poly in &polys {
                for i in 0..poly.len() {
                    let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                    if (a.y <= y) != (b.y <= y) {
                        xs.push(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
                    }
                }
            }
            xs.sort_by(f64::total_cmp);
            want.extend(
                xs.chunks_exact(2)
                    .filter(|w| w[1] > w[0])
                    .map(|w| (w[0], w[1], y)),
            );
            k += 1;
        }
        let got: Vec<(f64, f64, f64)> = lines
            .iter()
            .map(|p| {
                let (a, b) = (p.start().unwrap(), p.end().unwrap());
                (a.x, b.x, a.y)
            })
            .collect();
        assert_eq!(got, want);
        assert_eq!(
            hatch_line_count(std::slice::from_ref(&r), 0.0, spacing),
            k as f64
        );
        assert!(ring_count_bound(&[r], spacing) >= (10.0 / spacing).floor());
    }

    #[test]
    fn hatch_lines_lie_inside_and_cover_area() {
        // A square with a square hole: hatch length ≈ area / spacing.
        let outer = pline_from_points(
            &[
                DVec2::new(0.0, 0.0),
                DVec2::new(20.0, 0.0),
                DVec2::new(20.0, 20.0),
                DVec2::new(0.0, 20.0),
            ],
            true,
        );
        let hole = pline_from_points(
            &[
                DVec2::new(5.0, 5.0),
                DVec2::new(15.0, 5.0),
                DVec2::new(15.0, 15.0),
                DVec2::new(5.0, 15.0),
            ],
            true,
        );
        let r = Region::from_contours(vec![outer, hole]);
        for angle in [0.0, 0.3, PI / 4.0, 1.2] {
            let lines = hatch(&r, angle, 0.5, true, 1e-3);
            let total: f64 = lines.iter().map(|p| p.length(1e-9)).sum();
            assert!(
                (total * 0.5 - 300.0).abs() < 0.05 * 300.0,
                "angle {angle}: {total}"
            );
            for l in &lines {
                for i in 1..10 {
                    let p = l.segs[0].eval(i as f64 / 10.0);
                    assert!(r.contains(p), "hatch point {p} outside");
                }
            }
        }
    }

    #[test]
    fn concentric_rings_never_cross_and_shrink() {
        let r = square_region(20.0);
        let rings = concentric(&r, 1.0, 1.0, 0.5, 100, 1e-6);
        // Side 20 shrinks by 2 per ring: sides 18, 16, …, 2; the tenth ring vanishes.
        assert_eq!(rings.len(), 9);
        // A tool reaching 3 to each side has cleared the square once offset + 3 ≥ 10:
        // the ring at offset 7 is the last.
        assert_eq!(concentric(&r, 1.0, 1.0, 3.0, 100, 1e-6).len(), 7);
        let areas: Vec<f64> = rings
            .iter()
            .map(|p| crate::geom::path::polygon_area(&p.flatten(1e-3)).abs())
            .collect();
        assert!(areas.windows(2).all(|w| w[1] < w[0]));
    }

    /// Distance from `p` to the nearest point of any of `paths` (flattened within 1e-4,
    /// closing edges included: `flatten` does not repeat a closed path's first point).
    fn distance_to_paths(p: DVec2, paths: &[Path]) -> f64 {
        let mut best = f64::INFINITY;
        for path in paths {
            let mut pts = path.flatten(1e-4);
            if path.closed {
                pts.extend(pts.first().copied());
            }
            for w in pts.windows(2) {
                let (a, b) = (w[0], w[1]);
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
                best = best.min(p.distance(a + ab * t));
            }
        }
        best
    }

    /// The smallest distance between two points of one ring that lie farther apart than
    /// `gap` along it (how close the ring comes to touching itself).
    fn self_clearance(path: &Path, gap: f64) -> f64 {
        let pts = path.flatten(1e-4);
        let mut along = vec![0.0];
        for w in pts.windows(2) {
            along.push(along.last().unwrap() + w[0].distance(w[1]));
        }
        let total = *along.last().unwrap();
        let mut best = f64::INFINITY;
        for i in 0..pts.len() {
            for j in i + 1..pts.len() {
                let s = (along[j] - along[i]).min(total - (along[j] - along[i]));
                if s > gap {
                    best = best.min(pts[i].distance(pts[j]));
                }
            }
        }
        best
    }

    #[test]
    fn concentric_channel_has_no_sliver_ring_and_clears_everything() {
        // A channel of half-width h = 1.8·r + 0.04 along a V of two gently curved arms
        // (polylines, as a flattened spine is) with a 60° bend: the offset at r + 0.8·r is
        // a fat patch at the bend, where the inner corner lies (h + h/sin 30°)/2 = 1.5·h >
        // 2r from the walls, out of the first ring's reach, plus spurs 0.08 wide along both
        // arms. The second ring must clear the patch and leave the spurs out.
        let (r, step) = (1.5875, 0.8 * 1.5875);
        let h = r + step + 0.04;
        let arm = |from: DVec2, to: DVec2| -> Vec<DVec2> {
            let n = (to - from).normalize().perp();
            (0..=40)
                .map(|i| {
                    let t = i as f64 / 40.0;
                    from.lerp(to, t) + n * (3.0 * t * (1.0 - t))
                })
                .collect()
        };
        let bend = DVec2::new(40.0, 0.0);
        let mut spine = arm(DVec2::ZERO, bend);
        spine.extend(
            arm(bend, DVec2::new(20.0, 20.0 * 3f64.sqrt()))
                .into_iter()
                .skip(1),
        );
        // The build's tolerances: 0.01 mm, offsets to a tenth of it.
        let region = swept_region(&spine, false, h, 1e-2);
        let rings = concentric(&region, r, step, r, 100, 1e-3);
        assert!(
            rings.len() >= 2,
            "the bend needs a second ring: {}",
            rings.len()
        );
        // No ring comes within 0.1 mm of itself away from its own neighbourhood.
        for (k, ring) in rings.iter().enumerate().skip(1) {
            let c = self_clearance(ring, 1.0);
            assert!(c > 0.1, "ring {k} comes {c} from itself");
        }
        // Every point of the region lies within the tool's reach of a ring (a 0.5 mm grid,
        // within the region's flattening and offset accuracy).
        let mut y = -h - 3.0;
        while y <= 35.0 + h {
            let mut x = -h;
            while x <= 43.0 + h {
                let p = DVec2::new(x, y);
                if region.contains(p) {
                    let d = distance_to_paths(p, &rings);
                    assert!(d <= r + 2e-2, "{p} is {d} from every ring");
                }
                x += 0.5;
            }
            y += 0.5;
        }
    }

    #[test]
    fn backboard_closes_gaps_and_has_no_holes() {
        let a = square_region(10.0);
        let mut b = square_region(10.0);
        for c in &mut b.contours {
            c.translate_mut(13.0, 0.0);
        }
        let bb = backboard(&[a, b], 2.0, 1.0, 1e-3, 1e-6);
        assert_eq!(bb.contours.len(), 1, "the 3 mm gap closes at margin 2");
        assert!(bb.area() > 23.0 * 10.0);
    }

    #[test]
    fn vcarve_depth_closed_form() {
        // 90° bit: depth equals half-width.
        assert!((vcarve_depth(1.5, PI / 2.0, 10.0) + 1.5).abs() < 1e-12);
        // 60° bit: depth = r·cot(30°) = r√3, capped.
        assert!((vcarve_depth(1.0, PI / 3.0, 10.0) + 3f64.sqrt()).abs() < 1e-12);
        assert_eq!(vcarve_depth(10.0, PI / 3.0, 2.0), -2.0);
    }

    #[test]
    fn swept_region_area_of_straight_channel() {
        // Stadium: length·w + π(w/2)².
        let r = swept_region(&[DVec2::ZERO, DVec2::new(30.0, 0.0)], false, 2.0, 1e-3);
        let expect = 30.0 * 4.0 + PI * 4.0;
        assert!((r.area() - expect).abs() < 0.01 * expect, "{}", r.area());
    }
}
