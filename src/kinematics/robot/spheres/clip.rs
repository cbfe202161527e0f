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

    /// A sphere enclosing the candidate vertices of `cell ∩ hull` (cell: the box at
    /// `shape_from_cell` with half extents `half`), or `None` if there are none: centred at
    /// their box's centre moved inwards ([`inward`]).
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
        let center = inward((lo + hi) / 2.0, half.max(), &found, &planes);
        let radius = enclosing(&center, &found);
        Some(Sphere::new(
            shape_from_cell * Point3::from(center),
            radius + INSIDE_TOLERANCE,
        ))
    }
}

impl Polytope {
    /// How far (m) sphere `s` (shape frame) reaches past the hull's face planes: its radius
    /// less its centre's depth in the hull (negative when it lies inside).
    pub(super) fn overshoot(&self, s: &Sphere) -> f64 {
        s.radius - depth(&s.center.coords, &self.planes)
    }

    /// Whether `p` (shape frame) lies in the hull, by its face planes.
    #[cfg(test)]
    pub(super) fn holds(&self, p: &Point3<f64>) -> bool {
        depth(&p.coords, &self.planes) >= 0.0
    }
}

/// The depth (m) of `point` in the polytope of `planes`: the least `d − n·p` over the faces
/// (negative outside).
fn depth(point: &Vector3<f64>, planes: &[(Vector3<f64>, f64)]) -> f64 {
    planes
        .iter()
        .map(|(n, d)| d - n.dot(point))
        .fold(f64::INFINITY, f64::min)
}

/// The radius of the ball at `center` enclosing `points`.
fn enclosing(center: &Vector3<f64>, points: &[Vector3<f64>]) -> f64 {
    points
        .iter()
        .map(|p| (p - center).norm())
        .fold(0.0, f64::max)
}

/// How far past the hull's face planes the ball at `center` enclosing `points` reaches: its
/// radius less the centre's depth in the hull (the least `d − n·c` over the faces; negative
/// outside).
fn overshoot(
    center: &Vector3<f64>,
    points: &[Vector3<f64>],
    planes: &[(Vector3<f64>, f64)],
) -> f64 {
    enclosing(center, points) - depth(center, planes)
}

/// Steps (m) below which [`inward`] stops.
const INWARD_STEP: f64 = 1e-4;

/// A centre for the ball enclosing `points` (a cell's part of the hull) that reaches less far
/// past the hull's faces than the ball at `start`: a pattern search, from `start` in steps
/// of `scale / 2` halved down to [`INWARD_STEP`] along the 26 grid directions, of the convex
/// [`overshoot`] (the ball's radius less its centre's depth), stopped once that is not
/// positive. Moving the centre inwards grows the ball but moves it off the face: a ball
/// around a thin slice of the hull at a face otherwise reaches out by about its radius.
/// Any centre gives a ball that encloses `points`; this only chooses a tighter one.
fn inward(
    start: Vector3<f64>,
    scale: f64,
    points: &[Vector3<f64>],
    planes: &[(Vector3<f64>, f64)],
) -> Vector3<f64> {
    // The 26 unit directions to the neighbours of a grid point.
    let directions: Vec<Vector3<f64>> = (0..27)
        .filter(|&k| k != 13)
        .map(|k| {
            Vector3::new(
                f64::from(k % 3) - 1.0,
                f64::from((k / 3) % 3) - 1.0,
                f64::from(k / 9) - 1.0,
            )
            .normalize()
        })
        .collect();
    let mut best = (start, overshoot(&start, points, planes));
    let mut step = scale / 2.0;
    while step >= INWARD_STEP && best.1 > 0.0 {
        let mut moved = false;
        for dir in &directions {
            let c = best.0 + dir * step;
            let f = overshoot(&c, points, planes);
            if f < best.1 {
                best = (c, f);
                moved = true;
            }
        }
        if !moved {
            step /= 2.0;
        }
    }
    best.0
}
