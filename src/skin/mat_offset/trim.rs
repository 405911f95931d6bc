//! Global trimming of outer MAT offsets.
//!
//! The region of an RE/MPH skin is the union U of its MAT disks ȳ(t) = (y(t), r(t))
//! (re-skinning-cnc Sec. 2: the skin is the envelope of the one-parameter family of circles,
//! closed by the end circles). Its outer δ-offset is the boundary of the union of the grown
//! disks (y, r + δ), and the distance of a point p outside U is exactly
//! d(p) = min_t (‖p − y(t)‖ − r(t)). Every point y + (r + δ) m± of the raw offset curve has
//! d ≤ δ, with equality where it lies on the boundary of the grown union; where distant parts
//! of the offset cross (a narrow gap or hole closing up at large δ, not only the local loops
//! where τ < 0) the curve runs inside the grown union and d < δ.
//!
//! So the offset is trimmed exactly: all crossings of the offset pieces are found (seeded on
//! a polyline of the pieces, refined by Newton's method on the exact curves), the pieces are
//! split there, the sub-pieces whose midpoint has d < δ are dropped, and the rest chain into
//! closed contours end to start. A part of the region that vanishes leaves no contour, and
//! a contour that pinches off splits into several.

use super::{LoopCut, MatOffset, MatOffsetError, OffsetContour, Piece};
use crate::geom::roots::{Golden, GoldenBracket, Tie};
use crate::geom::{Arc, DVec2};
use crate::skin::re::{Branch, ReSkin};

/// Samples per exact curve piece (and per quarter turn of an arc piece) for seeding the
/// crossing search: crossings of sub-pieces shorter than this spacing can be missed (the
/// local loop search of `outer_offset` catches the short loops where τ < 0).
const SEED_SAMPLES: usize = 96;
/// Geometrically refined seeds towards each end of a piece (down to 2^-END_SEEDS of the
/// first sample spacing).
const END_SEEDS: usize = 24;
/// Samples per segment for bracketing the minimum of ‖p − y(t)‖ − r(t).
const DIST_SAMPLES: usize = 48;
/// Newton iterations for a crossing o_a(s) = o_b(u).
const NEWTON_ITERS: usize = 40;
/// Golden-section iterations for the distance minimum: 0.618^80 ≈ 2e-17 of the bracket.
const GOLDEN_ITERS: usize = 80;
/// Relative (to the skin's size) tolerance for joining sub-pieces end to start and for
/// accepting a refined crossing.
const JOIN_REL: f64 = 1e-7;
/// Relative (to the skin's size) distance from a joint of two pieces within which a refined
/// crossing of those pieces is taken for the joint itself.
const NEAR_JOINT_REL: f64 = 1e-6;
/// Below this sine of the angle between the two pieces a crossing near their joint counts
/// as the (tangent) joint itself; a true crossing is transversal.
const TANGENT_SIN: f64 = 1e-3;
/// Relative tolerance of the keep test d(midpoint) ≥ δ: kept sub-pieces have d = δ up to
/// rounding (about 1e-15 of the size); the tiny loops next to a joint dip inside the grown
/// union only by the square of their size, so the test must be this tight.
const KEEP_REL: f64 = 1e-11;

/// Parameter steps (on [0, 1]) below this end the golden-section and Newton iterations: the
/// resolution of f64 near 1.
const PARAM_RESOLUTION: f64 = 1e-15;

/// Two roots closer than this in the parameter are one.
const SAME_PARAM: f64 = 1e-12;

/// A crossing within this parameter distance of a piece's end is at its joint; splits
/// closer than this are one.
const END_PARAM: f64 = 1e-9;

