//! Collision geometry compiled once at build time into parry shapes.

use std::fmt;
use std::panic::{AssertUnwindSafe, catch_unwind};

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query::{self, Ray};
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape, SupportMap};

use super::convert;
use super::hull::{HullGraph, Walk};
use crate::scene::Error;
use crate::scene::shape::{BoundingSphere, Shape};

/// A scene [`Shape`] as a parry shape, with the pose of parry's frame in the shape's frame:
/// the identity except for a cylinder (parry's runs along y, a scene cylinder along z). The
/// shape the collision checks use, for programs that query parry themselves or hand the shape
/// to a physics engine built on parry (rapier); [`parry`](super::parry) is the parry crate
/// this returns.
///
/// # Errors
/// [`Error::DegenerateMesh`] if parry cannot build a convex mesh's hull.
///
/// # Example
/// ```
/// use kinscene::scene::Shape;
/// use kinscene::scene::collision::parry_shape;
/// use nalgebra::{Point3, Vector3};
///
/// let (cylinder, shape_from_parry) = parry_shape(&Shape::Cylinder { radius: 0.1, length: 0.4 })?;
/// // Parry's axis (y) is the scene cylinder's axis (z).
/// let axis = shape_from_parry * Vector3::y();
/// assert!((axis - Vector3::z()).norm() < 1e-12);
/// assert!(cylinder.as_cylinder().is_some());
/// # Ok::<(), kinscene::scene::Error>(())
/// ```
pub fn parry_shape(shape: &Shape) -> Result<(SharedShape, Isometry3<f64>), Error> {
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
            // parry's hull code has panicked on near-degenerate input in the past; the
            // builder already rejects flat point clouds, this keeps a panic from escaping.
            let hull = catch_unwind(AssertUnwindSafe(|| SharedShape::convex_hull(&points)))
                .ok()
                .flatten();
            hull.ok_or_else(|| Error::DegenerateMesh {
                what: "convex mesh".to_string(),
                reason: "convex hull construction failed".into(),
            })?
        }
    };
    Ok((compiled, shape_from_parry))
}

/// A shape ready for parry queries, with its placement in its owner's frame (the part frame,
/// or the world frame for base shapes).
#[derive(Clone)]
pub(crate) struct CompiledShape {
    shape: SharedShape,
    /// Owner frame from parry's shape frame (includes the cylinder's z-to-y alignment).
    owner_from_parry: Isometry3<f64>,
    /// Bounding sphere in the owner frame.
    pub sphere: BoundingSphere,
    /// A convex mesh's edge graph, for parry's support points without its scan of every
    /// vertex (the `hull` module); `None` for other shapes and hulls it does not fit.
    graph: Option<HullGraph>,
}

impl fmt::Debug for CompiledShape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("CompiledShape")
            .field("shape_type", &self.shape.shape_type())
            .field("owner_from_parry", &self.owner_from_parry)
            .field("sphere", &self.sphere)
            .finish()
    }
}

impl CompiledShape {
    /// Compiles a validated shape placed at `owner_from_shape`.
    ///
    /// # Errors
    /// [`Error::DegenerateMesh`] if parry cannot build a convex hull.
    pub(crate) fn new(
        shape: &Shape,
        owner_from_shape: &Isometry3<f64>,
        what: &str,
    ) -> Result<Self, Error> {
        let (compiled, shape_from_parry) = parry_shape(shape).map_err(|e| match e {
            Error::DegenerateMesh { reason, .. } => Error::DegenerateMesh {
                what: what.to_string(),
                reason,
            },
            e => e,
        })?;
        let local = shape.bounding_sphere();
        let graph = match (shape, compiled.as_convex_polyhedron()) {
            (Shape::ConvexMesh { vertices, .. }, Some(hull)) => {
                let input: Vec<_> = vertices.iter().map(convert::point).collect();
                HullGraph::new(&input, hull)
            }
            _ => None,
        };
        Ok(CompiledShape {
            graph,
            shape: compiled,
            owner_from_parry: owner_from_shape * shape_from_parry,
            sphere: BoundingSphere {
                center: owner_from_shape * local.center,
                radius: local.radius,
            },
        })
    }

