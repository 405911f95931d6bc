//! DXF parses back: $INSUNITS = mm, one layer per operation, closed flags, and the polylines
//! (bulges turned back into arcs) trace the same contours. Read by the test's own group-code
//! reader, which ezdxf (the reference Python DXF library, when installed: `python3-ezdxf`)
//! confirms on every drawing the tests write.

use crate::support;

use glam::DVec2;
use proptest::prelude::*;
use skinpath::emit::{DxfOptions, dxf};
use skinpath::geom::Arc;
use skinpath::toolpath::Toolpath;
use support::dxf::{Poly, load};
use support::emit::*;

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
    assert_eq!(d.insunits, Some(4), "millimetres");
    let layers = &d.layers;
    for (i, op) in tp.operations.iter().enumerate() {
        let want = layer_name(i, &op.name);
        assert!(layers.contains(&want), "{want} not in {layers:?}");
    }
    let polys = &d.polylines;
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
        assert_eq!(*layer, layer_name(oi, &op.name));
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
    let (lo, hi) = d.extents.expect("extents in the header");
    assert_eq!((lo.x, lo.y), (20.0, 20.0));
    assert_eq!((hi.x, hi.y), (80.0, 60.0));
    // A lone circle: the extents are the circle's box, not its start point.
    let d = load(&dxf(&lone_circle(true), &DxfOptions::default()).unwrap());
    let (lo, hi) = d.extents.expect("extents in the header");
    assert!(
        (lo.x - 3.0).abs() < 1e-12 && (lo.y - 3.0).abs() < 1e-12,
        "{lo:?}"
    );
    assert!(
        (hi.x - 7.0).abs() < 1e-12 && (hi.y - 7.0).abs() < 1e-12,
        "{hi:?}"
    );
}

/// `tp` with every cut reversed: arcs change direction, starts become ends.
fn reversed(mut tp: Toolpath) -> Toolpath {
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
    tp
}

/// A lone full circle of radius 2 about (5, 5), as a hole.
fn lone_circle(ccw: bool) -> Toolpath {
    Toolpath {
        operations: vec![op(
            "hole",
            skinpath::toolpath::OperationKind::Holes,
            vec![circle(DVec2::new(5.0, 5.0), 2.0, 0.0, ccw, 1.0)],
        )],
    }
}

/// A profile along a chain of lines and tangent arcs from `start` (see `support::emit::chain`).
fn chain_job(start: DVec2, steps: &[(u8, f64, f64, f64, bool)]) -> Toolpath {
    Toolpath {
        operations: vec![op(
            "random",
            skinpath::toolpath::OperationKind::Profile,
            vec![cut(start.extend(0.0), chain(start, steps, 0.0))],
        )],
    }
}

#[test]
fn passes_and_reversed_directions_round_trip() {
    check(&reversed(job(&[0.0, -1.0], 1.0)));
}

