//! SVG for laser-cutter upload: mm page (width/height in mm, viewBox in mm, so one user unit
//! is one millimetre), hairline strokes, one colour per operation kind from the profile, one
//! `<path>` per cut in cut order, arcs as SVG `A` commands. The design's y axis points up, SVG's
//! down: y is flipped about the page.

use super::geometry::{CutContour, Seg, bounds, contours, split_arc, validate};
use super::svg_page::SvgPage;
use super::{EmitError, check_tolerance, fnum};
use crate::machine::{OperationColors, Profile};
use crate::toolpath::{OperationKind, Toolpath};
use glam::DVec2;
use std::f64::consts::PI;
use std::fmt::Write;

/// Largest sweep of one SVG `A` command: 120°, so the large-arc flag is always 0 and a full
/// circle (which one `A` cannot draw) becomes three pieces.
pub const SVG_MAX_SWEEP: f64 = 2.0 * PI / 3.0;

/// Smallest page side, mm (an empty toolpath still makes a valid SVG).
const MIN_PAGE: f64 = 1.0;

/// The page the drawing sits on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Page {
    /// The drawing's bounding box grown by `margin` mm on each side.
    Bounds {
        /// Margin on each side (mm).
        margin: f64,
    },
    /// The profile's work area (the bed): design coordinates keep their place on the bed,
    /// with the design's origin at the bed's bottom-left corner.
    WorkArea,
}

/// Options of [`laser_svg`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct LaserSvgOptions {
    /// The page the drawing sits on.
    pub page: Page,
    /// Job name for `<title>`.
    pub job: String,
    /// Largest start/end radius mismatch accepted on an arc move (mm).
    pub tolerance: f64,
}

impl Default for LaserSvgOptions {
    fn default() -> Self {
        LaserSvgOptions {
            page: Page::Bounds { margin: 1.0 },
            job: "skinpath".to_string(),
            tolerance: crate::geom::tol::FLATTEN,
        }
    }
}

/// The stroke colour of an operation kind; a line is cut like a profile, in its colour.
pub fn color_of(colors: &OperationColors, kind: OperationKind) -> &str {
    match kind {
        OperationKind::Profile | OperationKind::Line => &colors.profile,
        OperationKind::Channel => &colors.channel,
        OperationKind::Backboard => &colors.backboard,
        OperationKind::Holes => &colors.holes,
        OperationKind::Fill => &colors.fill,
        OperationKind::VCarve => &colors.vcarve,
    }
}

/// Maps design coordinates (mm, y up) to page coordinates (mm, y down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PageFrame {
    /// Design x at the page's left edge.
    pub x0: f64,
    /// Design y at the page's top edge.
    pub y1: f64,
    /// Page width (mm).
    pub width: f64,
    /// Page height (mm).
    pub height: f64,
}

impl PageFrame {
    /// Page point (y down) of a design point (y up).
    pub fn map(&self, p: DVec2) -> DVec2 {
        DVec2::new(p.x - self.x0, self.y1 - p.y)
    }

    /// The frame of the bounding box of `cs` and `extra` grown by `margin`.
    pub fn around(cs: &[CutContour], extra: &[DVec2], margin: f64) -> PageFrame {
        let (lo, hi) = bounds(cs, extra).unwrap_or((DVec2::ZERO, DVec2::ZERO));
        let lo = lo - DVec2::splat(margin);
        let hi = hi + DVec2::splat(margin);
        PageFrame {
            x0: lo.x,
            y1: hi.y,
            width: (hi.x - lo.x).max(MIN_PAGE),
            height: (hi.y - lo.y).max(MIN_PAGE),
        }
    }
}

