//! Whole-body manipulation at the motion layer on the kitchen: for each door given (default:
//! the two corner doors to 1.4 rad), the sampled longest-prefix placement of the Gen3 from the
//! kitchen's start pose, and, when that one base pose does not reach every waypoint, whole-body
//! plans from its best samples and several arm seeds each
//! ([`plan_whole_body_from_starts`], [`WholeBodySettings::starts`] and
//! [`WholeBodySettings::arm_seeds`]). Prints, per attempt, the start used, the waypoints
//! reached and why not, and for the tracked one the base travel.
//!
//! ```text
//! cargo run --example whole_body -- [--starts N] [--arm-seeds M] [--cone RAD] [--turn RAD]
//!     [JOINT HANDLE TO]...
//! ```
//!
//! `--starts` and `--arm-seeds` override [`WholeBodySettings::starts`] and
//! [`WholeBodySettings::arm_seeds`] (defaults 4 and 3), `--cone` the manipulation's
//! `approach_cone` (default 0), `--turn` the placement's
//! [`bar_turn`](PlacementSettings::bar_turn) (default 0: the grasp along the handle's
//! normal; the placement line then names the grasp angle it kept).

use std::f64::consts::FRAC_PI_2;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use kinscene::Termination;
use kinscene::kinematics::ik::{IkSettings, IkSolver};
use kinscene::kinematics::robot::{RobotCollision, RobotModel};
use kinscene::motion::placement::{
    GraspRotation, ManipulationSettings, PlacementData, PlacementMethod, PlacementObjective,
    PlacementProblem, PlacementSettings, SamplingSettings, WholeBodyOutcome, WholeBodySettings,
    WholeBodyStart, place_and_plan, plan_whole_body_from_starts,
};
use kinscene::scene::urdf::{self, ImportOptions};

/// The kitchen goals' robot start (examples/scenes/goals/corner.toml).
const START: [f64; 3] = [1.0, 0.0, FRAC_PI_2];

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut whole_body = WholeBodySettings::default();
    let mut cone = 0.0;
    let mut turn = 0.0;
    while args.len() >= 2 && args[0].starts_with("--") {
        let (count, angle) = (args[1].parse().ok(), args[1].parse().ok());
        match (args[0].as_str(), count, angle) {
            ("--starts", Some(n), _) => whole_body.starts = n,
            ("--arm-seeds", Some(n), _) => whole_body.arm_seeds = n,
            ("--cone", _, Some(a)) => cone = a,
            ("--turn", _, Some(a)) => turn = a,
            _ => {
                eprintln!("whole_body: bad option {} {}", args[0], args[1]);
                return ExitCode::from(2);
            }
        }
        args.drain(..2);
    }
    let doors: Vec<(String, String, f64)> = if args.is_empty() {
        vec![
            (
                "corner_door_back_hinge".into(),
                "corner_door_back_handle".into(),
                1.4,
            ),
            (
                "corner_door_side_hinge".into(),
                "corner_door_side_handle".into(),
                1.4,
            ),
        ]
    } else if args.len() % 3 == 0 {
        args.chunks(3)
            .map(|c| (c[0].clone(), c[1].clone(), c[2].parse().unwrap_or(f64::NAN)))
            .collect()
    } else {
        eprintln!(
            "usage: whole_body [--starts N] [--arm-seeds M] [--cone RAD] [--turn RAD] \
             [JOINT HANDLE TO]..."
        );
        return ExitCode::from(2);
    };
    match run(&doors, &whole_body, cone, turn) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("whole_body: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(
    doors: &[(String, String, f64)],
    whole_body: &WholeBodySettings,
    cone: f64,
    turn: f64,
) -> Result<(), Box<dyn std::error::Error>> {
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
        manipulation: ManipulationSettings {
            approach_cone: cone,
            ..ManipulationSettings::default()
        },
        sampling: SamplingSettings {
            objective: PlacementObjective::LongestPrefix,
            keep: whole_body.starts,
            ..SamplingSettings::default()
        },
        bar_turn: turn,
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
            "{joint}: one base pose {:?}, grasp turned {:.3} rad about the bar, reaches {} of {} \
             waypoints ({:.1} s){}",
            placement.base.map(|v| (v * 1000.0).round() / 1000.0),
            placement.motion.grasp_angle,
            placement.reached.iter().filter(|r| **r).count(),
            placement.reached.len(),
            started.elapsed().as_secs_f64(),
            placement
                .reason
                .as_ref()
                .map(|r| format!(": {r}"))
                .unwrap_or_default()
        );
        if placement.is_complete() {
            continue;
        }
        let starts: Vec<WholeBodyStart> = placement
            .ranked
            .iter()
            .filter(|p| p.reached_prefix() > 0)
            .map(|p| WholeBodyStart {
                base: p.base,
                seed: p.arm[0].clone(),
            })
            .collect();
        let started = Instant::now();
        let attempts = plan_whole_body_from_starts(
            problem,
            &placement.motion,
            &starts,
            GraspRotation::Free,
            &settings.manipulation,
            whole_body,
            &Termination::none(),
        )?;
        let seconds = started.elapsed().as_secs_f64();
        for a in &attempts {
            println!(
                "{joint}:   start {}: {} waypoints reached; {}",
                a.start,
                a.reached(),
                a.summary()
            );
        }
        match attempts.last().map(|a| (a, &a.outcome)) {
            Some((a, WholeBodyOutcome::Tracked(plan))) => println!(
                "{joint}: whole-body tracks every waypoint from start {} arm seed {} \
                 ({} attempts, {seconds:.1} s): the base moves at {} of {} waypoints, {:.3} m, \
                 ends at {:?}",
                a.start,
                a.arm_seed,
                attempts.len(),
                plan.base_moves(),
                plan.bases.len(),
                plan.base_travel(),
                plan.bases
                    .last()
                    .map(|b| b.map(|v| (v * 1000.0).round() / 1000.0))
            ),
            _ => println!(
                "{joint}: no whole-body plan from {} starts ({} attempts, {seconds:.1} s); \
                 furthest waypoint {}",
                starts.len(),
                attempts.len(),
                attempts.iter().map(|a| a.reached()).max().unwrap_or(0)
            ),
        }
    }
    Ok(())
}
