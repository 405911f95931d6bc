//! The pixmap backend of [`Drawing`] (feature `png`): tiny-skia paints the shapes, resvg
//! sets the text with a system font.

use super::{Drawing, Item, Paint, Rgb, Style, SvgPage};
use glam::DVec2;
use tiny_skia::{
    FillRule, LineCap, LineJoin, Paint as SkPaint, PathBuilder, Pixmap, Stroke, StrokeDash,
    Transform,
};

/// Opacity of the white halo behind stroke digits.
const HALO_OPACITY: f64 = 0.85;
/// Halo width as a multiple of the digits' stroke width.
const HALO_WIDTH: f64 = 2.6;
/// Points per stroked piece in the pixmap backend: tiny-skia's scan converter keeps every
/// edge of a path active across its rows, so one path of 10⁵ segments costs several times
/// what 10⁵/64 short paths do (same pixels: the pieces share their end points).
const PIECE_POINTS: usize = 64;

impl Style {
    /// This style with what it leaves unset taken from `parent`.
    pub fn over(&self, parent: &Style) -> Style {
        Style {
            fill: self.fill.or(parent.fill),
            fill_opacity: self.fill_opacity.or(parent.fill_opacity),
            stroke: self.stroke.or(parent.stroke),
            stroke_width: self.stroke_width.or(parent.stroke_width),
            stroke_opacity: self.stroke_opacity.or(parent.stroke_opacity),
            dash: self.dash.or(parent.dash),
            round_caps: self.round_caps || parent.round_caps,
            round_joins: self.round_joins || parent.round_joins,
        }
    }
}

impl Drawing {
    /// The drawing rasterised by tiny-skia on a white `w` × `h` pixmap (the page scaled to
    /// fill it). Text is set with a system font through usvg/resvg when one is installed
    /// (DejaVu, Liberation, ...); without one the words are left out and everything else
    /// (shapes and stroke digits) still shows. None when the pixmap cannot be allocated.
    pub fn to_pixmap(&self, w: u32, h: u32) -> Option<Pixmap> {
        let mut pixmap = Pixmap::new(w, h)?;
        pixmap.fill(tiny_skia::Color::WHITE);
        let t = Transform::from_scale(
            (w as f64 / self.width) as f32,
            (h as f64 / self.height) as f32,
        );
        let mut stack = vec![Style::default()];
        let mut texts = SvgPage::bare(self.width, self.height, 1.0);
        let mut has_text = false;
        for item in &self.items {
            let parent = stack.last().copied().unwrap_or_default();
            match item {
                Item::Open { style, .. } => stack.push(style.over(&parent)),
                Item::Close => {
                    if stack.len() > 1 {
                        stack.pop();
                    }
                }
                Item::Path {
                    subpaths,
                    closed,
                    style,
                    ..
                } => paint_path(&mut pixmap, t, subpaths, *closed, &style.over(&parent)),
                Item::Circle {
                    center, r, style, ..
                } => {
                    if let Some(p) =
                        PathBuilder::from_circle(center.x as f32, center.y as f32, *r as f32)
                    {
                        paint_shape(&mut pixmap, t, &p, &style.over(&parent));
                    }
                }
                Item::Rect {
                    at, size, style, ..
                } => {
                    let r = tiny_skia::Rect::from_xywh(
                        at.x as f32,
                        at.y as f32,
                        size.x as f32,
                        size.y as f32,
                    );
                    if let Some(r) = r {
                        paint_shape(
                            &mut pixmap,
                            t,
                            &PathBuilder::from_rect(r),
                            &style.over(&parent),
                        );
                    }
                }
                Item::Number {
                    center,
                    height,
                    color,
                    text,
                    ..
                } => {
                    let segs: Vec<Vec<DVec2>> =
                        crate::emit::preview::glyphs::number_segments(text, *center, *height)
                            .into_iter()
                            .map(|[a, b]| vec![a, b])
                            .collect();
                    let width = height * crate::emit::preview::glyphs::STROKE;
                    let halo = Style {
                        stroke_opacity: Some(HALO_OPACITY),
                        ..Style::stroked(Rgb::WHITE, HALO_WIDTH * width).round()
                    };
                    paint_path(&mut pixmap, t, &segs, false, &halo);
                    paint_path(
                        &mut pixmap,
                        t,
                        &segs,
                        false,
                        &Style::stroked(*color, width).round(),
                    );
                }
                Item::Text {
                    class,
                    at,
                    size,
                    color,
                    text,
                } => {
                    texts.text(class, *at, *size, &color.hex(), text);
                    has_text = true;
                }
            }
        }
        if has_text {
            draw_text(&mut pixmap, texts.finish(), w, h);
        }
        Some(pixmap)
    }
}

