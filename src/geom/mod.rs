//! Shared geometric primitives: circles (disks), line segments, circular arcs, cubic Bézier
//! curves, and paths made of them; tolerance defaults; exact orientation predicates.
//!
//! Everything is `f64` with [`glam::DVec2`] for points and vectors. Every approximate routine
//! takes its tolerance as an argument; the defaults a caller may use live in [`tol`].

pub mod aabb;
pub mod arc;
pub mod bernstein;
pub mod circle;
pub mod cubic;
pub mod hull;
pub mod index;
pub mod interop;
pub mod line;
pub mod path;
pub mod predicates;
pub mod quad;
pub mod roots;

pub mod tol;

pub use aabb::Aabb;
pub use arc::Arc;
pub use circle::Circle;
pub use cubic::CubicBez;
pub use glam::DVec2;
pub use line::Line;
pub use path::{Path, PathSeg};

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
