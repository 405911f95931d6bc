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
//! - Fills follow the paint model ([`paint`]): in document order a later fill hides what
//!   lies under it, fills of one colour that overlap merge, white and background fills knock
//!   out; each shape is the visible part of its fill.
//! - Strokes and shapes carry the Inkscape layer they lie in (`layer`, the layer's label, also
//!   the prefix of their names: `Layer 1/path12`) and their paint (`color`, `#rrggbb`).
//! - Path data is cleaned within the tolerance before fitting ([`fit::clean`]); a fit beyond
//!   the tolerance is kept with a warning naming the element and the worst error.
//! - Filled paths whose fill encloses no area or is fully transparent (listed when they
//!   have no stroke), hidden paths, paths with neither fill nor stroke (or a stroke-width of
//!   zero or less), images, text and malformed path data are skipped, each listed by id with
//!   the reason; so is any element that does not make a valid stroke or shape, or whose
//!   counts exceed the limits (checked before the work). One bad element never stops the
//!   import; a file with nothing usable is an error naming the file and what was skipped.
//!   The XML is read by [`xml::parse`] (DTD and internal entities within bounds, nothing
//!   external); no image or other external reference is ever opened.
//!
//! Coordinates: millimetres, 96 px per inch (mm, cm, in, pt, pc and px are resolved by
//! usvg from `width`/`height` and the viewBox); SVG's y axis points down, so y is flipped
//! about the page height: the drawing keeps its orientation and sits in x, y ≥ 0 when it
//! lies on the page.

use super::MAX_ITEMS;
use super::error::{DesignError, ErrorKind};
use super::model::{Design, Stroke};
use super::shape::{Shape, resolve_rings};
use crate::geom::DVec2;
use kurbo::{BezPath, CubicBez, PathEl, QuadBez};
use std::collections::{HashMap, HashSet};

mod fill;
mod fit;
mod paint;
mod power;
pub mod xml;

/// The Inkscape namespace (`inkscape:path-effect`, `inkscape:original-d`,
/// `inkscape:groupmode`, `inkscape:label`).
const INKSCAPE_NS: &str = "http://www.inkscape.org/namespaces/inkscape";

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
    /// Elements imported with a caveat: a fit beyond the tolerance (with the worst error),
    /// path data read up to an error.
    pub warnings: Vec<Skipped>,
}

/// usvg's options for import: no image or other external reference is ever resolved (the
/// resolvers answer nothing, so no file, device, FIFO or URL is opened: images are skipped
/// from the source anyway), no resources directory.
fn usvg_options() -> usvg::Options<'static> {
    usvg::Options {
        resources_dir: None,
        image_href_resolver: usvg::ImageHrefResolver {
            resolve_data: Box::new(|_, _, _| None),
            resolve_string: Box::new(|_, _| None),
        },
        ..usvg::Options::default()
    }
}

fn err(file: &str, m: String) -> DesignError {
    DesignError::file(file, ErrorKind::Invalid(m))
}

