//! The complete lattice search: lazy best-first search over lattice states with a closed set,
//! in focal order ([`Open`]; A* with `heuristic_weight = 1`), grown over an active joint set.
//!
//! Its model, with the move re-queue and the rounds that stop early to grow the active set, is
//! `search_run` in `proofs/theories/Task/Requeue.v` (soundness, completeness over all joints,
//! termination; a re-queued key stays a lower bound: `RequeueKey.v`). The model pops any open
//! item, so the focal order is covered; the sweep prefetch only reads the next open items.

use std::cmp::Ordering;
use std::collections::{BTreeSet, HashMap, HashSet};
use std::time::Instant;

use rayon::prelude::*;

use super::check::{Blockers, Caches, Checker, Choice, Key, SweepVerdict, Verdict};
use super::conflict::static_conflict;
use super::goal::Problem;
use super::greedy;
use super::heuristic::Heuristic;
use super::lattice::Lattice;
use super::plan::{
    Cause, Failure, Infeasibility, Outcome, Partial, Plan, PlanResult, SearchStats, Step,
};
use super::refine::Refiner;
use super::settings::TaskSettings;
use super::{Error, Termination};
use crate::scene::collision::collisions;
use crate::scene::{JointId, SceneData, SceneModel, forward_kinematics};

/// Expansions between checks of the deferred failures' blockers (see the round loop). Round
/// `r` (from 1) checks first after `GROW_CHECK · 2^(r−1)` expansions, so that each round
/// may spend at least as much as all earlier ones before it gives way to a larger active
/// set (a round that would end with a plan is not cut short too early).
const GROW_CHECK: usize = 32;

/// A closed (expanded) state.
struct Node {
    key: Key,
    robot: usize,
    g: f64,
    parent: Option<(usize, Step)>,
}

/// What a heap item carries.
enum Item {
    /// A move out of closed node `from`, not yet checked. `bounded`: its priority already
    /// includes the bound of [`Checker::move_bound`].
    Edge {
        from: usize,
        joint: JointId,
        to: u16,
        bounded: bool,
    },
    /// A checked move's target state, to be closed.
    Node(Box<Node>),
}

struct Entry {
    /// Lower bound on the cost of a plan through this item (`g + h`).
    f: f64,
    g: f64,
    /// Goal targets still unmet after this item (the focal order's first key).
    unmet: usize,
    seq: u64,
    item: Item,
}

/// An `f64` ordered by [`f64::total_cmp`].
#[derive(Debug, Clone, Copy)]
struct Ordered(f64);

impl PartialEq for Ordered {
    fn eq(&self, o: &Self) -> bool {
        self.0.total_cmp(&o.0) == Ordering::Equal
    }
}
impl Eq for Ordered {}
impl PartialOrd for Ordered {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Ordered {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// The open list of a focal search (A*ε, Pearl and Kim 1982): the items whose `f` is within
/// the factor `weight` of the least open `f` form the *focal* set, and the search pops the
/// focal item with the fewest unmet goal targets (then lowest `f`, deepest, oldest). With
/// `weight = 1` the focal set holds only the items of least `f`: A* with ties broken by
/// progress.
struct Open {
    weight: f64,
    /// Items with `f` at or above this are dropped (the anytime pass's incumbent cost).
    cap: f64,
    items: HashMap<u64, Entry>,
    by_f: BTreeSet<(Ordered, u64)>,
    /// Focal order: unmet targets, f, −g, seq.
    focal: BTreeSet<(usize, Ordered, Ordered, u64)>,
    /// `weight · (least open f)`: the focal set is every item with `f <= bound`.
    bound: f64,
}

impl Open {
    fn new(weight: f64, cap: f64) -> Self {
        Open {
            weight,
            cap,
            items: HashMap::new(),
            by_f: BTreeSet::new(),
            focal: BTreeSet::new(),
            bound: f64::NEG_INFINITY,
        }
    }

    fn focal_key(e: &Entry) -> (usize, Ordered, Ordered, u64) {
        (e.unmet, Ordered(e.f), Ordered(-e.g), e.seq)
    }

    /// The focal bound for least open `f` `f_min` (a small absolute slack keeps items of
    /// equal `f` up to rounding together).
    fn bound_for(&self, f_min: f64) -> f64 {
        self.weight * f_min + 1e-9
    }

