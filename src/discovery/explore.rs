//! One exploratory interaction (Algorithm 1, lines 11–20): grasp, then pull step by step with
//! GetComplianceAction and DetectFailure, and classify the motion for Reposition.

use nalgebra::{Isometry2, Isometry3, Point3, Unit, Vector3};

use super::cloud::{VoxelIndex, fit_plane, mean_nearest_distance, neighbourhood};
use super::error::{DiscoveryError, check_finite};
use super::interface::{PointCloud, Robot};
use super::log::{AttemptEnd, AttemptLog, MotionClass};
use super::settings::DiscoverySettings;

/// A new surface normal more than this far (rad) from the previous pull direction is ignored
/// (the plane fit latched onto another surface): 60°.
const MAX_NORMAL_TURN: f64 = std::f64::consts::FRAC_PI_3;

/// What one attempt needs.
pub(crate) struct AttemptInput<'a> {
    /// This attempt's pre-interaction observation (DetectFailure's reference).
    pub o_pre: &'a PointCloud,
    /// Where to grasp (m), map frame.
    pub hotspot: Point3<f64>,
    /// Outward surface normal at the hotspot: the approach is its opposite and the first pull
    /// goes along it.
    pub normal: Unit<Vector3<f64>>,
    /// The base pose the attempt is made from.
    pub world_from_base: Isometry2<f64>,
    /// The handle's first grasp point in an earlier attempt, if any: `target` and
    /// `sufficient_pull` count the contact's distance from it (the opening so far), not from
    /// this attempt's grasp.
    pub first_grasp: Option<Point3<f64>>,
    /// The attempt succeeds once the contact is this far (m) from `first_grasp` (or this
    /// attempt's grasp): `target_pull`, or `extra_pull` for a further pull.
    pub target: f64,
}

/// What one attempt produced.
pub(crate) struct AttemptResult {
    /// The log entry.
    pub log: AttemptLog,
    /// The contact at the grasp, if the grasp succeeded.
    pub grasp: Option<Point3<f64>>,
    /// The contact at the end, if the grasp succeeded.
    pub contact: Option<Point3<f64>>,
    /// The last trusted outward surface normal (or pull direction) at the contact.
    pub normal: Unit<Vector3<f64>>,
}

/// Checks a pose reported by the hardware.
pub(crate) fn checked_pose(
    pose: Isometry3<f64>,
    what: &'static str,
) -> Result<Isometry3<f64>, DiscoveryError> {
    check_finite(
        pose.translation
            .vector
            .iter()
            .chain(pose.rotation.coords.iter())
            .copied(),
        || what.to_string(),
    )?;
    Ok(pose)
}

/// Checks an observation from perception.
pub(crate) fn checked_cloud(cloud: &PointCloud, what: &str) -> Result<(), DiscoveryError> {
    let finite = cloud
        .points
        .iter()
        .flat_map(|p| p.coords.iter())
        .chain(cloud.origin.coords.iter())
        .chain(std::iter::once(&cloud.stamp))
        .all(|v| v.is_finite());
    if finite {
        Ok(())
    } else {
        Err(DiscoveryError::NonFinite {
            what: format!("{what} observation"),
        })
    }
}

/// GetComplianceAction's surface normal: a robust plane fit to the observation around the
/// contact, oriented towards the sensor (the visible, outward side).
pub(crate) fn surface_normal(
    cloud: &PointCloud,
    contact: &Point3<f64>,
    s: &DiscoverySettings,
) -> Option<Unit<Vector3<f64>>> {
    let near = neighbourhood(&cloud.points, contact, s.normal_radius);
    fit_plane(
        &near,
        s.min_normal_points,
        s.plane_inlier_distance,
        &cloud.origin,
    )
    .map(|p| p.normal)
}

