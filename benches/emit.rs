//! Number formatting for G-code words: `format_number` (integer route, falling back to the
//! standard formatter near ties) against `format_number_std` (the standard formatter alone,
//! the naive baseline) on the same coordinates. Both give the same text (tested in
//! `machine::tests`).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use skinpath::machine::{format_number, format_number_std};
use std::hint::black_box;

/// Coordinates of a 300 × 200 mm job, the kind `build` writes.
fn coordinates(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 * 0.618_033_988_749_895;
            150.0 + 140.0 * (t * 1.3).sin() * (t * 0.07).cos()
        })
        .collect()
}

fn bench_format(c: &mut Criterion) {
    let values = coordinates(10_000);
    let mut g = c.benchmark_group("format_number_10k");
    g.throughput(Throughput::Elements(values.len() as u64));
    for decimals in [3u32, 4] {
        g.bench_with_input(
            BenchmarkId::new("skinpath", decimals),
            &decimals,
            |b, &d| {
                b.iter(|| {
                    for &v in &values {
                        black_box(format_number(v, d));
                    }
                })
            },
        );
        g.bench_with_input(
            BenchmarkId::new("std_format", decimals),
            &decimals,
            |b, &d| {
                b.iter(|| {
                    for &v in &values {
                        black_box(format_number_std(v, d));
                    }
                })
            },
        );
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench_format
}
criterion_main!(benches);
