//! The anytime passes (src/task/mod.rs, "Anytime"; `TaskSettings::first_pass_weight`) on
//! generated kitchens with base travel in the cost, where the first pass's plan is often not
//! yet proven minimal.
//!
//! Deterministic instances (one `TestRunner::deterministic` stream of
//! `generators::instance(3..=5, 2..=4)`), each planned three ways without a budget: one pass
//! at `w = 2` (the first pass alone), the default (a first pass at 2, then 1 below the
//! incumbent), and one pass at `w = 1`. What must hold, by the docs: the same verdict all
//! three ways (completeness does not depend on the order); every plan validates; the
//! default's plan costs no more than the first pass's (the second pass only accepts cheaper
//! plans) and, run to the end, is proven minimal (`suboptimality` 1, within the focal bound
//! `w = 1`); one pass at 2 reports a factor of at most 2. And a cancel flag raised during the
//! second pass returns the first pass's plan as `Solved`, with a factor in `[1, 2]`.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use kinscene::task::{
    MoveContext, NoRefinement, Outcome, PlanResult, Problem, Refinement, TaskSettings, Termination,
    plan, validate,
};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::TestRunner;

use super::generators::{Kitchen, instance};

fn with_weights(first: f64, w: f64) -> TaskSettings {
    let s = TaskSettings {
        heuristic_weight: w,
        first_pass_weight: first,
        // The passes alone (the dive's incumbent changes what the first pass returns).
        dive: false,
        ..TaskSettings::default()
    };
    assert!(s.cost.travel > 0.0, "the default cost has base travel");
    s
}

fn solve(k: &Kitchen, p: &Problem, s: &TaskSettings) -> PlanResult {
    plan(&k.model, p, s, &NoRefinement, &Termination::none()).expect("plan")
}

fn cost(r: &PlanResult) -> Option<f64> {
    match &r.outcome {
        Outcome::Solved(p) => Some(p.cost),
        Outcome::Infeasible(_) => None,
        Outcome::Timeout(_) | Outcome::Cancelled(_) => panic!("timeout without a budget"),
    }
}

fn instances(n: usize) -> Vec<(Kitchen, Problem)> {
    let mut runner = TestRunner::deterministic();
    let strategy = instance(3..=5, 2..=4);
    let mut out = Vec::new();
    while out.len() < n {
        let (kitchen, spec) = strategy.new_tree(&mut runner).expect("strategy").current();
        if let Ok(problem) = Problem::from_spec(&kitchen.model, &spec) {
            out.push((kitchen, problem));
        }
    }
    out
}

#[test]
fn the_second_pass_proves_or_improves_the_first_plan() {
    let mut second_passes = 0;
    let mut improved = 0;
    for (i, (k, p)) in instances(16).iter().enumerate() {
        let first = solve(k, p, &with_weights(2.0, 2.0));
        let any = solve(k, p, &with_weights(2.0, 1.0));
        let astar = solve(k, p, &with_weights(1.0, 1.0));
        let (c1, c, ca) = (cost(&first), cost(&any), cost(&astar));
        assert_eq!(c1.is_some(), c.is_some(), "#{i}: verdicts differ");
        assert_eq!(ca.is_some(), c.is_some(), "#{i}: verdicts differ");
        assert_eq!(first.stats.passes, 1, "#{i}");
        let (Some(c1), Some(c)) = (c1, c) else {
            assert!(any.stats.suboptimality.is_none(), "#{i}");
            continue;
        };
        for (what, r) in [("first pass", &first), ("default", &any), ("A*", &astar)] {
            let Outcome::Solved(plan) = &r.outcome else {
                unreachable!()
            };
            let v = validate(&k.model, p, &plan.steps, &TaskSettings::default()).unwrap();
            assert!(v.valid, "#{i} {what}: {v:?}");
        }
        let f1 = first
            .stats
            .suboptimality
            .expect("a solved plan has a factor");
        assert!(
            (1.0..=2.0 + 1e-9).contains(&f1),
            "#{i}: first pass factor {f1}"
        );
        assert!(c <= c1 + 1e-9, "#{i}: default {c} > first pass {c1}");
        assert_eq!(any.stats.suboptimality, Some(1.0), "#{i}");
        assert!(any.stats.first_plan.is_some(), "#{i}");
        if any.stats.passes == 2 {
            second_passes += 1;
            if c < c1 - 1e-9 {
                improved += 1;
            }
        } else {
            assert_eq!(any.stats.passes, 1, "#{i}");
            // One pass: the first plan was proven within `w = 1` already.
            assert!(f1 <= 1.0 + 1e-9, "#{i}: one pass but factor {f1}");
        }
    }
    eprintln!("anytime: {second_passes} of 16 instances needed a second pass, {improved} improved");
    assert!(second_passes > 0, "no instance exercised the second pass");
}

