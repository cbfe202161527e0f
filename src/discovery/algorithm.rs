//! Algorithm 1 (articulation discovery) as a library function: [`discover`].

use std::collections::BTreeMap;

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use super::error::{DiscoveryError, check_finite};
use super::fusion::MappedHandle;
use super::interface::Robot;
use super::log::{Exploration, HandleLog, Stage};
use super::placement::FreeSpace;
use super::reconcile::{CUTS, Observation, Reconciliation, reconcile};
use super::run::Run;
use super::settings::DiscoverySettings;
use crate::articulation::ArticulationEstimator;
use crate::scene::collision::SweepSettings;
use crate::scene::{BaseMap, PartId, SceneModel, SceneModelBuilder, State};

/// The result of [`discover`]: the scene model M, the state the scene was left in, and what
/// happened to every handle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Discovery {
    /// The base map plus one registered part per successfully explored handle.
    pub model: SceneModel,
    /// The estimated current state: each explored part at the opening it was left at (the
    /// exploration does not close what it opened).
    pub state: State,
    /// One entry per input handle, in input order.
    pub log: Vec<HandleLog>,
    /// How the registered boxes were cut back to agree with what the robot saw (the closed
    /// scene, each executed opening), and what could not be made to agree.
    pub reconciliation: Reconciliation,
}

