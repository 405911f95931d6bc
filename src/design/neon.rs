//! The `[neon]` table: the LED-neon flex a sign is made for.
//!
//! ```toml
//! [neon]
//! flex = "6mm"              # preset: "6mm" | "8mm"; default "6mm"; the keys below override it
//! width = 6.0               # flex width (what the channel holds), design units
//! height = 10.0             # flex height
//! min_bend_radius = 15.0    # tightest spine radius the flex takes (datasheet), design units
//! cut_unit = 25.0           # length step at which the flex may be cut
//! hole_diameter = 4.0       # wire hole diameter
//! channel_depth = 10.0      # depth of the routed channel
//! board_thickness = 12.0    # thickness of the board (holes and backboard go through it)
//! join_tolerance = 6.0      # stroke ends at most this far apart join into one run; default: width
//! break_at = [[40.0, 25.0]] # joins within the flex width of these points are not made
//! round_bends = false       # true: bends tighter than min_bend_radius become arcs of that radius
//! min_run_length = 20.0     # shorter runs are marks: channel cut, no flex, no holes; default unset
//!
//! [[neon.run]]              # an explicit run: these strokes, in this order
//! name = "underline"        # default "run N"
//! strokes = ["bar", "tail"] # stroke names; a text or a stroke split at corners stands for its strokes
//! ```
//!
//! Presets ([`FlexPreset`], typical of 12 V silicone side-bend neon flex; check your flex's
//! datasheet and override what differs):
//!
//! | key | `"6mm"` | `"8mm"` |
//! |---|---|---|
//! | `width` | 6 | 8 |
//! | `height` | 10 | 12 |
//! | `min_bend_radius` | 15 | 25 |
//! | `cut_unit` | 25 | 50 |
//! | `hole_diameter` | 4 | 6 |
//! | `channel_depth` | 10 | 12 |
//! | `board_thickness` | 12 | 18 |
//!
//! (millimetres, converted to the design's units.) `join_tolerance` defaults to the flex
//! width: stroke ends closer than that lie in one pocket anyway (their channels, wider than
//! the flex, overlap), so the flex continues from one to the other; a script font's letters
//! meet within a grid unit of each other (about 1 mm at a 22 mm cap height), not exactly.
//!
//! With a `[neon]` table, operations take the flex's sizes where they leave a key unset
//! ([`apply_defaults`]): a channel's `width` is the flex width plus
//! [`CHANNEL_CLEARANCE_MM`] and its `depth` the channel depth; holes take `diameter` =
//! `hole_diameter` and `depth` = `board_thickness` (through the board); a backboard takes
//! `depth` = `board_thickness`. Holes are then drilled where flex runs end, not at every
//! stroke end (the neon stage of the build).
//!
//! Validation ([`validate`]): every length finite, > 0 and at most
//! [`MAX_COORD`](super::MAX_COORD) (`join_tolerance` ≥ 0); `break_at` points finite; a run's
//! `strokes` non-empty, each name a stroke (or a text or split stroke), no stroke in two
//! runs; run names non-empty and unique. Errors name the key: `file: [neon] cut_unit: -1
//! must be positive`.

use super::error::{DesignError, ErrorKind};
use super::model::{Design, OperationKind};
use super::validate::MAX_COORD;
use crate::units::Units;
use serde::{Deserialize, Serialize};

/// Clearance added to the flex width for a channel's default width (mm): the flex slides in
/// without binding, and the channels of `examples/` (6.5 mm for 6 mm flex, 8.5 mm for 8 mm)
/// have it.
pub const CHANNEL_CLEARANCE_MM: f64 = 0.5;

/// A flex preset: the sizes of a common flex.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FlexPreset {
    /// `"6mm"`: 6 × 10 mm flex.
    #[default]
    #[serde(rename = "6mm")]
    Mm6,
    /// `"8mm"`: 8 × 12 mm flex.
    #[serde(rename = "8mm")]
    Mm8,
}

