//! The drawing layer every skinpath picture goes through (the outline drawing and the
//! toolpath preview): a page in millimetres, world coordinates with y up mapped onto it, and
//! a few primitives written as SVG. The PNG is this SVG rasterised ([`super::png`]), so there
//! is no second drawing code.

use super::glyphs;
use crate::emit::xml_escape;
use glam::DVec2;
use std::fmt::Write as _;

/// World (y up) to page (y down) mapping: `page = (p − lo) · scale` with y flipped about
/// the top edge `hi.y`, shifted by `offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub lo: DVec2,
    pub hi: DVec2,
    /// Page units per world unit.
    pub scale: f64,
    /// Page position of the world's top-left corner.
    pub offset: DVec2,
}

impl Frame {
    /// The frame showing world box `lo..hi` at `scale`, its corner at `offset` on the page.
    pub fn new(lo: DVec2, hi: DVec2, scale: f64, offset: DVec2) -> Frame {
        Frame {
            lo,
            hi,
            scale,
            offset,
        }
    }

    /// Page coordinates of a world point.
    pub fn map(&self, p: DVec2) -> DVec2 {
        self.offset + DVec2::new(p.x - self.lo.x, self.hi.y - p.y) * self.scale
    }

    /// Page size of the framed world box.
    pub fn size(&self) -> DVec2 {
        (self.hi - self.lo) * self.scale
    }
}

/// Decimals written for page coordinates: 1 µm on a page in mm.
const DECIMALS: usize = 3;

