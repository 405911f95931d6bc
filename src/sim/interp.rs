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
use super::parse_ahead::{self, Ahead, ParseAhead};
use crate::geom::{Arc, DVec2, perp};
use glam::DVec3;
use std::borrow::Cow;
use std::collections::HashMap;
use std::f64::consts::TAU;

/// GRBL's ARC_ANGULAR_TRAVEL_EPSILON: an IJ arc whose end direction is within this angle
/// (radians) past its start direction is a full circle.
const ANGULAR_EPSILON: f64 = 5e-7;

/// Relative part of the IJ radius check (LinuxCNC `spiral_rel_tolerance` default 0.001,
/// GRBL's 0.1 %): an error needs both the absolute and this relative difference.
const RADIUS_RELATIVE_TOLERANCE: f64 = 1e-3;

/// LinuxCNC's absolute IJ radius tolerance (`CENTER_ARC_RADIUS_TOLERANCE_MM` = 0.02 mm,
/// 0.002 inch); differences beyond 100 times it are errors regardless of the radius.
const LINUXCNC_RADIUS_TOLERANCE_MM: f64 = 0.02;

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

/// Marlin's feed rate before any F word (mm/min): `feedrate_mm_s = MMM_TO_MMS(1500.0f)` in
/// Marlin/src/module/motion.cpp.
pub const MARLIN_DEFAULT_FEED_MM_MIN: f64 = 1500.0;

/// Smoothieware's feed rate before any F word (mm/min): `default_feed_rate`, compiled-in
/// default 100 (Robot.cpp `by_default(100.0F)`) when the config file does not set it.
pub const SMOOTHIE_DEFAULT_FEED_MM_MIN: f64 = 100.0;

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
pub struct Options<'a> {
    /// Loader of called subroutine files (`o<name> call` of a sub not in the program); None: such calls are errors.
    pub load_sub: Option<SubLoader<'a>>,
}

struct Source<'a> {
    name: String,
    body: Body<'a>,
}

enum Body<'a> {
    /// The whole text, with the byte offset of each line start.
    Mem {
        text: Cow<'a, str>,
        starts: Vec<usize>,
    },
    /// A program read line by line from a seekable stream ([`interpret_stream`]).
    Stream(Box<LineStream<'a>>),
}

impl<'a> Source<'a> {
    fn new(name: String, text: Cow<'a, str>) -> Self {
        let mut starts = vec![0];
        starts.extend(memchr_lines(text.as_bytes()));
        Source {
            name,
            body: Body::Mem { text, starts },
        }
    }
    fn len(&self) -> usize {
        match &self.body {
            Body::Mem { starts, .. } => starts.len(),
            Body::Stream(s) => s.len,
        }
    }
    fn line(&mut self, i: usize) -> &str {
        match &mut self.body {
            Body::Mem { text, starts } => {
                let a = starts[i];
                let b = starts.get(i + 1).map_or(text.len(), |&e| e - 1);
                let l = &text[a..b.max(a)];
                l.strip_suffix('\r').unwrap_or(l)
            }
            Body::Stream(s) => s.line(i),
        }
    }
}

/// Where [`interpret_stream`] hands each move, with the pocket marks read so far (see
/// [`Program::group_marks`]).
pub type MotionSink<'s> = &'s mut dyn FnMut(Motion, &[(usize, Option<u32>)]);

/// Both [`std::io::Read`] and [`std::io::Seek`].
pub trait ReadSeek: std::io::Read + std::io::Seek {}
impl<T: std::io::Read + std::io::Seek> ReadSeek for T {}

/// Lines of a program read on demand: forward reading is sequential; a jump back (loops,
/// subroutine returns) seeks to the nearest recorded line start before the target (every
/// O-word line, its successor, and every [`CHECKPOINT_EVERY`]th line) and reads on from there.
struct LineStream<'a> {
    reader: std::io::BufReader<Box<dyn ReadSeek + 'a>>,
    /// (line index, byte offset of its start), sorted by line.
    checkpoints: Vec<(usize, u64)>,
    /// Number of lines (as [`Source::new`] counts them).
    len: usize,
    /// Index of the line in `buf` (`usize::MAX`: none yet).
    cur: usize,
    buf: String,
    raw: Vec<u8>,
    /// The first read error, if any.
    error: Option<String>,
}

/// Distance in lines between the recorded line starts of a [`LineStream`].
const CHECKPOINT_EVERY: usize = 4096;

impl LineStream<'_> {
    fn read_next(&mut self) {
        use std::io::BufRead;
        self.raw.clear();
        if let Err(e) = self.reader.read_until(b'\n', &mut self.raw) {
            self.error.get_or_insert_with(|| e.to_string());
        }
        if self.raw.last() == Some(&b'\n') {
            self.raw.pop();
        }
        if self.raw.last() == Some(&b'\r') {
            self.raw.pop();
        }
        self.buf.clear();
        self.buf.push_str(&String::from_utf8_lossy(&self.raw));
        self.cur = self.cur.wrapping_add(1);
    }

    fn line(&mut self, i: usize) -> &str {
        if i >= self.len {
            return "";
        }
        let ahead = self.cur != usize::MAX && i >= self.cur && i - self.cur <= CHECKPOINT_EVERY;
        if !ahead {
            let k = self.checkpoints.partition_point(|&(l, _)| l <= i);
            let (l, off) = self
                .checkpoints
                .get(k.wrapping_sub(1))
                .copied()
                .unwrap_or((0, 0));
            if let Err(e) = std::io::Seek::seek(&mut self.reader, std::io::SeekFrom::Start(off)) {
                self.error.get_or_insert_with(|| e.to_string());
            }
            self.cur = l.wrapping_sub(1);
        }
        while self.cur != i && self.error.is_none() {
            self.read_next();
        }
        if self.cur != i {
            return "";
        }
        &self.buf
    }
}

/// What one pass over a streamed program finds before it is interpreted
/// ([`interpret_stream`]).
#[derive(Clone, Debug, Default)]
pub struct Scan {
    /// Length in bytes (the byte-order mark excluded).
    pub bytes: u64,
    /// Every character is white space.
    pub blank: bool,
    /// A NUL byte occurs.
    pub nul: bool,
    /// The `invalid-utf8` warning of [`crate::sim::decode`], when it applies.
    pub utf8_warning: Option<Finding>,
    /// Number of lines (one more than the number of line feeds).
    pub lines: usize,
    /// Line starts recorded for seeking.
    checkpoints: Vec<(usize, u64)>,
    /// Lines with an O-word: (line index, statement).
    owords: Vec<(usize, ngc::OStmt)>,
}

/// Reads `input` once: line count, blank/NUL/UTF-8 facts, O-word lines (parsed with the
/// dialect's syntax) and seek points.
fn scan(input: &mut dyn ReadSeek, syn: Syntax) -> std::io::Result<Scan> {
    use std::io::{BufRead, SeekFrom};
    std::io::Seek::seek(input, SeekFrom::Start(0))?;
    let mut r = std::io::BufReader::with_capacity(1 << 16, &mut *input);
    let mut sc = Scan {
        blank: true,
        ..Scan::default()
    };
    let mut off: u64 = 0;
    if r.fill_buf()?.starts_with(b"\xEF\xBB\xBF") {
        r.consume(3);
        off = 3;
    }
    let base = off;
    let (mut bad_lines, mut bad_total) = (Vec::new(), 0usize);
    let mut raw = Vec::new();
    let mut i = 0usize;
    loop {
        raw.clear();
        let n = r.read_until(b'\n', &mut raw)?;
        if i.is_multiple_of(CHECKPOINT_EVERY) || sc.owords.last().is_some_and(|o| o.0 + 1 == i) {
            sc.checkpoints.push((i, off));
        }
        off += n as u64;
        let body = raw.strip_suffix(b"\n").unwrap_or(&raw);
        if memchr::memchr(0, body).is_some() {
            sc.nul = true;
        }
        let text = match std::str::from_utf8(body) {
            Ok(t) => Cow::Borrowed(t),
            Err(_) => {
                bad_total += 1;
                if bad_lines.len() < 10 {
                    bad_lines.push(i + 1);
                }
                String::from_utf8_lossy(body)
            }
        };
        if sc.blank && !text.trim().is_empty() {
            sc.blank = false;
        }
        if syn.ngc && memchr::memchr2(b'o', b'O', body).is_some() {
            let l = text.strip_suffix('\r').unwrap_or(&text);
            if let Some(o) = ngc::parse_line(l, syn).oword {
                if sc.checkpoints.last().is_none_or(|c| c.0 != i) {
                    sc.checkpoints.push((i, off - n as u64));
                }
                sc.owords.push((i, o));
            }
        }
        i += 1;
        if raw.last() != Some(&b'\n') {
            break;
        }
    }
    sc.lines = i;
    sc.bytes = off - base;
    if bad_total > 0 {
        sc.utf8_warning = Some(crate::sim::utf8_warning(bad_lines, bad_total));
    }
    Ok(sc)
}

fn memchr_lines(b: &[u8]) -> impl Iterator<Item = usize> + '_ {
    memchr::memchr_iter(b'\n', b).map(|i| i + 1)
}

/// Indexes of the lines of `s` holding an `o` or `O` (the only ones that can hold an O-word),
/// in order, each once.
fn lines_with_o(text: &str, starts: &[usize]) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::new();
    for at in memchr::memchr2_iter(b'o', b'O', text.as_bytes()) {
        let line = starts.partition_point(|&st| st <= at).saturating_sub(1);
        if out.last() != Some(&line) {
            out.push(line);
        }
    }
    out
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
    /// Streaming route ([`interpret_stream`]): moves wait in `pending` until the line is
    /// done and go to the caller's sink instead of into `prog`.
    streaming: bool,
    pending: Vec<Motion>,
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
        streaming: false,
        pending: Vec::new(),
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
pub fn interpret_with(src: &str, cfg: &CheckConfig, opts: &Options<'_>) -> Program {
    let mut it = new_interp(cfg, opts);
    it.add_source("program".into(), Cow::Borrowed(src));
    // About one move per line: reserving it up front avoids the doubling growth whose
    // spare capacity would count against an address-space limit on long programs; the
    // unused part is returned at the end.
    let lines = it.sources.first().map_or(0, |s| s.len());
    it.prog.motions.reserve(lines);
    // Asked only for long programs: the answer reads the process's CPU limits.
    let two_threads = || std::thread::available_parallelism().is_ok_and(|n| n.get() > 1);
    if lines >= parse_ahead::MIN_LINES && two_threads() {
        std::thread::scope(|scope| {
            let mut ahead = ParseAhead::spawn(scope, src, it.syn);
            it.run(None, Some(&mut ahead));
        });
    } else {
        it.run(None, None);
    }
    it.prog.motions.shrink_to_fit();
    it.prog.final_tool = it.st.tool;
    it.prog
}

