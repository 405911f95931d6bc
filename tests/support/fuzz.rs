//! A small seeded mutation fuzzer for the stable toolchain (cargo-fuzz needs nightly).
//!
//! Each target takes a seed corpus (the shipped examples, profiles and G-code corpus),
//! mutates it with the tests' seeded generator ([`super::rng::Rng`]) and feeds every mutant to the public
//! API under `catch_unwind`: a panic is a crash, reported with the input written to a file
//! for a regression test. CI runs a small bounded number of cases; set
//! `SKINPATH_FUZZ_CASES=N` for longer local runs and `SKINPATH_FUZZ_SEED=S` for other
//! mutants than CI's.
#![allow(dead_code)]

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use super::ROOT;

pub use super::rng::Rng;

/// Cases per target: `SKINPATH_FUZZ_CASES` or `default`.
pub fn cases(default: usize) -> usize {
    std::env::var("SKINPATH_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The generator seed: `SKINPATH_FUZZ_SEED` or a fixed one (CI is deterministic).
pub fn seed(target: &str) -> u64 {
    let base = std::env::var("SKINPATH_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED);
    target
        .bytes()
        .fold(base, |h, b| h.wrapping_mul(31).wrapping_add(u64::from(b)))
}

/// Tokens that tend to break parsers and numeric code.
const TOKENS: &[&str] = &[
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "nan",
    "inf",
    "-inf",
    "1e38",
    "1e-15",
    "4294967295",
    "18446744073709551615",
    "9223372036854775807",
    "-1",
    "[",
    "]",
    "{",
    "}",
    ",",
    "\"",
    "=",
    "\n",
    "[[stroke]]",
    "[[operation]]",
    "[[circles]]",
    "[[tools]]",
    "(",
    ")",
    ";",
    "%",
    "G0",
    "G1",
    "G2",
    "G3",
    "G20",
    "G21",
    "G90",
    "G91",
    "M3",
    "M4",
    "M5",
    "M2",
    "M30",
    "X",
    "Y",
    "Z",
    "I",
    "J",
    "R",
    "F",
    "S",
    "P",
    "1e9",
    "0.000001",
    "\u{feff}",
    "\u{00e9}",
    "true",
    "false",
    "[0.0, 0.0, 1.0]",
    "[1.0, 2.0, 3.0, 4.0]",
];

/// One random mutation of `text`, borrowing from `other` for splices.
pub fn mutate(rng: &mut Rng, text: &str, other: &str) -> String {
    let mut b: Vec<u8> = text.as_bytes().to_vec();
    let rounds = 1 + rng.below(4);
    for _ in 0..rounds {
        let n = b.len().max(1);
        match rng.below(7) {
            0 if !b.is_empty() => {
                // Replace a number-ish run with a token.
                let at = rng.below(b.len());
                let mut end = at;
                while end < b.len() && (b[end].is_ascii_alphanumeric() || b[end] == b'.') {
                    end += 1;
                }
                let t = rng.pick(TOKENS).as_bytes().to_vec();
                b.splice(at..end, t);
            }
            1 => {
                let at = rng.below(n).min(b.len());
                let t = rng.pick(TOKENS).as_bytes().to_vec();
                b.splice(at..at, t);
            }
            2 if !b.is_empty() => {
                let at = rng.below(b.len());
                let len = rng.below(16).min(b.len() - at);
                b.drain(at..at + len);
            }
            3 if !b.is_empty() => {
                let at = rng.below(b.len());
                b[at] ^= 1 << rng.below(8);
            }
            4 if !b.is_empty() => {
                // Duplicate a line range.
                let at = rng.below(b.len());
                let len = rng.below(200).min(b.len() - at);
                let piece = b[at..at + len].to_vec();
                let to = rng.below(b.len());
                b.splice(to..to, piece);
            }
            5 if !other.is_empty() => {
                let o = other.as_bytes();
                let at = rng.below(o.len());
                let len = rng.below(300).min(o.len() - at);
                let to = rng.below(n).min(b.len());
                b.splice(to..to, o[at..at + len].iter().copied());
            }
            _ => {
                // Scale a digit run by replacing one digit.
                if let Some(pos) = (0..b.len())
                    .map(|_| rng.below(n))
                    .find(|&i| i < b.len() && b[i].is_ascii_digit())
                {
                    b[pos] = b'0' + rng.below(10) as u8;
                }
            }
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}

/// What a fuzz run did.
#[derive(Debug, Default)]
pub struct Stats {
    pub executions: usize,
    pub accepted: usize,
    pub slowest: Duration,
}

/// Runs `f` on `input`, turning a panic into a test failure that names a file holding the
/// input. `f` returns whether the input was accepted (parsed/built without error).
pub fn run_one(target: &str, input: &str, stats: &mut Stats, f: impl FnOnce(&str) -> bool) {
    let start = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(|| f(input)));
    stats.executions += 1;
    stats.slowest = stats.slowest.max(start.elapsed());
    match r {
        Ok(true) => stats.accepted += 1,
        Ok(false) => {}
        Err(_) => {
            let dir = std::env::temp_dir().join("skinpath-fuzz-crashes");
            std::fs::create_dir_all(&dir).unwrap();
            let p = dir.join(format!("{target}-{}.txt", stats.executions));
            std::fs::write(&p, input).unwrap();
            panic!("{target}: crash on input saved to {}", p.display());
        }
    }
}

/// Files of `dir` (relative to the crate root) ending in one of `exts`, sorted.
pub fn corpus(dir: &str, exts: &[&str]) -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = std::fs::read_dir(format!("{ROOT}/{dir}"))
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| exts.contains(&e))
        })
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

/// Mutation fuzzing of `corpus` through `f` for `n` cases; returns the statistics.
pub fn fuzz(
    target: &str,
    corpus: &[(String, String)],
    n: usize,
    mut f: impl FnMut(&str) -> bool,
) -> Stats {
    let mut rng = Rng::new(seed(target));
    let mut stats = Stats::default();
    // The unmutated seeds first: they must not crash either.
    for (_, text) in corpus {
        run_one(target, text, &mut stats, &mut f);
    }
    for _ in 0..n {
        let (_, a) = rng.pick(corpus);
        let (_, b) = rng.pick(corpus);
        let m = mutate(&mut rng, a, b);
        run_one(target, &m, &mut stats, &mut f);
    }
    println!(
        "{target}: {} executions, {} accepted, slowest {:?}, 0 crashes",
        stats.executions, stats.accepted, stats.slowest
    );
    stats
}
