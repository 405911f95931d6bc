//! Interpolation and least-squares approximation of disk sequences by disk B-spline curves
//! (wu-2021 "Interpolation" and "Approximation", eq. 16).
//!
//! The data disks ⟨Q_i; d_i⟩ are fitted as points (x, y, r) of R^{2,1}: one B-spline of
//! `DVec3` fits the centre curve and the radius function with the same basis at once, as
//! wu-2021 fits both with one knot vector. Parameters come from the centres only (uniform,
//! chord length as in eq. 16, or centripetal, see [`Parametrization`]); the radii do not
//! enter the parametrisation. Knots: clamped averaged (P&T eq. 9.8 / 9.68–9.69) for open
//! curves, which replaces wu-2021's knots-at-data with added end conditions; periodic
//! through the data ([`crate::spline::fit::closed_breaks`]) for closed ones.
//!
//! A fit whose control disks would have a non-positive radius is an error naming the
//! control disk ([`DbscFitError::ControlRadius`]), never returned silently: such a curve is
//! not a disk B-spline. Fewer control disks or a smaller degree usually cure it.

use super::DiskBSpline;
use crate::geom::Circle;
use crate::spline::BSpline;
use crate::spline::fit::{self, FitError, Parametrization};
use glam::DVec3;

/// Errors of disk B-spline fitting; disk indices refer to the input slice, control disk
/// indices to the fitted curve's distinct control disks.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DbscFitError {
    /// A data disk's centre or radius is NaN or infinite.
    #[error("disk {index}: centre or radius is not finite")]
    NotFinite {
        /// Index of the data disk.
        index: usize,
    },
    /// A data disk's radius is zero or negative.
    #[error("disk {index}: radius {radius} must be positive")]
    Radius {
        /// Index of the data disk.
        index: usize,
        /// The offending radius.
        radius: f64,
    },
    /// Two consecutive data disks (cyclically for closed data) share a centre, so their
    /// chord is zero and the centre curve would stall between them.
    #[error("disks {index} and {next} have the same centre (zero chord)")]
    RepeatedCentre {
        /// Index of the first disk of the pair.
        index: usize,
        /// Index of the second disk: index + 1, or 0 when closing the loop.
        next: usize,
    },
    /// The fit produced a control disk whose radius is zero, negative or NaN.
    #[error("fitted control disk {index} has non-positive radius {radius}")]
    ControlRadius {
        /// Index among the fitted curve's distinct control disks.
        index: usize,
        /// The fitted control radius.
        radius: f64,
    },
    /// The underlying B-spline fit failed (too few disks, degree, singular system, …).
    #[error(transparent)]
    Fit(#[from] FitError),
}

/// Check the data disks and return their parameters from the centres (see
/// `spline::fit::parameters`: m values for open data, m + 1 for closed).
///
/// Consecutive disks with the same centre (cyclically for closed data) are rejected under
/// every parametrisation: the centre curve would stall there (q′ = 0 ≤ |r′|), where a DBSC
/// has no envelope.
pub fn disk_parameters(
    disks: &[Circle],
    closed: bool,
    kind: Parametrization,
) -> Result<Vec<f64>, DbscFitError> {
    for (index, d) in disks.iter().enumerate() {
        if !(d.c.x.is_finite() && d.c.y.is_finite() && d.r.is_finite()) {
            return Err(DbscFitError::NotFinite { index });
        }
        if d.r <= 0.0 {
            return Err(DbscFitError::Radius { index, radius: d.r });
        }
    }
    let m = disks.len();
    let pairs = if closed { m } else { m.saturating_sub(1) };
    if m >= 2 {
        for index in 0..pairs {
            let next = (index + 1) % m;
            if disks[index].c == disks[next].c {
                return Err(DbscFitError::RepeatedCentre { index, next });
            }
        }
    }
    let centres: Vec<_> = disks.iter().map(|d| d.c).collect();
    Ok(fit::parameters(&centres, kind, closed)?)
}

fn xyr(disks: &[Circle]) -> Vec<DVec3> {
    disks
        .iter()
        .map(|d| DVec3::new(d.c.x, d.c.y, d.r))
        .collect()
}

