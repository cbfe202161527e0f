//! The anytime passes and their rounds: a round searches the lattice restricted to the active
//! joints until it finds a plan, is exhausted, gives way to a larger active set or is stopped.

use std::collections::HashSet;

use super::expand::Move;
use super::open::{Entry, Item, Open};
use super::report::{Incumbent, infeasibility};
use super::{Search, close_over_ancestors};
use crate::scene::{JointId, SceneData};
use crate::task::Error;
use crate::task::check::{Caches, Checker, Key};
use crate::task::plan::{Cause, Outcome, PlanResult, Step};

/// Expansions between checks of the deferred failures' blockers ([`Search::grow_early`]).
/// Round `r` (from 1) checks first after `GROW_CHECK · 2^(r−1)` expansions, so that each
/// round may spend at least as much as all earlier ones before it gives way to a larger
/// active set (a round that would end with a plan is not cut short too early).
const GROW_CHECK: usize = 32;

/// A closed (expanded) state.
pub(super) struct Node {
    pub(super) key: Key,
    pub(super) robot: usize,
    pub(super) g: f64,
    pub(super) parent: Option<(usize, Step)>,
}

/// A recorded failure with the state it happened in.
pub(super) struct Recorded {
    pub(super) key: Key,
    pub(super) joint: JointId,
    pub(super) to: u16,
    pub(super) cause: Cause,
}

/// One round's search state: its closed nodes, its open items and the failures it recorded.
pub(super) struct Round {
    pub(super) nodes: Vec<Node>,
    pub(super) closed: HashSet<Key>,
    pub(super) open: Open,
    /// The sequence number of the last item pushed.
    pub(super) seq: u64,
    pub(super) failures: Vec<Recorded>,
    /// Inactive joints the failures depend on.
    pub(super) new_blockers: Vec<bool>,
    /// Whether a failure depends on joints it cannot name.
    pub(super) unknown_blockers: bool,
    /// Failures whose blockers are computed only if this round is exhausted.
    pub(super) deferred: Vec<usize>,
    /// Deferred failures whose blockers have been computed.
    processed: usize,
    /// Expansions this round.
    expanded: usize,
    /// Whether this round pushes only the reduced moves (the partial-order reduction; see
    /// [`Search::reduces`]).
    pub(super) reduced: bool,
    /// Whether the reduction has pruned a move in this round (until then the round is the
    /// unreduced one).
    pub(super) pruned: bool,
}

/// What follows an item of a round.
pub(super) enum Flow {
    /// The round goes on.
    Continue,
    /// The round gives way to a larger active set.
    GiveWay,
    /// The final pass starts below the incumbent the round found.
    NextPass,
    /// The search ends with this result.
    Done(Box<PlanResult>),
}

/// The steps from the start to node `idx`.
pub(super) fn path_to(nodes: &[Node], idx: usize) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut at = idx;
    while let Some((parent, step)) = &nodes[at].parent {
        steps.push(step.clone());
        at = *parent;
    }
    steps.reverse();
    steps
}

