//! One handle of Algorithm 1: PlanBase, GlobalNavTo, DetectHandle, the attempts with
//! Reposition, the post-interaction observation, PredArticulation and the part to register.
//! The rules are documented on [`discover`](super::discover).

use nalgebra::{Isometry2, Isometry3, Point3, Unit, Vector2, Vector3};

use super::error::{DiscoveryError, check_finite};
use super::explore::{AttemptInput, attempt, checked_cloud, surface_normal};
use super::fusion::MappedHandle;
use super::interface::{HardwareFailure, LocalGoal, PointCloud, Robot};
use super::log::{AttemptEnd, AttemptLog, Exploration, HandleLog, MotionClass, Stage};
use super::part::{NewPart, Observed, new_part};
use super::placement::{FreeSpace, horizontal, plan_base, shifted};
use super::settings::DiscoverySettings;
use crate::articulation::ArticulationEstimator;
use crate::scene::{SceneModel, State};

/// A refined normal more than this far (rad) from the registered one is not trusted: 45°.
const MAX_NORMAL_REFINEMENT: f64 = std::f64::consts::FRAC_PI_4;

/// The interfaces and settings of one run.
pub(crate) struct Run<'a> {
    pub robot: &'a mut dyn Robot,
    pub estimator: &'a dyn ArticulationEstimator,
    pub s: &'a DiscoverySettings,
}

/// The log entry, failed at `stage` with `reason`.
fn failed(mut entry: HandleLog, stage: Stage, reason: impl Into<String>) -> HandleLog {
    entry.outcome = Exploration::Failed {
        stage,
        reason: reason.into(),
    };
    entry
}

/// Why a handle's exploration ended before a part: a stage that failed (logged, the run goes
/// on) or an error (the run ends).
pub(super) enum Stop {
    Failed(Stage, String),
    Error(DiscoveryError),
}

impl From<DiscoveryError> for Stop {
    fn from(e: DiscoveryError) -> Self {
        Stop::Error(e)
    }
}

/// Stops the exploration: `stage` failed for `reason`.
pub(super) fn fail<T>(stage: Stage, reason: impl Into<String>) -> Result<T, Stop> {
    Err(Stop::Failed(stage, reason.into()))
}

/// What the attempts left: the first grasp's pre-interaction observation and contact, the
/// last contact, the end-effector poses, where each grasp's poses begin, and whether the last
/// attempt succeeded.
struct Attempts {
    first: Option<(PointCloud, Point3<f64>)>,
    contact_post: Option<Point3<f64>>,
    ee_poses: Vec<(f64, Isometry3<f64>)>,
    segments: Vec<usize>,
    success: bool,
}

/// A successful exploration: the first grasp's pre-interaction observation and contact, the
/// last contact, the end-effector poses and where each grasp's poses begin.
pub(super) struct Pulled {
    pub(super) o_first: PointCloud,
    pub(super) contact_pre: Point3<f64>,
    pub(super) contact_post: Point3<f64>,
    pub(super) ee_poses: Vec<(f64, Isometry3<f64>)>,
    pub(super) segments: Vec<usize>,
}

