//! Benchmarks of the simulation backend:
//! - the contour-contact check (hash grid + exact predicates) on 10k, 100k and 1M segments,
//!   against geo's sweep-line `Intersections` and a naive O(n²) all-pairs baseline;
//! - interpretation throughput (MB/s) against the gcode crate's parser.
//!
//! Input: a square grid of closed circles (flattened to 1000-gons), the shape of a nesting
//! or a lettering job: many contours, no intersections, all of them checked.
//! Run: `cargo bench --bench sim -- --measurement-time 2` (criterion options after `--`).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use skinpath::geom::DVec2;
use skinpath::sim::checks::SegmentSet;
use std::hint::black_box;
use std::time::Duration;

/// Segments per circle.
const PER_CIRCLE: usize = 1000;

/// `n` segments as closed 1000-gons of radius 4 on a 10 mm grid.
fn circles(n: usize) -> Vec<Vec<DVec2>> {
    let k = n.div_ceil(PER_CIRCLE);
    let side = (k as f64).sqrt().ceil() as usize;
    (0..k)
        .map(|c| {
            let o = DVec2::new((c % side) as f64 * 10.0, (c / side) as f64 * 10.0);
            (0..=PER_CIRCLE)
                .map(|i| {
                    let t = std::f64::consts::TAU * (i % PER_CIRCLE) as f64 / PER_CIRCLE as f64;
                    o + 4.0 * DVec2::new(t.cos(), t.sin())
                })
                .collect()
        })
        .collect()
}

fn segment_set(polys: &[Vec<DVec2>]) -> SegmentSet {
    let mut s = SegmentSet::new();
    for p in polys {
        s.push_polyline(p, &[]);
    }
    s
}

fn geo_lines(polys: &[Vec<DVec2>]) -> Vec<geo::Line<f64>> {
    polys
        .iter()
        .flat_map(|p| {
            p.windows(2)
                .map(|w| geo::Line::from([(w[0].x, w[0].y), (w[1].x, w[1].y)]))
        })
        .collect()
}

fn contacts(c: &mut Criterion) {
    let mut g = c.benchmark_group("contacts");
    g.sample_size(10);
    for n in [10_000usize, 100_000, 1_000_000] {
        let polys = circles(n);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("grid", n), &polys, |b, p| {
            b.iter(|| {
                let s = segment_set(p);
                black_box(s.contacts().len())
            })
        });
        g.bench_with_input(BenchmarkId::new("geo-sweep", n), &polys, |b, p| {
            b.iter(|| {
                let lines = geo_lines(p);
                black_box(geo::algorithm::sweep::Intersections::from_iter(lines).count())
            })
        });
    }
    for n in [1_000usize, 10_000] {
        let polys = circles(n);
        let set = segment_set(&polys);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("naive", n), &set, |b, s| {
            b.iter(|| {
                let mut hits = 0usize;
                for i in 0..s.segs.len() {
                    for j in i + 1..s.segs.len() {
                        hits += usize::from(s.test_pair(i, j).is_some());
                    }
                }
                black_box(hits)
            })
        });
    }
    g.finish();
}

/// About `bytes` of G-code: a laser job of lines and arcs with comments.
fn program(bytes: usize) -> String {
    let mut s = String::from("G21 G90 G17\nM4 S800 ; laser\n");
    let mut i = 0usize;
    while s.len() < bytes {
        let x = (i % 500) as f64 * 0.3;
        let y = (i / 500 % 500) as f64 * 0.3;
        s.push_str(&format!(
            "N{i} G1 X{x:.3} Y{y:.3} F1500\nG2 X{:.3} Y{y:.3} I0.100 J0 (arc)\n",
            x + 0.2
        ));
        i += 1;
    }
    s.push_str("M5\nM2\n");
    s
}

fn interpret(c: &mut Criterion) {
    let src = program(1 << 20);
    let mut g = c.benchmark_group("interpret");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(src.len() as u64));
    g.bench_function("skinpath-builtin", |b| {
        b.iter(|| black_box(skinpath::sim::interp::interpret(&src, 0.005).motions.len()))
    });
    g.bench_function("gcode-crate-parse", |b| {
        b.iter(|| black_box(gcode::parse(&src).map(|p| p.blocks.len()).unwrap_or(0)))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    targets = contacts, interpret
}
criterion_main!(benches);
