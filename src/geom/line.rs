//! Straight line segments.

use super::DVec2;
use super::predicates::segments_intersect;

/// The segment from `p0` to `p1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// Start point.
    pub p0: DVec2,
    /// End point.
    pub p1: DVec2,
}

impl Line {
    /// The segment from `p0` to `p1`.
    pub const fn new(p0: DVec2, p1: DVec2) -> Self {
        Line { p0, p1 }
    }

    /// The point (1 − t)·p0 + t·p1 at parameter `t`.
    pub fn eval(&self, t: f64) -> DVec2 {
        self.p0.lerp(self.p1, t)
    }

    /// Length ‖p1 − p0‖.
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

    /// The same segment traversed from `p1` to `p0`.
    pub fn reversed(&self) -> Self {
        Line::new(self.p1, self.p0)
    }

    /// Euclidean distance between this segment and `other`: 0 when the closed segments
    /// share a point (decided exactly by [`segments_intersect`]), otherwise the least of
    /// the four end-point-to-segment distances (the nearest pair of points of two disjoint
    /// segments always includes an end point).
    pub fn distance_to_line(&self, other: &Line) -> f64 {
        if segments_intersect(self.p0, self.p1, other.p0, other.p1) {
            return 0.0;
        }
        self.distance(other.p0)
            .min(self.distance(other.p1))
            .min(other.distance(self.p0))
            .min(other.distance(self.p1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_to_segment_distance() {
        // Parallel segments 0.5 apart; crossing segments; an end point nearest an interior.
        let a = Line::new(DVec2::new(0.0, 0.5), DVec2::new(1.0, 0.5));
        let b = Line::new(DVec2::ZERO, DVec2::new(1.0, 0.0));
        assert!((a.distance_to_line(&b) - 0.5).abs() < 1e-15);
        let x = Line::new(DVec2::ZERO, DVec2::ONE);
        let y = Line::new(DVec2::Y, DVec2::X);
        assert_eq!(x.distance_to_line(&y), 0.0);
        let t = Line::new(DVec2::new(0.5, 2.0), DVec2::new(0.5, 3.0));
        assert_eq!(t.distance_to_line(&a), 1.5);
        assert_eq!(a.distance_to_line(&t), 1.5);
    }
}
