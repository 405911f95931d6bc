//! Machine profiles: what a machine can do and how its controller wants to be spoken to.
//!
//! Profiles are data (`machines/*.toml`), parsed with `deny_unknown_fields` and a `version`
//! field, then validated; every error names the file and the key.

use super::dialect::Dialect;
use super::template;
use serde::Deserialize;
use std::fmt;

/// The only profile format version this build reads.
pub const PROFILE_VERSION: u32 = 1;

/// What kind of machine (or file) a profile describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MachineKind {
    /// A laser driven by G-code.
    Laser,
    /// A router or mill driven by G-code (spindle, Z axis).
    Router,
    /// A laser cutter fed with SVG (or DXF) files by its own software.
    Svg,
}

/// Length units of the machine's coordinates and feeds (the crate's one
/// [`crate::units::Units`]).
pub use crate::units::Units;

/// How arcs are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ArcFormat {
    /// G2/G3 with the centre as I J offsets from the start (centre format).
    Ij,
    /// G2/G3 with a radius R (no full circles; long arcs are split).
    R,
    /// No arcs: flattened to G1 lines within the caller's tolerance.
    None,
}

/// A closed interval `[min, max]` of one axis.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
pub struct Range(pub f64, pub f64);

impl Range {
    /// Lower end of the range.
    pub fn min(&self) -> f64 {
        self.0
    }
    /// Upper end of the range.
    pub fn max(&self) -> f64 {
        self.1
    }
    /// True when `v` lies in the range, with slack `tol`.
    #[must_use]
    pub fn contains(&self, v: f64, tol: f64) -> bool {
        v >= self.0 - tol && v <= self.1 + tol
    }
}

/// The travel of each axis, in the profile's units.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkArea {
    /// Travel of the x axis.
    pub x: Range,
    /// Travel of the y axis.
    pub y: Range,
    /// Travel of the z axis.
    pub z: Range,
}

/// A value per axis (maximum feed in units/min, acceleration in units/s²).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axes {
    /// Value for the x axis.
    pub x: f64,
    /// Value for the y axis.
    pub y: f64,
    /// Value for the z axis.
    pub z: f64,
}

/// The controller's power word range: laser `S` (GRBL `$30`, Marlin 0..255, Smoothie 0..1)
/// or spindle rpm.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PowerRange {
    /// Smallest non-zero value the machine runs at (spindle minimum rpm; 0 for lasers).
    pub min: f64,
    /// Largest value (full power, or maximum spindle rpm).
    pub max: f64,
}

/// What a tool is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToolKind {
    /// Flat end mill.
    Endmill,
    /// Ball nose end mill.
    Ballnose,
    /// V-bit (engraving cutter) with an included angle.
    Vbit,
    /// A laser beam with a kerf.
    Beam,
}

/// One tool the machine holds.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tool {
    /// Name the design's operations refer to the tool by.
    pub name: String,
    /// What the tool is.
    pub kind: ToolKind,
    /// Cutter diameter (end mills, V-bit shank at full depth); unused for beams.
    #[serde(default)]
    pub diameter: f64,
    /// Kerf width of a beam (the width of the cut line).
    #[serde(default)]
    pub kerf: f64,
    /// Included angle of a V-bit, in degrees.
    #[serde(default)]
    pub angle: f64,
    /// Flat tip diameter of a V-bit (0 for a sharp tip).
    #[serde(default)]
    pub tip_diameter: f64,
}

impl Tool {
    /// Compensation radius: half the kerf for a beam, half the diameter otherwise.
    #[must_use]
    pub fn radius(&self) -> f64 {
        match self.kind {
            ToolKind::Beam => 0.5 * self.kerf,
            _ => 0.5 * self.diameter,
        }
    }
}

/// Laser spindle-mode command.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LaserMode {
    /// `M4`: GRBL dynamic power (scaled with speed); G0 never fires in laser mode.
    Dynamic,
    /// `M3`: constant power.
    Constant,
}

/// How the emitter makes sure the beam is off during a rapid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RapidOff {
    /// The controller never fires on G0 (GRBL `M4` in laser mode, Smoothie's laser module).
    Firmware,
    /// Set `S0` before the rapid (GRBL `M3`).
    S0,
    /// Turn the laser off with `M5` before the rapid and on again at the next cut (Marlin).
    M5,
}

