//! Whole-body manipulation at the motion layer on the kitchen: for each door given (default:
//! the two corner doors), the sampled placement of the Gen3 from the kitchen's start pose, and,
//! when that one base pose does not reach every waypoint, the whole-body plan from its base
//! pose ([`plan_whole_body`]). Prints what each reaches and why not.
//!
//! ```text
//! cargo run --example whole_body -- [JOINT HANDLE TO]...
//! ```

use std::f64::consts::FRAC_PI_2;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use kinscene::Termination;
use kinscene::kinematics::ik::{IkSettings, IkSolver};
use kinscene::kinematics::robot::{RobotCollision, RobotModel};
use kinscene::motion::placement::{
    GraspRotation, PlacementData, PlacementMethod, PlacementProblem, PlacementSettings,
    WholeBodyOutcome, WholeBodySettings, place_and_plan, plan_whole_body,
};
use kinscene::scene::urdf::{self, ImportOptions};

/// The kitchen goals' robot start (examples/scenes/goals/corner.toml).
const START: [f64; 3] = [1.0, 0.0, FRAC_PI_2];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let doors: Vec<(String, String, f64)> = if args.is_empty() {
        vec![
            (
                "corner_door_back_hinge".into(),
                "corner_door_back_handle".into(),
                FRAC_PI_2,
            ),
            (
                "corner_door_side_hinge".into(),
                "corner_door_side_handle".into(),
                FRAC_PI_2,
            ),
        ]
    } else if args.len() % 3 == 0 {
        args.chunks(3)
            .map(|c| (c[0].clone(), c[1].clone(), c[2].parse().unwrap_or(f64::NAN)))
            .collect()
    } else {
        eprintln!("usage: whole_body [JOINT HANDLE TO]...");
        return ExitCode::from(2);
    };
    match run(&doors) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("whole_body: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(doors: &[(String, String, f64)]) -> Result<(), Box<dyn std::error::Error>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/kitchen.urdf");
    let model = urdf::read_file(path, &ImportOptions::default())?;
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot)?;
    let ik = IkSolver::for_robot(&robot, IkSettings::default())?;
    let state = model.zero_state();
    let problem = PlacementProblem {
        robot: &robot,
        collision: &collision,
        ik: &ik,
        model: &model,
        state: &state,
    };
    let settings = PlacementSettings {
        method: PlacementMethod::Sampled,
        stow: Some(robot.neutral()),
        ..PlacementSettings::default()
    };
    for (joint, handle, to) in doors {
        let (Ok(j), Ok(h)) = (model.joint_id(joint), model.handle_id(handle)) else {
            println!("{joint}: unknown joint or handle {handle:?}");
            continue;
        };
        let started = Instant::now();
        let placement = place_and_plan(
            problem,
            j,
            h,
            *to,
            START,
            &settings,
            &mut PlacementData::new(),
            &Termination::none(),
        )?;
        println!(
            "{joint}: one base pose {:?} reaches {} of {} waypoints ({:.1} s){}",
            placement.base.map(|v| (v * 1000.0).round() / 1000.0),
            placement.reached.iter().filter(|r| **r).count(),
            placement.reached.len(),
            started.elapsed().as_secs_f64(),
            placement
                .reason
                .as_ref()
                .map(|r| format!(": {r}"))
                .unwrap_or_default()
        );
        if placement.is_complete() || !placement.reached[0] {
            continue;
        }
        let started = Instant::now();
        let outcome = plan_whole_body(
            problem,
            &placement.motion,
            placement.base,
            &placement.arm[0],
            GraspRotation::Free,
            &settings.manipulation,
            &WholeBodySettings::default(),
        )?;
        let seconds = started.elapsed().as_secs_f64();
        match &outcome {
            WholeBodyOutcome::Tracked(plan) => println!(
                "{joint}: whole-body tracks every waypoint ({seconds:.3} s): the base moves at \
                 {} of {} waypoints, {:.3} m, ends at {:?}",
                plan.base_moves(),
                plan.bases.len(),
                plan.base_travel(),
                plan.bases
                    .last()
                    .map(|b| b.map(|v| (v * 1000.0).round() / 1000.0))
            ),
            failed => println!(
                "{joint}: {} ({seconds:.3} s)",
                failed.reason().unwrap_or_default()
            ),
        }
    }
    Ok(())
}
