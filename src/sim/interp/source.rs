//! Reading the program: sources (the main text, called files, a stream read line by line
//! with seek checkpoints), the pre-scan of O-word lines, and the loop that runs line by line.

use super::*;

pub(super) struct Source<'a> {
    pub(super) name: String,
    pub(super) body: Body<'a>,
}

pub(super) enum Body<'a> {
    /// The whole text, read line by line in memory.
    Mem(MemText<'a>),
    /// A program read line by line from a seekable stream ([`interpret_stream`]).
    Stream(Box<LineStream<'a>>),
}

/// An in-memory text read by line index. Line `i` is the `i`th piece of
/// `text.split('\n')` without a trailing `\r` ([`line_end`], [`cut`]). Reading in order
/// walks the text from the last line read; a read out of order (a jump back, a forward
/// jump past unread lines) goes through the [`LineStarts`], built at the first such read,
/// so a program read straight through never builds them (4 bytes a line) nor makes a pass
/// of its own: the plain route's scan finds the end of the lines it takes
/// ([`ngc::plain_words`] stops at the `\n`; [`MemText::record_read`]), [`line_end`] that
/// of the others.
pub(super) struct MemText<'a> {
    pub(super) text: Cow<'a, str>,
    /// The line read last: (index, first byte, end: the byte offset of its `\n` or the
    /// text's length).
    last: Option<(usize, usize, usize)>,
    starts: Option<LineStarts>,
}

/// The byte offset of each line start of an in-memory text: 4 bytes a line for texts
/// below 4 GiB (a million-line program keeps 4 MB, not 8), 8 beyond.
pub(super) enum LineStarts {
    /// Offsets that fit in 32 bits.
    Narrow(Vec<u32>),
    /// Offsets of a text of 4 GiB or more.
    Wide(Vec<usize>),
}

impl LineStarts {
    /// The line starts of `text` (the first at 0, then after each `\n`).
    pub(super) fn of(text: &[u8]) -> Self {
        if u32::try_from(text.len()).is_ok() {
            let mut v = vec![0u32];
            // Every offset is at most text.len(), which fits.
            v.extend(memchr_lines(text).map(|i| i as u32));
            LineStarts::Narrow(v)
        } else {
            let mut v = vec![0usize];
            v.extend(memchr_lines(text));
            LineStarts::Wide(v)
        }
    }

    /// Number of lines.
    pub(super) fn len(&self) -> usize {
        match self {
            LineStarts::Narrow(v) => v.len(),
            LineStarts::Wide(v) => v.len(),
        }
    }

    /// Start of line `i`.
    pub(super) fn get(&self, i: usize) -> Option<usize> {
        match self {
            LineStarts::Narrow(v) => v.get(i).map(|&s| s as usize),
            LineStarts::Wide(v) => v.get(i).copied(),
        }
    }
}

/// The end of the line of `text` that starts at byte `start`: the offset of the next `\n`,
/// or the text's length when none follows (the last line).
pub(super) fn line_end(text: &[u8], start: usize) -> usize {
    text.get(start..)
        .and_then(|rest| memchr::memchr(b'\n', rest))
        .map_or(text.len(), |k| start + k)
}

/// The line of `text` from byte `start` to its end `end` ([`line_end`]), without a
/// trailing `\r`.
pub(super) fn cut(text: &str, start: usize, end: usize) -> &str {
    let l = text.get(start..end).unwrap_or_default();
    l.strip_suffix('\r').unwrap_or(l)
}

impl<'a> MemText<'a> {
    pub(super) fn new(text: Cow<'a, str>) -> Self {
        MemText {
            text,
            last: None,
            starts: None,
        }
    }