fn sk_paint(color: Rgb, opacity: Option<f64>) -> SkPaint<'static> {
    let mut p = SkPaint::default();
    let a = (opacity.unwrap_or(1.0).clamp(0.0, 1.0) * 255.0).round() as u8;
    p.set_color_rgba8(color.0, color.1, color.2, a);
    p.anti_alias = true;
    p
}

fn sk_stroke(style: &Style) -> Stroke {
    let mut s = Stroke {
        width: style.stroke_width.unwrap_or(1.0) as f32,
        ..Stroke::default()
    };
    if style.round_caps {
        s.line_cap = LineCap::Round;
    }
    if style.round_joins {
        s.line_join = LineJoin::Round;
    }
    if let Some([d, g]) = style.dash {
        s.dash = StrokeDash::new(vec![d as f32, g as f32], 0.0);
    }
    s
}

/// Fills and strokes a closed shape (circle, rectangle) as SVG does: fill first.
fn paint_shape(pixmap: &mut Pixmap, t: Transform, path: &tiny_skia::Path, style: &Style) {
    // SVG's initial fill is black.
    let fill = style.fill.unwrap_or(Paint::Color(Rgb(0, 0, 0)));
    if let Paint::Color(c) = fill {
        pixmap.fill_path(
            path,
            &sk_paint(c, style.fill_opacity),
            FillRule::Winding,
            t,
            None,
        );
    }
    if let Some(Paint::Color(c)) = style.stroke {
        pixmap.stroke_path(
            path,
            &sk_paint(c, style.stroke_opacity),
            &sk_stroke(style),
            t,
            None,
        );
    }
}

/// Fills (closed subpaths, or open ones closed as SVG fills them) and strokes polylines.
/// Strokes go in pieces of [`PIECE_POINTS`] points; a subpath whose points all coincide is
/// drawn as its round cap (a dot) when it has round caps, as SVG renderers do.
fn paint_path(
    pixmap: &mut Pixmap,
    t: Transform,
    subpaths: &[Vec<DVec2>],
    closed: bool,
    style: &Style,
) {
    let fill = style.fill.unwrap_or(Paint::Color(Rgb(0, 0, 0)));
    if let Paint::Color(c) = fill {
        let mut pb = PathBuilder::new();
        for sp in subpaths.iter().filter(|sp| sp.len() >= 3) {
            pb.move_to(sp[0].x as f32, sp[0].y as f32);
            for p in &sp[1..] {
                pb.line_to(p.x as f32, p.y as f32);
            }
            pb.close();
        }
        if let Some(path) = pb.finish() {
            pixmap.fill_path(
                &path,
                &sk_paint(c, style.fill_opacity),
                FillRule::Winding,
                t,
                None,
            );
        }
    }
    let Some(Paint::Color(c)) = style.stroke else {
        return;
    };
    let paint = sk_paint(c, style.stroke_opacity);
    let stroke = sk_stroke(style);
    let mut pb = PathBuilder::new();
    let mut segments = 0;
    let mut flush = |pb: &mut PathBuilder, segments: &mut usize| {
        if let Some(path) = std::mem::replace(pb, PathBuilder::new()).finish() {
            pixmap.stroke_path(&path, &paint, &stroke, t, None);
        }
        *segments = 0;
    };
    let mut dots = Vec::new();
    for sp in subpaths {
        let Some(first) = sp.first() else {
            continue;
        };
        if sp.iter().all(|p| p == first) {
            dots.push(*first);
            continue;
        }
        let closing = closed.then_some(first);
        for (k, p) in sp.iter().chain(closing).enumerate() {
            if k == 0 {
                pb.move_to(p.x as f32, p.y as f32);
                continue;
            }
            pb.line_to(p.x as f32, p.y as f32);
            segments += 1;
            if segments >= PIECE_POINTS {
                flush(&mut pb, &mut segments);
                pb.move_to(p.x as f32, p.y as f32);
            }
        }
    }
    flush(&mut pb, &mut segments);
    if style.round_caps {
        let r = 0.5 * style.stroke_width.unwrap_or(1.0);
        for d in dots {
            if let Some(dot) = PathBuilder::from_circle(d.x as f32, d.y as f32, r as f32) {
                pixmap.fill_path(&dot, &paint, FillRule::Winding, t, None);
            }
        }
    }
}

