//! Detection of intersections of the two envelopes of an RE curve
//! (re-mph-skinning-flexible Theorem 1 and Corollary 1): x⁺(t) = x⁻(t) iff x has a singular
//! point, f(t) = 0, or ȳ′(t) is light-like (‖y′‖² = r′²).

use super::poly::{Poly, cubic_roots_01};
use super::re_curve::ReCurve;
use super::skin::ReSkin;
use crate::geom::DVec2;

/// Floor of the scale of x″ in [`singular_points`], so a straight curve (x″ = 0) gets a
/// positive (tiny) threshold instead of zero.
const MIN_SCALE: f64 = 1e-300;

/// Which case of Corollary 1 an intersection comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntersectionKind {
    /// x′(t) = 0: x is irregular and x(t) is a singular point.
    SingularX,
    /// f(t) = 0 (so r(t) = 0).
    FZero,
    /// ‖y′(t)‖² − r′(t)² = 0: ȳ′ is light-like.
    LightLike,
}

/// One detected intersection of x⁺ and x⁻: segment, parameter and point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopeIntersection {
    /// Index of the segment (circle pair) in the skin.
    pub segment: usize,
    /// Which case of Corollary 1 it is.
    pub kind: IntersectionKind,
    /// Local parameter in [0, 1] on the segment.
    pub t: f64,
    /// The point x⁺(t) = x(t) where the envelopes meet.
    pub point: DVec2,
}

/// The polynomial μ(t) = ‖x′‖² + f · (x′ × x″). For an RE curve, in the frame
/// T = x′/‖x′‖, N = x′⊥/‖x′‖ one has y′·N = r′ and y′·T = μ/‖x′‖, hence
/// ‖y′‖² − r′² = μ² / ‖x′‖²: ȳ′ is never time-like, and it is light-like exactly at the
/// (simple) roots of μ, where y reaches the centre of curvature of x (f‖x′‖ = ρ).
pub fn light_like_factor(c: &ReCurve) -> Poly {
    let (x1, y1) = c.dx_polys();
    let x2 = x1.deriv();
    let y2 = y1.deriv();
    let cr = x1.mul(&y2).sub(&y1.mul(&x2));
    c.speed_sq().add(&c.f.mul(&cr))
}

/// The polynomial Λ(t) = ‖y′‖² ‖x′‖² − (f′‖x′‖² + f x′·x″)², which has the sign of
/// ‖y′‖² − r′² (r′ = (f′‖x′‖² + f x′·x″)/‖x′‖): its roots are the light-like points.
#[cfg(test)]
pub fn light_like_poly(c: &ReCurve) -> Poly {
    let (yx, yy) = c.dy_polys();
    let (x1, y1) = c.dx_polys();
    let s2 = c.speed_sq();
    let x2 = x1.deriv();
    let y2 = y1.deriv();
    let dot = x1.mul(&x2).add(&y1.mul(&y2));
    let rr = c.f.deriv().mul(&s2).add(&c.f.mul(&dot));
    yx.mul(&yx).add(&yy.mul(&yy)).mul(&s2).sub(&rr.mul(&rr))
}

/// Roots of f in [0, 1]: Cardano for a cubic (mph Sec. 4.1), Bernstein subdivision for
/// higher degree (the quartic of eqs. 18–19). `tol` is the parameter accuracy.
pub fn f_roots(f: &Poly, tol: f64) -> Vec<f64> {
    let deg = f.c.iter().rposition(|a| *a != 0.0).unwrap_or(0);
    if deg <= 3 {
        cubic_roots_01(f, tol)
    } else {
        f.roots_01(tol, tol * f.norm_inf())
    }
}

/// Singular points of x in [0, 1]: roots of x′ₓ at which |x′_y| ≤ `tol` · (scale of x″),
/// and vice versa (a polynomial x′ vanishes only where both components do).
pub fn singular_points(c: &ReCurve, tol: f64) -> Vec<f64> {
    let (x1, y1) = c.dx_polys();
    let scale = x1
        .deriv()
        .norm_inf()
        .max(y1.deriv().norm_inf())
        .max(MIN_SCALE);
    let mut out = Vec::new();
    let (a, b) = if x1.norm_inf() >= y1.norm_inf() {
        (x1, y1)
    } else {
        (y1, x1)
    };
    for t in a.roots_01(tol, 0.0) {
        if b.eval(t).abs() <= 10.0 * tol * scale {
            out.push(t);
        }
    }
    out
}

/// All intersections of x⁺ and x⁻ on one RE curve (Corollary 1), parameter accuracy `tol`.
pub fn detect_curve(c: &ReCurve, segment: usize, tol: f64) -> Vec<EnvelopeIntersection> {
    let mut out = Vec::new();
    let mut push = |kind, t: f64| {
        out.push(EnvelopeIntersection {
            segment,
            kind,
            t,
            point: c.x(t),
        });
    };
    let sing = singular_points(c, tol);
    for &t in &sing {
        push(IntersectionKind::SingularX, t);
    }
    for t in f_roots(&c.f, tol) {
        push(IntersectionKind::FZero, t);
    }
    if sing.is_empty() {
        // Λ = μ²: find the simple roots of μ instead of the double roots of Λ.
        let mu = light_like_factor(c);
        for t in mu.roots_01(tol, 0.0) {
            push(IntersectionKind::LightLike, t);
        }
    }
    out.sort_by(|a, b| a.t.total_cmp(&b.t));
    out
}

