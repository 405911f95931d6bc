//! The checks run on a [`Program`]: each returns named [`Finding`]s.
//!
//! | id | severity | what |
//! |---|---|---|
//! | `self-intersection` | error | a cut contour crosses or touches itself (passing twice through one of its vertices without crossing, or tangentially as arc leads at a closed contour's start do, is no touch) |
//! | `contour-crossing` | error | two cut contours cross, one finding per crossing whatever the passes of each path (listed) (off with `allow_crossings`; contours of one marked pocket may, line cuts (`skinpath:group 0`) may cross anything) |
//! | `too-many-contacts` | error | the contours meet in more than `MAX_CONTACTS` places; only the first are listed |
//! | `check-limit` | error | the cut contours flatten to more than `MAX_CONTOUR_SEGMENTS` segments; the contour checks stopped there |
//! | `gouge` | error | tool centre nearer the design than tool radius − tolerance, or on the wrong side |
//! | `out-of-bounds` | error | a move leaves the work area |
//! | `laser-on-rapid` | warning (GRBL laser mode) / error | G0 with M3/M4 and S > 0 |
//! | `rapid-below-safe-z` | error | router rapid moving in xy below safe z |
//! | `rapid-into-stock` | error | router rapid ending below the stock top |
//! | `feed-out-of-range` | error | cutting feed missing or outside the range |
//! | `power-out-of-range` | error | S outside the range while cutting |
//! | `tool-on-at-end` | error (no M2/M30) / warning | the program ends with the tool on |
//! | `missing-program-end` | warning (info where the dialect needs none) | no M2/M30 |
//!
//! Interpreter diagnostics (`gcode-syntax`, `bad-checksum`, `unknown-word`, `unknown-code`,
//! `unsupported-code`, `invalid-arc`, `invalid-value`, `modal-conflict`, `duplicate-word`,
//! `no-motion-mode`, `after-program-end`, `canon-error`, `no-feed-rate`,
//! `percent-without-start`, `no-axis-words`, `axis-in-cycle`: per dialect, see README.md "What each controller refuses") join
//! the same list.

pub(crate) mod contours;
pub(crate) mod gouge;
pub(crate) mod intersect;
pub(crate) mod machine;

pub use contours::{SimContour, cut_contours, is_cutting};
pub use gouge::{DesignBoundary, KeepSide};
pub use intersect::Seg;
#[allow(unused_imports)] // the benches' path, through `crate::internals`
pub use intersect::{Across, SegmentSet};

use super::config::CheckConfig;
use super::findings::Finding;
use super::motion::{Motion, Program};

/// Findings of one check kept up to a cap per id, the rest only counted.
#[derive(Clone, Debug)]
pub(crate) struct Capped {
    cap: usize,
    /// The findings kept, in the order pushed.
    pub(crate) kept: Vec<Finding>,
    /// Per id: findings kept, findings left out.
    counts: Vec<(&'static str, usize, usize)>,
    /// Ids whose search stopped early: their count left out is a lower bound.
    lower: Vec<&'static str>,
}

impl Capped {
    /// A collector keeping at most `cap` (at least 1) findings per id.
    pub(crate) fn new(cap: usize) -> Self {
        Capped {
            cap: cap.max(1),
            kept: Vec::new(),
            counts: Vec::new(),
            lower: Vec::new(),
        }
    }

    /// Keeps `f` unless its id is at the cap.
    pub(crate) fn push(&mut self, f: Finding) {
        self.push_with(f.id, || Some(f));
    }

    /// A finding of `id` built by `make` only when its id is below the cap (messages are
    /// formatted for the findings shown, not for the hundreds of thousands a job placed
    /// off the machine's bed produces); beyond the cap it is counted, and `make` must then
    /// be sure to return `Some`.
    pub(crate) fn push_with(&mut self, id: &'static str, make: impl FnOnce() -> Option<Finding>) {
        let k = match self.counts.iter().position(|c| c.0 == id) {
            Some(k) => k,
            None => {
                self.counts.push((id, 0, 0));
                self.counts.len() - 1
            }
        };
        let c = &mut self.counts[k];
        if c.1 < self.cap {
            if let Some(f) = make() {
                c.1 += 1;
                self.kept.push(f);
            }
        } else {
            c.2 += 1;
        }
    }

