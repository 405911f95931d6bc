//! Cuts as configured: tabs, lead-ins and passes appear where asked and nowhere else; stroke
//! attributes (power, feed, depth) reach the V-carve moves, checked against an independent
//! Cox–de Boor evaluation of the attribute B-spline.

use super::*;
use crate::design::{Operation, OperationKind as DKind};
use crate::geom::Path;
use crate::job::{BuildOptions, build_toolpath};
use crate::machine::builtin_profile;
use crate::toolpath::cut::{Lead, Tabs};
use crate::toolpath::ops::{ProfileSide, profile};
use crate::toolpath::plan::{Geometry, OpSpec, plan};
use crate::toolpath::{Cut, MoveKind, OperationKind};
use glam::{DVec2, DVec3};

/// Paths to cut: two nested squares, a far square, and the outside profile of the
/// calligraphy example's first stroke (lines and arcs).
fn contours() -> Vec<Path> {
    let mut v = vec![
        square(DVec2::ZERO, 20.0),
        square(DVec2::ZERO, 5.0),
        square(DVec2::new(80.0, 0.0), 7.0),
    ];
    let (_, r) = regions("calligraphy", 1e-3).remove(0);
    v.extend(profile(&r, ProfileSide::Outside, 1.5, 1e-6));
    v
}

fn spec(paths: Vec<Path>, tabs: Option<Tabs>, lead: Lead) -> OpSpec {
    OpSpec {
        name: "profile".into(),
        kind: OperationKind::Profile,
        geometry: Geometry::Paths(paths),
        sources: vec![],
        groups: vec![],
        design_index: None,
        air_assist: false,
        depth: 6.0,
        step_down: 2.0,
        repeat: 1,
        feed: 1000.0,
        plunge_feed: 250.0,
        power: 1.0,
        tabs,
        lead,
        dwell: 0.0,
    }
}

/// The cuts of one planned operation.
fn cut_of(specs: OpSpec) -> Vec<Cut> {
    let (tp, _) = plan(&[specs], DVec2::ZERO, 1e-3);
    tp.operations[0].cuts.clone()
}

#[test]
fn tabs_lift_only_on_deep_passes_over_tab_spans() {
    let tabs = Tabs {
        count: 3,
        width: 4.0,
        height: 3.0,
    };
    let levels = [-2.0, -4.0, -6.0];
    let tab_top = -6.0 + 3.0;
    let deep = levels.iter().filter(|&&z| z < tab_top).count();
    for cut in cut_of(spec(contours(), Some(tabs), Lead::None)) {
        // Arc length along the contour since the current pass's plunge.
        let mut s = 0.0;
        let mut pass_len = Vec::new();
        let mut lifts = Vec::new(); // (pass level, s)
        let mut drops = Vec::new();
        let mut prev = cut.start;
        let mut level = 0.0;
        for m in &cut.moves {
            let planar = move_len(prev, m.kind, m.to);
            if planar == 0.0 && m.to.z < prev.z && levels.contains(&m.to.z) && m.to.z < level {
                // A plunge to the next level (not a drop back from a tab top).
                if level != 0.0 {
                    pass_len.push(s);
                }
                level = m.to.z;
                s = 0.0;
            } else if planar == 0.0 && m.to.z > prev.z {
                lifts.push((level, s));
            } else if planar == 0.0 && m.to.z < prev.z {
                drops.push((level, s));
            }
            s += planar;
            prev = m.to;
        }
        pass_len.push(s);
        let total = pass_len[0];
        assert!(pass_len.iter().all(|l| (l - total).abs() < 1e-6 * total));
        // Lifts only on passes below the tab top, exactly tabs × deep passes of them.
        assert!(lifts.iter().all(|(z, _)| *z < tab_top), "{lifts:?}");
        assert_eq!(lifts.len(), tabs.count * deep);
        assert_eq!(drops.len(), tabs.count * deep);
        // Each lift at the start of a tab span, each drop at its end.
        let spans: Vec<(f64, f64)> = (0..tabs.count)
            .map(|k| {
                let mid = (k as f64 + 0.5) * total / tabs.count as f64;
                (mid - tabs.width / 2.0, mid + tabs.width / 2.0)
            })
            .collect();
        for (_, s) in &lifts {
            assert!(
                spans.iter().any(|(a, _)| (s - a).abs() < 1e-6),
                "lift at {s}"
            );
        }
        for (_, s) in &drops {
            assert!(
                spans.iter().any(|(_, b)| (s - b).abs() < 1e-6),
                "drop at {s}"
            );
        }
        // The moves at the tab top are exactly over the spans.
        let top_z: Vec<f64> = cut
            .moves
            .iter()
            .map(|m| m.to.z)
            .filter(|z| *z == tab_top)
            .collect();
        assert!(!top_z.is_empty());
    }
    // Without tabs the tool never rises inside a cut.
    for cut in cut_of(spec(contours(), None, Lead::None)) {
        let mut prev = cut.start;
        for m in &cut.moves {
            assert!(m.to.z <= prev.z, "rise from {prev} to {}", m.to);
            prev = m.to;
        }
    }
}

