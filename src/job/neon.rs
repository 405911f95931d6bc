//! Flex runs of a neon sign and its bill of materials.
//!
//! The LED flex follows the strokes' spines. A **run** is one piece of flex: a continuous
//! path through strokes whose ends meet ([`runs`]). Ends of different strokes (or both ends
//! of one stroke) at most `join_tolerance` apart are joined, tangent-continuous or not; the
//! pieces `NAME#0`, `NAME#1` of a stroke split at a corner share the corner disk and so
//! are joined; where three or more ends meet, the pairs that turn least are joined first
//! and the rest end runs. A join within the flex width of a `break_at` point is not made;
//! `[[neon.run]]` tables make runs of the strokes they list, in that order (a gap between
//! consecutive strokes is bridged too). A closed stroke is a closed run
//! of its own. A gap between joined ends is bridged straight and counted in the length
//! (`bridged_mm`). Circle sequences and shapes have no spine and carry no flex.
//!
//! Per run ([`RunBom`]): the strokes in order, the length L = Σ ∫‖q′(t)‖dt over the strokes'
//! spines (adaptive Gauss–Legendre per knot span, [`spine_length`]), the length rounded up to
//! the cut unit, ⌈L / cut_unit⌉·cut_unit, and the smallest bend radius along it: the spine's
//! radius of curvature ρ = 1/κ, κ = |q′ × q″| / ‖q′‖³, found per knot span by dense
//! sampling and golden-section refinement of every sampled local maximum of κ
//! ([`span_min_radius`]); a join whose tangents differ by more than [`TANGENT_BREAK_DEG`]
//! (and a point where q′ = 0) is a bend of radius 0.
//!
//! Warnings ([`NeonBom::judge`]): every stretch of a run whose bend radius is below the
//! flex's minimum, with its place; with the design scaled (`--fit`/`--scale`: the strokes
//! shrink, the flex does not), also every pair of runs whose spines came closer than the
//! channel width (their channels merge) while at the design's own size they were not, every
//! island of board the channels went around at the design's size (a letter's counter) that
//! the scaled channels cut away ([`filled_islands`]), and the note that a bend became too
//! tight by the scaling, every run shorter than the cut unit (`short`), and every bend
//! `round_bends` could not round (`round`). `break_at` points scale with the artwork.
//!
//! `[neon] round_bends = true` rounds the tight bends before the channel is made
//! ([`round_bends`], module `round`); `min_run_length` makes shorter runs marks
//! ([`split_marks`]): channelled, no flex, no holes, listed in [`NeonBom::marks`].

mod round;
pub use round::{
    ARC_PIECE_DEG, ARC_RADIUS_MARGIN, ROUND_MARGIN, ROUND_SAMPLES, RoundReport, Rounded,
    round_bends,
};

use crate::dbsc::DiskBSpline;
use crate::design::neon::{CHANNEL_CLEARANCE_MM, Flex, strokes_named};
use crate::design::{Design, HoleAt, OperationKind};
use crate::geom::{DVec2, cross};

/// Turning angle (degrees) above which a join of two strokes is a corner (bend radius 0):
/// G1 joins of fitted strokes agree to far below a degree; a font's corner turns by tens.
pub const TANGENT_BREAK_DEG: f64 = 1.0;

/// Curvature samples per knot span before refinement: a cubic span's curvature has at
/// most a few local maxima, each resolved by a 32-sample grid.
pub const BEND_SAMPLES: usize = 32;

/// Relative tolerance of the spine lengths (of the spine's length): far below the
/// 0.1 % a flex order can tell.
pub const LENGTH_REL_TOL: f64 = 1e-9;

/// Parameter tolerance of the bend refinement, as a fraction of the knot span.
pub const BEND_PARAM_TOL: f64 = 1e-10;

/// Flattening tolerance of the spines for the merge test, as a fraction of the flex width:
/// 6 µm for 6 mm flex, far below a distance that decides whether channels merge.
pub const SPINE_FLATTEN_OF_WIDTH: f64 = 1e-3;

/// One stroke of a run, as the run passes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Leg {
    /// Index of the stroke in the design.
    pub stroke: usize,
    /// The run passes the stroke from its end to its start.
    pub reversed: bool,
}

/// A run: its legs in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// The run's name (`[[neon.run]]` name, else `run N`).
    pub name: String,
    /// The strokes it passes, in order.
    pub legs: Vec<Leg>,
    /// The run returns to its start (a closed stroke, or a chain whose ends meet).
    pub closed: bool,
}

impl Leg {
    fn entry(&self, curves: &[DiskBSpline]) -> (DVec2, f64) {
        let c = &curves[self.stroke];
        let (lo, hi) = c.domain();
        let t = if self.reversed { hi } else { lo };
        (c.center(t), t)
    }

    fn exit(&self, curves: &[DiskBSpline]) -> (DVec2, f64) {
        let c = &curves[self.stroke];
        let (lo, hi) = c.domain();
        let t = if self.reversed { lo } else { hi };
        (c.center(t), t)
    }

    /// Unit tangent in the run's direction at parameter `t` (zero where q′ = 0).
    fn direction(&self, curves: &[DiskBSpline], t: f64) -> DVec2 {
        let d = curves[self.stroke].derivs(t, 1)[1].0.normalize_or_zero();
        if self.reversed { -d } else { d }
    }
}

impl Run {
    /// Start point of the run (the seam of a closed run).
    pub fn start(&self, curves: &[DiskBSpline]) -> DVec2 {
        self.legs[0].entry(curves).0
    }