    /// The shape's world-aligned bounding box for an owner at `world_from_owner` (parry's
    /// `compute_aabb`: exact for every shape used here).
    pub(crate) fn world_box(&self, world_from_owner: &Isometry3<f64>) -> WorldBox {
        let aabb = self
            .shape
            .compute_aabb(&convert::pose(&(world_from_owner * self.owner_from_parry)));
        WorldBox {
            min: convert::from_vector(&aabb.mins),
            max: convert::from_vector(&aabb.maxs),
        }
    }

    /// A world-aligned box enclosing the shape for an owner at `world_from_owner`, for
    /// broad phases: [`CompiledShape::world_box`] grown by [`ENCLOSING_SLACK`] on every
    /// side, except that a hull with an edge graph finds its six extreme vertices by walking
    /// the graph (the `hull` module) instead of parry's transform of every vertex. The walk
    /// maximises each world coordinate as a dot product in the hull's frame, whose rounding
    /// differs from the transformed coordinate's by far less than the slack, so the box
    /// contains `world_box`'s.
    #[cfg_attr(
        not(all(feature = "ompl", feature = "pinocchio", feature = "casadi")),
        allow(dead_code)
    )]
    pub(crate) fn enclosing_world_box(&self, world_from_owner: &Isometry3<f64>) -> WorldBox {
        let grow = Vector3::repeat(ENCLOSING_SLACK);
        let (Some(hull), Some(graph)) = (self.shape.as_convex_polyhedron(), &self.graph) else {
            let b = self.world_box(world_from_owner);
            return WorldBox {
                min: b.min - grow,
                max: b.max + grow,
            };
        };
        let pose = world_from_owner * self.owner_from_parry;
        let rotation = pose.rotation.to_rotation_matrix();
        let points = hull.points();
        let (mut min, mut max) = (Vector3::zeros(), Vector3::zeros());
        for k in 0..3 {
            // World axis k in the hull's frame: row k of the rotation.
            let axis = rotation.matrix().row(k).transpose();
            let along = |id: usize| (pose * Point3::from(convert::from_vector(&points[id])))[k];
            let top = graph.support_id(points, convert::vector(&axis), 0);
            let bottom = graph.support_id(points, convert::vector(&-axis), top);
            max[k] = along(top);
            min[k] = along(bottom);
        }
        WorldBox {
            min: min - grow,
            max: max + grow,
        }
    }

    /// parry's `project_point` of the world point `p` onto the solid, for an owner at
    /// `world_from_owner`: the nearest boundary point (world frame) and whether `p` is inside.
    pub(crate) fn project_point(
        &self,
        world_from_owner: &Isometry3<f64>,
        p: &Point3<f64>,
    ) -> (Point3<f64>, bool) {
        let pose = convert::pose(&(world_from_owner * self.owner_from_parry));
        let proj = self.shape.project_point(&pose, convert::point(p), false);
        (
            Point3::from(convert::from_vector(&proj.point)),
            proj.is_inside,
        )
    }

    /// parry's solid `cast_ray` from the world point `origin` along the unit `dir`, for an
    /// owner at `world_from_owner`: the distance to the first surface point within `max` (0 if
    /// `origin` is inside), or `None`.
    pub(crate) fn cast_ray(
        &self,
        world_from_owner: &Isometry3<f64>,
        origin: &Point3<f64>,
        dir: &Vector3<f64>,
        max: f64,
    ) -> Option<f64> {
        let pose = convert::pose(&(world_from_owner * self.owner_from_parry));
        let ray = Ray::new(convert::point(origin), convert::vector(dir));
        self.shape.cast_ray(&pose, &ray, max, true)
    }

    /// A rounded box enclosing the shape, in the owner frame: `(owner_from_box, half
    /// extents, radius)`, the points within `radius` of the box. Exact for boxes, balls and
    /// capsules (a segment is a box with two zero extents); the local bounding box of parry's
    /// shape otherwise (cylinders, convex hulls).
    pub(crate) fn rounded_box(&self) -> (Isometry3<f64>, Vector3<f64>, f64) {
        if let Some(ball) = self.shape.as_ball() {
            return (self.owner_from_parry, Vector3::zeros(), ball.radius);
        }
        let (mins, maxs, radius) = match self.shape.as_capsule() {
            Some(c) => (
                convert::from_vector(&c.segment.a.min(c.segment.b)),
                convert::from_vector(&c.segment.a.max(c.segment.b)),
                c.radius,
            ),
            None => {
                let aabb = self.shape.compute_local_aabb();
                (
                    convert::from_vector(&aabb.mins),
                    convert::from_vector(&aabb.maxs),
                    0.0,
                )
            }
        };
        let center = nalgebra::Translation3::from((mins + maxs) / 2.0);
        (self.owner_from_parry * center, (maxs - mins) / 2.0, radius)
    }

    /// A hull with an edge graph as a parry support map for one query (`None` for other
    /// shapes).
    fn walk(&self) -> Option<Walk<'_>> {
        Some(Walk::new(
            self.shape.as_convex_polyhedron()?,
            self.graph.as_ref()?,
        ))
    }

    /// The bounding sphere's centre in the world, given the owner's world pose.
    pub(crate) fn world_center(&self, world_from_owner: &Isometry3<f64>) -> Point3<f64> {
        world_from_owner * self.sphere.center
    }
}

