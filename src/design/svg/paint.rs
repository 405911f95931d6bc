//! The paint model of fills (SVG 1.1 §3.3, the painter's algorithm): fills paint in
//! document order and a later fill hides what lies under it. The ink of the drawing is the
//! visible painted area, kept per fill as the part of it nothing later covers:
//!
//! - a fill of another colour (or another layer) cuts its area out of the earlier regions
//!   it overlaps (region − fill), so the boundary between two colours is kept on both;
//! - a fill of the same colour and layer merges with the earlier regions it overlaps
//!   (their union): the boundary between them is not visible;
//! - a white fill, or one of the page's background colour, is a knockout: it cuts its area
//!   out and is no ink itself. The background is a first fill that covers the whole page
//!   (a `<rect>` behind the art, as plotting tools write); it is listed as skipped.
//!
//! - a fill drawn with an opacity (`opacity` of it and its groups times `fill-opacity`)
//!   below [`MIN_INK_OPACITY`] is no ink at all; one below [`HIDE_OPACITY`] is ink that
//!   hides nothing (what lies under it shows through), so it neither cuts nor knocks out;
//! - a stroke drawn before a fill that hides is hidden where the fill covers its centre
//!   line ([`Paint::visible_lines`]): the visible runs of the line are kept, each a stroke.
//!
//! Regions are simple rings (outer counter-clockwise, holes clockwise, none crossing), so
//! the even-odd rule of geo's boolean operations (i_overlay) reads them exactly. Only
//! regions whose bounding boxes meet are compared (an R-tree of the boxes), so a drawing of
//! n fills that do not overlap costs O(n log n).

use super::*;
use crate::design::shape::rings_of;
use geo::BooleanOps;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

/// White: a fill of this colour is a knockout (the default page background).
pub(super) const WHITE: &str = "#ffffff";

/// Paint whose opacity (its own times its element's and groups' `opacity`) is below this
/// is not ink: too faint to be meant for the machine (a construction line, a hidden guide).
pub(super) const MIN_INK_OPACITY: f64 = 0.1;

/// A fill hides what lies under it (and a white one knocks out) only from this opacity on:
/// under a fill less than half opaque the earlier art stays the more visible.
pub(super) const HIDE_OPACITY: f64 = 0.5;

/// Distance (mm) within which the end of one clipped piece of a line and the start of the
/// next are the same point, and the pieces are joined into one run.
const PIECE_JOIN: f64 = 1e-9;

/// One visible region of a fill.
pub(super) struct Region {
    /// The shape name (the element id, `ID.fill` beside a stroke).
    pub(super) name: String,
    pub(super) layer: Option<String>,
    pub(super) color: Option<String>,
    /// Simple rings, outer counter-clockwise and holes clockwise.
    pub(super) rings: Vec<Vec<DVec2>>,
}

type Boxed = GeomWithData<Rectangle<[f64; 2]>, usize>;

/// The paint state: regions in paint order (`None` once covered or merged away) and an
/// R-tree of their bounding boxes.
#[derive(Default)]
pub(super) struct Paint {
    pub(super) regions: Vec<Option<Region>>,
    tree: RTree<Boxed>,
    boxes: Vec<Option<AABB<[f64; 2]>>>,
    /// The page background's colour, once a first fill covered the page.
    pub(super) background: Option<String>,
    /// Fills that hide what lies under them, with their paint order (strokes painted
    /// before one are hidden where it covers them).
    covers: Vec<(usize, geo::MultiPolygon<f64>)>,
    /// R-tree of the covers' bounding boxes.
    cover_tree: RTree<Boxed>,
    /// Paint order of the next fill or stroke.
    pub(super) seq: usize,
}

fn bbox(rings: &[Vec<DVec2>]) -> Option<AABB<[f64; 2]>> {
    let pts: Vec<[f64; 2]> = rings.iter().flatten().map(|p| [p.x, p.y]).collect();
    (!pts.is_empty()).then(|| AABB::from_points(pts.iter()))
}

fn to_geo(rings: &[Vec<DVec2>]) -> geo::MultiPolygon<f64> {
    geo::MultiPolygon::new(
        rings
            .iter()
            .map(|r| {
                let mut c: Vec<geo::Coord<f64>> =
                    r.iter().map(|p| geo::Coord { x: p.x, y: p.y }).collect();
                c.push(c[0]);
                geo::Polygon::new(geo::LineString::new(c), vec![])
            })
            .collect(),
    )
}