    /// End point of the run.
    pub fn end(&self, curves: &[DiskBSpline]) -> DVec2 {
        self.legs[self.legs.len() - 1].exit(curves).0
    }
}

/// A stroke end: (stroke index, true for the end at the domain's upper bound).
type End = (usize, bool);

/// The runs of `design` (module docs); `curves[i]` is the curve of `design.stroke[i]`.
pub fn runs(design: &Design, curves: &[DiskBSpline], flex: &Flex) -> Vec<Run> {
    let n = curves.len();
    let neon = design.neon.clone().unwrap_or_default();
    let mut used = vec![false; n];
    // (first stroke index, run) pairs, sorted at the end.
    let mut out: Vec<(usize, Option<String>, Vec<Leg>, bool)> = Vec::new();
    for r in &neon.run {
        let ids: Vec<usize> = r
            .strokes
            .iter()
            .flat_map(|s| strokes_named(design, s))
            .filter(|&i| i < n && !used[i])
            .collect();
        if ids.is_empty() {
            continue;
        }
        for &i in &ids {
            used[i] = true;
        }
        let legs = chain(&ids, curves);
        let closed = if legs.len() == 1 {
            curves[legs[0].stroke].is_closed()
        } else {
            legs[legs.len() - 1]
                .exit(curves)
                .0
                .distance(legs[0].entry(curves).0)
                <= flex.join_tolerance
        };
        let first = *ids.iter().min().unwrap_or(&0);
        out.push((first, r.name.clone(), legs, closed));
    }
    for i in 0..n {
        if !used[i] && curves[i].is_closed() {
            used[i] = true;
            out.push((
                i,
                None,
                vec![Leg {
                    stroke: i,
                    reversed: false,
                }],
                true,
            ));
        }
    }
    let open: Vec<usize> = (0..n).filter(|&i| !used[i]).collect();
    let partner = pair_ends(
        design,
        &open,
        curves,
        flex,
        neon.break_at.as_deref().unwrap_or(&[]),
    );
    for &s in &open {
        if used[s] {
            continue;
        }
        // Walk backwards from s's start to a free end (or around a cycle back to s).
        let (mut cur, mut entry_is_end) = (s, false);
        let mut steps = 0;
        let mut cycle = false;
        while let Some(&(p, p_end)) = partner.get(&(cur, entry_is_end)) {
            steps += 1;
            // Leaving stroke p through its other end backwards.
            if p == s || steps > open.len() {
                cycle = p == s;
                if cycle {
                    // Start the cycle at s itself.
                    cur = s;
                    entry_is_end = false;
                }
                break;
            }
            cur = p;
            entry_is_end = !p_end;
        }
        let mut legs = Vec::new();
        let (mut at, mut enter_end) = (cur, entry_is_end);
        loop {
            if used[at] {
                break;
            }
            used[at] = true;
            legs.push(Leg {
                stroke: at,
                reversed: enter_end,
            });
            match partner.get(&(at, !enter_end)) {
                Some(&(q, q_end)) => {
                    at = q;
                    enter_end = q_end;
                }
                None => break,
            }
        }
        let first = legs.iter().map(|l| l.stroke).min().unwrap_or(s);
        out.push((first, None, legs, cycle));
    }
    out.sort_by_key(|(first, ..)| *first);
    out.into_iter()
        .enumerate()
        .map(|(k, (_, name, legs, closed))| Run {
            name: name.unwrap_or_else(|| format!("run {}", k + 1)),
            legs,
            closed,
        })
        .collect()
}

/// Legs of an explicit run: `ids` in order, each passed in the direction that starts
/// nearest the previous one's exit (the first: the direction whose exit is nearest the
/// second stroke).
fn chain(ids: &[usize], curves: &[DiskBSpline]) -> Vec<Leg> {
    let ends = |i: usize| {
        let (lo, hi) = curves[i].domain();
        (curves[i].center(lo), curves[i].center(hi))
    };
    let mut legs: Vec<Leg> = Vec::with_capacity(ids.len());
    for (k, &i) in ids.iter().enumerate() {
        let (a, b) = ends(i);
        let reversed = match legs.last() {
            Some(prev) => {
                let p = prev.exit(curves).0;
                b.distance(p) < a.distance(p)
            }
            None => match ids.get(k + 1) {
                Some(&j) => {
                    let (c, d) = ends(j);
                    a.distance(c).min(a.distance(d)) < b.distance(c).min(b.distance(d))
                }
                None => false,
            },
        };
        legs.push(Leg {
            stroke: i,
            reversed,
        });
    }
    legs
}

/// Unit tangent pointing into stroke `i` from its end `e`.
fn inward(curves: &[DiskBSpline], (i, e): End) -> DVec2 {
    let c = &curves[i];
    let (lo, hi) = c.domain();
    let d = c.derivs(if e { hi } else { lo }, 1)[1]
        .0
        .normalize_or_zero();
    if e { -d } else { d }
}

/// Ends at most this far apart (relative to the coordinates' size) coincide: their join
/// has no gap, and among such joins the straightest is made first.
const COINCIDE_REL: f64 = 1e-9;

