//! The preview as SVG: work area, cut contours coloured by laser power or router depth and
//! grouped by operation, rapids dashed in a light colour, direction arrows, start markers
//! with their order numbers, the checker's findings ringed at their places, and a legend
//! that lists the scale, the operations and the findings with their G-code lines. Page in
//! millimetres, 1 page unit = 1 mm of the machine, y up as on the machine.
//!
//! The picture is a [`Drawing`] ([`scene_drawing`]) that the SVG writes as text and the PNG
//! rasterises ([`super::png`]). Its size and level of detail are decided before anything is
//! drawn ([`Layout`], [`Detail`]): polylines are simplified to the output's pixel, moves
//! shorter than a pixel merge, and each layer (cuts, rapids, markers, findings) draws at most
//! a fixed number of elements, points and, for a raster, pixels of ink; a layer that reaches
//! its budget stops there and the legend says how much was drawn.

use super::Scene;
use super::draw::{Drawing, Frame, Paint, Rgb, Style};
use crate::sim::{MotionKind, Severity};
use glam::DVec2;

mod layers;
mod legend;

pub use layers::{CUT_BUDGET, FINDING_BUDGET, LayerBudget, MARK_BUDGET, RAPID_BUDGET};
use layers::{Chain, Layer, move_points};
pub use legend::hms;
use legend::legend_rows;

/// Least sagitta tolerance (page mm) of the arcs the preview flattens: a tenth of the cut
/// line's width, but not below this, so a huge page does not flatten finer than visible.
const MIN_FLATTEN_TOL: f64 = 1e-4;

/// Options of [`scene_svg`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
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
pub const RAPID_COLOR: Rgb = Rgb(0xa9, 0xb4, 0xbd);
/// Colour of the cut start markers.
pub const START_COLOR: Rgb = Rgb(0x2c, 0xa0, 0x2c);
/// Colour of the checker's findings.
pub const FINDING_COLOR: Rgb = Rgb(0xe0, 0x00, 0x00);
const WORK_FILL: Rgb = Rgb(0xf6, 0xf6, 0xf2);
const WORK_STROKE: Rgb = Rgb(0xb8, 0xb8, 0xb0);
const TEXT_COLOR: Rgb = Rgb(0x22, 0x22, 0x22);
/// Colour of the cut order numbers.
const ORDER_COLOR: Rgb = Rgb(0x1b, 0x5e, 0x20);
/// Opacity of the direction arrows.
const ARROW_OPACITY: f64 = 0.75;

/// Operations listed in the legend one by one (a count of the rest beyond).
const LISTED_OPERATIONS: usize = 24;
/// Largest raster side the SVG's detail is meant for, pixels: geometry closer than the
/// page's larger side over this merges (the largest PNG, [`super::png::MAX_SIDE`]).
pub const SVG_DETAIL_SIDE: f64 = 16384.0;

/// The region the drawing shows (world mm): the moves and findings, and the work area when
/// it is not much larger than the job.
pub fn view_box(scene: &Scene) -> (DVec2, DVec2) {
    let findings = (0..scene.findings.len()).flat_map(|i| scene.finding_points(i).iter().copied());
    frame_region(scene.bounds(), findings, scene.work_area)
}

