//! The refinement state of one stroke and its phases (kruppa-2023 Sec. 4.2–4.3): the
//! parameter sequence, the segment marks, insertion with the admissibility tests, and the
//! assembly of the sided outline.

use super::bounds::{KeyMap, Mode, SideSkin, param_bits};
use super::{CircleUse, DbscSkinError, DbscSkinOptions, Phase, adm_opts, not_admissible, overlaps};
use crate::dbsc::{DiskBSpline, EnvelopeLoop, Side, SpanPoly};
use crate::geom::intersect::{
    path_self_intersections, path_self_intersects_changed, paths_intersections,
};
use crate::geom::{Circle, CubicBez, DVec2, Path, PathSeg};
use crate::skin::bits_hash::{BitsMap, BitsSet};
use crate::skin::hausdorff::{HausdorffBounds, Work};
use crate::skin::outline::outline_from_skins;
use crate::skin::touching::touching_points_with;
use crate::skin::touching::triplet_touching;
use crate::skin::{SkinError, Skins, TouchingPoints, bezier_skins, check_admissible};
use std::cell::RefCell;

/// Relative tolerance of the radical centre of phase 3 (kruppa-2023 Sec. 4.3): centres
/// collinear within it have none ([`Circle::radical_centre`]).
const RADICAL_CENTRE_REL: f64 = 1e-14;

/// Refinement state of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Mark {
    Open,
    Finished,
    Stopped(Phase),
}

pub(super) struct State<'a> {
    pub(super) c: &'a DiskBSpline,
    pub(super) closed: bool,
    pub(super) hi: f64,
    pub(super) opts: DbscSkinOptions,
    pub(super) params: Vec<f64>,
    pub(super) uses: Vec<CircleUse>,
    /// Per segment: mark and weight of eq. 25.
    pub(super) marks: Vec<Mark>,
    pub(super) weights: Vec<f64>,
    /// Error bounds by (arc, span, side, mode).
    pub(super) cache: RefCell<KeyMap<HausdorffBounds>>,
    /// Decide-mode keys whose bound the quick proof of D_H ≤ ε − gap gave in a run that
    /// never ran out of work, with the work spent: the Compare bound of the same arc and
    /// span is that run again (same steps, same bounds), taken from here instead.
    pub(super) quick: RefCell<KeyMap<usize>>,
    /// The outline contours of the last insertion phase 3 kept, which
    /// [`State::self_intersects`] found free of crossings: the final outline when no
    /// insertion followed (rejected ones restore the state), so its safety net is known.
    pub(super) clear: RefCell<Option<Vec<Path>>>,
    /// Envelope loops of the curve (kruppa-2023 Sec. 3).
    pub(super) loops: Vec<EnvelopeLoop>,
    /// Refinement steps left for the Hausdorff bounds of the whole skinning.
    pub(super) work: RefCell<Work>,
    /// The curve's knot spans in Bernstein form, shared by every envelope segment.
    pub(super) spans: Vec<SpanPoly>,
    /// The circles ⟨q(u); r(u)⟩ evaluated so far, by the bits of u: the sequence is
    /// evaluated again for every admissibility test and skin, and most of its parameters
    /// stay from pass to pass.
    pub(super) circles: RefCell<BitsMap<u64, Circle>>,
    /// Parameter sequences (by their bits) whose circles passed [`check_admissible`]: the
    /// skin of a pass's sequence need not test again what its insertion test showed.
    pub(super) admissible: RefCell<BitsSet<Vec<u64>>>,
    /// The last [`State::skin_sides`] with the bits of its parameters and the circle uses:
    /// a pass skins its sequence for the bounds of two modes and for the outline test.
    pub(super) sides: RefCell<Option<SidesMemo>>,
    /// The touching points of each triplet skinned so far (or none), by the bits of its
    /// three parameters.
    pub(super) touching: RefCell<BitsMap<[u64; 3], Option<TouchingPoints>>>,
}

