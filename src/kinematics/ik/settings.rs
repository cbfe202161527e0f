//! Solver settings with their defaults and validation.

use std::time::Duration;

use super::IkError;
use crate::InvalidSetting;

/// Settings of [`crate::kinematics::ik::IkSolver`]. Build with `Default` and override fields;
/// [`IkSettings::validate`] (called by the solver's constructor) checks them.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSettings {
    /// Converged when the tool origin is within this distance of the target (m). Default 1e-5.
    pub position_tolerance: f64,
    /// Converged when the rotation error is at most this angle (rad): the angle of
    /// `target_rotation * current_rotation⁻¹` for a pose target, the angle between the tool +z
    /// axis and the target axis for a position + axis target. Default 1e-4.
    pub rotation_tolerance: f64,
    /// Steps per attempt (the seed, then each restart). Default 100.
    pub max_iterations: usize,
    /// Steps of one whole solve, over all its attempts: the solve's budget counted in
    /// iterations. Unlike [`IkSettings::budget`] it does not depend on the machine's speed or
    /// load, so a solve that ends here gives the same answer every time; keep it low enough
    /// that it, not the wall clock, ends the solves that fail. A step costs about 1.5 µs on a
    /// 7-DoF arm in a release build (Pinocchio's kinematics and Jacobian dominate) unless it
    /// falls back to Clarabel (about 25 µs, see [`IkSettings::step_solver`]); the
    /// default, 5 000, is then about 10 ms, a fifth of the default wall-clock budget, and with
    /// the default `restarts` and `max_iterations` (at most 5 100 steps) it ends only the
    /// last attempt early. Default 5 000.
    pub max_total_iterations: usize,
    /// Largest change of any velocity coordinate in one step (rad or m): the bound
    /// `|dq_i| ≤ max_step` of every step QP, a trust region. Default 0.5.
    pub max_step: f64,
    /// Floor of the Levenberg–Marquardt damping: each step uses `λ = damping + 0.1 ‖e‖²`
    /// (Sugihara's rule, e the stacked error in m and rad). Small, so that targets near a
    /// singularity still converge quickly once the error is small; the error term and
    /// `max_step` tame the steps far from the target. Default 1e-7.
    pub damping: f64,
    /// Attempts from random configurations (uniform within the joint limits) after the attempt
    /// from the seed ([`crate::kinematics::ik::IkSolver::solve`] only). Default 50.
    pub restarts: usize,
    /// Wall-clock budget of one solve; when it runs out the solve reports
    /// [`Timeout`](crate::Outcome::Timeout) with the best configuration seen.
    /// A safety net: where it ends a solve, the answer depends on the machine's load (see
    /// [`IkSettings::max_total_iterations`]). Default 50 ms.
    pub budget: Duration,
    /// Seed of the ChaCha8 generator of restart configurations. Every solve starts from this
    /// seed, so a solve is a deterministic function of (target, seed configuration) apart from
    /// where the wall-clock budget cuts it. Default 0.
    pub seed: u64,
    /// How each step is taken. Default [`StepSolver::DampedLeastSquares`].
    pub step_solver: StepSolver,
}

/// How [`crate::kinematics::ik::IkSolver`] takes each step. [`StepSolver::Dense`] and
/// [`StepSolver::Clarabel`] both give the step QP's minimiser, Clarabel to its tolerance. On a
/// redundant arm the two can still return different solutions of the same target: once the
/// damping `λ` is small the step QP is nearly flat along the task's null space (7 joints, 5 or
/// 6 task dimensions), where Clarabel's tolerance leaves room and the dense step is exact, so
/// the descents part (on the kitchen simulator's top-drawer grasp from the stow, Clarabel
/// converges in 17 steps to q₂ = −2.134 rad, the dense step in 12 to q₂ = −2.092 rad, both
/// within tolerance). [`StepSolver::DampedLeastSquares`] takes exactly the steps of
/// [`StepSolver::Dense`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StepSolver {
    /// The fast path: the damped-least-squares step `(JᵀJ + λI)⁻¹ Jᵀe` (one Cholesky
    /// factorisation of an n × n matrix, n the joints moving the frame), taken when it lies
    /// within the trust region and the joint limits — there it is the step QP's minimiser —;
    /// the step QP as [`StepSolver::Dense`] solves it only when the step would cross a bound.
    /// So it takes the same steps as `Dense`, without the active-set bookkeeping on the steps
    /// that no bound cuts; when a bound does, the active-set rounds continue from the DLS
    /// step's factorisation. (Projecting instead — the step scaled into the trust region and
    /// clamped into the limits, the QP only when that stops reducing the error — took 5 %
    /// more steps on the TRAC-IK protocol, 2 000 targets per arm, with the scaling alone, and
    /// 47 % (Gen3) and 82 % (Panda) more with the clamp as well: the QP's step along an
    /// active limit is worth its few extra factorisations.)
    #[default]
    DampedLeastSquares,
    /// The step QP's minimiser for every step, by a dense active-set method on the bounds: one
    /// Cholesky factorisation of the damped normal matrix when no bound is active — the
    /// damped-least-squares step —, one more per bound that becomes active; the answer is
    /// taken only with its optimality (KKT) certificate, else the step falls back to Clarabel.
    /// About 1.5 µs a step on a 7-DoF arm (Gen3, release build), 21× faster per solve than
    /// Clarabel on the TRAC-IK protocol (`benches/ik.rs`).
    Dense,
    /// Clarabel's interior-point method for every step (20–36 µs each).
    Clarabel,
}

impl Default for IkSettings {
    fn default() -> Self {
        IkSettings {
            position_tolerance: 1e-5,
            rotation_tolerance: 1e-4,
            max_iterations: 100,
            max_total_iterations: 5_000,
            max_step: 0.5,
            damping: 1e-7,
            restarts: 50,
            budget: Duration::from_millis(50),
            seed: 0,
            step_solver: StepSolver::DampedLeastSquares,
        }
    }
}

impl IkSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`IkError::InvalidSetting`] naming the first bad field: tolerances, `max_step` and
    /// `budget` must be positive and finite, `damping` non-negative and finite,
    /// `max_iterations` and `max_total_iterations` at least 1.
    pub fn validate(&self) -> Result<(), IkError> {
        let positive = [
            ("position_tolerance", self.position_tolerance),
            ("rotation_tolerance", self.rotation_tolerance),
            ("max_step", self.max_step),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(InvalidSetting::new(name, value, "positive and finite").into());
            }
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(
                InvalidSetting::new("damping", self.damping, "non-negative and finite").into(),
            );
        }
        if self.max_iterations == 0 {
            return Err(InvalidSetting::new("max_iterations", 0.0, "at least 1").into());
        }
        if self.max_total_iterations == 0 {
            return Err(InvalidSetting::new("max_total_iterations", 0.0, "at least 1").into());
        }
        if self.budget.is_zero() {
            return Err(InvalidSetting::new("budget", 0.0, "positive").into());
        }
        Ok(())
    }
}