/// The partner of every joined end among the open strokes `open` (module docs). Candidate
/// pairs are ends at most the join tolerance apart whose midpoint is not within the flex
/// width of a `break_at` point; they are taken greedily, each end at most once: first the
/// corners at which loading split a stroke (`NAME#k` end to `NAME#k+1` start, the pen's own
/// path), then coinciding ends before ends with a gap, nearer gaps first, and among equals
/// the smaller turning angle.
fn pair_ends(
    design: &Design,
    open: &[usize],
    curves: &[DiskBSpline],
    flex: &Flex,
    break_at: &[[f64; 2]],
) -> std::collections::HashMap<End, End> {
    let mut ends: Vec<(End, DVec2)> = Vec::with_capacity(2 * open.len());
    for &i in open {
        let (lo, hi) = curves[i].domain();
        ends.push(((i, false), curves[i].center(lo)));
        ends.push(((i, true), curves[i].center(hi)));
    }
    let corner_pair = |a: End, b: End| {
        let name = |i: usize| design.stroke[i].name.as_str();
        design.corners.iter().any(|c| {
            let (x, y) = (c.pieces[0].as_str(), c.pieces[1].as_str());
            (a.1 && !b.1 && name(a.0) == x && name(b.0) == y)
                || (b.1 && !a.1 && name(b.0) == x && name(a.0) == y)
        })
    };
    // Candidate pairs by a sweep in x.
    let mut order: Vec<usize> = (0..ends.len()).collect();
    order.sort_by(|&a, &b| ends[a].1.x.total_cmp(&ends[b].1.x));
    let tol = flex.join_tolerance;
    // (corner first, gap, turn, a, b)
    let mut pairs: Vec<(bool, f64, f64, usize, usize)> = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            let (pa, pb) = (ends[a].1, ends[b].1);
            if pb.x - pa.x > tol {
                break;
            }
            let gap = pa.distance(pb);
            let mid = 0.5 * (pa + pb);
            if gap > tol
                || break_at
                    .iter()
                    .any(|p| mid.distance(DVec2::from(*p)) <= flex.width)
            {
                continue;
            }
            // Arriving along −inward(a), leaving along inward(b): the turn between them.
            let da = -inward(curves, ends[a].0);
            let db = inward(curves, ends[b].0);
            let turn = cross(da, db).atan2(da.dot(db)).abs();
            let coincide = gap <= COINCIDE_REL * (1.0 + pa.length());
            let (x, y) = (a.min(b), a.max(b));
            let corner = corner_pair(ends[x].0, ends[y].0);
            pairs.push((!corner, if coincide { 0.0 } else { gap }, turn, x, y));
        }
    }
    pairs.sort_by(|p, q| {
        (p.0.cmp(&q.0))
            .then(p.1.total_cmp(&q.1))
            .then(p.2.total_cmp(&q.2))
            .then(p.3.cmp(&q.3))
            .then(p.4.cmp(&q.4))
    });
    let mut partner = std::collections::HashMap::new();
    for (_, _, _, a, b) in pairs {
        let (ea, eb) = (ends[a].0, ends[b].0);
        if partner.contains_key(&ea) || partner.contains_key(&eb) {
            continue;
        }
        partner.insert(ea, eb);
        partner.insert(eb, ea);
    }
    partner
}

/// Arc length ∫‖q′(t)‖dt of the spine of `c` over its whole domain, by adaptive
/// Gauss–Legendre quadrature ([`crate::geom::quad::integrate`]) on every knot span (the
/// integrand is smooth inside a span), to the absolute error `tol` in total (shared among
/// the spans by their parameter length).
pub fn spine_length(c: &DiskBSpline, tol: f64) -> f64 {
    let (lo, hi) = c.domain();
    let speed = |t: f64| c.derivs(t, 1)[1].0.length();
    c.breakpoints()
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| {
            let share = tol * (w[1] - w[0]) / (hi - lo);
            crate::geom::quad::integrate(&speed, w[0], w[1], share)
        })
        .sum()
}

/// Radius of curvature ρ = ‖q′‖³ / |q′ × q″| of the spine at `t` (∞ on a straight
/// stretch, 0 where q′ = 0).
pub fn bend_radius(c: &DiskBSpline, t: f64) -> f64 {
    let d = c.derivs(t, 2);
    let (q1, q2) = (d[1].0, d[2].0);
    let s = q1.length();
    if s <= f64::MIN_POSITIVE {
        return 0.0;
    }
    let k = cross(q1, q2).abs();
    if k == 0.0 {
        f64::INFINITY
    } else {
        s * s * s / k
    }
}

/// The smallest radius of curvature of the spine on the knot span [a, b] and where it is:
/// κ sampled at [`BEND_SAMPLES`] + 1 points (the ends moved inside by 10⁻⁹ of the span, so
/// that each span sees its own one-sided curvature at a knot), then every sampled local
/// maximum of κ refined by golden-section search on its two neighbouring intervals to a
/// parameter interval of `param_tol`·(b − a). Returns (ρ, t).
pub fn span_min_radius(c: &DiskBSpline, a: f64, b: f64, param_tol: f64) -> (f64, f64) {
    let inset = 1e-9 * (b - a);
    let (a0, b0) = (a + inset, b - inset);
    let ts: Vec<f64> = (0..=BEND_SAMPLES)
        .map(|k| a0 + (b0 - a0) * k as f64 / BEND_SAMPLES as f64)
        .collect();
    let kappa = |t: f64| {
        let r = bend_radius(c, t);
        if r == 0.0 { f64::INFINITY } else { 1.0 / r }
    };
    let ks: Vec<f64> = ts.iter().map(|&t| kappa(t)).collect();
    let mut best = (f64::INFINITY, a0);
    for k in 0..ts.len() {
        let left = if k > 0 { ks[k - 1] } else { f64::NEG_INFINITY };
        let right = ks.get(k + 1).copied().unwrap_or(f64::NEG_INFINITY);
        if !(ks[k] >= left && ks[k] >= right) {
            continue;
        }
        let lo = ts[k.saturating_sub(1)];
        let hi = ts[(k + 1).min(ts.len() - 1)];
        let t = golden_max(&kappa, lo, hi, param_tol * (b - a));
        let (t, kv) = if kappa(t) >= ks[k] {
            (t, kappa(t))
        } else {
            (ts[k], ks[k])
        };
        let r = if kv.is_infinite() { 0.0 } else { 1.0 / kv };
        if r < best.0 {
            best = (r, t);
        }
    }
    best
}