/// Wrap a fitted (x, y, r) curve, rejecting non-positive control radii.
fn checked(curve: BSpline<DVec3>) -> Result<DiskBSpline, DbscFitError> {
    let distinct = if curve.is_closed() {
        curve.ctrl().len() - curve.degree()
    } else {
        curve.ctrl().len()
    };
    for (index, c) in curve.ctrl()[..distinct].iter().enumerate() {
        if c.z.is_nan() || c.z <= 0.0 {
            return Err(DbscFitError::ControlRadius { index, radius: c.z });
        }
    }
    Ok(DiskBSpline::from_curve(curve))
}

impl DiskBSpline {
    /// The DBSC of degree p whose disk at t_i is the data disk i: centre Q_i and radius d_i
    /// (wu-2021 "Interpolation", parameters by eq. 16 for chord length; see
    /// `spline::fit::interpolate_with_params` for the knots and the O(m³) dense solve). The data
    /// parameters t_i are [`disk_parameters`]. Open curves start at disk 0 and end at disk
    /// m − 1; closed curves (m distinct disks, the first not repeated) are C^{p−1}.
    ///
    /// Errors: invalid or repeated disks, too few disks (m < p + 1), a singular system, or a
    /// fitted control disk with non-positive radius ([`DbscFitError::ControlRadius`]).
    pub fn interpolate(
        disks: &[Circle],
        degree: usize,
        closed: bool,
        kind: Parametrization,
    ) -> Result<DiskBSpline, DbscFitError> {
        let params = disk_parameters(disks, closed, kind)?;
        let curve = fit::interpolate_with_params(&xyr(disks), &params, degree, closed)?;
        checked(curve)
    }

