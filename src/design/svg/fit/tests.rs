//! The fit's nearest-point hierarchy against a scan of every item, and its measure with
//! and without the early stop against the measure computed by scans.

use super::*;
use proptest::prelude::*;

/// Distance from `p` to the segment a–b by projection clamped to the segment (a second
/// formula: the closest point a + s·(b − a), s = clamp(((p − a)·(b − a)) / |b − a|², 0, 1)).
fn seg_distance(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    let d = b - a;
    let s = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + s * d - p).length()
}

/// The least distance from `p` to the segments of `pts` (to its one point when alone).
fn scan(pts: &[DVec2], p: DVec2) -> f64 {
    if pts.len() == 1 {
        return pts[0].distance(p);
    }
    pts.windows(2)
        .map(|w| seg_distance(w[0], w[1], p))
        .fold(f64::INFINITY, f64::min)
}

fn points(v: &[(f64, f64)]) -> Vec<DVec2> {
    v.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
}

/// A wavy run: y = amp·sin(x) sampled every `step` over [0, len].
fn wave(len: f64, step: f64, amp: f64) -> Vec<DVec2> {
    let n = (len / step).round() as usize;
    (0..=n)
        .map(|i| {
            let x = len * i as f64 / n as f64;
            DVec2::new(x, amp * x.sin())
        })
        .collect()
}

/// The measure of [`deviation`] by scans: the spine sampled as there, every spine sample
/// against every run segment (radius at the nearest point), every run point against every
/// spine segment and every spine sample (radius at the nearest sample).
fn deviation_by_scans(samples: &[[f64; 3]], ring: &[DVec2], ring_r: &[f64], closed: bool) -> f64 {
    let mut st = Stroke::from_disks("t", Vec::new());
    st.disks = None;
    st.closed = closed;
    st.degree = 3.min(samples.len() - 1).max(1);
    st.points = Some(samples.to_vec());
    let c = st.to_dbsc("t.svg", 0).unwrap();
    let (lo, hi) = c.domain();
    let n = (samples.len() * 16).max(64);
    let disks: Vec<_> = (0..=n)
        .map(|i| c.circle_at(lo + (hi - lo) * i as f64 / n as f64))
        .collect();
    let spine: Vec<DVec2> = disks.iter().map(|d| d.c).collect();
    let (mut a, mut b, mut rerr) = (0.0f64, 0.0f64, 0.0f64);
    for d in &disks {
        let (mut best, mut r) = (f64::INFINITY, ring_r[0]);
        for i in 0..ring.len() - 1 {
            let dist = seg_distance(ring[i], ring[i + 1], d.c);
            if dist < best {
                let seg = ring[i + 1] - ring[i];
                let s = ((d.c - ring[i]).dot(seg) / seg.length_squared()).clamp(0.0, 1.0);
                best = dist;
                r = ring_r[i] + s * (ring_r[i + 1] - ring_r[i]);
            }
        }
        a = a.max(best);
        rerr = rerr.max((d.r - r).abs());
    }
    for (&q, &r) in ring.iter().zip(ring_r) {
        b = b.max(scan(&spine, q));
        let j = (0..disks.len())
            .min_by(|&x, &y| disks[x].c.distance(q).total_cmp(&disks[y].c.distance(q)))
            .unwrap();
        rerr = rerr.max((disks[j].r - r).abs());
    }
    a.max(b) + rerr
}

/// Evenly spaced samples of the run as `fit_run` takes them, `count` of them.
fn even_samples(ring: &[DVec2], ring_r: &[f64], count: usize) -> Vec<[f64; 3]> {
    let mut s = vec![0.0];
    for w in ring.windows(2) {
        s.push(s.last().unwrap() + w[0].distance(w[1]));
    }
    let total = *s.last().unwrap();
    (0..count)
        .map(|j| {
            let u = total * j as f64 / (count - 1) as f64;
            let i = s.partition_point(|&v| v <= u).clamp(1, s.len() - 1);
            let f = (u - s[i - 1]) / (s[i] - s[i - 1]);
            let p = ring[i - 1].lerp(ring[i], f);
            [p.x, p.y, ring_r[i - 1] + f * (ring_r[i] - ring_r[i - 1])]
        })
        .collect()
}

