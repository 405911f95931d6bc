//! DBSC → skin approximation (kruppa-2023 Sec. 4) at ε = 0.01 mm on a few strokes.
//!
//! Run: `cargo bench --bench skin_dbsc`. Before timing, each stroke's result is printed
//! once (circles used, segments within ε, worst error bound) so the numbers can be read
//! together with the work done.
//!
//! Peer in the same run: a 10-disk stroke skinned on a one-thread rayon pool (the serial
//! path) against the default pool (Hausdorff bounds of a pass in parallel); the ratio of
//! their median times is printed. The same stroke with `ReportBounds::Decided` (what
//! `build` asks for: no tight bounds for the final report) is timed beside them, on both
//! pools, and so are eight such strokes skinned side by side (as `build` skins a design's
//! strokes in parallel), whose throughput criterion reports per stroke.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;
use skinpath::dbsc::{DiskBSpline, find_loops};
use skinpath::geom::{Circle, DVec2};
use skinpath::skin::{DbscSkinOptions, ReportBounds, skin_dbsc};
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
    let mut opts = DbscSkinOptions::default();
    opts.epsilon = 0.01;
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
    // 10-disk stroke: serial (one-thread pool) vs parallel, same result.
    let ten: Vec<(f64, f64, f64)> = (0..10)
        .map(|i| {
            let x = 6.0 * i as f64;
            (
                x,
                5.0 * (0.7 * i as f64).sin(),
                1.2 + 0.4 * (0.8 * i as f64).cos(),
            )
        })
        .collect();
    let ten = open(&ten);
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("thread pool")
    };
    let (serial, parallel) = (pool(1), pool(0));
    let same =
        serial.install(|| skin_dbsc(&ten, &opts)) == parallel.install(|| skin_dbsc(&ten, &opts));
    println!("ten_disks: serial and parallel results equal: {same}");
    let mut decided = opts;
    decided.report = ReportBounds::Decided;
    let median = |p: &rayon::ThreadPool, o: &DbscSkinOptions| {
        let mut ts: Vec<f64> = (0..15)
            .map(|_| {
                let t = std::time::Instant::now();
                let _ = p.install(|| skin_dbsc(black_box(&ten), o));
                t.elapsed().as_secs_f64()
            })
            .collect();
        ts.sort_by(f64::total_cmp);
        ts[ts.len() / 2]
    };
    let (ts, tp) = (median(&serial, &opts), median(&parallel, &opts));
    let td = median(&parallel, &decided);
    println!(
        "ten_disks: serial {:.3} ms, parallel ({} threads) {:.3} ms, serial/parallel = {:.2}; \
         decided report {:.3} ms, tight/decided = {:.2}",
        ts * 1e3,
        parallel.current_num_threads(),
        tp * 1e3,
        ts / tp,
        td * 1e3,
        tp / td
    );
    let mut g = c.benchmark_group("skin_dbsc_10_disks");
    g.sample_size(10);
    g.bench_function("serial_1_thread", |b| {
        b.iter(|| serial.install(|| skin_dbsc(black_box(&ten), &opts)))
    });
    g.bench_function("parallel", |b| {
        b.iter(|| parallel.install(|| skin_dbsc(black_box(&ten), &opts)))
    });
    // What `build` asks for: the same skin with the bounds that decided ε, no tight report.
    g.bench_function("parallel_decided_report", |b| {
        b.iter(|| parallel.install(|| skin_dbsc(black_box(&ten), &decided)))
    });
    g.bench_function("serial_decided_report", |b| {
        b.iter(|| serial.install(|| skin_dbsc(black_box(&ten), &decided)))
    });
    g.finish();
    // Eight strokes at once: the stroke-level parallelism of a design.
    let eight = vec![ten.clone(); 8];
    let mut g = c.benchmark_group("skin_dbsc_10_disks_x8");
    g.sample_size(10);
    g.throughput(Throughput::Elements(eight.len() as u64));
    g.bench_function("parallel_decided_report", |b| {
        b.iter(|| {
            parallel.install(|| {
                eight
                    .par_iter()
                    .map(|s| skin_dbsc(black_box(s), &decided))
                    .collect::<Vec<_>>()
            })
        })
    });
    g.finish();
    let mut g = c.benchmark_group("find_loops");
    for (name, s) in strokes() {
        g.bench_function(name, |b| b.iter(|| find_loops(black_box(&s), 1e-10)));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
