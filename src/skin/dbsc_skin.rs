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
//!   examples' skins; on 150 random sharp strokes it saves 17 of 3,978 circles
//!   (tests/skin_push_back.rs).
//! * Phase 2: the same with plain midpoint insertion u* and no pair check.
//! * Phase 3 (Sec. 4.3): where both sides miss ε, insert c* at the midpoint when the radical
//!   centre of (c_i, c*, c_{i+1}) lies inside c*, on the side whose touching point on c* is
//!   not covered by c_i ∪ c_{i+1} only (circle marks LEFT/RIGHT; the others BOTH). The left
//!   skin skins the LEFT and BOTH circles, the right skin the RIGHT and BOTH circles. An
//!   insertion is kept only if the resulting outline stays free of self-intersections.

use super::bits_hash::{BitsMap, BitsSet};
use super::hausdorff::{
    EnvelopeSegment, HausdorffBounds, HausdorffError, MAX_BOUND_WORK, Rejection, Work,
    skin_envelope_bounds, skin_envelope_within,
};
use super::outline::outline_from_skins;
use super::touching::triplet_touching;
use super::{AdmissibilityOptions, SkinError, Skins, TouchingPoints, check_admissible};
use crate::dbsc::{DiskBSpline, EnvelopeLoop, LoopError, Side, SpanPoly, find_loops};
use crate::geom::intersect::path_self_intersections;
use crate::geom::intersect::paths_intersections;
use crate::geom::{Circle, CubicBez, DVec2, Path};
use crate::par::prelude::*;
use std::cell::RefCell;

/// Options of [`skin_dbsc`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DbscSkinOptions {
    /// ε of kruppa-2023 Sec. 4.2 (model units).
    pub eps: f64,
    /// Hausdorff bounds are refined to a gap of `gap_fraction · ε`.
    pub gap_fraction: f64,
    /// Parameter tolerance of loop detection (kruppa-2023 Sec. 3).
    pub loop_tol: f64,
    /// Phase 1 stops halving the weights of eq. 25 below this value ("too close").
    pub min_weight: f64,
    /// Phase 1 may push the previous insertion back towards its segment start when the
    /// next insertion is not admissible otherwise (kruppa-2023 Sec. 4.2, the paragraph after
    /// eq. 25). Off by default: it saves 0.4 % of the circles on random sharp strokes and
    /// changes no example, but on one random design of the issue-11 campaign (seed
    /// 0x5EED0011, case 145) the sequence it leaves cannot be skinned in phase 3.
    pub push_back: bool,
    /// Upper limit of circles, a guard against runaway refinement.
    pub max_circles: usize,
    /// Budget of Hausdorff refinement steps (branch-and-bound nodes, see
    /// [`super::hausdorff::MAX_BOUND_WORK`]) for the whole skinning of one stroke. Running
    /// out is [`DbscSkinError::WorkBudget`], never a hang.
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
            eps: crate::geom::tol::SKIN_EPSILON,
            gap_fraction: 0.1,
            loop_tol: 1e-10,
            // 1/64: c* within 1.6 % of the span end, i.e. almost a repeated knot circle.
            min_weight: 1.0 / 64.0,
            push_back: false,
            max_circles: 20_000,
            max_work: DEFAULT_MAX_WORK,
            two_sided: true,
            intersect_tol: 1e-9,
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

/// Default of [`DbscSkinOptions::max_work`]: one million refinement steps. The examples'
/// strokes need at most about 11 000 at ε = 0.01 mm (loop.toml; the G-clef 8 800; measured
/// by the test `examples_stay_well_inside_the_work_budget`), since most bounds are settled
/// by the matching-bound search of [`super::hausdorff`] before any point-distance search.
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
         fine for ε = {eps}: its size, or a kink or near-degenerate spot of its envelope, needs \
         more work than allowed); raise ε (--epsilon) or smooth the stroke"
    )]
    WorkBudget {
        /// The budget that ran out, in refinement steps.
        budget: usize,
        /// The ε asked for.
        eps: f64,
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

/// Refinement state of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mark {
    Open,
    Finished,
    Stopped(Phase),
}

