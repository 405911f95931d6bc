//! Tessellation of a skinned region (kruppa-2023 Sec. 5, eqs. 26–27).
//!
//! Between the skins the region is parametrised by linear interpolation,
//! s(u, v) = (1 − v) s⁻(u) + v s⁺(u), v ∈ [0, 1] (eq. 26), where for a DBSC parameter u the
//! skin arcs are evaluated at their local parameter (u − u_k)/(u_{k+1} − u_k) (eq. 27). With
//! two-sided skins the left and right arcs have their own breakpoints; each side is
//! evaluated on the arc of its own sequence that contains u.

use super::dbsc_skin::DbscSkin;
use crate::geom::{CubicBez, DVec2};

/// A triangle mesh: vertices and counter-clockwise index triples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RegionMesh {
    /// Mesh vertices, row by row along the stroke; each row runs from the right skin (v = 0) to the
    /// left skin (v = 1).
    pub vertices: Vec<DVec2>,
    /// Triangles as indices into `vertices`, counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
}

/// Errors of the tessellation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// `along` or `across` is zero.
    #[error("need at least 1 division along and across the stroke, got {along} × {across}")]
    Divisions {
        /// Steps in u per segment between consecutive circles.
        along: usize,
        /// Steps in v across the stroke, from the right skin to the left one.
        across: usize,
    },
    /// A skin has no arcs (or no arc contains a row's parameter).
    #[error("{side} skin is empty")]
    EmptySkin {
        /// Which skin: `"left"`, `"right"` or `"left or right"`.
        side: &'static str,
    },
}

