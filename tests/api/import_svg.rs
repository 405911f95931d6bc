//! SVG import (issue 12): units, viewBox, nested transforms and `use`, fitting tolerance
//! (both ways, against the SVG centre line computed here with kurbo), corners, y flip,
//! skipped elements and errors.

use crate::support::rng::Rng;
use glam::DVec2;
use kurbo::{CubicBez, ParamCurve, Point};
use skinpath::design::svg::{ImportOptions, MM_PER_PX, import};
use skinpath::design::{Design, load};

fn svg(attrs: &str, body: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" {attrs}>{body}</svg>"#
    )
}

/// Spine points of every (expanded) stroke, densely sampled.
fn spine(d: &Design, name: &str) -> Vec<DVec2> {
    let strokes = d.strokes().unwrap();
    let mut out = Vec::new();
    for (s, c) in d.stroke.iter().zip(&strokes) {
        if s.name == name || s.name.starts_with(&format!("{name}#")) {
            let (lo, hi) = c.domain();
            out.extend((0..=2000).map(|i| c.center(lo + (hi - lo) * i as f64 / 2000.0)));
        }
    }
    out
}

fn dist(p: DVec2, poly: &[DVec2]) -> f64 {
    poly.windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let t = ((p - w[0]).dot(d) / d.length_squared().max(1e-300)).clamp(0.0, 1.0);
            p.distance(w[0] + d * t)
        })
        .fold(f64::INFINITY, f64::min)
}

fn hausdorff(a: &[DVec2], b: &[DVec2]) -> f64 {
    let ab = a.iter().map(|&p| dist(p, b)).fold(0.0, f64::max);
    let ba = b.iter().map(|&p| dist(p, a)).fold(0.0, f64::max);
    ab.max(ba)
}

#[test]
fn line_of_100_mm_with_scaled_viewbox_is_100_mm() {
    // 10 user units across 100 mm: one user unit is 10 mm; stroke-width 0.4 → 4 mm.
    let text = svg(
        r#"width="100mm" height="50mm" viewBox="0 0 10 5""#,
        r#"<path id="l" d="M0 2.5 H10" stroke="black" stroke-width="0.4" fill="none"/>"#,
    );
    let d = load(&text, "line.svg").unwrap();
    let p = spine(&d, "l");
    let len: f64 = p.windows(2).map(|w| w[0].distance(w[1])).sum();
    assert!((len - 100.0).abs() < 1e-3, "{len}");
    assert!((p[0] - DVec2::new(0.0, 25.0)).length() < 1e-3, "{}", p[0]);
    let r = d.stroke[0].points.as_ref().unwrap()[0][2];
    assert!((r - 2.0).abs() < 1e-5, "{r}");
}

#[test]
fn every_unit_resolves_to_millimetres() {
    for (unit, mm) in [
        ("mm", 1.0),
        ("cm", 10.0),
        ("in", 25.4),
        ("pt", 25.4 / 72.0),
        ("pc", 25.4 / 6.0),
        ("px", MM_PER_PX),
        ("", MM_PER_PX),
    ] {
        // Without a viewBox, one user unit is one px; with width in `unit` and a viewBox of
        // 10 units, one user unit is one `unit`.
        let text = svg(
            &format!(r#"width="10{unit}" height="10{unit}" viewBox="0 0 10 10""#),
            r#"<line id="l" x1="0" y1="5" x2="10" y2="5" stroke="black" stroke-width="1"/>"#,
        );
        let d = load(&text, "u.svg").unwrap();
        let p = spine(&d, "l");
        let len = p[0].distance(p[p.len() - 1]);
        assert!(
            (len - 10.0 * mm).abs() < 1e-4 * mm.max(1.0),
            "{unit}: {len}"
        );
    }
}

#[test]
fn nested_transforms_and_use_are_honoured() {
    // The symbol's segment (0,0)-(10,0), placed by use at (5,0), inside a group that
    // scales by 2 then translates by (20,30): ends at (30,30) and (50,30) in px, with a
    // stroke width of 1 × 2 px.
    let text = svg(
        r#"width="100" height="100""#,
        r##"<defs><path id="seg" d="M0 0 L10 0"/></defs>
           <g transform="translate(20 30)"><g transform="scale(2)">
             <use id="u" xlink:href="#seg" x="2.5" y="0" stroke="black" stroke-width="1"/>
           </g></g>"##,
    );
    let imp = import(&text, "t.svg", &ImportOptions::default()).unwrap();
    assert_eq!(imp.design.stroke.len(), 1, "{:?}", imp.skipped);
    let pts = imp.design.stroke[0].points.clone().unwrap();
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let px = |x: f64, y: f64| [x * MM_PER_PX, (100.0 - y) * MM_PER_PX];
    let (ea, eb) = (px(25.0, 30.0), px(45.0, 30.0));
    for (got, want) in [(a, ea), (b, eb)] {
        assert!(
            (got[0] - want[0]).abs() < 1e-4 && (got[1] - want[1]).abs() < 1e-4,
            "{got:?} {want:?}"
        );
    }
    assert!((a[2] - MM_PER_PX).abs() < 1e-5, "radius {}", a[2]);
}

#[test]
fn fitted_spine_within_tolerance_of_the_svg_centre_line() {
    let c = [(10.0, 80.0), (40.0, 0.0), (120.0, 160.0), (190.0, 60.0)];
    let text = svg(
        r#"width="200mm" height="200mm" viewBox="0 0 200 200""#,
        &format!(
            r#"<path id="s" d="M{} {} C{} {} {} {} {} {}" stroke="black" stroke-width="3" fill="none"/>"#,
            c[0].0, c[0].1, c[1].0, c[1].1, c[2].0, c[2].1, c[3].0, c[3].1
        ),
    );
    let bez = CubicBez::new(
        Point::new(c[0].0, c[0].1),
        Point::new(c[1].0, c[1].1),
        Point::new(c[2].0, c[2].1),
        Point::new(c[3].0, c[3].1),
    );
    let truth: Vec<DVec2> = (0..=4000)
        .map(|i| {
            let p = bez.eval(i as f64 / 4000.0);
            DVec2::new(p.x, 200.0 - p.y)
        })
        .collect();
    for tol in [0.2, 0.05, 0.01] {
        let opts = ImportOptions {
            tolerance: tol,
            ..ImportOptions::default()
        };
        let mut d = import(&text, "fit.svg", &opts).unwrap().design;
        d.expand().unwrap();
        let h = hausdorff(&spine(&d, "s"), &truth);
        // The dense samples' chords add well under 1 µm here.
        assert!(h <= tol, "tolerance {tol}: distance {h}");
    }
}

#[test]
fn corners_are_kept_and_y_points_up() {
    // Up then right in SVG coordinates (y down): in the design the first leg goes down.
    let text = svg(
        r#"width="100mm" height="100mm" viewBox="0 0 100 100""#,
        r#"<polyline id="el" points="10,10 10,60 60,60" stroke="black" stroke-width="2" fill="none"/>"#,
    );
    let imp = import(&text, "c.svg", &ImportOptions::default()).unwrap();
    let s = &imp.design.stroke[0];
    assert_eq!(s.corners.as_deref(), Some(&[1usize][..]));
    let p = s.points.as_ref().unwrap();
    assert!(
        (p[0][1] - 90.0).abs() < 1e-5 && (p[1][1] - 40.0).abs() < 1e-5,
        "{p:?}"
    );
    let d = load(&text, "c.svg").unwrap();
    let names: Vec<&str> = d.stroke.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["el#0", "el#1"]);
    assert_eq!(d.corners.len(), 1);
    let at = d.corners[0].at;
    assert!(
        (at[0] - 10.0).abs() < 1e-5 && (at[1] - 40.0).abs() < 1e-5,
        "{at:?}"
    );
}

