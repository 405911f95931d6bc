//! The MAT route of profiles and backboards (re-skinning-cnc-kruppa-2021 Sec. 4): the tool
//! path of an RE/MPH skin is its exact offset y + (r ± δ) m± (eq. 13) by the tool radius or
//! half the kerf, trimmed where r < δ (inner side), emitted as true arcs where the offset is
//! a circle arc (the end caps) and elsewhere as merged G1 arcs, each within the tolerance of
//! the exact offset curve by a bound on the whole curve
//! ([`MatOffset::to_merged_arc_paths`]).
//!
//! The general route ([`super::ops::profile`]) offsets a flattened or arc-fitted Bézier skin
//! with cavalier_contours; this one never offsets an approximation: each arc is fitted to
//! the exact offset curve, so the only error is the fitting tolerance.

use super::biarc::biarc;
use super::ops::ProfileSide;
use crate::geom::tol::DISTANCE_FLATTEN;
use crate::geom::{DVec2, Line, Path, PathSeg};
use crate::skin::mat_offset::{self, MatOffset, MatOffsetError};
use crate::skin::re::{Branch, ReSkin};

/// Parameter accuracy of the trim points (roots of r = δ) and loop crossings: far below any
/// machine resolution, and within what Bernstein subdivision reaches in f64.
pub const PARAM_TOL: f64 = 1e-12;

/// Interior samples at which a fitted biarc is compared with the exact offset curve: the
/// tolerance is verified there, not proved between them (the curves are smooth rational
/// curves and a piece is bisected until all samples pass, so the gap between samples is
/// small compared with the curvature radius).
const CHECK_SAMPLES: usize = 16;
/// Deepest bisection of a piece while fitting biarcs (2^24 pieces per segment at most).
const MAX_FIT_DEPTH: u32 = 24;

/// Counts of what a MAT route emitted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SegCounts {
    /// Number of arcs.
    pub arcs: usize,
    /// Number of lines.
    pub lines: usize,
}

impl SegCounts {
    /// Arcs and lines of `paths` (cubics are not emitted by either route).
    pub fn of(paths: &[Path]) -> SegCounts {
        let mut c = SegCounts::default();
        for p in paths {
            for s in &p.segs {
                match s {
                    PathSeg::Arc(_) => c.arcs += 1,
                    _ => c.lines += 1,
                }
            }
        }
        c
    }
}

/// Profile paths of an RE/MPH skin: the outline (`On`, or `tool_radius` = 0), its exact
/// outer offset (`Outside`) or its exact inner offset trimmed where r < δ (`Inside`), as
/// merged G1 arcs within `tol` (`arc_paths`) and oriented like [`super::ops::profile`]'s (material on the right:
/// outer contours clockwise, holes counter-clockwise).
pub fn mat_profile(
    skin: &ReSkin,
    side: ProfileSide,
    tool_radius: f64,
    tol: f64,
) -> Result<Vec<Path>, MatOffsetError> {
    let off = match side {
        _ if tool_radius <= 0.0 => mat_offset::outline(skin)?,
        ProfileSide::On => mat_offset::outline(skin)?,
        ProfileSide::Outside => mat_offset::outer_offset(skin, tool_radius, PARAM_TOL)?,
        ProfileSide::Inside => mat_offset::inner_offset(skin, tool_radius, PARAM_TOL)?,
    };
    Ok(orient_for_climb(arc_paths(&off, tol)?, tol))
}

/// The merged G1 arcs of `off` ([`MatOffset::to_merged_arc_paths`]), or the
/// bisected biarcs ([`biarc_paths`]) when some sample interval of the exact curve could not
/// be bounded (an inflection or a singular point the sampling does not resolve).
fn arc_paths(off: &MatOffset, tol: f64) -> Result<Vec<Path>, MatOffsetError> {
    let merged = off.to_merged_arc_paths(tol)?;
    Ok(if merged.unproved == 0 {
        merged.paths
    } else {
        biarc_paths(off, tol)?
    })
}

/// The backboard of a single skin: its exact outer offset by `distance` (margin plus tool
/// radius; with the inner corner radius equal to the tool radius the closing of the grown
/// outline changes nothing, since an offset by ρ is already open with respect to ρ-disks),
/// outer contours only (a backboard has no holes), oriented for climb milling.
pub fn mat_backboard(skin: &ReSkin, distance: f64, tol: f64) -> Result<Vec<Path>, MatOffsetError> {
    let off = mat_offset::outer_offset(skin, distance, PARAM_TOL)?;
    let paths = orient_for_climb(arc_paths(&off, tol)?, tol);
    let flat: Vec<Vec<DVec2>> = paths.iter().map(|p| p.flatten(tol)).collect();
    Ok(paths
        .into_iter()
        .enumerate()
        .filter(|(i, _)| nesting_depth(&flat, *i).is_multiple_of(2))
        .map(|(_, p)| p)
        .collect())
}