    /// Per id, the findings left out (ids with none left out omitted).
    pub(crate) fn dropped(&self) -> impl Iterator<Item = (&'static str, usize)> + '_ {
        self.counts.iter().filter(|c| c.2 > 0).map(|c| (c.0, c.2))
    }

    /// Marks `id` as searched only in part: the findings left out of it are at least the
    /// ones counted.
    pub(crate) fn at_least(&mut self, id: &'static str) {
        if !self.lower.contains(&id) {
            self.lower.push(id);
        }
    }

    /// The ids marked by [`Capped::at_least`] with findings left out.
    pub(crate) fn lower_bounds(&self) -> Vec<&'static str> {
        self.dropped()
            .map(|d| d.0)
            .filter(|id| self.lower.contains(id))
            .collect()
    }
}

/// What the checks found: the findings built, and per id how many more were found but not
/// built because the id had reached `max_findings_per_check` (they come after the ones
/// built; [`crate::sim::assemble_with`] counts them as suppressed).
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct CheckFindings {
    /// The findings, in the order of the checks.
    pub findings: Vec<Finding>,
    /// Per id, findings counted but not built.
    pub dropped: Vec<(&'static str, usize)>,
    /// Ids of `dropped` whose search stopped once the report was full: more findings than
    /// counted may exist (the contact search stops early).
    pub at_least: Vec<&'static str>,
}

/// The checks on the cut contours (`cfg` in mm): self-intersections and crossings, then
/// gouges. With [`MoveChecks`] on the same program, every check.
pub fn contour_findings(
    prog: &Program,
    cfg: &CheckConfig,
    design: &[DesignBoundary],
) -> CheckFindings {
    let mut pass = ContourPass::new(cfg, design);
    pass.gather
        .reserve(prog.motions.len().min(contours::MAX_CONTOUR_SEGMENTS));
    for m in &prog.motions {
        pass.motion(&m);
    }
    pass.finish()
}

/// [`contour_findings`] fed move by move, for callers that do not store the moves: the
/// segments are gathered and each move's gouges found as the moves come, the contacts
/// and the contour starts' gouges looked for at the end.
pub(crate) struct ContourPass<'c> {
    cfg: &'c CheckConfig,
    gather: contours::SegmentGather,
    gouge: Option<gouge::GougeIndex<'c>>,
    /// The gouges of the moves so far.
    gouges: Vec<Finding>,
}

impl<'c> ContourPass<'c> {
    /// No move seen yet (`cfg` in mm, `design` in mm).
    pub(crate) fn new(cfg: &'c CheckConfig, design: &'c [DesignBoundary]) -> Self {
        ContourPass {
            cfg,
            gather: contours::SegmentGather::new(cfg),
            gouge: gouge::GougeIndex::new(design, cfg),
            gouges: Vec::new(),
        }
    }

    /// Takes the next move.
    pub(crate) fn motion(&mut self, m: &Motion) {
        self.gather.motion(m, self.cfg);
        if let Some(g) = &self.gouge
            && let Some(f) = g.motion(m, is_cutting(m, self.cfg))
        {
            self.gouges.push(f);
        }
    }

    /// The findings: contacts (capped, counted beyond the cap), the moves' gouges, the
    /// contour starts' gouges.
    pub(crate) fn finish(self) -> CheckFindings {
        let cfg = self.cfg;
        let (set, starts, limit) = self.gather.finish();
        let mut inter = Capped::new(cfg.max_findings_per_check);
        if let Some(f) = limit {
            inter.push(f);
        }
        contours::intersection_findings(&set, &starts, cfg, &mut inter);
        drop(set);
        let dropped = inter.dropped().collect();
        let at_least = inter.lower_bounds();
        let mut findings = inter.kept;
        findings.extend(self.gouges);
        if let Some(g) = &self.gouge {
            findings.extend(g.contour_starts(&starts));
        }
        CheckFindings {
            findings,
            dropped,
            at_least,
        }
    }
}

/// The findings of every check: `contour` ([`contour_findings`]) first, then those of
/// [`MoveChecks`].
pub fn join(contour: CheckFindings, moves: CheckFindings) -> CheckFindings {
    let mut findings = contour.findings;
    findings.extend(moves.findings);
    let mut dropped = contour.dropped;
    dropped.extend(moves.dropped);
    let mut at_least = contour.at_least;
    at_least.extend(moves.at_least);
    CheckFindings {
        findings,
        dropped,
        at_least,
    }
}

/// The checks of one move at a time (`cfg` in mm): travel limits, rapids, feed and power,
/// and at the end the program end's. Fed by any pass over the moves (the time estimate's,
/// so that the moves are read once for both).
pub struct MoveChecks<'c> {
    cfg: &'c CheckConfig,
    limits: machine::Limits,
    bounds: Capped,
    rapids: Vec<Finding>,
    feeds: Vec<Finding>,
    feed_power: machine::FeedPower,
}

impl<'c> MoveChecks<'c> {
    /// No move checked yet.
    pub fn new(cfg: &'c CheckConfig) -> Self {
        MoveChecks {
            cfg,
            limits: machine::Limits::new(cfg),
            bounds: Capped::new(cfg.max_findings_per_check),
            rapids: Vec::new(),
            feeds: Vec::new(),
            feed_power: machine::FeedPower::default(),
        }
    }

