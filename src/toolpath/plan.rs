//! From operation geometry to an ordered [`Toolpath`]: depths and passes, feeds and power,
//! tabs and leads, and the cut order.
//!
//! Operations run in a fixed order that keeps the work held until the end: holes, fills,
//! V-carving, lines, channels, profiles, backboard. Within an operation, inner contours are cut
//! before the contours that enclose them, then travel is shortened ([`super::order`]).

use super::cut::{CutOptions, Lead, Tabs, contour_cut_leads, step_levels};
use super::model::{Cut, Move, MoveKind, Operation, OperationKind, Toolpath};
use super::order::{OrderStats, order_paths};
use crate::geom::{Aabb, DVec2, Path};
use glam::DVec3;

/// What the tool centre follows in one operation.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// Closed or open paths of lines and arcs, cut at the operation's depth levels.
    Paths(Vec<Path>),
    /// Points to drill (routers: plunge, peck) or pierce (lasers: dwell).
    Points(Vec<DVec2>),
    /// Polylines with their own z and, per point, their own feed and power (a stroke's
    /// attribute curves sampled along its spine), cut in one pass each.
    AttrPolylines3(Vec<AttrPolyline>),
}

impl Geometry {
    /// The box in xy of what the tool centre follows, or `None` when there is
    /// nothing: paths by their segments' boxes (arcs exact, cubics by their control points,
    /// [`crate::geom::PathSeg::bounding_box`]), points and polylines by their points. It does
    /// not depend on the cut order, so a placement computed from it is known before the order
    /// is chosen (leads, added by the cuts, can reach past it).
    #[must_use]
    pub fn bounds(&self) -> Option<Aabb> {
        let b = match self {
            Geometry::Paths(paths) => (paths.iter().flat_map(|p| &p.segs))
                .fold(Aabb::EMPTY, |b, s| b.union(s.bounding_box())),
            Geometry::Points(points) => Aabb::from_points(points),
            Geometry::AttrPolylines3(lines) => (lines.iter().flat_map(|l| &l.points))
                .fold(Aabb::EMPTY, |b, p| b.add_point(p.truncate())),
        };
        b.non_empty()
    }
}

/// A polyline with per-point z, feed and power: the move that reaches `points[i]` cuts at
/// `feed[i]` and `power[i]`. An empty `feed` or `power` (or one of another length than
/// `points`) falls back to the operation's value; the plunge to the first point uses the
/// operation's plunge feed and the first point's power.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct AttrPolyline {
    /// The points in order (x, y and the depth z of each).
    pub points: Vec<DVec3>,
    /// Feed per point, units per minute.
    pub feed: Vec<f64>,
    /// Power per point, fraction of the machine's maximum.
    pub power: Vec<f64>,
}

/// One operation's geometry and settings.
#[derive(Clone, Debug, PartialEq)]
pub struct OpSpec {
    /// Operation name.
    pub name: String,
    /// What the operation does.
    pub kind: OperationKind,
    /// Paths, polylines or points to cut.
    pub geometry: Geometry,
    /// Source stroke names per path or point (same length as the geometry, or empty).
    pub sources: Vec<String>,
    /// Pocket per path or point (same length as the geometry, or empty): see
    /// [`Cut::group`].
    pub groups: Vec<Option<u32>>,
    /// Index of the design's `[[operation]]` this comes from.
    pub design_index: Option<usize>,
    /// Air assist on during the operation (lasers).
    pub air_assist: bool,
    /// Final depth below the surface (0 for lasers).
    pub depth: f64,
    /// Largest depth per pass (routers); ignored when depth is 0.
    pub step_down: f64,
    /// Number of passes at the same level (lasers cutting thick stock); at least 1.
    pub repeat: usize,
    /// Cutting feed, units per minute.
    pub feed: f64,
    /// Plunge feed, units per minute.
    pub plunge_feed: f64,
    /// Laser power or spindle speed, fraction of the machine's maximum.
    pub power: f64,
    /// Holding tabs, if any.
    pub tabs: Option<Tabs>,
    /// How cuts are entered.
    pub lead: Lead,
    /// Dwell at each drilled or pierced point, seconds.
    pub dwell: f64,
}

