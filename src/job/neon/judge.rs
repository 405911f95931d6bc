//! Warnings on a neon sign's bill of materials ([`NeonBom::judge`]): tight bends, runs
//! that come closer than the channel width, counters the channels fill, and what the
//! rounding and the marks changed; the CSV of the bill ([`NeonBom::to_csv`]).

use super::{CloseRuns, MarkBom, NeonBom, NeonWarning, RoundReport, Run};
use crate::design::Design;
use crate::geom::{DVec2, cross};

/// Smallest island of board that the counter test reports, as the radius of a disk of
/// the island's area over the channel width: smaller islands between channels are slivers
/// the router clears anyway, not a letter's counter.
pub const MIN_ISLAND_OF_WIDTH: f64 = 0.25;

/// Flattening tolerance of the channel regions of the counter test, as a fraction of the
/// channel width (65 µm for a 6.5 mm channel): far below an island's size.
pub const ISLAND_FLATTEN_OF_WIDTH: f64 = 1e-2;

/// The islands of board that the channels enclose at the design's size and fill at the
/// built size `scale` (a letter's counter closing up): one point inside each (the mean of
/// its ring's vertices). The channels at the built size are the spines `spines` (closed
/// where `closed`) swept by a disk of radius width/2; at the design's size, scaled to the
/// built size, by width·scale/2, since s·(S/s ⊕ D_{w/2}) = S ⊕ D_{s·w/2}. The built
/// channels hold the scaled design ones, so each hole of theirs lies in one hole H of
/// the design's; an H that holds none (of area at least π(MIN_ISLAND_OF_WIDTH·w·s)², as
/// H itself: smaller holes are slivers of the union) is filled.
fn filled_islands(spines: &[Vec<DVec2>], closed: &[bool], width: f64, scale: f64) -> Vec<DVec2> {
    use crate::toolpath::ops::swept_region;
    use crate::toolpath::region::{Region, flatten_pline};
    use cavalier_contours::polyline::PlineSource;
    let tol = ISLAND_FLATTEN_OF_WIDTH * width;
    let channels = |half: f64| {
        let parts: Vec<Region> = spines
            .iter()
            .zip(closed)
            .map(|(p, &c)| swept_region(p, c, half, tol))
            .collect();
        Region::union(&parts, tol)
    };
    let (then, now) = (channels(width * scale / 2.0), channels(width / 2.0));
    let min_area = std::f64::consts::PI * (MIN_ISLAND_OF_WIDTH * width * scale).powi(2);
    let holes_now: Vec<DVec2> = now
        .contours
        .iter()
        .filter(|c| c.area() < -min_area)
        .filter_map(|c| c.iter_vertexes().next().map(|v| DVec2::new(v.x, v.y)))
        .collect();
    then.contours
        .iter()
        .filter(|h| h.area() < -min_area)
        .filter(|h| {
            !holes_now.iter().any(|p| {
                h.winding_number(cavalier_contours::core::math::Vector2::new(p.x, p.y)) != 0
            })
        })
        .map(|h| {
            let pts = flatten_pline(h, tol);
            pts.iter().copied().sum::<DVec2>() / pts.len().max(1) as f64
        })
        .collect()
}

/// Pairs of runs (polylines `polys`, names `names`) with two segments whose distance d lies
/// in [lo, hi): per pair the smallest such d and the midpoint of its closest points. Pairs
/// whose bounding boxes are `hi` apart are skipped.
fn close_runs(polys: &[Vec<DVec2>], names: &[String], lo: f64, hi: f64) -> Vec<CloseRuns> {
    let boxes: Vec<(DVec2, DVec2)> = polys
        .iter()
        .map(|p| {
            p.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), &q| (lo.min(q), hi.max(q)),
            )
        })
        .collect();
    let mut out = Vec::new();
    for i in 0..polys.len() {
        for j in i + 1..polys.len() {
            let (a, b) = (boxes[i], boxes[j]);
            let gap = (b.0 - a.1).max(a.0 - b.1).max(DVec2::ZERO);
            if gap.length() >= hi {
                continue;
            }
            let mut best = (f64::INFINITY, DVec2::ZERO);
            for s in polys[i].windows(2) {
                for u in polys[j].windows(2) {
                    let (d, m) = segment_distance(s[0], s[1], u[0], u[1]);
                    if d >= lo && d < best.0 {
                        best = (d, m);
                    }
                }
            }
            if best.0 < hi {
                out.push(CloseRuns {
                    runs: [names[i].clone(), names[j].clone()],
                    distance: best.0,
                    at: best.1.to_array(),
                });
            }
        }
    }
    out
}

