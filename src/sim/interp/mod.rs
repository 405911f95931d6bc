//! The built-in RS274NGC interpreter: LinuxCNC's language (parameters, expressions, O-word
//! subroutines and loops, see [`super::ngc`]) and modal codes over parsed lines, producing
//! [`Motion`]s in machine millimetres.
//!
//! Per block the RS274NGC order of execution is applied (LinuxCNC manual, "G-code overview:
//! Order of execution"): comments and messages, feed mode, F, S, T, M6/M61, spindle,
//! coolant, dwell, plane, units, cutter compensation, tool length offset, coordinate
//! system, path control, distance modes, retract mode, G10/G28/G30/G52/G92, motion, stops.
//! Parameter assignments take effect after every value of the block has been read.
//!
//! Supported codes: G0 G1 G2 G3 (IJK and R forms, helices, arcs in G17/G18/G19; arcs outside
//! XY become chords within [`CHORD_ANGLE`]), G4, G7/G8, G10 L1/L2/L10/L11/L20, G17–G19,
//! G20/G21, G28/G28.1/G30/G30.1, G40 (G41/G42 only with a zero tool radius), G43/G43.1/G49,
//! G52, G53, G54–G59.3, G61/G61.1/G64, G73 G80–G86 G88 G89 (expanded into moves), G90/G91,
//! G90.1/G91.1, G92/G92.1/G92.2/G92.3, G93/G94/G95, G96/G97, G98/G99, M0 M1 M2 M30 M60, M3
//! M4 M5, M6 M61 T, M7 M8 M9, M48–M53, M62–M68 (events). G38.x and user M-codes (M100–M199)
//! are "cannot be simulated": later moves are uncertain. Everything else is "not supported"
//! with its code and line. Interpretation goes on after an error, except for errors that
//! make the rest meaningless (loop limit, recursion, `(abort,…)`).
//!
//! Nothing after M2/M30 or the closing `%` is interpreted.

use super::config::{CheckConfig, Dialect, ToolEntry};
use super::findings::{Finding, Severity};
use super::motion::{Event, Motion, MotionKind, Program, ProgramEnd, Spindle, ToolState, Units};
use super::ngc::{self, Expr, Line, OKind, ParamRef, ParamSource, Syntax};
use crate::geom::{Arc, DVec2, perp};
use glam::DVec3;
use std::borrow::Cow;
use std::collections::HashMap;
use std::f64::consts::TAU;

mod cycles;
mod execute;
mod modal;
mod moves;
mod offsets;
mod oword;
mod params;
mod source;
#[cfg(test)]
mod tests;

use modal::*;
use source::*;
pub use source::{MotionSink, ReadSeek, Scan};

/// GRBL's ARC_ANGULAR_TRAVEL_EPSILON: an IJ arc whose end direction is within this angle
/// (radians) past its start direction is a full circle.
const ANGULAR_EPSILON: f64 = 5e-7;

/// Relative part of the IJ radius check (LinuxCNC `spiral_rel_tolerance` default 0.001,
/// GRBL's 0.1 %): an error needs both the absolute and this relative difference.
const RADIUS_RELATIVE_TOLERANCE: f64 = 1e-3;

/// LinuxCNC's absolute IJ radius tolerance in mm programs (`CENTER_ARC_RADIUS_TOLERANCE_MM`
/// = 0.02 mm); differences beyond 100 times it are errors regardless of the radius.
const LINUXCNC_RADIUS_TOLERANCE_MM: f64 = 0.02;

/// LinuxCNC's absolute IJ radius tolerance in inch programs
/// (`CENTER_ARC_RADIUS_TOLERANCE_INCH` = 0.002 inch).
const LINUXCNC_RADIUS_TOLERANCE_INCH: f64 = 0.002;