    /// The first byte of line `i`, None past the last line: the last line read or the one
    /// after it from the cursor, any other through the line starts.
    #[inline]
    fn start_of(&mut self, i: usize) -> Option<usize> {
        match self.last {
            None if i == 0 => return Some(0),
            Some((l, s, _)) if l == i => return Some(s),
            // The line after one that ends at a `\n` starts after it.
            Some((l, _, e)) if l.checked_add(1) == Some(i) => {
                return (e < self.text.len()).then_some(e + 1);
            }
            _ => {}
        }
        self.starts
            .get_or_insert_with(|| LineStarts::of(self.text.as_bytes()))
            .get(i)
    }

    /// Line `i` (see [`MemText`]), None past the last line.
    pub(super) fn line(&mut self, i: usize) -> Option<&str> {
        let (s, e) = match self.last {
            Some((l, s, e)) if l == i => (s, e),
            _ => {
                let s = self.start_of(i)?;
                let e = line_end(self.text.as_bytes(), s);
                self.last = Some((i, s, e));
                (s, e)
            }
        };
        Some(cut(&self.text, s, e))
    }

    /// The first byte of line `i` and the text from there on, when the text is borrowed
    /// for `'a` (the program of [`interpret_with`]): where [`Interp::plain_text`] reads the
    /// line from, and finds its end, without borrowing the source. None past the last line
    /// and for an owned text.
    #[inline]
    pub(super) fn text_from_line(&mut self, i: usize) -> Option<(usize, &'a [u8])> {
        let text: &'a str = match &self.text {
            Cow::Borrowed(t) => t,
            Cow::Owned(_) => return None,
        };
        let s = self.start_of(i)?;
        Some((s, text.as_bytes().get(s..)?))
    }

    /// Line `i` holds a comment (a `(` or `;`), found by one search that stops at the
    /// line's end or the comment. A line with one is recorded as read (its end searched
    /// from the comment on), so that [`MemText::line`] gives it without searching again.
    pub(super) fn has_comment(&mut self, i: usize) -> bool {
        let Some(s) = self.start_of(i) else {
            return false;
        };
        let b = self.text.as_bytes();
        let Some(k) = b
            .get(s..)
            .and_then(|rest| memchr::memchr3(b'\n', b'(', b';', rest))
            .map(|k| s + k)
            .filter(|&k| b[k] != b'\n')
        else {
            return false;
        };
        self.last = Some((i, s, line_end(b, k)));
        true
    }

    /// Records line `i`, read from its first byte `start` ([`MemText::text_from_line`]), as
    /// `len` bytes long (up to its `\n`): the last line read.
    #[inline]
    pub(super) fn record_read(&mut self, i: usize, start: usize, len: usize) {
        self.last = Some((i, start, start + len));
    }
}

impl<'a> Source<'a> {
    pub(super) fn new(name: String, text: Cow<'a, str>) -> Self {
        Source {
            name,
            body: Body::Mem(MemText::new(text)),
        }
    }

    /// Number of lines (one more than the number of `\n`).
    pub(super) fn len(&self) -> usize {
        match &self.body {
            Body::Mem(m) => m.starts.as_ref().map_or_else(
                || memchr::memchr_iter(b'\n', m.text.as_bytes()).count() + 1,
                LineStarts::len,
            ),
            Body::Stream(s) => s.len,
        }
    }

    /// Line `i` exists.
    #[inline]
    pub(super) fn has_line(&mut self, i: usize) -> bool {
        match &mut self.body {
            Body::Mem(m) => m.start_of(i).is_some(),
            Body::Stream(s) => i < s.len,
        }
    }

    /// [`MemText::text_from_line`] of an in-memory source; None for a stream.
    #[inline]
    pub(super) fn text_from_line(&mut self, i: usize) -> Option<(usize, &'a [u8])> {
        match &mut self.body {
            Body::Mem(m) => m.text_from_line(i),
            Body::Stream(_) => None,
        }
    }

    /// [`MemText::has_comment`] of an in-memory source; false for a stream.
    pub(super) fn has_comment(&mut self, i: usize) -> bool {
        match &mut self.body {
            Body::Mem(m) => m.has_comment(i),
            Body::Stream(_) => false,
        }
    }

