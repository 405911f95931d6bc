//! Approximation of a disk B-spline curve by skinning curves (kruppa-2023 Sec. 4).
//!
//! * Initialisation (eq. 19): the knot circles ⟨q(u); r(u)⟩ at the distinct knots of the
//!   domain; they must form an admissible sequence (Def. 4.1), otherwise the span is named
//!   in [`DbscSkinError::NotAdmissible`] (the limitation of Fig. 13).
//! * Error (eqs. 20–21): per segment and side the Hausdorff distance between the skin arc
//!   and the envelope arc on the same knot span, with guaranteed bounds
//!   ([`super::hausdorff`]); a side meets ε when the upper bound is ≤ ε.
//! * Phase 1 (eqs. 22–25): for a segment missing ε, insert u* = (1 − w_i) u_i + w_i u_{i+1}
//!   only if the sequence with u* and its symmetric pair u** = w_{i+1} u_{i+1} +
//!   (1 − w_{i+1}) u_{i+2} is admissible; otherwise halve both weights, down to
//!   [`DbscSkinOptions::min_weight`]. When that fails right after an insertion into the
//!   previous segment, push that insertion back towards its own segment start (halving its
//!   weight) and try again ([`DbscSkinOptions::push_back`], the paragraph after eq. 25;
//!   off by default); otherwise mark the segment STOPPED. Segments within ε are FINISHED.
//!   Repeat until every segment is FINISHED or STOPPED. Push-back changes none of the
//!   examples' skins and saves few circles on random sharp strokes.
//! * Phase 2: the same with plain midpoint insertion u* and no pair check.
//! * Phase 3 (Sec. 4.3): where both sides miss ε, insert c* at the midpoint when the radical
//!   centre of (c_i, c*, c_{i+1}) lies inside c*, on the side whose touching point on c* is
//!   not covered by c_i ∪ c_{i+1} only (circle marks LEFT/RIGHT; the others BOTH). The left
//!   skin skins the LEFT and BOTH circles, the right skin the RIGHT and BOTH circles. An
//!   insertion is kept only if the resulting outline stays free of self-intersections.

use super::hausdorff::{HausdorffBounds, HausdorffError, Work};
use super::{AdmissibilityOptions, SkinError, check_admissible};
use crate::dbsc::{DiskBSpline, EnvelopeLoop, LoopError, LoopReport, Side, SpanPoly, find_loops};
use crate::geom::{Circle, CubicBez, Path};
use std::cell::RefCell;

mod bounds;
mod state;

use bounds::{KeyMap, Mode};
use state::{Mark, State, crossed, first_crossing};

/// Options of [`skin_dbsc`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct DbscSkinOptions {
    /// ε of kruppa-2023 Sec. 4.2: the largest Hausdorff distance (eqs. 20–21) allowed between
    /// a skin arc and its envelope arc (model units). Named as in
    /// [`BuildOptions::epsilon`](crate::BuildOptions::epsilon).
    #[doc(alias = "eps")]
    pub epsilon: f64,
    /// Hausdorff bounds are refined to a gap of `gap_fraction · ε`.
    pub gap_fraction: f64,
    /// Parameter tolerance of loop detection (kruppa-2023 Sec. 3).
    pub loop_tol: f64,
    /// Phase 1 stops halving the weights of eq. 25 below this value ("too close").
    pub min_weight: f64,
    /// Phase 1 may push the previous insertion back towards its segment start when the
    /// next insertion is not admissible otherwise (kruppa-2023 Sec. 4.2, the paragraph after
    /// eq. 25). Off by default: it saves few circles and changes no example, but the sequence
    /// it leaves can be one that phase 3 cannot skin.
    pub push_back: bool,
    /// Upper limit of circles, a guard against runaway refinement.
    pub max_circles: usize,
    /// Budget of Hausdorff refinement steps (branch-and-bound nodes) for the whole skinning
    /// of one stroke. Running out is [`DbscSkinError::WorkBudget`], never a hang.
    pub max_work: usize,
    /// Run phase 3 (two-sided skinning).
    pub two_sided: bool,
    /// Tolerance of the self-intersection test of the outline (model units).
    pub intersect_tol: f64,
    /// How tight the error bounds of the final report are ([`ReportBounds`]).
    pub report: ReportBounds,
    /// Return the outline even when it crosses itself. A stroke whose spine crosses itself
    /// (a G-clef, a loop drawn on purpose) overlaps itself globally: no skin of it can be
    /// free of crossings, and the caller resolves the overlap (for example by a union of
    /// the region). Local envelope loops are still avoided.
    pub allow_global_overlap: bool,
}

