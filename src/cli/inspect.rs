//! `skinpath inspect DESIGN [--json]`.

use super::io;
use anyhow::Result;
use skinpath::job::OutlineOptions;
use skinpath::job::inspect;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The design file (.toml or .json).
    design: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Skin approximation accuracy ε, in design units.
    #[arg(long)]
    epsilon: Option<f64>,
}

pub fn run(a: Args) -> Result<u8> {
    let text = io::read_text(&a.design)?;
    let design = skinpath::design::load(&text, &a.design.display().to_string())?;
    let mut opts = OutlineOptions::default();
    if let Some(e) = a.epsilon {
        anyhow::ensure!(
            e.is_finite() && e > 0.0,
            "--epsilon must be positive, got {e}"
        );
        opts.epsilon = e;
    }
    let info = inspect(&design, &opts)?;
    let text = if a.json {
        format!("{}\n", serde_json::to_string_pretty(&info)?)
    } else {
        info.to_string()
    };
    crate::print_stdout(&text)?;
    Ok(0)
}
