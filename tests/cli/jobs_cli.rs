//! Jobs that never fail a user (issue 11), through the command line: the E channel and the
//! whole "OPEN" sign, every example on every shipped profile with default flags, placement
//! options, build = check (what `build` writes passes `check --machine SAME` with no flags),
//! firmware conventions per dialect, the `--json` summary and how outputs are written.
//!
//! Firmware behaviour the outputs follow, quoted from the firmware sources:
//! - Marlin: "M30 <filename>: Delete SD Card file" (MarlinFirmware/Marlin,
//!   Marlin/src/gcode/sd/M30.cpp, lines 30-38: `GcodeSuite::M30` calls
//!   `card.removeFile(parser.string_arg)`), and Marlin has no M2: a Marlin program ends
//!   without either, and `check --machine marlin-laser` notes that as info.
//! - GRBL 1.1 (gnea/grbl, grbl/gcode.c, lines 868-873): "If in laser mode, setup laser
//!   power based on current and past parser conditions. ... if ( !((gc_block.modal.motion
//!   == MOTION_MODE_LINEAR) || ... CW_ARC ... CCW_ARC) ) { gc_parser_flags |=
//!   GC_PARSER_LASER_DISABLE; }": only with $32=1 does a G0 switch the beam off, so the
//!   program states that it expects $32=1 and also writes S0 before every rapid.
//! - Smoothieware (src/modules/tools/laser/Laser.cpp, lines 238-245): "get laser power for
//!   the currently executing block, returns false if nothing running or a G0", testing
//!   `block->is_g123`: the laser never fires on G0, so no S0 is needed there.
//! - LinuxCNC (docs/src/gcode/m-code.adoc, section `[[mcode:m2-m30]]`, near line 58):
//!   "M2 - end the program", "M30 - exchange pallet shuttles and end the program", both
//!   stop the spindle (like M5) and turn coolant off (like M9): the router program ends
//!   with M5 and M2 at safe Z.

use serde_json::Value as Json;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Output;

use crate::support;
use support::{EXAMPLES, ROOT, example_path, skinpath, tmpdir};

const GCODE_PROFILES: [&str; 5] = [
    "grbl-laser",
    "grbl-router",
    "linuxcnc-router",
    "marlin-laser",
    "smoothie-laser",
];
const SVG_PROFILES: [&str; 2] = ["svg-laser", "svg-laser-lightburn"];

/// Example × profile builds that are refused with default flags, with the reason the
/// message must give. Everything else must build and check clean.
const DO_NOT_FIT: [(&str, &str, &str); 8] = [
    // A laser engraving: its fill has no depth, which a router needs.
    ("brush", "grbl-router", "needs `depth`"),
    ("brush", "linuxcnc-router", "needs `depth`"),
    // Larger than the machine's work area: the message names the option that fixes it.
    ("circles", "marlin-laser", "--fit"),
    ("gclef", "grbl-router", "--fit"),
    ("gclef", "marlin-laser", "--fit"),
    ("neon_word", "marlin-laser", "--fit"),
    ("seahorse", "grbl-router", "--fit"),
    ("snake", "marlin-laser", "--fit"),
];

fn text(o: &Output) -> String {
    format!(
        "exit {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn data(name: &str) -> String {
    format!("{ROOT}/tests/jobs_data/{name}.toml")
}

fn ext(machine: &str) -> &'static str {
    if machine.starts_with("svg") {
        "svg"
    } else {
        "gcode"
    }
}

/// `check PROGRAM --machine M --json` with no other flag: (errors, warnings, report).
fn check(program: &Path, machine: &str) -> (usize, usize, Json) {
    let o = skinpath(&[
        "check",
        program.to_str().unwrap(),
        "--machine",
        machine,
        "--json",
    ]);
    let j: Json = serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", text(&o)));
    let count = |sev: &str| {
        j["findings"]
            .as_array()
            .map(|a| a.iter().filter(|f| f["severity"] == sev).count())
            .unwrap_or(0)
    };
    (count("error"), count("warning"), j)
}

