//! Cubic Bézier curves.

use super::{Aabb, DVec2, bernstein};

/// Subdivision depth cap of [`CubicBez::nearest`]'s root isolation: pieces of 2⁻⁶⁰ of the
/// parameter range are below any accuracy asked.
const NEAREST_MAX_DEPTH: u32 = 60;

/// Cap on split pieces of [`CubicBez::nearest`]'s root isolation: a quintic has at most five
/// roots, so a few hundred pieces isolate them unless the polynomial vanishes identically
/// (p the centre of a circular-looking cubic), where any candidate is as near as another.
const NEAREST_MAX_SPLITS: usize = 512;

/// The cubic Bézier curve with control points `p0..p3`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicBez {
    /// Start point B(0).
    pub p0: DVec2,
    /// First control point (start tangent direction p1 − p0).
    pub p1: DVec2,
    /// Second control point (end tangent direction p3 − p2).
    pub p2: DVec2,
    /// End point B(1).
    pub p3: DVec2,
}

impl CubicBez {
    /// The cubic with control points `p0`..`p3`.
    pub const fn new(p0: DVec2, p1: DVec2, p2: DVec2, p3: DVec2) -> Self {
        CubicBez { p0, p1, p2, p3 }
    }

    /// The cubic Hermite arc from `w0` with tangent `v0` to `w1` with tangent `v1`
    /// (Bézier form b1 = w0 + v0/3, b2 = w1 − v1/3; re-skinning-cnc eq. 11).
    pub fn hermite(w0: DVec2, v0: DVec2, w1: DVec2, v1: DVec2) -> Self {
        CubicBez::new(w0, w0 + v0 / 3.0, w1 - v1 / 3.0, w1)
    }

    /// The four control points in order.
    pub fn points(&self) -> [DVec2; 4] {
        [self.p0, self.p1, self.p2, self.p3]
    }

    /// Point at `t` by de Casteljau.
    pub fn eval(&self, t: f64) -> DVec2 {
        let mt = 1.0 - t;
        let a = self.p0 * mt + self.p1 * t;
        let b = self.p1 * mt + self.p2 * t;
        let c = self.p2 * mt + self.p3 * t;
        let d = a * mt + b * t;
        let e = b * mt + c * t;
        d * mt + e * t
    }

    /// First derivative at `t`.
    pub fn deriv(&self, t: f64) -> DVec2 {
        let mt = 1.0 - t;
        let d0 = self.p1 - self.p0;
        let d1 = self.p2 - self.p1;
        let d2 = self.p3 - self.p2;
        3.0 * (d0 * mt * mt + d1 * 2.0 * mt * t + d2 * t * t)
    }

    /// Second derivative at `t`.
    pub fn deriv2(&self, t: f64) -> DVec2 {
        let a = self.p2 - 2.0 * self.p1 + self.p0;
        let b = self.p3 - 2.0 * self.p2 + self.p1;
        6.0 * (a * (1.0 - t) + b * t)
    }

    /// The two halves at `t` (de Casteljau subdivision).
    pub fn split(&self, t: f64) -> (CubicBez, CubicBez) {
        let mt = 1.0 - t;
        let a = self.p0 * mt + self.p1 * t;
        let b = self.p1 * mt + self.p2 * t;
        let c = self.p2 * mt + self.p3 * t;
        let d = a * mt + b * t;
        let e = b * mt + c * t;
        let f = d * mt + e * t;
        (
            CubicBez::new(self.p0, a, d, f),
            CubicBez::new(f, e, c, self.p3),
        )
    }

    /// The sub-curve on [t0, t1].
    pub fn subsegment(&self, t0: f64, t1: f64) -> CubicBez {
        let (_, right) = self.split(t0);
        if t0 >= 1.0 {
            return right;
        }
        let (left, _) = right.split((t1 - t0) / (1.0 - t0));
        left
    }

    /// The same curve traversed from `p3` to `p0` (control points reversed).
    pub fn reversed(&self) -> Self {
        CubicBez::new(self.p3, self.p2, self.p1, self.p0)
    }

