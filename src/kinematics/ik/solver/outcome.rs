//! How an IK solve ends: the solution, or why it did not converge and the best configuration
//! seen.

use nalgebra::DVector;

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