#[test]
fn varying_widths_from_data_attribute() {
    let text = svg(
        r#"width="100mm" height="100mm" viewBox="0 0 100 100""#,
        r#"<path id="t" d="M0 50 H100" stroke="black" stroke-width="1" data-skinpath-widths="2 10"/>"#,
    );
    let d = load(&text, "w.svg").unwrap();
    let c = &d.strokes().unwrap()[0];
    let (lo, hi) = c.domain();
    for k in 0..=10 {
        let t = lo + (hi - lo) * k as f64 / 10.0;
        let x = c.center(t).x;
        let want = 0.5 * (2.0 + 8.0 * x / 100.0);
        assert!(
            (c.radius(t) - want).abs() < 1e-3,
            "x {x}: r {} want {want}",
            c.radius(t)
        );
    }
    let bad = text.replace("2 10", "2 -1");
    let e = load(&bad, "w.svg").unwrap_err().to_string();
    // The only element is skipped with its reason: nothing usable, an error naming both.
    assert!(
        e.contains("w.svg") && e.contains("t (") && e.contains("-1"),
        "{e}"
    );
}

#[test]
fn skipped_elements_are_listed_by_id() {
    let text = svg(
        r#"width="100mm" height="100mm" viewBox="0 0 100 100""#,
        r#"<rect id="plate" x="0" y="0" width="10" height="10" fill="red"/>
           <rect x="20" y="0" width="10" height="10" fill="blue"/>
           <path d="M0 70 H50" fill="none"/>
           <text id="caption" x="0" y="90">hello</text>
           <path id="keep" d="M0 50 H50" stroke="black"/>"#,
    );
    let imp = import(&text, "s.svg", &ImportOptions::default()).unwrap();
    let ids: Vec<&str> = imp.skipped.iter().map(|s| s.id.as_str()).collect();
    assert!(ids.contains(&"caption"), "{ids:?}");
    // Filled shapes are imported as shapes (issue 12 item 3), not skipped.
    assert!(!ids.contains(&"plate"), "{ids:?}");
    let shapes: Vec<&str> = imp.design.shape.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(shapes.len(), 2, "{shapes:?}");
    assert!(shapes.contains(&"plate"), "{shapes:?}");
    // The unnamed path with neither fill nor stroke is listed by its place.
    assert!(ids.iter().any(|i| i.starts_with("<path> #")), "{ids:?}");
    assert!(imp.skipped.iter().all(|s| !s.reason.is_empty()));
    assert_eq!(imp.design.stroke.len(), 1);
}

#[test]
fn malformed_svg_names_the_file_and_line() {
    let e = load(
        "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<path d=\"M0 0\">\n</svg>",
        "bad.svg",
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("bad.svg:"), "{e}");
    assert!(e.contains(":3:") || e.contains(":2:"), "{e}");
}

/// An Inkscape Power Stroke: a filled outline (its `d` is ignored) drawn from the centre line
/// `inkscape:original-d` and the effect's width points.
fn power_stroke(id: &str, original_d: &str, offsets: &str, extra: &str, transform: &str) -> String {
    format!(
        r##"<defs><inkscape:path-effect id="{id}-lpe" effect="powerstroke" offset_points="{offsets}" {extra}/></defs>
           <path id="{id}" d="M0 0 H1 V1 Z" fill="black" transform="{transform}"
                 inkscape:path-effect="#{id}-lpe" inkscape:original-d="{original_d}"/>"##
    )
}

#[test]
fn inkscape_power_stroke_is_imported_with_its_widths() {
    let ns = r#"xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="100mm" height="100mm" viewBox="0 0 100 100""#;
    // Two line segments (path time 0..2), butt caps: the width points hold to the ends.
    let text = svg(
        ns,
        &power_stroke(
            "lines",
            "M 0,50 L 50,50 L 100,50",
            "0.5,1 | 1,4 | 1.5,1",
            r#"start_linecap_type="butt" end_linecap_type="round""#,
            "",
        ),
    );
    let imp = import(&text, "p.svg", &ImportOptions::default()).unwrap();
    assert!(imp.skipped.is_empty(), "{:?}", imp.skipped);
    let d = load(&text, "p.svg").unwrap();
    let c = &d.strokes().unwrap()[0];
    let (lo, hi) = c.domain();
    // Expected half width at x (path time x / 50), linear between the points.
    let want = |x: f64| {
        let t = x / 50.0;
        if t <= 0.5 || t >= 1.5 {
            1.0
        } else if t <= 1.0 {
            1.0 + 3.0 * (t - 0.5) / 0.5
        } else {
            4.0 - 3.0 * (t - 1.0) / 0.5
        }
    };
    for k in 0..=40 {
        let t = lo + (hi - lo) * k as f64 / 40.0;
        let p = c.center(t);
        assert!((p.y - 50.0).abs() < 1e-3, "{p}");
        assert!(
            (c.radius(t) - want(p.x)).abs() < 0.1,
            "x {}: r {} want {}",
            p.x,
            c.radius(t),
            want(p.x)
        );
    }

    // A curve under a transform, zero-width caps (Inkscape's default): widths scale with the
    // transform and run down to half the tolerance at both ends; the spine follows the
    // original centre line, not the filled outline.
    let text = svg(
        ns,
        &power_stroke(
            "curve",
            "M 10,50 C 30,10 70,90 90,50",
            "0.5,3",
            r#"scale_width="2""#,
            "scale(0.5)",
        ),
    );
    let d = load(&text, "p.svg").unwrap();
    let c = &d.strokes().unwrap()[0];
    let (lo, hi) = c.domain();
    let tol = ImportOptions::default().tolerance;
    assert!((c.radius(lo) - 0.5 * tol).abs() < 1e-6, "{}", c.radius(lo));
    assert!((c.radius(hi) - 0.5 * tol).abs() < 1e-6, "{}", c.radius(hi));
    let peak = (0..=200)
        .map(|k| c.radius(lo + (hi - lo) * k as f64 / 200.0))
        .fold(0.0, f64::max);
    assert!((peak - 3.0).abs() < 0.05, "peak radius {peak}");
    let cubic = CubicBez::new(
        Point::new(10.0, 50.0),
        Point::new(30.0, 10.0),
        Point::new(70.0, 90.0),
        Point::new(90.0, 50.0),
    );
    let truth: Vec<DVec2> = (0..=400)
        .map(|k| {
            let p = cubic.eval(k as f64 / 400.0);
            DVec2::new(0.5 * p.x, 100.0 - 0.5 * p.y)
        })
        .collect();
    let h = hausdorff(&spine(&d, "curve"), &truth);
    assert!(h < tol + 1e-3, "spine {h} from the centre line");

    // A width point that is not "time,width" is an error naming the element.
    let bad = text.replace("0.5,3", "0.5;3");
    let e = load(&bad, "p.svg").unwrap_err().to_string();
    assert!(
        e.contains("p.svg") && e.contains("curve (") && e.contains("Power Stroke"),
        "{e}"
    );
}