/// Import the SVG `text` (see the module docs); `file` names it in errors. One element that
/// cannot be used is skipped with its id and the reason; a file with nothing usable left is
/// an error naming the file and what was skipped.
pub fn import(text: &str, file: &str, opts: &ImportOptions) -> Result<Imported, DesignError> {
    if !(opts.tolerance.is_finite() && opts.tolerance > 0.0) {
        return Err(err(
            file,
            format!("import tolerance {} must be positive", opts.tolerance),
        ));
    }
    let xml = xml::parse(text, file)?;
    let tree = usvg::Tree::from_xmltree(&xml, &usvg_options()).map_err(|e| {
        DesignError::file(
            file,
            ErrorKind::Parse {
                line: None,
                column: None,
                message: format!("not a usable SVG file: {e}"),
            },
        )
    })?;
    let mut ids = HashMap::new();
    for n in xml.descendants().filter(|n| n.is_element()) {
        if let Some(id) = n.attribute("id") {
            ids.entry(id).or_insert(n);
        }
    }
    let mut ctx = Ctx {
        file,
        opts: *opts,
        ids,
        names: HashSet::new(),
        suffix: HashMap::new(),
        warnings: Vec::new(),
        seen: HashSet::new(),
        page_width: tree.size().width() as f64,
        page_height: tree.size().height() as f64,
        layer: None,
        path_layer: None,
        paint: paint::Paint::default(),
        sheet: style_rules(&xml),
        opacity: 1.0,
        strokes: Vec::new(),
        stroke_src: Vec::new(),
        shapes: Vec::new(),
        skipped: Vec::new(),
        counter: 0,
        max_deviation: 0.0,
    };
    // Text, images and malformed path data are listed from the source (usvg without fonts
    // drops text, images are never resolved, and usvg drops a path whose data has no
    // usable segment).
    let mut malformed = Vec::new();
    for n in xml.descendants().filter(|n| n.is_element()) {
        let tag = n.tag_name().name();
        let reason = match tag {
            "text" => "text is not imported: convert it to paths (Inkscape: Path > Object to \
                       Path), or use [[text]]"
                .to_string(),
            "image" => "raster images are not imported (their files are not read)".to_string(),
            "path" => match n.attribute("d").map(path_data_error) {
                Some(Some(e)) => {
                    malformed.push((n, e));
                    continue;
                }
                _ => continue,
            },
            _ => continue,
        };
        ctx.skip(source_name(&xml, n), &reason);
    }
    ctx.group(tree.root());
    ctx.hide_strokes();
    ctx.finish_paint();
    // A malformed path that usvg kept was drawn up to the error (as SVG renderers do);
    // one it dropped had nothing before the error.
    for (n, e) in malformed {
        let id = n.attribute("id").unwrap_or("");
        if !id.is_empty() && ctx.seen.contains(id) {
            ctx.warn(
                id.to_string(),
                format!("path data {e}; imported up to there"),
            );
        } else {
            ctx.skip(source_name(&xml, n), &format!("path data {e}"));
        }
    }
    if ctx.strokes.is_empty() && ctx.shapes.is_empty() {
        return Err(err(file, nothing_usable(&ctx.skipped)));
    }
    let mut design = Design::empty(file);
    design.stroke = ctx.strokes;
    design.shape = ctx.shapes;
    Ok(Imported {
        design,
        skipped: ctx.skipped,
        max_deviation: ctx.max_deviation,
        warnings: ctx.warnings,
    })
}

/// Load an SVG file as a design (import with default options, then the usual expansion
/// and validation).
pub fn load_svg(text: &str, file: &str) -> Result<Design, DesignError> {
    load_svg_noted(text, file).map(|(d, _)| d)
}

/// [`load_svg`], with what the import left out or caught: one line per skipped element
/// (`skipped ID: reason`) and per warning (`warning: ID: reason`), for the caller to show.
pub fn load_svg_noted(text: &str, file: &str) -> Result<(Design, Vec<String>), DesignError> {
    let imported = import(text, file, &ImportOptions::default())?;
    let notes = (imported
        .skipped
        .iter()
        .map(|s| format!("skipped {}: {}", s.id, s.reason)))
    .chain((imported.warnings.iter()).map(|w| format!("warning: {}: {}", w.id, w.reason)))
    .collect();
    let mut d = imported.design;
    d.expand()?;
    super::validate(&d)?;
    Ok((d, notes))
}

/// Why a subpath is skipped: it has no length.
const ZERO_LENGTH: &str = "subpath of zero length";

/// Why a subpath is skipped: no stroke through evenly spaced points of it builds (the
/// interpolation system is singular at every sample count tried, or for all runs together).
const NO_INTERPOLANT: &str = "no stroke interpolates its points (singular system)";

/// Most points one subpath may flatten to (within a tenth of the tolerance) before it is
/// refused: the fit compares every spine sample with every point, so this bounds its work
/// (a 1 m circle flattens to about 10³ points at the default tolerance).
const MAX_FLAT_POINTS: usize = 20_000;

/// The largest number of segments of one subpath of `data` (`None` for no segment), counted
/// without flattening.
fn longest_subpath(data: &usvg::tiny_skia_path::Path) -> Option<usize> {
    use usvg::tiny_skia_path::PathVerb as V;
    let (mut best, mut cur) = (None, 0usize);
    for v in data.verbs() {
        match v {
            V::Move => cur = 0,
            V::Close => {}
            _ => {
                cur += 1;
                best = Some(best.unwrap_or(0).max(cur));
            }
        }
    }
    best
}

/// What is wrong with an item, without the file and item (the skip list names those).
fn reason_of(e: &DesignError) -> String {
    match &e.part {
        Some(p) => format!("{p}: {}", e.kind),
        None => e.kind.to_string(),
    }
}