impl FlexPreset {
    /// The preset's sizes in millimetres (see the module docs' table).
    #[must_use]
    pub fn sizes_mm(self) -> Flex {
        let (width, height, min_bend_radius, cut_unit, hole_diameter, channel_depth, board) =
            match self {
                FlexPreset::Mm6 => (6.0, 10.0, 15.0, 25.0, 4.0, 10.0, 12.0),
                FlexPreset::Mm8 => (8.0, 12.0, 25.0, 50.0, 6.0, 12.0, 18.0),
            };
        Flex {
            width,
            height,
            min_bend_radius,
            cut_unit,
            hole_diameter,
            channel_depth,
            board_thickness: board,
            join_tolerance: width,
        }
    }
}

/// The `[neon]` table as written (see the module docs).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Neon {
    /// `flex`: the preset the other keys override; default `"6mm"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flex: Option<FlexPreset>,
    /// `width`: flex width, design units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// `height`: flex height, design units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// `min_bend_radius`: the tightest spine radius the flex takes, design units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_bend_radius: Option<f64>,
    /// `cut_unit`: the length step at which the flex may be cut, design units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cut_unit: Option<f64>,
    /// `hole_diameter`: wire hole diameter, design units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hole_diameter: Option<f64>,
    /// `channel_depth`: depth of the channel, design units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel_depth: Option<f64>,
    /// `board_thickness`: thickness of the board, design units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub board_thickness: Option<f64>,
    /// `join_tolerance`: stroke ends at most this far apart are joined into one run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub join_tolerance: Option<f64>,
    /// `break_at`: points `[x, y]`; a join within the flex width of one is not made.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub break_at: Option<Vec<[f64; 2]>>,
    /// `round_bends`: before the channel is made, replace every bend of a run tighter than
    /// `min_bend_radius` by an arc of that radius tangent to the spine before and after it
    /// (the neon stage of the build); default false (bends tighter than the flex are warned
    /// about and cut as drawn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub round_bends: Option<bool>,
    /// `min_run_length`: runs shorter than this (design units) are marks, not flex: their
    /// channel is still cut (a pocket to paint or fill), they get no wire holes and are
    /// left out of the flex totals (listed as `neon.marks`). Unset: every run is flex, and
    /// one shorter than the cut unit is warned about.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_run_length: Option<f64>,
    /// `[[neon.run]]`: explicit runs.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub run: Vec<NeonRun>,
}

/// A `[[neon.run]]`: strokes that make one run, in order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NeonRun {
    /// `name`: the run's name in the bill of materials; default `run N`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// `strokes` (required): the run's strokes in order (a text or a split stroke stands
    /// for its strokes in layout order).
    pub strokes: Vec<String>,
}

/// The flex's sizes in design units, presets resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flex {
    /// Flex width.
    pub width: f64,
    /// Flex height.
    pub height: f64,
    /// Tightest spine radius the flex takes.
    pub min_bend_radius: f64,
    /// Length step at which the flex may be cut.
    pub cut_unit: f64,
    /// Wire hole diameter.
    pub hole_diameter: f64,
    /// Channel depth.
    pub channel_depth: f64,
    /// Board thickness.
    pub board_thickness: f64,
    /// Stroke ends at most this far apart are joined.
    pub join_tolerance: f64,
}

impl Neon {
    /// The flex in design units of `units`: the preset (converted from mm) with every key
    /// that is set put over it.
    #[must_use]
    pub fn flex(&self, units: Units) -> Flex {
        let per_mm = 1.0 / units.mm_per_unit();
        let p = self.flex.unwrap_or_default().sizes_mm();
        let pick = |v: Option<f64>, mm: f64| v.unwrap_or(mm * per_mm);
        let width = pick(self.width, p.width);
        Flex {
            width,
            height: pick(self.height, p.height),
            min_bend_radius: pick(self.min_bend_radius, p.min_bend_radius),
            cut_unit: pick(self.cut_unit, p.cut_unit),
            hole_diameter: pick(self.hole_diameter, p.hole_diameter),
            channel_depth: pick(self.channel_depth, p.channel_depth),
            board_thickness: pick(self.board_thickness, p.board_thickness),
            join_tolerance: self.join_tolerance.unwrap_or(width),
        }
    }
}

/// The indices of the strokes `name` stands for in `design` (expanded): the stroke of that
/// name, else the pieces `name#k` of a stroke split at corners and the strokes `name/…` of a
/// text, in design order. Empty when nothing matches.
pub fn strokes_named(design: &Design, name: &str) -> Vec<usize> {
    if let Some(i) = design.stroke.iter().position(|s| s.name == name) {
        return vec![i];
    }
    let (piece, text) = (format!("{name}#"), format!("{name}/"));
    design
        .stroke
        .iter()
        .enumerate()
        .filter(|(_, s)| s.name.starts_with(&piece) || s.name.starts_with(&text))
        .map(|(i, _)| i)
        .collect()
}

