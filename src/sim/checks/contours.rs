//! Cut contours: maximal runs of cutting moves at one depth, flattened for the geometric
//! checks, and the self-intersection and crossing checks on them.
//!
//! A [`SimContour`] is rebuilt from the simulated moves of a program; not to be confused with
//! [`CutContour`](crate::emit::CutContour) (a run of cutting segments the writers emit from a
//! toolpath) or [`OutlineContour`](crate::emit::outline::OutlineContour) (a flattened contour
//! of the outline document).

use super::Capped;
use super::intersect::{Across, MAX_CONTACTS, OpenPolyline, SegmentSet};
use crate::geom::DVec2;
use crate::sim::config::{CheckConfig, Dialect, MachineKind};
use crate::sim::findings::{Finding, Severity};
use crate::sim::motion::{Motion, MotionKind, Motions};

/// True when the move removes material: a laser feed with the beam on (M3/M4, S > 0; on
/// Smoothieware, whose laser module fires on every G1/G2/G3 with its S power and never on G0,
/// any feed with S > 0), or a router feed with an end below `cut_z`.
pub fn is_cutting(m: &Motion, cfg: &CheckConfig) -> bool {
    if m.kind != MotionKind::Feed {
        return false;
    }
    match cfg.kind {
        MachineKind::Laser if cfg.dialect == Dialect::Smoothie => m.tool.s > 0.0,
        MachineKind::Laser => m.tool.is_on(),
        MachineKind::Router => m.from.z.min(m.to.z) < cfg.cut_z,
    }
}

/// A cut contour: consecutive cutting moves in the xy plane at constant z in one tool session
/// (switching the tool off and on starts a new contour). Moves that change
/// z (plunges, ramps, helices) and dwells end a contour without joining one, so the passes
/// of a multi-depth cut are separate contours.
#[derive(Clone, Debug, PartialEq)]
pub struct SimContour {
    /// Flattened xy points (sagitta ≤ the flatten tolerance).
    pub points: Vec<DVec2>,
    /// Motion index of the segment ending at `points[k + 1]`.
    pub sources: Vec<u32>,
    /// Height (z, mm) the contour is cut at.
    pub z: f64,
    /// Tool session ([`crate::sim::ToolState::session`]) the contour was cut in.
    pub session: u32,
    /// Pocket mark in force where the contour was cut ([`note_group_marks`]).
    pub group: Option<u32>,
}

/// Records the pocket marks among a line's comments: `skinpath:group N` (N a number) starts
/// pocket N, `skinpath:group none` ends it (the text skinpath's emitter writes, see
/// `emit::gcode::GROUP_MARK`). Other comments are ignored. Called by the interpreter for
/// every line, words or not.
pub fn note_group_marks(comments: &[String], line: usize, marks: &mut Vec<(usize, Option<u32>)>) {
    for c in comments {
        let Some(rest) = c.trim().strip_prefix("skinpath:group") else {
            continue;
        };
        let rest = rest.trim();
        if rest == "none" {
            marks.push((line, None));
        } else if let Ok(n) = rest.parse::<u32>() {
            marks.push((line, Some(n)));
        }
    }
}

/// The cut contours of a program, arcs flattened to `cfg.flatten_tolerance` (mm).
pub fn cut_contours(motions: &Motions, cfg: &CheckConfig) -> Vec<SimContour> {
    let mut out = Vec::new();
    for_each_cut_contour(motions, false, cfg, |c| out.push(c.clone()));
    out
}

/// [`cut_contours`] with the pocket marks the moves were cut under ([`Motion::group`]): a
/// contour also ends where the mark changes, and carries the mark it was cut under.
#[cfg(test)]
pub fn cut_contours_marked(motions: &Motions, cfg: &CheckConfig) -> Vec<SimContour> {
    let mut out = Vec::new();
    for_each_cut_contour(motions, true, cfg, |c| out.push(c.clone()));
    out
}

/// Most segments the contour checks take from one program (arcs flattened): 2²³ segments
/// hold about 200 MB in the checks' segment set (24 bytes a segment), eight times the
/// densest programs the benches check (10⁶ segments), while arcs of a million turns or
/// thousands of circles of kilometre radius would flatten to hundreds of millions. Past it
/// the checks stop with a [`check_limit`] finding.
pub const MAX_CONTOUR_SEGMENTS: usize = 1 << 23;

