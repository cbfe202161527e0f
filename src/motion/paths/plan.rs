//! The two planning entry points: input checks, the OMPL call, status mapping.

use std::f64::consts::PI;
use std::sync::RwLock;

use kinscene_ompl::{
    MotionValidator, PlanOutcome, PlanSettings, PlanStatus, Problem, StateSpace,
    StateValidityChecker, Termination,
};

use super::{PathError, PathFailure, PathOutcome, PathSettings};
use crate::InvalidSetting;
use crate::kinematics::robot::ArmCheck;

/// Half-width (rad) of the window a continuous joint (infinite bounds) is planned in: the
/// joint is bounded to `[min(start, goal) − W, max(start, goal) + W]`, one half turn of slack
/// on either side of the straight motion, so the planner can detour around an obstacle in
/// either direction. The goal value is kept as given (no 2π unwrapping): callers who want the
/// shorter way round should pass the goal representative nearest to the start.
pub const CONTINUOUS_JOINT_WINDOW: f64 = PI;

/// Serialises seeded plans (write lock) against every other plan of this module (read lock):
/// OMPL draws every sampler's seed from one process-wide generator.
static OMPL_RNG: RwLock<()> = RwLock::new(());

/// Plans a base path in SE(2) from `start` to `goal` (`[x, y, yaw]`, metres and radians).
///
/// `bounds` = `([x_min, y_min], [x_max, y_max])` bounds x and y; yaw is free and wraps. The
/// closure `valid` sees states with yaw in `[-π, π]`. Planning stops at the earlier of
/// `termination` and [`PathSettings::budget`] from now ([`Timeout`](crate::Outcome::Timeout)), or when its
/// cancel flag is raised ([`Cancelled`](crate::Outcome::Cancelled)).
///
/// The returned path follows the module's conventions: yaw unwrapped from `start[2]`. A goal
/// outside the bounds is [`PathFailure::InvalidGoal`], as in OMPL.
///
/// # Errors
/// [`PathError::NonFinite`] for NaN or infinite coordinates or bounds,
/// [`PathError::InvalidBounds`], [`PathError::StartOutOfBounds`],
/// [`PathError::InvalidSetting`] (see [`PathSettings::validate`]), and [`PathError::Ompl`]
/// when the backend cannot be loaded or throws.
pub fn plan_base(
    start: [f64; 3],
    goal: [f64; 3],
    bounds: ([f64; 2], [f64; 2]),
    valid: &(dyn Fn(&[f64; 3]) -> bool + Sync),
    settings: &PathSettings,
    termination: &crate::control::Termination<'_>,
) -> Result<PathOutcome, PathError> {
    settings.validate()?;
    let (lower, upper) = bounds;
    check_finite("xy bounds", lower.iter().chain(&upper))?;
    check_finite("start", &start)?;
    check_finite("goal", &goal)?;
    check_bounds(&lower, &upper)?;
    check_start(&start[..2], &lower, &upper)?;

    let space = StateSpace::Se2 {
        x: [lower[0], upper[0]],
        y: [lower[1], upper[1]],
    };
    let extent = (upper[0] - lower[0]).hypot(upper[1] - lower[1]) + 0.5 * PI;
    let checker = |q: &[f64]| q.len() == 3 && valid(&[q[0], q[1], q[2]]);
    let problem = Problem::new(space, start.to_vec(), goal.to_vec());
    let outcome = run(&problem, &checker, None, extent, settings, termination)?;
    Ok(match outcome {
        PathOutcome::Solved(mut path) => {
            unwrap_yaw(&mut path, &start);
            PathOutcome::Solved(path)
        }
        other => other,
    })
}

/// Plans an arm path in joint space from `start` to `goal` within `lower ≤ q ≤ upper`.
///
/// An infinite bound (a continuous joint, ±∞) is replaced by a finite window around the start
/// and goal values, see [`CONTINUOUS_JOINT_WINDOW`]. The closure `valid` sees states inside
/// the (windowed) bounds. A goal outside the bounds is [`PathFailure::InvalidGoal`], as in
/// OMPL. The returned path's first state is `start`. `termination` as for [`plan_base`].
///
/// # Errors
/// [`PathError::ZeroDimension`], [`PathError::DimensionMismatch`] (goal and bounds against
/// start), [`PathError::NonFinite`] (NaN anywhere, an infinite start or goal),
/// [`PathError::InvalidBounds`] (lower > upper, lower = +∞ or upper = −∞),
/// [`PathError::StartOutOfBounds`], [`PathError::InvalidSetting`], [`PathError::Ompl`].
pub fn plan_arm(
    start: &[f64],
    goal: &[f64],
    lower: &[f64],
    upper: &[f64],
    valid: &(dyn Fn(&[f64]) -> bool + Sync),
    settings: &PathSettings,
    termination: &crate::control::Termination<'_>,
) -> Result<PathOutcome, PathError> {
    plan_arm_with_motion(
        start,
        goal,
        lower,
        upper,
        valid,
        None,
        settings,
        termination,
    )
}