/// Largest angle (radians) of one chord when an arc outside the XY plane is split: the
/// chord length deficit per chord is θ²/24 < 1e-5 relative, well inside the 1e-4 budget
/// for cut lengths compared with LinuxCNC.
pub const CHORD_ANGLE: f64 = 0.015;

/// Deepest subroutine nesting (LinuxCNC `INTERP_SUB_ROUTINE_LEVELS`).
pub const MAX_CALL_DEPTH: usize = 10;

/// G73/G83 retract clearance (LinuxCNC `G83_RAPID_DELTA`: 0.010 inch, 0.254 mm).
const PECK_CLEARANCE_MM: f64 = 0.254;

/// Largest arc radius accepted (mm): 10 km, far beyond any machine, while keeping the
/// centre's coordinates within the range where points on the circle are computed to well
/// under a micrometre (|c| · 2⁻⁵² ≈ 2·10⁻⁹ mm). Larger radii (`R[10**300]`) and
/// non-finite centres are `invalid-arc` errors.
const MAX_ARC_RADIUS_MM: f64 = 1e7;

/// Numbered parameters holding stored positions (LinuxCNC manual, "Numbered parameters").
const P_G28: usize = 5161;
const P_G30: usize = 5181;
const P_G92: usize = 5211;
const P_CS: usize = 5220;
const P_G54: usize = 5221;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
    /// Canned cycle G73, G81–G89 (code × 10).
    Cycle(i64),
    /// G80: no motion mode.
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Plane {
    Xy,
    Xz,
    Yz,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FeedMode {
    PerMinute,
    InverseTime,
    PerRev,
}

/// Returns the text of subroutine file `<name>.ngc` from a search path, if any.
pub type SubLoader<'a> = &'a dyn LoadSub;

/// A source of subroutine files. Any `Fn(&str) -> Option<String>` is one (None: no such
/// file); [`CheckedLoader`] wraps a loader that can also refuse a file it found.
pub trait LoadSub {
    /// The text of `<name>.ngc`: `Ok(None)` when there is no such file, `Err(reason)` when
    /// there is one that cannot be read (not a regular file, too large, unreadable).
    fn load(&self, name: &str) -> Result<Option<String>, String>;
}

impl<F: Fn(&str) -> Option<String>> LoadSub for F {
    fn load(&self, name: &str) -> Result<Option<String>, String> {
        Ok(self(name))
    }
}

/// A loader `Fn(&str) -> Result<Option<String>, String>` as a [`LoadSub`]: its errors
/// become `o-word` errors on the line of the call.
pub struct CheckedLoader<F>(pub F);

impl<F: Fn(&str) -> Result<Option<String>, String>> LoadSub for CheckedLoader<F> {
    fn load(&self, name: &str) -> Result<Option<String>, String> {
        (self.0)(name)
    }
}

/// Options beyond [`CheckConfig`]: where called subroutine files come from.
#[derive(Default)]
#[non_exhaustive]
pub struct Options<'a> {
    /// Loader of called subroutine files (`o<name> call` of a sub not in the program); None: such calls are errors.
    pub load_sub: Option<SubLoader<'a>>,
}

impl<'a> Options<'a> {
    /// Called subroutine files come from `loader`.
    #[must_use]
    pub fn with_loader(loader: SubLoader<'a>) -> Self {
        Options {
            load_sub: Some(loader),
        }
    }
}

/// One O-word statement found by the pre-scan.
#[derive(Clone, Copy, Debug)]
struct OPos {
    line: usize,
    kind: OKind,
    /// A `while` that closes a `do` loop.
    do_while: bool,
}

struct CallFrame {
    ret: (usize, usize),
    locals: HashMap<String, f64>,
    saved: [f64; 30],
    repeats: usize,
    /// State saved by M73, restored at the return.
    autorestore: Option<State>,
}

