//! The drawing's layers under their budgets: what each layer may hold, what it has drawn,
//! and the simplification of polylines and travel chains to the output's pixel.

use super::{Detail, Drawing, RAPID_COLOR, Rgb, Style};
use glam::DVec2;

/// What one layer of the drawing may hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerBudget {
    /// Drawn elements (paths, circles).
    pub elements: usize,
    /// Polyline points over all its paths.
    pub points: usize,
    /// Raster ink: the area its strokes cover, counted as (length + width) · width per path,
    /// in pixels² (rasterising costs about this many pixel writes; ignored for SVG).
    pub ink: f64,
}

/// Cut contours and ramps: a million points, 10⁵ paths, 4·10⁷ px² of ink (about 15 times a
/// 1600 × 1600 image covered; tiny-skia strokes some 10⁷ px² a second).
pub const CUT_BUDGET: LayerBudget = LayerBudget {
    elements: 100_000,
    points: 1_000_000,
    ink: 4.0e7,
};
/// Rapids and travels.
pub const RAPID_BUDGET: LayerBudget = LayerBudget {
    elements: 50_000,
    points: 500_000,
    ink: 2.0e7,
};
/// Start markers, order numbers and direction arrows.
pub const MARK_BUDGET: LayerBudget = LayerBudget {
    elements: 20_000,
    points: 100_000,
    ink: 1.0e7,
};
/// Finding rings and numbers.
pub const FINDING_BUDGET: LayerBudget = LayerBudget {
    elements: 20_000,
    points: 100_000,
    ink: 1.0e7,
};

/// What a layer of the drawing has drawn against its [`LayerBudget`]; the first elements
/// in drawing order are drawn, the layer stops at the first that would exceed a budget.
pub(super) struct Layer {
    pub(super) name: &'static str,
    pub(super) budget: LayerBudget,
    pub(super) detail: Detail,
    pub(super) elements: usize,
    pub(super) points: usize,
    pub(super) ink: f64,
    pub(super) full: bool,
    /// Elements left out once the budget was reached.
    pub(super) left_out: usize,
    /// Whether the last element drawn was cut short at the budget.
    pub(super) truncated: bool,
    /// The last dot (a path shorter than a pixel) drawn and its colour: the next one of
    /// that colour within a pixel of it merges into it.
    pub(super) last_dot: Option<(DVec2, Rgb)>,
}

impl Layer {
    pub(super) fn new(name: &'static str, budget: LayerBudget, detail: Detail) -> Layer {
        Layer {
            name,
            budget,
            detail,
            elements: 0,
            points: 0,
            ink: 0.0,
            full: false,
            left_out: 0,
            truncated: false,
            last_dot: None,
        }
    }

    /// Whether an element of `points` points, `length` long and `width` wide (page mm)
    /// fits; counts it when it does, and as left out when it does not.
    pub(super) fn admit(&mut self, points: usize, length: f64, width: f64) -> bool {
        let ink = if self.detail.raster {
            (length + width) * width / (self.detail.pixel * self.detail.pixel)
        } else {
            0.0
        };
        if !self.full
            && (self.elements + 1 > self.budget.elements
                || self.points + points > self.budget.points
                || self.ink + ink > self.budget.ink)
        {
            self.full = true;
        }
        if self.full {
            self.left_out += 1;
            return false;
        }
        self.elements += 1;
        self.points += points;
        self.ink += ink;
        true
    }

    /// Admits a polyline of page points stroked `width` wide in `color`, simplified to the
    /// pixel. A polyline shorter than a pixel is a dot: dropped when `dots` is false
    /// (rapids), merged into the previous dot when that has its colour and lies within a
    /// pixel. None when nothing is drawn.
    pub(super) fn polyline(
        &mut self,
        pts: &[DVec2],
        width: f64,
        color: Rgb,
        dots: bool,
    ) -> Option<Vec<DVec2>> {
        let pts = simplify(pts, self.detail.pixel);
        let first = *pts.first()?;
        let length: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
        if pts.len() <= 2 && length < self.detail.pixel {
            let merges = self
                .last_dot
                .is_some_and(|(d, c)| c == color && d.distance(first) < self.detail.pixel);
            if !dots || merges || !self.admit(2, 0.0, width) {
                return None;
            }
            self.last_dot = Some((first, color));
            return Some(if pts.len() == 2 {
                pts
            } else {
                vec![first, first]
            });
        }
        self.fit(pts, width)
    }

