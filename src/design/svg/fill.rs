//! Filled paths: each fill becomes a shape of its resolved region (see the module docs of
//! [`super`]).

use super::*;
use crate::geom::predicates::segments_intersect;

/// Most subpaths (rings) of one fill: resolving them compares every ring with every other.
const MAX_FILL_RINGS: usize = 2_000;

/// Most points one fill may flatten to in all its rings.
const MAX_FILL_POINTS: usize = 50_000;

/// Most edge crossings a self-crossing fill may have: resolving it under its fill rule
/// (a boolean union) costs O((n + k) log n) for n edges and k crossings.
const MAX_FILL_CROSSINGS: usize = 100_000;

/// Most edge pairs compared while counting crossings (pairs whose x ranges overlap).
const MAX_PAIR_TESTS: usize = 50_000_000;

/// Why the rings cannot be resolved within the budgets: more than [`MAX_FILL_CROSSINGS`]
/// crossings, or more than [`MAX_PAIR_TESTS`] edge pairs to compare. A sweep over the edges
/// in order of their smallest x compares the pairs whose x ranges overlap (exact
/// orientation predicates), leaving out edges next to each other in one ring.
fn crossing_budget(rings: &[Vec<DVec2>]) -> Option<String> {
    let edges: Vec<(DVec2, DVec2, usize, usize)> = rings
        .iter()
        .enumerate()
        .flat_map(|(r, ring)| {
            (0..ring.len()).map(move |i| (ring[i], ring[(i + 1) % ring.len()], r, i))
        })
        .collect();
    let mut order: Vec<usize> = (0..edges.len()).collect();
    let xmin = |e: &(DVec2, DVec2, usize, usize)| e.0.x.min(e.1.x);
    order.sort_by(|&a, &b| xmin(&edges[a]).total_cmp(&xmin(&edges[b])));
    let (mut crossings, mut tests) = (0usize, 0usize);
    for (k, &e) in order.iter().enumerate() {
        let (a, b, ra, ia) = edges[e];
        let xmax = a.x.max(b.x);
        for &f in &order[k + 1..] {
            let (c, d, rc, ic) = edges[f];
            if xmin(&edges[f]) > xmax {
                break;
            }
            tests += 1;
            if tests > MAX_PAIR_TESTS {
                return Some(format!(
                    "more than {MAX_PAIR_TESTS} pairs of its edges overlap; simplify the fill"
                ));
            }
            let n = rings[ra].len();
            if ra == rc && ((ia + 1) % n == ic || (ic + 1) % n == ia) {
                continue;
            }
            if segments_intersect(a, b, c, d) {
                crossings += 1;
                if crossings > MAX_FILL_CROSSINGS {
                    return Some(format!(
                        "its outline crosses itself more than {MAX_FILL_CROSSINGS} times; \
                         simplify the fill"
                    ));
                }
            }
        }
    }
    None
}

/// Whether every subpath of `data` is at most one straight segment (closed or not): such a
/// fill encloses no area. Read from the verbs, before any work.
fn encloses_nothing(data: &usvg::tiny_skia_path::Path) -> bool {
    use usvg::tiny_skia_path::PathVerb as V;
    let mut segments = 0usize;
    for v in data.verbs() {
        match v {
            V::Move => segments = 0,
            V::Line => segments += 1,
            V::Quad | V::Cubic => return false,
            V::Close => {}
        }
        if segments > 1 {
            return false;
        }
    }
    true
}

