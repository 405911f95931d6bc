//! Errors of design loading and validation: each names the file, the item (stroke, circle
//! sequence, shape, operation) and the part (disk, knot, point, attribute value) at fault.

use std::fmt;

/// The top-level item of a design an error is about.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Item {
    /// `[[stroke]]` number `index` (0-based) with its `name`. After loading has expanded
    /// texts and split strokes at corners, `index` counts the expanded list.
    Stroke {
        /// 0-based position among the strokes.
        index: usize,
        /// The stroke's `name` key.
        name: String,
    },
    /// `[[circles]]` number `index` (0-based) with its `name`.
    Circles {
        /// 0-based position among the circle sequences.
        index: usize,
        /// The sequence's `name` key.
        name: String,
    },
    /// `[[operation]]` number `index` (0-based) with its `kind`.
    Operation {
        /// 0-based position among the operations.
        index: usize,
        /// The operation's `kind` key as written in the file (`"profile"`, …).
        kind: String,
    },
    /// The `[outline]` table.
    Outline,
    /// `[[text]]` number `index` (0-based) with its `name`.
    Text {
        /// 0-based position among the texts.
        index: usize,
        /// The text's `name` key.
        name: String,
    },
    /// `[[shape]]` number `index` (0-based) with its `name`.
    Shape {
        /// 0-based position among the shapes.
        index: usize,
        /// The shape's `name` key.
        name: String,
    },
    /// `[[output]]` number `index` (0-based) with its `name`.
    Output {
        /// 0-based position among the outputs.
        index: usize,
        /// The output's `name` key.
        name: String,
    },
}

impl fmt::Display for Item {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Item::Stroke { index, name } => write!(f, "stroke {index} \"{name}\""),
            Item::Circles { index, name } => write!(f, "circles {index} \"{name}\""),
            Item::Operation { index, kind } => write!(f, "operation {index} ({kind})"),
            Item::Outline => write!(f, "outline"),
            Item::Text { index, name } => write!(f, "text {index} \"{name}\""),
            Item::Shape { index, name } => write!(f, "shape {index} \"{name}\""),
            Item::Output { index, name } => write!(f, "output {index} \"{name}\""),
        }
    }
}

/// The part of an item an error is about.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Part {
    /// Control disk `i` of a stroke's `disks`.
    Disk(usize),
    /// Data point `i` of a stroke's `points`.
    Point(usize),
    /// Circle `i` of a circle sequence.
    Circle(usize),
    /// Knot `i` of a stroke's `knots`.
    Knot(usize),
    /// Value `index` of attribute channel `channel`.
    Attribute {
        /// The channel's key under `[stroke.attributes]`: `power`, `depth` or `feed`.
        channel: String,
        /// 0-based index of the value (= control disk).
        index: usize,
    },
    /// A key of the item.
    Key(String),
    /// Contour `i` of a shape.
    Contour(usize),
    /// Point `point` of contour `contour` of a shape.
    ContourPoint {
        /// 0-based index of the contour in the shape's `contours`.
        contour: usize,
        /// 0-based index of the point in that contour.
        point: usize,
    },
}

impl fmt::Display for Part {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Part::Disk(i) => write!(f, "disk {i}"),
            Part::Point(i) => write!(f, "point {i}"),
            Part::Circle(i) => write!(f, "circle {i}"),
            Part::Knot(i) => write!(f, "knot {i}"),
            Part::Attribute { channel, index } => write!(f, "attribute {channel} value {index}"),
            Part::Key(k) => write!(f, "key `{k}`"),
            Part::Contour(i) => write!(f, "contour {i}"),
            Part::ContourPoint { contour, point } => write!(f, "contour {contour}, point {point}"),
        }
    }
}

