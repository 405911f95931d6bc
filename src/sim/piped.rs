//! The in-memory route of the builtin backend's check that never stores the moves: the
//! interpreter hands its moves over in chunks, and every check, the statistics and the time
//! estimate take them as they come, beside it on a thread of their own (for texts of
//! [`THREAD_ABOVE_BYTES`] and more). The cut contours' segments are gathered on the way;
//! the contacts between them are looked for after the last move. The report is
//! [`super::check`]'s of the stored program, finding for finding.
//!
//! ```text
//! text ─► interp::interpret_each ─► chunks of moves ─► MovePass: stats, estimate,
//!                                                     per-move checks, contour segments
//!                                                     ─► contacts, gouges ─► Report
//! ```

use super::checks::{self, CheckFindings, ContourPass, DesignBoundary, MoveChecks};
use super::config::CheckConfig;
use super::interp::{self, Options};
use super::motion::{Motion, Motions, Program};
use super::report::{Report, StatsSum};
use super::time::Estimator;
use std::time::Instant;

/// Moves handed from the interpreter to the checks at a time: 128 KB of stored moves,
/// which stay in the cache of the core that reads them next.
const CHUNK_MOVES: usize = 4096;

/// Texts of at least this many bytes are checked beside the interpreter on a thread of
/// their own; below it starting the thread costs more than it saves.
pub const THREAD_ABOVE_BYTES: usize = 1 << 20;

/// Wall seconds of the stages of [`super::check_text_timed`]. The per-move work overlaps
/// another stage: interpreting on the builtin backend's route, the contour checks on the
/// LinuxCNC backend's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct StageTimes {
    /// Interpreting the program (the builtin backend's G-code, or rs274's output).
    pub interpret: f64,
    /// The checks on the cut contours (intersections, gouges).
    pub contours: f64,
    /// The per-move checks, statistics and time estimate.
    pub moves: f64,
    /// All of it.
    pub total: f64,
}

/// Everything done move by move: statistics, time estimate, per-move checks, and the
/// contour checks' gathering.
struct MovePass<'c> {
    stats: StatsSum,
    time: Estimator,
    checks: MoveChecks<'c>,
    contours: ContourPass<'c>,
    /// Index of the next move.
    next: usize,
    /// Wall seconds spent on the moves.
    busy: f64,
}

impl<'c> MovePass<'c> {
    fn new(cfg: &'c CheckConfig, design: &'c [DesignBoundary]) -> Self {
        MovePass {
            stats: StatsSum::new(),
            time: Estimator::new(cfg),
            checks: MoveChecks::new(cfg),
            contours: ContourPass::new(cfg, design),
            next: 0,
            busy: 0.0,
        }
    }

    /// Takes the moves of `chunk` and leaves it empty for reuse.
    fn chunk(&mut self, chunk: &mut Motions) {
        let clock = Instant::now();
        for m in &*chunk {
            self.motion(&m);
        }
        chunk.clear();
        self.busy += clock.elapsed().as_secs_f64();
    }

    /// As [`super::checks_and_stats`] takes each stored move.
    fn motion(&mut self, m: &Motion) {
        let bounds = m.bounds();
        self.checks.motion_in(m, bounds);
        self.stats.motion(m, bounds);
        self.time.motion(m);
        self.contours.motion(self.next, m);
        self.next += 1;
    }
}

/// The report of [`super::check_text_with`] on the builtin backend, on the piped route
/// (module docs), and the time of its stages. `cfg` as given (maybe in inch).
pub(super) fn check_builtin(
    text: &str,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &Options<'_>,
) -> (Report, StageTimes) {
    let threaded = text.len() >= THREAD_ABOVE_BYTES;
    check_piped(text, cfg, design, opts, threaded, CHUNK_MOVES)
}

/// [`check_builtin`] with the per-move work on a thread of its own or not (`threaded`),
/// handed `chunk` moves at a time; the report does not depend on either (for the tests).
pub(crate) fn check_piped(
    text: &str,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &Options<'_>,
    threaded: bool,
    chunk: usize,
) -> (Report, StageTimes) {
    let mut times = StageTimes::default();
    if let Some(reason) = super::unusable_text(text) {
        let prog = Program {
            unusable: Some(reason),
            ..Program::default()
        };
        return (super::check(&prog, cfg, design), times);
    }
    let mm = cfg.in_mm();
    let start = Instant::now();
    let clock = start;
    let (prog, pass) = crate::par::pipeline(
        threaded,
        MovePass::new(&mm, design),
        MovePass::chunk,
        |send| {
            let mut take = |moves: &mut Motions| {
                let full = std::mem::take(moves);
                if let Some(used) = send(full) {
                    // Its room is taken again for the moves to come.
                    *moves = used;
                }
            };
            let sink = interp::MotionSink {
                take: &mut take,
                chunk,
            };
            interp::interpret_each(text, &mm, opts, sink)
        },
    );
    times.interpret = clock.elapsed().as_secs_f64();
    times.moves = pass.busy;
    let clock = Instant::now();
    let contour = pass.contours.finish();
    times.contours = clock.elapsed().as_secs_f64();
    let moves: CheckFindings = pass.checks.finish(&prog);
    let stats = pass.stats.finish(pass.time.finish());
    let found = super::found_of(&prog, checks::join(contour, moves));
    let report = super::assemble_found(&prog, cfg, found, stats);
    times.total = start.elapsed().as_secs_f64();
    (report, times)
}
