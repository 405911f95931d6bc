//! Circles (and the closed disks they bound).

use super::DVec2;

/// A circle with centre `c` and radius `r` (r > 0 for user data; validation is the caller's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    pub c: DVec2,
    pub r: f64,
}

impl Circle {
    pub const fn new(c: DVec2, r: f64) -> Self {
        Circle { c, r }
    }

    /// From `[x, y, r]`.
    pub fn from_xyr(v: [f64; 3]) -> Self {
        Circle::new(DVec2::new(v[0], v[1]), v[2])
    }

    /// The point at angle `theta` (radians, counter-clockwise from +x).
    pub fn point_at(&self, theta: f64) -> DVec2 {
        self.c + self.r * DVec2::new(theta.cos(), theta.sin())
    }

    /// Signed distance from `p` to the circle: negative inside the disk.
    pub fn signed_distance(&self, p: DVec2) -> f64 {
        (p - self.c).length() - self.r
    }

    /// Power of the point `p` with respect to the circle: ‖p − c‖² − r².
    pub fn power(&self, p: DVec2) -> f64 {
        (p - self.c).length_squared() - self.r * self.r
    }

    /// True when the closed disk contains `p` within `tol`.
    pub fn contains(&self, p: DVec2, tol: f64) -> bool {
        self.signed_distance(p) <= tol
    }
}