impl Paint {
    /// Paint a fill: cut it out of the earlier regions of other colours or layers it
    /// overlaps, merge the overlapping ones of its colour and layer into it, and keep it
    /// unless it is a knockout. The names of regions it covers entirely are returned (they
    /// are hidden).
    pub(super) fn paint(&mut self, mut fill: Region, knockout: bool) -> Vec<String> {
        let mut hidden = Vec::new();
        let Some(b) = bbox(&fill.rings) else {
            return hidden;
        };
        self.cover_tree.insert(GeomWithData::new(
            Rectangle::from_corners(b.lower(), b.upper()),
            self.covers.len(),
        ));
        self.covers.push((self.seq, to_geo(&fill.rings)));
        self.seq += 1;
        let near: Vec<usize> = self
            .tree
            .locate_in_envelope_intersecting(b)
            .map(|g| g.data)
            .collect();
        let mut merged = fill.rings.clone();
        let clip = to_geo(&fill.rings);
        for i in near {
            let Some(r) = self.regions[i].as_mut() else {
                continue;
            };
            let same = !knockout && r.color == fill.color && r.layer == fill.layer;
            if same {
                merged = rings_of(&to_geo(&merged).union(&to_geo(&r.rings)));
            } else {
                r.rings = rings_of(&to_geo(&r.rings).difference(&clip));
            }
            let gone = same || r.rings.is_empty();
            if let Some(old) = self.boxes[i].take() {
                self.tree.remove(&GeomWithData::new(
                    Rectangle::from_corners(old.lower(), old.upper()),
                    i,
                ));
            }
            if gone {
                let r = self.regions[i].take();
                if !same && let Some(r) = r {
                    hidden.push(r.name);
                }
            } else {
                self.insert(i);
            }
        }
        if !knockout {
            fill.rings = merged;
            self.regions.push(Some(fill));
            self.boxes.push(None);
            self.insert(self.regions.len() - 1);
        }
        hidden
    }

    /// Paint a translucent fill (opacity below [`HIDE_OPACITY`]): ink of its own that
    /// hides, cuts and merges with nothing.
    pub(super) fn paint_translucent(&mut self, fill: Region) {
        self.seq += 1;
        self.regions.push(Some(fill));
        self.boxes.push(None);
        self.insert(self.regions.len() - 1);
    }

    /// The runs of the open polyline `line` (a stroke's centre line painted at `seq`) that
    /// no later hiding fill covers, in order along the line (geo's line clipping, i_overlay,
    /// even-odd on the fills' simple rings). `None` when no later fill reaches the line's
    /// box grown by `reach` (the line is kept whole, untouched).
    pub(super) fn visible_lines(
        &self,
        seq: usize,
        line: &[DVec2],
        reach: f64,
    ) -> Option<Vec<Vec<DVec2>>> {
        let b = bbox(std::slice::from_ref(&line.to_vec()))?;
        let grow = |v: [f64; 2], d: f64| [v[0] + d, v[1] + d];
        let b = AABB::from_corners(grow(b.lower(), -reach), grow(b.upper(), reach));
        let mut over: Vec<usize> = self
            .cover_tree
            .locate_in_envelope_intersecting(b)
            .map(|g| g.data)
            .filter(|&k| self.covers[k].0 > seq)
            .collect();
        over.sort_unstable();
        if over.is_empty() {
            return None;
        }
        let coords = line.iter().map(|p| geo::Coord { x: p.x, y: p.y }).collect();
        let mut lines = geo::MultiLineString::new(vec![geo::LineString::new(coords)]);
        for k in over {
            lines = self.covers[k].1.clip(&lines, true);
        }
        Some(along(line, &lines))
    }

    fn insert(&mut self, i: usize) {
        let Some(b) = self.regions[i].as_ref().and_then(|r| bbox(&r.rings)) else {
            return;
        };
        self.tree.insert(GeomWithData::new(
            Rectangle::from_corners(b.lower(), b.upper()),
            i,
        ));
        self.boxes[i] = Some(b);
    }

    /// Whether nothing has been painted yet.
    pub(super) fn is_empty(&self) -> bool {
        self.regions.iter().all(Option::is_none)
    }
}

/// The pieces of `clipped` (parts of the polyline `line`) in order along `line`, each
/// running forwards, pieces that meet end to start joined: a clipper returns the parts in
/// any order and direction.
fn along(line: &[DVec2], clipped: &geo::MultiLineString<f64>) -> Vec<Vec<DVec2>> {
    let index = super::fit::Polyline::new(line);
    let mut arc = vec![0.0];
    for w in line.windows(2) {
        arc.push(arc.last().copied().unwrap_or(0.0) + w[0].distance(w[1]));
    }
    let pos = |q: DVec2| {
        let (_, i, f) = index.nearest(q);
        let next = arc.get(i + 1).copied().unwrap_or(arc[i]);
        arc[i] + f * (next - arc[i])
    };
    let mut pieces: Vec<(f64, Vec<DVec2>)> = clipped
        .iter()
        .filter_map(|ls| {
            let mut pts: Vec<DVec2> = ls.coords().map(|c| DVec2::new(c.x, c.y)).collect();
            let (&first, &last) = (pts.first()?, pts.last()?);
            let (a, b) = (pos(first), pos(last));
            if b < a {
                pts.reverse();
            }
            Some((a.min(b), pts))
        })
        .collect();
    pieces.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<Vec<DVec2>> = Vec::new();
    for (_, p) in pieces {
        match out.last_mut() {
            Some(last)
                if last
                    .last()
                    .zip(p.first())
                    .is_some_and(|(a, b)| a.distance(*b) < PIECE_JOIN) =>
            {
                last.extend_from_slice(&p[1..]);
            }
            _ => out.push(p),
        }
    }
    out
}

/// A solid paint as `#rrggbb` (lower case); `None` for gradients and patterns.
pub(super) fn paint_color(p: &usvg::Paint) -> Option<String> {
    match p {
        usvg::Paint::Color(c) => Some(format!("#{:02x}{:02x}{:02x}", c.red, c.green, c.blue)),
        _ => None,
    }
}
