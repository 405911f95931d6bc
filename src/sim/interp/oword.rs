//! O-word control flow: `sub`/`endsub`, `call`/`return`, `if`/`elseif`/`else`, `while`/`do`,
//! `repeat`, `break`/`continue`, and loading called subroutine files.

use super::*;

impl Interp<'_, '_> {
    pub(super) fn find_o(
        &self,
        src: usize,
        label: &str,
        after: usize,
        kinds: &[OKind],
    ) -> Option<OPos> {
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
    pub(super) fn sub_within(&self, src: usize, from: usize, to: usize) -> Option<&str> {
        self.olines
            .iter()
            .filter(|((s, _), _)| *s == src)
            .find(|(_, v)| {
                v.iter()
                    .any(|p| p.kind == OKind::Sub && p.line > from && p.line < to)
            })
            .map(|((_, l), _)| l.as_str())
    }

    pub(super) fn find_o_back(
        &self,
        src: usize,
        label: &str,
        before: usize,
        kind: OKind,
    ) -> Option<OPos> {
        self.olines
            .get(&(src, label.to_string()))?
            .iter()
            .rev()
            .find(|p| p.line < before && p.kind == kind && !p.do_while)
            .copied()
    }

    pub(super) fn count_iteration(&mut self) -> bool {
        self.count_work(1)
    }

    /// Counts `n` units of work against the loop budget (`max_loop_iterations`): loop
    /// iterations, and the repeats of one block (canned-cycle repeats L and pecks, arc
    /// turns P), so that no block creates more moves than the budget allows. False, with a
    /// `loop-limit` error naming the line, once the budget is spent: interpretation stops.
    pub(super) fn count_work(&mut self, n: u64) -> bool {
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

    pub(super) fn oword(&mut self, o: &ngc::OStmt, src: usize, i: usize, jumped: bool) -> Flow {
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
    pub(super) fn load_sub(&mut self, label: &str) -> Result<Option<(usize, usize)>, ()> {
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
}