impl Run<'_> {
    /// Explores one handle: its log entry and, on success, the part to register.
    pub(crate) fn handle(
        &mut self,
        index: usize,
        h: &MappedHandle,
        model: &SceneModel,
        state: &State,
        free: &FreeSpace,
    ) -> Result<(HandleLog, Option<NewPart>), DiscoveryError> {
        let mut entry = HandleLog {
            index,
            mapped: h.position,
            detected: None,
            outcome: Exploration::Failed {
                stage: Stage::Mapping,
                reason: String::new(),
            },
            attempts: Vec::new(),
            pull_distance: 0.0,
            estimate: None,
            notes: Vec::new(),
        };
        match self.explore(&mut entry, index, h, model, state, free) {
            Ok(part) => Ok((entry, Some(part))),
            Err(Stop::Failed(stage, reason)) => Ok((failed(entry, stage, reason), None)),
            Err(Stop::Error(e)) => Err(e),
        }
    }

    /// The steps of one handle, logged into `entry`: the part to register, or where the
    /// exploration stopped.
    fn explore(
        &mut self,
        entry: &mut HandleLog,
        index: usize,
        h: &MappedHandle,
        model: &SceneModel,
        state: &State,
        free: &FreeSpace,
    ) -> Result<NewPart, Stop> {
        let s = self.s;
        let Some(attachment) = &h.attachment else {
            return Err(DiscoveryError::UnregisteredHandle { index }.into());
        };
        let registered =
            Unit::try_new(attachment.normal, 1e-9).ok_or_else(|| DiscoveryError::NonFinite {
                what: format!("normal of handle {index} (zero)"),
            })?;
        // PlanBase(h), GlobalNavTo(b).
        let dir = self.approach(h, &registered, free)?;
        // GetCurrentObs, DetectHandle.
        let o = self.observe(Stage::Mapping, "observation", "approach")?;
        let p = self.redetect(index, h)?;
        entry.detected = Some(p);
        let normal = surface_normal(&o, &p, s)
            .filter(|n| n.angle(&registered) <= MAX_NORMAL_REFINEMENT)
            .unwrap_or(registered);
        // PlanBase(p).
        let toward_robot = self.toward_robot(&p)?;
        let dir = horizontal(&normal, &toward_robot).unwrap_or(dir);
        let Some(b_pre) = plan_base(free, &p, &dir, s.interaction_distance, s.base_search_radius)
        else {
            return fail(Stage::Navigation, "no free pre-interaction base pose");
        };
        // The exploratory interaction, with Reposition between attempts.
        let attempts = self.attempts(entry, index, p, normal, b_pre, free)?;
        let mut pulled = pulled(entry, attempts)?;
        // Step back, o_post.
        self.step_back(entry, &p, &dir, pulled.contact_post, free);
        let o_post = self.observe(
            Stage::Estimation,
            "post-interaction observation",
            "post-interaction",
        )?;
        // PredArticulation, on the end-effector path of one grasp.
        let estimate = self.predict(entry, index, &mut pulled, &o_post)?;
        // Register.
        let observed = Observed {
            pre: &pulled.o_first,
            post: &o_post,
            contact_pre: pulled.contact_pre,
            normal,
        };
        match new_part(index, &estimate, &observed, model, state, s) {
            Ok(part) => {
                entry.notes.extend(part.notes.iter().cloned());
                entry.outcome = Exploration::Registered {
                    part: part.spec.name.clone(),
                    joint: part.spec.joint.name.clone(),
                    parent: part.spec.parent.clone(),
                };
                Ok(part)
            }
            Err(reason) => fail(Stage::Estimation, reason),
        }
    }

    /// PlanBase(h) and GlobalNavTo(b): drives to a free base pose in front of the mapped
    /// handle (registered outward normal `registered`); the approach direction.
    fn approach(
        &mut self,
        h: &MappedHandle,
        registered: &Unit<Vector3<f64>>,
        free: &FreeSpace,
    ) -> Result<Vector2<f64>, Stop> {
        let s = self.s;
        let toward_robot = self.toward_robot(&h.position)?;
        let Some(dir) = horizontal(registered, &toward_robot) else {
            return fail(Stage::Navigation, "no approach direction");
        };
        let Some(b) = plan_base(
            free,
            &h.position,
            &dir,
            s.approach_distance,
            s.base_search_radius,
        ) else {
            return fail(
                Stage::Navigation,
                "no free base pose in front of the handle",
            );
        };
        if let Err(f) = self.robot.navigate_to(&b) {
            return fail(Stage::Navigation, format!("global navigation: {f}"));
        }
        Ok(dir)
    }

    /// GetCurrentObs from the observation camera, checked (`what` names it in errors); a
    /// sensor failure fails `stage` with `reason` and the sensor's message.
    fn observe(&mut self, stage: Stage, reason: &str, what: &str) -> Result<PointCloud, Stop> {
        let o = match self.robot.observe(self.s.observation_camera) {
            Ok(o) => o,
            Err(e) => return fail(stage, format!("{reason}: {e}")),
        };
        checked_cloud(&o, what)?;
        Ok(o)
    }

    /// DetectHandle, up to `redetect_tries` frames: the first detection within
    /// `redetect_radius` of the mapped handle (the nearest in its frame).
    fn redetect(&mut self, index: usize, h: &MappedHandle) -> Result<Point3<f64>, Stop> {
        let s = self.s;
        let (seen, nearest) = match self.detect_near(index, &h.position)? {
            Near::Found(q) => return Ok(q),
            Near::Missed { seen, nearest } => (seen, nearest),
            Near::Failed(e) => return fail(Stage::Mapping, format!("detector: {e}")),
        };
        let b = self.robot.base_pose();
        let near = if nearest.is_finite() {
            format!(", the nearest {nearest:.2} m away")
        } else {
            String::new()
        };
        fail(
            Stage::Mapping,
            format!(
                "not re-detected within {} m in {} frame(s) from base ({:.2}, {:.2}, {:.0}°): {seen} detection(s){near}",
                s.redetect_radius,
                s.redetect_tries,
                b.translation.x,
                b.translation.y,
                b.rotation.angle().to_degrees()
            ),
        )
    }

    /// Up to `redetect_tries` detector frames: the first detection within `redetect_radius` of
    /// `expected` (the nearest in its frame).
    fn detect_near(&mut self, index: usize, expected: &Point3<f64>) -> Result<Near, Stop> {
        let s = self.s;
        let (mut seen, mut nearest) = (0usize, f64::INFINITY);
        for _ in 0..s.redetect_tries {
            let detections = match self.robot.detect_handles() {
                Ok(d) => d,
                Err(e) => return Ok(Near::Failed(e.to_string())),
            };
            for (k, d) in detections.iter().enumerate() {
                check_finite(d.position.coords.iter().copied(), || {
                    format!("re-detection {k} of handle {index}")
                })?;
            }
            seen += detections.len();
            let best = detections
                .iter()
                .map(|d| (d.position, (d.position - expected).norm()))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((q, d)) = best {
                nearest = nearest.min(d);
                if d <= s.redetect_radius {
                    return Ok(Near::Found(q));
                }
            }
        }
        Ok(Near::Missed { seen, nearest })
    }

    /// The exploratory interaction at handle `p` (outward normal `normal`): up to
    /// `max_attempts` attempts from `b_pre` until one succeeds, each logged in `entry`, with
    /// Reposition between them. A retry grasps at the last contact (the part's path stays
    /// that of one point, as the estimators assume), or, after a grasp that missed the handle,
    /// where it is re-detected ([`Run::regrasp_target`]).
    fn attempts(
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
        };
        // Whether the last attempt's gripper closed where the handle was not.
        let mut missed = false;
        for k in 0..s.max_attempts {
            let goal = LocalGoal {
                target: hotspot,
                world_from_base: b_pre,
            };
            if let Err(failure) = self.robot.navigate_local(&goal) {
                entry
                    .attempts
                    .push(skipped(b_pre, AttemptEnd::Navigation { failure }));
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
            missed = matches!(
                result.log.end,
                AttemptEnd::Grasp {
                    failure: HardwareFailure::GraspLost
                }
            );
            let motion = result.log.motion;
            out.success = result.log.end.is_success();
            entry.attempts.push(result.log);
            if let Err(f) = self.robot.retract() {
                return fail(Stage::Exploration, format!("retract: {f}"));
            }
            if out.success {
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
    fn step_back(
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
    fn toward_robot(&self, p: &Point3<f64>) -> Result<Vector2<f64>, DiscoveryError> {
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

/// What DetectHandle found near an expected position.
enum Near {
    /// A detection within `redetect_radius`.
    Found(Point3<f64>),
    /// None within it: how many detections the frames held, and the nearest one's distance.
    Missed { seen: usize, nearest: f64 },
    /// The detector failed (its message).
    Failed(String),
}

/// The attempts' outcome, with the pull distance recorded in `entry`: on success the first
/// grasp and the last contact; otherwise a failure of navigation (when every attempt failed
/// there) or of exploration, with the last attempt's end.
fn pulled(entry: &mut HandleLog, attempts: Attempts) -> Result<Pulled, Stop> {
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
    })
}

/// The log entry of an attempt that did not get to the grasp.
fn skipped(world_from_base: Isometry2<f64>, end: AttemptEnd) -> AttemptLog {
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