/// A fuzzed copy of a laser SVG (tests/robust_data/fuzz_svg_singular.svg): the runs of its
/// first path interpolate one by one but not all together (a singular 124×124 system), and
/// the importer once wrote that stroke anyway, so the design did not build. The path is
/// skipped with the reason, and everything imported builds.
#[test]
fn a_path_no_stroke_interpolates_is_skipped_with_the_reason() {
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/robust_data/fuzz_svg_singular.svg"
    );
    let text = std::fs::read_to_string(file).unwrap();
    let imp = import(&text, "fuzz.svg", &ImportOptions::default()).unwrap();
    let skipped = imp
        .skipped
        .iter()
        .find(|s| s.id == "op0-cut0")
        .expect("op0-cut0 skipped");
    assert!(skipped.reason.contains("singular"), "{}", skipped.reason);
    assert!(imp.design.stroke.iter().all(|s| s.name != "op0-cut0"));
    assert!(!imp.design.stroke.is_empty());
    imp.design.strokes().expect("what is imported builds");
}

/// An Illustrator-style file: XML declaration, a DOCTYPE with an internal subset of entities
/// (the namespace URIs), entities used in attributes.
const ILLUSTRATOR: &str = r#"<?xml version="1.0" encoding="utf-8"?>
<!-- Generator: Adobe Illustrator 16.0.0, SVG Export Plug-In . SVG Version: 6.00 Build 0)  -->
<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" "http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd" [
	<!ENTITY ns_svg "http://www.w3.org/2000/svg">
	<!ENTITY ns_xlink "http://www.w3.org/1999/xlink">
	<!ENTITY st "black">
]>
<svg version="1.1" xmlns="&ns_svg;" xmlns:xlink="&ns_xlink;" width="100mm" height="100mm" viewBox="0 0 100 100">
<path id="line" d="M10 50 H90" stroke="&st;" stroke-width="2" fill="none"/>
</svg>"#;

#[test]
fn doctype_with_internal_entities_is_read() {
    let imp = import(ILLUSTRATOR, "ai.svg", &ImportOptions::default()).unwrap();
    assert_eq!(imp.design.stroke.len(), 1);
    let p = imp.design.stroke[0].points.as_ref().unwrap();
    // 80 user units = 80 mm; width 2 → radius 1.
    let len = p[0][0] - p[p.len() - 1][0];
    assert!((len.abs() - 80.0).abs() < 1e-3, "{len}");
    assert!((p[0][2] - 1.0).abs() < 1e-6, "{p:?}");
    // A plain DOCTYPE without a subset (Batik, CorelDRAW) too.
    let plain = r#"<?xml version="1.0"?><!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.0//EN" "http://www.w3.org/TR/2001/REC-SVG-20010904/DTD/svg10.dtd"><svg xmlns="http://www.w3.org/2000/svg" width="10mm" height="10mm" viewBox="0 0 10 10"><path id="a" d="M1 5 H9" stroke="black"/></svg>"#;
    assert_eq!(
        import(plain, "b.svg", &ImportOptions::default())
            .unwrap()
            .design
            .stroke
            .len(),
        1
    );
}

/// A "billion laughs" document: each entity is ten of the one before.
fn entity_bomb(levels: usize) -> String {
    let mut dtd = String::from("<!ENTITY l0 \"lol\">");
    for i in 1..=levels {
        let refs: String = (0..10).map(|_| format!("&l{};", i - 1)).collect();
        dtd.push_str(&format!("<!ENTITY l{i} \"{refs}\">"));
    }
    format!(
        "<?xml version=\"1.0\"?><!DOCTYPE svg [{dtd}]><svg xmlns=\"http://www.w3.org/2000/svg\"><text>&l{levels};</text></svg>"
    )
}

#[test]
fn entity_bomb_is_an_error_naming_the_file() {
    // 3 · 10⁹ characters asked for; refused from the declarations before any expansion.
    let e = import(&entity_bomb(9), "bomb.svg", &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("bomb.svg:"), "{e}");
    assert!(e.contains("entity"), "{e}");
    // Many references to one large entity at the top level (each within roxmltree's own
    // per-reference limits) add up, and are refused too: 10⁴ × 10⁴ characters.
    let big = "x".repeat(10_000);
    let refs = "&big;".repeat(10_000);
    let text = format!(
        "<!DOCTYPE svg [<!ENTITY big \"{big}\">]><svg xmlns=\"http://www.w3.org/2000/svg\"><desc>{refs}</desc></svg>"
    );
    let e = import(&text, "wide.svg", &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("wide.svg:") && e.contains("expand"), "{e}");
}

#[test]
fn external_entities_are_never_read() {
    // The entity points at a file that exists; referring to it is an error, its content
    // never appears.
    for uri in [
        "/etc/hostname",
        "file:///etc/passwd",
        "http://example.com/x",
    ] {
        let text = format!(
            r#"<!DOCTYPE svg [<!ENTITY ext SYSTEM "{uri}">]><svg xmlns="http://www.w3.org/2000/svg" width="10mm" height="10mm"><path id="&ext;" d="M1 1 H9" stroke="black"/></svg>"#
        );
        let e = import(&text, "ext.svg", &ImportOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("ext.svg:") && e.contains("external"), "{e}");
    }
    // Declared but not used: the file imports, the entity is not read.
    let text = r#"<!DOCTYPE svg [<!ENTITY ext SYSTEM "/etc/passwd">]><svg xmlns="http://www.w3.org/2000/svg" width="10mm" height="10mm"><path id="p" d="M1 1 H9" stroke="black"/></svg>"#;
    let imp = import(text, "ext.svg", &ImportOptions::default()).unwrap();
    assert_eq!(imp.design.stroke[0].name, "p");
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let depth = 100_000;
    let text = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\">{}<path d=\"M0 0 H1\" stroke=\"black\"/>{}</svg>",
        "<g>".repeat(depth),
        "</g>".repeat(depth)
    );
    let e = import(&text, "deep.svg", &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("deep.svg:") && e.contains("nest"), "{e}");
    // A modest depth imports.
    let text = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10mm\" height=\"10mm\">{}<path id=\"p\" d=\"M0 0 H1\" stroke=\"black\"/>{}</svg>",
        "<g>".repeat(250),
        "</g>".repeat(250)
    );
    assert_eq!(
        import(&text, "ok.svg", &ImportOptions::default())
            .unwrap()
            .design
            .stroke
            .len(),
        1
    );
}