/// Laser specifics.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LaserSettings {
    /// Constant (M3) or dynamic (M4) power.
    pub mode: LaserMode,
    /// Power as an `S` word on each cutting move (GRBL, Smoothie, Marlin `M3 I`); otherwise
    /// power is set on the `M3`/`M4` line and changes need a new `M3`/`M4`.
    pub inline_power: bool,
    /// Extra words on the laser-on line, e.g. `"I"` for Marlin's inline mode.
    #[serde(default)]
    pub on_suffix: String,
    /// Whether the dialect needs an `M3`/`M4` at all (Smoothie fires on `G1 S` alone).
    #[serde(default = "default_true")]
    pub needs_on_command: bool,
    /// How the beam is kept off during rapids.
    pub rapid_off: RapidOff,
    /// Wait after the beam comes on at a cut start, in seconds (0 = none).
    #[serde(default)]
    pub pierce_dwell: f64,
    /// Power in percent of `power.max` for operations that set no `power`
    /// (default `DEFAULT_LASER_POWER`): a design without power settings must not burn
    /// at full power.
    #[serde(default)]
    pub default_power: Option<f64>,
    /// Air assist on for every operation that does not say (`air_assist` in the design).
    #[serde(default)]
    pub air_assist: bool,
    /// Line that switches air assist on (default `M8`: flood coolant, which GRBL, Marlin's
    /// AIR_ASSIST and Smoothie's default switch module map to the air valve).
    #[serde(default = "default_air_on")]
    pub air_on: String,
    /// Line that switches air assist off (default `M9`).
    #[serde(default = "default_air_off")]
    pub air_off: String,
}

/// Laser power in percent for operations without `power` when the profile sets no
/// `laser.default_power`: low enough to mark rather than cut through most stock.
pub const DEFAULT_LASER_POWER: f64 = 20.0;

fn default_air_on() -> String {
    "M8".to_string()
}

fn default_air_off() -> String {
    "M9".to_string()
}

impl LaserSettings {
    /// Power in percent for operations that set none.
    #[must_use]
    pub fn default_power(&self) -> f64 {
        self.default_power.unwrap_or(DEFAULT_LASER_POWER)
    }
}

fn default_true() -> bool {
    true
}

/// Router specifics.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RouterSettings {
    /// Height for every XY rapid.
    pub safe_z: f64,
    /// Height down to which a rapid may descend before plunging at `plunge_feed`.
    pub clearance_z: f64,
    /// Feed for plunges (units/min); a cut's pure downward moves never go faster.
    pub plunge_feed: f64,
    /// Wait after the spindle starts or changes speed, in seconds.
    pub spindle_dwell: f64,
}

/// G-code output specifics.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GcodeSettings {
    /// Decimals of coordinates (3 for mm, 4 for inch).
    pub decimals: u32,
    /// How arcs are written (I J centre, R radius, or flattened to lines).
    pub arcs: ArcFormat,
    /// Path blending tolerance for LinuxCNC `G64 P` (placeholder `{path_tolerance}`).
    #[serde(default)]
    pub path_tolerance: Option<f64>,
    /// Lines after the `G17 G2x G90 G94` setup line (placeholders allowed).
    #[serde(default)]
    pub preamble: String,
    /// Lines after the tool is off, before `program_end` (placeholders allowed).
    #[serde(default)]
    pub postamble: String,
    /// The program end word: `M2`, `M30`, or empty where the controller has none (Marlin).
    pub program_end: String,
    /// Write comments (operation names, sources).
    #[serde(default = "default_true")]
    pub comments: bool,
}

/// Stroke colours per operation kind, `#rrggbb`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperationColors {
    /// Colour of profile cuts.
    pub profile: String,
    /// Colour of channel cuts.
    pub channel: String,
    /// Colour of backboard cuts.
    pub backboard: String,
    /// Colour of holes.
    pub holes: String,
    /// Colour of fills.
    pub fill: String,
    /// Colour of V-carving.
    pub vcarve: String,
}

/// SVG/DXF output specifics.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SvgSettings {
    /// Stroke width in mm (hairline: 0.01 mm or the shop's own).
    pub stroke_width: f64,
    /// Stroke colour per operation kind.
    pub colors: OperationColors,
}

