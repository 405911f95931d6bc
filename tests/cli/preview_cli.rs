//! `skinpath preview` and `build --preview` from the command line: the three formats, for a
//! design and for a G-code program, and the errors a person can act on.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn skinpath(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(args)
        .output()
        .expect("runs")
}

fn root(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .display()
        .to_string()
}

/// This test run's own directory (created on first use).
fn tmp_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("skinpath-preview-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("dir");
    d
}

fn tmp(name: &str) -> PathBuf {
    assert!(
        !name.is_empty() && !name.contains('/'),
        "a file name: {name:?}"
    );
    tmp_dir().join(name)
}

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn design_and_program_in_three_formats() {
    let svg = tmp("circles.svg");
    let png = tmp("circles.png");
    let html = tmp("circles.html");
    let design = root("examples/circles.toml");
    for out in [&svg, &png, &html] {
        let o = skinpath(&[
            "preview",
            &design,
            "--machine",
            "grbl-laser",
            "-o",
            &out.display().to_string(),
        ]);
        ok(&o);
    }
    let text = std::fs::read_to_string(&svg).expect("svg");
    let doc = roxmltree::Document::parse(&text).expect("parses");
    assert!(
        doc.descendants()
            .any(|n| n.attribute("class") == Some("cut"))
    );
    let bytes = std::fs::read(&png).expect("png");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let page = std::fs::read_to_string(&html).expect("html");
    assert!(
        page.contains("skinpathPlayer") && !page.contains("http://") && !page.contains("https://")
    );

    // A program from a file, no machine: PNG at a chosen width.
    let prog_png = tmp("selfx.png");
    let o = skinpath(&[
        "preview",
        &root("tests/sim_corpus/fault_self_intersection.nc"),
        "-o",
        &prog_png.display().to_string(),
        "--width",
        "321",
    ]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("1 findings"));
    let img = resvg::tiny_skia::Pixmap::decode_png(&std::fs::read(&prog_png).expect("png"))
        .expect("decodes");
    assert_eq!(img.width(), 321);

    // build --preview writes the player next to the G-code.
    let gcode = tmp("circles.gcode");
    let player = tmp("circles-build.html");
    let o = skinpath(&[
        "build",
        &design,
        "--machine",
        "grbl-laser",
        "--place",
        "lower-left",
        "--margin",
        "5",
        "-o",
        &gcode.display().to_string(),
        "--preview",
        &player.display().to_string(),
    ]);
    ok(&o);
    let page = std::fs::read_to_string(&player).expect("html");
    // The build passed its checks: the preview shows no error findings (warnings such as
    // GRBL laser-mode rapids may be listed).
    assert!(page.contains("\"findings\":["));
    assert!(
        !page.contains("\"severity\":\"error\""),
        "a checked build previews without errors"
    );
    // Only this run's own directory, never its parent.
    let _ = std::fs::remove_dir_all(tmp_dir());
}

#[test]
fn errors_name_what_to_change() {
    let o = skinpath(&[
        "preview",
        &root("examples/circles.toml"),
        "-o",
        &tmp("x.svg").display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--machine"));
    let o = skinpath(&[
        "preview",
        &root("tests/sim_corpus/clean_laser.nc"),
        "-o",
        &tmp("x.pdf").display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains(".svg, .png or .html"));
}

/// An SVG drawing is a design, as `build` reads it (issue 40, item 13): it used to be read
/// as G-code (an empty preview with dozens of syntax findings, exit 0).
#[test]
fn svg_drawing_previews_as_the_design_it_imports_to() {
    let drawing = root("examples/gallery/badge.svg");
    let out = tmp("badge-preview.svg");
    let o = skinpath(&[
        "preview",
        &drawing,
        "--machine",
        "grbl-laser",
        "-o",
        &out.display().to_string(),
    ]);
    ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let text = std::fs::read_to_string(&out).expect("svg");
    let doc = roxmltree::Document::parse(&text).expect("parses");
    let cuts = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("cut"))
        .count();
    // The same contours `build` makes of the drawing: the build's G-code read back.
    let gcode = tmp("badge.gcode");
    ok(&skinpath(&[
        "build",
        &drawing,
        "--machine",
        "grbl-laser",
        "--place",
        "design",
        "-o",
        &gcode.display().to_string(),
    ]));
    let prog = skinpath(&[
        "preview",
        &gcode.display().to_string(),
        "--machine",
        "grbl-laser",
        "-o",
        &tmp("badge-gcode.svg").display().to_string(),
    ]);
    ok(&prog);
    let contours = |s: &str| {
        s.split(" contours")
            .next()
            .and_then(|h| h.rsplit(' ').next())
            .and_then(|n| n.parse::<usize>().ok())
    };
    assert!(cuts > 0, "{stdout}");
    assert_eq!(contours(&stdout), Some(cuts), "{stdout}");
    assert_eq!(
        contours(&stdout),
        contours(&String::from_utf8_lossy(&prog.stdout)),
        "{stdout}"
    );
    assert!(!text.contains("syntax"), "no G-code syntax findings");
    // A design needs a machine, an SVG drawing too.
    let o = skinpath(&["preview", &drawing, "-o", &out.display().to_string()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--machine"));
}