/// What went wrong.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// Syntax error, wrong type or unknown key, at a 1-based line and column when known.
    Parse {
        /// 1-based line of the error, when the parser reports a position.
        line: Option<usize>,
        /// 1-based column of the error (TOML: in characters), with `line`.
        column: Option<usize>,
        /// The parser's message, without the parser's own position suffix.
        message: String,
    },
    /// The file name has none of the extensions `.toml`, `.json` and `.svg`.
    UnknownFormat,
    /// No top-level `version` key.
    MissingVersion,
    /// A `version` other than 1.
    Version(String),
    /// A number that is NaN or infinite.
    NotFinite,
    /// A radius that is not positive.
    Radius(f64),
    /// A disk or circle equal to the one before it.
    Repeated,
    /// A data point with the centre of the one before it (a fit needs a non-zero chord).
    RepeatedCentre,
    /// Fewer disks/points/circles than the curve needs.
    TooFew {
        /// What is counted, as a plural noun: `"disks"`, `"points"`, `"circles"`, ….
        what: &'static str,
        /// The least number the item needs.
        need: usize,
        /// The number given.
        got: usize,
    },
    /// A knot vector of the wrong length.
    KnotCount {
        /// Number of knots given.
        got: usize,
        /// Required number: disks + degree + 1 (open), disks + 1 breakpoints (closed).
        expected: usize,
    },
    /// A knot smaller than the one before it (or, for closed breakpoints, not larger).
    KnotDecreasing {
        /// The knot before the offending one.
        prev: f64,
        /// The offending knot.
        next: f64,
    },
    /// Any other knot-vector problem (multiplicity, empty domain).
    Knots(String),
    /// An attribute channel with one value per control disk expected.
    AttributeCount {
        /// Number of values in the channel.
        got: usize,
        /// Number of control disks
        /// ([`Stroke::control_disk_count`](super::Stroke::control_disk_count)).
        expected: usize,
    },
    /// Two items with the same name.
    DuplicateName {
        /// The item that has the name first, as displayed (e.g. `stroke 0 "s1"`).
        first: String,
    },
    /// An operation names a stroke that does not exist.
    UnknownStroke(String),
    /// A value outside its allowed range, or keys that do not go together.
    Invalid(String),
    /// Building the curve failed (disk B-spline construction or fitting).
    Build(String),
    /// Serialising the design failed.
    Serialize(String),
    /// The file needs a part of skinpath this build leaves out (a Cargo feature that is off).
    FeatureOff {
        /// What the file needs, in words (`"SVG import"`).
        what: &'static str,
        /// The Cargo feature that provides it (`"svg-import"`).
        feature: &'static str,
    },
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ErrorKind::Parse { message, .. } => write!(f, "{message}"),
            ErrorKind::UnknownFormat => {
                write!(
                    f,
                    "unknown design format: expected a .toml, .json or .svg file"
                )
            }
            ErrorKind::MissingVersion => write!(f, "missing `version = 1`"),
            ErrorKind::Version(v) => write!(
                f,
                "unsupported design file version {v}: this skinpath reads version 1"
            ),
            ErrorKind::NotFinite => write!(f, "number is not finite"),
            ErrorKind::Radius(r) => write!(f, "radius {r} must be positive"),
            ErrorKind::Repeated => write!(f, "repeats the one before it"),
            ErrorKind::RepeatedCentre => write!(f, "has the centre of the one before it"),
            ErrorKind::TooFew { what, need, got } => {
                write!(f, "needs at least {need} {what}, got {got}")
            }
            ErrorKind::KnotCount { got, expected } => {
                write!(f, "knot vector has {got} knots, expected {expected}")
            }
            ErrorKind::KnotDecreasing { prev, next } => {
                write!(f, "knot {next} does not follow {prev} in order")
            }
            ErrorKind::Knots(m) => write!(f, "{m}"),
            ErrorKind::AttributeCount { got, expected } => write!(
                f,
                "has {got} values, expected {expected} (one per control disk)"
            ),
            ErrorKind::DuplicateName { first } => {
                write!(f, "name already used by {first}")
            }
            ErrorKind::UnknownStroke(n) => write!(f, "names unknown stroke \"{n}\""),
            ErrorKind::Invalid(m) => write!(f, "{m}"),
            ErrorKind::Build(m) => write!(f, "{m}"),
            ErrorKind::Serialize(m) => write!(f, "cannot write design: {m}"),
            ErrorKind::FeatureOff { what, feature } => write!(
                f,
                "{what} is not built into this skinpath (build it with the `{feature}` feature)"
            ),
        }
    }
}

/// Where and what: the content of a [`DesignError`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ErrorInfo {
    /// The file name given to the loader.
    pub file: String,
    /// The item at fault; `None` for an error about the whole file.
    pub item: Option<Item>,
    /// The part of the item at fault; `None` when the error concerns the whole item.
    pub part: Option<Part>,
    /// What went wrong.
    pub kind: ErrorKind,
}

/// An error of a design file: `file: item, part: what` (boxed to keep `Result`s small;
/// the fields of [`ErrorInfo`] are reachable through `Deref`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub struct DesignError(pub Box<ErrorInfo>);

impl std::ops::Deref for DesignError {
    type Target = ErrorInfo;
    fn deref(&self) -> &ErrorInfo {
        &self.0
    }
}

impl DesignError {
    /// An error about the whole file.
    #[must_use]
    pub fn file(file: &str, kind: ErrorKind) -> Self {
        DesignError(Box::new(ErrorInfo {
            file: file.to_string(),
            item: None,
            part: None,
            kind,
        }))
    }

    /// An error about one item (and optionally one of its parts).
    #[must_use]
    pub fn at(file: &str, item: Item, part: Option<Part>, kind: ErrorKind) -> Self {
        DesignError(Box::new(ErrorInfo {
            file: file.to_string(),
            item: Some(item),
            part,
            kind,
        }))
    }
}

impl fmt::Display for DesignError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let ErrorKind::Parse {
            line: Some(l),
            column: Some(c),
            ..
        } = &self.kind
        {
            write!(f, ":{l}:{c}")?;
        }
        write!(f, ": ")?;
        match (&self.item, &self.part) {
            (Some(i), Some(p)) => write!(f, "{i}, {p}: ")?,
            (Some(i), None) => write!(f, "{i}: ")?,
            (None, Some(p)) => write!(f, "{p}: ")?,
            (None, None) => {}
        }
        write!(f, "{}", self.kind)
    }
}
