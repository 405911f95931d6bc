//! MAT offset + trim of an RE skin (re-skinning-cnc eq. 13) against the general route on
//! the same outline: arc approximation of the outline within TOL (caps as true arcs) and
//! cavalier_contours `parallel_offset` with self-intersection handling, at equal tolerance.
//! Prints the time ratio and each route's Hausdorff distance to the exact offset.

use cavalier_contours::polyline::{PlineOffsetOptions, PlineSource, PlineSourceMut, Polyline};
use criterion::Criterion;
use skinpath::geom::Circle;
use skinpath::geom::path::polygon_area;
use skinpath::geom::{DVec2, Path, PathSeg};
use skinpath::skin::mat_offset::{MatOffset, inner_offset, outline};
use skinpath::skin::re::{Interp, ReSkin, Touch};
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

fn mat_route(skin: &ReSkin) -> Vec<Path> {
    inner_offset(skin, DELTA, 1e-12)
        .map(|o| o.to_line_paths(TOL))
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

fn general_route(skin: &ReSkin) -> Vec<Vec<DVec2>> {
    let Ok(out) = outline(skin) else {
        return Vec::new();
    };
    let path = &out.to_arc_paths(TOL)[0];
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
            Path::new(segs, true).flatten(TOL * 0.1)
        })
        .collect()
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

fn main() {
    let cs = circles();
    let skin = match ReSkin::build(&cs, &touches(&cs), false, Interp::Cubic, 1e-9) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("skin: {e}");
            return;
        }
    };
    let Ok(exact) = inner_offset(&skin, DELTA, 1e-12) else {
        eprintln!("exact offset failed");
        return;
    };
    let ex = exact_samples(&exact, 1000);
    let mat: Vec<Vec<DVec2>> = mat_route(&skin)
        .iter()
        .map(|p| p.flatten(TOL * 0.1))
        .collect();
    let gen_ = general_route(&skin);
    let (tm, tg) = (
        time(20, || mat_route(&skin)),
        time(20, || general_route(&skin)),
    );
    println!(
        "mat_offset: {} circles, delta {DELTA}, tol {TOL}: {} trims, {} contours (general: {})",
        cs.len(),
        exact.trims.len(),
        exact.contours.len(),
        gen_.len()
    );
    println!(
        "mat_offset: MAT route {:.3} ms, general route {:.3} ms, ratio general/MAT {:.2}",
        tm * 1e3,
        tg * 1e3,
        tg / tm
    );
    println!(
        "mat_offset: Hausdorff to exact offset: MAT {:.2e}, general {:.2e}",
        hausdorff(&ex, &mat),
        hausdorff(&ex, &gen_)
    );
    let t_trim = time(50, || {
        inner_offset(&skin, DELTA, 1e-12).map(|o| o.trims.len())
    });
    let t_cubic = time(20, || {
        inner_offset(&skin, DELTA, 1e-12).map(|o| o.to_cubic_paths(TOL))
    });
    let cub: Vec<Vec<DVec2>> = exact
        .to_cubic_paths(TOL)
        .iter()
        .map(|p| p.flatten(TOL * 0.1))
        .collect();
    println!(
        "mat_offset: exact offset + trim only {:.3} ms; with cubic output {:.3} ms (Hausdorff {:.2e}, {} cubics vs {} arcs)",
        t_trim * 1e3,
        t_cubic * 1e3,
        hausdorff(&ex, &cub),
        exact
            .to_cubic_paths(TOL)
            .iter()
            .map(|p| p.segs.len())
            .sum::<usize>(),
        mat_route(&skin).iter().map(|p| p.segs.len()).sum::<usize>(),
    );
    // Breakdown of the general route: the arc fit of the outline vs cavalier alone.
    if let Ok(ol) = outline(&skin) {
        let t_fit = time(20, || ol.to_arc_paths(TOL));
        let path = &ol.to_arc_paths(TOL)[0];
        let pl = to_pline(path);
        let off = if polygon_area(&path.flatten(TOL)) > 0.0 {
            DELTA
        } else {
            -DELTA
        };
        let opts = PlineOffsetOptions {
            handle_self_intersects: true,
            ..Default::default()
        };
        let t_cav = time(20, || pl.parallel_offset_opt(off, &opts).len());
        println!(
            "mat_offset: general route = outline arc fit {:.3} ms ({} arcs) + cavalier offset {:.3} ms",
            t_fit * 1e3,
            path.segs.len(),
            t_cav * 1e3
        );
    }
    routes_on_examples();
    let mut c = Criterion::default().configure_from_args();
    c.bench_function("mat_offset/re_mat_trim", |b| {
        b.iter(|| mat_route(black_box(&skin)))
    });
    c.bench_function("mat_offset/cavalier_general", |b| {
        b.iter(|| general_route(black_box(&skin)))
    });
    c.final_summary();
}

/// Whole builds of the examples by each route (`build --method skin|re|mph`): time per
/// build and the arcs and lines of every profile and backboard, with the route taken.
fn routes_on_examples() {
    use skinpath::design::OutlineMethod;
    use skinpath::job::build::{BuildOptions, build_toolpath};
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
        let Some(Ok(profile)) = skinpath::machine::builtin_profile(machine) else {
            continue;
        };
        for method in [OutlineMethod::Skin, OutlineMethod::Re, OutlineMethod::Mph] {
            let opts = BuildOptions {
                method,
                ..BuildOptions::default()
            };
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
