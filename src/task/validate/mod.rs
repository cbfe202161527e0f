//! The independent plan validator: replays a plan with dense checks and the goal test.
//!
//! [`validate`] shares no code path with the search's feasibility predicate (`check/`,
//! `scene/nav/search.rs`, `reach.rs`, [`check_joint_motion`](crate::scene::collision::check_joint_motion)):
//! it uses only the scene layer's state queries ([`collisions_of`], [`occupancy`],
//! [`part_footprint`], [`grasp_trajectory`], [`max_displacement`]) and its own grid search, so
//! that a bug in the search's memo, keys or certified sweep shows up as a rejected plan.
//! (Underneath, [`collisions_of`] and `check_joint_motion` build their pair lists and exact
//! distances from the same scene-layer primitives; the scene tests check [`collisions_of`]
//! against [`collisions`](crate::scene::collision::collisions) over all pairs.)
//!
//! What is checked, and how it differs from the search: see [`validate`].
//!
//! [`collisions_of`]: crate::scene::collision::collisions_of
//! [`occupancy`]: crate::scene::nav::occupancy
//! [`part_footprint`]: crate::scene::nav::part_footprint
//! [`grasp_trajectory`]: crate::scene::motion::grasp_trajectory
//! [`max_displacement`]: crate::scene::motion::max_displacement

use serde::{Deserialize, Serialize};

use super::Error;
use super::goal::Problem;
use super::plan::Step;
use super::settings::TaskSettings;
use crate::scene::SceneModel;

mod base_pose;
mod cells;
mod exact;
mod replay;

use replay::Replay;

/// Largest number of collision samples per step of the dense sweep check.
pub const MAX_SWEEP_SAMPLES: usize = 200_000;

/// Largest number of footprint samples per step of the swept-footprint check.
const MAX_FOOTPRINT_SAMPLES: usize = 20_000;

/// Tolerance (rad or m) of the continuity check `from == current value`.
const FROM_TOLERANCE: f64 = 1e-9;

/// The verdict of [`validate`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Validation {
    /// Whether every step passed and the final state satisfies the goal.
    pub valid: bool,
    /// The first failing step (zero-based index) and why; `None` if every step passed.
    pub first_failure: Option<(usize, String)>,
    /// Goal joints whose target the replayed state misses (the final state, or the state
    /// before the first failing step).
    pub unmet: Vec<String>,
    /// Number of joint values checked for collisions over all replayed steps: `n + 1` per
    /// passed step, and up to the first colliding sample for a step that fails its sweep
    /// (samples are checked in parallel; the count does not depend on the scheduling).
    pub checked_samples: usize,
}