    /// [`MemText::record_read`] of an in-memory source.
    #[inline]
    pub(super) fn record_read(&mut self, i: usize, start: usize, len: usize) {
        if let Body::Mem(m) = &mut self.body {
            m.record_read(i, start, len);
        }
    }

    /// Line `i`, without its `\n` and a trailing `\r`; None past the last line.
    pub(super) fn line(&mut self, i: usize) -> Option<&str> {
        match &mut self.body {
            Body::Mem(m) => m.line(i),
            Body::Stream(s) if i < s.len => Some(s.line(i)),
            Body::Stream(_) => None,
        }
    }
}

/// Where [`interpret_each`] and [`interpret_stream`] hand the moves instead of keeping them:
/// `take` gets the moves produced since it was last called, before a line is read once
/// there are at least `chunk` of them, and after the last line. Moves `take` leaves in the
/// list are dropped.
pub struct MotionSink<'s> {
    /// Takes the moves out of the list (swapping in an empty one, or reading them).
    pub take: &'s mut dyn FnMut(&mut crate::sim::motion::Motions),
    /// Moves gathered before `take` is called (1: after every line that moved).
    pub chunk: usize,
}

/// Both [`std::io::Read`] and [`std::io::Seek`].
pub trait ReadSeek: std::io::Read + std::io::Seek {}
impl<T: std::io::Read + std::io::Seek> ReadSeek for T {}

/// Lines of a program read on demand: forward reading is sequential; a jump back (loops,
/// subroutine returns) seeks to the nearest recorded line start before the target (every
/// O-word line, its successor, and every [`CHECKPOINT_EVERY`]th line) and reads on from there.
pub(super) struct LineStream<'a> {
    pub(super) reader: std::io::BufReader<Box<dyn ReadSeek + 'a>>,
    /// (line index, byte offset of its start), sorted by line.
    pub(super) checkpoints: Vec<(usize, u64)>,
    /// Number of lines (as [`Source::new`] counts them).
    pub(super) len: usize,
    /// Index of the line in `buf` (`usize::MAX`: none yet).
    pub(super) cur: usize,
    pub(super) buf: String,
    pub(super) raw: Vec<u8>,
    /// The first read error, if any.
    pub(super) error: Option<String>,
}

/// Distance in lines between the recorded line starts of a [`LineStream`].
pub(super) const CHECKPOINT_EVERY: usize = 4096;

impl LineStream<'_> {
    pub(super) fn read_next(&mut self) {
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

    pub(super) fn line(&mut self, i: usize) -> &str {
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
    pub(super) checkpoints: Vec<(usize, u64)>,
    /// Lines with an O-word: (line index, statement).
    pub(super) owords: Vec<(usize, ngc::OStmt)>,
}

/// Reads `input` once: line count, blank/NUL/UTF-8 facts, O-word lines (parsed with the
/// dialect's syntax) and seek points.
pub(super) fn scan(input: &mut dyn ReadSeek, syn: Syntax) -> std::io::Result<Scan> {
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

pub(super) fn memchr_lines(b: &[u8]) -> impl Iterator<Item = usize> + '_ {
    memchr::memchr_iter(b'\n', b).map(|i| i + 1)
}

/// The lines of `text` holding an `o` or `O` (the only ones that can hold an O-word), in
/// order, each once: (index, line as [`MemText`] gives it). Found without line starts: the
/// `\n`s before each are counted.
pub(super) fn lines_with_o(text: &str) -> Vec<(usize, &str)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    // `start` is the first byte of line `line`.
    let (mut line, mut start) = (0usize, 0usize);
    while let Some(k) = b
        .get(start..)
        .and_then(|rest| memchr::memchr2(b'o', b'O', rest))
    {
        let at = start + k;
        let s = memchr::memrchr(b'\n', &b[start..at]).map_or(start, |j| start + j + 1);
        line += memchr::memchr_iter(b'\n', &b[start..s]).count();
        let e = line_end(b, s);
        out.push((line, cut(text, s, e)));
        line += 1;
        start = e + 1;
    }
    out
}