    /// Checks the next move, whose [`Motion::bounds`] are `bounds`.
    pub fn motion_in(&mut self, m: &Motion, bounds: (glam::DVec3, glam::DVec3)) {
        let cfg = self.cfg;
        self.limits.check_move_in(m, bounds, cfg, &mut self.bounds);
        machine::rapid_move(m, cfg, &mut self.rapids);
        self.feed_power.motion(m, cfg, &mut self.feeds);
    }

    /// The travel-limit, rapid and feed-and-power findings one after the other,
    /// then the program end's; out-of-bounds findings beyond the cap counted, not built.
    pub fn finish(self, prog: &Program) -> CheckFindings {
        let dropped = self.bounds.dropped().collect();
        let mut findings = self.bounds.kept;
        findings.extend(self.rapids);
        findings.extend(self.feeds);
        findings.extend(machine::program_end(prog, self.cfg));
        CheckFindings {
            findings,
            dropped,
            at_least: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::intersect::{Across, SegmentSet};
    use super::*;
    use crate::geom::DVec2;
    use crate::sim::config::Dialect;
    use crate::sim::{Backend, CheckConfig, check_text};
    use proptest::prelude::*;

    /// A star-shaped polygon about the origin: angles i·2π/n + jitter (gaps stay in
    /// (0.1, 1.9)·2π/n < π), radii in [1, 10], shifted by `c`.
    fn star(jitter: &[f64], radii: &[f64], c: DVec2) -> Vec<DVec2> {
        let n = jitter.len().min(radii.len());
        (0..n)
            .map(|i| {
                let t = std::f64::consts::TAU * (i as f64 + 0.9 * jitter[i]) / n as f64;
                c + radii[i] * DVec2::new(t.cos(), t.sin())
            })
            .collect()
    }

    fn variants(p: &[DVec2]) -> Vec<Vec<DVec2>> {
        let rot = DVec2::from_angle(0.7);
        vec![
            p.to_vec(),
            p.iter().rev().copied().collect(),
            p.iter().map(|&q| 1e3 * rot.rotate(q)).collect(),
            p.iter().map(|&q| 1e-3 * q).collect(),
        ]
    }

    /// A job placed partly off the bed: 3,000 feed moves, every third one ending beyond
    /// x = 300. With a cap of 7 the report keeps the first 7 out-of-bounds findings of the
    /// uncapped report, counts the rest as suppressed, and the streaming route says the same.
    #[test]
    fn out_of_bounds_beyond_the_cap_are_counted_not_built() {
        let mut src = String::from("G21 G90 F1000 S500\nG0 X10 Y10\nM3\n");
        for i in 0..3000 {
            let x = if i % 3 == 2 { 310.0 } else { 200.0 };
            src += &format!("G1 X{x:.3} Y{:.3}\n", 10.0 + 0.01 * i as f64);
        }
        src += "M5\nM2\n";
        let capped = CheckConfig {
            max_findings_per_check: 7,
            ..CheckConfig::default()
        };
        let all = CheckConfig {
            max_findings_per_check: usize::MAX,
            ..capped.clone()
        };
        let oob = |r: &crate::sim::Report| -> Vec<Finding> {
            r.findings
                .iter()
                .filter(|f| f.id == machine::OUT_OF_BOUNDS)
                .cloned()
                .collect()
        };
        let full = check_text(Backend::Builtin, &src, &all, &[]);
        // Every third move goes out (1,000) and the next one starts outside (999 more).
        assert_eq!(oob(&full).len(), 1999);
        let r = check_text(Backend::Builtin, &src, &capped, &[]);
        assert_eq!(oob(&r), oob(&full)[..7].to_vec());
        assert_eq!(r.suppressed, vec![("out-of-bounds".to_string(), 1992)]);
        let opts = crate::sim::interp::Options { load_sub: None };
        let _running = crate::sim::stream::TEST_LOCK
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        let (streamed, _) = crate::sim::stream::check_stream(
            Box::new(std::io::Cursor::new(src.clone().into_bytes())),
            &capped,
            &[],
            &opts,
        )
        .unwrap();
        assert_eq!(oob(&streamed), oob(&r));
        assert_eq!(streamed.suppressed, r.suppressed);
        // The totals count what the cap left out; the summary says both numbers.
        assert_eq!(r.errors_in_all(), full.errors());
        assert_eq!(full.errors_in_all(), full.errors());
        let expected = format!("{} errors ({} shown)", full.errors(), r.errors());
        assert!(r.to_string().contains(&expected), "{r}");
        // A cap of 0 still shows one finding, so the program still fails its check.
        let none = CheckConfig {
            max_findings_per_check: 0,
            ..capped.clone()
        };
        let z = check_text(Backend::Builtin, &src, &none, &[]);
        assert_eq!(oob(&z).len(), 1);
        assert_eq!((z.exit_code(), z.errors_in_all()), (1, full.errors()));
    }

    /// The contour findings of `src` on the in-memory route, the same as the streaming
    /// route's (checked), and the report's suppressed counts.
    fn contour_report(src: &str, cfg: &CheckConfig) -> (Vec<Finding>, Vec<(String, usize)>) {
        let r = check_text(Backend::Builtin, src, cfg, &[]);
        let opts = crate::sim::interp::Options { load_sub: None };
        let _running = crate::sim::stream::TEST_LOCK
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        let (streamed, _) = crate::sim::stream::check_stream(
            Box::new(std::io::Cursor::new(src.as_bytes().to_vec())),
            cfg,
            &[],
            &opts,
        )
        .unwrap();
        assert_eq!(streamed.findings, r.findings);
        assert_eq!(streamed.suppressed, r.suppressed);
        let kept = r
            .findings
            .iter()
            .filter(|f| f.id == "contour-crossing" || f.id == "self-intersection")
            .cloned()
            .collect();
        (kept, r.suppressed)
    }

    /// A square of side `s` at (`x`, `y`), its own contour (laser on, then off).
    fn square_pass(x: f64, y: f64, s: f64) -> String {
        format!(
            "G0 X{x} Y{y}\nM4 S500\nG1 X{} Y{y} F1000\nG1 X{} Y{}\nG1 X{x} Y{}\nG1 X{x} Y{y}\nM5\n",
            x + s,
            x + s,
            y + s,
            y + s
        )
    }

    /// Smoothieware's laser module fires on G1 with S and no M3: two crossing squares cut so
    /// are two crossings on the smoothie dialect (and none where M3 is needed to fire).
    #[test]
    fn smoothie_laser_cuts_without_m3() {
        let mut src = String::from("G21 G90\n");
        for (x, y) in [(0.0, 0.0), (5.0, 5.0)] {
            src += &square_pass(x, y, 10.0)
                .replace("M4 S500\n", "")
                .replace("F1000", "F1000 S0.5");
        }
        src += "M2\n";
        let smoothie = CheckConfig {
            dialect: Dialect::Smoothie,
            ..CheckConfig::default()
        };
        assert_eq!(contour_report(&src, &smoothie).0.len(), 2);
        assert_eq!(contour_report(&src, &CheckConfig::default()).0.len(), 0);
    }

    /// Two squares crossing at two points, (10, 5) and (5, 10), each cut in `passes`
    /// passes: two findings whatever the passes, each at its crossing and listing the
    /// passes; on both routes.
    #[test]
    fn multi_pass_crossings_are_counted_once() {
        for (passes, interleaved) in [(1, false), (2, false), (2, true), (5, false)] {
            let mut src = String::from("G21 G90\n");
            if interleaved {
                for _ in 0..passes {
                    src += &square_pass(0.0, 0.0, 10.0);
                    src += &square_pass(5.0, 5.0, 10.0);
                }
            } else {
                for _ in 0..passes {
                    src += &square_pass(0.0, 0.0, 10.0);
                }
                for _ in 0..passes {
                    src += &square_pass(5.0, 5.0, 10.0);
                }
            }
            src += "M2\n";
            let (found, _) = contour_report(&src, &CheckConfig::default());
            assert_eq!(found.len(), 2, "{passes} passes: {found:#?}");
            let mut at: Vec<[f64; 2]> = found.iter().map(|f| [f.at[0][0], f.at[0][1]]).collect();
            at.sort_by(|a, b| a[0].total_cmp(&b[0]));
            assert_eq!(at, vec![[5.0, 10.0], [10.0, 5.0]]);
            let list: Vec<String> = (1..=passes).map(|p| p.to_string()).collect();
            for f in &found {
                assert_eq!(f.id, "contour-crossing");
                if passes > 1 {
                    let want = format!("in passes {} of contour", list.join(", "));
                    assert!(f.message.contains(&want), "{}", f.message);
                } else {
                    assert!(!f.message.contains("passes"), "{}", f.message);
                }
            }
        }
    }

    /// One contour around a square 300 times: every pass touches every other along each
    /// side. With a cap of 7 the report keeps the first 7 findings of the uncapped one and
    /// counts the rest, on both routes.
    #[test]
    fn retraced_contour_findings_are_capped_and_counted() {
        let mut src = String::from("G21 G90\nG0 X0 Y0\nM4 S500\n");
        for _ in 0..300 {
            src += "G1 X4 Y0 F1000\nG1 X4 Y4\nG1 X0 Y4\nG1 X0 Y0\n";
        }
        src += "M5\nM2\n";
        let all = CheckConfig {
            max_findings_per_check: usize::MAX,
            ..CheckConfig::default()
        };
        let capped = CheckConfig {
            max_findings_per_check: 7,
            ..all.clone()
        };
        let (full, none) = contour_report(&src, &all);
        assert!(none.is_empty());
        // Each move after the first pass lies on its side's first pass: a finding each
        // (copies of a segment are tested against their first copy, SegmentSet::cell_pairs).
        assert!(full.len() >= 1196, "{}", full.len());
        assert!(full.iter().all(|f| f.id == "self-intersection"));
        let (kept, dropped) = contour_report(&src, &capped);
        assert_eq!(kept, full[..7].to_vec());
        assert_eq!(
            dropped,
            vec![("self-intersection".to_string(), full.len() - 7)]
        );
    }

    /// One contour around a 1000-gon 70 times (70,000 segments, searched in rounds): with
    /// the report's cap the search stops once it is full, shows the first findings of the
    /// whole search and gives the rest as a lower bound, marked in the report (text and
    /// JSON); without a cap it is the whole search.
    #[test]
    fn long_retrace_stops_once_the_report_is_full() {
        let mut src = String::from("G21 G90\nG0 X14 Y10\nM4 S500 F1000\n");
        for _ in 0..70 {
            for i in 1..=1000 {
                let t = std::f64::consts::TAU * f64::from(i % 1000) / 1000.0;
                src += &format!(
                    "G1 X{:.3} Y{:.3}\n",
                    10.0 + 4.0 * t.cos(),
                    10.0 + 4.0 * t.sin()
                );
            }
        }
        src += "M5\nM2\n";
        let all = CheckConfig {
            max_findings_per_check: usize::MAX,
            ..CheckConfig::default()
        };
        let full = check_text(Backend::Builtin, &src, &all, &[]);
        assert!(full.suppressed_at_least.is_empty());
        let full: Vec<Finding> = (full.findings.into_iter())
            .filter(|f| f.id == "self-intersection")
            .collect();
        assert!(full.len() > 60_000, "{}", full.len());
        let cfg = CheckConfig::default();
        let cap = cfg.max_findings_per_check;
        let r = check_text(Backend::Builtin, &src, &cfg, &[]);
        let kept: Vec<&Finding> = (r.findings.iter())
            .filter(|f| f.id == "self-intersection")
            .collect();
        assert_eq!(kept, full[..cap].iter().collect::<Vec<_>>());
        let more = r.suppressed.iter().find(|s| s.0 == "self-intersection");
        let more = more.map_or(0, |s| s.1);
        assert!(more >= 1 && more < full.len() - cap, "{more}");
        assert_eq!(r.suppressed_at_least, vec!["self-intersection".to_string()]);
        let text = r.to_string();
        assert!(text.contains(&format!("... at least {more} more [self-intersection]")));
        assert!(
            text.contains(&format!("at least {} errors", cap + more)),
            "{text}"
        );
        let json = serde_json::to_value(&r).unwrap_or_default();
        assert_eq!(json["suppressed_at_least"][0], "self-intersection");
    }

    /// An arc of 500 turns on one line (78,540 chords crossing one another some 10⁷ times):
    /// all its contacts make one finding, so the search stops once it has it. The report
    /// is that finding at the first contact in segment order (found here by testing the
    /// first segments against all others), exact (no lower bound, no contact limit
    /// reached), on the circle within the flattening tolerance.
    #[test]
    fn arc_of_many_turns_on_one_line_makes_one_finding_and_stops() {
        let src = "G21 G90 G17\nG0 X0 Y0\nM3 S500\nG2 X10 Y0 I5 J0 P500 F600\nM5\nM2\n";
        let cfg = CheckConfig::default();
        let r = check_text(Backend::Builtin, src, &cfg, &[]);
        assert!(
            r.findings.iter().all(|f| f.id != "too-many-contacts"),
            "{r}"
        );
        assert!(
            r.suppressed_at_least.is_empty() && r.suppressed.is_empty(),
            "{r}"
        );
        let own: Vec<&Finding> = (r.findings.iter())
            .filter(|f| f.id == "self-intersection")
            .collect();
        assert_eq!(own.len(), 1, "{r}");
        assert_eq!(own[0].lines, vec![4, 4]);
        let prog = crate::sim::load(Backend::Builtin, src, &cfg.in_mm());
        let (set, _, _) = contours::contour_segments(&prog.motions, &cfg);
        let n = set.len();
        assert!(n >= intersect::ROUNDS_MIN, "{n}");
        let first = (0..n)
            .find_map(|i| (i + 1..n).find_map(|j| set.test_pair(i, j)))
            .map(|c| [c.point.x, c.point.y, 0.0]);
        assert_eq!(Some(own[0].at[0]), first);
        let from_centre = DVec2::new(own[0].at[0][0] - 5.0, own[0].at[0][1]).length();
        assert!(
            (from_centre - 5.0).abs() <= cfg.flatten_tolerance,
            "{from_centre}"
        );
    }

    fn gcode(p: &[DVec2]) -> String {
        let mut s = String::from("G21 G90\n");
        let first = p.first().copied().unwrap_or_default();
        s += &format!("G0 X{:.6} Y{:.6}\nM4 S500\n", first.x, first.y);
        for q in p.iter().skip(1).chain(std::iter::once(&first)) {
            s += &format!("G1 X{:.6} Y{:.6} F1000\n", q.x, q.y);
        }
        s + "M5\nM2\n"
    }

    /// A scribble that crosses itself everywhere: a boustrophedon of 1100 rows and then 1100
    /// columns, one contour with 1100² = 1.21 M crossings. The search stops at
    /// MAX_CONTACTS (2²⁰) and the report says so, besides listing the first crossings.
    #[test]
    fn contacts_stop_at_the_limit_and_the_report_says_so() {
        let k = 1100;
        let side = k as f64 + 1.0;
        let mut pts = Vec::new();
        for r in 0..k {
            let y = r as f64 + 0.5;
            let (a, b) = if r % 2 == 0 { (0.0, side) } else { (side, 0.0) };
            pts.push(DVec2::new(a, y));
            pts.push(DVec2::new(b, y));
        }
        for c in 0..k {
            let x = c as f64 + 0.25;
            let (a, b) = if c % 2 == 0 { (side, 0.0) } else { (0.0, side) };
            pts.push(DVec2::new(x, a));
            pts.push(DVec2::new(x, b));
        }
        let mut s = SegmentSet::new();
        s.push_polyline(&pts, &[]);
        let (contacts, capped) = s.contacts_capped();
        assert!(capped);
        assert!(contacts.len() <= intersect::MAX_CONTACTS + pts.len());
        assert!(
            contacts.len() >= intersect::MAX_CONTACTS / 2,
            "{}",
            contacts.len()
        );
        let r = check_text(Backend::Builtin, &gcode(&pts), &CheckConfig::default(), &[]);
        assert!(
            r.findings.iter().any(|f| f.id == "too-many-contacts"),
            "{r}"
        );
        assert!(r.findings.iter().any(|f| f.id == "self-intersection"));
        // Below the limit nothing is said: 100 rows and columns, 10⁴ crossings.
        let small: Vec<DVec2> = pts
            .iter()
            .filter(|p| (p.x.fract() == 0.25 && p.x < 100.0) || (p.y.fract() == 0.5 && p.y < 100.0))
            .copied()
            .collect();
        let mut s = SegmentSet::new();
        s.push_polyline(&small, &[]);
        assert!(!s.contacts_capped().1);
    }

    /// The eight passes of a multi-depth cut lie on one another in xy: every segment touches
    /// three segments of each other pass, 20 000 · 8 · 3 · 7 / 2 = 1.68 M contacts in all,
    /// beyond MAX_CONTACTS. The intersection check counts only crossings between contours,
    /// so it finds none and does not stop; a contour planted across the passes is found.
    #[test]
    fn coincident_passes_are_not_contacts_but_crossings_between_them_are() {
        let n = 20_000;
        let ring: Vec<DVec2> = (0..=n)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / n as f64;
                DVec2::new(50.0 * t.cos(), 50.0 * t.sin())
            })
            .collect();
        let passes = |across| {
            let mut s = SegmentSet::new();
            s.across = across;
            for _ in 0..8 {
                s.push_polyline(&ring, &[]);
            }
            s
        };
        let (all, capped) = passes(Across::All).contacts_capped();
        assert!(capped, "{}", all.len());
        for across in [Across::Crossings, Across::Never] {
            let (c, capped) = passes(across).contacts_capped();
            assert!(c.is_empty() && !capped, "{across:?}: {}", c.len());
        }
        let mut s = passes(Across::Crossings);
        s.push_polyline(&[DVec2::new(0.0, 0.0), DVec2::new(60.0, 1.0)], &[]);
        let c = s.contacts();
        assert_eq!(c.len(), 8, "one crossing per pass: {c:?}");
        assert!(
            c.iter()
                .all(|c| c.proper && (c.point.length() - 50.0).abs() < 1e-3)
        );
        let mut s = passes(Across::Never);
        s.push_polyline(&[DVec2::new(0.0, 0.0), DVec2::new(60.0, 1.0)], &[]);
        assert!(s.contacts().is_empty());
    }

