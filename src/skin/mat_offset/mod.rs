//! MAT offsets of RE/MPH skins (re-skinning-cnc eq. 13 and Sec. 4).
//!
//! The outline of a skin is the envelope y + r m± of its MAT ȳ = (y, r). Its inner
//! δ-offsets are x±δ(t) = y(t) + (r(t) − δ) m±(t) (eq. 13), and they are trimmed exactly
//! where r(t) < δ: at a root of r = δ both offsets meet in the MAT point y(t), so each
//! maximal parameter run with r > δ closes into one contour — no curve–curve intersection.
//! For RE curves r² = f² ‖x′‖² is a polynomial, so the trim points are polynomial roots.
//!
//! Outer offsets are y + (r + δ) m±; their local loops lie where τ = o′·y′ < 0
//! (kruppa-2023 Sec. 3 with r + δ in place of r) and are cut at the loop's self-crossing;
//! then every remaining crossing of the offset (global: parts of the skin that approach
//! each other, a hole closing up) is found on the exact curves and the parts closer than δ
//! to the skin are dropped (`trim`), so the contours split where a part vanishes.
//!
//! Inner offsets need no such trimming: a point y + (r − δ) m± lies in the disk ȳ(t), whose
//! δ-neighbourhood B(y + (r − δ) m±, δ) ⊂ ȳ(t) is inside the skin's region, and it is at
//! distance δ from the touching point y + r m±, which lies on the boundary wherever the
//! envelope is loop-free (`envelope_loops` empty). So every kept point is at distance
//! exactly δ from the outline.

use crate::geom::{Arc, DVec2};
use crate::skin::re::poly::{Positivity, prove_positive};
use crate::skin::re::{Branch, ReCurve, ReSkin};
use thiserror::Error;

/// Errors of MAT offsetting; each names the segment (circle pair) involved.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum MatOffsetError {
    /// The offset distance δ is not finite and positive.
    #[error("offset distance {0} must be finite and positive")]
    BadDelta(f64),
    /// The output tolerance is not finite and positive.
    #[error("tolerance {0} must be finite and positive")]
    BadTolerance(f64),
    /// f is not positive on a segment, so r = f‖x′‖ ≤ 0 somewhere: the envelopes cross and must be
    /// eliminated first (the elimination of the RE route).
    #[error("segment {segment}: f ≤ 0 at t = {t} (r ≤ 0: the envelopes cross; eliminate first)")]
    NonPositiveRadius {
        /// Index of the segment (circle pair) in the skin.
        segment: usize,
        /// Local parameter in [0, 1] where f ≤ 0 (the witness of the positivity proof).
        t: f64,
    },
    /// f > 0 on a segment could be neither proved nor refuted down to the proof's
    /// subdivision limit: f comes within rounding of 0, r = f‖x′‖ ≈ 0, the envelopes all but
    /// touch and the offset frame is ill-conditioned there.
    #[error(
        "segment {segment}: f > 0 not proved (f comes within rounding of 0: the envelopes \
         nearly touch)"
    )]
    UndecidedRadius {
        /// Index of the segment (circle pair) in the skin.
        segment: usize,
    },
    /// x′ = 0 or y′ = 0 at a parameter, so the frame (and m±) is undefined there.
    #[error("segment {segment}: singular point of x or y at t = {t}")]
    Singular {
        /// Index of the segment (circle pair) in the skin.
        segment: usize,
        /// Local parameter in [0, 1] of the singular point.
        t: f64,
    },
    /// The skin has no segments.
    #[error("the skin has no segments")]
    Empty,
    /// A segment's circle indices are out of range of the skin's circles.
    #[error("segment {segment} names a circle the skin does not have")]
    Inconsistent {
        /// Index of the inconsistent segment.
        segment: usize,
    },
    /// The trimmed pieces of an outer offset do not chain into closed contours.
    #[error(
        "the trimmed offset does not close at ({:.6}, {:.6}): a crossing was missed; \
         use a smaller tolerance or the general offset route",
        point.x, point.y
    )]
    OpenContour {
        /// The end of the chain where no next piece starts (model units).
        point: DVec2,
    },
}

mod arcs;
mod fit;
mod flatten;
#[cfg(test)]
mod global_tests;
mod trim;

pub use trim::region_distance;

/// A point where the inner offset is trimmed: r(t) = δ, x⁺δ(t) = x⁻δ(t) = y(t).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimPoint {
    /// Index of the segment (circle pair) where r = δ.
    pub segment: usize,
    /// Local parameter in [0, 1] on that segment, a root of r² − δ² = f²‖x′‖² − δ².
    pub t: f64,
    /// The MAT point y(t) where both offsets meet (model units).
    pub point: DVec2,
}

