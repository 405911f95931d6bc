//! Long segments checked apart from the others: a few far moves among many short ones
//! would otherwise size the grid by the box they span.

use super::*;

/// A segment longer than this many times the median segment length is checked apart from
/// the others ([`SegmentSet::split_contacts`]): one far move among 10⁵ short ones would
/// otherwise size the grid by the bounding box it spans (all short segments in one cell,
/// quadratic) or cover 10⁹ cells. 64 keeps the ordinary mix of a program (arc chords,
/// lines a few hundred times longer are rare) on the single grid.
pub(super) const LONG_SEGMENT: f64 = 64.0;

/// Fewest segments for which [`SegmentSet::grid_only_contacts`] looks for long ones: below
/// it the single grid is cheap whatever the lengths.
pub(super) const SPLIT_MIN: usize = 1024;

impl SegmentSet {
    /// The median segment length (the upper one for an even count; 0 for no segment).
    pub(super) fn median_length(&self) -> f64 {
        let mut lengths: Vec<f64> = (0..self.len())
            .map(|k| {
                let (a, b) = self.ends(k);
                a.distance(b)
            })
            .collect();
        if lengths.is_empty() {
            return 0.0;
        }
        let mid = lengths.len() / 2;
        *lengths.select_nth_unstable_by(mid, f64::total_cmp).1
    }

    /// Bounds (lo, hi) and total length of `segs`.
    pub(super) fn extent(&self, segs: impl Iterator<Item = Seg>) -> (DVec2, DVec2, f64) {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let mut total = 0.0;
        for s in segs {
            lo = lo.min(s.a).min(s.b);
            hi = hi.max(s.a).max(s.b);
            total += s.a.distance(s.b);
        }
        (lo, hi, total)
    }

    /// The segments among `ids` longer than [`LONG_SEGMENT`] times their median length,
    /// in order, when there are any: a uniform grid
    /// sized for the others would make each of them cover a great many cells, and one
    /// sized for them (or for the bounding box they span) would put the others all in a
    /// few cells. None when every length is finite and none is that long, or some length
    /// is not finite (the plain grid, or its brute-force fallback, decides then).
    pub(super) fn long_segments(&self, ids: &[u32]) -> Option<Vec<u32>> {
        if ids.len() < 2 {
            return None;
        }
        let len = |k: u32| {
            let (a, b) = self.ends(k as usize);
            a.distance(b)
        };
        let mut lengths: Vec<f64> = ids.iter().map(|&k| len(k)).collect();
        if !lengths.iter().all(|l| l.is_finite()) {
            return None;
        }
        let mid = lengths.len() / 2;
        let (_, median, _) = lengths.select_nth_unstable_by(mid, f64::total_cmp);
        let bar = LONG_SEGMENT * *median;
        if bar.is_nan() || bar <= 0.0 {
            return None;
        }
        let long: Vec<u32> = ids.iter().copied().filter(|&k| len(k) > bar).collect();
        (!long.is_empty()).then_some(long)
    }

    /// The contacts among `ids` (segment indices, ascending) of which the segments `long`
    /// (ascending, a subset, all longer than the median) stand far out: the others among
    /// themselves on a grid sized for them, the long ones among themselves the same way
    /// (recursively), and the long ones against the others ([`SegmentSet::long_against`]).
    /// Each level holds at most half the segments of the one before. Unsorted, with
    /// repeats; stops adding at [`MAX_CONTACTS`].
    pub(super) fn split_contacts(&self, ids: &[u32], long: Vec<u32>, out: &mut Vec<Contact>) {
        let short = self.without(ids, &long);
        self.subset_contacts(&short, out);
        match self.long_segments(&long) {
            Some(longer) => self.split_contacts(&long, longer, out),
            None => self.subset_contacts(&long, out),
        }
        self.long_against(&long, &short, out);
    }

    /// `ids` without `drop` (both ascending, `drop` a subset).
    pub(super) fn without(&self, ids: &[u32], drop: &[u32]) -> Vec<u32> {
        let mut d = drop.iter().peekable();
        ids.iter()
            .copied()
            .filter(|&k| {
                if d.peek() == Some(&&k) {
                    d.next();
                    false
                } else {
                    true
                }
            })
            .collect()
    }

