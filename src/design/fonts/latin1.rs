//! The Latin-1 letters and signs of the single-stroke fonts, composed from the fonts' own
//! ASCII glyphs (the Hershey `.jhf` files carry ASCII only).
//!
//! An accented letter is its base letter's strokes plus the strokes of its mark, each
//! mark one or two single strokes on the Hershey grid (cap height 21, y down):
//! acute, grave, circumflex, diaeresis, tilde, ring (above), cedilla (below), and the
//! stroke through Ø/ø. A mark above sits [`MARK_GAP`] units above the base glyph's top
//! (its x-height for lower case, its cap line for capitals: the glyph's own box), centred
//! on the middle of the glyph's upper quarter ([`UPPER_PART`]); in the script font every
//! mark point moves right by [`SCRIPT_SLANT`] per unit of height above the glyph's top,
//! as the script letters lean. The cedilla hangs from the middle of the glyph's lower
//! quarter, at its bottom. ì í î ï use the dotless i (the i without its dot: strokes
//! no larger than [`DOT_SIZE`]). The advance widths are the base letter's.
//!
//! Own glyphs: ß (one stroke, stem, upper bowl, cusp, lower bowl), Æ (diagonal leg and E
//! sharing the apex), æ (a and e: set touching in sans, joined at the advance in script,
//! as the script letters join); the script ß and Æ are the sans ones slanted by
//! [`SCRIPT_SLANT`]. Signs: ¡ and ¿ (! and ? turned by 180°), « », ° and · drawn on the
//! grid, and the no-break space (the space's advance).

use super::Glyph;

/// Units between the top of a glyph and the bottom of a mark above it.
pub const MARK_GAP: i32 = 2;
/// The part of a glyph's height (from its top) whose middle centres a mark above it
/// (and, from its bottom, a cedilla): a quarter, so that a script letter's entry and exit
/// strokes near the baseline do not pull the mark aside.
pub const UPPER_PART: f64 = 0.25;
/// The script font's lean: x grows by this per unit of height (the descender of the
/// script `p` runs 6 units across for 18 down).
pub const SCRIPT_SLANT: f64 = 1.0 / 3.0;
/// Largest side of a stroke's box that makes it a dot (the i's dot is a diamond of side 2
/// in sans, a square of side 1 in script).
pub const DOT_SIZE: i32 = 2;
/// The baseline's y on the grid.
const BASELINE: i32 = 9;

/// A diamond dot of radius 1 centred at (x, y), as the sans i's dot.
const fn dot(x: i32, y: i32) -> [[i32; 2]; 5] {
    [[x, y - 1], [x - 1, y], [x, y + 1], [x + 1, y], [x, y - 1]]
}

/// Marks above, drawn with their bottom at y = 0 and centred at x = 0.
const ACUTE: &[&[[i32; 2]]] = &[&[[-1, 0], [1, -3]]];
const GRAVE: &[&[[i32; 2]]] = &[&[[1, 0], [-1, -3]]];
const CIRCUMFLEX: &[&[[i32; 2]]] = &[&[[-3, 0], [0, -3], [3, 0]]];
const DIAERESIS: &[&[[i32; 2]]] = &[&dot(-3, -1), &dot(3, -1)];
const TILDE: &[&[[i32; 2]]] = &[&[[-3, 0], [-2, -1], [-1, -1], [1, 0], [2, 0], [3, -1]]];
const RING: &[&[[i32; 2]]] = &[&[
    [-1, -3],
    [1, -3],
    [2, -2],
    [2, -1],
    [1, 0],
    [-1, 0],
    [-2, -1],
    [-2, -2],
    [-1, -3],
]];
/// The cedilla, hanging down from (0, 0).
const CEDILLA: &[[i32; 2]] = &[[0, 0], [1, 2], [2, 3], [2, 4], [1, 5], [-1, 5]];

