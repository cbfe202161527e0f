//! The paper's two baselines, selectable through [`plan`](super::plan) with
//! [`Strategy::Random`](super::Strategy::Random) and [`Strategy::Paper`](super::Strategy::Paper).
//!
//! Both move each goal joint once, straight from its start value to the point of its target
//! interval nearest to it (goal joints whose start value already meets the target are left
//! alone), in some order; neither moves a joint outside the goal nor consults the
//! [`Refiner`](super::Refiner). They return the same [`PlanResult`] as the search, with
//! `stats.samples` = the number of orders tried.
//!
//! - **Random** (the paper's baseline): one order drawn uniformly with a seeded SplitMix64
//!   generator. It is accepted iff every step passes the search's own feasibility predicate
//!   ([`Feasibility`]: certified sweep, base pose and path), which also gives the base poses;
//!   otherwise the outcome is `Infeasible`, naming the failing step and its cause.
//! - **Paper** (the paper's planner, Sec. "Scene-Level Planning": "If the bounding boxes of
//!   the manipulated parts overlap or the path of the robot is blocked, the plan is ruled
//!   infeasible"). The manipulated parts of a goal joint are its part and the part's
//!   descendants (they move with it). For each goal joint, the axis-aligned world box of each
//!   manipulated part that has colliders (one box around all its colliders) at 6 values
//!   interpolated from its start value towards its target by 90° (revolute) or 15 cm
//!   (prismatic), clamped to the limits (from 0 to 90° / 15 cm for a closed part, as in the
//!   paper), and at its start value and its target, all computed once in the start state.
//!   Orders (permutations of the goal joints) are drawn at random without repetition, up to
//!   [`TaskSettings::max_samples`]. An order is rejected if, at some position,
//!   1. at one of its 6 configurations, a box of a manipulated part of the joint moved there
//!      overlaps (open intervals on all three axes) the box of a manipulated part of another
//!      goal joint in that joint's current configuration (at its target if moved already,
//!      else at its start) — except a pair in one kinematic chain (one part an ancestor of
//!      the other, e.g. a rack and the door it rides on) and a pair allowed in
//!      [`CollisionSettings`](crate::scene::collision::CollisionSettings); or
//!   2. the robot's path is blocked: the search's base-pose and path rule (check 2 of
//!      [`Feasibility`]) with the sweep check switched off.
//!
//!   Only manipulated parts are boxed: base shapes (walls, carcasses, worktops) and parts
//!   outside the goal take part in rule 2 (they block the robot) but never in rule 1. The
//!   first accepted order is `Solved`; a budget or sample limit reached first gives
//!   `Timeout` with the longest accepted prefix; once every permutation has been rejected,
//!   `Infeasible`.
//!
//! What *Paper* misses, by design: collisions of the manipulated parts with the static base
//! and with parts outside the goal, collisions between the samples (a thin part between two
//! of the 6 boxes), motion beyond 90° / 15 cm, and the true shape of a part (its box). Its
//! plans are checked with [`validate`](super::validate) in the tests; the search's are
//! certified.

use nalgebra::Point2;

use super::lattice::Lattice;
use super::plan::{BodyName, Plan, Step};
use super::{Error, Problem, TaskSettings};
use crate::scene::collision::collisions;
use crate::scene::motion::grasp_trajectory;
use crate::scene::nav::occupancy;
use crate::scene::nav::search::Blocked;
use crate::scene::{JointId, JointKind, SceneData, SceneModel, forward_kinematics};

mod paper;
mod random;

pub(crate) use paper::paper;
pub(crate) use random::random;

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny, seedable generator, enough for drawing
/// orders reproducibly.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`), by multiply-shift (bias below `n / 2^64`).
    fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next()) * n as u128) >> 64) as usize
    }

    /// Fisher–Yates shuffle.
    fn shuffle<T>(&mut self, v: &mut [T]) {
        for i in (1..v.len()).rev() {
            let j = self.below(i + 1);
            v.swap(i, j);
        }
    }
}

/// A goal joint the baselines move: its id and the value it moves to.
#[derive(Debug, Clone, Copy)]
struct Move {
    joint: JointId,
    to: f64,
}

/// Goal joints whose start value misses the target, in id order, each with the point of
/// its target nearest to the start value.
fn pending_moves(problem: &Problem) -> Vec<Move> {
    problem
        .goal
        .targets()
        .iter()
        .filter(|(j, t)| !t.contains(problem.start.q[j.index()]))
        .map(|(j, t)| Move {
            joint: *j,
            to: t.nearest(problem.start.q[j.index()]),
        })
        .collect()
}