/// Interprets a program read line by line from `input` (never held whole in memory), handing
/// every move to `sink` as it is produced (with the pocket marks read so far) instead of
/// storing it: the returned program has no motions. `cfg` as for [`interpret_with`]. Returns the pre-scan's facts beside it, or
/// the read error.
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
    it.streaming = true;
    it.run(Some(sink), None);
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
        if self.streaming {
            self.pending.push(m);
        } else {
            self.prog.motions.push(m);
        }
    }

    fn add_source(&mut self, name: String, text: Cow<'a, str>) -> usize {
        let mut s = Source::new(name, text);
        let owords: Vec<(usize, ngc::OStmt)> = if self.syn.ngc {
            let lines = match &s.body {
                Body::Mem { text, starts } => lines_with_o(text, starts),
                Body::Stream(_) => Vec::new(),
            };
            lines
                .into_iter()
                .filter_map(|i| ngc::parse_line(s.line(i), self.syn).oword.map(|o| (i, o)))
                .collect()
        } else {
            Vec::new()
        };
        self.push_source(s, owords)
    }

    /// Registers a source and its O-word statements (line index, statement) in line order.
    fn push_source(&mut self, s: Source<'a>, owords: Vec<(usize, ngc::OStmt)>) -> usize {
        let id = self.sources.len();
        self.high_water.push(0);
        if self.syn.ngc {
            let mut per: HashMap<String, Vec<OPos>> = HashMap::new();
            for (i, o) in owords {
                {
                    let v = per.entry(o.label.clone()).or_default();
                    let do_while = o.kind == OKind::While && {
                        // A while closes a do when the latest open do/while of the label is a do.
                        let mut open: Vec<OKind> = Vec::new();
                        for p in v.iter() {
                            match p.kind {
                                OKind::Do => open.push(OKind::Do),
                                OKind::While if !p.do_while => open.push(OKind::While),
                                OKind::While | OKind::EndWhile => {
                                    open.pop();
                                }
                                _ => {}
                            }
                        }
                        open.last() == Some(&OKind::Do)
                    };
                    if o.kind == OKind::Sub {
                        self.subs.entry(o.label.clone()).or_insert((id, i));
                    }
                    v.push(OPos {
                        line: i,
                        kind: o.kind,
                        do_while,
                    });
                }
            }
            for (k, v) in per {
                self.olines.insert((id, k), v);
            }
        }
        self.sources.push(s);
        id
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

    /// Runs the program from its first line; `ahead` parses the main program's lines on
    /// another thread ([`ParseAhead`]).
    fn run(&mut self, mut sink: Option<MotionSink<'_>>, mut ahead: Option<&mut ParseAhead>) {
        let mut drain = |it: &mut Self| {
            if let Some(f) = sink.as_mut() {
                for m in it.pending.drain(..) {
                    f(m, &it.prog.group_marks);
                }
            }
        };
        let (mut src, mut i) = (0usize, 0usize);
        let mut started = false;
        let mut percent_open = false;
        let mut scratch = Line::default();
        while !self.stop {
            drain(self);
            if i >= self.sources[src].len() {
                if src != 0 {
                    self.err(
                        "o-word",
                        None,
                        format!(
                            "subroutine file {} ended without endsub",
                            self.sources[src].name
                        ),
                    );
                }
                break;
            }
            self.src = src;
            self.line = i + 1;
            if src == 0 {
                self.prog.lines = i + 1;
            }
            // Lines of the main program read for the first time come from the worker when
            // there is one, parsed or marked blank (whitespace only).
            let fresh = src == 0 && i >= self.high_water[src];
            let early = match ahead.as_deref_mut() {
                Some(a) if fresh => a.get(i),
                _ => None,
            };
            let cached: Option<std::rc::Rc<Line>>;
            let parsed: &Line = match early {
                Some(Ahead::Blank) => {
                    i += 1;
                    continue;
                }
                Some(Ahead::Line(l)) => {
                    self.high_water[src] = i + 1;
                    l
                }
                None => {
                    let text = self.sources[src].line(i);
                    if text.trim().is_empty() {
                        i += 1;
                        continue;
                    }
                    // Lines met again (loop bodies, subroutines) are parsed once and
                    // cached; lines read for the first time are parsed into one reused
                    // buffer and not kept (bounded memory and no allocation per line on
                    // long programs).
                    cached = if i < self.high_water[src] {
                        Some(match self.cache.get(&(src, i)) {
                            Some(l) => l.clone(),
                            None => {
                                let l = std::rc::Rc::new(ngc::parse_line(text, self.syn));
                                self.cache.insert((src, i), l.clone());
                                l
                            }
                        })
                    } else {
                        self.high_water[src] = i + 1;
                        ngc::parse_line_into(text, self.syn, &mut scratch);
                        None
                    };
                    cached.as_deref().unwrap_or(&scratch)
                }
            };
            if parsed.percent && src == 0 {
                if !started {
                    started = true;
                    percent_open = true;
                    i += 1;
                    continue;
                }
                // The closing tape mark ends the program. Without an opening one it is a
                // warning: LinuxCNC's rs274 reads it as the end (the cross-check in
                // tests/sim_refusals.rs runs it), other readers may refuse the file.
                if !percent_open && matches!(self.cfg.dialect, Dialect::Linuxcnc | Dialect::Generic)
                {
                    self.warn(
                        "percent-without-start",
                        None,
                        "`%` ends a program that did not start with one (LinuxCNC stops there; \
                         other readers may refuse a lone tape mark)"
                            .to_string(),
                    );
                }
                if self.prog.end.is_none() {
                    self.prog.end = Some(ProgramEnd {
                        line: i + 1,
                        tool_before: self.st.tool,
                    });
                }
                self.after_end(src, i + 1);
                break;
            }
            if !(parsed.words.is_empty() && parsed.assigns.is_empty() && parsed.oword.is_none()) {
                started = true;
            }
            let jumped = std::mem::take(&mut self.jumped);
            match self.exec(parsed, src, i, jumped) {
                Flow::Next => i += 1,
                Flow::Goto(s, l) => {
                    src = s;
                    i = l;
                }
                Flow::End => {
                    if !self.stop {
                        self.after_end(src, i + 1);
                    }
                    break;
                }
            }
        }
        drain(self);
    }

    /// Reports (once) that non-blank lines follow the end and are ignored.
    fn after_end(&mut self, src: usize, from: usize) {
        if src != 0 {
            return;
        }
        let s = &mut self.sources[0];
        let syn = self.syn;
        if let Some(l) = (from..s.len()).find(|&l| {
            let t = s.line(l).trim();
            if t.is_empty() || t == "%" {
                return false;
            }
            let p = ngc::parse_line(t, syn);
            !(p.words.is_empty()
                && p.assigns.is_empty()
                && p.oword.is_none()
                && p.errors.is_empty())
        }) {
            let end = self.line;
            self.prog.diagnostics.push(
                Finding::new(
                    "after-program-end",
                    Severity::Warning,
                    format!("lines after the program end on line {end} are not interpreted"),
                )
                .line(l + 1),
            );
        }
    }

    fn view(&self) -> View<'_, 'a, '_> {
        View { it: self }
    }

    fn eval(&mut self, e: &Expr, col: usize) -> Option<f64> {
        match e.eval(&self.view()) {
            Ok(v) if v.is_finite() => Some(v),
            Ok(v) => {
                self.err("expression", Some(col), format!("expression gives {v}"));
                None
            }
            Err(m) => {
                self.err("expression", Some(col), m);
                None
            }
        }
    }

    fn set_param(&mut self, p: &ParamRef, v: f64, col: usize) {
        match p {
            ParamRef::Num(e) => {
                let Some(n) = self.eval(e, col) else { return };
                match ngc::param_index(n) {
                    Ok(n) => self.params[n as usize] = v,
                    Err(m) => self.err("expression", Some(col), m),
                }
            }
            ParamRef::Named(n) if n.starts_with('_') => {
                if predefined(n) {
                    self.err(
                        "expression",
                        Some(col),
                        format!("#<{n}> is a read-only predefined parameter"),
                    );
                } else {
                    self.globals.insert(n.clone(), v);
                }
            }
            ParamRef::Named(n) => {
                self.locals.insert(n.clone(), v);
            }
        }
    }

    fn find_o(&self, src: usize, label: &str, after: usize, kinds: &[OKind]) -> Option<OPos> {
        self.olines
            .get(&(src, label.to_string()))?
            .iter()
            .find(|p| p.line > after && kinds.contains(&p.kind))
            .copied()
    }

    /// The label of a subroutine definition (`O… sub`) of source `src` strictly between
    /// lines `from` and `to`: a nested definition, which LinuxCNC refuses
    /// (`interp_read.cc` `read_o`, NCE_NESTED_SUBROUTINE_DEFN "Nested
    /// subroutine definition").
    fn sub_within(&self, src: usize, from: usize, to: usize) -> Option<&str> {
        self.olines
            .iter()
            .filter(|((s, _), _)| *s == src)
            .find(|(_, v)| {
                v.iter()
                    .any(|p| p.kind == OKind::Sub && p.line > from && p.line < to)
            })
            .map(|((_, l), _)| l.as_str())
    }

    fn find_o_back(&self, src: usize, label: &str, before: usize, kind: OKind) -> Option<OPos> {
        self.olines
            .get(&(src, label.to_string()))?
            .iter()
            .rev()
            .find(|p| p.line < before && p.kind == kind && !p.do_while)
            .copied()
    }

    fn count_iteration(&mut self) -> bool {
        self.count_work(1)
    }

    /// Counts `n` units of work against the loop budget (`max_loop_iterations`): loop
    /// iterations, and the repeats of one block (canned-cycle repeats L and pecks, arc
    /// turns P), so that no block creates more moves than the budget allows. False, with a
    /// `loop-limit` error naming the line, once the budget is spent: interpretation stops.
    fn count_work(&mut self, n: u64) -> bool {
        self.iterations = self.iterations.saturating_add(n);
        if self.iterations > self.cfg.max_loop_iterations {
            self.err(
                "loop-limit",
                None,
                format!(
                    "loops, canned-cycle repeats and pecks, and arc turns ran more than {} \
                     iterations: interpretation stopped (raise max_loop_iterations if the \
                     program really needs more)",
                    self.cfg.max_loop_iterations
                ),
            );
            self.stop = true;
            return false;
        }
        true
    }

    fn exec(&mut self, l: &Line, src: usize, i: usize, jumped: bool) -> Flow {
        if self.plain_moves && self.plain_block(l) {
            return Flow::Next;
        }
        for e in &l.errors {
            self.err(e.id, Some(e.column), e.message.clone());
        }
        if let Some(d) = &l.dollar {
            self.prog.words += 1;
            self.prog.events.push(Event {
                line: self.line,
                code: format!("${d}"),
            });
            return Flow::Next;
        }
        if let Some(o) = &l.oword {
            self.prog.words += 1;
            return self.oword(o, src, i, jumped);
        }
        self.comments(l);
        if self.stop {
            return Flow::End;
        }
        if l.words.is_empty() && l.assigns.is_empty() {
            return Flow::Next;
        }
        if self.src == 0 {
            self.prog.last_line = self.line;
        }
        // Read every value first, then assign parameters (LinuxCNC: "parameter setting does
        // not take effect until after all parameter values on the same line have been found").
        let mut words = std::mem::take(&mut self.word_buf);
        words.clear();
        let mut bad = false;
        for w in &l.words {
            let v = match w.value {
                // What `eval` gives a finite number, without the call.
                Expr::Num(v) if v.is_finite() => Some(v),
                ref e => self.eval(e, w.column),
            };
            match v {
                Some(v) => words.push((w.letter, v, w.column)),
                None => bad = true,
            }
        }
        let mut sets = Vec::new();
        for (p, e, col) in &l.assigns {
            if let Some(v) = self.eval(e, *col) {
                sets.push((p, v, *col));
            }
        }
        for (p, v, col) in sets {
            self.set_param(p, v, col);
            self.prog.words += 1;
        }
        let flow = if bad || words.is_empty() {
            Flow::Next
        } else {
            self.exec_words(&words)
        };
        self.word_buf = words;
        flow
    }

    /// Executes one block of evaluated words.
    fn exec_words(&mut self, words: &[(char, f64, usize)]) -> Flow {
        let mut b = Block::new();
        if !self.collect(&mut b, words) {
            return Flow::Next;
        }
        if self.execute(b) {
            self.prog.end = Some(ProgramEnd {
                line: self.calls.first().map_or(self.line, |c| c.ret.1),
                tool_before: self.tool_at_stop,
            });
            return Flow::End;
        }
        Flow::Next
    }

    fn comments(&mut self, l: &Line) {
        for c in &l.comments {
            let lower = c.to_ascii_lowercase();
            if let Some(rest) = lower.strip_prefix("skinpath:group") {
                let rest = rest.trim();
                if rest == "end" || rest == "none" {
                    self.group = None;
                    self.prog.group_marks.push((self.line, None));
                } else {
                    match rest.parse::<u32>() {
                        Ok(g) => {
                            self.group = Some(g);
                            self.prog.group_marks.push((self.line, Some(g)));
                        }
                        Err(_) => self.warn(
                            "comment",
                            None,
                            format!("(skinpath:group {rest}) needs a number or `end`"),
                        ),
                    }
                }
                continue;
            }
            let Some((head, text)) = c.split_once(',') else {
                continue;
            };
            match head.trim().to_ascii_lowercase().as_str() {
                "debug" | "print" if self.syn.ngc => {
                    let t = self.substitute(text);
                    let f = self.finding("message", Severity::Info, None, t);
                    self.diagnose(f);
                }
                "msg" => {
                    let f = self.finding("message", Severity::Info, None, text.trim().into());
                    self.diagnose(f);
                }
                "abort" if self.syn.ngc => {
                    let t = self.substitute(text);
                    self.err("abort", None, format!("program aborted: {t}"));
                    self.stop = true;
                }
                _ => {}
            }
        }
    }

    /// `(debug,…)` text with `#n` and `#<name>` replaced by their values (`%f`, as LinuxCNC).
    fn substitute(&self, text: &str) -> String {
        let mut out = String::new();
        let b: Vec<char> = text.chars().collect();
        let mut i = 0;
        while i < b.len() {
            if b[i] == '#' {
                if b.get(i + 1) == Some(&'<') {
                    if let Some(k) = b[i + 2..].iter().position(|&c| c == '>') {
                        let name: String = b[i + 2..i + 2 + k]
                            .iter()
                            .filter(|c| !c.is_whitespace())
                            .collect::<String>()
                            .to_ascii_lowercase();
                        match self.view().named(&name) {
                            Some(v) => out += &format!("{v:.6}"),
                            None => out += "######",
                        }
                        i += k + 3;
                        continue;
                    }
                } else {
                    let d: String = b[i + 1..]
                        .iter()
                        .take_while(|c| c.is_ascii_digit())
                        .collect();
                    if let Some(n) = d.parse::<i64>().ok().filter(|&n| n <= ngc::MAX_PARAMETER) {
                        out += &format!("{:.6}", self.view().numbered(n));
                        i += 1 + d.len();
                        continue;
                    }
                }
            }
            out.push(b[i]);
            i += 1;
        }
        out.trim().to_string()
    }

    fn oword(&mut self, o: &ngc::OStmt, src: usize, i: usize, jumped: bool) -> Flow {
        let label = o.label.as_str();
        let arg = |it: &mut Self| -> Option<f64> {
            let e = o.args.first()?;
            it.eval(e, 1)
        };
        let missing = |it: &mut Self, what: &str| {
            it.err(
                "o-word",
                None,
                format!("O{label} {:?} has no matching {what}", o.kind),
            );
            it.stop = true;
            Flow::End
        };
        match o.kind {
            OKind::Sub => match self.find_o(src, label, i, &[OKind::EndSub]) {
                Some(p) => {
                    if let Some(inner) = self.sub_within(src, i, p.line) {
                        self.err(
                            "o-word",
                            None,
                            format!(
                                "O{inner} sub inside the definition of O{label}: LinuxCNC \
                                 refuses it (\"Nested subroutine definition\")"
                            ),
                        );
                    }
                    Flow::Goto(src, p.line + 1)
                }
                None => missing(self, "endsub"),
            },
            OKind::EndSub | OKind::Return => {
                let v = if o.args.is_empty() { None } else { arg(self) };
                self.value = v;
                let Some(f) = self.calls.pop() else {
                    self.err(
                        "o-word",
                        None,
                        format!("O{label} endsub/return outside a subroutine"),
                    );
                    return Flow::Next;
                };
                self.locals = f.locals;
                self.params[1..31].copy_from_slice(&f.saved);
                self.repeats.truncate(f.repeats);
                if let Some(s) = f.autorestore {
                    self.restore(s);
                }
                Flow::Goto(f.ret.0, f.ret.1)
            }
            OKind::Call => {
                if self.calls.len() >= MAX_CALL_DEPTH {
                    self.err(
                        "call-depth",
                        None,
                        format!(
                            "O{label} call nests deeper than {MAX_CALL_DEPTH} subroutine levels \
                             (LinuxCNC's limit): interpretation stopped"
                        ),
                    );
                    self.stop = true;
                    return Flow::End;
                }
                let mut args = Vec::new();
                for e in &o.args {
                    match self.eval(e, 1) {
                        Some(v) => args.push(v),
                        None => return Flow::Next,
                    }
                }
                let target = match self.subs.get(label).copied() {
                    Some(t) => Some(t),
                    None => match self.load_sub(label) {
                        Ok(t) => t,
                        // Reported: the file exists and cannot be read.
                        Err(()) => return Flow::Next,
                    },
                };
                let Some((ts, tl)) = target else {
                    self.err(
                        "o-word",
                        None,
                        format!(
                            "O{label} call: no subroutine O{label} in the program and no file \
                             {label}.ngc in the subroutine path"
                        ),
                    );
                    return Flow::Next;
                };
                let mut saved = [0.0; 30];
                saved.copy_from_slice(&self.params[1..31]);
                for (k, slot) in self.params[1..31].iter_mut().enumerate() {
                    *slot = args.get(k).copied().unwrap_or(0.0);
                }
                let locals = std::mem::take(&mut self.locals);
                self.calls.push(CallFrame {
                    ret: (src, i + 1),
                    locals,
                    saved,
                    repeats: self.repeats.len(),
                    autorestore: None,
                });
                Flow::Goto(ts, tl + 1)
            }
            OKind::If => {
                let Some(c) = arg(self) else {
                    return Flow::Next;
                };
                if c != 0.0 {
                    return Flow::Next;
                }
                match self.find_o(src, label, i, &[OKind::ElseIf, OKind::Else, OKind::EndIf]) {
                    Some(p) => {
                        self.jumped = true;
                        Flow::Goto(src, p.line)
                    }
                    None => missing(self, "endif"),
                }
            }
            OKind::ElseIf => {
                if jumped {
                    let Some(c) = arg(self) else {
                        return Flow::Next;
                    };
                    if c != 0.0 {
                        return Flow::Next;
                    }
                    match self.find_o(src, label, i, &[OKind::ElseIf, OKind::Else, OKind::EndIf]) {
                        Some(p) => {
                            self.jumped = true;
                            Flow::Goto(src, p.line)
                        }
                        None => missing(self, "endif"),
                    }
                } else {
                    match self.find_o(src, label, i, &[OKind::EndIf]) {
                        Some(p) => Flow::Goto(src, p.line + 1),
                        None => missing(self, "endif"),
                    }
                }
            }
            OKind::Else => {
                if jumped {
                    Flow::Next
                } else {
                    match self.find_o(src, label, i, &[OKind::EndIf]) {
                        Some(p) => Flow::Goto(src, p.line + 1),
                        None => missing(self, "endif"),
                    }
                }
            }
            OKind::EndIf | OKind::Do => Flow::Next,
            OKind::While => {
                let do_while = self
                    .olines
                    .get(&(src, label.to_string()))
                    .and_then(|v| v.iter().find(|p| p.line == i))
                    .is_some_and(|p| p.do_while);
                let Some(c) = arg(self) else {
                    return Flow::Next;
                };
                if do_while {
                    if c == 0.0 {
                        return Flow::Next;
                    }
                    if !self.count_iteration() {
                        return Flow::End;
                    }
                    return match self.find_o_back(src, label, i, OKind::Do) {
                        Some(p) => Flow::Goto(src, p.line + 1),
                        None => missing(self, "do"),
                    };
                }
                if c != 0.0 {
                    return Flow::Next;
                }
                match self.find_o(src, label, i, &[OKind::EndWhile]) {
                    Some(p) => Flow::Goto(src, p.line + 1),
                    None => missing(self, "endwhile"),
                }
            }
            OKind::EndWhile => {
                if !self.count_iteration() {
                    return Flow::End;
                }
                match self.find_o_back(src, label, i, OKind::While) {
                    Some(p) => Flow::Goto(src, p.line),
                    None => missing(self, "while"),
                }
            }
            OKind::Repeat => {
                let Some(n) = arg(self) else {
                    return Flow::Next;
                };
                if n.round() < 1.0 {
                    return match self.find_o(src, label, i, &[OKind::EndRepeat]) {
                        Some(p) => Flow::Goto(src, p.line + 1),
                        None => missing(self, "endrepeat"),
                    };
                }
                self.repeats.push((src, label.to_string(), i, n.round()));
                Flow::Next
            }
            OKind::EndRepeat | OKind::Continue
                if o.kind == OKind::EndRepeat
                    || self
                        .repeats
                        .last()
                        .is_some_and(|r| r.0 == src && r.1 == label) =>
            {
                let Some(r) = self
                    .repeats
                    .last_mut()
                    .filter(|r| r.0 == src && r.1 == label)
                else {
                    return missing(self, "repeat");
                };
                r.3 -= 1.0;
                if r.3 >= 1.0 {
                    let start = r.2;
                    if !self.count_iteration() {
                        return Flow::End;
                    }
                    Flow::Goto(src, start + 1)
                } else {
                    self.repeats.pop();
                    match self.find_o(src, label, i.saturating_sub(1), &[OKind::EndRepeat]) {
                        Some(p) => Flow::Goto(src, p.line + 1),
                        None => missing(self, "endrepeat"),
                    }
                }
            }
            OKind::Continue => {
                if !self.count_iteration() {
                    return Flow::End;
                }
                let next = self.find_o(src, label, i, &[OKind::EndWhile, OKind::While]);
                match next {
                    Some(p) if p.kind == OKind::While && p.do_while => Flow::Goto(src, p.line),
                    Some(p) => match self.find_o_back(src, label, p.line, OKind::While) {
                        Some(w) => Flow::Goto(src, w.line),
                        None => missing(self, "while"),
                    },
                    None => missing(self, "loop end"),
                }
            }
            OKind::EndRepeat => missing(self, "repeat"),
            OKind::Break => {
                if self
                    .repeats
                    .last()
                    .is_some_and(|r| r.0 == src && r.1 == label)
                {
                    self.repeats.pop();
                }
                match self.find_o(
                    src,
                    label,
                    i,
                    &[OKind::EndWhile, OKind::EndRepeat, OKind::While],
                ) {
                    Some(p) if p.kind != OKind::While || p.do_while => Flow::Goto(src, p.line + 1),
                    _ => missing(self, "loop end"),
                }
            }
        }
    }

    /// The subroutine `label` from its file, loaded by `opts.load_sub`: None when there is
    /// none, Err after an `o-word` error when the file exists and cannot be read.
    fn load_sub(&mut self, label: &str) -> Result<Option<(usize, usize)>, ()> {
        let Some(loader) = self.opts.load_sub else {
            return Ok(None);
        };
        let text = match loader.load(label) {
            Ok(Some(text)) => text,
            Ok(None) => return Ok(None),
            Err(why) => {
                self.err(
                    "o-word",
                    None,
                    format!("O{label} call: subroutine file cannot be read: {why}"),
                );
                return Err(());
            }
        };
        self.add_source(format!("{label}.ngc"), Cow::Owned(text));
        Ok(self.subs.get(label).copied())
    }

    /// Sorts the words into `b`; false when the block cannot run.
    fn collect(&mut self, b: &mut Block, words: &[(char, f64, usize)]) -> bool {
        let mut ok = true;
        for &(letter, v, col) in words {
            self.prog.words += 1;
            match letter {
                'G' => ok &= self.g_code(b, v, col),
                'M' => ok &= self.m_code(b, v, col),
                'N' => {}
                c => {
                    let Some(i) = letter_index(c) else {
                        if matches!(self.cfg.dialect, Dialect::Marlin | Dialect::Smoothie) {
                            // E (extruder) and other firmware words: harmless here.
                            continue;
                        }
                        self.err(
                            "unknown-word",
                            Some(col),
                            format!("word {c}{v} is not supported"),
                        );
                        ok = false;
                        continue;
                    };
                    if b.vals[i].is_some() {
                        self.err(
                            "duplicate-word",
                            Some(col),
                            format!("{c} appears twice in the block"),
                        );
                        ok = false;
                    } else {
                        b.vals[i] = Some(v);
                        b.cols[i] = col;
                    }
                }
            }
        }
        ok
    }

    fn modal(&mut self, b: &mut Block, group: usize, code: i64, col: usize, prefix: char) -> bool {
        if let Some(prev) = b.group(group) {
            self.err(
                "modal-conflict",
                Some(col),
                format!(
                    "{prefix}{} and {prefix}{} are in the same modal group: only one may be in a \
                     block",
                    fmt_code(prev),
                    fmt_code(code)
                ),
            );
            return false;
        }
        b.set_group(group, code);
        true
    }

    fn g_code(&mut self, b: &mut Block, v: f64, col: usize) -> bool {
        let Some(code) = tenths(v) else {
            self.err("unknown-code", Some(col), format!("G{v} is not a G-code"));
            return false;
        };
        let grbl = self.cfg.dialect == Dialect::Grbl;
        let group = match code {
            0 | 10 | 20 | 30 | 332 | 330 | 760 | 730 | 800..=890 | 382..=385 | 50 | 51 | 52 => {
                G_MOTION
            }
            40 | 100 | 280 | 281 | 300 | 301 | 520 | 530 | 920..=923 => G_NONMODAL,
            170 | 180 | 190 => G_PLANE,
            900 | 910 => G_DISTANCE,
            901 | 911 => G_ARC_DISTANCE,
            930 | 940 | 950 => G_FEED_MODE,
            200 | 210 => G_UNITS,
            400 | 410 | 420 | 411 | 421 => G_COMP,
            430 | 431 | 490 => G_TLO,
            980 | 990 => G_RETURN,
            540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => G_COORD,
            610 | 611 | 640 => G_PATH,
            960 | 970 => G_SPINDLE,
            70 | 80 => G_LATHE,
            _ => {
                self.err(
                    "unknown-code",
                    Some(col),
                    format!("G{} is not supported (unknown code)", fmt_code(code)),
                );
                return false;
            }
        };
        let grbl_ok = matches!(
            code,
            0 | 10
                | 20
                | 30
                | 40
                | 100
                | 170
                | 180
                | 190
                | 200
                | 210
                | 280
                | 281
                | 300
                | 301
                | 382..=385
                | 400
                | 431
                | 490
                | 530..=590
                | 610
                | 800
                | 900
                | 910
                | 911
                | 920
                | 921
                | 930
                | 940
        ) && !matches!(code, 531..=539 | 541..=549 | 551..=559 | 561..=569 | 571..=579 | 581..=589);
        if grbl && !grbl_ok {
            self.err(
                "unsupported-code",
                Some(col),
                format!("G{} is not supported by GRBL (error:20)", fmt_code(code)),
            );
            return false;
        }
        if !self.modal(b, group, code, col, 'G') {
            return false;
        }
        true
    }

    fn m_code(&mut self, b: &mut Block, v: f64, col: usize) -> bool {
        let Some(code) = tenths(v).filter(|c| c % 10 == 0).map(|c| c / 10) else {
            self.err("unknown-code", Some(col), format!("M{v} is not an M-code"));
            return false;
        };
        let marlin = matches!(self.cfg.dialect, Dialect::Marlin | Dialect::Smoothie);
        let group = match code {
            0 | 1 | 2 | 30 | 60 => M_STOP,
            6 | 61 => M_TOOL,
            3..=5 => M_SPINDLE,
            7..=9 => {
                // M7 and M8 may share a block (mist and flood); M9 shares it with neither.
                // Codes are stored in tenths: M9 is 90.
                if code == 9 || b.group(M_COOLANT).is_none_or(|c| c == 90) {
                    M_COOLANT
                } else {
                    M_COOLANT2
                }
            }
            48..=53 => M_OVERRIDE,
            62..=68 => M_IO,
            70..=73 => M_STATE,
            100..=199 => M_USER,
            _ if marlin => {
                self.warn(
                    "unknown-code",
                    Some(col),
                    format!("M{code} is not supported by this checker and ignored"),
                );
                return true;
            }
            _ => {
                self.err(
                    "unknown-code",
                    Some(col),
                    format!("M{code} is not supported (unknown code)"),
                );
                return false;
            }
        };
        if self.cfg.dialect == Dialect::Grbl && !matches!(code, 0..=5 | 7..=9 | 30 | 56) {
            self.err(
                "unsupported-code",
                Some(col),
                format!("M{code} is not supported by GRBL (error:20)"),
            );
            return false;
        }
        self.modal(b, group, code * 10, col, 'M')
    }

    /// Runs the block; true at a program end (M2/M30).
    fn execute(&mut self, mut b: Block) -> bool {
        let groups = b.groups;
        let g = |grp: usize| group_code(groups[grp]);
        // Feed mode and F.
        if let Some(c) = g(G_FEED_MODE) {
            self.st.feed_mode = match c {
                930 => FeedMode::InverseTime,
                950 => FeedMode::PerRev,
                _ => FeedMode::PerMinute,
            };
        }
        if let Some(f) = b.val('F') {
            if f < 0.0 {
                self.err(
                    "invalid-value",
                    Some(b.col('F')),
                    format!("feed F{f} is negative"),
                );
            } else if f == 0.0 && self.firmware_feed().is_some() {
                self.warn(
                    "no-feed-rate",
                    Some(b.col('F')),
                    "F0 is ignored by Marlin and Smoothieware: the last feed rate applies".into(),
                );
            } else {
                self.st.feed = f;
                self.st.feed_k = self.st.k();
            }
        }
        let mut next = (self.st.tool.spindle, self.st.tool.s);
        if let Some(s) = b.val('S') {
            if s >= 0.0 {
                next.1 = s;
            } else {
                self.err(
                    "invalid-value",
                    Some(b.col('S')),
                    format!("S{s} must not be negative"),
                );
            }
        }
        if let Some(t) = b.val('T') {
            if t < 0.0 || t.fract() != 0.0 {
                self.err(
                    "invalid-value",
                    Some(b.col('T')),
                    format!("T{t} must be a whole non-negative number"),
                );
            } else {
                self.st.selected_tool = t as u32;
            }
        }
        match g(M_TOOL) {
            Some(60) => {
                if !self.tools.is_empty() && self.st.selected_tool != 0 {
                    let t = self.st.selected_tool;
                    if self.tool(t).is_none() {
                        self.err(
                            "invalid-value",
                            Some(b.col('T')),
                            format!("tool {t} is not in the tool table: add it or change T"),
                        );
                    }
                }
                self.st.current_tool = self.st.selected_tool;
                self.event(format!("M6 T{}", self.st.current_tool));
            }
            Some(610) => match b.val('Q') {
                Some(q) if q >= 0.0 => {
                    self.st.current_tool = q as u32;
                    b.used_q = true;
                }
                _ => self.err(
                    "invalid-value",
                    None,
                    "M61 needs Q with a tool number ≥ 0".into(),
                ),
            },
            _ => {}
        }
        match g(M_SPINDLE) {
            Some(30) => next.0 = Spindle::Cw,
            Some(40) => next.0 = Spindle::Ccw,
            Some(50) => next.0 = Spindle::Off,
            _ => {}
        }
        if g(M_SPINDLE).is_some() && b.val('I').is_some() {
            // Marlin M3/M4 I: inline laser power mode.
            b.used_i = true;
        }
        self.st.tool.switch(next.0, next.1);
        for grp in [M_COOLANT, M_COOLANT2] {
            if let Some(c) = g(grp) {
                match c {
                    70 => self.st.mist = true,
                    80 => self.st.flood = true,
                    _ => {
                        self.st.mist = false;
                        self.st.flood = false;
                    }
                }
                self.event(format!("M{}", c / 10));
            }
        }
        if let Some(c) = g(M_OVERRIDE) {
            let _ = c;
            b.used_p = true;
        }
        if let Some(c) = g(M_IO) {
            let mut code = format!("M{}", c / 10);
            for l in ['P', 'E', 'L', 'Q'] {
                if let Some(v) = b.val(l) {
                    code += &format!(" {l}{v}");
                }
            }
            b.used_p = true;
            b.used_q = true;
            b.used_l = true;
            self.event(code);
        }
        match g(M_STATE) {
            // M70 save, M71 invalidate, M72 restore, M73 save and restore at the return of
            // the current subroutine (LinuxCNC manual, "M70–M73").
            Some(700) => self.saved_state = Some(self.st.clone()),
            Some(710) => self.saved_state = None,
            Some(720) => match self.saved_state.clone() {
                Some(s) => self.restore(s),
                None => self.err(
                    "invalid-value",
                    None,
                    "M72 without a state saved by M70".into(),
                ),
            },
            Some(730) => {
                let s = self.st.clone();
                match self.calls.last_mut() {
                    Some(f) => f.autorestore = Some(s),
                    None => self.err("invalid-value", None, "M73 outside a subroutine".into()),
                }
            }
            _ => {}
        }
        if let Some(c) = g(M_USER) {
            self.err(
                "cannot-simulate",
                None,
                format!(
                    "M{} is a user M-code (a program on the real machine): not supported, \
                     it cannot be simulated; later moves are uncertain",
                    c / 10
                ),
            );
            b.used_p = true;
            b.used_q = true;
            self.uncertain();
        }
        // Dwell.
        if g(G_NONMODAL) == Some(40) {
            b.used_p = true;
            let p = match self.cfg.dialect {
                Dialect::Marlin | Dialect::Smoothie => {
                    b.val('P').map(|p| p / 1000.0).or(b.val('S'))
                }
                _ => b.val('P'),
            };
            match p {
                Some(p) if p >= 0.0 => {
                    let m = self.motion(MotionKind::Dwell { seconds: p }, self.st.pos, None);
                    self.emit(m);
                }
                _ => self.err(
                    "invalid-value",
                    None,
                    "G4 needs P with the dwell time (P ≥ 0)".into(),
                ),
            }
        }
        match g(G_PLANE) {
            Some(170) => self.st.plane = Plane::Xy,
            Some(180) => self.st.plane = Plane::Xz,
            Some(190) => self.st.plane = Plane::Yz,
            _ => {}
        }
        match g(G_UNITS) {
            Some(200) => self.st.units = Units::Inch,
            Some(210) => self.st.units = Units::Mm,
            _ => {}
        }
        match g(G_COMP) {
            Some(400) => self.st.comp = false,
            Some(c) => {
                let d = b
                    .val('D')
                    .map(|d| d * self.st.k())
                    .or_else(|| self.tool(self.st.current_tool).map(|t| t.diameter))
                    .unwrap_or(0.0);
                b.used_d = true;
                if d != 0.0 {
                    self.err(
                        "unsupported-code",
                        None,
                        format!(
                            "G{} cutter compensation with a tool of diameter {d} mm is not \
                             supported: the path is checked uncompensated",
                            fmt_code(c)
                        ),
                    );
                }
                self.st.comp = true;
            }
            None => {}
        }
        match g(G_TLO) {
            Some(430) => {
                let h = b
                    .val('H')
                    .map_or(self.st.current_tool, |h| h.max(0.0) as u32);
                b.used_h = true;
                let t = self.tool(h).copied().unwrap_or_default();
                self.st.tlo = DVec3::new(t.x, 0.0, t.z);
            }
            Some(431) => {
                let k = self.st.k();
                let mut o = self.st.tlo;
                for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                    if let Some(v) = b.val(c) {
                        o[i] = v * k;
                    }
                }
                b.axes_used = true;
                self.st.tlo = o;
            }
            Some(490) => self.st.tlo = DVec3::ZERO,
            _ => {}
        }
        if let Some(c) = g(G_COORD) {
            let n = match c {
                591..=593 => 7 + (c - 591) as usize,
                _ => (c / 10 - 53) as usize,
            };
            self.select_cs(n);
        }
        match g(G_DISTANCE) {
            Some(900) => self.st.absolute = true,
            Some(910) => self.st.absolute = false,
            _ => {}
        }
        match g(G_ARC_DISTANCE) {
            Some(901) => self.st.arc_absolute = true,
            Some(911) => self.st.arc_absolute = false,
            _ => {}
        }
        match g(G_RETURN) {
            Some(980) => self.st.retract_r = false,
            Some(990) => self.st.retract_r = true,
            _ => {}
        }
        match g(G_LATHE) {
            Some(70) => self.st.diameter_mode = true,
            Some(80) => self.st.diameter_mode = false,
            _ => {}
        }
        if matches!(g(G_PATH), Some(640)) {
            b.used_p = true;
            b.used_q = true;
        }
        let nonmodal = g(G_NONMODAL).filter(|&c| c != 40);
        let has_axis = b.has_axis();
        if let (Some(c), Some(m)) = (nonmodal, g(G_MOTION))
            && has_axis
            && c != 100
            && c != 530
        {
            self.err(
                "modal-conflict",
                None,
                format!(
                    "G{} and G{} both use the axis words of the block",
                    fmt_code(c),
                    fmt_code(m)
                ),
            );
            return false;
        }
        if let Some(c) = nonmodal {
            self.nonmodal(c, &mut b);
        }
        if self.cfg.dialect == Dialect::Linuxcnc && self.linuxcnc_refuses_motion(&b, g(G_MOTION)) {
            return false;
        }
        if let Some(m) = g(G_MOTION) {
            self.st.mode = match m {
                0 => Mode::Rapid,
                10 => Mode::Linear,
                20 => Mode::ArcCw,
                30 => Mode::ArcCcw,
                800 => Mode::Off,
                730 | 810..=890 => {
                    if !matches!(self.st.mode, Mode::Cycle(_)) {
                        // A new series of canned cycles: its start height is taken at the
                        // first hole (G98 returns there; G91 R counts from it).
                        self.st.cycle_start_z = None;
                    }
                    Mode::Cycle(m)
                }
                382..=385 => {
                    self.warn(
                        "cannot-simulate",
                        None,
                        format!(
                            "G{} probing needs the real machine: it cannot be simulated (taken \
                             as a feed to the target); later moves are uncertain",
                            fmt_code(m)
                        ),
                    );
                    self.uncertain();
                    b.axes_used = true;
                    let to = self.target(&b);
                    self.straight(MotionKind::Feed, to);
                    self.st.mode
                }
                330 => {
                    if self.st.tool.spindle == Spindle::Off {
                        self.err(
                            "invalid-value",
                            None,
                            "G33 needs the spindle turning (M3/M4)".into(),
                        );
                    }
                    // Spindle-synchronised motion: geometrically a straight feed; K is the
                    // distance per revolution.
                    b.axes_used = true;
                    b.used_arc = true;
                    let to = self.target(&b);
                    self.straight(MotionKind::Feed, to);
                    Mode::Linear
                }
                _ => {
                    self.err(
                        "unsupported-code",
                        None,
                        format!("G{} is not supported: its motion is skipped", fmt_code(m)),
                    );
                    b.axes_used = true;
                    b.used_all = true;
                    Mode::Off
                }
            };
        }
        if has_axis && !b.axes_used {
            match self.st.mode {
                Mode::Off => self.err(
                    "no-motion-mode",
                    None,
                    "axis words without a motion mode (G0/G1/G2/G3 or a canned cycle)".into(),
                ),
                mode => self.move_block(mode, &mut b),
            }
        } else if !has_axis
            && matches!(self.st.mode, Mode::ArcCw | Mode::ArcCcw)
            && ['I', 'J', 'K', 'R']
                .into_iter()
                .any(|c| b.val(c).is_some() && !(c == 'I' && b.used_i))
            && g(G_NONMODAL).is_none()
        {
            // An arc block without axis words ends where it starts: a full circle (IJK).
            // Marlin's `M3 I` (inline power) after a G2 is not one: its I is the spindle's.
            let mode = self.st.mode;
            self.move_block(mode, &mut b);
        }
        self.unused_words(&b);
        match g(M_STOP) {
            Some(0) | Some(10) | Some(600) => {
                let c = g(M_STOP).unwrap_or(0) / 10;
                self.event(format!("M{c}"));
                false
            }
            Some(20) | Some(300) => {
                // M2/M30: spindle and coolant off, G54, G17, G90, G94, G80 (LinuxCNC).
                self.tool_at_stop = self.st.tool;
                self.st.tool.switch(Spindle::Off, self.st.tool.s);
                self.st.absolute = true;
                true
            }
            _ => false,
        }
    }

    /// LinuxCNC's refusals of a block's motion words, checked before the motion (an error,
    /// true when the block is refused; LinuxCNC stops there). `motion` is the block's own
    /// group-1 code (tenths). From `interp_internal.cc` `enhance_block`, `interp_check.cc`
    /// `check_other_codes` and `interp_convert.cc` `convert_straight`:
    /// - a motion code other than G0–G3, G5.2, G6.2, G70–G72 with no axis word:
    ///   NCE_ALL_AXES_MISSING_WITH_MOTION_CODE;
    /// - an A, B or C word in a canned-cycle block (`is_a_cycle`: G73, G74, G81–G89):
    ///   NCE_CANNOT_PUT_AN_A_IN_CANNED_CYCLE (and the B, C versions);
    /// - G1 with no axis word while no feed rate is set (feed per minute or per revolution):
    ///   LinuxCNC still runs `convert_straight`, NCE_CANNOT_DO_G1_WITH_ZERO_FEED_RATE.
    fn linuxcnc_refuses_motion(&mut self, b: &Block, motion: Option<i64>) -> bool {
        let has_axis = b.has_axis();
        if let Some(m) = motion
            && !has_axis
            && !matches!(m, 0 | 10 | 20 | 30 | 52 | 62 | 700 | 710..=712 | 720..=722 | 800)
        {
            self.err(
                "no-axis-words",
                None,
                format!(
                    "G{} with no axis word: LinuxCNC refuses it (\"All axes missing with motion \
                     code\")",
                    fmt_code(m)
                ),
            );
            return true;
        }
        let cycle = match (motion, self.st.mode) {
            (Some(m), _) => Some(m),
            (None, Mode::Cycle(m)) if has_axis => Some(m),
            _ => None,
        }
        .filter(|&m| matches!(m, 730 | 740 | 810..=890));
        if let Some(c) = cycle
            && let Some(axis) = ['A', 'B', 'C'].into_iter().find(|&a| b.val(a).is_some())
        {
            self.err(
                "axis-in-cycle",
                Some(b.col(axis)),
                format!(
                    "{axis} word in a G{} canned cycle: LinuxCNC refuses it (\"Cannot put {} {} \
                     in canned cycle\")",
                    fmt_code(c),
                    if axis == 'A' { "an" } else { "a" },
                    axis.to_ascii_lowercase()
                ),
            );
            return true;
        }
        if motion == Some(10)
            && !has_axis
            && self.st.feed_mode != FeedMode::InverseTime
            && self.st.feed <= 0.0
        {
            self.err(
                "no-feed-rate",
                None,
                "G1 with no axis word while no feed rate is set: LinuxCNC still refuses it \
                 (\"Cannot do g1 with zero feed rate\")"
                    .into(),
            );
            return true;
        }
        false
    }

    fn unused_words(&mut self, b: &Block) {
        if b.used_all || matches!(self.cfg.dialect, Dialect::Marlin | Dialect::Smoothie) {
            return;
        }
        let arc = b.used_arc;
        let checks: [(char, bool); 8] = [
            ('I', arc || b.used_i),
            ('J', arc),
            ('K', arc),
            ('R', arc || b.used_r),
            ('P', b.used_p),
            ('Q', b.used_q),
            ('L', b.used_l),
            ('E', b.used_l),
        ];
        for (c, used) in checks {
            if b.val(c).is_some() && !used {
                self.err(
                    "unused-word",
                    Some(b.col(c)),
                    format!("{c} word with no code in the block that uses it"),
                );
            }
        }
        if (b.val('H').is_some() && !b.used_h) || (b.val('D').is_some() && !b.used_d) {
            let c = if b.val('H').is_some() && !b.used_h {
                'H'
            } else {
                'D'
            };
            self.err(
                "unused-word",
                Some(b.col(c)),
                format!("{c} word with no code in the block that uses it"),
            );
        }
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

    fn cs_origin(&self, n: usize) -> DVec3 {
        let base = P_G54 + 20 * (n - 1);
        DVec3::new(
            self.params[base],
            self.params[base + 1],
            self.params[base + 2],
        )
    }

    fn select_cs(&mut self, n: usize) {
        self.st.cs = n;
        self.params[P_CS] = n as f64;
        self.st.g5x = self.cs_origin(n);
    }

    fn g92_stored(&self) -> DVec3 {
        DVec3::new(
            self.params[P_G92],
            self.params[P_G92 + 1],
            self.params[P_G92 + 2],
        )
    }

    fn store(&mut self, base: usize, v: DVec3) {
        self.params[base] = v.x;
        self.params[base + 1] = v.y;
        self.params[base + 2] = v.z;
    }

    /// G10, G28, G30, G52, G53 (handled with the motion), G92*.
    fn nonmodal(&mut self, c: i64, b: &mut Block) {
        let k = self.st.k();
        let axes = |b: &Block| -> [Option<f64>; 3] {
            [b.val('X'), b.val('Y'), b.val('Z')].map(|v| v.map(|v| v * k))
        };
        match c {
            100 => {
                b.axes_used = true;
                b.used_l = true;
                b.used_p = true;
                b.used_r = true;
                let l = b.val('L').map(|l| l.round() as i64);
                let p = b.val('P').map(|p| p.round() as i64);
                let a = axes(b);
                match (l, p) {
                    (Some(2) | Some(20), Some(p)) if (0..=9).contains(&p) => {
                        let n = if p == 0 { self.st.cs } else { p as usize };
                        if b.val('R').is_some_and(|r| r != 0.0) {
                            self.err(
                                "unsupported-code",
                                None,
                                "G10 L2 R (coordinate system rotation) is not supported".into(),
                            );
                        }
                        let mut o = self.cs_origin(n);
                        for i in 0..3 {
                            if let Some(v) = a[i] {
                                o[i] = if l == Some(2) {
                                    v
                                } else {
                                    self.st.pos[i] - self.st.g92[i] - self.st.tlo[i] - v
                                };
                            }
                        }
                        self.store(P_G54 + 20 * (n - 1), o);
                        if n == self.st.cs {
                            self.st.g5x = o;
                        }
                    }
                    (Some(1) | Some(10) | Some(11), Some(p)) if p >= 0 => {
                        let mut t = self.tool(p as u32).copied().unwrap_or(ToolEntry {
                            number: p as u32,
                            ..Default::default()
                        });
                        if let Some(z) = a[2] {
                            t.z = if l == Some(1) {
                                z
                            } else {
                                self.st.pos.z - self.st.g5x.z - self.st.g92.z - z
                            };
                        }
                        if let Some(x) = a[0] {
                            t.x = if l == Some(1) {
                                x
                            } else {
                                self.st.pos.x - self.st.g5x.x - self.st.g92.x - x
                            };
                        }
                        if let Some(r) = b.val('R') {
                            t.diameter = 2.0 * r * k;
                        }
                        // The tool table is configuration; G10 L1 edits a copy for this run.
                        self.tools.retain(|e| e.number != t.number);
                        self.tools.push(t);
                    }
                    _ => self.err(
                        "invalid-value",
                        None,
                        "G10 needs L1, L2, L10, L11 or L20 with a valid P".into(),
                    ),
                }
            }
            280 | 300 => {
                b.axes_used = true;
                let stored = DVec3::from_array(std::array::from_fn(|i| {
                    self.params[if c == 280 { P_G28 } else { P_G30 } + i]
                }));
                let a = axes(b);
                let mut target = stored;
                if a.iter().any(Option::is_some) {
                    let mid = self.target(b);
                    self.straight(MotionKind::Rapid, mid);
                    for i in 0..3 {
                        if a[i].is_none() {
                            target[i] = self.st.pos[i];
                        }
                    }
                }
                self.straight(MotionKind::Rapid, target);
            }
            281 | 301 => {
                let p = self.st.pos;
                self.store(if c == 281 { P_G28 } else { P_G30 }, p);
            }
            520 | 920 => {
                b.axes_used = true;
                let a = axes(b);
                let mut o = self.st.g92;
                for i in 0..3 {
                    if let Some(v) = a[i] {
                        o[i] = if c == 520 {
                            v
                        } else {
                            self.st.pos[i] - self.st.g5x[i] - self.st.tlo[i] - v
                        };
                    }
                }
                self.st.g92 = o;
                self.store(P_G92, o);
            }
            921 => {
                self.st.g92 = DVec3::ZERO;
                self.store(P_G92, DVec3::ZERO);
            }
            922 => self.st.g92 = DVec3::ZERO,
            923 => self.st.g92 = self.g92_stored(),
            530 => b.machine_coords = true,
            _ => {}
        }
    }

    /// The end point of the block's axis words in machine coordinates.
    fn target(&self, b: &Block) -> DVec3 {
        let k = self.st.k();
        let off = if b.machine_coords {
            DVec3::ZERO
        } else {
            self.st.offset()
        };
        let cur = self.st.pos - off;
        let mut t = cur;
        if b.val('@').is_some() || b.val('^').is_some() {
            // Polar words (LinuxCNC): @ distance and ^ angle (degrees) in the XY plane from
            // the origin; in G91 added to the current point's polar coordinates.
            let r0 = cur.truncate().length() / k;
            let a0 = cur.y.atan2(cur.x).to_degrees();
            let (mut r, mut a) = (b.val('@').unwrap_or(r0), b.val('^').unwrap_or(a0));
            if !self.st.absolute {
                r = r0 + b.val('@').unwrap_or(0.0);
                a = a0 + b.val('^').unwrap_or(0.0);
            }
            t.x = r * k * a.to_radians().cos();
            t.y = r * k * a.to_radians().sin();
        }
        let xyz = [b.val('X'), b.val('Y'), b.val('Z')];
        self.axes(t, cur, xyz, b.machine_coords) + off
    }

    /// `t` with the axis words `xyz` applied (program units, relative to `cur` in G91
    /// unless `machine`): the axis part of [`Interp::target`], before the offsets are
    /// added back.
    fn axes(&self, mut t: DVec3, cur: DVec3, xyz: [Option<f64>; 3], machine: bool) -> DVec3 {
        let k = self.st.k();
        for (i, v) in xyz.into_iter().enumerate() {
            if let Some(mut v) = v {
                if i == 0 && self.st.diameter_mode {
                    v *= 0.5;
                }
                t[i] = if self.st.absolute || machine {
                    v * k
                } else {
                    cur[i] + v * k
                };
            }
        }
        t
    }

    /// A block of plain words `G0`/`G1`, `X`, `Y`, `Z`, `F` and `S` (each at most once,
    /// numbers, F > 0, S ≥ 0) and `N` in a feed per minute mode with G0 or G1 in force or
    /// given: what CAM programs are made of (a laser's inline power in S too). Runs it as
    /// [`Interp::exec`] would (the same state changes, word count and move) without sorting
    /// it into a [`Block`]; returns false, having changed nothing, for any other line.
    fn plain_block(&mut self, l: &Line) -> bool {
        if !(l.errors.is_empty()
            && l.dollar.is_none()
            && l.oword.is_none()
            && l.comments.is_empty()
            && l.assigns.is_empty()
            && self.st.feed_mode == FeedMode::PerMinute)
        {
            return false;
        }
        let mut mode = self.st.mode;
        let mut xyz: [Option<f64>; 3] = [None; 3];
        let mut feed: Option<f64> = None;
        let mut speed: Option<f64> = None;
        let mut g = false;
        for w in &l.words {
            let Expr::Num(v) = w.value else {
                return false;
            };
            if !v.is_finite() {
                return false;
            }
            let slot = match w.letter {
                'G' if !g => {
                    g = true;
                    mode = match tenths(v) {
                        Some(0) => Mode::Rapid,
                        Some(10) => Mode::Linear,
                        _ => return false,
                    };
                    continue;
                }
                // Line numbers are counted as words and otherwise ignored (as in `collect`).
                'N' => continue,
                'X' => &mut xyz[0],
                'Y' => &mut xyz[1],
                'Z' => &mut xyz[2],
                // F0 takes the general route (Marlin and Smoothie ignore it).
                'F' if v > 0.0 => &mut feed,
                'S' if v >= 0.0 => &mut speed,
                _ => return false,
            };
            if slot.is_some() {
                return false;
            }
            *slot = Some(v);
        }
        let kind = match mode {
            Mode::Rapid => MotionKind::Rapid,
            Mode::Linear => MotionKind::Feed,
            _ => return false,
        };
        if l.words.is_empty() {
            return false;
        }
        // A G1 with no axis word and no feed rate: the general route reports LinuxCNC's refusal.
        if g && kind == MotionKind::Feed
            && feed.is_none()
            && self.st.feed <= 0.0
            && xyz.iter().all(Option::is_none)
        {
            return false;
        }
        // As exec, collect and execute do it, in their order.
        if self.src == 0 {
            self.prog.last_line = self.line;
        }
        self.prog.words += l.words.len();
        if let Some(f) = feed {
            self.st.feed = f;
            self.st.feed_k = self.st.k();
        }
        if let Some(s) = speed {
            let spindle = self.st.tool.spindle;
            self.st.tool.switch(spindle, s);
        }
        self.st.mode = mode;
        if xyz.iter().any(Option::is_some) {
            let off = self.st.offset();
            let cur = self.st.pos - off;
            let to = self.axes(cur, cur, xyz, false) + off;
            self.straight(kind, to);
        }
        true
    }

    fn motion(&self, kind: MotionKind, to: DVec3, arc: Option<Arc>) -> Motion {
        Motion {
            kind,
            from: self.st.pos,
            to,
            arc,
            feed: self.st.feed * self.st.feed_k,
            tool: self.st.tool,
            line: self.calls.first().map_or(self.line, |c| {
                if c.ret.0 == 0 { c.ret.1 } else { self.line }
            }),
            group: self.group,
        }
    }

    fn push(&mut self, mut m: Motion) {
        // Finite words can still overflow (G91 X1e308 twice, or from -1e308 to 1e308): no
        // NaN or infinity reaches the lengths, the bounds or the time. The squared length
        // (no square root on the hot path) overflows from about 1e154 mm on: out of range
        // too. Arcs are checked in `arc_move`.
        if !(m.to - m.from).length_squared().is_finite() {
            return self.out_of_range();
        }
        if m.kind == MotionKind::Feed
            && self.st.feed_mode != FeedMode::InverseTime
            && self.st.feed <= 0.0
        {
            self.no_feed(&mut m);
        }
        m.feed = match self.st.feed_mode {
            FeedMode::PerMinute => m.feed,
            FeedMode::InverseTime => m.length() * self.st.feed,
            FeedMode::PerRev => m.feed * self.st.tool.s,
        };
        m.group = self.group;
        self.emit(m);
    }

    /// The firmware's feed rate (mm/min) before any F word, for dialects that have one.
    fn firmware_feed(&self) -> Option<f64> {
        match self.cfg.dialect {
            Dialect::Marlin => Some(MARLIN_DEFAULT_FEED_MM_MIN),
            Dialect::Smoothie => Some(SMOOTHIE_DEFAULT_FEED_MM_MIN),
            _ => None,
        }
    }

    /// A feed move `m` while no feed rate is set (no F yet, or F0): LinuxCNC and GRBL refuse
    /// it (an error, one per line); Marlin and Smoothieware run it at their default feed
    /// (a warning, once); the generic dialect warns and leaves the move untimed.
    fn no_feed(&mut self, m: &mut Motion) {
        if let Some(f) = self.firmware_feed() {
            // Ungiven F is the firmware default from then on (F0 never reaches here: ignored).
            self.st.feed = f;
            self.st.feed_k = 1.0;
            m.feed = f;
            if self.no_feed_at.is_none() {
                self.no_feed_at = Some((self.src, self.line));
                self.warn(
                    "no-feed-rate",
                    None,
                    format!("feed move before any F: the firmware default F{f} mm/min applies"),
                );
            }
            return;
        }
        if self.no_feed_at == Some((self.src, self.line)) {
            return;
        }
        let first = self.no_feed_at.is_none();
        self.no_feed_at = Some((self.src, self.line));
        let what = match self.st.mode {
            Mode::ArcCw | Mode::ArcCcw => "Cannot make arc with zero feed rate",
            Mode::Cycle(_) => "Cannot feed with zero feed rate",
            _ => "Cannot do g1 with zero feed rate",
        };
        match self.cfg.dialect {
            Dialect::Linuxcnc => self.err("no-feed-rate", None, format!("{what} (LinuxCNC)")),
            Dialect::Grbl => self.err(
                "no-feed-rate",
                None,
                "feed rate has not yet been set or is undefined (GRBL error:22)".into(),
            ),
            _ if first => self.warn(
                "no-feed-rate",
                None,
                format!(
                    "feed move without a feed rate (LinuxCNC: \"{what}\", GRBL: error:22); \
                     not timed"
                ),
            ),
            _ => {}
        }
    }

    /// The error of a move whose end point or length is not a finite number.
    fn out_of_range(&mut self) {
        self.err(
            "invalid-value",
            None,
            "the move's end point or length is out of range (not a finite number)".into(),
        );
    }

    fn straight(&mut self, kind: MotionKind, to: DVec3) {
        if !to.is_finite() {
            return self.out_of_range();
        }
        if to != self.st.pos {
            let m = self.motion(kind, to, None);
            self.push(m);
        }
        self.st.pos = to;
    }

    fn move_block(&mut self, mode: Mode, b: &mut Block) {
        if self.st.feed_mode == FeedMode::InverseTime
            && !matches!(mode, Mode::Rapid)
            && b.val('F').is_none()
        {
            self.err(
                "invalid-value",
                None,
                "inverse time feed (G93) needs F on every feed move".into(),
            );
        }
        if self.cfg.dialect == Dialect::Linuxcnc
            && ['U', 'V', 'W'].into_iter().any(|c| b.val(c).is_some())
        {
            self.err(
                "unsupported-code",
                None,
                "U V W axes are not supported (rs274 without an INI file has X Y Z A B C)".into(),
            );
        }
        if !self.reported_axes
            && ['A', 'B', 'C', 'U', 'V', 'W']
                .into_iter()
                .any(|c| b.val(c).is_some())
        {
            self.reported_axes = true;
            self.warn(
                "unsupported-code",
                None,
                "rotary and secondary axes (A B C U V W) are not supported: ignored".into(),
            );
        }
        match mode {
            Mode::Rapid | Mode::Linear => {
                let to = self.target(b);
                let kind = if mode == Mode::Rapid {
                    MotionKind::Rapid
                } else {
                    MotionKind::Feed
                };
                self.straight(kind, to);
            }
            Mode::ArcCw | Mode::ArcCcw => {
                b.used_arc = true;
                if b.machine_coords {
                    self.err(
                        "invalid-value",
                        None,
                        "G53 needs G0 or G1, not an arc".into(),
                    );
                    return;
                }
                self.arc_move(mode == Mode::ArcCcw, b);
            }
            Mode::Cycle(c) => self.cycle(c, b),
            Mode::Off => {}
        }
    }

    /// Arc in the selected plane: exact for G17, chords within [`CHORD_ANGLE`] otherwise.
    fn arc_move(&mut self, ccw: bool, b: &Block) {
        let k = self.st.k();
        let to = self.target(b);
        let from = self.st.pos;
        // (first, second, linear) axis indices of the plane (LinuxCNC: XY, ZX, YZ).
        let (u, v, w, cu, cv) = match self.st.plane {
            Plane::Xy => (0, 1, 2, 'I', 'J'),
            Plane::Xz => (2, 0, 1, 'K', 'I'),
            Plane::Yz => (1, 2, 0, 'J', 'K'),
        };
        for (c, axis) in [('I', 0), ('J', 1), ('K', 2)] {
            if b.val(c).is_some() && axis == w {
                self.err(
                    "invalid-arc",
                    Some(b.col(c)),
                    format!("{c} is not an arc offset in the selected plane"),
                );
                return;
            }
        }
        let p0 = DVec2::new(from[u], from[v]);
        let p1 = DVec2::new(to[u], to[v]);
        let tol = self.radius_tolerance();
        let center = if let Some(r) = b.val('R') {
            if b.val(cu).is_some() || b.val(cv).is_some() {
                self.err("invalid-arc", None, "arc with both R and I/J/K".into());
                return;
            }
            match r_center(p0, p1, r * k, ccw, tol) {
                Ok(c) => c,
                Err(m) => return self.err("invalid-arc", None, m),
            }
        } else {
            if b.val(cu).is_none() && b.val(cv).is_none() {
                self.err(
                    "invalid-arc",
                    None,
                    "arc needs R or a centre offset (I/J/K) in the selected plane".into(),
                );
                return;
            }
            let off = DVec2::new(b.val(cu).unwrap_or(0.0) * k, b.val(cv).unwrap_or(0.0) * k);
            let c = if self.st.arc_absolute {
                let o = self.st.offset();
                off + DVec2::new(o[u], o[v])
            } else {
                p0 + off
            };
            let r0 = p0.distance(c);
            let r1 = p1.distance(c);
            if r0 == 0.0 {
                return self.err("invalid-arc", None, "arc centre at its start point".into());
            }
            let diff = (r0 - r1).abs();
            let linuxcnc_abs = LINUXCNC_RADIUS_TOLERANCE_MM * k / self.st.k().max(1.0)
                * if self.st.units == Units::Inch {
                    2.54
                } else {
                    1.0
                };
            let hard = matches!(self.cfg.dialect, Dialect::Generic | Dialect::Linuxcnc)
                && diff > 100.0 * linuxcnc_abs;
            if hard || (diff > tol && diff > RADIUS_RELATIVE_TOLERANCE * r0) {
                return self.err(
                    "invalid-arc",
                    None,
                    format!(
                        "radius to end {r1:.4} mm differs from radius to start {r0:.4} mm by \
                         {diff:.4} mm"
                    ),
                );
            }
            c
        };
        let turns = b.val('P').map_or(1.0, |p| p.round().max(1.0));
        // In XY each turn after the first counts against the loop budget (`as` saturates);
        // in the other planes the chords do, below.
        if self.st.plane == Plane::Xy && turns > 1.0 && !self.count_work((turns - 1.0) as u64) {
            return;
        }
        let mut arc = arc_between(center, p0, p1, ccw);
        if turns > 1.0 {
            arc.sweep += arc.sweep.signum() * (turns - 1.0) * TAU;
        }
        let finite = arc.center.is_finite()
            && arc.radius.is_finite()
            && arc.sweep.is_finite()
            && arc.length().is_finite()
            && to.is_finite();
        if !finite {
            return self.err(
                "invalid-arc",
                None,
                "the arc's centre, radius or length is not a finite number (its words \
                 overflow)"
                    .into(),
            );
        }
        if arc.radius > MAX_ARC_RADIUS_MM {
            return self.err(
                "invalid-arc",
                None,
                format!(
                    "arc radius {:.4e} mm is larger than {MAX_ARC_RADIUS_MM:.0e} mm",
                    arc.radius
                ),
            );
        }
        if self.st.plane == Plane::Xy {
            let m = self.motion(MotionKind::Feed, to, Some(arc));
            self.push(m);
            self.st.pos = to;
            return;
        }
        let n = ((arc.sweep.abs() / CHORD_ANGLE).ceil() as usize).clamp(1, 1_000_000);
        // The chords beyond one full turn's count against the loop budget.
        let turn = (TAU / CHORD_ANGLE).ceil() as usize;
        if n > turn && !self.count_work((n - turn) as u64) {
            return;
        }
        for s in 1..=n {
            let t = s as f64 / n as f64;
            let q = if s == n { p1 } else { arc.eval(t) };
            let mut pt = DVec3::ZERO;
            pt[u] = q.x;
            pt[v] = q.y;
            pt[w] = from[w] + (to[w] - from[w]) * t;
            let m = self.motion(MotionKind::Feed, pt, None);
            self.push(m);
            self.st.pos = pt;
        }
        self.st.pos = to;
    }

    fn radius_tolerance(&self) -> f64 {
        match self.cfg.dialect {
            Dialect::Generic | Dialect::Linuxcnc => {
                let lc = if self.st.units == Units::Inch {
                    0.002 * 25.4
                } else {
                    LINUXCNC_RADIUS_TOLERANCE_MM
                };
                self.cfg.arc_radius_tolerance.max(lc)
            }
            _ => self.cfg.arc_radius_tolerance,
        }
    }

    /// Canned cycles in the XY plane, expanded as LinuxCNC does (`convert_cycle_xy`):
    /// preliminary rapid up to R when below it, then per repeat (L): rapid in XY at the
    /// current height, rapid down to R, the cycle's own moves, retract to R (G99) or to the
    /// height before the cycle (G98).
    fn cycle(&mut self, code: i64, b: &mut Block) {
        let k = self.st.k();
        b.used_r = true;
        b.used_l = true;
        b.used_p = true;
        b.used_q = true;
        if self.st.plane != Plane::Xy {
            self.err(
                "unsupported-code",
                None,
                format!("G{} outside the XY plane is not supported", fmt_code(code)),
            );
            return;
        }
        if matches!(code, 870 | 760 | 840 | 740) && code != 840 {
            self.err(
                "unsupported-code",
                None,
                format!(
                    "G{} is not supported: its motion is skipped",
                    fmt_code(code)
                ),
            );
            return;
        }
        if let Some(r) = b.val('R') {
            self.st.cycle_r = Some(r);
        }
        if let Some(z) = b.val('Z') {
            self.st.cycle_z = Some(z);
        }
        if let Some(q) = b.val('Q') {
            self.st.cycle_q = Some(q);
        }
        if let Some(p) = b.val('P') {
            self.st.cycle_p = Some(p);
        }
        let (Some(r), Some(z)) = (self.st.cycle_r, self.st.cycle_z) else {
            self.err(
                "invalid-value",
                None,
                format!("G{} needs R and Z", fmt_code(code)),
            );
            return;
        };
        let off = self.st.offset();
        let old_z = *self.st.cycle_start_z.get_or_insert(self.st.pos.z);
        // R and Z in machine coordinates; incremental (G91): R from the Z where the series of
        // cycles started, Z from R (as rs274 does).
        let (r_m, z_m) = if self.st.absolute {
            (r * k + off.z, z * k + off.z)
        } else {
            (old_z + r * k, old_z + r * k + z * k)
        };
        if z_m > r_m {
            self.err(
                "invalid-value",
                None,
                "canned cycle bottom Z is above the R plane".into(),
            );
            return;
        }
        let q = self.st.cycle_q.map(|q| q * k);
        if matches!(code, 730 | 830) && q.is_none_or(|q| q <= 0.0) {
            self.err(
                "invalid-value",
                None,
                format!("G{} needs Q > 0 (peck depth)", fmt_code(code)),
            );
            return;
        }
        let dwell = self.st.cycle_p.unwrap_or(0.0);
        let reps = b.val('L').map_or(1, |l| l.round().max(0.0) as usize);
        if self.st.pos.z < r_m {
            let p = DVec3::new(self.st.pos.x, self.st.pos.y, r_m);
            self.straight(MotionKind::Rapid, p);
        }
        let clear = if self.st.retract_r {
            r_m
        } else {
            old_z.max(r_m)
        };
        let mut cur_z = self.st.pos.z;
        for rep in 0..reps {
            // Each repeat after the first counts against the loop budget.
            if rep > 0 && !self.count_iteration() {
                return;
            }
            // X Y (or polar @ ^) of this hole; in G91 each repeat moves by X Y again.
            let mut xy = self.st.pos;
            if b.val('@').is_some() || b.val('^').is_some() {
                let mut pb = b.clone();
                pb.vals[2] = None;
                xy = self.target(&pb);
            } else {
                for (i, c) in ['X', 'Y'].into_iter().enumerate() {
                    if let Some(v) = b.val(c) {
                        xy[i] = if self.st.absolute {
                            v * k + off[i]
                        } else {
                            self.st.pos[i] + v * k
                        };
                    }
                }
            }
            self.straight(MotionKind::Rapid, DVec3::new(xy.x, xy.y, cur_z));
            if cur_z != r_m {
                self.straight(MotionKind::Rapid, DVec3::new(xy.x, xy.y, r_m));
            }
            let at = |z: f64| DVec3::new(xy.x, xy.y, z);
            match code {
                810 => {
                    self.straight(MotionKind::Feed, at(z_m));
                    self.straight(MotionKind::Rapid, at(clear));
                }
                820 | 890 | 860 | 880 | 850 => {
                    self.straight(MotionKind::Feed, at(z_m));
                    if code != 850 && dwell > 0.0 {
                        let m = self.motion(MotionKind::Dwell { seconds: dwell }, at(z_m), None);
                        self.emit(m);
                    }
                    match code {
                        850 | 890 => {
                            self.straight(MotionKind::Feed, at(r_m));
                            self.straight(MotionKind::Rapid, at(clear));
                        }
                        _ => self.straight(MotionKind::Rapid, at(clear)),
                    }
                }
                840 => {
                    self.straight(MotionKind::Feed, at(z_m));
                    self.straight(MotionKind::Feed, at(r_m));
                    self.straight(MotionKind::Rapid, at(clear));
                }
                730 | 830 => {
                    let q = q.unwrap_or(1.0);
                    let mut depth = r_m;
                    while depth > z_m {
                        // Each peck after the first counts against the loop budget.
                        if depth < r_m && !self.count_iteration() {
                            return;
                        }
                        let next = (depth - q).max(z_m);
                        if code == 830 && depth < r_m {
                            self.straight(MotionKind::Rapid, at(depth + PECK_CLEARANCE_MM));
                        }
                        self.straight(MotionKind::Feed, at(next));
                        depth = next;
                        if depth > z_m {
                            if code == 830 {
                                self.straight(MotionKind::Rapid, at(r_m));
                            } else {
                                self.straight(MotionKind::Rapid, at(depth + PECK_CLEARANCE_MM));
                            }
                        }
                    }
                    self.straight(MotionKind::Rapid, at(clear));
                }
                _ => {}
            }
            cur_z = clear;
        }
    }
}

