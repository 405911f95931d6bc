//! Toolpath benches: offsetting an outline with arcs (cavalier_contours, via
//! `Region::offset`) against geo's `Buffer` of the same outline flattened, in the same run;
//! plus hatch filling and ordering, on a synthetic flower and on the shipped examples'
//! outlines (`bench_example_offsets`: inward and outward, with accuracy and area ratio),
//! and winding numbers through `toolpath::winding` against cavalier's (`bench_winding`),
//! and a channel's region with arcs against geo's buffer of its flattened spine
//! (`bench_channel_region`).
//! Accuracy of both offsets (largest deviation of the result's vertices from distance δ to
//! the source) is printed once per size.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use geo::Buffer;
use skinpath::geom::{DVec2, Line, Path};
use skinpath::internals::{
    ProfileSide, Region, concentric, flatten_pline, hatch, order_paths, pline_from_points, profile,
};
use skinpath::job::design_outlines;
use std::hint::black_box;

/// A wavy closed outline with `n` vertices (a flower of radius 40 ± 8 mm).
fn flower(n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64 * std::f64::consts::TAU;
            let r = 40.0 + 8.0 * (7.0 * t).sin();
            DVec2::new(r * t.cos(), r * t.sin())
        })
        .collect()
}

fn polygon_distance(poly: &[DVec2], p: DVec2) -> f64 {
    (0..poly.len())
        .map(|i| Line::new(poly[i], poly[(i + 1) % poly.len()]).distance(p))
        .fold(f64::INFINITY, f64::min)
}

fn bench_offsets(c: &mut Criterion) {
    let delta = 1.5;
    let mut g = c.benchmark_group("offset_outward_1.5mm");
    for &n in &[100usize, 1000, 10_000] {
        let pts = flower(n);
        let region = Region::from_contours(vec![pline_from_points(&pts, true)]);
        let mut ring: Vec<geo::Coord<f64>> =
            pts.iter().map(|p| geo::Coord { x: p.x, y: p.y }).collect();
        ring.push(ring[0]);
        let poly = geo::Polygon::new(geo::LineString::new(ring), vec![]);

        // Accuracy, once: vertices of each result against distance δ.
        let cav = region.offset(delta, 1e-6);
        let cav_err = cav
            .contours
            .iter()
            .flat_map(|c| flatten_pline(c, 1e-4))
            .map(|p| (polygon_distance(&pts, p) - delta).abs())
            .fold(0.0, f64::max);
        let geo_res = poly.buffer(delta);
        let geo_err = geo_res
            .0
            .iter()
            .flat_map(|p| {
                p.exterior()
                    .coords()
                    .map(|c| DVec2::new(c.x, c.y))
                    .collect::<Vec<_>>()
            })
            .map(|p| (polygon_distance(&pts, p) - delta).abs())
            .fold(0.0, f64::max);
        println!(
            "n={n}: max |dist − δ| cavalier (arcs) {cav_err:.2e} mm, geo buffer {geo_err:.2e} mm"
        );

        g.bench_with_input(BenchmarkId::new("cavalier_region_offset", n), &n, |b, _| {
            b.iter(|| black_box(region.offset(delta, 1e-6)))
        });
        g.bench_with_input(BenchmarkId::new("geo_buffer", n), &n, |b, _| {
            b.iter(|| black_box(poly.buffer(delta)))
        });
    }
    g.finish();
}

/// Winding numbers of every vertex of an offset flower about the flower (what
/// `Region::holds` asks after an offset): the slab index of `toolpath::winding` against
/// cavalier_contours' `winding_number` walking every segment, in the same run. The two
/// counts are compared once.
fn bench_winding(c: &mut Criterion) {
    use cavalier_contours::core::math::Vector2;
    use cavalier_contours::polyline::{PlineSource, Polyline};
    use skinpath::geom::WindingIndex;
    let mut g = c.benchmark_group("winding_of_offset_vertices");
    for &n in &[100usize, 1000, 10_000] {
        let region = Region::from_contours(vec![pline_from_points(&flower(n), true)]);
        let grown = region.offset(1.5, 1e-6);
        let pl: &Polyline<f64> = &region.contours[0];
        let probes: Vec<Vector2<f64>> = (grown.contours.iter())
            .flat_map(|c| c.iter_vertexes().map(|v| Vector2::new(v.x, v.y)))
            .collect();
        let index = WindingIndex::new(pl);
        let same = probes
            .iter()
            .all(|&p| index.winding(p) == pl.winding_number(p));
        println!("n={n}: {} probes, index == cavalier: {same}", probes.len());
        g.bench_with_input(BenchmarkId::new("index_build_and_query", n), &n, |b, _| {
            b.iter(|| {
                let w = WindingIndex::new(pl);
                black_box(probes.iter().map(|&p| w.winding(p)).sum::<i32>())
            })
        });
        g.bench_with_input(
            BenchmarkId::new("cavalier_winding_number", n),
            &n,
            |b, _| b.iter(|| black_box(probes.iter().map(|&p| pl.winding_number(p)).sum::<i32>())),
        );
    }
    g.finish();
}

