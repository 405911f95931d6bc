//! Planar Pythagorean-hodograph quintics by C¹ Hermite interpolation (Farouki & Neff 1995,
//! as used for MPH skins in re-skinning-cnc Sec. 3.2 and re-mph-skinning-flexible Sec. 2.1:
//! "if x(t) is a PH curve, then ȳ(t) is an MPH curve and the offsets are rational").
//!
//! In complex form the hodograph is x′(t) = w(t)², w(t) = w₀B₀²(t) + w₁B₁²(t) + w₂B₂²(t).
//! The end conditions give w₀² = d₀ = x′(0), w₂² = d₁ = x′(1), and ∫₀¹ x′ = Δp gives
//! w₁ = −¾(w₀ + w₂) ± ¼ √(120 Δp − 15(d₀ + d₁) + 10 w₀w₂): four interpolants, of which we
//! keep the one of least bending energy ∫ κ² ds.

use super::poly::Poly;
use crate::geom::DVec2;
use nalgebra::Complex;

type C = Complex<f64>;

fn c(v: DVec2) -> C {
    C::new(v.x, v.y)
}

fn v(z: C) -> DVec2 {
    DVec2::new(z.re, z.im)
}

/// Gauss–Legendre nodes/weights on [−1, 1] (10 points) for the bending energy used only
/// to rank the four interpolants: exact for polynomials of degree 19, ample for ranking.
const GL_X: [f64; 5] = [
    0.148_874_338_981_631_2,
    0.433_395_394_129_247_2,
    0.679_409_568_299_024_4,
    0.865_063_366_688_984_5,
    0.973_906_528_517_171_7,
];
const GL_W: [f64; 5] = [
    0.295_524_224_714_752_9,
    0.269_266_719_309_996_4,
    0.219_086_362_515_982,
    0.149_451_349_150_580_6,
    0.066_671_344_308_688_1,
];

/// A planar PH quintic: Bézier control points and the preimage coefficients w₀, w₁, w₂.
#[derive(Clone, Debug, PartialEq)]
pub struct PhQuintic {
    /// Bézier control points p₀ … p₅.
    pub ctrl: [DVec2; 6],
    /// The preimage coefficients w₀, w₁, w₂ of the hodograph x′ = w², as complex numbers (re, im).
    pub w: [(f64, f64); 3],
}

impl PhQuintic {
    /// From the preimage w and the start point: p₁ = p₀ + w₀²/5, p₂ = p₁ + w₀w₁/5,
    /// p₃ = p₂ + (2w₁² + w₀w₂)/15, p₄ = p₃ + w₁w₂/5, p₅ = p₄ + w₂²/5.
    fn from_preimage(p0: DVec2, w0: C, w1: C, w2: C) -> Self {
        let p1 = p0 + v(w0 * w0) / 5.0;
        let p2 = p1 + v(w0 * w1) / 5.0;
        let p3 = p2 + v(w1 * w1 * 2.0 + w0 * w2) / 15.0;
        let p4 = p3 + v(w1 * w2) / 5.0;
        let p5 = p4 + v(w2 * w2) / 5.0;
        PhQuintic {
            ctrl: [p0, p1, p2, p3, p4, p5],
            w: [(w0.re, w0.im), (w1.re, w1.im), (w2.re, w2.im)],
        }
    }

    fn wc(&self, k: usize) -> C {
        let (re, im) = self.w[k];
        C::new(re, im)
    }

    /// The four Hermite interpolants of p₀, p₁ with end derivatives d₀, d₁.
    pub fn hermite_all(p0: DVec2, d0: DVec2, p1: DVec2, d1: DVec2) -> [PhQuintic; 4] {
        let dp = c(p1 - p0);
        let w0 = c(d0).sqrt();
        let s1 = c(d1).sqrt();
        let mk = |w2: C, sg: f64| {
            let disc = (dp * 120.0 - (c(d0) + c(d1)) * 15.0 + w0 * w2 * 10.0).sqrt();
            let w1 = -(w0 + w2) * 0.75 + disc * (0.25 * sg);
            PhQuintic::from_preimage(p0, w0, w1, w2)
        };
        [mk(s1, 1.0), mk(s1, -1.0), mk(-s1, 1.0), mk(-s1, -1.0)]
    }

    /// The interpolant of least bending energy ∫ κ² ds (Farouki's selection rule).
    /// `None` when every candidate has a singular point (zero hodograph).
    #[cfg(test)]
    pub fn hermite(p0: DVec2, d0: DVec2, p1: DVec2, d1: DVec2) -> Option<PhQuintic> {
        PhQuintic::hermite_ranked(p0, d0, p1, d1).into_iter().next()
    }

