//! The task layer on generated kitchens (tests/task/generators.rs, fixed seeds): the lattice
//! search against the paper's sampler and against brute force, on the same instances in the
//! same run.
//!
//! # Instances
//! Cells: 10 / 50 / 100-part kitchens × 3 / 6 / 10 / 20 goal joints (cells with more goal
//! joints than the scene has joints are skipped), [`INSTANCES`] instances per cell
//! ([`QUICK_INSTANCES`] with `KINSCENE_BENCH_QUICK=1`), in two families:
//!
//! - **random**: `generators::instance(parts..=parts, goals..=goals)` drawn from one
//!   deterministic proptest runner per cell: random layout (island, corner pairs), goal
//!   joints open (≥ 3/4 of the upper limit) with probability 3/4 else closed, doors open at
//!   the start with probability 0.3. Many of these goals are infeasible (neighbouring parts
//!   that collide when both are open, a rack that hits its carcass while its door is
//!   closed); proving that takes an exhaustive search. The table counts, per cell, the
//!   random goals that a cheap static test proves infeasible ([`static_conflict`]: two goal
//!   parts, or a goal part and the base, collide at every lattice value of their targets).
//! - **planted**: the same kitchens, starts and goal joints, with the goal made feasible by
//!   construction ([`planted`]): the goal joints are moved greedily, each straight to its
//!   target, while [`Feasibility::check`] accepts; a goal joint no pass can move keeps its
//!   current value as an exact target. The greedy sequence is a plan in the lattice, so a
//!   complete search must solve every planted instance (given time).
//!
//! # Planners
//! Each bounded by a wall-clock [`Termination::after`] (or a deadline for brute force):
//!
//! - **search**: [`Strategy::Search`], default [`TaskSettings`] (1 interior value per joint,
//!   default cost weights, `parallelism` 0 = one rayon thread per core), budget
//!   [`SEARCH_BUDGET`] (`KINSCENE_BENCH_SEARCH_BUDGET=<seconds>` overrides it,
//!   `KINSCENE_BENCH_WEIGHT=<w>` sets `heuristic_weight` and `KINSCENE_BENCH_FIRST_WEIGHT=<w>`
//!   the anytime `first_pass_weight` for both search rows; the table also gives the time to
//!   the first plan and the largest proven suboptimality factor);
//! - **search_t0**: the same with `cost.travel = 0` (base travel free), planted family only:
//!   an ablation that shows how much of the search's effort comes from the base-travel term
//!   its heuristic does not bound;
//! - **paper**: [`Strategy::Paper`] (rejection-sampled orders of the goal joints, boxes of the
//!   manipulated parts at 6 samples, the search's path rule; see src/task/baseline.rs),
//!   `max_samples` [`PAPER_MAX_SAMPLES`], budget [`PAPER_BUDGET`], seed = instance number;
//! - **brute_force**: breadth-first search over the full lattice (every joint, every lattice
//!   value, no heuristic, no memo, no active set) from the start, calling
//!   [`Feasibility::check`] on every move out of every dequeued state, goal test on
//!   generation, stopped after [`BRUTE_BUDGET`] or [`BRUTE_MAX_STATES`] generated states
//!   (reported as a timeout). Only on 10-part scenes with 3 and 6 goal joints, first
//!   [`BRUTE_INSTANCES`] instances: a check costs milliseconds and a 10-joint lattice state
//!   has about 40 successors, so BFS reaches depth 2 at best.
//!
//! # Output
//! Before criterion runs, `main` plays every planner on every instance once, validates
//! every `Solved` plan with [`validate`] outside the timed region, and prints: a table of
//! outcome counts, validated plans, median and max wall time per instance (a timeout counts
//! at the time it returned), the median time to a *valid* plan (instances without one count
//! as ∞), the search's statistics; the Paper/Search ratios at 10 goal joints; whether
//! 100 parts / 20 goal joints stays under 1 s; agreement between the planners' verdicts; and
//! the cost of the predicate's phases on one instance per scene size, timed through the
//! public API. Criterion then times one planted instance per headline
//! (`task/<planner>/<p>parts_<g>goals`): the one with the median time among those the
//! planner solved in the table run (headlines with no solved instance are skipped), and the
//! exact decision at the grid's boundary against the grid alone
//! (`boundary/{predicate_setup,goal_moves}/<p>parts/{exact,grid}`, see [`boundary`]).
//!
//! `cargo bench --no-default-features --bench task -- --warm-up-time 1 --measurement-time 2`
//! (the task layer is pure Rust). `KINSCENE_BENCH_QUICK=1` shrinks the instance sets,
//! `KINSCENE_BENCH_CELLS=10x3,100x20` selects cells, `KINSCENE_BENCH_PLANNERS=search,paper`
//! selects planners (labels as in the table), `KINSCENE_BENCH_VERBOSE=1` prints one line per
//! run.

#[path = "../tests/task/generators.rs"]
mod generators;

use std::collections::{HashSet, VecDeque};
use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode};
use kinscene::scene::collision::{Body, Contact, check_joint_motion, collisions};
use kinscene::scene::nav::occupancy;
use kinscene::scene::{JointId, PartId, SceneData, SceneModel, State, forward_kinematics};
use kinscene::task::{
    Feasibility, GoalSpec, Lattice, MoveCheck, NoRefinement, Outcome, Problem, SearchStats, Step,
    Strategy, TargetSpec, TaskSettings, Termination, plan, validate,
};
use proptest::strategy::{Strategy as _, ValueTree};
use proptest::test_runner::TestRunner;

