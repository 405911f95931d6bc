//! Outer offsets at every δ: the wreath's hole closing up, and random sequences against
//! geo's buffer of the flattened skin.

use super::*;
use crate::geom::Circle;
use crate::skin::re::{Interp, Touch};
use geo::{Area, Buffer};
use proptest::prelude::*;

/// The wreath of examples/circles.toml: fourteen circles of radii 7 and 5 around a 25 mm
/// circle (closed).
fn wreath() -> Vec<Circle> {
    [
        [225.00, 55.00, 7.0],
        [222.52, 65.85, 5.0],
        [215.59, 74.55, 7.0],
        [205.56, 79.37, 5.0],
        [194.44, 79.37, 7.0],
        [184.41, 74.55, 5.0],
        [177.48, 65.85, 7.0],
        [175.00, 55.00, 5.0],
        [177.48, 44.15, 7.0],
        [184.41, 35.45, 5.0],
        [194.44, 30.63, 7.0],
        [205.56, 30.63, 5.0],
        [215.59, 35.45, 7.0],
        [222.52, 44.15, 5.0],
    ]
    .iter()
    .map(|c| Circle::new(DVec2::new(c[0], c[1]), c[2]))
    .collect()
}

fn kh_skin(cs: &[Circle], closed: bool, interp: Interp) -> ReSkin {
    let tps = crate::skin::touching::touching_points(cs, closed, 1e-12).unwrap();
    let touches: Vec<Touch> = tps
        .iter()
        .map(|t| Touch::Fixed {
            plus: t.left,
            minus: t.right,
        })
        .collect();
    ReSkin::build(cs, &touches, closed, interp, 1e-9 * 300.0).unwrap()
}

/// Dense points of every contour piece.
fn piece_samples(off: &MatOffset, per_piece: usize) -> Vec<DVec2> {
    let mut v = Vec::new();
    for c in &off.contours {
        for p in &c.pieces {
            for k in 0..=per_piece {
                v.push(off.piece_point(p, k as f64 / per_piece as f64).unwrap());
            }
        }
    }
    v
}

/// Signed area of the contours (flattened), counter-clockwise positive.
fn signed_area(off: &MatOffset, tol: f64) -> f64 {
    off.to_line_paths(tol)
        .unwrap()
        .iter()
        .map(|p| crate::geom::path::polygon_area(&p.flatten(tol)))
        .sum()
}

/// geo polygon of the skin's region: its outline contours flattened (outer and hole).
fn skin_polygon(skin: &ReSkin, tol: f64) -> geo::MultiPolygon<f64> {
    let ol = outline(skin).unwrap();
    let mut rings: Vec<(f64, geo::LineString<f64>)> = ol
        .to_line_paths(tol)
        .unwrap()
        .iter()
        .map(|p| {
            let pts = p.flatten(tol);
            let a = crate::geom::path::polygon_area(&pts);
            let ls: geo::LineString<f64> =
                pts.iter().map(|q| geo::coord! {x: q.x, y: q.y}).collect();
            (a, ls)
        })
        .collect();
    rings.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
    let outer = rings.remove(0).1;
    let holes = rings.into_iter().map(|r| r.1).collect();
    geo::MultiPolygon(vec![geo::Polygon::new(outer, holes)])
}

fn ring_count(mp: &geo::MultiPolygon<f64>) -> usize {
    mp.0.iter().map(|p| 1 + p.interiors().len()).sum()
}

#[test]
fn wreath_hole_side_at_large_delta_is_at_delta() {
    // Before the global trim the hole-side contour kept parts 14.06 from the skin at δ = 15.
    let skin = kh_skin(&wreath(), true, Interp::Cubic);
    for (delta, contours) in [(1.0, 2), (8.0, 2), (15.0, 2), (21.0, 1), (30.0, 1)] {
        let off = outer_offset(&skin, delta, 1e-12)
            .map_err(|e| format!("δ = {delta}: {e}"))
            .unwrap();
        assert_eq!(off.contours.len(), contours, "δ = {delta}");
        for q in piece_samples(&off, 24) {
            let d = region_distance(&skin, q).unwrap();
            assert!((d - delta).abs() < 1e-6, "δ = {delta}: {q} at {d}");
        }
        // The exact contours close and do not cross themselves.
        for p in off.to_cubic_paths(1e-5).unwrap() {
            assert!(p.max_gap() < 1e-7, "gap {}", p.max_gap());
            let hits = crate::geom::intersect::path_self_intersections(&p, 1e-9);
            assert!(hits.is_empty(), "δ = {delta}: {hits:?}");
        }
    }
}