/// Signed distance from `p` to the region of `skin` (the union of its MAT disks, end circles
/// included), exact up to the root finding: min over the segments of
/// min_t (‖p − y(t)‖ − r(t)), bracketed on DIST_SAMPLES samples per segment and refined by
/// golden-section search. Negative inside. `None` if the skin has a singular point.
pub fn region_distance(skin: &ReSkin, p: DVec2) -> Option<f64> {
    let mut best = f64::INFINITY;
    for seg in &skin.segments {
        let g = |t: f64| -> Option<f64> {
            let fr = seg.curve.frame(t)?;
            Some(p.distance(fr.y) - fr.r)
        };
        let vals: Vec<f64> = (0..=DIST_SAMPLES)
            .map(|k| g(k as f64 / DIST_SAMPLES as f64))
            .collect::<Option<Vec<f64>>>()?;
        for k in 0..=DIST_SAMPLES {
            let left = if k > 0 { vals[k - 1] } else { f64::INFINITY };
            let right = if k < DIST_SAMPLES {
                vals[k + 1]
            } else {
                f64::INFINITY
            };
            if vals[k] > left || vals[k] > right {
                continue;
            }
            // A local minimum among the samples: refine in the neighbouring intervals.
            let h = 1.0 / DIST_SAMPLES as f64;
            let a = (k as f64 * h - h).max(0.0);
            let b = (k as f64 * h + h).min(1.0);
            // Stops once the bracket is narrower than PARAM_RESOLUTION (the bracket starts at
            // least h wide); (√5 − 1)/2 as evaluated in f64 is the ratio these results use.
            let golden = Golden::new(PARAM_RESOLUTION.next_down(), GOLDEN_ITERS, Tie::Right)
                .with_ratio(0.5 * (5f64.sqrt() - 1.0));
            let GoldenBracket { fc: gc, fd: gd, .. } =
                golden.min_with(|t| g(t).ok_or(()), a, b).ok()?;
            best = best.min(vals[k]).min(gc).min(gd);
        }
    }
    Some(best)
}

/// Point and derivative (with respect to the local parameter s ∈ [0, 1]) of a piece.
fn piece_pd(off: &MatOffset, p: &Piece, s: f64) -> Option<(DVec2, DVec2)> {
    match *p {
        Piece::Curve {
            segment,
            branch,
            t0,
            t1,
        } => off
            .curve_point(segment, branch, t0 + s * (t1 - t0))
            .map(|(q, d)| (q, d * (t1 - t0))),
        Piece::Arc(a) => Some((a.eval(s), a.tangent(s) * a.sweep.abs() * a.radius)),
    }
}

/// The part of `p` for local parameters s0..s1.
fn sub_piece(p: &Piece, s0: f64, s1: f64) -> Piece {
    match *p {
        Piece::Curve {
            segment,
            branch,
            t0,
            t1,
        } => Piece::Curve {
            segment,
            branch,
            t0: t0 + s0 * (t1 - t0),
            t1: t0 + s1 * (t1 - t0),
        },
        Piece::Arc(a) => Piece::Arc(Arc::new(
            a.center,
            a.radius,
            a.start + s0 * a.sweep,
            (s1 - s0) * a.sweep,
        )),
    }
}

/// Seed parameters s of a piece: uniform, plus the extra seeds (branch, global parameter
/// segment + t) that fall inside a curve piece.
fn seed_params(p: &Piece, extra: &[(Branch, f64)]) -> Vec<f64> {
    let n = match p {
        Piece::Curve { .. } => SEED_SAMPLES,
        Piece::Arc(a) => {
            let quarters = (a.sweep.abs() / std::f64::consts::FRAC_PI_2).ceil() as usize;
            (SEED_SAMPLES / 4 * quarters.max(1)).max(8)
        }
    };
    let mut v: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    // Geometric refinement towards both ends: a loop that crosses the neighbouring piece
    // just after their joint is seen by polyline segments that do not share the joint.
    for k in 1..=END_SEEDS {
        let e = 0.5f64.powi(k as i32) / n as f64;
        v.push(e);
        v.push(1.0 - e);
    }
    if let Piece::Curve {
        segment,
        branch,
        t0,
        t1,
    } = *p
    {
        for &(b, g) in extra {
            let t = g - segment as f64;
            if b == branch && (0.0..=1.0).contains(&t) && t1 != t0 {
                let s = (t - t0) / (t1 - t0);
                if s > 0.0 && s < 1.0 {
                    v.push(s);
                }
            }
        }
    }
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < SAME_PARAM);
    v
}

