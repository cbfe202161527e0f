//! Forward kinematics against hand-derived chain products.
//!
//! Tolerance 1e-12 (metres, and unitless for rotation-matrix entries): each pose is a product
//! of fewer than ten rigid transforms with O(1) entries, so double rounding accumulates to a few
//! 1e-16; 1e-12 leaves a wide margin while any modelling error (wrong axis, offset order,
//! frame composition) shows up at the 1e-2 level or above.

use std::f64::consts::PI;

use kinscene_pinocchio::{
    Data, FrameIndex, JointIndex, JointKind, JointLimits, ModelBuilder, forward_kinematics,
    frame_placement, joint_placement,
};
use nalgebra::{DVector, Isometry3, Translation3, UnitQuaternion, Vector3};

use crate::support::{P1, P2, P3, TOOL, iso, pose, pose_error, three_link_arm};

const TOL: f64 = 1e-12;

fn rot(axis: Vector3<f64>, angle: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle),
    )
}

fn slide(axis: Vector3<f64>, d: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(axis.normalize() * d),
        UnitQuaternion::identity(),
    )
}

#[test]
fn three_link_arm_matches_hand_derived_chain() {
    let arm = three_link_arm();
    let mut data = Data::new(&arm.model).unwrap();
    let qs = [
        [0.0, 0.0, 0.0],
        [0.5, -0.3, 0.2],
        [-2.0, 1.2, 0.45],
        [PI, -PI / 2.0, 0.1],
    ];
    for q in qs {
        // world_from_tool = P1 Rz(q1) P2 Ry(q2) P3 Tx(q3) TOOL, written from the joint list.
        let world_from_j1 = iso(P1) * rot(Vector3::z(), q[0]);
        let world_from_j2 = world_from_j1 * iso(P2) * rot(Vector3::y(), q[1]);
        let world_from_j3 = world_from_j2 * iso(P3) * slide(Vector3::x(), q[2]);
        let world_from_tool = world_from_j3 * iso(TOOL);

        forward_kinematics(&arm.model, &mut data, &DVector::from_row_slice(&q)).unwrap();
        let got = frame_placement(&arm.model, &data, arm.tool).unwrap();
        assert!(
            pose_error(&got, &world_from_tool) < TOL,
            "q = {q:?}: {got} vs {world_from_tool}"
        );
        for (j, expected) in [world_from_j1, world_from_j2, world_from_j3]
            .iter()
            .enumerate()
        {
            let joint = JointIndex(j + 1);
            let got = joint_placement(&arm.model, &data, joint).unwrap();
            assert!(pose_error(&got, expected) < TOL, "joint {j} at q = {q:?}");
            // A joint's own frame sits at the joint.
            let frame = arm.model.joint(joint).unwrap().frame;
            let got = frame_placement(&arm.model, &data, frame).unwrap();
            assert!(pose_error(&got, expected) < TOL);
        }
        let universe = joint_placement(&arm.model, &data, JointIndex::UNIVERSE).unwrap();
        assert!(pose_error(&universe, &Isometry3::identity()) == 0.0);
    }
}

#[test]
fn unaligned_axes_match_axis_angle_products() {
    // Revolute about (1, 2, 3) and prismatic along (-1, 0, 2): the builder normalises the axes,
    // the expected chain uses nalgebra's axis-angle rotation and a normalised translation.
    let (ra, pa) = (Vector3::new(1.0, 2.0, 3.0), Vector3::new(-1.0, 0.0, 2.0));
    let mut b = ModelBuilder::new();
    let r = b
        .add_joint(
            "r",
            JointIndex::UNIVERSE,
            pose(0.1, 0.2, 0.3, 0.1, 0.2, 0.3),
            JointKind::Revolute { axis: ra },
            JointLimits::NONE,
        )
        .unwrap();
    let p = b
        .add_joint(
            "p",
            r,
            pose(0.0, 0.4, 0.0, -0.5, 0.0, 0.1),
            JointKind::Prismatic { axis: pa },
            JointLimits::NONE,
        )
        .unwrap();
    let tip = b
        .add_frame("tip", p, pose(0.05, 0.0, 0.0, 0.0, 0.0, 0.0))
        .unwrap();
    let model = b.build().unwrap();
    let mut data = Data::new(&model).unwrap();
    for (qr, qp) in [(0.7, 0.3), (-2.5, -0.8)] {
        let expected = pose(0.1, 0.2, 0.3, 0.1, 0.2, 0.3)
            * rot(ra, qr)
            * pose(0.0, 0.4, 0.0, -0.5, 0.0, 0.1)
            * slide(pa, qp)
            * pose(0.05, 0.0, 0.0, 0.0, 0.0, 0.0);
        forward_kinematics(&model, &mut data, &DVector::from_vec(vec![qr, qp])).unwrap();
        let got = frame_placement(&model, &data, tip).unwrap();
        assert!(pose_error(&got, &expected) < TOL);
    }
}

#[test]
fn planar_joint_places_its_child_in_the_xy_plane() {
    // world_from_tool = Trans(x, y, 0) Rz(θ) TOOL for a planar root joint.
    let mut b = ModelBuilder::new();
    let base = b
        .add_joint(
            "base",
            JointIndex::UNIVERSE,
            Isometry3::identity(),
            JointKind::Planar,
            JointLimits::NONE,
        )
        .unwrap();
    let tool = b.add_frame("tool", base, iso(TOOL)).unwrap();
    let model = b.build().unwrap();
    let mut data = Data::new(&model).unwrap();
    let (x, y, theta): (f64, f64, f64) = (1.5, -0.7, 2.2);
    forward_kinematics(
        &model,
        &mut data,
        &DVector::from_vec(vec![x, y, theta.cos(), theta.sin()]),
    )
    .unwrap();
    let expected = Isometry3::translation(x, y, 0.0) * rot(Vector3::z(), theta) * iso(TOOL);
    assert!(pose_error(&frame_placement(&model, &data, tool).unwrap(), &expected) < TOL);
}

