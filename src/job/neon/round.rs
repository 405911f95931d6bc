//! Rounding bends tighter than the flex (`[neon] round_bends = true`).
//!
//! Before the channel is made, every stretch of a run's spine bent tighter than the flex's
//! minimum radius R (a corner, or a curve of radius below R) is replaced by the circular
//! arc of radius R tangent to the spine before and after it: the rolling-ball fillet. Its
//! centre c is where the spine's offset curves at distance R on the inner side of the bend,
//! o(t) = q(t) + s·R·n(t) (n the left unit normal, s = ±1 the bend's turning sign), before
//! and after the stretch meet, o(tᵢ) = o(tⱼ) (the self-intersection of the offset's
//! swallowtail; Farouki & Neff 1990, "Analytic properties of plane offset curves", §4).
//! The crossing is found on the sampled offsets and refined by Newton's method on
//! F(tᵢ, tⱼ) = o(tᵢ) − o(tⱼ); the spine is then q(t) up to tᵢ, the arc from q(tᵢ) to
//! q(tⱼ) about c, and q(t) from tⱼ on: tangent-continuous (G1) at both ends, since at a
//! tangency the arc's tangent is the spine's. The arc is cubic Bézier pieces of at most
//! [`ARC_PIECE_DEG`] each with handles k = 4/3·tan(θ/4) (Dokken et al. 1990), the kept parts
//! are the strokes' own Bézier pieces (knot insertion, P&T A5.1), raised to a common degree
//! (P&T eq. 5.36); the stroke becomes one B-spline with interior knots of multiplicity p. A
//! fillet that reaches across strokes of the run gives each stroke its share of the arc, so
//! the run stays one piece. Where the spine before or after a stretch ends (the run's end,
//! or another bend turning the other way) before the offsets meet, the stretch is too
//! short for R: it stays as drawn and a `round` warning says where.

use super::{BEND_PARAM_TOL, Leg, NeonWarning, Run, TANGENT_BREAK_DEG, bend_radius, runs};
use crate::dbsc::DiskBSpline;
use crate::design::Design;
use crate::design::neon::Flex;
use crate::geom::{DVec2, cross, perp};
use crate::spline::BSpline;
use glam::DVec3;

/// Spine samples per knot span when looking for tight stretches and fillet centres.
pub const ROUND_SAMPLES: usize = 64;

/// A sample is tight when its bend radius is below R·(1 + this): the fillet then touches
/// the spine where it is at least that much straighter than the flex's minimum, so the
/// kept spine next to the arc stays within the flex's limit between samples.
pub const ROUND_MARGIN: f64 = 0.02;

/// Largest angle of one cubic Bézier piece of a fillet arc (degrees): its radius of
/// curvature is then within 10⁻⁴ of R (the error of the 4/3·tan(θ/4) handles grows as θ⁴).
pub const ARC_PIECE_DEG: f64 = 15.0;

/// Fillet arcs are drawn with the radius R·(1 + this): the cubic pieces' radius of
/// curvature is within 10⁻⁵ of the arc's, so the rounded spine's stays at least R.
pub const ARC_RADIUS_MARGIN: f64 = 1e-4;

/// Newton iterations for the fillet's tangency parameters.
const NEWTON_STEPS: usize = 40;

/// Residual at which the Newton search for where two offsets of a bend cross stops, as a
/// fraction of the flattening tolerance: a millionth, far below what the arc placed there
/// can show.
const NEWTON_OF_TOL: f64 = 1e-6;

/// Step of the central differences of that Newton search, as a fraction of the knot span:
/// 10⁻⁷, about the cube root of the double's precision (the step that balances truncation
/// against round-off of a central difference).
const DIFF_STEP_OF_SPAN: f64 = 1e-7;

/// Length below which a piece of a rounded spine is degenerate and dropped, as a fraction
/// of the size of the spine's coordinates: 10⁻¹², a few units of round-off.
const DEGENERATE_OF_SCALE: f64 = 1e-12;

