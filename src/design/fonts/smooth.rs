//! Smooth spines of the glyph polylines: the Hershey glyphs are polylines on an integer
//! grid, their curves sampled every one to three units, so a spine through the vertices
//! kinks at every vertex and wiggles with the rounding. Each polyline becomes a chain of
//! cubic B-splines instead:
//!
//! - **Corners** are the vertices where the polyline turns by more than
//!   [`FONT_CORNER_DEG`] (stems meeting bars, cusps of the script letters); elsewhere the
//!   glyph is a curve and its spine is G1 (C² inside a piece).
//! - Each piece between corners is fitted by least squares
//!   ([`crate::spline::fit::least_squares_with_params`], P&T Sec. 9.4.1) to points
//!   resampled every [`SAMPLE_STEP`] along it, with the fewest control points (from 4 up)
//!   whose curve lies within [`FIT_TOLERANCE`] of the polyline both ways (two-sided
//!   distance, [`deviation`]); a piece whose vertices are collinear is a segment.
//!   Its end points are the polyline's, exactly (the fit keeps them), and its end tangents
//!   are the polyline's end segments: the second and the second-last control point are
//!   moved onto those segments' lines ([`keep_end_tangents`]), so script letters whose
//!   entry and exit segments line up still join tangentially and a corner keeps its angle.
//! - A closed polyline without corners is one periodic cubic; one with corners is an open chain from a corner round to it. Closed polylines no larger
//!   than [`super::latin1::DOT_SIZE`] (dots: diamonds and squares) have no corners.
//!
//! The pieces use clamped uniform knots, the knots a `disks` stroke with `corners` gets
//! when it is loaded, so a spine is written as such a stroke (its control disks and
//! corners) and loads as the curve fitted here. To get those knots from the fitter, the
//! m resampled points (equally spaced in arc length) get the parameters t_0 = 0,
//! t_i = (i + 1)/m for i ≥ 1: nearly their arc length, and exactly the parameters for
//! which P&T eq. 9.68–9.69 put the interior knots at j/(n − p) when m ≥ 2(n − p)
//! ([`uniform_knot_params`]).

use crate::geom::{DVec2, Line};
use crate::spline::BSpline;
use crate::spline::fit::least_squares_with_params;

/// Turning angle (degrees) above which a glyph vertex is a corner. On the Hershey grid the
/// sampled curves turn by at most 72° at a vertex (the tight tops of the script humps and
/// loops, a (2, −1) segment followed by a (1, 1)), the corners and cusps of the letters
/// by 84° (the sans 5) and more (90° at the sans e's bar, 150–175° at the script cusps).
pub const FONT_CORNER_DEG: f64 = 80.0;

/// Largest distance (grid units, cap height 21) between a spine and its glyph polyline:
/// the grid's own rounding (±0.5), 2.4 % of the cap height.
pub const FIT_TOLERANCE: f64 = 0.5;

/// Spacing (grid units) of the points a piece is resampled to before fitting.
pub const SAMPLE_STEP: f64 = 0.25;

/// The spines' degree.
pub const SPINE_DEGREE: usize = 3;

/// Samples per knot span when a spine is measured against its polyline.
pub const CHECK_SAMPLES: usize = 24;

/// Most control points a piece is fitted with.
const MAX_CTRL: usize = 64;

/// Shortest end handle (second control point from the end), as a fraction of the end
/// segment: where the fit's handle points backwards, the spine still leaves along it.
const MIN_HANDLE: f64 = 0.1;

/// A glyph polyline as a smooth spine (grid units, y down).
#[derive(Clone, Debug, PartialEq)]
pub struct Spine {
    /// The control points of the pieces, one after the other; neighbouring pieces share
    /// the control point at their joint.
    pub ctrl: Vec<DVec2>,
    /// Indices into `ctrl` of the joints: the glyph's corners (and, in a laid-out text,
    /// G1 splits of pieces that loop back to their own end).
    pub corners: Vec<usize>,
    /// A periodic curve (no corners) through `ctrl` cyclically.
    pub closed: bool,
}

/// The degree of a piece of `n` control points (as loading gives it).
fn degree_of(n: usize) -> usize {
    SPINE_DEGREE.min(n - 1)
}

