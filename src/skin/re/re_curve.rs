//! One RE (or MPH) curve ȳ(t) = (y(t), r(t)) between two circles and its two envelopes
//! (re-skinning-cnc eqs. 1–5, 13; re-mph-skinning-flexible eqs. 4–7, 13–16).
//!
//! The planar curve x(t) interpolates the left touching points; the medial axis is the
//! one-sided offset y = x + f x′⊥ with r = f ‖x′‖ (mph eq. 4 / 7 / 15). Then x itself is the
//! left envelope x⁺ (y + r m⁺ with m⁺ = −x′⊥/‖x′‖), and the right envelope x⁻ is the mirror
//! image of x in the tangent line of y: the *rational envelope formula*
//! x⁻ = y + r m⁻, m⁻ = −m⁺ − 2 r′ y′ / ‖y′‖² (no square root: ‖y′‖² is a polynomial).

use super::cyclographic::{proj, rot_cw};
use super::mph::PhQuintic;
use super::poly::{Poly, mul_add_into};
use crate::geom::DVec2;
use glam::DVec3;

/// Which planar interpolant x(t) is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Interp {
    /// Cubic Hermite arc (RE skins, re-skinning-cnc Sec. 3.2).
    #[default]
    Cubic,
    /// PH quintic Hermite interpolant (MPH skins; rational offsets).
    PhQuintic,
}

/// Which envelope: `Plus` is x⁺ (left of the travel direction), `Minus` is x⁻.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Branch {
    /// x⁺ = y + r m⁺, the left envelope; it is the planar interpolant x itself.
    Plus,
    /// x⁻ = y + r m⁻, the right envelope: the mirror image of x⁺ in the tangent line of y.
    Minus,
}

/// Hermite data of one circle for a segment: cyclographic point p, tangent t (R^{2,1}),
/// left touching point w and planar tangent v.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndData {
    /// Cyclographic point p = (o, r) ∈ R^{2,1} of the circle.
    pub p: DVec3,
    /// Tangent vector of p in R^{2,1} (re-skinning-cnc eqs. 7–10 or mph eq. 11).
    pub t: DVec3,
    /// Left touching point w⁺ on the circle, where x passes.
    pub w: DVec2,
    /// Planar Hermite tangent of x at `w`, of length α = 2 dist(w, l) with l the radical line of
    /// the segment's circle pair (re-skinning-cnc eqs. 11–12).
    pub v: DVec2,
}

/// Everything about ȳ at one parameter: x and its derivatives, y, r and theirs, m±, m±′.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// x(t), the planar interpolant (= the left envelope x⁺).
    pub x: DVec2,
    /// x′(t).
    pub x1: DVec2,
    /// y(t) = x + f x′⊥, the planar MAT point (centre of the circle ȳ(t)).
    pub y: DVec2,
    /// y′(t).
    pub y1: DVec2,
    /// y″(t).
    pub y2: DVec2,
    /// r(t) = f ‖x′‖, the radius of the circle ȳ(t).
    pub r: f64,
    /// r′(t).
    pub r1: f64,
    /// r″(t).
    pub r2: f64,
    /// m⁺ = −x′⊥/‖x′‖: unit direction from y to the left envelope point.
    pub m_plus: DVec2,
    /// m⁻ = −m⁺ − 2r′y′/‖y′‖², the mirror image of m⁺ in the line along y′ (as m⁺·y′ = −r′):
    /// unit direction from y to the right envelope point.
    pub m_minus: DVec2,
    /// Derivative of m⁺ with respect to t.
    pub dm_plus: DVec2,
    /// Derivative of m⁻ with respect to t.
    pub dm_minus: DVec2,
}

/// Point y + (r + d) m and derivative y′ + r′m + (r + d) m′ of an offset curve
/// ([`Frame::offset`]).
fn offset_of(y: DVec2, y1: DVec2, r: f64, r1: f64, m: DVec2, dm: DVec2, d: f64) -> (DVec2, DVec2) {
    (y + (r + d) * m, y1 + r1 * m + (r + d) * dm)
}

