//! The step QP solved densely: `min ½ dqᵀ H dq + gᵀ dq  s.t.  lower ≤ dq ≤ upper`, H symmetric
//! positive definite and `lower ≤ 0 ≤ upper`, by the primal active-set method on bound
//! constraints (Nocedal & Wright, *Numerical Optimization*, Algorithm 16.3), one Cholesky
//! factorisation of the free block per round.
//!
//! Start at `dq = 0` (feasible) with no bound fixed. Each round solves the equality-constrained
//! problem on the free coordinates (fixed ones held at their bound), `H_FF y_F = −(g_F + H_FW
//! dq_W)`, then
//! - if `y` leaves the box, moves from `dq` towards `y` until the first free coordinate meets
//!   its bound and fixes that coordinate there (the ratio test);
//! - otherwise sets `dq = y` and checks the multipliers of the fixed coordinates, `r = H dq + g`:
//!   a coordinate fixed at its lower bound needs `r_i ≥ 0`, at its upper bound `r_i ≤ 0`. If all
//!   hold, `dq` satisfies the KKT conditions of a strictly convex QP, so it is **the** minimiser;
//!   otherwise the most violated one is released and the next round starts.
//!
//! With no bound active at the minimiser (the common case away from the joint limits and
//! within the trust region) this is one factorisation: the damped-least-squares step itself.
//! The answer is returned only with its KKT certificate; after [`MAX_ROUNDS`] rounds (an
//! unlucky or degenerate active set) or a failed factorisation the caller falls back to
//! Clarabel, so the step taken is always the QP's minimiser whichever solver found it.

use nalgebra::{DMatrix, DVector};

/// Rounds (factorisations) before giving up. Each round fixes or releases one coordinate, so a
/// minimiser with k active bounds needs about k + 1 rounds: enough for every bound of a 10-DoF
/// chain, and still far cheaper than one Clarabel solve (~20 µs against ~0.2 µs per round).
const MAX_ROUNDS: usize = 24;

/// Whether a coordinate is free or held at one of its bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Status {
    Free,
    AtLower,
    AtUpper,
}

/// Scratch of [`DenseBoxQp::solve`] for `n` variables: nothing is allocated per solve.
#[derive(Debug)]
pub(crate) struct DenseBoxQp {
    status: Vec<Status>,
    dq: DVector<f64>,
    /// The free coordinates of the current round, ascending.
    free: Vec<usize>,
    /// The free block of H, then its Cholesky factor L (row-major, k × k, lower triangle).
    factor: Vec<f64>,
    /// The right-hand side, then the solution, of the free block's system (k entries).
    y: Vec<f64>,
    /// `1 / L_ii` of the factor (k entries).
    inverse_diagonal: Vec<f64>,
}

impl DenseBoxQp {
    pub fn new(n: usize) -> DenseBoxQp {
        DenseBoxQp {
            status: vec![Status::Free; n],
            dq: DVector::zeros(n),
            free: Vec::with_capacity(n),
            factor: vec![0.0; n * n],
            y: vec![0.0; n],
            inverse_diagonal: vec![0.0; n],
        }
    }

    /// The minimiser, or `None` when no certified minimiser was found within [`MAX_ROUNDS`]
    /// rounds or a free block was not numerically positive definite.
    pub fn solve(
        &mut self,
        h: &DMatrix<f64>,
        g: &DVector<f64>,
        lower: &DVector<f64>,
        upper: &DVector<f64>,
    ) -> Option<&DVector<f64>> {
        debug_assert_eq!(self.dq.len(), g.len(), "scratch sized for the problem");
        self.status.fill(Status::Free);
        self.dq.fill(0.0);
        self.active_set(h, g, lower, upper, false)
    }

