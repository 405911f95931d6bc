//! The checks run on a [`Program`]: each returns named [`Finding`]s.
//!
//! | id | severity | what |
//! |---|---|---|
//! | `self-intersection` | error | a cut contour crosses or touches itself |
//! | `contour-crossing` | error | two cut contours cross (off with `allow_crossings`; contours of one marked pocket may) |
//! | `too-many-contacts` | error | the contours meet in more than `MAX_CONTACTS` places; only the first are listed |
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
//! `no-motion-mode`, `after-program-end`, `canon-error`) join the same list.

pub mod contours;
pub mod gouge;
pub mod intersect;
pub mod machine;

pub use contours::{SimContour, cut_contours, is_cutting};
pub use gouge::{DesignBoundary, KeepSide};
pub use intersect::{Across, Contact, Seg, SegmentSet};

use super::config::CheckConfig;
use super::findings::Finding;
use super::motion::Program;

/// Runs every check (`cfg` in mm, see [`CheckConfig::in_mm`]); findings in program order
/// within each check.
pub fn run_all(prog: &Program, cfg: &CheckConfig, design: &[DesignBoundary]) -> Vec<Finding> {
    let contours = contours::cut_contours_marked(&prog.motions, &prog.group_marks, cfg);
    let mut out = Vec::new();
    out.extend(contours::intersection_findings(
        &contours,
        &prog.motions,
        cfg,
    ));
    out.extend(gouge::gouge_findings(&prog.motions, &contours, design, cfg));
    // The per-move checks in one pass over the moves; their findings in the order of
    // `out_of_bounds`, `rapids` and `feed_and_power` one after the other.
    let limits = machine::Limits::new(cfg);
    let (mut bounds, mut rapids, mut feeds) = (Vec::new(), Vec::new(), Vec::new());
    let mut fp = machine::FeedPower::default();
    for m in &prog.motions {
        bounds.extend(limits.motion(&m, cfg));
        machine::rapid_move(&m, cfg, &mut rapids);
        fp.motion(&m, cfg, &mut feeds);
    }
    out.extend(bounds);
    out.extend(rapids);
    out.extend(feeds);
    out.extend(machine::program_end(prog, cfg));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec2;
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

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

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
