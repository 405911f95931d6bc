//! The Hausdorff error bounds of a pass (kruppa-2023 eqs. 20–21): the cache of bounds by
//! skin arc and parameter interval, the shared work budget, and the bounds computed in
//! parallel before they are taken in serial order.

use super::DbscSkinError;
use super::state::State;
use crate::dbsc::Side;
use crate::geom::CubicBez;
use crate::par::prelude::*;
use crate::skin::SkinError;
use crate::skin::bits_hash::{BitsMap, BitsSet};
use crate::skin::hausdorff::{
    EnvelopeSegment, HausdorffBounds, HausdorffError, MAX_BOUND_WORK, Rejection, Work,
    skin_envelope_bounds, skin_envelope_within, skin_envelope_within_path,
};

/// What the error bounds of a pass are for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Mode {
    /// Whether each side meets ε ([`skin_envelope_within`], quick rejection without the
    /// upper bound of failing sides, which a pass never reads).
    Decide,
    /// The final report of [`ReportBounds::Decided`]: `Decide`'s bounds, with the quick
    /// rejection's upper bound for failing sides. Sides `Decide` found within ε are read
    /// from its cache (the same bounds).
    DecidedReport,
    /// As `Decide`, with the upper bounds of failing sides from the full search: phase 3
    /// compares them.
    Compare,
    /// Bounds to the gap (the final report).
    Tight,
}

pub(super) type CacheKey = ([u64; 10], usize, Mode);

/// Maps keyed by [`CacheKey`].
pub(super) type KeyMap<V> = BitsMap<CacheKey, V>;

pub(super) fn cache_key(arc: &CubicBez, t0: f64, t1: f64, side: usize, mode: Mode) -> CacheKey {
    let p = arc.points();
    let mut k = [0u64; 10];
    for (i, q) in p.iter().enumerate() {
        k[2 * i] = q.x.to_bits();
        k[2 * i + 1] = q.y.to_bits();
    }
    k[8] = t0.to_bits();
    k[9] = t1.to_bits();
    (k, side, mode)
}

/// The bound of `key` computed already: its own or, for [`Mode::DecidedReport`], one that
/// [`Mode::Decide`] found within `eps` (the same bound: the two differ only where D_H > ε).
pub(super) fn cached(
    cache: &KeyMap<HausdorffBounds>,
    key: &CacheKey,
    eps: f64,
) -> Option<HausdorffBounds> {
    cache.get(key).copied().or_else(|| {
        let decide = (key.0, key.1, Mode::Decide);
        let met = |h: &HausdorffBounds| h.upper <= eps;
        (key.2 == Mode::DecidedReport)
            .then(|| cache.get(&decide).copied().filter(met))
            .flatten()
    })
}

/// One Hausdorff bound to compute: a skin arc against the envelope on `side` over [t0, t1].
pub(super) struct BoundJob {
    key: CacheKey,
    arc: CubicBez,
    side: Side,
    t0: f64,
    t1: f64,
}

pub(super) type SideSkin = Result<(Vec<f64>, Vec<CubicBez>), SkinError>;
/// A bound computed ahead: the bounds and whether the quick proof of D_H ≤ ε − gap gave them
/// ([`skin_envelope_within_path`]), or the error; and the work it spent.
pub(super) type Speculative = (Result<(HausdorffBounds, bool), HausdorffError>, usize);

/// Runs `bound` in parallel (rayon) on every distinct uncached (arc, span) of the sides up
/// to the first side that failed and that `reused` does not take from an earlier bound,
/// keyed by cache key; the caller decides in serial order which results stand (a pure
/// function of the job and the budget, so thread count and scheduling cannot change them).
pub(super) fn speculative_bounds(
    sides: &[SideSkin; 2],
    hi: f64,
    (mode, eps): (Mode, f64),
    cache: &KeyMap<HausdorffBounds>,
    reused: impl Fn(&CacheKey) -> bool,
    bound: impl Fn(&BoundJob) -> Speculative + Sync,
) -> KeyMap<Speculative> {
    let mut jobs: Vec<BoundJob> = Vec::new();
    let mut seen: BitsSet<CacheKey> = BitsSet::default();
    for (k, side) in [Side::Left, Side::Right].into_iter().enumerate() {
        let Ok((ps, arcs)) = &sides[k] else {
            break;
        };
        for (a, arc) in arcs.iter().enumerate() {
            let t0 = ps[a];
            let t1 = ps.get(a + 1).copied().unwrap_or(hi);
            let key = cache_key(arc, t0, t1, k, mode);
            if cached(cache, &key, eps).is_none() && !reused(&key) && seen.insert(key) {
                jobs.push(BoundJob {
                    key,
                    arc: *arc,
                    side,
                    t0,
                    t1,
                });
            }
        }
    }
    // One job gains nothing from a thread; keep it on the caller's.
    if jobs.len() < 2 {
        return KeyMap::default();
    }
    jobs.par_iter().map(|j| (j.key, bound(j))).collect()
}

/// The bits of a parameter sequence, the key of [`State::admissible`].
pub(super) fn param_bits(ps: &[f64]) -> Vec<u64> {
    ps.iter().map(|t| t.to_bits()).collect()
}

