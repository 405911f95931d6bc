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

#[cfg(test)]
mod tests {
    use super::*;

    /// The factor s makes s·outline + extra fit w × h, with equality in the binding axis
    /// (extra = job − outline, the parts that do not scale); none when the fixed parts
    /// alone are larger than the size.
    #[test]
    fn fit_scale_fits_the_binding_axis_exactly() {
        let (job, outline) = (DVec2::new(30.0, 20.0), DVec2::new(25.0, 18.0));
        let extra = job - outline;
        let (w, h) = (100.0, 50.0);
        let s = fit_scale(job, outline, w, h).expect("a factor");
        let fitted = s * outline + extra;
        assert!(fitted.x <= w + 1e-12 && fitted.y <= h + 1e-12);
        assert!((fitted.y - h).abs() < 1e-12, "y binds: {fitted}");
        assert!((s - (h - extra.y) / outline.y).abs() < 1e-15);
        assert_eq!(fit_scale(job, outline, 4.0, 50.0), None);
    }

    /// Disks, points and the neon breaks scale by f about the origin, operation settings
    /// do not.
    #[test]
    fn scaled_design_scales_the_artwork_only() {
        let text = include_str!("../../../examples/neon_word.toml");
        let d = crate::design::load(text, "neon_word.toml").expect("example design");
        let f = 0.37;
        let s = scaled_design(&d, f);
        for (a, b) in d.stroke.iter().zip(&s.stroke) {
            let (da, db) = (a.disks.as_ref(), b.disks.as_ref());
            for (p, q) in da.into_iter().flatten().zip(db.into_iter().flatten()) {
                for k in 0..3 {
                    assert_eq!(q[k], p[k] * f);
                }
            }
        }
        assert_eq!(d.operation.len(), s.operation.len());
        for (a, b) in d.operation.iter().zip(&s.operation) {
            assert_eq!(
                (a.width, a.diameter, a.depth),
                (b.width, b.diameter, b.depth)
            );
        }
    }

    /// The outlines' box of a scaled design is the scaled box (the skin scales with its
    /// disks) within the skin's and the flattening's tolerance.
    #[test]
    fn outline_bounds_scale_with_the_design() {
        use super::super::super::outline::{OutlineOptions, design_outlines};
        let text = include_str!("../../../examples/ring_o.toml");
        let d = crate::design::load(text, "ring_o.toml").expect("example design");
        let opts = OutlineOptions::default();
        let f = 0.5;
        let tol = opts.tolerance;
        let (lo, hi) =
            outline_bounds(&design_outlines(&d, &opts).expect("outlines"), tol).expect("a box");
        let scaled = design_outlines(&scaled_design(&d, f), &opts).expect("outlines");
        let (slo, shi) = outline_bounds(&scaled, tol).expect("a box");
        let allow = 2.0 * (opts.epsilon + tol);
        assert!(
            (slo - f * lo).abs().max_element() <= allow,
            "{slo} vs {}",
            f * lo
        );
        assert!(
            (shi - f * hi).abs().max_element() <= allow,
            "{shi} vs {}",
            f * hi
        );
    }
}
