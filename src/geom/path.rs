//! Paths: connected sequences of lines, arcs and cubic Béziers, open or closed.

use super::{Aabb, Arc, CubicBez, DVec2, Line};

/// One piece of a [`Path`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathSeg {
    /// A straight segment.
    Line(Line),
    /// A circular arc.
    Arc(Arc),
    /// A cubic Bézier curve.
    Cubic(CubicBez),
}

impl PathSeg {
    /// The segment's start point.
    pub fn start(&self) -> DVec2 {
        match self {
            PathSeg::Line(l) => l.p0,
            PathSeg::Arc(a) => a.p0(),
            PathSeg::Cubic(c) => c.p0,
        }
    }

    /// The segment's end point.
    pub fn end(&self) -> DVec2 {
        match self {
            PathSeg::Line(l) => l.p1,
            PathSeg::Arc(a) => a.p1(),
            PathSeg::Cubic(c) => c.p3,
        }
    }

    /// Point at the segment's own parameter `t` in [0, 1].
    pub fn eval(&self, t: f64) -> DVec2 {
        match self {
            PathSeg::Line(l) => l.eval(t),
            PathSeg::Arc(a) => a.eval(t),
            PathSeg::Cubic(c) => c.eval(t),
        }
    }

    /// The same segment traversed backwards.
    pub fn reversed(&self) -> Self {
        match self {
            PathSeg::Line(l) => PathSeg::Line(l.reversed()),
            PathSeg::Arc(a) => PathSeg::Arc(a.reversed()),
            PathSeg::Cubic(c) => PathSeg::Cubic(c.reversed()),
        }
    }

    /// The segment moved by `d`.
    pub fn translated(&self, d: DVec2) -> Self {
        match self {
            PathSeg::Line(l) => PathSeg::Line(Line::new(l.p0 + d, l.p1 + d)),
            PathSeg::Arc(a) => PathSeg::Arc(Arc::new(a.center + d, a.radius, a.start, a.sweep)),
            PathSeg::Cubic(c) => {
                PathSeg::Cubic(CubicBez::new(c.p0 + d, c.p1 + d, c.p2 + d, c.p3 + d))
            }
        }
    }

    /// Length; cubic lengths to relative accuracy `tol`.
    pub fn length(&self, tol: f64) -> f64 {
        match self {
            PathSeg::Line(l) => l.length(),
            PathSeg::Arc(a) => a.length(),
            PathSeg::Cubic(c) => c.arclen(tol),
        }
    }

    /// Points with chord deviation ≤ `tol`, first and last included.
    pub fn flatten(&self, tol: f64) -> Vec<DVec2> {
        match self {
            PathSeg::Line(l) => vec![l.p0, l.p1],
            PathSeg::Arc(a) => a.flatten(tol),
            PathSeg::Cubic(c) => c.flatten(tol),
        }
    }

    /// An axis-aligned box holding the segment and its flattenings: a line's ends,
    /// an arc's exact [`Arc::bounding_box`], a cubic's [`CubicBez::control_bbox`].
    #[must_use]
    pub fn bounding_box(&self) -> Aabb {
        match self {
            PathSeg::Line(l) => Aabb::from_corners(l.p0, l.p1),
            PathSeg::Arc(a) => a.bounding_box(),
            PathSeg::Cubic(c) => c.control_bbox(),
        }
    }
}

/// A connected path; `closed` joins the last end back to the first start.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Path {
    /// The segments in order, each starting where the previous one ends.
    pub segs: Vec<PathSeg>,
    /// True when the path returns to its start (last end = first start).
    pub closed: bool,
}

impl Path {
    /// A path of `segs`, closed when `closed`.
    pub fn new(segs: Vec<PathSeg>, closed: bool) -> Self {
        Path { segs, closed }
    }

