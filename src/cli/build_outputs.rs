//! `skinpath build DESIGN [-o OUT]` for a design with `[[output]]` tables: one program per
//! output, each for its own machine profile and checked with it as a single build is, named
//! by the output (`OUT-STEM.NAME.EXT` beside `-o`, or the output's `file` template), and
//! written as a set: every program (and preview, and bill of materials) goes to its
//! temporary file first and all are renamed only when every output built and checked
//! ([`super::io::write_set`]); on an error or a signal nothing is written.
//!
//! `-o` gives the folder and the file stem (its extension is not used: each output's format
//! follows its file's extension); `-o` naming an existing folder writes there with the
//! design's stem. `--machine` is refused (the outputs name their machines), `--only NAME`
//! builds some of them, `--format` is refused (use the output's `file`). `--preview F`
//! writes one preview per output, `F-STEM.NAME.F-EXT` beside F; `--bom` writes the bill of
//! materials of the output that drills the most wire holes (the first of those).

use super::build::{Args, check_bom, job_name, load_profile, print_bom, print_job, settings};
use super::io;
use anyhow::{Context, Result, bail};
use skinpath::design::{Design, Output};
use skinpath::job::{JobError, JobOptions, OutputFormat, Stage, Summary, Timings};
use skinpath::job::{OutputJob, run_outputs};
use skinpath::machine::{MachineKind, Profile, builtin_profile};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One output ready to build: its table, profile, profile file (when it is a file), path
/// and format.
struct Planned<'a> {
    output: &'a Output,
    profile: Profile,
    profile_file: Option<PathBuf>,
    path: PathBuf,
    format: OutputFormat,
}

/// `build --json` of a design with outputs.
#[derive(serde::Serialize)]
struct RunSummary<'a> {
    /// The design file.
    design: &'a str,
    /// One entry per output built, in design order.
    outputs: Vec<OutputSummary<'a>>,
    /// Every file written: the programs, then the previews and the bill of materials.
    files: Vec<String>,
}

/// One output of [`RunSummary`].
#[derive(serde::Serialize)]
struct OutputSummary<'a> {
    /// The output's name.
    name: &'a str,
    /// Its machine profile's name.
    machine: &'a str,
    /// Its program.
    file: String,
    /// `gcode`, `svg` or `dxf`.
    format: &'static str,
    /// The `[[operation]]` numbers (1-based) it built; `null`: every operation.
    operations: Option<Vec<usize>>,
    /// The job's summary, as `build --json` prints it for one program (its `outputs`: the
    /// program and its preview).
    summary: Summary,
}

/// A shipped profile by name, or a profile file: a relative path is read from the design
/// file's folder `design_dir`.
pub fn output_profile(spec: &str, design_dir: &Path) -> Result<(Profile, Option<PathBuf>)> {
    if !builtin_profile(spec).is_err_and(|e| e.is_unknown_builtin()) {
        return Ok((load_profile(spec)?, None));
    }
    let path = design_dir.join(spec);
    if !path.exists() {
        bail!(
            "no machine profile named {spec:?} (see `skinpath machines`) and no file {}",
            path.display()
        );
    }
    let text = io::read_text(&path)?;
    let profile = Profile::from_toml(&text, &path.display().to_string())?;
    Ok((profile, Some(path)))
}

/// The folder (`None`: the current one) and file stem the outputs are named from: `-o`'s
/// (its folder and stem, or the folder it names), else the design's stem.
fn folder_and_stem(a: &Args) -> (Option<PathBuf>, String) {
    let design_stem = job_name(&a.design);
    match &a.output {
        Some(o) if o.is_dir() => (Some(o.clone()), design_stem),
        Some(o) => {
            let dir = o.parent().filter(|d| !d.as_os_str().is_empty());
            let stem = o.file_stem().map(|s| s.to_string_lossy().into_owned());
            (dir.map(Path::to_path_buf), stem.unwrap_or(design_stem))
        }
        None => (None, design_stem),
    }
}

/// The outputs `--only` asks for (all when it is empty), in design order.
fn selected<'a>(a: &Args, design: &'a Design, file: &str) -> Result<Vec<&'a Output>> {
    if let Some(n) = a
        .only
        .iter()
        .find(|n| !design.output.iter().any(|o| &o.name == *n))
    {
        let names: Vec<&str> = design.output.iter().map(|o| o.name.as_str()).collect();
        bail!(
            "{file}: --only {n}: no [[output]] of that name; the design's outputs are {}",
            names.join(", ")
        );
    }
    Ok((design.output.iter())
        .filter(|o| a.only.is_empty() || a.only.contains(&o.name))
        .collect())
}

