//! The RE/MPH route of a build (`build --method re|mph`, or `method` on an operation):
//! every item's RE or MPH skin (re-skinning-cnc-kruppa-2021, re-mph-skinning-flexible-
//! kruppa-2021) and the operations whose cuts are its exact MAT offsets
//! ([`crate::toolpath::re_route`]). Where the route cannot be exact — the skin keeps an
//! envelope intersection or a local envelope loop, the spine crosses itself, items overlap
//! so that the cut must follow their union — the operation takes the general (Bézier skin)
//! route and the build says why.

use super::outline::{
    ItemOutline, OutlineOptions, ReOutlineError, re_outline, sequence_touches, stroke_re_input,
};
use crate::dbsc::DiskBSpline;
use crate::design::Design;
use crate::geom::{DVec2, Line, Path};
use crate::skin::mat_offset::MatOffsetError;
use crate::skin::re::{Interp, ReSkin};
use crate::toolpath::ops::ProfileSide;
use crate::toolpath::re_route::{SegCounts, mat_backboard, mat_profile};

/// One item's RE/MPH skin, ready for MAT offsets.
#[derive(Clone, Debug)]
pub struct ReItem {
    /// The skin after elimination.
    pub skin: ReSkin,
    /// The skin's outline, flattened within the build tolerance (for checks and fills).
    pub outline: Vec<Path>,
    /// Where an envelope of the skin runs backwards (a local loop, cut off the outline by
    /// the union of the disks): the route is not taken (see [`re_profile`]).
    pub loop_note: Option<String>,
}

/// Why an item or an operation cannot take the exact (MAT offset) route; the build then
/// takes the general route and notes this as the reason.
#[derive(Debug, thiserror::Error)]
pub enum RouteRefusal {
    /// The stroke's spine crosses itself.
    #[error("the spine crosses itself (the cut follows the union)")]
    SelfOverlap,
    /// A stroke without its disk B-spline.
    #[error("stroke without its disk B-spline")]
    NoCurve,
    /// The item is not a stroke or circle sequence of the design (a shape, for example).
    #[error("not a stroke or circle sequence (a shape has no RE/MPH skin)")]
    NoItem,
    /// The RE/MPH skin or its outline could not be built.
    #[error(transparent)]
    Outline(#[from] ReOutlineError),
    /// Envelope intersections are left after elimination.
    #[error("the envelopes still meet after elimination (segment {segment}, t = {t:.4})")]
    EnvelopesMeet {
        /// Segment of the skin.
        segment: usize,
        /// Parameter on the segment.
        t: f64,
    },
    /// Elimination could not fix a circle pair.
    #[error("elimination failed between circles {i} and {j}")]
    EliminationFailed {
        /// First circle.
        i: usize,
        /// Second circle.
        j: usize,
    },
    /// The exact offset (outline, profile or backboard) failed.
    #[error(transparent)]
    Offset(#[from] MatOffsetError),
    /// An item's envelope runs backwards (see [`ReItem::loop_note`]).
    #[error("{name}: {note}")]
    Loop {
        /// The item's name.
        name: String,
        /// Where the envelope runs backwards.
        note: String,
    },
    /// The exact profile of item `name` failed.
    #[error("{name}: {source}")]
    Profile {
        /// The item's name.
        name: String,
        /// Why the offset failed.
        source: MatOffsetError,
    },
    /// Two items overlap.
    #[error("{a} and {b} overlap (the cut follows their union)")]
    Overlap {
        /// First item's name.
        a: String,
        /// Second item's name.
        b: String,
    },
    /// An item without a skin.
    #[error("item without a skin")]
    NoSkin,
    /// The operation has no items.
    #[error("no items")]
    NoItems,
    /// The rounding of inner corners differs from the tool radius.
    #[error(
        "the inner corner radius {rho} differs from the tool radius {r} (the rounding is a \
         closing of the union)"
    )]
    CornerRadius {
        /// The inner corner radius asked for.
        rho: f64,
        /// The tool radius.
        r: f64,
    },
    /// A backboard around several items follows their union.
    #[error("{0} items: the backboard follows their union")]
    Union(usize),
    /// A channel reaches beyond the item's outline: the backboard follows the union of the
    /// outline and the channel, grown by the margin.
    #[error("a channel reaches beyond the outline: the backboard follows both")]
    ChannelOutside,
    /// The board's pieces are joined by bridges: the backboard follows the bridged board.
    #[error("{0} bridge(s) join the board's pieces: the backboard follows the bridged board")]
    Bridged(usize),
    /// The board's convex corners are rounded to `corner_radius`: the backboard follows the
    /// rounded board.
    #[error("corner_radius {0}: the backboard follows the board with its corners rounded")]
    Rounded(f64),
}

