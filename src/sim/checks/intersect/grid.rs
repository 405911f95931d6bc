//! The uniform hash grid: cell size, each segment's (widened) cell cover, the sorted
//! (cell, segment) list, and the exact tests of the pairs that share a cell.

use super::*;

/// Cells per axis are capped at 2²⁴ so that cell keys fit in a u64 and grid coordinates keep
/// ≥ 28 bits of precision for the widening below.
pub(super) const MAX_CELLS_PER_AXIS: f64 = (1u64 << 24) as f64;

/// Widening of each segment's cell cover, in cell units: far above the rounding error of
/// grid coordinates (≤ 2²⁴ · 2⁻⁵² ≈ 4e-9), so the cover is a superset of the cells the
/// exact segment touches.
pub(super) const COVER_EPS: f64 = 1e-6;

/// Cells with at most this many segments test all pairs; larger ones group exact copies
/// first ([`SegmentSet::cell_pairs`]).
pub(super) const TWIN_CELL_MIN: usize = 32;

/// The uniform grid of [`SegmentSet::contacts`]: origin, cell size and rows; a cell's key
/// is `column · ny + row`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Lower corner of the segments' bounds.
    pub lo: DVec2,
    /// Cell size.
    pub h: f64,
    /// Columns (keys are below `nx · ny`).
    pub nx: u64,
    /// Rows.
    pub ny: u64,
}

impl Grid {
    /// The grid for `n` ≥ 2 segments with bounds `lo`..`hi` and total length `total`
    /// (summed in segment order); None where it cannot be built (non-finite input) and
    /// every pair must be tested.
    pub fn new(lo: DVec2, hi: DVec2, total: f64, n: usize) -> Option<Grid> {
        if !(lo.is_finite() && hi.is_finite() && total.is_finite()) {
            return None;
        }
        let ext = hi - lo;
        let mean = total / n as f64;
        let by_area = (ext.x.max(mean) * ext.y.max(mean) / n as f64).sqrt();
        let floor = ext.max_element() / MAX_CELLS_PER_AXIS;
        let mut h = mean.min(by_area).max(floor);
        // Long segments packed close (a dense hatch) would cover ~n^1.5 cells at the
        // area-based size: grow the cells until the covers total at most MAX_COVER_PER_SEG·n.
        if total / h > MAX_COVER_PER_SEG * n as f64 {
            h = total / (MAX_COVER_PER_SEG * n as f64);
        }
        if h.is_nan() || h <= 0.0 {
            return None;
        }
        let ny = (ext.y / h).floor() as u64 + 2;
        let nx = (ext.x / h).floor() as u64 + 2;
        Some(Grid { lo, h, nx, ny })
    }

    /// Calls `f` with the key of every cell segment `a`–`b` may touch.
    pub fn cover(&self, a: DVec2, b: DVec2, mut f: impl FnMut(u64)) {
        let ny = self.ny;
        cover((a - self.lo) / self.h, (b - self.lo) / self.h, |cx, cy| {
            f(cx * ny + cy)
        });
    }
}

/// Largest digit of [`radix_sort_high`]: 2¹⁰ buckets keep the scatter's destinations in
/// cache.
pub(super) const RADIX_BITS: u32 = 10;

/// Sorts `v` by bits 32..32 + `bits` (the bits above are zero), stably: a least significant
/// digit radix sort, at most [`RADIX_BITS`] bits per pass.
pub(super) fn radix_sort_high(v: &mut Vec<u64>, bits: u32) {
    if v.len() < 2 || bits == 0 {
        return;
    }
    let passes = bits.div_ceil(RADIX_BITS);
    let width = bits.div_ceil(passes);
    let mask = (1u64 << width) - 1;
    let mut tmp: Vec<u64> = vec![0; v.len()];
    let mut count = vec![0usize; 1 << width];
    for p in 0..passes {
        let shift = 32 + p * width;
        count.iter_mut().for_each(|c| *c = 0);
        for &x in v.iter() {
            count[((x >> shift) & mask) as usize] += 1;
        }
        let mut sum = 0;
        for c in count.iter_mut() {
            let n = *c;
            *c = sum;
            sum += n;
        }
        for &x in v.iter() {
            let d = ((x >> shift) & mask) as usize;
            tmp[count[d]] = x;
            count[d] += 1;
        }
        std::mem::swap(v, &mut tmp);
    }
}

