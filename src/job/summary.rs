//! The summary of a job ([`Summary`], made by [`JobOutput::summary`]): per operation its
//! cuts and lengths, the skin routes, the placed box, the times and the skin repairs, as
//! `skinpath build --json` prints it.

use super::build::Placement;
use super::checked::JobOutput;
use crate::geom::DVec2;
use crate::machine::Profile;
use crate::sim::Finding;
use crate::toolpath::Toolpath;

/// One operation of the [`Summary`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct OperationSummary {
    /// The operation's name.
    pub name: String,
    /// The toolpath operation kind, lower case (`profile`, `pocket`, ...).
    pub kind: String,
    /// Index of the `[[operation]]` in the design; `None` for the default profile.
    pub design_index: Option<usize>,
    /// Number of cuts.
    pub cuts: usize,
    /// Length of the cutting moves (design units).
    pub cut_length: f64,
    /// Whether the operation switches air assist on.
    pub air_assist: bool,
}

/// The route one operation's paths took ([`crate::job::re_route::RouteNote`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct RouteSummary {
    /// The operation's name in the toolpath (e.g. "profile 1").
    pub operation: String,
    /// "skin", "re" or "mph".
    pub route: String,
    /// What the route did, or why the exact route was not taken.
    pub detail: String,
    /// Arcs of the operation's paths.
    pub arcs: usize,
    /// Lines of the operation's paths.
    pub lines: usize,
    /// Wall time of the operation's paths, seconds (varies from run to run).
    pub seconds: f64,
}

/// Bounding box of the job.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Bounds {
    /// Lowest x, y, z.
    pub min: [f64; 3],
    /// Highest x, y, z.
    pub max: [f64; 3],
}

/// Time estimates in seconds.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct TimeSummary {
    /// The checker's estimate with the machine's acceleration (G-code only).
    pub with_acceleration: Option<f64>,
    /// Cut length over programmed feeds.
    pub at_programmed_feeds: f64,
}

/// The summary of a built job: `skinpath build --json` prints it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct Summary {
    /// The design's file name.
    pub design: String,
    /// The machine profile's name.
    pub machine: String,
    /// Files written (filled in by the caller, which writes them).
    pub outputs: Vec<String>,
    /// One summary per operation.
    pub operations: Vec<OperationSummary>,
    /// Length of all cutting moves (design units).
    pub cut_length: f64,
    /// Length of all travels (design units).
    pub travel_length: f64,
    /// Bounding box of the toolpath.
    pub bounds: Bounds,
    /// Where the job was placed.
    pub placement: Placement,
    /// Time estimates.
    pub time: TimeSummary,
    /// The checker's findings (G-code only).
    pub findings: Vec<Finding>,
    /// The route each profile and backboard took, with its time.
    pub routes: Vec<RouteSummary>,
    /// Wall time of the RE/MPH skins, seconds (0 when the build used none).
    pub re_skin_seconds: f64,
    /// Strokes whose skin cut into them, built on the union of their disks instead
    /// ([`crate::job::outline::ItemOutline::disk_union`]).
    pub disk_unions: Vec<DiskUnionSummary>,
    /// The neon bill of materials (designs with a `[neon]` table).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub neon: Option<super::neon::NeonBom>,
    /// Strokes that could not be skinned as one piece: split at the failing places, pieces
    /// that still failed built on the union of their disks
    /// ([`crate::job::outline::ItemOutline::repair`]).
    pub skin_repairs: Vec<SkinRepairSummary>,
    /// What the build could not cut as drawn: features narrower than the tool
    /// ([`crate::job::build::BuildWarning`]).
    pub warnings: Vec<crate::job::build::BuildWarning>,
}