/// The value of the inherited presentation property `name` on `n`: from its `style`
/// attribute, else the last rule of the highest specificity of the style `sheet` that
/// matches it, else the attribute itself (the CSS cascade of SVG 1.1 §6.4, without
/// `!important`), else from the nearest ancestor that sets it.
fn inherited<'a>(
    n: roxmltree::Node<'a, 'a>,
    name: &str,
    sheet: &[simplecss::Rule<'a>],
) -> Option<&'a str> {
    n.ancestors().filter(|a| a.is_element()).find_map(|a| {
        let styled = a.attribute("style").and_then(|st| {
            st.split(';').find_map(|decl| {
                let (k, v) = decl.split_once(':')?;
                (k.trim() == name).then_some(v)
            })
        });
        let css = || {
            sheet
                .iter()
                .filter(|r| r.selector.matches(&XmlElement(a)))
                .filter_map(|r| {
                    let d = r.declarations.iter().rev().find(|d| d.name == name)?;
                    Some((r.selector.specificity(), d.value))
                })
                .fold(None, |best: Option<([u8; 3], &str)>, (sp, v)| match best {
                    Some((b, _)) if b > sp => best,
                    _ => Some((sp, v)),
                })
                .map(|(_, v)| v)
        };
        styled.or_else(css).or_else(|| a.attribute(name))
    })
}

/// The rules of every `<style>` element of the document, in document order.
fn style_rules<'a>(xml: &'a roxmltree::Document<'a>) -> Vec<simplecss::Rule<'a>> {
    let mut sheet = simplecss::StyleSheet::new();
    for n in xml.descendants().filter(|n| n.has_tag_name("style")) {
        for t in n.children().filter_map(|c| c.text()) {
            sheet.parse_more(t);
        }
    }
    sheet.rules
}

/// A source element as CSS selectors see it.
#[derive(Clone, Copy)]
struct XmlElement<'a>(roxmltree::Node<'a, 'a>);

impl simplecss::Element for XmlElement<'_> {
    fn parent_element(&self) -> Option<Self> {
        self.0.parent_element().map(XmlElement)
    }

    fn prev_sibling_element(&self) -> Option<Self> {
        self.0.prev_sibling_element().map(XmlElement)
    }

    fn has_local_name(&self, name: &str) -> bool {
        self.0.tag_name().name() == name
    }

    fn attribute_matches(&self, local_name: &str, operator: simplecss::AttributeOperator) -> bool {
        self.0
            .attribute(local_name)
            .is_some_and(|v| operator.matches(v))
    }

    fn pseudo_class_matches(&self, class: simplecss::PseudoClass) -> bool {
        matches!(class, simplecss::PseudoClass::FirstChild)
            && self.0.prev_sibling_element().is_none()
    }
}

/// The label of an Inkscape layer (`inkscape:groupmode="layer"`, its `inkscape:label`, else
/// its id), `None` for any other element.
fn layer_label<'a>(n: roxmltree::Node<'a, 'a>) -> Option<&'a str> {
    if n.attribute((INKSCAPE_NS, "groupmode")) != Some("layer") {
        return None;
    }
    n.attribute((INKSCAPE_NS, "label"))
        .or_else(|| n.attribute("id"))
        .filter(|l| !l.is_empty())
}

/// A solid paint as `#rrggbb` (lower case); `None` for gradients and patterns.
fn paint_color(p: &usvg::Paint) -> Option<String> {
    match p {
        usvg::Paint::Color(c) => Some(format!("#{:02x}{:02x}{:02x}", c.red, c.green, c.blue)),
        _ => None,
    }
}

/// Most skipped elements an error about a file with nothing usable names.
const NAMED_SKIPS: usize = 5;

/// The message of a file with nothing usable: how many elements were skipped, the first
/// [`NAMED_SKIPS`] with their reasons.
fn nothing_usable(skipped: &[Skipped]) -> String {
    if skipped.is_empty() {
        return "no stroked or filled path to import (the drawing is empty)".to_string();
    }
    let named: Vec<String> = skipped
        .iter()
        .take(NAMED_SKIPS)
        .map(|s| format!("{} ({})", s.id, s.reason))
        .collect();
    let more = skipped.len().saturating_sub(NAMED_SKIPS);
    format!(
        "no stroked or filled path to import: {} element(s) skipped: {}{}",
        skipped.len(),
        named.join("; "),
        if more > 0 {
            format!("; and {more} more")
        } else {
            String::new()
        }
    )
}

