//! `skinpath machines`: the shipped machine profiles.

use anyhow::Result;
use skinpath::machine::builtin_profiles;

#[derive(clap::Args, Debug)]
pub struct Args {}

pub fn run(_a: Args) -> Result<u8> {
    let profiles = builtin_profiles()?;
    let width = profiles.iter().map(|p| p.name.len()).max().unwrap_or(0);
    let mut text = String::new();
    for p in &profiles {
        text.push_str(&format!(
            "{:width$}  {:7}  {}\n",
            p.name,
            format!("{:?}", p.kind).to_lowercase(),
            p.description
        ));
    }
    text.push_str("\nUse one with --machine NAME, or pass the path of your own profile (.toml).\n");
    crate::print_stdout(&text)?;
    Ok(0)
}
