//! Output writers: G-code, laser SVG, DXF, previews.
//!
//! Every writer takes a [`Toolpath`](crate::toolpath::Toolpath) in millimetres and a machine
//! [`Profile`](crate::machine::Profile), validates the moves first (finite coordinates,
//! power in 0..1, arcs whose start and end lie on one circle) and returns the file's text; the
//! caller writes it (atomically).

pub(crate) mod dxf;
pub(crate) mod gcode;
pub(crate) mod geometry;
pub(crate) mod laser_svg;
pub(crate) mod outline;
pub(crate) mod preview;
pub(crate) mod svg_page;

pub use dxf::{DxfOptions, dxf};
pub use gcode::{GROUP_MARK, GcodeOptions, LineOrigin, gcode, gcode_with_origins};
pub use geometry::{CutContour, Seg};
pub use laser_svg::{LaserSvgOptions, Page, laser_svg};
pub use outline::{
    CircleRole, ContourRole, Marker, MarkerKind, OutlineContour, OutlineDoc, RefCircle,
    StrokeOutline,
};
pub use preview::{
    COLOR_STEPS, CUT_BUDGET, ColorScale, FINDING_BUDGET, HtmlOptions, LayerBudget, MARK_BUDGET,
    PngOptions, ProgramInput, RAPID_BUDGET, Scene, SvgOptions, hms, player_html, scene_png,
    scene_svg, view_box,
};
pub use svg_page::SvgPage;

use std::fmt;

/// Where in a toolpath something is: operation index and name, cut index, move index (the
/// cut's start when `mv` is `None`). Indices are 0-based.
#[derive(Clone, Debug, PartialEq)]
pub struct Location {
    /// Operation index.
    pub op: usize,
    /// Operation name.
    pub op_name: String,
    /// Cut index in the operation.
    pub cut: usize,
    /// Move index in the cut; `None` for the cut's start.
    pub mv: Option<usize>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "operation {} ({:?}), cut {}",
            self.op, self.op_name, self.cut
        )?;
        match self.mv {
            Some(m) => write!(f, ", move {m}"),
            None => write!(f, ", start"),
        }
    }
}

/// Why a toolpath could not be written.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EmitError {
    /// A move the writer cannot express faithfully.
    #[error("{at}: {reason}")]
    InvalidMove {
        /// Where in the toolpath.
        at: Location,
        /// What is wrong with the move.
        reason: String,
    },
    /// A coordinate outside the machine's travel.
    #[error(
        "{at}: {axis} = {value} is outside the work area [{min}, {max}] of profile {profile:?}{}",
        if *axis == 'Z' {
            ": lower the operation's `depth` or raise the profile's work_area.z"
        } else {
            ": place the job with `build --place lower-left` or `--place center`, or scale it with `--fit`"
        }
    )]
    OutOfWorkArea {
        /// Where in the toolpath.
        at: Location,
        /// The axis (`X`, `Y` or `Z`).
        axis: char,
        /// The coordinate (machine units).
        value: f64,
        /// Lower end of the travel.
        min: f64,
        /// Upper end of the travel.
        max: f64,
        /// The machine profile's name.
        profile: String,
    },
    /// The profile is for another kind of output.
    #[error("profile {profile:?} cannot be used for {output}: {reason}")]
    WrongProfile {
        /// The machine profile's name.
        profile: String,
        /// The output asked for ("G-code", "laser SVG", "DXF").
        output: &'static str,
        /// Why the profile does not fit.
        reason: String,
    },
    /// An option out of range.
    #[error("option {name}: {reason}")]
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// Why its value is refused.
        reason: String,
    },
    /// An output this build of skinpath leaves out: the Cargo feature that provides it was
    /// not enabled.
    #[error("{output} needs skinpath built with the `{feature}` feature")]
    FeatureDisabled {
        /// The output asked for ("PNG preview").
        output: &'static str,
        /// The Cargo feature that provides it.
        feature: &'static str,
    },
    /// A template that failed to render (names the template).
    #[error("profile {profile:?}, {key}: {reason}")]
    Template {
        /// The machine profile's name.
        profile: String,
        /// The template's key in the profile.
        key: &'static str,
        /// What failed.
        reason: String,
    },
}

/// Checks that `tol` is a usable positive tolerance.
pub(crate) fn check_tolerance(name: &'static str, tol: f64) -> Result<(), EmitError> {
    if tol.is_finite() && tol > 0.0 {
        Ok(())
    } else {
        Err(EmitError::InvalidOption {
            name,
            reason: format!("must be a positive number, got {tol}"),
        })
    }
}

/// A number for SVG/DXF text at f64 precision: shortest round-trip form, `-0` as `0`.
pub(crate) fn fnum(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        "0".to_string()
    } else {
        format!("{v}")
    }
}
