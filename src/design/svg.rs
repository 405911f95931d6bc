//! SVG import: stroked paths become strokes, filled paths become shapes.
//!
//! usvg resolves units, the viewBox, nested transforms, `use`, CSS and presentation
//! attributes, and turns shapes (rect, circle, ellipse, line, polyline, polygon) and arcs
//! into absolute Bézier paths. Then, per path:
//!
//! - A path with a stroke becomes one stroke per subpath. Its centre line is the subpath
//!   (flattened to a polyline within a tenth of the tolerance); it is split into runs at the
//!   corners, the nodes where the path's tangent turns by more than the corner angle
//!   (default [`CORNER_ANGLE_DEG`](super::corners::CORNER_ANGLE_DEG)). Each run is
//!   interpolated by a disk B-spline (cubic, chord-length parameters: wu-2021
//!   "Interpolation", eq. 16) through points spaced evenly along it, doubling their number
//!   until the spine stays within the tolerance of the run both ways (the largest distance
//!   from the spine to the run and from the run to the spine). The stroke lists its
//!   corners, so it is split there into pieces with a round joint (see
//!   [`crate::design::corners`]). A closed subpath is a closed stroke.
//! - The radius is half the stroke width (scaled by the element's transform), or varies
//!   along the path when the element has `data-skinpath-widths="w0 w1 ... wk"`: stroke
//!   widths (user units, like `stroke-width`) at k + 1 points spread evenly along the length
//!   of each subpath, linear in between. The attribute needs the element's `id` (usvg keeps
//!   ids but not custom attributes).
//! - Inkscape's Power Stroke (a filled outline whose element has `inkscape:path-effect`
//!   pointing to an effect with `effect="powerstroke"`) is imported as the stroke it was
//!   drawn as: the centre line is `inkscape:original-d` (first subpath, as Inkscape draws
//!   it), the radius at each point the effect's half width (`offset_points="t,w | …"`, path
//!   time t = segment index + curve parameter, w × `scale_width`), linear between the width
//!   points, running to half the tolerance at `zerowidth` caps (Inkscape's default) and
//!   kept to the ends with other caps.
//! - A filled path becomes a [`Shape`] (a closed region, `[[shape]]`): every
//!   subpath is closed (as SVG fills it) and flattened within the tolerance after the
//!   element's transform, and the rings are resolved under the element's `fill-rule`
//!   (nonzero or evenodd) into simple contours, outer counter-clockwise and holes clockwise
//!   ([`resolve_rings`]), so the written shape needs no fill
//!   rule. The shape is named after the element's id. As in a laser program (LightBurn,
//!   Inkscape to laser: fill = an area to engrave, stroke = a line to cut), a path with both
//!   a fill and a stroke gives both: its stroke as a stroke named by the id and its fill as a
//!   shape named `ID.fill`; what the SVG paints is what the design holds. Give a path
//!   `fill="none"` to import only its stroke (SVG fills a path black unless told otherwise).
//!   An Inkscape Power Stroke's fill is the stroke's drawing, not a shape.
//! - Filled paths whose fill encloses no area or is fully transparent (listed when they
//!   have no stroke), hidden paths, paths with neither fill nor stroke, images and text are
//!   skipped, each listed by id with the reason.
//!
//! Coordinates: millimetres, 96 px per inch (mm, cm, in, pt, pc and px are resolved by
//! usvg from `width`/`height` and the viewBox); SVG's y axis points down, so y is flipped
//! about the page height: the drawing keeps its orientation and sits in x, y ≥ 0 when it
//! lies on the page.

use super::error::{DesignError, ErrorKind};
use super::model::{Design, Stroke, Units, VERSION};
use super::shape::{Shape, resolve_rings};
use crate::geom::DVec2;
use kurbo::{BezPath, CubicBez, PathEl, QuadBez};

/// Millimetres per CSS pixel (96 px per inch).
pub const MM_PER_PX: f64 = 25.4 / 96.0;

/// Default fitting tolerance of imported centre lines, mm: below the width of a laser kerf
/// or a fine engraving bit, above the f32 precision usvg keeps for drawings up to metres.
pub const DEFAULT_TOLERANCE: f64 = 0.05;

/// Largest number of interpolation points per run before the fit gives up refining (the
/// best fit is kept and its deviation reported).
const MAX_RUN_POINTS: usize = 1025;

/// Imported coordinates are rounded to 1/ROUND mm (far below usvg's f32 precision).
const ROUND: f64 = 1e6;

/// Options of [`import`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImportOptions {
    /// Largest distance between a stroke's spine and the SVG centre line, mm.
    pub tolerance: f64,
    /// Turning angle (degrees) above which a path node is a corner.
    pub corner_angle: f64,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            tolerance: DEFAULT_TOLERANCE,
            corner_angle: super::corners::CORNER_ANGLE_DEG,
        }
    }
}

/// An element that was not imported.
#[derive(Clone, Debug, PartialEq)]
pub struct Skipped {
    /// The element's id, or `<tag> #k` (k-th such element in document order) without one.
    pub id: String,
    /// Why it was not imported, in words (e.g. "raster images are not imported").
    pub reason: String,
}

/// The result of [`import`].
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// The design: one stroke per stroked subpath (with `corners`), not yet expanded, and
    /// one shape per filled path.
    pub design: Design,
    /// The elements that were not imported, with their reasons.
    pub skipped: Vec<Skipped>,
    /// The largest distance between a fitted spine and its SVG centre line, mm.
    pub max_deviation: f64,
}

