//! The drawing layer every skinpath picture goes through (the outline drawing and the
//! toolpath preview): world coordinates with y up mapped onto a page in millimetres, drawn
//! with the one SVG writer ([`SvgPage`]). The PNG is this SVG rasterised ([`super::png`]), so
//! there is no second drawing code.

pub use crate::emit::svg_page::{SvgPage, num};
use glam::DVec2;

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

    /// Page size of the framed world box.
    pub fn size(&self) -> DVec2 {
        (self.hi - self.lo) * self.scale
    }
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