    /// As [`DenseBoxQp::solve`], with the flag `true` when the minimiser is the unconstrained
    /// one `−H⁻¹ g` (the damped-least-squares step), which is then returned after the first
    /// factorisation without the multiplier check (no bound is fixed, so there is none to
    /// check); otherwise the active-set rounds continue from that factorisation.
    pub fn solve_unconstrained_first(
        &mut self,
        h: &DMatrix<f64>,
        g: &DVector<f64>,
        lower: &DVector<f64>,
        upper: &DVector<f64>,
    ) -> Option<(&DVector<f64>, bool)> {
        debug_assert_eq!(self.dq.len(), g.len(), "scratch sized for the problem");
        self.status.fill(Status::Free);
        self.dq.fill(0.0);
        if !self.free_minimiser(h, g) {
            return None;
        }
        if self.ratio_test(lower, upper).is_none() {
            for (k, &j) in self.free.iter().enumerate() {
                self.dq[j] = self.y[k];
            }
            return Some((&self.dq, true));
        }
        self.active_set(h, g, lower, upper, true)
            .map(|dq| (dq, false))
    }

    /// The active-set rounds from `dq` and `status`; with `factored`, the first round's free
    /// minimiser is already in `self.y`.
    fn active_set(
        &mut self,
        h: &DMatrix<f64>,
        g: &DVector<f64>,
        lower: &DVector<f64>,
        upper: &DVector<f64>,
        mut factored: bool,
    ) -> Option<&DVector<f64>> {
        // Multipliers below this count as zero: rounding in `H dq + g` is a few ulps of its
        // largest term.
        let scale = g.amax() + h.amax() * upper.amax().max(lower.amax());
        let tolerance = 1e-12 * scale.max(f64::MIN_POSITIVE);
        for _ in 0..MAX_ROUNDS {
            if !std::mem::take(&mut factored) && !self.free_minimiser(h, g) {
                return None;
            }
            match self.ratio_test(lower, upper) {
                Some((i, alpha, status)) => {
                    for (k, &j) in self.free.iter().enumerate() {
                        self.dq[j] += alpha * (self.y[k] - self.dq[j]);
                    }
                    self.dq[i] = if status == Status::AtLower {
                        lower[i]
                    } else {
                        upper[i]
                    };
                    self.status[i] = status;
                }
                None => {
                    for (k, &j) in self.free.iter().enumerate() {
                        self.dq[j] = self.y[k];
                    }
                    match self.most_violated_multiplier(h, g, tolerance) {
                        Some(i) => self.status[i] = Status::Free,
                        None => return Some(&self.dq),
                    }
                }
            }
        }
        None
    }

    /// Fills `self.free` and puts in `self.y` the minimiser over the free coordinates with the
    /// fixed ones held: `H_FF y = −(g_F + H_FW dq_W)`. `false` if `H_FF` is not numerically
    /// positive definite.
    fn free_minimiser(&mut self, h: &DMatrix<f64>, g: &DVector<f64>) -> bool {
        let n = g.len();
        self.free.clear();
        self.free
            .extend((0..n).filter(|&i| self.status[i] == Status::Free));
        let k = self.free.len();
        for (a, &i) in self.free.iter().enumerate() {
            for (b, &j) in self.free.iter().enumerate().take(a + 1) {
                self.factor[a * k + b] = h[(i, j)];
            }
            let mut rhs = -g[i];
            for j in 0..n {
                if self.status[j] != Status::Free {
                    rhs -= h[(i, j)] * self.dq[j];
                }
            }
            self.y[a] = rhs;
        }
        cholesky_solve(
            &mut self.factor[..k * k],
            &mut self.y[..k],
            &mut self.inverse_diagonal[..k],
        )
    }

    /// The free coordinate that first meets a bound on the segment from `dq` to `y`, the
    /// fraction of the segment travelled and the bound, or `None` if `y` is in the box.
    fn ratio_test(
        &self,
        lower: &DVector<f64>,
        upper: &DVector<f64>,
    ) -> Option<(usize, f64, Status)> {
        let mut blocking = None;
        let mut alpha = 1.0;
        for (k, &i) in self.free.iter().enumerate() {
            let (from, to) = (self.dq[i], self.y[k]);
            let (bound, status) = if to < lower[i] {
                (lower[i], Status::AtLower)
            } else if to > upper[i] {
                (upper[i], Status::AtUpper)
            } else {
                continue;
            };
            // `from` is within the box and `to` beyond `bound`, so 0 ≤ a < 1.
            let a = ((bound - from) / (to - from)).clamp(0.0, 1.0);
            if blocking.is_none() || a < alpha {
                alpha = a;
                blocking = Some((i, status));
            }
        }
        blocking.map(|(i, status)| (i, alpha, status))
    }

