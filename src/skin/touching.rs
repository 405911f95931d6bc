//! Touching points of the skins on the circles (Kunkli–Hoffmann 2010, as used in
//! kruppa-2023 Sec. 4.2 and re-skinning-cnc Sec. 2, Fig. 2).
//!
//! An inner circle c_i takes its two touching points from the triplet (c_{i−1}, c_i,
//! c_{i+1}): the two Apollonius cycles touching all three "the same way" (all three outside
//! the one, all three inside the other, or common tangent lines in the limit) touch c_i at
//! the left and right touching points. End circles of open sequences take the touching
//! points of the two outer common tangents with their neighbour.
//!
//! Method. Gergonne's construction (the line through the radical centre and the pole of the
//! external similitude axis cuts c_i in the two points, [`gergonne_points`]) is exact but
//! degenerates when the centres are collinear: the radical centre and the pole then both lie
//! at the same point at infinity, and nearly collinear triplets (the common case along a
//! smooth stroke) lose all digits in the line through them. The production path therefore
//! solves the same Apollonius pair in homogeneous cyclographic form: an oriented cycle
//! (x, ρ) (signed radius ρ) touches ⟨c_j; r_j⟩ the same way as the others when
//! ‖x − c_j‖² = (ρ + r_j)². With c_i at the origin, d_k = c_k − c_i, s_k = r_k − r_i,
//! subtracting gives two linear equations 2 d_k·x + 2 s_k ρ = (‖d_k‖² − r_k² + r_i²) h in
//! homogeneous (x, y, ρ, h); their null space is a projective line, cut by the quadric
//! ‖x‖² − (ρ + r_i h)² = 0 in the two solutions. h = 0 is a common tangent line (equal
//! radii, collinear centres), handled without special cases. The touching point on c_i is
//! c_i + r_i x / (ρ + r_i h). [`gergonne_points`] stays as the independent second method in
//! the tests.

use super::admissible::{SkinError, check_count, validate_circles};
use crate::geom::{Circle, DVec2, cross, perp};

/// Two directions are parallel when the largest 2×2 minor of their pair is at most this
/// fraction of the product of their lengths.
const PARALLEL_REL: f64 = 1e-14;

/// Homogeneous vectors (axes, lines) shorter than this (absolute, or relative to the line's
/// length) are degenerate: the construction has no solution.
#[cfg(test)]
const DEGENERATE: f64 = 1e-12;

/// The left and right touching points on one circle; left is on the left of the direction
/// of travel (increasing index).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct TouchingPoints {
    /// Touching point on the left of the direction of travel (on the left skin).
    pub left: DVec2,
    /// Touching point on the right of the direction of travel (on the right skin).
    pub right: DVec2,
}

/// An Apollonius solution touching three circles the same way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Apollonius {
    /// Centre and signed radius: > 0 when the three circles lie outside it, < 0 when it
    /// encloses them. In both cases ‖center − c_j‖ = |radius + r_j|.
    Circle {
        /// Centre of the Apollonius circle.
        center: DVec2,
        /// Signed radius: > 0 when the three circles lie outside, < 0 when it encloses them.
        radius: f64,
    },
    /// The line n·p = offset (‖n‖ = 1) with the circles on the side n·p < offset, each at
    /// distance r_j: n·c_j + r_j = offset.
    Line {
        /// Unit normal n pointing away from the circles.
        normal: DVec2,
        /// Signed distance of the line from the origin along `normal`.
        offset: f64,
    },
}

impl Apollonius {
    /// Where this cycle touches the circle `c` (assuming it does).
    pub fn touching_point(&self, c: &Circle) -> DVec2 {
        match *self {
            Apollonius::Circle { center, radius } => {
                let v = center - c.c;
                c.c + c.r * v.normalize_or_zero() * (radius + c.r).signum()
            }
            Apollonius::Line { normal, .. } => c.c + c.r * normal,
        }
    }
}

