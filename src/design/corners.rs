//! Strokes with corners, and the expansion of a loaded design into plain strokes.
//!
//! A stroke may list `corners = [i, j, ...]`: indices of its `disks` or `points` where the
//! stroke turns sharply. Loading splits the stroke there into G1 pieces named `NAME#0`,
//! `NAME#1`, ... that share the corner disk: piece k runs from corner k−1 (or the start) to
//! corner k (or the end), so the union of the pieces' regions is the stroke's region with a
//! round joint at every corner (the corner disk), like a round line join. A closed stroke is
//! split cyclically; with a single corner it is also split at the disk opposite it, so no
//! piece starts and ends at the same disk. A piece of m disks or points gets degree
//! min(degree, m − 1): a piece between two neighbouring corners is a straight segment of
//! degree 1.
//!
//! Operations that name the stroke apply to all its pieces. [`Design::corners`] lists the
//! corners (for `inspect`).
//!
//! Imported data (SVG paths, font glyphs) marks corners where the polyline turns by more
//! than [`CORNER_ANGLE_DEG`] ([`sharp_turns`]).

use super::error::{DesignError, ErrorKind, Item, Part};
use super::model::{Attributes, Design, Fit, Stroke};
use crate::dbsc::DiskBSpline;
use crate::geom::DVec2;
use serde::{Deserialize, Serialize};

/// Turning angle (degrees) above which imported polylines (SVG paths, glyphs) get a corner.
/// A smooth curve sampled or digitised as a polyline turns by well under this at every
/// vertex (a Hershey glyph's circle of 16–20 vertices turns 18–23°); letters' strokes meet
/// at 45° and more (the diagonals of N, M, W, V).
pub const CORNER_ANGLE_DEG: f64 = 40.0;

/// A corner at which a stroke was split into pieces.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Corner {
    /// The stroke's name in the file.
    pub stroke: String,
    /// Whether `index` counts `disks` or `points`.
    pub kind: String,
    /// Index of the corner in the stroke's `disks` or `points`.
    pub index: usize,
    /// Centre of the corner disk.
    pub at: [f64; 2],
    /// The pieces that meet there: the one ending and the one starting at the corner.
    pub pieces: [String; 2],
}

/// Indices of the interior vertices of `points` (all vertices when `closed`) where the
/// polyline turns by more than `angle_deg` degrees.
pub fn sharp_turns(points: &[DVec2], closed: bool, angle_deg: f64) -> Vec<usize> {
    let n = points.len();
    let cos_max = angle_deg.to_radians().cos();
    let mut out = Vec::new();
    if n < 3 {
        return out;
    }
    for i in 0..n {
        if !closed && (i == 0 || i == n - 1) {
            continue;
        }
        let a = points[(i + n - 1) % n];
        let b = points[i];
        let c = points[(i + 1) % n];
        let (u, v) = (b - a, c - b);
        let (lu, lv) = (u.length(), v.length());
        if lu == 0.0 || lv == 0.0 {
            continue;
        }
        if u.dot(v) / (lu * lv) < cos_max {
            out.push(i);
        }
    }
    out
}

/// Piece name of piece `k` of stroke `name`.
pub fn piece_name(name: &str, k: usize) -> String {
    format!("{name}#{k}")
}

fn slice_cyclic<T: Clone>(v: &[T], from: usize, to: usize) -> Vec<T> {
    // Inclusive range from..=to, wrapping once past the end.
    if from <= to {
        v[from..=to].to_vec()
    } else {
        let mut out = v[from..].to_vec();
        out.extend_from_slice(&v[..=to]);
        out
    }
}

/// The index ranges (inclusive, possibly wrapping) of the pieces of a stroke of `n`
/// elements with sorted, distinct `corners`.
fn piece_ranges(n: usize, closed: bool, corners: &[usize]) -> Vec<(usize, usize)> {
    if closed {
        let mut cs = corners.to_vec();
        if cs.len() == 1 {
            let opposite = (cs[0] + n / 2) % n;
            cs.push(opposite);
            cs.sort_unstable();
        }
        (0..cs.len())
            .map(|k| (cs[k], cs[(k + 1) % cs.len()]))
            .collect()
    } else {
        let mut bounds = vec![0];
        bounds.extend(corners.iter().copied().filter(|&c| c > 0 && c < n - 1));
        bounds.push(n - 1);
        bounds.windows(2).map(|w| (w[0], w[1])).collect()
    }
}

fn count_cyclic(n: usize, from: usize, to: usize) -> usize {
    if from <= to {
        to - from + 1
    } else {
        n - from + to + 1
    }
}