/// A self-crossing of one side of an outer offset where a loop (local, or global where
/// parts of the skin approach each other) was cut out: the offset crosses itself at
/// parameters `t0` (on segment `seg0`) and `t1` (on `seg1`), at `point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopCut {
    /// The side of the offset that crosses itself.
    pub branch: Branch,
    /// Index of the segment holding `t0`.
    pub seg0: usize,
    /// Local parameter in [0, 1] on `seg0`.
    pub t0: f64,
    /// Index of the segment holding `t1`.
    pub seg1: usize,
    /// Local parameter in [0, 1] on `seg1`.
    pub t1: f64,
    /// The crossing point (model units).
    pub point: DVec2,
}

/// One piece of an offset contour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    /// The exact curve y + (r + d) m± of `segment` traversed from `t0` to `t1` (t1 < t0
    /// for backwards traversal).
    Curve {
        /// Index of the segment (circle pair) in the skin.
        segment: usize,
        /// Which side, y + (r + d) m⁺ or y + (r + d) m⁻.
        branch: Branch,
        /// Local parameter in [0, 1] where the piece starts.
        t0: f64,
        /// Local parameter in [0, 1] where the piece ends.
        t1: f64,
    },
    /// An offset cap arc of an end circle.
    Arc(Arc),
}

/// Every segment of one side (`branch`) of an `n`-segment skin as whole curve pieces, in
/// parameter order (`forwards`) or reversed.
pub(crate) fn whole_side(n: usize, branch: Branch, forwards: bool) -> Vec<Piece> {
    let mut v: Vec<Piece> = (0..n)
        .map(|segment| Piece::Curve {
            segment,
            branch,
            t0: if forwards { 0.0 } else { 1.0 },
            t1: if forwards { 1.0 } else { 0.0 },
        })
        .collect();
    if !forwards {
        v.reverse();
    }
    v
}

/// A closed offset contour.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OffsetContour {
    /// Pieces in order, each starting where the previous one ends; the last ends where the first
    /// starts.
    pub pieces: Vec<Piece>,
}

/// The offset of a skin at signed distance `d` (−δ inner, +δ outer) with its exact pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct MatOffset {
    /// Signed offset distance (model units): −δ inner, +δ outer, 0 for the outline itself
    /// ([`outline`]).
    pub d: f64,
    /// The RE curves of the skin's segments, indexed by [`Piece::Curve`]'s `segment`
    /// (shared with the skin, not copied).
    pub curves: Vec<std::sync::Arc<ReCurve>>,
    /// The closed contours of the offset. Inner offsets and the outline run the `Plus` side
    /// forwards and the `Minus` side backwards per parameter run; trimmed outer offsets follow the
    /// re-chained pieces.
    pub contours: Vec<OffsetContour>,
    /// Where the inner offset was trimmed (r = δ), in segment order; empty for outer offsets.
    pub trims: Vec<TrimPoint>,
    /// Self-crossings cut out of an outer offset; empty for inner offsets.
    pub loops: Vec<LoopCut>,
}

/// Global parameter intervals (segment index + t) where the outline's own envelope runs
/// backwards (τ = x±′·y′ < 0, a local loop of the skin), ends to `tol`. There the RE curve
/// is not a true MAT and [`inner_offset`] near the loop is not the offset of the outline:
/// callers should refine the circles (re-skinning-cnc Sec. 4) or use the general route.
/// Kept separate from [`inner_offset`] because it costs more than the offset itself.
pub fn envelope_loops(skin: &ReSkin, tol: f64) -> Result<Vec<(Branch, f64, f64)>, MatOffsetError> {
    check_f(skin)?;
    let mut out = Vec::new();
    for b in [Branch::Plus, Branch::Minus] {
        for (lo, hi) in negative_tau_intervals(skin, b, 0.0, tol)? {
            out.push((b, lo, hi));
        }
    }
    Ok(out)
}

fn check_delta(delta: f64) -> Result<(), MatOffsetError> {
    if delta.is_finite() && delta > 0.0 {
        Ok(())
    } else {
        Err(MatOffsetError::BadDelta(delta))
    }
}

/// Ok when `tol` is a tolerance the fits of an offset can meet: positive and finite (at 0
/// or NaN they would bisect every piece to their depth limit).
pub(crate) fn check_tolerance(tol: f64) -> Result<(), MatOffsetError> {
    if tol.is_finite() && tol > 0.0 {
        Ok(())
    } else {
        Err(MatOffsetError::BadTolerance(tol))
    }
}

/// Subdivision depth of the f > 0 proof before offsetting.
const F_PROOF_DEPTH: u32 = 30;

/// The skin's RE curves for a [`MatOffset`]: shared, not copied.
fn shared_curves(skin: &ReSkin) -> Vec<std::sync::Arc<ReCurve>> {
    skin.segments
        .iter()
        .map(|s| std::sync::Arc::clone(&s.curve))
        .collect()
}