/// The first-order part of a [`Frame`] ([`ReCurve::first_order`]), with x″, x′·x″, f, f′,
/// s, s′ and l = ‖y′‖² the rest of the frame is built from.
struct FirstOrder {
    x: DVec2,
    x1: DVec2,
    x2: DVec2,
    xx2: f64,
    f: f64,
    f1: f64,
    s: f64,
    s1: f64,
    y: DVec2,
    y1: DVec2,
    l: f64,
    r: f64,
    r1: f64,
    m_plus: DVec2,
    dm_plus: DVec2,
}

impl Frame {
    /// m⁺ or m⁻ for `b`.
    pub fn m(&self, b: Branch) -> DVec2 {
        match b {
            Branch::Plus => self.m_plus,
            Branch::Minus => self.m_minus,
        }
    }

    /// The derivative of m⁺ or m⁻ for `b`.
    pub fn dm(&self, b: Branch) -> DVec2 {
        match b {
            Branch::Plus => self.dm_plus,
            Branch::Minus => self.dm_minus,
        }
    }

    /// Point and derivative of the curve y + (r + d) m± (d = 0: envelope; d = −δ: inner
    /// MAT offset, re-skinning-cnc eq. 13; d = +δ: outer offset).
    pub fn offset(&self, b: Branch, d: f64) -> (DVec2, DVec2) {
        offset_of(self.y, self.y1, self.r, self.r1, self.m(b), self.dm(b), d)
    }

    /// ‖y′‖² − r′²: positive where ȳ′ is space-like (a real envelope exists).
    pub fn space_like(&self) -> f64 {
        self.y1.length_squared() - self.r1 * self.r1
    }
}

/// An RE curve: planar interpolant x = (xx, xy) and the polynomial f, power basis on [0, 1].
#[derive(Clone, Debug, PartialEq)]
pub struct ReCurve {
    /// The kind of planar interpolant.
    pub interp: Interp,
    /// x component of x(t).
    pub xx: Poly,
    /// y component of x(t).
    pub xy: Poly,
    /// f(t), with y = x + f x′⊥ and r = f ‖x′‖ (mph eq. 4); must be > 0 on [0, 1] for the envelopes
    /// not to cross.
    pub f: Poly,
    /// σ = ‖x′‖ as a polynomial when x is a PH quintic.
    pub sigma: Option<Poly>,
    d: [Poly; 6],
    df: [Poly; 2],
}

/// f boundary values (f̃₀, f̃₁, f̃′₀, f̃′₁) of mph eqs. 5–6 / 13–14.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FBoundary {
    /// f̃₀ = f(0) = p_z/‖v‖ at the first circle.
    pub f0: f64,
    /// f̃₁ = f(1) at the second circle.
    pub f1: f64,
    /// f̃′₀ = f′(0).
    pub df0: f64,
    /// f̃′₁ = f′(1).
    pub df1: f64,
}

impl FBoundary {
    /// The cubic Hermite f with these end values and derivatives.
    pub fn cubic(&self) -> Poly {
        self.quartic(0.0)
    }

    /// The quartic family of mph eqs. 18–19, f = k t⁴ + a₃t³ + a₂t² + f̃′₀ t + f̃₀ with
    /// a₃ = f̃′₀ + f̃′₁ + 2f̃₀ − 2f̃₁ − 2k, a₂ = 3f̃₁ − 3f̃₀ − 2f̃′₀ − f̃′₁ + k; i.e. the cubic
    /// Hermite f plus k t²(1 − t)². (The paper prints the leading term as t⁴ and f̃₀ for
    /// 2f̃₀ in a₃; with those, f(1) = 1 + f̃₁ − k, so the boundary conditions fail unless
    /// k = 1 — we use the corrected form, which satisfies (5)–(6) for every k.)
    pub fn quartic(&self, k: f64) -> Poly {
        let FBoundary { f0, f1, df0, df1 } = *self;
        Poly::new(vec![
            f0,
            df0,
            3.0 * f1 - 3.0 * f0 - 2.0 * df0 - df1 + k,
            df0 + df1 + 2.0 * f0 - 2.0 * f1 - 2.0 * k,
            k,
        ])
    }
}

fn d2(px: &Poly, py: &Poly, t: f64) -> DVec2 {
    DVec2::new(px.eval(t), py.eval(t))
}

