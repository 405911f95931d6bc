//! Parameters and expressions: numbered, named and predefined parameters, assignments after
//! the block is read, and parameter substitution in messages (`(debug,…)`, `(print,…)`).

use super::*;

/// Parameter access for expressions.
pub(super) struct View<'v, 'a, 'o> {
    pub(super) it: &'v Interp<'a, 'o>,
}

/// Named parameters LinuxCNC predefines (read-only).
pub(super) fn predefined(name: &str) -> bool {
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

impl<'a> Interp<'a, '_> {
    pub(super) fn view(&self) -> View<'_, 'a, '_> {
        View { it: self }
    }

    pub(super) fn eval(&mut self, e: &Expr, col: usize) -> Option<f64> {
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

    pub(super) fn set_param(&mut self, p: &ParamRef, v: f64, col: usize) {
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

    pub(super) fn comments(&mut self, l: &Line) {
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
    pub(super) fn substitute(&self, text: &str) -> String {
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
}
