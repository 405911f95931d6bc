//! The design file model (format v1, TOML or JSON), its validation, and import.
//!
//! The library never reads files: [`load`] takes the text and the file name (whose
//! extension, `.toml` or `.json`, picks the format; [`from_str`] takes the format
//! explicitly). Parsing uses serde with unknown keys rejected; TOML and JSON errors carry
//! line:column. The version is checked before anything else.
//!
//! The keys of a design file (strokes, circle sequences, shapes, text, operations, layers
//! and colours, `[neon]`, `[[output]]`), their ranges and the errors are specified once, in
//! the design-format reference on the [crate page](crate) (`docs/design-format.md`, whose
//! examples the doc tests load).
//!
//! Geometry: [`Design::strokes`] gives every stroke as a
//! [`DiskBSpline`](crate::dbsc::DiskBSpline) (points strokes through
//! `DiskBSpline::interpolate`/`approximate`), [`Design::circle_sequences`] the circle lists,
//! and [`Stroke::attribute_curves`] the attribute channels as scalar B-splines on the
//! stroke's knots (wu-2021 eq. 18).
//!
//! Errors ([`DesignError`]) name the file, the item and the key; see the reference.

mod build;
pub(crate) mod corners;
mod error;
mod load;
mod model;
pub(crate) mod neon;
pub(crate) mod output;
pub(crate) mod select;
pub(crate) mod shape;
#[cfg(feature = "svg-import")]
pub(crate) mod svg;
pub(crate) mod text;
mod validate;

pub use build::attribute_curve;
pub use corners::{CORNER_ANGLE_DEG, Corner};
pub use error::{DesignError, ErrorInfo, ErrorKind, Item, Part};
pub use load::{Format, from_str, line_col, load, load_noted};
pub use model::{
    Attributes, CircleSeq, DEFAULT_DEGREE, Design, FillPattern, Fit, HoleAt, LineBoundaries,
    MountingHoles, Operation, OperationKind, Outline, OutlineMethod, Parametrization, ProfileSide,
    Stroke, Tabs, Units, VERSION,
};
pub use neon::{Flex, FlexPreset, Neon, NeonRun};
pub use output::{OperationRef, Output};
pub use select::{HAIRLINE_MM, Selection, Tags, default_operations, normalize_color};
pub use shape::{FillRule, Shape};
#[cfg(feature = "svg-import")]
pub use svg::{
    DEFAULT_TOLERANCE as DEFAULT_IMPORT_TOLERANCE, ImportOptions, Imported, MM_PER_PX, Skipped,
    import,
};
pub use text::smooth::FIT_TOLERANCE as TEXT_FIT_TOLERANCE;
pub use text::{
    Align, DEFAULT_LINE_SPACING, Font, Kerning, MAX_TEXT_CHARS, MIN_HEIGHT, Text, TextProblem,
    layout_problem,
};
pub use validate::{
    MAX_COORD, MAX_DEGREE, MAX_FEED, MAX_ITEMS, MAX_PASSES, MAX_TABS, MIN_RADIUS, NEAR_FRACTION,
    validate,
};

#[cfg(test)]
mod tests;
