//! Unit tests of the interpreter.

use super::*;
use std::f64::consts::PI;

fn run(src: &str) -> Program {
    interpret(src, 0.005)
}

fn run_cfg(src: &str, cfg: &CheckConfig) -> Program {
    interpret_with(src, cfg, &Options { load_sub: None })
}

/// [`interpret_with`] without the plain block route: every block goes through
/// `collect` and `execute`.
fn run_general(src: &str, cfg: &CheckConfig) -> Program {
    let opts = Options { load_sub: None };
    let mut it = new_interp(cfg, &opts);
    it.plain_moves = false;
    it.add_source("program".into(), Cow::Borrowed(src));
    it.run(None);
    it.prog.final_tool = it.st.tool;
    it.prog
}

/// Line ends mixed into the programs the plain route is tested on: CRLF, an empty line, a
/// comment after the words (the plain route refuses the line only where it meets it), a
/// `\r` left inside the line (CR CR LF).
const LINE_ENDS: [&str; 7] = ["\n", "\n", "\r\n", "\n\n", " ; c\n", " (c)\n", "\r\r\n"];

/// Lines the plain route takes or must refuse, mixed with the modal state they depend on.
const PLAIN_MIX: [&str; 42] = [
    "N10 G1 X1 Y1",
    "N20 N30 X2",
    "N5",
    "G0 X1 Y2",
    "G1 X3.5 Y-1 F1200",
    "X2 Y2",
    "Y0.25",
    "Z-1",
    "G1 Z0 F-5",
    "G1 X1 X2",
    "G0 G1 X4",
    "F300",
    "G1",
    "G01 X0.5",
    "G91",
    "G90",
    "G20",
    "G21",
    "G93",
    "G94",
    "G95",
    "G2 X1 Y0 I0.5 J0",
    "M3 S100",
    "M5",
    "G7",
    "G8",
    "G53 G0 X1",
    "G92 X0 Y0",
    "G92.1",
    "G80",
    "G81 X1 Y1 Z-1 R1",
    "G55",
    "G54",
    "X1 I2",
    "G1 X2 (c)",
    "G1 X1 Y2 S500",
    "X3 S0",
    "G0 X1 S-5",
    "S250",
    "M4",
    "G1 X2 S12.5 S3",
    "M3",
];

/// [`tenths`] by its definition with `f64::round`.
fn tenths_by_round(v: f64) -> Option<i64> {
    let t = (v * 10.0).round();
    ((v * 10.0 - t).abs() < 1e-6 && t.abs() < 1e9 && t >= 0.0).then_some(t as i64)
}

#[test]
fn tenths_match_rounding_at_the_edges() {
    let edges = [
        0.0,
        -0.0,
        0.1,
        90.1,
        38.2,
        1.0,
        -0.04,
        -0.05,
        -0.049999999,
        0.05,
        0.0499999999,
        99_999_999.9,
        99_999_999.95,
        99_999_999.94,
        1e8,
        2.5e15,
        1e300,
        -1.0,
        0.30000001,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MIN_POSITIVE,
        4503599627370495.5,
    ];
    for v in edges {
        assert_eq!(tenths(v), tenths_by_round(v), "{v:e}");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4096))]
    #[test]
    fn tenths_match_rounding(code in 0u32..2000, off in -1e-5f64..1e-5, any in proptest::num::f64::ANY) {
        let v = f64::from(code) / 10.0 + off;
        proptest::prop_assert_eq!(tenths(v), tenths_by_round(v));
        proptest::prop_assert_eq!(tenths(any), tenths_by_round(any));
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]
    /// The plain block route gives the program the general route gives: moves, state,
    /// words, findings, end, bit for bit.
    #[test]
    fn plain_blocks_match_the_general_route(
        picks in proptest::collection::vec(0usize..PLAIN_MIX.len(), 1..40),
        values in proptest::collection::vec(-50i32..50, 40),
        ends in proptest::collection::vec(0usize..LINE_ENDS.len(), 40),
        last in 0usize..3,
        d in 0usize..5,
    ) {
        let mut src = String::new();
        for (k, &p) in picks.iter().enumerate() {
            // Vary the numbers: every digit string a value of `values`.
            let v = f64::from(values[k % values.len()]) / 8.0;
            src += &PLAIN_MIX[p].replace("0.5", &format!("{v}"));
            src += LINE_ENDS[ends[k % ends.len()]];
        }
        // The end: M2 and a line feed, M2 as the text's last line, or no M2.
        src += ["M2\n", "M2", ""][last];
        let dialect = [
            Dialect::Generic,
            Dialect::Linuxcnc,
            Dialect::Grbl,
            Dialect::Marlin,
            Dialect::Smoothie,
        ][d];
        let cfg = CheckConfig {
            dialect,
            ..CheckConfig::default()
        };
        let fast = run_cfg(&src, &cfg);
        let general = run_general(&src, &cfg);
        proptest::prop_assert_eq!(format!("{fast:?}"), format!("{general:?}"), "{:?}", src);
        // The lines are the pieces of `split('\n')` without a trailing `\r`: the text
        // rejoined with bare line feeds is the same program.
        let lf: Vec<&str> = src.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l)).collect();
        let lf = run_cfg(&lf.join("\n"), &cfg);
        proptest::prop_assert_eq!(format!("{fast:?}"), format!("{lf:?}"), "{:?}", src);
    }
}

