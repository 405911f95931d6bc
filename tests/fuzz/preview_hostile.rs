//! Previews of hostile programs (issue 40, item 18): a many-turn arc, a loop that never
//! ends, a million canned-cycle repeats, coordinates of 10⁹ mm at 300 dpi and a million
//! tiny moves. Each runs the built binary as a child under an address-space limit and a
//! generous time limit (a hang guard, not a speed test: the limit only turns a regression
//! into a failure instead of a stuck run) and asserts on the outcome: exit code, image size,
//! what the drawing holds and what it says.

use skinpath::emit::preview::svg::{CUT_BUDGET, FINDING_BUDGET, MARK_BUDGET, RAPID_BUDGET};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::support;

/// Kill a child still running after this long (debug build, two shared cores).
const CHILD_LIMIT: Duration = Duration::from_secs(400);
/// Address space a child may use, KiB: the 2 GB.
const ADDRESS_SPACE_KIB: u64 = 2 * 1024 * 1024;

/// What a child run produced.
struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Whether `ulimit -v` works here (it does in Linux shells).
fn can_limit_memory() -> bool {
    Command::new("sh")
        .args(["-c", "ulimit -v 1000000"])
        .status()
        .is_ok_and(|s| s.success())
}

/// `skinpath ARGS` under [`ADDRESS_SPACE_KIB`] (when it can be set) and [`CHILD_LIMIT`].
fn run_limited(args: &[&str]) -> Run {
    let bin = env!("CARGO_BIN_EXE_skinpath");
    let mut cmd = if can_limit_memory() {
        let mut c = Command::new("sh");
        c.arg("-c")
            .arg(format!(
                "ulimit -v {ADDRESS_SPACE_KIB} && exec \"$0\" \"$@\""
            ))
            .arg(bin);
        c
    } else {
        eprintln!("`ulimit -v` is not available: running without the memory limit");
        Command::new(bin)
    };
    let mut child = cmd
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    // Drain the pipes on threads so a chatty child never blocks on a full pipe.
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = out.read_to_string(&mut s);
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > CHILD_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("skinpath {args:?} still running after {CHILD_LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    Run {
        code: status.code(),
        stdout: out.join().unwrap_or_default(),
        stderr: err.join().unwrap_or_default(),
    }
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p.display().to_string()
}

fn out(dir: &Path, name: &str) -> (PathBuf, String) {
    let p = dir.join(name);
    let s = p.display().to_string();
    (p, s)
}

/// Previews `program` as SVG and as PNG (default width); both succeed. Returns the SVG.
fn svg_and_png(dir: &Path, program: &str) -> (String, Run) {
    let (svg, svg_s) = out(dir, "p.svg");
    let (png, png_s) = out(dir, "p.png");
    let r = run_limited(&["preview", program, "-o", &svg_s]);
    assert_eq!(r.code, Some(0), "{}\n{}", r.stdout, r.stderr);
    let p = run_limited(&["preview", program, "-o", &png_s]);
    assert_eq!(p.code, Some(0), "{}\n{}", p.stdout, p.stderr);
    let img =
        resvg::tiny_skia::Pixmap::decode_png(&std::fs::read(&png).expect("png")).expect("a PNG");
    assert_eq!(img.width(), 1600);
    assert!(img.height() >= 1 && img.height() <= 16384);
    (std::fs::read_to_string(&svg).expect("svg"), r)
}

/// Elements of `class` in the SVG and their path points.
fn drawn(doc: &roxmltree::Document, class: &str) -> (usize, usize) {
    let els: Vec<_> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some(class))
        .collect();
    let pts = els
        .iter()
        .filter_map(|n| n.attribute("d"))
        .map(|d| d.matches(['M', 'L']).count())
        .sum();
    (els.len(), pts)
}

/// Legend rows of class `limit` (what the drawing left out or where reading stopped).
fn limit_rows(doc: &roxmltree::Document) -> Vec<String> {
    doc.descendants()
        .filter(|n| n.attribute("class") == Some("limit"))
        .filter_map(|n| n.text().map(str::to_string))
        .collect()
}

/// The drawing keeps to the layers' budgets, whatever the program.
fn within_budgets(doc: &roxmltree::Document) {
    let (cuts, cut_pts) = drawn(doc, "cut");
    let (ramps, ramp_pts) = drawn(doc, "ramp");
    assert!(cuts + ramps <= CUT_BUDGET.elements);
    assert!(
        cut_pts + ramp_pts <= CUT_BUDGET.points,
        "{cut_pts} + {ramp_pts}"
    );
    let (rapids, rapid_pts) = drawn(doc, "rapid");
    assert!(rapids <= RAPID_BUDGET.elements && rapid_pts <= RAPID_BUDGET.points);
    let (starts, _) = drawn(doc, "start");
    let (arrows, _) = drawn(doc, "arrow");
    assert!(starts + arrows <= MARK_BUDGET.elements);
    let rings = doc
        .descendants()
        .filter(|n| {
            n.attribute("class")
                .is_some_and(|c| c.starts_with("finding "))
        })
        .count();
    assert!(rings <= FINDING_BUDGET.elements);
}

