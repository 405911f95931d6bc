//! Polylines for output within a chordal tolerance: the spine q(t), each envelope side
//! b±(t) (wu-2021 eq. 9) split into pieces at the no-envelope intervals, and the end caps.
//! These feed the outline roles "spine" and "envelope".
//!
//! Error control: adaptive subdivision of the parameter interval. A piece [a, b] is
//! accepted when the curve points at `PROBES` of it lie within `PROBE_SAFETY`·`tol`
//! of the chord f(a)f(b) and progress monotonically along it (no backtracking, which
//! catches envelope cusps); otherwise it is halved. For a C² piece the true deviation is at most
//! (b − a)²/8 · max‖f″‖, which the probes do not bound rigorously: this is a heuristic that
//! holds once the pieces are short against the curve's features (one bend per piece), which
//! the initial split ([`MIN_PIECES_PER_SPAN`] per knot span) and recursion ensure in
//! practice. Depth is capped at [`MAX_DEPTH`] halvings per initial piece, so near cusps and
//! square-root ends the result may exceed `tol` on pieces shorter than 2⁻²⁴ of a span.
//! Arcs (caps) use the exact sagitta bound of [`Arc::flatten`].

use super::caps::{End, cap};
use super::no_envelope::no_envelope_intervals;
use super::{DiskBSpline, Side};
use crate::geom::{Arc, Circle, DVec2, Line, perp};

/// Halvings allowed below each initial piece.
pub const MAX_DEPTH: usize = 24;

/// Initial pieces per knot span, so that a span whose probes happen to lie on its chord
/// (an S-shape symmetric about its midpoint, a span that closes on itself) is still split.
pub const MIN_PIECES_PER_SPAN: usize = 4;

/// Probe positions inside a piece, as fractions of it. The probes close to the ends make
/// the monotonicity test see an envelope cusp right next to an end (the curve runs out to
/// the tip and back): the excursion it can hide shrinks with the square of the gap.
const PROBES: [f64; 5] = [1.0 / 32.0, 0.25, 0.5, 0.75, 31.0 / 32.0];

/// Index of the midpoint probe in [`PROBES`].
const MID: usize = 2;

/// Probes must lie within this fraction of `tol`: the margin covers the deviation between
/// probes where the parametrisation is uneven. Near envelope cusps (local loops, τ± < 0)
/// the tip can still fall between probes; tests allow 4·tol there.
pub const PROBE_SAFETY: f64 = 0.5;

/// Chords shorter than this fraction of `tol` skip the monotonicity test (their direction
/// is rounding noise, e.g. where the envelope is nearly stationary); the depth cap still
/// bounds the work.
pub const NOISE_CHORD: f64 = 1e-6;

/// Parameter tolerance, relative to the domain length, for locating the no-envelope
/// interval ends the envelope pieces start and stop at.
pub const ROOT_TOL_REL: f64 = 1e-12;

/// A flattened outline of a DBSC.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatOutline {
    /// The centre curve (for closed curves first point = last point).
    pub spine: Vec<DVec2>,
    /// Left envelope pieces in the direction of travel.
    pub left: Vec<Vec<DVec2>>,
    /// Right envelope pieces in the direction of travel.
    pub right: Vec<Vec<DVec2>>,
    /// End caps of open strokes, start cap then end cap, in the contour direction of
    /// [`super::caps()`]. A cap whose end has no envelope is left out; `no_envelope` shows it.
    pub caps: Vec<(End, Vec<DVec2>)>,
    /// The no-envelope intervals the envelope sides were split at.
    pub no_envelope: Vec<(f64, f64)>,
}