/// Bends rounded on one run and how far the rounded spine is from the drawn one.
#[derive(Clone, Debug, PartialEq)]
pub struct RoundReport {
    /// The run's name.
    pub run: String,
    /// Tight stretches replaced by arcs.
    pub rounded: usize,
    /// Largest distance between a replaced stretch and its arc (either way), design units.
    pub deviation: f64,
}

/// The design with its tight bends rounded, and what was done.
#[derive(Clone, Debug)]
pub struct Rounded {
    /// The design whose strokes follow the rounded spines.
    pub design: Design,
    /// Per run (of the drawn design, in order).
    pub reports: Vec<RoundReport>,
    /// A `round` warning for every stretch that could not be rounded.
    pub warnings: Vec<NeonWarning>,
}

/// One spine sample of a run: on leg `leg` at parameter `t`, point `p`, unit tangent `u`
/// in the run's direction.
#[derive(Clone, Copy, Debug)]
struct Sample {
    leg: usize,
    t: f64,
    p: DVec2,
    u: DVec2,
    tight: bool,
}

/// A piece of a leg's new spine, in the run's direction.
enum Piece {
    /// The stroke's own spine from parameter .0 to .1 (decreasing on a reversed leg).
    Keep(f64, f64),
    /// Cubic Bézier pieces (x, y, r) of a fillet arc.
    Arc(Vec<[DVec3; 4]>),
}

/// A fillet found on a run: from (leg, t) to (leg, t) about `c`.
struct Fillet {
    from: (usize, f64),
    to: (usize, f64),
    c: DVec2,
    turn: f64,
}

/// The design with every bend of every run tighter than the flex's minimum radius rounded
/// (module docs); `tol` is the build tolerance (design units), the Newton tolerance is
/// 10⁻⁶ of it. Strokes without a tight bend are unchanged.
pub fn round_bends(
    design: &Design,
    flex: &Flex,
    tol: f64,
) -> Result<Rounded, crate::design::DesignError> {
    let curves = design.strokes()?;
    let runs = runs(design, &curves, flex);
    let r = flex.min_bend_radius * (1.0 + ARC_RADIUS_MARGIN);
    let mm = design.units.mm_per_unit();
    let mut out = design.clone();
    let mut reports = Vec::new();
    let mut warnings = Vec::new();
    let mut changed = vec![false; curves.len()];
    for run in &runs {
        let samples = run_samples(run, &curves, r);
        let stretches = tight_stretches(&samples);
        let mut fillets: Vec<Fillet> = Vec::new();
        let mut report = RoundReport {
            run: run.name.clone(),
            rounded: 0,
            deviation: 0.0,
        };
        let mut lo = 0;
        let mut k = 0;
        while k < stretches.len() {
            let (a, b, s) = stretches[k];
            // The after side may run through later stretches turning the same way, not
            // through one turning the other way.
            let hi = stretches[k + 1..]
                .iter()
                .find(|x| x.2 != s)
                .map_or(samples.len() - 1, |x| x.0);
            let attrs = run.legs[samples[a].leg..=samples[b].leg]
                .iter()
                .any(|l| !design.stroke[l.stroke].attributes.is_empty());
            let found = if attrs || a == 0 || b + 1 >= samples.len() {
                None
            } else {
                fillet(&samples, run, &curves, (lo, a, b, hi), s, r, tol)
            };
            let sa = samples[(a + b) / 2];
            let Some((f, j_end)) = found else {
                let stroke = &design.stroke[run.legs[sa.leg].stroke].name;
                warnings.push(NeonWarning {
                    kind: "round".into(),
                    message: format!(
                        "{}: the bend at ({:.2}, {:.2}) on stroke \"{stroke}\" was not rounded \
                         to the flex's minimum radius {:.2} mm: {}; it stays as drawn",
                        run.name,
                        sa.p.x,
                        sa.p.y,
                        flex.min_bend_radius * mm,
                        if attrs {
                            "the stroke has attributes".to_string()
                        } else {
                            "the spine before or after it is too short for that radius".to_string()
                        }
                    ),
                    at: sa.p.to_array(),
                });
                lo = b;
                k += 1;
                continue;
            };
            // Later stretches the fillet covers are rounded with it.
            let mut covered = 1;
            while k + covered < stretches.len() && stretches[k + covered].0 < j_end {
                covered += 1;
            }
            report.rounded += covered;
            report.deviation = report
                .deviation
                .max(deviation(&samples, &f, r, &curves, run));
            lo = j_end;
            k += covered;
            fillets.push(f);
        }
        if !fillets.is_empty() {
            for (leg, pieces) in leg_pieces(run, &curves, &fillets, r) {
                let l = run.legs[leg];
                let c = curves[l.stroke].curve();
                let segs = assemble(c, &pieces, l.reversed);
                let s = &mut out.stroke[l.stroke];
                let p = c.degree().max(3);
                let (disks, knots) = to_disks(&segs, p);
                s.degree = p;
                s.closed = false;
                s.disks = Some(disks);
                s.knots = Some(knots);
                s.points = None;
                s.fit = None;
                s.parametrization = None;
                s.control_disks = None;
                s.corners = None;
                changed[l.stroke] = true;
            }
        }
        reports.push(report);
    }
    // Corners at which loading split strokes move with the rounded joints.
    for c in &mut out.corners {
        if let Some(i) = out.stroke.iter().position(|s| s.name == c.pieces[0])
            && changed[i]
            && let Some(d) = out.stroke[i].disks.as_ref().and_then(|d| d.last())
        {
            c.at = [d[0], d[1]];
        }
    }
    Ok(Rounded {
        design: out,
        reports,
        warnings,
    })
}

