//! Preview SVG and PNG: parse the SVG back, count paths against the program, find the
//! planted finding, and read pixels of the PNG drawn from the same drawing.

use glam::DVec2;
use skinpath::emit::preview::svg::view_box;
use skinpath::emit::preview::{PngOptions, ProgramInput, Scene, SvgOptions, scene_png, scene_svg};
use skinpath::sim::{self, Backend, CheckConfig};

fn scene(text: &str, cfg: &CheckConfig) -> Scene {
    let prog = sim::load(Backend::Builtin, text, cfg);
    let report = sim::check(&prog, cfg, &[]);
    Scene::from_program(ProgramInput {
        title: "test",
        program: &prog,
        text: Some(text),
        cfg,
        findings: report.findings,
        draw_work_area: true,
    })
}

fn mm(s: &str) -> f64 {
    s.strip_suffix("mm")
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN)
}

fn count(doc: &roxmltree::Document, class: &str) -> usize {
    doc.descendants()
        .filter(|n| n.attribute("class") == Some(class))
        .count()
}

/// Three separate laser contours (beam switched off between them) and two rapids between.
const THREE_CUTS: &str = "G21 G90\nG0 X10 Y10\nM3 S1000\nG1 X30 F1200\nY30\nM5\nG0 X40 Y10\n\
M3 S1000\nG1 X60\nM5\nG0 X40 Y40\nM3 S400\nG2 X40 Y40 I5 J0\nM5\nM2\n";

#[test]
fn svg_parses_back_with_mm_sizes_and_one_path_per_contour() {
    let cfg = CheckConfig::default();
    let s = scene(THREE_CUTS, &cfg);
    let out = scene_svg(&s, &SvgOptions::default());
    let doc = roxmltree::Document::parse(&out).expect("the preview SVG parses");
    let root = doc.root_element();
    let (w, h) = (
        mm(root.attribute("width").unwrap_or("")),
        mm(root.attribute("height").unwrap_or("")),
    );
    let vb: Vec<f64> = root
        .attribute("viewBox")
        .unwrap_or("")
        .split_whitespace()
        .filter_map(|v| v.parse().ok())
        .collect();
    assert_eq!(vb.len(), 4);
    // 1 user unit = 1 mm.
    assert!(
        (vb[2] - w).abs() < 1e-9 && (vb[3] - h).abs() < 1e-9,
        "{w} {h} {vb:?}"
    );
    // The drawing frames the job (the 300 mm bed is more than 4 times its area) in
    // millimetres: as wide as the framed region, or the legend's minimum width.
    let (lo, hi) = view_box(&s);
    assert!(w >= (hi - lo).x - 1e-9 && w < 300.0, "{w}");
    assert!(lo.x <= 10.0 && hi.x >= 60.0 && lo.y <= 10.0 && hi.y >= 45.0);
    // Three beam-on runs: three contours, three cut paths, three start markers, numbered.
    assert_eq!(count(&doc, "cut"), 3);
    assert_eq!(count(&doc, "start"), 3);
    assert_eq!(count(&doc, "order"), 3);
    assert_eq!(count(&doc, "arrow"), 3);
    // Rapids: origin to (10,10), (30,30) to (40,10), (60,10) to (40,40).
    assert_eq!(count(&doc, "rapid"), 3);
    let rapids = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("rapids"))
        .expect("rapids group");
    assert!(rapids.attribute("stroke-dasharray").is_some());
    // The first cut path goes through the program's points, mapped with y flipped.
    let first = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("contour1"))
        .expect("contour1");
    let d = first.attribute("d").unwrap_or("");
    let nums: Vec<f64> = d
        .split(|c: char| c == 'M' || c == 'L' || c.is_whitespace())
        .filter_map(|v| v.parse().ok())
        .collect();
    let want = [(10.0, 10.0), (30.0, 10.0), (30.0, 30.0)];
    assert_eq!(nums.len(), 2 * want.len(), "{d}");
    for (k, (x, y)) in want.iter().enumerate() {
        assert!((nums[2 * k] - (x - lo.x)).abs() < 1e-3);
        assert!((nums[2 * k + 1] - (hi.y - y)).abs() < 1e-3);
    }
    // The contour at S400 is in a lighter step than the full-power ones.
    let scale = s.color_scale();
    let third = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("contour3"))
        .and_then(|n| n.attribute("stroke"))
        .unwrap_or("");
    assert_eq!(third, scale.color(scale.step(400.0)));
    assert_ne!(third, scale.color(scale.step(1000.0)));
    // No findings, and the legend says so.
    assert!(out.contains("checker: no findings"));
}

