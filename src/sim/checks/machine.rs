//! Per-move machine checks: travel limits, rapids with the tool on or too low, feed and power
//! ranges, and how the program ends.

use super::contours::is_cutting;
use crate::sim::config::{CheckConfig, Dialect, MachineKind};
use crate::sim::findings::{Finding, Severity};
use crate::sim::motion::{Motion, MotionKind, Program};

/// Slack on the travel limits relative to the coordinates, so that a move ending exactly on a
/// limit after unit conversion (25.4 · x) is not flagged.
fn limit_slack(v: f64) -> f64 {
    crate::geom::tol::scaled(v)
}

/// The travel limits of a configuration with their slack ([`limit_slack`]), computed once
/// for many moves.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Limits {
    /// The limits of `cfg`.
    pub fn new(cfg: &CheckConfig) -> Self {
        Limits {
            lo: [0, 1, 2].map(|i| cfg.work_min[i] - limit_slack(cfg.work_min[i])),
            hi: [0, 1, 2].map(|i| cfg.work_max[i] + limit_slack(cfg.work_max[i])),
        }
    }

    /// The `out-of-bounds` finding of a move (rapids included) that leaves the work area
    /// [work_min, work_max] of `cfg` (arcs by their exact bounds), with these limits.
    pub fn motion(&self, m: &Motion, cfg: &CheckConfig) -> Option<Finding> {
        if !self.leaves(m) {
            return None;
        }
        let (lo, hi) = m.bounds();
        out_of_bounds_finding(m, cfg, lo, hi, self)
    }

    /// [`Limits::motion`] into `out`, built only while `out` keeps out-of-bounds findings
    /// (beyond its cap the move is only counted: no message is formatted).
    pub(crate) fn check_move(&self, m: &Motion, cfg: &CheckConfig, out: &mut super::Capped) {
        self.check_move_in(m, m.bounds(), cfg, out);
    }

    /// [`Limits::check_move`] of a move whose [`Motion::bounds`] are `bounds` (for callers
    /// that have them already).
    pub(crate) fn check_move_in(
        &self,
        m: &Motion,
        bounds: (glam::DVec3, glam::DVec3),
        cfg: &CheckConfig,
        out: &mut super::Capped,
    ) {
        if self.outside(bounds) {
            out.push_with(OUT_OF_BOUNDS, || self.motion(m, cfg));
        }
    }

    /// Whether `m` leaves the work area: exactly when [`Limits::motion`] finds it.
    pub fn leaves(&self, m: &Motion) -> bool {
        self.outside(m.bounds())
    }

    /// Whether bounds `(lo, hi)` reach outside the work area.
    fn outside(&self, (lo, hi): (glam::DVec3, glam::DVec3)) -> bool {
        (0..3).any(|i| lo[i] < self.lo[i] || hi[i] > self.hi[i])
    }
}

/// Id of the findings of moves leaving the work area.
pub const OUT_OF_BOUNDS: &str = "out-of-bounds";

/// The finding of a move with bounds `lo`..`hi` outside `limits`, if any.
fn out_of_bounds_finding(
    m: &Motion,
    cfg: &CheckConfig,
    lo: glam::DVec3,
    hi: glam::DVec3,
    limits: &Limits,
) -> Option<Finding> {
    let mut bad = Vec::new();
    for (i, axis) in ["x", "y", "z"].into_iter().enumerate() {
        if lo[i] < limits.lo[i] {
            bad.push(format!("{axis} {:.3} < {:.3}", lo[i], cfg.work_min[i]));
        }
        if hi[i] > limits.hi[i] {
            bad.push(format!("{axis} {:.3} > {:.3}", hi[i], cfg.work_max[i]));
        }
    }
    if bad.is_empty() {
        return None;
    }
    let what = if m.kind == MotionKind::Rapid {
        "rapid"
    } else {
        "move"
    };
    Some(
        Finding::new(
            OUT_OF_BOUNDS,
            Severity::Error,
            format!("{what} leaves the work area: {}", bad.join(", ")),
        )
        .line(m.line)
        .at(m.to.to_array()),
    )
}