/// Scene sizes (parts = joints).
const PARTS: [usize; 3] = [10, 50, 100];
/// Goal sizes (joints named in the goal).
const GOALS: [usize; 4] = [3, 6, 10, 20];
/// Instances per cell and family.
const INSTANCES: usize = 5;
/// Instances per cell and family with `KINSCENE_BENCH_QUICK=1`.
const QUICK_INSTANCES: usize = 2;
/// Budget of the search per instance: twice the target at 100 parts / 20 goal joints.
const SEARCH_BUDGET: Duration = Duration::from_secs(2);
/// Budget of the Paper sampler per instance (its sample limit usually ends it first).
const PAPER_BUDGET: Duration = Duration::from_secs(2);
/// Orders the Paper sampler may draw per instance (the default of [`TaskSettings`]).
const PAPER_MAX_SAMPLES: usize = 10_000;
/// Budget of brute force per instance.
const BRUTE_BUDGET: Duration = Duration::from_secs(2);
/// Lattice states brute force may generate per instance.
const BRUTE_MAX_STATES: usize = 20_000;
/// Instances per cell brute force runs on.
const BRUTE_INSTANCES: usize = 3;
/// Cells (parts, goal joints) brute force runs on.
const BRUTE_CELLS: [(usize, usize); 2] = [(10, 3), (10, 6)];
/// The target for 100 parts / 20 goal joints.
const TARGET_100_20: Duration = Duration::from_secs(1);
/// The target speed-up over the sampler at 10 goal joints.
const TARGET_RATIO: f64 = 100.0;

// ---------------------------------------------------------------------------------------------
// Instances

/// How the goal of an instance was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Family {
    Random,
    Planted,
}

impl Family {
    fn label(self) -> &'static str {
        match self {
            Family::Random => "random",
            Family::Planted => "planted",
        }
    }
}

/// One planning problem of a cell.
#[derive(Clone)]
struct Instance {
    kitchen: generators::Kitchen,
    spec: GoalSpec,
    problem: Problem,
}

/// A static conflict that proves the goal infeasible: two bodies (two parts, or a part and a
/// base shape) that collide in *every* goal state of the lattice. Candidates are the pairs
/// colliding in the state "every goal joint at its target point nearest the start"; a pair
/// qualifies when the pose of each of its parts depends only on goal joints (the part's
/// joint and all its ancestors' are in the goal) and it collides at every combination of
/// those joints' lattice values inside their targets. Every state the search reaches is
/// collision-free (each move's certified sweep includes its end value, and the generated
/// starts are collision-free), so no plan in the lattice can end in a goal state then.
/// Returns the pair's names.
fn static_conflict(inst: &Instance) -> Option<(String, String)> {
    let model = &inst.kitchen.model;
    let problem = &inst.problem;
    let settings = TaskSettings::default();
    let lattice = Lattice::new(model, problem, &settings.lattice);
    let mut q = problem.start.as_slice().to_vec();
    for (j, t) in problem.goal.targets() {
        q[j.index()] = t.nearest(q[j.index()]);
    }
    let collide = |q: &[f64]| -> Vec<Contact> {
        let state = State::from_slice(model, q).expect("lattice values lie within the limits");
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, &state).expect("fk");
        collisions(model, &data, &settings.sweep.collision).expect("collisions")
    };
    // The joints that place a body: the part's joint and its ancestors'.
    let chain = |body: Body| -> Vec<JointId> {
        match body {
            Body::Part(p) => model.path_to_base(p).map(PartId::joint).collect(),
            Body::Base(_) => Vec::new(),
        }
    };
    let name = |body: Body| match body {
        Body::Part(p) => model.parts()[p.index()].name().to_string(),
        Body::Base(b) => model.base().shapes[b.index()].name.clone(),
    };
    for contact in collide(&q) {
        let mut joints = chain(contact.a);
        joints.extend(chain(contact.b));
        joints.sort_by_key(|j| j.index());
        joints.dedup();
        // The lattice values inside each chain joint's target; `None` if one is not a goal
        // joint (it could move the pair apart).
        let Some(choices) = joints
            .iter()
            .map(|j| {
                let t = problem.goal.target(*j)?;
                let values = lattice.values(*j).iter().copied();
                Some(values.filter(|v| t.contains(*v)).collect::<Vec<f64>>())
            })
            .collect::<Option<Vec<Vec<f64>>>>()
        else {
            continue;
        };
        let same = |c: &Contact| {
            (c.a, c.b) == (contact.a, contact.b) || (c.a, c.b) == (contact.b, contact.a)
        };
        // Every combination of the chain joints' target values (a mixed-radix counter).
        let mut digits = vec![0usize; joints.len()];
        let always = loop {
            let mut state = q.clone();
            for ((j, d), values) in joints.iter().zip(&digits).zip(&choices) {
                state[j.index()] = values[*d];
            }
            if !collide(&state).iter().any(same) {
                break false;
            }
            let mut k = 0;
            while k < digits.len() {
                digits[k] += 1;
                if digits[k] < choices[k].len() {
                    break;
                }
                digits[k] = 0;
                k += 1;
            }
            if k == digits.len() {
                break true;
            }
        };
        if always {
            return Some((name(contact.a), name(contact.b)));
        }
    }
    None
}

/// The random instances of a cell: one deterministic runner per cell, so a cell does not
/// change when another is added or removed.
fn random_instances(parts: usize, goals: usize, n: usize) -> Vec<Instance> {
    let mut runner = TestRunner::deterministic();
    let strategy = generators::instance(parts..=parts, goals..=goals);
    let mut out = Vec::with_capacity(n);
    let mut drawn = 0;
    while out.len() < n {
        drawn += 1;
        assert!(
            drawn <= 100 * n,
            "cannot draw valid instances for {parts}/{goals}"
        );
        let (kitchen, spec) = strategy.new_tree(&mut runner).expect("strategy").current();
        // A goal document the model rejects would be a generator bug: skip it loudly.
        match Problem::from_spec(&kitchen.model, &spec) {
            Ok(problem) => out.push(Instance {
                kitchen,
                spec,
                problem,
            }),
            Err(e) => eprintln!("task bench: skipping an instance the model rejects: {e}"),
        }
    }
    out
}

/// The lattice indices of `problem.start`.
fn start_key(model: &SceneModel, problem: &Problem, lattice: &Lattice) -> Vec<usize> {
    model
        .parts()
        .iter()
        .map(|p| {
            let j = p.joint();
            lattice
                .index_of(j, problem.start.as_slice()[j.index()])
                .expect("the start value is in the lattice")
        })
        .collect()
}

