//! Elimination of envelope intersections caused by roots of f
//! (re-mph-skinning-flexible Sec. 4.2): tune the free uᵢ of flexible circles (eq. 11) until
//! f > 0 on [0, 1] (eq. 17), or raise f to the quartic of eqs. 18–19 with k chosen so that
//! f > 0. Positivity is proved on Bernstein coefficients after subdivision, never by
//! sampling alone. A pair where neither works gets a typed [`PairFix::Failed`].

use super::ReError;
use super::poly::{Poly, Positivity, prove_positive};
use super::skin::ReSkin;
use super::tangents::Touch;

/// Options of [`eliminate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EliminateOptions {
    /// Number of candidate u values tried per flexible circle (spread over (0, π)).
    pub u_samples: usize,
    /// Try tuning u of flexible circles first.
    pub try_u: bool,
    /// The "combined" method (mph Sec. 3.2): also release the right touching point of a
    /// [`Touch::Fixed`] circle (keeping W⁺, starting from the u that reproduces W⁻) when
    /// that removes the intersection.
    pub unfix: bool,
    /// Try the quartic f with free k.
    pub try_k: bool,
    /// Subdivision depth limit of the positivity proof.
    pub max_depth: u32,
    /// Largest k tried, relative to max(f̃₀, f̃₁, |f̃′₀|, |f̃′₁|, 1).
    pub k_max_rel: f64,
}

impl Default for EliminateOptions {
    fn default() -> Self {
        EliminateOptions {
            u_samples: 64,
            try_u: true,
            unfix: false,
            try_k: true,
            max_depth: 30,
            k_max_rel: 1e6,
        }
    }
}

/// Why a pair could not be fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FailReason {
    /// f ≤ 0 at an end: f̃ᵢ = rᵢ/‖vᵢ‖ must be positive.
    EndNotPositive,
    /// No tried u made f > 0, and the quartic was disabled or failed.
    NoUNoK,
    /// The positivity proof stayed undecided (f touches 0 within rounding).
    Undecided,
}

/// What was done to one pair of circles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PairFix {
    /// f > 0 on [0, 1] was proved without change.
    Clear,
    /// Setting u of circle `circle` to `u` made f > 0 on all segments using that circle.
    TunedU {
        /// Index of the flexible circle whose u was changed.
        circle: usize,
        /// The new u ∈ (0, π).
        u: f64,
    },
    /// The quartic f of eqs. 18–19 with this k is proved positive.
    Quartic {
        /// The k of the quartic, ≥ 0.
        k: f64,
    },
    /// Neither tuning u nor the quartic made f provably positive.
    Failed {
        /// Why the pair could not be fixed.
        reason: FailReason,
    },
}

/// Result per segment (pair of circles i, j).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairResult {
    /// Index of the segment in the skin.
    pub segment: usize,
    /// Index of the first circle of the pair.
    pub i: usize,
    /// Index of the second circle of the pair.
    pub j: usize,
    /// What was done, or why nothing worked.
    pub fix: PairFix,
}

fn positive(f: &Poly, depth: u32) -> Positivity {
    prove_positive(f, depth)
}

fn proven(f: &Poly, depth: u32) -> bool {
    matches!(positive(f, depth), Positivity::Proven { .. })
}

/// The smallest k (found by bisection on the proof) in [0, k_max] for which the quartic
/// f = f_cubic + k t²(1 − t)² is proved positive; `None` if even k_max fails.
pub fn positive_k(
    cubic: &Poly,
    boundary: &super::re_curve::FBoundary,
    k_max: f64,
    depth: u32,
) -> Option<f64> {
    let ok = |k: f64| proven(&boundary.quartic(k), depth);
    if proven(cubic, depth) {
        return Some(0.0);
    }
    // Grow k geometrically to a proven value, then bisect down (with a 10 % margin kept).
    let scale = [
        boundary.f0,
        boundary.f1,
        boundary.df0.abs(),
        boundary.df1.abs(),
        1.0,
    ]
    .iter()
    .fold(0.0f64, |m, v| m.max(*v));
    let mut hi = 0.01 * scale;
    while !ok(hi) {
        hi *= 2.0;
        if hi > k_max {
            return None;
        }
    }
    let mut lo = 0.0;
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let k = hi * 1.1;
    if ok(k) { Some(k) } else { Some(hi) }
}