// ---- Issue 40 items 8–12: hostile drawings. Each either imports or is refused with a
// reason naming the file or the element; the counts are checked before the work.

fn page(body: &str) -> String {
    svg(
        r#"width="200mm" height="200mm" viewBox="0 0 200 200""#,
        body,
    )
}

fn reasons(imp: &skinpath::design::svg::Imported) -> Vec<(String, String)> {
    imp.skipped
        .iter()
        .map(|s| (s.id.clone(), s.reason.clone()))
        .collect()
}

#[test]
fn two_thousand_equal_ids_get_distinct_names() {
    let body: String = (0..2000)
        .map(|i| {
            format!(
                r#"<path id="same" d="M{} {} l5 3" stroke="black" fill="none"/>"#,
                i % 190,
                i / 190 + 1
            )
        })
        .collect();
    let imp = import(&page(&body), "ids.svg", &ImportOptions::default()).unwrap();
    let names: std::collections::HashSet<&str> =
        imp.design.stroke.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names.len(), 2000);
    // The first keeps the id, the k-th (k ≥ 1) is `same~k`.
    assert!(names.contains("same") && names.contains("same~1") && names.contains("same~1999"));
    // A taken suffixed name is stepped over, not reused.
    let body = r#"<path id="a~1" d="M0 0 H9" stroke="black"/><path id="a" d="M0 5 H9" stroke="black"/><path id="a" d="M0 9 H9" stroke="black"/>"#;
    let imp = import(&page(body), "ids.svg", &ImportOptions::default()).unwrap();
    let names: Vec<&str> = imp.design.stroke.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["a~1", "a", "a~2"]);
}

#[test]
fn oversized_paths_and_fills_are_refused_by_count() {
    // A 10⁶-segment zigzag: refused from the segment count, before it is flattened.
    let n = 1_000_000;
    let mut d = String::from("M0 0");
    for i in 1..n {
        d.push_str(&format!(" L{} {:.4}", (i % 2) * 10, i as f64 * 1e-4));
    }
    let body = format!(
        r#"<path id="zz" d="{d}" stroke="black" fill="none"/><path id="ok" d="M0 50 H100" stroke="black"/>"#
    );
    let imp = import(&page(&body), "zz.svg", &ImportOptions::default()).unwrap();
    let r = reasons(&imp);
    assert!(
        r.iter()
            .any(|(id, why)| id == "zz" && why.contains(&format!("{} segments", n - 1))),
        "{r:?}"
    );
    assert_eq!(imp.design.stroke.len(), 1);
    // A fill of 10⁶ points: the same.
    let pts: String = (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            format!(
                "{:.5},{:.5} ",
                100.0 + 90.0 * a.cos(),
                100.0 + 90.0 * a.sin()
            )
        })
        .collect();
    let body = format!(r#"<polygon id="big" points="{pts}" fill="black"/>"#);
    let e = import(&page(&body), "big.svg", &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("big.svg:") && e.contains("big (fill with a subpath of"),
        "{e}"
    );
}

/// A polygon through `n` pseudo-random points of the page (the tests' generator, fixed seed): its
/// edges cross each other about n²/10 times.
fn random_polygon(n: usize) -> String {
    let mut rng = Rng::new(0x9E37_79B9_7F4A_7C15);
    let mut next = || rng.range(0.0, 200.0);
    (0..n)
        .map(|_| format!("{:.3},{:.3} ", next(), next()))
        .collect()
}

#[test]
fn a_fill_crossing_itself_too_often_is_skipped_and_a_modest_one_resolved() {
    let body = format!(
        r#"<polygon id="star" points="{}" fill="black"/><path id="ok" d="M0 50 H100" stroke="black"/>"#,
        random_polygon(10_000)
    );
    let imp = import(&page(&body), "x.svg", &ImportOptions::default()).unwrap();
    let r = reasons(&imp);
    assert!(
        r.iter()
            .any(|(id, why)| id == "star" && why.contains("crosses itself more than")),
        "{r:?}"
    );
    // A pentagram (5 crossings) resolves to a shape with the area of its nonzero fill.
    let star = r#"<polygon id="p" points="100,10 153,172 15,72 185,72 47,172" fill="black"/>"#;
    let imp = import(&page(star), "p.svg", &ImportOptions::default()).unwrap();
    let shape = &imp.design.shape[0];
    let area: f64 = shape
        .rings()
        .iter()
        .map(|r| skinpath::design::shape::ring_area(r))
        .sum();
    // Nonzero fills the whole pentagram, centre included: its area counted independently
    // on a 1000 × 1000 grid of cell centres by the winding number (Sunday's rule).
    let p = [
        (100.0, 10.0),
        (153.0, 172.0),
        (15.0, 72.0),
        (185.0, 72.0),
        (47.0, 172.0),
    ];
    let winding = |x: f64, y: f64| {
        let mut w = 0;
        for i in 0..5 {
            let ((ax, ay), (bx, by)) = (p[i], p[(i + 1) % 5]);
            let side = (bx - ax) * (y - ay) - (x - ax) * (by - ay);
            if ay <= y && by > y && side > 0.0 {
                w += 1;
            } else if ay > y && by <= y && side < 0.0 {
                w -= 1;
            }
        }
        w
    };
    let (n, x0, y0, span) = (1000, 10.0, 5.0, 180.0);
    let cell = span / n as f64;
    let inside = (0..n * n)
        .filter(|k| {
            let (i, j) = (k % n, k / n);
            winding(x0 + (i as f64 + 0.5) * cell, y0 + (j as f64 + 0.5) * cell) != 0
        })
        .count();
    let want = inside as f64 * cell * cell;
    assert!((area.abs() - want).abs() < 5e-3 * want, "{area} vs {want}");
}

