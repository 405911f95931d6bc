//! Which items an operation applies to (`strokes`, `layers` and `colors` selectors), and the
//! operations a design without any is given ([`default_operations`]).
//!
//! Selection: an operation with none of `strokes`, `layers`, `colors` applies to every item;
//! otherwise an item is selected when any given selector names it: its name is in
//! `strokes`, its `layer` is in `layers`, or its `color` is in `colors` (colours compared
//! case-insensitively as `#rrggbb`). Circle sequences and the strokes a `[[text]]` lays out
//! have no layer or colour: only `strokes` (or no selector) selects them.

use super::model::{Design, LineBoundaries, Operation, OperationKind};
use std::collections::{BTreeMap, HashMap, HashSet};

/// Width (mm) at or below which a stroke is a hairline whatever the tool: a line drawn to be
/// followed, not a shape whose two edges are cut. SVG's default `stroke-width` is 1 user
/// unit, 1 mm in a document drawn in millimetres (svg2gcode's `shapes.svg` leaves it unset
/// on two of its seven outlines); pen-plotter art and Inkscape's hairlines (0.26 mm)
/// are thinner. Cutting both edges of a stroke this thin leaves a sliver narrower than a
/// millimetre between two kerfs.
pub const HAIRLINE_MM: f64 = 1.0;

/// Relative slack of the hairline test: widths read from an SVG pass through f32
/// (≈ 6·10⁻⁸ relative precision) and transforms, so a 1 mm stroke may come out a hair
/// wider.
pub const HAIRLINE_SLACK: f64 = 1e-6;

/// `#rrggbb` in lower case, or `None` when `s` is not `#` and six hexadecimal digits (any
/// case).
#[must_use]
pub fn normalize_color(s: &str) -> Option<String> {
    let hex = s.strip_prefix('#')?;
    (hex.len() == 6 && hex.bytes().all(|b| b.is_ascii_hexdigit()))
        .then(|| format!("#{}", hex.to_ascii_lowercase()))
}

/// The selectors of one operation, ready to test items against.
#[derive(Clone, Debug)]
pub struct Selection<'a> {
    /// No selector given: every item.
    all: bool,
    names: HashSet<&'a str>,
    layers: HashSet<&'a str>,
    /// Lower case.
    colors: HashSet<String>,
}

impl<'a> Selection<'a> {
    /// The selectors of `op`.
    pub fn of(op: &'a Operation) -> Self {
        let set = |v: &'a Option<Vec<String>>| -> HashSet<&'a str> {
            v.iter().flatten().map(String::as_str).collect()
        };
        Selection {
            all: op.strokes.is_none() && op.layers.is_none() && op.colors.is_none(),
            names: set(&op.strokes),
            layers: set(&op.layers),
            colors: op
                .colors
                .iter()
                .flatten()
                .map(|c| c.to_ascii_lowercase())
                .collect(),
        }
    }

    /// Whether the item named `name` with `tags` (its layer and colour) is selected.
    pub fn selects(&self, name: &str, tags: Tags<'_>) -> bool {
        self.all
            || self.names.contains(name)
            || tags.layer.is_some_and(|l| self.layers.contains(l))
            || tags
                .color
                .is_some_and(|c| self.colors.contains(&c.to_ascii_lowercase()))
    }
}

/// The layer and colour of an item (none for circle sequences).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Tags<'a> {
    /// `layer`.
    pub layer: Option<&'a str>,
    /// `color`.
    pub color: Option<&'a str>,
}

