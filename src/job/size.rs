//! The job's size against the machine's work area: the exact test on the placed toolpath
//! ([`super::build::place_job`]) and an early one on the design, before any skinning
//! ([`early_extent`], [`check_fits`]), so that a job that cannot fit (a thousand letters
//! on a 300 mm router) is refused at once rather than after its whole build.

use super::JobError;
use super::build::Place;
use super::tolerances::MM_UNIT_TOL;
use crate::design::{Design, Fit, OperationKind, ProfileSide};
use crate::geom::DVec2;
use crate::machine::Profile;

/// Refuses a job of `size` (design units; `at_least` when it is a lower bound known
/// before the build) that does not fit the work area of `profile` with the padding of
/// `place` (`margin` + `inset` at the lower-left corner, `inset` elsewhere): the error
/// gives both sizes and the `--fit` / `--scale` that would help (the job was built at
/// `scale`).
#[allow(clippy::too_many_arguments)]
pub fn check_fits(
    size: DVec2,
    at_least: bool,
    profile: &Profile,
    design_mm_per_unit: f64,
    place: Place,
    margin: f64,
    inset: f64,
    scale: f64,
) -> Result<(), JobError> {
    let k = profile.units.mm_per_unit() / design_mm_per_unit;
    let wa = &profile.work_area;
    let a_size = DVec2::new(wa.x.max() - wa.x.min(), wa.y.max() - wa.y.min()) * k;
    let pad = match place {
        Place::LowerLeft => margin + inset,
        _ => inset,
    };
    if size.x + pad + inset <= a_size.x && size.y + pad + inset <= a_size.y {
        return Ok(());
    }
    let units = units_name(design_mm_per_unit);
    let room = a_size - DVec2::splat(pad + inset);
    let fit = (room.x / size.x).min(room.y / size.y);
    Err(JobError::Options(format!(
        "the job is {}{:.1} x {:.1} {units} ({}{}), larger than the work area of profile \
         \"{}\", {:.1} x {:.1} {units}: use --fit {:.0}x{:.0} to scale the design down to fit \
         (about --scale {:.3} of the current size), or a larger machine",
        if at_least { "at least " } else { "" },
        size.x,
        size.y,
        if at_least {
            "its strokes and shapes alone, before tool paths"
        } else {
            "tool paths included"
        },
        if pad > inset {
            format!(", plus the {margin} margin")
        } else {
            String::new()
        },
        profile.name,
        a_size.x,
        a_size.y,
        (room.x - inset).max(0.0).floor(),
        (room.y - inset).max(0.0).floor(),
        scale * fit.max(0.0) * 0.99,
    )))
}

/// A lower bound on the job's extent `(min, max)` in design units, from the design alone
/// (O(disks + points + circles)), or `None` when the design's operations do not say that
/// the cut goes around every item. It applies to a design without operations (every item
/// is profiled) and to one with a profile on or outside, or a backboard, of every item
/// (no `strokes`, `layers` or `colors` selection): such a cut encloses each item's outline,
/// which holds every disk the stroke's centre curve passes through up to `slack` (the
/// outline's guarantee 2·(ε + 2·tolerance)). The disks known to lie on a stroke: every
/// point of an interpolated `points` stroke, the end disks of an open `disks` stroke with
/// the default clamped knots; every circle of a circle sequence, every point of a shape.
pub fn early_extent(design: &Design, slack: f64) -> Option<(DVec2, DVec2)> {
    let encloses_all = design.operation.is_empty()
        || design.operation.iter().any(|op| {
            let around = match op.kind {
                OperationKind::Profile => op.side != Some(ProfileSide::Inside),
                OperationKind::Backboard => true,
                _ => false,
            };
            around && op.strokes.is_none() && op.layers.is_none() && op.colors.is_none()
        });
    if !encloses_all {
        return None;
    }
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    let mut disk = |d: &[f64; 3]| {
        let r = (d[2] - slack).max(0.0);
        lo = lo.min(DVec2::new(d[0] - r, d[1] - r));
        hi = hi.max(DVec2::new(d[0] + r, d[1] + r));
    };
    for s in &design.stroke {
        if let Some(points) = &s.points
            && s.fit.unwrap_or_default() == Fit::Interpolate
        {
            points.iter().for_each(&mut disk);
        } else if let Some(disks) = &s.disks
            && !s.closed
            && s.knots.is_none()
        {
            disks
                .first()
                .into_iter()
                .chain(disks.last())
                .for_each(&mut disk);
        }
    }
    for c in &design.circles {
        c.circles.iter().for_each(&mut disk);
    }
    for sh in &design.shape {
        for p in sh.contours.iter().flatten() {
            disk(&[p[0], p[1], 0.0]);
        }
    }
    (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
}

/// The name of the design's unit for messages: "mm" when a unit is a millimetre (up to
/// [`MM_UNIT_TOL`]), else "in".
pub(crate) fn units_name(design_mm_per_unit: f64) -> &'static str {
    if (design_mm_per_unit - 1.0).abs() < MM_UNIT_TOL {
        "mm"
    } else {
        "in"
    }
}
