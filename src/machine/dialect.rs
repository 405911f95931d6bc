//! G-code dialects: the few places where controllers disagree on syntax.
//!
//! Everything else a profile varies (units, ranges, templates, laser and router behaviour) is
//! data in the profile; a dialect only knows how its controller spells comments and dwells and
//! whether it keeps the motion mode modal.

use serde::Deserialize;

/// The controller family a G-code profile targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    /// GRBL 1.1 (laser mode `$32=1` for lasers): `( )` comments, `G4 P` in seconds.
    Grbl,
    /// Marlin 2.x with `LASER_FEATURE` or `SPINDLE_FEATURE`: `;` comments, `G4 P` in
    /// milliseconds, no modal motion (every move names its G word), no `M2`.
    Marlin,
    /// LinuxCNC: `( )` comments, `G4 P` in seconds, `G64 P` path blending.
    Linuxcnc,
    /// Smoothieware: `;` comments, `G4 P` in milliseconds, laser module fires on G1/G2/G3
    /// only, with `S` as a fraction 0..1.
    Smoothie,
    /// No G-code at all (SVG/DXF profiles).
    None,
}

/// Longest comment text we write (without delimiters). GRBL's line buffer holds 80
/// characters (`LINE_BUFFER_SIZE`); staying well under it keeps every controller happy.
pub const MAX_COMMENT_CHARS: usize = 60;

impl Dialect {
    /// `text` as a comment line this controller accepts: only ASCII letters, digits, spaces
    /// and `- _ . , : = / + # *` survive (GRBL treats `!`, `?`, `~` as real-time commands even
    /// inside comments, and parentheses cannot nest), and at most `MAX_COMMENT_CHARS`.
    #[must_use]
    pub fn comment(self, text: &str) -> String {
        let clean = sanitize_comment(text);
        match self {
            Dialect::Marlin | Dialect::Smoothie => format!("; {clean}"),
            _ => format!("({clean})"),
        }
    }

    /// A dwell of `seconds` (G4), in the unit this controller expects for `P`.
    #[must_use]
    pub fn dwell(self, seconds: f64) -> String {
        match self {
            Dialect::Marlin | Dialect::Smoothie => {
                format!("G4 P{}", super::format_number(seconds * 1000.0, 0))
            }
            _ => format!("G4 P{}", super::format_number(seconds, 3)),
        }
    }

    /// True when the controller keeps G0/G1/G2/G3 modal, so a move line may omit its G word.
    pub fn modal_motion(self) -> bool {
        !matches!(self, Dialect::Marlin)
    }
}

/// Keeps only the characters every supported controller accepts inside a comment.
pub fn sanitize_comment(text: &str) -> String {
    let mut out = String::new();
    for c in text.chars() {
        if out.chars().count() >= MAX_COMMENT_CHARS {
            break;
        }
        let ok = c.is_ascii_alphanumeric() || " -_.,:=/+#*".contains(c);
        out.push(if ok { c } else { ' ' });
    }
    out.trim().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_drop_realtime_and_nesting_characters() {
        let c = Dialect::Grbl.comment("cut (outer)! ok? ~now");
        assert!(c.starts_with('(') && c.ends_with(')'));
        let inner = &c[1..c.len() - 1];
        for bad in ['!', '?', '~', '(', ')', ';'] {
            assert!(!inner.contains(bad), "{c}");
        }
        assert!(inner.contains("cut") && inner.contains("outer"));
        assert!(Dialect::Marlin.comment("x").starts_with("; "));
    }

    #[test]
    fn long_comments_are_cut() {
        let long = "a".repeat(500);
        let c = Dialect::Grbl.comment(&long);
        assert_eq!(c.len(), MAX_COMMENT_CHARS + 2);
    }

    #[test]
    fn dwell_units_per_dialect() {
        assert_eq!(Dialect::Grbl.dwell(1.5), "G4 P1.5");
        assert_eq!(Dialect::Linuxcnc.dwell(2.0), "G4 P2");
        assert_eq!(Dialect::Marlin.dwell(1.5), "G4 P1500");
        assert_eq!(Dialect::Smoothie.dwell(0.25), "G4 P250");
    }
}