/// [`plan_arm`] with the arm's fast exact check: states by [`ArmCheck::is_valid`], motions by
/// [`ArmCheck::check_motion`] (one call into Rust per motion in place of one per state,
/// scratch reused). With the check's default continuous motions every segment of the
/// returned path is certified free, however thin the obstacles; with
/// [`ArmCheck::with_continuous`]`(false)` the states OMPL's discrete motion check would visit
/// at [`PathSettings::resolution`] are checked, each with the exact parry answer.
///
/// # Errors
/// As [`plan_arm`].
///
/// [`ArmCheck::is_valid`]: crate::kinematics::robot::ArmCheck::is_valid
/// [`ArmCheck::check_motion`]: crate::kinematics::robot::ArmCheck::check_motion
/// [`ArmCheck::with_continuous`]: crate::kinematics::robot::ArmCheck::with_continuous
pub fn plan_arm_checked(
    start: &[f64],
    goal: &[f64],
    lower: &[f64],
    upper: &[f64],
    check: &ArmCheck<'_>,
    settings: &PathSettings,
    termination: &crate::control::Termination<'_>,
) -> Result<PathOutcome, PathError> {
    let valid = |q: &[f64]| check.is_valid(q);
    let resolution = settings.resolution;
    let motion = |a: &[f64], b: &[f64]| check.check_motion(a, b, resolution);
    // `check_motion` checks its end state itself.
    plan_arm_inner(
        start,
        goal,
        lower,
        upper,
        &valid,
        Some((&motion, true)),
        settings,
        termination,
    )
}

/// A whole-motion check for [`plan_arm_with_motion`]: whether the straight joint-space motion
/// from the first configuration to the second is free, e.g. a certified
/// [`ArmCheck::check_motion`](crate::kinematics::robot::ArmCheck::check_motion).
pub type MotionCheck<'a> = dyn Fn(&[f64], &[f64]) -> bool + Sync + 'a;

/// [`plan_arm`] with an optional whole-motion check. With `Some(motion)`, OMPL (planner and
/// simplifier) accepts a motion `a → b` when `valid(b)` and `motion(a, b)` both hold, in place
/// of its discrete check of `valid` every [`PathSettings::resolution`]; `valid` still decides
/// the start, the goal and the sampled states. With a certified `motion` (one that accepts
/// only free motions, such as [`ArmCheck::check_motion`]), every returned segment is free
/// however thin the obstacles. With `None` this is [`plan_arm`].
///
/// # Errors
/// As [`plan_arm`].
///
/// [`ArmCheck::check_motion`]: crate::kinematics::robot::ArmCheck::check_motion
#[allow(clippy::too_many_arguments)]
pub fn plan_arm_with_motion(
    start: &[f64],
    goal: &[f64],
    lower: &[f64],
    upper: &[f64],
    valid: &(dyn Fn(&[f64]) -> bool + Sync),
    motion: Option<&MotionCheck<'_>>,
    settings: &PathSettings,
    termination: &crate::control::Termination<'_>,
) -> Result<PathOutcome, PathError> {
    plan_arm_inner(
        start,
        goal,
        lower,
        upper,
        valid,
        motion.map(|m| (m, false)),
        settings,
        termination,
    )
}

