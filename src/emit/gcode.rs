//! G-code for lasers and routers, following a machine [`Profile`].
//!
//! The program: header comments, `G17 G21|G20 G90 G94`, the profile's preamble, the cuts,
//! tool off (`M5`), the postamble and the program end. Modal words (motion G, F, S, unchanged
//! axes) are written only when they change; coordinates are rounded to the profile's
//! decimals and never print as `-0`. Lasers: the beam is off on every rapid, by the
//! controller (GRBL `M4` in laser mode, Smoothie), by `S0` (GRBL `M3`) or by `M5` (Marlin),
//! as the profile says. Routers: every XY rapid happens at safe Z, descents below the
//! clearance height are `G1` plunges at the plunge feed, the spindle starts (with its dwell)
//! before the first descent. Arcs are `G2`/`G3` with `I J`, or with `R` (split into pieces of
//! at most [`R_MAX_SWEEP`]), or flattened to lines within the caller's tolerance.

use super::geometry::{arc_of, split_arc, validate};
use super::{EmitError, Location, check_tolerance};
use crate::geom::Arc;
use crate::machine::{
    ArcFormat, Dialect, GcodeSettings, LaserMode, LaserSettings, MachineKind, Profile, RapidOff,
    RouterSettings, Units, format_number, pow10, push_number, template,
};
pub use crate::sim::checks::intersect::LINE_GROUP;
use crate::toolpath::{Cut, Move, MoveKind, OperationKind, Toolpath};
use glam::{DVec2, DVec3};
use std::cell::RefCell;
use std::rc::Rc;

/// Largest xy length (machine units) of a downward router move that is still a plunge (fed
/// at the plunge feed): round-off of a vertical move.
const PLUNGE_XY: f64 = 1e-12;

/// Smallest share |dᵢ|/‖d‖ of a move along an axis for that axis's maximum feed to limit the
/// move's feed (limit = maxᵢ / share); a smaller share is round-off of a move along the
/// other axes.
const AXIS_SHARE_MIN: f64 = 1e-12;

/// Largest sweep of one `R`-format arc: 120°. The centre recomputed from `R` gets
/// ill-conditioned as the sweep nears 180° (the chord nears the diameter) and `R` cannot
/// express a full circle, so longer arcs are split into equal pieces.
pub const R_MAX_SWEEP: f64 = 2.0 * std::f64::consts::FRAC_PI_3;

/// Options of [`gcode`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct GcodeOptions {
    /// Job name, for the header comment and the `{job}` placeholder.
    pub job: String,
    /// Units of the toolpath's coordinates and feeds (the model is in mm by default).
    pub input_units: Units,
    /// Tolerance in input units: chord error when arcs are flattened, and the largest
    /// start/end radius mismatch accepted on an arc move.
    pub tolerance: f64,
    /// Reject coordinates outside the profile's work area.
    pub check_work_area: bool,
}

impl Default for GcodeOptions {
    fn default() -> Self {
        GcodeOptions {
            job: "skinpath".to_string(),
            input_units: Units::Mm,
            tolerance: crate::geom::tol::FLATTEN,
            check_work_area: true,
        }
    }
}

/// Prefix of the comment that marks the cuts of one pocket: `(skinpath:group N)` before the
/// first cut of pocket N, `(skinpath:group none)` before a cut of no pocket. Moves of one
/// pocket may cross each other (concentric rings meeting a hole); the checker
/// judges every other crossing, and every file without the marks, strictly. Cuts of `line`
/// operations go under `(skinpath:group 0)` (`LINE_GROUP`): lines of a drawing may cross
/// each other, themselves and other cuts. The marks are written whether or not the profile
/// writes comments.
pub const GROUP_MARK: &str = "skinpath:group";

/// Where a line of the program came from: the operation (index in the toolpath) and the
/// cut within it, or none for header, travel between operations and the ending.
pub type LineOrigin = Option<(usize, usize)>;

/// The G-code program for `tp` on the machine `profile`.
pub fn gcode(tp: &Toolpath, profile: &Profile, opts: &GcodeOptions) -> Result<String, EmitError> {
    gcode_with_origins(tp, profile, opts).map(|(text, _)| text)
}

