//! The serde model of a design file (format v1). Field names are the file's keys; see the
//! module docs of [`crate::design`] for the format.

use serde::{Deserialize, Serialize};

/// The only design format version this crate reads and writes.
pub const VERSION: u32 = 1;

/// Strict `[x, y, r]` triples: serde's fixed-size arrays ignore extra elements in some
/// formats (TOML), so a disk `[x, y, r, 7]` would be read as `[x, y, r]`. Each triple is
/// read as a list and its length checked; the parser reports the offending value's
/// line:column.
mod xyr {
    use serde::de::{Deserialize, Deserializer, Error};

    struct Xyr([f64; 3]);

    impl<'de> Deserialize<'de> for Xyr {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            let v = Vec::<f64>::deserialize(d)?;
            match v.as_slice() {
                &[x, y, r] => Ok(Xyr([x, y, r])),
                _ => Err(D::Error::invalid_length(
                    v.len(),
                    &"exactly 3 numbers [x, y, r]",
                )),
            }
        }
    }

    pub fn list<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 3]>, D::Error> {
        Ok(Vec::<Xyr>::deserialize(d)?
            .into_iter()
            .map(|x| x.0)
            .collect())
    }

    pub fn opt_list<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<[f64; 3]>>, D::Error> {
        Ok(Option::<Vec<Xyr>>::deserialize(d)?.map(|v| v.into_iter().map(|x| x.0).collect()))
    }
}

/// Default degree of a stroke's B-splines.
pub const DEFAULT_DEGREE: usize = 3;

fn default_degree() -> usize {
    DEFAULT_DEGREE
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// A whole design: strokes, circle sequences, operations and outline settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Design {
    /// `version` (required, checked before anything else): always [`VERSION`].
    pub version: u32,
    /// `units`: `"mm"` or `"inch"`, the length unit of every coordinate, radius and length
    /// parameter; default mm.
    #[serde(default)]
    pub units: Units,
    /// How outlines are computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outline: Option<Outline>,
    /// The `[[stroke]]` tables: disk B-spline strokes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stroke: Vec<Stroke>,
    /// The `[[circles]]` tables: circle sequences skinned directly.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub circles: Vec<CircleSeq>,
    /// The `[[shape]]` tables: closed regions (see [`Shape`](crate::design::Shape)).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shape: Vec<super::shape::Shape>,
    /// The `[[text]]` tables: single-stroke text, laid out into strokes when loaded
    /// (see [`crate::design::Text`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub text: Vec<super::text::Text>,
    /// The `[[operation]]` tables: toolpath operations (plain data for the toolpath stage).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operation: Vec<Operation>,
    /// The `[neon]` table: the LED-neon flex (see [`Neon`](crate::design::Neon)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub neon: Option<super::neon::Neon>,
    /// The `[[output]]` tables: the layers of a job, each a program of some of the
    /// operations for its own machine (see [`Output`](crate::design::Output)). Empty: one program
    /// of every operation for the machine the build is given.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub output: Vec<super::output::Output>,
    /// The file name the design was loaded from (not part of the file).
    #[serde(skip)]
    pub file: String,
    /// The corners at which loading split strokes into pieces (not part of the file; see
    /// [`crate::design::Corner`]).
    #[serde(skip)]
    pub corners: Vec<super::corners::Corner>,
}

/// Length unit of a design (the crate's one [`crate::units::Units`]).
pub use crate::units::Units;

/// `[outline]`: the outline method and its tolerance.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Outline {
    /// `method`: `"skin"`, `"envelope"`, `"re"` or `"mph"`; unset means `skin`. Read by the
    /// `outline` command, whose `--method` overrides it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<OutlineMethod>,
    /// `tolerance`: approximation tolerance in design units, > 0 and at most
    /// [`MAX_COORD`](super::MAX_COORD). Read by the `outline` command, whose `--tolerance`
    /// overrides it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
}

/// How a stroke's outline is computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutlineMethod {
    /// DBSC skinning (kruppa-2023).
    #[default]
    Skin,
    /// The raw envelope (wu-2021 eq. 9), loops and all.
    Envelope,
    /// Rational-envelope skins (re-skinning-cnc).
    Re,
    /// Minkowski-Pythagorean-hodograph skins (re-mph-skinning-flexible).
    Mph,
}

