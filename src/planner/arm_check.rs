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

    /// Whether `q` is free of self-collision and keeps `margin` from the scene. With the
    /// sphere fast path: self-collision is the exact test of the link pairs whose spheres
    /// meet, and the exact scene check runs only when some sphere reaches an obstacle.
    pub(super) fn valid(&self, q: &[f64]) -> bool {
        let ctx = self.ctx;
        let Some(poses) = self.poses(q) else {
            return false;
        };
        let exact_scene = || {
            ctx.collision
                .scene_collision(&poses, ctx.model, self.data, self.exempt, self.margin)
                .is_none()
        };
        match (ctx.spheres, &self.obstacles) {
            (Some(spheres), Some(obstacles)) => {
                let mut placed = SphereData::default();
                spheres.place(&poses, &mut placed);
                spheres
                    .self_collision_exact(&placed, ctx.collision, &poses)
                    .is_none()
                    && (obstacles.first_hit(&placed).is_none() || exact_scene())
            }
            _ => ctx.collision.self_collision(&poses).is_none() && exact_scene(),
        }
    }

    /// [`ArmCheck::valid`], and the robot's links keep `margin` from each other too
    /// ([`RobotCollision::self_collision_within`]): the check of the time shortcuts, which
    /// pull a path tight against whatever it goes round, the robot itself included.
    ///
    /// [`RobotCollision::self_collision_within`]: crate::kinematics::robot::RobotCollision::self_collision_within
    pub(super) fn valid_with_self_margin(&self, q: &[f64], margin: f64) -> bool {
        self.valid(q)
            && self.poses(q).is_some_and(|poses| {
                self.ctx
                    .collision
                    .self_collision_within(&poses, margin)
                    .is_none()
            })
    }

    /// What the robot touches at `q`, with URDF names (`None` if it is valid).
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
        )
        .map(|obstacle| Contact::Touches {
            obstacle,
            margin: self.margin,
        })
    }

    /// [`ArmCheck::hit`], or that nothing was found.
    pub(super) fn describe(&self, q: &[f64]) -> Contact {
        self.hit(q).unwrap_or(Contact::Unnamed)
    }
}