struct State<'a> {
    c: &'a DiskBSpline,
    closed: bool,
    hi: f64,
    opts: DbscSkinOptions,
    params: Vec<f64>,
    uses: Vec<CircleUse>,
    /// Per segment: mark and weight of eq. 25.
    marks: Vec<Mark>,
    weights: Vec<f64>,
    /// Error bounds by (arc, span, side, mode).
    cache: RefCell<KeyMap<HausdorffBounds>>,
    /// Envelope loops of the curve (kruppa-2023 Sec. 3).
    loops: Vec<EnvelopeLoop>,
    /// Refinement steps left for the Hausdorff bounds of the whole skinning.
    work: RefCell<Work>,
    /// The curve's knot spans in Bernstein form, shared by every envelope segment.
    spans: Vec<SpanPoly>,
    /// The circles ⟨q(u); r(u)⟩ evaluated so far, by the bits of u: the sequence is
    /// evaluated again for every admissibility test and skin, and most of its parameters
    /// stay from pass to pass.
    circles: RefCell<BitsMap<u64, Circle>>,
    /// Parameter sequences (by their bits) whose circles passed [`check_admissible`]: the
    /// skin of a pass's sequence need not test again what its insertion test showed.
    admissible: RefCell<BitsSet<Vec<u64>>>,
}

/// What the error bounds of a pass are for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Mode {
    /// Whether each side meets ε ([`hausdorff_within_work`], quick rejection without the
    /// upper bound of failing sides, which a pass never reads).
    Decide,
    /// The final report of [`ReportBounds::Decided`]: `Decide`'s bounds, with the quick
    /// rejection's upper bound for failing sides. Sides `Decide` found within ε are read
    /// from its cache (the same bounds).
    DecidedReport,
    /// As `Decide`, with the upper bounds of failing sides from the full search: phase 3
    /// compares them.
    Compare,
    /// Bounds to the gap (the final report).
    Tight,
}

type CacheKey = ([u64; 10], usize, Mode);

/// Maps keyed by [`CacheKey`].
type KeyMap<V> = BitsMap<CacheKey, V>;

fn cache_key(arc: &CubicBez, t0: f64, t1: f64, side: usize, mode: Mode) -> CacheKey {
    let p = arc.points();
    let mut k = [0u64; 10];
    for (i, q) in p.iter().enumerate() {
        k[2 * i] = q.x.to_bits();
        k[2 * i + 1] = q.y.to_bits();
    }
    k[8] = t0.to_bits();
    k[9] = t1.to_bits();
    (k, side, mode)
}

/// The bound of `key` computed already: its own or, for [`Mode::DecidedReport`], one that
/// [`Mode::Decide`] found within `eps` (the same bound: the two differ only where D_H > ε).
fn cached(cache: &KeyMap<HausdorffBounds>, key: &CacheKey, eps: f64) -> Option<HausdorffBounds> {
    cache.get(key).copied().or_else(|| {
        let decide = (key.0, key.1, Mode::Decide);
        let met = |h: &HausdorffBounds| h.upper <= eps;
        (key.2 == Mode::DecidedReport)
            .then(|| cache.get(&decide).copied().filter(met))
            .flatten()
    })
}

/// One Hausdorff bound to compute: a skin arc against the envelope on `side` over [t0, t1].
struct BoundJob {
    key: CacheKey,
    arc: CubicBez,
    side: Side,
    t0: f64,
    t1: f64,
}

type SideSkin = Result<(Vec<f64>, Vec<CubicBez>), SkinError>;
type Speculative = (Result<HausdorffBounds, HausdorffError>, usize);

