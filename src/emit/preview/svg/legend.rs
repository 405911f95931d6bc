//! The legend: the colour scale, the operations, the findings with their G-code lines and
//! what each layer left out, as rows of text.

use super::super::{COLOR_STEPS, Scene};
use super::{FINDING_COLOR, FINDING_LINES, LISTED_OPERATIONS, RAPID_COLOR, START_COLOR};
use super::{Rgb, SvgOptions};
use crate::sim::{MachineKind, Severity};

/// Seconds as `h:mm:ss` or `m:ss.s`.
#[must_use]
pub fn hms(t: f64) -> String {
    let t = if t.is_finite() { t.max(0.0) } else { 0.0 };
    let h = (t / 3600.0).floor();
    let m = ((t - 3600.0 * h) / 60.0).floor();
    let s = t - 3600.0 * h - 60.0 * m;
    if h > 0.0 {
        format!("{h}:{m:02}:{:02}", s.floor())
    } else {
        format!("{m}:{s:04.1}")
    }
}

/// Text lines of the legend with optional swatch colour and dash flag.
pub(super) struct Row {
    pub(super) swatch: Option<(Rgb, bool)>,
    pub(super) text: String,
    pub(super) class: &'static str,
}

/// The legend's rows; `notes` (what the drawing left out) follow the title.
pub(super) fn legend_rows(scene: &Scene, opts: &SvgOptions, notes: &[String]) -> Vec<Row> {
    let mut rows = Vec::new();
    let text = |s: String, class| Row {
        swatch: None,
        text: s,
        class,
    };
    let cut_moves = (0..scene.motions.len())
        .filter(|&i| scene.is_cut(i))
        .count();
    rows.push(text(
        format!(
            "{}: {} moves ({} cutting), {} contours, time {} (with acceleration)",
            scene.title,
            scene.motions.len(),
            cut_moves,
            scene.contours.len(),
            hms(scene.total_time)
        ),
        "title",
    ));
    if let Some(f) = scene.stopped() {
        rows.push(text(
            format!(
                "reading stopped at a limit{} [{}]: the moves after it are not shown",
                f.lines
                    .first()
                    .map(|l| format!(" on line {l}"))
                    .unwrap_or_default(),
                f.id
            ),
            "limit",
        ));
    }
    for n in notes {
        rows.push(text(n.clone(), "limit"));
    }
    let scale = scene.color_scale();
    let what = match scene.kind {
        MachineKind::Laser => "cut colour: laser power S",
        MachineKind::Router => "cut colour: depth below z 0 (mm)",
    };
    rows.push(text(what.to_string(), "scale"));
    let mut used = [false; COLOR_STEPS];
    for m in scene.motions.iter() {
        if crate::sim::checks::is_cutting(&m, &scene.cfg) {
            used[scale.step(scene.value_of(&m))] = true;
        }
    }
    let fmt = |v: f64| match scene.kind {
        MachineKind::Laser => format!("S {}", crate::emit::svg_page::num(v)),
        MachineKind::Router => format!("{v:.2} mm"),
    };
    for (k, _) in used.iter().enumerate().filter(|(_, u)| **u) {
        let (a, b) = scale.range(k);
        let label = if scale.hi > scale.lo {
            format!("{} to {}", fmt(a), fmt(b))
        } else {
            fmt(scale.hi)
        };
        rows.push(Row {
            swatch: Some((scale.rgb(k), false)),
            text: label,
            class: "scale",
        });
    }
    rows.push(Row {
        swatch: Some((RAPID_COLOR, true)),
        text: "rapids and travels".into(),
        class: "key",
    });
    rows.push(Row {
        swatch: Some((START_COLOR, false)),
        text: "cut starts, numbered in cutting order; arrows show the direction".into(),
        class: "key",
    });
    let mut per_op = vec![0usize; scene.operations.len()];
    for c in &scene.contours {
        if let Some(n) = per_op.get_mut(scene.contour_op(c)) {
            *n += 1;
        }
    }
    for (i, name) in scene.operations.iter().enumerate().take(LISTED_OPERATIONS) {
        rows.push(text(
            format!("operation {}: {name}, {} contours", i + 1, per_op[i]),
            "op",
        ));
    }
    if scene.operations.len() > LISTED_OPERATIONS {
        let rest = &per_op[LISTED_OPERATIONS..];
        rows.push(text(
            format!(
                "operations {} to {}: {} contours",
                LISTED_OPERATIONS + 1,
                scene.operations.len(),
                rest.iter().sum::<usize>()
            ),
            "op",
        ));
    }
    if !scene.checked {
        rows.push(text(
            "checker: not run (no G-code for this machine)".into(),
            "findings",
        ));
    } else if scene.findings.is_empty() {
        rows.push(text("checker: no findings".into(), "findings"));
    } else {
        rows.push(Row {
            swatch: Some((FINDING_COLOR, false)),
            text: format!(
                "checker: {} findings (ringed and numbered)",
                scene.findings.len()
            ),
            class: "findings",
        });
        if scene.findings.len() <= opts.max_listed_findings {
            for (i, f) in scene.findings.iter().enumerate() {
                rows.push(text(format!("{}. {f}", i + 1), "finding-text"));
            }
        } else {
            // Many findings: one row per kind with its count and first lines.
            let mut kinds: Vec<(&str, Severity, Vec<usize>, usize)> = Vec::new();
            for f in &scene.findings {
                match kinds.iter_mut().find(|k| k.0 == f.id) {
                    Some(k) => {
                        k.3 += 1;
                        k.2.extend(f.lines.iter().take(1));
                    }
                    None => kinds.push((
                        f.id,
                        f.severity,
                        f.lines.iter().take(1).copied().collect(),
                        1,
                    )),
                }
            }
            for (id, sev, lines, count) in kinds {
                let shown: Vec<String> = lines
                    .iter()
                    .take(FINDING_LINES)
                    .map(|l| l.to_string())
                    .collect();
                let more = if lines.len() > FINDING_LINES {
                    ", ..."
                } else {
                    ""
                };
                rows.push(text(
                    format!("{sev} [{id}] x{count}: lines {}{more}", shown.join(", ")),
                    "finding-text",
                ));
            }
            rows.push(text(
                "(skinpath check lists every finding)".to_string(),
                "finding-text",
            ));
        }
    }
    rows
}
