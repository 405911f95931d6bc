//! Flex runs and bends against independent computation: run and spine lengths against
//! Richardson-extrapolated polylines and closed forms, bend radii against closed forms and
//! dense samples, holes only at run ends inside the channel, explicit runs and breaks;
//! `round_bends` on a V corner and a 1 mm hairpin against their closed-form fillets.

use super::{bend_radius, round_bends, runs, spine_length};
use crate::dbsc::DiskBSpline;
use crate::design::{Design, load};
use crate::geom::DVec2;
use crate::job::build::{BuildOptions, BuildResult, build_toolpath};
use crate::machine::Profile;

/// The builtin GRBL router profile.
fn router() -> Profile {
    let text = include_str!("../../../machines/grbl-router.toml");
    Profile::from_toml(text, "grbl-router.toml").unwrap()
}

/// Polyline length of the spine with `n` equal parameter steps per knot span.
fn polyline_length(c: &DiskBSpline, n: usize) -> f64 {
    c.breakpoints()
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| {
            (0..n)
                .map(|k| {
                    let a = w[0] + (w[1] - w[0]) * k as f64 / n as f64;
                    let b = w[0] + (w[1] - w[0]) * (k + 1) as f64 / n as f64;
                    c.center(a).distance(c.center(b))
                })
                .sum::<f64>()
        })
        .sum()
}

/// Arc length by a second method: inscribed polylines L(n), whose error is c/n² + O(n⁻⁴)
/// for a smooth span, Richardson-extrapolated: (4·L(2n) − L(n))/3.
fn richardson_length(c: &DiskBSpline) -> f64 {
    let (l1, l2) = (polyline_length(c, 2000), polyline_length(c, 4000));
    (4.0 * l2 - l1) / 3.0
}

fn design(text: &str) -> Design {
    load(text, "neon_test.toml").unwrap()
}

/// Twelve disks on a circle of radius `r` about (50, 50), interpolated by a closed stroke.
fn circle_points(r: f64, n: usize) -> String {
    let pts: Vec<String> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            format!(
                "[{:.12}, {:.12}, 3.0]",
                50.0 + r * a.cos(),
                50.0 + r * a.sin()
            )
        })
        .collect();
    pts.join(", ")
}

const TWO_STROKES: &str = r#"
version = 1
[neon]
flex = "6mm"
[[stroke]]
name = "a"
disks = [[0, 0, 3], [20, 10, 3], [40, -5, 3], [60, 0, 3]]
[[stroke]]
name = "b"
disks = [[60, 0, 3], [75, 20, 3], [70, 40, 3], [50, 45, 3]]
[[stroke]]
name = "far"
disks = [[0, 60, 3], [30, 70, 3], [60, 60, 3]]
[[operation]]
kind = "channel"
[[operation]]
kind = "holes"
"#;

#[test]
fn run_length_is_the_sum_of_spine_lengths_against_richardson() {
    let d = design(TWO_STROKES);
    let curves = d.strokes().unwrap();
    let flex = d.neon.as_ref().unwrap().flex(d.units);
    let rs = runs(&d, &curves, &flex);
    assert_eq!(rs.len(), 2, "{rs:?}");
    assert_eq!(rs[0].legs.len(), 2);
    let p = router();
    let built = build_toolpath(&d, &p, &BuildOptions::default()).unwrap();
    let bom = built.neon.unwrap();
    let independent: f64 = richardson_length(&curves[0]) + richardson_length(&curves[1]);
    let l = bom.runs[0].length_mm;
    assert!(
        (l - independent).abs() <= 1e-3 * independent,
        "{l} vs {independent}"
    );
    // Much tighter than the 0.1 % asked for: both integrations are accurate to ~1e-9.
    assert!((l - independent).abs() <= 1e-6 * independent);
    assert_eq!(bom.runs[0].strokes, ["a", "b"]);
    // Cut length: the length rounded up to the 25 mm cut unit.
    let cut = bom.runs[0].cut_length_mm;
    assert!(
        cut >= l && cut - l < 25.0 && (cut / 25.0).fract() == 0.0,
        "{cut}"
    );
    let total: f64 = bom.runs.iter().map(|r| r.length_mm).sum();
    assert!((bom.total_length_mm - total).abs() < 1e-9);
}