/// Runs `bound` in parallel (rayon) on every distinct uncached (arc, span) of the sides up
/// to the first side that failed, keyed by cache key; the caller decides in serial order
/// which results stand (a pure function of the job and the budget, so thread count and
/// scheduling cannot change them).
fn speculative_bounds(
    sides: &[SideSkin; 2],
    hi: f64,
    (mode, eps): (Mode, f64),
    cache: &KeyMap<HausdorffBounds>,
    bound: impl Fn(&BoundJob) -> Speculative + Sync,
) -> KeyMap<Speculative> {
    let mut jobs: Vec<BoundJob> = Vec::new();
    let mut seen: BitsSet<CacheKey> = BitsSet::default();
    for (k, side) in [Side::Left, Side::Right].into_iter().enumerate() {
        let Ok((ps, arcs)) = &sides[k] else {
            break;
        };
        for (a, arc) in arcs.iter().enumerate() {
            let t0 = ps[a];
            let t1 = ps.get(a + 1).copied().unwrap_or(hi);
            let key = cache_key(arc, t0, t1, k, mode);
            if cached(cache, &key, eps).is_none() && seen.insert(key) {
                jobs.push(BoundJob {
                    key,
                    arc: *arc,
                    side,
                    t0,
                    t1,
                });
            }
        }
    }
    // One job gains nothing from a thread; keep it on the caller's.
    if jobs.len() < 2 {
        return KeyMap::default();
    }
    jobs.par_iter().map(|j| (j.key, bound(j))).collect()
}

