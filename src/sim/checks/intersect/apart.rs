//! Proofs that no two segments touch without listing pairs: exact copies grouped, and
//! chains of consecutive segments swept in blocks.

use super::*;

/// Steps per segment [`SegmentSet::proven_apart`] may take before it leaves the decision to
/// the grid.
pub(super) const CHAIN_BUDGET: usize = 16;

/// Steps per segment of the first try of the sweep over chains in
/// [`SegmentSet::proven_apart`] (and 4096 more): enough for sets whose chains each overlap
/// a few others (the benches' circles, rounded to 3 decimals, need between 1/2 and 1),
/// a sixteenth of the full budget lost where chains overlap by the hundred (a spiral)
/// before the block grid decides.
pub(super) const SWEEP_TRIAL: usize = 1;

/// A run of segments `start..end` whose x strictly increases (or decreases when `rev`),
/// with its bounding box (see [`SegmentSet::proven_apart`]).
pub(super) struct Chain {
    pub(super) start: u32,
    pub(super) end: u32,
    pub(super) rev: bool,
    pub(super) lo: DVec2,
    pub(super) hi: DVec2,
    /// Its contour's number: segment k of the chain starts at `points[k + shift]`
    /// (see [`SegmentSet`]).
    pub(super) shift: u32,
    /// Index of its first block in the y ranges of [`SegmentSet::proven_apart`].
    pub(super) block: u32,
}

impl Chain {
    /// Number of its blocks of [`CHAIN_BLOCK`] segments (the last may be shorter).
    pub(super) fn blocks(&self) -> usize {
        ((self.end - self.start) as usize).div_ceil(CHAIN_BLOCK)
    }
}

/// How many times over the chains' boxes may cover the set's box before
/// [`SegmentSet::proven_apart`] skips the short try of its sweep: disjoint contours cover
/// it less than once (the benches' circles 0.8 times), the spiral's nested half turns
/// about a hundred times.
pub(super) const NESTED_COVER: f64 = 8.0;

/// Most grid cells per (cell, block) entry for which [`SegmentSet::blocks_apart_on_grid`]
/// sorts its entries by counting (one count per cell): a dense set (the spiral's blocks
/// take about 3 entries per cell) is sorted in two passes over 4-byte entries; a sparse
/// one (few blocks spread over a large box) by the radix sort, whose memory does not grow
/// with the cells.
pub(super) const DENSE_KEYS_PER_ENTRY: u64 = 4;

/// Segments per block of a chain in [`SegmentSet::chains_apart`].
pub(super) const CHAIN_BLOCK: usize = 8;