impl Default for DbscSkinOptions {
    fn default() -> Self {
        DbscSkinOptions {
            epsilon: crate::geom::tol::SKIN_EPSILON,
            gap_fraction: 0.1,
            loop_tol: DEFAULT_LOOP_TOL,
            // 1/64: c* within 1.6 % of the span end, i.e. almost a repeated knot circle.
            min_weight: 1.0 / 64.0,
            push_back: false,
            max_circles: 20_000,
            max_work: DEFAULT_MAX_WORK,
            two_sided: true,
            intersect_tol: DEFAULT_INTERSECT_TOL,
            report: ReportBounds::Tight,
            allow_global_overlap: false,
        }
    }
}

/// The error bounds [`skin_dbsc`] reports per segment ([`DbscSkin::report`]). Both are
/// certified (lower ≤ D_H ≤ upper, kruppa-2023 eqs. 20–21), `met` is upper ≤ ε in both, and
/// the skin is the same; the `met` flags can differ only for sides whose distance lies
/// within the gap of ε.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReportBounds {
    /// Refined until upper − lower ≤ `gap_fraction · ε`: one more Hausdorff bound per
    /// segment side after refinement (about 40 % of the bound work on a 10-disk stroke).
    Tight,
    /// The bounds that decided each side against ε during refinement (cached, so at most
    /// the sides changed by the last insertions cost anything): the upper bound is ≤ ε on
    /// met sides, the lower bound may be 0; failing sides get the quick rejection's upper
    /// bound (the matching bound of both directions). For callers that use the skin, not
    /// the numbers (toolpaths, the circles of the RE route).
    Decided,
}

/// Default of [`DbscSkinOptions::loop_tol`]: the parameter tolerance of envelope-loop
/// detection (kruppa-2023 Sec. 3), in units of the curve's parameter.
pub const DEFAULT_LOOP_TOL: f64 = 1e-10;

/// Default of [`DbscSkinOptions::intersect_tol`]: the distance (model units) within which
/// two outline curves count as intersecting ([`crate::geom::path_self_intersections`]).
pub const DEFAULT_INTERSECT_TOL: f64 = 1e-9;

/// Default of [`DbscSkinOptions::max_work`]: one million refinement steps. The examples'
/// strokes need at most about 11 000 at ε = 0.01 mm (loop.toml; the G-clef 8 800; measured
/// by the test `examples_stay_well_inside_the_work_budget`), since most bounds are settled
/// by the matching-bound search of the Hausdorff bounds before any point-distance search.
pub const DEFAULT_MAX_WORK: usize = 1_000_000;

/// Phase of kruppa-2023 Sec. 4 that ended refinement of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Phase {
    /// Phase 1: paired insertion with weights (eqs. 22–25). [`skin_dbsc`] reopens the segments
    /// phase 1 stops for phase 2, so its reports do not name this phase.
    One,
    /// Phase 2: plain midpoint insertion.
    Two,
    /// Phase 3: two-sided skinning (Sec. 4.3).
    Three,
}

/// Which skins use a circle (kruppa-2023 Sec. 4.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum CircleUse {
    /// On both skins (BOTH): every knot circle and every circle of phases 1–2.
    Both,
    /// On the left skin only (LEFT): inserted in phase 3 for the left side.
    Left,
    /// On the right skin only (RIGHT): inserted in phase 3 for the right side.
    Right,
}

impl CircleUse {
    fn on(self, side: Side) -> bool {
        matches!(
            (self, side),
            (CircleUse::Both, _) | (CircleUse::Left, Side::Left) | (CircleUse::Right, Side::Right)
        )
    }
}

/// Report of one segment [t0, t1] between consecutive circles.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SegmentReport {
    /// DBSC parameter of the circle starting the segment.
    pub t0: f64,
    /// DBSC parameter of the next circle (the domain end for the last segment of a closed stroke).
    pub t1: f64,
    /// Hausdorff bounds (eqs. 20–21) between the left skin arc that covers this segment and the
    /// left envelope over that arc's parameter span. With two-sided skins one arc may cover several
    /// segments, which then share its bounds.
    pub error_left: HausdorffBounds,
    /// Hausdorff bounds of the right skin against the right envelope, as
    /// [`SegmentReport::error_left`].
    pub error_right: HausdorffBounds,
    /// Whether the left side meets ε: `error_left.upper ≤ ε`.
    pub met_left: bool,
    /// Whether the right side meets ε: `error_right.upper ≤ ε`.
    pub met_right: bool,
    /// The phase in which insertion into this segment became impossible while ε was still
    /// missed (`None` when ε is met on both sides).
    pub stopped_in: Option<Phase>,
    /// Envelope loops overlapping the segment.
    pub loops: Vec<EnvelopeLoop>,
}