/// A `[[stroke]]`: either control disks (`disks`, optional `knots`) or data `points` to fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stroke {
    /// `name` (required): non-empty and unique among strokes, circle sequences and shapes;
    /// operations' `strokes` lists refer to it.
    pub name: String,
    /// `degree`: the B-spline degree p, in 1..=[`MAX_DEGREE`](super::MAX_DEGREE); default
    /// [`DEFAULT_DEGREE`]. Without `knots` the curve may be built with a lower degree
    /// ([`Stroke::effective_degree`]).
    #[serde(default = "default_degree")]
    pub degree: usize,
    /// `closed`: a periodic stroke whose last disk joins its first (the first is not
    /// repeated at the end); default false.
    #[serde(default, skip_serializing_if = "is_false")]
    pub closed: bool,
    /// `disks`: control disks `[x, y, r]` (exactly three numbers each), at most
    /// [`MAX_ITEMS`](super::MAX_ITEMS); finite, |x|, |y|, r ≤ [`MAX_COORD`](super::MAX_COORD),
    /// r ≥ [`MIN_RADIUS`](super::MIN_RADIUS), none (nearly) equal to the one before it.
    /// Exactly one of `disks` and `points` is given.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "xyr::opt_list"
    )]
    pub disks: Option<Vec<[f64; 3]>>,
    /// `knots` (`disks` strokes only). Open: the full knot vector (disks + degree + 1
    /// knots, non-decreasing, multiplicity ≤ degree + 1). Closed: the disks + 1 strictly
    /// increasing breakpoints of one period. Unset: clamped uniform (open) or uniform
    /// breakpoints (closed) on [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knots: Option<Vec<f64>>,
    /// `points`: data disks `[x, y, r]` the stroke interpolates or approximates, with the
    /// limits of `disks` and no centre equal to the one before it.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "xyr::opt_list"
    )]
    pub points: Option<Vec<[f64; 3]>>,
    /// `fit` (`points` strokes only): `"interpolate"` or `"approximate"`; default
    /// interpolate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<Fit>,
    /// `parametrization` (`points` strokes only): `"chord"`, `"centripetal"` or
    /// `"uniform"`; default chord length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parametrization: Option<Parametrization>,
    /// `control_disks`: number of control disks of an approximation; required for, and only
    /// for, `fit = "approximate"`, between 2 (3 when closed) and the number of points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_disks: Option<usize>,
    /// `[stroke.attributes]`: values on the control disks, blended like the radius
    /// (wu-2021 eq. 18); each channel has one value per control disk.
    #[serde(default, skip_serializing_if = "Attributes::is_empty")]
    pub attributes: Attributes,
    /// `corners`: distinct indices of `disks` or `points` that are corners: the stroke is
    /// split there into pieces that share the corner disk (see [`crate::design::Corner`]).
    /// Not combined with `knots`; the end indices of an open stroke are ignored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corners: Option<Vec<usize>>,
    /// `layer`: the drawing layer the stroke came from (an SVG import writes the Inkscape
    /// layer's label); operations select by it with `layers = [...]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<String>,
    /// `color`: the stroke's colour as `#rrggbb` (lower case; an SVG import writes the
    /// stroke paint); operations select by it with `colors = [...]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<String>,
}

impl Stroke {
    /// A stroke with control disks and default settings (degree 3, open, uniform knots).
    #[must_use]
    pub fn from_disks(name: &str, disks: Vec<[f64; 3]>) -> Self {
        Stroke {
            name: name.to_string(),
            degree: DEFAULT_DEGREE,
            closed: false,
            disks: Some(disks),
            knots: None,
            points: None,
            fit: None,
            parametrization: None,
            control_disks: None,
            attributes: Attributes::default(),
            corners: None,
            layer: None,
            color: None,
        }
    }

    /// The degree the stroke's curve is built with: `degree`, lowered to one less than the
    /// number of control disks when a stroke without `knots` has fewer than `degree + 1` of
    /// them (two disks give a line, three a parabola; a closed stroke needs three). A
    /// `knots` list fixes the degree: then `degree + 1` disks are required.
    #[must_use]
    pub fn effective_degree(&self) -> usize {
        let n = self.control_disk_count();
        if self.knots.is_some() || n < 2 {
            self.degree
        } else {
            self.degree.min(n - 1)
        }
    }

    /// The number of control disks the stroke's curve has: `disks.len()`, `points.len()`
    /// for an interpolation, `control_disks` for an approximation. Attribute channels
    /// have this many values.
    #[must_use]
    pub fn control_disk_count(&self) -> usize {
        match (&self.disks, &self.points) {
            (Some(d), _) => d.len(),
            (None, Some(p)) => match self.fit.unwrap_or_default() {
                Fit::Interpolate => p.len(),
                Fit::Approximate => self.control_disks.unwrap_or(0),
            },
            (None, None) => 0,
        }
    }
}