/// Samples of a run's spine ([`ROUND_SAMPLES`] per knot span and the span's tightest
/// point), in the run's direction; tight where the radius is below R·(1 + [`ROUND_MARGIN`]),
/// at a joint whose tangents break by more than [`TANGENT_BREAK_DEG`] (both sides), and
/// where q′ = 0. The seam of a closed run is an end of the sample list.
fn run_samples(run: &Run, curves: &[DiskBSpline], r: f64) -> Vec<Sample> {
    let limit = r * (1.0 + ROUND_MARGIN);
    let break_cos = TANGENT_BREAK_DEG.to_radians().cos();
    let mut out: Vec<Sample> = Vec::new();
    for (k, leg) in run.legs.iter().enumerate() {
        let c = &curves[leg.stroke];
        let mut ts = Vec::new();
        for w in c.breakpoints().windows(2).filter(|w| w[1] > w[0]) {
            for i in 0..ROUND_SAMPLES {
                ts.push(w[0] + (w[1] - w[0]) * i as f64 / ROUND_SAMPLES as f64);
            }
            let (rm, tm) = super::span_min_radius(c, w[0], w[1], BEND_PARAM_TOL);
            if rm < r {
                ts.push(tm);
            }
        }
        ts.push(c.domain().1);
        ts.sort_by(f64::total_cmp);
        ts.dedup();
        if leg.reversed {
            ts.reverse();
        }
        let first = out.len();
        for t in ts {
            let u = leg.direction(curves, t);
            out.push(Sample {
                leg: k,
                t,
                p: c.center(t),
                u,
                tight: u == DVec2::ZERO || bend_radius(c, t) < limit,
            });
        }
        if first > 0 && out[first - 1].u.dot(out[first].u) < break_cos {
            out[first - 1].tight = true;
            out[first].tight = true;
        }
    }
    out
}