/// The bits of a parameter sequence, the key of [`State::admissible`].
fn param_bits(ps: &[f64]) -> Vec<u64> {
    ps.iter().map(|t| t.to_bits()).collect()
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

impl State<'_> {
    fn circles_of(&self, ps: &[f64]) -> Vec<Circle> {
        let mut memo = self.circles.borrow_mut();
        ps.iter()
            .map(|&t| {
                *memo
                    .entry(t.to_bits())
                    .or_insert_with(|| self.c.circle_at(t))
            })
            .collect()
    }

    /// End parameter of segment i.
    fn seg_end(&self, i: usize) -> f64 {
        self.params.get(i + 1).copied().unwrap_or(self.hi)
    }

    fn n_segments(&self) -> usize {
        if self.closed {
            self.params.len()
        } else {
            self.params.len() - 1
        }
    }

    fn admissible_with(&self, extra: &[f64]) -> bool {
        self.admissible_moved(None, extra)
    }

    /// Admissibility of the circles of `params` with circle `moved.0` at parameter `moved.1`
    /// instead, plus the circles at `extra`.
    fn admissible_moved(&self, moved: Option<(usize, f64)>, extra: &[f64]) -> bool {
        let mut ps: Vec<f64> = self.params.clone();
        if let Some((k, u)) = moved {
            ps[k] = u;
        }
        ps.extend_from_slice(extra);
        ps.sort_by(f64::total_cmp);
        ps.dedup();
        self.admissible_params(&ps).is_ok()
    }

    /// [`check_admissible`] of the circles at `ps`; a sequence that passed once is not
    /// tested again ([`State::admissible`]).
    fn admissible_params(&self, ps: &[f64]) -> Result<(), SkinError> {
        let key = param_bits(ps);
        if self.admissible.borrow().contains(&key) {
            return Ok(());
        }
        check_admissible(&self.circles_of(ps), self.closed, &adm_opts())?;
        self.admissible.borrow_mut().insert(key);
        Ok(())
    }

    fn insert(&mut self, i: usize, u: f64) {
        self.params.insert(i + 1, u);
        self.uses.insert(i + 1, CircleUse::Both);
        self.marks[i] = Mark::Open;
        self.marks.insert(i + 1, Mark::Open);
        self.weights[i] = 0.5;
        self.weights.insert(i + 1, 0.5);
    }

    /// Parameters of the circles used on `side`.
    fn side_params(&self, side: Side) -> Vec<f64> {
        self.params
            .iter()
            .zip(&self.uses)
            .filter(|(_, u)| u.on(side))
            .map(|(&t, _)| t)
            .collect()
    }

    /// The left and the right skin: per side its circles' parameters and arcs. While both
    /// sides skin the same circles (every circle BOTH, phases 1 and 2; a LEFT or RIGHT
    /// circle is on one side only) one skinning of the sequence gives both, and the
    /// sequence must be admissible: the test `skin_circles` would make (same options, same
    /// error), skipped for a sequence that passed before. With one-sided circles (phase 3)
    /// one side's sequence may break the admissibility of the other's, so none is tested.
    fn skin_sides(&self) -> [SideSkin; 2] {
        let (pl, pr) = (self.side_params(Side::Left), self.side_params(Side::Right));
        if pl == pr {
            let skins = self
                .admissible_params(&pl)
                .and_then(|()| skin_both_arcs(&self.circles_of(&pl), self.closed));
            return match skins {
                Ok((left, right)) => [Ok((pl.clone(), left)), Ok((pr, right))],
                Err(e) => [Err(e.clone()), Err(e)],
            };
        }
        [(Side::Left, pl), (Side::Right, pr)].map(|(side, ps)| {
            let (left, right) = skin_both_arcs(&self.circles_of(&ps), self.closed)?;
            let arcs = match side {
                Side::Left => left,
                Side::Right => right,
            };
            Ok((ps, arcs))
        })
    }

    /// Errors of every side segment, mapped onto the segments of `params`.
    ///
    /// The bounds not yet cached are computed in parallel ([`speculative_bounds`]), then
    /// taken in serial order against the shared work budget exactly as a serial run would
    /// spend it; a bound whose parallel run might have been cut short by a smaller serial
    /// budget is recomputed with that budget, so the result does not depend on threads.
    fn errors(&self, mode: Mode) -> Result<Vec<[HausdorffBounds; 2]>, DbscSkinError> {
        let mut out = vec![
            [HausdorffBounds {
                lower: 0.0,
                upper: 0.0
            }; 2];
            self.n_segments()
        ];
        let sides = self.skin_sides();
        let gap = self.opts.gap_fraction * self.opts.eps;
        let (c, eps) = (self.c, self.opts.eps);
        let spans = &self.spans;
        let bound = |arc: &CubicBez, side: Side, t0: f64, t1: f64, w: &mut Work| {
            let env = EnvelopeSegment::with_spans(c, spans, side, t0, t1)?;
            match mode {
                Mode::Tight => skin_envelope_bounds(arc, &env, gap, w),
                Mode::Decide => {
                    skin_envelope_within(arc, &env, (eps, Rejection::QuickLower), gap, w)
                }
                Mode::DecidedReport => {
                    skin_envelope_within(arc, &env, (eps, Rejection::Quick), gap, w)
                }
                Mode::Compare => skin_envelope_within(arc, &env, (eps, Rejection::Full), gap, w),
            }
        };
        let par_budget = self.work.borrow().left.min(MAX_BOUND_WORK);
        let mut pre = speculative_bounds(&sides, self.hi, (mode, eps), &self.cache.borrow(), |j| {
            let mut w = Work::new(par_budget);
            let r = bound(&j.arc, j.side, j.t0, j.t1, &mut w);
            (r, w.spent)
        });
        for (k, (side, skin)) in [Side::Left, Side::Right].into_iter().zip(sides).enumerate() {
            let (ps, arcs) = skin?;
            let mut j = 0;
            for (a, arc) in arcs.iter().enumerate() {
                let t0 = ps[a];
                let t1 = ps.get(a + 1).copied().unwrap_or(self.hi);
                // An arc and its span determine the error: reuse it across passes (most
                // arcs are unchanged by insertions elsewhere).
                let key = cache_key(arc, t0, t1, k, mode);
                let known = cached(&self.cache.borrow(), &key, eps);
                let h = match known {
                    Some(h) => h,
                    None => {
                        let mut budget = self.work.borrow_mut();
                        if budget.left == 0 {
                            return Err(DbscSkinError::WorkBudget {
                                budget: self.opts.max_work,
                                eps: self.opts.eps,
                            });
                        }
                        let mut w = Work::new(budget.left.min(MAX_BOUND_WORK));
                        let h = match pre.remove(&key) {
                            // Never ran out and fits this budget: the same run as serial.
                            Some((r, spent)) if spent < par_budget && spent <= w.left => {
                                w = Work {
                                    left: w.left - spent,
                                    spent,
                                };
                                r?
                            }
                            _ => bound(arc, side, t0, t1, &mut w)?,
                        };
                        budget.left -= w.spent;
                        budget.spent += w.spent;
                        self.cache.borrow_mut().insert(key, h);
                        h
                    }
                };
                while j < out.len() && self.params[j] < t1 {
                    out[j][k] = h;
                    j += 1;
                }
            }
        }
        Ok(out)
    }

    fn met(&self, h: &HausdorffBounds) -> bool {
        h.upper <= self.opts.eps
    }

    /// Initialisation (eq. 19: the knot circles must be admissible), then phase 1 (paired
    /// insertions) and phase 2 (midpoints) until no pass inserts.
    fn phases_one_two(&mut self) -> Result<(), DbscSkinError> {
        if let Err(e) = self.admissible_params(&self.params) {
            return Err(not_admissible(&self.params, self.hi, self.closed, e));
        }
        while self.pass(true)? {}
        for m in self.marks.iter_mut() {
            if *m == Mark::Stopped(Phase::One) {
                *m = Mark::Open;
            }
        }
        while self.pass(false)? {}
        Ok(())
    }

    /// One pass of phase 1 (`paired`) or phase 2; returns whether anything was inserted.
    fn pass(&mut self, paired: bool) -> Result<bool, DbscSkinError> {
        let phase = if paired { Phase::One } else { Phase::Two };
        let err = self.errors(Mode::Decide)?;
        // Marks from the errors of this pass (segments are re-opened by neighbours'
        // insertions, which move their touching points).
        for (i, e) in err.iter().enumerate() {
            if self.met(&e[0]) && self.met(&e[1]) {
                self.marks[i] = Mark::Finished;
            } else if self.marks[i] == Mark::Finished {
                self.marks[i] = Mark::Open;
            }
        }
        let mut inserted = false;
        // The circle this pass inserted last, if it ends the segment before `i`: its index in
        // `params`, its segment (u_{p+i}, u_{p+i+1}) and weight, for the push-back.
        let mut last: Option<(usize, f64, f64, f64)> = None;
        let mut i = 0;
        while i < self.marks.len() {
            if self.marks[i] != Mark::Open || self.params.len() >= self.opts.max_circles {
                i += 1;
                continue;
            }
            let (u0, u1) = (self.params[i], self.seg_end(i));
            // The next segment (u_{i+1}, u_{i+2}) of eq. 24; for closed strokes the last
            // segment's successor is the first one, starting at u_0 ≡ hi.
            let next = if i + 1 < self.n_segments() {
                Some((u1, self.seg_end(i + 1), i + 1))
            } else if self.closed && self.n_segments() > 1 {
                Some((self.params[0], self.seg_end(0), 0))
            } else {
                None
            };
            let mut found = None;
            let mut pushed = None;
            if paired {
                // The previous insertion of this pass, when it is the circle that starts this
                // segment's predecessor: it may be pushed back (below).
                let prev = last.filter(|&(k, ..)| k + 1 == i);
                let w_start = self.weights[i];
                let w2_start = next.map_or(0.5, |n| self.weights[n.2]);
                let mut w2_end;
                // First the weights of eq. 25 alone; then, as kruppa-2023 Sec. 4.2 continues,
                // with the previous insertion pushed back towards its own segment start (its
                // weight halved each time), since halving this segment's weights moves c*
                // towards that circle and can break the previous insertion's admissibility.
                let mut w_prev = prev.map_or(0.0, |p| p.3);
                'push: loop {
                    let moved = prev
                        .filter(|_| self.opts.push_back && w_prev < prev.map_or(0.0, |p| p.3))
                        .map(|(k, a, b, _)| (k, (1.0 - w_prev) * a + w_prev * b));
                    let (mut w, mut w2) = (w_start, w2_start);
                    while w >= self.opts.min_weight && w2 >= self.opts.min_weight {
                        let us = (1.0 - w) * u0 + w * u1;
                        let mut extra = vec![us];
                        if let Some((a, b, _)) = next {
                            extra.push(w2 * a + (1.0 - w2) * b);
                        }
                        // A pushed-back circle is kept only if the sequence it leaves, with
                        // c* alone (without the look-ahead c**), is admissible as well.
                        if us > u0
                            && us < u1
                            && self.admissible_moved(moved, &extra)
                            && (moved.is_none() || self.admissible_moved(moved, &[us]))
                        {
                            found = Some((us, w));
                            pushed = moved;
                            break;
                        }
                        w *= 0.5;
                        w2 *= 0.5;
                    }
                    w2_end = w2;
                    w_prev *= 0.5;
                    if found.is_some()
                        || !self.opts.push_back
                        || prev.is_none()
                        || w_prev < self.opts.min_weight
                    {
                        break 'push;
                    }
                }
                // The halved partner weight is kept for that segment (kruppa-2023 Sec. 4.2).
                if let Some((_, _, k)) = next {
                    self.weights[k] = w2_end.max(self.opts.min_weight);
                }
            } else {
                let us = 0.5 * (u0 + u1);
                if us > u0 && us < u1 && self.admissible_with(&[us]) {
                    found = Some((us, 0.5));
                }
            }
            match found {
                Some((us, w)) => {
                    if let Some((k, u)) = pushed {
                        self.params[k] = u;
                        self.marks[k - 1] = Mark::Open;
                        self.marks[k] = Mark::Open;
                    }
                    self.insert(i, us);
                    last = Some((i + 1, u0, u1, w));
                    inserted = true;
                    i += 2;
                }
                None => {
                    self.marks[i] = Mark::Stopped(phase);
                    last = None;
                    i += 1;
                }
            }
        }
        Ok(inserted)
    }

    fn outline(&self) -> Result<SidedOutline, SkinError> {
        let [left_side, right_side] = self.skin_sides();
        let (left_params, left) = left_side?;
        let (right_params, right) = right_side?;
        let contours = assemble_outline(&self.circles_of(&self.params), &left, &right, self.closed);
        Ok(SidedOutline {
            left_params,
            left,
            right_params,
            right,
            contours,
        })
    }

    fn self_intersects(&self) -> bool {
        match self.outline() {
            Ok(o) => outline_intersects(&o.contours, self.opts.intersect_tol),
            Err(_) => true,
        }
    }

    /// The neighbours of the segment (u0, u1) in the circle sequence of `side`.
    fn side_neighbours(&self, side: Side, u0: f64, u1: f64) -> Option<(Circle, Circle)> {
        let sp = self.side_params(side);
        let prev = sp.iter().rev().find(|&&p| p <= u0).copied();
        let next = sp.iter().find(|&&p| p >= u1).copied();
        let (prev, next) = if self.closed {
            (prev.or(sp.last().copied())?, next.or(sp.first().copied())?)
        } else {
            (prev?, next?)
        };
        Some((self.c.circle_at(prev), self.c.circle_at(next)))
    }

    /// kruppa-2023 Sec. 4.3 step 2 for one side: the radical centre of (a, c*, b) lies inside
    /// c* (so c* cannot join both skins) and the `side` touching point on c* is not covered
    /// by the neighbours a, b of that side (so that skin can use c*).
    fn one_sided_usable(&self, side: Side, u0: f64, u1: f64, m: &Circle) -> bool {
        let Some((a, b)) = self.side_neighbours(side, u0, u1) else {
            return false;
        };
        if a.radical_centre(m, &b, 1e-14)
            .is_none_or(|s| m.power(s) >= 0.0)
        {
            return false;
        }
        self.touching_uncovered(side, u0, u1, m)
    }

    /// True when the `side` touching point on `m`, in the triplet with that side's
    /// neighbours, exists and is not covered by them (so that skin can use `m`).
    fn touching_uncovered(&self, side: Side, u0: f64, u1: f64, m: &Circle) -> bool {
        let Some((a, b)) = self.side_neighbours(side, u0, u1) else {
            return false;
        };
        let Some(tt) = triplet_touching(&a, m, &b, adm_opts().rel_tol) else {
            return false;
        };
        let p = match side {
            Side::Left => tt.points.left,
            Side::Right => tt.points.right,
        };
        !(a.power(p) < 0.0 || b.power(p) < 0.0)
    }

    /// Phase 3 (kruppa-2023 Sec. 4.3): two-sided insertion where both sides miss ε.
    fn phase3(&mut self) -> Result<(), DbscSkinError> {
        loop {
            let err = self.errors(Mode::Decide)?;
            let both_miss = |e: &[HausdorffBounds; 2]| !self.met(&e[0]) && !self.met(&e[1]);
            // Where both sides miss ε the choice of side below compares their upper bounds:
            // those of the full search.
            let err = if err.iter().any(both_miss) {
                self.errors(Mode::Compare)?
            } else {
                err
            };
            let mut inserted = false;
            let mut i = err.len();
            while i > 0 {
                i -= 1;
                let both_miss = !self.met(&err[i][0]) && !self.met(&err[i][1]);
                if !both_miss || self.params.len() >= self.opts.max_circles {
                    continue;
                }
                if self.marks[i] == Mark::Stopped(Phase::Three) {
                    continue;
                }
                let (u0, u1) = (self.params[i], self.seg_end(i));
                let us = 0.5 * (u0 + u1);
                if !(us > u0 && us < u1) {
                    continue;
                }
                let m = self.c.circle_at(us);
                let usable: Vec<Side> = [Side::Left, Side::Right]
                    .into_iter()
                    .filter(|&side| self.one_sided_usable(side, u0, u1, &m))
                    .collect();
                let use_ = match usable.as_slice() {
                    [Side::Left] => CircleUse::Left,
                    [Side::Right] => CircleUse::Right,
                    _ => {
                        // Extension beyond the paper: where the radical-point rule gives no
                        // side, offer c* to the side that misses ε by less when that side's
                        // envelope has no loop here (so the skin follows a real boundary)
                        // and its touching point on c* is not covered by that side's
                        // neighbours; the outline check below still decides.
                        let (lo_err, hi_err) = (err[i][0].upper, err[i][1].upper);
                        let side = if lo_err <= hi_err {
                            Side::Left
                        } else {
                            Side::Right
                        };
                        let (dlo, dhi) = self.c.domain();
                        let narrow = (u1 - u0) < MIN_PHASE3_SPAN * (dhi - dlo);
                        let looped = self
                            .loops
                            .iter()
                            .any(|l| l.side == side && overlaps(l.t_a, l.t_b, u0, u1));
                        if narrow || looped || !self.touching_uncovered(side, u0, u1, &m) {
                            self.marks[i] = Mark::Stopped(Phase::Three);
                            continue;
                        }
                        match side {
                            Side::Left => CircleUse::Left,
                            Side::Right => CircleUse::Right,
                        }
                    }
                };
                let saved = (
                    self.params.clone(),
                    self.uses.clone(),
                    self.marks.clone(),
                    self.weights.clone(),
                );
                self.insert(i, us);
                self.uses[i + 1] = use_;
                if self.self_intersects() {
                    (self.params, self.uses, self.marks, self.weights) = saved;
                    self.marks[i] = Mark::Stopped(Phase::Three);
                } else {
                    inserted = true;
                }
            }
            if !inserted {
                return Ok(());
            }
        }
    }
}

