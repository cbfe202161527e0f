//! What a manipulation plan at one base pose is: the arm's configurations along the grasp
//! trajectory, which waypoints they reach, and why the others fail.

use std::fmt;

use nalgebra::DVector;

use nalgebra::Isometry3;

use crate::kinematics::robot::{Exempt, RobotCollision, RobotModel};
use crate::scene::collision::Body;
use crate::scene::collision::BodyName;
use crate::scene::{PartId, SceneData, SceneModel};

/// The number of leading `true`s of `reached`.
pub(crate) fn reached_prefix(reached: &[bool]) -> usize {
    reached.iter().take_while(|r| **r).count()
}

/// What a robot configuration touches, by index and by URDF name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Obstacle {
    /// Two links of the robot, `(i, j)` with `i < j` (indices into
    /// [`RobotModel::links`](crate::kinematics::robot::RobotModel::links)), and their names
    /// (a link carrying other URDF links through fixed or frozen joints is named
    /// `link/urdf_link`, after the URDF link whose shape touches).
    SelfCollision(usize, usize, [String; 2]),
    /// A robot link and a scene body.
    Scene {
        /// The robot link.
        link: usize,
        /// The scene body within the margin.
        body: Body,
        /// The link's URDF name.
        link_name: String,
        /// The body's name.
        body_name: BodyName,
    },
}

impl Obstacle {
    /// What the robot at `link_poses` (world from link) touches, named: the first checked link
    /// pair within `self_margin` of each other
    /// ([`RobotCollision::self_collision_within`]), else the first link within `margin` of
    /// the scene in `data` under `exempt` ([`RobotCollision::scene_collision`]); `None` if it
    /// is free.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn at(
        robot: &RobotModel,
        collision: &RobotCollision,
        model: &SceneModel,
        link_poses: &[Isometry3<f64>],
        data: &SceneData,
        exempt: Exempt<'_>,
        margin: f64,
        self_margin: f64,
    ) -> Option<Obstacle> {
        if let Some((i, j)) = collision.self_collision_within(link_poses, self_margin) {
            return Some(Obstacle::self_collision(
                robot,
                collision,
                link_poses,
                (i, j),
            ));
        }
        collision
            .scene_contact(link_poses, model, data, exempt, margin)
            .map(|(link, collider, body)| {
                Obstacle::scene_named(robot, model, (link, body), Some(collider))
            })
    }

    /// Links `i` and `j` touching, named: each by its robot link name, followed by
    /// `/` and the URDF link of the touching collider when that is another URDF link merged
    /// into it (`base_footprint/l_forearm_link`: a frozen arm's forearm, carried by the base).
    pub(crate) fn self_collision(
        robot: &RobotModel,
        collision: &RobotCollision,
        link_poses: &[Isometry3<f64>],
        (i, j): (usize, usize),
    ) -> Obstacle {
        let merged = |l: usize| robot.links()[l].merged.len() > 1;
        let closest = (merged(i) || merged(j))
            .then(|| collision.closest_colliders(link_poses, i, j))
            .flatten();
        let name = |l: usize, c: Option<usize>| robot.links()[l].contact_name(c);
        Obstacle::SelfCollision(
            i,
            j,
            [name(i, closest.map(|c| c.0)), name(j, closest.map(|c| c.1))],
        )
    }

    /// A robot link touching a scene body, named.
    pub(crate) fn scene(robot: &RobotModel, model: &SceneModel, hit: (usize, Body)) -> Obstacle {
        Obstacle::scene_named(robot, model, hit, None)
    }

    /// A robot link touching a scene body, named; with the link's touching `collider`, a
    /// link that carries other URDF links is named `link/urdf_link` after the collider's.
    pub(crate) fn scene_named(
        robot: &RobotModel,
        model: &SceneModel,
        (link, body): (usize, Body),
        collider: Option<usize>,
    ) -> Obstacle {
        Obstacle::Scene {
            link,
            body,
            link_name: robot.links()[link].contact_name(collider),
            body_name: BodyName::of(model, body),
        }
    }
}

impl fmt::Display for Obstacle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Obstacle::SelfCollision(_, _, [a, b]) => {
                write!(f, "robot links {a:?} and {b:?} collide")
            }
            Obstacle::Scene {
                link_name,
                body_name,
                ..
            } => write!(f, "robot link {link_name:?} touches {body_name}"),
        }
    }
}

