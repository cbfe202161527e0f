//! Solving a [`Problem`]: the planner call, its status and its path.

use std::ptr;
use std::sync::atomic::Ordering;
use std::time::Duration;

use crate::checker::{
    CheckerContext, MotionContext, MotionValidator, StateValidityChecker, cancel_trampoline,
    path_sink,
};
use crate::ffi::{self, PlanRequest, PlanResult, api};
use crate::{Error, PlanSettings, Problem, StateSpace, Termination};

/// How planning ended (OMPL's `PlannerStatus`, plus [`Cancelled`](PlanStatus::Cancelled)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum PlanStatus {
    /// A path reaching the goal within the goal tolerance.
    ExactSolution,
    /// The path ending closest to the goal; see [`PlanOutcome::goal_distance`].
    ApproximateSolution,
    /// The budget ran out without any path.
    Timeout,
    /// The cancel flag stopped planning before an exact solution (OMPL sees a timeout or an
    /// approximate solution; an approximate path, if any, is still returned, unsimplified).
    Cancelled,
    /// The start is out of bounds or rejected by the checker (checked before planning, the
    /// same way for every planner).
    InvalidStart,
    /// The goal is out of bounds or rejected by the checker.
    InvalidGoal,
    /// The planner does not handle this goal type.
    UnrecognizedGoalType,
    /// The planner crashed.
    Crash,
    /// The planner gave up for another reason.
    Abort,
    /// OMPL returned no status.
    Unknown,
}

impl PlanStatus {
    fn from_ompl(status: i32) -> PlanStatus {
        match status {
            1 => PlanStatus::InvalidStart,
            2 => PlanStatus::InvalidGoal,
            3 => PlanStatus::UnrecognizedGoalType,
            4 => PlanStatus::Timeout,
            5 => PlanStatus::ApproximateSolution,
            6 => PlanStatus::ExactSolution,
            7 => PlanStatus::Crash,
            8 => PlanStatus::Abort,
            _ => PlanStatus::Unknown,
        }
    }
}

/// The result of [`plan`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOutcome {
    /// How planning ended.
    pub status: PlanStatus,
    /// The states of the path, start first (empty when there is none). Consecutive states are
    /// connected by the space's interpolation (straight lines; shortest angle for yaw).
    pub path: Vec<Vec<f64>>,
    /// Distance (the space's) from the path's last state to the goal; `None` without a path.
    pub goal_distance: Option<f64>,
    /// Wall-clock time of set-up and the planner's `solve`.
    pub planning_time: Duration,
    /// Wall-clock time of simplification and interpolation.
    pub simplification_time: Duration,
    /// Panics caught in the validity checker (each counted as an invalid state) and in the
    /// motion validator, if any (each counted as an invalid motion).
    pub checker_panics: usize,
    /// The termination checks the planner's `solve` made: about one per iteration (0 when
    /// the start or goal was rejected before planning).
    pub iterations: u64,
    /// Whether [`PlanSettings::max_iterations`](crate::PlanSettings::max_iterations) ended the
    /// search.
    pub iteration_budget_spent: bool,
}

impl PlanOutcome {
    /// True for [`PlanStatus::ExactSolution`].
    pub fn is_exact(&self) -> bool {
        self.status == PlanStatus::ExactSolution
    }
}

/// Plans a path for `problem` with OMPL, checking states with `checker`.
///
/// A new OMPL `SpaceInformation`, `ProblemDefinition` and planner are built for every call, so
/// calls from several threads are independent (except for OMPL's global random generator, see
/// [`set_seed`](crate::set_seed)).
///
/// # Errors
/// Bad input: the variants of [`Problem::validate`], [`PlanSettings::validate`] and
/// [`Termination::validate`]. [`Error::Load`] when the shim cannot be loaded,
/// [`Error::Backend`] when OMPL throws (e.g. a space of zero extent). Not finding a path is not
/// an error: see [`PlanOutcome::status`].
///
/// # Example
/// ```
/// use std::time::Duration;
/// use kinscene_ompl::{plan, PlanSettings, Problem, StateSpace, Termination};
///
/// let space = StateSpace::RealVector { lower: vec![0.0; 2], upper: vec![1.0; 2] };
/// let problem = Problem::new(space, vec![0.1, 0.1], vec![0.9, 0.9]);
/// // Valid outside the disc of radius 0.2 around the centre.
/// let free = |q: &[f64]| (q[0] - 0.5).powi(2) + (q[1] - 0.5).powi(2) > 0.04;
/// let outcome = plan(&problem, &free, &PlanSettings::default(),
///                    Termination::after(Duration::from_secs(1)))?;
/// assert!(outcome.is_exact());
/// assert_eq!(outcome.path.first(), Some(&vec![0.1, 0.1]));
/// # Ok::<(), kinscene_ompl::Error>(())
/// ```
pub fn plan<C: StateValidityChecker + ?Sized>(
    problem: &Problem,
    checker: &C,
    settings: &PlanSettings,
    termination: Termination<'_>,
) -> Result<PlanOutcome, Error> {
    plan_with_motion::<C, dyn MotionValidator>(problem, checker, None, settings, termination)
}

