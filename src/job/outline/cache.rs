//! Skin each distinct stroke once: strokes that are translated copies of each other (the
//! glyphs of a text, repeated elements of a drawing) share one skinning.
//!
//! **Why a copy may reuse the skin.** Every construction of the skinning (Apollonius
//! circles, Gergonne's touching points, the Hermite tangent lengths α = 2·dist(w, l) of
//! re-skinning-cnc eqs. 11–12, the Hausdorff bounds of kruppa-2023 eqs. 20–21, the repair's
//! splits by knot insertion) is built from distances, angles and parameters, all invariant
//! under a translation T_d: skin(T_d S) = T_d skin(S) in exact arithmetic. The tolerances
//! are absolute lengths, so the decisions do not change either.
//!
//! **Key** ([`StrokeKey`]): the degree, the closed flag, the knots and the control disks with
//! their centres taken relative to the first centre, p_i − p_0, each number rounded to a
//! grid: [`KEY_GRID_FRACTION`] of the outline tolerance for lengths, [`KNOT_GRID_FRACTION`]
//! of the parameter domain's length for knots. Text laid out at different places gives
//! copies whose relative coordinates differ in the last bits (p + o − (p₀ + o) is not
//! p − p₀ in floating point), which an exact key would miss; two strokes with one key differ
//! by less than half a grid step per number, so a copy's outline is the representative's
//! translated by d = p₀(copy) − p₀(representative), within a few grid steps of the copy's
//! own skin (1e-6 of the tolerance: far inside ε). Rounding can also put two copies in
//! different cells; that only costs a second skinning.
//!
//! **Deterministic**: the representative of a key is its first stroke in file order, keys
//! are assigned before any skinning, and the representatives are skinned as every stroke
//! was (in parallel, collected in file order), so the result does not depend on the number
//! of threads, and a design without copies is skinned exactly as before.

use super::ItemOutline;
use crate::dbsc::DiskBSpline;
use crate::geom::DVec2;
use crate::skin::bits_hash::BitsMap;

/// Grid of the key's lengths (relative centres and radii) as a fraction of the outline
/// tolerance: 1e-6 of it (1e-8 mm at the default 0.01 mm) is far above the rounding noise of
/// placed copies (about 1e-13 mm for coordinates of a few hundred mm) and far below
/// anything the skin resolves.
pub const KEY_GRID_FRACTION: f64 = 1e-6;

/// Grid of the key's knots as a fraction of the parameter domain's length: 1e-10, above the
/// rounding noise of chord-length parameters (about 1e-15 relative).
pub const KNOT_GRID_FRACTION: f64 = 1e-10;

/// A stroke's geometry up to translation, rounded to grids ([`stroke_key`]).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct StrokeKey {
    degree: usize,
    closed: bool,
    /// Knots on the grid of [`KNOT_GRID_FRACTION`] of the domain, relative to its start.
    knots: Vec<i64>,
    /// (x − x₀, y − y₀, r) per control disk, on the grid of lengths.
    disks: Vec<[i64; 3]>,
}

/// `v / step` rounded to the nearest integer (saturating for absurd values, which then
/// only share a key with equally absurd ones).
fn cell(v: f64, step: f64) -> i64 {
    (v / step).round() as i64
}

/// The key of stroke `c` with lengths rounded to `grid` (design units, positive) and its
/// first control centre, the point its copies are placed by.
pub fn stroke_key(c: &DiskBSpline, grid: f64) -> (StrokeKey, DVec2) {
    let curve = c.curve();
    let ctrl = curve.ctrl();
    let origin = ctrl
        .first()
        .map(|v| DVec2::new(v.x, v.y))
        .unwrap_or_default();
    let (t0, t1) = c.domain();
    let knot_step = KNOT_GRID_FRACTION * (t1 - t0).abs().max(f64::MIN_POSITIVE);
    let key = StrokeKey {
        degree: c.degree(),
        closed: c.is_closed(),
        knots: curve
            .knots()
            .iter()
            .map(|&k| cell(k - t0, knot_step))
            .collect(),
        disks: ctrl
            .iter()
            .map(|v| {
                [
                    cell(v.x - origin.x, grid),
                    cell(v.y - origin.y, grid),
                    cell(v.z, grid),
                ]
            })
            .collect(),
    };
    (key, origin)
}

/// For each stroke, the index of the first stroke with its key (itself when it is the
/// first): O(n) expected through a hash map, in file order.
pub fn representatives(keys: &[StrokeKey]) -> Vec<usize> {
    let mut first: BitsMap<&StrokeKey, usize> = BitsMap::default();
    keys.iter()
        .enumerate()
        .map(|(i, k)| *first.entry(k).or_insert(i))
        .collect()
}