/// Golden-section search for a maximum of `f` on [a, b] to an interval of `tol`
/// (Kiefer 1953): the interval shrinks by 1/φ per step keeping the larger inner value.
fn golden_max(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> f64 {
    const INV_PHI: f64 = 0.618_033_988_749_894_8;
    let mut c = b - INV_PHI * (b - a);
    let mut d = a + INV_PHI * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    // Each step shrinks the interval by 1/φ; 200 steps reach any tol from any interval.
    for _ in 0..200 {
        if b - a <= tol.max(0.0) {
            break;
        }
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - INV_PHI * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + INV_PHI * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

/// Where along a run something is: the stroke, its parameter and the point (design
/// coordinates, before placement).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunPlace {
    /// The stroke's name.
    pub stroke: String,
    /// Parameter on the stroke.
    pub t: f64,
    /// x of the point.
    pub x: f64,
    /// y of the point.
    pub y: f64,
}

/// A stretch of a run bent tighter than the flex takes (or a corner: radius 0).
#[derive(Clone, Debug, PartialEq)]
pub struct TightBend {
    /// The run's name.
    pub run: String,
    /// Smallest radius on the stretch (design units).
    pub radius: f64,
    /// Where it is.
    pub at: RunPlace,
    /// The bend is a join of two strokes whose tangents break.
    pub join: bool,
}

/// Two runs whose spines come closer than the channel width.
#[derive(Clone, Debug, PartialEq)]
pub struct CloseRuns {
    /// Names of the two runs.
    pub runs: [String; 2],
    /// Smallest distance between their spines (design units).
    pub distance: f64,
    /// Midpoint of the closest points.
    pub at: [f64; 2],
}

/// One run in the bill of materials.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunBom {
    /// The run's name.
    pub name: String,
    /// Its strokes, in order.
    pub strokes: Vec<String>,
    /// The run returns to its start.
    pub closed: bool,
    /// Flex length: the spine lengths (plus any bridged gap), mm.
    pub length_mm: f64,
    /// The length rounded up to the cut unit, mm.
    pub cut_length_mm: f64,
    /// Straight gaps between joined strokes that the flex bridges (in `length_mm`), mm.
    pub bridged_mm: f64,
    /// The smallest bend radius along the run, mm (0 at a corner).
    pub min_bend_radius_mm: f64,
    /// Where that bend is.
    pub at: RunPlace,
    /// With `round_bends`: the bends rounded to the flex's minimum radius.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rounded_bends: Option<usize>,
    /// With `round_bends`: the largest distance between a rounded stretch and the drawn
    /// spine, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rounding_deviation_mm: Option<f64>,
}

/// A run shorter than `[neon] min_run_length`: a mark (channel cut, no flex, no holes).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MarkBom {
    /// The run's name.
    pub name: String,
    /// Its strokes, in order.
    pub strokes: Vec<String>,
    /// Its spine length (with bridged gaps), mm.
    pub length_mm: f64,
}

/// A warning of the neon check.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NeonWarning {
    /// `bend` (tighter than the flex) or `merge` (channels of two runs run into one).
    pub kind: String,
    /// What and where, in words.
    pub message: String,
    /// The place (design coordinates, before placement).
    pub at: [f64; 2],
}

/// The flex's sizes in the summary, mm.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FlexSummary {
    /// Flex width.
    pub width_mm: f64,
    /// Flex height.
    pub height_mm: f64,
    /// Minimum bend radius.
    pub min_bend_radius_mm: f64,
    /// Cut unit.
    pub cut_unit_mm: f64,
}

/// The neon bill of materials of a build (`build --json`: `neon`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NeonBom {
    /// The flex.
    pub flex: FlexSummary,
    /// Every run.
    pub runs: Vec<RunBom>,
    /// Σ of the runs' lengths, mm.
    pub total_length_mm: f64,
    /// Σ of the runs' cut lengths, mm (what to order).
    pub total_cut_length_mm: f64,
    /// Wire holes drilled by the build's holes operations.
    pub holes: usize,
    /// The scale the design was built at (1 unscaled).
    pub scale: f64,
    /// Runs shorter than `min_run_length`: marks, not flex (not in the totals).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub marks: Vec<MarkBom>,
    /// Bends below the flex minimum, channels that merge, runs shorter than the cut unit
    /// and bends `round_bends` could not round ([`NeonBom::judge`]).
    pub warnings: Vec<NeonWarning>,
    /// The `round` warnings of [`round_bends`] (kept across [`NeonBom::judge`]).
    #[serde(skip)]
    pub round_warnings: Vec<NeonWarning>,
    /// Every stretch bent tighter than the flex (design units).
    #[serde(skip)]
    pub tight: Vec<TightBend>,
    /// The runs' spines, flattened (design units), for the merge test of [`NeonBom::judge`].
    #[serde(skip)]
    pub spines: Vec<Vec<DVec2>>,
    /// Per run and spine point, the index (in the run's `strokes`) of the stroke it is on.
    #[serde(skip)]
    pub spine_legs: Vec<Vec<usize>>,
    /// The flex minimum radius and the channel width, design units.
    #[serde(skip)]
    pub limits: (f64, f64),
    /// Millimetres per design unit.
    #[serde(skip)]
    pub mm: f64,
}

