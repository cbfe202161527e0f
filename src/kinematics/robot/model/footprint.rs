//! The base's footprint: how far the robot's colliders reach from the base's vertical axis.

use nalgebra::{DVector, Isometry3};

use super::{RobotConfig, RobotModel};
use crate::scene::Collider;

impl RobotModel {
    /// The radius of the vertical cylinder about the base origin enclosing every collider at
    /// the neutral configuration (bounding spheres, so slightly conservative for boxes).
    pub(super) fn footprint_at_neutral(&self) -> f64 {
        self.footprint_at(&self.neutral)
    }

    /// The largest horizontal distance of the base link's colliders from the base's vertical
    /// axis: the chassis alone, whatever the arm does.
    pub(in crate::kinematics::robot) fn base_radius(&self) -> f64 {
        self.links[0]
            .colliders
            .iter()
            .map(|c| horizontal_reach(c, &Isometry3::identity()))
            .fold(0.0, f64::max)
    }

    /// The footprint radius with the arm at `arm`: the largest horizontal distance of any
    /// collider from the base's vertical axis (0 for a configuration of the wrong size).
    pub(in crate::kinematics::robot) fn footprint_at(&self, arm: &DVector<f64>) -> f64 {
        let config = RobotConfig {
            base: [0.0; 3],
            arm: arm.clone(),
        };
        let Ok(poses) = self.link_poses(&config) else {
            return 0.0;
        };
        let mut radius: f64 = 0.0;
        for (link, pose) in self.links.iter().zip(&poses) {
            for collider in &link.colliders {
                radius = radius.max(horizontal_reach(collider, pose));
            }
        }
        radius
    }
}

/// The largest horizontal distance from the world z axis of a collider placed at
/// `world_from_link`: exact for boxes (their corners), bounding sphere otherwise.
fn horizontal_reach(collider: &Collider, world_from_link: &Isometry3<f64>) -> f64 {
    use crate::scene::Shape;
    let world_from_shape = world_from_link * collider.part_from_shape;
    match &collider.shape {
        Shape::Cuboid { half_extents } => {
            let mut reach: f64 = 0.0;
            for k in 0..8 {
                let sign = |bit: usize| if k & bit == 0 { -1.0 } else { 1.0 };
                let corner = nalgebra::Point3::new(
                    sign(1) * half_extents.x,
                    sign(2) * half_extents.y,
                    sign(4) * half_extents.z,
                );
                let p = world_from_shape * corner;
                reach = reach.max(p.x.hypot(p.y));
            }
            reach
        }
        shape => {
            let sphere = shape.bounding_sphere();
            let c = world_from_shape * sphere.center;
            c.x.hypot(c.y) + sphere.radius
        }
    }
}
