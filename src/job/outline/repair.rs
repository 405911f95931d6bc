//! Every stroke gets an outline: where a stroke cannot be skinned as it is, it is split at
//! the failing place and its pieces are skinned again; a piece that still fails is built on
//! the union of its disks (issue 39, build item 1).
//!
//! **Splitting is exact.** A piece is the curve restricted to a parameter interval by knot
//! insertion (Boehm, P&T A5.1, [`BSpline::split`]), so the pieces' disks are the stroke's
//! disks, and two neighbouring pieces share the disk at the split: the round joint of a
//! corner (`design::corners`), without refitting anything. The stroke's region is the
//! union of its pieces' regions, so the outline is the boolean union of the pieces' regions
//! ([`Region::union_pairwise`], flattened within the tolerance): simple (the boundary of a union)
//! and holding every disk as each piece holds its own.
//!
//! **Where to split** ([`failing_place`]): at the middle circle of a triplet that violates
//! kruppa-2023 Def. 4.1 cond. 2 or 3 (the bend is there; splitting removes the triplet);
//! at a covered circle (cond. 1) when the circles covering it are its neighbours, otherwise
//! in the middle of the widest parameter gap between the circles the error names (a stroke
//! that comes back over itself: the split separates the covered part from the part
//! covering it); at the deepest disk where a skin cuts into its stroke
//! ([`crate::skin::coverage::uncovered`]) or, for a piece, where its skin runs outside the
//! piece's disks by more than the same limit (at the nearest disk; where that is an end of
//! the piece, the piece is built on its disks); in the middle of the piece for any other error
//! except an exhausted work budget, which is not retried (its cost is already spent). A
//! closed stroke is first opened at its seam (the same curve, clamped at both ends).
//!
//! **Last resort:** a piece that fails while shorter than [`MIN_PIECE_FRACTION`] of the
//! stroke, whose failing place is not inside it, or once the stroke has [`max_pieces`]
//! pieces, is the union of its disks ([`swept_disks`], within the tolerance).
//!
//! **Deviation:** the outline of a repaired stroke is measured against the stroke's disks
//! (sampled within the tolerance): how far a disk reaches outside it
//! ([`crate::skin::coverage::uncovered`]) and how far its boundary lies outside the disks
//! ([`crate::skin::coverage::excess`], boundary sampled every [`EXCESS_STEP`] tolerances);
//! the larger is [`SkinRepair::deviation`].

use crate::dbsc::flatten::flatten_disks;
use crate::dbsc::{DiskBSpline, LoopReport};
use crate::geom::{Circle, DVec2, Path};
use crate::skin::admissible::{Condition, SkinError};
use crate::skin::coverage::{Uncovered, excess, uncovered};
use crate::skin::dbsc_skin::{
    DbscSkin, DbscSkinError, DbscSkinOptions, SegmentReport, check_knot_circles,
    skin_dbsc_or_overlap,
};
use crate::spline::BSpline;
use crate::toolpath::ops::swept_disks;
use crate::toolpath::region::Region;
use glam::DVec3;

/// Shortest piece that is split again, as a fraction of the stroke's parameter domain: a
/// shorter piece that fails is built on the union of its disks (a place that keeps failing
/// however close the split comes reaches it after about 30 halvings).
pub const MIN_PIECE_FRACTION: f64 = 1e-9;

/// Pieces a stroke may be split into: four per knot span plus 16 (a handwriting stroke
/// fails at most at every knot circle, each split adds one piece), so the attempts grow
/// linearly with the stroke.
pub fn max_pieces(c: &DiskBSpline) -> usize {
    4 * c.breakpoints().len() + 16
}

/// Fraction of a piece's parameter span that a split must keep clear of its ends: a split
/// closer to an end would leave a piece of almost no length, which fails as its parent did.
const END_CLEARANCE: f64 = 1e-6;

/// Spacing of the boundary samples of the deviation, in tolerances: the outer part of
/// [`SkinRepair::deviation`] may miss the true largest distance by half of it.
const EXCESS_STEP: f64 = 4.0;

/// A split of a stroke into two pieces that share the disk there.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinSplit {
    /// Curve parameter of the split.
    pub t: f64,
    /// Centre of the shared disk.
    pub at: DVec2,
    /// Why the piece was split (the skinning error, or how deep its skin cut in).
    pub reason: String,
}