/// A machine profile.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    /// Profile format version.
    pub version: u32,
    /// Profile name, as given to `--machine`.
    pub name: String,
    /// One line saying what the machine is.
    #[serde(default)]
    pub description: String,
    /// Router (G-code) or laser (G-code or SVG).
    pub kind: MachineKind,
    /// The G-code dialect of the controller.
    pub dialect: Dialect,
    /// Units of coordinates and feeds.
    pub units: Units,
    /// Travel of each axis.
    pub work_area: WorkArea,
    /// Maximum feed per axis, units/min.
    pub max_feed: Axes,
    /// Acceleration per axis, units/s².
    pub acceleration: Axes,
    /// Range of the power word (laser S or spindle rpm).
    pub power: PowerRange,
    /// The tools the machine holds.
    #[serde(default)]
    pub tools: Vec<Tool>,
    /// G-code output settings (G-code machines).
    #[serde(default)]
    pub gcode: Option<GcodeSettings>,
    /// Laser settings (lasers).
    #[serde(default)]
    pub laser: Option<LaserSettings>,
    /// Router settings (routers).
    #[serde(default)]
    pub router: Option<RouterSettings>,
    /// SVG/DXF output settings (SVG lasers).
    #[serde(default)]
    pub svg: Option<SvgSettings>,
}

/// A profile that failed to load: the file, the key (dotted path) and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub struct ProfileError {
    /// The profile file (or built-in name).
    pub file: String,
    /// Dotted key path (`router.safe_z`), or the line's key for syntax errors.
    pub key: String,
    /// 1-based line number for syntax and type errors, when known.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
    /// Which kind of failure.
    pub kind: ProfileErrorKind,
}

/// The kind of a [`ProfileError`].
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ProfileErrorKind {
    /// The text does not parse, or a value is missing or out of range.
    Invalid,
    /// [`builtin_profile`](super::builtin_profile) was asked for a name no shipped profile has.
    UnknownBuiltin {
        /// The name asked for.
        name: String,
    },
}

impl ProfileError {
    /// An error about the text of the profile `file`.
    fn invalid(file: &str, key: String, line: Option<usize>, message: String) -> Self {
        ProfileError {
            file: file.to_string(),
            key,
            line,
            message,
            kind: ProfileErrorKind::Invalid,
        }
    }

    /// No shipped profile is called `name`: the message lists the shipped ones.
    pub(crate) fn unknown_builtin(name: &str) -> Self {
        let shipped: Vec<&str> = super::builtin_names().collect();
        ProfileError {
            file: name.to_string(),
            key: String::new(),
            line: None,
            message: format!(
                "no built-in machine profile of this name (built-in: {})",
                shipped.join(", ")
            ),
            kind: ProfileErrorKind::UnknownBuiltin {
                name: name.to_string(),
            },
        }
    }

    /// Whether the error is a name no shipped profile has (rather than a faulty profile).
    #[must_use]
    pub fn is_unknown_builtin(&self) -> bool {
        matches!(self.kind, ProfileErrorKind::UnknownBuiltin { .. })
    }
}

impl fmt::Display for ProfileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if !self.key.is_empty() {
            write!(f, ": key `{}`", self.key)?;
        }
        write!(f, ": {}", self.message)
    }
}

impl Profile {
    /// Parses and validates a profile; `file_name` is used in error messages only.
    pub fn from_toml(text: &str, file_name: &str) -> Result<Profile, ProfileError> {
        let profile: Profile = toml::from_str(text).map_err(|e| {
            let (line, key) = match e.span() {
                Some(span) => locate(text, span.start),
                None => (None, String::new()),
            };
            let msg = e.message();
            let names_field = msg.contains("unknown field") || msg.contains("missing field");
            let key = if names_field {
                backticked(msg).unwrap_or(key)
            } else {
                key
            };
            ProfileError::invalid(file_name, key, line, e.message().trim().to_string())
        })?;
        profile
            .validate()
            .map_err(|(key, message)| ProfileError::invalid(file_name, key, None, message))?;
        Ok(profile)
    }

    /// The G-code settings, for G-code profiles (validated to be present for laser/router).
    pub fn gcode_settings(&self) -> Option<&GcodeSettings> {
        self.gcode.as_ref()
    }

    /// The first tool, if the profile names any.
    pub fn default_tool(&self) -> Option<&Tool> {
        self.tools.first()
    }