/// The sans ß: stem up from the baseline, the upper bowl, a cusp, the lower bowl.
const SHARP_S: &[[i32; 2]] = &[
    [-6, 9],
    [-6, -6],
    [-5, -10],
    [-3, -12],
    [0, -12],
    [2, -11],
    [3, -9],
    [3, -7],
    [1, -5],
    [-1, -4],
    [2, -4],
    [4, -3],
    [6, -1],
    [6, 3],
    [5, 6],
    [3, 8],
    [0, 9],
    [-2, 8],
];
/// The sans Æ: the A's left leg up to the apex; the E's top bar from the apex; the E's
/// stem down from the apex and its bottom bar; the E's middle bar; the A's crossbar. (The
/// top bar is a stroke of its own: slanted for the script, it meets the stem at 72°, a
/// turn the corner angle would take for a curve.)
const AE_CAPITAL: &[&[[i32; 2]]] = &[
    &[[-9, 9], [1, -12]],
    &[[1, -12], [11, -12]],
    &[[1, -12], [1, 9], [11, 9]],
    &[[1, -2], [9, -2]],
    &[[-5, 1], [1, 1]],
];
/// «, drawn around the x-height's middle; » is its mirror image.
const GUILLEMET: &[&[[i32; 2]]] = &[&[[-1, -1], [-4, 2], [-1, 5]], &[[3, -1], [0, 2], [3, 5]]];
/// °: a ring at the cap line.
const DEGREE: &[[i32; 2]] = &[
    [-1, -12],
    [1, -12],
    [2, -11],
    [2, -9],
    [1, -8],
    [-1, -8],
    [-2, -9],
    [-2, -11],
    [-1, -12],
];

#[derive(Clone, Copy)]
enum Mark {
    Above(&'static [&'static [[i32; 2]]]),
    Cedilla,
    Slash,
}

/// The base letter and mark of an accented Latin-1 letter.
fn decompose(c: char) -> Option<(char, Mark)> {
    use Mark::*;
    let (a, g, c_, d, t, r) = (
        Above(ACUTE),
        Above(GRAVE),
        Above(CIRCUMFLEX),
        Above(DIAERESIS),
        Above(TILDE),
        Above(RING),
    );
    Some(match c {
        'À' => ('A', g),
        'Á' => ('A', a),
        'Â' => ('A', c_),
        'Ã' => ('A', t),
        'Ä' => ('A', d),
        'Å' => ('A', r),
        'Ç' => ('C', Cedilla),
        'È' => ('E', g),
        'É' => ('E', a),
        'Ê' => ('E', c_),
        'Ë' => ('E', d),
        'Ì' => ('I', g),
        'Í' => ('I', a),
        'Î' => ('I', c_),
        'Ï' => ('I', d),
        'Ñ' => ('N', t),
        'Ò' => ('O', g),
        'Ó' => ('O', a),
        'Ô' => ('O', c_),
        'Õ' => ('O', t),
        'Ö' => ('O', d),
        'Ø' => ('O', Slash),
        'Ù' => ('U', g),
        'Ú' => ('U', a),
        'Û' => ('U', c_),
        'Ü' => ('U', d),
        'Ý' => ('Y', a),
        'à' => ('a', g),
        'á' => ('a', a),
        'â' => ('a', c_),
        'ã' => ('a', t),
        'ä' => ('a', d),
        'å' => ('a', r),
        'ç' => ('c', Cedilla),
        'è' => ('e', g),
        'é' => ('e', a),
        'ê' => ('e', c_),
        'ë' => ('e', d),
        'ì' => ('i', g),
        'í' => ('i', a),
        'î' => ('i', c_),
        'ï' => ('i', d),
        'ñ' => ('n', t),
        'ò' => ('o', g),
        'ó' => ('o', a),
        'ô' => ('o', c_),
        'õ' => ('o', t),
        'ö' => ('o', d),
        'ø' => ('o', Slash),
        'ù' => ('u', g),
        'ú' => ('u', a),
        'û' => ('u', c_),
        'ü' => ('u', d),
        'ý' => ('y', a),
        'ÿ' => ('y', d),
        _ => return None,
    })
}

/// The base letter of an accented Latin-1 letter (`None` for other characters).
#[cfg(test)]
fn base_letter(c: char) -> Option<char> {
    decompose(c).map(|(b, _)| b)
}

fn points(g: &Glyph) -> impl Iterator<Item = [i32; 2]> + '_ {
    g.strokes.iter().flatten().copied()
}

/// The middle x of the glyph's points with y in `lo..=hi`.
fn middle_x(g: &Glyph, lo: f64, hi: f64) -> f64 {
    let (a, b) = points(g)
        .filter(|p| (lo..=hi).contains(&(p[1] as f64)))
        .fold((i32::MAX, i32::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])));
    if a > b { 0.0 } else { 0.5 * (a + b) as f64 }
}

fn round(v: f64) -> i32 {
    v.round() as i32
}

