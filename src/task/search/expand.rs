//! A popped item of a round: a state is closed and its moves pushed (or, at a goal, the pass
//! ends); a move is re-queued with a tighter bound or checked, its sweep prefetched with the
//! next few.

use std::collections::HashSet;

use rayon::prelude::*;

use super::Search;
use super::feasible_step;
use super::open::{Entry, Item};
use super::pass::{Flow, Node, Recorded, Round, path_to};
use super::report::Incumbent;
use crate::scene::{JointId, SceneData, SceneModel, State};
use crate::task::Error;
use crate::task::check::{Blockers, Caches, Checker, Key, SweepVerdict, Verdict};
use crate::task::plan::{Outcome, Plan, PlanResult, SearchStats};

/// A move out of closed node `from`: joint `joint` to its lattice value `to`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Move {
    pub(super) from: usize,
    pub(super) joint: JointId,
    pub(super) to: u16,
}

impl Search<'_> {
    /// Closes `node`, popped with priority `f` (unless it is closed already): it becomes the
    /// best partial plan if it is the nearest the goal so far, ends the pass if it meets the
    /// goal, and otherwise pushes its moves.
    pub(super) fn expand(&mut self, round: &mut Round, node: Node, f: f64) -> Result<Flow, Error> {
        if !round.closed.insert(node.key.clone()) {
            return Ok(Flow::Continue);
        }
        self.stats.expanded += 1;
        let idx = round.nodes.len();
        let key = node.key.clone();
        round.nodes.push(node);
        let state = self.checker.state_of(&key);
        let unmet = self
            .problem
            .goal
            .targets()
            .iter()
            .filter(|(j, i)| !i.contains(state.q[j.index()]))
            .count();
        let hk = self.h(&key, round.nodes[idx].robot);
        if self
            .best_partial
            .as_ref()
            .is_none_or(|(u, bh, _)| (unmet, hk) < (*u, *bh))
        {
            self.best_partial = Some((unmet, hk, path_to(&round.nodes, idx)));
        }
        if unmet == 0 {
            return Ok(self.reached_goal(round, idx, f));
        }
        self.push_moves(round, idx, &key, &state)?;
        Ok(Flow::Continue)
    }

    /// Closed node `idx` meets the goal (popped with priority `f`): the result if its cost is
    /// proven within the final weight or this is the final pass; otherwise it becomes the
    /// incumbent and the final pass starts.
    fn reached_goal(&mut self, round: &Round, idx: usize, f: f64) -> Flow {
        let g = round.nodes[idx].g;
        // Proven factor: its cost over the least lower bound still open (the popped item's
        // own `f` included). A reduced round with travel that has pruned a move holds the
        // reordered plans only, whose costs may differ: its bound is the start's (as for the
        // dive's plan).
        let exact = !round.pruned || self.settings.cost.travel == 0.0;
        let least = if exact {
            round.open.least_f().min(f)
        } else {
            self.h(&self.start_key, self.checker.start_cell)
        };
        let factor = if g <= least { 1.0 } else { g / least };
        let steps = path_to(&round.nodes, idx);
        self.stats.first_plan.get_or_insert(self.started.elapsed());
        let focal = if exact { self.w } else { f64::INFINITY };
        if factor <= self.final_w + 1e-9 || focal <= self.final_w {
            // Within the final weight, or a final-pass plan (cheaper than any incumbent by
            // the cap, and within `final_w` by the focal rule).
            self.finish();
            self.stats.suboptimality = Some(factor.min(focal));
            return Flow::Done(Box::new(PlanResult {
                outcome: Outcome::Solved(Plan { steps, cost: g }),
                stats: std::mem::take(&mut self.stats),
            }));
        }
        self.incumbent = Some(Incumbent {
            steps,
            cost: g,
            factor: factor.min(focal),
        });
        self.start_final_pass();
        Flow::NextPass
    }

    /// Pushes the moves of every active joint out of closed node `idx` (state `key`) to the
    /// lattice values whose states are not closed, unchecked, each with its lower bound.
    fn push_moves(
        &mut self,
        round: &mut Round,
        idx: usize,
        key: &Key,
        state: &State,
    ) -> Result<(), Error> {
        let g = round.nodes[idx].g;
        let robot = self.checker.cell_xy(round.nodes[idx].robot);
        let approach =
            self.heuristic
                .approach(self.model, &mut self.data, state, &self.active, robot)?;
        let pushed = self.reduced_joints(round, state);
        for (j, is_active) in self.active.iter().enumerate() {
            if !is_active {
                continue;
            }
            let joint = JointId(j);
            if !pushed.as_ref().is_none_or(|p| p[j]) {
                self.stats.pruned += self.lattice.values(joint).len() - 1;
                round.pruned = true;
                continue;
            }
            for to in 0..self.lattice.values(joint).len() as u16 {
                if to == key[j] {
                    continue;
                }
                let mut next = key.clone();
                next[j] = to;
                if round.closed.contains(&next) {
                    continue;
                }
                // The move's cost without travel, the rest of the plan's, and the travel to
                // the move's base pose or on from there.
                let lb = self.heuristic.move_work(joint, key[j], to);
                let travel = self
                    .heuristic
                    .travel_of(&next)
                    .at(round.nodes[idx].robot)
                    .max(approach[j]);
                round.seq += 1;
                round.open.push(Entry {
                    f: g + lb + self.heuristic.work(&next) + travel,
                    g: g + lb,
                    unmet: self.heuristic.unmet(&next),
                    seq: round.seq,
                    item: Item::Edge {
                        from: idx,
                        joint,
                        to,
                        // Without travel the region bound adds nothing.
                        bounded: self.settings.cost.travel == 0.0,
                    },
                });
            }
        }
        Ok(())
    }

    /// The joints whose moves a state with joint values `state` pushes in a reduced round:
    /// the component of [`Interaction::reduced_component`](crate::task::Interaction); `None`
    /// (all) outside reduced rounds.
    fn reduced_joints(&self, round: &Round, state: &State) -> Option<Vec<bool>> {
        if !round.reduced {
            return None;
        }
        let interaction = self.interaction()?;
        let c = interaction.reduced_component(self.problem, &state.q)?;
        Some(
            (0..self.model.nq())
                .map(|j| interaction.component(JointId(j)) == c)
                .collect(),
        )
    }

    /// Move `mv`, popped with priority `f`, `g` and `unmet` targets: skipped if its state is
    /// closed; unless `bounded`, its priority is first tightened with the move's region
    /// (travel to its base cells and on from there) and it goes back to the open list if that
    /// raises it; otherwise it is checked.
    pub(super) fn edge(
        &mut self,
        round: &mut Round,
        mv: Move,
        bounded: bool,
        f: f64,
        g: f64,
        unmet: usize,
    ) -> Result<(), Error> {
        let mut next = round.nodes[mv.from].key.clone();
        next[mv.joint.index()] = mv.to;
        if round.closed.contains(&next) {
            return Ok(());
        }
        if !bounded {
            let tightened = self.tightened(round, mv, &next)?;
            if tightened > f + 1e-9 {
                round.seq += 1;
                round.open.push(Entry {
                    f: tightened,
                    g,
                    unmet,
                    seq: round.seq,
                    item: Item::Edge {
                        from: mv.from,
                        joint: mv.joint,
                        to: mv.to,
                        bounded: true,
                    },
                });
                return Ok(());
            }
        }
        self.prefetch(round, mv)?;
        self.check_move(round, mv, next, unmet)
    }

    /// The priority of move `mv` (to state `next`) with the bound of
    /// [`Checker::move_bound`]: the action, the heuristic's work after it, and the least cost
    /// of reaching one of its base cells and going on from there.
    fn tightened(&mut self, round: &Round, mv: Move, next: &Key) -> Result<f64, Error> {
        let from = &round.nodes[mv.from];
        let travel = self.heuristic.travel_of(next);
        let b = self.checker.move_bound(
            &mut self.caches,
            &mut self.data,
            &from.key,
            from.robot,
            mv.joint,
            mv.to,
            &|cell| travel.at(cell),
        )?;
        Ok(from.g + self.settings.cost.action + self.heuristic.work(next) + b)
    }

    /// Checks the sweeps of move `mv` and of the next few bounded moves in pop order in
    /// parallel (into the memo).
    fn prefetch(&mut self, round: &Round, mv: Move) -> Result<(), Error> {
        let mut batch = vec![(round.nodes[mv.from].key.clone(), mv.joint, mv.to)];
        for e in round.open.peek(4 * self.threads) {
            if batch.len() >= self.threads {
                break;
            }
            if let Item::Edge {
                from,
                joint,
                to,
                bounded: true,
            } = &e.item
            {
                batch.push((round.nodes[*from].key.clone(), *joint, *to));
            }
        }
        prefetch_sweeps(
            self.model,
            self.checker,
            &mut self.caches,
            &mut self.stats,
            &batch,
        )
    }

    /// Checks move `mv` to state `next` (`unmet` targets after it): a feasible move pushes
    /// its state with the base pose chosen; a failure is recorded with the joints it depends
    /// on, or deferred.
    fn check_move(
        &mut self,
        round: &mut Round,
        mv: Move,
        next: Key,
        unmet: usize,
    ) -> Result<(), Error> {
        let Move { from, joint, to } = mv;
        self.stats.evaluated += 1;
        let key = round.nodes[from].key.clone();
        let verdict = self.checker.evaluate(
            &mut self.caches,
            &mut self.data,
            &key,
            round.nodes[from].robot,
            joint,
            to,
            self.refiner,
        )?;
        match verdict {
            Verdict::Feasible(choice) => {
                let (step, cost) = feasible_step(
                    self.model,
                    self.lattice,
                    self.settings,
                    &key,
                    joint,
                    to,
                    &choice,
                );
                let g = round.nodes[from].g + cost;
                round.seq += 1;
                round.open.push(Entry {
                    f: g + self.h(&next, choice.cell),
                    g,
                    unmet,
                    seq: round.seq,
                    item: Item::Node(Box::new(Node {
                        key: next,
                        robot: choice.cell,
                        g,
                        parent: Some((from, step)),
                    })),
                });
            }
            Verdict::Infeasible { cause, blockers } => {
                match blockers {
                    Blockers::Unknown => round.unknown_blockers = true,
                    Blockers::Deferred => round.deferred.push(round.failures.len()),
                    Blockers::Known(js) => {
                        for j in js {
                            if !self.active[j.index()] {
                                round.new_blockers[j.index()] = true;
                            }
                        }
                    }
                }
                round.failures.push(Recorded {
                    key,
                    joint,
                    to,
                    cause,
                });
            }
        }
        Ok(())
    }
}