/// `inst` with its goal made feasible by construction: the goal joints whose start value
/// misses the target are moved, in joint order, in repeated passes until a pass moves none,
/// each straight to the point of its target nearest to its start value, whenever
/// [`Feasibility::check`] (default settings) accepts the move in the current state. A goal
/// joint no pass could move gets the exact target "its start value". The accepted moves form
/// a plan of the new problem in its lattice (their values are start values and target points
/// nearest the start, both lattice values, and the predicate does not depend on the goal).
fn planted(inst: &Instance) -> Instance {
    let model = &inst.kitchen.model;
    let settings = TaskSettings::default();
    let lattice = Lattice::new(model, &inst.problem, &settings.lattice);
    let mut feasibility =
        Feasibility::new(model, &inst.problem, &settings, &lattice).expect("valid instance");
    let start = inst.problem.start.as_slice();
    let mut key = start_key(model, &inst.problem, &lattice);
    let mut pending: Vec<(JointId, usize)> = inst
        .problem
        .goal
        .targets()
        .iter()
        .filter(|(j, t)| !t.contains(start[j.index()]))
        .map(|(j, t)| {
            let to = lattice
                .index_of(*j, t.nearest(start[j.index()]))
                .expect("the target point is in the lattice");
            (*j, to)
        })
        .collect();
    loop {
        let before = pending.len();
        pending.retain(|&(j, to)| {
            match feasibility.check(&key, j, to).expect("indices in range") {
                MoveCheck::Feasible { .. } => {
                    key[j.index()] = to;
                    false
                }
                MoveCheck::Infeasible(_) => true,
            }
        });
        if pending.is_empty() || pending.len() == before {
            break;
        }
    }
    let mut spec = inst.spec.clone();
    for (j, _) in &pending {
        let name = model.joints()[j.index()].name.clone();
        spec.goal.insert(name, TargetSpec::Value(start[j.index()]));
    }
    let problem = Problem::from_spec(model, &spec).expect("a planted goal is valid");
    Instance {
        kitchen: inst.kitchen.clone(),
        spec,
        problem,
    }
}

// ---------------------------------------------------------------------------------------------
// Brute force

/// A generated lattice state: its key, its parent and the step from it.
struct BruteNode {
    key: Vec<usize>,
    parent: Option<(usize, Step)>,
}

/// Breadth-first search over the full lattice with [`Feasibility::check`] (see the module
/// docs). Returns the verdict, the plan (base pose and handle from the predicate; travel and
/// cost left at 0, `validate` does not read them), predicate calls and states generated.
fn brute_force(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    deadline: Instant,
) -> (Verdict, Vec<Step>, usize, usize) {
    let lattice = Lattice::new(model, problem, &settings.lattice);
    let Ok(mut feasibility) = Feasibility::new(model, problem, settings, &lattice) else {
        return (Verdict::Error, Vec::new(), 0, 0);
    };
    let joints: Vec<JointId> = model.parts().iter().map(|p| p.joint()).collect();
    let satisfied = |key: &[usize]| {
        let q: Vec<f64> = joints
            .iter()
            .zip(key)
            .map(|(j, &i)| lattice.values(*j)[i])
            .collect();
        let state = State::from_slice(model, &q).expect("lattice values are within the limits");
        problem.goal.is_satisfied(&state)
    };
    let start = start_key(model, problem, &lattice);
    if satisfied(&start) {
        return (Verdict::Solved, Vec::new(), 0, 1);
    }
    let mut nodes = vec![BruteNode {
        key: start.clone(),
        parent: None,
    }];
    let mut seen: HashSet<Vec<usize>> = HashSet::from([start]);
    let mut queue = VecDeque::from([0usize]);
    let mut checks = 0;
    while let Some(at) = queue.pop_front() {
        let key = nodes[at].key.clone();
        for (k, &joint) in joints.iter().enumerate() {
            let values = lattice.values(joint);
            for to in 0..values.len() {
                let mut next = key.clone();
                next[k] = to;
                if to == key[k] || seen.contains(&next) {
                    continue;
                }
                if Instant::now() >= deadline || seen.len() >= BRUTE_MAX_STATES {
                    return (Verdict::Timeout, Vec::new(), checks, seen.len());
                }
                checks += 1;
                let Ok(verdict) = feasibility.check(&key, joint, to) else {
                    return (Verdict::Error, Vec::new(), checks, seen.len());
                };
                let MoveCheck::Feasible { base, handle } = verdict else {
                    continue;
                };
                let step = Step {
                    joint: model.joints()[k].name.clone(),
                    from: values[key[k]],
                    to: values[to],
                    handle: Some(handle),
                    base: Some(base),
                    travel: 0.0,
                    cost: 0.0,
                };
                seen.insert(next.clone());
                let done = satisfied(&next);
                nodes.push(BruteNode {
                    key: next,
                    parent: Some((at, step)),
                });
                let idx = nodes.len() - 1;
                if done {
                    let mut steps = Vec::new();
                    let mut i = idx;
                    while let Some((p, s)) = &nodes[i].parent {
                        steps.push(s.clone());
                        i = *p;
                    }
                    steps.reverse();
                    return (Verdict::Solved, steps, checks, seen.len());
                }
                queue.push_back(idx);
            }
        }
    }
    (Verdict::Infeasible, Vec::new(), checks, seen.len())
}

// ---------------------------------------------------------------------------------------------
// Runs

/// The planners compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Planner {
    Search,
    SearchTravel0,
    Paper,
    Brute,
}

