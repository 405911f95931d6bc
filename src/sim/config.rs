//! What the checks need to know about the machine and the job. Plain data: the CLI maps a
//! machine profile into it, so `sim` does not depend on `machine`.

use super::motion::Units;
use serde::{Deserialize, Serialize};

/// Laser (cuts where the beam is on) or router/mill (cuts where the tool is below `cut_z`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MachineKind {
    #[default]
    /// A laser cutter or engraver: cutting means the beam is on.
    Laser,
    /// A router or mill: cutting means the tool is below the stock top.
    Router,
}

/// Machine limits and check options. Lengths are in `units` (feeds in units/min,
/// accelerations in units/s²); [`CheckConfig::in_mm`] converts to the mm the checks use.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct CheckConfig {
    /// Units of every length, feed and acceleration in this configuration.
    pub units: Units,
    /// Laser or router.
    pub kind: MachineKind,
    /// Travel limits (min corner, max corner) in machine coordinates.
    pub work_min: [f64; 3],
    /// Max corner of the travel limits.
    pub work_max: [f64; 3],
    /// Router: rapids that move in xy must stay at or above this z.
    pub safe_z: f64,
    /// Router: a feed move with an end below this z is in the material (the stock top).
    pub cut_z: f64,
    /// Maximum rate per axis (x, y, z), units/min (GRBL $110–$112); rapids run at these.
    pub max_rate: [f64; 3],
    /// Allowed programmed feed for cutting moves, units/min.
    pub feed_min: f64,
    /// Largest allowed programmed feed for cutting moves, units/min.
    pub feed_max: f64,
    /// Allowed S while cutting (laser power or spindle rpm, in S units).
    pub power_min: f64,
    /// Largest allowed S while cutting.
    pub power_max: f64,
    /// Acceleration per axis, units/s² (GRBL $120–$122).
    pub accel: [f64; 3],
    /// GRBL junction deviation ($11), units.
    pub junction_deviation: f64,
    /// Chord tolerance used to split arcs for the time estimate (GRBL $12), units.
    pub arc_tolerance: f64,
    /// Chord tolerance for flattening arcs in geometric checks, units.
    pub flatten_tolerance: f64,
    /// Tool radius (half the kerf for lasers), units: the gouge check's clearance.
    pub tool_radius: f64,
    /// Gouge slack: the tool centre may come `tool_radius − gouge_tolerance` close.
    pub gouge_tolerance: f64,
    /// Do not report crossings between different contours.
    pub allow_crossings: bool,
    /// The dialect ends a program without M2/M30 (Marlin: M30 deletes a file on the SD
    /// card, and a print host just stops sending): a missing end is then only noted.
    pub program_end_optional: bool,
    /// GRBL laser mode ($32=1): G0 never fires the beam, so a rapid with M3/M4 and S>0 is
    /// only a warning (it still is an error on controllers without laser mode).
    pub grbl_laser_mode: bool,
    /// Radius tolerance for IJ arcs (|r_start − r_end|), units.
    pub arc_radius_tolerance: f64,
    /// At most this many findings per check id are kept (the rest are counted); 0 keeps
    /// one, so that a program with errors always shows one.
    pub max_findings_per_check: usize,
    /// How the controller reads the program (see [`Dialect`]).
    pub dialect: Dialect,
    /// Tool table for M6/G43 (tool length offsets) and G10 L1/L10 (units as `units`).
    pub tool_table: Vec<ToolEntry>,
    /// Loop iterations (backward jumps of while/do/repeat/continue) allowed in one program;
    /// beyond it interpretation stops with a `loop-limit` error.
    pub max_loop_iterations: u64,
    /// Route of the CLI's `check` (not part of the TOML): None reads programs larger than
    /// [`crate::sim::stream::STREAM_ABOVE_BYTES`] on the streaming route
    /// ([`crate::sim::stream::check_stream`]) and smaller ones in memory; Some(true) and
    /// Some(false) force one route.
    #[serde(skip)]
    pub stream: Option<bool>,
}

