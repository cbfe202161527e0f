//! The independent plan validator on hand-built plans.

use std::f64::consts::FRAC_PI_4;

use kinscene::scene::collision::{CollisionSettings, collisions};
use kinscene::scene::{BaseShape, SceneData, Shape, forward_kinematics};
use kinscene::task::{
    Error, NoRefinement, Outcome, Step, Strategy, TaskSettings, Termination, plan, validate,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::baselines::{one_door, open_door_problem};

fn step(joint: &str, from: f64, to: f64) -> Step {
    Step {
        joint: joint.into(),
        from,
        to,
        handle: None,
        base: None,
        travel: 0.0,
        cost: 0.0,
    }
}

#[test]
fn accepts_the_plan_of_the_one_door_case() {
    let model = one_door(Vec::new());
    let problem = open_door_problem(&model);
    let settings = TaskSettings::default();
    let r = plan(
        &model,
        &problem,
        &settings,
        &NoRefinement,
        &Termination::none(),
    )
    .unwrap();
    let Outcome::Solved(p) = r.outcome else {
        panic!("expected a plan, got {:?}", r.outcome)
    };
    assert_eq!(p.steps.len(), 1);
    assert!(
        p.steps[0].base.is_some(),
        "the search records its base pose"
    );
    let v = validate(&model, &problem, &p.steps, &settings).unwrap();
    assert!(v.valid, "{v:?}");
    assert_eq!(v.first_failure, None);
    assert!(v.unmet.is_empty());
    // Dense samples: the door's motion bound is its bounding sphere's reach from the axis,
    // 0.25 (centre) + |(0.25, 0.01, 0.35)| (radius) m/rad; with min_margin = 1e-4 m the
    // validator takes ⌈L·Δ / 1e-4⌉ + 1 samples.
    let lipschitz: f64 = 0.25 + Vector3::new(0.25, 0.01, 0.35).norm();
    let delta = p.steps[0].to - p.steps[0].from;
    let expected = (lipschitz * delta / settings.sweep.min_margin).ceil() as usize + 1;
    assert!(
        v.checked_samples.abs_diff(expected) <= 1,
        "{} vs {expected}",
        v.checked_samples
    );
    // The same step without its recorded base pose: some cell must still pass (brute force).
    let mut bare = p.steps.clone();
    bare[0].base = None;
    bare[0].handle = None;
    assert!(validate(&model, &problem, &bare, &settings).unwrap().valid);
}

/// A 0.25 m × 2 cm wall running radially from the hinge at 45°, between 0.2 m and 0.45 m from
/// it: the door (closed along +x, open to 1.3 rad ≈ 74.5°) misses it at both ends but must
/// pass through it.
fn radial_wall() -> BaseShape {
    let r = 0.325;
    BaseShape::new(
        "wall",
        Shape::box_size(Vector3::new(0.25, 0.02, 0.7)),
        Isometry3::from_parts(
            Translation3::new(r * FRAC_PI_4.cos(), r * FRAC_PI_4.sin(), 0.35),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), FRAC_PI_4),
        ),
    )
}

#[test]
fn rejects_a_step_that_sweeps_through_a_wall() {
    let model = one_door(vec![radial_wall()]);
    let problem = open_door_problem(&model);
    let settings = TaskSettings::default();
    // Both ends of the step are collision-free; only the motion between them is not.
    let mut data = SceneData::new(&model);
    for v in [0.0, 1.3] {
        let mut s = problem.start.clone();
        s.set_by_name(&model, "door_hinge", v).unwrap();
        forward_kinematics(&model, &mut data, &s).unwrap();
        assert!(
            collisions(&model, &data, &CollisionSettings::default())
                .unwrap()
                .is_empty()
        );
    }
    let v = validate(&model, &problem, &[step("door_hinge", 0.0, 1.3)], &settings).unwrap();
    assert!(!v.valid);
    let (i, why) = v.first_failure.expect("the sweep crosses the wall");
    assert_eq!(i, 0);
    assert!(why.contains("base shape \"wall\""), "{why}");
    // The replay stopped before the step: the door is still closed.
    assert_eq!(v.unmet, ["door_hinge"]);
    // Without the wall the same plan is valid.
    let free = one_door(Vec::new());
    let v = validate(&free, &problem, &[step("door_hinge", 0.0, 1.3)], &settings).unwrap();
    assert!(v.valid, "{v:?}");
}

