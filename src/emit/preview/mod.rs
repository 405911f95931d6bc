//! Toolpath previews people look at: one scene model, one drawing of it
//! ([`svg::scene_drawing`], sized and detailed for its output before it is drawn) with two
//! backends (SVG text, tiny-skia pixmap for the PNG), and a self-contained HTML player.
//!
//! ```text
//! G-code ─► sim::load ─► Program ─┐
//! Toolpath ─► motions ────────────┴► Scene (motions, operations, contours, findings)
//!            ─► svg::scene_drawing ─► Drawing ─► to_svg | to_pixmap (png::scene_png)
//!            └► html::player (with the planner's timeline)
//! ```
//!
//! A [`Scene`] holds the motions in machine millimetres as the simulator reads them, so a
//! program from any tool previews the same way as one skinpath built. The cut contours are
//! the checker's ([`crate::sim::checks::cut_contours`]), so "one drawn path per contour" means
//! the same thing to the preview and to the findings.

pub(crate) mod draw;
pub(crate) mod glyphs;
pub(crate) mod html;
pub(crate) mod png;
pub(crate) mod svg;

use crate::sim::checks::{SimContour, cut_contours, is_cutting};
use crate::sim::timeline::{Timeline, timeline};
use crate::sim::{
    CheckConfig, Finding, MachineKind, Motion, MotionKind, Motions, Program, ToolState,
};
use crate::toolpath::{MoveKind, Toolpath};
use glam::{DVec2, DVec3};
use std::collections::HashMap;

pub use html::{HtmlOptions, player_html};
pub use png::{PngOptions, scene_png};
pub use svg::{
    CUT_BUDGET, FINDING_BUDGET, LayerBudget, MARK_BUDGET, RAPID_BUDGET, SvgOptions, hms, scene_svg,
    view_box,
};

/// What the simulator's findings say when it stopped reading the program at one of its
/// limits (loop iterations, subroutine depth, ...): the moves after that point are missing.
pub const STOPPED: &str = "interpretation stopped";

/// Number of colour steps of the power/depth scale (and legend rows).
pub const COLOR_STEPS: usize = 5;

/// Everything a preview shows, in machine millimetres.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Scene {
    /// Laser (cut colour by power) or router (by depth).
    pub kind: MachineKind,
    /// Title shown in the legend and the HTML page (file or job name).
    pub title: String,
    /// Machine travel in xy (min, max), when known.
    pub work_area: Option<(DVec2, DVec2)>,
    /// Operation names; `op_of` indexes this list.
    pub operations: Vec<String>,
    /// The simulator's motions (mm), stored compactly.
    pub motions: Motions,
    /// Operation of each motion.
    pub op_of: Vec<usize>,
    /// Checker configuration (mm) the scene was read with: what counts as cutting.
    pub cfg: CheckConfig,
    /// The checker's cut contours (flattened at `cfg.flatten_tolerance`).
    pub contours: Vec<SimContour>,
    /// The checker's findings.
    pub findings: Vec<Finding>,
    /// Where each finding is drawn ([`Scene::finding_points`]), found once for all.
    finding_at: Vec<Vec<DVec2>>,
    /// Whether the checker ran (a scene of a toolpath without G-code is not checked).
    pub checked: bool,
    /// The planner's time for the whole program, seconds (with acceleration; the total of
    /// [`Scene::timeline`]).
    pub total_time: f64,
    /// The program's source lines, when the scene was read from G-code (1-based lines map
    /// to index line − 1).
    pub source: Option<String>,
}

/// What the colour of a cut stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorScale {
    /// Value range: laser S (power units) or router depth below z = 0 (mm).
    pub lo: f64,
    /// Upper end of the value range.
    pub hi: f64,
    /// Laser (power) or router (depth).
    pub kind: MachineKind,
}

/// Lasers: light orange (low power) to dark red (full power).
const LASER_RAMP: [(u8, u8, u8); 2] = [(0xf4, 0xa2, 0x3c), (0x8b, 0x00, 0x00)];
/// Routers: light blue (shallow) to navy (deep).
const ROUTER_RAMP: [(u8, u8, u8); 2] = [(0x6b, 0xae, 0xd6), (0x08, 0x30, 0x6b)];

