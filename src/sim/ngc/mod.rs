//! RS274NGC block syntax as LinuxCNC reads it: a line becomes words whose values are
//! expressions, parameter assignments, an optional O-word statement and its comments.
//!
//! Following LinuxCNC's reader (manual, "G-code overview": *Format of a line*, *Parameters*,
//! *Expressions*, *Binary operators*, *Functions*): outside comments, spaces and tabs are
//! ignored and letters are case-insensitive (`g 1x [1 + 2 ]` is `G1 X3`); `;` starts a comment
//! to the end of the line; `( )` comments are kept verbatim for `(debug,…)`, `(print,…)`,
//! `(msg,…)` and the `(skinpath:group N)` hook. Values are real numbers, `#` parameters
//! (`#12`, `##1`, `#[1+2]`, `#<name>`, `#<_global>`), bracketed expressions and unary
//! functions (`SIN[30]`, `ATAN[1]/[2]`, `EXISTS[#<x>]`). A top-level `*` followed by digits is
//! a RepRap/Marlin checksum (XOR of the bytes before it).
//!
//! Binary operator precedence, highest first (LinuxCNC `precedence()`): `**`; `*` `/` `MOD`;
//! `+` `-`; `EQ NE GT GE LT LE`; `AND OR XOR`. Operators of equal precedence associate left.

use std::f64::consts::PI;

mod cursor;
mod expr;
mod fast;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_expr;

use cursor::*;
use expr::*;
pub use expr::{BinOp, Expr, ParamRef, ParamSource, param_index};
pub use fast::plain_words;
use fast::*;

/// Two values compare equal (EQ/NE) when they differ by less than this: LinuxCNC's
/// `TOLERANCE_EQUAL` (interp_internal.hh).
pub const TOLERANCE_EQUAL: f64 = 0.0001;

/// Highest numbered parameter (LinuxCNC `RS274NGC_MAX_PARAMETERS` − 1).
pub const MAX_PARAMETER: i64 = 5601;

/// Longest line LinuxCNC reads (`LINELEN` − 1).
pub const MAX_LINE_LEN: usize = 255;

/// Deepest nesting accepted in one expression, counting brackets (function arguments
/// included), unary signs and parameter indirections (`#`) alike: `[[1]]`, `--1` and `##1`
/// are each two deep. A guard against stack exhaustion on hostile input (3·10⁴ nested `#`
/// or unary minus signs); LinuxCNC programs nest a handful deep. Flat runs of binary
/// operators do not nest (see [`Expr::Chain`]): a sum of 10⁵ terms is one level.
pub const MAX_NESTING: usize = 64;

/// O-word keywords.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OKind {
    /// `sub`: start of a subroutine.
    Sub,
    /// `endsub`
    EndSub,
    /// `call`
    Call,
    /// `return`
    Return,
    /// `if`
    If,
    /// `elseif`
    ElseIf,
    /// `else`
    Else,
    /// `endif`
    EndIf,
    /// `while` (or the end of a `do` loop)
    While,
    /// `endwhile`
    EndWhile,
    /// `do`
    Do,
    /// `repeat`
    Repeat,
    /// `endrepeat`
    EndRepeat,
    /// `break`
    Break,
    /// `continue`
    Continue,
}

const OKINDS: [(&str, OKind); 15] = [
    ("endsub", OKind::EndSub),
    ("endif", OKind::EndIf),
    ("endwhile", OKind::EndWhile),
    ("endrepeat", OKind::EndRepeat),
    ("elseif", OKind::ElseIf),
    ("else", OKind::Else),
    ("sub", OKind::Sub),
    ("call", OKind::Call),
    ("return", OKind::Return),
    ("if", OKind::If),
    ("while", OKind::While),
    ("do", OKind::Do),
    ("repeat", OKind::Repeat),
    ("break", OKind::Break),
    ("continue", OKind::Continue),
];

/// An O-word statement: label (`100` or a lower-case name), keyword and its bracketed
/// arguments (the condition, the repeat count, call arguments or a return value).
#[derive(Clone, Debug, PartialEq)]
pub struct OStmt {
    /// Label: a number as written or a lower-case name.
    pub label: String,
    /// The keyword.
    pub kind: OKind,
    /// Bracketed arguments.
    pub args: Vec<Expr>,
}

/// One word such as `X[#1 + 2]`: upper-case letter, value expression, 1-based column.
#[derive(Clone, Debug, PartialEq)]
pub struct PWord {
    /// Upper-case address letter.
    pub letter: char,
    /// Value expression.
    pub value: Expr,
    /// 1-based column of the letter.
    pub column: usize,
}

/// A syntax problem with its 1-based column and a kebab-case id.
#[derive(Clone, Debug, PartialEq)]
pub struct SyntaxError {
    /// 1-based column.
    pub column: usize,
    /// Kebab-case identifier (`gcode-syntax`, ...).
    pub id: &'static str,
    /// What is wrong.
    pub message: String,
}