/// Parameters and points of `f` on [t0, t1] with chord deviation within `tol` at the
/// probes (module docs), starting from `n0` equal pieces. `f` gives several curves at once
/// (e.g. spine and both envelopes); a piece is split when any of them deviates.
pub(crate) fn adaptive_samples<const K: usize>(
    f: &dyn Fn(f64) -> [DVec2; K],
    t0: f64,
    t1: f64,
    n0: usize,
    tol: f64,
) -> Vec<(f64, [DVec2; K])> {
    let n0 = n0.max(1);
    let mut out = vec![(t0, f(t0))];
    for i in 0..n0 {
        let a = out[out.len() - 1];
        let tb = if i + 1 == n0 {
            t1
        } else {
            t0 + (t1 - t0) * (i + 1) as f64 / n0 as f64
        };
        let b = (tb, f(tb));
        refine(f, a, b, tol, 0, &mut out);
    }
    out
}

fn refine<const K: usize>(
    f: &dyn Fn(f64) -> [DVec2; K],
    a: (f64, [DVec2; K]),
    b: (f64, [DVec2; K]),
    tol: f64,
    depth: usize,
    out: &mut Vec<(f64, [DVec2; K])>,
) {
    let probes: [(f64, [DVec2; K]); PROBES.len()] = PROBES.map(|s| {
        let t = a.0 + s * (b.0 - a.0);
        (t, f(t))
    });
    let ok = depth >= MAX_DEPTH
        || (0..K).all(|k| {
            let (pa, pb) = (a.1[k], b.1[k]);
            let chord = Line::new(pa, pb);
            let d = pb - pa;
            // Probes progress monotonically along the chord: a piece that backtracks (an
            // envelope cusp, a turn of more than 90°) is split whatever its deviation.
            let mut last = 0.0;
            let mut monotone = true;
            for s in probes
                .iter()
                .map(|(_, p)| (p[k] - pa).dot(d))
                .chain([d.dot(d)])
            {
                monotone &= s >= last;
                last = s;
            }
            // On a vanishing chord the direction is noise; the distance test alone decides.
            let short = d.length() <= NOISE_CHORD * tol;
            (monotone || short)
                && probes
                    .iter()
                    .all(|(_, p)| chord.distance(p[k]) <= PROBE_SAFETY * tol)
        });
    if ok {
        out.push(b);
        return;
    }
    let mid = probes[MID];
    refine(f, a, mid, tol, depth + 1, out);
    refine(f, mid, b, tol, depth + 1, out);
}

/// (q, r), (q′, r′) at t; with `left` the limits from the left of t (the polynomial of the
/// span ending at t), otherwise from the right ([`DiskBSpline::derivs`]). The envelope of a
/// DBSC that is only C⁰ at a knot (degree 1, or a knot of multiplicity p) jumps there.
fn derivs1(c: &DiskBSpline, t: f64, left: bool) -> [(DVec2, f64); 2] {
    let curve = c.curve();
    let (k, p, n) = (curve.knots(), curve.degree(), curve.ctrl().len());
    let (lo, _) = c.domain();
    if left && t > lo {
        // The span j with k[j] < t ≤ k[j + 1], j in p..n.
        let j = (p..n).rev().find(|&j| k[j] < t).unwrap_or(p);
        let d = crate::spline::ders_basis_funs(k, p, j, t, 1);
        let mut out = [(DVec2::ZERO, 0.0); 2];
        for (order, o) in out.iter_mut().enumerate() {
            for (i, &w) in d[order].iter().enumerate() {
                let v = curve.ctrl()[j - p + i];
                o.0 += w * v.truncate();
                o.1 += w * v.z;
            }
        }
        return out;
    }
    let d = c.derivs(t, 1);
    [d[0], d[1]]
}

/// The envelope point with s = √max(D, 0): equal to b±(t) (wu-2021 eq. 9) where the
/// envelope exists, and its limit q − r r′ q′/‖q′‖² at the ends of a no-envelope interval,
/// where the located root may leave D a rounding error below 0. `left` selects the limit
/// from the left at a knot (see [`derivs1`]). Where q′ = 0 the parameter is nudged towards
/// `toward`.
pub(crate) fn envelope_point_closed(
    c: &DiskBSpline,
    side: Side,
    t: f64,
    left: bool,
    toward: f64,
) -> DVec2 {
    let mut t = t;
    for _ in 0..4 {
        let [(q, r), (q1, r1)] = derivs1(c, t, left);
        let l = q1.length_squared();
        if l > 0.0 {
            let s = (l - r1 * r1).max(0.0).sqrt();
            return q + (r / l) * (side.sign() * s * perp(q1) - r1 * q1);
        }
        t += (toward - t) * 1e-9;
    }
    c.center(t)
}