/// Plain lines read straight from the text ([`Interp::plain_text`]) only where they are read
/// for the first time: the program is the general route's across jumps and calls.
#[test]
fn plain_text_route_follows_jumps_and_calls() {
    // A subroutine called in a loop (its lines met again come from the cache), if/else
    // jumping forward over thousands of lines, errors, comments, CRLF, empty and
    // whitespace-only lines, and lines after the end.
    let chunk = 2048;
    let mut src = String::from("o100 sub\nG1 X#1 Y[#1*2] F600\nG2 X0 Y0 I1 J1\no100 endsub\n");
    src += "#5 = 0\no200 while [#5 LT 3]\no100 call [#5 + 1]\n#5 = [#5 + 1]\no200 endwhile\n";
    src += "o300 if [#5 GT 10]\n";
    for k in 0..2 * chunk {
        src += &format!("G1 X{k} Y1 (skipped)\n");
    }
    src += "o300 else\n";
    for k in 0..3 * chunk {
        src += &match k % 6 {
            0 => format!("G1 X{}.5 Y-{k}\r\n", k % 97),
            1 if k % 4 == 1 => "\n".to_string(),
            // Whitespace only (no words: skipped), and a no-break space, which
            // `str::trim` takes as whitespace too.
            1 => " \t\u{a0}\r\n".to_string(),
            2 => format!("G0 Z{} ; lift\n", k % 5),
            3 => "G1 Q7 X1\n".to_string(),
            4 => format!("#7 = [#7 + {k}]\n"),
            _ => format!("N{k} G3 X{} Y0 R40\n", k % 31),
        };
    }
    src += "o300 endif\no100 call [2]\nM2\nG1 X5\n";
    for dialect in [Dialect::Linuxcnc, Dialect::Grbl] {
        let cfg = CheckConfig {
            dialect,
            ..CheckConfig::default()
        };
        let fast = run_cfg(&src, &cfg);
        let general = run_general(&src, &cfg);
        assert!(general.motions.len() > chunk, "{dialect:?}");
        assert_eq!(format!("{fast:?}"), format!("{general:?}"), "{dialect:?}");
    }
}

fn ids(p: &Program) -> Vec<(&'static str, usize)> {
    p.diagnostics
        .iter()
        .filter(|d| d.severity != Severity::Info)
        .map(|d| (d.id, d.lines.first().copied().unwrap_or(0)))
        .collect()
}

