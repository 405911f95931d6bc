//! Run time estimate with GRBL's planner model: moves (arcs split into chords of
//! `arc_tolerance`) run at trapezoidal speed profiles, junction speeds from the junction
//! deviation, per-axis rate and acceleration limits, a backward and a forward pass.
//!
//! Junction speed (GRBL 1.1 planner, "junction deviation"): with unit directions u₀, u₁,
//! cos θ = −u₀·u₁ and sin(θ/2) = √((1 − cos θ)/2), the corner is taken at
//! v² = a_j · δ · sin(θ/2) / (1 − sin(θ/2)), a_j the acceleration limit along u₁ − u₀.
//! Block limits along a unit direction u are min over moving axes of limit_i / |u_i|.
//! A block of length L from entry speed vᵢ to exit v_f with nominal v and acceleration a
//! takes (v − vᵢ)/a + (v − v_f)/a + (L − d_a − d_d)/v with d = (v² − v₀²)/(2a) when it
//! reaches v, otherwise peaks at v_p² = aL + (vᵢ² + v_f²)/2.

use super::config::CheckConfig;
use super::motion::{Motion, MotionKind, Motions};
use glam::DVec3;
use serde::Serialize;

/// Smallest chord tolerance (mm) arcs are flattened with for the estimate: a zero or negative
/// configured `arc_tolerance` would otherwise bound no chord count.
pub(crate) const MIN_ARC_TOLERANCE_MM: f64 = 1e-9;

/// Cosine bounds beyond which a junction counts as straight or a full reversal (GRBL).
const COS_STRAIGHT: f64 = 0.999999;

/// Estimated seconds, split by kind of move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct TimeEstimate {
    /// Whole program, seconds.
    pub total: f64,
    /// Time spent on feed moves, seconds.
    pub feed: f64,
    /// Time spent on rapids, seconds.
    pub rapid: f64,
    /// Time spent in dwells, seconds.
    pub dwell: f64,
    /// Feed moves without a feed rate (no F, or F0, where the controller refuses them):
    /// they contribute no time, so the estimate is incomplete when this is not 0.
    pub untimed_moves: usize,
}

/// One planner block: a straight chord with its nominal speed and acceleration.
#[derive(Clone, Copy, Debug)]
pub(super) struct Block {
    pub len: f64,
    pub unit: DVec3,
    /// Nominal speed, mm/s.
    pub v: f64,
    /// Acceleration, mm/s².
    pub a: f64,
}

impl Block {
    /// The block of chord `d` (mm) at programmed `feed` (mm/min; 0 = the rate limit, which
    /// [`Estimator::motion`] never passes for a feed move), or at
    /// the rate limit for a rapid. None for a chord the limits cannot move (zero length,
    /// zero or non-finite speed or acceleration).
    pub(super) fn of_chord(d: DVec3, feed: f64, rapid: bool, lim: &AxisLimits) -> Option<Block> {
        let len = d.length();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let unit = d * (1.0 / len);
        let vmax = axis_limited(lim.inv_rate, d, len);
        let prog = if feed > 0.0 { feed / 60.0 } else { vmax };
        let v = if rapid { vmax } else { prog.min(vmax) };
        let a = axis_limited(lim.inv_accel, d, len);
        (v > 0.0 && a > 0.0 && v.is_finite() && a.is_finite()).then_some(Block { len, unit, v, a })
    }
}

/// The machine's per-axis limits as reciprocals (so a block takes one division per limit,
/// not one per axis): 1/rate in s/mm and 1/acceleration in s²/mm, 0 for an unlimited axis
/// and +∞ for one that cannot move (limit ≤ 0); a NaN limit is ignored.
#[derive(Clone, Copy, Debug)]
pub(super) struct AxisLimits {
    inv_rate: [f64; 3],
    inv_accel: [f64; 3],
    junction_deviation: f64,
}

impl AxisLimits {
    /// The limits of `cfg` (mm; rates in mm/min).
    pub(super) fn new(cfg: &CheckConfig) -> Self {
        let inv = |lim: f64| {
            if lim > 0.0 {
                1.0 / lim
            } else if lim.is_nan() {
                0.0
            } else {
                f64::INFINITY
            }
        };
        AxisLimits {
            inv_rate: cfg.max_rate.map(|r| inv(r / 60.0)),
            inv_accel: cfg.accel.map(inv),
            junction_deviation: cfg.junction_deviation,
        }
    }
}