impl ReCurve {
    /// From planar polynomials and f.
    pub fn from_parts(interp: Interp, xx: Poly, xy: Poly, f: Poly, sigma: Option<Poly>) -> Self {
        let x1 = xx.deriv();
        let y1 = xy.deriv();
        let x2 = x1.deriv();
        let y2 = y1.deriv();
        let x3 = x2.deriv();
        let y3 = y2.deriv();
        let f1 = f.deriv();
        let f2 = f1.deriv();
        ReCurve {
            interp,
            xx,
            xy,
            f,
            sigma,
            d: [x1, y1, x2, y2, x3, y3],
            df: [f1, f2],
        }
    }

    /// The planar interpolant of `a.w → b.w` with tangents `a.v`, `b.v` (cubic Hermite or
    /// PH quintic) and the boundary values of f from mph eqs. 5–6 / 13–14:
    /// f(i) = p_z/‖vᵢ‖, f′(i) = −tᵢ∇·(f(i) x″(i) − vᵢ⊥) / (tᵢ∇·vᵢ). `None` when the PH
    /// interpolant is singular, a tangent is zero or tᵢ∇·vᵢ = 0.
    pub fn planar_and_boundary(
        interp: Interp,
        a: &EndData,
        b: &EndData,
    ) -> Option<(Poly, Poly, Option<Poly>, FBoundary)> {
        match interp {
            Interp::Cubic => {
                let bx = [a.w.x, a.w.x + a.v.x / 3.0, b.w.x - b.v.x / 3.0, b.w.x];
                let by = [a.w.y, a.w.y + a.v.y / 3.0, b.w.y - b.v.y / 3.0, b.w.y];
                let (xx, xy) = (Poly::from_bernstein(&bx), Poly::from_bernstein(&by));
                let (fb, _) = ReCurve::boundary(&xx, &xy, a, b)?;
                Some((xx, xy, None, fb))
            }
            Interp::PhQuintic => {
                // Of the four PH interpolants, the least-energy one whose ȳ′ runs along
                // +tᵢ at both ends: with ȳ′ = λ t and λ < 0 at one end (a PH quintic can
                // bend hard near an end, and f x″ then outweighs x′) the MAT turns back at
                // the join and the minus envelope reverses there although the tangent line
                // is shared (proptest-regressions/skin/re/skin.txt, the `ph = true` case).
                let mut first = None;
                for q in PhQuintic::hermite_ranked(a.w, a.v, b.w, b.v) {
                    let (xx, xy) = q.polys();
                    let Some((fb, forward)) = ReCurve::boundary(&xx, &xy, a, b) else {
                        continue;
                    };
                    let cand = (xx, xy, Some(q.sigma()), fb);
                    if forward {
                        return Some(cand);
                    }
                    first.get_or_insert(cand);
                }
                first
            }
        }
    }

    /// The boundary values of f for the planar curve (xx, xy) (see
    /// [`ReCurve::planar_and_boundary`]) and whether ȳ′ = λ tᵢ has λ > 0 at both ends.
    fn boundary(xx: &Poly, xy: &Poly, a: &EndData, b: &EndData) -> Option<(FBoundary, bool)> {
        let x2 = (xx.deriv().deriv(), xy.deriv().deriv());
        let end = |e: &EndData, s: f64| -> Option<(f64, f64, bool)> {
            let vl = e.v.length();
            let tv = proj(e.t).dot(e.v);
            if vl.is_nan() || vl <= 0.0 || tv == 0.0 {
                return None;
            }
            let f = e.p.z / vl;
            let xpp = d2(&x2.0, &x2.1, s);
            let df = -proj(e.t).dot(f * xpp - rot_cw(e.v)) / tv;
            // ȳ′ = x′ + f′ x′⊥ + f x″⊥ (with ⊥ = rot_cw) against the planar part of tᵢ.
            let y1 = e.v + df * rot_cw(e.v) + f * rot_cw(xpp);
            Some((f, df, y1.dot(proj(e.t)) > 0.0))
        };
        let (f0, df0, fw0) = end(a, 0.0)?;
        let (f1, df1, fw1) = end(b, 1.0)?;
        Some((FBoundary { f0, f1, df0, df1 }, fw0 && fw1))
    }

