//! Every kind of bad input gives its typed error, before anything reaches C++.

use kinscene_pinocchio::{
    Data, Error, FrameIndex, Inertia, JointIndex, JointKind, JointLimits, ModelBuilder,
    ReferenceFrame, forward_kinematics, frame_jacobian, frame_placement, integrate,
    joint_placement,
};
use nalgebra::{DVector, Isometry3, Matrix3, Quaternion, Translation3, UnitQuaternion, Vector3};

use crate::support::three_link_arm;

fn revolute_z() -> JointKind {
    JointKind::Revolute { axis: Vector3::z() }
}

fn one_joint() -> (ModelBuilder, JointIndex) {
    let mut b = ModelBuilder::new();
    let j = b
        .add_joint(
            "j",
            JointIndex::UNIVERSE,
            Isometry3::identity(),
            revolute_z(),
            JointLimits::NONE,
        )
        .unwrap();
    (b, j)
}

#[test]
fn bad_joints_are_rejected() {
    let (mut b, j) = one_joint();
    let id = Isometry3::identity();
    let none = JointLimits::NONE;
    let add = |b: &mut ModelBuilder, name: &str, parent, placement, kind, limits| {
        b.add_joint(name, parent, placement, kind, limits)
    };

    assert!(matches!(
        add(&mut b, "j", j, id, revolute_z(), none),
        Err(Error::DuplicateName { what: "joint", .. })
    ));
    assert!(matches!(
        add(&mut b, "universe", j, id, revolute_z(), none),
        Err(Error::DuplicateName { .. })
    ));
    assert!(matches!(
        add(&mut b, "", j, id, revolute_z(), none),
        Err(Error::InvalidName { .. })
    ));
    assert!(matches!(
        add(&mut b, "a\0b", j, id, revolute_z(), none),
        Err(Error::InvalidName { .. })
    ));
    assert!(matches!(
        add(&mut b, "k", JointIndex(7), id, revolute_z(), none),
        Err(Error::JointOutOfRange { index: 7, count: 2 })
    ));
    for axis in [
        Vector3::zeros(),
        Vector3::new(f64::NAN, 0.0, 1.0),
        Vector3::new(0.0, f64::INFINITY, 0.0),
    ] {
        assert!(matches!(
            add(&mut b, "k", j, id, JointKind::Prismatic { axis }, none),
            Err(Error::InvalidAxis { .. })
        ));
    }
    let nan_placement = Isometry3::translation(0.0, f64::NAN, 0.0);
    assert!(matches!(
        add(&mut b, "k", j, nan_placement, revolute_z(), none),
        Err(Error::NonFinite {
            what: "parent_from_joint"
        })
    ));
    let bad_rotation = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::new_unchecked(Quaternion::new(f64::INFINITY, 0.0, 0.0, 0.0)),
    );
    assert!(matches!(
        add(&mut b, "k", j, bad_rotation, revolute_z(), none),
        Err(Error::NonFinite { .. })
    ));

    assert!(matches!(
        add(
            &mut b,
            "k",
            j,
            id,
            revolute_z(),
            JointLimits::position(1.0, -1.0)
        ),
        Err(Error::InvertedLimits {
            lower: 1.0,
            upper: -1.0,
            ..
        })
    ));
    assert!(matches!(
        add(
            &mut b,
            "k",
            j,
            id,
            revolute_z(),
            JointLimits::position(f64::NAN, 1.0)
        ),
        Err(Error::InvertedLimits { .. })
    ));
    assert!(matches!(
        add(
            &mut b,
            "k",
            j,
            id,
            revolute_z(),
            JointLimits::NONE.with_velocity(-1.0)
        ),
        Err(Error::NegativeLimit {
            what: "velocity",
            ..
        })
    ));
    assert!(matches!(
        add(
            &mut b,
            "k",
            j,
            id,
            revolute_z(),
            JointLimits::NONE.with_effort(f64::NAN)
        ),
        Err(Error::NegativeLimit { what: "effort", .. })
    ));
    assert!(matches!(
        add(
            &mut b,
            "k",
            j,
            id,
            JointKind::Planar,
            JointLimits::position(-1.0, 1.0)
        ),
        Err(Error::LimitsNotSupported { .. })
    ));
    // None of the failures above changed the builder.
    assert_eq!(b.njoints(), 2);
    // Equal bounds and infinite bounds are fine.
    add(
        &mut b,
        "k",
        j,
        id,
        revolute_z(),
        JointLimits::position(0.5, 0.5),
    )
    .unwrap();
    add(
        &mut b,
        "l",
        JointIndex(2),
        id,
        revolute_z(),
        JointLimits::position(f64::NEG_INFINITY, 1.0),
    )
    .unwrap();
}

