//! MAT offset + trim of an RE skin (re-skinning-cnc eq. 13) emitted as merged G1 arcs
//! (issue #16 item 5) against the general routes on the same outline, all at TOL: the
//! outline fitted with arcs and offset by cavalier_contours `parallel_offset` with
//! self-intersection handling, and the outline flattened and shrunk by geo's buffer.
//! Prints times, ratios, arc and line counts and each route's Hausdorff distance to the
//! exact offset.

use cavalier_contours::polyline::{PlineOffsetOptions, PlineSource, PlineSourceMut, Polyline};
use criterion::Criterion;
use skinpath::geom::polygon_area;
use skinpath::geom::{Circle, DVec2, Path, PathSeg};
use skinpath::internals::{MatOffset, biarc_paths, inner_offset, outline};
use skinpath::skin::{Interp, ReSkin, Touch};
use std::hint::black_box;
use std::time::Instant;

/// Output / approximation tolerance of both routes (mm).
const TOL: f64 = 1e-3;
/// Inner offset distance (tool radius, mm): larger than the thinnest circles, so it trims.
const DELTA: f64 = 0.55;

fn circles() -> Vec<Circle> {
    (0..14)
        .map(|i| {
            let x = i as f64 * 2.6;
            let y = 2.0 * (i as f64 * 0.45).sin();
            let r = 0.95 + 0.5 * (i as f64 * 0.9).cos();
            Circle::new(DVec2::new(x, y), r)
        })
        .collect()
}

/// Touching points of the smooth tangent family (Catmull–Rom direction, radius slope).
fn touches(cs: &[Circle]) -> Vec<Touch> {
    let n = cs.len();
    (0..n)
        .map(|i| {
            let a = cs[i.saturating_sub(1)];
            let b = cs[(i + 1).min(n - 1)];
            let d = b.c - a.c;
            let rho = ((b.r - a.r) / d.length()).clamp(-0.9, 0.9);
            let u = d.normalize();
            let left = DVec2::new(-u.y, u.x);
            let q = (1.0 - rho * rho).sqrt();
            Touch::Fixed {
                plus: cs[i].c + cs[i].r * (-rho * u + q * left),
                minus: cs[i].c + cs[i].r * (-rho * u - q * left),
            }
        })
        .collect()
}

/// The exact inner offset and its trim, emitted as merged G1 arcs within TOL.
fn mat_route(skin: &ReSkin) -> Vec<Path> {
    inner_offset(skin, DELTA, 1e-12)
        .and_then(|o| o.to_merged_arc_paths(TOL))
        .map(|m| m.paths)
        .unwrap_or_default()
}

fn to_pline(path: &Path) -> Polyline<f64> {
    let mut pl = Polyline::new_closed();
    for s in &path.segs {
        let p = s.start();
        let bulge = match s {
            PathSeg::Arc(a) => a.bulge(),
            _ => 0.0,
        };
        pl.add(p.x, p.y, bulge);
    }
    pl
}

/// The general route: the outline fitted with 3-point arcs within TOL (cavalier_contours
/// takes arcs and lines), offset by cavalier_contours with self-intersection handling.
fn general_route(skin: &ReSkin) -> Vec<Path> {
    let Ok(out) = outline(skin) else {
        return Vec::new();
    };
    let Some(path) = out.to_arc_paths(TOL).unwrap().into_iter().next() else {
        return Vec::new();
    };
    cavalier_offset(&path)
}

fn cavalier_offset(path: &Path) -> Vec<Path> {
    let pl = to_pline(path);
    let area = polygon_area(&path.flatten(TOL));
    let off = if area > 0.0 { DELTA } else { -DELTA };
    let opts = PlineOffsetOptions {
        handle_self_intersects: true,
        ..Default::default()
    };
    pl.parallel_offset_opt(off, &opts)
        .iter()
        .map(|p| {
            let segs: Vec<PathSeg> = (0..p.vertex_count())
                .map(|i| {
                    let v = p.at(i);
                    let w = p.at((i + 1) % p.vertex_count());
                    let (a, b) = (DVec2::new(v.x, v.y), DVec2::new(w.x, w.y));
                    if v.bulge == 0.0 {
                        PathSeg::Line(skinpath::geom::Line::new(a, b))
                    } else {
                        PathSeg::Arc(skinpath::geom::Arc::from_bulge(a, b, v.bulge))
                    }
                })
                .collect();
            Path::new(segs, true)
        })
        .collect()
}

/// geo's buffer (i_overlay) of the outline flattened within TOL (geo has no arcs), shrunk
/// by DELTA with round joins of the angle step `Region::buffered` uses for TOL.
fn geo_route(skin: &ReSkin) -> Vec<Vec<DVec2>> {
    let Ok(out) = outline(skin) else {
        return Vec::new();
    };
    geo_buffer(&out.flatten(TOL))
}