/// Algorithm 1: explores every handle physically and builds the scene-level articulation
/// model M from the base map `base` and one registered part per handle whose exploration and
/// estimation succeeded.
///
/// Per handle `h` (in input order; see [`fuse_detections`](super::fuse_detections) for the
/// order it produces):
/// 1. **PlanBase(h)**: the base pose facing `h` at `approach_distance` along the handle's
///    registered normal (its horizontal part; for a nearly vertical normal, the direction
///    from the handle to the robot), free in the current scene's navigation grid inflated by
///    `robot_radius`; if the nominal position is occupied, a free position on rings around
///    the handle (turns up to ±60°, within `base_search_radius` of the nominal position):
///    the one whose distance to the handle is nearest the nominal distance, then the smaller
///    turn, then the nearer to the nominal position.
///    No pose: a [`Stage::Navigation`] failure.
/// 2. **GlobalNavTo**, then **DetectHandle**: the detection nearest to `h` within
///    `redetect_radius`, over up to `redetect_tries` detector frames (the first frame with
///    one wins). A navigation failure is [`Stage::Navigation`]; no detection (or no
///    observation) is [`Stage::Mapping`] (the mapped handle was not real where mapped).
///    The surface normal is refined by a plane fit to the observation around the detection
///    (kept if within 45° of the registered normal).
/// 3. **PlanBase(p)** at `interaction_distance`; then up to `max_attempts` attempts:
///    **LocalNavTo(b_pre)** tracking the handle, the pre-interaction observation `o_pre`
///    (`observation_camera`), the grasp (approach against the normal) and up to `max_steps`
///    pull steps of `step` metres, each preceded by:
///    - **DetectFailure**: a new observation from the same camera; the mean distance from its
///      points within `displacement_radius` of the contact to their nearest neighbours in
///      `o_pre` (each capped at `displacement_cap`) is the part's displacement. Still below
///      `displacement_threshold` after `stall_steps` steps is a failure (the part does not
///      move: a slipped grasp, a wrong direction, no joint). Hardware failure signals
///      (grasp, pull) are failures too, except when the contact is already `sufficient_pull`
///      from the first grasp point with the part displaced: then the attempt ends as a
///      success. With `resume_short_pulls` (off by default), while it is short of
///      `target_pull` and attempts remain, the robot still Repositions and pulls on from the
///      last contact, as Algorithm 1 retries every failure; the success stands whatever the
///      later attempts do.
///    - **GetComplianceAction**: the surface normal from a robust plane fit (PCA, one
///      inlier refit) to the `interaction_camera` observation within `normal_radius` of the
///      contact, oriented towards the sensor; the pull direction is
///      `surface_weight · n + (1 − surface_weight) · m̂`, with `m̂` the direction of the
///      contact's last step (the surface predicts the part's motion — for a door the
///      surface normal at the handle is tangent to its arc; the motion so far smooths noise).
///
///    The attempt succeeds when the contact is `target_pull` from the handle's first grasp
///    point (the opening over all attempts so far), or all steps ran with the part displaced.
///    A failed local navigation or pre-interaction observation uses up an attempt. After a
///    failed observation the next attempt retries from the same pose. After a failed local
///    navigation (the robot's own navigation refused the goal: something the base map does
///    not hold stands there) the next attempt goes to the free pose found as in PlanBase, at
///    the same distance from the handle, that keeps `robot_radius` from every refused goal
///    (the same pose if there is none); the log notes it. If every attempt failed at local
///    navigation, the handle is a [`Stage::Navigation`] failure, otherwise a
///    [`Stage::Exploration`] failure.
/// 4. **Reposition** after a failed attempt (the arm is retracted first): the motion seen is
///    classified ([`MotionClass`](super::MotionClass)) from the tracked plane — the turn of
///    the surface normal between the first and last step (the end effector's rotation when
///    the plane was not tracked): at least `rotation_threshold` is revolute, left
///    (clockwise seen from above) or right, or about a horizontal axis; otherwise a contact
///    motion of at least `translation_threshold` is prismatic; a part that was not displaced
///    is "no motion". The base then moves by `reposition_distance` (the paper's 30 cm):
///    towards the side of the rotation for a left/right revolute joint, straight back for
///    prismatic and horizontal-axis joints, and not at all for no motion (a plain retry);
///    the move is shortened to 3/4, 1/2, 1/4 if the target is occupied. The next attempt grasps
///    along the last tracked normal at the last contact (so the end effector keeps tracing
///    one point of the part: an arc or a line of the same joint, what the estimators fit),
///    or, when the last attempt's gripper closed on no handle (`GraspLost` at the grasp),
///    where DetectHandle finds it after LocalNavTo (as in step 2, within `redetect_radius`
///    of the point that missed; that point again if it is not re-detected). The same point
///    would miss again: a re-detection off by more than the gripper's reach of the handle,
///    or a part that moved on after the last contact (under a pull step the arm could not
///    follow, and settling after the release).
/// 5. **Post-interaction observation** from a small step back (Algorithm 1, lines 24–27):
///    after retracting, the base goes to `PlanBase(p)` at `interaction_distance +
///    post_step_back` (if that fails, the observation is taken from where the robot is, and
///    the log notes it).
/// 6. **PredArticulation**: the estimator gets the first attempt's `o_pre` (the closed pose:
///    retries add motion instead of restarting it — the listing overwrites `o_pre` per
///    attempt, but only the closed pose can be registered as the joint's zero), `o_post`,
///    the first grasp contact, the last contact, and every end-effector pose recorded while
///    grasping (after a regrasp, the later grasps' poses are expressed in the first grasp's
///    frame, stitched where each grasp began: one rigid grasp, the estimators' model). An
///    `Unknown` estimate is a [`Stage::Estimation`] failure, and so is a revolute axis that
///    contradicts the rotation the exploration measured: more than 45° from
///    horizontal for a front seen turning about a horizontal axis, or less than 45° for one
///    seen turning left or right (the last attempt that saw a rotation decides). A revolute
///    estimate that turned less than `rotation_threshold` while every attempt that moved the
///    part saw it slide is registered as the slide along the chord its contact moved (a turn
///    that small about an axis metres away is a translation; the log keeps the estimate).
///
///    **Keep pulling until confident** (beyond the paper's Algorithm 1): the estimate has a
///    doubt ([`Doubt`](super::Doubt)) when its axis's 95 % half-angle exceeds
///    `confident_axis_95`, a revolute pivot's 95 % radius exceeds `confident_pivot_95`, its
///    type probability is below `confident_type_probability`, or it carries no uncertainty
///    (an unknown joint). While it has one, up to `max_extra_pulls` times, the robot pulls
///    further: LocalNavTo back to the last successful attempt's base pose, a new `o_pre`
///    (DetectFailure's reference), a grasp at the last contact along the last tracked
///    normal, pull steps until the contact is `extra_pull` from that grasp (the same
///    DetectFailure and GetComplianceAction), retract, then step 5 and this step again on
///    all the motion so far (the new grasp's poses stitched like a retry's). A pull that
///    ended at the arm's limit (`JointLimit`, from the first attempts or a further pull)
///    cannot go on from its base pose: the next further pull starts from PlanBase for the
///    last contact instead (facing it along the last tracked normal at
///    `interaction_distance`; `reposition_at_arm_limit`), and the log notes the pose.
///    Pulling stops when the estimate is confident, at the arm's limit when no other free
///    pose is found (or the setting is off), when a further pull moves nothing (the part's
///    own limit) or fails otherwise, or after `max_extra_pulls`;
///    [`HandleLog::pulling`](super::HandleLog) says
///    which ([`PullEnd`](super::PullEnd)), with the doubts left, and the estimate log the
///    uncertainty it stopped at. The most confident estimate is kept (the least largest ratio
///    of a region to its limit): when a further pull made the estimate worse (a view the
///    estimator could not use), the earlier one is kept with its opening re-measured to the
///    last contact (the angle about its axis, the distance along it), and the log notes it.
///    The checks above apply to the kept estimate.
/// 7. **Register**: the joint from the estimate, oriented so that the observed opening is
///    positive — revolute: the axis through the foot of the perpendicular from the contact
///    onto the estimated axis; prismatic: the axis through the contact. An axis within
///    `axis_snap` of horizontal is projected onto the horizontal plane, one within it of
///    vertical made vertical (the gravity prior: furniture joints are built level; noted in
///    the log, which keeps the estimator's own axis). Its frame is aligned
///    with the map frame at discovery time, so the part frame at value 0 is the closed pose
///    observed before the interaction. Limits `[0, max(observed, default upper)]`
///    (`default_revolute_upper`, `default_prismatic_upper`). Box colliders around the
///    estimator's part points (or, if it returned fewer than 4, the pre points that moved
///    consistently with the estimated joint), after dropping the points that cannot be the
///    part's: for a revolute joint those beyond the hinge line (a front turns about an edge),
///    then those within `base_clearance` of the base map (static surfaces), then those not
///    connected to the contact. The box has one axis along the joint axis (a front's edges
///    run along or across it), the others turned about it to the least trimmed area; extents
///    are trimmed by `box_trim`, at least `min_half_extent` (a flat front's thickness is
///    padded behind its observed surface, against the normal). The front's box ends at its
///    surface (the median depth along the normal; depth noise spreads returns either side);
///    points more than `handle_standoff` in front of it (the handle, a tray on a door) are
///    grouped into connected clusters; those of at least 10 points whose median stands out
///    by 1.5 `handle_standoff` or more get their own box (the rest is noise), so a handle
///    does not thicken the whole front. Each drop and split is noted in the log. One handle
///    with the refined normal, at the centre of the protrusion nearest the contact if one
///    is within 5 cm of it (the handle as the camera saw it), else at the contact. The parent is the already registered part whose collider, at its
///    current estimated pose, is within `nest_margin` of the contact (the nearest; ties to
///    the deeper part) — a dishwasher rack reached through its open door — else the base
///    map. Parts are named `part{i}` after the handle's input index, joints
///    `part{i}_hinge` / `part{i}_slide`, handles `part{i}_handle`. A model the scene builder
///    rejects is a [`Stage::Estimation`] failure.
/// 8. **Reconcile** ([`reconcile`], with `sweep`): what the robot saw was collision-free — the
///    closed scene (the mapping), and each opening it executed (from 0 to the part's value,
///    the parts explored before at the openings they were left at, the others closed) — so
///    the model with the new part is cut back, one box face at a time, until those are
///    collision-free in it, cutting the new part's faces first (the parts before it already
///    agreed). A conflict no cut resolves is kept and recorded in
///    [`Discovery::reconciliation`] (the part stays: dropping it would hide an obstacle from
///    the motion planner). Cuts and conflicts are noted in the handle's log.
///
/// The navigation grid includes the parts registered so far at their current opening, so
/// later base poses avoid the doors left open. A mapped handle within `nest_margin` of a
/// registered part's collider in its closed pose (where the mapping saw it) is carried along
/// with the part's estimated motion before it is explored, so a handle on a door that was
/// left open is looked for where it now is (and then nests on the door).
///
/// # Errors
/// [`DiscoveryError::InvalidSetting`]; [`DiscoveryError::UnregisteredHandle`] for a handle
/// without attachment; [`DiscoveryError::NonFinite`] for a NaN handle, pose or observation;
/// [`DiscoveryError::Scene`] for an invalid base map; [`DiscoveryError::Estimator`] when the
/// estimator rejects its input. Hardware and sensor failures, lost handles and unknown
/// estimates are outcomes in the log.
pub fn discover(
    robot: &mut dyn Robot,
    base: &BaseMap,
    handles: &[MappedHandle],
    estimator: &dyn ArticulationEstimator,
    settings: &DiscoverySettings,
) -> Result<Discovery, DiscoveryError> {
    settings.validate()?;
    check_handles(handles)?;
    let mut builder = SceneModelBuilder {
        base: base.clone(),
        parts: Vec::new(),
    };
    let mut model = builder.build()?;
    let mut values: BTreeMap<String, f64> = BTreeMap::new();
    let mut log = Vec::with_capacity(handles.len());
    let mut run = Run {
        robot,
        estimator,
        s: settings,
    };
    // Where the handles are expected now: handles on an explored part move with it.
    let mut pending: Vec<MappedHandle> = handles.to_vec();
    // Each executed opening: the other joints' values then, the joint, its opening.
    let mut openings: Vec<Opening> = Vec::new();
    let mut reconciliation = Reconciliation::default();
    for index in 0..pending.len() {
        let h = pending[index].clone();
        let state = state_of(&model, &values)?;
        let free = FreeSpace::new(&model, &state, settings.robot_radius)?;
        let (mut entry, part) = run.handle(index, &h, &model, &state, &free)?;
        if let Some(part) = part {
            let joint = part.spec.joint.name.clone();
            let name = part.spec.name.clone();
            builder.parts.push(part.spec.clone());
            match builder.build() {
                Ok(m) => {
                    let mut tried = openings.clone();
                    tried.push((values.clone(), joint.clone(), part.value));
                    let newest = m.part_id(&name).ok();
                    let (cut, rec) = reconciled(&m, &tried, &settings.sweep, newest)?;
                    note_reconciliation(&mut entry.notes, &rec, &tried);
                    reconciliation.cuts.extend(rec.cuts);
                    reconciliation.unresolved.extend(rec.unresolved);
                    model = cut;
                    builder = model.to_builder();
                    openings = tried;
                    values.insert(joint, part.value);
                    for later in &mut pending[index + 1..] {
                        if part.carries(&later.position, settings.nest_margin) {
                            carry(later, &part.world_motion);
                            entry.notes.push(format!(
                                "carried a mapped handle at {:?} along with {name}",
                                later.position
                            ));
                        }
                    }
                }
                Err(e) => {
                    let spec = builder.parts.pop();
                    entry.outcome = Exploration::Failed {
                        stage: Stage::Estimation,
                        reason: format!(
                            "the scene builder rejected part {:?}: {e}",
                            spec.map(|s| s.name).unwrap_or_default()
                        ),
                    };
                }
            }
        }
        log.push(entry);
    }
    let state = state_of(&model, &values)?;
    Ok(Discovery {
        model,
        state,
        log,
        reconciliation,
    })
}