impl Ctx<'_> {
    /// The fill of `p` as a shape (see the module docs): subpaths closed and flattened within
    /// the tolerance in millimetres, resolved under `rule`, rounded like stroke points.
    /// A fill that encloses no area, or whose contours do not make a valid shape after
    /// rounding, is listed as skipped (a stroked path's empty fill, e.g. a straight line's,
    /// is not: the path was imported as a stroke).
    pub(super) fn fill_shape(
        &mut self,
        p: &usvg::Path,
        id: &str,
        fill: &usvg::Fill,
        stroked: bool,
        translucent: bool,
    ) {
        let rule = fill.rule();
        let t = p.abs_transform();
        let mm = |q: usvg::tiny_skia_path::Point| {
            let x = t.sx as f64 * q.x as f64 + t.kx as f64 * q.y as f64 + t.tx as f64;
            let y = t.ky as f64 * q.x as f64 + t.sy as f64 * q.y as f64 + t.ty as f64;
            self.to_mm(DVec2::new(x, y))
        };
        let name = if stroked {
            format!("{id}.fill")
        } else {
            id.to_string()
        };
        // Count before work: segments per subpath and subpaths.
        let data = p.data();
        let subpaths = data
            .verbs()
            .iter()
            .filter(|v| matches!(v, usvg::tiny_skia_path::PathVerb::Move))
            .count();
        if let Some(n) = longest_subpath(data)
            && n > MAX_ITEMS
        {
            let m = format!(
                "fill with a subpath of {n} segments, more than the limit {MAX_ITEMS} points \
                 of a contour; simplify the path"
            );
            self.skip(name, &m);
            return;
        }
        if encloses_nothing(data) {
            // Every subpath is one straight segment (a plotter's line list): the fill has no
            // area, however many subpaths it has.
            if !stroked {
                self.skip(name, "filled shape that encloses no area");
            }
            return;
        }
        if subpaths > MAX_FILL_RINGS {
            let m = format!("fill of {subpaths} subpaths, more than the limit {MAX_FILL_RINGS}");
            self.skip(name, &m);
            return;
        }
        let tol = self.opts.tolerance;
        let mut total = 0usize;
        let mut rings: Vec<Vec<DVec2>> = Vec::new();
        let mut cur: Vec<DVec2> = Vec::new();
        let mut start = DVec2::ZERO;
        for seg in p.data().segments() {
            use usvg::tiny_skia_path::PathSegment as S;
            if !matches!(seg, S::MoveTo(_) | S::Close) && cur.is_empty() {
                cur.push(start); // drawing on after a close starts at the subpath's start
            }
            let last = cur.last().copied().unwrap_or(start);
            match seg {
                S::MoveTo(q) => {
                    total += cur.len();
                    rings.push(std::mem::take(&mut cur));
                    start = mm(q);
                    cur.push(start);
                }
                S::LineTo(q) => cur.push(mm(q)),
                S::QuadTo(a, b) => flatten_segment(&[last, mm(a), mm(b)], tol, &mut cur),
                S::CubicTo(a, b, c) => flatten_segment(&[last, mm(a), mm(b), mm(c)], tol, &mut cur),
                S::Close => {
                    total += cur.len();
                    rings.push(std::mem::take(&mut cur));
                }
            }
            if total + cur.len() > MAX_FILL_POINTS {
                let m = format!(
                    "fill flattens to more than {MAX_FILL_POINTS} points within the tolerance; \
                     simplify the path or raise the tolerance"
                );
                self.skip(name, &m);
                return;
            }
        }
        rings.push(cur);
        rings.retain(|r| r.len() >= 3);
        let rule = match rule {
            usvg::FillRule::NonZero => crate::design::FillRule::Nonzero,
            usvg::FillRule::EvenOdd => crate::design::FillRule::Evenodd,
        };
        if let Some(m) = crossing_budget(&rings) {
            self.skip(name, &format!("fill not resolved: {m}"));
            return;
        }
        let region = resolve_rings(&rings, rule);
        if region.is_empty() {
            if !stroked {
                self.skip(name, "filled shape that encloses no area");
            }
            return;
        }
        let color = paint_color(fill.paint());
        if self.paint.is_empty() && self.strokes.is_empty() && self.covers_page(&region) {
            self.skip(
                name,
                "page background (a fill covering the whole page, painted first): not ink; \
                 fills of its colour knock out",
            );
            self.paint.background = Some(color.unwrap_or_else(|| paint::WHITE.to_string()));
            return;
        }
        let knockout = color.as_deref() == Some(paint::WHITE)
            || (color.is_some() && color == self.paint.background);
        if translucent && knockout {
            self.skip(
                name,
                &format!(
                    "translucent white or background-coloured fill (opacity below {}): \
                     neither ink nor a knockout",
                    paint::HIDE_OPACITY
                ),
            );
            return;
        }
        let region = paint::Region {
            name: self.unique(name),
            layer: self.path_layer.clone(),
            color,
            rings: region,
        };
        if translucent {
            self.paint.paint_translucent(region);
            return;
        }
        let knocked = knockout.then(|| region.name.clone());
        for gone in self.paint.paint(region, knockout) {
            self.skip(gone, "hidden: later fills cover it entirely");
        }
        if let Some(name) = knocked {
            self.skip(
                name,
                "white or background-coloured fill: a knockout, cut out of the fills under \
                 it, not ink itself",
            );
        }
    }

    /// Whether the rings' bounding box covers the page (within the tolerance).
    fn covers_page(&self, rings: &[Vec<DVec2>]) -> bool {
        let (lo, hi) = rings.iter().flatten().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let t = self.opts.tolerance;
        let page = DVec2::new(self.page_width, self.page_height) * MM_PER_PX;
        lo.x <= t && lo.y <= t && hi.x >= page.x - t && hi.y >= page.y - t
    }

    /// The visible regions as shapes, in paint order: rounded like stroke points, checked
    /// one by one (a region that does not make a valid shape is skipped with the reason).
    pub(super) fn finish_paint(&mut self) {
        let regions = std::mem::take(&mut self.paint.regions);
        for r in regions.into_iter().flatten() {
            let size = r
                .rings
                .iter()
                .flatten()
                .fold(1.0f64, |m, q| m.max(q.abs().max_element()));
            // usvg keeps f32 coordinates: digits past 1e-6 mm are noise. Points that
            // rounding brings within twice the design's near-repeat distance of their
            // predecessor go.
            let apart = 2.0 * (crate::design::NEAR_FRACTION * size).max(1.0 / ROUND);
            let contours: Vec<Vec<[f64; 2]>> = r
                .rings
                .iter()
                .map(|ring| {
                    let mut out: Vec<[f64; 2]> = Vec::with_capacity(ring.len());
                    for q in ring {
                        let v = [q.x, q.y].map(|c| (c * ROUND).round() / ROUND);
                        let far = |w: &[f64; 2]| (v[0] - w[0]).hypot(v[1] - w[1]) > apart;
                        if out.last().is_none_or(far) {
                            out.push(v);
                        }
                    }
                    while out.len() > 1
                        && out
                            .first()
                            .zip(out.last())
                            .is_some_and(|(f, l)| (f[0] - l[0]).hypot(f[1] - l[1]) <= apart)
                    {
                        out.pop();
                    }
                    out
                })
                .filter(|ring| ring.len() >= 3)
                .collect();
            if contours.is_empty() {
                self.skip(r.name, "its visible part encloses no area");
                continue;
            }
            let shape = Shape {
                name: r.name.clone(),
                fill_rule: None,
                contours,
                layer: r.layer,
                color: r.color,
            };
            match shape.validate(self.file, self.shapes.len()) {
                Ok(()) => self.shapes.push(shape),
                Err(e) => {
                    let part = e.part.as_ref().map_or(String::new(), |p| format!("{p}: "));
                    let reason = format!("its fill does not make a valid shape: {part}{}", e.kind);
                    self.skip(r.name, &reason);
                }
            }
        }
    }
}
