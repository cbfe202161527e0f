//! Solver settings with their defaults and validation.

use std::time::Duration;

use super::IkError;

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
    /// QP steps per attempt (the seed, then each restart). Default 100.
    pub max_iterations: usize,
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
    /// [`crate::kinematics::ik::IkOutcome::NotConverged`] with the best configuration seen.
    /// Default 50 ms.
    pub budget: Duration,
    /// Seed of the ChaCha8 generator of restart configurations. Every solve starts from this
    /// seed, so a solve is a deterministic function of (target, seed configuration) apart from
    /// where the budget cuts it. Default 0.
    pub seed: u64,
}

impl Default for IkSettings {
    fn default() -> Self {
        IkSettings {
            position_tolerance: 1e-5,
            rotation_tolerance: 1e-4,
            max_iterations: 100,
            max_step: 0.5,
            damping: 1e-7,
            restarts: 50,
            budget: Duration::from_millis(50),
            seed: 0,
        }
    }
}

impl IkSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`IkError::InvalidSetting`] naming the first bad field: tolerances, `max_step` and
    /// `budget` must be positive and finite, `damping` non-negative and finite,
    /// `max_iterations` at least 1.
    pub fn validate(&self) -> Result<(), IkError> {
        let positive = [
            ("position_tolerance", self.position_tolerance),
            ("rotation_tolerance", self.rotation_tolerance),
            ("max_step", self.max_step),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(IkError::InvalidSetting {
                    name,
                    value,
                    reason: "must be positive and finite",
                });
            }
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(IkError::InvalidSetting {
                name: "damping",
                value: self.damping,
                reason: "must be non-negative and finite",
            });
        }
        if self.max_iterations == 0 {
            return Err(IkError::InvalidSetting {
                name: "max_iterations",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        if self.budget.is_zero() {
            return Err(IkError::InvalidSetting {
                name: "budget",
                value: 0.0,
                reason: "must be positive",
            });
        }
        Ok(())
    }
}
