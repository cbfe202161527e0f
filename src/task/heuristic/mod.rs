//! The search's heuristic: a lower bound on the cost still to pay from a lattice state with
//! the robot at a grid cell.
//!
//! `h(Θ, x) = work(Θ) + travel(Θ, x)`:
//!
//! - `work(Θ)`: each unmet goal joint needs at least one more action, and its handle must
//!   travel at least `r·(distance of its value to the target interval)`, `r` the least
//!   distance of the part's handles from the joint axis (1 for prismatic joints);
//! - `travel(Θ, x)`, in metres times the travel weight: the robot must still visit, for each
//!   unmet goal joint `j`, the base cell of the move that finally brings `j` into its target.
//!   That cell lies in the *final-move set* `C_j`: cells connected to the robot's start
//!   through the free cells of the inflated base map (parts only add obstacles to it, and
//!   every base cell is connected to the start after its move), within `[reach_min,
//!   reach_max]` of one of the part's handle positions with the joint at a lattice value
//!   inside the target and its ancestors at any combination of lattice values, the handle
//!   within the height band (the manipulation region holds the grasp point's last position,
//!   in reach and in the band; with segmented moves,
//!   [`ManipulationSettings::segments`](super::ManipulationSettings::segments) `>= 2`, the
//!   base cell covers the grasp point's *first* position instead, so `C_j` takes the joint
//!   at every lattice value). With `D_j(x)` the straight-line distance from the centre of
//!   cell `x` to the nearest centre of a cell of `C_j` (grid paths are no shorter) and
//!   `d(C_i, C_k)` the least such distance between the two sets, any remaining route from `x`
//!   is at least `max_j D_j(x)` (it reaches every set) and at least `min_j D_j(x) + MST`, the
//!   weight of a minimum spanning tree over the unmet goals' sets with edge weights
//!   `d(C_i, C_k)` (the route reaches a first set, then visits the others one after another:
//!   a spanning path of that graph). `travel` is the larger of the two.
//!
//! Both parts never overestimate (the heuristic is *admissible*). `work` is consistent, and
//! so is `travel` along every move that does not take a goal joint out of its target: `D_j`
//! and their minimum are 1-Lipschitz in the robot's position; a move that meets goal `j`
//! ends with the robot at a cell of `C_j`, which removes `j` from the bound at a cost no
//! larger than the route already paid. A move that takes a goal joint *out* of its target
//! can raise the bound by more than the move costs (a new set joins the tree).
//!
//! A goal joint with more than [`MAX_POSE_COMBINATIONS`] ancestor value combinations gets no
//! travel bound (`C_j` is then not computed and the joint is left out of `travel`). An empty
//! `C_j` proves the goal infeasible: no move can bring the joint into its target. With segmented
//! moves `C_j` is also taken empty when no cell serves a position inside the target (the
//! move's last run must hold one from such a cell).
//!
//! Here the heuristic and its `work` term; the final-move sets in `final_move.rs`, the `travel`
//! term in `travel.rs`, on the distance transform of `distance.rs`.

mod distance;
mod final_move;
mod travel;

use std::cell::OnceCell;

use super::Error;
use super::check::Checker;
use super::goal::Problem;
use super::lattice::Lattice;
use super::settings::TaskSettings;
use crate::scene::nav::search::{Blocked, Flood};
use crate::scene::{JointId, JointKind, SceneData, SceneModel, State, forward_kinematics};

/// Ancestor value combinations beyond which a goal joint gets no travel bound.
pub(crate) const MAX_POSE_COMBINATIONS: usize = 256;

/// Slack (m) on the reach and height limits when building the final-move sets, so that
/// rounding in the grasp trajectory cannot put a base cell outside its set.
const SLACK: f64 = 1e-6;

