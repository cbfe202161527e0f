//! Differential-drive bases end to end: the base paths of returned plans never move sideways
//! (measured here by finite differences of the sampled trajectory, not from the planner's
//! pieces), respect the forward and yaw limits, and the plans pass the independent re-check
//! of `contact.rs`; TIAGo (example-robot-data) as a differential-drive robot opens a cabinet
//! door and then the drawer behind it.

use std::path::Path;
use std::time::{Duration, Instant};

use kinscene::kinematics::robot::{BaseKind, RobotDescription, RobotError, RobotModel};
use kinscene::motion::timing::{TimedPath, time_parameterise};
use kinscene::planner::{HierarchicalPlanner, MotionOutcome, MotionPlan, PlannerSettings};
use kinscene::scene::{
    BaseShape, Handle, Joint, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape,
};
use kinscene::task::{Problem, Termination};
use nalgebra::{Isometry3, Point3, Vector3};

use super::contact::{RobotGeometry, recheck, recheck_robot};
use crate::kinematics::third_party::example_robot_data;

/// Time step (s) of the finite differences.
const DT: f64 = 1e-3;

/// The largest speeds of a timed base path, by finite differences of poses sampled every
/// [`DT`] (the last step shorter): across the heading (lateral, m/s), along it (forward,
/// m/s) and in yaw (rad/s). Each difference is taken in the base frame at the mean yaw of its
/// two samples.
fn speeds(path: &TimedPath) -> (f64, f64, f64) {
    let n = (path.duration / DT).ceil() as usize;
    let times: Vec<f64> = (0..=n)
        .map(|i| (i as f64 * DT).min(path.duration))
        .collect();
    let (mut lateral, mut forward, mut yaw) = (0.0_f64, 0.0_f64, 0.0_f64);
    for w in times.windows(2) {
        let h = w[1] - w[0];
        if h <= 0.0 {
            continue;
        }
        let (a, b) = (path.sample(w[0]), path.sample(w[1]));
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let psi = 0.5 * (a[2] + b[2]);
        lateral = lateral.max((-psi.sin() * dx + psi.cos() * dy).abs() / h);
        forward = forward.max((psi.cos() * dx + psi.sin() * dy).abs() / h);
        yaw = yaw.max((b[2] - a[2]).abs() / h);
    }
    (lateral, forward, yaw)
}

/// Every base path of `plan` moves along the heading only (lateral speed below 1e-6 m/s: a
/// straight drive has none, a turn in place does not move the position; the tolerance covers
/// round-off and a difference straddling a corner, where the base is at rest), within the
/// base's forward and yaw limits (1e-6 relative). Returns the distance driven and the largest
/// turn, summed over the steps.
fn assert_no_sideways(robot: &RobotModel, plan: &MotionPlan) -> (f64, f64) {
    let base = robot.base();
    assert_eq!(base.kind, BaseKind::DifferentialDrive);
    let (mut driven, mut turned) = (0.0, 0.0_f64);
    for (i, step) in plan.steps.iter().enumerate() {
        let path = &step.base_path;
        let (lateral, forward, yaw) = speeds(path);
        assert!(lateral < 1e-6, "step {i}: lateral speed {lateral} m/s");
        assert!(
            forward <= base.max_velocity[0] * (1.0 + 1e-6),
            "step {i}: {forward}"
        );
        assert!(
            yaw <= base.max_velocity[2] * (1.0 + 1e-6),
            "step {i}: {yaw}"
        );
        for w in path.positions.windows(2) {
            driven += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            turned = turned.max((w[1][2] - w[0][2]).abs());
        }
    }
    (driven, turned)
}

fn solve(planner: &HierarchicalPlanner, model: &SceneModel, problem: &Problem) -> MotionPlan {
    let result = planner
        .plan(
            model,
            problem,
            &Termination::after(Duration::from_secs(300)),
        )
        .expect("valid input");
    match result.outcome {
        MotionOutcome::Solved(plan) => plan,
        other => panic!("expected a plan, got {other:?}"),
    }
}

