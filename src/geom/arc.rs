//! Circular arcs: centre, radius, start angle and signed sweep.

use super::{Aabb, DVec2};
use std::f64::consts::{FRAC_PI_2, PI};

/// The arc of the circle (`center`, `radius`) from angle `start` through the signed angle
/// `sweep` (counter-clockwise when positive; |sweep| ≤ 2π, a full circle when |sweep| = 2π).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// Centre of the circle.
    pub center: DVec2,
    /// Radius (> 0 for user data).
    pub radius: f64,
    /// Angle of the start point, radians counter-clockwise from +x.
    pub start: f64,
    /// Signed swept angle: counter-clockwise when positive.
    pub sweep: f64,
}

impl Arc {
    /// The arc of the circle (`center`, `radius`) from angle `start` through `sweep`.
    pub const fn new(center: DVec2, radius: f64, start: f64, sweep: f64) -> Self {
        Arc {
            center,
            radius,
            start,
            sweep,
        }
    }

    /// The arc of the circle (`center`, radius ‖p0 − center‖) from `p0` to the direction of
    /// `p1`, counter-clockwise when `ccw`. Equal directions give a full circle.
    pub fn from_center_points(center: DVec2, p0: DVec2, p1: DVec2, ccw: bool) -> Self {
        let a0 = (p0 - center).to_angle();
        let a1 = (p1 - center).to_angle();
        let mut sweep = a1 - a0;
        if ccw {
            while sweep <= 0.0 {
                sweep += 2.0 * PI;
            }
        } else {
            while sweep >= 0.0 {
                sweep -= 2.0 * PI;
            }
        }
        Arc::new(center, p0.distance(center), a0, sweep)
    }

    /// The arc from `p0` to `p1` with bulge `b = tan(θ/4)` (θ the signed sweep), as in
    /// polyline formats (DXF LWPOLYLINE, cavalier_contours). `b` must be non-zero.
    pub fn from_bulge(p0: DVec2, p1: DVec2, b: f64) -> Self {
        let chord = p1 - p0;
        let c = chord.length();
        let sweep = 4.0 * b.atan();
        // Sagitta geometry: the centre lies on the chord's bisector at signed distance
        // d = (c/2)·(1 − b²)/(2b) to the left of p0→p1.
        let d = 0.5 * c * (1.0 - b * b) / (2.0 * b);
        let mid = 0.5 * (p0 + p1);
        let left = if c > 0.0 {
            DVec2::new(-chord.y, chord.x) / c
        } else {
            DVec2::ZERO
        };
        let center = mid + d * left;
        let radius = center.distance(p0);
        Arc::new(center, radius, (p0 - center).to_angle(), sweep)
    }

    /// The bulge tan(sweep/4) of the arc.
    pub fn bulge(&self) -> f64 {
        (self.sweep / 4.0).tan()
    }

    /// Angle of the end point, `start + sweep`.
    pub fn end_angle(&self) -> f64 {
        self.start + self.sweep
    }

    /// True when the arc runs counter-clockwise (positive sweep).
    pub fn is_ccw(&self) -> bool {
        self.sweep > 0.0
    }

    /// Point at parameter `t` in [0, 1].
    pub fn eval(&self, t: f64) -> DVec2 {
        let a = self.start + t * self.sweep;
        self.center + self.radius * DVec2::new(a.cos(), a.sin())
    }

    /// Unit tangent along the direction of travel at parameter `t`.
    pub fn tangent(&self, t: f64) -> DVec2 {
        let a = self.start + t * self.sweep;
        let s = self.sweep.signum();
        s * DVec2::new(-a.sin(), a.cos())
    }

    /// Start point, `eval(0)`.
    pub fn p0(&self) -> DVec2 {
        self.eval(0.0)
    }

    /// End point, `eval(1)`.
    pub fn p1(&self) -> DVec2 {
        self.eval(1.0)
    }