/// The spine within `tol` (module docs for the bound).
pub fn flatten_spine(c: &DiskBSpline, tol: f64) -> Vec<DVec2> {
    spine_samples(c, tol)
        .into_iter()
        .map(|(_, p)| p[0])
        .collect()
}

/// The disk family c(t) = (q(t), r(t)) sampled so that linear interpolation of centre and
/// radius between consecutive samples stays within `tol` of both (the same adaptive
/// subdivision as the spine, applied to q and to r; module docs for the bound). Returns
/// (t, disk) pairs in parameter order, knots included; a closed curve's last sample
/// repeats its first.
pub fn flatten_disks(c: &DiskBSpline, tol: f64) -> Vec<(f64, Circle)> {
    // One evaluation gives both: the centre and radius of `circle_at` are those of
    // `center` and `radius`.
    let f = |t: f64, _left: bool| {
        let d = c.circle_at(t);
        [d.c, DVec2::new(d.r, 0.0)]
    };
    piecewise(c, c.domain(), &f, tol)
        .into_iter()
        .map(|(t, [q, r])| (t, Circle::new(q, r.x)))
        .collect()
}

fn spine_samples(c: &DiskBSpline, tol: f64) -> Vec<(f64, [DVec2; 1])> {
    let f = |t: f64, _left: bool| [c.center(t)];
    piecewise(c, c.domain(), &f, tol)
}

/// Adaptive samples over [a, b] started at every knot span inside it. Each span is
/// sampled on its own polynomial (`f(t, true)` gives the limit from the left at the span's
/// end); where the two one-sided values at a knot differ both are kept.
fn piecewise<const K: usize>(
    c: &DiskBSpline,
    (a, b): (f64, f64),
    f: &dyn Fn(f64, bool) -> [DVec2; K],
    tol: f64,
) -> Vec<(f64, [DVec2; K])> {
    let mut cuts = vec![a];
    cuts.extend(c.breakpoints().into_iter().filter(|&k| k > a && k < b));
    cuts.push(b);
    let mut out: Vec<(f64, [DVec2; K])> = Vec::new();
    for w in cuts.windows(2) {
        let end = w[1];
        let g = |t: f64| f(t, t == end);
        let s = adaptive_samples(&g, w[0], w[1], MIN_PIECES_PER_SPAN, tol);
        let skip = usize::from(
            out.last()
                .is_some_and(|l| s.first().is_some_and(|f| f.1 == l.1)),
        );
        out.extend(s.into_iter().skip(skip));
    }
    out
}

/// The parameter pieces of the domain where an envelope exists (the complement of the
/// no-envelope intervals), joined across the seam of a closed curve.
fn envelope_pieces(c: &DiskBSpline, gaps: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let (lo, hi) = c.domain();
    let mut pieces = Vec::new();
    let mut start = lo;
    for &(a, b) in gaps {
        if a > start {
            pieces.push(vec![(start, a)]);
        }
        start = start.max(b);
    }
    if hi > start {
        pieces.push(vec![(start, hi)]);
    }
    if c.is_closed() && !gaps.is_empty() && pieces.len() >= 2 {
        let first_at_lo = pieces
            .first()
            .and_then(|p| p.first())
            .is_some_and(|p| p.0 == lo);
        let last_at_hi = pieces
            .last()
            .and_then(|p| p.last())
            .is_some_and(|p| p.1 == hi);
        if first_at_lo && last_at_hi {
            let first = pieces.remove(0);
            if let Some(last) = pieces.last_mut() {
                last.extend(first);
            }
        }
    }
    pieces
}

