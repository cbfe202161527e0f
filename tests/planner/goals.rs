//! Shipped goal files planned with the shipped Gen3 and re-checked by the independent
//! re-checker of `contact.rs`: the 0.6 m cabinet door and the bottom-hinged oven door of
//! `examples/scenes/appliances.urdf`, each opened 90°.

use std::path::PathBuf;
use std::time::Instant;

use kinscene::scene::SceneModel;
use kinscene::scene::urdf::{ImportOptions, read_file};
use kinscene::task::Problem;

use super::contact::{recheck, solve, solve_with};

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/scenes")
}

/// The appliances scene and the goal file `goals/<name>.toml`.
fn appliance_goal(name: &str) -> (SceneModel, Problem) {
    let model = read_file(scenes().join("appliances.urdf"), &ImportOptions::default())
        .expect("the appliances scene loads");
    let goal = std::fs::read_to_string(scenes().join(format!("goals/{name}.toml")))
        .expect("the goal file exists");
    let problem = super::problem(&model, &goal);
    (model, problem)
}

/// Plans `name` and re-checks the plan: every step moves the goal's joint, the last to its
/// limit π/2 (the goal's minimum), and no sample breaks the contact rule.
fn planned_and_rechecked(name: &str, joint: &str) {
    let (model, problem) = appliance_goal(name);
    let started = Instant::now();
    let (planner, plan) = solve(&model, &problem);
    let planned = started.elapsed();
    assert!(
        plan.steps.iter().all(|s| s.joint == joint),
        "{:?}",
        plan.steps
    );
    assert!(
        plan.steps
            .last()
            .is_some_and(|s| s.to >= std::f64::consts::FRAC_PI_2 - 1e-9)
    );
    let report = recheck(&planner, &model, &problem.start, &plan).unwrap_or_else(|v| panic!("{v}"));
    eprintln!(
        "{name}: {} step(s), planned in {:.1} s: {report}",
        plan.steps.len(),
        planned.as_secs_f64()
    );
    assert!(report.contact_samples > 0);
}

#[test]
fn a_wide_cabinet_door_opens_90_degrees_with_the_gen3() {
    planned_and_rechecked("wide_door", "cabinet_door_hinge");
}

#[test]
fn an_oven_door_opens_flat_with_the_gen3() {
    planned_and_rechecked("oven", "oven_door_hinge");
}

/// With an approach cone of 0.3 rad (`ManipulationSettings::approach_cone`), the counter drawer
/// (handle facing −x, so the approach is +x) is planned, the tool's +z stays within 0.3 rad
/// (plus the rotation tolerance) of +x at every manipulation sample by the robot's FK, and the
/// independent re-checker accepts the plan.
#[test]
fn an_approach_cone_keeps_the_tool_within_it_and_the_contact_rule() {
    use kinscene::kinematics::robot::{RobotConfig, RobotModel};
    use kinscene::planner::{HierarchicalPlanner, PlannerSettings};
    use nalgebra::{DVector, Vector3};

    let mut settings = PlannerSettings::default();
    settings.placement.manipulation.approach_cone = 0.3;
    let tolerance = settings.placement.manipulation.rotation_tolerance;
    let robot = RobotModel::kinova_gen3_mobile();
    let planner = HierarchicalPlanner::new(robot.clone(), settings).unwrap();
    let model = super::counter_with_drawer(0.75);
    let problem = super::problem(
        &model,
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let (planner, plan) = solve_with(planner, &model, &problem);
    let mut largest: f64 = 0.0;
    for step in &plan.steps {
        for q in &step.manipulation.positions {
            let tool = robot
                .world_from_tool(&RobotConfig {
                    base: step.base,
                    arm: DVector::from_column_slice(q),
                })
                .unwrap();
            largest = largest.max((tool.rotation * Vector3::z()).angle(&Vector3::x()));
        }
    }
    assert!(largest <= 0.3 + tolerance, "tool tilted {largest} rad");
    let report = recheck(&planner, &model, &problem.start, &plan).unwrap_or_else(|v| panic!("{v}"));
    eprintln!("cone: largest tilt {largest:.3} rad; {report}");
    assert!(report.contact_samples > 0);
}
