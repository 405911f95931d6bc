//! The preview as PNG: the SVG of [`super::svg`] rasterised by resvg (tiny-skia), so both
//! formats show the same picture. Text is set with a system font when one is installed
//! (DejaVu, Liberation, ...); without one the legend's words are left out and everything
//! else (cuts, numbers drawn as strokes, findings) still shows.

use crate::emit::EmitError;

/// CSS pixels per inch: SVG lengths in mm map to pixels at this resolution.
const CSS_DPI: f64 = 96.0;
/// Largest raster side accepted, pixels (a 16k × 16k RGBA image is 1 GiB).
pub const MAX_SIDE: u32 = 16384;

/// Size of the raster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PngOptions {
    /// Width in pixels; the height follows the page's aspect ratio.
    Width(u32),
    /// Resolution: pixels per inch of the page's millimetre size.
    Dpi(f64),
}

impl Default for PngOptions {
    fn default() -> Self {
        PngOptions::Width(1600)
    }
}

/// Rasterises `svg` to PNG bytes.
pub fn rasterize(svg: &str, size: PngOptions) -> Result<Vec<u8>, EmitError> {
    let mut opt = resvg::usvg::Options {
        dpi: CSS_DPI as f32,
        ..resvg::usvg::Options::default()
    };
    opt.fontdb_mut().load_system_fonts();
    let tree = resvg::usvg::Tree::from_str(svg, &opt).map_err(|e| EmitError::InvalidOption {
        name: "svg",
        reason: format!("the preview SVG could not be read back: {e}"),
    })?;
    let page = tree.size();
    let scale = match size {
        PngOptions::Width(w) => {
            if w == 0 || w > MAX_SIDE {
                return Err(EmitError::InvalidOption {
                    name: "width",
                    reason: format!("must be 1..={MAX_SIDE} pixels, got {w}"),
                });
            }
            w as f64 / page.width() as f64
        }
        PngOptions::Dpi(d) => {
            if !(d.is_finite() && d > 0.0) {
                return Err(EmitError::InvalidOption {
                    name: "dpi",
                    reason: format!("must be a positive number, got {d}"),
                });
            }
            d / CSS_DPI
        }
    };
    let w = (page.width() as f64 * scale).round();
    let h = (page.height() as f64 * scale).round();
    if !(w >= 1.0 && h >= 1.0 && w <= MAX_SIDE as f64 && h <= MAX_SIDE as f64) {
        return Err(EmitError::InvalidOption {
            name: "size",
            reason: format!(
                "the image would be {w} x {h} pixels; choose a size or DPI giving 1..={MAX_SIDE} \
                 pixels a side"
            ),
        });
    }
    let mut pixmap =
        resvg::tiny_skia::Pixmap::new(w as u32, h as u32).ok_or(EmitError::InvalidOption {
            name: "size",
            reason: format!("cannot allocate a {w} x {h} image"),
        })?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    let sx = w / page.width() as f64;
    let sy = h / page.height() as f64;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(sx as f32, sy as f32),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().map_err(|e| EmitError::InvalidOption {
        name: "png",
        reason: format!("PNG encoding failed: {e}"),
    })
}