    /// Concentric rings (a channel's clearing rings, 2,000 chords each) inside a board
    /// outline, every contour cut in three passes: the chains' boxes overlap over their whole
    /// length, yet nothing meets; the grid and every pair agree. Then a ring nudged onto its
    /// neighbour is caught, in one pass of it or in all.
    #[test]
    fn nested_rings_in_passes_are_apart_and_a_touch_is_found() {
        let ring = |r: f64, n: usize| -> Vec<DVec2> {
            (0..=n)
                .map(|k| DVec2::from_angle(k as f64 * std::f64::consts::TAU / n as f64) * r)
                .collect()
        };
        let board = vec![
            DVec2::new(-20.0, -12.0),
            DVec2::new(20.0, -12.0),
            DVec2::new(20.0, 12.0),
            DVec2::new(-20.0, 12.0),
            DVec2::new(-20.0, -12.0),
        ];
        let build = |rings: &[Vec<DVec2>], passes: usize| {
            let mut s = SegmentSet::new();
            s.across = Across::Crossings;
            for p in rings.iter().chain([&board]) {
                for _ in 0..passes {
                    s.push_polyline(p, &[]);
                }
            }
            s
        };
        let rings: Vec<Vec<DVec2>> = (1..=4).map(|k| ring(2.0 * k as f64, 500)).collect();
        for passes in [1, 3] {
            let s = build(&rings, passes);
            assert!(s.contacts().is_empty());
            assert!(s.brute_force().is_empty());
        }
        // The third ring bulges across the second at one chord.
        let mut bent = rings.clone();
        bent[2][100] = bent[1][100] * 0.9;
        for passes in [1, 3] {
            let s = build(&bent, passes);
            let (grid, all) = (s.contacts(), s.brute_force());
            assert!(!grid.is_empty());
            assert_eq!(grid.len(), all.len(), "{passes} passes");
        }
    }

