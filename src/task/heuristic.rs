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
//!   in reach and in the band). With `D_j(x)` the straight-line distance from the centre of
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
//! `C_j` proves the goal infeasible: no move can bring the joint into its target.

use std::cell::OnceCell;

use super::Error;
use super::check::Checker;
use super::goal::Problem;
use super::lattice::Lattice;
use super::reach::ancestor_joints;
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

    /// `C_j` of one goal joint (see the module docs); `None` beyond [`MAX_POSE_COMBINATIONS`]
    /// ancestor value combinations, or if the joint meets its target at every value.
    #[allow(clippy::too_many_arguments)]
    fn final_move_set(
        &self,
        model: &SceneModel,
        checker: &Checker<'_>,
        data: &mut SceneData,
        joint: JointId,
        reachable: &[bool],
        least_span: &mut f64,
    ) -> Result<Option<Vec<usize>>, Error> {
        let Some(target) = self.problem.goal.target(joint) else {
            return Ok(None);
        };
        let values = self.lattice.values(joint);
        let inside: Vec<f64> = values
            .iter()
            .copied()
            .filter(|v| target.contains(*v))
            .collect();
        if inside.len() == values.len() {
            // Every value meets the target: the joint is never unmet.
            return Ok(None);
        }
        let part = &model.parts()[joint.index()];
        let ancestors = ancestor_joints(model, part.id());
        let Some(combinations) = ancestors
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(self.lattice.values(*a).len()))
            .filter(|n| *n <= MAX_POSE_COMBINATIONS)
        else {
            return Ok(None);
        };
        let m = &self.settings.manipulation;
        let grid = checker.base_grid();
        let (w, h, res) = (self.width, self.height, self.resolution);
        let o = grid.origin();
        let index = |v: f64, o: f64, n: usize| {
            (((v - o) / res).floor().max(0.0) as usize).min(n.saturating_sub(1))
        };
        let mut member = vec![false; w * h];
        let mut state: State = self.problem.start.clone();
        for mut k in 0..combinations {
            for a in &ancestors {
                let values = self.lattice.values(*a);
                state.q[a.index()] = values[k % values.len()];
                k /= values.len();
            }
            for v in &inside {
                state.q[joint.index()] = *v;
                forward_kinematics(model, data, &state)?;
                let world_from_part = data.world_from_parts()[part.id().index()];
                for handle in part.handles() {
                    let p = world_from_part * handle.position;
                    let n = world_from_part * handle.normal;
                    if p.z < m.height_min - SLACK || p.z > m.height_max + SLACK {
                        continue;
                    }
                    let r = m.reach_max + SLACK;
                    for j in index(p.y - r, o.y, h)..=index(p.y + r, o.y, h) {
                        for i in index(p.x - r, o.x, w)..=index(p.x + r, o.x, w) {
                            let c = grid.cell_center(i, j);
                            let d = (c.x - p.x).hypot(c.y - p.y);
                            let cell = j * w + i;
                            if d >= m.reach_min - SLACK && d <= r && reachable[cell] {
                                match &m.arm {
                                    Some(arm) => {
                                        let span = arm.span([c.x, c.y], &p, &n);
                                        *least_span = least_span.min(span);
                                        if span <= arm.radius + SLACK {
                                            member[cell] = true;
                                        }
                                    }
                                    None => member[cell] = true,
                                }
                            }
                        }
                    }
                }
            }
        }
        Ok(Some((0..w * h).filter(|&c| member[c]).collect()))
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

    /// `D_k` of goal target `k` (which has a set).
    fn field(&self, k: usize) -> &[f64] {
        self.fields[k].get_or_init(|| {
            let set = self.sets[k].as_deref().unwrap_or_default();
            distance_field(set, self.width, self.height, self.resolution)
        })
    }

    /// `d(C_i, C_k)`.
    fn pair(&self, i: usize, k: usize) -> f64 {
        let (i, k) = (i.min(k), i.max(k));
        let n = self.sets.len();
        *self.pairs[i * n + k].get_or_init(|| {
            let set = self.sets[i].as_deref().unwrap_or_default();
            let field = self.field(k);
            set.iter().map(|&c| field[c]).fold(f64::INFINITY, f64::min)
        })
    }

    /// The `travel` term of a state, as a function of the robot's cell.
    pub fn travel_of(&self, key: &[u16]) -> Travel<'_> {
        let weight = self.settings.cost.travel;
        let mut fields = Vec::new();
        let mut unmet = Vec::new();
        if weight > 0.0 {
            for (k, ((j, i), set)) in self
                .problem
                .goal
                .targets()
                .iter()
                .zip(&self.sets)
                .enumerate()
            {
                let v = self.lattice.values(*j)[key[j.index()] as usize];
                if set.as_ref().is_some_and(|s| !s.is_empty()) && !i.contains(v) {
                    unmet.push(k);
                    fields.push(self.field(k));
                }
            }
        }
        // Prim's algorithm over the unmet goals' sets.
        let mut tree = 0.0;
        if unmet.len() > 1 {
            let mut best: Vec<f64> = unmet.iter().map(|&k| self.pair(unmet[0], k)).collect();
            let mut done = vec![false; unmet.len()];
            done[0] = true;
            for _ in 1..unmet.len() {
                let (next, d) = best
                    .iter()
                    .enumerate()
                    .filter(|(a, _)| !done[*a])
                    .map(|(a, d)| (a, *d))
                    .fold(
                        (usize::MAX, f64::INFINITY),
                        |x, y| if y.1 < x.1 { y } else { x },
                    );
                if next == usize::MAX {
                    break;
                }
                done[next] = true;
                tree += d;
                for (a, b) in best.iter_mut().enumerate() {
                    if !done[a] {
                        *b = b.min(self.pair(unmet[next], unmet[a]));
                    }
                }
            }
        }
        Travel {
            weight,
            tree,
            fields,
        }
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
        let reach = self.settings.manipulation.reach_max;
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

