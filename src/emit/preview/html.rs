//! The preview as one self-contained HTML file: a canvas player of the program (play, pause,
//! speed, a scrubber over program time, zoom and pan, layer toggles, the current G-code line,
//! elapsed and total time). No network, no external scripts or fonts: the page's content
//! security policy forbids loading anything.
//!
//! The moves are embedded as base64 little-endian typed arrays, one entry per planner block
//! of [`crate::sim::timeline`]: vertices (Float32 x, y), times and speeds (Float32 t₀, Δt,
//! vᵢ, v_c, v_f, a), style (Uint8: kind | colour step << 2), operation (Uint16) and source
//! line (Uint32). The page places the tool with the same trapezoidal profile as
//! [`crate::sim::timeline::Segment::distance_at`], so the scrubber at time t shows the tool
//! where the simulator puts it. Drawing skips vertices closer than a pixel to the last one
//! drawn (decimation for drawing only; every block keeps its time).

use super::Scene;
use super::svg::{FINDING_COLOR, RAPID_COLOR, START_COLOR, view_box};
use crate::emit::EmitError;
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;
use serde_json::json;

/// Style codes of the embedded blocks.
pub const STYLE_TRAVEL: u8 = 0;
/// Style code of a cutting block.
pub const STYLE_CUT: u8 = 1;
/// Style code of a dwell.
pub const STYLE_DWELL: u8 = 2;

/// Options of [`player_html`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct HtmlOptions {
    /// Embed the program text so the page shows the current line's text (not only its
    /// number) when the text is at most this many bytes.
    pub max_source_bytes: usize,
}

impl Default for HtmlOptions {
    fn default() -> Self {
        HtmlOptions {
            max_source_bytes: 64 << 20,
        }
    }
}

fn b64_f32(v: &[f32]) -> String {
    let mut bytes = Vec::with_capacity(v.len() * 4);
    for x in v {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    STANDARD.encode(bytes)
}

/// JSON text safe inside a `<script>` element.
fn script_json(v: &serde_json::Value) -> String {
    v.to_string()
        .replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

/// The player page of `scene`.
pub fn player_html(scene: &Scene, opts: &HtmlOptions) -> Result<String, EmitError> {
    let timeline = scene.timeline();
    let segs = &timeline.segments;
    let n = segs.len();
    if n > u32::MAX as usize / 8 {
        return Err(EmitError::InvalidOption {
            name: "moves",
            reason: format!("{n} blocks are too many for one page"),
        });
    }
    let mut v = Vec::with_capacity(2 * (n + 1));
    for s in segs {
        v.push(s.from.x as f32);
        v.push(s.from.y as f32);
    }
    if let Some(s) = segs.last() {
        v.push(s.to.x as f32);
        v.push(s.to.y as f32);
    }
    let mut t = vec![0f32; 6 * n];
    let mut k = Vec::with_capacity(n);
    let mut o = Vec::with_capacity(2 * n);
    let mut l = Vec::with_capacity(4 * n);
    let scale = scene.color_scale();
    for (i, s) in segs.iter().enumerate() {
        t[i] = s.t0 as f32;
        t[n + i] = s.dt as f32;
        t[2 * n + i] = s.vi as f32;
        t[3 * n + i] = s.vc as f32;
        t[4 * n + i] = s.vf as f32;
        t[5 * n + i] = s.a as f32;
        let m = scene.motions.get(s.motion);
        let style = match &m {
            Some(m) if matches!(m.kind, crate::sim::MotionKind::Dwell { .. }) => STYLE_DWELL,
            Some(m) if scene.is_cut(s.motion) => {
                STYLE_CUT | ((scale.step(scene.value_of(m)) as u8) << 2)
            }
            _ => STYLE_TRAVEL,
        };
        k.push(style);
        let op = scene.op_of.get(s.motion).copied().unwrap_or(0).min(65535) as u16;
        o.extend_from_slice(&op.to_le_bytes());
        let line = m.map_or(0, |m| m.line.min(u32::MAX as usize) as u32);
        l.extend_from_slice(&line.to_le_bytes());
    }
    let (lo, hi) = view_box(scene);
    let steps: Vec<String> = (0..super::COLOR_STEPS).map(|s| scale.color(s)).collect();
    let ranges: Vec<[f64; 2]> = (0..super::COLOR_STEPS)
        .map(|s| {
            let (a, b) = scale.range(s);
            [a, b]
        })
        .collect();
    let findings: Vec<serde_json::Value> = scene
        .findings
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let pts: Vec<[f64; 2]> = scene
                .finding_points(i)
                .iter()
                .filter(|p| p.is_finite())
                .map(|p| [p.x, p.y])
                .collect();
            json!({
                "id": f.id,
                "severity": f.severity.to_string(),
                "text": f.to_string(),
                "lines": f.lines,
                "at": pts,
            })
        })
        .collect();
    let meta = json!({
        "title": scene.title,
        "kind": match scene.kind { crate::sim::MachineKind::Laser => "laser", _ => "router" },
        "n": n,
        "total": timeline.total,
        "view": [lo.x, lo.y, hi.x, hi.y],
        "workArea": scene.work_area.map(|(a, b)| [a.x, a.y, b.x, b.y]),
        "operations": scene.operations,
        "colors": steps,
        "ranges": ranges,
        "rapidColor": RAPID_COLOR.hex(),
        "startColor": START_COLOR.hex(),
        "findingColor": FINDING_COLOR.hex(),
        "findings": findings,
        "checked": scene.checked,
        "starts": scene.contours.iter().filter_map(|c| c.points.first()).map(|p| [p.x, p.y]).collect::<Vec<_>>(),
    });
    let source = match &scene.source {
        Some(s) if s.len() <= opts.max_source_bytes => script_json(&json!(s)),
        _ => "null".to_string(),
    };
    let title = crate::emit::svg_page::text_content(&scene.title);
    let parts = [
        ("TITLE", title),
        ("META", script_json(&meta)),
        ("SOURCE", source),
        ("V", b64_f32(&v)),
        ("T", b64_f32(&t)),
        ("K", STANDARD.encode(&k)),
        ("O", STANDARD.encode(&o)),
        ("L", STANDARD.encode(&l)),
    ];
    Ok(fill(TEMPLATE, &parts))
}

/// `template` with every `{{NAME}}` replaced by its value, in one pass (a value is never
/// searched for further placeholders).
fn fill(template: &str, parts: &[(&str, String)]) -> String {
    let extra: usize = parts.iter().map(|(_, v)| v.len()).sum();
    let mut out = String::with_capacity(template.len() + extra);
    let mut rest = template;
    while let Some(i) = rest.find("{{") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        match after.find("}}").and_then(|j| {
            let name = &after[..j];
            parts.iter().find(|(n, _)| *n == name).map(|(_, v)| (v, j))
        }) {
            Some((v, j)) => {
                out.push_str(v);
                rest = &after[j + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

const TEMPLATE: &str = include_str!("player.html");