impl Planner {
    fn label(self) -> &'static str {
        match self {
            Planner::Search => "search",
            Planner::SearchTravel0 => "search_t0",
            Planner::Paper => "paper",
            Planner::Brute => "brute_force",
        }
    }

    fn settings(self, seed: u64) -> TaskSettings {
        let mut s = TaskSettings::default();
        match self {
            Planner::Search | Planner::Brute => {
                s.heuristic_weight = heuristic_weight();
                s.first_pass_weight = first_pass_weight();
            }
            Planner::SearchTravel0 => {
                s.heuristic_weight = heuristic_weight();
                s.first_pass_weight = first_pass_weight();
                s.cost.travel = 0.0;
            }
            Planner::Paper => {
                s.strategy = Strategy::Paper { seed };
                s.max_samples = PAPER_MAX_SAMPLES;
            }
        }
        s
    }

    fn budget(self) -> Duration {
        match self {
            Planner::Search | Planner::SearchTravel0 => search_budget(),
            Planner::Paper => PAPER_BUDGET,
            Planner::Brute => BRUTE_BUDGET,
        }
    }
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Verdict {
    Solved,
    Infeasible,
    /// Budget, sample limit or state cap reached.
    Timeout,
    /// `Err` (bad input): should not happen on generated instances.
    Error,
}

/// One planner on one instance.
struct Run {
    verdict: Verdict,
    time: Duration,
    steps: usize,
    stats: SearchStats,
    /// Brute force: predicate calls and states generated.
    checks: usize,
    states: usize,
    /// [`validate`] of a solved plan: `Some(valid)`; `None` if not solved.
    valid: Option<bool>,
    validate_time: Duration,
    /// Why infeasible, what a timeout left unmet, why a plan was rejected.
    note: String,
}

/// Plays `planner` on `inst` (instance number `i`) once, timed; validates a solved plan
/// afterwards, untimed, with the planner's settings (the validator reads the sweep,
/// manipulation and robot settings, which all planners share).
fn run(planner: Planner, inst: &Instance, i: usize) -> Run {
    let model = &inst.kitchen.model;
    let settings = planner.settings(i as u64);
    let mut note = String::new();
    let started = Instant::now();
    let (verdict, steps, stats, checks, states) = match planner {
        Planner::Brute => {
            let (v, steps, checks, states) =
                brute_force(model, &inst.problem, &settings, started + planner.budget());
            (v, steps, SearchStats::default(), checks, states)
        }
        _ => {
            let termination = Termination::after(planner.budget());
            match plan(model, &inst.problem, &settings, &NoRefinement, &termination) {
                Ok(r) => {
                    let (v, steps) = match r.outcome {
                        Outcome::Solved(p) => (Verdict::Solved, p.steps),
                        Outcome::Infeasible(why) => {
                            note = why.message;
                            (Verdict::Infeasible, Vec::new())
                        }
                        Outcome::Timeout(partial) | Outcome::Cancelled(partial) => {
                            note = format!(
                                "best partial: {} steps, unmet {:?}",
                                partial.plan.steps.len(),
                                partial.unmet
                            );
                            (Verdict::Timeout, Vec::new())
                        }
                    };
                    (v, steps, r.stats, 0, 0)
                }
                Err(e) => {
                    note = format!("error: {e}");
                    (Verdict::Error, Vec::new(), SearchStats::default(), 0, 0)
                }
            }
        }
    };
    let time = started.elapsed();
    let started = Instant::now();
    let valid = (verdict == Verdict::Solved).then(|| {
        match validate(model, &inst.problem, &steps, &settings) {
            Ok(v) if v.valid => true,
            Ok(v) => {
                note = format!("{:?}", v.first_failure);
                false
            }
            Err(e) => {
                note = format!("validate error: {e}");
                false
            }
        }
    });
    Run {
        verdict,
        time,
        steps: steps.len(),
        stats,
        checks,
        states,
        valid,
        validate_time: started.elapsed(),
        note,
    }
}

// ---------------------------------------------------------------------------------------------
// Settings from the environment

fn env_flag(name: &str) -> bool {
    std::env::var(name).is_ok_and(|v| !v.is_empty() && v != "0")
}

fn quick() -> bool {
    env_flag("KINSCENE_BENCH_QUICK")
}

fn verbose() -> bool {
    env_flag("KINSCENE_BENCH_VERBOSE")
}

/// `KINSCENE_BENCH_CELLS=10x3,100x20`: only these cells (default: all).
fn selected(parts: usize, goals: usize) -> bool {
    match std::env::var("KINSCENE_BENCH_CELLS") {
        Ok(list) if !list.trim().is_empty() => list
            .split(',')
            .any(|c| c.trim() == format!("{parts}x{goals}")),
        _ => true,
    }
}

/// `KINSCENE_BENCH_PLANNERS=search,paper`: only these planners, by label (default: all).
fn planner_selected(planner: Planner) -> bool {
    match std::env::var("KINSCENE_BENCH_PLANNERS") {
        Ok(list) if !list.trim().is_empty() => list.split(',').any(|p| p.trim() == planner.label()),
        _ => true,
    }
}

/// [`SEARCH_BUDGET`], or `KINSCENE_BENCH_SEARCH_BUDGET` seconds.
fn search_budget() -> Duration {
    std::env::var("KINSCENE_BENCH_SEARCH_BUDGET")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .and_then(|s| Duration::try_from_secs_f64(s).ok())
        .unwrap_or(SEARCH_BUDGET)
}

/// The search's `heuristic_weight`: the default (1, A*), or `KINSCENE_BENCH_WEIGHT` (2: the
/// focal order for large rooms).
fn heuristic_weight() -> f64 {
    std::env::var("KINSCENE_BENCH_WEIGHT")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .unwrap_or(TaskSettings::default().heuristic_weight)
}

/// The search's `first_pass_weight`: the default (2), or `KINSCENE_BENCH_FIRST_WEIGHT` (1:
/// one pass).
fn first_pass_weight() -> f64 {
    std::env::var("KINSCENE_BENCH_FIRST_WEIGHT")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .unwrap_or(TaskSettings::default().first_pass_weight)
}

// ---------------------------------------------------------------------------------------------
// Summary

/// The results of one cell and family.
struct Cell {
    parts: usize,
    goals: usize,
    family: Family,
    instances: Vec<Instance>,
    /// [`static_conflict`] of each instance (random family only; planted goals are feasible).
    conflicts: Vec<Option<(String, String)>>,
    runs: Vec<(Planner, Vec<Run>)>,
}