/// Calls `f` with each contour of [`cut_contours`] (of `cut_contours_marked` when
/// `marked`) in order, built in one buffer
/// reused from contour to contour: a caller that does not keep the contours whole (the
/// checks keep their segments) needs no memory for all of them at once. Stops before the
/// move whose flattened segments would take the contours past [`MAX_CONTOUR_SEGMENTS`]
/// and returns its index (None when every move was taken).
pub fn for_each_cut_contour(
    motions: &Motions,
    marked: bool,
    cfg: &CheckConfig,
    mut f: impl FnMut(&SimContour),
) -> Option<usize> {
    let mut cur = SimContour {
        points: Vec::new(),
        sources: Vec::new(),
        z: 0.0,
        session: 0,
        group: None,
    };
    for_each_cut_point(motions, marked, cfg, |e| match e {
        CutPoint::Start {
            point,
            z,
            session,
            group,
        } => {
            cur.points.push(point);
            (cur.z, cur.session, cur.group) = (z, session, group);
        }
        CutPoint::Next { point, source, .. } => {
            cur.points.push(point);
            cur.sources.push(source);
        }
        CutPoint::End => {
            f(&cur);
            cur.points.clear();
            cur.sources.clear();
        }
    })
}

/// The points of the contours of [`for_each_cut_contour`], in order, as
/// [`for_each_cut_point`] hands them out.
enum CutPoint {
    /// A contour starts at `point`, cut at height `z` in tool session `session` under
    /// pocket mark `group`.
    Start {
        point: DVec2,
        z: f64,
        session: u32,
        group: Option<u32>,
    },
    /// The contour's next point, the end of a segment of motion `source`, on program
    /// line `line`.
    Next {
        point: DVec2,
        source: u32,
        line: usize,
    },
    /// The contour ends.
    End,
}

/// [`for_each_cut_contour`] point by point: no buffer holds a contour (a spiral of a
/// million moves is one contour). Same stop and return value.
fn for_each_cut_point(
    motions: &Motions,
    marked: bool,
    cfg: &CheckConfig,
    mut f: impl FnMut(CutPoint),
) -> Option<usize> {
    let mut cut = CutPoints::new(marked);
    for m in motions {
        cut.motion(&m, cfg, &mut f);
        if cut.stopped.is_some() {
            break;
        }
    }
    cut.close(&mut f);
    cut.stopped.map(|(k, _)| k)
}

/// [`for_each_cut_point`] move by move: what it keeps between two moves.
#[derive(Clone, Copy, Debug)]
struct CutPoints {
    /// Whether contours carry the pocket marks of their moves (else none).
    marked: bool,
    /// The open contour's tool session and pocket mark, while one is open.
    open: Option<(u32, Option<u32>)>,
    /// Segments handed out so far (one per line, the chords of arcs).
    total: usize,
    /// Index of the next move (the moves taken so far).
    next: usize,
    /// Index and line of the move that would have taken the contours past
    /// [`MAX_CONTOUR_SEGMENTS`]: no point is handed out from it on.
    stopped: Option<(usize, usize)>,
}

impl CutPoints {
    /// Nothing handed out yet.
    fn new(marked: bool) -> Self {
        CutPoints {
            marked,
            open: None,
            total: 0,
            next: 0,
            stopped: None,
        }
    }

    /// Hands `f` the points the next move, `m`, adds to the contours.
    fn motion(&mut self, m: &Motion, cfg: &CheckConfig, f: &mut impl FnMut(CutPoint)) {
        let k = self.next;
        self.next += 1;
        if self.stopped.is_some() || matches!(m.kind, MotionKind::Dwell { .. }) {
            return;
        }
        let planar = m.from.z == m.to.z;
        if !(is_cutting(m, cfg) && planar) {
            self.close(f);
            return;
        }
        let group = if self.marked { m.group } else { None };
        if self.open.is_some_and(|o| o != (m.tool.session, group)) {
            self.close(f);
        }
        if self.open.is_none() {
            self.open = Some((m.tool.session, group));
            f(CutPoint::Start {
                point: m.from.truncate(),
                z: m.from.z,
                session: m.tool.session,
                group,
            });
        }
        let chords = m
            .arc
            .map_or(1, |a| a.chords_for_tolerance(cfg.flatten_tolerance));
        self.total += chords;
        if self.total > MAX_CONTOUR_SEGMENTS {
            self.close(f);
            self.stopped = Some((k, m.line));
            return;
        }
        let (source, line) = (k as u32, m.line);
        if m.arc.is_none() {
            // A line flattens to its two ends: no point list to build.
            f(CutPoint::Next {
                point: m.to.truncate(),
                source,
                line,
            });
        } else {
            for p in m.flatten_xy(cfg.flatten_tolerance).into_iter().skip(1) {
                f(CutPoint::Next {
                    point: p,
                    source,
                    line,
                });
            }
        }
    }

