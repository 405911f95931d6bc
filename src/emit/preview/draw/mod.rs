//! The drawing layer every skinpath picture goes through (the outline drawing and the
//! toolpath preview): world coordinates with y up mapped onto a page in millimetres
//! ([`Frame`]), and one drawing model ([`Drawing`]: groups, polylines, circles, rectangles,
//! stroke digits and text on a page) with two backends: SVG text through the one SVG writer
//! ([`SvgPage`], [`Drawing::to_svg`]) and a tiny-skia pixmap ([`Drawing::to_pixmap`]), so
//! the SVG and the PNG show the same picture from the same drawing.

pub use crate::emit::svg_page::{SvgPage, num};
use glam::DVec2;

#[cfg(feature = "png")]
mod raster;

/// World (y up) to page (y down) mapping: `page = (p − lo) · scale` with y flipped about
/// the top edge `hi.y`, shifted by `offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Lower-left corner of the framed world box.
    pub lo: DVec2,
    /// Upper-right corner of the framed world box.
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
}

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// White, the page's background.
    pub const WHITE: Rgb = Rgb(0xff, 0xff, 0xff);

    /// `#rrggbb`.
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

/// What a fill or a stroke paints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Paint {
    /// Nothing (SVG `none`).
    None,
    /// A colour.
    Color(Rgb),
}

/// Presentation of an element or a group, SVG's model: a field left `None` (or `false`) is
/// not set and inherits from the enclosing group, down to SVG's initial values (fill black,
/// no stroke, stroke width 1, butt caps, miter joins, opaque).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Style {
    /// Fill paint.
    pub fill: Option<Paint>,
    /// Fill opacity, 0..1.
    pub fill_opacity: Option<f64>,
    /// Stroke paint.
    pub stroke: Option<Paint>,
    /// Stroke width, page units.
    pub stroke_width: Option<f64>,
    /// Stroke opacity, 0..1.
    pub stroke_opacity: Option<f64>,
    /// Dash and gap lengths, page units.
    pub dash: Option<[f64; 2]>,
    /// Round line caps.
    pub round_caps: bool,
    /// Round line joins.
    pub round_joins: bool,
}

impl Style {
    /// A stroke of `color` and `width`, no fill.
    pub fn stroked(color: Rgb, width: f64) -> Style {
        Style {
            fill: Some(Paint::None),
            stroke: Some(Paint::Color(color)),
            stroke_width: Some(width),
            ..Style::default()
        }
    }

    /// A fill of `color`.
    pub fn filled(color: Rgb) -> Style {
        Style {
            fill: Some(Paint::Color(color)),
            ..Style::default()
        }
    }

    /// Round caps and joins.
    pub fn round(self) -> Style {
        Style {
            round_caps: true,
            round_joins: true,
            ..self
        }
    }

    /// The SVG presentation attributes of what is set.
    fn attrs(&self) -> Vec<(&'static str, String)> {
        let paint = |p: Paint| match p {
            Paint::None => "none".to_string(),
            Paint::Color(c) => c.hex(),
        };
        let mut a = Vec::new();
        if let Some(p) = self.fill {
            a.push(("fill", paint(p)));
        }
        if let Some(o) = self.fill_opacity {
            a.push(("fill-opacity", num(o)));
        }
        if let Some(p) = self.stroke {
            a.push(("stroke", paint(p)));
        }
        if let Some(w) = self.stroke_width {
            a.push(("stroke-width", num(w)));
        }
        if let Some(o) = self.stroke_opacity {
            a.push(("stroke-opacity", num(o)));
        }
        if let Some([d, g]) = self.dash {
            a.push(("stroke-dasharray", format!("{} {}", num(d), num(g))));
        }
        if self.round_caps {
            a.push(("stroke-linecap", "round".into()));
        }
        if self.round_joins {
            a.push(("stroke-linejoin", "round".into()));
        }
        a
    }
}

/// One element of a [`Drawing`], in page units (y down).
#[derive(Clone, Debug, PartialEq)]
enum Item {
    /// A group: its id (none when empty), style and SVG-only `data-` attributes.
    Open {
        id: String,
        style: Style,
        data: Vec<(&'static str, String)>,
    },
    /// The end of the innermost open group.
    Close,
    /// Polylines (subpaths) with one style; `id` only in the SVG.
    Path {
        class: String,
        id: Option<String>,
        subpaths: Vec<Vec<DVec2>>,
        closed: bool,
        style: Style,
    },
    /// A circle with an SVG tooltip.
    Circle {
        class: String,
        center: DVec2,
        r: f64,
        style: Style,
        title: Option<String>,
    },
    /// An axis-aligned rectangle.
    Rect {
        class: String,
        at: DVec2,
        size: DVec2,
        style: Style,
    },
    /// Digits drawn as strokes on a white halo ([`super::glyphs`]), centred on `center`.
    Number {
        class: String,
        center: DVec2,
        height: f64,
        color: Rgb,
        text: String,
    },
    /// Text in a system sans-serif font, baseline start at `at`.
    Text {
        class: String,
        at: DVec2,
        size: f64,
        color: Rgb,
        text: String,
    },
}

/// A picture on a page of `width` × `height` units (1 unit = 1 mm), white background:
/// the one model both backends draw.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// Page width, mm.
    pub width: f64,
    /// Page height, mm.
    pub height: f64,
    items: Vec<Item>,
}