#[test]
fn differential_drive_base_limits_are_checked() {
    let robot = RobotModel::kinova_gen3_mobile();
    let diff = robot.base().to_differential_drive();
    assert_eq!(diff.max_velocity[1], 0.0);
    assert!(robot.clone().with_base(diff.clone()).is_ok());
    let sideways = kinscene::kinematics::robot::MobileBase {
        max_velocity: [0.5, 0.1, 1.0],
        ..diff.clone()
    };
    let err = robot.clone().with_base(sideways).unwrap_err();
    assert!(
        matches!(&err, RobotError::InvalidSetting(s) if s.field == "max_velocity[1]"),
        "{err}"
    );
    let no_yaw = kinscene::kinematics::robot::MobileBase {
        max_acceleration: [0.5, 0.0, f64::NAN],
        ..diff
    };
    assert!(matches!(
        robot.with_base(no_yaw),
        Err(RobotError::NonPositiveLimit {
            what: "acceleration",
            ..
        })
    ));
}

/// The Gen3 of the drawer test in `mod.rs` as a differential-drive base, starting 1.5 m to
/// the side of the drawer, facing the counter: farther to the side than the arm reaches
/// (about 0.9 m), so every placement is off the line ahead and a holonomic base would slide
/// sideways to it.
#[test]
fn a_differential_drive_plan_never_moves_sideways_and_rechecks() {
    let robot = RobotModel::kinova_gen3_mobile();
    let base = robot.base().to_differential_drive();
    let robot = robot.with_base(base).unwrap();
    let planner = HierarchicalPlanner::new(robot, PlannerSettings::default()).unwrap();
    let model = super::counter_with_drawer(0.75);
    let problem = super::problem(
        &model,
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-1.1, 1.5, 0.0]\n",
    );
    let plan = solve(&planner, &model, &problem);
    let (driven, turned) = assert_no_sideways(planner.robot(), &plan);
    // The measure sees sideways motion: the straight SE(2) line from the start to the first
    // manipulation pose, timed per axis as a holonomic base would, slides across its heading.
    let start = problem.robot.base.unwrap();
    let end = plan.steps[0].base;
    let line = vec![start.to_vec(), end.to_vec()];
    let holonomic = time_parameterise(&line, &[0.5; 3], &[0.5; 3], Some(2)).unwrap();
    let (slide, _, _) = speeds(&holonomic);
    assert!(slide > 0.1, "{slide}");
    // The differential drive got there all the same, at least the straight line's length,
    // turning on the way.
    let straight = (end[0] - start[0]).hypot(end[1] - start[1]);
    assert!(
        driven >= straight - 1e-9 && turned > 0.1,
        "driven {driven} (straight {straight}), turned {turned}"
    );
    let report = recheck(&planner, &model, &problem.start, &plan).unwrap_or_else(|v| panic!("{v}"));
    eprintln!(
        "gen3 differential: drove {driven:.3} m (straight line {straight:.3} m), largest turn \
         {turned:.3} rad, base time {:.2} s; rechecked: {report}",
        plan.steps.iter().map(|s| s.timing.base).sum::<f64>()
    );
    assert!(report.contact_samples > 0, "{report}");
}

/// A cabinet (x in [0.06, 0.66], y in [-0.6, 0.6], 0.9 m high) with a drawer whose front
/// (x in [0.02, 0.04] closed, 0.4 m wide, 0.2 m tall, centred at z = 0.75) slides out along -x
/// (0 to 0.35 m; handle 0.03 m proud of the front's centre, normal -x), and in front of it a door
/// (x in [-0.03, -0.01] closed, y in [-0.3, 0.3], z in [0.25, 0.95]) hinged about the vertical
/// line x = -0.03, y = -0.3, opening to 2 rad by swinging its free edge into the room (-x), its
/// handle a vertical bar as `contact::counter_with_door_of`'s, 0.04 m from the free edge at
/// z = 0.6.
///
/// Closed, the door is 0.04 m in front of the drawer's front: sliding the drawer out 0.25 m
/// (front to x in [-0.21, -0.23]) runs it through the door. Open to 1.5 rad, the door's inner
/// face at x = -0.22 lies at y = -0.3 + 0.02 sin 1.5 + 0.19 cos 1.5 ≈ -0.267 (0.19 m along the
/// door), clear of the drawer (y >= -0.2).
pub(super) fn cabinet_with_door_and_drawer() -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(BaseShape::new(
        "cabinet",
        Shape::box_size(Vector3::new(0.6, 1.2, 0.9)),
        Isometry3::translation(0.36, 0.0, 0.45),
    ));
    b.add_part(
        PartSpec::on_base(
            "drawer",
            Joint::prismatic(
                "drawer_slide",
                Point3::new(0.03, 0.0, 0.75),
                -Vector3::x(),
                Limits::new(0.0, 0.35),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.02, 0.4, 0.2)),
            Isometry3::identity(),
        )
        .with_handle(Handle::new(
            "drawer_handle",
            Point3::new(-0.03, 0.0, 0.0),
            -Vector3::x(),
        )),
    );
    let width = 0.6;
    b.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "door_hinge",
                Point3::new(-0.03, -width / 2.0, 0.6),
                Vector3::z(),
                Limits::new(0.0, 2.0),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.02, width, 0.7)),
            Isometry3::translation(0.01, width / 2.0, 0.0),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.035, 0.012, 0.16)),
            Isometry3::translation(-0.0175, width - 0.04, 0.0),
        )
        .with_handle(Handle::new(
            "door_handle",
            Point3::new(-0.0175, width - 0.04, 0.0),
            -Vector3::x(),
        )),
    );
    b.build().expect("the cabinet is valid")
}

