//! Neon signs: boards, bill of materials, golden programs, layered signs and rounded
//! channels.
//!
//! One test binary; each module was once a file of its own under tests/.

#[path = "../support/mod.rs"]
mod support;

mod neon_board;
mod neon_bom;
mod neon_golden;
mod neon_layers;
mod neon_round;
