//! Internals the benchmarks measure (feature `internals`, off by default; not part of the
//! public API and free to change in any release).
//!
//! `benches/` times single stages (skinning, offsets, the checker's segment sweep, the G-code
//! parser) beside peer crates, below the public front ([`crate::Job`] and the module roots).
//! This module re-exports exactly the items they use that the front does not offer; every
//! `[[bench]]` target requires the feature (`cargo bench --features internals`).

pub use crate::sim::checks::{Across, SegmentSet};
pub use crate::sim::interp::interpret;
pub use crate::sim::ngc::{Line as NgcLine, Syntax, parse_line_into};
pub use crate::skin::mat_offset::{MatOffset, inner_offset, outline};
pub use crate::toolpath::ops::{ProfileSide, concentric, hatch, profile, swept_region};
pub use crate::toolpath::order::order_paths;
pub use crate::toolpath::re_route::biarc_paths;
pub use crate::toolpath::region::{Region, flatten_pline, pline_from_path, pline_from_points};
pub use crate::toolpath::swept::swept_arc_region;
