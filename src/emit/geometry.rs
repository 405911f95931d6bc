//! Validation of toolpath moves and their plane geometry (contours of lines and arcs), shared
//! by all writers.
//!
//! A [`CutContour`] is a run of a toolpath's cutting segments as the writers emit it; not to
//! be confused with [`OutlineContour`](super::outline::OutlineContour) (a flattened contour
//! of the outline document) or [`SimContour`](crate::sim::checks::SimContour) (a cut contour
//! the G-code checker rebuilt from simulated moves).

use super::{EmitError, Location};
use crate::geom::Arc;
use crate::toolpath::{Cut, MoveKind, OperationKind, Toolpath};
use glam::{DVec2, DVec3};

/// A plane segment of a contour, from the previous point to `to`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Seg {
    /// A straight line.
    Line {
        /// End point.
        to: DVec2,
    },
    /// A circular arc about `center`; `sweep` is signed (counter-clockwise positive) with
    /// 0 < |sweep| ≤ 2π (a full circle when `to` is the start point).
    Arc {
        /// End point.
        to: DVec2,
        /// Arc centre.
        center: DVec2,
        /// Signed sweep angle (radians, counter-clockwise positive).
        sweep: f64,
    },
}

impl Seg {
    /// End point of the segment.
    pub fn to(&self) -> DVec2 {
        match *self {
            Seg::Line { to } | Seg::Arc { to, .. } => to,
        }
    }
}

/// A connected run of cutting segments in the plane: one cut, or the part of a cut between
/// two rapids. Plunges and retracts (pure z moves) and dwells leave no trace here.
#[derive(Clone, Debug, PartialEq)]
pub struct CutContour {
    /// Index of the operation in the toolpath.
    pub op: usize,
    /// Kind of that operation (chooses the colour or layer).
    pub kind: OperationKind,
    /// Index of the cut in its operation.
    pub cut: usize,
    /// Start point.
    pub start: DVec2,
    /// Segments from the start point on.
    pub segs: Vec<Seg>,
    /// Power fraction of the first cutting move.
    pub power: f64,
}

impl CutContour {
    /// End point of the contour (the start when it has no segments).
    pub fn end(&self) -> DVec2 {
        self.segs.last().map_or(self.start, |s| s.to())
    }

    /// True when the contour returns to its start within `tol`.
    pub fn is_closed(&self, tol: f64) -> bool {
        !self.segs.is_empty() && self.end().distance(self.start) <= tol
    }
}

/// The swept arc of an arc move from `from` to `to` about `center`. Equal directions (after
/// the model's own arithmetic) give a full circle.
pub fn arc_of(from: DVec2, to: DVec2, center: DVec2, ccw: bool) -> Arc {
    Arc::from_center_points(center, from, to, ccw)
}