/// Phase 3 does not split segments shorter than this fraction of the domain: a guard that
/// ends one-sided refinement where a side cannot reach ε (no envelope to follow there).
const MIN_PHASE3_SPAN: f64 = 1e-4;

/// Skins of both sides with their circle parameters and the outline contours.
struct SidedOutline {
    left_params: Vec<f64>,
    left: Vec<CubicBez>,
    right_params: Vec<f64>,
    right: Vec<CubicBez>,
    contours: Vec<Path>,
}

/// Outline contours of (possibly two-sided) skins by the skin outline assembly
/// ([`outline_from_skins`]). Adapter: that assembly reads the touching points of the first
/// and last circle (end caps) and the touching polygons (orientation of closed contours);
/// with two-sided skins the sides have different circle counts, so each side's touching
/// points are taken from its own arcs' start points and the shorter list is padded with its
/// last point (a repeated vertex changes no polygon area).
fn assemble_outline(
    circles: &[Circle],
    left: &[CubicBez],
    right: &[CubicBez],
    closed: bool,
) -> Vec<Path> {
    let ends = |arcs: &[CubicBez]| -> Vec<DVec2> {
        let mut v: Vec<DVec2> = arcs.iter().map(|a| a.p0).collect();
        if !closed && let Some(last) = arcs.last() {
            v.push(last.p3);
        }
        v
    };
    let (lp, rp) = (ends(left), ends(right));
    let n = lp.len().max(rp.len());
    let pick = |v: &[DVec2], i: usize| v.get(i).or(v.last()).copied().unwrap_or(DVec2::ZERO);
    let mut touching: Vec<TouchingPoints> = (0..n)
        .map(|i| TouchingPoints {
            left: pick(&lp, i),
            right: pick(&rp, i),
        })
        .collect();
    if !closed && let (Some(l), Some(r), Some(t)) = (lp.last(), rp.last(), touching.last_mut()) {
        // The last circle's touching points end both skins.
        *t = TouchingPoints {
            left: *l,
            right: *r,
        };
    }
    let skins = Skins {
        left: left.to_vec(),
        right: right.to_vec(),
        touching,
        closed,
    };
    outline_from_skins(circles, skins).contours
}

