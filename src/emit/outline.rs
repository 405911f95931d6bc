//! The outline document: what `skinpath outline` writes, as JSON (a contract other tools
//! read) or as an SVG drawing in millimetres.
//!
//! JSON shape (format 1):
//! `{"units": "mm", "strokes": [{"name": "s1", "contours": [{"role": "envelope",
//! "closed": false, "points": [[x, y], ...]}, ...], "markers": [...]}]}`.
//! Roles: `spine`, `envelope` (each side with its caps), `outline` (the closed
//! intersection-free contours of the chosen method), `knot-circle`, `control-disk`,
//! `offset`. Markers carry point features: envelope loops and spans without an envelope.
//!
//! An [`OutlineContour`] is a drawn contour of this document; not to be confused with
//! [`CutContour`](super::CutContour) (a run of emitted cutting segments of a toolpath) or
//! [`SimContour`](crate::sim::checks::SimContour) (a cut contour the G-code checker rebuilt
//! from simulated moves).

use super::preview::draw::{Frame, SvgPage, num};
use crate::geom::DVec2;
use serde::{Deserialize, Serialize};

/// What a drawn contour is; serialised as the outline JSON's `role` strings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContourRole {
    /// The intersection-free outline of the chosen method (`"outline"`).
    Outline,
    /// A piece of the raw envelope or an end cap (`"envelope"`).
    Envelope,
    /// The centre curve of a stroke (`"spine"`).
    Spine,
    /// An inner or outer offset drawn at the requested distance (`"offset"`).
    Offset,
}

/// What a reference circle is; serialised as the outline JSON's `role` strings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CircleRole {
    /// A circle at a knot of the disk curve (`"knot-circle"`).
    KnotCircle,
    /// A control disk of a disk B-spline (`"control-disk"`).
    ControlDisk,
    /// A circle of a circle sequence (`"circle"`).
    Circle,
}

/// What a marker points at; serialised as the outline JSON's `kind` strings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MarkerKind {
    /// A loop of the envelope (`"loop"`).
    Loop,
    /// A span where the disks have no envelope (`"no-envelope"`).
    NoEnvelope,
    /// Two parts of one stroke's outline overlap (`"self-overlap"`).
    SelfOverlap,
    /// A loop of a reconstructed-envelope curve (`"re-loop"`).
    ReLoop,
    /// Two reconstructed-envelope curves cross (`"re-intersection"`).
    ReIntersection,
    /// The skin cut into the stroke, so its outline is the union of the disks
    /// (`"disk-union"`).
    DiskUnion,
}

macro_rules! as_str_display {
    ($t:ty { $($v:ident => $s:literal),* $(,)? }) => {
        impl $t {
            /// The JSON string of the value.
            pub fn as_str(self) -> &'static str {
                match self {
                    $(Self::$v => $s,)*
                }
            }
        }
        impl std::fmt::Display for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}

as_str_display!(ContourRole { Outline => "outline", Envelope => "envelope", Spine => "spine", Offset => "offset" });
as_str_display!(CircleRole { KnotCircle => "knot-circle", ControlDisk => "control-disk", Circle => "circle" });
as_str_display!(MarkerKind {
    Loop => "loop",
    NoEnvelope => "no-envelope",
    SelfOverlap => "self-overlap",
    ReLoop => "re-loop",
    ReIntersection => "re-intersection",
    DiskUnion => "disk-union",
});

/// One flattened contour with its role.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OutlineContour {
    /// What the contour is.
    pub role: ContourRole,
    /// Whether the last point joins the first.
    pub closed: bool,
    /// Points (design units, y up).
    pub points: Vec<[f64; 2]>,
}

/// Closing gap relative to the coordinates' magnitude under which a closed contour's last
/// point counts as a repeat of its first: far below any flattening tolerance, far above
/// the 1e-14 rounding residue an outline's closing point carries.
const REPEAT_REL: f64 = 1e-9;

