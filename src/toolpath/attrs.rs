//! Stroke attributes on the moves: laser power and feed along a cut follow the attribute
//! curves of the stroke the cut came from.
//!
//! An attribute is blended like the radius, a(t) = Σ N_{i,p}(t)·A_i (wu-2021 eq. 18, the
//! per-disk constant case, `crate::dbsc::attributes`). A point p of a cut (on the outline,
//! on a hatch line inside it, on a channel wall) takes the value at the *nearest spine
//! parameter*: the t minimising ‖q(t) − p‖, the foot of the perpendicular
//! (q(t) − p)·q′(t) = 0 on the centre curve q.
//!
//! Each cutting move is split into pieces at most `step` long; every piece takes the
//! attributes at its midpoint, **quantised** (power to [`AttrOptions::power_quantum`],
//! feed to [`AttrOptions::feed_quantum`]), and consecutive pieces with equal quantised
//! values are merged again, so a move is split only where the emitted `S` or `F` word
//! changes (the emitter writes `S`/`F` only when they change). Arcs stay arcs (their
//! pieces share the centre); lines stay lines. Moves with the beam off (tab bridges,
//! power 0) and moves without xy extent (plunges) keep their values.

use super::model::{Cut, Move, MoveKind, Operation};
use crate::dbsc::DiskBSpline;
use crate::geom::{Arc, DVec2};
use crate::spline::BSpline;
use glam::DVec3;
use rstar::RTree;
use rstar::primitives::{GeomWithData, Line as RLine};
use std::collections::BTreeMap;

/// The default power quantum as a fraction of full power: 0.5 %. Finer steps than this
/// are below what a diode or CO₂ tube reproduces (their power-to-mark response is not
/// that repeatable) and only multiply the `S` words of a program.
pub const POWER_QUANTUM: f64 = 0.005;

/// Longest attribute piece in multiples of the build tolerance. Pieces are at most 0.5 mm
/// or this many tolerances, whichever is longer: 0.5 mm at the default 0.01 mm tolerance,
/// and the same number of pieces when a job and its tolerance are scaled together (a job
/// cut to 1 mm is not sampled every 0.5 mm).
pub const PIECE_TOLERANCES: f64 = 50.0;

/// The default feed quantum as a fraction of the machine's slower XY maximum feed: 0.5 %
/// (30 mm/min on a 6000 mm/min machine), well inside a controller's feed-override step.
pub const FEED_QUANTUM: f64 = 0.005;

/// The attribute curves of one stroke: its centre curve and the channels the moves use.
#[derive(Clone, Debug)]
pub struct AttrField {
    /// The stroke (its centre curve q(t) locates the nearest parameter).
    pub spine: DiskBSpline,
    /// Power in percent of the machine's maximum (the design's convention), on the
    /// stroke's knots.
    pub power_percent: Option<BSpline<f64>>,
    /// Feed in design units per minute, on the stroke's knots.
    pub feed: Option<BSpline<f64>>,
}

/// How attributes are put on moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttrOptions {
    /// Longest piece of a move that takes one value (design units).
    pub step: f64,
    /// Power step as a fraction of full power (> 0): emitted power is a multiple of it.
    pub power_quantum: f64,
    /// Feed step in design units per minute (> 0): emitted feed is a multiple of it.
    pub feed_quantum: f64,
    /// Tolerance of the nearest-parameter search: Newton stops when the parameter step
    /// moves the spine point by less than this (design units).
    pub tol: f64,
}

/// The power quantum (fraction of full power) for a machine whose `S` runs up to `s_max`
/// and is written with resolution `s_resolution` (1 for integer `S`, 0.001 for fractional):
/// the smallest multiple of the resolution not below [`POWER_QUANTUM`] of the range, so a
/// quantised power is written exactly. GRBL `S0..1000`: steps of 5; Marlin `S0..255`:
/// steps of 2; Smoothie `S0..1`: steps of 0.005.
pub fn power_quantum(s_max: f64, s_resolution: f64) -> f64 {
    if s_max.is_nan() || s_resolution.is_nan() || s_max <= 0.0 || s_resolution <= 0.0 {
        return POWER_QUANTUM;
    }
    let units = (POWER_QUANTUM * s_max / s_resolution - 1e-9)
        .ceil()
        .max(1.0);
    units * s_resolution / s_max
}

