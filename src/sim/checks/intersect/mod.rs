//! Segment contacts among many polylines: a uniform hash grid over the segments plus exact
//! orientation predicates ([`crate::geom::predicates`]).
//!
//! Each segment is entered into every grid cell its (slightly widened) path crosses; pairs
//! sharing a cell are tested exactly. The cell size is min(mean segment length, √(area/n)),
//! so each segment covers O(1) cells and each cell holds O(1) segments for the paths CNC
//! programs are made of; the (cell, segment) list is sorted instead of hashed. Work is
//! O(n log n + pairs sharing a cell).

use crate::geom::DVec2;
use crate::geom::predicates::{line_intersection, orient2d, segments_intersect};

mod apart;
mod grid;
mod pair;
mod split;
#[cfg(test)]
mod tests;

pub use grid::Grid;
use grid::*;
use split::*;

/// Bound on the mean number of cells a segment's cover may take (memory guard, see
/// [`SegmentSet::contacts`]): 4 keeps the (cell, segment) list within a few times n.
const MAX_COVER_PER_SEG: f64 = 4.0;

/// Most contacts the grid collects (memory guard): a program that crosses itself
/// everywhere, such as a random scribble of n segments, has O(n²) contacts, a list no memory
/// holds for a few ten thousand lines. Beyond this many the grid stops and
/// [`SegmentSet::contacts_capped`] says so; 2²⁰ contacts take about 40 MB.
pub const MAX_CONTACTS: usize = 1 << 20;

/// Fewest segments [`SegmentSet::contacts_in_order`] searches in rounds: below it one
/// search over all segments is cheap, and the count of findings past the report's cap stays
/// exact.
pub const ROUNDS_MIN: usize = 1 << 16;

/// Segments in the first window of [`SegmentSet::contacts_in_order`].
const FIRST_ROUND: usize = 64;

/// Growth of the windows of [`SegmentSet::contacts_in_order`] from one round to the next:
/// a set that never stops is searched in log₈(n / [`FIRST_ROUND`]) + 1 rounds, each
/// skipping in O(1) the cells without a pair in its window.
const ROUND_GROWTH: usize = 8;

/// One segment of a polyline: `contour` numbers the polyline, `index` the segment in it.
/// A [`SegmentSet`] does not store it: it builds it on demand ([`SegmentSet::seg`]) from
/// its point array and each segment's contour number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seg {
    /// Start point.
    pub a: DVec2,
    /// End point.
    pub b: DVec2,
    /// Number of the polyline the segment belongs to.
    pub contour: u32,
    /// Position of the segment in its polyline.
    pub index: u32,
}

/// The pocket mark of line cuts (`(skinpath:group 0)`; pockets are numbered from 1): cuts
/// along a drawing's lines, whose contacts with any contour, their own included, never
/// count (the intersection check's pair test skips them).
pub const LINE_GROUP: u32 = 0;

/// Which contacts between segments of two different contours [`SegmentSet::test_pair`]
/// reports (within one contour every contact counts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Across {
    /// Every contact: crossings, touches and overlaps.
    #[default]
    All,
    /// Proper crossings only (interiors crossing transversally). The passes of a
    /// multi-depth cut lie on one another in xy; their touches and overlaps are not
    /// tested further, stored or sorted, and do not count towards [`MAX_CONTACTS`].
    Crossings,
    /// None: contours may cross one another.
    Never,
}

/// Most contacts a window of [`SegmentSet::contacts_in_order`] wider than one segment may
/// give: a window past it is searched again, [`ROUND_GROWTH`] times narrower (its search
/// stops there, so each try costs about this many contacts). An arc of 100,000 turns
/// crosses itself some 10⁴ times per chord, 2²⁰ times in the first 64 chords; its report
/// is decided by the first chord's contacts.
const WINDOW_CONTACTS: usize = 1 << 16;

