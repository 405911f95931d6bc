//! Skinning cost per circle: admissibility check, touching points, Bézier skins and the
//! outline contour for open sequences of n = 10 … 100 000 circles along a wavy stroke.
//! Throughput is reported per circle (elements); it should stay flat in n.
//!
//! Peer, in the same run: the outline as a polygon union, what a user without skinning
//! would do: every disk flattened to a regular polygon within [`PEER_TOLERANCE`] (chord
//! sagitta r(1 − cos(π/k)) ≤ tol), the convex hull of each consecutive pair (the tapered
//! capsule swept by a disk moving linearly between them) and the capsules merged with
//! geo's `unary_union` (i_overlay). The bench prints, per n, the median time of both and
//! the ratio peer / skinning, with the area of both outlines: the capsule union has corners
//! where consecutive capsules meet; the skin is G¹ there and bulges a little past them.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use geo::{Area, ConvexHull, LineString, MultiPoint, Polygon, unary_union};
use skinpath::geom::{Circle, DVec2};
use skinpath::skin::{SkinOptions, outline_circles};
use std::hint::black_box;
use std::time::Instant;

/// Chord tolerance of the peer's disk polygons (mm).
const PEER_TOLERANCE: f64 = 1e-3;

/// Largest n the peer runs on (a union of 10⁵ polygons takes seconds a call).
const PEER_MAX_N: usize = 10_000;

/// An admissible wavy sequence: centres 1.5 apart along a sine wave, radii between 0.7 and
/// 1.3 varying slowly.
fn wavy(n: usize) -> Vec<Circle> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            Circle::new(
                DVec2::new(1.5 * t, 3.0 * (0.15 * t).sin()),
                1.0 + 0.3 * (0.05 * t).cos(),
            )
        })
        .collect()
}

/// Circle `c` as a counter-clockwise regular polygon inscribed within `tol`.
fn disk_polygon(c: &Circle, tol: f64) -> Polygon<f64> {
    let step = 2.0 * (1.0 - tol / c.r).clamp(-1.0, 1.0).acos();
    let k = ((std::f64::consts::TAU / step).ceil() as usize).max(8);
    let ring: Vec<(f64, f64)> = (0..=k)
        .map(|i| {
            let t = std::f64::consts::TAU * (i % k) as f64 / k as f64;
            (c.c.x + c.r * t.cos(), c.c.y + c.r * t.sin())
        })
        .collect();
    Polygon::new(LineString::from(ring), vec![])
}

/// The peer: the convex hull of each consecutive pair of disk polygons, merged into one
/// outline.
fn union_outline(polys: &[Polygon<f64>]) -> geo::MultiPolygon<f64> {
    let capsules: Vec<Polygon<f64>> = polys
        .windows(2)
        .map(|w| {
            let pts: Vec<geo::Point<f64>> = w.iter().flat_map(|p| p.exterior().points()).collect();
            MultiPoint::from(pts).convex_hull()
        })
        .collect();
    unary_union(&capsules)
}

/// Median wall time of `f` over `runs` calls, in seconds.
fn median_time<R>(runs: usize, mut f: impl FnMut() -> R) -> f64 {
    let mut ts: Vec<f64> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed().as_secs_f64()
        })
        .collect();
    ts.sort_by(f64::total_cmp);
    ts[ts.len() / 2]
}

/// Area enclosed by the outline's contours, flattened within `tol` (signed: outer
/// counter-clockwise, inner clockwise).
fn outline_area(contours: &[skinpath::geom::Path], tol: f64) -> f64 {
    contours
        .iter()
        .map(|p| {
            let pts = p.flatten(tol);
            let ring: Vec<(f64, f64)> = pts.iter().map(|q| (q.x, q.y)).collect();
            Polygon::new(LineString::from(ring), vec![]).signed_area()
        })
        .sum()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("skin_circles");
    let opts = SkinOptions::default();
    for n in [10usize, 100, 1_000, 10_000, 100_000] {
        let cs = wavy(n);
        // Fail loudly (in the bench, not the library) if the input is not admissible.
        let outline = match outline_circles(&cs, false, &opts) {
            Ok(o) => o,
            Err(e) => panic!("bench input not admissible: {e}"),
        };
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::from_parameter(n), &cs, |b, cs| {
            b.iter(|| outline_circles(black_box(cs), false, &opts))
        });
        if n <= PEER_MAX_N {
            let polys: Vec<Polygon<f64>> =
                cs.iter().map(|c| disk_polygon(c, PEER_TOLERANCE)).collect();
            let union = union_outline(&polys);
            g.bench_with_input(BenchmarkId::new("geo_capsule_union", n), &polys, |b, p| {
                b.iter(|| union_outline(black_box(p)))
            });
            let runs = if n <= 1_000 { 21 } else { 5 };
            let t_skin = median_time(runs, || outline_circles(&cs, false, &opts));
            let t_peer = median_time(runs, || union_outline(&polys));
            println!(
                "skin_circles n={n}: skinning {:.3} ms ({:.2} M circles/s), geo union of capsules \
                 of {}-tolerance disk polygons {:.3} ms; ratio union/skinning = {:.1}; area: \
                 skin outline {:.4}, union {:.4} ({} polygon(s))",
                t_skin * 1e3,
                n as f64 / t_skin / 1e6,
                PEER_TOLERANCE,
                t_peer * 1e3,
                t_peer / t_skin,
                outline_area(&outline.contours, PEER_TOLERANCE),
                union.unsigned_area(),
                union.0.len()
            );
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
