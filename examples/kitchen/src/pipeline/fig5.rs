//! The Fig. 5 attempts of one sequence in one run: Ours, Random and Oracle, their plan files
//! and the sequence's top view (run 0).

use std::collections::BTreeMap;
use std::time::Instant;

use kinscene::scene::SceneModel;

use super::PipelineError;
use super::config::Method;
use super::manipulation::{
    self, Attempt, Category, Translated, TrueGoal, Verdict, plan_and_execute,
};
use super::sequences::Sequence;
use super::session::Session;
use super::sim::SimWorld;
use super::summary::AttemptRow;
use super::svg;

/// Runs every selected method on sequence `q` in run `r`. `translated` is the goal on the
/// run's estimated model, or why it has none.
///
/// # Errors
/// Simulator resets and true-model problems that do not fit (contract violations).
pub fn attempts(
    s: &mut Session<'_>,
    world: &mut SimWorld,
    r: usize,
    q: &Sequence,
    goal: &TrueGoal,
    translated: &Result<Translated, String>,
    random_seed: u64,
) -> Result<(), PipelineError> {
    let truth = s.truth;
    for k in 0..s.methods.len() {
        let method = s.methods[k];
        s.ui.doing(format!("run {r}: {} / {}", q.name, method.name()));
        let t0 = Instant::now();
        let (attempt, drawn_on): (Attempt, Option<&SceneModel>) = match (method, translated) {
            (Method::Ours, Ok(t)) => {
                let (a, _) = plan_and_execute(
                    &s.planning,
                    world,
                    &t.model,
                    &t.problem,
                    goal,
                    &t.names,
                    None,
                )?;
                (a, Some(&t.model))
            }
            (Method::Random, Ok(t)) => (
                manipulation::random(&s.planning, world, t, goal, random_seed)?,
                Some(&t.model),
            ),
            (Method::Ours | Method::Random, Err(reason)) => (
                Attempt {
                    verdict: Verdict::failed(Category::Other, reason.clone()),
                    document: None,
                    plan: None,
                    execution: None,
                    trace: Vec::new(),
                },
                None,
            ),
            (Method::Oracle, _) => {
                let problem = goal.true_problem(truth)?;
                let names: BTreeMap<String, String> = truth
                    .joints()
                    .iter()
                    .map(|j| (j.name.clone(), j.name.clone()))
                    .collect();
                let (a, result) = plan_and_execute(
                    &s.planning,
                    world,
                    truth,
                    &problem,
                    goal,
                    &names,
                    s.oracle_cache.get(q.name),
                )?;
                if let Some(result) = result {
                    s.oracle_cache.entry(q.name.to_string()).or_insert(result);
                }
                (a, Some(truth))
            }
        };
        s.tick(&format!("fig5 {}", method.name()), t0);
        s.ui.say(format!(
            "  {} / {}: {}{}",
            q.name,
            method.name(),
            attempt.verdict.category.name(),
            if attempt.verdict.reason.is_empty() {
                String::new()
            } else {
                format!(" ({})", attempt.verdict.reason)
            }
        ));
        let stem = format!("run{r}-{}-{}", q.name, method.name().to_lowercase());
        s.outputs.add_attempt(&stem, &attempt);
        if r == 0 {
            top_view(s, q, goal, translated, method, &attempt, drawn_on)?;
        }
        s.report.fig5.push(AttemptRow {
            run: r,
            sequence: q.name.to_string(),
            method,
            verdict: attempt.verdict,
        });
        s.ui.done();
    }
    Ok(())
}

/// The sequence's top view: Ours' plan on the estimated model, or the Oracle's on the true
/// model when Ours has none.
fn top_view(
    s: &mut Session<'_>,
    q: &Sequence,
    goal: &TrueGoal,
    translated: &Result<Translated, String>,
    method: Method,
    attempt: &Attempt,
    model: Option<&SceneModel>,
) -> Result<(), PipelineError> {
    let file = format!("top-{}.svg", q.name);
    let wanted = match method {
        Method::Ours => true,
        Method::Oracle => !s.outputs.files.iter().any(|(f, _)| *f == file),
        Method::Random => false,
    };
    let (Some(plan), Some(model), true) = (&attempt.plan, model, wanted) else {
        return Ok(());
    };
    let start = match (method, translated) {
        (Method::Oracle, _) => goal.start_state(s.truth)?,
        (_, Ok(t)) => t.problem.start.clone(),
        (_, Err(_)) => model.zero_state(),
    };
    let title = format!(
        "{}: {} plan on the {} model, run 0, executed base trace dashed",
        q.name,
        method.name(),
        if method == Method::Oracle {
            "true"
        } else {
            "estimated"
        }
    );
    match svg::top_view(model, &start, Some(plan), &attempt.trace, &title) {
        Ok(svg) => s.outputs.add(file, svg),
        Err(e) => s.report.notes.push(format!(
            "the top view of {} could not be drawn: {e}",
            q.name
        )),
    }
    Ok(())
}
