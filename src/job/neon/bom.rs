//! The bill of materials of a neon sign ([`NeonBom`], made by [`bom`]): per run its
//! strokes, length, cut length and tightest bend.

use super::runs::COINCIDE_REL;
use super::{
    BEND_PARAM_TOL, Run, SPINE_FLATTEN_OF_WIDTH, TANGENT_BREAK_DEG, span_min_radius, spine_length,
};
use crate::dbsc::DiskBSpline;
use crate::design::neon::{CHANNEL_CLEARANCE_MM, Flex};
use crate::design::{Design, OperationKind};
use crate::geom::DVec2;

/// Relative round-off forgiven when a run's length is rounded up to whole cut units: a
/// run of exactly n units (up to 10⁻¹² of its length, the quadrature's and the sum's
/// rounding) orders n units, not n + 1.
const CUT_UNIT_ROUNDOFF: f64 = 1e-12;

/// Where along a run something is: the stroke, its parameter and the point (design
/// coordinates, before placement).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunPlace {
    /// The stroke's name.
    pub stroke: String,
    /// Parameter on the stroke.
    pub t: f64,
    /// x of the point.
    pub x: f64,
    /// y of the point.
    pub y: f64,
}

/// A stretch of a run bent tighter than the flex takes (or a corner: radius 0).
#[derive(Clone, Debug, PartialEq)]
pub struct TightBend {
    /// The run's name.
    pub run: String,
    /// Smallest radius on the stretch (design units).
    pub radius: f64,
    /// Where it is.
    pub at: RunPlace,
    /// The bend is a join of two strokes whose tangents break.
    pub join: bool,
}

/// Two runs whose spines come closer than the channel width.
#[derive(Clone, Debug, PartialEq)]
pub struct CloseRuns {
    /// Names of the two runs.
    pub runs: [String; 2],
    /// Smallest distance between their spines (design units).
    pub distance: f64,
    /// Midpoint of the closest points.
    pub at: [f64; 2],
}

/// One run in the bill of materials.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunBom {
    /// The run's name.
    pub name: String,
    /// Its strokes, in order.
    pub strokes: Vec<String>,
    /// The run returns to its start.
    pub closed: bool,
    /// Flex length: the spine lengths (plus any bridged gap), mm.
    pub length_mm: f64,
    /// The length rounded up to the cut unit, mm.
    pub cut_length_mm: f64,
    /// Straight gaps between joined strokes that the flex bridges (in `length_mm`), mm.
    pub bridged_mm: f64,
    /// The smallest bend radius along the run, mm (0 at a corner).
    pub min_bend_radius_mm: f64,
    /// Where that bend is.
    pub at: RunPlace,
    /// With `round_bends`: the bends rounded to the flex's minimum radius.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rounded_bends: Option<usize>,
    /// With `round_bends`: the largest distance between a rounded stretch and the drawn
    /// spine, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rounding_deviation_mm: Option<f64>,
}

/// A run shorter than `[neon] min_run_length`: a mark (channel cut, no flex, no holes).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MarkBom {
    /// The run's name.
    pub name: String,
    /// Its strokes, in order.
    pub strokes: Vec<String>,
    /// Its spine length (with bridged gaps), mm.
    pub length_mm: f64,
}

/// A warning of the neon check.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NeonWarning {
    /// `bend` (tighter than the flex) or `merge` (channels of two runs run into one).
    pub kind: String,
    /// What and where, in words.
    pub message: String,
    /// The place (design coordinates, before placement).
    pub at: [f64; 2],
}

/// The flex's sizes in the summary, mm.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FlexSummary {
    /// Flex width.
    pub width_mm: f64,
    /// Flex height.
    pub height_mm: f64,
    /// Minimum bend radius.
    pub min_bend_radius_mm: f64,
    /// Cut unit.
    pub cut_unit_mm: f64,
}

