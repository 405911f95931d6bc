//! `[[shape]]`: closed regions given by their boundary, for artwork that is an area rather
//! than a stroke (an SVG's filled shapes, a plate, a logo's solid parts).
//!
//! ```toml
//! [[shape]]
//! name = "ring"                  # unique among strokes, circle sequences and shapes
//! fill_rule = "evenodd"          # "nonzero" (default) | "evenodd"
//! contours = [
//!   [[0.0, 0.0], [40.0, 0.0], [40.0, 40.0], [0.0, 40.0]],      # outer boundary
//!   [[10.0, 10.0], [30.0, 10.0], [30.0, 30.0], [10.0, 30.0]],  # a hole
//! ]
//! ```
//!
//! Each contour is a closed polyline `[[x, y], ...]`: the last point joins the first (a
//! last point equal to the first is allowed and dropped). The region is the set of points
//! the contours enclose under the fill rule, as in SVG (`fill-rule`, SVG 1.1 §11.3):
//! `nonzero` — the sum of the contours' winding numbers is not zero (a contour running the
//! other way round inside another is a hole); `evenodd` — an odd number of contours
//! encloses the point (every nested contour is a hole, whatever its direction). Contours
//! may cross each other (the fill rule decides); a contour may not cross or touch itself.
//!
//! Rules (each error names the shape by index and name, and the contour and point):
//! at least one contour, at most [`MAX_ITEMS`] contours and [`MAX_ITEMS`] points per
//! contour; at least 3 points per contour; every number finite and within ±[`MAX_COORD`];
//! no point equal or nearly equal (closer than [`NEAR_FRACTION`] of the shape's size) to
//! the one before it; no contour that crosses or touches itself (running back along its
//! own edge included), none of zero area (|area| ≤ [`NEAR_FRACTION`]·size²); the region
//! must not be empty.
//!
//! Jobs treat a shape like the outline of a stroke: profile, fill and backboard operations
//! cut its region (joined with the stroke outlines they select), `outline` draws it and
//! `inspect` lists it. Channel, holes and V-carve operations follow stroke spines, which a
//! shape has none of: they skip shapes.

use super::error::{DesignError, ErrorKind, Item, Part};
use super::validate::{MAX_COORD, MAX_ITEMS, NEAR_FRACTION};
use crate::geom::DVec2;
use crate::geom::predicates::{orient2d, segments_intersect};
use serde::{Deserialize, Serialize};

/// Strict `[x, y]` pairs (TOML's fixed-size arrays would accept `[x, y, z]`).
mod xy {
    use serde::de::{Deserialize, Deserializer, Error};

    struct Xy([f64; 2]);

    impl<'de> Deserialize<'de> for Xy {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            let v = Vec::<f64>::deserialize(d)?;
            match v.as_slice() {
                &[x, y] => Ok(Xy([x, y])),
                _ => Err(D::Error::invalid_length(
                    v.len(),
                    &"exactly 2 numbers [x, y]",
                )),
            }
        }
    }

    pub fn rings<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<[f64; 2]>>, D::Error> {
        Ok(Vec::<Vec<Xy>>::deserialize(d)?
            .into_iter()
            .map(|r| r.into_iter().map(|p| p.0).collect())
            .collect())
    }
}

/// Which points the contours of a shape enclose (SVG 1.1 §11.3 `fill-rule`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FillRule {
    /// Non-zero sum of winding numbers.
    #[default]
    Nonzero,
    /// An odd number of enclosing contours.
    Evenodd,
}

impl FillRule {
    /// The rule's value of the `fill_rule` key in design files.
    pub fn as_str(self) -> &'static str {
        match self {
            FillRule::Nonzero => "nonzero",
            FillRule::Evenodd => "evenodd",
        }
    }
}

/// A `[[shape]]` table: a closed region bounded by polylines.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shape {
    /// `name` (required): non-empty and unique among strokes, circle sequences and shapes.
    pub name: String,
    /// `fill_rule`: `"nonzero"` or `"evenodd"`, how the contours make a region; default
    /// nonzero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fill_rule: Option<FillRule>,
    /// `contours` (required): closed polylines `[[x, y], ...]`, outer boundaries and holes;
    /// at least one, each with at least 3 points, a non-zero area, not crossing or touching itself.
    #[serde(deserialize_with = "xy::rings")]
    pub contours: Vec<Vec<[f64; 2]>>,
    /// `layer`: the drawing layer the shape came from (see the stroke's `layer`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<String>,
    /// `color`: the shape's fill colour as `#rrggbb` (see the stroke's `color`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<String>,
}