/// One parsed line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Line {
    /// A `%` tape mark line.
    pub percent: bool,
    /// Starts with `/` (block delete).
    pub block_delete: bool,
    /// Address words in line order.
    pub words: Vec<PWord>,
    /// `#…=expr` assignments, applied after the block's values are read.
    pub assigns: Vec<(ParamRef, Expr, usize)>,
    /// The O-word statement of the line, if any.
    pub oword: Option<OStmt>,
    /// `( )` comment texts (verbatim, trimmed) and a `;` comment.
    pub comments: Vec<String>,
    /// `$…` GRBL system command text (only at the start of a line).
    pub dollar: Option<String>,
    /// Problems found in the line.
    pub errors: Vec<SyntaxError>,
    /// A checksum was present and correct.
    pub checksum_ok: bool,
}

/// Which constructs the reader accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Syntax {
    /// Parameters, expressions and O-words (LinuxCNC); otherwise they are "not supported".
    pub ngc: bool,
    /// `*NN` checksums (RepRap/Marlin).
    pub checksums: bool,
    /// `$` system commands (GRBL).
    pub dollar: bool,
}

/// Parses one line (without its terminator).
pub fn parse_line(raw: &str, syn: Syntax) -> Line {
    let mut out = Line::default();
    if syn.ngc && raw.len() > MAX_LINE_LEN {
        out.errors.push(SyntaxError {
            column: MAX_LINE_LEN + 1,
            id: "gcode-syntax",
            message: format!(
                "line longer than {MAX_LINE_LEN} characters (LinuxCNC's LINELEN): shorten it"
            ),
        });
    }
    // Split off comments and checksum, collect significant characters.
    let mut sig: Vec<(char, usize)> = Vec::with_capacity(raw.len());
    let mut chars = raw.char_indices().enumerate().peekable();
    let mut first = true;
    while let Some((ci, (bi, c))) = chars.next() {
        let col = ci + 1;
        if c == ' ' || c == '\t' || c == '\r' {
            continue;
        }
        if first {
            first = false;
            if c == '%' {
                out.percent = true;
                continue;
            }
            if c == '/' {
                out.block_delete = true;
                continue;
            }
            if c == '$' && syn.dollar {
                out.dollar = Some(raw[bi + 1..].trim().to_string());
                return out;
            }
        }
        match c {
            ';' => {
                out.comments.push(raw[bi + 1..].trim().to_string());
                break;
            }
            '(' => {
                let mut text = String::new();
                let mut closed = false;
                for (_, (_, ch)) in chars.by_ref() {
                    if ch == ')' {
                        closed = true;
                        break;
                    }
                    text.push(ch);
                }
                if !closed {
                    out.errors.push(SyntaxError {
                        column: col,
                        id: "gcode-syntax",
                        message: "'(' comment not closed".into(),
                    });
                }
                out.comments.push(text.trim().to_string());
            }
            '*' if syn.checksums && depth_zero(&sig) && !next_is_star(raw, bi) => {
                checksum(raw, bi, col, &mut out);
                break;
            }
            _ => sig.push((c.to_ascii_lowercase(), col)),
        }
    }
    if out.percent && !sig.is_empty() {
        // `%` followed by text: LinuxCNC ignores the rest of a percent line.
        sig.clear();
    }
    let mut cur = Cursor {
        c: &sig,
        i: 0,
        depth: 0,
    };
    while let Some(c) = cur.peek() {
        let col = cur.col();
        let res: Result<(), (usize, String)> = if c == '#' {
            if !syn.ngc {
                not_supported(&mut out, col, "parameters (#)");
                break;
            }
            cur.i += 1;
            (|| {
                let p = cur.param_ref()?;
                if !cur.eat('=') {
                    return cur.err("'=' expected after a parameter at the start of a word");
                }
                let v = cur.real_value()?;
                out.assigns.push((p, v, col));
                Ok(())
            })()
        } else if c == 'o' && out.words.is_empty() && out.oword.is_none() && syn.ngc {
            cur.i += 1;
            oword(&mut cur).map(|o| out.oword = Some(o))
        } else if c.is_ascii_alphabetic() || (syn.ngc && (c == '@' || c == '^')) {
            cur.i += 1;
            let letter = c.to_ascii_uppercase();
            if !syn.ngc && matches!(cur.peek(), Some('[') | Some('#')) {
                not_supported(&mut out, col, "expressions and parameters");
                break;
            }
            let flag = !syn.ngc && cur.peek().is_none_or(|n| n.is_ascii_alphabetic());
            if flag {
                // Marlin-style flag word without a value (`M3 I`): taken as 1.
                out.words.push(PWord {
                    letter,
                    value: Expr::Num(1.0),
                    column: col,
                });
                continue;
            }
            cur.real_value().map(|value| {
                out.words.push(PWord {
                    letter,
                    value,
                    column: col,
                })
            })
        } else if c == '[' && !syn.ngc {
            not_supported(&mut out, col, "expressions ([ ])");
            break;
        } else {
            cur.i += 1;
            Err((col, format!("unexpected character {c:?}")))
        };
        if let Err((column, message)) = res {
            out.errors.push(SyntaxError {
                column,
                id: "gcode-syntax",
                message,
            });
            cur.depth = 0;
            // Skip to the next letter to keep going.
            while let Some(ch) = cur.peek() {
                if ch.is_ascii_alphabetic() {
                    break;
                }
                cur.i += 1;
            }
        }
    }
    out
}