    /// The Hermite interpolants of finite bending energy, least energy first.
    pub fn hermite_ranked(p0: DVec2, d0: DVec2, p1: DVec2, d1: DVec2) -> Vec<PhQuintic> {
        let mut v: Vec<(f64, PhQuintic)> = PhQuintic::hermite_all(p0, d0, p1, d1)
            .into_iter()
            .map(|q| (q.bending_energy(), q))
            .filter(|(e, _)| e.is_finite())
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v.into_iter().map(|(_, q)| q).collect()
    }

    /// Power-basis coordinate polynomials (x(t), y(t)).
    pub fn polys(&self) -> (Poly, Poly) {
        let bx: Vec<f64> = self.ctrl.iter().map(|p| p.x).collect();
        let by: Vec<f64> = self.ctrl.iter().map(|p| p.y).collect();
        (Poly::from_bernstein(&bx), Poly::from_bernstein(&by))
    }

    /// Parametric speed σ(t) = |w(t)|² as a quartic (Bernstein coefficients |w₀|²,
    /// Re(w₀ w̄₁), (2|w₁|² + Re(w₀ w̄₂))/3, Re(w₁ w̄₂), |w₂|²).
    pub fn sigma(&self) -> Poly {
        let (w0, w1, w2) = (self.wc(0), self.wc(1), self.wc(2));
        let b = [
            w0.norm_sqr(),
            (w0 * w1.conj()).re,
            (2.0 * w1.norm_sqr() + (w0 * w2.conj()).re) / 3.0,
            (w1 * w2.conj()).re,
            w2.norm_sqr(),
        ];
        Poly::from_bernstein(&b)
    }

    /// Bending energy ∫₀¹ κ² σ dt = ∫ (x′ × x″)² / σ⁵ dt (Gauss–Legendre, 10 points on
    /// each half of [0, 1]); +∞ at a singular point.
    pub fn bending_energy(&self) -> f64 {
        let (x, y) = self.polys();
        let (x1, y1) = (x.deriv(), y.deriv());
        let (x2, y2) = (x1.deriv(), y1.deriv());
        let mut e = 0.0;
        for (a, b) in [(0.0, 0.5), (0.5, 1.0)] {
            let h = 0.5 * (b - a);
            let m = 0.5 * (a + b);
            for k in 0..5 {
                for sg in [-1.0, 1.0] {
                    let t = m + sg * h * GL_X[k];
                    let d1 = DVec2::new(x1.eval(t), y1.eval(t));
                    let d2 = DVec2::new(x2.eval(t), y2.eval(t));
                    let s = d1.length();
                    if s == 0.0 {
                        return f64::INFINITY;
                    }
                    e += GL_W[k] * h * crate::geom::cross(d1, d2).powi(2) / s.powi(5);
                }
            }
        }
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn pt() -> impl Strategy<Value = DVec2> {
        (-5.0f64..5.0, -5.0f64..5.0).prop_map(|(x, y)| DVec2::new(x, y))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn hermite_interpolates_and_is_ph(p0 in pt(), p1 in pt(), d0 in pt(), d1 in pt()) {
            prop_assume!(d0.length() > 0.1 && d1.length() > 0.1 && (p1 - p0).length() > 0.1);
            let scale = 1.0 + p0.length() + p1.length() + d0.length() + d1.length();
            for q in PhQuintic::hermite_all(p0, d0, p1, d1) {
                let (x, y) = q.polys();
                let (x1, y1) = (x.deriv(), y.deriv());
                prop_assert!((DVec2::new(x.eval(1.0), y.eval(1.0)) - p1).length() < 1e-9 * scale);
                prop_assert!((DVec2::new(x1.eval(0.0), y1.eval(0.0)) - d0).length() < 1e-9 * scale);
                prop_assert!((DVec2::new(x1.eval(1.0), y1.eval(1.0)) - d1).length() < 1e-9 * scale);
                // Pythagorean hodograph on coefficients: x′² + y′² − σ² ≡ 0.
                let s = q.sigma();
                let lhs = x1.mul(&x1).add(&y1.mul(&y1));
                let diff = lhs.sub(&s.mul(&s));
                prop_assert!(diff.norm_inf() <= 1e-9 * lhs.norm_inf().max(1.0), "{:?}", diff);
            }
            if let Some(best) = PhQuintic::hermite(p0, d0, p1, d1) {
                let e = best.bending_energy();
                for q in PhQuintic::hermite_all(p0, d0, p1, d1) {
                    prop_assert!(e <= q.bending_energy() * (1.0 + 1e-12));
                }
            }
        }
    }

    #[test]
    fn straight_data_gives_straight_line() {
        // Collinear Hermite data: the least-energy PH quintic is the straight segment.
        let q = PhQuintic::hermite(
            DVec2::ZERO,
            DVec2::new(3.0, 0.0),
            DVec2::new(3.0, 0.0),
            DVec2::new(3.0, 0.0),
        )
        .unwrap();
        assert!(q.bending_energy() < 1e-20);
        for p in q.ctrl {
            assert!(p.y.abs() < 1e-14);
        }
    }
}