/// The glyph without its dots (strokes whose box is at most [`DOT_SIZE`] on each side).
fn without_dots(g: &Glyph) -> Glyph {
    let strokes = g
        .strokes
        .iter()
        .filter(|s| {
            let side = |k: usize| {
                let (a, b) = s
                    .iter()
                    .fold((i32::MAX, i32::MIN), |(a, b), p| (a.min(p[k]), b.max(p[k])));
                b - a
            };
            side(0) > DOT_SIZE || side(1) > DOT_SIZE
        })
        .cloned()
        .collect();
    Glyph {
        strokes,
        ..g.clone()
    }
}

/// `base` with `mark` added (module docs); `slant` is the font's lean.
fn with_mark(base: &Glyph, mark: Mark, slant: f64) -> Glyph {
    let mut g = base.clone();
    let (top, bottom) =
        points(base).fold((i32::MAX, i32::MIN), |(t, b), p| (t.min(p[1]), b.max(p[1])));
    let part = UPPER_PART * (bottom - top) as f64;
    match mark {
        Mark::Above(strokes) => {
            let cx = middle_x(base, top as f64, top as f64 + part);
            let y0 = top - MARK_GAP;
            for s in strokes {
                g.strokes.push(
                    s.iter()
                        .map(|&[x, y]| {
                            let yy = y0 + y;
                            [round(cx + x as f64 + slant * (top - yy) as f64), yy]
                        })
                        .collect(),
                );
            }
        }
        Mark::Cedilla => {
            let cx = middle_x(base, bottom as f64 - part, bottom as f64);
            g.strokes.push(
                CEDILLA
                    .iter()
                    .map(|&[x, y]| {
                        let yy = bottom + y;
                        [round(cx + x as f64 - slant * y as f64), yy]
                    })
                    .collect(),
            );
        }
        Mark::Slash => {
            let (left, right) =
                points(base).fold((i32::MAX, i32::MIN), |(l, r), p| (l.min(p[0]), r.max(p[0])));
            g.strokes
                .push(vec![[left - 1, bottom + 1], [right + 1, top - 1]]);
        }
    }
    g
}

/// `strokes` slanted by `slant` about the baseline: x grows by `slant` per unit above it.
fn slanted(strokes: &[&[[i32; 2]]], slant: f64) -> Vec<Vec<[i32; 2]>> {
    strokes
        .iter()
        .map(|s| {
            s.iter()
                .map(|&[x, y]| [round(x as f64 + slant * (BASELINE - y) as f64), y])
                .collect()
        })
        .collect()
}

/// `g` turned by 180° about (0, −1.5), the middle of the cap height: ! becomes ¡.
fn turned(g: &Glyph) -> Glyph {
    Glyph {
        left: -g.right,
        right: -g.left,
        strokes: g
            .strokes
            .iter()
            .map(|s| s.iter().map(|&[x, y]| [-x, -3 - y]).collect())
            .collect(),
    }
}

fn owned(left: i32, right: i32, strokes: &[&[[i32; 2]]]) -> Glyph {
    Glyph {
        left,
        right,
        strokes: strokes.iter().map(|s| s.to_vec()).collect(),
    }
}

/// The glyph of the Latin-1 character `c` (U+00A0 to U+00FF) composed from the ASCII
/// glyphs `ascii` of a font whose letters lean by `slant` and join at the advance when
/// `joined` (module docs), or `None` when the font does not have it.
pub fn compose(
    c: char,
    ascii: &dyn Fn(char) -> Option<Glyph>,
    slant: f64,
    joined: bool,
) -> Option<Glyph> {
    if let Some((b, mark)) = decompose(c) {
        let base = ascii(b)?;
        let base = if b == 'i' { without_dots(&base) } else { base };
        return Some(with_mark(&base, mark, slant));
    }
    Some(match c {
        '\u{a0}' => ascii(' ')?,
        '¡' => turned(&ascii('!')?),
        '¿' => turned(&ascii('?')?),
        '«' => owned(-7, 7, GUILLEMET),
        '»' => {
            let mut g = owned(-7, 7, GUILLEMET);
            for s in &mut g.strokes {
                for p in s.iter_mut() {
                    p[0] = -p[0];
                }
            }
            g
        }
        '°' => owned(-5, 5, &[DEGREE]),
        '·' => owned(-4, 4, &[&dot(0, 2)]),
        'ß' => Glyph {
            left: -10,
            right: 9,
            strokes: slanted(&[SHARP_S], slant),
        },
        'Æ' => Glyph {
            left: -12,
            right: 13,
            strokes: slanted(AE_CAPITAL, slant),
        },
        'æ' => {
            let (a, e) = (ascii('a')?, ascii('e')?);
            // Script: e one advance on, where the letters join; sans: e's left side on
            // a's stem.
            let shift = if joined {
                a.right - e.left
            } else {
                let a_right = points(&a).map(|p| p[0]).max()?;
                let e_left = points(&e).map(|p| p[0]).min()?;
                a_right - e_left
            };
            let mut g = a.clone();
            g.right = e.right + shift;
            g.strokes.extend(
                e.strokes
                    .iter()
                    .map(|s| s.iter().map(|&[x, y]| [x + shift, y]).collect()),
            );
            g
        }
        _ => return None,
    })
}

