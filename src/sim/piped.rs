//! The in-memory route of the builtin backend's check that never stores the moves: the
//! interpreter hands its moves over in chunks, and the per-move checks, the statistics and
//! the time estimate take them as they come, beside it on a thread of their own (for texts
//! of [`THREAD_ABOVE_BYTES`] and more). The contour checks gather the chunks' segments (and
//! gouges) on one side or the other, whichever balances the two: beside the estimate where
//! the moves are lines (interpreting costs most), on the interpreter's thread where they
//! are mostly arcs (the estimate and the contours both flatten them, and interpreting
//! costs least). The contacts between the segments are looked for after the last move.
//! The report is [`super::check`]'s of the stored program, finding for finding.
//!
//! ```text
//! text ─► interp::interpret_each ─► chunks of moves ─► MovePass (its own thread): stats,
//!              │                                      estimate, per-move checks, and the
//!              │                                      ContourPass for programs of lines
//!              └─ ContourPass (interpreter's thread) for programs of arcs
//! ContourPass ───► contacts, gouges ─┐
//! MovePass ──────────────────────────┴─► Report
//! ```

use super::checks::{self, CheckFindings, ContourPass, DesignBoundary, MoveChecks};
use super::config::CheckConfig;
use super::interp::{self, Options};
use super::motion::{Motion, Motions, Program};
use super::report::{Report, Stats, StatsSum};
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

/// A chunk of moves, and with the first the contour checks when they go beside.
struct Chunk<'c> {
    moves: Motions,
    contours: Option<ContourPass<'c>>,
}

/// Moves per arc in the first chunk from which the contour checks go beside the estimate:
/// with fewer arcs than one in 8 moves the program is mostly lines (see the module docs).
const MOVES_PER_ARC_BESIDE: usize = 8;

/// Whether the contour checks go beside the estimate: the moves of the first chunk are
/// mostly lines (see the module docs).
fn contours_beside(moves: &Motions) -> bool {
    let arcs = moves.iter().filter(|m| m.arc.is_some()).count();
    arcs * MOVES_PER_ARC_BESIDE <= moves.len()
}

/// The per-move side: statistics, time estimate, per-move checks, and the contour checks
/// when they came along. [`super::checks_and_stats`] runs it over stored moves too.
pub(super) struct MovePass<'c> {
    stats: StatsSum,
    time: Estimator,
    checks: MoveChecks<'c>,
    contours: Option<ContourPass<'c>>,
    /// Wall seconds spent on the moves.
    busy: f64,
}

impl<'c> MovePass<'c> {
    /// No move yet (`cfg` in mm).
    pub(super) fn new(cfg: &'c CheckConfig) -> Self {
        MovePass {
            stats: StatsSum::new(),
            time: Estimator::new(cfg),
            checks: MoveChecks::new(cfg),
            contours: None,
            busy: 0.0,
        }
    }

    /// Takes the moves of `chunk` (and the contour checks, when it brings them) and leaves
    /// it empty for reuse.
    fn chunk(&mut self, chunk: &mut Chunk<'c>) {
        let clock = Instant::now();
        if let Some(c) = chunk.contours.take() {
            self.contours = Some(c);
        }
        for m in &chunk.moves {
            self.motion(&m);
        }
        chunk.moves.clear();
        self.busy += clock.elapsed().as_secs_f64();
    }

    /// Takes the next move.
    pub(super) fn motion(&mut self, m: &Motion) {
        let bounds = m.bounds();
        self.checks.motion_in(m, bounds);
        self.stats.motion(m, bounds);
        self.time.motion(m);
        if let Some(c) = self.contours.as_mut() {
            c.motion(m);
        }
    }

    /// The per-move checks' findings (the program end's last) and the statistics with the
    /// time estimate.
    pub(super) fn finish(self, prog: &Program) -> (CheckFindings, Stats) {
        let stats = self.stats.finish(self.time.finish());
        (self.checks.finish(prog), stats)
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
    check_piped(text, cfg, design, opts, threaded, CHUNK_MOVES, None)
}

/// [`check_builtin`] with the per-move work on a thread of its own or not (`threaded`),
/// handed `chunk` moves at a time, the contour checks beside it or not (`beside`; None:
/// as the first chunk says). The report does not depend on any of them (for the tests).
pub(crate) fn check_piped(
    text: &str,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &Options<'_>,
    threaded: bool,
    chunk: usize,
    beside: Option<bool>,
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
    // The contour checks, while they are on the interpreter's thread.
    let mut here = Some(ContourPass::new(&mm, design));
    let mut first = true;
    let (prog, mut pass) =
        crate::par::pipeline(threaded, MovePass::new(&mm), MovePass::chunk, |send| {
            let mut take = |moves: &mut Motions| {
                let mut chunk = Chunk {
                    moves: std::mem::take(moves),
                    contours: None,
                };
                if std::mem::take(&mut first)
                    && beside.unwrap_or_else(|| contours_beside(&chunk.moves))
                {
                    chunk.contours = here.take();
                }
                if let Some(c) = here.as_mut() {
                    for m in &chunk.moves {
                        c.motion(&m);
                    }
                }
                if let Some(used) = send(chunk) {
                    // Its room is taken again for the moves to come.
                    *moves = used.moves;
                }
            };
            let sink = interp::MotionSink {
                take: &mut take,
                chunk,
            };
            interp::interpret_each(text, &mm, opts, sink)
        });
    times.interpret = clock.elapsed().as_secs_f64();
    times.moves = pass.busy;
    let clock = Instant::now();
    // Exactly one side holds the contour checks (the interpreter's, when no chunk came).
    let Some(contours) = here.or(pass.contours.take()) else {
        return super::check_stored(super::Backend::Builtin, text, cfg, design, opts);
    };
    let contour = contours.finish();
    times.contours = clock.elapsed().as_secs_f64();
    let (moves, stats) = pass.finish(&prog);
    let found = super::found_of(&prog, checks::join(contour, moves));
    let report = super::assemble_found(&prog, cfg, found, stats);
    times.total = start.elapsed().as_secs_f64();
    (report, times)
}
