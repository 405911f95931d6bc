//! The report: JSON via serde, a human summary via `Display`, and the exit code the CLI
//! returns. Its findings are [`super::findings::Finding`]s (re-exported here).

pub use super::findings::{Finding, Severity};
use super::motion::{Motion, MotionKind};
use glam::DVec3;
use serde::Serialize;
use std::fmt;

/// Totals over the program (mm, seconds).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Stats {
    /// Number of moves (dwells not counted).
    pub motions: usize,
    /// Length of feed moves, mm (helical length for arcs).
    pub cut_length: f64,
    /// Length of rapid moves, mm.
    pub rapid_length: f64,
    /// Bounding box of all moves (min, max), None for a program without moves.
    pub bbox: Option<[[f64; 3]; 2]>,
    /// Estimated run time.
    pub time: super::time::TimeEstimate,
}

/// [`Stats`] summed one move at a time, all but the time (which
/// [`super::time::Estimator`] gives).
#[derive(Clone, Debug)]
pub(crate) struct StatsSum {
    stats: Stats,
    lo: DVec3,
    hi: DVec3,
}

impl StatsSum {
    /// No move yet.
    pub(crate) fn new() -> Self {
        StatsSum {
            stats: Stats::default(),
            lo: DVec3::splat(f64::INFINITY),
            hi: DVec3::splat(f64::NEG_INFINITY),
        }
    }

    /// Adds `m`, whose [`Motion::bounds`] are `(lo, hi)`: its length, and its bounds
    /// unless it is a dwell.
    pub(crate) fn motion(&mut self, m: &Motion, (lo, hi): (DVec3, DVec3)) {
        let s = &mut self.stats;
        match m.kind {
            MotionKind::Rapid => s.rapid_length += m.length(),
            MotionKind::Feed => s.cut_length += m.length(),
            MotionKind::Dwell { .. } => return,
        }
        s.motions += 1;
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }

    /// The statistics of the moves added, with the run time `time`.
    pub(crate) fn finish(self, time: super::time::TimeEstimate) -> Stats {
        let mut s = self.stats;
        s.time = time;
        if s.motions > 0 {
            s.bbox = Some([self.lo.to_array(), self.hi.to_array()]);
        }
        s
    }
}

/// The result of checking one program.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Report {
    /// Which backend read the program ("builtin" or "linuxcnc").
    pub backend: &'static str,
    /// False when the input is not a G-code program at all (empty, binary, nothing parsed).
    pub usable: bool,
    /// Why the input is not usable (when `usable` is false).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Findings in order: interpreter diagnostics, then each check (capped per check).
    pub findings: Vec<Finding>,
    /// Findings left out per check id after `max_findings_per_check`.
    pub suppressed: Vec<(String, usize)>,
    /// Ids of `suppressed` whose count is a lower bound: the search stopped once the
    /// report was full (the intersection check on large sets), so at least that many more
    /// exist. Omitted from the JSON when empty.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub suppressed_at_least: Vec<String>,
    /// Totals over the program.
    pub stats: Stats,
}

impl Report {
    /// Number of error findings shown.
    #[must_use]
    pub fn errors(&self) -> usize {
        self.count(Severity::Error)
    }

    /// Number of warning findings shown.
    #[must_use]
    pub fn warnings(&self) -> usize {
        self.count(Severity::Warning)
    }

    fn count(&self, s: Severity) -> usize {
        self.findings.iter().filter(|f| f.severity == s).count()
    }

    /// Number of error findings, those left out by `max_findings_per_check` included.
    #[must_use]
    pub fn errors_in_all(&self) -> usize {
        self.count_in_all(Severity::Error)
    }

    /// Number of warning findings, those left out by `max_findings_per_check` included.
    #[must_use]
    pub fn warnings_in_all(&self) -> usize {
        self.count_in_all(Severity::Warning)
    }

    /// Findings of severity `s`, shown or suppressed. A suppressed id always has shown
    /// findings (the cap keeps at least one per id), and one id has one severity in a run
    /// (each check sets it from the configuration), so the left-out findings of an id have
    /// the severity of its shown ones.
    fn count_in_all(&self, s: Severity) -> usize {
        let left_out: usize = self
            .suppressed
            .iter()
            .filter(|(id, _)| {
                self.findings
                    .iter()
                    .find(|f| f.id == id.as_str())
                    .is_some_and(|f| f.severity == s)
            })
            .map(|(_, n)| n)
            .sum();
        self.count(s) + left_out
    }