/// A piece of a stroke whose outline is the union of its disks.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinFallback {
    /// Parameter interval of the piece.
    pub t: [f64; 2],
    /// Centre of the piece's middle disk.
    pub at: DVec2,
    /// Why the piece could not be skinned.
    pub reason: String,
    /// Where its skin cut into it, when it had a skin that did.
    pub missed: Option<Uncovered>,
}

/// What was done to give a stroke an outline that it could not get as one skin.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinRepair {
    /// Splits, in parameter order.
    pub splits: Vec<SkinSplit>,
    /// Pieces built on the union of their disks, in parameter order.
    pub fallbacks: Vec<SkinFallback>,
    /// Worst deviation of the outline from the stroke's disks (see the module docs).
    pub deviation: f64,
    /// Where the deviation is largest.
    pub deviation_at: DVec2,
    /// Which control disks to change, and how, for the stroke to skin as one piece
    /// (the corner hint the design module writes for a stroke), when something stands out.
    pub hint: Option<String>,
}

/// The outline of a stroke from its pieces.
pub struct Repaired {
    /// Closed, non-intersecting contours of the union of the pieces' outlines.
    pub contours: Vec<Path>,
    /// The circles of the pieces' skins, in parameter order.
    pub circles: Vec<Circle>,
    /// The pieces' segment reports, in parameter order.
    pub segments: Vec<SegmentReport>,
    /// Whether a piece's skin overlapped itself.
    pub self_overlap: bool,
    /// What was done.
    pub repair: SkinRepair,
}

/// One piece: the curve on `range`.
struct Piece {
    curve: DiskBSpline,
    range: (f64, f64),
}

/// What became of a piece.
enum Done {
    Skinned(Box<DbscSkin>, bool),
    Fallback(SkinFallback, Region),
}

/// How a piece failed: where to split it (if anywhere) and why.
struct Failure {
    place: Option<f64>,
    reason: String,
    missed: Option<Uncovered>,
}

/// The skin of one piece as the job takes it: retried with
/// [`DbscSkinOptions::allow_global_overlap`] when its spine crosses itself (one run,
/// [`skin_dbsc_or_overlap`]); `loops`, when given, are `find_loops(c, opts.loop_tol)`.
pub fn skin_piece(
    c: &DiskBSpline,
    opts: &DbscSkinOptions,
    loops: Option<&LoopReport>,
) -> Result<(DbscSkin, bool), DbscSkinError> {
    skin_dbsc_or_overlap(c, opts, loops)
}

/// Contours of a skin as the job draws them: the union of its lobes when it overlaps itself.
pub fn skin_contours(sk: &DbscSkin, overlap: bool, tol: f64) -> Vec<Path> {
    if overlap {
        Region::from_overlapping_paths(&sk.outline, tol).paths()
    } else {
        sk.outline.clone()
    }
}

/// Where a skin's contours leave a disk of `c` outside by more than `limit`, measured on
/// disks and contours flattened within `tol`.
pub fn missed(c: &DiskBSpline, contours: &[Path], tol: f64, limit: f64) -> Option<Uncovered> {
    let disks = flatten_disks(c, tol);
    let polygons: Vec<Vec<DVec2>> = contours.iter().map(|p| p.flatten(tol)).collect();
    uncovered(&disks, &polygons).filter(|u| u.depth > limit)
}