/// [`plan_arm_with_motion`], the motion check with whether it checks its end state itself
/// (then `valid` is not asked for it first).
#[allow(clippy::too_many_arguments)]
fn plan_arm_inner(
    start: &[f64],
    goal: &[f64],
    lower: &[f64],
    upper: &[f64],
    valid: &(dyn Fn(&[f64]) -> bool + Sync),
    motion: Option<(&MotionCheck<'_>, bool)>,
    settings: &PathSettings,
    termination: &crate::control::Termination<'_>,
) -> Result<PathOutcome, PathError> {
    settings.validate()?;
    let dim = start.len();
    if dim == 0 {
        return Err(PathError::ZeroDimension);
    }
    for (what, v) in [
        ("goal", goal),
        ("lower bounds", lower),
        ("upper bounds", upper),
    ] {
        if v.len() != dim {
            return Err(PathError::DimensionMismatch {
                what,
                expected: dim,
                got: v.len(),
            });
        }
    }
    check_finite("start", start)?;
    check_finite("goal", goal)?;
    for (what, v) in [("lower bounds", lower), ("upper bounds", upper)] {
        if let Some(index) = v.iter().position(|x| x.is_nan()) {
            return Err(PathError::NonFinite {
                what,
                index,
                value: v[index],
            });
        }
    }
    check_bounds(lower, upper)?;
    check_start(start, lower, upper)?;

    // Continuous joints: a finite window around the start and goal values.
    let window_lower: Vec<f64> = (0..dim)
        .map(|i| match lower[i] {
            l if l.is_finite() => l,
            _ => start[i].min(goal[i]) - CONTINUOUS_JOINT_WINDOW,
        })
        .collect();
    let window_upper: Vec<f64> = (0..dim)
        .map(|i| match upper[i] {
            u if u.is_finite() => u,
            _ => start[i].max(goal[i]) + CONTINUOUS_JOINT_WINDOW,
        })
        .collect();
    let extent = window_lower
        .iter()
        .zip(&window_upper)
        .map(|(l, u)| (u - l).powi(2))
        .sum::<f64>()
        .sqrt();
    let space = StateSpace::RealVector {
        lower: window_lower,
        upper: window_upper,
    };
    let checker = |q: &[f64]| valid(q);
    let whole = motion
        .map(|(m, checks_end)| move |a: &[f64], b: &[f64]| (checks_end || valid(b)) && m(a, b));
    let whole = whole.as_ref().map(|m| m as &dyn MotionValidator);
    let problem = Problem::new(space, start.to_vec(), goal.to_vec());
    let settings = &PathSettings {
        range: settings
            .range
            .or(Some(ARM_RANGE.min(OMPL_RANGE_FRACTION * extent))),
        ..settings.clone()
    };
    let outcome = run(&problem, &checker, whole, extent, settings, termination)?;
    Ok(match outcome {
        PathOutcome::Solved(mut path) => {
            // OMPL copies the start's values; make that exact whatever the shim does.
            path[0].copy_from_slice(start);
            PathOutcome::Solved(path)
        }
        other => other,
    })
}

/// OMPL's default range of most planners, as a fraction of the space's maximum extent.
const OMPL_RANGE_FRACTION: f64 = 0.2;

/// An arm path's default range (rad, or m for prismatic joints: the joint-space Euclidean
/// distance; [`PathSettings::range`] `None`): OMPL's own, a fifth of the space's maximum
/// extent, but at most this. On the MotionBenchMaker Panda set (extent 13 rad, so OMPL's
/// range is 2.6 rad) RRTConnect with the exact arm check had a p95 of 99 ms at OMPL's range
/// and 17 ms at 0.75 rad, the median 2.2 against 2.1 ms, and solved 3 more problems
/// (`cargo bench --bench mbm -- range=R`): long extensions into clutter fail late and are
/// thrown away.
pub const ARM_RANGE: f64 = 0.75;

/// The OMPL call (seeded or not) and the status mapping.
fn run<C: StateValidityChecker>(
    problem: &Problem,
    checker: &C,
    motion: Option<&dyn MotionValidator>,
    extent: f64,
    settings: &PathSettings,
    termination: &crate::control::Termination<'_>,
) -> Result<PathOutcome, PathError> {
    // OMPL checks motions every `fraction × extent`; it rejects fractions outside (ε, 1 − ε).
    let fraction = (settings.resolution / extent).min(0.5);
    if fraction < f64::EPSILON {
        return Err(InvalidSetting::new(
            "resolution",
            settings.resolution,
            format!("at least machine epsilon times the space's maximum extent ({extent})"),
        )
        .into());
    }
    let ompl_settings = PlanSettings {
        planner: settings.planner,
        range: settings.range,
        resolution_fraction: fraction,
        simplify: settings.simplify,
        simplifier: settings.simplifier,
        max_iterations: settings.max_iterations,
        ..PlanSettings::default()
    };
    // The shim is loaded before the budget starts (the first call's load is not planning).
    kinscene_ompl::load()?;
    // The one conversion to OMPL's condition: this call's share of the caller's condition,
    // capped by the per-path budget.
    let ours = termination.capped(settings.budget);
    let budget = ours.remaining().unwrap_or(settings.budget);
    if ours.should_stop() || budget.is_zero() {
        return Ok(PathOutcome::stopped(&ours, ()));
    }
    let deadline = std::time::Instant::now() + budget;
    let mut termination = Termination::after(budget);
    if let Some(flag) = ours.cancel_flag() {
        termination = termination.with_cancel(flag);
    }
    let outcome = match settings.seed {
        Some(seed) => {
            // A poisoned lock only means another plan panicked; the guarded state is `()`.
            let _exclusive = OMPL_RNG.write().unwrap_or_else(|e| e.into_inner());
            kinscene_ompl::set_seed(seed)?;
            kinscene_ompl::plan_with_motion(problem, checker, motion, &ompl_settings, termination)?
        }
        None => {
            let _shared = OMPL_RNG.read().unwrap_or_else(|e| e.into_inner());
            kinscene_ompl::plan_with_motion(problem, checker, motion, &ompl_settings, termination)?
        }
    };
    Ok(map_outcome(
        outcome,
        std::time::Instant::now() >= deadline || ours.should_stop(),
        settings.max_iterations,
    ))
}

/// OMPL's status as a [`PathOutcome`]; approximate solutions are not paths. OMPL's planners
/// return an approximate solution when their termination condition stops them, so one that
/// comes back after the budget ran out (`expired`) is a [`PathOutcome::Timeout`], and one that
/// the iteration budget ended is [`PathFailure::IterationBudget`].
fn map_outcome(outcome: PlanOutcome, expired: bool, max_iterations: Option<u64>) -> PathOutcome {
    let failure = match outcome.status {
        PlanStatus::ExactSolution if !outcome.path.is_empty() => {
            return PathOutcome::Solved(outcome.path);
        }
        PlanStatus::Timeout | PlanStatus::ApproximateSolution if outcome.iteration_budget_spent => {
            PathFailure::IterationBudget {
                iterations: max_iterations.unwrap_or(outcome.iterations),
            }
        }
        PlanStatus::Timeout => return PathOutcome::Timeout(()),
        PlanStatus::ApproximateSolution if expired => return PathOutcome::Timeout(()),
        PlanStatus::Cancelled => return PathOutcome::Cancelled(()),
        PlanStatus::ApproximateSolution => PathFailure::Approximate {
            goal_distance: outcome.goal_distance.unwrap_or(f64::INFINITY),
            checker_panics: outcome.checker_panics,
        },
        PlanStatus::InvalidStart => PathFailure::InvalidStart,
        PlanStatus::InvalidGoal => PathFailure::InvalidGoal,
        status => PathFailure::Planner {
            status,
            checker_panics: outcome.checker_panics,
        },
    };
    PathOutcome::Infeasible(failure)
}

/// Rewrites the yaws of an SE(2) path so that the first is `start[2]` and each differs from
/// the previous one by the shortest angle (at most π).
fn unwrap_yaw(path: &mut [Vec<f64>], start: &[f64; 3]) {
    let mut previous_raw = start[2];
    let mut previous = start[2];
    for (k, q) in path.iter_mut().enumerate() {
        let raw = q[2];
        let yaw = if k == 0 {
            start[2]
        } else {
            previous + (raw - previous_raw).sin().atan2((raw - previous_raw).cos())
        };
        previous_raw = raw;
        previous = yaw;
        q[2] = yaw;
    }
    if let Some(first) = path.first_mut() {
        first.copy_from_slice(start);
    }
}

fn check_finite<'a>(
    what: &'static str,
    values: impl IntoIterator<Item = &'a f64>,
) -> Result<(), PathError> {
    match values.into_iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((index, &value)) => Err(PathError::NonFinite { what, index, value }),
        None => Ok(()),
    }
}

/// `lower ≤ upper`, `lower ≠ +∞`, `upper ≠ −∞` (NaN already excluded).
fn check_bounds(lower: &[f64], upper: &[f64]) -> Result<(), PathError> {
    let bad = |l: f64, u: f64| l > u || l == f64::INFINITY || u == f64::NEG_INFINITY;
    match (0..lower.len()).find(|&i| bad(lower[i], upper[i])) {
        Some(axis) => Err(PathError::InvalidBounds {
            axis,
            lower: lower[axis],
            upper: upper[axis],
        }),
        None => Ok(()),
    }
}

/// The start within the bounds, with OMPL's tolerance (machine epsilon, absolute).
fn check_start(start: &[f64], lower: &[f64], upper: &[f64]) -> Result<(), PathError> {
    let outside =
        |i: usize| start[i] - f64::EPSILON > upper[i] || start[i] + f64::EPSILON < lower[i];
    match (0..start.len()).find(|&i| outside(i)) {
        Some(axis) => Err(PathError::StartOutOfBounds {
            axis,
            value: start[axis],
            lower: lower[axis],
            upper: upper[axis],
        }),
        None => Ok(()),
    }
}
