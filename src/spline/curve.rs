//! The B-spline curve type: evaluation (de Boor), derivatives, knot insertion, splitting.

use super::basis::{find_span, with_basis_funs, with_ders_basis_funs};
use super::knots;
use super::{SplineError, Vector};

/// A B-spline curve C(t) = Σ N_{i,p}(t) P_i with control values of type `P`.
///
/// `closed` curves are stored unclamped with wrapped control values (see the module docs);
/// evaluation wraps t into the domain.
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline<P> {
    degree: usize,
    knots: Vec<f64>,
    ctrl: Vec<P>,
    closed: bool,
}

impl<P: Vector> BSpline<P> {
    /// A curve from explicit knots (n_ctrl + degree + 1 of them, non-decreasing).
    pub fn new(degree: usize, knots: Vec<f64>, ctrl: Vec<P>) -> Result<Self, SplineError> {
        knots::validate(&knots, degree, ctrl.len())?;
        Ok(BSpline {
            degree,
            knots,
            ctrl,
            closed: false,
        })
    }

    /// An open curve on clamped uniform knots over [0, 1].
    pub fn clamped_uniform(degree: usize, ctrl: Vec<P>) -> Result<Self, SplineError> {
        check_count(degree, ctrl.len(), degree + 1)?;
        Self::new(degree, knots::clamped_uniform(degree, ctrl.len()), ctrl)
    }

    /// A closed curve through the cyclic control values `ctrl` (not repeated by the caller)
    /// on uniform periodic knots over [0, 1].
    pub fn closed_uniform(degree: usize, ctrl: Vec<P>) -> Result<Self, SplineError> {
        check_count(degree, ctrl.len(), degree + 1)?;
        let n = ctrl.len();
        let breaks: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
        Self::closed_with_breaks(degree, ctrl, &breaks)
    }