impl Cell {
    fn runs(&self, planner: Planner) -> Option<&[Run]> {
        self.runs
            .iter()
            .find(|(p, _)| *p == planner)
            .map(|(_, r)| r.as_slice())
    }

    fn name(&self) -> String {
        format!("{}parts_{}goals", self.parts, self.goals)
    }

    /// The instance with the median time among those `planner` solved.
    fn median_solved(&self, planner: Planner) -> Option<usize> {
        let mut solved: Vec<(Duration, usize)> = self
            .runs(planner)?
            .iter()
            .enumerate()
            .filter(|(_, r)| r.verdict == Verdict::Solved)
            .map(|(i, r)| (r.time, i))
            .collect();
        solved.sort();
        solved.get(solved.len().saturating_sub(1) / 2).map(|x| x.1)
    }
}

/// The median (lower middle for an even count) of `v`, `None` if empty.
fn median(mut v: Vec<Duration>) -> Option<Duration> {
    v.sort();
    v.get(v.len().saturating_sub(1) / 2).copied()
}

/// The median time to a validated plan, runs without one counting as ∞ (`None`).
fn median_to_valid(runs: &[Run]) -> Option<Duration> {
    let mut v: Vec<Option<Duration>> = runs
        .iter()
        .map(|r| (r.valid == Some(true)).then_some(r.time))
        .collect();
    // `None` (∞) after every finite time.
    v.sort_by_key(|t| (t.is_none(), *t));
    v.get(v.len().saturating_sub(1) / 2).copied().flatten()
}

/// The median time to the search's first plan, runs without one counting as ∞ (`None`).
fn median_first_plan(runs: &[Run]) -> Option<Duration> {
    let mut v: Vec<Option<Duration>> = runs.iter().map(|r| r.stats.first_plan).collect();
    v.sort_by_key(|t| (t.is_none(), *t));
    v.get(v.len().saturating_sub(1) / 2).copied().flatten()
}

/// The largest proven suboptimality factor of the solved runs, if any.
fn max_factor(runs: &[Run]) -> Option<f64> {
    runs.iter()
        .filter_map(|r| r.stats.suboptimality)
        .max_by(f64::total_cmp)
}

fn ms(d: Duration) -> String {
    let x = d.as_secs_f64() * 1e3;
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 10.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.2}")
    }
}

fn ms_or_inf(d: Option<Duration>) -> String {
    d.map_or("∞".into(), ms)
}

fn count(runs: &[Run], v: Verdict) -> usize {
    runs.iter().filter(|r| r.verdict == v).count()
}

fn mean(runs: &[Run], f: impl Fn(&Run) -> usize) -> f64 {
    runs.iter().map(f).sum::<usize>() as f64 / runs.len().max(1) as f64
}

