//! The built-in RS274 interpreter: modal state over lexed lines, producing [`Motion`]s.
//!
//! Supported: G0 G1 G2 G3 (IJ and R forms, full circles with IJ, helices), G4 (P seconds),
//! G17 (G18/G19 are diagnosed: arcs in those planes are skipped), G20/G21, G90/G91,
//! G90.1/G91.1, G54 (identity offsets), G94, G40 G49 G61 G61.1 G64 G80 (no-ops), F, S,
//! M3/M4/M5, M0/M1, M2/M30, M6 T, M7/M8/M9, N words. Per block the RS274 order is applied:
//! units and distance modes, F, S, spindle, dwell, motion, program end. Everything else is a
//! diagnostic [`Finding`] with line and column; interpretation always continues (except that
//! lines after M2/M30 are ignored, as a controller would).

use super::lexer::{LexErrorKind, Word, lex_line};
use super::motion::{Motion, MotionKind, Program, ProgramEnd, Spindle, ToolState, Units};
use super::report::{Finding, Severity};
use crate::geom::{Arc, DVec2, perp};
use glam::DVec3;
use std::f64::consts::TAU;

/// GRBL's ARC_ANGULAR_TRAVEL_EPSILON: an IJ arc whose end direction is within this angle
/// (radians) past its start direction is a full circle.
const ANGULAR_EPSILON: f64 = 5e-7;