    /// The polyline through `points` (closed: back to the first point). Repeated
    /// consecutive points give no segment.
    pub fn polyline(points: &[DVec2], closed: bool) -> Self {
        let n = points.len();
        let count = if closed && n > 2 {
            n
        } else {
            n.saturating_sub(1)
        };
        let segs = (0..count)
            .map(|i| (points[i], points[(i + 1) % n]))
            .filter(|(a, b)| a != b)
            .map(|(a, b)| PathSeg::Line(Line::new(a, b)))
            .collect();
        Path::new(segs, closed)
    }

    /// True when the path has no segments.
    pub fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }

    /// Start of the first segment, `None` for an empty path.
    pub fn start(&self) -> Option<DVec2> {
        self.segs.first().map(PathSeg::start)
    }

    /// End of the last segment, `None` for an empty path.
    pub fn end(&self) -> Option<DVec2> {
        self.segs.last().map(PathSeg::end)
    }

    /// The path traversed backwards.
    pub fn reversed(&self) -> Path {
        Path::new(
            self.segs.iter().rev().map(PathSeg::reversed).collect(),
            self.closed,
        )
    }

    /// The path moved by `d`.
    pub fn translated(&self, d: DVec2) -> Path {
        Path::new(
            self.segs.iter().map(|s| s.translated(d)).collect(),
            self.closed,
        )
    }

    /// Total length; cubic lengths to relative accuracy `tol`.
    pub fn length(&self, tol: f64) -> f64 {
        self.segs.iter().map(|s| s.length(tol)).sum()
    }

    /// A polyline within `tol` of the path. Closed paths do not repeat the first point.
    pub fn flatten(&self, tol: f64) -> Vec<DVec2> {
        let mut out: Vec<DVec2> = Vec::new();
        for s in &self.segs {
            let pts = s.flatten(tol);
            let skip = usize::from(!out.is_empty());
            out.extend_from_slice(&pts[skip..]);
        }
        if self.closed && out.len() > 1 && out.first() == out.last() {
            out.pop();
        }
        out
    }

    /// Largest gap between the end of one segment and the start of the next (and, closed,
    /// between the last end and the first start): 0 for a connected path.
    pub fn max_gap(&self) -> f64 {
        let mut g: f64 = 0.0;
        for w in self.segs.windows(2) {
            g = g.max(w[0].end().distance(w[1].start()));
        }
        if self.closed
            && let (Some(a), Some(b)) = (self.end(), self.start())
        {
            g = g.max(a.distance(b));
        }
        g
    }
}

/// Snaps the start of every line of the closed chain `segs` to the previous segment's end
/// (pieces computed separately, such as cap arcs and curve ends, meet only up to rounding;
/// arcs keep their exact ends, lines absorb the gap).
pub fn close_line_gaps(segs: &mut [PathSeg]) {
    let n = segs.len();
    for k in 0..n {
        let prev_end = segs[(k + n - 1) % n].end();
        if let PathSeg::Line(l) = &mut segs[k] {
            l.p0 = prev_end;
        }
    }
}

/// Signed area of a closed polygon (shoelace formula): positive when counter-clockwise.
pub fn polygon_area(pts: &[DVec2]) -> f64 {
    let n = pts.len();
    if n < 3 {
        return 0.0;
    }
    let mut s = 0.0;
    for i in 0..n {
        s += super::cross(pts[i], pts[(i + 1) % n]);
    }
    0.5 * s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_area_and_length() {
        let p = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        assert_eq!(polygon_area(&p), 1.0);
        let segs = (0..4)
            .map(|i| PathSeg::Line(Line::new(p[i], p[(i + 1) % 4])))
            .collect();
        let path = Path::new(segs, true);
        assert_eq!(path.length(1e-9), 4.0);
        assert_eq!(path.max_gap(), 0.0);
        assert_eq!(path.flatten(1e-3).len(), 4);
        assert_eq!(polygon_area(&path.reversed().flatten(1e-3)), -1.0);
        // The same square from its corner points.
        assert_eq!(Path::polyline(&p, true), path);
        assert_eq!(Path::polyline(&p, false).segs.len(), 3);
    }
}
