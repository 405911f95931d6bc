//! Parsing ahead of the interpreter on a second thread: the lines of an in-memory program
//! are parsed in chunks by a worker while the interpreter executes the chunk before, so
//! reading a long program costs about the larger of parsing and executing, not their sum.
//!
//! Parsing is a pure function of the line's text and the syntax ([`ngc::parse_line_into`]),
//! so a line parsed ahead is the line the interpreter would have parsed itself: the
//! program, its moves and its diagnostics do not depend on whether the worker ran. Only
//! first readings use it (the interpreter reads the main program's lines for the first
//! time in increasing order; loop bodies and subroutines met again come from its cache).
//! Blank lines (whitespace only), which the interpreter skips, are marked instead of
//! parsed, so it need not look at their text either ([`Ahead`]).
//!
//! Memory is bounded: at most [`IN_FLIGHT`] chunks of [`CHUNK_LINES`] parsed lines wait,
//! and their buffers are handed back for reuse. The worker stops when the interpreter
//! drops its [`ParseAhead`] (a program ending early does not wait for the rest to be
//! parsed).

use super::interp::LineStarts;
use super::ngc::{self, Line, Syntax};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};

/// Lines per chunk: large enough that the hand-over (two channel operations) is noise,
/// small enough that a chunk's parsed lines stay in the caches.
pub const CHUNK_LINES: usize = 2048;

/// Parsed chunks that may wait for the interpreter.
const IN_FLIGHT: usize = 4;

/// Programs with fewer lines than this are parsed on the interpreter's thread: starting a
/// worker costs more than it saves.
pub const MIN_LINES: usize = 16 * CHUNK_LINES;

/// Consecutive lines parsed by the worker.
struct Chunk {
    /// Index of the first line.
    first: usize,
    /// The parsed lines; those marked blank are not parsed (stale buffers).
    lines: Vec<Line>,
    /// Per line: blank (whitespace only, `str::trim` empty).
    blank: Vec<bool>,
}

/// A line of the program as the worker hands it out.
#[derive(Debug, PartialEq)]
pub enum Ahead<'a> {
    /// Whitespace only: the interpreter skips it without parsing it.
    Blank,
    /// Parsed.
    Line(&'a Line),
}

/// The interpreter's end of the worker: hands out parsed lines by index.
pub struct ParseAhead {
    rx: Receiver<Chunk>,
    recycle: SyncSender<(Vec<Line>, Vec<bool>)>,
    cur: Option<Chunk>,
}

impl ParseAhead {
    /// Starts a worker in `scope` parsing the lines of `text` with `syn`: the lines
    /// [`super::interp`] reads from an in-memory source, found by its line `starts` (of
    /// `text`; split at `\n`, a trailing `\r` removed).
    pub fn spawn<'scope, 'env: 'scope>(
        scope: &'scope std::thread::Scope<'scope, 'env>,
        text: &'env str,
        starts: Arc<LineStarts>,
        syn: Syntax,
    ) -> ParseAhead {
        let (tx, rx) = sync_channel::<Chunk>(IN_FLIGHT);
        let (recycle, spare) = sync_channel::<(Vec<Line>, Vec<bool>)>(IN_FLIGHT + 2);
        scope.spawn(move || parse_chunks(text, &starts, syn, &tx, &spare));
        ParseAhead {
            rx,
            recycle,
            cur: None,
        }
    }

    /// Line `i` parsed or marked blank, when the worker has it: `i` must not be below the
    /// line asked for before (chunks passed are dropped). None when the worker has stopped
    /// or `i` is behind it; the caller reads the line itself then.
    pub fn get(&mut self, i: usize) -> Option<Ahead<'_>> {
        loop {
            match &self.cur {
                Some(c) if i < c.first => return None,
                Some(c) if i < c.first + c.lines.len() => break,
                _ => {}
            }
            if let Some(old) = self.cur.take() {
                // The worker allocates afresh when no buffer comes back.
                let _ = self.recycle.try_send((old.lines, old.blank));
            }
            self.cur = Some(self.rx.recv().ok()?);
        }
        let c = self.cur.as_ref()?;
        let k = i - c.first;
        if *c.blank.get(k)? {
            Some(Ahead::Blank)
        } else {
            c.lines.get(k).map(Ahead::Line)
        }
    }
}

