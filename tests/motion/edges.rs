//! Certified arm edges ([`ArmEdgeCheck`]): every edge it accepts is free under a dense exact
//! parry check, on the shipped robots among 1 mm plates; and a thin plate that the discrete
//! check at the default resolution jumps is caught.

use std::cell::Cell;
use std::time::Duration;

use kinscene::Termination;
use kinscene::kinematics::robot::{
    ArmEdgeCheck, EdgeScene, EdgeSettings, Exempt, RobotCollision, RobotConfig, RobotError,
    RobotModel, RobotSpheres, SphereSettings, Srdf,
};
use kinscene::motion::paths::{PathOutcome, PathSettings, first_invalid, plan_arm_with_motion};
use kinscene::scene::{
    BaseShape, SceneData, SceneModel, SceneModelBuilder, Shape, State, forward_kinematics,
};
use nalgebra::{DVector, Isometry3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::kinematics::third_party::{example_robot_data, options};

/// Thickness (m) of the plates.
const PLATE: f64 = 0.001;
/// Spacing (joint-space Euclidean norm) of the dense exact re-check. A step of norm `h` moves
/// no point more than `h·√7·1.3 m` on these 7-joint arms (every lever arm is under 1.3 m), so
/// at 2e-4 no point moves 0.7 mm between samples: no link crosses a 1 mm plate unseen.
const DENSE: f64 = 2e-4;

fn scene_data(model: &SceneModel) -> SceneData {
    let mut data = SceneData::new(model);
    let state = State::from_slice(model, &[]).unwrap();
    forward_kinematics(model, &mut data, &state).unwrap();
    data
}

/// A floor and six 1 mm plates of various orientations around a robot at the origin.
fn plates() -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(BaseShape::new(
        "floor",
        Shape::cuboid(Vector3::new(3.0, 3.0, 0.05)),
        Isometry3::translation(0.0, 0.0, -0.05),
    ));
    let plates = [
        (
            Vector3::new(0.2, 0.3, PLATE / 2.0),
            Vector3::new(0.5, 0.0, 0.55),
            Vector3::zeros(),
        ),
        (
            Vector3::new(PLATE / 2.0, 0.25, 0.3),
            Vector3::new(0.45, -0.35, 0.8),
            Vector3::zeros(),
        ),
        (
            Vector3::new(0.3, PLATE / 2.0, 0.3),
            Vector3::new(-0.1, 0.5, 0.7),
            Vector3::zeros(),
        ),
        (
            Vector3::new(0.25, 0.25, PLATE / 2.0),
            Vector3::new(-0.4, -0.3, 1.0),
            Vector3::new(0.4, 0.2, 0.0),
        ),
        (
            Vector3::new(PLATE / 2.0, 0.3, 0.2),
            Vector3::new(0.0, -0.55, 0.4),
            Vector3::new(0.0, 0.0, 0.7),
        ),
        (
            Vector3::new(0.2, 0.2, PLATE / 2.0),
            Vector3::new(0.3, 0.3, 1.2),
            Vector3::new(-0.5, 0.3, 0.0),
        ),
    ];
    for (k, (half, at, rotation)) in plates.into_iter().enumerate() {
        b.add_base_shape(BaseShape::new(
            format!("plate{k}"),
            Shape::cuboid(half),
            Isometry3::new(at, rotation),
        ));
    }
    b.build().unwrap()
}

fn panda() -> RobotModel {
    let root = example_robot_data().join("robots/panda_description");
    let panda =
        RobotModel::from_urdf_file_with(&root.join("urdf/panda.urdf"), &options("panda_hand"))
            .unwrap();
    let srdf = Srdf::parse(&std::fs::read_to_string(root.join("srdf/panda.srdf")).unwrap());
    panda.with_srdf(&srdf.unwrap()).unwrap()
}

/// The exact check: no self-collision and no contact with the scene (margin 0).
fn exact<'a>(
    robot: &'a RobotModel,
    collision: &'a RobotCollision,
    model: &'a SceneModel,
    data: &'a SceneData,
) -> impl Fn(&[f64]) -> bool + 'a {
    move |q: &[f64]| {
        let config = RobotConfig {
            base: [0.0; 3],
            arm: DVector::from_column_slice(q),
        };
        robot.link_poses(&config).is_ok_and(|p| {
            collision.self_collision(&p).is_none()
                && collision
                    .scene_collision(&p, model, data, Exempt::Nothing, 0.0)
                    .is_none()
        })
    }
}

