//! Plan a scene URDF and a goal file with a robot, and print the plan: the example to read
//! first. It uses the front door (`kinscene::prelude`) alone.
//!
//! ```text
//! cargo run --release --example plan -- SCENE.urdf GOAL.toml [ROBOT.urdf TOOL_LINK [ROBOT.srdf]]
//! cargo run --release --example plan -- examples/scenes/counter.urdf \
//!     examples/scenes/goals/counter_drawer.toml
//! ```
//!
//! Without a robot URDF it plans for the shipped Kinova Gen3 on its omnidirectional base. A
//! robot URDF is loaded as it ships (meshes as convex hulls); its allowed collision pairs and
//! stowed configuration come from the SRDF when one is given, else they are computed (sampled
//! pairs, a compact self-collision-free stow). The motion document goes to `plan.json`.

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use kinscene::kinematics::robot::{PairSampling, Srdf, StowSearch};
use kinscene::prelude::*;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if !(args.len() == 2 || args.len() == 4 || args.len() == 5) {
        eprintln!("usage: plan SCENE.urdf GOAL.toml [ROBOT.urdf TOOL_LINK [ROBOT.srdf]]");
        return ExitCode::from(2);
    }
    match run(&args) {
        Ok(solved) if solved => ExitCode::SUCCESS,
        Ok(_) => ExitCode::from(3),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// Plans, prints and writes the plan; whether it was solved.
fn run(args: &[String]) -> Result<bool, Box<dyn std::error::Error>> {
    let scene = SceneModel::from_urdf_file(&args[0])?;
    let problem = Problem::from_goal_file(&scene, &args[1])?;
    let robot = match args.get(2) {
        None => RobotModel::kinova_gen3_mobile(),
        Some(urdf) => load_robot(Path::new(urdf), &args[3], args.get(4).map(Path::new))?,
    };
    println!(
        "scene: {} joints; robot: {} ({} arm joints)",
        scene.joints().len(),
        robot.name(),
        robot.dof()
    );

    // The default settings are seeded: the same input gives the same plan. The minute is a
    // safety net, not what decides the result.
    let planner = HierarchicalPlanner::new(robot, PlannerSettings::default())?;
    let result = planner.plan(
        &scene,
        &problem,
        &Termination::after(Duration::from_secs(60)),
    )?;
    let document = MotionDocument::from_result(&result, planner.robot().name());
    std::fs::write("plan.json", document.to_json())?;

    match &result.outcome {
        Outcome::Solved(plan) => {
            println!(
                "solved in {:.1} s: {} steps, {:.1} s to execute",
                result.task_time + result.motion_time,
                plan.steps.len(),
                plan.duration()
            );
            for (i, step) in plan.steps.iter().enumerate() {
                let [x, y, yaw] = step.base;
                println!(
                    "  {}. {} {:.3} -> {:.3} by {}: base at ({x:.2}, {y:.2}, {yaw:.2} rad), \
                     base {:.1} s, arm {:.1} s, {} arm configurations along the handle",
                    i + 1,
                    step.joint,
                    step.from,
                    step.to,
                    step.handle,
                    step.timing.base,
                    step.timing.arm(),
                    step.manipulation.positions.len()
                );
            }
            println!("motion document: plan.json");
            Ok(true)
        }
        Outcome::Infeasible(why) => {
            println!("infeasible: {why}");
            Ok(false)
        }
        Outcome::Timeout(progress) | Outcome::Cancelled(progress) => {
            println!("no plan within the budget: {progress}");
            Ok(false)
        }
    }
}

/// A robot URDF as it ships, with its SRDF if given.
fn load_robot(
    urdf: &Path,
    tool_link: &str,
    srdf: Option<&Path>,
) -> Result<RobotModel, Box<dyn std::error::Error>> {
    let options = RobotImportOptions {
        tool_link: tool_link.to_string(),
        ..RobotImportOptions::default()
    };
    let robot = RobotModel::from_urdf_file_with(urdf, &options)?;
    Ok(match srdf {
        Some(path) => {
            let srdf = Srdf::from_file(path)?;
            let described = robot.with_srdf(&srdf)?;
            match srdf.stow_state() {
                Some(_) => described,
                None => described.with_computed_stow(&StowSearch::default())?,
            }
        }
        None => robot
            .with_computed_stow(&StowSearch::default())?
            .with_sampled_pairs(&PairSampling::default())?,
    })
}