struct Interp<'a, 'o> {
    cfg: &'o CheckConfig,
    opts: &'o Options<'o>,
    syn: Syntax,
    sources: Vec<Source<'a>>,
    /// (source, label) → O-word statements in line order.
    olines: HashMap<(usize, String), Vec<OPos>>,
    subs: HashMap<String, (usize, usize)>,
    prog: Program,
    st: State,
    params: Vec<f64>,
    globals: HashMap<String, f64>,
    calls: Vec<CallFrame>,
    locals: HashMap<String, f64>,
    /// Active repeat loops: (source, label, start line, iterations left).
    repeats: Vec<(usize, String, usize, f64)>,
    iterations: u64,
    /// Current source line (1-based, in the source being read) for findings.
    line: usize,
    src: usize,
    /// The line was reached by skipping (if/elseif evaluation).
    jumped: bool,
    group: Option<u32>,
    value: Option<f64>,
    stop: bool,
    reported_axes: bool,
    saved_state: Option<State>,
    /// Per source: lines below this index have been read before.
    high_water: Vec<usize>,
    cache: HashMap<(usize, usize), std::rc::Rc<Line>>,
    /// The tool table (G10 L1/L10/L11 edit this copy).
    tools: Vec<ToolEntry>,
    /// The evaluated words of the current block (a buffer reused from line to line).
    word_buf: Vec<(char, f64, usize)>,
    /// The spindle/laser as M2/M30 found it, after the rest of its block (an M5 in the same
    /// block runs first) and before the stop turns it off.
    tool_at_stop: ToolState,
    /// Plain motion blocks take [`Interp::plain_block`] (off only to test it against the
    /// general route).
    plain_moves: bool,
    /// Per id, diagnostics kept so far (see [`Interp::diagnose`]).
    diag_kept: HashMap<&'static str, usize>,
    /// (source, line) of the last `no-feed-rate` finding: one per line, however many moves
    /// the line makes (arcs, canned cycles).
    no_feed_at: Option<(usize, usize)>,
}

#[derive(Clone, Debug)]
struct State {
    pos: DVec3,
    units: Units,
    absolute: bool,
    arc_absolute: bool,
    plane: Plane,
    mode: Mode,
    feed_mode: FeedMode,
    /// Programmed F in the units current when it was given.
    feed: f64,
    feed_k: f64,
    tool: ToolState,
    cs: usize,
    g5x: DVec3,
    g92: DVec3,
    tlo: DVec3,
    current_tool: u32,
    selected_tool: u32,
    retract_r: bool,
    cycle_r: Option<f64>,
    cycle_z: Option<f64>,
    cycle_q: Option<f64>,
    cycle_p: Option<f64>,
    /// Z (machine) when the current series of canned cycles started.
    cycle_start_z: Option<f64>,
    diameter_mode: bool,
    comp: bool,
    flood: bool,
    mist: bool,
}

impl Default for State {
    fn default() -> Self {
        State {
            pos: DVec3::ZERO,
            units: Units::Mm,
            absolute: true,
            arc_absolute: false,
            plane: Plane::Xy,
            mode: Mode::Off,
            feed_mode: FeedMode::PerMinute,
            feed: 0.0,
            feed_k: 1.0,
            tool: ToolState::default(),
            cs: 1,
            g5x: DVec3::ZERO,
            g92: DVec3::ZERO,
            tlo: DVec3::ZERO,
            current_tool: 0,
            selected_tool: 0,
            cycle_r: None,
            cycle_z: None,
            cycle_q: None,
            cycle_p: None,
            cycle_start_z: None,
            // rs274 starts in G99 (retract to R), as its canon output shows.
            retract_r: true,
            diameter_mode: false,
            comp: false,
            flood: false,
            mist: false,
        }
    }
}

impl State {
    fn k(&self) -> f64 {
        self.units.to_mm()
    }
    /// Offsets from program to machine coordinates.
    fn offset(&self) -> DVec3 {
        self.g5x + self.g92 + self.tlo
    }
    fn program_pos(&self) -> DVec3 {
        self.pos - self.offset()
    }
}