#[test]
fn straight_and_circular_spines_have_their_closed_form_lengths() {
    // A straight stroke: its length is the distance of its ends.
    let d = design(
        "version = 1\n[[stroke]]\nname = \"s\"\ndisks = [[1, 2, 1], [4, 6, 1], [7, 10, 1], [13, 18, 1]]\n",
    );
    let c = &d.strokes().unwrap()[0];
    let l = spine_length(c, 1e-10);
    assert!((l - 20.0).abs() < 1e-9, "{l}");
    // A closed stroke through 24 points of a circle of radius 30: its length is the curve's
    // own (Richardson) length, and within 0.1 % of the circle's 2π·30.
    let text = format!(
        "version = 1\n[[stroke]]\nname = \"o\"\nclosed = true\npoints = [{}]\n",
        circle_points(30.0, 24)
    );
    let d = design(&text);
    let c = &d.strokes().unwrap()[0];
    let l = spine_length(c, 1e-9);
    let r = richardson_length(c);
    assert!((l - r).abs() <= 1e-7 * r, "{l} vs {r}");
    let circle = std::f64::consts::TAU * 30.0;
    assert!((l - circle).abs() <= 1e-3 * circle, "{l} vs {circle}");
}

#[test]
fn bend_radius_matches_closed_forms() {
    // The quadratic Bézier (−a, a), (0, −a), (a, a) is the parabola y = x²/a on x ∈ [−a, a]:
    // its smallest radius of curvature is a/2, at the vertex (t = ½).
    for a in [2.0, 10.0, 37.5] {
        let text = format!(
            "version = 1\n[neon]\nmin_bend_radius = 1000.0\n[[stroke]]\nname = \"p\"\ndegree = 2\n\
             disks = [[{m}, {a}, 1], [0, {m}, 1], [{a}, {a}, 1]]\n",
            m = -a
        );
        let d = design(&text);
        let p = router();
        let built = build_toolpath(&d, &p, &BuildOptions::default()).unwrap();
        let bom = built.neon.unwrap();
        let r = &bom.runs[0];
        assert!((r.min_bend_radius_mm - a / 2.0).abs() < 1e-9 * a, "{r:?}");
        assert!(
            (r.at.t - 0.5).abs() < 1e-6 && r.at.x.abs() < 1e-6 * a,
            "{r:?}"
        );
        // The stretch is reported as a warning with its place.
        assert!(bom.warnings.iter().any(|w| w.kind == "bend"
            && w.message.contains("stroke \"p\"")
            && (w.at[0]).abs() < 1e-6 * a));
    }
    // A closed stroke through 36 points of a circle of radius 25: every bend radius is 25
    // within the interpolation's deviation from the circle, and the reported minimum is the
    // minimum of a dense sample (a second method) to 1e-6.
    let text = format!(
        "version = 1\n[neon]\n[[stroke]]\nname = \"o\"\nclosed = true\npoints = [{}]\n",
        circle_points(25.0, 36)
    );
    let d = design(&text);
    let c = &d.strokes().unwrap()[0];
    let (lo, hi) = c.domain();
    // The reference sample includes both sides of every knot (where a cubic's curvature
    // often peaks) besides a dense grid.
    let knots = c.breakpoints();
    let sampled = (0..20_000)
        .map(|k| lo + (hi - lo) * (k as f64 + 0.5) / 20_000.0)
        .chain(knots.iter().flat_map(|&t| [t - 1e-9, t + 1e-9]))
        .filter(|t| (lo..=hi).contains(t))
        .map(|t| bend_radius(c, t))
        .fold(f64::INFINITY, f64::min);
    let p = router();
    let built = build_toolpath(&d, &p, &BuildOptions::default()).unwrap();
    let bom = built.neon.unwrap();
    let r = bom.runs[0].min_bend_radius_mm;
    assert!(bom.runs[0].closed);
    assert!((r - 25.0).abs() < 0.01 * 25.0, "{r}");
    assert!(
        r <= sampled + 1e-9 && sampled - r < 1e-6 * 25.0,
        "{r} vs {sampled}"
    );
    // 25 mm is above the 6 mm flex's 15 mm minimum: no warning.
    assert!(bom.warnings.is_empty(), "{:?}", bom.warnings);
}