/// Result of [`skin_dbsc`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct DbscSkin {
    /// Whether the DBSC is closed: the circle sequence is cyclic and the last segment ends at the
    /// domain end.
    pub closed: bool,
    /// Parameters of the circles used, increasing.
    pub params: Vec<f64>,
    /// The circles at `params`: ⟨q(u); r(u)⟩ (kruppa-2023 eq. 19 for the knot circles), one per
    /// parameter.
    pub circles: Vec<Circle>,
    /// Which skins use each circle, one entry per circle.
    pub uses: Vec<CircleUse>,
    /// Left skin: one arc per consecutive pair of LEFT/BOTH circles.
    pub left: Vec<CubicBez>,
    /// Parameters of the circles of the left skin (LEFT and BOTH), increasing: arc k spans
    /// `left_params[k]` to `left_params[k + 1]` (to the domain end for the last arc of a closed
    /// stroke).
    pub left_params: Vec<f64>,
    /// Right skin: one arc per consecutive pair of RIGHT/BOTH circles.
    pub right: Vec<CubicBez>,
    /// Parameters of the circles of the right skin (RIGHT and BOTH), as [`DbscSkin::left_params`].
    pub right_params: Vec<f64>,
    /// The outline contours (skin outline assembly): open strokes one counter-clockwise
    /// contour with end caps, closed strokes the outer and the inner contour.
    pub outline: Vec<Path>,
    /// One report per segment between consecutive circles of `params`, in order.
    pub report: Vec<SegmentReport>,
    /// Hausdorff refinement steps spent (out of [`DbscSkinOptions::max_work`]).
    pub work: usize,
}