/// Which route an operation took, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct RouteNote {
    /// The operation's name in the toolpath (e.g. "profile 1").
    pub operation: String,
    /// "skin", "re" or "mph".
    pub route: String,
    /// What the route did, or why the exact route was not taken.
    pub detail: String,
    /// Arcs and lines of the operation's paths.
    pub counts: SegCounts,
    /// Wall time spent on the operation's paths (seconds): the exact offsets, or the general
    /// offsets, or both when the exact route was tried and refused. The RE/MPH skins
    /// themselves are in [`super::build::BuildResult::re_skin_seconds`].
    pub seconds: f64,
}

/// The RE/MPH skin of every item of `outlines` (strokes by their DBSC skin's knot and
/// inserted circles with the exact envelope touching points, circle sequences by their
/// Kunkli–Hoffmann touching points), or why an item cannot take the exact route.
pub fn re_items(
    design: &Design,
    strokes: &[DiskBSpline],
    outlines: &[ItemOutline],
    interp: Interp,
    opts: &OutlineOptions,
) -> Vec<Result<ReItem, RouteRefusal>> {
    outlines
        .iter()
        .map(|o| {
            if o.self_overlap {
                return Err(RouteRefusal::SelfOverlap);
            }
            let (circles, touches, closed) =
                if let Some(k) = design.stroke.iter().position(|s| s.name == o.name) {
                    let c = strokes.get(k).ok_or(RouteRefusal::NoCurve)?;
                    stroke_re_input(c, opts)?
                } else if let Some(seq) = design.circles.iter().find(|s| s.name == o.name) {
                    let cs = seq.to_circles();
                    let t = sequence_touches(&cs, seq.closed).map_err(ReOutlineError::from)?;
                    (cs, t, seq.closed)
                } else {
                    return Err(RouteRefusal::NoItem);
                };
            let ro = re_outline(&circles, &touches, closed, interp, opts.tolerance)?;
            if let Some(e) = ro.intersections.first() {
                return Err(RouteRefusal::EnvelopesMeet {
                    segment: e.segment,
                    t: e.t,
                });
            }
            if let Some(&(i, j)) = ro.failed_pairs.first() {
                return Err(RouteRefusal::EliminationFailed { i, j });
            }
            let loop_note = ro.loops.first().map(|&(_, g0, g1)| {
                format!(
                    "an envelope runs backwards (local loop) for global t in [{g0:.4}, {g1:.4}]"
                )
            });
            crate::skin::mat_offset::outline(&ro.skin)?;
            Ok(ReItem {
                loop_note,
                outline: ro
                    .contours
                    .iter()
                    .map(|c| Path::polyline(c, true))
                    .collect(),
                skin: ro.skin,
            })
        })
        .collect()
}

