//! Certified (continuous) collision checking of a straight arm motion with the sphere model:
//! conservative advancement with bisection (Schwarzer, Saha & Latombe 2005, "Adaptive dynamic
//! collision checking for single and multiple articulated robots in complex environments").
//!
//! **Motion bound.** Along the straight joint-space motion `q(t) = a + t·(b − a)`, a point `p`
//! fixed to link `l` moves with velocity `Σ_j q̇_j·(ω_j × (p − o_j))` (revolute `j`) plus
//! `Σ_j q̇_j·v_j` (prismatic `j`), over the joints `j` that move `l`. So its path length over
//! `[t0, t1]` is at most `(t1 − t0)·Σ_j |Δq_j|·R_j(p)`, with `R_j(p)` the distance from `p` to
//! joint `j`'s axis (revolute) or 1 (prismatic). That distance is at most the distance to the
//! axis' origin, the origin of the child link of `j`, which is at most the sum of the fixed
//! offsets down the chain to `l`'s origin (each prismatic joint in between adding its largest
//! travel) plus `|c| + r` for the sphere `(c, r)` (link frame) that contains `p`. This bound
//! `b_s = Σ_j |Δq_j|·R_{j,s}` does not depend on the configuration.
//!
//! **Guarantee.** [`ArmEdgeCheck::check`] returns `true` only if no point of the robot's exact
//! geometry comes within the obstacles' margin of the scene, and no checked link pair touches,
//! anywhere on the closed motion. *Proof sketch.* An interval `[a, b]` is accepted when for
//! every sphere `s`, `d_s(a) + d_s(b) > b_s` (`d_s`: the sphere's obstacle clearance, a lower
//! bound on the distance from every point of it to every margin-inflated obstacle, see
//! [`SphereObstacles`]), and for every checked pair of links `i, k`, `d_ik(a) + d_ik(b) > B_i +
//! B_k` (`d_ik`: the least distance between their spheres, `B_l`: the largest `b_s` of link
//! `l`; where the spheres of a pair meet, `d_ik` is the exact distance of the links' shapes
//! instead, [`RobotCollision::pair_distance`]). A link whose spheres fail the first test still
//! passes when `D_l(a) + D_l(b) > B_l`, `D_l` the larger of its least sphere clearance and
//! its exact distance to the scene minus the margin ([`RobotCollision::link_scene_distance`],
//! computed where the spheres come within 2 cm): every point of the link moves at most `B_l`. Suppose a point `p` of sphere `s` (the
//! spheres cover the exact shapes) reached an obstacle at `t`. The point moved at most
//! `t·b_s` from `a` and `(1 − t)·b_s` to `b`, so `d_s(a) ≤ t·b_s` and `d_s(b) ≤ (1 − t)·b_s`:
//! `d_s(a) + d_s(b) ≤ b_s`, a contradiction. For a pair, the two points close in by at most `B_i + B_k` per unit of `t` together; the same
//! argument applies. An interval not accepted is bisected (the clearances of its midpoint
//! computed once); one shorter than [`EdgeSettings::min_step`] (the Euclidean norm of `Δq`)
//! is reported in collision, as is any configuration without a pose. Clearances are computed
//! in `f32` with [`SPHERE_SLACK`](super::SPHERE_SLACK) subtracted, which covers the rounding.
//!
//! The converse does not hold: a motion that comes within about `min_step·max b_s` of an
//! obstacle, or whose spheres overlap an obstacle or each other where the exact geometry does
//! not, is rejected although it may be free.

use nalgebra::DVector;

use super::{RobotSpheres, SphereData, SphereObstacles};
use crate::InvalidSetting;
use crate::kinematics::robot::{
    ArmJointKind, Exempt, RobotCollision, RobotConfig, RobotError, RobotModel,
};
use crate::scene::{SceneData, SceneModel};

/// Below this sphere clearance (m) of a link, its exact distance to the scene is computed too.
const EXACT_BELOW: f32 = 0.02;

/// The scene an [`ArmEdgeCheck`] checks against, as
/// [`RobotCollision::scene_collision`] takes it.
#[derive(Debug, Clone, Copy)]
pub struct EdgeScene<'a> {
    /// The scene model.
    pub model: &'a SceneModel,
    /// Its part poses ([`crate::scene::forward_kinematics`] of `model`).
    pub data: &'a SceneData,
    /// Which bodies some robot shapes may touch.
    pub exempt: Exempt<'a>,
    /// Clearance (m) required from the scene; negative or NaN counts as 0.
    pub margin: f64,
}

/// Settings of [`ArmEdgeCheck`].
#[derive(Debug, Clone, PartialEq)]
pub struct EdgeSettings {
    /// The shortest interval (Euclidean norm of its `Δq`, rad or m) that is still bisected;
    /// a shorter one that cannot be certified is reported in collision. Finite, `> 0`.
    /// Default 1e-3.
    pub min_step: f64,
}

impl Default for EdgeSettings {
    fn default() -> Self {
        EdgeSettings { min_step: 1e-3 }
    }
}

