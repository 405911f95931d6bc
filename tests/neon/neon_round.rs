//! `[neon] round_bends` and `min_run_length` (issue 41 items 2 and 4): a V corner and a
//! 1 mm hairpin rounded to 5 mm against their closed-form fillets (radius by circumcircles
//! of the rounded spine, deviation, tangency, length), endpoints and far spine unchanged,
//! one run; a hairpin too narrow for the radius warned about and left as drawn; short runs
//! warned about, and made marks on request.

use crate::support;

use skinpath::dbsc::DiskBSpline;
use skinpath::design::{Design, load};
use skinpath::geom::DVec2;
use skinpath::job::build::{BuildOptions, build_toolpath};
use skinpath::job::neon::round_bends;
use skinpath::machine::builtin_profile;
use support::{skinpath_in, tmpdir};

/// Flex minimum radius of the tests (mm).
const R: f64 = 5.0;

fn design(body: &str, extra: &str) -> Design {
    let text = format!(
        "version = 1\nunits = \"mm\"\n[neon]\nmin_bend_radius = {R}\n{extra}\n{body}\n[[operation]]\nkind = \"channel\"\n[[operation]]\nkind = \"holes\"\n"
    );
    load(&text, "round.toml").unwrap()
}

/// A V: (0, 60) → (30, 0) → (60, 60), split at its corner.
const V: &str =
    "[[stroke]]\nname = \"v\"\npoints = [[0, 60, 1], [30, 0, 1], [60, 60, 1]]\ncorners = [1]\n";

/// The parabola y = x²/2 for |x| ≤ 10 (a quadratic Bézier): radius of curvature 1 at its
/// vertex, (1 + x²)^{3/2} elsewhere.
const HAIRPIN: &str =
    "[[stroke]]\nname = \"pin\"\ndegree = 2\ndisks = [[-10, 50, 1], [0, -50, 1], [10, 50, 1]]\n";

/// Dense points of the spines of `curves` (in order), `n` per knot span.
fn spine_points(c: &DiskBSpline, n: usize) -> Vec<DVec2> {
    let mut out = Vec::new();
    for w in c.breakpoints().windows(2).filter(|w| w[1] > w[0]) {
        for k in 0..n {
            out.push(c.center(w[0] + (w[1] - w[0]) * k as f64 / n as f64));
        }
    }
    out.push(c.center(c.domain().1));
    out
}

/// Smallest circumradius of three points a chord length `h` apart along the polyline (a
/// second method for the radius of curvature, independent of the derivatives).
fn min_circumradius(pts: &[DVec2], h: f64) -> f64 {
    // Resample at arc length steps h.
    let mut even = vec![pts[0]];
    let mut left = h;
    for w in pts.windows(2) {
        let (mut a, b) = (w[0], w[1]);
        while a.distance(b) >= left {
            a += (b - a).normalize() * left;
            even.push(a);
            left = h;
        }
        left -= a.distance(b);
    }
    even.windows(3)
        .map(|w| {
            let (a, b, c) = (w[0], w[1], w[2]);
            let area2 = (b - a).perp_dot(c - a).abs();
            if area2 == 0.0 {
                f64::INFINITY
            } else {
                a.distance(b) * b.distance(c) * c.distance(a) / (2.0 * area2)
            }
        })
        .fold(f64::INFINITY, f64::min)
}