/// Sets the text elements of `svg` (a page of the drawing's size holding only text) onto
/// the pixmap with usvg and resvg, fonts from the system.
fn draw_text(pixmap: &mut Pixmap, svg: String, w: u32, h: u32) {
    let mut opt = resvg::usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    // The document is ours and holds only text: it parses.
    let Ok(tree) = resvg::usvg::Tree::from_str(&svg, &opt) else {
        return;
    };
    let page = tree.size();
    let t = Transform::from_scale(w as f32 / page.width(), h as f32 / page.height());
    resvg::render(&tree, t, &mut pixmap.as_mut());
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pixel(p: &Pixmap, x: u32, y: u32) -> [u8; 3] {
        let c = p.pixel(x, y).expect("inside");
        [c.red(), c.green(), c.blue()]
    }

    /// One drawing, two backends: the SVG carries the styles (inherited from groups) as
    /// attributes, and the pixmap paints the same shapes where the SVG puts them.
    #[test]
    fn svg_and_pixmap_draw_the_same_shapes() {
        let red = Rgb(0xc0, 0x10, 0x20);
        let mut d = Drawing::new(100.0, 50.0);
        d.open("g", Style::stroked(red, 4.0).round(), &[("data-name", "x")]);
        // A horizontal line at y = 10 from x = 10 to 90 and a dot at (50, 40).
        d.polyline(
            "line",
            vec![DVec2::new(10.0, 10.0), DVec2::new(90.0, 10.0)],
            false,
            Style::default(),
            Some("l1".into()),
        );
        d.polyline(
            "dot",
            vec![DVec2::new(50.0, 40.0), DVec2::new(50.0, 40.0)],
            false,
            Style::default(),
            None,
        );
        d.close();
        d.circle(
            "c",
            DVec2::new(80.0, 35.0),
            5.0,
            Style::filled(Rgb(0, 0x80, 0)),
            None,
        );
        let svg = d.to_svg();
        let doc = roxmltree::Document::parse(&svg).expect("parses");
        let g = doc
            .descendants()
            .find(|n| n.attribute("id") == Some("g"))
            .expect("group");
        assert_eq!(g.attribute("stroke"), Some("#c01020"));
        assert_eq!(g.attribute("stroke-width"), Some("4"));
        assert_eq!(g.attribute("stroke-linecap"), Some("round"));
        assert_eq!(g.attribute("fill"), Some("none"));
        assert_eq!(g.attribute("data-name"), Some("x"));
        let l = doc
            .descendants()
            .find(|n| n.attribute("id") == Some("l1"))
            .expect("line");
        assert_eq!(l.attribute("d"), Some("M10 10 L90 10"));
        // 2 pixels per mm.
        let p = d.to_pixmap(200, 100).expect("pixmap");
        assert_eq!(pixel(&p, 100, 20), [0xc0, 0x10, 0x20], "on the line");
        assert_eq!(pixel(&p, 100, 30), [255, 255, 255], "5 mm off it");
        // The round cap reaches 2 mm past the end, not 3.
        assert_eq!(pixel(&p, 182, 20), [0xc0, 0x10, 0x20]);
        assert_eq!(pixel(&p, 187, 20), [255, 255, 255]);
        assert_eq!(pixel(&p, 100, 80), [0xc0, 0x10, 0x20], "the dot");
        assert_eq!(pixel(&p, 160, 70), [0, 0x80, 0], "the filled circle");
        // Without a group, SVG's initial values: a closed path is filled black.
        let mut d = Drawing::new(10.0, 10.0);
        let sq = vec![
            DVec2::new(2.0, 2.0),
            DVec2::new(8.0, 2.0),
            DVec2::new(8.0, 8.0),
            DVec2::new(2.0, 8.0),
        ];
        d.polyline("sq", sq, true, Style::default(), None);
        let p = d.to_pixmap(10, 10).expect("pixmap");
        assert_eq!(pixel(&p, 5, 5), [0, 0, 0]);
        assert_eq!(pixel(&p, 0, 0), [255, 255, 255]);
    }

    /// A long polyline is stroked in pieces: the pieces join without gaps.
    #[test]
    fn long_polylines_are_stroked_without_gaps() {
        let n = 10 * PIECE_POINTS;
        let pts: Vec<DVec2> = (0..=n)
            .map(|i| DVec2::new(5.0 + 90.0 * i as f64 / n as f64, 5.0))
            .collect();
        let mut d = Drawing::new(100.0, 10.0);
        d.polyline("l", pts, false, Style::stroked(Rgb(0, 0, 0), 2.0), None);
        let p = d.to_pixmap(100, 10).expect("pixmap");
        for x in 6..95 {
            assert_eq!(pixel(&p, x, 5), [0, 0, 0], "x = {x}");
        }
    }

    #[test]
    fn styles_inherit_what_they_leave_unset() {
        let parent = Style {
            dash: Some([1.0, 2.0]),
            ..Style::stroked(Rgb(1, 2, 3), 0.5).round()
        };
        let child = Style {
            stroke: Some(Paint::Color(Rgb(9, 9, 9))),
            ..Style::default()
        };
        let s = child.over(&parent);
        assert_eq!(s.stroke, Some(Paint::Color(Rgb(9, 9, 9))));
        assert_eq!(s.stroke_width, Some(0.5));
        assert_eq!(s.dash, Some([1.0, 2.0]));
        assert!(s.round_caps && s.round_joins);
        assert_eq!(s.fill, Some(Paint::None));
        assert_eq!(Rgb(0x0a, 0xb0, 0xff).hex(), "#0ab0ff");
    }
}
