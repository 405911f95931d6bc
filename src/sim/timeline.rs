//! Where the tool is at a given program time: the time estimate's planner (GRBL 1.1 model,
//! see [`super::time`]) kept per block instead of summed, so a preview can play the program.
//!
//! Every motion is split into the same chords as the estimate (`arc_tolerance`); each chord
//! becomes a [`Segment`] with its start time, entry, cruise and exit speed and acceleration.
//! Within a segment the travelled distance follows the trapezoidal profile
//! s(τ) = vᵢτ + aτ²/2 while accelerating (τ < t₁ = (v_c − vᵢ)/a), d₁ + v_c(τ − t₁) while
//! cruising, and d₁ + d₂ + v_cτ′ − aτ′²/2 while decelerating (τ′ the time since the
//! deceleration began). The sum of the segments' durations is the estimate's total.

use super::config::CheckConfig;
use super::motion::{MotionKind, Motions};
use super::time::{AxisLimits, Block, MIN_ARC_TOLERANCE_MM, block_time, plan, untimed};
use glam::DVec3;

/// One planner block (a chord of a motion) or a dwell, with its place in time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Index of the motion in the program's motion list.
    pub motion: usize,
    /// Start point (mm).
    pub from: DVec3,
    /// End point (mm).
    pub to: DVec3,
    /// Start time, seconds from the program start.
    pub t0: f64,
    /// Duration, seconds (0 for a chord the machine limits cannot move, e.g. a zero rate).
    pub dt: f64,
    /// Entry, cruise (or peak) and exit speed, mm/s.
    pub vi: f64,
    /// Cruise (or peak) speed, mm/s.
    pub vc: f64,
    /// Exit speed, mm/s.
    pub vf: f64,
    /// Acceleration along the chord, mm/s² (0 for dwells).
    pub a: f64,
}

impl Segment {
    /// Length of the chord, mm.
    pub fn len(&self) -> f64 {
        (self.to - self.from).length()
    }

    /// True for a dwell or any segment that does not move.
    pub fn is_empty(&self) -> bool {
        self.from == self.to
    }

    /// Distance travelled `tau` seconds after the segment started (clamped to the segment).
    pub fn distance_at(&self, tau: f64) -> f64 {
        let len = self.len();
        if !(self.a > 0.0 && self.vc > 0.0) || tau >= self.dt {
            return if tau >= self.dt { len } else { 0.0 };
        }
        let tau = tau.max(0.0);
        let t1 = ((self.vc - self.vi) / self.a).max(0.0);
        let d1 = (self.vc * self.vc - self.vi * self.vi) / (2.0 * self.a);
        let d3 = (self.vc * self.vc - self.vf * self.vf) / (2.0 * self.a);
        let t2 = ((len - d1 - d3) / self.vc).max(0.0);
        let s = if tau < t1 {
            self.vi * tau + 0.5 * self.a * tau * tau
        } else if tau < t1 + t2 {
            d1 + self.vc * (tau - t1)
        } else {
            let u = tau - t1 - t2;
            d1 + self.vc * t2 + self.vc * u - 0.5 * self.a * u * u
        };
        s.clamp(0.0, len)
    }

    /// The tool position `tau` seconds after the segment started.
    pub fn position_at(&self, tau: f64) -> DVec3 {
        let len = self.len();
        if len == 0.0 {
            return self.to;
        }
        self.from + (self.to - self.from) * (self.distance_at(tau) / len)
    }
}

/// The whole program in time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timeline {
    /// Blocks and dwells in program order.
    pub segments: Vec<Segment>,
    /// Total seconds (equals the time estimate's total).
    pub total: f64,
}

impl Timeline {
    /// Index of the segment running at time `t` (the last one at or after the end, None
    /// for an empty timeline).
    pub fn segment_at(&self, t: f64) -> Option<usize> {
        if self.segments.is_empty() {
            return None;
        }
        // First segment whose end lies beyond t.
        let i = self.segments.partition_point(|s| s.t0 + s.dt <= t);
        Some(i.min(self.segments.len() - 1))
    }

