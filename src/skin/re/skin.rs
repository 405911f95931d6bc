//! RE / MPH skins of a circle sequence (re-skinning-cnc Sec. 3; re-mph-skinning-flexible
//! Algorithm 1 with the per-circle "combined" choice of Sec. 3.2).
//!
//! Input: circles and, per circle, its touching point(s) ([`Touch`]). Output: one
//! [`ReCurve`] per consecutive pair (and the closing pair for closed sequences).

use super::ReError;
use super::cyclographic::{cyclographic, touching_points};
use super::re_curve::{Branch, EndData, FBoundary, Interp, ReCurve};
use super::tangents::{Touch, hermite_tangent, tangent_for};
use crate::geom::{Circle, DVec2};
use glam::DVec3;
use std::sync::Arc;

/// The RE curve between circles `i` and `j` with its f boundary data and the quartic
/// parameter k when f was raised to degree 4 (mph eqs. 18–19).
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Index of the first circle of the pair.
    pub i: usize,
    /// Index of the second circle (i + 1, or 0 for the closing segment of a closed skin).
    pub j: usize,
    /// The RE/MPH curve from circle `i` (t = 0) to circle `j` (t = 1), shared with the
    /// offsets made from the skin ([`crate::skin::mat_offset::MatOffset::curves`]).
    pub curve: Arc<ReCurve>,
    /// Boundary values of f, kept to rebuild f with another k ([`ReSkin::set_k`]).
    pub boundary: FBoundary,
    /// The quartic parameter k of mph eqs. 18–19, `None` for the cubic Hermite f.
    pub k: Option<f64>,
}

/// An RE/MPH skin: both envelopes of a spline of RE curves.
#[derive(Clone, Debug, PartialEq)]
pub struct ReSkin {
    /// The circles, in order.
    pub circles: Vec<Circle>,
    /// Touching-point data per circle.
    pub touches: Vec<Touch>,
    /// Tangent vectors tᵢ ∈ R^{2,1} (eqs. 7–10 or mph eq. 11).
    pub tangents: Vec<DVec3>,
    /// One segment per consecutive circle pair.
    pub segments: Vec<Segment>,
    /// Whether the last circle is joined to the first.
    pub closed: bool,
    /// The planar interpolant of every segment: cubic (RE) or PH quintic (MPH).
    pub interp: Interp,
}

/// Circle pairs (i, j) joined by segments.
pub fn pairs(n: usize, closed: bool) -> Vec<(usize, usize)> {
    let mut v: Vec<(usize, usize)> = (0..n.saturating_sub(1)).map(|i| (i, i + 1)).collect();
    if closed && n >= 3 {
        v.push((n - 1, 0));
    }
    v
}

impl ReSkin {
    /// Builds the skin. `touch_tol` is how far (model units) a given touching point may be
    /// from its circle. Errors name the circle or the pair.
    pub fn build(
        circles: &[Circle],
        touches: &[Touch],
        closed: bool,
        interp: Interp,
        touch_tol: f64,
    ) -> Result<ReSkin, ReError> {
        let n = circles.len();
        if n < 2 {
            return Err(ReError::TooFewCircles(n));
        }
        if touches.len() != n {
            return Err(ReError::TouchCount {
                touches: touches.len(),
                circles: n,
            });
        }
        for (index, c) in circles.iter().enumerate() {
            if !(c.c.x.is_finite() && c.c.y.is_finite() && c.r.is_finite() && c.r > 0.0) {
                return Err(ReError::BadCircle { index });
            }
        }
        let tangents = circles
            .iter()
            .zip(touches)
            .enumerate()
            .map(|(i, (c, t))| tangent_for(c, i, t, touch_tol))
            .collect::<Result<Vec<_>, _>>()?;
        let mut skin = ReSkin {
            circles: circles.to_vec(),
            touches: touches.to_vec(),
            tangents,
            segments: Vec::new(),
            closed,
            interp,
        };
        for (i, j) in pairs(n, closed) {
            let seg = skin.make_segment(i, j, None)?;
            skin.segments.push(seg);
        }
        Ok(skin)
    }