/// Interprets G-code text with the default configuration (generic dialect) and IJ radius
/// tolerance `arc_radius_tol` (mm).
#[allow(dead_code)] // the benches' entry (`crate::internals`) and the tests'
#[must_use]
pub fn interpret(src: &str, arc_radius_tol: f64) -> Program {
    let cfg = CheckConfig {
        arc_radius_tolerance: arc_radius_tol,
        ..CheckConfig::default()
    };
    interpret_with(src, &cfg, &Options { load_sub: None })
}

/// A fresh interpreter for `cfg` (mm) and `opts`, without a source.
fn new_interp<'a, 'o>(cfg: &'o CheckConfig, opts: &'o Options<'o>) -> Interp<'a, 'o> {
    let syn = match cfg.dialect {
        Dialect::Generic => Syntax {
            ngc: true,
            checksums: true,
            dollar: false,
        },
        Dialect::Linuxcnc => Syntax {
            ngc: true,
            checksums: false,
            dollar: false,
        },
        Dialect::Grbl => Syntax {
            ngc: false,
            checksums: false,
            dollar: true,
        },
        Dialect::Marlin | Dialect::Smoothie => Syntax {
            ngc: false,
            checksums: true,
            dollar: false,
        },
    };
    let mut it = Interp {
        cfg,
        opts,
        syn,
        sources: Vec::new(),
        olines: HashMap::new(),
        subs: HashMap::new(),
        prog: Program::default(),
        st: State::default(),
        params: vec![0.0; ngc::MAX_PARAMETER as usize + 1],
        globals: HashMap::new(),
        calls: Vec::new(),
        locals: HashMap::new(),
        repeats: Vec::new(),
        iterations: 0,
        line: 0,
        src: 0,
        jumped: false,
        group: None,
        value: None,
        stop: false,
        reported_axes: false,
        saved_state: None,
        high_water: Vec::new(),
        cache: HashMap::new(),
        tools: cfg.tool_table.clone(),
        word_buf: Vec::new(),
        tool_at_stop: ToolState::default(),
        plain_moves: true,
        diag_kept: HashMap::new(),
        no_feed_at: None,
    };
    it.params[P_CS] = 1.0;
    it
}

/// Interprets G-code text. `cfg` must be in mm ([`CheckConfig::in_mm`]): its dialect, tool
/// table, loop budget and IJ radius tolerance apply.
#[must_use]
pub fn interpret_with(src: &str, cfg: &CheckConfig, opts: &Options<'_>) -> Program {
    interpret_text(src, cfg, opts, None)
}

/// [`interpret_with`], handing the moves to `sink` in chunks as they are produced instead
/// of keeping them: the returned program has no motions.
pub fn interpret_each(
    src: &str,
    cfg: &CheckConfig,
    opts: &Options<'_>,
    sink: MotionSink<'_>,
) -> Program {
    interpret_text(src, cfg, opts, Some(sink))
}

/// [`interpret_with`] storing the moves, or [`interpret_each`] handing them to `sink`.
fn interpret_text(
    src: &str,
    cfg: &CheckConfig,
    opts: &Options<'_>,
    sink: Option<MotionSink<'_>>,
) -> Program {
    let mut it = new_interp(cfg, opts);
    it.add_source("program".into(), Cow::Borrowed(src));
    if sink.is_none() {
        // About one move per line: reserving it up front avoids the doubling growth whose
        // spare capacity would count against an address-space limit on long programs; the
        // unused part is returned at the end.
        let lines = it.sources.first().map_or(0, |s| s.len());
        it.prog.motions.reserve(lines);
    }
    it.run(sink);
    it.prog.motions.shrink_to_fit();
    it.prog.final_tool = it.st.tool;
    it.prog
}