    /// Admits a polyline stroked `width` wide, or as much of its start as the budget holds
    /// (then the layer is full).
    pub(super) fn fit(&mut self, mut pts: Vec<DVec2>, width: f64) -> Option<Vec<DVec2>> {
        if !self.full && self.elements + 1 > self.budget.elements {
            self.full = true;
        }
        if self.full {
            self.left_out += 1;
            return None;
        }
        // Ink per page mm of length (the width term is the round caps).
        let per_mm = if self.detail.raster {
            width / (self.detail.pixel * self.detail.pixel)
        } else {
            0.0
        };
        let mut ink = self.ink + width * per_mm;
        let mut taken = 1;
        for (i, w) in pts.windows(2).enumerate() {
            let more = w[0].distance(w[1]) * per_mm;
            if self.points + i + 2 > self.budget.points || ink + more > self.budget.ink {
                break;
            }
            ink += more;
            taken = i + 2;
        }
        if taken < pts.len() {
            self.full = true;
            if taken < 2 {
                self.left_out += 1;
                return None;
            }
            self.truncated = true;
            pts.truncate(taken);
        }
        self.elements += 1;
        self.points += taken;
        self.ink = ink;
        Some(pts)
    }

    /// The legend's note when the layer left something out.
    pub(super) fn note(&self) -> Option<String> {
        (self.left_out > 0 || self.truncated).then(|| {
            format!(
                "preview limit: {} of {} {} drawn{} (the first in program order)",
                self.elements,
                self.elements + self.left_out,
                self.name,
                if self.truncated {
                    ", the last in part"
                } else {
                    ""
                }
            )
        })
    }
}

/// A path of connected travels being collected: its points simplified to the pixel as they
/// come (see [`simplify`]), at most `cap` of them (then it is drawn and a new one starts).
pub(super) struct Chain {
    pixel: f64,
    cap: usize,
    pts: Vec<DVec2>,
    /// The last point added (kept or not): the path's end.
    end: Option<DVec2>,
}

impl Chain {
    pub(super) fn new(pixel: f64, cap: usize) -> Chain {
        Chain {
            pixel,
            cap: cap.max(2),
            pts: Vec::new(),
            end: None,
        }
    }

    /// Adds a travel through page points `pts`; one that does not start where the path
    /// ends starts a new path.
    pub(super) fn extend(
        &mut self,
        pts: &[DVec2],
        page: &mut Drawing,
        layer: &mut Layer,
        width: f64,
    ) {
        let Some(&first) = pts.first() else {
            return;
        };
        if self.end != Some(first) {
            self.flush(page, layer, width);
            self.pts.push(first);
        }
        for &p in &pts[1..] {
            if self.pts.last().is_some_and(|l| l.distance(p) >= self.pixel) {
                if self.pts.len() + 1 >= self.cap {
                    self.end = Some(p);
                    self.flush(page, layer, width);
                }
                self.pts.push(p);
            }
            self.end = Some(p);
        }
    }

    /// Draws the path collected (when the layer admits it) and starts an empty one.
    pub(super) fn flush(&mut self, page: &mut Drawing, layer: &mut Layer, width: f64) {
        let mut pts = std::mem::take(&mut self.pts);
        if let Some(end) = self.end.take()
            && pts.last() != Some(&end)
        {
            pts.push(end);
        }
        if pts.len() >= 2
            && let Some(pts) = layer.polyline(&pts, width, RAPID_COLOR, false)
        {
            page.polyline("rapid", pts, false, Style::default(), None);
        }
    }
}

/// `pts` without the points closer than `tol` to the last point kept (the last point
/// always stays): every point left out lies within `tol` of a kept one, so the drawing
/// moves by less than `tol` (radial-distance simplification).
pub fn simplify(pts: &[DVec2], tol: f64) -> Vec<DVec2> {
    let Some((&first, rest)) = pts.split_first() else {
        return Vec::new();
    };
    let mut out = vec![first];
    let mut last = first;
    for &p in rest {
        if p.distance(last) >= tol {
            out.push(p);
            last = p;
        }
    }
    if let Some(&end) = pts.last()
        && last != end
    {
        out.push(end);
    }
    out
}

/// The xy points of a move with sagitta ≤ `tol`. An arc of more than one turn covers its
/// circle once: the later turns retrace it.
pub(super) fn move_points(m: &crate::sim::Motion, tol: f64) -> Vec<DVec2> {
    match m.arc {
        Some(a) if a.sweep.abs() > std::f64::consts::TAU => crate::geom::Arc {
            sweep: std::f64::consts::TAU.copysign(a.sweep),
            ..a
        }
        .flatten(tol),
        _ => m.flatten_xy(tol),
    }
}
