//! Turning one contour (lines and arcs) into a cut: passes stepping down to the final
//! depth, lead-in and lead-out arcs on the waste side, and holding tabs on through-cuts.

use super::model::{Cut, Move, MoveKind};
use crate::geom::tol::LENGTH_ACCURACY;
use crate::geom::{Aabb, Arc, DVec2, Line, Path, PathSeg, perp};
use glam::DVec3;

/// Holding tabs: short bridges left standing on the last passes of a through-cut. On a
/// cut at the surface (a laser) a tab is a gap with the beam off on every pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tabs {
    /// Number of tabs, spread evenly along the contour.
    pub count: usize,
    /// Length of each tab along the contour (add the tool diameter: this is the tool centre's
    /// lift length).
    pub width: f64,
    /// Height of the tabs above the final depth.
    pub height: f64,
}

/// How the tool enters and leaves the contour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lead {
    /// Straight onto the contour.
    None,
    /// A quarter arc of the given radius tangent to the contour, on the waste side.
    Arc(f64),
}

/// Parameters of one cut.
#[derive(Clone, Debug, PartialEq)]
pub struct CutOptions {
    /// Cutting feed, units per minute.
    pub feed: f64,
    /// Plunge (z down) feed, units per minute.
    pub plunge_feed: f64,
    /// Laser power or spindle speed, fraction of the machine's maximum.
    pub power: f64,
    /// The z of each pass, in order (≤ 0; lasers use 0 for every pass).
    pub levels: Vec<f64>,
    /// Holding tabs left uncut on the last pass, if any.
    pub tabs: Option<Tabs>,
    /// How the cut is entered.
    pub lead: Lead,
    /// True when the waste (the side the lead may use) is left of the travel direction.
    pub waste_left: bool,
}

/// Relative slack of the pass count ⌈depth / step_down − slack⌉: a depth that is a whole
/// number of steps up to rounding (3 × 0.1 = 0.30000000000000004) gets that many passes,
/// not one more.
const STEP_COUNT_SLACK: f64 = 1e-9;

/// Depth levels stepping down by at most `step_down` to `depth` (depth > 0 is below the
/// surface): ⌈depth / step_down⌉ equal passes. A zero depth gives one pass at z = 0.
pub fn step_levels(depth: f64, step_down: f64) -> Vec<f64> {
    if depth <= 0.0 || step_down <= 0.0 {
        return vec![0.0];
    }
    let n = (depth / step_down - STEP_COUNT_SLACK).ceil().max(1.0) as usize;
    (1..=n).map(|i| -depth * i as f64 / n as f64).collect()
}

fn seg_tangent(s: &PathSeg, t: f64) -> DVec2 {
    match s {
        PathSeg::Line(l) => (l.p1 - l.p0).normalize_or_zero(),
        PathSeg::Arc(a) => a.tangent(t),
        PathSeg::Cubic(c) => c.deriv(t).normalize_or_zero(),
    }
}

/// The piece of a line or arc between arc lengths `s0` and `s1` from its start.
fn sub_seg(s: &PathSeg, s0: f64, s1: f64, len: f64) -> PathSeg {
    let (t0, t1) = if len > 0.0 {
        (s0 / len, s1 / len)
    } else {
        (0.0, 1.0)
    };
    match s {
        PathSeg::Line(l) => PathSeg::Line(Line::new(l.eval(t0), l.eval(t1))),
        PathSeg::Arc(a) => PathSeg::Arc(Arc::new(
            a.center,
            a.radius,
            a.start + t0 * a.sweep,
            (t1 - t0) * a.sweep,
        )),
        PathSeg::Cubic(c) => PathSeg::Cubic(c.subsegment(t0, t1)),
    }
}

