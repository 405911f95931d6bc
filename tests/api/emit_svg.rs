//! Laser SVG and preview SVG parse back with roxmltree: page in mm with a matching viewBox,
//! colours per operation kind from the profile, one path per cut in cut order, and the path
//! data reproduces the contours (arcs recomputed from the SVG arc parameters).

use crate::support;

use glam::{DVec2, DVec3};
use proptest::prelude::*;
use skinpath::emit::laser_svg::color_of;
use skinpath::emit::{LaserSvgOptions, Page, laser_svg};
use skinpath::machine::{Profile, builtin_profile};
use skinpath::toolpath::Toolpath;
use support::emit::*;

fn profile(name: &str) -> Profile {
    builtin_profile(name).unwrap().unwrap()
}

/// Parses "12.5mm" → 12.5.
fn mm(attr: &str) -> f64 {
    attr.strip_suffix("mm")
        .expect("width/height in mm")
        .parse()
        .unwrap()
}

/// A traced SVG path: subpaths of points; arcs give (start, end, centre).
#[derive(Debug, Default)]
struct Traced {
    points: Vec<DVec2>,
    centres: Vec<(DVec2, f64)>,
    subpaths: usize,
    closed: usize,
    length: f64,
}

/// Follows `d` (M, L, A, Z with absolute coordinates) and recomputes arc centres from the
/// SVG endpoint parameterisation (SVG 1.1 F.6.5, with rx = ry and no rotation).
fn trace(d: &str) -> Traced {
    let toks: Vec<&str> = d.split_whitespace().collect();
    let mut t = Traced::default();
    let mut i = 0;
    let mut cur = DVec2::ZERO;
    let mut start = DVec2::ZERO;
    let f = |s: &str| -> f64 { s.parse().unwrap_or_else(|_| panic!("number {s:?} in {d}")) };
    while i < toks.len() {
        match toks[i] {
            "M" => {
                cur = DVec2::new(f(toks[i + 1]), f(toks[i + 2]));
                start = cur;
                t.points.push(cur);
                t.subpaths += 1;
                i += 3;
            }
            "L" => {
                let p = DVec2::new(f(toks[i + 1]), f(toks[i + 2]));
                t.length += cur.distance(p);
                cur = p;
                t.points.push(cur);
                i += 3;
            }
            "A" => {
                let (rx, ry) = (f(toks[i + 1]), f(toks[i + 2]));
                assert_eq!(rx, ry);
                let large = toks[i + 4] == "1";
                let sweep = toks[i + 5] == "1";
                let p = DVec2::new(f(toks[i + 6]), f(toks[i + 7]));
                let half = 0.5 * cur.distance(p);
                let h = (rx * rx - half * half).max(0.0).sqrt();
                let m = 0.5 * (cur + p);
                let dir = (p - cur).normalize();
                let perp = DVec2::new(-dir.y, dir.x);
                // F.6.5.2: the centre's sign is + when large != sweep.
                let c = if large != sweep {
                    m + h * perp
                } else {
                    m - h * perp
                };
                let a0 = (cur - c).to_angle();
                let a1 = (p - c).to_angle();
                let mut da = a1 - a0;
                if sweep {
                    while da <= 0.0 {
                        da += std::f64::consts::TAU;
                    }
                } else {
                    while da >= 0.0 {
                        da -= std::f64::consts::TAU;
                    }
                }
                assert!(da.abs() <= std::f64::consts::PI * 2.0 / 3.0 + 1e-9);
                t.length += rx * da.abs();
                t.centres.push((c, rx));
                cur = p;
                t.points.push(cur);
                i += 8;
            }
            "Z" => {
                t.closed += 1;
                assert!(
                    cur.distance(start) < 1e-9,
                    "Z after a contour that is not closed"
                );
                i += 1;
            }
            other => panic!("unexpected token {other} in {d}"),
        }
    }
    t
}

