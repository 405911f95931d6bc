//! Stroke attributes reach the laser moves (issue 14, item 4): the brush example's `power`
//! and `feed` attributes (wu-2021 eq. 18) drive S and F on its fill and profile cuts.
//!
//! The program is read back with the `gcode` crate; every cutting move with the beam on is
//! mapped back to design coordinates (the placement offset from `--json`), and its S is
//! compared with the attribute evaluated by an independent Cox–de Boor recursion at the
//! nearest centre-curve parameter (found by brute-force sampling and golden-section
//! refinement) at points along the move.

use crate::support;

use ::gcode::{Code, Value};
use glam::DVec2;
use skinpath::dbsc::DiskBSpline;
use skinpath::spline::BSpline;
use support::{ROOT, skinpath, tmpdir};

/// Cox–de Boor recursion N_{i,p}(t) on `knots` (right end: the last non-zero span).
fn basis(knots: &[f64], i: usize, p: usize, t: f64) -> f64 {
    if p == 0 {
        let (a, b) = (knots[i], knots[i + 1]);
        let last = knots[knots.len() - 1];
        return if (a <= t && t < b) || (t == last && b == last && a < b) {
            1.0
        } else {
            0.0
        };
    }
    let mut v = 0.0;
    let d1 = knots[i + p] - knots[i];
    if d1 > 0.0 {
        v += (t - knots[i]) / d1 * basis(knots, i, p - 1, t);
    }
    let d2 = knots[i + p + 1] - knots[i + 1];
    if d2 > 0.0 {
        v += (knots[i + p + 1] - t) / d2 * basis(knots, i + 1, p - 1, t);
    }
    v
}

fn cox_de_boor(c: &BSpline<f64>, t: f64) -> f64 {
    c.ctrl()
        .iter()
        .enumerate()
        .map(|(i, a)| a * basis(c.knots(), i, c.degree(), t))
        .sum()
}

/// The spine parameter nearest to `p`: the best of 4000 samples, refined by golden
/// section on its neighbourhood.
fn nearest(c: &DiskBSpline, samples: &[(f64, DVec2)], p: DVec2) -> f64 {
    let k = samples
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.1.distance(p).total_cmp(&b.1.1.distance(p)))
        .map(|(k, _)| k)
        .unwrap();
    let (mut a, mut b) = (
        samples[k.saturating_sub(1)].0,
        samples[(k + 1).min(samples.len() - 1)].0,
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let x1 = b - g * (b - a);
        let x2 = a + g * (b - a);
        if c.center(x1).distance(p) < c.center(x2).distance(p) {
            b = x2;
        } else {
            a = x1;
        }
    }
    0.5 * (a + b)
}

fn num(v: &Value) -> f64 {
    match v {
        Value::Literal(x) => *x as f64,
        _ => panic!("non-literal value {v:?}"),
    }
}

/// A cutting move read back: start and end (machine coordinates), arc centre and sense,
/// S and F in force.
struct Cutting {
    from: DVec2,
    to: DVec2,
    arc: Option<(DVec2, bool)>,
    s: f64,
    f: f64,
}

impl Cutting {
    fn point(&self, u: f64) -> DVec2 {
        match self.arc {
            None => self.from.lerp(self.to, u),
            Some((c, ccw)) => {
                let a0 = (self.from - c).to_angle();
                let mut sw = (self.to - c).to_angle() - a0;
                if ccw {
                    while sw <= 0.0 {
                        sw += std::f64::consts::TAU;
                    }
                } else {
                    while sw >= 0.0 {
                        sw -= std::f64::consts::TAU;
                    }
                }
                c + self.from.distance(c) * DVec2::from_angle(a0 + u * sw)
            }
        }
    }
}