/// Parameter access for expressions.
struct View<'v, 'a, 'o> {
    it: &'v Interp<'a, 'o>,
}

/// Named parameters LinuxCNC predefines (read-only).
fn predefined(name: &str) -> bool {
    const NAMES: [&str; 33] = [
        "_x",
        "_y",
        "_z",
        "_a",
        "_b",
        "_c",
        "_u",
        "_v",
        "_w",
        "_abs_x",
        "_abs_y",
        "_abs_z",
        "_line",
        "_motion_mode",
        "_plane",
        "_metric",
        "_imperial",
        "_absolute",
        "_incremental",
        "_inverse_time",
        "_units_per_minute",
        "_units_per_rev",
        "_coord_system",
        "_tool_offset",
        "_retract_r_plane",
        "_retract_old_z",
        "_current_tool",
        "_selected_tool",
        "_feed",
        "_rpm",
        "_call_level",
        "_task",
        "_value",
    ];
    NAMES.contains(&name)
        || matches!(
            name,
            "_value_returned" | "_vmajor" | "_vminor" | "_spindle_on" | "_flood" | "_mist"
        )
}

impl ParamSource for View<'_, '_, '_> {
    fn numbered(&self, n: i64) -> f64 {
        let st = &self.it.st;
        let k = st.k();
        let n = n as usize;
        match n {
            5400 => st.current_tool as f64,
            5401..=5409 => st.tlo.to_array().get(n - 5401).map_or(0.0, |v| v / k),
            5420..=5428 => st
                .program_pos()
                .to_array()
                .get(n - 5420)
                .map_or(0.0, |v| v / k),
            5161..=5169 | 5181..=5189 | 5211..=5219 | 5221..=5400 => {
                let base = (n - 1) % 10;
                let axis_like = base < 3 || (n >= 5221 && (n - 5221) % 20 < 3);
                if axis_like {
                    self.it.params[n] / k
                } else {
                    self.it.params[n]
                }
            }
            _ => self.it.params[n],
        }
    }

    fn named(&self, name: &str) -> Option<f64> {
        let it = self.it;
        if !name.starts_with('_') {
            return it.locals.get(name).copied();
        }
        if let Some(v) = it.globals.get(name) {
            return Some(*v);
        }
        let st = &it.st;
        let k = st.k();
        let t = |c: bool| if c { 1.0 } else { 0.0 };
        let pp = st.program_pos() / k;
        Some(match name {
            "_x" => pp.x,
            "_y" => pp.y,
            "_z" => pp.z,
            "_a" | "_b" | "_c" | "_u" | "_v" | "_w" => 0.0,
            "_abs_x" => st.pos.x / k,
            "_abs_y" => st.pos.y / k,
            "_abs_z" => st.pos.z / k,
            "_line" => it.line as f64,
            "_motion_mode" => match st.mode {
                Mode::Rapid => 0.0,
                Mode::Linear => 10.0,
                Mode::ArcCw => 20.0,
                Mode::ArcCcw => 30.0,
                Mode::Cycle(c) => c as f64,
                Mode::Off => 800.0,
            },
            "_plane" => match st.plane {
                Plane::Xy => 170.0,
                Plane::Xz => 180.0,
                Plane::Yz => 190.0,
            },
            "_metric" => t(st.units == Units::Mm),
            "_imperial" => t(st.units == Units::Inch),
            "_absolute" => t(st.absolute),
            "_incremental" => t(!st.absolute),
            "_inverse_time" => t(st.feed_mode == FeedMode::InverseTime),
            "_units_per_minute" => t(st.feed_mode == FeedMode::PerMinute),
            "_units_per_rev" => t(st.feed_mode == FeedMode::PerRev),
            "_coord_system" => [
                540.0, 550.0, 560.0, 570.0, 580.0, 590.0, 591.0, 592.0, 593.0,
            ][st.cs.clamp(1, 9) - 1],
            "_tool_offset" => t(st.tlo != DVec3::ZERO),
            "_retract_r_plane" => t(st.retract_r),
            "_retract_old_z" => t(!st.retract_r),
            "_current_tool" => st.current_tool as f64,
            "_selected_tool" => st.selected_tool as f64,
            "_feed" => st.feed,
            "_rpm" => st.tool.s,
            "_spindle_on" => t(st.tool.spindle != Spindle::Off),
            "_flood" => t(st.flood),
            "_mist" => t(st.mist),
            "_call_level" => it.calls.len() as f64,
            "_task" => 0.0,
            "_vmajor" => 2.0,
            "_vminor" => 9.0,
            "_value" => it.value.unwrap_or(0.0),
            "_value_returned" => t(it.value.is_some()),
            _ => return None,
        })
    }
}