/// Makes f > 0 on every segment where it can (mph Sec. 4.2) and reports per pair.
/// Segments whose f is already proved positive are left unchanged.
pub fn eliminate(skin: &mut ReSkin, opts: &EliminateOptions) -> Result<Vec<PairResult>, ReError> {
    let mut out = Vec::new();
    for s in 0..skin.segments.len() {
        let (i, j) = (skin.segments[s].i, skin.segments[s].j);
        let f = skin.segments[s].curve.f.clone();
        let fb = skin.segments[s].boundary;
        let res = |fix| PairResult {
            segment: s,
            i,
            j,
            fix,
        };
        if !(fb.f0 > 0.0 && fb.f1 > 0.0) {
            out.push(res(PairFix::Failed {
                reason: FailReason::EndNotPositive,
            }));
            continue;
        }
        if proven(&f, opts.max_depth) {
            out.push(res(PairFix::Clear));
            continue;
        }
        if opts.try_u
            && let Some(fix) = tune_u(skin, s, opts)?
        {
            out.push(res(fix));
            continue;
        }
        if opts.try_k {
            let k_max = opts.k_max_rel
                * [fb.f0, fb.f1, fb.df0.abs(), fb.df1.abs(), 1.0]
                    .iter()
                    .fold(0.0f64, |m, v| m.max(*v));
            if let Some(k) = positive_k(&f, &fb, k_max, opts.max_depth) {
                skin.set_k(s, Some(k))?;
                out.push(res(PairFix::Quartic { k }));
                continue;
            }
            out.push(res(PairFix::Failed {
                reason: FailReason::Undecided,
            }));
            continue;
        }
        out.push(res(PairFix::Failed {
            reason: FailReason::NoUNoK,
        }));
    }
    Ok(out)
}