/// How data points become a stroke.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Fit {
    /// The centre passes through every point, the radius takes every point's radius.
    #[default]
    Interpolate,
    /// Least squares with `control_disks` control disks.
    Approximate,
}

/// Parameter values of data points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Parametrization {
    /// Cumulative chord length (wu-2021 eq. 16).
    #[default]
    Chord,
    /// Cumulative square root of chord length.
    Centripetal,
    /// Equally spaced.
    Uniform,
}

/// `[stroke.attributes]`: one value per control disk for each channel.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Attributes {
    /// `power`: laser power in percent of the machine's maximum, each in 0..=100.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub power: Option<Vec<f64>>,
    /// `depth`: cut depth in design units, each in 0..=[`MAX_COORD`](super::MAX_COORD).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<Vec<f64>>,
    /// `feed`: feed rate in design units per minute, each in
    /// (0, [`MAX_FEED`](super::MAX_FEED)].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feed: Option<Vec<f64>>,
}

impl Attributes {
    /// True when no channel is set (the `attributes` table is then not written).
    pub fn is_empty(&self) -> bool {
        self.power.is_none() && self.depth.is_none() && self.feed.is_none()
    }

    /// The channels present, by name.
    pub fn channels(&self) -> Vec<(&'static str, &[f64])> {
        let mut out = Vec::new();
        for (name, v) in [
            ("power", &self.power),
            ("depth", &self.depth),
            ("feed", &self.feed),
        ] {
            if let Some(v) = v {
                out.push((name, v.as_slice()));
            }
        }
        out
    }
}

/// A `[[circles]]` table: a circle sequence to skin directly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CircleSeq {
    /// `name` (required): non-empty and unique among strokes, circle sequences and shapes.
    pub name: String,
    /// `closed`: the sequence wraps from its last circle to its first (which is not
    /// repeated); default false. At least 3 circles when closed, 2 when open.
    #[serde(default, skip_serializing_if = "is_false")]
    pub closed: bool,
    /// `circles` (required): circles `[x, y, r]` in order, with the limits of a stroke's
    /// `disks`.
    #[serde(deserialize_with = "xyr::list")]
    pub circles: Vec<[f64; 3]>,
}

/// The kind of an `[[operation]]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OperationKind {
    /// Cut on, outside or inside the outline.
    Profile,
    /// A neon channel along the spine.
    Channel,
    /// One contour around all outlines at a margin.
    Backboard,
    /// Holes at stroke ends.
    Holes,
    /// Hatch or concentric fill inside the outline.
    Fill,
    /// V-bit carving along the spine, depth from the radius.
    Vcarve,
    /// Cut or engrave once along a stroke's spine (centre line), a shape's boundary or the
    /// polyline through a circle sequence's centres: lasers on the path, routers on the
    /// path at a shallow depth (see [`crate::job`]'s build for the defaults).
    Line,
}

impl OperationKind {
    /// The kind's value of the `kind` key in design files.
    pub fn as_str(self) -> &'static str {
        match self {
            OperationKind::Profile => "profile",
            OperationKind::Channel => "channel",
            OperationKind::Backboard => "backboard",
            OperationKind::Holes => "holes",
            OperationKind::Fill => "fill",
            OperationKind::Vcarve => "vcarve",
            OperationKind::Line => "line",
        }
    }
}

/// Where a profile cut runs relative to the outline. There is no default side: an unset
/// `side` means `on` for a laser and `outside` for a router (the build decides).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileSide {
    /// `"on"`: the tool centre follows the outline.
    On,
    /// `"outside"`: the path is offset outwards by the tool radius (or half the kerf), so
    /// the part keeps its size.
    Outside,
    /// `"inside"`: the path is offset inwards by the tool radius, so a hole keeps its size.
    Inside,
}

/// Where holes go.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HoleAt {
    /// Both ends of every open stroke.
    #[default]
    Ends,
    /// The start of every open stroke.
    Start,
    /// The end of every open stroke.
    End,
}

/// Fill pattern.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FillPattern {
    /// `"hatch"`: parallel lines `spacing` apart at `angle` (with `cross_hatch`, a second
    /// set at angle + 90°).
    #[default]
    Hatch,
    /// `"concentric"`: rings offset inwards from the outline, `spacing` apart.
    Concentric,
}

