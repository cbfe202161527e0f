//! Inverse kinematics: FK → IK → FK round trips, position + axis targets, unreachable targets,
//! joint limits, continuity of `solve_near`, typed errors for bad input; the dense step path
//! against a hand-derived FK and against the Clarabel-only solver, and the iteration budget's
//! independence of the machine's load.
//!
//! Most tests use an 8-DoF test arm built here with every joint kind the solver handles
//! differently (limited revolute, revolute with infinite limits, unbounded `(cos, sin)`
//! revolute, prismatic); the Gen3 tests use the shipped robot; the dense-path tests also a
//! planar 3R arm whose FK is written out here.

use std::f64::consts::PI;
use std::time::Duration;

use kinscene::kinematics::ik::{
    IkBest, IkData, IkError, IkFailure, IkOutcome, IkSettings, IkSolution, IkSolver, IkTarget,
    NoConvergence, StepSolver,
};
use kinscene::kinematics::pinocchio::{
    self as pin, FrameIndex, JointIndex, JointKind, JointLimits, Model,
};
use kinscene::kinematics::robot::RobotModel;
use nalgebra::{DVector, Isometry3, Point3, Unit, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The test arm: (parent_from_joint translation, kind, limits) per joint, then a tool frame
/// 0.1 m along the last joint's z. Offsets sum to a reach of at most 1.45 m from the root
/// (0.3 + 0.05 + 0.35 + 0.05 + 0.3 + 0.2 (prismatic travel) + 0.1 + 0.1), see [`REACH`].
fn test_arm() -> (Model, FrameIndex) {
    let z = Vector3::z();
    let y = Vector3::y();
    let joints: [([f64; 3], JointKind, JointLimits); 8] = [
        (
            [0.0; 3],
            JointKind::RevoluteUnbounded { axis: z },
            JointLimits::NONE,
        ),
        (
            [0.0, 0.0, 0.3],
            JointKind::Revolute { axis: y },
            JointLimits::position(-2.2, 2.2),
        ),
        (
            [0.0, 0.05, 0.0],
            JointKind::Revolute { axis: z },
            JointLimits::position(f64::NEG_INFINITY, f64::INFINITY),
        ),
        (
            [0.0, 0.0, 0.35],
            JointKind::Revolute { axis: y },
            JointLimits::position(-2.5, 2.5),
        ),
        (
            [0.0, -0.05, 0.0],
            JointKind::Revolute { axis: z },
            JointLimits::position(-2.9, 2.9),
        ),
        (
            [0.0, 0.0, 0.3],
            JointKind::Prismatic { axis: z },
            JointLimits::position(0.0, 0.2),
        ),
        (
            [0.0, 0.0, 0.0],
            JointKind::Revolute { axis: y },
            JointLimits::position(-2.0, 2.0),
        ),
        (
            [0.0, 0.0, 0.1],
            JointKind::Revolute { axis: z },
            JointLimits::position(-3.0, 3.0),
        ),
    ];
    let mut b = pin::ModelBuilder::new();
    let mut parent = JointIndex::UNIVERSE;
    for (i, (t, kind, limits)) in joints.into_iter().enumerate() {
        parent = b
            .add_joint(
                &format!("j{i}"),
                parent,
                Isometry3::translation(t[0], t[1], t[2]),
                kind,
                limits,
            )
            .unwrap();
    }
    let tool = b
        .add_frame("tool", parent, Isometry3::translation(0.0, 0.0, 0.1))
        .unwrap();
    (b.build().unwrap(), tool)
}

/// Upper bound on the distance of the test arm's tool from its root (m): the sum of the norms
/// of every offset, with the prismatic joint at its 0.2 m upper limit (triangle inequality).
const REACH: f64 = 0.3 + 0.05 + 0.35 + 0.05 + 0.3 + 0.2 + 0.1 + 0.1;

/// A configuration drawn uniformly within the limits; unlimited angles uniform in [−π, π).
fn random_q(model: &Model, rng: &mut ChaCha8Rng) -> DVector<f64> {
    let mut q = model.neutral();
    for joint in model.joints() {
        let i = joint.idx_q;
        let (lo, hi) = joint.limits.position.unwrap_or((-PI, PI));
        match joint.kind {
            JointKind::RevoluteUnbounded { .. } => {
                let (sin, cos) = rng.random_range(-PI..PI).sin_cos();
                q[i] = cos;
                q[i + 1] = sin;
            }
            _ => q[i] = rng.random_range(lo.max(-PI)..hi.min(PI)),
        }
    }
    q
}

fn tool_pose(model: &Model, frame: FrameIndex, q: &DVector<f64>) -> Isometry3<f64> {
    let mut data = pin::Data::new(model).unwrap();
    pin::forward_kinematics(model, &mut data, q).unwrap();
    pin::frame_placement(model, &data, frame).unwrap()
}

/// Every coordinate with position limits is within them (exactly: the solver clamps).
fn assert_within_limits(model: &Model, q: &DVector<f64>) {
    let (lower, upper) = model.position_bounds();
    for i in 0..q.len() {
        assert!(
            lower[i] <= q[i] && q[i] <= upper[i],
            "q[{i}] = {} outside [{}, {}]",
            q[i],
            lower[i],
            upper[i]
        );
    }
    pin::check_configuration(model, q).unwrap();
}

fn converged(outcome: IkOutcome) -> Option<DVector<f64>> {
    match outcome {
        IkOutcome::Solved(solution) => Some(solution.q),
        _ => None,
    }
}

/// FK → IK (from neutral) → FK on `samples` random configurations; returns the success count
/// after asserting that every converged q is within limits and reproduces its target within
/// the tolerances.
fn round_trip(
    model: &Model,
    frame: FrameIndex,
    solver: &IkSolver,
    samples: usize,
    seed: u64,
) -> usize {
    let settings = solver.settings();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut data = IkData::new(solver).unwrap();
    let neutral = model.neutral();
    let mut successes = 0;
    for _ in 0..samples {
        let q_true = random_q(model, &mut rng);
        let target = tool_pose(model, frame, &q_true);
        let outcome = solver
            .solve_with(&mut data, &IkTarget::Pose(target), &neutral)
            .unwrap();
        match outcome {
            IkOutcome::Solved(IkSolution { q, .. }) => {
                assert_within_limits(model, &q);
                let reached = tool_pose(model, frame, &q);
                let dp = (reached.translation.vector - target.translation.vector).norm();
                let dr = reached.rotation.angle_to(&target.rotation);
                assert!(dp <= settings.position_tolerance, "position error {dp}");
                assert!(dr <= settings.rotation_tolerance, "rotation error {dr}");
                successes += 1;
            }
            other => assert_within_limits(model, other.best_q()),
        }
    }
    successes
}

#[test]
fn round_trip_pose_on_the_test_arm() {
    let (model, tool) = test_arm();
    let solver = IkSolver::new(&model, tool, IkSettings::default()).unwrap();
    let samples = 300;
    let successes = round_trip(&model, tool, &solver, samples, 1);
    // Every target comes from a configuration within the limits, so it is reachable; the
    // issue's bar for the Gen3 is 99.5 %. On 300 samples allow 2 misses (99.3 %): a solver
    // missing 2 % of reachable targets fails this with probability > 0.9.
    assert!(successes + 2 >= samples, "{successes}/{samples} converged");
}

#[test]
fn round_trip_position_axis_leaves_the_roll_free() {
    let (model, tool) = test_arm();
    let settings = IkSettings::default();
    let solver = IkSolver::new(&model, tool, settings.clone()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let samples = 100;
    let mut successes = 0;
    for _ in 0..samples {
        let pose = tool_pose(&model, tool, &random_q(&model, &mut rng));
        let position = Point3::from(pose.translation.vector);
        let axis = Unit::new_normalize(pose.rotation * Vector3::z());
        let target = IkTarget::PositionAxis { position, axis };
        let Some(q) = converged(solver.solve(&target, &model.neutral()).unwrap()) else {
            continue;
        };
        successes += 1;
        assert_within_limits(&model, &q);
        let reached = tool_pose(&model, tool, &q);
        let z = reached.rotation * Vector3::z();
        // Same direction (not opposite) within the rotation tolerance.
        assert!(
            z.angle(&axis) <= settings.rotation_tolerance,
            "axis error {}",
            z.angle(&axis)
        );
        let dp = (reached.translation.vector - position.coords).norm();
        assert!(dp <= settings.position_tolerance, "position error {dp}");
        let (ep, er) = target.errors(&reached);
        assert!(ep <= settings.position_tolerance && er <= settings.rotation_tolerance);
    }
    assert!(successes + 1 >= samples, "{successes}/{samples} converged");
}

#[test]
fn position_axis_converges_where_the_full_pose_cannot() {
    // A planar 2R arm in the xy plane moves its tip in the plane and turns it about z only. A
    // tip target with z pointing along +z (the tool's z is the joint axis) is a 2-D problem:
    // the position + axis target converges; the same position with a pose that tilts the
    // tool's z is unreachable (the joints only rotate about z), so NotConverged.
    let mut b = pin::ModelBuilder::new();
    let limits = JointLimits::position(-3.0, 3.0);
    let j1 = b
        .add_joint(
            "j1",
            JointIndex::UNIVERSE,
            Isometry3::identity(),
            JointKind::Revolute { axis: Vector3::z() },
            limits,
        )
        .unwrap();
    let j2 = b
        .add_joint(
            "j2",
            j1,
            Isometry3::translation(0.5, 0.0, 0.0),
            JointKind::Revolute { axis: Vector3::z() },
            limits,
        )
        .unwrap();
    let tip = b
        .add_frame("tip", j2, Isometry3::translation(0.5, 0.0, 0.0))
        .unwrap();
    let model = b.build().unwrap();
    let settings = IkSettings {
        restarts: 3,
        ..IkSettings::default()
    };
    let solver = IkSolver::new(&model, tip, settings).unwrap();
    let position = Point3::new(0.3, 0.6, 0.0);
    let axis_target = IkTarget::PositionAxis {
        position,
        axis: Vector3::z_axis(),
    };
    let q = converged(solver.solve(&axis_target, &model.neutral()).unwrap()).expect("reachable");
    let reached = tool_pose(&model, tip, &q);
    assert!((reached.translation.vector - position.coords).norm() <= 1e-5);

    let tilted = Isometry3::from_parts(
        position.coords.into(),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.5),
    );
    match solver
        .solve(&IkTarget::Pose(tilted), &model.neutral())
        .unwrap()
    {
        IkOutcome::Infeasible(IkFailure {
            best: IkBest { rotation_error, .. },
            ..
        }) => {
            // Rotations about z keep the tool's z on +z, so a 0.5 rad tilt about x stays.
            assert!(
                rotation_error >= 0.5 - 1e-9,
                "rotation error {rotation_error}"
            );
        }
        other => panic!("a tilted tool is unreachable for a planar arm: {other:?}"),
    }
}

#[test]
fn unreachable_target_is_an_outcome_not_an_error() {
    let (model, tool) = test_arm();
    let settings = IkSettings {
        budget: Duration::from_millis(200),
        restarts: 5,
        ..IkSettings::default()
    };
    let solver = IkSolver::new(&model, tool, settings).unwrap();
    // 2 m beyond the reach bound along x.
    let far = Isometry3::translation(REACH + 2.0, 0.0, 0.3);
    for target in [
        IkTarget::Pose(far),
        IkTarget::PositionAxis {
            position: Point3::new(REACH + 2.0, 0.0, 0.3),
            axis: Vector3::x_axis(),
        },
    ] {
        match solver.solve(&target, &model.neutral()).unwrap() {
            IkOutcome::Infeasible(IkFailure {
                best:
                    IkBest {
                        q: best,
                        position_error,
                        ..
                    },
                reason,
            }) => {
                assert_within_limits(&model, &best);
                // The tool is at most REACH from the root, the target at least REACH + 2.
                assert!(position_error >= 2.0, "position error {position_error}");
                let reached = tool_pose(&model, tool, &best);
                let (ep, _) = target.errors(&reached);
                assert!(
                    (ep - position_error).abs() < 1e-9,
                    "best and its error disagree"
                );
                assert_eq!(reason, NoConvergence::AttemptsExhausted);
            }
            other => panic!("unreachable target converged: {other:?}"),
        }
        let near = solver.solve_near(&target, &model.neutral()).unwrap();
        assert!(near.is_infeasible(), "{near:?}");
    }
}

#[test]
fn budget_bounds_the_solve_time() {
    let (model, tool) = test_arm();
    let budget = Duration::from_millis(30);
    let settings = IkSettings {
        budget,
        restarts: 1_000_000,
        // The wall clock alone ends this solve.
        max_total_iterations: usize::MAX,
        ..IkSettings::default()
    };
    let solver = IkSolver::new(&model, tool, settings).unwrap();
    let target = IkTarget::Pose(Isometry3::translation(REACH + 2.0, 0.0, 0.0));
    let start = std::time::Instant::now();
    let outcome = solver.solve(&target, &model.neutral()).unwrap();
    let elapsed = start.elapsed();
    assert!(
        matches!(outcome, IkOutcome::Timeout(_)),
        "an unreachable target with unbounded restarts ends on the wall clock: {outcome:?}"
    );
    // The budget is checked before every step; one step (FK, Jacobian, a 7-variable QP) takes
    // well under 10 ms even in an unoptimised build, so 30 ms + 100 ms is a loose bound.
    assert!(
        elapsed < budget + Duration::from_millis(100),
        "took {elapsed:?}"
    );
}

#[test]
fn joint_limits_hold_when_the_target_presses_against_them() {
    // A 1-DoF arm: a 1 m link turning about z, limited to [−0.5, 0.5] rad. A tip target at
    // angle 1.0 rad is unreachable; the best configuration must sit exactly at the limit 0.5
    // (the closest reachable tip), not beyond.
    let mut b = pin::ModelBuilder::new();
    let j = b
        .add_joint(
            "j",
            JointIndex::UNIVERSE,
            Isometry3::identity(),
            JointKind::Revolute { axis: Vector3::z() },
            JointLimits::position(-0.5, 0.5),
        )
        .unwrap();
    let tip = b
        .add_frame("tip", j, Isometry3::translation(1.0, 0.0, 0.0))
        .unwrap();
    let model = b.build().unwrap();
    let solver = IkSolver::new(
        &model,
        tip,
        IkSettings {
            restarts: 3,
            ..IkSettings::default()
        },
    )
    .unwrap();
    let target = IkTarget::PositionAxis {
        position: Point3::new(1.0f64.cos(), 1.0f64.sin(), 0.0),
        axis: Vector3::z_axis(),
    };
    // A seed beyond the limit is clamped into it.
    let seed = DVector::from_vec(vec![2.0]);
    match solver.solve(&target, &seed).unwrap() {
        IkOutcome::Infeasible(IkFailure {
            best:
                IkBest {
                    q: best,
                    position_error,
                    ..
                },
            ..
        }) => {
            assert!((best[0] - 0.5).abs() < 1e-9, "{}", best[0]);
            // Chord between angles 1.0 and 0.5 on the unit circle: 2 sin(0.25).
            assert!(
                (position_error - 2.0 * 0.25f64.sin()).abs() < 1e-6,
                "{position_error}"
            );
        }
        other => panic!("target beyond the limit converged: {other:?}"),
    }
}

#[test]
fn solve_near_tracks_a_trajectory_without_jumps() {
    let (model, tool) = test_arm();
    let solver = IkSolver::new(&model, tool, IkSettings::default()).unwrap();
    let mut data = IkData::new(&solver).unwrap();
    // A smooth joint-space path (every scalar joint moves by at most 0.01 rad or 0.005 m per
    // waypoint), its tool poses as targets, solved from the previous solution.
    let q_at = |t: f64| {
        let mut q = model.neutral();
        let (sin, cos) = (0.3 + 0.5 * t).sin_cos();
        q[0] = cos;
        q[1] = sin;
        q[2] = 0.4 + 0.6 * t;
        q[3] = -0.5 + t;
        q[4] = 1.2 - 0.8 * t;
        q[5] = 0.3 * t;
        q[6] = 0.05 + 0.1 * t;
        q[7] = 0.5 - 0.9 * t;
        q[8] = 0.2 + 0.4 * t;
        q
    };
    let steps = 100;
    let mut q = q_at(0.0);
    for k in 1..=steps {
        let target = IkTarget::Pose(tool_pose(&model, tool, &q_at(k as f64 / steps as f64)));
        let outcome = solver.solve_near_with(&mut data, &target, &q).unwrap();
        let Some(next) = converged(outcome.clone()) else {
            panic!("waypoint {k} did not converge: {outcome:?}");
        };
        assert_within_limits(&model, &next);
        // The nominal path moves at most 0.01 per waypoint; with two redundant degrees of
        // freedom a solution may drift along the self-motion, but a jump to another IK branch
        // moves some joint by a large fraction of a radian. 0.05 separates the two.
        let step = pin::difference(&model, &q, &next).unwrap();
        assert!(
            step.amax() < 0.05,
            "waypoint {k}: joint step {}",
            step.amax()
        );
        q = next;
    }
}

#[test]
fn solve_near_at_the_target_does_not_move() {
    let (model, tool) = test_arm();
    let solver = IkSolver::new(&model, tool, IkSettings::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let q = random_q(&model, &mut rng);
    let target = IkTarget::Pose(tool_pose(&model, tool, &q));
    match solver.solve_near(&target, &q).unwrap() {
        IkOutcome::Solved(IkSolution {
            q: found,
            iterations,
            restarts,
        }) => {
            assert_eq!((iterations, restarts), (0, 0));
            assert_eq!(found, q);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn solve_near_stays_closer_to_the_seed_than_solve_from_neutral() {
    // Seeds 0.05 rad away from a random solution: solve_near returns a q near the seed (the
    // nearby solution), while the target is generic, so solving from neutral usually lands on
    // another branch. Only the first property is asserted.
    let (model, tool) = test_arm();
    let solver = IkSolver::new(&model, tool, IkSettings::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..20 {
        let q_true = random_q(&model, &mut rng);
        let target = IkTarget::Pose(tool_pose(&model, tool, &q_true));
        let offset = DVector::from_fn(model.nv(), |_, _| rng.random_range(-0.05..0.05));
        let mut seed = pin::integrate(&model, &q_true, &offset).unwrap();
        // Keep the perturbed seed within limits (the solver would clamp it anyway).
        let (lower, upper) = model.position_bounds();
        for i in 0..seed.len() {
            seed[i] = seed[i].clamp(lower[i], upper[i]);
        }
        let q = converged(solver.solve_near(&target, &seed).unwrap()).expect("nearby target");
        let moved = pin::difference(&model, &seed, &q).unwrap().norm();
        // The seed is at most 0.05·√8 ≈ 0.14 from q_true, which solves the target.
        assert!(moved < 0.2, "moved {moved} from the seed");
    }
}

#[test]
fn solves_are_deterministic_and_work_across_threads() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<IkSolver>();
    let (model, tool) = test_arm();
    let solver = IkSolver::new(&model, tool, IkSettings::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let targets: Vec<IkTarget> = (0..8)
        .map(|_| IkTarget::Pose(tool_pose(&model, tool, &random_q(&model, &mut rng))))
        .collect();
    let neutral = model.neutral();
    let here: Vec<IkOutcome> = targets
        .iter()
        .map(|t| solver.solve(t, &neutral).unwrap())
        .collect();
    let there: Vec<IkOutcome> = std::thread::scope(|s| {
        let handles: Vec<_> = targets
            .iter()
            .map(|t| s.spawn(|| solver.solve(t, &neutral).unwrap()))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(here, there);
}

#[test]
fn bad_input_gives_typed_errors() {
    let (model, tool) = test_arm();
    let solver = IkSolver::new(&model, tool, IkSettings::default()).unwrap();
    let neutral = model.neutral();
    let pose = IkTarget::Pose(Isometry3::translation(0.3, 0.0, 0.5));

    let short = DVector::zeros(model.nq() - 1);
    assert!(matches!(
        solver.solve(&pose, &short),
        Err(IkError::DimensionMismatch { what: "seed", expected, got }) if expected == model.nq() && got == model.nq() - 1
    ));
    let mut nan_seed = neutral.clone();
    nan_seed[3] = f64::NAN;
    assert!(matches!(
        solver.solve(&pose, &nan_seed),
        Err(IkError::NonFinite { what: "seed" })
    ));
    // The (cos, sin) pair of joint j0 off unit length: Pinocchio's check, wrapped.
    let mut off_pair = neutral.clone();
    off_pair[0] = 2.0;
    assert!(matches!(
        solver.solve(&pose, &off_pair),
        Err(IkError::Pinocchio(pin::Error::NotNormalized { .. }))
    ));

    let nan_target = IkTarget::Pose(Isometry3::translation(f64::NAN, 0.0, 0.0));
    assert!(matches!(
        solver.solve_near(&nan_target, &neutral),
        Err(IkError::NonFinite {
            what: "target position"
        })
    ));
    let skewed = IkTarget::PositionAxis {
        position: Point3::new(0.3, 0.0, 0.5),
        axis: Unit::new_unchecked(Vector3::new(1.0, 1.0, 0.0)),
    };
    assert!(matches!(
        solver.solve(&skewed, &neutral),
        Err(IkError::NonUnitAxis { norm }) if (norm - 2f64.sqrt()).abs() < 1e-12
    ));
    let bad_rotation = IkTarget::Pose(Isometry3::from_parts(
        Vector3::zeros().into(),
        UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(2.0, 0.0, 0.0, 0.0)),
    ));
    assert!(matches!(
        solver.solve(&bad_rotation, &neutral),
        Err(IkError::NonUnitRotation { norm }) if norm == 2.0
    ));

    let bad_settings = [
        (
            IkSettings {
                position_tolerance: 0.0,
                ..IkSettings::default()
            },
            "position_tolerance",
        ),
        (
            IkSettings {
                rotation_tolerance: f64::NAN,
                ..IkSettings::default()
            },
            "rotation_tolerance",
        ),
        (
            IkSettings {
                max_step: -1.0,
                ..IkSettings::default()
            },
            "max_step",
        ),
        (
            IkSettings {
                damping: f64::INFINITY,
                ..IkSettings::default()
            },
            "damping",
        ),
        (
            IkSettings {
                max_iterations: 0,
                ..IkSettings::default()
            },
            "max_iterations",
        ),
        (
            IkSettings {
                budget: Duration::ZERO,
                ..IkSettings::default()
            },
            "budget",
        ),
        (
            IkSettings {
                max_total_iterations: 0,
                ..IkSettings::default()
            },
            "max_total_iterations",
        ),
    ];
    for (settings, field) in bad_settings {
        assert!(
            matches!(IkSolver::new(&model, tool, settings), Err(IkError::InvalidSetting(s)) if s.field == field),
            "{field}"
        );
    }

    let frames = model.frames().len();
    assert!(matches!(
        IkSolver::new(&model, FrameIndex(frames + 3), IkSettings::default()),
        Err(IkError::UnknownFrame { index, count }) if index == frames + 3 && count == frames
    ));
    assert!(matches!(
        IkSolver::new(&model, FrameIndex::UNIVERSE, IkSettings::default()),
        Err(IkError::NoDegreesOfFreedom { .. })
    ));

    // Scratch made for another solver's model.
    let (other_model, other_tool) = test_arm();
    let other = IkSolver::new(&other_model, other_tool, IkSettings::default()).unwrap();
    let mut other_data = IkData::new(&other).unwrap();
    assert!(matches!(
        solver.solve_with(&mut other_data, &pose, &neutral),
        Err(IkError::Pinocchio(pin::Error::DataModelMismatch))
    ));
}

// ---------------------------------------------------------------------------------------------
// The shipped Kinova Gen3

/// A Gen3 arm configuration: uniform within the limits, continuous joints in [−π, π).
fn random_gen3(robot: &RobotModel, rng: &mut ChaCha8Rng) -> DVector<f64> {
    let (lower, upper) = robot.arm_bounds();
    DVector::from_fn(robot.dof(), |i, _| {
        rng.random_range(lower[i].max(-PI)..upper[i].min(PI))
    })
}

#[test]
fn gen3_round_trip_from_neutral() {
    let robot = RobotModel::kinova_gen3_mobile();
    let settings = IkSettings::default();
    let solver = IkSolver::for_robot(&robot, settings.clone()).unwrap();
    let mut data = IkData::new(&solver).unwrap();
    let (lower, upper) = robot.arm_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let samples = 200;
    let mut successes = 0;
    for _ in 0..samples {
        let q_true = random_gen3(&robot, &mut rng);
        // The target from the robot's own pure-Rust FK (independent of Pinocchio, which the
        // solver uses).
        let target = robot.base_from_tool(&q_true).unwrap();
        let outcome = solver
            .solve_with(&mut data, &IkTarget::Pose(target), &robot.neutral())
            .unwrap();
        let IkOutcome::Solved(IkSolution { q, .. }) = outcome else {
            continue;
        };
        successes += 1;
        for i in 0..robot.dof() {
            assert!(lower[i] <= q[i] && q[i] <= upper[i], "joint {i}: {}", q[i]);
            // Continuous joints stay within π of the seed.
            if lower[i].is_infinite() {
                assert!((q[i] - robot.neutral()[i]).abs() <= PI + 1e-12);
            }
        }
        let reached = robot.base_from_tool(&q).unwrap();
        let dp = (reached.translation.vector - target.translation.vector).norm();
        let dr = reached.rotation.angle_to(&target.rotation);
        // Pinocchio and the pure-Rust FK agree to ~1e-15 m, far below the tolerances.
        assert!(
            dp <= settings.position_tolerance + 1e-12,
            "position error {dp}"
        );
        assert!(
            dr <= settings.rotation_tolerance + 1e-12,
            "rotation error {dr}"
        );
    }
    // The bar is 99.5 %; on 200 samples at most 1 miss.
    assert!(successes + 1 >= samples, "{successes}/{samples} converged");
}

#[test]
fn gen3_position_axis_grasps() {
    let robot = RobotModel::kinova_gen3_mobile();
    let settings = IkSettings::default();
    let solver = IkSolver::for_robot(&robot, settings.clone()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let samples = 50;
    let mut successes = 0;
    for _ in 0..samples {
        let pose = robot
            .base_from_tool(&random_gen3(&robot, &mut rng))
            .unwrap();
        let position = Point3::from(pose.translation.vector);
        let axis = Unit::new_normalize(pose.rotation * Vector3::z());
        let target = IkTarget::PositionAxis { position, axis };
        let Some(q) = converged(solver.solve(&target, &robot.neutral()).unwrap()) else {
            continue;
        };
        successes += 1;
        let reached = robot.base_from_tool(&q).unwrap();
        let z = reached.rotation * Vector3::z();
        assert!(z.angle(&axis) <= settings.rotation_tolerance + 1e-12);
        assert!(
            (reached.translation.vector - position.coords).norm()
                <= settings.position_tolerance + 1e-12
        );
    }
    assert!(successes + 1 >= samples, "{successes}/{samples} converged");
}

#[test]
fn gen3_solve_near_keeps_continuous_joints_continuous() {
    // A wrist turn through ±π on continuous joint 7 (Actuator7): the solutions must follow it
    // past π (joint values continuing to grow) instead of wrapping back to −π, i.e. no 2π jump.
    let robot = RobotModel::kinova_gen3_mobile();
    let solver = IkSolver::for_robot(&robot, IkSettings::default()).unwrap();
    let mut q_nominal = robot.neutral();
    q_nominal[6] = 3.0;
    let mut q = q_nominal.clone();
    for k in 1..=40 {
        q_nominal[6] = 3.0 + 0.01 * k as f64;
        let target = IkTarget::Pose(robot.base_from_tool(&q_nominal).unwrap());
        let next = converged(solver.solve_near(&target, &q).unwrap())
            .unwrap_or_else(|| panic!("waypoint {k} did not converge"));
        let jump = (&next - &q).amax();
        assert!(jump < 0.05, "waypoint {k}: joint step {jump}");
        q = next;
    }
    assert!(q[6] > PI, "joint 7 ended at {} (wrapped?)", q[6]);
}

// ---------------------------------------------------------------------------------------------
// The dense step path, the Clarabel fallback and the iteration budget

/// Link lengths (m) of the planar 3R arm: joints about z at the origin and at the ends of the
/// first two links, the tool at the end of the third, its +x along the link.
const PLANAR: [f64; 3] = [0.5, 0.4, 0.3];
/// Limits of the planar arm's joints (rad): asymmetric, so that random targets and solutions
/// press against them.
const PLANAR_LIMITS: [(f64, f64); 3] = [(-2.0, 2.5), (-1.5, 2.6), (-2.2, 1.9)];

fn planar_arm() -> (Model, FrameIndex) {
    let mut b = pin::ModelBuilder::new();
    let mut parent = JointIndex::UNIVERSE;
    let mut offset = 0.0;
    for (i, &(lo, hi)) in PLANAR_LIMITS.iter().enumerate() {
        parent = b
            .add_joint(
                &format!("p{i}"),
                parent,
                Isometry3::translation(offset, 0.0, 0.0),
                JointKind::Revolute { axis: Vector3::z() },
                JointLimits::position(lo, hi),
            )
            .unwrap();
        offset = PLANAR[i];
    }
    let tool = b
        .add_frame("tool", parent, Isometry3::translation(offset, 0.0, 0.0))
        .unwrap();
    (b.build().unwrap(), tool)
}

/// The planar arm's tool pose, written out: position `Σ lᵢ (cos φᵢ, sin φᵢ, 0)` with
/// `φᵢ = q₀ + … + qᵢ`, rotation about z by `φ₂`. Independent of Pinocchio and of the solver.
fn planar_fk(q: &DVector<f64>) -> Isometry3<f64> {
    let (mut x, mut y, mut phi) = (0.0, 0.0, 0.0);
    for i in 0..3 {
        phi += q[i];
        x += PLANAR[i] * phi.cos();
        y += PLANAR[i] * phi.sin();
    }
    Isometry3::new(Vector3::new(x, y, 0.0), Vector3::z() * phi)
}

fn random_planar(rng: &mut ChaCha8Rng) -> DVector<f64> {
    DVector::from_fn(3, |i, _| {
        let (lo, hi) = PLANAR_LIMITS[i];
        rng.random_range(lo..=hi)
    })
}

#[test]
fn dense_path_solutions_check_out_by_a_hand_derived_fk() {
    // Every target is the written-out FK of a configuration within the limits, a fifth of them
    // with a joint exactly at a limit. The dense path solves them without Clarabel (the counts
    // say so), within the limits, and the written-out FK of the answer meets the tolerances.
    let (model, tool) = planar_arm();
    let settings = IkSettings {
        step_solver: StepSolver::Dense,
        ..IkSettings::default()
    };
    let solver = IkSolver::new(&model, tool, settings.clone()).unwrap();
    let mut data = IkData::new(&solver).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let samples = 200;
    let (mut successes, mut clarabel_steps) = (0, 0);
    for k in 0..samples {
        let mut q_true = random_planar(&mut rng);
        if k % 5 == 0 {
            let i = k % 3;
            q_true[i] = if k % 2 == 0 {
                PLANAR_LIMITS[i].0
            } else {
                PLANAR_LIMITS[i].1
            };
        }
        let target = planar_fk(&q_true);
        // Pinocchio agrees with the written-out FK (so the two are the same arm).
        let pinocchio = tool_pose(&model, tool, &q_true);
        assert!((pinocchio.translation.vector - target.translation.vector).norm() < 1e-12);
        assert!(pinocchio.rotation.angle_to(&target.rotation) < 1e-12);

        let outcome = solver
            .solve_with(&mut data, &IkTarget::Pose(target), &model.neutral())
            .unwrap();
        clarabel_steps += data.last_solve().clarabel_steps;
        let Some(q) = converged(outcome) else {
            continue;
        };
        successes += 1;
        assert_within_limits(&model, &q);
        let reached = planar_fk(&q);
        let dp = (reached.translation.vector - target.translation.vector).norm();
        let dr = reached.rotation.angle_to(&target.rotation);
        assert!(dp <= settings.position_tolerance, "position error {dp}");
        assert!(dr <= settings.rotation_tolerance, "rotation error {dr}");
    }
    // Non-redundant with limits: a target has at most 2 solutions and one may be outside the
    // limits, so restarts matter, but every target is reachable.
    assert_eq!(successes, samples, "{successes}/{samples} converged");
    assert_eq!(clarabel_steps, 0, "the dense path fell back to Clarabel");
}

#[test]
fn dense_and_clarabel_steps_reach_the_same_solutions() {
    // Both solve each step's QP to its minimiser, so on a non-redundant arm (no null space in
    // which the two could drift apart) from the same seed, with the same restarts, they reach
    // the same solution. Not bit for bit: Clarabel's steps are accurate to ~1e-8, so the
    // descents end one step apart now and then, each somewhere within the tolerances (1e-5 m,
    // 1e-4 rad) of the target, i.e. ~1e-5 rad apart on this arm (its Jacobian's singular values
    // are ≳ 0.1 m away from singularities). 1e-3 rad separates that from another IK branch,
    // which differs by a large fraction of a radian. A budget of 10 s keeps the wall clock
    // (slow Clarabel steps in an unoptimised build) out of it.
    let (model, tool) = planar_arm();
    let settings = IkSettings {
        budget: Duration::from_secs(10),
        ..IkSettings::default()
    };
    let dense = IkSolver::new(&model, tool, settings.clone()).unwrap();
    let clarabel = IkSolver::new(
        &model,
        tool,
        IkSettings {
            step_solver: StepSolver::Clarabel,
            ..settings
        },
    )
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let mut compared = 0;
    for _ in 0..40 {
        let target = IkTarget::Pose(planar_fk(&random_planar(&mut rng)));
        let a = dense.solve(&target, &model.neutral()).unwrap();
        let b = clarabel.solve(&target, &model.neutral()).unwrap();
        match (&a, &b) {
            (
                IkOutcome::Solved(IkSolution {
                    q: qa,
                    restarts: ra,
                    ..
                }),
                IkOutcome::Solved(IkSolution {
                    q: qb,
                    restarts: rb,
                    ..
                }),
            ) => {
                assert_eq!(ra, rb, "{a:?} vs {b:?}");
                assert!((qa - qb).amax() < 1e-3, "{qa} vs {qb}");
                compared += 1;
            }
            _ => panic!("reachable target: {a:?} vs {b:?}"),
        }
    }
    assert_eq!(compared, 40);
}

#[test]
fn clarabel_steps_still_hold_active_limits() {
    // The Clarabel step (the fallback, and every step with StepSolver::Clarabel) on the
    // targets the dense path is tested on: a 1-DoF arm pressed against its limit stops exactly
    // there, and test-arm targets from configurations with joints at their limits converge
    // within the limits.
    let clarabel = IkSettings {
        step_solver: StepSolver::Clarabel,
        restarts: 3,
        // Clarabel steps are slow in an unoptimised build: keep the wall clock out of it.
        budget: Duration::from_secs(10),
        ..IkSettings::default()
    };
    let mut b = pin::ModelBuilder::new();
    let j = b
        .add_joint(
            "j",
            JointIndex::UNIVERSE,
            Isometry3::identity(),
            JointKind::Revolute { axis: Vector3::z() },
            JointLimits::position(-0.5, 0.5),
        )
        .unwrap();
    let tip = b
        .add_frame("tip", j, Isometry3::translation(1.0, 0.0, 0.0))
        .unwrap();
    let one = b.build().unwrap();
    for step_solver in [StepSolver::Dense, StepSolver::Clarabel] {
        let solver = IkSolver::new(
            &one,
            tip,
            IkSettings {
                step_solver,
                ..clarabel.clone()
            },
        )
        .unwrap();
        let target = IkTarget::PositionAxis {
            position: Point3::new(1.0f64.cos(), 1.0f64.sin(), 0.0),
            axis: Vector3::z_axis(),
        };
        let mut data = IkData::new(&solver).unwrap();
        match solver
            .solve_with(&mut data, &target, &DVector::from_vec(vec![0.0]))
            .unwrap()
        {
            IkOutcome::Infeasible(IkFailure {
                best: IkBest { q: best, .. },
                ..
            }) => {
                assert!((best[0] - 0.5).abs() < 1e-9, "{step_solver:?}: {}", best[0])
            }
            other => panic!("{step_solver:?}: beyond the limit, converged: {other:?}"),
        }
        let stats = data.last_solve();
        if step_solver == StepSolver::Clarabel {
            assert_eq!(stats.clarabel_steps, stats.steps);
        }
    }

    let (model, tool) = test_arm();
    let solver = IkSolver::new(&model, tool, clarabel).unwrap();
    let (lower, upper) = model.position_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut successes = 0;
    for k in 0..20 {
        let mut q_true = random_q(&model, &mut rng);
        // Joints j1 (q[2]) and j3 (q[4]) at a limit each.
        q_true[2] = if k % 2 == 0 { lower[2] } else { upper[2] };
        q_true[4] = if k % 3 == 0 { lower[4] } else { upper[4] };
        let target = IkTarget::Pose(tool_pose(&model, tool, &q_true));
        match solver.solve(&target, &model.neutral()).unwrap() {
            IkOutcome::Solved(IkSolution { q, .. }) => {
                assert_within_limits(&model, &q);
                let (ep, er) = target.errors(&tool_pose(&model, tool, &q));
                assert!(ep <= 1e-5 && er <= 1e-4);
                successes += 1;
            }
            other => assert_within_limits(&model, other.best_q()),
        }
    }
    assert!(successes >= 19, "{successes}/20 converged");
}

/// A batch of solves on the test arm whose results the iteration budget decides: hard and
/// unreachable targets, many restarts, at most 300 steps per solve.
fn budgeted_batch(budget: Duration) -> Vec<(IkOutcome, usize)> {
    let (model, tool) = test_arm();
    let settings = IkSettings {
        restarts: usize::MAX,
        max_total_iterations: 300,
        budget,
        // Tight tolerances: more steps per attempt, so the budget binds more often.
        position_tolerance: 1e-9,
        rotation_tolerance: 1e-9,
        ..IkSettings::default()
    };
    let solver = IkSolver::new(&model, tool, settings).unwrap();
    let mut data = IkData::new(&solver).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(24);
    let mut targets: Vec<IkTarget> = (0..12)
        .map(|_| IkTarget::Pose(tool_pose(&model, tool, &random_q(&model, &mut rng))))
        .collect();
    targets.push(IkTarget::Pose(Isometry3::translation(
        REACH + 1.0,
        0.0,
        0.0,
    )));
    targets.push(IkTarget::PositionAxis {
        position: Point3::new(0.0, REACH + 0.5, 0.2),
        axis: Vector3::x_axis(),
    });
    targets
        .iter()
        .map(|t| {
            let outcome = solver.solve_with(&mut data, t, &model.neutral()).unwrap();
            (outcome, data.last_solve().steps)
        })
        .collect()
}

#[test]
fn the_iteration_budget_makes_solves_independent_of_the_machine_load() {
    // The same batch with an hour of wall-clock budget on an idle core, and with one second
    // while two busy threads compete for the cores: equal outcomes, bit for bit (the wall
    // clock never ends a solve: 300 steps take well under a second even unoptimised and
    // shared). The unreachable targets end on the iteration budget after exactly 300 steps.
    let idle = budgeted_batch(Duration::from_secs(3600));
    let stop = std::sync::atomic::AtomicBool::new(false);
    let loaded = std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                let mut x = 0u64;
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
                }
            });
        }
        let batch = budgeted_batch(Duration::from_secs(1));
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        batch
    });
    assert_eq!(idle, loaded);
    let mut budget_ends = 0;
    for (outcome, steps) in &idle {
        assert!(*steps <= 300, "{steps} steps");
        if let IkOutcome::Infeasible(failure) = outcome {
            assert_eq!(failure.reason, NoConvergence::IterationBudget, "{failure}");
            assert_eq!(*steps, 300);
            budget_ends += 1;
        }
    }
    assert!(
        budget_ends >= 2,
        "the unreachable targets end on the iteration budget"
    );
}

/// A planar 2R arm (both joints about +z, so the tool's z stays on +z): a target axis tilted
/// 0.3 rad from +z is out of reach exactly (`PositionAxis`) and within a cone of half-angle
/// 0.35 rad (`PositionCone` converges, the tool's z 0.3 rad from the axis, measured with FK),
/// but not within 0.25 rad (the angle beyond the cone, 0.05 rad, stays). A half-angle outside
/// `[0, π/2]` or NaN is a typed error.
#[test]
fn a_position_cone_accepts_a_tilted_approach_and_nothing_beyond_it() {
    let mut b = pin::ModelBuilder::new();
    let limits = JointLimits::position(-3.0, 3.0);
    let j1 = b
        .add_joint(
            "j1",
            JointIndex::UNIVERSE,
            Isometry3::identity(),
            JointKind::Revolute { axis: Vector3::z() },
            limits,
        )
        .unwrap();
    let j2 = b
        .add_joint(
            "j2",
            j1,
            Isometry3::translation(0.5, 0.0, 0.0),
            JointKind::Revolute { axis: Vector3::z() },
            limits,
        )
        .unwrap();
    let tip = b
        .add_frame("tip", j2, Isometry3::translation(0.5, 0.0, 0.0))
        .unwrap();
    let model = b.build().unwrap();
    let settings = IkSettings {
        restarts: 3,
        ..IkSettings::default()
    };
    let solver = IkSolver::new(&model, tip, settings.clone()).unwrap();
    let position = Point3::new(0.3, 0.6, 0.0);
    let axis = Unit::new_normalize(Vector3::new(0.0, 0.3f64.sin(), 0.3f64.cos()));
    let cone = |half_angle| IkTarget::PositionCone {
        position,
        axis,
        half_angle,
    };
    assert!(
        converged(
            solver
                .solve(&IkTarget::PositionAxis { position, axis }, &model.neutral())
                .unwrap()
        )
        .is_none()
    );
    let q =
        converged(solver.solve(&cone(0.35), &model.neutral()).unwrap()).expect("within the cone");
    let reached = tool_pose(&model, tip, &q);
    assert!((reached.translation.vector - position.coords).norm() <= settings.position_tolerance);
    let tilt = (reached.rotation * Vector3::z()).angle(&axis);
    assert!((tilt - 0.3).abs() < 1e-9, "tilt {tilt}");
    match solver.solve(&cone(0.25), &model.neutral()).unwrap() {
        IkOutcome::Infeasible(IkFailure {
            best: IkBest { rotation_error, .. },
            ..
        }) => assert!(
            (rotation_error - 0.05).abs() < 1e-6,
            "rotation error {rotation_error}"
        ),
        other => panic!("0.3 rad is beyond a 0.25 rad cone: {other:?}"),
    }
    for bad in [-0.1, 2.0, f64::NAN] {
        assert!(
            matches!(
                solver.solve(&cone(bad), &model.neutral()),
                Err(IkError::InvalidCone { .. })
            ),
            "half-angle {bad}"
        );
    }
}