fn side_samples(
    c: &DiskBSpline,
    side: Side,
    gaps: &[(f64, f64)],
    tol: f64,
) -> Vec<Vec<(f64, DVec2)>> {
    envelope_pieces(c, gaps)
        .into_iter()
        .map(|ranges| {
            let mut out: Vec<(f64, DVec2)> = Vec::new();
            for (a, b) in ranges {
                let mid = 0.5 * (a + b);
                let f = |t: f64, left: bool| [envelope_point_closed(c, side, t, left, mid)];
                let s = piecewise(c, (a, b), &f, tol);
                let skip = usize::from(
                    out.last()
                        .is_some_and(|l| s.first().is_some_and(|f| f.1[0] == l.1)),
                );
                out.extend(s.into_iter().skip(skip).map(|(t, p)| (t, p[0])));
            }
            out
        })
        .collect()
}

/// The envelope side `side` within `tol`, one polyline per piece between no-envelope
/// intervals (located to `ROOT_TOL_REL` of the domain).
pub fn flatten_envelope(c: &DiskBSpline, side: Side, tol: f64) -> Vec<Vec<DVec2>> {
    let gaps = no_envelope_intervals(c, root_tol(c));
    side_samples(c, side, &gaps, tol)
        .into_iter()
        .map(|v| v.into_iter().map(|(_, p)| p).collect())
        .collect()
}

fn root_tol(c: &DiskBSpline) -> f64 {
    let (lo, hi) = c.domain();
    ROOT_TOL_REL * (hi - lo)
}