/// Profile paths of the selected items by the MAT route: each item's exact offset, as long
/// as the items' paths stay apart (otherwise the profile must follow their union: `Err`).
pub fn re_profile(
    items: &[(&str, &ReItem)],
    side: ProfileSide,
    tool_radius: f64,
    tol: f64,
) -> Result<Vec<Path>, RouteRefusal> {
    let mut per_item: Vec<Vec<Path>> = Vec::new();
    for (name, it) in items {
        // The outer offset would still be exact (the region is the union of the disks),
        // but the item's outline for fills and gouge checks stays the Bézier skin, which
        // the exact offset of the RE skin can approach closer than the tool radius.
        if let Some(l) = &it.loop_note {
            return Err(RouteRefusal::Loop {
                name: name.to_string(),
                note: l.clone(),
            });
        }
        let p = mat_profile(&it.skin, side, tool_radius, tol).map_err(|source| {
            RouteRefusal::Profile {
                name: name.to_string(),
                source,
            }
        })?;
        per_item.push(p);
    }
    for a in 0..per_item.len() {
        for b in a + 1..per_item.len() {
            if paths_meet(&per_item[a], &per_item[b], tol) {
                return Err(RouteRefusal::Overlap {
                    a: items[a].0.to_string(),
                    b: items[b].0.to_string(),
                });
            }
        }
    }
    Ok(per_item.into_iter().flatten().collect())
}

/// The backboard of one item by the MAT route (outer offset by margin + tool radius).
pub fn re_backboard(item: &ReItem, distance: f64, tol: f64) -> Result<Vec<Path>, RouteRefusal> {
    Ok(mat_backboard(&item.skin, distance, tol)?)
}

/// Whether two sets of closed paths cross, touch within `tol`, or one lies inside the
/// other (flattened within `tol`).
fn paths_meet(a: &[Path], b: &[Path], tol: f64) -> bool {
    let fa: Vec<Vec<DVec2>> = a.iter().map(|p| p.flatten(tol)).collect();
    let fb: Vec<Vec<DVec2>> = b.iter().map(|p| p.flatten(tol)).collect();
    let bbox = |pts: &[DVec2]| {
        pts.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    };
    for pa in &fa {
        for pb in &fb {
            let ((la, ha), (lb, hb)) = (bbox(pa), bbox(pb));
            if la.x > hb.x + tol || lb.x > ha.x + tol || la.y > hb.y + tol || lb.y > ha.y + tol {
                continue;
            }
            if pa
                .first()
                .is_some_and(|&p| crate::geom::predicates::inside_even_odd(pb, p))
                || pb
                    .first()
                    .is_some_and(|&p| crate::geom::predicates::inside_even_odd(pa, p))
            {
                return true;
            }
            for i in 0..pa.len() {
                let s = Line::new(pa[i], pa[(i + 1) % pa.len()]);
                for j in 0..pb.len() {
                    let (q0, q1) = (pb[j], pb[(j + 1) % pb.len()]);
                    if s.distance(q0) <= tol
                        || Line::new(q0, q1).distance(s.p0) <= tol
                        || crosses(s.p0, s.p1, q0, q1)
                    {
                        return true;
                    }
                }
            }
        }
    }
    false
}