/// On seeded random edges (length 0.1–0.5 rad) between exactly free configurations of the
/// Gen3 and the Panda among the plates, every edge the certified check accepts passes the
/// dense exact re-check. Not vacuous: both robots have accepted edges that pass within 6 cm of
/// a plate (the scene check at a 6 cm margin fires on some dense sample). Rejections are
/// printed (the thin-plate test below asserts one).
#[test]
fn every_certified_edge_is_free_under_a_dense_exact_check() {
    let model = plates();
    let data = scene_data(&model);
    let obstacles = EdgeScene {
        model: &model,
        data: &data,
        exempt: Exempt::Nothing,
        margin: 0.0,
    };
    for (name, robot) in [
        ("gen3", RobotModel::kinova_gen3_mobile()),
        ("panda", panda()),
    ] {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let edges = ArmEdgeCheck::new(
            &robot,
            &collision,
            &spheres,
            obstacles,
            [0.0; 3],
            &EdgeSettings::default(),
        )
        .unwrap();
        let free = exact(&robot, &collision, &model, &data);
        let (lo, hi) = robot.arm_bounds();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let random = |rng: &mut ChaCha8Rng| -> Vec<f64> {
            (0..robot.dof())
                .map(|i| rng.random_range(lo[i].max(-3.0)..=hi[i].min(3.0)))
                .collect()
        };
        let (mut accepted, mut near, mut rejected) = (0, 0, 0);
        for _ in 0..600 {
            if accepted >= 30 {
                break;
            }
            let a = random(&mut rng);
            let direction: Vec<f64> = random(&mut rng)
                .iter()
                .zip(&a)
                .map(|(x, y)| x - y)
                .collect();
            let norm = direction.iter().map(|d| d * d).sum::<f64>().sqrt();
            let length = rng.random_range(0.1..0.5);
            let b: Vec<f64> = (0..a.len())
                .map(|i| (a[i] + direction[i] * length / norm).clamp(lo[i], hi[i]))
                .collect();
            if !free(&a) || !free(&b) {
                continue;
            }
            if !edges.check(&a, &b) {
                rejected += 1;
                continue;
            }
            accepted += 1;
            let close = Cell::new(false);
            let dense = |q: &[f64]| {
                let config = RobotConfig {
                    base: [0.0; 3],
                    arm: DVector::from_column_slice(q),
                };
                let poses = robot.link_poses(&config).unwrap();
                if collision
                    .scene_collision(&poses, &model, &data, Exempt::Nothing, 0.06)
                    .is_some()
                {
                    close.set(true);
                }
                free(q)
            };
            let hit = first_invalid(&[a.clone(), b.clone()], DENSE, false, &dense);
            assert!(
                hit.is_none(),
                "{name}: certified edge {a:?} -> {b:?} collides at {hit:?}"
            );
            near += usize::from(close.get());
        }
        println!(
            "{name}: {accepted} certified edges ({near} within 6 cm of a plate), {rejected} rejected"
        );
        assert!(
            accepted >= 30 && near > 0,
            "{name}: {accepted} {near} {rejected}"
        );
    }
}

/// One revolute joint about z at 0.5 m carrying a 2 m rod of 2 mm square section.
const ROD: &str = r#"<robot name="rod">
  <link name="base"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="rod"><collision><origin xyz="1.0 0 0"/><geometry><box size="2.0 0.002 0.002"/></geometry></collision></link>
  <joint name="turn" type="revolute"><origin xyz="0 0 0.5"/><parent link="base"/><child link="rod"/><axis xyz="0 0 1"/><limit lower="-0.3" upper="0.3" velocity="1"/></joint>
  <link name="tool_frame"/>
  <joint name="tool_joint" type="fixed"><origin xyz="2.0 0 0"/><parent link="rod"/><child link="tool_frame"/></joint>
</robot>"#;

/// A 1 mm plate, radial at angle `angle` about z, spanning radii 1.5–1.9 m and the rod's
/// height.
fn radial_plate(angle: f64) -> SceneModel {
    let mut b = SceneModelBuilder::new();
    let pose = Isometry3::new(
        Vector3::new(1.7 * angle.cos(), 1.7 * angle.sin(), 0.5),
        Vector3::new(0.0, 0.0, angle),
    );
    b.add_base_shape(BaseShape::new(
        "plate",
        Shape::cuboid(Vector3::new(0.2, PLATE / 2.0, 0.05)),
        pose,
    ));
    b.build().unwrap()
}

