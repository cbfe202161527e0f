//! The arm's reach bound the planner hands the task layer (`kinscene::planner::arm_reach`):
//! sound (it never rules out a grasp the arm holds) and tight enough to rule out at once what
//! the arm cannot do.

use std::f64::consts::PI;
use std::time::Duration;

use kinscene::kinematics::pinocchio::{Data, forward_kinematics, frame_placement};
use kinscene::kinematics::robot::RobotModel;
use kinscene::planner::{MotionInfeasibility, MotionOutcome, arm_reach};
use kinscene::task::Termination;
use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The shoulder-to-wrist span of the shipped Gen3, from its URDF alone: the wrist point is
/// Actuator6's origin (on Actuator7's axis), the shoulder Actuator2's (on Actuator1's vertical
/// axis), so the span is the sum of the lengths of the `<origin xyz>` of Actuator3 to
/// Actuator6 in robots/kinova_gen3_mobile.urdf.
fn gen3_span_from_the_urdf() -> f64 {
    let urdf = urdf_rs::read_file(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/kinova_gen3_mobile.urdf"),
    )
    .unwrap();
    ["Actuator3", "Actuator4", "Actuator5", "Actuator6"]
        .iter()
        .map(|name| {
            let j = urdf.joints.iter().find(|j| j.name == *name).unwrap();
            let [x, y, z] = *j.origin.xyz;
            (x * x + y * y + z * z).sqrt()
        })
        .sum()
}

#[test]
fn the_reach_bound_never_rules_out_a_grasp_the_arm_holds() {
    // 3000 random configurations of the Gen3 (continuous joints in [-π, π]); the tool pose by
    // Pinocchio's forward kinematics (not the bound's code, which composes the URDF origins);
    // the grasp point behind the tool origin by 0, half and all of the standoff range along
    // the approach, its outward normal against the approach. Held from the base at the origin
    // (yaw 0), so the bound's span from (0, 0) must not exceed its radius.
    let robot = RobotModel::kinova_gen3_mobile();
    let standoff = 0.035;
    let reach = arm_reach(&robot, standoff);
    assert!(
        (reach.radius - gen3_span_from_the_urdf()).abs() < 1e-9,
        "{reach:?}"
    );
    let pin = robot.pinocchio();
    let mut data = Data::new(pin).unwrap();
    let (lower, upper) = robot.arm_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut tightest = 0.0f64;
    for _ in 0..3000 {
        let q = DVector::from_fn(robot.dof(), |i, _| {
            rng.random_range(lower[i].max(-PI)..upper[i].min(PI))
        });
        forward_kinematics(pin, &mut data, &q).unwrap();
        let tool = frame_placement(pin, &data, robot.tool_frame()).unwrap();
        let normal = -(tool.rotation * nalgebra::Vector3::z());
        for s in [0.0, 0.5 * standoff, standoff] {
            let grasp = tool.translation.vector - normal * s;
            let span = reach.span([0.0, 0.0], &grasp.into(), &normal);
            assert!(
                span <= reach.radius + 1e-9,
                "q {q:?}: span {span} > radius {}",
                reach.radius
            );
            tightest = tightest.max(span / reach.radius);
        }
    }
    eprintln!("reach bound: largest span over radius at a held grasp {tightest:.3}");
    // The bound is not slack everywhere: some configuration comes close to it.
    assert!(tightest > 0.95, "{tightest}");
}

#[test]
fn a_handle_out_of_reach_is_infeasible_at_the_task_level_with_the_numbers() {
    // A drawer handle 1.99 m high, inside the task level's default height band (up to 2 m),
    // 0.05 m in front of a 0.9 m counter. The Gen3's shoulder (Actuator2's origin) is 0.685 m
    // above the floor (URDF: mount 0.40 + 0.15643 + 0.12838) and its wrist point 0.3675 m
    // behind the tool along the approach (0.20 + 0.0615 + 0.10593), so holding the horizontal
    // handle puts the wrist 1.305 m above the shoulder: more than the 0.735 m span, from any
    // base pose. The task layer rules it out before any motion is planned.
    let model = super::counter_with_drawer(1.99);
    let problem = super::problem(
        &model,
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let result = super::planner()
        .plan(
            &model,
            &problem,
            &Termination::after(Duration::from_secs(60)),
        )
        .expect("valid input");
    let MotionOutcome::Infeasible(MotionInfeasibility { vetoes, task }) = &result.outcome else {
        panic!("expected infeasible, got {:?}", result.outcome);
    };
    assert!(vetoes.is_empty(), "{vetoes:?}");
    assert_eq!(result.task_plans, 1, "one task search, no order to refine");
    let reason = &task.message;
    let radius = format!("{:.3} m", gen3_span_from_the_urdf());
    assert!(
        reason.contains("drawer_slide") && reason.contains(&radius),
        "{reason}"
    );
    // The span it reports is at least the vertical distance less the standoff range and the
    // slack (1.305 − 0.035 − 0.002).
    let span: f64 = reason
        .split("at least ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no span in {reason}"));
    assert!(span >= 1.268, "{reason}");
}

#[test]
fn the_gen3_plans_a_kitchen_goal_within_its_reach_and_the_plan_rechecks() {
    // examples/scenes/goals/sink_and_drawers.toml: two drawers and the sink door, handles 0.5
    // to 0.9 m high. Planned with the shipped robot, and every phase re-checked by the
    // independent checker of `contact.rs` (urdf-rs + Pinocchio placements + parry, the grasp
    // contact rule).
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = kinscene::scene::urdf::read_file(
        root.join("examples/scenes/kitchen.urdf"),
        &kinscene::scene::urdf::ImportOptions::default(),
    )
    .unwrap();
    let text =
        std::fs::read_to_string(root.join("examples/scenes/goals/sink_and_drawers.toml")).unwrap();
    let problem = super::problem(&model, &text);
    let planner = super::planner();
    let result = planner
        .plan(
            &model,
            &problem,
            &Termination::after(Duration::from_secs(120)),
        )
        .expect("valid input");
    let MotionOutcome::Solved(plan) = &result.outcome else {
        panic!("expected a plan, got {:?}", result.outcome);
    };
    let joints: Vec<&str> = plan.steps.iter().map(|s| s.joint.as_str()).collect();
    for goal in [
        "island_drawer_left_slide",
        "sink_door_hinge",
        "drawer_top_slide",
    ] {
        assert!(joints.contains(&goal), "{joints:?}");
    }
    let report = super::contact::recheck(&planner, &model, &problem.start, plan)
        .unwrap_or_else(|v| panic!("{v}"));
    eprintln!("sink and drawers: {report}");
}
