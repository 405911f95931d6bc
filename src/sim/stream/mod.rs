//! The streaming route of `check`: a program of any size is checked in bounded
//! memory, with the same report as [`super::check_text`].
//!
//! - The file is read line by line ([`interp::interpret_stream`]): a pre-scan records the
//!   line count, O-word lines and seek points; the text is never held whole.
//! - Moves go to the checks as the interpreter produces them and are not stored: bounds,
//!   rapids, feed and power, gouges, statistics and the time estimate
//!   ([`crate::sim::time::Estimator`]) are running accumulators, and each check keeps at
//!   most `max_findings_per_check` findings per id, counting the rest.
//! - Cut contours are split into segments as they are cut; each segment is written to a
//!   temporary file (`.skinpath-check-PID-N` in the system's temporary folder, removed on
//!   every return; files a killed run left are removed by the next streaming check, see
//!   [`super::temp`]) with what the contact test needs of its neighbours. After the last move
//!   the contact grid of [`SegmentSet::contacts`] is laid over all segments, its cells are
//!   split into key ranges (tiles) of bounded size, each segment is copied to the tile files
//!   its cells fall in, and each tile is tested in memory cell by cell, exactly as the
//!   in-memory route tests that cell. Contacts are gathered by segment pair, so a pair seen
//!   in several tiles counts once.
//!
//! What stays in memory: the interpreter's diagnostics, events and pocket marks (one entry
//! per diagnostic, event or mark), the findings kept, the contacts found (one per
//! touching or crossing pair of segments) and one tile of segments at a time. Programs
//! with non-finite coordinates fall back to testing all pairs in memory.

use super::checks::gouge::GougeIndex;
use super::checks::intersect::{Contact, Grid, Link, MAX_CONTACTS, Seg, SegmentSet};
use super::checks::{Capped, DesignBoundary, contours, machine};
use super::config::CheckConfig;
use super::findings::Finding;
use super::interp::{self, ReadSeek};
use super::motion::{Motion, MotionKind, Program};
use super::report::{Report, Stats, StatsSum};
use super::time::Estimator;
use crate::geom::DVec2;
use crate::geom::predicates::orient2d;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::PathBuf;

#[cfg(test)]
mod tests;

/// Held by the unit tests while a streamed check runs: its temporary files carry this
/// process's id, so a test that counts them must not overlap another streamed check.
#[cfg(test)]
pub(crate) static TEST_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Inputs larger than this (bytes) take the streaming route in the CLI (`skinpath check`);
/// smaller ones are read into memory, which is faster.
pub const STREAM_ABOVE_BYTES: u64 = 64 << 20;

/// Cell entries (a segment in a cell) per tile of the contact test: about 1M entries, a
/// tile of about 150 MB at most (unless one cell holds more).
const TILE_ENTRIES: u64 = 1 << 20;

/// Histogram buckets over the grid's keys, from which the tiles are cut.
const BUCKETS: u64 = 1 << 16;

/// Bytes of one segment record in the temporary files.
const REC: usize = 104;

/// The report of `check` on the program read from `input` (see [`super::check_text_with`],
/// builtin backend), on the streaming route, and the `invalid-utf8` warning where the
/// input is not UTF-8 (the CLI puts it first in a usable report, as for
/// [`super::decode`]). An error only where the input or a temporary file cannot be read
/// or written.
pub fn check_stream<'a>(
    input: Box<dyn ReadSeek + 'a>,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &interp::Options<'_>,
) -> std::io::Result<(Report, Option<Finding>)> {
    check_stream_tiled(input, cfg, design, opts, TILE_ENTRIES)
}

/// [`check_stream`] with tiles of at most `tile_entries` cell entries each (where one cell
/// does not hold more); the report does not depend on it (for tests and tuning).
pub fn check_stream_tiled<'a>(
    input: Box<dyn ReadSeek + 'a>,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
    opts: &interp::Options<'_>,
    tile_entries: u64,
) -> std::io::Result<(Report, Option<Finding>)> {
    let mm = cfg.in_mm();
    let mut ck = Checker::new(&mm, design)?;
    ck.tile_entries = tile_entries.max(1);
    let (mut prog, scan) = interp::interpret_stream(
        input,
        &mm,
        opts,
        interp::MotionSink {
            take: &mut |moves| {
                for m in &*moves {
                    ck.motion(m);
                }
            },
            chunk: 1,
        },
    )?;
    ck.finish_contour();
    if let Some(e) = ck.error.take() {
        return Err(e);
    }
    if scan.blank {
        prog.unusable = Some(if scan.bytes == 0 {
            "the file is empty".into()
        } else {
            "the file holds only blank lines".into()
        });
    } else if scan.nul {
        prog.unusable = Some("the file holds NUL bytes: it is binary, not G-code".into());
    }
    let report = ck.report(&prog, cfg)?;
    Ok((report, scan.utf8_warning))
}

