//! The outline of a skinned circle sequence as closed [`Path`] contours.
//!
//! Open sequence: one contour, counter-clockwise: the right skin forward, the end cap arc of
//! the last circle counter-clockwise from its right to its left touching point, the left
//! skin backwards, the start cap arc of the first circle from its left to its right touching
//! point (DESIGN.md "Skinning", traversed the other way round so the area is positive).
//! Closed sequence: two contours, the outer one counter-clockwise and the inner one
//! clockwise (the skin whose touching polygon encloses more area is the outer one).

use super::admissible::SkinError;
use super::bezier::{SkinOptions, Skins, skin_circles};
use crate::dbsc::Side;
use crate::geom::path::polygon_area;
use crate::geom::{Arc, Circle, Path, PathSeg};

/// Outline contours with the skins they were built from.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Outline {
    /// Open input: `[outline]`; closed input: `[outer, inner]`. Outer contours are
    /// counter-clockwise, inner ones clockwise.
    pub contours: Vec<Path>,
    /// The left and right skins the contours were assembled from.
    pub skins: Skins,
}

/// Skins `circles` ([`skin_circles`]) and assembles the outline contours (module docs).
pub fn outline_circles(
    circles: &[Circle],
    closed: bool,
    opts: &SkinOptions,
) -> Result<Outline, SkinError> {
    let skins = skin_circles(circles, closed, opts)?;
    Ok(outline_from_skins(circles, skins))
}

