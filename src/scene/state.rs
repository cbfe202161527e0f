//! The scene's kinematic state Θ: one value per joint.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::ids::JointId;
use super::joint::Joint;
use super::model::SceneModel;
use super::{ElementKind, Error};

/// Joint values Θ (radians or metres), indexed by [`JointId`], for one [`SceneModel`].
///
/// Constructors and checked setters validate against the model: known names, finite values,
/// within limits. [`set_clamped`](State::set_clamped) and
/// [`from_values_clamped`](State::from_values_clamped) clamp into the limits instead of
/// failing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub(crate) q: Vec<f64>,
}

fn checked_value(joint: &Joint, value: f64) -> Result<f64, Error> {
    if !value.is_finite() {
        return Err(Error::NonFinite {
            what: format!("value of joint {:?}", joint.name),
        });
    }
    if !joint.limits.contains(value) {
        return Err(Error::JointLimit {
            joint: joint.name.clone(),
            value,
            min: joint.limits.lower,
            max: joint.limits.upper,
        });
    }
    Ok(value)
}

fn clamped_value(joint: &Joint, value: f64) -> Result<f64, Error> {
    if value.is_nan() {
        return Err(Error::NonFinite {
            what: format!("value of joint {:?}", joint.name),
        });
    }
    Ok(joint.limits.clamp(value))
}

impl State {
    /// The zero state ([`SceneModel::zero_state`]) with the named joints set.
    /// Joints not named keep 0 clamped into their limits.
    ///
    /// # Errors
    /// [`Error::UnknownJoint`], [`Error::NonFinite`], [`Error::JointLimit`].
    pub fn from_values<S: AsRef<str>>(
        model: &SceneModel,
        values: impl IntoIterator<Item = (S, f64)>,
    ) -> Result<State, Error> {
        let mut state = model.zero_state();
        for (name, value) in values {
            state.set_by_name(model, name.as_ref(), value)?;
        }
        Ok(state)
    }

    /// [`from_values`](State::from_values) from a map.
    ///
    /// # Errors
    /// As [`from_values`](State::from_values).
    pub fn from_map(model: &SceneModel, values: &BTreeMap<String, f64>) -> Result<State, Error> {
        State::from_values(model, values.iter().map(|(k, v)| (k.as_str(), *v)))
    }

    /// Like [`from_values`](State::from_values) but clamps values into the limits
    /// (±∞ clamp to the limit).
    ///
    /// # Errors
    /// [`Error::UnknownJoint`], [`Error::NonFinite`] for NaN.
    pub fn from_values_clamped<S: AsRef<str>>(
        model: &SceneModel,
        values: impl IntoIterator<Item = (S, f64)>,
    ) -> Result<State, Error> {
        let mut state = model.zero_state();
        for (name, value) in values {
            let id = model.joint_id(name.as_ref())?;
            state.set_clamped(model, id, value)?;
        }
        Ok(state)
    }

    /// A state from values in joint-id order.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`], [`Error::NonFinite`], [`Error::JointLimit`].
    pub fn from_slice(model: &SceneModel, values: &[f64]) -> Result<State, Error> {
        let state = State { q: values.to_vec() };
        state.validate(model)?;
        Ok(state)
    }

    /// Checks the state fits the model: right length, finite, within limits.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`], [`Error::NonFinite`], [`Error::JointLimit`].
    pub fn validate(&self, model: &SceneModel) -> Result<(), Error> {
        self.check_len(model)?;
        for (joint, v) in model.joints.iter().zip(&self.q) {
            checked_value(joint, *v)?;
        }
        Ok(())
    }

    /// Fails with [`Error::DimensionMismatch`] unless the state has `model.nq()` values.
    pub(crate) fn check_len(&self, model: &SceneModel) -> Result<(), Error> {
        if self.q.len() == model.nq() {
            Ok(())
        } else {
            Err(Error::DimensionMismatch {
                what: "state".into(),
                expected: model.nq(),
                got: self.q.len(),
            })
        }
    }

    /// The values in joint-id order.
    pub fn as_slice(&self) -> &[f64] {
        &self.q
    }

    /// Number of values.
    pub fn len(&self) -> usize {
        self.q.len()
    }

    /// Whether the state has no values (a scene without joints).
    pub fn is_empty(&self) -> bool {
        self.q.is_empty()
    }

    /// The value of a joint, `None` for an id out of range.
    pub fn value(&self, id: JointId) -> Option<f64> {
        self.q.get(id.0).copied()
    }

    /// The value of the joint called `name`.
    ///
    /// # Errors
    /// [`Error::UnknownJoint`]; [`Error::DimensionMismatch`] if the state is not sized for
    /// the model.
    pub fn value_by_name(&self, model: &SceneModel, name: &str) -> Result<f64, Error> {
        self.check_len(model)?;
        Ok(self.q[model.joint_id(name)?.0])
    }

    fn slot<'s, 'm>(
        &'s mut self,
        model: &'m SceneModel,
        id: JointId,
    ) -> Result<(&'m Joint, &'s mut f64), Error> {
        self.check_len(model)?;
        let joint = model.checked_joint(id)?;
        let slot = self.q.get_mut(id.0).ok_or(Error::UnknownId {
            kind: ElementKind::Joint,
            index: id.0,
        })?;
        Ok((joint, slot))
    }

    /// Sets a joint value after checking it is finite and within limits.
    ///
    /// # Errors
    /// [`Error::UnknownId`], [`Error::DimensionMismatch`], [`Error::NonFinite`],
    /// [`Error::JointLimit`]; the state is unchanged on error.
    pub fn set(&mut self, model: &SceneModel, id: JointId, value: f64) -> Result<(), Error> {
        let (joint, slot) = self.slot(model, id)?;
        *slot = checked_value(joint, value)?;
        Ok(())
    }

    /// [`set`](State::set) by joint name.
    ///
    /// # Errors
    /// As [`set`](State::set), and [`Error::UnknownJoint`].
    pub fn set_by_name(&mut self, model: &SceneModel, name: &str, value: f64) -> Result<(), Error> {
        let id = model.joint_id(name)?;
        self.set(model, id, value)
    }

    /// Sets a joint value clamped into its limits and returns the value stored.
    ///
    /// # Errors
    /// [`Error::UnknownId`], [`Error::DimensionMismatch`], [`Error::NonFinite`] for NaN.
    pub fn set_clamped(
        &mut self,
        model: &SceneModel,
        id: JointId,
        value: f64,
    ) -> Result<f64, Error> {
        let (joint, slot) = self.slot(model, id)?;
        *slot = clamped_value(joint, value)?;
        Ok(*slot)
    }

    /// Sets a joint value without any check (not even finiteness).
    ///
    /// # Panics
    /// If `id` is out of range for this state.
    pub fn set_unchecked(&mut self, id: JointId, value: f64) {
        self.q[id.0] = value;
    }

    /// The state with every value clamped into its joint's limits.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`], [`Error::NonFinite`] for NaN.
    pub fn clamped(&self, model: &SceneModel) -> Result<State, Error> {
        self.check_len(model)?;
        let q = model
            .joints
            .iter()
            .zip(&self.q)
            .map(|(j, v)| clamped_value(j, *v))
            .collect::<Result<_, _>>()?;
        Ok(State { q })
    }

    /// The values by joint name.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if the state is not sized for the model.
    pub fn to_map(&self, model: &SceneModel) -> Result<BTreeMap<String, f64>, Error> {
        self.check_len(model)?;
        Ok(model
            .joints
            .iter()
            .zip(&self.q)
            .map(|(j, v)| (j.name.clone(), *v))
            .collect())
    }
}
