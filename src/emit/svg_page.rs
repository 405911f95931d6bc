//! The one SVG writer of skinpath: the outline drawing ([`super::outline`]), the laser-cutter
//! SVG ([`super::laser_svg::laser_svg`]) and the toolpath preview ([`super::preview`]) all build their
//! document through [`SvgPage`], which holds it in the `svg` crate's document model and
//! serialises it with the crate (attribute values and text escaped by it; attributes come
//! out in name order).
//!
//! Path data is kept as attribute strings at full f64 precision: the crate's
//! `path::Data` stores f32 coordinates, which would move a 1 m job's points by up to 30 µm.

use ::svg::Node as _;
use ::svg::node::element::Element;
use ::svg::node::{Text, Value};
use glam::DVec2;
use std::borrow::Cow;
use std::fmt::Write as _;

/// The XML declaration written before the `<svg>` element.
const XML_DECLARATION: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>";

/// Decimals written for page coordinates by [`num`]: 1 µm on a page in mm.
const DECIMALS: usize = 3;

/// A number formatted for page coordinates: 3 decimals, no trailing zeros, `-0` as `0`,
/// non-finite values as `0`.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return "0".into();
    }
    let s = format!("{v:.DECIMALS$}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".into()
    } else {
        s.to_string()
    }
}

/// `s` with the control characters XML 1.0 does not allow (below U+0020 except tab and
/// newline) replaced by spaces; the `svg` crate escapes markup characters but passes these
/// through, and a design's names may carry them.
fn xml_chars(s: &str) -> Cow<'_, str> {
    let bad = |c: char| (c as u32) < 0x20 && c != '\n' && c != '\t';
    if s.chars().any(bad) {
        Cow::Owned(s.chars().map(|c| if bad(c) { ' ' } else { c }).collect())
    } else {
        Cow::Borrowed(s)
    }
}

/// `s` as text content of an XML or HTML element: markup characters escaped by the `svg`
/// crate, control characters replaced by spaces.
pub fn text_content(s: &str) -> String {
    Text::new(xml_chars(s)).to_string()
}

fn element(name: &str, attrs: &[(&str, &str)]) -> Element {
    let mut e = Element::new(name);
    for (k, v) in attrs {
        e.assign(*k, Value::from(xml_chars(v).into_owned()));
    }
    e
}

/// An SVG document being written: a page of user units, each a given number of
/// millimetres, with groups opened and closed around the elements.
pub struct SvgPage {
    /// The root `<svg>` element and the groups opened in it, innermost last.
    stack: Vec<Element>,
    /// Page width in user units.
    pub width: f64,
    /// Page height in user units.
    pub height: f64,
}

impl SvgPage {
    /// A page of `width` × `height` user units, each `mm_per_unit` millimetres, with a
    /// white background.
    pub fn new(width: f64, height: f64, mm_per_unit: f64) -> SvgPage {
        let mut page = SvgPage::bare(width, height, mm_per_unit);
        page.push(element(
            "rect",
            &[
                ("x", "0"),
                ("y", "0"),
                ("width", &num(width)),
                ("height", &num(height)),
                ("fill", "#ffffff"),
            ],
        ));
        page
    }

    /// A page without background (what a laser cutter's software imports): width and
    /// height at f64 precision in millimetres, a matching viewBox.
    pub fn bare(width: f64, height: f64, mm_per_unit: f64) -> SvgPage {
        let root = element(
            "svg",
            &[
                ("xmlns", "http://www.w3.org/2000/svg"),
                ("version", "1.1"),
                ("width", &format!("{}mm", super::fnum(width * mm_per_unit))),
                (
                    "height",
                    &format!("{}mm", super::fnum(height * mm_per_unit)),
                ),
                (
                    "viewBox",
                    &format!("0 0 {} {}", super::fnum(width), super::fnum(height)),
                ),
            ],
        );
        SvgPage {
            stack: vec![root],
            width,
            height,
        }
    }

    fn push(&mut self, e: Element) {
        if let Some(top) = self.stack.last_mut() {
            top.append(e);
        }
    }

    /// Opens a group with id `id` (none when empty) and `attrs`.
    pub fn open(&mut self, id: &str, attrs: &[(&str, &str)]) {
        let mut g = element("g", attrs);
        if !id.is_empty() {
            g.assign("id", Value::from(xml_chars(id).into_owned()));
        }
        self.stack.push(g);
    }

    /// Closes the innermost open group (the root stays open until [`SvgPage::finish`]).
    pub fn close(&mut self) {
        if self.stack.len() > 1
            && let Some(g) = self.stack.pop()
        {
            self.push(g);
        }
    }

    /// A `<title>` in the current group (the document's title at the top level).
    pub fn title(&mut self, s: &str) {
        let mut t = Element::new("title");
        t.append(Text::new(xml_chars(s)));
        self.push(t);
    }

    /// Path data of page points, each number to 3 decimals (1 µm on a page in mm).
    pub fn path_data(pts: &[DVec2], closed: bool) -> String {
        let mut d = String::with_capacity(pts.len() * 16);
        for (i, p) in pts.iter().enumerate() {
            let _ = write!(
                d,
                "{}{} {}",
                if i == 0 { "M" } else { " L" },
                num(p.x),
                num(p.y)
            );
        }
        if closed {
            d.push_str(" Z");
        }
        d
    }

    /// A polyline through page points (nothing for fewer than two).
    pub fn polyline(&mut self, class: &str, pts: &[DVec2], closed: bool, attrs: &[(&str, &str)]) {
        if pts.len() < 2 {
            return;
        }
        self.path(class, &Self::path_data(pts, closed), attrs);
    }

