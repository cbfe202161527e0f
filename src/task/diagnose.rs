//! Diagnosing an infeasible goal: which of its targets conflict.

use super::{Error, Goal, NoRefinement, Outcome, Problem, TaskSettings, Termination, plan};
use crate::scene::SceneModel;

/// A minimal set of goal targets that no plan meets together, by joint name, for an infeasible
/// `problem` with at least two targets; `None` with fewer targets, or if `termination` stops a
/// plan first.
///
/// Useful when [`plan`] answers `Infeasible` without naming an unreached joint: every target
/// is reachable on its own, so it is their combination that fails.
///
/// The deletion filter: for each target in turn, plan without it (and without the targets
/// dropped so far); if that is still infeasible, drop it. Every kept target `t` was kept
/// because the remaining targets without `t` had a plan, and that plan also meets any subset
/// of them: so dropping any one target of the result leaves a goal with a plan, while the
/// result itself has none (it is the input, or a set the planner found infeasible). It costs
/// one task search per target.
///
/// # Errors
/// As [`plan`].
pub fn conflicting_targets(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    termination: &Termination<'_>,
) -> Result<Option<Vec<String>>, Error> {
    let mut kept = problem.goal.targets().to_vec();
    if kept.len() < 2 {
        return Ok(None);
    }
    let mut k = 0;
    while k < kept.len() {
        let mut goal = Goal::empty();
        for (i, (joint, interval)) in kept.iter().enumerate() {
            if i != k {
                goal.set(model, *joint, *interval)?;
            }
        }
        let without = Problem {
            start: problem.start.clone(),
            goal,
            robot: problem.robot,
        };
        match plan(model, &without, settings, &NoRefinement, termination)?.outcome {
            Outcome::Infeasible(_) => {
                kept.remove(k);
            }
            Outcome::Solved(_) => k += 1,
            Outcome::Timeout(_) | Outcome::Cancelled(_) => return Ok(None),
        }
    }
    Ok(Some(
        kept.iter()
            .map(|(joint, _)| model.joints()[joint.index()].name.clone())
            .collect(),
    ))
}
