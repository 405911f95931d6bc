//! Conformance against LinuxCNC's own interpreter: every sample program shipped with
//! linuxcnc-uspace (/usr/share/doc/linuxcnc/examples, `.ngc` and `.nc`) is read by `rs274`
//! and by the builtin interpreter. A program rs274 reads without error must be accepted
//! (no interpreter error) with the same bounding box (0.01 mm) and cut length (1e-4
//! relative); one rs274 rejects must be rejected. Programs that need the real machine are
//! listed in [`MACHINE_DEPENDENT`] with the reason. Skipped (with a message) when rs274 or
//! the samples are missing. Runs rs274 once at a time; each run is killed after 5 s.

use skinpath::sim::rs274::{Rs274Error, Rs274Options};
use skinpath::sim::{self, Backend, CheckConfig, Dialect, Severity, ToolEntry, interp};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

const SAMPLES: &str = "/usr/share/doc/linuxcnc/examples";

/// Programs whose result depends on the machine, by path suffix, with the reason.
const MACHINE_DEPENDENT: &[(&str, &str)] = &[
    (
        "nc_files/offsets.ngc",
        "reads tool offsets of tools 0-4 in a do-while; stand-alone rs274 never finishes it",
    ),
    ("nc_files/smartprobe.ngc", "loops on G38 probe results"),
    (
        "nc_files/tool-length-probe.ngc",
        "G38.2 probing (rs274 rejects its simulated probe)",
    ),
    (
        "nc_files/x-trim.ngc",
        "G38.2 probing in touchoff.ngc: later positions are the machine's",
    ),
    (
        "external_offsets/opa_demo.ngc",
        "user M-code M111 (a program of the machine)",
    ),
    (
        "orphans/taskcall.ngc",
        "calls a Python task plugin (qdemo) of a running machine",
    ),
    (
        "demos/xyzac_switchkins.ngc",
        "subroutine only on the machine's INI subroutine path",
    ),
    (
        "demos/xyzbc_switchkins.ngc",
        "subroutine only on the machine's INI subroutine path",
    ),
    (
        "craftsman/macros/m106.ngc",
        "a GUI macro (subroutine file), rs274 never finishes it",
    ),
];

/// Known gaps of the builtin interpreter, by path suffix, with the reason.
const NOT_SUPPORTED: &[(&str, &str)] = &[
    (
        "nc_files/comp.ngc",
        "cutter radius compensation G41/G42 is not implemented",
    ),
    (
        "gmoccapy_2_tools_with_cutter_radius_compensation.ngc",
        "cutter radius compensation G41/G42 is not implemented",
    ),
    (
        "nc_files/useful-subroutines.ngc",
        "cutter radius compensation G41/G42 is not implemented",
    ),
    (
        "lathe_g7x_face_boring.ngc",
        "G70-G72 lathe cycles are not implemented",
    ),
    (
        "lathe_g7x_quadrants.ngc",
        "G70-G72 lathe cycles are not implemented",
    ),
    (
        "nc_files/systems.ngc",
        "G5.1 splines (rs274 prints NURBS_FEED without coordinates)",
    ),
    (
        "nc_files/tcdemo.ngc",
        "G5.1 splines (rs274 prints NURBS_FEED without coordinates)",
    ),
    (
        "ngcgui_lib/qpex.ngc",
        "the N words added for rs274 push a 249-character line past its limit",
    ),
    (
        "ngcgui_lib/qpex_mm.ngc",
        "the N words added for rs274 push a 223-character line past its limit",
    ),
];

fn samples() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![PathBuf::from(SAMPLES)];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .is_some_and(|x| x.eq_ignore_ascii_case("ngc") || x.eq_ignore_ascii_case("nc"))
            {
                out.push(p);
            }
        }
    }
    out.sort();
    // The samples repeat the same programs under many configurations: keep one path per
    // distinct content (symbolic links and copies).
    let mut seen = std::collections::HashSet::new();
    out.retain(|p| seen.insert(std::fs::read(p).unwrap_or_default()));
    if let Ok(only) = std::env::var("SKINPATH_CONFORMANCE_ONLY") {
        out.retain(|p| p.to_string_lossy().contains(&only));
    }
    out
}

/// rs274's canon output (stdout, then stderr) or None on timeout. The program keeps the
/// sample's file name (rs274 treats a file that only defines the subroutine of its own name
/// as a call of it); the sample's folder supplies called subroutines.
fn rs274(path: &Path, text: &str, dir: &Path) -> Option<String> {
    let opts = Rs274Options {
        timeout: Duration::from_secs(5),
        sub_dirs: vec![dir.to_path_buf()],
        program_name: path.file_name()?.to_string_lossy().into_owned(),
        ..Default::default()
    };
    match sim::rs274::run(&sim::linuxcnc::number_lines(text), &opts) {
        Ok(out) => Some(out.combined()),
        Err(Rs274Error::Timeout(_) | Rs274Error::OutputTooLarge(_)) => None,
        Err(e) => panic!("rs274 on {}: {e}", path.display()),
    }
}

/// The tool table stand-alone rs274 starts with (seen in its canon output: tools 1–3 with
/// length offsets 0.511, 0.1 and 1.273 inch).
fn rs274_tools() -> Vec<ToolEntry> {
    [(1, 12.9794), (2, 2.54), (3, 32.3342)]
        .into_iter()
        .map(|(number, z)| ToolEntry {
            number,
            z,
            ..Default::default()
        })
        .collect()
}