/// An executed opening: the other joints' values then, the joint's name, its opening.
type Opening = (BTreeMap<String, f64>, String, f64);

/// The input checks of [`discover`]: every handle finite and registered to the base map.
fn check_handles(handles: &[MappedHandle]) -> Result<(), DiscoveryError> {
    for (index, h) in handles.iter().enumerate() {
        check_finite(h.position.coords.iter().copied(), || {
            format!("position of handle {index}")
        })?;
        let a = h
            .attachment
            .as_ref()
            .ok_or(DiscoveryError::UnregisteredHandle { index })?;
        check_finite(a.normal.iter().copied(), || {
            format!("normal of handle {index}")
        })?;
    }
    Ok(())
}

/// Step 8's notes for the handle's log: each cut of `rec`, then each conflict left, naming the
/// observation it was made for (0 the closed scene, `k` the opening `tried[k - 1]`).
fn note_reconciliation(notes: &mut Vec<String>, rec: &Reconciliation, tried: &[Opening]) {
    let what = |k: usize| match k {
        0 => "the closed scene the mapping saw".to_string(),
        k => format!("the opening of {} it executed", tried[k - 1].1),
    };
    for c in &rec.cuts {
        notes.push(format!(
            "box {} of {} cut back by {} m on its {}{} face, clear of {} \
                 in {}",
            c.collider,
            c.part,
            c.depth,
            if c.side > 0.0 { "+" } else { "-" },
            ["x", "y", "z"][c.axis],
            c.other,
            what(c.observation)
        ));
    }
    for c in &rec.unresolved {
        notes.push(format!(
            "{} and {} still collide in {} with the boxes cut back by up \
                 to {} m (kept: the estimate is off there)",
            c.a,
            c.b,
            what(c.observation),
            CUTS[CUTS.len() - 1]
        ));
    }
}

