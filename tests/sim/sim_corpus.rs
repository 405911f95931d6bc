//! Corpus tests for the simulation backend: every program under tests/sim_corpus/ carries
//! its expectations in `;` comments:
//!
//! - `; config <toml line>`: a line of the CheckConfig (TOML);
//! - `; design outside|inside|either x,y x,y ...`: a design boundary for the gouge check;
//! - `; expect finding <id> <line> [<line>]`: a finding with that id on those lines;
//! - `; expect motions <n>`, `; expect end <i> <x> <y> <z>` (mm), `; expect cut_length <mm>`;
//! - `; expect exit <code>`; `; expect clean` (no finding at all);
//! - `; nolinuxcnc`: skip the rs274 cross-check.
//!
//! Every error finding must be expected. When `rs274` (linuxcnc-uspace) is installed, each
//! program is also run through it and its motions are compared with the builtin ones.

use crate::support;

use skinpath::sim::{self, Backend, CheckConfig, DesignBoundary, Severity};
use std::path::{Path, PathBuf};

struct Case {
    path: PathBuf,
    src: String,
    cfg: CheckConfig,
    design: Vec<DesignBoundary>,
    findings: Vec<(String, Vec<usize>)>,
    motions: Option<usize>,
    ends: Vec<(usize, [f64; 3])>,
    cut_length: Option<f64>,
    exit: Option<i32>,
    clean: bool,
    linuxcnc: bool,
}

fn nums(s: &str) -> Vec<f64> {
    s.split([' ', ','])
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap_or_else(|_| panic!("bad number {t:?}")))
        .collect()
}

fn load(path: &Path) -> Case {
    let src = std::fs::read_to_string(path).expect("read corpus file");
    let (cfg, design) = support::corpus_header(&src);
    let mut c = Case {
        path: path.to_path_buf(),
        src: src.clone(),
        cfg,
        design,
        findings: Vec::new(),
        motions: None,
        ends: Vec::new(),
        cut_length: None,
        exit: None,
        clean: false,
        linuxcnc: true,
    };
    for line in src.lines() {
        let Some(d) = line.trim().strip_prefix(';') else {
            continue;
        };
        let d = d.trim();
        if d.starts_with("nolinuxcnc") {
            c.linuxcnc = false;
        } else if let Some(t) = d.strip_prefix("expect ") {
            let mut it = t.split_whitespace();
            match it.next() {
                Some("finding") => {
                    let id = it.next().expect("id").to_string();
                    let lines = it.map(|l| l.parse().expect("line")).collect();
                    c.findings.push((id, lines));
                }
                Some("motions") => c.motions = it.next().and_then(|n| n.parse().ok()),
                Some("end") => {
                    let v: Vec<f64> = nums(&it.collect::<Vec<_>>().join(" "));
                    c.ends.push((v[0] as usize, [v[1], v[2], v[3]]));
                }
                Some("cut_length") => c.cut_length = it.next().and_then(|n| n.parse().ok()),
                Some("exit") => c.exit = it.next().and_then(|n| n.parse().ok()),
                Some("clean") => c.clean = true,
                other => panic!("unknown expectation {other:?} in {}", path.display()),
            }
        }
    }
    c
}

fn corpus() -> Vec<Case> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sim_corpus");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("corpus dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("nc" | "gcode")))
        .collect();
    paths.sort();
    paths.iter().map(|p| load(p)).collect()
}

fn check_case(c: &Case) {
    let name = c.path.file_name().and_then(|n| n.to_str()).unwrap_or("?");
    let prog = sim::load(Backend::Builtin, &c.src, &c.cfg);
    let r = sim::check(&prog, &c.cfg, &c.design);
    let ctx = format!("{name}:\n{r}");
    for (id, lines) in &c.findings {
        assert!(
            r.findings
                .iter()
                .any(|f| f.id == id && lines.iter().all(|l| f.lines.contains(l))),
            "{ctx}\nmissing {id} at {lines:?}"
        );
    }
    for f in r.findings.iter().filter(|f| f.severity == Severity::Error) {
        assert!(
            c.findings.iter().any(|(id, _)| id == f.id),
            "{ctx}\nunexpected {f}"
        );
    }
    if c.clean {
        assert!(r.findings.is_empty(), "{ctx}");
    }
    if let Some(n) = c.motions {
        assert_eq!(prog.motions.len(), n, "{ctx}");
    }
    for (i, want) in &c.ends {
        let got = prog
            .motions
            .get(*i)
            .map_or([f64::NAN; 3], |m| m.to.to_array());
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() < 1e-9,
                "{ctx}\nmotion {i}: {got:?}"
            );
        }
    }
    if let Some(l) = c.cut_length {
        assert!((r.stats.cut_length - l).abs() < 1e-9 * l.max(1.0), "{ctx}");
    }
    if let Some(e) = c.exit {
        assert_eq!(r.exit_code(), e, "{ctx}");
    }
    // The JSON report is well formed and carries the findings.
    let json: serde_json::Value = serde_json::to_value(&r).expect("json");
    assert_eq!(
        json["findings"].as_array().map(|a| a.len()),
        Some(r.findings.len())
    );
}

