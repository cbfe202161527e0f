//! The hierarchical interface: scripted refiners (closures) veto moves; the search records
//! the vetoes, counts them and returns a different plan or an infeasibility naming them.
//!
//! Scenes are those of `cases.rs`: the dead-end corridor with doors `b` (deep) and `a` (near
//! the open end), and the dishwasher room.

use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use kinscene::scene::{SceneModel, State};
use kinscene::task::{
    Cause, MoveContext, NoRefinement, Outcome, PlanResult, Problem, Refinement, Refiner,
    TaskSettings, Termination, plan,
};

use super::cases::{
    CORRIDOR_ROBOT, OPEN, ROBOT_MIDDLE, blank, corridor, door_unit, joints_of, problem, run,
    settings, solved, south_kitchen,
};
use super::generators::{Hinge, Rack, Unit, UnitKind};

fn run_with(
    model: &SceneModel,
    p: &Problem,
    s: &TaskSettings,
    refiner: &dyn Refiner,
) -> PlanResult {
    plan(model, p, s, refiner, &Termination::none()).expect("valid input")
}

/// A 3.6 m square room with one door `a` on [1.5, 2.1] of the south run (hinged `Right`),
/// robot in the middle: nothing but the door itself limits it.
fn one_door_room() -> SceneModel {
    south_kitchen(
        3.6,
        3.6,
        &[
            ("l", blank(1.5)),
            ("a", door_unit(0.6, Hinge::Right)),
            ("r", blank(1.5)),
        ],
        |_, _| {},
    )
}

fn joint_name<'a>(ctx: &MoveContext<'a>) -> &'a str {
    &ctx.model.joints()[ctx.joint.index()].name
}

fn value(ctx: &MoveContext<'_>, joint: &str) -> f64 {
    ctx.state.value_by_name(ctx.model, joint).unwrap()
}

fn veto(reason: &str, blockers: Option<Vec<kinscene::scene::PartId>>) -> Refinement {
    Refinement::Veto {
        reason: reason.into(),
        blockers,
    }
}

/// Every move of the goal joint is vetoed, and the refiner says no other part matters
/// (`Some(vec![])`): infeasible after one round, the conflict carries the refiner's reason,
/// and the search counted each veto.
#[test]
fn vetoing_every_move_of_the_goal_joint_is_infeasible_with_the_reason() {
    let model = corridor(false);
    let p = problem(
        &model,
        &format!("[goal]\na_door_hinge = {{ min = {OPEN} }}\n{CORRIDOR_ROBOT}"),
    );
    let calls = AtomicUsize::new(0);
    let refiner = |ctx: &MoveContext<'_>| {
        if joint_name(ctx) == "a_door_hinge" {
            calls.fetch_add(1, Ordering::Relaxed);
            veto("no IK solution for a_door_handle", Some(Vec::new()))
        } else {
            Refinement::Accept
        }
    };
    let r = run_with(&model, &p, &settings(1), &refiner);
    let Outcome::Infeasible(why) = &r.outcome else {
        panic!("expected infeasible, got {:#?}", r.outcome)
    };
    assert!(
        why.conflicts.iter().any(|f| f.joint == "a_door_hinge"
            && f.cause
                == Cause::Vetoed {
                    reason: "no IK solution for a_door_handle".into()
                }),
        "{why:#?}"
    );
    let n = calls.load(Ordering::Relaxed);
    assert!(n >= 1);
    assert_eq!(r.stats.vetoes, n, "every veto is counted");
    assert_eq!(r.stats.rounds, 1, "no blocker named: no second round");
}

/// Door `a` of [`one_door_room`] (goal ≥ 1.178 rad, lattice {0, π/4, 1.178, π/2} with one
/// interior value) opens in one step without refinement. A refiner vetoing "0 → beyond 1 rad" (say, the arm cannot
/// follow the long arc) leaves the two-step opening through π/4 as the cheapest plan.
#[test]
fn vetoed_direct_opening_gives_a_two_step_plan() {
    let model = one_door_room();
    let p = problem(
        &model,
        &format!("[goal]\na_door_hinge = {{ min = {OPEN} }}\n{ROBOT_MIDDLE}"),
    );
    let s = settings(1);
    let free = solved(&model, &p, &s, &run(&model, &p, &s));
    assert_eq!(free.steps.len(), 1);
    let vetoed = |ctx: &MoveContext<'_>| {
        joint_name(ctx) == "a_door_hinge" && ctx.from == 0.0 && ctx.to >= 1.0
    };
    let calls = AtomicUsize::new(0);
    let refiner = |ctx: &MoveContext<'_>| {
        if vetoed(ctx) {
            calls.fetch_add(1, Ordering::Relaxed);
            veto("arc too long", Some(Vec::new()))
        } else {
            Refinement::Accept
        }
    };
    let r = run_with(&model, &p, &s, &refiner);
    let plan = solved(&model, &p, &s, &r);
    assert_ne!(plan, free);
    assert_eq!(
        joints_of(&plan),
        ["a_door_hinge", "a_door_hinge"],
        "{plan:#?}"
    );
    assert!((plan.steps[0].to - FRAC_PI_4).abs() < 1e-12, "{plan:#?}");
    assert!(plan.steps.iter().all(|s| !(s.from == 0.0 && s.to >= 1.0)));
    assert!(calls.load(Ordering::Relaxed) >= 1);
    assert_eq!(r.stats.vetoes, calls.load(Ordering::Relaxed));
}