#[test]
fn lead_in_only_as_the_first_cutting_move() {
    for lead in [Lead::Arc(2.0)] {
        let (mut with_lead, mut dropped) = (0, 0);
        let paths = contours();
        for cut in cut_of(spec(paths.clone(), None, lead)) {
            // The contour this cut runs: the one its second move ends on.
            let on = cut.moves[1].to.truncate();
            let rings: Vec<Vec<DVec2>> = paths.iter().map(|p| p.flatten(1e-6)).collect();
            let ring = rings
                .iter()
                .min_by(|a, b| {
                    rings_distance(&[a.to_vec()], on).total_cmp(&rings_distance(&[b.to_vec()], on))
                })
                .unwrap();
            let d = |p: DVec3| rings_distance(std::slice::from_ref(ring), p.truncate());
            // A lead that would run into the contour is shrunk or, failing that, dropped:
            // then every move stays on the contour.
            let n = cut.moves.len();
            if d(cut.start) < 1e-9 {
                dropped += 1;
                assert!(cut.moves.iter().all(|m| d(m.to) < 1e-6), "{lead:?}");
                continue;
            }
            with_lead += 1;
            // The entry is off the contour, the lead-in (move 1) lands on it.
            assert!(d(cut.moves[1].to) < 1e-6);
            match (lead, cut.moves[1].kind) {
                (Lead::Arc(_), MoveKind::Arc { .. }) => {}
                other => panic!("lead-in of the wrong kind: {other:?}"),
            }
            // Every move between the lead-in and the lead-out stays on the contour.
            for m in &cut.moves[1..n - 1] {
                assert!(d(m.to) < 1e-6, "move off the contour at {}", m.to);
            }
            // The lead-out leaves it.
            assert!(d(cut.moves[n - 1].to) > 1e-3);
        }
        assert!(
            with_lead >= 3,
            "{lead:?}: {with_lead} cuts with a lead, {dropped} without"
        );
    }
}

#[test]
fn distinct_z_levels_equal_the_passes() {
    for (depth, step) in [(6.0, 2.0), (5.0, 2.0), (1.0, 3.0), (9.0, 1.0)] {
        let mut s = spec(contours(), None, Lead::None);
        s.depth = depth;
        s.step_down = step;
        let passes = (depth / step).ceil() as usize;
        for cut in cut_of(s) {
            let mut zs: Vec<f64> = cut.moves.iter().map(|m| m.to.z).collect();
            zs.sort_by(f64::total_cmp);
            zs.dedup();
            assert_eq!(zs.len(), passes, "depth {depth} step {step}: {zs:?}");
            assert_eq!(zs[0], -depth);
        }
    }
    // Lasers: `repeat` passes at the surface: the first entered by a plunge (to z = 0),
    // each later one after a travel in place (the beam goes off and on between passes, so
    // each pass is a contour of its own).
    let mut s = spec(contours(), None, Lead::None);
    s.depth = 0.0;
    s.repeat = 3;
    for cut in cut_of(s) {
        assert!(cut.moves.iter().all(|m| m.to.z == 0.0));
        let count = |kind: fn(&MoveKind) -> bool, feed: Option<f64>| {
            cut.moves
                .iter()
                .filter(|m| kind(&m.kind) && feed.is_none_or(|f| m.feed == f))
                .count()
        };
        assert_eq!(count(|k| matches!(k, MoveKind::Line), Some(250.0)), 1);
        assert_eq!(count(|k| matches!(k, MoveKind::Rapid), None), 2);
    }
}

