//! The complete lattice search: lazy best-first search over lattice states with a closed set,
//! in focal order ([`Open`](open::Open); A* with `heuristic_weight = 1`), grown over an active
//! joint set.
//!
//! Its model, with the move re-queue and the rounds that stop early to grow the active set, is
//! `search_run` in `proofs/theories/Task/Requeue.v` (soundness, completeness over all joints,
//! termination; a re-queued key stays a lower bound: `RequeueKey.v`). The model pops any open
//! item, so the focal order is covered; the sweep prefetch only reads the next open items.
//!
//! This file holds [`run`] and its steps before the passes (the static proofs, the dive);
//! the passes and rounds are in `pass.rs`, a popped item's expansion or check in `expand.rs`.

mod expand;
mod open;
mod pass;
mod report;

use std::time::Instant;

use self::report::{Best, Incumbent, stopped, unreachable_target};
use super::check::{Caches, Checker, Choice, Key};
use super::conflict::static_conflict;
use super::goal::Problem;
use super::greedy;
use super::heuristic::Heuristic;
use super::interaction::Interaction;
use super::lattice::Lattice;
use super::plan::{Cause, Infeasibility, Outcome, PlanResult, SearchStats, Step};
use super::refine::Refiner;
use super::settings::TaskSettings;
use super::{Error, Termination};
use crate::scene::{JointId, SceneData, SceneModel};

/// Most moves a goal target's static base-pose proof checks
/// ([`Checker::target_without_base_pose`]); each costs one manipulation region.
const STATIC_BASE_POSE_CHECKS: usize = 256;

/// One search: the problem with its checker and heuristic, and what carries over from pass
/// to pass and from round to round (the memo, the incumbent, the active joints).
struct Search<'a> {
    model: &'a SceneModel,
    problem: &'a Problem,
    settings: &'a TaskSettings,
    refiner: &'a dyn Refiner,
    termination: &'a Termination<'a>,
    lattice: &'a Lattice,
    checker: &'a Checker<'a>,
    heuristic: &'a Heuristic<'a>,
    started: Instant,
    start_key: Key,
    caches: Caches,
    data: SceneData,
    stats: SearchStats,
    /// The final pass's focal weight (`heuristic_weight`).
    final_w: f64,
    /// The current pass's focal weight.
    w: f64,
    /// The best plan so far (the dive's or a pass's).
    incumbent: Option<Incumbent>,
    /// The joints the search may move (closed over ancestors).
    active: Vec<bool>,
    /// The closed state nearest the goal so far.
    best_partial: Option<Best>,
    /// Sweeps checked in parallel.
    threads: usize,
    /// The partial-order reduction: `Off`, not yet needed, or its interaction relation.
    reduction: Reduction,
}

/// The search's partial-order reduction ([`TaskSettings::reduction`]).
enum Reduction {
    /// Off (by the settings or the refiner), or useless: some part blocks floor cells, so
    /// every joint with a handle is in one component (`interaction.rs`).
    Off,
    /// On, its relation not computed yet (the first reduced round computes it).
    Pending,
    /// On, with the relation.
    On(Interaction),
}

/// Plans with the lattice search: the static proofs of infeasibility, the greedy dive, then
/// the anytime passes over a growing active set (see the module docs of [`crate::task`]).
pub(crate) fn run(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    refiner: &dyn Refiner,
    termination: &Termination<'_>,
) -> Result<PlanResult, Error> {
    let started = Instant::now();
    let lattice = Lattice::new(model, problem, &settings.lattice);
    let checker = Checker::new(model, problem, settings, &lattice)?;
    let start_key = start_key(model, problem, &lattice);
    let mut data = SceneData::new(model);
    let heuristic = Heuristic::new(model, problem, settings, &lattice, &checker, &mut data)?;
    let mut search = Search {
        model,
        problem,
        settings,
        refiner,
        termination,
        lattice: &lattice,
        checker: &checker,
        heuristic: &heuristic,
        started,
        start_key,
        caches: Caches::for_search(),
        data,
        stats: SearchStats::default(),
        final_w: settings.heuristic_weight,
        w: first_pass_weight(settings),
        incumbent: None,
        active: goal_joints(model, problem),
        best_partial: None,
        threads: threads(settings),
        reduction: if settings.reduction && refiner.local() {
            Reduction::Pending
        } else {
            Reduction::Off
        },
    };
    if let Some(why) = search.static_infeasibility()? {
        search.stats.elapsed = started.elapsed();
        return Ok(PlanResult {
            outcome: Outcome::Infeasible(why),
            stats: search.stats,
        });
    }
    search.stats.passes = 1;
    if let Some(result) = search.dive()? {
        return Ok(result);
    }
    search.passes()
}