    /// The RE curve with the cubic Hermite f (mph Sec. 3.2) or the quartic of eqs. 18–19
    /// when `k` is given.
    pub fn build(
        interp: Interp,
        a: &EndData,
        b: &EndData,
        k: Option<f64>,
    ) -> Option<(ReCurve, FBoundary)> {
        let (xx, xy, sigma, fb) = ReCurve::planar_and_boundary(interp, a, b)?;
        let f = match k {
            Some(k) => fb.quartic(k),
            None => fb.cubic(),
        };
        Some((ReCurve::from_parts(interp, xx, xy, f, sigma), fb))
    }

    /// The same planar curve with another f.
    pub fn with_f(&self, f: Poly) -> ReCurve {
        ReCurve::from_parts(
            self.interp,
            self.xx.clone(),
            self.xy.clone(),
            f,
            self.sigma.clone(),
        )
    }

    /// The planar interpolant x(t) (the left envelope).
    pub fn x(&self, t: f64) -> DVec2 {
        d2(&self.xx, &self.xy, t)
    }

    /// x′(t).
    pub fn dx(&self, t: f64) -> DVec2 {
        d2(&self.d[0], &self.d[1], t)
    }

    /// x′ as polynomials.
    pub fn dx_polys(&self) -> (&Poly, &Poly) {
        (&self.d[0], &self.d[1])
    }

    /// y′ = x′ + f′ x′⊥ + f x″⊥ as polynomials (mph eq. 4 differentiated).
    pub fn dy_polys(&self) -> (Poly, Poly) {
        let (x1, y1, x2, y2) = (&self.d[0], &self.d[1], &self.d[2], &self.d[3]);
        let f1 = &self.df[0];
        // v⊥ = (v_y, −v_x)
        let px = x1.add(&f1.mul(y1)).add(&self.f.mul(y2));
        let py = y1.sub(&f1.mul(x1)).sub(&self.f.mul(x2));
        (px, py)
    }

    /// ‖x′‖² as a polynomial.
    pub fn speed_sq(&self) -> Poly {
        self.d[0].mul(&self.d[0]).add(&self.d[1].mul(&self.d[1]))
    }

    /// r² = f² ‖x′‖² as a polynomial (r = f ‖x′‖): f·f times (x′ₓ·x′ₓ + x′ᵧ·x′ᵧ), the
    /// same operations in the same order as with [`Poly::mul`] and [`Poly::add`], with
    /// the three products on the stack when they fit.
    pub fn r_sq(&self) -> Poly {
        /// Coefficients of the stack buffers (degree ≤ 15: squares of quintics and below).
        const STACK: usize = 16;
        let (f, x, y) = (&self.f.c, &self.d[0].c, &self.d[1].c);
        let fits = |p: &[f64]| !p.is_empty() && 2 * p.len() - 1 <= STACK;
        if !(fits(f) && fits(x) && fits(y)) {
            return self.f.mul(&self.f).mul(&self.speed_sq());
        }
        let square = |p: &[f64]| {
            let mut out = [0.0; STACK];
            mul_add_into(p, p, &mut out);
            (out, 2 * p.len() - 1)
        };
        let ((f2, nf), (x2, nx), (y2, ny)) = (square(f), square(x), square(y));
        // Poly::add: the shorter operand's missing terms are 0.0 (the buffers' zeros).
        let ns = nx.max(ny);
        let mut s2 = [0.0; STACK];
        for (k, s) in s2.iter_mut().enumerate().take(ns) {
            *s = x2[k] + y2[k];
        }
        let mut c = vec![0.0; nf + ns - 1];
        mul_add_into(&f2[..nf], &s2[..ns], &mut c);
        Poly::new(c)
    }

    /// ȳ(t) = (x + f x′⊥, f‖x′‖) (re-skinning-cnc eq. 5, mph eq. 7).
    pub fn point(&self, t: f64) -> DVec3 {
        let x = self.x(t);
        let x1 = self.dx(t);
        let f = self.f.eval(t);
        let y = x + f * rot_cw(x1);
        DVec3::new(y.x, y.y, f * x1.length())
    }