fn check_f(skin: &ReSkin) -> Result<(), MatOffsetError> {
    if skin.segments.is_empty() {
        return Err(MatOffsetError::Empty);
    }
    for (segment, seg) in skin.segments.iter().enumerate() {
        if seg.i >= skin.circles.len() || seg.j >= skin.circles.len() {
            return Err(MatOffsetError::Inconsistent { segment });
        }
        match prove_positive(&seg.curve.f, F_PROOF_DEPTH) {
            Positivity::Proven { .. } => {}
            Positivity::Fails { t, .. } => {
                return Err(MatOffsetError::NonPositiveRadius { segment, t });
            }
            Positivity::Undecided => return Err(MatOffsetError::UndecidedRadius { segment }),
        }
    }
    Ok(())
}

/// A parameter run on consecutive segments: (segment, t0, t1) with t1 > t0.
type Run = Vec<(usize, f64, f64)>;

/// Splits the kept intervals (segment, t0, t1), in segment order, of a skin of `n`
/// segments into maximal runs, joining across segment ends (and across the closing join
/// of a closed skin).
fn runs(kept: &[(usize, f64, f64)], n: usize, closed: bool) -> Vec<Run> {
    let mut out: Vec<Run> = Vec::new();
    let mut cur: Run = Vec::new();
    for &(s, a, b) in kept {
        let joins = cur
            .last()
            .is_some_and(|&(ps, _, pb)| ps + 1 == s && pb == 1.0 && a == 0.0);
        if !joins && !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
        cur.push((s, a, b));
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    if closed && out.len() > 1 {
        let first_starts = out
            .first()
            .and_then(|r| r.first())
            .is_some_and(|&(s, a, _)| s == 0 && a == 0.0);
        let last_ends = out
            .last()
            .and_then(|r| r.last())
            .is_some_and(|&(s, _, b)| s + 1 == n && b == 1.0);
        if first_starts && last_ends {
            let first = out.remove(0);
            if let Some(last) = out.last_mut() {
                last.extend(first);
            }
        }
    }
    out
}

fn cap(center: DVec2, from: DVec2, to: DVec2) -> Piece {
    Piece::Arc(Arc::from_center_points(center, from, to, false))
}

/// Builds the contours of runs: each run is its `Plus` offset forward, the end cap when it
/// reaches the end of an open skin, its `Minus` offset backwards, the start cap.
fn contours_of_runs(
    skin: &ReSkin,
    d: f64,
    side_runs: &[Run],
    full_loop: bool,
) -> Result<Vec<OffsetContour>, MatOffsetError> {
    let nseg = skin.segments.len();
    let point = |s: usize, b: Branch, t: f64| -> Result<DVec2, MatOffsetError> {
        let fr = skin.segments[s]
            .curve
            .frame(t)
            .ok_or(MatOffsetError::Singular { segment: s, t })?;
        Ok(fr.offset(b, d).0)
    };
    let mut out = Vec::new();
    if full_loop {
        // Closed skin without trims: the two sides are separate loops.
        for (b, fwd) in [(Branch::Plus, true), (Branch::Minus, false)] {
            out.push(OffsetContour {
                pieces: whole_side(nseg, b, fwd),
            });
        }
        return Ok(out);
    }
    for run in side_runs {
        let mut pieces = Vec::new();
        for &(segment, t0, t1) in run {
            pieces.push(Piece::Curve {
                segment,
                branch: Branch::Plus,
                t0,
                t1,
            });
        }
        let (Some(&(ls, _, lb)), Some(&(fs, fa, _))) = (run.last(), run.first()) else {
            continue;
        };
        if !skin.closed && ls + 1 == nseg && lb == 1.0 {
            let c = skin.circles[skin.segments[ls].j];
            pieces.push(cap(
                c.c,
                point(ls, Branch::Plus, 1.0)?,
                point(ls, Branch::Minus, 1.0)?,
            ));
        }
        for &(segment, t0, t1) in run.iter().rev() {
            pieces.push(Piece::Curve {
                segment,
                branch: Branch::Minus,
                t0: t1,
                t1: t0,
            });
        }
        if !skin.closed && fs == 0 && fa == 0.0 {
            let c = skin.circles[skin.segments[0].i];
            pieces.push(cap(
                c.c,
                point(0, Branch::Minus, 0.0)?,
                point(0, Branch::Plus, 0.0)?,
            ));
        }
        out.push(OffsetContour { pieces });
    }
    Ok(out)
}

/// Inner δ-offset of an RE/MPH skin (re-skinning-cnc eq. 13): x±δ = y + (r − δ) m±,
/// trimmed exactly at the roots of r(t) = δ (found as roots of the polynomial
/// f²‖x′‖² − δ² in [0, 1] by Bernstein subdivision to parameter accuracy `tol`). The cap
/// arcs of an open skin are offset to radius r − δ (and vanish with their circle when
/// r ≤ δ). Requires f > 0 (no envelope crossing; see `re::eliminate`).
pub fn inner_offset(skin: &ReSkin, delta: f64, tol: f64) -> Result<MatOffset, MatOffsetError> {
    check_delta(delta)?;
    check_f(skin)?;
    let mut trims = Vec::new();
    let nseg = skin.segments.len();
    let mut kept: Vec<(usize, f64, f64)> = Vec::with_capacity(nseg);
    let mut cuts: Vec<f64> = Vec::new();
    for (s, seg) in skin.segments.iter().enumerate() {
        // r² − δ²: only the constant term changes.
        let mut p = seg.curve.r_sq();
        match p.c.first_mut() {
            Some(c0) => *c0 -= delta * delta,
            None => p.c.push(-delta * delta),
        }
        let roots = p.roots_01(tol, 0.0);
        cuts.clear();
        cuts.push(0.0);
        for &t in &roots {
            if t > 0.0 && t < 1.0 {
                let fr = seg
                    .curve
                    .frame(t)
                    .ok_or(MatOffsetError::Singular { segment: s, t })?;
                trims.push(TrimPoint {
                    segment: s,
                    t,
                    point: fr.y,
                });
                cuts.push(t);
            }
        }
        cuts.push(1.0);
        for w in cuts.windows(2) {
            let m = 0.5 * (w[0] + w[1]);
            if w[1] > w[0] && p.eval(m) > 0.0 {
                kept.push((s, w[0], w[1]));
            }
        }
    }
    // Every segment kept whole: one interval (s, 0, 1) each.
    let all_kept = kept.len() == nseg && kept.iter().all(|&(_, a, b)| (a, b) == (0.0, 1.0));
    let rs = runs(&kept, nseg, skin.closed);
    let contours = contours_of_runs(skin, -delta, &rs, skin.closed && all_kept)?;
    Ok(MatOffset {
        d: -delta,
        curves: shared_curves(skin),
        contours,
        trims,
        loops: Vec::new(),
    })
}

/// The outline itself (the envelopes with their end caps, offset distance 0) as a
/// [`MatOffset`], so it can be evaluated and output like an offset.
pub fn outline(skin: &ReSkin) -> Result<MatOffset, MatOffsetError> {
    check_f(skin)?;
    let nseg = skin.segments.len();
    let kept: Vec<(usize, f64, f64)> = (0..nseg).map(|s| (s, 0.0, 1.0)).collect();
    let rs = runs(&kept, nseg, skin.closed);
    let contours = contours_of_runs(skin, 0.0, &rs, skin.closed)?;
    Ok(MatOffset {
        d: 0.0,
        curves: shared_curves(skin),
        contours,
        trims: Vec::new(),
        loops: Vec::new(),
    })
}

/// Samples per segment for bracketing the roots of τ (then refined by bisection); a loop
/// narrower than 1/TAU_SAMPLES of a segment's parameter range can be missed.
const TAU_SAMPLES: usize = 128;
/// Seed points per backwards-running interval of an outer offset (see `trim`).
const LOOP_SEEDS: usize = 8;

/// Outer δ-offset: y + (r + δ) m± on both sides with end caps of radius r + δ, and the
/// local loops removed: τ = o′·y′ (o the offset) is bracketed on a grid and its roots
/// refined to `tol`; each τ < 0 interval is cut out at the offset's self-crossing around
/// it (seeded on a polyline, refined by Newton on o(a) = o(b) to `tol`). Then the global
/// crossings are removed and the contours re-chained (module `trim`): the result is the
/// boundary of the union of the grown disks (y, r + δ) at every δ, holes that close up
/// vanish and contours that pinch off split. Envelope loops of the skin itself do not
/// matter here (the region is the union of the disks).
pub fn outer_offset(skin: &ReSkin, delta: f64, tol: f64) -> Result<MatOffset, MatOffsetError> {
    check_delta(delta)?;
    check_f(skin)?;
    let nseg = skin.segments.len();
    // Extra seed parameters for the crossing search: the cusps (roots of τ) and interior
    // points of every backwards-running interval, so that a local loop's two arms are
    // separate polyline segments however short the loop is.
    let mut seeds: Vec<(Branch, f64)> = Vec::new();
    let mut side_kept: Vec<Vec<Vec<(f64, f64)>>> = Vec::new();
    for b in [Branch::Plus, Branch::Minus] {
        for (lo, hi) in negative_tau_intervals(skin, b, delta, tol)? {
            for k in 0..=LOOP_SEEDS {
                seeds.push((b, lo + (hi - lo) * k as f64 / LOOP_SEEDS as f64));
            }
        }
        side_kept.push(vec![vec![(0.0, 1.0)]; nseg]);
    }
    // Contours: plus side runs forward, cap, minus side backwards, cap.
    let point = |s: usize, b: Branch, t: f64| -> Result<DVec2, MatOffsetError> {
        let fr = skin.segments[s]
            .curve
            .frame(t)
            .ok_or(MatOffsetError::Singular { segment: s, t })?;
        Ok(fr.offset(b, delta).0)
    };
    let side_pieces = |kept: &Vec<Vec<(f64, f64)>>, b: Branch, fwd: bool| -> Vec<Piece> {
        let mut v: Vec<Piece> = Vec::new();
        for (segment, iv) in kept.iter().enumerate() {
            for &(t0, t1) in iv {
                v.push(Piece::Curve {
                    segment,
                    branch: b,
                    t0,
                    t1,
                });
            }
        }
        if !fwd {
            v.reverse();
            for p in v.iter_mut() {
                if let Piece::Curve { t0, t1, .. } = p {
                    std::mem::swap(t0, t1);
                }
            }
        }
        v
    };
    let plus = side_pieces(&side_kept[0], Branch::Plus, true);
    let minus = side_pieces(&side_kept[1], Branch::Minus, false);
    let contours = if skin.closed {
        vec![
            OffsetContour { pieces: plus },
            OffsetContour { pieces: minus },
        ]
    } else {
        let last = nseg - 1;
        let ce = skin.circles[skin.segments[last].j];
        let cs = skin.circles[skin.segments[0].i];
        let mut pieces = plus;
        pieces.push(cap(
            ce.c,
            point(last, Branch::Plus, 1.0)?,
            point(last, Branch::Minus, 1.0)?,
        ));
        pieces.extend(minus);
        pieces.push(cap(
            cs.c,
            point(0, Branch::Minus, 0.0)?,
            point(0, Branch::Plus, 0.0)?,
        ));
        vec![OffsetContour { pieces }]
    };
    let mut off = MatOffset {
        d: delta,
        curves: shared_curves(skin),
        contours,
        trims: Vec::new(),
        loops: Vec::new(),
    };
    trim::trim_outer(skin, &mut off, &seeds)?;
    Ok(off)
}

fn from_gparam(g: f64, nseg: usize) -> (usize, f64) {
    let s = (g.floor().max(0.0) as usize).min(nseg - 1);
    (s, (g - s as f64).clamp(0.0, 1.0))
}

fn tau(skin: &ReSkin, b: Branch, d: f64, g: f64) -> Option<f64> {
    let (s, t) = from_gparam(g, skin.segments.len());
    let fr = skin.segments[s].curve.frame(t)?;
    Some(fr.offset(b, d).1.dot(fr.y1))
}

/// Global parameter intervals where τ < 0, ends refined by bisection to `tol`.
fn negative_tau_intervals(
    skin: &ReSkin,
    b: Branch,
    d: f64,
    tol: f64,
) -> Result<Vec<(f64, f64)>, MatOffsetError> {
    let nseg = skin.segments.len();
    let n = nseg * TAU_SAMPLES;
    let g_of = |i: usize| i as f64 / TAU_SAMPLES as f64;
    let val = |g: f64| -> Result<f64, MatOffsetError> {
        let (s, t) = from_gparam(g, nseg);
        tau(skin, b, d, g).ok_or(MatOffsetError::Singular { segment: s, t })
    };
    let refine = |mut lo: f64, mut hi: f64, neg_at_lo: bool| -> Result<f64, MatOffsetError> {
        while hi - lo > tol {
            let m = 0.5 * (lo + hi);
            if (val(m)? < 0.0) == neg_at_lo {
                lo = m;
            } else {
                hi = m;
            }
        }
        Ok(0.5 * (lo + hi))
    };
    let mut out = Vec::new();
    let mut start: Option<f64> = None;
    let mut prev = val(0.0)?;
    if prev < 0.0 {
        start = Some(0.0);
    }
    for i in 1..=n {
        let g = g_of(i);
        let v = val(g)?;
        if prev >= 0.0 && v < 0.0 {
            start = Some(refine(g_of(i - 1), g, false)?);
        } else if prev < 0.0 && v >= 0.0 {
            let end = refine(g_of(i - 1), g, true)?;
            out.push((start.take().unwrap_or(0.0), end));
        }
        prev = v;
    }
    if let Some(s) = start {
        out.push((s, nseg as f64));
    }
    Ok(out)
}

impl MatOffset {
    /// Point and derivative (w.r.t. the curve's own parameter t) of an exact piece.
    pub fn curve_point(&self, segment: usize, branch: Branch, t: f64) -> Option<(DVec2, DVec2)> {
        self.curves.get(segment)?.offset_at(branch, self.d, t)
    }

    /// Point of piece `p` at local s ∈ [0, 1].
    pub fn piece_point(&self, p: &Piece, s: f64) -> Option<DVec2> {
        match *p {
            Piece::Curve {
                segment,
                branch,
                t0,
                t1,
            } => self
                .curve_point(segment, branch, t0 + s * (t1 - t0))
                .map(|q| q.0),
            Piece::Arc(a) => Some(a.eval(s)),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geom::Circle;
    use crate::geom::Line;
    use crate::skin::re::skin::tests::{test_touches, transform};
    use crate::skin::re::{Interp, Touch};

    /// Five circles along a gentle wave (the shared fixture of the MAT offset tests).
    pub(crate) fn gentle() -> Vec<Circle> {
        vec![
            Circle::new(DVec2::new(0.0, 0.0), 1.2),
            Circle::new(DVec2::new(3.0, 0.6), 0.7),
            Circle::new(DVec2::new(6.0, 0.4), 1.4),
            Circle::new(DVec2::new(9.0, -0.5), 0.5),
            Circle::new(DVec2::new(11.5, -0.4), 0.9),
        ]
    }

    fn skin_of(cs: &[Circle], interp: Interp) -> ReSkin {
        let touches: Vec<Touch> = test_touches(cs, &[]);
        ReSkin::build(cs, &touches, false, interp, 1e-9).unwrap()
    }

    /// Dense envelope samples (both branches and the caps): the outline.
    fn outline_samples(skin: &ReSkin) -> Vec<DVec2> {
        let mut v = Vec::new();
        for seg in &skin.segments {
            for b in [Branch::Plus, Branch::Minus] {
                for i in 0..=4000 {
                    v.push(seg.curve.envelope(b, i as f64 / 4000.0).unwrap());
                }
            }
        }
        // Cap arcs only (the rest of the end circles is inside the outline).
        let last = skin.segments.len() - 1;
        let e = |s: usize, b, t| skin.segments[s].curve.envelope(b, t).unwrap();
        let caps = [
            Arc::from_center_points(
                skin.circles[0].c,
                e(0, Branch::Minus, 0.0),
                e(0, Branch::Plus, 0.0),
                false,
            ),
            Arc::from_center_points(
                skin.circles[skin.segments[last].j].c,
                e(last, Branch::Plus, 1.0),
                e(last, Branch::Minus, 1.0),
                false,
            ),
        ];
        for a in caps {
            for i in 0..=2000 {
                v.push(a.eval(i as f64 / 2000.0));
            }
        }
        v
    }

    fn no_envelope_loops(skin: &ReSkin) -> bool {
        skin.segments.iter().all(|s| {
            (0..=200).all(|i| {
                let fr = s.curve.frame(i as f64 / 200.0).unwrap();
                [Branch::Plus, Branch::Minus]
                    .iter()
                    .all(|&b| fr.offset(b, 0.0).1.dot(fr.y1) > 0.0)
            })
        })
    }

    /// Nearest distance from p to the outline sample set.
    fn dist(pts: &[DVec2], p: DVec2) -> f64 {
        pts.iter()
            .map(|q| q.distance(p))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn inner_offset_is_trimmed_at_r_eq_delta_and_at_distance_delta() {
        for (rot, scale, rev) in [(0.0, 1.0, false), (1.1, 2.5, true)] {
            for interp in [Interp::Cubic, Interp::PhQuintic] {
                let cs = transform(&gentle(), rot, scale, DVec2::new(-2.0, 7.0), rev);
                let skin = skin_of(&cs, interp);
                assert!(no_envelope_loops(&skin), "test precondition");
                let delta = 0.6 * scale; // larger than the 0.5 and smaller than the others
                let off = inner_offset(&skin, delta, 1e-12).unwrap();
                assert!(envelope_loops(&skin, 1e-10).unwrap().is_empty());
                assert!(!off.trims.is_empty());
                for tp in &off.trims {
                    let fr = skin.segments[tp.segment].curve.frame(tp.t).unwrap();
                    assert!(
                        (fr.r - delta).abs() < 1e-9 * scale,
                        "r = {} vs δ = {delta}",
                        fr.r
                    );
                    let (a, b) = (
                        fr.offset(Branch::Plus, -delta).0,
                        fr.offset(Branch::Minus, -delta).0,
                    );
                    assert!((a - b).length() < 1e-8 * scale);
                }
                assert_eq!(off.contours.len(), off.trims.len() / 2 + 1);
                // Distance to the outline: δ within the sampling error of the outline.
                let pts = outline_samples(&skin);
                let sample_err = 2e-3 * scale;
                for c in &off.contours {
                    for p in &c.pieces {
                        for k in 0..=50 {
                            let q = off.piece_point(p, k as f64 / 50.0).unwrap();
                            let dd = dist(&pts, q);
                            assert!(
                                dd > delta - 1e-9 * scale && dd < delta + sample_err,
                                "{dd} vs {delta} at {p:?} k={k} {interp:?} {rot}"
                            );
                        }
                    }
                }
                // Paths: closed, within tolerance of the exact pieces.
                let mut all = off.to_cubic_paths(1e-4 * scale).unwrap();
                all.extend(off.to_arc_paths(1e-4 * scale).unwrap());
                all.extend(off.to_line_paths(1e-4 * scale).unwrap());
                let nc = off.contours.len();
                for (q, path) in all.iter().enumerate() {
                    let c = &off.contours[q % nc];
                    assert!(path.max_gap() < 1e-8 * scale, "gap {}", path.max_gap());
                    // The closed polyline with its closing edge (flatten does not repeat
                    // the first point).
                    let mut flat = path.flatten(1e-5 * scale);
                    flat.extend(flat.first().copied());
                    for p in &c.pieces {
                        for k in 0..=20 {
                            let q = off.piece_point(p, k as f64 / 20.0).unwrap();
                            let dd = flat
                                .windows(2)
                                .map(|w| Line::new(w[0], w[1]).distance(q))
                                .fold(f64::INFINITY, f64::min);
                            assert!(dd < 1.1e-4 * scale, "{dd}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn real_touching_points_give_intersection_free_outline() {
        // Touching points from the Kunkli–Hoffmann construction (skin::touching), outline
        // checked by the independent curve–curve checker (skin::intersect).
        for (rot, scale, rev) in [(0.0, 1.0, false), (2.2, 4.0, true)] {
            let cs = transform(&gentle(), rot, scale, DVec2::new(3.0, 1.0), rev);
            let tps = crate::skin::touching::touching_points(&cs, false, 1e-9).unwrap();
            let touches: Vec<Touch> = tps
                .iter()
                .map(|t| Touch::Fixed {
                    plus: t.left,
                    minus: t.right,
                })
                .collect();
            for interp in [Interp::Cubic, Interp::PhQuintic] {
                let skin = ReSkin::build(&cs, &touches, false, interp, 1e-9 * scale).unwrap();
                for (i, tp) in tps.iter().enumerate() {
                    let s = i.min(skin.segments.len() - 1);
                    let t = if i == skin.segments.len() { 1.0 } else { 0.0 };
                    let fr = skin.segments[s].curve.frame(t).unwrap();
                    assert!((fr.offset(Branch::Plus, 0.0).0 - tp.left).length() < 1e-9 * scale);
                    assert!((fr.offset(Branch::Minus, 0.0).0 - tp.right).length() < 1e-9 * scale);
                }
                assert!(envelope_loops(&skin, 1e-10).unwrap().is_empty());
                let path = &outline(&skin)
                    .unwrap()
                    .to_cubic_paths(1e-6 * scale)
                    .unwrap()[0];
                let hits = crate::geom::intersect::path_self_intersections(path, 1e-9 * scale);
                assert!(hits.is_empty(), "{interp:?}: {hits:?}");
                let off = inner_offset(&skin, 0.6 * scale, 1e-12).unwrap();
                for p in off.to_cubic_paths(1e-6 * scale).unwrap() {
                    assert!(
                        crate::geom::intersect::path_self_intersections(&p, 1e-9 * scale)
                            .is_empty()
                    );
                }
            }
        }
    }

    #[test]
    fn envelope_loops_are_reported() {
        // The snake's right envelope runs backwards at the start of segment 2 (τ⁻ < 0).
        let cs = crate::skin::re::skin::tests::snake();
        let skin = skin_of(&cs, Interp::Cubic);
        let loops = envelope_loops(&skin, 1e-10).unwrap();
        assert!(!loops.is_empty());
        for &(b, lo, hi) in &loops {
            assert!(hi > lo);
            let g = 0.5 * (lo + hi);
            let (s, t) = (g.floor() as usize, g - g.floor());
            let fr = skin.segments[s].curve.frame(t).unwrap();
            assert!(fr.offset(b, 0.0).1.dot(fr.y1) < 0.0);
        }
    }

    #[test]
    fn small_delta_keeps_one_contour_and_caps() {
        let skin = skin_of(&gentle(), Interp::Cubic);
        let off = inner_offset(&skin, 0.1, 1e-12).unwrap();
        assert!(off.trims.is_empty());
        assert_eq!(off.contours.len(), 1);
        let arcs = off.contours[0]
            .pieces
            .iter()
            .filter(|p| matches!(p, Piece::Arc(_)))
            .count();
        assert_eq!(arcs, 2);
        for p in &off.contours[0].pieces {
            if let Piece::Arc(a) = p {
                assert!(a.radius > 0.0 && a.sweep < 0.0);
            }
        }
        let path = &off.to_line_paths(1e-4).unwrap()[0];
        assert!(path.max_gap() < 1e-9);
        assert!(matches!(
            inner_offset(&skin, -1.0, 1e-9),
            Err(MatOffsetError::BadDelta(_))
        ));
    }

    #[test]
    fn closed_ring_offsets() {
        // A ring of circles travelled counter-clockwise; left = inside of the ring.
        let cs: Vec<Circle> = (0..8)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 8.0;
                Circle::new(
                    6.0 * DVec2::new(a.cos(), a.sin()),
                    1.0 + 0.3 * (k % 2) as f64,
                )
            })
            .collect();
        let touches: Vec<Touch> = cs
            .iter()
            .map(|c| {
                let n = c.c.normalize();
                Touch::Fixed {
                    plus: c.c - c.r * n,
                    minus: c.c + c.r * n,
                }
            })
            .collect();
        let skin = ReSkin::build(&cs, &touches, true, Interp::Cubic, 1e-9).unwrap();
        // δ below every radius: two loops, no trims.
        let off = inner_offset(&skin, 0.5, 1e-12).unwrap();
        assert!(off.trims.is_empty());
        assert_eq!(off.contours.len(), 2);
        // δ between the radii 1.0 and 1.3: the ring is cut at every thin circle.
        let off = inner_offset(&skin, 1.1, 1e-12).unwrap();
        assert_eq!(off.trims.len(), 8);
        assert_eq!(off.contours.len(), 4);
        for (path, c) in off.to_line_paths(1e-5).unwrap().iter().zip(&off.contours) {
            assert!(path.max_gap() < 1e-8, "gap {}", path.max_gap());
            assert!(c.pieces.iter().all(|p| matches!(p, Piece::Curve { .. })));
        }
        for tp in &off.trims {
            let fr = skin.segments[tp.segment].curve.frame(tp.t).unwrap();
            assert!((fr.r - 1.1).abs() < 1e-9);
        }
        let ol = outline(&skin).unwrap();
        assert_eq!(ol.contours.len(), 2);
    }

    #[test]
    fn outline_is_closed_and_touches_circles() {
        let skin = skin_of(&gentle(), Interp::PhQuintic);
        let ol = outline(&skin).unwrap();
        assert_eq!(ol.contours.len(), 1);
        let path = &ol.to_cubic_paths(1e-6).unwrap()[0];
        assert!(path.max_gap() < 1e-9);
        // Clockwise (left skin forward, end cap, right skin back, start cap).
        assert!(crate::geom::path::polygon_area(&path.flatten(1e-4)) < 0.0);
        for (i, c) in skin.circles.iter().enumerate() {
            let w = skin.touches[i].plus();
            let d = path
                .flatten(1e-6)
                .iter()
                .map(|p| p.distance(w))
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1e-3, "circle {i}: {d}");
            assert!(c.signed_distance(w).abs() < 1e-12);
        }
    }

    #[test]
    fn outer_offset_is_at_distance_delta_and_loops_are_cut() {
        let cs = gentle();
        let skin = skin_of(&cs, Interp::Cubic);
        let pts = outline_samples(&skin);
        for delta in [0.2, 1.5] {
            let off = outer_offset(&skin, delta, 1e-12).unwrap();
            assert_eq!(off.contours.len(), 1);
            for lc in &off.loops {
                // The crossing is a true self-crossing of the offset curve.
                let a = off.curve_point(lc.seg0, lc.branch, lc.t0).unwrap().0;
                let b = off.curve_point(lc.seg1, lc.branch, lc.t1).unwrap().0;
                assert!((a - b).length() < 1e-8, "{a} {b}");
            }
            // Every kept point is at distance ≥ δ from the outline (no gouge) and ≈ δ.
            for p in &off.contours[0].pieces {
                for k in 0..=40 {
                    let q = off.piece_point(p, k as f64 / 40.0).unwrap();
                    let dd = dist(&pts, q);
                    assert!(dd > delta - 1e-6 && dd < delta + 2e-3, "δ={delta}: {dd}");
                }
            }
            let path = &off.to_cubic_paths(1e-4).unwrap()[0];
            assert!(path.max_gap() < 1e-7, "gap {}", path.max_gap());
        }
        // Large δ on this bent outline must produce loops on the concave side.
        let off = outer_offset(&skin, 1.5, 1e-12).unwrap();
        assert!(!off.loops.is_empty());
    }
}
