//! Embedding skinpath: a stroke made in code, built for the shipped `grbl-router` profile,
//! checked, and its summary printed as JSON (the program goes to `embed.gcode` in the
//! current folder only when a path is given: `cargo run --example embed -- out.gcode`).
//!
//! The same code runs as the crate-level doc test in `src/lib.rs` and in
//! `tests/api_embed.rs`, so `cargo test` proves it works.

use skinpath::geom::DVec2;
use skinpath::{
    Circle, DiskBSpline, Job, JobError, JobOptions, Stage, builtin_profile, design_of_strokes,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // A cubic disk B-spline through five control disks (x, y, radius; millimetres).
    let disks: Vec<Circle> = [
        (0.0, 0.0, 2.0),
        (15.0, 12.0, 3.0),
        (30.0, 0.0, 2.5),
        (45.0, -10.0, 3.5),
        (60.0, 5.0, 2.0),
    ]
    .iter()
    .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
    .collect();
    let wave = DiskBSpline::open(3, &disks, None)?;
    let design = design_of_strokes("wave", &[("wave", &wave)], &[])?;
    let profile = builtin_profile("grbl-router")?;

    // Progress of the long stages, on stderr.
    let progress = |p: skinpath::Progress| {
        if p.fraction >= 1.0 && p.stage == Stage::Skin {
            eprintln!("skinned every stroke");
        }
    };
    let mut options = JobOptions::default();
    options.name = "wave";
    options.progress = Some(&progress);
    let job = Job::new(&design, &profile, options);
    let out = match job.run() {
        Ok(out) => out,
        Err(JobError::Unchecked { explanations, .. }) => {
            for e in explanations {
                eprintln!("{e}");
            }
            return Err("the program failed its check".into());
        }
        Err(e) => return Err(e.into()),
    };
    if let Some(path) = std::env::args().nth(1) {
        std::fs::write(&path, &out.program)?;
    }
    let mut summary = out.summary(&profile);
    summary.outputs = std::env::args().skip(1).collect();
    println!("{}", serde_json::to_string_pretty(&summary)?);
    Ok(())
}
