//! How fast the robot's points can move: per link (against the world, the base held still) and
//! per checked link pair (one link against the other), as lever sums over the arm joints, for
//! conservative advancement along a timed arm motion
//! ([`RobotCollision::speed_bound`]).
//!
//! **Bound.** A point `p` of link `k` moves relative to link `i < k` with velocity
//! `Σ_j q̇_j·(ω_j × (p − o_j))` (revolute `j`) plus `Σ_j q̇_j·v_j` (prismatic `j`), over the
//! joints `i <= j < k`, so at speed at most `Σ_j |q̇_j|·λ_j`, with `λ_j` a bound on the distance
//! from joint `j`'s axis to any point of link `k` (1 for a prismatic joint). The levers are
//! those of the sphere model's motion bounds, computed here from the one sphere per link that
//! encloses the link's collision shapes. With every `|q̇_j| <= v_j` (the joints' velocity
//! limits), no point of link `k` moves faster than `Σ_j v_j·λ_j`: in time `Δt` its distance
//! to anything still (or to link `i`) shrinks by at most that times `Δt`.
//!
//! **Moving base.** The base turns about its vertical axis and translates: a point at
//! horizontal distance `ρ` from that axis moves at most `|v| + |ω|·ρ` faster on top of the
//! arm's share, with `|v|` the base's planar speed and `|ω|` its yaw rate. For the base link
//! `ρ` is bounded by its enclosing sphere's `|c| + r` (base frame); for an arm link by the arm
//! root's offset from the base origin plus the joint offsets down the chain (each prismatic
//! joint's largest travel added) plus the link's `|c| + r` ([`SpeedBound::link_radius`]).
//! [`ContactWalk`] walks a timed motion, of the arm or of the whole robot, with the steps
//! these bounds allow.

use super::super::spheres::{Sphere, chain_step, levers, reach};
use super::{Exempt, RobotCollision, RobotModel};
use crate::scene::{SceneData, SceneModel};

/// The speed bounds of one robot's links ([`RobotCollision::speed_bound`]): a point of link
/// `k` moves relative to link `i < k` (or to the world, `i` = the base) no faster than
/// `Σ_j |q̇_j|·λ_j` over the joints `i <= j < k`, `λ_j` a bound on the distance from joint
/// `j`'s axis to any point of link `k` (1 for a prismatic joint), from the sphere enclosing
/// the link's shapes and the joint offsets down the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedBound {
    /// Per link, `(arm joint, lever)` against the world (links without shapes: empty).
    links: Vec<Levers>,
    /// Per checked pair `(i, k)` of [`RobotCollision`], `(arm joint, lever)` of link `k`
    /// against link `i`.
    pairs: Vec<((usize, usize), Levers)>,
    /// Per link, a bound (m) on the distance of its points from the base's vertical axis at
    /// every arm configuration (0 for a link without shapes).
    radii: Vec<f64>,
}

/// `(arm joint, lever)` pairs: see [`SpeedBound`].
type Levers = Vec<(usize, f64)>;

impl SpeedBound {
    /// The highest speed (m/s) of any point of link `l` against the world when every arm
    /// joint `j` moves no faster than `velocity[j]` (rad/s or m/s; absolute values are
    /// taken, a missing entry counts as 0). 0 for a link without shapes or out of range.
    pub fn link_speed(&self, l: usize, velocity: &[f64]) -> f64 {
        self.links
            .get(l)
            .map_or(0.0, |levers| sum(levers, velocity))
    }

    /// A bound (m) on the distance of any point of link `l` from the base's vertical axis,
    /// whatever the arm configuration: the lever of the base's yaw (0 for a link without
    /// shapes or out of range).
    pub fn link_radius(&self, l: usize) -> f64 {
        self.radii.get(l).copied().unwrap_or(0.0)
    }

    /// The checked link pairs `(i, k)`, `i < k`, in the order of
    /// [`SpeedBound::pair_speed`].
    pub fn pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.pairs.iter().map(|(p, _)| *p)
    }

    /// The highest speed (m/s) of any point of the `p`-th checked pair's second link
    /// relative to its first under the same joint speeds (0 out of range).
    pub fn pair_speed(&self, p: usize, velocity: &[f64]) -> f64 {
        self.pairs
            .get(p)
            .map_or(0.0, |(_, levers)| sum(levers, velocity))
    }
}

fn sum(levers: &[(usize, f64)], velocity: &[f64]) -> f64 {
    levers
        .iter()
        .map(|&(j, lever)| velocity.get(j).map_or(0.0, |v| v.abs()) * lever)
        .sum()
}