/// [`gcode`], with the origin of every line (index 0 is line 1), so that findings of the
/// checker can be traced back to the operation and cut that made them.
pub fn gcode_with_origins(
    tp: &Toolpath,
    profile: &Profile,
    opts: &GcodeOptions,
) -> Result<(String, Vec<LineOrigin>), EmitError> {
    check_tolerance("tolerance", opts.tolerance)?;
    let wrong = |reason: &str| EmitError::WrongProfile {
        profile: profile.name.clone(),
        output: "G-code",
        reason: reason.to_string(),
    };
    let g = profile
        .gcode
        .as_ref()
        .ok_or_else(|| wrong("it has no [gcode] table"))?;
    let tool = match profile.kind {
        MachineKind::Laser => Tool::Laser(
            profile
                .laser
                .as_ref()
                .ok_or_else(|| wrong("a laser profile needs [laser]"))?,
        ),
        MachineKind::Router => Tool::Router(
            profile
                .router
                .as_ref()
                .ok_or_else(|| wrong("a router profile needs [router]"))?,
        ),
        MachineKind::Svg => return Err(wrong("it is an SVG profile")),
    };
    validate(tp, opts.tolerance)?;
    let scale = opts.input_units.mm_per_unit() / profile.units.mm_per_unit();
    let mut w = Writer {
        p: profile,
        g,
        tool,
        opts,
        scale,
        out: String::new(),
        motion: None,
        printed: [None; 3],
        cur: None,
        feed: None,
        s: None,
        on: false,
        rpm: None,
        at: Location {
            op: 0,
            op_name: String::new(),
            cut: 0,
            mv: None,
        },
        origin: None,
        origins: Vec::new(),
        group: None,
        air: false,
        feed_text: RefCell::new(None),
        power_text: RefCell::new(None),
    };
    w.program(tp)?;
    Ok((w.out, w.origins))
}

#[derive(Clone, Copy)]
enum Tool<'a> {
    Laser(&'a LaserSettings),
    Router(&'a RouterSettings),
}

struct Writer<'a> {
    p: &'a Profile,
    g: &'a GcodeSettings,
    tool: Tool<'a>,
    opts: &'a GcodeOptions,
    /// Input units → machine units.
    scale: f64,
    out: String,
    /// Modal motion G number last written.
    motion: Option<u8>,
    /// Axis values as last written (rounded), for modal omission.
    printed: [Option<f64>; 3],
    /// Exact machine position (unrounded), once known.
    cur: Option<DVec3>,
    feed: Option<String>,
    /// Last `S` word written (string form).
    s: Option<String>,
    /// Laser `M3`/`M4` in force (lasers) or spindle running (routers).
    on: bool,
    rpm: Option<String>,
    at: Location,
    /// Origin of the lines being written, and of every line written so far.
    origin: LineOrigin,
    origins: Vec<LineOrigin>,
    /// Pocket mark in force ([`GROUP_MARK`]).
    group: Option<u32>,
    /// Air assist on.
    air: bool,
    /// The last feed and power formatted, by the bits of the value they were made of: a
    /// program repeats a handful of values on every move.
    feed_text: RefCell<Option<(u64, Rc<str>)>>,
    power_text: RefCell<Option<(u64, Rc<str>)>>,
}

/// `format(v)`, from `memo` when it holds the text of the same value (the same bits);
/// shared, so a move repeating the feed of the last one allocates nothing.
fn memoized(
    memo: &RefCell<Option<(u64, Rc<str>)>>,
    v: f64,
    format: impl Fn() -> String,
) -> Rc<str> {
    let mut m = memo.borrow_mut();
    match &*m {
        Some((bits, text)) if *bits == v.to_bits() => Rc::clone(text),
        _ => {
            let text: Rc<str> = format().into();
            *m = Some((v.to_bits(), Rc::clone(&text)));
            text
        }
    }
}

/// A word written after the axis words of a motion line.
enum Word {
    /// A number with the program's decimals (I, J, R).
    Num(char, f64),
    /// The feed (F), written only when its text changes.
    Feed(Rc<str>),
    /// The inline laser power (S), written only when its text changes.
    Power(Rc<str>),
}