    /// Ends the open contour, if any.
    fn close(&mut self, f: &mut impl FnMut(CutPoint)) {
        if self.open.take().is_some() {
            f(CutPoint::End);
        }
    }
}

/// The finding of contour checks stopped at [`MAX_CONTOUR_SEGMENTS`], on `line`: the
/// intersection and gouge checks saw only the moves before it.
pub fn check_limit(line: usize) -> Finding {
    Finding::new(
        "check-limit",
        Severity::Error,
        format!(
            "the cut contours flatten to more than {MAX_CONTOUR_SEGMENTS} segments: the \
             intersection and gouge checks stopped at this line and did not check the rest"
        ),
    )
    .line(line)
}

/// Where a cut contour starts and the height it is cut at: what the gouge check reads of
/// it ([`super::gouge::GougeIndex::contour_starts`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourStart {
    /// First point.
    pub point: DVec2,
    /// Program line of its first segment (None for a contour of one point).
    pub line: Option<usize>,
    /// Height (z, mm).
    pub z: f64,
}

/// The segments of the cut contours ([`cut_contours_marked`]) for the intersection check
/// ([`intersection_findings`]), each tagged with its program line (saturated at
/// `u32::MAX`), and each contour's start, in one pass that does not keep the contours'
/// point lists (a second copy of every point, 20 bytes a segment). Also the
/// [`check_limit`] finding when the contours were cut short at [`MAX_CONTOUR_SEGMENTS`].
/// The checks gather them move by move ([`SegmentGather`]); the tests from stored moves.
#[cfg(test)]
pub fn contour_segments(
    motions: &Motions,
    cfg: &CheckConfig,
) -> (SegmentSet, Vec<ContourStart>, Option<Finding>) {
    let mut gather = SegmentGather::new(cfg);
    gather.reserve(motions.len().min(MAX_CONTOUR_SEGMENTS));
    for m in motions {
        gather.motion(&m, cfg);
        if gather.cut.stopped.is_some() {
            break;
        }
    }
    gather.finish()
}

/// [`contour_segments`] move by move, for callers that do not store the moves.
#[derive(Clone, Debug)]
pub(crate) struct SegmentGather {
    set: SegmentSet,
    starts: Vec<ContourStart>,
    open: Option<OpenPolyline>,
    cut: CutPoints,
}

impl SegmentGather {
    /// Nothing gathered yet.
    pub(crate) fn new(cfg: &CheckConfig) -> Self {
        SegmentGather {
            set: new_set(cfg),
            starts: Vec::new(),
            open: None,
            cut: CutPoints::new(true),
        }
    }

    /// Reserves room for `n` more segments (straight moves give at most one each).
    pub(crate) fn reserve(&mut self, n: usize) {
        self.set.reserve(n);
    }

    /// Adds the segments of the next move, `m`, under the pocket mark it was cut under;
    /// none once the contours were cut short.
    pub(crate) fn motion(&mut self, m: &Motion, cfg: &CheckConfig) {
        let (set, starts, open) = (&mut self.set, &mut self.starts, &mut self.open);
        self.cut
            .motion(m, cfg, &mut |e| gather_point(set, starts, open, e));
    }

    /// The segment set, the contour starts and the [`check_limit`] finding (see
    /// [`contour_segments`]).
    pub(crate) fn finish(mut self) -> (SegmentSet, Vec<ContourStart>, Option<Finding>) {
        let (set, starts, open) = (&mut self.set, &mut self.starts, &mut self.open);
        self.cut.close(&mut |e| gather_point(set, starts, open, e));
        let limit = self.cut.stopped.map(|(_, line)| check_limit(line));
        (self.set, self.starts, limit)
    }
}