fn err(file: &str, m: String) -> DesignError {
    DesignError::file(file, ErrorKind::Invalid(m))
}

/// Import the SVG `text` (see the module docs); `file` names it in errors.
pub fn import(text: &str, file: &str, opts: &ImportOptions) -> Result<Imported, DesignError> {
    if !(opts.tolerance.is_finite() && opts.tolerance > 0.0) {
        return Err(err(
            file,
            format!("import tolerance {} must be positive", opts.tolerance),
        ));
    }
    let xml = roxmltree::Document::parse(text).map_err(|e| {
        let p = e.pos();
        DesignError::file(
            file,
            ErrorKind::Parse {
                line: Some(p.row as usize),
                column: Some(p.col as usize),
                message: format!("not a well-formed SVG file: {e}"),
            },
        )
    })?;
    let tree = usvg::Tree::from_str(text, &usvg::Options::default()).map_err(|e| {
        DesignError::file(
            file,
            ErrorKind::Parse {
                line: None,
                column: None,
                message: format!("not a usable SVG file: {e}"),
            },
        )
    })?;
    let mut ctx = Ctx {
        file,
        opts: *opts,
        xml: &xml,
        page_height: tree.size().height() as f64,
        strokes: Vec::new(),
        shapes: Vec::new(),
        skipped: Vec::new(),
        counter: 0,
        max_deviation: 0.0,
    };
    // Text and images are listed from the source (usvg without fonts drops text).
    for (tag, what) in [
        (
            "text",
            "text is not imported: convert it to paths, or use [[text]]",
        ),
        ("image", "raster images are not imported"),
    ] {
        for (k, n) in xml
            .descendants()
            .filter(|n| n.is_element() && n.tag_name().name() == tag)
            .enumerate()
        {
            ctx.skipped.push(Skipped {
                id: n
                    .attribute("id")
                    .map_or_else(|| format!("<{tag}> #{k}"), str::to_string),
                reason: what.to_string(),
            });
        }
    }
    ctx.group(tree.root())?;
    let design = Design {
        version: VERSION,
        units: Units::Mm,
        outline: None,
        stroke: ctx.strokes,
        circles: Vec::new(),
        shape: ctx.shapes,
        text: Vec::new(),
        operation: Vec::new(),
        file: file.to_string(),
        corners: Vec::new(),
        neon: None,
    };
    Ok(Imported {
        design,
        skipped: ctx.skipped,
        max_deviation: ctx.max_deviation,
    })
}

/// Load an SVG file as a design (import with default options, then the usual expansion
/// and validation).
pub fn load_svg(text: &str, file: &str) -> Result<Design, DesignError> {
    let mut d = import(text, file, &ImportOptions::default())?.design;
    d.expand()?;
    super::validate(&d)?;
    Ok(d)
}

/// Why a subpath is skipped: it has no length.
const ZERO_LENGTH: &str = "subpath of zero length";

/// Why a subpath is skipped: no stroke through evenly spaced points of it builds (the
/// interpolation system is singular at every sample count tried, or for all runs together).
const NO_INTERPOLANT: &str = "no stroke interpolates its points (singular system)";

struct Ctx<'a> {
    file: &'a str,
    opts: ImportOptions,
    xml: &'a roxmltree::Document<'a>,
    page_height: f64,
    strokes: Vec<Stroke>,
    shapes: Vec<Shape>,
    skipped: Vec<Skipped>,
    counter: usize,
    max_deviation: f64,
}

/// One node of a subpath: its index in the flattened polyline and whether it is a corner.
struct Subpath {
    pts: Vec<DVec2>,
    /// Indices in `pts` of the path's nodes, with the tangent turn there (radians).
    nodes: Vec<(usize, f64)>,
    closed: bool,
    /// Path time of every point (segment index + parameter in the segment, as Inkscape's
    /// Power Stroke counts it); filled only for Power Stroke paths.
    times: Vec<f64>,
}

fn turn(a: DVec2, b: DVec2) -> f64 {
    if a.length() == 0.0 || b.length() == 0.0 {
        return 0.0;
    }
    a.angle_to(b).abs()
}

fn kp(p: DVec2) -> kurbo::Point {
    kurbo::Point::new(p.x, p.y)
}

fn dv(p: kurbo::Point) -> DVec2 {
    DVec2::new(p.x, p.y)
}

/// Start and end tangents of a segment given by its control points (the first control
/// point apart from the end point; zero for a degenerate segment).
fn tangents(ctrl: &[DVec2]) -> (DVec2, DVec2) {
    let first = ctrl[0];
    let last = ctrl[ctrl.len() - 1];
    let start = ctrl[1..]
        .iter()
        .find(|&&q| q != first)
        .map_or(DVec2::ZERO, |&q| q - first);
    let end = ctrl[..ctrl.len() - 1]
        .iter()
        .rev()
        .find(|&&q| q != last)
        .map_or(DVec2::ZERO, |&q| last - q);
    (start, end)
}