    /// True when the count of findings of severity `s` is a lower bound (an id of that
    /// severity is in `suppressed_at_least`).
    fn lower_bound(&self, s: Severity) -> bool {
        self.suppressed_at_least.iter().any(|id| {
            self.findings
                .iter()
                .any(|f| f.id == id.as_str() && f.severity == s)
        })
    }

    /// Exit status for the CLI: 0 clean (warnings allowed), 1 at least one error finding,
    /// 2 unusable input.
    #[must_use]
    pub fn exit_code(&self) -> i32 {
        if !self.usable {
            2
        } else if self.errors() > 0 {
            1
        } else {
            0
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.usable {
            match &self.reason {
                Some(r) => writeln!(f, "input is not a usable G-code program: {r}")?,
                None => writeln!(f, "input is not a usable G-code program")?,
            }
            if self.findings.is_empty() && self.stats.motions == 0 {
                return write!(f, "nothing checked ({} backend)", self.backend);
            }
        }
        for x in &self.findings {
            writeln!(f, "{x}")?;
        }
        for (id, n) in &self.suppressed {
            let least = if self.suppressed_at_least.contains(id) {
                "at least "
            } else {
                ""
            };
            writeln!(f, "... {least}{n} more [{id}] findings not shown")?;
        }
        let s = &self.stats;
        writeln!(
            f,
            "{} moves, cut {:.1} mm, rapid {:.1} mm, time {} (cutting {}, rapids {}, dwell {})",
            s.motions,
            s.cut_length,
            s.rapid_length,
            hms(s.time.total),
            hms(s.time.feed),
            hms(s.time.rapid),
            hms(s.time.dwell)
        )?;
        if s.time.untimed_moves > 0 {
            writeln!(
                f,
                "time incomplete: {} feed moves without a feed rate are not timed",
                s.time.untimed_moves
            )?;
        }
        if let Some([lo, hi]) = s.bbox {
            writeln!(
                f,
                "bounds x {:.3}..{:.3}  y {:.3}..{:.3}  z {:.3}..{:.3}",
                lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
            )?;
        }
        let total = |all: usize, shown: usize, what: &str, s: Severity| {
            let least = if self.lower_bound(s) { "at least " } else { "" };
            if all == shown {
                format!("{all} {what}")
            } else {
                format!("{least}{all} {what} ({shown} shown)")
            }
        };
        write!(
            f,
            "{}, {} ({} backend)",
            total(
                self.errors_in_all(),
                self.errors(),
                "errors",
                Severity::Error
            ),
            total(
                self.warnings_in_all(),
                self.warnings(),
                "warnings",
                Severity::Warning
            ),
            self.backend
        )
    }
}

/// Seconds as `h:mm:ss.s` (or `m:ss.s` under an hour).
fn hms(t: f64) -> String {
    let t = if t.is_finite() { t.max(0.0) } else { 0.0 };
    let h = (t / 3600.0).floor();
    let m = ((t - 3600.0 * h) / 60.0).floor();
    let s = t - 3600.0 * h - 60.0 * m;
    if h > 0.0 {
        format!("{h}:{m:02}:{s:04.1}")
    } else {
        format!("{m}:{s:04.1}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes_and_text() {
        let mut r = Report {
            backend: "builtin",
            usable: true,
            ..Default::default()
        };
        assert_eq!(r.exit_code(), 0);
        r.findings
            .push(Finding::new("missing-program-end", Severity::Warning, "no M2").line(3));
        assert_eq!(r.exit_code(), 0);
        r.findings.push(
            Finding::new("laser-on-rapid", Severity::Error, "G0 with laser on")
                .line(7)
                .at([1.0, 2.0, 0.0]),
        );
        assert_eq!(r.exit_code(), 1);
        let text = r.to_string();
        assert!(text.contains("error [laser-on-rapid] line 7: G0 with laser on"));
        assert!(text.contains("1 errors, 1 warnings"));
        let json = serde_json::to_value(&r).unwrap_or_default();
        assert_eq!(json["findings"][1]["id"], "laser-on-rapid");
        assert_eq!(json["findings"][1]["severity"], "error");
        r.usable = false;
        assert_eq!(r.exit_code(), 2);
        assert_eq!(hms(3725.0), "1:02:05.0");
    }
}
