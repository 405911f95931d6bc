//! The left and right skins as G1 cubic Bézier splines (Kunkli–Hoffmann 2010, tangent
//! lengths of re-skinning-cnc eqs. 11–12).
//!
//! Between c_i and c_{i+1} each skin is the Hermite arc b0 = w_i, b1 = w_i + v_i/3,
//! b2 = w_{i+1} − v_{i+1}/3, b3 = w_{i+1} through the touching points w_j, whose tangent
//! v_j is perpendicular to the radius at w_j, points along travel, and has length
//! α_j = 2·dist(w_j, l_i) with l_i the radical line of c_i and c_{i+1} (eq. 12). Each
//! touching point ends one arc and starts the next with the same tangent direction, so the
//! skins are G1.

use super::admissible::{AdmissibilityOptions, SkinError, check_admissible, check_count};
use super::touching::{TouchingPoints, touching_points};
use crate::dbsc::Side;
use crate::geom::{Circle, CubicBez, DVec2, Path, PathSeg, perp};

/// The two skins of a circle sequence: segment i joins circle i to circle i + 1 (and, closed,
/// the last circle to the first).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Skins {
    /// Left skin: segment i is the cubic Hermite arc from the left touching point of circle i to
    /// that of circle i + 1.
    pub left: Vec<CubicBez>,
    /// Right skin, segment by segment as [`Skins::left`].
    pub right: Vec<CubicBez>,
    /// Touching points used, one entry per circle.
    pub touching: Vec<TouchingPoints>,
    /// Whether the sequence is cyclic: the last segment joins the last circle to the first.
    pub closed: bool,
}

impl Skins {
    /// One skin as a [`Path`] (closed for closed sequences), in the direction of travel.
    pub fn path(&self, side: Side) -> Path {
        let segs = match side {
            Side::Left => &self.left,
            Side::Right => &self.right,
        };
        Path::new(
            segs.iter().map(|c| PathSeg::Cubic(*c)).collect(),
            self.closed,
        )
    }
}

/// Options of [`skin_circles`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SkinOptions {
    /// Admissibility conditions to enforce and the relative tolerance used throughout.
    pub admissibility: AdmissibilityOptions,
    /// Check admissibility first (kruppa-2023 Def. 4.1). Turn off only when the caller has
    /// already checked the same sequence.
    pub check_admissibility: bool,
}

impl Default for SkinOptions {
    fn default() -> Self {
        SkinOptions {
            admissibility: AdmissibilityOptions::default(),
            check_admissibility: true,
        }
    }
}

/// Unit tangent of the skin on `side` at the touching point `w` of circle `c`: the radius
/// direction u = (w − c)/r turned a quarter clockwise for the left skin, counter-clockwise
/// for the right one (both point along travel).
pub fn skin_tangent(c: &Circle, w: DVec2, side: Side) -> DVec2 {
    let u = (w - c.c).normalize_or_zero();
    match side {
        Side::Left => -perp(u),
        Side::Right => perp(u),
    }
}

/// Tangent length α = 2·dist(w, l) of re-skinning-cnc eq. 12, l the radical line of `a` and
/// `b`: dist(w, l) = |pow_b(w) − pow_a(w)| / (2‖c_b − c_a‖).
pub fn tangent_length(a: &Circle, b: &Circle, w: DVec2) -> f64 {
    let d = a.c.distance(b.c);
    if d == 0.0 {
        return 0.0;
    }
    (b.power(w) - a.power(w)).abs() / d
}

/// The skin arc on `side` from touching point `w0` on `c0` to `w1` on `c1`
/// (re-skinning-cnc eqs. 11–12 with the Hermite–Bézier form of [`CubicBez::hermite`]).
#[must_use]
pub fn skin_segment(c0: &Circle, w0: DVec2, c1: &Circle, w1: DVec2, side: Side) -> CubicBez {
    let v0 = tangent_length(c0, c1, w0) * skin_tangent(c0, w0, side);
    let v1 = tangent_length(c0, c1, w1) * skin_tangent(c1, w1, side);
    CubicBez::hermite(w0, v0, w1, v1)
}

