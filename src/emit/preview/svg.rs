//! The preview as SVG: work area, cut contours coloured by laser power or router depth and
//! grouped by operation, rapids dashed in a light colour, direction arrows, start markers
//! with their order numbers, the checker's findings ringed at their places, and a legend
//! that lists the scale, the operations and the findings with their G-code lines. Page in
//! millimetres, 1 page unit = 1 mm of the machine, y up as on the machine.

use super::draw::{Frame, SvgPage, num};
use super::{COLOR_STEPS, Scene};
use crate::sim::{MachineKind, MotionKind, Severity};
use glam::DVec2;

/// Options of [`scene_svg`].
#[derive(Clone, Debug, PartialEq)]
pub struct SvgOptions {
    /// Draw the legend below the drawing.
    pub legend: bool,
    /// At most this many start markers carry an order number (every k-th beyond).
    pub max_numbers: usize,
    /// At most this many findings are listed in the legend (all are drawn).
    pub max_listed_findings: usize,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            legend: true,
            max_numbers: 60,
            max_listed_findings: 12,
        }
    }
}

/// Cut stroke width as a fraction of the drawing's larger side: wide enough to see at any
/// raster size a person looks at, whatever the kerf (a laser's 0.01 mm hairline included).
const CUT_WIDTH: f64 = 0.003;
/// Legend font size as a fraction of the drawing's larger side.
const FONT: f64 = 0.02;
/// Margin around the drawing as a fraction of its larger side.
const MARGIN: f64 = 0.04;
/// The work area is framed with the job when it is at most this many times the job's
/// area; a job small on a large bed is framed alone (the bed's edges show where near).
const WORK_AREA_RATIO: f64 = 4.0;

/// Lines named per kind of finding when the findings are summarised.
const FINDING_LINES: usize = 8;
/// Findings carry their number on the drawing up to this many (rings only beyond).
const NUMBERED_FINDINGS: usize = 30;

/// Colours of the parts that are not cuts.
pub const RAPID_COLOR: &str = "#a9b4bd";
/// Colour of the cut start markers.
pub const START_COLOR: &str = "#2ca02c";
/// Colour of the checker's findings.
pub const FINDING_COLOR: &str = "#e00000";
const WORK_FILL: &str = "#f6f6f2";
const WORK_STROKE: &str = "#b8b8b0";
const TEXT_COLOR: &str = "#222222";

/// Seconds as `h:mm:ss` or `m:ss.s`.
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

