//! Distance tables of the self-collision pairs whose relative pose depends on one or two
//! joints: a certified lower bound on the pair's exact distance at any configuration, without
//! parry ([`PairTable`]).
//!
//! **Why.** Links two joints apart along the chain (the Panda's `link5` and its `link7` with
//! the hand) can pass a few centimetres apart at every configuration while their sphere
//! covers overlap: the broad phase then sends the pair to parry at nearly every state (on the
//! MotionBenchMaker problems this pair took most of the planning time).
//!
//! **Bound.** Links `i < k` of the serial chain: the pose of link `k` in link `i`'s frame is a
//! function of the joints `i ..= k − 1` only (joint `j` moves links `j + 1 ..`), so their exact
//! distance `d(q)` is one of those one or two joint values. The table holds parry's distance
//! `d(n)` at the nodes `n` of a regular grid over the joints' limits (a continuous joint: one
//! turn, `[−π, π]`, values wrapped into it). Along the straight joint-space motion from a node
//! `n` to `q` no point of link `k` moves relative to link `i` by more than
//! `Σ_j |q_j − n_j|·λ_j`, with `λ_j` the lever arms of [`levers`](super::levers) (the spheres
//! contain the shapes). So `d(q) ≥ d(n) − Σ_j |q_j − n_j|·λ_j` for every node, and the table's
//! bound at `q` is the largest of these over the corners of `q`'s grid cell. Node distances
//! are exact below [`TABLE_CUTOFF`] and capped at it (a lower bound beyond). A value outside a
//! bounded joint's limits gets no bound (`−∞`). The rounding of poses computed along other
//! chains is far below the 1 µm the callers keep (`CERTIFIED_GAP`).

use std::f64::consts::PI;

use nalgebra::DVector;

use super::Sphere;
use crate::kinematics::robot::{ArmJointKind, RobotCollision, RobotConfig, RobotModel};

/// The most grid nodes of one pair's table. Building costs one parry distance per node
/// (tens of µs each for convex hulls), once per robot.
const MAX_NODES: usize = 4096;

/// Node distances (m) are exact below this and capped at it.
const TABLE_CUTOFF: f64 = 0.1;

/// One joint of a table: its index, grid and lever arm.
#[derive(Debug, Clone)]
struct Axis {
    joint: usize,
    /// First node's value and the node spacing (rad or m); `cells + 1` nodes.
    lo: f64,
    step: f64,
    cells: usize,
    lever: f64,
    /// A continuous joint: values are wrapped into `[lo, lo + 2π)`.
    wrap: bool,
}

impl Axis {
    /// The value of node `c`.
    fn node(&self, c: usize) -> f64 {
        self.lo + c as f64 * self.step
    }

    /// The cell of value `x` (wrapped for a continuous joint) and the value, `None` outside
    /// the grid.
    fn locate(&self, x: f64) -> Option<(usize, f64)> {
        let x = if self.wrap {
            self.lo + (x - self.lo).rem_euclid(2.0 * PI)
        } else {
            x
        };
        let u = (x - self.lo) / self.step;
        // NaN is in no range.
        if !(0.0..=self.cells as f64).contains(&u) {
            return None;
        }
        Some(((u.floor() as usize).min(self.cells - 1), x))
    }
}

/// The distance table of one checked pair (see the module's bound).
#[derive(Debug, Clone)]
pub(super) struct PairTable {
    axes: Vec<Axis>,
    /// Node distances, the first axis varying slowest.
    d: Vec<f64>,
}