/// Holding tabs left on a through cut.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tabs {
    /// `tabs.count`: tabs per contour, 1..=[`MAX_TABS`](super::MAX_TABS).
    pub count: u32,
    /// `tabs.width`: tab length along the contour, design units, in
    /// (0, [`MAX_COORD`](super::MAX_COORD)] (the toolpath gap adds the tool diameter).
    pub width: f64,
    /// `tabs.height`: tab height above the cut's bottom, design units, in
    /// (0, [`MAX_COORD`](super::MAX_COORD)].
    pub height: f64,
}

/// Mounting holes through a backboard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MountingHoles {
    /// `mounting_holes.count`: number of holes, 1..=[`MAX_TABS`](super::MAX_TABS); up to
    /// four go to the corners (1: top centre; 2: top corners; 3: top corners and bottom
    /// centre; 4: all corners), more are spread farthest apart.
    pub count: u32,
    /// `mounting_holes.diameter`: hole diameter, design units, in (0,
    /// [`MAX_COORD`](super::MAX_COORD)].
    pub diameter: f64,
    /// `mounting_holes.inset`: distance of each hole's centre from the board's edge,
    /// design units, in (0, [`MAX_COORD`](super::MAX_COORD)]; default
    /// 8 mm (`toolpath::board::MOUNTING_INSET_MM`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inset: Option<f64>,
}

