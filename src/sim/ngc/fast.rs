//! Fast paths of [`parse_line_into`]: lines of plain words (letters and decimal numbers)
//! read without building expressions, and short lines without brackets or parameters.

use super::*;

/// Longest run of significant characters [`parse_simple`] takes; longer lines are read by
/// the general parser.
pub(super) const SIMPLE_MAX: usize = 160;

/// Longest line [`parse_plain`] takes (bytes): within [`SIMPLE_MAX`] and [`MAX_LINE_LEN`],
/// so [`parse_simple`] would not refuse it for its length.
pub(super) const PLAIN_MAX: usize = 128;

/// Most digits [`plain_number`] reads as an integer: 10¹⁵ < 2⁵³, so the digits are exact in
/// an f64.
pub(super) const PLAIN_DIGITS: usize = 15;

/// Exact powers of ten 10⁰…10²² (every one is an f64 exactly).
pub(super) const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The fastest path of [`parse_line_into`]: lines of words `letter [sign] number` separated
/// by blanks or nothing, each number written without blanks inside it (`G1 X-1.5 Y2`,
/// `G0X1Y2`), with ASCII `( )` comments between words and a `;` comment at the end
/// (`G2 X1 Y2 I0.5 J0 (arc)`), which is what CAM output is made of. Gives exactly what
/// [`parse_simple`] gives (same words, columns, bit-identical values and the same comment
/// texts, trimmed, pushed onto `comments`); returns false, with `words` partly overwritten
/// and `comments` partly filled, for anything else (blanks between a letter and its number,
/// a comment inside a word or left open, other characters, long lines), which
/// [`parse_simple`] or the general parser then read.
///
/// The words go into `words` in place of the ones it holds (the previous line's), which
/// is then cut to this line's: each field is written where it stays, where a pushed word
/// would be built on the stack and copied, and that copy's wide load has to wait for the
/// narrow stores of the value just computed (a store-forwarding stall).
pub(super) fn parse_plain(
    raw: &[u8],
    syn: Syntax,
    words: &mut Vec<PWord>,
    comments: &mut Vec<String>,
) -> bool {
    if raw.len() > PLAIN_MAX {
        return false;
    }
    let mut count = 0usize;
    let whole = scan_plain(
        raw,
        syn,
        |letter, v, column| {
            match words.get_mut(count) {
                Some(w) => {
                    w.letter = letter;
                    // A number over a number needs no drop glue.
                    match &mut w.value {
                        Expr::Num(x) => *x = v,
                        e => *e = Expr::Num(v),
                    }
                    w.column = column;
                }
                None => words.push(PWord {
                    letter,
                    value: Expr::Num(v),
                    column,
                }),
            }
            count += 1;
            true
        },
        // Only ASCII lines are `parse_simple`'s, so only ASCII comments are this path's.
        |text| {
            let ok = text.is_ascii();
            if ok {
                comments.push(comment_text(text));
            }
            ok
        },
    ) == Some(raw.len());
    if whole {
        words.truncate(count);
    }
    whole
}

/// The words of the plain line that `text` starts with (up to its first `\n`, or all of
/// `text`), as [`parse_plain`] reads them (upper-case letter, value): each handed to
/// `word`, which returns false to stop. The line's length (the offset of its `\n`, or
/// `text.len()`) when the whole line was read and every word taken; None at a comment or
/// anything [`parse_plain`] does not read, a line longer than [`PLAIN_MAX`] (a trailing
/// `\r` not counted) among them; the line then takes [`parse_line_into`]. The
/// interpreter's route for plain motion blocks: the line's end is found by the scan, and no
/// [`Line`] is built.
pub fn plain_words(
    text: &[u8],
    syn: Syntax,
    mut word: impl FnMut(char, f64) -> bool,
) -> Option<usize> {
    // A line of PLAIN_MAX bytes, a `\r` and its `\n` at most.
    let raw = text.get(..PLAIN_MAX + 2).unwrap_or(text);
    let end = scan_plain(raw, syn, |c, v, _| word(c, v), |_| false)?;
    let at_end = end < raw.len() || raw.len() == text.len();
    let len = end - usize::from(raw[..end].ends_with(b"\r"));
    (at_end && len <= PLAIN_MAX).then_some(end)
}

/// The scanner of [`parse_plain`]: hands each word (upper-case letter, value, 1-based
/// column) to `word` and each comment's text (between the parentheses, or after `;`) to
/// `comment`, in line order; either returns false to stop. The line is `raw` up to its
/// first `\n` (all of `raw` when it has none): its length when the whole line was read,
/// None when stopped.
fn scan_plain(
    raw: &[u8],
    syn: Syntax,
    mut word: impl FnMut(char, f64, usize) -> bool,
    mut comment: impl FnMut(&[u8]) -> bool,
) -> Option<usize> {
    let n = raw.len();
    let mut k = 0usize;
    loop {
        while k < n && matches!(raw[k], b' ' | b'\t' | b'\r') {
            k += 1;
        }
        if k == n || raw[k] == b'\n' {
            return Some(k);
        }
        let c = raw[k];
        if c == b'(' {
            let e = memchr::memchr(b')', &raw[k + 1..])?;
            if !comment(&raw[k + 1..k + 1 + e]) {
                return None;
            }
            k += e + 2;
            continue;
        }
        if c == b';' {
            if !comment(&raw[k + 1..]) {
                return None;
            }
            k = n;
            continue;
        }
        if !c.is_ascii_alphabetic() || (syn.ngc && (c == b'o' || c == b'O')) {
            return None;
        }
        let column = k + 1;
        k += 1;
        let (v, end) = plain_number(raw, k)?;
        // The number must end at a blank, the next letter, a comment or the end of the line.
        if end < n
            && !matches!(
                raw[end],
                b' ' | b'\t' | b'\r' | b'\n' | b'(' | b';' | b'a'..=b'z' | b'A'..=b'Z'
            )
        {
            return None;
        }
        k = end;
        if !word(char::from(c.to_ascii_uppercase()), v, column) {
            return None;
        }
    }
}