/// The region the drawing shows (world mm): the moves and findings, and the work area when
/// it is not much larger than the job.
pub fn view_box(scene: &Scene) -> (DVec2, DVec2) {
    let (mut lo, mut hi) = scene.bounds().unwrap_or((DVec2::ZERO, DVec2::ONE));
    for f in &scene.findings {
        for p in scene.finding_points(f) {
            if p.is_finite() {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
    }
    if let Some((wl, wh)) = scene.work_area {
        let job = (hi - lo).max(DVec2::splat(1.0));
        let wa = (wh - wl).max(DVec2::ZERO);
        if wa.x * wa.y <= WORK_AREA_RATIO * job.x * job.y {
            lo = lo.min(wl);
            hi = hi.max(wh);
        }
    }
    let size = (hi - lo).max_element().max(1.0);
    let m = MARGIN * size;
    (lo - m, hi + m)
}

/// Sizes derived from the drawing's larger side `s` (mm).
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    /// Cut stroke width.
    pub cut: f64,
    /// Rapid stroke width.
    pub rapid: f64,
    /// Start marker radius.
    pub marker: f64,
    /// Height of order numbers.
    pub number: f64,
    /// Length of direction arrows.
    pub arrow: f64,
    /// Legend font size.
    pub font: f64,
}

impl Sizes {
    /// The sizes for a drawing whose larger side is `s` mm.
    pub fn of(s: f64) -> Sizes {
        let cut = CUT_WIDTH * s;
        Sizes {
            cut,
            rapid: 0.45 * cut,
            marker: 1.8 * cut,
            number: 5.5 * cut,
            arrow: 4.5 * cut,
            font: FONT * s,
        }
    }
}

/// Text lines of the legend with optional swatch colour and dash flag.
struct Row {
    swatch: Option<(String, bool)>,
    text: String,
    class: &'static str,
}

fn legend_rows(scene: &Scene, opts: &SvgOptions) -> Vec<Row> {
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
            hms(scene.timeline.total)
        ),
        "title",
    ));
    let scale = scene.color_scale();
    let what = match scene.kind {
        MachineKind::Laser => "cut colour: laser power S",
        MachineKind::Router => "cut colour: depth below z 0 (mm)",
    };
    rows.push(text(what.to_string(), "scale"));
    let mut used = [false; COLOR_STEPS];
    for (i, m) in scene.motions.iter().enumerate() {
        if scene.is_cut(i) {
            used[scale.step(scene.value_of(m))] = true;
        }
    }
    let fmt = |v: f64| match scene.kind {
        MachineKind::Laser => format!("S {v:.0}"),
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
            swatch: Some((scale.color(k), false)),
            text: label,
            class: "scale",
        });
    }
    rows.push(Row {
        swatch: Some((RAPID_COLOR.to_string(), true)),
        text: "rapids and travels".into(),
        class: "key",
    });
    rows.push(Row {
        swatch: Some((START_COLOR.to_string(), false)),
        text: "cut starts, numbered in cutting order; arrows show the direction".into(),
        class: "key",
    });
    for (i, name) in scene.operations.iter().enumerate() {
        let n = scene
            .contours
            .iter()
            .filter(|c| scene.contour_op(c) == i)
            .count();
        rows.push(text(
            format!("operation {}: {name}, {n} contours", i + 1),
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
            swatch: Some((FINDING_COLOR.to_string(), false)),
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

/// The point at half the length of a polyline and the unit direction there.
fn midpoint(pts: &[DVec2]) -> Option<(DVec2, DVec2)> {
    let total: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
    let mut acc = 0.0;
    for w in pts.windows(2) {
        let l = w[0].distance(w[1]);
        if l > 0.0 && acc + l >= 0.5 * total {
            let t = (0.5 * total - acc) / l;
            return Some((w[0].lerp(w[1], t), (w[1] - w[0]) / l));
        }
        acc += l;
    }
    None
}

/// The preview SVG of `scene`.
pub fn scene_svg(scene: &Scene, opts: &SvgOptions) -> String {
    let (lo, hi) = view_box(scene);
    let size = hi - lo;
    let sz = Sizes::of(size.max_element());
    let frame = Frame::new(lo, hi, 1.0, DVec2::ZERO);
    let rows = if opts.legend {
        legend_rows(scene, opts)
    } else {
        Vec::new()
    };
    let line_h = 1.5 * sz.font;
    let legend_h = if rows.is_empty() {
        0.0
    } else {
        (rows.len() as f64 + 0.8) * line_h
    };
    // The legend needs room for its text even below a narrow drawing.
    let width = size
        .x
        .max(if rows.is_empty() { 0.0 } else { 40.0 * sz.font });
    let mut page = SvgPage::new(width, size.y + legend_h, 1.0);
    let flat_tol = (0.1 * sz.cut).max(1e-4);

    if let Some((wl, wh)) = scene.work_area {
        let a = frame.map(DVec2::new(wl.x, wh.y));
        let b = frame.map(DVec2::new(wh.x, wl.y));
        page.rect(
            "work-area",
            a,
            b - a,
            &[
                ("fill", WORK_FILL),
                ("stroke", WORK_STROKE),
                ("stroke-width", &num(0.5 * sz.cut)),
            ],
        );
    }

    // Rapids and travels: every move that does not cut and moves in xy.
    page.open(
        "rapids",
        &[
            ("fill", "none"),
            ("stroke", RAPID_COLOR),
            ("stroke-width", &num(sz.rapid)),
            (
                "stroke-dasharray",
                &format!("{} {}", num(3.0 * sz.cut), num(2.0 * sz.cut)),
            ),
            ("stroke-linecap", "round"),
        ],
    );
    for (i, m) in scene.motions.iter().enumerate() {
        if matches!(m.kind, MotionKind::Dwell { .. }) || scene.is_cut(i) {
            continue;
        }
        if m.from.truncate() == m.to.truncate() && m.arc.is_none() {
            continue;
        }
        let pts: Vec<DVec2> = m
            .flatten_xy(flat_tol)
            .iter()
            .map(|p| frame.map(*p))
            .collect();
        page.polyline("rapid", &pts, false, &[]);
    }
    page.close();

    let scale = scene.color_scale();
    for (oi, name) in scene.operations.iter().enumerate() {
        page.open(
            &format!("op{oi}"),
            &[
                ("data-name", name),
                ("fill", "none"),
                ("stroke-width", &num(sz.cut)),
                ("stroke-linecap", "round"),
                ("stroke-linejoin", "round"),
            ],
        );
        for (ci, c) in scene.contours.iter().enumerate() {
            if scene.contour_op(c) != oi {
                continue;
            }
            let color = scale.color(scale.step(scene.contour_value(c)));
            let pts: Vec<DVec2> = c.points.iter().map(|p| frame.map(*p)).collect();
            page.polyline(
                "cut",
                &pts,
                false,
                &[("id", &format!("contour{}", ci + 1)), ("stroke", &color)],
            );
        }
        // Cutting moves that change depth (plunges, ramps, helices) belong to no contour.
        for (i, m) in scene.motions.iter().enumerate() {
            if scene.op_of.get(i) != Some(&oi) || !scene.is_cut(i) || m.from.z == m.to.z {
                continue;
            }
            let pts: Vec<DVec2> = m
                .flatten_xy(flat_tol)
                .iter()
                .map(|p| frame.map(*p))
                .collect();
            let color = scale.color(scale.step(scene.value_of(m)));
            page.polyline("ramp", &pts, false, &[("stroke", &color)]);
        }
        page.close();
    }

    page.open("arrows", &[("fill", TEXT_COLOR), ("fill-opacity", "0.75")]);
    for c in &scene.contours {
        let pts: Vec<DVec2> = c.points.iter().map(|p| frame.map(*p)).collect();
        let len: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
        if len < 3.0 * sz.arrow {
            continue;
        }
        if let Some((p, d)) = midpoint(&pts) {
            let nrm = d.perp();
            let tip = p + d * (0.5 * sz.arrow);
            let back = p - d * (0.5 * sz.arrow);
            let tri = [
                tip,
                back + nrm * (0.4 * sz.arrow),
                back - nrm * (0.4 * sz.arrow),
            ];
            page.polyline("arrow", &tri, true, &[]);
        }
    }
    page.close();

    page.open("starts", &[]);
    // Many cuts (hatching): small markers, so the cuts stay visible between them.
    let marker = if scene.contours.len() > opts.max_numbers {
        0.6 * sz.marker
    } else {
        sz.marker
    };
    let every = scene
        .contours
        .len()
        .div_ceil(opts.max_numbers.max(1))
        .max(1);
    let starts: Vec<Option<DVec2>> = scene
        .contours
        .iter()
        .map(|c| c.points.first().map(|p| frame.map(*p)))
        .collect();
    let mut ci = 0;
    while ci < starts.len() {
        let Some(p) = starts[ci] else {
            ci += 1;
            continue;
        };
        // Passes of one cut start where the previous one did: one marker, "first-last".
        let mut last = ci;
        while last + 1 < starts.len() && starts[last + 1].is_some_and(|q| q.distance(p) < sz.marker)
        {
            last += 1;
        }
        for k in ci..=last {
            page.circle(
                "start",
                p,
                marker,
                &[("fill", START_COLOR)],
                Some(&format!("contour {} starts here", k + 1)),
            );
        }
        if (ci..=last).any(|k| k % every == 0) || last + 1 == starts.len() {
            let label = if last > ci {
                format!("{}-{}", ci + 1, last + 1)
            } else {
                (ci + 1).to_string()
            };
            let w = super::glyphs::width(&label, sz.number);
            let at = p + DVec2::new(sz.marker + 0.5 * w + 0.2 * sz.number, -0.8 * sz.number);
            page.number("order", at, sz.number, "#1b5e20", &label);
        }
        ci = last + 1;
    }
    page.close();

    page.open(
        "findings",
        &[
            ("fill", "none"),
            ("stroke", FINDING_COLOR),
            ("stroke-width", &num(0.8 * sz.cut)),
        ],
    );
    for (fi, f) in scene.findings.iter().enumerate() {
        let pts = scene.finding_points(f);
        let ring = if f.severity == Severity::Error {
            5.0 * sz.cut
        } else {
            4.0 * sz.cut
        };
        for p in pts.iter().filter(|p| p.is_finite()) {
            let q = frame.map(*p);
            page.circle(
                &format!("finding {}", f.id),
                q,
                ring,
                &[],
                Some(&format!("{}. {f}", fi + 1)),
            );
            if scene.findings.len() > NUMBERED_FINDINGS {
                continue;
            }
            page.number(
                "finding-number",
                q + DVec2::new(ring + 0.6 * sz.number, ring),
                sz.number,
                FINDING_COLOR,
                &(fi + 1).to_string(),
            );
        }
    }
    page.close();

    if !rows.is_empty() {
        page.open("legend", &[]);
        let x0 = 0.5 * sz.font;
        let mut y = size.y + line_h;
        for r in &rows {
            let mut x = x0;
            if let Some((color, dashed)) = &r.swatch {
                let a = DVec2::new(x, y - 0.35 * sz.font);
                let b = a + DVec2::new(1.6 * sz.font, 0.0);
                let width = num(0.45 * sz.font);
                let dash = format!("{} {}", num(0.4 * sz.font), num(0.25 * sz.font));
                let mut attrs = vec![("stroke", color.as_str()), ("stroke-width", &width)];
                if *dashed {
                    attrs.push(("stroke-dasharray", &dash));
                }
                page.path("swatch", &SvgPage::path_data(&[a, b], false), &attrs);
                x += 2.2 * sz.font;
            }
            // Average glyph advance of a sans-serif font is about 0.55 em.
            let fits = ((width - x) / (0.55 * sz.font)).max(8.0) as usize;
            let t: String = if r.text.chars().count() > fits {
                let mut t: String = r.text.chars().take(fits.saturating_sub(3)).collect();
                t.push_str("...");
                t
            } else {
                r.text.clone()
            };
            page.text(r.class, DVec2::new(x, y), sz.font, TEXT_COLOR, &t);
            y += line_h;
        }
        page.close();
    }
    page.finish()
}