fn tight_bend(run: &Run, radius: f64, at: RunPlace, join: bool) -> TightBend {
    TightBend {
        run: run.name.clone(),
        radius,
        at,
        join,
    }
}

fn place(design: &Design, c: &DiskBSpline, stroke: usize, t: f64) -> RunPlace {
    let p = c.center(t);
    RunPlace {
        stroke: design.stroke[stroke].name.clone(),
        t,
        x: p.x,
        y: p.y,
    }
}

/// The bill of materials of `runs` (module docs) with the flex `flex`; `tol` is the
/// absolute length tolerance per stroke (design units); `holes` the wire holes drilled.
pub fn bom(
    design: &Design,
    curves: &[DiskBSpline],
    runs: &[Run],
    flex: &Flex,
    tol: f64,
    holes: usize,
) -> NeonBom {
    let mm = design.units.mm_per_unit();
    let break_cos = TANGENT_BREAK_DEG.to_radians().cos();
    let mut out_runs = Vec::new();
    let mut tight = Vec::new();
    for run in runs {
        let mut length = 0.0;
        let mut bridged = 0.0;
        let mut best: Option<(f64, RunPlace)> = None;
        let mut lower = |r: f64, at: &dyn Fn() -> RunPlace| {
            if best.as_ref().is_none_or(|(b, _)| r < *b) {
                best = Some((r, at()));
            }
        };
        let n = run.legs.len();
        for (k, leg) in run.legs.iter().enumerate() {
            let c = &curves[leg.stroke];
            length += spine_length(c, tol);
            // Spans in the run's direction; a stretch of consecutive tight spans is one
            // tight bend (its smallest radius).
            let mut spans: Vec<(f64, f64)> = c
                .breakpoints()
                .windows(2)
                .filter(|w| w[1] > w[0])
                .map(|w| span_min_radius(c, w[0], w[1], BEND_PARAM_TOL))
                .collect();
            if leg.reversed {
                spans.reverse();
            }
            let mut stretch: Option<(f64, f64)> = None;
            for &(r, t) in &spans {
                lower(r, &|| place(design, c, leg.stroke, t));
                if r < flex.min_bend_radius {
                    if stretch.is_none_or(|(b, _)| r < b) {
                        stretch = Some((r, t));
                    }
                } else if let Some((sr, st)) = stretch.take() {
                    tight.push(tight_bend(run, sr, place(design, c, leg.stroke, st), false));
                }
            }
            if let Some((sr, st)) = stretch {
                tight.push(tight_bend(run, sr, place(design, c, leg.stroke, st), false));
            }
            // The join into the next leg (and the seam of a closed chain).
            let next = if k + 1 < n {
                Some(&run.legs[k + 1])
            } else if run.closed && n > 1 {
                Some(&run.legs[0])
            } else {
                None
            };
            if let Some(nx) = next {
                let (p, t_out) = leg.exit(curves);
                let (q, t_in) = nx.entry(curves);
                let gap = p.distance(q);
                let u = leg.direction(curves, t_out);
                let v = nx.direction(curves, t_in);
                // A gap is bridged straight: the flex turns from u to the bridge and from
                // the bridge to v.
                let broken = if gap <= COINCIDE_REL * (1.0 + p.length()) {
                    u.dot(v) < break_cos
                } else {
                    bridged += gap;
                    let g = (q - p) / gap;
                    u.dot(g) < break_cos || g.dot(v) < break_cos
                };
                if broken {
                    let at = || place(design, &curves[nx.stroke], nx.stroke, t_in);
                    lower(0.0, &at);
                    tight.push(tight_bend(run, 0.0, at(), true));
                }
            }
        }
        // A run without any bend (all straight) reports its start, radius ∞.
        let (min_r, at) = best.unwrap_or_else(|| {
            let l = run.legs[0];
            let t = l.entry(curves).1;
            (f64::INFINITY, place(design, &curves[l.stroke], l.stroke, t))
        });
        let length = length + bridged;
        let units = (length / flex.cut_unit * (1.0 - 1e-12)).ceil().max(1.0);
        out_runs.push(RunBom {
            name: run.name.clone(),
            strokes: run
                .legs
                .iter()
                .map(|l| design.stroke[l.stroke].name.clone())
                .collect(),
            closed: run.closed,
            length_mm: length * mm,
            cut_length_mm: units * flex.cut_unit * mm,
            bridged_mm: bridged * mm,
            min_bend_radius_mm: min_r * mm,
            at,
            rounded_bends: None,
            rounding_deviation_mm: None,
        });
    }
    let width = channel_width(design, flex);
    let (spines, spine_legs) = run_polylines(curves, runs, SPINE_FLATTEN_OF_WIDTH * flex.width);
    let total_length_mm = out_runs.iter().map(|r| r.length_mm).sum();
    let total_cut_length_mm = out_runs.iter().map(|r| r.cut_length_mm).sum();
    let mut b = NeonBom {
        flex: FlexSummary {
            width_mm: flex.width * mm,
            height_mm: flex.height * mm,
            min_bend_radius_mm: flex.min_bend_radius * mm,
            cut_unit_mm: flex.cut_unit * mm,
        },
        runs: out_runs,
        total_length_mm,
        total_cut_length_mm,
        holes,
        scale: 1.0,
        marks: Vec::new(),
        warnings: Vec::new(),
        round_warnings: Vec::new(),
        tight,
        spines,
        spine_legs,
        limits: (flex.min_bend_radius, width),
        mm,
    };
    b.judge(1.0);
    b
}

