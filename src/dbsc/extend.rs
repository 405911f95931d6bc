//! G² extension of a cubic DBSC to a target disk (zhang-2014).
//!
//! The extending piece is a cubic disk Bézier ⟨B⟩(u) = Σ B_i³(u) ⟨Q_i; R_i⟩, u ∈ [0, 1],
//! attached at the end t = b of the clamped cubic DBSC ⟨D⟩(t) = ⟨P(t); r(t)⟩ and ending at
//! the target disk ⟨Q; R⟩. With β₁ = β₂ = 0 the G² conditions (zhang-2014 eqs. 2.1–2.2)
//! Q(0) = P(b), Q′(0) = α₁P′(b), Q″(0) = α₁²P″(b) and R(0) = r(b), R′(0) = α₂r′(b),
//! R″(0) = α₂²r″(b) fix the control disks:
//!
//! Q₁ = Q₀ + α₁P′/3, Q₂ = 2Q₁ − Q₀ + α₁²P″/6, Q₃ = Q (and the same for R with α₂, r).
//!
//! α₁ > 0 minimises the bending energy of the centre, E = ∫ κ² ds = ∫₀¹ (Q′×Q″)²/‖Q′‖⁵ du;
//! α₂ > 0 minimises E_R = ∫₀¹ R″(u)² du = 12 (A² + AB + B²) with A = R₂ − 2R₁ + R₀ = α₂²r″/6
//! and B = R₃ − 2R₂ + R₁ = (R₃ − R₀) − α₂r′ − α₂²r″/3, subject to R > 0, enforced through
//! the control radii R₁, R₂ ≥ [`MIN_RADIUS_FRACTION`] · min(R₀, R₃) (convex hull).
//!
//! The result is one clamped cubic B-spline: the original knots with the end knot b kept
//! with multiplicity 3 (the joint), followed by four copies of b + Δ, and control disks
//! ⟨P_i; r_i⟩ followed by ⟨Q₁; R₁⟩, ⟨Q₂; R₂⟩, ⟨Q₃; R₃⟩. On [b, b + Δ] it is ⟨B⟩((t − b)/Δ).
//! With Δ = α₁ the centre is even C² in t. The radius is G² in the sense of eq. 2.2; when
//! α₂ ≠ α₁ and r′(b) ≠ 0 the ratio r′/‖q′‖, which sets the envelope direction (wu-2021
//! eq. 9), jumps at the joint, so the envelope is then only G⁰ there.
//! [`RadiusFairing::Coupled`] takes α₂ = α₁ instead: the whole disk curve is then C² in t
//! and so are the envelopes, at the cost of a less fair radius.

use super::DiskBSpline;
use crate::geom::roots::{Golden, Tie};
use crate::geom::{Circle, DVec2, cross};
use crate::spline::BSpline;
use glam::DVec3;

/// Lower bound of the extension's control radii relative to the smaller end radius: keeps
/// the minimiser of ∫R″² off the boundary R = 0, where the stroke would pinch to a point.
pub const MIN_RADIUS_FRACTION: f64 = 0.1;

/// The α₁ search range as factors of α_ref = chord/‖P′‖ (α_ref makes ‖Q₁ − Q₀‖ a third of
/// the chord ‖Q₃ − Q₀‖). The upper end 3 keeps the first control leg no longer than the
/// chord: ∫κ² ds is scale-dependent and, when the end tangent points away from the target,
/// keeps falling as the extension balloons (no minimiser); α₁ then sits at this bound.
pub const ALPHA1_RANGE: (f64, f64) = (0.02, 3.0);

/// The α₂ search range as factors of α₁. Small α₂ is always feasible (R₁, R₂ → R₀), so
/// the range reaches far down; E_R stays bounded there.
pub const ALPHA2_RANGE: (f64, f64) = (1e-6, 1e2);

/// Relative slack on the control-radius bound for candidates computed on the boundary
/// itself (their R₁ or R₂ equals the bound up to rounding).
const BOUNDARY_SLACK: f64 = 1e-12;

/// Samples of the global log-spaced scan before local refinement.
const SCAN_SAMPLES: usize = 128;

