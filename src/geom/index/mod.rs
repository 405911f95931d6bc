//! Spatial indexes: which one to use for what.
//!
//! Five kinds are in use; each suits a different shape of data and query. Costs are for n
//! items and k answers.
//!
//! | index | where | build | query | suits |
//! |---|---|---|---|---|
//! | R-tree (`rstar`, bulk-loaded) | `toolpath::{order, inks, region, attrs}`, `design::svg::paint`, `sim::checks::gouge` | O(n log n) | O(log n + k) box / nearest | scattered boxes of any size; nearest-neighbour walks; few queries per build |
//! | sequence BVH (`SeqBvh`; and the nearest-point hierarchy of `design::svg::fit`, built the same way) | `geom::intersect`; `design::svg::fit` | O(n) | O(log n + k); nearest seeded with the previous answer | boxes in path order (consecutive segments of a path, circles of a stroke): blocks of consecutive boxes stay tight however long and thin the shape |
//! | uniform box grid (`skin::box_grid::BoxGrid`) | `skin::coverage` | O(n) | nearest by rings of cells, seeded with the previous answer | boxes of similar size spread over the stroke (the coverage queries of a skin) |
//! | uniform hash grid (`Grid`) | `sim::checks::intersect`, `sim::stream` | O(n) | O(1 + k) per cell | many short segments of similar length spread evenly (a G-code program's moves): all-pairs contacts in one pass |
//! | slabs ([`Slabs`], [`PolygonWinding`], [`WindingIndex`]) | here; used by `toolpath::{order, region, inks}` | O(n) | O(1 + k) | point queries against one polygon or polyline (inside, winding number): only height matters |
//!
//! Why each stays (the benchmark that shows it):
//! - **R-tree**: the general case. Nearest-neighbour ordering walks boxes by distance
//!   (`toolpath::order`), which neither the grid nor the slabs answer; the design and sim
//!   uses have few queries per build. No benchmark isolates it; it is the default.
//! - **Sequence BVH**: `benches/skin_circles.rs` and `benches/skin_dbsc.rs` (skin of long
//!   wavy strokes): an rstar tree bulk-loaded by OMT splitting degrades on long thin strokes
//!   (query cost grows with n), and a uniform grid is flat but slower than the hierarchy,
//!   whose query cost stays nearly constant from 10² to 10⁵ circles.
//! - **Hash grid**: `benches/sim.rs`, group `contacts` (grid against geo's sweep line on
//!   10⁴–10⁶ segments, and a dense spiral): the grid scales linearly where the sweep's
//!   O((n + k) log n) and its allocation dominate.
//! - **Slabs**: `benches/toolpath.rs`, group `winding_of_offset_vertices` (index build and
//!   query against cavalier's O(n) `winding_number` for 10²–10⁴ vertices): one slab walk
//!   per point instead of every segment.
//!
//! The R-tree and the BVH answer the same queries; the BVH is kept only where items come in
//! path order. The grid and the slabs answer narrower queries in O(1 + k).

mod slabs;
mod winding;

pub use slabs::PolygonWinding;
pub use winding::WindingIndex;