impl ColorScale {
    /// Colour step (0 .. COLOR_STEPS) of a value.
    pub fn step(&self, v: f64) -> usize {
        if self.hi.partial_cmp(&self.lo) != Some(std::cmp::Ordering::Greater) || !v.is_finite() {
            return COLOR_STEPS - 1;
        }
        let f = ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0);
        ((f * COLOR_STEPS as f64) as usize).min(COLOR_STEPS - 1)
    }

    /// The colour of a step.
    pub fn rgb(&self, step: usize) -> draw::Rgb {
        let [a, b] = match self.kind {
            MachineKind::Laser => LASER_RAMP,
            MachineKind::Router => ROUTER_RAMP,
        };
        let f = if COLOR_STEPS > 1 {
            step.min(COLOR_STEPS - 1) as f64 / (COLOR_STEPS - 1) as f64
        } else {
            1.0
        };
        let mix = |x: u8, y: u8| (x as f64 + f * (y as f64 - x as f64)).round() as u8;
        draw::Rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
    }

    /// `#rrggbb` of a colour step.
    pub fn color(&self, step: usize) -> String {
        self.rgb(step).hex()
    }

    /// The value range `[from, to)` of a colour step.
    pub fn range(&self, step: usize) -> (f64, f64) {
        let w = (self.hi - self.lo) / COLOR_STEPS as f64;
        (self.lo + w * step as f64, self.lo + w * (step + 1) as f64)
    }
}

/// Where a scene comes from, for [`Scene::from_program`].
pub struct ProgramInput<'a> {
    /// Title shown in the legend and the HTML page.
    pub title: &'a str,
    /// The program as the simulator read it.
    pub program: &'a Program,
    /// The G-code text (for the HTML player's line display and operation comments).
    pub text: Option<&'a str>,
    /// Checker configuration the program was read with.
    pub cfg: &'a CheckConfig,
    /// The checker's findings.
    pub findings: Vec<Finding>,
    /// Whether the checker configuration's travel limits describe a real machine (a
    /// profile was given) and should be drawn.
    pub draw_work_area: bool,
}

impl Scene {
    /// A scene from a program the simulator read.
    pub fn from_program(input: ProgramInput<'_>) -> Scene {
        let motions = input.program.motions.clone();
        Scene::from_program_motions(input, motions)
    }

    /// [`Scene::from_program`] with the program's motions handed over instead of copied
    /// (`input.program.motions` is not read): a program of 10⁷ moves holds 400 MB of them.
    pub fn from_program_motions(input: ProgramInput<'_>, motions: Motions) -> Scene {
        let cfg = input.cfg.in_mm();
        let (operations, op_of) = operations_from_comments(input.text, &motions);
        let work_area = input.draw_work_area.then(|| work_area_of(&cfg));
        let mut scene = Scene::assemble(
            input.title,
            cfg,
            work_area,
            operations,
            motions,
            op_of,
            input.findings,
            input.text.map(str::to_string),
        );
        scene.checked = true;
        scene
    }