/// Whether outline contours intersect themselves or each other (skin intersection tests).
/// Whether the outline contours cross themselves or each other within `tol`.
fn outline_intersects(contours: &[Path], tol: f64) -> bool {
    first_crossing(contours, tol).is_some()
}

/// The first crossing of the outline contours, as (contour, other contour, segment of the
/// first): a contour crossing itself first, then pairs of contours.
fn first_crossing(contours: &[Path], tol: f64) -> Option<(usize, usize, usize)> {
    let own = contours
        .iter()
        .enumerate()
        .find_map(|(k, c)| path_self_intersections(c, tol).first().map(|h| (k, k, h.a)));
    own.or_else(|| {
        contours.iter().enumerate().find_map(|(i, a)| {
            contours
                .iter()
                .enumerate()
                .skip(i + 1)
                .find_map(|(j, b)| paths_intersections(a, b, tol).first().map(|h| (i, j, h.a)))
        })
    })
}

/// "intersects itself" or "crosses contour N" (the message of
/// [`DbscSkinError::SelfIntersection`]).
fn crossed(contour: usize, other: usize) -> String {
    if contour == other {
        "intersects itself".into()
    } else {
        format!("crosses contour {other}")
    }
}

/// The left and the right skin arcs of one circle sequence ([`super::skin_circles`]),
/// without its admissibility test: [`State::skin_sides`] makes that test where it applies.
fn skin_both_arcs(
    circles: &[Circle],
    closed: bool,
) -> Result<(Vec<CubicBez>, Vec<CubicBez>), SkinError> {
    let opts = super::SkinOptions {
        admissibility: adm_opts(),
        check_admissibility: false,
    };
    let s = super::skin_circles(circles, closed, &opts)?;
    Ok((s.left, s.right))
}

