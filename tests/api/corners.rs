//! Strokes with corners (issue 12 item 1): random polylines with a corner at every vertex
//! are split into pieces that each skin; the union of the pieces' outlines (geo) is one
//! simple polygon that contains every disk, with the area of geo's union of the exact
//! capsules (segment ⊕ disk) within the tolerance. Also the corner letters of the issue
//! (N, M, W, Z, V, A, K, E, 4, 7) outline and build, and an unskinnable stroke is repaired
//! (issue 39) with a hint that names its disks and what to change.

use geo::{Area, BooleanOps, Contains, Coord, LineString, MultiPolygon, Polygon};
use glam::DVec2;
use proptest::prelude::*;
use skinpath::design::load;
use skinpath::job::outline::{OutlineOptions, design_outlines};

/// Flattening tolerance of the skinned contours and of the capsules (mm).
const TOL: f64 = 0.01;

fn polygon(pts: &[DVec2]) -> Polygon<f64> {
    let mut c: Vec<Coord<f64>> = pts.iter().map(|p| Coord { x: p.x, y: p.y }).collect();
    c.push(c[0]);
    Polygon::new(LineString::new(c), vec![])
}

fn union_all(polys: Vec<Polygon<f64>>) -> MultiPolygon<f64> {
    polys.into_iter().fold(MultiPolygon::new(vec![]), |acc, p| {
        acc.union(&MultiPolygon::new(vec![p]))
    })
}

/// The capsule of segment ab and radius r: exact region of a straight piece, its arcs
/// flattened with chord error below TOL (inscribed, so slightly smaller).
fn capsule(a: DVec2, b: DVec2, r: f64) -> Polygon<f64> {
    let n = ((std::f64::consts::PI / (2.0 * (1.0 - TOL / r).acos())).ceil() as usize).max(8);
    let d = (b - a).normalize();
    let perp = DVec2::new(-d.y, d.x);
    let mut pts = Vec::new();
    for (c, start) in [(b, -perp), (a, perp)] {
        let a0 = start.y.atan2(start.x);
        for i in 0..=n {
            let t = a0 + std::f64::consts::PI * i as f64 / n as f64;
            pts.push(c + r * DVec2::new(t.cos(), t.sin()));
        }
    }
    polygon(&pts)
}

fn design_text(points: &[DVec2], r: f64) -> String {
    let list: Vec<String> = points
        .iter()
        .map(|p| format!("[{}, {}, {}]", p.x, p.y, r))
        .collect();
    let corners: Vec<String> = (1..points.len() - 1).map(|i| i.to_string()).collect();
    format!(
        "version = 1\n[[stroke]]\nname = \"z\"\npoints = [{}]\ncorners = [{}]\n",
        list.join(", "),
        corners.join(", ")
    )
}

fn piece_outlines(text: &str) -> Vec<Vec<DVec2>> {
    let d = load(text, "corners.toml").unwrap();
    let opts = OutlineOptions {
        tolerance: TOL,
        ..OutlineOptions::default()
    };
    design_outlines(&d, &opts)
        .unwrap()
        .iter()
        .flat_map(|o| o.contours.iter().map(|c| c.flatten(TOL)))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn polylines_with_corners(
        steps in proptest::collection::vec((4.0f64..20.0, -2.6f64..2.6), 2..6),
        r in 0.5f64..2.0,
    ) {
        // A polyline that never turns back on itself: every turn below 150°, legs longer
        // than the width.
        let mut pts = vec![DVec2::ZERO];
        let mut heading = 0.0f64;
        for &(len, turn) in &steps {
            heading += turn;
            let last = *pts.last().unwrap();
            pts.push(last + len * DVec2::new(heading.cos(), heading.sin()));
        }
        let capsules: Vec<Polygon<f64>> =
            pts.windows(2).map(|w| capsule(w[0], w[1], r)).collect();
        let exact = union_all(capsules);
        // Legs that cross each other make holes; compare areas either way, and check
        // simplicity on polylines whose capsules form one region without holes.
        let outlines = piece_outlines(&design_text(&pts, r));
        prop_assert_eq!(outlines.len(), pts.len() - 1, "one contour per piece");
        let skinned = union_all(outlines.iter().map(|c| polygon(c)).collect());
        let perimeter: f64 = pts.windows(2).map(|w| 2.0 * w[0].distance(w[1])).sum::<f64>()
            + 2.0 * std::f64::consts::PI * r * pts.len() as f64;
        let (a, b) = (skinned.unsigned_area(), exact.unsigned_area());
        prop_assert!((a - b).abs() <= TOL * perimeter, "area {a} vs capsules {b}");
        if exact.0.len() == 1 && exact.0[0].interiors().is_empty() {
            prop_assert_eq!(skinned.0.len(), 1);
            prop_assert!(skinned.0[0].interiors().is_empty());
        }
        // Every disk inside: its centre and four points at r − TOL.
        for p in &pts {
            for k in 0..4 {
                let t = k as f64 * std::f64::consts::FRAC_PI_2 + 0.3;
                let q = *p + (r - 2.0 * TOL) * DVec2::new(t.cos(), t.sin());
                prop_assert!(skinned.contains(&geo::Point::new(q.x, q.y)), "{q} of disk at {p}");
            }
        }
    }
}