/// One segment of a cut contour, as written to the temporary files.
#[derive(Clone, Copy, Debug, Default)]
struct SegRec {
    a: DVec2,
    b: DVec2,
    link: Link,
    /// Height of its contour.
    z: f64,
    /// Source line of its move.
    line: u64,
    /// Position among all segments.
    gid: u64,
    contour: u32,
    index: u32,
    group: Option<u32>,
}

impl SegRec {
    fn encode(&self, out: &mut [u8; REC]) {
        let none = f64::NAN;
        let pa = self.link.prev_a.unwrap_or(DVec2::splat(none));
        let nb = self.link.next_b.unwrap_or(DVec2::splat(none));
        let fs = [
            self.a.x, self.a.y, self.b.x, self.b.y, pa.x, pa.y, nb.x, nb.y, self.z,
        ];
        for (i, v) in fs.iter().enumerate() {
            out[8 * i..8 * i + 8].copy_from_slice(&v.to_le_bytes());
        }
        out[72..80].copy_from_slice(&self.line.to_le_bytes());
        out[80..88].copy_from_slice(&self.gid.to_le_bytes());
        out[88..92].copy_from_slice(&self.contour.to_le_bytes());
        out[92..96].copy_from_slice(&self.index.to_le_bytes());
        out[96..100].copy_from_slice(&self.group.unwrap_or(0).to_le_bytes());
        out[100] = u8::from(self.link.prev_a.is_some())
            | u8::from(self.link.next_b.is_some()) << 1
            | u8::from(self.link.wrap) << 2
            | u8::from(self.group.is_some()) << 3;
        out[101..].fill(0);
    }

    fn decode(b: &[u8; REC]) -> SegRec {
        let f = |i: usize| {
            let mut x = [0u8; 8];
            x.copy_from_slice(&b[8 * i..8 * i + 8]);
            f64::from_le_bytes(x)
        };
        let u64_at = |i: usize| {
            let mut x = [0u8; 8];
            x.copy_from_slice(&b[i..i + 8]);
            u64::from_le_bytes(x)
        };
        let u32_at = |i: usize| {
            let mut x = [0u8; 4];
            x.copy_from_slice(&b[i..i + 4]);
            u32::from_le_bytes(x)
        };
        let flags = b[100];
        SegRec {
            a: DVec2::new(f(0), f(1)),
            b: DVec2::new(f(2), f(3)),
            link: Link {
                prev_a: (flags & 1 != 0).then(|| DVec2::new(f(4), f(5))),
                next_b: (flags & 2 != 0).then(|| DVec2::new(f(6), f(7))),
                wrap: flags & 4 != 0,
            },
            z: f(8),
            line: u64_at(72),
            gid: u64_at(80),
            contour: u32_at(88),
            index: u32_at(92),
            group: (flags & 8 != 0).then(|| u32_at(96)),
        }
    }
}

/// Prefix of the streaming check's temporary files (`.skinpath-check-PID-N`); the first
/// file a process makes removes those killed runs left ([`super::temp`]).
pub const TEMP_PREFIX: &str = ".skinpath-check-";

/// A temporary file named `.skinpath-check-PID-N`, removed when dropped.
struct TempFile {
    path: PathBuf,
}

