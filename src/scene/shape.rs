//! Collision shapes and their placement on a part.

use nalgebra::{Isometry3, Point3, Vector3};
use serde::{Deserialize, Serialize};

use super::Error;
use super::validate::{check_finite, check_isometry, check_positive};

/// A convex collision shape in its own frame. All lengths in metres.
///
/// Non-exhaustive: more shapes may be added (match with a wildcard arm).
///
/// Shapes follow URDF conventions where URDF has the shape: centred on the frame origin, a
/// cylinder along the frame's z axis. A triangle mesh is represented by the convex hull of its
/// vertices ([`Shape::ConvexMesh`]); the hull contains the mesh, so collision answers are
/// conservative for non-convex meshes. A URDF importer should split a strongly non-convex part
/// into several colliders (one per convex piece).
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// A box with the given half extents along x, y, z (URDF `box size` is twice this).
    Cuboid {
        /// Half extents (m), all > 0.
        half_extents: Vector3<f64>,
    },
    /// A solid cylinder along z, centred on the origin (as URDF `cylinder`).
    Cylinder {
        /// Radius (m), > 0.
        radius: f64,
        /// Total length along z (m), > 0.
        length: f64,
    },
    /// A solid sphere centred on the origin.
    Sphere {
        /// Radius (m), > 0.
        radius: f64,
    },
    /// A capsule along z: the points within `radius` of the segment from `(0, 0, -length/2)`
    /// to `(0, 0, length/2)` (total extent `length + 2 radius`, as URDF's `capsule`).
    Capsule {
        /// Radius (m), > 0.
        radius: f64,
        /// Length of the central segment (m), > 0.
        length: f64,
    },
    /// The convex hull of a point cloud (for example a mesh's vertices, already scaled).
    /// At least 4 points spanning a volume.
    ConvexMesh {
        /// The points (m), in the shape frame.
        vertices: Vec<Point3<f64>>,
        /// Where the points came from, kept so an exporter can write the mesh reference back.
        source: Option<MeshSource>,
    },
}

/// The file a [`Shape::ConvexMesh`] was loaded from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshSource {
    /// The mesh URI as written in the scene description (for example `package://k/door.stl`).
    pub uri: String,
    /// The scale that was applied to the file's vertices.
    pub scale: Vector3<f64>,
}

/// A shape placed on a part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Collider {
    /// The shape.
    pub shape: Shape,
    /// Pose of the shape frame in the part frame (URDF `collision/origin`).
    pub part_from_shape: Isometry3<f64>,
}

impl Collider {
    /// A collider with the given shape and pose in the part frame.
    pub fn new(shape: Shape, part_from_shape: Isometry3<f64>) -> Self {
        Collider {
            shape,
            part_from_shape,
        }
    }
}

/// Bounding sphere of a shape or collider: every point of the shape is within `radius` of
/// `center`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundingSphere {
    /// Centre (m), in the frame the sphere is expressed in.
    pub center: Point3<f64>,
    /// Radius (m).
    pub radius: f64,
}

impl Shape {
    /// A box from its half extents (m).
    pub fn cuboid(half_extents: Vector3<f64>) -> Self {
        Shape::Cuboid { half_extents }
    }

    /// A box from its full size (m), as URDF `<box size="x y z"/>`.
    pub fn box_size(size: Vector3<f64>) -> Self {
        Shape::Cuboid {
            half_extents: size / 2.0,
        }
    }

    /// A sphere of the given radius (m).
    pub fn sphere(radius: f64) -> Self {
        Shape::Sphere { radius }
    }

    /// A cylinder along z (m).
    pub fn cylinder(radius: f64, length: f64) -> Self {
        Shape::Cylinder { radius, length }
    }