fn print_table(cells: &[Cell]) {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!();
    println!(
        "task: {} instances per cell and family (brute force: {}); budgets: search {:?}, paper {:?} or {PAPER_MAX_SAMPLES} orders, brute force {:?} or {BRUTE_MAX_STATES} states; {threads} hardware threads",
        cells.first().map_or(0, |c| c.instances.len()),
        BRUTE_INSTANCES.min(cells.first().map_or(0, |c| c.instances.len())),
        search_budget(),
        PAPER_BUDGET,
        BRUTE_BUDGET,
    );
    println!(
        "S/I/T = solved / infeasible / timeout (budget, sample limit or state cap); valid = solved plans that pass validate; times per instance in ms, wall clock; to-valid = median time to a valid plan (no valid plan = ∞)"
    );
    println!(
        "{:<16} {:<8} {:<11} {:>7} {:>5} {:>8} {:>8} {:>8} {:>5} | details (means over the cell)",
        "cell", "family", "planner", "S/I/T", "valid", "median", "max", "to-valid", "steps"
    );
    for cell in cells {
        if cell.family == Family::Random {
            println!(
                "{:<16} random goals proven infeasible by a static conflict: {}/{}",
                cell.name(),
                cell.conflicts.iter().filter(|c| c.is_some()).count(),
                cell.instances.len()
            );
            if verbose() {
                for (i, c) in cell.conflicts.iter().enumerate() {
                    if let Some((a, b)) = c {
                        println!("    #{i}: {a} and {b} collide in every goal state");
                    }
                }
            }
        }
        for (planner, runs) in &cell.runs {
            let times: Vec<Duration> = runs.iter().map(|r| r.time).collect();
            let solved: Vec<&Run> = runs
                .iter()
                .filter(|r| r.verdict == Verdict::Solved)
                .collect();
            let steps = if solved.is_empty() {
                "-".to_string()
            } else {
                format!(
                    "{:.1}",
                    solved.iter().map(|r| r.steps).sum::<usize>() as f64 / solved.len() as f64
                )
            };
            let details = match planner {
                Planner::Search | Planner::SearchTravel0 => format!(
                    "first plan median {} ms, proven factor max {}, 2-pass runs {}; expanded {:.0}, evaluated {:.0}, sweeps {:.0}, memo hits {:.0}, rounds {:.1}, active {:.1}",
                    ms_or_inf(median_first_plan(runs)),
                    max_factor(runs).map_or("-".into(), |f| format!("{f:.2}")),
                    runs.iter().filter(|r| r.stats.passes == 2).count(),
                    mean(runs, |r| r.stats.expanded),
                    mean(runs, |r| r.stats.evaluated),
                    mean(runs, |r| r.stats.sweeps),
                    mean(runs, |r| r.stats.memo_hits),
                    mean(runs, |r| r.stats.rounds),
                    mean(runs, |r| r.stats.active_joints),
                ),
                Planner::Paper => format!(
                    "orders sampled {:.0}, path checks {:.0}",
                    mean(runs, |r| r.stats.samples),
                    mean(runs, |r| r.stats.evaluated),
                ),
                Planner::Brute => format!(
                    "predicate calls {:.0}, states generated {:.0}",
                    mean(runs, |r| r.checks),
                    mean(runs, |r| r.states),
                ),
            };
            println!(
                "{:<16} {:<8} {:<11} {:>7} {:>5} {:>8} {:>8} {:>8} {:>5} | {details}",
                cell.name(),
                cell.family.label(),
                planner.label(),
                format!(
                    "{}/{}/{}",
                    count(runs, Verdict::Solved),
                    count(runs, Verdict::Infeasible),
                    count(runs, Verdict::Timeout)
                ),
                runs.iter().filter(|r| r.valid == Some(true)).count(),
                ms(median(times.clone()).unwrap_or_default()),
                ms(times.iter().copied().max().unwrap_or_default()),
                ms_or_inf(median_to_valid(runs)),
                steps,
            );
            for (i, r) in runs.iter().enumerate() {
                if r.verdict == Verdict::Error {
                    println!("    {}#{i}: {}", cell.name(), r.note);
                }
            }
        }
    }

    // Every solved plan through the validator.
    println!();
    let mut validate_time = Duration::ZERO;
    for planner in [
        Planner::Search,
        Planner::SearchTravel0,
        Planner::Paper,
        Planner::Brute,
    ] {
        let (mut solved, mut invalid) = (0, 0);
        for cell in cells {
            for (i, r) in cell.runs(planner).unwrap_or_default().iter().enumerate() {
                validate_time += r.validate_time;
                let Some(valid) = r.valid else {
                    continue;
                };
                solved += 1;
                if !valid {
                    invalid += 1;
                    println!(
                        "    {} plan of {}/{}#{i} rejected: {}",
                        planner.label(),
                        cell.name(),
                        cell.family.label(),
                        r.note
                    );
                    if planner != Planner::Paper {
                        println!(
                            "    kitchen {:?}, goal:\n{}",
                            cell.instances[i].kitchen.params,
                            cell.instances[i].spec.to_toml()
                        );
                    }
                }
            }
        }
        let expect = match planner {
            Planner::Paper => {
                "(allowed by design: the sampler misses collisions between its samples, beyond 90° / 15 cm and with parts outside the goal)"
            }
            _ => "(must be 0)",
        };
        println!(
            "validate: {invalid} of {solved} solved {} plans rejected {expect}",
            planner.label()
        );
    }
    println!("validate: {validate_time:.1?} in total, untimed");

    // Verdicts that contradict completeness: the search calls an instance infeasible but
    // another planner returns a valid plan for it (every plan of the baselines moves goal
    // joints to lattice values, so it lies in the search's lattice), or a planted instance
    // is called infeasible, or brute force exhausts a lattice the search found a plan in.
    let mut contradictions = 0;
    for cell in cells {
        let Some(search) = cell.runs(Planner::Search) else {
            continue;
        };
        let mut say = |i: usize, what: &str| {
            contradictions += 1;
            println!("    {}/{}#{i}: {what}", cell.name(), cell.family.label());
        };
        for (i, s) in search.iter().enumerate() {
            if cell.family == Family::Planted && s.verdict == Verdict::Infeasible {
                say(i, "the search calls a planted (feasible) goal infeasible");
            }
            if let (Some((a, b)), Verdict::Solved) = (&cell.conflicts[i], s.verdict) {
                say(
                    i,
                    &format!("the search solves a goal that {a} and {b} make infeasible"),
                );
            }
        }
        for other in [Planner::SearchTravel0, Planner::Paper, Planner::Brute] {
            for (i, (s, o)) in search
                .iter()
                .zip(cell.runs(other).unwrap_or_default())
                .enumerate()
            {
                if s.verdict == Verdict::Infeasible && o.valid == Some(true) {
                    say(
                        i,
                        &format!("search: infeasible; {}: a valid plan", other.label()),
                    );
                }
                if other == Planner::Brute
                    && o.verdict == Verdict::Infeasible
                    && s.verdict == Verdict::Solved
                {
                    say(i, "brute force exhausts the lattice; the search solves it");
                }
            }
        }
    }
    println!(
        "agreement: {contradictions} contradictions with the search's completeness (must be 0)"
    );

    // Ratios at 10 goal joints.
    println!();
    for cell in cells.iter().filter(|c| c.goals == 10) {
        let (Some(search), Some(paper)) = (cell.runs(Planner::Search), cell.runs(Planner::Paper))
        else {
            continue;
        };
        let t_search = median(search.iter().map(|r| r.time).collect()).unwrap_or_default();
        let t_paper = median(paper.iter().map(|r| r.time).collect()).unwrap_or_default();
        let ratio = t_paper.as_secs_f64() / t_search.as_secs_f64().max(1e-9);
        let valid = |runs: &[Run]| runs.iter().filter(|r| r.valid == Some(true)).count();
        let to_valid = match (median_to_valid(paper), median_to_valid(search)) {
            (Some(p), Some(s)) => format!("{:.3}×", p.as_secs_f64() / s.as_secs_f64()),
            (None, Some(_)) => "∞ (the sampler has no valid plan on most instances)".into(),
            (Some(_), None) => "0 (the search has no plan on most instances)".into(),
            (None, None) => "undefined (neither has a valid plan on most instances)".into(),
        };
        // The anytime search's first plan (the call goes on to prove or improve it).
        let first = match (
            median(paper.iter().map(|r| r.time).collect()),
            median_first_plan(search),
        ) {
            (Some(p), Some(f)) => format!(
                "{} ms, paper/first plan {:.3}×",
                ms(f),
                p.as_secs_f64() / f.as_secs_f64().max(1e-9)
            ),
            _ => "none on most instances".into(),
        };
        println!(
            "paper/search at {} ({}): median time {} ms / {} ms = {:.3}× (target ≥ {TARGET_RATIO}×: {}); search's first plan: {first}; valid plans {}/{} vs {}/{}; median time to a valid plan: {} / {} ms = {to_valid}",
            cell.name(),
            cell.family.label(),
            ms(t_paper),
            ms(t_search),
            ratio,
            if ratio >= TARGET_RATIO {
                "met"
            } else {
                "MISSED"
            },
            valid(paper),
            paper.len(),
            valid(search),
            search.len(),
            ms_or_inf(median_to_valid(paper)),
            ms_or_inf(median_to_valid(search)),
        );
    }
    for cell in cells.iter().filter(|c| c.parts == 100 && c.goals == 20) {
        for planner in [Planner::Search, Planner::SearchTravel0] {
            let Some(runs) = cell.runs(planner) else {
                continue;
            };
            let max = runs.iter().map(|r| r.time).max().unwrap_or_default();
            // With the anytime passes a call may go on proving after its first plan; the
            // target is read on the first plan (a valid plan, with its proven factor).
            let first: Vec<Option<Duration>> = runs.iter().map(|r| r.stats.first_plan).collect();
            let max_first = first
                .iter()
                .copied()
                .max_by_key(|t| (t.is_none(), *t))
                .flatten();
            let all_first = first.iter().all(|t| t.is_some_and(|t| t < TARGET_100_20));
            println!(
                "100 parts / 20 goal joints ({}, {}): solved {}/{}, median {} ms, max {} ms; first plan median {} ms, max {} ms, proven factor max {}; every instance has its first plan in under {:?}: {}",
                cell.family.label(),
                planner.label(),
                count(runs, Verdict::Solved),
                runs.len(),
                ms(median(runs.iter().map(|r| r.time).collect()).unwrap_or_default()),
                ms(max),
                ms_or_inf(median_first_plan(runs)),
                ms_or_inf(max_first),
                max_factor(runs).map_or("-".into(), |f| format!("{f:.2}")),
                TARGET_100_20,
                if all_first && count(runs, Verdict::Solved) == runs.len() {
                    "yes"
                } else {
                    "NO"
                },
            );
        }
    }
    println!();
}

