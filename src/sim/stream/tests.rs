//! The streaming route of `check`, and the piped route of the in-memory check (moves never
//! stored, see [`crate::sim::piped`]), give the report of the in-memory check of the stored
//! moves, finding for finding and bit for bit in the statistics: on every program of the sim corpus and the
//! golden G-code files (under each config and design the corpus gives), and on generated
//! programs with the cases that stress it (retraced and coincident contours, crossings
//! across tiles, arcs, dwells, pocket marks, loops, findings beyond the cap, odd bytes).
//! Each streamed check runs with the default tiles and with tiny ones, so that the contact
//! test is split over many tiles.

use super::check_stream_tiled;
use crate::sim::{
    self, Backend, CheckConfig, DesignBoundary, InterpOptions, KeepSide, MachineKind,
};
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// The config and design boundaries a corpus program names in its header comments:
/// `; config KEY = VALUE` lines (TOML of a [`CheckConfig`]) and `; design SIDE x,y x,y …`
/// lines (a boundary kept `outside`, `inside` or either side).
fn corpus_header(src: &str) -> (CheckConfig, Vec<DesignBoundary>) {
    let mut toml_cfg = String::new();
    let mut design = Vec::new();
    for line in src.lines() {
        let Some(d) = line.trim().strip_prefix(';') else {
            continue;
        };
        let d = d.trim();
        if let Some(t) = d.strip_prefix("config ") {
            toml_cfg.push_str(t);
            toml_cfg.push('\n');
        } else if let Some(t) = d.strip_prefix("design ") {
            let (side, pts) = t.split_once(' ').expect("design side");
            let keep = match side {
                "outside" => KeepSide::Outside,
                "inside" => KeepSide::Inside,
                _ => KeepSide::Either,
            };
            let v: Vec<f64> = pts
                .split([' ', ','])
                .filter(|t| !t.is_empty())
                .map(|t| t.parse().unwrap_or_else(|_| panic!("bad number {t:?}")))
                .collect();
            let p: Vec<_> = v
                .chunks(2)
                .map(|q| crate::geom::DVec2::new(q[0], q[1]))
                .collect();
            design.push(DesignBoundary::new(&p, keep));
        }
    }
    (toml::from_str(&toml_cfg).expect("config lines"), design)
}

/// The report of the in-memory route on the stored moves ([`sim::check`] of
/// [`sim::load_with`]) as the CLI builds it (decode, check, the UTF-8 warning first), as
/// JSON.
fn in_memory(bytes: &[u8], cfg: &CheckConfig, design: &[DesignBoundary]) -> String {
    let (text, decode) = sim::decode(bytes);
    let opts = InterpOptions::default();
    let prog = sim::load_with(Backend::Builtin, &text, cfg, &opts);
    let mut r = sim::check(&prog, cfg, design);
    if r.usable {
        r.findings.splice(0..0, decode);
    }
    serde_json::to_string_pretty(&r).expect("json")
}

/// [`in_memory`] on the piped route ([`crate::sim::piped`]): the moves handed over `chunk`
/// at a time, to a thread of their own when `threaded`, the contour checks beside them
/// when `beside`.
fn piped(
    bytes: &[u8],
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    threaded: bool,
    chunk: usize,
    beside: bool,
) -> String {
    let (text, decode) = sim::decode(bytes);
    let opts = InterpOptions::default();
    let (mut r, _) =
        sim::piped::check_piped(&text, cfg, design, &opts, threaded, chunk, Some(beside));
    r.backend = Backend::Builtin.name();
    if r.usable {
        r.findings.splice(0..0, decode);
    }
    serde_json::to_string_pretty(&r).expect("json")
}

fn streamed(bytes: &[u8], cfg: &CheckConfig, design: &[DesignBoundary], tiles: u64) -> String {
    let _running = super::TEST_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    streamed_unlocked(bytes, cfg, design, tiles)
}

fn streamed_unlocked(
    bytes: &[u8],
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    tiles: u64,
) -> String {
    let opts = InterpOptions::default();
    let input = Box::new(Cursor::new(bytes.to_vec()));
    let (mut r, utf8) =
        check_stream_tiled(input, cfg, design, &opts, tiles).expect("streamed check");
    if r.usable {
        r.findings.splice(0..0, utf8);
    }
    serde_json::to_string_pretty(&r).expect("json")
}