/// The path's segments cut at the given increasing arc lengths, each piece with the arc
/// length at its start.
fn split_at_lengths(path: &Path, marks: &[f64]) -> Vec<(PathSeg, f64)> {
    let mut out = Vec::new();
    let mut s_start = 0.0;
    let mut mi = 0;
    for seg in &path.segs {
        let len = seg.length(LENGTH_ACCURACY);
        let mut local = 0.0;
        while mi < marks.len() && marks[mi] < s_start + len {
            let m = marks[mi] - s_start;
            if m > local {
                out.push((sub_seg(seg, local, m, len), s_start + local));
                local = m;
            }
            mi += 1;
        }
        if len - local > 0.0 {
            out.push((sub_seg(seg, local, len, len), s_start + local));
        }
        s_start += len;
    }
    out
}

fn move_along(seg: &PathSeg, z: f64, feed: f64, power: f64) -> Move {
    let end = seg.end();
    let to = DVec3::new(end.x, end.y, z);
    let kind = match seg {
        PathSeg::Arc(a) => MoveKind::Arc {
            center: a.center,
            ccw: a.sweep > 0.0,
        },
        _ => MoveKind::Line,
    };
    Move {
        kind,
        to,
        feed,
        power,
    }
}

/// How often a lead that runs into the contour is halved before it is left out.
const LEAD_HALVINGS: usize = 3;

/// Lead-in (from the entry point to `start`, arriving along `t0`) and lead-out (from `end`,
/// leaving along `t1`) on the side `side` (+1 left of travel, −1 right).
fn lead_geometry(
    lead: Lead,
    side: f64,
    start: DVec2,
    t0: DVec2,
    end: DVec2,
    t1: DVec2,
) -> (DVec2, Option<PathSeg>, Option<PathSeg>) {
    match lead {
        Lead::None => (start, None, None),
        Lead::Arc(r) => {
            // Centres on the waste side at distance r: a quarter turn tangent to the contour.
            let c = start + side * r * perp(t0);
            let e = c - r * t0;
            let c1 = end + side * r * perp(t1);
            let x = c1 + r * t1;
            (
                e,
                Some(PathSeg::Arc(Arc::from_center_points(
                    c,
                    e,
                    start,
                    side > 0.0,
                ))),
                Some(PathSeg::Arc(Arc::from_center_points(
                    c1,
                    end,
                    x,
                    side > 0.0,
                ))),
            )
        }
    }
}

/// Fraction of a lead, at its contour end, tested only against the contour's segments that
/// do not end at the touch point: there the lead touches the contour tangentially by
/// construction, and flattened or rounded the two may meet.
const LEAD_TOUCH_FRACTION: f64 = 0.05;

/// Fraction of a lead left out at its touch point when testing it against the contour: the
/// contour's end segments and the lead share that point exactly, which is no crossing.
const LEAD_END_BACKOFF: f64 = 1e-9;