    /// The contacts between a segment of `long` and one of `short` (segment indices,
    /// ascending, every one of `long` longer than those of `short` by far): `long` split by
    /// length again where its own lengths spread ([`SegmentSet::long_segments`]), then on
    /// a grid whose cells are sized for the long ones, holding the short segments within
    /// their bounds too, where only pairs of one long and one short segment are tested.
    pub(super) fn long_against(&self, long: &[u32], short: &[u32], out: &mut Vec<Contact>) {
        if long.is_empty() || out.len() >= MAX_CONTACTS {
            return;
        }
        if let Some(longer) = self.long_segments(long) {
            let rest = self.without(long, &longer);
            self.long_against(&longer, short, out);
            self.long_against(&rest, short, out);
            return;
        }
        let seg = |k: &u32| self.seg(*k as usize);
        let (llo, lhi, ltotal) = self.extent(long.iter().map(seg));
        let near: Vec<u32> = short
            .iter()
            .copied()
            .filter(|k| {
                let s = seg(k);
                !(s.a.min(s.b).cmpgt(lhi).any() || s.a.max(s.b).cmplt(llo).any())
            })
            .collect();
        if near.is_empty() {
            return;
        }
        let (slo, shi, _) = self.extent(near.iter().map(seg));
        let Some(grid) = Grid::new(llo.min(slo), lhi.max(shi), ltotal, long.len().max(2)) else {
            return self.pairs_between(long, &near, out);
        };
        // Entries (cell, long?, segment) sorted by cell, the short ones first in each.
        let mut entries: Vec<(u64, bool, u32)> = Vec::with_capacity(2 * (long.len() + near.len()));
        for (set, flag) in [(long, true), (&near[..], false)] {
            for k in set {
                let s = seg(k);
                grid.cover(s.a, s.b, |key| entries.push((key, flag, *k)));
            }
        }
        entries.sort_unstable();
        let mut js: Vec<u32> = Vec::new();
        let mut g = 0;
        while g < entries.len() && out.len() < MAX_CONTACTS {
            let key = entries[g].0;
            let mut e = g + 1;
            while e < entries.len() && entries[e].0 == key {
                e += 1;
            }
            let cell = &entries[g..e];
            let split = cell.partition_point(|x| !x.1);
            let (shorts, longs) = cell.split_at(split);
            js.clear();
            js.extend(shorts.iter().map(|x| x.2));
            for &(_, _, i) in longs {
                self.pairs_between(&[i], &js, out);
            }
            g = e;
        }
    }

    /// Every pair of one segment of `a` and one of `b` tested (the fallback of
    /// [`SegmentSet::split_contacts`] where a grid cannot be built).
    pub(super) fn pairs_between(&self, a: &[u32], b: &[u32], out: &mut Vec<Contact>) {
        for &i in a {
            for &j in b {
                if out.len() >= MAX_CONTACTS {
                    return;
                }
                // In index order, as the plain grid tests them: the same contact point to
                // the last bit.
                let (i, j) = (i.min(j) as usize, i.max(j) as usize);
                if let Some(c) = self.test_pair(i, j) {
                    out.push(c);
                }
            }
        }
    }

    /// The contacts among the segments `ids` on a grid sized for them alone, cell by cell
    /// as [`SegmentSet::cell_contacts`] tests them; appended to `out`.
    pub(super) fn subset_contacts(&self, ids: &[u32], out: &mut Vec<Contact>) {
        if ids.len() < 2 {
            return;
        }
        let (lo, hi, total) = self.extent(ids.iter().map(|&k| self.seg(k as usize)));
        let Some(grid) = Grid::new(lo, hi, total, ids.len()) else {
            for (x, &i) in ids.iter().enumerate() {
                self.pairs_between(&[i], &ids[x + 1..], out);
            }
            return;
        };
        let mut entries: Vec<(u64, u32)> = Vec::with_capacity(2 * ids.len());
        for &k in ids {
            let (a, b) = self.ends(k as usize);
            grid.cover(a, b, |key| entries.push((key, k)));
        }
        entries.sort_unstable();
        let room = MAX_CONTACTS.saturating_sub(out.len());
        let mut found = self.sorted_cell_contacts(entries.len(), |i| entries[i]);
        found.truncate(room);
        out.extend(found);
    }
}
