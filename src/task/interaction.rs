//! Which moves interact: the dependence relation of the search's partial-order reduction
//! ([`TaskSettings::reduction`](super::TaskSettings::reduction)).
//!
//! **Relation.** Two different joints `a` and `b` *interact* when
//! 1. one is in the other's sweep context ([`Checker::sweep_context`]: ancestors, subtree,
//!    and the parts whose conservative reach spheres come within the contact gap, with their
//!    ancestors), or
//! 2. one is a *floor joint* (it places a part that blocks cells beyond the inflated base map
//!    at some lattice value of that part's placing joints) and the other has a handle.
//!
//! **Claim (locality).** The verdict of [`Checker::evaluate`] on a move of joint `j` depends
//! only on the values of `j` and of the joints that interact with `j` (the premise `local`
//! of `proofs/theories/Task/Reduction.v`), for a refiner that is [`Refiner::local`]
//! ([`NoRefinement`](super::NoRefinement) is). **Why**, per check:
//! - no handle: depends on nothing;
//! - the sweep: its verdict is a function of the values of its context (the memo's key,
//!   transparent by assumption (b) of `proofs/README.md`), and its context joints interact
//!   with `j` by rule 1;
//! - the base pose: the manipulation region depends on `j`'s ancestors and the swept
//!   footprint on its ancestors and subtree (both in the sweep context); the occupancy before
//!   and after the move, and with it the start's free component, is the union of the parts'
//!   footprints, each a function of that part's placing joints; a part that never blocks a
//!   cell beyond the base map adds nothing, so the occupancy is a function of the floor
//!   joints' values, and every floor joint interacts with `j` (which has a handle) by rule 2.
//!   Connectivity is global: one open door anywhere may close the aisle, so no finer rule
//!   for the floor is sound;
//! - the refiner: local by its own contract.
//!
//! The relation is symmetric by construction. Its connected components are what the
//! reduction prunes by: in a state whose goal is unmet, only the moves of the component of
//! one unmet goal joint are pushed ([`Interaction::reduced_component`]).
//!
//! **Costs.** With `cost.travel = 0` a move's cost is `action + actuation·(handle travel)`
//! of the cheapest feasible region cell, which is computed from the same data as the
//! base-pose check: a function of the same joints. So a reordering of commuting moves (each
//! move's joints keep their values) costs the same, and the reduced search keeps an optimal
//! plan's cost. With travel, the cost depends on where the robot stands, which the order
//! changes: the search then uses the reduction only until its first plan.
//!
//! **Consequence.** Where some part on the floor moves, every joint with a handle is in one
//! component (rule 2), so the reduction prunes only between parts that never touch the
//! navigation band (wall cabinets above it, a robot whose band is low) and joints whose
//! sweeps, regions and footprints are apart from each other.

use super::Error;
use super::check::Checker;
use super::goal::Problem;
use super::lattice::Lattice;
use super::settings::TaskSettings;
use crate::scene::{JointId, SceneData, SceneModel};

/// The interaction relation of a problem's joints and its connected components (see the
/// module docs of [`crate::task`] and `interaction.rs`).
#[derive(Debug, Clone)]
pub struct Interaction {
    /// Per joint, the joints it interacts with (sorted).
    neighbours: Vec<Vec<JointId>>,
    /// Per joint, its component's number.
    component: Vec<usize>,
    /// Per component, its number of joints.
    sizes: Vec<usize>,
}

impl Interaction {
    /// The relation of `problem`'s joints on `model`, with the lattice built from
    /// `settings.lattice` (as [`plan`](super::plan) builds it).
    ///
    /// # Errors
    /// As [`Feasibility::new`](super::Feasibility::new).
    pub fn new(
        model: &SceneModel,
        problem: &Problem,
        settings: &TaskSettings,
    ) -> Result<Self, Error> {
        settings.validate()?;
        problem.start.validate(model)?;
        let lattice = Lattice::new(model, problem, &settings.lattice);
        let checker = Checker::new(model, problem, settings, &lattice)?;
        let key: Vec<u16> = (0..model.nq())
            .map(|k| {
                lattice
                    .index_of(JointId(k), problem.start.as_slice()[k])
                    .unwrap_or(0) as u16
            })
            .collect();
        Self::of(&checker, &mut SceneData::new(model), &key)
    }

    /// The relation of `checker`'s problem; `key` is any lattice state (the start).
    pub(crate) fn of(
        checker: &Checker<'_>,
        data: &mut SceneData,
        key: &[u16],
    ) -> Result<Self, Error> {
        let model = checker.model;
        let n = model.nq();
        let floor = checker.floor_joints(data, key, false)?;
        let handle: Vec<bool> = model
            .parts()
            .iter()
            .map(|p| !p.handles().is_empty())
            .collect();
        let mut neighbours = vec![Vec::new(); n];
        let mut root: Vec<usize> = (0..n).collect();
        for a in 0..n {
            for b in a + 1..n {
                let near = checker.sweep_context(JointId(a)).contains(&JointId(b))
                    || checker.sweep_context(JointId(b)).contains(&JointId(a));
                let ground = (floor[a] && handle[b]) || (floor[b] && handle[a]);
                if near || ground {
                    neighbours[a].push(JointId(b));
                    neighbours[b].push(JointId(a));
                    let (ra, rb) = (find(&mut root, a), find(&mut root, b));
                    root[ra.max(rb)] = ra.min(rb);
                }
            }
        }
        // Number the components by their least joint.
        let mut component = vec![usize::MAX; n];
        let mut sizes = Vec::new();
        let mut number = vec![usize::MAX; n];
        for (j, c) in component.iter_mut().enumerate() {
            let r = find(&mut root, j);
            if number[r] == usize::MAX {
                number[r] = sizes.len();
                sizes.push(0);
            }
            *c = number[r];
            sizes[number[r]] += 1;
        }
        Ok(Interaction {
            neighbours,
            component,
            sizes,
        })
    }

    /// Whether moves of joints `a` and `b` may interact (never for `a == b`: a joint's own
    /// moves are always in its component).
    pub fn interacts(&self, a: JointId, b: JointId) -> bool {
        self.neighbours
            .get(a.index())
            .is_some_and(|v| v.binary_search(&b).is_ok())
    }

    /// The number of `joint`'s component.
    pub fn component(&self, joint: JointId) -> usize {
        self.component[joint.index()]
    }

    /// The number of joints in `joint`'s component.
    pub fn component_len(&self, joint: JointId) -> usize {
        self.sizes[self.component[joint.index()]]
    }

    /// The number of components.
    pub fn components(&self) -> usize {
        self.sizes.len()
    }

    /// The component whose moves the reduced search pushes at joint values `q`: that of the
    /// unmet goal joint with the fewest joints in its component (then the lowest joint
    /// index); `None` when every target is met. It depends only on which targets `q` meets.
    pub fn reduced_component(&self, problem: &Problem, q: &[f64]) -> Option<usize> {
        problem
            .goal
            .targets()
            .iter()
            .filter(|(j, t)| !t.contains(q[j.index()]))
            .min_by_key(|(j, _)| (self.component_len(*j), j.index()))
            .map(|(j, _)| self.component(*j))
    }
}

/// The root of `x` in the union-find forest `root` (with path halving).
fn find(root: &mut [usize], mut x: usize) -> usize {
    while root[x] != x {
        root[x] = root[root[x]];
        x = root[x];
    }
    x
}