impl Design {
    /// The layer and colour of every stroke and shape, by name.
    pub fn tags(&self) -> HashMap<&str, Tags<'_>> {
        let strokes = self.stroke.iter().map(|s| {
            let t = Tags {
                layer: s.layer.as_deref(),
                color: s.color.as_deref(),
            };
            (s.name.as_str(), t)
        });
        let shapes = self.shape.iter().map(|s| {
            let t = Tags {
                layer: s.layer.as_deref(),
                color: s.color.as_deref(),
            };
            (s.name.as_str(), t)
        });
        strokes.chain(shapes).collect()
    }

    /// Writes every valid colour of items and `colors` selectors as lower-case `#rrggbb`
    /// ([`normalize_color`]); loading does this after validation.
    pub fn normalize_colors(&mut self) {
        let fix = |c: &mut String| {
            if let Some(n) = normalize_color(c) {
                *c = n;
            }
        };
        self.stroke
            .iter_mut()
            .filter_map(|s| s.color.as_mut())
            .for_each(fix);
        self.shape
            .iter_mut()
            .filter_map(|s| s.color.as_mut())
            .for_each(fix);
        for op in &mut self.operation {
            op.colors.iter_mut().flatten().for_each(fix);
        }
        for o in &mut self.output {
            o.colors.iter_mut().flatten().for_each(fix);
        }
    }

    /// Whether some stroke or shape has a `layer` or `color`: the design is a drawing
    /// (an SVG import writes both), whose items [`default_operations`] cuts one by one.
    pub fn is_tagged(&self) -> bool {
        let tagged = |l: &Option<String>, c: &Option<String>| l.is_some() || c.is_some();
        self.stroke.iter().any(|s| tagged(&s.layer, &s.color))
            || self.shape.iter().any(|s| tagged(&s.layer, &s.color))
    }
}

/// The operation kind [`default_operations`] gives the stroke `s`: `line` when it is a
/// hairline (its width 2·max rᵢ over its listed disks or points is at most `hairline`, with
/// [`HAIRLINE_SLACK`]), else `profile`. The radius of a disk B-spline is a convex combination of its control
/// radii (B-spline basis: Nᵢ ≥ 0, Σ Nᵢ = 1), so it never exceeds their largest.
pub fn stroke_default_kind(s: &super::model::Stroke, hairline: f64) -> OperationKind {
    let r = s
        .disks
        .iter()
        .chain(s.points.iter())
        .flatten()
        .map(|d| d[2])
        .fold(0.0f64, f64::max);
    if 2.0 * r <= hairline * (1.0 + HAIRLINE_SLACK) {
        OperationKind::Line
    } else {
        OperationKind::Profile
    }
}

/// The operations a design without any is cut with, chosen per item so that a user can read
/// and edit them (`import` writes them into the design; `build` uses them for a drawing
/// without operations):
/// - strokes of width at most `hairline` (design units; see [`HAIRLINE_MM`] and
///   `stroke_default_kind`) → `line` along the spine, cut once;
/// - wider strokes, shapes (outer boundaries and holes) and circle sequences → `profile`
///   (touching items are cut around their union, as every profile does).
///
/// Lines are grouped by layer and colour; all profiled items are one group (touching items
/// must be cut around their union, and two profiles of overlapping items would cross).
/// When profiled items of different colours may meet (their boxes do), a `line` operation with
/// `boundaries = "inner"` and the same selector follows the profile: the visible
/// boundaries between differently coloured areas inside the union (a logo's inner star
/// where gold meets black) are cut once each along the boundary
/// (`toolpath::inks`); the profile cuts the union's outside and holes.
/// Groups come in order of first appearance; each is one operation selecting exactly its
/// items: by `layers = [...]` when the group is every item of those layers, else by
/// `colors = [...]` when it is every item of those colours, else by `strokes = [...]` (no
/// selector at all when it is every item of the design). No item is
/// selected twice, but for the inner boundaries' line beside its profile. Operation settings (depth, power, feed) are left unset: the build's
/// defaults apply, and a router needs `depth` on profiles. Texts must have been laid out
/// (a loaded design has).
#[must_use]
pub fn default_operations(design: &Design, hairline: f64) -> Vec<Operation> {
    // (name, tags, kind) of every item in design order, and each item's box.
    let mut items: Vec<(&str, Tags<'_>, OperationKind)> = Vec::new();
    let mut boxes: HashMap<&str, Box2> = HashMap::new();
    for s in &design.stroke {
        let tags = Tags {
            layer: s.layer.as_deref(),
            color: s.color.as_deref(),
        };
        items.push((&s.name, tags, stroke_default_kind(s, hairline)));
        boxes.insert(
            &s.name,
            disks_box(s.disks.iter().chain(s.points.iter()).flatten()),
        );
    }
    for c in &design.circles {
        items.push((&c.name, Tags::default(), OperationKind::Profile));
        boxes.insert(&c.name, disks_box(c.circles.iter()));
    }
    for s in &design.shape {
        let tags = Tags {
            layer: s.layer.as_deref(),
            color: s.color.as_deref(),
        };
        items.push((&s.name, tags, OperationKind::Profile));
        let corners = s.contours.iter().flatten().map(|p| [p[0], p[1], 0.0]);
        boxes.insert(&s.name, disks_box(corners.collect::<Vec<_>>().iter()));
    }
    let lower = |c: Option<&str>| c.map(str::to_ascii_lowercase);
    // Groups keyed by (kind, layer, colour), in order of first appearance. Profiled items
    // are one group whatever their layer and colour: touching items must be cut around
    // their union, which only one operation does (two profiles of overlapping items cross).
    type Key<'k> = (OperationKind, Option<&'k str>, Option<String>);
    let mut order: Vec<Key<'_>> = Vec::new();
    let mut groups: HashMap<Key<'_>, Vec<(&str, Tags<'_>)>> = HashMap::new();
    let mut per_layer: BTreeMap<&str, usize> = BTreeMap::new();
    let mut per_color: BTreeMap<String, usize> = BTreeMap::new();
    for &(name, tags, kind) in &items {
        let key = match kind {
            OperationKind::Line => (kind, tags.layer, lower(tags.color)),
            _ => (kind, None, None),
        };
        if let Some(l) = tags.layer {
            *per_layer.entry(l).or_default() += 1;
        }
        if let Some(c) = lower(tags.color) {
            *per_color.entry(c).or_default() += 1;
        }
        groups
            .entry(key.clone())
            .or_insert_with(|| {
                order.push(key);
                Vec::new()
            })
            .push((name, tags));
    }
    let mut out = Vec::new();
    for key in order {
        let members = &groups[&key];
        let mut op = Operation::new(key.0);
        if members.len() == items.len() {
            // Every item: no selector.
        } else if let Some(layers) = whole(
            members,
            |t| t.layer.map(str::to_string),
            |l| per_layer.get(l.as_str()).copied(),
        ) {
            op.layers = Some(layers);
        } else if let Some(colors) =
            whole(members, |t| lower(t.color), |c| per_color.get(c).copied())
        {
            op.colors = Some(colors);
        } else {
            op.strokes = Some(members.iter().map(|(n, _)| n.to_string()).collect());
        }
        // Where profiled items of several inks meet, the boundaries between them are
        // cut as lines, once each; the profile cuts the outside of their union.
        let inner = (key.0 == OperationKind::Profile && inks_meet(members, &boxes)).then(|| {
            let mut line = op.clone();
            line.kind = OperationKind::Line;
            line.boundaries = Some(LineBoundaries::Inner);
            line
        });
        out.push(op);
        out.extend(inner);
    }
    out
}