impl OutlineContour {
    /// A contour of `points`. Closed contours never repeat their first point at the end (the
    /// `closed` flag says it; the convention of every output: DXF closed polylines, SVG `Z`
    /// after the last distinct point): a last point within `REPEAT_REL` of the first is
    /// dropped, so polygon libraries (GEOS, Shapely, geo) do not read a 1e-14 sliver edge.
    pub fn new(role: ContourRole, closed: bool, points: &[DVec2]) -> Self {
        let mut pts: Vec<[f64; 2]> = points.iter().map(|p| [p.x, p.y]).collect();
        while closed && pts.len() > 1 {
            let (f, l) = (pts[0], pts[pts.len() - 1]);
            let scale = 1.0 + f[0].abs().max(f[1].abs());
            if (f[0] - l[0]).hypot(f[1] - l[1]) <= REPEAT_REL * scale {
                pts.pop();
            } else {
                break;
            }
        }
        OutlineContour {
            role,
            closed,
            points: pts,
        }
    }
}

/// A point feature worth showing: an envelope loop, a span with no envelope.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// What was found.
    pub kind: MarkerKind,
    /// Where (design units).
    pub at: [f64; 2],
    /// Explanation shown as a tooltip.
    pub message: String,
}

/// A circle drawn for reference (control disks, knot circles).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefCircle {
    /// What the circle is.
    pub role: CircleRole,
    /// Centre (design units).
    pub center: [f64; 2],
    /// Radius (design units).
    pub radius: f64,
}

/// Everything drawn for one stroke or circle sequence.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct StrokeOutline {
    /// The stroke's or circle sequence's name.
    pub name: String,
    /// Drawn contours (spine, envelope, outline, offsets).
    pub contours: Vec<OutlineContour>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    /// Reference circles.
    pub circles: Vec<RefCircle>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    /// Markers of what the outline found (loops, overlaps, intersections).
    pub markers: Vec<Marker>,
}

/// The whole document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OutlineDoc {
    /// Units of the design: `mm` or `inch`.
    pub units: String,
    /// One drawing per stroke and circle sequence, in file order.
    pub strokes: Vec<StrokeOutline>,
}

