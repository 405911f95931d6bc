//! Regions: sets of closed contours made of lines and arcs, the shapes toolpaths are cut
//! around. Contours are cavalier_contours polylines (arcs as bulges, b = tan(θ/4)) oriented
//! like cavalier's `Shape`: material counter-clockwise, holes clockwise.
//!
//! - Conversion from geometric paths: cubics become biarc chains within a tolerance
//!   ([`super::biarc`]), so arcs stay arcs all the way to G2/G3.
//! - Offsets: cavalier_contours' shape offset (exact for lines and arcs, islands handled).
//! - Union of overlapping regions (letters drawn with crossing strokes): geo's BooleanOps on
//!   the contours flattened within the tolerance; the result is lines only. Regions that
//!   lie apart can be joined as they are, arcs kept ([`Region::union_keeping_arcs`]).
//!
//! Complexity: offsets O(n log n) in the number of segments (cavalier's spatial index);
//! union O((n + k) log n) (i_overlay sweep).

use super::biarc::fit_cubic;
pub(crate) use super::rings::degenerate;
use super::rings::{despike, drop_repeated_rings, simplify_ring, single_traversal};
use crate::geom::index::WindingIndex;
use crate::geom::interop::{self, push_line_or_arc};
pub use crate::geom::interop::{flatten_pline, path_from_pline, pline_from_points};
use crate::geom::{Aabb, DVec2, Path, PathSeg};
use crate::geom::{path_self_intersections, paths_intersections};
use cavalier_contours::polyline::{PlineSource, PlineSourceMut, Polyline};
use cavalier_contours::shape_algorithms::{Shape, ShapeOffsetOptions};
use rstar::RTree;
use rstar::primitives::{GeomWithData, Rectangle};

/// Most regions [`Region::union_pairwise`] unites in one overlay. A few overlapping rings
/// are one overlay's cheapest case (the repairs of the shipped examples have 2 to 6 pieces);
/// the overlay's long work begins with dozens of nearly coincident rings (40 of them took
/// 1.2 s in a debug build, 67 took 35 s in release), which the tree unites in milliseconds.
const ONE_OVERLAY_MAX_REGIONS: usize = 8;

/// Closed contours of a region: counter-clockwise material, clockwise holes.
#[derive(Clone, Debug, Default)]
pub struct Region {
    /// The contours, each closed.
    pub contours: Vec<Polyline<f64>>,
}

/// Vertices closer than this fraction of the tolerance are one vertex, and a vertex between
/// two lines that lies nearer than this fraction of the tolerance to the chord of its
/// neighbours is dropped ([`simplify_ring`]). It must exceed the position tolerance the
/// offsets use (`eps`·0.1 = tolerance·0.01, see [`Region::offset`] and the build's
/// `eps = tolerance·0.1`): cavalier_contours keeps vertices 1.5 × its position tolerance
/// apart as distinct and then joins offset slices at them into zero-area two-vertex
/// contours (such a pair can lie 1.5e-4 apart at tolerance 1e-2).
pub const REPEAT_FRACTION: f64 = 0.05;

/// A polyline from a path, closed when the path is (an open one ends with the path's end
/// point); cubics become biarcs within `tol`.
pub fn pline_from_path(path: &Path, tol: f64) -> Polyline<f64> {
    let mut pl = Polyline::new_closed();
    for seg in &path.segs {
        match seg {
            PathSeg::Cubic(c) => {
                for s in fit_cubic(c, tol) {
                    push_line_or_arc(&mut pl, &s);
                }
            }
            other => push_line_or_arc(&mut pl, other),
        }
    }
    pl.set_is_closed(path.closed);
    if let (false, Some(end)) = (path.closed, path.end()) {
        pl.add(end.x, end.y, 0.0);
    }
    // Repeated positions (a biarc joint on a path's own end point) relative to the
    // tolerance, so the result does not depend on the size or position of the path.
    pl.remove_repeat_pos(tol * REPEAT_FRACTION).unwrap_or(pl)
}

/// Winding numbers of contours about many points, one [`WindingIndex`] per contour (a
/// point outside a contour's height range costs one comparison), and an R-tree of the
/// contours' boxes ([`WindingIndex::bounds`], arcs' extremes included: cavalier's extents
/// miss those of arcs sweeping more than a half turn), outside which a contour winds 0
/// times: a point is asked of the contours whose box holds it, O(log n + c) for c such
/// contours instead of O(n).
struct Windings {
    each: Vec<WindingIndex>,
    /// Boxes of the contours with finite boxes (none for a contour without segments).
    tree: RTree<GeomWithData<Rectangle<[f64; 2]>, usize>>,
    /// Contours whose box is not finite: asked about every point.
    everywhere: Vec<usize>,
}

impl Windings {
    fn new(contours: &[Polyline<f64>]) -> Windings {
        let each: Vec<WindingIndex> = contours.iter().map(WindingIndex::new).collect();
        let mut boxes = Vec::new();
        let mut everywhere = Vec::new();
        for (k, w) in each.iter().enumerate() {
            match w.bounds() {
                Some(b) if b.min.is_finite() && b.max.is_finite() => {
                    boxes.push(GeomWithData::new(interop::rectangle(b), k));
                }
                Some(_) => everywhere.push(k),
                None => {}
            }
        }
        Windings {
            each,
            tree: RTree::bulk_load(boxes),
            everywhere,
        }
    }