fn end(p: &Program) -> DVec3 {
    p.motions.last().map(|m| m.to).unwrap_or(DVec3::NAN)
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn modal_lines_inch_relative() {
    let p = run("G20 G91\nG1 X1 Y1 F10\nX1\nG90 G0 X0 Y0\nM2");
    assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
    assert_eq!(p.motions.len(), 3);
    let m = &p.motions.to_vec()[1];
    assert!(close(m.to, DVec3::new(50.8, 25.4, 0.0)));
    assert_eq!(m.line, 3);
    assert!((m.feed - 254.0).abs() < 1e-12);
    assert_eq!(p.motions.to_vec()[2].kind, MotionKind::Rapid);
    assert_eq!(p.end.map(|e| e.line), Some(5));
}

#[test]
fn arcs_ij_r_and_full_circle() {
    let p = run("G0 X10 Y0\nG3 X0 Y10 I-10 J0 F100\nG2 X0 Y10 I0 J-10");
    assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
    let q = p.motions.to_vec()[1]
        .arc
        .unwrap_or(Arc::new(DVec2::ZERO, 0.0, 0.0, 0.0));
    assert!((q.sweep - PI / 2.0).abs() < 1e-12);
    let c = p.motions.to_vec()[2].arc.unwrap_or(q);
    assert!((c.sweep + 2.0 * PI).abs() < 1e-12);
    for (code, r, sweep) in [("G3", 10.0, PI / 2.0), ("G2", -10.0, -1.5 * PI)] {
        let p = run(&format!("G0 X10 Y0\n{code} X0 Y10 R{r} F50"));
        let a = p.motions.to_vec()[1].arc.unwrap_or(q);
        assert!((a.sweep - sweep).abs() < 1e-9, "{code} R{r}: {}", a.sweep);
    }
    // The planted arc: end radius 15 against start radius 5.
    let bad = run("G21 G90 G90.1\nG0 X10 Y0\nG2 X20 Y0 I5 J0 F100\nM2");
    assert_eq!(ids(&bad), vec![("invalid-arc", 3)]);
}

#[test]
fn arcs_in_xz_and_yz_planes_are_chords_of_the_true_arc() {
    // G18 half circle of radius 5 from (0,0,0) to (10,0,0) about (5,0,0): length 5π.
    let p = run("G18 G1 F100\nG2 X10 Z0 I5 K0\nG19 G3 Y10 Z0 J5 K0");
    assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
    let len: f64 = p.motions.iter().map(|m| m.length()).sum();
    assert!((len - 10.0 * PI).abs() / (10.0 * PI) < 1e-4, "{len}");
    let zmax = p.motions.iter().map(|m| m.to.z).fold(f64::MIN, f64::max);
    let zmin = p.motions.iter().map(|m| m.to.z).fold(f64::MAX, f64::min);
    // Both go through -Z: G18 G2 is clockwise in the (Z, X) frame rs274's ARC_FEED uses,
    // G19 G3 counter-clockwise in (Y, Z).
    assert!(
        zmax.abs() < 1e-12 && (zmin + 5.0).abs() < 1e-3,
        "{zmax} {zmin}"
    );
}

#[test]
fn parameters_are_assigned_after_the_block_reads_them() {
    let p = run("#1 = 5\n#1 = 6 G0 X#1\nY#1\n#<len> = [#1 * 2] Z#<len>");
    assert_eq!(ids(&p), vec![("expression", 4)]);
    assert!(close(p.motions.to_vec()[1].to, DVec3::new(5.0, 6.0, 0.0)));
    // #<_x> is read before the block moves: Z gets the X of the line before.
    let q = run("#<len> = 3\nG0 X[#<len> * 2] Y[2 ** 3] Z#<_x>\nG0 Z#<_x>");
    assert!(close(end(&q), DVec3::new(6.0, 8.0, 6.0)), "{:?}", end(&q));
}

#[test]
fn subroutines_with_arguments_and_return_values() {
    let src = "o<sq> sub\n  G1 X[#1 * #1] F100\n  o<sq> return [#1 + 1]\no<sq> endsub\n\
               o<sq> call [3]\nG0 Y#<_value>\no100 sub\n#<local> = 7\no100 endsub\n\
               o100 call\no101 if [EXISTS[#<local>]]\nG0 Z99\no101 else\nG0 Z1\no101 endif\nM2";
    let p = run(src);
    assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
    assert!(close(p.motions.to_vec()[0].to, DVec3::new(9.0, 0.0, 0.0)));
    // Moves inside a call carry the caller's line.
    assert_eq!(p.motions.to_vec()[0].line, 5);
    assert!(close(end(&p), DVec3::new(9.0, 4.0, 1.0)), "{:?}", end(&p));
}

#[test]
fn loops_if_elseif_break_continue() {
    let src = "#1 = 0\no1 while [#1 LT 5]\n#1 = [#1 + 1]\no2 if [#1 EQ 2]\no1 continue\n\
               o2 elseif [#1 EQ 4]\no1 break\no2 else\nG1 X#1 F10\no2 endif\no1 endwhile\n\
               #2 = 0\no3 do\n#2 = [#2 + 1]\no3 while [#2 LT 3]\nG1 Y#2\n\
               o4 repeat [4]\nG91 G1 Z1\no4 endrepeat\nG90\nM2";
    let p = run(src);
    assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
    let xs: Vec<f64> = p.motions.iter().map(|m| m.to.x).collect();
    assert_eq!(&xs[..2], &[1.0, 3.0]);
    assert!(close(end(&p), DVec3::new(3.0, 3.0, 4.0)), "{:?}", end(&p));
}

#[test]
fn runaway_loops_and_recursion_stop_with_clear_errors() {
    // The default budget (one million iterations) against a 10M-iteration while.
    let cfg = CheckConfig::default();
    let p = run_cfg(
        "#1 = 0\no1 while [#1 LT 10000000]\n#1 = [#1 + 1]\no1 endwhile\nG0 X1\nM2",
        &cfg,
    );
    assert_eq!(ids(&p), vec![("loop-limit", 4)]);
    assert!(p.diagnostics[0].message.contains("1000000 iterations"));
    assert!(p.motions.is_empty());
    let r = run("o<r> sub\no<r> call\no<r> endsub\no<r> call\nM2");
    assert_eq!(ids(&r)[0].0, "call-depth");
    assert!(r.diagnostics[0].message.contains("10 subroutine levels"));
}

#[test]
fn modal_group_conflicts_are_errors() {
    for (src, col) in [
        ("G90 G91 X1", 5),
        ("G20 G21", 5),
        ("G0 G1 X1", 4),
        ("M3 M5", 4),
        ("M7 M9", 4),
        ("M9 M7", 4),
        ("M9 M8", 4),
    ] {
        let p = run(src);
        assert_eq!(ids(&p), vec![("modal-conflict", 1)], "{src}");
        assert_eq!(p.diagnostics[0].column, Some(col), "{src}");
    }
}

#[test]
fn mist_and_flood_share_a_block() {
    for src in ["M7 M8", "M8 M7"] {
        assert!(ids(&run(src)).is_empty(), "{src}");
    }
}

#[test]
fn nothing_after_the_end_is_interpreted() {
    let p = run("%\nG0 X1\n%\nG0 X2 #\nnot gcode at all");
    assert_eq!(ids(&p), vec![("after-program-end", 4)]);
    assert!(close(end(&p), DVec3::new(1.0, 0.0, 0.0)));
    assert_eq!(p.end.map(|e| e.line), Some(3));
    let q = run("G0 X1\nM2\nthis is ignored (\n");
    assert_eq!(ids(&q), vec![("after-program-end", 3)]);
}

#[test]
fn offsets_coordinate_systems_and_home() {
    let src = "G10 L2 P2 X100 Y50\nG55 G0 X1 Y1\nG92 X0 Y0\nG0 X1\nG92.1\nG53 G0 X5 Y5\n\
               G28.1\nG54 G0 X0 Y0\nG28\nG43.1 Z-2\nG0 Z0\nG49 G0 Z0";
    let p = run(src);
    assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
    let to: Vec<DVec3> = p.motions.iter().map(|m| m.to).collect();
    assert!(close(to[0], DVec3::new(101.0, 51.0, 0.0)));
    assert!(close(to[1], DVec3::new(102.0, 51.0, 0.0)));
    assert!(close(to[2], DVec3::new(5.0, 5.0, 0.0)));
    assert!(close(to[3], DVec3::new(0.0, 0.0, 0.0)));
    assert!(close(to[4], DVec3::new(5.0, 5.0, 0.0)));
    assert!(close(to[5], DVec3::new(5.0, 5.0, -2.0)));
    assert!(close(to[6], DVec3::new(5.0, 5.0, 0.0)));
}

#[test]
fn canned_cycles_expand_like_rs274() {
    // rs274 2.9 output for this program (G99 is its start-up mode): see
    // tests/rs274_conformance.rs for the full comparison.
    let p = run("G20 G90 G0 X0 Y0 Z0.3\nG81 X1 R.1 Z-.5 F60\nX2\nG91 X1 R.1 Z-.5 L2\nG80");
    assert!(ids(&p).is_empty(), "{:?}", p.diagnostics);
    let feeds: Vec<DVec3> = p
        .motions
        .iter()
        .filter(|m| m.kind == MotionKind::Feed)
        .map(|m| m.to / 25.4)
        .collect();
    let want = [
        DVec3::new(1.0, 0.0, -0.5),
        DVec3::new(2.0, 0.0, -0.5),
        DVec3::new(3.0, 0.0, -0.1),
        DVec3::new(4.0, 0.0, -0.1),
    ];
    assert_eq!(feeds.len(), 4);
    for (a, b) in feeds.iter().zip(want) {
        assert!(close(*a, b), "{a:?} vs {b:?}");
    }
    let q = run("G0 Z5\nG98 G83 X1 Y1 Z-3 R1 Q1.2 F100\nG80");
    let qf: Vec<f64> = q
        .motions
        .iter()
        .filter(|m| m.kind == MotionKind::Feed)
        .map(|m| m.to.z)
        .collect();
    assert_eq!(qf.len(), 4);
    assert!((qf[3] + 3.0).abs() < 1e-12 && (end(&q).z - 5.0).abs() < 1e-12);
}

#[test]
fn messages_events_group_hook_and_probing() {
    let src = "#1 = 2.5\n(debug, depth #1 name #<nope>)\nM8\nM64 P2\n(skinpath:group 3)\n\
               M3 S100\nG1 X1 F10\n(skinpath:group end)\nG1 X2\nG38.2 Z-5 F10\nG0 X3";
    let p = run(src);
    let info: Vec<&str> = p
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Info)
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(info, vec!["depth 2.500000 name ######"]);
    let codes: Vec<&str> = p.events.iter().map(|e| e.code.as_str()).collect();
    assert_eq!(codes, vec!["M8", "M64 P2"]);
    assert_eq!(p.motions.to_vec()[0].group, Some(3));
    assert_eq!(p.motions.to_vec()[1].group, None);
    assert_eq!(ids(&p), vec![("cannot-simulate", 10)]);
    assert_eq!(p.uncertain_from, Some(10));
}

