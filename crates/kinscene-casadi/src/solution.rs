//! What a solve returns.

use std::time::Duration;

use crate::expr::{Expr, Owner};

/// IPOPT's exit status (its `return_status`, as CasADi reports it).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum NlpStatus {
    /// Converged to `tolerance` (`Solve_Succeeded`).
    SolveSucceeded,
    /// Converged to `acceptable_tolerance` only (`Solved_To_Acceptable_Level`).
    SolvedToAcceptableLevel,
    /// The restoration phase converged to a point minimising the constraint violation that is
    /// not feasible: the problem is (locally) infeasible (`Infeasible_Problem_Detected`).
    InfeasibleProblemDetected,
    /// `Search_Direction_Becomes_Too_Small`.
    SearchDirectionTooSmall,
    /// The iterates diverge (`Diverging_Iterates`): the problem may be unbounded.
    DivergingIterates,
    /// `User_Requested_Stop`.
    UserRequestedStop,
    /// `Feasible_Point_Found` (square-problem mode).
    FeasiblePointFound,
    /// `Maximum_Iterations_Exceeded`.
    MaximumIterationsExceeded,
    /// `Maximum_CpuTime_Exceeded`.
    MaximumCpuTimeExceeded,
    /// `Maximum_WallTime_Exceeded`.
    MaximumWallTimeExceeded,
    /// `Restoration_Failed`.
    RestorationFailed,
    /// `Error_In_Step_Computation`.
    ErrorInStepComputation,
    /// `Not_Enough_Degrees_Of_Freedom` (more active equalities than variables).
    NotEnoughDegreesOfFreedom,
    /// `Invalid_Problem_Definition`.
    InvalidProblemDefinition,
    /// `Invalid_Option` (e.g. a linear solver that is not available).
    InvalidOption,
    /// `Invalid_Number_Detected`: NaN or inf in a function value or derivative.
    InvalidNumberDetected,
    /// Any other status string (IPOPT's internal errors, CasADi's own statuses).
    Other(String),
}

impl NlpStatus {
    /// Maps IPOPT's status string.
    pub fn from_ipopt(status: &str) -> NlpStatus {
        match status {
            "Solve_Succeeded" => NlpStatus::SolveSucceeded,
            "Solved_To_Acceptable_Level" => NlpStatus::SolvedToAcceptableLevel,
            "Infeasible_Problem_Detected" => NlpStatus::InfeasibleProblemDetected,
            "Search_Direction_Becomes_Too_Small" => NlpStatus::SearchDirectionTooSmall,
            "Diverging_Iterates" => NlpStatus::DivergingIterates,
            "User_Requested_Stop" => NlpStatus::UserRequestedStop,
            "Feasible_Point_Found" => NlpStatus::FeasiblePointFound,
            "Maximum_Iterations_Exceeded" => NlpStatus::MaximumIterationsExceeded,
            "Maximum_CpuTime_Exceeded" => NlpStatus::MaximumCpuTimeExceeded,
            "Maximum_WallTime_Exceeded" => NlpStatus::MaximumWallTimeExceeded,
            "Restoration_Failed" => NlpStatus::RestorationFailed,
            "Error_In_Step_Computation" => NlpStatus::ErrorInStepComputation,
            "Not_Enough_Degrees_Of_Freedom" => NlpStatus::NotEnoughDegreesOfFreedom,
            "Invalid_Problem_Definition" => NlpStatus::InvalidProblemDefinition,
            "Invalid_Option" => NlpStatus::InvalidOption,
            "Invalid_Number_Detected" => NlpStatus::InvalidNumberDetected,
            other => NlpStatus::Other(other.to_owned()),
        }
    }

    /// True when IPOPT converged ([`SolveSucceeded`](NlpStatus::SolveSucceeded) or
    /// [`SolvedToAcceptableLevel`](NlpStatus::SolvedToAcceptableLevel)).
    pub fn is_success(&self) -> bool {
        matches!(
            self,
            NlpStatus::SolveSucceeded | NlpStatus::SolvedToAcceptableLevel
        )
    }
}

/// The result of [`NlpSolver::solve`](crate::NlpSolver::solve): IPOPT's last iterate, whether
/// or not it converged (see [`status`](NlpSolution::status)).
///
/// # Multiplier signs (CasADi's convention)
/// The Lagrangian is `L(x, λx, λg) = f(x) + λxᵀ x + λgᵀ g(x)`, so at a KKT point
/// `∇f + J_gᵀ λg + λx = 0`. A multiplier is positive when its upper bound is active, negative
/// when its lower bound is active, and 0 when the bound is inactive; for an equality constraint
/// `g = c` its sign is free. `λg` is then the sensitivity `-∂f*/∂ubg` (raising an active upper
/// bound by ε lowers the optimal value by about `λg·ε`).
#[derive(Debug, Clone, PartialEq)]
pub struct NlpSolution {
    /// The decision variables, by index.
    pub x: Vec<f64>,
    /// The objective value at `x`.
    pub f: f64,
    /// The constraint values at `x`, by constraint index.
    pub g: Vec<f64>,
    /// Multipliers of the variable bounds.
    pub lam_x: Vec<f64>,
    /// Multipliers of the constraints.
    pub lam_g: Vec<f64>,
    /// IPOPT's exit status.
    pub status: NlpStatus,
    /// IPOPT iterations.
    pub iterations: usize,
    /// Wall-clock time of the solve call (IPOPT and CasADi's function evaluations).
    pub solve_time: Duration,
    /// The `Nlp` that was solved.
    pub(crate) owner: Owner,
}

impl NlpSolution {
    /// The value of a variable (an [`Expr`] returned by
    /// [`Nlp::variable`](crate::Nlp::variable) of the problem solved); `None` if `var` is not a
    /// variable leaf of that problem.
    pub fn value(&self, var: &Expr) -> Option<f64> {
        if var.owner() != self.owner {
            return None;
        }
        var.variable_index().and_then(|i| self.x.get(i).copied())
    }
}