impl EdgeSettings {
    /// Checks `min_step` (finite, `> 0`).
    ///
    /// # Errors
    /// [`InvalidSetting`] naming the field.
    pub fn validate(&self) -> Result<(), InvalidSetting> {
        if !(self.min_step.is_finite() && self.min_step > 0.0) {
            return Err(InvalidSetting::new(
                "min_step",
                self.min_step,
                "finite and > 0",
            ));
        }
        Ok(())
    }
}

/// Certified straight-motion checks of the arm at a fixed base pose, with a sphere model
/// against the scene's [`SphereObstacles`] and itself (see the module's guarantee).
/// `Send + Sync`; every check allocates its own scratch.
#[derive(Debug, Clone)]
pub struct ArmEdgeCheck<'a> {
    robot: &'a RobotModel,
    collision: &'a RobotCollision,
    spheres: &'a RobotSpheres,
    scene: EdgeScene<'a>,
    obstacles: SphereObstacles,
    base: [f64; 3],
    /// Per link, the arm joints that move it with their coefficients (see [`movers`]).
    movers: Vec<Vec<Mover>>,
    /// Per link, per sphere: `|centre| + radius` in the link frame.
    rho: Vec<Vec<f64>>,
    min_step: f64,
}

/// The clearances at one configuration: per real sphere against obstacles, per checked pair.
struct Clearance {
    spheres: Vec<f32>,
    /// Per link, a lower bound on its distance to the scene beyond the margin.
    links: Vec<f64>,
    pairs: Vec<f64>,
}

impl<'a> ArmEdgeCheck<'a> {
    /// The check for `robot` with base pose `base`, `spheres` built from `robot` and
    /// `collision`, against `scene` (as [`SphereObstacles`] for the spheres, exact distances
    /// where a link's spheres come within 2 cm).
    ///
    /// # Errors
    /// [`RobotError::InvalidSetting`] for bad `settings`, [`RobotError::DimensionMismatch`]
    /// when `spheres` has another number of links than `robot`, [`RobotError::NonFiniteValue`]
    /// for a non-finite base pose.
    pub fn new(
        robot: &'a RobotModel,
        collision: &'a RobotCollision,
        spheres: &'a RobotSpheres,
        scene: EdgeScene<'a>,
        base: [f64; 3],
        settings: &EdgeSettings,
    ) -> Result<Self, RobotError> {
        settings.validate()?;
        check_inputs(robot, spheres, base)?;
        let movers = movers(robot);
        let rho = spheres
            .links()
            .iter()
            .map(|l| {
                l.iter()
                    .map(|s| s.center.coords.norm() + s.radius)
                    .collect()
            })
            .collect();
        let obstacles = SphereObstacles::new(scene.model, scene.data, scene.exempt, scene.margin);
        Ok(ArmEdgeCheck {
            robot,
            collision,
            spheres,
            scene,
            obstacles,
            base,
            movers,
            rho,
            min_step: settings.min_step,
        })
    }

    /// Whether the straight motion from `a` to `b` (arm configurations) is certified free,
    /// both ends included (see the module's guarantee). `false` for configurations of the
    /// wrong length or with non-finite values.
    pub fn check(&self, a: &[f64], b: &[f64]) -> bool {
        let mut scratch = SphereData::default();
        let (Some(ca), Some(cb)) = (
            self.clearance(a, &mut scratch),
            self.clearance(b, &mut scratch),
        ) else {
            return false;
        };
        self.bisect(a, b, &ca, &cb, &mut scratch)
    }

    /// Accept `[a, b]`, or bisect it down to the minimum step.
    fn bisect(
        &self,
        a: &[f64],
        b: &[f64],
        ca: &Clearance,
        cb: &Clearance,
        scratch: &mut SphereData,
    ) -> bool {
        let delta: Vec<f64> = a.iter().zip(b).map(|(x, y)| (y - x).abs()).collect();
        if self.certified(&delta, ca, cb) {
            return true;
        }
        if delta.iter().map(|d| d * d).sum::<f64>().sqrt() <= self.min_step {
            return false;
        }
        let mid: Vec<f64> = a.iter().zip(b).map(|(x, y)| 0.5 * (x + y)).collect();
        let Some(cm) = self.clearance(&mid, scratch) else {
            return false;
        };
        self.bisect(a, &mid, ca, &cm, scratch) && self.bisect(&mid, b, &cm, cb, scratch)
    }

    /// The clearances at `q` (`None` if `q` has no pose).
    fn clearance(&self, q: &[f64], scratch: &mut SphereData) -> Option<Clearance> {
        let poses = self
            .robot
            .link_poses(&RobotConfig {
                base: self.base,
                arm: DVector::from_column_slice(q),
            })
            .ok()?;
        self.spheres.place(&poses, scratch);
        let mut spheres = Vec::new();
        self.obstacles.clearances(scratch, &mut spheres);
        // Where a pair's spheres meet, the exact distance of its shapes (also a lower bound).
        let pairs = self
            .spheres
            .checked_pairs()
            .iter()
            .map(|&(i, k)| {
                let spheres = self.spheres.pair_clearance(scratch, i, k);
                if spheres > 0.0 {
                    f64::from(spheres)
                } else {
                    self.collision.pair_distance(&poses, i, k)
                }
            })
            .collect();
        let links = self.link_clearances(&poses, &spheres, scratch);
        Some(Clearance {
            spheres,
            links,
            pairs,
        })
    }