#[test]
fn corpus_expectations() {
    let cases = corpus();
    assert!(cases.len() >= 14);
    for c in &cases {
        check_case(c);
    }
}

/// One test per planted fault (and per feature file), so a failure names its file.
macro_rules! corpus_case {
    ($($test:ident => $file:literal),* $(,)?) => {$(
        #[test]
        fn $test() {
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sim_corpus").join($file);
            let c = load(&path);
            assert!(!c.findings.is_empty() || c.clean || c.exit == Some(0));
            check_case(&c);
        }
    )*};
}

corpus_case! {
    planted_self_intersection => "fault_self_intersection.nc",
    planted_crossing_contours => "fault_crossing.nc",
    planted_gouge => "fault_gouge.nc",
    planted_out_of_bounds => "fault_out_of_bounds.nc",
    planted_laser_on_rapid => "fault_laser_on_rapid.nc",
    planted_rapid_at_cutting_depth => "fault_rapid_at_depth.nc",
    planted_missing_tool_off => "fault_missing_tool_off.nc",
    planted_feed_out_of_range => "fault_feed_out_of_range.nc",
    planted_gouge_wrong_side => "fault_gouge_wrong_side.nc",
    router_two_depth_passes => "router_multipass.nc",
    inch_and_relative => "inch_relative.nc",
    r_format_arcs => "r_arcs.nc",
    comments_and_checksums => "comments_checksums.gcode",
    malformed_lines => "malformed.nc",
    case_and_spacing => "spacing_case.nc",
    clean_laser_job => "clean_laser.nc",
}

/// LinuxCNC's stand-alone interpreter's canon output (standard output only) on a numbered
/// copy of `src`, or None when rs274 is not installed.
fn run_rs274(src: &str, name: &str) -> Option<String> {
    let opts = sim::rs274::Rs274Options {
        timeout: std::time::Duration::from_secs(20),
        program_name: format!("{name}.ngc"),
        ..Default::default()
    };
    match sim::rs274::run(&sim::linuxcnc::number_lines(src), &opts) {
        Ok(out) => Some(out.stdout),
        Err(sim::rs274::Rs274Error::NotRunnable(_)) => None,
        Err(e) => panic!("rs274 on {name}: {e}"),
    }
}

#[test]
fn linuxcnc_backend_agrees_with_builtin() {
    if run_rs274("G0 X1\nM2\n", "probe").is_none() {
        eprintln!("rs274 not installed: skipping the LinuxCNC cross-check");
        return;
    }
    let mut compared = 0;
    for c in corpus().iter().filter(|c| c.linuxcnc) {
        let name = c.path.file_stem().and_then(|n| n.to_str()).unwrap_or("x");
        let canon = run_rs274(&c.src, name).expect("rs274 output");
        let lc = sim::load(Backend::LinuxCnc, &canon, &c.cfg);
        let bi = sim::load(Backend::Builtin, &c.src, &c.cfg);
        assert_eq!(lc.motions.len(), bi.motions.len(), "{name}\n{canon}");
        for (a, b) in lc.motions.iter().zip(&bi.motions) {
            // rs274 prints 4 decimals (in inch: 0.0001 in = 2.54 µm).
            assert!(a.to.distance(b.to) < 3e-3, "{name}: {a:?} vs {b:?}");
            assert_eq!(a.kind, b.kind, "{name}");
            assert_eq!(a.line, b.line, "{name}");
            assert_eq!(a.arc.is_some(), b.arc.is_some(), "{name}");
            if let (Some(p), Some(q)) = (a.arc, b.arc) {
                assert!((p.sweep - q.sweep).abs() < 1e-3, "{name}: {p:?} vs {q:?}");
            }
        }
        let rl = sim::check(&lc, &c.cfg, &c.design);
        let rb = sim::check(&bi, &c.cfg, &c.design);
        let ids = |r: &sim::Report| {
            let mut v: Vec<_> = r
                .findings
                .iter()
                .filter(|f| f.severity == Severity::Error)
                .map(|f| (f.id, f.lines.clone()))
                .collect();
            v.sort();
            v
        };
        assert_eq!(ids(&rl), ids(&rb), "{name}");
        compared += 1;
    }
    assert!(compared >= 10);
}