/// Flatten one segment (control points) to points after its start, within `tol`.
fn flatten_segment(ctrl: &[DVec2], tol: f64, out: &mut Vec<DVec2>) {
    match ctrl.len() {
        2 => out.push(ctrl[1]),
        3 => {
            let q = QuadBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]));
            let mut bp = BezPath::new();
            bp.move_to(q.p0);
            bp.quad_to(q.p1, q.p2);
            flatten_into(&bp, tol, out);
        }
        _ => {
            let c = CubicBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]), kp(ctrl[3]));
            let mut bp = BezPath::new();
            bp.move_to(c.p0);
            bp.curve_to(c.p1, c.p2, c.p3);
            flatten_into(&bp, tol, out);
        }
    }
}

fn flatten_into(bp: &BezPath, tol: f64, out: &mut Vec<DVec2>) {
    kurbo::flatten(bp.iter(), tol, |el| {
        if let PathEl::LineTo(p) = el {
            out.push(dv(p));
        }
    });
}

/// Parameter in [0, 1] of the point of the segment `ctrl` (2, 3 or 4 control points) nearest
/// to `q`, found to `accuracy` (kurbo's nearest-point search on the curve).
fn segment_time(ctrl: &[DVec2], q: DVec2, accuracy: f64) -> f64 {
    use kurbo::{Line, ParamCurveNearest};
    let q = kp(q);
    match ctrl.len() {
        2 => Line::new(kp(ctrl[0]), kp(ctrl[1])).nearest(q, accuracy).t,
        3 => {
            QuadBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]))
                .nearest(q, accuracy)
                .t
        }
        _ => {
            CubicBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]), kp(ctrl[3]))
                .nearest(q, accuracy)
                .t
        }
    }
}

/// The point at parameter `t` of the segment `ctrl` (2, 3 or 4 control points).
fn segment_point(ctrl: &[DVec2], t: f64) -> DVec2 {
    use kurbo::{Line, ParamCurve};
    dv(match ctrl.len() {
        2 => Line::new(kp(ctrl[0]), kp(ctrl[1])).eval(t),
        3 => QuadBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2])).eval(t),
        _ => CubicBez::new(kp(ctrl[0]), kp(ctrl[1]), kp(ctrl[2]), kp(ctrl[3])).eval(t),
    })
}

/// The Inkscape namespace of `inkscape:path-effect` and `inkscape:original-d`.
const INKSCAPE_NS: &str = "http://www.inkscape.org/namespaces/inkscape";

/// An Inkscape Power Stroke path effect on an element: its centre line (`inkscape:original-d`)
/// and its width points (`offset_points="t,w | t,w | …"`: path time t, half width w in user
/// units, times `scale_width`).
struct PowerStroke {
    /// The centre line, in the element's user units.
    centre: usvg::tiny_skia_path::Path,
    /// (path time, half width) sorted by time.
    points: Vec<(f64, f64)>,
    /// Whether the width runs to zero at the start / end (`zerowidth` caps, Inkscape's
    /// default); other caps keep the first / last point's width to the end.
    taper: (bool, bool),
    /// Path time at the end of the centre line (its number of segments).
    end: f64,
}

impl PowerStroke {
    /// Radius at each path time in `times`: the half widths interpolated linearly between
    /// the width points (Inkscape draws a smooth interpolating curve through them, by default
    /// centripetal Catmull–Rom, so between points the widths can differ from Inkscape's by
    /// that curve's bulge), tapered to `min_radius` at a zero-width cap, times `to_mm`.
    fn radii(&self, times: &[f64], to_mm: f64, min_radius: f64) -> Vec<f64> {
        let mut pts = self.points.clone();
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        pts.insert(0, (0.0, if self.taper.0 { 0.0 } else { first.1 }));
        pts.push((self.end, if self.taper.1 { 0.0 } else { last.1 }));
        times
            .iter()
            .map(|&t| {
                let i = pts.partition_point(|p| p.0 <= t).clamp(1, pts.len() - 1);
                let (a, b) = (pts[i - 1], pts[i]);
                let f = if b.0 > a.0 {
                    ((t - a.0) / (b.0 - a.0)).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                (((1.0 - f) * a.1 + f * b.1) * to_mm).max(min_radius)
            })
            .collect()
    }
}

impl Ctx<'_> {
    fn to_mm(&self, p: DVec2) -> DVec2 {
        DVec2::new(p.x * MM_PER_PX, (self.page_height - p.y) * MM_PER_PX)
    }

    fn group(&mut self, g: &usvg::Group) -> Result<(), DesignError> {
        for node in g.children() {
            match node {
                usvg::Node::Group(g) => self.group(g)?,
                usvg::Node::Path(p) => self.path(p)?,
                usvg::Node::Image(_) | usvg::Node::Text(_) => {}
            }
        }
        Ok(())
    }

    fn element_id(&mut self, id: &str) -> String {
        self.counter += 1;
        if id.is_empty() {
            format!("<path> #{}", self.counter - 1)
        } else {
            id.to_string()
        }
    }

    fn skip(&mut self, id: String, reason: &str) {
        self.skipped.push(Skipped {
            id,
            reason: reason.to_string(),
        });
    }