/// `v` rounded to the nearest multiple of `q` (unchanged when `q` ≤ 0).
pub fn quantise(v: f64, q: f64) -> f64 {
    if q > 0.0 { (v / q).round() * q } else { v }
}

/// Samples of a spine for nearest-parameter queries (an R-tree of the sample chords).
#[derive(Clone, Debug)]
pub struct SpineIndex<'a> {
    curve: &'a DiskBSpline,
    ts: Vec<f64>,
    pts: Vec<DVec2>,
    /// The sample chords (index i: pts[i − 1]–pts[i]) for nearest-chord queries in
    /// O(log n).
    chords: RTree<GeomWithData<RLine<[f64; 2]>, usize>>,
}

impl<'a> SpineIndex<'a> {
    /// Samples of `curve` uniform in t, about `spacing` apart along the centre curve.
    pub fn new(curve: &'a DiskBSpline, spacing: f64) -> Self {
        let (lo, hi) = curve.domain();
        let coarse = 256;
        let len: f64 = (0..coarse)
            .map(|i| {
                let a = lo + (hi - lo) * i as f64 / coarse as f64;
                let b = lo + (hi - lo) * (i + 1) as f64 / coarse as f64;
                curve.center(a).distance(curve.center(b))
            })
            .sum();
        let n = if spacing > 0.0 && len.is_finite() {
            ((len / spacing).ceil() as usize).clamp(16, 1 << 16)
        } else {
            16
        };
        let ts: Vec<f64> = (0..=n)
            .map(|i| lo + (hi - lo) * i as f64 / n as f64)
            .collect();
        let pts: Vec<DVec2> = ts.iter().map(|&t| curve.center(t)).collect();
        let chords = RTree::bulk_load(
            (1..pts.len())
                .map(|i| {
                    let (a, b) = (pts[i - 1], pts[i]);
                    GeomWithData::new(RLine::new([a.x, a.y], [b.x, b.y]), i)
                })
                .collect(),
        );
        SpineIndex {
            curve,
            ts,
            pts,
            chords,
        }
    }

    /// The parameter t of the spine point nearest to `p`: the nearest sample chord gives a
    /// start in its bracket [t_{i−1}, t_{i+1}]; Newton's method on
    /// g(t) = (q(t) − p)·q′(t), g′(t) = ‖q′‖² + (q(t) − p)·q″(t), kept inside the
    /// bracket, refines it until a step moves q by less than `tol`.
    pub fn nearest(&self, p: DVec2, tol: f64) -> f64 {
        let i = self
            .chords
            .nearest_neighbor(p.to_array())
            .map_or(1, |c| c.data)
            .max(1);
        let (a, b) = (self.pts[i - 1], self.pts[i]);
        let s = crate::geom::Line::new(a, b).nearest_t(p);
        let best = (0.0, i, s);
        let (t0, t1) = (self.ts[i - 1], self.ts[i]);
        let lo = self.ts[i.saturating_sub(2)];
        let hi = self.ts[(i + 1).min(self.ts.len() - 1)];
        let mut t = t0 + best.2 * (t1 - t0);
        for _ in 0..32 {
            let d = self.curve.derivs(t, 2);
            let (q, q1, q2) = (d[0].0, d[1].0, d[2].0);
            let g = (q - p).dot(q1);
            let gp = q1.length_squared() + (q - p).dot(q2);
            if gp.is_nan() || gp <= 0.0 {
                break;
            }
            let next = (t - g / gp).clamp(lo, hi);
            let moved = (next - t).abs() * q1.length();
            t = next;
            if moved.is_nan() || moved <= tol {
                break;
            }
        }
        t
    }
}

/// What [`apply`] did to an operation.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct AttrStats {
    /// Moves that took attribute values.
    pub moves: usize,
    /// The pieces those moves became.
    pub pieces: usize,
    /// Range of the power put on moves (fraction), when a power attribute was applied.
    pub power: Option<(f64, f64)>,
    /// Range of the feed put on moves (design units per minute), when a feed attribute
    /// was applied.
    pub feed: Option<(f64, f64)>,
}