/// The ring's points without a closing point that repeats the first.
fn open_ring(ring: &[[f64; 2]]) -> Vec<DVec2> {
    let mut pts: Vec<DVec2> = ring.iter().map(|&[x, y]| DVec2::new(x, y)).collect();
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    pts
}

/// Signed area of a closed polygon (shoelace formula; counter-clockwise positive).
pub fn ring_area(pts: &[DVec2]) -> f64 {
    crate::geom::path::polygon_area(pts)
}

/// Where a closed ring meets itself: `Some((i, j))`, i < j, for edges i (from point i to
/// i + 1) and j that cross or touch while not adjacent. Exact (orientation predicates,
/// Shewchuk); edges are swept in order of their smallest x, so only edges whose x ranges
/// overlap are compared. A ring of four or more points that runs back along its own edge (a
/// spike) always has such a pair (the edge after the spike starts on the edge before it, or
/// the edge before it ends on the edge after it); a triangle that does has zero area.
pub fn self_intersection(pts: &[DVec2]) -> Option<(usize, usize)> {
    edge_meeting(std::slice::from_ref(&pts.to_vec())).map(|((_, i), (_, j))| (i.min(j), i.max(j)))
}

/// The first pair of edges of `rings` (closed, each edge named by (ring, index of its first
/// point)) that cross or touch, leaving out the two edges next to each other in one ring
/// (which share a point). Exact (orientation predicates); edges are swept in order of their
/// smallest x, so only edges whose x ranges overlap are compared.
pub fn edge_meeting(rings: &[Vec<DVec2>]) -> Option<((usize, usize), (usize, usize))> {
    let edge = |(r, i): (usize, usize)| {
        let ring = &rings[r];
        (ring[i], ring[(i + 1) % ring.len()])
    };
    let mut order: Vec<(usize, usize)> = rings
        .iter()
        .enumerate()
        .filter(|(_, ring)| ring.len() >= 3)
        .flat_map(|(r, ring)| (0..ring.len()).map(move |i| (r, i)))
        .collect();
    let xmin = |e: (usize, usize)| {
        let (a, b) = edge(e);
        a.x.min(b.x)
    };
    order.sort_by(|&e, &f| xmin(e).total_cmp(&xmin(f)).then(e.cmp(&f)));
    for (k, &e) in order.iter().enumerate() {
        let (a, b) = edge(e);
        let xmax = a.x.max(b.x);
        let (ylo, yhi) = (a.y.min(b.y), a.y.max(b.y));
        for &f in &order[k + 1..] {
            if xmin(f) > xmax {
                break;
            }
            let n = rings[e.0].len();
            let adjacent = e.0 == f.0 && ((e.1 + 1) % n == f.1 || (f.1 + 1) % n == e.1);
            if adjacent {
                continue;
            }
            let (c, d) = edge(f);
            if c.y.max(d.y) < ylo || c.y.min(d.y) > yhi {
                continue;
            }
            if segments_intersect(a, b, c, d) {
                return Some((e.min(f), e.max(f)));
            }
        }
    }
    None
}

/// Winding number of the closed ring `ring` around `p` (Sunday's crossing rule with the
/// exact orientation predicate); `p` must not lie on the ring.
fn winding(ring: &[DVec2], p: DVec2) -> i32 {
    let n = ring.len();
    let mut w = 0;
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        if a.y <= p.y {
            if b.y > p.y && orient2d(a, b, p) > 0.0 {
                w += 1;
            }
        } else if b.y <= p.y && orient2d(a, b, p) < 0.0 {
            w -= 1;
        }
    }
    w
}