impl RobotCollision {
    /// The speed bounds of `robot`'s links (this collision model's shapes, its checked pairs):
    /// see [`SpeedBound`]. `robot` must be the model this was compiled from.
    pub fn speed_bound(&self, robot: &RobotModel) -> SpeedBound {
        let covers: Vec<Vec<Sphere>> = self
            .spheres
            .iter()
            .map(|s| {
                s.map(|(center, radius)| Sphere { center, radius })
                    .into_iter()
                    .collect()
            })
            .collect();
        SpeedBound {
            links: (0..covers.len())
                .map(|l| {
                    if covers[l].is_empty() {
                        Vec::new()
                    } else {
                        levers(robot, &covers, 0, l)
                    }
                })
                .collect(),
            pairs: self
                .checked
                .iter()
                .map(|&(i, k)| ((i, k), levers(robot, &covers, i, k)))
                .collect(),
            radii: covers
                .iter()
                .enumerate()
                .map(|(l, cover)| radius(robot, cover, l))
                .collect(),
        }
    }
}

/// Link `l`'s bound on the distance of its points from the base's vertical axis: its
/// spheres' `|c| + r` (link frame), plus for an arm link (`l >= 1`, the child of arm joint
/// `l − 1`) the arm root's offset from the base origin and the joint offsets down the chain,
/// each prismatic joint's largest travel added (a chain of offsets reaches no farther than
/// their sum).
fn radius(robot: &RobotModel, cover: &[Sphere], l: usize) -> f64 {
    if cover.is_empty() {
        return 0.0;
    }
    let reach = reach(cover);
    if l == 0 {
        return reach;
    }
    let chain: f64 = robot.arm_joints().iter().take(l).map(chain_step).sum();
    robot.base_from_arm_root().translation.vector.norm() + chain + reach
}

/// A distance (m) at or below which [`ContactWalk`] counts two shapes as touching: the walk
/// would otherwise creep up to a contact in ever smaller steps.
pub const WALK_CONTACT: f64 = 1e-5;

/// An exact distance is computed again once its bound has fallen below this fraction of it.
const RECOMPUTE: f64 = 0.5;

/// Continuous contact check of a timed arm motion by conservative advancement: see
/// [`ContactWalk::first_contact`].
#[derive(Clone, Copy)]
pub struct ContactWalk<'a> {
    /// The robot.
    pub robot: &'a RobotModel,
    /// Its collision model.
    pub collision: &'a RobotCollision,
    /// Its speed bounds (`collision.speed_bound(robot)`).
    pub bound: &'a SpeedBound,
    /// The scene and its part poses, as [`RobotCollision::scene_collision`] takes them.
    pub model: &'a SceneModel,
    /// The part poses of `model`'s state (at every time, unless `scene_at` moves parts).
    pub data: &'a SceneData,
    /// Parts that move along the motion: fills the data with the part poses at a time
    /// (`false`: none there, which the walk reports as a contact). `None`: `data` throughout.
    pub scene_at: Option<&'a SceneAt<'a>>,
    /// The most any point of the parts `scene_at` moves travels per second (m/s): added to
    /// every link's speed against the scene. 0 for a still scene.
    pub scene_speed: f64,
    /// Which bodies some robot shapes may touch.
    pub exempt: Exempt<'a>,
    /// The base: still at a pose, or moving.
    pub base: WalkBase<'a>,
    /// Per arm joint, the most its speed reaches along the motion (rad/s or m/s; the
    /// joints' velocity limits for a trajectory timed under them).
    pub joint_speed: &'a [f64],
    /// Most configurations looked at before giving up ([`WalkOutcome::TooClose`]).
    pub max_steps: usize,
}

/// Fills scene data with the part poses at a time (`false`: none there): see
/// [`ContactWalk::scene_at`].
pub type SceneAt<'a> = dyn Fn(f64, &mut SceneData) -> bool + 'a;

/// The base along a [`ContactWalk`].
#[derive(Clone, Copy)]
pub enum WalkBase<'a> {
    /// Held still at this pose `[x, y, yaw]`.
    Still([f64; 3]),
    /// Moving: its pose at a time, and bounds on its speeds along the motion.
    Moving {
        /// The base pose `[x, y, yaw]` at a time (s).
        pose: &'a dyn Fn(f64) -> [f64; 3],
        /// The most its planar speed `|(ẋ, ẏ)|` reaches (m/s).
        linear: f64,
        /// The most its yaw rate `|ω|` reaches (rad/s).
        angular: f64,
    },
}