    /// A closed curve with the period's breakpoints u_0 < … < u_n given (n = ctrl.len()).
    pub fn closed_with_breaks(
        degree: usize,
        ctrl: Vec<P>,
        breaks: &[f64],
    ) -> Result<Self, SplineError> {
        check_count(degree, ctrl.len(), degree + 1)?;
        if breaks.len() != ctrl.len() + 1 {
            return Err(SplineError::KnotCount {
                got: breaks.len(),
                expected: ctrl.len() + 1,
            });
        }
        for (i, w) in breaks.windows(2).enumerate() {
            if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                return Err(SplineError::KnotDecreasing {
                    index: i + 1,
                    prev: w[0],
                    next: w[1],
                });
            }
        }
        let mut wrapped = ctrl.clone();
        for i in 0..degree {
            wrapped.push(ctrl[i % ctrl.len()]);
        }
        let k = knots::periodic_from_breaks(degree, breaks);
        let mut c = Self::new(degree, k, wrapped)?;
        c.closed = true;
        Ok(c)
    }

    /// The degree p.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knot vector u_0..u_m (m = n + p + 1).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// All stored control values (for closed curves, including the p wrapped copies).
    pub fn ctrl(&self) -> &[P] {
        &self.ctrl
    }

    /// True for a closed (periodic) curve.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// The parameter domain [u_p, u_{n+1}].
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.ctrl.len()])
    }

    /// The distinct knot values inside the domain, ends included: the span boundaries.
    pub fn breakpoints(&self) -> Vec<f64> {
        let (lo, hi) = self.domain();
        let mut out: Vec<f64> = Vec::new();
        for &k in &self.knots[self.degree..=self.ctrl.len()] {
            if k >= lo && k <= hi && out.last() != Some(&k) {
                out.push(k);
            }
        }
        out
    }

    /// `t` mapped into the domain: wrapped for closed curves, clamped for open ones.
    pub fn wrap(&self, t: f64) -> f64 {
        let (lo, hi) = self.domain();
        if self.closed {
            if t >= lo && t <= hi {
                t
            } else {
                lo + (t - lo).rem_euclid(hi - lo)
            }
        } else {
            t.clamp(lo, hi)
        }
    }

    /// The point C(t) (de Boor via the non-zero basis functions).
    pub fn eval(&self, t: f64) -> P {
        let t = self.wrap(t);
        let span = find_span(&self.knots, self.degree, self.ctrl.len(), t);
        with_basis_funs(&self.knots, self.degree, span, t, |n| {
            let mut acc = P::ZERO;
            for (j, nj) in n.iter().enumerate() {
                acc = acc + self.ctrl[span - self.degree + j] * *nj;
            }
            acc
        })
    }

    /// C(t), C′(t), …, C^{(k)}(t) (P&T A3.2). Orders above the degree are zero.
    pub fn derivs(&self, t: f64, k: usize) -> Vec<P> {
        let t = self.wrap(t);
        let span = find_span(&self.knots, self.degree, self.ctrl.len(), t);
        with_ders_basis_funs(&self.knots, self.degree, span, t, k, |d| {
            (0..=k).map(|order| self.ders_row(span, d, order)).collect()
        })
    }

    /// [`BSpline::derivs`] for k = N − 1 into an array (no heap allocation for degrees
    /// below 8 and N ≤ 4).
    pub fn derivs_array<const N: usize>(&self, t: f64) -> [P; N] {
        let t = self.wrap(t);
        let span = find_span(&self.knots, self.degree, self.ctrl.len(), t);
        with_ders_basis_funs(&self.knots, self.degree, span, t, N - 1, |d| {
            std::array::from_fn(|order| self.ders_row(span, d, order))
        })
    }

    /// C^{(order)}(t) from the basis derivatives `d` (row-major, stride p + 1).
    fn ders_row(&self, span: usize, d: &[f64], order: usize) -> P {
        let mut acc = P::ZERO;
        if order <= self.degree {
            let base = span - self.degree;
            let w = self.degree + 1;
            for (cj, dj) in self.ctrl[base..=span]
                .iter()
                .zip(&d[order * w..(order + 1) * w])
            {
                acc = acc + *cj * *dj;
            }
        }
        acc
    }

    /// The derivative curve C′(t) of degree p − 1, with control values
    /// Q_i = p (P_{i+1} − P_i) / (u_{i+p+1} − u_{i+1}) on knots u_1..u_{m−1} (P&T eq. 3.8).
    /// Degree-1 curves have a piecewise constant derivative, which needs degree 0: they
    /// return `None` (use [`BSpline::derivs`] for their derivative values).
    pub fn derivative(&self) -> Option<BSpline<P>> {
        let p = self.degree;
        if p < 2 {
            return None;
        }
        let n = self.ctrl.len();
        let ctrl: Vec<P> = (0..n - 1)
            .map(|i| {
                let den = self.knots[i + p + 1] - self.knots[i + 1];
                if den > 0.0 {
                    (self.ctrl[i + 1] - self.ctrl[i]) * (p as f64 / den)
                } else {
                    P::ZERO
                }
            })
            .collect();
        let knots = self.knots[1..self.knots.len() - 1].to_vec();
        Some(BSpline {
            degree: p - 1,
            knots,
            ctrl,
            closed: self.closed,
        })
    }

    /// Multiplicity of the knot value `t` in the knot vector.
    pub fn multiplicity(&self, t: f64) -> usize {
        self.knots.iter().filter(|&&k| k == t).count()
    }

    /// The same curve with `t` inserted `times` times (Boehm's algorithm, P&T A5.1); the
    /// total multiplicity is capped at the degree. The curve is unchanged on its domain.
    pub fn insert_knot(&self, t: f64, times: usize) -> Result<BSpline<P>, SplineError> {
        let (lo, hi) = self.domain();
        if !(t >= lo && t <= hi) {
            return Err(SplineError::OutOfDomain { t, lo, hi });
        }
        let mut c = self.clone();
        let room = self.degree.saturating_sub(self.multiplicity(t));
        for _ in 0..times.min(room) {
            c = c.insert_once(t);
        }
        Ok(c)
    }

    fn insert_once(&self, t: f64) -> BSpline<P> {
        let p = self.degree;
        let n = self.ctrl.len();
        // The span k with u_k ≤ t < u_{k+1}, found over the whole knot vector so that t at
        // the domain's right end still lands left of the trailing knots.
        let k = find_span(&self.knots, p, n, t);
        let mut ctrl = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let q = if i + p <= k {
                self.ctrl[i]
            } else if i > k {
                self.ctrl[i - 1]
            } else {
                let den = self.knots[i + p] - self.knots[i];
                let a = if den > 0.0 {
                    (t - self.knots[i]) / den
                } else {
                    0.0
                };
                self.ctrl[i] * a + self.ctrl[i - 1] * (1.0 - a)
            };
            ctrl.push(q);
        }
        let mut knots = self.knots.clone();
        knots.insert(k + 1, t);
        BSpline {
            degree: p,
            knots,
            ctrl,
            closed: self.closed,
        }
    }

    /// The two halves of an open curve at an interior parameter `t`: each a clamped curve
    /// on its own part of the domain, meeting at C(t).
    pub fn split(&self, t: f64) -> Result<(BSpline<P>, BSpline<P>), SplineError> {
        let (lo, hi) = self.domain();
        if !(t > lo && t < hi) {
            return Err(SplineError::OutOfDomain { t, lo, hi });
        }
        let p = self.degree;
        let full = self.insert_knot(t, p)?;
        // After insertion t has multiplicity p: control value index `first` is C(t).
        let first = full.knots.iter().position(|&k| k == t).unwrap_or(0);
        let joint = first - 1;
        let mut left_knots: Vec<f64> = full.knots[..first + p].to_vec();
        left_knots.push(t);
        let left_ctrl = full.ctrl[..=joint].to_vec();
        let mut right_knots = vec![t];
        right_knots.extend_from_slice(&full.knots[first..]);
        let right_ctrl = full.ctrl[joint..].to_vec();
        Ok((
            BSpline::new(p, left_knots, left_ctrl)?,
            BSpline::new(p, right_knots, right_ctrl)?,
        ))
    }

    /// The curve with every control value mapped by `f` (an affine map of the control
    /// values maps the curve, by affine invariance).
    pub fn map<Q: Vector>(&self, f: impl Fn(P) -> Q) -> BSpline<Q> {
        BSpline {
            degree: self.degree,
            knots: self.knots.clone(),
            ctrl: self.ctrl.iter().map(|&c| f(c)).collect(),
            closed: self.closed,
        }
    }

    /// The same curve parametrised backwards: C_rev(t) = C(lo + hi − t).
    pub fn reversed(&self) -> BSpline<P> {
        let (lo, hi) = self.domain();
        let mut knots: Vec<f64> = self.knots.iter().rev().map(|&k| lo + hi - k).collect();
        // Keep -0.0 out of the knot vector.
        for k in &mut knots {
            if *k == 0.0 {
                *k = 0.0;
            }
        }
        BSpline {
            degree: self.degree,
            knots,
            ctrl: self.ctrl.iter().rev().copied().collect(),
            closed: self.closed,
        }
    }
}

