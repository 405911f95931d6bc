//! One checked job, the library's entry point for a whole build: a design (read from a
//! file or made in code, see [`design_of_strokes`]) and a machine profile in; the machine
//! program, its toolpath, the checker's report and a summary out.
//!
//! [`Job::run`] does what `skinpath build` does between reading its files and writing
//! them: scale the design (`scale`/`fit`), build the toolpath ([`super::build`]), place it
//! in the work area, write the program and, for G-code, read it back and check it exactly
//! as `skinpath check PROGRAM --machine SAME` would, with the allowance the build gives
//! itself near the design (arc fitting and boundary flattening, each `tolerance`,
//! coordinate rounding and the checker's arc flattening). A program with findings of error
//! severity is refused ([`JobError::Unchecked`]) unless
//! [`JobOptions::write_unchecked`] is set.

use super::JobError;
use super::build::{
    BuildOptions, BuildResult, Place, PlaceAt, Placement, build_toolpath_placed, fit_scale,
    outline_bounds, place_job, scaled_design,
};
use super::check::{check_config, design_boundaries};
use super::progress::{Progress, ProgressFn, Stage, Timings};
use crate::dbsc::DiskBSpline;
use crate::design::{CircleSeq, Design, Stroke};
use crate::emit::{
    DxfOptions, GcodeOptions, LaserSvgOptions, LineOrigin, dxf, gcode_with_origins, laser_svg,
};
use crate::geom::{Circle, DVec2};
use crate::machine::{MachineKind, Profile};
use crate::sim::{Backend, Finding, Report, Severity, check_text};
use crate::toolpath::Toolpath;
use std::sync::{Mutex, MutexGuard};
use std::time::Instant;

/// How much smaller than exact `--fit` makes the design, as a fraction of the scale: a
/// millionth, so that the program's rounded coordinates stay inside the size asked for.
const FIT_SHRINK: f64 = 1e-6;

/// The kind of machine program a job writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// G-code, checked before it is returned.
    Gcode,
    /// Laser SVG for upload (LightBurn-style colours per operation).
    Svg,
    /// DXF.
    Dxf,
}

impl OutputFormat {
    /// The format a file extension names (`gcode`, `nc`, `ngc`, `tap`, `g`, `svg`, `dxf`;
    /// lower case, without the dot).
    pub fn from_extension(ext: &str) -> Option<Self> {
        match ext {
            "gcode" | "nc" | "ngc" | "tap" | "g" => Some(OutputFormat::Gcode),
            "svg" => Some(OutputFormat::Svg),
            "dxf" => Some(OutputFormat::Dxf),
            _ => None,
        }
    }

    /// The format's name: `gcode`, `svg` or `dxf`.
    pub fn as_str(self) -> &'static str {
        match self {
            OutputFormat::Gcode => "gcode",
            OutputFormat::Svg => "svg",
            OutputFormat::Dxf => "dxf",
        }
    }

    /// The format a profile writes by default: laser SVG for SVG profiles, else G-code.
    pub fn default_for(profile: &Profile) -> Self {
        match profile.kind {
            MachineKind::Svg => OutputFormat::Svg,
            MachineKind::Laser | MachineKind::Router => OutputFormat::Gcode,
        }
    }
}

/// How the design is scaled before it is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// As written.
    None,
    /// Strokes, circles and text scaled by this factor about the origin (channel widths,
    /// hole diameters, depths and margins stay as written, as `scaled_design` scales it).
    By(f64),
    /// Scaled uniformly so that the whole job (tool paths included) fits `width` ×
    /// `height` design units.
    Fit {
        /// Largest width (design units).
        width: f64,
        /// Largest height (design units).
        height: f64,
    },
}

/// Options of a [`Job`].
#[derive(Clone, Copy)]
#[non_exhaustive]
pub struct JobOptions<'a> {
    /// Tolerance, ε and skin route of the toolpath.
    pub build: BuildOptions,
    /// Where the job goes in the work area.
    pub place: Place,
    /// Distance from the work area's corner with [`Place::LowerLeft`], design units.
    pub margin: f64,
    /// Scaling of the design.
    pub scale: Scale,
    /// The program to write.
    pub format: OutputFormat,
    /// The job's name in the program's header.
    pub name: &'a str,
    /// Return a G-code program even when its check finds errors (the findings are then in
    /// [`JobOutput::report`] and [`JobOutput::explanations`]).
    pub write_unchecked: bool,
    /// Called with the stage and fraction done during long work.
    pub progress: Option<ProgressFn<'a>>,
}