/// Relative part of the IJ radius check: the radii may also differ by 0.1 % of the radius
/// (GRBL's rule: error only when both the absolute and relative limits are exceeded).
const RADIUS_RELATIVE_TOLERANCE: f64 = 1e-3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum MotionMode {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Plane {
    Xy,
    Xz,
    Yz,
}

/// Modal state of the interpreter.
#[derive(Clone, Debug)]
struct State {
    pos: DVec3,
    units: Units,
    absolute: bool,
    arc_absolute: bool,
    plane: Plane,
    mode: Option<MotionMode>,
    /// Programmed F in the units current when it is used (RS274: F is in current units).
    feed: f64,
    tool: ToolState,
}

impl Default for State {
    fn default() -> Self {
        State {
            pos: DVec3::ZERO,
            units: Units::Mm,
            absolute: true,
            arc_absolute: false,
            plane: Plane::Xy,
            mode: None,
            feed: 0.0,
            tool: ToolState::default(),
        }
    }
}

/// Interprets G-code text. `arc_radius_tol` (mm) bounds |r_start − r_end| of IJ arcs and the
/// shortfall of R arcs whose radius is less than half the chord.
pub fn interpret(src: &str, arc_radius_tol: f64) -> Program {
    let mut prog = Program::default();
    let mut st = State::default();
    let mut ended_at: Option<usize> = None;
    let mut after_end_reported = false;
    for (idx, raw) in src.split('\n').enumerate() {
        let line_no = idx + 1;
        prog.lines = line_no;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        let lexed = lex_line(raw);
        for e in &lexed.errors {
            prog.diagnostics
                .push(lex_finding(e.column, &e.kind, line_no));
        }
        super::checks::contours::note_group_marks(&lexed.comments, line_no, &mut prog.group_marks);
        if lexed.words.is_empty() {
            continue;
        }
        if let Some(end) = ended_at {
            if !after_end_reported {
                after_end_reported = true;
                prog.diagnostics.push(
                    Finding::new(
                        "after-program-end",
                        Severity::Warning,
                        format!("words after the program end on line {end} are ignored"),
                    )
                    .line(line_no),
                );
            }
            continue;
        }
        prog.last_line = line_no;
        let mut b = Block::new(line_no);
        b.collect(&lexed.words, &mut prog);
        if b.execute(&mut st, &mut prog, arc_radius_tol) {
            ended_at = Some(line_no);
        }
    }
    prog.final_tool = st.tool;
    prog
}

fn lex_finding(column: usize, kind: &LexErrorKind, line: usize) -> Finding {
    let (id, msg) = match kind {
        LexErrorKind::MissingNumber(c) => ("gcode-syntax", format!("'{c}' without a number")),
        LexErrorKind::Unexpected(c) => ("gcode-syntax", format!("unexpected character {c:?}")),
        LexErrorKind::UnclosedComment => ("gcode-syntax", "'(' comment not closed".into()),
        LexErrorKind::MalformedChecksum => ("bad-checksum", "'*' without a checksum".into()),
        LexErrorKind::BadChecksum { expected, found } => (
            "bad-checksum",
            format!("checksum {found} does not match the line (expected {expected})"),
        ),
        LexErrorKind::TrailingAfterChecksum => {
            ("gcode-syntax", "text after the checksum".to_string())
        }
    };
    Finding::new(id, Severity::Error, msg)
        .line(line)
        .column(column)
}

/// The words of one block sorted into what the interpreter needs.
#[derive(Default)]
struct Block {
    line: usize,
    g_motion: Option<(MotionMode, usize)>,
    dwell: bool,
    plane: Option<Plane>,
    units: Option<Units>,
    absolute: Option<bool>,
    arc_absolute: Option<bool>,
    spindle: Option<Spindle>,
    end: bool,
    /// Letter values: X Y Z I J K R F S P, in this order.
    vals: [Option<f64>; 10],
    cols: [usize; 10],
}

const LETTERS: [char; 10] = ['X', 'Y', 'Z', 'I', 'J', 'K', 'R', 'F', 'S', 'P'];

impl Block {
    fn new(line: usize) -> Self {
        Block {
            line,
            ..Default::default()
        }
    }

    fn diag(&self, prog: &mut Program, id: &'static str, sev: Severity, col: usize, msg: String) {
        prog.diagnostics
            .push(Finding::new(id, sev, msg).line(self.line).column(col));
    }

    fn val(&self, c: char) -> Option<f64> {
        LETTERS
            .iter()
            .position(|&l| l == c)
            .and_then(|i| self.vals[i])
    }

    fn collect(&mut self, words: &[Word], prog: &mut Program) {
        for w in words {
            let col = w.column;
            match w.letter {
                'G' => self.g_code(w, prog),
                'M' => self.m_code(w, prog),
                'N' | 'T' | 'Q' => prog.words += 1,
                c => match LETTERS.iter().position(|&l| l == c) {
                    Some(i) => {
                        prog.words += 1;
                        if self.vals[i].is_some() {
                            self.diag(
                                prog,
                                "duplicate-word",
                                Severity::Error,
                                col,
                                format!("{c} appears twice in the block; the first is used"),
                            );
                        } else {
                            self.vals[i] = Some(w.value);
                            self.cols[i] = col;
                        }
                    }
                    None => self.diag(
                        prog,
                        "unknown-word",
                        Severity::Warning,
                        col,
                        format!("word {c}{} is not supported and ignored", w.value),
                    ),
                },
            }
        }
    }

    /// The code as an integer number of tenths (G90.1 → 901), None if not a tenth.
    fn tenths(v: f64) -> Option<i64> {
        let t = (v * 10.0).round();
        ((v * 10.0 - t).abs() < 1e-6 && t.abs() < 1e9).then_some(t as i64)
    }

    fn g_code(&mut self, w: &Word, prog: &mut Program) {
        let col = w.column;
        let Some(code) = Self::tenths(w.value) else {
            self.diag(
                prog,
                "unknown-code",
                Severity::Error,
                col,
                format!("G{} is not a G-code", w.value),
            );
            return;
        };
        prog.words += 1;
        let motion = |m| Some(m);
        let mm = match code {
            0 => motion(MotionMode::Rapid),
            10 => motion(MotionMode::Linear),
            20 => motion(MotionMode::ArcCw),
            30 => motion(MotionMode::ArcCcw),
            _ => None,
        };
        if let Some(m) = mm {
            if let Some((_, c0)) = self.g_motion {
                self.diag(
                    prog,
                    "modal-conflict",
                    Severity::Error,
                    col,
                    format!(
                        "two motion codes in one block (first at column {c0}); the last is used"
                    ),
                );
            }
            self.g_motion = Some((m, col));
            return;
        }
        match code {
            40 => self.dwell = true,
            170 => self.plane = Some(Plane::Xy),
            180 | 190 => {
                self.plane = Some(if code == 180 { Plane::Xz } else { Plane::Yz });
                self.diag(
                    prog,
                    "unsupported-code",
                    Severity::Error,
                    col,
                    format!(
                        "G{} plane selection is not supported: arcs in it are skipped",
                        code / 10
                    ),
                );
            }
            200 => self.units = Some(Units::Inch),
            210 => self.units = Some(Units::Mm),
            900 => self.absolute = Some(true),
            910 => self.absolute = Some(false),
            901 => self.arc_absolute = Some(true),
            911 => self.arc_absolute = Some(false),
            // Work offset 1 (identity here), feed per minute, cancel codes, path control.
            540 | 940 | 400 | 490 | 800 | 610 | 611 | 640 => {}
            280
            | 300
            | 530
            | 550
            | 560
            | 570
            | 580
            | 590
            | 920
            | 930
            | 410
            | 420
            | 430
            | 100
            | 50
            | 51
            | 382
            | 383
            | 384
            | 385
            | 810..=890 => self.diag(
                prog,
                "unsupported-code",
                Severity::Error,
                col,
                format!(
                    "G{} is not supported: the motion after it may be wrong",
                    fmt_code(code)
                ),
            ),
            _ => self.diag(
                prog,
                "unknown-code",
                Severity::Error,
                col,
                format!("unknown code G{}", fmt_code(code)),
            ),
        }
    }

    fn m_code(&mut self, w: &Word, prog: &mut Program) {
        let col = w.column;
        let code = Self::tenths(w.value);
        if code.is_some() {
            prog.words += 1;
        }
        match code {
            Some(30) => self.spindle = Some(Spindle::Cw),
            Some(40) => self.spindle = Some(Spindle::Ccw),
            Some(50) => self.spindle = Some(Spindle::Off),
            Some(20) | Some(300) => self.end = true,
            // Pause, optional pause, tool change, coolant.
            Some(0) | Some(10) | Some(60) | Some(70) | Some(80) | Some(90) => {}
            _ => self.diag(
                prog,
                "unknown-code",
                Severity::Warning,
                col,
                format!("unknown code M{} ignored", w.value),
            ),
        }
    }

    /// Runs the block; returns true at a program end.
    fn execute(&self, st: &mut State, prog: &mut Program, arc_tol: f64) -> bool {
        if let Some(u) = self.units {
            st.units = u;
        }
        if let Some(a) = self.absolute {
            st.absolute = a;
        }
        if let Some(a) = self.arc_absolute {
            st.arc_absolute = a;
        }
        if let Some(p) = self.plane {
            st.plane = p;
        }
        let k = st.units.to_mm();
        if let Some(f) = self.val('F') {
            if f > 0.0 {
                st.feed = f;
            } else {
                self.diag(
                    prog,
                    "invalid-value",
                    Severity::Error,
                    self.cols[7],
                    format!("feed F{f} must be positive"),
                );
            }
        }
        let mut next = (st.tool.spindle, st.tool.s);
        if let Some(s) = self.val('S') {
            if s >= 0.0 {
                next.1 = s;
            } else {
                self.diag(
                    prog,
                    "invalid-value",
                    Severity::Error,
                    self.cols[8],
                    format!("S{s} must not be negative"),
                );
            }
        }
        if let Some(sp) = self.spindle {
            next.0 = sp;
        }
        st.tool.switch(next.0, next.1);
        if self.dwell {
            match self.val('P') {
                Some(p) if p >= 0.0 => prog.motions.push(Motion {
                    kind: MotionKind::Dwell { seconds: p },
                    from: st.pos,
                    to: st.pos,
                    arc: None,
                    feed: st.feed * k,
                    tool: st.tool,
                    line: self.line,
                }),
                _ => self.diag(
                    prog,
                    "invalid-value",
                    Severity::Error,
                    1,
                    "G4 needs P with the dwell in seconds (P ≥ 0)".into(),
                ),
            }
        }
        if let Some((m, _)) = self.g_motion {
            st.mode = Some(m);
        }
        let has_axis =
            self.val('X').is_some() || self.val('Y').is_some() || self.val('Z').is_some();
        let has_arc_word =
            self.val('I').is_some() || self.val('J').is_some() || self.val('R').is_some();
        if has_axis || (has_arc_word && !self.dwell) {
            match st.mode {
                None => self.diag(
                    prog,
                    "no-motion-mode",
                    Severity::Error,
                    1,
                    "axis words before any G0/G1/G2/G3".into(),
                ),
                Some(mode) => self.motion(mode, st, prog, arc_tol),
            }
        }
        if self.end {
            prog.end = Some(ProgramEnd {
                line: self.line,
                tool_before: st.tool,
            });
            // M2/M30 stop the spindle and reset the distance mode on real controllers.
            st.tool.switch(Spindle::Off, st.tool.s);
            st.absolute = true;
            return true;
        }
        false
    }

    fn target(&self, st: &State) -> DVec3 {
        let k = st.units.to_mm();
        let mut t = st.pos;
        for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let Some(v) = self.val(c) {
                t[i] = if st.absolute { v * k } else { t[i] + v * k };
            }
        }
        t
    }

    fn motion(&self, mode: MotionMode, st: &mut State, prog: &mut Program, arc_tol: f64) {
        let to = self.target(st);
        let from = st.pos;
        let k = st.units.to_mm();
        let mut m = Motion {
            kind: MotionKind::Feed,
            from,
            to,
            arc: None,
            feed: st.feed * k,
            tool: st.tool,
            line: self.line,
        };
        match mode {
            MotionMode::Rapid | MotionMode::Linear => {
                if mode == MotionMode::Rapid {
                    m.kind = MotionKind::Rapid;
                }
                if from != to {
                    prog.motions.push(m);
                }
            }
            MotionMode::ArcCw | MotionMode::ArcCcw => {
                if st.plane != Plane::Xy {
                    self.diag(
                        prog,
                        "unsupported-code",
                        Severity::Error,
                        1,
                        "arc outside the XY plane (G18/G19) skipped".into(),
                    );
                } else {
                    match self.arc(mode == MotionMode::ArcCcw, st, from, to, arc_tol) {
                        Ok(a) => {
                            m.arc = Some(a);
                            prog.motions.push(m);
                        }
                        Err(msg) => self.diag(prog, "invalid-arc", Severity::Error, 1, msg),
                    }
                }
            }
        }
        st.pos = to;
    }

    /// The xy arc of a G2/G3 block from `from` to `to`.
    fn arc(&self, ccw: bool, st: &State, from: DVec3, to: DVec3, tol: f64) -> Result<Arc, String> {
        let k = st.units.to_mm();
        let p0 = from.truncate();
        let p1 = to.truncate();
        let center = if let Some(r) = self.val('R') {
            if self.val('I').is_some() || self.val('J').is_some() {
                return Err("arc with both R and I/J".into());
            }
            r_center(p0, p1, r * k, ccw, tol)?
        } else {
            let off = DVec2::new(
                self.val('I').unwrap_or(0.0) * k,
                self.val('J').unwrap_or(0.0) * k,
            );
            let c = if st.arc_absolute { off } else { p0 + off };
            let r0 = p0.distance(c);
            let r1 = p1.distance(c);
            if r0 == 0.0 {
                return Err("arc centre at its start point".into());
            }
            let diff = (r0 - r1).abs();
            if diff > tol && diff > RADIUS_RELATIVE_TOLERANCE * r0 {
                return Err(format!(
                    "radius to end {r1:.4} differs from radius to start {r0:.4} by {diff:.4} mm"
                ));
            }
            c
        };
        Ok(arc_between(center, p0, p1, ccw))
    }
}