    /// Hermite data of circle `c` for the pair (`i`, `j`).
    pub fn end_data(&self, c: usize, i: usize, j: usize) -> Result<EndData, ReError> {
        let (Some(ci), Some(cj), Some(cc), Some(touch), Some(&t)) = (
            self.circles.get(i),
            self.circles.get(j),
            self.circles.get(c),
            self.touches.get(c),
            self.tangents.get(c),
        ) else {
            return Err(ReError::BadIndex { index: c });
        };
        let w = touch.plus();
        let v = hermite_tangent(cc, w, ci, cj).ok_or(ReError::Concentric { i, j })?;
        if v.length().is_nan() || v.length() <= 0.0 {
            return Err(ReError::ZeroTangent { i, j });
        }
        Ok(EndData {
            p: cyclographic(cc),
            t,
            w,
            v,
        })
    }

    /// Builds the segment of pair (`i`, `j`) with the cubic f, or the quartic with `k`.
    pub fn make_segment(&self, i: usize, j: usize, k: Option<f64>) -> Result<Segment, ReError> {
        let a = self.end_data(i, i, j)?;
        let b = self.end_data(j, i, j)?;
        let (curve, boundary) =
            ReCurve::build(self.interp, &a, &b, k).ok_or(ReError::Degenerate { i, j })?;
        Ok(Segment {
            i,
            j,
            curve: Arc::new(curve),
            boundary,
            k,
        })
    }

    /// The right touching point W⁻ of circle `c` implied by its tangent (eq. 2).
    pub fn minus_point(&self, c: usize) -> Option<DVec2> {
        let (circle, t) = (self.circles.get(c)?, self.tangents.get(c)?);
        touching_points(cyclographic(circle), *t).map(|q| q.1)
    }

    /// Sets the free parameter u of a [`Touch::Flexible`] circle and rebuilds the segments
    /// that use it (keeping their k).
    pub fn set_u(&mut self, c: usize, u: f64) -> Result<(), ReError> {
        let Some(Touch::Flexible { plus, .. }) = self.touches.get(c).copied() else {
            return Err(ReError::NotFlexible { index: c });
        };
        let touch = Touch::Flexible { plus, u };
        let circle = *self.circles.get(c).ok_or(ReError::BadIndex { index: c })?;
        let t = tangent_for(&circle, c, &touch, f64::INFINITY)?;
        if c >= self.tangents.len() {
            return Err(ReError::BadIndex { index: c });
        }
        self.touches[c] = touch;
        self.tangents[c] = t;
        for s in 0..self.segments.len() {
            let (i, j, k) = (self.segments[s].i, self.segments[s].j, self.segments[s].k);
            if i == c || j == c {
                self.segments[s] = self.make_segment(i, j, k)?;
            }
        }
        Ok(())
    }

    /// Replaces f of segment `s` by the quartic with parameter `k` (mph eqs. 18–19).
    pub fn set_k(&mut self, s: usize, k: Option<f64>) -> Result<(), ReError> {
        let seg = self.segments.get(s).ok_or(ReError::BadIndex { index: s })?;
        let f = match k {
            Some(k) => seg.boundary.quartic(k),
            None => seg.boundary.cubic(),
        };
        let curve = seg.curve.with_f(f);
        self.segments[s].curve = Arc::new(curve);
        self.segments[s].k = k;
        Ok(())
    }