/// Touching data of the middle circle of a triplet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TripletTouching {
    /// The left and right touching points on the middle circle.
    pub points: TouchingPoints,
    /// The Apollonius cycle through the left touching point.
    pub left_cycle: Apollonius,
    /// The Apollonius cycle through the right touching point.
    pub right_cycle: Apollonius,
}

/// A cycle whose homogeneous weight |h| is below this fraction of its other coordinates is
/// reported as its limiting line: its radius would exceed 10¹² times the local scale.
const LINE_WEIGHT: f64 = 1e-12;

type V4 = [f64; 4];

fn dot4(a: &V4, b: &V4) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

fn axpy(a: f64, x: &V4, y: &V4) -> V4 {
    [
        y[0] + a * x[0],
        y[1] + a * x[1],
        y[2] + a * x[2],
        y[3] + a * x[3],
    ]
}

fn scale4(a: f64, x: &V4) -> V4 {
    [a * x[0], a * x[1], a * x[2], a * x[3]]
}

/// A basis of the null space of the 2×4 matrix with rows `m1`, `m2`, in closed form from
/// the Plücker coordinates p_ij = m1_i m2_j − m1_j m2_i of the row space: the Hodge dual of
/// m1 ∧ m2 contracted with e_k gives the null vector v⁽ᵏ⁾_l = Σ_{i<j} ε_{klij} p_ij
/// (v⁽⁰⁾ = (0, p23, −p13, p12), v⁽¹⁾ = (−p23, 0, p03, −p02), v⁽²⁾ = (p13, −p03, 0, p01),
/// v⁽³⁾ = (−p12, p02, −p01, 0)); each is orthogonal to both rows because its dot product with
/// a row is a 3×3 determinant with that row twice. With p_ij the largest coordinate in
/// magnitude and {k, l} the complementary pair, v⁽ᵏ⁾ and v⁽ˡ⁾ hold ±p_ij in components l and
/// k and zeros in k and l, so they are independent and well conditioned. Returned
/// normalized. `None` when the rows are parallel to working precision (every |p_ij| at most
/// 10⁻¹⁴ ‖m1‖‖m2‖).
fn null_space(m1: &V4, m2: &V4) -> Option<[V4; 2]> {
    let p = |i: usize, j: usize| m1[i] * m2[j] - m1[j] * m2[i];
    let (p01, p02, p03, p12, p13, p23) = (p(0, 1), p(0, 2), p(0, 3), p(1, 2), p(1, 3), p(2, 3));
    let v = [
        [0.0, p23, -p13, p12],
        [-p23, 0.0, p03, -p02],
        [p13, -p03, 0.0, p01],
        [-p12, p02, -p01, 0.0],
    ];
    // (|p_ij|, k, l) with {k, l} the complement of {i, j}.
    let (big, k, l) = [
        (p01, 2, 3),
        (p02, 1, 3),
        (p03, 1, 2),
        (p12, 0, 3),
        (p13, 0, 2),
        (p23, 0, 1),
    ]
    .into_iter()
    .map(|(pij, k, l)| (pij.abs(), k, l))
    .fold((0.0, 0, 0), |best, c| if c.0 > best.0 { c } else { best });
    let parallel = PARALLEL_REL * (dot4(m1, m1) * dot4(m2, m2)).sqrt();
    if big.partial_cmp(&parallel) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let unit = |x: &V4| scale4(1.0 / dot4(x, x).sqrt(), x);
    Some([unit(&v[k]), unit(&v[l])])
}