    /// Where the tool is at time `t` and which motion it is executing.
    pub fn position_at(&self, t: f64) -> Option<(DVec3, usize)> {
        let i = self.segment_at(t)?;
        let s = &self.segments[i];
        Some((s.position_at(t - s.t0), s.motion))
    }
}

/// The timeline of `motions` (mm) under `cfg` (converted to mm here). The machine starts
/// and ends at rest and stops for every dwell, as in [`super::time::estimate`].
pub fn timeline(motions: &Motions, cfg: &CheckConfig) -> Timeline {
    let cfg = cfg.in_mm();
    let mut segs: Vec<Segment> = Vec::new();
    let mut blocks: Vec<Block> = Vec::new();
    // The segment of each block.
    let mut seg_of: Vec<usize> = Vec::new();
    let lim = AxisLimits::new(&cfg);
    for (mi, m) in motions.iter().enumerate() {
        match m.kind {
            MotionKind::Dwell { seconds } => {
                store_speeds(&blocks, &seg_of, &lim, &mut segs);
                blocks.clear();
                seg_of.clear();
                segs.push(Segment {
                    motion: mi,
                    from: m.to,
                    to: m.to,
                    t0: 0.0,
                    dt: if seconds.is_finite() {
                        seconds.max(0.0)
                    } else {
                        0.0
                    },
                    vi: 0.0,
                    vc: 0.0,
                    vf: 0.0,
                    a: 0.0,
                });
            }
            MotionKind::Rapid | MotionKind::Feed => {
                let rapid = m.kind == MotionKind::Rapid;
                let pts = m.flatten_3d(cfg.arc_tolerance.max(MIN_ARC_TOLERANCE_MM));
                for w in pts.windows(2) {
                    segs.push(Segment {
                        motion: mi,
                        from: w[0],
                        to: w[1],
                        t0: 0.0,
                        dt: 0.0,
                        vi: 0.0,
                        vc: 0.0,
                        vf: 0.0,
                        a: 0.0,
                    });
                    if untimed(&m) {
                        continue;
                    }
                    if let Some(b) = Block::of_chord(w[1] - w[0], m.feed, rapid, &lim) {
                        blocks.push(b);
                        seg_of.push(segs.len() - 1);
                    }
                }
            }
        }
    }
    store_speeds(&blocks, &seg_of, &lim, &mut segs);
    let mut t = 0.0;
    for s in &mut segs {
        s.t0 = t;
        t += s.dt;
    }
    Timeline {
        segments: segs,
        total: t,
    }
}

