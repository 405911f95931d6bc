//! Every program we emit parses with the independent `gcode` crate, and a small interpreter
//! of the parsed blocks checks the safety and fidelity rules of DESIGN.md "Output
//! conventions": preamble, no firing rapid, routers travel at safe Z and plunge at the plunge
//! feed, the program ends with the tool off, coordinates stay in the work area, arcs (I J or
//! R) reproduce the input's circles, and the cut length matches the input.

use crate::support;

use ::gcode::{Code, Value};
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use skinpath::emit::{EmitError, GcodeOptions, gcode};
use skinpath::machine::{
    ArcFormat, MachineKind, Profile, RapidOff, Units, builtin_profile, builtin_profiles,
};
use skinpath::toolpath::{MoveKind, Toolpath};
use support::emit::*;

/// What the interpreter saw.
#[derive(Debug, Default)]
struct Run {
    /// Cutting length in the plane, mm.
    cut_xy: f64,
    /// (centre, radius) of every arc, mm.
    /// Every arc as written: centre, radius, chord length, midpoint (mm).
    arcs: Vec<(DVec2, f64, f64, DVec2)>,
    arc_count: usize,
    ends_off: bool,
    lines: usize,
}

fn num(v: &Value) -> f64 {
    match v {
        Value::Literal(x) => *x as f64,
        _ => panic!("variable or other value in emitted G-code: {v:?}"),
    }
}

fn words(args: &[::gcode::Argument]) -> Vec<(char, f64)> {
    args.iter()
        .map(|a| (a.letter.to_ascii_uppercase(), num(&a.value)))
        .collect()
}

fn get(ws: &[(char, f64)], c: char) -> Option<f64> {
    ws.iter().find(|(l, _)| *l == c).map(|(_, v)| *v)
}

