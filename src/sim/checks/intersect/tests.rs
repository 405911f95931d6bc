//! Unit tests of the segment contact search.

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
    assert_eq!(reps.len(), 8);
    assert!(reps.iter().skip(4).all(|g| g.contour == 1 && g.a.x >= 5.0));
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
    let crossing = set.len() - 1;
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
            .any(|c| one.seg(c.i).contour == one.seg(c.j).contour)
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
    assert!(SPLIT_MIN <= s.len());
    let long = s.long_segments(&(0..s.len() as u32).collect::<Vec<_>>());
    assert!(long.is_some_and(|l| l.len() >= 6 && l.len() < 100));
    let got: Vec<_> = s.contacts().iter().map(|c| (c.i, c.j)).collect();
    let want = naive(&s);
    assert_eq!(got, want);
    // Long segments cross short ones too: the long-against-short pass is exercised.
    let long_short = want.iter().any(|&(i, j)| {
        let len = |k: usize| s.seg(k).a.distance(s.seg(k).b);
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
    let n = s.len();
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
    assert!(s.len() >= ROUNDS_MIN);
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
        let meets = (0..s.len())
            .any(|i| (i + 1..s.len()).any(|j| s.test_pair(i, j).is_some()));
        if s.proven_apart() {
            proptest::prop_assert!(!meets);
        }
        if spread == 50.0 && !meets {
            proptest::prop_assert!(s.proven_apart());
        }
    }
}

/// A polyline around a circle 70,000 times a chord of 2π/10.48576 rad (the chords of an
/// arc of many turns flattened to the chord cap: every chord crosses thousands of others).
/// Searched in rounds, the first window would give far more than [`WINDOW_CONTACTS`]
/// contacts: it is searched again narrower, and the first batch handed out is every
/// contact whose lower segment is in it, as testing each of its segments against every
/// other segment gives them, in (i, j) order.
#[test]
fn a_window_crossed_everywhere_is_narrowed_to_its_first_segments() {
    let n = ROUNDS_MIN + 4_464;
    let step = std::f64::consts::TAU / 10.485_76;
    let p: Vec<DVec2> = (0..=n)
        .map(|k| DVec2::new(5.0, 0.0) - 5.0 * DVec2::from_angle(k as f64 * step))
        .collect();
    let mut s = SegmentSet::new();
    s.push_polyline(&p, &[]);
    assert_eq!(s.len(), n);
    let mut first = Vec::new();
    let (capped, stopped) = s.contacts_in_order(|b| {
        first.extend_from_slice(b);
        false
    });
    assert!(!capped && stopped);
    let last = first.iter().map(|c| c.i).max().unwrap_or(0);
    assert!(last + 1 < FIRST_ROUND, "window not narrowed: {last}");
    let s = &s;
    let want: Vec<Contact> = (0..=last)
        .flat_map(|i| (i + 1..n).filter_map(move |j| s.test_pair(i, j)))
        .collect();
    assert!(want.len() > 1000, "{}", want.len());
    assert_eq!(first, want);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]
    /// The segments a set builds from its point array ([`SegmentSet::seg`]) are those of
    /// its polylines listed one by one: each pair of consecutive distinct points, numbered
    /// by contour and position, with its tag and pocket, whatever empty, one-point or
    /// repeated-point polylines come between; a tile built from them holds the same
    /// segments; and the set without copies holds the segments of the contours kept.
    #[test]
    fn segments_from_points_are_those_listed_one_by_one(
        lines in proptest::collection::vec(
            (proptest::collection::vec((0u8..4, 0u8..4), 0..9), proptest::option::of(1u32..3)),
            0..7,
        ),
    ) {
        let mut s = SegmentSet::new();
        let mut want: Vec<(Seg, u32, Option<u32>)> = Vec::new();
        let mut closed = Vec::new();
        for (c, (line, pocket)) in lines.iter().enumerate() {
            let points: Vec<DVec2> =
                line.iter().map(|&(x, y)| DVec2::new(f64::from(x), f64::from(y))).collect();
            let tags: Vec<u32> = (0..points.len() as u32).map(|k| 100 * c as u32 + k).collect();
            proptest::prop_assert_eq!(s.push_polyline_in(&points, &tags, *pocket), c as u32);
            let mut index = 0;
            let mut prev = points.first().copied();
            for (k, &p) in points.iter().enumerate().skip(1) {
                if prev != Some(p) {
                    let a = prev.unwrap_or(p);
                    let seg = Seg { a, b: p, contour: c as u32, index };
                    want.push((seg, tags[k - 1], *pocket));
                    index += 1;
                    prev = Some(p);
                }
            }
            closed.push(index >= 2 && points.first() == prev.as_ref());
        }
        proptest::prop_assert_eq!(s.len(), want.len());
        proptest::prop_assert_eq!(s.is_empty(), want.is_empty());
        let got: Vec<(Seg, u32, Option<u32>)> =
            (0..s.len()).map(|i| (s.seg(i), s.source(i), s.pocket(i))).collect();
        proptest::prop_assert_eq!(&got, &want);
        proptest::prop_assert!(s.get(s.len()).is_none());
        let got_closed: Vec<bool> = s.contours.iter().map(|c| c.1).collect();
        proptest::prop_assert_eq!(got_closed, closed);
        let tile = SegmentSet::tile(
            want.iter().map(|w| w.0).collect(),
            vec![Link::default(); want.len()],
            want.iter().map(|w| w.2).collect(),
            Across::All,
            0.0,
        );
        let tiled: Vec<Seg> = tile.iter().collect();
        let listed: Vec<Seg> = want.iter().map(|w| w.0).collect();
        proptest::prop_assert_eq!(&tiled, &listed);
        s.across = Across::Crossings;
        if let Some(reps) = s.without_copies() {
            // The contours kept, renumbered, with their segments, tags and pockets.
            // A contour's segments (end points and tag) and its pocket.
            type Listed = (Vec<(DVec2, DVec2, u32)>, Option<u32>);
            let kept: Vec<Listed> = (0..reps.contours.len())
                .map(|c| {
                    let segs = (0..reps.len())
                        .filter(|&i| reps.seg(i).contour == c as u32)
                        .map(|i| (reps.seg(i).a, reps.seg(i).b, reps.source(i)))
                        .collect();
                    (segs, reps.pockets[c])
                })
                .collect();
            let of = |c: usize| -> Listed {
                let segs = want
                    .iter()
                    .filter(|w| w.0.contour == c as u32)
                    .map(|w| (w.0.a, w.0.b, w.1))
                    .collect();
                (segs, lines[c].1)
            };
            let originals: Vec<_> = (0..lines.len()).map(of).collect();
            // Each kept contour is an original one, in order.
            let mut from = 0;
            for k in &kept {
                let at = (from..originals.len()).find(|&c| originals[c] == *k);
                proptest::prop_assert!(at.is_some(), "{k:?}");
                from = at.unwrap_or(0) + 1;
            }
            proptest::prop_assert!(kept.len() < lines.len());
        }
    }
}