impl OutlineDoc {
    /// Pretty JSON.
    pub fn to_json(&self) -> String {
        // Serialising plain data with finite or non-finite floats cannot fail with
        // serde_json (non-finite values become null).
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Bounding box of every contour point and reference circle.
    pub fn bounds(&self) -> Option<(DVec2, DVec2)> {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for s in &self.strokes {
            for c in &s.contours {
                for p in &c.points {
                    lo = lo.min(DVec2::new(p[0], p[1]));
                    hi = hi.max(DVec2::new(p[0], p[1]));
                }
            }
            for c in &s.circles {
                let ctr = DVec2::new(c.center[0], c.center[1]);
                lo = lo.min(ctr - c.radius);
                hi = hi.max(ctr + c.radius);
            }
        }
        (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
    }

    /// An SVG drawing: width/height in mm with a matching viewBox (1 user unit = 1 design
    /// unit; inch designs are drawn at 25.4 mm per unit), y pointing up as in the design.
    /// Outline solid, envelope dashed (solid when it is the only boundary), spine thin,
    /// reference circles faint, markers as red rings with a tooltip. Drawn with the
    /// preview's drawing layer, so it rasterises the same way.
    pub fn to_svg(&self) -> String {
        let (lo, hi) = self.bounds().unwrap_or((DVec2::ZERO, DVec2::ONE));
        let margin = 0.05 * (hi - lo).max_element().max(1.0);
        let lo = lo - margin;
        let hi = hi + margin;
        let size = hi - lo;
        let mm = if self.units == "inch" { 25.4 } else { 1.0 };
        let w = 0.002 * size.max_element();
        let frame = Frame::new(lo, hi, 1.0, DVec2::ZERO);
        let mut page = SvgPage::new(size.x, size.y, mm);
        let map = |p: &[f64; 2]| frame.map(DVec2::new(p[0], p[1]));
        for st in &self.strokes {
            let has_outline = st.contours.iter().any(|c| c.role == ContourRole::Outline);
            page.open(&st.name, &[]);
            for c in &st.circles {
                let stroke = match c.role {
                    CircleRole::KnotCircle => "#4a90d9",
                    CircleRole::ControlDisk | CircleRole::Circle => "#bbbbbb",
                };
                page.circle(
                    c.role.as_str(),
                    map(&c.center),
                    c.radius,
                    &[
                        ("fill", "none"),
                        ("stroke", stroke),
                        ("stroke-width", &num(w * 0.6)),
                    ],
                    None,
                );
            }
            for c in &st.contours {
                let (stroke, width, dashed) = match c.role {
                    ContourRole::Outline => ("#000000", w * 1.5, false),
                    ContourRole::Envelope if has_outline => ("#d9534f", w, true),
                    ContourRole::Envelope => ("#000000", w * 1.5, false),
                    ContourRole::Spine => ("#888888", w * 0.6, false),
                    ContourRole::Offset => ("#2e8b57", w, false),
                };
                let pts: Vec<DVec2> = c.points.iter().map(map).collect();
                let width = num(width);
                let dash = format!("{} {}", num(4.0 * w), num(3.0 * w));
                let mut attrs = vec![
                    ("fill", "none"),
                    ("stroke", stroke),
                    ("stroke-width", &width),
                ];
                if dashed {
                    attrs.push(("stroke-dasharray", &dash));
                }
                page.polyline(c.role.as_str(), &pts, c.closed, &attrs);
            }
            for m in &st.markers {
                page.circle(
                    &format!("marker {}", m.kind),
                    map(&m.at),
                    6.0 * w,
                    &[
                        ("fill", "none"),
                        ("stroke", "#e00000"),
                        ("stroke-width", &num(w)),
                    ],
                    Some(&m.message),
                );
            }
            page.close();
        }
        page.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roles_and_kinds_serialise_to_their_strings() {
        let json = |v: String| v.trim_matches('"').to_string();
        for r in [
            ContourRole::Outline,
            ContourRole::Envelope,
            ContourRole::Spine,
            ContourRole::Offset,
        ] {
            assert_eq!(json(serde_json::to_string(&r).unwrap()), r.as_str());
        }
        for r in [
            CircleRole::KnotCircle,
            CircleRole::ControlDisk,
            CircleRole::Circle,
        ] {
            assert_eq!(json(serde_json::to_string(&r).unwrap()), r.as_str());
        }
        for k in [
            MarkerKind::Loop,
            MarkerKind::NoEnvelope,
            MarkerKind::SelfOverlap,
            MarkerKind::ReLoop,
            MarkerKind::ReIntersection,
            MarkerKind::DiskUnion,
        ] {
            assert_eq!(json(serde_json::to_string(&k).unwrap()), k.to_string());
        }
        assert_eq!(MarkerKind::NoEnvelope.as_str(), "no-envelope");
        assert_eq!(CircleRole::KnotCircle.as_str(), "knot-circle");
    }

    fn doc() -> OutlineDoc {
        OutlineDoc {
            units: "mm".into(),
            strokes: vec![StrokeOutline {
                name: "s<1>".into(),
                contours: vec![OutlineContour::new(
                    ContourRole::Outline,
                    true,
                    &[
                        DVec2::new(0.0, 0.0),
                        DVec2::new(10.0, 0.0),
                        DVec2::new(10.0, 5.0),
                    ],
                )],
                circles: vec![RefCircle {
                    role: CircleRole::ControlDisk,
                    center: [0.0, 0.0],
                    radius: 2.0,
                }],
                markers: vec![],
            }],
        }
    }

    #[test]
    fn json_round_trip() {
        let d = doc();
        let back: OutlineDoc = serde_json::from_str(&d.to_json()).unwrap();
        assert_eq!(back, d);
    }

    #[test]
    fn svg_has_mm_size_matching_viewbox() {
        let svg = doc().to_svg();
        let x = roxmltree::Document::parse(&svg).unwrap();
        let root = x.root_element();
        let w: f64 = root
            .attribute("width")
            .unwrap()
            .trim_end_matches("mm")
            .parse()
            .unwrap();
        let vb: Vec<f64> = root
            .attribute("viewBox")
            .unwrap()
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        assert!((w - vb[2]).abs() < 1e-3);
        // Bounds: x from −2 (disk) to 10, plus 5 % margin of the 12 mm extent each side.
        assert!((vb[2] - 12.0 * 1.1).abs() < 1e-9);
        assert!(svg.contains("s&lt;1&gt;"));
    }
}