/// Centre of the arc of signed radius `r` from `p0` to `p1` (RS274 R format: r > 0 takes the
/// arc of at most a half turn, r < 0 the larger one). The centre lies on the chord bisector at
/// h = √(r² − d²/4) (d the chord length), left of p0→p1 for a short CCW arc.
fn r_center(p0: DVec2, p1: DVec2, r: f64, ccw: bool, tol: f64) -> Result<DVec2, String> {
    let chord = p1 - p0;
    let d = chord.length();
    if d == 0.0 {
        return Err("R-format arc with coincident end points (use I/J for a full circle)".into());
    }
    if r == 0.0 {
        return Err("R-format arc with zero radius".into());
    }
    let h2 = r * r - 0.25 * d * d;
    let h = if h2 >= 0.0 {
        h2.sqrt()
    } else if 0.5 * d - r.abs() <= tol {
        0.0
    } else {
        return Err(format!(
            "radius {:.4} is less than half the chord {:.4}",
            r.abs(),
            0.5 * d
        ));
    };
    let mut side = if ccw { 1.0 } else { -1.0 };
    if r < 0.0 {
        side = -side;
    }
    Ok(0.5 * (p0 + p1) + side * h * perp(chord) / d)
}

/// The arc about `center` from `p0` to the direction of `p1`, with GRBL's full-circle rule:
/// an end direction within [`ANGULAR_EPSILON`] past the start makes a full turn.
fn arc_between(center: DVec2, p0: DVec2, p1: DVec2, ccw: bool) -> Arc {
    let a0 = (p0 - center).to_angle();
    let a1 = (p1 - center).to_angle();
    let mut sweep = (a1 - a0).rem_euclid(TAU);
    if ccw {
        if sweep <= ANGULAR_EPSILON {
            sweep += TAU;
        }
    } else {
        sweep -= TAU;
        if sweep >= -ANGULAR_EPSILON {
            sweep -= TAU;
        }
    }
    if sweep.abs() > TAU {
        sweep = sweep.signum() * TAU;
    }
    Arc::new(center, p0.distance(center), a0, sweep)
}