impl<'a> Interp<'a, '_> {
    pub(super) fn add_source(&mut self, name: String, text: Cow<'a, str>) -> usize {
        let s = Source::new(name, text);
        let owords: Vec<(usize, ngc::OStmt)> = match &s.body {
            Body::Mem(m) if self.syn.ngc => lines_with_o(&m.text)
                .into_iter()
                .filter_map(|(i, l)| ngc::parse_line(l, self.syn).oword.map(|o| (i, o)))
                .collect(),
            _ => Vec::new(),
        };
        self.push_source(s, owords)
    }

    /// Registers a source and its O-word statements (line index, statement) in line order.
    pub(super) fn push_source(&mut self, s: Source<'a>, owords: Vec<(usize, ngc::OStmt)>) -> usize {
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

    /// Runs the program from its first line.
    pub(super) fn run(&mut self, mut sink: Option<MotionSink<'_>>) {
        let chunk = sink.as_ref().map_or(usize::MAX, |s| s.chunk);
        // Hands the moves to the sink once there are at least `chunk` of them.
        let mut drain = |it: &mut Self, chunk: usize| {
            if let Some(s) = sink.as_mut()
                && it.prog.motions.len() >= chunk.max(1)
            {
                (s.take)(&mut it.prog.motions);
                it.prog.motions.clear();
            }
        };
        let (mut src, mut i) = (0usize, 0usize);
        let mut started = false;
        let mut percent_open = false;
        let mut scratch = Line::default();
        // The plain route refuses a line with a comment only when it meets the comment,
        // after the words before it, which the general route then reads again. Programs
        // that comment a line tend to comment the next: after a fresh line with a comment,
        // the next is searched for one first ([`Source::has_comment`]) and, holding one, goes
        // to the general route straight.
        let mut comment_before = false;
        while !self.stop {
            drain(self, chunk);
            if !self.sources[src].has_line(i) {
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
            let fresh = src == 0 && i >= self.high_water[src];
            // Plain motion lines of the main program read for the first time are run
            // straight from its text ([`Interp::plain_text`]); the others are parsed.
            if self.plain_moves
                && fresh
                && !(comment_before && self.sources[0].has_comment(i))
                && let Some((start, text)) = self.sources[0].text_from_line(i)
                && let Some(len) = self.plain_text(text)
            {
                self.sources[0].record_read(i, start, len);
                comment_before = false;
                self.high_water[src] = i + 1;
                started = true;
                self.jumped = false;
                i += 1;
                continue;
            }
            let text = self.sources[src].line(i).unwrap_or_default();
            if text.trim().is_empty() {
                i += 1;
                continue;
            }
            // Lines met again (loop bodies, subroutines) are parsed once and cached; lines
            // read for the first time are parsed into one reused buffer and not kept
            // (bounded memory and no allocation per line on long programs).
            let cached: Option<std::rc::Rc<Line>> = if i < self.high_water[src] {
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
                comment_before = !scratch.comments.is_empty();
                None
            };
            let parsed: &Line = cached.as_deref().unwrap_or(&scratch);
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
        drain(self, 1);
    }

    /// Reports (once) that non-blank lines follow the end and are ignored.
    pub(super) fn after_end(&mut self, src: usize, from: usize) {
        if src != 0 {
            return;
        }
        let s = &mut self.sources[0];
        let syn = self.syn;
        let mut l = from;
        let ignored = loop {
            let Some(t) = s.line(l) else { break None };
            let t = t.trim();
            if !(t.is_empty() || t == "%") {
                let p = ngc::parse_line(t, syn);
                if !(p.words.is_empty()
                    && p.assigns.is_empty()
                    && p.oword.is_none()
                    && p.errors.is_empty())
                {
                    break Some(l);
                }
            }
            l += 1;
        };
        if let Some(l) = ignored {
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
}