/// What [`CompiledShape::enclosing_world_box`] adds on every side (m): far above the
/// rounding of a coordinate within kilometres of the origin (about 1e-13 m).
#[cfg_attr(
    not(all(feature = "ompl", feature = "pinocchio", feature = "casadi")),
    allow(dead_code)
)]
pub(crate) const ENCLOSING_SLACK: f64 = 1e-9;

/// An axis-aligned box in the world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WorldBox {
    /// Lower corner.
    pub min: Vector3<f64>,
    /// Upper corner.
    pub max: Vector3<f64>,
}

impl WorldBox {
    /// The smallest box containing both.
    pub(crate) fn union(self, o: WorldBox) -> WorldBox {
        WorldBox {
            min: self.min.inf(&o.min),
            max: self.max.sup(&o.max),
        }
    }

    /// Whether the open boxes intersect (touching faces do not count).
    pub(crate) fn overlaps(&self, o: &WorldBox) -> bool {
        (0..3).all(|k| self.min[k] < o.max[k] && o.min[k] < self.max[k])
    }

    /// The largest separation of the two boxes along a world axis (`<= 0` if they overlap):
    /// a lower bound on the distance between any point of one and any point of the other.
    pub(crate) fn gap(&self, o: &WorldBox) -> f64 {
        (o.min - self.max).sup(&(self.min - o.max)).max()
    }
}

/// A compiled shape placed in the world.
pub(crate) struct Placed<'a> {
    pub shape: &'a CompiledShape,
    pub pose: parry3d_f64::math::Pose,
    pub center: Point3<f64>,
}

impl<'a> Placed<'a> {
    /// Places `shape` for an owner at `world_from_owner`.
    pub(crate) fn new(shape: &'a CompiledShape, world_from_owner: &Isometry3<f64>) -> Self {
        Placed {
            shape,
            pose: convert::pose(&(world_from_owner * shape.owner_from_parry)),
            center: shape.world_center(world_from_owner),
        }
    }

    /// A lower bound on the distance (m) between the two shapes from their bounding spheres.
    pub(crate) fn sphere_gap(&self, other: &Placed<'_>) -> f64 {
        (self.center - other.center).norm() - self.shape.sphere.radius - other.shape.sphere.radius
    }

    /// The exact separation distance (m), 0 if touching or overlapping. A pair parry does not
    /// support (none of the convex shapes used here) counts as touching (conservative).
    ///
    /// parry's `query::distance`, bit for bit, with two exceptions:
    /// - where a hull with an edge graph meets another shape that is not a ball, parry's GJK
    ///   (the function its dispatcher picks for that pair) runs with the hull's support points
    ///   found by a walk over the graph instead of a scan (the same points, see the `hull`
    ///   module);
    /// - two boxes go to parry's GJK as well, not to its box–box distance
    ///   (`distance_cuboid_cuboid`), which can be far off near contact: for a 0.44 × 0.36 ×
    ///   0.37 m box and a slab 0.5 mm thick swinging towards it, parry 0.31 gives 0.158 m
    ///   where GJK gives 2.5e-5 m, between samples at 4.0e-4 and 1.5e-6 m (the test
    ///   `two_boxes_near_contact_get_gjk_s_distance`).
    pub(crate) fn distance(&self, other: &Placed<'_>) -> f64 {
        if let Some(d) = self.walked_distance(other) {
            return d.max(0.0);
        }
        query::distance(
            &self.pose,
            &*self.shape.shape,
            &other.pose,
            &*other.shape.shape,
        )
        .map(|d| d.distance.max(0.0))
        .unwrap_or(0.0)
    }