/// The region framing `bounds` (of the moves, None when nothing moves), the finite
/// `points`, and `work_area` when it is at most [`WORK_AREA_RATIO`] times the job's area,
/// with a margin. It only grows with what it frames.
pub fn frame_region(
    bounds: Option<(DVec2, DVec2)>,
    points: impl Iterator<Item = DVec2>,
    work_area: Option<(DVec2, DVec2)>,
) -> (DVec2, DVec2) {
    let (mut lo, mut hi) = bounds.unwrap_or((DVec2::ZERO, DVec2::ONE));
    for p in points {
        if p.is_finite() {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if let Some((wl, wh)) = work_area {
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
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// Where the drawing goes on the page and how big its parts are, decided from the region
/// it frames before anything is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    /// Lower-left corner of the framed region (world mm).
    pub lo: DVec2,
    /// Upper-right corner of the framed region (world mm).
    pub hi: DVec2,
    /// Stroke widths, marker and font sizes.
    pub sizes: Sizes,
    /// Page width, mm: the region, or the legend's minimum width.
    pub width: f64,
    /// Height of the drawing above the legend, mm.
    pub drawing_height: f64,
    /// Whether a legend goes below the drawing.
    pub legend: bool,
}

impl Layout {
    /// The layout of a drawing framing `lo..hi` (see [`view_box`]).
    pub fn of_box(lo: DVec2, hi: DVec2, legend: bool) -> Layout {
        let size = hi - lo;
        let sizes = Sizes::of(size.max_element());
        // The legend needs room for its text even below a narrow drawing.
        let width = if legend {
            size.x.max(40.0 * sizes.font)
        } else {
            size.x
        };
        Layout {
            lo,
            hi,
            sizes,
            width,
            drawing_height: size.y,
            legend,
        }
    }

    /// The layout of `scene`'s drawing.
    pub fn of(scene: &Scene, opts: &SvgOptions) -> Layout {
        let (lo, hi) = view_box(scene);
        Layout::of_box(lo, hi, opts.legend)
    }

    /// Height of a legend row, mm.
    fn line_height(&self) -> f64 {
        1.5 * self.sizes.font
    }

    /// Page height with a legend of `rows` rows, mm.
    pub fn height(&self, rows: usize) -> f64 {
        if !self.legend || rows == 0 {
            self.drawing_height
        } else {
            self.drawing_height + (rows as f64 + 0.8) * self.line_height()
        }
    }
}

/// How fine the drawing is: geometry closer than a pixel merges, and whether the layers'
/// ink budgets apply (a raster).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detail {
    /// Page size of one output pixel, mm.
    pub pixel: f64,
    /// True for a raster (the ink budgets apply).
    pub raster: bool,
}

impl Detail {
    /// The SVG's detail: a pixel of the largest raster of the page
    /// ([`SVG_DETAIL_SIDE`] pixels a side).
    pub fn svg(layout: &Layout) -> Detail {
        Detail {
            pixel: layout.width.max(layout.drawing_height) / SVG_DETAIL_SIDE,
            raster: false,
        }
    }
}

/// The preview SVG of `scene`.
#[must_use]
pub fn scene_svg(scene: &Scene, opts: &SvgOptions) -> String {
    let layout = Layout::of(scene, opts);
    scene_drawing(scene, opts, &layout, &Detail::svg(&layout)).to_svg()
}

/// The preview drawing of `scene` on `layout` at `detail` (see the module's notes).
pub fn scene_drawing(
    scene: &Scene,
    opts: &SvgOptions,
    layout: &Layout,
    detail: &Detail,
) -> Drawing {
    let (lo, hi) = (layout.lo, layout.hi);
    let size = hi - lo;
    let sz = layout.sizes;
    let frame = Frame::new(lo, hi, 1.0, DVec2::ZERO);
    let mut page = Drawing::new(layout.width, layout.drawing_height);
    let flat_tol = (0.1 * sz.cut).max(MIN_FLATTEN_TOL);
    let mut rapids = Layer::new("rapids", RAPID_BUDGET, *detail);
    let mut cuts = Layer::new("cut paths", CUT_BUDGET, *detail);
    let mut marks = Layer::new("start markers and arrows", MARK_BUDGET, *detail);
    let mut rings = Layer::new("finding marks", FINDING_BUDGET, *detail);

    if let Some((wl, wh)) = scene.work_area {
        let a = frame.map(DVec2::new(wl.x, wh.y));
        let b = frame.map(DVec2::new(wh.x, wl.y));
        page.rect(
            "work-area",
            a,
            b - a,
            Style {
                fill: Some(Paint::Color(WORK_FILL)),
                ..Style::stroked(WORK_STROKE, 0.5 * sz.cut)
            },
        );
    }

    // Rapids and travels: every move that does not cut and moves in xy.
    page.open(
        "rapids",
        Style {
            dash: Some([3.0 * sz.cut, 2.0 * sz.cut]),
            round_caps: true,
            ..Style::stroked(RAPID_COLOR, sz.rapid)
        },
        &[],
    );
    // Connected travels are one path (moves that only change z, cutting or not, leave the
    // path in xy as it is), kept simplified to the pixel as it grows.
    let mut chain = Chain::new(detail.pixel, RAPID_BUDGET.points);
    for m in scene.motions.iter() {
        if matches!(m.kind, MotionKind::Dwell { .. })
            || (m.from.truncate() == m.to.truncate() && m.arc.is_none())
        {
            continue;
        }
        if crate::sim::checks::is_cutting(&m, &scene.cfg) {
            chain.flush(&mut page, &mut rapids, sz.rapid);
            continue;
        }
        let pts: Vec<DVec2> = move_points(&m, flat_tol)
            .iter()
            .map(|p| frame.map(*p))
            .collect();
        chain.extend(&pts, &mut page, &mut rapids, sz.rapid);
    }
    chain.flush(&mut page, &mut rapids, sz.rapid);
    page.close();

    // Cuts by operation: contours, then the cutting moves that change depth (plunges,
    // ramps, helices), which belong to no contour.
    let scale = scene.color_scale();
    let nops = scene.operations.len().max(1);
    let mut contours_of: Vec<Vec<usize>> = vec![Vec::new(); nops];
    for (ci, c) in scene.contours.iter().enumerate() {
        contours_of[scene.contour_op(c).min(nops - 1)].push(ci);
    }
    let mut ramps_of: Vec<Vec<usize>> = vec![Vec::new(); nops];
    for (i, m) in scene.motions.iter().enumerate() {
        if m.from.z != m.to.z && crate::sim::checks::is_cutting(&m, &scene.cfg) {
            let op = scene.op_of.get(i).copied().unwrap_or(0);
            ramps_of[op.min(nops - 1)].push(i);
        }
    }
    let mut drawn_contour = vec![false; scene.contours.len()];
    for (oi, name) in scene.operations.iter().enumerate() {
        if contours_of[oi].is_empty() && ramps_of[oi].is_empty() {
            continue;
        }
        page.open(
            &format!("op{oi}"),
            Style {
                fill: Some(Paint::None),
                stroke_width: Some(sz.cut),
                ..Style::default()
            }
            .round(),
            &[("data-name", name)],
        );
        for &ci in &contours_of[oi] {
            let c = &scene.contours[ci];
            let color = scale.rgb(scale.step(scene.contour_value(c)));
            let pts: Vec<DVec2> = c.points.iter().map(|p| frame.map(*p)).collect();
            if let Some(pts) = cuts.polyline(&pts, sz.cut, color, true) {
                drawn_contour[ci] = true;
                let style = Style {
                    stroke: Some(Paint::Color(color)),
                    ..Style::default()
                };
                page.polyline("cut", pts, false, style, Some(format!("contour{}", ci + 1)));
            }
        }
        for &i in &ramps_of[oi] {
            let Some(m) = scene.motions.get(i) else {
                continue;
            };
            let pts: Vec<DVec2> = move_points(&m, flat_tol)
                .iter()
                .map(|p| frame.map(*p))
                .collect();
            let color = scale.rgb(scale.step(scene.value_of(&m)));
            if let Some(pts) = cuts.polyline(&pts, sz.cut, color, true) {
                let style = Style {
                    stroke: Some(Paint::Color(color)),
                    ..Style::default()
                };
                page.polyline("ramp", pts, false, style, None);
            }
        }
        page.close();
    }

    page.open(
        "arrows",
        Style {
            fill: Some(Paint::Color(TEXT_COLOR)),
            fill_opacity: Some(ARROW_OPACITY),
            ..Style::default()
        },
        &[],
    );
    for (ci, c) in scene.contours.iter().enumerate() {
        if !drawn_contour[ci] {
            continue;
        }
        let pts: Vec<DVec2> = c.points.iter().map(|p| frame.map(*p)).collect();
        let len: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
        if len < 3.0 * sz.arrow {
            continue;
        }
        if let Some((p, d)) = midpoint(&pts) {
            if !marks.admit(3, 1.2 * sz.arrow, 0.8 * sz.arrow) {
                break;
            }
            let nrm = d.perp();
            let tip = p + d * (0.5 * sz.arrow);
            let back = p - d * (0.5 * sz.arrow);
            let tri = vec![
                tip,
                back + nrm * (0.4 * sz.arrow),
                back - nrm * (0.4 * sz.arrow),
            ];
            page.polyline("arrow", tri, true, Style::default(), None);
        }
    }
    page.close();

    page.open("starts", Style::default(), &[]);
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
        .zip(&drawn_contour)
        .map(|(c, &drawn)| c.points.first().filter(|_| drawn).map(|p| frame.map(*p)))
        .collect();
    let mut ci = 0;
    'starts: while ci < starts.len() {
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
            if !marks.admit(1, 0.0, 2.0 * marker) {
                break 'starts;
            }
            page.circle(
                "start",
                p,
                marker,
                Style::filled(START_COLOR),
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
            if !marks.admit(7 * label.len(), w, sz.number) {
                break;
            }
            let at = p + DVec2::new(sz.marker + 0.5 * w + 0.2 * sz.number, -0.8 * sz.number);
            page.number("order", at, sz.number, ORDER_COLOR, &label);
        }
        ci = last + 1;
    }
    page.close();

    page.open("findings", Style::stroked(FINDING_COLOR, 0.8 * sz.cut), &[]);
    'findings: for (fi, f) in scene.findings.iter().enumerate() {
        let ring = if f.severity == Severity::Error {
            5.0 * sz.cut
        } else {
            4.0 * sz.cut
        };
        for p in scene.finding_points(fi).iter().filter(|p| p.is_finite()) {
            let q = frame.map(*p);
            if !rings.admit(1, std::f64::consts::TAU * ring, 0.8 * sz.cut) {
                break 'findings;
            }
            page.circle(
                &format!("finding {}", f.id),
                q,
                ring,
                Style::default(),
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

    let notes: Vec<String> = [&cuts, &rapids, &marks, &rings]
        .iter()
        .filter_map(|l| l.note())
        .collect();
    let rows = if opts.legend {
        legend_rows(scene, opts, &notes)
    } else {
        Vec::new()
    };
    page.height = layout.height(rows.len());
    if !rows.is_empty() {
        page.open("legend", Style::default(), &[]);
        let line_h = layout.line_height();
        let x0 = 0.5 * sz.font;
        let mut y = size.y + line_h;
        for r in &rows {
            let mut x = x0;
            if let Some((color, dashed)) = r.swatch {
                let a = DVec2::new(x, y - 0.35 * sz.font);
                let b = a + DVec2::new(1.6 * sz.font, 0.0);
                let style = Style {
                    stroke: Some(Paint::Color(color)),
                    stroke_width: Some(0.45 * sz.font),
                    dash: dashed.then_some([0.4 * sz.font, 0.25 * sz.font]),
                    ..Style::default()
                };
                page.polyline("swatch", vec![a, b], false, style, None);
                x += 2.2 * sz.font;
            }
            // Average glyph advance of a sans-serif font is about 0.55 em.
            let fits = ((layout.width - x) / (0.55 * sz.font)).max(8.0) as usize;
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
    page
}

#[cfg(test)]
mod tests {
    use super::layers::simplify;
    use super::*;
    use proptest::prelude::*;

    fn detail(pixel: f64, raster: bool) -> Detail {
        Detail { pixel, raster }
    }

    proptest! {
        /// Radial-distance simplification: the ends stay, kept points are a pixel apart
        /// (the last one excepted) and every point left out lies within the tolerance of
        /// the kept point before it.
        #[test]
        fn simplify_moves_no_point_by_more_than_the_tolerance(
            raw in prop::collection::vec((-10.0f64..10.0, -10.0f64..10.0), 1..200),
            tol in 0.01f64..3.0,
        ) {
            let pts: Vec<DVec2> = raw.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
            let out = simplify(&pts, tol);
            prop_assert_eq!(out[0], pts[0]);
            prop_assert_eq!(*out.last().unwrap(), *pts.last().unwrap());
            for w in out[..out.len() - 1].windows(2) {
                prop_assert!(w[0].distance(w[1]) >= tol);
            }
            // Walk the input: each point is kept, or within tol of the last kept one.
            let mut k = 0;
            for p in &pts {
                if k + 1 < out.len() && *p == out[k + 1] {
                    k += 1;
                } else {
                    prop_assert!(p.distance(out[k]) < tol || *p == out[k] || *p == *out.last().unwrap());
                }
            }
        }
    }

    #[test]
    fn layers_stop_at_their_budget_and_say_so() {
        let budget = LayerBudget {
            elements: 3,
            points: 10,
            ink: f64::INFINITY,
        };
        let mut l = Layer::new("things", budget, detail(0.1, false));
        let line = |x: f64| vec![DVec2::new(x, 0.0), DVec2::new(x, 1.0), DVec2::new(x, 2.0)];
        assert!(l.polyline(&line(0.0), 0.1, Rgb::WHITE, true).is_some());
        assert!(l.polyline(&line(1.0), 0.1, Rgb::WHITE, true).is_some());
        assert_eq!(l.note(), None);
        // 6 points used: the third path fits (9 points), the fourth does not (one path
        // of 3 elements at most).
        assert!(l.polyline(&line(2.0), 0.1, Rgb::WHITE, true).is_some());
        assert!(l.polyline(&line(3.0), 0.1, Rgb::WHITE, true).is_none());
        assert_eq!(
            l.note().as_deref(),
            Some("preview limit: 3 of 4 things drawn (the first in program order)")
        );
        // A path longer than the points left is drawn in part.
        let mut l = Layer::new("things", budget, detail(0.1, false));
        let long: Vec<DVec2> = (0..20).map(|i| DVec2::new(i as f64, 0.0)).collect();
        assert_eq!(
            l.polyline(&long, 0.1, Rgb::WHITE, true).map(|p| p.len()),
            Some(10)
        );
        assert!(l.note().is_some_and(|n| n.contains("in part")));
    }

    #[test]
    fn raster_ink_bounds_long_strokes() {
        // Ink (length + width) · width / pixel²: a 100 mm line 1 mm wide at 0.1 mm pixels
        // is (100 + 1) · 1 / 0.01 = 10100 px².
        let budget = LayerBudget {
            elements: 100,
            points: 100,
            ink: 25_000.0,
        };
        let mut l = Layer::new("lines", budget, detail(0.1, true));
        let line = vec![DVec2::ZERO, DVec2::new(100.0, 0.0)];
        assert!(l.polyline(&line, 1.0, Rgb::WHITE, true).is_some());
        assert!(l.polyline(&line, 1.0, Rgb::WHITE, true).is_some());
        assert!(l.polyline(&line, 1.0, Rgb::WHITE, true).is_none());
        assert!((l.ink - 20_200.0).abs() < 1e-6, "{}", l.ink);
        // The SVG has no ink budget.
        let mut l = Layer::new("lines", budget, detail(0.1, false));
        for _ in 0..50 {
            assert!(l.polyline(&line, 1.0, Rgb::WHITE, true).is_some());
        }
    }

    #[test]
    fn sub_pixel_paths_are_dots_merged_by_colour() {
        let mut l = Layer::new("cuts", CUT_BUDGET, detail(1.0, true));
        let tiny = |x: f64| vec![DVec2::new(x, 0.0), DVec2::new(x + 0.1, 0.0)];
        let blue = Rgb(0, 0, 255);
        assert!(l.polyline(&tiny(0.0), 0.5, blue, true).is_some());
        assert!(l.polyline(&tiny(0.3), 0.5, blue, true).is_none(), "merged");
        assert!(
            l.polyline(&tiny(0.3), 0.5, Rgb::WHITE, true).is_some(),
            "other colour"
        );
        assert!(
            l.polyline(&tiny(5.0), 0.5, Rgb::WHITE, true).is_some(),
            "elsewhere"
        );
        // Travels shorter than a pixel are not drawn at all.
        let mut r = Layer::new("rapids", RAPID_BUDGET, detail(1.0, true));
        assert!(r.polyline(&tiny(0.0), 0.5, RAPID_COLOR, false).is_none());
        assert_eq!(r.note(), None);
    }

    #[test]
    fn arcs_of_many_turns_are_drawn_once_round() {
        use crate::sim::{Motion, MotionKind, ToolState};
        use glam::DVec3;
        let arc = crate::geom::Arc {
            center: DVec2::ZERO,
            radius: 10.0,
            start: 0.0,
            sweep: 1000.0 * std::f64::consts::TAU,
        };
        let m = Motion {
            kind: MotionKind::Feed,
            from: DVec3::new(10.0, 0.0, 0.0),
            to: DVec3::new(10.0, 0.0, 0.0),
            arc: Some(arc),
            feed: 100.0,
            tool: ToolState::default(),
            line: 1,
            group: None,
        };
        let tol = 0.01;
        let once = crate::geom::Arc {
            sweep: std::f64::consts::TAU,
            ..arc
        };
        let pts = move_points(&m, tol);
        assert_eq!(pts.len(), once.chords_for_tolerance(tol) + 1);
        assert!(pts.iter().all(|p| (p.length() - 10.0).abs() < 1e-9));
    }
}