/// The tight stretches of a sample list: (first, last, turning sign s = ±1 of the stretch).
fn tight_stretches(samples: &[Sample]) -> Vec<(usize, usize, f64)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < samples.len() {
        if !samples[i].tight {
            i += 1;
            continue;
        }
        let a = i;
        while i + 1 < samples.len() && samples[i + 1].tight {
            i += 1;
        }
        let b = i;
        // Signed turning across the stretch, from the tangent before to the one after.
        let (u0, u1) = (
            samples[a.saturating_sub(1)].u,
            samples[(b + 1).min(samples.len() - 1)].u,
        );
        let mut turn = 0.0;
        for w in samples[a.saturating_sub(1)..=(b + 1).min(samples.len() - 1)].windows(2) {
            turn += cross(w[0].u, w[1].u).atan2(w[0].u.dot(w[1].u));
        }
        let s = if turn != 0.0 {
            turn.signum()
        } else {
            cross(u0, u1).signum()
        };
        out.push((a, b, if s == 0.0 { 1.0 } else { s }));
        i += 1;
    }
    out
}

/// Offset point o = q + s·R·n of leg `leg` at `t` (n the left normal in the run's
/// direction), with q.
fn offset(run: &Run, curves: &[DiskBSpline], leg: usize, t: f64, s: f64, r: f64) -> (DVec2, DVec2) {
    let l: &Leg = &run.legs[leg];
    let q = curves[l.stroke].center(t);
    (q + perp(l.direction(curves, t)) * (s * r), q)
}

/// The fillet of the stretch `a..=b` turning by sign `s`: the crossing of the offsets
/// before (samples `lo..=a`) and after (`b..=hi`), nearest the stretch first, refined by
/// Newton's method; with the sample index where the after side's tangency lies.
fn fillet(
    samples: &[Sample],
    run: &Run,
    curves: &[DiskBSpline],
    (lo, a, b, hi): (usize, usize, usize, usize),
    s: f64,
    r: f64,
    tol: f64,
) -> Option<(Fillet, usize)> {
    let o: Vec<DVec2> = samples.iter().map(|x| x.p + perp(x.u) * (s * r)).collect();
    let hit = |i: usize, j: usize| segment_cross(o[i], o[i + 1], o[j], o[j + 1]);
    let mut found = None;
    'outer: for w in 1..=samples.len() {
        let i = a.checked_sub(w).filter(|&i| i >= lo);
        let j = Some(b + w - 1).filter(|&j| j < hi);
        if i.is_none() && j.is_none() {
            break;
        }
        if let Some(i) = i {
            for jj in b..(b + w).min(hi) {
                if let Some(x) = hit(i, jj) {
                    found = Some((i, jj, x));
                    break 'outer;
                }
            }
        }
        if let Some(j) = j {
            for ii in a.saturating_sub(w).max(lo)..a {
                if let Some(x) = hit(ii, j) {
                    found = Some((ii, j, x));
                    break 'outer;
                }
            }
        }
    }
    let (i, j, (la, lb)) = found?;
    let param = |k: usize, lam: f64| {
        let (x, y) = (samples[k], samples[k + 1]);
        if x.leg == y.leg {
            (x.leg, x.t + (y.t - x.t) * lam)
        } else if lam < 0.5 {
            (x.leg, x.t)
        } else {
            (y.leg, y.t)
        }
    };
    let (mut pi, mut pj) = (param(i, la), param(j, lb));
    // Newton on F(tᵢ, tⱼ) = o(tᵢ) − o(tⱼ), central-difference Jacobian, each parameter
    // kept in its stroke's domain.
    let f = |pi: (usize, f64), pj: (usize, f64)| {
        offset(run, curves, pi.0, pi.1, s, r).0 - offset(run, curves, pj.0, pj.1, s, r).0
    };
    let eps = NEWTON_OF_TOL * tol;
    for _ in 0..NEWTON_STEPS {
        let v = f(pi, pj);
        if v.length() <= eps {
            break;
        }
        let span = |leg: usize| {
            let (x, y) = curves[run.legs[leg].stroke].domain();
            (x, y)
        };
        let (ai, bi) = span(pi.0);
        let (aj, bj) = span(pj.0);
        let hi_ = DIFF_STEP_OF_SPAN * (bi - ai);
        let hj = DIFF_STEP_OF_SPAN * (bj - aj);
        let di = (f((pi.0, (pi.1 + hi_).min(bi)), pj) - f((pi.0, (pi.1 - hi_).max(ai)), pj))
            / ((pi.1 + hi_).min(bi) - (pi.1 - hi_).max(ai));
        let dj = (f(pi, (pj.0, (pj.1 + hj).min(bj))) - f(pi, (pj.0, (pj.1 - hj).max(aj))))
            / ((pj.1 + hj).min(bj) - (pj.1 - hj).max(aj));
        let det = cross(di, dj);
        if det.abs() <= f64::MIN_POSITIVE {
            break;
        }
        // Solve di·x + dj·y = −v (Cramer).
        let x = cross(-v, dj) / det;
        let y = cross(di, -v) / det;
        pi.1 = (pi.1 + x).clamp(ai, bi);
        pj.1 = (pj.1 + y).clamp(aj, bj);
    }
    let (oi, qi) = offset(run, curves, pi.0, pi.1, s, r);
    let (oj, qj) = offset(run, curves, pj.0, pj.1, s, r);
    let c = 0.5 * (oi + oj);
    let (ui, uj) = (qi - c, qj - c);
    // The sweep in the bend's direction, in (0, 2π).
    let mut turn = cross(ui, uj).atan2(ui.dot(uj)) * s;
    if turn <= 0.0 {
        turn += std::f64::consts::TAU;
    }
    Some((
        Fillet {
            from: pi,
            to: pj,
            c,
            turn: turn * s,
        },
        j + 1,
    ))
}