/// Hole centres of the build's holes operations (a drill's point, a milled circle's arc
/// centre).
fn hole_centres(built: &BuildResult) -> Vec<DVec2> {
    let mut out = Vec::new();
    for op in &built.toolpath.operations {
        if op.kind != crate::toolpath::OperationKind::Holes {
            continue;
        }
        for c in &op.cuts {
            let centre = c.moves.iter().find_map(|m| match m.kind {
                crate::toolpath::MoveKind::Arc { center, .. } => Some(center),
                _ => None,
            });
            out.push(centre.unwrap_or(c.start.truncate()));
        }
    }
    out
}

/// Every hole lies at a run end, none at a join inside a run, and each hole's disk lies
/// inside the channel (distance to the nearest spine + hole radius ≤ channel half-width).
fn holes_at_run_ends(d: &Design, channel: f64, hole: f64) -> (usize, usize) {
    let p = router();
    let built = build_toolpath(d, &p, &BuildOptions::default()).unwrap();
    let curves = d.strokes().unwrap();
    let flex = d.neon.as_ref().unwrap().flex(d.units);
    let rs = runs(d, &curves, &flex);
    let mut ends = Vec::new();
    let mut joins = Vec::new();
    for r in &rs {
        ends.push(r.start(&curves));
        if !r.closed {
            ends.push(r.end(&curves));
        }
        for w in r.legs.windows(2) {
            let c = &curves[w[1].stroke];
            let (lo, hi) = c.domain();
            joins.push(c.center(if w[1].reversed { hi } else { lo }));
        }
    }
    let holes = hole_centres(&built);
    let tol = 1e-3;
    for h in &holes {
        assert!(
            ends.iter().any(|e| e.distance(*h) < tol),
            "hole at {h} is at no run end"
        );
        assert!(
            !joins.iter().any(|j| j.distance(*h) < tol)
                || ends.iter().any(|e| e.distance(*h) < tol),
            "hole at {h} sits on a join"
        );
        let near = curves
            .iter()
            .flat_map(|c| {
                let (lo, hi) = c.domain();
                (0..=4000).map(move |k| c.center(lo + (hi - lo) * k as f64 / 4000.0))
            })
            .map(|q| q.distance(*h))
            .fold(f64::INFINITY, f64::min);
        assert!(
            near + hole / 2.0 <= channel / 2.0 + 1e-9,
            "hole at {h} reaches out of the channel"
        );
    }
    // Every run end got its hole (distinct ends).
    let mut distinct: Vec<DVec2> = Vec::new();
    for e in ends {
        if !distinct.iter().any(|q| q.distance(e) < tol) {
            distinct.push(e);
        }
    }
    (holes.len(), distinct.len())
}

#[test]
fn holes_sit_only_at_run_ends_inside_the_channel() {
    let d = design(TWO_STROKES);
    // Channel 6.5 (6 mm flex + 0.5), holes 4 mm (the 6 mm preset).
    let ch = &d.operation[0];
    assert_eq!((ch.width, ch.depth), (Some(6.5), Some(10.0)));
    assert_eq!(d.operation[1].diameter, Some(4.0));
    let (holes, ends) = holes_at_run_ends(&d, 6.5, 4.0);
    // Two open runs: "a"+"b" joined at (60, 0) and "far": 4 holes, none at (60, 0).
    assert_eq!((holes, ends), (4, 4));
    // `at = "start"`: one hole per run.
    let d = design(&TWO_STROKES.replace("kind = \"holes\"", "kind = \"holes\"\nat = \"start\""));
    let p = router();
    let built = build_toolpath(&d, &p, &BuildOptions::default()).unwrap();
    assert_eq!(hole_centres(&built).len(), 2);
    assert_eq!(built.neon.unwrap().holes, 2);
}

