//! Proptest strategies for scene graphs, shared by the scene tests and reusable by later
//! issues and benches through `#[path = ".../tests/scene/generators.rs"] mod generators;`.
//!
//! Depends only on `kinscene`, `nalgebra` and `proptest`.
#![allow(dead_code)]

use std::f64::consts::PI;

use kinscene::scene::{
    BaseShape, Collider, Handle, Joint, JointKind, Limits, PartSpec, SceneModel, SceneModelBuilder,
    Shape, State,
};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;

/// Deepest tree generated (a part on the base has depth 1).
pub const MAX_DEPTH: usize = 4;

/// A uniformly distributed unit vector.
pub fn unit_vector() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..=1.0f64, 0.0..(2.0 * PI)).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vector3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// A random rotation (axis-angle with a uniform axis).
pub fn rotation() -> impl Strategy<Value = UnitQuaternion<f64>> {
    (unit_vector(), -PI..PI).prop_map(|(axis, angle)| UnitQuaternion::new(axis * angle))
}

/// A random pose with translation components in `[-max_translation, max_translation]` (m).
pub fn isometry(max_translation: f64) -> impl Strategy<Value = Isometry3<f64>> {
    let t = -max_translation..=max_translation;
    (t.clone(), t.clone(), t, rotation())
        .prop_map(|(x, y, z, r)| Isometry3::from_parts(Translation3::new(x, y, z), r))
}

/// Revolute or prismatic.
pub fn joint_kind() -> impl Strategy<Value = JointKind> {
    prop_oneof![Just(JointKind::Revolute), Just(JointKind::Prismatic)]
}

/// Limits containing 0: revolute within `[-π, π]`, prismatic within `[-0.3, 0.5]` m.
pub fn limits(kind: JointKind) -> impl Strategy<Value = Limits> {
    let (lo, hi) = match kind {
        JointKind::Revolute => (PI, PI),
        JointKind::Prismatic => (0.3, 0.5),
    };
    (0.0..=lo, 0.0..=hi).prop_map(|(l, u)| Limits::new(-l, u))
}

/// A joint called `name` with a random kind, origin (within 0.6 m), axis (not normalised:
/// random length in `[0.2, 3]`) and limits.
pub fn joint(name: String) -> impl Strategy<Value = Joint> {
    joint_kind().prop_flat_map(move |kind| {
        let name = name.clone();
        (isometry(0.6), unit_vector(), 0.2..3.0f64, limits(kind)).prop_map(
            move |(origin, axis, len, limits)| {
                Joint::new(name.clone(), kind, origin, axis * len, limits)
            },
        )
    })
}

/// A point cloud spanning a volume: a tetrahedron plus random points, within 0.3 m.
pub fn hull_points() -> impl Strategy<Value = Vec<Point3<f64>>> {
    let c = -0.3..0.3f64;
    (
        0.05..0.3f64,
        prop::collection::vec(
            (c.clone(), c.clone(), c).prop_map(|(x, y, z)| Point3::new(x, y, z)),
            0..8,
        ),
    )
        .prop_map(|(s, extra)| {
            let mut v = vec![
                Point3::new(s, 0.0, 0.0),
                Point3::new(0.0, s, 0.0),
                Point3::new(0.0, 0.0, s),
                Point3::new(-s, -s, -s),
            ];
            v.extend(extra);
            v
        })
}

/// Any shape, dimensions between 1 cm and 0.4 m.
pub fn shape() -> impl Strategy<Value = Shape> {
    let d = 0.01..0.4f64;
    prop_oneof![
        (d.clone(), d.clone(), d.clone())
            .prop_map(|(x, y, z)| Shape::cuboid(Vector3::new(x, y, z))),
        (d.clone(), d.clone()).prop_map(|(radius, length)| Shape::Cylinder { radius, length }),
        d.clone().prop_map(Shape::sphere),
        (d.clone(), d).prop_map(|(radius, length)| Shape::Capsule { radius, length }),
        hull_points().prop_map(|vertices| Shape::ConvexMesh {
            vertices,
            source: None
        }),
    ]
}

/// A shape at a random pose (within 0.5 m) in its part frame.
pub fn collider() -> impl Strategy<Value = Collider> {
    (shape(), isometry(0.5)).prop_map(|(s, pose)| Collider::new(s, pose))
}

/// A handle called `name` within 0.5 m of the part origin, normal not normalised.
pub fn handle(name: String) -> impl Strategy<Value = Handle> {
    let c = -0.5..0.5f64;
    (c.clone(), c.clone(), c, unit_vector(), 0.5..2.0f64)
        .prop_map(move |(x, y, z, n, len)| Handle::new(name.clone(), Point3::new(x, y, z), n * len))
}

/// Parent choices for `n` parts: `None` is the base, `Some(k)` an earlier part, depth ≤
/// [`MAX_DEPTH`].
pub fn tree(n: usize) -> impl Strategy<Value = Vec<Option<usize>>> {
    prop::collection::vec(any::<u32>(), n).prop_map(|raw| {
        let mut depth = Vec::with_capacity(raw.len());
        let mut parents = Vec::with_capacity(raw.len());
        for (i, r) in raw.iter().enumerate() {
            let choice = *r as usize % (i + 1);
            let parent = if choice == 0 || depth[choice - 1] >= MAX_DEPTH {
                None
            } else {
                Some(choice - 1)
            };
            depth.push(parent.map_or(1, |p: usize| depth[p] + 1));
            parents.push(parent);
        }
        parents
    })
}

