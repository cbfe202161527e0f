//! The solver: Levenberg–Marquardt steps, each one a box-constrained QP, with random restarts.

use std::f64::consts::PI;
use std::time::Instant;

use kinscene_pinocchio as pin;
use nalgebra::DVector;
use pin::{FrameIndex, JointKind, Model, ReferenceFrame};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::step::{StepQpData, StepSolvers};
use super::target::Task;
use super::{IkError, IkSettings, IkTarget};
use crate::kinematics::robot::RobotModel;

/// An attempt that has not reduced its error by this factor over the last
/// [`STALL_WINDOW`] steps is stuck in a local minimum (or crawling along a limit) and is
/// abandoned for a restart.
const STALL_FACTOR: f64 = 0.9;
/// See [`STALL_FACTOR`].
const STALL_WINDOW: usize = 10;

/// How one IK solve ended: [`Solved`](crate::Outcome::Solved) when both tolerances were met,
/// [`Infeasible`](crate::Outcome::Infeasible) when no attempt met them within the iteration
/// limits and restarts (with the best configuration seen), or
/// [`Timeout`](crate::Outcome::Timeout) when the wall-clock budget
/// ([`IkSettings::budget`](super::IkSettings::budget)) ran out first (with the best seen). IK
/// takes no cancel flag, so it is never `Cancelled`.
pub type IkOutcome = crate::Outcome<IkSolution, IkFailure, IkBest>;

/// A configuration that meets both tolerances.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSolution {
    /// The configuration (length nq, within the joint limits).
    pub q: DVector<f64>,
    /// Steps over all attempts.
    pub iterations: usize,
    /// Random restarts used (0: converged from the seed).
    pub restarts: usize,
}

/// The configuration with the smallest error an unsuccessful solve saw.
#[derive(Debug, Clone, PartialEq)]
pub struct IkBest {
    /// The configuration (length nq, within the joint limits).
    pub q: DVector<f64>,
    /// Its position error (m).
    pub position_error: f64,
    /// Its rotation error (rad).
    pub rotation_error: f64,
    /// Steps over all attempts.
    pub iterations: usize,
    /// Random restarts used.
    pub restarts: usize,
}

impl std::fmt::Display for IkBest {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "best error {:.2e} m, {:.2e} rad after {} iterations and {} restarts",
            self.position_error, self.rotation_error, self.iterations, self.restarts
        )
    }
}

/// Why an IK solve ended without meeting the tolerances.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoConvergence {
    /// The iteration budget over all attempts
    /// ([`IkSettings::max_total_iterations`](super::IkSettings::max_total_iterations)) ran out.
    IterationBudget,
    /// Every attempt stalled in a local minimum or used its iterations.
    AttemptsExhausted,
}

/// An IK solve that did not converge: why, and the best configuration seen.
#[derive(Debug, Clone, PartialEq)]
pub struct IkFailure {
    /// Why the solver stopped.
    pub reason: NoConvergence,
    /// The best configuration seen.
    pub best: IkBest,
}

impl std::fmt::Display for IkFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let why = match self.reason {
            NoConvergence::IterationBudget => "iteration budget exhausted",
            NoConvergence::AttemptsExhausted => "every attempt stalled or ran out of steps",
        };
        write!(f, "IK did not converge ({why}); {}", self.best)
    }
}

impl IkOutcome {
    /// The converged configuration, if any.
    pub fn q(&self) -> Option<&DVector<f64>> {
        self.solved().map(|s| &s.q)
    }

    /// The best configuration seen, converged or not.
    pub fn best_q(&self) -> &DVector<f64> {
        match self {
            crate::Outcome::Solved(s) => &s.q,
            crate::Outcome::Infeasible(f) => &f.best.q,
            crate::Outcome::Timeout(b) | crate::Outcome::Cancelled(b) => &b.q,
        }
    }
}

/// How a velocity coordinate's configuration behaves under a step.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Coordinate {
    /// A revolute or prismatic coordinate `q[idx_q]` within `[lower, upper]` (either may be
    /// infinite, but not both for a revolute joint).
    Scalar {
        idx_q: usize,
        lower: f64,
        upper: f64,
    },
    /// A revolute coordinate `q[idx_q]` without limits: kept within π of the seed's value.
    Angle { idx_q: usize },
    /// A `(cos, sin)` pair or planar block: unbounded, moved by Pinocchio's `integrate`.
    Manifold,
}

