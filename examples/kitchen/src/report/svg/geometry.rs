//! Floor projections: the convex outlines of colliders seen from above, their height ranges,
//! and the xy bounds of a drawing.

use std::f64::consts::PI;

use kinscene::scene::{SceneData, SceneModel, Shape};
use nalgebra::{Isometry3, Point2, Point3, Vector2, Vector3};

/// Points per circle when a cylinder, sphere or capsule is projected (inscribed polygon).
const CIRCLE_POINTS: usize = 24;

/// The world points whose xy convex hull is the shape's floor projection (exact for boxes and
/// meshes; cylinders, spheres and capsules by inscribed 24-gons) and whose z range is the
/// shape's (exact for every shape).
pub(super) fn shape_points(
    shape: &Shape,
    world_from_shape: &Isometry3<f64>,
    out: &mut Vec<Point3<f64>>,
) {
    let circle = |out: &mut Vec<Point3<f64>>, centre: Point3<f64>, r: f64| {
        for k in 0..CIRCLE_POINTS {
            let a = 2.0 * PI * k as f64 / CIRCLE_POINTS as f64;
            out.push(centre + Vector3::new(r * a.cos(), r * a.sin(), 0.0));
        }
        out.push(centre + Vector3::new(0.0, 0.0, r));
        out.push(centre - Vector3::new(0.0, 0.0, r));
    };
    match shape {
        Shape::Cuboid { half_extents: h } => {
            for k in 0..8 {
                let sx = if k & 1 == 0 { -1.0 } else { 1.0 };
                let sy = if k & 2 == 0 { -1.0 } else { 1.0 };
                let sz = if k & 4 == 0 { -1.0 } else { 1.0 };
                out.push(world_from_shape * Point3::new(sx * h.x, sy * h.y, sz * h.z));
            }
        }
        Shape::Cylinder { radius, length } => {
            // A tilted cylinder's projection is the hull of its two end discs' projections;
            // the z extremes of a disc lie on it, so 24 points per disc plus the exact z
            // extent of the rims below.
            let axis = world_from_shape.rotation * Vector3::z();
            for end in [-0.5, 0.5] {
                for k in 0..CIRCLE_POINTS {
                    let a = 2.0 * PI * k as f64 / CIRCLE_POINTS as f64;
                    out.push(
                        world_from_shape
                            * Point3::new(radius * a.cos(), radius * a.sin(), end * length),
                    );
                }
                // Exact z extremes of the rim: centre ± r·sqrt(1 − axis_z²).
                let centre = world_from_shape * Point3::new(0.0, 0.0, end * length);
                let dz = radius * (1.0 - axis.z * axis.z).max(0.0).sqrt();
                out.push(centre + Vector3::new(0.0, 0.0, dz));
                out.push(centre - Vector3::new(0.0, 0.0, dz));
            }
        }
        Shape::Sphere { radius } => {
            circle(out, world_from_shape * Point3::origin(), *radius);
        }
        Shape::Capsule { radius, length } => {
            for end in [-0.5, 0.5] {
                circle(
                    out,
                    world_from_shape * Point3::new(0.0, 0.0, end * length),
                    *radius,
                );
            }
        }
        Shape::ConvexMesh { vertices, .. } => {
            out.extend(vertices.iter().map(|v| world_from_shape * v));
        }
        other => {
            // A shape this version does not know: its bounding sphere (conservative).
            let s = other.bounding_sphere();
            circle(out, world_from_shape * s.center, s.radius);
        }
    }
}

/// A body projected on the floor: its convex outline (counter-clockwise, world xy, metres)
/// and its height range (m).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Footprint {
    pub(super) outline: Vec<Point2<f64>>,
    pub(super) z_min: f64,
    pub(super) z_max: f64,
}

impl Footprint {
    pub(super) fn of(points: &[Point3<f64>]) -> Option<Footprint> {
        if points.is_empty() {
            return None;
        }
        let z_min = points.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        let z_max = points.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
        let outline = convex_hull(points.iter().map(|p| Point2::new(p.x, p.y)).collect());
        Some(Footprint {
            outline,
            z_min,
            z_max,
        })
    }
}

/// A part projected on the floor: one convex outline per collider.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Outline {
    pub(super) pieces: Vec<Footprint>,
}

impl Outline {
    pub(super) fn points(&self) -> impl Iterator<Item = &Point2<f64>> {
        self.pieces.iter().flat_map(|p| &p.outline)
    }

    pub(super) fn z_min(&self) -> f64 {
        self.pieces
            .iter()
            .map(|p| p.z_min)
            .fold(f64::INFINITY, f64::min)
    }

    /// The mean of the outline vertices (a label position).
    pub(super) fn centroid(&self) -> Point2<f64> {
        let (sum, n) = self
            .points()
            .fold((Vector2::zeros(), 0usize), |(acc, n), p| {
                (acc + p.coords, n + 1)
            });
        Point2::from(sum / n.max(1) as f64)
    }
}

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise, without
/// collinear points. Fewer than three distinct points are returned as they are.
fn convex_hull(mut points: Vec<Point2<f64>>) -> Vec<Point2<f64>> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup_by(|a, b| (a.x - b.x).abs() < 1e-12 && (a.y - b.y).abs() < 1e-12);
    if points.len() < 3 {
        return points;
    }
    let cross = |o: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>| {
        (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
    };
    let mut hull: Vec<Point2<f64>> = Vec::with_capacity(points.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point2<f64>>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2
                && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 1e-14
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull
}

/// The floor projection of part `index` (one outline per collider) at the poses in `data`;
/// `None` for a part without colliders.
pub(super) fn part_outline(model: &SceneModel, data: &SceneData, index: usize) -> Option<Outline> {
    let part = model.parts().get(index)?;
    let world_from_part = data.world_from_parts().get(index)?;
    let mut pieces = Vec::new();
    let mut points = Vec::new();
    for c in part.colliders() {
        points.clear();
        shape_points(
            &c.shape,
            &(world_from_part * c.part_from_shape),
            &mut points,
        );
        pieces.extend(Footprint::of(&points));
    }
    (!pieces.is_empty()).then_some(Outline { pieces })
}

/// Axis-aligned xy bounds.
#[derive(Clone, Copy)]
pub(super) struct Bounds {
    pub(super) lo: Point2<f64>,
    pub(super) hi: Point2<f64>,
}

impl Bounds {
    pub(super) fn empty() -> Self {
        Bounds {
            lo: Point2::new(f64::INFINITY, f64::INFINITY),
            hi: Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        }
    }
    pub(super) fn add(&mut self, p: Point2<f64>, pad: f64) {
        self.lo = Point2::new(self.lo.x.min(p.x - pad), self.lo.y.min(p.y - pad));
        self.hi = Point2::new(self.hi.x.max(p.x + pad), self.hi.y.max(p.y + pad));
    }
    pub(super) fn is_empty(&self) -> bool {
        self.lo.x > self.hi.x
    }
}