/// Split one stroke with corners into its pieces (see the module docs).
fn split_stroke(file: &str, index: usize, s: &Stroke) -> Result<Vec<Stroke>, DesignError> {
    let item = || Item::Stroke {
        index,
        name: s.name.clone(),
    };
    let invalid = |m: String| {
        DesignError::at(
            file,
            item(),
            Some(Part::Key("corners".into())),
            ErrorKind::Invalid(m),
        )
    };
    let corners = s.corners.clone().unwrap_or_default();
    let list = s.disks.as_ref().or(s.points.as_ref());
    let Some(list) = list else {
        // Validation reports the missing geometry.
        return Ok(vec![s.clone()]);
    };
    let n = list.len();
    let mut sorted = corners.clone();
    sorted.sort_unstable();
    sorted.dedup();
    if sorted.len() != corners.len() {
        return Err(invalid("lists a corner twice".into()));
    }
    if let Some(&bad) = sorted.iter().find(|&&c| c >= n) {
        return Err(invalid(format!(
            "corner {bad} is not an index of the stroke's {n} {}",
            if s.disks.is_some() { "disks" } else { "points" }
        )));
    }
    if s.knots.is_some() {
        return Err(invalid(
            "`corners` and `knots` cannot be combined: each piece gets clamped uniform knots; \
             remove `knots` or split the stroke by hand"
                .into(),
        ));
    }
    let approximate = s.points.is_some() && s.fit.unwrap_or_default() == Fit::Approximate;
    if approximate && !s.attributes.is_empty() {
        return Err(invalid(
            "`corners` on an approximated stroke cannot carry attributes (they are per \
             control disk); use fit = \"interpolate\" or remove the corners"
                .into(),
        ));
    }
    if !s.closed {
        sorted.retain(|&c| c > 0 && c + 1 < n);
    }
    if sorted.is_empty() || n < 3 {
        let mut one = s.clone();
        one.corners = None;
        return Ok(vec![one]);
    }
    let ranges = piece_ranges(n, s.closed, &sorted);
    let total = if s.closed { n } else { n - 1 };
    let mut out = Vec::new();
    for (k, &(a, b)) in ranges.iter().enumerate() {
        let m = count_cyclic(n, a, b);
        let mut p = s.clone();
        p.name = piece_name(&s.name, k);
        p.closed = false;
        p.corners = None;
        p.degree = s.degree.min(m - 1).max(1);
        let part = slice_cyclic(list, a, b);
        if s.disks.is_some() {
            p.disks = Some(part);
        } else {
            p.points = Some(part);
            if approximate {
                let want = s.control_disks.unwrap_or(m);
                let share = (want as f64 * (m - 1) as f64 / total as f64).round() as usize;
                p.control_disks = Some(share.clamp(p.degree + 1, m));
            }
        }
        let mut attrs = Attributes::default();
        for (name, values) in s.attributes.channels() {
            let v = if values.len() == n {
                slice_cyclic(values, a, b)
            } else {
                // Validation reports the wrong count on the whole stroke.
                values.to_vec()
            };
            match name {
                "power" => attrs.power = Some(v),
                "depth" => attrs.depth = Some(v),
                _ => attrs.feed = Some(v),
            }
        }
        p.attributes = attrs;
        out.push(p);
    }
    Ok(out)
}

/// Relative distance within which a point is a recorded corner: piece ends are the corner
/// points evaluated again, so only rounding separates them.
const CORNER_MATCH: f64 = 1e-9;

impl Design {
    /// Whether `p` is one of the corners at which loading split a stroke (|p − c| ≤
    /// `CORNER_MATCH`·(1 + |c|)): piece ends there are joints, not stroke ends.
    pub fn is_corner(&self, p: DVec2) -> bool {
        self.corners.iter().any(|c| {
            let q = DVec2::new(c.at[0], c.at[1]);
            q.distance(p) <= CORNER_MATCH * (1.0 + q.length())
        })
    }