    fn path(&mut self, p: &usvg::Path) -> Result<(), DesignError> {
        let id = self.element_id(p.id());
        if !p.is_visible() {
            self.skip(id, "hidden (visibility or display)");
            return Ok(());
        }
        let power = self.power_stroke(p.id(), &id)?;
        // A fully transparent fill (fill-opacity 0, or the colour `transparent`) paints
        // nothing: it is no area to engrave.
        let fill = p.fill().filter(|f| f.opacity().get() > 0.0);
        if power.is_none()
            && let Some(fill) = fill
        {
            self.fill_shape(p, &id, fill.rule(), p.stroke().is_some());
        }
        let stroke_width = match (&power, p.stroke()) {
            (Some(_), _) => 0.0,
            (None, Some(stroke)) => stroke.width().get() as f64,
            (None, None) => {
                if p.fill().is_none() {
                    self.skip(id, "neither stroked nor filled");
                } else if fill.is_none() {
                    self.skip(id, "its fill is fully transparent and it has no stroke");
                }
                return Ok(());
            }
        };
        let t = p.abs_transform();
        let scale = ((t.sx as f64 * t.sy as f64 - t.kx as f64 * t.ky as f64).abs()).sqrt();
        let width_mm = stroke_width * scale * MM_PER_PX;
        let widths = self.widths(p.id(), &id)?;
        let data = match &power {
            Some(ps) => ps.centre.clone(),
            None => p.data().clone(),
        };
        let mut segment = 0usize;
        let map = |q: usvg::tiny_skia_path::Point| {
            let x = t.sx as f64 * q.x as f64 + t.kx as f64 * q.y as f64 + t.tx as f64;
            let y = t.ky as f64 * q.x as f64 + t.sy as f64 * q.y as f64 + t.ty as f64;
            DVec2::new(x, y)
        };
        let tol = self.opts.tolerance;
        let mut subpaths: Vec<Subpath> = Vec::new();
        let mut cur: Option<(Subpath, DVec2, DVec2)> = None; // (subpath, start, in-tangent)
        let mut first_tangent = DVec2::ZERO;
        let finish = |cur: &mut Option<(Subpath, DVec2, DVec2)>, out: &mut Vec<Subpath>| {
            if let Some((s, _, _)) = cur.take()
                && s.pts.len() >= 2
            {
                out.push(s);
            }
        };
        for seg in data.segments() {
            use usvg::tiny_skia_path::PathSegment as S;
            let ctrl: Vec<DVec2> = match seg {
                S::MoveTo(q) => {
                    finish(&mut cur, &mut subpaths);
                    let q = self.to_mm(map(q));
                    cur = Some((
                        Subpath {
                            pts: vec![q],
                            nodes: vec![(0, 0.0)],
                            closed: false,
                            times: vec![segment as f64],
                        },
                        q,
                        DVec2::ZERO,
                    ));
                    continue;
                }
                S::LineTo(q) => vec![map(q)],
                S::QuadTo(a, b) => vec![map(a), map(b)],
                S::CubicTo(a, b, c) => vec![map(a), map(b), map(c)],
                S::Close => {
                    if let Some((s, start, tin)) = cur.as_mut() {
                        let last = *s.pts.last().unwrap_or(start);
                        let mut tin = *tin;
                        if last.distance(*start) > 1e-9 {
                            segment += 1;
                            let (a, b) = tangents(&[last, *start]);
                            let k = s.pts.len() - 1;
                            if let Some(n) = s.nodes.last_mut()
                                && n.0 == k
                            {
                                n.1 = turn(tin, a);
                            }
                            s.pts.push(*start);
                            s.times.push(segment as f64);
                            s.nodes.push((s.pts.len() - 1, 0.0));
                            tin = b;
                        }
                        // The closing node: from the last segment into the first.
                        s.nodes[0].1 = turn(tin, first_tangent);
                        s.closed = true;
                    }
                    finish(&mut cur, &mut subpaths);
                    continue;
                }
            };
            let Some((s, _, tin)) = cur.as_mut() else {
                continue;
            };
            let prev = *s.pts.last().unwrap_or(&DVec2::ZERO);
            let mut full = vec![prev];
            full.extend(ctrl.iter().map(|&q| self.to_mm(q)));
            let (a, b) = tangents(&full);
            let index = segment;
            segment += 1;
            if a == DVec2::ZERO {
                continue; // a zero-length segment
            }
            let k = s.pts.len() - 1;
            if k == 0 {
                first_tangent = a;
            }
            if let Some(n) = s.nodes.last_mut()
                && n.0 == k
            {
                n.1 = turn(*tin, a);
            }
            let from = s.pts.len();
            flatten_segment(&full, 0.1 * tol, &mut s.pts);
            if let Some(ps) = &power {
                // Path times of the flattened points, and a point at every width point
                // inside the segment, so the widths are sampled where they turn.
                let mut timed: Vec<(f64, DVec2)> = s.pts[from..]
                    .iter()
                    .map(|&q| (index as f64 + segment_time(&full, q, 1e-9 * tol), q))
                    .collect();
                for &(t, _) in &ps.points {
                    let f = t - index as f64;
                    if f > 0.0 && f < 1.0 {
                        timed.push((t, segment_point(&full, f)));
                    }
                }
                timed.sort_by(|a, b| a.0.total_cmp(&b.0));
                s.pts.truncate(from);
                for (t, q) in timed {
                    s.pts.push(q);
                    s.times.push(t);
                }
            }
            s.nodes.push((s.pts.len() - 1, 0.0));
            *tin = b;
        }
        finish(&mut cur, &mut subpaths);
        if subpaths.is_empty() {
            self.skip(id, "stroked path of zero length");
            return Ok(());
        }
        if power.is_some() && subpaths.len() > 1 {
            // Inkscape applies Power Stroke to the first subpath only.
            subpaths.truncate(1);
            self.skip(
                format!("{id} (subpaths after the first)"),
                "Power Stroke draws only a path's first subpath",
            );
        }
        let many = subpaths.len() > 1;
        for (j, sp) in subpaths.into_iter().enumerate() {
            let name = if many {
                format!("{id}.{j}")
            } else {
                id.clone()
            };
            let name = self.unique(name);
            let radii = match &power {
                Some(ps) => ps.radii(&sp.times, scale * MM_PER_PX, 0.5 * self.opts.tolerance),
                None => self.radii(&sp.pts, width_mm, widths.as_deref(), scale),
            };
            match self.fit_subpath(&name, &sp, &radii) {
                Ok(s) => self.strokes.push(s),
                Err(reason) => self.skip(name, reason),
            }
        }
        Ok(())
    }