/// The neon bill of materials of a build (`build --json`: `neon`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct NeonBom {
    /// The flex.
    pub flex: FlexSummary,
    /// Every run.
    pub runs: Vec<RunBom>,
    /// Σ of the runs' lengths, mm.
    pub total_length_mm: f64,
    /// Σ of the runs' cut lengths, mm (what to order).
    pub total_cut_length_mm: f64,
    /// Wire holes drilled by the build's holes operations.
    pub holes: usize,
    /// The scale the design was built at (1 unscaled).
    pub scale: f64,
    /// Runs shorter than `min_run_length`: marks, not flex (not in the totals).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub marks: Vec<MarkBom>,
    /// Bends below the flex minimum, channels that merge, runs shorter than the cut unit
    /// and bends `round_bends` could not round ([`NeonBom::judge`]).
    pub warnings: Vec<NeonWarning>,
    /// The `round` warnings of `round_bends` (kept across [`NeonBom::judge`]).
    #[serde(skip)]
    pub round_warnings: Vec<NeonWarning>,
    /// Every stretch bent tighter than the flex (design units).
    #[serde(skip)]
    pub tight: Vec<TightBend>,
    /// The runs' spines, flattened (design units), for the merge test of [`NeonBom::judge`].
    #[serde(skip)]
    pub spines: Vec<Vec<DVec2>>,
    /// Per run and spine point, the index (in the run's `strokes`) of the stroke it is on.
    #[serde(skip)]
    pub spine_legs: Vec<Vec<usize>>,
    /// The flex minimum radius and the channel width, design units.
    #[serde(skip)]
    pub limits: (f64, f64),
    /// Millimetres per design unit.
    #[serde(skip)]
    pub mm: f64,
}

fn tight_bend(run: &Run, radius: f64, at: RunPlace, join: bool) -> TightBend {
    TightBend {
        run: run.name.clone(),
        radius,
        at,
        join,
    }
}

fn place(design: &Design, c: &DiskBSpline, stroke: usize, t: f64) -> RunPlace {
    let p = c.center(t);
    RunPlace {
        stroke: design.stroke[stroke].name.clone(),
        t,
        x: p.x,
        y: p.y,
    }
}

