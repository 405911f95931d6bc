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

/// The contribution of the directed edge a → b to the winding number of `p`: +1 when the
/// edge crosses the horizontal ray from `p` towards +x upwards, −1 downwards, 0 otherwise.
/// Half-open in y (an edge covers a.y ≤ y < b.y or b.y ≤ y < a.y), so a vertex on the ray
/// counts once; the side of `p` is decided exactly by [`orient2d`] (Sunday's crossing rule
/// with Shewchuk's predicate). A point on the edge itself contributes 0.
pub fn edge_winding(a: DVec2, b: DVec2, p: DVec2) -> i32 {
    if (a.y > p.y) == (b.y > p.y) {
        return 0;
    }
    let o = orient2d(a, b, p);
    if b.y > a.y && o > 0.0 {
        1
    } else if b.y < a.y && o < 0.0 {
        -1
    } else {
        0
    }
}

/// Winding number of `p` with respect to the closed polygon `poly` (last vertex joined to
/// the first): the sum of `edge_winding` over its edges, exact for all finite inputs.
/// Its parity is the even-odd (crossing number) inside test.
pub fn winding_number(poly: &[DVec2], p: DVec2) -> i32 {
    let n = poly.len();
    (0..n)
        .map(|i| edge_winding(poly[i], poly[(i + 1) % n], p))
        .sum()
}

/// Even-odd inside test of `p` against the closed polygon `poly`: an odd
/// [`winding_number`].
pub fn inside_even_odd(poly: &[DVec2], p: DVec2) -> bool {
    winding_number(poly, p) % 2 != 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn winding_of_square_and_doubly_wound_loop() {
        let sq = [
            DVec2::ZERO,
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        assert_eq!(winding_number(&sq, DVec2::ONE), 1);
        let cw: Vec<DVec2> = sq.iter().rev().copied().collect();
        assert_eq!(winding_number(&cw, DVec2::ONE), -1);
        assert_eq!(winding_number(&sq, DVec2::new(3.0, 1.0)), 0);
        // A ray through a vertex (y = 0 and y = 2 at the corners) counts once.
        assert_eq!(winding_number(&sq, DVec2::new(-1.0, 0.0)), 0);
        assert!(inside_even_odd(&sq, DVec2::new(1.0, 0.0)));
        // The square traversed twice winds twice and is outside by even-odd.
        let twice: Vec<DVec2> = sq.iter().chain(sq.iter()).copied().collect();
        assert_eq!(winding_number(&twice, DVec2::ONE), 2);
        assert!(!inside_even_odd(&twice, DVec2::ONE));
    }

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
