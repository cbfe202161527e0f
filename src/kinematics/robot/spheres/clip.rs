//! The vertices of the intersection of a convex hull and a box, for a tight sphere around it.
//!
//! Every vertex of `cell ∩ hull` (two convex polytopes) is the meeting point of three of
//! their bounding planes, so it is one of: a hull vertex inside the cell, a cell corner inside
//! the hull, a hull edge crossing a cell face, or a cell edge crossing a hull face. All four
//! kinds are enumerated with an inclusive tolerance ([`INSIDE_TOLERANCE`]): a point kept by
//! round-off that lies slightly outside only makes the sphere larger, never smaller.

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::shape::ConvexPolyhedron;

use super::Sphere;
use crate::scene::collision::convert;

/// Tolerance (m) of the inside tests.
const INSIDE_TOLERANCE: f64 = 1e-9;

/// A convex hull's vertices, edges and face planes, in the shape frame.
pub(super) struct Polytope {
    points: Vec<Point3<f64>>,
    edges: Vec<[usize; 2]>,
    /// Face planes `n · x <= d` (outward unit normal `n`).
    planes: Vec<(Vector3<f64>, f64)>,
}

impl Polytope {
    /// The polytope of parry's hull placed at `shape_from_parry`.
    pub(super) fn new(hull: &ConvexPolyhedron, shape_from_parry: &Isometry3<f64>) -> Polytope {
        let points: Vec<Point3<f64>> = hull
            .points()
            .iter()
            .map(|p| shape_from_parry * Point3::from(convert::from_vector(p)))
            .collect();
        let edges = hull
            .edges()
            .iter()
            .map(|e| [e.vertices[0] as usize, e.vertices[1] as usize])
            .collect();
        let adjacent = hull.vertices_adj_to_face();
        let planes = hull
            .faces()
            .iter()
            .map(|f| {
                let n = shape_from_parry.rotation * convert::from_vector(&f.normal);
                let p = points[adjacent[f.first_vertex_or_edge as usize] as usize];
                (n, n.dot(&p.coords))
            })
            .collect();
        Polytope {
            points,
            edges,
            planes,
        }
    }

    /// The smallest-box-centred sphere enclosing the candidate vertices of
    /// `cell ∩ hull` (cell: the box at `shape_from_cell` with half extents `half`), or `None`
    /// if there are none.
    pub(super) fn sphere_in_cell(
        &self,
        shape_from_cell: &Isometry3<f64>,
        half: &Vector3<f64>,
    ) -> Option<Sphere> {
        let cell_from_shape = shape_from_cell.inverse();
        let points: Vec<Vector3<f64>> = self
            .points
            .iter()
            .map(|p| (cell_from_shape * p).coords)
            .collect();
        let planes: Vec<(Vector3<f64>, f64)> = self
            .planes
            .iter()
            .map(|(n, d)| {
                let n_cell = cell_from_shape.rotation * n;
                (n_cell, d + n_cell.dot(&cell_from_shape.translation.vector))
            })
            .collect();
        let in_cell = |p: &Vector3<f64>| (0..3).all(|i| p[i].abs() <= half[i] + INSIDE_TOLERANCE);
        let in_hull =
            |p: &Vector3<f64>| planes.iter().all(|(n, d)| n.dot(p) <= d + INSIDE_TOLERANCE);
        let mut found: Vec<Vector3<f64>> = points.iter().filter(|p| in_cell(p)).copied().collect();
        for k in 0..8 {
            let corner =
                Vector3::from_fn(|i, _| if k & (1 << i) == 0 { -half[i] } else { half[i] });
            if in_hull(&corner) {
                found.push(corner);
            }
        }
        // Hull edges across cell faces.
        for [a, b] in &self.edges {
            let (a, b) = (points[*a], points[*b]);
            for i in 0..3 {
                let span = b[i] - a[i];
                if span.abs() < f64::EPSILON {
                    continue;
                }
                for face in [-half[i], half[i]] {
                    let t = (face - a[i]) / span;
                    if (0.0..=1.0).contains(&t) {
                        let mut p = a + (b - a) * t;
                        p[i] = face;
                        if in_cell(&p) {
                            found.push(p);
                        }
                    }
                }
            }
        }
        // Cell edges across hull faces: axis `i` varies, the other two sit at corners.
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            for (sj, sk) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
                let mut base = Vector3::zeros();
                base[j] = sj * half[j];
                base[k] = sk * half[k];
                for (n, d) in &planes {
                    if n[i].abs() < f64::EPSILON {
                        continue;
                    }
                    let x = (d - n.dot(&base)) / n[i];
                    if x.abs() <= half[i] + INSIDE_TOLERANCE {
                        let mut p = base;
                        p[i] = x;
                        if in_hull(&p) {
                            found.push(p);
                        }
                    }
                }
            }
        }
        let first = *found.first()?;
        let (lo, hi) = found
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        let center = (lo + hi) / 2.0;
        let radius = found
            .iter()
            .map(|p| (p - center).norm())
            .fold(0.0, f64::max);
        Some(Sphere::new(
            shape_from_cell * Point3::from(center),
            radius + INSIDE_TOLERANCE,
        ))
    }
}
