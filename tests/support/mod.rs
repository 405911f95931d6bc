//! What the test binaries (tests/{api,cli,fuzz,neon,sim}) share, each including this
//! module with `#[path = "../support/mod.rs"] mod support;`: the shipped examples
//! (examples/*.toml, kept in step with the folder by `cli::every_example_is_listed`), a
//! fresh temporary directory, a run of the built binary, the header of a check-corpus
//! program, golden G-code comparison, the "OPEN" neon sign fixture, and the submodules
//! [`dxf`] (a DXF reader), [`emit`] (hand-built toolpaths), [`fuzz`] (the mutation fuzzer) and [`rng`] (the one
//! seeded random-number generator). Each binary uses only
//! part of it.
#![allow(dead_code)]

pub mod dxf;
pub mod emit;
pub mod fuzz;
pub mod rng;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Output};
use std::sync::Once;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// The crate's root folder.
pub const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The names of the shipped example designs, without `.toml`.
pub const EXAMPLES: [&str; 9] = [
    "brush",
    "calligraphy",
    "circles",
    "gclef",
    "loop",
    "neon_word",
    "ring_o",
    "seahorse",
    "snake",
];

/// Prefixes of the temporary folders test processes make, each followed by the process id.
const TEMP_PREFIXES: [&str; 3] = [
    "skinpath-itest-",
    "skinpath-hardening-",
    "skinpath-sim-input-",
];

/// Removes, once per process, the temporary folders of test processes that have ended: a
/// test binary cannot clean up when it exits, and the folders piled up by the thousand.
/// A process is taken as ended when /proc has no entry for its id (Linux; elsewhere
/// nothing is removed), so folders of tests running beside this one stay.
fn sweep_ended_processes() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if !Path::new("/proc/self").exists() {
            return;
        }
        let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
            return;
        };
        for e in entries.flatten() {
            let name = e.file_name();
            let name = name.to_string_lossy();
            let pid = TEMP_PREFIXES
                .iter()
                .find_map(|p| name.strip_prefix(p))
                .and_then(|rest| rest.split('-').next())
                .and_then(|p| p.parse::<u32>().ok());
            if let Some(pid) = pid
                && pid != std::process::id()
                && !Path::new(&format!("/proc/{pid}")).exists()
            {
                let _ = std::fs::remove_dir_all(e.path());
            }
        }
    });
}

/// The path of the shipped example examples/`name`.toml.
pub fn example_path(name: &str) -> String {
    format!("{ROOT}/examples/{name}.toml")
}

/// The shipped example examples/`name`.toml, loaded.
pub fn example(name: &str) -> skinpath::design::Design {
    let path = example_path(name);
    let text = std::fs::read_to_string(&path).unwrap();
    skinpath::design::load(&text, &path).unwrap()
}

