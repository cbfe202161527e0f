//! The robot model: URDF loading, pure-Rust FK against Pinocchio, the shipped Gen3 mobile
//! manipulator, typed errors for bad URDFs, and robot collision checking.

use std::f64::consts::{FRAC_PI_2, PI};

use kinscene::kinematics::pinocchio::{
    Data, JointIndex, forward_kinematics, frame_placement, joint_placement,
};
use kinscene::kinematics::robot::{
    ArmJointKind, Exempt, MobileBase, RobotCollision, RobotConfig, RobotError, RobotImportOptions,
    RobotModel, TOOL_FRAME,
};
use kinscene::scene::collision::Body;
use kinscene::scene::{
    BaseShape, Joint, JointKind, Limits, PartSpec, SceneData, SceneModel, SceneModelBuilder, Shape,
    State, forward_kinematics as scene_fk,
};
use nalgebra::{DVector, Isometry3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Translation distance (m) and rotation angle (rad) between two poses.
fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

/// A random arm configuration: uniform within the limits, continuous joints in [-2π, 2π].
fn random_arm(robot: &RobotModel, rng: &mut ChaCha8Rng) -> DVector<f64> {
    let (lower, upper) = robot.arm_bounds();
    DVector::from_fn(robot.dof(), |i, _| {
        rng.random_range(lower[i].max(-2.0 * PI)..=upper[i].min(2.0 * PI))
    })
}

// ---------------------------------------------------------------------------------------------
// Forward kinematics
// ---------------------------------------------------------------------------------------------

/// Pure-Rust FK (nalgebra, joint by joint) and Pinocchio's FK of the model built from the
/// parsed robot are independent implementations; they must agree on every link frame and the
/// tool frame. Tolerance 1e-12 m / rad: both compose 7–9 rigid transforms of O(1 m) in f64,
/// whose rounding error is ~1e-15 per operation.
#[test]
fn pure_rust_fk_matches_pinocchio_on_the_gen3() {
    let robot = RobotModel::kinova_gen3_mobile();
    let model = robot.pinocchio();
    assert_eq!((model.nq(), model.nv()), (robot.dof(), robot.dof()));
    let mut data = Data::new(model).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut worst: f64 = 0.0;
    for _ in 0..300 {
        let q = random_arm(&robot, &mut rng);
        let base = [
            rng.random_range(-5.0..5.0),
            rng.random_range(-5.0..5.0),
            rng.random_range(-PI..PI),
        ];
        forward_kinematics(model, &mut data, &q).unwrap();
        let world_from_base = RobotModel::world_from_base(base);
        let poses = robot
            .link_poses(&RobotConfig {
                base,
                arm: q.clone(),
            })
            .unwrap();
        assert_eq!(poses.len(), robot.dof() + 1);
        let (t, r) = pose_error(&poses[0], &world_from_base);
        assert!(t < 1e-12 && r < 1e-12);
        // Pinocchio joint i + 1 is arm joint i; its frame is link i + 1's frame.
        for i in 0..robot.dof() {
            let pin = world_from_base * joint_placement(model, &data, JointIndex(i + 1)).unwrap();
            let (t, r) = pose_error(&poses[i + 1], &pin);
            worst = worst.max(t).max(r);
            assert!(t < 1e-12 && r < 1e-12, "link {}: {t} m, {r} rad", i + 1);
        }
        let pin_tool = frame_placement(model, &data, robot.tool_frame()).unwrap();
        let (t, r) = pose_error(&robot.base_from_tool(&q).unwrap(), &pin_tool);
        assert!(t < 1e-12 && r < 1e-12, "tool: {t} m, {r} rad");
        let world_tool = robot
            .world_from_tool(&RobotConfig { base, arm: q })
            .unwrap();
        let (t, r) = pose_error(&world_tool, &(world_from_base * pin_tool));
        assert!(t < 1e-12 && r < 1e-12, "world tool: {t} m, {r} rad");
    }
    assert!(worst < 1e-12);
}

/// A two-joint toy arm, FK derived by hand.
///
/// Base → fixed mount at (0, 0, 0.5) → joint `j1` revolute about z at (0, 0, 0.1) → joint `j2`
/// revolute about y at (0.3, 0, 0) → tool 0.2 along x. In the base frame the tool is at
/// `(0, 0, 0.6) + Rz(q1)·[(0.3, 0, 0) + Ry(q2)·(0.2, 0, 0)]` with `Ry(q2)·(0.2, 0, 0) =
/// (0.2 cos q2, 0, -0.2 sin q2)`. At q = (π/2, π/2): (0.3, 0, -0.2) turned by Rz(π/2) is
/// (0, 0.3, -0.2), so the tool is at (0, 0.3, 0.4); its z axis is Rz(π/2)·Ry(π/2)·z =
/// Rz(π/2)·x = y. With the base at (1, 2, π/2): (1, 2, 0) + Rz(π/2)·(0, 0.3, 0.4) =
/// (0.7, 2, 0.4), z axis Rz(π/2)·y = -x.
#[test]
fn toy_arm_fk_matches_the_hand_derivation() {
    let robot = RobotModel::from_urdf_str(TOY).unwrap();
    assert_eq!(robot.dof(), 2);
    assert_eq!(robot.name(), "toy");
    assert!(
        (robot.base_from_arm_root().translation.vector - Vector3::new(0.0, 0.0, 0.5)).norm()
            < 1e-15
    );
    let q = DVector::from_vec(vec![FRAC_PI_2, FRAC_PI_2]);
    let base_from_tool = robot.base_from_tool(&q).unwrap();
    assert!((base_from_tool.translation.vector - Vector3::new(0.0, 0.3, 0.4)).norm() < 1e-12);
    assert!((base_from_tool.rotation * Vector3::z() - Vector3::y()).norm() < 1e-12);
    let world = robot
        .world_from_tool(&RobotConfig {
            base: [1.0, 2.0, FRAC_PI_2],
            arm: q,
        })
        .unwrap();
    assert!((world.translation.vector - Vector3::new(0.7, 2.0, 0.4)).norm() < 1e-12);
    assert!((world.rotation * Vector3::z() + Vector3::x()).norm() < 1e-12);
    // At q = 0 the tool is at (0.3 + 0.2, 0, 0.6) by the same formula.
    let zero = robot.base_from_tool(&DVector::zeros(2)).unwrap();
    assert!((zero.translation.vector - Vector3::new(0.5, 0.0, 0.6)).norm() < 1e-12);
}

const TOY: &str = r#"<robot name="toy">
  <link name="base"><collision><origin xyz="0 0 0.25"/><geometry><box size="0.4 0.4 0.5"/></geometry></collision></link>
  <link name="mount"/>
  <joint name="mount_joint" type="fixed"><origin xyz="0 0 0.5"/><parent link="base"/><child link="mount"/></joint>
  <link name="l1"><collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/><geometry><capsule radius="0.03" length="0.3"/></geometry></collision></link>
  <joint name="j1" type="revolute"><origin xyz="0 0 0.1"/><parent link="mount"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1"/></joint>
  <link name="l2"><collision><origin xyz="0.1 0 0"/><geometry><sphere radius="0.03"/></geometry></collision></link>
  <joint name="j2" type="revolute"><origin xyz="0.3 0 0"/><parent link="l1"/><child link="l2"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" velocity="1.5"/></joint>
  <link name="tool_frame"/>
  <joint name="tool_joint" type="fixed"><origin xyz="0.2 0 0"/><parent link="l2"/><child link="tool_frame"/></joint>
</robot>"#;

#[test]
fn configurations_are_validated() {
    let robot = RobotModel::from_urdf_str(TOY).unwrap();
    let short = RobotConfig {
        base: [0.0; 3],
        arm: DVector::zeros(3),
    };
    assert!(matches!(
        robot.link_poses(&short),
        Err(RobotError::DimensionMismatch {
            expected: 2,
            got: 3,
            ..
        })
    ));
    let nan = RobotConfig {
        base: [0.0; 3],
        arm: DVector::from_vec(vec![0.0, f64::NAN]),
    };
    assert!(matches!(
        robot.world_from_tool(&nan),
        Err(RobotError::NonFiniteValue {
            what: "arm",
            index: 1
        })
    ));
    let bad_base = RobotConfig {
        base: [0.0, f64::INFINITY, 0.0],
        arm: DVector::zeros(2),
    };
    assert!(matches!(
        robot.link_poses(&bad_base),
        Err(RobotError::NonFiniteValue {
            what: "base",
            index: 1
        })
    ));
    assert!(matches!(
        robot
            .clone()
            .with_neutral(&DVector::from_vec(vec![0.0, 2.5])),
        Err(RobotError::OutOfLimits { upper: 2.0, .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// The shipped robot
// ---------------------------------------------------------------------------------------------

/// Every expected number below is transcribed from GEN3_URDF_V12.urdf in the PyPI package
/// rtb-data 1.1.0 (rtbdata/xacro/kortex_description/arms/gen3/7dof/urdf/), independently of
/// robots/kinova_gen3_mobile.urdf, unless stated otherwise.
#[test]
fn shipped_robot_matches_the_transcribed_numbers() {
    let robot = RobotModel::kinova_gen3_mobile();
    assert_eq!(robot.name(), "kinova_gen3_mobile");
    assert_eq!(robot.dof(), 7);
    assert_eq!(robot.links().len(), 8);
    let names: Vec<&str> = robot.arm_joints().iter().map(|j| j.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "Actuator1",
            "Actuator2",
            "Actuator3",
            "Actuator4",
            "Actuator5",
            "Actuator6",
            "Actuator7"
        ]
    );
    // Joints 1, 3, 5, 7 are `continuous`; 2, 4, 6 `revolute` with limits ±2.41, ±2.66, ±2.23.
    let revolute = [(1, 2.41), (3, 2.66), (5, 2.23)];
    for (i, joint) in robot.arm_joints().iter().enumerate() {
        // <axis xyz="0 0 1"/> and <limit velocity="0.8727"/> for every actuator.
        assert_eq!(joint.axis.into_inner(), Vector3::z());
        assert_eq!(joint.max_velocity, 0.8727);
        match revolute.iter().find(|(k, _)| *k == i) {
            Some(&(_, limit)) => {
                assert_eq!(joint.kind, ArmJointKind::Revolute);
                assert_eq!((joint.lower, joint.upper), (-limit, limit));
            }
            None => {
                assert_eq!(joint.kind, ArmJointKind::Continuous);
                assert_eq!(
                    (joint.lower, joint.upper),
                    (f64::NEG_INFINITY, f64::INFINITY)
                );
            }
        }
        // The module docs' default for revolute joints (URDF 1.0 has no acceleration limit).
        assert_eq!(joint.max_acceleration, 2.0);
    }
    // Joint origins (xyz) of Actuator1..7 in GEN3_URDF_V12.urdf.
    let xyz = [
        [0.0, 0.0, 0.15643],
        [0.0, 0.005375, -0.12838],
        [0.0, -0.21038, -0.006375],
        [0.0, 0.006375, -0.21038],
        [0.0, -0.20843, -0.006375],
        [0.0, 0.00017505, -0.10593],
        [0.0, -0.10593, -0.00017505],
    ];
    // Their rpy roll angles (pitch and yaw are below 1e-15 there): 3.1416, then ±1.5708.
    // (Deliberately the file's rounded values, not π and π/2.)
    #[allow(clippy::approx_constant)]
    let roll = [3.1416, 1.5708, -1.5708, 1.5708, -1.5708, 1.5708, -1.5708];
    for (i, joint) in robot.arm_joints().iter().enumerate() {
        assert_eq!(
            joint.parent_from_joint.translation.vector,
            Vector3::from(xyz[i])
        );
        let expected = UnitQuaternion::from_euler_angles(roll[i], 0.0, 0.0);
        assert!(joint.parent_from_joint.rotation.angle_to(&expected) < 1e-14);
    }
    // The mount (this project's choice, URDF header): the arm base 0.12 m forward, on the
    // chassis top at 0.40 m.
    assert_eq!(
        robot.base_from_arm_root().translation.vector,
        Vector3::new(0.12, 0.0, 0.40)
    );
    // Tool: the EndEffector fixed joint (0, 0, -0.061525) rpy (π, 0, 0) from the bracelet,
    // then kortex_description's 2F-140 tool_frame 0.20 m along the flange z: in the bracelet
    // frame (0, 0, -0.061525) + Rx(π)·(0, 0, 0.20) = (0, 0, -0.261525), tool z = -z.
    let tool = robot.last_from_tool();
    assert!((tool.translation.vector - Vector3::new(0.0, 0.0, -0.261525)).norm() < 1e-12);
    assert!((tool.rotation * Vector3::z() + Vector3::z()).norm() < 1e-12);
    // Pinocchio model: the tool frame is named "tool"; continuous joints are unbounded.
    let model = robot.pinocchio();
    assert_eq!(model.frame_index(TOOL_FRAME), Some(robot.tool_frame()));
    let (lower, upper) = model.position_bounds();
    assert_eq!((lower[1], upper[1]), (-2.41, 2.41));
    assert_eq!((lower[0], upper[0]), (f64::NEG_INFINITY, f64::INFINITY));
    assert!(model.velocity_limits().iter().all(|&v| v == 0.8727));
    // Base: the module docs' defaults; footprint at least the chassis corner radius
    // hypot(0.22, 0.18) = 0.2843 m, and the stowed arm inside 0.30 m (the task layer's default).
    let base = robot.base();
    assert_eq!(base.max_velocity, [0.5, 0.5, 1.0]);
    assert_eq!(base.max_acceleration, [0.5, 0.5, 1.0]);
    assert!(base.footprint_radius >= 0.22f64.hypot(0.18) - 1e-12);
    assert!(base.footprint_radius <= 0.30, "{}", base.footprint_radius);
    // Neutral lies within the limits.
    let (lo, hi) = robot.arm_bounds();
    let neutral = robot.neutral();
    assert!((0..7).all(|i| lo[i] <= neutral[i] && neutral[i] <= hi[i]));
}

#[test]
fn setters_validate_their_input() {
    let robot = RobotModel::kinova_gen3_mobile();
    let faster = robot
        .clone()
        .with_acceleration_limits(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0])
        .unwrap();
    assert_eq!(faster.arm_joints()[6].max_acceleration, 7.0);
    assert!(matches!(
        robot.clone().with_acceleration_limits(&[1.0; 6]),
        Err(RobotError::DimensionMismatch {
            expected: 7,
            got: 6,
            ..
        })
    ));
    assert!(matches!(
        robot
            .clone()
            .with_acceleration_limits(&[1.0, 1.0, -1.0, 1.0, 1.0, 1.0, 1.0]),
        Err(RobotError::NonPositiveLimit {
            what: "acceleration",
            ..
        })
    ));
    let base = MobileBase {
        max_velocity: [1.0, 0.2, 0.5],
        ..robot.base().clone()
    };
    assert_eq!(robot.clone().with_base(base.clone()).unwrap().base(), &base);
    let bad = MobileBase {
        footprint_radius: f64::NAN,
        ..base
    };
    let err = robot.with_base(bad).unwrap_err();
    assert!(
        matches!(&err, RobotError::InvalidSetting(s) if s.field == "footprint_radius"),
        "{err}"
    );
    // One sentence, the requirement after the layer's prefix.
    assert_eq!(
        err.to_string(),
        "robot setting footprint_radius = NaN: must be finite and > 0"
    );
}

// ---------------------------------------------------------------------------------------------
// URDF conventions and bad input
// ---------------------------------------------------------------------------------------------

/// A robot with a `world` root, a planar joint to the base, a gripper finger joint off the arm
/// chain (with velocity limit 0, which a frozen joint may have) and a tool link `tcp`.
const WORLD_ROOTED: &str = r#"<robot name="w">
  <link name="world"/>
  <link name="base"/>
  <joint name="base_motion" type="planar"><parent link="world"/><child link="base"/></joint>
  <link name="l1"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/><axis xyz="0 0 2"/><limit velocity="1"/></joint>
  <link name="finger"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.01 0.01 0.05"/></geometry></collision></link>
  <joint name="finger_joint" type="prismatic"><origin xyz="0 0 0.2"/><parent link="l1"/><child link="finger"/><axis xyz="0 1 0"/><limit lower="0.01" upper="0.05" velocity="0"/></joint>
  <link name="tcp"/>
  <joint name="tcp_joint" type="fixed"><origin xyz="0.1 0 0"/><parent link="l1"/><child link="tcp"/></joint>
</robot>"#;

#[test]
fn planar_root_and_gripper_joints_are_handled() {
    let options = RobotImportOptions {
        tool_link: "tcp".into(),
        ..RobotImportOptions::default()
    };
    let robot = RobotModel::from_urdf_str_with(WORLD_ROOTED, &options).unwrap();
    assert_eq!(robot.dof(), 1);
    assert_eq!(robot.links()[0].name, "base");
    assert_eq!(robot.arm_joints()[0].kind, ArmJointKind::Continuous);
    // The axis (0, 0, 2) is normalised.
    assert_eq!(robot.arm_joints()[0].axis.into_inner(), Vector3::z());
    // The finger is frozen at 0 clamped into [0.01, 0.05], i.e. 0.01 along y, and merged into
    // l1: its box sits at (0, 0.01, 0.2 + 0.1) in l1.
    let finger = &robot.links()[1].colliders[0];
    assert!(
        (finger.part_from_shape.translation.vector - Vector3::new(0.0, 0.01, 0.3)).norm() < 1e-15
    );
    assert_eq!(
        robot.last_from_tool().translation.vector,
        Vector3::new(0.1, 0.0, 0.0)
    );
    // Without the option, `tool_frame` is missing.
    assert!(matches!(
        RobotModel::from_urdf_str(WORLD_ROOTED),
        Err(RobotError::MissingToolLink { link }) if link == "tool_frame"
    ));
}

/// The toy robot with a head on the base: `head_pan` (about z, limits [0.5, 1.5] rad) 1 m above
/// the base origin, and a 5 cm ball 0.1 m out along the head's x axis.
fn toy_with_head() -> String {
    TOY.replace(
        "</robot>",
        r#"<link name="head"><collision><origin xyz="0.1 0 0"/><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="head_pan" type="revolute"><origin xyz="0 0 1"/><parent link="base"/><child link="head"/><axis xyz="0 0 1"/><limit lower="0.5" upper="1.5" velocity="1"/></joint>
</robot>"#,
    )
}

/// A movable branch off the arm (a head) is frozen and its geometry stays, at the value
/// given or at 0 clamped into the limits (0.5 here): the ball's centre in the base frame is
/// (0.1 cos v, 0.1 sin v, 1) by hand. An arm root cuts the arm: with `l1` as the root, `j1` is
/// frozen (at 0) and the arm is `j2` alone, rooted 0.6 m above the base (mount 0.5 + j1's
/// 0.1). Bad names and values are typed errors naming them.
#[test]
fn branches_off_the_arm_are_frozen_with_their_geometry() {
    let text = toy_with_head();
    let ball = |robot: &RobotModel| {
        let c = robot.links()[0]
            .colliders
            .iter()
            .find(|c| matches!(c.shape, kinscene::scene::Shape::Sphere { .. }))
            .expect("the head's ball is on the base link");
        c.part_from_shape.translation.vector
    };
    let robot = RobotModel::from_urdf_str(&text).unwrap();
    assert_eq!(robot.dof(), 2);
    assert_eq!(robot.frozen_joints().len(), 1);
    assert_eq!(robot.frozen_joints()[0].name, "head_pan");
    assert_eq!(robot.frozen_joints()[0].value, 0.5);
    let expected = Vector3::new(0.1 * 0.5f64.cos(), 0.1 * 0.5f64.sin(), 1.0);
    assert!((ball(&robot) - expected).norm() < 1e-12, "{}", ball(&robot));
    let with = |frozen: &[(&str, f64)], arm_root: Option<&str>| {
        RobotModel::from_urdf_str_with(
            &text,
            &RobotImportOptions {
                frozen: frozen.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
                arm_root: arm_root.map(str::to_string),
                ..RobotImportOptions::default()
            },
        )
    };
    let turned = with(&[("head_pan", 1.0)], None).unwrap();
    let expected = Vector3::new(0.1 * 1.0f64.cos(), 0.1 * 1.0f64.sin(), 1.0);
    assert!((ball(&turned) - expected).norm() < 1e-12);
    for (frozen, named) in [
        (("head_pan", 2.0), "head_pan"),
        (("head_pan", f64::NAN), "head_pan"),
        (("j1", 0.0), "j1"),
        (("no_such_joint", 0.0), "no_such_joint"),
    ] {
        let e = with(&[frozen], None).unwrap_err();
        assert!(
            matches!(&e, RobotError::InvalidFrozen { joint, .. } if joint == named),
            "{e}"
        );
    }
    let cut = with(&[], Some("l1")).unwrap();
    assert_eq!(cut.dof(), 1);
    assert_eq!(cut.arm_joints()[0].name, "j2");
    let names: Vec<&str> = cut
        .frozen_joints()
        .iter()
        .map(|f| f.name.as_str())
        .collect();
    assert_eq!(names, ["j1", "head_pan"]);
    assert!(
        (cut.base_from_arm_root().translation.vector - Vector3::new(0.0, 0.0, 0.6)).norm() < 1e-12
    );
    // j1 at 0 rad: the tool 0.3 (l1) + 0.2 m out along x at the root's height, j2 at 0.
    let tool = cut
        .world_from_tool(&RobotConfig {
            base: [0.0; 3],
            arm: DVector::zeros(1),
        })
        .unwrap();
    assert!((tool.translation.vector - Vector3::new(0.5, 0.0, 0.6)).norm() < 1e-12);
    for root in ["no_such_link", "head"] {
        let e = with(&[], Some(root)).unwrap_err();
        assert!(
            matches!(&e, RobotError::InvalidArmRoot { link, .. } if link == root),
            "{e}"
        );
    }
    assert!(matches!(
        with(&[], Some("l2")).unwrap_err(),
        RobotError::NoMovableJoint { .. }
    ));
}

/// The toy URDF with `from` replaced by `to` (which must occur).
fn toy_with(from: &str, to: &str) -> String {
    assert!(TOY.contains(from), "{from}");
    TOY.replacen(from, to, 1)
}

#[test]
fn bad_urdfs_give_typed_errors() {
    let load = |text: &str| RobotModel::from_urdf_str(text).unwrap_err();
    assert!(matches!(
        load("<robot name=\"x\"><link"),
        RobotError::Xml { .. }
    ));
    assert!(matches!(
        load(&"<a>".repeat(10_000)),
        RobotError::Xml { .. }
    ));
    // Every joint fixed: no arm.
    assert!(matches!(
        load(&toy_with(r#"name="j1" type="revolute""#, r#"name="j1" type="fixed""#)
            .replacen(r#"name="j2" type="revolute""#, r#"name="j2" type="fixed""#, 1)),
        RobotError::NoMovableJoint { base } if base == "base"
    ));
    assert!(matches!(
        load(&toy_with(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 0 0"/>"#)),
        RobotError::InvalidAxis { joint, .. } if joint == "j2"
    ));
    assert!(matches!(
        load(&toy_with(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 NaN 0"/>"#)),
        RobotError::InvalidAxis { joint, .. } if joint == "j2"
    ));
    assert!(matches!(
        load(&toy_with(r#"lower="-2" upper="2""#, r#"lower="2" upper="-2""#)),
        RobotError::InvalidLimits { joint, lower, upper } if joint == "j2" && lower == 2.0 && upper == -2.0
    ));
    assert!(matches!(
        load(&toy_with(r#"<origin xyz="0.3 0 0"/>"#, r#"<origin xyz="0.3 NaN 0"/>"#)),
        RobotError::NonFinite { what } if what.contains("j2")
    ));
    assert!(matches!(
        load(&toy_with(r#"<origin xyz="0.2 0 0"/>"#, r#"<origin xyz="0.2 0 0" rpy="inf 0 0"/>"#)),
        RobotError::NonFinite { what } if what.contains("tool_joint")
    ));
    assert!(matches!(
        load(&toy_with(r#"<link name="tool_frame"/>"#, r#"<link name="tool"/>"#)
            .replacen(r#"<child link="tool_frame"/>"#, r#"<child link="tool"/>"#, 1)),
        RobotError::MissingToolLink { link } if link == "tool_frame"
    ));
    assert!(matches!(
        load(&toy_with(r#"name="j2" type="revolute""#, r#"name="j2" type="spherical""#)),
        RobotError::UnsupportedJointType { joint, kind } if joint == "j2" && kind == "spherical"
    ));
    // A planar joint is only accepted (and skipped) as the root link's only joint.
    assert!(matches!(
        load(&toy_with(r#"name="tool_joint" type="fixed""#, r#"name="tool_joint" type="planar""#)),
        RobotError::UnsupportedJointType { joint, kind } if joint == "tool_joint" && kind == "planar"
    ));
    assert!(matches!(
        load(&toy_with(r#"name="j2" type="revolute""#, r#"name="j2" type="floating""#)),
        RobotError::UnsupportedJointType { joint, .. } if joint == "j2"
    ));
    assert!(matches!(
        load(&toy_with(r#"velocity="1.5""#, r#"velocity="0""#)),
        RobotError::NonPositiveLimit { joint, what: "velocity", .. } if joint == "j2"
    ));
    assert!(matches!(
        load(&toy_with(r#"<sphere radius="0.03"/>"#, r#"<mesh filename="package://x/l2.stl"/>"#)),
        RobotError::MeshCollision { link, filename, reason }
            if link == "l2" && filename == "package://x/l2.stl" && reason.contains("package")
    ));
    assert!(matches!(
        load(&toy_with(r#"<sphere radius="0.03"/>"#, r#"<sphere radius="-0.03"/>"#)),
        RobotError::InvalidShape { link, index: 0, .. } if link == "l2"
    ));
    assert!(matches!(
        load(&toy_with(r#"<link name="l2">"#, r#"<link name="l1">"#)),
        RobotError::DuplicateName { what: "link", name } if name == "l1"
    ));
    assert!(matches!(
        load(&toy_with(r#"<child link="l2"/>"#, r#"<child link="l3"/>"#)),
        RobotError::UnknownLink { joint, role: "child", link } if joint == "j2" && link == "l3"
    ));
    assert!(matches!(
        load(&toy_with(
            r#"<parent link="base"/>"#,
            r#"<parent link="l1"/>"#
        )),
        RobotError::NotATree { .. }
    ));
    assert!(matches!(
        RobotModel::from_urdf_file(std::path::Path::new("/nonexistent/robot.urdf")),
        Err(RobotError::Io { .. })
    ));
}

/// Edits of the shipped URDF: cut a byte range, or overwrite a range with a short string
/// (numbers, signs, markup, NaN). Loading must return `Ok` or `Err`, never panic.
fn mutated_urdf() -> impl Strategy<Value = String> {
    let text = include_str!("../../robots/kinova_gen3_mobile.urdf");
    let n = text.len();
    let replacement = prop_oneof![
        Just(String::new()),
        Just("NaN".to_string()),
        Just("-1e308".to_string()),
        Just("0".to_string()),
        Just("\"".to_string()),
        Just("<".to_string()),
        Just("/>".to_string()),
        Just("</link>".to_string()),
        "[-0-9. e]{1,8}",
        "[a-z_<>/=\" ]{1,12}",
    ];
    (0..n, 0usize..40, replacement, 1usize..4).prop_map(move |(at, len, with, times)| {
        let mut s = text.to_string();
        for k in 0..times {
            let start = (at + k * 997) % s.len();
            let mut end = (start + len).min(s.len());
            let mut start = start;
            while !s.is_char_boundary(start) {
                start -= 1;
            }
            while !s.is_char_boundary(end) {
                end += 1;
            }
            s.replace_range(start..end, &with);
        }
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn mutated_urdfs_never_panic(text in mutated_urdf()) {
        let loaded = RobotModel::from_urdf_str(&text);
        if let Ok(robot) = loaded {
            // A loaded robot is usable: FK at neutral and a collision model.
            let config = RobotConfig { base: [0.0; 3], arm: robot.neutral() };
            prop_assert!(robot.link_poses(&config).is_ok());
            let _ = RobotCollision::new(&robot);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Collision
// ---------------------------------------------------------------------------------------------

#[test]
fn neutral_is_free_and_only_adjacent_links_are_exempt() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    // Stronger than "no self-collision at neutral" (which holds by construction for pairs
    // touching there): no non-adjacent pair touches at neutral, so all are checked.
    let adjacent: Vec<(usize, usize)> = (0..robot.dof()).map(|i| (i, i + 1)).collect();
    assert_eq!(collision.allowed_pairs(), adjacent.as_slice());
    assert_eq!(collision.base_links(), &[0]);
    let poses = robot
        .link_poses(&RobotConfig {
            base: [3.0, -1.0, 2.0],
            arm: robot.neutral(),
        })
        .unwrap();
    assert_eq!(collision.self_collision(&poses), None);
}

/// Folding the arm back and down (q2 = -2.1, q4 = -1.55) puts the wrist into the chassis. The
/// origin of link 6 (SphericalWrist2, the frame of Actuator6) is an end point of the segment
/// its capsule is built around, hence inside that capsule; when it is also inside the chassis
/// box, the two shapes overlap, so the pair (0, 6) — not adjacent, hence checked (see the
/// allowed pairs above) — collides, and it or an earlier checked pair must be reported.
#[test]
fn arm_folded_into_the_base_is_a_self_collision() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let arm = DVector::from_vec(vec![0.0, -2.1, 0.0, -1.55, 0.0, 0.0, 0.0]);
    let poses = robot
        .link_poses(&RobotConfig {
            base: [0.0; 3],
            arm,
        })
        .unwrap();
    // The chassis box: |x| <= 0.22, |y| <= 0.18, 0.03 <= z <= 0.40 (URDF header).
    let p = poses[6].translation.vector;
    assert!(
        p.x.abs() < 0.22 && p.y.abs() < 0.18 && p.z > 0.03 && p.z < 0.40,
        "the wrist is not inside the chassis: {p:?}"
    );
    // Pairs are reported in lexicographic order, so the answer is (0, j) with 2 <= j <= 6.
    let hit = collision.self_collision(&poses);
    assert!(
        matches!(hit, Some((0, j)) if (2..=6).contains(&j)),
        "{hit:?}"
    );
    // The same fold seen from anywhere in the world.
    let moved = robot
        .link_poses(&RobotConfig {
            base: [2.0, -3.0, 1.0],
            arm: DVector::from_vec(vec![0.0, -2.1, 0.0, -1.55, 0.0, 0.0, 0.0]),
        })
        .unwrap();
    assert_eq!(collision.self_collision(&moved), hit);
}

#[test]
fn models_are_send_and_sync() {
    fn shareable<T: Send + Sync + Clone>() {}
    shareable::<RobotModel>();
    shareable::<RobotCollision>();
}

/// A scene with one part `cube`, a box of the given half extents whose frame is
/// `world_from_cube` (prismatic joint, at value 0), and with `wall`, a wall on the base map at
/// x in [0.23, 0.33] (|y| <= 3, z in [0, 2]): 10 mm in front of the chassis of a robot at the
/// origin.
fn box_scene(
    world_from_cube: Isometry3<f64>,
    half_extents: Vector3<f64>,
    wall: bool,
) -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.add_part(
        PartSpec::on_base(
            "cube",
            Joint::new(
                "cube_slide",
                JointKind::Prismatic,
                world_from_cube,
                Vector3::x(),
                Limits::new(0.0, 0.1),
            ),
        )
        .with_collider(Shape::cuboid(half_extents), Isometry3::identity()),
    );
    if wall {
        b.add_base_shape(BaseShape::new(
            "wall",
            Shape::cuboid(Vector3::new(0.05, 3.0, 1.0)),
            Isometry3::translation(0.28, 0.0, 1.0),
        ));
    }
    b.build().unwrap()
}

/// The scene's part poses at the zero state.
fn scene_data(model: &SceneModel) -> SceneData {
    let mut data = SceneData::new(model);
    let state = State::from_slice(model, &vec![0.0; model.nq()]).unwrap();
    scene_fk(model, &mut data, &state).unwrap();
    data
}

#[test]
fn scene_collisions_are_found_and_ignored_parts_skipped() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    // The arm stretched straight up (q = 0, free of self-collision): the gripper is far from
    // every other link, so a cube at the tool can only be reached by link 7.
    let up = RobotConfig {
        base: [0.0; 3],
        arm: DVector::zeros(7),
    };
    let poses = robot.link_poses(&up).unwrap();
    assert_eq!(collision.self_collision(&poses), None);
    let world_from_tool = robot.world_from_tool(&up).unwrap();
    assert!(world_from_tool.translation.z > 1.5);

    // A 0.15 × 0.02 × 0.02 m box at the tool frame: it spans |x| <= 0.075 between the fingers,
    // whose inner faces are at |x| = 0.07 (URDF header), and z in [0.19, 0.21] in the flange
    // frame, inside the fingers' [0.11, 0.23]: it overlaps both fingers.
    let model = box_scene(world_from_tool, Vector3::new(0.075, 0.01, 0.01), true);
    let cube = model.part_id("cube").unwrap();
    let wall = model.base_shape_id("wall").unwrap();
    let data = scene_data(&model);
    // The wall is 10 mm from the chassis: clear at margin 5 mm; the box ignored.
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Parts(&[cube]), 0.005),
        None
    );
    // Not ignored, the box touches the gripper, on the last link.
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Nothing, 0.005),
        Some((7, Body::Part(cube)))
    );
    // At margin 20 mm the wall is in reach of the chassis; link 0 comes first.
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Parts(&[cube]), 0.02),
        Some((0, Body::Base(wall)))
    );
    // At neutral (stowed arm, behind x = 0.17: the shoulder capsule, radius 0.05 about
    // x = 0.12) the same holds, and 1 m further back (-x) the robot is clear of everything.
    let stowed = robot
        .link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: robot.neutral(),
        })
        .unwrap();
    assert_eq!(
        collision.scene_collision(&stowed, &model, &data, Exempt::Nothing, 0.005),
        None
    );
    assert_eq!(
        collision.scene_collision(&stowed, &model, &data, Exempt::Nothing, 0.02),
        Some((0, Body::Base(wall)))
    );
    let back = robot
        .link_poses(&RobotConfig {
            base: [-1.0, 0.0, 0.0],
            arm: robot.neutral(),
        })
        .unwrap();
    assert_eq!(
        collision.scene_collision(&back, &model, &data, Exempt::Nothing, 0.02),
        None
    );

    // A 20 mm cube at the tool: 0.06 m from the inner finger faces (0.07 - 0.01) and 0.08 m
    // from the gripper body (0.19 - 0.11), so its clearance is 0.06 m: clear at margin 0.05,
    // hit at margin 0.07.
    let model = box_scene(world_from_tool, Vector3::repeat(0.01), false);
    let cube = model.part_id("cube").unwrap();
    let data = scene_data(&model);
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Nothing, 0.05),
        None
    );
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Nothing, 0.07),
        Some((7, Body::Part(cube)))
    );
}

#[test]
fn the_grasp_rule_lets_only_the_fingers_touch_the_grasped_part() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    // The shipped URDF: the finger boxes (collisions `finger_left` / `finger_right`) span z in
    // [0.17 - 0.06, 0.17 + 0.06] of the gripper frame, the tool frame is at z = 0.20: the
    // fingertips reach 0.03 m past the tool origin.
    let reach = collision
        .fingertip_reach(&robot)
        .expect("the Gen3 has fingers");
    assert!((reach - 0.03).abs() < 1e-9, "fingertip reach {reach}");
    let flags: Vec<bool> = robot.links()[7].contact.clone();
    assert_eq!(
        flags,
        vec![false, false, true, true],
        "bracelet, body, fingers"
    );

    let up = RobotConfig {
        base: [0.0; 3],
        arm: DVector::zeros(7),
    };
    let poses = robot.link_poses(&up).unwrap();
    let world_from_tool = robot.world_from_tool(&up).unwrap();
    // The box between the fingers of the test above, overlapping both fingers only (the
    // gripper body ends at z = 0.11, the box starts at 0.19): grasped, it is allowed.
    let model = box_scene(world_from_tool, Vector3::new(0.075, 0.01, 0.01), false);
    let cube = model.part_id("cube").unwrap();
    let data = scene_data(&model);
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Grasp(&[cube]), 0.005),
        None
    );
    // Grasped or not, any other part is checked for the fingers too.
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Grasp(&[]), 0.005),
        Some((7, Body::Part(cube)))
    );
    // A 0.2 m tall bar at the tool between the fingers reaches z = 0.10 < 0.11: into the
    // gripper body, which the rule does not exempt, at margin 0 as at 5 mm.
    let model = box_scene(world_from_tool, Vector3::new(0.01, 0.01, 0.1), false);
    let cube = model.part_id("cube").unwrap();
    let data = scene_data(&model);
    for margin in [0.0, 0.005] {
        assert_eq!(
            collision.scene_collision(&poses, &model, &data, Exempt::Grasp(&[cube]), margin),
            Some((7, Body::Part(cube)))
        );
    }
    // Exempting the part for every shape (a simulator's contact model) lets it through.
    assert_eq!(
        collision.scene_collision(&poses, &model, &data, Exempt::Parts(&[cube]), 0.0),
        None
    );
}

#[test]
fn contact_links_are_named_by_convention_or_by_the_options() {
    // WORLD_ROOTED's gripper link is called "finger": the convention marks it.
    let options = RobotImportOptions {
        tool_link: "tcp".into(),
        ..RobotImportOptions::default()
    };
    let robot = RobotModel::from_urdf_str_with(WORLD_ROOTED, &options).unwrap();
    assert_eq!(robot.links()[1].contact, vec![true]);
    // An explicit empty list: no contact geometry.
    let none = RobotImportOptions {
        contact_links: Some(vec![]),
        ..options.clone()
    };
    let robot = RobotModel::from_urdf_str_with(WORLD_ROOTED, &none).unwrap();
    assert_eq!(robot.links()[1].contact, vec![false]);
    // A listed link that does not exist, or does not move with the tool, is a typed error.
    for (link, why) in [("nope", "no such link"), ("base", "not rigidly attached")] {
        let bad = RobotImportOptions {
            contact_links: Some(vec![link.into()]),
            ..options.clone()
        };
        match RobotModel::from_urdf_str_with(WORLD_ROOTED, &bad) {
            Err(RobotError::InvalidContactLink { link: l, reason }) => {
                assert_eq!(l, link);
                assert!(reason.contains(why), "{reason}");
            }
            other => panic!("expected InvalidContactLink for {link:?}, got {other:?}"),
        }
    }
}

/// An OBJ of the box [−a, a] × [−b, b] × [−c, c] with one extra vertex at its centre (not on
/// the hull).
fn box_obj(a: f64, b: f64, c: f64) -> String {
    let mut out = String::from("o body\n");
    for (x, y, z) in [
        (-a, -b, -c),
        (a, -b, -c),
        (a, b, -c),
        (-a, b, -c),
        (-a, -b, c),
        (a, -b, c),
        (a, b, c),
        (-a, b, c),
        (0.0, 0.0, 0.0),
    ] {
        out.push_str(&format!("v {x} {y} {z}\n"));
    }
    out.push_str("f 1 2 3\nf 1 3 4\nf 1 2 6\nf 1 6 5\nf 9 1 2\nf 5 6 7\nf 5 7 8\n");
    out
}

#[test]
fn mesh_collision_geometry_loads_as_convex_hulls() {
    // TOY with l2's sphere replaced by a box mesh, once by a path relative to the URDF file and
    // once through a package with a scale of 2 (the box top at z = 0.03 goes to 0.06).
    let dir = std::env::temp_dir().join(format!("kinscene_robot_mesh_{}", std::process::id()));
    std::fs::create_dir_all(dir.join("pkg/meshes")).unwrap();
    std::fs::write(dir.join("pkg/meshes/l2.obj"), box_obj(0.05, 0.04, 0.03)).unwrap();
    let relative = toy_with(
        r#"<sphere radius="0.03"/>"#,
        r#"<mesh filename="pkg/meshes/l2.obj"/>"#,
    );
    let file = dir.join("toy.urdf");
    std::fs::write(&file, &relative).unwrap();
    let robot = RobotModel::from_urdf_file(&file).unwrap();
    let l2 = robot.links().iter().find(|l| l.name == "l2").unwrap();
    assert_eq!(l2.colliders.len(), 1);
    let kinscene::scene::Shape::ConvexMesh { vertices, .. } = &l2.colliders[0].shape else {
        panic!("expected a convex mesh, got {:?}", l2.colliders[0].shape);
    };
    // The faces' vertices, spanning the box (hand geometry: the centre vertex is inside).
    for (axis, half) in [(0, 0.05), (1, 0.04), (2, 0.03)] {
        let hi = vertices.iter().map(|p| p[axis]).fold(f64::MIN, f64::max);
        let lo = vertices.iter().map(|p| p[axis]).fold(f64::MAX, f64::min);
        assert!(
            (hi - half).abs() < 1e-6 && (lo + half).abs() < 1e-6,
            "axis {axis}"
        );
    }
    // The collision model compiles the hull.
    RobotCollision::new(&robot).unwrap();
    // Through a package, with a scale.
    let packaged = toy_with(
        r#"<sphere radius="0.03"/>"#,
        r#"<mesh filename="package://pkg/meshes/l2.obj" scale="2 2 2"/>"#,
    );
    let options = RobotImportOptions {
        package_paths: [("pkg".to_string(), dir.join("pkg"))].into_iter().collect(),
        ..RobotImportOptions::default()
    };
    let robot = RobotModel::from_urdf_str_with(&packaged, &options).unwrap();
    let l2 = robot.links().iter().find(|l| l.name == "l2").unwrap();
    assert_eq!(l2.colliders.len(), 1);
    assert_eq!(l2.contact, vec![false]);
    let kinscene::scene::Shape::ConvexMesh { vertices, .. } = &l2.colliders[0].shape else {
        panic!("expected a convex mesh");
    };
    let top = vertices.iter().map(|p| p.z).fold(f64::MIN, f64::max);
    // (The loader reads f32 vertices.)
    assert!((top - 0.06).abs() < 1e-6, "scale 2 applied: top {top}");
    // A missing file is a typed error naming the link, the URI and the path.
    let missing = toy_with(
        r#"<sphere radius="0.03"/>"#,
        r#"<mesh filename="pkg/meshes/none.stl"/>"#,
    );
    std::fs::write(dir.join("missing.urdf"), &missing).unwrap();
    match RobotModel::from_urdf_file(&dir.join("missing.urdf")) {
        Err(RobotError::MeshCollision {
            link,
            filename,
            reason,
        }) => {
            assert_eq!(link, "l2");
            assert_eq!(filename, "pkg/meshes/none.stl");
            assert!(reason.contains("not found"), "{reason}");
        }
        other => panic!("expected MeshCollision, got {other:?}"),
    }
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------------------------
// SRDF and self-collision exemptions
// ---------------------------------------------------------------------------------------------

/// The shipped Gen3 takes its stow and exemptions from its SRDF: the stow is the hand-found
/// fold written there (π, 0.4, 0, 2.2, π, −1, π/2), the exemptions the 7 adjacent pairs; and
/// the robot written back as an SRDF reads back to the same exemptions and stow.
#[test]
fn the_gen3_takes_stow_and_exemptions_from_its_srdf() {
    use kinscene::kinematics::robot::{PairReason, Srdf};
    let robot = RobotModel::kinova_gen3_mobile();
    let stow = [PI, 0.4, 0.0, 2.2, PI, -1.0, PI / 2.0];
    assert_eq!(robot.neutral().as_slice(), &stow);
    let pairs = robot.allowed_pairs().expect("from the SRDF");
    let listed: Vec<(usize, usize)> = pairs.iter().map(|p| (p.link1, p.link2)).collect();
    let adjacent: Vec<(usize, usize)> = (0..robot.dof()).map(|i| (i, i + 1)).collect();
    assert_eq!(listed, adjacent);
    assert!(
        pairs
            .iter()
            .all(|p| p.reason == PairReason::Srdf("Adjacent".into()))
    );
    let text = robot.to_srdf().to_xml().unwrap();
    let again = gen3_urdf_only()
        .with_srdf(&Srdf::parse(&text).unwrap())
        .unwrap();
    assert_eq!(again.neutral(), robot.neutral());
    assert_eq!(again.allowed_pairs(), robot.allowed_pairs());
}

/// The Gen3 from its URDF file alone (no SRDF).
fn gen3_urdf_only() -> RobotModel {
    RobotModel::from_urdf_file(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/robots/kinova_gen3_mobile.urdf"
    )))
    .unwrap()
}

/// Sampled exemptions on the Gen3's URDF. By default: exactly the adjacent pairs (no other pair
/// of this model touches at the stow, see `neutral_is_free_and_only_adjacent_links_are_exempt`,
/// nor in 95 % of configurations). With `disable_never`, as setup tools do, pairs touching in
/// none of 1 000 samples are exempt too; 1 000 fresh configurations (another seed), checked by
/// a model that checks only those pairs, show why that is not the default: such a pair can
/// still touch (here in 2 of 1 000; at most 1 % is asserted), while the pairs left checked
/// touch often (the fold into the chassis of `arm_folded_into_the_base_is_a_self_collision`).
#[test]
fn sampled_exemptions_are_what_the_samples_show() {
    use kinscene::kinematics::robot::{AllowedPair, PairReason, PairSampling};
    let urdf_only = gen3_urdf_only()
        .with_neutral(&RobotModel::kinova_gen3_mobile().neutral())
        .unwrap();
    let sampled = urdf_only
        .clone()
        .with_sampled_pairs(&PairSampling {
            samples: 1000,
            disable_never: true,
            ..PairSampling::default()
        })
        .unwrap();
    let pairs = sampled.allowed_pairs().unwrap();
    let n = sampled.links().len();
    for i in 0..sampled.dof() {
        assert!(pairs.contains(&AllowedPair {
            link1: i,
            link2: i + 1,
            reason: PairReason::Adjacent
        }));
    }
    let never: Vec<(usize, usize)> = pairs
        .iter()
        .filter(|p| p.reason == PairReason::Never)
        .map(|p| (p.link1, p.link2))
        .collect();
    assert!(!never.is_empty(), "{pairs:?}");
    // A model that checks only the Never pairs, and one that checks only the pairs left checked.
    let only = |checked: &dyn Fn(usize, usize) -> bool| {
        let mut exempt = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                if !checked(i, j) {
                    exempt.push(AllowedPair {
                        link1: i,
                        link2: j,
                        reason: PairReason::Default,
                    });
                }
            }
        }
        RobotCollision::new(&urdf_only.clone().with_allowed_pairs(exempt).unwrap()).unwrap()
    };
    let never_only = only(&|i, j| never.contains(&(i, j)));
    let sampled_collision = RobotCollision::new(&sampled).unwrap();
    let (lower, upper) = urdf_only.arm_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let (mut checked_hits, mut never_hits) = (0, 0);
    for _ in 0..1000 {
        let arm = DVector::from_fn(urdf_only.dof(), |i, _| {
            rng.random_range(lower[i].max(-PI)..=upper[i].min(PI))
        });
        let poses = urdf_only
            .link_poses(&RobotConfig {
                base: [0.0; 3],
                arm,
            })
            .unwrap();
        never_hits += usize::from(never_only.self_collision(&poses).is_some());
        checked_hits += usize::from(sampled_collision.self_collision(&poses).is_some());
    }
    assert!(checked_hits > 20, "{checked_hits}");
    assert!(never_hits <= 10, "{never_hits} of 1000 touch a Never pair");
    let strict = urdf_only
        .with_sampled_pairs(&PairSampling {
            samples: 200,
            ..PairSampling::default()
        })
        .unwrap();
    let strict: Vec<(usize, usize)> = strict
        .allowed_pairs()
        .unwrap()
        .iter()
        .map(|p| (p.link1, p.link2))
        .collect();
    assert_eq!(strict, (0..7).map(|i| (i, i + 1)).collect::<Vec<_>>());
}

/// Bad SRDF input is a typed error naming the element; a stow outside the limits is the
/// limits' error.
#[test]
fn bad_srdfs_are_typed_errors() {
    use kinscene::kinematics::robot::Srdf;
    let robot = RobotModel::kinova_gen3_mobile();
    let e = Srdf::parse("<robot><disable_collisions link1=\"a\"/></robot>").unwrap_err();
    assert!(matches!(e, RobotError::Srdf { .. }), "{e}");
    let out = Srdf::parse(
        r#"<robot><group_state name="home" group="arm"><joint name="Actuator2" value="9"/></group_state></robot>"#,
    )
    .unwrap();
    let e = robot.clone().with_srdf(&out).unwrap_err();
    assert!(
        matches!(e, RobotError::OutOfLimits { ref joint, .. } if joint == "Actuator2"),
        "{e}"
    );
    // Pairs naming links the model lacks are skipped and listed.
    let other = Srdf::parse(
        r#"<robot><disable_collisions link1="head_link" link2="base_link" reason="Never"/></robot>"#,
    )
    .unwrap();
    assert_eq!(
        robot.srdf_unknown_links(&other),
        vec!["head_link".to_string()]
    );
    assert_eq!(
        robot.with_srdf(&other).unwrap().allowed_pairs(),
        Some(&[][..])
    );
}

/// A robot whose torso and head are frozen into its base link: the base box (z ∈ [0, 0.3]),
/// the torso box on a frozen lift (x, y ∈ [−0.1, 0.1], z ∈ [0.3, 0.55]), the head ball on a
/// frozen pan joint (radius 0.1, centre (0, 0, 0.75)); the arm's first joint about z at
/// (0.1, 0, 0.52), its link a capsule of radius 0.04 out along x to 0.3 m (its cap around the
/// joint reaches x = 0.06 at z ∈ [0.48, 0.56], so it overlaps the torso in every
/// configuration), the second joint about y at the capsule's end, its link a ball of radius
/// 0.04 at 0.2 m along its x.
const TORSO_ROBOT: &str = r#"<robot name="torso">
  <link name="base"><collision><origin xyz="0 0 0.15"/><geometry><box size="0.4 0.4 0.3"/></geometry></collision></link>
  <link name="torso"><collision><origin xyz="0 0 0.125"/><geometry><box size="0.2 0.2 0.25"/></geometry></collision></link>
  <joint name="lift" type="prismatic"><origin xyz="0 0 0.3"/><parent link="base"/><child link="torso"/><axis xyz="0 0 1"/><limit lower="0" upper="0.2" velocity="0.1"/></joint>
  <link name="head"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
  <joint name="pan" type="revolute"><origin xyz="0 0 0.45"/><parent link="torso"/><child link="head"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1"/></joint>
  <link name="l1"><collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/><geometry><capsule radius="0.04" length="0.3"/></geometry></collision></link>
  <joint name="j1" type="revolute"><origin xyz="0.1 0 0.22"/><parent link="torso"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-3.2" upper="3.2" velocity="1"/></joint>
  <link name="l2"><collision><origin xyz="0.2 0 0"/><geometry><sphere radius="0.04"/></geometry></collision></link>
  <joint name="j2" type="revolute"><origin xyz="0.3 0 0"/><parent link="l1"/><child link="l2"/><axis xyz="0 1 0"/><limit lower="-2.6" upper="2.6" velocity="1"/></joint>
  <link name="tool_frame"/>
  <joint name="tool_joint" type="fixed"><origin xyz="0.25 0 0"/><parent link="l2"/><child link="tool_frame"/></joint>
</robot>"#;

/// An SRDF that disables some pairs of the URDF links two robot links carry exempts those
/// links' colliders only: the torso (frozen into the base link) and `l1` are exempt, the head
/// (frozen into the base link too) and `l2` are not.
/// - Arm straight out (j1 = j2 = 0): `l1` overlaps the torso, nothing else touches (by hand:
///   `l2`'s ball at (0.6, 0, 0.52)). No self-collision. Before collider-level exemptions the
///   SRDF's exemption of (torso, l1) was dropped, since (base, l1) and (head, l1) are not
///   disabled, and every configuration collided.
/// - j1 = π, j2 = −θ with cos θ = −0.656 (θ = 2.287): `l2` points from its joint at
///   (−0.2, 0, 0.52) towards the head centre, (0.2, 0, 0.23)/0.305 = (0.656, 0, 0.754); its
///   ball at (−0.069, 0, 0.671) is 0.105 m from the head centre (< 0.1 + 0.04) and 0.121 m
///   above the torso's top (> 0.04): the head and `l2` collide, named by the head's URDF link.
/// - The exemptions survive a round trip through the robot's own SRDF.
#[test]
fn an_srdf_exempts_the_colliders_of_merged_links_pair_by_pair() {
    use kinscene::kinematics::robot::Srdf;
    let srdf = Srdf::parse(
        r#"<robot name="torso">
  <disable_collisions link1="torso" link2="l1" reason="Adjacent"/>
  <disable_collisions link1="l1" link2="l2" reason="Adjacent"/>
</robot>"#,
    )
    .unwrap();
    // The arm starts at the torso: the lift and the head's pan are frozen (at 0).
    let loaded = RobotModel::from_urdf_str_with(
        TORSO_ROBOT,
        &RobotImportOptions {
            arm_root: Some("torso".into()),
            ..RobotImportOptions::default()
        },
    )
    .unwrap();
    assert_eq!(loaded.dof(), 2);
    assert_eq!(loaded.links()[0].merged, ["base", "torso", "head"]);
    let robot = loaded.clone().with_srdf(&srdf).unwrap();
    let exempt = robot.exempt_colliders();
    assert_eq!(exempt.len(), 1);
    // The base link's colliders: base box 0, torso box 1, head ball 2; l1's capsule 0.
    assert_eq!((exempt[0].link1, exempt[0].link2), (0, 1));
    assert_eq!(exempt[0].colliders, vec![(1, 0)]);
    let collision = RobotCollision::new(&robot).unwrap();
    let poses = |j1: f64, j2: f64| {
        robot
            .link_poses(&RobotConfig {
                base: [0.0; 3],
                arm: DVector::from_vec(vec![j1, j2]),
            })
            .unwrap()
    };
    let out = poses(0.0, 0.0);
    assert_eq!(collision.self_collision(&out), None);
    // The pair itself touches (the torso), so without the collider exemptions it collides.
    assert!(!collision.pair_touches(&out, 0, 1));
    let whole = RobotCollision::new(&loaded.clone().with_allowed_pairs(vec![]).unwrap()).unwrap();
    assert!(whole.pair_touches(&out, 0, 1));
    let theta = (-0.656f64).acos();
    let at_head = poses(PI, -theta);
    assert_eq!(collision.self_collision(&at_head), Some((0, 2)));
    let (a, b) = collision.closest_colliders(&at_head, 0, 2).unwrap();
    assert_eq!(robot.links()[0].source(a), Some("head"));
    assert_eq!(robot.links()[2].source(b), Some("l2"));
    // A cube beside the head, by hand 0.1 m from the head ball's surface (the ball's centre
    // (0, 0, 0.75), radius 0.1; the cube's near face at y = -0.2, z from 0.65) and
    // √(0.1² + 0.1²) = 0.141 m from the torso box's edge (y = -0.1, z = 0.55): within a 0.15 m
    // margin the base link touches it, the head's collider closest, named by its URDF link.
    let cube = box_scene(
        Isometry3::translation(0.0, -0.3, 0.75),
        Vector3::new(0.1, 0.1, 0.1),
        false,
    );
    let data = scene_data(&cube);
    let (l, k, body) = collision
        .scene_contact(&out, &cube, &data, Exempt::Nothing, 0.15)
        .unwrap();
    assert_eq!((l, robot.links()[l].source(k)), (0, Some("head")));
    assert!(matches!(body, Body::Part(_)));
    assert!(
        collision
            .scene_contact(&out, &cube, &data, Exempt::Nothing, 0.05)
            .is_none()
    );
    // Back through the robot's own SRDF: the same exemptions.
    let again = loaded
        .with_srdf(&Srdf::parse(&robot.to_srdf().to_xml().unwrap()).unwrap())
        .unwrap();
    assert_eq!(again.exempt_colliders(), robot.exempt_colliders());
    assert_eq!(again.allowed_pairs(), robot.allowed_pairs());
}

/// The floor carries the base: the toy's base box spans z ∈ [0, 0.5], so it touches a floor
/// slab whose top is z = 0, and that is no collision; a 1 cm kerb on the floor next to the
/// box (top z = 0.01, above `GROUND_TOP`) is one, for the base link. The arm keeps the margin
/// from the floor: with the arm straight out (j1 = j2 = 0) its lowest point is the capsule of
/// `l1` at z = 0.6 − 0.03 = 0.57 by hand, so a 0.6 m margin reports an arm link and a 0.5 m
/// margin nothing.
#[test]
fn the_base_may_stand_on_the_floor_and_the_arm_keeps_off_it() {
    use kinscene::kinematics::robot::GROUND_TOP;
    let robot = RobotModel::from_urdf_str(TOY).unwrap();
    let collision = RobotCollision::new(&robot).unwrap();
    let scene = |kerb: bool| {
        let mut b = SceneModelBuilder::new();
        b.add_base_shape(BaseShape::new(
            "floor",
            Shape::cuboid(Vector3::new(5.0, 5.0, 0.05)),
            Isometry3::translation(0.0, 0.0, -0.05),
        ));
        if kerb {
            // x ∈ [0.2, 0.3]: it touches the base box's face at x = 0.2.
            b.add_base_shape(BaseShape::new(
                "kerb",
                Shape::cuboid(Vector3::new(0.05, 0.5, 0.005)),
                Isometry3::translation(0.25, 0.0, 0.005),
            ));
        }
        b.build().unwrap()
    };
    let poses = robot
        .link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: DVector::zeros(2),
        })
        .unwrap();
    const { assert!(GROUND_TOP < 0.01) };
    let floor = scene(false);
    let data = scene_data(&floor);
    let hit = |margin| collision.scene_collision(&poses, &floor, &data, Exempt::Nothing, margin);
    assert_eq!(hit(0.0), None);
    assert_eq!(hit(0.5), None);
    assert!(matches!(hit(0.6), Some((l, _)) if l > 0), "{:?}", hit(0.6));
    let kerbed = scene(true);
    let data = scene_data(&kerbed);
    let kerb = kerbed.base_shape_id("kerb").unwrap();
    assert_eq!(
        collision.scene_collision(&poses, &kerbed, &data, Exempt::Nothing, 0.0),
        Some((0, Body::Base(kerb)))
    );
}

/// The computed stow of the toy: its footprint is set by the base box's corners (0.2·√2 =
/// 0.283 m), `l1`'s capsule (bounding sphere: centre 0.15 m out, radius 0.15 + 0.03, so 0.33
/// m whatever j1 is) and `l2`'s ball (0.3 + 0.1 cos j2 + 0.03 m), so the smallest footprint is
/// 0.33 m, reached with |j2| ≥ π/2 (by hand). The search finds it; the configuration is free
/// of self-collision and the footprint radius follows. A floor clearance no configuration
/// meets is `NoStow`; bad settings are typed errors.
#[test]
fn a_computed_stow_is_the_most_compact_free_configuration() {
    use kinscene::kinematics::robot::StowSearch;
    let search = StowSearch {
        samples: 300,
        ..StowSearch::default()
    };
    let robot = RobotModel::from_urdf_str(TOY)
        .unwrap()
        .with_computed_stow(&search)
        .unwrap();
    let stow = robot.neutral();
    assert!(
        (robot.base().footprint_radius - 0.33).abs() < 1e-9,
        "{stow}"
    );
    assert!(
        stow[1].abs() >= std::f64::consts::FRAC_PI_2 - 1e-9,
        "{stow}"
    );
    let poses = robot
        .link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: stow,
        })
        .unwrap();
    assert_eq!(
        RobotCollision::new(&robot).unwrap().self_collision(&poses),
        None
    );
    let too_high = StowSearch {
        floor_clearance: 10.0,
        ..search.clone()
    };
    assert!(matches!(
        RobotModel::from_urdf_str(TOY)
            .unwrap()
            .with_computed_stow(&too_high),
        Err(RobotError::NoStow { samples: 300 })
    ));
    for bad in [
        StowSearch {
            samples: 0,
            ..search.clone()
        },
        StowSearch {
            perturbation: f64::NAN,
            ..search.clone()
        },
    ] {
        assert!(matches!(
            RobotModel::from_urdf_str(TOY)
                .unwrap()
                .with_computed_stow(&bad),
            Err(RobotError::InvalidSetting(_))
        ));
    }
}

/// The Gen3 from its URDF alone (arm straight up at q = 0, inside the chassis' footprint but
/// 1.5 m tall): the computed stow folds the arm within a footprint no larger than the
/// hand-found stow's, about as low (highest link origin within 5 cm of it), and free of
/// self-collision under the shipped exemptions (adjacent pairs only).
#[test]
fn the_gen3_computed_stow_is_as_compact_as_the_hand_found_one() {
    use kinscene::kinematics::robot::StowSearch;
    let shipped = RobotModel::kinova_gen3_mobile();
    let computed = gen3_urdf_only()
        .with_computed_stow(&StowSearch {
            samples: 1000,
            ..StowSearch::default()
        })
        .unwrap();
    let (a, b) = (
        computed.base().footprint_radius,
        shipped.base().footprint_radius,
    );
    assert!(a <= b + 1e-9, "computed {a} hand-found {b}");
    // The arm's highest point: the tool frame's height bounds it from below, so compare the
    // highest link origin (FK, not the search's boxes).
    let top = |q: DVector<f64>| {
        shipped
            .link_poses(&RobotConfig {
                base: [0.0; 3],
                arm: q,
            })
            .unwrap()
            .iter()
            .map(|p| p.translation.z)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let (ta, tb) = (top(computed.neutral()), top(shipped.neutral()));
    // Measured: 1.102 m against 1.072 m (the straight-up arm: 1.5 m).
    assert!(ta <= tb + 0.05, "computed {ta} hand-found {tb}");
    let poses = shipped
        .link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: computed.neutral(),
        })
        .unwrap();
    assert_eq!(
        RobotCollision::new(&shipped)
            .unwrap()
            .self_collision(&poses),
        None
    );
}

/// `tool_approach` turns the tool frame so that its +z is the given direction of the tool
/// link: on the toy at q = 0 every frame is aligned with the world, so the approach is the
/// world's x for (1, 0, 0) and −z for (0, 0, −1) (the opposite of the default, a half turn),
/// and the tool's position does not move (0.5 m out, 0.6 m up, by hand). A zero or NaN
/// direction is a typed error.
#[test]
fn the_tool_approach_turns_the_tool_frame() {
    let with = |axis: [f64; 3]| {
        RobotModel::from_urdf_str_with(
            TOY,
            &RobotImportOptions {
                tool_approach: Some(axis),
                ..RobotImportOptions::default()
            },
        )
    };
    let zero = RobotConfig {
        base: [0.0; 3],
        arm: DVector::zeros(2),
    };
    for (axis, expected) in [
        ([1.0, 0.0, 0.0], Vector3::x()),
        ([0.0, 0.0, -2.0], -Vector3::z()),
        ([0.0, 0.0, 1.0], Vector3::z()),
    ] {
        let tool = with(axis).unwrap().world_from_tool(&zero).unwrap();
        assert!(
            ((tool.rotation * Vector3::z()) - expected).norm() < 1e-12,
            "{axis:?}"
        );
        assert!((tool.translation.vector - Vector3::new(0.5, 0.0, 0.6)).norm() < 1e-12);
    }
    for bad in [[0.0; 3], [f64::NAN, 0.0, 1.0]] {
        assert!(matches!(
            with(bad),
            Err(RobotError::InvalidToolApproach { .. })
        ));
    }
}

/// `self_collision_within(margin)` finds a pair exactly when some checked pair (every link
/// pair not in `allowed_pairs`) is within `margin` by `pair_distance` (parry's exact distance
/// over all shape pairs, no sphere filter): on 40 seeded random Gen3 configurations, at
/// margins just below and just above that least distance.
#[test]
fn self_collision_with_a_margin_agrees_with_the_pair_distances() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let links = robot.links().len();
    let mut bracketed = 0;
    for _ in 0..40 {
        let arm = random_arm(&robot, &mut rng);
        let poses = robot
            .link_poses(&RobotConfig {
                base: [0.0; 3],
                arm,
            })
            .unwrap();
        let least = (0..links)
            .flat_map(|i| (i + 1..links).map(move |j| (i, j)))
            .filter(|p| !collision.allowed_pairs().contains(p))
            .map(|(i, j)| collision.pair_distance(&poses, i, j))
            .fold(f64::INFINITY, f64::min);
        assert_eq!(
            collision.self_collision(&poses).is_some(),
            least <= 0.0,
            "{least}"
        );
        if least > 1e-6 && least < 0.2 {
            assert!(
                collision
                    .self_collision_within(&poses, least - 1e-6)
                    .is_none()
            );
            assert!(
                collision
                    .self_collision_within(&poses, least + 1e-6)
                    .is_some()
            );
            bracketed += 1;
        }
    }
    assert!(bracketed >= 10, "{bracketed}");
}
