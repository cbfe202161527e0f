//! Effects of the settings: range, interpolation, cost threshold, simplification, seeding.

use std::f64::consts::PI;
use std::time::Duration;

use kinscene_ompl::{
    LogLevel, PlanSettings, PlanStatus, Planner, Problem, Simplifier, StateSpace, Termination,
    plan, set_log_level, set_seed,
};

use crate::common::{assert_path_valid, distance, length, serial};

fn outside_disc(q: &[f64]) -> bool {
    (q[0] - 0.5).hypot(q[1] - 0.5) >= 0.15
}

fn problem() -> Problem {
    Problem::new(
        StateSpace::RealVector {
            lower: vec![0.0; 2],
            upper: vec![1.0; 2],
        },
        vec![0.1, 0.1],
        vec![0.9, 0.9],
    )
}

fn run(settings: &PlanSettings, budget: Duration) -> kinscene_ompl::PlanOutcome {
    plan(
        &problem(),
        &outside_disc,
        settings,
        Termination::after(budget),
    )
    .unwrap()
}

#[test]
fn range_bounds_each_step_of_an_unsimplified_path() {
    let _serial = serial();
    for planner in [Planner::RrtConnect, Planner::Rrt] {
        let settings = PlanSettings {
            range: Some(0.05),
            simplify: false,
            ..PlanSettings::with_planner(planner)
        };
        let outcome = run(&settings, Duration::from_secs(5));
        assert_eq!(outcome.status, PlanStatus::ExactSolution);
        // The start-goal distance is 1.13, so at least ⌈1.13 / 0.05⌉ = 23 steps.
        assert!(
            outcome.path.len() >= 24,
            "{planner:?}: {} states",
            outcome.path.len()
        );
        for w in outcome.path.windows(2) {
            let step = distance(&problem().space, &w[0], &w[1]);
            assert!(step <= 0.05 + 1e-12, "{planner:?}: step {step} > range");
        }
    }
}

#[test]
fn interpolation_gives_the_requested_state_count() {
    let _serial = serial();
    let settings = PlanSettings {
        interpolate_to: Some(57),
        ..PlanSettings::default()
    };
    let outcome = run(&settings, Duration::from_secs(5));
    assert_eq!(outcome.status, PlanStatus::ExactSolution);
    assert_eq!(outcome.path.len(), 57);
    assert_eq!(outcome.path[0], problem().start);
    assert!(
        distance(
            &problem().space,
            outcome.path.last().unwrap(),
            &problem().goal
        ) <= 1e-6
    );
}

#[test]
fn optimising_planner_uses_the_budget_unless_a_threshold_is_met() {
    let _serial = serial();
    let budget = Duration::from_millis(300);
    let settings = PlanSettings::with_planner(Planner::RrtStar);
    let outcome = run(&settings, budget);
    assert_eq!(outcome.status, PlanStatus::ExactSolution);
    assert!(
        outcome.planning_time >= budget,
        "{:?}",
        outcome.planning_time
    );

    // Any solution meets an infinite threshold: RRT* stops at its first one.
    let settings = PlanSettings {
        cost_threshold: Some(f64::INFINITY),
        ..settings
    };
    let outcome = run(&settings, Duration::from_secs(10));
    assert_eq!(outcome.status, PlanStatus::ExactSolution);
    assert!(
        outcome.planning_time < Duration::from_secs(2),
        "{:?}",
        outcome.planning_time
    );
}

#[test]
fn same_seed_gives_the_same_path_and_simplification_shortens_it() {
    let _serial = serial();
    let raw = PlanSettings {
        simplify: false,
        ..PlanSettings::default()
    };
    let budget = Duration::from_secs(5);
    set_seed(42).unwrap();
    let first = run(&raw, budget);
    set_seed(42).unwrap();
    let second = run(&raw, budget);
    assert_eq!(first.status, PlanStatus::ExactSolution);
    assert_eq!(
        first.path, second.path,
        "same seed, same planner: identical path"
    );

    set_seed(42).unwrap();
    let simplified = run(&PlanSettings::default(), budget);
    assert_eq!(simplified.status, PlanStatus::ExactSolution);
    assert_path_valid(&problem().space, &simplified.path, outside_disc);
    // The simplifier started from the same raw path (same seed) and only shortens it.
    let (l_raw, l_simple) = (
        length(&problem().space, &first.path),
        length(&problem().space, &simplified.path),
    );
    assert!(
        l_simple <= l_raw + 1e-9,
        "simplified {l_simple} > raw {l_raw}"
    );
    // The shortest way around the disc (two tangents plus an arc) is ≥ the straight 1.131.
    assert!(l_simple >= 0.8 * 2f64.sqrt());
}