/// Assembles the outline from skins of `circles` (module docs). `skins` must come from the
/// same circles (as [`skin_circles`] or [`super::bezier_skins`] return them).
pub fn outline_from_skins(circles: &[Circle], skins: Skins) -> Outline {
    let contours = if skins.closed {
        let l = skins.path(Side::Left);
        let r = skins.path(Side::Right);
        let al = polygon_area(&skins.touching.iter().map(|t| t.left).collect::<Vec<_>>());
        let ar = polygon_area(&skins.touching.iter().map(|t| t.right).collect::<Vec<_>>());
        let (outer, ao, inner, ai) = if ar.abs() >= al.abs() {
            (r, ar, l, al)
        } else {
            (l, al, r, ar)
        };
        let outer = if ao >= 0.0 { outer } else { outer.reversed() };
        let inner = if ai <= 0.0 { inner } else { inner.reversed() };
        vec![outer, inner]
    } else {
        let mut segs: Vec<PathSeg> = skins.right.iter().map(|c| PathSeg::Cubic(*c)).collect();
        if let (Some(first), Some(last), Some(t0), Some(tn)) = (
            circles.first(),
            circles.last(),
            skins.touching.first(),
            skins.touching.last(),
        ) {
            segs.push(PathSeg::Arc(Arc::from_center_points(
                last.c, tn.right, tn.left, true,
            )));
            segs.extend(
                skins
                    .left
                    .iter()
                    .rev()
                    .map(|c| PathSeg::Cubic(c.reversed())),
            );
            segs.push(PathSeg::Arc(Arc::from_center_points(
                first.c, t0.left, t0.right, true,
            )));
        }
        vec![Path::new(segs, true)]
    };
    Outline { contours, skins }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec2;
    use crate::geom::intersect::{path_self_intersections, paths_intersections};
    use crate::skin::admissible::AdmissibilityOptions;
    use crate::skin::bezier::max_disk_penetration;
    use proptest::prelude::*;

    fn c(x: f64, y: f64, r: f64) -> Circle {
        Circle::new(DVec2::new(x, y), r)
    }

    fn scale_of(cs: &[Circle]) -> f64 {
        cs.iter().map(|k| k.c.length() + k.r).fold(0.0, f64::max)
    }

    /// Relative depth (to the radius) by which a skin may enter a disk: the Hermite arcs
    /// of re-skinning-cnc eqs. 11–12 are tangent to the circles at the touching points but
    /// their curvature there can exceed the circle's, so they can dip in slightly (see
    /// `skins_can_dip_into_a_disk`). Observed in the random tests below (radius slope
    /// ≤ 0.4): at most 2.6e-4·r.
    const PENETRATION: f64 = 1e-3;

    /// The same for sequences that turn by more than 0.7 rad per step (the open walk's
    /// limit): flat ellipses of 12 circles turn ≈ 1.3 rad per step at their ends, where
    /// the fixed-seed run found a dip of 1.9e-3·r.
    const PENETRATION_SHARP: f64 = 5e-3;

    /// The penetration bound for `cs`: [`PENETRATION`] while every step turns by at most
    /// 0.7 rad, [`PENETRATION_SHARP`] otherwise.
    fn penetration_bound(cs: &[Circle], closed: bool) -> f64 {
        let n = cs.len();
        let steps = if closed { n } else { n.saturating_sub(2) };
        let sharp = (0..steps).any(|k| {
            let (a, b, d) = (cs[k], cs[(k + 1) % n], cs[(k + 2) % n]);
            (b.c - a.c).angle_to(d.c - b.c).abs() > 0.7
        });
        if sharp {
            PENETRATION_SHARP
        } else {
            PENETRATION
        }
    }

    /// The outline invariants: closed contours, orientation, no intersection anywhere
    /// (guaranteed curve test), no skin inside a disk deeper than the tolerance.
    fn check_outline(cs: &[Circle], closed: bool) -> Result<(), TestCaseError> {
        let opts = SkinOptions::default();
        let o =
            outline_circles(cs, closed, &opts).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        let scale = scale_of(cs);
        let tol = 1e-9 * scale;
        for p in &o.contours {
            prop_assert!(p.max_gap() <= 1e-9 * scale, "gap {}", p.max_gap());
            let hits = path_self_intersections(p, tol);
            prop_assert!(hits.is_empty(), "self-intersections {hits:?}");
        }
        // The two skins never meet (also covered by the contour check for open input).
        let h = paths_intersections(&o.skins.path(Side::Left), &o.skins.path(Side::Right), tol);
        prop_assert!(h.is_empty(), "left/right {h:?}");
        let area = |p: &Path| polygon_area(&p.flatten(1e-3 * scale));
        prop_assert!(area(&o.contours[0]) > 0.0);
        if closed {
            prop_assert!(area(&o.contours[1]) < 0.0);
            let h = paths_intersections(&o.contours[0], &o.contours[1], tol);
            prop_assert!(h.is_empty(), "outer/inner {h:?}");
        }
        let mut worst: f64 = 0.0;
        let bound = penetration_bound(cs, closed);
        for seg in o.skins.left.iter().chain(&o.skins.right) {
            for k in cs {
                let pen = max_disk_penetration(seg, k, 1e-7 * scale);
                worst = worst.max(pen / k.r);
                prop_assert!(pen <= 2e-7 * scale + bound * k.r, "enters {k:?} by {pen}");
            }
        }
        prop_assert!(worst <= bound + 1e-6);
        Ok(())
    }

    /// Reruns `check_outline` reversed, rotated and scaled.
    fn check_frames(cs: &[Circle], closed: bool) -> Result<(), TestCaseError> {
        check_outline(cs, closed)?;
        let rev: Vec<Circle> = cs.iter().rev().copied().collect();
        check_outline(&rev, closed)?;
        for (rot, s) in [(1.1, 1e-3), (-2.4, 1e4)] {
            let q = DVec2::from_angle(rot);
            let t: Vec<Circle> = cs
                .iter()
                .map(|k| Circle::new(q.rotate(k.c) * s, k.r * s))
                .collect();
            check_outline(&t, closed)?;
        }
        Ok(())
    }

    #[test]
    fn open_outline_contour_shape() {
        let cs: Vec<Circle> = (0..5).map(|i| c(2.0 * i as f64, 0.0, 1.0)).collect();
        let o = outline_circles(&cs, false, &SkinOptions::default()).unwrap();
        let p = &o.contours[0];
        assert_eq!(p.segs.len(), 2 * 4 + 2);
        // A stadium: straight sides y = ±1 plus two half circles; area 8·2 + π.
        let a = polygon_area(&p.flatten(1e-6));
        assert!((a - (16.0 + std::f64::consts::PI)).abs() < 1e-4, "{a}");
        check_frames(&cs, false).unwrap();
    }

    #[test]
    fn closed_outline_is_an_annulus() {
        let cs: Vec<Circle> = (0..12)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 12.0;
                c(5.0 * t.cos(), 5.0 * t.sin(), 1.0)
            })
            .collect();
        let o = outline_circles(&cs, true, &SkinOptions::default()).unwrap();
        let a0 = polygon_area(&o.contours[0].flatten(1e-6));
        let a1 = polygon_area(&o.contours[1].flatten(1e-6));
        // Close to the annulus between radii 6 and 4 (the cubics are not exact circles).
        let pi = std::f64::consts::PI;
        assert!((a0 - 36.0 * pi).abs() < 0.05 * 36.0 * pi, "{a0}");
        assert!((a1 + 16.0 * pi).abs() < 0.05 * 16.0 * pi, "{a1}");
        check_frames(&cs, true).unwrap();
    }

    #[test]
    fn sharp_turns_intersect_exactly_when_inadmissible() {
        // Three equal circles turning by `turn`: skinned without the admissibility check,
        // the inadmissible ones (kruppa-2023 Fig. 13) give outlines that the curve checker
        // finds intersecting; the admissible ones give clean outlines.
        let opts = SkinOptions {
            check_admissibility: false,
            ..Default::default()
        };
        let mut seen = [false, false];
        for turn in [2.0f64, 2.4, 2.7, 2.9] {
            for r in [0.6f64, 0.9, 1.2] {
                let cs = [
                    c(-2.0, 0.0, r),
                    c(0.0, 0.0, r),
                    c(2.0 * turn.cos(), 2.0 * turn.sin(), r),
                ];
                let adm = crate::skin::check_admissible(&cs, false, &Default::default()).is_ok();
                let o = outline_circles(&cs, false, &opts).unwrap();
                let hits = path_self_intersections(&o.contours[0], 1e-9);
                assert_eq!(hits.is_empty(), adm, "turn {turn} r {r}: {hits:?}");
                seen[usize::from(adm)] = true;
            }
        }
        assert_eq!(seen, [true, true]);
    }

    #[test]
    fn inadmissible_input_names_circles() {
        let cs = [c(0.0, 0.0, 0.3), c(0.5, 0.0, 1.0), c(2.0, 0.0, 1.0)];
        let e = outline_circles(&cs, false, &SkinOptions::default()).unwrap_err();
        assert!(matches!(e, SkinError::Inadmissible { .. }));
        assert!(
            format!("{e}").contains("circles [0, 1] violate condition 1"),
            "{e}"
        );
    }

    /// Random open sequences: a smooth-ish walk (bounded turn per step) whose radius changes
    /// by at most 0.4 of the step length; inadmissible ones (strict: far disks disjoint) are
    /// discarded.
    fn walk(steps: &[(f64, f64, f64)], r0: f64) -> Vec<Circle> {
        let mut p = DVec2::ZERO;
        let mut h = 0.0f64;
        let mut r = r0;
        let mut out = vec![Circle::new(p, r0)];
        for &(turn, len, dr) in steps {
            h += turn;
            p += len * DVec2::from_angle(h);
            r = (r + dr * len).clamp(0.3, 1.3);
            out.push(Circle::new(p, r));
        }
        out
    }

    #[test]
    fn skins_can_dip_into_a_disk() {
        // Found by the property test before the radius slope was bounded: a big circle
        // between two small ones (|Δr|/|Δc| ≈ 0.78). The Hermite arc is tangent to the big
        // circle at its touching point but curves more strongly, entering it by ≈ 2% of r.
        let cs = walk(&[(0.0, 1.0, 0.778), (-0.4194, 1.0, -0.778)], 0.4);
        assert!((cs[1].r - 1.178).abs() < 1e-12);
        let s = skin_circles(&cs, false, &SkinOptions::default()).unwrap();
        let worst = s
            .left
            .iter()
            .chain(&s.right)
            .map(|seg| max_disk_penetration(seg, &cs[1], 1e-9))
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(worst > 0.01 * cs[1].r && worst < 0.05 * cs[1].r, "{worst}");
        // The outline itself is still free of intersections.
        let o = outline_from_skins(&cs, s);
        assert!(path_self_intersections(&o.contours[0], 1e-9).is_empty());
    }

    fn strict_ok(cs: &[Circle], closed: bool) -> bool {
        let o = AdmissibilityOptions {
            strict_disjoint: true,
            ..Default::default()
        };
        crate::skin::check_admissible(cs, closed, &o).is_ok()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        #[test]
        fn random_open_sequences(
            steps in prop::collection::vec((-0.7f64..0.7, 1.0f64..2.0, -0.4f64..0.4), 1..12),
            r0 in 0.4f64..1.2,
        ) {
            let cs = walk(&steps, r0);
            prop_assume!(strict_ok(&cs, false));
            check_frames(&cs, false)?;
        }

        #[test]
        fn random_closed_sequences(
            n in 5usize..14,
            ax in 4.0f64..8.0, ay in 3.0f64..8.0,
            jitter in prop::collection::vec((-0.3f64..0.3, -0.3f64..0.3, 0.5f64..1.3), 14),
        ) {
            let cs: Vec<Circle> = (0..n).map(|k| {
                let t = k as f64 * std::f64::consts::TAU / n as f64;
                let (dx, dy, r) = jitter[k];
                c(ax * t.cos() + dx, ay * t.sin() + dy, r)
            }).collect();
            prop_assume!(strict_ok(&cs, true));
            // The penetration bounds assume a radius slope |Δr|/|Δc| ≤ 0.4, as in the open
            // walk; steeper neighbours dip deeper by design (`skins_can_dip_into_a_disk`).
            prop_assume!((0..n).all(|k| {
                let (a, b) = (cs[k], cs[(k + 1) % n]);
                (a.r - b.r).abs() <= 0.4 * a.c.distance(b.c)
            }));
            check_frames(&cs, true)?;
        }
    }
}
