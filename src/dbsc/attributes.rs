//! Scalar attributes on control disks (wu-2021 eq. 18): a(t) = Σ N_{i,p}(t) A_i, blended
//! by the same basis as the disks, so each channel is a `BSpline<f64>` on the DBSC's knots.
//!
//! Eq. 18 allows attributes A_i(ρ, θ) varying over each disk; this module implements the
//! per-disk constant case (power, depth, feed, colour along a stroke), which is what the
//! toolpath stage consumes.

use super::DiskBSpline;
use crate::spline::{BSpline, SplineError};
use std::collections::BTreeMap;

/// Errors of attribute channels.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AttributeError {
    /// A channel was given a number of values other than one per control disk.
    #[error("attribute channel {channel:?}: {got} values for {expected} control disks")]
    Count {
        /// Name of the channel.
        channel: String,
        /// Number of values given.
        got: usize,
        /// Number of control disks (closed curves: without the wrapped copies).
        expected: usize,
    },
    /// A channel value is NaN or infinite.
    #[error("attribute channel {channel:?}: value {index} is not finite")]
    NotFinite {
        /// Name of the channel.
        channel: String,
        /// Index of the first non-finite value.
        index: usize,
    },
    /// [`AttributedDbsc::eval`] was asked for a channel that was never added; holds its name.
    #[error("no attribute channel named {0:?}")]
    Unknown(String),
    /// Building the channel's B-spline on the curve's knots failed.
    #[error(transparent)]
    Spline(#[from] SplineError),
}

/// A DBSC with named scalar channels, one value per control disk, sharing its knots.
#[derive(Clone, Debug, PartialEq)]
pub struct AttributedDbsc {
    curve: DiskBSpline,
    channels: BTreeMap<String, BSpline<f64>>,
}

impl AttributedDbsc {
    /// A DBSC without channels.
    pub fn new(curve: DiskBSpline) -> Self {
        AttributedDbsc {
            curve,
            channels: BTreeMap::new(),
        }
    }

    /// Add (or replace) the channel `name` with one value per control disk, in the order of
    /// [`DiskBSpline::control_disks`] (closed curves: without the wrapped copies).
    pub fn with_channel(mut self, name: &str, values: &[f64]) -> Result<Self, AttributeError> {
        let expected = self.curve.control_disks().len();
        if values.len() != expected {
            return Err(AttributeError::Count {
                channel: name.to_string(),
                got: values.len(),
                expected,
            });
        }
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(AttributeError::NotFinite {
                channel: name.to_string(),
                index,
            });
        }
        // Stored control values: for closed curves the wrapped copies repeat cyclically.
        let stored = self.curve.curve().ctrl().len();
        let ctrl: Vec<f64> = (0..stored).map(|i| values[i % expected]).collect();
        let base = self.curve.curve();
        let ch = if base.is_closed() {
            // Same knots and closed flag as the disks: map the disk curve's structure.
            let idx = std::cell::Cell::new(0usize);
            base.map(|_| {
                let i = idx.get();
                idx.set(i + 1);
                ctrl.get(i).copied().unwrap_or(0.0)
            })
        } else {
            BSpline::new(base.degree(), base.knots().to_vec(), ctrl)?
        };
        self.channels.insert(name.to_string(), ch);
        Ok(self)
    }

    /// The disk B-spline the channels are attached to.
    pub fn curve(&self) -> &DiskBSpline {
        &self.curve
    }

    /// Channel names, sorted.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.channels.keys().map(|s| s.as_str())
    }

    /// The channel's B-spline.
    pub fn channel(&self, name: &str) -> Option<&BSpline<f64>> {
        self.channels.get(name)
    }

    /// a(t) = Σ N_{i,p}(t) A_i (wu-2021 eq. 18, per-disk constant attributes).
    pub fn eval(&self, name: &str, t: f64) -> Result<f64, AttributeError> {
        self.channels
            .get(name)
            .map(|c| c.eval(t))
            .ok_or_else(|| AttributeError::Unknown(name.to_string()))
    }

    /// Knot insertion (Boehm) applied to the disks and every channel alike, so that control
    /// disks and attribute values stay paired; curve and channels are unchanged.
    pub fn insert_knot(&self, t: f64, times: usize) -> Result<Self, AttributeError> {
        let curve = DiskBSpline::from_curve(self.curve.curve().insert_knot(t, times)?);
        let mut channels = BTreeMap::new();
        for (k, v) in &self.channels {
            channels.insert(k.clone(), v.insert_knot(t, times)?);
        }
        Ok(AttributedDbsc { curve, channels })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::tangent::tests::dbsc_strategy;
    use crate::geom::{Circle, DVec2};
    use proptest::prelude::*;

    #[test]
    fn count_and_name_errors() {
        let disks: Vec<Circle> = (0..5)
            .map(|i| Circle::new(DVec2::new(i as f64, 0.0), 1.0))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let a = AttributedDbsc::new(c);
        assert_eq!(
            a.clone().with_channel("power", &[1.0; 4]).unwrap_err(),
            AttributeError::Count {
                channel: "power".into(),
                got: 4,
                expected: 5
            }
        );
        assert_eq!(
            a.clone()
                .with_channel("depth", &[1.0, 2.0, f64::NAN, 0.0, 0.0])
                .unwrap_err(),
            AttributeError::NotFinite {
                channel: "depth".into(),
                index: 2
            }
        );
        let a = a.with_channel("power", &[1.0; 5]).unwrap();
        assert_eq!(
            a.eval("feed", 0.5),
            Err(AttributeError::Unknown("feed".into()))
        );
        assert!((a.eval("power", 0.3).unwrap() - 1.0).abs() < 1e-15);
        assert_eq!(a.names().collect::<Vec<_>>(), vec!["power"]);
    }

    proptest! {
        /// A channel holding the disk radii evaluates to r(t) (same basis); a channel
        /// 2x_i − 1 of the control x coordinates evaluates to 2x(t) − 1 (affine
        /// invariance); knot insertion changes neither curve nor channels.
        #[test]
        fn channels_blend_like_disks(c in dbsc_strategy(), s in 0.0f64..1.0, ins in 0.0f64..1.0, times in 1usize..3) {
            let radii: Vec<f64> = c.control_disks().iter().map(|d| d.r).collect();
            let xs: Vec<f64> = c.control_disks().iter().map(|d| 2.0 * d.c.x - 1.0).collect();
            let a = AttributedDbsc::new(c.clone())
                .with_channel("r", &radii).unwrap()
                .with_channel("x", &xs).unwrap();
            let (lo, hi) = c.domain();
            let t = lo + s * (hi - lo);
            prop_assert!((a.eval("r", t).unwrap() - c.radius(t)).abs() < 1e-12);
            prop_assert!((a.eval("x", t).unwrap() - (2.0 * c.center(t).x - 1.0)).abs() < 1e-10);
            let ti = lo + ins * (hi - lo);
            let b = a.insert_knot(ti, times).unwrap();
            prop_assert_eq!(b.channel("r").unwrap().knots(), b.curve().curve().knots());
            for i in 0..=20 {
                let u = lo + (hi - lo) * i as f64 / 20.0;
                for n in ["r", "x"] {
                    prop_assert!((b.eval(n, u).unwrap() - a.eval(n, u).unwrap()).abs() < 1e-10);
                }
                prop_assert!((b.curve().center(u) - c.center(u)).length() < 1e-10);
                prop_assert!((b.eval("r", u).unwrap() - b.curve().radius(u)).abs() < 1e-10);
            }
        }
    }
}
