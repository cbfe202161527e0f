//! The solver: Levenberg–Marquardt steps (damped least squares, or a box-constrained QP when a
//! bound is active), with random restarts.

mod attempt;
mod coordinates;
mod outcome;

use kinscene_pinocchio as pin;
use nalgebra::{DMatrix, DVector};
use pin::{FrameIndex, JointKind, Model};

use super::step::{StepQpData, StepSolvers};
use super::{IkError, IkSettings, IkTarget};
use crate::kinematics::robot::RobotModel;
use coordinates::Coordinate;
pub use outcome::{IkBest, IkFailure, IkOutcome, IkSolution, NoConvergence};

/// Inverse kinematics of one frame of a Pinocchio model.
///
/// Each iteration linearises the task at q with Pinocchio (frame placement and its
/// `LOCAL_WORLD_ALIGNED` Jacobian, one pass over the frame's support) and takes a step towards
/// the minimiser of the QP
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
/// **The step** ([`IkSettings::step_solver`]): the QP's minimiser. By default
/// ([`StepSolver::DampedLeastSquares`](super::StepSolver::DampedLeastSquares)) the fast path
/// first: the damped-least-squares step `(JᵀJ + λI)⁻¹ Jᵀe` (one Cholesky factorisation of an
/// n × n matrix, n ≤ ~10, well under a microsecond), which is the minimiser whenever it lies
/// within the bounds. When it would cross a bound, the QP is solved
/// ([`StepSolver::Dense`](super::StepSolver::Dense)) by a dense active-set method on the
/// bounds: a bound that the step would cross is fixed there and the rest re-solved, and the
/// result is taken only with its KKT certificate (the QP is strictly convex, so that makes it
/// the minimiser). When no certificate comes within a few rounds the step falls back to
/// Clarabel (20–36 µs).
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
    /// The frame Jacobian (6 × nv).
    jacobian: DMatrix<f64>,
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
            jacobian: DMatrix::zeros(6, solver.model.nv()),
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
    /// Steps that solved the step QP (the dense method or Clarabel) rather than taking the
    /// damped-least-squares step: every step with [`crate::kinematics::ik::StepSolver::Dense`]
    /// or `Clarabel`; with `DampedLeastSquares` the steps that a bound cut.
    pub qp_steps: usize,
    /// Attempts started: 1 for the seed plus the random restarts.
    pub attempts: usize,
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
}