/// Mean time of `f` over at least 3 calls and about 0.2 s.
fn time_it<T>(mut f: impl FnMut() -> T) -> Duration {
    let started = Instant::now();
    let mut n = 0u32;
    while n < 3 || (started.elapsed() < Duration::from_millis(200) && n < 1000) {
        black_box(f());
        n += 1;
    }
    started.elapsed() / n
}

/// The predicate's phases, timed through the public API on the first planted instance of
/// the 3-goal cell of each scene size, for its first feasible goal move from the start
/// state (each goal joint to its target, or to its upper limit if the start meets it).
fn phases(cells: &[Cell]) {
    println!(
        "phases of one feasibility check (first feasible goal move of the first planted 3-goal instance, mean of repeated calls; rest = check - sweep - 2 x (occupancy + inflate): region, swept footprint, connectivity, travel distances):"
    );
    for cell in cells
        .iter()
        .filter(|c| c.goals == 3 && c.family == Family::Planted)
    {
        let inst = &cell.instances[0];
        let model = &inst.kitchen.model;
        let problem = &inst.problem;
        let settings = TaskSettings::default();
        let start = &problem.start;
        let lattice = Lattice::new(model, problem, &settings.lattice);
        let mut feasibility =
            Feasibility::new(model, problem, &settings, &lattice).expect("predicate");
        let key = start_key(model, problem, &lattice);
        // (joint, from, to, to's lattice index, verdict) per goal joint.
        let moves: Vec<(JointId, f64, f64, usize, MoveCheck)> = problem
            .goal
            .targets()
            .iter()
            .map(|&(joint, target)| {
                let a = start.as_slice()[joint.index()];
                let b = if target.contains(a) {
                    model.joints()[joint.index()].limits.upper
                } else {
                    target.nearest(a)
                };
                let to = lattice.index_of(joint, b).expect("lattice value");
                let verdict = feasibility.check(&key, joint, to).expect("check");
                (joint, a, b, to, verdict)
            })
            .collect();
        let Some((joint, a, b, to, verdict)) = moves
            .iter()
            .find(|m| matches!(m.4, MoveCheck::Feasible { .. }))
            .or(moves.first())
            .cloned()
        else {
            continue;
        };
        let mut data = SceneData::new(model);
        let fk = time_it(|| forward_kinematics(model, &mut data, start).expect("fk"));
        forward_kinematics(model, &mut data, start).expect("fk");
        let grid = occupancy(model, &data).expect("occupancy");
        let occupancy_time = time_it(|| occupancy(model, &data).expect("occupancy"));
        let inflate = time_it(|| grid.inflate(problem.robot.radius).expect("inflate"));
        let sweep = time_it(|| {
            check_joint_motion(model, &mut data, start, joint, a, b, &settings.sweep)
                .expect("sweep")
        });
        let check = time_it(|| feasibility.check(&key, joint, to).expect("check"));
        let rest = check.saturating_sub(sweep + 2 * (occupancy_time + inflate));
        println!(
            "  {} parts, grid {}×{} ({} cells): forward kinematics {} ms, occupancy {} ms, inflate {} ms, sweep of {} ({a:.2} → {b:.2}) {} ms; Feasibility::check {} ms, rest {} ms ({})",
            cell.parts,
            grid.width(),
            grid.height(),
            grid.width() * grid.height(),
            ms(fk),
            ms(occupancy_time),
            ms(inflate),
            model.joints()[joint.index()].name,
            ms(sweep),
            ms(check),
            ms(rest),
            match verdict {
                MoveCheck::Feasible { .. } => "feasible".to_string(),
                MoveCheck::Infeasible(c) => format!("infeasible: {c}"),
            },
        );
    }
    println!();
}

