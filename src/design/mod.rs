//! The design file model (format v1, TOML or JSON), its validation, and import.
//!
//! The library never reads files: [`load`] takes the text and the file name (whose
//! extension, `.toml` or `.json`, picks the format; [`from_str`] takes the format
//! explicitly). Parsing uses serde with unknown keys rejected; TOML and JSON errors carry
//! line:column. The version is checked before anything else.
//!
//! # Format v1
//!
//! ```toml
//! version = 1                 # required; other versions are rejected
//! units = "mm"                # or "inch"; default "mm"
//!
//! [outline]                   # optional
//! method = "skin"             # "skin" | "envelope" | "re" | "mph"
//! tolerance = 0.05            # > 0, design units
//!
//! [[stroke]]
//! name = "s1"                 # unique among strokes and circle sequences
//! degree = 3                  # default 3
//! closed = false              # default false
//! disks = [[0.0, 0.0, 2.0], [10.0, 5.0, 3.0], [20.0, 0.0, 2.0], [30.0, 4.0, 1.5]]  # [x, y, r]
//! knots = [0, 0, 0, 0, 1, 1, 1, 1]   # optional
//!
//! [stroke.attributes]         # optional; one value per control disk (wu-2021 eq. 18)
//! power = [20.0, 60.0, 60.0, 20.0]   # percent, 0..=100
//! depth = [1.0, 2.0, 2.0, 1.0]       # >= 0
//! feed = [800.0, 600.0, 600.0, 800.0]  # > 0, units per minute
//!
//! [[stroke]]                  # a stroke fitted to data points instead of control disks
//! name = "s2"
//! points = [[0.0, 0.0, 1.0], [5.0, 3.0, 1.5], [10.0, 0.0, 1.0], [15.0, 2.0, 1.2]]
//! fit = "interpolate"         # or "approximate"; default "interpolate"
//! parametrization = "chord"   # "centripetal" | "uniform"; default "chord" (wu-2021 eq. 16)
//! # control_disks = 4         # required for (and only for) fit = "approximate"
//!
//! [[circles]]                 # a circle sequence skinned directly
//! name = "c1"
//! closed = false
//! circles = [[0.0, 0.0, 2.0], [6.0, 1.0, 2.5], [12.0, 0.0, 2.0]]
//!
//! [[shape]]                   # a closed region: outer contours and holes ([`shape`])
//! name = "plate"
//! fill_rule = "nonzero"       # or "evenodd"; default "nonzero"
//! contours = [[[0.0, -10.0], [40.0, -10.0], [40.0, -4.0], [0.0, -4.0]]]  # [[x, y], ...]
//!
//! [neon]                      # optional: the LED-neon flex ([`neon`])
//! flex = "6mm"                # preset "6mm" | "8mm"; width, height, min_bend_radius,
//! min_bend_radius = 20.0      # cut_unit, hole_diameter, channel_depth, board_thickness,
//!                             # join_tolerance, break_at override it
//!
//! [[operation]]               # toolpath operations: plain data for the toolpath stage
//! kind = "channel"            # profile | channel | backboard | holes | fill | vcarve | line
//! # name = "channels"         # optional; `[[output]]` tables select by it
//! strokes = ["s1"]            # default: all strokes, circle sequences and shapes
//! # layers = ["cut"]          # also selects by the items' `layer` and `color` ([`select`])
//! # colors = ["#ff0000"]
//! width = 6.0
//! depth = 8.0
//!
//! [[output]]                  # optional: one program per output ([`output`])
//! name = "router"             # unique; letters, digits, `-`, `_`
//! machine = "grbl-router"     # a shipped profile or a .toml path
//! operations = ["channels", 2]  # names, kinds, 1-based numbers; or layers/colors selectors
//! # file = "{stem}.{name}.{ext}"
//! ```
//!
//! JSON files use the same keys: `{"version": 1, "units": "mm", "stroke": [{"name": "s1",
//! "disks": [[0, 0, 2], ...]}], "circles": [...], "shape": [{"name": "p", "contours":
//! [[[0, 0], [4, 0], [4, 3]]]}], "operation": [...]}`. Integers are accepted
//! wherever a number is expected.
//!
//! Knots. An open stroke's `knots` is the full knot vector: disks + degree + 1 values,
//! finite, non-decreasing, no value more than degree + 1 times, non-empty domain
//! [u_p, u_n]. Without `knots` it is clamped uniform on [0, 1]. A closed stroke's `knots`
//! lists the n + 1 strictly increasing breakpoints u_0 < … < u_n of one period (n = number of
//! disks; the period is u_n − u_0 and the knot spacing repeats around the wrap), exactly what
//! [`DiskBSpline::closed`](crate::dbsc::DiskBSpline::closed) takes; without `knots` the
//! breakpoints are uniform on [0, 1].
//!
//! Counts. A stroke without `knots` needs at least 2 disks or points (3 when closed): with
//! fewer than `degree + 1` its degree is lowered to one less than their number (two disks
//! give a straight spine, three a parabola; [`Stroke::effective_degree`]). A stroke with
//! `knots` keeps its degree and needs `degree + 1` disks. `degree` lies in 1..=10
//! ([`MAX_DEGREE`]); a list holds at most 10 000 entries ([`MAX_ITEMS`]). An open circle
//! sequence needs at least 2 circles, a closed one 3. An approximation needs
//! 2 ≤ `control_disks` ≤ points (its degree lowered to `control_disks` − 1 when needed).
//! Attribute channels have one value per control disk: `disks.len()`, `points.len()` for an
//! interpolation (one control disk per point), or `control_disks` for an approximation.
//! A design needs at least one stroke, circle sequence or shape.
//!
//! Shapes. `[[shape]]` holds closed polylines `contours = [[[x, y], ...], ...]` (outer
//! boundaries and holes) and a `fill_rule`, "nonzero" (default) or "evenodd" as in SVG;
//! contours may cross each other but not themselves, each has at least 3 points and a
//! non-zero area. Profile, fill and backboard operations cut a shape's region joined with
//! the stroke outlines they select; channel, holes and V-carve follow spines and skip
//! shapes. Names are unique among strokes, circle sequences and shapes. See [`Shape`].
//!
//! Values. Every disk, point and circle is exactly `[x, y, r]` (a list of another length is
//! a parse error with line:column). All numbers finite, |x|, |y|, r ≤ 1e7 design units
//! ([`MAX_COORD`]), r ≥ 1e-4 ([`MIN_RADIUS`]); no disk, point or circle equal or nearly
//! equal (closer than 1e-9 of the item's size, [`NEAR_FRACTION`]) to the one before it (for
//! closed lists also the last to the first); remove one of such a pair.
//!
//! Ranges of the operation keys (one policy: a value outside its range is an error naming
//! the operation by index and kind, and the key): `passes` 1..=1000 ([`MAX_PASSES`], also
//! for `depth / step_down`); `feed` in (0, 1e6] units/min ([`MAX_FEED`], also for the feed
//! attribute); `power` 0..=100; lengths (`depth`, `step_down`, `width`, `margin`,
//! `diameter`, `spacing`, `max_depth`, `tabs.width`, `tabs.height`: > 0; `lead_in`,
//! `min_inner_radius`: ≥ 0) at most 1e7; `tabs.count` 1..=100 ([`MAX_TABS`]); fill `angle`
//! within ±360 degrees.
//!
//! Operations. Common keys: `strokes`, `passes` (≥ 1), `step_down`, `depth`, `feed` (> 0),
//! `power` (percent; lasers default to the profile's `laser.default_power`),
//! `air_assist` (lasers: true/false, default the profile's `laser.air_assist`),
//! `tabs = { count, width, height }`, `lead_in` (≥ 0). Per kind:
//! profile `side` = "on" | "outside" | "inside"; channel `width` (required); backboard
//! `margin`, `min_inner_radius`, `bridge_width` (≥ 0, default 10 mm: the board's pieces are
//! bridged into one, `toolpath::board`; 0 leaves them apart), `mounting_holes =
//! { count, diameter, inset }` (count 1..=100, diameter > 0, inset > 0, default 8 mm),
//! `corner_radius` (≥ 0: the board's convex corners at least this round,
//! `toolpath::board::rounded`);
//! holes `diameter` (required), `at` = "ends" | "start" |
//! "end"; fill `pattern` = "hatch" | "concentric", `angle` (degrees), `spacing` (required),
//! `cross_hatch`, `alternate`; vcarve `angle` (the bit's included angle, 0 < angle < 180,
//! required), `max_depth`; line: only `strokes`/`layers`/`colors`, `passes`, `step_down`,
//! `depth` (routers; default a shallow engraving depth), `feed`, `power`, `air_assist`
//! (no `lead_in`, no `tabs`). A per-kind key on another kind is an error, and so is a name
//! in `strokes` that no stroke, circle sequence or shape has.
//!
//! Layers and colours. Strokes and shapes may carry `layer = "..."` (any label) and
//! `color = "#rrggbb"` (six hexadecimal digits, any case; loading writes lower case).
//! Operations select by them with `layers = [...]` and `colors = [...]` beside `strokes`:
//! an item is selected when any given selector names it ([`Selection`]). Each list is
//! non-empty; a layer or colour that no stroke or shape has is an error that lists the
//! design's layers (colours).
//!
//! Neon. `[neon]` describes the LED flex a sign is made for (presets `flex = "6mm"` and
//! `"8mm"`, each key overriding; `[[neon.run]]` tables with `strokes = [...]` make explicit
//! runs, `break_at = [[x, y], ...]` breaks joins, `round_bends = true` rounds bends tighter
//! than `min_bend_radius` to that radius, `min_run_length` makes shorter runs marks). With it, channel, holes and backboard
//! operations take the flex's sizes for the keys they leave unset, holes go where flex runs
//! end, and `build` reports the bill of materials (`job::neon`). Errors name the
//! key: `file: [neon] cut_unit: -1 must be positive and at most 10000000`. See [`Neon`].
//!
//! Geometry: [`Design::strokes`] gives every stroke as a
//! [`DiskBSpline`](crate::dbsc::DiskBSpline) (points strokes through
//! `DiskBSpline::interpolate`/`approximate`), [`Design::circle_sequences`] the circle lists,
//! and [`Stroke::attribute_curves`] the attribute channels as scalar B-splines on the
//! stroke's knots (wu-2021 eq. 18).
//!
//! Errors ([`DesignError`]) read `file: stroke 1 "s2", disk 3: radius -1 must be positive`,
//! or `file:12:5: unknown field ...` for syntax errors; indices are 0-based.

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