fn geo_buffer(rings: &[Vec<DVec2>]) -> Vec<Vec<DVec2>> {
    use geo::Buffer;
    use geo::algorithm::buffer::{BufferStyle, LineJoin};
    let polys: Vec<geo::Polygon<f64>> = rings
        .iter()
        .map(|r| {
            let mut pts: Vec<geo::Coord<f64>> =
                r.iter().map(|p| geo::Coord { x: p.x, y: p.y }).collect();
            if let Some(&f) = pts.first() {
                pts.push(f);
            }
            geo::Polygon::new(geo::LineString::new(pts), vec![])
        })
        .collect();
    let phi = (8.0 * TOL / DELTA).sqrt().min(1.0);
    let style = BufferStyle::new(-DELTA).line_join(LineJoin::Round(phi));
    let shrunk = geo::MultiPolygon::new(polys).buffer_with_style(style);
    let ring = |l: &geo::LineString<f64>| -> Vec<DVec2> {
        let mut v: Vec<DVec2> = l.0.iter().map(|c| DVec2::new(c.x, c.y)).collect();
        v.pop();
        v
    };
    let mut out = Vec::new();
    for p in &shrunk.0 {
        out.push(ring(p.exterior()));
        out.extend(p.interiors().iter().map(ring));
    }
    out
}

/// Dense samples of each exact contour (closed polylines).
fn exact_samples(off: &MatOffset, per_piece: usize) -> Vec<Vec<DVec2>> {
    off.contours
        .iter()
        .map(|c| {
            let mut v = Vec::new();
            for p in &c.pieces {
                for k in 0..per_piece {
                    if let Some(q) = off.piece_point(p, k as f64 / per_piece as f64) {
                        v.push(q);
                    }
                }
            }
            v
        })
        .collect()
}

fn seg_dist(poly: &[DVec2], q: DVec2) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| skinpath::geom::Line::new(poly[i], poly[(i + 1) % n]).distance(q))
        .fold(f64::INFINITY, f64::min)
}