impl TempFile {
    fn create() -> std::io::Result<(TempFile, BufWriter<std::fs::File>)> {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        if NEXT.load(Ordering::Relaxed) == 0 {
            super::temp::remove_left_behind(&std::env::temp_dir(), TEMP_PREFIX);
        }
        loop {
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let path =
                std::env::temp_dir().join(format!("{TEMP_PREFIX}{}-{n}", std::process::id()));
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(file) => {
                    return Ok((TempFile { path }, BufWriter::with_capacity(1 << 16, file)));
                }
                // Left by an earlier process with this id (killed before it could clean
                // up): take the next name.
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && n < (1 << 20) => {}
                Err(e) => return Err(e),
            }
        }
    }

    fn reader(&self) -> std::io::Result<BufReader<std::fs::File>> {
        Ok(BufReader::with_capacity(
            1 << 16,
            std::fs::File::open(&self.path)?,
        ))
    }

    /// Calls `f` with every record of the file.
    fn for_each(&self, mut f: impl FnMut(SegRec)) -> std::io::Result<()> {
        let mut r = self.reader()?;
        let mut buf = [0u8; REC];
        loop {
            match r.read_exact(&mut buf) {
                Ok(()) => f(SegRec::decode(&buf)),
                Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(()),
                Err(e) => return Err(e),
            }
        }
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// A contact with what its findings need of the two segments.
#[derive(Clone, Copy, Debug)]
struct ContactRec {
    i: u64,
    j: u64,
    point: DVec2,
    proper: bool,
    contour: [u32; 2],
    /// Positions of the segments in their contours.
    index: [u32; 2],
    line: [u64; 2],
    /// Height of the first segment's contour.
    z: f64,
}

impl ContactRec {
    fn new(c: &Contact, s: &SegRec, t: &SegRec) -> Self {
        ContactRec {
            i: s.gid,
            j: t.gid,
            point: c.point,
            proper: c.proper,
            contour: [s.contour, t.contour],
            index: [s.index, t.index],
            line: [s.line, t.line],
            z: s.z,
        }
    }
}

/// The contour being cut.
struct Cur {
    session: u32,
    group: Option<u32>,
    z: f64,
    id: u32,
    first: DVec2,
    prev: DVec2,
    count: u32,
    first_rec: Option<SegRec>,
    held: Option<SegRec>,
    /// Its path so far ([`contours::PathHasher`]).
    path: contours::PathHasher,
}

/// The checks' state between moves.
struct Checker<'d> {
    cfg: CheckConfig,
    gouge: Option<GougeIndex<'d>>,
    gouge_moves: Capped,
    gouge_starts: Capped,
    oob: Capped,
    rapids: Capped,
    feed_power: Capped,
    fp: machine::FeedPower,
    limits: machine::Limits,
    scratch: Vec<Finding>,
    stats: StatsSum,
    time: Estimator,
    cur: Option<Cur>,
    contours: u32,
    /// Path key of every contour ended so far, in order.
    paths: Vec<contours::PathKey>,
    spill: TempFile,
    out: Option<BufWriter<std::fs::File>>,
    segs: u64,
    seg_lo: DVec2,
    seg_hi: DVec2,
    seg_total: f64,
    contacts: Vec<ContactRec>,
    /// The contact search stopped at [`MAX_CONTACTS`] (in a tile, or over all tiles).
    contacts_capped: bool,
    error: Option<std::io::Error>,
    tile_entries: u64,
}

impl<'d> Checker<'d> {
    fn new(cfg: &CheckConfig, design: &'d [DesignBoundary]) -> std::io::Result<Self> {
        let cap = cfg.max_findings_per_check;
        let (spill, out) = TempFile::create()?;
        Ok(Checker {
            cfg: cfg.clone(),
            gouge: GougeIndex::new(design, cfg),
            gouge_moves: Capped::new(cap),
            gouge_starts: Capped::new(cap),
            oob: Capped::new(cap),
            rapids: Capped::new(cap),
            feed_power: Capped::new(cap),
            fp: machine::FeedPower::default(),
            limits: machine::Limits::new(cfg),
            scratch: Vec::new(),
            stats: StatsSum::new(),
            time: Estimator::new(cfg),
            cur: None,
            contours: 0,
            paths: Vec::new(),
            spill,
            out: Some(out),
            segs: 0,
            seg_lo: DVec2::splat(f64::INFINITY),
            seg_hi: DVec2::splat(f64::NEG_INFINITY),
            seg_total: 0.0,
            contacts: Vec::new(),
            contacts_capped: false,
            error: None,
            tile_entries: TILE_ENTRIES,
        })
    }