impl Writer<'_> {
    fn dialect(&self) -> Dialect {
        self.p.dialect
    }

    fn line(&mut self, s: &str) {
        self.out.push_str(s);
        self.end_line();
    }

    /// Ends the line written into `out` and records its origin.
    fn end_line(&mut self) {
        self.out.push('\n');
        self.origins.push(self.origin);
    }

    /// A comment written even when the profile turns comments off (marks the checker reads).
    fn mark(&mut self, s: &str) {
        let c = self.dialect().comment(s);
        self.line(&c);
    }

    /// Air assist on or off (lasers), with the profile's codes.
    fn set_air(&mut self, on: bool) {
        if let Tool::Laser(l) = self.tool
            && self.air != on
        {
            let code = if on { &l.air_on } else { &l.air_off };
            let code = code.trim().to_string();
            if !code.is_empty() {
                self.line(&code);
            }
            self.air = on;
        }
    }

    fn comment(&mut self, s: &str) {
        if self.g.comments {
            let c = self.dialect().comment(s);
            self.line(&c);
        }
    }

    fn num(&self, v: f64) -> String {
        format_number(v, self.g.decimals)
    }

    /// Rounded value as the controller will read it.
    fn round(&self, v: f64) -> f64 {
        let f = pow10(self.g.decimals);
        (v * f).round() / f
    }

    fn feed_str(&self, f: f64) -> Rc<str> {
        memoized(&self.feed_text, f, || {
            format_number(f, self.g.decimals.saturating_sub(2))
        })
    }

    fn s_str(&self, power: f64) -> Rc<str> {
        memoized(&self.power_text, power, || {
            let r = self.p.power;
            let mut v = power * r.max;
            if power > 0.0 && v < r.min {
                v = r.min;
            }
            let dec = if r.max >= 100.0 { 0 } else { 3 };
            format_number(v.min(r.max), dec)
        })
    }

    fn render(&self, key: &'static str, t: &str) -> Result<String, EmitError> {
        let safe_z = match self.tool {
            Tool::Router(r) => self.num(r.safe_z),
            Tool::Laser(_) => "0".to_string(),
        };
        template::render(t, |name| match name {
            "name" => self.p.name.clone(),
            "job" => crate::machine::dialect::sanitize_comment(&self.opts.job),
            "units" => self.p.units.gcode().to_string(),
            "safe_z" => safe_z.clone(),
            "path_tolerance" => format_number(self.g.path_tolerance.unwrap_or(0.0), 6),
            "power_max" => format_number(self.p.power.max, 3),
            _ => String::new(),
        })
        .map_err(|reason| EmitError::Template {
            profile: self.p.name.clone(),
            key,
            reason,
        })
    }

    fn template_lines(&mut self, key: &'static str, t: &str) -> Result<(), EmitError> {
        let text = self.render(key, t)?;
        for l in text.lines() {
            let l = l.trim();
            if !l.is_empty() {
                self.line(l);
            }
        }
        Ok(())
    }

    fn program(&mut self, tp: &Toolpath) -> Result<(), EmitError> {
        let job = self.opts.job.clone();
        self.comment(&format!("skinpath job {job}"));
        let desc = format!("machine {} units {:?}", self.p.name, self.p.units);
        self.comment(&desc.to_lowercase());
        let setup = format!("G17 {} G90 G94", self.p.units.gcode());
        self.line(&setup);
        if let Tool::Laser(l) = self.tool
            && self.dialect() == Dialect::Grbl
            && l.rapid_off != RapidOff::M5
        {
            // GRBL fires the beam on G0 unless laser mode is on ($32=1, GRBL wiki "Laser
            // Mode"); the program also writes S0 before every rapid when the profile says
            // `rapid_off = "s0"`, which is safe either way.
            // Written as is: the comment sanitizer would drop the `$`, which GRBL reads as
            // a system command only at the start of a line, never inside a comment.
            self.line("(expects GRBL laser mode: $32=1)");
        }
        let pre = self.g.preamble.clone();
        self.template_lines("gcode.preamble", &pre)?;
        if let Tool::Router(r) = self.tool {
            // Position unknown: go to safe Z before anything else.
            self.rapid_z(r.safe_z)?;
        }
        for (oi, op) in tp.operations.iter().enumerate() {
            self.at.op = oi;
            self.at.op_name = op.name.clone();
            self.comment(&format!("op {oi} {} {:?}", op.name, op.kind).to_lowercase());
            self.set_air(op.air_assist);
            for (ci, cut) in op.cuts.iter().enumerate() {
                self.at.cut = ci;
                self.at.mv = None;
                self.origin = Some((oi, ci));
                // Line cuts go under the lines' mark: they may cross.
                let group = if op.kind == OperationKind::Line {
                    Some(LINE_GROUP)
                } else {
                    cut.group
                };
                if group != self.group {
                    let m = match group {
                        Some(g) => format!("{GROUP_MARK} {g}"),
                        None => format!("{GROUP_MARK} none"),
                    };
                    self.mark(&m);
                    self.group = group;
                }
                self.cut(cut)?;
            }
            self.origin = None;
        }
        self.finish()
    }

    fn finish(&mut self) -> Result<(), EmitError> {
        match self.tool {
            Tool::Router(r) => {
                self.at.mv = None;
                self.rapid_z(r.safe_z)?;
                self.line("M5");
            }
            Tool::Laser(l) => {
                if l.rapid_off == RapidOff::S0 && self.s.as_deref().is_some_and(|s| s != "0") {
                    self.line("S0");
                    self.s = Some("0".into());
                }
                self.line("M5");
            }
        }
        self.on = false;
        self.set_air(false);
        let post = self.g.postamble.clone();
        self.template_lines("gcode.postamble", &post)?;
        if !self.g.program_end.is_empty() {
            let end = self.g.program_end.clone();
            self.line(&end);
        }
        Ok(())
    }

    /// Machine coordinates of an input point, checked against the work area.
    fn machine(&self, p: DVec3) -> Result<DVec3, EmitError> {
        let q = p * self.scale;
        self.check(q)?;
        Ok(q)
    }

    fn check(&self, q: DVec3) -> Result<(), EmitError> {
        if !self.opts.check_work_area {
            return Ok(());
        }
        let slack = 0.5 * 10f64.powi(-(self.g.decimals as i32));
        let wa = self.p.work_area;
        let laser = matches!(self.tool, Tool::Laser(_));
        for (axis, v, r) in [('X', q.x, wa.x), ('Y', q.y, wa.y), ('Z', q.z, wa.z)] {
            // A laser that never leaves z = 0 writes no Z at all.
            if laser && axis == 'Z' && q.z == 0.0 {
                continue;
            }
            if !r.contains(v, slack) {
                return Err(EmitError::OutOfWorkArea {
                    at: self.at.clone(),
                    axis,
                    value: v,
                    min: r.min(),
                    max: r.max(),
                    profile: self.p.name.clone(),
                });
            }
        }
        Ok(())
    }

    fn cut(&mut self, cut: &Cut) -> Result<(), EmitError> {
        if let Some(src) = &cut.source {
            self.comment(&format!("cut {} {src}", self.at.cut));
        }
        let start = self.machine(cut.start)?;
        let first_power = cut
            .moves
            .iter()
            .find(|m| matches!(m.kind, MoveKind::Line | MoveKind::Arc { .. }))
            .map(|m| m.power);
        self.travel(start, first_power)?;
        let mut pos = start;
        for (mi, m) in cut.moves.iter().enumerate() {
            self.at.mv = Some(mi);
            match m.kind {
                MoveKind::Rapid => {
                    let to = self.machine(m.to)?;
                    let next = cut.moves[mi + 1..]
                        .iter()
                        .take_while(|n| !matches!(n.kind, MoveKind::Rapid))
                        .find(|n| matches!(n.kind, MoveKind::Line | MoveKind::Arc { .. }))
                        .map(|n| n.power);
                    self.travel(to, next)?;
                    pos = to;
                }
                MoveKind::Dwell { seconds } => {
                    let d = self.dialect().dwell(seconds);
                    self.line(&d);
                }
                MoveKind::Line => {
                    let to = self.machine(m.to)?;
                    self.tool_on(m)?;
                    let mut feed = m.feed * self.scale;
                    if let Tool::Router(r) = self.tool {
                        let d = to - pos;
                        if d.z < 0.0 && d.truncate().length() <= PLUNGE_XY {
                            feed = feed.min(r.plunge_feed);
                        }
                    }
                    self.cutting_line(pos, to, feed, m.power);
                    pos = to;
                }
                MoveKind::Arc { center, ccw } => {
                    let to = self.machine(m.to)?;
                    let c = center * self.scale;
                    // The arc's own extremes must be inside the work area, not just its ends.
                    let a = arc_of(pos.truncate(), to.truncate(), c, ccw);
                    for q in a.extrema() {
                        self.check(q.extend(to.z))?;
                    }
                    self.tool_on(m)?;
                    self.arc(pos, to, &a, m.feed * self.scale, m.power)?;
                    pos = to;
                }
            }
        }
        Ok(())
    }

    /// Moves to `to` with the tool safe: laser off on the rapid, router at safe Z; a router
    /// then starts its spindle at `power` and descends (G0 to clearance, G1 plunge below).
    fn travel(&mut self, to: DVec3, power: Option<f64>) -> Result<(), EmitError> {
        match self.tool {
            Tool::Laser(l) => {
                if self.stays_in_xy(to) && matches!(l.rapid_off, RapidOff::Firmware) {
                    // No G0 is written for a travel that stays in place, so the firmware
                    // would not switch the beam off: S0 does (a pass ends here).
                    self.beam_off_s0();
                } else {
                    self.beam_off_for_rapid(l);
                }
                self.rapid(to, true);
            }
            Tool::Router(r) => {
                if !self.stays_in_xy(to) {
                    self.rapid_z(r.safe_z)?;
                    self.rapid(DVec3::new(to.x, to.y, r.safe_z), false);
                }
                if let Some(p) = power {
                    self.spindle(p)?;
                }
                let cz = self.cur.map_or(r.safe_z, |c| c.z);
                if to.z >= r.clearance_z || to.z >= cz {
                    if self.round(to.z) != self.round(cz) {
                        self.rapid(to, false);
                    }
                } else {
                    if cz > r.clearance_z {
                        let c = DVec3::new(to.x, to.y, r.clearance_z);
                        self.rapid(c, false);
                    }
                    if self.on {
                        let feed = self.feed_str(r.plunge_feed);
                        self.move_line(1, to, [Word::Feed(feed)]);
                    } else {
                        return Err(EmitError::InvalidMove {
                            at: self.at.clone(),
                            reason: "descent below the clearance height with no cutting \
                                     move to set the spindle speed"
                                .to_string(),
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// Whether a move to `to` writes the current x and y again (after rounding): no G0 is
    /// written for it. False before the first move.
    fn stays_in_xy(&self, to: DVec3) -> bool {
        self.cur.is_some_and(|c| {
            self.round(c.x) == self.round(to.x) && self.round(c.y) == self.round(to.y)
        })
    }

    fn beam_off_for_rapid(&mut self, l: &LaserSettings) {
        match l.rapid_off {
            RapidOff::Firmware => {}
            RapidOff::S0 => self.beam_off_s0(),
            RapidOff::M5 => {
                if self.on {
                    self.line("M5");
                    self.on = false;
                    // Power after the next M3/M4 is not ours to assume: write S again.
                    self.s = None;
                }
            }
        }
    }

    /// Switches the beam off by power: S0, when the power written last was not 0.
    fn beam_off_s0(&mut self) {
        if self.s.as_deref().is_some_and(|s| s != "0") {
            self.line("S0");
            self.s = Some("0".into());
        }
    }

    fn rapid_z(&mut self, z: f64) -> Result<(), EmitError> {
        let here = self.cur.unwrap_or(DVec3::new(0.0, 0.0, f64::NAN));
        if self.printed[2] == Some(self.round(z)) {
            return Ok(());
        }
        let to = DVec3::new(here.x, here.y, z);
        self.check(DVec3::new(
            self.p.work_area.x.min(),
            self.p.work_area.y.min(),
            z,
        ))?;
        self.move_words(0, [None, None, Some(z)], []);
        self.cur = self.cur.map(|_| to);
        self.printed[2] = Some(self.round(z));
        Ok(())
    }

    /// A G0 to `to` (Z written only when it changes; lasers at z = 0 never write Z).
    fn rapid(&mut self, to: DVec3, laser: bool) {
        let z = if laser && to.z == 0.0 && self.printed[2].is_none() {
            None
        } else {
            Some(to.z)
        };
        self.move_words(0, [Some(to.x), Some(to.y), z], []);
        self.cur = Some(to);
    }

    fn move_line(&mut self, g: u8, to: DVec3, extra: impl IntoIterator<Item = Word>) {
        let laser = matches!(self.tool, Tool::Laser(_));
        let z = if laser && to.z == 0.0 && self.printed[2].is_none() {
            None
        } else {
            Some(to.z)
        };
        self.move_words(g, [Some(to.x), Some(to.y), z], extra);
        self.cur = Some(to);
    }

    /// Writes a motion line with the axis words that changed and `extra` words; returns
    /// false (writing nothing) when no axis changes and `g` is not an arc.
    fn move_words(
        &mut self,
        g: u8,
        axes: [Option<f64>; 3],
        extra: impl IntoIterator<Item = Word>,
    ) -> bool {
        let mut print = [None; 3];
        let mut moved = false;
        for (i, v) in axes.into_iter().enumerate() {
            if let Some(v) = v {
                let r = self.round(v);
                if self.printed[i] != Some(r) || (g >= 2 && i < 2) {
                    print[i] = Some(v);
                    moved |= self.printed[i] != Some(r) || g >= 2;
                    self.printed[i] = Some(r);
                }
            }
        }
        if !moved {
            return false;
        }
        // Written straight into the program: the motion word when it changes (or the
        // dialect is not modal), the axis words, then the extra words that changed.
        let start = self.out.len();
        if self.motion != Some(g) || !self.dialect().modal_motion() {
            self.out.push('G');
            self.out.push_str(itoa::Buffer::new().format(g));
            self.motion = Some(g);
        }
        for (letter, v) in ['X', 'Y', 'Z'].into_iter().zip(print) {
            if let Some(v) = v {
                if self.out.len() > start {
                    self.out.push(' ');
                }
                self.out.push(letter);
                push_number(&mut self.out, v, self.g.decimals);
            }
        }
        for word in extra {
            let (letter, text) = match word {
                Word::Num(letter, v) => {
                    self.out.push(' ');
                    self.out.push(letter);
                    push_number(&mut self.out, v, self.g.decimals);
                    continue;
                }
                Word::Feed(v) => {
                    if self.feed.as_deref() == Some(&*v) {
                        continue;
                    }
                    self.feed = Some(v.to_string());
                    ('F', v)
                }
                Word::Power(v) => {
                    if self.s.as_deref() == Some(&*v) {
                        continue;
                    }
                    self.s = Some(v.to_string());
                    ('S', v)
                }
            };
            self.out.push(' ');
            self.out.push(letter);
            self.out.push_str(&text);
        }
        self.end_line();
        true
    }

    /// Turns the laser on (or sets its power when power is not inline), or checks the
    /// spindle speed, before the cutting move `m`.
    fn tool_on(&mut self, m: &Move) -> Result<(), EmitError> {
        match self.tool {
            Tool::Laser(l) => {
                let s = self.s_str(m.power);
                let word = match l.mode {
                    LaserMode::Dynamic => "M4",
                    LaserMode::Constant => "M3",
                };
                let suffix = || {
                    if l.on_suffix.is_empty() {
                        String::new()
                    } else {
                        format!(" {}", l.on_suffix)
                    }
                };
                if l.inline_power {
                    if l.needs_on_command && !self.on {
                        let zero = if self.s.is_none() { " S0" } else { "" };
                        self.line(&format!("{word}{}{zero}", suffix()));
                        if !zero.is_empty() {
                            self.s = Some("0".into());
                        }
                        self.on = true;
                        self.pierce(l);
                    }
                } else if !self.on || self.s.as_deref() != Some(&*s) {
                    self.line(&format!("{word}{} S{s}", suffix()));
                    self.s = Some(s.to_string());
                    if !self.on {
                        self.on = true;
                        self.pierce(l);
                    }
                }
            }
            Tool::Router(_) => self.spindle(m.power)?,
        }
        Ok(())
    }

    fn pierce(&mut self, l: &LaserSettings) {
        if l.pierce_dwell > 0.0 {
            let d = self.dialect().dwell(l.pierce_dwell);
            self.line(&d);
        }
    }

    /// Spindle on at `power` (M3 S rpm), with the spin-up dwell when it was off or speeds up.
    fn spindle(&mut self, power: f64) -> Result<(), EmitError> {
        let Tool::Router(r) = self.tool else {
            return Ok(());
        };
        if power <= 0.0 {
            return Err(EmitError::InvalidMove {
                at: self.at.clone(),
                reason: "a router cutting move needs a spindle speed (power > 0)".to_string(),
            });
        }
        let s = self.s_str(power);
        if self.on && self.rpm.as_deref() == Some(&*s) {
            return Ok(());
        }
        let faster = match (&self.rpm, self.on) {
            (Some(old), true) => s.parse::<f64>().ok() > old.parse::<f64>().ok(),
            _ => true,
        };
        self.line(&format!("M3 S{s}"));
        self.rpm = Some(s.to_string());
        self.s = Some(s.to_string());
        self.on = true;
        if faster && r.spindle_dwell > 0.0 {
            let d = self.dialect().dwell(r.spindle_dwell);
            self.line(&d);
        }
        Ok(())
    }

    /// The largest feed along direction `d` that keeps every axis within its maximum.
    fn clamp_feed(&self, d: DVec3, feed: f64) -> f64 {
        let m = self.p.max_feed;
        let len = d.length();
        if len <= 0.0 {
            return feed;
        }
        let mut limit = feed;
        for (c, max) in [(d.x, m.x), (d.y, m.y), (d.z, m.z)] {
            let share = c.abs() / len;
            if share > AXIS_SHARE_MIN && max > 0.0 {
                limit = limit.min(max / share);
            }
        }
        limit
    }

    /// The feed word and, for lasers with inline power, the power word of a cutting move.
    fn power_words(&self, power: f64, feed: f64) -> impl Iterator<Item = Word> + use<> {
        let inline = matches!(self.tool, Tool::Laser(l) if l.inline_power);
        let power = inline.then(|| Word::Power(self.s_str(power)));
        std::iter::once(Word::Feed(self.feed_str(feed))).chain(power)
    }

    fn cutting_line(&mut self, from: DVec3, to: DVec3, feed: f64, power: f64) {
        let feed = self.clamp_feed(to - from, feed);
        let extra = self.power_words(power, feed);
        self.move_line(1, to, extra);
    }

    /// The arc move from `from` to `to`; `a` is its swept arc in the plane
    /// ([`arc_of`]), whose centre and sweep the formats use.
    fn arc(
        &mut self,
        from: DVec3,
        to: DVec3,
        a: &Arc,
        feed: f64,
        power: f64,
    ) -> Result<(), EmitError> {
        let (center, ccw) = (a.center, a.sweep > 0.0);
        // The direction turns along an arc: the slower of X and Y bounds it.
        let feed = feed.min(self.p.max_feed.x.min(self.p.max_feed.y));
        let g = if ccw { 3 } else { 2 };
        // A tiny arc whose ends round to one point would read as a full circle: write a line.
        let same_printed =
            self.round(from.x) == self.round(to.x) && self.round(from.y) == self.round(to.y);
        if same_printed && a.sweep.abs() < std::f64::consts::PI {
            self.cutting_line(from, to, feed, power);
            return Ok(());
        }
        match self.g.arcs {
            ArcFormat::Ij => {
                let (sx, sy) = self.start_printed(from);
                let ij = [Word::Num('I', center.x - sx), Word::Num('J', center.y - sy)];
                let extra = self.power_words(power, feed);
                self.move_line(g, to, ij.into_iter().chain(extra));
            }
            ArcFormat::R => {
                let pts = split_arc(from.truncate(), to.truncate(), center, a.sweep, R_MAX_SWEEP);
                let n = pts.len() as f64;
                let mut prev = from;
                for (i, p) in pts.iter().enumerate() {
                    let z = from.z + (to.z - from.z) * (i as f64 + 1.0) / n;
                    let end = DVec3::new(p.x, p.y, z);
                    self.check(end)?;
                    let (sx, sy) = self.start_printed(prev);
                    let r = center.distance(DVec2::new(sx, sy));
                    let words = self.power_words(power, feed);
                    if self.round(prev.x) == self.round(end.x)
                        && self.round(prev.y) == self.round(end.y)
                    {
                        self.move_line(1, end, words);
                    } else {
                        self.move_line(g, end, std::iter::once(Word::Num('R', r)).chain(words));
                    }
                    prev = end;
                }
            }
            ArcFormat::None => {
                let tol = self.opts.tolerance * self.scale;
                let pts = a.flatten(tol);
                let n = (pts.len() - 1).max(1) as f64;
                let mut prev = from;
                for (i, p) in pts.iter().enumerate().skip(1) {
                    let z = from.z + (to.z - from.z) * i as f64 / n;
                    let end = if i + 1 == pts.len() {
                        to
                    } else {
                        DVec3::new(p.x, p.y, z)
                    };
                    self.check(end)?;
                    self.cutting_line(prev, end, feed, power);
                    prev = end;
                }
            }
        }
        Ok(())
    }

    /// The start point as the controller knows it (last written, rounded).
    fn start_printed(&self, from: DVec3) -> (f64, f64) {
        (
            self.printed[0].unwrap_or(self.round(from.x)),
            self.printed[1].unwrap_or(self.round(from.y)),
        )
    }
}

#[cfg(test)]
mod tests;