/// Regions of the shipped examples' outlines (arcs from the biarc fit within 1e-3): each
/// example's largest item (items of one design may overlap, and a region's contours must
/// not cross).
fn example_regions() -> Vec<(String, Region)> {
    let mut out = Vec::new();
    for ex in ["brush", "ring_o", "neon_word", "calligraphy", "circles"] {
        let file = format!("{}/examples/{ex}.toml", env!("CARGO_MANIFEST_DIR"));
        let Ok(text) = std::fs::read_to_string(&file) else {
            continue;
        };
        let Ok(design) = skinpath::design::load(&text, &file) else {
            continue;
        };
        let opts = skinpath::job::OutlineOptions::default();
        let Ok(items) = design_outlines(&design, &opts) else {
            continue;
        };
        let largest = items
            .iter()
            .map(|o| Region::from_paths(&o.contours, 1e-3))
            .max_by(|a, b| a.area().abs().total_cmp(&b.area().abs()));
        if let Some(r) = largest {
            out.push((ex.to_string(), r));
        }
    }
    out
}

/// Exact distance from `p` to closed rings.
fn rings_distance(rings: &[Vec<DVec2>], p: DVec2) -> f64 {
    rings
        .iter()
        .map(|r| polygon_distance(r, p))
        .fold(f64::INFINITY, f64::min)
}

/// Largest |distance to the source − δ| over at most ~300 samples of the result.
fn max_error(src: &[Vec<DVec2>], result: &[Vec<DVec2>], delta: f64) -> f64 {
    result
        .iter()
        .flat_map(|r| r.iter().step_by((r.len() / 300).max(1)).copied())
        .map(|p| (rings_distance(src, p) - delta).abs())
        .fold(0.0, f64::max)
}

/// Offsets of each example's outline: cavalier (arcs) against geo's buffer of the same
/// outline flattened within 1e-3, both ways; prints time ratio inputs via criterion and
/// the accuracy and area ratio once.
fn bench_example_offsets(c: &mut Criterion) {
    use geo::Area;
    let flat_tol = 1e-3;
    let mut g = c.benchmark_group("example_offset");
    for (ex, region) in example_regions() {
        let poly = region.to_geo(flat_tol);
        let src: Vec<Vec<DVec2>> = region
            .contours
            .iter()
            .map(|c| flatten_pline(c, 1e-4))
            .collect();
        let n: usize = src.iter().map(Vec::len).sum();
        for delta in [1.5, -1.0] {
            // Round joins with chord sagitta ≤ flat_tol: angle step √(8·tol/|δ|).
            let phi = (8.0 * flat_tol / f64::abs(delta)).sqrt();
            let style = geo::algorithm::buffer::BufferStyle::new(delta)
                .line_join(geo::algorithm::buffer::LineJoin::Round(phi));
            let cav = region.offset(delta, 1e-6);
            let theirs = poly.buffer_with_style(style.clone());
            let cav_rings: Vec<Vec<DVec2>> = cav
                .contours
                .iter()
                .map(|c| flatten_pline(c, 1e-4))
                .collect();
            let geo_rings: Vec<Vec<DVec2>> = theirs
                .0
                .iter()
                .flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors()))
                .map(|l| l.coords().map(|c| DVec2::new(c.x, c.y)).collect())
                .collect();
            println!(
                "{ex} (n={n}) δ={delta}: max |d − δ| cavalier {:.2e}, geo {:.2e}; area ratio \
                 cavalier/geo {:.6}",
                max_error(&src, &cav_rings, delta.abs()),
                max_error(&src, &geo_rings, delta.abs()),
                cav.area() / theirs.unsigned_area()
            );
            g.bench_function(BenchmarkId::new(format!("cavalier_{delta}"), &ex), |b| {
                b.iter(|| black_box(region.offset(delta, 1e-6)))
            });
            g.bench_function(BenchmarkId::new(format!("geo_buffer_{delta}"), &ex), |b| {
                b.iter(|| black_box(poly.buffer_with_style(style.clone())))
            });
        }
        g.bench_function(BenchmarkId::new("hatch_0.5", &ex), |b| {
            b.iter(|| black_box(hatch(&region, 0.5, 0.5, true, flat_tol)))
        });
        g.bench_function(BenchmarkId::new("concentric_1", &ex), |b| {
            b.iter(|| black_box(concentric(&region, 1.0, 1.0, 1.0, 10_000, 1e-6)))
        });
        let profiles = profile(&region, ProfileSide::Outside, 1.5, 1e-6);
        g.bench_function(BenchmarkId::new("order_profiles", &ex), |b| {
            b.iter(|| black_box(order_paths(&profiles, DVec2::ZERO, flat_tol)))
        });
    }
    g.finish();
}