    fn motion(&mut self, m: Motion) {
        let cfg = &self.cfg;
        self.stats.motion(&m, m.bounds());
        self.time.motion(&m);
        let cutting = contours::is_cutting(&m, cfg);
        if let Some(g) = &self.gouge
            && let Some(f) = g.motion(&m, cutting)
        {
            self.gouge_moves.push(f);
        }
        self.limits.check_move(&m, cfg, &mut self.oob);
        machine::rapid_move(&m, cfg, &mut self.scratch);
        for f in self.scratch.drain(..) {
            self.rapids.push(f);
        }
        self.fp.motion(&m, cfg, &mut self.scratch);
        for f in self.scratch.drain(..) {
            self.feed_power.push(f);
        }
        self.contour_step(&m, cutting);
    }

    /// [`contours::cut_contours_marked`] and [`SegmentSet::push_polyline`], move by move.
    fn contour_step(&mut self, m: &Motion, cutting: bool) {
        if matches!(m.kind, MotionKind::Dwell { .. }) {
            return;
        }
        let planar = m.from.z == m.to.z;
        if !(cutting && planar) {
            self.finish_contour();
            return;
        }
        let group = m.group;
        if self
            .cur
            .as_ref()
            .is_some_and(|c| c.session != m.tool.session || c.group != group)
        {
            self.finish_contour();
        }
        if self.cur.is_none() {
            let p = m.from.truncate();
            if let Some(g) = &self.gouge
                && let Some(f) = g.contour_start(p, m.line, m.from.z)
            {
                self.gouge_starts.push(f);
            }
            self.cur = Some(Cur {
                session: m.tool.session,
                group,
                z: m.from.z,
                id: self.contours,
                first: p,
                prev: p,
                count: 0,
                first_rec: None,
                held: None,
                path: contours::PathHasher::default(),
            });
            self.contours += 1;
        }
        let line = m.line as u64;
        if m.arc.is_none() {
            self.point(m.to.truncate(), line);
        } else {
            for p in m.flatten_xy(self.cfg.flatten_tolerance).into_iter().skip(1) {
                self.point(p, line);
            }
        }
    }

    /// The next point of the current contour, from a move on `line`.
    fn point(&mut self, p: DVec2, line: u64) {
        let Some(c) = self.cur.as_mut() else { return };
        let q = c.prev;
        if q == p {
            return;
        }
        c.prev = p;
        c.path.segment(q, p);
        let mut rec = SegRec {
            a: q,
            b: p,
            link: Link::default(),
            z: c.z,
            line,
            gid: self.segs,
            contour: c.id,
            index: c.count,
            group: c.group,
        };
        c.count += 1;
        self.segs += 1;
        self.seg_lo = self.seg_lo.min(q).min(p);
        self.seg_hi = self.seg_hi.max(q).max(p);
        self.seg_total += q.distance(p);
        let before = if rec.index == 1 {
            c.first_rec.as_mut()
        } else {
            c.held.as_mut()
        };
        if let Some(s) = before {
            rec.link.prev_a = Some(s.a);
            s.link.next_b = Some(p);
            // Consecutive segments folding back onto each other (adjacent_overlaps).
            if orient2d(s.a, s.b, p) == 0.0 && (p - s.b).dot(s.a - s.b) > 0.0 {
                let contact = Contact {
                    i: 0,
                    j: 0,
                    point: s.b,
                    proper: false,
                };
                self.contacts.push(ContactRec::new(&contact, s, &rec));
            }
        }
        if rec.index == 0 {
            c.first_rec = Some(rec);
        } else if let Some(h) = c.held.replace(rec) {
            write_rec(&mut self.out, &mut self.error, &h);
        }
    }

    /// Ends the current contour: closes it (links of its first and last segments) and
    /// writes its held segments.
    fn finish_contour(&mut self) {
        let Some(mut c) = self.cur.take() else {
            return;
        };
        let closed = c.count >= 2 && c.first == c.prev;
        self.paths.push(c.path.key(closed, c.group));
        if closed && let (Some(f), Some(l)) = (c.first_rec.as_mut(), c.held.as_mut()) {
            f.link.prev_a = Some(l.a);
            f.link.wrap = true;
            l.link.next_b = Some(f.b);
            l.link.wrap = true;
            if orient2d(l.a, l.b, f.b) == 0.0 && (f.b - l.b).dot(l.a - l.b) > 0.0 {
                let contact = Contact {
                    i: 0,
                    j: 0,
                    point: l.b,
                    proper: false,
                };
                // The pair is (first, last) with the last segment's end as the point.
                self.contacts.push(ContactRec::new(&contact, f, l));
            }
        }
        for r in [c.first_rec, c.held].into_iter().flatten() {
            write_rec(&mut self.out, &mut self.error, &r);
        }
    }