impl WalkBase<'_> {
    /// The pose at time `t`.
    fn at(&self, t: f64) -> [f64; 3] {
        match self {
            WalkBase::Still(b) => *b,
            WalkBase::Moving { pose, .. } => pose(t),
        }
    }

    /// The most a point at `radius` from the base's vertical axis moves per second with the
    /// base (0 for a still base).
    fn speed(&self, radius: f64) -> f64 {
        match self {
            WalkBase::Still(_) => 0.0,
            WalkBase::Moving {
                linear, angular, ..
            } => linear.abs() + angular.abs() * radius,
        }
    }
}

/// What [`ContactWalk::first_contact`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WalkOutcome {
    /// No link comes within [`WALK_CONTACT`] of the scene (under the exemption) or of a link
    /// it is checked against, anywhere on the motion; after this many configurations.
    Free {
        /// Configurations looked at.
        steps: usize,
    },
    /// A link comes within [`WALK_CONTACT`] at this time (or has no pose there).
    Contact {
        /// The time (s).
        t: f64,
    },
    /// `max_steps` configurations did not reach the end (the motion stays within a hair of
    /// something for long); the time reached.
    TooClose {
        /// The time (s).
        t: f64,
    },
}

impl ContactWalk<'_> {
    /// Walks `trajectory` (time → arm configuration) from `from` to `to` s by conservative
    /// advancement. At time `t` each link's exact distance `d_l` to the scene and each
    /// checked pair's `d_p` are known, or bounded below by an earlier exact value less the
    /// most its points can have moved since (computed again once that bound falls below half
    /// the value); no point of link `l` moves faster than [`SpeedBound::link_speed`] at
    /// `joint_speed` plus the base's share ([`WalkBase`], [`SpeedBound::link_radius`]) plus
    /// `scene_speed` (the pairs' distances do not depend on the base), so nothing touches
    /// before `t + min(d_l / s_l, d_p / s_p)`, the next time looked at. So no obstacle is
    /// passed between two looks, however thin, provided the trajectory's joint speeds stay
    /// within `joint_speed` and the base's within its bounds. `to` itself is looked at.
    pub fn first_contact(
        &self,
        trajectory: &dyn Fn(f64) -> Vec<f64>,
        from: f64,
        to: f64,
    ) -> WalkOutcome {
        let links = self.robot.links().len();
        let pairs: Vec<(usize, usize)> = self.bound.pairs().collect();
        let mut moved = self.scene_at.map(|_| self.data.clone());
        let speed: Vec<f64> = (0..links)
            .map(|l| {
                self.bound.link_speed(l, self.joint_speed)
                    + self.base.speed(self.bound.link_radius(l))
                    + self.scene_speed
            })
            .chain((0..pairs.len()).map(|p| self.bound.pair_speed(p, self.joint_speed)))
            .collect();
        // Per item (links, then pairs): the time and value of its last exact distance.
        let mut last: Vec<Option<(f64, f64)>> = vec![None; speed.len()];
        let mut t = from;
        for steps in 1..=self.max_steps {
            let arm = nalgebra::DVector::from_vec(trajectory(t));
            let Ok(poses) = self.robot.link_poses(&super::RobotConfig {
                base: self.base.at(t),
                arm,
            }) else {
                return WalkOutcome::Contact { t };
            };
            let data = match (&mut moved, self.scene_at) {
                (Some(buffer), Some(at)) => {
                    if !at(t, buffer) {
                        return WalkOutcome::Contact { t };
                    }
                    &*buffer
                }
                _ => self.data,
            };
            let mut step = f64::INFINITY;
            for (k, entry) in last.iter_mut().enumerate() {
                let v = speed[k];
                let d = match entry.map(|(tk, dk)| (dk - v * (t - tk), dk)) {
                    Some((b, dk)) if b > RECOMPUTE * dk => b,
                    _ => {
                        let d = if k < links {
                            self.collision.link_scene_distance(
                                &poses,
                                k,
                                self.model,
                                data,
                                self.exempt,
                            )
                        } else {
                            let (i, j) = pairs[k - links];
                            self.collision.pair_distance(&poses, i, j)
                        };
                        if d <= WALK_CONTACT {
                            return WalkOutcome::Contact { t };
                        }
                        *entry = Some((t, d));
                        d
                    }
                };
                if v > 0.0 {
                    step = step.min(d / v);
                }
            }
            if t >= to {
                return WalkOutcome::Free { steps };
            }
            t = (t + step).min(to);
        }
        WalkOutcome::TooClose { t }
    }
}
