//! The arm's validity during a step: self-collision and the scene under one exemption, with
//! what it touches named by URDF names.

use std::fmt;

use nalgebra::DVector;

use super::step::StepContext;
use crate::kinematics::robot::{Exempt, RobotConfig};
use crate::scene::SceneData;
use crate::scene::collision::BodyName;

/// The arm's validity at one base pose against one scene state, under one exemption: self
/// collision, and the scene within `margin` ([`RobotCollision::scene_collision`]).
pub(super) struct ArmCheck<'a> {
    pub ctx: &'a StepContext<'a>,
    pub base: [f64; 3],
    pub data: &'a SceneData,
    pub exempt: Exempt<'a>,
    pub margin: f64,
}

/// What an invalid arm configuration touches.
pub(super) enum Hit {
    /// The configuration has no pose (wrong length, not finite).
    Unposable,
    /// Two robot links.
    SelfCollision(String, String),
    /// A robot link within the margin of a scene body.
    Scene(String, BodyName, f64),
}

impl fmt::Display for Hit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Hit::Unposable => f.write_str("the arm configuration has no pose"),
            Hit::SelfCollision(a, b) => write!(f, "robot links {a:?} and {b:?} collide"),
            Hit::Scene(link, body, margin) => write!(
                f,
                "robot link {link:?} comes within {:.0} mm of {body}",
                1000.0 * margin
            ),
        }
    }
}

impl ArmCheck<'_> {
    /// The first thing the robot touches at arm configuration `q`, or `None` if it is valid.
    pub(super) fn hit(&self, q: &[f64]) -> Option<Hit> {
        let ctx = self.ctx;
        let cfg = RobotConfig {
            base: self.base,
            arm: DVector::from_column_slice(q),
        };
        let Ok(poses) = ctx.robot.link_poses(&cfg) else {
            return Some(Hit::Unposable);
        };
        let name = |l: usize| ctx.robot.links()[l].name.clone();
        if let Some((a, b)) = ctx.collision.self_collision(&poses) {
            return Some(Hit::SelfCollision(name(a), name(b)));
        }
        ctx.collision
            .scene_collision(&poses, ctx.model, self.data, self.exempt, self.margin)
            .map(|(l, body)| Hit::Scene(name(l), BodyName::of(ctx.model, body), self.margin))
    }

    pub(super) fn valid(&self, q: &[f64]) -> bool {
        self.hit(q).is_none()
    }

    /// [`ArmCheck::hit`] in words.
    pub(super) fn describe(&self, q: &[f64]) -> String {
        self.hit(q)
            .map_or_else(|| "no collision found".to_owned(), |h| h.to_string())
    }
}
