//! Shared geometric primitives: circles (disks), line segments, circular arcs, cubic Bézier
//! curves, and paths made of them; tolerance defaults; exact orientation predicates.
//!
//! Everything is `f64` with [`glam::DVec2`] for points and vectors. Every approximate routine
//! takes its tolerance as an argument; the defaults a caller may use live in `tol`.

pub(crate) mod aabb;
pub(crate) mod arc;
pub(crate) mod bernstein;
pub(crate) mod circle;
pub(crate) mod cubic;
pub(crate) mod hull;
pub(crate) mod index;
pub(crate) mod interop;
pub(crate) mod intersect;
pub(crate) mod interval;
pub(crate) mod line;
pub(crate) mod path;
pub(crate) mod predicates;
pub(crate) mod quad;
pub(crate) mod roots;
pub(crate) mod tol;
pub use aabb::Aabb;
pub use arc::Arc;
pub use circle::Circle;
pub use cubic::CubicBez;
pub use glam::DVec2;
pub use index::WindingIndex;
pub use intersect::{
    Hit, PathHit, cubic_intersections, cubic_self_intersections, path_self_intersections,
    paths_intersections,
};
pub use line::Line;
pub use path::{Path, PathSeg, polygon_area};
pub use predicates::{
    inside_even_odd, line_intersection, orient2d, segments_intersect, winding_number,
};
pub use tol::{FLATTEN, SKIN_EPSILON};

/// `v` rotated a quarter turn counter-clockwise: (x, y) ↦ (−y, x).
#[inline]
pub fn perp(v: DVec2) -> DVec2 {
    DVec2::new(-v.y, v.x)
}

/// The z component of the cross product of two plane vectors, `a.x·b.y − a.y·b.x`.
#[inline]
pub fn cross(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}