    /// Semantic checks after parsing; the error is (key, message).
    fn validate(&self) -> Result<(), (String, String)> {
        let err = |k: &str, m: String| Err((k.to_string(), m));
        if self.version != PROFILE_VERSION {
            return err(
                "version",
                format!(
                    "unsupported profile version {} (this build reads {PROFILE_VERSION})",
                    self.version
                ),
            );
        }
        if self.name.trim().is_empty() {
            return err("name", "must not be empty".into());
        }
        for (axis, r) in [
            ("x", self.work_area.x),
            ("y", self.work_area.y),
            ("z", self.work_area.z),
        ] {
            let lim = MAX_LENGTH_MM / self.units.mm_per_unit();
            if !(r.0.is_finite() && r.1.is_finite() && r.0 <= r.1 && r.0 >= -lim && r.1 <= lim) {
                return err(
                    &format!("work_area.{axis}"),
                    format!(
                        "needs [min, max] with min <= max within ±{lim}, got [{}, {}]",
                        r.0, r.1
                    ),
                );
            }
        }
        if self.work_area.x.0 >= self.work_area.x.1 || self.work_area.y.0 >= self.work_area.y.1 {
            return err(
                "work_area",
                "x and y ranges must have positive length".into(),
            );
        }
        for (table, axes) in [
            ("max_feed", self.max_feed),
            ("acceleration", self.acceleration),
        ] {
            for (axis, v) in [("x", axes.x), ("y", axes.y), ("z", axes.z)] {
                let lim = MAX_RATE_MM / self.units.mm_per_unit();
                if !(v.is_finite() && v >= 0.0 && v <= lim) || (axis != "z" && v <= 0.0) {
                    return err(
                        &format!("{table}.{axis}"),
                        format!("must be a positive number up to {lim}, got {v}"),
                    );
                }
            }
        }
        let p = self.power;
        if !(p.min.is_finite()
            && p.max.is_finite()
            && p.min >= 0.0
            && p.max > 0.0
            && p.min <= p.max)
        {
            return err(
                "power",
                format!(
                    "needs 0 <= min <= max and max > 0, got min {} max {}",
                    p.min, p.max
                ),
            );
        }
        for (i, t) in self.tools.iter().enumerate() {
            validate_tool(t, self.units.mm_per_unit()).map_err(|(k, m)| {
                (
                    format!("tools[{i}].{k}"),
                    format!("tool \"{}\": {m}", t.name),
                )
            })?;
        }
        if self.kind == MachineKind::Router && self.tools.is_empty() {
            return err(
                "tools",
                "a router profile needs at least one [[tools]] entry (kind = \"endmill\", \
                 \"ballnose\" or \"vbit\" with its diameter)"
                    .into(),
            );
        }
        let needs = |section: &str, present: bool| -> Result<(), (String, String)> {
            if present {
                Ok(())
            } else {
                err(
                    section,
                    format!("a {:?} profile needs a [{section}] table", self.kind).to_lowercase(),
                )
            }
        };
        let forbids = |section: &str, present: bool| -> Result<(), (String, String)> {
            if present {
                err(
                    section,
                    format!(
                        "a {:?} profile must not have a [{section}] table",
                        self.kind
                    )
                    .to_lowercase(),
                )
            } else {
                Ok(())
            }
        };
        match self.kind {
            MachineKind::Laser => {
                needs("gcode", self.gcode.is_some())?;
                needs("laser", self.laser.is_some())?;
                forbids("router", self.router.is_some())?;
            }
            MachineKind::Router => {
                needs("gcode", self.gcode.is_some())?;
                needs("router", self.router.is_some())?;
                forbids("laser", self.laser.is_some())?;
            }
            MachineKind::Svg => {
                needs("svg", self.svg.is_some())?;
                forbids("gcode", self.gcode.is_some())?;
                forbids("router", self.router.is_some())?;
                if self.units != Units::Mm {
                    return err("units", "SVG profiles are in mm".into());
                }
            }
        }
        if self.kind != MachineKind::Svg && self.dialect == Dialect::None {
            return err("dialect", "a G-code profile needs a dialect".into());
        }
        if let Some(g) = &self.gcode {
            if g.decimals > 6 {
                return err(
                    "gcode.decimals",
                    format!("must be 0..=6, got {}", g.decimals),
                );
            }
            if let Some(t) = g.path_tolerance
                && !(t.is_finite() && t >= 0.0)
            {
                return err("gcode.path_tolerance", format!("must be >= 0, got {t}"));
            }
            template::check(&g.preamble).map_err(|m| ("gcode.preamble".to_string(), m))?;
            template::check(&g.postamble).map_err(|m| ("gcode.postamble".to_string(), m))?;
            for (key, text) in [
                ("gcode.preamble", &g.preamble),
                ("gcode.postamble", &g.postamble),
            ] {
                if let Some((line, word, why)) = forbidden_m_word(text) {
                    return err(
                        key,
                        format!(
                            "line {line} holds {word}, which would {why}; the program's own \
                             setup and end handle it: remove it (program_end sets the end word)"
                        ),
                    );
                }
            }
            if let Some(t) = g.path_tolerance
                && t > MAX_LENGTH_MM / self.units.mm_per_unit()
            {
                return err(
                    "gcode.path_tolerance",
                    format!("must be at most {MAX_LENGTH_MM} mm, got {t}"),
                );
            }
            if template::uses(&g.preamble, "path_tolerance") && g.path_tolerance.is_none() {
                return err(
                    "gcode.path_tolerance",
                    "the preamble uses {path_tolerance} but it is not set".into(),
                );
            }
            if !["M2", "M30", ""].contains(&g.program_end.as_str()) {
                return err(
                    "gcode.program_end",
                    format!("must be \"M2\", \"M30\" or \"\", got {:?}", g.program_end),
                );
            }
        }
        if let Some(l) = &self.laser {
            if !(l.pierce_dwell.is_finite() && (0.0..=MAX_DWELL_S).contains(&l.pierce_dwell)) {
                return err(
                    "laser.pierce_dwell",
                    format!("must be in 0..={MAX_DWELL_S} s, got {}", l.pierce_dwell),
                );
            }
            if let Some(p) = l.default_power
                && !(p.is_finite() && (0.0..=100.0).contains(&p))
            {
                return err(
                    "laser.default_power",
                    format!("must be a percentage in 0..=100, got {p}"),
                );
            }
            for (key, code) in [("laser.air_on", &l.air_on), ("laser.air_off", &l.air_off)] {
                let t = code.trim().to_ascii_uppercase();
                if t.contains("M2") || t.contains("M30") || t.contains("M3") || t.contains("M4") {
                    return err(
                        key,
                        format!("must switch the air only (e.g. M8/M9), got {code:?}"),
                    );
                }
            }
            if !l.inline_power && !l.needs_on_command {
                return err(
                    "laser.needs_on_command",
                    "without inline_power the power is set by M3/M4, so it must be true".into(),
                );
            }
        }
        if let Some(r) = &self.router {
            let z = self.work_area.z;
            if !(r.safe_z.is_finite() && r.safe_z > 0.0 && z.contains(r.safe_z, 0.0)) {
                return err(
                    "router.safe_z",
                    format!(
                        "must be above the stock (> 0) and within work_area.z [{}, {}], got {}",
                        z.0, z.1, r.safe_z
                    ),
                );
            }
            if !(r.clearance_z.is_finite() && r.clearance_z >= 0.0 && r.clearance_z <= r.safe_z) {
                return err(
                    "router.clearance_z",
                    format!("must be in [0, safe_z], got {}", r.clearance_z),
                );
            }
            if !(r.plunge_feed.is_finite()
                && r.plunge_feed > 0.0
                && r.plunge_feed <= self.max_feed.z)
            {
                return err(
                    "router.plunge_feed",
                    format!(
                        "must be in (0, max_feed.z = {}], got {}",
                        self.max_feed.z, r.plunge_feed
                    ),
                );
            }
            if !(r.spindle_dwell.is_finite() && (0.0..=MAX_DWELL_S).contains(&r.spindle_dwell)) {
                return err(
                    "router.spindle_dwell",
                    format!("must be in 0..={MAX_DWELL_S} s, got {}", r.spindle_dwell),
                );
            }
        }
        if let Some(s) = &self.svg {
            if !(s.stroke_width.is_finite() && s.stroke_width > 0.0 && s.stroke_width <= 10.0) {
                return err(
                    "svg.stroke_width",
                    format!("must be in (0, 10] mm, got {}", s.stroke_width),
                );
            }
            let c = &s.colors;
            for (k, v) in [
                ("profile", &c.profile),
                ("channel", &c.channel),
                ("backboard", &c.backboard),
                ("holes", &c.holes),
                ("fill", &c.fill),
                ("vcarve", &c.vcarve),
            ] {
                if !is_hex_color(v) {
                    return err(
                        &format!("svg.colors.{k}"),
                        format!("must be a colour #rrggbb, got {v:?}"),
                    );
                }
            }
        }
        Ok(())
    }
}