/// Adds cut point `e` to `set` and `starts`, `open` the contour being added.
fn gather_point(
    set: &mut SegmentSet,
    starts: &mut Vec<ContourStart>,
    open: &mut Option<OpenPolyline>,
    e: CutPoint,
) {
    match e {
        CutPoint::Start {
            point, z, group, ..
        } => {
            *open = Some(set.begin_polyline(point, group));
            starts.push(ContourStart {
                point,
                line: None,
                z,
            });
        }
        CutPoint::Next { point, line, .. } => {
            if let Some(s) = starts.last_mut() {
                s.line.get_or_insert(line);
            }
            if let Some(o) = open.as_mut() {
                set.polyline_to(o, point, u32::try_from(line).unwrap_or(u32::MAX));
            }
        }
        CutPoint::End => {
            if let Some(o) = open.take() {
                set.end_polyline(o);
            }
        }
    }
}

/// The empty segment set of the intersection check under `cfg`.
fn new_set(cfg: &CheckConfig) -> SegmentSet {
    let mut set = SegmentSet::new();
    set.across = across(cfg);
    set.tangent_slack = tangent_slack(cfg);
    set
}

/// What tells one contour's path from another's, for numbering the passes of a path cut
/// several times ([`pass_numbers`]): segment count, closedness, pocket mark, and the 128-bit
/// FNV-1a hash (Fowler–Noll–Vo, offset basis and prime of the 128-bit variant) of the bits
/// of every segment's end points, in order. Two contours with equal keys repeat one path
/// bit for bit unless the hash collides (about 2⁻¹²⁸ a pair).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PathKey {
    count: u32,
    closed: bool,
    pocket: Option<u32>,
    hash: u128,
}

/// Builds a [`PathKey`] segment by segment (both routes of the check feed it the same
/// segments: those [`SegmentSet::push_polyline_in`] keeps).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathHasher {
    count: u32,
    hash: u128,
}

/// FNV-1a 128-bit offset basis.
const FNV128_BASIS: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
/// FNV-1a 128-bit prime, 2⁸⁸ + 2⁸ + 0x3b.
const FNV128_PRIME: u128 = (1 << 88) + (1 << 8) + 0x3b;

impl Default for PathHasher {
    fn default() -> Self {
        PathHasher {
            count: 0,
            hash: FNV128_BASIS,
        }
    }
}

impl PathHasher {
    /// Adds the segment `a`–`b`.
    pub fn segment(&mut self, a: DVec2, b: DVec2) {
        self.count += 1;
        for w in [a.x, a.y, b.x, b.y] {
            self.hash = (self.hash ^ u128::from(w.to_bits())).wrapping_mul(FNV128_PRIME);
        }
    }

    /// The key of the contour fed so far.
    pub fn key(&self, closed: bool, pocket: Option<u32>) -> PathKey {
        PathKey {
            count: self.count,
            closed,
            pocket,
            hash: self.hash,
        }
    }
}

/// Per contour (keys in contour order): the first contour with the same path key and the
/// pass number of this one among the contours of that path (1 for the first).
pub(crate) fn pass_numbers(keys: &[PathKey]) -> Vec<(u32, u32)> {
    let mut seen: std::collections::HashMap<PathKey, (u32, u32)> =
        std::collections::HashMap::with_capacity(keys.len());
    keys.iter()
        .enumerate()
        .map(|(c, k)| {
            let e = seen.entry(*k).or_insert((c as u32, 0));
            e.1 += 1;
            *e
        })
        .collect()
}

/// A multiplicative hasher for the small integer keys of [`ContactFolder`] (SipHash, the
/// standard one, is slow for keys hashed once per contact): each word is mixed in by
/// h = (rotl(h, 5) ⊕ w) · K with K = ⌊2⁶⁴/φ⌋ (Fibonacci hashing, Knuth TAOCP vol. 3
/// §6.4), as rustc's FxHasher does. Keys come from the program, not from an adversary
/// who would gain anything by colliding them.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct WordHasher(u64);

/// ⌊2⁶⁴/φ⌋, the multiplier of [`WordHasher`].
const FIBONACCI_K: u64 = 0x9e37_79b9_7f4a_7c15;