#[test]
fn branches_and_interleaved_frames_keep_builder_indices() {
    // Frames added in between joints on several branches: Pinocchio must number them exactly as
    // the builder did (the build fails otherwise), and each places where its chain says.
    let mut b = ModelBuilder::new();
    let a = b
        .add_joint(
            "a",
            JointIndex::UNIVERSE,
            pose(1.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            JointKind::Revolute { axis: Vector3::z() },
            JointLimits::NONE,
        )
        .unwrap();
    let fa = b
        .add_frame("fa", a, pose(0.0, 0.5, 0.0, 0.0, 0.0, 0.0))
        .unwrap();
    let bj = b
        .add_joint(
            "b",
            a,
            pose(0.0, 0.0, 1.0, 0.0, 0.0, 0.0),
            JointKind::Prismatic { axis: Vector3::z() },
            JointLimits::NONE,
        )
        .unwrap();
    let c = b
        .add_joint(
            "c",
            JointIndex::UNIVERSE,
            pose(-1.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            JointKind::Revolute { axis: Vector3::x() },
            JointLimits::NONE,
        )
        .unwrap();
    let fb = b
        .add_fixed_joint_frame("fb", bj, pose(0.2, 0.0, 0.0, 0.0, 0.0, 0.0))
        .unwrap();
    let fc = b
        .add_frame("fc", c, pose(0.0, 0.3, 0.0, 0.0, 0.0, 0.0))
        .unwrap();
    assert_eq!((fa, fb, fc), (FrameIndex(2), FrameIndex(5), FrameIndex(6)));
    let model = b.build().unwrap();
    assert_eq!(model.frame_index("fb"), Some(fb));
    assert_eq!(model.joint_index("c"), Some(c));
    assert_eq!(model.joint_index("fa"), None);
    assert_eq!(model.joint_index("universe"), Some(JointIndex::UNIVERSE));

    let mut data = Data::new(&model).unwrap();
    let q = [0.4, 0.25, -1.1];
    forward_kinematics(&model, &mut data, &DVector::from_row_slice(&q)).unwrap();
    let world_from_a = pose(1.0, 0.0, 0.0, 0.0, 0.0, 0.0) * rot(Vector3::z(), q[0]);
    let world_from_b =
        world_from_a * pose(0.0, 0.0, 1.0, 0.0, 0.0, 0.0) * slide(Vector3::z(), q[1]);
    let world_from_c = pose(-1.0, 0.0, 0.0, 0.0, 0.0, 0.0) * rot(Vector3::x(), q[2]);
    let cases = [
        (fa, world_from_a * pose(0.0, 0.5, 0.0, 0.0, 0.0, 0.0)),
        (fb, world_from_b * pose(0.2, 0.0, 0.0, 0.0, 0.0, 0.0)),
        (fc, world_from_c * pose(0.0, 0.3, 0.0, 0.0, 0.0, 0.0)),
    ];
    for (frame, expected) in cases {
        assert!(pose_error(&frame_placement(&model, &data, frame).unwrap(), &expected) < TOL);
    }
}

#[test]
fn extending_a_model_keeps_it_and_adds_frames() {
    let arm = three_link_arm();
    let mut b = arm.model.to_builder();
    let extra = b
        .add_frame(
            "extra",
            JointIndex(3),
            Isometry3::translation(0.0, 0.0, 0.1),
        )
        .unwrap();
    let bigger = b.build().unwrap();
    assert_eq!(bigger.frame_index("tool"), Some(arm.tool));
    assert_eq!(extra.0, arm.model.frames().len());
    let mut data = Data::new(&bigger).unwrap();
    let q = DVector::from_vec(vec![0.3, 0.2, 0.1]);
    forward_kinematics(&bigger, &mut data, &q).unwrap();
    let j3 = joint_placement(&bigger, &data, JointIndex(3)).unwrap();
    let got = frame_placement(&bigger, &data, extra).unwrap();
    assert!(pose_error(&got, &(j3 * Isometry3::translation(0.0, 0.0, 0.1))) < TOL);
}

#[test]
fn limits_and_sizes_are_reported() {
    let arm = three_link_arm();
    let m = &arm.model;
    assert_eq!(
        (m.nq(), m.nv(), m.njoints(), m.frames().len()),
        (3, 3, 4, 5)
    );
    let (lower, upper) = m.position_bounds();
    assert_eq!(lower.as_slice(), &[-3.0, f64::NEG_INFINITY, 0.0]);
    assert_eq!(upper.as_slice(), &[3.0, f64::INFINITY, 0.5]);
    assert!(m.velocity_limits().iter().all(|v| v.is_infinite()));
    assert_eq!(m.joint_name(JointIndex(2)), Some("j2"));
    assert_eq!(m.joint_name(JointIndex(9)), None);
    assert_eq!(kinscene_pinocchio::pinocchio_version().unwrap(), "4.1.0");
}

#[cfg(feature = "bench")]
#[test]
fn cpp_benchmark_loop_runs() {
    let arm = three_link_arm();
    let mut data = Data::new(&arm.model).unwrap();
    let q = DVector::from_vec(vec![0.3, 0.2, 0.1]);
    let elapsed = kinscene_pinocchio::bench::cpp_forward_kinematics_loop(
        &arm.model, &mut data, &q, arm.tool, 100,
    )
    .unwrap();
    assert!(elapsed.as_nanos() > 0);
    // The loop leaves placements unspecified: reading them needs a new forward_kinematics.
    assert!(frame_placement(&arm.model, &data, arm.tool).is_err());
}
