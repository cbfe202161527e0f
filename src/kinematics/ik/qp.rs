//! The step QP, solved with Clarabel:
//! `min ½ dqᵀ H dq + gᵀ dq  s.t.  lower ≤ dq ≤ upper` (H symmetric positive definite).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT,
    SolverStatus,
};
use nalgebra::{DMatrix, DVector};

use super::IkError;

/// Clarabel problem data for `n` variables: H's dense upper triangle and the box as
/// `[I; −I] dq + s = [upper; −lower]`, `s ≥ 0`. The sparsity pattern is fixed, so after the
/// first solve the solver is reused through Clarabel's data updates (no new symbolic
/// factorisation, no reallocation).
pub(crate) struct StepQp {
    n: usize,
    solver: Option<DefaultSolver<f64>>,
    p_values: Vec<f64>,
    q: Vec<f64>,
    b: Vec<f64>,
}

impl std::fmt::Debug for StepQp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StepQp")
            .field("n", &self.n)
            .field("built", &self.solver.is_some())
            .finish()
    }
}

impl StepQp {
    pub fn new(n: usize) -> StepQp {
        StepQp {
            n,
            solver: None,
            p_values: vec![0.0; n * (n + 1) / 2],
            q: vec![0.0; n],
            b: vec![0.0; 2 * n],
        }
    }

    /// The minimiser. `lower ≤ 0 ≤ upper` keeps the problem feasible; H must be positive
    /// definite (the damping guarantees it), so the minimiser is unique.
    ///
    /// # Errors
    /// [`IkError::QpSetup`] if Clarabel rejects the data, [`IkError::QpFailed`] for any
    /// final status other than `Solved`/`AlmostSolved`.
    pub fn solve(
        &mut self,
        h: &DMatrix<f64>,
        g: &DVector<f64>,
        lower: &DVector<f64>,
        upper: &DVector<f64>,
    ) -> Result<DVector<f64>, IkError> {
        let n = self.n;
        let mut k = 0;
        for j in 0..n {
            for i in 0..=j {
                self.p_values[k] = h[(i, j)];
                k += 1;
            }
        }
        for i in 0..n {
            self.q[i] = g[i];
            self.b[i] = upper[i];
            self.b[n + i] = -lower[i];
        }
        let solver = match self.solver.as_mut() {
            Some(solver) => {
                solver
                    .update_P(&self.p_values)
                    .and_then(|()| solver.update_q(&self.q))
                    .and_then(|()| solver.update_b(&self.b))
                    .map_err(|e| IkError::QpSetup {
                        message: e.to_string(),
                    })?;
                solver
            }
            None => {
                let built = self.build()?;
                self.solver.insert(built)
            }
        };
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                Ok(DVector::from_column_slice(&solver.solution.x))
            }
            status => Err(IkError::QpFailed {
                status: format!("{status:?}"),
            }),
        }
    }

    fn build(&self) -> Result<DefaultSolver<f64>, IkError> {
        let n = self.n;
        let colptr: Vec<usize> = (0..=n).map(|j| j * (j + 1) / 2).collect();
        let rowval: Vec<usize> = (0..n).flat_map(|j| 0..=j).collect();
        let p = CscMatrix::new(n, n, colptr, rowval, self.p_values.clone());
        let a = CscMatrix::new(
            2 * n,
            n,
            (0..=n).map(|j| 2 * j).collect(),
            (0..n).flat_map(|j| [j, n + j]).collect(),
            (0..n).flat_map(|_| [1.0, -1.0]).collect(),
        );
        let cones = [NonnegativeConeT(2 * n)];
        DefaultSolver::new(&p, &self.q, &a, &self.b, &cones, settings()).map_err(|e| {
            IkError::QpSetup {
                message: e.to_string(),
            }
        })
    }
}

/// Quiet; without presolve (which would forbid data updates); with the absolute duality-gap
/// tolerances off. Near convergence the whole objective is ~‖e‖² ≪ Clarabel's default
/// absolute tolerance (1e-8), so that test would accept steps as inaccurate as the step
/// itself and stall the descent; the relative tolerances (1e-8, reduced 5e-5) still apply.
fn settings() -> DefaultSettings<f64> {
    DefaultSettingsBuilder::default()
        .verbose(false)
        .presolve_enable(false)
        .tol_gap_abs(0.0)
        .reduced_tol_gap_abs(0.0)
        .build()
        .expect("constant Clarabel settings are valid")
}