/// The two Apollonius cycles touching `a`, `m`, `b` the same way, in homogeneous
/// cyclographic form (see the module docs), as (unit direction of the touching point on
/// `m`, cycle) pairs. `None` when there is no real pair (the discriminant is negative
/// beyond `rel_tol`) or the input is degenerate (nested or identical circles).
fn apollonius_pair(
    a: &Circle,
    m: &Circle,
    b: &Circle,
    rel_tol: f64,
) -> Option<[(DVec2, Apollonius); 2]> {
    let scale = m.r + a.r + b.r + m.c.distance(a.c) + m.c.distance(b.c);
    let r0 = m.r / scale;
    let row = |k: &Circle| -> V4 {
        let d = (k.c - m.c) / scale;
        let rk = k.r / scale;
        let e = d.length_squared() - rk * rk + r0 * r0;
        [2.0 * d.x, 2.0 * d.y, 2.0 * (rk - r0), -e]
    };
    let [n1, n2] = null_space(&row(a), &row(b))?;
    // Bilinear form of the quadric ‖x‖² − (ρ + r0 h)².
    let bil = |z: &V4, w: &V4| z[0] * w[0] + z[1] * w[1] - (z[2] + r0 * z[3]) * (w[2] + r0 * w[3]);
    let (q11, q12, q22) = (bil(&n1, &n1), bil(&n1, &n2), bil(&n2, &n2));
    let mut disc = q12 * q12 - q11 * q22;
    if disc < 0.0 {
        if disc < -rel_tol * (q12 * q12 + (q11 * q22).abs()) {
            return None;
        }
        disc = 0.0;
    }
    // Roots of q11 a² + 2 q12 ab + q22 b² = 0 without cancellation:
    // (a : b) = (q : q11) and (q22 : q), q = −(q12 + sign(q12)·√disc).
    let q = -(q12 + disc.sqrt().copysign(q12));
    let zs: [V4; 2] = if q == 0.0 {
        let z = if q11.abs() <= q22.abs() { n1 } else { n2 };
        [z, z]
    } else {
        [
            axpy(q11, &n2, &scale4(q, &n1)),
            axpy(q, &n2, &scale4(q22, &n1)),
        ]
    };
    let mut out = [(
        DVec2::ZERO,
        Apollonius::Line {
            normal: DVec2::ZERO,
            offset: 0.0,
        },
    ); 2];
    for (slot, z) in out.iter_mut().zip(zs.iter()) {
        let x = DVec2::new(z[0], z[1]);
        let den = z[2] + r0 * z[3];
        let xn = x.length();
        if xn == 0.0 || den == 0.0 || !xn.is_finite() {
            return None;
        }
        let u = x / xn * den.signum();
        let size = xn.max(z[2].abs());
        let cycle = if z[3].abs() <= LINE_WEIGHT * size {
            let w = m.c + m.r * u;
            Apollonius::Line {
                normal: u,
                offset: u.dot(w),
            }
        } else {
            Apollonius::Circle {
                center: m.c + x * (scale / z[3]),
                radius: z[2] * scale / z[3],
            }
        };
        *slot = (u, cycle);
    }
    Some(out)
}

/// Touching points on the middle circle `m` of the triplet (`a`, `m`, `b`), travelling from
/// `a` to `b`, with the two Apollonius cycles (module docs). The left point is the one on
/// the left of both directions a→m and m→b (largest sum of the two cross products).
/// `None` when the triplet has no real Apollonius pair (inadmissible, kruppa-2023 Def. 4.1
/// cond. 3) or is degenerate. `rel_tol` bounds a negative discriminant treated as zero.
#[must_use]
pub fn triplet_touching(
    a: &Circle,
    m: &Circle,
    b: &Circle,
    rel_tol: f64,
) -> Option<TripletTouching> {
    let [(u1, c1), (u2, c2)] = apollonius_pair(a, m, b, rel_tol)?;
    let t1 = (m.c - a.c).normalize_or_zero();
    let t2 = (b.c - m.c).normalize_or_zero();
    let side = |u: DVec2| cross(t1, u) + cross(t2, u);
    let (pl, cl, pr, cr) = if side(u1) >= side(u2) {
        (u1, c1, u2, c2)
    } else {
        (u2, c2, u1, c1)
    };
    Some(TripletTouching {
        points: TouchingPoints {
            left: m.c + m.r * pl,
            right: m.c + m.r * pr,
        },
        left_cycle: cl,
        right_cycle: cr,
    })
}