/// The region of `rings` under `rule` as simple rings: outer boundaries counter-clockwise,
/// holes clockwise, no two crossing or touching, so either fill rule gives the same region.
///
/// Rings that neither cross nor touch themselves or each other (the usual case: outlines
/// and holes) keep their points exactly: the winding number just outside a ring is the sum
/// of the windings of the rings around it, just inside that plus the ring's own ±1 (its
/// orientation); the ring bounds the region where the fill rule (SVG 1.1 §11.3: nonzero,
/// or evenodd on the number of enclosing rings) fills one side and not the other, and is
/// oriented by which side. Rings that cross or touch are resolved by geo's boolean union
/// under the fill rule (i_overlay's sweep, O((n + k) log n) for n edges and k crossings),
/// exact up to its integer snapping grid (about 1e-8 of the rings' extent).
pub fn resolve_rings(rings: &[Vec<DVec2>], rule: FillRule) -> Vec<Vec<DVec2>> {
    let rings: Vec<Vec<DVec2>> = rings
        .iter()
        .filter(|r| r.len() >= 3 && ring_area(r) != 0.0)
        .cloned()
        .collect();
    if edge_meeting(&rings).is_none() {
        let filled = |w: i32, depth: usize| match rule {
            FillRule::Nonzero => w != 0,
            FillRule::Evenodd => depth % 2 == 1,
        };
        let mut out = Vec::new();
        for (i, r) in rings.iter().enumerate() {
            let own = if ring_area(r) > 0.0 { 1 } else { -1 };
            let (mut w, mut depth) = (0, 0);
            for (j, o) in rings.iter().enumerate() {
                let k = if j == i { 0 } else { winding(o, r[0]) };
                if k != 0 {
                    w += k;
                    depth += 1;
                }
            }
            let (outside, inside) = (filled(w, depth), filled(w + own, depth + 1));
            if outside != inside {
                let mut r = r.clone();
                if (ring_area(&r) > 0.0) != inside {
                    r.reverse();
                }
                out.push(r);
            }
        }
        return out;
    }
    resolve_crossing(&rings, rule)
}

/// [`resolve_rings`] for rings that cross or touch: geo's union under the fill rule.
fn resolve_crossing(rings: &[Vec<DVec2>], rule: FillRule) -> Vec<Vec<DVec2>> {
    use geo::BooleanOps;
    use geo::algorithm::bool_ops::{FillRule as GeoRule, OpType};
    let closed = |r: &[DVec2]| {
        let mut c: Vec<geo::Coord<f64>> = r.iter().map(|p| geo::Coord { x: p.x, y: p.y }).collect();
        if let Some(&f) = c.first() {
            c.push(f);
        }
        geo::LineString::new(c)
    };
    let subject = geo::MultiPolygon::new(
        rings
            .iter()
            .filter(|r| r.len() >= 3)
            .map(|r| geo::Polygon::new(closed(r), vec![]))
            .collect(),
    );
    let empty = geo::MultiPolygon::<f64>::new(vec![]);
    let rule = match rule {
        FillRule::Nonzero => GeoRule::NonZero,
        FillRule::Evenodd => GeoRule::EvenOdd,
    };
    let merged = subject.boolean_op_with_fill_rule(&empty, OpType::Union, rule);
    rings_of(&merged)
}

/// The rings of `mp` as point rings without a closing point: each polygon's exterior
/// counter-clockwise, then its holes clockwise; rings of fewer than 3 points dropped.
pub(crate) fn rings_of(mp: &geo::MultiPolygon<f64>) -> Vec<Vec<DVec2>> {
    let ring = |ls: &geo::LineString<f64>, ccw: bool| {
        let mut pts: Vec<DVec2> = ls.coords().map(|c| DVec2::new(c.x, c.y)).collect();
        if pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        if (ring_area(&pts) > 0.0) != ccw {
            pts.reverse();
        }
        pts
    };
    let mut out = Vec::new();
    for p in &mp.0 {
        out.push(ring(p.exterior(), true));
        out.extend(p.interiors().iter().map(|h| ring(h, false)));
    }
    out.retain(|r| r.len() >= 3);
    out
}

impl Shape {
    /// The contours as point rings (a closing point equal to the first dropped).
    #[must_use]
    pub fn rings(&self) -> Vec<Vec<DVec2>> {
        self.contours.iter().map(|r| open_ring(r)).collect()
    }

    /// The shape's region as simple rings, outer counter-clockwise and holes clockwise
    /// (`resolve_rings` under the shape's fill rule).
    #[must_use]
    pub fn region(&self) -> Vec<Vec<DVec2>> {
        resolve_rings(&self.rings(), self.fill_rule.unwrap_or_default())
    }