/// Number of the other polygons that contain the first point of polygon `i`.
fn nesting_depth(flat: &[Vec<DVec2>], i: usize) -> usize {
    let Some(&p) = flat[i].first() else { return 0 };
    flat.iter()
        .enumerate()
        .filter(|(k, poly)| *k != i && crate::geom::predicates::inside_even_odd(poly, p))
        .count()
}

/// Outer contours (even nesting depth) clockwise, holes counter-clockwise.
fn orient_for_climb(paths: Vec<Path>, tol: f64) -> Vec<Path> {
    let flat: Vec<Vec<DVec2>> = paths.iter().map(|p| p.flatten(tol)).collect();
    paths
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            let ccw = crate::geom::path::polygon_area(&flat[i]) > 0.0;
            let want_ccw = !nesting_depth(&flat, i).is_multiple_of(2);
            if ccw == want_ccw { p } else { p.reversed() }
        })
        .collect()
}

/// The contours of `off` as G1 chains of biarcs within `tol` of the exact offset curves
/// (each piece bisected in its parameter until CHECK_SAMPLES interior points of the exact
/// curve lie within `tol` of its biarc), with the cap arcs kept as they are. The profiles
/// and backboards of the MAT route use the fewer, hull-bounded arcs of
/// [`MatOffset::to_merged_arc_paths`]; this fit is kept for comparison (benches, tests).
/// `tol` must be positive and finite ([`MatOffsetError::BadTolerance`]).
pub fn biarc_paths(off: &MatOffset, tol: f64) -> Result<Vec<Path>, MatOffsetError> {
    crate::skin::mat_offset::check_tolerance(tol)?;
    Ok(off
        .fitted_contours(
            |a| a.radius > 0.0 && a.sweep != 0.0,
            |segment, branch, t0, t1, segs| {
                if t0 != t1 {
                    fit(off, segment, branch, t0, t1, tol, 0, segs);
                }
            },
        )
        .into_iter()
        .map(|mut segs| {
            crate::geom::path::close_line_gaps(&mut segs);
            Path::new(segs, true)
        })
        .filter(|p| !p.is_empty())
        .collect())
}

/// Point and unit tangent (in the direction of travel from t0 to t1) of the exact curve.
fn point_dir(
    off: &MatOffset,
    s: usize,
    b: Branch,
    t: f64,
    forward: bool,
) -> Option<(DVec2, DVec2)> {
    let (p, d) = off.curve_point(s, b, t)?;
    let d = if forward { d } else { -d };
    let len = d.length();
    (len > 0.0 && len.is_finite()).then(|| (p, d / len))
}

fn seg_distance(s: &PathSeg, p: DVec2) -> f64 {
    match s {
        PathSeg::Line(l) => l.distance(p),
        PathSeg::Arc(a) => a.distance(p),
        PathSeg::Cubic(c) => super::biarc::polyline_distance(&c.flatten(DISTANCE_FLATTEN), p),
    }
}

#[allow(clippy::too_many_arguments)]
fn fit(
    off: &MatOffset,
    s: usize,
    b: Branch,
    t0: f64,
    t1: f64,
    tol: f64,
    depth: u32,
    out: &mut Vec<PathSeg>,
) {
    let forward = t1 > t0;
    let (Some((p0, d0)), Some((p1, d1))) = (
        point_dir(off, s, b, t0, forward),
        point_dir(off, s, b, t1, forward),
    ) else {
        // A singular end (zero speed): a chord, bisected like any other piece.
        let (Some(a), Some(c)) = (off.curve_point(s, b, t0), off.curve_point(s, b, t1)) else {
            return;
        };
        out.push(PathSeg::Line(Line::new(a.0, c.0)));
        return;
    };
    let chain: Vec<PathSeg> = match biarc(p0, d0, p1, d1, tol * 0.01) {
        Some(pair) => pair.to_vec(),
        None => vec![PathSeg::Line(Line::new(p0, p1))],
    };
    let samples: Vec<DVec2> = (0..=CHECK_SAMPLES)
        .filter_map(|k| {
            let u = k as f64 / CHECK_SAMPLES as f64;
            off.curve_point(s, b, t0 + u * (t1 - t0)).map(|q| q.0)
        })
        .collect();
    let curve_to_chain = samples.iter().all(|&q| {
        chain
            .iter()
            .map(|c| seg_distance(c, q))
            .fold(f64::INFINITY, f64::min)
            <= tol
    });
    // The other direction against the samples' polyline (whose chords may sag by up to
    // another `tol` where the curve-to-chain test passed): no bulge of the biarc away
    // from the curve between the samples.
    let chain_to_curve = || {
        chain.iter().all(|c| {
            (1..4).all(|k| {
                super::biarc::polyline_distance(&samples, c.eval(k as f64 / 4.0)) <= 2.0 * tol
            })
        })
    };
    let ok = depth >= MAX_FIT_DEPTH || (curve_to_chain && chain_to_curve());
    if ok {
        out.extend(chain);
    } else {
        let m = 0.5 * (t0 + t1);
        fit(off, s, b, t0, m, tol, depth + 1, out);
        fit(off, s, b, m, t1, tol, depth + 1, out);
    }
}
