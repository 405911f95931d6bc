//! What `skinpath inspect` reports about a design: per stroke its degree, disks, knot
//! spans, spine length, radius range, spans without an envelope, envelope loops and the
//! skin approximation report; per circle sequence its size and admissibility.

use super::JobError;
use super::outline::{OutlineOptions, circles_outline, stroke_outline};
use crate::dbsc::flatten::flatten_spine;
use crate::dbsc::{DiskBSpline, Side};
use crate::design::Design;
use serde::Serialize;

/// Radius samples per knot span when measuring the radius range (r is a polynomial of
/// degree p per span; the extremes of the control radii bound it, samples refine it).
const RADIUS_SAMPLES_PER_SPAN: usize = 64;

#[derive(Clone, Debug, Serialize)]
/// An envelope loop of a stroke: a parameter interval where one envelope runs backwards.
pub struct LoopInfo {
    /// The envelope side that loops.
    pub side: Side,
    /// Parameter interval of the loop.
    pub t: [f64; 2],
    /// A cusp of the loop, when one was located.
    pub point: Option<[f64; 2]>,
}

#[derive(Clone, Debug, Serialize)]
/// One segment of a stroke's skin approximation.
pub struct SegmentInfo {
    /// Parameter interval of the segment.
    pub t: [f64; 2],
    /// Upper bounds of the Hausdorff error, left and right.
    pub error: [f64; 2],
    /// Whether both bounds are within ε.
    pub met: bool,
    /// The stage the refinement stopped in, when it stopped short of ε.
    pub stopped_in: Option<String>,
    /// Envelope loops inside the segment.
    pub loops: usize,
}

#[derive(Clone, Debug, Serialize)]
/// The report on one stroke.
pub struct StrokeInfo {
    /// The stroke's name.
    pub name: String,
    /// Degree of the disk B-spline.
    pub degree: usize,
    /// Whether the stroke is closed.
    pub closed: bool,
    /// Number of control disks.
    pub disks: usize,
    /// Number of non-empty knot spans.
    pub knot_spans: usize,
    /// Parameter domain.
    pub domain: [f64; 2],
    /// Length of the spine (design units).
    pub spine_length: f64,
    /// Smallest and largest radius along the stroke.
    pub radius_range: [f64; 2],
    /// Parameter intervals without an envelope (|q'| ≤ |r'|).
    pub no_envelope: Vec<[f64; 2]>,
    /// Envelope loops.
    pub loops: Vec<LoopInfo>,
    /// Circles the skin touches (knot and inserted circles).
    pub skin_circles: usize,
    /// The skin approximation's segments.
    pub segments: Vec<SegmentInfo>,
    /// Why no skin could be made, when it could not.
    pub skin_error: Option<String>,
}

#[derive(Clone, Debug, Serialize)]
/// The report on one circle sequence.
pub struct CirclesInfo {
    /// The sequence's name.
    pub name: String,
    /// Whether the sequence is closed.
    pub closed: bool,
    /// Number of circles.
    pub circles: usize,
    /// Whether the sequence meets the skinning conditions.
    pub admissible: bool,
    /// Why it does not, when it does not.
    pub error: Option<String>,
}

#[derive(Clone, Debug, Serialize)]
/// The report on a design (what `skinpath inspect` prints).
#[non_exhaustive]
pub struct DesignInfo {
    /// The design file.
    pub file: String,
    /// Design units: `mm` or `inch`.
    pub units: String,
    /// ε of the skin approximation.
    pub epsilon: f64,
    /// One report per stroke.
    pub strokes: Vec<StrokeInfo>,
    /// One report per circle sequence.
    pub circles: Vec<CirclesInfo>,
    /// Corners at which strokes were split into pieces (`corners` in the design).
    pub corners: Vec<crate::design::Corner>,
    /// The `[[shape]]` regions.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub shapes: Vec<super::shapes::ShapeInfo>,
    /// The `[[output]]` tables: what `build` writes for each.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub outputs: Vec<OutputInfo>,
}

