//! Strokes that a build cuts only along their spines (`line` operations) are not skinned
//! (issue 39: the skins of hairlines cost seconds and no cut used them): their outline in
//! the build is the box of their disks, checked here against dense samples of q(t) ± r(t);
//! a stroke that any other operation selects, or a translated copy of a spine-only stroke
//! that is profiled, keeps its own skin and its profile cut.

use skinpath::design::{OutlineMethod, load};
use skinpath::geom::DVec2;
use skinpath::job::build::{BuildOptions, build_toolpath, outline_bounds};
use skinpath::machine::builtin_profile;
use skinpath::toolpath::OperationKind;

/// An S-curve of radius 0.1 (a hairline) in layer "lines"; the same curve moved by (50, 0)
/// in layer "shapes" (a translated copy: the skin cache would share its outline); a wide
/// stroke in layer "both", which a line and a profile select.
const DESIGN: &str = r#"
version = 1
units = "mm"

[[stroke]]
name = "hair"
degree = 3
points = [[0, 0, 0.1], [10, 12, 0.1], [20, -6, 0.1], [30, 8, 0.1], [40, 0, 0.1]]
layer = "lines"

[[stroke]]
name = "copy"
degree = 3
points = [[50, 0, 0.1], [60, 12, 0.1], [70, -6, 0.1], [80, 8, 0.1], [90, 0, 0.1]]
layer = "shapes"

[[stroke]]
name = "both"
degree = 3
points = [[0, 30, 1.0], [15, 40, 1.5], [30, 30, 1.0]]
layer = "both"

[[operation]]
kind = "line"
layers = ["lines", "both"]

[[operation]]
kind = "profile"
layers = ["shapes", "both"]
"#;

/// The box of a stroke's disks by dense sampling (an independent measure): min and max
/// over 20 000 parameters of q(t) ∓ r(t).
fn sampled_box(c: &skinpath::dbsc::DiskBSpline) -> (DVec2, DVec2) {
    let (lo, hi) = c.domain();
    let n = 20_000;
    let mut a = DVec2::splat(f64::INFINITY);
    let mut b = DVec2::splat(f64::NEG_INFINITY);
    for k in 0..=n {
        let t = lo + (hi - lo) * k as f64 / n as f64;
        let (q, r) = (c.center(t), c.radius(t));
        a = a.min(q - DVec2::splat(r));
        b = b.max(q + DVec2::splat(r));
    }
    (a, b)
}

#[test]
fn line_only_strokes_are_not_skinned_and_the_rest_are() {
    let design = load(DESIGN, "spine_only.toml").unwrap();
    let strokes = design.strokes().unwrap();
    let profile = builtin_profile("grbl-laser").unwrap().unwrap();
    let opts = BuildOptions::default();
    let built = build_toolpath(&design, &profile, &opts).unwrap();
    let by_name = |n: &str| built.outlines.iter().find(|o| o.name == n).unwrap();

    // The hairline: no skin, the box of its disks within the flattening of the disks.
    let hair = by_name("hair");
    assert!(hair.contours.is_empty() && hair.repair.is_none());
    let (lo, hi) = hair.spine_box.expect("a spine-only stroke has a box");
    let (slo, shi) = sampled_box(&strokes[0]);
    for (got, want) in [(lo, slo), (hi, shi)] {
        assert!(
            got.distance(want) <= 2.0 * opts.tolerance,
            "box corner {got} vs sampled {want}"
        );
    }

    // The profiled copy and the stroke both operations select are skinned: contours that
    // enclose their disks' boxes up to ε and the flattening.
    for (name, k) in [("copy", 1), ("both", 2)] {
        let o = by_name(name);
        assert!(o.spine_box.is_none(), "{name}");
        assert!(!o.contours.is_empty(), "{name} has no skin");
        let (olo, ohi) = outline_bounds(std::slice::from_ref(o), opts.tolerance).unwrap();
        let (slo, shi) = sampled_box(&strokes[k]);
        let slack = 2.0 * (opts.epsilon + 2.0 * opts.tolerance);
        for (got, want) in [(olo, slo), (ohi, shi)] {
            assert!(got.distance(want) <= slack, "{name}: {got} vs {want}");
        }
    }

    // The profile cuts around the copy (on the laser: on its outline): its cuts reach the
    // copy's box, not the hairline's.
    let prof = (built.toolpath.operations.iter())
        .find(|o| o.kind == OperationKind::Profile)
        .unwrap();
    let copy_cuts: Vec<_> = (prof.cuts.iter())
        .filter(|c| c.source.as_deref() == Some("copy"))
        .collect();
    assert!(!copy_cuts.is_empty(), "the copy is not profiled");
    let (clo, chi) = sampled_box(&strokes[1]);
    for c in copy_cuts {
        for m in &c.moves {
            let p = m.to.truncate();
            assert!(
                p.x >= clo.x - 0.1 && p.x <= chi.x + 0.1 && p.y >= clo.y - 0.1,
                "copy cut at {p} outside the copy's box"
            );
        }
    }

    // The job's bounds hold every stroke's disks.
    let (blo, bhi) = outline_bounds(&built.outlines, opts.tolerance).unwrap();
    assert!(blo.x <= slo.x + 2.0 * opts.tolerance && bhi.x >= clo.x);
}

/// On the RE route every item keeps an outline (the exact skins are made for all items).
#[test]
fn the_re_route_skins_every_stroke() {
    let design = load(DESIGN, "spine_only.toml").unwrap();
    let profile = builtin_profile("grbl-laser").unwrap().unwrap();
    let opts = BuildOptions {
        method: OutlineMethod::Re,
        ..BuildOptions::default()
    };
    let built = build_toolpath(&design, &profile, &opts).unwrap();
    for o in &built.outlines {
        assert!(
            o.spine_box.is_none() && !o.contours.is_empty(),
            "{}",
            o.name
        );
    }
}
