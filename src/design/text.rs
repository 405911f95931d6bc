//! Single-stroke text: `[[text]]` in a design, laid out into strokes when the design is
//! loaded.
//!
//! ```toml
//! [[text]]
//! name = "sign"               # strokes are called sign/<char index>:<char>/<k>
//! text = "OPEN\nlate"         # lines split at \n; printable ASCII and Latin-1 letters
//! font = "sans"               # "sans" (Hershey Roman Simplex) | "script" (joining letters)
//! height = 80.0               # cap height: baseline to cap line, design units
//! width = 8.0                 # stroke width (twice the radius)
//! at = [0.0, 0.0]             # anchor on the first line's baseline; default [0, 0]
//! align = "left"              # "left" | "centre" | "right" (about `at`); default "left"
//! letter_spacing = 0.0        # extra space between letters; default 0
//! line_spacing = 1.6          # baseline to baseline, in multiples of `height`; default 1.6
//! kerning = "auto"            # "auto" | "none"; default "auto"
//! ```
//!
//! The fonts are Hershey fonts (public domain; see `src/design/fonts/README.md`). Each glyph
//! is a set of polylines on an integer grid with a cap height of 21 units; advance widths
//! are the glyphs' left and right bounds. The Hershey fonts carry no kerning pairs, so with
//! `kerning = "auto"` (the default) each pair of neighbouring letters is kerned optically
//! from the glyphs' own strokes (see [`pair_kern`]): a pair that stands farther apart than
//! the font's own stem gap (the nearest distance between two "n"s) moves together until its
//! centre lines are that far apart, within a bounded shift ("AV", "To", "LT", "P.").
//! Script letters join at the advance, so the script font is never kerned.
//!
//! Besides printable ASCII the fonts have the Latin-1 letters (à to ÿ, À to Ý, ß, æ, Æ;
//! not Ð ð Þ þ) and the signs ¡ ¿ « » ° · and the no-break space, composed from the ASCII glyphs
//! ([`latin1`]: base letter plus mark strokes, placed by the glyph's box). Any other
//! character is refused, naming it and its position.
//!
//! Every pen-down polyline becomes a smooth stroke ([`smooth`]): cubic B-splines fitted by
//! least squares within [`smooth::FIT_TOLERANCE`] (2.4 % of the cap height) of the
//! polyline, G1 where the glyph is a curve, with a corner wherever the polyline turns by
//! more than [`smooth::FONT_CORNER_DEG`], and the polyline's end points and end directions
//! kept. A polyline that ends where it starts and has no corner is a closed stroke. In the
//! script font the letters' entry and exit strokes meet the neighbours' at the advance
//! (same point, same direction), so a word is one connected shape once the strokes are
//! united, and one smooth flex run.

use super::error::{DesignError, ErrorKind, Item, Part};
use super::model::{DEFAULT_DEGREE, Stroke};
use super::validate::{MAX_COORD, MIN_RADIUS};
use crate::geom::{DVec2, Line};
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

#[cfg(test)]
#[path = "fonts/tests.rs"]
mod font_tests;
#[path = "fonts/latin1.rs"]
pub(crate) mod latin1;
#[path = "fonts/smooth.rs"]
pub(crate) mod smooth;

/// Default distance between baselines, in multiples of the cap height: the Hershey fonts'
/// cap line to descender line is 28 units for a 21-unit cap height, plus a gap.
pub const DEFAULT_LINE_SPACING: f64 = 1.6;

/// Largest number of characters of a `[[text]]` element, line breaks included, and of
/// all the text of one design together: each visible character becomes a few strokes that
/// are skinned, offset and checked, and the build's cost grows faster than the length; a
/// longer text belongs in several jobs.
pub const MAX_TEXT_CHARS: usize = 2_000;

/// Smallest cap height, design units: 21 × [`MIN_RADIUS`], so that one unit of the 21-unit
/// Hershey grid is at least the smallest radius and a letter's points stay apart.
pub const MIN_HEIGHT: f64 = 2.1e-3;

/// How many distinct characters a missing-glyph error names.
const MISSING_SHOWN: usize = 8;

/// What is wrong with a `[[text]]` element ([`Text::problem`]): the key it concerns and the
/// problem, without the file or element (which the caller knows).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct TextProblem {
    /// The design-file key: `text`, `height`, `width`, `at`, `letter_spacing`,
    /// `line_spacing`.
    pub key: &'static str,
    /// What is wrong and the allowed range.
    pub message: String,
}

/// The total number of characters of `texts` ([`MAX_TEXT_CHARS`] for a whole design):
/// an error naming `file` and the element that passes the limit, checked before any text
/// is laid out.
pub fn check_total(texts: &[Text], file: &str) -> Result<(), DesignError> {
    let mut total = 0usize;
    for (index, t) in texts.iter().enumerate() {
        total += t.text.chars().count();
        if total > MAX_TEXT_CHARS {
            return Err(DesignError::at(
                file,
                Item::Text {
                    index,
                    name: t.name.clone(),
                },
                Some(Part::Key("text".into())),
                ErrorKind::Invalid(format!(
                    "the design's texts reach {total} characters here, more than the limit \
                     {MAX_TEXT_CHARS} (line breaks included)"
                )),
            ));
        }
    }
    Ok(())
}

