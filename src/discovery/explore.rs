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
    /// The handle's first grasp point in an earlier attempt, if any: `target_pull` and
    /// `sufficient_pull` count the contact's distance from it (the opening so far), not from
    /// this attempt's grasp.
    pub first_grasp: Option<Point3<f64>>,
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
    let c0 = Point3::from(ee0.translation.vector);
    let origin = input.first_grasp.unwrap_or(c0);
    let pre_index = VoxelIndex::new(&input.o_pre.points, s.displacement_cap);
    let mut ee = ee0;
    let mut contact = c0;
    let mut prev_contact = c0;
    let mut dir = input.normal;
    let mut first_normal: Option<Unit<Vector3<f64>>> = None;
    let mut last_normal: Option<Unit<Vector3<f64>>> = None;
    let mut displacement = 0.0;
    let mut end = None;
    for i in 1..=s.max_steps {
        // o' and DetectFailure (same camera as o_pre, so the sampling matches).
        let o_obs = match robot.observe(s.observation_camera) {
            Ok(o) => o,
            Err(e) => {
                end = Some(AttemptEnd::Sensor {
                    reason: e.to_string(),
                });
                break;
            }
        };
        checked_cloud(&o_obs, "interaction")?;
        let near = neighbourhood(&o_obs.points, &contact, s.displacement_radius);
        displacement = mean_nearest_distance(&near, &pre_index).unwrap_or(0.0);
        log.displacement = Some(displacement);
        if (contact - origin).norm() >= s.target_pull {
            end = Some(AttemptEnd::Success);
            break;
        }
        if i > s.stall_steps && displacement < s.displacement_threshold {
            end = Some(AttemptEnd::NoDisplacement { displacement });
            break;
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
                Err(e) => {
                    end = Some(AttemptEnd::Sensor {
                        reason: e.to_string(),
                    });
                    break;
                }
            }
        };
        let n = surface_normal(&o_int, &contact, s).filter(|n| n.angle(&dir) <= MAX_NORMAL_TURN);
        if n.is_some() {
            first_normal = first_normal.or(n);
            last_normal = n;
        }
        dir = compliance_direction(n, &(contact - prev_contact), &dir, s);
        // ApplyAction.
        match robot.pull_step(&dir, s.step) {
            Ok(pose) => {
                ee = checked_pose(pose, "end-effector pose")?;
                record(ee, robot.time());
                prev_contact = contact;
                contact = Point3::from(ee.translation.vector);
                log.steps += 1;
            }
            Err(failure) => {
                let opened = (contact - origin).norm();
                end = Some(
                    if opened >= s.sufficient_pull && displacement >= s.displacement_threshold {
                        AttemptEnd::SuccessAfter { failure }
                    } else {
                        AttemptEnd::Pull { failure }
                    },
                );
                break;
            }
        }
    }
    let travel = (contact - c0).norm();
    log.pull_distance = travel;
    log.end = end.unwrap_or(
        if displacement >= s.displacement_threshold && travel >= s.translation_threshold {
            AttemptEnd::Success
        } else {
            AttemptEnd::NoDisplacement { displacement }
        },
    );
    // The tracked rotation: the surface normal's turn, or the end effector's.
    let (angle, axis) = match (first_normal, last_normal) {
        (Some(a), Some(b)) => {
            let c = a.cross(&b);
            (c.norm().atan2(a.dot(&b)), c)
        }
        _ => {
            let r = ee.rotation * ee0.rotation.inverse();
            (r.angle(), r.scaled_axis())
        }
    };
    log.rotation = angle;
    let displaced = displacement >= s.displacement_threshold;
    log.motion = classify(angle, &axis, travel, displaced, s);
    Ok(AttemptResult {
        log,
        grasp: Some(c0),
        contact: Some(contact),
        normal: last_normal.unwrap_or(dir),
    })
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