/// Plays every planner on every cell and family.
fn measure() -> Vec<Cell> {
    let n = if quick() { QUICK_INSTANCES } else { INSTANCES };
    let mut cells = Vec::new();
    for parts in PARTS {
        for goals in GOALS {
            if goals > parts || !selected(parts, goals) {
                continue;
            }
            let started = Instant::now();
            let random = random_instances(parts, goals, n);
            let planted: Vec<Instance> = random.iter().map(planted).collect();
            let generated = started.elapsed();
            for (family, instances) in [(Family::Random, random), (Family::Planted, planted)] {
                let mut planners = vec![Planner::Search, Planner::Paper];
                if family == Family::Planted {
                    planners.push(Planner::SearchTravel0);
                }
                if BRUTE_CELLS.contains(&(parts, goals)) {
                    planners.push(Planner::Brute);
                }
                planners.retain(|p| planner_selected(*p));
                let mut runs = Vec::new();
                for planner in planners {
                    let count = match planner {
                        Planner::Brute => BRUTE_INSTANCES.min(instances.len()),
                        _ => instances.len(),
                    };
                    let r: Vec<Run> = instances[..count]
                        .iter()
                        .enumerate()
                        .map(|(i, inst)| {
                            let r = run(planner, inst, i);
                            if verbose() {
                                eprintln!(
                                    "  {parts}x{goals}/{}#{i} {} {:?} {:.1?} ({} steps, validate {:.1?}) {:?} {:?} {}",
                                    family.label(),
                                    planner.label(),
                                    r.verdict,
                                    r.time,
                                    r.steps,
                                    r.validate_time,
                                    inst.kitchen.params,
                                    r.stats,
                                    r.note,
                                );
                            }
                            r
                        })
                        .collect();
                    runs.push((planner, r));
                }
                let conflicts = match family {
                    Family::Random => instances.iter().map(static_conflict).collect(),
                    Family::Planted => vec![None; instances.len()],
                };
                cells.push(Cell {
                    parts,
                    goals,
                    family,
                    instances,
                    conflicts,
                    runs,
                });
            }
            eprintln!(
                "task bench: {parts} parts / {goals} goal joints done ({n} instances per family generated in {generated:.1?}, cell {:.1?})",
                started.elapsed()
            );
        }
    }
    cells
}

// ---------------------------------------------------------------------------------------------
// Criterion headline timings

/// Headlines: planner, parts, goal joints (planted family).
const HEADLINES: [(Planner, usize, usize); 7] = [
    (Planner::Search, 10, 10),
    (Planner::Search, 50, 10),
    (Planner::Search, 100, 20),
    (Planner::SearchTravel0, 100, 20),
    (Planner::Paper, 10, 10),
    (Planner::Paper, 50, 10),
    (Planner::Brute, 10, 3),
];

fn headlines(c: &mut Criterion, cells: &[Cell]) {
    let mut group = c.benchmark_group("task");
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    for (planner, parts, goals) in HEADLINES {
        let Some(cell) = cells
            .iter()
            .find(|c| c.parts == parts && c.goals == goals && c.family == Family::Planted)
        else {
            continue;
        };
        let id = format!("{}/{}", planner.label(), cell.name());
        let Some(i) = cell.median_solved(planner) else {
            println!("task/{id}: no planted instance solved within the budget; not timed");
            continue;
        };
        let inst = &cell.instances[i];
        let model = &inst.kitchen.model;
        let settings = planner.settings(i as u64);
        println!(
            "task/{id}: planted instance #{i} ({} steps in the table run)",
            cell.runs(planner).map_or(0, |r| r[i].steps),
        );
        group.bench_function(id, |b| {
            b.iter(|| match planner {
                Planner::Brute => {
                    let deadline = Instant::now() + planner.budget();
                    black_box(brute_force(model, &inst.problem, &settings, deadline));
                }
                _ => {
                    let termination = Termination::after(planner.budget());
                    black_box(
                        plan(model, &inst.problem, &settings, &NoRefinement, &termination)
                            .expect("plan"),
                    );
                }
            })
        });
    }
    group.finish();
}

/// The cost of the exact decision at the grid's boundary
/// ([`TaskSettings::boundary_clearance`]): per scene size, on the first planted instance of
/// its first cell, the predicate's construction (where the boundary cells are decided) and
/// one memo-free check of every goal joint's move from the start to its last lattice value,
/// each with the default settings (`exact`) and with `boundary_clearance: None` (`grid`).
fn boundary(c: &mut Criterion, cells: &[Cell]) {
    let mut group = c.benchmark_group("boundary");
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    let mut seen = HashSet::new();
    for cell in cells.iter().filter(|c| c.family == Family::Planted) {
        let Some(inst) = cell.instances.first() else {
            continue;
        };
        if !seen.insert(cell.parts) {
            continue;
        }
        let (model, problem) = (&inst.kitchen.model, &inst.problem);
        let start: Vec<f64> = problem.start.as_slice().to_vec();
        for (label, clearance) in [
            ("exact", TaskSettings::default().boundary_clearance),
            ("grid", None),
        ] {
            let settings = TaskSettings {
                boundary_clearance: clearance,
                ..TaskSettings::default()
            };
            let lattice = Lattice::new(model, problem, &settings.lattice);
            // One part per joint, in joint order.
            let values: Vec<usize> = model
                .parts()
                .iter()
                .map(|p| {
                    let j = p.joint();
                    lattice
                        .index_of(j, start[j.index()])
                        .expect("the start is in the lattice")
                })
                .collect();
            let parts = cell.parts;
            group.bench_function(format!("predicate_setup/{parts}parts/{label}"), |b| {
                b.iter(|| {
                    black_box(Feasibility::new(model, problem, &settings, &lattice).expect("valid"))
                })
            });
            let mut f = Feasibility::new(model, problem, &settings, &lattice).expect("valid");
            group.bench_function(format!("goal_moves/{parts}parts/{label}"), |b| {
                b.iter(|| {
                    for (j, _) in problem.goal.targets() {
                        let to = lattice.values(*j).len() - 1;
                        black_box(f.check(&values, *j, to).expect("valid move"));
                    }
                })
            });
        }
    }
    group.finish();
}

fn main() {
    let mut criterion = Criterion::default().configure_from_args();
    // `--list` (cargo's test harness protocol) only lists; nothing to measure then.
    if !std::env::args().any(|a| a == "--list") {
        let started = Instant::now();
        let cells = measure();
        print_table(&cells);
        phases(&cells);
        println!("task: table and phases in {:.1?}", started.elapsed());
        headlines(&mut criterion, &cells);
        boundary(&mut criterion, &cells);
    }
    criterion.final_summary();
}
