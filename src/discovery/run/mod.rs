//! One handle of Algorithm 1: PlanBase, GlobalNavTo, DetectHandle, the attempts with
//! Reposition, the post-interaction observation, PredArticulation and the part to register.
//! The rules are documented on [`discover`](super::discover).

use nalgebra::{Isometry2, Isometry3, Point3, Unit, Vector2, Vector3};

use super::error::{DiscoveryError, check_finite};
use super::explore::{checked_cloud, surface_normal};
use super::fusion::MappedHandle;
use super::interface::{PointCloud, Robot};
use super::log::{Exploration, HandleLog, Stage};
use super::part::{NewPart, Observed, new_part};
use super::placement::{FreeSpace, horizontal, plan_base};
use super::settings::DiscoverySettings;
use crate::articulation::ArticulationEstimator;
use crate::scene::{SceneModel, State};

mod confident;
mod pull;

pub(super) use confident::{doubts, shortfall};

use pull::pulled;

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

/// A successful exploration: the first grasp's pre-interaction observation and contact, the
/// last contact, the end-effector poses (as recorded, not stitched) and where each grasp's
/// poses begin; the last successful attempt's base pose and last tracked normal (where a
/// further pull starts from).
pub(super) struct Pulled {
    pub(super) o_first: PointCloud,
    pub(super) contact_pre: Point3<f64>,
    pub(super) contact_post: Point3<f64>,
    pub(super) ee_poses: Vec<(f64, Isometry3<f64>)>,
    pub(super) segments: Vec<usize>,
    pub(super) base: Isometry2<f64>,
    pub(super) normal: Unit<Vector3<f64>>,
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
            pulling: None,
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
        // Step back, o_post, PredArticulation; pull further until confident.
        let (estimate, o_post) =
            self.estimate_until_confident(entry, index, &p, &dir, &mut pulled, free)?;
        let estimate = self.checked(entry, &pulled, estimate)?;
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