/// Builds `design` for `machine` with `extra` flags into a fresh folder; on success the
/// G-code must pass `check --machine` with nothing above info.
fn build_clean(design: &str, machine: &str, extra: &[&str], what: &str) -> PathBuf {
    let d = tmpdir("b");
    let out = d.join(format!("out.{}", ext(machine)));
    let mut args = vec![
        "build",
        design,
        "--machine",
        machine,
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = skinpath(&args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{what} on {machine}: {}",
        text(&o)
    );
    if ext(machine) == "gcode" {
        let (e, w, j) = check(&out, machine);
        assert_eq!(
            (e, w),
            (0, 0),
            "{what} on {machine}: check finds {e} errors, {w} warnings: {j}"
        );
    }
    out
}

/// [`build_clean`] of the design text `design`, written to a fresh temporary folder.
fn build_clean_text(design: &str, machine: &str, what: &str) -> PathBuf {
    let f = tmpdir("design").join("design.toml");
    std::fs::write(&f, design).unwrap();
    build_clean(f.to_str().unwrap(), machine, &[], what)
}

/// The cut length `check` reports for the program `out`.
fn cut_length(out: &Path, machine: &str) -> f64 {
    let (_, _, j) = check(out, machine);
    j["stats"]["cut_length"].as_f64().unwrap_or(f64::NAN)
}

#[test]
fn e_channel_builds_and_checks_clean_on_every_gcode_profile() {
    for m in GCODE_PROFILES {
        let out = build_clean(&data("e_channel"), m, &[], "E channel");
        let g = std::fs::read_to_string(&out).unwrap();
        // The channel is cut all along the E: a move reaches both its top and bottom arms
        // (the lower half was missing before the fix) and no cutting move is longer than
        // the E's longest straight run (80 mm stem, the stray cut was 72.5 mm across).
        assert!(g.lines().count() > 50, "{m}");
    }
    // Placed as the issue placed it: lower-left with a margin.
    build_clean(
        &data("e_channel"),
        "grbl-router",
        &["--place", "lower-left", "--margin", "5"],
        "E channel, margin 5",
    );
}

/// A laser profile in two passes builds and checks clean on every laser profile: the passes
/// were written back to back with the beam on, one contour retracing itself, which every
/// check refused ("cut contour touches itself"), and Marlin's `M3 I1` after an arc was read
/// as a full circle.
#[test]
fn laser_passes_build_and_check_clean_on_every_laser_profile() {
    for m in ["grbl-laser", "marlin-laser", "smoothie-laser", "svg-laser"] {
        let out = build_clean(&data("laser_passes"), m, &[], "two laser passes");
        if ext(m) == "gcode" {
            let two = cut_length(&out, m);
            // The same design in one pass: half the cut length.
            let design = std::fs::read_to_string(data("laser_passes")).unwrap();
            let one_pass = design.replace("passes = 2", "passes = 1");
            let one = cut_length(&build_clean_text(&one_pass, m, "one pass"), m);
            assert!((two - 2.0 * one).abs() < 1e-6 * one, "{m}: {two} vs {one}");
        }
    }
}

/// Arc leads on a closed contour: the lead-in arrives on the waste side and the lead-out
/// leaves on the same circle, both tangent at the contour's start, so the path crosses
/// itself there tangentially; the check refused it ("cut contour touches itself") on the
/// laser profiles. The leads add two quarter circles, π·r of cut length.
#[test]
fn arc_leads_on_a_closed_contour_build_and_check() {
    let design = std::fs::read_to_string(data("laser_passes"))
        .unwrap()
        .replace("passes = 2", "depth = 2.0");
    let built_cut =
        |design: &str, m: &str, what: &str| cut_length(&build_clean_text(design, m, what), m);
    for m in [
        "grbl-laser",
        "marlin-laser",
        "smoothie-laser",
        "grbl-router",
    ] {
        let plain = built_cut(&design, m, "plain");
        for r in [0.5, 1.0, 2.0] {
            let led = built_cut(&format!("{design}lead_in = {r}\n"), m, "led");
            let extra = PI * r;
            assert!(
                (led - plain - extra).abs() < 1e-2,
                "{m} r {r}: {led} - {plain} vs π·r = {extra}"
            );
        }
    }
}

/// Leads on outlines that start at a corner: the gallery's starter with `lead_in = 2` on
/// its profile. A flattened outline's start vertex turned 10°, the lead-in was tangent to
/// the first side and the lead-out to the last, and the two passes through the start
/// crossed there ("cut contour touches itself", 16 times on grbl-laser). Leads now start
/// at the middle of a side.
#[test]
fn leads_on_outlines_starting_at_a_corner_build_and_check() {
    let design = std::fs::read_to_string(example_path("gallery/starter"))
        .unwrap()
        .replace("power = 80", "power = 80\nlead_in = 2.0");
    assert!(design.contains("lead_in = 2.0"));
    for m in [
        "grbl-laser",
        "marlin-laser",
        "grbl-router",
        "linuxcnc-router",
    ] {
        build_clean_text(&design, m, "starter with leads");
    }
}

#[test]
fn open_sign_builds_on_every_profile_it_fits() {
    for m in GCODE_PROFILES.iter().chain(SVG_PROFILES.iter()) {
        let d = tmpdir("open");
        let out = d.join(format!("open.{}", ext(m)));
        let o = skinpath(&[
            "build",
            &data("open_sign"),
            "--machine",
            m,
            "-o",
            out.to_str().unwrap(),
        ]);
        if *m == "marlin-laser" {
            // 263 mm wide: does not fit the 220 mm bed; the message says how to fix it
            // and nothing is written.
            assert_eq!(o.status.code(), Some(2), "{}", text(&o));
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(
                err.contains("--fit") && err.contains("220.0 x 220.0"),
                "{err}"
            );
            assert!(!out.exists());
            build_clean(&data("open_sign"), m, &["--fit", "219x219"], "OPEN, fitted");
            continue;
        }
        assert_eq!(o.status.code(), Some(0), "OPEN on {m}: {}", text(&o));
        if ext(m) == "gcode" {
            let (e, w, j) = check(&out, m);
            assert_eq!((e, w), (0, 0), "OPEN on {m}: {j}");
        }
    }
}

#[test]
fn readme_snippet_builds_and_checks_clean_on_grbl_router() {
    build_clean(
        &data("readme_snippet"),
        "grbl-router",
        &[],
        "README snippet",
    );
}

#[test]
fn readme_first_command_output_checks_clean_without_flags() {
    let d = tmpdir("readme");
    let out = d.join("neon.gcode");
    let prev = d.join("neon-preview.svg");
    let o = skinpath(&[
        "build",
        "examples/neon_word.toml",
        "--machine",
        "grbl-router",
        "-o",
        out.to_str().unwrap(),
        "--place",
        "lower-left",
        "--margin",
        "5",
        "--preview",
        prev.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let (e, w, j) = check(&out, "grbl-router");
    assert_eq!((e, w), (0, 0), "{j}");
    assert!(prev.exists());
}

#[test]
fn every_example_on_every_profile_with_default_flags() {
    let mut built = 0;
    for name in EXAMPLES {
        for m in GCODE_PROFILES.iter().chain(SVG_PROFILES.iter()) {
            let expected = DO_NOT_FIT
                .iter()
                .find(|(n, p, _)| *n == name && p == m)
                .map(|(_, _, why)| *why);
            match expected {
                None => {
                    build_clean(&example_path(name), m, &[], name);
                    built += 1;
                }
                Some(why) => {
                    let d = tmpdir("nofit");
                    let out = d.join(format!("x.{}", ext(m)));
                    let o = skinpath(&[
                        "build",
                        &example_path(name),
                        "--machine",
                        m,
                        "-o",
                        out.to_str().unwrap(),
                    ]);
                    assert_eq!(o.status.code(), Some(2), "{name} on {m}: {}", text(&o));
                    let err = String::from_utf8_lossy(&o.stderr);
                    assert!(err.contains(why), "{name} on {m}: {err}");
                    assert!(!out.exists(), "{name} on {m}: wrote output on failure");
                }
            }
        }
    }
    assert_eq!(built, EXAMPLES.len() * 7 - DO_NOT_FIT.len());
}

#[test]
fn the_too_big_ones_fit_with_the_option_the_message_names() {
    for (name, m, why) in DO_NOT_FIT {
        if why != "--fit" {
            continue;
        }
        let d = tmpdir("fit");
        let out = d.join("x.gcode");
        let o = skinpath(&[
            "build",
            &example_path(name),
            "--machine",
            m,
            "-o",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        let fit = err
            .split_whitespace()
            .skip_while(|w| *w != "--fit")
            .nth(1)
            .unwrap_or_else(|| panic!("{name} on {m}: {err}"));
        build_clean(
            &example_path(name),
            m,
            &["--fit", fit],
            &format!("{name} --fit {fit}"),
        );
    }
}

/// `build ... --json` with `extra` flags: the summary.
fn build_json(design: &str, machine: &str, extra: &[&str]) -> Json {
    let d = tmpdir("json");
    let out = d.join(format!("out.{}", ext(machine)));
    let mut args = vec![
        "build",
        design,
        "--machine",
        machine,
        "-o",
        out.to_str().unwrap(),
        "--json",
    ];
    args.extend_from_slice(extra);
    let o = skinpath(&args);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", text(&o)))
}

/// (min x, min y, max x, max y) of a `--json` summary (exact: arcs by their extremes).
fn bounds(j: &Json) -> [f64; 4] {
    let v = |a: &str, k: usize| j["bounds"][a][k].as_f64().unwrap();
    [v("min", 0), v("min", 1), v("max", 0), v("max", 1)]
}

#[test]
fn placement_lower_left_center_design_scale_and_fit() {
    let ring = example_path("ring_o");
    // Default: the job's lower-left corner at the work origin (plus two units of the last
    // decimal, 0.002 mm), and the run says where it went.
    let d = tmpdir("place");
    let out = d.join("a.gcode");
    let o = skinpath(&[
        "build",
        &ring,
        "--machine",
        "grbl-laser",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("placed (lower-left)"));
    let j = build_json(&ring, "grbl-laser", &[]);
    let b = bounds(&j);
    assert!(
        (b[0] - 0.002).abs() < 1e-9 && (b[1] - 0.002).abs() < 1e-9,
        "{b:?}"
    );
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    assert_eq!(j["placement"]["place"], "lower-left");
    // --margin moves the corner.
    let bm = bounds(&build_json(&ring, "grbl-laser", &["--margin", "7"]));
    assert!(
        (bm[0] - 7.002).abs() < 1e-9 && (bm[1] - 7.002).abs() < 1e-9,
        "{bm:?}"
    );
    // Centre: the job's centre at the 400 x 400 area's centre, same size.
    let bc = bounds(&build_json(&ring, "grbl-laser", &["--place", "center"]));
    assert!(((bc[0] + bc[2]) / 2.0 - 200.0).abs() < 1e-9, "{bc:?}");
    assert!(((bc[1] + bc[3]) / 2.0 - 200.0).abs() < 1e-9, "{bc:?}");
    assert!((bc[2] - bc[0] - w).abs() < 1e-9 && (bc[3] - bc[1] - h).abs() < 1e-9);
    // --place design: the design's own coordinates (ring_o lies inside the area).
    let jd = build_json(&ring, "grbl-laser", &["--place", "design"]);
    assert_eq!(jd["placement"]["offset"][0].as_f64(), Some(0.0));
    // --scale 2: the outline doubles, a tool offset would not: 2·(w − k) + k with k the
    // offset's share of the width; ring_o has no operations, so a laser cuts it on the
    // line (k = 0).
    let kerf = 0.0;
    let bs = bounds(&build_json(&ring, "grbl-laser", &["--scale", "2"]));
    let want = 2.0 * (w - kerf) + kerf;
    assert!(
        (bs[2] - bs[0] - want).abs() < 0.01,
        "{bs:?} want width {want}"
    );
    // --fit: the binding side becomes the given size, aspect kept; then it checks clean.
    let jf = build_json(&ring, "grbl-laser", &["--fit", "30x200"]);
    let bf = bounds(&jf);
    assert!((bf[2] - bf[0] - 30.0).abs() < 0.01, "{bf:?}");
    let ratio = (bf[3] - bf[1] - kerf) / (bf[2] - bf[0] - kerf);
    assert!(
        (ratio - (h - kerf) / (w - kerf)).abs() < 1e-3,
        "aspect {ratio}"
    );
    build_clean(&ring, "grbl-laser", &["--fit", "30x200"], "fit 30x200");
    // --place design keeps the design's coordinates: the neon example's holes at x < 0
    // do not fit, and the message names the option.
    let d2 = tmpdir("design");
    let out2 = d2.join("n.gcode");
    let o = skinpath(&[
        "build",
        &example_path("neon_word"),
        "--machine",
        "grbl-router",
        "-o",
        out2.to_str().unwrap(),
        "--place",
        "design",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--place lower-left"));
    assert!(!out2.exists());
    // Placement applies to laser SVG and DXF alike.
    for fmt in ["svg", "dxf"] {
        let j = build_json(&ring, "svg-laser", &["--place", "center", "--format", fmt]);
        let b = bounds(&j);
        assert!(((b[0] + b[2]) / 2.0 - 300.0).abs() < 1e-9, "{fmt}: {b:?}");
        assert!(((b[1] + b[3]) / 2.0 - 150.0).abs() < 1e-9, "{fmt}: {b:?}");
    }
}

#[test]
fn marlin_ends_without_m30_and_check_accepts_it() {
    let out = build_clean(&example_path("loop"), "marlin-laser", &[], "loop on marlin");
    let g = std::fs::read_to_string(&out).unwrap();
    let codes: Vec<&str> = g
        .lines()
        .map(|l| l.split(';').next().unwrap_or("").trim())
        .collect();
    assert!(
        !codes
            .iter()
            .any(|l| l.split_whitespace().any(|w| w == "M30" || w == "M2"))
    );
    assert_eq!(codes.iter().rev().find(|l| !l.is_empty()), Some(&"M5"));
    // The checker notes the missing end as info, not as a warning, with the profile.
    let (e, w, j) = check(&out, "marlin-laser");
    assert_eq!((e, w), (0, 0), "{j}");
    assert!(
        j["findings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|f| f["id"] == "missing-program-end" && f["severity"] == "info")
    );
}

#[test]
fn grbl_laser_writes_s0_before_every_rapid_and_states_laser_mode() {
    let out = build_clean(
        &example_path("neon_word"),
        "grbl-laser",
        &[],
        "neon on grbl-laser",
    );
    let g = std::fs::read_to_string(&out).unwrap();
    assert!(
        g.lines().take(5).any(|l| l.contains("$32=1")),
        "header: {g:.300}"
    );
    // Track S as GRBL does (modal), and require S = 0 on every G0 after the first cut.
    let mut s = 0.0;
    let mut motion = "";
    let mut rapids = 0;
    for l in g.lines() {
        let code = l.split('(').next().unwrap_or("");
        let mut has_xy = false;
        for w in code.split_whitespace() {
            let (k, v) = w.split_at(1);
            match k {
                "S" => s = v.parse().unwrap(),
                "G" if v == "0" || v == "1" || v == "2" || v == "3" => {
                    motion = match v {
                        "0" => "G0",
                        _ => "G1",
                    }
                }
                "X" | "Y" => has_xy = true,
                _ => {}
            }
        }
        if has_xy && motion == "G0" {
            rapids += 1;
            assert_eq!(s, 0.0, "rapid with S{s}: {l}");
        }
    }
    assert!(rapids > 3);
}

#[test]
fn laser_default_power_comes_from_the_profile() {
    // ring_o's operations set no power: grbl-laser's default_power is 20 % of S1000.
    let out = build_clean(
        &example_path("ring_o"),
        "grbl-laser",
        &[],
        "ring on grbl-laser",
    );
    let g = std::fs::read_to_string(&out).unwrap();
    let s: Vec<f64> = g
        .split_whitespace()
        .filter_map(|w| w.strip_prefix('S'))
        .filter_map(|v| v.parse().ok())
        .filter(|v: &f64| *v > 0.0)
        .collect();
    assert!(!s.is_empty());
    assert!(s.iter().all(|v| *v == 200.0), "{s:?}");
}

#[test]
fn air_assist_per_operation() {
    let d = tmpdir("air");
    let design = d.join("air.toml");
    let ring = std::fs::read_to_string(example_path("ring_o")).unwrap();
    let base: String = ring
        .lines()
        .take_while(|l| !l.starts_with("[[operation]]"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(
        &design,
        format!(
            "{base}\n[[operation]]\nkind = \"profile\"\nside = \"on\"\nair_assist = true\n\
             power = 50.0\n"
        ),
    )
    .unwrap();
    let out = build_clean(design.to_str().unwrap(), "grbl-laser", &[], "air");
    let g = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = g.lines().collect();
    let on = lines.iter().position(|l| *l == "M8").expect("M8 written");
    let off = lines.iter().position(|l| *l == "M9").expect("M9 written");
    let first_cut = lines
        .iter()
        .position(|l| ["G1 ", "G2 ", "G3 "].iter().any(|g| l.starts_with(g)))
        .unwrap();
    assert!(on < first_cut && off > first_cut, "{on} {off} {first_cut}");
}

#[test]
fn pocket_marks_let_only_marked_pockets_cross() {
    let out = build_clean(&example_path("neon_word"), "grbl-router", &[], "neon");
    let g = std::fs::read_to_string(&out).unwrap();
    assert!(g.contains("(skinpath:group 1)"));
    // Without the marks the same moves are judged strictly: crossings are errors.
    let stripped: String = g
        .lines()
        .filter(|l| !l.contains("skinpath:group"))
        .map(|l| format!("{l}\n"))
        .collect();
    let d = tmpdir("marks");
    let p = d.join("stripped.gcode");
    std::fs::write(&p, stripped).unwrap();
    let (e, _, j) = check(&p, "grbl-router");
    assert!(e > 0, "{j}");
    assert!(
        j["findings"]
            .as_array()
            .unwrap()
            .iter()
            .all(|f| f["id"] == "contour-crossing" || f["severity"] != "error")
    );
}

#[test]
fn build_json_summary() {
    let d = tmpdir("json");
    let out = d.join("e.gcode");
    let o = skinpath(&[
        "build",
        &data("e_channel"),
        "--machine",
        "grbl-router",
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let j: Json = serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", text(&o)));
    let ops = j["operations"].as_array().unwrap();
    assert_eq!(ops.len(), 3);
    // Operations name their index in the design (0-based), in machine order.
    let idx: Vec<i64> = ops
        .iter()
        .map(|o| o["design_index"].as_i64().unwrap())
        .collect();
    assert_eq!(idx, vec![1, 0, 2]);
    let sum: f64 = ops.iter().map(|o| o["cut_length"].as_f64().unwrap()).sum();
    assert!((sum - j["cut_length"].as_f64().unwrap()).abs() < 1e-6 * sum);
    assert_eq!(j["placement"]["place"], "lower-left");
    assert!(j["time"]["with_acceleration"].as_f64().unwrap() > 0.0);
    assert_eq!(j["findings"].as_array().unwrap().len(), 0);
    let min = &j["bounds"]["min"];
    assert!(min[0].as_f64().unwrap() >= 0.0 && min[1].as_f64().unwrap() >= 0.0);
}

#[test]
fn outputs_are_written_as_a_set() {
    let d = tmpdir("set");
    let out = d.join("e.gcode");
    // --preview equal to -o is refused.
    let o = skinpath(&[
        "build",
        &data("e_channel"),
        "--machine",
        "grbl-router",
        "-o",
        out.to_str().unwrap(),
        "--preview",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--preview"));
    assert!(!out.exists());
    // A failing build (no room on the machine) writes no preview either.
    let prev = d.join("p.svg");
    let o = skinpath(&[
        "build",
        &example_path("gclef"),
        "--machine",
        "grbl-router",
        "-o",
        out.to_str().unwrap(),
        "--preview",
        prev.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!prev.exists() && !out.exists());
    // An output folder that does not exist: nothing written, not even the preview.
    let missing = d.join("no-such-folder").join("e.gcode");
    let o = skinpath(&[
        "build",
        &data("e_channel"),
        "--machine",
        "grbl-router",
        "-o",
        missing.to_str().unwrap(),
        "--preview",
        prev.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(!prev.exists());
    // A stale temporary file of a killed run (a process id that is not running) is removed
    // by the next run in that folder; the names are recognisable.
    let stale = d.join(".skinpath-tmp-4194303-e.gcode");
    std::fs::write(&stale, "half a program").unwrap();
    build_clean_in(&d, &data("e_channel"), "grbl-router");
    assert!(!stale.exists());
    let left: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".skinpath-tmp-"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

fn build_clean_in(d: &Path, design: &str, machine: &str) {
    let out = d.join("e.gcode");
    let o = skinpath(&[
        "build",
        design,
        "--machine",
        machine,
        "-o",
        out.to_str().unwrap(),
        "--preview",
        d.join("e.svg").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(out.exists() && d.join("e.svg").exists());
}

#[test]
fn checker_findings_name_the_design_operation_and_stroke() {
    // A profile around stroke b, which crosses the channel of stroke a: the profile (not
    // a pocket) crosses the channel's rings, a real fault traced back to the design.
    let d = tmpdir("trace");
    let design = d.join("t.toml");
    std::fs::write(
        &design,
        "version = 1\n[[stroke]]\nname = \"a\"\npoints = [[0,0,2],[10,0,2],[20,0,2],[30,0,2]]\n\
         [[stroke]]\nname = \"b\"\npoints = [[15,-10,2],[15,-3,2],[15,3,2],[15,10,2]]\n\
         [[operation]]\nkind = \"channel\"\nwidth = 4.0\ndepth = 1.0\nstrokes = [\"a\"]\n\
         [[operation]]\nkind = \"profile\"\nside = \"outside\"\ndepth = 1.0\nstrokes = [\"b\"]\n",
    )
    .unwrap();
    let out = d.join("t.gcode");
    let o = skinpath(&[
        "build",
        design.to_str().unwrap(),
        "--machine",
        "grbl-router",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("t.toml"), "{err}");
    assert!(
        err.contains("[[operation]] 1 (channel 1), stroke \"a\" and [[operation]] 2 (profile 2), stroke \"b\"")
            || err.contains("[[operation]] 2 (profile 2), stroke \"b\" and [[operation]] 1 (channel 1), stroke \"a\""),
        "{err}"
    );
    assert!(err.contains("contour-crossing"), "{err}");
    assert!(!out.exists());
}

#[test]
fn router_profile_without_a_fitting_tool_says_so() {
    let d = tmpdir("notool");
    let profile = d.join("bare.toml");
    let text_ = std::fs::read_to_string(format!("{ROOT}/machines/grbl-router.toml")).unwrap();
    // Keep only the V-bit: a channel needs an end mill.
    let without: String = text_
        .split("[[tools]]")
        .enumerate()
        .filter(|(k, part)| *k == 0 || part.contains("vbit"))
        .map(|(k, part)| {
            if k == 0 {
                part.to_string()
            } else {
                format!("[[tools]]{part}")
            }
        })
        .collect();
    std::fs::write(&profile, without).unwrap();
    let out = d.join("e.gcode");
    let o = skinpath(&[
        "build",
        &data("e_channel"),
        "--machine",
        profile.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("no tool that fits") && err.contains("endmill"),
        "{err}"
    );
    assert!(err.contains("[[operation]] 1 (channel)"), "{err}");
}

#[test]
fn linuxcnc_and_smoothie_programs_follow_their_firmware() {
    // LinuxCNC: spindle off, then M2, with the tool at safe Z (the profile's 0.2 in).
    let out = build_clean(
        &example_path("ring_o"),
        "linuxcnc-router",
        &[],
        "ring on linuxcnc",
    );
    let g = std::fs::read_to_string(&out).unwrap();
    let codes: Vec<&str> = g
        .lines()
        .map(|l| l.split('(').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty())
        .collect();
    let n = codes.len();
    assert_eq!(&codes[n - 2..], &["M5", "M2"], "{:?}", &codes[n - 4..]);
    // Smoothie fires only on G1/G2/G3: rapids carry no S and the program needs no S0.
    let out = build_clean(
        &example_path("circles"),
        "smoothie-laser",
        &[],
        "circles on smoothie",
    );
    let g = std::fs::read_to_string(&out).unwrap();
    for l in g.lines().filter(|l| l.starts_with("G0")) {
        assert!(!l.contains('S'), "{l}");
    }
    // The power rides on a cutting move (an arc where the outline was merged into arcs).
    let cutting = |l: &str| ["G1", "G2", "G3"].iter().any(|g| l.starts_with(g));
    assert!(g.lines().any(|l| cutting(l) && l.contains(" S")));
}