/// The limit along direction `d` (of length `len` > 0) from per-axis limits given as
/// reciprocals: min over axes with dᵢ ≠ 0 of limitᵢ · len / |dᵢ| = len / maxᵢ(|dᵢ| / limitᵢ)
/// (GRBL limit_value_by_axis_maximum). A product 0 · ∞ (a still axis that cannot move) is
/// NaN, which `f64::max` passes over.
fn axis_limited(inv: [f64; 3], d: DVec3, len: f64) -> f64 {
    let m = (d.x.abs() * inv[0])
        .max(d.y.abs() * inv[1])
        .max(d.z.abs() * inv[2]);
    len / m
}

/// Estimates the run time of `motions` (mm) under `cfg` (mm, see [`CheckConfig::in_mm`]).
/// The machine starts and ends at rest and stops for every dwell.
pub fn estimate(motions: &Motions, cfg: &CheckConfig) -> TimeEstimate {
    estimate_each(motions, cfg, |_| {})
}

/// [`estimate`], calling `f` with every motion in program order on the way: callers that
/// need the moves too read them once. Runs the [`Estimator`] over the moves: its window
/// keeps the memory bounded (a run of a million blocks between two stops would otherwise
/// hold a million entry speeds, all of them fresh pages to fault in).
pub fn estimate_each(
    motions: &Motions,
    cfg: &CheckConfig,
    mut f: impl FnMut(&Motion),
) -> TimeEstimate {
    let mut est = Estimator::new(cfg);
    for m in motions {
        f(&m);
        est.motion(&m);
    }
    est.finish()
}

/// True for a feed move without a feed rate (no F, or F0): it gets no planner blocks and
/// no time, here and in [`super::timeline`], rather than an invented feed.
pub(super) fn untimed(m: &Motion) -> bool {
    m.kind == MotionKind::Feed && (m.feed <= 0.0 || m.feed.is_nan())
}

/// The planner blocks of a rapid or feed move, with whether it is a rapid.
fn for_blocks(m: &Motion, lim: &AxisLimits, cfg: &CheckConfig, mut f: impl FnMut(Block, bool)) {
    let is_rapid = m.kind == MotionKind::Rapid;
    if m.arc.is_none() {
        // A line is one chord: no point list to build.
        if let Some(b) = Block::of_chord(m.to - m.from, m.feed, is_rapid, lim) {
            f(b, is_rapid);
        }
        return;
    }
    let pts = m.flatten_3d(cfg.arc_tolerance.max(MIN_ARC_TOLERANCE_MM));
    for w in pts.windows(2) {
        if let Some(b) = Block::of_chord(w[1] - w[0], m.feed, is_rapid, lim) {
            f(b, is_rapid);
        }
    }
}

/// [`estimate`] move by move in bounded memory: the same sums, bit for bit.
///
/// `plan` needs a whole run of blocks (rest to rest) for its backward pass, but a block's
/// planned speeds depend on the blocks after it only until the room to brake from them
/// exceeds its own limit. The planner keeps a window of blocks and plans it twice, once
/// with the run ending at rest after the window and once with no limit there; where the
/// two give the same squared entry speed (bit for bit, the passes being monotone), every
/// earlier block's speeds are final and its time is added.
#[derive(Clone, Debug)]
pub struct Estimator {
    cfg: CheckConfig,
    lim: AxisLimits,
    /// The window: block, rapid, its junction limit with the block before (0 for the first
    /// block of a run; computed for blocks before `fresh` only).
    window: Vec<(Block, bool, f64)>,
    /// Index of the first window block whose junction limit is still to be computed.
    fresh: usize,
    /// Final squared entry speed of the window's first block.
    entry: f64,
    /// Window length that triggers an attempt to settle blocks.
    limit: usize,
    /// Squared entry speeds of the window's blocks while settling (a reused buffer).
    speeds: Vec<f64>,
    t: TimeEstimate,
}

/// Blocks kept before the [`Estimator`] tries to settle some.
const WINDOW: usize = 8192;

impl Estimator {
    /// An estimator for `cfg` (mm).
    pub fn new(cfg: &CheckConfig) -> Self {
        Estimator {
            cfg: cfg.clone(),
            lim: AxisLimits::new(cfg),
            window: Vec::new(),
            fresh: 0,
            entry: 0.0,
            limit: WINDOW,
            speeds: Vec::new(),
            t: TimeEstimate::default(),
        }
    }

    /// Adds the next move.
    pub fn motion(&mut self, m: &Motion) {
        match m.kind {
            MotionKind::Dwell { seconds } => {
                self.settle(true);
                if seconds.is_finite() {
                    self.t.dwell += seconds;
                }
            }
            // No feed is invented: the controller refuses the move, the estimate counts it.
            MotionKind::Feed if untimed(m) => self.t.untimed_moves += 1,
            MotionKind::Rapid | MotionKind::Feed => {
                // Junction limits are computed when settling, in a loop of their own.
                let window = &mut self.window;
                for_blocks(m, &self.lim, &self.cfg, |b, r| window.push((b, r, 0.0)));
                if self.window.len() >= self.limit {
                    self.settle(false);
                }
            }
        }
    }