/// The `travel` term of one state.
pub(crate) struct Travel<'h> {
    weight: f64,
    /// Minimum spanning tree weight over the unmet goals' sets (m).
    tree: f64,
    /// `D_j` of the unmet goals.
    fields: Vec<&'h [f64]>,
}

impl Travel<'_> {
    /// The term with the robot at `cell`.
    pub fn at(&self, cell: usize) -> f64 {
        if self.fields.is_empty() {
            return 0.0;
        }
        let (mut near, mut far) = (f64::INFINITY, 0.0f64);
        for f in &self.fields {
            near = near.min(f[cell]);
            far = far.max(f[cell]);
        }
        self.weight * far.max(near + self.tree)
    }
}

/// Distance (m) from every cell centre to the nearest cell centre of `set` on a
/// `width × height` grid of cell size `resolution`; `INFINITY` everywhere if `set` is empty.
/// Exact Euclidean distance transform (Felzenszwalb and Huttenlocher 2012): the squared
/// transform along columns, then along rows.
pub(crate) fn distance_field(
    set: &[usize],
    width: usize,
    height: usize,
    resolution: f64,
) -> Vec<f64> {
    if set.is_empty() {
        return vec![f64::INFINITY; width * height];
    }
    const FAR: f64 = 1e30;
    let mut sq = vec![FAR; width * height];
    for &c in set {
        sq[c] = 0.0;
    }
    let n = width.max(height);
    let (mut f, mut d) = (vec![0.0; n], vec![0.0; n]);
    let (mut v, mut z) = (vec![0usize; n], vec![0.0; n + 1]);
    for i in 0..width {
        for j in 0..height {
            f[j] = sq[j * width + i];
        }
        transform_1d(&f[..height], &mut d[..height], &mut v, &mut z);
        for j in 0..height {
            sq[j * width + i] = d[j];
        }
    }
    for j in 0..height {
        f[..width].copy_from_slice(&sq[j * width..(j + 1) * width]);
        transform_1d(&f[..width], &mut d[..width], &mut v, &mut z);
        sq[j * width..(j + 1) * width].copy_from_slice(&d[..width]);
    }
    sq.iter()
        .map(|&s| {
            if s >= FAR {
                f64::INFINITY
            } else {
                s.sqrt() * resolution
            }
        })
        .collect()
}

/// The 1D squared distance transform `d[q] = min_p (q − p)² + f[p]` (lower envelope of
/// parabolas).
fn transform_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        let s = |p: usize| {
            ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * q as f64 - 2.0 * p as f64)
        };
        let mut x = s(v[k]);
        while x <= z[k] {
            k -= 1;
            x = s(v[k]);
        }
        k += 1;
        v[k] = q;
        z[k] = x;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, out) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *out = (q as f64 - p as f64).powi(2) + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transform equals the brute-force minimum over the set.
    #[test]
    fn distance_field_matches_brute_force() {
        let (w, h, res) = (23, 17, 0.05);
        for set in [
            vec![0],
            vec![w * h - 1],
            vec![5 * w + 7, 12 * w + 20, 3],
            (0..w * h).filter(|c| c % 29 == 3).collect::<Vec<_>>(),
        ] {
            let field = distance_field(&set, w, h, res);
            for (c, d) in field.iter().enumerate() {
                let (i, j) = ((c % w) as f64, (c / w) as f64);
                let brute = set
                    .iter()
                    .map(|&s| {
                        let (si, sj) = ((s % w) as f64, (s / w) as f64);
                        (i - si).hypot(j - sj) * res
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!((d - brute).abs() < 1e-9, "cell {c}: {d} vs {brute}");
            }
        }
        assert!(
            distance_field(&[], 4, 3, res)
                .iter()
                .all(|d| d.is_infinite())
        );
    }
}