/// Profiles, paths and formats of the outputs, every path checked against the inputs and
/// the other outputs.
fn plan<'a>(a: &Args, design: &'a Design, file: &str) -> Result<Vec<Planned<'a>>> {
    let design_dir = a
        .design
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let (dir, stem) = folder_and_stem(a);
    let mut planned: Vec<Planned<'a>> = Vec::new();
    for output in selected(a, design, file)? {
        let at = || format!("{file}: [[output]] \"{}\"", output.name);
        let (profile, profile_file) = output_profile(&output.machine, &design_dir)
            .with_context(|| format!("{}: machine {:?}", at(), output.machine))?;
        let ext = match profile.kind {
            MachineKind::Svg => "svg",
            MachineKind::Laser | MachineKind::Router => "gcode",
        };
        let name = output.file_name(&stem, ext);
        let path = dir
            .as_ref()
            .map_or_else(|| PathBuf::from(&name), |d| d.join(&name));
        let file_ext = io::extension(&path);
        let Some(format) = OutputFormat::from_extension(&file_ext) else {
            bail!(
                "{}: cannot tell the format of {} from .{file_ext}: end `file` with .gcode, \
                 .nc, .ngc, .tap, .svg, .dxf or {{ext}}",
                at(),
                path.display()
            );
        };
        if let Some(p) = planned.iter().find(|p| io::same_file(&p.path, &path)) {
            bail!(
                "{}: writes {}, as [[output]] \"{}\" does: give the outputs their own files \
                 (put {{name}} in `file`)",
                at(),
                path.display(),
                p.output.name
            );
        }
        planned.push(Planned {
            output,
            profile,
            profile_file,
            path,
            format,
        });
    }
    let mut inputs: Vec<&Path> = vec![&a.design];
    inputs.extend(planned.iter().filter_map(|p| p.profile_file.as_deref()));
    for p in &planned {
        io::refuse_overwriting_inputs(&p.path, &inputs)?;
    }
    Ok(planned)
}

