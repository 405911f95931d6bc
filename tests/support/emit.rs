//! Shared fixtures for the emit integration tests: hand-built toolpaths.
#![allow(dead_code)]

use glam::{DVec2, DVec3};
use skinpath::toolpath::{Cut, Move, MoveKind, Operation, OperationKind, Toolpath};

pub fn line(x: f64, y: f64, z: f64, power: f64) -> Move {
    Move {
        kind: MoveKind::Line,
        to: DVec3::new(x, y, z),
        feed: 800.0,
        power,
    }
}

pub fn arc(x: f64, y: f64, z: f64, c: DVec2, ccw: bool, power: f64) -> Move {
    Move {
        kind: MoveKind::Arc { center: c, ccw },
        to: DVec3::new(x, y, z),
        feed: 600.0,
        power,
    }
}

pub fn cut(start: DVec3, moves: Vec<Move>) -> Cut {
    Cut {
        source: Some("stroke 1".into()),
        group: None,
        start,
        moves,
    }
}

pub fn op(name: &str, kind: OperationKind, cuts: Vec<Cut>) -> Operation {
    Operation {
        name: name.into(),
        kind,
        design_index: None,
        air_assist: false,
        cuts,
    }
}

/// A rounded rectangle at (x0, y0), w × h, corner radius r, at depth z: lines and
/// counter-clockwise quarter arcs, closed.
pub fn rounded_rect(x0: f64, y0: f64, w: f64, h: f64, r: f64, z: f64, p: f64) -> Cut {
    let (x1, y1) = (x0 + w, y0 + h);
    cut(
        DVec3::new(x0 + r, y0, z),
        vec![
            line(x1 - r, y0, z, p),
            arc(x1, y0 + r, z, DVec2::new(x1 - r, y0 + r), true, p),
            line(x1, y1 - r, z, p),
            arc(x1 - r, y1, z, DVec2::new(x1 - r, y1 - r), true, p),
            line(x0 + r, y1, z, p),
            arc(x0, y1 - r, z, DVec2::new(x0 + r, y1 - r), true, p),
            line(x0, y0 + r, z, p),
            arc(x0 + r, y0, z, DVec2::new(x0 + r, y0 + r), true, p),
        ],
    )
}

/// A full circle of radius r about c (one arc move back to the start).
pub fn circle(c: DVec2, r: f64, z: f64, ccw: bool, p: f64) -> Cut {
    let s = DVec3::new(c.x + r, c.y, z);
    cut(s, vec![arc(s.x, s.y, z, c, ccw, p)])
}

/// An open S-curve from `o`: a clockwise semicircle (radius 10), a 270° counter-clockwise
/// arc (radius 8), a line.
pub fn s_curve(o: DVec2, z: f64, p: f64) -> Cut {
    let c1 = o + DVec2::new(10.0, 0.0);
    let e1 = o + DVec2::new(20.0, 0.0);
    let c2 = e1 + DVec2::new(8.0, 0.0);
    let e2 = c2 + DVec2::new(0.0, 8.0);
    cut(
        DVec3::new(o.x, o.y, z),
        vec![
            arc(e1.x, e1.y, z, c1, false, p),
            arc(e2.x, e2.y, z, c2, true, p),
            line(e2.x + 15.0, e2.y, z, p),
        ],
    )
}

/// A job of every kind of geometry; the outline is cut once per depth in `zs` (passes).
pub fn job(zs: &[f64], p: f64) -> Toolpath {
    let mut outline = Vec::new();
    for &z in zs {
        outline.push(rounded_rect(20.0, 20.0, 60.0, 40.0, 5.0, z, p));
    }
    let z = zs[zs.len() - 1];
    Toolpath {
        operations: vec![
            op(
                "holes",
                OperationKind::Holes,
                vec![
                    circle(DVec2::new(30.0, 40.0), 3.0, z, true, p),
                    circle(DVec2::new(70.0, 40.0), 3.0, z, false, p),
                ],
            ),
            op(
                "spine",
                OperationKind::Channel,
                vec![s_curve(DVec2::new(25.0, 30.0), z, p)],
            ),
            op("outline", OperationKind::Profile, outline),
        ],
    }
}

/// The xy length of every cutting move of `tp` (lines and arcs), in mm.
pub fn cut_length_xy(tp: &Toolpath) -> f64 {
    let mut total = 0.0;
    for op in &tp.operations {
        for c in &op.cuts {
            let mut pos = c.start;
            for m in &c.moves {
                match m.kind {
                    MoveKind::Line => total += (m.to - pos).truncate().length(),
                    MoveKind::Arc { center, ccw } => {
                        let a = skinpath::geom::Arc::from_center_points(
                            center,
                            pos.truncate(),
                            m.to.truncate(),
                            ccw,
                        );
                        total += a.length();
                    }
                    _ => {}
                }
                if !matches!(m.kind, MoveKind::Dwell { .. }) {
                    pos = m.to;
                }
            }
        }
    }
    total
}

/// Arc centres and radii of the input (mm).
pub fn arc_circles(tp: &Toolpath) -> Vec<(DVec2, f64)> {
    let mut out = Vec::new();
    for op in &tp.operations {
        for c in &op.cuts {
            let mut pos = c.start;
            for m in &c.moves {
                if let MoveKind::Arc { center, .. } = m.kind {
                    out.push((center, pos.truncate().distance(center)));
                }
                if !matches!(m.kind, MoveKind::Dwell { .. }) {
                    pos = m.to;
                }
            }
        }
    }
    out
}

/// A chain of lines and tangent arcs from `start`: each step is (kind, length or radius,
/// turn of the heading, arc sweep, ccw); kind 0 is a line, anything else an arc.
pub fn chain(start: DVec2, steps: &[(u8, f64, f64, f64, bool)], z: f64) -> Vec<Move> {
    let mut moves = Vec::new();
    let mut pos = start;
    let mut heading: f64 = 0.0;
    for &(kind, len, turn, sweep, ccw) in steps {
        heading += turn;
        let dir = DVec2::new(heading.cos(), heading.sin());
        if kind == 0 {
            pos += len * dir;
            moves.push(line(pos.x, pos.y, z, 0.7));
        } else {
            // Arc of radius `len` tangent to the heading, turning left or right.
            let left = DVec2::new(-dir.y, dir.x);
            let c = if ccw {
                pos + len * left
            } else {
                pos - len * left
            };
            let a0 = (pos - c).to_angle();
            let a1 = a0 + if ccw { sweep } else { -sweep };
            pos = c + len * DVec2::new(a1.cos(), a1.sin());
            moves.push(arc(pos.x, pos.y, z, c, ccw, 0.7));
            heading += if ccw { sweep } else { -sweep };
        }
    }
    moves
}