    /// Every coordinate multiplied by `f` (about the origin).
    pub fn scale(&mut self, f: f64) {
        for p in self.contours.iter_mut().flatten() {
            p[0] *= f;
            p[1] *= f;
        }
    }

    /// Check the shape (see the module docs); `index` is its place among the shapes.
    pub fn validate(&self, file: &str, index: usize) -> Result<(), DesignError> {
        let item = || Item::Shape {
            index,
            name: self.name.clone(),
        };
        let at = |part: Option<Part>, kind: ErrorKind| DesignError::at(file, item(), part, kind);
        let point = |contour: usize, point: usize| Some(Part::ContourPoint { contour, point });
        if self.contours.is_empty() {
            return Err(at(
                Some(Part::Key("contours".into())),
                ErrorKind::TooFew {
                    what: "contours",
                    need: 1,
                    got: 0,
                },
            ));
        }
        if self.contours.len() > MAX_ITEMS {
            return Err(at(
                Some(Part::Key("contours".into())),
                ErrorKind::Invalid(format!(
                    "{} contours, more than the limit {MAX_ITEMS}; split the shape",
                    self.contours.len()
                )),
            ));
        }
        for (c, ring) in self.contours.iter().enumerate() {
            if ring.len() > MAX_ITEMS {
                return Err(at(
                    Some(Part::Contour(c)),
                    ErrorKind::Invalid(format!(
                        "{} points, more than the limit {MAX_ITEMS}; simplify the contour",
                        ring.len()
                    )),
                ));
            }
            for (i, p) in ring.iter().enumerate() {
                if !p.iter().all(|v| v.is_finite()) {
                    return Err(at(point(c, i), ErrorKind::NotFinite));
                }
                if let Some(&v) = p.iter().find(|v| v.abs() > MAX_COORD) {
                    return Err(at(
                        point(c, i),
                        ErrorKind::Invalid(format!(
                            "value {v} is beyond ±{MAX_COORD} design units; scale the design down"
                        )),
                    ));
                }
            }
        }
        let size = self
            .contours
            .iter()
            .flatten()
            .flatten()
            .fold(1.0f64, |m, v| m.max(v.abs()));
        let near = NEAR_FRACTION * size;
        for (c, ring) in self.contours.iter().enumerate() {
            let pts = open_ring(ring);
            if pts.len() < 3 {
                return Err(at(
                    Some(Part::Contour(c)),
                    ErrorKind::TooFew {
                        what: "points (a closed contour)",
                        need: 3,
                        got: pts.len(),
                    },
                ));
            }
            let n = pts.len();
            for i in 0..n {
                let (prev, p) = (pts[(i + n - 1) % n], pts[i]);
                if p == prev {
                    return Err(at(point(c, i), ErrorKind::Repeated));
                }
                if p.distance(prev) <= near {
                    return Err(at(
                        point(c, i),
                        ErrorKind::Invalid(format!(
                            "point nearly repeats the one before it (closer than {near:e}, \
                             {NEAR_FRACTION:e} of the shape's size); remove one of the two"
                        )),
                    ));
                }
            }
            if let Some((i, j)) = self_intersection(&pts) {
                return Err(at(
                    Some(Part::Contour(c)),
                    ErrorKind::Invalid(format!(
                        "contour crosses or touches itself: edge {i} (points {i}–{}) meets \
                         edge {j} (points {j}–{}); split it into separate contours",
                        (i + 1) % n,
                        (j + 1) % n
                    )),
                ));
            }
            let (lo, hi) = pts.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), &p| (lo.min(p), hi.max(p)),
            );
            let area = ring_area(&pts);
            if area.abs() <= NEAR_FRACTION * (hi - lo).length_squared() {
                return Err(at(
                    Some(Part::Contour(c)),
                    ErrorKind::Invalid(format!(
                        "contour encloses no area (area {area:e}: its points lie on a line); \
                         remove it or move its points apart"
                    )),
                ));
            }
        }
        if self.region().is_empty() {
            return Err(at(
                None,
                ErrorKind::Invalid(format!(
                    "the contours enclose no area under fill rule \"{}\" (every point is \
                     outside or cancelled by a hole)",
                    self.fill_rule.unwrap_or_default().as_str()
                )),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "shape_tests.rs"]
mod tests;
