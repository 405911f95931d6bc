//! Placement: where a built job goes in the machine's work area ([`Place`]), the cut
//! order planned from the machine's origin where it will be ([`plan_placed`]), and the
//! move itself with the check that the job fits ([`place_job`]).

use super::super::JobError;
use super::super::tolerances::Tolerances;
use super::BuildResult;
use crate::geom::DVec2;
use crate::machine::Profile;
use crate::toolpath::Toolpath;
use crate::toolpath::plan::{OpSpec, PlanStats, plan};

/// How a job will be placed ([`place_job`]): what fixes the machine's origin in design
/// coordinates before the cut order is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaceAt {
    /// The placement asked for.
    pub place: Place,
    /// Distance from the work area's edges with [`Place::LowerLeft`] (design units).
    pub margin: f64,
    /// Rounding inset (design units): see [`place_job`].
    pub inset: f64,
}

/// Grid (design units) the placed toolpath's coordinates are snapped to when the placement
/// moves the job. A design moved by D before placement reaches the same placed coordinates
/// only within the rounding of numbers of size D (ulp(10⁴) ≈ 1.8·10⁻¹², a few of them per
/// built point); a number that prints at a rounding tie (an arc's centre offset `I` at
/// exactly x.xxx5: the job's box corner placed at the inset, plus a tool radius of 1.5875
/// mm) would print either way. On this grid both land on the same double, far below the
/// program's last decimal (10⁻³ mm, 10⁻⁴ in) and above that noise for moves up to 10⁶ units.
pub const PLACE_GRID: f64 = 1e-9;

/// Most plans of one build placed by [`build_toolpath_placed`]: the first from the
/// placement of the geometry, one more when leads move the placed job, a last when that
/// moved the leads again.
const MAX_PLACE_ROUNDS: usize = 3;

/// [`plan`] of `specs` from the machine's origin of a job placed as `at` says, in design
/// coordinates: minus the shift [`placement_offset`] gives the box of the specs' geometry
/// ([`Geometry::bounds`], the same whatever the order). Leads (`lead_in`) can reach past
/// that box and so move the placed job: while the shift of the planned toolpath's box
/// differs from the one planned from by more than `tol.fit`, the job is planned again from it
/// (at most [`MAX_PLACE_ROUNDS`] plans). Every step moves with the design, so a design
/// moved before placement gets the same order.
pub(super) fn plan_placed(
    specs: &[OpSpec],
    profile: &Profile,
    design_mm_per_unit: f64,
    at: PlaceAt,
    tol: &Tolerances,
) -> (Toolpath, Vec<PlanStats>) {
    let tol = tol.fit;
    let Some(crate::geom::Aabb { min: lo, max: hi }) =
        (specs.iter().filter_map(|s| s.geometry.bounds())).reduce(crate::geom::Aabb::union)
    else {
        return plan(specs, DVec2::ZERO, tol);
    };
    let offset_of = |lo, hi| placement_offset(lo, hi, profile, design_mm_per_unit, at);
    let mut offset = offset_of(lo, hi);
    let mut planned = plan(specs, -offset, tol);
    for _ in 1..MAX_PLACE_ROUNDS {
        let s = planned.0.stats(DVec2::ZERO);
        let (lo, hi) = (
            DVec2::from_slice(&s.bbox_min),
            DVec2::from_slice(&s.bbox_max),
        );
        if !(lo.is_finite() && hi.is_finite()) {
            break;
        }
        let next = offset_of(lo, hi);
        if next.distance(offset) <= tol {
            break;
        }
        offset = next;
        planned = plan(specs, -offset, tol);
    }
    planned
}

/// The shift [`place_job`] gives a job whose box is `lo..hi` (design units) on `profile`:
/// none at the design's coordinates; the box's lower-left corner to the work area's plus
/// `margin + inset`; the box's centre to the work area's.
pub fn placement_offset(
    lo: DVec2,
    hi: DVec2,
    profile: &Profile,
    design_mm_per_unit: f64,
    at: PlaceAt,
) -> DVec2 {
    let (a_lo, a_hi) = work_area_xy(profile, design_mm_per_unit);
    match at.place {
        Place::Design => DVec2::ZERO,
        Place::LowerLeft => a_lo + DVec2::splat(at.margin + at.inset) - lo,
        Place::Center => 0.5 * (a_lo + a_hi) - 0.5 * (lo + hi),
    }
}