/// The bill of materials of `runs` (module docs) with the flex `flex`; `tol` is the
/// absolute length tolerance per stroke (design units); `holes` the wire holes drilled.
pub fn bom(
    design: &Design,
    curves: &[DiskBSpline],
    runs: &[Run],
    flex: &Flex,
    tol: f64,
    holes: usize,
) -> NeonBom {
    let mm = design.units.mm_per_unit();
    let break_cos = TANGENT_BREAK_DEG.to_radians().cos();
    let mut out_runs = Vec::new();
    let mut tight = Vec::new();
    for run in runs {
        let mut length = 0.0;
        let mut bridged = 0.0;
        let mut best: Option<(f64, RunPlace)> = None;
        let mut lower = |r: f64, at: &dyn Fn() -> RunPlace| {
            if best.as_ref().is_none_or(|(b, _)| r < *b) {
                best = Some((r, at()));
            }
        };
        let n = run.legs.len();
        for (k, leg) in run.legs.iter().enumerate() {
            let c = &curves[leg.stroke];
            length += spine_length(c, tol);
            // Spans in the run's direction; a stretch of consecutive tight spans is one
            // tight bend (its smallest radius).
            let mut spans: Vec<(f64, f64)> = c
                .breakpoints()
                .windows(2)
                .filter(|w| w[1] > w[0])
                .map(|w| span_min_radius(c, w[0], w[1], BEND_PARAM_TOL))
                .collect();
            if leg.reversed {
                spans.reverse();
            }
            let mut stretch: Option<(f64, f64)> = None;
            for &(r, t) in &spans {
                lower(r, &|| place(design, c, leg.stroke, t));
                if r < flex.min_bend_radius {
                    if stretch.is_none_or(|(b, _)| r < b) {
                        stretch = Some((r, t));
                    }
                } else if let Some((sr, st)) = stretch.take() {
                    tight.push(tight_bend(run, sr, place(design, c, leg.stroke, st), false));
                }
            }
            if let Some((sr, st)) = stretch {
                tight.push(tight_bend(run, sr, place(design, c, leg.stroke, st), false));
            }
            // The join into the next leg (and the seam of a closed chain).
            let next = if k + 1 < n {
                Some(&run.legs[k + 1])
            } else if run.closed && n > 1 {
                Some(&run.legs[0])
            } else {
                None
            };
            if let Some(nx) = next {
                let (p, t_out) = leg.exit(curves);
                let (q, t_in) = nx.entry(curves);
                let gap = p.distance(q);
                let u = leg.direction(curves, t_out);
                let v = nx.direction(curves, t_in);
                // A gap is bridged straight: the flex turns from u to the bridge and from
                // the bridge to v.
                let broken = if gap <= COINCIDE_REL * (1.0 + p.length()) {
                    u.dot(v) < break_cos
                } else {
                    bridged += gap;
                    let g = (q - p) / gap;
                    u.dot(g) < break_cos || g.dot(v) < break_cos
                };
                if broken {
                    let at = || place(design, &curves[nx.stroke], nx.stroke, t_in);
                    lower(0.0, &at);
                    tight.push(tight_bend(run, 0.0, at(), true));
                }
            }
        }
        // A run without any bend (all straight) reports its start, radius ∞.
        let (min_r, at) = best.unwrap_or_else(|| {
            let l = run.legs[0];
            let t = l.entry(curves).1;
            (f64::INFINITY, place(design, &curves[l.stroke], l.stroke, t))
        });
        let length = length + bridged;
        let units = (length / flex.cut_unit * (1.0 - CUT_UNIT_ROUNDOFF))
            .ceil()
            .max(1.0);
        out_runs.push(RunBom {
            name: run.name.clone(),
            strokes: run
                .legs
                .iter()
                .map(|l| design.stroke[l.stroke].name.clone())
                .collect(),
            closed: run.closed,
            length_mm: length * mm,
            cut_length_mm: units * flex.cut_unit * mm,
            bridged_mm: bridged * mm,
            min_bend_radius_mm: min_r * mm,
            at,
            rounded_bends: None,
            rounding_deviation_mm: None,
        });
    }
    let width = channel_width(design, flex);
    let (spines, spine_legs) = run_polylines(curves, runs, SPINE_FLATTEN_OF_WIDTH * flex.width);
    let total_length_mm = out_runs.iter().map(|r| r.length_mm).sum();
    let total_cut_length_mm = out_runs.iter().map(|r| r.cut_length_mm).sum();
    let mut b = NeonBom {
        flex: FlexSummary {
            width_mm: flex.width * mm,
            height_mm: flex.height * mm,
            min_bend_radius_mm: flex.min_bend_radius * mm,
            cut_unit_mm: flex.cut_unit * mm,
        },
        runs: out_runs,
        total_length_mm,
        total_cut_length_mm,
        holes,
        scale: 1.0,
        marks: Vec::new(),
        warnings: Vec::new(),
        round_warnings: Vec::new(),
        tight,
        spines,
        spine_legs,
        limits: (flex.min_bend_radius, width),
        mm,
    };
    b.judge(1.0);
    b
}

/// The width of the design's channels: the first channel operation's `width`, else the flex
/// width plus [`CHANNEL_CLEARANCE_MM`].
pub fn channel_width(design: &Design, flex: &Flex) -> f64 {
    design
        .operation
        .iter()
        .find(|o| o.kind == OperationKind::Channel)
        .and_then(|o| o.width)
        .unwrap_or(flex.width + CHANNEL_CLEARANCE_MM / design.units.mm_per_unit())
}

/// The runs' spines flattened within `tol`, one polyline per run (its legs in order), and
/// per point the index of its leg in the run.
fn run_polylines(
    curves: &[DiskBSpline],
    runs: &[Run],
    tol: f64,
) -> (Vec<Vec<DVec2>>, Vec<Vec<usize>>) {
    runs.iter()
        .map(|r| {
            let mut pts = Vec::new();
            let mut legs = Vec::new();
            for (k, l) in r.legs.iter().enumerate() {
                let mut p = crate::dbsc::flatten::flatten_spine(&curves[l.stroke], tol);
                if l.reversed {
                    p.reverse();
                }
                legs.extend(std::iter::repeat_n(k, p.len()));
                pts.extend(p);
            }
            (pts, legs)
        })
        .unzip()
}