    /// Axis-aligned box of the control polygon (contains the curve).
    #[must_use]
    pub fn control_bbox(&self) -> Aabb {
        Aabb::from_points(&self.points())
    }

    /// Largest distance of the inner control points from the chord p0p3: the curve lies
    /// within 3/4 of it from the chord, so it bounds the flatness of the curve.
    pub fn flatness(&self) -> f64 {
        let l = super::Line::new(self.p0, self.p3);
        l.distance(self.p1).max(l.distance(self.p2))
    }

    /// Points along the curve such that the chords deviate from the curve by at most `tol`,
    /// by recursive subdivision until the control polygon is flat (distance of the curve to
    /// a chord ≤ ¾ · control-point distance to that chord). First and last point included.
    pub fn flatten(&self, tol: f64) -> Vec<DVec2> {
        let mut out = vec![self.p0];
        self.flatten_into(tol, 0, &mut out);
        out
    }

    fn flatten_into(&self, tol: f64, depth: u32, out: &mut Vec<DVec2>) {
        if depth >= 24 || 0.75 * self.flatness() <= tol {
            out.push(self.p3);
        } else {
            let (a, b) = self.split(0.5);
            a.flatten_into(tol, depth + 1, out);
            b.flatten_into(tol, depth + 1, out);
        }
    }