    /// The grid contacts of all segments, tile by tile.
    fn grid_contacts(&mut self) -> std::io::Result<()> {
        if let Some(mut w) = self.out.take() {
            w.flush()?;
        }
        let n = self.segs;
        if n < 2 {
            return Ok(());
        }
        let Some(grid) = Grid::new(self.seg_lo, self.seg_hi, self.seg_total, n as usize) else {
            // Non-finite coordinates: every pair, in memory.
            let (set, recs) = load_tile(&self.spill, &self.cfg)?;
            let found = set.brute_force();
            self.contacts_capped |= found.len() >= MAX_CONTACTS;
            for c in found {
                self.contacts
                    .push(ContactRec::new(&c, &recs[c.i], &recs[c.j]));
            }
            return Ok(());
        };
        let keys = u128::from(grid.nx) * u128::from(grid.ny);
        let bucket = |k: u64| (u128::from(k) * u128::from(BUCKETS) / keys.max(1)) as usize;
        let mut hist = vec![0u64; BUCKETS as usize];
        self.spill.for_each(|r| {
            grid.cover(r.a, r.b, |k| {
                if let Some(h) = hist.get_mut(bucket(k)) {
                    *h += 1;
                }
            })
        })?;
        // Tiles: runs of buckets with at most `tile_entries` entries (at least one bucket).
        let mut starts: Vec<u64> = vec![0];
        let mut acc = 0u64;
        for (b, &h) in hist.iter().enumerate() {
            if acc > 0 && acc + h > self.tile_entries {
                // First key of bucket b: ceil(b · keys / BUCKETS).
                let k = (b as u128 * keys).div_ceil(u128::from(BUCKETS));
                starts.push(u64::try_from(k).unwrap_or(u64::MAX));
                acc = 0;
            }
            acc += h;
        }
        drop(hist);
        let end = u64::try_from(keys).unwrap_or(u64::MAX);
        if starts.len() == 1 {
            return self.tile_contacts(&self.spill.path.clone(), &grid, 0..end);
        }
        let mut files = Vec::with_capacity(starts.len());
        for _ in &starts {
            files.push(TempFile::create()?);
        }
        let mut buf = [0u8; REC];
        let mut err = None;
        let mut hit: Vec<usize> = Vec::new();
        self.spill.for_each(|r| {
            hit.clear();
            grid.cover(r.a, r.b, |k| {
                let t = starts.partition_point(|&s| s <= k).saturating_sub(1);
                if hit.last() != Some(&t) {
                    hit.push(t);
                }
            });
            hit.sort_unstable();
            hit.dedup();
            r.encode(&mut buf);
            for &t in &hit {
                if let Some((_, w)) = files.get_mut(t)
                    && let Err(e) = w.write_all(&buf)
                {
                    err.get_or_insert(e);
                }
            }
        })?;
        if let Some(e) = err {
            return Err(e);
        }
        for (t, (file, mut w)) in files.into_iter().enumerate() {
            w.flush()?;
            drop(w);
            let range = starts[t]..starts.get(t + 1).copied().unwrap_or(end);
            self.tile_contacts(&file.path, &grid, range)?;
        }
        Ok(())
    }

    /// The contacts of one tile file in the key range `keys`.
    fn tile_contacts(
        &mut self,
        path: &std::path::Path,
        grid: &Grid,
        keys: std::ops::Range<u64>,
    ) -> std::io::Result<()> {
        if self.contacts.len() >= MAX_CONTACTS {
            self.contacts_capped = true;
            return Ok(());
        }
        let tmp = TempFileRef { path };
        let (set, recs) = load_tile_at(&tmp, &self.cfg)?;
        let found = set.cell_contacts(grid, keys);
        self.contacts_capped |= found.len() >= MAX_CONTACTS;
        for c in found {
            self.contacts
                .push(ContactRec::new(&c, &recs[c.i], &recs[c.j]));
        }
        Ok(())
    }

