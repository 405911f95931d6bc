//! Progress of long work: the stage a job is in and how far it got, reported to a
//! caller-supplied callback (a terminal progress bar in the CLI, nothing by default), and
//! the wall time each stage took.

use std::time::{Duration, Instant};

/// A stage of a job, in pipeline order. `Read` and `Write` are the caller's file I/O
/// (the library reads and writes no files); they are here so that a caller's timings table
/// names every stage the same way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stage {
    /// Reading the design and the machine profile (caller side).
    Read,
    /// Skinning: outlines of every stroke and circle sequence.
    Skin,
    /// Offsets and toolpath planning of every operation.
    Toolpath,
    /// Placing the job in the work area.
    Place,
    /// Writing the machine program (G-code, laser SVG or DXF) as text.
    Emit,
    /// Reading the program back and checking it.
    Check,
    /// Writing the output files (caller side).
    Write,
}

impl Stage {
    /// The stage's name as printed and in JSON (`"skin"`, `"toolpath"`, ...).
    pub fn as_str(self) -> &'static str {
        match self {
            Stage::Read => "read",
            Stage::Skin => "skin",
            Stage::Toolpath => "toolpath",
            Stage::Place => "place",
            Stage::Emit => "emit",
            Stage::Check => "check",
            Stage::Write => "write",
        }
    }
}

/// One progress report: the stage and the fraction of it done, in [0, 1]. A stage starts
/// with fraction 0 and ends with fraction 1; in between it reports after every stroke
/// skinned or operation planned.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Progress {
    /// The stage running.
    pub stage: Stage,
    /// Share of the stage done, 0 to 1.
    pub fraction: f64,
}

/// A callback that receives [`Progress`] reports; `Sync`, since items are skinned on
/// several threads and each reports when it is done.
pub type ProgressFn<'a> = &'a (dyn Fn(Progress) + Sync);

/// Reports `done` of `total` steps of `stage` (fraction 1 when `total` is 0).
pub(crate) fn report(progress: Option<ProgressFn<'_>>, stage: Stage, done: usize, total: usize) {
    if let Some(f) = progress {
        let fraction = if total == 0 {
            1.0
        } else {
            (done as f64 / total as f64).clamp(0.0, 1.0)
        };
        f(Progress { stage, fraction });
    }
}

/// Wall time per stage, in the order the stages first ran; a stage that runs more than
/// once (`--fit` builds the design a few times) adds up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timings {
    /// Each stage with its total wall time.
    pub stages: Vec<(Stage, Duration)>,
}

impl Timings {
    /// Adds `d` to `stage`.
    pub fn add(&mut self, stage: Stage, d: Duration) {
        match self.stages.iter_mut().find(|(s, _)| *s == stage) {
            Some((_, t)) => *t += d,
            None => self.stages.push((stage, d)),
        }
    }

    /// Runs `f`, adding its wall time to `stage`.
    pub fn time<T>(&mut self, stage: Stage, f: impl FnOnce() -> T) -> T {
        let t0 = Instant::now();
        let r = f();
        self.add(stage, t0.elapsed());
        r
    }

    /// Appends the stages of `other` (adding up stages both have).
    pub fn extend(&mut self, other: &Timings) {
        for &(s, d) in &other.stages {
            self.add(s, d);
        }
    }

    /// The total of all stages.
    pub fn total(&self) -> Duration {
        self.stages.iter().map(|(_, d)| *d).sum()
    }

    /// Seconds per stage as a JSON object (`{"read": 0.001, "skin": ..., "total": ...}`):
    /// one key per stage that ran, and `total`.
    pub fn to_json(&self) -> serde_json::Value {
        let mut m = serde_json::Map::new();
        for (s, d) in &self.stages {
            m.insert(s.as_str().to_string(), d.as_secs_f64().into());
        }
        m.insert("total".into(), self.total().as_secs_f64().into());
        serde_json::Value::Object(m)
    }

    /// A small table, one stage a line, milliseconds, and the total.
    pub fn table(&self) -> String {
        let mut out = String::from("stage          ms\n");
        for (s, d) in &self.stages {
            out.push_str(&format!(
                "{:10} {:>8.1}\n",
                s.as_str(),
                1e3 * d.as_secs_f64()
            ));
        }
        out.push_str(&format!(
            "{:10} {:>8.1}\n",
            "total",
            1e3 * self.total().as_secs_f64()
        ));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_add_up_and_keep_first_order() {
        let mut t = Timings::default();
        t.add(Stage::Skin, Duration::from_millis(2));
        t.add(Stage::Toolpath, Duration::from_millis(3));
        t.add(Stage::Skin, Duration::from_millis(5));
        assert_eq!(
            t.stages,
            vec![
                (Stage::Skin, Duration::from_millis(7)),
                (Stage::Toolpath, Duration::from_millis(3))
            ]
        );
        assert_eq!(t.total(), Duration::from_millis(10));
        let j = t.to_json();
        let keys: Vec<&String> = j
            .as_object()
            .map(|o| o.keys().collect())
            .unwrap_or_default();
        assert_eq!(keys.len(), 3);
        assert!(t.table().lines().count() == 4);
    }

    #[test]
    fn report_clamps_and_handles_empty_work() {
        let seen = std::sync::Mutex::new(Vec::new());
        let f = |p: Progress| seen.lock().unwrap().push(p.fraction);
        report(Some(&f), Stage::Skin, 0, 0);
        report(Some(&f), Stage::Skin, 1, 4);
        report(Some(&f), Stage::Skin, 9, 4);
        assert_eq!(*seen.lock().unwrap(), vec![1.0, 0.25, 1.0]);
    }
}
