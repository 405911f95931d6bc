//! Hostile and random input: the seeded mutation fuzzers (support::fuzz), random designs,
//! hostile previews and programs, and the hardening limits (hangs are guarded by running
//! the CLI as a child).
//!
//! One test binary; each module was once a file of its own under tests/.

#[path = "../support/mod.rs"]
mod support;

mod fuzz_design;
mod fuzz_gcode;
mod fuzz_ngc_flow;
mod fuzz_pipeline;
mod fuzz_profile;
mod fuzz_svg;
mod hardening;
mod jobs_props;
mod preview_hostile;
mod sim_hostile;