#[test]
fn wreath_matches_geo_buffer() {
    let skin = kh_skin(&wreath(), true, Interp::PhQuintic);
    let poly = skin_polygon(&skin, 1e-3);
    for delta in [2.0, 15.0, 21.0] {
        let off = outer_offset(&skin, delta, 1e-12).unwrap();
        let buf = poly.buffer(delta);
        let areas: Vec<f64> = off
            .to_line_paths(1e-3)
            .unwrap()
            .iter()
            .map(|p| crate::geom::path::polygon_area(&p.flatten(1e-3)))
            .collect();
        assert_eq!(
            off.contours.len(),
            ring_count(&buf),
            "δ = {delta}: {areas:?}"
        );
        let (a, b) = (signed_area(&off, 1e-3).abs(), buf.unsigned_area());
        assert!((a - b).abs() < 2e-3 * a, "δ = {delta}: {a} vs geo {b}");
    }
}

/// Random admissible-looking open sequences: centres along a wandering path starting in
/// direction `dir0`, each step turning by up to ±`turn` and `len` long (longer than the
/// radius change), radii in `radii`. Shared with the merged-arc tests.
pub(crate) fn wandering(
    turn: f64,
    len: std::ops::Range<f64>,
    radii: std::ops::Range<f64>,
    dir0: f64,
) -> impl Strategy<Value = Vec<Circle>> {
    prop::collection::vec((-turn..turn, len, radii), 3..7).prop_map(move |steps| {
        let mut dir = dir0;
        let mut p = DVec2::ZERO;
        steps
            .iter()
            .map(|&(turn, len, r)| {
                dir += turn;
                p += len * DVec2::new(dir.cos(), dir.sin());
                Circle::new(p, r)
            })
            .collect()
    })
}

/// [`wandering`] with turns up to ±0.9, steps 2–3.5 and radii in [0.5, 2].
fn sequence() -> impl Strategy<Value = Vec<Circle>> {
    wandering(0.9, 2.0..3.5, 0.5..2.0, 0.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Outer offsets up to 3× the largest radius sit at distance δ from the skin's region
    /// and agree with geo's buffer of the flattened skin in ring count and area.
    #[test]
    fn outer_offset_matches_geo_buffer(cs in sequence(), k in 0.05f64..3.0, ph in any::<bool>()) {
        let admissible = crate::skin::check_admissible(
            &cs,
            false,
            &crate::skin::AdmissibilityOptions::default(),
        )
        .is_ok();
        prop_assume!(admissible);
        let interp = if ph { Interp::PhQuintic } else { Interp::Cubic };
        let tps = crate::skin::touching::touching_points(&cs, false, 1e-12);
        prop_assume!(tps.is_ok());
        let touches: Vec<Touch> = tps
            .unwrap()
            .iter()
            .map(|t| Touch::Fixed { plus: t.left, minus: t.right })
            .collect();
        let skin = ReSkin::build(&cs, &touches, false, interp, 1e-9 * 50.0);
        prop_assume!(skin.is_ok());
        let skin = skin.unwrap();
        prop_assume!(check_f(&skin).is_ok());
        prop_assume!(envelope_loops(&skin, 1e-10).unwrap().is_empty());
        let rmax = cs.iter().fold(0.0f64, |m, c| m.max(c.r));
        let delta = k * rmax;
        let off = outer_offset(&skin, delta, 1e-12).unwrap();
        for q in piece_samples(&off, 12) {
            let d = region_distance(&skin, q).unwrap();
            prop_assert!((d - delta).abs() < 1e-6, "{q} at {d} vs {delta}");
        }
        let buf = skin_polygon(&skin, 1e-3).buffer(delta);
        prop_assert_eq!(off.contours.len(), ring_count(&buf));
        let (a, b) = (signed_area(&off, 1e-3).abs(), buf.unsigned_area());
        prop_assert!((a - b).abs() < 3e-3 * a, "{a} vs geo {b}");
    }
}
