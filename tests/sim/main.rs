//! The checker and RS274 interpreter: the G-code corpus, expressions, streaming input,
//! refusals, the RS274 back end and the memory budget of a check (measured in a child
//! process).
//!
//! One test binary; each module was once a file of its own under tests/.

#[path = "../support/mod.rs"]
mod support;

mod rs274_backend;
mod rs274_conformance;
mod sim_corpus;
mod sim_expr;
mod sim_input;
mod sim_memory;
mod sim_refusals;
mod sim_stream;