#[test]
fn corner_letters_outline_and_build() {
    let bin = env!("CARGO_BIN_EXE_skinpath");
    let dir = std::env::temp_dir().join(format!("skinpath-corners-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let design = dir.join("letters.toml");
    let ok = std::process::Command::new(bin)
        .args(["text", "NMWZVAKE47", "--height", "20", "--width", "2", "-o"])
        .arg(&design)
        .status()
        .unwrap();
    assert!(ok.success());
    let text = std::fs::read_to_string(&design).unwrap();
    let d = load(&text, "letters.toml").unwrap();
    // Hershey letters draw most legs as strokes of their own; the bends within one stroke
    // (Z, 4, 7) are corners.
    assert!(!d.corners.is_empty());
    assert!(d.stroke.iter().any(|s| s.name.contains("#1")));
    for (m, ext) in [("grbl-laser", "gcode"), ("grbl-router", "gcode")] {
        let out = dir.join(format!("letters-{m}.{ext}"));
        let b = std::process::Command::new(bin)
            .arg("build")
            .arg(&design)
            .args(["--machine", m, "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            b.status.success(),
            "{m}: {}",
            String::from_utf8_lossy(&b.stderr)
        );
        let c = std::process::Command::new(bin)
            .arg("check")
            .arg(&out)
            .args(["--machine", m])
            .output()
            .unwrap();
        assert!(
            c.status.success(),
            "{m}: {}",
            String::from_utf8_lossy(&c.stdout)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unskinnable_stroke_is_repaired_and_names_disks_and_what_to_change() {
    // A bulge whose radius swallows its neighbours: no envelope, not skinnable as one piece.
    // It gets an outline all the same (issue 39: split, or the union of its disks), and the
    // repair says which disks to change.
    let text = "version = 1\n[[stroke]]\nname = \"bulge\"\ndegree = 2\n\
                disks = [[0, 0, 2], [10, 0, 2], [10.5, 0.2, 8], [11, 0, 2], [20, 0, 2]]\n";
    let d = load(text, "b.toml").unwrap();
    let o = design_outlines(&d, &OutlineOptions::default()).unwrap();
    let r = o[0].repair.as_ref().expect("repaired");
    let m = r.hint.clone().unwrap_or_default();
    assert!(m.contains("what to change"), "{m}");
    assert!(
        m.contains("disk 1 lies inside disk 2") && m.contains("lower the radius of disk 2"),
        "{m}"
    );
}

#[test]
fn marked_corners_split_the_stroke() {
    // The N as four points; with its two inner points marked it is three straight
    // pieces sharing the corner disks.
    let text = "version = 1\n[[stroke]]\nname = \"N\"\npoints = [[0, 0, 3], [0, 60, 3], [40, 0, 3], [40, 60, 3]]\ncorners = [1, 2]\n";
    let d = load(text, "n.toml").unwrap();
    let names: Vec<&str> = d.stroke.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["N#0", "N#1", "N#2"]);
    assert!(d.stroke.iter().all(|s| s.degree == 1));
    assert_eq!(d.corners.len(), 2);
    assert_eq!((d.corners[0].index, d.corners[1].index), (1, 2));
    assert_eq!(d.corners[1].pieces, ["N#1".to_string(), "N#2".to_string()]);
    assert!(design_outlines(&d, &OutlineOptions::default()).is_ok());
}