/// The worker: parses `text` chunk by chunk into `tx` until the text ends or the
/// interpreter hangs up.
fn parse_chunks(
    text: &str,
    starts: &LineStarts,
    syn: Syntax,
    tx: &SyncSender<Chunk>,
    spare: &Receiver<(Vec<Line>, Vec<bool>)>,
) {
    let mut lines_of = (0..starts.len()).map(|i| starts.line(text, i));
    let mut first = 0;
    loop {
        let (mut lines, mut blank) = spare.try_recv().unwrap_or_default();
        blank.clear();
        let mut n = 0;
        for raw in lines_of.by_ref().take(CHUNK_LINES) {
            if n == lines.len() {
                lines.push(Line::default());
            }
            // The interpreter's test for a line to skip (`str::trim` empty), taken off its
            // thread; a line starting with a visible ASCII character is not blank.
            let is_blank =
                !raw.as_bytes().first().is_some_and(u8::is_ascii_graphic) && raw.trim().is_empty();
            if !is_blank {
                ngc::parse_line_into(raw, syn, &mut lines[n]);
            }
            blank.push(is_blank);
            n += 1;
        }
        if n == 0 {
            return;
        }
        lines.truncate(n);
        if tx
            .send(Chunk {
                first,
                lines,
                blank,
            })
            .is_err()
        {
            return;
        }
        first += n;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn syn() -> Syntax {
        Syntax {
            ngc: true,
            checksums: false,
            dollar: false,
        }
    }

    #[test]
    fn lines_match_parsing_in_place_and_skips_are_allowed() {
        let text: String = (0..3 * CHUNK_LINES + 17)
            .map(|k| match k % 5 {
                0 => format!("G1 X{k} Y-{k}.5 F300\r\n"),
                1 if k % 2 == 0 => "\n".to_string(),
                1 => " \t\r\n".to_string(),
                2 => format!("#{} = [{k} * 2] (c)\n", 100 + k % 7),
                3 => format!("o{k} if [1 GT 0]\n"),
                _ => format!("N{k} G0 Z{}.25 ; note\n", k % 9),
            })
            .collect();
        let lines: Vec<&str> = text
            .split('\n')
            .map(|l| l.strip_suffix('\r').unwrap_or(l))
            .collect();
        std::thread::scope(|s| {
            let starts = Arc::new(LineStarts::of(text.as_bytes()));
            let mut ahead = ParseAhead::spawn(s, &text, starts, syn());
            // Every line in order, then a forward jump over whole chunks.
            let mut want = Line::default();
            for i in (0..CHUNK_LINES + 5).chain(3 * CHUNK_LINES..lines.len()) {
                if lines[i].trim().is_empty() {
                    assert_eq!(ahead.get(i), Some(Ahead::Blank), "line {i}: {:?}", lines[i]);
                    continue;
                }
                ngc::parse_line_into(lines[i], syn(), &mut want);
                assert_eq!(
                    ahead.get(i),
                    Some(Ahead::Line(&want)),
                    "line {i}: {:?}",
                    lines[i]
                );
            }
            // Behind the current chunk: the caller parses it.
            assert_eq!(ahead.get(3), None);
            // Past the end.
            assert_eq!(ahead.get(lines.len()), None);
        });
    }

    #[test]
    fn dropping_the_reader_stops_the_worker() {
        let text = "G1 X1\n".repeat(20 * CHUNK_LINES);
        std::thread::scope(|s| {
            let starts = Arc::new(LineStarts::of(text.as_bytes()));
            let mut ahead = ParseAhead::spawn(s, &text, starts, syn());
            assert!(ahead.get(0).is_some());
            drop(ahead);
            // The scope joins the worker: this returns only if it stopped.
        });
    }
}