/// Inverse kinematics of one frame of a Pinocchio model.
///
/// Each iteration linearises the task at q with Pinocchio (frame placement and its
/// `LOCAL_WORLD_ALIGNED` Jacobian) and solves the QP
///
/// ```text
/// min_dq  ½‖J dq − e‖² + ½ λ‖dq‖²   (+ ½ μ‖N (q + dq − seed)‖² in solve_near)
/// s.t.    lower ≤ q + dq ≤ upper,   |dq_i| ≤ max_step
/// ```
///
/// with `e` the task error of [`IkTarget`] (metres and radians, equal weights), Levenberg–
/// Marquardt damping `λ = damping + 0.1 ‖e‖²` (after Sugihara 2011), N the projector onto the
/// null space of J and μ = 1e-2, faded out linearly once ‖e‖ < 1e-3 so that the pull never
/// holds the solution away from the target. Then `q ← q ⊕ dq` (Pinocchio's `integrate`). dq
/// ranges over the velocity coordinates of the joints that move the frame (the others have
/// zero Jacobian columns and no pull, so their step is 0 and they keep the seed's values).
///
/// **The step's solver** ([`IkSettings::step_solver`]). By default
/// ([`StepSolver::Dense`](super::StepSolver::Dense)) a dense active-set method on the bounds:
/// with no bound active the minimiser is the damped-least-squares step `(JᵀJ + λI)⁻¹ Jᵀe`, one Cholesky factorisation of an n × n matrix (n ≤ ~10, well under a
/// microsecond); a bound that the step would cross is fixed there and the rest re-solved, and
/// the result is taken only with its KKT certificate (the QP is strictly convex, so that makes
/// it the minimiser). When no certificate comes within a few rounds the step falls back to
/// Clarabel (20–36 µs). Either way the step is the QP's minimiser.
///
/// **Joint limits.** Revolute and prismatic coordinates stay within the model's position
/// limits (the QP's constraints, then a clamp that removes the interior-point solver's ~1e-9
/// residual). Revolute joints whose limits are both infinite and unbounded revolute joints
/// (`(cos, sin)` pairs, URDF `continuous`) are unconstrained. The former are wrapped after
/// every step into `[s − π, s + π)` around the seed's value s (the representative nearest
/// the seed, so a trajectory solved with [`IkSolver::solve_near`] never jumps by 2π); the
/// latter are angles on the circle by construction.
///
/// **Restarts and budgets.** [`IkSolver::solve`] starts from the seed, then from up to
/// [`IkSettings::restarts`] configurations drawn uniformly within the limits (ChaCha8 seeded
/// with [`IkSettings::seed`]; unlimited angles uniformly within π of the seed's value;
/// unlimited prismatic and planar translations keep the seed's value). An attempt ends after
/// [`IkSettings::max_iterations`] steps or when its error stalls (less than 10 % reduction over
/// 10 steps). [`IkSettings::max_total_iterations`] bounds the steps of the whole solve, so a
/// solve is a deterministic function of (target, seed, settings) unless the wall-clock
/// [`IkSettings::budget`], a safety net, runs out first.
///
/// `IkSolver` is `Send + Sync`: it owns its own copy of the model and no mutable state.
/// Per-call scratch lives in an [`IkData`]; [`IkSolver::solve`] makes one per call,
/// [`IkSolver::solve_with`] reuses the caller's (for hot loops).
#[derive(Debug)]
pub struct IkSolver {
    model: Model,
    frame: FrameIndex,
    settings: IkSettings,
    coordinates: Vec<Coordinate>,
    /// Joints (index into `model.joints()`) on the chain from the root to the frame.
    support: Vec<usize>,
    /// Velocity coordinates of those joints, ascending: the step's variables.
    support_v: Vec<usize>,
    /// `q` index of each step variable, when all are revolute or prismatic coordinates
    /// (`q ⊕ dq = q + dq` there, see `kinscene_pinocchio::integrate`); `None` when one is a
    /// `(cos, sin)` pair or planar block, which Pinocchio's `integrate` moves.
    step_q: Option<Vec<usize>>,
}

/// Scratch for [`IkSolver::solve_with`]: Pinocchio data and the step solvers' workspaces, and
/// the counts of the last solve ([`IkData::last_solve`]). Make one per thread with
/// [`IkData::new`].
#[derive(Debug)]
pub struct IkData {
    data: pin::Data,
    steps: StepSolvers,
    qp: StepQpData,
    /// The step over the step variables.
    dq: DVector<f64>,
    last: IkStats,
}