#[test]
fn findings_are_drawn_where_the_checker_puts_them() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/sim_corpus/fault_self_intersection.nc"
    ))
    .expect("corpus file");
    let s = scene(&text, &CheckConfig::default());
    let f = s
        .findings
        .iter()
        .find(|f| f.id == "self-intersection")
        .expect("the planted self-intersection is found")
        .clone();
    let out = scene_svg(&s, &SvgOptions::default());
    let doc = roxmltree::Document::parse(&out).expect("parses");
    let rings: Vec<_> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("finding self-intersection"))
        .collect();
    assert!(!rings.is_empty());
    // The bow-tie's diagonals cross at (20, 20).
    let (lo, hi) = view_box(&s);
    let cx: f64 = rings[0]
        .attribute("cx")
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN);
    let cy: f64 = rings[0]
        .attribute("cy")
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN);
    assert!((cx - (20.0 - lo.x)).abs() < 1e-3 && (cy - (hi.y - 20.0)).abs() < 1e-3);
    // Listed with its G-code lines.
    assert!(f.lines.contains(&4) && f.lines.contains(&6));
    let listed = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("finding-text"))
        .filter_map(|n| n.text())
        .any(|t| t.contains("self-intersection") && t.contains("line 4, 6"));
    assert!(listed, "{out}");
}

fn decode(png: &[u8]) -> resvg::tiny_skia::Pixmap {
    resvg::tiny_skia::Pixmap::decode_png(png).expect("a PNG")
}

fn pixel(p: &resvg::tiny_skia::Pixmap, x: f64, y: f64) -> [u8; 3] {
    let c = p
        .pixel(x.round() as u32, y.round() as u32)
        .expect("inside the image");
    [c.red(), c.green(), c.blue()]
}

fn hex(c: &str) -> [u8; 3] {
    let v = u32::from_str_radix(c.trim_start_matches('#'), 16).unwrap_or(0);
    [(v >> 16) as u8, (v >> 8) as u8, v as u8]
}

fn close(a: [u8; 3], b: [u8; 3], tol: i32) -> bool {
    a.iter()
        .zip(b.iter())
        .all(|(x, y)| (*x as i32 - *y as i32).abs() <= tol)
}