/// Where segments ab and cd cross: their parameters (λ, μ) in [0, 1]².
fn segment_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Option<(f64, f64)> {
    let (e, g) = (b - a, d - c);
    let den = cross(e, g);
    if den == 0.0 {
        return None;
    }
    let l = cross(c - a, g) / den;
    let m = cross(c - a, e) / den;
    ((0.0..=1.0).contains(&l) && (0.0..=1.0).contains(&m)).then_some((l, m))
}

/// Largest distance between the drawn spine of a fillet's stretch (its samples) and the
/// arc, either way (sampled both).
fn deviation(samples: &[Sample], f: &Fillet, r: f64, curves: &[DiskBSpline], run: &Run) -> f64 {
    let start = curves[run.legs[f.from.0].stroke].center(f.from.1) - f.c;
    let a0 = start.y.atan2(start.x);
    let arc: Vec<DVec2> = (0..=64)
        .map(|k| f.c + DVec2::from_angle(a0 + f.turn * k as f64 / 64.0) * r)
        .collect();
    let drawn: Vec<DVec2> = samples
        .iter()
        .filter(|x| within(x, f, run))
        .map(|x| x.p)
        .collect();
    let to_poly = |p: DVec2, poly: &[DVec2]| {
        poly.windows(2)
            .map(|w| super::judge::segment_distance(p, p, w[0], w[1]).0)
            .fold(f64::INFINITY, f64::min)
    };
    let mut d: f64 = 0.0;
    if drawn.len() >= 2 {
        for &p in &arc {
            d = d.max(to_poly(p, &drawn));
        }
        for &p in &drawn {
            d = d.max(to_poly(p, &arc));
        }
    }
    d
}

/// Whether a sample lies on the stretch a fillet replaces (between its tangencies along
/// the run).
fn within(x: &Sample, f: &Fillet, run: &Run) -> bool {
    let key = |leg: usize, t: f64| {
        let l = run.legs[leg];
        (leg, if l.reversed { -t } else { t })
    };
    let k = key(x.leg, x.t);
    let lo = key(f.from.0, f.from.1);
    let hi = key(f.to.0, f.to.1);
    k.0.cmp(&lo.0).then(k.1.total_cmp(&lo.1)).is_ge()
        && k.0.cmp(&hi.0).then(k.1.total_cmp(&hi.1)).is_le()
}

