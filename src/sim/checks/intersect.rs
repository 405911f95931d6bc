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

/// Cells per axis are capped at 2²⁴ so that cell keys fit in a u64 and grid coordinates keep
/// ≥ 28 bits of precision for the widening below.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 24) as f64;

/// Widening of each segment's cell cover, in cell units: far above the rounding error of
/// grid coordinates (≤ 2²⁴ · 2⁻⁵² ≈ 4e-9), so the cover is a superset of the cells the
/// exact segment touches.
const COVER_EPS: f64 = 1e-6;

/// Cells with at most this many segments test all pairs; larger ones group exact copies
/// first ([`SegmentSet::cell_pairs`]).
const TWIN_CELL_MIN: usize = 32;

/// Bound on the mean number of cells a segment's cover may take (memory guard, see
/// [`SegmentSet::contacts`]): 4 keeps the (cell, segment) list within a few times n.
const MAX_COVER_PER_SEG: f64 = 4.0;

/// Most contacts the grid collects (memory guard): a program that crosses itself
/// everywhere, such as a random scribble of n segments, has O(n²) contacts (a 30 000-line
/// one needed 23 GB and 88 s to list them all). Beyond this many the grid stops and
/// [`SegmentSet::contacts_capped`] says so; 2²⁰ contacts take about 40 MB.
pub const MAX_CONTACTS: usize = 1 << 20;

/// A segment longer than this many times the median segment length is checked apart from
/// the others ([`SegmentSet::split_contacts`]): one far move among 10⁵ short ones would
/// otherwise size the grid by the bounding box it spans (all short segments in one cell,
/// quadratic) or cover 10⁹ cells. 64 keeps the ordinary mix of a program (arc chords,
/// lines a few hundred times longer are rare) on the single grid.
const LONG_SEGMENT: f64 = 64.0;

/// Fewest segments for which [`SegmentSet::grid_only_contacts`] looks for long ones: below
/// it the single grid is cheap whatever the lengths.
const SPLIT_MIN: usize = 1024;

/// Fewest segments [`SegmentSet::contacts_in_order`] searches in rounds: below it the
/// whole search costs a few milliseconds, and the count of findings past the report's cap
/// stays exact.
pub const ROUNDS_MIN: usize = 1 << 16;

/// Segments in the first window of [`SegmentSet::contacts_in_order`].
const FIRST_ROUND: usize = 64;

/// Growth of the windows of [`SegmentSet::contacts_in_order`] from one round to the next:
/// a set that never stops is searched in log₈(n / [`FIRST_ROUND`]) + 1 rounds, each
/// skipping in O(1) the cells without a pair in its window.
const ROUND_GROWTH: usize = 8;

/// Steps per segment [`SegmentSet::proven_apart`] may take before it leaves the decision to
/// the grid.
const CHAIN_BUDGET: usize = 16;

/// Steps per segment of the first try of the sweep over chains in
/// [`SegmentSet::proven_apart`] (and 4096 more): enough for sets whose chains each overlap
/// a few others (the benches' circles, rounded to 3 decimals, need between 1/2 and 1),
/// a sixteenth of the full budget lost where chains overlap by the hundred (a spiral)
/// before the block grid decides.
const SWEEP_TRIAL: usize = 1;

/// A run of segments `start..end` whose x strictly increases (or decreases when `rev`),
/// with its bounding box (see [`SegmentSet::proven_apart`]).
struct Chain {
    start: u32,
    end: u32,
    rev: bool,
    lo: DVec2,
    hi: DVec2,
    /// Index of its first block in the y ranges of [`SegmentSet::proven_apart`].
    block: u32,
}

/// How many times over the chains' boxes may cover the set's box before
/// [`SegmentSet::proven_apart`] skips the short try of its sweep: disjoint contours cover
/// it less than once (the benches' circles 0.8 times), the spiral's nested half turns
/// about a hundred times.
const NESTED_COVER: f64 = 8.0;

/// Segments per block of a chain in [`SegmentSet::chains_apart`].
const CHAIN_BLOCK: usize = 8;

/// One segment of a polyline: `contour` numbers the polyline, `index` the segment in it,
/// `source` is the caller's tag (a motion index).
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
    /// The caller's tag (a motion index).
    pub source: u32,
    /// The pocket its contour clears with others (see [`SegmentSet::push_polyline_in`]).
    pub pocket: Option<u32>,
}

/// The pocket mark of line cuts (`(skinpath:group 0)`; pockets are numbered from 1): cuts
/// along a drawing's lines, whose contacts with any contour, their own included, never
/// count ([`SegmentSet::test_pair`]).
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

/// Polylines split into segments (zero-length segments dropped).
#[derive(Clone, Debug, Default)]
pub struct SegmentSet {
    /// The segments, polyline by polyline.
    pub segs: Vec<Seg>,
    /// Per contour: number of segments and whether it is closed (last point = first).
    pub contours: Vec<(u32, bool)>,
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

/// Two segments that share a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Indices into [`SegmentSet::segs`], i < j.
    pub i: usize,
    /// The other segment (index into [`SegmentSet::segs`]).
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

    /// Adds a polyline; `sources[k]` tags the segment from `points[k]` to `points[k+1]`.
    /// Repeated points are skipped. Returns the contour number.
    pub fn push_polyline(&mut self, points: &[DVec2], sources: &[u32]) -> u32 {
        self.push_polyline_in(points, sources, None)
    }

