//! Exact orientation predicates (Shewchuk's adaptive arithmetic via the `robust` crate) and
//! the segment tests built on them.

use super::DVec2;

fn coord(p: DVec2) -> robust::Coord<f64> {
    robust::Coord { x: p.x, y: p.y }
}

/// Sign of the orientation of (a, b, c): > 0 counter-clockwise, < 0 clockwise, 0 collinear.
/// Exact for all finite inputs.
pub fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    robust::orient2d(coord(a), coord(b), coord(c))
}

/// True when `p`, known collinear with segment ab, lies within its bounding box.
fn on_segment(a: DVec2, b: DVec2, p: DVec2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// Exact test whether the closed segments ab and cd share a point.
pub fn segments_intersect(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let o1 = orient2d(a, b, c);
    let o2 = orient2d(a, b, d);
    let o3 = orient2d(c, d, a);
    let o4 = orient2d(c, d, b);
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return true;
    }
    (o1 == 0.0 && on_segment(a, b, c))
        || (o2 == 0.0 && on_segment(a, b, d))
        || (o3 == 0.0 && on_segment(c, d, a))
        || (o4 == 0.0 && on_segment(c, d, b))
}

/// The point where the lines through ab and cd cross, or `None` when they are parallel.
pub fn line_intersection(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Option<DVec2> {
    let r = b - a;
    let s = d - c;
    let den = super::cross(r, s);
    if den == 0.0 {
        return None;
    }
    let t = super::cross(c - a, s) / den;
    Some(a + t * r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_touching_and_disjoint() {
        let o = DVec2::ZERO;
        let x = DVec2::new(2.0, 2.0);
        assert!(segments_intersect(
            o,
            x,
            DVec2::new(0.0, 2.0),
            DVec2::new(2.0, 0.0)
        ));
        // Touching at an end point.
        assert!(segments_intersect(o, x, x, DVec2::new(3.0, 0.0)));
        // Collinear, disjoint.
        assert!(!segments_intersect(
            o,
            DVec2::new(1.0, 1.0),
            x,
            DVec2::new(3.0, 3.0)
        ));
        // Near-degenerate: exactness matters.
        let a = DVec2::new(0.1, 0.1);
        let b = DVec2::new(0.3, 0.3);
        assert_eq!(orient2d(a, b, DVec2::new(0.2, 0.2)), 0.0);
    }
}