    /// The full [`Frame`] at `t`. With s = ‖x′‖: y′ = x′ + f′x′⊥ + f x″⊥,
    /// y″ = x″ + f″x′⊥ + 2f′x″⊥ + f x‴⊥, r′ = f′s + f s′, r″ = f″s + 2f′s′ + f s″,
    /// s′ = x′·x″/s, s″ = (‖x″‖² + x′·x‴)/s − (x′·x″)²/s³; m⁺ = −x′⊥/s,
    /// m⁻ = −m⁺ − 2r′y′/‖y′‖² and their derivatives by the quotient rule.
    /// `None` at a singular point of x (s = 0) or where y′ = 0.
    pub fn frame(&self, t: f64) -> Option<Frame> {
        let o = self.first_order(t)?;
        let (x1, x2, xx2, s, s1) = (o.x1, o.x2, o.xx2, o.s, o.s1);
        let (f, f1, y1, r1, l) = (o.f, o.f1, o.y1, o.r1, o.l);
        let x3 = d2(&self.d[4], &self.d[5], t);
        let f2 = self.df[1].eval(t);
        let s2 = (x2.length_squared() + x1.dot(x3)) / s - xx2 * xx2 / (s * s * s);
        let y2 = x2 + f2 * rot_cw(x1) + 2.0 * f1 * rot_cw(x2) + f * rot_cw(x3);
        let r2 = f2 * s + 2.0 * f1 * s1 + f * s2;
        let m_minus = -o.m_plus - 2.0 * r1 * y1 / l;
        let dl = 2.0 * y1.dot(y2);
        let dm_minus = -o.dm_plus - 2.0 * ((r2 * y1 + r1 * y2) * l - r1 * y1 * dl) / (l * l);
        Some(Frame {
            x: o.x,
            x1,
            y: o.y,
            y1,
            y2,
            r: o.r,
            r1,
            r2,
            m_plus: o.m_plus,
            m_minus,
            dm_plus: o.dm_plus,
            dm_minus,
        })
    }

    /// The part of [`ReCurve::frame`] that needs x″ but not x‴: all that m⁺ and its
    /// derivative need. `None` where [`ReCurve::frame`] is.
    fn first_order(&self, t: f64) -> Option<FirstOrder> {
        let x = self.x(t);
        let x1 = d2(&self.d[0], &self.d[1], t);
        let x2 = d2(&self.d[2], &self.d[3], t);
        let f = self.f.eval(t);
        let f1 = self.df[0].eval(t);
        let s = x1.length();
        if s.is_nan() || s <= 0.0 {
            return None;
        }
        let xx2 = x1.dot(x2);
        let s1 = xx2 / s;
        let y1 = x1 + f1 * rot_cw(x1) + f * rot_cw(x2);
        let l = y1.length_squared();
        if l.is_nan() || l <= 0.0 {
            return None;
        }
        Some(FirstOrder {
            x,
            x1,
            x2,
            xx2,
            f,
            f1,
            s,
            s1,
            y: x + f * rot_cw(x1),
            y1,
            l,
            r: f * s,
            r1: f1 * s + f * s1,
            m_plus: -rot_cw(x1) / s,
            dm_plus: -(rot_cw(x2) * s - rot_cw(x1) * s1) / (s * s),
        })
    }

    /// Point and derivative of y + (r + d) m± at `t` ([`Frame::offset`]): what
    /// `self.frame(t).map(|fr| fr.offset(b, d))` gives, bit for bit, without the second
    /// derivatives on the + branch, whose m⁺′ needs only x″ (sampling offsets evaluates
    /// this at every sample).
    pub fn offset_at(&self, b: Branch, d: f64, t: f64) -> Option<(DVec2, DVec2)> {
        match b {
            Branch::Plus => {
                let o = self.first_order(t)?;
                Some(offset_of(o.y, o.y1, o.r, o.r1, o.m_plus, o.dm_plus, d))
            }
            Branch::Minus => self.frame(t).map(|fr| fr.offset(b, d)),
        }
    }

