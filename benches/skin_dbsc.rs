//! DBSC → skin approximation (kruppa-2023 Sec. 4) at ε = 0.01 mm on a few strokes.
//!
//! Run: `cargo bench --bench skin_dbsc`. Before timing, each stroke's result is printed
//! once (circles used, segments within ε, worst error bound) so the numbers can be read
//! together with the work done.

use criterion::{Criterion, criterion_group, criterion_main};
use skinpath::dbsc::{DiskBSpline, find_loops};
use skinpath::geom::{Circle, DVec2};
use skinpath::skin::dbsc_skin::{DbscSkinOptions, skin_dbsc};
use std::hint::black_box;

fn open(d: &[(f64, f64, f64)]) -> DiskBSpline {
    let disks: Vec<Circle> = d
        .iter()
        .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
        .collect();
    DiskBSpline::open(3, &disks, None).expect("valid bench stroke")
}

fn strokes() -> Vec<(&'static str, DiskBSpline)> {
    let wave: Vec<(f64, f64, f64)> = (0..12)
        .map(|i| {
            let x = 5.0 * i as f64;
            (
                x,
                4.0 * (0.6 * i as f64).sin(),
                1.0 + 0.5 * (0.9 * i as f64).cos().abs(),
            )
        })
        .collect();
    let ring: Vec<Circle> = (0..8)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 8.0;
            Circle::new(
                DVec2::new(20.0 * a.cos(), 12.0 * a.sin()),
                1.5 + 0.5 * (i % 2) as f64,
            )
        })
        .collect();
    vec![
        (
            "s_curve",
            open(&[
                (0.0, 0.0, 1.0),
                (6.0, 3.0, 1.5),
                (12.0, 0.0, 2.0),
                (18.0, -3.0, 1.5),
                (24.0, 0.0, 1.2),
                (30.0, 2.0, 1.0),
            ]),
        ),
        (
            "sharp_bend_loop",
            open(&[
                (0.0, 0.0, 0.8),
                (4.0, 0.0, 0.8),
                (5.0, 1.0, 0.8),
                (4.0, 2.0, 0.8),
                (0.0, 2.2, 0.8),
            ]),
        ),
        ("wave_12_disks", open(&wave)),
        (
            "closed_ring",
            DiskBSpline::closed(3, &ring, None).expect("valid bench ring"),
        ),
    ]
}

fn bench(c: &mut Criterion) {
    let opts = DbscSkinOptions {
        eps: 0.01,
        ..DbscSkinOptions::default()
    };
    let mut g = c.benchmark_group("skin_dbsc_eps_0.01mm");
    g.sample_size(10);
    for (name, s) in strokes() {
        if let Ok(r) = skin_dbsc(&s, &opts) {
            let met = r
                .report
                .iter()
                .filter(|x| x.met_left && x.met_right)
                .count();
            let worst = r
                .report
                .iter()
                .map(|x| x.error_left.upper.max(x.error_right.upper))
                .fold(0.0, f64::max);
            let loops = find_loops(&s, 1e-10).map(|l| l.loops.len()).unwrap_or(0);
            println!(
                "{name}: {} knot circles -> {} circles, {met}/{} segments within eps, worst upper bound {worst:.4} mm, {loops} envelope loops",
                s.breakpoints().len(),
                r.circles.len(),
                r.report.len()
            );
        }
        g.bench_function(name, |b| b.iter(|| skin_dbsc(black_box(&s), &opts)));
    }
    g.finish();
    let mut g = c.benchmark_group("find_loops");
    for (name, s) in strokes() {
        g.bench_function(name, |b| b.iter(|| find_loops(black_box(&s), 1e-10)));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
