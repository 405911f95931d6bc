//! Figures of a toolpath: cutting length, travel length, bounding box, time at feed.

use super::model::{MoveKind, Toolpath};
use crate::geom::Arc;
use glam::{DVec2, DVec3};

/// Summary figures of a toolpath (design units; time in seconds).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct ToolpathStats {
    /// Number of operations.
    pub operations: usize,
    /// Number of cuts.
    pub cuts: usize,
    /// Length of every cutting move (lines, arcs with their helix z change).
    pub cut_length: f64,
    /// Straight-line travel between cuts, starting from the origin.
    pub travel_length: f64,
    /// Cutting time at the programmed feeds (no acceleration).
    pub cut_time: f64,
    /// Lower corner of the bounding box (x, y, z).
    pub bbox_min: [f64; 3],
    /// Upper corner of the bounding box (x, y, z).
    pub bbox_max: [f64; 3],
}

/// Length of a move from `from`: arcs by radius × sweep (with the helix's z), lines by
/// distance, dwells zero.
#[must_use]
pub fn move_length(from: DVec3, kind: &MoveKind, to: DVec3) -> f64 {
    match kind {
        MoveKind::Line | MoveKind::Rapid => from.distance(to),
        MoveKind::Arc { center, ccw } => {
            let a = Arc::from_center_points(*center, from.truncate(), to.truncate(), *ccw);
            a.length().hypot(to.z - from.z)
        }
        MoveKind::Dwell { .. } => 0.0,
    }
}

impl Toolpath {
    /// Summary figures; `home` is where the tool starts. The bounding box is exact: arcs
    /// count with their axis-extreme points.
    #[must_use]
    pub fn stats(&self, home: DVec2) -> ToolpathStats {
        let mut s = ToolpathStats {
            operations: self.operations.len(),
            cuts: 0,
            cut_length: 0.0,
            travel_length: 0.0,
            cut_time: 0.0,
            bbox_min: [f64::INFINITY; 3],
            bbox_max: [f64::NEG_INFINITY; 3],
        };
        let mut grow = |p: DVec3| {
            for (i, v) in p.to_array().into_iter().enumerate() {
                s.bbox_min[i] = s.bbox_min[i].min(v);
                s.bbox_max[i] = s.bbox_max[i].max(v);
            }
        };
        let mut pos = home;
        let (mut cut_length, mut travel, mut time, mut cuts) = (0.0, 0.0, 0.0, 0);
        for op in &self.operations {
            for cut in &op.cuts {
                cuts += 1;
                travel += pos.distance(cut.start.truncate());
                let mut here = cut.start;
                grow(here);
                for m in &cut.moves {
                    let l = move_length(here, &m.kind, m.to);
                    // Arcs reach past their end points: add their axis-extreme points.
                    if let MoveKind::Arc { center, ccw } = m.kind {
                        let a =
                            Arc::from_center_points(center, here.truncate(), m.to.truncate(), ccw);
                        for q in a.extrema() {
                            grow(DVec3::new(q.x, q.y, here.z.min(m.to.z)));
                        }
                    }
                    match m.kind {
                        MoveKind::Rapid => travel += l,
                        MoveKind::Dwell { seconds } => time += seconds,
                        _ => {
                            cut_length += l;
                            if m.feed > 0.0 {
                                time += 60.0 * l / m.feed;
                            }
                        }
                    }
                    here = m.to;
                    grow(here);
                }
                pos = here.truncate();
            }
        }
        s.cuts = cuts;
        s.cut_length = cut_length;
        s.travel_length = travel;
        s.cut_time = time;
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::model::{Cut, Move, Operation, OperationKind};

    #[test]
    fn full_circle_and_line_lengths() {
        // A unit-radius circle as two half arcs, then a line of 3: length π·2 + 3.
        let c = DVec2::ZERO;
        let mv = |kind, x: f64, y: f64| Move {
            kind,
            to: DVec3::new(x, y, 0.0),
            feed: 600.0,
            power: 1.0,
        };
        let tp = Toolpath {
            operations: vec![Operation {
                name: "p".into(),
                kind: OperationKind::Profile,
                design_index: None,
                air_assist: false,
                cuts: vec![Cut {
                    source: None,
                    group: None,
                    start: DVec3::new(1.0, 0.0, 0.0),
                    moves: vec![
                        mv(
                            MoveKind::Arc {
                                center: c,
                                ccw: true,
                            },
                            -1.0,
                            0.0,
                        ),
                        mv(
                            MoveKind::Arc {
                                center: c,
                                ccw: true,
                            },
                            1.0,
                            0.0,
                        ),
                        mv(MoveKind::Line, 4.0, 0.0),
                    ],
                }],
            }],
        };
        let s = tp.stats(DVec2::ZERO);
        assert!((s.cut_length - (2.0 * std::f64::consts::PI + 3.0)).abs() < 1e-12);
        assert!((s.travel_length - 1.0).abs() < 1e-12);
        // 600 mm/min = 10 mm/s.
        assert!((s.cut_time - s.cut_length / 10.0).abs() < 1e-12);
        assert_eq!(s.bbox_max[0], 4.0);
        // The circle reaches y = ±1 and x = −1 between its end points.
        assert!((s.bbox_min[1] + 1.0).abs() < 1e-12 && (s.bbox_max[1] - 1.0).abs() < 1e-12);
        assert!((s.bbox_min[0] + 1.0).abs() < 1e-12);
    }
}