impl IkData {
    /// Scratch sized for `solver`'s model.
    ///
    /// # Errors
    /// [`IkError::Pinocchio`] if the backend cannot allocate its data.
    pub fn new(solver: &IkSolver) -> Result<IkData, IkError> {
        let n = solver.support_v.len();
        Ok(IkData {
            data: pin::Data::new(&solver.model)?,
            steps: StepSolvers::new(n),
            qp: StepQpData::new(n),
            dq: DVector::zeros(n),
            last: IkStats::default(),
        })
    }

    /// What the last solve with this scratch did (zeros before the first, and after a solve
    /// that returned `Err` before its first step).
    pub fn last_solve(&self) -> IkStats {
        self.last
    }
}

/// Counts of one solve.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct IkStats {
    /// Steps over all attempts (what [`IkSettings::max_total_iterations`] bounds).
    pub steps: usize,
    /// Of those, steps whose QP the dense method could not certify, solved by Clarabel (all of
    /// them with [`crate::kinematics::ik::StepSolver::Clarabel`]).
    pub clarabel_steps: usize,
    /// Attempts started: 1 for the seed plus the random restarts.
    pub attempts: usize,
}

/// The best configuration seen so far and its errors.
struct Best {
    q: DVector<f64>,
    score: f64,
    position_error: f64,
    rotation_error: f64,
}

/// What every attempt of one solve shares.
#[derive(Clone, Copy)]
struct Problem<'a> {
    target: &'a IkTarget,
    /// The seed, clamped into the limits: the first start, the centre of unlimited angles,
    /// and what `solve_near` pulls towards.
    seed: &'a DVector<f64>,
    /// `solve_near`: pull towards the seed, no restarts.
    near: bool,
    deadline: Option<Instant>,
}

/// How one attempt ended.
enum Attempt {
    Converged(DVector<f64>),
    Stalled,
    OutOfIterations,
    OutOfIterationBudget,
    OutOfTime,
}

impl IkSolver {
    /// A solver for `frame` of `model` (copied into the solver).
    ///
    /// # Errors
    /// [`IkError::InvalidSetting`] (see [`IkSettings::validate`]), [`IkError::UnknownFrame`],
    /// [`IkError::NoDegreesOfFreedom`] when no joint moves the frame, [`IkError::Pinocchio`]
    /// if the copy of the model cannot be built.
    pub fn new(
        model: &Model,
        frame: FrameIndex,
        settings: IkSettings,
    ) -> Result<IkSolver, IkError> {
        settings.validate()?;
        let frame_info = model.frame(frame).map_err(|_| IkError::UnknownFrame {
            index: frame.0,
            count: model.frames().len(),
        })?;
        let mut support = Vec::new();
        let mut joint = frame_info.parent_joint;
        while joint != pin::JointIndex::UNIVERSE {
            support.push(joint.0 - 1);
            joint = model.joint(joint)?.parent;
        }
        support.reverse();
        if support.is_empty() {
            return Err(IkError::NoDegreesOfFreedom {
                frame: frame_info.name.clone(),
            });
        }
        let mut coordinates = Vec::with_capacity(model.nv());
        for joint in model.joints() {
            let (lower, upper) = joint
                .limits
                .position
                .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
            let idx_q = joint.idx_q;
            match joint.kind {
                JointKind::Revolute { .. } if lower.is_infinite() && upper.is_infinite() => {
                    coordinates.push(Coordinate::Angle { idx_q });
                }
                JointKind::Revolute { .. } | JointKind::Prismatic { .. } => {
                    coordinates.push(Coordinate::Scalar {
                        idx_q,
                        lower,
                        upper,
                    });
                }
                JointKind::RevoluteUnbounded { .. } | JointKind::Planar => {
                    coordinates.extend(std::iter::repeat_n(Coordinate::Manifold, joint.nv()));
                }
            }
        }
        let support_v: Vec<usize> = support
            .iter()
            .flat_map(|&j| {
                let joint = &model.joints()[j];
                joint.idx_v..joint.idx_v + joint.nv()
            })
            .collect();
        let step_q = support_v
            .iter()
            .map(|&i| match coordinates[i] {
                Coordinate::Scalar { idx_q, .. } | Coordinate::Angle { idx_q } => Some(idx_q),
                Coordinate::Manifold => None,
            })
            .collect();
        Ok(IkSolver {
            model: model.to_builder().build()?,
            frame,
            settings,
            coordinates,
            support,
            support_v,
            step_q,
        })
    }