/// Interprets `src` for `p`, asserting the rules on the way. Coordinates reported in mm.
fn interpret(src: &str, p: &Profile) -> Run {
    let prog = ::gcode::parse(src).unwrap_or_else(|d| panic!("parse errors {d:?}\n{src}"));
    let mm = p.units.mm_per_unit();
    let g = p.gcode.as_ref().unwrap();
    let laser = p.laser.as_ref();
    let router = p.router.as_ref();
    let mut run = Run::default();
    let mut pos: [Option<f64>; 3] = [None; 3];
    let mut motion: Option<u32> = None;
    let (mut s, mut on, mut feed) = (0.0f64, false, None::<f64>);
    let mut saw_setup = false;
    let mut ended = false;
    let tol = 1.5 * 10f64.powi(-(g.decimals as i32));
    for (bi, b) in prog.blocks.iter().enumerate() {
        let text = &src[b.span.start..b.span.end()];
        assert!(text.len() <= 80, "line too long: {text}");
        for c in &b.comments {
            for bad in ['!', '?', '~', '(', ')'] {
                assert!(
                    !c.value.trim_matches(['(', ')']).contains(bad),
                    "comment {c:?}"
                );
            }
        }
        if b.codes.is_empty() && b.word_addresses.is_empty() {
            continue;
        }
        run.lines += 1;
        assert!(!ended, "code after program end: {text}");
        let mut mv: Option<(u32, Vec<(char, f64)>)> = None;
        let bare = words_of_bare(b);
        for code in &b.codes {
            match code {
                Code::General(gc) => {
                    let n = gc.number.major();
                    let ws = words(&gc.args);
                    match n {
                        0..=3 => {
                            assert!(saw_setup, "motion before the setup line");
                            let mut all = ws.clone();
                            all.extend(bare.iter().copied());
                            mv = Some((n, all));
                            motion = Some(n);
                        }
                        17 | 90 | 94 | 40 | 49 | 80 | 64 => {}
                        20 | 21 => {
                            let want = if p.units == Units::Inch { 20 } else { 21 };
                            assert_eq!(n, want, "units word");
                        }
                        4 => {}
                        other => panic!("unexpected G{other} in {text}"),
                    }
                    if n == 17 {
                        assert!(text.contains("G90") && text.contains("G94"), "{text}");
                        assert!(text.contains(p.units.gcode()), "{text}");
                        saw_setup = true;
                    }
                }
                Code::Miscellaneous(m) => {
                    let ws = words(&m.args);
                    match m.number.major() {
                        3 | 4 => {
                            on = true;
                            if let Some(v) = get(&ws, 'S') {
                                s = v;
                            }
                        }
                        5 => on = false,
                        2 | 30 => {
                            assert!(!on, "program end with the tool on");
                            ended = true;
                        }
                        other => panic!("unexpected M{other}"),
                    }
                }
                _ => panic!("unexpected code {code}"),
            }
        }
        if b.codes.is_empty() {
            // Bare words: a modal move or an S/F change.
            if bare.iter().any(|(c, _)| "XYZ".contains(*c)) {
                assert!(
                    p.dialect.modal_motion(),
                    "modal move on a dialect without modal motion: {text}"
                );
                mv = Some((motion.expect("modal move before any G0/G1"), bare.clone()));
            }
        }
        if mv.is_none() {
            if let Some(v) = get(&bare, 'S') {
                s = v;
            }
            if let Some(v) = get(&bare, 'F') {
                feed = Some(v);
            }
        }
        let Some((gnum, ws)) = mv else { continue };
        if let Some(v) = get(&ws, 'F') {
            feed = Some(v);
        }
        if let Some(v) = get(&ws, 'S') {
            s = v;
        }
        let from = pos;
        let mut to = pos;
        for (i, c) in ['X', 'Y', 'Z'].iter().enumerate() {
            if let Some(v) = get(&ws, *c) {
                to[i] = Some(v);
            }
        }
        // Work area.
        for (i, r) in [p.work_area.x, p.work_area.y, p.work_area.z]
            .iter()
            .enumerate()
        {
            if let Some(v) = to[i] {
                assert!(
                    r.contains(v, tol),
                    "axis {i} = {v} outside work area: {text}"
                );
            }
        }
        match gnum {
            0 => {
                if let Some(l) = laser {
                    let fires = on && s > 0.0 && l.rapid_off != RapidOff::Firmware;
                    assert!(!fires, "G0 with the laser on (block {bi}: {text})");
                    assert!(
                        get(&ws, 'S').is_none_or(|v| v == 0.0),
                        "power on a G0: {text}"
                    );
                }
                if let Some(r) = router {
                    let xy_moves = (0..2).any(|i| to[i] != from[i]);
                    if xy_moves {
                        let z = from[2].expect("XY rapid before Z is known");
                        assert!(
                            z >= r.safe_z - tol,
                            "XY rapid at z {z} below safe z: {text}"
                        );
                        assert!(to[2] == from[2], "rapid moves XY and Z together: {text}");
                    }
                    if let (Some(z0), Some(z1)) = (from[2], to[2])
                        && z1 < z0
                    {
                        assert!(z1 >= r.clearance_z - tol, "rapid below clearance: {text}");
                    }
                }
            }
            1..=3 => {
                let f = feed.expect("cutting move without a feed");
                assert!(f > 0.0);
                let m = p.max_feed;
                assert!(f <= m.x.max(m.y).max(m.z) + tol, "feed {f} above maximum");
                if let Some(r) = router {
                    assert!(
                        on && s >= p.power.min,
                        "cutting with the spindle off: {text}"
                    );
                    let plunge = (0..2).all(|i| to[i] == from[i])
                        && matches!((from[2], to[2]), (Some(a), Some(b)) if b < a);
                    if plunge {
                        assert!(f <= r.plunge_feed + tol, "plunge at F{f}: {text}");
                    }
                }
                let (Some(x0), Some(y0), Some(x1), Some(y1)) = (from[0], from[1], to[0], to[1])
                else {
                    panic!("cutting move from an unknown position: {text}")
                };
                let (a, b) = (DVec2::new(x0, y0), DVec2::new(x1, y1));
                if gnum == 1 {
                    run.cut_xy += a.distance(b) * mm;
                } else {
                    let ccw = gnum == 3;
                    let c = match (get(&ws, 'I'), get(&ws, 'J'), get(&ws, 'R')) {
                        (Some(i), Some(j), None) => {
                            assert_eq!(g.arcs, ArcFormat::Ij, "{text}");
                            a + DVec2::new(i, j)
                        }
                        (None, None, Some(r)) => {
                            assert_eq!(g.arcs, ArcFormat::R, "{text}");
                            assert!(a != b, "R arc with equal ends: {text}");
                            center_from_r(a, b, r, ccw)
                        }
                        _ => panic!("arc needs I J or R: {text}"),
                    };
                    let (r0, r1) = (a.distance(c), b.distance(c));
                    assert!(
                        (r0 - r1).abs() <= 2.0 * tol,
                        "radius mismatch {r0} {r1}: {text}"
                    );
                    let arc = skinpath::geom::Arc::from_center_points(c, a, b, ccw);
                    run.cut_xy += arc.length() * mm;
                    run.arcs
                        .push((c * mm, r0 * mm, a.distance(b) * mm, arc.eval(0.5) * mm));
                    run.arc_count += 1;
                }
            }
            _ => unreachable!(),
        }
        pos = to;
    }
    assert!(saw_setup, "no G17 G2x G90 G94 line");
    assert!(!on, "program ends with the tool on");
    run.ends_off = !on;
    if g.program_end.is_empty() {
        let last = src.lines().rev().find(|l| !l.trim().is_empty()).unwrap();
        assert!(
            last.trim() == "M5" || !g.postamble.is_empty(),
            "last line {last}"
        );
    } else {
        assert!(ended, "no {}", g.program_end);
    }
    run
}

