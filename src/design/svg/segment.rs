//! The geometry of one path segment (2, 3 or 4 control points) and of a subpath's
//! nodes: tangents, turns, flattening and nearest points through kurbo.

use super::*;
use kurbo::{BezPath, CubicBez, PathEl, QuadBez};

/// The largest number of segments of one subpath of `data` (`None` for no segment), counted
/// without flattening.
pub(super) fn longest_subpath(data: &usvg::tiny_skia_path::Path) -> Option<usize> {
    use usvg::tiny_skia_path::PathVerb as V;
    let (mut best, mut cur) = (None, 0usize);
    for v in data.verbs() {
        match v {
            V::Move => cur = 0,
            V::Close => {}
            _ => {
                cur += 1;
                best = Some(best.unwrap_or(0).max(cur));
            }
        }
    }
    best
}

impl Subpath {
    /// An open subpath along the polyline `pts`, a node at every point with the turn there.
    pub(super) fn polyline(pts: Vec<DVec2>) -> Self {
        let n = pts.len();
        let nodes = (0..n)
            .map(|i| {
                let a = if i > 0 && i + 1 < n {
                    turn(pts[i] - pts[i - 1], pts[i + 1] - pts[i])
                } else {
                    0.0
                };
                (i, a)
            })
            .collect();
        Subpath {
            pts,
            nodes,
            closed: false,
            times: Vec::new(),
        }
    }
}

pub(super) fn turn(a: DVec2, b: DVec2) -> f64 {
    if a.length() == 0.0 || b.length() == 0.0 {
        return 0.0;
    }
    a.angle_to(b).abs()
}

use crate::geom::interop::{from_kurbo_point as dv, kurbo_point as kp};

/// Start and end tangents of a segment given by its control points (the first control
/// point apart from the end point; zero for a degenerate segment).
pub(super) fn tangents(ctrl: &[DVec2]) -> (DVec2, DVec2) {
    let first = ctrl[0];
    let last = ctrl[ctrl.len() - 1];
    let start = ctrl[1..]
        .iter()
        .find(|&&q| q != first)
        .map_or(DVec2::ZERO, |&q| q - first);
    let end = ctrl[..ctrl.len() - 1]
        .iter()
        .rev()
        .find(|&&q| q != last)
        .map_or(DVec2::ZERO, |&q| last - q);
    (start, end)
}

/// Flatten one segment (control points) to points after its start, within `tol`.
pub(super) fn flatten_segment(ctrl: &[DVec2], tol: f64, out: &mut Vec<DVec2>) {
    match ctrl.len() {
        2 => out.push(ctrl[1]),
        3 => {
            let q = QuadBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]));
            let mut bp = BezPath::new();
            bp.move_to(q.p0);
            bp.quad_to(q.p1, q.p2);
            flatten_into(&bp, tol, out);
        }
        _ => {
            let c = CubicBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]), kp(ctrl[3]));
            let mut bp = BezPath::new();
            bp.move_to(c.p0);
            bp.curve_to(c.p1, c.p2, c.p3);
            flatten_into(&bp, tol, out);
        }
    }
}

fn flatten_into(bp: &BezPath, tol: f64, out: &mut Vec<DVec2>) {
    kurbo::flatten(bp.iter(), tol, |el| {
        if let PathEl::LineTo(p) = el {
            out.push(dv(p));
        }
    });
}

/// Parameter in [0, 1] of the point of the segment `ctrl` (2, 3 or 4 control points) nearest
/// to `q`, found to `accuracy` (kurbo's nearest-point search on the curve).
pub(super) fn segment_time(ctrl: &[DVec2], q: DVec2, accuracy: f64) -> f64 {
    use kurbo::{Line, ParamCurveNearest};
    let q = kp(q);
    match ctrl.len() {
        2 => Line::new(kp(ctrl[0]), kp(ctrl[1])).nearest(q, accuracy).t,
        3 => {
            QuadBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]))
                .nearest(q, accuracy)
                .t
        }
        _ => {
            CubicBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]), kp(ctrl[3]))
                .nearest(q, accuracy)
                .t
        }
    }
}

/// The point at parameter `t` of the segment `ctrl` (2, 3 or 4 control points).
pub(super) fn segment_point(ctrl: &[DVec2], t: f64) -> DVec2 {
    use kurbo::{Line, ParamCurve};
    dv(match ctrl.len() {
        2 => Line::new(kp(ctrl[0]), kp(ctrl[1])).eval(t),
        3 => QuadBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2])).eval(t),
        _ => CubicBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]), kp(ctrl[3])).eval(t),
    })
}