/// Most golden-section steps after the scan: (1/φ)²⁰⁰ of the bracket is far below any
/// tolerance, so the relative width `tol` ends the search first.
const GOLDEN_MAX_STEPS: usize = 200;

/// Initial panels of the bending-energy quadrature.
const QUAD_PIECES: usize = 8;

/// How the radius parameter α₂ is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusFairing {
    /// α₂ minimising ∫R″² (zhang-2014).
    MinEnergy,
    /// α₂ = α₁: the disk curve is C², so the envelopes are too (see the module docs);
    /// an error when this α₂ would take a control radius below the bound.
    Coupled,
}

/// Errors of the extension.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExtendError {
    /// The curve is not cubic; holds its degree.
    #[error("extension needs a cubic DBSC, got degree {0}")]
    Degree(usize),
    /// The curve is closed, or its last p + 1 knots are not all equal to the end b.
    #[error("extension needs an open DBSC clamped at its end")]
    NotClampedEnd,
    /// The target disk's radius is not positive and finite; holds it.
    #[error("target disk: radius {0} must be positive and finite")]
    TargetRadius(f64),
    /// The target disk's centre is NaN or infinite.
    #[error("target disk: centre is not finite")]
    TargetNotFinite,
    /// P′(b) = 0, so there is no end tangent to continue; also returned when no α₁ in
    /// `ALPHA1_RANGE` gives a finite bending energy.
    #[error("the centre curve has zero velocity at its end: no tangent to continue")]
    ZeroEndTangent,
    /// The target centre Q equals the end point P(b): the chord is zero.
    #[error("target disk centre coincides with the end of the centre curve")]
    TargetAtEnd,
    /// No α₂ (for [`RadiusFairing::Coupled`]: α₂ = α₁) keeps R₁ and R₂ at or above the
    /// bound `MIN_RADIUS_FRACTION` · min(R₀, R₃).
    #[error("no α₂ keeps the extension's control radii above {min}")]
    NoPositiveRadius {
        /// The control-radius bound, in the curve's length unit.
        min: f64,
    },
    /// Building the extended B-spline failed.
    #[error(transparent)]
    Spline(#[from] crate::spline::SplineError),
}

/// The extended curve and the chosen free parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Extension {
    /// The original curve followed by the extending piece, one clamped cubic DBSC on
    /// [u_p, b + Δ] (see the module docs for its knots and control disks).
    pub curve: DiskBSpline,
    /// α₁ > 0, the centre's speed factor Q′(0) = α₁P′(b) (zhang-2014 eq. 2.1), chosen to
    /// minimise the bending energy ∫κ² ds.
    pub alpha1: f64,
    /// α₂ > 0, the radius's speed factor R′(0) = α₂r′(b) (zhang-2014 eq. 2.2): the
    /// minimiser of ∫R″² for [`RadiusFairing::MinEnergy`], α₁ for
    /// [`RadiusFairing::Coupled`].
    pub alpha2: f64,
    /// The parameter length Δ = α₁ of the new piece: it occupies [b, b + Δ].
    pub delta: f64,
    /// The joint parameter b.
    pub joint: f64,
}

/// Bézier control points Q₀..Q₃ of the centre for a given α₁ (zhang-2014 eq. 2.1, β₁ = 0).
pub fn centre_controls(p0: DVec2, p1: DVec2, p2: DVec2, target: DVec2, alpha1: f64) -> [DVec2; 4] {
    let q1 = p0 + alpha1 * p1 / 3.0;
    let q2 = 2.0 * q1 - p0 + alpha1 * alpha1 * p2 / 6.0;
    [p0, q1, q2, target]
}

/// Control radii R₀..R₃ for a given α₂ (zhang-2014 eq. 2.2, β₂ = 0).
pub fn radius_controls(r0: f64, r1: f64, r2: f64, target: f64, alpha2: f64) -> [f64; 4] {
    let a1 = r0 + alpha2 * r1 / 3.0;
    let a2 = 2.0 * a1 - r0 + alpha2 * alpha2 * r2 / 6.0;
    [r0, a1, a2, target]
}