    /// A scene from a toolpath in design units (`mm_per_unit` converts), for outputs without
    /// G-code (laser SVG/DXF profiles). `power_max` is the machine's S at full power; the
    /// motions carry no source lines (line 0).
    pub fn from_toolpath(
        title: &str,
        tp: &Toolpath,
        mm_per_unit: f64,
        cfg: &CheckConfig,
        work_area: Option<(DVec2, DVec2)>,
    ) -> Scene {
        let cfg = cfg.in_mm();
        let k = mm_per_unit;
        let mut motions = Vec::new();
        let mut op_of = Vec::new();
        let mut pos = DVec3::ZERO;
        let mut tool = ToolState::default();
        for (oi, op) in tp.operations.iter().enumerate() {
            for cut in &op.cuts {
                let start = cut.start * k;
                if start != pos {
                    tool.switch(crate::sim::Spindle::Off, 0.0);
                    motions.push(Motion {
                        kind: MotionKind::Rapid,
                        from: pos,
                        to: start,
                        arc: None,
                        feed: 0.0,
                        tool,
                        line: 0,
                        group: None,
                    });
                    op_of.push(oi);
                    pos = start;
                }
                for m in &cut.moves {
                    let to = m.to * k;
                    let s = m.power * cfg.power_max;
                    let (kind, arc) = match m.kind {
                        MoveKind::Rapid => {
                            tool.switch(crate::sim::Spindle::Off, 0.0);
                            (MotionKind::Rapid, None)
                        }
                        MoveKind::Line => {
                            tool.switch(crate::sim::Spindle::Cw, s);
                            (MotionKind::Feed, None)
                        }
                        MoveKind::Arc { center, ccw } => {
                            tool.switch(crate::sim::Spindle::Cw, s);
                            let a = crate::geom::Arc::from_center_points(
                                center * k,
                                pos.truncate(),
                                to.truncate(),
                                ccw,
                            );
                            (MotionKind::Feed, Some(a))
                        }
                        MoveKind::Dwell { seconds } => (MotionKind::Dwell { seconds }, None),
                    };
                    let to = if matches!(kind, MotionKind::Dwell { .. }) {
                        pos
                    } else {
                        to
                    };
                    motions.push(Motion {
                        kind,
                        from: pos,
                        to,
                        arc,
                        feed: m.feed * k,
                        tool,
                        line: 0,
                        group: None,
                    });
                    op_of.push(oi);
                    pos = to;
                }
            }
        }
        let operations = tp.operations.iter().map(|o| o.name.clone()).collect();
        Scene::assemble(
            title,
            cfg,
            work_area,
            operations,
            Motions::from(&motions[..]),
            op_of,
            Vec::new(),
            None,
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn assemble(
        title: &str,
        cfg: CheckConfig,
        work_area: Option<(DVec2, DVec2)>,
        operations: Vec<String>,
        motions: Motions,
        op_of: Vec<usize>,
        findings: Vec<Finding>,
        source: Option<String>,
    ) -> Scene {
        let contours = cut_contours(&motions, &cfg);
        let total_time = crate::sim::time::estimate(&motions, &cfg).total;
        let finding_at = finding_anchors(&motions, &findings);
        Scene {
            kind: cfg.kind,
            title: title.to_string(),
            work_area,
            operations,
            motions,
            op_of,
            cfg,
            contours,
            findings,
            finding_at,
            total_time,
            checked: false,
            source,
        }
    }

    /// True when motion `i` removes material (the checker's rule for a cutting move).
    pub fn is_cut(&self, i: usize) -> bool {
        self.motions
            .get(i)
            .is_some_and(|m| is_cutting(&m, &self.cfg))
    }

    /// The finding saying the simulator stopped reading the program at a limit (see
    /// `STOPPED`), when it did: the scene holds the moves before that point only.
    pub fn stopped(&self) -> Option<&Finding> {
        self.findings.iter().find(|f| f.message.contains(STOPPED))
    }

    /// Per-block times from the simulator's planner (what the HTML player animates),
    /// computed on demand: a block per chord, 104 bytes each.
    pub fn timeline(&self) -> Timeline {
        timeline(&self.motions, &self.cfg)
    }

    /// The value a cut's colour stands for: S for lasers, depth below z = 0 for routers.
    pub fn value_of(&self, m: &Motion) -> f64 {
        match self.kind {
            MachineKind::Laser => m.tool.s,
            MachineKind::Router => -(m.from.z.min(m.to.z)),
        }
    }

    /// The colour scale over every cutting motion.
    pub fn color_scale(&self) -> ColorScale {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for m in self.motions.iter().filter(|m| is_cutting(m, &self.cfg)) {
            let v = self.value_of(&m);
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        if lo > hi {
            // No cutting motion.
            (lo, hi) = (0.0, 0.0);
        }
        if self.kind == MachineKind::Laser {
            // Power reads best against the machine's full scale.
            lo = lo.min(0.0);
            hi = hi.max(self.cfg.power_max);
        }
        ColorScale {
            lo,
            hi,
            kind: self.kind,
        }
    }

    /// The value a contour is coloured by: the largest over its motions.
    pub fn contour_value(&self, c: &SimContour) -> f64 {
        c.sources
            .iter()
            .filter_map(|&k| self.motions.get(k as usize))
            .map(|m| self.value_of(&m))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Operation of a contour (that of its first motion).
    pub fn contour_op(&self, c: &SimContour) -> usize {
        c.sources
            .first()
            .and_then(|&k| self.op_of.get(k as usize))
            .copied()
            .unwrap_or(0)
    }

    /// Bounds (min, max) of every motion in xy, None when nothing moves.
    pub fn bounds(&self) -> Option<(DVec2, DVec2)> {
        motion_bounds(&self.motions)
    }

    /// Where finding `i` is drawn: its coordinates, or the end of the first motion on its
    /// first line.
    pub fn finding_points(&self, i: usize) -> &[DVec2] {
        self.finding_at.get(i).map_or(&[], |v| v.as_slice())
    }
}

/// Bounds (min, max) of every move in xy (dwells and non-finite moves left out), None when
/// nothing moves.
pub fn motion_bounds(motions: &Motions) -> Option<(DVec2, DVec2)> {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for m in motions.iter() {
        if matches!(m.kind, MotionKind::Dwell { .. }) {
            continue;
        }
        let (a, b) = m.bounds();
        if a.is_finite() && b.is_finite() {
            lo = lo.min(a.truncate());
            hi = hi.max(b.truncate());
        }
    }
    (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
}

/// The machine's travel in xy (min, max) of a configuration in mm.
pub fn work_area_of(cfg: &CheckConfig) -> (DVec2, DVec2) {
    (
        DVec2::new(cfg.work_min[0], cfg.work_min[1]),
        DVec2::new(cfg.work_max[0], cfg.work_max[1]),
    )
}

/// Where each finding is drawn: its coordinates, or the end of the first motion on its
/// first line (one pass over the motions for all findings).
fn finding_anchors(motions: &Motions, findings: &[Finding]) -> Vec<Vec<DVec2>> {
    let mut first_on: HashMap<usize, Option<DVec2>> = findings
        .iter()
        .filter(|f| f.at.is_empty())
        .filter_map(|f| f.lines.first().map(|&l| (l, None)))
        .collect();
    if !first_on.is_empty() {
        for m in motions.iter() {
            if let Some(slot @ None) = first_on.get_mut(&m.line) {
                *slot = Some(m.to.truncate());
            }
        }
    }
    findings
        .iter()
        .map(|f| {
            if !f.at.is_empty() {
                return f.at.iter().map(|p| DVec2::new(p[0], p[1])).collect();
            }
            f.lines
                .first()
                .and_then(|l| first_on.get(l).copied().flatten())
                .into_iter()
                .collect()
        })
        .collect()
}

/// Operations named by skinpath's `op N NAME KIND` comments (any dialect's comment syntax):
/// each motion belongs to the last such comment above its line. Programs without them are
/// one operation, "program".
pub fn operations_from_comments(
    text: Option<&str>,
    motions: &Motions,
) -> (Vec<String>, Vec<usize>) {
    let mut starts: Vec<(usize, String)> = Vec::new();
    if let Some(text) = text {
        for (i, line) in text.lines().enumerate() {
            let t = line.trim();
            let body = t
                .strip_prefix('(')
                .and_then(|s| s.strip_suffix(')'))
                .or_else(|| t.strip_prefix(';'))
                .map(str::trim);
            let Some(rest) = body.and_then(|b| b.strip_prefix("op ")) else {
                continue;
            };
            let mut words = rest.split_whitespace();
            if words.next().is_some_and(|n| n.parse::<usize>().is_ok()) {
                let name: Vec<&str> = words.collect();
                let name = match name.len() {
                    0 => format!("operation {}", starts.len()),
                    1 => name[0].to_string(),
                    // The last word is the operation kind.
                    n => format!("{} ({})", name[..n - 1].join(" "), name[n - 1]),
                };
                starts.push((i + 1, name));
            }
        }
    }
    if starts.is_empty() {
        return (vec!["program".to_string()], vec![0; motions.len()]);
    }
    let op_of = motions
        .iter()
        .map(|m| {
            starts
                .partition_point(|(l, _)| *l <= m.line)
                .saturating_sub(1)
        })
        .collect();
    (starts.into_iter().map(|(_, n)| n).collect(), op_of)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::interp::interpret;

    #[test]
    fn operations_follow_comments() {
        let src = "(op 0 outline profile)\nG1 X1 F100\n; op 1 inner channel\nG1 X2\nG1 X3\n";
        let p = interpret(src, 0.005);
        let (ops, of) = operations_from_comments(Some(src), &p.motions);
        assert_eq!(ops, vec!["outline (profile)", "inner (channel)"]);
        assert_eq!(of, vec![0, 1, 1]);
        let (ops, of) = operations_from_comments(None, &p.motions);
        assert_eq!(ops, vec!["program"]);
        assert_eq!(of, vec![0, 0, 0]);
    }

    #[test]
    fn color_steps_cover_the_range() {
        let s = ColorScale {
            lo: 0.0,
            hi: 1000.0,
            kind: MachineKind::Laser,
        };
        assert_eq!(s.step(0.0), 0);
        assert_eq!(s.step(1000.0), COLOR_STEPS - 1);
        assert_eq!(s.step(199.0), 0);
        assert_eq!(s.step(201.0), 1);
        assert_eq!(s.color(0), "#f4a23c");
        assert_eq!(s.color(COLOR_STEPS - 1), "#8b0000");
        assert_eq!(s.range(1), (200.0, 400.0));
    }
}