    /// The contours that may wind about (x, y) (every other winds 0 times), in no order.
    fn around(&self, x: f64, y: f64) -> impl Iterator<Item = usize> + '_ {
        self.tree
            .locate_all_at_point([x, y])
            .map(|e| e.data)
            .chain(self.everywhere.iter().copied())
    }

    /// The winding number of contour `k` about (x, y).
    fn of(&self, k: usize, x: f64, y: f64) -> i32 {
        self.each
            .get(k)
            .map_or(0, |w| w.winding(interop::vector2(DVec2::new(x, y))))
    }

    /// The total winding number of the contours other than `skip` about (x, y).
    fn total(&self, x: f64, y: f64, skip: Option<usize>) -> i32 {
        self.around(x, y)
            .filter(|&k| Some(k) != skip)
            .map(|k| self.of(k, x, y))
            .sum()
    }
}

/// Fraction of the offset accuracy `eps` within which [`Region::simple`] counts two
/// segments as meeting, as the offset checks use it. Rings that share an edge or cross meet
/// exactly; a whole `eps` would also catch the segments on either side of an arc shorter
/// than `eps`, which the rounded joins of an offset are full of.
pub const MEET_FRACTION: f64 = 1e-3;

impl Region {
    /// A region from closed contours in any orientation and nesting: contours at even
    /// nesting depth become material (counter-clockwise), odd depth holes (clockwise).
    /// Contours must not cross each other (outlines from the skin stage do not).
    pub fn from_contours(contours: Vec<Polyline<f64>>) -> Region {
        let windings = Windings::new(&contours);
        let depth: Vec<usize> = contours
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let Some(v) = c.iter_vertexes().next() else {
                    return 0;
                };
                windings
                    .around(v.x, v.y)
                    .filter(|&j| j != i && windings.of(j, v.x, v.y) != 0)
                    .count()
            })
            .collect();
        let contours = contours
            .into_iter()
            .zip(depth)
            .filter(|(c, _)| c.vertex_count() > 1)
            .map(|(mut c, d)| {
                let ccw = c.area() > 0.0;
                if ccw != (d % 2 == 0) {
                    c.invert_direction_mut();
                }
                c
            })
            .collect();
        Region { contours }
    }

    /// A region from closed paths (cubics fitted by biarcs within `tol`).
    pub fn from_paths(paths: &[Path], tol: f64) -> Region {
        Region::from_contours(paths.iter().map(|p| pline_from_path(p, tol)).collect())
    }

    /// True when the region has no contours.
    pub fn is_empty(&self) -> bool {
        self.contours.is_empty()
    }

    /// Signed area: material minus holes.
    pub fn area(&self) -> f64 {
        self.contours.iter().map(|c| c.area()).sum()
    }

    /// Total length of the contours (arcs exact).
    pub fn perimeter(&self) -> f64 {
        self.contours.iter().map(|c| c.path_length()).sum()
    }

    /// The region grown by `delta` (shrunk when negative): every boundary moves `delta` along
    /// its outward normal; arcs stay arcs, convex corners get round joins (cavalier_contours
    /// shape offset). `eps` is the position tolerance for joining offset slices. A ring
    /// returned traversed more than once is traversed once ([`single_traversal`]), and a
    /// ring returned more than once is kept once ([`drop_repeated_rings`]).
    pub fn offset(&self, delta: f64, eps: f64) -> Region {
        if self.contours.is_empty() || delta == 0.0 {
            return self.clone();
        }
        // Centre the coordinates first: cavalier's intersection and join tests compare
        // absolute differences, so a region far from the origin would lose digits (a job
        // at x = 10 000 has 4 fewer significant digits than one at the origin).
        let c = self.center();
        let moved = self.translated(-c);
        let shape = Shape::from_plines(moved.contours.iter().cloned());
        // Passes of one ring, and copies of a ring, that cavalier returns differ by up to a
        // few `eps` (2e-3 at eps = 1e-3 has been seen); within 10·eps (the
        // build's arc tolerance) they are one path for the tool.
        let near = 10.0 * eps;
        let opts = ShapeOffsetOptions {
            pos_equal_eps: eps * 0.1,
            offset_dist_eps: eps,
            slice_join_eps: eps,
        };
        // cavalier offsets to the left of travel: inward for counter-clockwise material.
        let out = shape.parallel_offset(-delta, &opts);
        let rings = out
            .ccw_plines
            .into_iter()
            .chain(out.cw_plines)
            .map(|ip| single_traversal(&despike(&ip.polyline, eps, near), eps * 0.1, near))
            .filter(|pl| !degenerate(pl, eps))
            .collect();
        Region {
            contours: drop_repeated_rings(rings, eps * 0.1, near),
        }
        .translated(c)
    }

    /// [`Region::offset`], checked ([`Region::sound_offset`]): the result must be
    /// [`simple`](Region::simple), nest as a region should and keep apart from this
    /// region's boundary; a grown region must hold every vertex (and segment middle) of
    /// this one and have none of its own inside it, a shrunk one must lie inside it
    /// (offsets are monotone, and an offset curve lies |δ| from this region's boundary, on
    /// the side it moved to). Where
    /// cavalier_contours' result fails that (it can nest one ring in another, split a
    /// region along a chord or loop a ring over itself when its input is dense, as the
    /// union of a stroke's disks is), the offset is made by geo's buffer
    /// ([`Region::buffered`]) instead, with arcs flattened within `tol`. Cost of the check:
    /// winding tests of the V vertices in against the W segments out (and back) through
    /// slab indexes, O(V + W) plus the segments met in the slabs, and the segment tests of
    /// [`Region::simple`] and [`Region::apart_from`].
    ///
    /// A large region grown by `delta` has its narrow valleys closed first
    /// ([`super::valleys::fill_narrow_valleys`], within `tol` of the exact offset); the
    /// result is still checked against this region.
    pub fn offset_checked(&self, delta: f64, eps: f64, tol: f64) -> Region {
        if let Some(filled) = super::valleys::fill_narrow_valleys(self, delta, tol) {
            let out = filled.offset(delta, eps);
            return if self.sound_offset(&out, delta, eps) {
                out
            } else {
                filled.buffered(delta, tol)
            };
        }
        self.checked_offset(self.offset(delta, eps), delta, eps, tol)
    }

    /// `out`, this region's [`Region::offset`] by `delta` at accuracy `eps`, when it passes
    /// the checks of [`Region::offset_checked`]; else geo's buffer flattened within `tol`.
    pub fn checked_offset(&self, out: Region, delta: f64, eps: f64, tol: f64) -> Region {
        if self.sound_offset(&out, delta, eps) {
            out
        } else {
            self.buffered(delta, tol)
        }
    }

    /// Whether `out` can be this region offset by `delta` at accuracy `eps`: it nests as a
    /// region should, lies on the side it moved to (grown: holds every vertex and segment
    /// middle of this region and has none of its own inside it; shrunk: lies in this
    /// region's material), is [simple](Region::simple) and keeps
    /// [apart from](Region::apart_from) this region's boundary (within
    /// [`MEET_FRACTION`]·`eps`).
    pub fn sound_offset(&self, out: &Region, delta: f64, eps: f64) -> bool {
        let meet = eps * MEET_FRACTION;
        let sided = if delta > 0.0 {
            out.holds(self) && self.excludes(out)
        } else {
            self.holds(out)
        };
        sided && out.simple(meet) && out.apart_from(self, meet)
    }

    /// Whether this region nests as a region should (`well_nested`: material and holes
    /// alternate) and every vertex and segment midpoint of `other` lies in its material
    /// (winding number 1). The midpoints catch a shrunk ring that cuts across a hole or a
    /// notch with one chord whose ends both lie in the material (cavalier's offset of the
    /// dense union of overlapping script strokes did, 14 mm across a letter's counter).
    pub fn holds(&self, other: &Region) -> bool {
        self.well_nested() && self.winds_every_sample(std::slice::from_ref(other), |w| w == 1)
    }

    /// Whether every contour is simple and no two meet within `tol`: no contour crosses or
    /// touches itself (a grown board can come back as one ring looping over itself across a
    /// channel), and rings that share an edge, which pass every vertex test, are caught too
    /// (a grown board can come back as two rings split along a chord through a channel).
    /// Either way the profile would cut the channel. Pairs are prefiltered by bounding boxes; segments are tested through
    /// [`path_self_intersections`] and [`paths_intersections`] (bounding-volume trees).
    pub fn simple(&self, tol: f64) -> bool {
        let paths = self.paths();
        if paths
            .iter()
            .any(|p| !path_self_intersections(p, tol).is_empty())
        {
            return false;
        }
        let boxes = self.boxes(tol);
        (0..paths.len()).all(|i| {
            (i + 1..paths.len()).all(|j| !meet(&paths[i], boxes[i], &paths[j], boxes[j], tol))
        })
    }

    /// Whether no contour of this region meets (within `tol`) a contour of `other`: a ring
    /// shrunk from `other` that passes this and [`Region::holds`] lies in its material
    /// without touching its boundary (a chord across a hole of the dense union of script
    /// strokes had both ends and its middle in the material and crossed the hole's edge).
    /// Pairs prefiltered by bounding boxes, segments tested as in [`Region::simple`].
    pub fn apart_from(&self, other: &Region, tol: f64) -> bool {
        let (paths, others) = (self.paths(), other.paths());
        let (boxes, other_boxes) = (self.boxes(tol), other.boxes(tol));
        paths.iter().zip(&boxes).all(|(p, &b)| {
            others
                .iter()
                .zip(&other_boxes)
                .all(|(q, &c)| !meet(p, b, q, c, tol))
        })
    }

    /// The bounding box of the contours, arcs included (None without contours).
    #[must_use]
    pub fn bounds(&self) -> Option<Aabb> {
        self.boxes(0.0).into_iter().flatten().reduce(Aabb::union)
    }

    /// Each contour's bounding box grown by `tol` (None for an empty contour).
    fn boxes(&self, tol: f64) -> Vec<Option<Aabb>> {
        self.contours
            .iter()
            .map(|c| {
                c.extents().map(|b| {
                    Aabb::new(DVec2::new(b.min_x, b.min_y), DVec2::new(b.max_x, b.max_y)).grow(tol)
                })
            })
            .collect()
    }

    /// Whether no vertex or segment midpoint of `other` lies in this region's material
    /// (winding number 0).
    pub fn excludes(&self, other: &Region) -> bool {
        self.winds_every_sample(std::slice::from_ref(other), |w| w == 0)
    }

    /// Whether every vertex and segment midpoint of every region of `others` lies in this
    /// region's material ([`Region::contains`]: non-zero total winding), asked through one
    /// index.
    pub fn contains_samples_of(&self, others: &[Region]) -> bool {
        self.winds_every_sample(others, |w| w != 0)
    }

    /// Whether this region's total winding number about every vertex of `others`, and the
    /// midpoint of every segment (line or arc), passes `ok`, each contour asked through a
    /// [`WindingIndex`] (the same number as cavalier's `winding_number`): O(W) to build and
    /// O(1 + k) per point for the k segments in its slab, instead of O(V·W).
    fn winds_every_sample(&self, others: &[Region], ok: impl Fn(i32) -> bool) -> bool {
        let windings = Windings::new(&self.contours);
        let passes = |x: f64, y: f64| ok(windings.total(x, y, None));
        others
            .iter()
            .flat_map(|o| &o.contours)
            .flat_map(|c| c.iter_segments())
            .all(|(v1, v2)| {
                let m = cavalier_contours::polyline::seg_midpoint(v1, v2);
                passes(v1.x, v1.y) && passes(m.x, m.y)
            })
    }

    /// Whether the contours nest as material and holes should: a counter-clockwise contour
    /// lies where the others wind 0 times (outside, or in a hole), a clockwise one where
    /// they wind once (in material). Tested at each contour's first vertex.
    pub(crate) fn well_nested(&self) -> bool {
        let windings = Windings::new(&self.contours);
        self.contours.iter().enumerate().all(|(i, c)| {
            let Some(v) = c.iter_vertexes().next() else {
                return true;
            };
            let others = windings.total(v.x, v.y, Some(i));
            others == if c.area() > 0.0 { 0 } else { 1 }
        })
    }

    /// The region grown by `delta` (shrunk when negative) through geo's buffer (i_overlay)
    /// with round joins whose chords stay within `tol` of the arc (step φ = √(8·tol/|δ|),
    /// as in [`super::ops::swept_region`]); coordinates centred first, lines only.
    pub fn buffered(&self, delta: f64, tol: f64) -> Region {
        use geo::Buffer;
        use geo::algorithm::buffer::{BufferStyle, LineJoin};
        if self.contours.is_empty() || delta == 0.0 {
            return self.clone();
        }
        let c = self.center();
        let phi = (8.0 * tol / delta.abs()).sqrt().min(1.0);
        let style = BufferStyle::new(delta).line_join(LineJoin::Round(phi));
        let grown = self.translated(-c).to_geo(tol).buffer_with_style(style);
        Region::from_geo(&grown, tol).translated(c)
    }

    /// Centre of the bounding box of the vertices (zero for an empty region).
    pub fn center(&self) -> DVec2 {
        let b = (self.contours.iter().flat_map(|c| c.iter_vertexes()))
            .fold(Aabb::EMPTY, |b, v| b.add_point(interop::vertex_point(&v)));
        if b.min.x <= b.max.x {
            b.center()
        } else {
            DVec2::ZERO
        }
    }

    /// The region moved by `d`.
    pub fn translated(&self, d: DVec2) -> Region {
        let mut out = self.clone();
        for c in &mut out.contours {
            for i in 0..c.vertex_count() {
                if let Some(mut v) = c.get(i) {
                    v.x += d.x;
                    v.y += d.y;
                    c.set_vertex(i, v);
                }
            }
        }
        out
    }

    /// The union of several regions, keeping the arcs of regions that lie apart: when their
    /// contours together are [simple](Region::simple) within `tol` and
    /// well nested (no boundary meets another, none lies in another's
    /// material) they are the union as they are; otherwise [`Region::union`].
    pub fn union_keeping_arcs(regions: &[Region], tol: f64) -> Region {
        let together = Region {
            contours: regions.iter().flat_map(|r| r.contours.clone()).collect(),
        };
        if together.well_nested() && together.simple(tol) {
            together
        } else {
            Region::union(regions, tol)
        }
    }

    /// The union of several regions, through polygons flattened within `tol`: one
    /// i_overlay overlay of all their rings (geo's `unary_union`). For regions that may
    /// pile up in one place, [`Region::union_pairwise`].
    pub fn union(regions: &[Region], tol: f64) -> Region {
        let polys: Vec<geo::MultiPolygon<f64>> = regions.iter().map(|r| r.to_geo(tol)).collect();
        let merged = geo::algorithm::bool_ops::unary_union(polys.iter());
        Region::from_geo(&merged, tol)
    }

    /// The union of several regions united two at a time in a balanced tree (⌈log₂ n⌉
    /// levels of i_overlay unions, fill rule non-zero), through polygons flattened within
    /// `tol`; up to [`ONE_OVERLAY_MAX_REGIONS`] regions in one overlay, as
    /// [`Region::union`]. For many regions that overlap in one place, such as the pieces of
    /// a repaired stroke where a place keeps failing (dozens of nearly coincident disks):
    /// one overlay of all their rings sends i_overlay's split solver into long work (67
    /// such rings, 2,983 vertices: 35 s), the tree takes milliseconds for the same area.
    /// For many regions that lie mostly apart, [`Region::union`] is the cheaper (one pass
    /// over the vertices instead of one per level).
    pub fn union_pairwise(regions: &[Region], tol: f64) -> Region {
        if regions.len() <= ONE_OVERLAY_MAX_REGIONS {
            return Region::union(regions, tol);
        }
        let mut level: Vec<geo::MultiPolygon<f64>> =
            regions.iter().map(|r| r.to_geo(tol)).collect();
        while level.len() > 1 {
            level = level
                .chunks(2)
                .map(|pair| match pair {
                    [a, b] => geo::BooleanOps::boolean_op_with_fill_rule(
                        a,
                        b,
                        geo::algorithm::bool_ops::OpType::Union,
                        geo::algorithm::bool_ops::FillRule::NonZero,
                    ),
                    _ => pair[0].clone(),
                })
                .collect();
        }
        Region::from_geo(&level[0], tol)
    }

    /// The region bounded by closed paths that may cross themselves and each other (a
    /// stroke whose spine crosses itself): the points of non-zero total winding, i.e. the
    /// union of the lobes, with counter-clockwise material and clockwise holes. The paths
    /// are flattened within `tol`; the result has lines only.
    pub fn from_overlapping_paths(paths: &[Path], tol: f64) -> Region {
        Region::from_overlapping_rings(paths.iter().map(|p| p.flatten(tol)).collect(), tol)
    }

    /// The points of non-zero total winding of closed polygons (last vertex joined to the
    /// first) that may cross themselves and each other: their union, with
    /// counter-clockwise material and clockwise holes (i_overlay through geo's
    /// `BooleanOps`, fill rule non-zero). `tol` is the tolerance of the result's cleaning.
    pub fn from_overlapping_rings(rings: Vec<Vec<DVec2>>, tol: f64) -> Region {
        let polys = geo::MultiPolygon::new(
            rings
                .into_iter()
                .map(|ring| geo::Polygon::new(interop::ring_line_string(ring), vec![]))
                .collect(),
        );
        let empty = geo::MultiPolygon::<f64>::new(vec![]);
        let merged = geo::BooleanOps::boolean_op_with_fill_rule(
            &polys,
            &empty,
            geo::algorithm::bool_ops::OpType::Union,
            geo::algorithm::bool_ops::FillRule::NonZero,
        );
        Region::from_geo(&merged, tol)
    }

    /// The region as geo polygons (contours flattened within `tol`).
    pub fn to_geo(&self, tol: f64) -> geo::MultiPolygon<f64> {
        let ring = |c: &Polyline<f64>| interop::ring_line_string(flatten_pline(c, tol));
        let outers: Vec<&Polyline<f64>> = self.contours.iter().filter(|c| c.area() > 0.0).collect();
        let holes: Vec<&Polyline<f64>> = self.contours.iter().filter(|c| c.area() <= 0.0).collect();
        let mut polys: Vec<geo::Polygon<f64>> = outers
            .iter()
            .map(|o| geo::Polygon::new(ring(o), vec![]))
            .collect();
        for h in holes {
            let Some(v) = h.iter_vertexes().next() else {
                continue;
            };
            // The smallest outer contour that contains the hole owns it.
            let owner = outers
                .iter()
                .enumerate()
                .filter(|(_, o)| o.winding_number(v.pos()) != 0)
                .min_by(|a, b| a.1.area().total_cmp(&b.1.area()))
                .map(|(i, _)| i);
            if let Some(i) = owner {
                polys[i].interiors_push(ring(h));
            }
        }
        geo::MultiPolygon::new(polys)
    }

    /// A region from geo polygons (lines only) whose rings were flattened within `tol`.
    /// Rings are cleaned of spikes (zero-width there-and-back excursions a polygon boolean
    /// may leave), so no tool path retraces itself, and of vertices within
    /// [`REPEAT_FRACTION`]·`tol` of their neighbours or of the chord between them
    /// ([`simplify_ring`]), which offsets would turn into degenerate slivers, and of hairs
    /// narrower than `tol` ([`despike`]).
    pub fn from_geo(mp: &geo::MultiPolygon<f64>, tol: f64) -> Region {
        let mut contours = Vec::new();
        let conv = |ls: &geo::LineString<f64>| {
            let pts = interop::ring_points(ls);
            // Zigzags of a few µm along a boundary (a laser channel's union can go back and
            // forth 0.03 mm several times) are hairs too.
            despike(
                &pline_from_points(&simplify_ring(pts, tol * REPEAT_FRACTION), true),
                tol * 0.1,
                tol,
            )
        };
        for p in &mp.0 {
            contours.push(conv(p.exterior()));
            for h in p.interiors() {
                contours.push(conv(h));
            }
        }
        Region::from_contours(
            contours
                .into_iter()
                .filter(|c| c.vertex_count() >= 3)
                .collect(),
        )
    }

    /// True when `p` is inside the material (non-zero total winding).
    pub fn contains(&self, p: DVec2) -> bool {
        let v = interop::vector2(p);
        self.contours
            .iter()
            .map(|c| c.winding_number(v))
            .sum::<i32>()
            != 0
    }

    /// The contours as paths (lines and arcs).
    pub fn paths(&self) -> Vec<Path> {
        self.contours.iter().map(path_from_pline).collect()
    }
}