/// Distance between segments ab and cd and the midpoint of the closest points (0 and the
/// crossing point when they cross).
pub(super) fn segment_distance(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> (f64, DVec2) {
    let foot = |p: DVec2, s: DVec2, e: DVec2| {
        let v = e - s;
        let l2 = v.length_squared();
        let t = if l2 > 0.0 {
            ((p - s).dot(v) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        s + v * t
    };
    let (r, s) = (b - a, d - c);
    let den = cross(r, s);
    if den != 0.0 {
        let t = cross(c - a, s) / den;
        let u = cross(c - a, r) / den;
        if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
            return (0.0, a + r * t);
        }
    }
    [
        (a, foot(a, c, d)),
        (b, foot(b, c, d)),
        (c, foot(c, a, b)),
        (d, foot(d, a, b)),
    ]
    .into_iter()
    .map(|(p, q)| (p.distance(q), 0.5 * (p + q)))
    .min_by(|x, y| x.0.total_cmp(&y.0))
    .unwrap_or((f64::INFINITY, a))
}

impl NeonBom {
    /// Sets the warnings for a design built at `scale` (1: as drawn): every tight bend
    /// (noting those that only the scaling made too tight, ρ/scale ≥ the minimum), and, when
    /// scaled, every pair of runs closer than the channel width that was not at the
    /// design's own size (distance/scale ≥ width): their channels merge.
    pub fn judge(&mut self, scale: f64) {
        self.scale = scale;
        let (min_r, width) = self.limits;
        let mm = self.mm;
        let mut w = Vec::new();
        for b in &self.tight {
            let what = if b.join {
                format!(
                    "a corner where the strokes join at \"{}\" (radius 0)",
                    b.at.stroke
                )
            } else {
                format!(
                    "bend radius {:.2} mm on stroke \"{}\" at t = {:.4}",
                    b.radius * mm,
                    b.at.stroke,
                    b.at.t
                )
            };
            let by_scale = scale != 1.0 && b.radius > 0.0 && b.radius / scale >= min_r;
            w.push(NeonWarning {
                kind: "bend".into(),
                message: format!(
                    "{}: {what}, at ({:.2}, {:.2}), is tighter than the flex's minimum {:.2} \
                     mm{}",
                    b.run,
                    b.at.x,
                    b.at.y,
                    min_r * mm,
                    if by_scale {
                        format!(
                            " since the design was scaled by {scale:.4} (it is {:.2} mm at \
                             the design's size)",
                            b.radius / scale * mm
                        )
                    } else {
                        String::new()
                    }
                ),
                at: [b.at.x, b.at.y],
            });
        }
        if scale < 1.0 {
            // A place where two runs are closer than the channel width now but were not at
            // the design's size: distance d with d < width ≤ d/scale.
            let names: Vec<String> = self.runs.iter().map(|r| r.name.clone()).collect();
            for c in close_runs(&self.spines, &names, width * scale, width) {
                {
                    w.push(NeonWarning {
                        kind: "merge".into(),
                        message: format!(
                            "{} and {}: their channels merge at ({:.2}, {:.2}): the spines \
                             are {:.2} mm apart, less than the channel width {:.2} mm, since \
                             the design was scaled by {scale:.4} ({:.2} mm apart at the \
                             design's size)",
                            c.runs[0],
                            c.runs[1],
                            c.at[0],
                            c.at[1],
                            c.distance * mm,
                            width * mm,
                            c.distance / scale * mm
                        ),
                        at: c.at,
                    });
                }
            }
            // Islands of board inside the channels (a letter's counter) that the scaled
            // channels fill.
            let closed: Vec<bool> = self.runs.iter().map(|r| r.closed).collect();
            for p in filled_islands(&self.spines, &closed, width, scale) {
                let near = self.nearest_stroke(p);
                w.push(NeonWarning {
                    kind: "merge".into(),
                    message: format!(
                        "{near}: the island of board at ({:.2}, {:.2}) that its channel \
                         goes around (a letter's counter) is cut away: the channel width \
                         {:.2} mm stays while the design was scaled by {scale:.4}",
                        p.x,
                        p.y,
                        width * mm
                    ),
                    at: p.to_array(),
                });
            }
        }
        // A run shorter than the cut unit: no flex is cut that short.
        let cut = self.flex.cut_unit_mm;
        for r in self.runs.iter().filter(|r| r.length_mm < cut) {
            let start = [r.at.x, r.at.y];
            w.push(NeonWarning {
                kind: "short".into(),
                message: format!(
                    "{} (strokes {}): {:.2} mm of flex is shorter than the cut unit {:.2} mm; \
                     set [neon] min_run_length to make such runs marks (channel cut, no \
                     flex, no wire holes)",
                    r.name,
                    r.strokes
                        .iter()
                        .map(|s| format!("\"{s}\""))
                        .collect::<Vec<_>>()
                        .join(", "),
                    r.length_mm,
                    cut
                ),
                at: start,
            });
        }
        w.extend(self.round_warnings.iter().cloned());
        self.warnings = w;
    }

    /// Records what `round_bends` did: per run the bends rounded and the largest
    /// deviation (design units), and its warnings.
    pub fn set_rounding(&mut self, reports: &[RoundReport], warnings: Vec<NeonWarning>) {
        for r in &mut self.runs {
            let rep = reports.iter().find(|x| x.run == r.name);
            r.rounded_bends = Some(rep.map_or(0, |x| x.rounded));
            r.rounding_deviation_mm = Some(rep.map_or(0.0, |x| x.deviation * self.mm));
        }
        self.round_warnings = warnings;
        self.judge(self.scale);
    }

    /// Adds the marks (runs shorter than `min_run_length`, see `split_marks`) with their
    /// lengths (design units).
    pub fn set_marks(&mut self, design: &Design, marks: &[(Run, f64)]) {
        self.marks = marks
            .iter()
            .map(|(run, len)| MarkBom {
                name: run.name.clone(),
                strokes: run
                    .legs
                    .iter()
                    .map(|l| design.stroke[l.stroke].name.clone())
                    .collect(),
                length_mm: len * self.mm,
            })
            .collect();
    }

    /// The run and stroke whose spine comes nearest to `p`, as `run N, stroke "S"`.
    fn nearest_stroke(&self, p: DVec2) -> String {
        let mut best = (f64::INFINITY, 0, 0);
        for (k, pts) in self.spines.iter().enumerate() {
            for (i, q) in pts.iter().enumerate() {
                let d = q.distance(p);
                if d < best.0 {
                    best = (d, k, self.spine_legs[k][i]);
                }
            }
        }
        match self.runs.get(best.1) {
            Some(r) => format!("{}, stroke \"{}\"", r.name, r.strokes[best.2]),
            None => "the sign".into(),
        }
    }

    /// The bill of materials as CSV: a header, one row per run (strokes joined by `;`),
    /// and a total row. Fields with a comma, quote or line break are quoted (RFC 4180).
    pub fn to_csv(&self) -> String {
        fn field(s: &str) -> String {
            if s.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", s.replace('"', "\"\""))
            } else {
                s.to_string()
            }
        }
        let mut out = String::from(
            "run,strokes,closed,length_mm,cut_length_mm,min_bend_radius_mm,at_stroke,at_x,at_y\n",
        );
        for r in &self.runs {
            out.push_str(&format!(
                "{},{},{},{:.2},{:.2},{},{},{:.3},{:.3}\n",
                field(&r.name),
                field(&r.strokes.join(";")),
                r.closed,
                r.length_mm,
                r.cut_length_mm,
                if r.min_bend_radius_mm.is_finite() {
                    format!("{:.3}", r.min_bend_radius_mm)
                } else {
                    "inf".into()
                },
                field(&r.at.stroke),
                r.at.x,
                r.at.y
            ));
        }
        out.push_str(&format!(
            "total,,,{:.2},{:.2},,,,\n",
            self.total_length_mm, self.total_cut_length_mm
        ));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring spine of radius R with channels of width w at scale s: the counter (a disk
    /// of radius s·(R − w/2) at the design's size, scaled) fills when R ≤ w/2.
    #[test]
    fn ring_counter_fills_when_the_ring_is_narrower_than_the_channel() {
        let ring = |r: f64| -> Vec<DVec2> {
            (0..720)
                .map(|k| DVec2::from_angle(std::f64::consts::TAU * k as f64 / 720.0) * r)
                .collect()
        };
        let (w, s) = (10.0, 0.2);
        assert_eq!(filled_islands(&[ring(4.0)], &[true], w, s).len(), 1);
        assert!(filled_islands(&[ring(6.0)], &[true], w, s).is_empty());
    }
}