/// ezdxf, the reference DXF library, reads every drawing these tests write as the test's own
/// reader does: the same units, extents, layers and polylines, number for number. Skipped
/// (and says so) where no Python with ezdxf is installed.
#[test]
fn ezdxf_reads_what_the_group_code_reader_reads() {
    const SCRIPT: &str = r#"
import json, sys, ezdxf
def num(x):
    return repr(float(x))
out = []
for path in sys.argv[1:]:
    doc = ezdxf.readfile(path)
    h = doc.header
    out.append({
        "insunits": h.get("$INSUNITS"),
        "extents": [[num(c) for c in list(h[k])[:2]] for k in ("$EXTMIN", "$EXTMAX")],
        "layers": [l.dxf.name for l in doc.layers],
        "polylines": [[e.dxf.layer, e.is_closed,
                       [[num(v.dxf.location[0]), num(v.dxf.location[1]),
                         num(v.dxf.get("bulge", 0.0))]
                        for v in e.vertices]]
                      for e in doc.modelspace() if e.dxftype() == "POLYLINE"],
    })
print(json.dumps(out))
"#;
    let Some(python) = ["python3", "/usr/bin/python3"].into_iter().find(|p| {
        std::process::Command::new(p)
            .args(["-c", "import ezdxf"])
            .output()
            .is_ok_and(|o| o.status.success())
    }) else {
        eprintln!("SKIPPED: ezdxf (python3-ezdxf) is not installed");
        return;
    };
    let mut rng = support::rng::Rng::new(0xD8F0_0001);
    let mut drawings = vec![
        job(&[0.0], 1.0),
        reversed(job(&[0.0, -1.0], 1.0)),
        lone_circle(true),
        lone_circle(false),
    ];
    for _ in 0..64 {
        let start = DVec2::new(rng.range(-50.0, 50.0), rng.range(-50.0, 50.0));
        let steps: Vec<_> = (0..1 + rng.below(11))
            .map(|_| {
                let kind = rng.below(3) as u8;
                let (len, turn, sweep) = (
                    rng.range(0.5, 20.0),
                    rng.range(-3.1, 3.1),
                    rng.range(0.01, 6.2),
                );
                (kind, len, turn, sweep, rng.below(2) == 1)
            })
            .collect();
        drawings.push(chain_job(start, &steps));
    }
    let dir = support::tmpdir("ezdxf");
    let mut paths = Vec::new();
    let mut ours = Vec::new();
    for (i, tp) in drawings.iter().enumerate() {
        let text = dxf(tp, &DxfOptions::default()).unwrap();
        let path = dir.join(format!("d{i}.dxf"));
        std::fs::write(&path, &text).unwrap();
        paths.push(path);
        ours.push(load(&text));
    }
    let out = std::process::Command::new(python)
        .arg("-c")
        .arg(SCRIPT)
        .args(&paths)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(theirs.len(), ours.len());
    // Numbers come as Python's shortest round-trip text, parsed here correctly rounded (JSON
    // numbers through serde_json may be one unit in the last place off).
    let f = |v: &serde_json::Value| v.as_str().unwrap().parse::<f64>().unwrap();
    for (i, (t, o)) in theirs.iter().zip(&ours).enumerate() {
        assert_eq!(t["insunits"].as_i64(), o.insunits, "drawing {i}");
        let e = &t["extents"];
        let ext = (
            DVec2::new(f(&e[0][0]), f(&e[0][1])),
            DVec2::new(f(&e[1][0]), f(&e[1][1])),
        );
        assert_eq!(Some(ext), o.extents, "drawing {i}");
        // ezdxf adds its two standard layers ("0", "Defpoints") to every document.
        let layers: Vec<&str> = (t["layers"].as_array().unwrap().iter())
            .map(|l| l.as_str().unwrap())
            .filter(|l| !["0", "Defpoints"].contains(l))
            .collect();
        assert_eq!(layers, o.layers, "drawing {i}");
        let polys: Vec<Poly> = (t["polylines"].as_array().unwrap().iter())
            .map(|p| {
                let vs = (p[2].as_array().unwrap().iter())
                    .map(|v| (DVec2::new(f(&v[0]), f(&v[1])), f(&v[2])))
                    .collect();
                (
                    p[0].as_str().unwrap().to_string(),
                    p[1].as_bool().unwrap(),
                    vs,
                )
            })
            .collect();
        assert_eq!(polys, o.polylines, "drawing {i}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn lone_full_circle_is_closed() {
    let d = load(&dxf(&lone_circle(false), &DxfOptions::default()).unwrap());
    let polys = &d.polylines;
    assert_eq!(polys.len(), 1);
    assert!(polys[0].1, "closed flag");
    assert_eq!(polys[0].2.len(), 3, "three 120° pieces");
    let (len, _) = measure(true, &polys[0].2);
    assert!((len - 2.0 * std::f64::consts::PI * 2.0).abs() < 1e-12);
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
        check(&chain_job(DVec2::new(start.0, start.1), &steps));
    }
}

/// The layer the DXF writer names for operation `index` called `name`: `OP{index}_` and the
/// name with every character other than ASCII letters, digits, `-` and `_` replaced by `_`,
/// at most 40 of them.
fn layer_name(index: usize, name: &str) -> String {
    let clean: String = name
        .chars()
        .take(40)
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("OP{index}_{clean}")
}
