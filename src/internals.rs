//! Internals the benchmarks measure (feature `internals`, off by default; not part of the
//! public API and free to change in any release).
//!
//! `benches/` times single stages (skinning, offsets, the checker's segment sweep, the G-code
//! parser) beside peer crates, below the public front ([`crate::Job`] and the module roots).
//! This module re-exports exactly the items they use that the front does not offer; every
//! `[[bench]]` target requires the feature (`cargo bench --features internals`).

pub use crate::dbsc::spine::spine_cubics;
pub use crate::geom::index::WindingIndex;
pub use crate::geom::path::polygon_area;
pub use crate::job::build::build_toolpath;
pub use crate::job::outline::{OutlineOptions, design_outlines};
pub use crate::machine::{format_number, format_number_std};
pub use crate::sim::checks::{Across, SegmentSet};
pub use crate::sim::interp::interpret;
pub use crate::sim::ngc::{Line as NgcLine, Syntax, parse_line_into};
pub use crate::skin::dbsc_skin::{DbscSkinOptions, ReportBounds, skin_dbsc};
pub use crate::skin::mat_offset::{MatOffset, inner_offset, outline};
pub use crate::skin::re::{Interp, ReSkin, Touch};
pub use crate::toolpath::ops::{ProfileSide, concentric, hatch, profile, swept_region};
pub use crate::toolpath::order::order_paths;
pub use crate::toolpath::re_route::biarc_paths;
pub use crate::toolpath::region::{Region, flatten_pline, pline_from_path, pline_from_points};
pub use crate::toolpath::swept::swept_arc_region;
