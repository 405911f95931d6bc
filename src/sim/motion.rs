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
    /// M5: spindle or laser off.
    Off,
    /// M3: spindle clockwise; laser constant power.
    Cw,
    /// M4: spindle counter-clockwise; GRBL laser dynamic power.
    Ccw,
}

/// Tool state in effect during a move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ToolState {
    /// Spindle or laser mode.
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

    /// Sets the spindle mode and S, counting an off → on switch: by M3/M4, or by S rising
    /// from 0 (a laser that fires on S alone, as Smoothieware's, is switched off and on by
    /// `S0` … `S>0` between two passes).
    pub fn switch(&mut self, spindle: Spindle, s: f64) {
        let was_on = self.is_on();
        let s_rises = self.s <= 0.0 && s > 0.0;
        self.spindle = spindle;
        self.s = s;
        if self.is_on() && !was_on || s_rises {
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
    Dwell {
        /// Dwell time, seconds.
        seconds: f64,
    },
}

/// One move from `from` to `to` (mm, machine coordinates). `arc` is set for G2/G3: the xy
/// projection is that arc (exact, not flattened), z varies linearly along it (helix).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Rapid, feed or dwell.
    pub kind: MotionKind,
    /// Start point (mm, machine coordinates).
    pub from: DVec3,
    /// End point (mm, machine coordinates).
    pub to: DVec3,
    /// The xy arc of a G2/G3 move (None for straight moves).
    pub arc: Option<Arc>,
    /// Programmed feed in mm/min (0 when none was ever set).
    pub feed: f64,
    /// Spindle or laser state during the move.
    pub tool: ToolState,
    /// 1-based source line.
    pub line: usize,
    /// Group id from the latest `(skinpath:group N)` comment (cleared by
    /// `(skinpath:group end)`): moves of one group belong together for the crossing check.
    pub group: Option<u32>,
}

impl Motion {
    /// Length of the xy projection (arc length for arcs).
    #[must_use]
    pub fn xy_length(&self) -> f64 {
        match &self.arc {
            Some(a) => a.length(),
            None => self.from.truncate().distance(self.to.truncate()),
        }
    }

    /// Length in space: helical arc length √((rθ)² + Δz²) for arcs, chord otherwise.
    #[must_use]
    pub fn length(&self) -> f64 {
        match &self.arc {
            Some(a) => a.length().hypot(self.to.z - self.from.z),
            None => self.from.distance(self.to),
        }
    }

    /// The xy path as points with sagitta ≤ `tol` (start and end included): the chord
    /// flattening of [`Arc::flatten`] for arcs, the two end points for lines.
    #[must_use]
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
    #[must_use]
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
    /// Inlined for straight moves (most of a program's): the caller's copy of the move
    /// is read where it is.
    #[must_use]
    #[inline]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let lo = self.from.min(self.to);
        let hi = self.from.max(self.to);
        match &self.arc {
            Some(a) => arc_bounds(a, lo, hi),
            None => (lo, hi),
        }
    }
}

/// Bounds `lo`..`hi` of a move's end points widened by the extremes of its arc `a`.
fn arc_bounds(a: &Arc, mut lo: DVec3, mut hi: DVec3) -> (DVec3, DVec3) {
    for p in a.extrema() {
        lo = lo.min(p.extend(lo.z));
        hi = hi.max(p.extend(hi.z));
    }
    (lo, hi)
}

/// The motions of a program, stored compactly: 32 bytes per move instead of the 160 of a
/// [`Motion`] (a 10M-move program needs 320 MB instead of 1.6 GB).
///
/// Each move keeps its end point, kind, and either its source line and an index into a
/// table of distinct (feed, tool state, group) states (consecutive moves mostly share one),
/// or an index into a side table holding what few moves have (an arc, a dwell time, a
/// start point that is not the previous move's end, a line or state index too large for
/// the record) together with their line and state. The start point of every other move is the end point of
/// the move before it (compared bit for bit, so nothing is rounded). [`Motion`] values are
/// built on demand by [`Motions::get`] and [`Motions::iter`]; they equal the ones pushed.
#[derive(Clone, Default, PartialEq)]
pub struct Motions {
    recs: Vec<Rec>,
    states: Vec<MoveState>,
    sides: Vec<Side>,
}