/// How the controller reads G-code.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    /// LinuxCNC's RS274NGC (parameters, expressions, O-words) plus RepRap checksums: reads
    /// what any controller writes.
    #[default]
    Generic,
    /// LinuxCNC 2.9 exactly as `rs274` reads it (no checksums).
    Linuxcnc,
    /// GRBL 1.1: no parameters, expressions or O-words; `$` system commands; G4 P seconds.
    Grbl,
    /// Marlin 2.x: `;` comments, checksums, G4 P milliseconds (S seconds), M3/M4 `I` inline
    /// power, no parameters, expressions or O-words.
    Marlin,
    /// Smoothieware: like Marlin for syntax; G4 P milliseconds.
    Smoothie,
}

impl Dialect {
    /// Name as given to `--dialect`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Dialect::Generic => "generic",
            Dialect::Linuxcnc => "linuxcnc",
            Dialect::Grbl => "grbl",
            Dialect::Marlin => "marlin",
            Dialect::Smoothie => "smoothie",
        }
    }

    /// The feed (mm/min) the firmware runs a feed move at while no F word has set one:
    /// Marlin's 1500 (motion.cpp) and Smoothieware's compiled-in 100 (Robot.cpp); None for
    /// the dialects that refuse such a move (LinuxCNC, GRBL) or leave it untimed (generic).
    #[must_use]
    pub fn default_feed(self) -> Option<f64> {
        match self {
            Dialect::Marlin => Some(MARLIN_DEFAULT_FEED_MM_MIN),
            Dialect::Smoothie => Some(SMOOTHIE_DEFAULT_FEED_MM_MIN),
            Dialect::Generic | Dialect::Linuxcnc | Dialect::Grbl => None,
        }
    }

    /// Parses a `--dialect` name.
    #[must_use]
    pub fn from_name(s: &str) -> Option<Dialect> {
        [
            Dialect::Generic,
            Dialect::Linuxcnc,
            Dialect::Grbl,
            Dialect::Marlin,
            Dialect::Smoothie,
        ]
        .into_iter()
        .find(|d| d.name() == s)
    }
}

/// Marlin's feed rate before any F word (mm/min): `feedrate_mm_s = MMM_TO_MMS(1500.0f)` in
/// Marlin/src/module/motion.cpp.
pub const MARLIN_DEFAULT_FEED_MM_MIN: f64 = 1500.0;

/// Smoothieware's feed rate before any F word (mm/min): `default_feed_rate`, compiled-in
/// default 100 (Robot.cpp `by_default(100.0F)`) when the config file does not set it.
pub const SMOOTHIE_DEFAULT_FEED_MM_MIN: f64 = 100.0;

/// One tool of the tool table (LinuxCNC `.tbl` line `T1 P1 Z0.5 D3.175`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct ToolEntry {
    /// Tool number (T).
    pub number: u32,
    /// Length offset along z (G43).
    pub z: f64,
    /// Offset along x (G43 on lathes).
    pub x: f64,
    /// Tool diameter (cutter compensation and the gouge check).
    pub diameter: f64,
}

impl ToolEntry {
    /// Tool `number` of `diameter` (no length or x offset).
    #[must_use]
    pub fn new(number: u32, diameter: f64) -> Self {
        ToolEntry {
            number,
            diameter,
            ..ToolEntry::default()
        }
    }
}

/// Reads a LinuxCNC tool table: one tool per line, `T<n> P<pocket> X.. Z.. D..` words in
/// any order, `;` comments. Lines without `T` are skipped; a malformed number is an error
/// naming the line.
pub fn parse_tool_table(text: &str) -> Result<Vec<ToolEntry>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let body = line.split(';').next().unwrap_or("");
        let mut t = ToolEntry::default();
        let mut has_t = false;
        for w in body.split_whitespace() {
            let mut ch = w.chars();
            let Some(letter) = ch.next() else { continue };
            let v: f64 = ch.as_str().parse().map_err(|_| {
                format!(
                    "tool table line {}: {w:?} is not a letter and a number",
                    i + 1
                )
            })?;
            match letter.to_ascii_uppercase() {
                'T' => {
                    has_t = true;
                    t.number = v.max(0.0) as u32;
                }
                'Z' => t.z = v,
                'X' => t.x = v,
                'D' => t.diameter = v,
                _ => {}
            }
        }
        if has_t {
            out.push(t);
        }
    }
    Ok(out)
}