/// A fresh, empty directory unique to this process and call (the folders of ended test
/// processes are removed first).
pub fn tmpdir(tag: &str) -> PathBuf {
    sweep_ended_processes();
    static N: AtomicUsize = AtomicUsize::new(0);
    let n = N.fetch_add(1, Ordering::SeqCst);
    let d = std::env::temp_dir().join(format!("skinpath-itest-{}-{tag}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the built `skinpath` binary in the crate's root folder.
pub fn skinpath(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(args)
        .current_dir(ROOT)
        .output()
        .expect("run skinpath")
}

/// Runs the built `skinpath` binary in `dir`.
pub fn skinpath_in(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run skinpath")
}

/// A hang guard for child processes, not a speed test: the runs it guards take well under
/// a second to a few seconds in a debug build; tests run in parallel on shared cores.
pub const CHILD_LIMIT: Duration = Duration::from_secs(120);

/// Waits for `child`, killing it after [`CHILD_LIMIT`] (then the test fails, naming `what`).
pub fn wait_limited(mut child: Child, what: &str) -> ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if start.elapsed() > CHILD_LIMIT {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("{what}: still running after {CHILD_LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The setup a check-corpus program (tests/sim_corpus) carries in its `;` comments: the
/// `; config <toml line>` lines as one CheckConfig, and each
/// `; design outside|inside|either x,y x,y ...` line as a design boundary for the gouge
/// check.
pub fn corpus_header(
    src: &str,
) -> (
    skinpath::sim::CheckConfig,
    Vec<skinpath::sim::DesignBoundary>,
) {
    use skinpath::sim::{DesignBoundary, KeepSide};
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
                .map(|q| skinpath::geom::DVec2::new(q[0], q[1]))
                .collect();
            design.push(DesignBoundary::new(&p, keep));
        }
    }
    (toml::from_str(&toml_cfg).expect("config lines"), design)
}

/// Coordinates of a golden G-code may differ by this much (float formatting).
pub const GOLDEN_TOL: f64 = 1e-3;

/// The words of a G-code line (letter + number, upper case), comments dropped.
pub fn gcode_words(line: &str) -> Vec<String> {
    let code = line.split(';').next().unwrap_or("");
    let mut out = Vec::new();
    let mut depth = 0;
    let mut cur = String::new();
    for ch in code.chars() {
        match ch {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if depth > 0 || ch.is_whitespace() => {}
            c if c.is_ascii_alphabetic() => {
                if !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                }
                cur.push(c.to_ascii_uppercase());
            }
            c => cur.push(c),
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// A neon sign of `text` in `font` at `height` mm (`skinpath text … --neon`), built with
/// default flags on grbl-router and grbl-laser: each build exits 0 with no findings, checks
/// clean with its profile, and its program equals tests/golden/`golden`.MACHINE.gcode
/// ([`assert_golden`]). Returns each machine with its `build --json` summary for the
/// caller's own assertions.
pub fn neon_text_matches_golden(
    text: &str,
    font: &str,
    height: &str,
    golden: &str,
) -> Vec<(&'static str, serde_json::Value)> {
    let dir = tmpdir(&format!("neon-golden-{golden}"));
    let design = dir.join(format!("{golden}.toml"));
    let d = design.to_str().unwrap();
    let t = skinpath(&[
        "text", text, "--font", font, "--height", height, "--neon", "-o", d,
    ]);
    assert!(t.status.success(), "{}", String::from_utf8_lossy(&t.stderr));
    let mut out = Vec::new();
    for machine in ["grbl-router", "grbl-laser"] {
        let program = dir.join(format!("{golden}-{machine}.gcode"));
        let o = program.to_str().unwrap();
        let b = skinpath(&["build", d, "--machine", machine, "-o", o, "--json"]);
        assert!(
            b.status.success(),
            "{machine}: {}",
            String::from_utf8_lossy(&b.stderr)
        );
        let summary: serde_json::Value = serde_json::from_slice(&b.stdout).unwrap();
        assert_eq!(
            summary["findings"].as_array().map(Vec::len),
            Some(0),
            "{machine}"
        );
        let c = skinpath(&["check", o, "--machine", machine]);
        assert!(
            c.status.success(),
            "{machine}: {}",
            String::from_utf8_lossy(&c.stdout)
        );
        let got = std::fs::read_to_string(&program).unwrap();
        assert_golden(&got, &format!("{golden}.{machine}.gcode"), machine);
        out.push((machine, summary));
    }
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// `got` against tests/golden/`name`: the same blocks, words and letters, every number
/// within [`GOLDEN_TOL`]; `SKINPATH_BLESS=1` rewrites the golden instead. `what` names the
/// case in failures.
pub fn assert_golden(got: &str, name: &str, what: &str) {
    let golden = Path::new(ROOT).join("tests/golden").join(name);
    if std::env::var("SKINPATH_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(&golden, got).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&golden).unwrap();
    let (g, w): (Vec<_>, Vec<_>) = (
        got.lines()
            .map(gcode_words)
            .filter(|v| !v.is_empty())
            .collect(),
        want.lines()
            .map(gcode_words)
            .filter(|v| !v.is_empty())
            .collect(),
    );
    assert_eq!(g.len(), w.len(), "{what}: blocks");
    for (i, (a, b)) in g.iter().zip(&w).enumerate() {
        assert_eq!(a.len(), b.len(), "{what}: block {i}");
        for (x, y) in a.iter().zip(b) {
            assert_eq!(x[..1], y[..1], "{what}: block {i}");
            let (vx, vy): (f64, f64) = (x[1..].parse().unwrap(), y[1..].parse().unwrap());
            // One unit in the last of three written decimals is within the tolerance,
            // whatever the binary rounding of the two parsed numbers' difference.
            assert!(
                (vx - vy).abs() <= GOLDEN_TOL * (1.0 + 1e-9),
                "{what}: block {i}: {x} vs {y}"
            );
        }
    }
}

/// Widths, diameters and depths (mm) the routed operations of [`open_sign`] may set
/// instead of the design format's defaults.
pub struct OpenSignCuts {
    pub channel_width: f64,
    pub channel_depth: f64,
    pub hole_diameter: f64,
    pub hole_depth: f64,
    pub board_depth: f64,
}

/// The two outputs of the "OPEN" sign: the routed channels, holes and board on grbl-router,
/// the laser-cut face on grbl-laser (append to [`open_sign`]).
pub const OPEN_SIGN_OUTPUTS: &str = r#"
[[output]]
name = "router"
machine = "grbl-router"
operations = ["channels", "holes", "board"]

[[output]]
name = "laser"
machine = "grbl-laser"
operations = ["face"]
"#;

/// A neon sign: "OPEN" in the sans font with the gallery sign's channel, holes and
/// backboard (routed), a second backboard named "face" (the laser-cut acrylic face), the
/// routed operations at `cuts` (or the format's defaults), and `outputs` appended
/// ([`OPEN_SIGN_OUTPUTS`], a variant of it, or nothing).
pub fn open_sign(cuts: Option<&OpenSignCuts>, outputs: &str) -> String {
    let (channel, holes, board) = match cuts {
        Some(c) => (
            format!(
                "width = {:?}\ndepth = {:?}\n",
                c.channel_width, c.channel_depth
            ),
            format!(
                "diameter = {:?}\ndepth = {:?}\n",
                c.hole_diameter, c.hole_depth
            ),
            format!("depth = {:?}\n", c.board_depth),
        ),
        None => Default::default(),
    };
    format!(
        r#"version = 1
units = "mm"

[[text]]
name = "open"
text = "OPEN"
font = "sans"
height = 40.0
width = 6.0
at = [8.0, 13.0]

[neon]
flex = "6mm"

[[operation]]
name = "channels"
kind = "channel"
{channel}
[[operation]]
kind = "holes"
{holes}
[[operation]]
name = "board"
kind = "backboard"
margin = 6.0
{board}
[[operation]]
name = "face"
kind = "backboard"
margin = 6.0
power = 90.0
{outputs}"#
    )
}