/// Runs one attempt. Records `(time, world_from_ee)` into `ee_poses` while grasping (times
/// strictly increasing; a sample whose time does not advance is skipped).
///
/// # Errors
/// [`DiscoveryError::NonFinite`] for a NaN pose or observation.
pub(crate) fn attempt(
    robot: &mut dyn Robot,
    s: &DiscoverySettings,
    input: &AttemptInput<'_>,
    ee_poses: &mut Vec<(f64, Isometry3<f64>)>,
) -> Result<AttemptResult, DiscoveryError> {
    let mut log = AttemptLog {
        world_from_base: input.world_from_base,
        steps: 0,
        pull_distance: 0.0,
        displacement: None,
        rotation: 0.0,
        motion: MotionClass::NoMotion,
        end: AttemptEnd::Success,
    };
    let approach = -input.normal;
    let ee0 = match robot.grasp(&input.hotspot, &approach) {
        Ok(pose) => checked_pose(pose, "grasp pose")?,
        Err(failure) => {
            log.end = AttemptEnd::Grasp { failure };
            return Ok(AttemptResult {
                log,
                grasp: None,
                contact: None,
                normal: input.normal,
            });
        }
    };
    let mut record = |pose: Isometry3<f64>, t: f64| {
        if t.is_finite() && ee_poses.last().is_none_or(|(last, _)| t > *last) {
            ee_poses.push((t, pose));
        }
    };
    record(ee0, robot.time());
    let pre_index = VoxelIndex::new(&input.o_pre.points, s.displacement_cap);
    let mut pull = Pull::new(ee0, input);
    let mut end = None;
    for i in 1..=s.max_steps {
        end = pull.step(robot, s, i, &pre_index, &mut log, &mut record)?;
        if end.is_some() {
            break;
        }
    }
    Ok(pull.finish(log, end, s))
}

/// A pull in progress, from the grasp on: the end effector, the contact and the compliance
/// direction.
struct Pull {
    /// The end effector at the grasp.
    ee0: Isometry3<f64>,
    /// The end effector now.
    ee: Isometry3<f64>,
    /// The contact at the grasp.
    c0: Point3<f64>,
    /// Where the pull is measured from: the first grasp of the handle's attempts.
    origin: Point3<f64>,
    contact: Point3<f64>,
    prev_contact: Point3<f64>,
    /// The pull direction.
    dir: Unit<Vector3<f64>>,
    /// The first and the last surface normal seen near the contact.
    first_normal: Option<Unit<Vector3<f64>>>,
    last_normal: Option<Unit<Vector3<f64>>>,
    /// The last mean displacement of the observation near the contact.
    displacement: f64,
    /// The pull succeeds once the contact is this far (m) from `origin`.
    target: f64,
}

impl Pull {
    fn new(ee0: Isometry3<f64>, input: &AttemptInput<'_>) -> Self {
        let c0 = Point3::from(ee0.translation.vector);
        Pull {
            ee0,
            ee: ee0,
            c0,
            origin: input.first_grasp.unwrap_or(c0),
            contact: c0,
            prev_contact: c0,
            dir: input.normal,
            first_normal: None,
            last_normal: None,
            displacement: 0.0,
            target: input.target,
        }
    }

    /// Step `i`: observe and DetectFailure, GetComplianceAction, ApplyAction. `Some` ends the
    /// attempt.
    fn step(
        &mut self,
        robot: &mut dyn Robot,
        s: &DiscoverySettings,
        i: usize,
        pre_index: &VoxelIndex,
        log: &mut AttemptLog,
        record: &mut dyn FnMut(Isometry3<f64>, f64),
    ) -> Result<Option<AttemptEnd>, DiscoveryError> {
        let sensor = |e: &dyn std::fmt::Display| {
            Some(AttemptEnd::Sensor {
                reason: e.to_string(),
            })
        };
        // o' and DetectFailure (same camera as o_pre, so the sampling matches).
        let o_obs = match robot.observe(s.observation_camera) {
            Ok(o) => o,
            Err(e) => return Ok(sensor(&e)),
        };
        checked_cloud(&o_obs, "interaction")?;
        let near = neighbourhood(&o_obs.points, &self.contact, s.displacement_radius);
        self.displacement = mean_nearest_distance(&near, pre_index).unwrap_or(0.0);
        log.displacement = Some(self.displacement);
        if (self.contact - self.origin).norm() >= self.target {
            return Ok(Some(AttemptEnd::Success));
        }
        if i > s.stall_steps && self.displacement < s.displacement_threshold {
            return Ok(Some(AttemptEnd::NoDisplacement {
                displacement: self.displacement,
            }));
        }
        // GetComplianceAction.
        let o_int = if s.interaction_camera == s.observation_camera {
            o_obs
        } else {
            match robot.observe(s.interaction_camera) {
                Ok(o) => {
                    checked_cloud(&o, "interaction")?;
                    o
                }
                Err(e) => return Ok(sensor(&e)),
            }
        };
        let n = surface_normal(&o_int, &self.contact, s)
            .filter(|n| n.angle(&self.dir) <= MAX_NORMAL_TURN);
        if n.is_some() {
            self.first_normal = self.first_normal.or(n);
            self.last_normal = n;
        }
        self.dir = compliance_direction(n, &(self.contact - self.prev_contact), &self.dir, s);
        // ApplyAction.
        match robot.pull_step(&self.dir, s.step) {
            Ok(pose) => {
                self.ee = checked_pose(pose, "end-effector pose")?;
                record(self.ee, robot.time());
                self.prev_contact = self.contact;
                self.contact = Point3::from(self.ee.translation.vector);
                log.steps += 1;
                Ok(None)
            }
            Err(failure) => {
                let opened = (self.contact - self.origin).norm();
                Ok(Some(
                    if opened >= s.sufficient_pull && self.displacement >= s.displacement_threshold
                    {
                        AttemptEnd::SuccessAfter { failure }
                    } else {
                        AttemptEnd::Pull { failure }
                    },
                ))
            }
        }
    }