    /// Lay out every `[[text]]` into strokes and split every stroke with corners into its
    /// pieces (see the module docs); operations naming a text or a split stroke are given
    /// its strokes. Records the corners in [`Design::corners`]. Loading calls this before
    /// validation; a design without text or corners is unchanged.
    pub fn expand(&mut self) -> Result<(), DesignError> {
        let mut renamed: Vec<(String, Vec<String>)> = Vec::new();
        let texts = std::mem::take(&mut self.text);
        super::text::check_total(&texts, &self.file)?;
        for (i, t) in texts.iter().enumerate() {
            let strokes = t.to_strokes(&self.file, i)?;
            renamed.push((
                t.name.clone(),
                strokes.iter().map(|s| s.name.clone()).collect(),
            ));
            self.stroke.extend(strokes);
        }
        let mut out = Vec::with_capacity(self.stroke.len());
        let mut corners = Vec::new();
        let strokes = std::mem::take(&mut self.stroke);
        for (i, s) in strokes.into_iter().enumerate() {
            if s.corners.as_ref().is_none_or(|c| c.is_empty()) {
                let mut s = s;
                s.corners = None;
                out.push(s);
                continue;
            }
            let pieces = split_stroke(&self.file, i, &s)?;
            if pieces.len() > 1 {
                let list = s.disks.as_ref().or(s.points.as_ref()).cloned();
                let n = pieces.len();
                for k in 0..n {
                    let ends_at = &pieces[k];
                    let next = if k + 1 < n {
                        &pieces[k + 1]
                    } else if s.closed {
                        &pieces[0]
                    } else {
                        continue;
                    };
                    let last = ends_at
                        .disks
                        .as_ref()
                        .or(ends_at.points.as_ref())
                        .and_then(|v| v.last().copied())
                        .unwrap_or([0.0; 3]);
                    let index = list.as_ref().and_then(|l| {
                        s.corners
                            .iter()
                            .flatten()
                            .copied()
                            .find(|&c| l.get(c) == Some(&last))
                    });
                    // The extra split of a closed stroke with one corner is not a corner.
                    if let Some(index) = index {
                        corners.push(Corner {
                            stroke: s.name.clone(),
                            kind: if s.disks.is_some() { "disk" } else { "point" }.into(),
                            index,
                            at: [last[0], last[1]],
                            pieces: [ends_at.name.clone(), next.name.clone()],
                        });
                    }
                }
                renamed.push((
                    s.name.clone(),
                    pieces.iter().map(|p| p.name.clone()).collect(),
                ));
            }
            out.extend(pieces);
        }
        self.stroke = out;
        self.corners = corners;
        // Names of texts may themselves have been split further (text strokes with corners).
        let resolve = |name: &str, renamed: &[(String, Vec<String>)]| -> Vec<String> {
            let mut todo = vec![name.to_string()];
            let mut done = Vec::new();
            while let Some(n) = todo.pop() {
                match renamed.iter().find(|(from, _)| *from == n) {
                    Some((_, to)) => todo.extend(to.iter().rev().cloned()),
                    None => done.push(n),
                }
            }
            done
        };
        for op in &mut self.operation {
            if let Some(names) = &op.strokes {
                op.strokes = Some(names.iter().flat_map(|n| resolve(n, &renamed)).collect());
            }
        }
        Ok(())
    }
}

/// What to change when a stroke cannot be skinned: the control disks of `curve` that turn
/// sharply (mark them as corners), whose radius reaches past a neighbouring disk's centre
/// (lower the radius or move the disk), or that lie inside a neighbour (move the disk).
/// Indices are those of the curve's control disks; `None` when nothing stands out.
pub fn skin_hint(curve: &DiskBSpline) -> Option<String> {
    let disks = curve.control_disks();
    let n = disks.len();
    let closed = curve.is_closed();
    let pts: Vec<DVec2> = disks.iter().map(|d| d.c).collect();
    let mut hints = Vec::new();
    let turns = sharp_turns(&pts, closed, CORNER_ANGLE_DEG);
    if !turns.is_empty() {
        hints.push(format!(
            "the spine turns sharply at disk{} {:?}: mark {} as corner{} (`corners = {:?}`) \
             or move the disk{} to round the turn",
            if turns.len() > 1 { "s" } else { "" },
            turns,
            if turns.len() > 1 { "them" } else { "it" },
            if turns.len() > 1 { "s" } else { "" },
            turns,
            if turns.len() > 1 { "s" } else { "" },
        ));
    }
    for i in 0..n {
        let j = if i + 1 < n {
            i + 1
        } else if closed {
            0
        } else {
            break;
        };
        let (a, b) = (&disks[i], &disks[j]);
        let d = a.c.distance(b.c);
        if d + b.r <= a.r || d + a.r <= b.r {
            let (inner, outer) = if a.r < b.r { (i, j) } else { (j, i) };
            hints.push(format!(
                "disk {inner} lies inside disk {outer}: move disk {inner} away or lower the \
                 radius of disk {outer}"
            ));
        }
    }
    for i in 0..n {
        if !closed && (i == 0 || i + 1 == n) {
            continue;
        }
        let prev = &disks[(i + n - 1) % n];
        let next = &disks[(i + 1) % n];
        let me = &disks[i];
        let reach = prev.c.distance(me.c).min(me.c.distance(next.c));
        if turns.contains(&i) {
            continue;
        }
        // A radius larger than the distance to a neighbour at a bend is what makes the
        // radical centre of the triplet fall inside a disk (kruppa-2023 Def. 4.1 cond. 3).
        let bend = (me.c - prev.c).angle_to(next.c - me.c).abs();
        if me.r > reach && bend > 0.35 {
            hints.push(format!(
                "disk {i} (radius {:.3}) bends by {:.0}° within {:.3} of its neighbours: lower its \
                 radius below {:.3} or move the neighbouring disks apart",
                me.r,
                bend.to_degrees(),
                reach,
                reach
            ));
        }
    }
    if hints.is_empty() {
        None
    } else {
        Some(format!("what to change: {}", hints.join("; ")))
    }
}