    /// A sphere containing the shape, in the shape frame. Exact (smallest) for the primitive
    /// shapes; for a convex mesh, centred on the centre of the vertices' bounding box.
    pub fn bounding_sphere(&self) -> BoundingSphere {
        let (center, radius) = match self {
            Shape::Cuboid { half_extents } => (Point3::origin(), half_extents.norm()),
            Shape::Cylinder { radius, length } => (Point3::origin(), radius.hypot(length / 2.0)),
            Shape::Sphere { radius } => (Point3::origin(), *radius),
            Shape::Capsule { radius, length } => (Point3::origin(), radius + length / 2.0),
            Shape::ConvexMesh { vertices, .. } => {
                let mut lo = Vector3::repeat(f64::INFINITY);
                let mut hi = Vector3::repeat(f64::NEG_INFINITY);
                for v in vertices {
                    lo = lo.inf(&v.coords);
                    hi = hi.sup(&v.coords);
                }
                let c = Point3::from((lo + hi) / 2.0);
                let r = vertices.iter().map(|v| (v - c).norm()).fold(0.0, f64::max);
                (c, r)
            }
        };
        BoundingSphere { center, radius }
    }

    /// Checks dimensions are finite and positive and a mesh spans a volume.
    pub(crate) fn validate(&self, what: &str) -> Result<(), Error> {
        match self {
            Shape::Cuboid { half_extents } => {
                for (axis, v) in ["x", "y", "z"].iter().zip(half_extents.iter()) {
                    check_positive(*v, || format!("{what} half extent {axis}"))?;
                }
            }
            Shape::Cylinder { radius, length } | Shape::Capsule { radius, length } => {
                check_positive(*radius, || format!("{what} radius"))?;
                check_positive(*length, || format!("{what} length"))?;
            }
            Shape::Sphere { radius } => check_positive(*radius, || format!("{what} radius"))?,
            Shape::ConvexMesh { vertices, source } => {
                for v in vertices {
                    check_finite(v.coords.iter().copied(), || format!("{what} vertex"))?;
                }
                if let Some(s) = source {
                    check_finite(s.scale.iter().copied(), || format!("{what} mesh scale"))?;
                }
                check_volume(vertices, what)?;
            }
        }
        Ok(())
    }
}

impl Collider {
    /// The shape's bounding sphere in the part frame.
    pub fn bounding_sphere(&self) -> BoundingSphere {
        let s = self.shape.bounding_sphere();
        BoundingSphere {
            center: self.part_from_shape * s.center,
            radius: s.radius,
        }
    }

    pub(crate) fn validate(&self, what: &str) -> Result<(), Error> {
        self.shape.validate(what)?;
        check_isometry(&self.part_from_shape, what)
    }
}

/// Thickness, relative to the largest extent, below which a point cloud counts as flat.
const MIN_RELATIVE_THICKNESS: f64 = 1e-6;

/// Rejects point clouds with fewer than 4 points or thinner than [`MIN_RELATIVE_THICKNESS`]
/// times their extent in some direction.
fn check_volume(vertices: &[Point3<f64>], what: &str) -> Result<(), Error> {
    let degenerate = |reason: &str| Error::DegenerateMesh {
        what: what.to_string(),
        reason: reason.to_string(),
    };
    if vertices.len() < 4 {
        return Err(degenerate("fewer than 4 vertices"));
    }
    let p0 = vertices[0];
    let far = |f: &dyn Fn(&Point3<f64>) -> f64| {
        vertices
            .iter()
            .copied()
            .max_by(|a, b| f(a).total_cmp(&f(b)))
            .unwrap_or(p0)
    };
    let p1 = far(&|p| (p - p0).norm());
    let d = (p1 - p0).norm();
    if d <= 0.0 {
        return Err(degenerate("all vertices coincide"));
    }
    let e1 = (p1 - p0) / d;
    let p2 = far(&|p| (p - p0).cross(&e1).norm());
    let n = (p2 - p0).cross(&e1);
    if n.norm() <= MIN_RELATIVE_THICKNESS * d {
        return Err(degenerate("vertices are collinear"));
    }
    let n = n.normalize();
    let h = vertices
        .iter()
        .map(|p| (p - p0).dot(&n).abs())
        .fold(0.0, f64::max);
    if h <= MIN_RELATIVE_THICKNESS * d {
        return Err(degenerate("vertices are coplanar"));
    }
    Ok(())
}
