//! Tests of the toolpath operations on the shipped examples and on built regions: cuts as
//! configured ([`cuts`]), geometric properties against independent computations
//! ([`props`]), backboard bridges ([`board`]) and clearing rings of dense channels
//! ([`channels`]). The helpers here are what they share:
//! example loading, region transforms, exact point-to-polyline distances, and cut tracing.

mod board;
mod channels;
mod cuts;
mod props;

use crate::design::Design;
use crate::geom::interop::flatten_pline;
use crate::geom::{Arc, Line, Path};
use crate::job::{ItemOutline, OutlineOptions, design_outlines};
use crate::toolpath::region::Region;
use crate::toolpath::{Cut, MoveKind};
use cavalier_contours::polyline::{PlineCreation, PlineSource, PlineSourceMut, Polyline};
use glam::{DVec2, DVec3};

/// The examples every property is rerun on.
pub const EXAMPLES: [&str; 5] = ["brush", "ring_o", "neon_word", "calligraphy", "circles"];

/// The axis-aligned square of half-side `s` about `c`, counter-clockwise from its lower-left
/// corner.
pub fn square(c: DVec2, s: f64) -> Path {
    let corner = |x: f64, y: f64| c + DVec2::new(x * s, y * s);
    Path::polyline(
        &[
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ],
        true,
    )
}

/// The shipped example examples/`name`.toml, loaded.
pub fn example(name: &str) -> Design {
    let path = format!("{}/examples/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    crate::design::load(&text, &path).unwrap()
}

/// Outlines of an example at the default build tolerances.
pub fn outlines(name: &str) -> Vec<ItemOutline> {
    design_outlines(&example(name), &OutlineOptions::default()).unwrap()
}

/// Regions of every item of an example, biarc-fitted within `tol`.
pub fn regions(name: &str, tol: f64) -> Vec<(String, Region)> {
    outlines(name)
        .into_iter()
        .map(|o| (o.name.clone(), Region::from_paths(&o.contours, tol)))
        .collect()
}

/// The region rotated by `angle` about the origin and scaled by `s > 0` (bulges are
/// invariant under similarities that keep orientation).
pub fn similar(r: &Region, angle: f64, s: f64) -> Region {
    let (sn, cs) = angle.sin_cos();
    Region {
        contours: r
            .contours
            .iter()
            .map(|c| {
                let mut out = Polyline::with_capacity(c.vertex_count(), c.is_closed());
                for v in c.iter_vertexes() {
                    out.add(
                        s * (cs * v.x - sn * v.y),
                        s * (sn * v.x + cs * v.y),
                        v.bulge,
                    );
                }
                out
            })
            .collect(),
    }
}

/// Exact distance from `p` to a set of closed polylines.
pub fn rings_distance(rings: &[Vec<DVec2>], p: DVec2) -> f64 {
    rings
        .iter()
        .flat_map(|r| {
            let n = r.len();
            (0..n).map(move |i| Line::new(r[i], r[(i + 1) % n]).distance(p))
        })
        .fold(f64::INFINITY, f64::min)
}

/// Region contours flattened within `tol`.
pub fn flat_rings(r: &Region, tol: f64) -> Vec<Vec<DVec2>> {
    r.contours.iter().map(|c| flatten_pline(c, tol)).collect()
}

/// Even–odd point in polygon.
pub fn in_polygon(poly: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            inside = !inside;
        }
    }
    inside
}

/// The xy trace of a cut's moves from its start, arcs flattened within `tol`.
pub fn trace_xy(c: &Cut, tol: f64) -> Vec<DVec2> {
    let mut out = vec![c.start.truncate()];
    let mut prev = c.start.truncate();
    for m in &c.moves {
        let to = m.to.truncate();
        match m.kind {
            MoveKind::Arc { center, ccw } if to != prev => {
                let a = Arc::from_center_points(center, prev, to, ccw);
                out.extend(a.flatten(tol).into_iter().skip(1));
            }
            _ => {
                if to != prev {
                    out.push(to);
                }
            }
        }
        prev = to;
    }
    out
}

/// Planar length of one move from `prev`.
pub fn move_len(prev: DVec3, kind: MoveKind, to: DVec3) -> f64 {
    match kind {
        MoveKind::Arc { center, ccw } => {
            Arc::from_center_points(center, prev.truncate(), to.truncate(), ccw).length()
        }
        _ => prev.truncate().distance(to.truncate()),
    }
}
