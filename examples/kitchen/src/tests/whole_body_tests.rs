//! The simulator executing a whole-body step: the planner's plan for a 0.6 m cabinet door on a
//! counter opened 90°, which no single base pose of the Gen3 covers (the scene and reasoning
//! of the planner's tests, tests/planner/whole_body.rs and segments.rs), with one segment and
//! whole-body manipulation on, so that the one step moves the base with the arm.
//!
//! Checked by the simulator, which shares no code with the planner's checks: rapier3d physics
//! drags the door by the grasp spring along its true hinge, and the robot's links (base
//! included) are checked against the scene with parry3d. The expected joint value is the
//! goal's (90°); the expected end pose is the plan's last manipulation base pose.

use std::f64::consts::FRAC_PI_2;
use std::time::Duration;

use kinscene::discovery::Hardware;
use kinscene::kinematics::robot::RobotModel;
use kinscene::motion::placement::WholeBodySettings;
use kinscene::planner::{HierarchicalPlanner, MotionOutcome, PlannerSettings, StepMode};
use kinscene::scene::{
    BaseShape, Handle, Joint, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape,
};
use kinscene::task::{GoalSpec, LatticeSettings, Problem, TaskSettings, Termination};
use nalgebra::{Isometry2, Isometry3, Point3, Vector2, Vector3};

use crate::report::svg::top_view;
use crate::sim::{SimSettings, SimWorld};

/// The start pose: 0.9 m in front of the counter, facing it.
const START: [f64; 3] = [-0.9, 0.0, 0.0];

/// A 0.9 m counter (front face x = 0) with a 0.6 m door hinged at its right edge (y = -0.3),
/// opening to 90° into the room; its handle bar 4 cm from the free edge at half height. The
/// geometry of tests/planner/contact.rs's `counter_with_door_of(0.6, π/2)`.
fn wide_door() -> SceneModel {
    let (width, half) = (0.6, 0.3);
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(BaseShape::new(
        "counter",
        Shape::box_size(Vector3::new(0.6, 2.0, 0.9)),
        Isometry3::translation(0.3, 0.0, 0.45),
    ));
    b.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "door_hinge",
                Point3::new(-0.03, -half, 0.5),
                Vector3::z(),
                Limits::new(0.0, FRAC_PI_2),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.02, width, 0.7)),
            Isometry3::translation(0.01, half, 0.0),
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
    b.build().expect("the test scene is valid")
}

/// The planner's plan for opening the door to 90° from [`START`] with one segment and
/// whole-body manipulation on (a lattice without interior values: the one move 0 → 90°).
fn whole_body_plan(model: &SceneModel) -> kinscene::planner::MotionPlan {
    let settings = PlannerSettings {
        task: TaskSettings {
            lattice: LatticeSettings { interior_values: 0 },
            ..TaskSettings::default()
        },
        max_segments: 1,
        whole_body: Some(WholeBodySettings::default()),
        ..PlannerSettings::default()
    };
    let planner = HierarchicalPlanner::new(RobotModel::kinova_gen3_mobile(), settings)
        .expect("the shipped robot builds");
    let spec = GoalSpec::from_toml(
        "[goal]\ndoor_hinge = { min = 1.5707963267948966 }\n\
         [robot]\nbase = [-0.9, 0.0, 0.0]\n",
    )
    .expect("goal parses");
    let problem = Problem::from_spec(model, &spec).expect("goal fits the scene");
    let result = planner
        .plan(
            model,
            &problem,
            &Termination::after(Duration::from_secs(300)),
        )
        .expect("valid input");
    match result.outcome {
        MotionOutcome::Solved(plan) => plan,
        other => panic!("expected a plan, got {other:?}"),
    }
}

fn world_at_start(model: &SceneModel) -> SimWorld {
    SimWorld::new(
        model,
        &RobotModel::kinova_gen3_mobile(),
        Isometry2::new(Vector2::new(START[0], START[1]), START[2]),
        SimSettings::default(),
    )
    .expect("the simulator builds on the counter")
}

#[test]
fn whole_body_step_opens_the_wide_door_in_the_simulator() {
    let model = wide_door();
    let plan = whole_body_plan(&model);
    assert_eq!(plan.steps.len(), 1, "one grasp, one step");
    let step = &plan.steps[0];
    assert_eq!(step.mode, StepMode::WholeBody);
    let end = step.end_base();

    let mut world = world_at_start(&model);
    let done = world.execute(&plan);
    let hinge = world
        .true_state()
        .value_by_name(&model, "door_hinge")
        .expect("known joint");
    let at = world.base_pose();
    println!(
        "whole-body door: planned 0 -> {FRAC_PI_2:.4} rad, reached {hinge:.4} rad; base ends at \
         ({:.3}, {:.3}, {:.3}), planned {end:?}; failure {:?}",
        at.translation.x,
        at.translation.y,
        at.rotation.angle(),
        done.failure
    );
    assert_eq!(done.failure, None, "the simulator reports no collision");
    assert!(
        (hinge - FRAC_PI_2).abs() < 0.02,
        "the door ended at {hinge} rad, planned {FRAC_PI_2}"
    );
    // The robot ends where the manipulation's base poses end (the retreat does not move it).
    let off = (at.translation.x - end[0]).hypot(at.translation.y - end[1]);
    assert!(off < 1e-9, "base {off} m from the plan's end pose");
    assert!((at.rotation.angle() - end[2]).abs() < 1e-9);
    // The base moved during the manipulation: the trace has poses between the manipulation's
    // first and last pose (the first is where the base path ends).
    let moved = (end[0] - step.base[0]).hypot(end[1] - step.base[1]);
    assert!(moved > 0.05, "the plan's base moves {moved} m");
    // Time: the manipulation counts as arm time, the base's share is not added to base time.
    let exec = &done.steps[0];
    assert!((exec.arm_time - step.timing.arm()).abs() < 1e-9);
    assert!((exec.base_time - step.timing.base).abs() < 1e-9);
    // The executed trace follows the base during the manipulation: a pose within 1 cm of
    // the end pose, beyond where the base path ended.
    let trace = world.base_trace();
    assert!(
        trace
            .iter()
            .any(|p| { (p.translation.x - end[0]).hypot(p.translation.y - end[1]) < 0.01 }),
        "the trace never reaches the end pose"
    );
    // The top view draws the manipulation's base trail and its end pose once.
    let doc = top_view(&model, &model.zero_state(), Some(&plan), trace, "door").expect("draws");
    assert_eq!(doc.matches(r#"class="manipulation-base""#).count(), 1);
    assert_eq!(doc.matches(r#"class="manipulation-end""#).count(), 1);
}

#[test]
fn whole_body_step_with_the_base_held_still_does_not_open_the_door() {
    // Control: the same step with the base standing at the manipulation's first pose
    // throughout (no base poses): the arm's configurations were computed for a moving base,
    // so the tool leaves the handle's arc and the door does not reach 90°.
    let model = wide_door();
    let mut plan = whole_body_plan(&model);
    plan.steps[0].manipulation_base = None;
    let mut world = world_at_start(&model);
    let done = world.execute(&plan);
    let hinge = world
        .true_state()
        .value_by_name(&model, "door_hinge")
        .expect("known joint");
    println!(
        "base held still: reached {hinge:.4} rad of {FRAC_PI_2:.4}; failure {:?}",
        done.failure
    );
    assert!(
        done.failure.is_some() || (hinge - FRAC_PI_2).abs() > 0.1,
        "without the base moving the door reached {hinge} rad and nothing failed"
    );
}
