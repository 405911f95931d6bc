//! Outlines hold their strokes (issue 11): every disk c(t) of a stroke lies inside the
//! outline the job draws for it, up to ε plus the flattening. Where the skin cannot meet ε
//! (a hairpin whose bend no admissible circle can follow) it used to cut through the
//! stroke; the job now measures that (`skin::coverage`) and draws the union of the disks
//! instead, with a `disk-union` marker.

use skinpath::dbsc::DiskBSpline;
use skinpath::dbsc::flatten_disks;
use skinpath::design::load;
use skinpath::geom::{Circle, DVec2};
use skinpath::job::{BuildOptions, build_toolpath};
use skinpath::job::{OutlineOptions, design_outlines};
use skinpath::machine::builtin_profile;
use skinpath::skin::uncovered;

use crate::support;
use support::{EXAMPLES, ROOT};

/// ε plus the flattening of outline and disks, doubled: what `job::outline` allows.
fn limit(o: &OutlineOptions) -> f64 {
    2.0 * (o.epsilon + 2.0 * o.tolerance)
}

/// How deep the deepest disk of `c` reaches outside `contours` (flattened within `tol`).
fn depth(c: &DiskBSpline, contours: &[skinpath::geom::Path], tol: f64) -> f64 {
    let polygons: Vec<Vec<DVec2>> = contours.iter().map(|p| p.flatten(tol)).collect();
    uncovered(&flatten_disks(c, tol), &polygons).map_or(0.0, |u| u.depth)
}

/// Asserts that every stroke's outline holds its disks; per stroke, whether the outline had
/// to be repaired (split where the skin cut in, or built on the union of the disks). Err: the design or its outline was refused (with this message).
fn outlines_hold_their_disks(text: &str, file: &str) -> Result<Vec<bool>, String> {
    let design = load(text, file).map_err(|e| e.to_string())?;
    let opts = OutlineOptions::default();
    let outlines = design_outlines(&design, &opts).map_err(|e| e.to_string())?;
    let strokes = design.strokes().map_err(|e| e.to_string())?;
    Ok(strokes
        .iter()
        .zip(&outlines)
        .map(|(c, o)| {
            let d = depth(c, &o.contours, opts.tolerance);
            assert!(
                d <= limit(&opts),
                "{file} {}: a disk reaches {d} outside",
                o.name
            );
            o.repair.is_some()
        })
        .collect())
}

#[test]
fn every_example_outline_holds_its_disks() {
    for name in EXAMPLES {
        let file = format!("{ROOT}/examples/{name}.toml");
        outlines_hold_their_disks(&std::fs::read_to_string(&file).unwrap(), &file).unwrap();
    }
}

/// Area of the union of disks on a grid of `n`² cells over their bounding box (an
/// independent estimate: cell centres inside any disk).
fn raster_area(disks: &[Circle], n: usize) -> f64 {
    let lo = disks
        .iter()
        .map(|d| d.c - d.r)
        .fold(DVec2::INFINITY, DVec2::min);
    let hi = disks
        .iter()
        .map(|d| d.c + d.r)
        .fold(DVec2::NEG_INFINITY, DVec2::max);
    let cell = (hi - lo) / n as f64;
    let mut count = 0usize;
    for i in 0..n {
        for j in 0..n {
            let p = lo + DVec2::new((i as f64 + 0.5) * cell.x, (j as f64 + 0.5) * cell.y);
            if disks.iter().any(|d| p.distance_squared(d.c) <= d.r * d.r) {
                count += 1;
            }
        }
    }
    count as f64 * cell.x * cell.y
}