/// True when neither lead meets the contour (exact segment tests on flattenings within
/// 1e-3 of the lead's length), apart from the tangential touch at the contour end, nor any
/// of the operation's `others` contours (a lead into a narrow gap between two pieces of a
/// board crossed the piece beyond it). The lead's stretch next to the contour
/// ([`LEAD_TOUCH_FRACTION`]) is tested against every segment but the contour's first and
/// last (a board's lead-out crossed the contour 0.2 mm after its start, where the contour
/// turned sharply toward the waste side).
fn leads_clear(
    leads: &(DVec2, Option<PathSeg>, Option<PathSeg>),
    path: &Path,
    others: &[&Path],
) -> bool {
    let tol = |s: &PathSeg| (s.length(LENGTH_ACCURACY) * 1e-3).max(1e-9);
    let flat_tol = leads.1.as_ref().map(tol).unwrap_or(1e-3);
    // The contour's chords, segment by segment; `inner` leaves out the chords of the first
    // and last segments (those ending at the touch point).
    let mut ring: Vec<[DVec2; 2]> = Vec::new();
    let (mut first_end, mut last_start) = (0, 0);
    for (k, seg) in path.segs.iter().enumerate() {
        if k + 1 == path.segs.len() {
            last_start = ring.len();
        }
        let f = seg.flatten(flat_tol);
        ring.extend(f.windows(2).map(|r| [r[0], r[1]]));
        if k == 0 {
            first_end = ring.len();
        }
    }
    let inner = ring.get(first_end..last_start).unwrap_or(&[]);
    // Only segments whose bounding box meets the lead's can meet it (closed boxes, so
    // touching counts); the exact predicate decides the rest. O(n + k·m) instead of O(n·m).
    let hits = |pts: &[DVec2], contour: &[[DVec2; 2]]| {
        let lead = Aabb::from_points(pts);
        let mut near: Vec<[DVec2; 2]> = contour
            .iter()
            .filter(|r| Aabb::from_corners(r[0], r[1]).intersects(&lead))
            .copied()
            .collect();
        // The other contours' segments near the lead, flattened one by one.
        for seg in others.iter().flat_map(|o| &o.segs) {
            if seg.bounding_box().intersects(&lead) {
                let f = seg.flatten(flat_tol);
                near.extend(f.windows(2).map(|r| [r[0], r[1]]));
            }
        }
        pts.windows(2).any(|w| {
            near.iter()
                .any(|r| crate::geom::predicates::segments_intersect(w[0], w[1], r[0], r[1]))
        })
    };
    let part = |s: &PathSeg, a: f64, b: f64| -> Vec<DVec2> {
        let n = ((s.length(LENGTH_ACCURACY) / tol(s)).ceil() as usize).clamp(2, 4096);
        (0..=n)
            .map(|i| s.eval(a + (b - a) * i as f64 / n as f64))
            .collect()
    };
    // A lead from `far` (its free end) to `touch` (on the contour), as lead parameters.
    let clear = |s: &PathSeg, far: f64, touch: f64| {
        let split = far + (touch - far) * (1.0 - LEAD_TOUCH_FRACTION);
        // The touch point itself is left out: the contour's first and last segments end
        // there, and the lead's end there is shared with them.
        let end = touch - (touch - far) * LEAD_END_BACKOFF;
        !hits(&part(s, far, split), &ring) && !hits(&part(s, split, end), inner)
    };
    let lead_in_ok = leads
        .1
        .as_ref()
        .is_none_or(|s| clear(s, 0.0, 1.0) && !grazes(s, s.end(), path));
    let lead_out_ok = leads
        .2
        .as_ref()
        .is_none_or(|s| clear(s, 1.0, 0.0) && !grazes(s, s.start(), path));
    lead_in_ok && lead_out_ok
}

/// Largest lead radius, as a fraction of the radius R of a contour arc it touches from
/// inside (the contour curving toward the waste side at the touch point), that the lead may
/// have. Lead and contour are tangent there and part by s²/2·(1/r − 1/R) at arc length s,
/// so they stay within a flattening or rounding error f of each other for
/// s < √(2f / (1/r − 1/R)): with r ≤ R/2 that is at most √2 times the stretch along a
/// straight contour, where it is √(2fr). Nearer, flattened or rounded, the two cross (a
/// laser board's later passes crossed its first lead-in at a concave corner).
const GRAZE_RATIO: f64 = 0.5;

/// Whether the lead arc `lead`, tangent to the closed or open `path` at `touch` (the
/// path's start or end), lies in a contour arc's circle that is less than 1/[`GRAZE_RATIO`]
/// times larger.
fn grazes(lead: &PathSeg, touch: DVec2, path: &Path) -> bool {
    let PathSeg::Arc(l) = lead else {
        return false;
    };
    let ends = [path.segs.first(), path.segs.last()];
    ends.into_iter().flatten().any(|s| match s {
        PathSeg::Arc(a) => {
            let at_touch = a.p0().distance(touch).min(a.p1().distance(touch));
            at_touch <= 1e-9 * (1.0 + a.radius)
                && (a.center - touch).dot(l.center - touch) > 0.0
                && l.radius > GRAZE_RATIO * a.radius
        }
        _ => false,
    })
}

/// Sine of the turn at a closed contour's start below which the start is smooth: leads
/// tangent to the contour there lie on one circle (lines: one normal) and the checker sees
/// the path graze itself there.
const SMOOTH_START_TURN: f64 = 1e-9;