/// The beam-on cutting moves of a program (laser on, S > 0).
/// `fires_without_on`: the controller fires on G1/G2/G3 with S > 0 without an M3/M4
/// (Smoothie's laser module).
fn cutting_moves(src: &str, fires_without_on: bool) -> (Vec<Cutting>, bool) {
    let prog = ::gcode::parse(src).unwrap_or_else(|e| panic!("parse errors {e:?}"));
    let (mut pos, mut s, mut f, mut on) = (DVec2::ZERO, 0.0, 0.0, fires_without_on);
    let mut motion = 0u32;
    let mut dynamic = false;
    let mut out = Vec::new();
    for b in &prog.blocks {
        let mut words: Vec<(char, f64)> = b
            .word_addresses
            .iter()
            .map(|w| (w.letter.to_ascii_uppercase(), num(&w.value)))
            .collect();
        let mut moved = false;
        for code in &b.codes {
            match code {
                Code::General(g) => {
                    let n = g.number.major();
                    if n <= 3 {
                        motion = n;
                        moved = true;
                    }
                    words.extend(
                        g.args
                            .iter()
                            .map(|a| (a.letter.to_ascii_uppercase(), num(&a.value))),
                    );
                }
                Code::Miscellaneous(m) => {
                    match m.number.major() {
                        3 => on = true,
                        4 => {
                            on = true;
                            dynamic = true;
                        }
                        5 => on = false,
                        _ => {}
                    }
                    words.extend(
                        m.args
                            .iter()
                            .map(|a| (a.letter.to_ascii_uppercase(), num(&a.value))),
                    );
                }
                _ => {}
            }
        }
        let get = |c: char| words.iter().find(|w| w.0 == c).map(|w| w.1);
        if let Some(v) = get('S') {
            s = v;
        }
        if let Some(v) = get('F') {
            f = v;
        }
        let (x, y) = (get('X'), get('Y'));
        moved |= x.is_some() || y.is_some();
        if !moved || (x.is_none() && y.is_none()) {
            continue;
        }
        let to = DVec2::new(x.unwrap_or(pos.x), y.unwrap_or(pos.y));
        if motion >= 1 && on && s > 0.0 {
            let arc = (motion >= 2).then(|| {
                let c = pos + DVec2::new(get('I').unwrap_or(0.0), get('J').unwrap_or(0.0));
                (c, motion == 3)
            });
            out.push(Cutting {
                from: pos,
                to,
                arc,
                s,
                f,
            });
        }
        pos = to;
    }
    (out, dynamic)
}

struct Figures {
    moves: usize,
    s_range: (f64, f64),
    /// The power attribute's range along the whole spine, in S units.
    attr_range: (f64, f64),
    correlation: f64,
}

fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

