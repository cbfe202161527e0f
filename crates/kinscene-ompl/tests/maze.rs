//! A 10 m × 10 m maze in a 2-D real vector space (disc robot) and in SE(2) (a two-disc robot
//! whose footprint turns with yaw), solved with RRTConnect and re-validated densely.
//!
//! Soundness margin: OMPL checks a motion at states at most `h = resolution × extent` apart
//! (DiscreteMotionValidator). Between two checked states every robot point moves at most
//! `max(1, 2L)·h` (SE(2) distance is `‖Δxy‖ + 0.5·|Δyaw|` and a point at offset L moves
//! `‖Δxy‖ + L·|Δyaw|`), so any intermediate configuration is within `max(1, 2L)·h/2` of a checked
//! one. The planner's checker therefore demands clearance `radius + MARGIN` with
//! `MARGIN ≥ max(1, 2L)·h/2`, and the re-validation demands just `radius`: it cannot fail unless
//! OMPL returned a motion it did not check at the stated resolution (e.g. through a wall).

use std::time::Duration;

use kinscene_ompl::{PlanSettings, PlanStatus, Problem, StateSpace, Termination, plan};

use crate::common::{
    Rect, assert_path_valid, clearance, distance, extent, first_violation, serial,
};

const RESOLUTION: f64 = 0.005;
/// SE(2) extent is 10·√2 + π/2 = 15.71, so h = 0.0786 and h/2 = 0.039 (2L = 0.8 < 1).
const MARGIN: f64 = 0.05;
const RADIUS: f64 = 0.15;
const ARM: f64 = 0.4;
const ARM_RADIUS: f64 = 0.1;

/// Three 0.2 m thick walls: the way from (1, 1) to (8, 8) zig-zags through a gap on the right,
/// a gap on the left, then over the top of a vertical wall.
fn walls() -> Vec<Rect> {
    vec![
        Rect {
            min: [0.0, 2.9],
            max: [7.0, 3.1],
        },
        Rect {
            min: [3.0, 5.9],
            max: [10.0, 6.1],
        },
        Rect {
            min: [4.9, 6.1],
            max: [5.1, 8.5],
        },
    ]
}

fn disc_valid(walls: &[Rect], q: &[f64], margin: f64) -> bool {
    clearance(walls, [q[0], q[1]]) >= RADIUS + margin
}

fn two_disc_valid(walls: &[Rect], q: &[f64], margin: f64) -> bool {
    let tip = [q[0] + ARM * q[2].cos(), q[1] + ARM * q[2].sin()];
    clearance(walls, [q[0], q[1]]) >= RADIUS + margin
        && clearance(walls, tip) >= ARM_RADIUS + margin
}

fn solve_and_check(problem: &Problem, valid: impl Fn(&[f64], f64) -> bool + Sync) {
    let _serial = serial();
    // The straight line is blocked, so a solution must actually go around the walls.
    let straight = [problem.start.clone(), problem.goal.clone()];
    assert!(first_violation(&problem.space, &straight, |q| valid(q, 0.0)).is_some());
    assert!(MARGIN >= RESOLUTION * extent(&problem.space) / 2.0);

    let settings = PlanSettings {
        resolution_fraction: RESOLUTION,
        ..PlanSettings::default()
    };
    let checker = |q: &[f64]| valid(q, MARGIN);
    let outcome = plan(
        problem,
        &checker,
        &settings,
        Termination::after(Duration::from_secs(10)),
    )
    .expect("planning runs");
    assert_eq!(outcome.status, PlanStatus::ExactSolution);
    assert_eq!(outcome.checker_panics, 0);
    let path = &outcome.path;
    assert!(
        path.len() >= 3,
        "a blocked straight line needs a via state: {path:?}"
    );
    // OMPL copies the start state: equal bit for bit (yaw 0 is already in [-π, π]).
    assert_eq!(path[0], problem.start);
    // The last state is within the goal tolerance (OMPL's distance, re-implemented).
    let to_goal = distance(&problem.space, path.last().unwrap(), &problem.goal);
    assert!(
        to_goal <= problem.goal_tolerance,
        "last state {to_goal} from the goal"
    );
    assert!((outcome.goal_distance.unwrap() - to_goal).abs() <= 1e-12);
    assert_path_valid(&problem.space, path, |q| valid(q, 0.0));
}

#[test]
fn maze_real_vector_disc_robot() {
    let space = StateSpace::RealVector {
        lower: vec![0.0; 2],
        upper: vec![10.0; 2],
    };
    let walls = walls();
    solve_and_check(
        &Problem::new(space, vec![1.0, 1.0], vec![8.0, 8.0]),
        |q, m| disc_valid(&walls, q, m),
    );
}

#[test]
fn maze_se2_two_disc_robot() {
    let space = StateSpace::Se2 {
        x: [0.0, 10.0],
        y: [0.0, 10.0],
    };
    let walls = walls();
    let problem = Problem::new(space, vec![1.0, 1.0, 0.0], vec![8.0, 8.0, 3.0]);
    solve_and_check(&problem, |q, m| two_disc_valid(&walls, q, m));
}