/// Plans a run of blocks from rest to rest ([`super::time::plan`]) and stores each block's
/// entry, cruise (or peak) and exit speed and its duration in its segment.
fn store_speeds(blocks: &[Block], seg_of: &[usize], lim: &AxisLimits, segs: &mut [Segment]) {
    let e = plan(blocks, lim);
    for (i, b) in blocks.iter().enumerate() {
        let (vi, vf) = (e[i].sqrt(), e[i + 1].sqrt());
        let da = (b.v * b.v - vi * vi) / (2.0 * b.a);
        let dd = (b.v * b.v - vf * vf) / (2.0 * b.a);
        let vc = if da + dd <= b.len {
            b.v
        } else {
            (b.a * b.len + 0.5 * (vi * vi + vf * vf)).sqrt().min(b.v)
        };
        let s = &mut segs[seg_of[i]];
        s.vi = vi;
        s.vc = vc;
        s.vf = vf;
        s.a = b.a;
        s.dt = block_time(b.len, vi, vf, b.v, b.a);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::interp::interpret;
    use crate::sim::time::estimate;

    fn cfg() -> CheckConfig {
        CheckConfig {
            max_rate: [12000.0, 12000.0, 1200.0],
            accel: [500.0, 500.0, 50.0],
            ..CheckConfig::default()
        }
    }

    #[test]
    fn total_matches_the_estimate() {
        for src in [
            "G1 X100 F6000",
            "G1 X10 F6000\nY10\nX0 Y0",
            "G0 X10\nG4 P0.5\nG2 X10 Y0 I-10 J0 F3000\nG0 Z5\nG1 Z-1 F100\nM2",
            "G1 X100 Y100 F6000\nG3 X0 Y100 R50\nG4 P1\nG0 X0 Y0",
        ] {
            let p = interpret(src, 0.005);
            let tl = timeline(&p.motions, &cfg());
            let est = estimate(&p.motions, &cfg());
            assert!(
                (tl.total - est.total).abs() < 1e-9 * est.total.max(1.0),
                "{src}: {} vs {}",
                tl.total,
                est.total
            );
        }
    }

    #[test]
    fn windowed_estimate_matches_the_whole_run_plan() {
        // Far more blocks than the estimator's window, with no stop between them: short
        // chords of a fast spiral (entry speeds limited by braking over many blocks ahead)
        // mixed with long lines and sharp turns. The timeline plans the run whole
        // ([`super::super::time::plan`]); the estimate settles it window by window.
        let mut src = String::from("G1 F6000\n");
        let mut seed = 0x5EED_u64;
        for k in 0..30_000 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = (seed >> 11) as f64 / (1u64 << 53) as f64;
            let t = k as f64 * 0.01;
            let (x, y) = if k % 997 < 3 {
                (200.0 * r, 150.0 * (1.0 - r))
            } else {
                (
                    100.0 + (20.0 + 0.002 * k as f64) * t.cos(),
                    80.0 + 30.0 * t.sin(),
                )
            };
            src.push_str(&format!("X{x:.4} Y{y:.4}\n"));
        }
        let p = interpret(&src, 0.005);
        assert!(p.motions.len() > 20_000);
        let tl = timeline(&p.motions, &cfg());
        let est = estimate(&p.motions, &cfg());
        assert!(
            (tl.total - est.total).abs() < 1e-9 * est.total,
            "{} vs {}",
            tl.total,
            est.total
        );
    }

    #[test]
    fn trapezoid_positions() {
        // v = 100 mm/s, a = 500 mm/s²: 0.2 s to reach speed over 10 mm, cruise 80 mm in
        // 0.8 s, brake 10 mm in 0.2 s (closed form s = at²/2 while accelerating).
        let p = interpret("G1 X100 F6000", 0.005);
        let tl = timeline(&p.motions, &cfg());
        assert!((tl.total - 1.2).abs() < 1e-12);
        let x = |t: f64| tl.position_at(t).map(|(p, _)| p.x).unwrap_or(f64::NAN);
        assert!((x(0.1) - 0.5 * 500.0 * 0.01).abs() < 1e-9);
        assert!((x(0.2) - 10.0).abs() < 1e-9);
        assert!((x(0.6) - 50.0).abs() < 1e-9);
        assert!((x(1.1) - (100.0 - 0.5 * 500.0 * 0.01)).abs() < 1e-9);
        assert!((x(5.0) - 100.0).abs() < 1e-12);
        assert_eq!(x(-1.0), 0.0);
        // Distance is monotone in time.
        let mut last = -1.0;
        for k in 0..=120 {
            let v = x(k as f64 * 0.01);
            assert!(v >= last - 1e-12);
            last = v;
        }
    }

    #[test]
    fn dwell_holds_position_and_motions_are_indexed() {
        let p = interpret("G1 X10 F600\nG4 P2\nG1 Y10", 0.005);
        let tl = timeline(&p.motions, &cfg());
        let d = tl
            .segments
            .iter()
            .find(|s| s.dt == 2.0)
            .copied()
            .unwrap_or(tl.segments[0]);
        assert_eq!(d.motion, 1);
        let (pos, m) = tl.position_at(d.t0 + 1.0).unwrap_or_default();
        assert_eq!(m, 1);
        assert!((pos - DVec3::new(10.0, 0.0, 0.0)).length() < 1e-12);
        let (end, m) = tl.position_at(tl.total).unwrap_or_default();
        assert_eq!(m, 2);
        assert!((end - DVec3::new(10.0, 10.0, 0.0)).length() < 1e-12);
    }
}
