//! The *Paper* baseline: random orders of the goal moves, rejected by overlapping part boxes
//! or a blocked robot path.

use std::collections::{HashMap, HashSet};
use std::time::Instant;

use crate::scene::collision::Body;
use crate::scene::collision::geometry::WorldBox;
use crate::scene::{
    BaseShapeId, JointId, JointKind, PartId, SceneData, SceneModel, State, forward_kinematics,
};
use crate::task::lattice::Lattice;
use crate::task::plan::{
    BodyName, Cause, Failure, Infeasibility, Outcome, Partial, PlanResult, SearchStats,
};
use crate::task::{Error, Feasibility, MoveCheck, Problem, TaskSettings, Termination};

use super::{
    Move, SplitMix64, build_steps, joint_name, lattice_index, pending_moves, plan_of,
    start_collisions, start_key, unmet_after,
};

/// Configurations per part in the *Paper* planner's box precomputation.
const PAPER_CONFIGURATIONS: usize = 6;

/// How far the *Paper* planner's boxes follow a revolute joint (rad): 90°.
const PAPER_REVOLUTE_RANGE: f64 = std::f64::consts::FRAC_PI_2;

/// How far the *Paper* planner's boxes follow a prismatic joint (m): 15 cm.
const PAPER_PRISMATIC_RANGE: f64 = 0.15;

/// Conflicts kept in an [`Infeasibility`] report.
const MAX_CONFLICTS: usize = 32;

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