/// An axis-aligned box: (min x, min y, max x, max y).
type Box2 = [f64; 4];

/// The box of disks `[x, y, r]`: it holds a disk B-spline whose control disks they are (the
/// centre curve lies in the convex hull of the control points, and its radius never exceeds
/// the largest control radius), a circle sequence, or a polygon (r = 0).
fn disks_box<'a>(disks: impl Iterator<Item = &'a [f64; 3]>) -> Box2 {
    disks.fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, d| {
            let r = d[2].abs();
            [
                b[0].min(d[0] - r),
                b[1].min(d[1] - r),
                b[2].max(d[0] + r),
                b[3].max(d[1] + r),
            ]
        },
    )
}

/// Whether two of `members` of different inks (colours, compared case-insensitively; no
/// colour is one ink of its own) have boxes that meet: only then can a boundary between two
/// inks lie inside their union. Sweep over the boxes sorted by their left side.
fn inks_meet(members: &[(&str, Tags<'_>)], boxes: &HashMap<&str, Box2>) -> bool {
    let mut b: Vec<(Box2, Option<String>)> = members
        .iter()
        .filter_map(|(n, t)| Some((*boxes.get(n)?, t.color.map(str::to_ascii_lowercase))))
        .collect();
    b.sort_by(|x, y| x.0[0].total_cmp(&y.0[0]));
    (0..b.len()).any(|i| {
        (b[i + 1..].iter())
            .take_while(|o| o.0[0] <= b[i].0[2])
            .any(|o| o.1 != b[i].1 && o.0[1] <= b[i].0[3] && b[i].0[1] <= o.0[3])
    })
}

/// The values of `tag` (layers or colours, in order of first appearance) when `members`
/// are exactly every item carrying those values (`count` of each value in the design), so
/// that a selector by them picks the members and nothing else; `None` when a member has
/// no such tag or the values also tag other items.
fn whole<'a>(
    members: &[(&str, Tags<'a>)],
    tag: impl Fn(Tags<'a>) -> Option<String>,
    count: impl Fn(&String) -> Option<usize>,
) -> Option<Vec<String>> {
    let mut values: Vec<String> = Vec::new();
    for &(_, t) in members {
        let v = tag(t)?;
        if !values.contains(&v) {
            values.push(v);
        }
    }
    let total: usize = values.iter().map(|v| count(v).unwrap_or(0)).sum();
    (total == members.len()).then_some(values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::{Format, from_str};

    const FILE: &str = "art.toml";

    /// Strokes: "thin" (0.3 mm wide, layer "ink", red), "wide" (4 mm, layer "ink", red),
    /// "blue" (0.2 mm, layer "marks", blue), "plain" (0.4 mm, no tags); shape "plate"
    /// (layer "cut", black); circle sequence "dots". `{OPS}` is replaced by operations.
    const ART: &str = r##"version = 1
[[stroke]]
name = "thin"
layer = "ink"
color = "#FF0000"
disks = [[0.0, 0.0, 0.15], [10.0, 5.0, 0.1], [20.0, 0.0, 0.15]]
[[stroke]]
name = "wide"
layer = "ink"
color = "#ff0000"
disks = [[0.0, 10.0, 2.0], [10.0, 15.0, 1.5], [20.0, 10.0, 2.0]]
[[stroke]]
name = "blue"
layer = "marks"
color = "#0000ff"
disks = [[0.0, 20.0, 0.1], [20.0, 20.0, 0.1]]
[[stroke]]
name = "plain"
disks = [[0.0, 30.0, 0.2], [20.0, 30.0, 0.2]]
[[circles]]
name = "dots"
circles = [[40.0, 0.0, 2.0], [46.0, 1.0, 2.5], [52.0, 0.0, 2.0]]
[[shape]]
name = "plate"
layer = "cut"
color = "#000000"
contours = [[[30.0, 20.0], [40.0, 20.0], [40.0, 30.0], [30.0, 30.0]]]
{OPS}"##;

    fn load(ops: &str) -> Result<Design, String> {
        from_str(&ART.replace("{OPS}", ops), Format::Toml, FILE).map_err(|e| e.to_string())
    }

    /// Names of the items `op` selects, in the order strokes, circle sequences, shapes.
    fn selected(d: &Design, op: &Operation) -> Vec<String> {
        let tags = d.tags();
        let sel = Selection::of(op);
        let names = (d.stroke.iter().map(|s| &s.name))
            .chain(d.circles.iter().map(|c| &c.name))
            .chain(d.shape.iter().map(|s| &s.name));
        names
            .filter(|n| sel.selects(n, tags.get(n.as_str()).copied().unwrap_or_default()))
            .cloned()
            .collect()
    }

    #[test]
    fn colours_normalise_to_lower_case_or_are_refused() {
        assert_eq!(normalize_color("#FFa0B1").as_deref(), Some("#ffa0b1"));
        for bad in ["ff0000", "#ff000", "#ff00000", "#gg0000", "red", "#fff", ""] {
            assert_eq!(normalize_color(bad), None, "{bad}");
        }
        // Loading writes lower case on items and selectors.
        let d = load("[[operation]]\nkind = \"line\"\ncolors = [\"#0000FF\"]\n").unwrap();
        assert_eq!(d.stroke[0].color.as_deref(), Some("#ff0000"));
        assert_eq!(d.operation[0].colors, Some(vec!["#0000ff".to_string()]));
    }

    #[test]
    fn selectors_select_what_any_of_them_names() {
        let d = load("").unwrap();
        let mut op = Operation::new(OperationKind::Line);
        assert_eq!(
            selected(&d, &op),
            ["thin", "wide", "blue", "plain", "dots", "plate"]
        );
        op.layers = Some(vec!["ink".into()]);
        assert_eq!(selected(&d, &op), ["thin", "wide"]);
        op.colors = Some(vec!["#0000FF".into()]);
        assert_eq!(selected(&d, &op), ["thin", "wide", "blue"]);
        op.strokes = Some(vec!["dots".into()]);
        assert_eq!(selected(&d, &op), ["thin", "wide", "blue", "dots"]);
        let mut by_color = Operation::new(OperationKind::Profile);
        by_color.colors = Some(vec!["#000000".into()]);
        assert_eq!(selected(&d, &by_color), ["plate"]);
    }

    #[test]
    fn unknown_or_malformed_selectors_and_colours_are_errors() {
        let msg =
            load("[[operation]]\nkind = \"line\"\nlayers = [\"ink\", \"Ink\"]\n").unwrap_err();
        assert!(msg.starts_with(FILE), "{msg}");
        assert!(msg.contains("operation 0 (line), key `layers`"), "{msg}");
        assert!(msg.contains("\"Ink\""), "{msg}");
        assert!(
            msg.contains("the design's layers are: \"cut\", \"ink\", \"marks\""),
            "{msg}"
        );
        let msg = load("[[operation]]\nkind = \"line\"\ncolors = [\"#00ff00\"]\n").unwrap_err();
        assert!(msg.contains("operation 0 (line), key `colors`"), "{msg}");
        assert!(
            msg.contains("the design's colours are: \"#000000\", \"#0000ff\", \"#ff0000\""),
            "{msg}"
        );
        let msg = load("[[operation]]\nkind = \"line\"\ncolors = [\"blue\"]\n").unwrap_err();
        assert!(msg.contains("not a colour #rrggbb"), "{msg}");
        for key in ["layers", "colors"] {
            let msg = load(&format!("[[operation]]\nkind = \"line\"\n{key} = []\n")).unwrap_err();
            assert!(msg.contains(&format!("key `{key}`")), "{msg}");
        }
        let bad = ART.replace("color = \"#0000ff\"", "color = \"#00f\"");
        let msg = from_str(&bad.replace("{OPS}", ""), Format::Toml, FILE)
            .unwrap_err()
            .to_string();
        assert!(msg.contains("stroke 2 \"blue\", key `color`"), "{msg}");
    }

    #[test]
    fn line_operations_take_only_their_keys() {
        let ok = "[[operation]]\nkind = \"line\"\npower = 40\nfeed = 900\ndepth = 0.3\n\
                  passes = 2\nstep_down = 0.1\nair_assist = true\nstrokes = [\"thin\"]\n";
        assert!(load(ok).is_ok());
        for key in [
            "lead_in = 1.0",
            "tabs = { count = 2, width = 2, height = 1 }",
            "side = \"on\"",
            "method = \"re\"",
            "width = 2.0",
            "spacing = 1.0",
        ] {
            let msg = load(&format!("[[operation]]\nkind = \"line\"\n{key}\n")).unwrap_err();
            let name = key.split(' ').next().unwrap_or_default();
            assert!(
                msg.contains(&format!("operation 0 (line), key `{name}`"))
                    && msg.contains("does not apply"),
                "{msg}"
            );
        }
    }

    /// Every item is selected by exactly one default operation, of the kind its width
    /// asks for; selectors are the layer or colour where the group is all of it.
    #[test]
    fn default_operations_select_every_item_once() {
        let d = load("").unwrap();
        let ops = default_operations(&d, HAIRLINE_MM);
        let kinds: Vec<&str> = ops.iter().map(|o| o.kind.as_str()).collect();
        // The profiled items have three inks (red, none, black) but lie apart: no line
        // along boundaries between inks.
        assert_eq!(kinds, ["line", "profile", "line", "line"]);
        // "thin" and "wide" share layer and colour but not kind: named; "blue" is all of
        // layer "marks"; the profiled items ("wide", "dots", "plate") are one operation.
        assert_eq!(ops[0].strokes, Some(vec!["thin".to_string()]));
        assert_eq!(
            ops[1].strokes,
            Some(vec![
                "wide".to_string(),
                "dots".to_string(),
                "plate".to_string()
            ])
        );
        assert_eq!(ops[2].layers, Some(vec!["marks".to_string()]));
        assert_eq!(ops[3].strokes, Some(vec!["plain".to_string()]));
        let mut count: HashMap<String, usize> = HashMap::new();
        for op in &ops {
            for n in selected(&d, op) {
                *count.entry(n).or_default() += 1;
            }
        }
        assert_eq!(count.len(), 6);
        assert!(count.values().all(|&c| c == 1), "{count:?}");
        // The operations load back: a design with them validates.
        let mut with = d.clone();
        with.operation = ops.clone();
        assert!(crate::design::validate(&with).is_ok());
        // A threshold below every stroke's width: everything is profiled, one operation
        // with no selector.
        let wide = default_operations(&d, 0.1);
        assert_eq!(wide.len(), 1);
        assert!(wide[0].kind == OperationKind::Profile && wide[0].strokes.is_none());
    }

    /// Profiled items of different colours whose boxes meet get a `line` along the
    /// boundaries between their inks, with the profile's selector, right after it; of one
    /// colour, none.
    #[test]
    fn default_operations_cut_the_boundaries_between_inks_that_meet() {
        let mut d = load("").unwrap();
        // "wide" (red) now crosses the black plate.
        d.stroke[1].disks = Some(vec![[25.0, 25.0, 2.0], [35.0, 25.0, 2.0]]);
        let ops = default_operations(&d, HAIRLINE_MM);
        let kinds: Vec<&str> = ops.iter().map(|o| o.kind.as_str()).collect();
        assert_eq!(kinds, ["line", "profile", "line", "line", "line"]);
        assert_eq!(ops[2].boundaries, Some(LineBoundaries::Inner));
        assert_eq!(ops[2].strokes, ops[1].strokes);
        let marked: Vec<bool> = ops.iter().map(|o| o.boundaries.is_some()).collect();
        assert_eq!(marked, [false, false, true, false, false]);
        let mut with = d.clone();
        with.operation = ops;
        assert!(crate::design::validate(&with).is_ok());
        // Written and read back, the key survives.
        let text = with.to_string_as(Format::Toml).unwrap();
        assert!(text.contains("boundaries = \"inner\""), "{text}");
        let back = from_str(&text, Format::Toml, FILE).unwrap();
        assert_eq!(back.operation[2].boundaries, Some(LineBoundaries::Inner));
        // The same colour (case aside): no boundary line.
        d.stroke[1].color = Some("#000000".into());
        let ops = default_operations(&d, HAIRLINE_MM);
        assert!(ops.iter().all(|o| o.boundaries.is_none()), "{ops:?}");
        // `boundaries` is a line's key only.
        let op = "[[operation]]\nkind = \"profile\"\ndepth = 1.0\nboundaries = \"inner\"\n";
        let msg = load(op).unwrap_err();
        assert!(msg.contains("`boundaries` does not apply"), "{msg}");
    }

    /// A layer whose items are one kind with several colours is selected by its layer; a
    /// colour spread over layers with one kind each by neither.
    #[test]
    fn default_operations_group_by_layer_then_colour() {
        let text = r##"version = 1
[[stroke]]
name = "r1"
layer = "a"
color = "#ff0000"
disks = [[0.0, 0.0, 0.1], [10.0, 0.0, 0.1]]
[[stroke]]
name = "r2"
layer = "b"
color = "#ff0000"
disks = [[0.0, 5.0, 0.1], [10.0, 5.0, 0.1]]
[[stroke]]
name = "g"
color = "#00ff00"
disks = [[0.0, 9.0, 0.1], [10.0, 9.0, 0.1]]
[[stroke]]
name = "fat"
color = "#00ff00"
disks = [[0.0, 20.0, 3.0], [10.0, 20.0, 3.0]]
"##;
        let d = from_str(text, Format::Toml, FILE).unwrap();
        let ops = default_operations(&d, HAIRLINE_MM);
        assert_eq!(ops.len(), 4);
        assert_eq!(ops[0].layers, Some(vec!["a".to_string()]));
        assert_eq!(ops[1].layers, Some(vec!["b".to_string()]));
        assert_eq!(ops[2].strokes, Some(vec!["g".to_string()]));
        assert_eq!(ops[3].strokes, Some(vec!["fat".to_string()]));
        // Without "fat" the green line is all of its colour.
        let mut d2 = d.clone();
        d2.stroke.pop();
        let ops = default_operations(&d2, HAIRLINE_MM);
        assert_eq!(ops[2].colors, Some(vec!["#00ff00".to_string()]));
        // Profiled items of several whole layers are one operation selecting the layers.
        let mut d3 = d2.clone();
        for s in &mut d3.stroke[..2] {
            s.disks = Some(vec![[0.0, 0.0, 2.0], [10.0, 0.0, 2.0]]);
        }
        let ops = default_operations(&d3, HAIRLINE_MM);
        assert_eq!(ops[0].kind, OperationKind::Profile);
        assert_eq!(ops[0].layers, Some(vec!["a".to_string(), "b".to_string()]));
    }
}
