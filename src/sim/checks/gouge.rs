//! Gouge check: the tool centre must stay at least `tool_radius − gouge_tolerance` away from
//! the design boundary, on the side the profile asks for.

use super::contours::ContourStart;
use crate::geom::predicates::edge_winding;
use crate::geom::{DVec2, Line};
use crate::sim::config::CheckConfig;
use crate::sim::findings::{Finding, Severity};
use crate::sim::motion::Motion;
use rstar::primitives::{GeomWithData, Line as RLine};
use rstar::{AABB, RTree};
use serde::{Deserialize, Serialize};

/// Where the tool centre belongs relative to a closed design boundary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KeepSide {
    /// Profile outside: the part is the inside of the boundary.
    #[default]
    Outside,
    /// Pocket or hole: the part is the outside.
    Inside,
    /// Distance only (open polylines, or no side known).
    Either,
}

/// A design boundary (mm, machine coordinates): a polyline, closed when `keep` is not
/// `Either` (the last point joins the first).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct DesignBoundary {
    /// The polyline (mm).
    pub points: Vec<[f64; 2]>,
    /// Which side of it the tool must stay on.
    pub keep: KeepSide,
}

impl DesignBoundary {
    /// A boundary from `points` (mm) with the side to keep.
    #[must_use]
    pub fn new(points: &[DVec2], keep: KeepSide) -> Self {
        DesignBoundary {
            points: points.iter().map(|p| [p.x, p.y]).collect(),
            keep,
        }
    }

    fn segments(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        let n = self.points.len();
        let closed = self.keep != KeepSide::Either && n >= 3;
        let count = if closed { n } else { n.saturating_sub(1) };
        (0..count).map(move |i| {
            let a = self.points[i];
            let b = self.points[(i + 1) % n];
            (DVec2::from(a), DVec2::from(b))
        })
    }

    /// Crossing-number point-in-polygon test with exact orientation signs.
    fn contains(&self, p: DVec2) -> bool {
        self.segments()
            .map(|(a, b)| edge_winding(a, b, p))
            .sum::<i32>()
            % 2
            != 0
    }
}

type Indexed = GeomWithData<RLine<[f64; 2]>, usize>;

/// The design boundaries indexed for the gouge check.
pub struct GougeIndex<'d> {
    design: &'d [DesignBoundary],
    tree: RTree<Indexed>,
    clearance: f64,
    tol: f64,
}

impl<'d> GougeIndex<'d> {
    /// The index of `design`, None when it has no segment (nothing to check).
    pub fn new(design: &'d [DesignBoundary], cfg: &CheckConfig) -> Option<Self> {
        let mut items = Vec::new();
        for (bi, b) in design.iter().enumerate() {
            for (a, c) in b.segments() {
                items.push(Indexed::new(RLine::new([a.x, a.y], [c.x, c.y]), bi));
            }
        }
        if items.is_empty() {
            return None;
        }
        Some(GougeIndex {
            design,
            tree: RTree::bulk_load(items),
            clearance: cfg.tool_radius - cfg.gouge_tolerance,
            tol: cfg.flatten_tolerance,
        })
    }

    /// The gouge of one move: a cutting move (`cutting`) nearer a boundary than the
    /// clearance.
    pub fn motion(&self, m: &Motion, cutting: bool) -> Option<Finding> {
        let clearance = self.clearance;
        if !(clearance > 0.0 && cutting) {
            return None;
        }
        let pts = m.flatten_xy(self.tol);
        let mut worst: Option<(f64, DVec2, usize)> = None;
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let lo = a.min(b) - DVec2::splat(clearance);
            let hi = a.max(b) + DVec2::splat(clearance);
            let env = AABB::from_corners([lo.x, lo.y], [hi.x, hi.y]);
            for it in self.tree.locate_in_envelope_intersecting(env) {
                let g = it.geom();
                let (c, d) = (DVec2::from(g.from), DVec2::from(g.to));
                let dist = Line::new(a, b).distance_to_line(&Line::new(c, d));
                if dist < clearance && worst.is_none_or(|(w, _, _)| dist < w) {
                    let near = Line::new(a, b);
                    let p = [c, d, a, b]
                        .into_iter()
                        .min_by(|x, y| near.distance(*x).total_cmp(&near.distance(*y)))
                        .unwrap_or(a);
                    worst = Some((dist, p, it.data));
                }
            }
        }
        let (dist, p, bi) = worst?;
        Some(
            Finding::new(
                "gouge",
                Severity::Error,
                format!(
                    "tool centre {dist:.4} mm from design boundary {bi} (needs {clearance:.4})"
                ),
            )
            .line(m.line)
            .at([p.x, p.y, m.to.z]),
        )
    }

    /// The findings of [`GougeIndex::contour_start`] for every contour start, in order.
    pub fn contour_starts(&self, starts: &[ContourStart]) -> Vec<Finding> {
        (starts.iter())
            .filter_map(|c| self.contour_start(c.point, c.line.unwrap_or(0), c.z))
            .collect()
    }

    /// The gouge of a contour starting at `p` (cut at height `z`, first move on `line`) on
    /// the wrong side of the nearest boundary.
    pub fn contour_start(&self, p: DVec2, line: usize, z: f64) -> Option<Finding> {
        let near = self.tree.nearest_neighbor([p.x, p.y])?;
        let b = self.design.get(near.data)?;
        let inside = b.contains(p);
        let wrong = match b.keep {
            KeepSide::Outside => inside,
            KeepSide::Inside => !inside,
            KeepSide::Either => false,
        };
        wrong.then(|| {
            Finding::new(
                "gouge",
                Severity::Error,
                format!(
                    "cut contour starts {} design boundary {} but must stay {}",
                    if inside { "inside" } else { "outside" },
                    near.data,
                    if inside { "outside" } else { "inside" }
                ),
            )
            .line(line)
            .at([p.x, p.y, z])
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_and_containment() {
        let sq = DesignBoundary::new(
            &[
                DVec2::ZERO,
                DVec2::new(2.0, 0.0),
                DVec2::new(2.0, 2.0),
                DVec2::new(0.0, 2.0),
            ],
            KeepSide::Outside,
        );
        assert!(sq.contains(DVec2::new(1.0, 1.0)));
        assert!(!sq.contains(DVec2::new(3.0, 1.0)));
        assert!(!sq.contains(DVec2::new(1.0, -0.5)));
    }
}