/// Largest rounding of a program's coordinates the start of a lead allows for, in design
/// units: the fourth decimal of an inch program is 2.5 µm, a mm program rounds to 0.5 µm
/// (a design in inches gets a larger margin than it needs).
const START_ROUNDING: f64 = 2e-3;

/// Shortest segment next to which a lead of radius (or length) `size` starts: √(2·size·q)
/// for the rounding q = [`START_ROUNDING`]. Rounding turns a segment of length L by up to
/// q/L, which moves its point at distance s from the start by q·s/L sideways, while a lead
/// of radius R parts from the contour's tangent by s²/(2R): the two stay apart along the
/// whole segment when L² ≥ 2Rq. (A 5 µm arc at the start of a letter's outline, rounded
/// to 1 µm, turned 8° and crossed the lead-out of the last pass.)
fn lead_start_segment(size: f64) -> f64 {
    (2.0 * size * START_ROUNDING).sqrt()
}

/// The closed `path` started at the middle of a segment at least `min_len` long, when it
/// starts at a corner (the sine of its turn there above [`SMOOTH_START_TURN`], or a turn
/// back) or next to a shorter segment: the nearest such segment to the start, else the
/// longest. None when the start is smooth between long segments, or the path is open. A
/// lead-in tangent to the first segment and a lead-out tangent to the last, both on the
/// waste side, cross each other's contour pass at a corner: the lead-in arrives from the
/// waste and the contour leaves along t₀, the contour arrives along t₁ and the lead-out
/// leaves to the waste, and unless t₀ = t₁ the two passes cross at the start at the angle
/// between them (a flattened outline's vertex turned 10°). CAM tools start leads on a
/// straight or smooth stretch for the same reason.
fn smooth_start(path: &Path, min_len: f64) -> Option<Path> {
    let n = path.segs.len();
    if !path.closed || n < 2 {
        return None;
    }
    let lens: Vec<f64> = path
        .segs
        .iter()
        .map(|s| s.length(LENGTH_ACCURACY))
        .collect();
    let (t0, t1) = (
        seg_tangent(&path.segs[0], 0.0),
        seg_tangent(&path.segs[n - 1], 1.0),
    );
    let smooth = t0.perp_dot(t1).abs() <= SMOOTH_START_TURN && t0.dot(t1) > 0.0;
    if smooth && lens[0] >= min_len && lens[n - 1] >= min_len {
        return None;
    }
    // The nearest segment long enough, forward and back from the start in turn.
    let k = (0..n)
        .flat_map(|d| [d, n - 1 - d])
        .find(|&k| lens[k] >= min_len)
        .or_else(|| (0..n).max_by(|&a, &b| lens[a].total_cmp(&lens[b])))?;
    let (seg, len) = (&path.segs[k], lens[k]);
    if len <= 0.0 {
        return None;
    }
    // Split segment k at its middle: the path runs from there round to there.
    let mut segs = vec![sub_seg(seg, 0.5 * len, len, len)];
    segs.extend(path.segs[k + 1..].iter().cloned());
    segs.extend(path.segs[..k].iter().cloned());
    segs.push(sub_seg(seg, 0.0, 0.5 * len, len));
    Some(Path::new(segs, true))
}

/// The cut that runs the closed contour `path` (lines and arcs) once per level.
///
/// The cut starts at the lead-in's start on the surface (z = 0); each level plunges at the
/// contour start with the plunge feed, runs the contour (lifting to the tab top over tab
/// spans when the level is below it), and the last level runs the lead-out. Open paths are
/// run back and forth (even passes reversed) so the tool never travels without cutting.
#[cfg(test)]
pub fn contour_cut(path: &Path, opts: &CutOptions, source: Option<String>) -> Option<Cut> {
    contour_cut_leads(path, &[], opts, source).map(|(c, _)| c)
}

