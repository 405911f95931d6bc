//! Triangle mesh of the region of a DBSC (wu-2021 Sec. "Interactive HE object design":
//! tessellation by linking interior points P±(t, u) of eq. 12).
//!
//! Region covered: the swept band between the left and right envelopes, i.e. the points
//! P±(t, u), t in the domain, u ∈ [0, 1]; the end caps are not in the mesh (add
//! [`super::caps()`] for the full stroke). Vertices: the centre q(t_i) (u = 0) and, on each
//! side, rings u_k = k / rings, k = 1..=rings, the last ring lying on the envelope. Where
//! P±(t, u) does not exist (no real envelope for the scaled family, ‖q′‖ < u|r′|), the
//! vertex is missing and the triangles using it are left out, so the mesh has a hole
//! there. Where the envelope folds back (loops, τ± < 0) triangles overlap with reversed
//! orientation; their signed areas then cancel rather than add.

use super::flatten::{MIN_PIECES_PER_SPAN, adaptive_samples};
use super::interior::interior_point;
use super::{DiskBSpline, Side};
use crate::geom::DVec2;

/// How finely to sample along t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Resolution {
    /// This many equal parameter steps over the domain.
    Count(usize),
    /// Adaptive steps keeping spine and both envelopes within this chordal tolerance (the
    /// heuristic of [`super::flatten()`]), started at every knot span.
    Chordal(f64),
}

/// Errors of tessellation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TessellateError {
    /// `Resolution::Count(0)` or zero rings were asked for.
    #[error("tessellation needs at least one step along t and one ring, got {steps} and {rings}")]
    Resolution {
        /// The requested number of steps along t (1 for [`Resolution::Chordal`]).
        steps: usize,
        /// The requested number of rings per side.
        rings: usize,
    },
    /// The [`Resolution::Chordal`] tolerance is not positive and finite; holds it.
    #[error("chordal tolerance {0} must be positive and finite")]
    Tolerance(f64),
}

/// An indexed triangle mesh; triangles are counter-clockwise where the region is
/// loop-free.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions: per t sample the centre q(t), then the left rings P⁺(t, u_k), then
    /// the right rings P⁻(t, u_k), leaving out the points that do not exist.
    pub vertices: Vec<DVec2>,
    /// The parameters (t, u, side) of each vertex (side `None` for centre vertices).
    pub params: Vec<(f64, f64, Option<Side>)>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[usize; 3]>,
}

impl Mesh {
    /// Sum of the signed triangle areas.
    pub fn signed_area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|&[a, b, c]| {
                let (p, q, r) = (self.vertices[a], self.vertices[b], self.vertices[c]);
                0.5 * crate::geom::cross(q - p, r - p)
            })
            .sum()
    }
}

/// The t samples for a resolution.
fn samples(c: &DiskBSpline, along: Resolution) -> Result<Vec<f64>, TessellateError> {
    let (lo, hi) = c.domain();
    match along {
        Resolution::Count(n) => Ok((0..=n)
            .map(|i| {
                if i == n {
                    hi
                } else {
                    lo + (hi - lo) * i as f64 / n as f64
                }
            })
            .collect()),
        Resolution::Chordal(tol) => {
            if !(tol > 0.0 && tol.is_finite()) {
                return Err(TessellateError::Tolerance(tol));
            }
            let f = |t: f64| {
                let q = c.center(t);
                let l = interior_point(c, Side::Left, t, 1.0).unwrap_or(q);
                let r = interior_point(c, Side::Right, t, 1.0).unwrap_or(q);
                [q, l, r]
            };
            let bps = c.breakpoints();
            let mut out: Vec<f64> = vec![lo];
            for w in bps.windows(2) {
                let s = adaptive_samples(&f, w[0], w[1], MIN_PIECES_PER_SPAN, tol);
                out.extend(s.into_iter().skip(1).map(|(t, _)| t));
            }
            Ok(out)
        }
    }
}

