//! Line lexer: splits one G-code line into words, comments and an optional checksum.
//!
//! Accepts what controllers accept in practice: any case, spaces anywhere between words and
//! between a letter and its number (`g1x1.5 y2`, `G 1 X 1.5`), `;` comments to end of line,
//! `( )` comments, a leading `/` (block delete), `%` tape marks and RepRap/Marlin checksums
//! (`N10 G1 X1*57`: XOR of every byte before `*`). Anything else becomes a [`LexError`] with
//! its column; lexing always goes on to the end of the line.

/// One address word such as `X-1.25`: an upper-case letter and its value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// Upper-case address letter.
    pub letter: char,
    /// Numeric value.
    pub value: f64,
    /// 1-based column (in characters) of the letter.
    pub column: usize,
}

/// What went wrong in a line, with its 1-based column.
#[derive(Clone, Debug, PartialEq)]
pub struct LexError {
    /// 1-based column (in characters).
    pub column: usize,
    /// What went wrong.
    pub kind: LexErrorKind,
}

/// The kinds of [`LexError`].
#[derive(Clone, Debug, PartialEq)]
pub enum LexErrorKind {
    /// A letter with no number after it (`X` or `G.`).
    MissingNumber(char),
    /// A character that starts no word (digits without a letter, `#`, `=`, control bytes...).
    Unexpected(char),
    /// `(` without a closing `)`.
    UnclosedComment,
    /// `*` not followed by a decimal checksum.
    MalformedChecksum,
    /// The checksum does not match the XOR of the bytes before `*`.
    BadChecksum {
        /// XOR of the bytes before `*`.
        expected: u8,
        /// The number written after `*`.
        found: u32,
    },
    /// Text after the checksum.
    TrailingAfterChecksum,
}

/// The lexed content of one line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LexedLine {
    /// Address words in line order.
    pub words: Vec<Word>,
    /// Comment texts (trimmed), `( )` and `;` alike.
    pub comments: Vec<String>,
    /// Problems found, in column order.
    pub errors: Vec<LexError>,
    /// The line is a `%` tape mark (nothing else but spaces or a comment).
    pub percent: bool,
    /// The line starts with `/` (optional block delete).
    pub block_delete: bool,
    /// A checksum was present and correct.
    pub checksum_ok: bool,
}

/// Longest number text accepted (digits, sign, point); longer runs are malformed input.
const MAX_NUMBER_LEN: usize = 64;

/// Lexes one line (without its line terminator).
pub fn lex_line(line: &str) -> LexedLine {
    let mut out = LexedLine::default();
    let chars: Vec<(usize, char)> = line.char_indices().collect();
    let n = chars.len();
    let mut i = 0;
    // Leading spaces, then optional block delete.
    while i < n && chars[i].1.is_whitespace() {
        i += 1;
    }
    if i < n && chars[i].1 == '%' {
        out.percent = true;
        i += 1;
    } else if i < n && chars[i].1 == '/' {
        out.block_delete = true;
        i += 1;
    }
    while i < n {
        let (byte_pos, c) = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c == ';' {
            let rest: String = chars[i + 1..].iter().map(|&(_, ch)| ch).collect();
            out.comments.push(rest.trim().to_string());
            break;
        } else if c == '(' {
            match chars[i + 1..].iter().position(|&(_, ch)| ch == ')') {
                Some(k) => {
                    let text: String = chars[i + 1..i + 1 + k].iter().map(|&(_, ch)| ch).collect();
                    out.comments.push(text.trim().to_string());
                    i += k + 2;
                }
                None => {
                    out.errors.push(LexError {
                        column,
                        kind: LexErrorKind::UnclosedComment,
                    });
                    break;
                }
            }
        } else if c == '*' {
            lex_checksum(line, &chars[i + 1..], byte_pos, column, &mut out);
            break;
        } else if c.is_ascii_alphabetic() {
            let letter = c.to_ascii_uppercase();
            i += 1;
            while i < n && chars[i].1 == ' ' {
                i += 1;
            }
            let mut text = String::new();
            while i < n && text.len() <= MAX_NUMBER_LEN {
                let ch = chars[i].1;
                let sign_ok = (ch == '+' || ch == '-') && text.is_empty();
                if ch.is_ascii_digit() || ch == '.' || sign_ok {
                    text.push(ch);
                    i += 1;
                } else {
                    break;
                }
            }
            match parse_number(&text) {
                Some(value) => out.words.push(Word {
                    letter,
                    value,
                    column,
                }),
                None => out.errors.push(LexError {
                    column,
                    kind: LexErrorKind::MissingNumber(letter),
                }),
            }
        } else {
            out.errors.push(LexError {
                column,
                kind: LexErrorKind::Unexpected(c),
            });
            i += 1;
            // Skip the rest of this junk token up to the next letter, space or comment.
            while i < n {
                let ch = chars[i].1;
                if ch.is_ascii_alphabetic() || ch.is_whitespace() || "(;*".contains(ch) {
                    break;
                }
                i += 1;
            }
        }
    }
    out
}