/// An `[[operation]]`: plain data, consumed by the toolpath stage. Which keys apply to which
/// kind is checked by validation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Operation {
    /// `kind` (required): which operation; decides which of the keys below apply.
    pub kind: OperationKind,
    /// `name`: what the operation is called (non-empty when given; several operations may
    /// share one); an `[[output]]`'s `operations` selects by it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// `strokes`: the strokes, circle sequences, shapes and texts it applies to, by name;
    /// non-empty, every name defined. Unset: all of them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strokes: Option<Vec<String>>,
    /// `layers`: selects the strokes and shapes whose `layer` is one of these labels
    /// (beside `strokes`: an item is selected when any given selector names it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layers: Option<Vec<String>>,
    /// `colors`: selects the strokes and shapes whose `color` is one of these (`#rrggbb`,
    /// compared case-insensitively).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colors: Option<Vec<String>>,
    // Common to all kinds.
    /// `passes`: number of passes, in 1..=[`MAX_PASSES`](super::MAX_PASSES); default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passes: Option<u32>,
    /// `step_down`: depth per pass, design units, > 0; `depth / step_down` at most
    /// [`MAX_PASSES`](super::MAX_PASSES). Unset: `depth / passes` when both are given, else
    /// the tool diameter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step_down: Option<f64>,
    /// `depth`: total cut depth below the surface, design units, > 0 and at most
    /// [`MAX_COORD`](super::MAX_COORD). Required by router operations other than vcarve;
    /// ignored by lasers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<f64>,
    /// `feed`: feed rate, design units per minute, in (0, [`MAX_FEED`](super::MAX_FEED)].
    /// Unset: the machine profile's default feed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feed: Option<f64>,
    /// `power`: laser power in percent, 0..=100. Unset: the profile's
    /// `laser.default_power`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub power: Option<f64>,
    /// `tabs` (profile and backboard only: the cuts that free a part): holding tabs
    /// `{count, width, height}`; count in 1..=[`MAX_TABS`](super::MAX_TABS), width and
    /// height > 0 and at most [`MAX_COORD`](super::MAX_COORD).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tabs: Option<Tabs>,
    /// `lead_in`: radius of the quarter-circle lead-in (and lead-out, on the same circle)
    /// on the waste side, design units, ≥ 0 and at most [`MAX_COORD`](super::MAX_COORD);
    /// 0 or unset: no leads. Leads are halved where they would meet a contour, and start
    /// on a smooth stretch of a closed contour (the middle of a segment when it starts at
    /// a corner).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lead_in: Option<f64>,
    // profile
    /// `side` (profile only): where the cut runs relative to the outline. Unset: `on` for a
    /// laser profile, `outside` otherwise (not [`ProfileSide`]'s `Default`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub side: Option<ProfileSide>,
    // channel
    /// `width` (channel only, required): channel width, design units, > 0 and at most
    /// [`MAX_COORD`](super::MAX_COORD).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    // backboard
    /// `margin` (backboard only): distance of the backboard contour from the outlines,
    /// design units, > 0 and at most [`MAX_COORD`](super::MAX_COORD); default 5 mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// `min_inner_radius` (backboard only): smallest concave corner radius of the backboard
    /// contour, design units, ≥ 0 and at most [`MAX_COORD`](super::MAX_COORD); default the
    /// tool radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_inner_radius: Option<f64>,
    /// `bridge_width` (backboard only): smallest width of the bridges that join the
    /// board's pieces (words and letters that lie apart) into one board, design units, ≥ 0
    /// and at most [`MAX_COORD`](super::MAX_COORD); default
    /// 10 mm (`toolpath::board::BRIDGE_WIDTH_MM`); 0 leaves the
    /// pieces apart.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bridge_width: Option<f64>,
    /// `mounting_holes` (backboard only): holes through the board to hang or screw it,
    /// `{count, diameter, inset}`; unset: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mounting_holes: Option<MountingHoles>,
    /// `corner_radius` (backboard only): smallest radius of the board's convex corners,
    /// design units, ≥ 0 and at most [`MAX_COORD`](super::MAX_COORD); unset or 0: the
    /// corners the margin gives (arcs of the margin's radius). Where a corner this round
    /// does not fit within the margin, the board grows there (never into the margin);
    /// see `toolpath::board::rounded`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner_radius: Option<f64>,
    // holes
    /// `diameter` (holes only, required): hole diameter in design units, > 0 and at most
    /// [`MAX_COORD`](super::MAX_COORD).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
    /// `at` (holes only): `"ends"`, `"start"` or `"end"`; default `ends`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<HoleAt>,
    // fill
    /// `pattern` (fill only): `"hatch"` or `"concentric"`; default `hatch`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pattern: Option<FillPattern>,
    /// `angle` (fill and vcarve). Fill: hatch angle in degrees from +x, within ±360,
    /// default 0. Vcarve (required): the V-bit's included angle in degrees, 0 < angle < 180.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<f64>,
    /// `spacing` (fill only, required): distance between hatch lines or concentric rings,
    /// design units, > 0 and at most [`MAX_COORD`](super::MAX_COORD).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// `cross_hatch` (fill only): a second hatch at angle + 90°; default false.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cross_hatch: Option<bool>,
    /// `alternate` (fill only): alternate the direction of consecutive hatch lines;
    /// default true.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alternate: Option<bool>,
    // vcarve
    /// `max_depth` (vcarve only): depth cap of a V-carve (flat bottom beyond it), design
    /// units, > 0 and at most [`MAX_COORD`](super::MAX_COORD); default `depth`, else
    /// uncapped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<f64>,
    /// `air_assist`: air assist during the operation (lasers; default: the profile's
    /// `laser.air_assist`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub air_assist: Option<bool>,
    /// `method` (profile and backboard only): the skin route of the cut: `skin` (Bézier skin,
    /// general offset), `re` or `mph` (exact MAT offsets of the RE/MPH skin,
    /// re-skinning-cnc eq. 13). Unset: the build's `--method`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<OutlineMethod>,
    // line
    /// `boundaries` (line only): what the line follows. Unset: each selected item's own
    /// line (a stroke's spine, a shape's contours, a circle sequence's centres).
    /// `"inner"`: the visible boundaries between the selected items' differently coloured
    /// areas inside their union, each cut once (where one ink meets another, or a later
    /// item lies on an earlier one), and not their outer boundary, which a profile of the
    /// same items cuts (`toolpath::inks`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundaries: Option<LineBoundaries>,
}

/// What a `line` operation with `boundaries` follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LineBoundaries {
    /// The visible boundaries between differently coloured items inside their union.
    Inner,
}

impl Operation {
    /// An operation of `kind` with every parameter unset.
    #[must_use]
    pub fn new(kind: OperationKind) -> Self {
        Operation {
            kind,
            name: None,
            strokes: None,
            layers: None,
            colors: None,
            passes: None,
            step_down: None,
            depth: None,
            feed: None,
            power: None,
            tabs: None,
            lead_in: None,
            side: None,
            width: None,
            margin: None,
            min_inner_radius: None,
            bridge_width: None,
            mounting_holes: None,
            corner_radius: None,
            diameter: None,
            at: None,
            pattern: None,
            angle: None,
            spacing: None,
            cross_hatch: None,
            alternate: None,
            max_depth: None,
            air_assist: None,
            method: None,
            boundaries: None,
        }
    }
}