#[test]
fn unsupported_codes_say_so_with_code_and_line() {
    let p = run("G1 X1 F10\nG76 X2\nM123\nG1 X2 E5 Q1");
    for d in &p.diagnostics {
        assert!(
            d.message.contains("not supported") || d.id == "unused-word",
            "{d}"
        );
    }
    assert!(p.diagnostics.iter().any(|d| d.message.contains("G76")));
    assert!(p.diagnostics.iter().any(|d| d.message.contains("M123")));
}

/// P on an arc is its number of turns (LinuxCNC G2/G3 P), used and not an unused word; GRBL
/// has no P on arcs and refuses it. A half turn then two full turns of radius 5: 5π·(1 + 4).
#[test]
fn arc_turns_word_is_used_where_the_dialect_has_it() {
    let src = "G21 G90 G17\nG0 X0 Y0\nG2 X10 Y0 I5 J0 P3 F600\nM2";
    for (dialect, unused) in [
        (Dialect::Linuxcnc, false),
        (Dialect::Generic, false),
        (Dialect::Grbl, true),
    ] {
        let cfg = CheckConfig {
            dialect,
            ..CheckConfig::default()
        };
        let p = run_cfg(src, &cfg);
        let flagged = p.diagnostics.iter().any(|d| d.id == "unused-word");
        assert_eq!(flagged, unused, "{dialect:?}: {:?}", p.diagnostics);
        let arc = (p.motions.to_vec().iter().find_map(|m| m.arc)).expect("an arc");
        assert!(
            (arc.sweep.abs() * arc.radius - 5.0 * PI * 5.0).abs() < 1e-9,
            "{dialect:?}"
        );
    }
}