/// Polylines split into segments (zero-length segments dropped).
///
/// The segments are not stored one by one ([`Seg`] is built on demand by
/// [`SegmentSet::seg`]): a polyline's points are stored once, the end of one segment being
/// the start of the next, and segment i runs from `points[i + shift[i]]` to the point after
/// it. In a set of whole polylines, contour c stores its count + 1 points (one for a
/// contour without segments), so `shift[i]` is segment i's contour number; in a tile
/// ([`SegmentSet::tile`]) each segment stores its two end points (`shift[i]` = i) and its
/// contour and index are held beside it. 24 bytes a segment with the caller's tag, not the
/// 44 of two end points, a contour, an index and a tag: less memory to fault in and to
/// stream through the searches.
#[derive(Clone, Debug, Default)]
pub struct SegmentSet {
    /// The polylines' points (see [`SegmentSet`]).
    points: Vec<DVec2>,
    /// Per segment: where its start point is in `points`, less its own index.
    shift: Vec<u32>,
    /// Per contour: number of segments and whether it is closed (last point = first).
    pub contours: Vec<(u32, bool)>,
    /// Per contour: index of its first segment (whole sets; empty for a tile).
    firsts: Vec<u32>,
    /// Per segment of a tile: its contour and its position in it (empty for whole sets).
    ids: Vec<(u32, u32)>,
    /// Per segment: the caller's tag (the check's program line; none in a tile, read as 0).
    sources: Vec<u32>,
    /// The pocket marks ([`SegmentSet::push_polyline_in`]): per contour, or per segment
    /// in a tile (whose contours are not held).
    pockets: Vec<Option<u32>>,
    /// The contacts between different contours that count.
    pub across: Across,
    /// How far (a length) a chord may stray from the curve it stands for, by flattening and
    /// by rounding of the program's numbers; 0 takes chords as the exact path. Two passes
    /// through a shared vertex that are tangent within it touch there without crossing
    /// (see [`SegmentSet::tangent_passes`]).
    pub tangent_slack: f64,
    /// A tile of a larger set ([`SegmentSet::tile`]): each segment's neighbours, since its
    /// contour is not held whole.
    links: Option<Vec<Link>>,
}

/// A polyline being added to a [`SegmentSet`] point by point
/// ([`SegmentSet::begin_polyline`]).
#[derive(Clone, Copy, Debug)]
pub struct OpenPolyline {
    contour: u32,
    count: u32,
    first: DVec2,
    prev: DVec2,
    pocket: Option<u32>,
}

/// What a segment of a tile knows of its neighbours in its contour.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Link {
    /// Start point of the segment before it (the last one's for the first segment of a
    /// closed contour).
    pub prev_a: Option<DVec2>,
    /// End point of the segment after it (the first one's for the last segment of a
    /// closed contour).
    pub next_b: Option<DVec2>,
    /// First or last segment of a closed contour (the two are adjacent).
    pub wrap: bool,
}

/// Two segments that share a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Indices into [`SegmentSet::seg`], i < j.
    pub i: usize,
    /// The other segment (index into [`SegmentSet::seg`]).
    pub j: usize,
    /// A point they share (the crossing point, or a shared end/overlap point).
    pub point: DVec2,
    /// True when the interiors cross transversally (strict orientation signs on both).
    pub proper: bool,
}