/// The heuristic of one search.
pub(crate) struct Heuristic<'a> {
    lattice: &'a Lattice,
    problem: &'a Problem,
    settings: &'a TaskSettings,
    /// Per joint: least handle travel per unit of joint motion (0 without handles).
    radii: Vec<f64>,
    /// Per goal target (in `problem.goal.targets()` order): the cells of `C_j`, ascending;
    /// `None` if unbounded.
    sets: Vec<Option<Vec<usize>>>,
    /// Per goal target: the least [`ArmReach::span`](super::ArmReach::span) over the cells
    /// of the start's free component within the annulus of a final handle position (∞ without
    /// an arm reach or such a cell).
    spans: Vec<f64>,
    /// Per goal target: `D_j` per cell (m), computed on first use.
    fields: Vec<OnceCell<Vec<f64>>>,
    /// `d(C_i, C_k)` (m) for goal targets `i`, `k`, computed on first use.
    pairs: Vec<OnceCell<f64>>,
    width: usize,
    height: usize,
    resolution: f64,
    /// The inflated base map.
    free: Blocked,
    /// How far a cell's centre can be from the base pose the task layer takes in it (m):
    /// half a cell diagonal with cells freed at the grid's boundary, else 0.
    witness_offset: f64,
}
impl<'a> Heuristic<'a> {
    pub fn new(
        model: &SceneModel,
        problem: &'a Problem,
        settings: &'a TaskSettings,
        lattice: &'a Lattice,
        checker: &Checker<'_>,
        data: &mut SceneData,
    ) -> Result<Self, Error> {
        let radii = model
            .joints()
            .iter()
            .zip(model.parts())
            .map(|(j, p)| match j.kind {
                _ if p.handles().is_empty() => 0.0,
                JointKind::Prismatic => 1.0,
                JointKind::Revolute => p
                    .handles()
                    .iter()
                    .map(|h| {
                        let v = h.position.coords;
                        (v - j.axis * j.axis.dot(&v)).norm()
                    })
                    .fold(f64::INFINITY, f64::min),
            })
            .collect();
        let grid = checker.base_grid();
        let (width, height, resolution) = (grid.width(), grid.height(), grid.resolution());
        let n = problem.goal.targets().len();
        let mut heuristic = Heuristic {
            lattice,
            problem,
            settings,
            radii,
            sets: Vec::with_capacity(n),
            spans: Vec::with_capacity(n),
            fields: (0..n).map(|_| OnceCell::new()).collect(),
            pairs: (0..n * n).map(|_| OnceCell::new()).collect(),
            width,
            height,
            resolution,
            free: Blocked::from_grid(grid),
            witness_offset: if checker.boundary_cells() > 0 {
                resolution * std::f64::consts::FRAC_1_SQRT_2
            } else {
                0.0
            },
        };
        if settings.cost.travel > 0.0 {
            let mut flood = Flood::new(&heuristic.free, checker.start_cell);
            let reachable = flood.complete(&heuristic.free).to_vec();
            for (joint, _) in problem.goal.targets() {
                let mut span = f64::INFINITY;
                let set = heuristic
                    .final_move_set(model, checker, data, *joint, &reachable, &mut span)?;
                heuristic.sets.push(set);
                heuristic.spans.push(span);
            }
        } else {
            heuristic.sets = vec![None; n];
            heuristic.spans = vec![f64::INFINITY; n];
        }
        Ok(heuristic)
    }

    /// Goal targets (indices into `problem.goal.targets()`) whose final-move set is known to
    /// be empty: no move can bring the joint into its target, so the goal is infeasible.
    pub fn unreachable_targets(&self) -> Vec<usize> {
        self.sets
            .iter()
            .enumerate()
            .filter(|(_, s)| s.as_ref().is_some_and(|s| s.is_empty()))
            .map(|(k, _)| k)
            .collect()
    }

    /// For goal target `k` (an index into `problem.goal.targets()`): the least shoulder-to-wrist
    /// span any free base cell within the annulus of its final handle positions needs, when the
    /// arm reach is set and such a cell exists.
    pub fn least_arm_span(&self, k: usize) -> Option<f64> {
        self.spans.get(k).copied().filter(|s| s.is_finite())
    }

    /// The cost of moving `joint` from value index `from` to `to` without base travel, at
    /// least: one action plus the least handle travel.
    pub fn move_work(&self, joint: JointId, from: u16, to: u16) -> f64 {
        let v = self.lattice.values(joint);
        self.settings.cost.action
            + self.settings.cost.actuation
                * self.radii[joint.index()]
                * (v[to as usize] - v[from as usize]).abs()
    }

    /// The number of goal targets a state does not meet.
    pub fn unmet(&self, key: &[u16]) -> usize {
        self.problem
            .goal
            .targets()
            .iter()
            .filter(|(j, i)| !i.contains(self.lattice.values(*j)[key[j.index()] as usize]))
            .count()
    }

    /// The `work` term of a state.
    pub fn work(&self, key: &[u16]) -> f64 {
        let c = &self.settings.cost;
        self.problem
            .goal
            .targets()
            .iter()
            .map(|(j, i)| {
                let v = self.lattice.values(*j)[key[j.index()] as usize];
                if i.contains(v) {
                    0.0
                } else {
                    c.action + c.actuation * self.radii[j.index()] * i.distance(v)
                }
            })
            .sum()
    }

    /// Per joint: for the active ones, the travel cost from `xy` to the nearest point within
    /// `reach_max` of one of its part's handles in `state` — every base cell of a move of
    /// the joint is there (the region holds the grasp point's first position within reach);
    /// 0 for the others.
    pub fn approach(
        &self,
        model: &SceneModel,
        data: &mut SceneData,
        state: &State,
        active: &[bool],
        xy: [f64; 2],
    ) -> Result<Vec<f64>, Error> {
        let tw = self.settings.cost.travel;
        let mut out = vec![0.0; active.len()];
        if tw == 0.0 {
            return Ok(out);
        }
        forward_kinematics(model, data, state)?;
        // A base cell's witness is within reach; its centre, where travel is measured, within
        // half a cell diagonal more.
        let reach = self.settings.manipulation.reach_max + self.witness_offset;
        for (k, part) in model.parts().iter().enumerate() {
            if !active[k] || part.handles().is_empty() {
                continue;
            }
            let world_from_part = data.world_from_parts()[k];
            let near = part
                .handles()
                .iter()
                .map(|h| {
                    let p = world_from_part * h.position;
                    (p.x - xy[0]).hypot(p.y - xy[1])
                })
                .fold(f64::INFINITY, f64::min);
            out[k] = tw * (near - reach).max(0.0);
        }
        Ok(out)
    }
}