/// Every Latin-1 character (U+00A0 to U+00FF) the fonts have.
#[cfg(test)]
pub(crate) fn supported() -> impl Iterator<Item = char> {
    ('\u{a0}'..='\u{ff}').filter(|&c| decompose(c).is_some() || "\u{a0}¡¿«»°·ßÆæ".contains(c))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::text::Font;

    /// Whether a stroke is a dot: its box no larger than [`DOT_SIZE`] each way.
    fn is_dot(s: &[[i32; 2]]) -> bool {
        (0..2).all(|k| {
            let lo = s.iter().map(|p| p[k]).min().unwrap();
            let hi = s.iter().map(|p| p[k]).max().unwrap();
            hi - lo <= DOT_SIZE
        })
    }

    #[test]
    fn every_latin1_letter_is_its_base_letter_and_a_mark_in_the_right_place() {
        let mut letters = 0;
        for font in Font::ALL {
            for c in supported() {
                let g = font.glyph(c).unwrap();
                if c != '\u{a0}' {
                    assert!(!g.strokes.is_empty(), "{c:?}");
                    assert!(!font.spines(c).unwrap().is_empty(), "{c:?}");
                }
                let Some(b) = base_letter(c) else {
                    continue;
                };
                letters += 1;
                let base: &Glyph = font.glyph(b).unwrap();
                // The base letter's strokes (the i's without its dot) come first, unchanged.
                let kept: Vec<&Vec<[i32; 2]>> = base
                    .strokes
                    .iter()
                    .filter(|s| b != 'i' || !is_dot(s))
                    .collect();
                assert!(g.strokes.len() > kept.len(), "{c:?}");
                for (s, k) in g.strokes.iter().zip(&kept) {
                    assert_eq!(s, *k, "{c:?}");
                }
                assert_eq!((g.left, g.right), (base.left, base.right), "{c:?}");
                let ys: Vec<i32> = kept.iter().flat_map(|s| s.iter().map(|p| p[1])).collect();
                let xs: Vec<i32> = kept.iter().flat_map(|s| s.iter().map(|p| p[0])).collect();
                let (top, bottom) = (*ys.iter().min().unwrap(), *ys.iter().max().unwrap());
                let (left, right) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
                let mark: Vec<[i32; 2]> =
                    g.strokes[kept.len()..].iter().flatten().copied().collect();
                // Script marks lean right by the slant over their height.
                let lean = if font == Font::Script { 3 } else { 0 };
                // Marks reach 4 units either side of their centre (the diaeresis' dots).
                let inside_x = |x: i32| (left - 4..=right + 4 + lean).contains(&x);
                match c {
                    'Ç' | 'ç' => {
                        assert!(mark.iter().all(|p| p[1] >= bottom && p[1] <= bottom + 5));
                        assert!(mark.iter().all(|p| (left - 3..=right + 2).contains(&p[0])));
                    }
                    'Ø' | 'ø' => {
                        assert_eq!(mark, vec![[left - 1, bottom + 1], [right + 1, top - 1]]);
                    }
                    _ => {
                        // Above the letter's box (its x-height or cap line), by the gap.
                        let low = mark.iter().map(|p| p[1]).max().unwrap();
                        let high = mark.iter().map(|p| p[1]).min().unwrap();
                        assert_eq!(low, top - MARK_GAP, "{} {c:?}", font.as_str());
                        assert!(high >= top - MARK_GAP - 3, "{c:?}");
                        assert!(
                            mark.iter().all(|p| inside_x(p[0])),
                            "{} {c:?}",
                            font.as_str()
                        );
                    }
                }
            }
        }
        // 28 lower-case and 27 capital accented letters (no capital ÿ in Latin-1).
        assert_eq!(letters, 2 * 55);
    }
}