/// Cap height of the Hershey glyph grid: cap line at −12, baseline at 9.
const HERSHEY_CAP: f64 = 21.0;
/// The baseline's y on the Hershey glyph grid (y grows downwards).
const HERSHEY_BASELINE: f64 = 9.0;

/// A single-stroke font.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Font {
    /// Hershey Roman Simplex (Futura Light): upright, one stroke per line.
    #[default]
    Sans,
    /// Hershey Script Simplex: slanted, joining lower-case letters.
    Script,
}

impl Font {
    /// Every shipped font.
    pub const ALL: [Font; 2] = [Font::Sans, Font::Script];

    /// The font's name in design files.
    pub fn as_str(self) -> &'static str {
        match self {
            Font::Sans => "sans",
            Font::Script => "script",
        }
    }

    fn data(self) -> &'static str {
        match self {
            Font::Sans => include_str!("fonts/futural.jhf"),
            Font::Script => include_str!("fonts/cursive.jhf"),
        }
    }

    /// The parsed glyphs (ASCII 32..=127), parsed once.
    pub fn glyphs(self) -> &'static [Glyph] {
        static SANS: OnceLock<Vec<Glyph>> = OnceLock::new();
        static SCRIPT: OnceLock<Vec<Glyph>> = OnceLock::new();
        let cell = match self {
            Font::Sans => &SANS,
            Font::Script => &SCRIPT,
        };
        cell.get_or_init(|| parse_jhf(self.data()))
    }

    /// The composed Latin-1 glyphs (U+00A0..=U+00FF, `None` where the font lacks one),
    /// composed once ([`latin1`]).
    fn latin1_glyphs(self) -> &'static [Option<Glyph>] {
        static SANS: OnceLock<Vec<Option<Glyph>>> = OnceLock::new();
        static SCRIPT: OnceLock<Vec<Option<Glyph>>> = OnceLock::new();
        let (cell, slant, joined) = match self {
            Font::Sans => (&SANS, 0.0, false),
            Font::Script => (&SCRIPT, latin1::SCRIPT_SLANT, true),
        };
        cell.get_or_init(|| {
            let ascii = |c: char| self.glyph(c).cloned();
            ('\u{a0}'..='\u{ff}')
                .map(|c| latin1::compose(c, &ascii, slant, joined))
                .collect()
        })
    }

    /// Index of `c` among the font's glyphs: ASCII 32..=127 first, then U+00A0..=U+00FF.
    fn glyph_index(c: char) -> Option<usize> {
        let code = c as usize;
        match code {
            32..128 => Some(code - 32),
            0xa0..=0xff => Some(code - 0xa0 + 96),
            _ => None,
        }
    }

    /// The glyph of `c`, if the font has it: printable ASCII, and the Latin-1 letters and
    /// signs of `latin1` (composed from the ASCII glyphs).
    pub fn glyph(self, c: char) -> Option<&'static Glyph> {
        let i = Self::glyph_index(c)?;
        if i < 96 {
            self.glyphs().get(i)
        } else {
            self.latin1_glyphs().get(i - 96)?.as_ref()
        }
    }

    /// The smooth spines of the glyph of `c` (`smooth`, within `smooth::FIT_TOLERANCE`
    /// of its polylines; grid units), fitted once per glyph.
    pub fn spines(self, c: char) -> Option<&'static [smooth::Spine]> {
        const GLYPHS: usize = 192;
        static SANS: [OnceLock<Vec<smooth::Spine>>; GLYPHS] = [const { OnceLock::new() }; GLYPHS];
        static SCRIPT: [OnceLock<Vec<smooth::Spine>>; GLYPHS] = [const { OnceLock::new() }; GLYPHS];
        let g = self.glyph(c)?;
        let cells = match self {
            Font::Sans => &SANS,
            Font::Script => &SCRIPT,
        };
        let cell = cells.get(Self::glyph_index(c)?)?;
        Some(cell.get_or_init(|| {
            glyph_grid_polylines(g)
                .iter()
                .filter_map(|p| smooth::fit_polyline(p, smooth::FIT_TOLERANCE))
                .collect()
        }))
    }
}

/// The glyph's polylines on its own grid (y down, unshifted).
fn glyph_grid_polylines(g: &Glyph) -> Vec<Vec<DVec2>> {
    g.strokes
        .iter()
        .map(|p| {
            p.iter()
                .map(|&[x, y]| DVec2::new(x as f64, y as f64))
                .collect()
        })
        .collect()
}

/// Horizontal alignment of each line about the anchor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Align {
    /// `"left"`: lines start at the anchor.
    #[default]
    Left,
    /// `"centre"` (or `"center"`): lines are centred on the anchor.
    #[serde(alias = "center")]
    Centre,
    /// `"right"`: lines end at the anchor.
    Right,
}