/// The outline of a stroke that failed as one skin with `first` (see the module docs):
/// pieces skinned with `opts`, disks covered up to `limit`, flattened within `tol`.
pub fn repair(
    c: &DiskBSpline,
    first: Failure0,
    opts: &DbscSkinOptions,
    tol: f64,
    limit: f64,
) -> Repaired {
    let mut splits = Vec::new();
    let mut done: Vec<((f64, f64), Done)> = Vec::new();
    let budget = max_pieces(c);
    let mut pieces = 1usize;
    // The whole stroke's failure is known: split it (a closed stroke is opened first).
    let mut todo: Vec<(Piece, Option<Failure>)> = Vec::new();
    let whole = open_at_seam(c);
    let first = first.into_failure(c);
    let range = whole.domain();
    let opened = Piece {
        curve: whole,
        range,
    };
    let shortest = MIN_PIECE_FRACTION * (range.1 - range.0);
    let knots = c.breakpoints();
    if c.is_closed() {
        // The seam is a split of its own: the opened curve's ends are the same disk.
        let t = 0.5 * (range.0 + range.1);
        let place = first.place.filter(|&s| inside(s, range)).unwrap_or(t);
        let reason = format!("closed stroke opened at its seam; {}", first.reason);
        match split(&opened, place) {
            Some((a, b)) => {
                splits.push(split_record(c, range.0, &reason));
                splits.push(split_record(c, place, &reason));
                pieces += 2;
                todo.push((b, None));
                todo.push((a, None));
            }
            None => todo.push((opened, Some(first))),
        }
    } else {
        todo.push((opened, Some(first)));
    }
    while let Some((piece, known)) = todo.pop() {
        let failure = match known {
            Some(f) => f,
            None if turn_piece(&piece, range, &knots) => Failure {
                place: None,
                reason: TURN_REASON.to_string(),
                missed: None,
            },
            None => match attempt(&piece, opts, tol, limit) {
                Ok((sk, overlap)) => {
                    done.push((piece.range, Done::Skinned(Box::new(sk), overlap)));
                    continue;
                }
                Err(f) => f,
            },
        };
        let halves = (piece.range.1 - piece.range.0 >= shortest && pieces < budget)
            .then_some(failure.place)
            .flatten()
            .and_then(|t| split(&piece, t).map(|h| (t, h)));
        match halves {
            Some((t, (a, b))) => {
                splits.push(split_record(c, t, &failure.reason));
                pieces += 1;
                todo.push((b, None));
                todo.push((a, None));
            }
            None => {
                let circles: Vec<Circle> = flatten_disks(&piece.curve, tol)
                    .into_iter()
                    .map(|(_, d)| d)
                    .collect();
                let (lo, hi) = piece.range;
                let fb = SkinFallback {
                    t: [lo, hi],
                    at: piece.curve.center(0.5 * (lo + hi)),
                    reason: failure.reason,
                    missed: failure.missed,
                };
                done.push((piece.range, Done::Fallback(fb, swept_disks(&circles, tol))));
            }
        }
    }
    done.sort_by(|a, b| a.0.0.total_cmp(&b.0.0));
    splits.sort_by(|a, b| a.t.total_cmp(&b.t));
    let mut regions = Vec::new();
    let mut circles = Vec::new();
    let mut segments = Vec::new();
    let mut fallbacks = Vec::new();
    let mut self_overlap = false;
    for (_, d) in done {
        match d {
            Done::Skinned(sk, overlap) => {
                self_overlap |= overlap;
                regions.push(Region::from_overlapping_paths(&sk.outline, tol));
                circles.extend(sk.circles);
                segments.extend(sk.report);
            }
            Done::Fallback(fb, region) => {
                regions.push(region);
                fallbacks.push(fb);
            }
        }
    }
    // Each piece is a region of its own (a piece on its disks may have a hole that another
    // piece covers), so the outline is the boolean union of the regions.
    let contours = Region::union_pairwise(&regions, tol).paths();
    let (deviation, deviation_at) = deviation(c, &contours, tol);
    Repaired {
        contours,
        circles,
        segments,
        self_overlap,
        repair: SkinRepair {
            splits,
            fallbacks,
            deviation,
            deviation_at,
            hint: crate::design::corners::skin_hint(c),
        },
    }
}

/// Why the whole stroke failed, before the cascade: its skinning error, or where its
/// skin cut into it.
pub enum Failure0 {
    /// The skinning error.
    Error(DbscSkinError),
    /// The skin cut into the stroke.
    Missed(Uncovered),
}

impl Failure0 {
    fn into_failure(self, c: &DiskBSpline) -> Failure {
        match self {
            Failure0::Error(e) => Failure {
                place: failing_place(&e, c.domain()),
                reason: short_reason(&e),
                missed: None,
            },
            Failure0::Missed(u) => missed_failure(u, c.domain()),
        }
    }
}

fn missed_failure(u: Uncovered, range: (f64, f64)) -> Failure {
    Failure {
        place: Some(if inside(u.t, range) {
            u.t
        } else {
            0.5 * (range.0 + range.1)
        }),
        reason: format!(
            "the skin cut {:.3} into the stroke at t = {:.6} (no admissible circle follows the bend)",
            u.depth, u.t
        ),
        missed: Some(u),
    }
}

/// Why a [`turn_piece`] is built on its disks.
const TURN_REASON: &str = "one knot span between two splits (the tip of a turn)";

