//! One waypoint of a whole-body plan: the arm alone, else the whole-body IK's candidates in
//! order, each verified by `Prepared::check_whole_body`, the first that passes kept.
//!
//! The candidates after the arm alone (see the [module docs](super)):
//! 1. **Relaxed**: the tracked solution (below) with its arm moved towards the posture (the arm
//!    at the first waypoint) by at most [`WholeBodySettings::posture_step`] per joint, as the
//!    seed of one more `solve_near`; the null-space pull then keeps the arm near that posture
//!    and the base takes up what the arm gives back.
//! 2. **Tracked**: the grasp frame moved from the previous waypoint's to this one's in
//!    [`SUBSTEPS`] steps, each solved near the last, from "base unmoved, arm unchanged".
//! 3. **Restricted** ([`WholeBodySettings::restricted_base_steps`]): 1 and 2 again on a model
//!    whose base may not move the way the tracked solution moved it along one base coordinate
//!    (its step bound cut at 0 on that side), the coordinate it moved farthest along (relative
//!    to its bound) first; when that fails too, also kept from the way the new solution moved
//!    along its farthest coordinate still free, and so on. The IK knows no collisions: this is
//!    how a base step that meets the scene is steered off it (the models are built at first
//!    use, one per pattern of sides).

use nalgebra::DVector;

use super::model::{Side, WholeBodyIk};
use super::{WholeBodyFailure, WholeBodySettings};
use crate::kinematics::ik::{IkData, IkOutcome, IkSolution, IkSolver, IkTarget};
use crate::kinematics::robot::RobotModel;
use crate::motion::placement::GraspFrame;
use crate::motion::placement::manipulation::{Attempt, Prepared, unwrap_continuous};
use crate::motion::placement::plan::WaypointFailure;
use crate::motion::placement::{ManipulationSettings, PlacementError};
use crate::scene::SceneData;

/// A waypoint's base pose and arm configuration.
type Pose = ([f64; 3], DVector<f64>);

/// A waypoint's base pose and arm configuration, or why there is none.
pub(super) type Reached = Result<Pose, WholeBodyFailure>;

/// A whole-body IK configuration, or why the IK found none.
type Solved = Result<DVector<f64>, WholeBodyFailure>;

/// Intermediate grasp frames per waypoint of the tracked candidate.
const SUBSTEPS: usize = 4;

/// `solve_near` rounds per target.
const ROUNDS: usize = 3;

/// A base coordinate moved along when its step is beyond this share of its step bound.
const MOVED: f64 = 1e-6;

/// The solvers and scratch of one [`plan_whole_body`](super::plan_whole_body).
pub(super) struct Run<'a> {
    pub prepared: &'a Prepared<'a>,
    pub wb: WholeBodyIk,
    pub manipulation: &'a ManipulationSettings,
    pub settings: &'a WholeBodySettings,
    pub arm_data: IkData,
    /// The whole-body IK solver and scratch of each side pattern (index
    /// [`WholeBodyIk::code`]), built at first use.
    pub solvers: Vec<Option<(IkSolver, IkData)>>,
    pub scratch: SceneData,
}

