//! Unit tests of the RS274NGC line reader.

use super::*;
use std::collections::HashMap;

struct P(HashMap<String, f64>, HashMap<i64, f64>);
impl ParamSource for P {
    fn numbered(&self, n: i64) -> f64 {
        self.1.get(&n).copied().unwrap_or(0.0)
    }
    fn named(&self, name: &str) -> Option<f64> {
        self.0.get(name).copied()
    }
}

const NGC: Syntax = Syntax {
    ngc: true,
    checksums: true,
    dollar: false,
};

fn val(s: &str) -> Result<f64, String> {
    let l = parse_line(&format!("X{s}"), NGC);
    if let Some(e) = l.errors.first() {
        return Err(e.message.clone());
    }
    let p = P(
        [("a".to_string(), 2.0)].into_iter().collect(),
        [(1, 3.0), (3, 7.0)].into_iter().collect(),
    );
    l.words[0].value.eval(&p)
}

#[test]
fn manual_examples() {
    // LinuxCNC manual, "Expressions": [1 + acos[0] - [#3 ** [4.0/2]]] with #3 = 7.
    assert!((val("[1 + acos[0] - [#3 ** [4.0/2]]]").unwrap_or(0.0) - 42.0).abs() < 1e-12);
    // "Binary operators": 2.0 / 3 * 1.5 - 5.5 / 11.0 = 0.5.
    assert!((val("[2.0 / 3 * 1.5 - 5.5 / 11.0]").unwrap_or(0.0) - 0.5).abs() < 1e-12);
    assert_eq!(val("[1 + 2 * 3 ** 2]"), Ok(19.0));
    assert_eq!(val("[2 ** 3 ** 2]"), Ok(64.0));
    assert_eq!(val("[1 LT 2 AND 3 GT 2]"), Ok(1.0));
    assert_eq!(val("[-7 MOD 3]"), Ok(2.0));
    assert_eq!(val("[ATAN[1]/[-1]]"), Ok(135.0));
    assert_eq!(val("##1"), Ok(7.0));
    assert_eq!(val("#<a>"), Ok(2.0));
    assert_eq!(val("[EXISTS[#<a>] + EXISTS[#<b>]]"), Ok(1.0));
    assert_eq!(
        val("[FIX[-1.5] + FUP[1.2] + ROUND[2.5] + ABS[-1]]"),
        Ok(4.0)
    );
    assert!((val("[SIN[30]]").unwrap_or(0.0) - 0.5).abs() < 1e-12);
    assert_eq!(val("[1.00001 EQ 1]"), Ok(1.0));
    assert!(val("[1/0]").is_err_and(|e| e.contains("division by zero")));
    assert!(val("[1+2").is_err_and(|e| e.contains("unclosed")));
    assert!(val("#<nope>").is_err_and(|e| e.contains("not defined")));
    assert!(val("[SQRT[-1]]").is_err());
}

#[test]
fn lines() {
    let l = parse_line("N10 #1 = 5 #<x>=[#1+1] G1 x#1 (debug, hi #1) ; rest", NGC);
    assert!(l.errors.is_empty(), "{:?}", l.errors);
    assert_eq!(l.assigns.len(), 2);
    assert_eq!(l.words.len(), 3);
    assert_eq!(l.comments, vec!["debug, hi #1".to_string(), "rest".into()]);
    let o = parse_line("o<my sub> call [1] [2+3]", NGC);
    let os = o.oword.unwrap_or(OStmt {
        label: String::new(),
        kind: OKind::Do,
        args: vec![],
    });
    assert_eq!(
        (os.label.as_str(), os.kind, os.args.len()),
        ("mysub", OKind::Call, 2)
    );
    let w = parse_line("O0100 WHILE [#1 LT 3]", NGC);
    assert_eq!(
        w.oword.map(|o| (o.label, o.kind)),
        Some(("100".into(), OKind::While))
    );
    let g = parse_line("G1 X#1", Syntax { ngc: false, ..NGC });
    assert_eq!(g.errors[0].id, "unsupported-code");
}

/// `Neg(Num(v))` as `Num(-v)`: the one difference in form the fast path may make.
fn norm(mut l: Line) -> Line {
    for w in &mut l.words {
        if let Expr::Neg(e) = &w.value
            && let Expr::Num(v) = **e
        {
            w.value = Expr::Num(-v);
        }
    }
    l
}