    /// [`SegmentSet::push_polyline`] for a contour that clears `pocket` together with the
    /// other contours of that pocket: contacts between two contours of one pocket never
    /// count, whatever [`SegmentSet::across`] says (they may cross: rings and a deeper wire
    /// hole of one channel).
    pub fn push_polyline_in(
        &mut self,
        points: &[DVec2],
        sources: &[u32],
        pocket: Option<u32>,
    ) -> u32 {
        let Some(&first) = points.first() else {
            self.contours.push((0, false));
            return self.contours.len() as u32 - 1;
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
    pub fn begin_polyline(&self, first: DVec2, pocket: Option<u32>) -> OpenPolyline {
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
            self.segs.push(Seg {
                a: open.prev,
                b: p,
                contour: open.contour,
                index: open.count,
                source,
                pocket: open.pocket,
            });
            open.count += 1;
            open.prev = p;
        }
    }

    /// Ends `open` (closed when it has two segments or more and ends where it began);
    /// returns its contour number.
    pub fn end_polyline(&mut self, open: OpenPolyline) -> u32 {
        let closed = open.count >= 2 && open.first == open.prev;
        self.contours.push((open.count, closed));
        open.contour
    }

    /// True when segments `s` and `t` of one contour are consecutive (they share an end
    /// point by construction).
    fn adjacent(&self, i: usize, j: usize, s: &Seg, t: &Seg) -> bool {
        if s.contour != t.contour {
            return false;
        }
        let (lo, hi) = (s.index.min(t.index), s.index.max(t.index));
        if hi - lo == 1 {
            return true;
        }
        if let Some(links) = &self.links {
            let wrap = |k: usize| links.get(k).is_some_and(|l| l.wrap);
            return wrap(i) && wrap(j);
        }
        let (n, closed) = self
            .contours
            .get(s.contour as usize)
            .copied()
            .unwrap_or((0, false));
        closed && lo == 0 && hi + 1 == n
    }

    /// The directions back along the incoming segment and along the outgoing segment of the
    /// pass of segment `i` through its end point `v`; `None` where the run starts or ends
    /// at `v`.
    fn pass_at(&self, i: usize, v: DVec2) -> Option<(DVec2, DVec2)> {
        let s = self.segs.get(i)?;
        if let Some(links) = &self.links {
            let l = links.get(i)?;
            return if s.a == v {
                l.prev_a.map(|p| (p - v, s.b - v))
            } else if s.b == v {
                l.next_b.map(|q| (s.a - v, q - v))
            } else {
                None
            };
        }
        let same = |k: usize| self.segs.get(k).filter(|t| t.contour == s.contour);
        let (n, closed) = self.contours.get(s.contour as usize).copied()?;
        let first = i - s.index as usize;
        let last = first + n as usize - 1;
        let prev = if i > first {
            Some(i - 1)
        } else {
            closed.then_some(last)
        };
        let next = if i < last {
            Some(i + 1)
        } else {
            closed.then_some(first)
        };
        if s.a == v {
            let p = same(prev?)?;
            (p.b == v).then_some((p.a - v, s.b - v))
        } else if s.b == v {
            let q = same(next?)?;
            (q.a == v).then_some((s.a - v, q.b - v))
        } else {
            None
        }
    }

    /// True when segments `i` and `j` meet only at an end point `v` of both, through which
    /// the path passes twice without the two passes crossing (or where one pass starts or
    /// ends): the directions of one pass do not separate those of the other around `v`.
    fn is_revisit(&self, i: usize, j: usize) -> bool {
        let (Some(s), Some(t)) = (self.segs.get(i), self.segs.get(j)) else {
            return false;
        };
        let Some(v) = [s.a, s.b].into_iter().find(|&p| p == t.a || p == t.b) else {
            return false;
        };
        // Collinear overlaps beyond the shared point are real contacts.
        let (ds, dt) = (s.b - s.a, t.b - t.a);
        if orient2d(s.a, s.b, t.a) == 0.0 && orient2d(s.a, s.b, t.b) == 0.0 {
            let (os, ot) = (
                if s.a == v { ds } else { -ds },
                if t.a == v { dt } else { -dt },
            );
            if os.dot(ot) > 0.0 {
                return false;
            }
        }
        let (Some((a1, a2)), Some((b1, b2))) = (self.pass_at(i, v), self.pass_at(j, v)) else {
            // One of the runs ends at v: a touch at a run end, no crossing.
            return true;
        };
        let ang = |d: DVec2| d.y.atan2(d.x);
        let tau = std::f64::consts::TAU;
        let span = (ang(a2) - ang(a1)).rem_euclid(tau);
        let inside = |b: DVec2| {
            let x = (ang(b) - ang(a1)).rem_euclid(tau);
            (x > 0.0 && x < span, x == 0.0 || x == span)
        };
        let ((in1, on1), (in2, on2)) = (inside(b1), inside(b2));
        !on1 && !on2 && in1 == in2 || self.tangent_passes([a1, a2], [b1, b2])
    }

    /// True when two passes through a vertex (each as the directions back along its incoming
    /// chord and along its outgoing chord) are smooth there and tangent to each other, going
    /// the same way, within what [`SegmentSet::tangent_slack`] allows: the passes meet in
    /// that one point and at most graze (a closed contour entered by a lead arc and left by
    /// one, both tangent at its start, where the leads lie on the waste side and the contour
    /// on the other: the path runs lead → contour → lead through the point, an S-shaped
    /// tangential crossing that no flattening can show as a touch).
    ///
    /// A chord of length L of an arc whose sagitta is at most f leaves the arc's tangent at
    /// its end at the angle 2·atan(2f/L) (the half-angle of the chord's arc φ/2 satisfies
    /// tan(φ/4) = 2·sagitta/L); ends rounded by up to f more turn it by at most atan(2f/L).
    /// Each chord of length L thus is within θ(L) = 3·atan(2f/L) of the curve's tangent, and
    /// two directions at the vertex agree when their angle is at most the sum of their θ.
    fn tangent_passes(&self, a: [DVec2; 2], b: [DVec2; 2]) -> bool {
        let f = self.tangent_slack;
        if f <= 0.0 {
            return false;
        }
        let theta = |d: DVec2| 3.0 * (2.0 * f / d.length()).atan();
        let agree = |u: DVec2, w: DVec2| u.perp_dot(w).abs().atan2(u.dot(w)) <= theta(u) + theta(w);
        let [a1, a2] = a;
        let [b1, b2] = b;
        agree(-a1, a2) && agree(-b1, b2) && agree(a1, b1) && agree(a2, b2)
    }

    /// All contacts: non-adjacent pairs that share any point (proper or not), and adjacent
    /// pairs that fold back onto each other (collinear overlap beyond the shared end).
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
    pub fn contacts_in_order(&self, mut take: impl FnMut(&[Contact]) -> bool) -> (bool, bool) {
        let n = self.segs.len();
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
            let mut batch: Vec<Contact> = overlaps
                .iter()
                .filter(|c| window.contains(&c.i))
                .copied()
                .collect();
            let found = self.window_cell_contacts(
                entries.len(),
                |i| (entries[i] >> 32, entries[i] as u32),
                &window,
                MAX_CONTACTS - total,
            );
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
        let n = self.segs.len();
        let (lo, hi, total) = self.extent(self.segs.iter());
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
        for &(n, closed) in &self.contours {
            let n = n as usize;
            let end = start + n;
            let mut check = |i: usize, j: usize| {
                let (Some(s), Some(t)) = (self.segs.get(i), self.segs.get(j)) else {
                    return;
                };
                // Line cuts may retrace themselves as they may cross (see `test_pair`).
                if s.pocket == Some(LINE_GROUP) {
                    return;
                }
                // s ends where t starts.
                let (a, b, c) = (s.a, s.b, t.b);
                if orient2d(a, b, c) == 0.0 && (c - b).dot(a - b) > 0.0 {
                    out.push(Contact {
                        i: i.min(j),
                        j: i.max(j),
                        point: b,
                        proper: false,
                    });
                }
            };
            for i in start..end.saturating_sub(1) {
                check(i, i + 1);
            }
            if closed && n >= 2 {
                check(end - 1, start);
            }
            start = end;
        }
        out
    }

    fn grid_contacts(&self) -> Vec<Contact> {
        if self.segs.len() < 2 || self.proven_apart_with_copies() {
            return Vec::new();
        }
        self.grid_only_contacts()
    }

    /// The contacts the grid finds over the whole set (no sweep tried first, no folds of
    /// consecutive segments): the route [`SegmentSet::contacts`] takes when the sweep
    /// cannot prove the set apart. Unsorted.
    pub fn grid_only_contacts(&self) -> Vec<Contact> {
        let n = self.segs.len();
        if n < 2 {
            return Vec::new();
        }
        let (lo, hi, total) = self.extent(self.segs.iter());
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

    /// The median segment length (the upper one for an even count; 0 for no segment).
    fn median_length(&self) -> f64 {
        let mut lengths: Vec<f64> = self.segs.iter().map(|s| s.a.distance(s.b)).collect();
        if lengths.is_empty() {
            return 0.0;
        }
        let mid = lengths.len() / 2;
        *lengths.select_nth_unstable_by(mid, f64::total_cmp).1
    }

    /// Bounds (lo, hi) and total length of `segs`.
    fn extent<'s>(&self, segs: impl Iterator<Item = &'s Seg>) -> (DVec2, DVec2, f64) {
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
    fn long_segments(&self, ids: &[u32]) -> Option<Vec<u32>> {
        if ids.len() < 2 {
            return None;
        }
        let len = |k: u32| {
            let s = &self.segs[k as usize];
            s.a.distance(s.b)
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
    fn split_contacts(&self, ids: &[u32], long: Vec<u32>, out: &mut Vec<Contact>) {
        let short = self.without(ids, &long);
        self.subset_contacts(&short, out);
        match self.long_segments(&long) {
            Some(longer) => self.split_contacts(&long, longer, out),
            None => self.subset_contacts(&long, out),
        }
        self.long_against(&long, &short, out);
    }

    /// `ids` without `drop` (both ascending, `drop` a subset).
    fn without(&self, ids: &[u32], drop: &[u32]) -> Vec<u32> {
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
    fn long_against(&self, long: &[u32], short: &[u32], out: &mut Vec<Contact>) {
        if long.is_empty() || out.len() >= MAX_CONTACTS {
            return;
        }
        if let Some(longer) = self.long_segments(long) {
            let rest = self.without(long, &longer);
            self.long_against(&longer, short, out);
            self.long_against(&rest, short, out);
            return;
        }
        let seg = |k: &u32| &self.segs[*k as usize];
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
    fn pairs_between(&self, a: &[u32], b: &[u32], out: &mut Vec<Contact>) {
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
    fn subset_contacts(&self, ids: &[u32], out: &mut Vec<Contact>) {
        if ids.len() < 2 {
            return;
        }
        let (lo, hi, total) = self.extent(ids.iter().map(|&k| &self.segs[k as usize]));
        let Some(grid) = Grid::new(lo, hi, total, ids.len()) else {
            for (x, &i) in ids.iter().enumerate() {
                self.pairs_between(&[i], &ids[x + 1..], out);
            }
            return;
        };
        let mut entries: Vec<(u64, u32)> = Vec::with_capacity(2 * ids.len());
        for &k in ids {
            let s = &self.segs[k as usize];
            grid.cover(s.a, s.b, |key| entries.push((key, k)));
        }
        entries.sort_unstable();
        let room = MAX_CONTACTS.saturating_sub(out.len());
        let mut found = self.sorted_cell_contacts(entries.len(), |i| entries[i]);
        found.truncate(room);
        out.extend(found);
    }

    /// [`SegmentSet::proven_apart`] on the set with every contour that repeats an earlier
    /// one left out, when contacts between contours are [`Across::Crossings`] or
    /// [`Across::Never`]; on the whole set otherwise.
    ///
    /// The passes of a multi-depth cut repeat one contour bit for bit; they lie on one
    /// another, so the sweep over the whole set would spend its budget on pairs of copies
    /// and leave the decision to the grid. Leaving the copies out decides the same: with
    /// D a copy of A (same segments, same closedness), a pair of D and another contour C
    /// meets as the same pair of A and C does (same points, and the tests within one
    /// contour see the same neighbours); D meets itself where A does; and a segment of D
    /// crosses one of A properly only where the two segments of A cross properly (equal
    /// or consecutive segments share points, they never cross), so a crossing between the
    /// copies is a crossing of A with itself. Touches between contours, which copies have
    /// everywhere, do not count under these two modes.
    fn proven_apart_with_copies(&self) -> bool {
        if self.across == Across::All {
            return self.proven_apart();
        }
        match self.without_copies() {
            Some(reps) => reps.proven_apart(),
            None => self.proven_apart(),
        }
    }

    /// The set without the contours that repeat an earlier one (same number of segments,
    /// same closedness, same pocket, every end point equal bit for bit), contours
    /// renumbered in order; None when no contour repeats another, and for a tile (whose
    /// contours are not held whole: its proof is left to the grid). Contours are grouped by
    /// their first segment, then by a hash of all their points, then compared in full:
    /// O(n + m log m) for n segments in m contours.
    fn without_copies(&self) -> Option<SegmentSet> {
        let mut starts = Vec::with_capacity(self.contours.len());
        let mut at = 0usize;
        for &(n, _) in &self.contours {
            starts.push(at);
            at += n as usize;
        }
        if at != self.segs.len() {
            return None;
        }
        let span = |c: usize| &self.segs[starts[c]..starts[c] + self.contours[c].0 as usize];
        let bits = |s: &Seg| {
            let p = s.pocket.map_or(0, |p| u64::from(p) + 1);
            let [ax, ay, bx, by] = [s.a.x, s.a.y, s.b.x, s.b.y].map(f64::to_bits);
            [ax, ay, bx, by, p]
        };
        let hash = |c: usize| {
            // FNV-1a over the coordinates' bits.
            let mut h: u64 = 0xcbf2_9ce4_8422_2325;
            for s in span(c) {
                for w in bits(s) {
                    h = (h ^ w).wrapping_mul(0x0000_0100_0000_01b3);
                }
            }
            h
        };
        let same =
            |c: usize, d: usize| span(c).iter().zip(span(d)).all(|(s, t)| bits(s) == bits(t));
        // Contours are grouped by size, closedness and first segment; only the few groups
        // of two or more (the passes of one cut, mostly) are hashed whole and compared.
        let head = |c: usize| (self.contours[c], span(c).first().map(bits));
        let mut order: Vec<usize> = (0..self.contours.len()).collect();
        order.sort_unstable_by_key(|&c| (head(c), c));
        let mut copy = vec![false; self.contours.len()];
        let mut g = 0;
        while g < order.len() {
            let mut e = g + 1;
            while e < order.len() && head(order[e]) == head(order[g]) {
                e += 1;
            }
            if e - g >= 2 {
                let mut run: Vec<(u64, usize)> =
                    order[g..e].iter().map(|&c| (hash(c), c)).collect();
                run.sort_unstable();
                // Within equal hashes, each contour is a copy when it equals an earlier
                // one that is not a copy itself.
                let mut h = 0;
                while h < run.len() {
                    let mut k = h + 1;
                    while k < run.len() && run[k].0 == run[h].0 {
                        k += 1;
                    }
                    for x in h + 1..k {
                        let c = run[x].1;
                        copy[c] = run[h..x].iter().any(|&(_, d)| !copy[d] && same(d, c));
                    }
                    h = k;
                }
            }
            g = e;
        }
        if !copy.contains(&true) {
            return None;
        }
        let mut out = SegmentSet {
            across: self.across,
            tangent_slack: self.tangent_slack,
            ..SegmentSet::default()
        };
        for (c, &(n, closed)) in self.contours.iter().enumerate() {
            if copy[c] {
                continue;
            }
            let number = out.contours.len() as u32;
            out.segs.extend(span(c).iter().map(|s| Seg {
                contour: number,
                ..*s
            }));
            out.contours.push((n, closed));
        }
        Some(out)
    }

    /// True when no two segments meet ([`SegmentSet::test_pair`] gives None for every
    /// pair), proven by a sweep over x-monotone chains: then the grid, which only reports
    /// pairs `test_pair` reports, finds nothing either, and is not built. False when a pair
    /// meets, when coordinates are not finite, for tiles, and when the sweep would take
    /// more than [`CHAIN_BUDGET`] steps per segment (many chains over one another, as in a
    /// dense hatch): the grid decides then.
    ///
    /// A chain is a maximal run of consecutive segments of one contour whose x strictly
    /// increases, or strictly decreases (a segment with constant x is a chain of its own).
    /// Two segments of one chain that are not consecutive have disjoint x ranges, so only
    /// segments of two chains can meet, and only where the chains' bounding boxes overlap
    /// (closed): for such chains every pair of segments with overlapping x ranges (closed)
    /// is tested, walking both chains in x order. The chains' blocks are first laid on a
    /// grid ([`SegmentSet::blocks_apart_on_grid`]), which decides in O(n) where chains'
    /// boxes overlap by the hundred (a spiral's half turns all nest); the sweep over
    /// chains decides where the blocks are too unequal for one grid.
    fn proven_apart(&self) -> bool {
        if self.links.is_some() {
            return false;
        }
        let n = self.segs.len();
        let dir = |s: &Seg| (s.b.x - s.a.x).partial_cmp(&0.0);
        let mut chains: Vec<Chain> = Vec::new();
        let mut blocks: Vec<(f64, f64)> = Vec::with_capacity(n / CHAIN_BLOCK + 1);
        let mut k = 0;
        while k < n {
            let s = &self.segs[k];
            if !(s.a.is_finite() && s.b.is_finite()) {
                return false;
            }
            let d = dir(s);
            let mut e = k + 1;
            if d != Some(std::cmp::Ordering::Equal) {
                while e < n {
                    let t = &self.segs[e];
                    if t.contour != s.contour
                        || t.index != self.segs[e - 1].index + 1
                        || dir(t) != d
                    {
                        break;
                    }
                    e += 1;
                }
            }
            if self.segs[k + 1..e].iter().any(|t| !t.b.is_finite()) {
                return false;
            }
            let block = blocks.len() as u32;
            for run in self.segs[k..e].chunks(CHAIN_BLOCK) {
                let (lo, hi) = run
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
                        (lo.min(t.a.y).min(t.b.y), hi.max(t.a.y).max(t.b.y))
                    });
                blocks.push((lo, hi));
            }
            // The chain's box: its end points bound its x range, its blocks its y range.
            let (x0, x1) = (s.a.x, self.segs[e - 1].b.x);
            let (y0, y1) = blocks[block as usize..]
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
                    (lo.min(y.0), hi.max(y.1))
                });
            chains.push(Chain {
                start: k as u32,
                end: e as u32,
                rev: d == Some(std::cmp::Ordering::Less),
                lo: DVec2::new(x0.min(x1), y0),
                hi: DVec2::new(x0.max(x1), y1),
                block,
            });
            k = e;
        }
        chains.sort_by(|a, b| a.lo.x.total_cmp(&b.lo.x));
        // A short try of the sweep over chains, which decides sparse sets (circles apart,
        // each chain near a few others) for less than the grid costs; then the grid; then
        // the sweep in full where the grid cannot be built.
        // Chains nested by the dozen (a spiral's half turns) make the try spend its budget
        // and decide nothing: their boxes then cover the set's box many times over, and
        // the grid goes first. Both routes are exact, so the answer is the same.
        let (lo, hi) = chains.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), c| (lo.min(c.lo), hi.max(c.hi)),
        );
        let covered: f64 = chains.iter().map(|c| (c.hi - c.lo).element_product()).sum();
        let box_area = (hi - lo).element_product();
        let nested = box_area > 0.0 && covered > NESTED_COVER * box_area;
        let trial = SWEEP_TRIAL.saturating_mul(n).saturating_add(4096);
        if !nested && let Some(apart) = self.chains_sweep(&chains, &blocks, trial) {
            return apart;
        }
        let full = CHAIN_BUDGET.saturating_mul(n).saturating_add(4096);
        let mut budget = full;
        let mut spend = |k: usize| {
            budget = budget.saturating_sub(k);
            budget > 0
        };
        if let Some(apart) = self.blocks_apart_on_grid(&chains, &blocks, &mut spend) {
            return apart;
        }
        self.chains_sweep(&chains, &blocks, full).unwrap_or(false)
    }

    /// The sweep over `chains` (sorted by their boxes' low x) of
    /// [`SegmentSet::proven_apart`]: Some(true) when no two segments meet, Some(false) when a
    /// pair meets, None when it ran out of steps first: `budget` for the comparisons of
    /// chains whose boxes overlap, [`CHAIN_BUDGET`] per segment for the scan of the chains
    /// active at each one (cheap box tests: a column of circles keeps hundreds active).
    fn chains_sweep(&self, chains: &[Chain], blocks: &[(f64, f64)], budget: usize) -> Option<bool> {
        let mut scan = CHAIN_BUDGET
            .saturating_mul(self.segs.len())
            .saturating_add(4096);
        let mut left = budget;
        let mut spend = |k: usize| {
            left = left.saturating_sub(k);
            left > 0
        };
        let mut active: Vec<usize> = Vec::new();
        for (c, ch) in chains.iter().enumerate() {
            active.retain(|&a| chains[a].hi.x >= ch.lo.x);
            scan = scan.saturating_sub(active.len() + 1);
            if scan == 0 || !spend(1) {
                return None;
            }
            for &a in &active {
                let o = &chains[a];
                if o.hi.y >= ch.lo.y
                    && ch.hi.y >= o.lo.y
                    && !self.chains_apart(o, ch, blocks, &mut spend)
                {
                    return if left == 0 { None } else { Some(false) };
                }
            }
            active.push(c);
        }
        Some(true)
    }

    /// [`SegmentSet::proven_apart`] by the blocks of its chains on a uniform grid: Some(true)
    /// when no two segments meet, Some(false) when a pair meets or the budget runs out, None
    /// when the grid would take too many cells (blocks far larger than the typical one, as
    /// a long move among short ones): the chain sweep decides then. `chains` in any order.
    ///
    /// Each block (up to [`CHAIN_BLOCK`] consecutive segments of one chain, `ys` its y
    /// range, its end points its x range) is entered into every cell its box overlaps; the
    /// cell size is the smaller of the median block extent and √(area / blocks), so that a
    /// dense set (a spiral of 200 turns, 10⁶ segments) has O(1) blocks per cell. A pair of
    /// blocks of two chains is examined in the one cell that holds the low corner of the
    /// intersection of their boxes (closed), and its segments are walked in x order, each
    /// tested ([`SegmentSet::test_pair`]) against those of the other whose x range overlaps
    /// its own. Pairs skipped cannot meet: boxes apart, x ranges apart, or one chain (its
    /// segments that are not consecutive have disjoint x ranges, consecutive ones are
    /// adjacent). O(n + m log m + pairs of blocks whose boxes overlap) for m blocks.
    fn blocks_apart_on_grid(
        &self,
        chains: &[Chain],
        ys: &[(f64, f64)],
        spend: &mut impl FnMut(usize) -> bool,
    ) -> Option<bool> {
        // Blocks: (box lo, box hi, chain, block number within the chain).
        let mut boxes: Vec<(DVec2, DVec2, u32, u32)> = Vec::with_capacity(ys.len());
        for (c, ch) in chains.iter().enumerate() {
            let count = (ch.end - ch.start) as usize;
            for i in 0..count.div_ceil(CHAIN_BLOCK) {
                let s0 = ch.start as usize + i * CHAIN_BLOCK;
                let s1 = (s0 + CHAIN_BLOCK).min(ch.end as usize);
                let (x0, x1) = (self.segs[s0].a.x, self.segs[s1 - 1].b.x);
                let (y0, y1) = *ys.get(ch.block as usize + i)?;
                boxes.push((
                    DVec2::new(x0.min(x1), y0),
                    DVec2::new(x0.max(x1), y1),
                    c as u32,
                    i as u32,
                ));
            }
        }
        let m = boxes.len();
        if m < 2 {
            return Some(true);
        }
        u32::try_from(m).ok()?;
        let (lo, hi) = boxes.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), b| (lo.min(b.0), hi.max(b.1)),
        );
        let mut extents: Vec<f64> = boxes.iter().map(|b| (b.1 - b.0).max_element()).collect();
        let (_, &mut median, _) = extents.select_nth_unstable_by(m / 2, f64::total_cmp);
        let ext = hi - lo;
        let by_area = (ext.x.max(median) * ext.y.max(median) / m as f64).sqrt();
        let h = median
            .min(by_area)
            .max(ext.max_element() / MAX_CELLS_PER_AXIS);
        if !(h.is_finite() && h > 0.0) {
            return None;
        }
        let ny = (ext.y / h) as u64 + 2;
        let cell = |p: DVec2| {
            let q = (p - lo) / h;
            (q.x as u64, q.y as u64)
        };
        // Cells a box covers, counted before any is stored (memory guard).
        let mut covers = 0u64;
        for b in &boxes {
            let ((c0, r0), (c1, r1)) = (cell(b.0), cell(b.1));
            covers = covers.saturating_add((c1 - c0 + 1).saturating_mul(r1 - r0 + 1));
        }
        let bound = (MAX_COVER_PER_SEG as u64)
            .saturating_mul(m as u64)
            .saturating_add(4096);
        let max_key = ((ext.x / h) as u64 + 2).saturating_mul(ny);
        if covers > bound || max_key > u64::from(u32::MAX) {
            return None;
        }
        let mut entries: Vec<u64> = Vec::with_capacity(covers as usize);
        for (k, b) in boxes.iter().enumerate() {
            let ((c0, r0), (c1, r1)) = (cell(b.0), cell(b.1));
            for c in c0..=c1 {
                for r in r0..=r1 {
                    entries.push(((c * ny + r) << 32) | k as u64);
                }
            }
        }
        radix_sort_high(&mut entries, 64 - max_key.leading_zeros());
        let mut g = 0;
        while g < entries.len() {
            let key = entries[g] >> 32;
            let mut e = g + 1;
            while e < entries.len() && entries[e] >> 32 == key {
                e += 1;
            }
            for x in g..e {
                let p = &boxes[entries[x] as u32 as usize];
                for &y in &entries[x + 1..e] {
                    let q = &boxes[y as u32 as usize];
                    if p.2 == q.2 || p.0.cmpgt(q.1).any() || q.0.cmpgt(p.1).any() {
                        continue;
                    }
                    let (c, r) = cell(p.0.max(q.0));
                    if c * ny + r != key {
                        continue;
                    }
                    let (a, b) = (&chains[p.2 as usize], &chains[q.2 as usize]);
                    if !spend(1) || !self.blocks_apart(a, p.3, b, q.3, spend) {
                        return Some(false);
                    }
                }
            }
            g = e;
        }
        Some(true)
    }

    /// True when no segment of block `i` of chain `a` meets one of block `j` of chain `b`
    /// (blocks of [`CHAIN_BLOCK`] segments in storage order); false when a pair meets or the
    /// budget runs out. The segments of each block are taken in x order; each is tested
    /// against the run of the other's whose x ranges (closed) overlap its own.
    fn blocks_apart(
        &self,
        a: &Chain,
        i: u32,
        b: &Chain,
        j: u32,
        spend: &mut impl FnMut(usize) -> bool,
    ) -> bool {
        // Segment indices of block k of chain c, in x order.
        let run = |c: &Chain, k: u32| {
            let s0 = c.start as usize + k as usize * CHAIN_BLOCK;
            let s1 = (s0 + CHAIN_BLOCK).min(c.end as usize);
            let rev = c.rev;
            (0..s1 - s0).map(move |t| if rev { s1 - 1 - t } else { s0 + t })
        };
        let xs = |k: usize| {
            let s = &self.segs[k];
            (s.a.x.min(s.b.x), s.a.x.max(s.b.x))
        };
        let mut held = [0usize; CHAIN_BLOCK];
        let mut count = 0;
        for q in run(b, j) {
            held[count] = q;
            count += 1;
        }
        let others = &held[..count];
        let mut first = 0;
        for p in run(a, i) {
            let (plo, phi) = xs(p);
            while first < others.len() && xs(others[first]).1 < plo {
                first += 1;
            }
            for &q in &others[first..] {
                if xs(q).0 > phi {
                    break;
                }
                if !spend(1) || self.test_pair(p, q).is_some() {
                    return false;
                }
            }
        }
        true
    }

    /// True when no segment of chain `a` meets one of chain `b` (see
    /// [`SegmentSet::proven_apart`]); false when a pair meets or the budget runs out.
    /// `ys` holds the y range of every block of [`CHAIN_BLOCK`] consecutive segments of
    /// each chain (a chain's blocks from [`Chain::block`] on, in storage order).
    ///
    /// The blocks of a chain, in x order, have increasing x ranges (the end points of a
    /// block bound its x range, and consecutive blocks share an end), so the blocks of one
    /// chain that overlap an x interval are a run found by binary search. Each block of the
    /// shorter chain within the other's box is compared with the run of the longer
    /// chain's blocks overlapping its x range; only blocks whose boxes overlap test their
    /// segment pairs. Nested contours (a board outline around letters, concentric clearing
    /// rings) have chains whose boxes overlap over their whole length while the chains stay
    /// apart in y; their blocks do not meet. O(k log m + pairs of blocks that meet) for
    /// chains of k ≤ m blocks.
    fn chains_apart(
        &self,
        a: &Chain,
        b: &Chain,
        ys: &[(f64, f64)],
        spend: &mut impl FnMut(usize) -> bool,
    ) -> bool {
        let (short, long) = if a.end - a.start <= b.end - b.start {
            (a, b)
        } else {
            (b, a)
        };
        let count = |c: &Chain| (c.end - c.start) as usize;
        let blocks = |c: &Chain| count(c).div_ceil(CHAIN_BLOCK);
        // Block i of chain c in storage order: its segment range and its box.
        let block = |c: &Chain, i: usize| {
            let s0 = c.start as usize + i * CHAIN_BLOCK;
            let s1 = (s0 + CHAIN_BLOCK).min(c.end as usize);
            let (x0, x1) = (self.segs[s0].a.x, self.segs[s1 - 1].b.x);
            let (y0, y1) = ys[c.block as usize + i];
            (
                s0..s1,
                DVec2::new(x0.min(x1), y0),
                DVec2::new(x0.max(x1), y1),
            )
        };
        // Block i of chain c in x order.
        let in_x_order = |c: &Chain, i: usize| {
            if c.rev {
                block(c, blocks(c) - 1 - i)
            } else {
                block(c, i)
            }
        };
        let nl = blocks(long);
        for i in 0..blocks(short) {
            let (run, lo, hi) = block(short, i);
            if lo.cmpgt(long.hi).any() || hi.cmplt(long.lo).any() {
                continue;
            }
            if !spend(1) {
                return false;
            }
            // First block of the long chain (in x order) whose x range reaches lo.x.
            let (mut j, mut top) = (0usize, nl);
            while j < top {
                let mid = (j + top) / 2;
                if in_x_order(long, mid).2.x < lo.x {
                    j = mid + 1;
                } else {
                    top = mid;
                }
            }
            while j < nl {
                let (other, olo, ohi) = in_x_order(long, j);
                if olo.x > hi.x {
                    break;
                }
                j += 1;
                if olo.y > hi.y || ohi.y < lo.y {
                    continue;
                }
                for ka in run.clone() {
                    for kb in other.clone() {
                        if !spend(1) || self.test_pair(ka, kb).is_some() {
                            return false;
                        }
                    }
                }
            }
        }
        true
    }

    /// A tile of a larger set: `segs` with their neighbours `links` (same length), in the
    /// larger set's order, contacts between contours counted by `across`; see
    /// [`SegmentSet::cell_contacts`].
    pub fn tile(segs: Vec<Seg>, links: Vec<Link>, across: Across, tangent_slack: f64) -> Self {
        SegmentSet {
            segs,
            contours: Vec::new(),
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
        let mut entries: Vec<(u64, u32)> = Vec::with_capacity(2 * self.segs.len());
        for (k, s) in self.segs.iter().enumerate() {
            grid.cover(s.a, s.b, |key| {
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
    fn sorted_cell_contacts(&self, n: usize, entry: impl Fn(usize) -> (u64, u32)) -> Vec<Contact> {
        self.window_cell_contacts(n, entry, &(0..usize::MAX), MAX_CONTACTS)
    }

    /// [`SegmentSet::sorted_cell_contacts`] of the pairs whose lower segment index is in
    /// `window`, until `limit` contacts: the same pairs tested as on the whole set (each
    /// cell's pairs are chosen from all its segments), those outside the window skipped.
    /// A cell's segments come in increasing index, so a cell whose first segment is at or
    /// past the window's end, or whose last is before its start, has no pair in it.
    fn window_cell_contacts(
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
    fn packed_cell_contacts(
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
    fn packed_entries(&self, grid: &Grid, keys: &std::ops::Range<u64>) -> Option<Vec<u64>> {
        u32::try_from(self.segs.len()).ok()?;
        let mut entries: Vec<u64> = Vec::with_capacity(2 * self.segs.len());
        let mut max_key = 0u64;
        for (k, s) in self.segs.iter().enumerate() {
            grid.cover(s.a, s.b, |key| {
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
    /// Only pairs whose lower index is in `window` are tested, until `limit` contacts.
    fn cell_pairs(
        &self,
        cell: &[u32],
        window: &std::ops::Range<usize>,
        limit: usize,
        out: &mut Vec<Contact>,
    ) {
        let mut test = |i: u32, j: u32| {
            if out.len() < limit
                && window.contains(&(i.min(j) as usize))
                && let Some(c) = self.test_pair(i as usize, j as usize)
            {
                out.push(c);
            }
        };
        if cell.len() <= TWIN_CELL_MIN {
            for (x, &i) in cell.iter().enumerate() {
                for &j in &cell[x + 1..] {
                    test(i, j);
                }
            }
            return;
        }
        let key = |k: u32| {
            let s = &self.segs[k as usize];
            let (p, q) = if (s.a.x, s.a.y) <= (s.b.x, s.b.y) {
                (s.a, s.b)
            } else {
                (s.b, s.a)
            };
            [p.x.to_bits(), p.y.to_bits(), q.x.to_bits(), q.y.to_bits()]
        };
        let mut ids: Vec<u32> = cell.to_vec();
        ids.sort_by_key(|&k| (key(k), k));
        let mut groups: Vec<(usize, usize)> = Vec::new();
        let mut g = 0;
        while g < ids.len() {
            let mut e = g + 1;
            while e < ids.len() && key(ids[e]) == key(ids[g]) {
                e += 1;
            }
            groups.push((g, e));
            g = e;
        }
        let reps: Vec<u32> = groups.iter().map(|&(a, _)| ids[a]).collect();
        for (x, &i) in reps.iter().enumerate() {
            for &j in &reps[x + 1..] {
                test(i, j);
            }
        }
        for (gi, &(a, e)) in groups.iter().enumerate() {
            for &m in &ids[a + 1..e] {
                test(ids[a], m);
                let cm = self.segs[m as usize].contour;
                for (gj, &r) in reps.iter().enumerate() {
                    if gj != gi && self.segs[r as usize].contour == cm {
                        test(m, r);
                    }
                }
            }
        }
    }

    /// Every pair tested (no grid, no folds of consecutive segments): the fallback for
    /// non-finite coordinates.
    pub fn brute_force(&self) -> Vec<Contact> {
        self.brute_force_contacts()
    }

    /// Quadratic fallback for degenerate extents (non-finite coordinates).
    fn brute_force_contacts(&self) -> Vec<Contact> {
        let mut out = Vec::new();
        for i in 0..self.segs.len() {
            for j in i + 1..self.segs.len() {
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

    /// Exact contact test of two segments; same-contour adjacent pairs are skipped (see
    /// `Self::adjacent_overlaps`), and pairs of two contours follow [`SegmentSet::across`].
    pub fn test_pair(&self, i: usize, j: usize) -> Option<Contact> {
        let (s, t) = (self.segs.get(i)?, self.segs.get(j)?);
        if s.a.max(s.b).cmplt(t.a.min(t.b)).any() || t.a.max(t.b).cmplt(s.a.min(s.b)).any() {
            return None;
        }
        let across = s.contour != t.contour;
        let one_pocket = s.pocket.is_some() && s.pocket == t.pocket;
        // Line cuts follow a drawing's lines: they may cross anything, themselves included.
        let line = s.pocket == Some(LINE_GROUP) || t.pocket == Some(LINE_GROUP);
        if line
            || across && (self.across == Across::Never || one_pocket)
            || self.adjacent(i, j, s, t)
        {
            return None;
        }
        let (i, j) = (i.min(j), i.max(j));
        let o1 = orient2d(s.a, s.b, t.a);
        let o2 = orient2d(s.a, s.b, t.b);
        let o3 = orient2d(t.a, t.b, s.a);
        let o4 = orient2d(t.a, t.b, s.b);
        if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
            let point = line_intersection(s.a, s.b, t.a, t.b).unwrap_or(s.a);
            return Some(Contact {
                i,
                j,
                point,
                proper: true,
            });
        }
        if across && self.across == Across::Crossings || !segments_intersect(s.a, s.b, t.a, t.b) {
            return None;
        }
        // The path passing twice through one of its vertices without crossing there (a
        // closed loop entered by a lead-in and closed at its start) is a revisit, not a
        // contact.
        if self.is_revisit(i, j) {
            return None;
        }
        // A touching or overlapping contact: report an end point that lies on the other.
        let point = [(o1, t.a), (o2, t.b)]
            .into_iter()
            .find(|&(o, _)| o == 0.0)
            .map(|(_, p)| p)
            .unwrap_or(if o3 == 0.0 { s.a } else { s.b });
        Some(Contact {
            i,
            j,
            point,
            proper: false,
        })
    }
}

/// Largest digit of [`radix_sort_high`]: 2¹⁰ buckets keep the scatter's destinations in
/// cache.
const RADIX_BITS: u32 = 10;

/// Sorts `v` by bits 32..32 + `bits` (the bits above are zero), stably: a least significant
/// digit radix sort, at most [`RADIX_BITS`] bits per pass.
fn radix_sort_high(v: &mut Vec<u64>, bits: u32) {
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
fn cover(a: DVec2, b: DVec2, mut f: impl FnMut(u64, u64)) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Contours under the line mark cross each other, themselves (or turn back onto themselves)
    /// without a contact (by the grid and by brute force alike); two unmarked contours
    /// that cross still give one.
    #[test]
    fn line_cuts_cross_freely_other_cuts_do_not() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        // A bow tie crossing itself at (1, 1), a line across it, and an unmarked square
        // the line crosses.
        let bow = [p(0.0, 0.0), p(2.0, 2.0), p(2.0, 0.0), p(0.0, 2.0)];
        let across = [p(-1.0, 1.5), p(3.0, 1.5)];
        let square = [
            p(2.5, 1.0),
            p(3.5, 1.0),
            p(3.5, 2.0),
            p(2.5, 2.0),
            p(2.5, 1.0),
        ];
        let mut s = SegmentSet::new();
        s.across = Across::Crossings;
        s.push_polyline_in(&bow, &[], Some(LINE_GROUP));
        s.push_polyline_in(&across, &[], Some(LINE_GROUP));
        // A line that turns back onto itself (a pen stroke retraced).
        let retrace = [p(5.0, 0.0), p(7.0, 0.0), p(6.0, 0.0)];
        s.push_polyline_in(&retrace, &[], Some(LINE_GROUP));
        s.push_polyline(&square, &[]);
        assert!(s.contacts_capped().0.is_empty());
        assert!(s.brute_force_contacts().is_empty());
        // Unmarked, the bow tie crosses itself (at (1, 1)), the line crosses each of the
        // bow tie's three segments and the square's left side.
        let mut t = SegmentSet::new();
        t.across = Across::Crossings;
        t.push_polyline(&bow, &[]);
        t.push_polyline(&across, &[]);
        t.push_polyline(&retrace, &[]);
        t.push_polyline(&square, &[]);
        let found = t.brute_force_contacts();
        assert_eq!(found.len(), 1 + 3 + 1, "{found:?}");
        // and the retrace folds back onto itself (an adjacent overlap, not a pair test).
        assert_eq!(t.contacts_capped().0.len(), found.len() + 1);
    }

    /// Passes of one contour are left out of the sweep's set; contours that only start
    /// alike, or repeat a contour in another pocket, are kept.
    #[test]
    fn copies_are_exact_repeats_of_a_contour() {
        let sq = |x: f64| {
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.0, 0.0)]
                .map(|(a, b)| DVec2::new(a + x, b))
        };
        let mut s = SegmentSet::new();
        s.across = Across::Crossings;
        for _ in 0..3 {
            s.push_polyline(&sq(0.0), &[]);
            s.push_polyline(&sq(5.0), &[]);
        }
        let reps = s.without_copies().expect("copies");
        assert_eq!(reps.contours, vec![(4, true), (4, true)]);
        assert_eq!(reps.segs.len(), 8);
        assert!(
            reps.segs[4..]
                .iter()
                .all(|g| g.contour == 1 && g.a.x >= 5.0)
        );
        // Same start, same count, another path: no copy.
        let mut other = sq(0.0);
        other[2].y = 2.0;
        let mut s = SegmentSet::new();
        s.push_polyline(&sq(0.0), &[]);
        s.push_polyline(&other, &[]);
        assert!(s.without_copies().is_none());
        // The same path in another pocket: no copy.
        let mut s = SegmentSet::new();
        s.push_polyline_in(&sq(0.0), &[], Some(1));
        s.push_polyline(&sq(0.0), &[]);
        assert!(s.without_copies().is_none());
    }

    #[test]
    fn radix_sort_orders_as_sort_unstable() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut v: Vec<u64> = (0..5000u64)
            .map(|k| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                ((x % 3000) << 32) | k
            })
            .collect();
        let mut want = v.clone();
        want.sort_unstable();
        radix_sort_high(&mut v, 12);
        assert_eq!(v, want);
    }

    fn naive(set: &SegmentSet) -> Vec<(usize, usize)> {
        let mut v: Vec<_> = set
            .brute_force_contacts()
            .into_iter()
            .chain(set.adjacent_overlaps())
            .map(|c| (c.i, c.j))
            .collect();
        v.sort();
        v.dedup();
        v
    }

    fn pts(v: &[(f64, f64)]) -> Vec<DVec2> {
        v.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
    }

    #[test]
    fn revisited_vertex_is_not_a_contact_but_a_crossing_vertex_is() {
        // Lead-in to (0,0), a square loop back to (0,0), lead-out: a revisit.
        let mut s = SegmentSet::new();
        s.push_polyline(
            &pts(&[
                (-1., -1.),
                (0., 0.),
                (1., 0.),
                (1., 1.),
                (0., 1.),
                (0., 0.),
                (-1., -0.5),
            ]),
            &[],
        );
        assert!(s.contacts().is_empty(), "{:?}", s.contacts());
        // A figure eight whose passes cross at the shared vertex (0,0).
        let mut x = SegmentSet::new();
        x.push_polyline(
            &pts(&[
                (-1., -1.),
                (0., 0.),
                (1., 1.),
                (1., -1.),
                (0., 0.),
                (-1., 1.),
            ]),
            &[],
        );
        assert!(!x.contacts().is_empty());
    }

    /// Points of the arc about `c` of radius `r` from angle `a0` sweeping `sweep`, in
    /// chords of sagitta at most `f`.
    fn arc_pts(c: DVec2, r: f64, a0: f64, sweep: f64, f: f64) -> Vec<DVec2> {
        let n = (sweep.abs() / (2.0 * (1.0 - f / r).acos())).ceil() as usize;
        (0..=n)
            .map(|k| {
                let a = a0 + sweep * k as f64 / n as f64;
                c + r * DVec2::new(a.cos(), a.sin())
            })
            .collect()
    }

    #[test]
    fn tangent_leads_at_a_contour_start_graze_but_a_shallow_crossing_does_not() {
        use std::f64::consts::{FRAC_PI_2, PI};
        let f = 1e-3;
        // A circle of radius 2 through (0,0), run counter-clockwise from there (travel +x);
        // a lead-in arc of radius 1 below (the waste side) arriving at (0,0) along +x, and
        // the lead-out on the same circle leaving along +x: an S-shaped tangential crossing.
        for (r_lead, r_contour) in [(1.0, 2.0), (0.3, 5.0), (3.0, 1.0)] {
            let lead_c = DVec2::new(0.0, -r_lead);
            // The program names the point (0,0) at each pass through it.
            let exact_at_origin = |mut p: Vec<DVec2>, first: bool| {
                let k = if first { 0 } else { p.len() - 1 };
                p[k] = DVec2::ZERO;
                p
            };
            let mut path = exact_at_origin(arc_pts(lead_c, r_lead, PI, -FRAC_PI_2, f), false);
            let contour = arc_pts(
                DVec2::new(0.0, r_contour),
                r_contour,
                -FRAC_PI_2,
                2.0 * PI,
                f,
            );
            path.extend_from_slice(&exact_at_origin(contour, false)[1..]);
            let lead_out = arc_pts(lead_c, r_lead, FRAC_PI_2, -FRAC_PI_2, f);
            path.extend_from_slice(&exact_at_origin(lead_out, true)[1..]);
            let mut strict = SegmentSet::new();
            strict.push_polyline(&path, &[]);
            assert!(!strict.contacts().is_empty(), "chords alone cross");
            let mut set = SegmentSet::new();
            set.tangent_slack = f;
            set.push_polyline(&path, &[]);
            assert!(
                set.contacts().is_empty(),
                "{r_lead} {r_contour}: {:?}",
                set.contacts()
            );
        }
        // Two passes through (0,0) crossing at 2 degrees on chords of length 1: a crossing.
        let a = 2f64.to_radians();
        let mut x = SegmentSet::new();
        x.tangent_slack = f;
        x.push_polyline(
            &pts(&[
                (-1.0, 0.0),
                (0.0, 0.0),
                (1.0, 0.0),
                (1.0, 1.0),
                (-1.0, 1.0),
                (-a.cos(), -a.sin()),
                (0.0, 0.0),
                (a.cos(), a.sin()),
            ]),
            &[],
        );
        assert!(!x.contacts().is_empty());
    }

    #[test]
    fn square_is_simple_bowtie_is_not() {
        let mut s = SegmentSet::new();
        s.push_polyline(
            &pts(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.), (0., 0.)]),
            &[],
        );
        assert!(s.contacts().is_empty());
        let mut b = SegmentSet::new();
        b.push_polyline(
            &pts(&[(0., 0.), (1., 1.), (1., 0.), (0., 1.), (0., 0.)]),
            &[],
        );
        let c = b.contacts();
        assert_eq!(c.len(), 1);
        assert!(c[0].proper);
        assert!((c[0].point - DVec2::splat(0.5)).length() < 1e-15);
    }

    #[test]
    fn backtrack_and_touch() {
        let mut s = SegmentSet::new();
        s.push_polyline(&pts(&[(0., 0.), (2., 0.), (1., 0.)]), &[]);
        assert_eq!(s.contacts().len(), 1);
        // A vertex touching a non-adjacent segment.
        let mut t = SegmentSet::new();
        t.push_polyline(&pts(&[(0., 0.), (4., 0.), (4., 2.), (2., 0.)]), &[]);
        let c = t.contacts();
        assert_eq!(c.len(), 1);
        assert!(!c[0].proper);
        assert_eq!(c[0].point, DVec2::new(2.0, 0.0));
    }

    #[test]
    fn coincident_contours_stay_linear() {
        // 2,000 copies of one square (and one square crossing them): contacts grow with
        // the copies, not with their pairs, and the crossing is still found.
        let sq = pts(&[
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (0.0, 10.0),
            (0.0, 0.0),
        ]);
        let mut set = SegmentSet::new();
        for _ in 0..2000 {
            set.push_polyline(&sq, &[]);
        }
        let cross = pts(&[(5.0, -5.0), (5.0, 5.0)]);
        set.push_polyline(&cross, &[]);
        let c = set.contacts();
        assert!(c.len() < 20 * 2000, "{} contacts", c.len());
        let crossing = set.segs.len() - 1;
        assert!(c.iter().any(|c| c.j == crossing && c.proper));
        // Copies of the same contour (a retraced contour) still touch themselves.
        let mut twice = sq.clone();
        twice.extend_from_slice(&sq[1..]);
        let mut one = SegmentSet::new();
        for _ in 0..40 {
            one.push_polyline(&twice, &[]);
        }
        let c = one.contacts();
        assert!(
            c.iter()
                .any(|c| one.segs[c.i].contour == one.segs[c.j].contour)
        );
    }

    #[test]
    fn dense_hatch_stays_small_and_exact() {
        // 400 parallel lines 100 long, 0.25 apart, plus one diagonal crossing them all.
        let mut s = SegmentSet::new();
        for k in 0..400 {
            let y = 0.25 * k as f64;
            s.push_polyline(&pts(&[(0.0, y), (100.0, y)]), &[]);
        }
        s.push_polyline(&pts(&[(0.5, -1.0), (99.5, 101.0)]), &[]);
        let got: Vec<_> = s.contacts().iter().map(|c| (c.i, c.j)).collect();
        assert_eq!(got.len(), 400);
        assert_eq!(got, naive(&s));
    }

    #[test]
    fn grid_matches_brute_force_on_a_random_scribble() {
        // A deterministic pseudo-random walk with many crossings, at several scales.
        for scale in [1e-3, 1.0, 1e4] {
            let mut s = SegmentSet::new();
            let mut state = 12345u64;
            let mut next = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((state >> 11) as f64 / (1u64 << 53) as f64) * scale
            };
            for _ in 0..4 {
                let p: Vec<DVec2> = (0..60).map(|_| DVec2::new(next(), next())).collect();
                s.push_polyline(&p, &[]);
            }
            let got: Vec<_> = s.contacts().iter().map(|c| (c.i, c.j)).collect();
            assert_eq!(got, naive(&s));
            assert!(!got.is_empty());
        }
    }

    /// A walk of short steps with long jumps of several scales among them (the split of
    /// [`SegmentSet::split_contacts`], recursively): the contacts are those of every pair
    /// tested, and the long jumps' bounds no longer size the grid (issue #40: 10⁵ short
    /// moves and one `G1 X1000000000`).
    #[test]
    fn long_segments_apart_give_the_contacts_of_every_pair() {
        let mut state = 777u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut s = SegmentSet::new();
        let mut p = DVec2::ZERO;
        let mut pts = vec![p];
        for k in 0..3000 {
            let step = match k % 500 {
                0 => 1e9,
                250 => 1e3,
                100 | 300 => 40.0,
                _ => 0.3,
            };
            let v = DVec2::new(next() - 0.5, next() - 0.5) * step;
            // The far jumps land at (x, 0.5), |x| up to 5·10⁸, and the walk goes on there.
            p = if step > 1e6 {
                DVec2::new(v.x, 0.5)
            } else {
                p + v
            };
            pts.push(p);
        }
        s.push_polyline(&pts, &[]);
        assert!(SPLIT_MIN <= s.segs.len());
        let long = s.long_segments(&(0..s.segs.len() as u32).collect::<Vec<_>>());
        assert!(long.is_some_and(|l| l.len() >= 6 && l.len() < 100));
        let got: Vec<_> = s.contacts().iter().map(|c| (c.i, c.j)).collect();
        let want = naive(&s);
        assert_eq!(got, want);
        // Long segments cross short ones too: the long-against-short pass is exercised.
        let long_short = want.iter().any(|&(i, j)| {
            let len = |k: usize| s.segs[k].a.distance(s.segs[k].b);
            (len(i) > 100.0) != (len(j) > 100.0)
        });
        assert!(long_short && want.len() > 100, "{}", want.len());
    }

    /// Polylines on a coarse integer lattice (shared vertices, collinear overlaps, vertical
    /// runs, retraced and coincident contours), spread apart by `spread`.
    fn lattice_set(steps: &[(i8, i8)], spread: f64, closed: bool) -> SegmentSet {
        let mut s = SegmentSet::new();
        for (c, run) in steps.chunks(7).enumerate() {
            let o = DVec2::new(spread * c as f64, 0.5 * spread * (c % 3) as f64);
            let mut p = vec![o];
            for &(dx, dy) in run {
                let q = *p.last().unwrap_or(&o) + DVec2::new(f64::from(dx), f64::from(dy));
                p.push(q);
            }
            if closed {
                p.push(o);
            }
            s.push_polyline(&p, &[]);
        }
        s
    }

    #[test]
    fn chains_prove_disjoint_circles_apart() {
        let mut s = SegmentSet::new();
        for c in 0..9 {
            let o = DVec2::new(9.0 * (c % 3) as f64, 9.0 * (c / 3) as f64);
            let p: Vec<DVec2> = (0..=200)
                .map(|i| {
                    let t = std::f64::consts::TAU * (i % 200) as f64 / 200.0;
                    let q = o + 4.0 * DVec2::new(t.cos(), t.sin());
                    // Rounded as G-code writes them: runs of equal x (vertical segments).
                    (q * 1e2).round() / 1e2
                })
                .collect();
            s.push_polyline(&p, &[]);
        }
        assert!(s.proven_apart());
        assert!(s.contacts().is_empty());
        assert!(naive(&s).is_empty());
    }

    /// An Archimedean spiral about `c`: `turns` turns `pitch` apart in `per_turn` chords a
    /// turn, points rounded to 3 decimals as a program writes them.
    fn spiral(c: DVec2, turns: usize, per_turn: usize, pitch: f64) -> Vec<DVec2> {
        (0..=turns * per_turn)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / per_turn as f64;
                let r = pitch * t / std::f64::consts::TAU;
                ((c + r * DVec2::new(t.cos(), t.sin())) * 1e3).round() / 1e3
            })
            .collect()
    }

    /// A dense spiral (40 turns 0.45 apart, 2,000 chords a turn: its half turns' chains all
    /// nest) is proven apart by the block grid, without the budget running out; its
    /// chords are far shorter than the gap between turns (≤ 2π·18/2000 ≈ 0.057 < 0.45), so
    /// no two non-consecutive ones can meet. A chord across it is found where the grid of
    /// segments and every pair tested agree.
    #[test]
    fn dense_spiral_is_proven_apart_and_a_chord_across_it_is_found() {
        let c = DVec2::new(50.0, 50.0);
        let mut s = SegmentSet::new();
        s.push_polyline(&spiral(c, 40, 2000, 0.45), &[]);
        let n = s.segs.len();
        assert!(n > 70_000, "{n}");
        assert!(s.proven_apart());
        assert!(s.contacts().is_empty());
        // A chord from the centre out, off the rounded points' lattice, crosses every turn
        // once (40; the points rounded near the centre, where chords are 10⁻⁴ long, zigzag
        // across it a few more times); its start touches the first point.
        s.push_polyline(&pts(&[(50.0, 50.0), (80.0, 61.3)]), &[]);
        assert!(!s.proven_apart());
        let got = s.contacts();
        let crossings = got.iter().filter(|c| c.proper).count();
        assert!((40..=44).contains(&crossings), "{crossings}");
        assert!(got.iter().all(|c| c.j == n));
        let by_pairs: Vec<_> = (0..n)
            .filter_map(|i| s.test_pair(i, n))
            .map(|c| (c.i, c.j))
            .collect();
        assert_eq!(got.iter().map(|c| (c.i, c.j)).collect::<Vec<_>>(), by_pairs);
    }

    /// One contour around a 10,000-gon seven times, passes 1, 3, 5 turned half a step
    /// (their chords cross the others' near every vertex): above ROUNDS_MIN, so searched
    /// in rounds. The batches in turn are the whole search's contacts, and a search stopped
    /// after its first batch says so and handed out a prefix of them.
    #[test]
    fn rounds_hand_out_the_whole_search_in_order() {
        let k = 10_000;
        let mut p = Vec::new();
        for pass in 0..7 {
            let turn = if pass % 2 == 1 { 0.5 } else { 0.0 };
            for i in 0..k {
                let t = std::f64::consts::TAU * (i as f64 + turn) / k as f64;
                p.push(DVec2::new(10.0 + 4.0 * t.cos(), 10.0 + 4.0 * t.sin()));
            }
        }
        p.push(p[0]);
        let mut s = SegmentSet::new();
        s.push_polyline(&p, &[]);
        assert!(s.segs.len() >= ROUNDS_MIN);
        let (want, capped) = s.contacts_capped();
        assert!(!capped);
        let mut got = Vec::new();
        let mut batches = 0;
        let (capped, stopped) = s.contacts_in_order(|b| {
            batches += 1;
            got.extend_from_slice(b);
            true
        });
        assert!(!capped && !stopped);
        assert!(batches >= 4, "{batches}");
        // Contacts with their lower segment in every pass but the last.
        assert!(want.iter().any(|c| c.i >= 5 * k), "{}", want.len());
        assert_eq!(got, want);
        let mut first = Vec::new();
        let (capped, stopped) = s.contacts_in_order(|b| {
            first.extend_from_slice(b);
            false
        });
        assert!(!capped && stopped);
        assert!(!first.is_empty() && first.len() < want.len());
        assert_eq!(first[..], want[..first.len()]);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(12))]
        /// Dense sets of a few thousand segments (random walks of short steps packed in a
        /// small square, several contours, steps a fraction of their spacing): the contacts
        /// are those of every pair tested exactly, and the sweep proves a set apart only
        /// when no pair meets.
        #[test]
        fn dense_sets_match_every_pair(
            seed in proptest::prelude::any::<u64>(),
            contours in 2usize..8,
            step in proptest::sample::select(vec![0.02, 0.1, 0.5]),
        ) {
            let mut state = seed | 1;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            let mut s = SegmentSet::new();
            s.across = Across::Crossings;
            for _ in 0..contours {
                let mut p = DVec2::new(10.0 * next(), 10.0 * next());
                let mut heading = std::f64::consts::TAU * next();
                let mut line = vec![p];
                for _ in 0..3000 / contours {
                    heading += 0.6 * (next() - 0.5);
                    p += step * DVec2::new(heading.cos(), heading.sin());
                    line.push((p * 1e3).round() / 1e3);
                }
                s.push_polyline(&line, &[]);
            }
            let want = naive(&s);
            let got: Vec<_> = s.contacts().iter().map(|c| (c.i, c.j)).collect();
            proptest::prop_assert_eq!(&got, &want);
            if s.proven_apart() {
                proptest::prop_assert!(want.is_empty());
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
        /// The chain sweep never declares apart a set in which some pair meets, and where
        /// nothing meets the contacts are the same either way (none).
        #[test]
        fn chains_never_miss_a_contact(
            steps in proptest::collection::vec((-2i8..=2, -2i8..=2), 1..60),
            spread in proptest::sample::select(vec![0.0, 1.0, 3.0, 50.0]),
            closed in proptest::bool::ANY,
        ) {
            let s = lattice_set(&steps, spread, closed);
            let meets = (0..s.segs.len())
                .any(|i| (i + 1..s.segs.len()).any(|j| s.test_pair(i, j).is_some()));
            if s.proven_apart() {
                proptest::prop_assert!(!meets);
            }
            if spread == 50.0 && !meets {
                proptest::prop_assert!(s.proven_apart());
            }
        }
    }
}
