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

use std::collections::{HashMap, HashSet};
use std::time::Instant;

use nalgebra::Point2;

use super::lattice::Lattice;
use super::plan::{
    BodyName, Cause, Failure, Infeasibility, Outcome, Partial, Plan, PlanResult, SearchStats, Step,
};
use super::{Error, Feasibility, MoveCheck, Problem, TaskSettings, Termination};
use crate::scene::collision::geometry::WorldBox;
use crate::scene::collision::{Body, collisions};
use crate::scene::motion::grasp_trajectory;
use crate::scene::nav::occupancy;
use crate::scene::nav::search::Blocked;
use crate::scene::{
    BaseShapeId, JointId, JointKind, PartId, SceneData, SceneModel, State, forward_kinematics,
};

/// Configurations per part in the *Paper* planner's box precomputation.
const PAPER_CONFIGURATIONS: usize = 6;

/// How far the *Paper* planner's boxes follow a revolute joint (rad): 90°.
const PAPER_REVOLUTE_RANGE: f64 = std::f64::consts::FRAC_PI_2;

/// How far the *Paper* planner's boxes follow a prismatic joint (m): 15 cm.
const PAPER_PRISMATIC_RANGE: f64 = 0.15;

/// Conflicts kept in an [`Infeasibility`] report.
const MAX_CONFLICTS: usize = 32;

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

/// The *Random* baseline (see the module docs).
pub(crate) fn random(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    termination: &Termination<'_>,
    seed: u64,
) -> Result<PlanResult, Error> {
    let started = Instant::now();
    let lattice = Lattice::new(model, problem, &settings.lattice);
    let mut feasibility = Feasibility::new(model, problem, settings, &lattice)?;
    let robot_start = feasibility.checker.start_cell;
    let mut order = pending_moves(problem);
    SplitMix64(seed).shuffle(&mut order);
    let mut stats = SearchStats {
        samples: 1,
        ..SearchStats::default()
    };
    let mut key = start_key(model, problem, &lattice)?;
    let mut accepted = Vec::with_capacity(order.len());
    for (i, m) in order.iter().enumerate() {
        if termination.should_stop() {
            let steps = build_steps(model, problem, settings, robot_start, &accepted)?;
            stats.elapsed = started.elapsed();
            return Ok(PlanResult {
                outcome: Outcome::Timeout(Partial {
                    unmet: unmet_after(model, problem, &steps),
                    plan: plan_of(steps),
                }),
                stats,
            });
        }
        let to = lattice_index(&lattice, m.joint, m.to, i)?;
        stats.evaluated += 1;
        match feasibility.check(&key, m.joint, to)? {
            MoveCheck::Feasible { base, handle } => {
                accepted.push((*m, base, handle));
                key[m.joint.index()] = to;
            }
            MoveCheck::Infeasible(cause) => {
                let failure = Failure {
                    joint: joint_name(model, m.joint),
                    from: problem.start.q[m.joint.index()],
                    to: m.to,
                    cause,
                };
                let names: Vec<String> = order.iter().map(|m| joint_name(model, m.joint)).collect();
                stats.elapsed = started.elapsed();
                return Ok(PlanResult {
                    outcome: Outcome::Infeasible(Infeasibility {
                        message: format!(
                            "random order [{}] fails at step {i}: {failure}",
                            names.join(", ")
                        ),
                        unreached: names[i..].to_vec(),
                        conflicts: vec![failure],
                        start_collisions: start_collisions(model, problem, settings)?,
                    }),
                    stats,
                });
            }
        }
    }
    let steps = build_steps(model, problem, settings, robot_start, &accepted)?;
    stats.elapsed = started.elapsed();
    Ok(PlanResult {
        outcome: Outcome::Solved(plan_of(steps)),
        stats,
    })
}

/// The boxes of the parts of a subtree at one state (parts without colliders have none).
type Boxes = Vec<(PartId, WorldBox)>;