/// Whether a piece is one knot span of the stroke, [u_k, u_k+1] with both ends split
/// (neither is an end of the stroke's domain `whole`; `knots` are the stroke's
/// breakpoints): where consecutive knot circles fail one after another (a hatch's turn)
/// this is the tip of the turn, which a skin follows only by many one-sided insertions; it
/// is built on the union of its disks instead (within the tolerance of them).
fn turn_piece(p: &Piece, whole: (f64, f64), knots: &[f64]) -> bool {
    let (lo, hi) = p.range;
    let k = knots.partition_point(|&u| u < lo);
    lo > whole.0
        && hi < whole.1
        && knots.get(k) == Some(&lo)
        && knots.get(k + 1) == Some(&hi)
        && p.curve.breakpoints().len() == 2
}

/// Skin one piece and check that it holds its disks.
fn attempt(
    p: &Piece,
    opts: &DbscSkinOptions,
    tol: f64,
    limit: f64,
) -> Result<(DbscSkin, bool), Failure> {
    match check_knot_circles(&p.curve).and_then(|()| skin_piece(&p.curve, opts, None)) {
        Ok((sk, overlap)) => {
            let contours = skin_contours(&sk, overlap, tol);
            // The same disks and polygons as [`missed`] measures.
            let disks = flatten_disks(&p.curve, tol);
            let polygons: Vec<Vec<DVec2>> = contours.iter().map(|c| c.flatten(tol)).collect();
            if let Some(u) = uncovered(&disks, &polygons).filter(|u| u.depth > limit) {
                return Err(missed_failure(u, p.range));
            }
            // A piece's skin may also round a bend well outside its disks (where its
            // Hausdorff bound stays unmet): split it there too, at the nearest disk.
            let circles: Vec<Circle> = disks.iter().map(|&(_, d)| d).collect();
            let (out, at) = excess(&circles, &polygons, EXCESS_STEP * tol);
            if out <= limit {
                return Ok((sk, overlap));
            }
            let nearest = disks
                .iter()
                .map(|&(t, d)| (t, at.distance(d.c) - d.r))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(t, _)| t);
            Err(Failure {
                place: nearest.filter(|&t| inside(t, p.range)),
                reason: format!(
                    "the skin runs {out:.3} outside the stroke's disks near ({:.3}, {:.3})",
                    at.x, at.y
                ),
                missed: None,
            })
        }
        Err(e) => Err(Failure {
            place: failing_place(&e, p.range),
            reason: short_reason(&e),
            missed: None,
        }),
    }
}

/// The skinning error in a few words: the admissibility condition a triplet violates
/// (the circles and parameters are the split's), or the error itself.
fn short_reason(e: &DbscSkinError) -> String {
    match e {
        DbscSkinError::NotAdmissible { source, .. } => match source {
            SkinError::Inadmissible { condition, .. } => condition.to_string(),
            other => other.to_string(),
        },
        other => other.to_string(),
    }
}

/// Whether `t` lies inside `range`, clear of its ends by [`END_CLEARANCE`] of its length.
fn inside(t: f64, (lo, hi): (f64, f64)) -> bool {
    let m = END_CLEARANCE * (hi - lo);
    t > lo + m && t < hi - m
}

/// Where to split a piece on `range` that failed with `e` (see the module docs); `None`
/// for an exhausted work budget or when no place lies inside the piece.
fn failing_place(e: &DbscSkinError, range: (f64, f64)) -> Option<f64> {
    let middle = 0.5 * (range.0 + range.1);
    let place = match e {
        DbscSkinError::WorkBudget { .. } => return None,
        DbscSkinError::NotAdmissible { params, source, .. } => match source {
            SkinError::Inadmissible {
                condition: Condition::RadicalCentreInside | Condition::LensOutsideMiddle,
                ..
            } if params.len() == 3 => Some(params[1]),
            SkinError::Inadmissible {
                condition: Condition::Covered,
                ..
            } => covered_place(params, range),
            _ => widest_gap(params),
        },
        DbscSkinError::Hausdorff(crate::skin::hausdorff::HausdorffError::NoEnvelope { t }) => {
            Some(*t)
        }
        _ => None,
    };
    Some(place.filter(|&t| inside(t, range)).unwrap_or(middle)).filter(|&t| inside(t, range))
}