fn bench_hatch_and_order(c: &mut Criterion) {
    let pts = flower(2000);
    let region = Region::from_contours(vec![pline_from_points(&pts, true)]);
    c.bench_function("hatch_0.2mm_flower", |b| {
        b.iter(|| black_box(hatch(&region, 0.5, 0.2, true, 1e-3)))
    });
    let squares: Vec<Path> = (0..400)
        .map(|i| {
            let c = DVec2::new((i * 37 % 200) as f64, (i * 91 % 200) as f64);
            Path::polyline(
                &[
                    c,
                    c + DVec2::new(3.0, 0.0),
                    c + DVec2::new(3.0, 3.0),
                    c + DVec2::new(0.0, 3.0),
                ],
                true,
            )
        })
        .collect();
    c.bench_function("order_400_contours", |b| {
        b.iter(|| black_box(order_paths(&squares, DVec2::ZERO, 1e-3)))
    });
}

/// A channel's region and its first clearing ring on neon_word's strokes (8.5 mm channel,
/// 1/8" tool, tolerance 0.05 mm as `build` uses them): the spine's cubic spans fitted by
/// arcs and bounded by exact offsets (`toolpath::swept`, what `build` does up to degree 3)
/// against geo's buffer of the spine flattened within the tolerance (the peer, and the
/// route `build` falls back to). Vertex counts and the areas' difference are printed once.
fn bench_channel_region(c: &mut Criterion) {
    use cavalier_contours::polyline::PlineSource;
    use skinpath::dbsc::flatten_spine;
    use skinpath::dbsc::spine_cubics;
    use skinpath::internals::{pline_from_path, swept_arc_region, swept_region};
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/neon_word.toml");
    let text = std::fs::read_to_string(file).expect("neon_word.toml");
    let design = skinpath::design::load(&text, file).expect("loads");
    let strokes = design.strokes().expect("builds");
    let (tol, half_width, tool_r) = (0.05, 4.25, 1.5875);
    let eps = tol * 0.1;
    let arcs = |c: &skinpath::DiskBSpline| {
        let pline = pline_from_path(&spine_cubics(c).expect("cubic spine"), tol);
        swept_arc_region(&pline, half_width, eps).expect("sound region")
    };
    let polygon = |c: &skinpath::DiskBSpline| {
        swept_region(&flatten_spine(c, tol), c.is_closed(), half_width, tol)
    };
    let count = |r: &Region| r.contours.iter().map(|c| c.vertex_count()).sum::<usize>();
    let (a, p): (Vec<Region>, Vec<Region>) = strokes.iter().map(|c| (arcs(c), polygon(c))).unzip();
    let worst = a
        .iter()
        .zip(&p)
        .map(|(x, y)| (x.area() - y.area()).abs() / x.perimeter())
        .fold(0.0, f64::max);
    println!(
        "neon_word channels: {} vertices with arcs, {} as polygons; areas differ by at most \
         {worst:.1e} x perimeter (the flattening within {tol})",
        a.iter().map(count).sum::<usize>(),
        p.iter().map(count).sum::<usize>(),
    );
    let mut g = c.benchmark_group("channel_region_neon_word");
    g.bench_function("arcs_exact_offsets", |b| {
        b.iter(|| black_box(strokes.iter().map(arcs).collect::<Vec<_>>()))
    });
    g.bench_function("geo_buffer_of_flattened_spine", |b| {
        b.iter(|| black_box(strokes.iter().map(polygon).collect::<Vec<_>>()))
    });
    g.bench_function("first_ring_arcs", |b| {
        b.iter(|| black_box(a.iter().map(|r| r.offset(-tool_r, eps)).collect::<Vec<_>>()))
    });
    g.bench_function("first_ring_geo_polygon", |b| {
        b.iter(|| black_box(p.iter().map(|r| r.offset(-tool_r, eps)).collect::<Vec<_>>()))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench_offsets, bench_hatch_and_order, bench_example_offsets, bench_winding,
        bench_channel_region
}
criterion_main!(benches);
