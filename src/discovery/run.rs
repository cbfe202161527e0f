//! One handle of Algorithm 1: PlanBase, GlobalNavTo, DetectHandle, the attempts with
//! Reposition, the post-interaction observation, PredArticulation and the part to register.
//! The rules are documented on [`discover`](super::discover).

use nalgebra::{Isometry2, Isometry3, Point3, Unit, Vector2};

use super::error::{DiscoveryError, check_finite};
use super::explore::{AttemptInput, attempt, checked_cloud, surface_normal};
use super::fusion::MappedHandle;
use super::interface::{LocalGoal, PointCloud, Robot};
use super::log::{AttemptEnd, AttemptLog, EstimateLog, HandleLog, MotionClass, Outcome, Stage};
use super::part::{NewPart, Observed, new_part};
use super::placement::{FreeSpace, horizontal, plan_base, shifted};
use super::settings::DiscoverySettings;
use crate::kinematics::articulation::{ArticulationEstimator, Interaction, JointEstimate};
use crate::scene::{JointAxis, JointKind, SceneModel, State};

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
    entry.outcome = Outcome::Failed {
        stage,
        reason: reason.into(),
    };
    entry
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
        let s = self.s;
        let mut entry = HandleLog {
            index,
            mapped: h.position,
            detected: None,
            outcome: Outcome::Failed {
                stage: Stage::Mapping,
                reason: String::new(),
            },
            attempts: Vec::new(),
            pull_distance: 0.0,
            estimate: None,
            notes: Vec::new(),
        };
        let Some(attachment) = &h.attachment else {
            return Err(DiscoveryError::UnregisteredHandle { index });
        };
        let registered =
            Unit::try_new(attachment.normal, 1e-9).ok_or_else(|| DiscoveryError::NonFinite {
                what: format!("normal of handle {index} (zero)"),
            })?;
        // PlanBase(h), GlobalNavTo(b).
        let toward_robot = self.toward_robot(&h.position)?;
        let Some(dir) = horizontal(&registered, &toward_robot) else {
            return Ok((
                failed(entry, Stage::Navigation, "no approach direction"),
                None,
            ));
        };
        let Some(b) = plan_base(
            free,
            &h.position,
            &dir,
            s.approach_distance,
            s.base_search_radius,
        ) else {
            return Ok((
                failed(
                    entry,
                    Stage::Navigation,
                    "no free base pose in front of the handle",
                ),
                None,
            ));
        };
        if let Err(f) = self.robot.navigate_to(&b) {
            return Ok((
                failed(entry, Stage::Navigation, format!("global navigation: {f}")),
                None,
            ));
        }
        // GetCurrentObs, DetectHandle.
        let o = match self.robot.observe(s.observation_camera) {
            Ok(o) => o,
            Err(e) => {
                return Ok((
                    failed(entry, Stage::Mapping, format!("observation: {e}")),
                    None,
                ));
            }
        };
        checked_cloud(&o, "approach")?;
        // DetectHandle, up to `redetect_tries` frames.
        let mut p = None;
        let (mut seen, mut nearest) = (0usize, f64::INFINITY);
        for _ in 0..s.redetect_tries {
            let detections = match self.robot.detect_handles() {
                Ok(d) => d,
                Err(e) => {
                    return Ok((
                        failed(entry, Stage::Mapping, format!("detector: {e}")),
                        None,
                    ));
                }
            };
            for (k, d) in detections.iter().enumerate() {
                check_finite(d.position.coords.iter().copied(), || {
                    format!("re-detection {k} of handle {index}")
                })?;
            }
            seen += detections.len();
            let best = detections
                .iter()
                .map(|d| (d.position, (d.position - h.position).norm()))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((q, d)) = best {
                nearest = nearest.min(d);
                if d <= s.redetect_radius {
                    p = Some(q);
                    break;
                }
            }
        }
        let Some(p) = p else {
            let b = self.robot.base_pose();
            let near = if nearest.is_finite() {
                format!(", the nearest {nearest:.2} m away")
            } else {
                String::new()
            };
            return Ok((
                failed(
                    entry,
                    Stage::Mapping,
                    format!(
                        "not re-detected within {} m in {} frame(s) from base ({:.2}, {:.2}, {:.0}°): {seen} detection(s){near}",
                        s.redetect_radius,
                        s.redetect_tries,
                        b.translation.x,
                        b.translation.y,
                        b.rotation.angle().to_degrees()
                    ),
                ),
                None,
            ));
        };
        entry.detected = Some(p);
        let normal = surface_normal(&o, &p, s)
            .filter(|n| n.angle(&registered) <= MAX_NORMAL_REFINEMENT)
            .unwrap_or(registered);
        // PlanBase(p).
        let toward_robot = self.toward_robot(&p)?;
        let dir = horizontal(&normal, &toward_robot).unwrap_or(dir);
        let Some(mut b_pre) =
            plan_base(free, &p, &dir, s.interaction_distance, s.base_search_radius)
        else {
            return Ok((
                failed(
                    entry,
                    Stage::Navigation,
                    "no free pre-interaction base pose",
                ),
                None,
            ));
        };
        // The exploratory interaction, with Reposition between attempts.
        let mut hotspot = p;
        let mut hot_normal = normal;
        let mut first: Option<(PointCloud, Point3<f64>)> = None;
        let mut contact_post = None;
        let mut ee_poses: Vec<(f64, Isometry3<f64>)> = Vec::new();
        // Where each grasp's poses begin in `ee_poses`.
        let mut segments: Vec<usize> = Vec::new();
        let mut success = false;
        for _ in 0..s.max_attempts {
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
                first_grasp: first.as_ref().map(|(_, g)| *g),
            };
            let seg = ee_poses.len();
            let result = attempt(&mut *self.robot, s, &input, &mut ee_poses)?;
            if ee_poses.len() > seg {
                segments.push(seg);
            }
            if let (None, Some(g)) = (&first, result.grasp) {
                first = Some((o_pre.clone(), g));
            }
            if let Some(c) = result.contact {
                hotspot = c;
                contact_post = Some(c);
            }
            hot_normal = result.normal;
            let motion = result.log.motion;
            success = result.log.end.is_success();
            entry.attempts.push(result.log);
            if let Err(f) = self.robot.retract() {
                let stage = Stage::Exploration;
                return Ok((failed(entry, stage, format!("retract: {f}")), None));
            }
            if success {
                break;
            }
            // Reposition.
            b_pre = reposition(free, &b_pre, motion, &hotspot, s).unwrap_or(b_pre);
        }
        if let (Some((_, g)), Some(c)) = (&first, contact_post) {
            entry.pull_distance = (c - g).norm();
        }
        let (Some((o_first, contact_pre)), Some(contact_post), true) =
            (first, contact_post, success)
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
            return Ok((failed(entry, stage, reason), None));
        };
        // Step back, o_post.
        let back = plan_base(
            free,
            &p,
            &dir,
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
        let o_post = match self.robot.observe(s.observation_camera) {
            Ok(o) => o,
            Err(e) => {
                let reason = format!("post-interaction observation: {e}");
                return Ok((failed(entry, Stage::Estimation, reason), None));
            }
        };
        checked_cloud(&o_post, "post-interaction")?;
        // PredArticulation, on the end-effector path of one grasp.
        if segments.len() > 1 {
            stitch_grasps(&mut ee_poses, &segments);
            entry.notes.push(format!(
                "end-effector poses of {} grasps stitched into the first grasp's frame",
                segments.len()
            ));
        }
        let interaction = Interaction {
            pre: &o_first,
            post: &o_post,
            contact_pre,
            contact_post,
            ee_poses: &ee_poses,
        };
        let estimate =
            self.estimator
                .estimate(&interaction)
                .map_err(|source| DiscoveryError::Estimator {
                    estimator: self.estimator.name().to_string(),
                    handle: index,
                    source,
                })?;
        entry.estimate = Some(EstimateLog::new(self.estimator.name(), &estimate));
        if let JointEstimate::Unknown { reason } = &estimate.joint {
            let reason = format!("estimator: {reason}");
            return Ok((failed(entry, Stage::Estimation, reason), None));
        }
        if let Some(reason) = contradicts_motion(&estimate.joint, &entry.attempts) {
            return Ok((failed(entry, Stage::Estimation, reason), None));
        }
        let mut estimate = estimate;
        if let Some((slide, note)) = small_turn_as_slide(
            &estimate.joint,
            &entry.attempts,
            &contact_pre,
            s.rotation_threshold,
        ) {
            entry.notes.push(note);
            estimate.joint = slide;
        }
        // Register.
        let observed = Observed {
            pre: &o_first,
            post: &o_post,
            contact_pre,
            normal,
        };
        match new_part(index, &estimate, &observed, model, state, s) {
            Ok(part) => {
                entry.notes.extend(part.notes.iter().cloned());
                entry.outcome = Outcome::Registered {
                    part: part.spec.name.clone(),
                    joint: part.spec.joint.name.clone(),
                    parent: part.spec.parent.clone(),
                };
                Ok((entry, Some(part)))
            }
            Err(reason) => Ok((failed(entry, Stage::Estimation, reason), None)),
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

/// Expresses the end-effector poses of every grasp after the first as if the first grasp
/// still held: each later grasp `k` starts where the part was left by grasp `k − 1`, so with
/// a rigid grasp `world_from_ee = part(θ)·G_k`, the last pose of grasp `k − 1` is
/// `part(θ_k)·G_{k−1}` and the first of grasp `k` is `part(θ_k)·G_k`; right-multiplying grasp
/// `k`'s poses by `first_k⁻¹·last_{k−1}` turns `part(θ)·G_k` into `part(θ)·G_{k−1}`.
/// Applied in order, every pose becomes `part(θ)·G_1`: one rigid grasp, the estimators'
/// model (a regrasp otherwise jumps the path and the orientation). Assumes the part does
/// not move between the grasps. `starts`: the index where each grasp's poses begin,
/// increasing, the first 0.
pub(crate) fn stitch_grasps(poses: &mut [(f64, Isometry3<f64>)], starts: &[usize]) {
    for (k, &start) in starts.iter().enumerate().skip(1) {
        if start == 0 || start >= poses.len() {
            continue;
        }
        let end = starts
            .get(k + 1)
            .map_or(poses.len(), |e| (*e).min(poses.len()));
        let offset = poses[start].1.inverse() * poses[start - 1].1;
        for (_, p) in &mut poses[start..end] {
            *p *= offset;
        }
    }
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

/// Why a revolute estimate contradicts the rotation the exploration measured (the turn of
/// the tracked surface normal, [`MotionClass`]), if it does: a front seen turning about a
/// horizontal axis (a door opening downwards) needs an axis within 45° of horizontal, one
/// seen turning left or right an axis within 45° of vertical. The last attempt that saw a
/// rotation decides. Two-view estimates from a small opening can fit a rigid motion of the
/// wrong points (in the kitchen, a dishwasher door pulled 15° was once estimated turning
/// about an axis 58° from horizontal); registered, such a part blocks its neighbours' plans.
fn contradicts_motion(joint: &JointEstimate, attempts: &[AttemptLog]) -> Option<String> {
    let JointEstimate::Revolute { axis, .. } = joint else {
        return None;
    };
    let seen = attempts.iter().rev().find_map(|a| match a.motion {
        MotionClass::RevoluteLeft
        | MotionClass::RevoluteRight
        | MotionClass::RevoluteHorizontal => Some(a.motion),
        MotionClass::Prismatic | MotionClass::NoMotion => None,
    })?;
    let from_horizontal = axis.z.abs().clamp(0.0, 1.0).asin().to_degrees();
    let (horizontal, turn) = match seen {
        MotionClass::RevoluteHorizontal => (true, "about a horizontal axis"),
        MotionClass::RevoluteLeft => (false, "to the left"),
        _ => (false, "to the right"),
    };
    if (horizontal && from_horizontal > 45.0) || (!horizontal && from_horizontal < 45.0) {
        Some(format!(
            "the estimated axis is {from_horizontal:.0}° from horizontal, but the exploration saw \
             the front turn {turn}"
        ))
    } else {
        None
    }
}

/// A revolute estimate that turned less than `threshold` (rad) while every attempt that moved
/// the part saw it slide (no tracked rotation of `threshold` or more) is a slide: a turn that
/// small about an axis metres away moves the front along its chord, and the two models' fits
/// are then nearly equal (in the kitchen a drawer pulled 15 cm was once estimated turning 1°
/// about an axis 6 m away, BIC 3.5 apart). Returns the prismatic joint along the chord the
/// contact moved, as far as it moved, and the note for the log.
fn small_turn_as_slide(
    joint: &JointEstimate,
    attempts: &[AttemptLog],
    contact: &Point3<f64>,
    threshold: f64,
) -> Option<(JointEstimate, String)> {
    let JointEstimate::Revolute { axis, pivot, angle } = joint else {
        return None;
    };
    let mut moved = attempts
        .iter()
        .filter(|a| a.motion != MotionClass::NoMotion)
        .peekable();
    moved.peek()?;
    if !moved.all(|a| a.motion == MotionClass::Prismatic) || angle.abs() >= threshold {
        return None;
    }
    let turn = JointAxis {
        kind: JointKind::Revolute,
        pivot: *pivot,
        direction: *axis,
    };
    let chord = turn.move_point(contact, *angle) - contact;
    let distance = chord.norm();
    let direction = Unit::try_new(chord, 1e-9)?;
    let radius = turn.distance_to_axis(contact);
    Some((
        JointEstimate::Prismatic {
            axis: direction,
            distance,
        },
        format!(
            "the estimate turned {:.1}° about an axis {radius:.1} m away, but the exploration saw \
             the part slide: registered as prismatic along the {distance:.3} m chord its \
             contact moved",
            angle.abs().to_degrees()
        ),
    ))
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry2, Point3, Unit, Vector3};

    use super::*;

    /// A door turning about the vertical line through (1, 2): grasp 1 holds it for
    /// θ = 0 … 0.5 rad, grasp 2 (another point, another orientation) from θ = 0.5 to 1.0,
    /// and grasp 3 from 1.0 to 1.2. Stitched, every pose is `part(θ)·G1` (the identity
    /// derived in the function's docs).
    #[test]
    fn stitched_grasps_follow_the_first_grasp() {
        let hinge = Vector3::new(1.0, 2.0, 0.0);
        let part = |t: f64| {
            Isometry3::translation(hinge.x, hinge.y, 0.0)
                * Isometry3::rotation(Vector3::z() * t)
                * Isometry3::translation(-hinge.x, -hinge.y, 0.0)
        };
        let g = [
            Isometry3::new(Vector3::new(1.5, 2.0, 0.8), Vector3::new(0.0, 1.2, 0.0)),
            Isometry3::new(Vector3::new(1.45, 2.05, 0.75), Vector3::new(0.3, 1.0, -0.2)),
            Isometry3::new(Vector3::new(1.4, 1.95, 0.9), Vector3::new(-0.2, 1.4, 0.1)),
        ];
        let spans = [(0.0, 0.5), (0.5, 1.0), (1.0, 1.2)];
        let mut poses = Vec::new();
        let mut starts = Vec::new();
        let mut thetas = Vec::new();
        for (k, (a, b)) in spans.iter().enumerate() {
            starts.push(poses.len());
            for i in 0..=5 {
                let t = a + (b - a) * f64::from(i) / 5.0;
                poses.push((poses.len() as f64, part(t) * g[k]));
                thetas.push(t);
            }
        }
        stitch_grasps(&mut poses, &starts);
        for ((_, p), t) in poses.iter().zip(&thetas) {
            let want = part(*t) * g[0];
            assert!(
                (p.translation.vector - want.translation.vector).norm() < 1e-12,
                "θ = {t}: {p} vs {want}"
            );
            assert!(p.rotation.angle_to(&want.rotation) < 1e-12, "θ = {t}");
        }
        // One grasp: nothing changes.
        let mut one = poses[..6].to_vec();
        let before = one.clone();
        stitch_grasps(&mut one, &[0]);
        assert_eq!(one, before);
    }

    fn attempt(motion: MotionClass) -> AttemptLog {
        AttemptLog {
            world_from_base: Isometry2::identity(),
            steps: 5,
            pull_distance: 0.15,
            displacement: Some(0.1),
            rotation: 0.27,
            motion,
            end: AttemptEnd::Success,
        }
    }

    fn revolute(axis: Vector3<f64>) -> JointEstimate {
        JointEstimate::Revolute {
            axis: Unit::new_normalize(axis),
            pivot: Point3::origin(),
            angle: 0.25,
        }
    }

    /// The axis' angle from horizontal is asin |z|: (0.496, 0.165, −0.852) (the kitchen's
    /// wrong dishwasher estimate) is 58.4° from horizontal, (1, 0, 0.05) 2.9°, (0.1, 0, 1)
    /// 84.3°. Against a front seen turning about a horizontal axis only the first
    /// contradicts; against one seen turning left only the second; a prismatic estimate or
    /// attempts without a rotation never do.
    #[test]
    fn axis_against_the_seen_rotation() {
        let wrong = revolute(Vector3::new(0.496, 0.165, -0.852));
        let flat = revolute(Vector3::new(1.0, 0.0, 0.05));
        let upright = revolute(Vector3::new(0.1, 0.0, 1.0));
        let down = [attempt(MotionClass::RevoluteHorizontal)];
        let left = [
            attempt(MotionClass::NoMotion),
            attempt(MotionClass::RevoluteLeft),
        ];
        let reason = contradicts_motion(&wrong, &down).expect("contradiction");
        assert!(reason.contains("58°"), "{reason}");
        assert!(contradicts_motion(&flat, &down).is_none());
        assert!(contradicts_motion(&upright, &down).is_some());
        assert!(contradicts_motion(&flat, &left).is_some());
        assert!(contradicts_motion(&upright, &left).is_none());
        let slide = JointEstimate::Prismatic {
            axis: Unit::new_normalize(Vector3::new(0.0, 0.0, 1.0)),
            distance: 0.2,
        };
        assert!(contradicts_motion(&slide, &down).is_none());
        let still = [
            attempt(MotionClass::Prismatic),
            attempt(MotionClass::NoMotion),
        ];
        assert!(contradicts_motion(&wrong, &still).is_none());
    }

    /// A 1° turn about a vertical axis 6 m to the side of the contact, with the exploration
    /// seeing a slide, is a slide along the chord: length 2 · 6 · sin(0.5°) = 0.10472 m by
    /// hand, direction the tangent at mid-turn (axis × radius, turned by half the angle). The
    /// same turn is kept when an attempt saw a rotation, when the turn reaches the threshold,
    /// or when no attempt moved the part.
    #[test]
    fn a_tiny_turn_seen_as_a_slide_is_a_slide() {
        let axis = Unit::new_normalize(Vector3::new(0.0, 0.0, 1.0));
        let contact = Point3::new(0.0, 0.0, 0.8);
        let pivot = Point3::new(6.0, 0.0, 0.0);
        let angle = 1f64.to_radians();
        let turn = JointEstimate::Revolute { axis, pivot, angle };
        let slid = [
            attempt(MotionClass::NoMotion),
            attempt(MotionClass::Prismatic),
        ];
        let (slide, note) = small_turn_as_slide(&turn, &slid, &contact, 0.14).expect("a slide");
        let JointEstimate::Prismatic { axis: d, distance } = slide else {
            panic!("{slide:?}")
        };
        assert!((distance - 12.0 * 0.5f64.to_radians().sin()).abs() < 1e-12);
        // Radius (−6, 0, 0) from the pivot; z × it = (0, −6, 0); turned by 0.5°.
        let half = 0.5f64.to_radians();
        let expected = Vector3::new(half.sin(), -half.cos(), 0.0);
        assert!((d.into_inner() - expected).norm() < 1e-9, "{d:?}");
        assert!(note.contains("1.0°") && note.contains("6.0 m"), "{note}");
        let turned = [
            attempt(MotionClass::Prismatic),
            attempt(MotionClass::RevoluteLeft),
        ];
        assert!(small_turn_as_slide(&turn, &turned, &contact, 0.14).is_none());
        let big = JointEstimate::Revolute {
            axis,
            pivot,
            angle: 0.14,
        };
        assert!(small_turn_as_slide(&big, &slid, &contact, 0.14).is_none());
        let still = [attempt(MotionClass::NoMotion)];
        assert!(small_turn_as_slide(&turn, &still, &contact, 0.14).is_none());
    }
}
