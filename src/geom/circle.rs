//! Circles (and the closed disks they bound).

use super::DVec2;

/// A circle with centre `c` and radius `r` (r > 0 for user data; validation is the caller's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    /// Centre.
    pub c: DVec2,
    /// Radius.
    pub r: f64,
}

impl Circle {
    /// The circle with centre `c` and radius `r`.
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

    /// The radical centre of `self`, `b` and `c`: the point of equal power with respect to
    /// the three circles, from the two linear equations pow_a(x) = pow_b(x) and
    /// pow_a(x) = pow_c(x), i.e. 2 (c_k − c_a)·x = ‖c_k‖² − r_k² − ‖c_a‖² + r_a² (k = b, c),
    /// by Cramer's rule. `None` when the centres are collinear within `rel_tol`: the
    /// determinant is at most `rel_tol` times the product of the two rows' lengths.
    pub fn radical_centre(&self, b: &Circle, c: &Circle, rel_tol: f64) -> Option<DVec2> {
        let row = |p: &Circle, q: &Circle| {
            (
                2.0 * (q.c - p.c),
                q.c.length_squared() - q.r * q.r - p.c.length_squared() + p.r * p.r,
            )
        };
        let (n1, d1) = row(self, b);
        let (n2, d2) = row(self, c);
        let det = super::cross(n1, n2);
        if det.abs() <= rel_tol * n1.length() * n2.length() {
            return None;
        }
        Some(DVec2::new(d1 * n2.y - d2 * n1.y, n1.x * d2 - n2.x * d1) / det)
    }

    /// True when the closed disk contains `p` within `tol`.
    pub fn contains(&self, p: DVec2, tol: f64) -> bool {
        self.signed_distance(p) <= tol
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radical_centre_has_equal_powers() {
        let a = Circle::new(DVec2::ZERO, 1.0);
        let b = Circle::new(DVec2::new(4.0, 0.0), 2.0);
        let c = Circle::new(DVec2::new(1.0, 3.0), 0.5);
        let s = a.radical_centre(&b, &c, 1e-14).unwrap();
        assert!((a.power(s) - b.power(s)).abs() < 1e-12);
        assert!((a.power(s) - c.power(s)).abs() < 1e-12);
        // Collinear centres: the radical axes are parallel.
        let d = Circle::new(DVec2::new(8.0, 0.0), 1.0);
        assert_eq!(a.radical_centre(&b, &d, 1e-14), None);
    }
}
