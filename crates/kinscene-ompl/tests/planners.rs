//! Every planner of the enum solves an easy problem in SE(2), the plane and a 4-D joint space.

use std::f64::consts::FRAC_PI_2;
use std::time::Duration;

use kinscene_ompl::{PlanSettings, PlanStatus, Planner, Problem, StateSpace, Termination, plan};

use crate::common::{assert_path_valid, distance, extent, length, serial};

const BUDGET: Duration = Duration::from_secs(5);

/// A problem with one ball obstacle on the straight line from start to goal (in x, y for SE(2)).
struct Case {
    problem: Problem,
    centre: Vec<f64>,
    radius: f64,
}

impl Case {
    /// Valid when the first `centre.len()` coordinates are at least `radius + margin` from the
    /// centre.
    fn outside(&self, q: &[f64], margin: f64) -> bool {
        let d2: f64 = self
            .centre
            .iter()
            .zip(q)
            .map(|(c, x)| (x - c) * (x - c))
            .sum();
        d2.sqrt() >= self.radius + margin
    }
}

fn cases() -> [Case; 3] {
    [
        Case {
            problem: Problem::new(
                StateSpace::RealVector {
                    lower: vec![0.0; 2],
                    upper: vec![1.0; 2],
                },
                vec![0.1, 0.1],
                vec![0.9, 0.9],
            ),
            centre: vec![0.5, 0.5],
            radius: 0.1,
        },
        Case {
            problem: Problem::new(
                StateSpace::Se2 {
                    x: [0.0, 1.0],
                    y: [0.0, 1.0],
                },
                vec![0.1, 0.1, 0.0],
                vec![0.9, 0.9, FRAC_PI_2],
            ),
            centre: vec![0.5, 0.5],
            radius: 0.1,
        },
        Case {
            problem: Problem::new(
                StateSpace::RealVector {
                    lower: vec![-3.0; 4],
                    upper: vec![3.0; 4],
                },
                vec![-2.0; 4],
                vec![2.0; 4],
            ),
            centre: vec![0.0; 4],
            radius: 1.0,
        },
    ]
}

#[test]
fn every_planner_solves_an_easy_problem_in_each_space() {
    for case in cases() {
        let problem = &case.problem;
        let space = &problem.space;
        // The planner's checker keeps a margin ≥ h/2, h = resolution × extent, so that the
        // dense re-check against the bare obstacle is sound (see maze.rs).
        let margin = 0.6 * PlanSettings::default().resolution_fraction * extent(space);
        // Twice the start-goal distance (a lower bound of any path's length): loose enough that
        // the optimising planners meet it with their first solutions, so they stop early.
        let threshold = 2.0 * distance(space, &problem.start, &problem.goal);
        for planner in Planner::ALL {
            let _serial = serial();
            let settings = PlanSettings {
                planner,
                cost_threshold: planner.is_optimizing().then_some(threshold),
                ..PlanSettings::default()
            };
            let checker = |q: &[f64]| case.outside(q, margin);
            let outcome = plan(problem, &checker, &settings, Termination::after(BUDGET))
                .expect("planning runs");
            let context = format!("{planner:?} in {space:?}");
            assert_eq!(outcome.status, PlanStatus::ExactSolution, "{context}");
            // Stopped on its own (solution found / threshold met), not by the budget.
            assert!(
                outcome.planning_time < BUDGET,
                "{context}: {:?}",
                outcome.planning_time
            );
            assert_eq!(outcome.path[0], problem.start, "{context}");
            let last = outcome.path.last().unwrap();
            assert!(
                distance(space, last, &problem.goal) <= problem.goal_tolerance,
                "{context}"
            );
            assert_path_valid(space, &outcome.path, |q| case.outside(q, 0.0));
            if planner.is_optimizing() {
                let length = length(space, &outcome.path);
                // Simplification only shortens, so the threshold still holds (+ rounding).
                assert!(
                    length <= threshold + 1e-9,
                    "{context}: length {length} > {threshold}"
                );
            }
        }
    }
}