/// One `[[output]]` of the design, as `build` makes it.
#[derive(Clone, Debug, Serialize)]
pub struct OutputInfo {
    /// The output's name.
    pub name: String,
    /// Its machine: a shipped profile name or a profile file.
    pub machine: String,
    /// The file name template (`{stem}`, `{name}`, `{ext}`).
    pub file: String,
    /// The operations it builds, each as `N kind` or `N kind "name"` (N 1-based, as in
    /// errors); every operation when it selects none.
    pub operations: Vec<String>,
}

/// The outputs of `design` with the operations each builds.
fn output_infos(design: &Design) -> Vec<OutputInfo> {
    design
        .output
        .iter()
        .map(|o| {
            let ops: Vec<usize> = o
                .operations_of(design)
                .unwrap_or_else(|| (0..design.operation.len()).collect());
            OutputInfo {
                name: o.name.clone(),
                machine: o.machine.clone(),
                file: o
                    .file
                    .clone()
                    .unwrap_or_else(|| crate::design::output::DEFAULT_FILE.to_string()),
                operations: ops
                    .iter()
                    .map(|&i| {
                        let op = &design.operation[i];
                        match &op.name {
                            Some(n) => format!("{} {} \"{n}\"", i + 1, op.kind.as_str()),
                            None => format!("{} {}", i + 1, op.kind.as_str()),
                        }
                    })
                    .collect(),
            }
        })
        .collect()
}

fn radius_range(c: &DiskBSpline) -> [f64; 2] {
    let b = c.breakpoints();
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for w in b.windows(2) {
        for k in 0..=RADIUS_SAMPLES_PER_SPAN {
            let r = c.radius(w[0] + (w[1] - w[0]) * k as f64 / RADIUS_SAMPLES_PER_SPAN as f64);
            lo = lo.min(r);
            hi = hi.max(r);
        }
    }
    [lo, hi]
}

/// Inspect every stroke and circle sequence.
pub fn inspect(design: &Design, opts: &OutlineOptions) -> Result<DesignInfo, JobError> {
    let strokes = design.strokes()?;
    let mut out = DesignInfo {
        file: design.file.clone(),
        units: format!("{:?}", design.units).to_lowercase(),
        epsilon: opts.epsilon,
        strokes: Vec::new(),
        circles: Vec::new(),
        corners: design.corners.clone(),
        shapes: super::shapes::shape_infos(design),
        outputs: output_infos(design),
    };
    for (s, c) in design.stroke.iter().zip(&strokes) {
        let spine = flatten_spine(c, opts.tolerance);
        let spine_length = spine.windows(2).map(|w| w[0].distance(w[1])).sum();
        let (lo, hi) = c.domain();
        let mut info = StrokeInfo {
            name: s.name.clone(),
            degree: c.degree(),
            closed: c.is_closed(),
            disks: c.control_disks().len(),
            knot_spans: c.breakpoints().len().saturating_sub(1),
            domain: [lo, hi],
            spine_length,
            radius_range: radius_range(c),
            no_envelope: Vec::new(),
            loops: Vec::new(),
            skin_circles: 0,
            segments: Vec::new(),
            skin_error: None,
        };
        match stroke_outline(design, &s.name, c, opts) {
            Ok(item) => {
                if let Some(l) = &item.loops {
                    info.no_envelope = l.no_envelope.iter().map(|&(a, b)| [a, b]).collect();
                    info.loops = l
                        .loops
                        .iter()
                        .map(|l| LoopInfo {
                            side: l.side,
                            t: [l.t_a, l.t_b],
                            point: l.cusp_a.map(|p| [p.x, p.y]),
                        })
                        .collect();
                }
                info.skin_circles = item.circles.len();
                info.segments = item
                    .segments
                    .iter()
                    .map(|r| SegmentInfo {
                        t: [r.t0, r.t1],
                        error: [r.error_left.upper, r.error_right.upper],
                        met: r.met_left && r.met_right,
                        stopped_in: r.stopped_in.map(|p| format!("{p:?}").to_lowercase()),
                        loops: r.loops.len(),
                    })
                    .collect();
            }
            Err(e) => info.skin_error = Some(e.to_string()),
        }
        out.strokes.push(info);
    }
    for (seq, circles) in design.circles.iter().zip(design.circle_sequences()) {
        let r = circles_outline(design, &seq.name, &circles, seq.closed);
        out.circles.push(CirclesInfo {
            name: seq.name.clone(),
            closed: seq.closed,
            circles: circles.len(),
            admissible: r.is_ok(),
            error: r.err().map(|e| e.to_string()),
        });
    }
    Ok(out)
}