/// One stored move (see [`Motions`]).
#[derive(Clone, Copy, PartialEq)]
struct Rec {
    to: [f64; 3],
    /// Source line, or with [`HAS_SIDE`] set in `tag` the index into [`Motions::sides`].
    line_or_side: u32,
    /// Bits 0–1: the kind (0 rapid, 1 feed, 2 dwell); bit 2: [`HAS_SIDE`]; bits 3–31:
    /// the index into [`Motions::states`] (without a side entry).
    tag: u32,
}

/// `Rec::tag` bit of a move with a side entry.
const HAS_SIDE: u32 = 1 << 2;

/// Bits of `Rec::tag` below the state index.
const STATE_SHIFT: u32 = 3;

/// `Rec::tag` mask of the kind.
const KIND_MASK: u32 = 3;

/// Largest state index a record holds itself (29 bits); larger ones go to the side entry.
const MAX_REC_STATE: u32 = u32::MAX >> STATE_SHIFT;

/// What consecutive moves mostly share.
#[derive(Clone, Copy, PartialEq)]
struct MoveState {
    feed: f64,
    tool: ToolState,
    group: Option<u32>,
}

/// What only some moves have.
#[derive(Clone, Copy, PartialEq)]
struct Side {
    /// Start point when it is not the previous move's end (bit for bit).
    from: Option<DVec3>,
    arc: Option<Arc>,
    /// Dwell time of a G4 (seconds).
    seconds: f64,
    /// Source line.
    line: usize,
    /// Index into [`Motions::states`].
    state: u32,
}

fn same_bits(a: DVec3, b: [f64; 3]) -> bool {
    a.x.to_bits() == b[0].to_bits()
        && a.y.to_bits() == b[1].to_bits()
        && a.z.to_bits() == b[2].to_bits()
}

fn same_state(a: &MoveState, b: &MoveState) -> bool {
    a.feed.to_bits() == b.feed.to_bits()
        && a.tool.spindle == b.tool.spindle
        && a.tool.s.to_bits() == b.tool.s.to_bits()
        && a.tool.session == b.tool.session
        && a.group == b.group
}

/// A table index as stored: tables never reach `u32::MAX` entries before memory runs out
/// (that many moves would take 160 GB), and a saturated index still reads a valid entry.
fn index32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX - 1)
}

impl Motions {
    /// An empty list.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of moves.
    pub fn len(&self) -> usize {
        self.recs.len()
    }

    /// True when there is no move.
    pub fn is_empty(&self) -> bool {
        self.recs.is_empty()
    }

    /// Removes every move, keeping the tables' room.
    pub fn clear(&mut self) {
        self.recs.clear();
        self.states.clear();
        self.sides.clear();
    }

    /// Reserves room for `n` more moves.
    pub fn reserve(&mut self, n: usize) {
        self.recs.reserve(n);
    }

    /// Returns unused capacity to the allocator.
    pub fn shrink_to_fit(&mut self) {
        self.recs.shrink_to_fit();
        self.states.shrink_to_fit();
        self.sides.shrink_to_fit();
    }

    /// Bytes held by the tables (capacity, not only length).
    pub fn heap_bytes(&self) -> usize {
        self.recs.capacity() * std::mem::size_of::<Rec>()
            + self.states.capacity() * std::mem::size_of::<MoveState>()
            + self.sides.capacity() * std::mem::size_of::<Side>()
    }

    /// Appends `m`.
    pub fn push(&mut self, m: Motion) {
        let st = MoveState {
            feed: m.feed,
            tool: m.tool,
            group: m.group,
        };
        if !self.states.last().is_some_and(|l| same_state(l, &st)) {
            self.states.push(st);
        }
        let state = index32(self.states.len() - 1);
        let chained = self.recs.last().is_some_and(|r| same_bits(m.from, r.to));
        let (kind, seconds) = match m.kind {
            MotionKind::Rapid => (0, 0.0),
            MotionKind::Feed => (1, 0.0),
            MotionKind::Dwell { seconds } => (2, seconds),
        };
        let line = u32::try_from(m.line).ok();
        let (line_or_side, tag) = match line {
            Some(line) if chained && m.arc.is_none() && kind != 2 && state <= MAX_REC_STATE => {
                (line, kind | state << STATE_SHIFT)
            }
            _ => {
                self.sides.push(Side {
                    from: (!chained).then_some(m.from),
                    arc: m.arc,
                    seconds,
                    line: m.line,
                    state,
                });
                (index32(self.sides.len() - 1), kind | HAS_SIDE)
            }
        };
        self.recs.push(Rec {
            to: m.to.to_array(),
            line_or_side,
            tag,
        });
    }

