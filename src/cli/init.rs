//! `skinpath init [-o design.toml]`: a commented starter design that builds as it is.

use super::io;
use anyhow::{Context, Result, bail};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Where to write the design.
    #[arg(short, long, default_value = "design.toml")]
    output: PathBuf,
    /// Overwrite the file if it exists.
    #[arg(long)]
    force: bool,
    /// Write the neon-sign starter: script text, a `[neon]` table and the channel, wire
    /// holes and backboard operations.
    #[arg(long)]
    neon: bool,
}

/// The starter design.
pub const STARTER: &str = r#"# A skinpath design (format v1). Build it with
#   skinpath build design.toml --machine grbl-laser -o design.gcode --preview design-preview.svg
#   skinpath build design.toml --machine grbl-router -o design.nc
# and look at the outlines with
#   skinpath outline design.toml -o outline.svg --control-disks
# Every length is in `units`; y points up; the origin is the machine's zero.
version = 1
units = "mm"              # or "inch"

[outline]
tolerance = 0.05          # how closely drawn and cut contours follow the exact outline

# A stroke through data points [x, y, r]: the spine passes through every (x, y), the
# width there is 2r. Points listed in `corners` (0-based) are sharp corners: the stroke is
# split there into pieces that meet in a round joint.
[[stroke]]
name = "wave"
points = [[10, 20, 2.0], [25, 32, 3.0], [40, 20, 4.0], [55, 8, 3.0], [70, 20, 2.0]]

[[stroke]]
name = "zigzag"
points = [[10, 50, 1.5], [25, 65, 1.5], [40, 50, 1.5], [55, 65, 1.5], [70, 50, 1.5]]
corners = [1, 2, 3]

# A stroke given by control disks [x, y, r] of a cubic disk B-spline: the spine is pulled
# towards the disks but passes only through the first and the last.
[[stroke]]
name = "brush"
disks = [[85, 10, 1.0], [95, 40, 5.0], [110, 45, 3.0], [120, 15, 1.0]]

# Single-stroke text (Hershey fonts "sans" or "script"): height is the cap height, width
# the stroke width. Use `skinpath text` to start a sign from a word.
[[text]]
name = "hello"
text = "Hi"
font = "script"
height = 20
width = 2
at = [88, 60]

# Operations. Without any, `build` cuts around every outline. For a laser, `power` is in
# percent; for a router, `depth` is required. Remove the kinds your machine cannot do.
[[operation]]
kind = "profile"          # profile | channel | backboard | holes | fill | vcarve
side = "on"               # on | outside | inside
depth = 2.0               # total depth (routers); ignored by lasers
power = 80                # percent (lasers)
"#;

/// The neon-sign starter (`init --neon`).
pub const STARTER_NEON: &str = r#"# A skinpath neon sign (format v1). Build it with
#   skinpath build design.toml --machine grbl-router -o design.nc --preview design-preview.png
# `build` prints the bill of materials: the flex runs, their lengths and cut lengths.
# Every length is in `units`; y points up; the origin is the machine's zero.
version = 1
units = "mm"

# The LED flex: preset "6mm" (6 x 10 mm) or "8mm" (8 x 12 mm). Keys set here override the
# preset: width, height, min_bend_radius, cut_unit, hole_diameter, channel_depth,
# board_thickness, join_tolerance, break_at. Check your flex's datasheet.
[neon]
flex = "6mm"

# The sign's words: single-stroke text, width = the flex width. Joined script letters are
# one flex run. `skinpath text "WORD" --neon -o sign.toml` starts a sign from a word.
[[text]]
name = "sign"
text = "Neon"
font = "script"
height = 30
width = 6
at = [14, 16]

# Sized by [neon]: the channel is the flex width + 0.5 mm wide and channel_depth deep; the
# wire holes (one at each end of each run) and the backboard cut go through the board.
[[operation]]
kind = "channel"

[[operation]]
kind = "holes"

[[operation]]
kind = "backboard"
"#;

/// The layers of the neon starter, written commented out after [`STARTER_NEON`] (see
/// [`neon_starter`]): a laser-cut acrylic face beside the routed board, as two outputs.
pub const NEON_LAYERS: &str = r#"[[operation]]
name = "face"
kind = "backboard"

[[output]]
name = "router"
machine = "grbl-router"
operations = [1, 2, 3]

[[output]]
name = "face"
machine = "grbl-laser"
operations = ["face"]
"#;

/// What `init --neon` writes: [`STARTER_NEON`], then [`NEON_LAYERS`] commented out with
/// how to use them.
pub fn neon_starter() -> String {
    let mut s = String::from(STARTER_NEON);
    s.push_str(
        "\n# Layers: to cut the board on a router and an acrylic face of the same outline on a\n\
         # laser, remove the `# ` below; then `skinpath build design.toml` (no --machine)\n\
         # writes design.router.gcode and design.face.gcode, each checked for its machine, as\n\
         # a set. --only face builds one of them.\n",
    );
    for line in NEON_LAYERS.lines() {
        s.push('#');
        if !line.is_empty() {
            s.push(' ');
            s.push_str(line);
        }
        s.push('\n');
    }
    s
}

pub fn run(a: Args) -> Result<u8> {
    let neon;
    let starter = if a.neon {
        neon = neon_starter();
        neon.as_str()
    } else {
        STARTER
    };
    if a.output.exists() && !a.force {
        bail!(
            "{} exists: choose another name with -o or pass --force",
            a.output.display()
        );
    }
    // The starter must load as it is; a failure here is a bug in skinpath, reported as such.
    skinpath::design::load(starter, &a.output.display().to_string())
        .context("the built-in starter design does not load")?;
    io::write_atomic(&a.output, starter.as_bytes())
        .with_context(|| format!("writing {}", a.output.display()))?;
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The neon starter with its layers taken in loads, and its outputs select the board's
    /// operations and the face.
    #[test]
    fn the_neon_starter_layers_load_when_taken_in() {
        let text = format!("{STARTER_NEON}{NEON_LAYERS}");
        let d = skinpath::design::load(&text, "design.toml").unwrap();
        let sel: Vec<_> = d.output.iter().map(|o| o.operations_of(&d)).collect();
        assert_eq!(sel, vec![Some(vec![0, 1, 2]), Some(vec![3])]);
        // Commented out, they change nothing.
        let plain = skinpath::design::load(STARTER_NEON, "design.toml").unwrap();
        let commented = skinpath::design::load(&neon_starter(), "design.toml").unwrap();
        assert_eq!(plain, commented);
    }
}