fn subtree_boxes(model: &SceneModel, data: &SceneData, root: PartId) -> Boxes {
    model.parts()[root.index()]
        .subtree()
        .filter_map(|p| {
            let world_from_part = data.world_from_parts()[p.index()];
            model.geometry.parts[p.index()]
                .iter()
                .map(|c| c.world_box(&world_from_part))
                .reduce(WorldBox::union)
                .map(|b| (p, b))
        })
        .collect()
}

/// The *Paper* planner's precomputed boxes for one goal joint.
struct PartBoxes {
    /// The 6 configurations: joint value and boxes.
    sweep: Vec<(f64, Boxes)>,
    /// Boxes at the start value and at the target.
    start: Boxes,
    end: Boxes,
}

/// The box test of the *Paper* planner.
struct BoxTest<'a> {
    model: &'a SceneModel,
    settings: &'a TaskSettings,
    moves: &'a [Move],
    parts: Vec<PartBoxes>,
}

impl<'a> BoxTest<'a> {
    fn new(
        model: &'a SceneModel,
        problem: &Problem,
        settings: &'a TaskSettings,
        moves: &'a [Move],
    ) -> Result<Self, Error> {
        let mut data = SceneData::new(model);
        let mut at = |joint: JointId, value: f64| -> Result<Boxes, Error> {
            let mut s: State = problem.start.clone();
            s.q[joint.index()] = value;
            forward_kinematics(model, &mut data, &s)?;
            Ok(subtree_boxes(model, &data, joint.part()))
        };
        let mut parts = Vec::with_capacity(moves.len());
        for m in moves {
            let j = &model.joints()[m.joint.index()];
            let a = problem.start.q[m.joint.index()];
            let range = match j.kind {
                JointKind::Revolute => PAPER_REVOLUTE_RANGE,
                JointKind::Prismatic => PAPER_PRISMATIC_RANGE,
            };
            let direction = if m.to < a { -1.0 } else { 1.0 };
            let mut sweep = Vec::with_capacity(PAPER_CONFIGURATIONS);
            for k in 0..PAPER_CONFIGURATIONS {
                let t = k as f64 / (PAPER_CONFIGURATIONS - 1) as f64;
                let v = j.limits.clamp(a + direction * t * range);
                sweep.push((v, at(m.joint, v)?));
            }
            parts.push(PartBoxes {
                sweep,
                start: at(m.joint, a)?,
                end: at(m.joint, m.to)?,
            });
        }
        Ok(BoxTest {
            model,
            settings,
            moves,
            parts,
        })
    }

    /// Whether the pair of parts is checked: not in one kinematic chain (neither is an
    /// ancestor of the other), not allowed.
    fn checked(&self, p: PartId, q: PartId) -> bool {
        let parts = self.model.parts();
        !parts[p.index()].subtree_contains(q)
            && !parts[q.index()].subtree_contains(p)
            && !self
                .settings
                .sweep
                .collision
                .allowed
                .is_allowed(Body::Part(p), Body::Part(q))
    }

    /// The first box conflict of moving `order[i]` with the moves `order[..i]` done: a box
    /// of the moving subtree overlapping a box of another manipulated part (base shapes are
    /// not checked, as in the paper).
    fn conflict(&self, order: &[usize], i: usize) -> Option<Failure> {
        let g = order[i];
        let root = self.moves[g].joint.part();
        let mut others: Vec<(PartId, WorldBox)> = Vec::new();
        for (pos, &h) in order.iter().enumerate() {
            if h == g {
                continue;
            }
            let boxes = if pos < i {
                &self.parts[h].end
            } else {
                &self.parts[h].start
            };
            others.extend(
                boxes
                    .iter()
                    .filter(|(q, _)| !self.model.parts()[root.index()].subtree_contains(*q)),
            );
        }
        for (value, boxes) in &self.parts[g].sweep {
            for (p, pb) in boxes {
                for (other, ob) in &others {
                    if self.checked(*p, *other) && pb.overlaps(ob) {
                        let m = self.moves[g];
                        return Some(Failure {
                            joint: joint_name(self.model, m.joint),
                            from: self.parts[g].sweep[0].0,
                            to: m.to,
                            cause: Cause::Collision {
                                moving: BodyName::of(self.model, Body::Part(*p)),
                                other: BodyName::of(self.model, Body::Part(*other)),
                                value: *value,
                            },
                        });
                    }
                }
            }
        }
        None
    }
}