/// Position in the fixed operation order.
fn rank(kind: OperationKind) -> usize {
    match kind {
        OperationKind::Holes => 0,
        OperationKind::Fill => 1,
        OperationKind::VCarve => 2,
        OperationKind::Line => 3,
        OperationKind::Channel => 4,
        OperationKind::Profile => 5,
        OperationKind::Backboard => 6,
    }
}

/// Travel figures of one planned operation.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanStats {
    /// Operation name.
    pub operation: String,
    /// Travel before and after ordering.
    pub order: OrderStats,
}

fn levels(spec: &OpSpec) -> Vec<f64> {
    let base = step_levels(spec.depth, spec.step_down);
    let mut out = Vec::new();
    for z in base {
        for _ in 0..spec.repeat.max(1) {
            out.push(z);
        }
    }
    out
}

/// Plan every operation; the tool starts at `home`. `tol` is the geometric tolerance used
/// for containment tests and snapping entry points.
pub fn plan(specs: &[OpSpec], home: DVec2, tol: f64) -> (Toolpath, Vec<PlanStats>) {
    let mut order: Vec<&OpSpec> = specs.iter().collect();
    order.sort_by_key(|s| rank(s.kind));
    let mut pos = home;
    let mut ops = Vec::new();
    let mut stats = Vec::new();
    for spec in order {
        let mut cuts: Vec<Cut> = Vec::new();
        let source_of = |i: usize| spec.sources.get(i).cloned();
        let group_of = |i: usize| spec.groups.get(i).copied().flatten();
        match &spec.geometry {
            Geometry::Paths(paths) => {
                let (ordered, st) = order_paths(paths, pos, tol);
                let opts = CutOptions {
                    feed: spec.feed,
                    plunge_feed: spec.plunge_feed,
                    power: spec.power,
                    levels: levels(spec),
                    tabs: spec.tabs,
                    lead: spec.lead,
                    waste_left: true,
                };
                // Leads stay clear of the operation's other contours and of the leads
                // of the cuts made before (two pieces' leads into one narrow gap crossed).
                let mut leads_run: Vec<Path> = Vec::new();
                for (k, (i, p)) in ordered.iter().enumerate() {
                    let others: Vec<&Path> = if matches!(spec.lead, Lead::None) {
                        Vec::new()
                    } else {
                        ordered
                            .iter()
                            .enumerate()
                            .filter(|&(j, _)| j != k)
                            .map(|(_, (_, q))| q)
                            .chain(&leads_run)
                            .collect()
                    };
                    if let Some((mut c, leads)) =
                        contour_cut_leads(p, &others, &opts, source_of(*i))
                    {
                        c.group = group_of(*i);
                        cuts.push(c);
                        leads_run.extend(leads.into_iter().map(|l| Path::new(vec![l], false)));
                    }
                }
                stats.push(PlanStats {
                    operation: spec.name.clone(),
                    order: st,
                });
            }
            Geometry::Points(points) => {
                // Nearest neighbour over points.
                let mut left: Vec<(usize, DVec2)> = points.iter().copied().enumerate().collect();
                let mut here = pos;
                let travel_input = travel_points(points, pos);
                let mut travel_ordered = 0.0;
                while !left.is_empty() {
                    let (k, _) = left
                        .iter()
                        .enumerate()
                        .min_by(|a, b| a.1.1.distance(here).total_cmp(&b.1.1.distance(here)))
                        .map(|(k, v)| (k, *v))
                        .unwrap_or((0, (0, here)));
                    let (i, p) = left.swap_remove(k);
                    travel_ordered += here.distance(p);
                    here = p;
                    let mut c = drill_cut(p, spec, source_of(i));
                    c.group = group_of(i);
                    cuts.push(c);
                }
                stats.push(PlanStats {
                    operation: spec.name.clone(),
                    order: OrderStats {
                        travel_input,
                        travel_ordered,
                    },
                });
            }
            Geometry::AttrPolylines3(lines) => {
                for (i, l) in lines.iter().enumerate() {
                    if let Some(mut c) = attr_polyline3_cut(l, spec, source_of(i)) {
                        c.group = group_of(i);
                        cuts.push(c);
                    }
                }
            }
        }
        if let Some(last) = cuts.last().and_then(|c| c.moves.last()) {
            pos = last.to.truncate();
        }
        ops.push(Operation {
            name: spec.name.clone(),
            kind: spec.kind,
            cuts,
            design_index: spec.design_index,
            air_assist: spec.air_assist,
        });
    }
    (Toolpath { operations: ops }, stats)
}