impl PairTable {
    /// The table of the pair `(i, k)`, `i < k`, when its relative pose depends on one or two
    /// joints with finite ranges (revolute or prismatic within limits, continuous over one
    /// turn), `None` otherwise. `links`: the sphere covers, for the lever arms.
    pub(super) fn build(
        robot: &RobotModel,
        collision: &RobotCollision,
        links: &[Vec<Sphere>],
        i: usize,
        k: usize,
    ) -> Option<PairTable> {
        let joints = robot.arm_joints();
        if !(i < k && k - i <= 2 && k <= joints.len()) {
            return None;
        }
        let levers = super::levers(robot, links, i, k);
        let mut axes = Vec::new();
        for (j, lever) in levers {
            let joint = &joints[j];
            let (lo, hi, wrap) = match joint.kind {
                ArmJointKind::Continuous => (-PI, PI, true),
                _ if joint.lower.is_finite() && joint.upper.is_finite() => {
                    (joint.lower, joint.upper, false)
                }
                _ => return None,
            };
            // Both finite here.
            if hi <= lo {
                return None;
            }
            axes.push((j, lo, hi, lever, wrap));
        }
        // Cells per axis so that each axis loses about the same to its lever at a cell's
        // centre, with at most MAX_NODES nodes.
        let spans: Vec<f64> = axes
            .iter()
            .map(|&(_, lo, hi, lever, _)| ((hi - lo) * lever).max(1e-9))
            .collect();
        let cells: Vec<usize> = match spans.as_slice() {
            [s] => vec![((s / 1e-4).ceil() as usize).clamp(1, MAX_NODES - 1)],
            [a, b] => {
                let c = (a * b / MAX_NODES as f64).sqrt();
                let (mut na, mut nb) = (((a / c) as usize).max(1), ((b / c) as usize).max(1));
                while (na + 1) * (nb + 1) > MAX_NODES {
                    if na >= nb { na -= 1 } else { nb -= 1 }
                }
                vec![na.max(1), nb.max(1)]
            }
            _ => return None,
        };
        let axes: Vec<Axis> = axes
            .iter()
            .zip(&cells)
            .map(|(&(joint, lo, hi, lever, wrap), &cells)| Axis {
                joint,
                lo,
                step: (hi - lo) / cells as f64,
                cells,
                lever,
                wrap,
            })
            .collect();
        let mut arm: DVector<f64> = robot.neutral();
        let mut d = Vec::new();
        let distance = |arm: &DVector<f64>| {
            let poses = robot
                .link_poses(&RobotConfig {
                    base: [0.0; 3],
                    arm: arm.clone(),
                })
                .ok()?;
            Some(collision.pair_distance_below(&poses, i, k, TABLE_CUTOFF))
        };
        match axes.as_slice() {
            [a] => {
                for c in 0..=a.cells {
                    arm[a.joint] = a.node(c);
                    d.push(distance(&arm)?);
                }
            }
            [a, b] => {
                for ca in 0..=a.cells {
                    arm[a.joint] = a.node(ca);
                    for cb in 0..=b.cells {
                        arm[b.joint] = b.node(cb);
                        d.push(distance(&arm)?);
                    }
                }
            }
            _ => return None,
        }
        Some(PairTable { axes, d })
    }

    /// A lower bound (m) on the pair's exact distance at arm configuration `q` (see the
    /// module's bound); `−∞` outside the grid or for a configuration too short.
    pub(super) fn lower_bound(&self, q: &[f64]) -> f64 {
        match self.axes.as_slice() {
            [a] => {
                let Some((c, x)) = q.get(a.joint).and_then(|&x| a.locate(x)) else {
                    return f64::NEG_INFINITY;
                };
                (c..=c + 1)
                    .map(|n| self.d[n] - (x - a.node(n)).abs() * a.lever)
                    .fold(f64::NEG_INFINITY, f64::max)
            }
            [a, b] => {
                let (Some((ca, xa)), Some((cb, xb))) = (
                    q.get(a.joint).and_then(|&x| a.locate(x)),
                    q.get(b.joint).and_then(|&x| b.locate(x)),
                ) else {
                    return f64::NEG_INFINITY;
                };
                let mut best = f64::NEG_INFINITY;
                for na in ca..=ca + 1 {
                    let la = (xa - a.node(na)).abs() * a.lever;
                    for nb in cb..=cb + 1 {
                        let lb = (xb - b.node(nb)).abs() * b.lever;
                        best = best.max(self.d[na * (b.cells + 1) + nb] - la - lb);
                    }
                }
                best
            }
            _ => f64::NEG_INFINITY,
        }
    }
}