/// TIAGo's hand: every URDF link of the Hey5 hand (palm, thumb, fingers) and the box the
/// description puts around it (`hand_safety_box`), the geometry that may touch a grasped part.
fn tiago_hand(link: &str) -> bool {
    link.starts_with("hand_")
}

/// TIAGo as the crate ships its description (`robots/tiago.toml`): differential-drive base,
/// arm rooted at the torso, torso, head, wheels and hand frozen, stow computed, exemptions
/// sampled, the hand's links as the contact geometry; example-robot-data from the test's own
/// lookup.
fn tiago() -> RobotModel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/tiago.toml");
    let description = RobotDescription::from_file(&path).expect("the description parses");
    let data = example_robot_data();
    let vars = |name: &str| (name == "EXAMPLE_ROBOT_DATA").then(|| data.display().to_string());
    let robot = RobotModel::from_description(&description, path.parent().unwrap(), &vars)
        .expect("TIAGo's description loads");
    assert_eq!(robot.base().kind, BaseKind::DifferentialDrive);
    robot
}

#[test]
fn tiago_opens_the_door_then_the_drawer_without_moving_sideways() {
    let started = Instant::now();
    let robot = tiago();
    let geometry = RobotGeometry {
        urdf: example_robot_data().join("robots/tiago_description/robots/tiago.urdf"),
        packages: vec![("example-robot-data".into(), example_robot_data())],
        frozen: robot
            .frozen_joints()
            .iter()
            .map(|f| (f.name.clone(), f.value))
            .collect(),
        // The planner's rule. Only the fingers would be stricter, but TIAGo's description
        // encloses the hand in `hand_safety_box` (0.2 × 0.115 × 0.18 m, from the wrist to
        // 0.2 m out), which contains the grasp frame (0.13 m out): that box touches every
        // grasped handle (a run with the fingers alone stopped at the first approach, the box
        // touching the door).
        contact: |link, _| tiago_hand(link),
        // Self-contact is re-checked with the Gen3's SRDF only.
        srdf: None,
        grasp_self_clearance: 0.0,
    };
    let planner = HierarchicalPlanner::new(robot, PlannerSettings::default()).unwrap();
    let model = cabinet_with_door_and_drawer();
    let problem = super::problem(
        &model,
        "[goal]\ndoor_hinge = { min = 1.5 }\ndrawer_slide = { min = 0.25 }\n\
         [robot]\nbase = [-1.3, 0.5, 0.0]\n",
    );
    let plan = solve(&planner, &model, &problem);
    let planned = started.elapsed();
    let order: Vec<&str> = plan.steps.iter().map(|s| s.joint.as_str()).collect();
    let first_drawer = order.iter().position(|j| *j == "drawer_slide").unwrap();
    assert!(
        order[..first_drawer].contains(&"door_hinge"),
        "the door opens first: {order:?}"
    );
    let (driven, turned) = assert_no_sideways(planner.robot(), &plan);
    assert!(driven > 0.3, "{driven}");
    let report = recheck_robot(&geometry, &planner, &model, &problem.start, &plan)
        .unwrap_or_else(|v| panic!("{v}"));
    eprintln!(
        "tiago: planned in {:.1} s ({} steps {order:?}), drove {driven:.3} m, largest turn \
         {turned:.3} rad, base time {:.2} s; rechecked: {report}",
        planned.as_secs_f64(),
        plan.steps.len(),
        plan.steps.iter().map(|s| s.timing.base).sum::<f64>()
    );
    assert!(report.contact_samples > 0, "{report}");
}