/// Calls `f(cx, cy)` for every grid cell the segment from `a` to `b` (grid coordinates,
/// ≥ 0) may touch: per row, the cells between the segment's x at the row's lower and upper
/// y, widened by [`COVER_EPS`].
pub(super) fn cover(a: DVec2, b: DVec2, mut f: impl FnMut(u64, u64)) {
    let (ylo, yhi) = (a.y.min(b.y), a.y.max(b.y));
    // `x as u64` is `x.floor().max(0.0) as u64` for every f64 (truncation equals floor
    // at and above 0, both give 0 below 0 and for NaN, and both saturate), without a call
    // to `floor`.
    let r0 = (ylo - COVER_EPS) as u64;
    let r1 = (yhi + COVER_EPS) as u64;
    let dy = b.y - a.y;
    for r in r0..=r1 {
        let (xa, xb) = if dy == 0.0 {
            (a.x, b.x)
        } else {
            let y0 = (r as f64).max(ylo);
            let y1 = ((r + 1) as f64).min(yhi);
            let x_at = |y: f64| a.x + (y - a.y) * (b.x - a.x) / dy;
            (x_at(y0), x_at(y1))
        };
        let c0 = (xa.min(xb).max(a.x.min(b.x)) - COVER_EPS) as u64;
        let c1 = (xa.max(xb).min(a.x.max(b.x)) + COVER_EPS) as u64;
        for c in c0..=c1 {
            f(c, r);
        }
    }
}

impl SegmentSet {
    /// A tile of a larger set: `segs` with their neighbours `links` and their contours'
    /// pocket marks `pockets` (both the same length), in the larger set's order, contacts
    /// between contours counted by `across`; see [`SegmentSet::cell_contacts`].
    pub fn tile(
        segs: Vec<Seg>,
        links: Vec<Link>,
        pockets: Vec<Option<u32>>,
        across: Across,
        tangent_slack: f64,
    ) -> Self {
        let mut points = Vec::with_capacity(2 * segs.len());
        let mut shift = Vec::with_capacity(segs.len());
        let mut ids = Vec::with_capacity(segs.len());
        for (i, s) in segs.iter().enumerate() {
            points.extend([s.a, s.b]);
            shift.push(i as u32);
            ids.push((s.contour, s.index));
        }
        SegmentSet {
            points,
            shift,
            firsts: Vec::new(),
            ids,
            contours: Vec::new(),
            sources: Vec::new(),
            pockets,
            across,
            tangent_slack,
            links: Some(links),
        }
    }

    /// The contacts of segment pairs sharing a cell of `grid` whose key is in `keys`,
    /// tested cell by cell as [`SegmentSet::contacts`] does (without the folds of
    /// consecutive segments). Unsorted.
    pub fn cell_contacts(&self, grid: &Grid, keys: std::ops::Range<u64>) -> Vec<Contact> {
        if let Some(out) = self.packed_cell_contacts(grid, &keys) {
            return out;
        }
        let mut entries: Vec<(u64, u32)> = Vec::with_capacity(2 * self.len());
        for k in 0..self.len() {
            let (a, b) = self.ends(k);
            grid.cover(a, b, |key| {
                if keys.contains(&key) {
                    entries.push((key, k as u32));
                }
            });
        }
        entries.sort_unstable();
        self.sorted_cell_contacts(entries.len(), |i| entries[i])
    }

    /// The contacts of the cells of `n` (cell, segment) entries sorted by cell, `entry(i)`
    /// the i-th: [`SegmentSet::cell_pairs`] on each cell of two or more, until
    /// [`MAX_CONTACTS`].
    pub(super) fn sorted_cell_contacts(
        &self,
        n: usize,
        entry: impl Fn(usize) -> (u64, u32),
    ) -> Vec<Contact> {
        self.window_cell_contacts(n, entry, &(0..usize::MAX), MAX_CONTACTS)
    }

    /// [`SegmentSet::sorted_cell_contacts`] of the pairs whose lower segment index is in
    /// `window`, until `limit` contacts: the same pairs tested as on the whole set (each
    /// cell's pairs are chosen from all its segments), those outside the window skipped.
    /// A cell's segments come in increasing index, so a cell whose first segment is at or
    /// past the window's end, or whose last is before its start, has no pair in it.
    pub(super) fn window_cell_contacts(
        &self,
        n: usize,
        entry: impl Fn(usize) -> (u64, u32),
        window: &std::ops::Range<usize>,
        limit: usize,
    ) -> Vec<Contact> {
        let mut out = Vec::new();
        let mut ids: Vec<u32> = Vec::new();
        let mut g = 0;
        while g < n {
            let key = entry(g).0;
            let mut e = g + 1;
            while e < n && entry(e).0 == key {
                e += 1;
            }
            let first = entry(g).1 as usize;
            let last = entry(e - 1).1 as usize;
            if e - g >= 2 && first < window.end && last >= window.start {
                ids.clear();
                ids.extend((g..e).map(|i| entry(i).1));
                self.cell_pairs(&ids, window, limit, &mut out);
                if out.len() >= limit {
                    break;
                }
            }
            g = e;
        }
        out
    }

    /// [`SegmentSet::cell_contacts`] with each (cell, segment) entry packed into one u64
    /// (`key << 32 | segment`) and sorted by a stable radix sort on the key bits: the
    /// entries are made in segment order, so the order is the one `sort_unstable` gives the
    /// (key, segment) pairs, and the contacts are the same in the same order. None (nothing
    /// done) when the set has 2³² segments or more or a key needs more than 32 bits.
    pub(super) fn packed_cell_contacts(
        &self,
        grid: &Grid,
        keys: &std::ops::Range<u64>,
    ) -> Option<Vec<Contact>> {
        let entries = self.packed_entries(grid, keys)?;
        Some(self.sorted_cell_contacts(entries.len(), |i| (entries[i] >> 32, entries[i] as u32)))
    }