    /// [`Placed::distance`] where it is at most `cutoff` (m), and `f64::INFINITY` where
    /// parry's GJK proves it larger: for a pair that [`Placed::distance`] runs through the
    /// hull walk, GJK is given `cutoff` as its `max_dist`, so that it stops at the first
    /// support point whose lower bound exceeds `cutoff` instead of converging. Otherwise it
    /// runs exactly the iterations of [`Placed::distance`] (that bound only ends them early),
    /// so the distances at most `cutoff` are the same, bit for bit. The same for the other
    /// pairs parry's dispatcher sends to GJK (boxes, cylinders, capsules against each
    /// other) and for two boxes (see [`Placed::distance`]); balls and the rest are
    /// [`Placed::distance`] itself.
    #[cfg_attr(
        not(all(feature = "ompl", feature = "pinocchio", feature = "casadi")),
        allow(dead_code)
    )]
    pub(crate) fn distance_within(&self, other: &Placed<'_>, cutoff: f64) -> f64 {
        match self.walked_distance_within(other, cutoff) {
            Some(d) => d.max(0.0),
            None => self.distance(other),
        }
    }

    /// parry's `distance_support_map_support_map_with_params` with no initial direction
    /// (the same steps) and GJK's `max_dist` set to `cutoff`: `+∞` when GJK stops on it.
    /// For the pairs [`Placed::walked_distance`] takes, two boxes, and the support-map pairs
    /// parry's dispatcher sends to that function (no ball, not two segments or a half-space,
    /// which it sends elsewhere); `None` for the others.
    fn walked_distance_within(&self, other: &Placed<'_>, cutoff: f64) -> Option<f64> {
        use parry3d_f64::math::{DEFAULT_EPSILON, Vector};
        use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
        use parry3d_f64::shape::HalfSpace;
        let (a, b) = (self.shape, other.shape);
        if a.shape.as_ball().is_some() || b.shape.as_ball().is_some() || cutoff.is_nan() {
            return None;
        }
        if a.graph.is_none()
            && b.graph.is_none()
            && (a.shape.as_segment().is_some() && b.shape.as_segment().is_some()
                || a.shape.as_shape::<HalfSpace>().is_some()
                || b.shape.as_shape::<HalfSpace>().is_some())
        {
            return None;
        }
        let (wa, wb) = (a.walk(), b.walk());
        let sa: &dyn SupportMap = match &wa {
            Some(w) => w,
            None => a.shape.as_support_map()?,
        };
        let sb: &dyn SupportMap = match &wb {
            Some(w) => w,
            None => b.shape.as_support_map()?,
        };
        let pos12 = self.pose.inv_mul(&other.pose);
        let dir = -pos12.translation;
        let dir = if dir.length_squared() > DEFAULT_EPSILON * DEFAULT_EPSILON {
            dir.normalize()
        } else {
            Vector::X
        };
        let mut simplex = VoronoiSimplex::new();
        simplex.reset(CsoPoint::from_shapes(&pos12, sa, sb, dir));
        let max_dist = cutoff.min(f64::MAX);
        Some(
            match gjk::closest_points(&pos12, sa, sb, max_dist, true, &mut simplex) {
                GJKResult::ClosestPoints(p1, p2, _) => (p1 - p2).length(),
                // GJK's lower bound passed `max_dist` (for `max_dist = f64::MAX`, never).
                GJKResult::NoIntersection(_) if max_dist < f64::MAX => f64::INFINITY,
                // As parry maps them (no proximity without `exact_dist = false`).
                _ => 0.0,
            },
        )
    }

    /// parry's distance of two support-mapped shapes, at least one a hull with a graph or
    /// both boxes, none a ball (parry's dispatcher sends balls elsewhere); `None` for other
    /// pairs.
    fn walked_distance(&self, other: &Placed<'_>) -> Option<f64> {
        let (a, b) = (self.shape, other.shape);
        let boxes = a.shape.as_cuboid().is_some() && b.shape.as_cuboid().is_some();
        if a.graph.is_none() && b.graph.is_none() && !boxes
            || a.shape.as_ball().is_some()
            || b.shape.as_ball().is_some()
        {
            return None;
        }
        // With no cutoff, the same steps as parry's `distance_support_map_support_map`.
        self.walked_distance_within(other, f64::INFINITY)
    }
}