/// The split for a covered circle `params[0]` covered by the circles at `params[1..]`: at
/// the covered circle when the coverers are local (no gap between the named circles is
/// more than twice any other), else in the widest gap.
fn covered_place(params: &[f64], range: (f64, f64)) -> Option<f64> {
    let &covered = params.first()?;
    let mut s = params.to_vec();
    s.sort_by(f64::total_cmp);
    let mut gaps: Vec<f64> = s.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_by(f64::total_cmp);
    let local = gaps.len() >= 2 && gaps[gaps.len() - 1] <= 2.0 * gaps[gaps.len() - 2];
    if local && inside(covered, range) {
        Some(covered)
    } else {
        widest_gap(params)
    }
}

/// The middle of the widest gap between the sorted `params`.
fn widest_gap(params: &[f64]) -> Option<f64> {
    let mut s = params.to_vec();
    s.sort_by(f64::total_cmp);
    s.windows(2)
        .max_by(|a, b| (a[1] - a[0]).total_cmp(&(b[1] - b[0])))
        .map(|w| 0.5 * (w[0] + w[1]))
}

fn split_record(c: &DiskBSpline, t: f64, reason: &str) -> SkinSplit {
    SkinSplit {
        t,
        at: c.center(t),
        reason: reason.to_string(),
    }
}

/// The two pieces of `p` at `t` (exact, by knot insertion).
fn split(p: &Piece, t: f64) -> Option<(Piece, Piece)> {
    if !inside(t, p.range) {
        return None;
    }
    let (a, b) = p.curve.curve().split(t).ok()?;
    let piece = |c: BSpline<DVec3>, range| Piece {
        curve: DiskBSpline::from_curve(c),
        range,
    };
    Some((piece(a, (p.range.0, t)), piece(b, (t, p.range.1))))
}

/// The curve as an open one, clamped at both ends of its domain: the same curve (a closed
/// curve's stored knots and wrapped control values, read as an open unclamped curve, are
/// the same polynomial pieces on the domain; inserting each domain end p times clamps it,
/// P&T A5.1 as in [`BSpline::split`]). Open curves are returned as they are.
fn open_at_seam(c: &DiskBSpline) -> DiskBSpline {
    if !c.is_closed() {
        return c.clone();
    }
    let k = c.curve();
    let p = k.degree();
    let (lo, hi) = k.domain();
    let clamp = || -> Result<BSpline<DVec3>, crate::spline::SplineError> {
        let full = BSpline::new(p, k.knots().to_vec(), k.ctrl().to_vec())?
            .insert_knot(lo, p)?
            .insert_knot(hi, p)?;
        let knots = full.knots();
        let first = knots.iter().position(|&u| u == lo).unwrap_or(1).max(1);
        let first_hi = knots
            .iter()
            .position(|&u| u == hi)
            .unwrap_or(knots.len())
            .max(first);
        // After insertion lo and hi have multiplicity p: control value `first − 1` is C(lo)
        // and `first_hi − 1` is C(hi) (as in `BSpline::split`); one more copy of each end
        // clamps the knot vector.
        let mut kv = vec![lo];
        kv.extend_from_slice(knots.get(first..first_hi + p).unwrap_or_default());
        kv.push(hi);
        let ctrl = full.ctrl().get(first - 1..first_hi).unwrap_or_default();
        BSpline::new(p, kv, ctrl.to_vec())
    };
    clamp().map_or_else(|_| c.clone(), DiskBSpline::from_curve)
}