    /// The attempt's result: how it ended (`end`, or by the travel and displacement after the
    /// last step), the tracked rotation (the surface normal's turn, or the end effector's) and
    /// the motion class.
    fn finish(
        self,
        mut log: AttemptLog,
        end: Option<AttemptEnd>,
        s: &DiscoverySettings,
    ) -> AttemptResult {
        let travel = (self.contact - self.c0).norm();
        log.pull_distance = travel;
        log.end = end.unwrap_or(
            if self.displacement >= s.displacement_threshold && travel >= s.translation_threshold {
                AttemptEnd::Success
            } else {
                AttemptEnd::NoDisplacement {
                    displacement: self.displacement,
                }
            },
        );
        let (angle, axis) = match (self.first_normal, self.last_normal) {
            (Some(a), Some(b)) => {
                let c = a.cross(&b);
                (c.norm().atan2(a.dot(&b)), c)
            }
            _ => {
                let r = self.ee.rotation * self.ee0.rotation.inverse();
                (r.angle(), r.scaled_axis())
            }
        };
        log.rotation = angle;
        let displaced = self.displacement >= s.displacement_threshold;
        log.motion = classify(angle, &axis, travel, displaced, s);
        AttemptResult {
            log,
            grasp: Some(self.c0),
            contact: Some(self.contact),
            normal: self.last_normal.unwrap_or(self.dir),
        }
    }
}

/// The pull direction: the surface normal `n` blended with the last contact motion `motion`
/// (`surface_weight · n + (1 - surface_weight) · m̂`), either alone when the other is missing
/// (a motion shorter than a quarter step counts as missing), or the previous direction.
fn compliance_direction(
    n: Option<Unit<Vector3<f64>>>,
    motion: &Vector3<f64>,
    previous: &Unit<Vector3<f64>>,
    s: &DiscoverySettings,
) -> Unit<Vector3<f64>> {
    let m = (motion.norm() >= s.step / 4.0).then(|| motion.normalize());
    let blended = match (n, m) {
        (Some(n), Some(m)) => n.into_inner() * s.surface_weight + m * (1.0 - s.surface_weight),
        (Some(n), None) => n.into_inner(),
        (None, Some(m)) => m,
        (None, None) => previous.into_inner(),
    };
    Unit::try_new(blended, 1e-9).unwrap_or(*previous)
}

/// Reposition's joint-type classification from the tracked rotation (`angle` about `axis`,
/// any length) and the contact's translation.
fn classify(
    angle: f64,
    axis: &Vector3<f64>,
    travel: f64,
    displaced: bool,
    s: &DiscoverySettings,
) -> MotionClass {
    if !displaced {
        return MotionClass::NoMotion;
    }
    if angle >= s.rotation_threshold {
        let a = axis.try_normalize(1e-12).unwrap_or_else(Vector3::z);
        if a.z.abs() >= std::f64::consts::FRAC_1_SQRT_2 {
            // Clockwise seen from above (axis down) swings the free edge to the robot's left.
            return if a.z < 0.0 {
                MotionClass::RevoluteLeft
            } else {
                MotionClass::RevoluteRight
            };
        }
        return MotionClass::RevoluteHorizontal;
    }
    if travel >= s.translation_threshold {
        MotionClass::Prismatic
    } else {
        MotionClass::NoMotion
    }
}