#[test]
fn dialects() {
    let grbl = CheckConfig {
        dialect: Dialect::Grbl,
        ..CheckConfig::default()
    };
    let p = run_cfg(
        "$H\n$32=1\n#1=2\nG1 X[1+1] F10\nG81 X1 R1 Z-1\nG1 X1",
        &grbl,
    );
    assert_eq!(p.events.len(), 2);
    let un: Vec<usize> = p
        .diagnostics
        .iter()
        .filter(|d| d.id == "unsupported-code")
        .map(|d| d.lines[0])
        .collect();
    assert_eq!(un, vec![3, 4, 5]);
    let marlin = CheckConfig {
        dialect: Dialect::Marlin,
        ..CheckConfig::default()
    };
    let m = run_cfg("M3 I S100\nG1 X5 E2 F100 S50 ; cut\nG4 P500\nM5", &marlin);
    assert!(ids(&m).is_empty(), "{:?}", m.diagnostics);
    assert_eq!(m.motions.to_vec()[0].tool.s, 50.0);
    assert_eq!(
        m.motions.to_vec()[1].kind,
        MotionKind::Dwell { seconds: 0.5 }
    );
    // `M3 I1` after an arc (a second laser pass) is the inline flag, not a full circle
    // of radius 1; a bare I after an arc still is one.
    let src = "G0 X10 Y10\nM3 I1 S0\nG2 X10 Y10 I2 J0 F600 S50\nM5\nM3 I1 S0\n";
    let m = run_cfg(src, &marlin);
    assert_eq!(m.motions.len(), 2, "{:?}", m.motions.to_vec());
    let m = run_cfg(&format!("{src}I2\n"), &marlin);
    assert_eq!(m.motions.len(), 3);
}