/// A decimal number: optional sign, digits with at most one point, at least one digit.
fn parse_number(text: &str) -> Option<f64> {
    let digits = text.chars().filter(|c| c.is_ascii_digit()).count();
    let points = text.chars().filter(|&c| c == '.').count();
    if digits == 0 || points > 1 || text.len() > MAX_NUMBER_LEN {
        return None;
    }
    let v: f64 = text.parse().ok()?;
    v.is_finite().then_some(v)
}

/// Checks `*NN` against the XOR of all bytes of `line` before the `*` at `star_byte`.
fn lex_checksum(
    line: &str,
    rest: &[(usize, char)],
    star_byte: usize,
    column: usize,
    out: &mut LexedLine,
) {
    let digits: String = rest
        .iter()
        .take_while(|&&(_, c)| c.is_ascii_digit())
        .map(|&(_, c)| c)
        .collect();
    let trailing = rest[digits.len()..]
        .iter()
        .any(|&(_, c)| !c.is_whitespace());
    let Some(found) = (!digits.is_empty() && digits.len() <= 9)
        .then(|| digits.parse::<u32>().ok())
        .flatten()
    else {
        out.errors.push(LexError {
            column,
            kind: LexErrorKind::MalformedChecksum,
        });
        return;
    };
    let expected = line
        .as_bytes()
        .get(..star_byte)
        .unwrap_or_default()
        .iter()
        .fold(0u8, |acc, b| acc ^ b);
    if u32::from(expected) == found {
        out.checksum_ok = true;
    } else {
        out.errors.push(LexError {
            column,
            kind: LexErrorKind::BadChecksum { expected, found },
        });
    }
    if trailing {
        out.errors.push(LexError {
            column: column + 1 + digits.len(),
            kind: LexErrorKind::TrailingAfterChecksum,
        });
    }
}

/// The XOR checksum RepRap/Marlin put after `*`, computed over `text` (for writing tests and
/// senders).
pub fn checksum(text: &str) -> u8 {
    text.bytes().fold(0, |acc, b| acc ^ b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn letters(l: &LexedLine) -> Vec<(char, f64)> {
        l.words.iter().map(|w| (w.letter, w.value)).collect()
    }

    #[test]
    fn spacing_and_case_variants() {
        let a = lex_line("g1x1.5 y2");
        let b = lex_line("G 1 X 1.5Y2.");
        let c = lex_line("  G01 X+1.50 Y2.000 ");
        assert!(a.errors.is_empty() && b.errors.is_empty() && c.errors.is_empty());
        let want = vec![('G', 1.0), ('X', 1.5), ('Y', 2.0)];
        assert_eq!(letters(&a), want);
        assert_eq!(letters(&b), want);
        assert_eq!(letters(&c), want);
        assert_eq!(a.words[1].column, 3);
    }

    #[test]
    fn comments() {
        let l = lex_line("G0 (move (fast) X5 ; rest X9");
        assert_eq!(letters(&l), vec![('G', 0.0), ('X', 5.0)]);
        assert_eq!(l.comments, vec!["move (fast".to_string(), "rest X9".into()]);
        let u = lex_line("G1 (open X1");
        assert_eq!(u.errors[0].kind, LexErrorKind::UnclosedComment);
        assert_eq!(u.errors[0].column, 4);
    }

    #[test]
    fn checksums() {
        let body = "N3 G1 X1.5 Y2";
        let good = format!("{body}*{}", checksum(body));
        assert!(lex_line(&good).checksum_ok);
        assert!(lex_line(&good).errors.is_empty());
        let bad = format!("{body}*{}", u32::from(checksum(body)) + 1);
        let l = lex_line(&bad);
        assert!(!l.checksum_ok);
        assert!(matches!(l.errors[0].kind, LexErrorKind::BadChecksum { .. }));
        assert_eq!(l.errors[0].column, body.len() + 1);
        assert_eq!(
            lex_line("G1*x").errors[0].kind,
            LexErrorKind::MalformedChecksum
        );
    }

    #[test]
    fn malformed_words_keep_going() {
        let l = lex_line("G1 X Y2 #5=3 Z1.2.3 F100");
        let kinds: Vec<_> = l
            .errors
            .iter()
            .map(|e| (e.column, e.kind.clone()))
            .collect();
        assert_eq!(kinds[0], (4, LexErrorKind::MissingNumber('X')));
        assert_eq!(kinds[1], (9, LexErrorKind::Unexpected('#')));
        assert_eq!(kinds[2], (14, LexErrorKind::MissingNumber('Z')));
        assert_eq!(letters(&l), vec![('G', 1.0), ('Y', 2.0), ('F', 100.0)]);
    }

    #[test]
    fn percent_and_block_delete() {
        assert!(lex_line("%").percent);
        let l = lex_line("/G0 X1");
        assert!(l.block_delete);
        assert_eq!(letters(&l), vec![('G', 0.0), ('X', 1.0)]);
    }
}