/// One-sided distance: the farthest vertex of `a` from the closed polylines `b`.
fn directed(a: &[Vec<DVec2>], b: &[Vec<DVec2>]) -> f64 {
    a.iter()
        .flatten()
        .map(|q| {
            b.iter()
                .map(|p| seg_dist(p, *q))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// Symmetric Hausdorff distance between closed polylines (vertex-to-segment both ways).
fn hausdorff(exact: &[Vec<DVec2>], polys: &[Vec<DVec2>]) -> f64 {
    directed(exact, polys).max(directed(polys, exact))
}

fn time<F: FnMut() -> R, R>(n: usize, mut f: F) -> f64 {
    let t = Instant::now();
    for _ in 0..n {
        black_box(f());
    }
    t.elapsed().as_secs_f64() / n as f64
}

/// Median of `rounds` timings of `n` calls each (seconds per call).
fn median_time<F: FnMut() -> R, R>(rounds: usize, n: usize, mut f: F) -> f64 {
    let mut v: Vec<f64> = (0..rounds).map(|_| time(n, &mut f)).collect();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn counts(paths: &[Path]) -> (usize, usize) {
    let arcs = paths
        .iter()
        .flat_map(|p| &p.segs)
        .filter(|s| matches!(s, PathSeg::Arc(_)))
        .count();
    let all: usize = paths.iter().map(|p| p.segs.len()).sum();
    (arcs, all - arcs)
}

fn flat(paths: &[Path]) -> Vec<Vec<DVec2>> {
    paths.iter().map(|p| p.flatten(TOL * 0.01)).collect()
}

fn main() {
    let cs = circles();
    let skin = match ReSkin::build(&cs, &touches(&cs), false, Interp::Cubic, 1e-9) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("skin: {e}");
            return;
        }
    };
    let (Ok(exact), Ok(ol)) = (inner_offset(&skin, DELTA, 1e-12), outline(&skin)) else {
        eprintln!("exact offset failed");
        return;
    };
    let ex = exact_samples(&exact, 1000);
    let merged = exact.to_merged_arc_paths(TOL).unwrap_or_default();
    let biarcs = biarc_paths(&exact, TOL).unwrap();
    let arcs3 = exact.to_arc_paths(TOL).unwrap();
    let lines = exact.to_line_paths(TOL).unwrap();
    let cav = general_route(&skin);
    let geo_ = geo_route(&skin);
    println!(
        "mat_offset: {} circles, delta {DELTA}, tol {TOL}: {} trims, {} contours (cavalier: {}, geo: {})",
        cs.len(),
        exact.trims.len(),
        exact.contours.len(),
        cav.len(),
        geo_.len()
    );
    println!(
        "mat_offset: merged arcs: {} samples of the exact curve, hull bound {:.3e}, {} unproved chords",
        merged.samples, merged.bound, merged.unproved
    );
    for (name, paths) in [
        ("MAT merged G1 arcs", &merged.paths),
        ("MAT biarcs (G-code route before)", &biarcs),
        ("MAT 3-point arcs (cavalier input before)", &arcs3),
        ("MAT lines", &lines),
        ("cavalier offset of the arc-fitted outline", &cav),
    ] {
        let (a, l) = counts(paths);
        println!(
            "mat_offset: {name}: {a} arcs + {l} lines, Hausdorff to exact offset {:.3e}",
            hausdorff(&ex, &flat(paths))
        );
    }
    println!(
        "mat_offset: geo buffer of the outline flattened within tol: {} segments, Hausdorff to exact offset {:.3e}",
        geo_.iter().map(|r| r.len()).sum::<usize>(),
        hausdorff(&ex, &geo_)
    );
    // Times: each route from the skin to its output at TOL, and the stages.
    let t_mat = median_time(7, 40, || mat_route(&skin));
    let t_trim = median_time(7, 40, || {
        inner_offset(&skin, DELTA, 1e-12).map(|o| o.contours.len())
    });
    let t_merge = median_time(7, 40, || {
        exact.to_merged_arc_paths(TOL).map(|m| m.paths.len())
    });
    let t_biarc = median_time(7, 40, || biarc_paths(&exact, TOL).unwrap().len());
    let t_cav = median_time(7, 40, || general_route(&skin));
    let ol_arcs = ol.to_arc_paths(TOL).unwrap();
    let t_cav_only = match ol_arcs.first() {
        Some(p) => median_time(7, 40, || cavalier_offset(p)),
        None => f64::NAN,
    };
    let t_geo = median_time(7, 40, || geo_route(&skin));
    let ol_flat = ol.flatten(TOL);
    let t_geo_only = median_time(7, 40, || geo_buffer(&ol_flat));
    println!(
        "mat_offset: MAT offset + trim + merged arcs {:.4} ms (offset + trim {:.4} ms, merging {:.4} ms; biarcs instead {:.4} ms)",
        t_mat * 1e3,
        t_trim * 1e3,
        t_merge * 1e3,
        t_biarc * 1e3
    );
    println!(
        "mat_offset: cavalier route (outline arc fit + offset) {:.4} ms (offset alone {:.4} ms); geo route (outline flattening + buffer) {:.4} ms (buffer alone {:.4} ms)",
        t_cav * 1e3,
        t_cav_only * 1e3,
        t_geo * 1e3,
        t_geo_only * 1e3
    );
    println!(
        "mat_offset: ratios: cavalier route / MAT route {:.2}, geo route / MAT route {:.2}; offsets alone: cavalier / MAT offset+trim {:.2}, geo buffer / MAT offset+trim {:.2}",
        t_cav / t_mat,
        t_geo / t_mat,
        t_cav_only / t_trim,
        t_geo_only / t_trim
    );
    routes_on_examples();
    let mut c = Criterion::default().configure_from_args();
    c.bench_function("mat_offset/re_mat_trim_merged_arcs", |b| {
        b.iter(|| mat_route(black_box(&skin)))
    });
    c.bench_function("mat_offset/cavalier_general", |b| {
        b.iter(|| general_route(black_box(&skin)))
    });
    c.bench_function("mat_offset/geo_buffer", |b| {
        b.iter(|| geo_route(black_box(&skin)))
    });
    c.final_summary();
}

/// Whole builds of the examples by each route (`build --method skin|re|mph`): time per
/// build and the arcs and lines of every profile and backboard, with the route taken.
fn routes_on_examples() {
    use skinpath::BuildOptions;
    use skinpath::design::OutlineMethod;
    use skinpath::job::build_toolpath;
    let examples = [
        ("ring_o", "grbl-router"),
        ("circles", "grbl-router"),
        ("brush", "grbl-laser"),
        ("loop", "grbl-router"),
        ("snake", "grbl-router"),
        ("neon_word", "grbl-router"),
    ];
    for (name, machine) in examples {
        let path = format!("{}/examples/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue;
        };
        let Ok(design) = skinpath::design::load(&text, &path) else {
            continue;
        };
        let Ok(profile) = skinpath::machine::builtin_profile(machine) else {
            continue;
        };
        for method in [OutlineMethod::Skin, OutlineMethod::Re, OutlineMethod::Mph] {
            let mut opts = BuildOptions::default();
            opts.method = method;
            let Ok(built) = build_toolpath(&design, &profile, &opts) else {
                println!("routes: {name} {method:?}: build failed");
                continue;
            };
            let t = time(2, || build_toolpath(&design, &profile, &opts).is_ok());
            for r in &built.routes {
                println!(
                    "routes: {name} on {machine} --method {method:?}: {} took {} ({} arcs, {} lines); whole build {:.0} ms",
                    r.operation,
                    r.route,
                    r.counts.arcs,
                    r.counts.lines,
                    t * 1e3
                );
            }
        }
    }
}