/// A sequence's parameter bits and circle uses with its two skins ([`State::sides`]).
pub(super) type SidesMemo = ((Vec<u64>, Vec<CircleUse>), [SideSkin; 2]);

impl State<'_> {
    pub(super) fn circles_of(&self, ps: &[f64]) -> Vec<Circle> {
        let mut memo = self.circles.borrow_mut();
        ps.iter()
            .map(|&t| {
                *memo
                    .entry(t.to_bits())
                    .or_insert_with(|| self.c.circle_at(t))
            })
            .collect()
    }

    /// End parameter of segment i.
    pub(super) fn seg_end(&self, i: usize) -> f64 {
        self.params.get(i + 1).copied().unwrap_or(self.hi)
    }

    pub(super) fn n_segments(&self) -> usize {
        if self.closed {
            self.params.len()
        } else {
            self.params.len() - 1
        }
    }

    pub(super) fn admissible_with(&self, extra: &[f64]) -> bool {
        self.admissible_moved(None, extra)
    }

    /// Admissibility of the circles of `params` with circle `moved.0` at parameter `moved.1`
    /// instead, plus the circles at `extra`.
    pub(super) fn admissible_moved(&self, moved: Option<(usize, f64)>, extra: &[f64]) -> bool {
        let mut ps: Vec<f64> = self.params.clone();
        if let Some((k, u)) = moved {
            ps[k] = u;
        }
        ps.extend_from_slice(extra);
        ps.sort_by(f64::total_cmp);
        ps.dedup();
        self.admissible_params(&ps).is_ok()
    }

    /// [`check_admissible`] of the circles at `ps`; a sequence that passed once is not
    /// tested again ([`State::admissible`]).
    pub(super) fn admissible_params(&self, ps: &[f64]) -> Result<(), SkinError> {
        let key = param_bits(ps);
        if self.admissible.borrow().contains(&key) {
            return Ok(());
        }
        check_admissible(&self.circles_of(ps), self.closed, &adm_opts())?;
        self.admissible.borrow_mut().insert(key);
        Ok(())
    }

    pub(super) fn insert(&mut self, i: usize, u: f64) {
        self.params.insert(i + 1, u);
        self.uses.insert(i + 1, CircleUse::Both);
        self.marks[i] = Mark::Open;
        self.marks.insert(i + 1, Mark::Open);
        self.weights[i] = 0.5;
        self.weights.insert(i + 1, 0.5);
    }

    /// Parameters of the circles used on `side`.
    pub(super) fn side_params(&self, side: Side) -> Vec<f64> {
        self.params
            .iter()
            .zip(&self.uses)
            .filter(|(_, u)| u.on(side))
            .map(|(&t, _)| t)
            .collect()
    }

    /// The left and the right skin: per side its circles' parameters and arcs. While both
    /// sides skin the same circles (every circle BOTH, phases 1 and 2; a LEFT or RIGHT
    /// circle is on one side only) one skinning of the sequence gives both, and the
    /// sequence must be admissible: the test `skin_circles` would make (same options, same
    /// error), skipped for a sequence that passed before. With one-sided circles (phase 3)
    /// one side's sequence may break the admissibility of the other's, so none is tested.
    pub(super) fn skin_sides(&self) -> [SideSkin; 2] {
        let key = (param_bits(&self.params), self.uses.clone());
        if let Some((k, sides)) = self.sides.borrow().as_ref()
            && *k == key
        {
            return sides.clone();
        }
        let sides = self.skin_sides_anew();
        *self.sides.borrow_mut() = Some((key, sides.clone()));
        sides
    }

    /// [`State::skin_sides`] computed.
    fn skin_sides_anew(&self) -> [SideSkin; 2] {
        let (pl, pr) = (self.side_params(Side::Left), self.side_params(Side::Right));
        if pl == pr {
            let skins = self
                .admissible_params(&pl)
                .and_then(|()| self.skin_both_arcs(&pl));
            return match skins {
                Ok((left, right)) => [Ok((pl.clone(), left)), Ok((pr, right))],
                Err(e) => [Err(e.clone()), Err(e)],
            };
        }
        [(Side::Left, pl), (Side::Right, pr)].map(|(side, ps)| {
            let (left, right) = self.skin_both_arcs(&ps)?;
            let arcs = match side {
                Side::Left => left,
                Side::Right => right,
            };
            Ok((ps, arcs))
        })
    }

    /// The left and the right skin arcs of the circles at `ps` ([`super::skin_circles`]
    /// without its admissibility test: [`State::skin_sides`] makes that test where it
    /// applies), each triplet's touching points kept by the bits of its three parameters
    /// ([`State::touching`]): an insertion changes the triplets around it only.
    fn skin_both_arcs(&self, ps: &[f64]) -> Result<(Vec<CubicBez>, Vec<CubicBez>), SkinError> {
        let circles = self.circles_of(ps);
        let n = ps.len();
        let rel_tol = adm_opts().rel_tol;
        let mut memo = self.touching.borrow_mut();
        let tp = touching_points_with(&circles, self.closed, |i| {
            let (a, b) = ((i + n - 1) % n, (i + 1) % n);
            let key = [ps[a].to_bits(), ps[i].to_bits(), ps[b].to_bits()];
            *memo.entry(key).or_insert_with(|| {
                triplet_touching(&circles[a], &circles[i], &circles[b], rel_tol).map(|t| t.points)
            })
        })?;
        let s = bezier_skins(&circles, &tp, self.closed)?;
        Ok((s.left, s.right))
    }

    pub(super) fn met(&self, h: &HausdorffBounds) -> bool {
        h.upper <= self.opts.epsilon
    }

    /// Initialisation (eq. 19: the knot circles must be admissible), then phase 1 (paired
    /// insertions) and phase 2 (midpoints) until no pass inserts.
    pub(super) fn phases_one_two(&mut self) -> Result<(), DbscSkinError> {
        if let Err(e) = self.admissible_params(&self.params) {
            return Err(not_admissible(&self.params, self.hi, self.closed, e));
        }
        while self.pass(true)? {}
        for m in self.marks.iter_mut() {
            if *m == Mark::Stopped(Phase::One) {
                *m = Mark::Open;
            }
        }
        while self.pass(false)? {}
        Ok(())
    }

    /// One pass of phase 1 (`paired`) or phase 2; returns whether anything was inserted.
    pub(super) fn pass(&mut self, paired: bool) -> Result<bool, DbscSkinError> {
        let phase = if paired { Phase::One } else { Phase::Two };
        let err = self.errors(Mode::Decide)?;
        // Marks from the errors of this pass (segments are re-opened by neighbours'
        // insertions, which move their touching points).
        for (i, e) in err.iter().enumerate() {
            if self.met(&e[0]) && self.met(&e[1]) {
                self.marks[i] = Mark::Finished;
            } else if self.marks[i] == Mark::Finished {
                self.marks[i] = Mark::Open;
            }
        }
        let mut inserted = false;
        // The circle this pass inserted last, if it ends the segment before `i`: its index in
        // `params`, its segment (u_{p+i}, u_{p+i+1}) and weight, for the push-back.
        let mut last: Option<(usize, f64, f64, f64)> = None;
        let mut i = 0;
        while i < self.marks.len() {
            if self.marks[i] != Mark::Open || self.params.len() >= self.opts.max_circles {
                i += 1;
                continue;
            }
            let (u0, u1) = (self.params[i], self.seg_end(i));
            // The next segment (u_{i+1}, u_{i+2}) of eq. 24; for closed strokes the last
            // segment's successor is the first one, starting at u_0 ≡ hi.
            let next = if i + 1 < self.n_segments() {
                Some((u1, self.seg_end(i + 1), i + 1))
            } else if self.closed && self.n_segments() > 1 {
                Some((self.params[0], self.seg_end(0), 0))
            } else {
                None
            };
            let mut found = None;
            let mut pushed = None;
            if paired {
                // The previous insertion of this pass, when it is the circle that starts this
                // segment's predecessor: it may be pushed back (below).
                let prev = last.filter(|&(k, ..)| k + 1 == i);
                let w_start = self.weights[i];
                let w2_start = next.map_or(0.5, |n| self.weights[n.2]);
                let mut w2_end;
                // First the weights of eq. 25 alone; then, as kruppa-2023 Sec. 4.2 continues,
                // with the previous insertion pushed back towards its own segment start (its
                // weight halved each time), since halving this segment's weights moves c*
                // towards that circle and can break the previous insertion's admissibility.
                let mut w_prev = prev.map_or(0.0, |p| p.3);
                'push: loop {
                    let moved = prev
                        .filter(|_| self.opts.push_back && w_prev < prev.map_or(0.0, |p| p.3))
                        .map(|(k, a, b, _)| (k, (1.0 - w_prev) * a + w_prev * b));
                    let (mut w, mut w2) = (w_start, w2_start);
                    while w >= self.opts.min_weight && w2 >= self.opts.min_weight {
                        let us = (1.0 - w) * u0 + w * u1;
                        let mut extra = vec![us];
                        if let Some((a, b, _)) = next {
                            extra.push(w2 * a + (1.0 - w2) * b);
                        }
                        // A pushed-back circle is kept only if the sequence it leaves, with
                        // c* alone (without the look-ahead c**), is admissible as well.
                        if us > u0
                            && us < u1
                            && self.admissible_moved(moved, &extra)
                            && (moved.is_none() || self.admissible_moved(moved, &[us]))
                        {
                            found = Some((us, w));
                            pushed = moved;
                            break;
                        }
                        w *= 0.5;
                        w2 *= 0.5;
                    }
                    w2_end = w2;
                    w_prev *= 0.5;
                    if found.is_some()
                        || !self.opts.push_back
                        || prev.is_none()
                        || w_prev < self.opts.min_weight
                    {
                        break 'push;
                    }
                }
                // The halved partner weight is kept for that segment (kruppa-2023 Sec. 4.2).
                if let Some((_, _, k)) = next {
                    self.weights[k] = w2_end.max(self.opts.min_weight);
                }
            } else {
                let us = 0.5 * (u0 + u1);
                if us > u0 && us < u1 && self.admissible_with(&[us]) {
                    found = Some((us, 0.5));
                }
            }
            match found {
                Some((us, w)) => {
                    if let Some((k, u)) = pushed {
                        self.params[k] = u;
                        self.marks[k - 1] = Mark::Open;
                        self.marks[k] = Mark::Open;
                    }
                    self.insert(i, us);
                    last = Some((i + 1, u0, u1, w));
                    inserted = true;
                    i += 2;
                }
                None => {
                    self.marks[i] = Mark::Stopped(phase);
                    last = None;
                    i += 1;
                }
            }
        }
        Ok(inserted)
    }

    pub(super) fn outline(&self) -> Result<SidedOutline, SkinError> {
        let [left_side, right_side] = self.skin_sides();
        let (left_params, left) = left_side?;
        let (right_params, right) = right_side?;
        let contours = assemble_outline(&self.circles_of(&self.params), &left, &right, self.closed);
        Ok(SidedOutline {
            left_params,
            left,
            right_params,
            right,
            contours,
        })
    }

    /// Whether the outline of the current sequence crosses itself (or cannot be made);
    /// an outline free of crossings is kept in [`State::clear`].
    pub(super) fn self_intersects(&self) -> bool {
        match self.outline() {
            Ok(o) => {
                let tol = self.opts.intersect_tol;
                let crosses = match self.clear.borrow().as_deref() {
                    Some(old) => crosses_since(old, &o.contours, tol),
                    None => outline_intersects(&o.contours, tol),
                };
                if !crosses {
                    *self.clear.borrow_mut() = Some(o.contours);
                }
                crosses
            }
            Err(_) => true,
        }
    }

    /// The neighbours of the segment (u0, u1) in the circle sequence of `side`.
    pub(super) fn side_neighbours(&self, side: Side, u0: f64, u1: f64) -> Option<(Circle, Circle)> {
        let sp = self.side_params(side);
        let prev = sp.iter().rev().find(|&&p| p <= u0).copied();
        let next = sp.iter().find(|&&p| p >= u1).copied();
        let (prev, next) = if self.closed {
            (prev.or(sp.last().copied())?, next.or(sp.first().copied())?)
        } else {
            (prev?, next?)
        };
        Some((self.c.circle_at(prev), self.c.circle_at(next)))
    }

    /// kruppa-2023 Sec. 4.3 step 2 for one side: the radical centre of (a, c*, b) lies inside
    /// c* (so c* cannot join both skins) and the `side` touching point on c* is not covered
    /// by the neighbours a, b of that side (so that skin can use c*).
    pub(super) fn one_sided_usable(&self, side: Side, u0: f64, u1: f64, m: &Circle) -> bool {
        let Some((a, b)) = self.side_neighbours(side, u0, u1) else {
            return false;
        };
        if a.radical_centre(m, &b, RADICAL_CENTRE_REL)
            .is_none_or(|s| m.power(s) >= 0.0)
        {
            return false;
        }
        self.touching_uncovered(side, u0, u1, m)
    }

    /// True when the `side` touching point on `m`, in the triplet with that side's
    /// neighbours, exists and is not covered by them (so that skin can use `m`).
    pub(super) fn touching_uncovered(&self, side: Side, u0: f64, u1: f64, m: &Circle) -> bool {
        let Some((a, b)) = self.side_neighbours(side, u0, u1) else {
            return false;
        };
        let Some(tt) = triplet_touching(&a, m, &b, adm_opts().rel_tol) else {
            return false;
        };
        let p = match side {
            Side::Left => tt.points.left,
            Side::Right => tt.points.right,
        };
        !(a.power(p) < 0.0 || b.power(p) < 0.0)
    }

    /// Phase 3 (kruppa-2023 Sec. 4.3): two-sided insertion where both sides miss ε.
    pub(super) fn phase3(&mut self) -> Result<(), DbscSkinError> {
        loop {
            let err = self.errors(Mode::Decide)?;
            let both_miss = |e: &[HausdorffBounds; 2]| !self.met(&e[0]) && !self.met(&e[1]);
            // Where both sides miss ε the choice of side below compares their upper bounds:
            // those of the full search.
            let err = if err.iter().any(both_miss) {
                self.errors(Mode::Compare)?
            } else {
                err
            };
            let mut inserted = false;
            let mut i = err.len();
            while i > 0 {
                i -= 1;
                let both_miss = !self.met(&err[i][0]) && !self.met(&err[i][1]);
                if !both_miss || self.params.len() >= self.opts.max_circles {
                    continue;
                }
                if self.marks[i] == Mark::Stopped(Phase::Three) {
                    continue;
                }
                let (u0, u1) = (self.params[i], self.seg_end(i));
                let us = 0.5 * (u0 + u1);
                if !(us > u0 && us < u1) {
                    continue;
                }
                let m = self.c.circle_at(us);
                let usable: Vec<Side> = [Side::Left, Side::Right]
                    .into_iter()
                    .filter(|&side| self.one_sided_usable(side, u0, u1, &m))
                    .collect();
                let use_ = match usable.as_slice() {
                    [Side::Left] => CircleUse::Left,
                    [Side::Right] => CircleUse::Right,
                    _ => {
                        // Extension beyond the paper: where the radical-point rule gives no
                        // side, offer c* to the side that misses ε by less when that side's
                        // envelope has no loop here (so the skin follows a real boundary)
                        // and its touching point on c* is not covered by that side's
                        // neighbours; the outline check below still decides.
                        let (lo_err, hi_err) = (err[i][0].upper, err[i][1].upper);
                        let side = if lo_err <= hi_err {
                            Side::Left
                        } else {
                            Side::Right
                        };
                        let (dlo, dhi) = self.c.domain();
                        let narrow = (u1 - u0) < MIN_PHASE3_SPAN * (dhi - dlo);
                        let looped = self
                            .loops
                            .iter()
                            .any(|l| l.side == side && overlaps(l.t_a, l.t_b, u0, u1));
                        if narrow || looped || !self.touching_uncovered(side, u0, u1, &m) {
                            self.marks[i] = Mark::Stopped(Phase::Three);
                            continue;
                        }
                        match side {
                            Side::Left => CircleUse::Left,
                            Side::Right => CircleUse::Right,
                        }
                    }
                };
                let saved = (
                    self.params.clone(),
                    self.uses.clone(),
                    self.marks.clone(),
                    self.weights.clone(),
                );
                self.insert(i, us);
                self.uses[i + 1] = use_;
                if self.self_intersects() {
                    (self.params, self.uses, self.marks, self.weights) = saved;
                    self.marks[i] = Mark::Stopped(Phase::Three);
                } else {
                    inserted = true;
                }
            }
            if !inserted {
                return Ok(());
            }
        }
    }
}