/// One glyph of a Hershey font, on its grid (y down).
#[derive(Clone, Debug, PartialEq)]
pub struct Glyph {
    /// Left bound.
    pub left: i32,
    /// Right bound; the advance width is right − left.
    pub right: i32,
    /// Pen-down polylines.
    pub strokes: Vec<Vec<[i32; 2]>>,
}

/// Parse a `.jhf` file (format in `src/design/fonts/README.md`). The shipped files are
/// checked by the tests; a malformed line gives an empty glyph.
fn parse_jhf(text: &str) -> Vec<Glyph> {
    text.lines()
        .filter(|l| !l.starts_with('#') && l.len() >= 10)
        .map(|l| {
            let b = l.as_bytes();
            let coord = |c: u8| c as i32 - b'R' as i32;
            let mut glyph = Glyph {
                left: coord(b[8]),
                right: coord(b[9]),
                strokes: Vec::new(),
            };
            let mut cur: Vec<[i32; 2]> = Vec::new();
            for pair in b[10..].chunks(2) {
                if pair.len() < 2 {
                    break;
                }
                if pair == b" R" {
                    if !cur.is_empty() {
                        glyph.strokes.push(std::mem::take(&mut cur));
                    }
                } else {
                    cur.push([coord(pair[0]), coord(pair[1])]);
                }
            }
            if !cur.is_empty() {
                glyph.strokes.push(cur);
            }
            glyph
        })
        .collect()
}

/// A `[[text]]` element (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Text {
    /// `name` (required): the prefix of the generated strokes' names
    /// (`<name>/<char index>:<char>/<k>`); operations' `strokes` lists may name the text to
    /// mean all of its strokes.
    pub name: String,
    /// `text` (required): the characters to set, lines split at `\n`; printable ASCII
    /// (space to `~`) and the Latin-1 letters and signs of `latin1` only, with at least
    /// one visible character; at most
    /// [`MAX_TEXT_CHARS`] characters (line breaks included), in one element and in all the
    /// texts of a design together.
    pub text: String,
    /// `font`: `"sans"` or `"script"`; default `sans`.
    #[serde(default)]
    pub font: Font,
    /// `height` (required): cap height (baseline to cap line), design units,
    /// [`MIN_HEIGHT`] to [`MAX_COORD`].
    pub height: f64,
    /// `width` (required): stroke width (twice the stroke radius), design units,
    /// 2·[`MIN_RADIUS`] to [`MAX_COORD`].
    pub width: f64,
    /// `at`: anchor `[x, y]` on the first line's baseline, finite; default [0, 0].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<[f64; 2]>,
    /// `align`: alignment of each line about `at`; default `left`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub align: Option<Align>,
    /// `letter_spacing`: extra space between letters, design units, finite (may be
    /// negative); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub letter_spacing: Option<f64>,
    /// `line_spacing`: baseline to baseline, in multiples of `height`, > 0; default
    /// [`DEFAULT_LINE_SPACING`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line_spacing: Option<f64>,
    /// `kerning`: `"auto"` or `"none"`, kerning of neighbouring letters; default
    /// [`Kerning::Auto`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kerning: Option<Kerning>,
}

/// How neighbouring letters are spaced beyond their advance widths.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kerning {
    /// Optical kerning from the glyphs' strokes (`pair_kern`); the script font is not
    /// kerned (its letters join at the advance).
    #[default]
    Auto,
    /// Advance widths only.
    None,
}

impl Kerning {
    /// The value's name in design files.
    pub fn as_str(self) -> &'static str {
        match self {
            Kerning::Auto => "auto",
            Kerning::None => "none",
        }
    }
}

/// The largest distance (Hershey grid units, cap height 21) [`pair_kern`] moves a letter
/// towards its left neighbour: a quarter of the cap height, about what typographers give
/// "AV" or "LT". Bounds the kern where the letters never reach the target gap (a letter
/// passing under an overhang).
pub const MAX_TIGHTEN: f64 = 5.25;
/// Resolution of the kern (grid units): the search steps by this and a kern is a multiple
/// of it, so layouts do not depend on rounding.
pub const KERN_STEP: f64 = 0.125;

/// Smallest distance between the segments of two sets of polylines (grid units), the
/// second set shifted by `dx` along x ([`Line::distance_to_line`] over all pairs).
fn polylines_distance(a: &[Vec<DVec2>], b: &[Vec<DVec2>], dx: f64) -> f64 {
    let shift = DVec2::new(dx, 0.0);
    let segments = |polys: &[Vec<DVec2>], by: DVec2| -> Vec<Line> {
        polys
            .iter()
            .flat_map(|p| {
                let single = (p.len() == 1).then(|| Line::new(p[0] + by, p[0] + by));
                p.windows(2)
                    .map(move |w| Line::new(w[0] + by, w[1] + by))
                    .chain(single)
            })
            .collect()
    };
    let (sa, sb) = (segments(a, DVec2::ZERO), segments(b, shift));
    let mut best = f64::INFINITY;
    for s in &sa {
        for t in &sb {
            best = best.min(s.distance_to_line(t));
        }
    }
    best
}