/// ∫₀¹ R″(u)² du of the cubic with control values `r` (exact: R″ is linear).
pub fn radius_energy(r: [f64; 4]) -> f64 {
    let a = r[2] - 2.0 * r[1] + r[0];
    let b = r[3] - 2.0 * r[2] + r[1];
    12.0 * (a * a + a * b + b * b)
}

/// ∫ κ² ds = ∫₀¹ (Q′×Q″)² / ‖Q′‖⁵ du of the cubic Bézier `q`, by adaptive 5-point
/// Gauss–Legendre quadrature: a panel is accepted when it agrees with the sum of its two
/// halves to `rel_tol` of the running total (near-cusps make the integrand spiky, so a
/// fixed rule is not enough), with depth capped at `QUAD_MAX_DEPTH`. ∞ where Q′ = 0 at
/// a node.
pub fn bending_energy(q: [DVec2; 4], rel_tol: f64) -> f64 {
    let d1 = [
        3.0 * (q[1] - q[0]),
        3.0 * (q[2] - q[1]),
        3.0 * (q[3] - q[2]),
    ];
    let d2 = [
        6.0 * (q[2] - 2.0 * q[1] + q[0]),
        6.0 * (q[3] - 2.0 * q[2] + q[1]),
    ];
    let f = |u: f64| {
        let v = 1.0 - u;
        let qd = d1[0] * (v * v) + d1[1] * (2.0 * u * v) + d1[2] * (u * u);
        let qdd = d2[0] * v + d2[1] * u;
        let sp = qd.length();
        if sp == 0.0 {
            return f64::INFINITY;
        }
        let c = cross(qd, qdd);
        c * c / sp.powi(5)
    };
    let h = 1.0 / QUAD_PIECES as f64;
    let coarse: Vec<f64> = (0..QUAD_PIECES)
        .map(|k| gl5(&f, h * k as f64, h * (k + 1) as f64))
        .collect();
    let total: f64 = coarse.iter().sum();
    if !total.is_finite() {
        return f64::INFINITY;
    }
    let abs_tol = rel_tol.max(1e-15) * total.max(f64::MIN_POSITIVE);
    (0..QUAD_PIECES)
        .map(|k| {
            adapt(
                &f,
                h * k as f64,
                h * (k + 1) as f64,
                coarse[k],
                abs_tol / QUAD_PIECES as f64,
                0,
            )
        })
        .sum()
}

/// Halvings allowed below each initial quadrature panel (bounds the work near cusps,
/// where the energy is huge anyway and its exact value does not matter).
const QUAD_MAX_DEPTH: usize = 10;

/// Relative accuracy of the bending-energy quadrature used by [`extend_g2`]: well below the
/// differences between neighbouring α the minimiser compares.
const QUAD_REL_TOL: f64 = 1e-9;

fn gl5(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const X: [f64; 5] = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
    ];
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    X.iter().zip(W).map(|(x, w)| w * f(m + h * x)).sum::<f64>() * h
}

fn adapt(f: &dyn Fn(f64) -> f64, a: f64, b: f64, whole: f64, tol: f64, depth: usize) -> f64 {
    let m = 0.5 * (a + b);
    let (l, r) = (gl5(f, a, m), gl5(f, m, b));
    if depth >= QUAD_MAX_DEPTH || (l + r - whole).abs() <= tol || !(l + r).is_finite() {
        return l + r;
    }
    adapt(f, a, m, l, 0.5 * tol, depth + 1) + adapt(f, m, b, r, 0.5 * tol, depth + 1)
}