/// One part spec `part{i}` (joint `joint{i}`, handles `handle{i}_{k}`) with up to 3 colliders
/// and 2 handles.
pub fn part(i: usize, parent: Option<usize>) -> impl Strategy<Value = PartSpec> {
    let handles = prop::collection::vec(Just(()), 0..=2).prop_flat_map(move |hs| {
        hs.iter()
            .enumerate()
            .map(|(k, _)| handle(format!("handle{i}_{k}")))
            .collect::<Vec<_>>()
    });
    (
        joint(format!("joint{i}")),
        prop::collection::vec(collider(), 0..=3),
        handles,
    )
        .prop_map(move |(joint, colliders, handles)| PartSpec {
            name: format!("part{i}"),
            parent: parent.map(|p| format!("part{p}")),
            joint,
            colliders,
            handles,
        })
}

/// A valid scene description with 1 to `max_parts` parts in a random tree of depth ≤
/// [`MAX_DEPTH`], inserted in shuffled order, and up to 3 base shapes.
pub fn scene_builder(max_parts: usize) -> impl Strategy<Value = SceneModelBuilder> {
    (1..=max_parts)
        .prop_flat_map(tree)
        .prop_flat_map(|parents| {
            parents
                .iter()
                .enumerate()
                .map(|(i, p)| part(i, *p))
                .collect::<Vec<_>>()
        })
        .prop_shuffle()
        .prop_flat_map(|parts| {
            let base = prop::collection::vec((shape(), isometry(2.0)), 0..=3);
            (Just(parts), base)
        })
        .prop_map(|(parts, base)| {
            let mut b = SceneModelBuilder::new();
            for (k, (s, pose)) in base.into_iter().enumerate() {
                b.add_base_shape(BaseShape::new(format!("base{k}"), s, pose));
            }
            for p in parts {
                b.add_part(p);
            }
            b
        })
}

/// A built scene (the generated descriptions are valid by construction).
pub fn scene(max_parts: usize) -> impl Strategy<Value = SceneModel> {
    scene_builder(max_parts).prop_map(|b| b.build().expect("generated scenes are valid"))
}

/// A state of `model` with every value uniform within its limits.
pub fn state(model: &SceneModel) -> impl Strategy<Value = State> + use<> {
    let limits: Vec<Limits> = model.joints().iter().map(|j| j.limits).collect();
    let m = model.clone();
    prop::collection::vec(0.0..=1.0f64, limits.len()).prop_map(move |ts| {
        let q: Vec<f64> = ts
            .iter()
            .zip(&limits)
            .map(|(t, l)| (l.lower + t * (l.upper - l.lower)).clamp(l.lower, l.upper))
            .collect();
        State::from_slice(&m, &q).expect("values within limits")
    })
}

/// A scene with a random state.
pub fn scene_and_state(max_parts: usize) -> impl Strategy<Value = (SceneModel, State)> {
    scene(max_parts).prop_flat_map(|m| {
        let s = state(&m);
        (Just(m), s)
    })
}

/// Sample points of a shape in its own frame: vertices, poles, rims.
pub fn shape_points(shape: &Shape) -> Vec<Point3<f64>> {
    let ring = |r: f64, z: f64| -> Vec<Point3<f64>> {
        (0..12)
            .map(|k| {
                // Half-step offset: between the vertices of polygonal approximations.
                let a = (k as f64 + 0.5) * std::f64::consts::TAU / 12.0;
                Point3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    };
    match shape {
        Shape::Cuboid { half_extents: h } => (0..8)
            .map(|k| {
                let s = |bit: usize| if k & bit == 0 { -1.0 } else { 1.0 };
                Point3::new(s(1) * h.x, s(2) * h.y, s(4) * h.z)
            })
            .collect(),
        Shape::Sphere { radius } => [
            Vector3::x(),
            -Vector3::x(),
            Vector3::y(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
        ]
        .iter()
        .map(|v| Point3::from(v * *radius))
        .collect(),
        Shape::Cylinder { radius, length } => {
            [ring(*radius, -length / 2.0), ring(*radius, length / 2.0)].concat()
        }
        Shape::Capsule { radius, length } => [
            ring(*radius, -length / 2.0),
            ring(*radius, length / 2.0),
            vec![
                Point3::new(0.0, 0.0, -length / 2.0 - radius),
                Point3::new(0.0, 0.0, length / 2.0 + radius),
            ],
        ]
        .concat(),
        Shape::ConvexMesh { vertices, .. } => vertices.clone(),
        _ => Vec::new(),
    }
}

/// Like [`scene_builder`], with what a URDF round trip preserves: handle names end in
/// `_handle` (the URDF handle convention, `kinscene::scene::urdf::HANDLE_SUFFIX`), and some
/// revolute joints are `continuous` with the importer's default working range `[-π, π]`.
pub fn urdf_scene_builder(max_parts: usize) -> impl Strategy<Value = SceneModelBuilder> {
    (
        scene_builder(max_parts),
        prop::collection::vec(any::<bool>(), max_parts),
    )
        .prop_map(|(mut b, continuous)| {
            for (p, c) in b.parts.iter_mut().zip(continuous) {
                for h in &mut p.handles {
                    h.name = format!("{}{}", h.name, kinscene::scene::urdf::HANDLE_SUFFIX);
                }
                if c && p.joint.kind == JointKind::Revolute {
                    p.joint.continuous = true;
                    p.joint.limits = Limits::new(-PI, PI);
                }
            }
            b
        })
}

/// A built scene from [`urdf_scene_builder`].
pub fn urdf_scene(max_parts: usize) -> impl Strategy<Value = SceneModel> {
    urdf_scene_builder(max_parts).prop_map(|b| b.build().expect("generated scenes are valid"))
}