#[test]
fn png_has_the_cut_colour_on_a_cut_and_not_beside_it() {
    // A 40 mm square cut at full power, no work area (so the drawing is the job).
    let text = "G21 G90\nG0 X0 Y0\nM3 S1000\nG1 X40 F1200\nY40\nX0\nY0\nM5\nM2\n";
    let cfg = CheckConfig::default();
    let prog = sim::load(Backend::Builtin, text, &cfg);
    let s = Scene::from_program(ProgramInput {
        title: "square",
        program: &prog,
        text: Some(text),
        cfg: &cfg,
        findings: Vec::new(),
        draw_work_area: false,
    });
    let svg = scene_svg(&s, &SvgOptions::default());
    let png = scene_png(&s, &SvgOptions::default(), PngOptions::Width(800)).expect("rasterises");
    let img = decode(&png);
    assert_eq!(img.width(), 800);
    let (lo, hi) = view_box(&s);
    let doc = roxmltree::Document::parse(&svg).expect("parses");
    let page_w: f64 = doc
        .root_element()
        .attribute("viewBox")
        .and_then(|v| v.split_whitespace().nth(2).and_then(|x| x.parse().ok()))
        .unwrap_or(f64::NAN);
    let k = 800.0 / page_w;
    let at = |p: DVec2| ((p.x - lo.x) * k, (hi.y - p.y) * k);
    let cut = hex(&s.color_scale().color(s.color_scale().step(1000.0)));
    // Middle of the right edge, x = 40: on the cut.
    let (x, y) = at(DVec2::new(40.0, 25.0));
    assert!(
        close(pixel(&img, x, y), cut, 8),
        "{:?} vs {cut:?}",
        pixel(&img, x, y)
    );
    // Inside the square, away from every line and marker: background.
    let (x, y) = at(DVec2::new(25.0, 15.0));
    assert!(close(pixel(&img, x, y), [255, 255, 255], 2));
    // DPI sizing: 96 dpi is one CSS pixel per 1/96 inch of the page's millimetres.
    let png = scene_png(&s, &SvgOptions::default(), PngOptions::Dpi(96.0)).expect("rasterises");
    let img = decode(&png);
    let want = (page_w / 25.4 * 96.0).round() as u32;
    assert!(img.width().abs_diff(want) <= 1, "{} vs {want}", img.width());
    assert!(scene_png(&s, &SvgOptions::default(), PngOptions::Width(0)).is_err());
    assert!(scene_png(&s, &SvgOptions::default(), PngOptions::Dpi(f64::NAN)).is_err());
}

#[test]
fn laser_svg_hairlines_are_visible_in_the_png() {
    // The laser SVG's cuts are 0.01 mm hairlines; the preview of the same toolpath draws
    // them at a visible width. Built for the svg-laser profile from a shipped example.
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/circles.toml"
    ))
    .expect("example");
    let design = skinpath::design::load(&text, "circles.toml").expect("design");
    let profile = skinpath::machine::builtin_profile("svg-laser")
        .expect("shipped")
        .expect("valid");
    let built = skinpath::job::build::build_toolpath(
        &design,
        &profile,
        &skinpath::job::build::BuildOptions::default(),
    )
    .expect("builds");
    let cfg = skinpath::job::check::check_config(&profile, 0.0);
    let s = Scene::from_toolpath(
        "circles",
        &built.toolpath,
        design.units.mm_per_unit(),
        &cfg,
        None,
    );
    assert!(!s.contours.is_empty());
    let svg = scene_svg(&s, &SvgOptions::default());
    let img = decode(
        &scene_png(&s, &SvgOptions::default(), PngOptions::Width(1600)).expect("rasterises"),
    );
    let scale = s.color_scale();
    let colors: Vec<[u8; 3]> = (0..skinpath::emit::preview::COLOR_STEPS)
        .map(|k| hex(&scale.color(k)))
        .collect();
    let on_cut = img
        .pixels()
        .iter()
        .filter(|p| {
            let c = [p.red(), p.green(), p.blue()];
            colors.iter().any(|&k| close(c, k, 10))
        })
        .count();
    // Several pixels wide along every contour: far more than a hairline's handful.
    let length: f64 = s
        .contours
        .iter()
        .map(|c| {
            c.points
                .windows(2)
                .map(|w| w[0].distance(w[1]))
                .sum::<f64>()
        })
        .sum();
    let doc = roxmltree::Document::parse(&svg).expect("parses");
    let page_w: f64 = doc
        .root_element()
        .attribute("viewBox")
        .and_then(|v| v.split_whitespace().nth(2).and_then(|x| x.parse().ok()))
        .unwrap_or(f64::NAN);
    let px_per_mm = 1600.0 / page_w;
    assert!(
        on_cut as f64 > 2.0 * length * px_per_mm,
        "{on_cut} cut pixels for {length:.1} mm of cuts at {px_per_mm:.2} px/mm"
    );
}
