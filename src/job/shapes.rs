//! Shapes (`[[shape]]`, closed regions) in whole-design jobs: their outlines join the
//! stroke outlines ([`shape_outlines`]), so profile, fill and backboard operations cut them
//! and the checks guard them; `outline` draws them ([`shape_drawings`]) and `inspect` lists
//! them ([`shape_infos`]).
//!
//! A shape's outline is its region resolved under its fill rule
//! ([`Shape::region`](crate::design::Shape::region)): simple polylines, outer boundaries
//! counter-clockwise and holes clockwise, the orientation every outline has, so the
//! operations' union of regions (non-zero winding over the union of the items) treats a
//! shape exactly like a stroke's outline.

use super::outline::{ItemOutline, OutlineOptions, region_offsets};
use crate::design::{Design, Shape};
use crate::emit::outline::{ContourRole, OutlineContour, StrokeOutline};
use crate::geom::{DVec2, Path};
use serde::Serialize;

/// The outline of one shape: its resolved contours as closed polylines.
pub fn shape_outline(shape: &Shape) -> ItemOutline {
    ItemOutline {
        name: shape.name.clone(),
        contours: shape
            .region()
            .iter()
            .map(|r| Path::polyline(r, true))
            .collect(),
        circles: Vec::new(),
        loops: None,
        segments: Vec::new(),
        self_overlap: false,
        disk_union: None,
        repair: None,
        spine_box: None,
    }
}

/// The outlines of every shape of the design, in file order (after the strokes and circle
/// sequences in a job's item list).
pub fn shape_outlines(design: &Design) -> Vec<ItemOutline> {
    design.shape.iter().map(shape_outline).collect()
}

/// The drawing of every shape for `skinpath outline`: its contours (role `outline`) and,
/// with `opts.offset`, the region's offsets at ± that distance (role `offset`).
pub fn shape_drawings(design: &Design, opts: &OutlineOptions) -> Vec<StrokeOutline> {
    design
        .shape
        .iter()
        .map(|s| {
            let item = shape_outline(s);
            let mut contours: Vec<OutlineContour> = item
                .contours
                .iter()
                .map(|p| {
                    OutlineContour::new(ContourRole::Outline, true, &p.flatten(opts.tolerance))
                })
                .collect();
            if let Some(delta) = opts.offset {
                contours.extend(
                    region_offsets(&item.contours, delta, opts.tolerance)
                        .iter()
                        .filter(|c| c.len() >= 3)
                        .map(|c| OutlineContour::new(ContourRole::Offset, true, c)),
                );
            }
            StrokeOutline {
                name: s.name.clone(),
                contours,
                circles: Vec::new(),
                markers: Vec::new(),
            }
        })
        .collect()
}

/// What `inspect` says about a shape.
#[derive(Clone, Debug, Serialize)]
pub struct ShapeInfo {
    /// The shape's name.
    pub name: String,
    /// "nonzero" or "evenodd".
    pub fill_rule: String,
    /// Contours as given.
    pub contours: usize,
    /// Points over all given contours.
    pub points: usize,
    /// Outer boundaries of the resolved region.
    pub outer: usize,
    /// Holes of the resolved region.
    pub holes: usize,
    /// Area of the region (outer areas minus hole areas), design units squared.
    pub area: f64,
    /// Lower-left and upper-right corner of the region.
    pub bbox: [[f64; 2]; 2],
}

/// The [`ShapeInfo`] of every shape, in file order.
pub fn shape_infos(design: &Design) -> Vec<ShapeInfo> {
    design
        .shape
        .iter()
        .map(|s| {
            let region = s.region();
            let areas: Vec<f64> = region
                .iter()
                .map(|r| crate::design::shape::ring_area(r))
                .collect();
            let (lo, hi) = region.iter().flatten().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), &p| (lo.min(p), hi.max(p)),
            );
            ShapeInfo {
                name: s.name.clone(),
                fill_rule: s.fill_rule.unwrap_or_default().as_str().to_string(),
                contours: s.contours.len(),
                points: s.contours.iter().map(Vec::len).sum(),
                outer: areas.iter().filter(|a| **a > 0.0).count(),
                holes: areas.iter().filter(|a| **a < 0.0).count(),
                area: areas.iter().sum(),
                bbox: [lo.to_array(), hi.to_array()],
            }
        })
        .collect()
}

impl std::fmt::Display for ShapeInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "shape \"{}\": {} contours ({} points), fill rule {}: {} outer, {} holes, area {:.3}, \
             x {:.3} .. {:.3}, y {:.3} .. {:.3}",
            self.name,
            self.contours,
            self.points,
            self.fill_rule,
            self.outer,
            self.holes,
            self.area,
            self.bbox[0][0],
            self.bbox[1][0],
            self.bbox[0][1],
            self.bbox[1][1]
        )
    }
}