/// Default loop budget: a million iterations run in well under a second in a release build
/// and cover every LinuxCNC sample program; a runaway `while` stops there.
pub const DEFAULT_MAX_LOOP_ITERATIONS: u64 = 1_000_000;

impl Default for CheckConfig {
    /// A GRBL-class 300 × 300 mm diode laser: 5000 mm/min and 500 mm/s² per axis,
    /// junction deviation 0.01 mm and arc tolerance 0.002 mm (GRBL defaults), S 0..1000.
    fn default() -> Self {
        CheckConfig {
            units: Units::Mm,
            kind: MachineKind::Laser,
            work_min: [0.0, 0.0, -50.0],
            work_max: [300.0, 300.0, 50.0],
            safe_z: 5.0,
            cut_z: 0.0,
            max_rate: [5000.0, 5000.0, 1000.0],
            feed_min: 1.0,
            feed_max: 5000.0,
            power_min: 0.0,
            power_max: 1000.0,
            accel: [500.0, 500.0, 100.0],
            junction_deviation: 0.01,
            arc_tolerance: 0.002,
            flatten_tolerance: crate::geom::tol::FLATTEN,
            tool_radius: 0.0,
            gouge_tolerance: 0.01,
            allow_crossings: false,
            program_end_optional: false,
            grbl_laser_mode: true,
            arc_radius_tolerance: 0.005,
            max_findings_per_check: 50,
            dialect: Dialect::Generic,
            tool_table: Vec::new(),
            max_loop_iterations: DEFAULT_MAX_LOOP_ITERATIONS,
            stream: None,
        }
    }
}

impl CheckConfig {
    /// A copy with every length, feed and acceleration in millimetres.
    #[must_use]
    pub fn in_mm(&self) -> CheckConfig {
        let k = self.units.to_mm();
        let s3 = |a: [f64; 3]| a.map(|v| v * k);
        CheckConfig {
            units: Units::Mm,
            work_min: s3(self.work_min),
            work_max: s3(self.work_max),
            safe_z: self.safe_z * k,
            cut_z: self.cut_z * k,
            max_rate: s3(self.max_rate),
            feed_min: self.feed_min * k,
            feed_max: self.feed_max * k,
            accel: s3(self.accel),
            junction_deviation: self.junction_deviation * k,
            arc_tolerance: self.arc_tolerance * k,
            flatten_tolerance: self.flatten_tolerance * k,
            tool_radius: self.tool_radius * k,
            gouge_tolerance: self.gouge_tolerance * k,
            arc_radius_tolerance: self.arc_radius_tolerance * k,
            tool_table: self
                .tool_table
                .iter()
                .map(|t| ToolEntry {
                    z: t.z * k,
                    x: t.x * k,
                    diameter: t.diameter * k,
                    ..*t
                })
                .collect(),
            ..self.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_partial_and_inch_conversion() {
        let c: CheckConfig = toml::from_str(
            "units = \"inch\"\nkind = \"router\"\nsafe_z = 0.25\nwork_max = [10.0, 10.0, 1.0]",
        )
        .unwrap_or_default();
        assert_eq!(c.kind, MachineKind::Router);
        let mm = c.in_mm();
        assert!((mm.safe_z - 6.35).abs() < 1e-12);
        assert!((mm.work_max[0] - 254.0).abs() < 1e-12);
        assert_eq!(mm.power_max, c.power_max);
        assert!(toml::from_str::<CheckConfig>("bogus = 1").is_err());
        let t = parse_tool_table("T1 P1 Z0.5 D3.175 ;mill\n\nT7 P2 X1 Z-2").unwrap_or_default();
        assert_eq!(t.len(), 2);
        assert_eq!((t[0].number, t[0].z, t[0].diameter), (1, 0.5, 3.175));
        assert_eq!((t[1].number, t[1].x, t[1].z), (7, 1.0, -2.0));
        assert!(parse_tool_table("T1 Zq").is_err());
    }
}