impl Default for JobOptions<'_> {
    fn default() -> Self {
        JobOptions {
            build: BuildOptions::default(),
            place: Place::LowerLeft,
            margin: 0.0,
            scale: Scale::None,
            format: OutputFormat::Gcode,
            name: "skinpath",
            write_unchecked: false,
            progress: None,
        }
    }
}

impl std::fmt::Debug for JobOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("JobOptions")
            .field("build", &self.build)
            .field("place", &self.place)
            .field("margin", &self.margin)
            .field("scale", &self.scale)
            .field("format", &self.format)
            .field("name", &self.name)
            .field("write_unchecked", &self.write_unchecked)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// A design to build for a machine.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Job<'a> {
    /// The design.
    pub design: &'a Design,
    /// The machine profile.
    pub profile: &'a Profile,
    /// How to build, check and write.
    pub options: JobOptions<'a>,
}

/// What a job made.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct JobOutput {
    /// The machine program (G-code, laser SVG or DXF text).
    pub program: String,
    /// The design as built (scaled when [`JobOptions::scale`] asked for it).
    pub design: Design,
    /// Toolpath (placed), outlines, skin routes and ordering statistics.
    pub built: BuildResult,
    /// Where the job went in the work area, and the scale it was built at.
    pub placement: Placement,
    /// The checker's report of a G-code program (`None` for SVG and DXF).
    pub report: Option<Report>,
    /// Every finding of error severity traced back to the design's operation and stroke,
    /// with advice (as `explain` writes them); empty when the check passed.
    pub explanations: Vec<String>,
    /// For every program line (0-based), the operation and cut that made it (G-code).
    pub origins: Vec<LineOrigin>,
    /// Wall time of the job's stages.
    pub timings: Timings,
}

impl<'a> Job<'a> {
    /// The job of building `design` for `profile` as `options` say.
    #[must_use]
    pub fn new(design: &'a Design, profile: &'a Profile, options: JobOptions<'a>) -> Self {
        Job {
            design,
            profile,
            options,
        }
    }

    /// Builds, places, writes and (G-code) checks the job.
    pub fn run(&self) -> Result<JobOutput, JobError> {
        self.run_of(None)
    }

