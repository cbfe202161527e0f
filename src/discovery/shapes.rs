//! Point projection onto scene shapes placed in the world (parry's `project_point`), for
//! handle registration and the nesting rule. The parry shapes are the scene layer's
//! `CompiledShape`s.

use nalgebra::{Isometry3, Point3};

use crate::scene::Shape;
use crate::scene::collision::geometry::{CompiledShape, Placed};

/// A scene shape placed in the world, ready for point queries (the scene layer's compiled
/// parry shape, owned by the world frame).
#[derive(Clone)]
pub(crate) struct PlacedShape {
    shape: CompiledShape,
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
        CompiledShape::new(shape, world_from_shape, "discovery shape")
            .ok()
            .map(|shape| PlacedShape { shape })
    }

    /// Projects `p` onto the shape's boundary.
    pub(crate) fn project(&self, p: &Point3<f64>) -> Projection {
        let (point, inside) = self.shape.project_point(&Isometry3::identity(), p);
        Projection { point, inside }
    }

    /// The separation (m) between the two solids, 0 if they touch or overlap.
    pub(crate) fn gap(&self, other: &PlacedShape) -> f64 {
        let at = Isometry3::identity();
        Placed::new(&self.shape, &at).distance(&Placed::new(&other.shape, &at))
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