impl State<'_> {
    /// Records a Decide bound that the quick proof of D_H ≤ ε − gap gave (`quick`) in a run
    /// that never ran out of work, with the work it spent ([`State::quick`]).
    fn note_quick(&self, key: &CacheKey, quick: bool, spent: usize) {
        if quick && key.2 == Mode::Decide {
            self.quick.borrow_mut().insert(*key, spent);
        }
    }

    /// For a Compare key whose Decide bound the quick proof gave: that bound and its work,
    /// when `left` covers the work (the Compare run takes the same steps to the same
    /// bounds: the quick proof does not depend on the rejection, [`skin_envelope_within_path`]).
    fn reuse_quick(&self, key: &CacheKey, left: usize) -> Option<(HausdorffBounds, usize)> {
        if key.2 != Mode::Compare {
            return None;
        }
        let decide = (key.0, key.1, Mode::Decide);
        let spent = *self.quick.borrow().get(&decide)?;
        let h = self.cache.borrow().get(&decide).copied()?;
        (spent <= left).then_some((h, spent))
    }

    /// Errors of every side segment, mapped onto the segments of `params`.
    ///
    /// The bounds not yet cached are computed in parallel ([`speculative_bounds`]), then
    /// taken in serial order against the shared work budget exactly as a serial run would
    /// spend it; a bound whose parallel run might have been cut short by a smaller serial
    /// budget is recomputed with that budget, so the result does not depend on threads.
    pub(super) fn errors(&self, mode: Mode) -> Result<Vec<[HausdorffBounds; 2]>, DbscSkinError> {
        let mut out = vec![
            [HausdorffBounds {
                lower: 0.0,
                upper: 0.0
            }; 2];
            self.n_segments()
        ];
        let sides = self.skin_sides();
        let gap = self.opts.gap_fraction * self.opts.epsilon;
        let (c, eps) = (self.c, self.opts.epsilon);
        let spans = &self.spans;
        let bound = |arc: &CubicBez, side: Side, t0: f64, t1: f64, w: &mut Work| {
            let env = EnvelopeSegment::with_spans(c, spans, side, t0, t1)?;
            let plain = |h: HausdorffBounds| (h, false);
            match mode {
                Mode::Tight => skin_envelope_bounds(arc, &env, gap, w).map(plain),
                Mode::Decide => {
                    skin_envelope_within_path(arc, &env, (eps, Rejection::QuickLower), gap, w)
                }
                Mode::DecidedReport => {
                    skin_envelope_within(arc, &env, (eps, Rejection::Quick), gap, w).map(plain)
                }
                Mode::Compare => {
                    skin_envelope_within_path(arc, &env, (eps, Rejection::Full), gap, w)
                }
            }
        };
        let par_budget = self.work.borrow().left.min(MAX_BOUND_WORK);
        // A Compare bound that the quick proof gave in Decide mode is that bound again
        // ([`State::quick`]); it is not computed ahead.
        let reused = |key: &CacheKey| {
            key.2 == Mode::Compare
                && self
                    .quick
                    .borrow()
                    .contains_key(&(key.0, key.1, Mode::Decide))
        };
        let mut pre = speculative_bounds(
            &sides,
            self.hi,
            (mode, eps),
            &self.cache.borrow(),
            reused,
            |j| {
                let mut w = Work::new(par_budget);
                let r = bound(&j.arc, j.side, j.t0, j.t1, &mut w);
                (r, w.spent)
            },
        );
        for (k, (side, skin)) in [Side::Left, Side::Right].into_iter().zip(sides).enumerate() {
            let (ps, arcs) = skin?;
            let mut j = 0;
            for (a, arc) in arcs.iter().enumerate() {
                let t0 = ps[a];
                let t1 = ps.get(a + 1).copied().unwrap_or(self.hi);
                // An arc and its span determine the error: reuse it across passes (most
                // arcs are unchanged by insertions elsewhere).
                let key = cache_key(arc, t0, t1, k, mode);
                let known = cached(&self.cache.borrow(), &key, eps);
                let h = match known {
                    Some(h) => h,
                    None => {
                        let mut budget = self.work.borrow_mut();
                        if budget.left == 0 {
                            return Err(DbscSkinError::WorkBudget {
                                budget: self.opts.max_work,
                                epsilon: self.opts.epsilon,
                            });
                        }
                        let mut w = Work::new(budget.left.min(MAX_BOUND_WORK));
                        let start = w.left;
                        let h = match (self.reuse_quick(&key, w.left), pre.remove(&key)) {
                            // The quick proof's run again, spending what it spent.
                            (Some((h, spent)), _) => {
                                w = Work {
                                    left: w.left - spent,
                                    spent,
                                };
                                h
                            }
                            // Never ran out and fits this budget: the same run as serial.
                            (None, Some((r, spent))) if spent < par_budget && spent <= w.left => {
                                w = Work {
                                    left: w.left - spent,
                                    spent,
                                };
                                let (h, quick) = r?;
                                self.note_quick(&key, quick, spent);
                                h
                            }
                            _ => {
                                let (h, quick) = bound(arc, side, t0, t1, &mut w)?;
                                if w.spent < start {
                                    self.note_quick(&key, quick, w.spent);
                                }
                                h
                            }
                        };
                        budget.left -= w.spent;
                        budget.spent += w.spent;
                        self.cache.borrow_mut().insert(key, h);
                        h
                    }
                };
                while j < out.len() && self.params[j] < t1 {
                    out[j][k] = h;
                    j += 1;
                }
            }
        }
        Ok(out)
    }
}