struct Outcome {
    name: String,
    verdict: Result<(), String>,
    lc_ok: bool,
}

fn compare(path: &Path) -> Outcome {
    let name = path
        .strip_prefix(SAMPLES)
        .unwrap_or(path)
        .display()
        .to_string();
    let bytes = std::fs::read(path).unwrap_or_default();
    let (text, _) = sim::decode(&bytes);
    let dir = path.parent().unwrap_or(Path::new("."));
    let Some(canon) = rs274(path, &text, dir) else {
        return Outcome {
            name,
            verdict: Err("rs274 timed out".into()),
            lc_ok: false,
        };
    };
    let cfg = CheckConfig {
        dialect: Dialect::Linuxcnc,
        tool_table: rs274_tools(),
        max_loop_iterations: 200_000,
        ..CheckConfig::default()
    };
    let lc = sim::load(Backend::LinuxCnc, &canon, &cfg);
    if std::env::var("SKINPATH_CONFORMANCE_DUMP").is_ok() {
        eprintln!("{canon}");
        eprintln!("{} motions, {:?}", lc.motions.len(), lc.diagnostics);
    }
    let lc_errors: Vec<String> = lc
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| d.to_string())
        .collect();
    let load = |n: &str| -> Option<String> {
        for c in [format!("{n}.ngc"), format!("{}.ngc", n.to_uppercase())] {
            if let Ok(b) = std::fs::read(dir.join(c)) {
                return Some(String::from_utf8_lossy(&b).into_owned());
            }
        }
        None
    };
    let ours = sim::load_with(
        Backend::Builtin,
        &text,
        &cfg,
        &interp::Options {
            load_sub: Some(&load),
        },
    );
    let our_errors: Vec<String> = ours
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| d.to_string())
        .collect();
    let lc_ok = lc_errors.is_empty();
    let verdict = match (lc_ok, our_errors.is_empty()) {
        (true, false) => Err(format!("rs274 accepts, we reject: {}", our_errors[0])),
        (false, true) => Err(format!("rs274 rejects ({}), we accept", lc_errors[0])),
        (false, false) => Ok(()),
        (true, true) => {
            let a = sim::stats(&lc, &cfg);
            let b = sim::stats(&ours, &cfg);
            let rel = (a.cut_length - b.cut_length).abs() / a.cut_length.abs().max(1e-9);
            let bbox = match (a.bbox, b.bbox) {
                (Some(x), Some(y)) => (0..2)
                    .flat_map(|i| (0..3).map(move |j| (x[i][j] - y[i][j]).abs()))
                    .fold(0.0, f64::max),
                (None, None) => 0.0,
                _ => f64::INFINITY,
            };
            // rs274 prints coordinates with 4 decimals: each printed end point is off by up to
            // 5e-5 (units), so a move's length by up to 1.5e-4 mm (inch: × 25.4).
            let rounding = 1.5e-4 * 25.4 * lc.motions.len() as f64;
            let diff = (a.cut_length - b.cut_length).abs();
            if rel > 1e-4 && diff > rounding.min(1e-3 * a.cut_length.abs()) {
                Err(format!(
                    "cut length {:.4} (rs274) vs {:.4} mm",
                    a.cut_length, b.cut_length
                ))
            } else if bbox > 0.01 {
                Err(format!(
                    "bounding boxes differ by {bbox:.4} mm: {:?} vs {:?}",
                    a.bbox, b.bbox
                ))
            } else {
                Ok(())
            }
        }
    };
    Outcome {
        name,
        verdict,
        lc_ok,
    }
}

#[test]
fn linuxcnc_samples_agree() {
    if Command::new("rs274").arg("-h").output().is_err() {
        eprintln!("SKIPPED: rs274 (Debian package linuxcnc-uspace) is not installed");
        return;
    }
    let files = samples();
    if files.is_empty() {
        eprintln!("SKIPPED: no LinuxCNC samples under {SAMPLES}");
        return;
    }
    // One rs274 at a time: concurrent stand-alone rs274 runs disturb each other (seen as
    // programs losing their moves when two run at once).
    let mut outcomes: Vec<Outcome> = files.iter().map(|p| compare(p)).collect();
    outcomes.sort_by(|x, y| x.name.cmp(&y.name));
    let lc_ok = outcomes.iter().filter(|o| o.lc_ok).count();
    let mut bad = Vec::new();
    let mut listed = 0;
    for o in &outcomes {
        if let Err(e) = &o.verdict {
            let machine = MACHINE_DEPENDENT.iter().find(|(n, _)| o.name.ends_with(n));
            let gap = NOT_SUPPORTED.iter().find(|(n, _)| o.name.ends_with(n));
            match (machine, gap) {
                (Some((_, why)), _) => {
                    listed += 1;
                    eprintln!("machine-dependent {}: {why} ({e})", o.name)
                }
                (_, Some((_, why))) => {
                    listed += 1;
                    eprintln!("not supported {}: {why} ({e})", o.name)
                }
                _ => bad.push(format!("{}: {e}", o.name)),
            }
        }
    }
    eprintln!(
        "{} distinct samples, rs274 reads {} without error; {} agree, {} listed, {} disagree",
        outcomes.len(),
        lc_ok,
        outcomes.len() - bad.len() - listed,
        listed,
        bad.len()
    );
    for b in &bad {
        eprintln!("  {b}");
    }
    assert!(bad.is_empty(), "{} disagreements", bad.len());
}