/// An open piece on clamped uniform knots.
pub fn open_curve(ctrl: &[DVec2]) -> Option<BSpline<DVec2>> {
    if ctrl.len() < 2 {
        return None;
    }
    BSpline::clamped_uniform(degree_of(ctrl.len()), ctrl.to_vec()).ok()
}

impl Spine {
    /// The inclusive index ranges of the pieces (one for a closed spine).
    pub fn pieces(&self) -> Vec<(usize, usize)> {
        let mut b = vec![0];
        b.extend(self.corners.iter().copied());
        b.push(self.ctrl.len() - 1);
        b.windows(2).map(|w| (w[0], w[1])).collect()
    }

    /// The curves of the pieces, as loading builds them.
    pub fn curves(&self) -> Vec<BSpline<DVec2>> {
        if self.closed {
            let n = self.ctrl.len();
            return BSpline::closed_uniform(degree_of(n), self.ctrl.clone())
                .ok()
                .into_iter()
                .collect();
        }
        self.pieces()
            .into_iter()
            .filter_map(|(a, b)| open_curve(&self.ctrl[a..=b]))
            .collect()
    }

    /// Points along the spine, [`CHECK_SAMPLES`] per knot span, in order (a closed spine
    /// ends where it starts).
    pub fn samples(&self) -> Vec<DVec2> {
        let mut out: Vec<DVec2> = Vec::new();
        for c in self.curves() {
            let s = sample(&c);
            let skip = usize::from(!out.is_empty());
            out.extend(s.into_iter().skip(skip));
        }
        out
    }

    /// The spine with every control point mapped by the affine map `f` (the curves map
    /// with them).
    pub fn map(&self, f: impl Fn(DVec2) -> DVec2) -> Spine {
        Spine {
            ctrl: self.ctrl.iter().map(|&p| f(p)).collect(),
            ..self.clone()
        }
    }
}

/// Points of `c`, [`CHECK_SAMPLES`] per knot span (ends included).
fn sample(c: &BSpline<DVec2>) -> Vec<DVec2> {
    let b = c.breakpoints();
    let mut out = vec![c.eval(b[0])];
    for w in b.windows(2) {
        for k in 1..=CHECK_SAMPLES {
            out.push(c.eval(w[0] + (w[1] - w[0]) * k as f64 / CHECK_SAMPLES as f64));
        }
    }
    out
}

