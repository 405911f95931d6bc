//! Flex runs of a neon sign and its bill of materials.
//!
//! The LED flex follows the strokes' spines. A **run** is one piece of flex: a continuous
//! path through strokes whose ends meet ([`runs`]). Ends of different strokes (or both ends
//! of one stroke) at most `join_tolerance` apart are joined, tangent-continuous or not; the
//! pieces `NAME#0`, `NAME#1` of a stroke split at a corner share the corner disk and so
//! are joined; where three or more ends meet, the pairs that turn least are joined first
//! and the rest end runs. A join within the flex width of a `break_at` point is not made;
//! `[[neon.run]]` tables make runs of the strokes they list, in that order (a gap between
//! consecutive strokes is bridged too). A closed stroke is a closed run
//! of its own. A gap between joined ends is bridged straight and counted in the length
//! (`bridged_mm`). Circle sequences and shapes have no spine and carry no flex.
//!
//! Per run ([`RunBom`]): the strokes in order, the length L = Σ ∫‖q′(t)‖dt over the strokes'
//! spines (adaptive Gauss–Legendre per knot span, [`spine_length`]), the length rounded up to
//! the cut unit, ⌈L / cut_unit⌉·cut_unit, and the smallest bend radius along it: the spine's
//! radius of curvature ρ = 1/κ, κ = |q′ × q″| / ‖q′‖³, found per knot span by dense
//! sampling and golden-section refinement of every sampled local maximum of κ
//! ([`span_min_radius`]); a join whose tangents differ by more than [`TANGENT_BREAK_DEG`]
//! (and a point where q′ = 0) is a bend of radius 0.
//!
//! Warnings ([`NeonBom::judge`]): every stretch of a run whose bend radius is below the
//! flex's minimum, with its place; with the design scaled (`--fit`/`--scale`: the strokes
//! shrink, the flex does not), also every pair of runs whose spines came closer than the
//! channel width (their channels merge) while at the design's own size they were not, every
//! island of board the channels went around at the design's size (a letter's counter) that
//! the scaled channels cut away ([`filled_islands`]), and the note that a bend became too
//! tight by the scaling, every run shorter than the cut unit (`short`), and every bend
//! `round_bends` could not round (`round`). `break_at` points scale with the artwork.
//!
//! `[neon] round_bends = true` rounds the tight bends before the channel is made
//! ([`round_bends`], module `round`); `min_run_length` makes shorter runs marks
//! ([`split_marks`]): channelled, no flex, no holes, listed in [`NeonBom::marks`].

mod bend;
mod bom;
mod judge;
mod round;
mod runs;
#[cfg(test)]
mod tests;

pub use bend::{bend_radius, span_min_radius, spine_length};
pub use bom::{
    CloseRuns, FlexSummary, MarkBom, NeonBom, NeonWarning, RunBom, RunPlace, TightBend, bom,
};
pub use round::{RoundReport, round_bends};
pub use runs::{Leg, Run, run_hole_points, runs, split_marks};

/// Turning angle (degrees) above which a join of two strokes is a corner (bend radius 0):
/// G1 joins of fitted strokes agree to far below a degree; a font's corner turns by tens.
pub const TANGENT_BREAK_DEG: f64 = 1.0;

/// Curvature samples per knot span before refinement: a cubic span's curvature has at
/// most a few local maxima, each resolved by a 32-sample grid.
pub const BEND_SAMPLES: usize = 32;

/// Parameter tolerance of the bend refinement, as a fraction of the knot span.
pub const BEND_PARAM_TOL: f64 = 1e-10;

/// Flattening tolerance of the spines for the merge test, as a fraction of the flex width:
/// 6 µm for 6 mm flex, far below a distance that decides whether channels merge.
pub const SPINE_FLATTEN_OF_WIDTH: f64 = 1e-3;