fn crosses(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> bool {
    let o = |a: DVec2, b: DVec2, c: DVec2| crate::geom::cross(b - a, c - a);
    (o(p0, p1, q0) > 0.0) != (o(p0, p1, q1) > 0.0) && (o(q0, q1, p0) > 0.0) != (o(q0, q1, p1) > 0.0)
}

/// The RE/MPH route against independent computation: on random admissible circle
/// sequences the profile lies at distance δ from the RE skin (the exact distance to the
/// union of its MAT disks) within the fitting tolerance and the program checks clean; on
/// the examples the RE and Bézier routes' profile regions differ by at most the skins'
/// Hausdorff distance plus the tolerances.
#[cfg(test)]
mod tests {
    use super::re_items;
    use crate::design::{Design, OutlineMethod};
    use crate::geom::{Circle, DVec2, Path};
    use crate::job::build::{BuildOptions, build_toolpath};
    use crate::job::check::check_config;
    use crate::job::outline::{OutlineOptions, design_outlines};
    use crate::machine::Profile;
    use crate::skin::mat_offset::region_distance;
    use crate::skin::re::Interp;
    use crate::toolpath::ops::{self, ProfileSide};
    use crate::toolpath::re_route::mat_profile;
    use crate::toolpath::region::Region;
    use geo::{Area, BooleanOps, Buffer};
    use proptest::prelude::*;

    /// The builtin GRBL router profile.
    fn router() -> Profile {
        let text = include_str!("../../machines/grbl-router.toml");
        Profile::from_toml(text, "grbl-router.toml").unwrap()
    }

    /// Biarc fitting tolerance of the tests (mm).
    const TOL: f64 = 0.01;

    fn design_of(cs: &[Circle], method: &str) -> Design {
        let list: Vec<String> = cs
            .iter()
            .map(|c| format!("[{}, {}, {}]", c.c.x, c.c.y, c.r))
            .collect();
        let text = format!(
            "version = 1\nunits = \"mm\"\n[[circles]]\nname = \"seq\"\nclosed = false\n\
             circles = [{}]\n[[operation]]\nkind = \"profile\"\nside = \"outside\"\n\
             depth = 2.0\nmethod = \"{method}\"\n",
            list.join(", ")
        );
        crate::design::load(&text, "random.toml").unwrap()
    }

    /// Open sequences inside the router's work area: steps longer than the radius changes.
    fn sequence() -> impl Strategy<Value = Vec<Circle>> {
        prop::collection::vec((-0.7f64..0.7, 9.0f64..16.0, 2.5f64..7.0), 3..6).prop_map(|steps| {
            let mut dir = 0.3f64;
            let mut p = DVec2::ZERO;
            let cs: Vec<Circle> = steps
                .iter()
                .map(|&(turn, len, r)| {
                    dir += turn;
                    p += len * DVec2::new(dir.cos(), dir.sin());
                    Circle::new(p, r)
                })
                .collect();
            // Moved so that the lowest circle edge sits 30 mm inside the work area's corner.
            let lo = cs.iter().fold(DVec2::splat(f64::INFINITY), |m, c| {
                m.min(c.c - DVec2::splat(c.r))
            });
            cs.iter()
                .map(|c| Circle::new(c.c - lo + DVec2::splat(30.0), c.r))
                .collect()
        })
    }

    fn samples(paths: &[Path], per_seg: usize) -> Vec<DVec2> {
        let mut v = Vec::new();
        for p in paths {
            for s in &p.segs {
                for k in 0..=per_seg {
                    v.push(s.eval(k as f64 / per_seg as f64));
                }
            }
        }
        v
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(8))]

        #[test]
        fn re_route_is_at_delta_and_checks_clean(cs in sequence(), ph in any::<bool>()) {
            let method = if ph { "mph" } else { "re" };
            let design = design_of(&cs, method);
            let profile = router();
            // Build-wide method: the items' outlines (the checker's design boundary) are then
            // the RE/MPH skins themselves, not the Bézier skins the route does not follow.
            let opts = BuildOptions {
                tolerance: TOL,
                method: if ph { OutlineMethod::Mph } else { OutlineMethod::Re },
                ..BuildOptions::default()
            };
            let built = build_toolpath(&design, &profile, &opts);
            prop_assume!(built.is_ok());
            let built = built.unwrap();
            prop_assume!(built.routes.iter().all(|r| r.route == method));
            // The same paths from the library, against the exact distance to the skin.
            let interp = if ph { Interp::PhQuintic } else { Interp::Cubic };
            let oo = OutlineOptions {
                tolerance: TOL,
                ..OutlineOptions::default()
            };
            let outlines = design_outlines(&design, &oo).unwrap();
            let items = re_items(&design, &[], &outlines, interp, &oo);
            let item = items[0].as_ref().unwrap();
            let r = profile.default_tool().unwrap().radius();
            let paths = mat_profile(&item.skin, ProfileSide::Outside, r, TOL).unwrap();
            for q in samples(&paths, 8) {
                let d = region_distance(&item.skin, q).unwrap();
                prop_assert!(d > 0.0 && (d - r).abs() <= TOL + 1e-9, "{q}: {d} vs {r}");
            }
            // The machine program passes the checker without errors.
            let g = crate::emit::gcode(
                &built.toolpath,
                &profile,
                &crate::emit::GcodeOptions {
                    job: "random".into(),
                    input_units: crate::machine::Units::Mm,
                    tolerance: TOL * 0.1,
                    check_work_area: true,
                },
            )
            .unwrap();
            let mut cfg = check_config(&profile, r);
            cfg.gouge_tolerance = cfg.gouge_tolerance.max(2.0 * TOL + 1e-3 + cfg.flatten_tolerance);
            let bounds = crate::job::check::design_boundaries(&built.outlines, true, TOL, 1.0);
            let report = crate::sim::check_text(crate::sim::Backend::Builtin, &g, &cfg, &bounds);
            prop_assert_eq!(report.errors(), 0, "{}", report);
        }
    }

    fn to_geo(paths: &[Path], tol: f64) -> geo::MultiPolygon<f64> {
        Region::from_paths(paths, tol).to_geo(tol)
    }

    /// Largest distance from the points of `a` to the polylines of `b` (both flattened).
    fn directed(a: &[Path], b: &[Path], tol: f64) -> f64 {
        let fb: Vec<Vec<DVec2>> = b.iter().map(|p| p.flatten(tol)).collect();
        let mut worst = 0.0f64;
        for p in a {
            for q in p.flatten(tol) {
                let d = fb
                    .iter()
                    .flat_map(|poly| {
                        (0..poly.len()).map(move |i| {
                            crate::geom::Line::new(poly[i], poly[(i + 1) % poly.len()]).distance(q)
                        })
                    })
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
            }
        }
        worst
    }

    #[test]
    fn re_and_bezier_routes_differ_by_the_skin_distance() {
        let r = 1.5;
        for name in ["circles", "ring_o", "brush", "loop", "snake", "neon_word"] {
            let path = format!("{}/examples/{name}.toml", env!("CARGO_MANIFEST_DIR"));
            let text = std::fs::read_to_string(&path).unwrap();
            let design = crate::design::load(&text, &path).unwrap();
            let oo = OutlineOptions {
                tolerance: TOL,
                ..OutlineOptions::default()
            };
            let outlines = design_outlines(&design, &oo).unwrap();
            let strokes = design.strokes().unwrap();
            for interp in [Interp::Cubic, Interp::PhQuintic] {
                let items = re_items(&design, &strokes, &outlines, interp, &oo);
                for (o, it) in outlines.iter().zip(&items) {
                    let Ok(it) = it else { continue };
                    // The skins' distance (both directions, flattened within TOL).
                    let e = directed(&o.contours, &it.outline, TOL).max(directed(
                        &it.outline,
                        &o.contours,
                        TOL,
                    ));
                    let bez = ops::profile(
                        &Region::from_paths(&o.contours, TOL),
                        ProfileSide::Outside,
                        r,
                        TOL * 0.1,
                    );
                    let Ok(re) = mat_profile(&it.skin, ProfileSide::Outside, r, TOL) else {
                        continue;
                    };
                    let (a, b) = (to_geo(&bez, TOL), to_geo(&re, TOL));
                    let bound = e + 3.0 * TOL;
                    // Each region lies within the other grown by the bound: nothing is left of
                    // the difference once the other is grown.
                    let a_out = a.difference(&b.buffer(bound)).unsigned_area();
                    let b_out = b.difference(&a.buffer(bound)).unsigned_area();
                    assert!(
                        a_out < 1e-6 * a.unsigned_area() && b_out < 1e-6 * b.unsigned_area(),
                        "{name}/{} {interp:?}: skins {e:.4} apart, regions leave {a_out} and {b_out}",
                        o.name
                    );
                }
            }
        }
    }
}