/// `n!`, or `None` if it exceeds `u64`.
fn factorial(n: usize) -> Option<u64> {
    (1..=n as u64).try_fold(1u64, |acc, k| acc.checked_mul(k))
}

/// Settings under which the sweep check has no pair to check: [`Feasibility`] then decides
/// on the base pose and the robot's path only.
fn path_only(model: &SceneModel, settings: &TaskSettings) -> TaskSettings {
    let mut s = settings.clone();
    let allowed = &mut s.sweep.collision.allowed;
    let n = model.parts().len();
    for p in 0..n {
        for q in p + 1..n {
            allowed.allow(Body::Part(PartId(p)), Body::Part(PartId(q)));
        }
        for b in 0..model.base().shapes.len() {
            allowed.allow(Body::Part(PartId(p)), Body::Base(BaseShapeId(b)));
        }
    }
    s
}

/// The *Paper* planner (see the module docs).
pub(crate) fn paper(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    termination: &Termination<'_>,
    seed: u64,
) -> Result<PlanResult, Error> {
    let started = Instant::now();
    let lattice = Lattice::new(model, problem, &settings.lattice);
    let path_settings = path_only(model, settings);
    let mut feasibility = Feasibility::new(model, problem, &path_settings, &lattice)?;
    let robot_start = feasibility.checker.start_cell;
    let moves = pending_moves(problem);
    let boxes = BoxTest::new(model, problem, settings, &moves)?;
    let start = start_key(model, problem, &lattice)?;
    let targets: Vec<usize> = moves
        .iter()
        .enumerate()
        .map(|(i, m)| lattice_index(&lattice, m.joint, m.to, i))
        .collect::<Result<_, _>>()?;
    let total = factorial(moves.len());
    let mut rng = SplitMix64(seed);
    let mut stats = SearchStats::default();
    let mut tried: HashSet<Vec<usize>> = HashSet::new();
    // Path verdicts by (lattice state, goal index): the state after a prefix depends only
    // on which goal joints it moved.
    let mut memo: HashMap<(Vec<usize>, usize), MoveCheck> = HashMap::new();
    let mut conflicts: HashMap<(usize, String), (usize, Failure)> = HashMap::new();
    let mut best: Vec<Accepted> = Vec::new();
    let mut order: Vec<usize> = (0..moves.len()).collect();
    let finish = |outcome: Outcome, mut stats: SearchStats| {
        stats.elapsed = started.elapsed();
        PlanResult { outcome, stats }
    };
    loop {
        if total.is_some_and(|t| tried.len() as u64 >= t) {
            let why =
                every_order_rejected(model, problem, settings, &moves, tried.len(), conflicts)?;
            return Ok(finish(Outcome::Infeasible(why), stats));
        }
        if termination.should_stop() || stats.samples >= settings.max_samples {
            let steps = build_steps(model, problem, settings, robot_start, &best)?;
            let partial = Partial {
                unmet: unmet_after(model, problem, &steps),
                plan: plan_of(steps),
            };
            return Ok(finish(Outcome::Timeout(partial), stats));
        }
        rng.shuffle(&mut order);
        if !tried.insert(order.clone()) {
            continue;
        }
        stats.samples += 1;
        // Boxes first (cheap), then the robot's path step by step.
        let mut failure = (0..order.len()).find_map(|i| boxes.conflict(&order, i));
        let mut accepted = Vec::with_capacity(order.len());
        if failure.is_none() {
            let mut paths = OrderCheck {
                model,
                problem,
                moves: &moves,
                targets: &targets,
                feasibility: &mut feasibility,
                memo: &mut memo,
            };
            failure = paths.check(&order, &start, &mut accepted, &mut stats)?;
        }
        match failure {
            None => {
                let steps = build_steps(model, problem, settings, robot_start, &accepted)?;
                return Ok(finish(Outcome::Solved(plan_of(steps)), stats));
            }
            Some(f) => {
                if accepted.len() > best.len() {
                    best = accepted;
                }
                record_conflict(model, &moves, &mut conflicts, f);
            }
        }
    }
}