/// Runs the sweeps of `batch` that the memo lacks, in parallel.
fn prefetch_sweeps(
    model: &SceneModel,
    checker: &Checker<'_>,
    caches: &mut Caches,
    stats: &mut SearchStats,
    batch: &[(Key, JointId, u16)],
) -> Result<(), Error> {
    let mut todo = Vec::new();
    let mut seen = HashSet::new();
    for (key, joint, to) in batch {
        if model.parts()[joint.index()].handles().is_empty() {
            continue;
        }
        let sk = checker.sweep_key(key, *joint, *to);
        if caches.sweeps.contains_key(&sk) {
            stats.memo_hits += 1;
        } else if seen.insert(sk.clone()) {
            todo.push((sk, key, *joint, *to));
        }
    }
    stats.sweeps += todo.len();
    let results: Vec<Result<SweepVerdict, Error>> = if todo.len() > 1 {
        todo.par_iter()
            .map_init(
                || SceneData::new(model),
                |data, (_, key, joint, to)| checker.sweep(data, key, *joint, *to),
            )
            .collect()
    } else {
        let mut data = SceneData::new(model);
        todo.iter()
            .map(|(_, key, joint, to)| checker.sweep(&mut data, key, *joint, *to))
            .collect()
    };
    for ((sk, ..), r) in todo.into_iter().zip(results) {
        caches.sweeps.insert(sk, r?);
    }
    Ok(())
}