/// Why a waypoint does not count as reached.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq)]
pub enum WaypointFailure {
    /// The grasp point is farther from the first arm joint than the arm's length bound
    /// ([`arm_reach`](super::arm_reach)); IK was not tried.
    OutOfReach {
        /// Distance (m) from the first arm joint's origin to the grasp point.
        distance: f64,
        /// The arm's length bound (m).
        reach: f64,
    },
    /// IK did not converge; its best configuration's errors.
    NotConverged {
        /// Position error (m).
        position_error: f64,
        /// Rotation error (rad).
        rotation_error: f64,
    },
    /// The configuration misses the grasp frame by more than the tolerances (checked again
    /// with the robot's forward kinematics), or leaves the joint limits.
    OutOfTolerance {
        /// Position error (m).
        position_error: f64,
        /// Rotation error (rad).
        rotation_error: f64,
    },
    /// A joint moves more than [`ManipulationSettings::max_joint_jump`](super::ManipulationSettings::max_joint_jump) from the previous
    /// waypoint.
    Jump {
        /// The arm joint (index).
        joint: usize,
        /// The change (rad or m).
        jump: f64,
    },
    /// The configuration at the waypoint collides.
    Collision(Obstacle),
    /// The configuration is free but the motion from the previous waypoint collides.
    SegmentCollision(Obstacle),
    /// Not evaluated: the base pose had already lost to a better one.
    Skipped,
}

impl fmt::Display for WaypointFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WaypointFailure::OutOfReach { distance, reach } => write!(
                f,
                "out of reach ({distance:.3} m from the first arm joint, reach {reach:.3} m)"
            ),
            WaypointFailure::NotConverged {
                position_error,
                rotation_error,
            } => write!(
                f,
                "IK did not converge (errors {position_error:.2e} m, {rotation_error:.2e} rad)"
            ),
            WaypointFailure::OutOfTolerance {
                position_error,
                rotation_error,
            } => write!(
                f,
                "off the grasp frame or joint limits (errors {position_error:.2e} m, \
                 {rotation_error:.2e} rad)"
            ),
            WaypointFailure::Jump { joint, jump } => {
                write!(
                    f,
                    "arm joint {joint} jumps {jump:.3} from the previous waypoint"
                )
            }
            WaypointFailure::Collision(o) => write!(f, "collision: {o}"),
            WaypointFailure::SegmentCollision(o) => {
                write!(f, "collision on the way from the previous waypoint: {o}")
            }
            WaypointFailure::Skipped => write!(f, "not evaluated"),
        }
    }
}

/// The arm's configurations along the grasp trajectory at one base pose.
#[derive(Debug, Clone, PartialEq)]
pub struct ManipulationPlan {
    /// The base pose: x (m), y (m), yaw (rad).
    pub base: [f64; 3],
    /// The arm configuration at each waypoint (`K + 1`); at a waypoint not reached, the best
    /// attempt (or the previous configuration).
    pub arm: Vec<DVector<f64>>,
    /// Whether each waypoint is reached: IK converged, the tool is on the grasp frame within
    /// the tolerances, joints within limits, no jump from the previous waypoint if that was
    /// reached, and the robot free of collisions at the waypoint and on the way from the
    /// previous reached one.
    pub reached: Vec<bool>,
    /// Why each waypoint not reached failed (`None` where reached).
    pub failures: Vec<Option<WaypointFailure>>,
}

impl ManipulationPlan {
    /// Number of waypoints reached.
    pub fn reached_count(&self) -> usize {
        self.reached.iter().filter(|r| **r).count()
    }

    /// True when every waypoint is reached.
    pub fn is_complete(&self) -> bool {
        self.reached.iter().all(|r| *r)
    }

    /// The scene parts the robot touched at (or on the way to) a waypoint not reached.
    pub fn obstacle_parts(&self) -> impl Iterator<Item = PartId> + '_ {
        self.failures.iter().filter_map(|f| match f {
            Some(
                WaypointFailure::Collision(Obstacle::Scene {
                    body: Body::Part(part),
                    ..
                })
                | WaypointFailure::SegmentCollision(Obstacle::Scene {
                    body: Body::Part(part),
                    ..
                }),
            ) => Some(*part),
            _ => None,
        })
    }

    /// Number of waypoints reached before the first one that is not (all of them when
    /// complete).
    pub fn reached_prefix(&self) -> usize {
        reached_prefix(&self.reached)
    }

    /// Joint-space path length `Σ ‖q_{k+1} − q_k‖` (rad or m, Euclidean).
    pub fn path_length(&self) -> f64 {
        self.arm.windows(2).map(|w| (&w[1] - &w[0]).norm()).sum()
    }

    /// Smoothness cost `Σ ‖q_{k+1} − q_k‖²` (the optimiser's objective without its pull term).
    pub fn smoothness(&self) -> f64 {
        self.arm
            .windows(2)
            .map(|w| (&w[1] - &w[0]).norm_squared())
            .sum()
    }

    /// A one-line summary of the first failure, `None` if complete.
    pub fn reason(&self) -> Option<String> {
        let missed = self.reached.iter().filter(|r| !**r).count();
        let (k, failure) = self
            .failures
            .iter()
            .enumerate()
            .find_map(|(k, f)| f.as_ref().map(|f| (k, f)))?;
        Some(format!(
            "{missed} of {} waypoints not reached; first at waypoint {k}: {failure}",
            self.reached.len()
        ))
    }
}
