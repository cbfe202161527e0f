//! The arm's validity during a step: self-collision and the scene under one exemption, with
//! what it touches named by URDF names.

use nalgebra::DVector;

use super::step::{Contact, StepContext};
use crate::kinematics::robot::{Exempt, RobotConfig, SphereData, SphereObstacles};
use crate::motion::placement::Obstacle;
use crate::scene::SceneData;

/// The arm's validity at one base pose against one scene state, under one exemption: self
/// collision, and the scene within `margin` ([`RobotCollision::scene_collision`]).
///
/// With `obstacles` (the scene state as [`SphereObstacles`] under the same exemption and
/// margin) and the context's sphere model, [`ArmCheck::valid`] takes the sphere fast path:
/// the same answers, see [`PlannerSettings::arm_spheres`](super::PlannerSettings::arm_spheres).
///
/// [`RobotCollision::scene_collision`]: crate::kinematics::robot::RobotCollision::scene_collision
pub(super) struct ArmCheck<'a> {
    pub ctx: &'a StepContext<'a>,
    pub base: [f64; 3],
    pub data: &'a SceneData,
    pub exempt: Exempt<'a>,
    pub margin: f64,
    /// The clearance (m) the robot's checked link pairs keep from each other; 0: touching is
    /// the only self-collision. The free phases keep one (see `StepRefinement::free_arm`).
    pub self_margin: f64,
    pub obstacles: Option<SphereObstacles>,
}

impl ArmCheck<'_> {
    /// The robot's link poses at arm configuration `q` (`None`: `q` has no pose).
    fn poses(&self, q: &[f64]) -> Option<Vec<nalgebra::Isometry3<f64>>> {
        let cfg = RobotConfig {
            base: self.base,
            arm: DVector::from_column_slice(q),
        };
        self.ctx.robot.link_poses(&cfg).ok()
    }

    /// Whether `q` is free of self-collision (keeping `self_margin` between checked links)
    /// and keeps `margin` from the scene. With the sphere fast path: the exact scene check
    /// runs only when some sphere reaches an obstacle, and without a self-clearance
    /// self-collision is the exact test of the link pairs whose spheres meet.
    pub(super) fn valid(&self, q: &[f64]) -> bool {
        let ctx = self.ctx;
        let Some(poses) = self.poses(q) else {
            return false;
        };
        let placed = ctx
            .spheres
            .filter(|_| self.obstacles.is_some())
            .map(|spheres| {
                let mut placed = SphereData::default();
                spheres.place(&poses, &mut placed);
                (spheres, placed)
            });
        let self_free = match &placed {
            _ if self.self_margin > 0.0 => ctx
                .collision
                .self_collision_within(&poses, self.self_margin)
                .is_none(),
            Some((spheres, placed)) => spheres
                .self_collision_exact(placed, ctx.collision, &poses)
                .is_none(),
            None => ctx.collision.self_collision(&poses).is_none(),
        };
        let sphere_free = match (&placed, &self.obstacles) {
            (Some((_, placed)), Some(obstacles)) => obstacles.first_hit(placed).is_none(),
            _ => false,
        };
        self_free
            && (sphere_free
                || ctx
                    .collision
                    .scene_collision(&poses, ctx.model, self.data, self.exempt, self.margin)
                    .is_none())
    }

    /// What the robot touches at `q`, with URDF names (`None` if it is valid): two links
    /// within the self-clearance, or a link within the margin of the scene.
    pub(super) fn hit(&self, q: &[f64]) -> Option<Contact> {
        let ctx = self.ctx;
        let Some(poses) = self.poses(q) else {
            return Some(Contact::NoPose);
        };
        Obstacle::at(
            ctx.robot,
            ctx.collision,
            ctx.model,
            &poses,
            self.data,
            self.exempt,
            self.margin,
            self.self_margin,
        )
        .map(|obstacle| Contact::Touches {
            margin: match obstacle {
                Obstacle::SelfCollision(..) => self.self_margin,
                Obstacle::Scene { .. } => self.margin,
            },
            obstacle,
        })
    }

    /// [`ArmCheck::hit`], or that nothing was found.
    pub(super) fn describe(&self, q: &[f64]) -> Contact {
        self.hit(q).unwrap_or(Contact::Unnamed)
    }
}