/// The stored, piped and streamed routes give `name` the same report. The piped route is
/// run as [`sim::check_text_with`] runs it, and on a thread of its own with chunks of one
/// and of 7 moves, the contour checks on either side; the streamed one with tiles of every
/// size.
fn same_on_both_routes(name: &str, bytes: &[u8], cfg: &CheckConfig, design: &[DesignBoundary]) {
    let want = in_memory(bytes, cfg, design);
    let mut routes: Vec<(String, String)> = Vec::new();
    let (text, decode) = sim::decode(bytes);
    let mut r = sim::check_text_with(Backend::Builtin, &text, cfg, design, &Default::default());
    if r.usable {
        r.findings.splice(0..0, decode);
    }
    routes.push((
        "piped as check_text".into(),
        serde_json::to_string_pretty(&r).expect("json"),
    ));
    for (threaded, chunk, beside) in [(true, 1, true), (true, 7, false), (false, 3, true)] {
        routes.push((
            format!("piped, threaded {threaded}, chunks of {chunk}, contours beside {beside}"),
            piped(bytes, cfg, design, threaded, chunk, beside),
        ));
    }
    for tiles in [u64::MAX, 64, 1] {
        routes.push((
            format!("streamed, tiles of {tiles}"),
            streamed(bytes, cfg, design, tiles),
        ));
    }
    for (route, got) in routes {
        if got != want {
            let diff: Vec<String> = want
                .lines()
                .zip(got.lines())
                .filter(|(a, b)| a != b)
                .take(6)
                .map(|(a, b)| format!("  stored {a}\n  route  {b}"))
                .collect();
            panic!(
                "{name} ({route}): the routes differ\n{}\n--- stored moves:\n{want}\n--- {route}:\n{got}",
                diff.join("\n")
            );
        }
    }
}

fn files(dir: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("nc" | "gcode")))
        .collect();
    v.sort();
    v
}

#[test]
fn corpus_and_golden_programs_agree() {
    let corpus = files("tests/sim_corpus");
    assert!(corpus.len() >= 14);
    for p in &corpus {
        let bytes = std::fs::read(p).expect("read");
        let (cfg, design) = corpus_header(&String::from_utf8_lossy(&bytes));
        same_on_both_routes(&p.display().to_string(), &bytes, &cfg, &design);
        // Also as a router and with crossings allowed: other checks fire.
        let router = CheckConfig {
            kind: MachineKind::Router,
            ..cfg.clone()
        };
        same_on_both_routes(&p.display().to_string(), &bytes, &router, &design);
    }
    let golden = files("tests/golden");
    assert!(!golden.is_empty());
    for p in &golden {
        let bytes = std::fs::read(p).expect("read");
        let name = p.display().to_string();
        let cfg = CheckConfig {
            kind: if name.contains("router") {
                MachineKind::Router
            } else {
                MachineKind::Laser
            },
            ..CheckConfig::default()
        };
        same_on_both_routes(&name, &bytes, &cfg, &[]);
    }
}

/// A square of side `s` at (`x`, `y`) cut `passes` times without switching off.
fn square(x: f64, y: f64, s: f64, passes: usize) -> String {
    let mut g = format!("G0 X{x:.3} Y{y:.3}\nM4 S500\n");
    for _ in 0..passes {
        g += &format!(
            "G1 X{:.3} Y{y:.3}\nG1 X{:.3} Y{:.3}\nG1 X{x:.3} Y{:.3}\nG1 X{x:.3} Y{y:.3}\n",
            x + s,
            x + s,
            y + s,
            y + s
        );
    }
    g + "M5\n"
}