fn check_laser_svg(tp: &Toolpath, p: &Profile, opts: &LaserSvgOptions) {
    let out = laser_svg(tp, p, opts).unwrap();
    let doc = roxmltree::Document::parse(&out).unwrap();
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let (w, h) = (
        mm(root.attribute("width").unwrap()),
        mm(root.attribute("height").unwrap()),
    );
    let vb: Vec<f64> = root
        .attribute("viewBox")
        .unwrap()
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(vb, vec![0.0, 0.0, w, h], "1 user unit = 1 mm");
    let svg = p.svg.as_ref().unwrap();
    let paths: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("path"))
        .collect();
    let ncuts: usize = tp.operations.iter().map(|o| o.cuts.len()).sum();
    assert_eq!(paths.len(), ncuts, "one path per cut");
    // Cut order: ids run through operations and cuts in order.
    let mut expected_ids = Vec::new();
    for (oi, op) in tp.operations.iter().enumerate() {
        for ci in 0..op.cuts.len() {
            expected_ids.push((format!("op{oi}-cut{ci}"), color_of(&svg.colors, op.kind)));
        }
    }
    let mut total = 0.0;
    for (path, (id, color)) in paths.iter().zip(&expected_ids) {
        assert_eq!(path.attribute("id"), Some(id.as_str()));
        assert_eq!(path.attribute("stroke"), Some(*color));
        let g = path.parent_element().unwrap();
        assert_eq!(
            g.attribute("stroke-width").unwrap().parse::<f64>().unwrap(),
            svg.stroke_width
        );
        assert_eq!(g.attribute("fill"), Some("none"));
        let t = trace(path.attribute("d").unwrap());
        for q in &t.points {
            assert!(q.x >= -1e-9 && q.x <= w + 1e-9 && q.y >= -1e-9 && q.y <= h + 1e-9);
        }
        total += t.length;
        // Every arc centre maps back (y flipped) onto an input circle.
        let top = h + page_bottom(tp, opts, p);
        let left = page_left(tp, opts, p);
        for (c, r) in &t.centres {
            let back = DVec2::new(c.x + left, top - c.y);
            assert!(
                arc_circles(tp)
                    .iter()
                    .any(|(ic, ir)| ic.distance(back) < 1e-6 && (ir - r).abs() < 1e-9),
                "arc centre {back} radius {r}"
            );
        }
    }
    let want = cut_length_xy(tp);
    assert!(
        (total - want).abs() < 1e-9 * want.max(1.0),
        "{total} vs {want}"
    );
}

/// The page's design x at its left edge and design y at its bottom edge.
fn page_left(tp: &Toolpath, opts: &LaserSvgOptions, p: &Profile) -> f64 {
    match opts.page {
        Page::WorkArea => p.work_area.x.min(),
        Page::Bounds { margin } => bounds(tp).0.x - margin,
    }
}

fn page_bottom(tp: &Toolpath, opts: &LaserSvgOptions, p: &Profile) -> f64 {
    match opts.page {
        Page::WorkArea => p.work_area.y.min(),
        Page::Bounds { margin } => bounds(tp).0.y - margin,
    }
}

/// Bounding box of `job`'s geometry computed independently: dense sampling of every move.
fn bounds(tp: &Toolpath) -> (DVec2, DVec2) {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = -lo;
    for op in &tp.operations {
        for c in &op.cuts {
            let mut pos = c.start.truncate();
            lo = lo.min(pos);
            hi = hi.max(pos);
            for m in &c.moves {
                if let skinpath::toolpath::MoveKind::Arc { center, ccw } = m.kind {
                    let a =
                        skinpath::geom::Arc::from_center_points(center, pos, m.to.truncate(), ccw);
                    for k in 0..=20_000 {
                        let q = a.eval(k as f64 / 20_000.0);
                        lo = lo.min(q);
                        hi = hi.max(q);
                    }
                }
                pos = m.to.truncate();
                lo = lo.min(pos);
                hi = hi.max(pos);
            }
        }
    }
    // Sampling finds an arc extreme to within r·(sweep/(2·10⁴))²/8 < 1.3e-8·r: the page offset
    // computed here is that close to the exact one (hence 1e-6 on centres above).
    (lo, hi)
}

#[test]
fn laser_svg_default_and_lightburn() {
    let tp = job(&[0.0], 1.0);
    for name in ["svg-laser", "svg-laser-lightburn"] {
        let p = profile(name);
        check_laser_svg(&tp, &p, &LaserSvgOptions::default());
        check_laser_svg(
            &tp,
            &p,
            &LaserSvgOptions {
                page: Page::WorkArea,
                ..Default::default()
            },
        );
    }
}

#[test]
fn page_size_is_the_bounds_plus_margin() {
    let tp = job(&[0.0], 1.0);
    let p = profile("svg-laser");
    let out = laser_svg(
        &tp,
        &p,
        &LaserSvgOptions {
            page: Page::Bounds { margin: 2.5 },
            ..Default::default()
        },
    )
    .unwrap();
    let doc = roxmltree::Document::parse(&out).unwrap();
    let root = doc.root_element();
    let (lo, hi) = bounds(&tp);
    let w = mm(root.attribute("width").unwrap());
    let h = mm(root.attribute("height").unwrap());
    assert!((w - (hi.x - lo.x + 5.0)).abs() < 1e-6, "{w}");
    assert!((h - (hi.y - lo.y + 5.0)).abs() < 1e-6, "{h}");
}