/// The glyph's polylines on its grid with the pen at 0 (x − left), y as in the font.
fn glyph_polylines(g: &Glyph) -> Vec<Vec<DVec2>> {
    g.strokes
        .iter()
        .map(|p| {
            p.iter()
                .map(|&[x, y]| DVec2::new((x - g.left) as f64, y as f64))
                .collect()
        })
        .collect()
}

/// Optical kern of the pair `a` `b` (grid units, added to `a`'s advance, never positive):
/// letters whose centre lines are farther apart than `gap` at their advance move together in
/// steps of [`KERN_STEP`], at most [`MAX_TIGHTEN`], until one more step would come closer
/// than `gap` (the first such shift, so a letter never slides under its neighbour's
/// overhang). Letters are never moved apart: pairs with open sides ("EN", "OO") are nearest
/// at a corner or a bulge and look right at their advance. Empty glyphs (space) are not
/// kerned. O(n·m·k) for glyphs of n and m segments and k steps.
pub fn pair_kern(a: &Glyph, b: &Glyph, gap: f64) -> f64 {
    let (pa, pb) = (glyph_polylines(a), glyph_polylines(b));
    if pa.iter().all(|p| p.is_empty()) || pb.iter().all(|p| p.is_empty()) {
        return 0.0;
    }
    let advance = (a.right - a.left) as f64;
    let d = |k: f64| polylines_distance(&pa, &pb, advance + k);
    let mut kern = 0.0;
    for i in 1..=(MAX_TIGHTEN / KERN_STEP).round() as i32 {
        let k = -(i as f64) * KERN_STEP;
        if d(k) < gap {
            break;
        }
        kern = k;
    }
    kern
}

impl Font {
    /// The font's stem gap (grid units): the nearest distance between two "n"s at their
    /// advance, the target of `pair_kern`.
    pub fn stem_gap(self) -> f64 {
        match self.glyph('n') {
            Some(n) => polylines_distance(
                &glyph_polylines(n),
                &glyph_polylines(n),
                (n.right - n.left) as f64,
            ),
            None => 0.0,
        }
    }
}

/// The name part of a character in stroke names: letters and digits as they are, anything
/// else as `u` and its hexadecimal code (names end up in SVG and G-code comments).
fn char_tag(c: char) -> String {
    if c.is_ascii_alphanumeric() {
        c.to_string()
    } else {
        format!("u{:02x}", c as u32)
    }
}

impl Text {
    /// A text element with default font, anchor, alignment and spacing.
    #[must_use]
    pub fn new(name: &str, text: &str, height: f64, width: f64) -> Self {
        Text {
            name: name.to_string(),
            text: text.to_string(),
            font: Font::default(),
            height,
            width,
            at: None,
            align: None,
            letter_spacing: None,
            line_spacing: None,
            kerning: None,
        }
    }