    /// Moves items into or out of the focal set after the least open `f` changed.
    fn rebound(&mut self) {
        let new = match self.by_f.first() {
            Some((f, _)) => self.bound_for(f.0),
            None => f64::NEG_INFINITY,
        };
        let old = self.bound;
        if new > old {
            let range = (
                std::ops::Bound::Excluded((Ordered(old), u64::MAX)),
                std::ops::Bound::Included((Ordered(new), u64::MAX)),
            );
            for (_, seq) in self.by_f.range(range) {
                let e = &self.items[seq];
                self.focal.insert(Self::focal_key(e));
            }
        } else if new < old {
            let range = (
                std::ops::Bound::Excluded((Ordered(new), u64::MAX)),
                std::ops::Bound::Included((Ordered(old), u64::MAX)),
            );
            for (_, seq) in self.by_f.range(range) {
                let e = &self.items[seq];
                self.focal.remove(&Self::focal_key(e));
            }
        }
        self.bound = new;
    }

    fn push(&mut self, e: Entry) {
        // No plan through it can beat the incumbent.
        if e.f >= self.cap - 1e-9 {
            return;
        }
        let seq = e.seq;
        self.by_f.insert((Ordered(e.f), seq));
        if e.f <= self.bound {
            self.focal.insert(Self::focal_key(&e));
        }
        self.items.insert(seq, e);
        // A new least `f` lowers the bound (or sets the first one).
        if self.by_f.first().is_some_and(|(_, s)| *s == seq) {
            self.rebound();
        }
    }

    fn pop(&mut self) -> Option<Entry> {
        let key = *self.focal.first()?;
        self.focal.remove(&key);
        let e = self
            .items
            .remove(&key.3)
            .expect("a focal item is an open item");
        self.by_f.remove(&(Ordered(e.f), e.seq));
        self.rebound();
        Some(e)
    }

    /// The least open `f` (`+∞` when empty).
    fn least_f(&self) -> f64 {
        self.by_f.first().map_or(f64::INFINITY, |(f, _)| f.0)
    }