proptest! {
    #[test]
    fn nearest_matches_a_scan_with_any_hint(
        v in proptest::collection::vec((-50.0f64..50.0, -50.0f64..50.0), 1..80),
        qs in proptest::collection::vec((-60.0f64..60.0, -60.0f64..60.0), 1..20),
        hint in 0usize..100,
        as_points in any::<bool>(),
    ) {
        let pts = points(&v);
        let chain = if as_points { Polyline::points(&pts) } else { Polyline::new(&pts) };
        for &(x, y) in &qs {
            let p = DVec2::new(x, y);
            let want = if as_points {
                pts.iter().map(|q| q.distance(p)).fold(f64::INFINITY, f64::min)
            } else {
                scan(&pts, p)
            };
            let (d, i, t) = chain.nearest_from(p, Some(hint));
            prop_assert!((d - want).abs() <= 1e-9, "{d} vs {want}");
            // The same answer without a hint, and the item found is at that distance.
            prop_assert_eq!(chain.nearest(p), (d, i, t));
            let at = if as_points || pts.len() == 1 {
                pts[i]
            } else {
                pts[i].lerp(pts[i + 1], t)
            };
            prop_assert!((at.distance(p) - d).abs() <= 1e-9);
            if !as_points && pts.len() > 1 {
                let (near, j) = chain.near_hint(p, hint.min(pts.len() - 2));
                prop_assert!(near >= d);
                prop_assert!((seg_distance(pts[j], pts[j + 1], p) - near).abs() <= 1e-12);
            }
        }
    }
}

#[test]
fn measure_matches_scans_and_stops_only_above_its_bound() {
    let ring = wave(20.0, 0.05, 2.0);
    let uniform = vec![0.4; ring.len()];
    let varying: Vec<f64> = ring.iter().map(|q| 0.3 + 0.02 * q.x).collect();
    for radii in [&uniform, &varying] {
        let run = Polyline::new(&ring);
        for count in [4, 7, 13, 25, 49] {
            let samples = even_samples(&ring, radii, count);
            let exact = deviation("t.svg", "t", &samples, &run, radii, false, f64::INFINITY);
            let want = deviation_by_scans(&samples, &ring, radii, false);
            assert!((exact - want).abs() <= 1e-9, "{count}: {exact} vs {want}");
            assert!(exact > 0.0);
            for f in [0.25, 0.5, 0.99] {
                let got = deviation("t.svg", "t", &samples, &run, radii, false, f * exact);
                assert!(
                    got > f * exact && got <= exact,
                    "{count} {f}: {got} vs {exact}"
                );
            }
            for f in [1.0, 2.0] {
                let got = deviation("t.svg", "t", &samples, &run, radii, false, f * exact);
                assert_eq!(got, exact);
            }
        }
    }
}

#[test]
fn runs_take_the_first_count_that_meets_the_target() {
    let tol = 0.05;
    let ring = wave(30.0, 0.02, 3.0);
    let radii = vec![0.25; ring.len()];
    let (samples, dev) = fit_run("t.svg", tol, "t", &ring, &radii, false).unwrap();
    assert!(dev <= FIT_TARGET * tol);
    let run = Polyline::new(&ring);
    let exact = deviation("t.svg", "t", &samples, &run, &radii, false, f64::INFINITY);
    assert_eq!(dev, exact);
    assert!((exact - deviation_by_scans(&samples, &ring, &radii, false)).abs() <= 1e-9);
    // Every smaller count of the sequence 2, 4, 7, 13, … misses the target.
    let mut count = 2;
    while count < samples.len() {
        let fewer = fit_samples_at(&ring, &radii, count);
        let d = deviation("t.svg", "t", &fewer, &run, &radii, false, f64::INFINITY);
        assert!(d > FIT_TARGET * tol, "{count}: {d}");
        count = if count == 2 { 4 } else { 2 * count - 1 };
    }
    assert_eq!(count, samples.len());
}

/// The samples `fit_run` takes at `count` (rounded as it rounds them).
fn fit_samples_at(ring: &[DVec2], radii: &[f64], count: usize) -> Vec<[f64; 3]> {
    even_samples(ring, radii, count)
        .into_iter()
        .map(|v| v.map(|x| (x * ROUND).round() / ROUND))
        .collect()
}
