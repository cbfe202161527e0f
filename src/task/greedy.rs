//! The search's greedy first pass: a plan at once on rooms where most orders work.
//!
//! A depth-first dive over the goal joints only: from the start state, move one unmet goal
//! joint straight to its target (the lattice value of its target interval nearest its current
//! value), trying the joints whose handles are nearest the robot first and descending on the
//! first move the search's own predicate ([`Checker::evaluate`], the [`Refiner`] included)
//! accepts; when no move from a state is feasible, the state is dead and the dive backs up.
//! Feasibility does not depend on where the robot stands (it is always in the start's free
//! component), so a dead state is dead whatever the route to it, and no state is entered
//! twice. The dive is not complete (it never moves a non-goal joint or a goal joint to an
//! intermediate value) and it stops after a number of move evaluations proportional to the
//! number of goal joints; the lattice search then runs as before, with the dive's plan as its
//! incumbent (see [`super::search`]). Every plan it returns is made of moves the search itself
//! accepts, so it is as sound as the search's.

use std::collections::HashSet;

use super::check::{Caches, Checker, Key, Verdict};
use super::goal::Problem;
use super::lattice::Lattice;
use super::plan::{SearchStats, Step};
use super::refine::Refiner;
use super::search::feasible_step;
use super::settings::TaskSettings;
use super::{Error, Termination};
use crate::scene::{JointId, SceneData, SceneModel, forward_kinematics};

/// Move evaluations the dive may spend per goal joint still unmet at the start (plus
/// [`EVALUATIONS_BASE`]): enough for a few backtracks per joint, a small share of what the
/// search spends on a room where it stalls.
const EVALUATIONS_PER_TARGET: usize = 8;

/// Move evaluations the dive may always spend.
const EVALUATIONS_BASE: usize = 16;

/// A state of the dive with its untried moves, nearest handle last (popped first).
struct Frame {
    key: Key,
    robot: usize,
    g: f64,
    /// The step that led here (none at the start).
    step: Option<Step>,
    /// Whether every goal target is met.
    goal: bool,
    untried: Vec<(JointId, u16)>,
}

/// The plan the dive found: its steps and cost (the search's cost).
pub(super) struct Dive {
    pub steps: Vec<Step>,
    pub cost: f64,
}

/// Everything the dive reads from the search.
pub(super) struct Context<'a> {
    pub model: &'a SceneModel,
    pub problem: &'a Problem,
    pub settings: &'a TaskSettings,
    pub lattice: &'a Lattice,
    pub checker: &'a Checker<'a>,
    pub refiner: &'a dyn Refiner,
}

/// Runs the dive from `start`; `None` when it found no plan within its evaluation budget or
/// `termination` stopped it. Its evaluations count in `stats.evaluated` and fill `caches`.
pub(super) fn dive(
    cx: &Context<'_>,
    caches: &mut Caches,
    data: &mut SceneData,
    start: &Key,
    stats: &mut SearchStats,
    termination: &Termination<'_>,
) -> Result<Option<Dive>, Error> {
    let unmet_at_start = unmet_moves(cx, start).len();
    let budget = EVALUATIONS_BASE + EVALUATIONS_PER_TARGET * unmet_at_start;
    let mut spent = 0usize;
    let mut seen: HashSet<Key> = HashSet::from([start.clone()]);
    let mut stack = vec![frame(
        cx,
        data,
        start.clone(),
        cx.checker.start_cell,
        0.0,
        None,
    )?];
    while let Some(top) = stack.last_mut() {
        if top.goal {
            let cost = top.g;
            let steps = stack.into_iter().filter_map(|f| f.step).collect();
            return Ok(Some(Dive { steps, cost }));
        }
        let Some((joint, to)) = top.untried.pop() else {
            // Dead: no goal move from here is feasible.
            stack.pop();
            continue;
        };
        if spent >= budget || termination.should_stop() {
            return Ok(None);
        }
        let mut next = top.key.clone();
        next[joint.index()] = to;
        if !seen.insert(next.clone()) {
            continue;
        }
        spent += 1;
        stats.evaluated += 1;
        let (key, robot, g) = (top.key.clone(), top.robot, top.g);
        let verdict = cx
            .checker
            .evaluate(caches, data, &key, robot, joint, to, cx.refiner)?;
        if let Verdict::Feasible(choice) = verdict {
            let (step, cost) =
                feasible_step(cx.model, cx.lattice, cx.settings, &key, joint, to, &choice);
            let f = frame(cx, data, next, choice.cell, g + cost, Some(step))?;
            stack.push(f);
        }
    }
    Ok(None)
}

/// The goal moves still to make from `key`: each unmet goal joint to the lattice value of its
/// target nearest its current value.
fn unmet_moves(cx: &Context<'_>, key: &[u16]) -> Vec<(JointId, u16)> {
    unmet(cx, key).flatten().collect()
}

/// Per unmet goal target, its move from `key` (`None` if its value is not in the lattice).
fn unmet<'c>(
    cx: &'c Context<'_>,
    key: &'c [u16],
) -> impl Iterator<Item = Option<(JointId, u16)>> + 'c {
    cx.problem
        .goal
        .targets()
        .iter()
        .filter(|(j, target)| !target.contains(cx.lattice.values(*j)[key[j.index()] as usize]))
        .map(|(j, target)| {
            let value = cx.lattice.values(*j)[key[j.index()] as usize];
            // The lattice holds the target point nearest the start value, and the dive moves
            // each goal joint once, from its start value.
            let to = cx.lattice.index_of(*j, target.nearest(value))?;
            Some((*j, to as u16))
        })
}

/// A frame at `key` with the robot at `robot`: its goal moves ordered by the horizontal
/// distance from the robot to the part's nearest handle, farthest first (the stack pops the
/// nearest), ties by joint index.
fn frame(
    cx: &Context<'_>,
    data: &mut SceneData,
    key: Key,
    robot: usize,
    g: f64,
    step: Option<Step>,
) -> Result<Frame, Error> {
    let goal = unmet(cx, &key).next().is_none();
    let mut untried = unmet_moves(cx, &key);
    forward_kinematics(cx.model, data, &cx.checker.state_of(&key))?;
    let xy = cx.checker.cell_xy(robot);
    let distance = |joint: JointId| {
        let part = &cx.model.parts()[joint.part().index()];
        let pose = data.world_from_parts()[joint.part().index()];
        part.handles()
            .iter()
            .map(|h| {
                let p = pose * h.position;
                (p.x - xy[0]).hypot(p.y - xy[1])
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut keyed: Vec<(f64, (JointId, u16))> =
        untried.drain(..).map(|m| (distance(m.0), m)).collect();
    keyed.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.1.0.index().cmp(&a.1.0.index())));
    Ok(Frame {
        key,
        robot,
        g,
        step,
        goal,
        untried: keyed.into_iter().map(|(_, m)| m).collect(),
    })
}
