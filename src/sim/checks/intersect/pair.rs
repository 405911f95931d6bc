//! The exact test of one pair of segments: contact point, and the contacts that are not
//! crossings (neighbours on one polyline, a tool passing the same point again, tangents).

use super::*;

impl SegmentSet {
    /// True when segments `s` and `t` of one contour are consecutive (they share an end
    /// point by construction).
    pub(super) fn adjacent(&self, i: usize, j: usize, s: &Seg, t: &Seg) -> bool {
        if s.contour != t.contour {
            return false;
        }
        let (lo, hi) = (s.index.min(t.index), s.index.max(t.index));
        if hi - lo == 1 {
            return true;
        }
        if let Some(links) = &self.links {
            let wrap = |k: usize| links.get(k).is_some_and(|l| l.wrap);
            return wrap(i) && wrap(j);
        }
        let (n, closed) = self
            .contours
            .get(s.contour as usize)
            .copied()
            .unwrap_or((0, false));
        closed && lo == 0 && hi + 1 == n
    }

    /// The directions back along the incoming segment and along the outgoing segment of the
    /// pass of segment `i` through its end point `v`; `None` where the run starts or ends
    /// at `v`.
    pub(super) fn pass_at(&self, i: usize, v: DVec2) -> Option<(DVec2, DVec2)> {
        let s = self.get(i)?;
        if let Some(links) = &self.links {
            let l = links.get(i)?;
            return if s.a == v {
                l.prev_a.map(|p| (p - v, s.b - v))
            } else if s.b == v {
                l.next_b.map(|q| (s.a - v, q - v))
            } else {
                None
            };
        }
        let same = |k: usize| self.get(k).filter(|t| t.contour == s.contour);
        let (n, closed) = self.contours.get(s.contour as usize).copied()?;
        let first = i - s.index as usize;
        let last = first + n as usize - 1;
        let prev = if i > first {
            Some(i - 1)
        } else {
            closed.then_some(last)
        };
        let next = if i < last {
            Some(i + 1)
        } else {
            closed.then_some(first)
        };
        if s.a == v {
            let p = same(prev?)?;
            (p.b == v).then_some((p.a - v, s.b - v))
        } else if s.b == v {
            let q = same(next?)?;
            (q.a == v).then_some((s.a - v, q.b - v))
        } else {
            None
        }
    }

    /// True when segments `i` and `j` meet only at an end point `v` of both, through which
    /// the path passes twice without the two passes crossing (or where one pass starts or
    /// ends): the directions of one pass do not separate those of the other around `v`.
    pub(super) fn is_revisit(&self, i: usize, j: usize) -> bool {
        let (Some(s), Some(t)) = (self.get(i), self.get(j)) else {
            return false;
        };
        let Some(v) = [s.a, s.b].into_iter().find(|&p| p == t.a || p == t.b) else {
            return false;
        };
        // Collinear overlaps beyond the shared point are real contacts.
        let (ds, dt) = (s.b - s.a, t.b - t.a);
        if orient2d(s.a, s.b, t.a) == 0.0 && orient2d(s.a, s.b, t.b) == 0.0 {
            let (os, ot) = (
                if s.a == v { ds } else { -ds },
                if t.a == v { dt } else { -dt },
            );
            if os.dot(ot) > 0.0 {
                return false;
            }
        }
        let (Some((a1, a2)), Some((b1, b2))) = (self.pass_at(i, v), self.pass_at(j, v)) else {
            // One of the runs ends at v: a touch at a run end, no crossing.
            return true;
        };
        let ang = |d: DVec2| d.y.atan2(d.x);
        let tau = std::f64::consts::TAU;
        let span = (ang(a2) - ang(a1)).rem_euclid(tau);
        let inside = |b: DVec2| {
            let x = (ang(b) - ang(a1)).rem_euclid(tau);
            (x > 0.0 && x < span, x == 0.0 || x == span)
        };
        let ((in1, on1), (in2, on2)) = (inside(b1), inside(b2));
        !on1 && !on2 && in1 == in2 || self.tangent_passes([a1, a2], [b1, b2])
    }