/// How an element of the source is named in the lists: its id, or `<tag> at line L`.
fn source_name(xml: &roxmltree::Document<'_>, n: roxmltree::Node<'_, '_>) -> String {
    match n.attribute("id") {
        Some(id) if !id.is_empty() => id.to_string(),
        _ => {
            let p = xml.text_pos_at(n.range().start);
            format!("<{}> at line {}", n.tag_name().name(), p.row)
        }
    }
}

/// Where the path data `d` stops being valid SVG path syntax, in words (`None` when it is
/// valid throughout), by svgtypes' path parser, the one usvg reads `d` with.
fn path_data_error(d: &str) -> Option<String> {
    svgtypes::PathParser::from(d)
        .find_map(Result::err)
        .map(|e| format!("is malformed ({e})"))
}

struct Ctx<'a> {
    file: &'a str,
    opts: ImportOptions,
    /// The source's elements by id (the first of each id, as `getElementById`).
    ids: HashMap<&'a str, roxmltree::Node<'a, 'a>>,
    /// Names given so far (strokes and shapes), for [`Ctx::unique`].
    names: HashSet<String>,
    /// Next suffix to try per base name, so a name repeated n times costs O(n) in all.
    suffix: HashMap<String, usize>,
    warnings: Vec<Skipped>,
    /// Ids of the usvg paths met.
    seen: HashSet<String>,
    page_width: f64,
    page_height: f64,
    /// The label of the Inkscape layer being walked.
    layer: Option<String>,
    /// The layer of the path being imported.
    path_layer: Option<String>,
    paint: paint::Paint,
    /// The document's style sheet rules (for the reasons that name a property).
    sheet: Vec<simplecss::Rule<'a>>,
    /// Product of the `opacity` of the groups being walked.
    opacity: f64,
    strokes: Vec<Stroke>,
    /// Where each stroke came from, parallel to `strokes`: for hiding it under later fills.
    stroke_src: Vec<StrokeSrc>,
    shapes: Vec<Shape>,
    skipped: Vec<Skipped>,
    counter: usize,
    max_deviation: f64,
}

/// The cleaned centre line of an imported stroke, its radii and its paint order.
struct StrokeSrc {
    seq: usize,
    pts: Vec<DVec2>,
    radii: Vec<f64>,
    closed: bool,
}

/// One node of a subpath: its index in the flattened polyline and whether it is a corner.
#[derive(Clone)]
struct Subpath {
    pts: Vec<DVec2>,
    /// Indices in `pts` of the path's nodes, with the tangent turn there (radians).
    nodes: Vec<(usize, f64)>,
    closed: bool,
    /// Path time of every point (segment index + parameter in the segment, as Inkscape's
    /// Power Stroke counts it); filled only for Power Stroke paths.
    times: Vec<f64>,
}

impl Subpath {
    /// An open subpath along the polyline `pts`, a node at every point with the turn there.
    fn polyline(pts: Vec<DVec2>) -> Self {
        let n = pts.len();
        let nodes = (0..n)
            .map(|i| {
                let a = if i > 0 && i + 1 < n {
                    turn(pts[i] - pts[i - 1], pts[i + 1] - pts[i])
                } else {
                    0.0
                };
                (i, a)
            })
            .collect();
        Subpath {
            pts,
            nodes,
            closed: false,
            times: Vec::new(),
        }
    }
}

fn turn(a: DVec2, b: DVec2) -> f64 {
    if a.length() == 0.0 || b.length() == 0.0 {
        return 0.0;
    }
    a.angle_to(b).abs()
}

use crate::geom::interop::{from_kurbo_point as dv, kurbo_point as kp};

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

