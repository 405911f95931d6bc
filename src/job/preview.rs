//! Preview scenes of whole jobs (what `skinpath preview` and `build --preview` draw): a
//! design built in memory for a machine and read back by the simulator, or any G-code
//! program. The drawing of a scene is [`crate::emit::preview`]'s; this module decides what
//! goes into it (cuts, rapids, start markers and the checker's findings).

use super::JobError;
use super::build::{BuildOptions, build_toolpath_placed};
use super::check::check_config;
use crate::design::{Design, OperationKind};
use crate::emit::preview::png::{PngOptions, check_size};
use crate::emit::preview::svg::{Layout, SvgOptions, frame_region};
use crate::emit::preview::{ProgramInput, Scene, motion_bounds, work_area_of};
use crate::emit::{GcodeOptions, gcode};
use crate::machine::{MachineKind, Profile};
use crate::sim::{self, CheckConfig, MotionKind};
use crate::toolpath::Toolpath;
use glam::DVec2;

/// A scene of G-code `text` read by the builtin simulator under `cfg`, with the checker's
/// findings; `work_area` draws the machine's travel.
pub fn scene_of_gcode(title: &str, text: &str, cfg: &CheckConfig, work_area: bool) -> Scene {
    let prog = sim::load(sim::Backend::Builtin, text, cfg);
    checked_scene(title, text, cfg, prog, work_area)
}

/// [`scene_of_gcode`] for a PNG of `png` (when given): the image's size is checked from
/// the program's bounds as soon as it is read, before the checker runs, so a program
/// whose picture would be too large is refused at once.
pub fn scene_of_gcode_for(
    title: &str,
    text: &str,
    cfg: &CheckConfig,
    work_area: bool,
    png: Option<PngOptions>,
) -> Result<Scene, JobError> {
    let prog = sim::load(sim::Backend::Builtin, text, cfg);
    if let Some(size) = png {
        let wa = work_area.then(|| work_area_of(&cfg.in_mm()));
        let (lo, hi) = frame_region(motion_bounds(&prog.motions), std::iter::empty(), wa);
        check_size(&Layout::of_box(lo, hi, SvgOptions::default().legend), size)?;
    }
    Ok(checked_scene(title, text, cfg, prog, work_area))
}

/// The scene of a program read under `cfg`, with the checker's findings; the program's
/// motions move into the scene.
fn checked_scene(
    title: &str,
    text: &str,
    cfg: &CheckConfig,
    mut prog: sim::Program,
    work_area: bool,
) -> Scene {
    let report = sim::check(&prog, cfg, &[]);
    let motions = std::mem::take(&mut prog.motions);
    Scene::from_program_motions(
        ProgramInput {
            title,
            program: &prog,
            text: Some(text),
            cfg,
            findings: report.findings,
            draw_work_area: work_area,
        },
        motions,
    )
}

/// The scene of a toolpath built for `profile`: its G-code `program` read back by the
/// simulator, or for SVG/DXF profiles (no program) the toolpath itself, with no G-code
/// lines. `allow_crossings` tells the checker that cuts may cross (channels, fills).
pub fn scene_of_build(
    title: &str,
    tp: &Toolpath,
    profile: &Profile,
    mm_per_design_unit: f64,
    program: Option<&str>,
    allow_crossings: bool,
) -> Scene {
    let tool_r = profile.default_tool().map(|t| t.radius()).unwrap_or(0.0);
    let mut cfg = check_config(profile, tool_r);
    cfg.allow_crossings = allow_crossings;
    match program {
        Some(g) => scene_of_gcode(title, g, &cfg, true),
        None => {
            let mm = cfg.in_mm();
            let wa = (
                DVec2::new(mm.work_min[0], mm.work_min[1]),
                DVec2::new(mm.work_max[0], mm.work_max[1]),
            );
            Scene::from_toolpath(title, tp, mm_per_design_unit, &cfg, Some(wa))
        }
    }
}

/// The scene of a design built for `profile` with `opts` (design placement): the toolpath,
/// and for G-code machines its program (arcs fitted within a tenth of the build tolerance)
/// read back and checked. A job outside the machine's travel is drawn, not refused: the
/// checker marks it. With `png`, the image's size is checked before the checker runs
/// (as `scene_of_gcode_for` checks a program).
pub fn scene_of_design(
    title: &str,
    design: &Design,
    profile: &Profile,
    opts: &BuildOptions,
    png: Option<PngOptions>,
) -> Result<Scene, JobError> {
    scene_of_design_of(title, design, profile, opts, png, None)
}