    /// The fixed coordinate whose multiplier has the wrong sign by the most, if any.
    fn most_violated_multiplier(
        &self,
        h: &DMatrix<f64>,
        g: &DVector<f64>,
        tolerance: f64,
    ) -> Option<usize> {
        let mut worst = None;
        let mut worst_violation = tolerance;
        for i in 0..g.len() {
            let sign = match self.status[i] {
                Status::Free => continue,
                Status::AtLower => -1.0,
                Status::AtUpper => 1.0,
            };
            // H is symmetric: column i is row i, and columns are contiguous.
            let gradient = h.column(i).dot(&self.dq) + g[i];
            // At the lower bound the objective must not decrease inwards: gradient ≥ 0.
            let violation = sign * gradient;
            if violation > worst_violation {
                worst_violation = violation;
                worst = Some(i);
            }
        }
        worst
    }
}

/// Solves `A x = b` in place for the symmetric positive definite k × k matrix A whose lower
/// triangle is in `a` (row-major; overwritten by its Cholesky factor L, A = L Lᵀ) and `b`
/// (overwritten by x); k = `b.len()`, and `inverse_diagonal` (k entries) receives `1 / L_ii`
/// (one division per row instead of one per entry: at this size the divisions' latency is
/// most of the cost). `false` if a pivot is not positive (A not numerically positive
/// definite). Written out rather than nalgebra's `Cholesky` so that the solver's scratch is
/// reused: at k ≤ 10 an allocation costs as much as the factorisation.
fn cholesky_solve(a: &mut [f64], b: &mut [f64], inverse_diagonal: &mut [f64]) -> bool {
    let k = b.len();
    for i in 0..k {
        for j in 0..=i {
            let mut sum = a[i * k + j];
            for m in 0..j {
                sum -= a[i * k + m] * a[j * k + m];
            }
            if i == j {
                if sum.is_nan() || sum <= 0.0 {
                    return false;
                }
                let root = sum.sqrt();
                a[i * k + i] = root;
                inverse_diagonal[i] = 1.0 / root;
            } else {
                a[i * k + j] = sum * inverse_diagonal[j];
            }
        }
    }
    // L z = b, then Lᵀ x = z.
    for i in 0..k {
        let mut sum = b[i];
        for m in 0..i {
            sum -= a[i * k + m] * b[m];
        }
        b[i] = sum * inverse_diagonal[i];
    }
    for i in (0..k).rev() {
        let mut sum = b[i];
        for m in i + 1..k {
            sum -= a[m * k + i] * b[m];
        }
        b[i] = sum * inverse_diagonal[i];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::ik::qp::StepQp;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random step QP like the solver's: H = JᵀJ + λI for a random 6 × n J, g = −Jᵀe, box
    /// `[−a, b]` with a, b in [0, 0.5] (some 0: a coordinate at its limit).
    fn random_problem(
        n: usize,
        rng: &mut ChaCha8Rng,
    ) -> (DMatrix<f64>, DVector<f64>, DVector<f64>, DVector<f64>, f64) {
        let j = DMatrix::from_fn(6, n, |_, _| rng.random_range(-1.0..1.0));
        let e = DVector::from_fn(6, |_, _| rng.random_range(-1.0..1.0));
        let lambda = 10f64.powf(rng.random_range(-7.0..0.0));
        let h = j.transpose() * &j + DMatrix::identity(n, n) * lambda;
        let g = -(j.transpose() * e);
        let bound = |rng: &mut ChaCha8Rng| {
            if rng.random_bool(0.1) {
                0.0
            } else {
                rng.random_range(0.0..0.5)
            }
        };
        let lower = DVector::from_fn(n, |_, _| -bound(rng));
        let upper = DVector::from_fn(n, |_, _| bound(rng));
        (h, g, lower, upper, lambda)
    }

    fn objective(h: &DMatrix<f64>, g: &DVector<f64>, x: &DVector<f64>) -> f64 {
        0.5 * x.dot(&(h * x)) + g.dot(x)
    }

    /// The dense solver's certified answers are Clarabel's minimisers: within the box exactly,
    /// and no worse in objective than Clarabel's point (which is feasible to ~1e-9, so its
    /// objective can undercut the true minimum by a few 1e-9 × gradient norm). The points
    /// themselves are compared where the problem is well conditioned (λ ≥ 0.1, the smallest
    /// curvature): an objective gap δ then bounds the distance by √(2δ/λ).
    #[test]
    fn agrees_with_clarabel_on_random_step_qps() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut certified = 0;
        let trials = 2000;
        for trial in 0..trials {
            let n = rng.random_range(1..=10);
            let (h, g, lower, upper, lambda) = random_problem(n, &mut rng);
            let mut dense = DenseBoxQp::new(n);
            let Some(x) = dense.solve(&h, &g, &lower, &upper).cloned() else {
                continue;
            };
            certified += 1;
            for i in 0..n {
                assert!(
                    lower[i] <= x[i] && x[i] <= upper[i],
                    "trial {trial}: x[{i}]"
                );
            }
            // The damped-least-squares-first entry: the same rounds, so the same bits; its
            // flag says whether no bound is active at the minimiser.
            let (first, unconstrained) = dense
                .solve_unconstrained_first(&h, &g, &lower, &upper)
                .expect("certified above");
            assert_eq!(first, &x, "trial {trial}");
            let free = -(h.clone().cholesky().unwrap().solve(&g));
            let inside = (0..n).all(|i| lower[i] <= free[i] && free[i] <= upper[i]);
            assert_eq!(unconstrained, inside, "trial {trial}");
            let reference = StepQp::new(n).solve(&h, &g, &lower, &upper).unwrap();
            let slack = 1e-7 * (1.0 + g.norm());
            assert!(
                objective(&h, &g, &x) <= objective(&h, &g, &reference) + slack,
                "trial {trial}: dense {} vs Clarabel {}",
                objective(&h, &g, &x),
                objective(&h, &g, &reference)
            );
            if lambda >= 0.1 {
                assert!(
                    (&x - &reference).amax() < 1e-3,
                    "trial {trial}: {x} vs {reference}"
                );
            }
        }
        // Random boxes with many active bounds: most are still certified within the rounds.
        assert!(
            certified * 10 >= trials * 9,
            "{certified}/{trials} certified"
        );
    }

    #[test]
    fn cholesky_solve_matches_nalgebra() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        for k in 1..=10 {
            let m = DMatrix::from_fn(k, k, |_, _| rng.random_range(-1.0..1.0));
            let a = &m * m.transpose() + DMatrix::identity(k, k) * 1e-3;
            let b = DVector::from_fn(k, |_, _| rng.random_range(-1.0..1.0));
            let mut flat: Vec<f64> = (0..k * k).map(|i| a[(i / k, i % k)]).collect();
            let mut x = b.as_slice().to_vec();
            assert!(cholesky_solve(&mut flat, &mut x, &mut vec![0.0; k]));
            let expected = a.clone().cholesky().unwrap().solve(&b);
            let x = DVector::from_vec(x);
            // Relative to the solution: cond(A) ≤ ~1e4 here, so ~1e-12 is double precision.
            assert!((&x - &expected).amax() <= 1e-9 * expected.amax(), "k = {k}");
        }
        let mut indefinite = vec![1.0, 2.0, 2.0, 1.0];
        assert!(!cholesky_solve(
            &mut indefinite,
            &mut [1.0, 1.0],
            &mut [0.0, 0.0]
        ));
    }

    #[test]
    fn an_interior_minimiser_is_the_damped_least_squares_step() {
        let h = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
        let g = DVector::from_vec(vec![-0.1, 0.05]);
        let wide = DVector::from_element(2, 10.0);
        let x = DenseBoxQp::new(2)
            .solve(&h, &g, &-&wide, &wide)
            .cloned()
            .unwrap();
        let expected = h.clone().cholesky().unwrap().solve(&-&g);
        assert!((x - expected).amax() < 1e-14);
    }
}