fn fmt_code(tenths: i64) -> String {
    if tenths % 10 == 0 {
        (tenths / 10).to_string()
    } else {
        format!("{}.{}", tenths / 10, (tenths % 10).abs())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn run(src: &str) -> Program {
        interpret(src, 0.005)
    }

    fn ids(p: &Program) -> Vec<(&'static str, usize)> {
        p.diagnostics
            .iter()
            .map(|d| (d.id, d.lines.first().copied().unwrap_or(0)))
            .collect()
    }

    #[test]
    fn modal_lines_inch_relative() {
        let p = run("G20 G91\nG1 X1 Y1 F10\nX1\nG90 G0 X0 Y0\nM2");
        assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
        assert_eq!(p.motions.len(), 3);
        let m = &p.motions[1];
        assert!((m.to - DVec3::new(50.8, 25.4, 0.0)).length() < 1e-12);
        assert_eq!(m.line, 3);
        assert!((m.feed - 254.0).abs() < 1e-12);
        assert_eq!(p.motions[2].kind, MotionKind::Rapid);
        assert_eq!(p.end.map(|e| e.line), Some(5));
    }

    #[test]
    fn ij_arcs_and_full_circle() {
        // Quarter CCW about the origin, then a CW full circle about (0, 0).
        let p = run("G0 X10 Y0\nG3 X0 Y10 I-10 J0 F100\nG2 X0 Y10 I0 J-10");
        assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
        let q = p.motions[1]
            .arc
            .unwrap_or(Arc::new(DVec2::ZERO, 0.0, 0.0, 0.0));
        assert!((q.sweep - PI / 2.0).abs() < 1e-12);
        assert!((p.motions[1].length() - 5.0 * PI).abs() < 1e-9);
        let c = p.motions[2].arc.unwrap_or(q);
        assert!((c.sweep + 2.0 * PI).abs() < 1e-12);
        assert!(c.center.length() < 1e-12);
        // Absolute IJ gives the same arc.
        let a = run("G90.1\nG0 X10 Y0\nG3 X0 Y10 I0 J0 F100");
        assert_eq!(a.motions[1].arc, p.motions[1].arc);
    }

    #[test]
    fn r_arcs_short_and_long() {
        for (code, r, sweep) in [
            ("G3", 10.0, PI / 2.0),
            ("G3", -10.0, 1.5 * PI),
            ("G2", 10.0, -PI / 2.0),
            ("G2", -10.0, -1.5 * PI),
        ] {
            let p = run(&format!("G0 X10 Y0\n{code} X0 Y10 R{r} F50"));
            assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
            let a = p.motions[1]
                .arc
                .unwrap_or(Arc::new(DVec2::ZERO, 0.0, 0.0, 0.0));
            assert!((a.sweep - sweep).abs() < 1e-9, "{code} R{r}: {}", a.sweep);
            assert!((a.radius - 10.0).abs() < 1e-9);
            assert!((a.p1() - DVec2::new(0.0, 10.0)).length() < 1e-9);
        }
    }

    #[test]
    fn bad_arcs_are_diagnosed() {
        let p = run("G0 X10\nG3 X0 Y12 I-10 F10\nG2 X10 Y12 R1\nG2 X10 Y12 R5");
        assert_eq!(
            ids(&p),
            vec![("invalid-arc", 2), ("invalid-arc", 3), ("invalid-arc", 4)]
        );
    }

    #[test]
    fn tool_state_and_dwell() {
        let p = run("M4 S300\nG1 X5 F200\nG4 P1.5\nM5\nG0 X0\nM30");
        assert_eq!(p.motions[0].tool.spindle, Spindle::Ccw);
        assert_eq!(p.motions[0].tool.s, 300.0);
        assert_eq!(p.motions[1].kind, MotionKind::Dwell { seconds: 1.5 });
        assert!(!p.motions[2].tool.is_on());
        assert!(p.end.is_some());
    }

    #[test]
    fn diagnostics_keep_going() {
        let p = run("G1 X1 F10\nG1 X2 E5\nG28\nM123\nG1 G0 X3\nX4 X5\nG1 Q\nG1 X6\nM2\nG1 X7");
        let got = ids(&p);
        for want in [
            ("unknown-word", 2),
            ("unsupported-code", 3),
            ("unknown-code", 4),
            ("modal-conflict", 5),
            ("duplicate-word", 6),
            ("gcode-syntax", 7),
            ("after-program-end", 10),
        ] {
            assert!(got.contains(&want), "{want:?} not in {got:?}");
        }
        assert!((p.motions.last().map(|m| m.to.x).unwrap_or(0.0) - 6.0).abs() < 1e-12);
        assert_eq!(p.diagnostics[0].column, Some(7));
    }

    #[test]
    fn no_motion_mode() {
        let p = run("X1 Y1");
        assert_eq!(ids(&p), vec![("no-motion-mode", 1)]);
        assert!(p.motions.is_empty());
    }
}