/// Intersections on every segment of a skin.
pub fn detect(skin: &ReSkin, tol: f64) -> Vec<EnvelopeIntersection> {
    skin.segments
        .iter()
        .enumerate()
        .flat_map(|(s, seg)| detect_curve(&seg.curve, s, tol))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::re_curve::{Branch, Interp};
    use super::*;

    fn curve(xx: Vec<f64>, xy: Vec<f64>, f: Vec<f64>) -> ReCurve {
        ReCurve::from_parts(
            Interp::Cubic,
            Poly::new(xx),
            Poly::new(xy),
            Poly::new(f),
            None,
        )
    }

    /// Theorem 1: at a detected parameter the two envelopes meet.
    fn envelopes_meet(c: &ReCurve, t: f64, tol: f64) {
        let fr = c.frame(t).unwrap();
        let a = fr.offset(Branch::Plus, 0.0).0;
        let b = fr.offset(Branch::Minus, 0.0).0;
        assert!((a - b).length() < tol, "t={t}: {a} vs {b}");
    }

    #[test]
    fn planted_f_roots_are_found_and_envelopes_meet() {
        // f = 0.5 (t − 0.3)(t − 0.7) − tiny: two simple roots near 0.3 and 0.7.
        let f = Poly::new(vec![0.105, -0.5, 0.5, 0.0]);
        let c = curve(
            vec![0.0, 4.0, 0.0, 0.0],
            vec![0.0, 0.0, 1.0, -1.0],
            f.c.clone(),
        );
        let hits = detect_curve(&c, 0, 1e-12);
        let fz: Vec<f64> = hits
            .iter()
            .filter(|h| h.kind == IntersectionKind::FZero)
            .map(|h| h.t)
            .collect();
        assert_eq!(fz.len(), 2);
        assert!((fz[0] - 0.3).abs() < 1e-10 && (fz[1] - 0.7).abs() < 1e-10);
        for t in fz {
            envelopes_meet(&c, t, 1e-9);
        }
    }

    #[test]
    fn planted_singular_point() {
        // x(t) = ((t − ½)³, (t − ½)²·(t − ½)·2) has x′(½) = 0.
        let x = Poly::new(vec![-0.125, 0.75, -1.5, 1.0]);
        let c = curve(x.c.clone(), x.scale(2.0).c, vec![0.2, 0.0, 0.0, 0.0]);
        let hits = detect_curve(&c, 3, 1e-10);
        assert!(
            hits.iter()
                .any(|h| h.kind == IntersectionKind::SingularX && (h.t - 0.5).abs() < 1e-4)
        );
        assert!(hits.iter().all(|h| h.segment == 3));
    }

    #[test]
    fn light_like_points_match_frame_sign_changes() {
        // x = (t, −t²) turns right (towards y) with curvature radius (1 + 4t²)^{3/2}/2;
        // ȳ′ is light-like where r = f‖x′‖ reaches it (y at the centre of curvature).
        let c = curve(
            vec![0.0, 1.0, 0.0, 0.0],
            vec![0.0, 0.0, -1.0, 0.0],
            vec![0.2, 4.0, -4.0, 0.0],
        );
        let hits = detect_curve(&c, 0, 1e-12);
        let ll: Vec<f64> = hits
            .iter()
            .filter(|h| h.kind == IntersectionKind::LightLike)
            .map(|h| h.t)
            .collect();
        // Λ = μ² on coefficients.
        let (lam, mu) = (light_like_poly(&c), light_like_factor(&c));
        assert!(lam.sub(&mu.mul(&mu)).norm_inf() < 1e-12 * lam.norm_inf());
        // Independent: sign changes of y′·x′ from the Frame (y′·x′ = μ), on a fine grid,
        // and ‖y′‖² − r′² ≥ 0 everywhere.
        let n = 4000;
        let mut changes = Vec::new();
        let mut prev = c.frame(0.0).unwrap().y1.dot(c.dx(0.0));
        for i in 1..=n {
            let t = i as f64 / n as f64;
            let fr = c.frame(t).unwrap();
            assert!(fr.space_like() >= -1e-12);
            let v = fr.y1.dot(fr.x1);
            if (v > 0.0) != (prev > 0.0) {
                changes.push(t);
            }
            prev = v;
        }
        assert!(
            !changes.is_empty(),
            "the planted case must have light-like points"
        );
        assert_eq!(ll.len(), changes.len(), "{ll:?} vs {changes:?}");
        for (a, b) in ll.iter().zip(&changes) {
            assert!((a - b).abs() <= 1.0 / n as f64);
            // At a light-like point the two envelope formulas coincide (Theorem 1).
            let p = c.envelope_eq16(Branch::Plus, *a).unwrap();
            let m = c.envelope_eq16(Branch::Minus, *a).unwrap();
            assert!((p - m).length() < 1e-9);
            envelopes_meet(&c, *a, 1e-9);
        }
    }

    #[test]
    fn clean_skin_has_no_intersections() {
        use super::super::skin::tests::{snake, test_touches};
        let cs = snake();
        let skin = ReSkin::build(&cs, &test_touches(&cs, &[]), false, Interp::Cubic, 1e-9).unwrap();
        assert!(
            detect(&skin, 1e-10).is_empty(),
            "{:?}",
            detect(&skin, 1e-10)
        );
    }
}
