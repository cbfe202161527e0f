//! Property tests on generated scene graphs (strategies in `generators.rs`).

use kinscene::scene::motion::{grasp_trajectory, motion_bound};
use kinscene::scene::{
    Error, JointKind, Parent, PartId, SceneData, SceneModel, forward_kinematics, joint_axis,
    world_from_handle,
};
use nalgebra::{Matrix3, Matrix4, Point3, Vector3};
use proptest::prelude::*;

use super::generators::{scene_and_state, scene_builder, shape_points};

/// Independent joint motion as a homogeneous matrix: Rodrigues' formula written out for a
/// revolute joint, a translation for a prismatic one.
fn motion_matrix(kind: JointKind, axis: &Vector3<f64>, value: f64) -> Matrix4<f64> {
    let u = axis.normalize();
    let mut m = Matrix4::identity();
    match kind {
        JointKind::Revolute => {
            let k = Matrix3::new(0.0, -u.z, u.y, u.z, 0.0, -u.x, -u.y, u.x, 0.0);
            let r = Matrix3::identity() + k * value.sin() + k * k * (1.0 - value.cos());
            m.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        }
        JointKind::Prismatic => m.fixed_view_mut::<3, 1>(0, 3).copy_from(&(u * value)),
    }
    m
}

/// World positions of all sample points and handle points of `root`'s subtree.
fn subtree_points(model: &SceneModel, data: &SceneData, root: PartId) -> Vec<Point3<f64>> {
    let part = model.part(root).unwrap();
    let mut out = Vec::new();
    for id in part.subtree() {
        let p = model.part(id).unwrap();
        let pose = data.world_from_part(id).unwrap();
        for c in p.colliders() {
            out.extend(
                shape_points(&c.shape)
                    .iter()
                    .map(|x| pose * (c.part_from_shape * x)),
            );
        }
        out.extend(p.handles().iter().map(|h| pose * h.position));
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// world_from_part(child) = world_from_part(parent) · parent_from_joint · motion(θ).
    #[test]
    fn forward_kinematics_composes_along_the_tree((model, state) in scene_and_state(50)) {
        let mut data = SceneData::new(&model);
        forward_kinematics(&model, &mut data, &state).unwrap();
        for part in model.parts() {
            let joint = &model.joints()[part.joint().index()];
            let parent = match part.parent() {
                Parent::Base => Matrix4::identity(),
                Parent::Part(p) => data.world_from_part(p).unwrap().to_homogeneous(),
            };
            let value = state.value(part.joint()).unwrap();
            let want = parent * joint.parent_from_joint.to_homogeneous() * motion_matrix(joint.kind, &joint.axis, value);
            let got = data.world_from_part(part.id()).unwrap().to_homogeneous();
            // Depth ≤ 4, translations ≤ ~3 m: accumulated rounding stays below 1e-12.
            prop_assert!((got - want).abs().max() < 1e-9, "part {}: {got} vs {want}", part.name());
        }
    }

    /// Every sampled point of the moving subtree travels at most L·|Δθ| and stays within the
    /// sweep radius of the axis.
    #[test]
    fn sweep_bound_holds_for_sampled_points(
        (model, state) in scene_and_state(50),
        pick in any::<prop::sample::Index>(),
        ta in 0.0..=1.0f64,
        tb in 0.0..=1.0f64,
    ) {
        let joint = model.joints().len();
        let id = model.parts()[pick.index(joint)].joint();
        let limits = model.joints()[id.index()].limits;
        let (a, b) = (limits.lower + ta * (limits.upper - limits.lower), limits.lower + tb * (limits.upper - limits.lower));
        let mut data = SceneData::new(&model);
        let mut s = state.clone();
        s.set(&model, id, a).unwrap();
        forward_kinematics(&model, &mut data, &s).unwrap();
        let bound = motion_bound(&model, &data, id).unwrap();
        let axis = joint_axis(&model, &data, id).unwrap();
        let start = subtree_points(&model, &data, id.part());
        for k in 1..=24 {
            let t = a + (b - a) * k as f64 / 24.0;
            s.set(&model, id, t.clamp(limits.lower, limits.upper)).unwrap();
            forward_kinematics(&model, &mut data, &s).unwrap();
            let now = subtree_points(&model, &data, id.part());
            let allowed = bound.max_displacement(t - a);
            for (p, q) in start.iter().zip(&now) {
                // Rounding of poses with coordinates of a few metres: 1e-9 m slack.
                prop_assert!((q - p).norm() <= allowed + 1e-9, "moved {} > bound {allowed}", (q - p).norm());
                if bound.kind == JointKind::Revolute {
                    prop_assert!(axis.distance_to_axis(q) <= bound.radius + 1e-9);
                }
            }
        }
    }

    /// The first and last grasp-trajectory poses are the forward kinematics of the handle at a
    /// and b, for any handle and any joint it moves with.
    #[test]
    fn trajectory_endpoints_match_forward_kinematics(
        (model, state) in scene_and_state(30),
        pick in any::<prop::sample::Index>(),
        up in any::<prop::sample::Index>(),
        ta in 0.0..=1.0f64,
        tb in 0.0..=1.0f64,
    ) {
        let handles: Vec<_> = model.handles().map(|(id, _)| id).collect();
        prop_assume!(!handles.is_empty());
        let handle = handles[pick.index(handles.len())];
        // Ancestors of the handle's part (itself included).
        let mut chain = vec![handle.part()];
        while let Parent::Part(p) = model.part(*chain.last().unwrap()).unwrap().parent() {
            chain.push(p);
        }
        let joint = chain[up.index(chain.len())].joint();
        let l = model.joints()[joint.index()].limits;
        let (a, b) = (l.lower + ta * (l.upper - l.lower), l.lower + tb * (l.upper - l.lower));
        let mut data = SceneData::new(&model);
        let traj = grasp_trajectory(&model, &mut data, &state, handle, joint, a, b, 7).unwrap();
        for (value, pose) in [(a, traj[0]), (b, traj[7])] {
            let mut s = state.clone();
            s.set(&model, joint, value).unwrap();
            forward_kinematics(&model, &mut data, &s).unwrap();
            let fk = world_from_handle(&model, &data, handle).unwrap();
            prop_assert!((fk.position - pose.position).norm() < 1e-9);
            prop_assert!((fk.normal.into_inner() - pose.normal.into_inner()).norm() < 1e-9);
        }
    }
}

/// A corruption applied to a valid description.
#[derive(Debug, Clone, Copy)]
enum Corruption {
    NanAxis,
    ZeroAxis,
    SwappedLimits,
    UnknownParent,
    DuplicatePart,
    DuplicateJoint,
    Cycle,
}

fn corruption() -> impl Strategy<Value = Corruption> {
    prop_oneof![
        Just(Corruption::NanAxis),
        Just(Corruption::ZeroAxis),
        Just(Corruption::SwappedLimits),
        Just(Corruption::UnknownParent),
        Just(Corruption::DuplicatePart),
        Just(Corruption::DuplicateJoint),
        Just(Corruption::Cycle),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Each corruption of a valid description is rejected with the matching typed error.
    #[test]
    fn validation_rejects_corrupted_variants(
        builder in scene_builder(12),
        what in corruption(),
        i in any::<prop::sample::Index>(),
        j in any::<prop::sample::Index>(),
    ) {
        prop_assert!(builder.build().is_ok());
        let mut b = builder.clone();
        let n = b.parts.len();
        let (i, j) = (i.index(n), j.index(n));
        let name = b.parts[i].name.clone();
        let joint = b.parts[i].joint.name.clone();
        let err = match what {
            Corruption::NanAxis => { b.parts[i].joint.axis.y = f64::NAN; b.build().unwrap_err() }
            Corruption::ZeroAxis => { b.parts[i].joint.axis = Vector3::zeros(); b.build().unwrap_err() }
            Corruption::SwappedLimits => {
                let l = &mut b.parts[i].joint.limits;
                l.lower = l.upper + 0.5;
                b.build().unwrap_err()
            }
            Corruption::UnknownParent => { b.parts[i].parent = Some("nowhere".into()); b.build().unwrap_err() }
            Corruption::DuplicatePart => {
                prop_assume!(i != j);
                b.parts[j].name = name.clone();
                b.build().unwrap_err()
            }
            Corruption::DuplicateJoint => {
                prop_assume!(i != j);
                b.parts[j].joint.name = joint.clone();
                b.build().unwrap_err()
            }
            Corruption::Cycle => {
                // Re-parent part i onto itself or one of its descendants.
                let mut below = vec![name.clone()];
                let mut k = 0;
                while k < below.len() {
                    let cur = below[k].clone();
                    below.extend(b.parts.iter().filter(|p| p.parent.as_deref() == Some(cur.as_str())).map(|p| p.name.clone()));
                    k += 1;
                }
                b.parts[i].parent = Some(below[j % below.len()].clone());
                b.build().unwrap_err()
            }
        };
        let ok = match (what, &err) {
            (Corruption::NanAxis, Error::NonFinite { what }) => what.contains(&format!("{joint:?}")),
            (Corruption::ZeroAxis, Error::ZeroAxis { joint: j }) => *j == joint,
            (Corruption::SwappedLimits, Error::InvalidLimits { joint: j, lower, upper }) => *j == joint && lower > upper,
            (Corruption::UnknownParent, Error::UnknownParent { part, parent }) => *part == name && parent == "nowhere",
            (Corruption::DuplicatePart, Error::DuplicateName { name: d, .. }) => *d == name,
            (Corruption::DuplicateJoint, Error::DuplicateName { name: d, .. }) => *d == joint,
            (Corruption::Cycle, Error::Cycle { parts }) => {
                // The reported parts form a cycle in the corrupted description.
                let parent_of = |p: &str| b.parts.iter().find(|s| s.name == p).and_then(|s| s.parent.clone());
                parts.contains(&name)
                    && (0..parts.len()).all(|k| parent_of(&parts[k]).as_deref() == Some(parts[(k + 1) % parts.len()].as_str()))
            }
            _ => false,
        };
        prop_assert!(ok, "{what:?} gave {err:?}");
    }
}
