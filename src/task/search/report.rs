//! What a search returns other than a plan it just found: the incumbent, the partial plan of
//! a stopped search, and the reports of infeasibility (static and after exhaustion).

use std::collections::HashMap;

use super::pass::{Node, Recorded};
use crate::scene::collision::collisions;
use crate::scene::{JointId, SceneData, SceneModel, forward_kinematics};
use crate::task::Error;
use crate::task::check::{Caches, Checker};
use crate::task::goal::Problem;
use crate::task::heuristic::Heuristic;
use crate::task::plan::{
    Cause, Failure, Infeasibility, Outcome, Partial, Plan, PlanResult, ReachShortfall, SearchStats,
    Step,
};
use crate::task::settings::TaskSettings;

/// The anytime search's best plan so far.
pub(super) struct Incumbent {
    pub(super) steps: Vec<Step>,
    pub(super) cost: f64,
    /// The factor it is proven within.
    pub(super) factor: f64,
}

impl Incumbent {
    /// The incumbent as the search's result, proven within `factor`.
    pub(super) fn solved(self, factor: f64, mut stats: SearchStats) -> PlanResult {
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
pub(super) fn stopped(
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
pub(super) type Best = (usize, f64, Vec<Step>);

/// The report of a goal joint that no base pose can operate into its target (the `k`-th goal
/// target, as [`Heuristic::unreachable_targets`] found it).
pub(super) fn unreachable_target(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    heuristic: &Heuristic<'_>,
    k: usize,
    shortfall: Option<ReachShortfall>,
) -> Infeasibility {
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
        _ => match &shortfall {
            Some(s) => format!(
                ": e.g. moving it from {from:.4} to {:.4}: {s}",
                target.nearest(from)
            ),
            None => String::new(),
        },
    };
    Infeasibility {
        message: format!(
            "no plan in the lattice: no base pose can operate {name} into its target{reach}"
        ),
        unreached: vec![name.clone()],
        conflicts: vec![Failure {
            joint: name,
            from,
            to: target.nearest(from),
            cause: Cause::NoBasePose {
                shortfall: shortfall.map(Box::new),
            },
        }],
        start_collisions: Vec::new(),
    }
}

/// The partial plan of a stopped search: the steps to the closed state nearest the goal, and
/// the goal joints it leaves unmet.
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
pub(super) fn infeasibility(
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
        match &mut cause {
            Cause::PathBlocked { blockers } => {
                *blockers = checker.path_blockers(caches, data, &f.key, f.joint, f.to)?;
            }
            Cause::NoBasePose { shortfall } => {
                *shortfall = checker
                    .reach_shortfall(caches, data, &f.key, f.joint, f.to)?
                    .map(Box::new);
            }
            _ => {}
        }
        conflicts.push(Failure {
            joint: model.joints()[f.joint.index()].name.clone(),
            from: lattice.values(f.joint)[f.key[f.joint.index()] as usize],
            to: lattice.values(f.joint)[f.to as usize],
            cause,
        });
    }
    if conflicts.is_empty() {
        conflicts = pruned_conflicts(model, problem, checker, caches, data, nodes, &unreached)?;
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

/// The failures of the direct moves from the start (the first node closed) into the
/// `unreached` targets that have no base pose: when the search pruned every move into them by
/// its bound, without a check, so that no failure was recorded.
fn pruned_conflicts(
    model: &SceneModel,
    problem: &Problem,
    checker: &Checker<'_>,
    caches: &mut Caches,
    data: &mut SceneData,
    nodes: &[Node],
    unreached: &[JointId],
) -> Result<Vec<Failure>, Error> {
    let lattice = checker.lattice;
    let mut conflicts = Vec::new();
    let Some(start) = nodes.first().map(|n| &n.key) else {
        return Ok(conflicts);
    };
    for j in unreached {
        let Some(i) = problem.goal.target(*j) else {
            continue;
        };
        let from = lattice.values(*j)[start[j.index()] as usize];
        let Some(to) = lattice.index_of(*j, i.nearest(from)) else {
            continue;
        };
        let to = to as u16;
        if let Some(cause) = checker.no_base_pose(caches, data, start, *j, to)? {
            conflicts.push(Failure {
                joint: model.joints()[j.index()].name.clone(),
                from,
                to: lattice.values(*j)[to as usize],
                cause,
            });
        }
    }
    Ok(conflicts)
}
