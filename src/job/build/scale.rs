//! Scale: the design scaled by a factor ([`scaled_design`]), the outlines' box
//! ([`outline_bounds`]) and the factor that fits a job into a size ([`fit_scale`]).

use super::super::outline::ItemOutline;
use crate::design::Design;
use crate::geom::DVec2;

/// The design with every stroke, circle sequence and text scaled by `f` about the origin:
/// centres and radii of disks, points and circles; height, stroke width, anchor and letter
/// spacing of `[[text]]` not yet laid out (a loaded design has its text as strokes); the
/// corners at which loading split strokes (so that piece ends there stay joints, not stroke
/// ends that get neon holes); the `[neon]` table's `break_at` points. Operation settings
/// (channel width, hole diameter, depths, margins, bridge width, mounting holes) and the
/// flex's sizes are physical sizes of tools and material and stay as written.
#[must_use]
pub fn scaled_design(design: &Design, f: f64) -> Design {
    let mut d = design.clone();
    let sc = |v: &mut [f64; 3]| {
        for x in v.iter_mut() {
            *x *= f;
        }
    };
    for s in &mut d.stroke {
        for list in [&mut s.disks, &mut s.points].into_iter().flatten() {
            list.iter_mut().for_each(sc);
        }
    }
    for c in &mut d.circles {
        c.circles.iter_mut().for_each(sc);
    }
    for t in &mut d.text {
        t.height *= f;
        t.width *= f;
        if let Some(at) = &mut t.at {
            at.iter_mut().for_each(|x| *x *= f);
        }
        if let Some(s) = &mut t.letter_spacing {
            *s *= f;
        }
    }
    for c in &mut d.corners {
        c.at.iter_mut().for_each(|x| *x *= f);
    }
    d.shape.iter_mut().for_each(|s| s.scale(f));
    // Where runs break is a place in the artwork (the flex's sizes are not).
    if let Some(points) = d.neon.as_mut().and_then(|n| n.break_at.as_mut()) {
        for p in points.iter_mut() {
            p.iter_mut().for_each(|x| *x *= f);
        }
    }
    d
}

/// Bounding box (min, max) of the outlines of a build (with the box of the disks of a
/// stroke cut only along its spine, [`ItemOutline::spine_box`]), in design units.
#[must_use]
pub fn outline_bounds(outlines: &[ItemOutline], tol: f64) -> Option<(DVec2, DVec2)> {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for p in outlines.iter().flat_map(|o| o.contours.iter()) {
        for q in p.flatten(tol) {
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    for (a, b) in outlines.iter().filter_map(|o| o.spine_box) {
        lo = lo.min(a);
        hi = hi.max(b);
    }
    (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
}

/// The scale factor that makes the job fit `w` × `h` (design units): the outlines scale
/// with the design, the rest of the job (tool offsets, channel widths, backboard margins)
/// does not, so the factor is (w − extra_x)/outline_w (likewise in y), the smaller of the
/// two. `job` and `outline` are the sizes at the current scale.
#[must_use]
pub fn fit_scale(job: DVec2, outline: DVec2, w: f64, h: f64) -> Option<f64> {
    let extra = job - outline;
    let sx = (w - extra.x) / outline.x;
    let sy = (h - extra.y) / outline.y;
    let s = sx.min(sy);
    (s.is_finite() && s > 0.0).then_some(s)
}
