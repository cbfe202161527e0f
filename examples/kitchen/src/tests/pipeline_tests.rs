//! Tests of the kitchen example's pipeline: the three stages end to
//! end at reduced size, fault injection at high rates, determinism, and bad configurations.

use crate::pipeline::{
    Category, Config, EXTRA_SEQUENCES, EstimatorChoice, Experiment, ExploreScope, Method,
    PRISMATIC_TOLERANCE, PipelineError, REVOLUTE_TOLERANCE, Report, SEQUENCES, run,
};

/// One sequence, one run, only its handles explored, Ours only, the quick camera. Seed 1 is
/// one whose discovery registers the three drawers (the stage still fails on some handle in
/// some runs: seeds 1, 2, 4, 6, 7 register all three, 3 misses one; see the example's report).
fn small(sequence: &str) -> Config {
    Config {
        seed: 1,
        runs: 1,
        quick: true,
        experiments: vec![Experiment::Fig5, Experiment::Fig6],
        sequences: Some(vec![sequence.to_string()]),
        explore: ExploreScope::Needed,
        methods: vec![Method::Ours],
        ..Config::default()
    }
}

/// The sequence of the end-to-end tests: three drawers, the parts the discovery stage
/// registers most reliably (the Fig. 5 sequences need the sink door, whose estimated box
/// still overlaps the carcass beside it, so nothing is planned on it: see the report).
const SEQUENCE: &str = "drawers";

#[test]
fn the_pipeline_reaches_the_goal_in_the_simulator() {
    let config = small(SEQUENCE);
    let report = run(&config, None, false).expect("the pipeline runs");
    // Mapping found the three handles the sequence needs, discovery registered them.
    let d = &report.runs[0].discovery[0];
    let q = SEQUENCES
        .iter()
        .chain(EXTRA_SEQUENCES.iter())
        .find(|q| q.name == SEQUENCE)
        .expect("the test's sequence exists");
    for (joint, _) in q.goal {
        assert!(
            d.matches.iter().any(|m| m.true_joint == *joint),
            "{joint} not discovered:\n{}",
            report.to_markdown()
        );
    }
    // The planned order was executed and the simulator's true state meets every target.
    let attempt = &report.fig5[0];
    assert_eq!(attempt.method, Method::Ours);
    assert_eq!(
        attempt.verdict.category,
        Category::Success,
        "{}",
        report.to_markdown()
    );
    assert_eq!(attempt.verdict.final_values.len(), q.goal.len());
    for ((joint, min), (name, value)) in q.goal.iter().zip(&attempt.verdict.final_values) {
        assert_eq!(joint, name);
        let tolerance = if joint.ends_with("_slide") {
            PRISMATIC_TOLERANCE
        } else {
            REVOLUTE_TOLERANCE
        };
        assert!(*value >= min - tolerance, "{joint} at {value} < {min}");
    }
    // Every goal joint was moved by the executed plan.
    for (joint, _) in q.goal {
        assert!(
            attempt.verdict.steps.iter().any(|s| s.starts_with(joint)),
            "{joint} not in {:?}",
            attempt.verdict.steps
        );
    }
}

#[test]
fn high_fault_rates_end_in_a_report_of_what_failed() {
    // The Oracle too, so that the faults also hit the execution of a plan.
    let config = Config {
        fault_rate: 0.5,
        methods: vec![Method::Ours, Method::Oracle],
        ..small(SEQUENCE)
    };
    let report = run(&config, None, false).expect("faults are outcomes, not errors");
    let md = report.to_markdown();
    // Something was not achieved, and the report says what and why.
    let failed_handles: Vec<_> = report.runs[0].discovery[0]
        .handles
        .iter()
        .filter(|h| h.outcome.starts_with("failed"))
        .collect();
    let failed_attempts: Vec<_> = report
        .fig5
        .iter()
        .filter(|a| a.verdict.category != Category::Success)
        .collect();
    assert!(
        !failed_handles.is_empty() || !failed_attempts.is_empty(),
        "at fault rate 0.5 something fails:\n{md}"
    );
    for h in failed_handles {
        assert!(md.contains("failed at"), "{md}");
        assert!(h.outcome.len() > "failed at".len());
    }
    for a in failed_attempts {
        assert!(!a.verdict.reason.is_empty());
        assert!(md.contains(a.verdict.category.name()));
    }
    // Fig. 6 accounts for every considered true handle.
    let row = &report.fig6[0];
    assert!(row.estimation <= row.exploration && row.exploration <= row.navigation);
    assert!(row.navigation <= row.mapping && row.mapping <= row.handles);
}

