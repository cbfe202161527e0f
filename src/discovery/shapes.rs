//! Point projection onto scene shapes placed in the world (parry's `project_point`), for
//! handle registration and the nesting rule. parry types stay inside this file; conversions go
//! through `scene::collision::convert`.

use std::panic::{AssertUnwindSafe, catch_unwind};

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::math::Pose;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape};

use crate::scene::Shape;
use crate::scene::collision::convert;

/// A scene shape placed in the world, ready for point queries.
#[derive(Clone)]
pub(crate) struct PlacedShape {
    shape: SharedShape,
    pose: Pose,
}

/// The projection of a point onto a shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Projection {
    /// The nearest point of the shape's boundary (world frame).
    pub point: Point3<f64>,
    /// Whether the query point is inside the solid.
    pub inside: bool,
}

impl PlacedShape {
    /// Places `shape` at `world_from_shape`; `None` if parry cannot build it (a degenerate
    /// hull; the scene builder already rejects those).
    pub(crate) fn new(shape: &Shape, world_from_shape: &Isometry3<f64>) -> Option<Self> {
        let mut shape_from_parry = Isometry3::identity();
        let compiled = match shape {
            Shape::Cuboid { half_extents } => {
                SharedShape::new(Cuboid::new(convert::vector(half_extents)))
            }
            Shape::Sphere { radius } => SharedShape::new(Ball::new(*radius)),
            Shape::Capsule { radius, length } => SharedShape::new(Capsule::new(
                convert::vector(&Vector3::new(0.0, 0.0, -length / 2.0)),
                convert::vector(&Vector3::new(0.0, 0.0, length / 2.0)),
                *radius,
            )),
            Shape::Cylinder { radius, length } => {
                // parry's cylinder runs along y; a +90° turn about x maps y onto z.
                shape_from_parry = Isometry3::rotation(Vector3::x() * std::f64::consts::FRAC_PI_2);
                SharedShape::new(Cylinder::new(length / 2.0, *radius))
            }
            Shape::ConvexMesh { vertices, .. } => {
                let points: Vec<_> = vertices.iter().map(convert::point).collect();
                catch_unwind(AssertUnwindSafe(|| SharedShape::convex_hull(&points)))
                    .ok()
                    .flatten()?
            }
        };
        Some(PlacedShape {
            shape: compiled,
            pose: convert::pose(&(world_from_shape * shape_from_parry)),
        })
    }

    /// Projects `p` onto the shape's boundary.
    pub(crate) fn project(&self, p: &Point3<f64>) -> Projection {
        let proj = self
            .shape
            .project_point(&self.pose, convert::point(p), false);
        Projection {
            point: Point3::from(convert::from_vector(&proj.point)),
            inside: proj.is_inside,
        }
    }

    /// Distance from `p` to the solid (0 inside).
    pub(crate) fn distance(&self, p: &Point3<f64>) -> f64 {
        let proj = self.project(p);
        if proj.inside {
            0.0
        } else {
            (proj.point - p).norm()
        }
    }
}