/// Where a waypoint starts from.
pub(super) struct Origin<'a> {
    /// The previous waypoint's base pose and arm (`None` at the first).
    pub prev: Option<([f64; 3], &'a DVector<f64>)>,
    /// The base pose and arm seed of the first waypoint.
    pub start: ([f64; 3], &'a DVector<f64>),
    /// The arm's posture (the first waypoint's configuration), once there is one.
    pub posture: Option<&'a DVector<f64>>,
    /// Whether the arm alone is tried first.
    pub arm_first: bool,
    /// Whether the base must stay where it stood (the straight approach to the grasp and the
    /// straight retreat from the release): only the arm alone is tried.
    pub base_fixed: bool,
}

impl Run<'_> {
    /// Waypoint `k` from `at`: the arm alone, else the whole-body candidates. An arm-alone
    /// solution that takes the arm beyond [`WholeBodySettings::posture_tolerance`] of the
    /// posture and farther from it than the previous waypoint's is kept only if no
    /// whole-body candidate passes.
    pub(super) fn waypoint(
        &mut self,
        k: usize,
        at: &Origin<'_>,
    ) -> Result<Reached, PlacementError> {
        let p = self.prepared;
        let (from, from_q) = at.prev.unwrap_or(at.start);
        let world_from_base = RobotModel::world_from_base(from);
        let target = p.motion.grasps[k].ik_target_in_cone(
            &world_from_base,
            p.rotation,
            self.manipulation.approach_cone,
        );
        let mut fallback = None;
        if at.arm_first || at.base_fixed {
            let attempt = Attempt {
                base: from,
                k,
                target: &target,
                continuing: at.prev.map(|(_, q)| q),
                start: from_q,
            };
            let (q, failure) = p.solve_waypoint(
                &attempt,
                self.manipulation,
                &mut self.arm_data,
                &mut self.scratch,
            )?;
            if at.base_fixed {
                return Ok(match failure {
                    None => Ok((from, q)),
                    Some(f) => Err(WholeBodyFailure::Waypoint(f)),
                });
            }
            if failure.is_none() {
                if !self.drifts(&q, from_q, at.posture) {
                    return Ok(Ok((from, q)));
                }
                fallback = Some((from, q));
            }
        }
        let reached = match at.prev {
            Some(prev) => self.candidates(k, at, prev, &target)?,
            None => {
                let seed = self.wb.seed(from_q);
                let (solver, data) = self.solver(&vec![Side::Both; self.wb.base_dofs])?;
                let solved = match solver.solve_with(data, &target, &seed)? {
                    IkOutcome::Solved(IkSolution { q, .. }) => Ok(q),
                    IkOutcome::Infeasible(f) => Err(not_converged(&f.best)),
                    IkOutcome::Timeout(best) | IkOutcome::Cancelled(best) => {
                        Err(not_converged(&best))
                    }
                };
                self.verify(k, at, solved)?
            }
        };
        Ok(match (reached, fallback) {
            (Err(_), Some(arm_alone)) => Ok(arm_alone),
            (reached, _) => reached,
        })
    }

    /// Whether the arm-alone configuration `q` leaves the posture (beyond the tolerance and
    /// farther than `prev`, in the largest joint difference).
    fn drifts(
        &self,
        q: &DVector<f64>,
        prev: &DVector<f64>,
        posture: Option<&DVector<f64>>,
    ) -> bool {
        let Some(posture) = posture else {
            return false;
        };
        let off = (q - posture).amax();
        off > self.settings.posture_tolerance && off > (prev - posture).amax()
    }

    /// The whole-body candidates of the [module docs](self) for waypoint `k > 0` after the
    /// previous waypoint's base pose `from` and arm `from_q`, in order: the first that passes,
    /// else the first failure.
    fn candidates(
        &mut self,
        k: usize,
        at: &Origin<'_>,
        (from, from_q): ([f64; 3], &DVector<f64>),
        target: &IkTarget,
    ) -> Result<Reached, PlacementError> {
        let mut first = None;
        let free = vec![Side::Both; self.wb.base_dofs];
        let tracked = self.track(&free, k, from, from_q)?;
        let step = self.base_step(&tracked);
        if let Some(r) = self.settle(&free, k, at, target, tracked, &mut first)? {
            return Ok(Ok(r));
        }
        let Some(step) = step.filter(|_| self.settings.restricted_base_steps) else {
            return Ok(Err(first.expect("at least one candidate")));
        };
        let mut tried = vec![false; self.wb.patterns()];
        for i in self.moved_along(&step, &free) {
            let (mut sides, mut step, mut i) = (free.clone(), step.clone(), i);
            loop {
                sides[i] = if step[i] > 0.0 {
                    Side::Negative
                } else {
                    Side::Positive
                };
                let code = WholeBodyIk::code(&sides);
                if tried[code] {
                    break;
                }
                tried[code] = true;
                let tracked = self.track(&sides, k, from, from_q)?;
                let next = self.base_step(&tracked);
                if let Some(r) = self.settle(&sides, k, at, target, tracked, &mut first)? {
                    return Ok(Ok(r));
                }
                // Keep the base also from the way it moved now, farthest first.
                let Some(j) = next.and_then(|next| {
                    let j = self.moved_along(&next, &sides).first().copied();
                    step = next;
                    j
                }) else {
                    break;
                };
                i = j;
            }
        }
        Ok(Err(first.expect("at least one candidate")))
    }

    /// The base coordinates of a whole-body IK configuration.
    fn base_step(&self, solved: &Solved) -> Option<DVector<f64>> {
        let n = self.wb.base_dofs;
        solved.as_ref().ok().map(|q| q.rows(0, n).into_owned())
    }

    /// The base coordinates still free in `sides` along which `step` moves, the farthest
    /// (relative to its step bound) first.
    fn moved_along(&self, step: &DVector<f64>, sides: &[Side]) -> Vec<usize> {
        let share = |i: usize| step[i].abs() / self.wb.step_bounds[i];
        let mut order: Vec<usize> = (0..step.len())
            .filter(|i| sides[*i] == Side::Both && share(*i) > MOVED)
            .collect();
        order.sort_by(|a, b| share(*b).total_cmp(&share(*a)));
        order
    }

    /// The IK solver and scratch of the side pattern `sides`, built at first use.
    fn solver(&mut self, sides: &[Side]) -> Result<&mut (IkSolver, IkData), PlacementError> {
        let code = WholeBodyIk::code(sides);
        if self.solvers[code].is_none() {
            let p = &self.prepared.problem;
            let solver = self.wb.solver(p.robot, p.ik.settings(), sides)?;
            let data = IkData::new(&solver)?;
            self.solvers[code] = Some((solver, data));
        }
        Ok(self.solvers[code].as_mut().expect("built above"))
    }

    /// The relaxed candidate of the tracked configuration `tracked` (solver `solver`), then
    /// `tracked` itself: the first that passes, recording the first failure in `first`.
    fn settle(
        &mut self,
        sides: &[Side],
        k: usize,
        at: &Origin<'_>,
        target: &IkTarget,
        tracked: Solved,
        first: &mut Option<WholeBodyFailure>,
    ) -> Result<Option<Pose>, PlacementError> {
        if let (Ok(q), Some(posture)) = (&tracked, at.posture)
            && self.settings.posture_step > 0.0
        {
            let seed = self.relaxed(q, posture);
            let solved = self.near(sides, target, &seed)?;
            match self.verify(k, at, solved)? {
                Ok(r) => return Ok(Some(r)),
                Err(f) => {
                    first.get_or_insert(f);
                }
            }
        }
        Ok(match self.verify(k, at, tracked)? {
            Ok(r) => Some(r),
            Err(f) => {
                first.get_or_insert(f);
                None
            }
        })
    }

    /// The whole-body configuration `q` with its arm moved towards `posture` by at most
    /// [`WholeBodySettings::posture_step`] per joint.
    fn relaxed(&self, q: &DVector<f64>, posture: &DVector<f64>) -> DVector<f64> {
        let (b, step) = (self.wb.base_dofs, self.settings.posture_step);
        let mut seed = q.clone();
        for (j, target) in posture.iter().enumerate() {
            let d = target - seed[b + j];
            seed[b + j] += d.clamp(-step, step);
        }
        seed
    }

    /// The base pose and arm of a whole-body IK result for waypoint `k`, verified.
    fn verify(
        &mut self,
        k: usize,
        at: &Origin<'_>,
        solved: Solved,
    ) -> Result<Reached, PlacementError> {
        let solution = match solved {
            Ok(q) => q,
            Err(failure) => return Ok(Err(failure)),
        };
        let (from, from_q) = at.prev.unwrap_or(at.start);
        let (base, mut q) = self.wb.split(from, &solution);
        if at.prev.is_some() {
            unwrap_continuous(self.prepared.problem.robot, &mut q, from_q);
        }
        let failure = self.prepared.check_whole_body(
            at.prev,
            base,
            &q,
            k,
            (self.manipulation, self.settings),
            &mut self.scratch,
        )?;
        Ok(failure.map_or(Ok((base, q)), Err))
    }

    /// Whole-body IK for waypoint `k` from the base at `from` and the arm at `from_q` (the
    /// previous waypoint's): the grasp frame moved from waypoint `k − 1`'s to `k`'s in
    /// [`SUBSTEPS`] equal steps (positions and orientations interpolated), each solved near
    /// the previous result, so the base displacement grows with the handle's motion.
    fn track(
        &mut self,
        sides: &[Side],
        k: usize,
        from: [f64; 3],
        from_q: &DVector<f64>,
    ) -> Result<Solved, PlacementError> {
        let p = self.prepared;
        let world_from_base = RobotModel::world_from_base(from);
        let (a, b) = (&p.motion.grasps[k - 1], &p.motion.grasps[k]);
        let mut q = self.wb.seed(from_q);
        for i in 1..=SUBSTEPS {
            let t = i as f64 / SUBSTEPS as f64;
            let frame = GraspFrame {
                position: a.position + (b.position - a.position) * t,
                approach: a.approach.slerp(&b.approach, t),
                world_from_tool: a.world_from_tool.lerp_slerp(&b.world_from_tool, t),
            };
            let target = frame.ik_target_in_cone(
                &world_from_base,
                p.rotation,
                self.manipulation.approach_cone,
            );
            q = match self.near(sides, &target, &q)? {
                Ok(q) => q,
                Err(failure) => return Ok(Err(failure)),
            };
        }
        Ok(Ok(q))
    }

    /// `solve_near` from `seed`, continued from its best configuration up to [`ROUNDS`] times
    /// while it does not converge (each round is one attempt of `max_iterations` steps).
    fn near(
        &mut self,
        sides: &[Side],
        target: &IkTarget,
        seed: &DVector<f64>,
    ) -> Result<Solved, PlacementError> {
        let mut seed = seed.clone();
        let mut last = None;
        let (solver, data) = self.solver(sides)?;
        for _ in 0..ROUNDS {
            let best = match solver.solve_near_with(data, target, &seed)? {
                IkOutcome::Solved(IkSolution { q, .. }) => return Ok(Ok(q)),
                IkOutcome::Infeasible(f) => f.best,
                IkOutcome::Timeout(best) | IkOutcome::Cancelled(best) => best,
            };
            seed = best.q.clone();
            last = Some(not_converged(&best));
        }
        Ok(Err(last.expect("at least one round")))
    }
}

fn not_converged(best: &crate::kinematics::ik::IkBest) -> WholeBodyFailure {
    WholeBodyFailure::Waypoint(WaypointFailure::NotConverged {
        position_error: best.position_error,
        rotation_error: best.rotation_error,
    })
}