    /// The pen advance after each character of `line` (design units): its advance width,
    /// the kern with the next letter ([`pair_kern`], when kerning applies) and the letter
    /// spacing. Characters missing from the font advance by 0.
    fn advances(&self, line: &str) -> Vec<f64> {
        let s = self.scale();
        let spacing = self.letter_spacing.unwrap_or(0.0);
        let kerned = self.font != Font::Script && self.kerning.unwrap_or_default() == Kerning::Auto;
        let gap = if kerned { self.font.stem_gap() } else { 0.0 };
        let chars: Vec<char> = line.chars().collect();
        let glyphs: Vec<Option<&Glyph>> = chars.iter().map(|&c| self.font.glyph(c)).collect();
        let mut memo = std::collections::HashMap::new();
        glyphs
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let Some(g) = g else { return 0.0 };
                let next = glyphs.get(i + 1).copied().flatten();
                let kern = match next {
                    Some(n) if kerned => *memo
                        .entry((chars[i], chars[i + 1]))
                        .or_insert_with(|| pair_kern(g, n, gap)),
                    _ => 0.0,
                };
                let last = i + 1 == glyphs.len();
                (g.right - g.left) as f64 * s + kern * s + if last { 0.0 } else { spacing }
            })
            .collect()
    }

    /// The error of this text (the `index`-th of `file`) for problem `p`, at `p`'s key.
    fn error(&self, file: &str, index: usize, p: TextProblem) -> DesignError {
        DesignError::at(
            file,
            Item::Text {
                index,
                name: self.name.clone(),
            },
            Some(Part::Key(p.key.into())),
            ErrorKind::Invalid(p.message),
        )
    }

    fn check(&self, file: &str, index: usize) -> Result<(), DesignError> {
        match self.problem() {
            None => Ok(()),
            Some(p) => Err(self.error(file, index, p)),
        }
    }

    /// The first problem with the element's values, or `None`: checked before any layout,
    /// in O(characters). The ranges: at most [`MAX_TEXT_CHARS`] characters with at least
    /// one visible, every one in the font; `height` within [`MIN_HEIGHT`]..=[`MAX_COORD`],
    /// `width` within 2·[`MIN_RADIUS`]..=[`MAX_COORD`], `at` within ±[`MAX_COORD`],
    /// `letter_spacing` finite within ±[`MAX_COORD`], `line_spacing` in (0, [`MAX_COORD`]].
    /// `skinpath text` shows the same problems under its option names.
    #[must_use]
    pub fn problem(&self) -> Option<TextProblem> {
        let bad = |key: &'static str, message: String| Some(TextProblem { key, message });
        let chars = self.text.chars().count();
        if chars > MAX_TEXT_CHARS {
            return bad(
                "text",
                format!(
                    "{chars} characters, more than the limit {MAX_TEXT_CHARS} (line breaks \
                     included); split the text"
                ),
            );
        }
        // Lengths are bounded like every other design length (MAX_COORD): a letter 1e300
        // high would lay out to infinite coordinates; below MIN_HEIGHT a letter's grid
        // points fall together and it has no stroke left.
        let min_width = 2.0 * MIN_RADIUS;
        for (key, v, min) in [
            ("height", self.height, MIN_HEIGHT),
            ("width", self.width, min_width),
        ] {
            if !(v.is_finite() && (min..=MAX_COORD).contains(&v)) {
                let why = if key == "height" {
                    "the smallest radius times the font's 21-unit cap height"
                } else {
                    "twice the smallest radius"
                };
                return bad(
                    key,
                    format!("{v:?} must be a number from {min:?} ({why}) to {MAX_COORD}"),
                );
            }
        }
        if let Some(at) = self.at
            && !at.iter().all(|v| v.abs() <= MAX_COORD)
        {
            return bad(
                "at",
                format!("{at:?} must be two numbers within ±{MAX_COORD}"),
            );
        }
        if let Some(s) = self.letter_spacing
            && !(s.is_finite() && s.abs() <= MAX_COORD)
        {
            return bad(
                "letter_spacing",
                format!("{s:?} must be a number within ±{MAX_COORD}"),
            );
        }
        if let Some(s) = self.line_spacing
            && !(s.is_finite() && s > 0.0 && s <= MAX_COORD)
        {
            return bad(
                "line_spacing",
                format!("{s:?} must be a positive number of at most {MAX_COORD}"),
            );
        }
        let mut missing: Vec<char> = Vec::new();
        let mut first = None;
        for (i, c) in self.text.chars().enumerate() {
            if c != '\n' && self.font.glyph(c).is_none() {
                first.get_or_insert((i, c));
                if !missing.contains(&c) && missing.len() < MISSING_SHOWN {
                    missing.push(c);
                }
            }
        }
        if let Some((i, c)) = first {
            let list: Vec<String> = missing
                .iter()
                .map(|c| format!("{c:?} (U+{:04X})", *c as u32))
                .collect();
            return bad(
                "text",
                format!(
                    "font \"{}\" lacks {}{} (first at character {i}, {c:?}): it has printable \
                     ASCII (space to ~), the Latin-1 letters but Ð ð Þ þ, and ¡ ¿ « » ° · only",
                    self.font.as_str(),
                    list.join(", "),
                    if missing.len() == MISSING_SHOWN {
                        ", ..."
                    } else {
                        ""
                    },
                ),
            );
        }
        if self.text.trim().is_empty() {
            return bad("text", "the text has no visible character".into());
        }
        None
    }

    /// Design units per Hershey grid unit.
    pub fn scale(&self) -> f64 {
        self.height / HERSHEY_CAP
    }

    /// Width of one line of text (advances plus letter spacing), design units.
    #[must_use]
    pub fn line_width(&self, line: &str) -> f64 {
        self.advances(line).iter().sum()
    }

    /// Where each character goes: its index in the text, the character, its glyph, and
    /// the map of its grid points into design coordinates, (x, y) ↦ (x0 + x·s,
    /// baseline − (y − 9)·s) with s = [`Text::scale`], as (x0, baseline).
    fn placements(&self) -> Vec<(usize, char, &'static Glyph, [f64; 2])> {
        let s = self.scale();
        let at = self.at.unwrap_or([0.0, 0.0]);
        let pitch = self.line_spacing.unwrap_or(DEFAULT_LINE_SPACING) * self.height;
        let mut out = Vec::new();
        let mut index = 0;
        for (row, line) in self.text.split('\n').enumerate() {
            let advances = self.advances(line);
            let w: f64 = advances.iter().sum();
            let mut pen = match self.align.unwrap_or_default() {
                Align::Left => at[0],
                Align::Centre => at[0] - 0.5 * w,
                Align::Right => at[0] - w,
            };
            let baseline = at[1] - row as f64 * pitch;
            for (c, advance) in line.chars().zip(advances) {
                if let Some(g) = self.font.glyph(c) {
                    out.push((index, c, g, [pen - g.left as f64 * s, baseline]));
                    pen += advance;
                }
                index += 1;
            }
            index += 1; // the newline
        }
        out
    }

    /// The design point of grid point `p` of a glyph placed at `origin` (see
    /// [`Text::placements`]).
    fn place(&self, origin: [f64; 2], p: DVec2) -> DVec2 {
        let s = self.scale();
        DVec2::new(
            origin[0] + p.x * s,
            origin[1] - (p.y - HERSHEY_BASELINE) * s,
        )
    }

    /// The laid-out polylines: for every character (index into the text, char) its
    /// glyph's pen-down polylines in design coordinates (y up).
    #[must_use]
    pub fn layout(&self) -> Vec<(usize, char, Vec<Vec<DVec2>>)> {
        self.placements()
            .into_iter()
            .map(|(i, c, g, origin)| {
                let polys = glyph_grid_polylines(g)
                    .into_iter()
                    .map(|p| p.into_iter().map(|q| self.place(origin, q)).collect())
                    .collect();
                (i, c, polys)
            })
            .collect()
    }

    /// The laid-out smooth spines (`smooth`): for every character its glyph's spines in
    /// design coordinates (y up), as [`Text::layout`] places the polylines.
    pub fn layout_spines(&self) -> Vec<(usize, char, Vec<smooth::Spine>)> {
        self.placements()
            .into_iter()
            .map(|(i, c, _, origin)| {
                let spines = self
                    .font
                    .spines(c)
                    .unwrap_or_default()
                    .iter()
                    .map(|sp| sp.map(|q| self.place(origin, q)))
                    .collect();
                (i, c, spines)
            })
            .collect()
    }

    /// The laid-out spines as point lists in the shape of [`Text::layout`]: their control
    /// polygons when `control` (whose hull holds each curve), else points along the
    /// curves (`smooth::Spine::samples`).
    #[must_use]
    pub fn spine_layout(&self, control: bool) -> Vec<(usize, char, Vec<Vec<DVec2>>)> {
        self.layout_spines()
            .into_iter()
            .map(|(i, c, spines)| {
                let pts = spines
                    .iter()
                    .map(|sp| {
                        if control {
                            sp.ctrl.clone()
                        } else {
                            sp.samples()
                        }
                    })
                    .collect();
                (i, c, pts)
            })
            .collect()
    }

    /// The text's strokes (see the module docs); `file` and `index` name it in errors.
    pub fn to_strokes(&self, file: &str, index: usize) -> Result<Vec<Stroke>, DesignError> {
        self.check(file, index)?;
        let r = 0.5 * self.width;
        if let Some(p) = layout_problem(&self.spine_layout(true), r) {
            return Err(self.error(file, index, p));
        }
        let mut out = Vec::new();
        for (i, c, spines) in self.layout_spines() {
            for (k, mut spine) in spines.into_iter().enumerate() {
                smooth::split_returning(&mut spine, r);
                let name = format!("{}/{}:{}/{}", self.name, i, char_tag(c), k);
                out.push(spine_stroke(&name, &spine, r));
            }
        }
        Ok(out)
    }
}