/// Minimise `f` over log α in [lo, hi] (feasible where `ok`): a scan of [`SCAN_SAMPLES`]
/// points, then golden-section search in the bracket around the best sample to a relative
/// width `tol`. Ties keep `prefer` when it is feasible and no worse. `None` if nothing is
/// feasible.
fn minimise(
    f: &dyn Fn(f64) -> f64,
    ok: &dyn Fn(f64) -> bool,
    lo: f64,
    hi: f64,
    tol: f64,
    prefer: Option<f64>,
) -> Option<f64> {
    let (la, lb) = (lo.ln(), hi.ln());
    let xs: Vec<f64> = (0..SCAN_SAMPLES)
        .map(|i| la + (lb - la) * i as f64 / (SCAN_SAMPLES - 1) as f64)
        .collect();
    let g = |x: f64| {
        let a = x.exp();
        if ok(a) { f(a) } else { f64::INFINITY }
    };
    let vals: Vec<f64> = xs.iter().map(|&x| g(x)).collect();
    let (best, &bv) = vals.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1))?;
    if !bv.is_finite() {
        return None;
    }
    // Golden section on [x_{best−1}, x_{best+1}].
    let (a, b) = (xs[best.saturating_sub(1)], xs[(best + 1).min(xs.len() - 1)]);
    // The ratio is (√5 − 1)/2 as evaluated in f64, which the extensions were computed with.
    let golden = Golden::new(tol.max(f64::EPSILON), GOLDEN_MAX_STEPS, Tie::Right)
        .with_ratio(0.5 * (5f64.sqrt() - 1.0));
    let bracket = golden.min(&g, a, b);
    let x = bracket.mid();
    let (best_a, best_v) = if g(x) <= bv {
        (x.exp(), g(x))
    } else {
        (xs[best].exp(), bv)
    };
    if let Some(p) = prefer
        && ok(p)
        && f(p) <= best_v * (1.0 + 1e-12) + f64::MIN_POSITIVE
    {
        return Some(p);
    }
    Some(best_a)
}

