//! The preview as PNG: the drawing of [`super::svg::scene_drawing`] rasterised directly by
//! tiny-skia ([`Drawing::to_pixmap`]), so the SVG and the PNG show the same picture. The
//! image size is checked from the drawing's layout before anything is drawn, and the drawing
//! is detailed to the image's pixel. Rasterising needs the `png` feature; without it
//! [`scene_png`] checks the size and returns [`EmitError::FeatureDisabled`].

use super::Scene;
use super::draw::Drawing;
use super::svg::{Detail, Layout, SvgOptions, scene_drawing};
use crate::emit::EmitError;

/// Millimetres per inch, for `--dpi`.
const MM_PER_INCH: f64 = 25.4;
/// Largest raster side accepted, pixels (a 16k × 16k RGBA image is 1 GiB).
pub const MAX_SIDE: u32 = 16384;

/// Size of the raster.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
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

/// Pixels per page millimetre of a page `page_width` mm wide at `size`.
pub fn pixels_per_mm(page_width: f64, size: PngOptions) -> Result<f64, EmitError> {
    match size {
        PngOptions::Width(w) => {
            if w == 0 || w > MAX_SIDE {
                return Err(EmitError::InvalidOption {
                    name: "width",
                    reason: format!("must be 1..={MAX_SIDE} pixels, got {w}"),
                });
            }
            Ok(w as f64 / page_width)
        }
        PngOptions::Dpi(d) => {
            if !(d.is_finite() && d > 0.0) {
                return Err(EmitError::InvalidOption {
                    name: "dpi",
                    reason: format!("must be a positive number, got {d}"),
                });
            }
            Ok(d / MM_PER_INCH)
        }
    }
}

/// The pixel size of a `width` × `height` mm page at `scale` pixels per mm: each side
/// rounded, 1..=[`MAX_SIDE`]; `at_least` says the height is a lower bound (the legend is
/// not laid out yet).
fn image_size(
    width: f64,
    height: f64,
    scale: f64,
    at_least: bool,
) -> Result<(u32, u32), EmitError> {
    let w = (width * scale).round();
    let h = (height * scale).round();
    if !(w >= 1.0 && h >= 1.0 && w <= MAX_SIDE as f64 && h <= MAX_SIDE as f64) {
        let bound = if at_least { "at least " } else { "" };
        return Err(EmitError::InvalidOption {
            name: "size",
            reason: format!(
                "the image would be {bound}{w} x {h} pixels; choose a size or DPI giving \
                 1..={MAX_SIDE} pixels a side"
            ),
        });
    }
    Ok((w as u32, h as u32))
}

/// Checks that a drawing laid out as `layout` (its legend not yet counted) gives an image
/// within the limits at `size`: what can be known from the program's bounds before it is
/// checked or drawn.
pub fn check_size(layout: &Layout, size: PngOptions) -> Result<(), EmitError> {
    let scale = pixels_per_mm(layout.width, size)?;
    image_size(layout.width, layout.drawing_height, scale, true).map(|_| ())
}

/// The preview PNG of `scene`: laid out, its size checked, drawn to the image's pixel and
/// rasterised.
pub fn scene_png(scene: &Scene, opts: &SvgOptions, size: PngOptions) -> Result<Vec<u8>, EmitError> {
    let layout = Layout::of(scene, opts);
    check_size(&layout, size)?;
    let scale = pixels_per_mm(layout.width, size)?;
    let detail = Detail {
        pixel: 1.0 / scale,
        raster: true,
    };
    rasterize(&scene_drawing(scene, opts, &layout, &detail), scale)
}

/// PNG bytes of `drawing` at `scale` pixels per page millimetre.
#[cfg(feature = "png")]
pub fn rasterize(drawing: &Drawing, scale: f64) -> Result<Vec<u8>, EmitError> {
    let (w, h) = image_size(drawing.width, drawing.height, scale, false)?;
    let pixmap = drawing
        .to_pixmap(w, h)
        .ok_or_else(|| EmitError::InvalidOption {
            name: "size",
            reason: format!("cannot allocate a {w} x {h} image"),
        })?;
    pixmap.encode_png().map_err(|e| EmitError::InvalidOption {
        name: "png",
        reason: format!("PNG encoding failed: {e}"),
    })
}

/// Without the `png` feature there is no rasteriser: the size is still checked, then
/// [`EmitError::FeatureDisabled`].
#[cfg(not(feature = "png"))]
pub fn rasterize(drawing: &Drawing, scale: f64) -> Result<Vec<u8>, EmitError> {
    image_size(drawing.width, drawing.height, scale, false)?;
    Err(EmitError::FeatureDisabled {
        output: "PNG preview",
        feature: "png",
    })
}