fn words_of_bare(b: &::gcode::Block) -> Vec<(char, f64)> {
    b.word_addresses
        .iter()
        .map(|w| (w.letter.to_ascii_uppercase(), num(&w.value)))
        .collect()
}

/// The centre of the arc a → b of radius |r| (negative r: the long way), G2 or G3: the
/// standard R-format rule, recomputed independently of the emitter.
fn center_from_r(a: DVec2, b: DVec2, r: f64, ccw: bool) -> DVec2 {
    let m = 0.5 * (a + b);
    let d = b - a;
    let half = 0.5 * d.length();
    let h = (r * r - half * half).max(0.0).sqrt();
    let left = DVec2::new(-d.y, d.x).normalize();
    // Short arc (r > 0): the centre is left of a→b for ccw, right for cw.
    let side = if ccw { 1.0 } else { -1.0 } * r.signum();
    m + side * h * left
}

fn gcode_profiles() -> Vec<Profile> {
    let mut ps: Vec<Profile> = builtin_profiles()
        .unwrap()
        .into_iter()
        .filter(|p| p.kind != MachineKind::Svg)
        .collect();
    // Variants: GRBL laser in M3 mode (S0 before rapids), with R arcs, with no arcs.
    let grbl = skinpath::machine::BUILTIN_SOURCES[0].1;
    let variants = [
        grbl.replace("mode = \"dynamic\"", "mode = \"constant\"")
            .replace("rapid_off = \"firmware\"", "rapid_off = \"s0\"")
            .replace("name = \"grbl-laser\"", "name = \"grbl-laser-m3\""),
        grbl.replace("arcs = \"ij\"", "arcs = \"r\"")
            .replace("name = \"grbl-laser\"", "name = \"grbl-laser-r\""),
        grbl.replace("arcs = \"ij\"", "arcs = \"none\"")
            .replace("name = \"grbl-laser\"", "name = \"grbl-laser-lines\""),
        skinpath::machine::BUILTIN_SOURCES[1]
            .1
            .replace("arcs = \"ij\"", "arcs = \"r\"")
            .replace("name = \"grbl-router\"", "name = \"grbl-router-r\""),
    ];
    for v in variants {
        ps.push(Profile::from_toml(&v, "variant.toml").unwrap());
    }
    ps
}

/// True when every point of `tp` (arcs sampled) lies in the work area grown by `slack`
/// machine units.
fn fits(tp: &Toolpath, p: &Profile, slack: f64) -> bool {
    let s = 1.0 / p.units.mm_per_unit();
    let wa = p.work_area;
    let ok = |q: DVec3| {
        wa.x.contains(q.x * s, slack)
            && wa.y.contains(q.y * s, slack)
            && (p.kind == MachineKind::Router || q.z == 0.0 || wa.z.contains(q.z * s, slack))
    };
    // Arcs are sampled densely: their bulge must fit too.
    tp.operations.iter().all(|o| {
        o.cuts.iter().all(|c| {
            let mut pos = c.start;
            ok(c.start)
                && c.moves.iter().all(|m| {
                    let inside = match m.kind {
                        MoveKind::Arc { center, ccw } => {
                            let a = skinpath::geom::Arc::from_center_points(
                                center,
                                pos.truncate(),
                                m.to.truncate(),
                                ccw,
                            );
                            (0..=2000).all(|k| ok(a.eval(k as f64 / 2000.0).extend(m.to.z)))
                        }
                        _ => ok(m.to),
                    };
                    pos = m.to;
                    inside
                })
        })
    })
}

fn job_for(p: &Profile, passes: &[f64]) -> Toolpath {
    match p.kind {
        MachineKind::Router => job(passes, 0.8),
        _ => job(&passes.iter().map(|z| z * 0.5).collect::<Vec<_>>(), 0.6),
    }
}