fn n(v: f64) -> String {
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

/// An SVG document being written.
pub struct SvgPage {
    out: String,
    pub width: f64,
    pub height: f64,
}

impl SvgPage {
    /// A page of `width` × `height` user units, each `mm_per_unit` millimetres, with a
    /// white background.
    pub fn new(width: f64, height: f64, mm_per_unit: f64) -> SvgPage {
        let mut out = String::new();
        out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n");
        let _ = writeln!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{}mm\" \
             height=\"{}mm\" viewBox=\"0 0 {} {}\">",
            crate::emit::fnum(width * mm_per_unit),
            crate::emit::fnum(height * mm_per_unit),
            crate::emit::fnum(width),
            crate::emit::fnum(height)
        );
        let _ = writeln!(
            out,
            "<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>",
            n(width),
            n(height)
        );
        SvgPage { out, width, height }
    }

    /// Opens a group with `attrs` (already formatted `name="value"` pairs).
    pub fn open(&mut self, id: &str, attrs: &str) {
        if id.is_empty() {
            let _ = writeln!(self.out, "<g {attrs}>");
        } else {
            let _ = writeln!(self.out, "<g id=\"{}\" {attrs}>", xml_escape(id));
        }
    }

    pub fn close(&mut self) {
        self.out.push_str("</g>\n");
    }

    /// Path data of page points.
    pub fn path_data(pts: &[DVec2], closed: bool) -> String {
        let mut d = String::with_capacity(pts.len() * 16);
        for (i, p) in pts.iter().enumerate() {
            let _ = write!(
                d,
                "{}{} {}",
                if i == 0 { "M" } else { " L" },
                n(p.x),
                n(p.y)
            );
        }
        if closed {
            d.push_str(" Z");
        }
        d
    }

    /// A polyline through page points.
    pub fn polyline(&mut self, class: &str, pts: &[DVec2], closed: bool, attrs: &str) {
        if pts.len() < 2 {
            return;
        }
        let _ = writeln!(
            self.out,
            "<path class=\"{class}\" d=\"{}\"{}{attrs}/>",
            Self::path_data(pts, closed),
            if attrs.is_empty() { "" } else { " " }
        );
    }

    /// A path with ready path data.
    pub fn path(&mut self, class: &str, d: &str, attrs: &str) {
        let _ = writeln!(
            self.out,
            "<path class=\"{class}\" d=\"{d}\"{}{attrs}/>",
            if attrs.is_empty() { "" } else { " " }
        );
    }

    /// A line between two page points.
    pub fn line(&mut self, class: &str, a: DVec2, b: DVec2) {
        let _ = writeln!(
            self.out,
            "<line class=\"{class}\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/>",
            n(a.x),
            n(a.y),
            n(b.x),
            n(b.y)
        );
    }

    /// A circle at a page point, with an optional tooltip.
    pub fn circle(&mut self, class: &str, c: DVec2, r: f64, attrs: &str, title: Option<&str>) {
        let _ = write!(
            self.out,
            "<circle class=\"{class}\" cx=\"{}\" cy=\"{}\" r=\"{}\"{}{attrs}",
            n(c.x),
            n(c.y),
            n(r),
            if attrs.is_empty() { "" } else { " " }
        );
        match title {
            Some(t) => {
                let _ = writeln!(self.out, "><title>{}</title></circle>", xml_escape(t));
            }
            None => self.out.push_str("/>\n"),
        }
    }

    /// A rectangle with page corner `at` and `size`.
    pub fn rect(&mut self, class: &str, at: DVec2, size: DVec2, attrs: &str) {
        let _ = writeln!(
            self.out,
            "<rect class=\"{class}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" {attrs}/>",
            n(at.x),
            n(at.y),
            n(size.x),
            n(size.y)
        );
    }

    /// Text set in the viewer's sans-serif font (rasterised only where a system font is
    /// installed; see [`super::png`]). `at` is the baseline start.
    pub fn text(&mut self, class: &str, at: DVec2, size: f64, color: &str, s: &str) {
        let _ = writeln!(
            self.out,
            "<text class=\"{class}\" x=\"{}\" y=\"{}\" font-family=\"DejaVu Sans, Liberation \
             Sans, Arial, sans-serif\" font-size=\"{}\" fill=\"{color}\">{}</text>",
            n(at.x),
            n(at.y),
            n(size),
            xml_escape(s)
        );
    }

    /// Digits (and '-') drawn as strokes (no font needed) on a white halo, centred on
    /// `center`, `height` tall.
    pub fn number(&mut self, class: &str, center: DVec2, height: f64, color: &str, text: &str) {
        let d = glyphs::number_path(text, center, height);
        let _ = writeln!(
            self.out,
            "<path class=\"halo\" d=\"{d}\" fill=\"none\" stroke=\"#ffffff\" \
             stroke-opacity=\"0.85\" stroke-width=\"{}\" stroke-linecap=\"round\" \
             stroke-linejoin=\"round\"/>",
            n(2.6 * height * glyphs::STROKE)
        );
        let _ = writeln!(
            self.out,
            "<path class=\"{class}\" d=\"{d}\" fill=\"none\" stroke=\"{color}\" \
             stroke-width=\"{}\" stroke-linecap=\"round\" stroke-linejoin=\"round\"/>",
            n(height * glyphs::STROKE)
        );
    }

    /// Raw SVG text (already escaped).
    pub fn raw(&mut self, s: &str) {
        self.out.push_str(s);
    }

    /// The finished document.
    pub fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }
}

/// A number formatted for path data (3 decimals, no trailing zeros).
pub fn num(v: f64) -> String {
    n(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_flips_y_and_scales() {
        let f = Frame::new(
            DVec2::new(10.0, 20.0),
            DVec2::new(30.0, 60.0),
            2.0,
            DVec2::new(1.0, 1.0),
        );
        assert_eq!(f.map(DVec2::new(10.0, 60.0)), DVec2::new(1.0, 1.0));
        assert_eq!(f.map(DVec2::new(30.0, 20.0)), DVec2::new(41.0, 81.0));
        assert_eq!(f.size(), DVec2::new(40.0, 80.0));
        assert_eq!(num(-0.0001), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(3.0), "3");
    }
}