#[test]
fn too_many_css_rules_are_refused_before_styling() {
    let rules: String = (0..10_000)
        .map(|i| format!(".c{i}{{stroke:#{:06x};stroke-width:1}}", i))
        .collect();
    let body = format!(r#"<style>{rules}</style><path id="a" class="c5" d="M0 0 L10 10"/>"#);
    let e = import(&page(&body), "css.svg", &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("css.svg:") && e.contains("CSS rules"), "{e}");
    // A few hundred rules are styled as usual.
    let rules: String = (0..300)
        .map(|i| format!(".c{i}{{stroke:#{:06x};stroke-width:{}}}", i, 1 + i % 3))
        .collect();
    let body =
        format!(r#"<style>{rules}</style><path id="a" class="c5" d="M0 0 L10 10" fill="none"/>"#);
    let imp = import(&page(&body), "css.svg", &ImportOptions::default()).unwrap();
    // .c5: stroke-width 1 + 5 % 3 = 3 → radius 1.5 mm (1 user unit = 1 mm).
    let r = imp.design.stroke[0].points.as_ref().unwrap()[0][2];
    assert!((r - 1.5).abs() < 1e-6, "{r}");
}

#[test]
fn power_stroke_far_wider_than_the_tolerance_warns_with_the_worst_error() {
    let text = page(
        r##"<defs><inkscape:path-effect xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" id="pe" effect="powerstroke" offset_points="0.5,100000" start_linecap_type="zerowidth" end_linecap_type="zerowidth"/></defs><path xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" id="ps" inkscape:path-effect="#pe" inkscape:original-d="M10 100 C 60 20 140 180 190 100" d="M10 100 L190 100 L190 101 Z" fill="black"/>"##,
    );
    let opts = ImportOptions::default();
    let imp = import(&text, "ps.svg", &opts).unwrap();
    let w: Vec<_> = imp.warnings.iter().filter(|w| w.id == "ps").collect();
    assert_eq!(w.len(), 1, "{:?}", imp.warnings);
    // The warning carries the worst error, which is the import's max_deviation and over the
    // tolerance.
    assert!(imp.max_deviation > opts.tolerance);
    assert!(
        w[0].reason
            .contains(&format!("{:.4} mm", imp.max_deviation)),
        "{:?}",
        w[0]
    );
}

#[test]
fn a_bad_element_is_skipped_with_its_reason_and_the_rest_imported() {
    let body = r#"<path id="closedtiny" d="M10 10 L10.00001 10 Z" stroke="black" fill="none"/>
        <path id="far" d="M0 0 L1e12 0" stroke="black" fill="none"/>
        <path id="badw" d="M0 20 H50" stroke="black" data-skinpath-widths="1 -2"/>
        <text id="t" x="0" y="10">hi</text>
        <image id="im" href="data:image/png;base64,AAAA" width="5" height="5"/>
        <path id="bad" d="M 0 0 L 10 10 Q zz" stroke="black" fill="none"/>
        <path id="bad2" d="zz" stroke="black" fill="none"/>
        <path id="w0" d="M0 20 H50" stroke="black" stroke-width="0" fill="none"/>
        <g stroke-width="-5"><path id="wneg" d="M0 30 H50" stroke="black" fill="none"/></g>
        <path id="ok" d="M0 50 H100" stroke="black" fill="none"/>"#;
    let imp = import(&page(body), "bad.svg", &ImportOptions::default()).unwrap();
    let r = reasons(&imp);
    let why = |id: &str| {
        r.iter()
            .find(|(i, _)| i == id)
            .map(|(_, w)| w.clone())
            .unwrap_or_else(|| panic!("{id} not listed: {r:?}"))
    };
    assert!(why("far").contains("beyond"), "{r:?}");
    assert!(why("badw").contains("-2"), "{r:?}");
    assert!(why("t").contains("text"), "{r:?}");
    assert!(why("im").contains("raster"), "{r:?}");
    assert!(why("bad2").contains("malformed"), "{r:?}");
    assert!(why("w0").starts_with("stroke-width 0"), "{r:?}");
    assert!(why("wneg").starts_with("stroke-width -5"), "{r:?}");
    assert!(!why("w0").contains("hidden"));
    // Data up to the error is imported, with a warning.
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.id == "bad" && w.reason.contains("malformed"))
    );
    let names: Vec<&str> = imp.design.stroke.iter().map(|s| s.name.as_str()).collect();
    assert!(names.contains(&"ok") && names.contains(&"bad"), "{names:?}");
    // Errors never name an output file: nothing usable names the SVG and what was skipped.
    let e = import(
        &page(r#"<text id="t">x</text><path id="w0" d="M0 0 H5" stroke="black" stroke-width="0" fill="none"/>"#),
        "none.svg",
        &ImportOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("none.svg:") && e.contains("2 element(s) skipped") && e.contains("w0 ("),
        "{e}"
    );
}

/// Runs `skinpath import` as a child under a 120 s limit and 4 GB of address space (a hang
/// or runaway memory guard, never a speed test): exit code and stderr.
fn import_limited(svg: &std::path::Path, out: &std::path::Path) -> (Option<i32>, String) {
    let cmd = format!(
        "ulimit -v 4000000; exec timeout -s KILL 120 '{}' import '{}' -o '{}'",
        env!("CARGO_BIN_EXE_skinpath"),
        svg.display(),
        out.display()
    );
    let o = std::process::Command::new("sh")
        .args(["-c", &cmd])
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn tmp(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("skinpath-import-svg-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn image_references_are_never_opened() {
    // A FIFO that nobody writes: opening it would block forever; /dev/zero would be read
    // without end. Both stay closed: the import ends, the images are listed as skipped.
    let d = tmp("images");
    let fifo = d.join("fifo");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    let body = format!(
        r#"<image id="z" href="/dev/zero" width="10" height="10"/><image id="pw" href="/etc/passwd" width="10" height="10"/><image id="up" href="../../../../etc/passwd" width="10" height="10"/><image id="f" href="{}" width="10" height="10"/><feImage/><path id="k" d="M0 0 H10" stroke="black"/>"#,
        fifo.display()
    );
    let svg = d.join("img.svg");
    std::fs::write(&svg, page(&body)).unwrap();
    let out = d.join("img.toml");
    let (code, err) = import_limited(&svg, &out);
    assert_eq!(code, Some(0), "{err}");
    for id in ["z", "pw", "up", "f"] {
        assert!(
            err.contains(&format!("skipped {id}: raster images")),
            "{err}"
        );
    }
    assert!(made, "mkfifo");
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(!written.contains("root:"), "{written}");
}

#[test]
fn cli_import_of_many_paths_ends_and_nothing_usable_writes_nothing() {
    let d = tmp("many");
    // 2·10⁴ short paths: the import is linear in the drawing (no name search, no element
    // search per path); the child limit only guards against a regression to a hang.
    let body: String = (0..20_000)
        .map(|i| {
            format!(
                r#"<path id="p{i}" d="M{} {} l3 2" stroke="black" stroke-width="0.2" fill="none"/>"#,
                (i * 7) % 190,
                (i * 13) % 190
            )
        })
        .collect();
    let svg = d.join("many.svg");
    std::fs::write(&svg, page(&body)).unwrap();
    let out = d.join("many.toml");
    let (code, err) = import_limited(&svg, &out);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("imported 20000 stroke(s)"), "{err}");
    // Nothing usable: an error naming the SVG (not the output), nothing written.
    let svg = d.join("none.svg");
    std::fs::write(&svg, page(r#"<text id="t">x</text>"#)).unwrap();
    let out = d.join("none.toml");
    let (code, err) = import_limited(&svg, &out);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("none.svg:") && !err.contains("none.toml"),
        "{err}"
    );
    assert!(!out.exists());
}

// ---- Issue 39 item 1 (import side): real path data is cleaned within the tolerance.

#[test]
fn repeated_points_and_zero_length_segments_are_merged() {
    let body = r#"<path id="r" d="M0 10 L0 10 L10 10 L10 10 L10.000001 10 L20 15 L20 15" stroke="black" fill="none"/>"#;
    let opts = ImportOptions::default();
    let imp = import(&page(body), "r.svg", &opts).unwrap();
    assert!(imp.skipped.is_empty(), "{:?}", imp.skipped);
    let d = {
        let mut d = imp.design;
        d.expand().unwrap();
        d
    };
    let truth = [
        DVec2::new(0.0, 190.0),
        DVec2::new(10.0, 190.0),
        DVec2::new(20.0, 185.0),
    ];
    let h = hausdorff(&spine(&d, "r"), &truth);
    assert!(h <= opts.tolerance, "{h}");
}

#[test]
fn a_path_drawn_back_to_its_start_is_a_closed_stroke() {
    // No `Z`: the pen ends 0.01 mm from where it started (within the 0.05 mm tolerance).
    let body =
        r#"<path id="sq" d="M10 10 L50 10 L50 50 L10 50 L10 10.01" stroke="black" fill="none"/>"#;
    let imp = import(&page(body), "c.svg", &ImportOptions::default()).unwrap();
    let s = &imp.design.stroke[0];
    assert!(s.closed, "{s:?}");
    // Four corners of the square, the start one included.
    assert_eq!(s.corners.as_ref().map(Vec::len), Some(4), "{s:?}");
    // 1 mm away is a gap the user drew: the stroke stays open.
    let body =
        r#"<path id="u" d="M10 10 L50 10 L50 50 L10 50 L10 11" stroke="black" fill="none"/>"#;
    let imp = import(&page(body), "c.svg", &ImportOptions::default()).unwrap();
    assert!(!imp.design.stroke[0].closed);
}

#[test]
fn pen_jitter_is_not_a_corner_and_real_corners_stay() {
    // A 60 mm line digitised every 0.2 mm with ±0.01 mm of noise across it: every vertex
    // turns by about 11°, the zig-zag of a shaky pen, above nothing the eye sees.
    let mut d = String::from("M10 100");
    for i in 1..=300 {
        let y = 100.0 + if i % 2 == 0 { 0.01 } else { -0.01 };
        d.push_str(&format!(" L{:.3} {y:.3}", 10.0 + 0.2 * i as f64));
    }
    // Then a real 90° corner and 20 mm up.
    d.push_str(" L70 80");
    let body = format!(r#"<path id="j" d="{d}" stroke="black" stroke-width="1" fill="none"/>"#);
    let opts = ImportOptions {
        corner_angle: 5.0,
        ..ImportOptions::default()
    };
    let imp = import(&page(&body), "j.svg", &opts).unwrap();
    let s = &imp.design.stroke[0];
    // One corner: the right angle at (70, 100); the jitter turns (above the 5° corner
    // angle) are not corners.
    assert_eq!(s.corners.as_ref().map(Vec::len), Some(1), "{:?}", s.corners);
    let pts = s.points.as_ref().unwrap();
    let c = pts[s.corners.as_ref().unwrap()[0]];
    assert!(
        (c[0] - 70.0).abs() < 0.05 && (c[1] - 100.0).abs() < 0.05,
        "{c:?}"
    );
    assert!(imp.warnings.is_empty(), "{:?}", imp.warnings);
    assert!(imp.max_deviation <= opts.tolerance, "{}", imp.max_deviation);
}

// ---- Issue 39 item 2 (SVG side): layers, colours and the paint model.

fn area(s: &skinpath::design::Shape) -> f64 {
    s.rings()
        .iter()
        .map(|r| skinpath::design::shape::ring_area(r))
        .sum()
}

#[test]
fn inkscape_layers_and_colours_are_kept() {
    let text = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="100mm" height="100mm" viewBox="0 0 100 100">
      <g inkscape:groupmode="layer" inkscape:label="Cut" id="layer1">
        <path id="path12" d="M10 10 H90" stroke="#FF0000" stroke-width="0.1" fill="none"/>
        <g id="g7"><rect id="r1" x="10" y="20" width="30" height="30" fill="rgb(0,0,255)"/></g>
      </g>
      <g inkscape:groupmode="layer" inkscape:label="Engrave" id="layer2">
        <path d="M10 80 H90" stroke="black" fill="none"/>
      </g>
      <path id="loose" d="M10 90 H90" stroke="#00ff00" fill="none"/>
    </svg>"##;
    let imp = import(text, "l.svg", &ImportOptions::default()).unwrap();
    let by = |n: &str| {
        imp.design
            .stroke
            .iter()
            .find(|s| s.name == n)
            .unwrap_or_else(|| panic!("{n}: {:?}", imp.design.stroke))
    };
    let s = by("Cut/path12");
    assert_eq!(s.layer.as_deref(), Some("Cut"));
    assert_eq!(s.color.as_deref(), Some("#ff0000"));
    let e = imp
        .design
        .stroke
        .iter()
        .find(|s| s.name.starts_with("Engrave/"))
        .unwrap();
    assert_eq!(
        (e.layer.as_deref(), e.color.as_deref()),
        (Some("Engrave"), Some("#000000"))
    );
    let l = by("loose");
    assert_eq!(
        (l.layer.as_deref(), l.color.as_deref()),
        (None, Some("#00ff00"))
    );
    let r = &imp.design.shape[0];
    assert_eq!(r.name, "Cut/r1");
    assert_eq!(
        (r.layer.as_deref(), r.color.as_deref()),
        (Some("Cut"), Some("#0000ff"))
    );
    // The design writes and reads back with its layers and colours.
    let toml = imp.design.to_toml_string().unwrap();
    let back = load(&toml, "l.toml").unwrap();
    assert!(
        back.stroke
            .iter()
            .any(|s| s.layer.as_deref() == Some("Cut"))
    );
}

#[test]
fn later_fills_hide_earlier_ones_and_white_knocks_out() {
    let opts = ImportOptions::default();
    // A 60 × 40 black rectangle, a red 20 × 20 square over its middle, a white 10 × 10
    // square over the rectangle's corner region, a black 10 × 10 square overlapping the
    // rectangle's right edge (merged with it: same colour), and a blue square hidden
    // entirely by a later green one.
    let body = r##"<rect id="black" x="20" y="20" width="60" height="40" fill="black"/>
        <rect id="red" x="40" y="30" width="20" height="20" fill="#f00"/>
        <rect id="white" x="22" y="22" width="10" height="10" fill="white"/>
        <rect id="more" x="75" y="25" width="10" height="10" fill="#000"/>
        <rect id="blue" x="120" y="120" width="10" height="10" fill="blue"/>
        <rect id="green" x="115" y="115" width="20" height="20" fill="green"/>"##;
    let imp = import(&page(body), "p.svg", &opts).unwrap();
    let names: Vec<&str> = imp.design.shape.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["red", "more", "green"], "{:?}", imp.skipped);
    let get = |n: &str| imp.design.shape.iter().find(|s| s.name == n).unwrap();
    // Red is whole: 400 mm².
    // usvg keeps f32 coordinates: areas agree to about 1e-7 of their size.
    assert!(
        (area(get("red")) - 400.0).abs() < 1e-6 * 400.0,
        "{}",
        area(get("red"))
    );
    // Black (merged into "more", its colour's later fill): 60·40 + the 5 × 10 part of the
    // small square outside it − red 400 − white 100 = 2400 + 50 − 500.
    let black = get("more");
    assert!(
        (area(black) - 1950.0).abs() < 1e-6 * 1950.0,
        "{}",
        area(black)
    );
    assert_eq!(black.color.as_deref(), Some("#000000"));
    // Its contours: the outer boundary and two holes (the red and the white squares): every
    // visible boundary is kept.
    assert_eq!(black.contours.len(), 3);
    assert!((area(get("green")) - 400.0).abs() < 1e-6 * 400.0);
    let why = |id: &str| {
        imp.skipped
            .iter()
            .find(|s| s.id == id)
            .map(|s| s.reason.clone())
            .unwrap_or_default()
    };
    assert!(why("white").contains("knockout"), "{:?}", imp.skipped);
    assert!(why("blue").contains("hidden"), "{:?}", imp.skipped);
}

#[test]
fn real_drawings_keep_their_visible_art() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/svg_real");
    let read = |f: &str| std::fs::read_to_string(format!("{dir}/{f}")).unwrap();
    let opts = ImportOptions::default();
    // svg2gcode's Koch curve: a white curve over a black rectangle that fills the page.
    // The rectangle is the page background, not ink: the design is the curve, not one
    // rectangle.
    let imp = import(&read("koch.svg"), "koch.svg", &opts).unwrap();
    assert!(imp.design.shape.is_empty(), "{:?}", imp.design.shape.len());
    assert_eq!(imp.design.stroke.len(), 1);
    assert_eq!(imp.design.stroke[0].color.as_deref(), Some("#ffffff"));
    assert!(
        imp.skipped
            .iter()
            .any(|s| s.reason.starts_with("page background"))
    );
    // The Vanderbilt logo: a gold star, a black star on it, a white V on that. The ink is a
    // gold ring (outer star minus the black star) and a black star minus the V: the inner
    // star and the letter stay as boundaries.
    let imp = import(&read("Vanderbilt_Commodores_logo.svg"), "v.svg", &opts).unwrap();
    let shapes = &imp.design.shape;
    assert_eq!(shapes.len(), 2);
    let gold = shapes
        .iter()
        .find(|s| s.color.as_deref() == Some("#a8996e"))
        .unwrap();
    let black = shapes
        .iter()
        .find(|s| s.color.as_deref() == Some("#000000"))
        .unwrap();
    assert_eq!((gold.contours.len(), black.contours.len()), (2, 2));
    // The gold ring's hole is the black star's outline: equal areas.
    let hole = |s: &skinpath::design::Shape| {
        s.rings()
            .iter()
            .map(|r| skinpath::design::shape::ring_area(r))
            .filter(|&a| a < 0.0)
            .sum::<f64>()
    };
    let outer = |s: &skinpath::design::Shape| {
        s.rings()
            .iter()
            .map(|r| skinpath::design::shape::ring_area(r))
            .filter(|&a| a > 0.0)
            .sum::<f64>()
    };
    assert!((-hole(gold) - outer(black)).abs() < 1e-3 * outer(black));
    // The V is a hole in the black star of a sensible size (a fraction of the star).
    assert!(-hole(black) > 0.05 * outer(black) && -hole(black) < 0.5 * outer(black));
}

/// `build drawing.svg` names what the import left out (issue 40 item 12: it used to drop
/// text and malformed paths without a word) and still builds the rest.
#[test]
fn build_from_svg_lists_skipped_elements() {
    let dir = std::env::temp_dir().join(format!("skinpath-build-skips-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("d.svg");
    std::fs::write(
        &src,
        svg(
            r#"width="100mm" height="100mm" viewBox="0 0 100 100""#,
            r#"<text id="caption" x="0" y="90">hello</text>
               <path id="broken" d="M 0 10 L" stroke="black" fill="none"/>
               <path id="keep" d="M10 50 H60" stroke="black" stroke-width="3" fill="none"/>"#,
        ),
    )
    .unwrap();
    let out = dir.join("d.gcode");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args([
            "build",
            src.to_str().unwrap(),
            "--machine",
            "grbl-laser",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("skipped caption:"), "{err}");
    assert!(err.contains("broken"), "{err}");
    assert!(out.exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// The x extent of every stroke whose name starts with `base` (spines sampled densely).
fn spans(d: &Design, base: &str) -> Vec<(f64, f64)> {
    let mut names: Vec<&str> = d
        .stroke
        .iter()
        .map(|s| s.name.split('#').next().unwrap_or(""))
        .filter(|n| *n == base || n.starts_with(&format!("{base}~")))
        .collect();
    names.dedup();
    let mut out: Vec<(f64, f64)> = names
        .iter()
        .map(|n| {
            let s = spine(d, n);
            let lo = s.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
            let hi = s.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

#[test]
fn later_fills_hide_strokes_under_them() {
    let opts = ImportOptions::default();
    // A hairline across the page, a white square over its middle (x 40–60), a thick line
    // under a red square (x 70–80) painted after it, a blue line entirely under a later
    // green rectangle, and a line drawn after the white square (not hidden).
    let body = r##"<path id="line" d="M 5 100 H 95" fill="none" stroke="#000" stroke-width="0.3"/>
        <rect id="ko" x="40" y="90" width="20" height="20" fill="#fff"/>
        <path id="under" d="M 5 150 H 95" fill="none" stroke="#000" stroke-width="2"/>
        <rect id="red" x="70" y="140" width="10" height="20" fill="#f00"/>
        <path id="gone" d="M 120 20 H 130" fill="none" stroke="#00f" stroke-width="0.3"/>
        <rect id="green" x="110" y="10" width="30" height="20" fill="#0f0"/>
        <path id="over" d="M 30 105 H 70" fill="none" stroke="#000" stroke-width="0.3"/>"##;
    let imp = import(&page(body), "p.svg", &opts).unwrap();
    let tol = opts.tolerance;
    let near = |got: &[(f64, f64)], want: &[(f64, f64)]| {
        got.len() == want.len()
            && got
                .iter()
                .zip(want)
                .all(|(a, b)| (a.0 - b.0).abs() < tol && (a.1 - b.1).abs() < tol)
    };
    // The knockout cuts the hairline at x = 40 and x = 60 (the visible runs, within the
    // tolerance of the drawn line's ends and the square's sides).
    let line = spans(&imp.design, "line");
    assert!(near(&line, &[(5.0, 40.0), (60.0, 95.0)]), "{line:?}");
    let under = spans(&imp.design, "under");
    assert!(near(&under, &[(5.0, 70.0), (80.0, 95.0)]), "{under:?}");
    // Drawn after the knockout: whole.
    let over = spans(&imp.design, "over");
    assert!(near(&over, &[(30.0, 70.0)]), "{over:?}");
    let why = |id: &str| {
        imp.skipped
            .iter()
            .find(|s| s.id == id)
            .map(|s| s.reason.clone())
            .unwrap_or_default()
    };
    assert!(why("gone").contains("hidden"), "{:?}", imp.skipped);
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.id == "line" && w.reason.contains("20.0 of its 90.0 mm")),
        "{:?}",
        imp.warnings
    );
    // The radius of the visible runs is the drawn one.
    let r = imp
        .design
        .stroke
        .iter()
        .filter(|s| s.name.starts_with("under"))
        .flat_map(|s| s.points.clone().unwrap_or_default())
        .map(|p| p[2])
        .fold(0.0, f64::max);
    assert!((r - 1.0).abs() < 1e-6, "{r}");
}

#[test]
fn transparent_and_faint_paint_is_not_ink_and_translucent_fills_hide_nothing() {
    let opts = ImportOptions::default();
    let body = r##"<path id="faint" d="M 5 50 H 95" fill="none" stroke="#000" stroke-opacity="0.05"/>
        <g opacity="0"><path id="ghost" d="M 5 55 H 95" fill="none" stroke="#000"/></g>
        <g opacity="0.5"><rect id="dim" x="5" y="5" width="10" height="10" fill="#000" opacity="0.1"/></g>
        <rect id="clear" x="20" y="5" width="10" height="10" fill="#000" fill-opacity="0"/>
        <rect id="black" x="40" y="40" width="40" height="40" fill="#000"/>
        <rect id="glass" x="50" y="50" width="20" height="20" fill="#00f" fill-opacity="0.3"/>
        <rect id="veil" x="45" y="45" width="5" height="5" fill="#fff" opacity="0.4"/>
        <path id="seen" d="M 10 150 H 30" fill="none" stroke="#000" stroke-width="0.3"/>
        <rect id="glass2" x="5" y="140" width="30" height="20" fill="#00f" fill-opacity="0.3"/>"##;
    let imp = import(&page(body), "p.svg", &opts).unwrap();
    let why = |id: &str| {
        imp.skipped
            .iter()
            .find(|s| s.id == id)
            .map(|s| s.reason.clone())
            .unwrap_or_default()
    };
    assert!(why("faint").contains("opacity 0.050"), "{:?}", imp.skipped);
    assert!(
        why("ghost").contains("fully transparent"),
        "{:?}",
        imp.skipped
    );
    // 0.5 × 0.1: below the ink threshold.
    assert!(why("dim").contains("opacity 0.050"), "{:?}", imp.skipped);
    assert!(
        why("clear").contains("fully transparent"),
        "{:?}",
        imp.skipped
    );
    assert!(why("veil").contains("translucent"), "{:?}", imp.skipped);
    let names: Vec<&str> = imp.design.shape.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["black", "glass", "glass2"], "{:?}", imp.skipped);
    // The translucent blue square hides nothing: the black square is whole (1600 mm², one
    // contour) and so is the stroke under the second one.
    let black = imp.design.shape.iter().find(|s| s.name == "black").unwrap();
    assert_eq!(black.contours.len(), 1);
    assert!(
        (area(black) - 1600.0).abs() < 1e-6 * 1600.0,
        "{}",
        area(black)
    );
    let seen = spans(&imp.design, "seen");
    assert_eq!(seen.len(), 1, "{seen:?}");
    assert!((seen[0].1 - seen[0].0 - 20.0).abs() < opts.tolerance);
}

#[test]
fn css_style_sheets_give_the_stroke_width_reason() {
    let body = r##"<style>.thin { stroke-width: 0 } #keep { stroke-width: 0.5 }</style>
        <path id="w0" class="thin" d="M 5 30 H 95" fill="none" stroke="#000"/>
        <path id="keep" class="thin" d="M 5 20 H 95" fill="none" stroke="#000"/>"##;
    let imp = import(&page(body), "p.svg", &ImportOptions::default()).unwrap();
    let r = reasons(&imp);
    assert_eq!(r.len(), 1, "{r:?}");
    assert_eq!(r[0].0, "w0");
    assert!(r[0].1.starts_with("stroke-width 0:"), "{r:?}");
    // The id rule is more specific than the class rule: 0.5 wide.
    let keep = &imp.design.stroke[0];
    assert_eq!(keep.name, "keep");
    let radius = keep.points.as_ref().unwrap()[0][2];
    assert!((radius - 0.25).abs() < 1e-6, "{radius}");
}

#[test]
fn a_fill_of_many_single_segments_encloses_no_area_whatever_its_count() {
    // A plotter's line list (vpype's plotter.svg): one path of 2500 one-segment subpaths,
    // stroked, with SVG's default black fill. The fill has no area: not a shape, and not
    // refused by the ring-count limit either.
    let d: String = (0..2500)
        .map(|k| format!("M {} 10 L {} 20 ", 5 + k % 190, 6 + k % 190))
        .collect();
    let body = format!(r##"<path id="lines" d="{d}" stroke="#f00" stroke-width="0.3"/>"##);
    let imp = import(&page(&body), "p.svg", &ImportOptions::default()).unwrap();
    assert!(imp.design.shape.is_empty());
    assert!(imp.skipped.is_empty(), "{:?}", imp.skipped);
    assert_eq!(imp.design.stroke.len(), 2500);
    // Unstroked, the same fill is skipped as enclosing no area.
    let body = format!(r##"<path id="lines" d="{d}"/>"##);
    let err = import(&page(&body), "p.svg", &ImportOptions::default()).unwrap_err();
    assert!(err.to_string().contains("encloses no area"), "{err}");
}