/// The new pieces of every leg a fillet touches, in the run's direction: (leg, pieces).
fn leg_pieces(
    run: &Run,
    curves: &[DiskBSpline],
    fillets: &[Fillet],
    r: f64,
) -> Vec<(usize, Vec<Piece>)> {
    let ends = |leg: usize| {
        let l = run.legs[leg];
        let (lo, hi) = curves[l.stroke].domain();
        if l.reversed { (hi, lo) } else { (lo, hi) }
    };
    let mut legs: std::collections::BTreeMap<usize, Vec<Piece>> = std::collections::BTreeMap::new();
    for f in fillets {
        let (ka, kb) = (f.from.0, f.to.0);
        let radius_at = |(leg, t): (usize, f64)| curves[run.legs[leg].stroke].radius(t);
        let arc = arc_beziers(
            curves,
            run,
            f,
            r,
            radius_at(f.from),
            radius_at(f.to),
            kb - ka + 1,
        );
        for (n, part) in arc.into_iter().enumerate() {
            let leg = ka + n;
            let list = legs.entry(leg).or_insert_with(|| {
                let (a, b) = ends(leg);
                vec![Piece::Keep(a, b)]
            });
            if leg == ka {
                // Cut the leg's last kept piece at the first tangency.
                if let Some(Piece::Keep(_, end)) = list.last_mut() {
                    *end = f.from.1;
                }
            } else {
                list.clear();
            }
            list.push(Piece::Arc(part));
            if leg == kb {
                list.push(Piece::Keep(f.to.1, ends(kb).1));
            }
        }
    }
    legs.into_iter().collect()
}

/// The fillet's arc as cubic Bézier pieces in (x, y, r), the radius linear in the angle
/// from `r0` to `r1`, split into `parts` groups of pieces of equal angle (one per leg the
/// fillet spans).
fn arc_beziers(
    curves: &[DiskBSpline],
    run: &Run,
    f: &Fillet,
    r: f64,
    r0: f64,
    r1: f64,
    parts: usize,
) -> Vec<Vec<[DVec3; 4]>> {
    let start = curves[run.legs[f.from.0].stroke].center(f.from.1) - f.c;
    let a0 = start.y.atan2(start.x);
    let per = (f.turn.abs() / ARC_PIECE_DEG.to_radians()).ceil().max(1.0) as usize;
    let per = per.div_ceil(parts);
    let n = per * parts;
    let d = f.turn / n as f64;
    let k = 4.0 / 3.0 * (d / 4.0).tan();
    let at = |i: usize| {
        let a = a0 + d * i as f64;
        let e = DVec2::from_angle(a);
        let rr = r0 + (r1 - r0) * i as f64 / n as f64;
        (f.c + e * r, perp(e) * r, rr)
    };
    let mut out = vec![Vec::new(); parts];
    for i in 0..n {
        let (p0, t0, w0) = at(i);
        let (p3, t3, w3) = at(i + 1);
        let p1 = p0 + t0 * k;
        let p2 = p3 - t3 * k;
        let v = |p: DVec2, w: f64| DVec3::new(p.x, p.y, w);
        out[i / per].push([
            v(p0, w0),
            v(p1, w0 + (w3 - w0) / 3.0),
            v(p2, w0 + 2.0 * (w3 - w0) / 3.0),
            v(p3, w3),
        ]);
    }
    out
}

/// A leg's new spine as Bézier segments (control values of each, degree ≥ 3) in the
/// stroke's own direction.
fn assemble(c: &BSpline<DVec3>, pieces: &[Piece], reversed: bool) -> Vec<Vec<DVec3>> {
    let p = c.degree().max(3);
    let mut segs: Vec<Vec<DVec3>> = Vec::new();
    for piece in pieces {
        match piece {
            Piece::Keep(a, b) => {
                let (lo, hi) = if a <= b { (*a, *b) } else { (*b, *a) };
                let mut part = beziers(c, lo, hi);
                if a > b {
                    part.reverse();
                    part.iter_mut().for_each(|s| s.reverse());
                }
                segs.extend(part.into_iter().map(|s| elevate(s, p)));
            }
            Piece::Arc(arc) => segs.extend(arc.iter().map(|s| elevate(s.to_vec(), p))),
        }
    }
    // Pieces too short to carry a direction are dropped (their ends coincide).
    let scale = segs
        .iter()
        .flatten()
        .map(|v| v.truncate().length())
        .fold(1.0, f64::max);
    segs.retain(|s| {
        s[0].truncate().distance(s[s.len() - 1].truncate()) > DEGENERATE_OF_SCALE * scale
            || poly_len(s) > DEGENERATE_OF_SCALE * scale
    });
    if reversed {
        segs.reverse();
        segs.iter_mut().for_each(|s| s.reverse());
    }
    segs
}