    /// The estimate of everything added.
    pub fn finish(mut self) -> TimeEstimate {
        self.settle(true);
        let mut t = self.t;
        t.total = t.feed + t.rapid + t.dwell;
        t
    }

    /// Adds the times of the blocks whose speeds are final (all of them when the run ends
    /// here, `end`).
    ///
    /// The backward pass runs from rest after the window (`lo`) and, unless the run ends
    /// here, alongside it from no limit there (`hi`) until the two agree bit for bit: both
    /// follow one recurrence, so every earlier entry agrees too and is final. The forward
    /// pass then times the blocks before that point.
    fn settle(&mut self, end: bool) {
        let n = self.window.len();
        if n == 0 {
            self.entry = 0.0;
            return;
        }
        // The junction limits of the blocks added since the last settling (the first block
        // of a run keeps 0). A loop of its own: the square roots and divisions of one
        // junction do not wait for those of the one before, unlike in `motion`'s body.
        for i in self.fresh.max(1)..n {
            let j = junction_speed_sqr(&self.window[i - 1].0, &self.window[i].0, &self.lim);
            self.window[i].2 = j;
        }
        let e = &mut self.speeds;
        e.clear();
        e.extend(self.window.iter().map(|w| w.2));
        e.push(0.0);
        let mut done = if end { n } else { 0 };
        let mut hi = (!end).then_some(f64::INFINITY);
        for i in (0..n).rev() {
            let b = &self.window[i].0;
            let junction = e[i];
            e[i] = junction.min(e[i + 1] + 2.0 * b.a * b.len);
            if let Some(h) = hi {
                let h = junction.min(h + 2.0 * b.a * b.len);
                if h.to_bits() == e[i].to_bits() {
                    // Highest index whose entry speed does not depend on what follows.
                    done = i;
                    hi = None;
                } else {
                    hi = Some(h);
                }
            }
        }
        // Forward pass over the settled part, from the final entry speed.
        e[0] = self.entry;
        let mut vi = e[0].sqrt();
        for i in 0..done {
            let b = self.window[i].0;
            e[i + 1] = e[i + 1].min(e[i] + 2.0 * b.a * b.len);
            let vf = e[i + 1].sqrt();
            let dt = block_time(b.len, vi, vf, b.v, b.a);
            vi = vf;
            if self.window[i].1 {
                self.t.rapid += dt;
            } else {
                self.t.feed += dt;
            }
        }
        if end {
            self.window.clear();
            self.entry = 0.0;
            self.limit = WINDOW;
        } else {
            self.entry = e[done];
            self.window.drain(..done);
            self.limit = WINDOW.max(2 * self.window.len());
        }
        self.fresh = self.window.len();
    }
}

/// Squared junction speed limit between blocks `p` and `q`.
fn junction_speed_sqr(p: &Block, q: &Block, lim: &AxisLimits) -> f64 {
    let cos = -p.unit.dot(q.unit);
    let nominal = p.v.min(q.v).powi(2);
    if cos > COS_STRAIGHT {
        return 0.0;
    }
    if cos < -COS_STRAIGHT {
        return nominal;
    }
    // The acceleration limit along u₁ − u₀ (not a still vector: cos ≥ −COS_STRAIGHT).
    let w = q.unit - p.unit;
    let aj = axis_limited(lim.inv_accel, w, w.length());
    let sin_half = (0.5 * (1.0 - cos)).sqrt();
    let vj2 = aj * lim.junction_deviation * sin_half / (1.0 - sin_half);
    vj2.min(nominal)
}

/// Plans a run of blocks from rest to rest: the squared entry speed of every block,
/// e[i] for block i and e[n] = 0 for the exit of the last (junction limits, then a backward
/// and a forward pass over v_next² ≤ v² + 2aL).
pub(super) fn plan(blocks: &[Block], lim: &AxisLimits) -> Vec<f64> {
    let n = blocks.len();
    let mut e = vec![0.0; n + 1];
    for i in 1..n {
        e[i] = junction_speed_sqr(&blocks[i - 1], &blocks[i], lim);
    }
    for i in (0..n).rev() {
        let b = &blocks[i];
        e[i] = e[i].min(e[i + 1] + 2.0 * b.a * b.len);
    }
    for i in 0..n {
        let b = &blocks[i];
        e[i + 1] = e[i + 1].min(e[i] + 2.0 * b.a * b.len);
    }
    e
}