/// The shortcut simplifier starts from the same raw path (same seed) and only replaces pieces
/// by checked motions: the path stays valid (dense check), keeps its ends and is no longer
/// than the raw one.
#[test]
fn shortcut_simplifier_keeps_the_path_valid_and_no_longer() {
    let _serial = serial();
    let budget = Duration::from_secs(5);
    let raw = PlanSettings {
        simplify: false,
        ..PlanSettings::default()
    };
    set_seed(7).unwrap();
    let first = run(&raw, budget);
    assert_eq!(first.status, PlanStatus::ExactSolution);
    let shortcut = PlanSettings {
        simplifier: Simplifier::Shortcut,
        ..PlanSettings::default()
    };
    set_seed(7).unwrap();
    let short = run(&shortcut, budget);
    assert_eq!(short.status, PlanStatus::ExactSolution);
    assert_path_valid(&problem().space, &short.path, outside_disc);
    assert_eq!(short.path.first(), first.path.first());
    assert_eq!(short.path.last(), first.path.last());
    let (l_raw, l_short) = (
        length(&problem().space, &first.path),
        length(&problem().space, &short.path),
    );
    assert!(l_short <= l_raw + 1e-9, "shortcut {l_short} > raw {l_raw}");
}

#[test]
fn se2_start_yaw_is_normalised_into_minus_pi_pi() {
    let _serial = serial();
    let problem = Problem::new(
        StateSpace::Se2 {
            x: [0.0, 1.0],
            y: [0.0, 1.0],
        },
        vec![0.1, 0.1, 4.0],
        vec![0.9, 0.9, -7.0],
    );
    let outcome = plan(
        &problem,
        &outside_disc,
        &PlanSettings::default(),
        Termination::after(Duration::from_secs(5)),
    )
    .unwrap();
    assert_eq!(outcome.status, PlanStatus::ExactSolution);
    // 4 − 2π and −7 + 2π are the representatives in [−π, π].
    assert!((outcome.path[0][2] - (4.0 - 2.0 * PI)).abs() <= 1e-12);
    assert!((outcome.path.last().unwrap()[2] - (-7.0 + 2.0 * PI)).abs() <= 1e-6);
}

#[test]
fn se2_yaw_of_exactly_pi_is_a_valid_start_and_goal() {
    // π is a heading like any other (a robot facing −x, as atan2(0, −1) gives). OMPL's SO(2)
    // bounds are the half-open [−π, π), and remainder(π, 2π) is π itself, so the shim must
    // map it to −π or the start (the goal) is reported invalid.
    let _serial = serial();
    for (start, goal) in [(PI, 0.0), (0.0, PI), (PI, PI), (-PI, PI)] {
        let problem = Problem::new(
            StateSpace::Se2 {
                x: [0.0, 1.0],
                y: [0.0, 1.0],
            },
            vec![0.1, 0.1, start],
            vec![0.9, 0.9, goal],
        );
        let outcome = plan(
            &problem,
            &outside_disc,
            &PlanSettings::default(),
            Termination::after(Duration::from_secs(5)),
        )
        .unwrap();
        assert_eq!(
            outcome.status,
            PlanStatus::ExactSolution,
            "start yaw {start}, goal yaw {goal}"
        );
        // Yaw π is reported as its representative −π (the same heading).
        let first = outcome.path[0][2];
        assert!(
            (first.sin() - start.sin()).abs() <= 1e-12
                && (first.cos() - start.cos()).abs() <= 1e-12,
            "start yaw {start} came back as {first}"
        );
        assert!((-PI..PI).contains(&first), "start yaw {first}");
    }
}

#[test]
fn log_level_can_be_changed() {
    set_log_level(LogLevel::Error).unwrap();
    set_log_level(LogLevel::None).unwrap();
}

#[test]
fn an_iteration_budget_ends_the_search_at_a_count_not_a_time() {
    // A disc in the way and tree steps of 0.01 (range): RRT needs at least
    // ⌈(1.13 − 0.3) / 0.01⌉ = 83 extensions to reach the goal, so a budget of 20 iterations
    // cannot find it, however long the wall clock allows (60 s here). Each planner checks its
    // condition once per iteration: the count stops at budget + 1, the check that ended it.
    let _serial = serial();
    let settings = PlanSettings {
        range: Some(0.01),
        max_iterations: Some(20),
        ..PlanSettings::with_planner(Planner::Rrt)
    };
    for _ in 0..2 {
        set_seed(7).unwrap();
        let outcome = run(&settings, Duration::from_secs(60));
        assert_ne!(outcome.status, PlanStatus::ExactSolution);
        assert!(outcome.iteration_budget_spent);
        assert_eq!(outcome.iterations, 21);
        assert!(outcome.planning_time < Duration::from_secs(30));
    }
    // A generous budget finds the path and says it was not spent.
    let roomy = PlanSettings {
        max_iterations: Some(1_000_000),
        ..PlanSettings::default()
    };
    set_seed(7).unwrap();
    let outcome = run(&roomy, Duration::from_secs(10));
    assert_eq!(outcome.status, PlanStatus::ExactSolution);
    assert!(!outcome.iteration_budget_spent);
    assert!(outcome.iterations >= 1 && outcome.iterations < 1_000_000);
    // Zero iterations is a setting error.
    let zero = PlanSettings {
        max_iterations: Some(0),
        ..PlanSettings::default()
    };
    assert!(
        zero.validate()
            .unwrap_err()
            .to_string()
            .contains("max_iterations")
    );
}