fn poly_len(s: &[DVec3]) -> f64 {
    s.windows(2)
        .map(|w| w[0].truncate().distance(w[1].truncate()))
        .sum()
}

/// The Bézier segments of `c` on [t0, t1] (t0 < t1, inside the domain; a closed curve is
/// read as the open curve over its period): every breakpoint between them and both ends
/// inserted to multiplicity p (Boehm, P&T A5.1); a segment [uₐ, u_b] is then the p + 1
/// control values from index (last index of uₐ) − p.
fn beziers(c: &BSpline<DVec3>, t0: f64, t1: f64) -> Vec<Vec<DVec3>> {
    let p = c.degree();
    let Ok(mut b) = BSpline::new(p, c.knots().to_vec(), c.ctrl().to_vec()) else {
        return Vec::new();
    };
    let inner: Vec<f64> = c
        .breakpoints()
        .into_iter()
        .filter(|&u| u > t0 && u < t1)
        .collect();
    for &u in [t0, t1].iter().chain(&inner) {
        if let Ok(x) = b.insert_knot(u, p) {
            b = x;
        }
    }
    let mut us = vec![t0];
    us.extend(inner);
    us.push(t1);
    us.windows(2)
        .filter(|w| w[1] > w[0])
        .filter_map(|w| {
            let kl = b.knots().iter().rposition(|&k| k == w[0])?;
            let s = kl.checked_sub(p)?;
            b.ctrl().get(s..=s + p).map(<[DVec3]>::to_vec)
        })
        .collect()
}

/// A Bézier curve of degree n raised to degree `p` ≥ n, once per step by
/// Qᵢ = i/(n+1)·Pᵢ₋₁ + (1 − i/(n+1))·Pᵢ (P&T eq. 5.36): the same curve.
fn elevate(mut s: Vec<DVec3>, p: usize) -> Vec<DVec3> {
    while s.len() < p + 1 {
        let n = s.len() - 1;
        let m = (n + 1) as f64;
        let mut q = Vec::with_capacity(n + 2);
        q.push(s[0]);
        for i in 1..=n {
            let a = i as f64 / m;
            q.push(s[i - 1] * a + s[i] * (1.0 - a));
        }
        q.push(s[n]);
        s = q;
    }
    s
}

/// Bézier segments of degree p joined end to end as one clamped B-spline: control disks
/// [x, y, r] and knots (interior knots of multiplicity p, spaced by each segment's control
/// polygon length, normalised to [0, 1]).
fn to_disks(segs: &[Vec<DVec3>], p: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
    let mut disks: Vec<[f64; 3]> = Vec::new();
    let lens: Vec<f64> = segs
        .iter()
        .map(|s| poly_len(s).max(f64::MIN_POSITIVE))
        .collect();
    let total: f64 = lens.iter().sum();
    let mut knots = vec![0.0; p + 1];
    let mut acc = 0.0;
    for (k, s) in segs.iter().enumerate() {
        let from = if k == 0 { 0 } else { 1 };
        disks.extend(s[from..].iter().map(|v| [v.x, v.y, v.z]));
        acc += lens[k];
        if k + 1 < segs.len() {
            knots.extend(std::iter::repeat_n(acc / total, p));
        }
    }
    knots.extend(std::iter::repeat_n(1.0, p + 1));
    (disks, knots)
}