    /// Only the point y + (r + d) m± of [`Frame::offset`], without second derivatives
    /// (cheaper, for fitting and sampling). `None` where x′ = 0 or y′ = 0.
    pub fn offset_point(&self, b: Branch, d: f64, t: f64) -> Option<DVec2> {
        let x = self.x(t);
        let x1 = d2(&self.d[0], &self.d[1], t);
        let x2 = d2(&self.d[2], &self.d[3], t);
        let f = self.f.eval(t);
        let f1 = self.df[0].eval(t);
        let s = x1.length();
        if s.is_nan() || s <= 0.0 {
            return None;
        }
        let y = x + f * rot_cw(x1);
        let r = f * s;
        let m_plus = -rot_cw(x1) / s;
        let m = match b {
            Branch::Plus => m_plus,
            Branch::Minus => {
                let y1 = x1 + f1 * rot_cw(x1) + f * rot_cw(x2);
                let l = y1.length_squared();
                if l.is_nan() || l <= 0.0 {
                    return None;
                }
                let r1 = f1 * s + f * x1.dot(x2) / s;
                -m_plus - 2.0 * r1 * y1 / l
            }
        };
        Some(y + (r + d) * m)
    }

    /// Envelope point by the rational formula: x⁺ = x(t), x⁻ = y + r m⁻ (mirror image of
    /// x in the tangent line of y).
    pub fn envelope(&self, b: Branch, t: f64) -> Option<DVec2> {
        self.frame(t).map(|fr| fr.offset(b, 0.0).0)
    }