    /// Envelope point of `branch` on segment `s` at local parameter `t` ∈ [0, 1].
    pub fn envelope(&self, s: usize, branch: Branch, t: f64) -> Option<DVec2> {
        self.segments.get(s)?.curve.envelope(branch, t)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::re_curve::Frame;
    use super::*;

    /// Relative size of τ = x±′·y′ below which a join counts as a cusp in the G1 test.
    const TAU_CLEAR: f64 = 1e-3;
    use proptest::prelude::*;

    /// Touching points for a test sequence: the envelope directions of the circles moving
    /// along the Catmull–Rom direction dᵢ of the centres with radius slope ρᵢ:
    /// m± = −ρ d ± √(1 − ρ²) d⊥ (the touching points of a smooth tangent curve family).
    pub fn test_touches(circles: &[Circle], flexible: &[bool]) -> Vec<Touch> {
        let n = circles.len();
        (0..n)
            .map(|i| {
                let a = circles[i.saturating_sub(1)];
                let b = circles[(i + 1).min(n - 1)];
                let d = b.c - a.c;
                let rho = ((b.r - a.r) / d.length()).clamp(-0.9, 0.9);
                let u = d.normalize();
                let left = DVec2::new(-u.y, u.x);
                let c = circles[i];
                let q = (1.0 - rho * rho).sqrt();
                let plus = c.c + c.r * (-rho * u + q * left);
                let minus = c.c + c.r * (-rho * u - q * left);
                if flexible.get(i).copied().unwrap_or(false) {
                    Touch::Flexible { plus, u: 1.3 }
                } else {
                    Touch::Fixed { plus, minus }
                }
            })
            .collect()
    }

    pub fn snake() -> Vec<Circle> {
        vec![
            Circle::new(DVec2::new(0.0, 0.0), 1.0),
            Circle::new(DVec2::new(3.0, 1.0), 1.4),
            Circle::new(DVec2::new(6.0, 0.5), 0.8),
            Circle::new(DVec2::new(8.5, -1.5), 1.1),
            Circle::new(DVec2::new(11.0, -1.0), 0.6),
        ]
    }

    pub fn transform(
        circles: &[Circle],
        rot: f64,
        scale: f64,
        shift: DVec2,
        reverse: bool,
    ) -> Vec<Circle> {
        let (s, c) = rot.sin_cos();
        let mut v: Vec<Circle> = circles
            .iter()
            .map(|k| {
                let p = DVec2::new(c * k.c.x - s * k.c.y, s * k.c.x + c * k.c.y) * scale + shift;
                Circle::new(p, k.r * scale)
            })
            .collect();
        if reverse {
            v.reverse();
        }
        v
    }

    fn check_skin(skin: &ReSkin) {
        check_skin_with(skin, true);
    }

    /// `directions`: also require the envelope to keep its direction across joins where τ
    /// is clearly positive on both sides. Known gap: on PH-quintic chains with steep radius
    /// changes (see proptest-regressions/skin/re/skin.txt, the `ph = true` case) the minus
    /// envelope reverses at a join although the tangent line is shared; the random test
    /// checks the shared tangent line there but not the direction.
    fn check_skin_with(skin: &ReSkin, directions: bool) {
        let scale = skin
            .circles
            .iter()
            .fold(1.0f64, |m, c| m.max(c.c.length() + c.r));
        let tol = 1e-9 * scale;
        for seg in &skin.segments {
            for (end, c) in [(0.0, seg.i), (1.0, seg.j)] {
                let circle = skin.circles[c];
                let fr: Frame = seg.curve.frame(end).unwrap();
                // ȳ interpolates the cyclographic point.
                let p = seg.curve.point(end);
                assert!(
                    (p - cyclographic(&circle)).length() < tol,
                    "{p} vs {circle:?}"
                );
                // ȳ′ ∥ tᵢ.
                let yb = DVec3::new(fr.y1.x, fr.y1.y, fr.r1);
                let t = skin.tangents[c];
                assert!(yb.cross(t).length() <= 1e-9 * yb.length() * t.length());
                // Envelopes touch at the prescribed points, tangent to the circle.
                let wp = skin.touches[c].plus();
                let wm = match skin.touches[c] {
                    Touch::Fixed { minus, .. } => minus,
                    Touch::Flexible { .. } => skin.minus_point(c).unwrap(),
                };
                for (br, w) in [(Branch::Plus, wp), (Branch::Minus, wm)] {
                    let (q, dq) = fr.offset(br, 0.0);
                    assert!((q - w).length() < tol, "{br:?} {q} vs {w}");
                    assert!(dq.dot(w - circle.c).abs() <= 1e-9 * dq.length() * circle.r);
                }
                // Tangent vectors are space-like.
                assert!(super::super::cyclographic::minkowski_sq(t) > 0.0);
            }
        }
        // G1 across circles on both sides: unit tangents agree.
        for w in skin.segments.windows(2) {
            let a = w[0].curve.frame(1.0).unwrap();
            let b = w[1].curve.frame(0.0).unwrap();
            for br in [Branch::Plus, Branch::Minus] {
                let (pa, da) = a.offset(br, 0.0);
                let (pb, db) = b.offset(br, 0.0);
                assert!((pa - pb).length() < tol);
                // Same tangent line; same direction unless the envelope has a cusp at the
                // join (τ = x±′·y′ changes sign there: a local loop, reported elsewhere).
                let (ua, ub) = (da.normalize(), db.normalize());
                assert!(crate::geom::cross(ua, ub).abs() < 1e-9, "{br:?} {da} {db}");
                // τ within rounding of 0 is a cusp at the join, where the envelope's direction
                // is undefined: compare directions only where τ is clearly positive.
                let clearly = |d: DVec2, y: DVec2| d.dot(y) > TAU_CLEAR * d.length() * y.length();
                if directions && clearly(da, a.y1) && clearly(db, b.y1) {
                    assert!((ua - ub).length() < 1e-9, "{br:?} {da} {db}");
                }
            }
        }
    }

    #[test]
    fn snake_skin_touches_and_is_g1() {
        for interp in [Interp::Cubic, Interp::PhQuintic] {
            for (rot, scale, rev) in [(0.0, 1.0, false), (0.7, 3.0, false), (-2.0, 0.05, true)] {
                let cs = transform(&snake(), rot, scale, DVec2::new(5.0, -3.0), rev);
                for flex in [vec![], vec![false, true, false, true, true]] {
                    let touches = test_touches(&cs, &flex);
                    let skin = ReSkin::build(&cs, &touches, false, interp, 1e-9).unwrap();
                    check_skin(&skin);
                }
            }
        }
    }

    #[test]
    fn closed_sequence_has_closing_segment() {
        let cs: Vec<Circle> = (0..6)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 6.0;
                Circle::new(
                    5.0 * DVec2::new(a.cos(), a.sin()),
                    1.0 + 0.2 * (k % 2) as f64,
                )
            })
            .collect();
        // Touching points on the outer/inner side of a ring travelled counter-clockwise.
        let touches: Vec<Touch> = cs
            .iter()
            .map(|c| {
                let n = c.c.normalize();
                Touch::Fixed {
                    plus: c.c - c.r * n,
                    minus: c.c + c.r * n,
                }
            })
            .collect();
        let skin = ReSkin::build(&cs, &touches, true, Interp::Cubic, 1e-9).unwrap();
        assert_eq!(skin.segments.len(), 6);
        check_skin(&skin);
    }

    #[test]
    fn errors_name_the_circle() {
        let cs = snake();
        let mut touches = test_touches(&cs, &[]);
        touches[2] = Touch::Fixed {
            plus: DVec2::new(100.0, 0.0),
            minus: cs[2].c + DVec2::Y * 0.8,
        };
        assert!(matches!(
            ReSkin::build(&cs, &touches, false, Interp::Cubic, 1e-9),
            Err(ReError::TouchOffCircle { index: 2, .. })
        ));
        assert!(matches!(
            ReSkin::build(&cs[..1], &touches[..1], false, Interp::Cubic, 1e-9),
            Err(ReError::TooFewCircles(1))
        ));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn random_chains_touch_exactly(
            steps in proptest::collection::vec((-0.6f64..0.6, 2.0f64..4.0, 0.5f64..1.5), 2..6),
            flex in proptest::collection::vec(any::<bool>(), 6),
            ph in any::<bool>(),
        ) {
            let mut cs = vec![Circle::new(DVec2::ZERO, 1.0)];
            let mut ang: f64 = 0.0;
            for (da, len, r) in steps {
                ang += da;
                let last = cs.last().unwrap().c;
                cs.push(Circle::new(last + len * DVec2::new(ang.cos(), ang.sin()), r));
            }
            let touches = test_touches(&cs, &flex);
            let interp = if ph { Interp::PhQuintic } else { Interp::Cubic };
            let skin = ReSkin::build(&cs, &touches, false, interp, 1e-9).unwrap();
            let _ = ph;
            check_skin_with(&skin, true);
        }
    }
}