    /// A solver for `robot`'s tool frame: [`IkSolver::new`] on
    /// [`RobotModel::pinocchio`] (the arm, rooted at the base frame, so targets are
    /// `base_from_tool`) and [`RobotModel::tool_frame`]. q is the arm configuration (length
    /// [`RobotModel::dof`]); continuous joints are revolute joints without limits there, kept
    /// within π of the seed.
    ///
    /// # Errors
    /// As [`IkSolver::new`].
    pub fn for_robot(robot: &RobotModel, settings: IkSettings) -> Result<IkSolver, IkError> {
        IkSolver::new(robot.pinocchio(), robot.tool_frame(), settings)
    }

    /// The solver's copy of the model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The frame being placed.
    pub fn frame(&self) -> FrameIndex {
        self.frame
    }

    /// The settings.
    pub fn settings(&self) -> &IkSettings {
        &self.settings
    }

    /// Solves for `target` from `seed` (length nq), then from random restarts.
    ///
    /// A seed outside the joint limits is clamped into them first.
    ///
    /// # Errors
    /// Only for bad input or a failed backend: [`IkError::DimensionMismatch`],
    /// [`IkError::NonFinite`], [`IkError::NonUnitAxis`], [`IkError::NonUnitRotation`],
    /// [`IkError::Pinocchio`] (e.g. a `(cos, sin)` pair of the seed off unit length),
    /// [`IkError::QpSetup`], [`IkError::QpFailed`]. Not converging is
    /// an [`IkOutcome`] other than `Solved`.
    pub fn solve(&self, target: &IkTarget, seed: &DVector<f64>) -> Result<IkOutcome, IkError> {
        self.solve_with(&mut IkData::new(self)?, target, seed)
    }

    /// Like [`IkSolver::solve`] with an extra cost pulling q towards `seed` in the null space
    /// of the task (continuity along a trajectory: redundant joints stay where they were), and
    /// no restarts.
    ///
    /// # Errors
    /// As [`IkSolver::solve`].
    pub fn solve_near(&self, target: &IkTarget, seed: &DVector<f64>) -> Result<IkOutcome, IkError> {
        self.solve_near_with(&mut IkData::new(self)?, target, seed)
    }

    /// [`IkSolver::solve`] with caller-owned scratch.
    ///
    /// # Errors
    /// As [`IkSolver::solve`]; [`IkError::Pinocchio`] also when `data` was made for another
    /// solver's model.
    pub fn solve_with(
        &self,
        data: &mut IkData,
        target: &IkTarget,
        seed: &DVector<f64>,
    ) -> Result<IkOutcome, IkError> {
        self.run(data, target, seed, false)
    }

    /// [`IkSolver::solve_near`] with caller-owned scratch.
    ///
    /// # Errors
    /// As [`IkSolver::solve_with`].
    pub fn solve_near_with(
        &self,
        data: &mut IkData,
        target: &IkTarget,
        seed: &DVector<f64>,
    ) -> Result<IkOutcome, IkError> {
        self.run(data, target, seed, true)
    }

    fn run(
        &self,
        data: &mut IkData,
        target: &IkTarget,
        seed: &DVector<f64>,
        near: bool,
    ) -> Result<IkOutcome, IkError> {
        // No deadline when the budget is too large to represent (e.g. `Duration::MAX`).
        let deadline = Instant::now().checked_add(self.settings.budget);
        data.last = IkStats::default();
        data.steps.reset();
        let seed = self.checked_seed(target, seed)?;
        let problem = Problem {
            target,
            seed: &seed,
            near,
            deadline,
        };
        let mut task = Task::new(target, self.support_v.len());
        let mut rng = ChaCha8Rng::seed_from_u64(self.settings.seed);
        let mut best: Option<Best> = None;
        let mut iterations = 0;
        let restarts = if near { 0 } else { self.settings.restarts };
        let mut ended_by = None;
        let mut attempts = 0;
        for attempt in 0..=restarts {
            let q0 = if attempt == 0 {
                seed.clone()
            } else {
                self.random_configuration(&seed, &mut rng)
            };
            let ended = self.attempt(data, &problem, &mut task, q0, &mut iterations, &mut best);
            attempts = attempt + 1;
            data.last = IkStats {
                steps: iterations,
                clarabel_steps: data.steps.clarabel_steps,
                attempts,
            };
            match ended? {
                Attempt::Converged(q) => {
                    return Ok(IkOutcome::Solved(IkSolution {
                        q,
                        iterations,
                        restarts: attempt,
                    }));
                }
                Attempt::OutOfIterationBudget => {
                    ended_by = Some(Some(NoConvergence::IterationBudget));
                    break;
                }
                Attempt::OutOfTime => {
                    ended_by = Some(None);
                    break;
                }
                Attempt::Stalled | Attempt::OutOfIterations => {}
            }
        }
        let best = best.expect("every attempt evaluates its start");
        let best = IkBest {
            q: best.q,
            position_error: best.position_error,
            rotation_error: best.rotation_error,
            iterations,
            restarts: attempts - 1,
        };
        Ok(match ended_by {
            Some(None) => IkOutcome::Timeout(best),
            Some(Some(reason)) => IkOutcome::Infeasible(IkFailure { reason, best }),
            None => IkOutcome::Infeasible(IkFailure {
                reason: NoConvergence::AttemptsExhausted,
                best,
            }),
        })
    }

