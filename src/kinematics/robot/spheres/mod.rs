//! A sphere-approximated robot: each link's collision geometry covered by a few spheres, for
//! fast conservative collision checks ([`RobotSpheres`], [`SphereObstacles`]).
//!
//! **Guarantee (conservative).** Every point of a link's exact collision shapes (the shapes
//! [`RobotCollision`] checks) lies inside some sphere of that link; every radius is further
//! grown by [`SphereSettings::padding`]. So when no sphere of a link meets an obstacle (or a
//! sphere of another link), neither does the link's exact geometry: *spheres free ⇒ exact
//! free*. The converse does not hold; a sphere hit is only a reason to run the exact check.
//! The per-shape coverings are described, with their proofs, in the `cover` module's source
//! (`src/kinematics/robot/spheres/cover.rs`).
//!
//! **Budget.** A link gets at most [`SphereSettings::max_per_link`] spheres, shared among its
//! shapes in proportion to their bounding-sphere volumes, at least one per shape: a link with
//! more shapes than the budget gets one sphere per shape.
//!
//! **Distance tables.** A checked self-collision pair whose relative pose depends on one or
//! two joints (links two joints apart, such as the Panda's `link5` and `link7` with the hand,
//! a few centimetres apart while their spheres overlap) also gets a table of parry's distances
//! over those joints, built once with the model: [`RobotSpheres::pair_distance_bound`] turns
//! it into a certified lower bound on the exact distance at any configuration, so that
//! [`ArmCheck`] decides such a pair without parry wherever the bound is positive.
//!
//! The model is immutable and `Send + Sync`; placing it at a configuration writes into a
//! caller-owned [`SphereData`] ([`RobotSpheres::place`]).
//!
//! # Example
//! ```
//! use kinscene::kinematics::robot::{
//!     RobotCollision, RobotConfig, RobotModel, RobotSpheres, SphereData, SphereSettings,
//! };
//!
//! let robot = RobotModel::kinova_gen3_mobile();
//! let collision = RobotCollision::new(&robot)?;
//! let settings = SphereSettings { padding: 0.005, max_per_link: 8 };
//! let spheres = RobotSpheres::new(&robot, &collision, &settings)?;
//! assert!(spheres.links().iter().all(|l| l.len() <= 8));
//! let poses = robot.link_poses(&RobotConfig { base: [0.0; 3], arm: robot.neutral() })?;
//! let mut data = SphereData::default();
//! spheres.place(&poses, &mut data);
//! // The neutral configuration is free of self-collision, so the exact check agrees with
//! // whatever the spheres say when they say "free".
//! if spheres.self_collision(&data).is_none() {
//!     assert!(collision.self_collision(&poses).is_none());
//! }
//! # Ok::<(), kinscene::kinematics::robot::RobotError>(())
//! ```

mod arm;
mod check;
mod clip;
mod cover;
mod edge;
mod levers;
mod obstacles;
mod table;

use nalgebra::Point3;

use super::{RobotCollision, RobotError, RobotModel};
use crate::InvalidSetting;

pub use arm::{ArmCheck, ArmCheckData, CONTACT_CLEARANCE, CONTINUOUS_BAND, MAX_CONTINUOUS_STATES};
pub use check::{SPHERE_SLACK, SphereData};
pub use cover::CELL_SLACK;
pub use edge::EdgeScene;
pub(crate) use levers::{chain_step, levers, reach};
pub use obstacles::SphereObstacles;

/// A sphere: centre and radius (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Centre (m), in the frame the sphere is expressed in.
    pub center: Point3<f64>,
    /// Radius (m).
    pub radius: f64,
}

impl Sphere {
    /// The sphere of `radius` around `center`.
    pub fn new(center: Point3<f64>, radius: f64) -> Self {
        Sphere { center, radius }
    }

    /// Whether `p` lies within `radius + tolerance` of the centre.
    pub fn contains(&self, p: &Point3<f64>, tolerance: f64) -> bool {
        (p - self.center).norm() <= self.radius + tolerance
    }
}

/// How to build a [`RobotSpheres`].
#[derive(Debug, Clone, PartialEq)]
pub struct SphereSettings {
    /// Added to every sphere's radius (m): finite and `>= 0`. Default 0.
    pub padding: f64,
    /// The most spheres per link (see the module's budget rule): `>= 1`. More spheres fit the
    /// geometry more tightly (fewer exact checks) and cost more per sphere check. Default 12.
    pub max_per_link: usize,
}

impl Default for SphereSettings {
    fn default() -> Self {
        SphereSettings {
            padding: 0.0,
            max_per_link: 12,
        }
    }
}

impl SphereSettings {
    /// Checks the padding (finite, `>= 0`) and the budget (`>= 1`).
    ///
    /// # Errors
    /// [`InvalidSetting`] naming the field.
    pub fn validate(&self) -> Result<(), InvalidSetting> {
        if !(self.padding.is_finite() && self.padding >= 0.0) {
            return Err(InvalidSetting::new(
                "padding",
                self.padding,
                "finite and >= 0",
            ));
        }
        if self.max_per_link == 0 {
            return Err(InvalidSetting::new("max_per_link", 0.0, "at least 1"));
        }
        Ok(())
    }
}