    /// [`Job::run`], building only the operations whose 0-based indices `only` lists (an
    /// `[[output]]`'s selection, [`crate::design::Output::operations_of`]); `None`: every
    /// operation. The design's other operations stay context (as `build_toolpath_placed` builds them).
    pub fn run_of(&self, only: Option<&[usize]>) -> Result<JobOutput, JobError> {
        let o = &self.options;
        let profile = self.profile;
        if !(o.margin.is_finite() && o.margin >= 0.0) {
            return Err(JobError::Options(format!(
                "the margin must be a finite, non-negative distance in design units, got {}",
                o.margin
            )));
        }
        let clock = StageClock::new(o.progress);
        let on_progress = |p: Progress| clock.seen(p);
        let progress: Option<ProgressFn<'_>> = Some(&on_progress);
        let decimals = profile.gcode_settings().map(|g| g.decimals).unwrap_or(3);
        let k = profile.units.mm_per_unit() / self.design.units.mm_per_unit();
        // Two units of the program's last decimal, so that coordinate rounding cannot put an
        // arc's extreme point a hair outside the work area: a reader takes the arc's radius
        // from the rounded start and the rounded centre offset, each off by up to half a unit
        // per axis, so the radius (and the extreme) moves by up to √2 units (with one unit, a
        // hole's circle placed at the corner can reach a unit outside).
        let inset = 2.0 * 10f64.powi(-(decimals as i32)) * k;
        let (design, mut built, scale) = self.scaled_build(progress, inset, only)?;
        clock.start(Stage::Place);
        let placement = place_job(
            &mut built,
            profile,
            design.units.mm_per_unit(),
            o.place,
            o.margin,
            inset,
            scale,
        )?;
        clock.start(Stage::Emit);
        let units = design.units;
        let mut report = None;
        let mut explanations = Vec::new();
        let mut origins = Vec::new();
        let program = match o.format {
            OutputFormat::Gcode => {
                if profile.kind == MachineKind::Svg {
                    return Err(JobError::Options(format!(
                        "profile {:?} is for SVG/DXF upload; choose a G-code profile or write \
                         .svg/.dxf",
                        profile.name
                    )));
                }
                let (g, orig) = gcode_with_origins(
                    &built.toolpath,
                    profile,
                    &GcodeOptions {
                        job: o.name.to_string(),
                        input_units: units,
                        tolerance: o.build.tolerance * super::tolerances::EMIT_OF_FIT,
                        check_work_area: true,
                    },
                )?;
                clock.start(Stage::Check);
                let r = check_program(&g, &design, &built, profile, &o.build, decimals);
                explanations = r
                    .findings
                    .iter()
                    .filter(|f| f.severity == Severity::Error)
                    .map(|f| explain(f, &orig, &built.toolpath, &design))
                    .collect();
                if r.errors() > 0 && !o.write_unchecked {
                    return Err(JobError::Unchecked {
                        file: design.file.clone(),
                        errors: r.errors_in_all(),
                        explanations,
                    });
                }
                origins = orig;
                report = Some(r);
                g
            }
            OutputFormat::Svg => laser_svg(
                &built.toolpath,
                profile,
                &LaserSvgOptions {
                    job: o.name.to_string(),
                    ..LaserSvgOptions::default()
                },
            )?,
            OutputFormat::Dxf => dxf(
                &built.toolpath,
                &DxfOptions {
                    colors: profile.svg.as_ref().map(|s| s.colors.clone()),
                    ..DxfOptions::default()
                },
            )?,
        };
        let timings = clock.finish();
        Ok(JobOutput {
            program,
            design,
            built,
            placement,
            report,
            explanations,
            origins,
            timings,
        })
    }

    /// The design scaled as [`JobOptions::scale`] says and its toolpath (not yet placed).
    /// Without `--fit`, a design whose extent alone cannot fit the work area (with the
    /// placement's padding and the rounding `inset`) is refused before the build
    /// ([`super::size::early_extent`]).
    fn scaled_build(
        &self,
        progress: Option<ProgressFn<'_>>,
        inset: f64,
        only: Option<&[usize]>,
    ) -> Result<(Design, BuildResult, f64), JobError> {
        let o = &self.options;
        let original = self.design;
        let fit = match o.scale {
            Scale::None => None,
            Scale::By(s) if !(s.is_finite() && s > 0.0) => {
                return Err(JobError::Options(format!(
                    "--scale {s}: must be a positive number"
                )));
            }
            Scale::By(_) => None,
            Scale::Fit { width, height }
                if !(width.is_finite() && height.is_finite() && width > 0.0 && height > 0.0) =>
            {
                return Err(JobError::Options(format!(
                    "--fit {width}x{height}: width and height must be positive numbers"
                )));
            }
            Scale::Fit { width, height } => Some((width, height)),
        };
        let mut scale = match o.scale {
            Scale::By(s) => s,
            _ => 1.0,
        };
        let mut design = if scale != 1.0 {
            scaled_design(original, scale)
        } else {
            original.clone()
        };
        let slack = 2.0 * (o.build.epsilon + 2.0 * o.build.tolerance) + o.build.tolerance;
        // The early extent reads the design's operations: with a selection, only those.
        let selected;
        let cut = match only {
            Some(only) => {
                selected = Design {
                    operation: (only.iter())
                        .filter_map(|&i| design.operation.get(i).cloned())
                        .collect(),
                    ..design.clone()
                };
                &selected
            }
            None => &design,
        };
        if fit.is_none()
            && let Some((lo, hi)) = super::size::early_extent(cut, slack)
        {
            super::size::check_fits(
                hi - lo,
                true,
                self.profile,
                design.units.mm_per_unit(),
                o.place,
                o.margin,
                inset,
                scale,
            )?;
        }
        // Ordered from the machine's origin where the placement will put it.
        let at = PlaceAt {
            place: o.place,
            margin: o.margin,
            inset,
        };
        let build =
            |d: &Design| build_toolpath_placed(d, self.profile, &o.build, Some(at), progress, only);
        let mut built = build(&design)?;
        if let Some((w, h)) = fit {
            // The outlines scale with the design, offsets and margins do not: a few rounds.
            for round in 0..=FIT_ROUNDS {
                let s = built.toolpath.stats(DVec2::ZERO);
                let job = DVec2::new(s.bbox_max[0] - s.bbox_min[0], s.bbox_max[1] - s.bbox_min[1]);
                if job.x <= w && job.y <= h && scale != 1.0 {
                    break;
                }
                if round == FIT_ROUNDS {
                    return Err(JobError::Options(format!(
                        "--fit {w}x{h}: the job is still {:.4} x {:.4} after {FIT_ROUNDS} \
                         rounds of scaling; give a slightly larger size",
                        job.x, job.y
                    )));
                }
                let Some((lo, hi)) = outline_bounds(&built.outlines, o.build.tolerance) else {
                    break;
                };
                let Some(f) = fit_scale(job, hi - lo, w, h) else {
                    return Err(JobError::Options(format!(
                        "--fit {w}x{h}: the job's fixed parts (tool offsets, margins) alone are \
                         {:.1} x {:.1}; give a larger size",
                        job.x - (hi - lo).x,
                        job.y - (hi - lo).y
                    )));
                };
                // A hair smaller than exact, so the rounded program stays inside.
                scale *= f * (1.0 - FIT_SHRINK);
                design = scaled_design(original, scale);
                built = build(&design)?;
            }
        }
        // Flex-sized features keep their size: say where the scaled art no longer fits them.
        if let Some(b) = &mut built.neon {
            b.judge(scale);
        }
        Ok((design, built, scale))
    }
}

