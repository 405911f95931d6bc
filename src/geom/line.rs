//! Straight line segments.

use super::DVec2;

/// The segment from `p0` to `p1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub p0: DVec2,
    pub p1: DVec2,
}

impl Line {
    pub const fn new(p0: DVec2, p1: DVec2) -> Self {
        Line { p0, p1 }
    }

    pub fn eval(&self, t: f64) -> DVec2 {
        self.p0.lerp(self.p1, t)
    }

    pub fn length(&self) -> f64 {
        self.p0.distance(self.p1)
    }

    /// Parameter in [0, 1] of the point of the segment nearest to `p`.
    pub fn nearest_t(&self, p: DVec2) -> f64 {
        let d = self.p1 - self.p0;
        let l2 = d.length_squared();
        if l2 == 0.0 {
            0.0
        } else {
            ((p - self.p0).dot(d) / l2).clamp(0.0, 1.0)
        }
    }

    /// Euclidean distance from `p` to the segment.
    pub fn distance(&self, p: DVec2) -> f64 {
        self.eval(self.nearest_t(p)).distance(p)
    }

    pub fn reversed(&self) -> Self {
        Line::new(self.p1, self.p0)
    }
}
