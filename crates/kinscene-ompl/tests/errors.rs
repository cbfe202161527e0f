//! Bad input gives typed errors; an exception inside OMPL gives `Error::Backend`.

use std::time::Duration;

use kinscene_ompl::{Error, PlanSettings, Problem, StateSpace, Termination, plan};
use kinscene_shim::CallError;

use crate::common::serial;

fn always_valid(_: &[f64]) -> bool {
    true
}

fn square() -> StateSpace {
    StateSpace::RealVector {
        lower: vec![0.0; 2],
        upper: vec![1.0; 2],
    }
}

fn try_plan(problem: Problem, settings: PlanSettings, budget: Duration) -> Result<(), Error> {
    plan(
        &problem,
        &always_valid,
        &settings,
        Termination::after(budget),
    )
    .map(|_| ())
}

fn try_problem(space: StateSpace, start: Vec<f64>, goal: Vec<f64>) -> Result<(), Error> {
    try_plan(
        Problem::new(space, start, goal),
        PlanSettings::default(),
        Duration::from_secs(1),
    )
}

fn try_settings(settings: PlanSettings) -> Result<(), Error> {
    try_plan(
        Problem::new(square(), vec![0.1; 2], vec![0.9; 2]),
        settings,
        Duration::from_secs(1),
    )
}

#[test]
fn bad_problems_are_typed_errors() {
    let rv = |lower: Vec<f64>, upper: Vec<f64>| StateSpace::RealVector { lower, upper };
    assert!(matches!(
        try_problem(square(), vec![f64::NAN, 0.1], vec![0.9; 2]),
        Err(Error::NonFinite { what: "start" })
    ));
    assert!(matches!(
        try_problem(square(), vec![0.1; 2], vec![0.9, f64::INFINITY]),
        Err(Error::NonFinite { what: "goal" })
    ));
    assert!(matches!(
        try_problem(square(), vec![0.1; 2], vec![0.9; 3]),
        Err(Error::DimensionMismatch {
            what: "goal",
            expected: 2,
            got: 3
        })
    ));
    assert!(matches!(
        try_problem(
            StateSpace::Se2 {
                x: [0.0, 1.0],
                y: [0.0, 1.0]
            },
            vec![0.1; 2],
            vec![0.9; 3]
        ),
        Err(Error::DimensionMismatch {
            what: "start",
            expected: 3,
            got: 2
        })
    ));
    assert!(matches!(
        try_problem(
            rv(vec![0.0, 1.0], vec![1.0, 0.5]),
            vec![0.1; 2],
            vec![0.9; 2]
        ),
        Err(Error::InvalidBounds {
            axis: 1,
            lower: 1.0,
            upper: 0.5
        })
    ));
    assert!(matches!(
        try_problem(
            StateSpace::Se2 {
                x: [2.0, 1.0],
                y: [0.0, 1.0]
            },
            vec![0.1; 3],
            vec![0.9; 3]
        ),
        Err(Error::InvalidBounds { axis: 0, .. })
    ));
    assert!(matches!(
        try_problem(rv(vec![0.0, 0.0], vec![1.0]), vec![0.1; 2], vec![0.9; 2]),
        Err(Error::DimensionMismatch {
            what: "upper bounds",
            expected: 2,
            got: 1
        })
    ));
    assert!(matches!(
        try_problem(
            rv(vec![0.0, f64::NEG_INFINITY], vec![1.0; 2]),
            vec![0.1; 2],
            vec![0.9; 2]
        ),
        Err(Error::NonFinite { what: "bounds" })
    ));
    assert!(matches!(
        try_problem(rv(vec![], vec![]), vec![], vec![]),
        Err(Error::ZeroDimension)
    ));
    let mut problem = Problem::new(square(), vec![0.1; 2], vec![0.9; 2]);
    problem.goal_tolerance = -1.0;
    assert!(matches!(
        try_plan(problem, PlanSettings::default(), Duration::from_secs(1)),
        Err(Error::InvalidSetting {
            name: "goal_tolerance",
            ..
        })
    ));
}

#[test]
fn bad_settings_are_typed_errors() {
    let problem = Problem::new(square(), vec![0.1; 2], vec![0.9; 2]);
    assert!(matches!(
        try_plan(problem, PlanSettings::default(), Duration::ZERO),
        Err(Error::NonPositiveBudget)
    ));
    for resolution in [0.0, -0.1, 1e-17, 1.0, 1.5, f64::NAN] {
        let r = try_settings(PlanSettings {
            resolution_fraction: resolution,
            ..PlanSettings::default()
        });
        assert!(
            matches!(r, Err(Error::ResolutionOutOfRange { .. })),
            "{resolution}: {r:?}"
        );
    }
    // Just below 1 (about one check per motion, at its end) is allowed.
    let _serial = serial();
    let r = try_settings(PlanSettings {
        resolution_fraction: 0.999,
        ..PlanSettings::default()
    });
    assert!(r.is_ok(), "{r:?}");
    let cases: [(PlanSettings, &str); 4] = [
        (
            PlanSettings {
                range: Some(0.0),
                ..PlanSettings::default()
            },
            "range",
        ),
        (
            PlanSettings {
                range: Some(f64::NAN),
                ..PlanSettings::default()
            },
            "range",
        ),
        (
            PlanSettings {
                interpolate_to: Some(1),
                ..PlanSettings::default()
            },
            "interpolate_to",
        ),
        (
            PlanSettings {
                cost_threshold: Some(f64::NAN),
                ..PlanSettings::default()
            },
            "cost_threshold",
        ),
    ];
    for (settings, field) in cases {
        let r = try_settings(settings);
        assert!(
            matches!(r, Err(Error::InvalidSetting { name, .. }) if name == field),
            "{field}: {r:?}"
        );
    }
}

#[test]
fn zero_extent_space_is_an_ompl_exception() {
    let _serial = serial();
    // lower == upper everywhere passes validation (lower ≤ upper) but has zero extent, and
    // OMPL's StateSpace::setup throws "The longest valid segment ... must be positive".
    let space = StateSpace::RealVector {
        lower: vec![0.5; 2],
        upper: vec![0.5; 2],
    };
    match try_problem(space, vec![0.5; 2], vec![0.5; 2]) {
        Err(Error::Backend(CallError::Exception { function, message })) => {
            assert_eq!(function, "ks_ompl_plan");
            assert!(message.contains("longest valid segment"), "{message}");
        }
        other => panic!("expected a C++ exception, got {other:?}"),
    }
}

/// `load` loads the shim ahead of the first plan (so a budget does not pay for it) and is
/// idempotent.
#[test]
fn the_shim_loads_ahead_of_the_first_plan() {
    assert!(kinscene_ompl::load().is_ok());
    assert!(kinscene_ompl::load().is_ok());
}
