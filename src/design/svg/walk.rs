//! The walk over usvg's tree: groups (layers, opacity), then per path its fill (a
//! shape) and its stroke (one stroke per subpath: flattened, cleaned and fitted), and the
//! strokes hidden by later fills.

use super::*;

/// Distance (mm) from a subpath's last point to its start below which `Z` adds no closing
/// segment (the path is already back at its start).
const CLOSE_GAP: f64 = 1e-9;

/// Accuracy of the nearest-point search that gives a flattened point its path time, as a
/// fraction of the tolerance (Power Stroke widths are looked up by path time).
const TIME_ACCURACY: f64 = 1e-9;

/// Relative difference between the drawn and the visible length of a stroke below which
/// no later fill hides any of it (the stroke is kept as fitted).
const SEEN_WHOLE: f64 = 1e-9;

impl Ctx<'_> {
    pub(super) fn to_mm(&self, p: DVec2) -> DVec2 {
        DVec2::new(p.x * MM_PER_PX, (self.page_height - p.y) * MM_PER_PX)
    }

    pub(super) fn group(&mut self, g: &usvg::Group) {
        let outer = self.layer.clone();
        let outer_opacity = self.opacity;
        self.opacity *= f64::from(g.opacity().get());
        if let Some(label) = self.element(g.id()).and_then(layer_label) {
            self.layer = Some(label.to_string());
        }
        for node in g.children() {
            match node {
                usvg::Node::Group(g) => self.group(g),
                usvg::Node::Path(p) => self.path(p),
                usvg::Node::Image(_) | usvg::Node::Text(_) => {}
            }
        }
        self.layer = outer;
        self.opacity = outer_opacity;
    }

    /// The name of a usvg path: its id, or `<path> #k` (k-th path in paint order), after
    /// its layer's label and a slash (`Layer 1/path12`) when it lies in an Inkscape layer.
    /// Sets the path's layer: from the source when the path has an id (usvg may fold the
    /// layer's group away), else the layer being walked.
    pub(super) fn element_id(&mut self, id: &str) -> String {
        self.counter += 1;
        self.path_layer = match self.element(id) {
            Some(n) => n
                .ancestors()
                .skip(1)
                .find_map(layer_label)
                .map(str::to_string),
            None => self.layer.clone(),
        };
        let own = if id.is_empty() {
            format!("<path> #{}", self.counter - 1)
        } else {
            id.to_string()
        };
        match &self.path_layer {
            Some(l) => format!("{l}/{own}"),
            None => own,
        }
    }

    pub(super) fn skip(&mut self, id: String, reason: &str) {
        self.skipped.push(Skipped {
            id,
            reason: reason.to_string(),
        });
    }

    pub(super) fn warn(&mut self, id: String, message: String) {
        self.warnings.push(Skipped {
            id,
            reason: message,
        });
    }

    /// Import one path: its fill as a shape, its stroke (one per subpath) as strokes; what
    /// cannot be used is skipped with the reason, never failing the import.
    pub(super) fn path(&mut self, p: &usvg::Path) {
        let id = self.element_id(p.id());
        if !p.id().is_empty() {
            self.seen.insert(p.id().to_string());
        }
        if !p.is_visible() {
            let reason = if p.fill().is_none() && p.stroke().is_none() {
                let width = self
                    .element(p.id())
                    .and_then(|n| inherited(n, "stroke-width", &self.sheet));
                match width {
                    Some(w) if w.trim().parse::<f64>().is_ok_and(|v| v <= 0.0) => format!(
                        "stroke-width {}: a stroke of zero or negative width draws nothing, \
                         and it has no fill",
                        w.trim()
                    ),
                    _ => "neither stroked nor filled".to_string(),
                }
            } else {
                "hidden (visibility: hidden)".to_string()
            };
            self.skip(id, &reason);
            return;
        }
        let power = match self.power_stroke(p.id()) {
            Ok(ps) => ps,
            Err(reason) => {
                self.skip(id, &format!("Power Stroke {reason}"));
                return;
            }
        };
        // A fully transparent fill (fill-opacity 0, or the colour `transparent`) paints
        // nothing: it is no area to engrave; nor does one fainter than MIN_INK_OPACITY.
        let group = self.opacity;
        let alpha = move |a: usvg::Opacity| f64::from(a.get()) * group;
        let fill = p
            .fill()
            .filter(|f| alpha(f.opacity()) >= paint::MIN_INK_OPACITY);
        let stroke = p
            .stroke()
            .filter(|s| alpha(s.opacity()) >= paint::MIN_INK_OPACITY);
        if power.is_none()
            && let Some(fill) = fill
        {
            let translucent = alpha(fill.opacity()) < paint::HIDE_OPACITY;
            self.fill_shape(p, &id, fill, stroke.is_some(), translucent);
        }
        let faint = |a: f64, what: &str| {
            if a <= 0.0 {
                format!("its {what} is fully transparent")
            } else {
                format!(
                    "its {what} is drawn at opacity {a:.3}, below {} (not ink)",
                    paint::MIN_INK_OPACITY
                )
            }
        };
        let stroke_width = match (&power, stroke) {
            (Some(_), _) => 0.0,
            (None, Some(stroke)) => stroke.width().get() as f64,
            (None, None) => {
                let no_fill = match p.fill() {
                    Some(f) if fill.is_none() => Some(faint(alpha(f.opacity()), "fill")),
                    _ => None,
                };
                match (p.stroke(), no_fill) {
                    (None, None) if p.fill().is_none() => {
                        self.skip(id, "neither stroked nor filled")
                    }
                    (None, Some(f)) => self.skip(id, &format!("{f} and it has no stroke")),
                    (Some(s), f) => {
                        let s = faint(alpha(s.opacity()), "stroke");
                        match f {
                            Some(f) => self.skip(id, &format!("{f}; {s}")),
                            None if p.fill().is_none() => self.skip(id, &s),
                            None => self.skip(format!("{id} (stroke)"), &s),
                        }
                    }
                    (None, None) => {}
                }
                return;
            }
        };
        let t = p.abs_transform();
        let scale = ((t.sx as f64 * t.sy as f64 - t.kx as f64 * t.ky as f64).abs()).sqrt();
        let width_mm = stroke_width * scale * MM_PER_PX;
        let widths = match self.widths(p.id()) {
            Ok(w) => w,
            Err(reason) => {
                self.skip(id, &reason);
                return;
            }
        };
        let data = match &power {
            Some(ps) => ps.centre.clone(),
            None => p.data().clone(),
        };
        // Count before work: a subpath of more segments than a stroke may have points is
        // refused before it is flattened.
        if let Some(n) = longest_subpath(&data)
            && n > MAX_ITEMS
        {
            self.skip(
                id,
                &format!(
                    "a subpath of {n} segments, more than the limit {MAX_ITEMS} points of a \
                     stroke; simplify the path"
                ),
            );
            return;
        }
        let mut segment = 0usize;
        let map = |q: usvg::tiny_skia_path::Point| {
            let x = t.sx as f64 * q.x as f64 + t.kx as f64 * q.y as f64 + t.tx as f64;
            let y = t.ky as f64 * q.x as f64 + t.sy as f64 * q.y as f64 + t.ty as f64;
            DVec2::new(x, y)
        };
        let tol = self.opts.tolerance;
        let mut subpaths: Vec<Subpath> = Vec::new();
        let mut cur: Option<(Subpath, DVec2, DVec2)> = None; // (subpath, start, in-tangent)
        let mut first_tangent = DVec2::ZERO;
        let mut too_many = false;
        let finish = |cur: &mut Option<(Subpath, DVec2, DVec2)>, out: &mut Vec<Subpath>| {
            if let Some((s, _, _)) = cur.take()
                && s.pts.len() >= 2
            {
                out.push(s);
            }
        };
        for seg in data.segments() {
            use usvg::tiny_skia_path::PathSegment as S;
            let ctrl: Vec<DVec2> = match seg {
                S::MoveTo(q) => {
                    finish(&mut cur, &mut subpaths);
                    let q = self.to_mm(map(q));
                    cur = Some((
                        Subpath {
                            pts: vec![q],
                            nodes: vec![(0, 0.0)],
                            closed: false,
                            times: vec![segment as f64],
                        },
                        q,
                        DVec2::ZERO,
                    ));
                    continue;
                }
                S::LineTo(q) => vec![map(q)],
                S::QuadTo(a, b) => vec![map(a), map(b)],
                S::CubicTo(a, b, c) => vec![map(a), map(b), map(c)],
                S::Close => {
                    if let Some((s, start, tin)) = cur.as_mut() {
                        let last = *s.pts.last().unwrap_or(start);
                        let mut tin = *tin;
                        if last.distance(*start) > CLOSE_GAP {
                            segment += 1;
                            let (a, b) = tangents(&[last, *start]);
                            let k = s.pts.len() - 1;
                            if let Some(n) = s.nodes.last_mut()
                                && n.0 == k
                            {
                                n.1 = turn(tin, a);
                            }
                            s.pts.push(*start);
                            s.times.push(segment as f64);
                            s.nodes.push((s.pts.len() - 1, 0.0));
                            tin = b;
                        }
                        // The closing node: from the last segment into the first.
                        s.nodes[0].1 = turn(tin, first_tangent);
                        s.closed = true;
                    }
                    finish(&mut cur, &mut subpaths);
                    continue;
                }
            };
            let Some((s, _, tin)) = cur.as_mut() else {
                continue;
            };
            let prev = *s.pts.last().unwrap_or(&DVec2::ZERO);
            let mut full = vec![prev];
            full.extend(ctrl.iter().map(|&q| self.to_mm(q)));
            let (a, b) = tangents(&full);
            let index = segment;
            segment += 1;
            if a == DVec2::ZERO {
                continue; // a zero-length segment
            }
            let k = s.pts.len() - 1;
            if k == 0 {
                first_tangent = a;
            }
            if let Some(n) = s.nodes.last_mut()
                && n.0 == k
            {
                n.1 = turn(*tin, a);
            }
            let from = s.pts.len();
            flatten_segment(&full, 0.1 * tol, &mut s.pts);
            if s.pts.len() > MAX_FLAT_POINTS {
                too_many = true;
                break;
            }
            if let Some(ps) = &power {
                // Path times of the flattened points, and a point at every width point
                // inside the segment, so the widths are sampled where they turn.
                let mut timed: Vec<(f64, DVec2)> = s.pts[from..]
                    .iter()
                    .map(|&q| {
                        (
                            index as f64 + segment_time(&full, q, TIME_ACCURACY * tol),
                            q,
                        )
                    })
                    .collect();
                for &(t, _) in &ps.points {
                    let f = t - index as f64;
                    if f > 0.0 && f < 1.0 {
                        timed.push((t, segment_point(&full, f)));
                    }
                }
                timed.sort_by(|a, b| a.0.total_cmp(&b.0));
                s.pts.truncate(from);
                for (t, q) in timed {
                    s.pts.push(q);
                    s.times.push(t);
                }
            }
            s.nodes.push((s.pts.len() - 1, 0.0));
            *tin = b;
        }
        finish(&mut cur, &mut subpaths);
        if too_many {
            self.skip(
                id,
                &format!(
                    "a subpath flattens to more than {MAX_FLAT_POINTS} points within the \
                     tolerance; simplify the path or raise the tolerance"
                ),
            );
            return;
        }
        if subpaths.is_empty() {
            self.skip(id, "stroked path of zero length");
            return;
        }
        if power.is_some() && subpaths.len() > 1 {
            // Inkscape applies Power Stroke to the first subpath only.
            subpaths.truncate(1);
            self.skip(
                format!("{id} (subpaths after the first)"),
                "Power Stroke draws only a path's first subpath",
            );
        }
        // A Power Stroke is drawn as its filled outline: its colour is the fill's.
        let color = match &power {
            Some(_) => p.fill().and_then(|f| paint_color(f.paint())),
            None => p.stroke().and_then(|st| paint_color(st.paint())),
        };
        let many = subpaths.len() > 1;
        for (j, mut sp) in subpaths.into_iter().enumerate() {
            fit::clean(&mut sp, self.opts.tolerance);
            let name = if many {
                format!("{id}.{j}")
            } else {
                id.clone()
            };
            let name = self.unique(name);
            let radii = match &power {
                Some(ps) => ps.radii(&sp.times, scale * MM_PER_PX, 0.5 * self.opts.tolerance),
                None => self.radii(&sp.pts, width_mm, widths.as_deref(), scale),
            };
            let mut fitted = self
                .fit_subpath(&name, &sp, &radii)
                .map_err(str::to_string)
                .and_then(|(s, dev)| self.usable(s).map(|s| (s, dev)));
            // Beyond the tolerance: try again with the cusps inside segments as corners.
            if fitted
                .as_ref()
                .is_ok_and(|(_, dev)| *dev > self.opts.tolerance)
            {
                let mut cusped = sp.clone();
                if fit::mark_cusps(&mut cusped, self.opts.tolerance) {
                    let again = self
                        .fit_subpath(&name, &cusped, &radii)
                        .map_err(str::to_string)
                        .and_then(|(s, dev)| self.usable(s).map(|s| (s, dev)));
                    let better = |a: &(Stroke, f64), b: &(Stroke, f64)| a.1 < b.1;
                    if let (Ok(a), Ok(b)) = (&again, &fitted)
                        && better(a, b)
                    {
                        fitted = again;
                    }
                }
            }
            match fitted {
                Ok((mut s, dev)) => {
                    self.max_deviation = self.max_deviation.max(dev);
                    s.layer = self.path_layer.clone();
                    s.color = color.clone();
                    if dev > self.opts.tolerance {
                        self.warn(
                            name,
                            format!(
                                "the stroke strays {dev:.4} mm from the drawn one, more than \
                                 the tolerance {} mm",
                                self.opts.tolerance
                            ),
                        );
                    }
                    self.strokes.push(s);
                    self.stroke_src.push(StrokeSrc {
                        seq: self.paint.seq,
                        pts: sp.pts,
                        radii,
                        closed: sp.closed,
                    });
                }
                Err(reason) => self.skip(name, &reason),
            }
        }
        self.paint.seq += 1;
    }

    /// Strokes painted before a fill that hides (see [`paint`]) lose the runs of their
    /// centre line the fill covers: a stroke covered entirely is listed as hidden, one
    /// covered in part becomes one stroke per visible run (fitted as any subpath, with the
    /// radii of the nearest point of the drawn line), with a warning; the others are kept
    /// as they were.
    pub(super) fn hide_strokes(&mut self) {
        let strokes = std::mem::take(&mut self.strokes);
        let srcs = std::mem::take(&mut self.stroke_src);
        let tol = self.opts.tolerance;
        for (s, src) in strokes.into_iter().zip(srcs) {
            let mut line = src.pts.clone();
            if src.closed && line.first() != line.last() {
                line.push(line[0]);
            }
            let reach = src.radii.iter().copied().fold(0.0, f64::max);
            let Some(runs) = self.paint.visible_lines(src.seq, &line, reach) else {
                self.strokes.push(s);
                continue;
            };
            let length = |l: &[DVec2]| l.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
            let (drawn, seen) = (length(&line), runs.iter().map(|r| length(r)).sum::<f64>());
            if runs.len() == 1 && (drawn - seen).abs() <= SEEN_WHOLE * drawn.max(1.0) {
                self.strokes.push(s);
                continue;
            }
            let runs: Vec<Vec<DVec2>> = runs.into_iter().filter(|r| length(r) > tol).collect();
            if runs.is_empty() {
                self.skip(s.name, "hidden: later fills cover its line entirely");
                continue;
            }
            let drawn_line = fit::Polyline::new(&line);
            let mut radii_of_line = src.radii.clone();
            if radii_of_line.len() < line.len() {
                radii_of_line.push(src.radii[0]);
            }
            self.warn(
                s.name.clone(),
                format!(
                    "later fills hide {:.1} of its {:.1} mm: {} visible run(s) kept",
                    drawn - seen,
                    drawn,
                    runs.len()
                ),
            );
            for (k, run) in runs.into_iter().enumerate() {
                let name = if k == 0 {
                    s.name.clone()
                } else {
                    self.unique(s.name.clone())
                };
                let mut sp = Subpath::polyline(run);
                fit::clean(&mut sp, tol);
                let radii: Vec<f64> = sp
                    .pts
                    .iter()
                    .map(|&q| {
                        let (_, i, f) = drawn_line.nearest(q);
                        let r0 = radii_of_line[i];
                        let r1 = radii_of_line.get(i + 1).copied().unwrap_or(r0);
                        r0 + f * (r1 - r0)
                    })
                    .collect();
                let fitted = self
                    .fit_subpath(&name, &sp, &radii)
                    .map_err(str::to_string)
                    .and_then(|(t, dev)| self.usable(t).map(|t| (t, dev)));
                match fitted {
                    Ok((mut t, dev)) => {
                        self.max_deviation = self.max_deviation.max(dev);
                        t.layer = s.layer.clone();
                        t.color = s.color.clone();
                        self.strokes.push(t);
                    }
                    Err(reason) => {
                        self.skip(name, &format!("visible run of a hidden stroke: {reason}"))
                    }
                }
            }
        }
    }

    /// `s` if it makes a valid design on its own (split at its corners and validated as
    /// loading does), else the reason it does not.
    pub(super) fn usable(&self, s: Stroke) -> Result<Stroke, String> {
        let mut d = Design::empty(self.file);
        d.stroke.push(s.clone());
        d.expand()
            .and_then(|()| crate::design::validate(&d))
            .map_err(|e| reason_of(&e))?;
        Ok(s)
    }

    /// `name`, or `name~k` with the least k ≥ 1 not yet given when `name` is taken: O(1)
    /// amortised (a set of the names given and the next k to try per base name).
    pub(super) fn unique(&mut self, name: String) -> String {
        if self.names.insert(name.clone()) {
            return name;
        }
        let mut k = self.suffix.get(&name).copied().unwrap_or(1);
        loop {
            let candidate = format!("{name}~{k}");
            k += 1;
            if self.names.insert(candidate.clone()) {
                self.suffix.insert(name, k);
                return candidate;
            }
        }
    }

    /// The source element with id `id` (usvg keeps ids but not custom or Inkscape
    /// attributes, which are read from the source).
    pub(super) fn element(&self, id: &str) -> Option<roxmltree::Node<'_, '_>> {
        self.ids.get(id).copied()
    }

    /// The `data-skinpath-widths` of the element with id `id`, if any; what is wrong with
    /// it otherwise.
    pub(super) fn widths(&self, id: &str) -> Result<Option<Vec<f64>>, String> {
        let Some(node) = self.element(id) else {
            return Ok(None);
        };
        let Some(v) = node.attribute("data-skinpath-widths") else {
            return Ok(None);
        };
        let mut out = Vec::new();
        for tok in v
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
        {
            match tok.parse::<f64>() {
                Ok(w) if w.is_finite() && w > 0.0 => out.push(w),
                _ => {
                    return Err(format!(
                        "data-skinpath-widths value {tok:?} is not a positive number"
                    ));
                }
            }
        }
        if out.len() < 2 {
            return Err(format!(
                "data-skinpath-widths needs at least two widths (start and end), got {}",
                out.len()
            ));
        }
        Ok(Some(out))
    }
}
