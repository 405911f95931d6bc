//! Validation of a parsed design: every error names the file, the item and the index.

use super::error::{DesignError, ErrorKind, Item, Part};
use super::model::{Design, Fit, Operation, OperationKind, Stroke, VERSION};
use super::select::normalize_color;
use crate::spline::SplineError;
use std::collections::{BTreeSet, HashMap};

type Result<T> = std::result::Result<T, DesignError>;

/// Largest `degree` of a stroke (curves of higher degree add nothing a sign needs and make
/// every evaluation slower).
pub const MAX_DEGREE: usize = 10;
/// Largest number of disks, points or circles of one item (the skinning inserts circles
/// between them, up to 20 000 per stroke).
pub const MAX_ITEMS: usize = 10_000;
/// Largest |coordinate| and largest length value (radius, depth, width, margin, …), in
/// design units: 10 km in mm. Beyond it the geometry's size relative to the tolerances
/// exhausts double precision and every refinement budget.
pub const MAX_COORD: f64 = 1e7;
/// Smallest radius of a disk, point or circle, in design units: below it a stroke is
/// thinner than any tolerance the outline is computed to (the default ε is 0.01).
pub const MIN_RADIUS: f64 = 1e-4;
/// Two consecutive disks (points, circles) closer than this fraction of the item's size
/// (the largest |coordinate| or radius, at least 1) count as the same disk: the curve
/// between them is a span of zero length at floating-point resolution.
pub const NEAR_FRACTION: f64 = 1e-9;
/// Largest `passes` of an operation, and largest number of passes implied by
/// `depth / step_down`.
pub const MAX_PASSES: u32 = 1_000;
/// Largest `tabs.count` per contour.
pub const MAX_TABS: u32 = 100;
/// Largest feed, design units per minute (1 km/min in mm; no machine moves faster).
pub const MAX_FEED: f64 = 1e6;

/// Check everything the format promises beyond its syntax (see the module docs of
/// [`crate::design`]); `points` strokes are fitted to check that the fit succeeds.
/// Returns the first error found, in file order.
pub fn validate(d: &Design) -> Result<()> {
    let file = d.file.as_str();
    if d.version != VERSION {
        return Err(DesignError::file(
            file,
            ErrorKind::Version(d.version.to_string()),
        ));
    }
    if let Some(o) = &d.outline
        && let Some(t) = o.tolerance
        && !(t.is_finite() && t > 0.0)
    {
        return Err(DesignError::at(
            file,
            Item::Outline,
            Some(Part::Key("tolerance".into())),
            ErrorKind::Invalid(format!("tolerance {t} must be positive")),
        ));
    }
    if let Some(o) = &d.outline
        && let Some(t) = o.tolerance
        && t > MAX_COORD
    {
        return Err(DesignError::at(
            file,
            Item::Outline,
            Some(Part::Key("tolerance".into())),
            ErrorKind::Invalid(format!("tolerance {t} must be at most {MAX_COORD}")),
        ));
    }
    if d.stroke.is_empty() && d.circles.is_empty() && d.shape.is_empty() {
        return Err(DesignError::file(
            file,
            ErrorKind::Invalid(
                "the design has no [[stroke]] and no [[circles]] (nor [[shape]]): nothing to \
                 outline or cut; add at least one"
                    .into(),
            ),
        ));
    }
    super::neon::validate(d)?;
    let mut names: HashMap<&str, Item> = HashMap::new();
    for (index, s) in d.stroke.iter().enumerate() {
        let item = Item::Stroke {
            index,
            name: s.name.clone(),
        };
        check_name(file, &s.name, item.clone(), &mut names)?;
        check_color(file, &item, s.color.as_deref())?;
        check_stroke(file, s, &item)?;
        if s.points.is_some() {
            // A fit can still fail (e.g. a control disk of non-positive radius): report it
            // at load time, so a loaded design always builds.
            s.to_dbsc(file, index)?;
        }
    }
    for (index, c) in d.circles.iter().enumerate() {
        let item = Item::Circles {
            index,
            name: c.name.clone(),
        };
        check_name(file, &c.name, item.clone(), &mut names)?;
        let need = if c.closed { 3 } else { 2 };
        check_count(file, &item, "circles", c.circles.len())?;
        check_xyr_list(file, &item, &c.circles, Part::Circle, c.closed, false)?;
        if c.circles.len() < need {
            return Err(DesignError::at(
                file,
                item,
                None,
                ErrorKind::TooFew {
                    what: "circles",
                    need,
                    got: c.circles.len(),
                },
            ));
        }
    }
    for (index, sh) in d.shape.iter().enumerate() {
        let item = Item::Shape {
            index,
            name: sh.name.clone(),
        };
        check_name(file, &sh.name, item.clone(), &mut names)?;
        check_color(file, &item, sh.color.as_deref())?;
        sh.validate(file, index)?;
    }
    let tags = Known::of(d);
    for (index, op) in d.operation.iter().enumerate() {
        let item = Item::Operation {
            index,
            kind: op.kind.as_str().to_string(),
        };
        check_operation(file, op, &item, &names)?;
        check_selectors(file, op, &item, &tags)?;
    }
    super::output::validate(d)
}