/// Replays `steps` from `problem.start` and checks each against the feasibility rules and
/// the final state against the goal, independently of the search.
///
/// # What is checked
/// Replaying from `problem.start`, for each step `i` moving joint `j` from `a` (the current
/// value) to `b`:
/// 1. **input**: `j` names a joint and `b` is finite and within its limits — otherwise the
///    plan does not fit the model and [`validate`] returns [`Error::InvalidStep`] (checked for
///    every step before the replay starts);
/// 2. **continuity**: `|from − a| <= 1e-9`;
/// 3. **sweep** (dense sampling): no checked pair between the moving subtree (the joint's
///    part and its descendants) and another body collides under
///    [`SweepSettings::collision`](crate::scene::collision::SweepSettings::collision)
///    ([`collisions_of`] with the joint's part) at `n + 1` equally spaced values from `a` to
///    `b`, where `n = ⌈L·|b − a| / min_margin⌉`, `L·|b − a|` the scene layer's
///    [`max_displacement`] bound and `min_margin` =
///    [`SweepSettings::min_margin`](crate::scene::collision::SweepSettings::min_margin): no
///    point of the moving subtree travels more than `min_margin` between samples. At most
///    [`MAX_SWEEP_SAMPLES`] per step (beyond the cap the spacing is
///    `L·|b − a| / MAX_SWEEP_SAMPLES`). Pairs inside the subtree are rigid and pairs of
///    fixed bodies do not change, so neither is checked, as in the search. The samples are
///    checked in parallel and the check stops at the first colliding one in order;
/// 4. **base pose**: some handle `h` of the joint's part (the step's `handle` if it names
///    one) and a base position `c` — the step's recorded `base`, or, if none is recorded,
///    any grid cell centre (brute force) — satisfy
///    - the [manipulation region](super::ManipulationSettings): at the `K + 1` grasp points
///      `p_k` of [`grasp_trajectory`], `height_min <= p_k.z <= height_max`, the start normal
///      at most `max_normal_elevation` from horizontal, and
///      `reach_min <= |c − p_k|_xy <= reach_max` (and, with an arm reach set,
///      [`ArmReach::admits`](super::ArmReach::admits) at every `p_k`), and
///      `(c − p_0)_xy · n_0 >= 0`;
///    - `c`'s cell is free in the occupancy of the state before the move
///      ([`occupancy`] inflated by the robot radius) and connected to the robot's start cell
///      through free cells (8-connected, a diagonal step needs both side cells free);
///    - `c`'s cell is outside the part's swept footprint: the union of the subtree's
///      [`part_footprint`]s at values spaced so that no point moves more than half a cell,
///      inflated by `max(radius − resolution·√2, 0)` (see below);
///    - `c`'s cell is free and connected to the start cell in the state after the move;
///    - with [`TaskSettings::boundary_clearance`] `Some(m)`, a recorded `c` whose cell fails
///      the first or the last of these occupancy rules passes it in exact geometry instead
///      when, at that state, parry's distance from the robot's footprint at `c` (a vertical
///      cylinder of the robot radius spanning the grid's height band) to every base shape and
///      part collider in the band exceeds `m` (less 1e-9), and a chain of straight moves,
///      each a parry shape cast of the footprint that touches nothing, leads from `c` through
///      side-neighbouring cells (each entered at the first contact-free point of a 7 × 7
///      lattice over the cell that such a move reaches) to the centre of a free cell
///      connected to the start cell;
///
///    With [`ManipulationSettings::segments`](super::ManipulationSettings::segments) `S >= 2`
///    a `c` that covers only a prefix `p_0..=p_e` (`e >= 1`, from the front at `p_0`) is in
///    the region too when some `p_t`, `1 <= t <= e`, starts at most `S − 1` runs covering the
///    rest: each run covers `p_s..=p_u` from one cell of the inflated base map connected to
///    the start cell, on the front side at `p_s` (brute force over every such cell, then a
///    breadth-first pass over the waypoints); such a `c` is exempt from the swept-footprint
///    condition;
/// 5. **goal**: after the last step, [`Goal::is_satisfied`](super::Goal::is_satisfied);
///    `unmet` lists the goal joints outside their target.
///
/// The replay stops at the first failing step (2–4): `first_failure` holds its index and the
/// reason, and `unmet` is evaluated in the state before it. The robot's start cell follows
/// the search's rule (the cell of `problem.robot.base`, snapped to the nearest free cell
/// within one radius plus one cell; without a base pose, the free cell nearest the grid
/// centre). Refinement vetoes are not replayed: the validator knows no refiner.
///
/// # How it differs from the search
/// - The search **certifies** each sweep over the continuous interval (Lipschitz bound,
///   exact distances, adaptive refinement); the validator samples **densely** at a fixed
///   spacing, so it can miss a collision narrower than `min_margin` of travel (or than the
///   capped spacing). A certified-free sweep passes every sample (up to the exact distance
///   query's own tolerance, about `5e-8` relative), so a plan the search returns validates;
///   the converse can fail only for sweeps that pass within the resolution of another body,
///   which the search declares `Inconclusive` (and treats as blocked) while dense samples
///   find no contact.
/// - The swept footprint: the search inflates its samples' footprints by
///   `radius + spacing/2` (sound for the continuous sweep). Different samples rasterise to
///   different cells, so the validator's own footprint is not comparable cell by cell; it
///   inflates by `radius − resolution·√2` instead. Every value of the motion lies within half
///   a search spacing of a search sample, and a rasterised cell is within its diagonal of the
///   shadow that marks it, so every cell the validator marks is marked by the search too: a
///   search plan passes (assuming no collider of the subtree enters or leaves the grid's
///   height band or the grid itself during the motion). The price is a tolerance: the
///   validator accepts a base disc that reaches up to `resolution·√2 + resolution/4` into
///   the continuous sweep's shadow.
/// - Occupancy, connectivity and the region are the same rules, recomputed independently.
///
/// [`collisions_of`]: crate::scene::collision::collisions_of
/// [`occupancy`]: crate::scene::nav::occupancy
/// [`part_footprint`]: crate::scene::nav::part_footprint
/// [`grasp_trajectory`]: crate::scene::motion::grasp_trajectory
/// [`max_displacement`]: crate::scene::motion::max_displacement
///
/// # Errors
/// Bad input only: [`Error::InvalidStep`] for a step naming an unknown joint or a `to`
/// value that is not finite or outside the joint's limits; [`Error::InvalidSetting`] and
/// scene errors for invalid settings or a start state that does not fit the model;
/// [`Error::InvalidRobotStart`] as for [`plan`](super::plan). A plan that breaks a rule is
/// `Ok` with `valid == false`.
///
/// # Example
/// ```
/// use kinscene::scene::{Handle, Joint, Limits, PartSpec, SceneModelBuilder, Shape};
/// use kinscene::task::{GoalSpec, Problem, Step, TaskSettings, validate};
/// use nalgebra::{Isometry3, Point3, Vector3};
///
/// let mut b = SceneModelBuilder::new();
/// b.add_part(
///     PartSpec::on_base("door", Joint::revolute("hinge", Point3::origin(), Vector3::z(), Limits::new(0.0, 1.6)))
///         .with_collider(Shape::box_size(Vector3::new(0.5, 0.02, 0.7)), Isometry3::translation(0.25, 0.0, 0.35))
///         .with_handle(Handle::new("door_handle", Point3::new(0.45, -0.03, 0.35), -Vector3::y())),
/// );
/// let model = b.build()?;
/// let spec = GoalSpec::from_toml("[goal]\nhinge = { min = 1.2 }\n[robot]\nbase = [0.8, -0.8, 0.0]")?;
/// let problem = Problem::from_spec(&model, &spec)?;
/// let step = |to: f64| Step {
///     joint: "hinge".into(), from: 0.0, to,
///     handle: None, base: None, travel: 0.0, cost: 0.0,
/// };
/// let settings = TaskSettings::default();
/// assert!(validate(&model, &problem, &[step(1.3)], &settings)?.valid);
/// // Opening only to 1.0 rad leaves the goal unmet.
/// assert_eq!(validate(&model, &problem, &[step(1.0)], &settings)?.unmet, ["hinge"]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn validate(
    model: &SceneModel,
    problem: &Problem,
    steps: &[Step],
    settings: &TaskSettings,
) -> Result<Validation, Error> {
    settings.validate()?;
    problem.start.validate(model)?;
    let model = &*model.covering(&problem.robot.start_point())?;
    // 1. Every step must fit the model before anything is replayed.
    let mut joints = Vec::with_capacity(steps.len());
    for (i, s) in steps.iter().enumerate() {
        let bad = |message: String| Error::InvalidStep { step: i, message };
        let joint = model
            .joint_id(&s.joint)
            .map_err(|_| bad(format!("unknown joint {:?}", s.joint)))?;
        let limits = model.joints()[joint.index()].limits;
        if !(s.to.is_finite() && limits.contains(s.to)) {
            return Err(bad(format!(
                "target {} of joint {:?} is outside its limits [{}, {}]",
                s.to, s.joint, limits.lower, limits.upper
            )));
        }
        joints.push(joint);
    }
    let mut replay = Replay::new(model, problem, settings)?;
    let mut state = problem.start.clone();
    let mut first_failure = None;
    for (i, (s, &joint)) in steps.iter().zip(&joints).enumerate() {
        let a = state.q[joint.index()];
        let failure = if (s.from - a).abs() <= FROM_TOLERANCE {
            replay.step(&state, joint, s)?
        } else {
            Some(format!(
                "joint {:?} is at {a} but the step starts from {}",
                s.joint, s.from
            ))
        };
        if let Some(why) = failure {
            first_failure = Some((i, why));
            break;
        }
        state.q[joint.index()] = s.to;
    }
    let unmet: Vec<String> = problem
        .goal
        .targets()
        .iter()
        .filter(|(j, t)| !t.contains(state.q[j.index()]))
        .map(|(j, _)| model.joints()[j.index()].name.clone())
        .collect();
    debug_assert_eq!(
        unmet.is_empty(),
        problem.goal.is_satisfied(&state),
        "unmet agrees with the goal test"
    );
    Ok(Validation {
        valid: first_failure.is_none() && problem.goal.is_satisfied(&state),
        first_failure,
        unmet,
        checked_samples: replay.samples,
    })
}