/// All compiled collision geometry of a model.
#[derive(Debug, Clone, Default)]
pub(crate) struct CollisionGeometry {
    /// Per part (by id), its colliders in the part frame.
    pub parts: Vec<Vec<CompiledShape>>,
    /// Base shapes (by id), in the world frame.
    pub base: Vec<CompiledShape>,
}

#[cfg(test)]
mod tests {
    use nalgebra::{Translation3, UnitQuaternion};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// The walked box of a hull contains parry's box and exceeds it by at most the slack plus
    /// a rounding hair: 50 seeded point clouds (on a sphere, and a box's grid surface with
    /// whole faces tying), each at 40 seeded poses up to 100 m from the origin.
    #[test]
    fn a_hull_s_walked_box_encloses_parry_s_box() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let mut walked = 0;
        for cloud in 0..50 {
            let vertices: Vec<Point3<f64>> = if cloud % 2 == 0 {
                (0..200)
                    .map(|_| {
                        let v = Vector3::new(
                            rng.random_range(-1.0..1.0),
                            rng.random_range(-1.0..1.0),
                            rng.random_range(-1.0..1.0),
                        );
                        Point3::from(v.normalize() * 0.1)
                    })
                    .collect()
            } else {
                let g = |i: i32| f64::from(i) * 0.02;
                (-3..=3)
                    .flat_map(|i| (-3..=3).flat_map(move |j| (-3..=3).map(move |k| (i, j, k))))
                    .filter(|&(i, j, k): &(i32, i32, i32)| {
                        i.abs() == 3 || j.abs() == 3 || k.abs() == 3
                    })
                    .map(|(i, j, k)| Point3::new(g(i), g(j), 1.5 * g(k)))
                    .collect()
            };
            let shape = Shape::ConvexMesh {
                vertices,
                source: None,
            };
            let owner_from_shape = Isometry3::translation(0.01, -0.02, 0.03);
            let compiled = CompiledShape::new(&shape, &owner_from_shape, "cloud").unwrap();
            walked += usize::from(compiled.graph.is_some());
            for _ in 0..40 {
                let pose = Isometry3::from_parts(
                    Translation3::new(
                        rng.random_range(-100.0..100.0),
                        rng.random_range(-100.0..100.0),
                        rng.random_range(-100.0..100.0),
                    ),
                    UnitQuaternion::from_euler_angles(
                        rng.random_range(-3.2..3.2),
                        rng.random_range(-3.2..3.2),
                        rng.random_range(-3.2..3.2),
                    ),
                );
                let exact = compiled.world_box(&pose);
                let b = compiled.enclosing_world_box(&pose);
                for k in 0..3 {
                    assert!(b.min[k] <= exact.min[k] && b.max[k] >= exact.max[k]);
                    assert!(exact.min[k] - b.min[k] <= ENCLOSING_SLACK + 1e-12);
                    assert!(b.max[k] - exact.max[k] <= ENCLOSING_SLACK + 1e-12);
                }
            }
        }
        // The walk, not parry's box, was tested.
        assert!(walked >= 40, "{walked} of 50 hulls have a graph");
    }

    /// `distance_within` is parry's distance bit for bit where that is at most the cutoff and
    /// more than the cutoff elsewhere: a hull (with its graph), a box, a cylinder, a capsule
    /// and a ball against each other, 400 seeded relative poses each, cutoffs 0, 0.02, 0.1
    /// and infinity.
    #[test]
    fn distance_within_is_parry_s_distance_up_to_the_cutoff() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let hull: Vec<Point3<f64>> = (0..60)
            .map(|_| {
                let v = Vector3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                Point3::from(v.normalize().component_mul(&Vector3::new(0.05, 0.08, 0.12)))
            })
            .collect();
        let shapes = [
            Shape::ConvexMesh {
                vertices: hull,
                source: None,
            },
            Shape::box_size(Vector3::new(0.1, 0.2, 0.05)),
            Shape::cylinder(0.04, 0.2),
            Shape::Capsule {
                radius: 0.03,
                length: 0.1,
            },
            Shape::sphere(0.05),
        ];
        let compiled: Vec<CompiledShape> = shapes
            .iter()
            .map(|s| CompiledShape::new(s, &Isometry3::identity(), "shape").unwrap())
            .collect();
        assert!(compiled[0].graph.is_some());
        let mut stopped = 0;
        for (i, a) in compiled.iter().enumerate() {
            for b in &compiled[i..] {
                for _ in 0..400 {
                    let pose = |rng: &mut ChaCha8Rng| {
                        Isometry3::from_parts(
                            Translation3::new(
                                rng.random_range(-0.25..0.25),
                                rng.random_range(-0.25..0.25),
                                rng.random_range(-0.25..0.25),
                            ),
                            UnitQuaternion::from_euler_angles(
                                rng.random_range(-3.2..3.2),
                                rng.random_range(-3.2..3.2),
                                rng.random_range(-3.2..3.2),
                            ),
                        )
                    };
                    let (pa, pb) = (pose(&mut rng), pose(&mut rng));
                    let (x, y) = (Placed::new(a, &pa), Placed::new(b, &pb));
                    let exact = x.distance(&y);
                    for cutoff in [0.0, 0.02, 0.1, f64::INFINITY] {
                        let d = x.distance_within(&y, cutoff);
                        if exact <= cutoff {
                            assert_eq!(d.to_bits(), exact.to_bits(), "{exact} {d} {cutoff}");
                        } else {
                            assert!(d > cutoff, "{exact} {d} {cutoff}");
                            stopped += usize::from(d == f64::INFINITY);
                        }
                    }
                }
            }
        }
        // GJK did stop early.
        assert!(stopped > 100, "{stopped}");
    }

    /// A 0.44 × 0.36 × 0.37 m box (a robot chassis) and a slab 0.5 mm thick, 0.4 m wide,
    /// turned about a vertical hinge 0.55 m away until its edge nearly meets the box:
    /// [`Placed::distance`] and [`Placed::distance_within`] give GJK's distance (parry 0.31's
    /// box–box distance gives 0.158 m there). Checked without any distance code: the boxes do
    /// not intersect (parry's SAT intersection test), and moved together along GJK's witness
    /// direction by the distance plus 1e-6 m they do, so the true distance lies between 0 and
    /// that.
    #[test]
    fn two_boxes_near_contact_get_gjk_s_distance() {
        use parry3d_f64::query;
        let chassis = CompiledShape::new(
            &Shape::cuboid(Vector3::new(0.22, 0.18, 0.185)),
            &Isometry3::identity(),
            "chassis",
        )
        .unwrap();
        let slab = CompiledShape::new(
            &Shape::cuboid(Vector3::new(0.2, 0.00025, 0.4)),
            &Isometry3::identity(),
            "slab",
        )
        .unwrap();
        let at_chassis = Isometry3::translation(0.0, 0.0, 0.215);
        let angle = std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * 0.34082;
        let at_slab = Isometry3::from_parts(
            Translation3::new(0.55 + 0.2 * angle.cos(), 0.2 * angle.sin(), 0.5),
            UnitQuaternion::from_euler_angles(0.0, 0.0, angle),
        );
        let (a, b) = (
            Placed::new(&chassis, &at_chassis),
            Placed::new(&slab, &at_slab),
        );
        let d = a.distance(&b);
        assert_eq!(a.distance_within(&b, 0.01), d);
        assert!(d > 0.0 && d < 1e-4, "{d}");
        let apart = |shift: Vector3<f64>| {
            let moved = Isometry3::from_parts(
                Translation3::from(at_slab.translation.vector + shift),
                at_slab.rotation,
            );
            !query::intersection_test(
                &convert::pose(&at_chassis),
                &*chassis.shape,
                &convert::pose(&moved),
                &*slab.shape,
            )
            .unwrap()
            .intersecting
        };
        assert!(apart(Vector3::zeros()));
        let witness = query::closest_points(
            &convert::pose(&at_chassis),
            &*chassis.shape,
            &convert::pose(&at_slab),
            &*slab.shape,
            1.0,
        )
        .unwrap();
        let query::ClosestPoints::WithinMargin(p1, p2) = witness else {
            panic!("{witness:?}");
        };
        let towards = Vector3::new(p1.x - p2.x, p1.y - p2.y, p1.z - p2.z).normalize();
        assert!(!apart(towards * (d + 1e-6)));
    }
}