/// The preview of each output: `--preview`'s folder, `STEM.NAME.EXT` of its stem and
/// extension.
fn preview_paths(preview: &Path, planned: &[Planned<'_>]) -> Vec<PathBuf> {
    let stem = preview
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = io::extension(preview);
    planned
        .iter()
        .map(|p| preview.with_file_name(format!("{stem}.{}.{ext}", p.output.name)))
        .collect()
}

pub fn run(a: Args) -> Result<u8> {
    let mut timings = Timings::default();
    let t_read = Instant::now();
    if let Some(f) = &a.format {
        bail!(
            "--format {f}: with [[output]] tables each output's format follows its file's \
             extension (e.g. `file = \"{{stem}}.{{name}}.dxf\"`); without them give --machine"
        );
    }
    let s = settings(&a)?;
    let text = io::read_text(&a.design)?;
    let file = a.design.display().to_string();
    let (design, notes) = skinpath::design::load_noted(&text, &file)?;
    for n in &notes {
        eprintln!("{file}: {n}");
    }
    if design.output.is_empty() {
        bail!(
            "--machine is required: {file} has no [[output]] tables (give --machine NAME or a \
             profile file; `skinpath machines` lists the shipped ones)"
        );
    }
    check_bom(&a, &design, &file)?;
    let planned = plan(&a, &design, &file)?;
    let mut inputs: Vec<&Path> = vec![&a.design];
    inputs.extend(planned.iter().filter_map(|p| p.profile_file.as_deref()));
    let previews = a
        .preview
        .as_deref()
        .map(|p| preview_paths(p, &planned))
        .unwrap_or_default();
    for p in &previews {
        io::refuse_overwriting_inputs(p, &inputs)?;
        if planned.iter().any(|o| io::same_file(p, &o.path)) {
            bail!(
                "--preview {} is an output file: give the preview its own name",
                p.display()
            );
        }
    }
    if let Some(p) = &a.bom {
        io::refuse_overwriting_inputs(p, &inputs)?;
        let others = planned.iter().map(|o| &o.path).chain(&previews);
        if others.into_iter().any(|q| io::same_file(p, q)) {
            bail!(
                "--bom {} is another output of this run: give the bill of materials its own name",
                p.display()
            );
        }
    }
    timings.add(Stage::Read, t_read.elapsed());
    let name = job_name(&a.design);
    let jobs: Vec<OutputJob<'_>> = planned
        .iter()
        .map(|p| OutputJob {
            output: p.output,
            profile: &p.profile,
            format: p.format,
        })
        .collect();
    let bar = super::progress::Bar::new();
    let on_progress = |p: skinpath::job::Progress| bar.show(p);
    let mut options = JobOptions::default();
    options.build = s.build;
    options.place = s.place;
    options.margin = a.margin;
    options.scale = s.scale;
    options.format = OutputFormat::Gcode;
    options.name = &name;
    options.write_unchecked = a.write_unchecked;
    options.progress = bar.active().then_some(&on_progress);
    let result = run_outputs(&design, &jobs, options);
    bar.finish();
    let outs = match result {
        Ok(outs) => outs,
        Err(e) => {
            if let JobError::Output { source, .. } = &e
                && let JobError::Unchecked { explanations, .. } = source.as_ref()
            {
                for x in explanations {
                    eprintln!("{x}");
                }
            }
            return Err(e.into());
        }
    };
    for (p, out) in planned.iter().zip(&outs) {
        timings.extend(&out.timings);
        if !out.explanations.is_empty() {
            for e in &out.explanations {
                eprintln!("{e}");
            }
            eprintln!(
                "skinpath: warning: writing output {} ({}), a program that failed its checks",
                p.output.name,
                p.path.display()
            );
        }
    }
    let t_write = Instant::now();
    let mut files: Vec<(&Path, Vec<u8>)> = (planned.iter().zip(&outs))
        .map(|(p, out)| (p.path.as_path(), out.program.clone().into_bytes()))
        .collect();
    for ((p, out), path) in planned.iter().zip(&outs).zip(&previews) {
        let scene = skinpath::job::scene_of_build(
            &skinpath::job::job_name(&name, p.output),
            &out.built.toolpath,
            &p.profile,
            out.design.units.mm_per_unit(),
            (p.format == OutputFormat::Gcode).then_some(out.program.as_str()),
            false,
        );
        files.push((
            path,
            super::preview::render(path, &scene, Default::default())?,
        ));
    }
    // The bill of materials of the output that drills the wire holes (most of them).
    let bom = (outs.iter().filter_map(|o| o.built.neon.as_ref()))
        .reduce(|best, b| if b.holes > best.holes { b } else { best });
    if let (Some(p), Some(bom)) = (&a.bom, bom) {
        files.push((p, bom.to_csv().into_bytes()));
    }
    io::write_set(&files)?;
    timings.add(Stage::Write, t_write.elapsed());
    let mut text = String::new();
    if a.json {
        let mut list = Vec::new();
        for (k, (p, out)) in planned.iter().zip(&outs).enumerate() {
            let mut summary = out.summary(&p.profile);
            summary.outputs = std::iter::once(&p.path)
                .chain(previews.get(k))
                .map(|f| f.display().to_string())
                .collect();
            list.push(OutputSummary {
                name: &p.output.name,
                machine: &p.profile.name,
                file: p.path.display().to_string(),
                format: p.format.as_str(),
                operations: (p.output.operations_of(&design))
                    .map(|v| v.into_iter().map(|i| i + 1).collect()),
                summary,
            });
        }
        let mut v = serde_json::to_value(RunSummary {
            design: &file,
            outputs: list,
            files: files.iter().map(|(p, _)| p.display().to_string()).collect(),
        })?;
        if a.timings
            && let Some(m) = v.as_object_mut()
        {
            m.insert("timings".into(), timings.to_json());
        }
        writeln!(text, "{}", serde_json::to_string_pretty(&v)?)?;
    } else {
        for (p, out) in planned.iter().zip(&outs) {
            writeln!(
                text,
                "output {} ({}) -> {}",
                p.output.name,
                p.profile.name,
                p.path.display()
            )?;
            print_job(&mut text, out, &p.profile, None)?;
        }
        if let Some(bom) = bom {
            print_bom(&mut text, bom)?;
        }
        for (p, _) in &files {
            writeln!(text, "wrote {}", p.display())?;
        }
        if a.timings {
            eprint!("{}", timings.table());
        }
    }
    crate::print_stdout(&text)?;
    Ok(0)
}