    /// The move at `i` (built from the tables).
    #[must_use]
    pub fn get(&self, i: usize) -> Option<Motion> {
        let r = self.recs.get(i)?;
        let prev = i
            .checked_sub(1)
            .and_then(|j| self.recs.get(j))
            .map(|p| p.to);
        Some(self.build(r, prev))
    }

    /// The first move.
    #[must_use]
    pub fn first(&self) -> Option<Motion> {
        self.get(0)
    }

    /// The last move.
    #[must_use]
    pub fn last(&self) -> Option<Motion> {
        self.len().checked_sub(1).and_then(|i| self.get(i))
    }

    /// The moves in order.
    #[must_use]
    pub fn iter(&self) -> Iter<'_> {
        Iter {
            list: self,
            next: 0,
            end: self.recs.len(),
            prev: None,
        }
    }

    /// Every move as a [`Motion`] (160 bytes each).
    #[must_use]
    pub fn to_vec(&self) -> Vec<Motion> {
        self.iter().collect()
    }

    #[inline]
    fn build(&self, r: &Rec, prev: Option<[f64; 3]>) -> Motion {
        let side = if r.tag & HAS_SIDE != 0 {
            self.sides.get(r.line_or_side as usize)
        } else {
            None
        };
        let state = side.map_or(r.tag >> STATE_SHIFT, |s| s.state);
        let st = self
            .states
            .get(state as usize)
            .copied()
            .unwrap_or(MoveState {
                feed: 0.0,
                tool: ToolState::default(),
                group: None,
            });
        let to = DVec3::from_array(r.to);
        let from = side
            .and_then(|s| s.from)
            .or(prev.map(DVec3::from_array))
            .unwrap_or(to);
        Motion {
            kind: match r.tag & KIND_MASK {
                0 => MotionKind::Rapid,
                1 => MotionKind::Feed,
                _ => MotionKind::Dwell {
                    seconds: side.map_or(0.0, |s| s.seconds),
                },
            },
            from,
            to,
            arc: side.and_then(|s| s.arc),
            feed: st.feed,
            tool: st.tool,
            line: side.map_or(r.line_or_side as usize, |s| s.line),
            group: st.group,
        }
    }
}

impl std::fmt::Debug for Motions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl FromIterator<Motion> for Motions {
    fn from_iter<I: IntoIterator<Item = Motion>>(it: I) -> Self {
        let mut out = Motions::new();
        for m in it {
            out.push(m);
        }
        out
    }
}

impl Extend<Motion> for Motions {
    fn extend<I: IntoIterator<Item = Motion>>(&mut self, it: I) {
        for m in it {
            self.push(m);
        }
    }
}

impl From<&[Motion]> for Motions {
    fn from(ms: &[Motion]) -> Self {
        ms.iter().copied().collect()
    }
}

impl<'a> IntoIterator for &'a Motions {
    type Item = Motion;
    type IntoIter = Iter<'a>;
    fn into_iter(self) -> Iter<'a> {
        self.iter()
    }
}

/// Iterator over [`Motions`], yielding [`Motion`] values.
#[derive(Clone)]
pub struct Iter<'a> {
    list: &'a Motions,
    /// Index of the next move from the front.
    next: usize,
    /// One past the index of the next move from the back.
    end: usize,
    /// End point of the move before `next` (None before the first).
    prev: Option<[f64; 3]>,
}

impl Iterator for Iter<'_> {
    type Item = Motion;
    #[inline]
    fn next(&mut self) -> Option<Motion> {
        if self.next >= self.end {
            return None;
        }
        let r = self.list.recs.get(self.next)?;
        self.next += 1;
        let m = self.list.build(r, self.prev);
        self.prev = Some(r.to);
        Some(m)
    }
    #[inline]
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.end.saturating_sub(self.next);
        (n, Some(n))
    }
}