fn check_count(degree: usize, got: usize, need: usize) -> Result<(), SplineError> {
    if degree < 1 {
        return Err(SplineError::Degree(degree));
    }
    if got < need {
        return Err(SplineError::TooFewControl { degree, need, got });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    use proptest::prelude::*;

    fn curve_strategy(closed: bool) -> impl Strategy<Value = BSpline<DVec2>> {
        (1usize..=5, 0usize..=6).prop_flat_map(move |(p, extra)| {
            let n = p + 1 + extra;
            (
                proptest::collection::vec((-10.0f64..10.0, -10.0f64..10.0), n),
                proptest::collection::vec(0.05f64..1.0, n),
            )
                .prop_map(move |(pts, gaps)| {
                    let ctrl: Vec<DVec2> = pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
                    if closed {
                        let mut breaks = vec![0.0];
                        for g in &gaps {
                            breaks.push(breaks.last().unwrap() + g);
                        }
                        BSpline::closed_with_breaks(p, ctrl, &breaks).unwrap()
                    } else {
                        let inner = n - p - 1;
                        let mut k = vec![0.0; p + 1];
                        let mut acc = 0.0;
                        for g in gaps.iter().take(inner) {
                            acc += g;
                            k.push(acc);
                        }
                        acc += 0.5;
                        k.extend(std::iter::repeat_n(acc, p + 1));
                        BSpline::new(p, k, ctrl).unwrap()
                    }
                })
        })
    }

    fn rel(a: DVec2, b: DVec2, scale: f64) -> f64 {
        (a - b).length() / scale.max(1.0)
    }

    proptest! {
        #[test]
        fn knot_insertion_keeps_curve(c in curve_strategy(false), s in 0.0f64..1.0, times in 1usize..4, closed in any::<bool>(), cc in curve_strategy(true)) {
            let c = if closed { cc } else { c };
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let d = c.insert_knot(t, times).unwrap();
            for i in 0..=50 {
                let u = lo + (hi - lo) * i as f64 / 50.0;
                prop_assert!(rel(c.eval(u), d.eval(u), 10.0) < 1e-12, "u={u}");
            }
        }

        #[test]
        fn derivatives_match_finite_differences(c in curve_strategy(false), s in 0.02f64..0.98) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let span = find_span(c.knots(), c.degree(), c.ctrl().len(), t);
            let h = 1e-5 * (c.knots()[span + 1] - c.knots()[span]);
            prop_assume!(t - h > c.knots()[span] && t + h < c.knots()[span + 1]);
            let d = c.derivs(t, 2);
            let fd1 = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
            let scale = d[1].length().max(1.0);
            prop_assert!((fd1 - d[1]).length() < 1e-5 * scale, "fd {fd1} d {}", d[1]);
            if c.degree() >= 2 {
                let fd2 = (c.derivs(t + h, 1)[1] - c.derivs(t - h, 1)[1]) / (2.0 * h);
                prop_assert!((fd2 - d[2]).length() < 1e-4 * d[2].length().max(1.0));
                // The derivative curve agrees with the basis derivatives.
                let dc = c.derivative().unwrap();
                prop_assert!((dc.eval(t) - d[1]).length() < 1e-9 * scale);
            }
        }

        #[test]
        fn closed_curves_close_with_c_p_minus_1(c in curve_strategy(true)) {
            let (lo, hi) = c.domain();
            let a = c.derivs(lo, c.degree() - 1);
            let b = c.derivs(hi, c.degree() - 1);
            for k in 0..c.degree() {
                let scale = a[k].length().max(b[k].length()).max(1.0);
                prop_assert!((a[k] - b[k]).length() < 1e-9 * scale, "order {k}: {} vs {}", a[k], b[k]);
            }
        }

        #[test]
        fn split_halves_match(c in curve_strategy(false), s in 0.05f64..0.95) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let (l, r) = c.split(t).unwrap();
            prop_assert_eq!(l.domain(), (lo, t));
            prop_assert_eq!(r.domain(), (t, hi));
            for i in 0..=20 {
                let u = lo + (t - lo) * i as f64 / 20.0;
                prop_assert!(rel(l.eval(u), c.eval(u), 10.0) < 1e-12);
                let v = t + (hi - t) * i as f64 / 20.0;
                prop_assert!(rel(r.eval(v), c.eval(v), 10.0) < 1e-12);
            }
        }

        #[test]
        fn reversed_runs_backwards(c in curve_strategy(false), s in 0.0f64..=1.0) {
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            let r = c.reversed();
            prop_assert!(rel(r.eval(lo + hi - t), c.eval(t), 10.0) < 1e-12);
        }
    }

    #[test]
    fn bezier_form_of_single_span() {
        let ctrl = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 3.0),
            DVec2::new(4.0, 3.0),
            DVec2::new(5.0, 0.0),
        ];
        let c = BSpline::clamped_uniform(3, ctrl.clone()).unwrap();
        let bez = crate::geom::CubicBez::new(ctrl[0], ctrl[1], ctrl[2], ctrl[3]);
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            assert!((c.eval(t) - bez.eval(t)).length() < 1e-14);
            assert!((c.derivs(t, 1)[1] - bez.deriv(t)).length() < 1e-13);
        }
    }

    #[test]
    fn wrong_inputs_are_errors() {
        let p = vec![DVec2::ZERO; 3];
        assert_eq!(
            BSpline::clamped_uniform(3, p.clone()),
            Err(SplineError::TooFewControl {
                degree: 3,
                need: 4,
                got: 3
            })
        );
        assert!(matches!(
            BSpline::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0], p.clone()),
            Err(SplineError::KnotCount { .. })
        ));
        assert!(matches!(
            BSpline::new(2, vec![0.0, 0.0, 0.0, 1.0, 0.5, 1.0], p),
            Err(SplineError::KnotDecreasing { index: 4, .. })
        ));
    }
}
