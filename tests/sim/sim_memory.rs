//! `check` in bounded memory (issue #18, item 5): a generated program is checked in a child
//! process whose address space is limited (`ulimit -v` in `sh`); the check must finish
//! cleanly within the budget. Where the limit cannot be set the test says so and passes.
//!
//! Budgets (address space, so they include the binary, its libraries and the allocator's
//! reservations, not only what is touched):
//! - always on: a 20 MB program (1M segments, the in-memory route) in [`SMALL_BUDGET_MB`];
//! - `#[ignore]` (minutes): a 200 MB program (10M segments) in [`LARGE_BUDGET_MB`] and a
//!   1 GB program (50M segments) in [`HUGE_BUDGET_MB`], both on the streaming route
//!   ([`skinpath::sim::check_stream`], taken above 64 MiB). Run with
//!   `cargo test --release --test sim -- --ignored sim_memory::`.

use crate::support;

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// Address-space budget of the 20 MB program, MiB (a release build passes in 200 since moves
/// are stored in 32 bytes; it needed more than 250 before they were 40).
const SMALL_BUDGET_MB: u64 = 300;

/// Address-space budget of the 200 MB program, MiB (streaming route; it needed 2000 in
/// memory, with a peak resident memory of 1.5 GB).
const LARGE_BUDGET_MB: u64 = 512;

/// Address-space budget of the 1 GB program, MiB: less than the program itself.
const HUGE_BUDGET_MB: u64 = 1024;

/// Writes a clean laser program of about `bytes`: closed 100-gons of radius 0.4 mm on a
/// 0.9 mm grid (no crossings), the grid shrunk where it would not fit inside the default
/// 300 mm work area (1 GB: radius 0.18 mm on a 0.41 mm grid).
fn write_program(path: &Path, bytes: usize) {
    const PER: usize = 100;
    let per_circle = 20 * (PER + 1) + 20;
    let circles = bytes.div_ceil(per_circle);
    let side = (circles as f64).sqrt().ceil() as usize;
    let pitch = (297.0 / side as f64).min(0.9);
    let radius = 0.4 * pitch / 0.9;
    let mut s = String::with_capacity(bytes + 4096);
    s.push_str("G21 G90 G17\nF1500 S800\n");
    let mut file = std::fs::File::create(path).expect("create program");
    for c in 0..circles {
        let (ox, oy) = (
            1.0 + (c % side) as f64 * pitch,
            1.0 + (c / side) as f64 * pitch,
        );
        for i in 0..=PER {
            let t = std::f64::consts::TAU * (i % PER) as f64 / PER as f64;
            let (x, y) = (ox + radius * t.cos(), oy + radius * t.sin());
            if i == 0 {
                let _ = write!(s, "G0 X{x:.3} Y{y:.3}\nM4\n");
            } else {
                let _ = writeln!(s, "G1 X{x:.3} Y{y:.3}");
            }
        }
        s.push_str("M5\n");
        if s.len() > 1 << 22 {
            std::io::Write::write_all(&mut file, s.as_bytes()).expect("write program");
            s.clear();
        }
    }
    s.push_str("M2\n");
    std::io::Write::write_all(&mut file, s.as_bytes()).expect("write program");
}

/// Runs `skinpath check` on a generated program of `bytes` under `budget_mb` of address
/// space; returns false (after saying why) when the limit cannot be set here.
fn check_within(tag: &str, bytes: usize, budget_mb: u64) -> bool {
    let dir = support::tmpdir(tag);
    let prog = dir.join("big.gcode");
    write_program(&prog, bytes);
    let probe = Command::new("sh")
        .args(["-c", "ulimit -v 1000000"])
        .status();
    if !probe.is_ok_and(|s| s.success()) {
        eprintln!("skipped: `ulimit -v` is not available, the memory budget cannot be set");
        let _ = std::fs::remove_dir_all(&dir);
        return false;
    }
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {} && exec \"$0\" \"$@\"",
            budget_mb * 1024
        ))
        .arg(env!("CARGO_BIN_EXE_skinpath"))
        .arg("check")
        .arg(&prog)
        .output()
        .expect("run sh");
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(0),
        "check of a {} MB program within {budget_mb} MiB of address space failed:\n{stdout}\n{stderr}",
        bytes >> 20
    );
    assert!(stdout.contains("0 errors, 0 warnings"), "{stdout}");
    true
}

#[test]
fn twenty_megabytes_within_budget() {
    check_within("mem-small", 20 << 20, SMALL_BUDGET_MB);
}

#[test]
#[ignore = "writes and checks a 200 MB program (a minute or more)"]
fn two_hundred_megabytes_within_budget() {
    check_within("mem-large", 200 << 20, LARGE_BUDGET_MB);
}

#[test]
#[ignore = "writes and checks a 1 GB program (several minutes; the file is removed after)"]
fn one_gigabyte_within_budget() {
    check_within("mem-huge", 1 << 30, HUGE_BUDGET_MB);
}

/// 2,000 passes over one square without switching the laser off (one contour retracing
/// itself, about 190 KB): the retraces are reported within the per-check cap with the rest
/// counted, and the check neither blows up nor loses the count.
#[test]
fn retraced_contour_is_reported_within_the_cap() {
    use skinpath::sim::{Backend, CheckConfig, check_text};
    let mut src = String::from("G21 G90 F1000 S500\nG0 X10 Y10\nM4\n");
    for _ in 0..2000 {
        src += "G1 X20.000 Y10.000\nG1 X20.000 Y20.000\nG1 X10.000 Y20.000\nG1 X10.000 Y10.000\n";
    }
    src += "M5\nM2\n";
    assert!(src.len() > 140_000);
    let cfg = CheckConfig::default();
    let r = check_text(Backend::Builtin, &src, &cfg, &[]);
    assert_eq!(r.stats.motions, 1 + 2000 * 4);
    let shown = r
        .findings
        .iter()
        .filter(|f| f.id == "self-intersection")
        .count();
    assert!(shown > 0 && shown <= cfg.max_findings_per_check, "{r}");
    let more = r
        .suppressed
        .iter()
        .find(|(id, _)| id == "self-intersection")
        .map_or(0, |s| s.1);
    assert!(more > 0, "{r}");
}
