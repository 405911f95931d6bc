//! Benchmarks of the simulation backend:
//! - the contour-contact check (hash grid + exact predicates) on 10k, 100k and 1M segments,
//!   against geo's sweep-line `Intersections` and a naive O(n²) all-pairs baseline; the
//!   same against geo's sweep on a dense spiral (100k and 1M segments, 200 turns);
//! - the same on a multi-pass job (nested rings in a board, 6 passes of each contour):
//!   the chain sweep without the repeated passes against the grid alone;
//! - interpretation throughput (MB/s) against the gcode crate's parser, beside skinpath's
//!   parser alone (what the gcode crate does: no interpretation) and a floor: lines split
//!   and every number after a letter parsed, nothing else (the least any reader does).
//!
//! Input: a square grid of closed circles (flattened to 1000-gons), the shape of a nesting
//! or a lettering job: many contours, no intersections, all of them checked.
//! Run: `cargo bench --bench sim -- --measurement-time 2` (criterion options after `--`).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use skinpath::geom::DVec2;
use skinpath::internals::{Across, NgcLine, SegmentSet, Syntax, parse_line_into};
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

/// `n` segments as one Archimedean spiral of 200 turns 0.45 mm apart (a spiral fill or an
/// engraving), points rounded to 3 decimals as a program writes them: dense geometry, whose
/// x-monotone half turns all nest.
fn spiral(n: usize) -> Vec<Vec<DVec2>> {
    let per_turn = n / 200;
    vec![
        (0..=200 * per_turn)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / per_turn as f64;
                let r = 0.45 * t / std::f64::consts::TAU;
                ((DVec2::splat(100.0) + r * DVec2::new(t.cos(), t.sin())) * 1e3).round() / 1e3
            })
            .collect(),
    ]
}

fn segment_set(polys: &[Vec<DVec2>]) -> SegmentSet {
    let mut s = SegmentSet::new();
    for p in polys {
        s.push_polyline(p, &[]);
    }
    s
}

/// 40 letters, each 4 concentric rings of 250 chords, inside a rectangular board, every
/// contour repeated `passes` times; contacts between contours are crossings only, as in
/// the intersection check.
fn multi_pass_rings(passes: usize) -> SegmentSet {
    let mut s = SegmentSet::new();
    s.across = Across::Crossings;
    let mut contours: Vec<Vec<DVec2>> = Vec::new();
    for l in 0..40 {
        let o = DVec2::new(12.0 * (l % 10) as f64, 12.0 * (l / 10) as f64);
        for k in 1..=4 {
            contours.push(
                (0..=250)
                    .map(|i| {
                        let t = std::f64::consts::TAU * (i % 250) as f64 / 250.0;
                        o + 1.2 * k as f64 * DVec2::new(t.cos(), t.sin())
                    })
                    .collect(),
            );
        }
    }
    let (lo, hi) = (DVec2::splat(-8.0), DVec2::new(116.0, 44.0));
    contours.push(vec![
        lo,
        DVec2::new(hi.x, lo.y),
        hi,
        DVec2::new(lo.x, hi.y),
        lo,
    ]);
    for c in &contours {
        for _ in 0..passes {
            s.push_polyline(c, &[]);
        }
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
    // Dense: the spiral, against geo's sweep on the same segments.
    for n in [100_000usize, 1_000_000] {
        let polys = spiral(n);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("spiral-grid", n), &polys, |b, p| {
            b.iter(|| {
                let s = segment_set(p);
                black_box(s.contacts().len())
            })
        });
        g.bench_with_input(BenchmarkId::new("spiral-geo-sweep", n), &polys, |b, p| {
            b.iter(|| {
                let lines = geo_lines(p);
                black_box(geo::algorithm::sweep::Intersections::from_iter(lines).count())
            })
        });
    }
    // A multi-depth router job: nested clearing rings of letters inside a board outline,
    // every contour cut in 6 passes (the passes repeat each contour bit for bit). Before
    // the copies were left out of the sweep, such a program always went to the grid:
    // "grid-only" is that route, measured beside the sweep on the same set.
    let passes = multi_pass_rings(6);
    let n = passes.len();
    g.throughput(Throughput::Elements(n as u64));
    g.bench_with_input(BenchmarkId::new("passes-sweep", n), &passes, |b, s| {
        b.iter(|| black_box(s.contacts().len()))
    });
    g.bench_with_input(BenchmarkId::new("passes-grid-only", n), &passes, |b, s| {
        b.iter(|| black_box(s.grid_only_contacts().len()))
    });
    for n in [1_000usize, 10_000] {
        let polys = circles(n);
        let set = segment_set(&polys);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("naive", n), &set, |b, s| {
            b.iter(|| {
                let mut hits = 0usize;
                for i in 0..s.len() {
                    for j in i + 1..s.len() {
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
        b.iter(|| black_box(skinpath::internals::interpret(&src, 0.005).motions.len()))
    });
    g.bench_function("gcode-crate-parse", |b| {
        b.iter(|| black_box(gcode::parse(&src).map(|p| p.blocks.len()).unwrap_or(0)))
    });
    let syn = Syntax {
        ngc: true,
        checksums: false,
        dollar: false,
    };
    g.bench_function("skinpath-parse-only", |b| {
        let mut line = NgcLine::default();
        b.iter(|| {
            let mut words = 0;
            for l in src.split('\n') {
                parse_line_into(l, syn, &mut line);
                words += line.words.len();
            }
            black_box(words)
        })
    });
    g.bench_function("floor-split-and-numbers", |b| {
        b.iter(|| black_box(split_and_numbers(src.as_bytes())))
    });
    g.finish();
}

/// The floor of reading G-code: split at line ends and parse the number after every letter
/// (fast_float2), keeping only their sum and count; no words, comments, errors or state.
fn split_and_numbers(text: &[u8]) -> (f64, usize) {
    let (mut sum, mut count) = (0.0, 0);
    for line in text.split(|&c| c == b'\n') {
        let mut k = 0;
        while k < line.len() {
            k += 1;
            if line[k - 1].is_ascii_alphabetic()
                && let Ok((v, used)) = fast_float2::parse_partial::<f64, _>(&line[k..])
            {
                sum += v;
                count += 1;
                k += used;
            }
        }
    }
    (sum, count)
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    targets = contacts, interpret
}
criterion_main!(benches);