impl Search<'_> {
    /// The anytime passes: the first with `first_pass_weight`, then (if its plan is not yet
    /// proven within `heuristic_weight`) one with `heuristic_weight` below the incumbent; each
    /// pass runs rounds over a growing active set until one ends the search.
    pub(super) fn passes(&mut self) -> Result<PlanResult, Error> {
        loop {
            if let Some(result) = self.round()? {
                return Ok(result);
            }
        }
    }

    /// One round; `None` when another round follows (a larger active set or the next pass).
    fn round(&mut self) -> Result<Option<PlanResult>, Error> {
        self.stats.rounds += 1;
        self.stats.active_joints = self.active.iter().filter(|a| **a).count();
        let mut round = self.new_round()?;
        while let Some(entry) = round.open.pop() {
            match self.popped(&mut round, entry)? {
                Flow::Continue => {}
                Flow::GiveWay => break,
                Flow::NextPass => return Ok(None),
                Flow::Done(result) => return Ok(Some(*result)),
            }
        }
        // Exhausted the lattice restricted to the active joints (or leaving early to grow).
        self.end_round(round)
    }

    /// A round with only the start state open, below the incumbent's cost (reduced or not,
    /// see [`Search::reduces`]).
    fn new_round(&mut self) -> Result<Round, Error> {
        let reduced = self.reduces()?;
        let cap = self.incumbent.as_ref().map_or(f64::INFINITY, |i| i.cost);
        let mut open = Open::new(self.w, cap);
        let seq = 0u64;
        open.push(Entry {
            f: self.h(&self.start_key, self.checker.start_cell),
            g: 0.0,
            unmet: self.heuristic.unmet(&self.start_key),
            seq,
            item: Item::Node(Box::new(Node {
                key: self.start_key.clone(),
                robot: self.checker.start_cell,
                g: 0.0,
                parent: None,
            })),
        });
        Ok(Round {
            nodes: Vec::new(),
            closed: HashSet::new(),
            open,
            seq,
            failures: Vec::new(),
            new_blockers: vec![false; self.model.nq()],
            unknown_blockers: false,
            deferred: Vec::new(),
            processed: 0,
            expanded: 0,
            reduced,
            pruned: false,
        })
    }

    /// A popped item: the early growth check (before a state), the stop check, then the
    /// state's expansion or the move's check.
    fn popped(&mut self, round: &mut Round, entry: Entry) -> Result<Flow, Error> {
        if matches!(entry.item, Item::Node(_)) && self.grow_early(round)? {
            return Ok(Flow::GiveWay);
        }
        if self.termination.should_stop() {
            let least = round.open.least_f().min(entry.f);
            return Ok(Flow::Done(Box::new(self.stop(least))));
        }
        let Entry {
            f, g, unmet, item, ..
        } = entry;
        match item {
            Item::Node(node) => self.expand(round, *node, f),
            Item::Edge {
                from,
                joint,
                to,
                bounded,
            } => {
                let mv = Move { from, joint, to };
                self.edge(round, mv, bounded, f, g, unmet)?;
                Ok(Flow::Continue)
            }
        }
    }

    /// Grow early: every `GROW_CHECK` expansions (from the round's first check on), computes
    /// the blockers of the failures deferred so far; if any names a joint outside the active
    /// set, the round cannot end Infeasible, so it gives way to the next one now instead of
    /// being exhausted. Counts the expansion; whether the round gives way.
    fn grow_early(&mut self, round: &mut Round) -> Result<bool, Error> {
        round.expanded += 1;
        let first_check = GROW_CHECK << (self.stats.rounds - 1).min(20);
        if round.expanded < first_check || round.expanded % GROW_CHECK != 0 {
            return Ok(false);
        }
        while round.processed < round.deferred.len() && !self.termination.should_stop() {
            mark_blockers(
                self.checker,
                &mut self.caches,
                &mut self.data,
                &round.failures[round.deferred[round.processed]],
                &self.active,
                &mut round.new_blockers,
            )?;
            round.processed += 1;
        }
        let all_active = self.active.iter().all(|a| *a);
        Ok(round.new_blockers.iter().any(|b| *b) || (round.unknown_blockers && !all_active))
    }

    /// The end of a round that was exhausted or gave way: the blockers of the failures still
    /// deferred, then a larger active set if they name new joints; otherwise the pass is over.
    fn end_round(&mut self, mut round: Round) -> Result<Option<PlanResult>, Error> {
        for &k in &round.deferred[round.processed..] {
            mark_blockers(
                self.checker,
                &mut self.caches,
                &mut self.data,
                &round.failures[k],
                &self.active,
                &mut round.new_blockers,
            )?;
            if self.termination.should_stop() {
                // Items are left open when the round gave way early to grow the active set;
                // when it was exhausted there are none below the cap.
                let least = round.open.least_f();
                return Ok(Some(self.stop(least)));
            }
        }
        if self.grow_active(&round) {
            return Ok(None);
        }
        self.pass_exhausted(round)
    }

    /// Adds the joints the round's failures depend on to the active set (all joints when a
    /// failure depends on joints it cannot name); whether the set grew.
    fn grow_active(&mut self, round: &Round) -> bool {
        let all_active = self.active.iter().all(|a| *a);
        if round.unknown_blockers && !all_active {
            self.active.iter_mut().for_each(|a| *a = true);
            true
        } else {
            let mut grew = false;
            for (j, b) in round.new_blockers.iter().enumerate() {
                if *b && !self.active[j] {
                    close_over_ancestors(self.model, JointId(j), &mut self.active);
                    grew = true;
                }
            }
            grew
        }
    }

    /// A pass that exhausted the lattice restricted to the active joints, whose failures name
    /// no new joint: the incumbent (or the final pass below it), or the infeasibility report.
    fn pass_exhausted(&mut self, round: Round) -> Result<Option<PlanResult>, Error> {
        self.finish();
        if let Some(inc) = self.incumbent.take() {
            if self.w > self.final_w {
                // A pass above the final weight closes states on first arrival in focal
                // order, so its exhausting below the cap (the dive's incumbent) proves the
                // incumbent within `w` only: run the final pass below it.
                self.incumbent = Some(Incumbent {
                    factor: inc.factor.min(self.w),
                    ..inc
                });
                self.start_final_pass();
                return Ok(None);
            }
            // No plan below the incumbent's cost over the active joints: with `w = 1` it
            // is minimal.
            let factor = inc.factor.min(self.w);
            return Ok(Some(inc.solved(factor, std::mem::take(&mut self.stats))));
        }
        let why = infeasibility(
            self.model,
            self.problem,
            self.checker,
            &mut self.caches,
            &mut self.data,
            &round.nodes,
            &round.failures,
        )?;
        Ok(Some(PlanResult {
            outcome: Outcome::Infeasible(why),
            stats: std::mem::take(&mut self.stats),
        }))
    }

    /// Starts the final pass (focal weight `heuristic_weight`, below the incumbent) with the
    /// current active set: not a new round of it.
    pub(super) fn start_final_pass(&mut self) {
        self.w = self.final_w;
        self.stats.passes = 2;
        self.stats.rounds -= 1;
    }
}

/// Marks the inactive joints a deferred (base-pose) failure depends on.
fn mark_blockers(
    checker: &Checker<'_>,
    caches: &mut Caches,
    data: &mut SceneData,
    f: &Recorded,
    active: &[bool],
    new_blockers: &mut [bool],
) -> Result<(), Error> {
    for j in checker.path_failure_blockers(caches, data, &f.key, f.joint, f.to, active)? {
        if !active[j.index()] {
            new_blockers[j.index()] = true;
        }
    }
    Ok(())
}