fn invalid(file: &str, key: &str, message: String) -> DesignError {
    DesignError::file(file, ErrorKind::Invalid(format!("[neon] {key}: {message}")))
}

/// Checks the `[neon]` table of `design` (module docs); a design without one passes.
pub fn validate(design: &Design) -> Result<(), DesignError> {
    let Some(n) = &design.neon else {
        return Ok(());
    };
    let file = design.file.as_str();
    let lengths = [
        ("width", n.width),
        ("height", n.height),
        ("min_bend_radius", n.min_bend_radius),
        ("cut_unit", n.cut_unit),
        ("hole_diameter", n.hole_diameter),
        ("channel_depth", n.channel_depth),
        ("board_thickness", n.board_thickness),
        ("min_run_length", n.min_run_length),
    ];
    for (key, v) in lengths {
        if let Some(v) = v
            && !(v.is_finite() && v > 0.0 && v <= MAX_COORD)
        {
            return Err(invalid(
                file,
                key,
                format!("{v} must be positive and at most {MAX_COORD}"),
            ));
        }
    }
    if let Some(v) = n.join_tolerance
        && !(v.is_finite() && (0.0..=MAX_COORD).contains(&v))
    {
        return Err(invalid(
            file,
            "join_tolerance",
            format!("{v} must be between 0 and {MAX_COORD}"),
        ));
    }
    for (k, p) in n.break_at.iter().flatten().enumerate() {
        if !p.iter().all(|x| x.is_finite() && x.abs() <= MAX_COORD) {
            return Err(invalid(
                file,
                "break_at",
                format!("point {k} {p:?} must be finite, within ±{MAX_COORD}"),
            ));
        }
    }
    let mut owner: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut names = std::collections::HashSet::new();
    for (r, run) in n.run.iter().enumerate() {
        let key = format!("run {r}");
        if let Some(name) = &run.name {
            if name.trim().is_empty() {
                return Err(invalid(file, &key, "`name` must not be empty".into()));
            }
            if !names.insert(name.as_str()) {
                return Err(invalid(
                    file,
                    &key,
                    format!("`name` \"{name}\" is used by another run"),
                ));
            }
        }
        if run.strokes.is_empty() {
            return Err(invalid(
                file,
                &key,
                "`strokes` must name at least one stroke".into(),
            ));
        }
        let mut mine = std::collections::HashSet::new();
        for s in &run.strokes {
            let found = strokes_named(design, s);
            if found.is_empty() {
                return Err(invalid(
                    file,
                    &key,
                    format!("`strokes`: no stroke (nor text or split stroke) is named \"{s}\""),
                ));
            }
            for i in found {
                let stroke = &design.stroke[i].name;
                if !mine.insert(i) {
                    return Err(invalid(
                        file,
                        &key,
                        format!("`strokes`: stroke \"{stroke}\" is named twice"),
                    ));
                }
                if let Some(other) = owner.insert(i, r) {
                    return Err(invalid(
                        file,
                        &key,
                        format!("`strokes`: stroke \"{stroke}\" is already in run {other}"),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Fills the keys operations leave unset from the `[neon]` table (module docs); a design
/// without one is unchanged. Loading calls this after expanding texts and corners and
/// before validation.
pub fn apply_defaults(design: &mut Design) {
    let Some(n) = &design.neon else {
        return;
    };
    let f = n.flex(design.units);
    let clearance = CHANNEL_CLEARANCE_MM / design.units.mm_per_unit();
    for op in &mut design.operation {
        match op.kind {
            OperationKind::Channel => {
                op.width.get_or_insert(f.width + clearance);
                op.depth.get_or_insert(f.channel_depth);
            }
            OperationKind::Holes => {
                op.diameter.get_or_insert(f.hole_diameter);
                op.depth.get_or_insert(f.board_thickness);
            }
            OperationKind::Backboard => {
                op.depth.get_or_insert(f.board_thickness);
            }
            _ => {}
        }
    }
}