impl Ctx<'_> {
    fn to_mm(&self, p: DVec2) -> DVec2 {
        DVec2::new(p.x * MM_PER_PX, (self.page_height - p.y) * MM_PER_PX)
    }

    fn group(&mut self, g: &usvg::Group) {
        let outer = self.layer.clone();
        let outer_opacity = self.opacity;
        self.opacity *= f64::from(g.opacity().get());
        if let Some(label) = self.element(g.id()).and_then(layer_label) {
            self.layer = Some(label.to_string());
        }
        for node in g.children() {
            match node {
                usvg::Node::Group(g) => self.group(g),
                usvg::Node::Path(p) => self.path(p),
                usvg::Node::Image(_) | usvg::Node::Text(_) => {}
            }
        }
        self.layer = outer;
        self.opacity = outer_opacity;
    }

    /// The name of a usvg path: its id, or `<path> #k` (k-th path in paint order), after
    /// its layer's label and a slash (`Layer 1/path12`) when it lies in an Inkscape layer.
    /// Sets the path's layer: from the source when the path has an id (usvg may fold the
    /// layer's group away), else the layer being walked.
    fn element_id(&mut self, id: &str) -> String {
        self.counter += 1;
        self.path_layer = match self.element(id) {
            Some(n) => n
                .ancestors()
                .skip(1)
                .find_map(layer_label)
                .map(str::to_string),
            None => self.layer.clone(),
        };
        let own = if id.is_empty() {
            format!("<path> #{}", self.counter - 1)
        } else {
            id.to_string()
        };
        match &self.path_layer {
            Some(l) => format!("{l}/{own}"),
            None => own,
        }
    }

    fn skip(&mut self, id: String, reason: &str) {
        self.skipped.push(Skipped {
            id,
            reason: reason.to_string(),
        });
    }

    fn warn(&mut self, id: String, message: String) {
        self.warnings.push(Skipped {
            id,
            reason: message,
        });
    }

    /// Import one path: its fill as a shape, its stroke (one per subpath) as strokes; what
    /// cannot be used is skipped with the reason, never failing the import.
    fn path(&mut self, p: &usvg::Path) {
        let id = self.element_id(p.id());
        if !p.id().is_empty() {
            self.seen.insert(p.id().to_string());
        }
        if !p.is_visible() {
            let reason = if p.fill().is_none() && p.stroke().is_none() {
                let width = self
                    .element(p.id())
                    .and_then(|n| inherited(n, "stroke-width", &self.sheet));
                match width {
                    Some(w) if w.trim().parse::<f64>().is_ok_and(|v| v <= 0.0) => format!(
                        "stroke-width {}: a stroke of zero or negative width draws nothing, \
                         and it has no fill",
                        w.trim()
                    ),
                    _ => "neither stroked nor filled".to_string(),
                }
            } else {
                "hidden (visibility: hidden)".to_string()
            };
            self.skip(id, &reason);
            return;
        }
        let power = match self.power_stroke(p.id()) {
            Ok(ps) => ps,
            Err(reason) => {
                self.skip(id, &format!("Power Stroke {reason}"));
                return;
            }
        };
        // A fully transparent fill (fill-opacity 0, or the colour `transparent`) paints
        // nothing: it is no area to engrave; nor does one fainter than MIN_INK_OPACITY.
        let group = self.opacity;
        let alpha = move |a: usvg::Opacity| f64::from(a.get()) * group;
        let fill = p
            .fill()
            .filter(|f| alpha(f.opacity()) >= paint::MIN_INK_OPACITY);
        let stroke = p
            .stroke()
            .filter(|s| alpha(s.opacity()) >= paint::MIN_INK_OPACITY);
        if power.is_none()
            && let Some(fill) = fill
        {
            let translucent = alpha(fill.opacity()) < paint::HIDE_OPACITY;
            self.fill_shape(p, &id, fill, stroke.is_some(), translucent);
        }
        let faint = |a: f64, what: &str| {
            if a <= 0.0 {
                format!("its {what} is fully transparent")
            } else {
                format!(
                    "its {what} is drawn at opacity {a:.3}, below {} (not ink)",
                    paint::MIN_INK_OPACITY
                )
            }
        };
        let stroke_width = match (&power, stroke) {
            (Some(_), _) => 0.0,
            (None, Some(stroke)) => stroke.width().get() as f64,
            (None, None) => {
                let no_fill = match p.fill() {
                    Some(f) if fill.is_none() => Some(faint(alpha(f.opacity()), "fill")),
                    _ => None,
                };
                match (p.stroke(), no_fill) {
                    (None, None) if p.fill().is_none() => {
                        self.skip(id, "neither stroked nor filled")
                    }
                    (None, Some(f)) => self.skip(id, &format!("{f} and it has no stroke")),
                    (Some(s), f) => {
                        let s = faint(alpha(s.opacity()), "stroke");
                        match f {
                            Some(f) => self.skip(id, &format!("{f}; {s}")),
                            None if p.fill().is_none() => self.skip(id, &s),
                            None => self.skip(format!("{id} (stroke)"), &s),
                        }
                    }
                    (None, None) => {}
                }
                return;
            }
        };
        let t = p.abs_transform();
        let scale = ((t.sx as f64 * t.sy as f64 - t.kx as f64 * t.ky as f64).abs()).sqrt();
        let width_mm = stroke_width * scale * MM_PER_PX;
        let widths = match self.widths(p.id()) {
            Ok(w) => w,
            Err(reason) => {
                self.skip(id, &reason);
                return;
            }
        };
        let data = match &power {
            Some(ps) => ps.centre.clone(),
            None => p.data().clone(),
        };
        // Count before work: a subpath of more segments than a stroke may have points is
        // refused before it is flattened.
        if let Some(n) = longest_subpath(&data)
            && n > MAX_ITEMS
        {
            self.skip(
                id,
                &format!(
                    "a subpath of {n} segments, more than the limit {MAX_ITEMS} points of a \
                     stroke; simplify the path"
                ),
            );
            return;
        }
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
        let mut too_many = false;
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
            if s.pts.len() > MAX_FLAT_POINTS {
                too_many = true;
                break;
            }
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
        if too_many {
            self.skip(
                id,
                &format!(
                    "a subpath flattens to more than {MAX_FLAT_POINTS} points within the \
                     tolerance; simplify the path or raise the tolerance"
                ),
            );
            return;
        }
        if subpaths.is_empty() {
            self.skip(id, "stroked path of zero length");
            return;
        }
        if power.is_some() && subpaths.len() > 1 {
            // Inkscape applies Power Stroke to the first subpath only.
            subpaths.truncate(1);
            self.skip(
                format!("{id} (subpaths after the first)"),
                "Power Stroke draws only a path's first subpath",
            );
        }
        // A Power Stroke is drawn as its filled outline: its colour is the fill's.
        let color = match &power {
            Some(_) => p.fill().and_then(|f| paint_color(f.paint())),
            None => p.stroke().and_then(|st| paint_color(st.paint())),
        };
        let many = subpaths.len() > 1;
        for (j, mut sp) in subpaths.into_iter().enumerate() {
            fit::clean(&mut sp, self.opts.tolerance);
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
            let mut fitted = self
                .fit_subpath(&name, &sp, &radii)
                .map_err(str::to_string)
                .and_then(|(s, dev)| self.usable(s).map(|s| (s, dev)));
            // Beyond the tolerance: try again with the cusps inside segments as corners.
            if fitted
                .as_ref()
                .is_ok_and(|(_, dev)| *dev > self.opts.tolerance)
            {
                let mut cusped = sp.clone();
                if fit::mark_cusps(&mut cusped, self.opts.tolerance) {
                    let again = self
                        .fit_subpath(&name, &cusped, &radii)
                        .map_err(str::to_string)
                        .and_then(|(s, dev)| self.usable(s).map(|s| (s, dev)));
                    let better = |a: &(Stroke, f64), b: &(Stroke, f64)| a.1 < b.1;
                    if let (Ok(a), Ok(b)) = (&again, &fitted)
                        && better(a, b)
                    {
                        fitted = again;
                    }
                }
            }
            match fitted {
                Ok((mut s, dev)) => {
                    self.max_deviation = self.max_deviation.max(dev);
                    s.layer = self.path_layer.clone();
                    s.color = color.clone();
                    if dev > self.opts.tolerance {
                        self.warn(
                            name,
                            format!(
                                "the stroke strays {dev:.4} mm from the drawn one, more than \
                                 the tolerance {} mm",
                                self.opts.tolerance
                            ),
                        );
                    }
                    self.strokes.push(s);
                    self.stroke_src.push(StrokeSrc {
                        seq: self.paint.seq,
                        pts: sp.pts,
                        radii,
                        closed: sp.closed,
                    });
                }
                Err(reason) => self.skip(name, &reason),
            }
        }
        self.paint.seq += 1;
    }

    /// Strokes painted before a fill that hides (see [`paint`]) lose the runs of their
    /// centre line the fill covers: a stroke covered entirely is listed as hidden, one
    /// covered in part becomes one stroke per visible run (fitted as any subpath, with the
    /// radii of the nearest point of the drawn line), with a warning; the others are kept
    /// as they were.
    fn hide_strokes(&mut self) {
        let strokes = std::mem::take(&mut self.strokes);
        let srcs = std::mem::take(&mut self.stroke_src);
        let tol = self.opts.tolerance;
        for (s, src) in strokes.into_iter().zip(srcs) {
            let mut line = src.pts.clone();
            if src.closed && line.first() != line.last() {
                line.push(line[0]);
            }
            let reach = src.radii.iter().copied().fold(0.0, f64::max);
            let Some(runs) = self.paint.visible_lines(src.seq, &line, reach) else {
                self.strokes.push(s);
                continue;
            };
            let length = |l: &[DVec2]| l.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
            let (drawn, seen) = (length(&line), runs.iter().map(|r| length(r)).sum::<f64>());
            if runs.len() == 1 && (drawn - seen).abs() <= 1e-9 * drawn.max(1.0) {
                self.strokes.push(s);
                continue;
            }
            let runs: Vec<Vec<DVec2>> = runs.into_iter().filter(|r| length(r) > tol).collect();
            if runs.is_empty() {
                self.skip(s.name, "hidden: later fills cover its line entirely");
                continue;
            }
            let drawn_line = fit::Polyline::new(&line);
            let mut radii_of_line = src.radii.clone();
            if radii_of_line.len() < line.len() {
                radii_of_line.push(src.radii[0]);
            }
            self.warn(
                s.name.clone(),
                format!(
                    "later fills hide {:.1} of its {:.1} mm: {} visible run(s) kept",
                    drawn - seen,
                    drawn,
                    runs.len()
                ),
            );
            for (k, run) in runs.into_iter().enumerate() {
                let name = if k == 0 {
                    s.name.clone()
                } else {
                    self.unique(s.name.clone())
                };
                let mut sp = Subpath::polyline(run);
                fit::clean(&mut sp, tol);
                let radii: Vec<f64> = sp
                    .pts
                    .iter()
                    .map(|&q| {
                        let (_, i, f) = drawn_line.nearest(q);
                        let r0 = radii_of_line[i];
                        let r1 = radii_of_line.get(i + 1).copied().unwrap_or(r0);
                        r0 + f * (r1 - r0)
                    })
                    .collect();
                let fitted = self
                    .fit_subpath(&name, &sp, &radii)
                    .map_err(str::to_string)
                    .and_then(|(t, dev)| self.usable(t).map(|t| (t, dev)));
                match fitted {
                    Ok((mut t, dev)) => {
                        self.max_deviation = self.max_deviation.max(dev);
                        t.layer = s.layer.clone();
                        t.color = s.color.clone();
                        self.strokes.push(t);
                    }
                    Err(reason) => {
                        self.skip(name, &format!("visible run of a hidden stroke: {reason}"))
                    }
                }
            }
        }
    }

    /// `s` if it makes a valid design on its own (split at its corners and validated as
    /// loading does), else the reason it does not.
    fn usable(&self, s: Stroke) -> Result<Stroke, String> {
        let mut d = Design::empty(self.file);
        d.stroke.push(s.clone());
        d.expand()
            .and_then(|()| super::validate(&d))
            .map_err(|e| reason_of(&e))?;
        Ok(s)
    }

    /// `name`, or `name~k` with the least k ≥ 1 not yet given when `name` is taken: O(1)
    /// amortised (a set of the names given and the next k to try per base name).
    fn unique(&mut self, name: String) -> String {
        if self.names.insert(name.clone()) {
            return name;
        }
        let mut k = self.suffix.get(&name).copied().unwrap_or(1);
        loop {
            let candidate = format!("{name}~{k}");
            k += 1;
            if self.names.insert(candidate.clone()) {
                self.suffix.insert(name, k);
                return candidate;
            }
        }
    }

    /// The source element with id `id` (usvg keeps ids but not custom or Inkscape
    /// attributes, which are read from the source).
    fn element(&self, id: &str) -> Option<roxmltree::Node<'_, '_>> {
        self.ids.get(id).copied()
    }

    /// The `data-skinpath-widths` of the element with id `id`, if any; what is wrong with
    /// it otherwise.
    fn widths(&self, id: &str) -> Result<Option<Vec<f64>>, String> {
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
                    return Err(format!(
                        "data-skinpath-widths value {tok:?} is not a positive number"
                    ));
                }
            }
        }
        if out.len() < 2 {
            return Err(format!(
                "data-skinpath-widths needs at least two widths (start and end), got {}",
                out.len()
            ));
        }
        Ok(Some(out))
    }
}
