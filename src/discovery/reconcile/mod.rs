//! Reconciling an estimated model with what the robot saw happen without a collision.
//!
//! Registration boxes each part around its observed points. Depth noise and a few points of a
//! neighbouring front make a box reach a centimetre or two past the true surface, while
//! kitchen fronts are 3–6 mm apart, so neighbouring estimated boxes can overlap where the
//! real parts did not touch: at the closed state the mapping saw, or along a motion the robot
//! executed (a door's hinge edge swinging into the drawer front next to it). The task layer
//! then finds every move of those parts colliding.
//!
//! What the robot saw is evidence: a state it saw, and a single-joint motion it executed, were
//! collision-free. [`reconcile`] makes the model agree with each [`Observation`] by moving box
//! faces inward, conflict by conflict: the faces of the newest part first (when it is in the
//! conflict; the parts before it already agreed), else of the other body (a part's only, for
//! a part–base conflict), the cut (of [`CUTS`]) that resolves it removing the least volume — one
//! face, or in a state two faces of one box. The other faces keep their extent, so a box is
//! never shrunk on a side where nothing conflicts (shrinking every side took 2 cm off the
//! kitchen's dishwasher door next to the sink door's handle, and the real arm then touched
//! the real door).
//!
//! Cuts only shrink boxes, so an observation made consistent stays consistent while later
//! ones are reconciled. A conflict that no cut of at most the largest of [`CUTS`] resolves
//! is reported, not forced.
//!
//! Here the observations, the report and the loop over conflicts; the conflicts of an
//! observation in `conflicts.rs`, the face cuts in `cut.rs`.

mod conflicts;
mod cut;
#[cfg(test)]
mod tests;

use serde::{Deserialize, Serialize};

use super::error::DiscoveryError;
use crate::scene::collision::{Body, BodyName, SweepSettings};
#[cfg(doc)]
use crate::scene::collision::{SweepStatus, check_joint_motion};
use crate::scene::{JointId, PartId, SceneModel, State};
use conflicts::offender;
use cut::best_cut;

/// Face cuts tried (m), smallest first.
pub const CUTS: [f64; 8] = [0.003, 0.006, 0.01, 0.015, 0.02, 0.03, 0.05, 0.08];
/// The smallest half extent (m) a cut box keeps.
const MIN_HALF_EXTENT: f64 = 0.005;
/// Conflicts resolved at most per observation (each round resolves one).
const MAX_ROUNDS: usize = 40;

/// Something the robot saw happen without a collision.
#[derive(Debug, Clone, PartialEq)]
pub enum Observation {
    /// The scene stood in this state (the mapping saw it closed; a task's start state).
    State(State),
    /// Joint `joint` moved from `from` to `to` (clamped into its limits), every other joint
    /// as in `state`.
    Motion {
        /// The other joints' values.
        state: State,
        /// The joint that moved.
        joint: JointId,
        /// Its value before (rad or m).
        from: f64,
        /// Its value after (rad or m).
        to: f64,
    },
}

/// One box face moved inward by [`reconcile`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoxCut {
    /// The part whose box was cut.
    pub part: String,
    /// Index of the box among the part's colliders.
    pub collider: usize,
    /// The face: box axis (0, 1, 2 for the box frame's x, y, z) and side (+1 or −1).
    pub axis: usize,
    /// `+1.0` for the face at `+half_extent`, `−1.0` for the opposite one.
    pub side: f64,
    /// How far the face moved in (m).
    pub depth: f64,
    /// The body the cut separates it from.
    pub other: BodyName,
    /// Index of the observation that required it.
    pub observation: usize,
}

/// A conflict no cut resolved: bodies `a` and `b` touch in observation `observation`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Conflict {
    /// Index of the observation.
    pub observation: usize,
    /// One body (a part).
    pub a: BodyName,
    /// The other body.
    pub b: BodyName,
}

