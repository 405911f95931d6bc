//! Digits drawn as strokes, so order numbers show in every renderer without a font (text
//! needs one, and none is shipped). Seven-segment shapes in a cell 0.6 wide and
//! 1 tall, y down.

use super::draw::num;
use glam::DVec2;
use std::fmt::Write as _;

/// Stroke width as a fraction of the digit height.
pub const STROKE: f64 = 0.14;
/// Advance per digit as a fraction of the height.
const ADVANCE: f64 = 0.8;
/// Digit width as a fraction of the height.
const WIDTH: f64 = 0.55;

/// Segment end points (a..g of a seven-segment digit) in the unit cell.
const SEGMENTS: [[(f64, f64); 2]; 7] = [
    [(0.0, 0.0), (1.0, 0.0)], // a top
    [(1.0, 0.0), (1.0, 0.5)], // b upper right
    [(1.0, 0.5), (1.0, 1.0)], // c lower right
    [(0.0, 1.0), (1.0, 1.0)], // d bottom
    [(0.0, 0.5), (0.0, 1.0)], // e lower left
    [(0.0, 0.0), (0.0, 0.5)], // f upper left
    [(0.0, 0.5), (1.0, 0.5)], // g middle
];

/// Segments lit per digit, bits a..g.
const DIGITS: [u8; 10] = [
    0b0111111, 0b0000110, 0b1011011, 0b1001111, 0b1100110, 0b1101101, 0b1111101, 0b0000111,
    0b1111111, 0b1101111,
];

/// The dash between the numbers of a range: the middle segment.
const DASH: u8 = 0b1000000;

/// Width of `text` (digits) drawn `height` tall.
pub fn width(text: &str, height: f64) -> f64 {
    let k = text.chars().count() as f64;
    if k == 0.0 {
        0.0
    } else {
        height * (ADVANCE * (k - 1.0) + WIDTH)
    }
}

/// The stroke segments of the digits of `text` (other characters are skipped), centred on
/// `center`, `height` tall (y down).
pub fn number_segments(text: &str, center: DVec2, height: f64) -> Vec<[DVec2; 2]> {
    let w = width(text, height);
    let origin = center - DVec2::new(0.5 * w, 0.5 * height);
    let mut out = Vec::new();
    for (i, ch) in text.chars().enumerate() {
        let bits = match ch {
            '-' => DASH,
            c => match c.to_digit(10) {
                Some(v) => DIGITS[v as usize],
                None => continue,
            },
        };
        let cell = origin + DVec2::new(i as f64 * ADVANCE * height, 0.0);
        for (s, seg) in SEGMENTS.iter().enumerate() {
            if bits & (1 << s) != 0 {
                let p = |(x, y): (f64, f64)| cell + DVec2::new(x * WIDTH * height, y * height);
                out.push([p(seg[0]), p(seg[1])]);
            }
        }
    }
    out
}

/// Path data of [`number_segments`].
pub fn number_path(text: &str, center: DVec2, height: f64) -> String {
    let mut d = String::new();
    for [a, b] in number_segments(text, center, height) {
        let _ = write!(
            d,
            "{}M{} {} L{} {}",
            if d.is_empty() { "" } else { " " },
            num(a.x),
            num(a.y),
            num(b.x),
            num(b.y)
        );
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_lights_every_segment_one_two() {
        assert_eq!(number_path("8", DVec2::ZERO, 1.0).matches('M').count(), 7);
        assert_eq!(number_path("1", DVec2::ZERO, 1.0).matches('M').count(), 2);
        assert_eq!(number_path("10", DVec2::ZERO, 1.0).matches('M').count(), 8);
        assert!((width("12", 10.0) - 13.5).abs() < 1e-12);
        assert_eq!(number_path("1-2", DVec2::ZERO, 1.0).matches('M').count(), 8);
    }
}