/// The work area's corners in xy (lower-left, upper-right), in design units.
fn work_area_xy(profile: &Profile, design_mm_per_unit: f64) -> (DVec2, DVec2) {
    let k = profile.units.mm_per_unit() / design_mm_per_unit;
    let wa = &profile.work_area;
    (
        DVec2::new(wa.x.min(), wa.y.min()) * k,
        DVec2::new(wa.x.max(), wa.y.max()) * k,
    )
}

/// Where a built job goes on the machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Place {
    /// The design's own coordinates.
    Design,
    /// The job's lower-left corner (tool paths included) at the work area's lower-left
    /// corner plus the margin: what svg2gcode and LaserGRBL do, and the default.
    LowerLeft,
    /// The job's centre at the work area's centre.
    Center,
}

impl Place {
    /// The name on the command line (`--place`).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Place::Design => "design",
            Place::LowerLeft => "lower-left",
            Place::Center => "center",
        }
    }
}

/// Where a job went: the shift applied, the job's size and where it lies, in design units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct Placement {
    /// The placement asked for.
    pub place: Place,
    /// Shift added to every coordinate.
    pub offset: [f64; 2],
    /// Size of the job (tool paths included).
    pub size: [f64; 2],
    /// Lower-left and upper-right corner of the placed job.
    pub min: [f64; 2],
    /// Upper-right corner of the placed job.
    pub max: [f64; 2],
    /// The design's scale factor (`--scale` or `--fit`), 1 when unscaled.
    pub scale: f64,
}

/// Moves the built job as `place` says and checks that it fits the work area of `profile`
/// (in xy). `margin` (design units) keeps the job that far from the area's edges with
/// [`Place::LowerLeft`]; `inset` (design units, two units of the program's last decimal) more
/// keeps rounding from pushing an arc's extreme over the edge. A job that does not fit
/// fails with its size, the area's size and the option that would help.
pub fn place_job(
    built: &mut BuildResult,
    profile: &Profile,
    design_mm_per_unit: f64,
    place: Place,
    margin: f64,
    inset: f64,
    scale: f64,
) -> Result<Placement, JobError> {
    let s = built.toolpath.stats(DVec2::ZERO);
    if s.cuts == 0 || !s.bbox_min[0].is_finite() || !s.bbox_max[0].is_finite() {
        // Operations that came out empty are named: their strokes exist, but what they
        // cut is narrower than the tool (a fill of thin lettering with a 1/4" bit).
        let empty: Vec<String> = built
            .toolpath
            .operations
            .iter()
            .filter(|o| o.cuts.is_empty())
            .map(super::super::checked::operation_label)
            .collect();
        let msg = if empty.is_empty() {
            "the design gives nothing to cut: add strokes, or operations that apply to them"
                .to_string()
        } else {
            format!(
                "the design gives nothing to cut: {} came out empty, what it cuts being \
                 narrower than the tool of profile \"{}\": use a smaller tool, wider strokes \
                 or another operation",
                empty.join(", "),
                profile.name
            )
        };
        return Err(JobError::Options(msg));
    }
    let lo = DVec2::new(s.bbox_min[0], s.bbox_min[1]);
    let hi = DVec2::new(s.bbox_max[0], s.bbox_max[1]);
    let size = hi - lo;
    let (a_lo, a_hi) = work_area_xy(profile, design_mm_per_unit);
    let units = super::super::size::units_name(design_mm_per_unit);
    super::super::size::check_fits(
        size,
        false,
        profile,
        design_mm_per_unit,
        place,
        margin,
        inset,
        scale,
    )?;
    let at = PlaceAt {
        place,
        margin,
        inset,
    };
    let offset = placement_offset(lo, hi, profile, design_mm_per_unit, at);
    let (plo, phi) = (lo + offset, hi + offset);
    if place == Place::Design
        && (plo.x < a_lo.x || plo.y < a_lo.y || phi.x > a_hi.x || phi.y > a_hi.y)
    {
        return Err(JobError::Options(format!(
            "at the design's coordinates the job spans x {:.2}..{:.2}, y {:.2}..{:.2} {units}, \
             outside the work area of profile \"{}\" (x {:.1}..{:.1}, y {:.1}..{:.1}): use \
             --place lower-left (the default) or --place center",
            plo.x, phi.x, plo.y, phi.y, profile.name, a_lo.x, a_hi.x, a_lo.y, a_hi.y
        )));
    }
    if offset != DVec2::ZERO {
        // Snapped to the placement grid: a design moved before placement differs here by
        // its rounding only, and must print the same numbers.
        built.toolpath = built
            .toolpath
            .mapped_xy(|p| ((p + offset) / PLACE_GRID).round() * PLACE_GRID);
        for o in &mut built.outlines {
            for p in &mut o.contours {
                *p = p.translated(offset);
            }
            o.spine_box = o.spine_box.map(|(lo, hi)| (lo + offset, hi + offset));
        }
    }
    Ok(Placement {
        place,
        offset: offset.to_array(),
        size: size.to_array(),
        min: plo.to_array(),
        max: phi.to_array(),
        scale,
    })
}