/// Phase 3 does not split segments shorter than this fraction of the domain: a guard that
/// ends one-sided refinement where a side cannot reach ε (no envelope to follow there).
pub(super) const MIN_PHASE3_SPAN: f64 = 1e-4;

/// Skins of both sides with their circle parameters and the outline contours.
pub(super) struct SidedOutline {
    pub(super) left_params: Vec<f64>,
    pub(super) left: Vec<CubicBez>,
    pub(super) right_params: Vec<f64>,
    pub(super) right: Vec<CubicBez>,
    pub(super) contours: Vec<Path>,
}

/// Outline contours of (possibly two-sided) skins by the skin outline assembly
/// ([`outline_from_skins`]). Adapter: that assembly reads the touching points of the first
/// and last circle (end caps) and the touching polygons (orientation of closed contours);
/// with two-sided skins the sides have different circle counts, so each side's touching
/// points are taken from its own arcs' start points and the shorter list is padded with its
/// last point (a repeated vertex changes no polygon area).
pub(super) fn assemble_outline(
    circles: &[Circle],
    left: &[CubicBez],
    right: &[CubicBez],
    closed: bool,
) -> Vec<Path> {
    let ends = |arcs: &[CubicBez]| -> Vec<DVec2> {
        let mut v: Vec<DVec2> = arcs.iter().map(|a| a.p0).collect();
        if !closed && let Some(last) = arcs.last() {
            v.push(last.p3);
        }
        v
    };
    let (lp, rp) = (ends(left), ends(right));
    let n = lp.len().max(rp.len());
    let pick = |v: &[DVec2], i: usize| v.get(i).or(v.last()).copied().unwrap_or(DVec2::ZERO);
    let mut touching: Vec<TouchingPoints> = (0..n)
        .map(|i| TouchingPoints {
            left: pick(&lp, i),
            right: pick(&rp, i),
        })
        .collect();
    if !closed && let (Some(l), Some(r), Some(t)) = (lp.last(), rp.last(), touching.last_mut()) {
        // The last circle's touching points end both skins.
        *t = TouchingPoints {
            left: *l,
            right: *r,
        };
    }
    let skins = Skins {
        left: left.to_vec(),
        right: right.to_vec(),
        touching,
        closed,
    };
    outline_from_skins(circles, skins).contours
}