const DIALECTS: [Syntax; 3] = [
    NGC,
    Syntax {
        ngc: false,
        checksums: true,
        dollar: false,
    },
    Syntax {
        ngc: false,
        checksums: false,
        dollar: true,
    },
];

#[test]
fn fast_path_takes_cam_lines() {
    for line in [
        "G1 X-1.5 Y2. Z+.25 F1500",
        "n10 g2 x 1 y 2 i.5 j0 (arc) ; done",
        "G0X1Y2",
        "M3 S1000 (spindle on)",
    ] {
        let mut l = Line::default();
        assert!(parse_simple(line.as_bytes(), NGC, &mut l), "{line}");
        assert_eq!(norm(l), norm(parse_line(line, NGC)), "{line}");
    }
    for line in [
        "#1=2",
        "G1 X[1+2]",
        "o100 sub",
        "%",
        "/G0 X1",
        "G1 X1.2.3",
        "G1 X",
    ] {
        let mut l = Line::default();
        assert!(!parse_simple(line.as_bytes(), NGC, &mut l), "{line}");
    }
}

/// The values and columns of a line's words, values as bits (−0.0 is not 0.0).
fn word_bits(l: &Line) -> Vec<(char, u64, usize)> {
    l.words
        .iter()
        .map(|w| match w.value {
            Expr::Num(v) => (w.letter, v.to_bits(), w.column),
            _ => (w.letter, u64::MAX, w.column),
        })
        .collect()
}