/// The skin point at DBSC parameter u (eq. 27): arc k with params[k] ≤ u ≤ params[k + 1]
/// (`end` closes the last arc of a closed skin).
fn skin_at(arcs: &[CubicBez], params: &[f64], end: f64, u: f64) -> Option<DVec2> {
    let k = params.partition_point(|&p| p <= u).saturating_sub(1);
    let k = k.min(arcs.len().checked_sub(1)?);
    let a = *params.get(k)?;
    let b = params.get(k + 1).copied().unwrap_or(end);
    let s = if b > a {
        ((u - a) / (b - a)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Some(arcs.get(k)?.eval(s))
}

/// Tessellates the region between the skins of `skin` (eqs. 26–27): every segment between
/// consecutive circles is divided into `along` steps in u and `across` steps in v; the
/// vertices of a row u are s(u, j/across). Triangles are oriented counter-clockwise for a
/// stroke whose left skin is on the left.
pub fn region_mesh(skin: &DbscSkin, along: usize, across: usize) -> Result<RegionMesh, MeshError> {
    if along == 0 || across == 0 {
        return Err(MeshError::Divisions { along, across });
    }
    if skin.left.is_empty() {
        return Err(MeshError::EmptySkin { side: "left" });
    }
    if skin.right.is_empty() {
        return Err(MeshError::EmptySkin { side: "right" });
    }
    let end = skin.report.last().map(|r| r.t1).unwrap_or(0.0);
    // Rows at the u values.
    let mut us = Vec::new();
    for r in &skin.report {
        for k in 0..along {
            us.push(r.t0 + (r.t1 - r.t0) * k as f64 / along as f64);
        }
    }
    if !skin.closed {
        us.push(end);
    }
    let mut mesh = RegionMesh::default();
    for &u in &us {
        let (Some(l), Some(r)) = (
            skin_at(&skin.left, &skin.left_params, end, u),
            skin_at(&skin.right, &skin.right_params, end, u),
        ) else {
            return Err(MeshError::EmptySkin {
                side: "left or right",
            });
        };
        for j in 0..=across {
            let v = j as f64 / across as f64;
            mesh.vertices.push((1.0 - v) * r + v * l);
        }
    }
    let row = across + 1;
    let rows = us.len();
    let quads = if skin.closed { rows } else { rows - 1 };
    for i in 0..quads {
        let (a, b) = (i * row, ((i + 1) % rows) * row);
        for j in 0..across {
            // Right skin at j = 0, left at j = across: travel direction is +i, so
            // (a+j, b+j, b+j+1) turns counter-clockwise.
            mesh.triangles.push([a + j, b + j, b + j + 1]);
            mesh.triangles.push([a + j, b + j + 1, a + j + 1]);
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dbsc::DiskBSpline;
    use crate::geom::Circle;
    use crate::geom::path::polygon_area;
    use crate::skin::dbsc_skin::{DbscSkinOptions, skin_dbsc};

    fn stroke(d: &[(f64, f64, f64)]) -> DiskBSpline {
        let disks: Vec<Circle> = d
            .iter()
            .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
            .collect();
        DiskBSpline::open(3, &disks, None).unwrap()
    }

    #[test]
    fn mesh_vertices_lie_inside_the_outline() {
        for d in [
            vec![
                (0.0, 0.0, 1.0),
                (6.0, 3.0, 1.5),
                (12.0, 0.0, 2.0),
                (18.0, -3.0, 1.5),
                (24.0, 0.0, 1.2),
            ],
            vec![
                (0.0, 0.0, 0.8),
                (4.0, 0.0, 0.8),
                (5.0, 1.0, 0.8),
                (4.0, 2.0, 0.8),
                (0.0, 2.2, 0.8),
            ],
        ] {
            let c = stroke(&d);
            let s = skin_dbsc(&c, &DbscSkinOptions::default()).unwrap();
            let (along, across) = (4, 3);
            let mesh = region_mesh(&s, along, across).unwrap();
            let rows = s.report.len() * along + 1;
            assert_eq!(mesh.vertices.len(), rows * (across + 1));
            assert_eq!(mesh.triangles.len(), 2 * (rows - 1) * across);
            let poly = s.outline[0].flatten(1e-6);
            assert!(polygon_area(&poly) > 0.0);
            let tol = 1e-6;
            for (k, &p) in mesh.vertices.iter().enumerate() {
                let on_boundary = poly
                    .windows(2)
                    .any(|w| crate::geom::Line::new(w[0], w[1]).distance(p) <= tol);
                assert!(
                    on_boundary || crate::geom::predicates::winding_number(&poly, p) == 1,
                    "vertex {k} {p} outside"
                );
            }
            // Rows interpolate the skins linearly: v = 0 is on the right skin, v = 1 on the
            // left, and the mid vertex is their average (eq. 26).
            for i in 0..rows {
                let row = &mesh.vertices[i * (across + 1)..(i + 1) * (across + 1)];
                let mid = 0.5 * (row[0] + row[across]);
                let third = row[0] + (row[across] - row[0]) / across as f64;
                assert!((row[1] - third).length() < 1e-12 && mid.is_finite());
            }
            // Triangles of a loop-free stroke are counter-clockwise (area > 0) and their
            // areas add up to the area between the skin polylines of the rows.
            if d[2].1 < 1.0 {
                let tri_area: f64 = mesh
                    .triangles
                    .iter()
                    .map(|t| {
                        let (a, b, c) = (
                            mesh.vertices[t[0]],
                            mesh.vertices[t[1]],
                            mesh.vertices[t[2]],
                        );
                        0.5 * crate::geom::cross(b - a, c - a)
                    })
                    .sum();
                assert!(mesh.triangles.iter().all(|t| {
                    let (a, b, c) = (
                        mesh.vertices[t[0]],
                        mesh.vertices[t[1]],
                        mesh.vertices[t[2]],
                    );
                    crate::geom::cross(b - a, c - a) > 0.0
                }));
                // The outline adds the two end caps and the curved skins between rows.
                assert!(tri_area < polygon_area(&poly) && tri_area > 0.8 * polygon_area(&poly));
            }
        }
        let s = skin_dbsc(
            &stroke(&[
                (0.0, 0.0, 1.0),
                (3.0, 1.0, 1.0),
                (6.0, 0.0, 1.0),
                (9.0, 0.0, 1.0),
            ]),
            &DbscSkinOptions::default(),
        )
        .unwrap();
        assert_eq!(
            region_mesh(&s, 0, 2),
            Err(MeshError::Divisions {
                along: 0,
                across: 2
            })
        );
    }
}
