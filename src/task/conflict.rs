//! Static proofs of infeasibility, tried before the search: two goal parts (or a goal part
//! and the base) that collide in every goal state of the lattice.
//!
//! **Claim.** Let bodies `A` and `B` be a checked pair (a part and another part or a base
//! shape) such that every joint placing them (the part's joint and its ancestors', for each
//! part of the pair) is a goal joint, they collide at every combination of those joints'
//! lattice values inside their targets, and they do not collide at the start. Then no plan
//! in the lattice reaches the goal.
//!
//! **Why.** Every move of a plan is certified by the sweep check, which covers the moving
//! subtree against every body outside it over the closed interval of the motion, end value
//! included. The relative pose of `A` and `B` changes only when a joint that places exactly
//! one of them moves (a common ancestor moves both rigidly), and such a move has exactly one
//! of them in its moving subtree. In the final (goal) state the pair collides, so its
//! relative pose differs from the start's (where it does not), so some move changed it; after
//! the last such move the relative pose no longer changes, so the pair collides at that
//! move's end value, where the certified sweep says it does not.
//!
//! **Machine-checked.** `proofs/theories/Task/Conflict.v` (`static_conflict_sound`) proves the
//! claim over an abstract model of the scene, with three premises: a feasible move of joint `j`
//! leaves no pair with exactly one body in `j`'s moving subtree colliding at its end value (the
//! certified sweep); whether a pair collides depends only on the joints that place exactly one
//! of its bodies; a goal state has every goal joint inside its target.

use super::check::{Checker, SweepVerdict};
use super::goal::Problem;
use super::lattice::Lattice;
use super::plan::{BodyName, Cause, Failure, Infeasibility};
use super::{Error, Termination};
use crate::scene::collision::{Body, Contact, collisions};
use crate::scene::{JointId, PartId, SceneData, SceneModel, State, forward_kinematics};

/// Value combinations tried per candidate pair before giving up on it.
const MAX_COMBINATIONS: usize = 64;

/// The first pair of bodies that collides in every goal state (see the module docs), as an
/// [`Infeasibility`]; `None` if no such pair is found. Only pairs colliding in the state
/// "every goal joint at the point of its target nearest its start value" are candidates.
///
/// The reported conflict is the sweep check's verdict on moving the pair's part's joint
/// from its start value straight to that target point (where the contact first occurs),
/// when it finds one. Returns `None` early when `termination` says stop.
pub(crate) fn static_conflict(
    model: &SceneModel,
    problem: &Problem,
    checker: &Checker<'_>,
    lattice: &Lattice,
    termination: &Termination<'_>,
) -> Result<Option<Infeasibility>, Error> {
    let settings = checker.settings;
    if problem.goal.is_satisfied(&problem.start) {
        return Ok(None);
    }
    let collision = &settings.sweep.collision;
    let mut data = SceneData::new(model);
    let mut probe = SceneData::new(model);
    let mut collide = |q: &[f64]| -> Result<Vec<Contact>, Error> {
        let state = State { q: q.to_vec() };
        forward_kinematics(model, &mut probe, &state)?;
        Ok(collisions(model, &probe, collision)?)
    };
    let start = problem.start.as_slice().to_vec();
    let at_start = collide(&start)?;
    let mut q = start.clone();
    for (j, t) in problem.goal.targets() {
        q[j.index()] = t.nearest(q[j.index()]);
    }
    // The joints that place a body: the part's joint and its ancestors'.
    let chain = |body: Body| -> Vec<JointId> {
        match body {
            Body::Part(p) => model.path_to_base(p).map(PartId::joint).collect(),
            Body::Base(_) => Vec::new(),
        }
    };
    for contact in collide(&q)? {
        if termination.should_stop() {
            return Ok(None);
        }
        if at_start.iter().any(|c| same_pair(c, &contact)) {
            continue;
        }
        let mut joints = chain(contact.a);
        joints.extend(chain(contact.b));
        joints.sort();
        joints.dedup();
        // The lattice values inside each joint's target; `None` if one is not a goal joint.
        let Some(choices) = joints
            .iter()
            .map(|j| {
                let t = problem.goal.target(*j)?;
                let values = lattice.values(*j).iter().copied();
                Some(values.filter(|v| t.contains(*v)).collect::<Vec<f64>>())
            })
            .collect::<Option<Vec<Vec<f64>>>>()
        else {
            continue;
        };
        let combinations = choices
            .iter()
            .try_fold(1usize, |n, c| n.checked_mul(c.len()))
            .filter(|n| *n <= MAX_COMBINATIONS && *n > 0);
        let Some(combinations) = combinations else {
            continue;
        };
        if !every_combination_collides(&q, &joints, &choices, combinations, &mut collide, &contact)?
        {
            continue;
        }
        let at = Contacts {
            start: &start,
            goal: &q,
            at_start: &at_start,
        };
        return report(model, checker, lattice, &mut data, &at, &contact, &joints).map(Some);
    }
    Ok(None)
}