    /// The seed checked against the model and clamped into the limits, after checking the
    /// target.
    fn checked_seed(
        &self,
        target: &IkTarget,
        seed: &DVector<f64>,
    ) -> Result<DVector<f64>, IkError> {
        target.validate()?;
        if seed.len() != self.model.nq() {
            return Err(IkError::DimensionMismatch {
                what: "seed",
                expected: self.model.nq(),
                got: seed.len(),
            });
        }
        if !seed.iter().all(|c| c.is_finite()) {
            return Err(IkError::NonFinite { what: "seed" });
        }
        let mut seed = seed.clone();
        self.clamp(&mut seed, None);
        pin::check_configuration(&self.model, &seed)?;
        Ok(seed)
    }

    /// One local descent from `q`.
    fn attempt(
        &self,
        data: &mut IkData,
        problem: &Problem<'_>,
        task: &mut Task,
        mut q: DVector<f64>,
        iterations: &mut usize,
        best: &mut Option<Best>,
    ) -> Result<Attempt, IkError> {
        let mut history: Vec<f64> = Vec::with_capacity(self.settings.max_iterations + 1);
        for step in 0..=self.settings.max_iterations {
            self.update_task(data, problem.target, &q, task)?;
            if task.position_error <= self.settings.position_tolerance
                && task.rotation_error <= self.settings.rotation_tolerance
            {
                return Ok(Attempt::Converged(q));
            }
            let score = task.residual.norm_squared();
            if best.as_ref().is_none_or(|b| score < b.score) {
                *best = Some(Best {
                    q: q.clone(),
                    score,
                    position_error: task.position_error,
                    rotation_error: task.rotation_error,
                });
            }
            if step == self.settings.max_iterations {
                return Ok(Attempt::OutOfIterations);
            }
            if *iterations >= self.settings.max_total_iterations {
                return Ok(Attempt::OutOfIterationBudget);
            }
            if problem.deadline.is_some_and(|d| Instant::now() >= d) {
                return Ok(Attempt::OutOfTime);
            }
            history.push(score);
            if step >= STALL_WINDOW
                && score.sqrt() > STALL_FACTOR * history[step - STALL_WINDOW].sqrt()
            {
                return Ok(Attempt::Stalled);
            }
            self.step(data, problem, &q, task)?;
            *iterations += 1;
            self.integrate(&mut q, &data.dq)?;
            self.clamp(&mut q, Some(problem.seed));
        }
        unreachable!("the loop returns at step == max_iterations")
    }

    /// `task` at q, its Jacobian restricted to the step's variables.
    fn update_task(
        &self,
        data: &mut IkData,
        target: &IkTarget,
        q: &DVector<f64>,
        task: &mut Task,
    ) -> Result<(), IkError> {
        pin::forward_kinematics(&self.model, &mut data.data, q)?;
        let pose = pin::frame_placement(&self.model, &data.data, self.frame)?;
        let jacobian = pin::frame_jacobian(
            &self.model,
            &mut data.data,
            q,
            self.frame,
            ReferenceFrame::LocalWorldAligned,
        )?;
        task.update(target, &pose, &jacobian, &self.support_v);
        Ok(())
    }