/// Extend the clamped cubic DBSC `c` at its end to the disk `target` with G² continuity
/// (zhang-2014, module docs). `tol` is the relative accuracy of α₁ and α₂.
pub fn extend_g2(
    c: &DiskBSpline,
    target: Circle,
    fairing: RadiusFairing,
    tol: f64,
) -> Result<Extension, ExtendError> {
    if c.degree() != 3 {
        return Err(ExtendError::Degree(c.degree()));
    }
    let (_, b) = c.domain();
    let curve = c.curve();
    let knots = curve.knots();
    let n = curve.ctrl().len();
    if c.is_closed() || knots[n..].iter().any(|&k| k != b) {
        return Err(ExtendError::NotClampedEnd);
    }
    if !(target.r > 0.0 && target.r.is_finite()) {
        return Err(ExtendError::TargetRadius(target.r));
    }
    if !(target.c.x.is_finite() && target.c.y.is_finite()) {
        return Err(ExtendError::TargetNotFinite);
    }
    let d = c.derivs(b, 2);
    let (p0, r0) = d[0];
    let (p1, r1) = d[1];
    let (p2, r2) = d[2];
    let speed = p1.length();
    if speed == 0.0 {
        return Err(ExtendError::ZeroEndTangent);
    }
    let chord = (target.c - p0).length();
    if chord == 0.0 {
        return Err(ExtendError::TargetAtEnd);
    }
    let aref = chord / speed;
    let e1 = |a: f64| bending_energy(centre_controls(p0, p1, p2, target.c, a), QUAD_REL_TOL);
    let alpha1 = minimise(
        &e1,
        &|_| true,
        aref * ALPHA1_RANGE.0,
        aref * ALPHA1_RANGE.1,
        tol,
        None,
    )
    .ok_or(ExtendError::ZeroEndTangent)?;
    let min_r = MIN_RADIUS_FRACTION * r0.min(target.r);
    let alpha2 = match fairing {
        RadiusFairing::Coupled => {
            let rs = radius_controls(r0, r1, r2, target.r, alpha1);
            if rs[1] < min_r || rs[2] < min_r {
                return Err(ExtendError::NoPositiveRadius { min: min_r });
            }
            alpha1
        }
        RadiusFairing::MinEnergy => {
            let e2 = |a: f64| radius_energy(radius_controls(r0, r1, r2, target.r, a));
            let ok = |a: f64| {
                let rs = radius_controls(r0, r1, r2, target.r, a);
                rs[1] >= min_r && rs[2] >= min_r
            };
            let (lo, hi) = (alpha1 * ALPHA2_RANGE.0, alpha1 * ALPHA2_RANGE.1);
            let scan = minimise(&e2, &ok, lo, hi, tol, Some(alpha1))
                .ok_or(ExtendError::NoPositiveRadius { min: min_r })?;
            // The constrained minimum may sit on the feasibility boundary, between scan
            // samples: R₁ = min (α = 3(min − R₀)/r′) or R₂ = min (a quadratic in α).
            let mut cands = vec![scan];
            if r1 != 0.0 {
                cands.push(3.0 * (min_r - r0) / r1);
            }
            let (qa, qb, qc) = (r2 / 6.0, 2.0 * r1 / 3.0, r0 - min_r);
            if qa != 0.0 {
                let disc = qb * qb - 4.0 * qa * qc;
                if disc >= 0.0 {
                    let sq = disc.sqrt();
                    cands.push((-qb + sq) / (2.0 * qa));
                    cands.push((-qb - sq) / (2.0 * qa));
                }
            } else if qb != 0.0 {
                cands.push(-qc / qb);
            }
            let near_ok = |a: f64| {
                let rs = radius_controls(r0, r1, r2, target.r, a);
                let slack = min_r * BOUNDARY_SLACK;
                rs[1] >= min_r - slack && rs[2] >= min_r - slack
            };
            cands
                .into_iter()
                .filter(|&a| a >= lo && a <= hi && near_ok(a))
                .min_by(|&a, &b| e2(a).total_cmp(&e2(b)).then(a.total_cmp(&b)))
                .filter(|&a| e2(a) < e2(scan))
                .unwrap_or(scan)
        }
    };
    let q = centre_controls(p0, p1, p2, target.c, alpha1);
    let rs = radius_controls(r0, r1, r2, target.r, alpha2);
    let delta = alpha1;
    let mut new_knots = knots[..n + 3].to_vec();
    new_knots.extend(std::iter::repeat_n(b + delta, 4));
    let mut ctrl = curve.ctrl().to_vec();
    for i in 1..4 {
        ctrl.push(DVec3::new(q[i].x, q[i].y, rs[i]));
    }
    let ext = BSpline::new(3, new_knots, ctrl)?;
    Ok(Extension {
        curve: DiskBSpline::from_curve(ext),
        alpha1,
        alpha2,
        delta,
        joint: b,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn signed_curvature(d1: DVec2, d2: DVec2) -> f64 {
        cross(d1, d2) / d1.length().powi(3)
    }

    fn open_cubic() -> impl Strategy<Value = (DiskBSpline, Circle)> {
        (
            0usize..3,
            proptest::collection::vec((-10.0f64..10.0, -10.0f64..10.0, 0.3f64..2.0), 7),
        )
            .prop_map(|(extra, v)| {
                let disks: Vec<Circle> = v[..4 + extra]
                    .iter()
                    .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
                    .collect();
                let t = v[6];
                (
                    DiskBSpline::open(3, &disks, None).unwrap(),
                    Circle::new(DVec2::new(t.0 + 25.0, t.1), t.2),
                )
            })
    }

    fn check_joint(c: &DiskBSpline, e: &Extension, target: Circle) -> Result<(), TestCaseError> {
        let b = e.joint;
        let l = c.derivs(b, 2);
        let r = e.curve.derivs(b, 2); // right-hand span at the triple knot
        let scale = l[0].0.length().max(1.0);
        prop_assert!((l[0].0 - r[0].0).length() < 1e-12 * scale);
        // Tangent direction and curvature continuous (centre, G²; here even C²).
        let (tl, tr) = (l[1].0.normalize(), r[1].0.normalize());
        prop_assert!((tl - tr).length() < 1e-9);
        let (kl, kr) = (
            signed_curvature(l[1].0, l[2].0),
            signed_curvature(r[1].0, r[2].0),
        );
        prop_assert!((kl - kr).abs() < 1e-7 * kl.abs().max(1.0), "{} {}", kl, kr);
        // Radius per eq. 2.2, in the Bézier parameter u = (t − b)/Δ.
        let (rr, rr1, rr2) = (r[0].1, r[1].1 * e.delta, r[2].1 * e.delta * e.delta);
        prop_assert!((rr - l[0].1).abs() < 1e-12 * l[0].1.max(1.0));
        prop_assert!((rr1 - e.alpha2 * l[1].1).abs() < 1e-9 * (l[1].1.abs() * e.alpha2).max(1.0));
        prop_assert!(
            (rr2 - e.alpha2 * e.alpha2 * l[2].1).abs()
                < 1e-8 * (l[2].1.abs() * e.alpha2 * e.alpha2).max(1.0)
        );
        // Centre per eq. 2.1 in u.
        prop_assert!(
            (r[1].0 * e.delta - e.alpha1 * l[1].0).length()
                < 1e-9 * (e.alpha1 * l[1].0.length()).max(1.0)
        );
        // Ends at the target disk.
        let end = e.curve.circle_at(b + e.delta);
        prop_assert!((end.c - target.c).length() < 1e-12 * target.c.length().max(1.0));
        prop_assert!((end.r - target.r).abs() < 1e-12);
        prop_assert_eq!(e.curve.domain().1, b + e.delta);
        // Original part unchanged.
        for i in 0..=10 {
            let t = b * i as f64 / 10.0;
            prop_assert!((c.center(t) - e.curve.center(t)).length() < 1e-10 * scale);
        }
        // Radius positive along the extension.
        for i in 0..=50 {
            prop_assert!(e.curve.radius(b + e.delta * i as f64 / 50.0) > 0.0);
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]
        #[test]
        fn extension_is_g2_and_reaches_target((c, target) in open_cubic()) {
            let e = match extend_g2(&c, target, RadiusFairing::MinEnergy, 1e-10) {
                Err(ExtendError::ZeroEndTangent) => {
                    prop_assert_eq!(c.derivs(1.0, 1)[1].0, DVec2::ZERO);
                    return Ok(());
                }
                e => e.unwrap(),
            };
            check_joint(&c, &e, target)?;
            let ec = match extend_g2(&c, target, RadiusFairing::Coupled, 1e-10) {
                Err(ExtendError::NoPositiveRadius { min }) => {
                    let d = c.derivs(e.joint, 2);
                    let rs = radius_controls(d[0].1, d[1].1, d[2].1, target.r, e.alpha1);
                    prop_assert!(rs[1] < min || rs[2] < min);
                    return Ok(());
                }
                ec => ec.unwrap(),
            };
            check_joint(&c, &ec, target)?;
            prop_assert_eq!(ec.alpha1, ec.alpha2);
            // Coupled: the disk curve is C¹ in t at the joint (radius too).
            let (l, r) = (c.derivs(e.joint, 1), ec.curve.derivs(e.joint, 1));
            prop_assert!((l[1].1 - r[1].1).abs() < 1e-9 * l[1].1.abs().max(1.0));
        }

        /// α₁ minimises the bending energy over its range: no sample of a fine independent
        /// scan, nor the neighbours α₁(1 ± 10⁻³) inside the range, is lower. Rotating and scaling the
        /// data leaves α₁ unchanged (E scales by 1/s, its minimiser does not move).
        #[test]
        fn alpha1_minimises_energy((c, target) in open_cubic(), angle in -3.0f64..3.0, s in 0.2f64..5.0) {
            prop_assume!(c.derivs(1.0, 1)[1].0.length() > 1e-6);
            let e = extend_g2(&c, target, RadiusFairing::MinEnergy, 1e-10).unwrap();
            let b = e.joint;
            let d = c.derivs(b, 2);
            let energy = |a: f64| bending_energy(centre_controls(d[0].0, d[1].0, d[2].0, target.c, a), 1e-10);
            let e0 = energy(e.alpha1);
            let aref = (target.c - d[0].0).length() / d[1].0.length();
            let (lo, hi) = (aref * ALPHA1_RANGE.0, aref * ALPHA1_RANGE.1);
            prop_assert!(e.alpha1 >= lo * (1.0 - 1e-12) && e.alpha1 <= hi * (1.0 + 1e-12));
            for i in 0..=400 {
                let a = lo * (hi / lo).powf(i as f64 / 400.0);
                prop_assert!(energy(a) >= e0 * (1.0 - 1e-6), "a={} E={} vs α₁={} E={}", a, energy(a), e.alpha1, e0);
            }
            for a in [e.alpha1 * 1.001, e.alpha1 * 0.999] {
                prop_assert!(a > hi || a < lo || energy(a) >= e0 * (1.0 - 1e-9));
            }
            // Radius energy: no feasible sample is lower.
            let er = |a: f64| radius_energy(radius_controls(d[0].1, d[1].1, d[2].1, target.r, a));
            let minr = MIN_RADIUS_FRACTION * d[0].1.min(target.r);
            let e2 = er(e.alpha2);
            for i in 0..=400 {
                let a = e.alpha1 * 10f64.powf(-6.0 + 8.0 * i as f64 / 400.0);
                let rs = radius_controls(d[0].1, d[1].1, d[2].1, target.r, a);
                if rs[1] >= minr && rs[2] >= minr {
                    prop_assert!(er(a) >= e2 * (1.0 - 1e-6) - 1e-12, "a={} {} vs {}", a, er(a), e2);
                }
            }
            let moved = c.rotated(angle, DVec2::new(1.0, 2.0)).scaled(s, DVec2::ZERO).unwrap();
            let rot = DVec2::from_angle(angle);
            let tc = s * (DVec2::new(1.0, 2.0) + rot.rotate(target.c - DVec2::new(1.0, 2.0)));
            let em = extend_g2(&moved, Circle::new(tc, s * target.r), RadiusFairing::MinEnergy, 1e-10).unwrap();
            prop_assert!((em.alpha1 - e.alpha1).abs() < 1e-6 * e.alpha1);
        }
    }

    /// A straight cubic continued straight ahead: zero bending for every α₁, and a constant
    /// radius continued to an equal target disk gives a constant radius (E_R = 0 at any
    /// α₂; the tie keeps α₂ = α₁).
    #[test]
    fn straight_continuation() {
        let disks: Vec<Circle> = (0..4)
            .map(|i| Circle::new(DVec2::new(i as f64, 0.0), 0.5))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let target = Circle::new(DVec2::new(6.0, 0.0), 0.5);
        let e = extend_g2(&c, target, RadiusFairing::MinEnergy, 1e-10).unwrap();
        assert_eq!(e.alpha2, e.alpha1);
        for i in 0..=20 {
            let t = 1.0 + e.delta * i as f64 / 20.0;
            assert!(e.curve.center(t).y.abs() < 1e-12);
            assert!((e.curve.radius(t) - 0.5).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_inputs_are_errors() {
        let disks: Vec<Circle> = (0..4)
            .map(|i| Circle::new(DVec2::new(i as f64, 0.0), 0.5))
            .collect();
        let q = DiskBSpline::open(2, &disks, None).unwrap();
        let t = Circle::new(DVec2::new(5.0, 0.0), 1.0);
        assert_eq!(
            extend_g2(&q, t, RadiusFairing::MinEnergy, 1e-9),
            Err(ExtendError::Degree(2))
        );
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        assert_eq!(
            extend_g2(&c, Circle::new(t.c, 0.0), RadiusFairing::MinEnergy, 1e-9),
            Err(ExtendError::TargetRadius(0.0))
        );
        assert_eq!(
            extend_g2(
                &c,
                Circle::new(DVec2::new(3.0, 0.0), 1.0),
                RadiusFairing::MinEnergy,
                1e-9
            ),
            Err(ExtendError::TargetAtEnd)
        );
        let closed = DiskBSpline::closed(3, &disks, None).unwrap();
        assert_eq!(
            extend_g2(&closed, t, RadiusFairing::MinEnergy, 1e-9),
            Err(ExtendError::NotClampedEnd)
        );
        let unclamped =
            DiskBSpline::open(3, &disks, Some((0..8).map(|i| i as f64).collect())).unwrap();
        assert_eq!(
            extend_g2(&unclamped, t, RadiusFairing::MinEnergy, 1e-9),
            Err(ExtendError::NotClampedEnd)
        );
    }
}
