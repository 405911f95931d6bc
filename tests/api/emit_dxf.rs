//! DXF parses back with the `dxf` crate: $INSUNITS = mm, one layer per operation, closed
//! flags, and the polylines (bulges turned back into arcs) trace the same contours.

use crate::support;

use glam::{DVec2, DVec3};
use proptest::prelude::*;
use skinpath::emit::{DxfOptions, dxf};
use skinpath::geom::Arc;
use skinpath::toolpath::Toolpath;
use support::emit::*;

fn load(text: &str) -> ::dxf::Drawing {
    ::dxf::Drawing::load(&mut text.as_bytes()).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// A polyline read back: layer, closed flag, vertices with bulges.
type Poly = (String, bool, Vec<(DVec2, f64)>);

/// Every polyline of the drawing.
fn polylines(d: &::dxf::Drawing) -> Vec<Poly> {
    d.entities()
        .filter_map(|e| match &e.specific {
            ::dxf::entities::EntityType::Polyline(p) => Some((
                e.common.layer.clone(),
                p.is_closed(),
                p.vertices()
                    .map(|v| (DVec2::new(v.location.x, v.location.y), v.bulge))
                    .collect(),
            )),
            _ => None,
        })
        .collect()
}

/// Length of a bulged polyline and the arcs it contains (centre, radius).
fn measure(closed: bool, vs: &[(DVec2, f64)]) -> (f64, Vec<(DVec2, f64)>) {
    let n = vs.len();
    let segs = if closed { n } else { n - 1 };
    let mut len = 0.0;
    let mut arcs = Vec::new();
    for i in 0..segs {
        let (p, b) = vs[i];
        let q = vs[(i + 1) % n].0;
        if b == 0.0 {
            len += p.distance(q);
        } else {
            let a = Arc::from_bulge(p, q, b);
            len += a.length();
            arcs.push((a.center, a.radius));
        }
    }
    (len, arcs)
}

fn check(tp: &Toolpath) {
    let text = dxf(tp, &DxfOptions::default()).unwrap();
    let d = load(&text);
    assert_eq!(
        d.header.default_drawing_units,
        ::dxf::enums::Units::Millimeters
    );
    let layers: Vec<String> = d.layers().map(|l| l.name.clone()).collect();
    for (i, op) in tp.operations.iter().enumerate() {
        let want = skinpath::emit::dxf::layer_name(i, &op.name);
        assert!(layers.contains(&want), "{want} not in {layers:?}");
    }
    let polys = polylines(&d);
    let ncuts: usize = tp.operations.iter().map(|o| o.cuts.len()).sum();
    assert_eq!(polys.len(), ncuts);
    let circles = arc_circles(tp);
    let mut total = 0.0;
    for ((layer, closed, vs), (oi, op, c)) in polys.iter().zip(
        tp.operations
            .iter()
            .enumerate()
            .flat_map(|(oi, op)| op.cuts.iter().map(move |c| (oi, op, c))),
    ) {
        assert_eq!(*layer, skinpath::emit::dxf::layer_name(oi, &op.name));
        let end = c.moves.last().unwrap().to.truncate();
        assert_eq!(*closed, end.distance(c.start.truncate()) < 1e-9);
        assert!((vs[0].0 - c.start.truncate()).length() < 1e-12);
        for (_, b) in vs {
            assert!(b.abs() <= (std::f64::consts::PI / 6.0).tan() + 1e-12);
        }
        let (len, arcs) = measure(*closed, vs);
        total += len;
        for (ac, ar) in arcs {
            assert!(
                circles
                    .iter()
                    .any(|(c, r)| c.distance(ac) < 1e-9 && (r - ar).abs() < 1e-9),
                "arc ({ac}, {ar}) from a bulge is on no input circle"
            );
        }
    }
    let want = cut_length_xy(tp);
    assert!((total - want).abs() < 1e-9 * want, "{total} vs {want}");
}

#[test]
fn job_round_trips() {
    check(&job(&[0.0], 1.0));
}

#[test]
fn extents_include_arc_bulges() {
    // Holes at (30, 40) and (70, 40) of radius 3, the S-curve and the outline: the drawing
    // spans x 20..80 and y 20..60 (outline), and the S-curve's semicircle reaches y = 40
    // while its 270° arc reaches x = 61 — all inside the outline.
    let d = load(&dxf(&job(&[0.0], 1.0), &DxfOptions::default()).unwrap());
    let (lo, hi) = (
        d.header.minimum_drawing_extents.clone(),
        d.header.maximum_drawing_extents.clone(),
    );
    assert_eq!((lo.x, lo.y), (20.0, 20.0));
    assert_eq!((hi.x, hi.y), (80.0, 60.0));
    // A lone circle: the extents are the circle's box, not its start point.
    let tp = Toolpath {
        operations: vec![op(
            "hole",
            skinpath::toolpath::OperationKind::Holes,
            vec![circle(DVec2::new(5.0, 5.0), 2.0, 0.0, true, 1.0)],
        )],
    };
    let d = load(&dxf(&tp, &DxfOptions::default()).unwrap());
    let (lo, hi) = (
        d.header.minimum_drawing_extents.clone(),
        d.header.maximum_drawing_extents.clone(),
    );
    assert!(
        (lo.x - 3.0).abs() < 1e-12 && (lo.y - 3.0).abs() < 1e-12,
        "{lo:?}"
    );
    assert!(
        (hi.x - 7.0).abs() < 1e-12 && (hi.y - 7.0).abs() < 1e-12,
        "{hi:?}"
    );
}

#[test]
fn passes_and_reversed_directions_round_trip() {
    let mut tp = job(&[0.0, -1.0], 1.0);
    // Reverse every cut: arcs change direction, starts become ends.
    for op in &mut tp.operations {
        for c in &mut op.cuts {
            let mut pts = vec![c.start];
            pts.extend(c.moves.iter().map(|m| m.to));
            let mut moves = Vec::new();
            for (i, m) in c.moves.iter().enumerate().rev() {
                let mut r = *m;
                r.to = pts[i];
                if let skinpath::toolpath::MoveKind::Arc { ccw, .. } = &mut r.kind {
                    *ccw = !*ccw;
                }
                moves.push(r);
            }
            c.start = *pts.last().unwrap();
            c.moves = moves;
        }
    }
    check(&tp);
}

#[test]
fn lone_full_circle_is_closed() {
    let tp = Toolpath {
        operations: vec![op(
            "hole",
            skinpath::toolpath::OperationKind::Holes,
            vec![circle(DVec2::new(5.0, 5.0), 2.0, 0.0, false, 1.0)],
        )],
    };
    let d = load(&dxf(&tp, &DxfOptions::default()).unwrap());
    let polys = polylines(&d);
    assert_eq!(polys.len(), 1);
    assert!(polys[0].1, "closed flag");
    assert_eq!(polys[0].2.len(), 3, "three 120° pieces");
    let (len, _) = measure(true, &polys[0].2);
    assert!((len - 2.0 * std::f64::consts::PI * 2.0).abs() < 1e-12);
    let _ = DVec3::ZERO;
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random chains of lines and tangent arcs (sweeps up to a full turn) round-trip.
    #[test]
    fn random_chains_round_trip(
        start in (-50.0f64..50.0, -50.0f64..50.0),
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
        check(&tp);
    }
}
