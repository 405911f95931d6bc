//! A progress bar on stderr for long work (`indicatif`), shown only when stderr is a
//! terminal: piped or captured output (tests, scripts) sees nothing.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use skinpath::{Progress, Stage};
use std::io::IsTerminal;
use std::sync::Mutex;

/// Steps of the bar per stage (the fraction is shown to a thousandth).
const STEPS: u64 = 1000;

/// The bar, or nothing when stderr is not a terminal.
pub struct Bar {
    bar: Option<ProgressBar>,
    stage: Mutex<Option<Stage>>,
}

impl Bar {
    /// A hidden bar that appears on the first report, when stderr is a terminal.
    pub fn new() -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let b = ProgressBar::with_draw_target(Some(STEPS), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template("{msg:>9} [{bar:30}] {percent:>3}%") {
                b.set_style(style.progress_chars("=> "));
            }
            b
        });
        Bar {
            bar,
            stage: Mutex::new(None),
        }
    }

    /// Whether reports are shown at all (a caller can skip producing them).
    pub fn active(&self) -> bool {
        self.bar.is_some()
    }

    /// Shows one report.
    pub fn show(&self, p: Progress) {
        let Some(b) = &self.bar else { return };
        if let Ok(mut stage) = self.stage.lock()
            && *stage != Some(p.stage)
        {
            *stage = Some(p.stage);
            b.set_message(p.stage.as_str());
        }
        b.set_position((p.fraction.clamp(0.0, 1.0) * STEPS as f64).round() as u64);
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