/// An accepted goal move: the move, the base pose it is made from (x, y, yaw) and the handle.
type Accepted = (Move, [f64; 3], String);

/// The robot-path check of one order of the goal moves, with the verdicts memoised by
/// (lattice state, goal index): the state after a prefix depends only on which goal joints it
/// moved.
struct OrderCheck<'a, 'f> {
    model: &'a SceneModel,
    problem: &'a Problem,
    moves: &'a [Move],
    targets: &'a [usize],
    feasibility: &'a mut Feasibility<'f>,
    memo: &'a mut HashMap<(Vec<usize>, usize), MoveCheck>,
}

impl OrderCheck<'_, '_> {
    /// Checks the moves of `order` in turn from the lattice state `start`, pushing the
    /// feasible ones to `accepted`; the first failure, if any.
    fn check(
        &mut self,
        order: &[usize],
        start: &[usize],
        accepted: &mut Vec<Accepted>,
        stats: &mut SearchStats,
    ) -> Result<Option<Failure>, Error> {
        let mut key = start.to_vec();
        for &g in order {
            let m = self.moves[g];
            let verdict = match self.memo.get(&(key.clone(), g)) {
                Some(v) => v.clone(),
                None => {
                    stats.evaluated += 1;
                    let v = self.feasibility.check(&key, m.joint, self.targets[g])?;
                    self.memo.insert((key.clone(), g), v.clone());
                    v
                }
            };
            match verdict {
                MoveCheck::Feasible { base, handle } => {
                    accepted.push((m, base, handle));
                    key[m.joint.index()] = self.targets[g];
                }
                MoveCheck::Infeasible(cause) => {
                    return Ok(Some(Failure {
                        joint: joint_name(self.model, m.joint),
                        from: self.problem.start.q[m.joint.index()],
                        to: m.to,
                        cause,
                    }));
                }
            }
        }
        Ok(None)
    }
}

/// Counts a rejected order's failure under (goal index, cause signature): box conflicts by
/// their bodies, path failures by their cause.
fn record_conflict(
    model: &SceneModel,
    moves: &[Move],
    conflicts: &mut HashMap<(usize, String), (usize, Failure)>,
    f: Failure,
) {
    let signature = match &f.cause {
        Cause::Collision { moving, other, .. } => format!("box {moving} {other}"),
        c => c.to_string(),
    };
    let index = moves
        .iter()
        .position(|m| joint_name(model, m.joint) == f.joint);
    conflicts
        .entry((index.unwrap_or(usize::MAX), signature))
        .and_modify(|(n, _)| *n += 1)
        .or_insert((1, f));
}

/// The *Paper* planner's verdict once every order was tried: the most frequent failures first.
fn every_order_rejected(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    moves: &[Move],
    tried: usize,
    conflicts: HashMap<(usize, String), (usize, Failure)>,
) -> Result<Infeasibility, Error> {
    let mut grouped: Vec<(usize, Failure)> = conflicts.into_values().collect();
    grouped.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.joint.cmp(&b.1.joint)));
    let conflicts: Vec<Failure> = grouped
        .into_iter()
        .take(MAX_CONFLICTS)
        .map(|(_, f)| f)
        .collect();
    let message = match conflicts.first() {
        Some(f) => {
            format!("every one of the {tried} orders of the goal joints is rejected; e.g. {f}")
        }
        None => "every order of the goal joints is rejected".into(),
    };
    let unreached = moves.iter().map(|m| joint_name(model, m.joint)).collect();
    Ok(Infeasibility {
        message,
        unreached,
        conflicts,
        start_collisions: start_collisions(model, problem, settings)?,
    })
}