#[test]
fn called_files_from_the_loader() {
    let load = |name: &str| -> Option<String> {
        (name == "lib").then(|| "o<lib> sub\nG0 X#1\no<lib> endsub\n".to_string())
    };
    let p = interpret_with(
        "o<lib> call [4]\no<nope> call\nM2",
        &CheckConfig::default(),
        &Options {
            load_sub: Some(&load),
        },
    );
    assert!(close(end(&p), DVec3::new(4.0, 0.0, 0.0)));
    assert_eq!(ids(&p), vec![("o-word", 2)]);
    assert!(p.diagnostics[0].message.contains("nope.ngc"));
}

/// Both layouts of [`source::LineStarts`] hold the line starts of `str::split('\n')`, and
/// the O-word pre-scan finds the lines holding an o.
#[test]
fn line_starts_narrow_and_wide_agree_with_split() {
    let text = "G1 X1\r\n\n(o-word o100)\nG0 Y2\n  \nlast";
    let lines: Vec<&str> = text.split('\n').collect();
    let mut begin = Vec::new();
    let mut at = 0usize;
    for l in &lines {
        begin.push(at);
        at += l.len() + 1;
    }
    let narrow = source::LineStarts::Narrow(begin.iter().map(|&b| b as u32).collect());
    let wide = source::LineStarts::Wide(begin.clone());
    assert!(matches!(
        source::LineStarts::of(text.as_bytes()),
        source::LineStarts::Narrow(ref v) if v.iter().map(|&b| b as usize).eq(begin.iter().copied())
    ));
    for starts in [&narrow, &wide] {
        assert_eq!(starts.len(), lines.len());
        for (i, &b) in begin.iter().enumerate() {
            assert_eq!(starts.get(i), Some(b));
        }
        assert_eq!(starts.get(lines.len()), None);
    }
    // The O-word pre-scan finds the one line holding an o (line 2), once.
    assert_eq!(source::lines_with_o(text), vec![(2, "(o-word o100)")]);
}