/// The lattice state of the problem's start.
fn start_key(model: &SceneModel, problem: &Problem, lattice: &Lattice) -> Key {
    (0..model.nq())
        .map(|k| {
            lattice
                .index_of(JointId(k), problem.start.as_slice()[k])
                .expect("the start value is in the lattice") as u16
        })
        .collect()
}

/// Sweeps checked in parallel: `settings.parallelism`, or rayon's thread count for 0.
fn threads(settings: &TaskSettings) -> usize {
    match settings.parallelism {
        0 => rayon::current_num_threads(),
        n => n,
    }
    .max(1)
}

/// The first pass's focal weight: `first_pass_weight` (at least `heuristic_weight`) with base
/// travel; without it the heuristic is close to the cost and one pass of `heuristic_weight` is
/// usually faster (see `TaskSettings::first_pass_weight`).
fn first_pass_weight(settings: &TaskSettings) -> f64 {
    let final_w = settings.heuristic_weight;
    if settings.cost.travel > 0.0 {
        settings.first_pass_weight.max(final_w)
    } else {
        final_w
    }
}

/// The joints active in the first round: the goal joints and their ancestors.
fn goal_joints(model: &SceneModel, problem: &Problem) -> Vec<bool> {
    let mut active = vec![false; model.nq()];
    for (j, _) in problem.goal.targets() {
        close_over_ancestors(model, *j, &mut active);
    }
    active
}