/// Lattice indices of the start state.
fn start_key(
    model: &SceneModel,
    problem: &Problem,
    lattice: &Lattice,
) -> Result<Vec<usize>, Error> {
    (0..model.nq())
        .map(|k| lattice_index(lattice, JointId(k), problem.start.q[k], k))
        .collect()
}

fn lattice_index(
    lattice: &Lattice,
    joint: JointId,
    value: f64,
    step: usize,
) -> Result<usize, Error> {
    lattice
        .index_of(joint, value)
        .ok_or_else(|| Error::InvalidStep {
            step,
            message: format!(
                "value {value} of joint {} is not in the lattice",
                joint.index()
            ),
        })
}

fn joint_name(model: &SceneModel, joint: JointId) -> String {
    model.joints()[joint.index()].name.clone()
}

fn start_collisions(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
) -> Result<Vec<(BodyName, BodyName)>, Error> {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, &problem.start)?;
    Ok(collisions(model, &data, &settings.sweep.collision)?
        .into_iter()
        .map(|c| (BodyName::of(model, c.a), BodyName::of(model, c.b)))
        .collect())
}

/// Turns accepted moves (with the base pose and handle the predicate chose) into plan steps:
/// base travel along the shortest free grid path from the robot's previous cell in the state
/// before each step, handle travel along the grasp trajectory, cost as
/// [`CostWeights`](super::CostWeights).
fn build_steps(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    robot_start: usize,
    moves: &[(Move, [f64; 3], String)],
) -> Result<Vec<Step>, Error> {
    let mut data = SceneData::new(model);
    let mut state = problem.start.clone();
    let grid = model.base_grid();
    let res = grid.resolution();
    let mut robot = robot_start;
    let mut steps = Vec::with_capacity(moves.len());
    for (m, base, handle) in moves {
        let (j, a, b) = (m.joint, state.q[m.joint.index()], m.to);
        forward_kinematics(model, &mut data, &state)?;
        let blocked = Blocked::from_grid(&occupancy(model, &data)?.inflate(problem.robot.radius)?);
        let cell = grid
            .cell_of(Point2::new(base[0], base[1]))
            .map(|(i, k)| k * grid.width() + i)
            .unwrap_or(robot);
        let path = blocked.distances(robot)[cell];
        let travel = if path.is_finite() {
            path * res
        } else {
            // The predicate only returns base cells in the start's free component, where the
            // robot also is; keep a finite lower bound should that ever not hold.
            let (p, q) = (
                grid.cell_center(robot % grid.width(), robot / grid.width()),
                grid.cell_center(cell % grid.width(), cell / grid.width()),
            );
            (p - q).norm()
        };
        let h = model.handle_id(handle)?;
        let traj = grasp_trajectory(
            model,
            &mut data,
            &state,
            h,
            j,
            a,
            b,
            settings.manipulation.steps,
        )?;
        let actuation = traj
            .windows(2)
            .map(|w| (w[1].position - w[0].position).norm())
            .sum::<f64>()
            .max(match model.joints()[j.index()].kind {
                JointKind::Prismatic => (b - a).abs(),
                JointKind::Revolute => 0.0,
            });
        let c = &settings.cost;
        steps.push(Step {
            joint: joint_name(model, j),
            from: a,
            to: b,
            handle: Some(handle.clone()),
            base: Some(*base),
            travel,
            cost: c.action + c.actuation * actuation + c.travel * travel,
        });
        state.q[j.index()] = b;
        robot = cell;
    }
    Ok(steps)
}

fn plan_of(steps: Vec<Step>) -> Plan {
    Plan {
        cost: steps.iter().map(|s| s.cost).sum(),
        steps,
    }
}

/// Goal joints a plan prefix leaves unmet.
fn unmet_after(model: &SceneModel, problem: &Problem, steps: &[Step]) -> Vec<String> {
    let mut state = problem.start.clone();
    for s in steps {
        if let Ok(j) = model.joint_id(&s.joint) {
            state.q[j.index()] = s.to;
        }
    }
    problem
        .goal
        .targets()
        .iter()
        .filter(|(j, t)| !t.contains(state.q[j.index()]))
        .map(|(j, _)| joint_name(model, *j))
        .collect()
}
