//! Findings: the leaf type every stage of the simulator produces (interpreter diagnostics,
//! check results). It imports nothing from the rest of `sim`, so `motion`, `report`, `time`
//! and `config` depend on it without forming a cycle.

use serde::Serialize;
use std::fmt;

/// How bad a finding is. Errors make the check fail (exit code 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Severity {
    /// Information: nothing to change.
    Info,
    /// Worth a look: the program still runs as intended.
    Warning,
    /// The program is wrong or unsafe as written.
    Error,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Error => "error",
        })
    }
}

/// One named finding: a stable kebab-case `id` (e.g. `self-intersection`), where (source
/// lines, 1-based; column when known) and the machine coordinates (mm) involved.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Finding {
    /// Kebab-case identifier of the check or diagnostic (`self-intersection`, `gcode-syntax`, ...).
    pub id: &'static str,
    /// How serious it is.
    pub severity: Severity,
    /// What is wrong and, where known, what to change.
    pub message: String,
    /// 1-based source lines involved.
    pub lines: Vec<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    /// 1-based column in the first line, when known.
    pub column: Option<usize>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    /// Points involved (mm, machine coordinates).
    pub at: Vec<[f64; 3]>,
}

impl Finding {
    /// A finding without lines, column or points.
    #[must_use]
    pub fn new(id: &'static str, severity: Severity, message: impl Into<String>) -> Self {
        Finding {
            id,
            severity,
            message: message.into(),
            lines: Vec::new(),
            column: None,
            at: Vec::new(),
        }
    }

    /// Adds a source line.
    #[must_use]
    pub fn line(mut self, line: usize) -> Self {
        self.lines.push(line);
        self
    }

    /// Adds source lines.
    #[must_use]
    pub fn lines(mut self, lines: impl IntoIterator<Item = usize>) -> Self {
        self.lines.extend(lines);
        self
    }

    /// Sets the column.
    #[must_use]
    pub fn column(mut self, column: usize) -> Self {
        self.column = Some(column);
        self
    }

    /// Adds a point (mm).
    #[must_use]
    pub fn at(mut self, p: [f64; 3]) -> Self {
        self.at.push(p);
        self
    }
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} [{}]", self.severity, self.id)?;
        if !self.lines.is_empty() {
            let l: Vec<String> = self.lines.iter().map(|l| l.to_string()).collect();
            write!(f, " line {}", l.join(", "))?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        write!(f, ": {}", self.message)?;
        for p in &self.at {
            write!(f, " @({:.3}, {:.3}, {:.3})", p[0], p[1], p[2])?;
        }
        Ok(())
    }
}
