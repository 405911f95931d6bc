//! Skinning cost per circle: admissibility check, touching points, Bézier skins and the
//! outline contour for open sequences of n = 10 … 100 000 circles along a wavy stroke.
//! Throughput is reported per circle (elements); it should stay flat in n.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use skinpath::geom::{Circle, DVec2};
use skinpath::skin::{SkinOptions, outline_circles};
use std::hint::black_box;

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

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("skin_circles");
    let opts = SkinOptions::default();
    for n in [10usize, 100, 1_000, 10_000, 100_000] {
        let cs = wavy(n);
        // Fail loudly (in the bench, not the library) if the input is not admissible.
        if let Err(e) = outline_circles(&cs, false, &opts) {
            panic!("bench input not admissible: {e}");
        }
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::from_parameter(n), &cs, |b, cs| {
            b.iter(|| outline_circles(black_box(cs), false, &opts))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
