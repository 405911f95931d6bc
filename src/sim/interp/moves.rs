//! Motion: targets in the active units, distance mode, plane and offsets; straight moves,
//! arcs (IJK and R forms, helices, chords outside XY), feed checks and range checks.

use super::*;

/// Centre of the arc of signed radius `r` from `p0` to `p1` (RS274 R format: r > 0 takes the
/// arc of at most a half turn, r < 0 the larger one). The centre lies on the chord bisector at
/// h = √(r² − d²/4) (d the chord length), left of p0→p1 for a short CCW arc.
pub(super) fn r_center(p0: DVec2, p1: DVec2, r: f64, ccw: bool, tol: f64) -> Result<DVec2, String> {
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
pub(super) fn arc_between(center: DVec2, p0: DVec2, p1: DVec2, ccw: bool) -> Arc {
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

impl Interp<'_, '_> {
    /// The end point of the block's axis words in machine coordinates.
    pub(super) fn target(&self, b: &Block) -> DVec3 {
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
    pub(super) fn axes(
        &self,
        mut t: DVec3,
        cur: DVec3,
        xyz: [Option<f64>; 3],
        machine: bool,
    ) -> DVec3 {
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
    pub(super) fn plain_block(&mut self, l: &Line) -> bool {
        if !(l.errors.is_empty()
            && l.dollar.is_none()
            && l.oword.is_none()
            && l.comments.is_empty()
            && l.assigns.is_empty())
        {
            return false;
        }
        let mut p = PlainWords::default();
        for w in &l.words {
            let Expr::Num(v) = w.value else {
                return false;
            };
            if !p.add(w.letter, v) {
                return false;
            }
        }
        self.plain_run(&p)
    }

    /// [`Interp::plain_block`] of the line that `text` starts with, read straight from the
    /// text by [`ngc::plain_words`], with no [`Line`] built: the same outcome as parsing it
    /// ([`ngc::parse_line_into`]) and running that, for the lines both take, and the line's
    /// length (up to its `\n`); None, having changed nothing, for the others (comments
    /// among them), which take that route.
    pub(super) fn plain_text(&mut self, text: &[u8]) -> Option<usize> {
        let mut p = PlainWords::default();
        let len = ngc::plain_words(text, self.syn, |letter, v| p.add(letter, v))?;
        self.plain_run(&p).then_some(len)
    }

    /// Runs the plain block `p` (see [`Interp::plain_block`]); false, having changed
    /// nothing, where it is not one in the current state.
    fn plain_run(&mut self, p: &PlainWords) -> bool {
        if self.st.feed_mode != FeedMode::PerMinute || p.words == 0 {
            return false;
        }
        let mode = p.mode.unwrap_or(self.st.mode);
        let kind = match mode {
            Mode::Rapid => MotionKind::Rapid,
            Mode::Linear => MotionKind::Feed,
            _ => return false,
        };
        // A G1 with no axis word and no feed rate: the general route reports LinuxCNC's refusal.
        if p.mode.is_some()
            && kind == MotionKind::Feed
            && p.feed.is_none()
            && self.st.feed <= 0.0
            && p.xyz.iter().all(Option::is_none)
        {
            return false;
        }
        // As exec, collect and execute do it, in their order.
        if self.src == 0 {
            self.prog.last_line = self.line;
        }
        self.prog.words += p.words;
        if let Some(f) = p.feed {
            self.st.feed = f;
            self.st.feed_k = self.st.k();
        }
        if let Some(s) = p.speed {
            let spindle = self.st.tool.spindle;
            self.st.tool.switch(spindle, s);
        }
        self.st.mode = mode;
        if p.xyz.iter().any(Option::is_some) {
            let off = self.st.offset();
            let cur = self.st.pos - off;
            let to = self.axes(cur, cur, p.xyz, false) + off;
            self.straight(kind, to);
        }
        true
    }

    pub(super) fn motion(&self, kind: MotionKind, to: DVec3, arc: Option<Arc>) -> Motion {
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

    pub(super) fn push(&mut self, mut m: Motion) {
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
    pub(super) fn firmware_feed(&self) -> Option<f64> {
        self.cfg.dialect.default_feed()
    }

    /// A feed move `m` while no feed rate is set (no F yet, or F0): LinuxCNC and GRBL refuse
    /// it (an error, one per line); Marlin and Smoothieware run it at their default feed
    /// (a warning, once); the generic dialect warns and leaves the move untimed.
    pub(super) fn no_feed(&mut self, m: &mut Motion) {
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
    pub(super) fn out_of_range(&mut self) {
        self.err(
            "invalid-value",
            None,
            "the move's end point or length is out of range (not a finite number)".into(),
        );
    }

    pub(super) fn straight(&mut self, kind: MotionKind, to: DVec3) {
        if !to.is_finite() {
            return self.out_of_range();
        }
        if to != self.st.pos {
            let m = self.motion(kind, to, None);
            self.push(m);
        }
        self.st.pos = to;
    }

    pub(super) fn move_block(&mut self, mode: Mode, b: &mut Block) {
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
                // P on G2/G3 is the number of turns in LinuxCNC (and the generic dialect);
                // GRBL has no such word and refuses it as unused (error:36).
                b.used_p |= self.cfg.dialect != Dialect::Grbl;
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
    pub(super) fn arc_move(&mut self, ccw: bool, b: &Block) {
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

    pub(super) fn radius_tolerance(&self) -> f64 {
        match self.cfg.dialect {
            Dialect::Generic | Dialect::Linuxcnc => {
                let lc = if self.st.units == Units::Inch {
                    LINUXCNC_RADIUS_TOLERANCE_INCH * Units::Inch.to_mm()
                } else {
                    LINUXCNC_RADIUS_TOLERANCE_MM
                };
                self.cfg.arc_radius_tolerance.max(lc)
            }
            _ => self.cfg.arc_radius_tolerance,
        }
    }
}

/// The words of a plain block ([`Interp::plain_block`]), gathered one by one.
#[derive(Default)]
struct PlainWords {
    /// The motion mode a `G0` or `G1` word sets.
    mode: Option<Mode>,
    xyz: [Option<f64>; 3],
    feed: Option<f64>,
    speed: Option<f64>,
    /// Words read (line numbers too: they count as words).
    words: usize,
}

impl PlainWords {
    /// Takes the word `letter` `v`; false when a plain block cannot hold it (another
    /// letter, a second G, X, Y, Z, F or S, a G other than G0 or G1, F ≤ 0, S < 0, a value
    /// that is not finite).
    fn add(&mut self, letter: char, v: f64) -> bool {
        if !v.is_finite() {
            return false;
        }
        self.words += 1;
        let slot = match letter {
            'G' if self.mode.is_none() => {
                self.mode = match tenths(v) {
                    Some(0) => Some(Mode::Rapid),
                    Some(10) => Some(Mode::Linear),
                    _ => return false,
                };
                return true;
            }
            // Line numbers are counted as words and otherwise ignored (as in `collect`).
            'N' => return true,
            'X' => &mut self.xyz[0],
            'Y' => &mut self.xyz[1],
            'Z' => &mut self.xyz[2],
            // F0 takes the general route (Marlin and Smoothie ignore it).
            'F' if v > 0.0 => &mut self.feed,
            'S' if v >= 0.0 => &mut self.speed,
            _ => return false,
        };
        if slot.is_some() {
            return false;
        }
        *slot = Some(v);
        true
    }
}