    /// Per link, the larger of its least sphere clearance and, where that is under
    /// [`EXACT_BELOW`], its exact distance to the scene minus the margin.
    fn link_clearances(
        &self,
        poses: &[nalgebra::Isometry3<f64>],
        spheres: &[f32],
        scratch: &SphereData,
    ) -> Vec<f64> {
        let margin = if self.scene.margin > 0.0 {
            self.scene.margin
        } else {
            0.0
        };
        let mut s = 0;
        (0..scratch.links.len())
            .map(|l| {
                let n = scratch.links[l].1;
                let least = spheres[s..s + n]
                    .iter()
                    .copied()
                    .fold(f32::INFINITY, f32::min);
                s += n;
                if least >= EXACT_BELOW {
                    return f64::from(least);
                }
                let (model, data, exempt) = (self.scene.model, self.scene.data, self.scene.exempt);
                let exact = self
                    .collision
                    .link_scene_distance(poses, l, model, data, exempt);
                f64::from(least).max(exact - margin)
            })
            .collect()
    }

    /// The acceptance test of an interval with joint displacements `delta` (`|Δq_j|`).
    fn certified(&self, delta: &[f64], ca: &Clearance, cb: &Clearance) -> bool {
        // Per link: the bound is `offset + rho · turn` for a sphere with `rho`.
        let mut largest = Vec::with_capacity(self.movers.len());
        let mut s = 0;
        for (movers, rho) in self.movers.iter().zip(&self.rho) {
            let (mut offset, mut turn) = (0.0, 0.0);
            for m in movers {
                let d = delta[m.joint];
                if d > 0.0 {
                    offset += d * m.offset;
                    if m.revolute {
                        turn += d;
                    }
                }
            }
            let mut link_bound: f64 = 0.0;
            let mut spheres_pass = true;
            for &r in rho {
                let bound = offset + r * turn;
                spheres_pass &= f64::from(ca.spheres[s]) + f64::from(cb.spheres[s]) > bound;
                link_bound = link_bound.max(bound);
                s += 1;
            }
            let l = largest.len();
            if !(spheres_pass || ca.links[l] + cb.links[l] > link_bound) {
                return false;
            }
            largest.push(link_bound);
        }
        self.spheres
            .checked_pairs()
            .iter()
            .zip(ca.pairs.iter().zip(&cb.pairs))
            .all(|(&(i, k), (&da, &db))| da + db > largest[i] + largest[k])
    }
}

/// An arm joint that moves a link, in the module's bound for that link's spheres.
#[derive(Debug, Clone, Copy)]
struct Mover {
    /// The joint's index.
    joint: usize,
    /// Revolute or continuous: the sphere's `|c| + r` adds to its lever arm.
    revolute: bool,
    /// Revolute: the offsets from the joint's child link's origin down to the link's origin
    /// (a prismatic joint in between adds its largest travel). Prismatic: 1.
    offset: f64,
}

/// Per link ([`RobotModel::links`] order: the base, then the child of each arm joint), the
/// arm joints that move it: joint `j` moves links `j + 1 ..`.
/// The number of `robot`'s links, after checking that `spheres` covers as many and that `base`
/// is finite (the inputs of the edge and arm checks).
pub(super) fn check_inputs(
    robot: &RobotModel,
    spheres: &RobotSpheres,
    base: [f64; 3],
) -> Result<usize, RobotError> {
    let links = robot.links().len();
    if spheres.links().len() != links {
        return Err(RobotError::DimensionMismatch {
            what: "sphere model links",
            expected: links,
            got: spheres.links().len(),
        });
    }
    if let Some(index) = base.iter().position(|v| !v.is_finite()) {
        return Err(RobotError::NonFiniteValue {
            what: "base",
            index,
        });
    }
    Ok(links)
}

fn movers(robot: &RobotModel) -> Vec<Vec<Mover>> {
    let joints = robot.arm_joints();
    // The distance of link m + 1's origin from link m's origin, at most.
    let step: Vec<f64> = joints
        .iter()
        .map(|j| {
            let travel = match j.kind {
                ArmJointKind::Prismatic => j.lower.abs().max(j.upper.abs()),
                _ => 0.0,
            };
            j.parent_from_joint.translation.vector.norm() + travel
        })
        .collect();
    (0..robot.links().len())
        .map(|l| {
            (0..joints.len().min(l))
                .map(|j| {
                    let revolute = joints[j].kind != ArmJointKind::Prismatic;
                    Mover {
                        joint: j,
                        revolute,
                        offset: if revolute {
                            step[j + 1..l].iter().sum()
                        } else {
                            1.0
                        },
                    }
                })
                .collect()
        })
        .collect()
}