    /// A path with ready path data; `class` is left out when empty.
    pub fn path(&mut self, class: &str, d: &str, attrs: &[(&str, &str)]) {
        let mut e = element("path", attrs);
        if !class.is_empty() {
            e.assign("class", class);
        }
        e.assign("d", d);
        self.push(e);
    }

    /// A line between two page points.
    pub fn line(&mut self, class: &str, a: DVec2, b: DVec2) {
        self.push(element(
            "line",
            &[
                ("class", class),
                ("x1", &num(a.x)),
                ("y1", &num(a.y)),
                ("x2", &num(b.x)),
                ("y2", &num(b.y)),
            ],
        ));
    }

    /// A circle at a page point, with an optional tooltip.
    pub fn circle(
        &mut self,
        class: &str,
        c: DVec2,
        r: f64,
        attrs: &[(&str, &str)],
        title: Option<&str>,
    ) {
        let mut e = element(
            "circle",
            &[
                ("class", class),
                ("cx", &num(c.x)),
                ("cy", &num(c.y)),
                ("r", &num(r)),
            ],
        );
        for (k, v) in attrs {
            e.assign(*k, Value::from(xml_chars(v).into_owned()));
        }
        if let Some(t) = title {
            let mut te = Element::new("title");
            te.append(Text::new(xml_chars(t)));
            e.append(te);
        }
        self.push(e);
    }

    /// A rectangle with page corner `at` and `size`.
    pub fn rect(&mut self, class: &str, at: DVec2, size: DVec2, attrs: &[(&str, &str)]) {
        let mut e = element(
            "rect",
            &[
                ("class", class),
                ("x", &num(at.x)),
                ("y", &num(at.y)),
                ("width", &num(size.x)),
                ("height", &num(size.y)),
            ],
        );
        for (k, v) in attrs {
            e.assign(*k, Value::from(xml_chars(v).into_owned()));
        }
        self.push(e);
    }

    /// Text set in the viewer's sans-serif font (rasterised only where a system font is
    /// installed; see [`super::scene_png`]). `at` is the baseline start.
    pub fn text(&mut self, class: &str, at: DVec2, size: f64, color: &str, s: &str) {
        let mut e = element(
            "text",
            &[
                ("class", class),
                ("x", &num(at.x)),
                ("y", &num(at.y)),
                (
                    "font-family",
                    "DejaVu Sans, Liberation Sans, Arial, sans-serif",
                ),
                ("font-size", &num(size)),
                ("fill", color),
            ],
        );
        e.append(Text::new(xml_chars(s)));
        self.push(e);
    }

    /// Digits (and '-') drawn as strokes (no font needed) on a white halo, centred on
    /// `center`, `height` tall.
    pub fn number(&mut self, class: &str, center: DVec2, height: f64, color: &str, text: &str) {
        let d = super::preview::glyphs::number_path(text, center, height);
        let stroke = [
            ("fill", "none"),
            ("stroke-linecap", "round"),
            ("stroke-linejoin", "round"),
        ];
        let halo_width = num(2.6 * height * super::preview::glyphs::STROKE);
        let mut halo = stroke.to_vec();
        halo.extend([
            ("stroke", "#ffffff"),
            ("stroke-opacity", "0.85"),
            ("stroke-width", &halo_width),
        ]);
        self.path("halo", &d, &halo);
        let width = num(height * super::preview::glyphs::STROKE);
        let mut glyph = stroke.to_vec();
        glyph.extend([("stroke", color), ("stroke-width", &width)]);
        self.path(class, &d, &glyph);
    }

    /// The finished document: the XML declaration, the `<svg>` element as the `svg` crate
    /// writes it (one element a line), a final newline.
    pub fn finish(mut self) -> String {
        while self.stack.len() > 1 {
            self.close();
        }
        let mut out = String::from(XML_DECLARATION);
        out.push('\n');
        if let Some(root) = self.stack.pop() {
            let _ = write!(out, "{root}");
        }
        out.push('\n');
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_escaping() {
        assert_eq!(num(-0.0001), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(3.0), "3");
        let mut p = SvgPage::bare(10.0, 5.0, 1.0);
        p.title("a <b> & \"c\"\u{1}");
        p.open("g\"1", &[("data-name", "x<y")]);
        p.circle("c", DVec2::new(1.0, 2.0), 0.5, &[], Some("t & u"));
        p.close();
        let s = p.finish();
        let doc = roxmltree::Document::parse(&s).unwrap();
        let root = doc.root_element();
        assert_eq!(root.attribute("width"), Some("10mm"));
        assert_eq!(root.attribute("viewBox"), Some("0 0 10 5"));
        let title = doc.descendants().find(|n| n.has_tag_name("title")).unwrap();
        assert_eq!(title.text(), Some("a <b> & \"c\" "));
        let g = doc.descendants().find(|n| n.has_tag_name("g")).unwrap();
        assert_eq!(g.attribute("id"), Some("g\"1"));
        assert_eq!(g.attribute("data-name"), Some("x<y"));
        let c = doc
            .descendants()
            .find(|n| n.has_tag_name("circle"))
            .unwrap();
        assert_eq!(c.attribute("cx"), Some("1"));
        assert_eq!(c.attribute("r"), Some("0.5"));
        assert!(s.starts_with(XML_DECLARATION) && s.ends_with("</svg>\n"));
    }
}