    /// Arc length r·|sweep|.
    pub fn length(&self) -> f64 {
        self.radius * self.sweep.abs()
    }

    /// The same arc traversed from its end to its start.
    pub fn reversed(&self) -> Self {
        Arc::new(
            self.center,
            self.radius,
            self.start + self.sweep,
            -self.sweep,
        )
    }

    /// True when the direction of `p − center` lies within the swept angle.
    pub fn contains_angle_of(&self, p: DVec2) -> bool {
        if self.sweep.abs() >= 2.0 * PI {
            return true;
        }
        let a = axis_angle(p - self.center);
        let mut d = (a - self.start) * self.sweep.signum();
        d = d.rem_euclid(2.0 * PI);
        d <= self.sweep.abs()
    }

    /// The arc's axis-extreme points (leftmost, rightmost, lowest, highest points of its
    /// circle, in the order +x, +y, −x, −y) that lie within the swept angle: with the two
    /// end points they bound the arc exactly, since a circular arc is monotone in x and y
    /// between them (x = cₓ + r cos θ has dx/dθ = 0 only at θ = 0, π; y likewise at ±π/2).
    /// The axis directions' angles come from `axis_angle` without a call to `atan2`.
    pub fn extrema(&self) -> impl Iterator<Item = DVec2> + '_ {
        [DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y]
            .into_iter()
            .map(|d| self.center + self.radius * d)
            .filter(|&q| self.contains_angle_of(q))
    }

    /// The exact axis-aligned bounding box (lo, hi) of the arc: its end points and its
    /// [`extrema`](Self::extrema).
    #[must_use]
    pub fn bounding_box(&self) -> Aabb {
        let start = Aabb::from_corners(self.p0(), self.p1());
        self.extrema().fold(start, Aabb::add_point)
    }

    /// Euclidean distance from `p` to the arc.
    pub fn distance(&self, p: DVec2) -> f64 {
        if self.contains_angle_of(p) {
            ((p - self.center).length() - self.radius).abs()
        } else {
            self.p0().distance(p).min(self.p1().distance(p))
        }
    }

    /// Number of chords needed so that the sagitta of each is at most `tol`.
    /// A chord over angle φ has sagitta r(1 − cos(φ/2)).
    pub fn chords_for_tolerance(&self, tol: f64) -> usize {
        if self.radius <= tol {
            return 1;
        }
        let max_phi = 2.0 * (1.0 - tol / self.radius).clamp(-1.0, 1.0).acos();
        if max_phi <= 0.0 {
            return 1;
        }
        ((self.sweep.abs() / max_phi).ceil() as usize).clamp(1, 1 << 20)
    }

    /// Points along the arc with sagitta ≤ `tol`, first and last included.
    pub fn flatten(&self, tol: f64) -> Vec<DVec2> {
        let n = self.chords_for_tolerance(tol);
        (0..=n).map(|i| self.eval(i as f64 / n as f64)).collect()
    }
}

