//! Library-level tests: design loading and SVG import, skins, outlines, toolpaths,
//! emitters, previews and text, each checked against independent computation (most through
//! the public API, a few through the built binary where the result is a file).
//!
//! One test binary; each module was once a file of its own under tests/.

#[path = "../support/mod.rs"]
mod support;

mod api_embed;
mod attrs_brush;
mod corners;
mod emit_dxf;
mod emit_gcode;
mod emit_svg;
mod examples_skin;
mod import_svg;
mod line_op;
mod order_machine;
mod outline_re;
mod preview_html;
mod preview_svg_png;
mod re_route;
mod robust_channels;
mod shapes;
mod skin_coverage;
mod skin_push_back;
mod skin_total;
mod spine_only;
mod svg_real_fidelity;
mod text_fonts;
mod text_glyphs;