/// The `d` attribute of a path through `cs` (each contour a subpath), at f64 precision.
/// A closed contour ends with `Z` after its last distinct point (its closing line is the
/// `Z`; a closing arc is drawn and then `Z` joins no gap).
/// Arcs are split into pieces of at most [`SVG_MAX_SWEEP`]; the sweep flag is 0 for a
/// counter-clockwise design arc because the page flips y.
pub fn path_data(cs: &[&CutContour], frame: &PageFrame, close_tol: f64) -> String {
    let mut d = String::new();
    for c in cs {
        let p = frame.map(c.start);
        let _ = write!(d, "{}M {} {}", sep(&d), fnum(p.x), fnum(p.y));
        let mut from = c.start;
        let closed = c.is_closed(close_tol);
        for (k, s) in c.segs.iter().enumerate() {
            match *s {
                // A closed contour's last line is drawn by `Z`: no repeated first point.
                Seg::Line { .. } if closed && k + 1 == c.segs.len() && k > 0 => {}
                Seg::Line { to } => {
                    let q = frame.map(to);
                    let _ = write!(d, " L {} {}", fnum(q.x), fnum(q.y));
                }
                Seg::Arc { to, center, sweep } => {
                    let r = from.distance(center);
                    let flag = if sweep > 0.0 { 0 } else { 1 };
                    for e in split_arc(from, to, center, sweep, SVG_MAX_SWEEP) {
                        let q = frame.map(e);
                        let _ = write!(
                            d,
                            " A {} {} 0 0 {flag} {} {}",
                            fnum(r),
                            fnum(r),
                            fnum(q.x),
                            fnum(q.y)
                        );
                    }
                }
            }
            from = s.to();
        }
        if closed {
            d.push_str(" Z");
        }
    }
    d
}

fn sep(d: &str) -> &'static str {
    if d.is_empty() { "" } else { " " }
}

/// The laser-cutter SVG of `tp` with the colours and stroke width of `profile`'s `[svg]`.
pub fn laser_svg(
    tp: &Toolpath,
    profile: &Profile,
    opts: &LaserSvgOptions,
) -> Result<String, EmitError> {
    check_tolerance("tolerance", opts.tolerance)?;
    let svg = profile
        .svg
        .as_ref()
        .ok_or_else(|| EmitError::WrongProfile {
            profile: profile.name.clone(),
            output: "laser SVG",
            reason: "it has no [svg] table".to_string(),
        })?;
    validate(tp, opts.tolerance)?;
    let cs = contours(tp);
    let frame = match opts.page {
        Page::Bounds { margin } => {
            if !(margin.is_finite() && margin >= 0.0) {
                return Err(EmitError::InvalidOption {
                    name: "page margin",
                    reason: format!("must be >= 0, got {margin}"),
                });
            }
            PageFrame::around(&cs, &[], margin)
        }
        Page::WorkArea => {
            let wa = profile.work_area;
            PageFrame {
                x0: wa.x.min(),
                y1: wa.y.max(),
                width: wa.x.max() - wa.x.min(),
                height: wa.y.max() - wa.y.min(),
            }
        }
    };
    let mut page = SvgPage::bare(frame.width, frame.height, 1.0);
    page.title(&opts.job);
    let sw = fnum(svg.stroke_width);
    for (oi, op) in tp.operations.iter().enumerate() {
        let color = color_of(&svg.colors, op.kind);
        page.open(
            &format!("op{oi}"),
            &[
                ("data-name", &op.name),
                ("data-kind", &format!("{:?}", op.kind)),
                ("fill", "none"),
                ("stroke", color),
                ("stroke-width", &sw),
            ],
        );
        for ci in 0..op.cuts.len() {
            let parts: Vec<&CutContour> = cs.iter().filter(|c| c.op == oi && c.cut == ci).collect();
            if parts.is_empty() {
                continue;
            }
            let d = path_data(&parts, &frame, opts.tolerance);
            page.path(
                "",
                &d,
                &[("id", &format!("op{oi}-cut{ci}")), ("stroke", color)],
            );
        }
        page.close();
    }
    Ok(page.finish())
}