impl std::hash::Hasher for WordHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, w: u64) {
        self.0 = (self.0.rotate_left(5) ^ w).wrapping_mul(FIBONACCI_K);
    }
    fn write_u32(&mut self, w: u32) {
        self.write_u64(u64::from(w));
    }
    fn write_usize(&mut self, w: usize) {
        self.write_u64(w as u64);
    }
    fn write_u8(&mut self, w: u8) {
        self.write_u64(u64::from(w));
    }
}

/// Hash maps keyed by small integers ([`WordHasher`]).
type WordMap<K, V> = std::collections::HashMap<K, V, std::hash::BuildHasherDefault<WordHasher>>;

/// One side of a contact as the crossing findings read it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Side {
    /// Contour number.
    pub contour: u32,
    /// Position of the segment in its contour.
    pub index: u32,
    /// Source line of the segment's move.
    pub line: usize,
}

/// A finding of [`ContactFolder`] before it is built: the first contact of its crossing,
/// and the pass numbers of each side's path met there.
#[derive(Clone, Debug)]
struct Folded {
    contours: [u32; 2],
    proper: bool,
    lines: [usize; 2],
    at: [f64; 3],
    passes: [std::collections::BTreeSet<u32>; 2],
}

/// Turns the contacts of the intersection check (taken in segment-pair order) into its
/// findings, on both routes: one per pair of source lines as before, and one per crossing
/// of two paths whatever the number of passes each is cut in: a contact whose
/// segments repeat, at the same positions of the same paths ([`pass_numbers`]), those of
/// an earlier contact joins that contact's finding, which lists the passes.
pub(crate) struct ContactFolder<'p> {
    passes: &'p [(u32, u32)],
    allow_crossings: bool,
    /// Per path (first contour): cut more than once.
    repeated: Vec<bool>,
    by_lines: WordMap<(bool, usize, usize), usize>,
    by_path: WordMap<[(u32, u32); 2], usize>,
    found: Vec<Folded>,
    /// Findings in `found` of contours touching themselves, of two contours crossing.
    counts: [usize; 2],
}

impl<'p> ContactFolder<'p> {
    /// A folder for contours numbered by `passes` ([`pass_numbers`]).
    pub fn new(passes: &'p [(u32, u32)], cfg: &CheckConfig) -> Self {
        let mut repeated = vec![false; passes.len()];
        for &(first, pass) in passes {
            if pass > 1
                && let Some(r) = repeated.get_mut(first as usize)
            {
                *r = true;
            }
        }
        ContactFolder {
            passes,
            repeated,
            allow_crossings: cfg.allow_crossings,
            by_lines: Default::default(),
            by_path: Default::default(),
            found: Vec::new(),
            counts: [0; 2],
        }
    }

    /// True when some path is cut more than once: its findings list the passes met,
    /// which the whole search must see.
    pub fn lists_passes(&self) -> bool {
        self.repeated.iter().any(|&r| r)
    }

    /// Findings so far: of contours touching themselves, of two contours crossing.
    pub fn counts(&self) -> [usize; 2] {
        self.counts
    }

    /// The path (first contour) and pass number of contour `c`.
    fn pass(&self, c: u32) -> (u32, u32) {
        self.passes.get(c as usize).copied().unwrap_or((c, 1))
    }

    /// Takes the next contact between sides `s` and `t` (`proper`: their interiors cross)
    /// at `at`.
    pub fn contact(&mut self, s: Side, t: Side, proper: bool, at: [f64; 3]) {
        if s.contour != t.contour && (!proper || self.allow_crossings) {
            return;
        }
        let ((ps, ns), (pt, nt)) = (self.pass(s.contour), self.pass(t.contour));
        let mut path = [(ps, s.index), (pt, t.index)];
        path.sort_unstable();
        let lines = (
            s.contour == t.contour,
            s.line.min(t.line),
            s.line.max(t.line),
        );
        // Only a contact on a path cut more than once can repeat an earlier one's place.
        let repeated = |p: u32| self.repeated.get(p as usize).copied().unwrap_or(false);
        let by_path = repeated(ps) || repeated(pt);
        let earlier = by_path.then(|| self.by_path.get(&path).copied()).flatten();
        let k = match (earlier, self.by_lines.get(&lines)) {
            (Some(k), _) | (None, Some(&k)) => k,
            (None, None) => {
                self.counts[usize::from(s.contour != t.contour)] += 1;
                self.found.push(Folded {
                    contours: [s.contour, t.contour],
                    proper,
                    lines: [lines.1, lines.2],
                    at,
                    passes: Default::default(),
                });
                self.found.len() - 1
            }
        };
        if by_path {
            self.by_path.entry(path).or_insert(k);
        }
        self.by_lines.entry(lines).or_insert(k);
        if !by_path {
            // Both paths cut once: pass 1 of each, nothing to list.
            return;
        }
        let p0 = self.pass(self.found[k].contours[0]).0;
        let f = &mut self.found[k];
        // Each pass number goes with the side of the finding on the same path (both sides
        // when the finding is a path crossing itself).
        if ps == pt {
            f.passes.iter_mut().for_each(|p| {
                p.insert(ns);
                p.insert(nt);
            });
        } else {
            let (a, b) = if ps == p0 { (ns, nt) } else { (nt, ns) };
            f.passes[0].insert(a);
            f.passes[1].insert(b);
        }
    }