    /// True when two passes through a vertex (each as the directions back along its incoming
    /// chord and along its outgoing chord) are smooth there and tangent to each other, going
    /// the same way, within what [`SegmentSet::tangent_slack`] allows: the passes meet in
    /// that one point and at most graze (a closed contour entered by a lead arc and left by
    /// one, both tangent at its start, where the leads lie on the waste side and the contour
    /// on the other: the path runs lead → contour → lead through the point, an S-shaped
    /// tangential crossing that no flattening can show as a touch).
    ///
    /// A chord of length L of an arc whose sagitta is at most f leaves the arc's tangent at
    /// its end at the angle 2·atan(2f/L) (the half-angle of the chord's arc φ/2 satisfies
    /// tan(φ/4) = 2·sagitta/L); ends rounded by up to f more turn it by at most atan(2f/L).
    /// Each chord of length L thus is within θ(L) = 3·atan(2f/L) of the curve's tangent, and
    /// two directions at the vertex agree when their angle is at most the sum of their θ.
    pub(super) fn tangent_passes(&self, a: [DVec2; 2], b: [DVec2; 2]) -> bool {
        let f = self.tangent_slack;
        if f <= 0.0 {
            return false;
        }
        let theta = |d: DVec2| 3.0 * (2.0 * f / d.length()).atan();
        let agree = |u: DVec2, w: DVec2| u.perp_dot(w).abs().atan2(u.dot(w)) <= theta(u) + theta(w);
        let [a1, a2] = a;
        let [b1, b2] = b;
        agree(-a1, a2) && agree(-b1, b2) && agree(a1, b1) && agree(a2, b2)
    }

    /// Exact contact test of two segments; same-contour adjacent pairs are skipped (see
    /// `Self::adjacent_overlaps`), and pairs of two contours follow [`SegmentSet::across`].
    pub fn test_pair(&self, i: usize, j: usize) -> Option<Contact> {
        if i.max(j) >= self.len() {
            return None;
        }
        let ((sa, sb), (ta, tb)) = (self.ends(i), self.ends(j));
        if sa.max(sb).cmplt(ta.min(tb)).any() || ta.max(tb).cmplt(sa.min(sb)).any() {
            return None;
        }
        let (s, t) = (self.seg(i), self.seg(j));
        let across = s.contour != t.contour;
        let (sp, tp) = (self.pocket(i), self.pocket(j));
        let one_pocket = sp.is_some() && sp == tp;
        // Line cuts follow a drawing's lines: they may cross anything, themselves included.
        let line = sp == Some(LINE_GROUP) || tp == Some(LINE_GROUP);
        if line
            || across && (self.across == Across::Never || one_pocket)
            || self.adjacent(i, j, &s, &t)
        {
            return None;
        }
        let (i, j) = (i.min(j), i.max(j));
        let o1 = orient2d(s.a, s.b, t.a);
        let o2 = orient2d(s.a, s.b, t.b);
        let o3 = orient2d(t.a, t.b, s.a);
        let o4 = orient2d(t.a, t.b, s.b);
        if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
            let point = line_intersection(s.a, s.b, t.a, t.b).unwrap_or(s.a);
            return Some(Contact {
                i,
                j,
                point,
                proper: true,
            });
        }
        if across && self.across == Across::Crossings || !segments_intersect(s.a, s.b, t.a, t.b) {
            return None;
        }
        // The path passing twice through one of its vertices without crossing there (a
        // closed loop entered by a lead-in and closed at its start) is a revisit, not a
        // contact.
        if self.is_revisit(i, j) {
            return None;
        }
        // A touching or overlapping contact: report an end point that lies on the other.
        let point = [(o1, t.a), (o2, t.b)]
            .into_iter()
            .find(|&(o, _)| o == 0.0)
            .map(|(_, p)| p)
            .unwrap_or(if o3 == 0.0 { s.a } else { s.b });
        Some(Contact {
            i,
            j,
            point,
            proper: false,
        })
    }
}