#[test]
fn explicit_runs_and_breaks() {
    // break_at at the join of "a" and "b" splits the run.
    let d = design(&TWO_STROKES.replace("flex = \"6mm\"", "flex = \"6mm\"\nbreak_at = [[60, 1]]"));
    let curves = d.strokes().unwrap();
    let flex = d.neon.as_ref().unwrap().flex(d.units);
    assert_eq!(runs(&d, &curves, &flex).len(), 3);
    // An explicit run joins "far" to "a" across a gap, which is bridged and counted.
    let d = design(&TWO_STROKES.replace(
        "[[stroke]]\nname = \"a\"",
        "[[neon.run]]\nname = \"top\"\nstrokes = [\"far\", \"a\"]\n[[stroke]]\nname = \"a\"",
    ));
    let p = router();
    let bom = build_toolpath(&d, &p, &BuildOptions::default())
        .unwrap()
        .neon
        .unwrap();
    let top = bom.runs.iter().find(|r| r.name == "top").unwrap();
    assert_eq!(top.strokes, ["far", "a"]);
    // "far" ends at (60, 60) nearest "a"'s ... start (0, 0) is 60 away, end (60, 0) 60 away:
    // "far" reversed ends at (0, 60), 60 from (0, 0).
    assert!((top.bridged_mm - 60.0).abs() < 1e-9, "{top:?}");
    assert!(top.min_bend_radius_mm == 0.0, "a bridged turn is a corner");
    // "b" is left on its own.
    assert!(bom.runs.iter().any(|r| r.strokes == ["b"]));
}

// `[neon] round_bends`.

/// Flex minimum radius of the tests (mm).
const R: f64 = 5.0;

fn round_design(body: &str, extra: &str) -> Design {
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
fn rounded_spine(d: &Design) -> (Vec<DVec2>, super::round::Rounded) {
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
    let d = round_design(V, "round_bends = true");
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
    let built = build_toolpath(&d, &router(), &BuildOptions::default()).unwrap();
    let bom = built.neon.unwrap();
    assert_eq!(bom.runs.len(), 1, "the run stays one piece");
    assert_eq!(bom.holes, 2, "holes at the run's two ends only");
    let want = 2.0 * (original[0].distance(original[1]) - tangent)
        + R * (1.0 + super::round::ARC_RADIUS_MARGIN) * (std::f64::consts::PI - 2.0 * h);
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
    let d = round_design(HAIRPIN, "round_bends = true");
    let (pts, r) = rounded_spine(&d);
    assert_eq!(r.reports[0].rounded, 1);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    // Closed form on y = x²/2: the normal at x meets the axis where √(1 + x²) = R, so the
    // ball touches at x = ±√(R² − 1), its centre at (0, (R² − 1)/2 + 1) and its lowest
    // point R below: the vertex lies (R² − 1)/2 + 1 − R from the arc.
    let rr = R * (1.0 + super::round::ARC_RADIUS_MARGIN);
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
    let built = build_toolpath(&d, &router(), &BuildOptions::default()).unwrap();
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
        .filter(|o| o.kind == crate::toolpath::OperationKind::Channel)
        .flat_map(|o| o.cuts.iter().flat_map(|c| c.moves.iter().map(|m| m.to.y)))
        .fold(f64::INFINITY, f64::min);
    assert!(lowest_cut >= dev - half - 1e-6, "{lowest_cut}");
    assert!(lowest_cut <= dev - half + 3.5, "{lowest_cut}");
}