/// The angle of `v`, `atan2(v.y, v.x)`, bit for bit: the values `atan2` gives on the
/// axes (±0, ±π, ±π/2, by the signs of the components) are returned without calling it,
/// the rest (NaN components included) by `atan2`.
fn axis_angle(v: DVec2) -> f64 {
    if v.y == 0.0 && v.x > 0.0 {
        v.y
    } else if v.y == 0.0 && v.x < 0.0 {
        PI.copysign(v.y)
    } else if v.x == 0.0 && v.y.abs() > 0.0 {
        FRAC_PI_2.copysign(v.y)
    } else {
        v.to_angle()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// `axis_angle` is `atan2` bit for bit: on the axes (both signs of zero, infinities),
    /// at the origin, with NaN components, and at points around a centre as `extrema`
    /// makes them (centre + r·axis − centre, which can round to an axis or to zero).
    #[test]
    fn axis_angle_is_atan2() {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            1e-300,
            -1e-300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for &x in &special {
            for &y in &special {
                let v = DVec2::new(x, y);
                let (a, b) = (axis_angle(v), v.to_angle());
                assert!(
                    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                    "{v}: {a} {b}"
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        #[test]
        fn axis_angle_is_atan2_around_centres(
            cx in -1e4f64..1e4,
            cy in -1e4f64..1e4,
            r in prop_oneof![1e-14f64..1e-9, 1e-3f64..1e3],
            k in 0usize..4,
            other in (-1e3f64..1e3, -1e3f64..1e3),
        ) {
            let c = DVec2::new(cx, cy);
            let d = [DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y][k];
            for v in [(c + r * d) - c, DVec2::new(other.0, other.1)] {
                prop_assert_eq!(axis_angle(v).to_bits(), v.to_angle().to_bits(), "{}", v);
            }
        }
    }

    #[test]
    fn bulge_round_trip() {
        let p0 = DVec2::new(1.0, 2.0);
        let p1 = DVec2::new(4.0, -1.0);
        for &b in &[0.1, 0.5, 1.0, 2.0, -0.3, -1.0, -3.0] {
            let a = Arc::from_bulge(p0, p1, b);
            assert!((a.p0() - p0).length() < 1e-12);
            assert!((a.p1() - p1).length() < 1e-12, "b={b}");
            assert!((a.bulge() - b).abs() < 1e-12);
        }
    }

    #[test]
    fn bounding_box_includes_swept_extremes_only() {
        // Quarter arc from +x to +y: the box is the unit square's corner [0, 1]².
        let q = Arc::new(DVec2::ZERO, 1.0, 0.0, PI / 2.0);
        let Aabb { min: lo, max: hi } = q.bounding_box();
        assert!(lo.abs().max_element() < 1e-15 && (hi - DVec2::ONE).abs().max_element() < 1e-15);
        // Arc from angle −π/4 through 0 to π/4 (centre (2, 3), radius 2): reaches x = 4.
        let a = Arc::new(DVec2::new(2.0, 3.0), 2.0, -PI / 4.0, PI / 2.0);
        assert_eq!(a.extrema().collect::<Vec<_>>(), vec![DVec2::new(4.0, 3.0)]);
        let Aabb { min: lo, max: hi } = a.bounding_box();
        assert_eq!(hi.x, 4.0);
        assert!((lo.x - (2.0 + 2.0_f64.sqrt())).abs() < 1e-12);
        assert!((hi.y - (3.0 + 2.0_f64.sqrt())).abs() < 1e-12);
        // The clockwise arc over the same ends sweeps the other three extremes.
        let cw = Arc::new(DVec2::new(2.0, 3.0), 2.0, -PI / 4.0, -1.5 * PI);
        assert_eq!(cw.extrema().count(), 3);
        assert_eq!(cw.bounding_box().min, DVec2::new(0.0, 1.0));
    }

    #[test]
    fn semicircle_from_center_points() {
        let a = Arc::from_center_points(DVec2::ZERO, DVec2::X, -DVec2::X, true);
        assert!((a.sweep - PI).abs() < 1e-15);
        assert!((a.eval(0.5) - DVec2::Y).length() < 1e-15);
        assert!((a.length() - PI).abs() < 1e-15);
        let cw = Arc::from_center_points(DVec2::ZERO, DVec2::X, -DVec2::X, false);
        assert!((cw.eval(0.5) + DVec2::Y).length() < 1e-15);
    }

    #[test]
    fn flatten_sagitta_within_tolerance() {
        let a = Arc::new(DVec2::new(3.0, 1.0), 10.0, 0.3, 4.0);
        let tol = 1e-3;
        let pts = a.flatten(tol);
        for w in pts.windows(2) {
            let mid = 0.5 * (w[0] + w[1]);
            let sag = a.radius - mid.distance(a.center);
            assert!(sag <= tol * (1.0 + 1e-9));
        }
    }
}