impl std::fmt::Display for DesignInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{} ({}), skin epsilon {}",
            self.file, self.units, self.epsilon
        )?;
        for o in &self.outputs {
            writeln!(
                f,
                "output \"{}\": machine {}, file {}, operations {}",
                o.name,
                o.machine,
                o.file,
                if o.operations.is_empty() {
                    "the default ones".to_string()
                } else {
                    o.operations.join(", ")
                }
            )?;
        }
        for c in &self.corners {
            writeln!(
                f,
                "corner of stroke \"{}\" at {} {} ({:.3}, {:.3}): pieces \"{}\" and \"{}\" share that disk",
                c.stroke, c.kind, c.index, c.at[0], c.at[1], c.pieces[0], c.pieces[1]
            )?;
        }
        for s in &self.strokes {
            writeln!(
                f,
                "stroke \"{}\": degree {}, {} disks, {} knot spans, {}, t in [{}, {}]",
                s.name,
                s.degree,
                s.disks,
                s.knot_spans,
                if s.closed { "closed" } else { "open" },
                s.domain[0],
                s.domain[1]
            )?;
            writeln!(
                f,
                "  spine length {:.3}, radius {:.3} .. {:.3}",
                s.spine_length, s.radius_range[0], s.radius_range[1]
            )?;
            if s.no_envelope.is_empty() {
                writeln!(f, "  envelope exists everywhere")?;
            }
            for iv in &s.no_envelope {
                writeln!(f, "  no envelope for t in [{:.6}, {:.6}]", iv[0], iv[1])?;
            }
            if s.loops.is_empty() {
                writeln!(f, "  envelope loops: none")?;
            }
            for l in &s.loops {
                writeln!(
                    f,
                    "  envelope loop: {:?} side, t in [{:.6}, {:.6}]",
                    l.side, l.t[0], l.t[1]
                )?;
            }
            match &s.skin_error {
                Some(e) => writeln!(f, "  skin: FAILED: {e}")?,
                None => {
                    let missed = s.segments.iter().filter(|g| !g.met).count();
                    let worst = s
                        .segments
                        .iter()
                        .map(|g| g.error[0].max(g.error[1]))
                        .fold(0.0, f64::max);
                    writeln!(
                        f,
                        "  skin: {} circles, {} segments, worst error {:.4} ({} segments miss epsilon)",
                        s.skin_circles,
                        s.segments.len(),
                        worst,
                        missed
                    )?;
                    for g in s.segments.iter().filter(|g| !g.met) {
                        writeln!(
                            f,
                            "    t in [{:.6}, {:.6}]: error left {:.4}, right {:.4}, stopped in phase {}{}",
                            g.t[0],
                            g.t[1],
                            g.error[0],
                            g.error[1],
                            g.stopped_in.as_deref().unwrap_or("-"),
                            if g.loops > 0 {
                                ", envelope loop here"
                            } else {
                                ""
                            }
                        )?;
                    }
                }
            }
        }
        for c in &self.circles {
            writeln!(
                f,
                "circles \"{}\": {} circles, {}, {}",
                c.name,
                c.circles,
                if c.closed { "closed" } else { "open" },
                match &c.error {
                    None => "admissible".to_string(),
                    Some(e) => format!("NOT admissible: {e}"),
                }
            )?;
        }
        for s in &self.shapes {
            write!(f, "{s}")?;
        }
        Ok(())
    }
}