/// [`contour_cut`] for one of several contours of an operation, whose leads must also stay
/// clear of the `others` (the operation's other contours and the leads of the cuts made
/// before); with the lead-in and lead-out the cut runs (none, one or two segments).
pub fn contour_cut_leads(
    path: &Path,
    others: &[&Path],
    opts: &CutOptions,
    source: Option<String>,
) -> Option<(Cut, Vec<PathSeg>)> {
    let lead_size = match opts.lead {
        Lead::None => None,
        Lead::Arc(r) => Some(r),
    };
    let smoothed = lead_size.and_then(|size| smooth_start(path, lead_start_segment(size)));
    let path = smoothed.as_ref().unwrap_or(path);
    let start = path.start()?;
    let total: f64 = path.segs.iter().map(|s| s.length(LENGTH_ACCURACY)).sum();
    if total <= 0.0 {
        return None;
    }
    let t0 = seg_tangent(&path.segs[0], 0.0);
    let last = &path.segs[path.segs.len() - 1];
    let t1 = seg_tangent(last, 1.0);
    let end = last.end();
    let side: f64 = if opts.waste_left { 1.0 } else { -1.0 };
    let mv = |kind, p: DVec2, z: f64, feed: f64| Move {
        kind,
        to: DVec3::new(p.x, p.y, z),
        feed,
        power: opts.power,
    };

    // Leads on the waste side; where a lead would run into the contour (a concave
    // stretch tighter than the lead), it is halved until clear, and left out after
    // `LEAD_HALVINGS` tries.
    let mut lead = opts.lead;
    let mut leads = lead_geometry(lead, side, start, t0, end, t1);
    for _ in 0..LEAD_HALVINGS {
        if leads_clear(&leads, path, others) {
            break;
        }
        lead = match lead {
            Lead::Arc(r) => Lead::Arc(r / 2.0),
            Lead::None => Lead::None,
        };
        leads = lead_geometry(lead, side, start, t0, end, t1);
    }
    if !leads_clear(&leads, path, others) {
        leads = lead_geometry(Lead::None, side, start, t0, end, t1);
    }
    let (entry, lead_in, lead_out) = leads;

    // Tab spans along the contour's arc length.
    let tab_spans: Vec<(f64, f64)> = match opts.tabs {
        Some(t) if t.count > 0 && path.closed => (0..t.count)
            .map(|k| {
                let mid = (k as f64 + 0.5) * total / t.count as f64;
                (
                    (mid - t.width / 2.0).max(0.0),
                    (mid + t.width / 2.0).min(total),
                )
            })
            .collect(),
        _ => Vec::new(),
    };
    let final_z = opts.levels.iter().copied().fold(0.0, f64::min);
    let tab_top = opts.tabs.map(|t| final_z + t.height);
    // Cuts at the surface (lasers) cannot lift: their tabs are bridges with the beam off.
    let laser_bridges = final_z >= 0.0;
    let marks: Vec<f64> = tab_spans.iter().flat_map(|&(a, b)| [a, b]).collect();
    let pieces = split_at_lengths(path, &marks);
    let in_tab = |s_mid: f64| tab_spans.iter().any(|&(a, b)| s_mid > a && s_mid < b);

    let mut moves = Vec::new();
    let n_levels = opts.levels.len();
    for (li, &z) in opts.levels.iter().enumerate() {
        let forward = path.closed || li % 2 == 0;
        let here = if forward { start } else { end };
        if li == 0 {
            if let Some(l) = &lead_in {
                moves.push(mv(MoveKind::Line, entry, z, opts.plunge_feed));
                moves.push(move_along(l, z, opts.feed, opts.power));
            } else {
                moves.push(mv(MoveKind::Line, here, z, opts.plunge_feed));
            }
        } else if opts.levels[li - 1] == z {
            // Another pass at the same level (a laser cutting thick stock): the tool goes
            // off and on again in place, so each pass is a contour of its own and the
            // second does not continue the first as one cut retracing itself.
            moves.push(mv(MoveKind::Rapid, here, z, opts.feed));
        } else {
            moves.push(mv(MoveKind::Line, here, z, opts.plunge_feed));
        }
        let mut cur_z = z;
        let run: Vec<(PathSeg, f64)> = if forward {
            pieces.clone()
        } else {
            pieces
                .iter()
                .rev()
                .map(|(s, _)| (s.reversed(), 0.0))
                .collect()
        };
        for (seg, s0) in &run {
            let len = seg.length(LENGTH_ACCURACY);
            let on_tab = forward && in_tab(s0 + len / 2.0);
            if laser_bridges && on_tab {
                // A laser leaves a tab as a bridge: the beam is off across it.
                moves.push(move_along(seg, cur_z, opts.feed, 0.0));
                continue;
            }
            let want_z = match tab_top {
                Some(top) if on_tab && z < top => top,
                _ => z,
            };
            if want_z != cur_z {
                let p = seg.start();
                let feed = if want_z > cur_z {
                    opts.feed
                } else {
                    opts.plunge_feed
                };
                moves.push(mv(MoveKind::Line, p, want_z, feed));
                cur_z = want_z;
            }
            moves.push(move_along(seg, cur_z, opts.feed, opts.power));
        }
        if cur_z != z {
            let p = if forward { end } else { start };
            moves.push(mv(MoveKind::Line, p, z, opts.plunge_feed));
        }
        if li + 1 == n_levels
            && let Some(l) = &lead_out
            && (forward || !path.closed)
        {
            moves.push(move_along(l, z, opts.feed, opts.power));
        }
    }
    let leads_run = lead_in.into_iter().chain(lead_out).collect();
    Some((
        Cut {
            source,
            group: None,
            start: DVec3::new(entry.x, entry.y, 0.0),
            moves,
        },
        leads_run,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_path(s: f64) -> Path {
        Path::polyline(
            &[
                DVec2::new(0.0, 0.0),
                DVec2::new(s, 0.0),
                DVec2::new(s, s),
                DVec2::new(0.0, s),
            ],
            true,
        )
    }

    fn opts() -> CutOptions {
        CutOptions {
            feed: 1000.0,
            plunge_feed: 300.0,
            power: 1.0,
            levels: step_levels(6.0, 2.5),
            tabs: None,
            lead: Lead::None,
            waste_left: false,
        }
    }

    #[test]
    fn levels_step_evenly_to_depth() {
        assert_eq!(step_levels(6.0, 2.5), vec![-2.0, -4.0, -6.0]);
        assert_eq!(step_levels(5.0, 2.5), vec![-2.5, -5.0]);
        assert_eq!(step_levels(0.0, 1.0), vec![0.0]);
    }

    #[test]
    fn passes_at_one_level_are_parted_by_a_travel_in_place() {
        let o = CutOptions {
            levels: vec![0.0, 0.0, 0.0],
            ..opts()
        };
        let c = contour_cut(&square_path(10.0), &o, None).unwrap();
        let rapids: Vec<&Move> = c
            .moves
            .iter()
            .filter(|m| m.kind == MoveKind::Rapid)
            .collect();
        // One break before each pass after the first, at the contour's start, no travel.
        assert_eq!(rapids.len(), 2);
        assert!(rapids.iter().all(|m| m.to == DVec3::ZERO));
        // Different levels are joined by a plunge as before.
        let c = contour_cut(&square_path(10.0), &opts(), None).unwrap();
        assert!(c.moves.iter().all(|m| m.kind != MoveKind::Rapid));
    }

    #[test]
    fn passes_cut_the_contour_once_per_level() {
        let c = contour_cut(&square_path(10.0), &opts(), None).unwrap();
        // Per level: one plunge plus four sides.
        assert_eq!(c.moves.len(), 3 * 5);
        let cutting: f64 = c
            .moves
            .windows(2)
            .filter(|w| w[1].to.z == w[0].to.z)
            .map(|w| (w[1].to - w[0].to).length())
            .sum();
        // Three levels × perimeter 40 at constant z.
        assert!((cutting - 120.0).abs() < 1e-9);
        assert_eq!(c.moves.last().unwrap().to.z, -6.0);
    }

    #[test]
    fn tabs_lift_only_on_deep_passes_and_only_over_tabs() {
        let mut o = opts();
        o.tabs = Some(Tabs {
            count: 4,
            width: 2.0,
            height: 3.0,
        });
        let c = contour_cut(&square_path(10.0), &o, None).unwrap();
        // Tab top −3: the −2 pass is above it; the −4 and −6 passes lift to −3 over 4 tabs.
        let at_top: Vec<&Move> = c
            .moves
            .iter()
            .filter(|m| m.to.z == -3.0 && matches!(m.kind, MoveKind::Line))
            .collect();
        // Per deep pass and tab: lift, run across the tab at −3.
        assert_eq!(at_top.len(), 2 * 4 * 2);
        // The lifted runs are exactly the tab width.
        let mut lifted = 0.0;
        let mut prev = c.start;
        for m in &c.moves {
            if m.to.z == -3.0 && prev.z == -3.0 {
                lifted += (m.to - prev).length();
            }
            prev = m.to;
        }
        assert!((lifted - 2.0 * 4.0 * 2.0).abs() < 1e-9, "{lifted}");
    }

    #[test]
    fn laser_tabs_are_beam_off_bridges_at_the_surface() {
        let mut o = opts();
        o.levels = vec![0.0, 0.0];
        o.tabs = Some(Tabs {
            count: 2,
            width: 3.0,
            height: 1.0,
        });
        let c = contour_cut(&square_path(10.0), &o, None).unwrap();
        assert!(c.moves.iter().all(|m| m.to.z == 0.0));
        let mut off = 0.0;
        let mut prev = c.start;
        for m in &c.moves {
            if m.power == 0.0 {
                off += (m.to - prev).length();
            }
            prev = m.to;
        }
        // Two passes × two tabs × 3 mm.
        assert!((off - 12.0).abs() < 1e-9, "{off}");
    }

    #[test]
    fn leads_shrink_in_tight_concave_corners() {
        // A fin 0.4 wide and 5 long sticking into the waste next to the contour start: a
        // lead arc of radius 4 would run into its wall at x = 5.6; radius 0.5 fits.
        let p = |x: f64, y: f64| DVec2::new(x, y);
        // Clockwise outline (material right of travel, waste left = outside): start in the
        // middle of the bottom side, next to a notch that sticks down into the waste.
        let pts = [
            p(5.0, 0.0),
            p(0.0, 0.0),
            p(0.0, 10.0),
            p(10.0, 10.0),
            p(10.0, 0.0),
            p(6.0, 0.0),
            p(6.0, -5.0),
            p(5.6, -5.0),
            p(5.6, 0.0),
        ];
        let path = Path::new(
            (0..pts.len())
                .map(|i| PathSeg::Line(Line::new(pts[i], pts[(i + 1) % pts.len()])))
                .collect(),
            true,
        );
        let mut o = opts();
        o.levels = vec![0.0];
        o.lead = Lead::Arc(4.0);
        o.waste_left = true;
        let c = contour_cut(&path, &o, None).unwrap();
        let MoveKind::Arc { center, .. } = c.moves[1].kind else {
            panic!("expected a lead-in arc")
        };
        let r = center.distance(p(5.0, 0.0));
        assert!((0.5 - 1e-12..4.0).contains(&r), "lead radius {r}");
        // The lead stays clear of the fin's wall at x = 5.6.
        assert!(c.start.x < 5.6 && center.x + r < 5.6);
    }

    #[test]
    fn lead_arcs_stay_well_inside_a_concave_contour_arc() {
        // A circle of radius 6 with the waste inside (a hole's wall): the contour curves
        // toward the waste everywhere. A lead of radius 4 touches it from inside and stays
        // within a flattening error of it for a long stretch: halved to 2 (≤ 6/2). A lead of
        // 2.5 is kept, and so is 4 when the waste is outside (the contour curves away).
        let half = |a0: f64| PathSeg::Arc(Arc::new(DVec2::ZERO, 6.0, a0, std::f64::consts::PI));
        let path = Path::new(vec![half(0.0), half(std::f64::consts::PI)], true);
        for (lead, waste_left, want) in [(4.0, true, 2.0), (2.5, true, 2.5), (4.0, false, 4.0)] {
            let mut o = opts();
            o.levels = vec![0.0];
            o.lead = Lead::Arc(lead);
            o.waste_left = waste_left;
            let c = contour_cut(&path, &o, None).unwrap();
            let MoveKind::Arc { center, .. } = c.moves[1].kind else {
                panic!("expected a lead-in arc")
            };
            let r = center.distance(DVec2::new(6.0, 0.0));
            assert!((r - want).abs() < 1e-12, "lead {lead}: radius {r}");
        }
    }

    #[test]
    fn leads_stay_clear_of_the_other_contours() {
        // The square's lead-in of radius 2 lies below the middle of its first side (waste
        // outside). A second contour 1.5 below that side is in its way: halved to 1.
        let mut o = opts();
        o.levels = vec![0.0];
        o.lead = Lead::Arc(2.0);
        o.waste_left = false;
        let square = square_path(10.0);
        let below = Path::polyline(&[DVec2::new(-5.0, -1.5), DVec2::new(15.0, -1.5)], false);
        let radius = |c: &Cut| match c.moves[1].kind {
            MoveKind::Arc { center, .. } => center.distance(DVec2::new(5.0, 0.0)),
            _ => 0.0,
        };
        let alone = contour_cut(&square, &o, None).unwrap();
        assert!((radius(&alone) - 2.0).abs() < 1e-12);
        let among = |other: &Path| contour_cut_leads(&square, &[other], &o, None).unwrap().0;
        let among_below = among(&below);
        assert!(
            (radius(&among_below) - 1.0).abs() < 1e-12,
            "{}",
            radius(&among_below)
        );
        // A contour far away changes nothing.
        let far = Path::polyline(&[DVec2::new(-5.0, -30.0), DVec2::new(15.0, -30.0)], false);
        assert_eq!(among(&far), alone);
    }

    #[test]
    fn arc_lead_in_is_tangent_and_on_the_waste_side() {
        let mut o = opts();
        o.levels = vec![0.0];
        o.lead = Lead::Arc(2.0);
        o.waste_left = false;
        // Counter-clockwise square from its corner (0,0): the right of travel is outside.
        // The corner is no place for tangent leads, so the cut starts at the middle of
        // the first side, (5,0).
        let c = contour_cut(&square_path(10.0), &o, None).unwrap();
        let mid = DVec2::new(5.0, 0.0);
        // Entry is outside the square (y < 0 below the first side).
        assert!(c.start.y < 0.0, "{:?}", c.start);
        match c.moves[1].kind {
            MoveKind::Arc { center, ccw } => {
                assert!((center - DVec2::new(5.0, -2.0)).length() < 1e-12);
                // Tangent at the contour start is +x: the radius there is vertical.
                assert!((c.moves[1].to.truncate() - mid).length() < 1e-12);
                // A quarter turn that arrives along +x (not the long way round).
                let a = Arc::from_center_points(center, c.start.truncate(), mid, ccw);
                assert!((a.sweep.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
                assert!((a.tangent(1.0) - DVec2::X).length() < 1e-12);
            }
            other => panic!("expected an arc lead-in, got {other:?}"),
        }
        // The contour runs round once, from (5,0) back to (5,0): 40 long.
        let contour: f64 = c.moves[2..c.moves.len() - 1]
            .iter()
            .scan(mid, |at, m| {
                let d = at.distance(m.to.truncate());
                *at = m.to.truncate();
                Some(d)
            })
            .sum();
        assert!((contour - 40.0).abs() < 1e-9, "{contour}");
        // A lead-out arc ends the cut, also outside, leaving (5,0) along +x with a quarter
        // turn on the lead-in's circle.
        let last = c.moves.last().unwrap();
        let MoveKind::Arc { center, ccw } = last.kind else {
            panic!("expected an arc lead-out, got {:?}", last.kind)
        };
        assert!(last.to.y < 0.0);
        assert!((center - DVec2::new(5.0, -2.0)).length() < 1e-12);
        let a = Arc::from_center_points(center, mid, last.to.truncate(), ccw);
        assert!((a.sweep.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!((a.tangent(0.0) - DVec2::X).length() < 1e-12);
    }
}