/// What was done to a stroke that could not be skinned as one piece.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct SkinRepairSummary {
    /// The stroke's name.
    pub stroke: String,
    /// How often it was split (pieces = splits + 1).
    pub splits: usize,
    /// Pieces built on the union of their disks.
    pub fallbacks: usize,
    /// Worst deviation of its outline from its disks (design units): how far a disk reaches
    /// outside the outline or the outline outside the disks.
    pub deviation: f64,
    /// Where the deviation is largest (design coordinates, before placement).
    pub deviation_at: [f64; 2],
    /// Curve parameters of the splits.
    pub split_at: Vec<f64>,
    /// Why the first split or fallback was needed (the skinning error).
    pub reason: String,
    /// Which control disks to change, and how, for the stroke to skin as one piece ("" when
    /// nothing stands out).
    pub hint: String,
}

/// A stroke built on the union of its disks because its skin cut into it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct DiskUnionSummary {
    /// The stroke's name.
    pub stroke: String,
    /// How deep the skin cut into the stroke (design units).
    pub depth: f64,
    /// Centre of the deepest-reaching disk (design coordinates, before placement).
    pub at: [f64; 2],
}

impl JobOutput {
    /// The job's summary, with `outputs` empty.
    pub fn summary(&self, profile: &Profile) -> Summary {
        let tp = &self.built.toolpath;
        let s = tp.stats(DVec2::ZERO);
        let operations = tp
            .operations
            .iter()
            .map(|op| {
                let single = Toolpath {
                    operations: vec![op.clone()],
                };
                let os = single.stats(DVec2::ZERO);
                OperationSummary {
                    name: op.name.clone(),
                    kind: format!("{:?}", op.kind).to_lowercase(),
                    design_index: op.design_index,
                    cuts: op.cuts.len(),
                    cut_length: os.cut_length,
                    air_assist: op.air_assist,
                }
            })
            .collect();
        Summary {
            design: self.design.file.clone(),
            machine: profile.name.clone(),
            outputs: Vec::new(),
            operations,
            cut_length: s.cut_length,
            travel_length: s.travel_length,
            bounds: Bounds {
                min: s.bbox_min,
                max: s.bbox_max,
            },
            placement: self.placement,
            time: TimeSummary {
                with_acceleration: self.report.as_ref().map(|r| r.stats.time.total),
                at_programmed_feeds: s.cut_time,
            },
            findings: self
                .report
                .as_ref()
                .map(|r| r.findings.clone())
                .unwrap_or_default(),
            routes: self
                .built
                .routes
                .iter()
                .map(|r| RouteSummary {
                    operation: r.operation.clone(),
                    route: r.route.clone(),
                    detail: r.detail.clone(),
                    arcs: r.counts.arcs,
                    lines: r.counts.lines,
                    seconds: r.seconds,
                })
                .collect(),
            re_skin_seconds: self.built.re_skin_seconds,
            disk_unions: self
                .built
                .outlines
                .iter()
                .filter_map(|o| {
                    o.disk_union.map(|u| DiskUnionSummary {
                        stroke: o.name.clone(),
                        depth: u.depth,
                        at: [u.at.x, u.at.y],
                    })
                })
                .collect(),
            neon: self.built.neon.clone(),
            skin_repairs: self
                .built
                .outlines
                .iter()
                .filter_map(|o| {
                    let r = o.repair.as_ref()?;
                    Some(SkinRepairSummary {
                        stroke: o.name.clone(),
                        splits: r.splits.len(),
                        fallbacks: r.fallbacks.len(),
                        deviation: r.deviation,
                        deviation_at: [r.deviation_at.x, r.deviation_at.y],
                        split_at: r.splits.iter().map(|s| s.t).collect(),
                        reason: r
                            .splits
                            .first()
                            .map(|s| s.reason.clone())
                            .or_else(|| r.fallbacks.first().map(|f| f.reason.clone()))
                            .unwrap_or_default(),
                        hint: r.hint.clone().unwrap_or_default(),
                    })
                })
                .collect(),
            warnings: self.built.warnings.clone(),
        }
    }
}