/// The refiner vetoes opening `a` while `b` is closed and names `b`'s part as the cause
/// ("the arm needs `b` out of the way"). `b` is not a goal joint: the first round has only
/// `a`; the named blocker joins the second, and the plan moves `b` first.
#[test]
fn veto_naming_a_blocker_adds_it_to_the_search() {
    let model = corridor(false);
    let b_part = model.part_id("b_door").unwrap();
    let p = problem(
        &model,
        &format!("[goal]\na_door_hinge = {{ min = {OPEN} }}\n{CORRIDOR_ROBOT}"),
    );
    let s = settings(0);
    let calls = AtomicUsize::new(0);
    let refiner = |ctx: &MoveContext<'_>| {
        if joint_name(ctx) == "a_door_hinge" && value(ctx, "b_door_hinge") == 0.0 {
            calls.fetch_add(1, Ordering::Relaxed);
            veto("arm path blocked by b_door", Some(vec![b_part]))
        } else {
            Refinement::Accept
        }
    };
    let r = run_with(&model, &p, &s, &refiner);
    let plan = solved(&model, &p, &s, &r);
    assert_eq!(
        joints_of(&plan),
        ["b_door_hinge", "a_door_hinge"],
        "{plan:#?}"
    );
    assert_eq!(r.stats.rounds, 2);
    assert_eq!(r.stats.vetoes, calls.load(Ordering::Relaxed));
}

/// `blockers: None` ("unknown") lets every joint move in the next round; the search still
/// finishes. Here the first two calls are vetoed: round 1 (only `a` active) has exactly two
/// moves out of the start ({0, 1.178, π/2} with no interior value), both vetoed; round 2
/// (all joints) does not ask again about those moves (verdicts are cached per state and
/// move), so it opens `a` from another state: after moving `b`.
#[test]
fn unknown_blockers_let_the_search_finish() {
    let model = corridor(false);
    let p = problem(
        &model,
        &format!("[goal]\na_door_hinge = {{ min = {OPEN} }}\n{CORRIDOR_ROBOT}"),
    );
    let s = settings(0);
    let calls = AtomicUsize::new(0);
    let refiner = |_: &MoveContext<'_>| {
        if calls.fetch_add(1, Ordering::Relaxed) < 2 {
            veto("transient", None)
        } else {
            Refinement::Accept
        }
    };
    let r = run_with(&model, &p, &s, &refiner);
    let plan = solved(&model, &p, &s, &r);
    assert_eq!(joints_of(&plan), ["b_door_hinge", "a_door_hinge"]);
    assert_eq!(r.stats.vetoes, 2);
    assert_eq!(r.stats.rounds, 2);
}

/// With a single joint every joint is already active: vetoes with unknown blockers cannot
/// grow the search, which ends `Infeasible` with the veto as the cause (vetoes are taken as
/// properties of the state and move, so they are not retried).
#[test]
fn unknown_blockers_with_every_joint_active_end_infeasible() {
    let model = one_door_room();
    let p = problem(
        &model,
        &format!("[goal]\na_door_hinge = {{ min = {OPEN} }}\n{ROBOT_MIDDLE}"),
    );
    let refiner = |_: &MoveContext<'_>| veto("transient", None);
    let r = run_with(&model, &p, &settings(0), &refiner);
    let Outcome::Infeasible(why) = &r.outcome else {
        panic!("expected infeasible, got {:#?}", r.outcome)
    };
    assert!(
        why.conflicts
            .iter()
            .all(|f| matches!(f.cause, Cause::Vetoed { .. })),
        "{why:#?}"
    );
    assert_eq!(r.stats.rounds, 1);
}