    /// The findings, in the order of their first contacts, into `out` (findings beyond its
    /// cap only counted).
    pub fn finish(self, out: &mut Capped) {
        for f in self.found {
            let id = if f.contours[0] == f.contours[1] {
                SELF_INTERSECTION
            } else {
                CONTOUR_CROSSING
            };
            out.push_with(id, || {
                let mut g = contact_finding(f.contours, f.proper, f.lines, f.at);
                let list = |p: &std::collections::BTreeSet<u32>| {
                    p.iter().map(u32::to_string).collect::<Vec<_>>().join(", ")
                };
                if f.passes.iter().any(|p| p.len() > 1) {
                    g.message += &if f.contours[0] == f.contours[1] {
                        format!(" (in passes {} of its path)", list(&f.passes[0]))
                    } else {
                        format!(
                            " (in passes {} of contour {}'s path and {} of contour {}'s)",
                            list(&f.passes[0]),
                            f.contours[0],
                            list(&f.passes[1]),
                            f.contours[1]
                        )
                    };
                }
                Some(g)
            });
        }
    }
}

/// Self-intersections of each contour and crossings between contours (unless
/// `cfg.allow_crossings`), on the contours' segments and starts ([`contour_segments`]),
/// into `out` (kept up to its cap per id, the rest counted).
/// Touching or overlapping counts within a contour; between contours only transversal
/// crossings do (a retraced contour, as in multi-pass laser cuts, overlaps itself without
/// crossing). Two contours cut under the same pocket mark ([`note_group_marks`]) may
/// cross, at one depth or at two: they clear one pocket together (a wire hole deeper than
/// its channel crosses the channel's rings in plan view at every level). A contour still
/// may not touch itself, and unmarked contours (profiles, backboards, other tools'
/// programs) are judged strictly. One finding per pair of source lines, and one per
/// crossing of two paths whatever their passes ([`ContactFolder`]).
pub(crate) fn intersection_findings(
    set: &SegmentSet,
    starts: &[ContourStart],
    cfg: &CheckConfig,
    out: &mut Capped,
) {
    let passes = pass_numbers(&path_keys(set));
    let mut folder = ContactFolder::new(&passes, cfg);
    // The search may stop once the report is full: every id that can still be found has
    // more findings than the cap, no finding lists passes that later contacts would add
    // to, and enough contacts were found that the rest are worth not looking for. It
    // stops as soon as every id has all the findings it can have (then the counts are
    // exact, and no lower bound is given).
    let cap = cfg.max_findings_per_check.max(1);
    let crossings = !cfg.allow_crossings && set.contours.len() > 1;
    let may_stop = !folder.lists_passes();
    let mut seen = 0usize;
    // Per id, all the findings it can have found ([`finding_bounds`], taken once contacts
    // come): its count is then exact, and the search need not go on for it.
    let mut bounds: Option<[usize; 2]> = None;
    let mut exhausted = [false; 2];
    let (capped, stopped) = set.contacts_in_order(|batch| {
        seen += batch.len();
        for c in batch {
            let (Some(s), Some(t)) = (set.get(c.i), set.get(c.j)) else {
                continue;
            };
            let side = |g: super::Seg, k: usize| Side {
                contour: g.contour,
                index: g.index,
                // Tagged with its line by [`contour_segments`].
                line: set.source(k) as usize,
            };
            let z = starts.get(s.contour as usize).map(|k| k.z).unwrap_or(0.0);
            folder.contact(
                side(s, c.i),
                side(t, c.j),
                c.proper,
                [c.point.x, c.point.y, z],
            );
        }
        if !may_stop || seen == 0 {
            return true;
        }
        let counts = folder.counts();
        let [own_max, across_max] = *bounds.get_or_insert_with(|| finding_bounds(set));
        exhausted = [counts[0] >= own_max, !crossings || counts[1] >= across_max];
        let done = |k: usize| exhausted[k] || counts[k] > cap;
        let full = done(0) && done(1);
        !(full && (seen >= STOP_AFTER_CONTACTS || exhausted == [true, true]))
    });
    if capped {
        out.push(too_many_contacts());
    }
    folder.finish(out);
    if stopped {
        for (id, exact) in [SELF_INTERSECTION, CONTOUR_CROSSING]
            .into_iter()
            .zip(exhausted)
        {
            if !exact {
                out.at_least(id);
            }
        }
    }
}