/// Touching points on an end circle `end` of an open sequence from the two outer common
/// tangents with its neighbour `nbr`: unit normals n with n·d = −s (d = centre step and
/// s = radius step along travel), n = −(s/‖d‖) û ± √(1 − s²/‖d‖²) û⊥, points end.c + r n.
/// `at_start` tells whether `end` is the first circle (travel from `end` to `nbr`).
/// `None` when one disk contains the other (no outer tangents).
pub fn end_touching(end: &Circle, nbr: &Circle, at_start: bool) -> Option<TouchingPoints> {
    let (d, s) = if at_start {
        (nbr.c - end.c, nbr.r - end.r)
    } else {
        (end.c - nbr.c, end.r - nbr.r)
    };
    let len = d.length();
    if len == 0.0 {
        return None;
    }
    let k = s / len;
    if k.is_nan() || k.abs() >= 1.0 {
        return None;
    }
    let u = d / len;
    let h = (1.0 - k * k).sqrt();
    Some(TouchingPoints {
        left: end.c + end.r * (-k * u + h * perp(u)),
        right: end.c + end.r * (-k * u - h * perp(u)),
    })
}

/// Touching points of every circle of an open or closed (`closed`: cyclic) sequence; see
/// the module docs. `rel_tol` as in [`triplet_touching`]. Admissibility is the caller's
/// ([`super::check_admissible`]); this only fails where the construction has no solution.
pub fn touching_points(
    circles: &[Circle],
    closed: bool,
    rel_tol: f64,
) -> Result<Vec<TouchingPoints>, SkinError> {
    let n = circles.len();
    touching_points_with(circles, closed, |i| {
        let (a, b) = (&circles[(i + n - 1) % n], &circles[(i + 1) % n]);
        triplet_touching(a, &circles[i], b, rel_tol).map(|t| t.points)
    })
}

/// [`touching_points`] with the points of circle i between its neighbours (every circle of
/// a closed sequence, the inner ones of an open one) given by `inner(i)`, which must be
/// those of [`triplet_touching`]: a caller that keeps them saves computing them again.
pub(crate) fn touching_points_with(
    circles: &[Circle],
    closed: bool,
    mut inner: impl FnMut(usize) -> Option<TouchingPoints>,
) -> Result<Vec<TouchingPoints>, SkinError> {
    validate_circles(circles)?;
    check_count(circles.len(), closed)?;
    let n = circles.len();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let err = SkinError::NoTouchingPoints { index: i };
        let tp = if !closed && i == 0 {
            end_touching(&circles[0], &circles[1], true).ok_or(err)?
        } else if !closed && i == n - 1 {
            end_touching(&circles[n - 1], &circles[n - 2], false).ok_or(err)?
        } else {
            inner(i).ok_or(err)?
        };
        out.push(tp);
    }
    Ok(out)
}