    /// Envelope point by the general envelope formula (re-skinning-cnc eq. 1, mph eq. 16):
    /// x± = y − r (r′y′ ± y′⊥ √(‖y′‖² − r′²)) / ‖y′‖². `None` where ȳ′ is not space-like.
    pub fn envelope_eq16(&self, b: Branch, t: f64) -> Option<DVec2> {
        let fr = self.frame(t)?;
        let l = fr.y1.length_squared();
        // Rounding makes ‖y′‖² − r′² slightly negative at light-like points: accept a
        // deficit of a few ulps of ‖y′‖² (ROUNDING_SLACK) as zero.
        const ROUNDING_SLACK: f64 = 1e-12;
        let mut disc = l - fr.r1 * fr.r1;
        if disc < 0.0 && disc >= -ROUNDING_SLACK * l {
            disc = 0.0;
        }
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let sg = match b {
            Branch::Plus => 1.0,
            Branch::Minus => -1.0,
        };
        Some(fr.y - fr.r * (fr.r1 * fr.y1 + sg * rot_cw(fr.y1) * disc.sqrt()) / l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_curve(interp: Interp, k: Option<f64>) -> ReCurve {
        let a = EndData {
            p: DVec3::new(0.0, 0.0, 1.0),
            t: DVec3::new(1.0, 0.1, -0.2),
            w: DVec2::ZERO,
            v: DVec2::ZERO,
        };
        let b = EndData {
            p: DVec3::new(4.0, 1.0, 0.7),
            t: DVec3::new(1.0, -0.3, 0.1),
            w: DVec2::ZERO,
            v: DVec2::ZERO,
        };
        let fix = |e: EndData, tang: DVec2| {
            let (wp, _) = super::super::cyclographic::touching_points(e.p, e.t).unwrap();
            EndData {
                w: wp,
                v: tang.length() * rot_cw(wp - proj(e.p)).normalize(),
                ..e
            }
        };
        let a = fix(a, DVec2::new(4.0, 0.0));
        let b = fix(b, DVec2::new(4.0, 0.0));
        ReCurve::build(interp, &a, &b, k).unwrap().0
    }

    #[test]
    fn frame_derivatives_match_finite_differences() {
        for interp in [Interp::Cubic, Interp::PhQuintic] {
            for k in [None, Some(2.0)] {
                let c = sample_curve(interp, k);
                let h = 1e-6;
                for i in 1..10 {
                    let t = i as f64 / 10.0;
                    let (a, b, fr) = (
                        c.frame(t - h).unwrap(),
                        c.frame(t + h).unwrap(),
                        c.frame(t).unwrap(),
                    );
                    let fd = |p: DVec2, q: DVec2| (q - p) / (2.0 * h);
                    assert!((fd(a.y, b.y) - fr.y1).length() < 1e-6);
                    assert!((fd(a.y1, b.y1) - fr.y2).length() < 1e-6);
                    assert!(((b.r - a.r) / (2.0 * h) - fr.r1).abs() < 1e-6);
                    assert!(((b.r1 - a.r1) / (2.0 * h) - fr.r2).abs() < 1e-6);
                    assert!((fd(a.m_plus, b.m_plus) - fr.dm_plus).length() < 1e-6);
                    assert!((fd(a.m_minus, b.m_minus) - fr.dm_minus).length() < 1e-6);
                    // ‖m±‖ = 1 and m±·y′ = −r′.
                    for br in [Branch::Plus, Branch::Minus] {
                        let m = fr.m(br);
                        assert!((m.length() - 1.0).abs() < 1e-12);
                        assert!((m.dot(fr.y1) + fr.r1).abs() < 1e-10 * (1.0 + fr.y1.length()));
                    }
                }
            }
        }
    }

    #[test]
    fn offset_at_is_the_frames_offset_bit_for_bit() {
        for interp in [Interp::Cubic, Interp::PhQuintic] {
            for k in [None, Some(2.0)] {
                let c = sample_curve(interp, k);
                for i in 0..=40 {
                    let t = i as f64 / 40.0;
                    for b in [Branch::Plus, Branch::Minus] {
                        for d in [-0.3, 0.0, 0.45] {
                            let want = c.frame(t).map(|fr| fr.offset(b, d));
                            let bits = |v: Option<(DVec2, DVec2)>| {
                                v.map(|(p, q)| [p.x, p.y, q.x, q.y].map(f64::to_bits))
                            };
                            assert_eq!(bits(c.offset_at(b, d, t)), bits(want), "t {t} {b:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn r_sq_is_the_polynomial_product_bit_for_bit_and_r_squared() {
        for interp in [Interp::Cubic, Interp::PhQuintic] {
            for k in [None, Some(2.0)] {
                let c = sample_curve(interp, k);
                let r2 = c.r_sq();
                let by_polys = c.f.mul(&c.f).mul(&c.speed_sq());
                let bits = |p: &Poly| p.c.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&r2), bits(&by_polys));
                for t in [0.0, 0.3, 0.77, 1.0] {
                    let r = c.frame(t).unwrap().r;
                    assert!((r2.eval(t) - r * r).abs() < 1e-12 * (1.0 + r * r));
                }
            }
        }
    }

    #[test]
    fn rational_envelope_equals_eq16() {
        for interp in [Interp::Cubic, Interp::PhQuintic] {
            let c = sample_curve(interp, None);
            for i in 0..=20 {
                let t = i as f64 / 20.0;
                for br in [Branch::Plus, Branch::Minus] {
                    let a = c.envelope(br, t).unwrap();
                    let b = c.envelope_eq16(br, t).unwrap();
                    assert!((a - b).length() < 1e-10, "{interp:?} {br:?} t={t}");
                }
                assert!((c.envelope(Branch::Plus, t).unwrap() - c.x(t)).length() < 1e-14);
                for br in [Branch::Plus, Branch::Minus] {
                    let fr = c.frame(t).unwrap();
                    let a = c.offset_point(br, -0.3, t).unwrap();
                    assert!((a - fr.offset(br, -0.3).0).length() < 1e-13);
                }
            }
        }
    }

    #[test]
    fn quartic_family_keeps_boundary_conditions() {
        let fb = FBoundary {
            f0: 0.3,
            f1: 0.8,
            df0: -1.5,
            df1: 2.0,
        };
        for k in [-3.0, 0.0, 1.0, 7.5] {
            let f = fb.quartic(k);
            let df = f.deriv();
            assert!((f.eval(0.0) - 0.3).abs() < 1e-14);
            assert!((f.eval(1.0) - 0.8).abs() < 1e-13);
            assert!((df.eval(0.0) + 1.5).abs() < 1e-14);
            assert!((df.eval(1.0) - 2.0).abs() < 1e-13);
            // f_k − f_0 = k t²(1 − t)².
            let t = 0.37;
            assert!(
                (f.eval(t) - fb.cubic().eval(t) - k * t * t * (1.0 - t) * (1.0 - t)).abs() < 1e-13
            );
        }
    }
}