    /// The Inkscape Power Stroke on the element with id `id`, if it has one: an
    /// `inkscape:path-effect` reference to an effect with `effect="powerstroke"` and an
    /// `inkscape:original-d` centre line. Malformed width points are an error naming the
    /// element.
    fn power_stroke(&self, id: &str, shown: &str) -> Result<Option<PowerStroke>, DesignError> {
        let Some(node) = self.element(id) else {
            return Ok(None);
        };
        let (Some(effects), Some(centre)) = (
            node.attribute((INKSCAPE_NS, "path-effect")),
            node.attribute((INKSCAPE_NS, "original-d")),
        ) else {
            return Ok(None);
        };
        let effect = effects
            .split(';')
            .filter_map(|r| r.trim().strip_prefix('#'))
            .filter_map(|r| self.element(r))
            .find(|n| n.attribute("effect") == Some("powerstroke"));
        let Some(effect) = effect else {
            return Ok(None);
        };
        let bad = |m: String| err(self.file, format!("element {shown}: Power Stroke {m}"));
        let bez = BezPath::from_svg(centre).map_err(|e| {
            bad(format!(
                "centre line (inkscape:original-d) is not path data: {e}"
            ))
        })?;
        let mut pb = usvg::tiny_skia_path::PathBuilder::new();
        let mut end = 0.0;
        let mut started = false;
        let (mut first, mut current) = (kurbo::Point::ZERO, kurbo::Point::ZERO);
        for el in bez.elements() {
            if let Some(p) = el.end_point() {
                if let PathEl::MoveTo(_) = el {
                    first = p;
                }
                current = p;
            }
            let f = |p: kurbo::Point| (p.x as f32, p.y as f32);
            match *el {
                PathEl::MoveTo(p) => {
                    if started {
                        break; // Power Stroke draws the first subpath only.
                    }
                    started = true;
                    let (x, y) = f(p);
                    pb.move_to(x, y);
                }
                PathEl::LineTo(p) => {
                    let (x, y) = f(p);
                    pb.line_to(x, y);
                    end += 1.0;
                }
                PathEl::QuadTo(a, p) => {
                    let ((ax, ay), (x, y)) = (f(a), f(p));
                    pb.quad_to(ax, ay, x, y);
                    end += 1.0;
                }
                PathEl::CurveTo(a, b, p) => {
                    let ((ax, ay), (bx, by), (x, y)) = (f(a), f(b), f(p));
                    pb.cubic_to(ax, ay, bx, by, x, y);
                    end += 1.0;
                }
                PathEl::ClosePath => {
                    pb.close();
                    if current.distance(first) > 0.0 {
                        end += 1.0; // a closing line; a closing point adds no segment
                    }
                }
            }
        }
        let Some(path) = pb.finish() else {
            return Err(bad("centre line (inkscape:original-d) is empty".into()));
        };
        let scale_width = match effect.attribute("scale_width") {
            None => 1.0,
            Some(v) => v
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|w| w.is_finite() && *w > 0.0)
                .ok_or_else(|| bad(format!("scale_width {v:?} is not a positive number")))?,
        };
        let mut points = Vec::new();
        for item in effect
            .attribute("offset_points")
            .unwrap_or("")
            .split('|')
            .map(str::trim)
            .filter(|t| !t.is_empty())
        {
            let nums: Vec<Option<f64>> = item
                .split(',')
                .map(|v| v.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
                .collect();
            match nums[..] {
                [Some(t), Some(w)] if w > 0.0 => points.push((t, w * scale_width)),
                _ => {
                    return Err(bad(format!(
                        "width point {item:?} is not \"time,half-width\" with a positive width"
                    )));
                }
            }
        }
        if points.is_empty() {
            return Err(bad("has no width points (offset_points)".into()));
        }
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let zero = |key: &str| effect.attribute(key).is_none_or(|c| c == "zerowidth");
        Ok(Some(PowerStroke {
            centre: path,
            points,
            taper: (zero("start_linecap_type"), zero("end_linecap_type")),
            end,
        }))
    }