/// Whether the paths `a` and `b`, with bounding boxes `ba` and `bb` grown by `tol`, meet
/// within `tol` (boxes first, then the segments through bounding-volume trees).
fn meet(a: &Path, ba: Option<Aabb>, b: &Path, bb: Option<Aabb>, tol: f64) -> bool {
    let (Some(ba), Some(bb)) = (ba, bb) else {
        return false;
    };
    ba.intersects(&bb) && !paths_intersections(a, b, tol).is_empty()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{CubicBez, Line};
    use std::f64::consts::PI;

    fn square(x0: f64, y0: f64, s: f64) -> Polyline<f64> {
        pline_from_points(
            &[
                DVec2::new(x0, y0),
                DVec2::new(x0 + s, y0),
                DVec2::new(x0 + s, y0 + s),
                DVec2::new(x0, y0 + s),
            ],
            true,
        )
    }

    #[test]
    fn outward_offset_of_square_has_rounded_corners_area() {
        // Square side a grown by d: a² + 4ad + πd² (Steiner formula).
        let r = Region::from_contours(vec![square(0.0, 0.0, 10.0)]);
        let g = r.offset(2.0, 1e-6);
        assert_eq!(g.contours.len(), 1);
        assert!(
            (g.area() - (100.0 + 80.0 + PI * 4.0)).abs() < 1e-6,
            "{}",
            g.area()
        );
        // Inward: (a − 2d)².
        let s = r.offset(-2.0, 1e-6);
        assert!((s.area() - 36.0).abs() < 1e-9);
    }

    /// Nesting found through the box R-tree is the nesting cavalier's own winding number
    /// gives asked of every other contour: circles (two half-turn arcs, or three arcs of a
    /// third of a turn whose vertices miss the circle's extremes) and squares, nested up to
    /// four deep and apart, given in either orientation.
    #[test]
    fn nesting_through_boxes_is_the_nesting_of_all_pairs() {
        use cavalier_contours::polyline::PlineSourceMut;
        let circle = |x: f64, y: f64, r: f64, thirds: bool| {
            let mut pl = Polyline::new_closed();
            if thirds {
                // Three arcs of 120° (bulge tan 30°), none through the circle's top.
                for k in 0..3 {
                    let a = 2.0 * PI * k as f64 / 3.0 + 0.3;
                    pl.add(x + r * a.cos(), y + r * a.sin(), (PI / 6.0).tan());
                }
            } else {
                pl.add(x + r, y, 1.0);
                pl.add(x - r, y, 1.0);
            }
            pl
        };
        // Cells 7 apart with up to three nested contours each, all in one big square.
        let mut contours = vec![square(-10.0, -10.0, 80.0)];
        for k in 0..40 {
            let (x, y) = ((k % 8) as f64 * 7.0, (k / 8) as f64 * 7.0);
            let mut cell = vec![circle(x, y, 3.0, k % 2 == 0)];
            match k % 3 {
                0 => cell.push(square(x - 1.0, y - 1.0, 2.0)),
                1 => {
                    cell.push(circle(x + 0.2, y, 1.5, false));
                    cell.push(square(x - 0.5, y - 0.2, 0.4));
                }
                _ => {}
            }
            for (m, mut c) in cell.into_iter().enumerate() {
                if (k + m) % 3 == 0 {
                    c.invert_direction_mut();
                }
                contours.push(c);
            }
        }
        let want: Vec<bool> = contours
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let v = c.iter_vertexes().next().expect("a vertex");
                let p = v.pos();
                let depth = (0..contours.len())
                    .filter(|&j| j != i && contours[j].winding_number(p) != 0)
                    .count();
                depth % 2 == 0
            })
            .collect();
        let r = Region::from_contours(contours);
        let got: Vec<bool> = r.contours.iter().map(|c| c.area() > 0.0).collect();
        assert_eq!(got, want);
        assert!(want.iter().any(|&w| !w) && want.iter().filter(|&&w| w).count() > 1);
        assert!(r.well_nested());
    }

    #[test]
    fn nesting_orients_holes_clockwise() {
        // Given both clockwise, the inner one becomes a hole.
        let mut outer = square(0.0, 0.0, 10.0);
        outer.invert_direction_mut();
        let mut inner = square(3.0, 3.0, 4.0);
        inner.invert_direction_mut();
        let r = Region::from_contours(vec![outer, inner]);
        assert!((r.area() - 84.0).abs() < 1e-12);
        assert!(r.contains(DVec2::new(1.0, 1.0)));
        assert!(!r.contains(DVec2::new(5.0, 5.0)));
        // Growing the ring shrinks the hole: hole side 4 − 2·1.
        let g = r.offset(1.0, 1e-6);
        let holes: Vec<f64> = g
            .contours
            .iter()
            .map(|c| c.area())
            .filter(|a| *a < 0.0)
            .collect();
        assert_eq!(holes.len(), 1);
        assert!((holes[0] + 4.0).abs() < 1e-9);
    }

    #[test]
    fn every_sample_test_agrees_with_contains() {
        // A ring with a hole and rounded (arc) corners from an offset; candidates inside,
        // in the hole, outside, and some with vertices on the boundary.
        let mut outer = square(0.0, 0.0, 10.0);
        outer.invert_direction_mut();
        let ring = Region::from_contours(vec![outer, square(3.0, 3.0, 4.0)]).offset(0.5, 1e-6);
        let candidates = [
            Region::from_contours(vec![square(0.5, 0.5, 1.0)]),
            Region::from_contours(vec![square(-0.4, 8.0, 1.0)]),
            Region::from_contours(vec![square(4.0, 4.0, 1.0)]),
            Region::from_contours(vec![square(2.0, 0.0, 0.5)]),
            Region::from_contours(vec![square(20.0, 20.0, 1.0)]),
            ring.offset(-0.25, 1e-6),
            ring.offset(0.25, 1e-6),
            // Every vertex in the material, the long sides across the hole.
            Region::from_contours(vec![pline_from_points(
                &[
                    DVec2::new(1.0, 5.0),
                    DVec2::new(9.0, 5.0),
                    DVec2::new(9.0, 5.1),
                    DVec2::new(1.0, 5.1),
                ],
                true,
            )]),
        ];
        let by_sample = |rs: &[Region]| {
            rs.iter().flat_map(|r| &r.contours).all(|c| {
                c.iter_segments().all(|(v1, v2)| {
                    let m = cavalier_contours::polyline::seg_midpoint(v1, v2);
                    ring.contains(DVec2::new(v1.x, v1.y)) && ring.contains(DVec2::new(m.x, m.y))
                })
            })
        };
        let mut seen = [false; 2];
        for k in 0..candidates.len() {
            for set in [&candidates[k..=k], &candidates[..=k]] {
                let want = by_sample(set);
                seen[usize::from(want)] = true;
                assert_eq!(ring.contains_samples_of(set), want, "candidates {k}");
            }
        }
        assert_eq!(seen, [true, true]);
    }

    #[test]
    fn figure_eight_resolves_to_two_lobes() {
        // A bow-tie ring crossing itself at the origin: two triangles of area 1 each
        // (non-zero winding keeps both lobes, whatever their orientation).
        let p = |x: f64, y: f64| DVec2::new(x, y);
        let pts = [p(-1.0, -1.0), p(1.0, 1.0), p(1.0, -1.0), p(-1.0, 1.0)];
        let path = Path::new(
            (0..4)
                .map(|i| PathSeg::Line(Line::new(pts[i], pts[(i + 1) % 4])))
                .collect(),
            true,
        );
        let r = Region::from_overlapping_paths(&[path], 1e-3);
        assert_eq!(r.contours.len(), 2);
        assert!((r.area() - 2.0).abs() < 1e-9, "{}", r.area());
    }

    /// geo's buffer of a square: area s² + 4sδ + πδ² grown (within the chords of the round
    /// joins), (s − 2δ)² shrunk; the checked offset of a square keeps cavalier's result.
    #[test]
    fn buffered_and_checked_offsets_of_a_square() {
        let (s, d, tol) = (10.0, 2.0, 1e-3);
        let sq = Region::from_contours(vec![pline_from_points(
            &[
                DVec2::new(0.0, 0.0),
                DVec2::new(s, 0.0),
                DVec2::new(s, s),
                DVec2::new(0.0, s),
            ],
            true,
        )]);
        let grown = sq.buffered(d, tol).area();
        let exact = s * s + 4.0 * s * d + PI * d * d;
        assert!(
            grown <= exact && grown >= exact - 2.0 * PI * d * tol,
            "{grown} vs {exact}"
        );
        let shrunk = sq.buffered(-d, tol).area();
        assert!((shrunk - (s - 2.0 * d).powi(2)).abs() < 1e-9, "{shrunk}");
        // cavalier's offsets (with true arcs at the corners) pass the check and are kept.
        for delta in [d, -d] {
            let (checked, plain) = (sq.offset_checked(delta, 1e-3, tol), sq.offset(delta, 1e-3));
            assert_eq!(checked.area(), plain.area());
            assert_eq!(
                checked.contours[0].vertex_count(),
                plain.contours[0].vertex_count()
            );
        }
    }

    #[test]
    fn union_of_overlapping_squares() {
        let a = Region::from_contours(vec![square(0.0, 0.0, 10.0)]);
        let b = Region::from_contours(vec![square(5.0, 5.0, 10.0)]);
        let u = Region::union(&[a, b], 1e-3);
        assert_eq!(u.contours.len(), 1);
        assert!((u.area() - 175.0).abs() < 1e-9);
    }

    /// Many nearly coincident disks (a stroke repaired into dozens of tiny pieces) and an
    /// annulus with a disk across its hole: the union's membership agrees with the
    /// inputs' at every grid point off their boundaries (a second, pointwise method).
    #[test]
    fn union_of_many_nearly_coincident_disks_and_a_hole() {
        let tol = 1e-3;
        let ring = |c: DVec2, r: f64, ccw: bool| {
            let mut pl = Polyline::new_closed();
            let b = if ccw { 1.0 } else { -1.0 };
            pl.add(c.x - r, c.y, b);
            pl.add(c.x + r, c.y, b);
            pl
        };
        // (centre, radius, hole radius): the annulus has material for r_hole < |p − c| < r.
        let mut shapes: Vec<(DVec2, f64, f64)> = (0..60)
            .map(|k| {
                let a = 0.7 * k as f64;
                (2e-3 * k as f64 * DVec2::new(a.cos(), a.sin()), 2.0, 0.0)
            })
            .collect();
        shapes.push((DVec2::new(20.0, 0.0), 5.0, 3.0));
        shapes.push((DVec2::new(17.5, 0.0), 1.5, 0.0));
        let regions: Vec<Region> = shapes
            .iter()
            .map(|&(c, r, hole)| {
                let mut contours = vec![ring(c, r, true)];
                if hole > 0.0 {
                    contours.push(ring(c, hole, false));
                }
                Region::from_contours(contours)
            })
            .collect();
        let u = Region::union_pairwise(&regions, tol);
        let (mut inside, mut checked) = (0, 0);
        for i in 0..=300 {
            for j in 0..=100 {
                let p = DVec2::new(-3.0 + 0.1 * i as f64, -5.5 + 0.11 * j as f64);
                let near_boundary = shapes.iter().any(|&(c, r, hole)| {
                    let d = p.distance(c);
                    (d - r).abs() < 4.0 * tol || (hole > 0.0 && (d - hole).abs() < 4.0 * tol)
                });
                if near_boundary {
                    continue;
                }
                let expected = shapes.iter().any(|&(c, r, hole)| {
                    let d = p.distance(c);
                    d < r && (hole == 0.0 || d > hole)
                });
                assert_eq!(u.contains(p), expected, "{p}");
                checked += 1;
                inside += usize::from(expected);
            }
        }
        assert!(checked > 25_000 && inside > 1_000, "{checked} {inside}");
    }

    #[test]
    fn union_keeping_arcs_keeps_regions_apart_as_they_are() {
        let disk = |x: f64, y: f64, r: f64| {
            let mut pl = Polyline::new_closed();
            pl.add(x - r, y, 1.0);
            pl.add(x + r, y, 1.0);
            Region::from_contours(vec![pl])
        };
        let (a, b) = (disk(0.0, 0.0, 2.0), disk(10.0, 0.0, 3.0));
        let apart = Region::union_keeping_arcs(&[a.clone(), b], 1e-3);
        assert_eq!(apart.contours.len(), 2);
        assert!(apart.contours.iter().all(|c| c.vertex_count() == 2));
        let exact = std::f64::consts::PI * (4.0 + 9.0);
        assert!((apart.area() - exact).abs() < 1e-9 * exact);
        // Overlapping disks, and a disk inside another: the flattened union.
        for other in [disk(3.0, 0.0, 2.0), disk(0.5, 0.0, 1.0)] {
            let u = Region::union_keeping_arcs(&[a.clone(), other], 1e-3);
            assert_eq!(u.contours.len(), 1);
            assert!(u.contours[0].vertex_count() > 2, "flattened");
        }
    }

    #[test]
    fn circle_from_cubics_keeps_arcs() {
        // Four standard quarter-circle cubics of radius 10: the biarc fit within 1e-3 yields
        // arcs whose polyline area is within the fit tolerance of π r².
        let k = 0.552_284_749_8 * 10.0;
        let q = |a: f64| {
            let (s, c) = a.sin_cos();
            let rot = |v: DVec2| DVec2::new(c * v.x - s * v.y, s * v.x + c * v.y);
            PathSeg::Cubic(CubicBez::new(
                rot(DVec2::new(10.0, 0.0)),
                rot(DVec2::new(10.0, k)),
                rot(DVec2::new(k, 10.0)),
                rot(DVec2::new(0.0, 10.0)),
            ))
        };
        let path = Path::new((0..4).map(|i| q(i as f64 * PI / 2.0)).collect(), true);
        let pl = pline_from_path(&path, 1e-3);
        assert!(pl.iter_vertexes().any(|v| v.bulge != 0.0));
        // Quarter-circle cubic error 2.7e-4·r; biarc error ≤ 1e-3; perimeter 2πr.
        let tol_area = 2.0 * PI * 10.0 * (2.8e-3 + 1e-3);
        assert!((pl.area() - PI * 100.0).abs() < tol_area);
    }
}
