//! The motion validator: a wall of zero thickness (no state is in collision) that only a
//! motion check sees, and panics inside the validator.

use std::time::Duration;

use kinscene_ompl::{
    PlanSettings, PlanStatus, Problem, StateSpace, Termination, plan, plan_with_motion,
};

use crate::common::serial;

/// The wall: the segment x = 0.5, y ≤ 0.8 of the unit square.
const WALL_X: f64 = 0.5;
const GAP_Y: f64 = 0.8;

/// Whether the straight segment a → b meets the wall (touching counts), by the intersection
/// with the line x = 0.5.
fn crosses_wall(a: &[f64], b: &[f64]) -> bool {
    let (da, db) = (a[0] - WALL_X, b[0] - WALL_X);
    if da * db > 0.0 {
        return false;
    }
    if da == db {
        // Both on the wall's line.
        return a[1].min(b[1]) <= GAP_Y;
    }
    let t = da / (da - db);
    a[1] + t * (b[1] - a[1]) <= GAP_Y
}

fn problem() -> Problem {
    let space = StateSpace::RealVector {
        lower: vec![0.0; 2],
        upper: vec![1.0; 2],
    };
    Problem::new(space, vec![0.1, 0.2], vec![0.9, 0.2])
}

#[test]
fn the_motion_validator_keeps_paths_off_a_wall_the_discrete_check_jumps() {
    let _serial = serial();
    kinscene_ompl::set_seed(7).unwrap();
    let every_state = |_: &[f64]| true;
    let budget = Termination::after(Duration::from_secs(2));
    let settings = PlanSettings::default();
    // Without a motion validator the states decide, and no state is on a zero-thickness wall:
    // the straight start-goal motion is accepted, through the wall.
    let discrete = plan(&problem(), &every_state, &settings, budget).unwrap();
    assert!(discrete.is_exact());
    assert!(discrete.path.windows(2).any(|w| crosses_wall(&w[0], &w[1])));

    let motion = |a: &[f64], b: &[f64]| !crosses_wall(a, b);
    let certified =
        plan_with_motion(&problem(), &every_state, Some(&motion), &settings, budget).unwrap();
    assert!(certified.is_exact(), "{:?}", certified.status);
    assert_eq!(certified.checker_panics, 0);
    assert!(
        certified
            .path
            .windows(2)
            .all(|w| !crosses_wall(&w[0], &w[1]))
    );
    // The path goes round the wall's free end.
    assert!(certified.path.iter().any(|q| q[1] > GAP_Y));
}

#[test]
fn a_panicking_motion_validator_counts_as_invalid_motions() {
    let _serial = serial();
    let every_state = |_: &[f64]| true;
    let motion = |_: &[f64], _: &[f64]| -> bool { panic!("motion validator failure") };
    let outcome = plan_with_motion(
        &problem(),
        &every_state,
        Some(&motion),
        &PlanSettings::default(),
        Termination::after(Duration::from_millis(200)),
    )
    .unwrap();
    assert!(outcome.checker_panics > 0);
    // No motion is valid, so no path leaves the start.
    assert_ne!(outcome.status, PlanStatus::ExactSolution);
    assert!(outcome.path.len() <= 1, "{:?}", outcome.path);
}
