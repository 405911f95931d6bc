//! The RE/MPH outline of a circle sequence or a stroke: the skin (re-skinning-cnc Sec. 3,
//! re-mph-skinning-flexible Sec. 3) with its envelope intersections detected and eliminated
//! (mph Theorem 1, Sec. 4.2), its exact envelopes with end caps as MAT pieces
//! ([`crate::skin::mat_offset`]) flattened, and its δ-offsets. The job layer draws it and
//! supplies the polygon union that cuts local envelope loops off.

use crate::dbsc::{DiskBSpline, Side};
use crate::geom::{Circle, DVec2};
use crate::skin::dbsc_skin::{DbscSkinError, DbscSkinOptions, ReportBounds, skin_dbsc};
use crate::skin::mat_offset::{self, MatOffset, OffsetContour, Piece};
use crate::skin::re::detect::{EnvelopeIntersection, detect};
use crate::skin::re::eliminate::{EliminateOptions, PairFix, eliminate};
use crate::skin::re::{Branch, Interp, ReSkin, Touch};

/// Why an RE/MPH outline (or its offsets) could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReOutlineError {
    /// No touching points for the circle sequence (Kunkli–Hoffmann construction).
    #[error(transparent)]
    Touching(#[from] crate::skin::SkinError),
    /// The RE/MPH skin or the elimination of envelope intersections failed.
    #[error(transparent)]
    Skin(#[from] crate::skin::re::ReError),
    /// An exact MAT offset failed.
    #[error(transparent)]
    Offset(#[from] crate::skin::mat_offset::MatOffsetError),
    /// The stroke's DBSC skin (whose circles the RE route uses) failed.
    #[error(transparent)]
    Dbsc(#[from] DbscSkinError),
    /// A circle where the stroke's envelope is undefined and the sequence's touching
    /// points, the fallback, could not be built.
    #[error("circle {index}: {source}")]
    Fallback {
        /// Index of the circle.
        index: usize,
        /// Why the sequence's touching points failed.
        source: crate::skin::SkinError,
    },
    /// A circle without touching points in the fallback.
    #[error("circle {index}: no touching points")]
    NoTouchingPoints {
        /// Index of the circle.
        index: usize,
    },
}

/// Relative tolerance of the touching-point construction (scaled by the sequence's size).
const TOUCH_REL_TOL: f64 = 1e-12;
/// How far (relative to the sequence's size) a touching point may lie off its circle when
/// the RE skin checks its input: the touching points are constructed on the circles, so
/// only rounding separates them.
const TOUCH_ON_CIRCLE_REL: f64 = 1e-9;
/// Parameter accuracy of the Corollary 1 root finding and of the offset trim points.
const RE_PARAM_TOL: f64 = 1e-12;

/// An RE/MPH outline of a circle sequence, flattened, with what was found on the way.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct ReOutline {
    /// The skin after elimination.
    pub skin: ReSkin,
    /// Outline polylines (closed): open sequences one counter-clockwise contour with end
    /// caps; closed sequences the outer (counter-clockwise) and inner (clockwise) contour.
    pub contours: Vec<Vec<DVec2>>,
    /// Envelope intersections (Corollary 1) left after elimination.
    pub intersections: Vec<EnvelopeIntersection>,
    /// Pairs elimination could not fix: (i, j) circle indices.
    pub failed_pairs: Vec<(usize, usize)>,
    /// Local envelope loops (τ < 0, `mat_offset::envelope_loops`): branch and global
    /// parameter interval (segment index + t). When present, `contours` are the boundary
    /// of the non-zero-winding union of the flattened envelopes, which cuts the loops off;
    /// offsets near a loop are not exact offsets of the outline.
    pub loops: Vec<(Branch, f64, f64)>,
}

fn seq_scale(circles: &[Circle]) -> f64 {
    circles
        .iter()
        .fold(1.0f64, |m, c| m.max(c.c.abs().max_element() + c.r))
}

/// Fixed touching points of a circle sequence (Kunkli–Hoffmann, `skin::touching`).
pub fn sequence_touches(
    circles: &[Circle],
    closed: bool,
) -> Result<Vec<Touch>, crate::skin::SkinError> {
    let tp = crate::skin::touching_points(circles, closed, TOUCH_REL_TOL)?;
    Ok(tp
        .iter()
        .map(|t| Touch::Fixed {
            plus: t.left,
            minus: t.right,
        })
        .collect())
}

/// Builds the RE/MPH skin of `circles` with fixed touching points `touches` (re-skinning-cnc
/// Sec. 3.1, eqs. 7–12; for [`Interp::PhQuintic`] re-mph-skinning-flexible Sec. 3), detects
/// the envelope intersections (mph Theorem 1 / Corollary 1) and, when there are any, removes
/// those caused by roots of f (mph Sec. 4.2: quartic f of eqs. 18–19), then flattens the
/// envelopes with their end caps within `tol` ([`MatOffset::flatten`]). Where an envelope
/// runs backwards (a local loop, τ < 0) the flattened envelopes are handed to `union`, which
/// returns the boundary of their non-zero-winding union as closed polylines (the caller's
/// polygon union: this layer has none). The contours are oriented last ([`orient`]).
pub fn re_outline(
    circles: &[Circle],
    touches: &[Touch],
    closed: bool,
    interp: Interp,
    tol: f64,
    union: impl FnOnce(&[Vec<DVec2>]) -> Vec<Vec<DVec2>>,
) -> Result<ReOutline, ReOutlineError> {
    let scale = seq_scale(circles);
    let mut skin = ReSkin::build(
        circles,
        touches,
        closed,
        interp,
        TOUCH_ON_CIRCLE_REL * scale,
    )?;
    let mut intersections = detect(&skin, RE_PARAM_TOL);
    let mut failed_pairs = Vec::new();
    if !intersections.is_empty() {
        let fixes = eliminate(&mut skin, &EliminateOptions::default())?;
        failed_pairs = fixes
            .iter()
            .filter(|f| matches!(f.fix, PairFix::Failed { .. }))
            .map(|f| (f.i, f.j))
            .collect();
        intersections = detect(&skin, RE_PARAM_TOL);
    }
    // The library refuses f ≤ 0; then the raw envelopes are drawn anyway (and marked).
    let mat = match mat_offset::outline(&skin) {
        Ok(m) => m,
        Err(_) => raw_outline(&skin),
    };
    let mut contours = mat.flatten(tol);
    let loops = mat_offset::envelope_loops(&skin, RE_PARAM_TOL).unwrap_or_default();
    if !loops.is_empty() {
        contours = union(&contours);
    }
    Ok(ReOutline {
        skin,
        contours: orient(contours),
        intersections,
        failed_pairs,
        loops,
    })
}

/// The envelopes with caps as [`MatOffset`] pieces (offset 0) without the f > 0 check of
/// `mat_offset::outline`: plus side forwards, end cap, minus side backwards, start cap
/// (closed skins: the two sides).
fn raw_outline(skin: &ReSkin) -> MatOffset {
    let n = skin.segments.len();
    let side = |b: Branch, fwd: bool| crate::skin::mat_offset::whole_side(n, b, fwd);
    let mut contours = Vec::new();
    if skin.closed {
        contours.push(OffsetContour {
            pieces: side(Branch::Plus, true),
        });
        contours.push(OffsetContour {
            pieces: side(Branch::Minus, false),
        });
    } else if let (Some(first), Some(last)) = (skin.segments.first(), skin.segments.last()) {
        let env = |s: usize, b: Branch, t: f64| skin.envelope(s, b, t);
        let mut pieces = side(Branch::Plus, true);
        if let (Some(a), Some(b), Some(c)) = (
            env(n - 1, Branch::Plus, 1.0),
            env(n - 1, Branch::Minus, 1.0),
            skin.circles.get(last.j),
        ) {
            pieces.push(Piece::Arc(crate::geom::Arc::from_center_points(
                c.c, a, b, false,
            )));
        }
        pieces.extend(side(Branch::Minus, false));
        if let (Some(a), Some(b), Some(c)) = (
            env(0, Branch::Minus, 0.0),
            env(0, Branch::Plus, 0.0),
            skin.circles.get(first.i),
        ) {
            pieces.push(Piece::Arc(crate::geom::Arc::from_center_points(
                c.c, a, b, false,
            )));
        }
        contours.push(OffsetContour { pieces });
    }
    MatOffset {
        d: 0.0,
        curves: skin.segments.iter().map(|s| s.curve.clone()).collect(),
        contours,
        trims: Vec::new(),
        loops: Vec::new(),
    }
}

/// Orients closed contours: the one of largest |area| counter-clockwise, the others
/// clockwise (holes of a closed sequence or stroke).
pub fn orient(mut cs: Vec<Vec<DVec2>>) -> Vec<Vec<DVec2>> {
    let areas: Vec<f64> = cs
        .iter()
        .map(|c| crate::geom::path::polygon_area(c))
        .collect();
    let big = areas
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map(|(i, _)| i);
    for (i, c) in cs.iter_mut().enumerate() {
        let want_ccw = Some(i) == big;
        if (areas[i] > 0.0) != want_ccw {
            c.reverse();
        }
    }
    cs
}

/// Inner and outer δ-offsets of an RE/MPH skin (re-skinning-cnc eq. 13, trimmed where
/// r < δ; outer: y + (r + δ) m± with local loops cut), flattened within `tol`.
pub fn re_offsets(skin: &ReSkin, delta: f64, tol: f64) -> Result<Vec<Vec<DVec2>>, ReOutlineError> {
    let inner = mat_offset::inner_offset(skin, delta, RE_PARAM_TOL)?;
    let outer = mat_offset::outer_offset(skin, delta, tol)?;
    let mut out = inner.flatten(tol);
    out.extend(outer.flatten(tol));
    Ok(out)
}

/// Touching points of a stroke's circles: the exact envelope points (wu-2021 eq. 9) at the
/// circles' parameters; where the envelope is undefined, the Kunkli–Hoffmann points of the
/// circle sequence.
fn stroke_touches(
    c: &DiskBSpline,
    params: &[f64],
    circles: &[Circle],
    closed: bool,
) -> Result<Vec<Touch>, ReOutlineError> {
    let fallback = sequence_touches(circles, closed);
    let mut out = Vec::with_capacity(params.len());
    for (i, &t) in params.iter().enumerate() {
        let l = c.envelope(Side::Left, t).map(|e| e.point);
        let r = c.envelope(Side::Right, t).map(|e| e.point);
        let touch = match (l, r) {
            (Some(l), Some(r)) => {
                // Plus is the left of travel; swap if the sides disagree.
                let d = c.derivs(t, 1);
                let dq = d.get(1).map(|x| x.0).unwrap_or(DVec2::X);
                let q = c.center(t);
                if crate::geom::cross(dq, l - q) >= 0.0 {
                    Touch::Fixed { plus: l, minus: r }
                } else {
                    Touch::Fixed { plus: r, minus: l }
                }
            }
            _ => {
                let fb = match &fallback {
                    Ok(fb) => fb,
                    Err(e) => {
                        return Err(ReOutlineError::Fallback {
                            index: i,
                            source: e.clone(),
                        });
                    }
                };
                *fb.get(i)
                    .ok_or(ReOutlineError::NoTouchingPoints { index: i })?
            }
        };
        out.push(touch);
    }
    Ok(out)
}

/// Circles and touching points of a stroke for the RE route: the knot and inserted circles
/// of its DBSC skin approximation within `epsilon` (kruppa-2023 Sec. 4) and the envelope
/// points on them.
pub fn stroke_re_input(
    c: &DiskBSpline,
    epsilon: f64,
) -> Result<(Vec<Circle>, Vec<Touch>, bool), ReOutlineError> {
    let mut skin_opts = DbscSkinOptions {
        epsilon,
        // Only the circles are used.
        report: ReportBounds::Decided,
        ..DbscSkinOptions::default()
    };
    let sk = match skin_dbsc(c, &skin_opts) {
        Ok(sk) => sk,
        Err(DbscSkinError::SelfIntersection { .. }) => {
            skin_opts.allow_global_overlap = true;
            skin_dbsc(c, &skin_opts)?
        }
        Err(e) => return Err(e.into()),
    };
    let touches = stroke_touches(c, &sk.params, &sk.circles, sk.closed)?;
    Ok((sk.circles, touches, sk.closed))
}