    /// Contours of one pocket may cross one another; contours of two pockets, or a pocket
    /// and a contour outside any, may not. A contour never may cross itself.
    #[test]
    fn contours_of_one_pocket_may_cross() {
        let x = [DVec2::new(0.0, 0.0), DVec2::new(10.0, 10.0)];
        let y = [DVec2::new(0.0, 10.0), DVec2::new(10.0, 0.0)];
        for (p, q, crossing) in [
            (Some(1), Some(1), false),
            (Some(1), Some(2), true),
            (Some(1), None, true),
            (None, None, true),
        ] {
            let mut s = SegmentSet::new();
            s.across = Across::Crossings;
            s.push_polyline_in(&x, &[], p);
            s.push_polyline_in(&y, &[], q);
            assert_eq!(s.contacts().len(), usize::from(crossing), "{p:?} {q:?}");
        }
        let mut s = SegmentSet::new();
        s.across = Across::Crossings;
        let bow = [x[0], x[1], y[0], y[1]];
        s.push_polyline_in(&bow, &[], Some(1));
        s.push_polyline_in(&bow, &[], Some(1));
        assert_eq!(s.contacts().len(), 2, "each copy crosses itself once");
        // A second pass of a pocket's contour cut outside the pocket is no copy of it: a
        // contour of the pocket crossing both crosses the second.
        let mut s = SegmentSet::new();
        s.across = Across::Crossings;
        s.push_polyline_in(&x, &[], Some(1));
        s.push_polyline_in(&x, &[], None);
        s.push_polyline_in(&y, &[], Some(1));
        let c = s.contacts();
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!((s.seg(c[0].i).contour, s.seg(c[0].j).contour), (1, 2));
    }