#[test]
fn arc_of_a_hundred_thousand_turns_is_drawn_once_round() {
    let dir = support::tmpdir("hostile-arc");
    let prog = write(
        &dir,
        "arc.nc",
        "G21 G90 G17\nG0 X0 Y0\nM3 S500\nG2 X10 Y0 I5 J0 P100000 F600\nM5\nM2\n",
    );
    let (svg, _) = svg_and_png(&dir, &prog);
    let doc = roxmltree::Document::parse(&svg).expect("parses");
    within_budgets(&doc);
    // The one contour is drawn, its points within the budget.
    assert_eq!(drawn(&doc, "cut").0, 1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn endless_loop_previews_what_was_read_and_says_it_stopped() {
    let dir = support::tmpdir("hostile-while");
    let prog = write(
        &dir,
        "while.nc",
        "G21 G90\nM3 S500\n#1=0\no1 while [1]\nG1 X[#1 MOD 100] Y[#1/1000] F600\n\
         #1=[#1+1]\no1 endwhile\nM5\nM2\n",
    );
    let (svg, run) = svg_and_png(&dir, &prog);
    assert!(run.stderr.contains("stopped"), "{}", run.stderr);
    let doc = roxmltree::Document::parse(&svg).expect("parses");
    within_budgets(&doc);
    let rows = limit_rows(&doc);
    assert!(
        rows.iter()
            .any(|r| r.contains("stopped") && r.contains("loop-limit")),
        "{rows:?}"
    );
    // A million zigzag moves of 100 mm are more ink than a picture holds: the legend says
    // the cut path was drawn in part.
    assert!(
        rows.iter().any(|r| r.starts_with("preview limit")),
        "{rows:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_million_canned_cycle_repeats_preview_within_budget() {
    let dir = support::tmpdir("hostile-g81");
    let prog = write(
        &dir,
        "g81.nc",
        "G21 G90\nG0 Z5\nG0 X0 Y0\nM3 S10000\nG91\nG81 X0.01 Y0 Z-1 R1 L1000000 F100\nG80\nG90\n\
         M5\nM2\n",
    );
    let (svg, _) = svg_and_png(&dir, &prog);
    let doc = roxmltree::Document::parse(&svg).expect("parses");
    within_budgets(&doc);
    // Whatever the simulator makes of the repeats (drilled, or stopped at its budget), the
    // drill points show: plunges closer than a pixel merge into dots, travels into one line.
    assert!(drawn(&doc, "ramp").0 >= 1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn too_large_an_image_is_refused_from_the_bounds() {
    let dir = support::tmpdir("hostile-far");
    let prog = write(
        &dir,
        "far.nc",
        "G21 G90\nM3 S500\nG0 X0 Y0\nG1 X1000000000 Y1000000000 F600\nM5\nM2\n",
    );
    let (png, png_s) = out(&dir, "far.png");
    let r = run_limited(&["preview", &prog, "-o", &png_s, "--dpi", "300"]);
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(
        r.stderr.contains("the image would be at least") && r.stderr.contains("pixels"),
        "{}",
        r.stderr
    );
    assert!(!png.exists(), "nothing written");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_million_tiny_moves_are_simplified_to_the_pixel() {
    let dir = support::tmpdir("hostile-tiny");
    // A spiral of 10⁶ moves of 4 µm: 4 m of cut drawn on a 1600-pixel image.
    let mut text = String::from("G21 G90\nM3 S500\nG0 X90 Y50\nF600\n");
    let n = 1_000_000;
    for i in 0..n {
        let a = i as f64 * 1e-4;
        let r = 40.0 * (1.0 - 0.5 * i as f64 / n as f64);
        text.push_str(&format!(
            "G1X{:.4}Y{:.4}\n",
            50.0 + r * a.cos(),
            50.0 + r * a.sin()
        ));
    }
    text.push_str("M5\nM2\n");
    let prog = write(&dir, "tiny.nc", &text);
    let (svg, run) = svg_and_png(&dir, &prog);
    assert!(run.stdout.contains(" 1 contours"), "{}", run.stdout);
    let doc = roxmltree::Document::parse(&svg).expect("parses");
    within_budgets(&doc);
    // One contour; its points are at least a pixel of the SVG's detail apart, so far
    // fewer than the moves.
    let (cuts, pts) = drawn(&doc, "cut");
    assert_eq!(cuts, 1);
    assert!(pts < n / 2, "{pts} points");
    let _ = std::fs::remove_dir_all(&dir);
}