/// Parses one line (without its terminator) into `out`, reusing its buffers: the allocation
/// free path of a streaming reader. Gives the same [`Line`] as [`parse_line`] up to the form
/// of constant values (`X-1` is `Num(-1)` here, `Neg(Num(1))` there; both evaluate alike).
pub fn parse_line_into(raw: &str, syn: Syntax, out: &mut Line) {
    out.percent = false;
    out.block_delete = false;
    out.assigns.clear();
    // Most lines have none: skip the drop glue.
    if out.oword.is_some() {
        out.oword = None;
    }
    out.comments.clear();
    if out.dollar.is_some() {
        out.dollar = None;
    }
    out.errors.clear();
    out.checksum_ok = false;
    // The plain path overwrites the previous line's words in place.
    if parse_plain(raw.as_bytes(), syn, &mut out.words, &mut out.comments) {
        return;
    }
    out.words.clear();
    out.comments.clear();
    if !parse_simple(raw.as_bytes(), syn, out) {
        *out = parse_line(raw, syn);
    }
}

fn depth_zero(sig: &[(char, usize)]) -> bool {
    let open = sig.iter().filter(|c| c.0 == '[').count();
    let close = sig.iter().filter(|c| c.0 == ']').count();
    open <= close
}

fn next_is_star(raw: &str, bi: usize) -> bool {
    raw.as_bytes().get(bi + 1) == Some(&b'*')
}

fn not_supported(out: &mut Line, column: usize, what: &str) {
    out.errors.push(SyntaxError {
        column,
        id: "unsupported-code",
        message: format!("{what} not supported in this dialect"),
    });
}

fn checksum(raw: &str, star: usize, column: usize, out: &mut Line) {
    let rest = &raw[star + 1..];
    let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
    let trailing = rest[digits.len()..]
        .trim()
        .trim_start_matches(';')
        .chars()
        .next()
        .is_some_and(|_| !rest[digits.len()..].trim().starts_with(';'));
    let found = (!digits.is_empty() && digits.len() <= 9)
        .then(|| digits.parse::<u32>().ok())
        .flatten();
    let Some(found) = found else {
        out.errors.push(SyntaxError {
            column,
            id: "bad-checksum",
            message: "'*' without a checksum".into(),
        });
        return;
    };
    let expected = raw.as_bytes()[..star].iter().fold(0u8, |a, b| a ^ b);
    if u32::from(expected) == found {
        out.checksum_ok = true;
    } else {
        out.errors.push(SyntaxError {
            column,
            id: "bad-checksum",
            message: format!("checksum {found} does not match the line (expected {expected})"),
        });
    }
    if trailing {
        out.errors.push(SyntaxError {
            column: column + 1 + digits.len(),
            id: "gcode-syntax",
            message: "text after the checksum".into(),
        });
    }
}

fn oword(cur: &mut Cursor<'_>) -> Result<OStmt, (usize, String)> {
    let label = if cur.eat('<') {
        let mut name = String::new();
        loop {
            match cur.peek() {
                Some('>') => {
                    cur.i += 1;
                    break;
                }
                Some(c) => {
                    name.push(c);
                    cur.i += 1;
                }
                None => return cur.err("O-word name without closing '>'"),
            }
        }
        name
    } else {
        let mut digits = String::new();
        while let Some(c) = cur.peek().filter(|c| c.is_ascii_digit()) {
            digits.push(c);
            cur.i += 1;
        }
        if digits.is_empty() {
            return cur.err("'O' needs a number or <name>");
        }
        digits.trim_start_matches('0').to_string()
    };
    let Some(kind) = OKINDS
        .iter()
        .find(|(k, _)| cur.starts_with(k))
        .map(|&(k, kind)| {
            cur.i += k.len();
            kind
        })
    else {
        return cur.err(format!(
            "O{label} needs a keyword (sub, endsub, call, return, if, elseif, else, endif, \
             while, endwhile, do, repeat, endrepeat, break, continue)"
        ));
    };
    let mut args = Vec::new();
    while cur.peek() == Some('[') {
        args.push(cur.bracketed()?);
    }
    if let Some(c) = cur.peek() {
        return cur.err(format!("unexpected {c:?} after the O-word statement"));
    }
    Ok(OStmt { label, kind, args })
}
