//! Axis-aligned bounding boxes.

use super::DVec2;

/// An axis-aligned box [min.x, max.x] × [min.y, max.y] (closed). The empty box has
/// `min = +∞`, `max = −∞`, so that [`Aabb::union`] and [`Aabb::add_point`] with it are the
/// identity and it contains and intersects nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The lower-left corner (componentwise minimum).
    pub min: DVec2,
    /// The upper-right corner (componentwise maximum).
    pub max: DVec2,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

/// The corners (min, max): the box in the tuple form of code that predates [`Aabb`].
impl From<Aabb> for (DVec2, DVec2) {
    fn from(b: Aabb) -> (DVec2, DVec2) {
        (b.min, b.max)
    }
}

impl Aabb {
    /// The empty box (min = +∞, max = −∞).
    pub const EMPTY: Aabb = Aabb {
        min: DVec2::splat(f64::INFINITY),
        max: DVec2::splat(f64::NEG_INFINITY),
    };

    /// The box with corners `min` and `max` (taken as given: `min ≤ max` componentwise for a
    /// non-empty box).
    #[must_use]
    pub const fn new(min: DVec2, max: DVec2) -> Aabb {
        Aabb { min, max }
    }

    /// The smallest box holding two points, in either order.
    #[must_use]
    pub fn from_corners(a: DVec2, b: DVec2) -> Aabb {
        Aabb::new(a.min(b), a.max(b))
    }

    /// The smallest box holding the points (empty for none).
    #[must_use]
    pub fn from_points<'a>(pts: impl IntoIterator<Item = &'a DVec2>) -> Aabb {
        pts.into_iter().fold(Aabb::EMPTY, |b, &p| b.add_point(p))
    }

    /// Whether the box holds no point (min > max in some coordinate, or NaN).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y)
    }

    /// The box, or `None` when it is empty.
    #[must_use]
    pub fn non_empty(self) -> Option<Aabb> {
        (!self.is_empty()).then_some(self)
    }

    /// The box grown to hold `p`.
    #[must_use]
    pub fn add_point(self, p: DVec2) -> Aabb {
        Aabb::new(self.min.min(p), self.max.max(p))
    }

    /// The smallest box holding both boxes.
    #[must_use]
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// The box grown by `d` on every side (shrunk for negative `d`).
    #[must_use]
    pub fn grow(self, d: f64) -> Aabb {
        Aabb::new(self.min - DVec2::splat(d), self.max + DVec2::splat(d))
    }

    /// Width and height (negative for the empty box).
    #[must_use]
    pub fn size(&self) -> DVec2 {
        self.max - self.min
    }

    /// The centre of the box.
    #[must_use]
    pub fn center(&self) -> DVec2 {
        0.5 * (self.min + self.max)
    }

    /// Whether `p` lies in the closed box.
    #[must_use]
    pub fn contains(&self, p: DVec2) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// Whether the closed boxes share a point.
    #[must_use]
    pub fn intersects(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// Euclidean distance from `p` to the box (0 inside): ‖max(min − p, p − max, 0)‖.
    #[must_use]
    pub fn distance(&self, p: DVec2) -> f64 {
        self.gap(p).length()
    }

    /// Squared distance from `p` to the box (0 inside), without the square root.
    #[must_use]
    pub fn distance_squared(&self, p: DVec2) -> f64 {
        self.gap(p).length_squared()
    }

    /// The componentwise gap max(min − p, p − max, 0) from `p` to the box.
    fn gap(&self, p: DVec2) -> DVec2 {
        (self.min - p).max(p - self.max).max(DVec2::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn empty_box_is_the_identity_of_union() {
        let b = Aabb::from_corners(DVec2::new(3.0, -1.0), DVec2::new(1.0, 2.0));
        assert_eq!(b.min, DVec2::new(1.0, -1.0));
        assert_eq!(b.max, DVec2::new(3.0, 2.0));
        assert_eq!(Aabb::EMPTY.union(b), b);
        assert!(Aabb::EMPTY.is_empty() && Aabb::EMPTY.non_empty().is_none());
        assert!(!Aabb::EMPTY.contains(DVec2::ZERO));
        assert!(!Aabb::EMPTY.intersects(&b));
        assert_eq!(Aabb::from_points(&[]), Aabb::EMPTY);
    }

    proptest! {
        /// The box of points holds each of them, touches each side at one of them, and its
        /// distance is the distance to the nearest point of the box found by clamping.
        #[test]
        fn box_of_points_is_tight(
            pts in prop::collection::vec((-1e3..1e3f64, -1e3..1e3f64), 1..20),
            q in (-2e3..2e3f64, -2e3..2e3f64),
        ) {
            let pts: Vec<DVec2> = pts.into_iter().map(|(x, y)| DVec2::new(x, y)).collect();
            let b = Aabb::from_points(&pts);
            prop_assert!(pts.iter().all(|&p| b.contains(p)));
            prop_assert!(pts.iter().any(|p| p.x == b.min.x));
            prop_assert!(pts.iter().any(|p| p.y == b.max.y));
            let q = DVec2::new(q.0, q.1);
            let clamped = q.clamp(b.min, b.max);
            prop_assert!((b.distance(q) - clamped.distance(q)).abs() <= 1e-9 * (1.0 + q.length()));
            let g = b.grow(1.0);
            prop_assert!(g.intersects(&b) && g.contains(b.min) && g.contains(b.max));
        }
    }
}