#[test]
fn generated_programs_agree() {
    let cfg = CheckConfig::default();
    let head = "G21 G90 G17 F1000\n";
    let mut cases: Vec<(&str, String)> = Vec::new();
    // Coincident contours: 300 copies of a square, and a line crossing them all.
    let mut s = head.to_string();
    for _ in 0..300 {
        s += &square(10.0, 10.0, 5.0, 1);
    }
    s += "G0 X12 Y5\nM4 S500\nG1 X12 Y20\nM5\nM2\n";
    cases.push(("coincident", s));
    // One contour retraced 300 times (self-touches beyond the cap).
    cases.push((
        "retraced",
        format!("{head}{}M2\n", square(20.0, 20.0, 4.0, 300)),
    ));
    // A grid of squares, every fourth one crossed by a long diagonal: contacts in many tiles.
    let mut s = head.to_string();
    for i in 0..20 {
        for j in 0..20 {
            s += &square(5.0 + 3.0 * i as f64, 5.0 + 3.0 * j as f64, 2.0, 1);
        }
    }
    s += "G0 X4 Y4.5\nM4 S500\nG1 X66 Y66.5\nG1 X4 Y66\nG1 X66 Y4\nM5\nM2\n";
    cases.push(("grid-crossed", s));
    // Arcs, a figure eight, dwells, pocket marks, a fold back, laser on rapids, feeds out
    // of range, a move out of bounds and no program end.
    cases.push((
        "mixed",
        format!(
            "{head}G0 X50 Y50\nM3 S300\nG2 X50 Y50 I5 J0\nG4 P0.5\nG3 X60 Y50 R5\n\
             G1 X70 Y60\nG1 X60 Y60\nG1 X70 Y50\nG1 X65 Y50\nG1 X75 Y50\nG1 X70 Y50\n\
             (skinpath:group 3)\nG1 X80 Y80\nG1 X80 Y90\n(skinpath:group none)\n\
             G0 X90 Y90\nG1 X100 Y95 F90000\nG1 X400 Y95\nM5\nG0 X0 Y0\n"
        ),
    ));
    // Router passes at several depths, plunges, helices.
    let mut s = "G21 G90 G17 F600 S12000 M3\nG0 Z5\n".to_string();
    for d in 1..=4 {
        s += &format!(
            "G0 X10 Y10\nG1 Z-{d}\nG1 X30 Y10\nG1 X30 Y30\nG1 X10 Y30\nG1 X10 Y10\n\
             G2 X10 Y10 Z-{d}.5 I5 J5\nG0 Z5\n"
        );
    }
    s += "G0 X20 Y20 Z-1\nM5\nM30\n";
    cases.push(("router", s));
    // O-word loops and a subroutine (backward jumps in the streamed text).
    cases.push((
        "owords",
        format!(
            "{head}o100 sub\nG1 X[#1] Y[#1]\nG1 X[#1+5] Y[#1]\no100 endsub\n#2=0\n\
             o101 while [#2 LT 30]\nG0 X[#2] Y0\nM4 S400\no100 call [#2]\nM5\n#2=[#2+1]\n\
             o101 endwhile\no102 repeat [5]\nG0 X1 Y1\no102 endrepeat\nM2\n"
        ),
    ));
    // Pocket marks read again in a loop, and out of line order in a subroutine called
    // after the moves below it: the piped route checks the stored program instead.
    cases.push((
        "marks-in-loops",
        format!(
            "{head}#1=0\no5 while [#1 LT 3]\n(skinpath:group 2)\nG0 X[#1*10] Y0\nM4 S400\n\
             G1 X[#1*10+5] Y0\nG1 X[#1*10+5] Y5\nG1 X[#1*10] Y-1\nM5\n(skinpath:group none)\n\
             #1=[#1+1]\no5 endwhile\nM2\n"
        ),
    ));
    cases.push((
        "marks-in-a-subroutine",
        format!(
            "{head}o9 sub\n(skinpath:group 4)\nG0 X0 Y10\nM4 S400\nG1 X10 Y0\nM5\no9 endsub\n\
             G0 X0 Y0\nM4 S400\nG1 X10 Y10\nM5\no9 call\n(skinpath:group none)\nM2\n"
        ),
    ));
    // Many lines between a loop's start and its end (seeking past checkpoints).
    let mut s = format!("{head}#1=0\no7 do\n");
    for k in 0..9000 {
        s += &format!("G0 X{} Y[#1]\n", k % 50);
    }
    s += "#1=[#1+1]\no7 while [#1 LT 3]\nM2\n";
    cases.push(("long-loop", s));
    for (name, src) in &cases {
        same_on_both_routes(name, src.as_bytes(), &cfg, &[]);
    }
    // Inch units, crossings allowed, a design with gouges, a cap of 3 findings.
    let inch = CheckConfig {
        units: sim::Units::Inch,
        work_max: [10.0, 10.0, 1.0],
        allow_crossings: true,
        tool_radius: 0.05,
        max_findings_per_check: 3,
        ..CheckConfig::default()
    };
    let design = vec![DesignBoundary::new(
        &[
            crate::geom::DVec2::new(11.0, 11.0),
            crate::geom::DVec2::new(14.0, 11.0),
            crate::geom::DVec2::new(14.0, 14.0),
            crate::geom::DVec2::new(11.0, 14.0),
        ],
        KeepSide::Outside,
    )];
    for (name, src) in &cases {
        same_on_both_routes(name, src.as_bytes(), &inch, &design);
    }
}

#[test]
fn odd_inputs_agree() {
    let cfg = CheckConfig::default();
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty", Vec::new()),
        ("blank", b"\n  \r\n\t\n".to_vec()),
        ("bom only", b"\xEF\xBB\xBF".to_vec()),
        ("nul", b"G0 X1\n\0\x01binary\0\n".to_vec()),
        (
            "bom and latin-1",
            b"\xEF\xBB\xBFG21 (caf\xE9)\nG0 X1\r\nM4 S1\nG1 X2 F100 (\xFF\xFE)\nM5\nM2".to_vec(),
        ),
        ("not g-code", b"hello world\nthis is text\n".to_vec()),
        ("no final newline", b"G0 X1\nM4 S100\nG1 X5 F500".to_vec()),
        ("after end", b"G0 X1\nM2\nG0 X5\n".to_vec()),
    ];
    for (name, bytes) in &cases {
        same_on_both_routes(name, bytes, &cfg, &[]);
    }
}

#[test]
fn temporary_files_are_removed() {
    let src = format!("G21 G90 F1000\n{}M2\n", square(1.0, 1.0, 1.0, 50));
    let prefix = format!(".skinpath-check-{}-", std::process::id());
    let count = || {
        std::fs::read_dir(std::env::temp_dir())
            .map(|d| {
                d.filter_map(|e| e.ok())
                    .filter(|e| e.file_name().to_string_lossy().starts_with(&prefix))
                    .count()
            })
            .unwrap_or(0)
    };
    let _running = super::TEST_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let r = streamed_unlocked(src.as_bytes(), &CheckConfig::default(), &[], 1);
    assert!(r.contains("self-intersection"), "{r}");
    assert_eq!(count(), 0);
}