#[test]
fn joints_must_be_added_depth_first() {
    let (mut b, a) = one_joint();
    let id = Isometry3::identity();
    let c = b
        .add_joint(
            "c",
            JointIndex::UNIVERSE,
            id,
            revolute_z(),
            JointLimits::NONE,
        )
        .unwrap();
    // `a`'s branch was left for `c`'s: going back to it would break depth-first order.
    assert!(matches!(
        b.add_joint("d", a, id, revolute_z(), JointLimits::NONE),
        Err(Error::NotDepthFirst { parent: 1, .. })
    ));
    // Children of the last joint and of the universe remain fine.
    b.add_joint("e", c, id, revolute_z(), JointLimits::NONE)
        .unwrap();
    b.add_joint(
        "f",
        JointIndex::UNIVERSE,
        id,
        revolute_z(),
        JointLimits::NONE,
    )
    .unwrap();
}

#[test]
fn bad_bodies_and_frames_are_rejected() {
    let (mut b, j) = one_joint();
    let body = |mass, rotational| Inertia {
        mass,
        com: Vector3::new(0.0, 0.0, 0.1),
        rotational,
    };
    assert!(matches!(
        b.add_body(j, body(-1.0, Matrix3::identity())),
        Err(Error::NegativeMass {
            joint: 1,
            mass: -1.0
        })
    ));
    assert!(matches!(
        b.add_body(j, body(f64::NAN, Matrix3::identity())),
        Err(Error::NonFinite { what: "mass" })
    ));
    let skew = Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert!(matches!(
        b.add_body(j, body(1.0, skew)),
        Err(Error::InvalidInertia {
            reason: "is not symmetric",
            ..
        })
    ));
    assert!(matches!(
        b.add_body(j, body(1.0, -Matrix3::identity())),
        Err(Error::InvalidInertia { .. })
    ));
    assert!(matches!(
        b.add_body(JointIndex(3), body(1.0, Matrix3::identity())),
        Err(Error::JointOutOfRange { .. })
    ));
    b.add_body(
        j,
        body(2.0, Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3))),
    )
    .unwrap();

    let id = Isometry3::identity();
    assert!(matches!(
        b.add_frame("j", j, id),
        Err(Error::DuplicateName { what: "frame", .. })
    ));
    assert!(matches!(
        b.add_frame("f", JointIndex(2), id),
        Err(Error::JointOutOfRange { .. })
    ));
    assert!(matches!(
        b.add_frame("f", j, Isometry3::translation(f64::INFINITY, 0.0, 0.0)),
        Err(Error::NonFinite { .. })
    ));
    b.add_frame("f", j, id).unwrap();
    assert!(matches!(
        b.add_fixed_joint_frame("f", j, id),
        Err(Error::DuplicateName { .. })
    ));
    let model = b.build().unwrap();
    assert_eq!(model.bodies().len(), 1);
}

#[test]
fn bad_calls_are_rejected() {
    let arm = three_link_arm();
    let m = &arm.model;
    let mut data = Data::new(m).unwrap();
    let q = DVector::from_vec(vec![0.1, 0.2, 0.3]);

    // Placements before any forward kinematics.
    assert!(matches!(
        frame_placement(m, &data, arm.tool),
        Err(Error::KinematicsNotComputed)
    ));
    assert!(matches!(
        forward_kinematics(m, &mut data, &DVector::zeros(2)),
        Err(Error::DimensionMismatch {
            what: "q",
            expected: 3,
            got: 2
        })
    ));
    let nan = DVector::from_vec(vec![0.1, f64::NAN, 0.3]);
    assert!(matches!(
        forward_kinematics(m, &mut data, &nan),
        Err(Error::NonFinite { what: "q" })
    ));
    assert!(matches!(
        frame_jacobian(m, &mut data, &nan, arm.tool, ReferenceFrame::World),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        integrate(m, &q, &DVector::from_vec(vec![0.0, f64::INFINITY, 0.0])),
        Err(Error::NonFinite { what: "v" })
    ));
    assert!(matches!(
        integrate(m, &q, &DVector::zeros(4)),
        Err(Error::DimensionMismatch { what: "v", .. })
    ));

    forward_kinematics(m, &mut data, &q).unwrap();
    assert!(matches!(
        frame_placement(m, &data, FrameIndex(99)),
        Err(Error::FrameOutOfRange {
            index: 99,
            count: 5
        })
    ));
    assert!(matches!(
        joint_placement(m, &data, JointIndex(4)),
        Err(Error::JointOutOfRange { index: 4, count: 4 })
    ));
    assert!(matches!(
        frame_jacobian(m, &mut data, &q, FrameIndex(5), ReferenceFrame::Local),
        Err(Error::FrameOutOfRange { .. })
    ));
    assert!(matches!(
        m.joint(JointIndex::UNIVERSE),
        Err(Error::JointOutOfRange { .. })
    ));

    // A Jacobian updates only part of the data: placements must be recomputed.
    frame_jacobian(m, &mut data, &q, arm.tool, ReferenceFrame::Local).unwrap();
    assert!(matches!(
        frame_placement(m, &data, arm.tool),
        Err(Error::KinematicsNotComputed)
    ));

    // Data belongs to the model it was made for, even an identical one.
    let other = three_link_arm();
    assert!(matches!(
        forward_kinematics(&other.model, &mut data, &q),
        Err(Error::DataModelMismatch)
    ));
}