/// The robot's links as unions of spheres (link frames), with the self-collision pairs of the
/// [`RobotCollision`] it was built from. Immutable, `Send + Sync`.
#[derive(Debug, Clone)]
pub struct RobotSpheres {
    /// Per link, its spheres (link frame, padded).
    links: Vec<Vec<Sphere>>,
    /// Link pairs `(i, j)`, `i < j`, checked for self-collision.
    checked: Vec<(usize, usize)>,
    /// Per checked pair, its distance table when its relative pose depends on one or two
    /// joints (the `table` module).
    tables: Vec<Option<table::PairTable>>,
    /// Where [`RobotSpheres::place`] puts the spheres, with their kinds (base link, contact
    /// shape: fingers, pads).
    layout: check::Layout,
}

impl RobotSpheres {
    /// Covers every link's collision shapes with spheres (see the module's guarantee and
    /// budget), and takes `collision`'s self-collision pairs (the pairs of links with shapes
    /// that are not in [`RobotCollision::allowed_pairs`]) and base links.
    ///
    /// # Errors
    /// [`RobotError::InvalidSetting`] for bad `settings` ([`SphereSettings::validate`]);
    /// [`RobotError::Collision`] if parry cannot build a mesh's hull.
    pub fn new(
        robot: &RobotModel,
        collision: &RobotCollision,
        settings: &SphereSettings,
    ) -> Result<RobotSpheres, RobotError> {
        settings.validate()?;
        let mut links = Vec::with_capacity(robot.links().len());
        let mut contact = Vec::with_capacity(robot.links().len());
        for link in robot.links() {
            let weights: Vec<f64> = link
                .colliders
                .iter()
                .map(|c| c.shape.bounding_sphere().radius.powi(3))
                .collect();
            let shares = shares(&weights, settings.max_per_link);
            let (mut spheres, mut flags) = (Vec::new(), Vec::new());
            for ((collider, is_contact), share) in link.colliders_with_contact().zip(shares) {
                let covered = cover::cover(&collider.shape, share).map_err(|message| {
                    RobotError::Collision {
                        link: link.name.clone(),
                        message,
                    }
                })?;
                for s in covered {
                    spheres.push(Sphere::new(
                        collider.part_from_shape * s.center,
                        s.radius + settings.padding,
                    ));
                    flags.push(is_contact);
                }
            }
            links.push(spheres);
            contact.push(flags);
        }
        let allowed = collision.allowed_pairs();
        let n = links.len();
        let checked = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                !links[i].is_empty() && !links[j].is_empty() && !allowed.contains(&(i, j))
            })
            .collect::<Vec<_>>();
        let tables = checked
            .iter()
            .map(|&(i, k)| table::PairTable::build(robot, collision, &links, i, k))
            .collect();
        let base_links = collision.base_links().to_vec();
        let layout = check::Layout::new(&links, &contact, &base_links);
        Ok(RobotSpheres {
            links,
            checked,
            tables,
            layout,
        })
    }

    /// Per link (as [`RobotModel::links`]), its spheres in the link frame, padding included.
    pub fn links(&self) -> &[Vec<Sphere>] {
        &self.links
    }

    /// The number of spheres of all links.
    pub fn count(&self) -> usize {
        self.links.iter().map(Vec::len).sum()
    }

    /// The link pairs `(i, j)`, `i < j`, checked for self-collision.
    pub fn checked_pairs(&self) -> &[(usize, usize)] {
        &self.checked
    }

    /// A lower bound (m) on the exact distance ([`RobotCollision::pair_distance`]) of checked
    /// pair `p` (index into [`RobotSpheres::checked_pairs`]) at arm configuration `q`, from
    /// the pair's distance table, without parry; `−∞` for a pair without one, outside the
    /// table or for `p` out of range. A pair gets a table when its relative pose depends on
    /// one or two joints of finite range (or continuous): parry's distances on a grid over
    /// those joints, each less the most the pair can close in from the grid node (the lever
    /// bound), see the `table` module's source (`src/kinematics/robot/spheres/table.rs`).
    pub fn pair_distance_bound(&self, p: usize, q: &[f64]) -> f64 {
        match self.tables.get(p) {
            Some(Some(t)) => t.lower_bound(q),
            _ => f64::NEG_INFINITY,
        }
    }
}

/// Splits `budget` among shapes in proportion to `weights`, at least 1 each, the sum at most
/// `max(budget, weights.len())`.
fn shares(weights: &[f64], budget: usize) -> Vec<usize> {
    let total: f64 = weights.iter().sum();
    let mut shares: Vec<usize> = weights
        .iter()
        .map(|w| {
            let share = if total > 0.0 {
                (budget as f64 * w / total).floor() as usize
            } else {
                budget / weights.len().max(1)
            };
            share.max(1)
        })
        .collect();
    while shares.iter().sum::<usize>() > budget.max(weights.len()) {
        if let Some(largest) = shares.iter_mut().max() {
            *largest -= 1;
        }
    }
    shares
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_fit_the_budget_with_one_per_shape() {
        assert_eq!(shares(&[1.0, 1.0, 1000.0], 3), vec![1, 1, 1]);
        assert_eq!(shares(&[1.0, 3.0], 8), vec![2, 6]);
        assert_eq!(shares(&[1.0, 1.0, 1.0], 2), vec![1, 1, 1]);
        assert_eq!(shares(&[0.0], 5), vec![5]);
    }

    #[test]
    fn bad_settings_are_typed_errors() {
        for (padding, max) in [(f64::NAN, 4), (-0.1, 4), (f64::INFINITY, 4), (0.0, 0)] {
            let settings = SphereSettings {
                padding,
                max_per_link: max,
            };
            assert!(settings.validate().is_err());
        }
    }
}