/// Both skins from given touching points (one [`TouchingPoints`] per circle).
pub fn bezier_skins(
    circles: &[Circle],
    touching: &[TouchingPoints],
    closed: bool,
) -> Result<Skins, SkinError> {
    check_count(circles.len(), closed)?;
    if touching.len() != circles.len() {
        return Err(SkinError::TouchingCount {
            index: touching.len().min(circles.len()),
            touching: touching.len(),
            circles: circles.len(),
        });
    }
    let n = circles.len();
    let m = if closed { n } else { n - 1 };
    let mut left = Vec::with_capacity(m);
    let mut right = Vec::with_capacity(m);
    for i in 0..m {
        let j = (i + 1) % n;
        let (a, b) = (&circles[i], &circles[j]);
        left.push(skin_segment(
            a,
            touching[i].left,
            b,
            touching[j].left,
            Side::Left,
        ));
        right.push(skin_segment(
            a,
            touching[i].right,
            b,
            touching[j].right,
            Side::Right,
        ));
    }
    Ok(Skins {
        left,
        right,
        touching: touching.to_vec(),
        closed,
    })
}

/// Skins an open or closed circle sequence: admissibility (kruppa-2023 Def. 4.1, unless
/// turned off), touching points ([`touching_points`]) and the Bézier skins.
pub fn skin_circles(
    circles: &[Circle],
    closed: bool,
    opts: &SkinOptions,
) -> Result<Skins, SkinError> {
    if opts.check_admissibility {
        check_admissible(circles, closed, &opts.admissibility)?;
    }
    let tp = touching_points(circles, closed, opts.admissibility.rel_tol)?;
    bezier_skins(circles, &tp, closed)
}

/// Distance from `p` to the convex hull of the control points of `c` (0 inside): the hull
/// of four points is covered by the four triangles of three of them, and outside it the
/// nearest hull point lies on one of the six segments between them.
#[cfg(test)]
fn hull_distance(c: &CubicBez, p: DVec2) -> f64 {
    let q = c.points();
    let tri = |a: DVec2, b: DVec2, d: DVec2| {
        let s1 = crate::geom::cross(b - a, p - a);
        let s2 = crate::geom::cross(d - b, p - b);
        let s3 = crate::geom::cross(a - d, p - d);
        (s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0) || (s1 <= 0.0 && s2 <= 0.0 && s3 <= 0.0)
    };
    if tri(q[0], q[1], q[2])
        || tri(q[0], q[1], q[3])
        || tri(q[0], q[2], q[3])
        || tri(q[1], q[2], q[3])
    {
        return 0.0;
    }
    let mut d = f64::INFINITY;
    for i in 0..4 {
        for j in i + 1..4 {
            d = d.min(crate::geom::Line::new(q[i], q[j]).distance(p));
        }
    }
    d
}