/// The stroke of radius `r` whose control disks are the spine's control points: loading
/// splits it at the spine's corners into pieces on clamped uniform knots, the curves of
/// [`smooth::Spine::curves`].
fn spine_stroke(name: &str, spine: &smooth::Spine, r: f64) -> Stroke {
    let disks = spine.ctrl.iter().map(|p| [p.x, p.y, r]).collect();
    let mut s = Stroke::from_disks(name, disks);
    s.degree = DEFAULT_DEGREE
        .min(spine.ctrl.len().saturating_sub(1))
        .max(1);
    s.closed = spine.closed;
    s.corners = (!spine.corners.is_empty()).then(|| spine.corners.clone());
    s
}

/// The problem of a laid-out text ([`Text::layout`]) whose strokes of radius `r` reach
/// beyond ±[`MAX_COORD`] (a large height times a large line spacing), or `None`.
pub fn layout_problem(layout: &[(usize, char, Vec<Vec<DVec2>>)], r: f64) -> Option<TextProblem> {
    let far = layout
        .iter()
        .flat_map(|(_, _, polys)| polys.iter().flatten())
        .find(|p| !(p.x.abs() + r <= MAX_COORD && p.y.abs() + r <= MAX_COORD))?;
    Some(TextProblem {
        key: "text",
        message: format!(
            "the lettering reaches ({:.1}, {:.1}), beyond ±{MAX_COORD}: give a smaller height, \
             line_spacing or letter_spacing, or an `at` nearer the origin",
            far.x, far.y
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_beyond_the_design_limit_are_refused_by_key() {
        let ok = Text::new("t", "OPEN", 20.0, 1.0);
        assert!(ok.check("f.toml", 0).is_ok());
        type Spoil = fn(&mut Text);
        let cases: [(&str, Spoil); 6] = [
            ("height", |t| t.height = 1e300),
            ("width", |t| t.width = 2.0 * MAX_COORD),
            ("at", |t| t.at = Some([0.0, -1e8])),
            ("letter_spacing", |t| t.letter_spacing = Some(f64::NAN)),
            ("letter_spacing", |t| t.letter_spacing = Some(-1e9)),
            ("line_spacing", |t| t.line_spacing = Some(f64::INFINITY)),
        ];
        for (key, spoil) in cases {
            let mut t = ok.clone();
            spoil(&mut t);
            let e = t.check("f.toml", 0).expect_err(key).to_string();
            assert!(e.contains("f.toml") && e.contains(key), "{key}: {e}");
        }
    }

    #[test]
    fn limits_are_checked_before_layout_and_named() {
        assert!((MIN_HEIGHT - HERSHEY_CAP * MIN_RADIUS).abs() < 1e-15);
        let ok = Text::new(
            "t",
            &"A".repeat(MAX_TEXT_CHARS),
            MIN_HEIGHT,
            2.0 * MIN_RADIUS,
        );
        assert_eq!(ok.problem(), None);
        let long = Text::new("t", &"A".repeat(MAX_TEXT_CHARS + 1), 10.0, 1.0);
        let p = long.problem().unwrap();
        assert_eq!(p.key, "text");
        assert!(
            p.message.contains(&MAX_TEXT_CHARS.to_string()),
            "{}",
            p.message
        );
        let p = Text::new("t", "AV", MIN_HEIGHT * 0.99, 1.0)
            .problem()
            .unwrap();
        assert_eq!(p.key, "height");
        let p = Text::new("t", "AV", 1.0, MIN_RADIUS).problem().unwrap();
        assert_eq!(p.key, "width");
        let p = Text::new("t", "a漢b字漢", 1.0, 0.1).problem().unwrap();
        assert_eq!(p.key, "text");
        assert!(
            p.message
                .contains("'漢' (U+6F22), '字' (U+5B57) (first at character 1"),
            "{}",
            p.message
        );
        // The design-wide total counts every element.
        let half = Text::new("t", &"A".repeat(MAX_TEXT_CHARS / 2 + 1), 10.0, 1.0);
        assert!(check_total(std::slice::from_ref(&half), "f.toml").is_ok());
        let e = check_total(&[half.clone(), half], "f.toml").unwrap_err();
        assert!(e.to_string().contains("text 1"), "{e}");
        // A layout beyond the coordinate limit is named.
        let mut far = Text::new("t", "A\nB", 1e6, 1.0);
        far.line_spacing = Some(100.0);
        assert_eq!(far.problem(), None);
        assert_eq!(layout_problem(&far.layout(), 0.5).unwrap().key, "text");
        assert!(far.to_strokes("f.toml", 0).is_err());
    }

    #[test]
    fn fonts_have_all_printable_ascii() {
        for f in Font::ALL {
            assert_eq!(f.glyphs().len(), 96, "{f:?}");
            for c in (33u8..127).map(char::from) {
                let g = f.glyph(c).unwrap();
                assert!(g.right > g.left, "{f:?} {c}");
                assert!(!g.strokes.is_empty(), "{f:?} {c}");
            }
        }
    }

    /// Nearest distance (design units) between the centre lines of two laid-out letters.
    fn letter_distance(a: &[Vec<DVec2>], b: &[Vec<DVec2>]) -> f64 {
        polylines_distance(a, b, 0.0)
    }

    #[test]
    fn kerning_tightens_open_pairs_to_the_stem_gap() {
        // Independent check on the laid-out letters (design units, scale 2): every tightened
        // pair keeps at least the stem gap, a tightened pair would come closer than it one
        // step further (or is at the bound), and the stem pair "nn" is not moved.
        let f = Font::Sans;
        let gap = f.stem_gap();
        assert!(gap > 0.0);
        for pair in ["AV", "To", "LT", "Yo", "P.", "nn", "OO", "EN", "HH"] {
            let c: Vec<char> = pair.chars().collect();
            let (ga, gb) = (f.glyph(c[0]).unwrap(), f.glyph(c[1]).unwrap());
            let k = pair_kern(ga, gb, gap);
            assert!((-MAX_TIGHTEN..=0.0).contains(&k), "{pair}: {k}");
            let t = Text::new("t", pair, 42.0, 1.0);
            let l = t.layout();
            let d = letter_distance(&l[0].2, &l[1].2) / t.scale();
            assert!(
                k == 0.0 || d >= gap - 1e-9,
                "{pair}: distance {d} < gap {gap}"
            );
            let kerned = Text {
                kerning: Some(Kerning::None),
                ..t.clone()
            };
            let plain = kerned.layout();
            let shift = (l[1].2[0][0].x - plain[1].2[0][0].x) / t.scale();
            assert!(
                (shift - k).abs() < 1e-9,
                "{pair}: shift {shift} vs kern {k}"
            );
            if k > -MAX_TIGHTEN && k < 0.0 {
                let closer = polylines_distance(
                    &glyph_polylines(ga),
                    &glyph_polylines(gb),
                    (ga.right - ga.left) as f64 + k - KERN_STEP,
                );
                assert!(closer < gap, "{pair}: one more step keeps {closer} ≥ {gap}");
            }
        }
        for (pair, tight) in [
            ("AV", true),
            ("To", true),
            ("LT", true),
            ("nn", false),
            ("OO", false),
        ] {
            let c: Vec<char> = pair.chars().collect();
            let k = pair_kern(f.glyph(c[0]).unwrap(), f.glyph(c[1]).unwrap(), gap);
            assert_eq!(k < 0.0, tight, "{pair}: {k}");
        }
    }

    #[test]
    fn kerning_none_and_script_keep_the_advances() {
        for (font, kerning) in [(Font::Sans, Some(Kerning::None)), (Font::Script, None)] {
            let mut t = Text::new("t", "AVTo", 21.0, 1.0);
            t.font = font;
            t.kerning = kerning;
            let sum: f64 = "AVTo"
                .chars()
                .map(|c| {
                    let g = font.glyph(c).unwrap();
                    (g.right - g.left) as f64
                })
                .sum();
            assert!((t.line_width("AVTo") - sum).abs() < 1e-12);
        }
        // Kerned: the line is narrower by the sum of the kerns, and centring uses it.
        let mut t = Text::new("t", "AVTo", 21.0, 1.0);
        let gap = Font::Sans.stem_gap();
        let g = |c| Font::Sans.glyph(c).unwrap();
        let kerns = pair_kern(g('A'), g('V'), gap)
            + pair_kern(g('V'), g('T'), gap)
            + pair_kern(g('T'), g('o'), gap);
        assert!(kerns < 0.0);
        let plain = Text {
            kerning: Some(Kerning::None),
            ..t.clone()
        };
        assert!((t.line_width("AVTo") - plain.line_width("AVTo") - kerns).abs() < 1e-9);
        t.align = Some(Align::Right);
        let right = t
            .layout()
            .iter()
            .flat_map(|g| g.2.concat())
            .map(|p| p.x)
            .fold(f64::NEG_INFINITY, f64::max);
        let o = g('o');
        let o_right = o.strokes.iter().flatten().map(|p| p[0]).max().unwrap();
        assert!((right - (o_right - o.right) as f64).abs() < 1e-9, "{right}");
    }

    #[test]
    fn kerning_key_parses() {
        let t: Text = toml::from_str(
            "name = \"t\"\ntext = \"AV\"\nheight = 10.0\nwidth = 1.0\nkerning = \"none\"",
        )
        .unwrap();
        assert_eq!(t.kerning, Some(Kerning::None));
        assert!(
            toml::from_str::<Text>(
                "name = \"t\"\ntext = \"AV\"\nheight = 10.0\nwidth = 1.0\nkerning = \"tight\""
            )
            .is_err()
        );
    }

    #[test]
    fn cap_height_and_advance() {
        let t = Text::new("t", "H", 80.0, 8.0);
        let l = t.layout();
        let ys: Vec<f64> = l[0].2.iter().flatten().map(|p| p.y).collect();
        let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert!(
            (lo - 0.0).abs() < 1e-9 && (hi - 80.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        // Advance of "HH" is twice that of "H"; centred text is symmetric about `at`.
        let g = Font::Sans.glyph('H').unwrap();
        let two = Text::new("t", "HH", 21.0, 1.0); // "HH" is a stem pair: not kerned
        assert!((two.line_width("HH") - 2.0 * (g.right - g.left) as f64).abs() < 1e-12);
        let mut c = Text::new("t", "HH", 21.0, 1.0);
        c.align = Some(Align::Centre);
        let xs: Vec<f64> = c
            .layout()
            .iter()
            .flat_map(|g| g.2.concat())
            .map(|p| p.x)
            .collect();
        let (a, b) = (
            xs.iter().copied().fold(f64::INFINITY, f64::min),
            xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
        assert!((a + b).abs() < 1e-9, "{a} {b}");
    }

    #[test]
    fn second_line_one_pitch_down_and_right_aligned() {
        let mut t = Text::new("t", "I\nII", 10.0, 1.0);
        t.align = Some(Align::Right);
        let l = t.layout();
        assert_eq!(l.len(), 3);
        let max_y = |i: usize| {
            l[i].2
                .iter()
                .flatten()
                .map(|p| p.y)
                .fold(f64::MIN, f64::max)
        };
        assert!((max_y(0) - max_y(1) - 16.0).abs() < 1e-9);
        // The last glyph of each line ends at the anchor.
        let x_of = |i: usize| l[i].2[0][0].x;
        assert!((x_of(0) - x_of(2)).abs() < 1e-9);
        assert!((x_of(1) - x_of(2) + t.line_width("I")).abs() < 1e-9);
    }

    #[test]
    fn script_letters_join() {
        // The exit of 'n' is the entry of the following 'n' one advance later.
        let t = Text::new("t", "nn", 21.0, 1.0);
        let l = t.layout();
        let end = *l[0].2.last().unwrap().last().unwrap();
        let start = l[1].2[0][0];
        let mut s = t.clone();
        s.font = Font::Script;
        let l = s.layout();
        let end_s = *l[0].2.last().unwrap().last().unwrap();
        let start_s = l[1].2[0][0];
        assert!(end_s.distance(start_s) < 1e-9, "{end_s} {start_s}");
        assert!(end.distance(start) > 1.0);
    }
}
