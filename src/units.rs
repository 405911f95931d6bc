//! Length units, shared by designs, machine profiles and the G-code simulator.

use serde::{Deserialize, Serialize};

/// A length unit: millimetres or inches. Serialised as `"mm"` and `"inch"` (the design
/// file's `units`, the machine profile's `units` and the check report's units all use these
/// strings).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Millimetres (G21).
    #[default]
    Mm,
    /// Inches of 25.4 mm (G20).
    Inch,
}

impl Units {
    /// Millimetres per unit: 1 for mm, 25.4 for inch (the inch is defined as 25.4 mm).
    pub fn mm_per_unit(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Inch => 25.4,
        }
    }

    /// Millimetres per unit, under the simulator's name; equal to [`Units::mm_per_unit`].
    pub fn to_mm(self) -> f64 {
        self.mm_per_unit()
    }

    /// The G-code word that selects these units.
    pub fn gcode(self) -> &'static str {
        match self {
            Units::Mm => "G21",
            Units::Inch => "G20",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serde_strings_and_scale() {
        assert_eq!(serde_json::to_string(&Units::Mm).unwrap(), "\"mm\"");
        assert_eq!(serde_json::to_string(&Units::Inch).unwrap(), "\"inch\"");
        let u: Units = serde_json::from_str("\"inch\"").unwrap();
        assert_eq!(u, Units::Inch);
        assert_eq!(Units::Inch.mm_per_unit(), 25.4);
        assert_eq!(Units::Mm.to_mm(), 1.0);
        assert_eq!(Units::default(), Units::Mm);
    }
}
