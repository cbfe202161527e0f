//! The attempts of one handle: grasp and pull, regrasp where the handle is re-detected,
//! Reposition between attempts, and what the attempts leave for the estimators.

use nalgebra::{Isometry2, Isometry3, Point2, Point3, Unit, Vector2, Vector3};

use crate::discovery::error::{DiscoveryError, check_finite};
use crate::discovery::explore::{AttemptInput, attempt, checked_cloud};
use crate::discovery::interface::{HardwareFailure, LocalGoal, PointCloud};
use crate::discovery::log::{AttemptEnd, AttemptLog, HandleLog, MotionClass, Stage};
use crate::discovery::placement::{FreeSpace, plan_base, plan_base_avoiding, shifted};
use crate::discovery::settings::DiscoverySettings;

use super::{Near, Pulled, Run, Stop, fail};

/// What the attempts left: the first grasp's pre-interaction observation and contact, the
/// last contact, the end-effector poses, where each grasp's poses begin, whether an attempt
/// succeeded, and the base pose and last tracked normal of the last attempt that grasped after
/// it (or of the last attempt).
pub(super) struct Attempts {
    first: Option<(PointCloud, Point3<f64>)>,
    contact_post: Option<Point3<f64>>,
    ee_poses: Vec<(f64, Isometry3<f64>)>,
    segments: Vec<usize>,
    success: bool,
    base: Isometry2<f64>,
    normal: Unit<Vector3<f64>>,
}

