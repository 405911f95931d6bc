//! Fuzz target: RS274NGC control flow (issue #40) through `sim::check_text`. Programs are
//! built from a fixed seed (tests/support/fuzz.rs with the generator of tests/support/rng.rs): deep nesting of
//! `while`/`do`/`repeat`/`if`, subroutine calls and recursion, huge counts (repeat and
//! canned-cycle L, pecks, arc turns P), deeply nested and very long expressions; then
//! mutated as the other targets' seeds are. Every program must end with a report (a panic
//! is a crash; a stack overflow or an allocation failure aborts the test binary), and the
//! report must hold finite totals and at most the cap of findings per id.

use crate::support;
use skinpath::sim::{Backend, CheckConfig, Report, check_text};
use support::fuzz::{Rng, cases, fuzz, seed};

/// A loop budget small enough for hundreds of cases in a debug build; the counting is the
/// same as under the default budget.
const BUDGET: u64 = 5_000;

/// First O-word label number of a program's blocks.
const FIRST_LABEL: usize = 100;

/// Most control-flow blocks in one program: the nesting is deep, not wide (without a bound
/// the random branching would grow programs exponentially).
const MAX_BLOCKS: usize = 200;

/// Huge or degenerate counts for repeat, L, P and Q words.
const COUNTS: &[&str] = &[
    "0",
    "1",
    "3",
    "1000000000",
    "[10**300]",
    "0.0000001",
    "-5",
    "[2**31]",
    "1e9",
];

/// A value expression of nesting about `depth` (brackets, signs, # indirections) or a
/// flat run of `depth` terms.
fn expr(rng: &mut Rng, depth: usize) -> String {
    match rng.below(5) {
        0 => format!("{}1{}", "[".repeat(depth), "]".repeat(depth)),
        1 => format!("[{}2]", "-".repeat(depth)),
        2 => format!("{}1", "#".repeat(depth)),
        3 => {
            let op = *rng.pick(&["+", "*", "-", "/", " MOD "]);
            format!("[{}]", vec!["1"; depth.max(1)].join(op))
        }
        _ => format!("[SIN[{}]]", rng.below(360)),
    }
}

/// One statement of body text at nesting `level` with O-word labels from `label`.
fn statement(rng: &mut Rng, level: usize, label: &mut usize, out: &mut String) {
    let count = *rng.pick(COUNTS);
    let depth = *rng.pick(&[1usize, 8, 63, 64, 65, 500, 30_000]);
    match rng.below(9) {
        0 => out.push_str(&format!(
            "G1 X{} Y{} F100\n",
            expr(rng, depth),
            rng.below(50)
        )),
        1 => out.push_str(&format!("G81 X1 Y1 Z-1 R1 L{count}\n")),
        2 => out.push_str(&format!("G83 X2 Y2 Z-10 R1 Q{count}\n")),
        3 => out.push_str(&format!("G2 X0 Y0 I1 J0 P{count}\n")),
        4 => out.push_str(&format!("G18 G2 X0 Z0 I1 K0 P{count}\nG17\n")),
        5 => out.push_str(&format!("#1=[#1+{}]\n", expr(rng, depth.min(64)))),
        _ if level > 0 && *label < FIRST_LABEL + MAX_BLOCKS => {
            *label += 1;
            let l = *label;
            let mut body = String::new();
            for _ in 0..1 + rng.below(3) {
                statement(rng, level - 1, label, &mut body);
            }
            out.push_str(&match rng.below(4) {
                0 => format!("o{l} repeat [{count}]\n{body}o{l} endrepeat\n"),
                1 => format!("o{l} while [1]\n{body}o{l} endwhile\n"),
                2 => format!("o{l} do\n{body}o{l} while [#1 LT {count}]\n"),
                _ => format!("o{l} if [#1 GT 0]\n{body}o{l} else\n{body}o{l} endif\n"),
            });
        }
        _ => out.push_str("G0 X0 Y0 Z5\n"),
    }
}

/// A whole program: a recursive subroutine, then statements nested up to `levels`.
fn program(rng: &mut Rng, levels: usize) -> String {
    let mut s =
        String::from("G21 G90 F100 S1000 M3\no<rec> sub\no<rec> call [#1+1]\no<rec> endsub\n");
    let mut label = FIRST_LABEL;
    for _ in 0..1 + rng.below(4) {
        statement(rng, levels, &mut label, &mut s);
    }
    if rng.below(4) == 0 {
        s.push_str("o<rec> call [0]\n");
    }
    s.push_str("M5\nM2\n");
    s
}

/// The report is whole: finite totals, at most the cap of findings per id shown.
fn sound(r: &Report, cap: usize) -> bool {
    let s = &r.stats;
    let finite = [s.cut_length, s.rapid_length, s.time.total]
        .iter()
        .all(|v| v.is_finite());
    let mut ids: Vec<&str> = r.findings.iter().map(|f| f.id).collect();
    ids.sort_unstable();
    let most = ids
        .chunk_by(|a, b| a == b)
        .map(|c| c.len())
        .max()
        .unwrap_or(0);
    finite && most <= cap.max(1) && r.exit_code() <= 2
}

#[test]
fn fuzz_ngc_control_flow() {
    let cfg = CheckConfig {
        max_loop_iterations: BUDGET,
        ..CheckConfig::default()
    };
    let mut rng = Rng::new(seed("ngc-flow-programs"));
    // Nesting from flat to 60 levels (beyond LinuxCNC's own limits).
    let seeds: Vec<(String, String)> = (0..40)
        .map(|k| {
            let levels = *rng.pick(&[0usize, 2, 5, 12, 60]);
            (format!("generated-{k}"), program(&mut rng, levels))
        })
        .collect();
    let stats = fuzz("ngc-flow", &seeds, cases(150), |t| {
        let r = check_text(Backend::Builtin, t, &cfg, &[]);
        let _ = r.to_string();
        assert!(sound(&r, cfg.max_findings_per_check), "{r}");
        r.errors() == 0
    });
    assert!(stats.executions >= seeds.len());
}