/// An item's `color`, when given, is `#rrggbb` (any case).
fn check_color(file: &str, item: &Item, color: Option<&str>) -> Result<()> {
    match color {
        Some(c) if normalize_color(c).is_none() => Err(invalid(
            file,
            item,
            "color",
            format!("color {c:?} is not a colour #rrggbb (six hexadecimal digits)"),
        )),
        _ => Ok(()),
    }
}

/// The layers and colours (lower case) the design's strokes and shapes carry, sorted.
struct Known<'a> {
    layers: BTreeSet<&'a str>,
    colors: BTreeSet<String>,
}

impl<'a> Known<'a> {
    fn of(d: &'a Design) -> Self {
        let tags = d
            .stroke
            .iter()
            .map(|s| (&s.layer, &s.color))
            .chain(d.shape.iter().map(|s| (&s.layer, &s.color)));
        let mut k = Known {
            layers: BTreeSet::new(),
            colors: BTreeSet::new(),
        };
        for (l, c) in tags {
            k.layers.extend(l.as_deref());
            k.colors.extend(c.as_deref().and_then(normalize_color));
        }
        k
    }
}

/// `layers` and `colors` of an operation: non-empty lists, each colour `#rrggbb`, each
/// layer and colour one that a stroke or shape has (the error lists those the design has).
fn check_selectors(file: &str, op: &Operation, item: &Item, known: &Known) -> Result<()> {
    let list = |set: &mut dyn Iterator<Item = String>| {
        let v: Vec<String> = set.map(|s| format!("\"{s}\"")).collect();
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    if let Some(layers) = &op.layers {
        if layers.is_empty() {
            return Err(invalid(
                file,
                item,
                "layers",
                "`layers` names no layer (leave it out)".into(),
            ));
        }
        if let Some(l) = layers.iter().find(|l| !known.layers.contains(l.as_str())) {
            return Err(invalid(
                file,
                item,
                "layers",
                format!(
                    "no stroke or shape is on layer \"{l}\"; the design's layers are: {}",
                    list(&mut known.layers.iter().map(|s| s.to_string()))
                ),
            ));
        }
    }
    if let Some(colors) = &op.colors {
        if colors.is_empty() {
            return Err(invalid(
                file,
                item,
                "colors",
                "`colors` names no colour (leave it out)".into(),
            ));
        }
        for c in colors {
            let Some(n) = normalize_color(c) else {
                return Err(invalid(
                    file,
                    item,
                    "colors",
                    format!("{c:?} is not a colour #rrggbb (six hexadecimal digits)"),
                ));
            };
            if !known.colors.contains(&n) {
                return Err(invalid(
                    file,
                    item,
                    "colors",
                    format!(
                        "no stroke or shape has colour {n}; the design's colours are: {}",
                        list(&mut known.colors.iter().cloned())
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn check_name<'a>(
    file: &str,
    name: &'a str,
    item: Item,
    names: &mut HashMap<&'a str, Item>,
) -> Result<()> {
    if name.is_empty() {
        return Err(DesignError::at(
            file,
            item,
            Some(Part::Key("name".into())),
            ErrorKind::Invalid("name must not be empty".into()),
        ));
    }
    if let Some(first) = names.get(name) {
        return Err(DesignError::at(
            file,
            item,
            None,
            ErrorKind::DuplicateName {
                first: first.to_string(),
            },
        ));
    }
    names.insert(name, item);
    Ok(())
}

/// Finite numbers, positive radii, no element equal to its predecessor (cyclically when
/// `closed`); with `centres`, no centre equal to its predecessor's.
fn check_xyr_list(
    file: &str,
    item: &Item,
    list: &[[f64; 3]],
    part: fn(usize) -> Part,
    closed: bool,
    centres: bool,
) -> Result<()> {
    let err = |i: usize, kind| Err(DesignError::at(file, item.clone(), Some(part(i)), kind));
    for (i, v) in list.iter().enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            return err(i, ErrorKind::NotFinite);
        }
        if v[2] <= 0.0 {
            return err(i, ErrorKind::Radius(v[2]));
        }
        if let Some(&x) = v.iter().find(|x| x.abs() > MAX_COORD) {
            return err(
                i,
                ErrorKind::Invalid(format!(
                    "value {x} is beyond ±{MAX_COORD} design units; scale the design down"
                )),
            );
        }
        if v[2] < MIN_RADIUS {
            return err(
                i,
                ErrorKind::Invalid(format!(
                    "radius {} is below the smallest radius {MIN_RADIUS} design units",
                    v[2]
                )),
            );
        }
    }
    let same = |a: &[f64; 3], b: &[f64; 3]| {
        if centres { a[..2] == b[..2] } else { a == b }
    };
    let kind = || {
        if centres {
            ErrorKind::RepeatedCentre
        } else {
            ErrorKind::Repeated
        }
    };
    for i in 1..list.len() {
        if same(&list[i], &list[i - 1]) {
            return err(i, kind());
        }
    }
    if closed && list.len() > 1 && same(&list[0], &list[list.len() - 1]) {
        return err(0, kind());
    }
    // Near-coincident neighbours: within NEAR_FRACTION of the item's size.
    let size = list
        .iter()
        .flat_map(|v| v.iter())
        .fold(1.0f64, |m, x| m.max(x.abs()));
    let near = NEAR_FRACTION * size;
    let close = |a: &[f64; 3], b: &[f64; 3]| {
        let dc = (a[0] - b[0]).hypot(a[1] - b[1]);
        let d = if centres {
            dc
        } else {
            dc + (a[2] - b[2]).abs()
        };
        // Exact repeats are reported below as such.
        let exact = if centres { a[..2] == b[..2] } else { a == b };
        d <= near && !exact
    };
    let near_kind = |a: &[f64; 3], b: &[f64; 3]| {
        ErrorKind::Invalid(format!(
            "{} nearly repeats the one before it ({:?} vs {:?}, closer than {near:e}, \
             {NEAR_FRACTION:e} of the item's size); remove one of the two",
            if centres { "centre" } else { "disk" },
            b,
            a
        ))
    };
    for i in 1..list.len() {
        if close(&list[i], &list[i - 1]) {
            return err(i, near_kind(&list[i], &list[i - 1]));
        }
    }
    if closed && list.len() > 1 && close(&list[0], &list[list.len() - 1]) {
        return err(0, near_kind(&list[0], &list[list.len() - 1]));
    }
    Ok(())
}

/// At most [`MAX_ITEMS`] entries in one list.
fn check_count(file: &str, item: &Item, key: &str, n: usize) -> Result<()> {
    if n > MAX_ITEMS {
        return Err(invalid(
            file,
            item,
            key,
            format!("{n} entries, more than the limit {MAX_ITEMS}; split the item"),
        ));
    }
    Ok(())
}

fn invalid(file: &str, item: &Item, key: &str, msg: String) -> DesignError {
    DesignError::at(
        file,
        item.clone(),
        Some(Part::Key(key.into())),
        ErrorKind::Invalid(msg),
    )
}

fn check_stroke(file: &str, s: &Stroke, item: &Item) -> Result<()> {
    if s.degree < 1 || s.degree > MAX_DEGREE {
        return Err(invalid(
            file,
            item,
            "degree",
            format!(
                "degree = {} is outside 1..={MAX_DEGREE} (3, the default, suits most strokes)",
                s.degree
            ),
        ));
    }
    // With `knots` the degree is fixed; otherwise it is lowered for short lists
    // (`Stroke::effective_degree`), so two disks (three closed) suffice.
    let min_count = |closed: bool| if closed { 3 } else { 2 };
    let need = if s.knots.is_some() {
        s.degree + 1
    } else {
        min_count(s.closed)
    };
    match (&s.disks, &s.points) {
        (Some(_), Some(_)) => {
            return Err(DesignError::at(
                file,
                item.clone(),
                None,
                ErrorKind::Invalid("give either `disks` or `points`, not both".into()),
            ));
        }
        (None, None) => {
            return Err(DesignError::at(
                file,
                item.clone(),
                None,
                ErrorKind::Invalid("needs `disks` (control disks) or `points` to fit".into()),
            ));
        }
        (Some(disks), None) => {
            for key in ["fit", "parametrization", "control_disks"] {
                let set = match key {
                    "fit" => s.fit.is_some(),
                    "parametrization" => s.parametrization.is_some(),
                    _ => s.control_disks.is_some(),
                };
                if set {
                    return Err(invalid(
                        file,
                        item,
                        key,
                        format!("`{key}` applies to `points` strokes only"),
                    ));
                }
            }
            check_count(file, item, "disks", disks.len())?;
            check_xyr_list(file, item, disks, Part::Disk, s.closed, false)?;
            if disks.len() < need {
                return Err(DesignError::at(
                    file,
                    item.clone(),
                    None,
                    ErrorKind::TooFew {
                        what: "disks",
                        need,
                        got: disks.len(),
                    },
                ));
            }
            if let Some(k) = &s.knots {
                check_knots(file, item, k, s.degree, disks.len(), s.closed)?;
            }
        }
        (None, Some(points)) => {
            if s.knots.is_some() {
                return Err(invalid(
                    file,
                    item,
                    "knots",
                    "`knots` applies to `disks` strokes; a fit chooses its own".into(),
                ));
            }
            check_count(file, item, "points", points.len())?;
            check_xyr_list(file, item, points, Part::Point, s.closed, true)?;
            if points.len() < need {
                return Err(DesignError::at(
                    file,
                    item.clone(),
                    None,
                    ErrorKind::TooFew {
                        what: "points",
                        need,
                        got: points.len(),
                    },
                ));
            }
            match (s.fit.unwrap_or_default(), s.control_disks) {
                (Fit::Interpolate, Some(_)) => {
                    return Err(invalid(
                        file,
                        item,
                        "control_disks",
                        "`control_disks` applies to fit = \"approximate\" only".into(),
                    ));
                }
                (Fit::Approximate, None) => {
                    return Err(invalid(
                        file,
                        item,
                        "control_disks",
                        "fit = \"approximate\" needs `control_disks`".into(),
                    ));
                }
                (Fit::Approximate, Some(n)) if n < need || n > points.len() => {
                    return Err(invalid(
                        file,
                        item,
                        "control_disks",
                        format!(
                            "control_disks = {n} must lie between {need} and the number of \
                             points {} (the degree is lowered to control_disks − 1 when \
                             needed)",
                            points.len()
                        ),
                    ));
                }
                _ => {}
            }
        }
    }
    let expected = s.control_disk_count();
    for (channel, values) in s.attributes.channels() {
        let at = |index: usize| Part::Attribute {
            channel: channel.to_string(),
            index,
        };
        if values.len() != expected {
            return Err(DesignError::at(
                file,
                item.clone(),
                Some(Part::Key(format!("attributes.{channel}"))),
                ErrorKind::AttributeCount {
                    got: values.len(),
                    expected,
                },
            ));
        }
        for (i, &v) in values.iter().enumerate() {
            let bad = if !v.is_finite() {
                Some(ErrorKind::NotFinite)
            } else {
                match channel {
                    "power" if !(0.0..=100.0).contains(&v) => Some(ErrorKind::Invalid(format!(
                        "power {v} outside 0..=100 (percent)"
                    ))),
                    "depth" if !(0.0..=MAX_COORD).contains(&v) => Some(ErrorKind::Invalid(
                        format!("depth {v} outside 0..={MAX_COORD} (design units)"),
                    )),
                    "feed" if !(v > 0.0 && v <= MAX_FEED) => Some(ErrorKind::Invalid(format!(
                        "feed {v} outside (0, {MAX_FEED}] (design units per minute)"
                    ))),
                    _ => None,
                }
            };
            if let Some(kind) = bad {
                return Err(DesignError::at(file, item.clone(), Some(at(i)), kind));
            }
        }
    }
    Ok(())
}

/// Open strokes: the full knot vector (n + p + 1 knots, finite, non-decreasing, multiplicity
/// at most p + 1, non-empty domain). Closed strokes: the n + 1 breakpoints of one period,
/// finite and strictly increasing.
fn check_knots(
    file: &str,
    item: &Item,
    knots: &[f64],
    degree: usize,
    n: usize,
    closed: bool,
) -> Result<()> {
    let at = |part: Option<Part>, kind| Err(DesignError::at(file, item.clone(), part, kind));
    for (i, k) in knots.iter().enumerate() {
        if !k.is_finite() {
            return at(Some(Part::Knot(i)), ErrorKind::NotFinite);
        }
    }
    if closed {
        if knots.len() != n + 1 {
            return at(
                Some(Part::Key("knots".into())),
                ErrorKind::KnotCount {
                    got: knots.len(),
                    expected: n + 1,
                },
            );
        }
        for i in 1..knots.len() {
            if knots[i] <= knots[i - 1] {
                return at(
                    Some(Part::Knot(i)),
                    ErrorKind::KnotDecreasing {
                        prev: knots[i - 1],
                        next: knots[i],
                    },
                );
            }
        }
        return Ok(());
    }
    match crate::spline::knots::validate(knots, degree, n) {
        Ok(()) => Ok(()),
        Err(SplineError::KnotCount { got, expected }) => at(
            Some(Part::Key("knots".into())),
            ErrorKind::KnotCount { got, expected },
        ),
        Err(SplineError::KnotDecreasing { index, prev, next }) => at(
            Some(Part::Knot(index)),
            ErrorKind::KnotDecreasing { prev, next },
        ),
        Err(SplineError::KnotMultiplicity { value, mult, max }) => {
            let first = knots.iter().position(|&k| k == value).unwrap_or(0);
            at(
                Some(Part::Knot(first)),
                ErrorKind::Knots(format!(
                    "knot {value} repeated {mult} times, more than degree + 1 = {max}"
                )),
            )
        }
        Err(e) => at(
            Some(Part::Key("knots".into())),
            ErrorKind::Knots(e.to_string()),
        ),
    }
}

/// Which operation kinds a per-kind key applies to.
fn applies(key: &str) -> &'static [OperationKind] {
    use OperationKind::*;
    match key {
        "side" => &[Profile],
        "width" => &[Channel],
        "margin" | "min_inner_radius" | "bridge_width" | "mounting_holes" | "corner_radius" => {
            &[Backboard]
        }
        "diameter" | "at" => &[Holes],
        "pattern" | "spacing" | "cross_hatch" | "alternate" => &[Fill],
        "angle" => &[Fill, Vcarve],
        "max_depth" => &[Vcarve],
        "boundaries" => &[Line],
        // Tabs hold a part cut free; the skin route is chosen for outline cuts.
        "tabs" | "method" => &[Profile, Backboard],
        // A line has no waste side to lead in from.
        "lead_in" => &[Profile, Channel, Backboard, Holes, Fill, Vcarve],
        _ => &[Profile, Channel, Backboard, Holes, Fill, Vcarve, Line],
    }
}

fn check_operation(
    file: &str,
    op: &Operation,
    item: &Item,
    names: &HashMap<&str, Item>,
) -> Result<()> {
    let set = [
        ("side", op.side.is_some()),
        ("width", op.width.is_some()),
        ("margin", op.margin.is_some()),
        ("min_inner_radius", op.min_inner_radius.is_some()),
        ("bridge_width", op.bridge_width.is_some()),
        ("mounting_holes", op.mounting_holes.is_some()),
        ("corner_radius", op.corner_radius.is_some()),
        ("diameter", op.diameter.is_some()),
        ("at", op.at.is_some()),
        ("pattern", op.pattern.is_some()),
        ("spacing", op.spacing.is_some()),
        ("cross_hatch", op.cross_hatch.is_some()),
        ("alternate", op.alternate.is_some()),
        ("angle", op.angle.is_some()),
        ("max_depth", op.max_depth.is_some()),
        ("tabs", op.tabs.is_some()),
        ("method", op.method.is_some()),
        ("lead_in", op.lead_in.is_some()),
        ("boundaries", op.boundaries.is_some()),
    ];
    for (key, present) in set {
        if present && !applies(key).contains(&op.kind) {
            return Err(invalid(
                file,
                item,
                key,
                format!("`{key}` does not apply to a {} operation", op.kind.as_str()),
            ));
        }
    }
    let required: &[(&str, bool)] = match op.kind {
        OperationKind::Channel => &[("width", op.width.is_some())],
        OperationKind::Holes => &[("diameter", op.diameter.is_some())],
        OperationKind::Fill => &[("spacing", op.spacing.is_some())],
        OperationKind::Vcarve => &[("angle", op.angle.is_some())],
        _ => &[],
    };
    for &(key, present) in required {
        if !present {
            return Err(invalid(
                file,
                item,
                key,
                format!("a {} operation needs `{key}`", op.kind.as_str()),
            ));
        }
    }
    // Upper limits: feeds MAX_FEED, power 100 %, lengths MAX_COORD.
    let limit = |key: &str| match key {
        "feed" => MAX_FEED,
        "power" => 100.0,
        _ => MAX_COORD,
    };
    let positive = |key: &str, v: Option<f64>, allow_zero: bool| -> Result<()> {
        match v {
            Some(x) if !x.is_finite() => Err(DesignError::at(
                file,
                item.clone(),
                Some(Part::Key(key.into())),
                ErrorKind::NotFinite,
            )),
            Some(x) if x < 0.0 || (x == 0.0 && !allow_zero) => Err(invalid(
                file,
                item,
                key,
                format!(
                    "{key} = {x} must be {}",
                    if allow_zero {
                        "non-negative"
                    } else {
                        "positive"
                    }
                ),
            )),
            Some(x) if x > limit(key) => Err(invalid(
                file,
                item,
                key,
                format!("{key} = {x} is above the limit {}", limit(key)),
            )),
            _ => Ok(()),
        }
    };
    positive("step_down", op.step_down, false)?;
    positive("depth", op.depth, false)?;
    positive("feed", op.feed, false)?;
    positive("power", op.power, true)?;
    positive("lead_in", op.lead_in, true)?;
    positive("width", op.width, false)?;
    positive("margin", op.margin, false)?;
    positive("min_inner_radius", op.min_inner_radius, true)?;
    positive("bridge_width", op.bridge_width, true)?;
    positive("corner_radius", op.corner_radius, true)?;
    positive("diameter", op.diameter, false)?;
    positive("spacing", op.spacing, false)?;
    positive("max_depth", op.max_depth, false)?;
    if let Some(p) = op.passes
        && !(1..=MAX_PASSES).contains(&p)
    {
        return Err(invalid(
            file,
            item,
            "passes",
            format!("passes = {p} outside 1..={MAX_PASSES}"),
        ));
    }
    if let (Some(depth), Some(step)) = (op.depth, op.step_down)
        && depth / step > f64::from(MAX_PASSES)
    {
        return Err(invalid(
            file,
            item,
            "step_down",
            format!(
                "depth {depth} / step_down {step} asks for more than {MAX_PASSES} passes; \
                 raise step_down"
            ),
        ));
    }
    if let Some(a) = op.angle {
        let ok = match op.kind {
            OperationKind::Vcarve => a > 0.0 && a < 180.0,
            _ => a.is_finite() && a.abs() <= 360.0,
        };
        if !ok {
            return Err(invalid(
                file,
                item,
                "angle",
                format!(
                    "angle = {a} out of range (vcarve: 0 < angle < 180 degrees; fill: \
                     -360..=360 degrees)"
                ),
            ));
        }
    }
    if let Some(t) = &op.tabs {
        let len_ok = |v: f64| v.is_finite() && v > 0.0 && v <= MAX_COORD;
        let bad = if !(1..=MAX_TABS).contains(&t.count) {
            Some((
                "tabs.count",
                format!("count = {} outside 1..={MAX_TABS}", t.count),
            ))
        } else if !len_ok(t.width) {
            Some((
                "tabs.width",
                format!("width = {} outside (0, {MAX_COORD}]", t.width),
            ))
        } else if !len_ok(t.height) {
            Some((
                "tabs.height",
                format!("height = {} outside (0, {MAX_COORD}]", t.height),
            ))
        } else {
            None
        };
        if let Some((key, msg)) = bad {
            return Err(invalid(file, item, key, msg));
        }
    }
    if let Some(m) = &op.mounting_holes {
        let len_ok = |v: f64| v.is_finite() && v > 0.0 && v <= MAX_COORD;
        let bad = if !(1..=MAX_TABS).contains(&m.count) {
            Some((
                "mounting_holes.count",
                format!("count = {} outside 1..={MAX_TABS}", m.count),
            ))
        } else if !len_ok(m.diameter) {
            Some((
                "mounting_holes.diameter",
                format!("diameter = {} outside (0, {MAX_COORD}]", m.diameter),
            ))
        } else {
            m.inset.filter(|&v| !len_ok(v)).map(|inset| {
                (
                    "mounting_holes.inset",
                    format!("inset = {inset} outside (0, {MAX_COORD}]"),
                )
            })
        };
        if let Some((key, msg)) = bad {
            return Err(invalid(file, item, key, msg));
        }
    }
    if let Some(list) = &op.strokes {
        if list.is_empty() {
            return Err(invalid(
                file,
                item,
                "strokes",
                "`strokes` names no stroke (leave it out for all strokes)".into(),
            ));
        }
        for name in list {
            if !names.contains_key(name.as_str()) {
                return Err(DesignError::at(
                    file,
                    item.clone(),
                    None,
                    ErrorKind::UnknownStroke(name.clone()),
                ));
            }
        }
    }
    Ok(())
}