/// Builds the brush for `machine` and checks S and F against the attributes; `quantum` is
/// one power step in S units, `feed_quantum` one feed step (mm/min).
fn check_brush(machine: &str, quantum: f64, feed_quantum: f64) -> Figures {
    let d = tmpdir(&format!("attrs-{machine}"));
    let out = d.join("brush.gcode");
    let design_path = format!("{ROOT}/examples/brush.toml");
    let o = skinpath(&[
        "build",
        &design_path,
        "--machine",
        machine,
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        o.status.success(),
        "build: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let off = &summary["placement"]["offset"];
    let offset = DVec2::new(off[0].as_f64().unwrap(), off[1].as_f64().unwrap());
    // build = check with the same profile.
    let c = skinpath(&["check", out.to_str().unwrap(), "--machine", machine]);
    assert!(
        c.status.success(),
        "check: {}",
        String::from_utf8_lossy(&c.stdout)
    );

    let text = std::fs::read_to_string(&design_path).unwrap();
    let design = skinpath::design::load(&text, "brush.toml").unwrap();
    let curve = design.strokes().unwrap().remove(0);
    let chans = design.stroke[0]
        .attribute_curves(&curve, "brush.toml", 0)
        .unwrap();
    let power = &chans.iter().find(|c| c.0 == "power").unwrap().1;
    let feed = &chans.iter().find(|c| c.0 == "feed").unwrap().1;
    let (lo, hi) = curve.domain();
    let samples: Vec<(f64, DVec2)> = (0..=4000)
        .map(|i| {
            let t = lo + (hi - lo) * i as f64 / 4000.0;
            (t, curve.center(t))
        })
        .collect();

    let profile = skinpath::machine::builtin_profiles()
        .unwrap()
        .into_iter()
        .find(|p| p.name == machine)
        .unwrap();
    let s_max = profile.power.max;
    let laser = profile.laser.as_ref().unwrap();
    let (moves, dynamic) = cutting_moves(
        &std::fs::read_to_string(&out).unwrap(),
        !laser.needs_on_command,
    );
    assert!(
        moves.len() > 1000,
        "{machine}: {} cutting moves",
        moves.len()
    );
    if laser.mode == skinpath::machine::LaserMode::Dynamic {
        assert!(dynamic, "{machine}: the profile asks for M4 dynamic power");
    }
    let (mut ss, mut want) = (Vec::new(), Vec::new());
    let mut s_range = (f64::INFINITY, f64::NEG_INFINITY);
    let mut distinct: Vec<f64> = Vec::new();
    for m in &moves {
        assert!(
            m.s >= profile.power.min && m.s <= s_max,
            "{machine}: S{} outside the profile's range",
            m.s
        );
        s_range = (s_range.0.min(m.s), s_range.1.max(m.s));
        if !distinct.contains(&m.s) {
            distinct.push(m.s);
        }
        // The attribute along the move (5 points): S lies within one quantum of its range.
        let (mut a_lo, mut a_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut f_lo, mut f_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..=4 {
            let p = m.point(k as f64 / 4.0) - offset;
            let t = nearest(&curve, &samples, p);
            let a = cox_de_boor(power, t) / 100.0 * s_max;
            a_lo = a_lo.min(a);
            a_hi = a_hi.max(a);
            let fv = cox_de_boor(feed, t);
            f_lo = f_lo.min(fv);
            f_hi = f_hi.max(fv);
        }
        // Rounding of the printed coordinates moves a point by at most 0.0005 mm; the
        // attributes change by far less than a quantum over that.
        let slack = 1e-6 * s_max;
        assert!(
            m.s >= a_lo - quantum - slack && m.s <= a_hi + quantum + slack,
            "{machine}: S{} at {:?}→{:?} where the attribute gives {a_lo:.2}..{a_hi:.2}",
            m.s,
            m.from - offset,
            m.to - offset
        );
        assert!(
            m.f >= f_lo - feed_quantum - 0.05 && m.f <= f_hi + feed_quantum + 0.05,
            "{machine}: F{} where the attribute gives {f_lo:.1}..{f_hi:.1}",
            m.f
        );
        let mid = m.point(0.5) - offset;
        ss.push(m.s);
        want.push(cox_de_boor(power, nearest(&curve, &samples, mid)) / 100.0 * s_max);
    }
    let correlation = pearson(&ss, &want);
    let attr: Vec<f64> = samples
        .iter()
        .map(|&(t, _)| cox_de_boor(power, t) / 100.0 * s_max)
        .collect();
    let attr_range = (
        attr.iter().copied().fold(f64::INFINITY, f64::min),
        attr.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    // The cuts cover the stroke from end to end: the emitted S spans the attribute's
    // range, to within a quantum (the hatch stops half a spacing short of the tips).
    assert!(
        (s_range.0 - attr_range.0).abs() <= 2.0 * quantum
            && (s_range.1 - attr_range.1).abs() <= quantum,
        "{machine}: S {s_range:?}, attribute {attr_range:?}"
    );
    assert!(correlation > 0.999, "{machine}: correlation {correlation}");
    // The brush's power runs 20..85 %: the program uses many levels, not one or two.
    assert!(
        distinct.len() > 50,
        "{machine}: {} S levels",
        distinct.len()
    );
    Figures {
        moves: moves.len(),
        s_range,
        attr_range,
        correlation,
    }
}

#[test]
fn brush_power_follows_pressure_on_grbl() {
    let f = check_brush("grbl-laser", 5.0, 30.0);
    eprintln!(
        "grbl-laser: {} moves, S {}..{} (attribute {:.1}..{:.1}), r = {:.5}",
        f.moves, f.s_range.0, f.s_range.1, f.attr_range.0, f.attr_range.1, f.correlation
    );
    // Control values 25..85 % (20 % at the tail's end disk): the blended curve peaks
    // below the belly's 85 %, and S is a multiple of 5.
    assert!(
        f.s_range.0 >= 195.0 && f.s_range.1 <= 850.0,
        "{:?}",
        f.s_range
    );
    assert_eq!(f.s_range.0 % 5.0, 0.0);
}

#[test]
fn brush_power_follows_pressure_on_marlin_and_smoothie() {
    // Marlin S0..255 in steps of 2 (0.5 % rounded up to whole S units); Smoothie S0..1
    // in steps of 0.005. Feed steps: 0.5 % of 6000 and of 24000 mm/min.
    let m = check_brush("marlin-laser", 2.0, 30.0);
    let s = check_brush("smoothie-laser", 0.005, 120.0);
    eprintln!(
        "marlin-laser: S {}..{}, r = {:.5}; smoothie-laser: S {}..{}, r = {:.5}",
        m.s_range.0, m.s_range.1, m.correlation, s.s_range.0, s.s_range.1, s.correlation
    );
}