/// Most findings the intersection check can make of `set`'s contacts when no path is cut
/// more than once (one finding per pair of source lines, [`ContactFolder`]): of contours
/// touching themselves, Σ r(r+1)/2, and of two contours crossing, Σ_{c<d} r_c·r_d =
/// ((Σ r)² − Σ r²)/2, where r counts the runs of segments of one source line along a
/// contour (no fewer than its distinct lines). A finding count that reaches its bound
/// is the whole count: an arc of 100,000 turns on one line makes one finding however
/// often it crosses itself.
fn finding_bounds(set: &SegmentSet) -> [usize; 2] {
    let (mut own, mut runs, mut squares) = (0u128, 0u128, 0u128);
    let mut at = 0usize;
    for &(n, _) in &set.contours {
        let mut r = 0u128;
        // Segments are tagged with their lines ([`contour_segments`]).
        let mut line = None;
        for k in at..at + n as usize {
            let l = set.source(k);
            r += u128::from(line != Some(l));
            line = Some(l);
        }
        at += n as usize;
        own += r * (r + 1) / 2;
        runs += r;
        squares += r * r;
    }
    let across = (runs * runs - squares) / 2;
    [own, across].map(|b| usize::try_from(b).unwrap_or(usize::MAX))
}

/// Contacts the intersection check finds before it may stop its search early: the counts
/// of findings stay exact where contacts are few (finding them all costs little), and a
/// contour retraced 200 times (199,000 touches) stops after its first window of segments.
const STOP_AFTER_CONTACTS: usize = 8192;

/// Id of the findings of a contour touching itself.
const SELF_INTERSECTION: &str = "self-intersection";

/// Id of the findings of two contours crossing.
const CONTOUR_CROSSING: &str = "contour-crossing";

/// The [`PathKey`] of every contour of `set`, in order, as [`pass_numbers`] reads them:
/// the hash of a contour's points is taken only where another contour has its count,
/// closedness and pocket mark (elsewhere the key differs from every other key whatever
/// the hash, which is then left at [`FNV128_BASIS`]), so that one long contour, as a
/// spiral, is not hashed for nothing. The pass numbers are those of the full keys.
fn path_keys(set: &SegmentSet) -> Vec<PathKey> {
    let mut at = 0usize;
    let spans: Vec<(usize, PathKey)> = set
        .contours
        .iter()
        .map(|&(n, closed)| {
            let end = at + n as usize;
            let segs = if end <= set.len() { at..end } else { at..at };
            let start = at;
            at += n as usize;
            let h = PathHasher {
                count: segs.len() as u32,
                hash: FNV128_BASIS,
            };
            let pocket = if segs.is_empty() {
                None
            } else {
                set.pocket(start)
            };
            (start, h.key(closed, pocket))
        })
        .collect();
    let mut shared: std::collections::HashMap<PathKey, u32> =
        std::collections::HashMap::with_capacity(spans.len());
    for (_, k) in &spans {
        *shared.entry(*k).or_insert(0) += 1;
    }
    spans
        .iter()
        .map(|&(start, k)| {
            if shared.get(&k).copied().unwrap_or(0) < 2 {
                return k;
            }
            let mut h = PathHasher::default();
            for g in start..start + k.count as usize {
                let (a, b) = set.ends(g);
                h.segment(a, b);
            }
            h.key(k.closed, k.pocket)
        })
        .collect()
}

