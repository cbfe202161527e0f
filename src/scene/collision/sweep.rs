//! Continuous-sound collision checking along a one-joint motion: the public entry point.

use super::query::{Contact, Placement, checked_pairs};
use super::search::Search;
use super::settings::SweepSettings;
use crate::scene::kinematics::{forward_kinematics, joint_axis};
use crate::scene::motion::{MotionBound, check_joint_value, motion_bound};
use crate::scene::{Error, JointId, SceneData, SceneModel, State};

/// Why a sweep could not be decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InconclusiveReason {
    /// Some interval could not be certified free at the finest resolution
    /// ([`SweepSettings::min_margin`]), although none of the samples collides: the moving
    /// subtree passes within about `contact_distance + 2·min_margin` of another body.
    Resolution,
    /// The sample budget ([`SweepSettings::max_samples`]) ran out.
    SampleBudget,
}

/// The verdict of [`check_joint_motion`].
#[derive(Debug, Clone, PartialEq)]
pub enum SweepStatus {
    /// Certified collision-free over the whole closed interval of values.
    Free,
    /// At joint value `value` (an actual sample) the listed pairs collide: the motion is
    /// definitely not free. It is the first colliding sample found from `a` towards `b`; the
    /// sample before it, at most one finest interval (`2·min_margin / L`) earlier, is free.
    Collision {
        /// Joint value (rad or m) of the colliding sample.
        value: f64,
        /// The colliding pairs at that value (`a` is a moving part), nearest first.
        contacts: Vec<Contact>,
    },
    /// Not certified free, yet no sample collides (or the budget ran out first); treat the
    /// motion as blocked.
    Inconclusive {
        /// Joint value (rad or m) of the first uncertifiable interval's nearer end, or where
        /// the budget ran out.
        value: f64,
        /// The checked pairs nearest to contact there, with their exact distances.
        nearest: Vec<Contact>,
        /// Why.
        reason: InconclusiveReason,
    },
}

/// The result of [`check_joint_motion`].
#[derive(Debug, Clone, PartialEq)]
pub struct SweepOutcome {
    /// The verdict.
    pub status: SweepStatus,
    /// Every value between `a` and `free_until` (closed) is certified collision-free; `b` when
    /// the status is [`SweepStatus::Free`], `None` if not even `a` is.
    pub free_until: Option<f64>,
    /// Number of joint values at which distances were evaluated.
    pub samples: usize,
    /// The motion bound used.
    pub bound: MotionBound,
}

impl SweepOutcome {
    /// Whether the motion is certified collision-free.
    pub fn is_free(&self) -> bool {
        self.status == SweepStatus::Free
    }
}

/// Checks the motion of `joint` from `a` to `b`, the other joints at their values in `state`,
/// for collisions of the moving subtree (the joint's part and its descendants) with every
/// other checked body (other parts and base shapes; see
/// [`CollisionSettings`](super::CollisionSettings) for the predicate and exemptions). Pairs
/// inside the moving subtree are rigid and pairs between fixed bodies do not change, so
/// neither is checked here (use [`collisions`](super::collisions) at the start state).
///
/// **Guarantee.** Let `D(θ)` be the minimum exact distance over the checked pairs at joint
/// value `θ`, `c` the contact distance and `L` the Lipschitz constant of the
/// [`MotionBound`] (the sweep radius in m/rad for revolute, 1 for prismatic). If the status is
/// [`SweepStatus::Free`] then `D(θ) > c` for **every** `θ` in the closed interval between `a`
/// and `b`, not only at the samples; likewise on `[a, free_until]` for any status. Reason:
/// every point of the moving subtree travels at most `L·|θ − θ'|` between values `θ` and `θ'`
/// (the motion bound), so `D` is `L`-Lipschitz. An interval `[s, e]` is accepted only if
/// `ℓ(s) > c`, `ℓ(e) > c` and `ℓ(s) + ℓ(e) − L·|e − s| > 2c`, where `ℓ ≤ D` are the computed
/// distances (exact parry distances, or bounding-sphere gaps for pairs provably farther than
/// `c + L·h₀`, `h₀` the initial spacing); then for `θ` inside,
/// `D(θ) ≥ max(ℓ(s) − L·|θ − s|, ℓ(e) − L·|e − θ|) ≥ (ℓ(s) + ℓ(e) − L·|e − s|)/2 > c`.
/// In terms of a margin `m`: samples spaced so that no point travels more than `2m` between
/// them, each with clearance `> c + m`, pass this test. Conversely
/// [`SweepStatus::Collision`] is only reported at a sample with an exact distance `<= c`.
///
/// **Sampling.** The first samples split `[a, b]` into `⌈L·|b − a| / (2·margin)⌉` equal
/// intervals (travel `<= 2·margin` each). An interval that fails the test is halved
/// (halving its margin) while its margin `L·|e − s|/2` exceeds `min_margin`. A finest
/// interval that still fails, with no colliding sample, is recorded as unresolved and the
/// search goes on, so a later real collision is still reported as such; with none, the
/// status is [`SweepStatus::Inconclusive`] at the first unresolved interval. Intervals are
/// explored from `a` towards `b` and the search stops at the first colliding sample, after
/// refining to the finest resolution before it.
///
/// **Assumptions.** Rigid parts; geometry exactly as modelled (convex shapes); exact distance
/// queries (parry's GJK stops at a relative error of about `5e-8`, far below sensible
/// `min_margin`s); the other joints do not move. On return `data` holds the forward
/// kinematics of `state`.
///
/// # Errors
/// [`Error::InvalidSetting`] for invalid settings; [`Error::UnknownId`],
/// [`Error::DimensionMismatch`]; [`Error::NonFinite`] / [`Error::JointLimit`] if `state` is
/// invalid or `a`, `b` are not valid values of the joint.
pub fn check_joint_motion(
    model: &SceneModel,
    data: &mut SceneData,
    state: &State,
    joint: JointId,
    a: f64,
    b: f64,
    settings: &SweepSettings,
) -> Result<SweepOutcome, Error> {
    settings.validate()?;
    state.validate(model)?;
    check_joint_value(model, joint, a)?;
    check_joint_value(model, joint, b)?;
    forward_kinematics(model, data, state)?;
    let bound = motion_bound(model, data, joint)?;
    let root = joint.part();
    let mut search = Search {
        model,
        settings,
        axis: joint_axis(model, data, joint)?,
        theta0: state.as_slice()[joint.index()],
        lipschitz: bound.lipschitz(),
        moving: root.index()..root.index() + model.parts()[root.index()].subtree().len(),
        world_from_moving: model.parts()[root.index()]
            .subtree()
            .map(|p| data.world_from_parts()[p.index()])
            .collect(),
        fixed: Placement::new(model, data),
        pairs: checked_pairs(model, &settings.collision, Some(root)),
        cutoff: 0.0,
        samples: 0,
        free_until: None,
        contiguous: true,
        unresolved: None,
    };
    let status = search.run(a, b);
    Ok(SweepOutcome {
        status,
        free_until: search.free_until,
        samples: search.samples,
        bound,
    })
}
