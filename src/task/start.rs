//! The start-state check that runs before any search: a start state in which two bodies
//! already collide is a modelling error (a drawer placed inside its counter, a door slab
//! through its carcass), not a planning problem, so it is reported at once, by name.

use serde::{Deserialize, Serialize};

use super::Error;
use crate::scene::collision::{BodyName, CollisionSettings, collisions};
use crate::scene::{SceneData, SceneModel, State, forward_kinematics};

/// Two bodies that collide in a state (their separation is at most the collision predicate's
/// contact distance).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CollidingPair {
    /// The first body (always a part).
    pub a: BodyName,
    /// The second body.
    pub b: BodyName,
    /// Their exact separation (m; 0 when they overlap).
    pub distance: f64,
}

impl std::fmt::Display for CollidingPair {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.distance > 0.0 {
            write!(
                f,
                "{} and {} ({:.4} m apart)",
                self.a, self.b, self.distance
            )
        } else {
            write!(f, "{} and {} (touching or overlapping)", self.a, self.b)
        }
    }
}

/// Every pair of bodies that collide in `state` under `settings` (the task layer uses its
/// sweep's predicate, [`SweepSettings::collision`](crate::scene::collision::SweepSettings)):
/// every part against every other part and every base shape, by name. Empty when the state
/// is collision-free.
///
/// # Errors
/// The scene layer's errors for a state that does not fit `model` or invalid settings.
pub fn colliding_pairs(
    model: &SceneModel,
    state: &State,
    settings: &CollisionSettings,
) -> Result<Vec<CollidingPair>, Error> {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state)?;
    Ok(collisions(model, &data, settings)?
        .into_iter()
        .map(|c| CollidingPair {
            a: BodyName::of(model, c.a),
            b: BodyName::of(model, c.b),
            distance: c.distance,
        })
        .collect())
}

/// [`Error::StartInCollision`] when some bodies collide in `start`.
pub(super) fn check_start(
    model: &SceneModel,
    start: &State,
    settings: &CollisionSettings,
) -> Result<(), Error> {
    let pairs = colliding_pairs(model, start, settings)?;
    if pairs.is_empty() {
        Ok(())
    } else {
        Err(Error::StartInCollision { pairs })
    }
}
