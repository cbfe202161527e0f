//! PredArticulation: the estimate from one handle's exploration, on its grasps' end-effector
//! poses stitched into one path, with a revolute axis checked against the rotation the
//! exploration saw and a tiny turn the exploration saw as a slide registered as one.

use nalgebra::{Isometry3, Point3, Unit};

use super::error::DiscoveryError;
use super::interface::PointCloud;
use super::log::{AttemptLog, EstimateLog, HandleLog, MotionClass, Stage};
use super::run::{Pulled, Run, Stop, fail};
use crate::articulation::{Estimate, Interaction, JointEstimate};
use crate::scene::{JointAxis, JointKind};

impl Run<'_> {
    /// PredArticulation on the end-effector path of one grasp (later grasps stitched, in a
    /// copy, into the first's frame), logged in `entry` (the last estimate stays).
    pub(super) fn estimate(
        &self,
        entry: &mut HandleLog,
        index: usize,
        pulled: &Pulled,
        o_post: &PointCloud,
    ) -> Result<Estimate, Stop> {
        let mut ee_poses = pulled.ee_poses.clone();
        stitch_grasps(&mut ee_poses, &pulled.segments);
        let interaction = Interaction {
            pre: &pulled.o_first,
            post: o_post,
            contact_pre: pulled.contact_pre,
            contact_post: pulled.contact_post,
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
        Ok(estimate)
    }

    /// The checks on the final estimate: an unknown joint or one that contradicts the
    /// rotation the exploration saw fails estimation, and a tiny turn seen as a slide becomes
    /// the slide (noted in `entry`).
    pub(super) fn checked(
        &self,
        entry: &mut HandleLog,
        pulled: &Pulled,
        mut estimate: Estimate,
    ) -> Result<Estimate, Stop> {
        if pulled.segments.len() > 1 {
            entry.notes.push(format!(
                "end-effector poses of {} grasps stitched into the first grasp's frame",
                pulled.segments.len()
            ));
        }
        if let JointEstimate::Unknown { reason } = &estimate.joint {
            return fail(Stage::Estimation, format!("estimator: {reason}"));
        }
        if let Some(reason) = contradicts_motion(&estimate.joint, &entry.attempts) {
            return fail(Stage::Estimation, reason);
        }
        if let Some((slide, note)) = small_turn_as_slide(
            &estimate.joint,
            &entry.attempts,
            &pulled.contact_pre,
            self.s.rotation_threshold,
        ) {
            entry.notes.push(note);
            estimate.joint = slide;
            // The estimator's regions describe the turn it estimated, not this slide.
            estimate.uncertainty = None;
        }
        Ok(estimate)
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

/// Why a revolute estimate contradicts the rotation the exploration measured (the turn of
/// the tracked surface normal, [`MotionClass`]), if it does: a front seen turning about a
/// horizontal axis (a door opening downwards) needs an axis within 45° of horizontal, one
/// seen turning left or right an axis within 45° of vertical. The last attempt that saw a
/// rotation decides. Two-view estimates from a small opening can fit a rigid motion of the
/// wrong points (in the kitchen, a dishwasher door pulled 15° was once estimated turning
/// about an axis 58° from horizontal); registered, such a part blocks its neighbours' plans.
pub(super) fn contradicts_motion(joint: &JointEstimate, attempts: &[AttemptLog]) -> Option<String> {
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
pub(super) fn small_turn_as_slide(
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
    use crate::discovery::log::AttemptEnd;

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