/// The refiner is consulted for every move the plan makes, with the state before it, the
/// base pose and handle the plan reports, and where the robot comes from: the start (its
/// cell centre) for the first step, the previous step's base afterwards.
#[test]
fn refiner_sees_the_moves_of_the_plan() {
    let model = corridor(true);
    let p = problem(
        &model,
        &format!(
            "[goal]\na_door_hinge = {{ min = {OPEN} }}\nb_door_hinge = {{ min = {OPEN} }}\n\
             [start]\na_door_hinge = {FRAC_PI_2}\n{CORRIDOR_ROBOT}"
        ),
    );
    let s = settings(0);
    type Seen = (String, Vec<f64>, f64, f64, [f64; 3], String, [f64; 2]);
    let seen: Mutex<Vec<Seen>> = Mutex::new(Vec::new());
    let refiner = |ctx: &MoveContext<'_>| {
        let handle = ctx.model.handle(ctx.handle).unwrap().name.clone();
        seen.lock().unwrap().push((
            joint_name(ctx).to_string(),
            ctx.state.as_slice().to_vec(),
            ctx.from,
            ctx.to,
            ctx.base,
            handle,
            ctx.robot_from,
        ));
        Refinement::Accept
    };
    let r = run_with(&model, &p, &s, &refiner);
    let plan = solved(&model, &p, &s, &r);
    assert_eq!(plan.steps.len(), 3);
    let seen = seen.into_inner().unwrap();
    let mut state: State = p.start.clone();
    let mut robot = [2.25, 3.8];
    for (i, step) in plan.steps.iter().enumerate() {
        let m = seen
            .iter()
            .find(|(j, q, from, to, base, handle, _)| {
                *j == step.joint
                    && q == state.as_slice()
                    && *from == step.from
                    && *to == step.to
                    && Some(*base) == step.base
                    && Some(handle) == step.handle.as_ref()
            })
            .unwrap_or_else(|| panic!("step {i} was not refined as planned: {step:?}"));
        let [x, y] = m.6;
        // The start is snapped to its cell centre (half a 5 cm cell per axis).
        let tol = if i == 0 { 0.025 + 1e-9 } else { 1e-9 };
        assert!(
            (x - robot[0]).abs() <= tol && (y - robot[1]).abs() <= tol,
            "step {i}: robot from {:?}, expected {robot:?}",
            m.6
        );
        robot = [step.base.unwrap()[0], step.base.unwrap()[1]];
        state.set_by_name(&model, &step.joint, step.to).unwrap();
    }
    // Closing `a` with the robot at the open end uses the back handle (the front one faces
    // the dead end while `a` is open).
    assert_eq!(plan.steps[0].handle.as_deref(), Some("a_door_back_handle"));
    assert_eq!(plan.steps[2].handle.as_deref(), Some("a_door_handle"));
}

/// "The search calls `refine` at most once per (state, move)" (the `Refiner` docs). A
/// dishwasher (basket goal, needs the door: 2 rounds) next to a door `x` (goal: open): `x`'s
/// moves are feasible and refined in round 1, and the search must not ask again about the
/// same state and move in round 2.
#[test]
fn refine_is_called_at_most_once_per_state_and_move() {
    let dw = Unit {
        kind: UnitKind::Dishwasher { rack: Rack::OnBase },
        width: 0.6,
    };
    let model = south_kitchen(
        3.6,
        3.6,
        &[
            ("l", blank(1.0)),
            ("dw", dw),
            ("x", door_unit(0.6, Hinge::Right)),
            ("r", blank(1.4)),
        ],
        |_, _| {},
    );
    let p = problem(
        &model,
        &format!(
            "[goal]\ndw_rack_slide = {{ min = 0.3 }}\nx_door_hinge = {{ min = {OPEN} }}\n{ROBOT_MIDDLE}"
        ),
    );
    let s = settings(0);
    let calls: Mutex<HashMap<String, usize>> = Mutex::new(HashMap::new());
    let refiner = |ctx: &MoveContext<'_>| {
        let key = format!("{:?} {} {}", ctx.state.as_slice(), joint_name(ctx), ctx.to);
        *calls.lock().unwrap().entry(key).or_default() += 1;
        Refinement::Accept
    };
    let r = run_with(&model, &p, &s, &refiner);
    solved(&model, &p, &s, &r);
    assert_eq!(r.stats.rounds, 2, "the door joins in a second round");
    let calls = calls.into_inner().unwrap();
    let repeated: Vec<_> = calls.iter().filter(|(_, n)| **n > 1).collect();
    assert!(repeated.is_empty(), "refined more than once: {repeated:?}");
}