/// Skins a DBSC within ε where its envelopes allow (kruppa-2023 Sec. 4, phases 1–3; module
/// docs). The outline never self-intersects: phases 1–2 keep the circle sequence admissible
/// and phase 3 keeps an insertion only when the outline stays free of intersections.
pub fn skin_dbsc(c: &DiskBSpline, opts: &DbscSkinOptions) -> Result<DbscSkin, DbscSkinError> {
    if !(opts.eps > 0.0 && opts.eps.is_finite()) {
        return Err(DbscSkinError::Options("eps must be positive and finite"));
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
        params,
        work: RefCell::new(Work::new(opts.max_work)),
        spans: SpanPoly::all(c),
        circles: RefCell::default(),
        admissible: RefCell::default(),
    };
    // The envelope loops (phase 3 and the report use them) beside phases 1 and 2, which
    // do not: a loop error still comes first, as when they were found before.
    let (loops, phases) = crate::par::join(|| find_loops(c, opts.loop_tol), || st.phases_one_two());
    let loops = loops?;
    phases?;
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
    // The state moves to the other closure by a unique borrow (its caches are not Sync).
    let state = &mut st;
    let (crossing, err) = crate::par::join(
        || {
            (!opts.allow_global_overlap)
                .then(|| first_crossing(&o.contours, opts.intersect_tol))
                .flatten()
        },
        move || state.errors(mode),
    );
    if let Some((contour, other, segment)) = crossing {
        return Err(DbscSkinError::SelfIntersection {
            contour,
            other,
            segment,
        });
    }
    let err = err?;
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
    Ok(DbscSkin {
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
    })
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
    use super::*;
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

    fn opts(eps: f64) -> DbscSkinOptions {
        DbscSkinOptions {
            eps,
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

    /// The parallel Hausdorff bounds give the serial result: one thread against four, with
    /// a budget large enough for every bound and one so small that the serial replay must
    /// recompute bounds cut short by the shared budget (and finally runs out).
    /// Two contours that cross each other but not themselves are named as a pair (the
    /// message used to say "contour 0 intersects itself at its segment 0").
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