/// Reads `[sign] digits [. digits]` (at least one digit) from `raw[k..]`: its value and the
/// index after it. The value is the correctly rounded f64 of the decimal, as `fast_float2`
/// and `str::parse` give it: up to [`PLAIN_DIGITS`] digits with at most 22 after the point,
/// the digits are an exact integer m < 2⁵³ and 10^f is exact, so m / 10^f is one correctly
/// rounded IEEE division; longer numbers go to `fast_float2`. The sign is applied last
/// (`-0` is −0.0, as in [`parse_simple`]).
pub(super) fn plain_number(raw: &[u8], mut k: usize) -> Option<(f64, usize)> {
    let neg = match raw.get(k) {
        Some(b'-') => {
            k += 1;
            true
        }
        Some(b'+') => {
            k += 1;
            false
        }
        _ => false,
    };
    let start = k;
    let mut m: u64 = 0;
    let mut digits = 0usize;
    let mut frac = 0usize;
    let mut point = false;
    while let Some(&b) = raw.get(k) {
        if b.is_ascii_digit() {
            m = m.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
            digits += 1;
            frac += usize::from(point);
        } else if b == b'.' && !point {
            point = true;
        } else {
            break;
        }
        k += 1;
    }
    if digits == 0 {
        return None;
    }
    let v = if digits <= PLAIN_DIGITS && frac == 0 {
        // A whole number (G1, F1500): m itself, exact, without the division's latency.
        m as f64
    } else if digits <= PLAIN_DIGITS {
        // frac ≤ digits ≤ 15 < 23.
        m as f64 / POW10[frac]
    } else {
        let v = fast_float2::parse::<f64, _>(&raw[start..k]).ok()?;
        if !v.is_finite() {
            return None;
        }
        v
    };
    Some((if neg { -v } else { v }, k))
}

/// A comment's text as the fast paths keep it: trimmed (`text` is ASCII there).
pub(super) fn comment_text(text: &[u8]) -> String {
    std::str::from_utf8(text).unwrap_or("").trim().to_string()
}

/// The fast path of [`parse_line_into`], over bytes: plain ASCII lines of words
/// `letter [sign] number` with blanks anywhere and `( )` or `;` comments, which is what
/// CAM output is made of. Numbers are read by `fast_float2` (correctly rounded, as
/// `str::parse`). Returns false, with `out` partly filled, at the first thing it does not
/// take (parameters, expressions, O-words, checksums, `%`, `/`, `$`, flags, errors): the
/// general parser then reads the whole line, so every diagnostic comes from one place.
pub(super) fn parse_simple(raw: &[u8], syn: Syntax, out: &mut Line) -> bool {
    if (syn.ngc && raw.len() > MAX_LINE_LEN) || !raw.is_ascii() {
        return false;
    }
    // Significant bytes (lower case) and their 1-based columns, comments taken out.
    let mut sig = [0u8; SIMPLE_MAX];
    let mut col = [0u16; SIMPLE_MAX];
    let mut n = 0usize;
    let mut k = 0usize;
    while k < raw.len() {
        let c = raw[k];
        match c {
            b' ' | b'\t' | b'\r' => {}
            b';' => {
                out.comments.push(comment_text(&raw[k + 1..]));
                break;
            }
            b'(' => {
                let Some(e) = memchr::memchr(b')', &raw[k + 1..]) else {
                    return false;
                };
                out.comments.push(comment_text(&raw[k + 1..k + 1 + e]));
                k += e + 2;
                continue;
            }
            b'0'..=b'9' | b'.' | b'+' | b'-' | b'a'..=b'z' | b'A'..=b'Z' => {
                if n == SIMPLE_MAX || k >= usize::from(u16::MAX) {
                    return false;
                }
                sig[n] = c.to_ascii_lowercase();
                col[n] = (k + 1) as u16;
                n += 1;
            }
            _ => return false,
        }
        k += 1;
    }
    let sig = &sig[..n];
    let mut i = 0usize;
    while i < n {
        let c = sig[i];
        if !c.is_ascii_alphabetic() || (c == b'o' && syn.ngc) {
            return false;
        }
        let column = usize::from(col[i]);
        i += 1;
        let neg = match sig.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let start = i;
        let mut point = false;
        while i < n && (sig[i].is_ascii_digit() || (sig[i] == b'.' && !point)) {
            point |= sig[i] == b'.';
            i += 1;
        }
        let text = &sig[start..i];
        if !text.iter().any(u8::is_ascii_digit) {
            return false;
        }
        let Ok(v) = fast_float2::parse::<f64, _>(text) else {
            return false;
        };
        if !v.is_finite() {
            return false;
        }
        out.words.push(PWord {
            letter: char::from(c.to_ascii_uppercase()),
            value: Expr::Num(if neg { -v } else { v }),
            column,
        });
    }
    true
}