/// Checks every move of `tp`: finite coordinates, feed and power; power in [0, 1]; feed > 0
/// on cutting moves; dwell ≥ 0; arcs of positive radius whose start and end radii agree
/// within `tol` (the largest radius mismatch a controller accepts is about 0.005 mm, GRBL's
/// error 33, so callers pass at most that).
pub fn validate(tp: &Toolpath, tol: f64) -> Result<(), EmitError> {
    for (oi, op) in tp.operations.iter().enumerate() {
        for (ci, cut) in op.cuts.iter().enumerate() {
            let at = |mv: Option<usize>| Location {
                op: oi,
                op_name: op.name.clone(),
                cut: ci,
                mv,
            };
            if !cut.start.is_finite() {
                return Err(EmitError::InvalidMove {
                    at: at(None),
                    reason: format!("start {} is not finite", cut.start),
                });
            }
            let mut pos = cut.start;
            for (mi, m) in cut.moves.iter().enumerate() {
                let bad = |reason: String| EmitError::InvalidMove {
                    at: at(Some(mi)),
                    reason,
                };
                if !m.to.is_finite() {
                    return Err(bad(format!("target {} is not finite", m.to)));
                }
                if !(m.power.is_finite() && (0.0..=1.0).contains(&m.power)) {
                    return Err(bad(format!("power {} is outside [0, 1]", m.power)));
                }
                match m.kind {
                    MoveKind::Rapid => {}
                    MoveKind::Dwell { seconds } => {
                        if !(seconds.is_finite() && seconds >= 0.0) {
                            return Err(bad(format!("dwell of {seconds} s")));
                        }
                    }
                    MoveKind::Line | MoveKind::Arc { .. } => {
                        if !(m.feed.is_finite() && m.feed > 0.0) {
                            return Err(bad(format!("feed {} must be > 0", m.feed)));
                        }
                    }
                }
                if let MoveKind::Arc { center, .. } = m.kind {
                    if !center.is_finite() {
                        return Err(bad(format!("arc centre {center} is not finite")));
                    }
                    let r0 = pos.truncate().distance(center);
                    let r1 = m.to.truncate().distance(center);
                    if r0 <= tol {
                        return Err(bad(format!("arc radius {r0} is not positive")));
                    }
                    if (r0 - r1).abs() > tol {
                        return Err(bad(format!(
                            "arc start radius {r0} and end radius {r1} differ by more than {tol}"
                        )));
                    }
                }
                if !matches!(m.kind, MoveKind::Dwell { .. }) {
                    pos = m.to;
                }
            }
        }
    }
    Ok(())
}

/// The plane contours of every cut, in cut order (call [`validate`] first).
pub fn contours(tp: &Toolpath) -> Vec<CutContour> {
    let mut out = Vec::new();
    for (oi, op) in tp.operations.iter().enumerate() {
        for (ci, cut) in op.cuts.iter().enumerate() {
            cut_contours(oi, op.kind, ci, cut, &mut out);
        }
    }
    out
}

fn cut_contours(op: usize, kind: OperationKind, ci: usize, cut: &Cut, out: &mut Vec<CutContour>) {
    let new = |start: DVec2| CutContour {
        op,
        kind,
        cut: ci,
        start,
        segs: Vec::new(),
        power: 0.0,
    };
    let mut cur = new(cut.start.truncate());
    let mut pos: DVec3 = cut.start;
    for m in &cut.moves {
        match m.kind {
            MoveKind::Dwell { .. } => continue,
            MoveKind::Rapid => {
                if !cur.segs.is_empty() {
                    out.push(std::mem::replace(&mut cur, new(m.to.truncate())));
                } else {
                    cur.start = m.to.truncate();
                }
            }
            MoveKind::Line => {
                if m.to.truncate() != pos.truncate() {
                    if cur.segs.is_empty() {
                        cur.power = m.power;
                    }
                    cur.segs.push(Seg::Line {
                        to: m.to.truncate(),
                    });
                }
            }
            MoveKind::Arc { center, ccw } => {
                if cur.segs.is_empty() {
                    cur.power = m.power;
                }
                let a = arc_of(pos.truncate(), m.to.truncate(), center, ccw);
                cur.segs.push(Seg::Arc {
                    to: m.to.truncate(),
                    center,
                    sweep: a.sweep,
                });
            }
        }
        pos = m.to;
    }
    if !cur.segs.is_empty() {
        out.push(cur);
    }
}

/// The exact bounding box (lo, hi) of `cs` and `extra` points, arcs included through their
/// axis-extreme points; `None` when there is nothing.
pub fn bounds(cs: &[CutContour], extra: &[DVec2]) -> Option<(DVec2, DVec2)> {
    let mut b: Option<(DVec2, DVec2)> = None;
    let mut add = |p: DVec2| {
        b = Some(b.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))));
    };
    for p in extra {
        add(*p);
    }
    for c in cs {
        add(c.start);
        let mut from = c.start;
        for s in &c.segs {
            if let Seg::Arc { center, sweep, .. } = *s {
                let r = from.distance(center);
                let a = Arc::new(center, r, (from - center).to_angle(), sweep);
                a.extrema().for_each(&mut add);
            }
            add(s.to());
            from = s.to();
        }
    }
    b
}

