//! Spine geometry of the flex: arc length ([`spine_length`]) and bend radius
//! ([`bend_radius`], its minimum over a span: [`span_min_radius`]).

use super::BEND_SAMPLES;
use crate::dbsc::DiskBSpline;
use crate::geom::cross;

/// How far inside a knot span the bend search starts and ends, as a fraction of the span:
/// 10⁻⁹, so that each span sees its own one-sided curvature at a knot and not its
/// neighbour's.
pub const KNOT_INSET: f64 = 1e-9;

/// Arc length ∫‖q′(t)‖dt of the spine of `c` over its whole domain, by adaptive
/// Gauss–Legendre quadrature ([`crate::geom::quad::integrate`]) on every knot span (the
/// integrand is smooth inside a span), to the absolute error `tol` in total (shared among
/// the spans by their parameter length).
pub fn spine_length(c: &DiskBSpline, tol: f64) -> f64 {
    let (lo, hi) = c.domain();
    let speed = |t: f64| c.derivs(t, 1)[1].0.length();
    c.breakpoints()
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| {
            let share = tol * (w[1] - w[0]) / (hi - lo);
            crate::geom::quad::integrate(&speed, w[0], w[1], share)
        })
        .sum()
}

/// Radius of curvature ρ = ‖q′‖³ / |q′ × q″| of the spine at `t` (∞ on a straight
/// stretch, 0 where q′ = 0).
pub fn bend_radius(c: &DiskBSpline, t: f64) -> f64 {
    let d = c.derivs(t, 2);
    let (q1, q2) = (d[1].0, d[2].0);
    let s = q1.length();
    if s <= f64::MIN_POSITIVE {
        return 0.0;
    }
    let k = cross(q1, q2).abs();
    if k == 0.0 {
        f64::INFINITY
    } else {
        s * s * s / k
    }
}

/// The smallest radius of curvature of the spine on the knot span [a, b] and where it is:
/// κ sampled at [`BEND_SAMPLES`] + 1 points (the ends moved inside by [`KNOT_INSET`] of the span, so
/// that each span sees its own one-sided curvature at a knot), then every sampled local
/// maximum of κ refined by golden-section search on its two neighbouring intervals to a
/// parameter interval of `param_tol`·(b − a). Returns (ρ, t).
pub fn span_min_radius(c: &DiskBSpline, a: f64, b: f64, param_tol: f64) -> (f64, f64) {
    let inset = KNOT_INSET * (b - a);
    let (a0, b0) = (a + inset, b - inset);
    let ts: Vec<f64> = (0..=BEND_SAMPLES)
        .map(|k| a0 + (b0 - a0) * k as f64 / BEND_SAMPLES as f64)
        .collect();
    let kappa = |t: f64| {
        let r = bend_radius(c, t);
        if r == 0.0 { f64::INFINITY } else { 1.0 / r }
    };
    let ks: Vec<f64> = ts.iter().map(|&t| kappa(t)).collect();
    let mut best = (f64::INFINITY, a0);
    for k in 0..ts.len() {
        let left = if k > 0 { ks[k - 1] } else { f64::NEG_INFINITY };
        let right = ks.get(k + 1).copied().unwrap_or(f64::NEG_INFINITY);
        if !(ks[k] >= left && ks[k] >= right) {
            continue;
        }
        let lo = ts[k.saturating_sub(1)];
        let hi = ts[(k + 1).min(ts.len() - 1)];
        let t = golden_max(&kappa, lo, hi, param_tol * (b - a));
        let (t, kv) = if kappa(t) >= ks[k] {
            (t, kappa(t))
        } else {
            (ts[k], ks[k])
        };
        let r = if kv.is_infinite() { 0.0 } else { 1.0 / kv };
        if r < best.0 {
            best = (r, t);
        }
    }
    best
}

/// Golden-section search for a maximum of `f` on [a, b] to an interval of `tol`
/// (Kiefer 1953; [`crate::geom::roots::Golden`] on −f, equal values keeping the left part),
/// the midpoint of the final bracket.
fn golden_max(f: &impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    use crate::geom::roots::{Golden, Tie};
    // Each step shrinks the interval by 1/φ; 200 steps reach any tol from any interval.
    const MAX_STEPS: usize = 200;
    Golden::new(tol.max(0.0), MAX_STEPS, Tie::Left)
        .min(|x| -f(x), a, b)
        .mid()
}