impl SegmentSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Reserves room for `n` more segments.
    pub fn reserve(&mut self, n: usize) {
        self.points.reserve(n);
        self.shift.reserve(n);
        self.sources.reserve(n);
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.shift.len()
    }

    /// True when the set has no segment.
    #[allow(dead_code)] // the counterpart of `len`, used by the tests
    pub fn is_empty(&self) -> bool {
        self.shift.is_empty()
    }

    /// The end points of segment `i` (`i` < [`SegmentSet::len`]).
    #[inline]
    pub fn ends(&self, i: usize) -> (DVec2, DVec2) {
        let k = i + self.shift[i] as usize;
        (self.points[k], self.points[k + 1])
    }

    /// Segment `i` (`i` < [`SegmentSet::len`]).
    #[inline]
    pub fn seg(&self, i: usize) -> Seg {
        let (a, b) = self.ends(i);
        let (contour, index) = match self.ids.get(i) {
            Some(&id) => id,
            None => {
                let c = self.shift[i];
                let first = self.firsts.get(c as usize).copied().unwrap_or(0);
                (c, i as u32 - first)
            }
        };
        Seg {
            a,
            b,
            contour,
            index,
        }
    }

    /// Segment `i`, None past the end.
    pub fn get(&self, i: usize) -> Option<Seg> {
        (i < self.len()).then(|| self.seg(i))
    }

    /// The segments in order.
    pub fn iter(&self) -> impl Iterator<Item = Seg> + '_ {
        (0..self.len()).map(|i| self.seg(i))
    }

    /// Contour number of segment `i` (`i` < [`SegmentSet::len`]).
    #[inline]
    pub fn contour_of(&self, i: usize) -> u32 {
        match self.ids.get(i) {
            Some(&(c, _)) => c,
            None => self.shift[i],
        }
    }

    /// Adds a polyline; `sources[k]` tags the segment from `points[k]` to `points[k+1]`.
    /// Repeated points are skipped. Returns the contour number.
    #[allow(dead_code)] // used by the benches (`crate::internals`) and the tests
    pub fn push_polyline(&mut self, points: &[DVec2], sources: &[u32]) -> u32 {
        self.push_polyline_in(points, sources, None)
    }

    /// [`SegmentSet::push_polyline`] for a contour that clears `pocket` together with the
    /// other contours of that pocket: contacts between two contours of one pocket never
    /// count, whatever [`SegmentSet::across`] says (they may cross: rings and a deeper wire
    /// hole of one channel).
    #[allow(dead_code)] // used by the benches (`crate::internals`) and the tests
    pub fn push_polyline_in(
        &mut self,
        points: &[DVec2],
        sources: &[u32],
        pocket: Option<u32>,
    ) -> u32 {
        let Some(&first) = points.first() else {
            // A contour without segments still holds a point (see [`SegmentSet`]).
            let open = self.begin_polyline(DVec2::ZERO, pocket);
            return self.end_polyline(open);
        };
        let mut open = self.begin_polyline(first, pocket);
        for (k, &p) in points.iter().enumerate().skip(1) {
            let source = sources.get(k - 1).or(sources.last()).copied().unwrap_or(0);
            self.polyline_to(&mut open, p, source);
        }
        self.end_polyline(open)
    }

    /// Starts a polyline at `first`, added point by point ([`SegmentSet::polyline_to`],
    /// then [`SegmentSet::end_polyline`]) as [`SegmentSet::push_polyline_in`] adds it
    /// whole: for callers that do not hold its points. No other polyline may be added
    /// before it ends.
    pub fn begin_polyline(&mut self, first: DVec2, pocket: Option<u32>) -> OpenPolyline {
        self.points.push(first);
        self.firsts.push(self.shift.len() as u32);
        OpenPolyline {
            contour: self.contours.len() as u32,
            count: 0,
            first,
            prev: first,
            pocket,
        }
    }

    /// Extends `open` to `p` with a segment tagged `source` (none when `p` repeats the
    /// point before).
    pub fn polyline_to(&mut self, open: &mut OpenPolyline, p: DVec2, source: u32) {
        if open.prev != p {
            self.points.push(p);
            self.shift.push(open.contour);
            self.sources.push(source);
            open.count += 1;
            open.prev = p;
        }
    }

    /// Ends `open` (closed when it has two segments or more and ends where it began);
    /// returns its contour number.
    pub fn end_polyline(&mut self, open: OpenPolyline) -> u32 {
        let closed = open.count >= 2 && open.first == open.prev;
        self.contours.push((open.count, closed));
        self.pockets.push(open.pocket);
        open.contour
    }

    /// The caller's tag of segment `i` (0 in a tile, or past the end).
    pub fn source(&self, i: usize) -> u32 {
        self.sources.get(i).copied().unwrap_or(0)
    }

    /// The pocket mark of segment `i`'s contour (None past the end).
    pub fn pocket(&self, i: usize) -> Option<u32> {
        if self.links.is_some() {
            return self.pockets.get(i).copied().flatten();
        }
        if i >= self.len() {
            return None;
        }
        let c = self.contour_of(i) as usize;
        self.pockets.get(c).copied().flatten()
    }

    /// All contacts: non-adjacent pairs that share any point (proper or not), and adjacent
    /// pairs that fold back onto each other (collinear overlap beyond the shared end).
    #[allow(dead_code)] // used by the benches (`crate::internals`) and the tests
    pub fn contacts(&self) -> Vec<Contact> {
        self.contacts_capped().0
    }

    /// [`SegmentSet::contacts`], and whether the grid stopped at [`MAX_CONTACTS`] (then
    /// the contacts are those of the cells tested first, not all).
    pub fn contacts_capped(&self) -> (Vec<Contact>, bool) {
        let mut out = self.adjacent_overlaps();
        let grid = self.grid_contacts();
        let capped = grid.len() >= MAX_CONTACTS;
        out.extend(grid);
        out.sort_by_key(|c| (c.i, c.j));
        out.dedup_by(|p, q| p.i == q.i && p.j == q.j);
        (out, capped)
    }

    /// [`SegmentSet::contacts_capped`] handed to `take` in batches, in order: each batch
    /// sorted by (i, j) and deduplicated, its contacts' lower indices i in a window of
    /// segments after the previous batch's, so that the batches in turn are the contacts of
    /// `contacts_capped` (up to where [`MAX_CONTACTS`] stops it, which here counts from the
    /// first batch). `take` returns false to stop the search there: the contacts after
    /// its batch are then not looked for. Returns (capped at [`MAX_CONTACTS`], stopped by
    /// `take` with segments left to search).
    ///
    /// Sets of fewer than [`ROUNDS_MIN`] segments, sets proven apart, and sets whose grid
    /// is not the single packed one ([`SegmentSet::round_entries`]) are searched whole, in
    /// one batch. Otherwise the grid's entries are built once and searched in rounds of
    /// windows [`FIRST_ROUND`] segments long, each [`ROUND_GROWTH`] times the one before:
    /// a retraced contour's contacts all have their lower segment in its first pass, and
    /// a report full after the first window is found at the cost of that window's cells.
    /// A window of more than one segment with [`WINDOW_CONTACTS`] contacts or more is
    /// searched again [`ROUND_GROWTH`] times narrower, down to one segment, so that a
    /// contour crossing itself everywhere hands out its first segments' contacts before the
    /// whole cap's worth.
    pub fn contacts_in_order(&self, mut take: impl FnMut(&[Contact]) -> bool) -> (bool, bool) {
        let n = self.len();
        let whole = |take: &mut dyn FnMut(&[Contact]) -> bool| {
            let (c, capped) = self.contacts_capped();
            take(&c);
            (capped, false)
        };
        if n < ROUNDS_MIN {
            return whole(&mut take);
        }
        let mut overlaps = self.adjacent_overlaps();
        overlaps.sort_by_key(|c| (c.i, c.j));
        if self.proven_apart_with_copies() {
            take(&overlaps);
            return (false, false);
        }
        let Some(entries) = self.round_entries() else {
            return whole(&mut take);
        };
        let (mut lo, mut size, mut total) = (0usize, FIRST_ROUND, 0usize);
        while lo < n {
            let hi = lo.saturating_add(size).min(n);
            let window = lo..hi;
            let room = MAX_CONTACTS - total;
            let limit = if hi - lo > 1 {
                room.min(WINDOW_CONTACTS)
            } else {
                room
            };
            let found = self.window_cell_contacts(
                entries.len(),
                |i| (entries[i] >> 32, entries[i] as u32),
                &window,
                limit,
            );
            if limit < room && found.len() >= limit {
                size = ((hi - lo) / ROUND_GROWTH).max(1);
                continue;
            }
            let mut batch: Vec<Contact> = overlaps
                .iter()
                .filter(|c| window.contains(&c.i))
                .copied()
                .collect();
            total += found.len();
            batch.extend(found);
            batch.sort_by_key(|c| (c.i, c.j));
            batch.dedup_by(|p, q| p.i == q.i && p.j == q.j);
            let capped = total >= MAX_CONTACTS;
            if !take(&batch) {
                return (capped, hi < n && !capped);
            }
            if capped {
                return (true, false);
            }
            lo = hi;
            size = size.saturating_mul(ROUND_GROWTH);
        }
        (false, false)
    }

    /// The packed (cell, segment) entries of the single grid [`SegmentSet::cell_contacts`]
    /// searches for [`SegmentSet::grid_only_contacts`], sorted by cell; None where that
    /// search takes another route (no grid, long segments apart, keys or indices beyond 32
    /// bits).
    fn round_entries(&self) -> Option<Vec<u64>> {
        let n = self.len();
        let (lo, hi, total) = self.extent(self.iter());
        let grid = Grid::new(lo, hi, total, n)?;
        if n >= SPLIT_MIN && grid.h > LONG_SEGMENT * self.median_length() {
            let all: Vec<u32> = (0..n as u32).collect();
            if self.long_segments(&all).is_some() {
                return None;
            }
        }
        self.packed_entries(&grid, &(0..u64::MAX))
    }

    /// Consecutive segments ab, bc where c lies on the ray from b through a: the path
    /// reverses along itself.
    fn adjacent_overlaps(&self) -> Vec<Contact> {
        let mut out = Vec::new();
        let mut start = 0usize;
        for (c, &(n, closed)) in self.contours.iter().enumerate() {
            let n = n as usize;
            // Contour c's points: n + 1 from points[start + c] (see [`SegmentSet`]);
            // segment start + t runs from p[t] to p[t + 1]. Line cuts may retrace
            // themselves as they may cross (see `test_pair`).
            let line = self.pockets.get(c).copied().flatten() == Some(LINE_GROUP);
            let p = self
                .points
                .get(start + c..start + c + n + 1)
                .unwrap_or_default();
            if !line && n >= 1 && p.len() == n + 1 {
                // Segment i (from a to b) and the next one j (from b to c): the cheap
                // test first, a path going on (not back) fails it.
                let mut check = |i: usize, j: usize, a: DVec2, b: DVec2, c: DVec2| {
                    if (c - b).dot(a - b) > 0.0 && orient2d(a, b, c) == 0.0 {
                        out.push(Contact {
                            i: i.min(j),
                            j: i.max(j),
                            point: b,
                            proper: false,
                        });
                    }
                };
                for (t, w) in p.windows(3).enumerate() {
                    check(start + t, start + t + 1, w[0], w[1], w[2]);
                }
                if closed && n >= 2 {
                    check(start + n - 1, start, p[n - 1], p[n], p[1]);
                }
            }
            start += n;
        }
        out
    }

    fn grid_contacts(&self) -> Vec<Contact> {
        if self.len() < 2 || self.proven_apart_with_copies() {
            return Vec::new();
        }
        self.grid_only_contacts()
    }

    /// The contacts the grid finds over the whole set (no sweep tried first, no folds of
    /// consecutive segments): the route [`SegmentSet::contacts`] takes when the sweep
    /// cannot prove the set apart. Unsorted.
    pub fn grid_only_contacts(&self) -> Vec<Contact> {
        let n = self.len();
        if n < 2 {
            return Vec::new();
        }
        let (lo, hi, total) = self.extent(self.iter());
        let Some(grid) = Grid::new(lo, hi, total, n) else {
            return self.brute_force_contacts();
        };
        // Cells far larger than a typical segment (sized by a few long segments, or by the
        // bounding box they span) crowd the short ones: the long ones are then checked
        // apart.
        if n >= SPLIT_MIN
            && u32::try_from(n).is_ok()
            && grid.h > LONG_SEGMENT * self.median_length()
        {
            let all: Vec<u32> = (0..n as u32).collect();
            if let Some(long) = self.long_segments(&all) {
                let mut out = Vec::new();
                self.split_contacts(&all, long, &mut out);
                return out;
            }
        }
        self.cell_contacts(&grid, 0..u64::MAX)
    }

    /// Every pair tested (no grid, no folds of consecutive segments): the fallback for
    /// non-finite coordinates.
    pub fn brute_force(&self) -> Vec<Contact> {
        self.brute_force_contacts()
    }

    /// Quadratic fallback for degenerate extents (non-finite coordinates).
    fn brute_force_contacts(&self) -> Vec<Contact> {
        let mut out = Vec::new();
        for i in 0..self.len() {
            for j in i + 1..self.len() {
                if let Some(c) = self.test_pair(i, j) {
                    out.push(c);
                    if out.len() >= MAX_CONTACTS {
                        return out;
                    }
                }
            }
        }
        out
    }
}