#[cfg(test)]
mod tests {
    use super::super::{BuildOptions, build_toolpath};
    use super::*;

    fn router() -> Profile {
        let text = include_str!("../../../machines/grbl-router.toml");
        Profile::from_toml(text, "grbl-router.toml").expect("builtin profile")
    }

    fn ring() -> crate::design::Design {
        let text = include_str!("../../../examples/ring_o.toml");
        crate::design::load(text, "ring_o.toml").expect("example design")
    }

    fn at(place: Place, margin: f64, inset: f64) -> PlaceAt {
        PlaceAt {
            place,
            margin,
            inset,
        }
    }

    /// Lower-left puts the box's min at the work area's corner plus margin and inset;
    /// centre puts the box's centre at the area's; the design's coordinates do not move.
    #[test]
    fn placement_offset_puts_the_box_where_asked() {
        let p = router();
        let (a_lo, a_hi) = work_area_xy(&p, 1.0);
        let (lo, hi) = (DVec2::new(-12.5, 40.25), DVec2::new(87.0, 93.5));
        let off = placement_offset(lo, hi, &p, 1.0, at(Place::LowerLeft, 5.0, 0.002));
        assert!(
            (lo + off - (a_lo + DVec2::splat(5.002)))
                .abs()
                .max_element()
                < 1e-12
        );
        let off = placement_offset(lo, hi, &p, 1.0, at(Place::Center, 5.0, 0.002));
        let mid = 0.5 * (lo + hi) + off;
        assert!((mid - 0.5 * (a_lo + a_hi)).abs().max_element() < 1e-12);
        let off = placement_offset(lo, hi, &p, 1.0, at(Place::Design, 5.0, 0.002));
        assert_eq!(off, DVec2::ZERO);
        // A design in inches: the work area (mm) is 25.4 times smaller in design units.
        let (i_lo, i_hi) = work_area_xy(&p, 25.4);
        assert!((i_lo * 25.4 - a_lo).abs().max_element() < 1e-9);
        assert!((i_hi * 25.4 - a_hi).abs().max_element() < 1e-9);
    }

    /// A built job placed lower-left with a margin: the placed toolpath's box starts at
    /// the work area's corner plus margin and inset (within the placement grid), and keeps
    /// its size; the placement reports that box.
    #[test]
    fn place_job_lower_left_puts_the_toolpath_min_at_the_margin() {
        let p = router();
        let mut built = build_toolpath(&ring(), &p, &BuildOptions::default()).expect("build");
        let before = built.toolpath.stats(DVec2::ZERO);
        let size = DVec2::new(
            before.bbox_max[0] - before.bbox_min[0],
            before.bbox_max[1] - before.bbox_min[1],
        );
        let (margin, inset) = (5.0, 0.002);
        let placed =
            place_job(&mut built, &p, 1.0, Place::LowerLeft, margin, inset, 1.0).expect("fits");
        let (a_lo, _) = work_area_xy(&p, 1.0);
        let want = a_lo + DVec2::splat(margin + inset);
        let s = built.toolpath.stats(DVec2::ZERO);
        let got = DVec2::new(s.bbox_min[0], s.bbox_min[1]);
        assert!(
            (got - want).abs().max_element() <= 4.0 * PLACE_GRID,
            "{got} vs {want}"
        );
        assert!((DVec2::from_array(placed.min) - want).abs().max_element() < 1e-9);
        assert!((DVec2::from_array(placed.size) - size).abs().max_element() < 1e-9);
        let got_size = DVec2::new(s.bbox_max[0], s.bbox_max[1]) - got;
        assert!((got_size - size).abs().max_element() <= 4.0 * PLACE_GRID);
    }
}
