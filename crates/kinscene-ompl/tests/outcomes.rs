//! Outcomes that are not errors: invalid start/goal, timeout, cancellation, panicking checkers.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use kinscene_ompl::{PlanSettings, PlanStatus, Planner, Problem, StateSpace, Termination, plan};

use crate::common::{assert_path_valid, serial};

fn unit_square(start: [f64; 2], goal: [f64; 2]) -> Problem {
    Problem::new(
        StateSpace::RealVector {
            lower: vec![0.0; 2],
            upper: vec![1.0; 2],
        },
        start.to_vec(),
        goal.to_vec(),
    )
}

/// Invalid in the square [0.4, 0.6]².
fn block(q: &[f64]) -> bool {
    !(q[0] > 0.4 && q[0] < 0.6 && q[1] > 0.4 && q[1] < 0.6)
}

/// Invalid on an annulus 0.05 ≤ r ≤ 0.1 around (0.9, 0.9): the goal there is valid but
/// unreachable, so no planner can finish.
fn walled_in_goal(q: &[f64]) -> bool {
    let r = (q[0] - 0.9).hypot(q[1] - 0.9);
    !(0.05..=0.1).contains(&r)
}

#[test]
fn invalid_start_and_goal_are_statuses_for_every_planner() {
    let _serial = serial();
    let budget = Termination::after(Duration::from_secs(5));
    let cases = [
        ([0.5, 0.5], [0.9, 0.9], PlanStatus::InvalidStart),
        ([0.1, 0.1], [0.5, 0.5], PlanStatus::InvalidGoal),
        // Out of bounds counts as invalid, as in OMPL's PlannerInputStates.
        ([1.5, 0.1], [0.9, 0.9], PlanStatus::InvalidStart),
        ([0.1, 0.1], [0.9, -0.1], PlanStatus::InvalidGoal),
    ];
    for planner in Planner::ALL {
        for (start, goal, expected) in cases {
            let settings = PlanSettings::with_planner(planner);
            let outcome = plan(&unit_square(start, goal), &block, &settings, budget).unwrap();
            assert_eq!(
                outcome.status, expected,
                "{planner:?} {start:?} -> {goal:?}"
            );
            assert!(outcome.path.is_empty() && outcome.goal_distance.is_none());
        }
    }
}

#[test]
fn budget_ends_an_impossible_problem() {
    let _serial = serial();
    let budget = Duration::from_millis(200);
    let t0 = Instant::now();
    let outcome = plan(
        &unit_square([0.1, 0.1], [0.9, 0.9]),
        &walled_in_goal,
        &PlanSettings::default(),
        Termination::after(budget),
    )
    .unwrap();
    let elapsed = t0.elapsed();
    // RRTConnect reports its closest approach as an approximate solution, or a timeout.
    assert!(
        matches!(
            outcome.status,
            PlanStatus::Timeout | PlanStatus::ApproximateSolution
        ),
        "{:?}",
        outcome.status
    );
    assert!(elapsed >= budget, "{elapsed:?}");
    // Simplifying an approximate path may take one more pass; 1 s is far above that.
    assert!(elapsed < budget + Duration::from_secs(1), "{elapsed:?}");
}

#[test]
fn cancel_flag_set_from_another_thread_stops_planning() {
    let _serial = serial();
    let flag = AtomicBool::new(false);
    let budget = Duration::from_secs(30);
    let t0 = Instant::now();
    let outcome = std::thread::scope(|s| {
        s.spawn(|| {
            std::thread::sleep(Duration::from_millis(200));
            flag.store(true, Ordering::Relaxed);
        });
        plan(
            &unit_square([0.1, 0.1], [0.9, 0.9]),
            &walled_in_goal,
            &PlanSettings::default(),
            Termination::after(budget).with_cancel(&flag),
        )
        .unwrap()
    });
    let elapsed = t0.elapsed();
    assert_eq!(outcome.status, PlanStatus::Cancelled);
    assert!(elapsed >= Duration::from_millis(200), "{elapsed:?}");
    // The flag is polled at every planner iteration: stopping takes far less than a second.
    assert!(
        elapsed < Duration::from_secs(2),
        "{elapsed:?} (budget {budget:?})"
    );
}

#[test]
fn cancel_flag_set_before_the_call_returns_at_once() {
    let _serial = serial();
    let flag = AtomicBool::new(true);
    for planner in Planner::ALL {
        let t0 = Instant::now();
        let outcome = plan(
            &unit_square([0.1, 0.1], [0.9, 0.9]),
            &walled_in_goal,
            &PlanSettings::with_planner(planner),
            Termination::after(Duration::from_secs(30)).with_cancel(&flag),
        )
        .unwrap();
        assert_eq!(outcome.status, PlanStatus::Cancelled, "{planner:?}");
        assert!(
            t0.elapsed() < Duration::from_secs(1),
            "{planner:?}: {:?}",
            t0.elapsed()
        );
    }
}

#[test]
fn panicking_checker_counts_as_invalid_and_never_aborts() {
    let _serial = serial();
    // Panics near the block instead of answering: those states must count as invalid. The
    // panic region is the block grown by 0.01 ≥ h/2 = 0.01 × √2 / 2, so the dense re-check
    // against the block itself is sound (see maze.rs).
    let panicking = |q: &[f64]| {
        if q[0] > 0.39 && q[0] < 0.61 && q[1] > 0.39 && q[1] < 0.61 {
            panic!("checker panics at {q:?}");
        }
        true
    };
    let problem = unit_square([0.1, 0.1], [0.9, 0.9]);
    for planner in [Planner::RrtConnect, Planner::Prm] {
        let outcome = plan(
            &problem,
            &panicking,
            &PlanSettings::with_planner(planner),
            Termination::after(Duration::from_secs(5)),
        )
        .unwrap();
        assert_eq!(outcome.status, PlanStatus::ExactSolution, "{planner:?}");
        assert!(outcome.checker_panics > 0, "{planner:?}");
        assert_path_valid(&problem.space, &outcome.path, block);
    }
}