/// The width of the design's channels: the first channel operation's `width`, else the flex
/// width plus [`CHANNEL_CLEARANCE_MM`].
pub fn channel_width(design: &Design, flex: &Flex) -> f64 {
    design
        .operation
        .iter()
        .find(|o| o.kind == OperationKind::Channel)
        .and_then(|o| o.width)
        .unwrap_or(flex.width + CHANNEL_CLEARANCE_MM / design.units.mm_per_unit())
}

/// The runs' spines flattened within `tol`, one polyline per run (its legs in order), and
/// per point the index of its leg in the run.
fn run_polylines(
    curves: &[DiskBSpline],
    runs: &[Run],
    tol: f64,
) -> (Vec<Vec<DVec2>>, Vec<Vec<usize>>) {
    runs.iter()
        .map(|r| {
            let mut pts = Vec::new();
            let mut legs = Vec::new();
            for (k, l) in r.legs.iter().enumerate() {
                let mut p = crate::dbsc::flatten::flatten_spine(&curves[l.stroke], tol);
                if l.reversed {
                    p.reverse();
                }
                legs.extend(std::iter::repeat_n(k, p.len()));
                pts.extend(p);
            }
            (pts, legs)
        })
        .unzip()
}

/// Smallest island of board that the counter test reports, as the radius of a disk of
/// the island's area over the channel width: smaller islands between channels are slivers
/// the router clears anyway, not a letter's counter.
pub const MIN_ISLAND_OF_WIDTH: f64 = 0.25;

/// Flattening tolerance of the channel regions of the counter test, as a fraction of the
/// channel width (65 µm for a 6.5 mm channel): far below an island's size.
pub const ISLAND_FLATTEN_OF_WIDTH: f64 = 1e-2;

/// The islands of board that the channels enclose at the design's size and fill at the
/// built size `scale` (a letter's counter closing up): one point inside each (the mean of
/// its ring's vertices). The channels at the built size are the spines `spines` (closed
/// where `closed`) swept by a disk of radius width/2; at the design's size, scaled to the
/// built size, by width·scale/2, since s·(S/s ⊕ D_{w/2}) = S ⊕ D_{s·w/2}. The built
/// channels hold the scaled design ones, so each hole of theirs lies in one hole H of
/// the design's; an H that holds none (of area at least π(MIN_ISLAND_OF_WIDTH·w·s)², as
/// H itself: smaller holes are slivers of the union) is filled.
fn filled_islands(spines: &[Vec<DVec2>], closed: &[bool], width: f64, scale: f64) -> Vec<DVec2> {
    use crate::geom::interop::flatten_pline;
    use crate::toolpath::ops::swept_region;
    use crate::toolpath::region::Region;
    use cavalier_contours::polyline::PlineSource;
    let tol = ISLAND_FLATTEN_OF_WIDTH * width;
    let channels = |half: f64| {
        let parts: Vec<Region> = spines
            .iter()
            .zip(closed)
            .map(|(p, &c)| swept_region(p, c, half, tol))
            .collect();
        Region::union(&parts, tol)
    };
    let (then, now) = (channels(width * scale / 2.0), channels(width / 2.0));
    let min_area = std::f64::consts::PI * (MIN_ISLAND_OF_WIDTH * width * scale).powi(2);
    let holes_now: Vec<DVec2> = now
        .contours
        .iter()
        .filter(|c| c.area() < -min_area)
        .filter_map(|c| c.iter_vertexes().next().map(|v| DVec2::new(v.x, v.y)))
        .collect();
    then.contours
        .iter()
        .filter(|h| h.area() < -min_area)
        .filter(|h| {
            !holes_now.iter().any(|p| {
                h.winding_number(cavalier_contours::core::math::Vector2::new(p.x, p.y)) != 0
            })
        })
        .map(|h| {
            let pts = flatten_pline(h, tol);
            pts.iter().copied().sum::<DVec2>() / pts.len().max(1) as f64
        })
        .collect()
}

/// Pairs of runs (polylines `polys`, names `names`) with two segments whose distance d lies
/// in [lo, hi): per pair the smallest such d and the midpoint of its closest points. Pairs
/// whose bounding boxes are `hi` apart are skipped.
fn close_runs(polys: &[Vec<DVec2>], names: &[String], lo: f64, hi: f64) -> Vec<CloseRuns> {
    let boxes: Vec<(DVec2, DVec2)> = polys
        .iter()
        .map(|p| {
            p.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), &q| (lo.min(q), hi.max(q)),
            )
        })
        .collect();
    let mut out = Vec::new();
    for i in 0..polys.len() {
        for j in i + 1..polys.len() {
            let (a, b) = (boxes[i], boxes[j]);
            let gap = (b.0 - a.1).max(a.0 - b.1).max(DVec2::ZERO);
            if gap.length() >= hi {
                continue;
            }
            let mut best = (f64::INFINITY, DVec2::ZERO);
            for s in polys[i].windows(2) {
                for u in polys[j].windows(2) {
                    let (d, m) = segment_distance(s[0], s[1], u[0], u[1]);
                    if d >= lo && d < best.0 {
                        best = (d, m);
                    }
                }
            }
            if best.0 < hi {
                out.push(CloseRuns {
                    runs: [names[i].clone(), names[j].clone()],
                    distance: best.0,
                    at: best.1.to_array(),
                });
            }
        }
    }
    out
}