    /// The step at q into `data.dq` (over the step variables): the minimiser of the step QP
    /// (see [`IkSolver`]).
    fn step(
        &self,
        data: &mut IkData,
        problem: &Problem<'_>,
        q: &DVector<f64>,
        task: &Task,
    ) -> Result<(), IkError> {
        let offset = if problem.near {
            let offset = pin::difference(&self.model, problem.seed, q)?;
            Some(offset.select_rows(&self.support_v))
        } else {
            None
        };
        data.qp
            .levenberg_marquardt(task, self.settings.damping, offset.as_ref());
        self.step_bounds(q, &mut data.qp);
        data.steps
            .solve(self.settings.step_solver, &data.qp, &mut data.dq)
    }

    /// `q ← q ⊕ dq` for a step `dq` over the step variables: `q + dq` on revolute and
    /// prismatic coordinates, Pinocchio's `integrate` when the chain has a `(cos, sin)` pair
    /// or a planar joint.
    fn integrate(&self, q: &mut DVector<f64>, dq: &DVector<f64>) -> Result<(), IkError> {
        if let Some(step_q) = &self.step_q {
            for (k, &i) in step_q.iter().enumerate() {
                q[i] += dq[k];
            }
            return Ok(());
        }
        let mut v = DVector::zeros(self.model.nv());
        for (k, &i) in self.support_v.iter().enumerate() {
            v[i] = dq[k];
        }
        *q = pin::integrate(&self.model, q, &v)?;
        Ok(())
    }

    /// `qp.lower ≤ dq ≤ qp.upper`: the joint limits relative to q, intersected with
    /// ±max_step, for the step's variables.
    fn step_bounds(&self, q: &DVector<f64>, qp: &mut StepQpData) {
        let max_step = self.settings.max_step;
        for (k, &i) in self.support_v.iter().enumerate() {
            let (lo, hi) = match self.coordinates[i] {
                Coordinate::Scalar {
                    idx_q,
                    lower,
                    upper,
                } => (
                    (lower - q[idx_q]).max(-max_step),
                    (upper - q[idx_q]).min(max_step),
                ),
                Coordinate::Angle { .. } | Coordinate::Manifold => (-max_step, max_step),
            };
            // q is within its limits (clamped), so lo ≤ 0 ≤ hi; max/min keep that exact.
            qp.lower[k] = lo.min(0.0);
            qp.upper[k] = hi.max(0.0);
        }
    }

    /// Clamps scalar coordinates into their limits and, given a `centre` configuration, wraps
    /// unlimited angles into `[c − π, c + π)` around the centre's value c.
    fn clamp(&self, q: &mut DVector<f64>, centre: Option<&DVector<f64>>) {
        for c in &self.coordinates {
            match *c {
                Coordinate::Scalar {
                    idx_q,
                    lower,
                    upper,
                } => q[idx_q] = q[idx_q].clamp(lower, upper),
                Coordinate::Angle { idx_q } => {
                    if let Some(c) = centre {
                        q[idx_q] = c[idx_q] + wrap_angle(q[idx_q] - c[idx_q]);
                    }
                }
                Coordinate::Manifold => {}
            }
        }
    }

    /// `seed` with the joints that move the frame drawn at random within their limits.
    fn random_configuration(&self, seed: &DVector<f64>, rng: &mut ChaCha8Rng) -> DVector<f64> {
        let mut q = seed.clone();
        for &j in &self.support {
            let joint = &self.model.joints()[j];
            let i = joint.idx_q;
            let (lower, upper) = joint
                .limits
                .position
                .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
            match joint.kind {
                JointKind::Revolute { .. } => {
                    let lo = if lower.is_finite() {
                        lower
                    } else if upper.is_finite() {
                        upper - 2.0 * PI
                    } else {
                        seed[i] - PI
                    };
                    let hi = upper.min(lo + 2.0 * PI);
                    q[i] = if lo < hi {
                        rng.random_range(lo..hi)
                    } else {
                        lo
                    };
                }
                JointKind::Prismatic { .. } => {
                    if lower.is_finite() && upper.is_finite() && lower < upper {
                        q[i] = rng.random_range(lower..upper);
                    }
                }
                JointKind::RevoluteUnbounded { .. } => {
                    let (sin, cos) = rng.random_range(-PI..PI).sin_cos();
                    q[i] = cos;
                    q[i + 1] = sin;
                }
                JointKind::Planar => {
                    let (sin, cos) = rng.random_range(-PI..PI).sin_cos();
                    q[i + 2] = cos;
                    q[i + 3] = sin;
                }
            }
        }
        q
    }
}

/// `angle` wrapped into [−π, π).
fn wrap_angle(angle: f64) -> f64 {
    (angle + PI).rem_euclid(2.0 * PI) - PI
}