#[test]
fn default_colours_are_red_cut_blue_score_black_engrave() {
    use skinpath::toolpath::OperationKind as K;
    let p = profile("svg-laser");
    let c = &p.svg.as_ref().unwrap().colors;
    assert_eq!(color_of(c, K::Profile), "#ff0000");
    assert_eq!(color_of(c, K::Channel), "#0000ff");
    assert_eq!(color_of(c, K::Fill), "#000000");
    assert!((p.svg.as_ref().unwrap().stroke_width - 0.01).abs() < 1e-15);
}

#[test]
fn g_code_profile_without_svg_table_is_refused() {
    let tp = job(&[0.0], 1.0);
    assert!(laser_svg(&tp, &profile("grbl-laser"), &LaserSvgOptions::default()).is_err());
}

#[test]
fn scaled_and_rotated_jobs_keep_their_length() {
    // Rotation by 90° about the origin and scaling by 3 (plus a shift into positive space).
    let base = job(&[0.0], 1.0);
    let map = |v: DVec3| DVec3::new(200.0 - 3.0 * v.y, 3.0 * v.x, v.z);
    let mut tp = base.clone();
    for op in &mut tp.operations {
        for c in &mut op.cuts {
            c.start = map(c.start);
            for m in &mut c.moves {
                m.to = map(m.to);
                if let skinpath::toolpath::MoveKind::Arc { center, .. } = &mut m.kind {
                    *center = map(center.extend(0.0)).truncate();
                }
            }
        }
    }
    assert!((cut_length_xy(&tp) - 3.0 * cut_length_xy(&base)).abs() < 1e-9);
    check_laser_svg(&tp, &profile("svg-laser"), &LaserSvgOptions::default());
}

/// The toolpath preview (the scene the `preview` verb draws, written by the shared SVG
/// writer): one path per cut contour with a start marker each, rapids dashed, and the drawn
/// cuts as long as the toolpath's cutting moves (up to the scene's flattening).
#[test]
fn preview_has_cuts_rapids_and_start_markers() {
    use skinpath::emit::preview::{Scene, SvgOptions, scene_svg};
    use skinpath::sim::{CheckConfig, MachineKind};
    let tp = job(&[-1.0, -2.0], 0.5);
    let cfg = CheckConfig {
        kind: MachineKind::Router,
        ..CheckConfig::default()
    };
    let scene = Scene::from_toolpath("t", &tp, 1.0, &cfg, None);
    let out = scene_svg(&scene, &SvgOptions::default());
    let doc = roxmltree::Document::parse(&out).unwrap();
    let root = doc.root_element();
    let (w, h) = (
        mm(root.attribute("width").unwrap()),
        mm(root.attribute("height").unwrap()),
    );
    assert!(w > 60.0 && h > 40.0, "{w} x {h}");
    let ncuts: usize = tp.operations.iter().map(|o| o.cuts.len()).sum();
    let count = |class: &str| {
        doc.descendants()
            .filter(|n| n.attribute("class") == Some(class))
            .count()
    };
    assert_eq!(count("cut"), scene.contours.len());
    assert!(
        count("cut") >= ncuts,
        "{} contours, {ncuts} cuts",
        count("cut")
    );
    assert_eq!(count("start"), scene.contours.len());
    assert!(count("rapid") >= 1);
    let rapids = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("rapids"))
        .unwrap();
    assert!(
        rapids.attribute("stroke-dasharray").is_some(),
        "rapids dashed"
    );
    let mut total = 0.0;
    for n in doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("cut"))
    {
        // Preview path data: "Mx y Lx y ..." (polylines in page mm).
        let d = n.attribute("d").unwrap().replace(['M', 'L'], " ");
        let v: Vec<f64> = d.split_whitespace().map(|t| t.parse().unwrap()).collect();
        let pts: Vec<DVec2> = v.chunks(2).map(|c| DVec2::new(c[0], c[1])).collect();
        total += pts.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
    }
    let want = cut_length_xy(&tp);
    // Chords of the flattened arcs are shorter; page coordinates carry 3 decimals.
    assert!(
        total <= want + 1e-2 && total >= want * (1.0 - 1e-3),
        "{total} vs {want}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random chains of lines and tangent arcs: the SVG path traces the same length and its
    /// arcs lie on the input circles, on a bounds page and on the bed.
    #[test]
    fn random_chains_round_trip(
        start in (100.0f64..200.0, 100.0f64..200.0),
        steps in prop::collection::vec(
            (0u8..3, 0.5f64..20.0, -3.1f64..3.1, 0.01f64..6.2, any::<bool>()), 1..12),
    ) {
        let s = DVec2::new(start.0, start.1);
        let tp = Toolpath {
            operations: vec![op(
                "random",
                skinpath::toolpath::OperationKind::Profile,
                vec![cut(s.extend(0.0), chain(s, &steps, 0.0))],
            )],
        };
        check_laser_svg(&tp, &profile("svg-laser"), &LaserSvgOptions::default());
    }
}