/// One read of a [`source::Source`] in a test sequence.
#[derive(Clone, Copy, Debug)]
enum Read {
    /// [`source::Source::line`].
    Line,
    /// [`source::Source::has_line`].
    Has,
    /// [`source::Source::has_comment`], then the line.
    Comment,
    /// The plain route: [`source::Source::text_from_line`], the line's end found by the caller,
    /// [`source::Source::record_read`], then the line.
    From,
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(1024))]
    /// An in-memory source gives line `i` as the `i`th piece of `str::split('\n')` without
    /// a trailing `\r`, and None past the last, whatever the order of the reads (in order,
    /// again, back, forward past unread lines), through every way the loop reads it; the
    /// O-word pre-scan finds the lines holding an o. Texts: empty, without a final `\n`,
    /// CRLF, lone `\r`, comments, multi-byte characters.
    #[test]
    fn in_memory_lines_are_the_pieces_of_split(
        text in "[\n\r(;oOG1 é]{0,40}",
        reads in proptest::collection::vec((0usize..4, proptest::bool::ANY, 0usize..16), 0..48),
        borrowed in proptest::bool::ANY,
    ) {
        let want: Vec<&str> = text
            .split('\n')
            .map(|l| l.strip_suffix('\r').unwrap_or(l))
            .collect();
        let with_o: Vec<(usize, &str)> = want
            .iter()
            .enumerate()
            .filter(|(_, l)| l.contains(['o', 'O']))
            .map(|(i, &l)| (i, l))
            .collect();
        proptest::prop_assert_eq!(source::lines_with_o(&text), with_o);
        let body = if borrowed {
            Cow::Borrowed(text.as_str())
        } else {
            Cow::Owned(text.clone())
        };
        let mut s = source::Source::new("t".into(), body);
        proptest::prop_assert_eq!(s.len(), want.len());
        let mut next = 0usize;
        for (kind, in_order, j) in reads {
            let i = if in_order { next } else { j };
            let read = [Read::Line, Read::Has, Read::Comment, Read::From][kind];
            let w = want.get(i).copied();
            match read {
                Read::Line => {}
                Read::Has => {
                    proptest::prop_assert_eq!(s.has_line(i), w.is_some(), "{:?} {}", text, i);
                    continue;
                }
                Read::Comment => {
                    let c = w.is_some_and(|l| l.contains(['(', ';']));
                    proptest::prop_assert_eq!(s.has_comment(i), c, "{:?} {}", text, i);
                }
                Read::From => match s.text_from_line(i) {
                    Some((start, rest)) => {
                        proptest::prop_assert!(borrowed);
                        proptest::prop_assert_eq!(rest, &text.as_bytes()[start..]);
                        let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
                        s.record_read(i, start, len);
                    }
                    None => proptest::prop_assert!(!borrowed || w.is_none()),
                },
            }
            proptest::prop_assert_eq!(s.line(i), w, "{:?} {} {:?}", text, i, read);
            next = i + 1;
        }
    }
}

/// Every program of the sim corpus (tests/sim_corpus) and a generated spiral of plain `G1`
/// lines (the shape `benches/check_vs_geos.py` checks) give, in every dialect, the same
/// program through the plain block route as through the general one: moves, state, words,
/// findings, end, bit for bit.
#[test]
fn plain_blocks_match_the_general_route_on_the_corpus() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sim_corpus");
    let mut programs: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("the corpus directory")
        .map(|e| e.expect("a corpus entry").path())
        .filter(|p| p.is_file())
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("a corpus program");
            (p.display().to_string(), text)
        })
        .collect();
    assert!(
        programs.len() >= 10,
        "corpus of {} programs",
        programs.len()
    );
    // Archimedean spiral r = 0.45 θ / 2π in 3-decimal words, as CAM writes it.
    let mut spiral = String::from("G21 G90 G17\nF1500 S800\nG0 X100.000 Y100.000\nM3\n");
    for k in 1..5000 {
        let t = f64::from(k) * 0.05;
        let r = 0.45 * t / TAU;
        let (x, y) = (100.0 + r * t.cos(), 100.0 + r * t.sin());
        spiral += &format!("G1 X{x:.3} Y{y:.3}\n");
    }
    spiral += "M5\nM2\n";
    programs.push(("spiral".into(), spiral));
    let mut plain_lines = 0;
    for (name, src) in &programs {
        for dialect in [
            Dialect::Generic,
            Dialect::Linuxcnc,
            Dialect::Grbl,
            Dialect::Marlin,
            Dialect::Smoothie,
        ] {
            let cfg = CheckConfig {
                dialect,
                ..CheckConfig::default()
            };
            let fast = run_cfg(src, &cfg);
            let general = run_general(src, &cfg);
            assert_eq!(
                format!("{fast:?}"),
                format!("{general:?}"),
                "{name} ({dialect:?})"
            );
        }
        plain_lines += src.lines().filter(|l| l.starts_with("G1 X")).count();
    }
    // The comparison covers the plain route, not only lines it refuses.
    assert!(plain_lines >= 4999, "{plain_lines} plain lines");
}