/// Whether outline contours intersect themselves or each other (skin intersection tests).
/// Whether the outline contours cross themselves or each other within `tol`.
pub(super) fn outline_intersects(contours: &[Path], tol: f64) -> bool {
    first_crossing(contours, tol).is_some()
}

/// [`outline_intersects`] of `new`, given that `old` is free of crossings (the outline
/// before one insertion): only the pairs of segments with a changed segment are tested.
/// A segment of `new` is unchanged when `old` holds it (same bits) with the same segments
/// before and after it; two unchanged segments then were a pair of `old` in the same order
/// and adjacency, whose test found nothing. Applies to one closed contour before and after
/// whose segments are all distinct and whose unchanged segments keep their order; anything
/// else is tested whole.
pub(super) fn crosses_since(old: &[Path], new: &[Path], tol: f64) -> bool {
    let ([o], [p]) = (old, new) else {
        return outline_intersects(new, tol);
    };
    if !(o.closed && p.closed) {
        return outline_intersects(new, tol);
    }
    match changed_segments(o, p) {
        Some(changed) => path_self_intersects_changed(p, tol, &changed),
        None => outline_intersects(new, tol),
    }
}

/// The bits of a path segment (kind and every coordinate, unused slots 0).
fn seg_bits(s: &PathSeg) -> [u64; 9] {
    let (kind, vals): (u64, [f64; 8]) = match s {
        PathSeg::Line(l) => (0, [l.p0.x, l.p0.y, l.p1.x, l.p1.y, 0.0, 0.0, 0.0, 0.0]),
        PathSeg::Arc(a) => (
            1,
            [
                a.center.x, a.center.y, a.radius, a.start, a.sweep, 0.0, 0.0, 0.0,
            ],
        ),
        PathSeg::Cubic(c) => {
            let q = c.points();
            (
                2,
                [
                    q[0].x, q[0].y, q[1].x, q[1].y, q[2].x, q[2].y, q[3].x, q[3].y,
                ],
            )
        }
    };
    let mut k = [kind; 9];
    for (slot, v) in k[1..].iter_mut().zip(vals) {
        *slot = v.to_bits();
    }
    k
}

