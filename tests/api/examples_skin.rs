//! The shipped examples through the skinning stage: every stroke skins to an outline that
//! does not cross itself, loop-free strokes meet ε on every segment, and on the hairpin
//! (examples/loop.toml) the side without the envelope loop meets ε everywhere while the
//! report names the looping segments.

use crate::support::example;
use skinpath::dbsc::Side;
use skinpath::geom::{path_self_intersections, paths_intersections};
use skinpath::job::{OutlineOptions, design_outlines};

const EPS: f64 = 0.01;

fn opts() -> OutlineOptions {
    let mut opts = OutlineOptions::default();
    opts.epsilon = EPS;
    opts
}

#[test]
fn every_example_outline_is_free_of_crossings() {
    for name in [
        "brush",
        "ring_o",
        "loop",
        "snake",
        "seahorse",
        "calligraphy",
        "neon_word",
        "circles",
        "gclef",
    ] {
        let d = example(name);
        for item in design_outlines(&d, &opts()).unwrap() {
            // A stroke that crosses itself (the G-clef) is outlined by the union of its
            // region: line contours that may meet at needle-sharp corners, which the curve
            // test counts as contacts; their crossing-freedom is checked exactly below.
            if item.self_overlap {
                assert_union_contours_do_not_cross(&item.contours);
                continue;
            }
            for (k, p) in item.contours.iter().enumerate() {
                assert!(
                    path_self_intersections(p, 1e-9).is_empty(),
                    "{name}/{}: contour {k} crosses itself",
                    item.name
                );
                for q in &item.contours[k + 1..] {
                    assert!(
                        paths_intersections(p, q, 1e-9).is_empty(),
                        "{name}/{}: contours cross",
                        item.name
                    );
                }
            }
        }
    }
}

/// No two non-adjacent segments of the line contours share a point (exact predicates).
fn assert_union_contours_do_not_cross(contours: &[skinpath::geom::Path]) {
    use skinpath::geom::segments_intersect;
    let segs: Vec<(usize, usize, skinpath::geom::DVec2, skinpath::geom::DVec2)> = contours
        .iter()
        .enumerate()
        .flat_map(|(c, p)| {
            p.segs
                .iter()
                .enumerate()
                .map(move |(i, s)| (c, i, s.start(), s.end()))
        })
        .collect();
    for (k, a) in segs.iter().enumerate() {
        for b in &segs[k + 1..] {
            let n = contours[a.0].segs.len();
            let adjacent = a.0 == b.0 && (b.1 == a.1 + 1 || (a.1 == 0 && b.1 + 1 == n));
            if adjacent {
                continue;
            }
            assert!(
                !segments_intersect(a.2, a.3, b.2, b.3),
                "union contours meet: {a:?} {b:?}"
            );
        }
    }
}

#[test]
fn loop_free_examples_meet_epsilon_everywhere() {
    for name in ["brush", "ring_o", "snake", "neon_word", "calligraphy"] {
        let d = example(name);
        for item in design_outlines(&d, &opts()).unwrap() {
            let loops = item.loops.as_ref().map(|l| l.loops.len()).unwrap_or(0);
            assert_eq!(loops, 0, "{name}/{} has envelope loops", item.name);
            for r in &item.segments {
                assert!(
                    r.met_left && r.met_right,
                    "{name}/{}: segment [{}, {}] misses ε: {:?} {:?}",
                    item.name,
                    r.t0,
                    r.t1,
                    r.error_left,
                    r.error_right
                );
                assert!(r.error_left.upper <= EPS && r.error_right.upper <= EPS);
            }
        }
    }
}

#[test]
fn hairpin_loop_side_is_named_and_the_other_side_meets_epsilon() {
    let d = example("loop");
    let items = design_outlines(&d, &opts()).unwrap();
    let item = &items[0];
    let report = item.loops.as_ref().unwrap();
    assert_eq!(report.loops.len(), 1);
    let side = report.loops[0].side;
    // The hairpin's skin follows a loop side unless the stroke was split there (the skin of
    // the whole stroke cut into it: the pieces then have no loop, and the repair says so).
    match &item.repair {
        None => assert!(item.segments.iter().any(|r| !r.loops.is_empty())),
        Some(repair) => assert!(!repair.splits.is_empty(), "{repair:?}"),
    }
    for r in &item.segments {
        let free_met = match side {
            Side::Left => r.met_right,
            Side::Right => r.met_left,
        };
        assert!(free_met, "loop-free side misses ε on [{}, {}]", r.t0, r.t1);
    }
}