/// Spine, both envelope sides and the caps within `tol` (module docs for the bound).
pub fn flatten(c: &DiskBSpline, tol: f64) -> FlatOutline {
    let gaps = no_envelope_intervals(c, root_tol(c));
    let strip = |v: Vec<Vec<(f64, DVec2)>>| -> Vec<Vec<DVec2>> {
        v.into_iter()
            .map(|p| p.into_iter().map(|(_, q)| q).collect())
            .collect()
    };
    let caps = [End::Start, End::End]
        .into_iter()
        .filter_map(|e| cap(c, e).ok().map(|a: Arc| (e, a.flatten(tol))))
        .collect();
    FlatOutline {
        spine: flatten_spine(c, tol),
        left: strip(side_samples(c, Side::Left, &gaps, tol)),
        right: strip(side_samples(c, Side::Right, &gaps, tol)),
        caps,
        no_envelope: gaps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::tangent::tests::dbsc_strategy;
    use crate::geom::Circle;
    use proptest::prelude::*;

    /// Pieces with a local loop (cusps) keep the heuristic only to a factor (measured: 14
    /// with probes at ¼, ½, ¾ only; the near-end probes are what brings it within this).
    const LOOPED_FACTOR: f64 = 4.0;

    /// Max distance of dense samples of f between consecutive output parameters to the
    /// output chord.
    fn max_dev(samples: &[(f64, DVec2)], f: impl Fn(f64) -> DVec2) -> f64 {
        let mut worst = 0.0f64;
        for w in samples.windows(2) {
            if w[1].0 < w[0].0 {
                continue; // across the seam of a closed curve: hi followed by lo
            }
            let ch = Line::new(w[0].1, w[1].1);
            for i in 1..16 {
                let t = w[0].0 + (w[1].0 - w[0].0) * i as f64 / 16.0;
                worst = worst.max(ch.distance(f(t)));
            }
        }
        worst
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn spine_and_envelopes_within_tolerance(c in dbsc_strategy(), tol in prop_oneof![Just(1e-3), Just(1e-2), Just(1e-1)]) {
            let s: Vec<(f64, DVec2)> = spine_samples(&c, tol).into_iter().map(|(t, p)| (t, p[0])).collect();
            prop_assert!(max_dev(&s, |t| c.center(t)) <= tol * (1.0 + 1e-9));
            let (lo, hi) = c.domain();
            prop_assert_eq!(s.first().unwrap().0, lo);
            prop_assert_eq!(s.last().unwrap().0, hi);
            let gaps = no_envelope_intervals(&c, root_tol(&c));
            for side in [Side::Left, Side::Right] {
                for piece in side_samples(&c, side, &gaps, tol) {
                    for w in piece.windows(2) {
                        // Every sample outside the no-envelope intervals (up to their ends).
                        prop_assert!(!gaps.iter().any(|&(a, b)| w[0].0 > a && w[0].0 < b));
                    }
                    let mid = 0.5 * (piece[0].0 + piece[piece.len() - 1].0);
                    let d = max_dev(&piece, |t| envelope_point_closed(&c, side, t, false, mid));
                    // Around envelope cusps (τ± < 0 somewhere: a local loop) the tip can fall
                    // between the probes; the heuristic is then only good to a small factor.
                    let looped = piece.iter().any(|&(t, _)| c.tau(side, t).is_some_and(|x| x < 0.0));
                    let bound = if looped { LOOPED_FACTOR * tol } else { tol * (1.0 + 1e-9) };
                    prop_assert!(d <= bound, "side {:?} dev {} looped {}", side, d, looped);
                }
            }
        }
    }

    #[test]
    fn straight_stroke_outline() {
        let disks: Vec<Circle> = (0..5)
            .map(|i| Circle::new(DVec2::new(i as f64, 0.0), 0.5))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let o = flatten(&c, 1e-3);
        assert!(o.no_envelope.is_empty());
        assert_eq!((o.left.len(), o.right.len(), o.caps.len()), (1, 1, 2));
        assert!(o.left[0].iter().all(|p| (p.y - 0.5).abs() < 1e-12));
        assert!(o.right[0].iter().all(|p| (p.y + 0.5).abs() < 1e-12));
        // Closed contour: left, end cap, right reversed, start cap.
        let mut ring: Vec<DVec2> = o.left[0].clone();
        ring.extend(o.caps[1].1.iter().skip(1));
        ring.extend(o.right[0].iter().rev().skip(1));
        ring.extend(o.caps[0].1.iter().skip(1));
        assert!((ring[0] - *ring.last().unwrap()).length() < 1e-12);
        // Area of the stadium: 4·1 + π/4, clockwise (negative). Each chord of sagitta ≤ tol
        // cuts off at most ⅔·tol·chord, so the caps (length π·0.5 each) lose ≤ ⅔·tol·π.
        let area = crate::geom::path::polygon_area(&ring);
        let want = -(4.0 + std::f64::consts::PI * 0.25);
        let slack = 2.0 / 3.0 * 1e-3 * std::f64::consts::PI;
        assert!(area >= want && area - want <= slack * 1.001, "{area}");
    }

    /// The cubic of no_envelope's closed-form test: the left side splits into three pieces
    /// around (0.0670, 0.25), (0.75, 0.933), each ending on the limit point.
    #[test]
    fn envelope_split_at_no_envelope_intervals() {
        let r = |t: f64| 1.0 + 2.0 * t - 16.0 * (t - 0.5f64).powi(3) / 3.0;
        let r1 = |t: f64| 2.0 - 16.0 * (t - 0.5f64).powi(2);
        let rs = [
            r(0.0),
            r(0.0) + r1(0.0) / 3.0,
            r(1.0) - r1(1.0) / 3.0,
            r(1.0),
        ];
        let disks: Vec<Circle> = (0..4)
            .map(|i| Circle::new(DVec2::new(i as f64 / 3.0, 0.0), rs[i]))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let o = flatten(&c, 1e-4);
        assert_eq!(o.no_envelope.len(), 3);
        assert_eq!(o.left.len(), 2);
        assert_eq!(o.right.len(), 2);
        assert!(o.caps.is_empty());
        // At t = 0.25 (r′ = 1 = ‖q′‖) the limit point is q − r q′: (0.25 − r(0.25), 0).
        let p = o.left[0].last().unwrap();
        assert!(
            (p.x - (0.25 - r(0.25))).abs() < 1e-6 && p.y.abs() < 1e-3,
            "{p}"
        );
    }
}