    /// The segment set built in one pass ([`contours::contour_segments`]) is the one built
    /// from the contours kept whole, with the same contour starts: a program with arcs,
    /// tool switches, depth changes, a dwell and pocket marks.
    #[test]
    fn contour_segments_match_the_kept_contours() {
        let src = "G21 G90 F1000 S500\nG0 X1 Y1\nM3\nG1 X5 Y1\nG2 X9 Y5 I0 J4\nY9\n\
                   M5\nG0 X20 Y0\nM3\n(skinpath:group 4)\nG1 X25\nG4 P0.5\nG3 X25 Y5 R3\n\
                   (skinpath:group none)\nG1 X20 Y5\nG1 Z-1\nG1 X20 Y0\nM3 S0\nG1 X30\n\
                   M3 S500\nG1 X30 Y30\nX31\nM5\nM2\n";
        let cfg = CheckConfig {
            kind: crate::sim::MachineKind::Laser,
            ..CheckConfig::default()
        }
        .in_mm();
        let prog = crate::sim::load(Backend::Builtin, src, &cfg);
        let kept = contours::cut_contours_marked(&prog.motions, &cfg);
        assert!(kept.len() >= 4, "{kept:?}");
        let (set, starts, _) = contours::contour_segments(&prog.motions, &cfg);
        let mut want = SegmentSet::new();
        for c in &kept {
            want.push_polyline_in(&c.points, &c.sources, c.group);
        }
        assert_eq!(
            set.iter().collect::<Vec<_>>(),
            want.iter().collect::<Vec<_>>()
        );
        assert_eq!(set.contours, want.contours);
        let want_starts: Vec<contours::ContourStart> = kept
            .iter()
            .map(|c| contours::ContourStart {
                point: c.points[0],
                line: c
                    .sources
                    .first()
                    .and_then(|&s| prog.motions.get(s as usize))
                    .map(|m| m.line),
                z: c.z,
            })
            .collect();
        assert_eq!(starts, want_starts);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Small polygons on a coarse integer grid (many shared vertices, collinear
        /// overlaps and touches), some repeated as further passes, some in pockets: the
        /// sweep with copies left out, the grid and the test of every pair find contacts
        /// alike.
        #[test]
        fn copies_and_pockets_change_nothing_found(
            polys in proptest::collection::vec(
                (proptest::collection::vec((0i32..6, 0i32..6), 3..7), 1usize..4, 0u32..3),
                1..6,
            ),
            across in 0usize..2,
        ) {
            let mut s = SegmentSet::new();
            s.across = [Across::Crossings, Across::Never][across];
            for (pts, passes, pocket) in &polys {
                let mut p: Vec<DVec2> =
                    pts.iter().map(|&(x, y)| DVec2::new(x as f64, y as f64)).collect();
                p.push(p[0]);
                for _ in 0..*passes {
                    s.push_polyline_in(&p, &[], (*pocket > 0).then_some(*pocket));
                }
            }
            let folds = s.contacts().iter().filter(|c| {
                let (a, b) = (s.seg(c.i), s.seg(c.j));
                a.contour == b.contour && b.index == a.index + 1
                    || a.contour == b.contour && a.index == 0 && b.index + 1 == s.contours[b.contour as usize].0
            }).count();
            let grid = s.contacts().len() - folds;
            let all = s.brute_force();
            prop_assert_eq!(grid == 0, all.is_empty(), "grid {} all {}", grid, all.len());
        }

        #[test]
        fn star_polygons_are_simple(
            jitter in proptest::collection::vec(0.0f64..1.0, 3..60),
            radii in proptest::collection::vec(1.0f64..10.0, 60),
        ) {
            let p = star(&jitter, &radii, DVec2::ZERO);
            for v in variants(&p) {
                let mut closed = v.clone();
                closed.push(v[0]);
                let mut s = SegmentSet::new();
                s.push_polyline(&closed, &[]);
                prop_assert!(s.contacts().is_empty());
            }
            // Through the whole pipeline: no finding at all (G-code rounded to 1e-6).
            let q: Vec<DVec2> = p.iter().map(|&x| x + DVec2::splat(20.0)).collect();
            let r = check_text(Backend::Builtin, &gcode(&q), &CheckConfig::default(), &[]);
            prop_assert!(r.findings.is_empty(), "{}", r);
        }

        #[test]
        fn planted_crossing_is_caught(
            jitter in proptest::collection::vec(0.0f64..1.0, 4..60),
            radii in proptest::collection::vec(1.0f64..10.0, 60),
            pick in 0usize..1000,
        ) {
            let p = star(&jitter, &radii, DVec2::ZERO);
            // Open polyline v0..v_{k}, then a spoke through the midpoint of edge i.
            let i = pick % (p.len() - 2);
            let m = 0.5 * (p[i] + p[i + 1]);
            let rot = DVec2::from_angle(0.7);
            let transforms: [&dyn Fn(DVec2) -> DVec2; 3] =
                [&|q| q, &|q| 1e3 * rot.rotate(q), &|q| 1e-3 * q];
            for reverse in [false, true] {
                for f in transforms {
                    let mut poly: Vec<DVec2> = p.iter().map(|&q| f(q)).collect();
                    if reverse {
                        poly.reverse();
                    }
                    poly.push(f(0.5 * m));
                    poly.push(f(1.5 * m));
                    let mut s = SegmentSet::new();
                    s.push_polyline(&poly, &[]);
                    let spoke = poly.len() - 2;
                    let c = s.contacts();
                    prop_assert!(
                        c.iter().any(|c| c.j == spoke),
                        "spoke {} not caught: {:?}", spoke, c
                    );
                }
            }
        }
    }
}