/// Time of a trapezoidal (or triangular) profile over length `len` from `vi` to `vf` with
/// nominal `v` and acceleration `a` (see the module docs).
pub fn block_time(len: f64, vi: f64, vf: f64, v: f64, a: f64) -> f64 {
    let inv_2a = 0.5 / a;
    let da = (v * v - vi * vi) * inv_2a;
    let dd = (v * v - vf * vf) * inv_2a;
    if da + dd <= len {
        (2.0 * v - vi - vf) * (2.0 * inv_2a) + (len - da - dd) / v
    } else {
        let vp = (a * len + 0.5 * (vi * vi + vf * vf)).sqrt().min(v);
        ((vp - vi).max(0.0) + (vp - vf).max(0.0)) * (2.0 * inv_2a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::interp::interpret;

    fn cfg() -> CheckConfig {
        CheckConfig {
            max_rate: [12000.0, 12000.0, 1200.0],
            accel: [500.0, 500.0, 50.0],
            ..CheckConfig::default()
        }
    }

    fn time(src: &str) -> TimeEstimate {
        estimate(&interpret(src, 0.005).motions, &cfg())
    }

    #[test]
    fn single_trapezoid_and_triangle() {
        // v = 100 mm/s, a = 500: accelerating takes 10 mm each way; t = v/a + L/v.
        let t = time("G1 X100 F6000");
        assert!((t.feed - (0.2 + 1.0)).abs() < 1e-12, "{t:?}");
        // L = 10 < v²/a: a triangle, t = 2√(L/a).
        let t = time("G1 X10 F6000");
        assert!((t.feed - 2.0 * (10.0f64 / 500.0).sqrt()).abs() < 1e-12);
        // Diagonal: per-axis limits scale by √2 (a = 500√2), feed below the rate limit.
        let t = time("G1 X100 Y100 F6000");
        let (l, a, v) = (100.0 * 2f64.sqrt(), 500.0 * 2f64.sqrt(), 100.0);
        assert!((t.feed - (v / a + l / v)).abs() < 1e-12);
        // Rapid in z runs at z's rate and acceleration: 20 mm/s, 50 mm/s².
        let t = time("G0 Z-30");
        assert!((t.rapid - (20.0 / 50.0 + 30.0 / 20.0)).abs() < 1e-12);
    }

    #[test]
    fn full_circle_at_constant_speed() {
        // Junctions of the chords allow far more than 50 mm/s, so the circle is one
        // trapezoid over its (flattened) length. With (near) infinite acceleration the time
        // is the circumference over the feed, t = 2πr/v, up to the chords' shortfall
        // (relative ≤ sagitta/r = 2e-4).
        let l = 2.0 * std::f64::consts::PI * 10.0;
        let src = "G0 X10\nG4 P0\nG2 X10 Y0 I-10 J0 F3000";
        let fast = CheckConfig {
            accel: [1e9; 3],
            ..cfg()
        };
        let t = estimate(&interpret(src, 0.005).motions, &fast);
        assert!((t.feed - l / 50.0).abs() < 2e-4 * l / 50.0, "{t:?}");
        // Per-axis acceleration lies between a (along an axis) and a√2 (diagonal), so the
        // time lies between the two trapezoids L/v + v/a.
        let t = time(src);
        let (lo, hi) = (
            l / 50.0 + 50.0 / (500.0 * 2f64.sqrt()),
            l / 50.0 + 50.0 / 500.0,
        );
        assert!(
            t.feed > lo && t.feed < hi * (1.0 + 1e-9),
            "{lo} < {} < {hi}",
            t.feed
        );
    }

    #[test]
    fn right_angle_corner_speed() {
        // Corner 90°: sin(θ/2) = √½, a_j = 500√2 along the diagonal junction vector.
        let t = time("G1 X100 F6000\nY100");
        let s = 0.5f64.sqrt();
        let vj = (500.0 * 2f64.sqrt() * 0.01 * s / (1.0 - s)).sqrt();
        let want = 2.0 * block_time(100.0, 0.0, vj, 100.0, 500.0);
        assert!((t.feed - want).abs() < 1e-12);
        // Reversed and rotated copies take the same time.
        let r = time("G0 X100 Y100\nG4 P0\nG1 X100 Y0 F6000\nX0");
        assert!((r.feed - want).abs() < 1e-12);
    }

    #[test]
    fn dwell_stops_and_adds() {
        let t = time("G1 X100 F6000\nG4 P2\nG1 X200");
        assert!((t.feed - 2.4).abs() < 1e-12);
        assert!((t.total - 4.4).abs() < 1e-12);
    }
}
