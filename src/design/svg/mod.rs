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
use std::collections::{HashMap, HashSet};

mod fill;
mod fit;
mod paint;
mod power;
mod segment;
mod source;
mod walk;
pub(crate) mod xml;

use paint::paint_color;
use segment::{flatten_segment, longest_subpath, segment_point, segment_time, tangents, turn};
use source::{inherited, layer_label, path_data_error, source_name, style_rules};

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
#[non_exhaustive]
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

impl ImportOptions {
    /// These options with the fitting tolerance `tolerance` (mm).
    #[must_use]
    pub fn with_tolerance(self, tolerance: f64) -> Self {
        ImportOptions { tolerance, ..self }
    }

    /// These options with the corner angle `degrees`.
    #[must_use]
    pub fn with_corner_angle(self, degrees: f64) -> Self {
        ImportOptions {
            corner_angle: degrees,
            ..self
        }
    }
}

/// An element that was not imported.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Skipped {
    /// The element's id, or `<tag> #k` (k-th such element in document order) without one.
    pub id: String,
    /// Why it was not imported, in words (e.g. "raster images are not imported").
    pub reason: String,
}

/// The result of [`import`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
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
/// and validation), with what the import left out or caught: one line per skipped element
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

/// What is wrong with an item, without the file and item (the skip list names those).
fn reason_of(e: &DesignError) -> String {
    match &e.part {
        Some(p) => format!("{p}: {}", e.kind),
        None => e.kind.to_string(),
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
