//! The tolerances of a build by the role each plays, made once from [`BuildOptions`] and
//! the machine profile ([`Tolerances::new`]) and passed down through the build.
//!
//! Two numbers come from the user: the skin approximation ε (`--epsilon`,
//! [`BuildOptions::epsilon`]) and the toolpath tolerance (`--tolerance`,
//! [`BuildOptions::tolerance`]); every other tolerance of the build is a fixed fraction of
//! the second, named here with the reason for its size.

use super::build::BuildOptions;
use crate::machine::{ArcFormat, MachineKind, Profile, Tool, ToolKind};

/// Offset accuracy as a fraction of the toolpath tolerance: the position tolerance of
/// region offsets (cavalier_contours' ε) is a tenth of the tolerance, so an offset adds
/// at most that to the error budget of the arcs it offsets.
pub const OFFSET_OF_FIT: f64 = 0.1;

/// Tolerance of the machine program's writer ([`crate::emit::GcodeOptions::tolerance`],
/// its arc and number checks) and of the preview's, as a fraction of the toolpath
/// tolerance: a tenth, so what is written stays within the tolerance the build kept.
pub const EMIT_OF_FIT: f64 = 0.1;

/// Length accuracy as a fraction of the toolpath tolerance: spine lengths of the neon bill
/// of materials, the search of run marks and the attribute quantisation's parameter search
/// are good to a thousandth of the tolerance (a bill's length is printed to 0.1 mm; the
/// positions they feed are within the tolerance with room to spare).
pub const LENGTH_OF_FIT: f64 = 1e-3;

/// Flattening tolerance of unions that are merged into arcs afterwards, as a fraction of the
/// build tolerance ([`crate::toolpath::arc_merge`]). The chords are within this fraction of
/// the exact outline and the merged arcs within the rest, (1 − fraction)·tol, of the chords,
/// so the cut stays within the build tolerance. An arc through a flattened arc's vertices is
/// within the chords' sagitta of them, which must stay below the merge's share for the arc
/// to pass: at a third for the chords, two thirds for the merge, every such run passes with
/// room to spare.
pub const ARC_UNION_FRACTION: f64 = 1.0 / 3.0;

/// Relative tolerance of "the same point" for stroke ends in design units: two ends within
/// 10⁻⁹·(1 + |p|) are one (strokes that end where another does, as a letter's stem and
/// bowl, get one hole); far below any drawn distance, above the round-off of points
/// computed along two strokes.
pub const SAME_POINT_REL: f64 = 1e-9;

/// Relative tolerance of "the same radius" (a backboard's inner corner radius against the
/// tool's): 10⁻¹²·(1 + r), the round-off of a radius converted between units.
pub const SAME_RADIUS_REL: f64 = 1e-12;

/// Tolerance of "the design is in millimetres" on its millimetres per unit (1 for mm, 25.4
/// for inches): exact up to round-off.
pub const MM_UNIT_TOL: f64 = 1e-12;

/// The tolerances of one build, by role (design units throughout).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Skin approximation ε ([`BuildOptions::epsilon`]): the accuracy of the Bézier skin of
    /// a disk B-spline against the exact envelope of its disks (kruppa-2023 Sec. 4, ε).
    pub skin: f64,
    /// Toolpath tolerance ([`BuildOptions::tolerance`]): arc fitting of outlines and spines,
    /// flattening of curves into polylines and of regions into polygons, and the distance
    /// two placements or joins may differ by.
    pub fit: f64,
    /// Position accuracy of region offsets ([`OFFSET_OF_FIT`] of `fit`).
    pub offset: f64,
    /// Accuracy of lengths and parameter searches along spines ([`LENGTH_OF_FIT`] of
    /// `fit`).
    pub length: f64,
    /// Flattening of the union of several outlines: `fit`, or [`ARC_UNION_FRACTION`] of it
    /// on a G-code laser that writes arcs, whose lines are merged into arcs afterwards.
    pub union: f64,
    /// Arc merge of flattened unions on such a laser: (1 − [`ARC_UNION_FRACTION`])·`fit`, so
    /// that flattening and merge together stay within `fit`.
    pub merge: f64,
    /// Hairline width: a stroke of a design without operations no wider than this is cut
    /// once along its spine, and open inner-boundary runs shorter than it are dropped:
    /// max(kerf or tool diameter, [`crate::design::HAIRLINE_MM`]) (a stroke no wider than
    /// the tool cannot have both edges cut).
    pub hairline: f64,
}

impl Tolerances {
    /// The tolerances of a build with `opts` on `profile` for a design of
    /// `design_mm_per_unit` millimetres per unit.
    #[must_use]
    pub fn new(opts: &BuildOptions, profile: &Profile, design_mm_per_unit: f64) -> Self {
        let fit = opts.tolerance;
        let per_mm = 1.0 / design_mm_per_unit;
        let k = profile.units.mm_per_unit() / design_mm_per_unit;
        let cutter = tool_of(
            profile,
            &[ToolKind::Endmill, ToolKind::Ballnose, ToolKind::Beam],
        );
        let diameter = 2.0 * cutter.map(|t| t.radius() * k).unwrap_or(0.0);
        Tolerances {
            skin: opts.epsilon,
            fit,
            offset: fit * OFFSET_OF_FIT,
            length: fit * LENGTH_OF_FIT,
            union: if laser_arcs(profile) {
                ARC_UNION_FRACTION * fit
            } else {
                fit
            },
            merge: (1.0 - ARC_UNION_FRACTION) * fit,
            hairline: diameter.max(crate::design::HAIRLINE_MM * per_mm),
        }
    }
}

/// The first tool of `profile` of one of the `want` kinds, else its first tool.
pub(crate) fn tool_of<'p>(profile: &'p Profile, want: &[ToolKind]) -> Option<&'p Tool> {
    (profile.tools.iter())
        .find(|t| want.contains(&t.kind))
        .or(profile.tools.first())
}

/// A G-code laser whose profile writes arcs (`arcs` other than "none").
pub(crate) fn laser_arcs(profile: &Profile) -> bool {
    !matches!(profile.kind, MachineKind::Router)
        && (profile.gcode.as_ref()).is_some_and(|g| g.arcs != ArcFormat::None)
}