    /// The point of the curve nearest to `p`, as (parameter, distance): the end points and
    /// the roots in (0, 1) of f(t) = (B(t) − p)·B′(t), the quintic whose zeros are the
    /// curve's points where the direction to `p` is normal to it. Its Bernstein
    /// coefficients are those of the product of the cubic B − p (points qᵢ = Pᵢ − p) and
    /// the quadratic B′ (points dⱼ = 3(Pⱼ₊₁ − Pⱼ)): cₖ = Σ_{i+j=k} C(3,i)C(2,j)/C(5,k) qᵢ·dⱼ
    /// (Farouki and Rajan 1988, product rule); the roots are isolated by subdivision and
    /// refined by Brent's method to `accuracy` in t (`bernstein::isolate_roots`). The
    /// lowest parameter wins a tie.
    #[must_use]
    pub fn nearest(&self, p: DVec2, accuracy: f64) -> (f64, f64) {
        let q = self.points().map(|c| c - p);
        let d = [self.p1 - self.p0, self.p2 - self.p1, self.p3 - self.p2].map(|v| 3.0 * v);
        let mut c = [0.0; 6];
        for (i, qi) in q.iter().enumerate() {
            for (j, dj) in d.iter().enumerate() {
                c[i + j] += bernstein::binom(3, i) * bernstein::binom(2, j) * qi.dot(*dj);
            }
        }
        for (k, ck) in c.iter_mut().enumerate() {
            *ck /= bernstein::binom(5, k);
        }
        let opts = bernstein::RootOptions {
            tol: accuracy,
            max_depth: NEAREST_MAX_DEPTH,
            max_splits: NEAREST_MAX_SPLITS,
        };
        let roots = bernstein::isolate_roots(&c, &opts);
        std::iter::once(0.0)
            .chain(roots)
            .chain(std::iter::once(1.0))
            .map(|t| (t, self.eval(t).distance(p)))
            .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a })
    }

    /// Arc length by adaptive Gauss–Legendre quadrature to relative accuracy `tol`.
    pub fn arclen(&self, tol: f64) -> f64 {
        fn gl5(c: &CubicBez, a: f64, b: f64) -> f64 {
            const X: [f64; 5] = [
                0.0,
                -0.538_469_310_105_683,
                0.538_469_310_105_683,
                -0.906_179_845_938_664,
                0.906_179_845_938_664,
            ];
            const W: [f64; 5] = [
                0.568_888_888_888_889,
                0.478_628_670_499_366,
                0.478_628_670_499_366,
                0.236_926_885_056_189,
                0.236_926_885_056_189,
            ];
            let h = 0.5 * (b - a);
            let m = 0.5 * (a + b);
            (0..5)
                .map(|i| W[i] * c.deriv(m + h * X[i]).length())
                .sum::<f64>()
                * h
        }
        fn rec(c: &CubicBez, a: f64, b: f64, whole: f64, tol: f64, depth: u32) -> f64 {
            let m = 0.5 * (a + b);
            let l = gl5(c, a, m);
            let r = gl5(c, m, b);
            if depth > 20 || (l + r - whole).abs() <= tol * (l + r).abs().max(1e-300) {
                l + r
            } else {
                rec(c, a, m, l, tol, depth + 1) + rec(c, m, b, r, tol, depth + 1)
            }
        }
        let whole = gl5(self, 0.0, 1.0);
        rec(self, 0.0, 1.0, whole, tol, 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_halves_match_curve() {
        let c = CubicBez::new(
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(3.0, -1.0),
            DVec2::new(4.0, 1.0),
        );
        let (a, b) = c.split(0.3);
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            assert!((a.eval(s) - c.eval(0.3 * s)).length() < 1e-14);
            assert!((b.eval(s) - c.eval(0.3 + 0.7 * s)).length() < 1e-14);
        }
        let sub = c.subsegment(0.2, 0.7);
        assert!((sub.eval(0.5) - c.eval(0.45)).length() < 1e-14);
    }

    #[test]
    fn derivative_matches_finite_difference() {
        let c = CubicBez::new(
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(3.0, -1.0),
            DVec2::new(4.0, 1.0),
        );
        let h = 1e-6;
        for i in 1..10 {
            let t = i as f64 / 10.0;
            let fd = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
            assert!((fd - c.deriv(t)).length() < 1e-8);
            let fd2 = (c.deriv(t + h) - c.deriv(t - h)) / (2.0 * h);
            assert!((fd2 - c.deriv2(t)).length() < 1e-7);
        }
    }

    /// The nearest point agrees with dense sampling refined by golden-section search (a
    /// second method), is never farther than any sample, and its direction to `p` is normal
    /// to the curve unless it is an end point.
    #[test]
    fn nearest_agrees_with_dense_sampling() {
        use crate::geom::roots::{Golden, Tie};
        let c = CubicBez::new(
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(3.0, -1.0),
            DVec2::new(4.0, 1.0),
        );
        for (x, y) in [
            (2.0, 2.0),
            (2.0, -1.0),
            (-1.0, -1.0),
            (5.0, 0.3),
            (1.0, 0.8),
            (3.3, 0.0),
        ] {
            let p = DVec2::new(x, y);
            let (t, d) = c.nearest(p, 1e-12);
            assert!((c.eval(t).distance(p) - d).abs() < 1e-15);
            let n = 4000;
            let k = (0..=n)
                .min_by(|&a, &b| {
                    let (ta, tb) = (a as f64 / n as f64, b as f64 / n as f64);
                    c.eval(ta).distance(p).total_cmp(&c.eval(tb).distance(p))
                })
                .unwrap();
            let (a, b) = (
                (k.max(1) - 1) as f64 / n as f64,
                (k + 1).min(n) as f64 / n as f64,
            );
            let g = Golden::new(1e-13, 200, Tie::Right).min(|s| c.eval(s).distance(p), a, b);
            let want = c
                .eval(g.mid())
                .distance(p)
                .min(c.eval(k as f64 / n as f64).distance(p));
            assert!(d <= want + 1e-12, "{p}: {d} vs {want}");
            assert!(d >= want - 1e-9, "{p}: {d} vs {want}");
            if t > 0.0 && t < 1.0 {
                let u = c.deriv(t).normalize();
                assert!((c.eval(t) - p).dot(u).abs() < 1e-9, "{p}");
            }
        }
    }

    #[test]
    fn arclen_of_straight_cubic() {
        let c = CubicBez::new(
            DVec2::ZERO,
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(3.0, 0.0),
        );
        assert!((c.arclen(1e-12) - 3.0).abs() < 1e-12);
    }
}