fn check_program(tp: &Toolpath, p: &Profile, opts: &GcodeOptions) -> Run {
    let out = gcode(tp, p, opts).unwrap_or_else(|e| panic!("{}: {e}", p.name));
    let run = interpret(&out, p);
    // The cut length matches the input (flattened arcs lose at most the chord error).
    let want = cut_length_xy(tp);
    let g = p.gcode.as_ref().unwrap();
    let rel = if g.arcs == ArcFormat::None {
        1e-3
    } else {
        1e-4
    };
    assert!(
        (run.cut_xy - want).abs() <= rel * want + 0.01,
        "{}: cut length {} vs {want}\n{out}",
        p.name,
        run.cut_xy
    );
    // Every written arc lies on an input circle.
    let circles = arc_circles(tp);
    let tol = 3.0 * 10f64.powi(-(g.decimals as i32)) * p.units.mm_per_unit();
    for (c, r, chord, mid) in &run.arcs {
        // Rounding the end points by e moves a centre recomputed from R (or I J) by about
        // e·r/(chord/2) sideways: short chords get the proportional allowance. The arc's
        // midpoint, though, must sit on the input circle within the rounding.
        let centre_tol = tol * (1.0 + 2.0 * r / chord.max(1e-12));
        assert!(
            circles.iter().any(|(ic, ir)| ic.distance(*c) <= centre_tol
                && (ir - r).abs() <= centre_tol
                && (mid.distance(*ic) - ir).abs() <= 2.0 * tol),
            "{}: arc ({c}, {r}) is on no input circle",
            p.name
        );
    }
    if g.arcs == ArcFormat::None {
        assert_eq!(run.arc_count, 0);
    } else if !circles.is_empty() {
        assert!(run.arc_count >= circles.len());
    }
    run
}

#[test]
fn every_profile_every_job() {
    let opts = GcodeOptions::default();
    for p in gcode_profiles() {
        for passes in [&[-1.0][..], &[-1.0, -2.0, -3.0][..]] {
            let tp = job_for(&p, passes);
            if fits(&tp, &p, 0.0) {
                check_program(&tp, &p, &opts);
            } else {
                let e = gcode(&tp, &p, &opts).unwrap_err();
                assert!(
                    matches!(e, EmitError::OutOfWorkArea { .. }),
                    "{}: {e}",
                    p.name
                );
            }
        }
        // Laser at z = 0 always fits.
        if p.kind == MachineKind::Laser {
            check_program(&job(&[0.0], 1.0), &p, &opts);
        }
    }
}

#[test]
fn r_arcs_are_split_and_recomputed_centres_match() {
    let p = gcode_profiles()
        .into_iter()
        .find(|p| p.name == "grbl-laser-r")
        .unwrap();
    let tp = job(&[0.0], 0.5);
    let out = gcode(&tp, &p, &GcodeOptions::default()).unwrap();
    let run = check_program(&tp, &p, &GcodeOptions::default());
    // Two full circles (3 pieces each), 4 quarter arcs, a semicircle (2), a 270° arc (3).
    assert_eq!(run.arc_count, 3 + 3 + 4 + 2 + 3, "{out}");
    assert!(!out.contains("R-"), "long arcs are split, never negative R");
}

#[test]
fn inch_router_program() {
    let p = builtin_profile("linuxcnc-router").unwrap().unwrap();
    let tp = job(&[-1.0, -2.0], 0.5);
    let out = gcode(&tp, &p, &GcodeOptions::default()).unwrap();
    assert!(out.contains("G20") && !out.contains("G21"));
    assert!(out.contains("G64 P0.0005"), "{out}");
    // 4 decimals at most on every number.
    for w in out.split_whitespace().filter(|w| !w.starts_with('(')) {
        if let Some((_, frac)) = w.split_once('.') {
            assert!(frac.len() <= 4, "{w}");
        }
    }
    check_program(&tp, &p, &GcodeOptions::default());
}

#[test]
fn no_negative_zero_and_decimals_respected() {
    let mut tp = job(&[0.0], 0.5);
    // Coordinates that round to zero from below.
    tp.operations[1].cuts[0].start.x = 25.0 - 1e-9;
    for p in gcode_profiles() {
        let tp = if p.kind == MachineKind::Router {
            job(&[-1e-7 - 1.0], 0.5)
        } else {
            tp.clone()
        };
        let out = gcode(&tp, &p, &GcodeOptions::default()).unwrap();
        assert!(!out.contains("-0 ") && !out.contains("-0\n"), "{out}");
        let dec = p.gcode.as_ref().unwrap().decimals as usize;
        for w in out.split_whitespace() {
            if w.starts_with(['X', 'Y', 'Z', 'I', 'J', 'R'])
                && let Some((_, frac)) = w.split_once('.')
            {
                assert!(frac.len() <= dec, "{w}");
                assert!(!w.ends_with('0'), "trailing zero {w}");
            }
        }
    }
}