    /// The fill of `p` as a shape (see the module docs): subpaths closed and flattened within
    /// the tolerance in millimetres, resolved under `rule`, rounded like stroke points.
    /// A fill that encloses no area, or whose contours do not make a valid shape after
    /// rounding, is listed as skipped (a stroked path's empty fill, e.g. a straight line's,
    /// is not: the path was imported as a stroke).
    fn fill_shape(&mut self, p: &usvg::Path, id: &str, rule: usvg::FillRule, stroked: bool) {
        let t = p.abs_transform();
        let mm = |q: usvg::tiny_skia_path::Point| {
            let x = t.sx as f64 * q.x as f64 + t.kx as f64 * q.y as f64 + t.tx as f64;
            let y = t.ky as f64 * q.x as f64 + t.sy as f64 * q.y as f64 + t.ty as f64;
            self.to_mm(DVec2::new(x, y))
        };
        let tol = self.opts.tolerance;
        let mut rings: Vec<Vec<DVec2>> = Vec::new();
        let mut cur: Vec<DVec2> = Vec::new();
        let mut start = DVec2::ZERO;
        for seg in p.data().segments() {
            use usvg::tiny_skia_path::PathSegment as S;
            if !matches!(seg, S::MoveTo(_) | S::Close) && cur.is_empty() {
                cur.push(start); // drawing on after a close starts at the subpath's start
            }
            let last = cur.last().copied().unwrap_or(start);
            match seg {
                S::MoveTo(q) => {
                    rings.push(std::mem::take(&mut cur));
                    start = mm(q);
                    cur.push(start);
                }
                S::LineTo(q) => cur.push(mm(q)),
                S::QuadTo(a, b) => flatten_segment(&[last, mm(a), mm(b)], tol, &mut cur),
                S::CubicTo(a, b, c) => flatten_segment(&[last, mm(a), mm(b), mm(c)], tol, &mut cur),
                S::Close => rings.push(std::mem::take(&mut cur)),
            }
        }
        rings.push(cur);
        rings.retain(|r| r.len() >= 3);
        let rule = match rule {
            usvg::FillRule::NonZero => super::FillRule::Nonzero,
            usvg::FillRule::EvenOdd => super::FillRule::Evenodd,
        };
        let region = resolve_rings(&rings, rule);
        let size = region
            .iter()
            .flatten()
            .fold(1.0f64, |m, q| m.max(q.abs().max_element()));
        // usvg keeps f32 coordinates: digits past 1e-6 mm are noise. Points that rounding
        // brings within twice the design's near-repeat distance of their predecessor go.
        let apart = 2.0 * (super::NEAR_FRACTION * size).max(1.0 / ROUND);
        let contours: Vec<Vec<[f64; 2]>> = region
            .iter()
            .map(|r| {
                let mut out: Vec<[f64; 2]> = Vec::with_capacity(r.len());
                for q in r {
                    let v = [q.x, q.y].map(|c| (c * ROUND).round() / ROUND);
                    let far = |w: &[f64; 2]| (v[0] - w[0]).hypot(v[1] - w[1]) > apart;
                    if out.last().is_none_or(far) {
                        out.push(v);
                    }
                }
                while out.len() > 1
                    && out
                        .first()
                        .zip(out.last())
                        .is_some_and(|(f, l)| (f[0] - l[0]).hypot(f[1] - l[1]) <= apart)
                {
                    out.pop();
                }
                out
            })
            .filter(|r| r.len() >= 3)
            .collect();
        let name = if stroked {
            format!("{id}.fill")
        } else {
            id.to_string()
        };
        if contours.is_empty() {
            if !stroked {
                self.skip(name, "filled shape that encloses no area");
            }
            return;
        }
        let name = self.unique(name);
        let shape = Shape {
            name: name.clone(),
            fill_rule: None,
            contours,
            layer: None,
            color: None,
        };
        match shape.validate(self.file, self.shapes.len()) {
            Ok(()) => self.shapes.push(shape),
            Err(e) => {
                let part = e.part.as_ref().map_or(String::new(), |p| format!("{p}: "));
                let reason = format!("its fill does not make a valid shape: {part}{}", e.kind);
                self.skip(name, &reason);
            }
        }
    }

    fn unique(&self, name: String) -> String {
        let taken = |n: &str| {
            self.strokes.iter().any(|s| s.name == n) || self.shapes.iter().any(|s| s.name == n)
        };
        if !taken(&name) {
            return name;
        }
        (1..)
            .map(|k| format!("{name}~{k}"))
            .find(|n| !taken(n))
            .unwrap_or(name)
    }

    /// The source element with id `id` (usvg keeps ids but not custom or Inkscape
    /// attributes, which are read from the source).
    fn element(&self, id: &str) -> Option<roxmltree::Node<'_, '_>> {
        if id.is_empty() {
            return None;
        }
        self.xml
            .descendants()
            .find(|n| n.is_element() && n.attribute("id") == Some(id))
    }

    /// The `data-skinpath-widths` of the element with id `id`, if any.
    fn widths(&self, id: &str, shown: &str) -> Result<Option<Vec<f64>>, DesignError> {
        let Some(node) = self.element(id) else {
            return Ok(None);
        };
        let Some(v) = node.attribute("data-skinpath-widths") else {
            return Ok(None);
        };
        let mut out = Vec::new();
        for tok in v
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
        {
            match tok.parse::<f64>() {
                Ok(w) if w.is_finite() && w > 0.0 => out.push(w),
                _ => {
                    return Err(err(
                        self.file,
                        format!(
                            "element {shown}: data-skinpath-widths value {tok:?} is not a \
                             positive number"
                        ),
                    ));
                }
            }
        }
        if out.len() < 2 {
            return Err(err(
                self.file,
                format!(
                    "element {shown}: data-skinpath-widths needs at least two widths (start \
                     and end), got {}",
                    out.len()
                ),
            ));
        }
        Ok(Some(out))
    }