/// `model` reconciled with the closed scene (the mapping saw it) and every opening in
/// `openings` (each executed without a collision), in that order.
fn reconciled(
    model: &SceneModel,
    openings: &[Opening],
    sweep: &SweepSettings,
    newest: Option<PartId>,
) -> Result<(SceneModel, Reconciliation), DiscoveryError> {
    let mut observations = vec![Observation::State(model.zero_state())];
    for (before, joint, value) in openings {
        observations.push(Observation::Motion {
            state: state_of(model, before)?,
            joint: model.joint_id(joint)?,
            from: 0.0,
            to: *value,
        });
    }
    reconcile(model, &observations, sweep, newest)
}

/// Moves a mapped handle (position, attachment point and normal) by `motion`.
fn carry(h: &mut MappedHandle, motion: &Isometry3<f64>) {
    h.position = motion * h.position;
    if let Some(a) = &mut h.attachment {
        a.surface_point = motion * a.surface_point;
        a.normal = motion * a.normal;
    }
}

/// The model's state with the named joint values (clamped into the limits).
fn state_of(model: &SceneModel, values: &BTreeMap<String, f64>) -> Result<State, DiscoveryError> {
    Ok(State::from_values_clamped(
        model,
        values.iter().map(|(n, v)| (n.as_str(), *v)),
    )?)
}
