//! One solve as its attempts: the seed, then random restarts, each a local descent of
//! QP steps until it converges, stalls or runs out of iterations or time.

use std::time::Instant;

use kinscene_pinocchio as pin;
use nalgebra::DVector;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{IkBest, IkData, IkFailure, IkOutcome, IkSolution, IkSolver, IkStats, NoConvergence};
use crate::kinematics::ik::target::Task;
use crate::kinematics::ik::{IkError, IkTarget};

/// An attempt that has not reduced its error by this factor over the last
/// [`STALL_WINDOW`] steps is stuck in a local minimum (or crawling along a limit) and is
/// abandoned for a restart.
const STALL_FACTOR: f64 = 0.9;
/// See [`STALL_FACTOR`].
const STALL_WINDOW: usize = 10;

/// The best configuration seen so far and its errors (`score` infinite before the first).
struct Best {
    q: DVector<f64>,
    score: f64,
    position_error: f64,
    rotation_error: f64,
}

impl Best {
    /// Keeps q if its `score` (‖e‖²) beats the best so far: a copy into the buffer, no
    /// allocation.
    fn offer(&mut self, q: &DVector<f64>, score: f64, task: &Task) {
        if score < self.score {
            self.q.copy_from(q);
            self.score = score;
            self.position_error = task.position_error;
            self.rotation_error = task.rotation_error;
        }
    }
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
    pub(super) fn run(
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
        let mut best = Best {
            q: seed.clone(),
            score: f64::INFINITY,
            position_error: f64::INFINITY,
            rotation_error: f64::INFINITY,
        };
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
                qp_steps: data.steps.qp_steps,
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
        best: &mut Best,
    ) -> Result<Attempt, IkError> {
        // ‖e‖² of the last STALL_WINDOW steps, step k's at k % STALL_WINDOW.
        let mut history = [0.0_f64; STALL_WINDOW];
        for step in 0..=self.settings.max_iterations {
            self.update_task(data, problem.target, &q, task)?;
            if task.position_error <= self.settings.position_tolerance
                && task.rotation_error <= self.settings.rotation_tolerance
            {
                return Ok(Attempt::Converged(q));
            }
            let score = task.residual.norm_squared();
            best.offer(&q, score, task);
            if step == self.settings.max_iterations {
                return Ok(Attempt::OutOfIterations);
            }
            if *iterations >= self.settings.max_total_iterations {
                return Ok(Attempt::OutOfIterationBudget);
            }
            if problem.deadline.is_some_and(|d| Instant::now() >= d) {
                return Ok(Attempt::OutOfTime);
            }
            let slot = &mut history[step % STALL_WINDOW];
            if step >= STALL_WINDOW && score.sqrt() > STALL_FACTOR * (*slot).sqrt() {
                return Ok(Attempt::Stalled);
            }
            *slot = score;
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
        let pose = pin::frame_placement_and_jacobian(
            &self.model,
            &mut data.data,
            q,
            self.frame,
            &mut data.jacobian,
        )?;
        task.update(target, &pose, &data.jacobian, &self.support_v);
        Ok(())
    }

    /// The step at q into `data.dq` (over the step variables): the minimiser of the step QP,
    /// as [`IkSettings::step_solver`](crate::kinematics::ik::IkSettings::step_solver) finds
    /// it (see [`IkSolver`]).
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
}