impl SegmentSet {
    /// Block `i` of chain `c` in storage order: its segment range and its box, whose x
    /// range the block's end points bound (the chain is x-monotone) and whose y range is
    /// the block's entry in `ys` (the y ranges of [`SegmentSet::proven_apart`]). None
    /// where `ys` has no such entry.
    fn chain_block(
        &self,
        c: &Chain,
        i: usize,
        ys: &[(f64, f64)],
    ) -> Option<(std::ops::Range<usize>, DVec2, DVec2)> {
        let s0 = c.start as usize + i * CHAIN_BLOCK;
        let s1 = (s0 + CHAIN_BLOCK).min(c.end as usize);
        let sh = c.shift as usize;
        let (x0, x1) = (self.points.get(s0 + sh)?.x, self.points.get(s1 + sh)?.x);
        let &(y0, y1) = ys.get(c.block as usize + i)?;
        Some((
            s0..s1,
            DVec2::new(x0.min(x1), y0),
            DVec2::new(x0.max(x1), y1),
        ))
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
    pub(super) fn proven_apart_with_copies(&self) -> bool {
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
    pub(super) fn without_copies(&self) -> Option<SegmentSet> {
        let mut starts = Vec::with_capacity(self.contours.len());
        let mut at = 0usize;
        for &(n, _) in &self.contours {
            starts.push(at);
            at += n as usize;
        }
        if at != self.len() || !self.ids.is_empty() {
            return None;
        }
        let span = |c: usize| starts[c]..starts[c] + self.contours[c].0 as usize;
        // Segment k of contour c, as bits.
        let bits = |c: usize, k: usize| {
            let p = self.pockets.get(c).copied().flatten();
            let p = p.map_or(0, |p| u64::from(p) + 1);
            let (a, b) = self.ends(k);
            let [ax, ay, bx, by] = [a.x, a.y, b.x, b.y].map(f64::to_bits);
            [ax, ay, bx, by, p]
        };
        let hash = |c: usize| {
            // FNV-1a over the coordinates' bits.
            let mut h: u64 = 0xcbf2_9ce4_8422_2325;
            for k in span(c) {
                for w in bits(c, k) {
                    h = (h ^ w).wrapping_mul(0x0000_0100_0000_01b3);
                }
            }
            h
        };
        let same = |c: usize, d: usize| span(c).zip(span(d)).all(|(s, t)| bits(c, s) == bits(d, t));
        // Contours are grouped by size, closedness and first segment; only the few groups
        // of two or more (the passes of one cut, mostly) are hashed whole and compared.
        let head = |c: usize| {
            let first = span(c).next().map(|k| bits(c, k));
            (self.contours[c], first)
        };
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
        for c in (0..self.contours.len()).filter(|&c| !copy[c]) {
            // The contour's first point (its only one when it has no segment).
            let first = self.points[starts[c] + c];
            let mut open = out.begin_polyline(first, self.pockets.get(c).copied().flatten());
            for k in span(c) {
                out.polyline_to(&mut open, self.ends(k).1, self.source(k));
            }
            // Same points, so the same count and closedness as contour c.
            out.end_polyline(open);
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
    pub(super) fn proven_apart(&self) -> bool {
        if self.links.is_some() {
            return false;
        }
        let n = self.len();
        let dir = |(a, b): (DVec2, DVec2)| (b.x - a.x).partial_cmp(&0.0);
        let mut chains: Vec<Chain> = Vec::new();
        let mut blocks: Vec<(f64, f64)> = Vec::with_capacity(n / CHAIN_BLOCK + 1);
        // Contour by contour (chains never span two): contour c's points are n + 1 from
        // points[f + c], f its first segment (see [`SegmentSet`]).
        let mut f = 0usize;
        for (c, &(count, _)) in self.contours.iter().enumerate() {
            let count = count as usize;
            let Some(p) = self.points.get(f + c..f + c + count + 1) else {
                return false;
            };
            let seg = |t: usize| (p[t], p[t + 1]);
            let mut k = 0;
            while k < count {
                let s = seg(k);
                if !(s.0.is_finite() && s.1.is_finite()) {
                    return false;
                }
                let d = dir(s);
                let mut e = k + 1;
                if d != Some(std::cmp::Ordering::Equal) {
                    while e < count && dir(seg(e)) == d {
                        e += 1;
                    }
                }
                if p[k + 2..e + 1].iter().any(|q| !q.is_finite()) {
                    return false;
                }
                let block = blocks.len() as u32;
                for r0 in (k..e).step_by(CHAIN_BLOCK) {
                    let (lo, hi) = (r0..(r0 + CHAIN_BLOCK).min(e))
                        .map(seg)
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
                            (lo.min(a.y).min(b.y), hi.max(a.y).max(b.y))
                        });
                    blocks.push((lo, hi));
                }
                // The chain's box: its end points bound its x range, its blocks its y
                // range.
                let (x0, x1) = (s.0.x, p[e].x);
                let (y0, y1) = blocks[block as usize..]
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
                        (lo.min(y.0), hi.max(y.1))
                    });
                chains.push(Chain {
                    start: (f + k) as u32,
                    end: (f + e) as u32,
                    rev: d == Some(std::cmp::Ordering::Less),
                    lo: DVec2::new(x0.min(x1), y0),
                    hi: DVec2::new(x0.max(x1), y1),
                    shift: c as u32,
                    block,
                });
                k = e;
            }
            f += count;
        }
        if f != n {
            return false;
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
    pub(super) fn chains_sweep(
        &self,
        chains: &[Chain],
        blocks: &[(f64, f64)],
        budget: usize,
    ) -> Option<bool> {
        let mut scan = CHAIN_BUDGET.saturating_mul(self.len()).saturating_add(4096);
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
    pub(super) fn blocks_apart_on_grid(
        &self,
        chains: &[Chain],
        ys: &[(f64, f64)],
        spend: &mut impl FnMut(usize) -> bool,
    ) -> Option<bool> {
        // Blocks: (box lo, box hi, chain, block number within the chain).
        let mut boxes: Vec<(DVec2, DVec2, u32, u32)> = Vec::with_capacity(ys.len());
        for (c, ch) in chains.iter().enumerate() {
            for i in 0..ch.blocks() {
                let (_, lo, hi) = self.chain_block(ch, i, ys)?;
                boxes.push((lo, hi, c as u32, i as u32));
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
        // The blocks of one cell, in increasing block number: pairs of two chains whose
        // boxes overlap, examined here when the low corner of their intersection is in it.
        let mut cell_apart = |key: u64, ids: &[u32]| {
            for (x, &i) in ids.iter().enumerate() {
                let p = &boxes[i as usize];
                for &y in &ids[x + 1..] {
                    let q = &boxes[y as usize];
                    if p.2 == q.2 || p.0.cmpgt(q.1).any() || q.0.cmpgt(p.1).any() {
                        continue;
                    }
                    let (c, r) = cell(p.0.max(q.0));
                    if c * ny + r != key {
                        continue;
                    }
                    let (a, b) = (&chains[p.2 as usize], &chains[q.2 as usize]);
                    if !spend(1) || !self.blocks_apart(a, p.3, b, q.3, spend) {
                        return false;
                    }
                }
            }
            true
        };
        // Each box's cells, block by block: keys in storage order per block.
        let for_each_entry = |f: &mut dyn FnMut(u64, u32)| {
            for (k, b) in boxes.iter().enumerate() {
                let ((c0, r0), (c1, r1)) = (cell(b.0), cell(b.1));
                for c in c0..=c1 {
                    for r in r0..=r1 {
                        f(c * ny + r, k as u32);
                    }
                }
            }
        };
        if max_key <= DENSE_KEYS_PER_ENTRY.saturating_mul(covers) {
            // Counting sort by cell (stable, so each cell's blocks stay in increasing
            // number, the order the radix sort below gives): 4 bytes an entry and one
            // count per cell, instead of 8 bytes an entry twice over.
            let mut end = vec![0u32; max_key as usize + 1];
            // Keys are below max_key by its definition; one that is not leaves the
            // decision to the sweep rather than be lost.
            let mut inside = true;
            for_each_entry(&mut |key, _| match end.get_mut(key as usize + 1) {
                Some(n) => *n += 1,
                None => inside = false,
            });
            if !inside {
                return None;
            }
            for k in 1..end.len() {
                end[k] += end[k - 1];
            }
            let mut ids = vec![0u32; covers as usize];
            for_each_entry(&mut |key, k| {
                let at = &mut end[key as usize];
                ids[*at as usize] = k;
                *at += 1;
            });
            // Now end[key] is where cell key's blocks end (and cell key + 1's begin).
            let mut begin = 0usize;
            for (key, &e) in end.iter().enumerate() {
                let e = e as usize;
                if e - begin >= 2 && !cell_apart(key as u64, &ids[begin..e]) {
                    return Some(false);
                }
                begin = e;
            }
            return Some(true);
        }
        let mut entries: Vec<u64> = Vec::with_capacity(covers as usize);
        for_each_entry(&mut |key, k| entries.push((key << 32) | u64::from(k)));
        radix_sort_high(&mut entries, 64 - max_key.leading_zeros());
        let mut ids: Vec<u32> = Vec::new();
        let mut g = 0;
        while g < entries.len() {
            let key = entries[g] >> 32;
            let mut e = g + 1;
            while e < entries.len() && entries[e] >> 32 == key {
                e += 1;
            }
            ids.clear();
            ids.extend(entries[g..e].iter().map(|&x| x as u32));
            if !cell_apart(key, &ids) {
                return Some(false);
            }
            g = e;
        }
        Some(true)
    }

    /// True when no segment of block `i` of chain `a` meets one of block `j` of chain `b`
    /// (blocks of [`CHAIN_BLOCK`] segments in storage order); false when a pair meets or the
    /// budget runs out. The segments of each block are taken in x order; each is tested
    /// against the run of the other's whose x ranges (closed) overlap its own.
    pub(super) fn blocks_apart(
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
        // A segment's index and box.
        let boxed = |k: usize| {
            let (a, b) = self.ends(k);
            (k, a.min(b), a.max(b))
        };
        let mut held = [(0usize, DVec2::ZERO, DVec2::ZERO); CHAIN_BLOCK];
        let mut count = 0;
        for q in run(b, j) {
            held[count] = boxed(q);
            count += 1;
        }
        let others = &held[..count];
        let mut first = 0;
        for (p, plo, phi) in run(a, i).map(boxed) {
            while first < others.len() && others[first].2.x < plo.x {
                first += 1;
            }
            for &(q, qlo, qhi) in &others[first..] {
                if qlo.x > phi.x {
                    break;
                }
                // Boxes apart: `test_pair` would say so first.
                let near = plo.cmple(qhi).all() && qlo.cmple(phi).all();
                if !spend(1) || near && self.test_pair(p, q).is_some() {
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
    pub(super) fn chains_apart(
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
        // Block i of chain c in x order (None only for block y ranges that do not match
        // the chains: then the chains are not proven apart).
        let in_x_order = |c: &Chain, i: usize| {
            let k = if c.rev { c.blocks() - 1 - i } else { i };
            self.chain_block(c, k, ys)
        };
        let nl = long.blocks();
        for i in 0..short.blocks() {
            let Some((run, lo, hi)) = self.chain_block(short, i, ys) else {
                return false;
            };
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
                let Some((_, _, mid_hi)) = in_x_order(long, mid) else {
                    return false;
                };
                if mid_hi.x < lo.x {
                    j = mid + 1;
                } else {
                    top = mid;
                }
            }
            while j < nl {
                let Some((other, olo, ohi)) = in_x_order(long, j) else {
                    return false;
                };
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
}