/// The rod turns from −0.3 to 0.3 rad through a radial 1 mm plate placed midway between two
/// samples of the discrete check at the default resolution ([`PathSettings::default`], the
/// spacing OMPL's motion check uses in `plan_arm`): the discrete check accepts the edge
/// although the rod meets the plate (exact check at the plate's angle); the certified check
/// rejects it, accepts the part of the turn short of the plate, and accepts the whole turn
/// without the plate; planning with the certified check finds no path (the plate blocks the
/// only way).
#[test]
fn a_thin_plate_the_discrete_check_jumps_is_caught() {
    let robot = RobotModel::from_urdf_str(ROD).unwrap();
    let collision = RobotCollision::new(&robot).unwrap();
    let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
    let (a, b) = (vec![-0.3], vec![0.3]);
    // The discrete check's samples: first_invalid's `n = ⌈0.6 / resolution⌉` equal steps.
    let resolution = PathSettings::default().resolution;
    let n = (0.6 / resolution).ceil();
    let angle = -0.3 + 0.6 * ((n / 2.0).floor() + 0.5) / n;
    let model = radial_plate(angle);
    let data = scene_data(&model);
    let free = exact(&robot, &collision, &model, &data);
    assert!(!free(&[angle]), "the rod meets the plate at {angle}");
    assert!(first_invalid(&[a.clone(), b.clone()], resolution, false, &free).is_none());

    let obstacles = EdgeScene {
        model: &model,
        data: &data,
        exempt: Exempt::Nothing,
        margin: 0.0,
    };
    let settings = EdgeSettings::default();
    let edges =
        ArmEdgeCheck::new(&robot, &collision, &spheres, obstacles, [0.0; 3], &settings).unwrap();
    assert!(!edges.check(&a, &b));
    assert!(edges.check(&a, &[angle - 0.2]));
    let empty = SceneModelBuilder::new().build().unwrap();
    let empty_data = scene_data(&empty);
    let nothing = EdgeScene {
        model: &empty,
        data: &empty_data,
        exempt: Exempt::Nothing,
        margin: 0.0,
    };
    let open =
        ArmEdgeCheck::new(&robot, &collision, &spheres, nothing, [0.0; 3], &settings).unwrap();
    assert!(open.check(&a, &b));

    let certified = |p: &[f64], q: &[f64]| edges.check(p, q);
    let path_settings = PathSettings {
        budget: Duration::from_millis(300),
        seed: Some(3),
        ..PathSettings::default()
    };
    let outcome = plan_arm_with_motion(
        &a,
        &b,
        &[-0.3],
        &[0.3],
        &free,
        Some(&certified),
        &path_settings,
        &Termination::none(),
    )
    .unwrap();
    assert!(!matches!(outcome, PathOutcome::Solved(_)), "{outcome:?}");
}

/// Bad settings and a sphere model of another robot are typed errors.
#[test]
fn bad_edge_settings_are_errors() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
    let empty = SceneModelBuilder::new().build().unwrap();
    let empty_data = scene_data(&empty);
    let obstacles = EdgeScene {
        model: &empty,
        data: &empty_data,
        exempt: Exempt::Nothing,
        margin: 0.0,
    };
    for min_step in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let settings = EdgeSettings { min_step };
        assert!(matches!(
            ArmEdgeCheck::new(&robot, &collision, &spheres, obstacles, [0.0; 3], &settings),
            Err(RobotError::InvalidSetting(_))
        ));
    }
    let rod = RobotModel::from_urdf_str(ROD).unwrap();
    assert!(matches!(
        ArmEdgeCheck::new(
            &rod,
            &collision,
            &spheres,
            obstacles,
            [0.0; 3],
            &EdgeSettings::default()
        ),
        Err(RobotError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        ArmEdgeCheck::new(
            &robot,
            &collision,
            &spheres,
            obstacles,
            [f64::NAN, 0.0, 0.0],
            &EdgeSettings::default()
        ),
        Err(RobotError::NonFiniteValue {
            what: "base",
            index: 0
        })
    ));
}
