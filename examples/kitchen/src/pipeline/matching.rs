//! Matching the estimated model's parts to the true parts (by handle position at the zero
//! state) and the articulation errors of each match (DiTH metrics, paper Table II).

use kinscene::articulation::{axis_angle_error, axis_position_error};
#[cfg(doc)]
use kinscene::discovery::DiscoverySettings;
use kinscene::discovery::{Discovery, Exploration};
use kinscene::scene::{
    JointKind, Parent, SceneData, SceneModel, forward_kinematics, joint_axis, world_from_handle,
};
use nalgebra::{Point3, Vector3};
use serde::Serialize;

use super::PipelineError;

/// A handle of the estimated model must lie within this distance (m) of a true handle, both at
/// their model's zero state, to match it: a few centimetres covers the detector's and the
/// grasp's error, while the nearest two true handles are 23 cm apart.
pub const MATCH_RADIUS: f64 = 0.06;

/// A part's joint, its handle and axis at the zero state of its model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartAxis {
    /// Joint name.
    pub joint: String,
    /// Part name.
    pub part: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// The (first) handle's grasp point (m), world frame, zero state.
    pub handle: Point3<f64>,
    /// A point on the axis (m), world frame, zero state.
    pub pivot: Point3<f64>,
    /// Unit axis direction, world frame, zero state (positive values open the part).
    pub direction: Vector3<f64>,
    /// Joint limits (rad or m).
    pub limits: [f64; 2],
}

/// The parts of `model` with a handle, in part order.
///
/// # Errors
/// [`PipelineError::Scene`] if forward kinematics fails (an invalid model).
pub fn part_axes(model: &SceneModel) -> Result<Vec<PartAxis>, PipelineError> {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, &model.zero_state())?;
    let mut out = Vec::new();
    for part in model.parts() {
        let Some((hid, _)) = model.handles().find(|(h, _)| h.part() == part.id()) else {
            continue;
        };
        let handle = world_from_handle(model, &data, hid)?;
        let axis = joint_axis(model, &data, part.joint())?;
        let joint = &model.joints()[part.joint().index()];
        out.push(PartAxis {
            joint: joint.name.clone(),
            part: part.name().to_string(),
            kind: axis.kind,
            handle: handle.position,
            pivot: axis.pivot,
            direction: axis.direction.into_inner(),
            limits: [joint.limits.lower, joint.limits.upper],
        });
    }
    Ok(out)
}

/// An estimated part matched to a true part, with its errors.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Match {
    /// The true joint.
    pub true_joint: String,
    /// The estimated joint.
    pub est_joint: String,
    /// True joint type.
    pub true_kind: JointKind,
    /// Estimated joint type.
    pub est_kind: JointKind,
    /// Distance (m) between the two handles at the zero states.
    pub handle_distance: f64,
    /// Axis angle error (degrees, DiTH: the sign of the axis does not matter) of the
    /// estimator's axis (the discovery log's estimate; see [`estimator_errors`]).
    pub angle_error: f64,
    /// Axis position error (m) for a revolute joint of the right type (the distance between
    /// the axis lines), else `None`; of the estimator's axis, like `angle_error`.
    pub position_error: Option<f64>,
    /// The estimator's own joint type (the discovery log's estimate), which registration may
    /// have changed (a tiny turn the exploration saw as a slide is registered prismatic);
    /// Table II counts a part only where the estimator, too, got the type right.
    pub estimator_kind: JointKind,
    /// The angle error (degrees) of the registered joint: the estimate after discovery's
    /// gravity prior ([`DiscoverySettings::axis_snap`]).
    pub registered_angle_error: f64,
    /// Estimated upper limit (rad or m).
    pub est_upper: f64,
    /// Whether the estimated axis opens the part the same way as the true one (positive dot
    /// product of the directions, for the right type).
    pub same_sense: bool,
}

/// Matches the parts of `est` to `truth` one to one: every pair of handles within
/// [`MATCH_RADIUS`], closest pairs first.
pub fn match_parts(truth: &[PartAxis], est: &[PartAxis]) -> Vec<Match> {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, t) in truth.iter().enumerate() {
        for (j, e) in est.iter().enumerate() {
            let d = (t.handle - e.handle).norm();
            if d <= MATCH_RADIUS {
                pairs.push((d, i, j));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut used_t = vec![false; truth.len()];
    let mut used_e = vec![false; est.len()];
    let mut out = Vec::new();
    for (d, i, j) in pairs {
        if used_t[i] || used_e[j] {
            continue;
        }
        used_t[i] = true;
        used_e[j] = true;
        let (t, e) = (&truth[i], &est[j]);
        let angle_error = axis_angle_error(&e.direction, &t.direction);
        let position_error = (t.kind == JointKind::Revolute && e.kind == JointKind::Revolute)
            .then(|| axis_position_error(&e.pivot, &e.direction, &t.pivot, &t.direction));
        out.push(Match {
            true_joint: t.joint.clone(),
            est_joint: e.joint.clone(),
            true_kind: t.kind,
            est_kind: e.kind,
            handle_distance: d,
            angle_error,
            position_error,
            registered_angle_error: angle_error,
            estimator_kind: e.kind,
            est_upper: e.limits[1],
            same_sense: t.kind == e.kind && e.direction.dot(&t.direction) > 0.0,
        });
    }
    out.sort_by(|a, b| a.true_joint.cmp(&b.true_joint));
    out
}

/// Replaces the axis errors of `matches` (computed from the registered joints of `model`)
/// by those of the estimator's own axes in the log of `d`, keeping the registered angle error
/// in `registered_angle_error`: Table II measures the estimators, and registration levels
/// nearly level axes ([`DiscoverySettings::axis_snap`]). The log's axes are in the map frame
/// at exploration time, which is the zero state's for a part on the base; a part nested on
/// another keeps its registered errors (its parent may have been open when it was explored).
pub fn estimator_errors(matches: &mut [Match], truth: &[PartAxis], d: &Discovery) {
    for m in matches {
        let Some(t) = truth.iter().find(|t| t.joint == m.true_joint) else {
            continue;
        };
        let on_base = d
            .model
            .joint_id(&m.est_joint)
            .is_ok_and(|j| d.model.parts()[j.index()].parent() == Parent::Base);
        let estimate = d.log.iter().find_map(|l| match &l.outcome {
            Exploration::Registered { joint, .. } if *joint == m.est_joint => l.estimate.as_ref(),
            _ => None,
        });
        let Some((axis, e)) = estimate.and_then(|e| Some((e.axis?, e))) else {
            continue;
        };
        m.estimator_kind = match e.kind.as_str() {
            "revolute" => JointKind::Revolute,
            "prismatic" => JointKind::Prismatic,
            _ => m.estimator_kind,
        };
        if !on_base || m.estimator_kind != m.est_kind {
            continue;
        }
        m.angle_error = axis_angle_error(&axis, &t.direction);
        if let (Some(_), Some(pivot)) = (m.position_error, e.pivot) {
            m.position_error = Some(axis_position_error(&pivot, &axis, &t.pivot, &t.direction));
        }
    }
}

/// The index of the true part whose handle is nearest to `p`, within `radius`.
pub fn nearest_part(truth: &[PartAxis], p: &Point3<f64>, radius: f64) -> Option<usize> {
    truth
        .iter()
        .enumerate()
        .map(|(i, t)| (i, (t.handle - p).norm()))
        .filter(|(_, d)| *d <= radius)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}