/// Most rebuilds of `--fit`: each scales the design by the ratio of the room left for the
/// outlines (the work area minus the parts that keep their size: tool offsets, margins,
/// leads) to the outlines' size. The job's fixed parts change a little with the scale
/// (seams and leads move with the order, bridges with the gaps), so the size converges
/// linearly, by a factor of about 30 a round on a neon board: eight rounds leave it
/// within the hair the scale is made smaller by.
const FIT_ROUNDS: usize = 8;

/// Reads a G-code program back and checks it exactly as `skinpath check PROGRAM --machine
/// SAME` will (same configuration, no allowances: pockets mark their own intended crossings
/// in the program). With design boundaries (a design without operations on a router: its
/// outlines are parts that must not be gouged) the tool may come nearer the design than its
/// radius by the errors the build allows itself: arc fitting of the outline and the
/// boundary's flattening (each `opts.tolerance`, design units), coordinate rounding
/// (`decimals`) and the checker's own arc flattening.
pub fn check_program(
    program: &str,
    design: &Design,
    built: &BuildResult,
    profile: &Profile,
    opts: &BuildOptions,
    decimals: u32,
) -> Report {
    let tool_r = profile.default_tool().map(|t| t.radius()).unwrap_or(0.0);
    let mut cfg = check_config(profile, tool_r);
    let kk = design.units.mm_per_unit() / profile.units.mm_per_unit();
    cfg.gouge_tolerance = cfg
        .gouge_tolerance
        .max(2.0 * opts.tolerance * kk + 10f64.powi(-(decimals as i32)) + cfg.flatten_tolerance);
    // The default operations of a drawing may engrave lines inside it: no gouge check then.
    let only_outside_profiles = design.operation.is_empty()
        && profile.kind == MachineKind::Router
        && (built.toolpath.operations.iter())
            .all(|o| o.kind == crate::toolpath::OperationKind::Profile);
    let bounds = if only_outside_profiles {
        design_boundaries(
            &built.outlines,
            true,
            opts.tolerance,
            design.units.mm_per_unit(),
        )
    } else {
        Vec::new()
    };
    check_text(Backend::Builtin, program, &cfg, &bounds)
}