impl DoubleEndedIterator for Iter<'_> {
    fn next_back(&mut self) -> Option<Motion> {
        if self.next >= self.end {
            return None;
        }
        self.end -= 1;
        self.list.get(self.end)
    }
}

impl ExactSizeIterator for Iter<'_> {}

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
#[non_exhaustive]
pub struct Program {
    /// The moves, in program order.
    pub motions: Motions,
    /// What the reader found wrong (syntax, unsupported codes, invalid values, ...): at
    /// most `max_findings_per_check` per id from the builtin interpreter.
    pub diagnostics: Vec<super::findings::Finding>,
    /// Per id, diagnostics found after `diagnostics` held `max_findings_per_check` of that
    /// id: counted, not kept (a 20 MB line of repeated words gives millions).
    pub diagnostics_dropped: Vec<(&'static str, usize)>,
    /// How the program ended (None: no M2/M30 or closing `%`).
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
    /// Pocket marks `(skinpath:group N)` with their lines, in the order read (None for
    /// `(skinpath:group none)`). The checks read the mark each move was cut under from the
    /// move ([`Motion::group`]): in a loop or a subroutine, the order read is not the
    /// lines' order.
    pub group_marks: Vec<(usize, Option<u32>)>,
}

/// A machine event that is not a move.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Event {
    /// 1-based source line.
    pub line: usize,
    /// The code as written, e.g. `M8`, `M64 P2`, `M6 T3`.
    pub code: String,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn compact_list_gives_back_what_was_pushed() {
        let on = ToolState {
            spindle: Spindle::Ccw,
            s: 800.0,
            session: 1,
        };
        let mv = |kind, from: [f64; 3], to: [f64; 3], line| Motion {
            kind,
            from: DVec3::from_array(from),
            to: DVec3::from_array(to),
            arc: None,
            feed: 1500.0,
            tool: on,
            line,
            group: None,
        };
        let mut want = [
            mv(MotionKind::Rapid, [0.0; 3], [1.0, 0.0, 0.0], 1),
            mv(MotionKind::Feed, [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], 2),
            // A start that is not the previous end (bit for bit: -0.0 is not 0.0).
            mv(MotionKind::Feed, [2.0, -0.0, 0.0], [3.0, 0.0, 0.0], 3),
            mv(
                MotionKind::Dwell { seconds: 0.5 },
                [3.0, 0.0, 0.0],
                [3.0, 0.0, 0.0],
                4,
            ),
            mv(
                MotionKind::Feed,
                [3.0, 0.0, 0.0],
                [f64::NAN, 0.0, 0.0],
                usize::MAX,
            ),
            mv(
                MotionKind::Feed,
                [f64::NAN, 0.0, 0.0],
                [4.0, 0.0, 0.0],
                u32::MAX as usize,
            ),
        ];
        want[1].arc = Some(Arc::new(DVec2::new(1.5, 0.0), 0.5, PI, -PI));
        want[2].feed = 900.0;
        want[2].group = Some(7);
        want[3].tool.session = 2;
        let list: Motions = want.iter().copied().collect();
        assert_eq!(list.len(), want.len());
        let bits = |m: &Motion| format!("{m:?}");
        let got: Vec<String> = list.iter().map(|m| bits(&m)).collect();
        let exp: Vec<String> = want.iter().map(bits).collect();
        assert_eq!(got, exp);
        assert_eq!(
            list.get(2).map(|m| m.from.y.to_bits()),
            Some((-0.0f64).to_bits())
        );
        for (i, m) in want.iter().enumerate() {
            assert_eq!(list.get(i).map(|g| bits(&g)), Some(bits(m)));
        }
        assert!(list.get(want.len()).is_none());
        let back: Vec<String> = list.iter().rev().map(|m| bits(&m)).collect();
        assert_eq!(back, exp.iter().rev().cloned().collect::<Vec<_>>());
        assert_eq!(std::mem::size_of::<Rec>(), 32);
    }

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
