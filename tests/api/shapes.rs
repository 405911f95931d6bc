//! `[[shape]]` closed regions (issue 12 item 3: "Filled shapes without a stroke become
//! outlines to profile or fill, not strokes"): shape-only designs build and check clean,
//! SVG fills import as shapes of the right area and radius, fill rules are honoured, errors
//! name the shape, contour and point, and shapes join stroke outlines in one region.

use glam::DVec2;
use skinpath::design::svg::{ImportOptions, import};
use skinpath::design::{Design, load};
use skinpath::job::build::{BuildOptions, build_toolpath};
use skinpath::machine::builtin_profile;
use std::f64::consts::PI;

use crate::support;
use support::{skinpath, tmpdir};

fn svg(attrs: &str, body: &str) -> String {
    format!(r#"<svg xmlns="http://www.w3.org/2000/svg" {attrs}>{body}</svg>"#)
}

/// Signed area (shoelace) of a closed ring.
fn area(r: &[DVec2]) -> f64 {
    (0..r.len())
        .map(|i| {
            let (a, b) = (r[i], r[(i + 1) % r.len()]);
            a.x * b.y - a.y * b.x
        })
        .sum::<f64>()
        / 2.0
}

fn region_area(d: &Design, name: &str) -> f64 {
    let s = d.shape.iter().find(|s| s.name == name).unwrap();
    s.region().iter().map(|r| area(r)).sum()
}

fn dist_to_ring(p: DVec2, r: &[DVec2]) -> f64 {
    (0..r.len())
        .map(|i| {
            let (a, b) = (r[i], r[(i + 1) % r.len()]);
            let d = b - a;
            let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
            p.distance(a + d * t)
        })
        .fold(f64::INFINITY, f64::min)
}

/// A frame with a hole (evenodd, both rings the same way round), a ring whose hole runs the
/// other way (nonzero), and a triangle inside the frame's hole.
const PLATES: &str = r#"version = 1

[[shape]]
name = "frame"
fill_rule = "evenodd"
contours = [
  [[0.0, 0.0], [60.0, 0.0], [60.0, 40.0], [0.0, 40.0]],
  [[10.0, 10.0], [50.0, 10.0], [50.0, 30.0], [10.0, 30.0]],
]

[[shape]]
name = "washer"
contours = [
  [[80.0, 0.0], [110.0, 0.0], [110.0, 30.0], [80.0, 30.0]],
  [[88.0, 8.0], [88.0, 22.0], [102.0, 22.0], [102.0, 8.0]],
]

[[shape]]
name = "tri"
contours = [[[20.0, 14.0], [40.0, 14.0], [30.0, 26.0], [20.0, 14.0]]]
"#;

#[test]
fn fill_rules_make_holes() {
    let d = load(PLATES, "plates.toml").unwrap();
    assert!((region_area(&d, "frame") - (2400.0 - 800.0)).abs() < 1e-6);
    assert!((region_area(&d, "washer") - (900.0 - 196.0)).abs() < 1e-6);
    assert!((region_area(&d, "tri") - 120.0).abs() < 1e-6);
    // The same frame under nonzero (both rings counter-clockwise): no hole.
    let nz = PLATES.replacen("fill_rule = \"evenodd\"\n", "", 1);
    let d = load(&nz, "plates.toml").unwrap();
    assert!((region_area(&d, "frame") - 2400.0).abs() < 1e-6);
    // Contours that cross each other: two overlapping squares (side 10, overlap 5 × 5)
    // are their union under nonzero and the union less the overlap under evenodd.
    let two = |rule: &str| {
        format!(
            "version = 1\n[[shape]]\nname = \"two\"\nfill_rule = \"{rule}\"\ncontours = [\
             [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],\
             [[5.0, 5.0], [15.0, 5.0], [15.0, 15.0], [5.0, 15.0]]]\n"
        )
    };
    let d = load(&two("nonzero"), "two.toml").unwrap();
    assert!((region_area(&d, "two") - 175.0).abs() < 1e-6);
    assert_eq!(d.shape[0].region().len(), 1);
    let d = load(&two("evenodd"), "two.toml").unwrap();
    assert!((region_area(&d, "two") - 150.0).abs() < 1e-6);
}

/// A five-pointed star drawn as one crossing path (a pentagram): under nonzero the centre
/// pentagon is filled, under evenodd it is a hole, as SVG renders it.
#[test]
fn svg_pentagram_follows_its_fill_rule() {
    let star = |rule: &str| {
        svg(
            r#"width="100mm" height="100mm" viewBox="0 0 100 100""#,
            &format!(
                r#"<path id="star" fill="black" fill-rule="{rule}" d="M 50 5 L 76.45 86.41 L 7.2 36.1 L 92.8 36.1 L 23.55 86.41 Z"/>"#
            ),
        )
    };
    let nz = load(&star("nonzero"), "s.svg").unwrap();
    let eo = load(&star("evenodd"), "s.svg").unwrap();
    let (a_nz, a_eo) = (region_area(&nz, "star"), region_area(&eo, "star"));
    // Nonzero: one outline of ten points. Evenodd: the centre pentagon is left out, and the
    // five points remain as triangles meeting at the pentagon's corners.
    assert_eq!(nz.shape[0].region().len(), 1);
    assert_eq!(nz.shape[0].region()[0].len(), 10);
    let eo_rings = eo.shape[0].region();
    assert_eq!(eo_rings.len(), 5, "evenodd: five triangles");
    assert!(eo_rings.iter().all(|r| r.len() == 3 && area(r) > 0.0));
    let hole = a_eo - a_nz;
    // Pentagram of circumradius R: inner pentagon circumradius ρ = R·cos 72° / cos 36°,
    // area (5/2)·ρ²·sin 72°.
    let r = 45.0f64;
    let rho = r * 72f64.to_radians().cos() / 36f64.to_radians().cos();
    let want = 2.5 * rho * rho * 72f64.to_radians().sin();
    assert!((-hole - want).abs() < 0.05 * want, "{} vs {want}", -hole);
}

/// Shape-only designs build on grbl-laser (fill + profile) and grbl-router (profile), and
/// what `build` writes passes `skinpath check` on the same profile with no flags; the hatch
/// stays inside the shapes (nothing in the frame's hole but the triangle, nothing in the
/// washer's hole).
#[test]
fn shape_only_design_builds_and_checks_clean() {
    let dir = tmpdir("shapes");
    let laser = format!(
        "{PLATES}
[[operation]]
kind = \"fill\"
spacing = 1.0
angle = 30.0
power = 40.0

[[operation]]
kind = \"profile\"
side = \"on\"
power = 80.0
"
    );
    let router = format!(
        "{PLATES}
[[operation]]
kind = \"profile\"
side = \"outside\"
depth = 3.0
"
    );
    for (machine, text) in [("grbl-laser", &laser), ("grbl-router", &router)] {
        let design = dir.join(format!("{machine}.toml"));
        std::fs::write(&design, text).unwrap();
        let gcode = dir.join(format!("{machine}.gcode"));
        let (ds, gs) = (design.to_str().unwrap(), gcode.to_str().unwrap());
        let o = skinpath(&["build", ds, "--machine", machine, "-o", gs]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let o = skinpath(&["check", gs, "--machine", machine]);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(o.status.success(), "{machine}: {out}");
        assert!(out.contains("0 errors, 0 warnings"), "{machine}: {out}");
    }

    // The library build at the design's coordinates: the profile cuts every contour of
    // the three regions (2 + 2 + 1), and every hatch point is inside a shape.
    let d = load(&laser, "plates.toml").unwrap();
    let profile = builtin_profile("grbl-laser").unwrap().unwrap();
    let built = build_toolpath(&d, &profile, &BuildOptions::default()).unwrap();
    let ops = &built.toolpath.operations;
    let fill = ops.iter().find(|o| o.name.starts_with("fill")).unwrap();
    let prof = ops.iter().find(|o| o.name.starts_with("profile")).unwrap();
    assert_eq!(prof.cuts.len(), 5);
    let inside = |p: DVec2| {
        let in_frame = (0.0..=60.0).contains(&p.x)
            && (0.0..=40.0).contains(&p.y)
            && !(p.x > 10.0 && p.x < 50.0 && p.y > 10.0 && p.y < 30.0);
        let in_washer = (80.0..=110.0).contains(&p.x)
            && (0.0..=30.0).contains(&p.y)
            && !(p.x > 88.0 && p.x < 102.0 && p.y > 8.0 && p.y < 22.0);
        let tri = [
            DVec2::new(20.0, 14.0),
            DVec2::new(40.0, 14.0),
            DVec2::new(30.0, 26.0),
        ];
        let in_tri = (0..3).all(|i| (tri[(i + 1) % 3] - tri[i]).perp_dot(p - tri[i]) >= -1e-9);
        in_frame || in_washer || in_tri
    };
    let mut n = 0;
    for c in &fill.cuts {
        for m in &c.moves {
            let p = DVec2::new(m.to.x, m.to.y);
            assert!(inside(p), "hatch point {p} outside the shapes");
            n += 1;
        }
    }
    assert!(n > 100, "{n} hatch points");
    // Hatching reaches every region, including the washer and the triangle.
    let hits = |f: &dyn Fn(DVec2) -> bool| {
        fill.cuts
            .iter()
            .flat_map(|c| &c.moves)
            .any(|m| f(DVec2::new(m.to.x, m.to.y)))
    };
    assert!(hits(&|p| p.x > 80.0));
    assert!(hits(&|p| p.x > 21.0
        && p.x < 39.0
        && p.y > 14.5
        && p.y < 25.0));
}

/// A filled rectangle and filled rings with a hole (nonzero with the inner circle running
/// the other way, and evenodd) import to shapes whose area is the closed form within the
/// flattening's bound: an inscribed polygon within `tol` of a curve of length L misses at
/// most L·tol of its area.
#[test]
fn filled_rect_and_ring_import_with_closed_form_area() {
    let tol = 0.05;
    // The three rings lie 100 units apart (fills of one colour that overlap merge, as the
    // paint model has it).
    let ring = |id: &str, sweep_inner: u8, rule: &str| {
        let dy = match id {
            "nonzero" => 0,
            "evenodd" => 100,
            _ => 200,
        };
        format!(
            r#"<path id="{id}" transform="translate(0 {dy})" fill="black" fill-rule="{rule}" d="M 50 70 a 20 20 0 1 0 40 0 a 20 20 0 1 0 -40 0 Z M 62 70 a 8 8 0 1 {sweep_inner} 16 0 a 8 8 0 1 {sweep_inner} -16 0 Z"/>"#
        )
    };
    let text = svg(
        r#"width="100mm" height="100mm" viewBox="0 0 100 100""#,
        &format!(
            r#"<rect id="plate" x="10" y="10" width="30" height="20" fill="red"/>{}{}{}"#,
            ring("nonzero", 1, "nonzero"),
            ring("evenodd", 0, "evenodd"),
            ring("solid", 0, "nonzero"),
        ),
    );
    let imp = import(
        &text,
        "r.svg",
        &ImportOptions {
            tolerance: tol,
            ..ImportOptions::default()
        },
    )
    .unwrap();
    assert!(imp.skipped.is_empty(), "{:?}", imp.skipped);
    assert!(imp.design.stroke.is_empty());
    let d = load(&text, "r.svg").unwrap();
    // Rectangle: exact up to usvg's f32 coordinates (40 mm is 151.18 px in f32, 40.000001
    // mm back), y flipped (SVG y 10..30 on a 100 mm page is y 70..90).
    assert!(
        (region_area(&d, "plate") - 600.0).abs() < 1e-3,
        "{:?}",
        d.shape[0]
    );
    let plate = &d.shape.iter().find(|s| s.name == "plate").unwrap().region()[0];
    assert_eq!(plate.len(), 4);
    for p in plate {
        let near = |v: f64, a: f64, b: f64| (v - a).abs() < 1e-5 || (v - b).abs() < 1e-5;
        assert!(near(p.x, 10.0, 40.0) && near(p.y, 70.0, 90.0), "{p}");
    }
    let ring_area = PI * (20.0f64.powi(2) - 8.0f64.powi(2));
    let bound = 2.0 * PI * (20.0 + 8.0) * tol;
    for name in ["nonzero", "evenodd"] {
        let a = region_area(&d, name);
        assert!(
            (a - ring_area).abs() <= bound && a < ring_area,
            "{name}: {a} vs {ring_area} ± {bound}"
        );
        let s = d.shape.iter().find(|s| s.name == name).unwrap();
        assert_eq!(s.region().len(), 2, "{name}: outer and hole");
    }
    // Both circles the same way round under nonzero: no hole.
    let a = region_area(&d, "solid");
    let disk = PI * 400.0;
    assert!(
        (a - disk).abs() <= 2.0 * PI * 20.0 * tol,
        "solid {a} vs {disk}"
    );
}

/// A filled circle under nested transforms and a scaled viewBox: every contour point lies
/// within the tolerance of the transformed circle, and so does every edge's midpoint.
#[test]
fn transformed_filled_circle_within_tolerance_of_its_radius() {
    let tol = 0.02;
    // viewBox 100 units across 200 mm: 2 mm per unit. Circle r 10 at (5, 0), scaled by 2,
    // rotated 30°, moved to (50, 50): centre (50 + 10 cos 30°, 50 + 10 sin 30°) units,
    // radius 20 units = 40 mm.
    let text = svg(
        r#"width="200mm" height="200mm" viewBox="0 0 100 100""#,
        r#"<g transform="translate(50 50) rotate(30)">
             <circle id="c" cx="5" cy="0" r="10" transform="scale(2)" fill="black"/>
           </g>"#,
    );
    let d = import(
        &text,
        "c.svg",
        &ImportOptions {
            tolerance: tol,
            ..ImportOptions::default()
        },
    )
    .unwrap()
    .design;
    let a = 30f64.to_radians();
    let centre_svg = DVec2::new(50.0 + 10.0 * a.cos(), 50.0 + 10.0 * a.sin());
    let centre = DVec2::new(centre_svg.x * 2.0, 200.0 - centre_svg.y * 2.0);
    let r = 40.0;
    let rings = d.shape[0].region();
    assert_eq!(rings.len(), 1);
    let ring = &rings[0];
    assert!(ring.len() >= 8);
    for (i, p) in ring.iter().enumerate() {
        let q = ring[(i + 1) % ring.len()];
        for x in [*p, 0.5 * (*p + q)] {
            let e = (x.distance(centre) - r).abs();
            assert!(e <= tol + 1e-5, "point {x}: {e} off the circle");
        }
    }
    // Both ways: every point of the true circle is within the tolerance of the contour.
    for k in 0..720 {
        let t = k as f64 * PI / 360.0;
        let p = centre + r * DVec2::new(t.cos(), t.sin());
        assert!(dist_to_ring(p, ring) <= tol + 1e-5);
    }
}

/// A path with both a fill and a stroke gives both: the stroke under its id, the fill as a
/// shape `ID.fill` (what a laser program does with fill and stroke).
#[test]
fn fill_and_stroke_give_a_stroke_and_a_shape() {
    let text = svg(
        r#"width="100mm" height="100mm" viewBox="0 0 100 100""#,
        r#"<circle id="dot" cx="50" cy="50" r="20" fill="red" stroke="black" stroke-width="2"/>
           <path id="line" d="M 10 10 L 90 10" stroke="black"/>"#,
    );
    let imp = import(&text, "b.svg", &ImportOptions::default()).unwrap();
    let strokes: Vec<&str> = imp.design.stroke.iter().map(|s| s.name.as_str()).collect();
    let shapes: Vec<&str> = imp.design.shape.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(strokes, ["dot", "line"]);
    // A straight line's default black fill has no area: no shape, nothing skipped.
    assert_eq!(shapes, ["dot.fill"]);
    assert!(imp.skipped.is_empty(), "{:?}", imp.skipped);
    // The whole design builds with the per-item defaults of a drawing: the line (SVG's
    // default width, 1 mm: a hairline) is cut once along its path; the dot's stroke band
    // and its fill make one region, profiled by one contour (its stroke's outer edge), and
    // the visible boundary between the black band and the red fill inside it (the band's
    // inner edge, radius 19) is one closed line cut.
    let d = load(&text, "b.svg").unwrap();
    let profile = builtin_profile("grbl-laser").unwrap().unwrap();
    let built = build_toolpath(&d, &profile, &BuildOptions::default()).unwrap();
    let ops: Vec<_> = (built.toolpath.operations.iter())
        .map(|o| (o.kind, o.cuts.len()))
        .collect();
    use skinpath::toolpath::OperationKind as Tp;
    assert_eq!(
        ops,
        [(Tp::Line, 1), (Tp::Line, 1), (Tp::Profile, 1)],
        "{ops:?}"
    );
    let cut_of = |name: &str| {
        (built.toolpath.operations.iter())
            .flat_map(|o| &o.cuts)
            .find(|c| c.source.as_deref() == Some(name) && c.moves.len() > 1)
            .unwrap()
    };
    let line = cut_of("line");
    let end = line.moves.last().unwrap().to;
    let d = line.start.distance(end);
    assert!((d - 80.0).abs() < 1e-3, "{d}");
    // The boundary is the stroke's (painted over its fill), a line cut, not the profile.
    let rim = (built.toolpath.operations.iter())
        .filter(|o| o.kind == Tp::Line)
        .flat_map(|o| &o.cuts)
        .find(|c| c.source.as_deref() == Some("dot"))
        .unwrap();
    let centre = glam::DVec3::new(50.0, 50.0, 0.0);
    for m in &rim.moves {
        let r = (m.to - centre).truncate().length();
        // The spine is fitted within the import tolerance (0.05), the skin within ε
        // (0.01), the cut within the build tolerance (0.01).
        assert!((r - 19.0).abs() <= 0.07, "{r}");
    }
    assert_eq!(
        rim.moves.last().unwrap().to.truncate(),
        rim.start.truncate()
    );
}

/// Fills that paint nothing are skipped and listed by id: fully transparent, or without
/// area; a half-transparent fill is still an area.
#[test]
fn fills_that_paint_nothing_are_listed() {
    let text = svg(
        r#"width="50mm" height="50mm" viewBox="0 0 50 50""#,
        r#"<rect id="ghost" x="5" y="5" width="10" height="10" fill="red" fill-opacity="0"/>
           <rect id="clear" x="20" y="5" width="10" height="10" fill="transparent"/>
           <path id="flat" d="M 5 40 L 30 40 L 45 40 Z" fill="black"/>
           <rect id="half" x="5" y="25" width="10" height="10" fill="red" opacity="0.5"/>"#,
    );
    let imp = import(&text, "t.svg", &ImportOptions::default()).unwrap();
    let shapes: Vec<&str> = imp.design.shape.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(shapes, ["half"]);
    let ids: Vec<&str> = imp.skipped.iter().map(|s| s.id.as_str()).collect();
    assert_eq!(ids, ["ghost", "clear", "flat"], "{:?}", imp.skipped);
    assert!(imp.skipped[0].reason.contains("transparent"));
    assert!(imp.skipped[2].reason.contains("no area"));
}

/// A stroke that crosses a shape's edge is profiled with it as one region (one contour),
/// and an operation may select a shape by name.
#[test]
fn shapes_join_stroke_outlines_and_can_be_selected() {
    let text = r#"version = 1
[[stroke]]
name = "bar"
disks = [[-10.0, 5.0, 1.0], [10.0, 5.0, 1.0]]
[[shape]]
name = "sq"
contours = [[[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [0.0, 10.0]]]
[[operation]]
kind = "profile"
[[operation]]
kind = "profile"
strokes = ["sq"]
"#;
    let d = load(text, "j.toml").unwrap();
    let profile = builtin_profile("grbl-laser").unwrap().unwrap();
    let built = build_toolpath(&d, &profile, &BuildOptions::default()).unwrap();
    let ops = &built.toolpath.operations;
    assert_eq!(ops[0].cuts.len(), 1, "the union is one contour");
    assert_eq!(ops[1].cuts.len(), 1);
    let xs: Vec<f64> = ops[1].cuts[0].moves.iter().map(|m| m.to.x).collect();
    assert!(
        xs.iter().all(|&x| (-1e-9..=20.0 + 1e-9).contains(&x)),
        "{xs:?}"
    );
    assert!(ops[0].cuts[0].moves.iter().any(|m| m.to.x < -5.0));
}

/// A channel follows stroke spines: one that selects only shapes is an error naming them and
/// what to use instead, not an empty operation.
#[test]
fn channel_of_shapes_only_is_refused_with_the_names() {
    let text = format!(
        "{PLATES}\n[[operation]]\nkind = \"channel\"\nwidth = 4.0\ndepth = 2.0\nstrokes = [\"frame\", \"tri\"]\n"
    );
    let d = load(&text, "c.toml").unwrap();
    let profile = builtin_profile("grbl-router").unwrap().unwrap();
    let e = build_toolpath(&d, &profile, &BuildOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("c.toml"), "{e}");
    assert!(e.contains("[[operation]] 1 (channel)"), "{e}");
    assert!(e.contains("\"frame\", \"tri\""), "{e}");
    assert!(e.contains("`profile` or `fill`"), "{e}");
}

/// A backboard around shapes on a router: contours at the margin plus the tool radius from
/// the shapes' union, and the program checks clean.
#[test]
fn backboard_goes_around_shapes() {
    let text = format!(
        "{PLATES}
[[operation]]
kind = \"backboard\"
margin = 4.0
depth = 3.0
bridge_width = 0.0
"
    );
    // `bridge_width = 0` keeps the plates' boards apart (by default they are bridged into
    // one board, tests/neon/neon_board.rs): this test measures each piece's reach.
    let d = load(&text, "b.toml").unwrap();
    let profile = builtin_profile("grbl-router").unwrap().unwrap();
    let built = build_toolpath(&d, &profile, &BuildOptions::default()).unwrap();
    let board = &built.toolpath.operations[0];
    let r = profile.tools[0].radius();
    let rings: Vec<Vec<DVec2>> = d.shape.iter().flat_map(|s| s.region()).collect();
    let mut n = 0;
    for c in &board.cuts {
        for m in &c.moves {
            let p = DVec2::new(m.to.x, m.to.y);
            let dmin = rings
                .iter()
                .map(|ring| dist_to_ring(p, ring))
                .fold(f64::INFINITY, f64::min);
            assert!(dmin >= 4.0 + r - 0.02, "{p}: {dmin}");
            n += 1;
        }
    }
    assert!(n > 4);
    // The contour bridges the 20 mm gap between the plates (margin 4 on each side does
    // not reach): it passes above and below the gap, x in 60..80, at y > 40 or y < 0.
    // The plates are 20 mm apart, more than twice the margin: one contour around each
    // (the triangle lies inside the frame's), reaching the margin plus the tool radius
    // beyond each plate's sides.
    assert_eq!(board.cuts.len(), 2);
    let span = |k: usize| {
        board.cuts[k]
            .moves
            .iter()
            .fold((f64::MAX, f64::MIN), |a, m| {
                (a.0.min(m.to.x), a.1.max(m.to.x))
            })
    };
    let (mut a, mut b) = (span(0), span(1));
    if a.0 > b.0 {
        std::mem::swap(&mut a, &mut b);
    }
    let reach = 4.0 + r;
    for (got, want) in [
        (a.0, -reach),
        (a.1, 60.0 + reach),
        (b.0, 80.0 - reach),
        (b.1, 110.0 + reach),
    ] {
        assert!((got - want).abs() < 0.05, "{got} vs {want}");
    }
    let dir = tmpdir("shapes-board");
    let (ds, gs) = (dir.join("b.toml"), dir.join("b.gcode"));
    std::fs::write(&ds, &text).unwrap();
    let (ds, gs) = (ds.to_str().unwrap(), gs.to_str().unwrap());
    let o = skinpath(&["build", ds, "--machine", "grbl-router", "-o", gs]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = skinpath(&["check", gs, "--machine", "grbl-router"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stdout));
}

fn err(text: &str, file: &str) -> String {
    load(text, file).unwrap_err().to_string()
}

/// Every error names the file, the shape by index and name, and the contour and point.
#[test]
fn errors_name_the_shape_contour_and_point() {
    let shape = |contours: &str| {
        format!(
            "version = 1\n[[shape]]\nname = \"ok\"\ncontours = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]]\n\
             [[shape]]\nname = \"bad\"\ncontours = {contours}\n"
        )
    };
    let square = "[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]";
    let cases = [
        (
            format!("[{square}, [[0.0, 0.0], [1.0, 0.0]]]"),
            "contour 1: needs at least 3",
        ),
        (
            format!("[{square}, [[0.0, 0.0], [nan, 1.0], [0.0, 1.0]]]"),
            "contour 1, point 1: number is not finite",
        ),
        (
            "[[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]]".into(),
            "contour 0: contour encloses no area",
        ),
        (
            format!("[{square}, [[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]]]"),
            "contour 1: contour crosses or touches itself: edge 0",
        ),
        (
            // A spike: the ring runs back along its own edge.
            "[[[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]]]".into(),
            "contour 0: contour crosses or touches itself: edge 0 (points 0–1) meets edge 2",
        ),
        (
            "[[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]]".into(),
            "contour 0, point 2: repeats the one before it",
        ),
        ("[]".into(), "needs at least 1 contours"),
    ];
    for (contours, want) in &cases {
        let e = err(&shape(contours), "s.toml");
        assert!(
            e.starts_with("s.toml: shape 1 \"bad\"") && e.contains(want),
            "{contours}: {e}"
        );
    }
    // Two copies of one ring under evenodd cancel out.
    let e = err(
        &format!(
            "version = 1\n[[shape]]\nname = \"twice\"\nfill_rule = \"evenodd\"\ncontours = [{square}, {square}]\n"
        ),
        "t.toml",
    );
    assert!(
        e.contains("shape 0 \"twice\"") && e.contains("no area under fill rule \"evenodd\""),
        "{e}"
    );
    // [x, y, z] is a parse error with line and column; names are shared with strokes.
    let e = err(
        &shape("[[[0.0, 0.0, 1.0], [1.0, 0.0], [0.0, 1.0]]]"),
        "s.toml",
    );
    assert!(
        e.starts_with("s.toml:7:") && e.contains("exactly 2 numbers"),
        "{e}"
    );
    let e = err(
        "version = 1\n[[stroke]]\nname = \"a\"\ndisks = [[0.0, 0.0, 1.0], [5.0, 0.0, 1.0]]\n\
         [[shape]]\nname = \"a\"\ncontours = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]]\n",
        "n.toml",
    );
    assert!(
        e.contains("shape 0 \"a\": name already used by stroke 0"),
        "{e}"
    );
    // JSON designs read the same keys and give the same errors.
    let json = r#"{"version": 1, "shape": [{"name": "j", "fill_rule": "evenodd",
        "contours": [[[0, 0], [3, 0], [3, 3], [0, 3]], [[1, 1], [2, 1], [1, 2], [2, 2]]]}]}"#;
    let e = err(json, "d.json");
    assert!(
        e.starts_with("d.json: shape 0 \"j\", contour 1: contour crosses or touches itself"),
        "{e}"
    );
    let ok = json.replace("[1, 2], [2, 2]", "[2, 2], [1, 2]");
    let d = load(&ok, "d.json").unwrap();
    assert!((region_area(&d, "j") - 8.0).abs() < 1e-9);
    // Round trip through TOML and JSON keeps the shape.
    let back = load(&d.to_toml_string().unwrap(), "d.toml").unwrap();
    assert_eq!(back.shape, d.shape);
}

/// `outline` draws shapes and `inspect` lists them (area and holes).
#[test]
fn outline_draws_and_inspect_lists_shapes() {
    let dir = tmpdir("shapes-cli");
    let design = dir.join("p.toml");
    std::fs::write(&design, PLATES).unwrap();
    let ds = design.to_str().unwrap();
    let o = skinpath(&["inspect", ds]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    assert!(
        out.contains("shape \"frame\": 2 contours (8 points), fill rule evenodd: 1 outer, 1 holes, area 1600.000"),
        "{out}"
    );
    let svg_out = dir.join("p.svg");
    let o = skinpath(&["outline", ds, "-o", svg_out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let drawn = std::fs::read_to_string(&svg_out).unwrap();
    for name in ["frame", "washer", "tri"] {
        assert!(drawn.contains(&format!("id=\"{name}\"")), "{drawn}");
    }
}

/// Random nested and disjoint rings (star-shaped polygons in separate radius bands around
/// two centres, each either way round): the exact resolution by nesting and orientation
/// (no crossings) gives the area of geo's union under the same fill rule, and its rings
/// are oriented (outer counter-clockwise, holes clockwise) so that nonzero and evenodd read
/// them alike.
mod resolve {
    use super::area;
    use geo::Area;
    use geo::BooleanOps;
    use geo::algorithm::bool_ops::{FillRule as GeoRule, OpType};
    use glam::DVec2;
    use proptest::prelude::*;
    use skinpath::design::FillRule;
    use skinpath::design::shape::{edge_meeting, resolve_rings};

    /// A star-shaped ring of `n` points around `centre`: point i at angle
    /// (i + jitter_i)·2π/n (jitter < 0.9, so neighbours are less than 1.9·2π/n apart) and
    /// radius band + 0.8·k_i. With n ≥ 16 and bands 2 apart every chord stays within 1.2 of
    /// its band (band·(1 − cos(1.9π/16)) < 1.2 for bands up to 11): rings never meet.
    fn ring(
        centre: DVec2,
        band: f64,
        n: usize,
        jitter: &[f64],
        radii: &[f64],
        ccw: bool,
    ) -> Vec<DVec2> {
        let mut r: Vec<DVec2> = (0..n)
            .map(|i| {
                let t = (i as f64 + jitter[i]) * std::f64::consts::TAU / n as f64;
                centre + (band + 0.8 * radii[i]) * DVec2::new(t.cos(), t.sin())
            })
            .collect();
        if !ccw {
            r.reverse();
        }
        r
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn exact_resolution_matches_geo(
            spec in prop::collection::vec(
                (0usize..2, 16usize..32, prop::collection::vec(0.0f64..0.9, 32),
                 prop::collection::vec(0.0f64..1.0, 32), any::<bool>()),
                1..6),
            evenodd in any::<bool>(),
        ) {
            // Ring j lies in the radius band [1 + 2j, 1.8 + 2j] around its centre: rings of
            // one centre nest without meeting, the two centres are far apart.
            let rings: Vec<Vec<DVec2>> = spec
                .iter()
                .enumerate()
                .map(|(j, (c, n, jitter, radii, ccw))| {
                    let centre = DVec2::new(100.0 * *c as f64, 0.0);
                    ring(centre, 1.0 + 2.0 * j as f64, *n, jitter, radii, *ccw)
                })
                .collect();
            prop_assert!(edge_meeting(&rings).is_none());
            let rule = if evenodd { FillRule::Evenodd } else { FillRule::Nonzero };
            let out = resolve_rings(&rings, rule);
            let ours: f64 = out.iter().map(|r| area(r)).sum();
            let poly = |r: &Vec<DVec2>| {
                let mut c: Vec<geo::Coord<f64>> =
                    r.iter().map(|p| geo::Coord { x: p.x, y: p.y }).collect();
                c.push(c[0]);
                geo::Polygon::new(geo::LineString::new(c), vec![])
            };
            let subject = geo::MultiPolygon::new(rings.iter().map(poly).collect());
            let geo_rule = if evenodd { GeoRule::EvenOdd } else { GeoRule::NonZero };
            let theirs = subject
                .boolean_op_with_fill_rule(
                    &geo::MultiPolygon::<f64>::new(vec![]),
                    OpType::Union,
                    geo_rule,
                )
                .unsigned_area();
            prop_assert!((ours - theirs).abs() <= 1e-6 * (1.0 + theirs), "{ours} vs {theirs}");
            // The result reads the same under the other rule.
            let other = if evenodd { FillRule::Nonzero } else { FillRule::Evenodd };
            let again: f64 = resolve_rings(&out, other).iter().map(|r| area(r)).sum();
            prop_assert!((again - ours).abs() <= 1e-9 * (1.0 + ours));
        }
    }
}

/// Random contours on a small integer grid (so repeats, collinear points, touching and
/// crossing edges are common) under either rule: loading never panics; it either fails
/// with an error that names the shape, or gives a shape whose region is non-empty, made of
/// rings that neither cross nor touch themselves, and that builds on a laser.
mod robustness {
    use proptest::prelude::*;
    use skinpath::design::load;
    use skinpath::design::shape::self_intersection;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(160))]
        #[test]
        fn grid_contours_load_or_name_the_shape(
            rings in prop::collection::vec(
                prop::collection::vec((0i32..6, 0i32..6), 2..5), 1..4),
            evenodd in any::<bool>(),
        ) {
            let contours: Vec<String> = rings
                .iter()
                .map(|r| {
                    let pts: Vec<String> =
                        r.iter().map(|(x, y)| format!("[{x}.0, {y}.0]")).collect();
                    format!("[{}]", pts.join(", "))
                })
                .collect();
            let text = format!(
                "version = 1\n[[shape]]\nname = \"r\"\nfill_rule = \"{}\"\ncontours = [{}]\n",
                if evenodd { "evenodd" } else { "nonzero" },
                contours.join(", ")
            );
            match load(&text, "g.toml") {
                Err(e) => {
                    let e = e.to_string();
                    prop_assert!(e.starts_with("g.toml: shape 0 \"r\""), "{e}");
                }
                Ok(d) => {
                    let region = d.shape[0].region();
                    prop_assert!(!region.is_empty());
                    for r in &region {
                        prop_assert!(r.len() >= 3);
                        prop_assert!(self_intersection(r).is_none(), "{r:?}");
                    }
                    let profile = skinpath::machine::builtin_profile("grbl-laser")
                        .unwrap()
                        .unwrap();
                    let built = skinpath::job::build::build_toolpath(
                        &d,
                        &profile,
                        &skinpath::job::build::BuildOptions::default(),
                    );
                    prop_assert!(built.is_ok(), "{text}: {:?}", built.err().map(|e| e.to_string()));
                }
            }
        }
    }
}