/// Guaranteed upper bound on how deep the curve `c` enters the disk `k`:
/// max_t (r − ‖c(t) − centre‖), within `tol` of the true maximum (branch and bound: the
/// convex hull of a subdivided piece bounds its distance from below, points on it from
/// above; pieces that cannot beat the best point by more than `tol` are dropped).
/// A value ≤ 0 means the curve stays outside the open disk.
#[cfg(test)]
pub fn max_disk_penetration(c: &CubicBez, k: &Circle, tol: f64) -> f64 {
    /// Subdivision depth limit: 2⁻⁴⁰ of the curve's size is below any useful tolerance.
    const MAX_DEPTH: u32 = 40;
    fn rec(c: &CubicBez, k: &Circle, tol: f64, depth: u32, best: &mut f64, open: &mut f64) {
        let ub = k.r - hull_distance(c, k.c);
        if ub <= *best + tol {
            return;
        }
        for t in [0.0, 0.5, 1.0] {
            *best = best.max(k.r - c.eval(t).distance(k.c));
        }
        if depth >= MAX_DEPTH {
            *open = open.max(ub);
            return;
        }
        let (a, b) = c.split(0.5);
        rec(&a, k, tol, depth + 1, best, open);
        rec(&b, k, tol, depth + 1, best, open);
    }
    let mut best = f64::NEG_INFINITY;
    let mut open = f64::NEG_INFINITY;
    rec(c, k, tol, 0, &mut best, &mut open);
    (best + tol).max(open)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(x: f64, y: f64, r: f64) -> Circle {
        Circle::new(DVec2::new(x, y), r)
    }

    fn wavy(n: usize) -> Vec<Circle> {
        (0..n)
            .map(|i| {
                let t = i as f64;
                c(1.6 * t, 1.2 * (0.7 * t).sin(), 1.0 + 0.3 * (0.9 * t).cos())
            })
            .collect()
    }

    /// Every skin invariant of one sequence: touching, tangency, G1 and no disk entered.
    fn check_skins(circles: &[Circle], closed: bool) -> Skins {
        let s = skin_circles(circles, closed, &SkinOptions::default()).unwrap();
        let n = circles.len();
        let scale = circles
            .iter()
            .map(|k| k.c.length() + k.r)
            .fold(0.0, f64::max);
        let eps = 1e-9 * scale;
        for (side, segs) in [(Side::Left, &s.left), (Side::Right, &s.right)] {
            let tp = |i: usize| match side {
                Side::Left => s.touching[i].left,
                Side::Right => s.touching[i].right,
            };
            for (i, seg) in segs.iter().enumerate() {
                let j = (i + 1) % n;
                assert!(seg.p0.distance(tp(i)) <= eps && seg.p3.distance(tp(j)) <= eps);
                for (k, p, d) in [
                    (&circles[i], seg.p0, seg.deriv(0.0)),
                    (&circles[j], seg.p3, seg.deriv(1.0)),
                ] {
                    assert!((p.distance(k.c) - k.r).abs() <= eps);
                    // Tangent ⟂ radius, along travel (positive along skin_tangent).
                    let u = (p - k.c) / k.r;
                    assert!(u.dot(d).abs() <= 1e-9 * d.length());
                    assert!(d.dot(skin_tangent(k, p, side)) > 0.0);
                }
                // Independent check of eq. 12: α from the radical line as a point–line
                // distance (the line through the radical point along the centre normal).
                let (a, b) = (&circles[i], &circles[j]);
                let dir = (b.c - a.c).normalize();
                // Radical line: points x with x·dir = (‖b‖² − ‖a‖² − r_b² + r_a²) / (2‖b − a‖).
                let off = (b.c.length_squared() - a.c.length_squared() - b.r * b.r + a.r * a.r)
                    / (2.0 * b.c.distance(a.c));
                let alpha0 = 2.0 * (seg.p0.dot(dir) - off).abs();
                assert!((seg.deriv(0.0).length() - alpha0).abs() <= 1e-7 * (alpha0 + scale));
            }
            // G1 at every joint: same unit tangent.
            let joints = if closed { segs.len() } else { segs.len() - 1 };
            for i in 0..joints {
                let (p, q) = (&segs[i], &segs[(i + 1) % segs.len()]);
                let (t0, t1) = (p.deriv(1.0).normalize(), q.deriv(0.0).normalize());
                assert!(t0.distance(t1) <= 1e-9, "joint {i}: {t0} vs {t1}");
            }
            // No disk entered beyond the tolerance (guaranteed bound).
            for seg in segs.iter() {
                for k in circles {
                    let pen = max_disk_penetration(seg, k, 1e-6 * scale);
                    assert!(pen <= 2e-6 * scale, "skin enters {k:?} by {pen}");
                }
            }
        }
        s
    }

    fn frames(cs: &[Circle], closed: bool) {
        check_skins(cs, closed);
        let rev: Vec<Circle> = cs.iter().rev().copied().collect();
        let r = check_skins(&rev, closed);
        let f = check_skins(cs, closed);
        // Reversal swaps the sides: left skin of the reverse = reversed right skin.
        let n = cs.len();
        for i in 0..n {
            let j = n - 1 - i;
            assert!(r.touching[j].left.distance(f.touching[i].right) < 1e-9 * 100.0);
        }
        for (rot, s) in [(0.8, 1e-3), (-2.1, 1e4)] {
            let q = DVec2::from_angle(rot);
            let t: Vec<Circle> = cs
                .iter()
                .map(|k| Circle::new(q.rotate(k.c) * s, k.r * s))
                .collect();
            check_skins(&t, closed);
        }
    }

    #[test]
    fn open_wavy_sequence() {
        frames(&wavy(9), false);
        frames(&wavy(2), false);
    }

    #[test]
    fn closed_ring() {
        let ring: Vec<Circle> = (0..9)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 9.0;
                c(6.0 * t.cos(), 4.0 * t.sin(), 1.0 + 0.2 * (3.0 * t).sin())
            })
            .collect();
        frames(&ring, true);
    }

    #[test]
    fn penetration_bound_matches_closed_form() {
        // A straight cubic through a disk: depth r − distance of the line.
        let seg = CubicBez::new(
            DVec2::new(-3.0, 0.5),
            DVec2::new(-1.0, 0.5),
            DVec2::new(1.0, 0.5),
            DVec2::new(3.0, 0.5),
        );
        let k = c(0.2, 0.0, 1.0);
        let p = max_disk_penetration(&seg, &k, 1e-9);
        assert!((p - 0.5).abs() <= 2e-9, "{p}");
        let far = c(0.0, 5.0, 1.0);
        assert!(max_disk_penetration(&seg, &far, 1e-9) < -3.0);
    }
}