/// Campaign case 95, stroke s2: a 4-point hairpin. Its skin was a bridge between the two
/// end circles, 23 mm short of the bend. The outline is now repaired (split where the skin
/// cut in, issue 39; before that the union of the disks): it holds them, its area matches a
/// raster of the disks within 1 %, and it has the hole the hairpin encloses.
#[test]
fn hairpin_outline_is_the_union_of_its_disks() {
    let text = r#"version = 1
units = "mm"
[[stroke]]
name = "s2"
points = [[23.001, 26.957, 3.077], [8.330, 22.987, 3.077], [9.743, 4.293, 3.077], [18.377, 24.759, 3.077]]
"#;
    assert_eq!(
        outlines_hold_their_disks(text, "hairpin.toml"),
        Ok(vec![true])
    );
    let design = load(text, "hairpin.toml").unwrap();
    let o = &design_outlines(&design, &OutlineOptions::default()).unwrap()[0];
    let c = &design.strokes().unwrap()[0];
    let disks: Vec<Circle> = flatten_disks(c, 1e-3).into_iter().map(|(_, d)| d).collect();
    // Signed areas: the outer contour counter-clockwise, the hole clockwise.
    let area: f64 = (o.contours.iter())
        .map(|c| skinpath::geom::polygon_area(&c.flatten(1e-3)))
        .sum();
    let raster = raster_area(&disks, 600);
    assert!(
        (area - raster).abs() <= 0.01 * raster,
        "outline area {area} vs raster {raster}"
    );
    assert_eq!(
        o.contours.len(),
        2,
        "outer contour and the hole inside the hairpin"
    );
}

/// The backboard of campaign case 95 keeps its margin from every stroke and holds every
/// channel, on both profiles (it was built on the bridge-shaped skin of the hairpin and ran
/// through its channel).
#[test]
fn backboard_of_the_hairpin_keeps_its_margin() {
    let file = format!("{ROOT}/tests/robust_data/random_c95.toml");
    let design = load(&std::fs::read_to_string(&file).unwrap(), &file).unwrap();
    let strokes = design.strokes().unwrap();
    let channel = design.operation.iter().find_map(|o| o.width).unwrap();
    let margin = design.operation.iter().find_map(|o| o.margin).unwrap();
    for machine in ["grbl-router", "grbl-laser"] {
        let p = builtin_profile(machine).unwrap();
        let built = build_toolpath(&design, &p, &BuildOptions::default()).unwrap();
        let board = built
            .toolpath
            .operations
            .iter()
            .find(|o| o.name.contains("backboard"))
            .unwrap();
        for c in &strokes {
            for (_, d) in flatten_disks(c, 0.05) {
                let reach = (d.r + margin).max(channel / 2.0) - 0.05;
                for m in board.cuts.iter().flat_map(|k| k.moves.iter()) {
                    let gap = DVec2::new(m.to.x, m.to.y).distance(d.c);
                    assert!(
                        gap >= reach,
                        "{machine}: board cut {gap} from the disk at {:?}, want {reach}",
                        d.c
                    );
                }
            }
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
    /// Random 4–6 point strokes with turns up to 170° (hairpins included): the outline
    /// the job draws holds every disk.
    #[test]
    fn random_bent_strokes_are_held(
        turns in proptest::collection::vec(-2.97f64..2.97, 3..6),
        steps in proptest::collection::vec(1.0f64..6.0, 3..6),
        r in 1.0f64..5.0,
    ) {
        let mut p = [50.0, 50.0];
        let mut heading = 0.3f64;
        let mut pts = vec![format!("[{:.3}, {:.3}, {r:.3}]", p[0], p[1])];
        for (t, s) in turns.iter().zip(&steps) {
            heading += t;
            p = [p[0] + s * r * heading.cos(), p[1] + s * r * heading.sin()];
            pts.push(format!("[{:.3}, {:.3}, {r:.3}]", p[0], p[1]));
        }
        let text = format!(
            "version = 1\nunits = \"mm\"\n[[stroke]]\nname = \"s\"\npoints = [{}]\n",
            pts.join(", ")
        );
        // A refusal (a bend no admissible circle sequence can follow) names the file.
        if let Err(e) = outlines_hold_their_disks(&text, "random.toml") {
            proptest::prop_assert!(e.contains("random.toml"), "{}", e);
        }
    }
}