#[test]
fn plain_path_takes_cam_lines_and_leaves_the_rest() {
    for line in [
        "G1 X-1.5 Y2. Z+.25 F1500",
        "G0X1Y2",
        "g1 x0.1 y-0 e1.5e3",
        "G1 X1234567.89012345 Y0.30000000000000004",
        "",
        "   \t",
        "M3 S1000 (on)",
        "G1 X1 ; c",
        "G2 X1(a)Y2 ( b  )I0.5;  end ( of ) line ",
        "(only a comment)",
        "G1 X1 ()",
    ] {
        let mut l = Line::default();
        assert!(
            parse_plain(line.as_bytes(), NGC, &mut l.words, &mut l.comments),
            "{line}"
        );
        let mut s = Line::default();
        assert!(parse_simple(line.as_bytes(), NGC, &mut s), "{line}");
        assert_eq!(word_bits(&l), word_bits(&s), "{line}");
        assert_eq!(l.comments, s.comments, "{line}");
    }
    for line in [
        "G1 X 1",
        "G1 X1 2",
        "G1 X(c)1",
        "G1 X1 (open",
        "G1 X1 (é)",
        "G1 X1 ; é",
        "G1 X1.2.3",
        "G1 X",
        "o100 sub",
        "#1=2",
        "G1 X--1",
        "G1 X1é",
    ] {
        let mut l = Line::default();
        assert!(
            !parse_plain(line.as_bytes(), NGC, &mut l.words, &mut l.comments),
            "{line}"
        );
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2048))]
    /// Short decimals read by integer and power of ten are the f64 `str::parse` gives,
    /// bit for bit, across digit counts on both sides of the 15-digit bound.
    #[test]
    fn plain_numbers_are_correctly_rounded(
        int in "[0-9]{0,12}",
        frac in "[0-9]{0,12}",
        point in proptest::bool::ANY,
        sign in "[-+]?",
    ) {
        let text = if point || int.is_empty() {
            format!("{sign}{int}.{frac}")
        } else {
            format!("{sign}{int}")
        };
        let got = plain_number(text.as_bytes(), 0);
        let digits = int.len() + if point || int.is_empty() { frac.len() } else { 0 };
        if digits == 0 {
            proptest::prop_assert!(got.is_none());
        } else {
            let want: f64 = text.parse().map_err(|e| {
                proptest::test_runner::TestCaseError::fail(format!("{text}: {e}"))
            })?;
            let (v, end) = got.ok_or_else(|| {
                proptest::test_runner::TestCaseError::fail(text.clone())
            })?;
            proptest::prop_assert_eq!(v.to_bits(), want.to_bits(), "{}", text);
            proptest::prop_assert_eq!(end, text.len());
        }
    }

    /// Where the plain reader takes a line, it gives what the byte fast path gives.
    #[test]
    fn plain_matches_simple(
        line in "([GMXYZFSogx][-+]?[0-9]{0,9}(\\.[0-9]{0,9})?[ \t]{0,2}(\\([a-z ()]{0,5}\\)?)?){0,8}(;[ a-z(]{0,4})?",
        d in 0..3usize,
    ) {
        let syn = DIALECTS[d];
        let mut plain = Line::default();
        if parse_plain(line.as_bytes(), syn, &mut plain.words, &mut plain.comments) {
            let mut simple = Line::default();
            proptest::prop_assert!(parse_simple(line.as_bytes(), syn, &mut simple));
            proptest::prop_assert_eq!(word_bits(&plain), word_bits(&simple));
            proptest::prop_assert_eq!(plain.comments, simple.comments);
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
    /// The reused-buffer reader gives what the general parser gives, on lines mixing
    /// words, blanks, comments and stray characters.
    #[test]
    fn parse_line_into_matches_parse_line(
        line in "([GMXYZIJKFSNOgxyoe@#*%/$\\[ \\t]{0,2}[-+]{0,2}[0-9]{0,4}(\\.[0-9]{0,3})?\\.?[ \\t]?(\\([a-z ]{0,4}\\)?)?(;c)?){0,10}",
        d in 0..3usize,
    ) {
        let syn = DIALECTS[d];
        let mut fast = Line::default();
        // Stale content from a previous line must not leak into the next: more words
        // than most lines here, one of them an expression (the plain path overwrites
        // words in place).
        parse_line_into("G1 X[1+#2] Y3 Z4 F5 S6 M7 (old) ; old", syn, &mut fast);
        parse_line_into(&line, syn, &mut fast);
        proptest::prop_assert_eq!(norm(fast), norm(parse_line(&line, syn)));
    }
}

/// [`plain_words`] takes a line of up to [`PLAIN_MAX`] bytes, a trailing `\r` not counted,
/// whether a `\n` and more text follow or the text ends there, as [`parse_plain`] takes
/// the line cut out.
#[test]
fn plain_words_take_lines_up_to_the_longest_plain_line() {
    for len in PLAIN_MAX - 2..PLAIN_MAX + 3 {
        // `G1` and blanks: one word whatever the length.
        let line = format!("G1{}", " ".repeat(len - 2));
        let mut cut = Line::default();
        let plain = parse_plain(line.as_bytes(), NGC, &mut cut.words, &mut cut.comments);
        assert_eq!(plain, len <= PLAIN_MAX, "{len}");
        for cr in ["", "\r"] {
            for after in ["", "\n", "\nG0 X1"] {
                let text = format!("{line}{cr}{after}");
                let mut n = 0;
                let end = plain_words(text.as_bytes(), NGC, |_, _| {
                    n += 1;
                    true
                });
                let want = plain.then_some(len + cr.len());
                assert_eq!(end, want, "{len} {cr:?} {after:?}");
                assert_eq!(n, 1, "{len} {cr:?} {after:?}");
            }
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(1024))]
    /// [`plain_words`] reads the line a text starts with up to its `\n` (or the text's end)
    /// as [`parse_plain`] reads that line cut out (a trailing `\r` dropped): the same words
    /// bit for bit, the line's length where it takes the line, and None where it does not
    /// (lines over [`PLAIN_MAX`] among them, a trailing `\r` not counted) or the line
    /// has a comment. The text after the `\n` is never read.
    #[test]
    fn plain_words_read_to_the_line_end(
        words in "([GXYZFSgoM][-+]?[0-9]{0,9}(\\.[0-9]{0,9})?[ \t\r]{0,2}){0,12}",
        cr in "\r{0,2}",
        comment in "(\\(c\\)|;c)?",
        after in proptest::option::of("[GX0-9 .\r\n(;]{0,12}"),
        d in 0..3usize,
    ) {
        let syn = DIALECTS[d];
        let raw = format!("{words}{comment}{cr}");
        let text = match &after {
            Some(rest) => format!("{raw}\n{rest}"),
            None => raw.clone(),
        };
        let line = raw.strip_suffix('\r').unwrap_or(&raw);
        let mut want = Line::default();
        let plain = comment.is_empty()
            && parse_plain(line.as_bytes(), syn, &mut want.words, &mut want.comments);
        let mut got = Vec::new();
        let end = plain_words(text.as_bytes(), syn, |c, v| {
            got.push((c, v.to_bits()));
            true
        });
        if plain {
            proptest::prop_assert_eq!(end, Some(raw.len()), "{:?}", text);
            let want: Vec<(char, u64)> = word_bits(&want).iter().map(|w| (w.0, w.1)).collect();
            proptest::prop_assert_eq!(got, want, "{:?}", text);
        } else {
            proptest::prop_assert_eq!(end, None, "{:?}", text);
        }
    }
}