fn widen(r: &mut Option<(f64, f64)>, v: f64) {
    *r = Some(match *r {
        Some((a, b)) => (a.min(v), b.max(v)),
        None => (v, v),
    });
}

/// Puts the attributes of `fields` (by stroke name) on every cutting move of the cuts of
/// `op` whose source has a field: power (percent → fraction, clamped to [0, 1]) and feed
/// (clamped to at least one quantum) follow the attribute at the nearest spine parameter,
/// piecewise as the module documentation describes.
pub fn apply(
    op: &mut Operation,
    fields: &BTreeMap<String, AttrField>,
    opts: &AttrOptions,
) -> AttrStats {
    let mut stats = AttrStats::default();
    let spacing = (opts.step / 2.0).max(opts.tol);
    let indexes: BTreeMap<&str, SpineIndex> = fields
        .iter()
        .filter(|(_, f)| f.power_percent.is_some() || f.feed.is_some())
        .map(|(k, f)| (k.as_str(), SpineIndex::new(&f.spine, spacing)))
        .collect();
    for cut in &mut op.cuts {
        let Some(src) = cut.source.as_deref() else {
            continue;
        };
        let (Some(field), Some(index)) = (fields.get(src), indexes.get(src)) else {
            continue;
        };
        attribute_cut(cut, field, index, opts, &mut stats);
    }
    stats
}

