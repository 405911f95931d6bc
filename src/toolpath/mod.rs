//! Machine-independent toolpaths: operations made of cuts, cuts made of moves.
//!
//! This stage turns outlines into ordered cuts (profiles, channels, backboards, holes,
//! fills, V-carving); `emit` turns them into a machine's dialect.

pub mod arc_merge;
pub mod attrs;
pub mod biarc;
pub mod board;
pub mod cut;
pub mod inks;
pub mod line;
pub mod model;
pub mod ops;
pub mod order;
pub mod plan;
pub mod re_route;
pub mod region;
pub mod rings;
pub mod stats;
pub mod swept;
pub mod valleys;

pub use model::{Cut, Move, MoveKind, Operation, OperationKind, Toolpath};