/// Distance between segments ab and cd and the midpoint of the closest points (0 and the
/// crossing point when they cross).
fn segment_distance(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> (f64, DVec2) {
    let foot = |p: DVec2, s: DVec2, e: DVec2| {
        let v = e - s;
        let l2 = v.length_squared();
        let t = if l2 > 0.0 {
            ((p - s).dot(v) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        s + v * t
    };
    let (r, s) = (b - a, d - c);
    let den = cross(r, s);
    if den != 0.0 {
        let t = cross(c - a, s) / den;
        let u = cross(c - a, r) / den;
        if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
            return (0.0, a + r * t);
        }
    }
    [
        (a, foot(a, c, d)),
        (b, foot(b, c, d)),
        (c, foot(c, a, b)),
        (d, foot(d, a, b)),
    ]
    .into_iter()
    .map(|(p, q)| (p.distance(q), 0.5 * (p + q)))
    .min_by(|x, y| x.0.total_cmp(&y.0))
    .unwrap_or((f64::INFINITY, a))
}

impl NeonBom {
    /// Sets the warnings for a design built at `scale` (1: as drawn): every tight bend
    /// (noting those that only the scaling made too tight, ρ/scale ≥ the minimum), and, when
    /// scaled, every pair of runs closer than the channel width that was not at the
    /// design's own size (distance/scale ≥ width): their channels merge.
    pub fn judge(&mut self, scale: f64) {
        self.scale = scale;
        let (min_r, width) = self.limits;
        let mm = self.mm;
        let mut w = Vec::new();
        for b in &self.tight {
            let what = if b.join {
                format!(
                    "a corner where the strokes join at \"{}\" (radius 0)",
                    b.at.stroke
                )
            } else {
                format!(
                    "bend radius {:.2} mm on stroke \"{}\" at t = {:.4}",
                    b.radius * mm,
                    b.at.stroke,
                    b.at.t
                )
            };
            let by_scale = scale != 1.0 && b.radius > 0.0 && b.radius / scale >= min_r;
            w.push(NeonWarning {
                kind: "bend".into(),
                message: format!(
                    "{}: {what}, at ({:.2}, {:.2}), is tighter than the flex's minimum {:.2} \
                     mm{}",
                    b.run,
                    b.at.x,
                    b.at.y,
                    min_r * mm,
                    if by_scale {
                        format!(
                            " since the design was scaled by {scale:.4} (it is {:.2} mm at \
                             the design's size)",
                            b.radius / scale * mm
                        )
                    } else {
                        String::new()
                    }
                ),
                at: [b.at.x, b.at.y],
            });
        }
        if scale < 1.0 {
            // A place where two runs are closer than the channel width now but were not at
            // the design's size: distance d with d < width ≤ d/scale.
            let names: Vec<String> = self.runs.iter().map(|r| r.name.clone()).collect();
            for c in close_runs(&self.spines, &names, width * scale, width) {
                {
                    w.push(NeonWarning {
                        kind: "merge".into(),
                        message: format!(
                            "{} and {}: their channels merge at ({:.2}, {:.2}): the spines \
                             are {:.2} mm apart, less than the channel width {:.2} mm, since \
                             the design was scaled by {scale:.4} ({:.2} mm apart at the \
                             design's size)",
                            c.runs[0],
                            c.runs[1],
                            c.at[0],
                            c.at[1],
                            c.distance * mm,
                            width * mm,
                            c.distance / scale * mm
                        ),
                        at: c.at,
                    });
                }
            }
            // Islands of board inside the channels (a letter's counter) that the scaled
            // channels fill.
            let closed: Vec<bool> = self.runs.iter().map(|r| r.closed).collect();
            for p in filled_islands(&self.spines, &closed, width, scale) {
                let near = self.nearest_stroke(p);
                w.push(NeonWarning {
                    kind: "merge".into(),
                    message: format!(
                        "{near}: the island of board at ({:.2}, {:.2}) that its channel \
                         goes around (a letter's counter) is cut away: the channel width \
                         {:.2} mm stays while the design was scaled by {scale:.4}",
                        p.x,
                        p.y,
                        width * mm
                    ),
                    at: p.to_array(),
                });
            }
        }
        // A run shorter than the cut unit: no flex is cut that short.
        let cut = self.flex.cut_unit_mm;
        for r in self.runs.iter().filter(|r| r.length_mm < cut) {
            let start = [r.at.x, r.at.y];
            w.push(NeonWarning {
                kind: "short".into(),
                message: format!(
                    "{} (strokes {}): {:.2} mm of flex is shorter than the cut unit {:.2} mm; \
                     set [neon] min_run_length to make such runs marks (channel cut, no \
                     flex, no wire holes)",
                    r.name,
                    r.strokes
                        .iter()
                        .map(|s| format!("\"{s}\""))
                        .collect::<Vec<_>>()
                        .join(", "),
                    r.length_mm,
                    cut
                ),
                at: start,
            });
        }
        w.extend(self.round_warnings.iter().cloned());
        self.warnings = w;
    }

    /// Records what [`round_bends`] did: per run the bends rounded and the largest
    /// deviation (design units), and its warnings.
    pub fn set_rounding(&mut self, reports: &[RoundReport], warnings: Vec<NeonWarning>) {
        for r in &mut self.runs {
            let rep = reports.iter().find(|x| x.run == r.name);
            r.rounded_bends = Some(rep.map_or(0, |x| x.rounded));
            r.rounding_deviation_mm = Some(rep.map_or(0.0, |x| x.deviation * self.mm));
        }
        self.round_warnings = warnings;
        self.judge(self.scale);
    }

    /// Adds the marks (runs shorter than `min_run_length`, see [`split_marks`]) with their
    /// lengths (design units).
    pub fn set_marks(&mut self, design: &Design, marks: &[(Run, f64)]) {
        self.marks = marks
            .iter()
            .map(|(run, len)| MarkBom {
                name: run.name.clone(),
                strokes: run
                    .legs
                    .iter()
                    .map(|l| design.stroke[l.stroke].name.clone())
                    .collect(),
                length_mm: len * self.mm,
            })
            .collect();
    }

    /// The run and stroke whose spine comes nearest to `p`, as `run N, stroke "S"`.
    fn nearest_stroke(&self, p: DVec2) -> String {
        let mut best = (f64::INFINITY, 0, 0);
        for (k, pts) in self.spines.iter().enumerate() {
            for (i, q) in pts.iter().enumerate() {
                let d = q.distance(p);
                if d < best.0 {
                    best = (d, k, self.spine_legs[k][i]);
                }
            }
        }
        match self.runs.get(best.1) {
            Some(r) => format!("{}, stroke \"{}\"", r.name, r.strokes[best.2]),
            None => "the sign".into(),
        }
    }

    /// The bill of materials as CSV: a header, one row per run (strokes joined by `;`),
    /// and a total row. Fields with a comma, quote or line break are quoted (RFC 4180).
    pub fn to_csv(&self) -> String {
        fn field(s: &str) -> String {
            if s.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", s.replace('"', "\"\""))
            } else {
                s.to_string()
            }
        }
        let mut out = String::from(
            "run,strokes,closed,length_mm,cut_length_mm,min_bend_radius_mm,at_stroke,at_x,at_y\n",
        );
        for r in &self.runs {
            out.push_str(&format!(
                "{},{},{},{:.2},{:.2},{},{},{:.3},{:.3}\n",
                field(&r.name),
                field(&r.strokes.join(";")),
                r.closed,
                r.length_mm,
                r.cut_length_mm,
                if r.min_bend_radius_mm.is_finite() {
                    format!("{:.3}", r.min_bend_radius_mm)
                } else {
                    "inf".into()
                },
                field(&r.at.stroke),
                r.at.x,
                r.at.y
            ));
        }
        out.push_str(&format!(
            "total,,,{:.2},{:.2},,,,\n",
            self.total_length_mm, self.total_cut_length_mm
        ));
        out
    }
}

/// Length of a run (design units): its strokes' spine lengths ([`spine_length`], absolute
/// tolerance `tol` each) plus the straight gaps bridged between consecutive strokes (and
/// from the last back to the first of a closed chain), as in [`bom`].
pub fn run_length(run: &Run, curves: &[DiskBSpline], tol: f64) -> f64 {
    let n = run.legs.len();
    let mut len: f64 = run
        .legs
        .iter()
        .map(|l| spine_length(&curves[l.stroke], tol))
        .sum();
    for k in 0..n {
        let next = if k + 1 < n {
            run.legs[k + 1]
        } else if run.closed && n > 1 {
            run.legs[0]
        } else {
            continue;
        };
        let p = run.legs[k].exit(curves).0;
        let gap = p.distance(next.entry(curves).0);
        if gap > COINCIDE_REL * (1.0 + p.length()) {
            len += gap;
        }
    }
    len
}

/// The runs split by `[neon] min_run_length` (unset: none is a mark): (flex runs, marks
/// with their lengths, design units); `tol` is the length tolerance per stroke.
pub fn split_marks(
    design: &Design,
    curves: &[DiskBSpline],
    runs: Vec<Run>,
    tol: f64,
) -> (Vec<Run>, Vec<(Run, f64)>) {
    let Some(min) = design.neon.as_ref().and_then(|n| n.min_run_length) else {
        return (runs, Vec::new());
    };
    let mut flex = Vec::new();
    let mut marks = Vec::new();
    for r in runs {
        let len = run_length(&r, curves, tol);
        if len < min {
            marks.push((r, len));
        } else {
            flex.push(r);
        }
    }
    (flex, marks)
}

/// Where the holes of a holes operation go with a `[neon]` table: at the start and end of
/// every open run (`at`: both, start only, end only; a closed run: one hole at its seam),
/// when the stroke at that end is among `selected` stroke indices. Each point comes with
/// the name of its stroke; coincident points are drilled once.
pub fn run_hole_points(
    design: &Design,
    curves: &[DiskBSpline],
    runs: &[Run],
    at: HoleAt,
    selected: &[usize],
) -> Vec<(DVec2, String)> {
    let mut out: Vec<(DVec2, String)> = Vec::new();
    for run in runs {
        let first = run.legs[0].stroke;
        let last = run.legs[run.legs.len() - 1].stroke;
        let mut pts = Vec::new();
        if run.closed {
            pts.push((run.start(curves), first));
        } else {
            if matches!(at, HoleAt::Ends | HoleAt::Start) {
                pts.push((run.start(curves), first));
            }
            if matches!(at, HoleAt::Ends | HoleAt::End) {
                pts.push((run.end(curves), last));
            }
        }
        for (p, s) in pts {
            let tol = 1e-9 * (1.0 + p.length());
            if selected.contains(&s) && !out.iter().any(|(q, _)| q.distance(p) <= tol) {
                out.push((p, design.stroke[s].name.clone()));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring spine of radius R with channels of width w at scale s: the counter (a disk
    /// of radius s·(R − w/2) at the design's size, scaled) fills when R ≤ w/2.
    #[test]
    fn ring_counter_fills_when_the_ring_is_narrower_than_the_channel() {
        let ring = |r: f64| -> Vec<DVec2> {
            (0..720)
                .map(|k| DVec2::from_angle(std::f64::consts::TAU * k as f64 / 720.0) * r)
                .collect()
        };
        let (w, s) = (10.0, 0.2);
        assert_eq!(filled_islands(&[ring(4.0)], &[true], w, s).len(), 1);
        assert!(filled_islands(&[ring(6.0)], &[true], w, s).is_empty());
    }
}