/// Worst deviation of `contours` from the disks of `c` (module docs) and where it is.
fn deviation(c: &DiskBSpline, contours: &[Path], tol: f64) -> (f64, DVec2) {
    let disks = flatten_disks(c, tol);
    let polygons: Vec<Vec<DVec2>> = contours.iter().map(|p| p.flatten(tol)).collect();
    let inner = uncovered(&disks, &polygons).map_or((0.0, DVec2::ZERO), |u| (u.depth, u.at));
    let circles: Vec<Circle> = disks.iter().map(|&(_, d)| d).collect();
    let outer = excess(&circles, &polygons, EXCESS_STEP * tol);
    if inner.0 >= outer.0 {
        (inner.0.max(0.0), inner.1)
    } else {
        outer
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Opening a closed curve at its seam keeps the curve: the same points over the domain.
    #[test]
    fn open_at_seam_is_the_same_curve() {
        let disks: Vec<Circle> = (0..7)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 7.0;
                Circle::new(
                    DVec2::new(10.0 * a.cos(), 6.0 * a.sin()),
                    1.0 + 0.2 * k as f64,
                )
            })
            .collect();
        for degree in [1, 2, 3] {
            let c = DiskBSpline::closed(degree, &disks, None).unwrap();
            let o = open_at_seam(&c);
            assert!(!o.is_closed());
            assert_eq!(o.domain(), c.domain());
            let (lo, hi) = c.domain();
            for i in 0..=200 {
                let t = lo + (hi - lo) * i as f64 / 200.0;
                let (a, b) = (c.circle_at(t), o.circle_at(t));
                assert!(
                    a.c.distance(b.c) < 1e-9 && (a.r - b.r).abs() < 1e-9,
                    "{degree} {t}"
                );
            }
            // Clamped: the first and last control disks are the curve's ends.
            let cd = o.control_disks();
            assert!(cd[0].c.distance(c.center(lo)) < 1e-9);
            assert!(cd[cd.len() - 1].c.distance(c.center(hi)) < 1e-9);
        }
    }

    /// A turn tip is exactly one knot span of the stroke with a split at both ends: not a
    /// piece at an end of the stroke, not a part of a span, not two spans.
    #[test]
    fn turn_pieces_are_inner_knot_spans() {
        // A zig-zag hatch: its turns fail kruppa-2023 Def. 4.1 at consecutive knots.
        let disks: Vec<Circle> = (0..9)
            .map(|k| Circle::new(DVec2::new(k as f64, 4.0 * (k % 2) as f64), 0.4))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let knots = c.breakpoints();
        let whole = c.domain();
        let stroke = Piece {
            curve: c.clone(),
            range: whole,
        };
        let (u1, u2, u3) = (knots[1], knots[2], knots[3]);
        let (_, rest) = split(&stroke, u1).unwrap();
        let (tip, rest) = split(&rest, u2).unwrap();
        assert_eq!(tip.range, (u1, u2));
        assert!(turn_piece(&tip, whole, &knots));
        // The first span reaches the stroke's start; the rest spans several knots.
        let (first, _) = split(&stroke, u1).unwrap();
        assert!(!turn_piece(&first, whole, &knots));
        assert!(!turn_piece(&rest, whole, &knots));
        // Part of a span, and a piece over two spans.
        let (part, _) = split(&tip, 0.5 * (u1 + u2)).unwrap();
        assert!(!turn_piece(&part, whole, &knots));
        let (two, _) = split(&split(&stroke, u1).unwrap().1, u3).unwrap();
        assert_eq!(two.range, (u1, u3));
        assert!(!turn_piece(&two, whole, &knots));
    }

    /// Split places: the middle of a bad triplet, a covered circle among neighbours, the
    /// widest gap when the coverers are far; nothing for a work budget or outside the piece.
    #[test]
    fn failing_places() {
        let tri = |condition, params: Vec<f64>| DbscSkinError::NotAdmissible {
            circles: vec![0, 1, 2],
            t0: params[0],
            t1: params[params.len() - 1],
            params,
            source: SkinError::Inadmissible {
                condition,
                circles: vec![0, 1, 2],
            },
        };
        let r = (0.0, 1.0);
        let e = tri(Condition::RadicalCentreInside, vec![0.2, 0.3, 0.4]);
        assert_eq!(failing_place(&e, r), Some(0.3));
        let e = tri(Condition::Covered, vec![0.5, 0.45, 0.55]);
        assert_eq!(failing_place(&e, r), Some(0.5));
        let e = tri(Condition::Covered, vec![0.9, 0.1, 0.12, 0.88, 0.92]);
        assert_eq!(failing_place(&e, r), Some(0.5));
        // The covered circle is the piece's end: the widest gap instead.
        let e = tri(Condition::Covered, vec![1.0, 0.0]);
        assert_eq!(failing_place(&e, r), Some(0.5));
        let w = DbscSkinError::WorkBudget {
            budget: 10,
            epsilon: 0.01,
        };
        assert_eq!(failing_place(&w, r), None);
        // A place at the piece's end falls back to its middle.
        let e = tri(Condition::RadicalCentreInside, vec![0.0, 0.0, 0.1]);
        assert_eq!(failing_place(&e, r), Some(0.5));
    }
}