/// What [`reconcile`] changed and what it could not resolve.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Reconciliation {
    /// The face cuts, in the order made.
    pub cuts: Vec<BoxCut>,
    /// The conflicts left.
    pub unresolved: Vec<Conflict>,
}

/// `model` with its boxes cut back until every observation is collision-free in it (see the
/// module documentation): a [`Observation::State`] has no colliding pair under
/// `sweep.collision`; a [`Observation::Motion`] is certified [`SweepStatus::Free`] by
/// [`check_joint_motion`] with `sweep` (an inconclusive sweep counts as a conflict with the
/// nearest pair, so a box left within the sweep's resolution of its neighbour is cut back
/// too). Observations are reconciled in order. Non-box colliders are never cut.
///
/// `newest` is the part to cut first: the one just registered, when the others already agreed
/// with what the robot saw (their boxes then stay as they were whenever cutting the newest
/// one resolves the conflict; otherwise the other body's least-volume cut is taken).
///
/// # Errors
/// [`DiscoveryError::Scene`] if the settings are invalid, an observation's state does not fit
/// `model`, or a cut model cannot be built (it is the input's tree with smaller boxes, so only
/// an invalid input fails).
pub fn reconcile(
    model: &SceneModel,
    observations: &[Observation],
    sweep: &SweepSettings,
    newest: Option<PartId>,
) -> Result<(SceneModel, Reconciliation), DiscoveryError> {
    sweep.validate()?;
    let mut model = model.clone();
    let mut out = Reconciliation::default();
    for (index, observation) in observations.iter().enumerate() {
        let observation = clamped(&model, observation);
        let mut stuck: Vec<(Body, Body)> = Vec::new();
        for _ in 0..MAX_ROUNDS {
            let Some((a, b)) = offender(&model, &observation, sweep, &stuck)? else {
                break;
            };
            // The newest part's faces first; if none of its cuts resolves the conflict, the
            // other body's (never the newest's candidates twice).
            let parts: Vec<PartId> = [a, b]
                .into_iter()
                .filter_map(|body| match body {
                    Body::Part(p) => Some(p),
                    Body::Base(_) => None,
                })
                .collect();
            let (first, rest): (Vec<PartId>, Vec<PartId>) =
                parts.into_iter().partition(|p| Some(*p) == newest);
            let cut = match best_cut(&model, &observation, sweep, a, b, &first)? {
                Some(c) => Some(c),
                None => best_cut(&model, &observation, sweep, a, b, &rest)?,
            };
            match cut {
                Some((cuts, cut_model)) => {
                    for cut in cuts {
                        let other = if Body::Part(cut.part) == a { b } else { a };
                        out.cuts.push(BoxCut {
                            part: model
                                .part(cut.part)
                                .map_or_else(String::new, |p| p.name().to_string()),
                            collider: cut.collider,
                            axis: cut.axis,
                            side: cut.side,
                            depth: cut.depth,
                            other: BodyName::of(&model, other),
                            observation: index,
                        });
                    }
                    model = cut_model;
                }
                None => stuck.push((a, b)),
            }
        }
        out.unresolved
            .extend(stuck.into_iter().map(|(a, b)| Conflict {
                observation: index,
                a: BodyName::of(&model, a),
                b: BodyName::of(&model, b),
            }));
    }
    Ok((model, out))
}

/// The observation with a motion's ends clamped into the joint's limits.
fn clamped(model: &SceneModel, observation: &Observation) -> Observation {
    match observation {
        Observation::Motion {
            state,
            joint,
            from,
            to,
        } => {
            let clamp = |v: f64| {
                model
                    .joint(*joint)
                    .map_or(v, |j| v.clamp(j.limits.lower, j.limits.upper))
            };
            Observation::Motion {
                state: state.clone(),
                joint: *joint,
                from: clamp(*from),
                to: clamp(*to),
            }
        }
        other => other.clone(),
    }
}