fn attribute_cut(
    cut: &mut Cut,
    field: &AttrField,
    index: &SpineIndex,
    opts: &AttrOptions,
    stats: &mut AttrStats,
) {
    let mut out = Vec::with_capacity(cut.moves.len());
    let mut from = cut.start;
    for m in &cut.moves {
        let start = from;
        from = m.to;
        let arc = match m.kind {
            MoveKind::Line => None,
            MoveKind::Arc { center, ccw } => Some(Arc::from_center_points(
                center,
                start.truncate(),
                m.to.truncate(),
                ccw,
            )),
            _ => {
                out.push(*m);
                continue;
            }
        };
        let len = match &arc {
            Some(a) => a.length(),
            None => start.truncate().distance(m.to.truncate()),
        };
        if m.power <= 0.0 || len.is_nan() || len <= 0.0 {
            out.push(*m);
            continue;
        }
        let n = if opts.step > 0.0 {
            ((len / opts.step).ceil() as usize).clamp(1, 1 << 16)
        } else {
            1
        };
        let at = |s: f64| -> DVec3 {
            let xy = match &arc {
                Some(a) => a.eval(s),
                None => start.truncate().lerp(m.to.truncate(), s),
            };
            xy.extend(start.z + (m.to.z - start.z) * s)
        };
        let value = |s: f64| -> (f64, f64) {
            let t = index.nearest(at(s).truncate(), opts.tol);
            let power = match &field.power_percent {
                Some(c) => quantise((c.eval(t) / 100.0).clamp(0.0, 1.0), opts.power_quantum)
                    .clamp(0.0, 1.0),
                None => m.power,
            };
            let feed = match &field.feed {
                Some(c) => quantise(c.eval(t), opts.feed_quantum).max(opts.feed_quantum.max(1e-9)),
                None => m.feed,
            };
            (power, feed)
        };
        stats.moves += 1;
        let mut run = value(0.5 / n as f64);
        for k in 1..=n {
            let next = (k < n).then(|| value((k as f64 + 0.5) / n as f64));
            if next == Some(run) {
                continue;
            }
            let to = if k == n {
                m.to
            } else {
                at(k as f64 / n as f64)
            };
            out.push(Move {
                kind: m.kind,
                to,
                feed: run.1,
                power: run.0,
            });
            stats.pieces += 1;
            if field.power_percent.is_some() {
                widen(&mut stats.power, run.0);
            }
            if field.feed.is_some() {
                widen(&mut stats.feed, run.1);
            }
            if let Some(v) = next {
                run = v;
            }
        }
    }
    cut.moves = out;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Circle;
    use crate::toolpath::OperationKind;

    fn straight(len: f64) -> DiskBSpline {
        let disks: Vec<Circle> = (0..5)
            .map(|i| Circle::new(DVec2::new(len * i as f64 / 4.0, 0.0), 2.0))
            .collect();
        DiskBSpline::open(3, &disks, None).unwrap()
    }

    fn field(c: &DiskBSpline, power: &[f64], feed: Option<&[f64]>) -> AttrField {
        let a = crate::dbsc::attributes::AttributedDbsc::new(c.clone())
            .with_channel("power", power)
            .unwrap();
        let a = match feed {
            Some(f) => a.with_channel("feed", f).unwrap(),
            None => a,
        };
        AttrField {
            spine: c.clone(),
            power_percent: a.channel("power").cloned(),
            feed: a.channel("feed").cloned(),
        }
    }

    fn op_of(moves: Vec<Move>, start: DVec3, source: &str) -> Operation {
        Operation {
            name: "t".into(),
            kind: OperationKind::Profile,
            cuts: vec![Cut {
                source: Some(source.into()),
                group: None,
                start,
                moves,
            }],
            design_index: None,
            air_assist: false,
        }
    }

    fn opts() -> AttrOptions {
        AttrOptions {
            step: 0.5,
            power_quantum: 0.005,
            feed_quantum: 10.0,
            tol: 1e-9,
        }
    }

    #[test]
    fn quanta_are_multiples_of_the_resolution() {
        assert!((power_quantum(1000.0, 1.0) - 0.005).abs() < 1e-15);
        assert!((power_quantum(255.0, 1.0) * 255.0 - 2.0).abs() < 1e-12);
        assert!((power_quantum(1.0, 0.001) - 0.005).abs() < 1e-12);
        // A coarse controller: one S unit is above 0.5 %.
        assert!((power_quantum(100.0, 1.0) - 0.01).abs() < 1e-15);
        assert_eq!(quantise(0.4237, 0.005), 0.425);
    }

    #[test]
    fn nearest_parameter_is_the_foot_of_the_perpendicular() {
        // A curved spine: for points off it, (q(t) − p)·q′(t) = 0 at the answer and no
        // sample of the curve is nearer.
        let disks: Vec<Circle> = (0..7)
            .map(|i| {
                let x = i as f64 * 10.0;
                Circle::new(DVec2::new(x, 8.0 * (x / 15.0).sin()), 1.0)
            })
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let idx = SpineIndex::new(&c, 1.0);
        let (lo, hi) = c.domain();
        for k in 0..40 {
            let p = DVec2::new(1.5 * k as f64, 3.0 * ((k * 7 % 11) as f64 - 5.0) / 5.0);
            let t = idx.nearest(p, 1e-12);
            let d = c.derivs(t, 1);
            let dist = d[0].0.distance(p);
            if t > lo + 1e-9 && t < hi - 1e-9 {
                let g = (d[0].0 - p).dot(d[1].0) / d[1].0.length();
                assert!(g.abs() < 1e-7, "p {p}: g {g}");
            }
            for i in 0..=2000 {
                let u = lo + (hi - lo) * i as f64 / 2000.0;
                assert!(c.center(u).distance(p) >= dist - 1e-9, "p {p}: {u} nearer");
            }
        }
    }

    #[test]
    fn power_and_feed_follow_a_ramp_along_a_line() {
        // Spine along x from 0 to 100, power ramping 10 → 90 % linearly in x (control
        // values linear in the control x: affine invariance), feed 1000 → 2000.
        let c = straight(100.0);
        let f = field(
            &c,
            &[10.0, 30.0, 50.0, 70.0, 90.0],
            Some(&[1000.0, 1250.0, 1500.0, 1750.0, 2000.0]),
        );
        let mut fields = BTreeMap::new();
        fields.insert("s".to_string(), f);
        // A cut 1 mm beside the spine, x 0 → 100, then a plunge-free laser move back with
        // the beam off (a tab bridge) that must stay as it is.
        let start = DVec3::new(0.0, 1.0, 0.0);
        let moves = vec![
            Move {
                kind: MoveKind::Line,
                to: DVec3::new(100.0, 1.0, 0.0),
                feed: 500.0,
                power: 0.5,
            },
            Move {
                kind: MoveKind::Line,
                to: DVec3::new(90.0, 1.0, 0.0),
                feed: 500.0,
                power: 0.0,
            },
        ];
        let mut op = op_of(moves, start, "s");
        let st = apply(&mut op, &fields, &opts());
        let ms = &op.cuts[0].moves;
        assert_eq!(st.moves, 1);
        // 80 % over 100 mm in steps of 0.5 %: 161 levels; the feed steps make a few more.
        assert!(ms.len() > 150 && ms.len() < 400, "{}", ms.len());
        let mut x0 = 0.0;
        for m in &ms[..ms.len() - 1] {
            let x1 = m.to.x;
            let xm = 0.5 * (x0 + x1);
            // On this spine t is x/100 and power(t) = 10 + 80 x/100 %.
            let want = 0.1 + 0.8 * xm / 100.0;
            assert!(
                (m.power - want).abs() <= 0.005 + 0.8 * (x1 - x0) / 200.0 + 1e-12,
                "x {xm}: {} vs {want}",
                m.power
            );
            let want_f = 1000.0 + 1000.0 * xm / 100.0;
            assert!((m.feed - want_f).abs() <= 10.0 + 1000.0 * (x1 - x0) / 200.0 + 1e-9);
            assert_eq!(m.to.y, 1.0);
            x0 = x1;
        }
        assert_eq!(ms[ms.len() - 2].to, DVec3::new(100.0, 1.0, 0.0));
        let last = ms[ms.len() - 1];
        assert_eq!((last.power, last.feed), (0.0, 500.0));
        // Neighbouring pieces differ (merged runs).
        for w in ms[..ms.len() - 1].windows(2) {
            assert!(w[0].power != w[1].power || w[0].feed != w[1].feed);
        }
        let (pl, ph) = st.power.unwrap();
        assert!(
            (pl - 0.1).abs() < 0.006 && (ph - 0.9).abs() < 0.006,
            "{pl} {ph}"
        );
    }

    #[test]
    fn arcs_stay_arcs_and_constant_attributes_leave_one_piece() {
        let c = straight(100.0);
        let mut fields = BTreeMap::new();
        fields.insert("s".to_string(), field(&c, &[40.0; 5], None));
        // A half circle about (50, 0) of radius 3, from (53, 0) to (47, 0) ccw.
        let start = DVec3::new(53.0, 0.0, 0.0);
        let m = Move {
            kind: MoveKind::Arc {
                center: DVec2::new(50.0, 0.0),
                ccw: true,
            },
            to: DVec3::new(47.0, 0.0, 0.0),
            feed: 700.0,
            power: 1.0,
        };
        let mut op = op_of(vec![m], start, "s");
        apply(&mut op, &fields, &opts());
        assert_eq!(op.cuts[0].moves.len(), 1);
        assert_eq!(op.cuts[0].moves[0].power, 0.4);
        assert_eq!(op.cuts[0].moves[0].feed, 700.0);
        // With a ramp the arc splits into arcs about the same centre, on the circle.
        fields.insert(
            "s".to_string(),
            field(&c, &[0.0, 0.0, 100.0, 0.0, 0.0], None),
        );
        let mut op = op_of(vec![m], start, "s");
        apply(&mut op, &fields, &opts());
        let ms = &op.cuts[0].moves;
        assert!(ms.len() > 2);
        for p in ms {
            assert_eq!(p.kind, m.kind);
            assert!((p.to.truncate().distance(DVec2::new(50.0, 0.0)) - 3.0).abs() < 1e-12);
        }
        assert_eq!(ms[ms.len() - 1].to, m.to);
        // A cut of another stroke is left alone.
        let mut op = op_of(vec![m], start, "other");
        assert_eq!(apply(&mut op, &fields, &opts()), AttrStats::default());
        assert_eq!(op.cuts[0].moves, vec![m]);
    }
}