/// What to change for each kind of checker finding in a program a job made.
pub fn advice(id: &str) -> &'static str {
    match id {
        "self-intersection" => {
            "the cut folds onto itself where the outline offset by the tool radius \
             collapses: move the stroke's disks apart there, widen the channel or use a \
             smaller tool, and please report the design"
        }
        "contour-crossing" => {
            "two cuts that must stay apart cross: move the strokes apart, or give the \
             operations `strokes = [...]` so they do not both cut here"
        }
        "gouge" => {
            "the tool comes nearer the design than its radius: lower --tolerance or use a \
             smaller tool"
        }
        "out-of-bounds" => "use --place lower-left or --place center, or --fit to scale down",
        "feed-out-of-range" => "set the operation's `feed` within the machine's range",
        "power-out-of-range" => "set the operation's `power` within 0..=100 percent",
        _ => "see the finding's id in `skinpath check --help`",
    }
}

/// A checker finding of the program traced back to what the design says: the operation
/// (its kind, name and number in the design), the stroke and the place, then [`advice`].
/// What the design calls the item named `name`: "stroke" (also the strokes `[[text]]`
/// lays out), "circle sequence" or "shape".
fn item_kind(design: &Design, name: &str) -> &'static str {
    if design.shape.iter().any(|s| s.name == name) {
        "shape"
    } else if design.circles.iter().any(|c| c.name == name) {
        "circle sequence"
    } else {
        "stroke"
    }
}

/// `origins` maps program lines (0-based) to (operation, cut) of `tp`; `file` names the
/// design.
pub fn explain(f: &Finding, origins: &[LineOrigin], tp: &Toolpath, design: &Design) -> String {
    let file = design.file.as_str();
    // Every distinct operation and stroke among the finding's lines (a crossing has two).
    let mut whos: Vec<String> = Vec::new();
    for (oi, ci) in f
        .lines
        .iter()
        .filter_map(|&l| origins.get(l.wrapping_sub(1)).copied().flatten())
    {
        let Some(op) = tp.operations.get(oi) else {
            continue;
        };
        let mut w = operation_label(op);
        if let Some(src) = op.cuts.get(ci).and_then(|c| c.source.as_ref()) {
            w.push_str(&format!(", {} \"{src}\"", item_kind(design, src)));
        }
        if !whos.contains(&w) {
            whos.push(w);
        }
    }
    let who = if whos.is_empty() {
        String::new()
    } else {
        format!("{}: ", whos.join(" and "))
    };
    let at =
        f.at.first()
            .map(|p| format!(" at x {:.3} y {:.3} z {:.3}", p[0], p[1], p[2]))
            .unwrap_or_default();
    let lines: Vec<String> = f.lines.iter().map(|l| l.to_string()).collect();
    format!(
        "{file}: {who}{} [{}]{at} (program line {}): {}",
        f.message,
        f.id,
        lines.join(", "),
        advice(f.id)
    )
}

/// A design of strokes and circle sequences made in code: `strokes` as (name, curve),
/// `circles` as (name, circles, closed), millimetres, no operations (a profile of every
/// outline), `file` naming it in messages. A closed curve whose knots are not the uniform
/// ones its breakpoints give keeps its breakpoints.
pub fn design_of_strokes(
    file: &str,
    strokes: &[(&str, &DiskBSpline)],
    circles: &[(&str, &[Circle], bool)],
) -> Result<Design, JobError> {
    let mut stroke = Vec::with_capacity(strokes.len());
    for (name, c) in strokes {
        let disks: Vec<[f64; 3]> = c
            .control_disks()
            .iter()
            .map(|d| [d.c.x, d.c.y, d.r])
            .collect();
        let mut s = Stroke::from_disks(name, disks);
        s.degree = c.degree();
        s.closed = c.is_closed();
        s.knots = Some(if c.is_closed() {
            c.breakpoints()
        } else {
            c.curve().knots().to_vec()
        });
        stroke.push(s);
    }
    let circles = circles
        .iter()
        .map(|(name, cs, closed)| CircleSeq {
            name: name.to_string(),
            closed: *closed,
            circles: cs.iter().map(|c| [c.c.x, c.c.y, c.r]).collect(),
        })
        .collect();
    let mut d = Design {
        stroke,
        circles,
        ..Design::empty(file)
    };
    d.expand()?;
    crate::design::validate(&d)?;
    Ok(d)
}

/// Turns progress reports into stage timings and passes them on.
struct StageClock<'a> {
    inner: Option<ProgressFn<'a>>,
    state: Mutex<(Option<Stage>, Instant, Timings)>,
}

