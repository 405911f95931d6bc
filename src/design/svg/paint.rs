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