// Modal groups (LinuxCNC manual, "Modal groups").
const G_NONMODAL: usize = 0;
const G_MOTION: usize = 1;
const G_PLANE: usize = 2;
const G_DISTANCE: usize = 3;
const G_ARC_DISTANCE: usize = 4;
const G_FEED_MODE: usize = 5;
const G_UNITS: usize = 6;
const G_COMP: usize = 7;
const G_TLO: usize = 8;
const G_RETURN: usize = 9;
const G_COORD: usize = 10;
const G_PATH: usize = 11;
const G_SPINDLE: usize = 12;
const G_LATHE: usize = 13;
const M_STOP: usize = 14;
const M_TOOL: usize = 15;
const M_SPINDLE: usize = 16;
const M_COOLANT: usize = 17;
const M_COOLANT2: usize = 18;
const M_OVERRIDE: usize = 19;
const M_IO: usize = 20;
const M_STATE: usize = 21;
const M_USER: usize = 22;
const GROUPS: usize = 23;

const LETTERS: [char; 24] = [
    'X', 'Y', 'Z', 'I', 'J', 'K', 'R', 'F', 'S', 'P', 'Q', 'L', 'T', 'H', 'D', 'A', 'B', 'C', 'U',
    'V', 'W', '@', '^', 'E',
];