impl Run<'_> {
    /// The exploratory interaction at handle `p` (outward normal `normal`): up to
    /// `max_attempts` attempts from `b_pre` until one succeeds (one that succeeded short of
    /// the target on a failure signal is pulled on: `resume_short_pulls`), each logged in
    /// `entry`, with Reposition between them. A retry grasps at the last contact (the part's path stays
    /// that of one point, as the estimators assume), or, after a grasp that missed the handle,
    /// where it is re-detected ([`Run::regrasp_target`]).
    pub(super) fn attempts(
        &mut self,
        entry: &mut HandleLog,
        index: usize,
        p: Point3<f64>,
        normal: Unit<Vector3<f64>>,
        mut b_pre: Isometry2<f64>,
        free: &FreeSpace,
    ) -> Result<Attempts, Stop> {
        let s = self.s;
        let mut hotspot = p;
        let mut hot_normal = normal;
        let mut out = Attempts {
            first: None,
            contact_post: None,
            ee_poses: Vec::new(),
            segments: Vec::new(),
            success: false,
            base: b_pre,
            normal,
        };
        // Whether the last attempt's gripper closed where the handle was not.
        let mut missed = false;
        // The base goals the robot's navigation refused.
        let mut refused: Vec<Point2<f64>> = Vec::new();
        for k in 0..s.max_attempts {
            let goal = LocalGoal {
                target: hotspot,
                world_from_base: b_pre,
            };
            if let Err(failure) = self.robot.navigate_local(&goal) {
                entry
                    .attempts
                    .push(skipped(b_pre, AttemptEnd::Navigation { failure }));
                // Something the map does not hold stands within the robot's radius of the
                // refused goal: the next attempt goes to the free pose nearest the same
                // distance from the handle that keeps the robot radius from every refused
                // goal (the same goal again would be refused again).
                let at = Point2::from(b_pre.translation.vector);
                refused.push(at);
                let from_target = at - Point2::new(hotspot.x, hotspot.y);
                if let Some(b) = from_target.try_normalize(1e-9).and_then(|dir| {
                    plan_base_avoiding(
                        free,
                        &hotspot,
                        &dir,
                        from_target.norm(),
                        s.base_search_radius,
                        &refused,
                        s.robot_radius,
                    )
                }) {
                    entry.notes.push(format!(
                        "attempt {}: navigation refused the base goal ({:.2}, {:.2}); the next \
                         attempt starts from ({:.2}, {:.2}), at least {} m from every refused \
                         goal",
                        k + 1,
                        at.x,
                        at.y,
                        b.translation.x,
                        b.translation.y,
                        s.robot_radius
                    ));
                    b_pre = b;
                }
                continue;
            }
            if missed {
                hotspot = self.regrasp_target(entry, index, k, hotspot)?;
            }
            let o_pre = match self.robot.observe(s.observation_camera) {
                Ok(o) => o,
                Err(e) => {
                    let reason = e.to_string();
                    entry
                        .attempts
                        .push(skipped(b_pre, AttemptEnd::Sensor { reason }));
                    continue;
                }
            };
            checked_cloud(&o_pre, "pre-interaction")?;
            let input = AttemptInput {
                o_pre: &o_pre,
                hotspot,
                normal: hot_normal,
                world_from_base: b_pre,
                first_grasp: out.first.as_ref().map(|(_, g)| *g),
                target: s.target_pull,
            };
            let seg = out.ee_poses.len();
            let result = attempt(&mut *self.robot, s, &input, &mut out.ee_poses)?;
            if out.ee_poses.len() > seg {
                out.segments.push(seg);
            }
            if let (None, Some(g)) = (&out.first, result.grasp) {
                out.first = Some((o_pre.clone(), g));
            }
            if let Some(c) = result.contact {
                hotspot = c;
                out.contact_post = Some(c);
            }
            hot_normal = result.normal;
            // After a success, only an attempt that grasped again moves the pose further
            // pulls return to.
            if !out.success || result.contact.is_some() {
                out.normal = result.normal;
                out.base = b_pre;
            }
            missed = matches!(
                result.log.end,
                AttemptEnd::Grasp {
                    failure: HardwareFailure::GraspLost
                }
            );
            let motion = result.log.motion;
            // A pull that stopped short of the target on a failure signal is a success, but
            // the next attempt (if any) pulls on from its last contact.
            let short = matches!(result.log.end, AttemptEnd::SuccessAfter { .. })
                && s.resume_short_pulls
                && k + 1 < s.max_attempts
                && opening(&out.first, &hotspot) < s.target_pull;
            out.success |= result.log.end.is_success();
            entry.attempts.push(result.log);
            if let Err(f) = self.robot.retract() {
                return fail(Stage::Exploration, format!("retract: {f}"));
            }
            if out.success && !short {
                break;
            }
            // Reposition.
            b_pre = reposition(free, &b_pre, motion, &hotspot, s).unwrap_or(b_pre);
        }
        Ok(out)
    }

    /// The grasp point of attempt `k` (from 0) after an attempt whose gripper closed on no
    /// handle at `last` (`GraspLost` at the grasp): the handle re-detected near `last`, else
    /// `last` again. The handle was not where the gripper closed: a re-detection that landed
    /// beyond the gripper's reach of it, or a part that moved on after the last contact
    /// (under a pull step the arm could not follow, or settling after the release); the same
    /// point would miss it again. A note records which.
    fn regrasp_target(
        &mut self,
        entry: &mut HandleLog,
        index: usize,
        k: usize,
        last: Point3<f64>,
    ) -> Result<Point3<f64>, Stop> {
        Ok(match self.detect_near(index, &last)? {
            Near::Found(q) => {
                entry.notes.push(format!(
                    "attempt {}: the gripper missed the handle at the last grasp point; \
                     re-detected {:.3} m from it",
                    k + 1,
                    (q - last).norm()
                ));
                q
            }
            Near::Missed { .. } | Near::Failed(_) => {
                entry.notes.push(format!(
                    "attempt {}: the gripper missed the handle at the last grasp point; not \
                     re-detected within {} m of it, grasping there again",
                    k + 1,
                    self.s.redetect_radius
                ));
                last
            }
        })
    }

    /// Steps back from the handle at `p` (approach direction `dir`) to observe the part at
    /// `contact_post`; when it cannot, a note says the observation is taken from where the
    /// robot is.
    pub(super) fn step_back(
        &mut self,
        entry: &mut HandleLog,
        p: &Point3<f64>,
        dir: &Vector2<f64>,
        contact_post: Point3<f64>,
        free: &FreeSpace,
    ) {
        let s = self.s;
        let back = plan_base(
            free,
            p,
            dir,
            s.interaction_distance + s.post_step_back,
            s.base_search_radius,
        );
        match back {
            Some(b_post) => {
                let goal = LocalGoal {
                    target: contact_post,
                    world_from_base: b_post,
                };
                if let Err(f) = self.robot.navigate_local(&goal) {
                    entry.notes.push(format!(
                        "step back failed ({f}); observed from where the robot is"
                    ));
                }
            }
            None => entry
                .notes
                .push("no free step-back pose; observed from where the robot is".into()),
        }
    }

    /// The horizontal direction from `p` to the robot's base (fallback approach direction).
    pub(super) fn toward_robot(&self, p: &Point3<f64>) -> Result<Vector2<f64>, DiscoveryError> {
        let b = self.robot.base_pose();
        check_finite(
            b.translation
                .vector
                .iter()
                .copied()
                .chain([b.rotation.angle()]),
            || "base pose".to_string(),
        )?;
        Ok(b.translation.vector - Vector2::new(p.x, p.y))
    }
}