/// Tool diameters and kerfs, in mm: smaller is no physical cutter (and makes offsets and
/// pass counts explode), larger is no tool a sign machine holds.
pub const TOOL_SIZE_MM: (f64, f64) = (1e-3, 1e3);
/// Largest |coordinate| of a work area and largest length setting, in mm.
pub const MAX_LENGTH_MM: f64 = 1e7;
/// Largest feed (mm/min) or acceleration (mm/s²) per axis.
pub const MAX_RATE_MM: f64 = 1e7;
/// Largest dwell (pierce, spindle spin-up), in seconds.
pub const MAX_DWELL_S: f64 = 600.0;

/// The first M word of a preamble/postamble that would end the program (`M2`, `M30`) or
/// start the spindle or laser (`M3`, `M4`): (1-based line, word, what it does). Comments
/// in parentheses and after `;` are skipped; spaces inside words are ignored as G-code does.
fn forbidden_m_word(text: &str) -> Option<(usize, String, &'static str)> {
    for (i, line) in text.lines().enumerate() {
        let mut code = String::new();
        let mut depth = 0usize;
        for ch in line.chars() {
            match ch {
                ';' if depth == 0 => break,
                '(' => depth += 1,
                ')' => depth = depth.saturating_sub(1),
                c if depth == 0 && !c.is_whitespace() => code.push(c.to_ascii_uppercase()),
                _ => {}
            }
        }
        let b = code.as_bytes();
        for (k, &c) in b.iter().enumerate() {
            if c != b'M' {
                continue;
            }
            let num: String = code[k + 1..]
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.')
                .collect();
            let why = match num.parse::<f64>() {
                Ok(v) if v == 2.0 || v == 30.0 => "end the program",
                Ok(v) if v == 3.0 || v == 4.0 => "start the spindle or laser",
                _ => continue,
            };
            return Some((i + 1, format!("M{num}"), why));
        }
    }
    None
}