/// The mesh of the region (module docs) with `rings` rings of u per side.
pub fn tessellate(
    c: &DiskBSpline,
    along: Resolution,
    rings: usize,
) -> Result<Mesh, TessellateError> {
    if rings == 0 || along == Resolution::Count(0) {
        let steps = match along {
            Resolution::Count(n) => n,
            Resolution::Chordal(_) => 1,
        };
        return Err(TessellateError::Resolution { steps, rings });
    }
    let ts = samples(c, along)?;
    let mut mesh = Mesh::default();
    // grid[i][side][k]: vertex index of sample i, side (0 left, 1 right), ring k (0 = centre).
    let mut grid: Vec<[Vec<Option<usize>>; 2]> = Vec::with_capacity(ts.len());
    for &t in &ts {
        let ci = mesh.vertices.len();
        mesh.vertices.push(c.center(t));
        mesh.params.push((t, 0.0, None));
        let mut row: [Vec<Option<usize>>; 2] = [vec![Some(ci)], vec![Some(ci)]];
        for (si, side) in [Side::Left, Side::Right].into_iter().enumerate() {
            for k in 1..=rings {
                let u = k as f64 / rings as f64;
                row[si].push(interior_point(c, side, t, u).map(|p| {
                    mesh.vertices.push(p);
                    mesh.params.push((t, u, Some(side)));
                    mesh.vertices.len() - 1
                }));
            }
        }
        grid.push(row);
    }
    for w in grid.windows(2) {
        for (si, _) in [Side::Left, Side::Right].iter().enumerate() {
            for k in 1..=rings {
                let a = w[0][si][k - 1];
                let b = w[1][si][k - 1];
                let d = w[1][si][k];
                let e = w[0][si][k];
                let (t1, t2) = if si == 0 {
                    ([a, b, d], [a, d, e])
                } else {
                    ([a, e, d], [a, d, b])
                };
                for tri in [t1, t2] {
                    if let [Some(x), Some(y), Some(z)] = tri
                        && x != y
                        && y != z
                        && x != z
                    {
                        mesh.triangles.push([x, y, z]);
                    }
                }
            }
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::tangent::tests::dbsc_strategy;
    use crate::geom::Circle;
    use proptest::prelude::*;

    /// Straight centre line of length ℓ (controls at the Greville abscissae, so q is linear
    /// in t) with constant radius R: the mesh is the ℓ × 2R rectangle exactly.
    #[test]
    fn straight_constant_radius_rectangle() {
        for (len, rr, angle) in [(4.0, 0.5, 0.0), (10.0, 2.0, 1.0), (0.01, 0.003, -2.0)] {
            let dir = DVec2::from_angle(angle);
            let disks: Vec<Circle> = (0..4)
                .map(|i| Circle::new(dir * len * i as f64 / 3.0, rr))
                .collect();
            let c = DiskBSpline::open(3, &disks, None).unwrap();
            for res in [Resolution::Count(7), Resolution::Chordal(1e-4)] {
                let m = tessellate(&c, res, 3).unwrap();
                assert!(
                    (m.signed_area() - 2.0 * rr * len).abs() < 1e-12 * len.max(1.0),
                    "{}",
                    m.signed_area()
                );
                assert!(m.triangles.iter().all(|&[a, b, cc]| {
                    crate::geom::cross(
                        m.vertices[b] - m.vertices[a],
                        m.vertices[cc] - m.vertices[a],
                    ) > 0.0
                }));
            }
        }
    }

    /// Constant radius R around a curved loop-free centre: the band's area is 2 R · length
    /// (the two envelopes are parallel curves at ±R), computed independently by Simpson
    /// quadrature of ‖q′‖; the mesh converges to it at O(h²).
    #[test]
    fn curved_constant_radius_band_area() {
        let pts = [(0.0, 0.0), (3.0, 2.0), (6.0, -1.0), (9.0, 1.0), (12.0, 0.0)];
        let rr = 0.4;
        let disks: Vec<Circle> = pts
            .iter()
            .map(|&(x, y)| Circle::new(DVec2::new(x, y), rr))
            .collect();
        let c = DiskBSpline::open(3, &disks, None).unwrap();
        let n = 20000;
        let mut len = 0.0;
        for i in 0..n {
            let (a, b) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
            let sp = |t: f64| c.derivs(t, 1)[1].0.length();
            len += (b - a) / 6.0 * (sp(a) + 4.0 * sp(0.5 * (a + b)) + sp(b));
        }
        let m = tessellate(&c, Resolution::Chordal(1e-5), 2).unwrap();
        let want = 2.0 * rr * len;
        assert!(
            (m.signed_area() - want).abs() < 1e-3 * want,
            "{} vs {want}",
            m.signed_area()
        );
        // Finer sampling gets closer.
        let coarse = tessellate(&c, Resolution::Count(40), 2).unwrap();
        let fine = tessellate(&c, Resolution::Count(400), 2).unwrap();
        assert!((fine.signed_area() - want).abs() < (coarse.signed_area() - want).abs());
    }

    #[test]
    fn bad_resolution_is_error() {
        let disks = [Circle::new(DVec2::ZERO, 1.0), Circle::new(DVec2::X, 1.0)];
        let c = DiskBSpline::open(1, &disks, None).unwrap();
        assert!(matches!(
            tessellate(&c, Resolution::Count(0), 2),
            Err(TessellateError::Resolution { .. })
        ));
        assert!(matches!(
            tessellate(&c, Resolution::Count(3), 0),
            Err(TessellateError::Resolution { .. })
        ));
        assert_eq!(
            tessellate(&c, Resolution::Chordal(-1.0), 2),
            Err(TessellateError::Tolerance(-1.0))
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Every vertex lies in the union of the disks ⟨q(t_k); r(t_k)⟩ of the samples, and
        /// every triangle's vertices come from neighbouring samples.
        #[test]
        fn vertices_inside_region(c in dbsc_strategy(), n in 1usize..30, rings in 1usize..4) {
            let m = tessellate(&c, Resolution::Count(n), rings).unwrap();
            let ts: Vec<f64> = m.params.iter().filter(|p| p.2.is_none()).map(|p| p.0).collect();
            prop_assert_eq!(ts.len(), n + 1);
            for v in &m.vertices {
                let inside = ts.iter().any(|&t| {
                    let d = c.circle_at(t);
                    v.distance(d.c) <= d.r * (1.0 + 1e-12) + 1e-12
                });
                prop_assert!(inside, "{}", v);
            }
            for tri in &m.triangles {
                let t: Vec<f64> = tri.iter().map(|&i| m.params[i].0).collect();
                let (a, b) = (t.iter().cloned().fold(f64::INFINITY, f64::min), t.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
                let ia = ts.iter().position(|&x| x == a).unwrap();
                prop_assert!(b == a || ts[ia + 1] == b);
            }
        }
    }
}