/// Tries u values of the flexible ends of segment `s`; accepts the first (nearest to the
/// current u) for which every segment using that circle has a proved-positive f (without
/// breaking a neighbour that was positive).
fn tune_u(
    skin: &mut ReSkin,
    s: usize,
    opts: &EliminateOptions,
) -> Result<Option<PairFix>, ReError> {
    let (i, j) = (skin.segments[s].i, skin.segments[s].j);
    for c in [j, i] {
        let u0 = match skin.touches.get(c).copied() {
            Some(Touch::Flexible { u, .. }) => u,
            Some(Touch::Fixed { plus, .. }) if opts.unfix => {
                let (Some(circle), Some(&t)) = (skin.circles.get(c), skin.tangents.get(c)) else {
                    continue;
                };
                let Some(u) = super::tangents::u_of_tangent(circle, plus, t) else {
                    continue;
                };
                u
            }
            _ => continue,
        };
        let mut base = skin.clone();
        if let Some(Touch::Fixed { plus, .. }) = base.touches.get(c).copied() {
            base.touches[c] = Touch::Flexible { plus, u: u0 };
        }
        let n = opts.u_samples.max(1);
        let mut cands: Vec<f64> = (1..=n)
            .map(|k| std::f64::consts::PI * k as f64 / (n + 1) as f64)
            .collect();
        cands.sort_by(|a, b| (a - u0).abs().total_cmp(&(b - u0).abs()));
        for u in cands {
            let mut trial = base.clone();
            if trial.set_u(c, u).is_err() {
                continue;
            }
            let ok = trial.segments.iter().enumerate().all(|(q, seg)| {
                if seg.i != c && seg.j != c {
                    return true;
                }
                let was_ok = q == s || proven(&skin.segments[q].curve.f, opts.max_depth);
                !was_ok
                    || (seg.boundary.f0 > 0.0
                        && seg.boundary.f1 > 0.0
                        && proven(&seg.curve.f, opts.max_depth))
            });
            if ok {
                *skin = trial;
                return Ok(Some(PairFix::TunedU { circle: c, u }));
            }
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::super::detect::{IntersectionKind, detect};
    use super::super::re_curve::{FBoundary, Interp};
    use super::*;
    use crate::geom::{Circle, DVec2};

    /// Two circles far apart with touching points rotated against the travel direction:
    /// long Hermite tangents make f̃ small while f̃′ is strongly negative, so the cubic f
    /// dips below zero (a planted f-root intersection).
    fn planted(flexible: Option<usize>) -> ReSkin {
        let cs = vec![
            Circle::new(DVec2::ZERO, 1.0),
            Circle::new(DVec2::new(2.5, 0.0), 1.0),
        ];
        let a = 0.8f64;
        let fixed = |c: &Circle| Touch::Fixed {
            plus: c.point_at(a),
            minus: c.point_at(-a),
        };
        let mut touches = vec![fixed(&cs[0]), fixed(&cs[1])];
        if let Some(c) = flexible {
            // The same touching points, as a flexible circle (u reproduces W⁻).
            let t = super::super::tangents::tangent_for(&cs[c], c, &touches[c], 1e-9).unwrap();
            let u = super::super::tangents::u_of_tangent(&cs[c], cs[c].point_at(a), t).unwrap();
            touches[c] = Touch::Flexible {
                plus: cs[c].point_at(a),
                u,
            };
        }
        ReSkin::build(&cs, &touches, false, Interp::Cubic, 1e-9).unwrap()
    }

    #[test]
    fn quartic_k_removes_planted_f_roots() {
        let mut skin = planted(None);
        let before = detect(&skin, 1e-12);
        assert!(
            before.iter().any(|h| h.kind == IntersectionKind::FZero),
            "planted case: {before:?}"
        );
        let opts = EliminateOptions {
            try_u: false,
            ..Default::default()
        };
        let res = eliminate(&mut skin, &opts).unwrap();
        let PairFix::Quartic { k } = res[0].fix else {
            panic!("{res:?}")
        };
        assert!(k > 0.0);
        // Independent check: f on a fine grid is positive and boundary values unchanged.
        let seg = &skin.segments[0];
        assert!((0..=1000).all(|i| seg.curve.f.eval(i as f64 / 1000.0) > 0.0));
        let fb: FBoundary = seg.boundary;
        assert!((seg.curve.f.eval(1.0) - fb.f1).abs() < 1e-12);
        assert!(
            detect(&skin, 1e-12)
                .iter()
                .all(|h| h.kind != IntersectionKind::FZero)
        );
    }

    fn assert_cleared(skin: &ReSkin) {
        assert!(matches!(
            prove_positive(&skin.segments[0].curve.f, 30),
            Positivity::Proven { .. }
        ));
        assert!((0..=1000).all(|i| skin.segments[0].curve.f.eval(i as f64 / 1000.0) > 0.0));
        assert!(
            detect(skin, 1e-12)
                .iter()
                .all(|h| h.kind != IntersectionKind::FZero)
        );
    }

    #[test]
    fn tuning_u_or_failing_is_reported() {
        let opts = EliminateOptions {
            try_k: false,
            ..Default::default()
        };
        // Circle 1 flexible: no u of it clears the pair; reported as failed.
        let mut skin = planted(Some(1));
        assert!(
            detect(&skin, 1e-12)
                .iter()
                .any(|h| h.kind == IntersectionKind::FZero)
        );
        let res = eliminate(&mut skin, &opts).unwrap();
        assert_eq!(
            res[0].fix,
            PairFix::Failed {
                reason: FailReason::NoUNoK
            }
        );
        // Circle 0 flexible: tuning its u works.
        let mut skin = planted(Some(0));
        assert!(
            detect(&skin, 1e-12)
                .iter()
                .any(|h| h.kind == IntersectionKind::FZero)
        );
        let res = eliminate(&mut skin, &opts).unwrap();
        let PairFix::TunedU { circle, u } = res[0].fix else {
            panic!("{res:?}")
        };
        assert_eq!(circle, 0);
        assert!(u > 0.0 && u < std::f64::consts::PI);
        assert_cleared(&skin);
        // The combined method: a fixed circle may be released (W⁺ kept exactly).
        let mut skin = planted(None);
        let opts_unfix = EliminateOptions {
            try_k: false,
            unfix: true,
            ..Default::default()
        };
        let res = eliminate(&mut skin, &opts_unfix).unwrap();
        let PairFix::TunedU { circle, .. } = res[0].fix else {
            panic!("{res:?}")
        };
        assert!(matches!(skin.touches[circle], Touch::Flexible { .. }));
        assert_cleared(&skin);
        let w = skin.touches[circle].plus();
        let t = if circle == skin.segments[0].j {
            1.0
        } else {
            0.0
        };
        assert!((skin.segments[0].curve.x(t) - w).length() < 1e-12);
        // With both ways disabled the pair is reported as failed.
        let mut skin = planted(None);
        let opts = EliminateOptions {
            try_k: false,
            try_u: false,
            ..Default::default()
        };
        let res = eliminate(&mut skin, &opts).unwrap();
        assert_eq!(
            res[0].fix,
            PairFix::Failed {
                reason: FailReason::NoUNoK
            }
        );
    }
}