/// Errors of [`skin_dbsc`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DbscSkinError {
    /// The knot circles (eq. 19) are not an admissible sequence (Def. 4.1), so the stroke cannot be
    /// skinned as it is (kruppa-2023 Fig. 13).
    #[error(
        "knot circles at t = {params:?} (circles {circles:?}, spans [{t0}, {t1}]) are not admissible: {source}"
    )]
    NotAdmissible {
        /// Indices of the knot circles named by the admissibility error.
        circles: Vec<usize>,
        /// DBSC parameters of those circles.
        params: Vec<f64>,
        /// Start of the parameter range of the named circles.
        t0: f64,
        /// End of the parameter range of the named circles (the domain end when the last circle
        /// of a closed stroke is among them).
        t1: f64,
        /// The admissibility error of the knot circle sequence.
        source: SkinError,
    },
    /// The final outline crosses itself (and [`DbscSkinOptions::allow_global_overlap`] is off).
    #[error("skin outline contour {contour} {} at its segment {segment}", crossed(*contour, *other))]
    SelfIntersection {
        /// Index of the contour in the outline.
        contour: usize,
        /// Index of the contour it crosses: `contour` itself, or the other contour of a
        /// closed stroke (outer and inner).
        other: usize,
        /// Index of the first segment of `contour` involved in the crossing.
        segment: usize,
    },
    /// An option is out of range; the message names it.
    #[error("invalid option: {0}")]
    Options(&'static str),
    /// The Hausdorff refinement ran out of [`DbscSkinOptions::max_work`].
    #[error(
        "skinning needed more than {budget} Hausdorff refinement steps (the stroke is too \
         fine for ε = {epsilon}: its size, or a kink or near-degenerate spot of its envelope, needs \
         more work than allowed); raise ε (--epsilon) or smooth the stroke"
    )]
    WorkBudget {
        /// The budget that ran out, in refinement steps.
        budget: usize,
        /// The ε asked for ([`DbscSkinOptions::epsilon`]).
        epsilon: f64,
    },
    /// Skinning a circle sequence failed.
    #[error(transparent)]
    Skin(#[from] SkinError),
    /// A Hausdorff bound failed (for example no real envelope at a parameter).
    #[error(transparent)]
    Hausdorff(#[from] HausdorffError),
    /// Envelope loop detection failed (kruppa-2023 Sec. 3).
    #[error(transparent)]
    Loops(#[from] LoopError),
}

/// The test [`skin_dbsc`] starts with, alone: the knot circles ⟨q(u_i); r(u_i)⟩ (eq. 19)
/// must be an admissible sequence (Def. 4.1), else [`DbscSkinError::NotAdmissible`]
/// exactly as [`skin_dbsc`] reports it. O(n log n) for n knot circles, without the loop
/// search and the Hausdorff refinement that [`skin_dbsc`] runs beside and after it: a
/// caller that splits strokes until they skin tests pieces with this first.
pub fn check_knot_circles(c: &DiskBSpline) -> Result<(), DbscSkinError> {
    let closed = c.is_closed();
    let (_, hi) = c.domain();
    let mut params = c.breakpoints();
    if closed {
        params.pop();
    }
    let circles: Vec<Circle> = params.iter().map(|&t| c.circle_at(t)).collect();
    check_admissible(&circles, closed, &adm_opts())
        .map_err(|e| not_admissible(&params, hi, closed, e))
}

fn adm_opts() -> AdmissibilityOptions {
    AdmissibilityOptions::default()
}

/// Skins a DBSC within ε where its envelopes allow (kruppa-2023 Sec. 4, phases 1–3; module
/// docs). The outline never self-intersects: phases 1–2 keep the circle sequence admissible
/// and phase 3 keeps an insertion only when the outline stays free of intersections.
pub fn skin_dbsc(c: &DiskBSpline, opts: &DbscSkinOptions) -> Result<DbscSkin, DbscSkinError> {
    let (crossing, skin) = skin_parts(c, opts, None)?;
    match crossing {
        Some((contour, other, segment)) => Err(DbscSkinError::SelfIntersection {
            contour,
            other,
            segment,
        }),
        None => skin,
    }
}

/// [`skin_dbsc`], and where its outline crosses itself the skin that
/// [`DbscSkinOptions::allow_global_overlap`] gives instead, marked `true`: the result of
/// `skin_dbsc(c, opts)` when that is not [`DbscSkinError::SelfIntersection`], else of
/// `skin_dbsc` with `allow_global_overlap` set — from one run (the option only skips the
/// final crossing test, so the second run would repeat the first). `loops`, when given,
/// must be `find_loops(c, opts.loop_tol)` (a caller that has them saves the search).
pub(crate) fn skin_dbsc_or_overlap(
    c: &DiskBSpline,
    opts: &DbscSkinOptions,
    loops: Option<&LoopReport>,
) -> Result<(DbscSkin, bool), DbscSkinError> {
    let (crossing, skin) = skin_parts(c, opts, loops)?;
    skin.map(|sk| (sk, crossing.is_some()))
}

/// The crossing of the final outline found by the safety net of [`skin_dbsc`] (none with
/// [`DbscSkinOptions::allow_global_overlap`]) and the skin or the error of its report;
/// the outer error is any earlier one (options, loops, phases, outline).
#[allow(clippy::type_complexity)]
fn skin_parts(
    c: &DiskBSpline,
    opts: &DbscSkinOptions,
    known_loops: Option<&LoopReport>,
) -> Result<
    (
        Option<(usize, usize, usize)>,
        Result<DbscSkin, DbscSkinError>,
    ),
    DbscSkinError,
> {
    if !(opts.epsilon > 0.0 && opts.epsilon.is_finite()) {
        return Err(DbscSkinError::Options(
            "epsilon must be positive and finite",
        ));
    }
    if !(opts.gap_fraction > 0.0 && opts.gap_fraction < 1.0) {
        return Err(DbscSkinError::Options("gap_fraction must be in (0, 1)"));
    }
    if !(opts.min_weight > 0.0 && opts.min_weight < 0.5) {
        return Err(DbscSkinError::Options("min_weight must be in (0, 1/2)"));
    }
    let closed = c.is_closed();
    let (_, hi) = c.domain();
    let mut params = c.breakpoints();
    if closed {
        params.pop();
    }
    let n = params.len();
    let mut st = State {
        c,
        loops: Vec::new(),
        closed,
        hi,
        opts: *opts,
        uses: vec![CircleUse::Both; n],
        marks: vec![Mark::Open; if closed { n } else { n.saturating_sub(1) }],
        weights: vec![0.5; if closed { n } else { n.saturating_sub(1) }],
        cache: RefCell::new(KeyMap::default()),
        quick: RefCell::default(),
        clear: RefCell::default(),
        params,
        work: RefCell::new(Work::new(opts.max_work)),
        spans: SpanPoly::all(c),
        circles: RefCell::default(),
        admissible: RefCell::default(),
        sides: RefCell::default(),
        touching: RefCell::default(),
    };
    // The envelope loops (phase 3 and the report use them) beside phases 1 and 2, which
    // do not: a loop error still comes first, as when they were found before.
    let loops = match known_loops {
        Some(l) => {
            st.phases_one_two()?;
            l.clone()
        }
        None => {
            let (loops, phases) =
                crate::par::join(|| find_loops(c, opts.loop_tol), || st.phases_one_two());
            let loops = loops?;
            phases?;
            loops
        }
    };
    st.loops = loops.loops.clone();
    if opts.two_sided {
        st.phase3()?;
    }
    let o = st.outline()?;
    // Safety net: never hand out a crossing outline (phases 1–2 rely on admissibility,
    // phase 3 checks each insertion; this re-checks the final result), checked beside the
    // final report's bounds; a crossing wins over any error of the report, whose bounds a
    // caller that retries with `allow_global_overlap` would discard.
    let mode = match opts.report {
        ReportBounds::Tight => Mode::Tight,
        ReportBounds::Decided => Mode::DecidedReport,
    };
    // Contours that phase 3 already found free of crossings (the same test) need no test.
    let verified = st.clear.take();
    // The state moves to the other closure by a unique borrow (its caches are not Sync).
    let state = &mut st;
    let (crossing, err) = crate::par::join(
        || {
            (!opts.allow_global_overlap && verified.as_ref() != Some(&o.contours))
                .then(|| first_crossing(&o.contours, opts.intersect_tol))
                .flatten()
        },
        move || state.errors(mode),
    );
    let err = match err {
        Ok(e) => e,
        Err(e) => return Ok((crossing, Err(e))),
    };
    let mut report = Vec::with_capacity(err.len());
    for (i, e) in err.iter().enumerate() {
        let (t0, t1) = (st.params[i], st.seg_end(i));
        let (ml, mr) = (st.met(&e[0]), st.met(&e[1]));
        let stopped_in = if ml && mr {
            None
        } else {
            Some(match st.marks[i] {
                Mark::Stopped(p) => p,
                _ if opts.two_sided => Phase::Three,
                _ => Phase::Two,
            })
        };
        let lp: Vec<EnvelopeLoop> = loops
            .loops
            .iter()
            .filter(|l| overlaps(l.t_a, l.t_b, t0, t1))
            .copied()
            .collect();
        report.push(SegmentReport {
            t0,
            t1,
            error_left: e[0],
            error_right: e[1],
            met_left: ml,
            met_right: mr,
            stopped_in,
            loops: lp,
        });
    }
    let skin = DbscSkin {
        closed,
        circles: st.circles_of(&st.params),
        params: st.params,
        uses: st.uses,
        left: o.left,
        left_params: o.left_params,
        right: o.right,
        right_params: o.right_params,
        outline: o.contours,
        report,
        work: st.work.borrow().spent,
    };
    Ok((crossing, Ok(skin)))
}

/// Whether the loop interval [a, b] (wrapping when a > b) overlaps [t0, t1].
fn overlaps(a: f64, b: f64, t0: f64, t1: f64) -> bool {
    if a <= b {
        a < t1 && b > t0
    } else {
        a < t1 || b > t0
    }
}

fn not_admissible(params: &[f64], hi: f64, closed: bool, e: SkinError) -> DbscSkinError {
    let circles = match &e {
        SkinError::Inadmissible { circles, .. } => circles.clone(),
        SkinError::InvalidCircle { index } | SkinError::NoTouchingPoints { index } => vec![*index],
        _ => Vec::new(),
    };
    let ps: Vec<f64> = circles
        .iter()
        .filter_map(|&i| params.get(i).copied())
        .collect();
    let lo_i = circles.iter().copied().min().unwrap_or(0);
    let hi_i = circles.iter().copied().max().unwrap_or(0);
    let t0 = params.get(lo_i).copied().unwrap_or(0.0);
    let t1 = if closed && hi_i + 1 >= params.len() {
        hi
    } else {
        params.get(hi_i).copied().unwrap_or(hi)
    };
    DbscSkinError::NotAdmissible {
        circles,
        params: ps,
        t0,
        t1,
        source: e,
    }
}

#[cfg(test)]
mod tests {
    use super::state::outline_intersects;
    use super::*;
    use crate::geom::DVec2;
    use crate::geom::intersect::path_self_intersections;
    use crate::geom::path::polygon_area;

    use crate::dbsc::test_util::{open, s_stroke};

    /// A stroke with a sharp left bend: the left envelope has a loop.
    fn bend_stroke() -> Vec<(f64, f64, f64)> {
        vec![
            (0.0, 0.0, 0.8),
            (4.0, 0.0, 0.8),
            (5.0, 1.0, 0.8),
            (4.0, 2.0, 0.8),
            (0.0, 2.2, 0.8),
        ]
    }

    fn opts(epsilon: f64) -> DbscSkinOptions {
        DbscSkinOptions {
            epsilon,
            ..DbscSkinOptions::default()
        }
    }

    fn area(s: &DbscSkin) -> f64 {
        s.outline
            .iter()
            .map(|c| polygon_area(&c.flatten(1e-5)))
            .sum()
    }

    fn transform(d: &[(f64, f64, f64)], rot: f64, scale: f64) -> Vec<(f64, f64, f64)> {
        let (sn, cs) = rot.sin_cos();
        d.iter()
            .map(|&(x, y, r)| {
                (
                    scale * (cs * x - sn * y),
                    scale * (sn * x + cs * y),
                    scale * r,
                )
            })
            .collect()
    }

    proptest::proptest! {
        /// The test of an outline after one change, from the crossing-free outline before
        /// it, agrees with the test of the whole outline: a star-shaped polygon (no
        /// crossings) with one vertex moved, one inserted and one removed.
        #[test]
        fn crosses_since_agrees_with_the_whole_test(
            radii in proptest::collection::vec(1.0f64..3.0, 5..40),
            k in 0usize..40,
            moved in (-4.0f64..4.0, -4.0f64..4.0),
        ) {
            use super::state::crosses_since;
            let n = radii.len();
            let star: Vec<DVec2> = radii
                .iter()
                .enumerate()
                .map(|(i, &r)| r * DVec2::from_angle(std::f64::consts::TAU * i as f64 / n as f64))
                .collect();
            let old = [Path::polyline(&star, true)];
            proptest::prop_assert!(!outline_intersects(&old, 1e-9));
            let k = k % n;
            let p = DVec2::new(moved.0, moved.1);
            let mut changed = star.clone();
            changed[k] = p;
            let mut inserted = star.clone();
            inserted.insert(k, p);
            let mut removed = star.clone();
            removed.remove(k);
            for v in [changed, inserted, removed] {
                let new = [Path::polyline(&v, true)];
                proptest::prop_assert_eq!(
                    crosses_since(&old, &new, 1e-9),
                    outline_intersects(&new, 1e-9)
                );
            }
        }
    }

    /// The parallel Hausdorff bounds give the serial result: one thread against four, with
    /// a budget large enough for every bound and one so small that the serial replay must
    /// recompute bounds cut short by the shared budget (and finally runs out).
    /// Two contours that cross each other but not themselves are named as a pair, not as
    /// one contour intersecting itself.
    #[test]
    fn first_crossing_names_both_contours() {
        let square = |x: f64| {
            let p = |a: f64, b: f64| DVec2::new(x + a, b);
            Path::polyline(&[p(0.0, 0.0), p(2.0, 0.0), p(2.0, 2.0), p(0.0, 2.0)], true)
        };
        let apart = [square(0.0), square(5.0)];
        assert_eq!(first_crossing(&apart, 1e-9), None);
        let (a, b, _) = first_crossing(&[square(0.0), square(1.0)], 1e-9).unwrap();
        assert_eq!((a, b), (0, 1));
        let e = DbscSkinError::SelfIntersection {
            contour: 0,
            other: 1,
            segment: 2,
        };
        assert_eq!(
            e.to_string(),
            "skin outline contour 0 crosses contour 1 at its segment 2"
        );
        let bow = Path::polyline(
            &[
                DVec2::ZERO,
                DVec2::new(2.0, 2.0),
                DVec2::new(2.0, 0.0),
                DVec2::new(0.0, 2.0),
            ],
            true,
        );
        let (a, b, _) = first_crossing(&[square(9.0), bow], 1e-9).unwrap();
        assert_eq!((a, b), (1, 1));
    }

    #[test]
    #[cfg(feature = "parallel")]
    fn parallel_skinning_equals_serial() {
        let pool = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        for (stroke, max_work) in [
            (s_stroke(), DEFAULT_MAX_WORK),
            (bend_stroke(), DEFAULT_MAX_WORK),
            (s_stroke(), 300),
        ] {
            let c = open(3, &stroke);
            let o = DbscSkinOptions {
                max_work,
                ..opts(0.01)
            };
            let serial = pool(1).install(|| skin_dbsc(&c, &o));
            let parallel = pool(4).install(|| skin_dbsc(&c, &o));
            assert_eq!(serial, parallel);
        }
        let small = DbscSkinOptions {
            max_work: 300,
            ..opts(0.01)
        };
        assert!(matches!(
            skin_dbsc(&open(3, &s_stroke()), &small),
            Err(DbscSkinError::WorkBudget { .. })
        ));
    }

    #[test]
    fn loop_free_stroke_meets_eps_everywhere() {
        let c = open(3, &s_stroke());
        assert!(find_loops(&c, 1e-10).unwrap().loops.is_empty());
        let eps = 0.01;
        let s = skin_dbsc(&c, &opts(eps)).unwrap();
        assert!(s.circles.len() > c.breakpoints().len());
        for r in &s.report {
            assert!(r.met_left && r.met_right, "{r:?}");
            assert!(r.error_left.upper <= eps && r.error_right.upper <= eps);
            assert!(r.stopped_in.is_none() && r.loops.is_empty());
            assert!(r.error_left.gap() <= 0.1 * eps + 1e-15);
        }
        assert!(!outline_intersects(&s.outline, 1e-9));
        // Independent check of the error: skin arc points lie within ε (+ gap) of the
        // envelope samples' polyline hull, sampled densely.
        for (k, arc) in s.left.iter().enumerate() {
            let (t0, t1) = (s.left_params[k], s.left_params[k + 1]);
            let env: Vec<DVec2> = (0..=200)
                .map(|i| {
                    c.envelope(Side::Left, t0 + (t1 - t0) * i as f64 / 200.0)
                        .unwrap()
                        .point
                })
                .collect();
            for i in 0..=50 {
                let p = arc.eval(i as f64 / 50.0);
                let d = env
                    .windows(2)
                    .map(|w| crate::geom::Line::new(w[0], w[1]).distance(p))
                    .fold(f64::INFINITY, f64::min);
                assert!(d <= eps * 1.01, "segment {k}: {d}");
            }
        }
        // Every circle of the result is a circle of the DBSC at its parameter.
        for (t, k) in s.params.iter().zip(&s.circles) {
            assert_eq!(c.circle_at(*t), *k);
        }
    }

    #[test]
    fn decided_report_bounds_give_the_same_skin_with_less_work() {
        let mut failing = 0;
        for (c, eps) in [
            (open(3, &s_stroke()), 0.01),
            (open(3, &bend_stroke()), 0.05),
        ] {
            let tight = skin_dbsc(&c, &opts(eps)).unwrap();
            let o = DbscSkinOptions {
                report: ReportBounds::Decided,
                ..opts(eps)
            };
            let decided = skin_dbsc(&c, &o).unwrap();
            assert_eq!(decided.outline, tight.outline);
            assert_eq!(decided.params, tight.params);
            assert!(
                decided.work < tight.work,
                "{} vs {}",
                decided.work,
                tight.work
            );
            assert_eq!(decided.report.len(), tight.report.len());
            for (d, t) in decided.report.iter().zip(&tight.report) {
                // Both enclose the same distance, so the intervals meet.
                for (a, b) in [(d.error_left, t.error_left), (d.error_right, t.error_right)] {
                    assert!(a.lower <= b.upper && b.lower <= a.upper, "{a:?} vs {b:?}");
                    // Failing sides too carry a finite upper bound (the passes leave it out).
                    assert!(a.upper.is_finite(), "{a:?}");
                    failing += usize::from(a.upper > eps);
                }
                // Met sides are proven within ε either way.
                if d.met_left && d.met_right {
                    assert!(d.error_left.upper <= eps && d.error_right.upper <= eps);
                }
                assert_eq!(
                    d.stopped_in.is_none(),
                    t.stopped_in.is_none(),
                    "{d:?} vs {t:?}"
                );
            }
        }
        assert!(
            failing > 0,
            "no failing side: the finite-upper check tested nothing"
        );
    }

    #[test]
    fn looping_stroke_gives_clean_outline_and_names_loops() {
        let c = open(3, &bend_stroke());
        let loops = find_loops(&c, 1e-10).unwrap();
        assert_eq!(loops.loops.len(), 1);
        let lp = loops.loops[0];
        let s = skin_dbsc(&c, &opts(0.01)).unwrap();
        assert!(!outline_intersects(&s.outline, 1e-9));
        for o in &s.outline {
            assert!(path_self_intersections(o, 1e-9).is_empty());
        }
        let named: Vec<&SegmentReport> = s.report.iter().filter(|r| !r.loops.is_empty()).collect();
        assert!(!named.is_empty());
        for r in &named {
            assert!(overlaps(lp.t_a, lp.t_b, r.t0, r.t1));
        }
        // The skin cannot follow the swallowtail: some looping segment misses ε on the
        // looping side and the report says which phase stopped it.
        assert!(named.iter().any(|r| !r.met_left && r.stopped_in.is_some()));
        // Segments away from the loop are accurate.
        for r in s.report.iter().filter(|r| r.loops.is_empty()) {
            if r.t1 < lp.t_a - 0.1 || r.t0 > lp.t_b + 0.1 {
                assert!(r.met_left && r.met_right, "{r:?}");
            }
        }
    }

    #[test]
    fn reversed_rotated_scaled_agree() {
        for d in [s_stroke(), bend_stroke()] {
            let eps = 0.01;
            let base = skin_dbsc(&open(3, &d), &opts(eps)).unwrap();
            let a0 = area(&base);
            // Rotation and uniform scaling (with ε scaled) give the same circle parameters.
            let k = 2.5;
            let t = skin_dbsc(&open(3, &transform(&d, 0.7, k)), &opts(k * eps)).unwrap();
            assert_eq!(t.params.len(), base.params.len());
            for (a, b) in t.params.iter().zip(&base.params) {
                assert!((a - b).abs() < 1e-12);
            }
            assert!(
                (area(&t) - k * k * a0).abs() < 1e-4 * k * k * a0.abs(),
                "{} {}",
                area(&t),
                k * k * a0
            );
            // Reversal: the same region within the accuracy (met segments reach ε on both
            // runs; the area differs by at most ε times the perimeter).
            let rev: Vec<(f64, f64, f64)> = d.iter().rev().copied().collect();
            let r = skin_dbsc(&open(3, &rev), &opts(eps)).unwrap();
            assert!(!outline_intersects(&r.outline, 1e-9));
            let perim: f64 = base.outline.iter().map(|c| c.length(1e-9)).sum();
            assert!(
                (area(&r) - a0).abs() <= 2.0 * eps * perim,
                "{} {}",
                area(&r),
                a0
            );
            let missed = |s: &DbscSkin| {
                s.report
                    .iter()
                    .filter(|x| !(x.met_left && x.met_right))
                    .count()
            };
            assert_eq!(missed(&base) == 0, missed(&r) == 0);
        }
    }

    #[test]
    fn inadmissible_knot_circles_name_the_span() {
        // Degree 1: the knot circles are the control disks; the middle one is covered.
        let c = open(
            1,
            &[
                (0.0, 0.0, 2.0),
                (0.5, 0.0, 0.2),
                (1.0, 0.0, 2.0),
                (5.0, 0.0, 1.0),
            ],
        );
        match skin_dbsc(&c, &opts(0.01)) {
            Err(DbscSkinError::NotAdmissible {
                circles,
                params,
                t0,
                t1,
                ..
            }) => {
                assert!(!circles.is_empty());
                assert_eq!(params.len(), circles.len());
                assert!(t0 <= t1);
                // The covered circle is at parameter 1/3.
                assert!(
                    params.iter().any(|&t| (t - 1.0 / 3.0).abs() < 1e-12),
                    "{params:?}"
                );
            }
            other => panic!("expected NotAdmissible, got {other:?}"),
        }
        assert!(matches!(
            skin_dbsc(&open(3, &s_stroke()), &opts(0.0)),
            Err(DbscSkinError::Options(_))
        ));
    }

    #[test]
    fn closed_stroke_meets_eps() {
        let disks: Vec<Circle> = (0..6)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 6.0;
                Circle::new(
                    DVec2::new(10.0 * a.cos(), 7.0 * a.sin()),
                    1.0 + 0.3 * (i % 2) as f64,
                )
            })
            .collect();
        let c = DiskBSpline::closed(3, &disks, None).unwrap();
        let s = skin_dbsc(&c, &opts(0.01)).unwrap();
        assert_eq!(s.outline.len(), 2);
        assert!(!outline_intersects(&s.outline, 1e-9));
        for r in &s.report {
            assert!(r.met_left && r.met_right, "{r:?}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(12))]

        /// Random strokes either skin to an intersection-free outline or are rejected as
        /// inadmissible at the knot circles: the safety net (SelfIntersection) never fires.
        #[test]
        fn random_strokes_never_cross(
            d in proptest::collection::vec((-1.0f64..1.0, -4.0f64..4.0, 0.3f64..1.5), 5..8),
        ) {
            let pts: Vec<(f64, f64, f64)> = d
                .iter()
                .enumerate()
                .map(|(i, &(x, y, r))| (4.0 * i as f64 + x, y, r))
                .collect();
            match skin_dbsc(&open(3, &pts), &opts(0.05)) {
                Ok(s) => {
                    proptest::prop_assert!(!outline_intersects(&s.outline, 1e-9));
                    for r in &s.report {
                        proptest::prop_assert!(r.error_left.lower <= r.error_left.upper);
                        proptest::prop_assert_eq!(r.met_left && r.met_right, r.stopped_in.is_none());
                    }
                }
                Err(DbscSkinError::NotAdmissible { .. }) => {}
                Err(e) => proptest::prop_assert!(false, "{}", e),
            }
        }
    }
}
