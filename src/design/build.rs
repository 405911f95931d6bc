//! From the validated model to geometry: disk B-spline curves, circle sequences and
//! attribute curves (wu-2021 eq. 18).

use super::error::{DesignError, ErrorKind, Item};
use super::model::{CircleSeq, Design, Fit, Parametrization, Stroke};
use crate::dbsc::DiskBSpline;
use crate::geom::Circle;
use crate::spline::fit::Parametrization as FitParametrization;
use crate::spline::{BSpline, SplineError};

fn circles(list: &[[f64; 3]]) -> Vec<Circle> {
    list.iter().map(|&v| Circle::from_xyr(v)).collect()
}

impl Stroke {
    /// The stroke's disk B-spline curve. `file` and `index` name the stroke in errors.
    ///
    /// `disks` strokes: [`DiskBSpline::open`] on `knots` (default clamped uniform on [0, 1])
    /// or [`DiskBSpline::closed`] on the period's breakpoints `knots` (default uniform).
    /// `points` strokes: [`DiskBSpline::interpolate`] or [`DiskBSpline::approximate`]
    /// (wu-2021 "Interpolation"/"Approximation", eq. 16 for chord-length parameters). A
    /// fit whose control disks would get a non-positive radius is an error.
    pub fn to_dbsc(&self, file: &str, index: usize) -> Result<DiskBSpline, DesignError> {
        let item = || Item::Stroke {
            index,
            name: self.name.clone(),
        };
        let build = |m: String| DesignError::at(file, item(), None, ErrorKind::Build(m));
        match (&self.disks, &self.points) {
            (Some(d), None) => {
                let disks = circles(d);
                let curve = if self.closed {
                    DiskBSpline::closed(self.effective_degree(), &disks, self.knots.as_deref())
                } else {
                    DiskBSpline::open(self.effective_degree(), &disks, self.knots.clone())
                };
                curve.map_err(|e| build(e.to_string()))
            }
            (None, Some(p)) => {
                let data = circles(p);
                let kind = self.parametrization.unwrap_or_default().to_fit();
                let curve = match (self.fit.unwrap_or_default(), self.control_disks) {
                    (Fit::Approximate, Some(n)) => DiskBSpline::approximate(
                        &data,
                        n,
                        self.effective_degree(),
                        self.closed,
                        kind,
                    ),
                    _ => {
                        DiskBSpline::interpolate(&data, self.effective_degree(), self.closed, kind)
                    }
                };
                curve.map_err(|e| build(format!("fitting `points`: {e}")))
            }
            _ => Err(build("needs either `disks` or `points`".to_string())),
        }
    }
}

impl Stroke {
    /// Every attribute channel of the stroke as a scalar B-spline on the knots of `curve`
    /// (the stroke's own curve from [`Stroke::to_dbsc`]), by [`attribute_curve`].
    pub fn attribute_curves(
        &self,
        curve: &DiskBSpline,
        file: &str,
        index: usize,
    ) -> Result<Vec<(&'static str, BSpline<f64>)>, DesignError> {
        self.attributes
            .channels()
            .into_iter()
            .map(|(name, values)| {
                attribute_curve(curve, values)
                    .map(|c| (name, c))
                    .map_err(|e| {
                        DesignError::at(
                            file,
                            Item::Stroke {
                                index,
                                name: self.name.clone(),
                            },
                            Some(super::error::Part::Key(format!("attributes.{name}"))),
                            ErrorKind::Build(e.to_string()),
                        )
                    })
            })
            .collect()
    }
}

impl Parametrization {
    /// The fitting module's parametrisation.
    pub fn to_fit(self) -> FitParametrization {
        match self {
            Parametrization::Chord => FitParametrization::ChordLength,
            Parametrization::Centripetal => FitParametrization::Centripetal,
            Parametrization::Uniform => FitParametrization::Uniform,
        }
    }
}

impl CircleSeq {
    /// The circles in order.
    #[must_use]
    pub fn to_circles(&self) -> Vec<Circle> {
        circles(&self.circles)
    }
}

impl Design {
    /// Every `[[stroke]]` as a disk B-spline curve, in file order.
    pub fn strokes(&self) -> Result<Vec<DiskBSpline>, DesignError> {
        self.stroke
            .iter()
            .enumerate()
            .map(|(i, s)| s.to_dbsc(&self.file, i))
            .collect()
    }

    /// Every `[[circles]]` sequence as circles, in file order.
    #[must_use]
    pub fn circle_sequences(&self) -> Vec<Vec<Circle>> {
        self.circles.iter().map(CircleSeq::to_circles).collect()
    }

    /// The index of the stroke, circle sequence or shape called `name`.
    pub fn find(&self, name: &str) -> Option<Item> {
        if let Some(index) = self.stroke.iter().position(|s| s.name == name) {
            return Some(Item::Stroke {
                index,
                name: name.to_string(),
            });
        }
        if let Some(index) = self.circles.iter().position(|c| c.name == name) {
            return Some(Item::Circles {
                index,
                name: name.to_string(),
            });
        }
        self.shape
            .iter()
            .position(|s| s.name == name)
            .map(|index| Item::Shape {
                index,
                name: name.to_string(),
            })
    }
}

/// An attribute channel as a scalar B-spline on the knots of `curve`:
/// a(t) = Σ N_{i,p}(t) A_i (wu-2021 eq. 18, with the attribute constant over each control
/// disk), `values` holding one A_i per control disk. Closed curves give a periodic channel.
pub fn attribute_curve(curve: &DiskBSpline, values: &[f64]) -> Result<BSpline<f64>, SplineError> {
    let c = curve.curve();
    if curve.is_closed() {
        BSpline::closed_with_breaks(c.degree(), values.to_vec(), &c.breakpoints())
    } else {
        BSpline::new(c.degree(), c.knots().to_vec(), values.to_vec())
    }
}