    /// The (cell, segment) entries of the cells of `grid` with keys in `keys`, packed and
    /// sorted as [`SegmentSet::packed_cell_contacts`] takes them; None when the set has 2³²
    /// segments or more or a key needs more than 32 bits.
    pub(super) fn packed_entries(
        &self,
        grid: &Grid,
        keys: &std::ops::Range<u64>,
    ) -> Option<Vec<u64>> {
        u32::try_from(self.len()).ok()?;
        let mut entries: Vec<u64> = Vec::with_capacity(2 * self.len());
        let mut max_key = 0u64;
        for k in 0..self.len() {
            let (a, b) = self.ends(k);
            grid.cover(a, b, |key| {
                if keys.contains(&key) {
                    max_key = max_key.max(key);
                    entries.push((key << 32) | k as u64);
                }
            });
            if max_key > u64::from(u32::MAX) {
                return None;
            }
        }
        radix_sort_high(&mut entries, 64 - max_key.leading_zeros());
        Some(entries)
    }

    /// Tests the segment pairs of one grid cell. Exact copies of a segment (same end points,
    /// either direction: coincident or retraced contours) are grouped: the first copy stands
    /// for the group against other segments, and every further copy is tested against that
    /// first copy and against the first copies of the other groups of its own contour. A cell
    /// holding k copies of a segment thus gives O(k) tests and contacts instead of O(k²)
    /// (2,000 coincident contours stay linear); contacts a copy would add are repeats of
    /// its first copy's at the same place.
    /// Only pairs whose lower index is in `window` are tested, until `limit` contacts: a
    /// segment outside the window is paired only with the first copies in it (w · k pairs
    /// for w of a cell's k segments in the window, not k²/2), in the order of the whole
    /// cell's pairs, so that the contacts found are those of the whole cell's loop.
    pub(super) fn cell_pairs(
        &self,
        cell: &[u32],
        window: &std::ops::Range<usize>,
        limit: usize,
        out: &mut Vec<Contact>,
    ) {
        let inside = |k: u32| window.contains(&(k as usize));
        // Tests a pair; false once `limit` contacts are found.
        let mut test = |i: u32, j: u32| {
            if out.len() < limit
                && inside(i.min(j))
                && let Some(c) = self.test_pair(i as usize, j as usize)
            {
                out.push(c);
            }
            out.len() < limit
        };
        if cell.len() <= TWIN_CELL_MIN {
            for (x, &i) in cell.iter().enumerate() {
                for &j in &cell[x + 1..] {
                    if !test(i, j) {
                        return;
                    }
                }
            }
            return;
        }
        let key = |k: u32| {
            let (a, b) = self.ends(k as usize);
            let (p, q) = if (a.x, a.y) <= (b.x, b.y) {
                (a, b)
            } else {
                (b, a)
            };
            [p.x.to_bits(), p.y.to_bits(), q.x.to_bits(), q.y.to_bits()]
        };
        // Sorted by (key, segment), each key computed once: the pairs are unique, so the
        // unstable sort gives the one order.
        let mut keyed: Vec<([u64; 4], u32)> = cell.iter().map(|&k| (key(k), k)).collect();
        keyed.sort_unstable();
        let ids: Vec<u32> = keyed.iter().map(|x| x.1).collect();
        let mut groups: Vec<(usize, usize)> = Vec::new();
        let mut g = 0;
        while g < ids.len() {
            let mut e = g + 1;
            while e < ids.len() && keyed[e].0 == keyed[g].0 {
                e += 1;
            }
            groups.push((g, e));
            g = e;
        }
        let reps: Vec<u32> = groups.iter().map(|&(a, _)| ids[a]).collect();
        // Groups whose first copy is in the window, in order: the only partners of a
        // segment outside it whose pair can be tested.
        let in_window: Vec<usize> = (0..reps.len()).filter(|&x| inside(reps[x])).collect();
        let all: Vec<usize> = (0..reps.len()).collect();
        for (x, &i) in reps.iter().enumerate() {
            // Partners of i after it: every group when i is in the window, else those whose
            // first copy is.
            let after = if inside(i) {
                &all[x + 1..]
            } else {
                &in_window[in_window.partition_point(|&y| y <= x)..]
            };
            for &y in after {
                if !test(i, reps[y]) {
                    return;
                }
            }
        }
        for (gi, &(a, e)) in groups.iter().enumerate() {
            for &m in &ids[a + 1..e] {
                if !test(ids[a], m) {
                    return;
                }
                let cm = self.contour_of(m as usize);
                let partners = if inside(m) { &all } else { &in_window };
                for &gj in partners {
                    let r = reps[gj];
                    if gj != gi && self.contour_of(r as usize) == cm && !test(m, r) {
                        return;
                    }
                }
            }
        }
    }
}