/// Per segment of the closed path `p`, whether it changed from the closed path `o`
/// ([`crosses_since`]); `None` when a path repeats a segment or the unchanged segments of
/// `p` do not keep their order in `o`.
fn changed_segments(o: &Path, p: &Path) -> Option<Vec<bool>> {
    let (ob, pb): (Vec<_>, Vec<_>) = (
        o.segs.iter().map(seg_bits).collect(),
        p.segs.iter().map(seg_bits).collect(),
    );
    let mut at: BitsMap<[u64; 9], usize> = BitsMap::default();
    for (i, k) in ob.iter().enumerate() {
        if at.insert(*k, i).is_some() {
            return None;
        }
    }
    let mut seen: BitsSet<[u64; 9]> = BitsSet::default();
    if !pb.iter().all(|k| seen.insert(*k)) {
        return None;
    }
    let (n, m) = (ob.len(), pb.len());
    if n == 0 || m == 0 {
        return None;
    }
    let mut last = None;
    let mut changed = vec![true; m];
    for (i, k) in pb.iter().enumerate() {
        let Some(&j) = at.get(k) else { continue };
        let same = ob[(j + n - 1) % n] == pb[(i + m - 1) % m] && ob[(j + 1) % n] == pb[(i + 1) % m];
        if same {
            if last.is_some_and(|l| l >= j) {
                return None;
            }
            last = Some(j);
            changed[i] = false;
        }
    }
    Some(changed)
}

/// The first crossing of the outline contours, as (contour, other contour, segment of the
/// first): a contour crossing itself first, then pairs of contours.
pub(super) fn first_crossing(contours: &[Path], tol: f64) -> Option<(usize, usize, usize)> {
    let own = contours
        .iter()
        .enumerate()
        .find_map(|(k, c)| path_self_intersections(c, tol).first().map(|h| (k, k, h.a)));
    own.or_else(|| {
        contours.iter().enumerate().find_map(|(i, a)| {
            contours
                .iter()
                .enumerate()
                .skip(i + 1)
                .find_map(|(j, b)| paths_intersections(a, b, tol).first().map(|h| (i, j, h.a)))
        })
    })
}

/// "intersects itself" or "crosses contour N" (the message of
/// [`DbscSkinError::SelfIntersection`]).
pub(super) fn crossed(contour: usize, other: usize) -> String {
    if contour == other {
        "intersects itself".into()
    } else {
        format!("crosses contour {other}")
    }
}