/// Laser: G0 with M3/M4 and S > 0 (a warning in GRBL laser mode, where G0 never fires, an
/// error elsewhere). Router: a rapid that moves in xy below `safe_z`, or that ends below
/// `cut_z` (a rapid plunge into the stock). Nothing unless `m` is a rapid.
pub fn rapid_move(m: &Motion, cfg: &CheckConfig, out: &mut Vec<Finding>) {
    if m.kind != MotionKind::Rapid {
        return;
    }
    match cfg.kind {
        MachineKind::Laser => {
            if m.tool.is_on() {
                let (sev, note) = if cfg.grbl_laser_mode {
                    (
                        Severity::Warning,
                        "GRBL laser mode keeps the beam off on G0; other controllers fire it",
                    )
                } else {
                    (Severity::Error, "the beam fires along the rapid")
                };
                out.push(
                    Finding::new(
                        "laser-on-rapid",
                        sev,
                        format!("G0 with the laser on (S{}): {note}", m.tool.s),
                    )
                    .line(m.line)
                    .at(m.to.to_array()),
                );
            }
        }
        MachineKind::Router => {
            let low = m.from.z.min(m.to.z);
            let xy = m.from.truncate() != m.to.truncate();
            if xy && low < cfg.safe_z {
                let depth = if low < cfg.cut_z {
                    " (inside the stock)"
                } else {
                    ""
                };
                out.push(
                    Finding::new(
                        "rapid-below-safe-z",
                        Severity::Error,
                        format!(
                            "rapid in xy at z {low:.3}, below safe z {:.3}{depth}",
                            cfg.safe_z
                        ),
                    )
                    .line(m.line)
                    .at(m.to.to_array()),
                );
            } else if m.to.z < cfg.cut_z {
                out.push(
                    Finding::new(
                        "rapid-into-stock",
                        Severity::Error,
                        format!(
                            "rapid plunges to z {:.3}, below the stock top {:.3}",
                            m.to.z, cfg.cut_z
                        ),
                    )
                    .line(m.line)
                    .at(m.to.to_array()),
                );
            }
        }
    }
}

/// Cutting moves whose feed or S is outside the configured ranges, one finding per run of
/// consecutive offending moves with the same value: the state between moves (the value of
/// the current run of offending moves).
#[derive(Clone, Debug, Default)]
pub struct FeedPower {
    last_feed: Option<f64>,
    last_power: Option<f64>,
}

impl FeedPower {
    /// Checks the next move (nothing unless it cuts).
    pub fn motion(&mut self, m: &Motion, cfg: &CheckConfig, out: &mut Vec<Finding>) {
        if !is_cutting(m, cfg) {
            return;
        }
        let f = m.feed;
        // LinuxCNC and GRBL refuse a feed move without F: the interpreter's `no-feed-rate`
        // error already names it.
        let refused = f <= 0.0 && matches!(cfg.dialect, Dialect::Linuxcnc | Dialect::Grbl);
        if !refused && (f < cfg.feed_min || f > cfg.feed_max) {
            if self.last_feed != Some(f) {
                let msg = if f <= 0.0 {
                    "cutting move without a feed rate (no F set)".to_string()
                } else {
                    format!(
                        "feed {f:.1} mm/min outside {:.1}..{:.1}",
                        cfg.feed_min, cfg.feed_max
                    )
                };
                out.push(
                    Finding::new("feed-out-of-range", Severity::Error, msg)
                        .line(m.line)
                        .at(m.from.to_array()),
                );
            }
            self.last_feed = Some(f);
        } else {
            self.last_feed = None;
        }
        let s = m.tool.s;
        let powered = m.tool.spindle != crate::sim::motion::Spindle::Off;
        if powered && (s < cfg.power_min || s > cfg.power_max) {
            if self.last_power != Some(s) {
                out.push(
                    Finding::new(
                        "power-out-of-range",
                        Severity::Error,
                        format!("S{s} outside {}..{}", cfg.power_min, cfg.power_max),
                    )
                    .line(m.line)
                    .at(m.from.to_array()),
                );
            }
            self.last_power = Some(s);
        } else {
            self.last_power = None;
        }
    }
}

/// The end of the program: no M2/M30 (a warning: GRBL streams need none, but a missing end
/// often means a truncated file), the tool still on at the end of a file without M2/M30 (an
/// error), or M2/M30 reached with the tool on (a warning: controllers stop it there).
pub fn program_end(prog: &Program, cfg: &CheckConfig) -> Vec<Finding> {
    let mut out = Vec::new();
    match prog.end {
        None => {
            let f = if cfg.program_end_optional {
                Finding::new(
                    "missing-program-end",
                    Severity::Info,
                    "no M2/M30, as this dialect expects (Marlin ends when the host stops \
                     sending; its M30 deletes a file on the SD card)",
                )
            } else {
                Finding::new(
                    "missing-program-end",
                    Severity::Warning,
                    "no M2/M30: the file may be truncated",
                )
            };
            out.push(f.line(prog.last_line));
            if prog.final_tool.is_on() {
                out.push(
                    Finding::new(
                        "tool-on-at-end",
                        Severity::Error,
                        format!(
                            "the program ends with the spindle/laser on (S{}) and no M5",
                            prog.final_tool.s
                        ),
                    )
                    .line(prog.last_line),
                );
            }
        }
        Some(end) if end.tool_before.is_on() => out.push(
            Finding::new(
                "tool-on-at-end",
                Severity::Warning,
                "M2/M30 reached with the spindle/laser on (no M5 before it)",
            )
            .line(end.line),
        ),
        Some(_) => {}
    }
    out
}
