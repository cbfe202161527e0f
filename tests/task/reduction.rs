//! The search's partial-order reduction against its premise and its theorem
//! (`proofs/theories/Task/Reduction.v`).
//!
//! Scenes: generated kitchens (generators.rs) as they are, and the same kitchens with a
//! navigation band below the doors' bottom edge ([`DOOR_BOTTOM`] = 0.1 m; band 0.01–0.08 m:
//! a low robot base that passes under open doors), where no door blocks a floor cell, so the
//! interaction relation ([`Interaction`]) splits the joints into several components and the
//! reduction prunes. With the default band every door blocks floor cells when open and every
//! joint with a handle interacts with it (connectivity is global), so there is one component.
//!
//! - `pruned_moves_commute_on_generated_kitchens`: the premise `local` on the implementation:
//!   the verdict of [`Feasibility::check`] on a move of joint `j` (the whole verdict: feasible
//!   with the same base pose and handle, or infeasible with the same cause) is the same in two
//!   lattice states that agree on `j` and on every joint interacting with `j`, the other
//!   joints drawn at random. Travel cost 0, so the base pose chosen (the cheapest region
//!   cell) is part of the claim: equal costs for reordered plans (`interaction.rs`, "Costs").
//! - `reduced_search_agrees_with_exhaustive_enumeration`: `reduced_search_run_correct` on the
//!   implementation: with the reduction on (the default), [`plan`] returns `Solved` iff the
//!   unreduced enumeration of brute_force.rs reaches a goal state, every plan validates and
//!   (travel 0, A*) costs the enumeration's minimum; the reduction did prune on some of the
//!   instances (asserted over the seeds).

use kinscene::scene::SceneModel;
use kinscene::scene::nav::NavGridSettings;
use kinscene::task::{
    Feasibility, GoalSpec, Interaction, Lattice, NoRefinement, Outcome, Problem, TaskSettings,
    Termination, plan,
};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, TestRng, TestRunner};

use super::brute_force::{compare, joint_ids, key_of};
use super::generators::{DOOR_BOTTOM, Kitchen, Rng, instance, nav_settings};

/// `kitchen` with the navigation band 0.01–0.08 m, below every door's bottom edge.
fn low_band(kitchen: &Kitchen) -> Kitchen {
    const { assert!(DOOR_BOTTOM > 0.08, "the band must stay below the doors") };
    let mut b = kitchen.model.to_builder();
    b.nav_settings(NavGridSettings {
        min_height: 0.01,
        max_height: 0.08,
        ..nav_settings()
    });
    Kitchen {
        model: b.build().expect("the same scene with another band builds"),
        ..kitchen.clone()
    }
}

fn settings() -> TaskSettings {
    let mut s = TaskSettings::default();
    s.cost.travel = 0.0;
    s.lattice.interior_values = 0;
    s
}

/// Generated instances (kitchen, goal) from `seed`, deterministic.
fn instances(
    seed: u64,
    n: usize,
    parts: std::ops::RangeInclusive<usize>,
) -> Vec<(Kitchen, GoalSpec)> {
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(
            proptest::test_runner::RngAlgorithm::ChaCha,
            &[seed as u8; 32],
        ),
    );
    let strategy = instance(parts, 1..=4);
    (0..n)
        .map(|_| {
            strategy
                .new_tree(&mut runner)
                .expect("the generators do not reject")
                .current()
        })
        .collect()
}

/// The premise `local` on `model`/`problem`: for `samples` random (state, move) pairs, the
/// verdict is unchanged when every joint not interacting with the moved one is redrawn.
/// Returns how many pairs had at least one joint redrawn.
fn check_locality(model: &SceneModel, problem: &Problem, samples: usize, rng: &mut Rng) -> usize {
    let settings = settings();
    let lattice = Lattice::new(model, problem, &settings.lattice);
    let interaction = Interaction::new(model, problem, &settings).expect("valid instance");
    let mut feasibility =
        Feasibility::new(model, problem, &settings, &lattice).expect("valid instance");
    let ids = joint_ids(model);
    let n = ids.len();
    let sizes: Vec<usize> = ids.iter().map(|j| lattice.values(*j).len()).collect();
    let start = key_of(model, &lattice, &problem.start);
    let mut redrawn = 0;
    for _ in 0..samples {
        let j = ids[rng.below(n)];
        if sizes[j.index()] < 2 {
            continue;
        }
        // A random state near the start (each joint moved with probability 1/2).
        let state: Vec<usize> = (0..n)
            .map(|k| {
                if rng.below(2) == 0 {
                    start[k]
                } else {
                    rng.below(sizes[k])
                }
            })
            .collect();
        let mut to = rng.below(sizes[j.index()] - 1);
        if to >= state[j.index()] {
            to += 1;
        }
        let mut other = state.clone();
        let mut changed = false;
        for k in 0..n {
            if k != j.index() && !interaction.interacts(j, ids[k]) {
                other[k] = rng.below(sizes[k]);
                changed |= other[k] != state[k];
            }
        }
        let a = feasibility.check(&state, j, to).expect("indices in range");
        let b = feasibility.check(&other, j, to).expect("indices in range");
        assert_eq!(
            a, b,
            "joint {j:?} to {to}: verdict in {state:?} differs from {other:?}, which agrees \
             on every joint interacting with it"
        );
        redrawn += usize::from(changed);
    }
    redrawn
}

#[test]
fn pruned_moves_commute_on_generated_kitchens() {
    let mut rng = Rng::new(24);
    let (mut components, mut redrawn) = (0, 0);
    for (kitchen, spec) in instances(7, 6, 3..=5) {
        for k in [kitchen.clone(), low_band(&kitchen)] {
            let problem = Problem::from_spec(&k.model, &spec).expect("generated goals are valid");
            let i = Interaction::new(&k.model, &problem, &settings()).expect("valid instance");
            components += i.components() - 1;
            redrawn += check_locality(&k.model, &problem, 40, &mut rng);
        }
    }
    eprintln!("locality: {redrawn} samples redrew joints; {components} extra components");
    // The test means something only if joints were redrawn.
    assert!(
        redrawn > 10,
        "only {redrawn} samples redrew a joint ({components} extra components)"
    );
}

#[test]
fn reduced_search_agrees_with_exhaustive_enumeration() {
    let mut pruned = 0;
    for (kitchen, spec) in instances(11, 10, 2..=4) {
        let k = low_band(&kitchen);
        // The reduction prunes (or not) in the search `compare` runs; count it here.
        let problem = Problem::from_spec(&k.model, &spec).expect("generated goals are valid");
        // Without the dive, so that the rounds (where the reduction acts) run.
        let s = TaskSettings {
            dive: false,
            ..settings()
        };
        let i = Interaction::new(&k.model, &problem, &s).expect("valid instance");
        let result = plan(&k.model, &problem, &s, &NoRefinement, &Termination::none())
            .expect("valid instance");
        assert!(!matches!(result.outcome, Outcome::Timeout(_)));
        pruned += result.stats.pruned;
        eprintln!(
            "{} joints, {} components, {} goal joints: pruned {}, expanded {}",
            k.model.nq(),
            i.components(),
            spec.goal.len(),
            result.stats.pruned,
            result.stats.expanded
        );
        compare(&k, &spec, 0).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(
        pruned > 0,
        "the reduction pruned nothing on the low-band kitchens"
    );
}