fn validate_tool(t: &Tool, mm_per_unit: f64) -> Result<(), (String, String)> {
    let bad = |k: &str, m: String| Err((k.to_string(), m));
    if t.name.trim().is_empty() {
        return bad("name", "must not be empty".into());
    }
    let (lo, hi) = (TOOL_SIZE_MM.0 / mm_per_unit, TOOL_SIZE_MM.1 / mm_per_unit);
    let size_ok = |v: f64| v.is_finite() && v >= lo && v <= hi;
    let range = |what: &str, v: f64| {
        format!(
            "{what} {v} is outside {lo}..={hi} (profile units; {}..={} mm)",
            TOOL_SIZE_MM.0, TOOL_SIZE_MM.1
        )
    };
    match t.kind {
        ToolKind::Beam => {
            if !size_ok(t.kerf) {
                return bad("kerf", range("a beam's kerf", t.kerf));
            }
        }
        ToolKind::Endmill | ToolKind::Ballnose => {
            if !size_ok(t.diameter) {
                return bad("diameter", range("diameter", t.diameter));
            }
        }
        ToolKind::Vbit => {
            if !size_ok(t.diameter) {
                return bad("diameter", range("diameter", t.diameter));
            }
            if !(t.angle > 0.0 && t.angle < 180.0) {
                return bad(
                    "angle",
                    format!("a V-bit needs 0 < angle < 180, got {}", t.angle),
                );
            }
            if !(t.tip_diameter >= 0.0 && t.tip_diameter < t.diameter) {
                return bad(
                    "tip_diameter",
                    format!("must be in [0, diameter), got {}", t.tip_diameter),
                );
            }
        }
    }
    Ok(())
}

/// True for `#rrggbb`.
pub fn is_hex_color(s: &str) -> bool {
    s.len() == 7 && s.starts_with('#') && s[1..].chars().all(|c| c.is_ascii_hexdigit())
}

/// The first `name` in backticks in a serde message ("unknown field `foo`").
fn backticked(msg: &str) -> Option<String> {
    let a = msg.find('`')?;
    let rest = &msg[a + 1..];
    let b = rest.find('`')?;
    Some(rest[..b].to_string())
}

/// 1-based line of byte offset `at`, and the key written on that line (before `=`), or the
/// table header.
fn locate(text: &str, at: usize) -> (Option<usize>, String) {
    let at = at.min(text.len());
    let before = text.get(..at).unwrap_or("");
    let line_no = before.matches('\n').count() + 1;
    let line = text.lines().nth(line_no - 1).unwrap_or("");
    let key = match line.split_once('=') {
        Some((k, _)) => k.trim().to_string(),
        None => line.trim().trim_matches(['[', ']']).to_string(),
    };
    (Some(line_no), key)
}