/// A veto that depends on the base pose the task level chose: opening `a` (of
/// [`one_door_room`], one interior value) from the base pose the unrefined plan uses, or any
/// west of it, is vetoed. The search cannot pick another base pose for the same state and
/// move; it returns a plan whose opening moves of `a` use bases further east, or
/// `Infeasible` with the veto as a cause.
#[test]
fn base_pose_veto_gives_another_plan_or_a_vetoed_infeasibility() {
    let model = one_door_room();
    let p = problem(
        &model,
        &format!("[goal]\na_door_hinge = {{ min = {OPEN} }}\n{ROBOT_MIDDLE}"),
    );
    let s = settings(1);
    let free = solved(&model, &p, &s, &run(&model, &p, &s));
    let x0 = free.steps[0].base.unwrap()[0];
    let limit = x0 + 0.01;
    let calls = AtomicUsize::new(0);
    let refiner = |ctx: &MoveContext<'_>| {
        if joint_name(ctx) == "a_door_hinge" && ctx.to > ctx.from && ctx.base[0] < limit {
            calls.fetch_add(1, Ordering::Relaxed);
            veto("no base placement west of the limit", Some(Vec::new()))
        } else {
            Refinement::Accept
        }
    };
    let r = run_with(&model, &p, &s, &refiner);
    assert!(calls.load(Ordering::Relaxed) >= 1);
    assert_eq!(r.stats.vetoes, calls.load(Ordering::Relaxed));
    match &r.outcome {
        Outcome::Solved(_) => {
            let plan = solved(&model, &p, &s, &r);
            assert!(
                plan.steps
                    .iter()
                    .filter(|s| s.joint == "a_door_hinge" && s.to > s.from)
                    .all(|s| s.base.unwrap()[0] >= limit)
            );
        }
        Outcome::Infeasible(why) => assert!(
            why.conflicts
                .iter()
                .any(|f| matches!(f.cause, Cause::Vetoed { .. })),
            "{why:#?}"
        ),
        Outcome::Timeout(_) | Outcome::Cancelled(_) => panic!("no budget was set"),
    }
}

/// The same kind of veto when the goal has two joints that are each reachable alone (`a`
/// and `b` of the corridor; `a`'s opening vetoed from the base pose the unrefined plan uses
/// or any west of it): if the verdict is `Infeasible`, the report must still say why — the
/// issue: "`Infeasible(reason)` — which goal joints conflict, which part blocks which path
/// or sweep".
#[test]
fn vetoed_infeasibility_with_two_goal_joints_names_the_veto() {
    let model = corridor(false);
    let p = problem(
        &model,
        &format!(
            "[goal]\na_door_hinge = {{ min = {OPEN} }}\nb_door_hinge = {{ min = {OPEN} }}\n{CORRIDOR_ROBOT}"
        ),
    );
    let s = settings(1);
    let free = solved(&model, &p, &s, &run(&model, &p, &s));
    let x0 = free
        .steps
        .iter()
        .find(|s| s.joint == "a_door_hinge")
        .unwrap()
        .base
        .unwrap()[0];
    let refiner = |ctx: &MoveContext<'_>| {
        if joint_name(ctx) == "a_door_hinge" && ctx.to > ctx.from && ctx.base[0] < x0 + 0.01 {
            veto("no base placement west of the limit", Some(Vec::new()))
        } else {
            Refinement::Accept
        }
    };
    let r = run_with(&model, &p, &s, &refiner);
    if let Outcome::Infeasible(why) = &r.outcome {
        assert!(
            why.conflicts
                .iter()
                .any(|f| matches!(f.cause, Cause::Vetoed { .. })),
            "the report names no veto: {why:#?}"
        );
    }
}

/// `NoRefinement` and an accept-all closure give the same result.
#[test]
fn accepting_refiner_changes_nothing() {
    let model = corridor(false);
    let p = problem(
        &model,
        &format!(
            "[goal]\na_door_hinge = {{ min = {OPEN} }}\nb_door_hinge = {{ min = {OPEN} }}\n{CORRIDOR_ROBOT}"
        ),
    );
    let s = settings(1);
    let a = run_with(&model, &p, &s, &NoRefinement);
    let b = run_with(&model, &p, &s, &|_: &MoveContext<'_>| Refinement::Accept);
    assert_eq!(a.outcome, b.outcome);
    assert_eq!(b.stats.vetoes, 0);
}