#[test]
fn a_cancel_during_the_second_pass_returns_the_first_plan() {
    // The first instance whose default run needs a second pass that consults the refiner.
    for (i, (k, p)) in instances(16).iter().enumerate() {
        // Refiner calls of the first pass alone (deterministic: the prefetch only fills the
        // sweep memo).
        let calls = AtomicUsize::new(0);
        let count = |_: &MoveContext<'_>| {
            calls.fetch_add(1, Ordering::Relaxed);
            Refinement::Accept
        };
        let first = plan(
            &k.model,
            p,
            &with_weights(2.0, 2.0),
            &count,
            &Termination::none(),
        )
        .unwrap();
        let Outcome::Solved(first_plan) = &first.outcome else {
            continue;
        };
        let n1 = calls.load(Ordering::Relaxed);
        // The same run with a second pass, cancelled at its first new refiner call.
        let flag = AtomicBool::new(false);
        let calls = AtomicUsize::new(0);
        let cancel = |_: &MoveContext<'_>| {
            if calls.fetch_add(1, Ordering::Relaxed) >= n1 {
                flag.store(true, Ordering::Relaxed);
            }
            Refinement::Accept
        };
        let r = plan(
            &k.model,
            p,
            &with_weights(2.0, 1.0),
            &cancel,
            &Termination::none().with_cancel(&flag),
        )
        .unwrap();
        if r.stats.passes < 2 || !flag.load(Ordering::Relaxed) {
            continue;
        }
        let Outcome::Solved(got) = &r.outcome else {
            panic!("#{i}: cancelled after a first plan, got {:?}", r.outcome);
        };
        assert_eq!(
            got.steps, first_plan.steps,
            "#{i}: not the first pass's plan"
        );
        let f = r.stats.suboptimality.expect("factor");
        assert!((1.0..=2.0 + 1e-9).contains(&f), "#{i}: factor {f}");
        return;
    }
    panic!("no instance cancelled during a second pass");
}

/// The greedy dive (`TaskSettings::dive`, on by default) changes neither the verdict nor the
/// minimum: with and without it, run to the end at `w = 1`, every instance gets the same
/// verdict and the same cost (A* below the dive's incumbent still proves minimality), every
/// plan validates, and at `w = 2` a plan the dive returns at once is proven within 2. The
/// instances are small generated kitchens where the dive finds a plan on most of them.
#[test]
fn the_dive_keeps_verdicts_and_minimal_costs() {
    let mut dived = 0;
    for (i, (k, p)) in instances(16).iter().enumerate() {
        let astar = solve(k, p, &with_weights(1.0, 1.0));
        let with_dive = TaskSettings {
            dive: true,
            ..with_weights(2.0, 1.0)
        };
        let d = solve(k, p, &with_dive);
        let quick = solve(
            k,
            p,
            &TaskSettings {
                dive: true,
                ..with_weights(2.0, 2.0)
            },
        );
        assert_eq!(cost(&d).is_some(), cost(&astar).is_some(), "#{i}");
        assert_eq!(cost(&quick).is_some(), cost(&astar).is_some(), "#{i}");
        let (Some(c), Some(ca), Some(cq)) = (cost(&d), cost(&astar), cost(&quick)) else {
            continue;
        };
        assert!((c - ca).abs() <= 1e-9 * ca.max(1.0), "#{i}: {c} vs A* {ca}");
        assert_eq!(d.stats.suboptimality, Some(1.0), "#{i}");
        assert!(cq <= 2.0 * ca + 1e-9, "#{i}: {cq} > 2 x {ca}");
        let f = quick.stats.suboptimality.expect("factor");
        assert!((1.0..=2.0 + 1e-9).contains(&f), "#{i}: factor {f}");
        assert!(cq <= f * ca + 1e-9, "#{i}: {cq} not within {f} of {ca}");
        for r in [&d, &quick] {
            let Outcome::Solved(plan) = &r.outcome else {
                unreachable!()
            };
            let v = validate(&k.model, p, &plan.steps, &TaskSettings::default()).unwrap();
            assert!(v.valid, "#{i}: {v:?}");
        }
        if d.stats.greedy_first_plan {
            dived += 1;
        }
    }
    eprintln!("dive: first plan on {dived} of 16 instances");
    assert!(dived > 0, "the dive found no plan on any instance");
}