    /// The next `n` items in pop order (without popping them).
    fn peek(&self, n: usize) -> impl Iterator<Item = &Entry> {
        self.focal.iter().take(n).map(|k| &self.items[&k.3])
    }
}

/// A recorded failure with the state it happened in.
struct Recorded {
    key: Key,
    joint: JointId,
    to: u16,
    cause: Cause,
}

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
    let start_key: Key = (0..model.nq())
        .map(|k| {
            lattice
                .index_of(JointId(k), problem.start.as_slice()[k])
                .expect("the start value is in the lattice") as u16
        })
        .collect();
    let mut caches = Caches::for_search();
    let mut data = SceneData::new(model);
    let heuristic = Heuristic::new(model, problem, settings, &lattice, &checker, &mut data)?;
    let mut stats = SearchStats::default();
    // Static proofs of infeasibility (sound for the whole lattice, see `conflict.rs` and
    // `heuristic.rs`): a goal joint no move can bring into its target, or two goal parts
    // that collide in every goal state.
    if !problem.goal.is_satisfied(&problem.start) {
        let unreachable = heuristic.unreachable_targets();
        let why = if let Some(&k) = unreachable.first() {
            let (joint, target) = problem.goal.targets()[k];
            let name = model.joints()[joint.index()].name.clone();
            let from = problem.start.as_slice()[joint.index()];
            let arm = settings.manipulation.arm.as_ref();
            let reach = match (heuristic.least_arm_span(k), arm) {
                (Some(span), Some(arm)) if span > arm.radius => format!(
                    ": from every free base cell within reach of its handle, holding it needs \
                     the arm to span at least {span:.3} m from the shoulder to the wrist, and it \
                     spans at most {:.3} m",
                    arm.radius
                ),
                _ => String::new(),
            };
            Some(Infeasibility {
                message: format!(
                    "no plan in the lattice: no base pose can operate {name} into its target{reach}"
                ),
                unreached: vec![name.clone()],
                conflicts: vec![Failure {
                    joint: name,
                    from,
                    to: target.nearest(from),
                    cause: Cause::NoBasePose,
                }],
                start_collisions: Vec::new(),
            })
        } else {
            static_conflict(model, problem, &checker, &lattice, termination)?
        };
        if let Some(why) = why {
            stats.elapsed = started.elapsed();
            return Ok(PlanResult {
                outcome: Outcome::Infeasible(why),
                stats,
            });
        }
    }
    // The anytime passes: the first with `first_pass_weight`, then (if its plan is not yet
    // proven within `heuristic_weight`) one with `heuristic_weight` below the incumbent.
    let final_w = settings.heuristic_weight;
    // Without base travel the heuristic is close to the cost and one pass of `final_w` is
    // usually faster (see `TaskSettings::first_pass_weight`).
    let mut w = if settings.cost.travel > 0.0 {
        settings.first_pass_weight.max(final_w)
    } else {
        final_w
    };
    let mut incumbent: Option<Incumbent> = None;
    stats.passes = 1;
    // The lower bound on the cost still to pay from a state with the robot at `cell`.
    let h = |key: &[u16], cell: usize| heuristic.work(key) + heuristic.travel_of(key).at(cell);
    // The greedy dive's plan, if it finds one, is the first incumbent: returned at once when
    // it is already proven within the final weight of the start's lower bound.
    if settings.dive && !problem.goal.is_satisfied(&problem.start) {
        let cx = greedy::Context {
            model,
            problem,
            settings,
            lattice: &lattice,
            checker: &checker,
            refiner,
        };
        if let Some(d) = greedy::dive(
            &cx,
            &mut caches,
            &mut data,
            &start_key,
            &mut stats,
            termination,
        )? {
            stats.first_plan = Some(started.elapsed());
            stats.greedy_first_plan = true;
            let least = h(&start_key, checker.start_cell);
            let factor = if d.cost <= least { 1.0 } else { d.cost / least };
            let inc = Incumbent {
                steps: d.steps,
                cost: d.cost,
                factor,
            };
            if factor <= final_w + 1e-9 {
                stats.elapsed = started.elapsed();
                stats.vetoes = caches.vetoes;
                return Ok(inc.solved(factor, stats));
            }
            incumbent = Some(inc);
        }
    }
    let mut active = vec![false; model.nq()];
    for (j, _) in problem.goal.targets() {
        close_over_ancestors(model, *j, &mut active);
    }
    let threads = match settings.parallelism {
        0 => rayon::current_num_threads(),
        n => n,
    }
    .max(1);
    // The closed state nearest the goal so far: (unmet targets, heuristic, steps to it).
    let mut best_partial: Option<Best> = None;
    'passes: loop {
        stats.rounds += 1;
        stats.active_joints = active.iter().filter(|a| **a).count();
        let mut nodes: Vec<Node> = Vec::new();
        let mut closed: HashSet<Key> = HashSet::new();
        let cap = incumbent.as_ref().map_or(f64::INFINITY, |i| i.cost);
        let mut heap = Open::new(w, cap);
        let mut seq = 0u64;
        let mut failures: Vec<Recorded> = Vec::new();
        let mut new_blockers = vec![false; model.nq()];
        let mut unknown_blockers = false;
        // Failures whose blockers are computed only if this round is exhausted.
        let mut deferred: Vec<usize> = Vec::new();
        heap.push(Entry {
            f: h(&start_key, checker.start_cell),
            g: 0.0,
            unmet: heuristic.unmet(&start_key),
            seq,
            item: Item::Node(Box::new(Node {
                key: start_key.clone(),
                robot: checker.start_cell,
                g: 0.0,
                parent: None,
            })),
        });
        // Deferred failures whose blockers have been computed, and expansions this round.
        let mut processed = 0;
        let mut round_expanded = 0usize;
        while let Some(entry) = heap.pop() {
            // Grow early: every GROW_CHECK expansions (from the round's first check on),
            // compute the blockers of the failures deferred so far; if any names a joint
            // outside the active set, the round cannot end Infeasible, so start the next one
            // now instead of exhausting this one.
            if matches!(entry.item, Item::Node(_)) {
                round_expanded += 1;
                let first_check = GROW_CHECK << (stats.rounds - 1).min(20);
                if round_expanded >= first_check && round_expanded % GROW_CHECK == 0 {
                    while processed < deferred.len() && !termination.should_stop() {
                        mark_blockers(
                            &checker,
                            &mut caches,
                            &mut data,
                            &failures[deferred[processed]],
                            &active,
                            &mut new_blockers,
                        )?;
                        processed += 1;
                    }
                    let all_active = active.iter().all(|a| *a);
                    if new_blockers.iter().any(|b| *b) || (unknown_blockers && !all_active) {
                        break;
                    }
                }
            }
            if termination.should_stop() {
                stats.elapsed = started.elapsed();
                stats.vetoes = caches.vetoes;
                let least = heap.least_f().min(entry.f);
                return Ok(stopped(
                    model,
                    problem,
                    incumbent,
                    best_partial,
                    least,
                    stats,
                ));
            }
            match entry.item {
                Item::Node(node) => {
                    if !closed.insert(node.key.clone()) {
                        continue;
                    }
                    stats.expanded += 1;
                    let idx = nodes.len();
                    let g = node.g;
                    let key = node.key.clone();
                    nodes.push(*node);
                    let state = checker.state_of(&key);
                    let unmet = problem
                        .goal
                        .targets()
                        .iter()
                        .filter(|(j, i)| !i.contains(state.q[j.index()]))
                        .count();
                    let hk = h(&key, nodes[idx].robot);
                    if best_partial
                        .as_ref()
                        .is_none_or(|(u, bh, _)| (unmet, hk) < (*u, *bh))
                    {
                        best_partial = Some((unmet, hk, path_to(&nodes, idx)));
                    }
                    if unmet == 0 {
                        // Proven factor: its cost over the least lower bound still open
                        // (the popped item's own `f` included).
                        let least = heap.least_f().min(entry.f);
                        let factor = if g <= least { 1.0 } else { g / least };
                        let steps = path_to(&nodes, idx);
                        stats.first_plan.get_or_insert(started.elapsed());
                        if factor <= final_w + 1e-9 || w <= final_w {
                            // Within the final weight, or a final-pass plan (cheaper than any
                            // incumbent by the cap, and within `final_w` by the focal rule).
                            stats.elapsed = started.elapsed();
                            stats.vetoes = caches.vetoes;
                            stats.suboptimality = Some(factor.min(w));
                            return Ok(PlanResult {
                                outcome: Outcome::Solved(Plan { steps, cost: g }),
                                stats,
                            });
                        }
                        incumbent = Some(Incumbent {
                            steps,
                            cost: g,
                            factor: factor.min(w),
                        });
                        w = final_w;
                        stats.passes = 2;
                        // The second pass goes on with this round's active set: not a new
                        // round of it.
                        stats.rounds -= 1;
                        continue 'passes;
                    }
                    let robot = checker.cell_xy(nodes[idx].robot);
                    let approach = heuristic.approach(model, &mut data, &state, &active, robot)?;
                    for (j, is_active) in active.iter().enumerate() {
                        if !is_active {
                            continue;
                        }
                        let joint = JointId(j);
                        for to in 0..lattice.values(joint).len() as u16 {
                            if to == key[j] {
                                continue;
                            }
                            let mut next = key.clone();
                            next[j] = to;
                            if closed.contains(&next) {
                                continue;
                            }
                            // The move's cost without travel, the rest of the plan's, and
                            // the travel to the move's base pose or on from there.
                            let lb = heuristic.move_work(joint, key[j], to);
                            let travel = heuristic
                                .travel_of(&next)
                                .at(nodes[idx].robot)
                                .max(approach[j]);
                            seq += 1;
                            heap.push(Entry {
                                f: g + lb + heuristic.work(&next) + travel,
                                g: g + lb,
                                unmet: heuristic.unmet(&next),
                                seq,
                                item: Item::Edge {
                                    from: idx,
                                    joint,
                                    to,
                                    // Without travel the region bound adds nothing.
                                    bounded: settings.cost.travel == 0.0,
                                },
                            });
                        }
                    }
                }
                Item::Edge {
                    from,
                    joint,
                    to,
                    bounded,
                } => {
                    let mut next = nodes[from].key.clone();
                    next[joint.index()] = to;
                    if closed.contains(&next) {
                        continue;
                    }
                    if !bounded {
                        // Tighten the priority with the move's region (travel to its base
                        // cells and on from there); check it later if that raises it.
                        let travel = heuristic.travel_of(&next);
                        let b = checker.move_bound(
                            &mut caches,
                            &mut data,
                            &nodes[from].key,
                            nodes[from].robot,
                            joint,
                            to,
                            &|cell| travel.at(cell),
                        )?;
                        let f = nodes[from].g + settings.cost.action + heuristic.work(&next) + b;
                        let item = Item::Edge {
                            from,
                            joint,
                            to,
                            bounded: true,
                        };
                        if f > entry.f + 1e-9 {
                            seq += 1;
                            heap.push(Entry {
                                f,
                                g: entry.g,
                                unmet: entry.unmet,
                                seq,
                                item,
                            });
                            continue;
                        }
                    }
                    // Check the sweeps of this and the next few pending moves in parallel.
                    let mut batch = vec![(nodes[from].key.clone(), joint, to)];
                    for e in heap.peek(4 * threads) {
                        if batch.len() >= threads {
                            break;
                        }
                        if let Item::Edge {
                            from,
                            joint,
                            to,
                            bounded: true,
                        } = &e.item
                        {
                            batch.push((nodes[*from].key.clone(), *joint, *to));
                        }
                    }
                    prefetch_sweeps(model, &checker, &mut caches, &mut stats, &batch)?;
                    stats.evaluated += 1;
                    let key = nodes[from].key.clone();
                    let verdict = checker.evaluate(
                        &mut caches,
                        &mut data,
                        &key,
                        nodes[from].robot,
                        joint,
                        to,
                        refiner,
                    )?;
                    match verdict {
                        Verdict::Feasible(choice) => {
                            let (step, cost) =
                                feasible_step(model, &lattice, settings, &key, joint, to, &choice);
                            let g = nodes[from].g + cost;
                            seq += 1;
                            heap.push(Entry {
                                f: g + h(&next, choice.cell),
                                g,
                                unmet: entry.unmet,
                                seq,
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
                                Blockers::Unknown => unknown_blockers = true,
                                Blockers::Deferred => deferred.push(failures.len()),
                                Blockers::Known(js) => {
                                    for j in js {
                                        if !active[j.index()] {
                                            new_blockers[j.index()] = true;
                                        }
                                    }
                                }
                            }
                            failures.push(Recorded {
                                key,
                                joint,
                                to,
                                cause,
                            });
                        }
                    }
                }
            }
        }
        // Exhausted the lattice restricted to the active joints (or leaving early to grow).
        for &k in &deferred[processed..] {
            mark_blockers(
                &checker,
                &mut caches,
                &mut data,
                &failures[k],
                &active,
                &mut new_blockers,
            )?;
            if termination.should_stop() {
                stats.elapsed = started.elapsed();
                stats.vetoes = caches.vetoes;
                // Items are left open when the round gave way early to grow the active set;
                // when it was exhausted there are none below the cap.
                return Ok(stopped(
                    model,
                    problem,
                    incumbent,
                    best_partial,
                    heap.least_f(),
                    stats,
                ));
            }
        }
        let all_active = active.iter().all(|a| *a);
        let grow = if unknown_blockers && !all_active {
            active.iter_mut().for_each(|a| *a = true);
            true
        } else {
            let mut grew = false;
            for (j, b) in new_blockers.iter().enumerate() {
                if *b && !active[j] {
                    close_over_ancestors(model, JointId(j), &mut active);
                    grew = true;
                }
            }
            grew
        };
        if !grow {
            stats.elapsed = started.elapsed();
            stats.vetoes = caches.vetoes;
            if let Some(inc) = incumbent.take() {
                if w > final_w {
                    // A pass above the final weight closes states on first arrival in focal
                    // order, so its exhausting below the cap (the dive's incumbent) proves the
                    // incumbent within `w` only: run the final pass below it.
                    incumbent = Some(Incumbent {
                        factor: inc.factor.min(w),
                        ..inc
                    });
                    w = final_w;
                    stats.passes = 2;
                    stats.rounds -= 1;
                    continue 'passes;
                }
                // No plan below the incumbent's cost over the active joints: with `w = 1` it
                // is minimal.
                let factor = inc.factor.min(w);
                return Ok(inc.solved(factor, stats));
            }
            let why = infeasibility(
                model,
                problem,
                &checker,
                &mut caches,
                &mut data,
                &nodes,
                &failures,
            )?;
            return Ok(PlanResult {
                outcome: Outcome::Infeasible(why),
                stats,
            });
        }
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

/// The anytime search's best plan so far.
struct Incumbent {
    steps: Vec<Step>,
    cost: f64,
    /// The factor it is proven within.
    factor: f64,
}

impl Incumbent {
    /// The incumbent as the search's result, proven within `factor`.
    fn solved(self, factor: f64, mut stats: SearchStats) -> PlanResult {
        stats.suboptimality = Some(factor);
        PlanResult {
            outcome: Outcome::Solved(Plan {
                steps: self.steps,
                cost: self.cost,
            }),
            stats,
        }
    }
}

/// The result when the budget or the cancel flag stops the search: the incumbent, proven
/// within the smaller of its factor and its cost over `least` (the least open lower bound,
/// `+∞` if none is known), or else the partial plan.
fn stopped(
    model: &SceneModel,
    problem: &Problem,
    incumbent: Option<Incumbent>,
    best_partial: Option<Best>,
    least: f64,
    stats: SearchStats,
) -> PlanResult {
    match incumbent {
        Some(inc) => {
            let factor = if inc.cost <= least {
                1.0
            } else {
                inc.factor.min(inc.cost / least)
            };
            inc.solved(factor, stats)
        }
        None => PlanResult {
            outcome: Outcome::Timeout(partial_plan(model, problem, best_partial)),
            stats,
        },
    }
}

/// The closed state nearest the goal: (unmet targets, heuristic, steps to it).
type Best = (usize, f64, Vec<Step>);

/// The steps from the start to node `idx`.
fn path_to(nodes: &[Node], idx: usize) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut at = idx;
    while let Some((parent, step)) = &nodes[at].parent {
        steps.push(step.clone());
        at = *parent;
    }
    steps.reverse();
    steps
}

fn partial_plan(model: &SceneModel, problem: &Problem, best: Option<Best>) -> Partial {
    let steps = best.map(|(_, _, s)| s).unwrap_or_default();
    let mut state = problem.start.clone();
    for s in &steps {
        if let Ok(j) = model.joint_id(&s.joint) {
            state.q[j.index()] = s.to;
        }
    }
    Partial {
        plan: Plan {
            cost: steps.iter().map(|s| s.cost).sum(),
            steps,
        },
        unmet: problem
            .goal
            .targets()
            .iter()
            .filter(|(j, i)| !i.contains(state.q[j.index()]))
            .map(|(j, _)| model.joints()[j.index()].name.clone())
            .collect(),
    }
}

/// Builds the report of an exhausted search.
fn infeasibility(
    model: &SceneModel,
    problem: &Problem,
    checker: &Checker<'_>,
    caches: &mut Caches,
    data: &mut SceneData,
    nodes: &[Node],
    failures: &[Recorded],
) -> Result<Infeasibility, Error> {
    let lattice = checker.lattice;
    let targets = problem.goal.targets();
    let mut reached = vec![false; targets.len()];
    for n in nodes {
        let s = checker.state_of(&n.key);
        for (k, (j, i)) in targets.iter().enumerate() {
            reached[k] |= i.contains(s.q[j.index()]);
        }
    }
    let unreached: Vec<JointId> = targets
        .iter()
        .zip(&reached)
        .filter(|(_, r)| !**r)
        .map(|((j, _), _)| *j)
        .collect();
    // Failed moves of unreached goal joints into their targets, grouped by cause.
    let mut groups: HashMap<(usize, String), (usize, &Recorded)> = HashMap::new();
    for f in failures {
        let Some(i) = problem.goal.target(f.joint) else {
            continue;
        };
        // Each target reachable alone but not all together: report the failed moves of every
        // goal joint into its target (e.g. two doors that collide when both open).
        let relevant = unreached.is_empty() || unreached.contains(&f.joint);
        if !relevant || !i.contains(lattice.values(f.joint)[f.to as usize]) {
            continue;
        }
        let sig = match &f.cause {
            Cause::Collision { other, .. } | Cause::Inconclusive { other, .. } => {
                format!("collision {other}")
            }
            c => format!("{c:?}")
                .split([' ', '{'])
                .next()
                .unwrap_or("")
                .to_string(),
        };
        groups
            .entry((f.joint.index(), sig))
            .and_modify(|(n, _)| *n += 1)
            .or_insert((1, f));
    }
    let mut grouped: Vec<(usize, &Recorded)> = groups.into_values().collect();
    grouped.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.joint.cmp(&b.1.joint)));
    let mut conflicts = Vec::new();
    for (_, f) in grouped.into_iter().take(32) {
        let mut cause = f.cause.clone();
        if let Cause::PathBlocked { blockers } = &mut cause {
            *blockers = checker.path_blockers(caches, data, &f.key, f.joint, f.to)?;
        }
        conflicts.push(Failure {
            joint: model.joints()[f.joint.index()].name.clone(),
            from: lattice.values(f.joint)[f.key[f.joint.index()] as usize],
            to: lattice.values(f.joint)[f.to as usize],
            cause,
        });
    }
    forward_kinematics(model, data, &problem.start)?;
    let start_collisions = collisions(model, data, &checker.settings.sweep.collision)?
        .into_iter()
        .map(|c| (checker.body_name(c.a), checker.body_name(c.b)))
        .collect();
    let names: Vec<String> = unreached
        .iter()
        .map(|j| model.joints()[j.index()].name.clone())
        .collect();
    let message = if names.is_empty() {
        match conflicts.first() {
            Some(first) => {
                format!("no plan in the lattice reaches all targets together; e.g. {first}")
            }
            None => "no plan in the lattice reaches all targets together".to_string(),
        }
    } else if let Some(first) = conflicts.first() {
        format!(
            "no plan in the lattice: cannot reach the target of {}; e.g. {first}",
            names.join(", ")
        )
    } else {
        format!(
            "no plan in the lattice: cannot reach the target of {}",
            names.join(", ")
        )
    };
    Ok(Infeasibility {
        message,
        unreached: names,
        conflicts,
        start_collisions,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(f: f64, g: f64, unmet: usize, seq: u64) -> Entry {
        Entry {
            f,
            g,
            unmet,
            seq,
            item: Item::Edge {
                from: 0,
                joint: JointId(0),
                to: 0,
                bounded: false,
            },
        }
    }

    /// The focal open list pops exactly what its definition says, against a brute-force
    /// scan of the open items: among those with `f <= w · (least f) + 1e-9`, the least by
    /// (unmet, f, −g, seq) (with `w = 1`: the least `f`, as A*).
    #[test]
    fn focal_open_list_matches_its_definition() {
        for weight in [1.0, 1.5, 2.0] {
            let mut open = Open::new(weight, f64::INFINITY);
            let mut shadow: Vec<(f64, f64, usize, u64)> = Vec::new();
            let mut state = 0x9e37_79b9_7f4a_7c15u64;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state
            };
            for seq in 0..3000u64 {
                if next() % 3 != 0 {
                    let f = (next() % 1000) as f64 / 10.0;
                    let g = (next() % 100) as f64 / 10.0;
                    let unmet = (next() % 6) as usize;
                    open.push(entry(f, g, unmet, seq));
                    shadow.push((f, g, unmet, seq));
                    continue;
                }
                let popped = open.pop();
                let least = shadow.iter().map(|e| e.0).fold(f64::INFINITY, f64::min);
                let expected = shadow
                    .iter()
                    .filter(|e| e.0 <= weight * least + 1e-9)
                    .min_by(|a, b| {
                        a.2.cmp(&b.2)
                            .then(a.0.total_cmp(&b.0))
                            .then((-a.1).total_cmp(&-b.1))
                            .then(a.3.cmp(&b.3))
                    })
                    .copied();
                match (popped, expected) {
                    (None, None) => {}
                    (Some(p), Some(e)) => {
                        assert_eq!(p.seq, e.3, "weight {weight}: popped {} expected {e:?}", p.f);
                        shadow.retain(|s| s.3 != e.3);
                    }
                    (p, e) => panic!("popped {:?}, expected {e:?}", p.map(|p| p.seq)),
                }
                let peeked: Vec<u64> = open.peek(3).map(|e| e.seq).collect();
                assert!(peeked.len() <= 3);
            }
        }
    }
}
