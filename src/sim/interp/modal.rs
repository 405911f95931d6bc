//! Modal groups: a line's words sorted into a [`Block`] (one code per modal group, one
//! value per letter), G- and M-code dispatch, and words no code used.

use super::*;

// Modal groups (LinuxCNC manual, "Modal groups").
pub(super) const G_NONMODAL: usize = 0;
pub(super) const G_MOTION: usize = 1;
pub(super) const G_PLANE: usize = 2;
pub(super) const G_DISTANCE: usize = 3;
pub(super) const G_ARC_DISTANCE: usize = 4;
pub(super) const G_FEED_MODE: usize = 5;
pub(super) const G_UNITS: usize = 6;
pub(super) const G_COMP: usize = 7;
pub(super) const G_TLO: usize = 8;
pub(super) const G_RETURN: usize = 9;
pub(super) const G_COORD: usize = 10;
pub(super) const G_PATH: usize = 11;
pub(super) const G_SPINDLE: usize = 12;
pub(super) const G_LATHE: usize = 13;
pub(super) const M_STOP: usize = 14;
pub(super) const M_TOOL: usize = 15;
pub(super) const M_SPINDLE: usize = 16;
pub(super) const M_COOLANT: usize = 17;
pub(super) const M_COOLANT2: usize = 18;
pub(super) const M_OVERRIDE: usize = 19;
pub(super) const M_IO: usize = 20;
pub(super) const M_STATE: usize = 21;
pub(super) const M_USER: usize = 22;
pub(super) const GROUPS: usize = 23;

pub(super) const LETTERS: [char; 24] = [
    'X', 'Y', 'Z', 'I', 'J', 'K', 'R', 'F', 'S', 'P', 'Q', 'L', 'T', 'H', 'D', 'A', 'B', 'C', 'U',
    'V', 'W', '@', '^', 'E',
];

/// Index of each ASCII character in [`LETTERS`] (`u8::MAX`: none).
pub(super) const LETTER_INDEX: [u8; 128] = {
    let mut t = [u8::MAX; 128];
    let mut i = 0;
    while i < LETTERS.len() {
        t[LETTERS[i] as usize] = i as u8;
        i += 1;
    }
    t
};

/// The position of `c` in [`LETTERS`].
pub(super) fn letter_index(c: char) -> Option<usize> {
    let i = *LETTER_INDEX.get(c as usize)?;
    (i != u8::MAX).then_some(usize::from(i))
}

/// A stored group code: −1 is none.
pub(super) fn group_code(stored: i32) -> Option<i64> {
    (stored >= 0).then_some(i64::from(stored))
}

/// The words of one block sorted into what the interpreter needs.
#[derive(Clone)]
pub(super) struct Block {
    /// Code per modal group (as [`tenths`] gives it), −1 for none: codes are below 10⁹.
    pub(super) groups: [i32; GROUPS],
    pub(super) vals: [Option<f64>; 24],
    pub(super) cols: [usize; 24],
    pub(super) machine_coords: bool,
    pub(super) axes_used: bool,
    pub(super) used_arc: bool,
    pub(super) used_i: bool,
    pub(super) used_r: bool,
    pub(super) used_p: bool,
    pub(super) used_q: bool,
    pub(super) used_l: bool,
    pub(super) used_h: bool,
    pub(super) used_d: bool,
    pub(super) used_all: bool,
}

impl Block {
    pub(super) fn new() -> Self {
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
    pub(super) fn group(&self, g: usize) -> Option<i64> {
        group_code(self.groups[g])
    }

    /// Records `code` (a [`tenths`] value, 0..10⁹) for modal group `g`.
    pub(super) fn set_group(&mut self, g: usize, code: i64) {
        self.groups[g] = i32::try_from(code).unwrap_or(i32::MAX);
    }

    pub(super) fn val(&self, c: char) -> Option<f64> {
        letter_index(c).and_then(|i| self.vals[i])
    }

    pub(super) fn col(&self, c: char) -> usize {
        letter_index(c).map_or(1, |i| self.cols[i])
    }

    pub(super) fn has_axis(&self) -> bool {
        ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W', '@', '^']
            .into_iter()
            .any(|c| self.val(c).is_some())
    }
}

/// The code as an integer number of tenths (G90.1 → 901), None if not a tenth (or
/// negative, or 10⁹ tenths or more). The tenths are rounded half away from zero, as
/// `f64::round` does, but by truncation (exact below 2⁵³): `f64::round` is a libm call on
/// the x86-64 baseline, and this runs for every G and M word.
pub(super) fn tenths(v: f64) -> Option<i64> {
    let x = v * 10.0;
    // round(x) lies in [0, 10⁹) exactly when x lies in (−0.5, 10⁹ − 0.5).
    if !(x > -0.5 && x < TENTHS_LIMIT - 0.5) {
        return None;
    }
    let r = x as i64;
    let t = if x - r as f64 >= 0.5 { r + 1 } else { r };
    ((x - t as f64).abs() < TENTHS_SLACK).then_some(t)
}

/// Codes are below this many tenths (10⁹), so that a [`Block`] stores them in an `i32`.
const TENTHS_LIMIT: f64 = 1e9;

/// A code is a whole number of tenths when ten times its value is within this of an integer:
/// far above the rounding of a decimal code read as `f64` (`G90.1` · 10 is off by an ulp),
/// far below the next tenth.
const TENTHS_SLACK: f64 = 1e-6;

pub(super) fn fmt_code(tenths: i64) -> String {
    if tenths % 10 == 0 {
        (tenths / 10).to_string()
    } else {
        format!("{}.{}", tenths / 10, (tenths % 10).abs())
    }
}

impl Interp<'_, '_> {
    pub(super) fn exec(&mut self, l: &Line, src: usize, i: usize, jumped: bool) -> Flow {
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
    pub(super) fn exec_words(&mut self, words: &[(char, f64, usize)]) -> Flow {
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

    /// Sorts the words into `b`; false when the block cannot run.
    pub(super) fn collect(&mut self, b: &mut Block, words: &[(char, f64, usize)]) -> bool {
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

    pub(super) fn modal(
        &mut self,
        b: &mut Block,
        group: usize,
        code: i64,
        col: usize,
        prefix: char,
    ) -> bool {
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

    pub(super) fn g_code(&mut self, b: &mut Block, v: f64, col: usize) -> bool {
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

    pub(super) fn m_code(&mut self, b: &mut Block, v: f64, col: usize) -> bool {
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

    pub(super) fn unused_words(&mut self, b: &Block) {
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
}
