//! Random RS274NGC expressions evaluate like a reference evaluator written here: a
//! recursive-descent parser over the same token list with LinuxCNC's precedence levels
//! (`**` > `* / MOD` > `+ -` > relational > logical, all left-associative). Deterministic:
//! proptest with a fixed seed.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use skinpath::sim::ngc::{self, ParamSource, Syntax};

#[derive(Clone, Debug)]
enum Tok {
    Num(f64),
    Op(&'static str),
}

const OPS: [&str; 15] = [
    "**", "*", "/", "MOD", "+", "-", "EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "XOR",
];

fn level(op: &str) -> u8 {
    match op {
        "**" => 6,
        "*" | "/" | "MOD" => 5,
        "+" | "-" => 4,
        "AND" | "OR" | "XOR" => 2,
        _ => 3,
    }
}

fn apply(op: &str, a: f64, b: f64) -> Option<f64> {
    let t = |c: bool| if c { 1.0 } else { 0.0 };
    Some(match op {
        "**" => {
            if (a < 0.0 && b.fract() != 0.0) || (a == 0.0 && b < 0.0) {
                return None;
            }
            a.powf(b)
        }
        "*" => a * b,
        "/" => {
            if b == 0.0 {
                return None;
            }
            a / b
        }
        "MOD" => {
            if b == 0.0 {
                return None;
            }
            let m = a - b * (a / b).trunc();
            if m < 0.0 { m + b.abs() } else { m }
        }
        "+" => a + b,
        "-" => a - b,
        "EQ" => t((a - b).abs() < 1e-4),
        "NE" => t((a - b).abs() >= 1e-4),
        "GT" => t(a > b),
        "GE" => t(a >= b),
        "LT" => t(a < b),
        "LE" => t(a <= b),
        "AND" => t(a != 0.0 && b != 0.0),
        "OR" => t(a != 0.0 || b != 0.0),
        _ => t((a != 0.0) != (b != 0.0)),
    })
}

/// Precedence climbing: parse operands of level ≥ `min` left to right.
fn reference(toks: &[Tok], pos: &mut usize, min: u8) -> Option<f64> {
    let Tok::Num(mut lhs) = toks[*pos] else {
        return None;
    };
    *pos += 1;
    while let Some(Tok::Op(op)) = toks.get(*pos) {
        let l = level(op);
        if l < min {
            break;
        }
        *pos += 1;
        let rhs = reference(toks, pos, l + 1)?;
        lhs = apply(op, lhs, rhs)?;
    }
    Some(lhs)
}

struct NoParams;
impl ParamSource for NoParams {
    fn numbered(&self, _: i64) -> f64 {
        0.0
    }
    fn named(&self, _: &str) -> Option<f64> {
        None
    }
}

fn expr_strategy() -> impl Strategy<Value = Vec<Tok>> {
    let num = (-20i32..20, 0u8..3)
        .prop_map(|(n, d)| Tok::Num(f64::from(n) / [1.0, 2.0, 4.0][d as usize]));
    let op = (0usize..OPS.len()).prop_map(|i| Tok::Op(OPS[i]));
    (num.clone(), proptest::collection::vec((op, num), 0..8)).prop_map(|(first, rest)| {
        let mut v = vec![first];
        for (o, n) in rest {
            v.push(o);
            v.push(n);
        }
        v
    })
}

fn text(toks: &[Tok]) -> String {
    let mut s = String::from("[");
    for t in toks {
        match t {
            // Negative numbers as [0 - n] would change precedence: LinuxCNC reads a leading
            // minus as part of the number, so write it inline.
            Tok::Num(v) => s += &format!("{v}"),
            Tok::Op(o) => s += &format!(" {o} "),
        }
    }
    s + "]"
}

#[test]
fn random_expressions_match_the_reference() {
    let cfg = Config {
        cases: 2000,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner =
        TestRunner::new_with_rng(cfg, TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]));
    let syn = Syntax {
        ngc: true,
        checksums: false,
        dollar: false,
    };
    runner
        .run(&expr_strategy(), |toks| {
            let src = format!("X{}", text(&toks));
            let line = ngc::parse_line(&src, syn);
            prop_assert!(line.errors.is_empty(), "{src}: {:?}", line.errors);
            let got = line.words[0].value.eval(&NoParams);
            let want = reference(&toks, &mut 0, 0);
            match (got, want) {
                (Ok(g), Some(w)) => {
                    let same = (g.is_nan() && w.is_nan())
                        || g == w
                        || (g - w).abs() <= 1e-9 * w.abs().max(1.0);
                    prop_assert!(same, "{src}: {g} vs {w}");
                }
                (Err(_), None) => {}
                (g, w) => prop_assert!(false, "{src}: {g:?} vs {w:?}"),
            }
            Ok(())
        })
        .expect("expressions agree with the reference evaluator");
}