fn travel_points(points: &[DVec2], home: DVec2) -> f64 {
    let mut pos = home;
    let mut t = 0.0;
    for p in points {
        t += pos.distance(*p);
        pos = *p;
    }
    t
}

/// A drilled (router) or pierced (laser) point: plunge in steps to depth, dwell, retract
/// to the surface.
fn drill_cut(p: DVec2, spec: &OpSpec, source: Option<String>) -> Cut {
    let mut moves = Vec::new();
    for z in levels(spec) {
        moves.push(Move {
            kind: MoveKind::Line,
            to: DVec3::new(p.x, p.y, z),
            feed: spec.plunge_feed,
            power: spec.power,
        });
        if spec.dwell > 0.0 {
            moves.push(Move {
                kind: MoveKind::Dwell {
                    seconds: spec.dwell,
                },
                to: DVec3::new(p.x, p.y, z),
                feed: spec.plunge_feed,
                power: spec.power,
            });
        }
    }
    Cut {
        source,
        group: None,
        start: DVec3::new(p.x, p.y, 0.0),
        moves,
    }
}

/// A polyline with its own z, feed and power per point, in one pass.
fn attr_polyline3_cut(l: &AttrPolyline, spec: &OpSpec, source: Option<String>) -> Option<Cut> {
    let n = l.points.len();
    let per_point = |v: &[f64], i: usize, default: f64| {
        if v.len() == n {
            v.get(i).copied().unwrap_or(default)
        } else {
            default
        }
    };
    let first = *l.points.first()?;
    let moves = l
        .points
        .iter()
        .enumerate()
        .map(|(i, &p)| Move {
            kind: MoveKind::Line,
            to: p,
            feed: if i == 0 {
                spec.plunge_feed
            } else {
                per_point(&l.feed, i, spec.feed)
            },
            power: per_point(&l.power, i, spec.power),
        })
        .collect();
    Some(Cut {
        source,
        group: None,
        start: DVec3::new(first.x, first.y, 0.0),
        moves,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::tests::square;

    fn spec(kind: OperationKind, geometry: Geometry) -> OpSpec {
        OpSpec {
            name: format!("{kind:?}"),
            kind,
            geometry,
            sources: vec![],
            groups: vec![],
            design_index: None,
            air_assist: false,
            depth: 3.0,
            step_down: 1.0,
            repeat: 1,
            feed: 800.0,
            plunge_feed: 200.0,
            power: 1.0,
            tabs: None,
            lead: Lead::None,
            dwell: 0.5,
        }
    }

    /// The box of the geometry is the box of the planned toolpath (no leads), whatever the
    /// tool's start and so whatever the order and seams: a circle of radius 3 about (10, 20)
    /// as two half arcs starting at 45° (its box 7..13 × 17..23 comes from the arcs'
    /// extremes, not their ends), a square 40..44 × 0..4 and a drilled point (−5, 30).
    #[test]
    fn geometry_bounds_are_the_planned_box_from_any_start() {
        use crate::geom::{Arc, PathSeg};
        let c = DVec2::new(10.0, 20.0);
        let q = std::f64::consts::FRAC_PI_4;
        let circle = Path::new(
            vec![
                PathSeg::Arc(Arc::new(c, 3.0, q, std::f64::consts::PI)),
                PathSeg::Arc(Arc::new(
                    c,
                    3.0,
                    q + std::f64::consts::PI,
                    std::f64::consts::PI,
                )),
            ],
            true,
        );
        let paths = Geometry::Paths(vec![square(DVec2::new(42.0, 2.0), 2.0), circle]);
        let points = Geometry::Points(vec![DVec2::new(-5.0, 30.0)]);
        let Aabb { min: lo, max: hi } = paths.bounds().expect("paths have a box");
        assert!(lo.distance(DVec2::new(7.0, 0.0)) < 1e-12, "{lo}");
        assert!(hi.distance(DVec2::new(44.0, 23.0)) < 1e-12, "{hi}");
        assert_eq!(
            points.bounds(),
            Some(Aabb::new(DVec2::new(-5.0, 30.0), DVec2::new(-5.0, 30.0)))
        );
        assert_eq!(Geometry::Points(vec![]).bounds(), None);
        let specs = [spec(OperationKind::Profile, paths)];
        for home in [
            DVec2::ZERO,
            DVec2::new(100.0, -50.0),
            DVec2::new(10.0, 26.0),
        ] {
            let (tp, _) = plan(&specs, home, 1e-6);
            let s = tp.stats(home);
            let got = [s.bbox_min[0], s.bbox_min[1], s.bbox_max[0], s.bbox_max[1]];
            for (g, w) in got.into_iter().zip([lo.x, lo.y, hi.x, hi.y]) {
                assert!((g - w).abs() < 1e-9, "{home}: {got:?}");
            }
        }
    }

    #[test]
    fn operations_run_holes_first_backboard_last() {
        let specs = vec![
            spec(
                OperationKind::Backboard,
                Geometry::Paths(vec![square(DVec2::ZERO, 50.0)]),
            ),
            spec(
                OperationKind::Profile,
                Geometry::Paths(vec![square(DVec2::ZERO, 10.0)]),
            ),
            spec(
                OperationKind::Holes,
                Geometry::Points(vec![DVec2::new(1.0, 1.0)]),
            ),
        ];
        let (tp, stats) = plan(&specs, DVec2::ZERO, 1e-3);
        let kinds: Vec<OperationKind> = tp.operations.iter().map(|o| o.kind).collect();
        assert_eq!(
            kinds,
            vec![
                OperationKind::Holes,
                OperationKind::Profile,
                OperationKind::Backboard
            ]
        );
        assert_eq!(stats.len(), 3);
        // The drill pecks to 3 mm in three steps with a dwell at each.
        let drill = &tp.operations[0].cuts[0];
        let zs: Vec<f64> = drill
            .moves
            .iter()
            .filter(|m| matches!(m.kind, MoveKind::Line))
            .map(|m| m.to.z)
            .collect();
        assert_eq!(zs, vec![-1.0, -2.0, -3.0]);
    }

    #[test]
    fn sources_follow_their_paths_through_ordering() {
        let mut s = spec(
            OperationKind::Profile,
            Geometry::Paths(vec![
                square(DVec2::new(100.0, 0.0), 5.0),
                square(DVec2::ZERO, 5.0),
            ]),
        );
        s.sources = vec!["far".into(), "near".into()];
        let (tp, _) = plan(&[s], DVec2::ZERO, 1e-3);
        let src: Vec<Option<String>> = tp.operations[0]
            .cuts
            .iter()
            .map(|c| c.source.clone())
            .collect();
        assert_eq!(src, vec![Some("near".into()), Some("far".into())]);
    }

    #[test]
    fn attributed_polylines_carry_feed_and_power_per_point() {
        let pts: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(i as f64, 0.0, -0.1 * i as f64))
            .collect();
        let line = AttrPolyline {
            points: pts.clone(),
            feed: (0..5).map(|i| 100.0 + i as f64).collect(),
            power: (0..5).map(|i| 0.1 * i as f64).collect(),
        };
        // A second line without attributes falls back to the operation's feed and power.
        let plain = AttrPolyline {
            points: pts.clone(),
            ..AttrPolyline::default()
        };
        let s = spec(
            OperationKind::VCarve,
            Geometry::AttrPolylines3(vec![line, plain]),
        );
        let (tp, _) = plan(&[s], DVec2::ZERO, 1e-3);
        let cuts = &tp.operations[0].cuts;
        assert_eq!(cuts.len(), 2);
        for (i, m) in cuts[0].moves.iter().enumerate() {
            assert_eq!(m.to, pts[i]);
            assert_eq!(m.power, 0.1 * i as f64);
            let want = if i == 0 { 200.0 } else { 100.0 + i as f64 };
            assert_eq!(m.feed, want);
        }
        assert!(cuts[1].moves.iter().all(|m| m.power == 1.0));
        assert!(cuts[1].moves[1..].iter().all(|m| m.feed == 800.0));
    }
}