/// The contacts of the scene at joint values `q`.
type Collide<'c> = dyn FnMut(&[f64]) -> Result<Vec<Contact>, Error> + 'c;

/// Whether two contacts are between the same bodies.
fn same_pair(c: &Contact, other: &Contact) -> bool {
    (c.a, c.b) == (other.a, other.b) || (c.a, c.b) == (other.b, other.a)
}

/// Whether `contact`'s pair collides in every one of the `combinations` states that put the
/// `joints` at their `choices` (mixed-radix over the choices) and the others at `q`.
fn every_combination_collides(
    q: &[f64],
    joints: &[JointId],
    choices: &[Vec<f64>],
    combinations: usize,
    collide: &mut Collide<'_>,
    contact: &Contact,
) -> Result<bool, Error> {
    for mut k in 0..combinations {
        let mut state = q.to_vec();
        for (j, values) in joints.iter().zip(choices) {
            state[j.index()] = values[k % values.len()];
            k /= values.len();
        }
        if !collide(&state)?.iter().any(|c| same_pair(c, contact)) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// The joint values around a static conflict: the start, the goal-nearest state and the
/// contacts already at the start.
struct Contacts<'a> {
    start: &'a [f64],
    goal: &'a [f64],
    at_start: &'a [Contact],
}

/// The infeasibility report of a static conflict: `contact`'s pair collides whenever the
/// `joints` that place it meet their targets. The reported move is the pair's own joint into
/// its target, with the sweep check's verdict on it (where the contact first occurs).
fn report(
    model: &SceneModel,
    checker: &Checker<'_>,
    lattice: &Lattice,
    data: &mut SceneData,
    at: &Contacts<'_>,
    contact: &Contact,
    joints: &[JointId],
) -> Result<Infeasibility, Error> {
    let (start, q) = (at.start, at.goal);
    let name = |b: Body| BodyName::of(model, b);
    let (a, b) = (name(contact.a), name(contact.b));
    let goal_names: Vec<String> = joints
        .iter()
        .map(|j| model.joints()[j.index()].name.clone())
        .collect();
    let moving = match contact.a {
        Body::Part(p) => model.parts()[p.index()].joint(),
        Body::Base(_) => joints[0],
    };
    let key: Vec<u16> = (0..start.len())
        .map(|k| lattice.index_of(JointId(k), start[k]).unwrap_or(0) as u16)
        .collect();
    let to = lattice.index_of(moving, q[moving.index()]).unwrap_or(0) as u16;
    let cause = match checker.sweep(data, &key, moving, to)? {
        SweepVerdict::Blocked { cause, .. } => cause,
        SweepVerdict::Free => Cause::Collision {
            moving: a.clone(),
            other: b.clone(),
            value: q[moving.index()],
        },
    };
    let conflict = Failure {
        joint: model.joints()[moving.index()].name.clone(),
        from: start[moving.index()],
        to: q[moving.index()],
        cause,
    };
    let start_collisions = at.at_start.iter().map(|c| (name(c.a), name(c.b))).collect();
    Ok(Infeasibility {
        message: format!(
            "no plan in the lattice: {a} and {b} collide whenever {} meet their targets",
            goal_names.join(", ")
        ),
        unreached: goal_names,
        conflicts: vec![conflict],
        start_collisions,
    })
}