/// Index of each ASCII character in [`LETTERS`] (`u8::MAX`: none).
const LETTER_INDEX: [u8; 128] = {
    let mut t = [u8::MAX; 128];
    let mut i = 0;
    while i < LETTERS.len() {
        t[LETTERS[i] as usize] = i as u8;
        i += 1;
    }
    t
};

/// The position of `c` in [`LETTERS`].
fn letter_index(c: char) -> Option<usize> {
    let i = *LETTER_INDEX.get(c as usize)?;
    (i != u8::MAX).then_some(usize::from(i))
}

/// A stored group code: −1 is none.
fn group_code(stored: i32) -> Option<i64> {
    (stored >= 0).then_some(i64::from(stored))
}

/// The words of one block sorted into what the interpreter needs.
#[derive(Clone)]
struct Block {
    /// Code per modal group (as [`tenths`] gives it), −1 for none: codes are below 10⁹.
    groups: [i32; GROUPS],
    vals: [Option<f64>; 24],
    cols: [usize; 24],
    machine_coords: bool,
    axes_used: bool,
    used_arc: bool,
    used_i: bool,
    used_r: bool,
    used_p: bool,
    used_q: bool,
    used_l: bool,
    used_h: bool,
    used_d: bool,
    used_all: bool,
}

impl Block {
    fn new() -> Self {
        Block {
            groups: [-1; GROUPS],
            vals: [None; 24],
            cols: [0; 24],
            machine_coords: false,
            axes_used: false,
            used_arc: false,
            used_i: false,
            used_r: false,
            used_p: false,
            used_q: false,
            used_l: false,
            used_h: false,
            used_d: false,
            used_all: false,
        }
    }