    /// The findings of the intersection check (as
    /// [`contours::intersection_findings`]).
    fn intersection(&mut self, out: &mut Capped) -> std::io::Result<()> {
        self.grid_contacts()?;
        if self.contacts_capped {
            out.push(contours::too_many_contacts());
        }
        let mut all = std::mem::take(&mut self.contacts);
        all.sort_by_key(|c| (c.i, c.j));
        all.dedup_by(|p, q| p.i == q.i && p.j == q.j);
        let passes = contours::pass_numbers(&self.paths);
        let mut folder = contours::ContactFolder::new(&passes, &self.cfg);
        for c in all {
            let side = |k: usize| contours::Side {
                contour: c.contour[k],
                index: c.index[k],
                line: c.line[k] as usize,
            };
            folder.contact(side(0), side(1), c.proper, [c.point.x, c.point.y, c.z]);
        }
        folder.finish(out);
        Ok(())
    }

    /// The report (as [`super::check`]); `cfg` as given (maybe in inch).
    fn report(mut self, prog: &Program, cfg: &CheckConfig) -> std::io::Result<Report> {
        if prog.unusable.is_some() {
            return Ok(super::assemble(prog, cfg, Vec::new(), Stats::default()));
        }
        let mut inter = Capped::new(self.cfg.max_findings_per_check);
        self.intersection(&mut inter)?;
        let mut end = Capped::new(self.cfg.max_findings_per_check);
        for f in machine::program_end(prog, &self.cfg) {
            end.push(f);
        }
        let stages = [
            inter,
            std::mem::replace(&mut self.gouge_moves, Capped::new(1)),
            std::mem::replace(&mut self.gouge_starts, Capped::new(1)),
            std::mem::replace(&mut self.oob, Capped::new(1)),
            std::mem::replace(&mut self.rapids, Capped::new(1)),
            std::mem::replace(&mut self.feed_power, Capped::new(1)),
            end,
        ];
        let mut all = prog.diagnostics.clone();
        let mut dropped: Vec<(&'static str, usize)> = prog.diagnostics_dropped.clone();
        for st in stages {
            dropped.extend(st.dropped());
            all.extend(st.kept);
        }
        let stats = self.stats.finish(self.time.finish());
        Ok(super::assemble_with(prog, cfg, all, stats, &dropped))
    }
}

fn write_rec(
    out: &mut Option<BufWriter<std::fs::File>>,
    error: &mut Option<std::io::Error>,
    r: &SegRec,
) {
    let mut buf = [0u8; REC];
    r.encode(&mut buf);
    if let Some(w) = out
        && let Err(e) = w.write_all(&buf)
        && error.is_none()
    {
        *error = Some(e);
    }
}

/// A file of segment records not owned here.
struct TempFileRef<'p> {
    path: &'p std::path::Path,
}

fn load_tile(f: &TempFile, cfg: &CheckConfig) -> std::io::Result<(SegmentSet, Vec<SegRec>)> {
    load_tile_at(&TempFileRef { path: &f.path }, cfg)
}

/// The records of a file in segment order, and the tile set of them.
fn load_tile_at(
    f: &TempFileRef<'_>,
    cfg: &CheckConfig,
) -> std::io::Result<(SegmentSet, Vec<SegRec>)> {
    let file = std::fs::File::open(f.path)?;
    let n = file.metadata().map_or(0, |m| m.len()) as usize / REC;
    let mut r = BufReader::with_capacity(1 << 16, file);
    let mut recs = Vec::with_capacity(n);
    let mut buf = [0u8; REC];
    loop {
        match r.read_exact(&mut buf) {
            Ok(()) => recs.push(SegRec::decode(&buf)),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
            Err(e) => return Err(e),
        }
    }
    recs.sort_by_key(|r| r.gid);
    let segs = recs
        .iter()
        .map(|r| Seg {
            a: r.a,
            b: r.b,
            contour: r.contour,
            index: r.index,
        })
        .collect();
    let links = recs.iter().map(|r| r.link).collect();
    let pockets = recs.iter().map(|r| r.group).collect();
    let set = SegmentSet::tile(
        segs,
        links,
        pockets,
        contours::across(cfg),
        contours::tangent_slack(cfg),
    );
    Ok((set, recs))
}