impl Search<'_> {
    /// The lower bound on the cost still to pay from state `key` with the robot at `cell`.
    fn h(&self, key: &[u16], cell: usize) -> f64 {
        self.heuristic.work(key) + self.heuristic.travel_of(key).at(cell)
    }

    /// Whether a new round uses the partial-order reduction: when it is on, and either moves
    /// cost the same in any order (`travel = 0`: the reduction keeps an optimal plan's cost,
    /// see `interaction.rs`) or no plan is known yet (the round only has to find one; if it
    /// prunes, its plan's proven factor is taken over the start's lower bound, and the passes
    /// that improve on it run without the reduction). Computes the relation on first use:
    /// `Off` if a part blocks floor cells at some lattice value (then the reduction could
    /// prune only moves of joints without a handle, which are infeasible anyway).
    fn reduces(&mut self) -> Result<bool, Error> {
        if !(self.settings.cost.travel == 0.0 || self.incumbent.is_none()) {
            return Ok(false);
        }
        if let Reduction::Pending = self.reduction {
            let floor = self
                .checker
                .floor_joints(&mut self.data, &self.start_key, true)?;
            self.reduction = if floor.iter().any(|f| *f) {
                Reduction::Off
            } else {
                Reduction::On(Interaction::of(
                    self.checker,
                    &mut self.data,
                    &self.start_key,
                )?)
            };
        }
        Ok(matches!(self.reduction, Reduction::On(_)))
    }

    /// The interaction relation, when the reduction is on and computed.
    pub(super) fn interaction(&self) -> Option<&Interaction> {
        match &self.reduction {
            Reduction::On(i) => Some(i),
            _ => None,
        }
    }

    /// Records the search's time and refiner vetoes in its statistics.
    fn finish(&mut self) {
        self.stats.elapsed = self.started.elapsed();
        self.stats.vetoes = self.caches.vetoes;
    }

    /// The result when the budget or the cancel flag stops the search, with `least` the least
    /// open lower bound (see [`stopped`]).
    fn stop(&mut self, least: f64) -> PlanResult {
        self.finish();
        stopped(
            self.model,
            self.problem,
            self.incumbent.take(),
            self.best_partial.take(),
            least,
            std::mem::take(&mut self.stats),
        )
    }

    /// Static proofs of infeasibility (sound for the whole lattice, see `conflict.rs` and
    /// `heuristic.rs`): a goal joint no move can bring into its target, or two goal parts
    /// that collide in every goal state.
    fn static_infeasibility(&mut self) -> Result<Option<Infeasibility>, Error> {
        if self.problem.goal.is_satisfied(&self.problem.start) {
            return Ok(None);
        }
        let unreachable = self.heuristic.unreachable_targets();
        if let Some(&k) = unreachable.first() {
            // The direct move into the target, as the example in numbers.
            let (joint, target) = self.problem.goal.targets()[k];
            let from = self.problem.start.as_slice()[joint.index()];
            let to = self.lattice.index_of(joint, target.nearest(from));
            let to = to.and_then(|i| u16::try_from(i).ok());
            let shortfall = match to {
                Some(to) => self.checker.reach_shortfall(
                    &mut self.caches,
                    &mut self.data,
                    &self.start_key,
                    joint,
                    to,
                )?,
                None => None,
            };
            return Ok(Some(unreachable_target(
                self.model,
                self.problem,
                self.settings,
                self.heuristic,
                k,
                shortfall,
            )));
        }
        for (k, (joint, target)) in self.problem.goal.targets().iter().enumerate() {
            let proof = self.checker.target_without_base_pose(
                &mut self.caches,
                &mut self.data,
                &self.start_key,
                *joint,
                &|v| target.contains(v),
                STATIC_BASE_POSE_CHECKS,
            )?;
            if let Some((_, cause)) = proof {
                let shortfall = match cause {
                    Cause::NoBasePose { shortfall } => shortfall.map(|s| *s),
                    _ => None,
                };
                return Ok(Some(unreachable_target(
                    self.model,
                    self.problem,
                    self.settings,
                    self.heuristic,
                    k,
                    shortfall,
                )));
            }
        }
        static_conflict(
            self.model,
            self.problem,
            self.checker,
            self.lattice,
            self.termination,
        )
    }

    /// The greedy dive: its plan, if it finds one, is the first incumbent, and the result at
    /// once when it is already proven within the final weight of the start's lower bound.
    fn dive(&mut self) -> Result<Option<PlanResult>, Error> {
        if !self.settings.dive || self.problem.goal.is_satisfied(&self.problem.start) {
            return Ok(None);
        }
        let cx = greedy::Context {
            model: self.model,
            problem: self.problem,
            settings: self.settings,
            lattice: self.lattice,
            checker: self.checker,
            refiner: self.refiner,
        };
        let Some(d) = greedy::dive(
            &cx,
            &mut self.caches,
            &mut self.data,
            &self.start_key,
            &mut self.stats,
            self.termination,
        )?
        else {
            return Ok(None);
        };
        self.stats.first_plan = Some(self.started.elapsed());
        self.stats.greedy_first_plan = true;
        let least = self.h(&self.start_key, self.checker.start_cell);
        let factor = if d.cost <= least { 1.0 } else { d.cost / least };
        let inc = Incumbent {
            steps: d.steps,
            cost: d.cost,
            factor,
        };
        if factor <= self.final_w + 1e-9 {
            self.finish();
            return Ok(Some(inc.solved(factor, std::mem::take(&mut self.stats))));
        }
        self.incumbent = Some(inc);
        Ok(None)
    }
}

fn close_over_ancestors(model: &SceneModel, joint: JointId, active: &mut [bool]) {
    let mut id = joint.part();
    active[id.index()] = true;
    while let crate::scene::Parent::Part(p) = model.parts()[id.index()].parent() {
        active[p.index()] = true;
        id = p;
    }
}

/// The step and its cost (the search's) of a feasible move of `joint` from its value in
/// `key` to lattice value `to`.
pub(super) fn feasible_step(
    model: &SceneModel,
    lattice: &Lattice,
    settings: &TaskSettings,
    key: &[u16],
    joint: JointId,
    to: u16,
    choice: &Choice,
) -> (Step, f64) {
    let c = &settings.cost;
    let cost = c.action + c.actuation * choice.actuation + c.travel * choice.travel;
    let step = Step {
        joint: model.joints()[joint.index()].name.clone(),
        from: lattice.values(joint)[key[joint.index()] as usize],
        to: lattice.values(joint)[to as usize],
        handle: Some(
            model
                .handle(choice.handle)
                .map(|h| h.name.clone())
                .unwrap_or_default(),
        ),
        base: Some(choice.base),
        travel: choice.travel,
        cost,
    };
    (step, cost)
}