/// Splits the arc `from` → `to` about `center` with signed `sweep` into the fewest equal
/// pieces of at most `max_sweep` each; returns the pieces' end points (the last is `to`).
pub fn split_arc(from: DVec2, to: DVec2, center: DVec2, sweep: f64, max_sweep: f64) -> Vec<DVec2> {
    let n = ((sweep.abs() / max_sweep).ceil() as usize).max(1);
    let r = from.distance(center);
    let a0 = (from - center).to_angle();
    let mut pts: Vec<DVec2> = (1..n)
        .map(|i| {
            let a = a0 + sweep * i as f64 / n as f64;
            center + r * DVec2::new(a.cos(), a.sin())
        })
        .collect();
    pts.push(to);
    pts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::{Move, Operation};
    use std::f64::consts::PI;

    fn mv(kind: MoveKind, x: f64, y: f64) -> Move {
        Move {
            kind,
            to: DVec3::new(x, y, 0.0),
            feed: 100.0,
            power: 0.5,
        }
    }

    fn tp(moves: Vec<Move>) -> Toolpath {
        Toolpath {
            operations: vec![Operation {
                name: "t".into(),
                kind: OperationKind::Profile,
                design_index: None,
                air_assist: false,
                cuts: vec![Cut {
                    source: None,
                    group: None,
                    start: DVec3::new(1.0, 0.0, 0.0),
                    moves,
                }],
            }],
        }
    }

    #[test]
    fn full_circle_and_split() {
        let c = DVec2::ZERO;
        let t = tp(vec![mv(
            MoveKind::Arc {
                center: c,
                ccw: true,
            },
            1.0,
            0.0,
        )]);
        validate(&t, 1e-6).unwrap();
        let cs = contours(&t);
        assert_eq!(cs.len(), 1);
        let Seg::Arc { sweep, .. } = cs[0].segs[0] else {
            panic!()
        };
        assert!((sweep - 2.0 * PI).abs() < 1e-12);
        assert!(cs[0].is_closed(1e-9));
        let pts = split_arc(DVec2::X, DVec2::X, c, sweep, PI / 2.0 + 1e-9);
        assert_eq!(pts.len(), 4);
        assert!((pts[0] - DVec2::Y).length() < 1e-12);
        assert!((pts[1] + DVec2::X).length() < 1e-12);
    }

    #[test]
    fn rejects_bad_moves_with_location() {
        let off = tp(vec![mv(
            MoveKind::Arc {
                center: DVec2::ZERO,
                ccw: false,
            },
            0.0,
            2.0,
        )]);
        let e = validate(&off, 1e-3).unwrap_err();
        assert!(e.to_string().contains("cut 0, move 0"), "{e}");
        let mut hot = tp(vec![mv(MoveKind::Line, 2.0, 0.0)]);
        hot.operations[0].cuts[0].moves[0].power = 1.5;
        assert!(validate(&hot, 1e-3).is_err());
        let nan = tp(vec![mv(MoveKind::Line, f64::NAN, 0.0)]);
        assert!(validate(&nan, 1e-3).is_err());
    }

    #[test]
    fn rapids_split_contours_and_plunges_vanish() {
        let mut plunge = mv(MoveKind::Line, 1.0, 0.0);
        plunge.to.z = -1.0;
        let t = tp(vec![
            plunge,
            mv(MoveKind::Line, 2.0, 0.0),
            mv(MoveKind::Rapid, 5.0, 5.0),
            mv(MoveKind::Line, 6.0, 5.0),
        ]);
        let cs = contours(&t);
        assert_eq!(cs.len(), 2);
        assert_eq!(cs[0].segs.len(), 1);
        assert_eq!(cs[1].start, DVec2::new(5.0, 5.0));
    }
}