impl Drawing {
    /// An empty page of `width` × `height` mm.
    pub fn new(width: f64, height: f64) -> Drawing {
        Drawing {
            width,
            height,
            items: Vec::new(),
        }
    }

    /// Opens a group with id `id` (none when empty), `style` and SVG `data-` attributes.
    pub fn open(&mut self, id: &str, style: Style, data: &[(&'static str, &str)]) {
        self.items.push(Item::Open {
            id: id.to_string(),
            style,
            data: data.iter().map(|(k, v)| (*k, v.to_string())).collect(),
        });
    }

    /// Closes the innermost open group.
    pub fn close(&mut self) {
        self.items.push(Item::Close);
    }

    /// A polyline through page points (nothing for fewer than two); `id` names it in the SVG.
    pub fn polyline(
        &mut self,
        class: &str,
        pts: Vec<DVec2>,
        closed: bool,
        style: Style,
        id: Option<String>,
    ) {
        if pts.len() < 2 {
            return;
        }
        self.items.push(Item::Path {
            class: class.to_string(),
            id,
            subpaths: vec![pts],
            closed,
            style,
        });
    }

    /// A circle with an optional tooltip (SVG only).
    pub fn circle(
        &mut self,
        class: &str,
        center: DVec2,
        r: f64,
        style: Style,
        title: Option<&str>,
    ) {
        self.items.push(Item::Circle {
            class: class.to_string(),
            center,
            r,
            style,
            title: title.map(str::to_string),
        });
    }

    /// A rectangle with corner `at` and `size`.
    pub fn rect(&mut self, class: &str, at: DVec2, size: DVec2, style: Style) {
        self.items.push(Item::Rect {
            class: class.to_string(),
            at,
            size,
            style,
        });
    }

    /// Digits (and '-') drawn as strokes on a white halo, centred on `center`.
    pub fn number(&mut self, class: &str, center: DVec2, height: f64, color: Rgb, text: &str) {
        self.items.push(Item::Number {
            class: class.to_string(),
            center,
            height,
            color,
            text: text.to_string(),
        });
    }

    /// Text in a system sans-serif font; `at` is the baseline start.
    pub fn text(&mut self, class: &str, at: DVec2, size: f64, color: Rgb, text: &str) {
        self.items.push(Item::Text {
            class: class.to_string(),
            at,
            size,
            color,
            text: text.to_string(),
        });
    }

    /// The drawing as an SVG document (1 user unit = 1 mm, white background).
    pub fn to_svg(&self) -> String {
        let mut page = SvgPage::new(self.width, self.height, 1.0);
        let attrs = |style: &Style| style.attrs();
        for item in &self.items {
            match item {
                Item::Open { id, style, data } => {
                    let mut a = data.clone();
                    a.extend(attrs(style));
                    page.open(id, &borrow(&a));
                }
                Item::Close => page.close(),
                Item::Path {
                    class,
                    id,
                    subpaths,
                    closed,
                    style,
                } => {
                    let d: Vec<String> = subpaths
                        .iter()
                        .map(|p| SvgPage::path_data(p, *closed))
                        .collect();
                    let mut a = attrs(style);
                    if let Some(id) = id {
                        a.push(("id", id.clone()));
                    }
                    page.path(class, &d.join(" "), &borrow(&a));
                }
                Item::Circle {
                    class,
                    center,
                    r,
                    style,
                    title,
                } => page.circle(class, *center, *r, &borrow(&attrs(style)), title.as_deref()),
                Item::Rect {
                    class,
                    at,
                    size,
                    style,
                } => page.rect(class, *at, *size, &borrow(&attrs(style))),
                Item::Number {
                    class,
                    center,
                    height,
                    color,
                    text,
                } => page.number(class, *center, *height, &color.hex(), text),
                Item::Text {
                    class,
                    at,
                    size,
                    color,
                    text,
                } => page.text(class, *at, *size, &color.hex(), text),
            }
        }
        page.finish()
    }
}

/// Attribute pairs as the SVG writer takes them.
fn borrow<'a>(a: &'a [(&'static str, String)]) -> Vec<(&'static str, &'a str)> {
    a.iter().map(|(k, v)| (*k, v.as_str())).collect()
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
        assert_eq!(num(-0.0001), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(3.0), "3");
    }
}