    /// Radius at every point of a subpath: half the stroke width, or the widths spread
    /// evenly along its length.
    fn radii(&self, pts: &[DVec2], width_mm: f64, widths: Option<&[f64]>, scale: f64) -> Vec<f64> {
        let Some(w) = widths else {
            return vec![0.5 * width_mm; pts.len()];
        };
        let mut s = vec![0.0];
        for q in pts.windows(2) {
            s.push(s.last().copied().unwrap_or(0.0) + q[0].distance(q[1]));
        }
        let total = s.last().copied().unwrap_or(0.0).max(f64::MIN_POSITIVE);
        let k = (w.len() - 1) as f64;
        s.iter()
            .map(|&si| {
                let u = (si / total * k).clamp(0.0, k);
                let i = (u.floor() as usize).min(w.len() - 2);
                let f = u - i as f64;
                0.5 * ((1.0 - f) * w[i] + f * w[i + 1]) * scale * MM_PER_PX
            })
            .collect()
    }

    /// The stroke of one subpath: runs between corners, each interpolated through enough
    /// evenly spaced points to stay within the tolerance; the reason it is skipped when a
    /// run has zero length or no interpolant through its samples builds.
    fn fit_subpath(
        &mut self,
        name: &str,
        sp: &Subpath,
        radii: &[f64],
    ) -> Result<Stroke, &'static str> {
        let limit = self.opts.corner_angle.to_radians();
        let mut cuts: Vec<usize> = sp
            .nodes
            .iter()
            .filter(|&&(i, a)| a > limit && (sp.closed || (i > 0 && i + 1 < sp.pts.len())))
            .map(|&(i, _)| i)
            .collect();
        cuts.sort_unstable();
        cuts.dedup();
        let n = sp.pts.len();
        let mut pts = sp.pts.clone();
        let mut rs = radii.to_vec();
        if sp.closed {
            // The last point repeats the first.
            pts.pop();
            rs.pop();
            cuts.retain(|&c| c < n - 1);
            if cuts.len() == 1 {
                // One corner on a closed path: also cut half-way round, so no piece starts
                // and ends at the same point.
                let m = pts.len();
                let c = (cuts[0] + m / 2) % m;
                cuts.push(c);
                cuts.sort_unstable();
            }
        }
        let m = pts.len();
        if m < 2 {
            return Err(ZERO_LENGTH);
        }
        // Runs as inclusive index ranges (wrapping for closed paths).
        let runs: Vec<Vec<usize>> = if cuts.is_empty() {
            vec![(0..m).collect()]
        } else if sp.closed {
            (0..cuts.len())
                .map(|k| {
                    let (a, b) = (cuts[k], cuts[(k + 1) % cuts.len()]);
                    let len = if b > a { b - a } else { m - a + b };
                    (0..=len).map(|j| (a + j) % m).collect()
                })
                .collect()
        } else {
            let mut b = vec![0];
            b.extend(&cuts);
            b.push(m - 1);
            b.windows(2).map(|w| (w[0]..=w[1]).collect()).collect()
        };
        let whole_closed = sp.closed && cuts.is_empty();
        let mut points: Vec<[f64; 3]> = Vec::new();
        let mut corners = Vec::new();
        for (k, run) in runs.iter().enumerate() {
            let rp: Vec<DVec2> = run.iter().map(|&i| pts[i]).collect();
            let rr: Vec<f64> = run.iter().map(|&i| rs[i]).collect();
            let (fit, dev) = self.fit_run(name, &rp, &rr, whole_closed)?;
            self.max_deviation = self.max_deviation.max(dev);
            if k > 0 {
                corners.push(points.len() - 1);
                points.extend_from_slice(&fit[1..]);
            } else {
                points.extend_from_slice(&fit);
            }
        }
        let mut s = Stroke::from_disks(name, Vec::new());
        s.disks = None;
        if sp.closed && !cuts.is_empty() {
            points.pop(); // back at the first corner
            corners.insert(0, 0);
            s.closed = true;
        } else if whole_closed {
            s.closed = true;
        }
        s.degree = 3.min(points.len() - 1).max(1);
        s.points = Some(points);
        s.corners = if corners.is_empty() {
            None
        } else {
            Some(corners)
        };
        // Each run built on its own; the stroke interpolates all of them in one system.
        s.to_dbsc(self.file, 0).map_err(|_| NO_INTERPOLANT)?;
        Ok(s)
    }

    /// Points [x, y, r] whose interpolant stays within the tolerance of the run `pts`
    /// (both ways), or the closest that builds, and the distance reached.
    fn fit_run(
        &self,
        name: &str,
        pts: &[DVec2],
        radii: &[f64],
        closed: bool,
    ) -> Result<(Vec<[f64; 3]>, f64), &'static str> {
        let mut s = vec![0.0];
        for q in pts.windows(2) {
            s.push(s.last().copied().unwrap_or(0.0) + q[0].distance(q[1]));
        }
        if closed {
            s.push(s.last().copied().unwrap_or(0.0) + pts[pts.len() - 1].distance(pts[0]));
        }
        let total = s.last().copied().unwrap_or(0.0);
        if total <= 0.0 {
            return Err(ZERO_LENGTH);
        }
        let mut ring: Vec<DVec2> = pts.to_vec();
        let mut ring_r = radii.to_vec();
        if closed {
            ring.push(pts[0]);
            ring_r.push(radii[0]);
        }
        let at = |u: f64| -> [f64; 3] {
            let i = s.partition_point(|&v| v <= u).clamp(1, s.len() - 1);
            let (a, b) = (s[i - 1], s[i]);
            let f = if b > a { (u - a) / (b - a) } else { 0.0 };
            let p = ring[i - 1].lerp(ring[i], f);
            let r = ring_r[i - 1] + f * (ring_r[i] - ring_r[i - 1]);
            // usvg keeps f32 coordinates: digits past 1e-6 mm are noise.
            [p.x, p.y, r].map(|v| (v * ROUND).round() / ROUND)
        };
        let mut count = if closed { 8 } else { 2 };
        let mut best: Option<(Vec<[f64; 3]>, f64)> = None;
        loop {
            let samples: Vec<[f64; 3]> = if closed {
                (0..count)
                    .map(|j| at(total * j as f64 / count as f64))
                    .collect()
            } else {
                (0..count)
                    .map(|j| at(total * j as f64 / (count - 1) as f64))
                    .collect()
            };
            // A fit that does not build (a singular interpolation system) is never kept.
            let dev = self.deviation(name, &samples, &ring, &ring_r, closed);
            if dev.is_finite() && best.as_ref().is_none_or(|b| dev < b.1) {
                best = Some((samples, dev));
            }
            let done = best
                .as_ref()
                .is_some_and(|b| b.1 <= 0.9 * self.opts.tolerance);
            if done || count >= MAX_RUN_POINTS {
                return best.ok_or(NO_INTERPOLANT);
            }
            count = if count == 2 { 4 } else { 2 * count - 1 };
        }
    }

    /// Both-ways distance between the interpolant of `samples` and the polyline `ring`
    /// (infinite when the fit fails).
    /// How far the stroke through `samples` strays from the run (`ring` with radii
    /// `ring_r`): the largest distance from its spine to the run and from the run to its
    /// spine, plus the largest radius error at the run's points (the radius at the spine
    /// sample nearest each point against the point's radius). The sum bounds how far the
    /// stroke's disks stray from the drawn ones.
    fn deviation(
        &self,
        name: &str,
        samples: &[[f64; 3]],
        ring: &[DVec2],
        ring_r: &[f64],
        closed: bool,
    ) -> f64 {
        let mut st = Stroke::from_disks(name, Vec::new());
        st.disks = None;
        st.closed = closed;
        st.degree = 3.min(samples.len() - 1).max(1);
        st.points = Some(samples.to_vec());
        let Ok(c) = st.to_dbsc(self.file, 0) else {
            return f64::INFINITY;
        };
        let (lo, hi) = c.domain();
        let n = (samples.len() * 16).max(64);
        let params: Vec<f64> = (0..=n)
            .map(|i| lo + (hi - lo) * i as f64 / n as f64)
            .collect();
        let spine: Vec<DVec2> = params.iter().map(|&t| c.center(t)).collect();
        let a = spine
            .iter()
            .map(|&q| dist_polyline(q, ring))
            .fold(0.0, f64::max);
        let b = ring
            .iter()
            .map(|&q| dist_polyline(q, &spine))
            .fold(0.0, f64::max);
        // Radius error both ways: at each spine sample against the run's radius at the
        // nearest point of the run, and at each run point against the spine sample nearest it.
        let to_run = spine
            .iter()
            .zip(&params)
            .map(|(&q, &t)| (c.radius(t) - radius_on_polyline(q, ring, ring_r)).abs())
            .fold(0.0, f64::max);
        let to_spine = ring
            .iter()
            .zip(ring_r)
            .map(|(&q, &r)| {
                let j = (0..spine.len())
                    .min_by(|&i, &k| q.distance(spine[i]).total_cmp(&q.distance(spine[k])))
                    .unwrap_or(0);
                (c.radius(params[j]) - r).abs()
            })
            .fold(0.0, f64::max);
        let radius_error = to_run.max(to_spine);
        a.max(b) + radius_error
    }
}

/// The radius (linear along each segment of `poly`, radii `r` at its points) at the point
/// of `poly` nearest to `p`.
fn radius_on_polyline(p: DVec2, poly: &[DVec2], r: &[f64]) -> f64 {
    if poly.len() == 1 {
        return r[0];
    }
    let mut best = (f64::INFINITY, r[0]);
    for (i, w) in poly.windows(2).enumerate() {
        let seg = crate::geom::Line::new(w[0], w[1]);
        let t = seg.nearest_t(p);
        let d = seg.eval(t).distance(p);
        if d < best.0 {
            best = (d, r[i] + t * (r[i + 1] - r[i]));
        }
    }
    best.1
}

fn dist_polyline(p: DVec2, poly: &[DVec2]) -> f64 {
    if poly.len() == 1 {
        return p.distance(poly[0]);
    }
    poly.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let d = b - a;
            let l2 = d.length_squared();
            let t = if l2 > 0.0 {
                ((p - a).dot(d) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            p.distance(a + d * t)
        })
        .fold(f64::INFINITY, f64::min)
}