/// [`plan`] with an optional [`MotionValidator`]: with `Some(validator)`, it decides every
/// motion the planner and the simplifier check (OMPL's `SpaceInformation::setMotionValidator`)
/// and [`PlanSettings::resolution_fraction`] is unused; with `None` this is [`plan`] (OMPL's
/// discrete motion check at that resolution). States are still checked by `checker` (samples,
/// start and goal).
///
/// # Errors
/// As [`plan`].
///
/// # Example
/// ```
/// use std::time::Duration;
/// use kinscene_ompl::{plan_with_motion, PlanSettings, Problem, StateSpace, Termination};
///
/// let space = StateSpace::RealVector { lower: vec![0.0; 2], upper: vec![1.0; 2] };
/// let problem = Problem::new(space, vec![0.1, 0.5], vec![0.9, 0.5]);
/// // A wall x = 0.5 of zero thickness with a gap at y > 0.8: no state is in collision, only
/// // motions crossing the wall below the gap are.
/// let free = |_: &[f64]| true;
/// let crosses = |a: &[f64], b: &[f64]| {
///     if (a[0] - 0.5) * (b[0] - 0.5) > 0.0 { return false; }
///     let t = if a[0] == b[0] { 0.0 } else { (0.5 - a[0]) / (b[0] - a[0]) };
///     a[1] + t * (b[1] - a[1]) <= 0.8
/// };
/// let motion = |a: &[f64], b: &[f64]| !crosses(a, b);
/// let outcome = plan_with_motion(&problem, &free, Some(&motion), &PlanSettings::default(),
///                                Termination::after(Duration::from_secs(1)))?;
/// assert!(outcome.is_exact());
/// assert!(outcome.path.windows(2).all(|w| motion(&w[0], &w[1])));
/// # Ok::<(), kinscene_ompl::Error>(())
/// ```
pub fn plan_with_motion<C: StateValidityChecker + ?Sized, M: MotionValidator + ?Sized>(
    problem: &Problem,
    checker: &C,
    motion: Option<&M>,
    settings: &PlanSettings,
    termination: Termination<'_>,
) -> Result<PlanOutcome, Error> {
    problem.validate()?;
    settings.validate()?;
    termination.validate()?;
    let api = api()?;

    let (lower, upper) = problem.space.bounds();
    let request = PlanRequest {
        space: match problem.space {
            StateSpace::Se2 { .. } => ffi::SPACE_SE2,
            StateSpace::RealVector { .. } => ffi::SPACE_REAL_VECTOR,
        },
        planner: settings.planner.to_ffi(),
        dim: problem.space.dimension(),
        bounds_len: lower.len(),
        lower: lower.as_ptr(),
        upper: upper.as_ptr(),
        start: problem.start.as_ptr(),
        goal: problem.goal.as_ptr(),
        goal_tolerance: problem.goal_tolerance,
        range: settings.range.unwrap_or(0.0),
        resolution: settings.resolution_fraction,
        budget_s: termination.budget.as_secs_f64(),
        simplify: match (settings.simplify, settings.simplifier) {
            (false, _) => ffi::SIMPLIFY_OFF,
            (true, crate::Simplifier::Full) => ffi::SIMPLIFY_FULL,
            (true, crate::Simplifier::Shortcut) => ffi::SIMPLIFY_SHORTCUT,
        },
        // validate() checked that it fits.
        interpolate_to: settings.interpolate_to.map_or(0, |n| n as u32),
        has_cost_threshold: i32::from(settings.cost_threshold.is_some()),
        cost_threshold: settings.cost_threshold.unwrap_or(0.0),
        max_iterations: settings.max_iterations.unwrap_or(0),
    };
    let context = CheckerContext::new(checker);
    let motion_context = motion.map(MotionContext::new);
    let (motion_fn, motion_user) = match &motion_context {
        Some(m) => (Some(m.trampoline()), m.as_user()),
        None => (None, ptr::null_mut()),
    };
    let (cancel_fn, cancel_user) = match termination.cancel {
        Some(flag) => (
            Some(cancel_trampoline as ffi::CancelFn),
            ptr::from_ref(flag).cast_mut().cast(),
        ),
        None => (None, ptr::null_mut()),
    };
    let mut path: Vec<Vec<f64>> = Vec::new();
    let mut result = PlanResult::default();
    // SAFETY: every pointer refers to data that lives until the call returns (request vectors,
    // contexts, flag, path, result); the shim calls the trampolines only during the call, with
    // the matching user pointers; the signatures match cpp/shim.h.
    kinscene_shim::call("ks_ompl_plan", |err, len| unsafe {
        (api.plan)(
            &request,
            context.trampoline(),
            context.as_user(),
            motion_fn,
            motion_user,
            cancel_fn,
            cancel_user,
            path_sink,
            ptr::from_mut(&mut path).cast(),
            &mut result,
            err,
            len,
        )
    })?;

    let mut status = PlanStatus::from_ompl(result.status);
    let cancelled = termination
        .cancel
        .is_some_and(|flag| flag.load(Ordering::Relaxed));
    if cancelled
        && matches!(
            status,
            PlanStatus::Timeout | PlanStatus::ApproximateSolution
        )
    {
        status = PlanStatus::Cancelled;
    }
    Ok(PlanOutcome {
        status,
        goal_distance: (!path.is_empty()).then_some(result.goal_distance),
        path,
        planning_time: Duration::from_secs_f64(result.planning_time_s.max(0.0)),
        simplification_time: Duration::from_secs_f64(result.simplification_time_s.max(0.0)),
        checker_panics: context.panics() + motion_context.as_ref().map_or(0, |m| m.panics()),
        iterations: result.iterations,
        iteration_budget_spent: settings
            .max_iterations
            .is_some_and(|n| result.iterations > n),
    })
}
