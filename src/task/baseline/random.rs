//! The *Random* baseline: one seeded random order of the goal moves, checked by the search's
//! own feasibility predicate.

use std::time::Instant;

use crate::scene::SceneModel;
use crate::task::lattice::Lattice;
use crate::task::plan::{Failure, Infeasibility, Outcome, Partial, PlanResult, SearchStats};
use crate::task::{Error, Feasibility, MoveCheck, Problem, TaskSettings, Termination};

use super::{
    SplitMix64, build_steps, joint_name, lattice_index, pending_moves, plan_of, start_collisions,
    start_key, unmet_after,
};

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
