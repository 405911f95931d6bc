//! Unit tests of [`super`]: the exact resolution of rings against geo's boolean operations,
//! and loading of random grid contours.

use crate::geom::DVec2;

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

/// Random nested and disjoint rings (star-shaped polygons in separate radius bands around
/// two centres, each either way round): the exact resolution by nesting and orientation
/// (no crossings) gives the area of geo's union under the same fill rule, and its rings
/// are oriented (outer counter-clockwise, holes clockwise) so that nonzero and evenodd read
/// them alike.
mod resolve {
    use super::area;
    use crate::design::FillRule;
    use crate::design::shape::{edge_meeting, resolve_rings};
    use crate::geom::DVec2;
    use geo::Area;
    use geo::BooleanOps;
    use geo::algorithm::bool_ops::{FillRule as GeoRule, OpType};
    use proptest::prelude::*;

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
    use crate::design::load;
    use crate::design::shape::self_intersection;
    use proptest::prelude::*;

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
                    let profile = crate::machine::builtin_profile("grbl-laser").unwrap();
                    let built = crate::job::build::build_toolpath(
                        &d,
                        &profile,
                        &crate::job::build::BuildOptions::default(),
                    );
                    prop_assert!(built.is_ok(), "{text}: {:?}", built.err().map(|e| e.to_string()));
                }
            }
        }
    }
}