/// Gergonne's construction (kept as an independent second method): the line through the
/// radical centre of (`a`, `m`, `b`) and the pole, with respect to `m`, of the external
/// similitude axis cuts `m` in the two touching points. All points and lines are
/// homogeneous (similitude centres of equal radii lie at infinity). `None` when the line is
/// undefined (collinear centres: radical centre and pole coincide at infinity, or the
/// three similitude centres coincide) or misses `m`.
#[cfg(test)]
pub fn gergonne_points(a: &Circle, m: &Circle, b: &Circle) -> Option<[DVec2; 2]> {
    type V3 = [f64; 3];
    let x3 = |p: V3, q: V3| -> V3 {
        [
            p[1] * q[2] - p[2] * q[1],
            p[2] * q[0] - p[0] * q[2],
            p[0] * q[1] - p[1] * q[0],
        ]
    };
    let n3 = |p: V3| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let scale = m.r + a.r + b.r + m.c.distance(a.c) + m.c.distance(b.c);
    let loc = |k: &Circle| ((k.c - m.c) / scale, k.r / scale);
    let (da, ra) = loc(a);
    let (db, rb) = loc(b);
    let r0 = m.r / scale;
    // External similitude centre of (p, rp), (q, rq): (rq p − rp q : rq − rp).
    let sim = |p: DVec2, rp: f64, q: DVec2, rq: f64| -> V3 {
        let v = rq * p - rp * q;
        [v.x, v.y, rq - rp]
    };
    let axis = x3(sim(da, ra, DVec2::ZERO, r0), sim(DVec2::ZERO, r0, db, rb));
    if n3(axis) < DEGENERATE {
        return None;
    }
    // Pole of the line (A, B, C) w.r.t. x² + y² = r0²: (A r0², B r0², −C).
    let pole = [axis[0] * r0 * r0, axis[1] * r0 * r0, -axis[2]];
    // Radical line of m (origin, r0) and (d, r): 2 d·p − (‖d‖² − r² + r0²) = 0.
    let rad = |d: DVec2, r: f64| -> V3 {
        [
            2.0 * d.x,
            2.0 * d.y,
            -(d.length_squared() - r * r + r0 * r0),
        ]
    };
    let centre = x3(rad(da, ra), rad(db, rb));
    let line = x3(centre, pole);
    let nl = DVec2::new(line[0], line[1]).length();
    if nl <= DEGENERATE * n3(line) || n3(centre) == 0.0 {
        return None;
    }
    let normal = DVec2::new(line[0], line[1]) / nl;
    let c = line[2] / nl;
    let h2 = r0 * r0 - c * c;
    if h2 < 0.0 {
        return None;
    }
    let foot = -c * normal;
    let h = h2.sqrt();
    Some([
        m.c + scale * (foot + h * perp(normal)),
        m.c + scale * (foot - h * perp(normal)),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn c(x: f64, y: f64, r: f64) -> Circle {
        Circle::new(DVec2::new(x, y), r)
    }

    /// The cycle touches the circle: centre distance = |radius + r| (relative `tol`), or
    /// for a line, the signed distance of the centre is −r.
    fn touches(cy: &Apollonius, k: &Circle, tol: f64) -> bool {
        match *cy {
            Apollonius::Circle { center, radius } => {
                let d = center.distance(k.c);
                (d - (radius + k.r).abs()).abs() <= tol * (d + radius.abs() + k.r)
            }
            Apollonius::Line { normal, offset } => {
                let s = normal.dot(k.c) - offset;
                (s + k.r).abs() <= tol * (offset.abs() + k.r + k.c.length())
            }
        }
    }

    fn check_triplet(a: &Circle, m: &Circle, b: &Circle) -> TripletTouching {
        let t = triplet_touching(a, m, b, 1e-9).expect("touching points");
        let scale = m.r + m.c.length();
        for (w, cy) in [
            (t.points.left, t.left_cycle),
            (t.points.right, t.right_cycle),
        ] {
            for k in [a, m, b] {
                assert!(touches(&cy, k, 1e-9), "{cy:?} does not touch {k:?}");
            }
            assert!((w.distance(m.c) - m.r).abs() <= 1e-12 * scale);
            assert!(w.distance(cy.touching_point(m)) <= 1e-9 * scale);
        }
        // Left is left of the chord direction a→b.
        let dir = b.c - a.c;
        assert!(cross(dir, t.points.left - t.points.right) > 0.0);
        t
    }

    fn tf(k: &Circle, rot: f64, s: f64) -> Circle {
        Circle::new(DVec2::from_angle(rot).rotate(k.c) * s, k.r * s)
    }

    fn check_all_frames(a: Circle, m: Circle, b: Circle) {
        let t = check_triplet(&a, &m, &b);
        // Reversed travel swaps left and right.
        let r = check_triplet(&b, &m, &a);
        let sc = m.r + m.c.length();
        assert!(r.points.left.distance(t.points.right) <= 1e-9 * sc);
        assert!(r.points.right.distance(t.points.left) <= 1e-9 * sc);
        for (rot, s) in [(0.9, 1.0), (2.5, 1e-3), (-1.3, 1e4)] {
            let q = check_triplet(&tf(&a, rot, s), &tf(&m, rot, s), &tf(&b, rot, s));
            let rotp = |p: DVec2| DVec2::from_angle(rot).rotate(p) * s;
            assert!(q.points.left.distance(rotp(t.points.left)) <= 1e-9 * sc * s);
            assert!(q.points.right.distance(rotp(t.points.right)) <= 1e-9 * sc * s);
        }
        // Far from the origin (1e4 mm): errors relative to the coordinates.
        let sh = DVec2::new(1e4, -7e3);
        let mv = |k: &Circle| Circle::new(k.c + sh, k.r);
        let q = check_triplet(&mv(&a), &mv(&m), &mv(&b));
        assert!(q.points.left.distance(t.points.left + sh) <= 1e-9 * 1e4);
        assert!(q.points.right.distance(t.points.right + sh) <= 1e-9 * 1e4);
    }

    #[test]
    fn generic_triplet_matches_gergonne() {
        let (a, m, b) = (c(0.0, 0.0, 1.0), c(2.0, 0.7, 1.3), c(4.0, 0.0, 0.8));
        check_all_frames(a, m, b);
        let t = check_triplet(&a, &m, &b).points;
        let g = gergonne_points(&a, &m, &b).unwrap();
        let near = |p: DVec2| g.iter().any(|q| q.distance(p) < 1e-9);
        assert!(near(t.left) && near(t.right), "{t:?} vs {g:?}");
    }

    #[test]
    fn equal_radii_and_collinear_centres() {
        // Equal radii, collinear: the common tangent lines y = ±r.
        let (a, m, b) = (c(0.0, 0.0, 1.0), c(1.5, 0.0, 1.0), c(3.0, 0.0, 1.0));
        check_all_frames(a, m, b);
        let t = check_triplet(&a, &m, &b);
        assert!(t.points.left.distance(DVec2::new(1.5, 1.0)) < 1e-12);
        assert!(t.points.right.distance(DVec2::new(1.5, -1.0)) < 1e-12);
        assert!(matches!(t.left_cycle, Apollonius::Line { .. }));
        assert!(gergonne_points(&a, &m, &b).is_none());
        // Collinear with radii linear in position (a cone): tangent lines again.
        let (a, m, b) = (c(0.0, 0.0, 1.0), c(1.0, 0.0, 1.2), c(3.0, 0.0, 1.6));
        let t = check_triplet(&a, &m, &b);
        // Outer tangent normal n with n·d = −s: n = (−0.2, √0.96).
        let n = DVec2::new(-0.2, 0.96f64.sqrt());
        assert!(t.points.left.distance(m.c + m.r * n) < 1e-12);
        check_all_frames(a, m, b);
        // Collinear, radii not linear: proper circles symmetric about the axis.
        let (a, m, b) = (c(0.0, 0.0, 1.0), c(1.5, 0.0, 1.3), c(3.0, 0.0, 1.0));
        let t = check_triplet(&a, &m, &b);
        assert!((t.points.left.x - t.points.right.x).abs() < 1e-12);
        assert!((t.points.left.y + t.points.right.y).abs() < 1e-12);
        check_all_frames(a, m, b);
        // Equal radii, not collinear: similitude centres at infinity.
        let (a, m, b) = (c(0.0, 0.0, 1.0), c(1.5, 0.6, 1.0), c(3.0, 0.0, 1.0));
        check_all_frames(a, m, b);
        let t = check_triplet(&a, &m, &b).points;
        let g = gergonne_points(&a, &m, &b).unwrap();
        assert!(g.iter().any(|q| q.distance(t.left) < 1e-9));
        assert!(g.iter().any(|q| q.distance(t.right) < 1e-9));
    }

    #[test]
    fn nearly_equal_radii_and_nearly_collinear() {
        for eps in [1e-4, 1e-8, 1e-12] {
            let (a, m, b) = (
                c(0.0, 0.0, 1.0),
                c(1.5, eps, 1.0 + eps),
                c(3.0, 0.0, 1.0 - eps),
            );
            check_all_frames(a, m, b);
            // Continuity: close to the exactly collinear equal-radii answer.
            let t = check_triplet(&a, &m, &b).points;
            assert!(t.left.distance(DVec2::new(1.5, 1.0)) < 1e4 * eps);
        }
    }

    #[test]
    fn end_circles_use_outer_tangents() {
        let (a, b) = (c(0.0, 0.0, 1.0), c(4.0, 1.0, 2.0));
        let s = end_touching(&a, &b, true).unwrap();
        let e = end_touching(&b, &a, false).unwrap();
        // Both points of one tangent line: the line touches both circles there.
        for (p, q) in [(s.left, e.left), (s.right, e.right)] {
            let t = q - p;
            assert!(t.dot(p - a.c).abs() < 1e-12 * t.length());
            assert!(t.dot(q - b.c).abs() < 1e-12 * t.length());
        }
        assert!(cross(b.c - a.c, s.left - a.c) > 0.0);
        assert!(cross(b.c - a.c, s.right - a.c) < 0.0);
        assert!(end_touching(&a, &c(0.5, 0.0, 3.0), true).is_none());
    }

    #[test]
    fn sequences_closed_and_open() {
        let ring: Vec<Circle> = (0..7)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 7.0;
                c(5.0 * t.cos(), 5.0 * t.sin(), 1.0 + 0.3 * (2.0 * t).sin())
            })
            .collect();
        let tp = touching_points(&ring, true, 1e-9).unwrap();
        // CCW ring: left points inside, right points outside.
        for (k, p) in ring.iter().zip(&tp) {
            assert!(p.left.length() < k.c.length());
            assert!(p.right.length() > k.c.length());
        }
        let open = touching_points(&ring, false, 1e-9).unwrap();
        assert_eq!(open.len(), 7);
        assert_eq!(open[3], tp[3]);
        assert!(matches!(
            touching_points(&ring[..1], false, 1e-9),
            Err(SkinError::TooFewCircles { .. })
        ));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]
        #[test]
        fn random_triplets_touch(
            turn1 in -1.0f64..1.0, turn2 in -1.0f64..1.0,
            l1 in 0.8f64..2.0, l2 in 0.8f64..2.0,
            r in 0.5f64..1.0, dr1 in -0.3f64..0.3, dr2 in -0.3f64..0.3,
        ) {
            let a = c(0.0, 0.0, r);
            let m = c(l1 * turn1.cos(), l1 * turn1.sin(), r + dr1);
            let b = Circle::new(m.c + l2 * DVec2::from_angle(turn1 + turn2), r + dr2);
            prop_assume!(crate::skin::check_admissible(&[a, m, b], false, &Default::default()).is_ok());
            check_all_frames(a, m, b);
            if let Some(g) = gergonne_points(&a, &m, &b) {
                // Second method, well conditioned away from collinear centres.
                if cross(m.c - a.c, b.c - m.c).abs() > 0.1 {
                    let t = check_triplet(&a, &m, &b).points;
                    prop_assert!(g.iter().any(|q| q.distance(t.left) < 1e-7));
                    prop_assert!(g.iter().any(|q| q.distance(t.right) < 1e-7));
                }
            }
        }
    }
}
