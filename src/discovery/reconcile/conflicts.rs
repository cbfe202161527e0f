//! The conflicts of an observation: the colliding body pairs of a state, or of a motion's
//! sweep.

use super::Observation;
use crate::discovery::error::DiscoveryError;
use crate::scene::collision::{
    Body, SweepSettings, SweepStatus, check_joint_motion, collisions, collisions_of,
};
use crate::scene::{SceneData, SceneModel, forward_kinematics};

/// The body pairs in conflict in `observation`, nearest (or first along the motion) first.
pub(super) fn conflicts(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
) -> Result<Vec<(Body, Body)>, DiscoveryError> {
    let mut data = SceneData::new(model);
    let contacts = match observation {
        Observation::State(state) => {
            forward_kinematics(model, &mut data, state)?;
            collisions(model, &data, &sweep.collision)?
        }
        Observation::Motion {
            state,
            joint,
            from,
            to,
        } => {
            let outcome = check_joint_motion(model, &mut data, state, *joint, *from, *to, sweep)?;
            match outcome.status {
                SweepStatus::Free => Vec::new(),
                SweepStatus::Collision { contacts, .. } => contacts,
                SweepStatus::Inconclusive { nearest, .. } => nearest,
            }
        }
    };
    Ok(contacts.into_iter().map(|c| (c.a, c.b)).collect())
}

/// The first conflicting pair of `observation` not in `stuck`.
pub(super) fn offender(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
    stuck: &[(Body, Body)],
) -> Result<Option<(Body, Body)>, DiscoveryError> {
    Ok(conflicts(model, observation, sweep)?
        .into_iter()
        .find(|p| !stuck.contains(p)))
}

/// Whether the pair `(a, b)` still conflicts in `observation`.
pub(super) fn still_conflicting(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
    a: Body,
    b: Body,
) -> Result<bool, DiscoveryError> {
    if let (Observation::State(state), Body::Part(p)) = (observation, a) {
        // The pair is one of `a`'s: checking `a`'s pairs is enough.
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, state)?;
        let contacts = collisions_of(model, &data, &sweep.collision, p)?;
        return Ok(contacts
            .iter()
            .any(|c| (c.a, c.b) == (a, b) || (c.a, c.b) == (b, a)));
    }
    Ok(conflicts(model, observation, sweep)?
        .iter()
        .any(|&p| p == (a, b) || p == (b, a)))
}
