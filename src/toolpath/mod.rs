//! Machine-independent toolpaths: operations made of cuts, cuts made of moves.
//!
//! This stage turns outlines into ordered cuts (profiles, channels, backboards, holes,
//! fills, V-carving); `emit` turns them into a machine's dialect.
//!
//! The public front is the model an embedder reads from a build or writes for an emitter
//! ([`Toolpath`], [`Operation`], [`Cut`], [`Move`] and their kinds), its summary figures
//! ([`ToolpathStats`]) and the two limits a build reports or documents
//! ([`MAX_HATCH_LINES`], [`MAX_NEAREST_PATHS`]). The operations themselves (offsets,
//! hatching, ordering, planning) are reached through `job`.

pub(crate) mod arc_merge;
pub(crate) mod attrs;
pub(crate) mod biarc;
pub(crate) mod board;
pub(crate) mod cut;
pub(crate) mod inks;
pub(crate) mod line;
pub(crate) mod model;
pub(crate) mod ops;
pub(crate) mod order;
pub(crate) mod plan;
pub(crate) mod re_route;
pub(crate) mod region;
pub(crate) mod rings;
pub(crate) mod stats;
pub(crate) mod swept;
pub(crate) mod valleys;

pub use model::{Cut, Move, MoveKind, Operation, OperationKind, Toolpath};
pub use ops::MAX_HATCH_LINES;
pub use order::MAX_NEAREST_PATHS;
pub use stats::ToolpathStats;

#[cfg(test)]
mod tests;
