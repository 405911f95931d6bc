//! Executing one block in the RS274NGC order of execution (LinuxCNC manual, "G-code
//! overview: Order of execution"), and the motion LinuxCNC refuses.

use super::*;

impl Interp<'_, '_> {
    /// Runs the block; true at a program end (M2/M30).
    pub(super) fn execute(&mut self, mut b: Block) -> bool {
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
    pub(super) fn linuxcnc_refuses_motion(&mut self, b: &Block, motion: Option<i64>) -> bool {
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
}
