//! The motion model both backends produce: straight and arc moves in machine millimetres,
//! each with its feed, tool state and source line.

use crate::geom::{Arc, DVec2};
use glam::DVec3;
use serde::Serialize;

/// Spindle or laser mode (M3, M4, M5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Spindle {
    #[default]
    Off,
    /// M3: spindle clockwise; laser constant power.
    Cw,
    /// M4: spindle counter-clockwise; GRBL laser dynamic power.
    Ccw,
}

/// Tool state in effect during a move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ToolState {
    pub spindle: Spindle,
    /// Programmed S (spindle rpm or laser power, in the machine's S units).
    pub s: f64,
    /// How many times the tool has been switched on so far (off → on by M3/M4 or S): a
    /// change ends a cut contour even without a move in between.
    pub session: u32,
}

impl ToolState {
    /// True when the spindle/laser is commanded on with a positive S.
    pub fn is_on(&self) -> bool {
        self.spindle != Spindle::Off && self.s > 0.0
    }

    /// Sets the spindle mode and S, counting an off → on switch.
    pub fn switch(&mut self, spindle: Spindle, s: f64) {
        let was_on = self.is_on();
        self.spindle = spindle;
        self.s = s;
        if self.is_on() && !was_on {
            self.session = self.session.wrapping_add(1);
        }
    }
}

/// What a motion does.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MotionKind {
    /// G0.
    Rapid,
    /// G1, G2, G3.
    Feed,
    /// G4: wait in place.
    Dwell { seconds: f64 },
}

/// One move from `from` to `to` (mm, machine coordinates). `arc` is set for G2/G3: the xy
/// projection is that arc (exact, not flattened), z varies linearly along it (helix).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub kind: MotionKind,
    pub from: DVec3,
    pub to: DVec3,
    pub arc: Option<Arc>,
    /// Programmed feed in mm/min (0 when none was ever set).
    pub feed: f64,
    pub tool: ToolState,
    /// 1-based source line.
    pub line: usize,
    /// Group id from the latest `(skinpath:group N)` comment (cleared by
    /// `(skinpath:group end)`): moves of one group belong together for the crossing check.
    pub group: Option<u32>,
}

impl Motion {
    /// Length of the xy projection (arc length for arcs).
    pub fn xy_length(&self) -> f64 {
        match &self.arc {
            Some(a) => a.length(),
            None => self.from.truncate().distance(self.to.truncate()),
        }
    }

    /// Length in space: helical arc length √((rθ)² + Δz²) for arcs, chord otherwise.
    pub fn length(&self) -> f64 {
        match &self.arc {
            Some(a) => a.length().hypot(self.to.z - self.from.z),
            None => self.from.distance(self.to),
        }
    }

    /// The xy path as points with sagitta ≤ `tol` (start and end included): the chord
    /// flattening of [`Arc::flatten`] for arcs, the two end points for lines.
    pub fn flatten_xy(&self, tol: f64) -> Vec<DVec2> {
        match &self.arc {
            Some(a) => {
                let mut pts = a.flatten(tol);
                // Pin the ends to the exact programmed points (the arc's eval may differ in
                // the last bits, and the end may carry a small radius mismatch).
                if let Some(first) = pts.first_mut() {
                    *first = self.from.truncate();
                }
                if let Some(last) = pts.last_mut() {
                    *last = self.to.truncate();
                }
                pts
            }
            None => vec![self.from.truncate(), self.to.truncate()],
        }
    }

    /// Points in space along the move with xy sagitta ≤ `tol`, z linear in arc length.
    pub fn flatten_3d(&self, tol: f64) -> Vec<DVec3> {
        match &self.arc {
            Some(_) => {
                let xy = self.flatten_xy(tol);
                let n = xy.len().saturating_sub(1).max(1) as f64;
                xy.iter()
                    .enumerate()
                    .map(|(i, p)| p.extend(self.from.z + (self.to.z - self.from.z) * i as f64 / n))
                    .collect()
            }
            None => vec![self.from, self.to],
        }
    }

    /// Axis-aligned bounds (min, max) of the move, arcs included exactly (the arc's
    /// axis extremes at angles 0, π/2, π, 3π/2 when swept).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = self.from.min(self.to);
        let mut hi = self.from.max(self.to);
        if let Some(a) = &self.arc {
            for p in a.extrema() {
                lo = lo.min(p.extend(lo.z));
                hi = hi.max(p.extend(hi.z));
            }
        }
        (lo, hi)
    }
}

/// How the program ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ProgramEnd {
    /// Line of M2/M30 (or LinuxCNC's PROGRAM_END).
    pub line: usize,
    /// Tool state just before the end code.
    pub tool_before: ToolState,
}

/// Length units the program was written in (the crate's one [`crate::units::Units`]).
pub use crate::units::Units;

/// Everything a backend extracts from a program.
#[derive(Clone, Debug, Default)]
pub struct Program {
    pub motions: Vec<Motion>,
    pub diagnostics: Vec<super::findings::Finding>,
    pub end: Option<ProgramEnd>,
    /// Tool state after the last line.
    pub final_tool: ToolState,
    /// Number of source lines (or canon lines for LinuxCNC).
    pub lines: usize,
    /// Last line that held a word.
    pub last_line: usize,
    /// Number of words (or canon commands) understood.
    pub words: usize,
    /// Machine events in program order: pauses (M0/M1/M60), tool changes, coolant,
    /// digital/analog outputs (M62–M68), messages.
    pub events: Vec<Event>,
    /// First line whose moves depend on the real machine (after G38.x probing or a user
    /// M-code): positions from there on are uncertain.
    pub uncertain_from: Option<usize>,
    /// Why nothing usable could be read (empty file, binary data), when that is the case.
    pub unusable: Option<String>,
    /// Pocket marks `(skinpath:group N)` by line (see
    /// [`crate::sim::checks::contours::note_group_marks`]), in line order.
    pub group_marks: Vec<(usize, Option<u32>)>,
}

/// A machine event that is not a move.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Event {
    pub line: usize,
    /// The code as written, e.g. `M8`, `M64 P2`, `M6 T3`.
    pub code: String,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn helix_length_and_bounds() {
        let arc = Arc::new(DVec2::ZERO, 2.0, 0.0, 2.0 * PI);
        let m = Motion {
            kind: MotionKind::Feed,
            from: DVec3::new(2.0, 0.0, 0.0),
            to: DVec3::new(2.0, 0.0, -3.0),
            arc: Some(arc),
            feed: 100.0,
            tool: ToolState::default(),
            line: 1,
            group: None,
        };
        // Unrolled helix: hypotenuse of circumference and drop.
        assert!((m.length() - (4.0 * PI).hypot(3.0)).abs() < 1e-12);
        let (lo, hi) = m.bounds();
        assert!((lo - DVec3::new(-2.0, -2.0, -3.0)).length() < 1e-12);
        assert!((hi - DVec3::new(2.0, 2.0, 0.0)).length() < 1e-12);
        let pts = m.flatten_3d(1e-3);
        assert!((pts.last().copied().unwrap_or_default().z + 3.0).abs() < 1e-12);
    }
}