#[test]
fn the_same_seed_gives_the_same_report() {
    let config = small(SEQUENCE);
    let a: Report = run(&config, None, false).expect("first run");
    let b: Report = run(&config, None, false).expect("second run");
    assert_eq!(a.to_markdown(), b.to_markdown());
}

#[test]
fn bad_configurations_are_typed_errors() {
    for bad in [
        Config {
            runs: 0,
            ..Config::quick()
        },
        Config {
            depth_noise: f64::NAN,
            ..Config::quick()
        },
        Config {
            fault_rate: 1.5,
            ..Config::quick()
        },
        Config {
            planner_budget: 0.0,
            ..Config::quick()
        },
        Config {
            sequences: Some(vec!["no-such-sequence".into()]),
            ..Config::quick()
        },
        Config {
            bar_turn: 2.0,
            ..Config::quick()
        },
        Config {
            bar_turn: f64::NAN,
            ..Config::quick()
        },
    ] {
        assert!(
            matches!(run(&bad, None, false), Err(PipelineError::Config(_))),
            "{bad:?}"
        );
    }
    let missing = Config {
        scene: "/nonexistent/kitchen.urdf".into(),
        ..Config::quick()
    };
    assert!(matches!(
        run(&missing, None, false),
        Err(PipelineError::Scene(_))
    ));
    assert!(Experiment::parse_list("fig5,table9").is_err());
    assert!(Experiment::parse_list("").is_err());
    assert_eq!(
        Experiment::parse_list("fig6, fig5,fig5").expect("valid list"),
        vec![Experiment::Fig5, Experiment::Fig6]
    );
    assert!(EstimatorChoice::parse("ditto").is_err());
}

/// The exploration order on run 0's mapped handles of the drawer stack (seed 1): the top
/// drawer's handle (1.41, 2.38, 0.74) is 2.909 m from the start (1.0, −0.5), the pot drawer's
/// (1.40, 2.36, 0.36) 2.888 m — 10 cm distance bins put the top one first. They are 2.2 cm
/// apart horizontally, one stack, so the lower goes first; the sink door's (2.15, 2.35, 0.75),
/// 2.962 m away by hand (hypot(1.15, 2.85)), heads the order, and the island drawer's
/// (1.81, 0.61, 0.74), 1.375 m (hypot(0.81, 1.11)), ends it.
#[test]
fn stacked_handles_are_explored_lowest_first() {
    use kinscene::discovery::MappedHandle;
    use nalgebra::{Point3, Vector3};

    use crate::pipeline::selection_order;

    let at = |x: f64, y: f64, z: f64| MappedHandle {
        position: Point3::new(x, y, z),
        half_extents: Vector3::repeat(0.01),
        confidence: 0.9,
        views: 1,
        spread: 0.0,
        stamp: 0.0,
        attachment: None,
    };
    let mut handles = vec![
        at(1.81, 0.61, 0.74),
        at(1.41, 2.38, 0.74),
        at(2.15, 2.35, 0.75),
        at(1.40, 2.36, 0.36),
    ];
    selection_order(&mut handles, [1.0, -0.5, std::f64::consts::FRAC_PI_2]);
    let order: Vec<[f64; 3]> = handles
        .iter()
        .map(|h| [h.position.x, h.position.y, h.position.z])
        .collect();
    assert_eq!(
        order,
        vec![
            [2.15, 2.35, 0.75],
            [1.40, 2.36, 0.36],
            [1.41, 2.38, 0.74],
            [1.81, 0.61, 0.74],
        ]
    );
}