    /// The code of modal group `g` in the block.
    fn group(&self, g: usize) -> Option<i64> {
        group_code(self.groups[g])
    }

    /// Records `code` (a [`tenths`] value, 0..10⁹) for modal group `g`.
    fn set_group(&mut self, g: usize, code: i64) {
        self.groups[g] = i32::try_from(code).unwrap_or(i32::MAX);
    }

    fn val(&self, c: char) -> Option<f64> {
        letter_index(c).and_then(|i| self.vals[i])
    }

    fn col(&self, c: char) -> usize {
        letter_index(c).map_or(1, |i| self.cols[i])
    }

    fn has_axis(&self) -> bool {
        ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W', '@', '^']
            .into_iter()
            .any(|c| self.val(c).is_some())
    }
}

/// The code as an integer number of tenths (G90.1 → 901), None if not a tenth (or
/// negative, or 10⁹ tenths or more). The tenths are rounded half away from zero, as
/// `f64::round` does, but by truncation (exact below 2⁵³): `f64::round` is a libm call on
/// the x86-64 baseline, and this runs for every G and M word.
fn tenths(v: f64) -> Option<i64> {
    let x = v * 10.0;
    // round(x) lies in [0, 10⁹) exactly when x lies in (−0.5, 10⁹ − 0.5).
    if !(x > -0.5 && x < 1e9 - 0.5) {
        return None;
    }
    let r = x as i64;
    let t = if x - r as f64 >= 0.5 { r + 1 } else { r };
    ((x - t as f64).abs() < 1e-6).then_some(t)
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

    fn run_cfg(src: &str, cfg: &CheckConfig) -> Program {
        interpret_with(src, cfg, &Options { load_sub: None })
    }

    /// [`interpret_with`] without the plain block route: every block goes through
    /// `collect` and `execute`.
    fn run_general(src: &str, cfg: &CheckConfig) -> Program {
        let opts = Options { load_sub: None };
        let mut it = new_interp(cfg, &opts);
        it.plain_moves = false;
        it.add_source("program".into(), Cow::Borrowed(src));
        it.run(None, None);
        it.prog.final_tool = it.st.tool;
        it.prog
    }

    /// Lines the plain route takes or must refuse, mixed with the modal state they depend on.
    const PLAIN_MIX: [&str; 42] = [
        "N10 G1 X1 Y1",
        "N20 N30 X2",
        "N5",
        "G0 X1 Y2",
        "G1 X3.5 Y-1 F1200",
        "X2 Y2",
        "Y0.25",
        "Z-1",
        "G1 Z0 F-5",
        "G1 X1 X2",
        "G0 G1 X4",
        "F300",
        "G1",
        "G01 X0.5",
        "G91",
        "G90",
        "G20",
        "G21",
        "G93",
        "G94",
        "G95",
        "G2 X1 Y0 I0.5 J0",
        "M3 S100",
        "M5",
        "G7",
        "G8",
        "G53 G0 X1",
        "G92 X0 Y0",
        "G92.1",
        "G80",
        "G81 X1 Y1 Z-1 R1",
        "G55",
        "G54",
        "X1 I2",
        "G1 X2 (c)",
        "G1 X1 Y2 S500",
        "X3 S0",
        "G0 X1 S-5",
        "S250",
        "M4",
        "G1 X2 S12.5 S3",
        "M3",
    ];

    /// [`tenths`] by its definition with `f64::round`.
    fn tenths_by_round(v: f64) -> Option<i64> {
        let t = (v * 10.0).round();
        ((v * 10.0 - t).abs() < 1e-6 && t.abs() < 1e9 && t >= 0.0).then_some(t as i64)
    }

    #[test]
    fn tenths_match_rounding_at_the_edges() {
        let edges = [
            0.0,
            -0.0,
            0.1,
            90.1,
            38.2,
            1.0,
            -0.04,
            -0.05,
            -0.049999999,
            0.05,
            0.0499999999,
            99_999_999.9,
            99_999_999.95,
            99_999_999.94,
            1e8,
            2.5e15,
            1e300,
            -1.0,
            0.30000001,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            4503599627370495.5,
        ];
        for v in edges {
            assert_eq!(tenths(v), tenths_by_round(v), "{v:e}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4096))]
        #[test]
        fn tenths_match_rounding(code in 0u32..2000, off in -1e-5f64..1e-5, any in proptest::num::f64::ANY) {
            let v = f64::from(code) / 10.0 + off;
            proptest::prop_assert_eq!(tenths(v), tenths_by_round(v));
            proptest::prop_assert_eq!(tenths(any), tenths_by_round(any));
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]
        /// The plain block route gives the program the general route gives: moves, state,
        /// words, findings, end, bit for bit.
        #[test]
        fn plain_blocks_match_the_general_route(
            picks in proptest::collection::vec(0usize..PLAIN_MIX.len(), 1..40),
            values in proptest::collection::vec(-50i32..50, 40),
            d in 0usize..5,
        ) {
            let mut src = String::new();
            for (k, &p) in picks.iter().enumerate() {
                // Vary the numbers: every digit string a value of `values`.
                let v = f64::from(values[k % values.len()]) / 8.0;
                src += &PLAIN_MIX[p].replace("0.5", &format!("{v}"));
                src.push('\n');
            }
            src += "M2\n";
            let dialect = [
                Dialect::Generic,
                Dialect::Linuxcnc,
                Dialect::Grbl,
                Dialect::Marlin,
                Dialect::Smoothie,
            ][d];
            let cfg = CheckConfig {
                dialect,
                ..CheckConfig::default()
            };
            let fast = run_cfg(&src, &cfg);
            let general = run_general(&src, &cfg);
            proptest::prop_assert_eq!(format!("{fast:?}"), format!("{general:?}"), "{}", src);
        }
    }

    /// `src` interpreted with its lines parsed on a second thread (`ahead`) or on this one.
    fn run_parsed(src: &str, cfg: &CheckConfig, ahead: bool) -> Program {
        let opts = Options { load_sub: None };
        let mut it = new_interp(cfg, &opts);
        it.add_source("program".into(), Cow::Borrowed(src));
        if ahead {
            std::thread::scope(|scope| {
                let mut a = ParseAhead::spawn(scope, src, it.syn);
                it.run(None, Some(&mut a));
            });
        } else {
            it.run(None, None);
        }
        it.prog.final_tool = it.st.tool;
        it.prog
    }

    #[test]
    fn parsing_ahead_gives_the_same_program() {
        // Several chunks of lines: a subroutine called in a loop (its lines met again come
        // from the cache), if/else jumping forward over whole chunks, errors, comments,
        // CRLF, empty and whitespace-only lines, and lines after the end.
        let chunk = parse_ahead::CHUNK_LINES;
        let mut src = String::from("o100 sub\nG1 X#1 Y[#1*2] F600\nG2 X0 Y0 I1 J1\no100 endsub\n");
        src += "#5 = 0\no200 while [#5 LT 3]\no100 call [#5 + 1]\n#5 = [#5 + 1]\no200 endwhile\n";
        src += "o300 if [#5 GT 10]\n";
        for k in 0..2 * chunk {
            src += &format!("G1 X{k} Y1 (skipped)\n");
        }
        src += "o300 else\n";
        for k in 0..3 * chunk {
            src += &match k % 6 {
                0 => format!("G1 X{}.5 Y-{k}\r\n", k % 97),
                1 if k % 4 == 1 => "\n".to_string(),
                // Whitespace only (the worker marks it blank), and a no-break space, which
                // `str::trim` takes as whitespace too.
                1 => " \t\u{a0}\r\n".to_string(),
                2 => format!("G0 Z{} ; lift\n", k % 5),
                3 => "G1 Q7 X1\n".to_string(),
                4 => format!("#7 = [#7 + {k}]\n"),
                _ => format!("N{k} G3 X{} Y0 R40\n", k % 31),
            };
        }
        src += "o300 endif\no100 call [2]\nM2\nG1 X5\n";
        for dialect in [Dialect::Linuxcnc, Dialect::Grbl] {
            let cfg = CheckConfig {
                dialect,
                ..CheckConfig::default()
            };
            let serial = run_parsed(&src, &cfg, false);
            let ahead = run_parsed(&src, &cfg, true);
            assert!(serial.motions.len() > chunk, "{dialect:?}");
            assert_eq!(format!("{serial:?}"), format!("{ahead:?}"), "{dialect:?}");
        }
    }

    fn ids(p: &Program) -> Vec<(&'static str, usize)> {
        p.diagnostics
            .iter()
            .filter(|d| d.severity != Severity::Info)
            .map(|d| (d.id, d.lines.first().copied().unwrap_or(0)))
            .collect()
    }

    fn end(p: &Program) -> DVec3 {
        p.motions.last().map(|m| m.to).unwrap_or(DVec3::NAN)
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    #[test]
    fn modal_lines_inch_relative() {
        let p = run("G20 G91\nG1 X1 Y1 F10\nX1\nG90 G0 X0 Y0\nM2");
        assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
        assert_eq!(p.motions.len(), 3);
        let m = &p.motions.to_vec()[1];
        assert!(close(m.to, DVec3::new(50.8, 25.4, 0.0)));
        assert_eq!(m.line, 3);
        assert!((m.feed - 254.0).abs() < 1e-12);
        assert_eq!(p.motions.to_vec()[2].kind, MotionKind::Rapid);
        assert_eq!(p.end.map(|e| e.line), Some(5));
    }

    #[test]
    fn arcs_ij_r_and_full_circle() {
        let p = run("G0 X10 Y0\nG3 X0 Y10 I-10 J0 F100\nG2 X0 Y10 I0 J-10");
        assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
        let q = p.motions.to_vec()[1]
            .arc
            .unwrap_or(Arc::new(DVec2::ZERO, 0.0, 0.0, 0.0));
        assert!((q.sweep - PI / 2.0).abs() < 1e-12);
        let c = p.motions.to_vec()[2].arc.unwrap_or(q);
        assert!((c.sweep + 2.0 * PI).abs() < 1e-12);
        for (code, r, sweep) in [("G3", 10.0, PI / 2.0), ("G2", -10.0, -1.5 * PI)] {
            let p = run(&format!("G0 X10 Y0\n{code} X0 Y10 R{r} F50"));
            let a = p.motions.to_vec()[1].arc.unwrap_or(q);
            assert!((a.sweep - sweep).abs() < 1e-9, "{code} R{r}: {}", a.sweep);
        }
        // The issue's planted arc: end radius 15 against start radius 5.
        let bad = run("G21 G90 G90.1\nG0 X10 Y0\nG2 X20 Y0 I5 J0 F100\nM2");
        assert_eq!(ids(&bad), vec![("invalid-arc", 3)]);
    }

    #[test]
    fn arcs_in_xz_and_yz_planes_are_chords_of_the_true_arc() {
        // G18 half circle of radius 5 from (0,0,0) to (10,0,0) about (5,0,0): length 5π.
        let p = run("G18 G1 F100\nG2 X10 Z0 I5 K0\nG19 G3 Y10 Z0 J5 K0");
        assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
        let len: f64 = p.motions.iter().map(|m| m.length()).sum();
        assert!((len - 10.0 * PI).abs() / (10.0 * PI) < 1e-4, "{len}");
        let zmax = p.motions.iter().map(|m| m.to.z).fold(f64::MIN, f64::max);
        let zmin = p.motions.iter().map(|m| m.to.z).fold(f64::MAX, f64::min);
        // Both go through -Z: G18 G2 is clockwise in the (Z, X) frame rs274's ARC_FEED uses,
        // G19 G3 counter-clockwise in (Y, Z).
        assert!(
            zmax.abs() < 1e-12 && (zmin + 5.0).abs() < 1e-3,
            "{zmax} {zmin}"
        );
    }

    #[test]
    fn parameters_are_assigned_after_the_block_reads_them() {
        let p = run("#1 = 5\n#1 = 6 G0 X#1\nY#1\n#<len> = [#1 * 2] Z#<len>");
        assert_eq!(ids(&p), vec![("expression", 4)]);
        assert!(close(p.motions.to_vec()[1].to, DVec3::new(5.0, 6.0, 0.0)));
        // #<_x> is read before the block moves: Z gets the X of the line before.
        let q = run("#<len> = 3\nG0 X[#<len> * 2] Y[2 ** 3] Z#<_x>\nG0 Z#<_x>");
        assert!(close(end(&q), DVec3::new(6.0, 8.0, 6.0)), "{:?}", end(&q));
    }

    #[test]
    fn subroutines_with_arguments_and_return_values() {
        let src = "o<sq> sub\n  G1 X[#1 * #1] F100\n  o<sq> return [#1 + 1]\no<sq> endsub\n\
                   o<sq> call [3]\nG0 Y#<_value>\no100 sub\n#<local> = 7\no100 endsub\n\
                   o100 call\no101 if [EXISTS[#<local>]]\nG0 Z99\no101 else\nG0 Z1\no101 endif\nM2";
        let p = run(src);
        assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
        assert!(close(p.motions.to_vec()[0].to, DVec3::new(9.0, 0.0, 0.0)));
        // Moves inside a call carry the caller's line.
        assert_eq!(p.motions.to_vec()[0].line, 5);
        assert!(close(end(&p), DVec3::new(9.0, 4.0, 1.0)), "{:?}", end(&p));
    }

    #[test]
    fn loops_if_elseif_break_continue() {
        let src = "#1 = 0\no1 while [#1 LT 5]\n#1 = [#1 + 1]\no2 if [#1 EQ 2]\no1 continue\n\
                   o2 elseif [#1 EQ 4]\no1 break\no2 else\nG1 X#1 F10\no2 endif\no1 endwhile\n\
                   #2 = 0\no3 do\n#2 = [#2 + 1]\no3 while [#2 LT 3]\nG1 Y#2\n\
                   o4 repeat [4]\nG91 G1 Z1\no4 endrepeat\nG90\nM2";
        let p = run(src);
        assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
        let xs: Vec<f64> = p.motions.iter().map(|m| m.to.x).collect();
        assert_eq!(&xs[..2], &[1.0, 3.0]);
        assert!(close(end(&p), DVec3::new(3.0, 3.0, 4.0)), "{:?}", end(&p));
    }

    #[test]
    fn runaway_loops_and_recursion_stop_with_clear_errors() {
        // The default budget (one million iterations) against a 10M-iteration while.
        let cfg = CheckConfig::default();
        let p = run_cfg(
            "#1 = 0\no1 while [#1 LT 10000000]\n#1 = [#1 + 1]\no1 endwhile\nG0 X1\nM2",
            &cfg,
        );
        assert_eq!(ids(&p), vec![("loop-limit", 4)]);
        assert!(p.diagnostics[0].message.contains("1000000 iterations"));
        assert!(p.motions.is_empty());
        let r = run("o<r> sub\no<r> call\no<r> endsub\no<r> call\nM2");
        assert_eq!(ids(&r)[0].0, "call-depth");
        assert!(r.diagnostics[0].message.contains("10 subroutine levels"));
    }

    #[test]
    fn modal_group_conflicts_are_errors() {
        for (src, col) in [
            ("G90 G91 X1", 5),
            ("G20 G21", 5),
            ("G0 G1 X1", 4),
            ("M3 M5", 4),
            ("M7 M9", 4),
            ("M9 M7", 4),
            ("M9 M8", 4),
        ] {
            let p = run(src);
            assert_eq!(ids(&p), vec![("modal-conflict", 1)], "{src}");
            assert_eq!(p.diagnostics[0].column, Some(col), "{src}");
        }
    }

    #[test]
    fn mist_and_flood_share_a_block() {
        for src in ["M7 M8", "M8 M7"] {
            assert!(ids(&run(src)).is_empty(), "{src}");
        }
    }

    #[test]
    fn nothing_after_the_end_is_interpreted() {
        let p = run("%\nG0 X1\n%\nG0 X2 #\nnot gcode at all");
        assert_eq!(ids(&p), vec![("after-program-end", 4)]);
        assert!(close(end(&p), DVec3::new(1.0, 0.0, 0.0)));
        assert_eq!(p.end.map(|e| e.line), Some(3));
        let q = run("G0 X1\nM2\nthis is ignored (\n");
        assert_eq!(ids(&q), vec![("after-program-end", 3)]);
    }

    #[test]
    fn offsets_coordinate_systems_and_home() {
        let src = "G10 L2 P2 X100 Y50\nG55 G0 X1 Y1\nG92 X0 Y0\nG0 X1\nG92.1\nG53 G0 X5 Y5\n\
                   G28.1\nG54 G0 X0 Y0\nG28\nG43.1 Z-2\nG0 Z0\nG49 G0 Z0";
        let p = run(src);
        assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
        let to: Vec<DVec3> = p.motions.iter().map(|m| m.to).collect();
        assert!(close(to[0], DVec3::new(101.0, 51.0, 0.0)));
        assert!(close(to[1], DVec3::new(102.0, 51.0, 0.0)));
        assert!(close(to[2], DVec3::new(5.0, 5.0, 0.0)));
        assert!(close(to[3], DVec3::new(0.0, 0.0, 0.0)));
        assert!(close(to[4], DVec3::new(5.0, 5.0, 0.0)));
        assert!(close(to[5], DVec3::new(5.0, 5.0, -2.0)));
        assert!(close(to[6], DVec3::new(5.0, 5.0, 0.0)));
    }

    #[test]
    fn canned_cycles_expand_like_rs274() {
        // rs274 2.9 output for this program (G99 is its start-up mode): see
        // tests/rs274_conformance.rs for the full comparison.
        let p = run("G20 G90 G0 X0 Y0 Z0.3\nG81 X1 R.1 Z-.5 F60\nX2\nG91 X1 R.1 Z-.5 L2\nG80");
        assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
        let feeds: Vec<DVec3> = p
            .motions
            .iter()
            .filter(|m| m.kind == MotionKind::Feed)
            .map(|m| m.to / 25.4)
            .collect();
        let want = [
            DVec3::new(1.0, 0.0, -0.5),
            DVec3::new(2.0, 0.0, -0.5),
            DVec3::new(3.0, 0.0, -0.1),
            DVec3::new(4.0, 0.0, -0.1),
        ];
        assert_eq!(feeds.len(), 4);
        for (a, b) in feeds.iter().zip(want) {
            assert!(close(*a, b), "{a:?} vs {b:?}");
        }
        let q = run("G0 Z5\nG98 G83 X1 Y1 Z-3 R1 Q1.2 F100\nG80");
        let qf: Vec<f64> = q
            .motions
            .iter()
            .filter(|m| m.kind == MotionKind::Feed)
            .map(|m| m.to.z)
            .collect();
        assert_eq!(qf.len(), 4);
        assert!((qf[3] + 3.0).abs() < 1e-12 && (end(&q).z - 5.0).abs() < 1e-12);
    }

    #[test]
    fn messages_events_group_hook_and_probing() {
        let src = "#1 = 2.5\n(debug, depth #1 name #<nope>)\nM8\nM64 P2\n(skinpath:group 3)\n\
                   M3 S100\nG1 X1 F10\n(skinpath:group end)\nG1 X2\nG38.2 Z-5 F10\nG0 X3";
        let p = run(src);
        let info: Vec<&str> = p
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Info)
            .map(|d| d.message.as_str())
            .collect();
        assert_eq!(info, vec!["depth 2.500000 name ######"]);
        let codes: Vec<&str> = p.events.iter().map(|e| e.code.as_str()).collect();
        assert_eq!(codes, vec!["M8", "M64 P2"]);
        assert_eq!(p.motions.to_vec()[0].group, Some(3));
        assert_eq!(p.motions.to_vec()[1].group, None);
        assert_eq!(ids(&p), vec![("cannot-simulate", 10)]);
        assert_eq!(p.uncertain_from, Some(10));
    }

    #[test]
    fn unsupported_codes_say_so_with_code_and_line() {
        let p = run("G1 X1 F10\nG76 X2\nM123\nG1 X2 E5 Q1");
        for d in &p.diagnostics {
            assert!(
                d.message.contains("not supported") || d.id == "unused-word",
                "{d}"
            );
        }
        assert!(p.diagnostics.iter().any(|d| d.message.contains("G76")));
        assert!(p.diagnostics.iter().any(|d| d.message.contains("M123")));
    }

    #[test]
    fn dialects() {
        let grbl = CheckConfig {
            dialect: Dialect::Grbl,
            ..CheckConfig::default()
        };
        let p = run_cfg(
            "$H\n$32=1\n#1=2\nG1 X[1+1] F10\nG81 X1 R1 Z-1\nG1 X1",
            &grbl,
        );
        assert_eq!(p.events.len(), 2);
        let un: Vec<usize> = p
            .diagnostics
            .iter()
            .filter(|d| d.id == "unsupported-code")
            .map(|d| d.lines[0])
            .collect();
        assert_eq!(un, vec![3, 4, 5]);
        let marlin = CheckConfig {
            dialect: Dialect::Marlin,
            ..CheckConfig::default()
        };
        let m = run_cfg("M3 I S100\nG1 X5 E2 F100 S50 ; cut\nG4 P500\nM5", &marlin);
        assert!(ids(&m).is_empty(), "{:?}", m.diagnostics);
        assert_eq!(m.motions.to_vec()[0].tool.s, 50.0);
        assert_eq!(
            m.motions.to_vec()[1].kind,
            MotionKind::Dwell { seconds: 0.5 }
        );
        // `M3 I1` after an arc (a second laser pass) is the inline flag, not a full circle
        // of radius 1; a bare I after an arc still is one.
        let src = "G0 X10 Y10\nM3 I1 S0\nG2 X10 Y10 I2 J0 F600 S50\nM5\nM3 I1 S0\n";
        let m = run_cfg(src, &marlin);
        assert_eq!(m.motions.len(), 2, "{:?}", m.motions.to_vec());
        let m = run_cfg(&format!("{src}I2\n"), &marlin);
        assert_eq!(m.motions.len(), 3);
    }

    #[test]
    fn called_files_from_the_loader() {
        let load = |name: &str| -> Option<String> {
            (name == "lib").then(|| "o<lib> sub\nG0 X#1\no<lib> endsub\n".to_string())
        };
        let p = interpret_with(
            "o<lib> call [4]\no<nope> call\nM2",
            &CheckConfig::default(),
            &Options {
                load_sub: Some(&load),
            },
        );
        assert!(close(end(&p), DVec3::new(4.0, 0.0, 0.0)));
        assert_eq!(ids(&p), vec![("o-word", 2)]);
        assert!(p.diagnostics[0].message.contains("nope.ngc"));
    }
}