/// For each of `strokes`, `Some((r, d))` when it is a copy of the earlier stroke r moved by
/// d ([`stroke_key`] with lengths on the grid of [`KEY_GRID_FRACTION`]·`tolerance`), `None`
/// for the first stroke of each key. O(n) expected.
pub fn copies(strokes: &[DiskBSpline], tolerance: f64) -> Vec<Option<(usize, DVec2)>> {
    use crate::par::prelude::*;
    let grid = KEY_GRID_FRACTION * tolerance;
    let (keys, origins): (Vec<_>, Vec<_>) = strokes.par_iter().map(|c| stroke_key(c, grid)).unzip();
    representatives(&keys)
        .into_iter()
        .enumerate()
        .map(|(i, r)| (r != i).then(|| (r, origins[i] - origins[r])))
        .collect()
}

impl ItemOutline {
    /// This outline moved by `d` and named `name`: every point it holds (contours, spine
    /// box, circles, loop cusps, where the skin missed, where a repair split or fell back)
    /// moves; curve parameters, error bounds and distances do not.
    pub fn translated(&self, d: DVec2, name: &str) -> ItemOutline {
        let mut o = self.clone();
        o.name = name.to_string();
        o.contours = self.contours.iter().map(|p| p.translated(d)).collect();
        o.spine_box = self.spine_box.map(|(lo, hi)| (lo + d, hi + d));
        for c in &mut o.circles {
            c.c += d;
        }
        let move_loops = |loops: &mut [crate::dbsc::EnvelopeLoop]| {
            for l in loops {
                l.cusp_a = l.cusp_a.map(|p| p + d);
                l.cusp_b = l.cusp_b.map(|p| p + d);
            }
        };
        if let Some(l) = &mut o.loops {
            move_loops(&mut l.loops);
        }
        for s in &mut o.segments {
            move_loops(&mut s.loops);
        }
        if let Some(u) = &mut o.disk_union {
            u.at += d;
        }
        if let Some(r) = &mut o.repair {
            r.deviation_at += d;
            for s in &mut r.splits {
                s.at += d;
            }
            for f in &mut r.fallbacks {
                f.at += d;
                if let Some(m) = &mut f.missed {
                    m.at += d;
                }
            }
        }
        o
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::tangent::tests::dbsc_strategy_in;
    use crate::geom::Line;
    use crate::job::design_of_strokes;
    use crate::job::outline::{OutlineOptions, design_outlines, stroke_outline};
    use proptest::prelude::*;

    /// Largest distance from a point of `a`'s contours (flattened within `tol`) to the
    /// polylines of `b`'s, both ways.
    fn hausdorff(a: &ItemOutline, b: &ItemOutline, tol: f64) -> f64 {
        let flat = |o: &ItemOutline| -> Vec<Vec<DVec2>> {
            o.contours.iter().map(|p| p.flatten(tol)).collect()
        };
        let one = |x: &[Vec<DVec2>], y: &[Vec<DVec2>]| {
            x.iter()
                .flatten()
                .map(|&q| {
                    y.iter()
                        .flat_map(|r| {
                            (0..r.len()).map(move |i| Line::new(r[i], r[(i + 1) % r.len()]))
                        })
                        .map(|l| l.distance(q))
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0f64, f64::max)
        };
        let (fa, fb) = (flat(a), flat(b));
        one(&fa, &fb).max(one(&fb, &fa))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// A translated copy in a design is found as a copy, and the outline it gets from its
        /// original (translated) matches its own skin, computed without the cache, within
        /// the skin's ε; points it carries move with it.
        #[test]
        fn copies_match_their_own_skins(
            c in dbsc_strategy_in(2..=3, 0..=3, 20.0, 0.5..2.0),
            dx in -500.0f64..500.0,
            dy in -500.0f64..500.0,
        ) {
            let d = DVec2::new(dx, dy);
            let moved = c.translated(d);
            let design = design_of_strokes("copies", &[("a", &c), ("b", &moved)], &[]).unwrap();
            let opts = OutlineOptions::default();
            let strokes = design.strokes().unwrap();
            let copy = copies(&strokes, opts.tolerance);
            prop_assert!(copy[0].is_none());
            let (r, shift) = copy[1].expect("the translated stroke is a copy");
            prop_assert_eq!(r, 0);
            prop_assert!(shift.distance(d) < 1e-9 * (1.0 + d.length()));
            let own = stroke_outline(&design, "b", &strokes[1], &opts);
            let cached = design_outlines(&design, &opts);
            prop_assume!(own.is_ok() && cached.is_ok());
            let (own, cached) = (own.unwrap(), cached.unwrap());
            let b = &cached[1];
            prop_assert_eq!(&b.name, "b");
            prop_assert_eq!(b.contours.len(), own.contours.len());
            prop_assert_eq!(b.circles.len(), own.circles.len());
            for (x, y) in b.circles.iter().zip(&own.circles) {
                prop_assert!(x.c.distance(y.c) < 1e-6 && (x.r - y.r).abs() < 1e-6);
            }
            let h = hausdorff(b, &own, opts.tolerance);
            prop_assert!(h <= opts.epsilon, "copy is {} from its own skin", h);
        }
    }
}