/// Cox–de Boor: value at t of the clamped B-spline with `knots`, `degree` and `ctrl`
/// (at the domain's end a clamped curve takes its last control value).
fn de_boor_value(knots: &[f64], degree: usize, ctrl: &[f64], t: f64) -> f64 {
    fn basis(k: &[f64], i: usize, p: usize, t: f64) -> f64 {
        if p == 0 {
            return if k[i] <= t && t < k[i + 1] { 1.0 } else { 0.0 };
        }
        let mut v = 0.0;
        if k[i + p] > k[i] {
            v += (t - k[i]) / (k[i + p] - k[i]) * basis(k, i, p - 1, t);
        }
        if k[i + p + 1] > k[i + 1] {
            v += (k[i + p + 1] - t) / (k[i + p + 1] - k[i + 1]) * basis(k, i + 1, p - 1, t);
        }
        v
    }
    if t >= knots[knots.len() - degree - 1] {
        return ctrl[ctrl.len() - 1];
    }
    ctrl.iter()
        .enumerate()
        .map(|(i, c)| c * basis(knots, i, degree, t))
        .sum()
}

fn vcarve_op(angle: f64, max_depth: f64) -> Operation {
    let mut op = Operation::new(DKind::Vcarve);
    op.angle = Some(angle);
    op.max_depth = Some(max_depth);
    op.feed = Some(777.0);
    op.power = Some(50.0);
    op
}

#[test]
fn attributes_reach_the_vcarve_moves() {
    let mut d = super::example("brush");
    let strokes = d.strokes().unwrap();
    let c = &strokes[0];
    let knots = c.curve().knots().to_vec();
    let deg = c.curve().degree();
    let power = d.stroke[0].attributes.power.clone().unwrap();
    let feed = d.stroke[0].attributes.feed.clone().unwrap();
    let depth: Vec<f64> = (0..power.len()).map(|i| 0.5 + 0.4 * i as f64).collect();
    let cap = 2.0;
    d.stroke[0].attributes.depth = Some(depth.clone());
    d.operation = vec![vcarve_op(60.0, cap)];
    let (lo, hi) = c.domain();
    for (machine, laser) in [("grbl-laser", true), ("grbl-router", false)] {
        let prof = builtin_profile(machine).unwrap();
        let b = build_toolpath(&d, &prof, &BuildOptions::default()).unwrap();
        let ops: Vec<_> = b
            .toolpath
            .operations
            .iter()
            .filter(|o| o.kind == OperationKind::VCarve)
            .collect();
        // With a depth attribute the router clears no flat bottom.
        assert_eq!(ops.len(), 1, "{machine}");
        let cut = &ops[0].cuts[0];
        let n = cut.moves.len() - 1;
        let (mut capped, mut free) = (0, 0);
        for (i, m) in cut.moves.iter().enumerate() {
            let t = lo + (hi - lo) * i as f64 / n as f64;
            assert!(c.center(t).distance(m.to.truncate()) < 1e-9);
            let p = de_boor_value(&knots, deg, &power, t) / 100.0;
            assert!(
                (m.power - p).abs() < 1e-9,
                "{machine} power {} vs {p}",
                m.power
            );
            if i > 0 {
                let f = de_boor_value(&knots, deg, &feed, t);
                assert!(
                    (m.feed - f).abs() < 1e-6,
                    "{machine} feed {} vs {f}",
                    m.feed
                );
            }
            let z = if laser {
                0.0
            } else {
                -de_boor_value(&knots, deg, &depth, t).min(cap)
            };
            assert!((m.to.z - z).abs() < 1e-9, "{machine} z {} vs {z}", m.to.z);
            if z == -cap { capped += 1 } else { free += 1 }
        }
        if !laser {
            assert!(
                capped > 0 && free > 0,
                "the cap is reached somewhere, not everywhere"
            );
        }
    }
    // Without attributes the V-carve falls back to the operation's power and feed.
    let mut plain = super::example("brush");
    plain.stroke[0].attributes = Default::default();
    plain.operation = vec![vcarve_op(60.0, cap)];
    let prof = builtin_profile("grbl-laser").unwrap();
    let b = build_toolpath(&plain, &prof, &BuildOptions::default()).unwrap();
    let cut = &b.toolpath.operations[0].cuts[0];
    assert!(cut.moves.iter().all(|m| (m.power - 0.5).abs() < 1e-12));
    assert!(cut.moves[1..].iter().all(|m| m.feed == 777.0));
}