/// Parameters (u, v) ∈ [0, 1]² where segments p0p1 and q0q1 cross, if they do.
fn seg_cross(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> Option<(f64, f64)> {
    let r = p1 - p0;
    let s = q1 - q0;
    let den = crate::geom::cross(r, s);
    if den == 0.0 {
        return None;
    }
    let u = crate::geom::cross(q0 - p0, s) / den;
    let v = crate::geom::cross(q0 - p0, r) / den;
    ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some((u, v))
}

/// Newton's method on o_a(s) − o_b(u) = 0 from (s, u); the refined pair if it converges
/// to a point where the two pieces meet within `join`.
fn refine(
    off: &MatOffset,
    a: &Piece,
    b: &Piece,
    mut s: f64,
    mut u: f64,
    join: f64,
) -> Option<(f64, f64)> {
    for _ in 0..NEWTON_ITERS {
        let (pa, da) = piece_pd(off, a, s)?;
        let (pb, db) = piece_pd(off, b, u)?;
        let r = pa - pb;
        let det = crate::geom::cross(da, -db);
        if det == 0.0 || !det.is_finite() {
            break;
        }
        let ds = crate::geom::cross(-r, -db) / det;
        let du = crate::geom::cross(da, -r) / det;
        s = (s + ds).clamp(0.0, 1.0);
        u = (u + du).clamp(0.0, 1.0);
        if ds.abs().max(du.abs()) < PARAM_RESOLUTION {
            break;
        }
    }
    let (pa, _) = piece_pd(off, a, s)?;
    let (pb, _) = piece_pd(off, b, u)?;
    (pa.distance(pb) <= join).then_some((s, u))
}

/// Size of the skin: the largest coordinate magnitude plus radius, and δ.
fn scale(skin: &ReSkin, delta: f64) -> f64 {
    skin.circles
        .iter()
        .fold(1.0f64, |m, c| m.max(c.c.abs().max_element() + c.r))
        + delta.abs()
}

/// Removes the parts of the outer offset `off` (signed distance `off.d` > 0) that lie
/// closer than δ to the skin's region, splitting and re-chaining its contours (see the
/// module docs). `extra` are additional seed parameters (branch, segment + t) where short
/// loops are expected. The crossings of one side with itself are recorded in `off.loops`.
/// Returns the number of crossings found.
pub fn trim_outer(
    skin: &ReSkin,
    off: &mut MatOffset,
    extra: &[(Branch, f64)],
) -> Result<usize, MatOffsetError> {
    let delta = off.d;
    let sc = scale(skin, delta);
    let join = JOIN_REL * sc;
    // All pieces with their contour and their seed polylines.
    let pieces: Vec<Piece> = off
        .contours
        .iter()
        .flat_map(|c| c.pieces.iter().copied())
        .filter(|p| !matches!(p, Piece::Arc(a) if a.radius <= 0.0 || a.sweep == 0.0))
        .collect();
    let params: Vec<Vec<f64>> = pieces.iter().map(|p| seed_params(p, extra)).collect();
    let polys: Vec<Vec<DVec2>> = pieces
        .iter()
        .zip(&params)
        .map(|(p, ss)| {
            ss.iter()
                .map(|&s| off.piece_point(p, s))
                .collect::<Option<Vec<DVec2>>>()
        })
        .collect::<Option<Vec<_>>>()
        .ok_or(MatOffsetError::Singular {
            segment: 0,
            t: f64::NAN,
        })?;
    // Segment boxes for a sweep over x.
    struct Seg {
        piece: usize,
        k: usize,
        lo: DVec2,
        hi: DVec2,
    }
    let mut segs: Vec<Seg> = Vec::new();
    for (pi, poly) in polys.iter().enumerate() {
        for k in 0..poly.len().saturating_sub(1) {
            segs.push(Seg {
                piece: pi,
                k,
                lo: poly[k].min(poly[k + 1]),
                hi: poly[k].max(poly[k + 1]),
            });
        }
    }
    segs.sort_by(|a, b| a.lo.x.total_cmp(&b.lo.x));
    let mut splits: Vec<Vec<f64>> = vec![Vec::new(); pieces.len()];
    let mut crossings = 0;
    let mut loops = Vec::new();
    let near = NEAR_JOINT_REL * sc;
    for i in 0..segs.len() {
        for j in i + 1..segs.len() {
            let (a, b) = (&segs[i], &segs[j]);
            if b.lo.x > a.hi.x {
                break;
            }
            if b.lo.y > a.hi.y || a.lo.y > b.hi.y {
                continue;
            }
            if a.piece == b.piece && a.k.abs_diff(b.k) <= 1 {
                continue;
            }
            let (pa, pb) = (&polys[a.piece], &polys[b.piece]);
            let Some((u, v)) = seg_cross(pa[a.k], pa[a.k + 1], pb[b.k], pb[b.k + 1]) else {
                continue;
            };
            let (sa, sb) = (&params[a.piece], &params[b.piece]);
            let s0 = sa[a.k] + u * (sa[a.k + 1] - sa[a.k]);
            let u0 = sb[b.k] + v * (sb[b.k + 1] - sb[b.k]);
            let Some((s, t)) = refine(off, &pieces[a.piece], &pieces[b.piece], s0, u0, join) else {
                continue;
            };
            // Where consecutive pieces join end to start: not a crossing. The pieces are
            // tangent there, so Newton's method creeps towards the joint only linearly:
            // any point within NEAR_JOINT_REL of an end shared by both pieces is the joint.
            // Two comparisons, not a range test: a NaN parameter is at no end.
            #[allow(clippy::manual_range_contains)]
            let at_end = |x: f64| x < END_PARAM || x > 1.0 - END_PARAM;
            if at_end(s) && at_end(t) {
                continue;
            }
            let (Some((x, dx)), Some((_, dy))) = (
                piece_pd(off, &pieces[a.piece], s),
                piece_pd(off, &pieces[b.piece], t),
            ) else {
                continue;
            };
            let sin = crate::geom::cross(dx.normalize_or_zero(), dy.normalize_or_zero()).abs();
            let ends = |p: &Piece| [off.piece_point(p, 0.0), off.piece_point(p, 1.0)];
            let near_joint = ends(&pieces[a.piece]).iter().flatten().any(|&ea| {
                ea.distance(x) <= near
                    && ends(&pieces[b.piece])
                        .iter()
                        .flatten()
                        .any(|&eb| eb.distance(ea) <= join)
            });
            if near_joint && sin < TANGENT_SIN {
                continue;
            }
            if a.piece == b.piece && (s - t).abs() < END_PARAM {
                continue;
            }
            splits[a.piece].push(s);
            splits[b.piece].push(t);
            crossings += 1;
            if let (
                Piece::Curve {
                    segment: seg0,
                    branch: b0,
                    t0: a0,
                    t1: a1,
                },
                Piece::Curve {
                    segment: seg1,
                    branch: b1,
                    t0: c0,
                    t1: c1,
                },
            ) = (pieces[a.piece], pieces[b.piece])
                && b0 == b1
            {
                loops.push(LoopCut {
                    branch: b0,
                    seg0,
                    t0: a0 + s * (a1 - a0),
                    seg1,
                    t1: c0 + t * (c1 - c0),
                    point: off.piece_point(&pieces[a.piece], s).unwrap_or(DVec2::NAN),
                });
            }
        }
    }
    // Split, keep the sub-pieces at distance δ.
    let keep_tol = KEEP_REL * sc;
    let mut kept: Vec<(Piece, DVec2, DVec2)> = Vec::new();
    for (pi, p) in pieces.iter().enumerate() {
        let mut ss = splits[pi].clone();
        ss.push(0.0);
        ss.push(1.0);
        ss.sort_by(f64::total_cmp);
        ss.dedup_by(|x, y| (*x - *y).abs() < END_PARAM);
        for w in ss.windows(2) {
            let (s0, s1) = (w[0], w[1]);
            if s1 - s0 < END_PARAM {
                continue;
            }
            let q = sub_piece(p, s0, s1);
            let mid = off.piece_point(&q, 0.5).ok_or(MatOffsetError::Singular {
                segment: pi,
                t: 0.5,
            })?;
            let d = region_distance(skin, mid).ok_or(MatOffsetError::Singular {
                segment: pi,
                t: 0.5,
            })?;
            if d >= delta - keep_tol {
                let (Some(a), Some(b)) = (off.piece_point(&q, 0.0), off.piece_point(&q, 1.0))
                else {
                    continue;
                };
                kept.push((q, a, b));
            }
        }
    }
    // Chain end to start.
    let mut used = vec![false; kept.len()];
    let mut contours = Vec::new();
    for first in 0..kept.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let start = kept[first].1;
        let mut end = kept[first].2;
        let mut pieces = vec![kept[first].0];
        let mut guard = 0;
        while end.distance(start) > join {
            guard += 1;
            let next = (0..kept.len())
                .filter(|&k| !used[k])
                .min_by(|&x, &y| kept[x].1.distance(end).total_cmp(&kept[y].1.distance(end)));
            match next {
                Some(k) if kept[k].1.distance(end) <= join && guard <= kept.len() => {
                    used[k] = true;
                    pieces.push(kept[k].0);
                    end = kept[k].2;
                }
                _ => return Err(MatOffsetError::OpenContour { point: end }),
            }
        }
        contours.push(OffsetContour { pieces });
    }
    off.contours = contours;
    off.loops = loops;
    Ok(crossings)
}