/// [`scene_of_design`] of the operations `only` (0-based, an `[[output]]`'s: see
/// [`crate::design::Output::operations_of`]); the others stay design context
/// (as `build_toolpath_placed` takes it). `None`: every operation.
pub fn scene_of_design_of(
    title: &str,
    design: &Design,
    profile: &Profile,
    opts: &BuildOptions,
    png: Option<PngOptions>,
    only: Option<&[usize]>,
) -> Result<Scene, JobError> {
    let built = build_toolpath_placed(design, profile, opts, None, None, only)?;
    let allow_crossings = (design.operation.iter().enumerate())
        .filter(|(i, _)| only.is_none_or(|o| o.contains(i)))
        .any(|(_, o)| !matches!(o.kind, OperationKind::Profile | OperationKind::Backboard));
    let program = if profile.kind == MachineKind::Svg {
        None
    } else {
        Some(gcode(
            &built.toolpath,
            profile,
            &GcodeOptions {
                job: title.to_string(),
                input_units: design.units,
                tolerance: opts.tolerance * super::tolerances::EMIT_OF_FIT,
                check_work_area: false,
            },
        )?)
    };
    let tool_r = profile.default_tool().map(|t| t.radius()).unwrap_or(0.0);
    let mut cfg = check_config(profile, tool_r);
    cfg.allow_crossings = allow_crossings;
    match program {
        Some(g) => scene_of_gcode_for(title, &g, &cfg, true, png),
        None => Ok(scene_of_build(
            title,
            &built.toolpath,
            profile,
            design.units.mm_per_unit(),
            None,
            allow_crossings,
        )),
    }
}

/// The scene of a G-code program from any tool. With a machine profile, its travel, limits
/// and tool; without, the default checker configuration with crossings allowed, read as a
/// router when some feed move goes below z = 0 and as a laser otherwise (no work area).
/// With `png`, the image's size is checked before the checker runs.
pub fn scene_of_program(
    title: &str,
    text: &str,
    profile: Option<&Profile>,
    png: Option<PngOptions>,
) -> Result<Scene, JobError> {
    match profile {
        Some(p) => {
            let r = p.default_tool().map(|t| t.radius()).unwrap_or(0.0);
            scene_of_gcode_for(title, text, &check_config(p, r), true, png)
        }
        None => {
            let mut cfg = CheckConfig {
                allow_crossings: true,
                ..CheckConfig::default()
            };
            let prog = sim::load(sim::Backend::Builtin, text, &cfg);
            if prog
                .motions
                .iter()
                .any(|m| m.kind == MotionKind::Feed && m.to.z.min(m.from.z) < 0.0)
            {
                cfg.kind = sim::MachineKind::Router;
            }
            if let Some(size) = png {
                let (lo, hi) = frame_region(motion_bounds(&prog.motions), std::iter::empty(), None);
                check_size(&Layout::of_box(lo, hi, SvgOptions::default().legend), size)?;
            }
            // The kind does not change what the simulator reads, only what the checker
            // and the drawing make of it.
            Ok(checked_scene(title, text, &cfg, prog, false))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A program without a machine reads as a router when it feeds below z = 0 and as a
    /// laser otherwise; the scene holds its cutting contour.
    #[test]
    fn program_without_machine_guesses_the_kind() {
        let router = "G21 G90\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F100\nG1 X10 Y0\nG1 X10 Y10\nG0 Z5\nM2\n";
        let s = scene_of_program("r", router, None, None).expect("a scene");
        assert_eq!(s.kind, sim::MachineKind::Router);
        assert!(!s.contours.is_empty());
        assert!(s.work_area.is_none());
        let laser = "G21 G90\nG0 X0 Y0\nM3 S500\nG1 X10 Y0 F600\nG1 X10 Y10\nM5\nM2\n";
        let s = scene_of_program("l", laser, None, None).expect("a scene");
        assert_eq!(s.kind, sim::MachineKind::Laser);
    }
}