    /// The DBSC of degree p with `n_ctrl` control disks nearest to the data disks in the
    /// least-squares sense Σ ‖(Q_i, d_i) − (q(t_i), r(t_i))‖² (wu-2021 "Approximation"; P&T
    /// Sec. 9.4.1, see `spline::fit::least_squares_with_params`). Open curves keep the end disks
    /// exactly. With n_ctrl = m it is [`DiskBSpline::interpolate`].
    ///
    /// Errors as for `interpolate`, and n_ctrl outside p + 1..=m.
    pub fn approximate(
        disks: &[Circle],
        n_ctrl: usize,
        degree: usize,
        closed: bool,
        kind: Parametrization,
    ) -> Result<DiskBSpline, DbscFitError> {
        let params = disk_parameters(disks, closed, kind)?;
        let curve = fit::least_squares_with_params(&xyr(disks), &params, n_ctrl, degree, closed)?;
        checked(curve)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec2;
    use proptest::prelude::*;

    fn disks_strategy(min: usize, max: usize) -> impl Strategy<Value = Vec<Circle>> {
        proptest::collection::vec((-10.0f64..10.0, -10.0f64..10.0, 1.0f64..1.3), min..=max)
            .prop_map(|v| {
                v.into_iter()
                    .map(|(x, y, r)| Circle::new(DVec2::new(x, y), r))
                    .collect::<Vec<Circle>>()
            })
            // Repeated centres are an error (tested below); keep generated data clear of them.
            .prop_filter("distinct consecutive centres", |v| {
                (0..v.len()).all(|i| (v[i].c - v[(i + 1) % v.len()].c).length() > 1e-3)
            })
    }

    fn kind_strategy() -> impl Strategy<Value = Parametrization> {
        prop_oneof![
            Just(Parametrization::Uniform),
            Just(Parametrization::ChordLength),
            Just(Parametrization::Centripetal),
        ]
    }

    fn dist(a: Circle, b: Circle) -> f64 {
        (a.c - b.c).length() + (a.r - b.r).abs()
    }

    proptest! {
        /// The curve passes through every data disk; when it fails, it fails only because a
        /// control radius is non-positive, and the reported one is.
        #[test]
        fn interpolation_passes_through_disks(
            disks in disks_strategy(6, 12),
            p in 1usize..=5,
            closed in any::<bool>(),
            kind in kind_strategy(),
            k in 0.01f64..100.0,
        ) {
            let params = disk_parameters(&disks, closed, kind).unwrap();
            match DiskBSpline::interpolate(&disks, p, closed, kind) {
                Ok(c) => {
                    prop_assert_eq!(c.is_closed(), closed);
                    for (i, (&d, &t)) in disks.iter().zip(&params).enumerate() {
                        prop_assert!(dist(c.circle_at(t), d) < 1e-9 * 20.0, "disk {i}");
                    }
                    prop_assert!(c.control_disks().iter().all(|d| d.r > 0.0));
                    // Scaling the data scales the curve (same parameters).
                    let scaled: Vec<Circle> =
                        disks.iter().map(|d| Circle::new(d.c * k, d.r * k)).collect();
                    let s = DiskBSpline::interpolate(&scaled, p, closed, kind).unwrap();
                    let (lo, hi) = c.domain();
                    for j in 0..=20 {
                        let t = lo + (hi - lo) * j as f64 / 20.0;
                        let (a, b) = (c.circle_at(t), s.circle_at(t));
                        prop_assert!(dist(Circle::new(a.c * k, a.r * k), b) < 1e-9 * 20.0 * k);
                    }
                }
                Err(DbscFitError::ControlRadius { index, radius }) => {
                    let xyr: Vec<DVec3> = disks.iter().map(|d| DVec3::new(d.c.x, d.c.y, d.r)).collect();
                    let raw = fit::interpolate_with_params(&xyr, &params, p, closed).unwrap();
                    prop_assert!(radius <= 0.0);
                    prop_assert_eq!(raw.ctrl()[index].z, radius);
                }
                Err(e) => prop_assert!(false, "unexpected error {e}"),
            }
        }

        /// Reversed input gives the reversed curve: the same disks, parameters mirrored.
        #[test]
        fn reversed_input_gives_reversed_curve(
            disks in disks_strategy(6, 10),
            p in 1usize..=5,
            closed in any::<bool>(),
            kind in kind_strategy(),
        ) {
            let rev: Vec<Circle> = disks.iter().rev().copied().collect();
            let (c, r) = match (
                DiskBSpline::interpolate(&disks, p, closed, kind),
                DiskBSpline::interpolate(&rev, p, closed, kind),
            ) {
                (Ok(c), Ok(r)) => (c, r),
                (Err(a), Err(b)) => {
                    let radius_errors = matches!(a, DbscFitError::ControlRadius { .. })
                        && matches!(b, DbscFitError::ControlRadius { .. });
                    prop_assert!(radius_errors, "{a} / {b}");
                    return Ok(());
                }
                (a, b) => {
                    return Err(TestCaseError::fail(format!("one direction failed: {a:?} {b:?}")));
                }
            };
            // Open: s ↦ 1 − s. Closed: reversed disk k is disk m−1−k, at t_{m−1} − s.
            let params = disk_parameters(&disks, closed, kind).unwrap();
            let pivot = if closed { params[disks.len() - 1] } else { 1.0 };
            let (lo, hi) = r.domain();
            for j in 0..=40 {
                let s = lo + (hi - lo) * j as f64 / 40.0;
                prop_assert!(dist(r.circle_at(s), c.circle_at(pivot - s)) < 1e-9 * 20.0, "s={s}");
            }
        }

        /// Least squares with as many control disks as data disks is interpolation, and
        /// disks sampled from a DBSC of the fitting space give that DBSC back.
        #[test]
        fn approximation_reproduces(
            disks in disks_strategy(6, 9),
            p in 1usize..=5,
            closed in any::<bool>(),
            kind in kind_strategy(),
            extra in 3usize..20,
        ) {
            if let Ok(c) = DiskBSpline::interpolate(&disks, p, closed, kind) {
                let a = DiskBSpline::approximate(&disks, disks.len(), p, closed, kind).unwrap();
                for (x, y) in c.control_disks().iter().zip(a.control_disks()) {
                    prop_assert!(dist(*x, y) < 1e-8 * 20.0);
                }
            }
            // Uniform parameters are known before the data: build the truth on the knots the
            // fit will choose and sample it there.
            let n = disks.len();
            let m = n + extra;
            let truth = if closed {
                let params: Vec<f64> = (0..=m).map(|i| i as f64 / m as f64).collect();
                let breaks = fit::closed_breaks(&params, n, p);
                DiskBSpline::closed(p, &disks, Some(&breaks)).unwrap()
            } else {
                let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
                let k = crate::spline::knots::clamped_averaged(p, n, &params);
                DiskBSpline::open(p, &disks, Some(k)).unwrap()
            };
            let samples: Vec<Circle> = (0..m)
                .map(|i| truth.circle_at(i as f64 / if closed { m } else { m - 1 } as f64))
                .collect();
            let fitted =
                DiskBSpline::approximate(&samples, n, p, closed, Parametrization::Uniform).unwrap();
            for (x, y) in fitted.control_disks().iter().zip(truth.control_disks()) {
                prop_assert!(dist(*x, y) < 1e-8 * 20.0, "{x:?} vs {y:?}");
            }
        }
    }

    /// Radii alternating between large and small overshoot in the cubic interpolant: the
    /// fit reports the first control disk with a non-positive radius.
    #[test]
    fn non_positive_control_radius_is_an_error() {
        let disks: Vec<Circle> = (0..8)
            .map(|i| {
                let r = if i % 2 == 0 { 2.0 } else { 0.05 };
                Circle::new(DVec2::new(i as f64, 0.0), r)
            })
            .collect();
        let err = DiskBSpline::interpolate(&disks, 3, false, Parametrization::ChordLength);
        let Err(DbscFitError::ControlRadius { index, radius }) = err else {
            panic!("expected a control radius error, got {err:?}");
        };
        // Independent check: the scalar radius interpolant (same parameters and knots).
        let params = disk_parameters(&disks, false, Parametrization::ChordLength).unwrap();
        let radii: Vec<f64> = disks.iter().map(|d| d.r).collect();
        let s = fit::interpolate_with_params(&radii, &params, 3, false).unwrap();
        let first = s.ctrl().iter().position(|&r| r <= 0.0).unwrap();
        assert_eq!(index, first);
        assert!((s.ctrl()[index] - radius).abs() < 1e-12 && radius <= 0.0);
        // The same for least squares: a single wide disk among thin ones rings.
        let mut spike: Vec<Circle> = (0..12)
            .map(|i| Circle::new(DVec2::new(i as f64, 0.0), 0.01))
            .collect();
        spike[6].r = 5.0;
        let err = DiskBSpline::approximate(&spike, 10, 3, false, Parametrization::ChordLength);
        assert!(
            matches!(err, Err(DbscFitError::ControlRadius { radius, .. }) if radius <= 0.0),
            "{err:?}"
        );
        // With degree 1 the control disks are the data disks: no overshoot, no error.
        assert!(DiskBSpline::interpolate(&disks, 1, false, Parametrization::ChordLength).is_ok());
    }

    #[test]
    fn invalid_disks_are_errors() {
        let mut disks: Vec<Circle> = (0..6)
            .map(|i| Circle::new(DVec2::new(i as f64, (i * i) as f64 * 0.1), 1.0))
            .collect();
        let ck = Parametrization::ChordLength;
        let mut rep = disks.clone();
        rep[4].c = rep[3].c;
        rep[4].r = 2.0;
        for kind in [Parametrization::Uniform, ck, Parametrization::Centripetal] {
            assert_eq!(
                DiskBSpline::interpolate(&rep, 3, false, kind),
                Err(DbscFitError::RepeatedCentre { index: 3, next: 4 })
            );
        }
        let mut wrap = disks.clone();
        wrap.push(disks[0]);
        assert_eq!(
            DiskBSpline::approximate(&wrap, 5, 3, true, ck),
            Err(DbscFitError::RepeatedCentre { index: 6, next: 0 })
        );
        assert!(DiskBSpline::interpolate(&wrap, 3, false, ck).is_ok());
        disks[2].r = 0.0;
        assert_eq!(
            DiskBSpline::interpolate(&disks, 3, false, ck),
            Err(DbscFitError::Radius {
                index: 2,
                radius: 0.0
            })
        );
        disks[2].r = 1.0;
        disks[5].c.x = f64::INFINITY;
        assert_eq!(
            DiskBSpline::interpolate(&disks, 3, true, ck),
            Err(DbscFitError::NotFinite { index: 5 })
        );
        disks[5].c.x = 5.0;
        assert_eq!(
            DiskBSpline::approximate(&disks, 7, 3, false, ck),
            Err(DbscFitError::Fit(FitError::ControlCount {
                n_ctrl: 7,
                min: 4,
                max: 6
            }))
        );
        assert_eq!(
            DiskBSpline::interpolate(&disks[..3], 3, false, ck),
            Err(DbscFitError::Fit(FitError::TooFewPoints {
                need: 4,
                got: 3
            }))
        );
    }
}