fn dist_to_poly(p: DVec2, poly: &[DVec2]) -> f64 {
    poly.windows(2)
        .map(|w| {
            let v = w[1] - w[0];
            let t = ((p - w[0]).dot(v) / v.length_squared()).clamp(0.0, 1.0);
            p.distance(w[0] + v * t)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The rounded design's spines, joined in stroke order (the V's pieces, or the one pin).
fn rounded_spine(d: &Design) -> (Vec<DVec2>, skinpath::job::neon::Rounded) {
    let flex = d.neon.as_ref().unwrap().flex(d.units);
    let r = round_bends(d, &flex, 0.01).unwrap();
    let mut pts = Vec::new();
    for c in r.design.strokes().unwrap() {
        pts.extend(spine_points(&c, 2000));
    }
    (pts, r)
}

#[test]
fn a_v_corner_is_rounded_to_the_flex_minimum() {
    let d = design(V, "round_bends = true");
    let original: Vec<DVec2> = [(0.0, 60.0), (30.0, 0.0), (60.0, 60.0)]
        .iter()
        .map(|&(x, y)| DVec2::new(x, y))
        .collect();
    let (pts, r) = rounded_spine(&d);
    assert_eq!(r.reports.len(), 1, "one run");
    assert_eq!(r.reports[0].rounded, 1);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    // Closed form: half the apex angle h = atan(30/60); the fillet touches each leg at
    // R/tan h from the corner; its centre is R/sin h from it, so the corner lies
    // R/sin h − R from the arc.
    let h = (30.0f64 / 60.0).atan();
    let dev = R / h.sin() - R;
    assert!(
        (r.reports[0].deviation - dev).abs() <= 1e-3 * R,
        "{} vs {dev}",
        r.reports[0].deviation
    );
    // Radius of curvature by circumcircles: never below R (within the resampling's error),
    // and R on the arc.
    let rho = min_circumradius(&pts, 0.05);
    assert!((R * (1.0 - 1e-3)..=R * 1.01).contains(&rho), "{rho}");
    // Endpoints unchanged, the legs unchanged beyond the tangency, the corner gone.
    assert!(pts[0].distance(original[0]) <= 1e-9);
    assert!(pts[pts.len() - 1].distance(original[2]) <= 1e-9);
    let tangent = R / h.tan();
    for leg in [[original[0], original[1]], [original[2], original[1]]] {
        let len = leg[0].distance(leg[1]);
        for k in 0..=100 {
            let s = (len - tangent) * 0.999 * k as f64 / 100.0;
            let p = leg[0] + (leg[1] - leg[0]).normalize() * s;
            assert!(dist_to_poly(p, &pts) <= 1e-6, "{p}");
        }
    }
    assert!(dist_to_poly(original[1], &pts) >= dev * 0.999);
    // The run's length: two legs shortened by the tangent length, plus the arc R·(π − 2h).
    let built = build_toolpath(
        &d,
        &builtin_profile("grbl-router").unwrap().unwrap(),
        &BuildOptions::default(),
    )
    .unwrap();
    let bom = built.neon.unwrap();
    assert_eq!(bom.runs.len(), 1, "the run stays one piece");
    assert_eq!(bom.holes, 2, "holes at the run's two ends only");
    let want = 2.0 * (original[0].distance(original[1]) - tangent)
        + R * (1.0 + skinpath::job::neon::ARC_RADIUS_MARGIN) * (std::f64::consts::PI - 2.0 * h);
    assert!(
        (bom.runs[0].length_mm - want).abs() <= 1e-4 * want,
        "{} vs {want}",
        bom.runs[0].length_mm
    );
    let rmin = bom.runs[0].min_bend_radius_mm;
    assert!((R..=R * 1.001).contains(&rmin), "{rmin}");
    assert_eq!(bom.runs[0].rounded_bends, Some(1));
    assert!(bom.warnings.is_empty(), "{:?}", bom.warnings);
}

#[test]
fn a_one_millimetre_hairpin_is_rounded_to_the_flex_minimum() {
    let d = design(HAIRPIN, "round_bends = true");
    let (pts, r) = rounded_spine(&d);
    assert_eq!(r.reports[0].rounded, 1);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    // Closed form on y = x²/2: the normal at x meets the axis where √(1 + x²) = R, so the
    // ball touches at x = ±√(R² − 1), its centre at (0, (R² − 1)/2 + 1) and its lowest
    // point R below: the vertex lies (R² − 1)/2 + 1 − R from the arc.
    let rr = R * (1.0 + skinpath::job::neon::ARC_RADIUS_MARGIN);
    let xt = (rr * rr - 1.0).sqrt();
    let dev = (rr * rr - 1.0) / 2.0 + 1.0 - rr;
    assert!(
        (r.reports[0].deviation - dev).abs() <= 1e-3 * R,
        "{} vs {dev}",
        r.reports[0].deviation
    );
    let rho = min_circumradius(&pts, 0.05);
    assert!((R * (1.0 - 1e-3)..=R * 1.01).contains(&rho), "{rho}");
    assert!(pts[0].distance(DVec2::new(-10.0, 50.0)) <= 1e-9);
    assert!(pts[pts.len() - 1].distance(DVec2::new(10.0, 50.0)) <= 1e-9);
    for k in 0..=200 {
        let x = xt + 1e-3 + (10.0 - xt - 1e-3) * k as f64 / 200.0;
        for p in [DVec2::new(x, x * x / 2.0), DVec2::new(-x, x * x / 2.0)] {
            assert!(dist_to_poly(p, &pts) <= 1e-6, "{p}");
        }
    }
    // The lowest point of the rounded spine is the arc's.
    let low = pts.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    assert!((low - dev).abs() <= 1e-3, "{low} vs {dev}");
    let built = build_toolpath(
        &d,
        &builtin_profile("grbl-router").unwrap().unwrap(),
        &BuildOptions::default(),
    )
    .unwrap();
    let bom = built.neon.unwrap();
    assert_eq!(bom.runs.len(), 1);
    assert!(bom.runs[0].min_bend_radius_mm >= R, "{:?}", bom.runs[0]);
    assert!(bom.warnings.is_empty(), "{:?}", bom.warnings);
    // The channel follows the rounded spine: nothing is cut below the arc's lowest point
    // minus the channel's half-width and the tool radius.
    let half = 6.5 / 2.0;
    let lowest_cut = built
        .toolpath
        .operations
        .iter()
        .filter(|o| o.kind == skinpath::toolpath::OperationKind::Channel)
        .flat_map(|o| o.cuts.iter().flat_map(|c| c.moves.iter().map(|m| m.to.y)))
        .fold(f64::INFINITY, f64::min);
    assert!(lowest_cut >= dev - half - 1e-6, "{lowest_cut}");
    assert!(lowest_cut <= dev - half + 3.5, "{lowest_cut}");
}

#[test]
fn a_hairpin_too_narrow_for_the_radius_is_warned_about_and_cut_as_drawn() {
    // A U two millimetres wide: no arc of radius 5 fits between its legs.
    let u = "[[stroke]]\nname = \"u\"\npoints = [[0, 50, 1], [0, 0, 1], [2, 0, 1], [2, 50, 1]]\ncorners = [1, 2]\n";
    let dir = tmpdir("neon-round-u");
    let mut programs = Vec::new();
    for extra in ["", "round_bends = true"] {
        let text = format!(
            "version = 1\nunits = \"mm\"\n[neon]\nmin_bend_radius = {R}\n{extra}\n{u}\n[[operation]]\nkind = \"channel\"\n"
        );
        std::fs::write(dir.join("u.toml"), text).unwrap();
        let o = skinpath_in(
            &[
                "build",
                "u.toml",
                "--machine",
                "grbl-router",
                "-o",
                "u.gcode",
                "--json",
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let round: Vec<_> = j["neon"]["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "round")
            .collect();
        if extra.is_empty() {
            assert!(round.is_empty());
            assert!(j["neon"]["runs"][0].get("rounded_bends").is_none());
        } else {
            assert_eq!(round.len(), 2, "one per corner: {round:?}");
            assert!(round[0]["message"].as_str().unwrap().contains("too short"));
            assert_eq!(j["neon"]["runs"][0]["rounded_bends"], 0);
        }
        programs.push(std::fs::read_to_string(dir.join("u.gcode")).unwrap());
    }
    assert_eq!(
        programs[0], programs[1],
        "nothing rounded: the same program"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 100 mm stroke and a 4 mm accent mark 20 mm away.
const WORD_AND_MARK: &str = "[[stroke]]\nname = \"word\"\ndisks = [[0, 0, 1], [100, 0, 1]]\n[[stroke]]\nname = \"mark\"\ndisks = [[48, 20, 1], [52, 20, 1]]\n";

#[test]
fn runs_shorter_than_the_cut_unit_are_warned_about_and_marks_on_request() {
    let b = |extra: &str| {
        let d = design(WORD_AND_MARK, extra);
        build_toolpath(
            &d,
            &builtin_profile("grbl-router").unwrap().unwrap(),
            &BuildOptions::default(),
        )
        .unwrap()
        .neon
        .unwrap()
    };
    let plain = b("");
    assert_eq!(plain.runs.len(), 2);
    assert!(plain.holes > 2, "the mark is drilled too");
    let short: Vec<_> = plain
        .warnings
        .iter()
        .filter(|w| w.kind == "short")
        .collect();
    assert_eq!(short.len(), 1, "{:?}", plain.warnings);
    assert!(
        short[0].message.contains("\"mark\""),
        "{}",
        short[0].message
    );
    assert!(short[0].message.contains("4.00 mm"), "{}", short[0].message);
    assert!(
        short[0].message.contains("25.00 mm"),
        "{}",
        short[0].message
    );
    let marked = b("min_run_length = 10");
    assert_eq!(marked.runs.len(), 1, "the mark is no flex run");
    assert_eq!(marked.runs[0].strokes, vec!["word".to_string()]);
    assert_eq!(marked.holes, 2, "no wire holes for the mark");
    assert_eq!(marked.marks.len(), 1);
    assert!((marked.marks[0].length_mm - 4.0).abs() <= 1e-9);
    assert!((marked.total_length_mm - 100.0).abs() <= 1e-9);
    assert!(marked.warnings.iter().all(|w| w.kind != "short"));
    let e = load(
        "version = 1\n[neon]\nmin_run_length = -1\n[[stroke]]\nname = \"s\"\ndisks = [[0, 0, 1], [9, 9, 1]]\n",
        "bad.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("[neon] min_run_length"), "{e}");
}
