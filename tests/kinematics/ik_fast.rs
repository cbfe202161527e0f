//! The IK fast path ([`StepSolver::DampedLeastSquares`], the default): damped-least-squares
//! steps, the step QP only when a bound (trust region or joint limit) cuts the step. On the
//! shipped Gen3, every answer is
//! re-checked by the robot's own pure-Rust forward kinematics
//! ([`RobotModel::base_from_tool`], which shares nothing with Pinocchio or the solver):
//! joint limits hold exactly, also when the solution sits on them; converged solutions meet
//! the tolerances; and a solve whose budget is counted in iterations is a bit-for-bit function
//! of (target, seed configuration, settings), whatever the machine's load.

use std::f64::consts::PI;
use std::time::Duration;

use kinscene::kinematics::ik::{
    IkData, IkOutcome, IkSettings, IkSolver, IkTarget, NoConvergence, StepSolver,
};
use kinscene::kinematics::robot::RobotModel;
use nalgebra::{DVector, Isometry3, Point3, Unit, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The TRAC-IK protocol's tolerances and an iteration budget in place of its wall clock: no
/// wall-clock deadline at all (`Duration::MAX` cannot be added to an instant), so nothing in
/// these solves depends on time.
fn protocol_settings() -> IkSettings {
    IkSettings {
        position_tolerance: 1e-5,
        rotation_tolerance: 1e-5,
        restarts: usize::MAX,
        max_total_iterations: 2_000,
        budget: Duration::MAX,
        step_solver: StepSolver::DampedLeastSquares,
        ..IkSettings::default()
    }
}

/// A Gen3 arm configuration uniform within the limits (continuous joints in [−π, π)).
fn random_gen3(robot: &RobotModel, rng: &mut ChaCha8Rng) -> DVector<f64> {
    let (lower, upper) = robot.arm_bounds();
    DVector::from_fn(robot.dof(), |i, _| {
        rng.random_range(lower[i].max(-PI)..upper[i].min(PI))
    })
}

/// The middle of the Gen3's limits (0 for continuous joints): the protocol's seed.
fn middle(robot: &RobotModel) -> DVector<f64> {
    let (lower, upper) = robot.arm_bounds();
    DVector::from_fn(robot.dof(), |i, _| {
        if lower[i].is_finite() && upper[i].is_finite() {
            0.5 * (lower[i] + upper[i])
        } else {
            0.0
        }
    })
}

/// Every limited joint of `q` within its limits, exactly (no tolerance: the solver clamps).
fn assert_within_limits(robot: &RobotModel, q: &DVector<f64>) {
    let (lower, upper) = robot.arm_bounds();
    for i in 0..robot.dof() {
        assert!(
            lower[i] <= q[i] && q[i] <= upper[i],
            "joint {i} = {} outside [{}, {}]",
            q[i],
            lower[i],
            upper[i]
        );
    }
}

/// Position and rotation error (m, rad) of `q` for `target`, by the robot's pure-Rust FK.
fn errors_by_robot_fk(robot: &RobotModel, q: &DVector<f64>, target: &IkTarget) -> (f64, f64) {
    let reached = robot.base_from_tool(q).unwrap();
    match target {
        IkTarget::Pose(pose) => (
            (reached.translation.vector - pose.translation.vector).norm(),
            reached.rotation.angle_to(&pose.rotation),
        ),
        IkTarget::PositionAxis { position, axis } => (
            (reached.translation.vector - position.coords).norm(),
            (reached.rotation * Vector3::z()).angle(axis),
        ),
        IkTarget::PositionCone {
            position,
            axis,
            half_angle,
        } => (
            (reached.translation.vector - position.coords).norm(),
            ((reached.rotation * Vector3::z()).angle(axis) - half_angle).max(0.0),
        ),
    }
}

#[test]
fn fast_path_solutions_check_out_by_the_robots_own_fk() {
    // 150 full poses and 50 position + axis targets of random configurations, solved on the
    // TRAC-IK protocol from the middle of the limits. Every solution: within the limits and
    // within the tolerances by the pure-Rust FK (Pinocchio and it agree to ~1e-15 m, so 1e-12
    // of slack is rounding only). Most steps are the plain damped-least-squares step.
    let robot = RobotModel::kinova_gen3_mobile();
    let settings = protocol_settings();
    let solver = IkSolver::for_robot(&robot, settings.clone()).unwrap();
    let mut data = IkData::new(&solver).unwrap();
    let seed = middle(&robot);
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let samples = 200;
    let (mut solved, mut steps, mut qp_steps) = (0, 0, 0);
    for k in 0..samples {
        let pose = robot
            .base_from_tool(&random_gen3(&robot, &mut rng))
            .unwrap();
        let target = if k < 150 {
            IkTarget::Pose(pose)
        } else {
            IkTarget::PositionAxis {
                position: Point3::from(pose.translation.vector),
                axis: Unit::new_normalize(pose.rotation * Vector3::z()),
            }
        };
        let outcome = solver.solve_with(&mut data, &target, &seed).unwrap();
        steps += data.last_solve().steps;
        qp_steps += data.last_solve().qp_steps;
        assert_within_limits(&robot, outcome.best_q());
        let Some(q) = outcome.q() else { continue };
        solved += 1;
        let (dp, dr) = errors_by_robot_fk(&robot, q, &target);
        assert!(
            dp <= settings.position_tolerance + 1e-12,
            "target {k}: {dp} m"
        );
        assert!(
            dr <= settings.rotation_tolerance + 1e-12,
            "target {k}: {dr} rad"
        );
    }
    assert!(
        2 * qp_steps < steps,
        "{qp_steps} of {steps} steps solved the QP"
    );
    // The goal is 99.9 % (the bench measures it on 10 000 targets): no miss on 200.
    assert_eq!(solved, samples, "{solved}/{samples} converged");
}

#[test]
fn fast_path_holds_joint_limits_when_the_solution_lies_on_them() {
    // Targets of configurations with one or more limited joints (the Gen3's joints 2, 4 and
    // 6) exactly at a limit, so that descents press against the limits and the fast path
    // hands steps to the QP. Every answer, converged or not, is within the limits; some steps
    // solved the QP and at least one converged answer has a joint exactly at a limit (else
    // the limits were never active), and every converged one meets the tolerances by the
    // pure-Rust FK.
    let robot = RobotModel::kinova_gen3_mobile();
    let (lower, upper) = robot.arm_bounds();
    let limited: Vec<usize> = (0..robot.dof()).filter(|&i| lower[i].is_finite()).collect();
    assert!(limited.len() >= 3, "the Gen3 has limited joints");
    let settings = protocol_settings();
    let solver = IkSolver::for_robot(&robot, settings.clone()).unwrap();
    let mut data = IkData::new(&solver).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let (mut solved, mut on_a_limit, mut qp_steps) = (0, 0, 0);
    for _ in 0..60 {
        let mut q_true = random_gen3(&robot, &mut rng);
        for &i in &limited {
            if rng.random_bool(0.6) {
                q_true[i] = if rng.random_bool(0.5) {
                    lower[i]
                } else {
                    upper[i]
                };
            }
        }
        let target = IkTarget::Pose(robot.base_from_tool(&q_true).unwrap());
        let outcome = solver
            .solve_with(&mut data, &target, &robot.neutral())
            .unwrap();
        qp_steps += data.last_solve().qp_steps;
        assert_within_limits(&robot, outcome.best_q());
        let Some(q) = outcome.q() else { continue };
        solved += 1;
        let (dp, dr) = errors_by_robot_fk(&robot, q, &target);
        assert!(dp <= settings.position_tolerance + 1e-12, "{dp} m");
        assert!(dr <= settings.rotation_tolerance + 1e-12, "{dr} rad");
        if limited
            .iter()
            .any(|&i| q[i] == lower[i] || q[i] == upper[i])
        {
            on_a_limit += 1;
        }
    }
    assert!(solved >= 57, "{solved}/60 converged");
    assert!(qp_steps > 0, "no step solved the QP");
    assert!(on_a_limit >= 1, "no solution on a limit");
}

/// A batch of Gen3 solves that the iteration budget decides: random targets, one beyond the
/// reach (it can only end on the budget), tolerances of 1e-9 so that descents are long; q and
/// the step count of each.
fn budgeted_batch(settings: &IkSettings) -> Vec<(Vec<u64>, bool, usize)> {
    let robot = RobotModel::kinova_gen3_mobile();
    let solver = IkSolver::for_robot(&robot, settings.clone()).unwrap();
    let mut data = IkData::new(&solver).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    let mut targets: Vec<IkTarget> = (0..8)
        .map(|_| {
            IkTarget::Pose(
                robot
                    .base_from_tool(&random_gen3(&robot, &mut rng))
                    .unwrap(),
            )
        })
        .collect();
    targets.push(IkTarget::Pose(Isometry3::translation(3.0, 0.0, 0.5)));
    targets
        .iter()
        .map(|target| {
            let outcome = solver
                .solve_with(&mut data, target, &robot.neutral())
                .unwrap();
            let bits = outcome.best_q().iter().map(|x| x.to_bits()).collect();
            if let IkOutcome::Infeasible(failure) = &outcome {
                assert_eq!(failure.reason, NoConvergence::IterationBudget);
            }
            (bits, outcome.q().is_some(), data.last_solve().steps)
        })
        .collect()
}

#[test]
fn iteration_budgeted_solves_are_bit_identical_under_load() {
    // 300 steps a solve, no wall clock. The same batch idle and with two threads spinning on
    // both cores gives the same q bit for bit; a different restart seed changes the batch (the
    // targets that needed restarts converge elsewhere), so the seed is what the answer
    // depends on.
    let settings = IkSettings {
        position_tolerance: 1e-9,
        rotation_tolerance: 1e-9,
        max_total_iterations: 300,
        ..protocol_settings()
    };
    let idle = budgeted_batch(&settings);
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
        let batch = budgeted_batch(&settings);
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        batch
    });
    assert_eq!(idle, loaded);
    let unreachable = idle.last().unwrap();
    assert!(!unreachable.1);
    assert_eq!(unreachable.2, 300, "ends on the iteration budget");
    assert!(idle.iter().filter(|(_, solved, _)| *solved).count() >= 6);
    let reseeded = budgeted_batch(&IkSettings {
        seed: settings.seed + 1,
        ..settings.clone()
    });
    assert_ne!(reseeded, idle);
}
