//! A mobile base modelled as joints (prismatic x, prismatic y, yaw from a world link) is
//! recognised by its structure: the Panda of example-robot-data wrapped in such a chain has the
//! same arm, links and forward kinematics as the Panda on a planar root joint; chains that do
//! not move the base as `world_from_base` does are left as joints.

use kinscene::kinematics::robot::{RobotConfig, RobotImportOptions, RobotModel};
use nalgebra::{DVector, Isometry3, Translation3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::third_party::example_robot_data;

/// One base joint: (name, type, axis, origin xyz).
type BaseJoint<'a> = (&'a str, &'a str, &'a str, &'a str);

/// The Panda URDF with `joints` in a chain from a new root link `w` to `panda_link0`.
fn panda_on(joints: &[BaseJoint<'_>]) -> String {
    let path = example_robot_data().join("robots/panda_description/urdf/panda.urdf");
    let text = std::fs::read_to_string(path).unwrap();
    let mut extra = String::from("<link name=\"w\"/>\n");
    let mut parent = "w".to_string();
    for (k, (name, kind, axis, xyz)) in joints.iter().enumerate() {
        let child = if k + 1 == joints.len() {
            "panda_link0".to_string()
        } else {
            let c = format!("carriage_{k}");
            extra += &format!("<link name=\"{c}\"/>\n");
            c
        };
        extra += &format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/>\
             <child link=\"{child}\"/><origin xyz=\"{xyz}\" rpy=\"0 0 0\"/><axis xyz=\"{axis}\"/>\
             <limit lower=\"-50\" upper=\"50\" velocity=\"1\" effort=\"1\"/></joint>\n"
        );
        parent = child;
    }
    text.replace("</robot>", &(extra + "</robot>"))
}

fn load(text: &str) -> RobotModel {
    let mut options = RobotImportOptions {
        tool_link: "panda_hand".into(),
        ..RobotImportOptions::default()
    };
    options
        .package_paths
        .insert("example-robot-data".into(), example_robot_data());
    RobotModel::from_urdf_str_with(text, &options).unwrap()
}

/// Names that say nothing (`a`, `b`, `c`), y before x, a continuous yaw joint and z offsets of
/// 0.07 m and 0.03 m: recognised as the base. The arm, frozen fingers and colliders match the
/// planar-root Panda's with the base link's shapes lifted by 0.1 m; at 20 seeded random base
/// poses and arm configurations every link pose equals the planar one lifted by 0.1 m along
/// world z (1e-12: the same products in another order).
#[test]
fn an_arm_on_xy_yaw_joints_is_the_arm_on_a_planar_joint() {
    let planar = load(&panda_on(&[("p", "planar", "0 0 1", "0 0 0")]));
    let chain = load(&panda_on(&[
        ("a", "prismatic", "0 1 0", "0 0 0.07"),
        ("b", "prismatic", "1 0 0", "0 0 0"),
        ("c", "continuous", "0 0 1", "0 0 0.03"),
    ]));
    let lift: Isometry3<f64> = Translation3::new(0.0, 0.0, 0.1).into();
    assert_eq!(chain.dof(), 7);
    assert_eq!(chain.arm_joints().len(), planar.arm_joints().len());
    assert_eq!(chain.links()[0].name, "panda_link0");
    assert_eq!(chain.frozen_joints(), planar.frozen_joints());
    let base_shapes = chain.links()[0].colliders.len();
    assert!(base_shapes > 0 && base_shapes == planar.links()[0].colliders.len());
    for (c, p) in chain.links()[0]
        .colliders
        .iter()
        .zip(&planar.links()[0].colliders)
    {
        assert!(
            (c.part_from_shape.to_homogeneous() - (lift * p.part_from_shape).to_homogeneous())
                .amax()
                < 1e-12
        );
    }
    assert_eq!(chain.links()[1..], planar.links()[1..]);
    let (lower, upper) = planar.arm_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..20 {
        let config = RobotConfig {
            base: [
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
                rng.random_range(-4.0..4.0),
            ],
            arm: DVector::from_fn(7, |i, _| rng.random_range(lower[i]..=upper[i])),
        };
        let (c, p) = (
            chain.link_poses(&config).unwrap(),
            planar.link_poses(&config).unwrap(),
        );
        assert!((c[0].to_homogeneous() - p[0].to_homogeneous()).amax() < 1e-12);
        for (c, p) in c.iter().zip(&p).skip(1) {
            assert!((c.to_homogeneous() - (lift * p).to_homogeneous()).amax() < 1e-12);
        }
        let (c, p) = (
            chain.world_from_tool(&config).unwrap(),
            planar.world_from_tool(&config).unwrap(),
        );
        assert!((c.to_homogeneous() - (lift * p).to_homogeneous()).amax() < 1e-12);
    }
}

/// Chains that are not a planar base stay joints, so the arm gains them (10 joints): an axis
/// along -x, yaw before the translations, an origin with an x offset, a revolute joint about y.
#[test]
fn other_chains_are_not_the_base() {
    let x = ("x", "prismatic", "1 0 0", "0 0 0");
    let y = ("y", "prismatic", "0 1 0", "0 0 0");
    let yaw = ("yaw", "revolute", "0 0 1", "0 0 0");
    for joints in [
        [("x", "prismatic", "-1 0 0", "0 0 0"), y, yaw],
        [yaw, x, y],
        [("x", "prismatic", "1 0 0", "0.2 0 0"), y, yaw],
        [x, y, ("yaw", "revolute", "0 1 0", "0 0 0")],
    ] {
        let robot = load(&panda_on(&joints));
        assert_eq!(robot.dof(), 10, "{joints:?}");
        assert_eq!(robot.links()[0].name, "w");
    }
}