/// The contacts between two cut contours the intersection check looks for: proper
/// crossings, or none with `allow_crossings`. Shared by both routes of the check.
pub(crate) fn across(cfg: &CheckConfig) -> Across {
    if cfg.allow_crossings {
        Across::Never
    } else {
        Across::Crossings
    }
}

/// How far a contour's chords may stray from the path the program describes: the
/// flattening tolerance of its arcs, which also stands for the rounding of its numbers
/// (see [`SegmentSet::tangent_slack`](super::intersect::SegmentSet::tangent_slack)). Shared
/// by both routes of the check.
pub(crate) fn tangent_slack(cfg: &CheckConfig) -> f64 {
    cfg.flatten_tolerance
}

/// The finding of a contact search stopped at [`MAX_CONTACTS`]. Shared by both routes of
/// the intersection check.
pub(crate) fn too_many_contacts() -> Finding {
    Finding::new(
        "too-many-contacts",
        Severity::Error,
        format!(
            "the cut contours meet in more than {MAX_CONTACTS} places: the check stopped there \
             and lists only the first it found"
        ),
    )
}

/// The finding of a contact between a segment of contour `contours[0]` (program line
/// `lines[0]`) and one of `contours[1]` at `at`: `self-intersection` when both are one
/// contour (it crosses itself when `proper`, touches itself otherwise), else
/// `contour-crossing`. Shared by both routes of the intersection check.
pub(crate) fn contact_finding(
    contours: [u32; 2],
    proper: bool,
    lines: [usize; 2],
    at: [f64; 3],
) -> Finding {
    let f = if contours[0] == contours[1] {
        Finding::new(
            "self-intersection",
            Severity::Error,
            format!(
                "cut contour {} {} itself",
                contours[0],
                if proper { "crosses" } else { "touches" }
            ),
        )
    } else {
        Finding::new(
            "contour-crossing",
            Severity::Error,
            format!("cut contours {} and {} cross", contours[0], contours[1]),
        )
    };
    f.lines(lines).at(at)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The keys of [`path_keys`] (hashes only where count, closedness and pocket collide)
    /// number the passes as keys hashed in full do, and as the copies were made.
    #[test]
    fn path_keys_number_passes_as_full_hashes_do() {
        let sq = |o: f64, s: f64| {
            [(0.0, 0.0), (s, 0.0), (s, s), (0.0, s), (0.0, 0.0)]
                .map(|(x, y)| DVec2::new(o + x, o + y))
                .to_vec()
        };
        let open = |o: f64| vec![DVec2::new(o, 0.0), DVec2::new(o + 1.0, 2.0)];
        let mut set = SegmentSet::new();
        // A, a copy of A, B (A's count and closedness, other points), C (one segment,
        // open), D (C's shape in pocket 3), a copy of D, and C's shape again: a copy of C.
        set.push_polyline(&sq(0.0, 1.0), &[]);
        set.push_polyline(&sq(0.0, 1.0), &[]);
        set.push_polyline(&sq(5.0, 2.0), &[]);
        set.push_polyline(&open(9.0), &[]);
        set.push_polyline_in(&open(9.0), &[], Some(3));
        set.push_polyline_in(&open(9.0), &[], Some(3));
        set.push_polyline(&open(9.0), &[]);
        let mut at = 0usize;
        let full: Vec<PathKey> = set
            .contours
            .iter()
            .enumerate()
            .map(|(c, &(n, closed))| {
                let mut h = PathHasher::default();
                for g in at..at + n as usize {
                    let (a, b) = set.ends(g);
                    h.segment(a, b);
                }
                let pocket = set.pocket(at);
                at += n as usize;
                assert_eq!(pocket, [None, None, None, None, Some(3), Some(3), None][c]);
                h.key(closed, pocket)
            })
            .collect();
        let got = pass_numbers(&path_keys(&set));
        assert_eq!(got, pass_numbers(&full));
        assert_eq!(
            got,
            vec![(0, 1), (0, 2), (2, 1), (3, 1), (4, 1), (4, 2), (3, 2)]
        );
    }
}