/// The attempts' outcome, with the pull distance recorded in `entry`: on success the first
/// grasp and the last contact; otherwise a failure of navigation (when every attempt failed
/// there) or of exploration, with the last attempt's end.
pub(super) fn pulled(entry: &mut HandleLog, attempts: Attempts) -> Result<Pulled, Stop> {
    if let (Some((_, g)), Some(c)) = (&attempts.first, attempts.contact_post) {
        entry.pull_distance = (c - g).norm();
    }
    let (Some((o_first, contact_pre)), Some(contact_post), true) =
        (attempts.first, attempts.contact_post, attempts.success)
    else {
        let stage = if entry
            .attempts
            .iter()
            .all(|a| matches!(a.end, AttemptEnd::Navigation { .. }))
        {
            Stage::Navigation
        } else {
            Stage::Exploration
        };
        let reason = entry
            .attempts
            .last()
            .map(|a| format!("{} attempts; last: {:?}", entry.attempts.len(), a.end))
            .unwrap_or_else(|| "no attempt".into());
        return fail(stage, reason);
    };
    Ok(Pulled {
        o_first,
        contact_pre,
        contact_post,
        ee_poses: attempts.ee_poses,
        segments: attempts.segments,
        base: attempts.base,
        normal: attempts.normal,
    })
}

/// The log entry of an attempt that did not get to the grasp.
pub(super) fn skipped(world_from_base: Isometry2<f64>, end: AttemptEnd) -> AttemptLog {
    AttemptLog {
        world_from_base,
        steps: 0,
        pull_distance: 0.0,
        displacement: None,
        rotation: 0.0,
        motion: MotionClass::NoMotion,
        end,
    }
}

/// The contact's distance from the first grasp point: the opening so far (0 before a grasp).
fn opening(first: &Option<(PointCloud, Point3<f64>)>, contact: &Point3<f64>) -> f64 {
    first.as_ref().map_or(0.0, |(_, g)| (contact - g).norm())
}

/// Reposition: the new pre-interaction pose after a failed attempt (see
/// [`discover`](super::discover)).
fn reposition(
    free: &FreeSpace,
    b_pre: &Isometry2<f64>,
    motion: MotionClass,
    hotspot: &Point3<f64>,
    s: &DiscoverySettings,
) -> Option<Isometry2<f64>> {
    let d = s.reposition_distance;
    let in_base = match motion {
        MotionClass::RevoluteLeft => Vector2::new(0.0, d),
        MotionClass::RevoluteRight => Vector2::new(0.0, -d),
        MotionClass::Prismatic | MotionClass::RevoluteHorizontal => Vector2::new(-d, 0.0),
        MotionClass::NoMotion => Vector2::zeros(),
    };
    let shift = b_pre.rotation * in_base;
    shifted(free, b_pre, &shift, hotspot)
}