/// Interprets a program read line by line from `input` (never held whole in memory), handing
/// the moves to `sink` as they are produced instead of keeping them: the returned program
/// has no motions. `cfg` as for [`interpret_with`]. Returns the pre-scan's facts beside it,
/// or the read error.
pub fn interpret_stream<'a>(
    mut input: Box<dyn ReadSeek + 'a>,
    cfg: &CheckConfig,
    opts: &Options<'_>,
    sink: MotionSink<'_>,
) -> std::io::Result<(Program, Scan)> {
    let mut it = new_interp(cfg, opts);
    let mut sc = scan(&mut *input, it.syn)?;
    let owords = std::mem::take(&mut sc.owords);
    let stream = LineStream {
        reader: std::io::BufReader::with_capacity(1 << 16, input),
        checkpoints: std::mem::take(&mut sc.checkpoints),
        len: sc.lines,
        cur: usize::MAX,
        buf: String::new(),
        raw: Vec::new(),
        error: None,
    };
    let src = Source {
        name: "program".into(),
        body: Body::Stream(Box::new(stream)),
    };
    it.push_source(src, owords);
    it.run(Some(sink));
    it.prog.final_tool = it.st.tool;
    let error = match it.sources.first().map(|s| &s.body) {
        Some(Body::Stream(s)) => s.error.clone(),
        _ => None,
    };
    if let Some(e) = error {
        return Err(std::io::Error::other(e));
    }
    Ok((it.prog, sc))
}

enum Flow {
    Next,
    Goto(usize, usize),
    End,
}

impl<'a> Interp<'a, '_> {
    fn emit(&mut self, m: Motion) {
        self.prog.motions.push(m);
    }

    fn finding(&self, id: &'static str, sev: Severity, col: Option<usize>, msg: String) -> Finding {
        let msg = if self.src == 0 {
            msg
        } else {
            format!(
                "{msg} (in {} line {})",
                self.sources[self.src].name, self.line
            )
        };
        let line = if self.src == 0 {
            self.line
        } else {
            self.calls.first().map_or(self.line, |c| c.ret.1)
        };
        let f = Finding::new(id, sev, msg).line(line);
        match col {
            Some(c) => f.column(c),
            None => f,
        }
    }

    /// Keeps `f` among the program's diagnostics while its id has fewer than
    /// `max_findings_per_check` (at least 1) kept; beyond, it is only counted in
    /// [`Program::diagnostics_dropped`], so memory stays bounded whatever the input.
    fn diagnose(&mut self, f: Finding) {
        let cap = self.cfg.max_findings_per_check.max(1);
        let kept = self.diag_kept.entry(f.id).or_insert(0);
        if *kept < cap {
            *kept += 1;
            self.prog.diagnostics.push(f);
            return;
        }
        let dropped = &mut self.prog.diagnostics_dropped;
        match dropped.iter_mut().find(|d| d.0 == f.id) {
            Some(d) => d.1 += 1,
            None => dropped.push((f.id, 1)),
        }
    }

    fn err(&mut self, id: &'static str, col: Option<usize>, msg: String) {
        let f = self.finding(id, Severity::Error, col, msg);
        self.diagnose(f);
    }

    fn warn(&mut self, id: &'static str, col: Option<usize>, msg: String) {
        let f = self.finding(id, Severity::Warning, col, msg);
        self.diagnose(f);
    }

    /// Restores modal state `s` (everything but the position).
    fn restore(&mut self, s: State) {
        let pos = self.st.pos;
        self.st = s;
        self.st.pos = pos;
        self.select_cs(self.st.cs);
    }

    fn event(&mut self, code: String) {
        self.prog.events.push(Event {
            line: self.line,
            code,
        });
    }

    fn uncertain(&mut self) {
        if self.prog.uncertain_from.is_none() {
            self.prog.uncertain_from = Some(self.line);
        }
    }

    fn tool(&self, n: u32) -> Option<&ToolEntry> {
        self.tools.iter().find(|t| t.number == n)
    }
}