#[test]
fn marlin_turns_the_laser_off_before_every_travel() {
    let p = builtin_profile("marlin-laser").unwrap().unwrap();
    let out = gcode(&job(&[0.0], 1.0), &p, &GcodeOptions::default()).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    let mut on = false;
    for l in &lines {
        if l.starts_with("M3") {
            on = true;
            assert!(l.contains(" I1"), "inline power: {l}");
        }
        if l.starts_with("M5") {
            on = false;
        }
        if l.starts_with("G0") {
            assert!(!on, "travel with M3 in force: {l}");
        }
        if l.starts_with("X") || l.starts_with("Y") {
            panic!("Marlin move without its G word: {l}");
        }
    }
    assert!(!out.contains("M2"), "Marlin has no M2");
    assert!(out.contains("S255"));
}

#[test]
fn m3_mode_sets_s0_before_each_rapid() {
    let p = gcode_profiles()
        .into_iter()
        .find(|p| p.name == "grbl-laser-m3")
        .unwrap();
    let out = gcode(&job(&[0.0], 1.0), &p, &GcodeOptions::default()).unwrap();
    let mut s_on = false;
    let mut rapids = 0;
    for l in out.lines() {
        if l.contains(" S1000") {
            s_on = true;
        }
        if l == "S0" {
            s_on = false;
        }
        if l.starts_with("G0") {
            rapids += 1;
            assert!(!s_on, "{l}\n{out}");
        }
    }
    assert!(rapids >= 4);
}

#[test]
fn dwells_and_rapids_inside_a_cut() {
    let p = builtin_profile("grbl-router").unwrap().unwrap();
    let mut tp = job(&[-1.0], 0.5);
    let c = &mut tp.operations[2].cuts[0];
    c.moves.insert(
        2,
        skinpath::toolpath::Move {
            kind: MoveKind::Dwell { seconds: 0.5 },
            to: DVec3::ZERO,
            feed: 0.0,
            power: 0.5,
        },
    );
    let resume = c.moves[3].to;
    let mut jump = c.moves[3];
    jump.kind = MoveKind::Rapid;
    jump.to = DVec3::new(100.0, 100.0, 2.0);
    c.moves.insert(3, jump);
    let mut back = c.moves[4];
    back.kind = MoveKind::Rapid;
    back.to = DVec3::new(resume.x, resume.y - 10.0, -1.0);
    c.moves.insert(4, back);
    let out = gcode(&tp, &p, &GcodeOptions::default()).unwrap();
    assert!(out.contains("G4 P0.5"), "{out}");
    interpret(&out, &p);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random chains of lines and arcs inside the bed: every profile's program parses, obeys
    /// the rules and reproduces the cut length.
    #[test]
    fn random_chains(
        start in (30.0f64..150.0, 30.0f64..150.0),
        steps in prop::collection::vec(
            (0u8..3, 0.5f64..20.0, -3.1f64..3.1, 0.01f64..6.2, any::<bool>()), 1..12),
        depth in -3.0f64..-0.1,
    ) {
        let moves = chain(DVec2::new(start.0, start.1), &steps, 0.0);
        let base = Toolpath {
            operations: vec![op(
                "random",
                skinpath::toolpath::OperationKind::Profile,
                vec![cut(DVec3::new(start.0, start.1, 0.0), moves)],
            )],
        };
        for p in gcode_profiles() {
            let mut tp = base.clone();
            if p.kind == MachineKind::Router {
                let c = &mut tp.operations[0].cuts[0];
                c.start.z = depth;
                for m in &mut c.moves {
                    m.to.z = depth;
                }
            }
            // Within half a unit of the last decimal of the boundary either answer is right.
            let slack = 10f64.powi(-(p.gcode.as_ref().unwrap().decimals as i32));
            if fits(&tp, &p, 0.0) {
                check_program(&tp, &p, &GcodeOptions::default());
            } else if !fits(&tp, &p, slack) {
                let e = gcode(&tp, &p, &GcodeOptions::default()).unwrap_err();
                prop_assert!(matches!(e, EmitError::OutOfWorkArea { .. }), "{e}");
            }
        }
    }
}