/// Two-sided distance between the point sequences `a` and `b` taken as polylines: the
/// largest distance of a vertex of either from the other polyline (the Hausdorff distance
/// of the vertex sets to the polylines; with `a` dense samples of a curve, the curve's
/// distance from `b` within the sampling's chord error).
pub fn deviation(a: &[DVec2], b: &[DVec2]) -> f64 {
    let one_way = |from: &[DVec2], to: &[DVec2]| -> f64 {
        let segs: Vec<Line> = if to.len() == 1 {
            vec![Line::new(to[0], to[0])]
        } else {
            to.windows(2).map(|w| Line::new(w[0], w[1])).collect()
        };
        from.iter()
            .map(|&p| {
                segs.iter()
                    .map(|s| s.distance(p))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

fn arc_length(pts: &[DVec2]) -> f64 {
    pts.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// `m` points equally spaced in arc length along the polyline, its ends included.
fn resample(pts: &[DVec2], m: usize) -> Vec<DVec2> {
    let total = arc_length(pts);
    let mut out = Vec::with_capacity(m);
    let mut seg = 0;
    let mut before = 0.0;
    for i in 0..m {
        let s = total * i as f64 / (m - 1) as f64;
        while seg + 2 < pts.len() && before + pts[seg].distance(pts[seg + 1]) < s {
            before += pts[seg].distance(pts[seg + 1]);
            seg += 1;
        }
        let l = pts[seg].distance(pts[seg + 1]);
        let t = if l > 0.0 {
            ((s - before) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(pts[seg].lerp(pts[seg + 1], t));
    }
    out[m - 1] = pts[pts.len() - 1];
    out
}

/// Parameters of `m` resampled points for which the least-squares knots (P&T
/// eq. 9.68–9.69) of `n_ctrl` control points of degree p are clamped uniform: t_0 = 0,
/// t_i = (i + 1)/m (module docs). With d = m/(n − p) ≥ 2, knot j interpolates the
/// parameters at index jd − 1 ≥ 1, where they are (index + 1)/m, giving jd/m = j/(n − p).
pub fn uniform_knot_params(m: usize) -> Vec<f64> {
    (0..m)
        .map(|i| {
            if i == 0 {
                0.0
            } else {
                (i + 1) as f64 / m as f64
            }
        })
        .collect()
}

/// Move the second and second-last of `ctrl` (at least 4 points) onto the lines of the
/// polyline's end segments, in their direction, at least [`MIN_HANDLE`] of the segment
/// from the end: the spine leaves and arrives along the polyline's end segments.
pub fn keep_end_tangents(ctrl: &mut [DVec2], pts: &[DVec2]) {
    let (n, k) = (ctrl.len(), pts.len());
    let set = |end: DVec2, next: DVec2, handle: DVec2| -> DVec2 {
        let seg = next - end;
        let dir = seg.normalize_or_zero();
        end + dir * (handle - end).dot(dir).max(MIN_HANDLE * seg.length())
    };
    ctrl[1] = set(pts[0], pts[1], ctrl[1]);
    ctrl[n - 2] = set(pts[k - 1], pts[k - 2], ctrl[n - 2]);
}

/// Distance from their chord, relative to their length, within which a piece's vertices
/// are collinear: such a piece is its chord (its end directions are the chord's).
const COLLINEAR: f64 = 1e-12;

/// The control points of an open piece through the polyline `pts` (module docs): its
/// chord when the vertices are collinear ([`COLLINEAR`]), else the least-squares cubic with the fewest control
/// points within `tol` (the closest one tried when none is).
fn fit_open(pts: &[DVec2], tol: f64) -> Vec<DVec2> {
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let line = vec![a, b];
    if pts.len() == 2 || deviation(&[a, b], pts) <= COLLINEAR * arc_length(pts) {
        return line;
    }
    let len = arc_length(pts);
    let p = SPINE_DEGREE;
    let mut best: Option<(f64, Vec<DVec2>)> = None;
    for n in p + 1..=MAX_CTRL {
        let m = ((len / SAMPLE_STEP).ceil() as usize + 1).max(2 * (n - p) + 2);
        let q = resample(pts, m);
        let Ok(c) = least_squares_with_params(&q, &uniform_knot_params(m), n, p, false) else {
            continue;
        };
        let mut ctrl = c.ctrl().to_vec();
        keep_end_tangents(&mut ctrl, pts);
        let Some(curve) = open_curve(&ctrl) else {
            continue;
        };
        let dev = deviation(&sample(&curve), pts);
        if dev <= tol {
            return ctrl;
        }
        if best.as_ref().is_none_or(|(d, _)| dev < *d) {
            best = Some((dev, ctrl));
        }
    }
    best.map_or(line, |(_, c)| c)
}

/// The distinct control points of a periodic cubic around the closed polyline `pts` (not
/// repeating its first point): the fewest within `tol` ([`fit_open`]'s rule).
fn fit_closed(pts: &[DVec2], tol: f64) -> Vec<DVec2> {
    let mut ring = pts.to_vec();
    ring.push(pts[0]);
    let len = arc_length(&ring);
    let p = SPINE_DEGREE;
    let mut best: Option<(f64, Vec<DVec2>)> = None;
    for n in p + 1..=MAX_CTRL {
        let m = ((len / SAMPLE_STEP).ceil() as usize).max(2 * n);
        // m points round the ring; uniform parameters put the periodic breaks at j/n.
        let mut q = resample(&ring, m + 1);
        q.pop();
        let params: Vec<f64> = (0..=m).map(|i| i as f64 / m as f64).collect();
        let Ok(c) = least_squares_with_params(&q, &params, n, p, true) else {
            continue;
        };
        let ctrl = c.ctrl()[..n].to_vec();
        let spine = Spine {
            ctrl: ctrl.clone(),
            corners: Vec::new(),
            closed: true,
        };
        let dev = deviation(&spine.samples(), &ring);
        if dev <= tol {
            return ctrl;
        }
        if best.as_ref().is_none_or(|(d, _)| dev < *d) {
            best = Some((dev, ctrl));
        }
    }
    best.map_or_else(|| pts.to_vec(), |(_, c)| c)
}

/// The indices of the vertices of `pts` (cyclically when `closed`) that turn by more than
/// [`FONT_CORNER_DEG`].
pub fn corners_of(pts: &[DVec2], closed: bool) -> Vec<usize> {
    crate::design::corners::sharp_turns(pts, closed, FONT_CORNER_DEG)
}

/// The smooth spine of a glyph polyline (grid units) within `tol` of it (module docs), or
/// `None` for a single point.
pub fn fit_polyline(poly: &[DVec2], tol: f64) -> Option<Spine> {
    let mut pts: Vec<DVec2> = Vec::with_capacity(poly.len());
    for &p in poly {
        if pts.last() != Some(&p) {
            pts.push(p);
        }
    }
    if pts.len() < 2 {
        return None;
    }
    let closed = pts.len() >= 4 && pts[0] == pts[pts.len() - 1];
    if closed {
        pts.pop();
        let (lo, hi) = pts.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let size = (hi - lo).max_element();
        let corners = if size <= super::latin1::DOT_SIZE as f64 {
            Vec::new()
        } else {
            corners_of(&pts, true)
        };
        match corners.first() {
            None => {
                return Some(Spine {
                    ctrl: fit_closed(&pts, tol),
                    corners: Vec::new(),
                    closed: true,
                });
            }
            Some(&c0) => {
                // Open from the first corner round to it.
                pts.rotate_left(c0);
                pts.push(pts[0]);
            }
        }
    }
    let corners = corners_of(&pts, false);
    let mut bounds = vec![0];
    bounds.extend(corners);
    bounds.push(pts.len() - 1);
    let mut ctrl: Vec<DVec2> = Vec::new();
    let mut joints = Vec::new();
    for w in bounds.windows(2) {
        let piece = fit_open(&pts[w[0]..=w[1]], tol);
        if !ctrl.is_empty() {
            joints.push(ctrl.len() - 1);
        }
        let skip = usize::from(!ctrl.is_empty());
        ctrl.extend(piece.into_iter().skip(skip));
    }
    Some(Spine {
        ctrl,
        corners: joints,
        closed: false,
    })
}

/// How many times a piece that comes back to its own end is halved at most.
const MAX_RETURN_SPLITS: usize = 4;

/// Split the pieces of an open spine that come back within 2r of one of their own ends
/// after running away from it by more than 4r (the script `o` and `O` close their loop
/// over their start): the end disk of such a piece would be covered by the piece's other
/// disks, which skinning cannot take (kruppa-2023 Def. 4.1 cond. 1). The piece is split
/// at its middle knot (at t = ½ when it has one span) by knot insertion (Boehm, P&T A5.1):
/// both halves are clamped uniform and the curve is unchanged, C² at the new joint.
pub fn split_returning(spine: &mut Spine, r: f64) {
    if spine.closed {
        return;
    }
    for _ in 0..MAX_RETURN_SPLITS {
        let mut done = true;
        for (a, b) in spine.pieces() {
            let ctrl = &spine.ctrl[a..=b];
            if ctrl.len() < SPINE_DEGREE + 1 {
                continue;
            }
            let Some(c) = open_curve(ctrl) else { continue };
            let s = sample(&c);
            let returns = |order: &mut dyn Iterator<Item = &DVec2>, end: DVec2| {
                let mut along = 0.0;
                let mut prev = end;
                for &q in order {
                    along += prev.distance(q);
                    prev = q;
                    if along > 4.0 * r && q.distance(end) < 2.0 * r {
                        return true;
                    }
                }
                false
            };
            let (first, last) = (s[0], s[s.len() - 1]);
            if !(returns(&mut s.iter(), first) || returns(&mut s.iter().rev(), last)) {
                continue;
            }
            let spans = ctrl.len() - SPINE_DEGREE;
            let t = if spans >= 2 {
                c.knots()[SPINE_DEGREE + spans / 2]
            } else {
                0.5
            };
            let Ok((l, rr)) = c.split(t) else { continue };
            let mut piece = l.ctrl().to_vec();
            let joint = a + piece.len() - 1;
            piece.extend_from_slice(&rr.ctrl()[1..]);
            let added = piece.len() - ctrl.len();
            spine.ctrl.splice(a..=b, piece);
            for k in spine.corners.iter_mut() {
                if *k >= b {
                    *k += added;
                }
            }
            spine.corners.push(joint);
            spine.corners.sort_unstable();
            done = false;
            break;
        }
        if done {
            return;
        }
    }
}