impl<'a> StageClock<'a> {
    fn new(inner: Option<ProgressFn<'a>>) -> Self {
        StageClock {
            inner,
            state: Mutex::new((None, Instant::now(), Timings::default())),
        }
    }

    /// The clock's state (a poisoned lock still holds valid times).
    fn state(&self) -> MutexGuard<'_, (Option<Stage>, Instant, Timings)> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Closes the running stage and starts `stage` (when it is not the running one).
    fn start(&self, stage: Stage) {
        let mut st = self.state();
        if st.0 != Some(stage) {
            let now = Instant::now();
            if let Some(s) = st.0 {
                let d = now - st.1;
                st.2.add(s, d);
            }
            *st = (Some(stage), now, std::mem::take(&mut st.2));
        }
        drop(st);
        if let Some(f) = self.inner {
            f(Progress {
                stage,
                fraction: 0.0,
            });
        }
    }

    fn seen(&self, p: Progress) {
        {
            let mut st = self.state();
            if st.0 != Some(p.stage) {
                let now = Instant::now();
                if let Some(s) = st.0 {
                    let d = now - st.1;
                    st.2.add(s, d);
                }
                st.0 = Some(p.stage);
                st.1 = now;
            }
        }
        if let Some(f) = self.inner {
            f(p);
        }
    }

    fn finish(&self) -> Timings {
        let mut st = self.state();
        if let Some(s) = st.0.take() {
            let d = st.1.elapsed();
            st.2.add(s, d);
        }
        if let (Some(f), Some(&(s, _))) = (self.inner, st.2.stages.last()) {
            f(Progress {
                stage: s,
                fraction: 1.0,
            });
        }
        std::mem::take(&mut st.2)
    }
}

/// How messages name an operation of the toolpath: `[[operation]] N (name)` as the design
/// file numbers it, or the default operation of a design without any.
pub(crate) fn operation_label(op: &crate::toolpath::model::Operation) -> String {
    match op.design_index {
        Some(d) => format!("[[operation]] {} ({})", d + 1, op.name),
        None => format!("the default {} (the design has no [[operation]])", op.name),
    }
}

#[cfg(test)]
mod tests {
    use super::item_kind;

    #[test]
    fn checker_explanations_name_the_item_kind() {
        let text = r#"version = 1
[[stroke]]
name = "s"
disks = [[0.0, 0.0, 1.0], [10.0, 0.0, 1.0]]
[[circles]]
name = "c"
circles = [[20.0, 0.0, 1.0], [30.0, 0.0, 2.0]]
[[shape]]
name = "q"
contours = [[[0.0, 10.0], [5.0, 10.0], [5.0, 15.0]]]
"#;
        let d = crate::design::load(text, "k.toml").unwrap();
        assert_eq!(item_kind(&d, "s"), "stroke");
        assert_eq!(item_kind(&d, "c"), "circle sequence");
        assert_eq!(item_kind(&d, "q"), "shape");
    }

    /// `--fit W×H` on a laser: the placed job's box fits W × H and fills the binding axis
    /// up to what a new skin at the new scale may differ by (2·(ε + 2·tol) per side).
    #[test]
    fn fit_makes_the_job_fit_the_size() {
        use super::{Job, JobOptions, Scale};
        let text = include_str!("../../examples/ring_o.toml");
        let d = crate::design::load(text, "ring_o.toml").unwrap();
        let text = include_str!("../../machines/grbl-laser.toml");
        let p = crate::machine::Profile::from_toml(text, "grbl-laser.toml").unwrap();
        let (w, h) = (50.0, 40.0);
        let o = JobOptions {
            scale: Scale::Fit {
                width: w,
                height: h,
            },
            ..JobOptions::default()
        };
        let out = Job::new(&d, &p, o).run().unwrap();
        let [sx, sy] = out.placement.size;
        let (eps, tol) = (o.build.epsilon, o.build.tolerance);
        assert!(sx <= w + tol && sy <= h + tol, "{sx} x {sy}");
        let slack = 4.0 * (eps + 2.0 * tol);
        assert!((w - sx).min(h - sy) <= slack, "{sx} x {sy} in {w} x {h}");
        assert!(out.placement.scale < 1.0);
    }
}