/// The dense check reports the first colliding sample in order and counts the samples up to
/// it. The wall's face towards the closed door lies 0.01 m on the door's side of the 45°
/// line, from 0.2 m to 0.45 m out; the door's leading face lies 0.01 m ahead of its own
/// radial line. A wall point `r·u_45 − 0.01·n_45` is `r sin δ − 0.01 cos δ` ahead of the
/// door's radial line at angle `φ = 45° − δ`, so the wall's inner corner (r = 0.2) meets the
/// leading face first, when `tan(δ/2) = 0.01 / 0.2`: `φ* = π/4 − 2 atan(0.05)` = 0.6855 rad.
#[test]
fn stops_at_the_first_colliding_sample() {
    let model = one_door(vec![radial_wall()]);
    let problem = open_door_problem(&model);
    let settings = TaskSettings::default();
    let v = validate(&model, &problem, &[step("door_hinge", 0.0, 1.3)], &settings).unwrap();
    let first = FRAC_PI_4 - 2.0 * 0.05f64.atan();
    // Samples k·1.3/n, n as in `accepts_the_plan_of_the_one_door_case`: the first colliding
    // one is k = ⌈φ*·n / 1.3⌉, and the samples 0..=k are counted.
    let lipschitz: f64 = 0.25 + Vector3::new(0.25, 0.01, 0.35).norm();
    let n = (lipschitz * 1.3 / settings.sweep.min_margin).ceil();
    let k = (first * n / 1.3).ceil() as usize;
    assert!(
        v.checked_samples.abs_diff(k + 1) <= 1,
        "{} vs {}",
        v.checked_samples,
        k + 1
    );
    let (_, why) = v.first_failure.unwrap();
    assert!(why.contains(&format!("of {n})")), "{why}");
}

#[test]
fn rejects_a_wrong_from() {
    let model = one_door(Vec::new());
    let problem = open_door_problem(&model);
    let steps = [step("door_hinge", 0.0, 1.3), step("door_hinge", 1.0, 1.5)];
    let v = validate(&model, &problem, &steps, &TaskSettings::default()).unwrap();
    assert!(!v.valid);
    let (i, why) = v.first_failure.unwrap();
    assert_eq!(
        i, 1,
        "the first step is fine, the second starts from 1.0 but the door is at 1.3"
    );
    assert!(why.contains("starts from 1"), "{why}");
    // The state before the failing step (door at 1.3) meets the goal.
    assert!(v.unmet.is_empty());
}

#[test]
fn rejects_a_plan_that_misses_the_goal() {
    let model = one_door(Vec::new());
    let problem = open_door_problem(&model);
    let settings = TaskSettings::default();
    for steps in [
        vec![step("door_hinge", 0.0, 1.0)],
        vec![step("door_hinge", 0.0, 1.3), step("door_hinge", 1.3, 0.6)],
        vec![],
    ] {
        let v = validate(&model, &problem, &steps, &settings).unwrap();
        assert!(!v.valid, "{steps:?}");
        assert_eq!(v.first_failure, None, "every step is feasible: {v:?}");
        assert_eq!(v.unmet, ["door_hinge"]);
    }
}

#[test]
fn rejects_a_base_pose_outside_the_manipulation_region() {
    let model = one_door(Vec::new());
    let problem = open_door_problem(&model);
    let mut s = step("door_hinge", 0.0, 1.3);
    // 1.8 m from the handle's start point (0.45, -0.02): beyond reach_max = 0.9 m.
    s.base = Some([-1.2, -0.8, 0.0]);
    let v = validate(&model, &problem, &[s], &TaskSettings::default()).unwrap();
    let (i, why) = v.first_failure.expect("out of reach");
    assert_eq!(i, 0);
    assert!(why.contains("manipulation region"), "{why}");
}

#[test]
fn errors_on_a_step_that_does_not_fit_the_model() {
    let model = one_door(Vec::new());
    let problem = open_door_problem(&model);
    let settings = TaskSettings::default();
    let unknown = [
        step("door_hinge", 0.0, 1.3),
        step("no_such_joint", 0.0, 1.0),
    ];
    match validate(&model, &problem, &unknown, &settings) {
        Err(Error::InvalidStep { step: 1, message }) => {
            assert!(message.contains("no_such_joint"), "{message}")
        }
        other => panic!("expected InvalidStep at step 1, got {other:?}"),
    }
    // Limits are [0, 1.6] rad.
    let beyond = [step("door_hinge", 0.0, 2.0)];
    assert!(matches!(
        validate(&model, &problem, &beyond, &settings),
        Err(Error::InvalidStep { step: 0, .. })
    ));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(12))]

    /// Every plan the search returns validates, and so does every plan of the *Random*
    /// baseline (it uses the search's predicate).
    #[test]
    fn search_and_random_plans_validate_on_generated_kitchens(
        (kitchen, spec) in super::generators::instance(3..=10, 1..=4),
        seed in 0u64..1000,
    ) {
        let model = &kitchen.model;
        let problem = kinscene::task::Problem::from_spec(model, &spec).unwrap();
        for strategy in [Strategy::Search, Strategy::Random { seed }] {
            let settings = TaskSettings { strategy, ..TaskSettings::default() };
            let r = plan(model, &problem, &settings, &NoRefinement, &Termination::none()).unwrap();
            if let Outcome::Solved(p) = &r.outcome {
                let v = validate(model, &problem, &p.steps, &settings).unwrap();
                proptest::prop_assert!(v.valid, "{strategy:?}: {v:?}\n{p:#?}");
            }
        }
    }
}
