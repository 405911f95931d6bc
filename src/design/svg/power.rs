//! Inkscape's Power Stroke: the centre line (`inkscape:original-d`) and the width points of
//! the path effect, read from the source (usvg draws only the filled outline).

use super::*;
use kurbo::{BezPath, PathEl};

/// An Inkscape Power Stroke path effect on an element: its centre line (`inkscape:original-d`)
/// and its width points (`offset_points="t,w | t,w | …"`: path time t, half width w in user
/// units, times `scale_width`).
pub(super) struct PowerStroke {
    /// The centre line, in the element's user units.
    pub(super) centre: usvg::tiny_skia_path::Path,
    /// (path time, half width) sorted by time.
    pub(super) points: Vec<(f64, f64)>,
    /// Whether the width runs to zero at the start / end (`zerowidth` caps, Inkscape's
    /// default); other caps keep the first / last point's width to the end.
    pub(super) taper: (bool, bool),
    /// Path time at the end of the centre line (its number of segments).
    pub(super) end: f64,
}

impl PowerStroke {
    /// Radius at each path time in `times`: the half widths interpolated linearly between
    /// the width points (Inkscape draws a smooth interpolating curve through them, by default
    /// centripetal Catmull–Rom, so between points the widths can differ from Inkscape's by
    /// that curve's bulge), tapered to `min_radius` at a zero-width cap, times `to_mm`.
    pub(super) fn radii(&self, times: &[f64], to_mm: f64, min_radius: f64) -> Vec<f64> {
        let mut pts = self.points.clone();
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        pts.insert(0, (0.0, if self.taper.0 { 0.0 } else { first.1 }));
        pts.push((self.end, if self.taper.1 { 0.0 } else { last.1 }));
        times
            .iter()
            .map(|&t| {
                let i = pts.partition_point(|p| p.0 <= t).clamp(1, pts.len() - 1);
                let (a, b) = (pts[i - 1], pts[i]);
                let f = if b.0 > a.0 {
                    ((t - a.0) / (b.0 - a.0)).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                (((1.0 - f) * a.1 + f * b.1) * to_mm).max(min_radius)
            })
            .collect()
    }
}

impl Ctx<'_> {
    /// The Inkscape Power Stroke on the element with id `id`, if it has one: an
    /// `inkscape:path-effect` reference to an effect with `effect="powerstroke"` and an
    /// `inkscape:original-d` centre line; what is wrong with a malformed one (the element is
    /// then skipped with that reason).
    pub(super) fn power_stroke(&self, id: &str) -> Result<Option<PowerStroke>, String> {
        let Some(node) = self.element(id) else {
            return Ok(None);
        };
        let (Some(effects), Some(centre)) = (
            node.attribute((INKSCAPE_NS, "path-effect")),
            node.attribute((INKSCAPE_NS, "original-d")),
        ) else {
            return Ok(None);
        };
        let effect = effects
            .split(';')
            .filter_map(|r| r.trim().strip_prefix('#'))
            .filter_map(|r| self.element(r))
            .find(|n| n.attribute("effect") == Some("powerstroke"));
        let Some(effect) = effect else {
            return Ok(None);
        };
        let bad = |m: String| m;
        let bez = BezPath::from_svg(centre).map_err(|e| {
            bad(format!(
                "centre line (inkscape:original-d) is not path data: {e}"
            ))
        })?;
        let mut pb = usvg::tiny_skia_path::PathBuilder::new();
        let mut end = 0.0;
        let mut started = false;
        let (mut first, mut current) = (kurbo::Point::ZERO, kurbo::Point::ZERO);
        for el in bez.elements() {
            if let Some(p) = el.end_point() {
                if let PathEl::MoveTo(_) = el {
                    first = p;
                }
                current = p;
            }
            let f = |p: kurbo::Point| (p.x as f32, p.y as f32);
            match *el {
                PathEl::MoveTo(p) => {
                    if started {
                        break; // Power Stroke draws the first subpath only.
                    }
                    started = true;
                    let (x, y) = f(p);
                    pb.move_to(x, y);
                }
                PathEl::LineTo(p) => {
                    let (x, y) = f(p);
                    pb.line_to(x, y);
                    end += 1.0;
                }
                PathEl::QuadTo(a, p) => {
                    let ((ax, ay), (x, y)) = (f(a), f(p));
                    pb.quad_to(ax, ay, x, y);
                    end += 1.0;
                }
                PathEl::CurveTo(a, b, p) => {
                    let ((ax, ay), (bx, by), (x, y)) = (f(a), f(b), f(p));
                    pb.cubic_to(ax, ay, bx, by, x, y);
                    end += 1.0;
                }
                PathEl::ClosePath => {
                    pb.close();
                    if current.distance(first) > 0.0 {
                        end += 1.0; // a closing line; a closing point adds no segment
                    }
                }
            }
        }
        let Some(path) = pb.finish() else {
            return Err(bad("centre line (inkscape:original-d) is empty".into()));
        };
        let scale_width = match effect.attribute("scale_width") {
            None => 1.0,
            Some(v) => v
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|w| w.is_finite() && *w > 0.0)
                .ok_or_else(|| bad(format!("scale_width {v:?} is not a positive number")))?,
        };
        let mut points = Vec::new();
        for item in effect
            .attribute("offset_points")
            .unwrap_or("")
            .split('|')
            .map(str::trim)
            .filter(|t| !t.is_empty())
        {
            let nums: Vec<Option<f64>> = item
                .split(',')
                .map(|v| v.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
                .collect();
            match nums[..] {
                [Some(t), Some(w)] if w > 0.0 => points.push((t, w * scale_width)),
                _ => {
                    return Err(bad(format!(
                        "width point {item:?} is not \"time,half-width\" with a positive width"
                    )));
                }
            }
        }
        if points.is_empty() {
            return Err(bad("has no width points (offset_points)".into()));
        }
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let zero = |key: &str| effect.attribute(key).is_none_or(|c| c == "zerowidth");
        Ok(Some(PowerStroke {
            centre: path,
            points,
            taper: (zero("start_linecap_type"), zero("end_linecap_type")),
            end,
        }))
    }
}
