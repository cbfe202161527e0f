//! The settings of [`Proprioceptive`](super::Proprioceptive): noise, orientation model,
//! outlier range, sampling and the minimum motion.

use nalgebra::{UnitQuaternion, Vector3};

#[cfg(doc)]
use super::Proprioceptive;
use crate::InvalidSetting;
use crate::articulation::error::ArticulationError;

/// Settings of [`Proprioceptive`]. Lengths in metres, angles in radians.
#[derive(Debug, Clone, PartialEq)]
pub struct ProprioceptiveSettings {
    /// Standard deviation of end-effector position noise (inlier model), per axis (m); with
    /// [`NoiseSource::FromPath`] only for paths too short to estimate it from.
    pub position_sigma: f64,
    /// Standard deviation of end-effector orientation noise (inlier model), per axis (rad);
    /// with [`NoiseSource::FromPath`] only for paths too short to estimate it from.
    pub orientation_sigma: f64,
    /// Where the fits' noise levels come from.
    pub noise: NoiseSource,
    /// How much of the end effector's orientation follows the part (a revolute joint turns a
    /// held end effector by the joint angle; a prismatic one does not turn it).
    pub orientation: OrientationModel,
    /// Radius of the uniform outlier density of position residuals.
    pub outlier_range: f64,
    /// MLESAC hypotheses per model.
    pub iterations: usize,
    /// Seed of the hypothesis sampler.
    pub seed: u64,
    /// Fewer poses than this gives [`Unknown`](crate::articulation::JointEstimate::Unknown).
    pub min_poses: usize,
    /// Positions spanning less than this give `Unknown`.
    pub min_motion: f64,
}

/// Where the proprioceptive fits' noise levels come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NoiseSource {
    /// `position_sigma` and `orientation_sigma` as set. The default, for now: with
    /// [`OrientationModel::Rigid`] under a compliant grasp the approach-axis noise estimate
    /// is far below the free roll, and every pose becomes an outlier (measured in
    /// `tests/articulation/proprioceptive.rs`); the calibration tests are measured with it.
    #[default]
    Settings,
    /// Estimated from the path's smoothness ([`path_noise`](crate::articulation::path_noise)),
    /// at least [`MIN_POSITION_SIGMA`](crate::articulation::MIN_POSITION_SIGMA) and
    /// [`MIN_ORIENTATION_SIGMA`](crate::articulation::MIN_ORIENTATION_SIGMA); the settings'
    /// values for a path of fewer than
    /// [`MIN_NOISE_POSES`](crate::articulation::MIN_NOISE_POSES) poses.
    FromPath,
}

/// Which part of the recorded end-effector orientations the estimator trusts to follow the part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OrientationModel {
    /// Positions only.
    Ignored,
    /// The tool z axis (the approach direction) turns with the part; the roll about it is free.
    /// This is what a compliance controller that keeps pulling along the front's normal
    /// guarantees (the paper's exploration, and [`crate::discovery`]'s): soft fingers and a
    /// re-solved arm let the wrist roll while the approach stays normal to the front. The
    /// default, since a rigid grasp satisfies it too.
    #[default]
    ApproachAxis,
    /// The whole orientation turns with the part (a rigid grasp). Under a compliant grasp the
    /// wrist's free roll then tilts the fitted axis.
    Rigid,
}

impl OrientationModel {
    /// Free parameters of the grasp orientation offset.
    pub(super) fn parameters(self) -> f64 {
        match self {
            OrientationModel::Ignored => 0.0,
            OrientationModel::ApproachAxis => 2.0,
            OrientationModel::Rigid => 3.0,
        }
    }

    /// The angle between two end-effector orientations that this model compares.
    pub(super) fn angle(self, a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
        match self {
            OrientationModel::Ignored => 0.0,
            OrientationModel::ApproachAxis => (a * Vector3::z()).angle(&(b * Vector3::z())),
            OrientationModel::Rigid => a.angle_to(b),
        }
    }
}

impl Default for ProprioceptiveSettings {
    fn default() -> Self {
        ProprioceptiveSettings {
            position_sigma: 0.005,
            orientation_sigma: 0.05,
            noise: NoiseSource::Settings,
            orientation: OrientationModel::ApproachAxis,
            outlier_range: 0.5,
            iterations: 200,
            seed: 0,
            min_poses: 6,
            min_motion: 0.02,
        }
    }
}

impl ProprioceptiveSettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`ArticulationError::InvalidSetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ArticulationError> {
        let positive = [
            ("position_sigma", self.position_sigma),
            ("orientation_sigma", self.orientation_sigma),
            ("outlier_range", self.outlier_range),
            ("min_motion", self.min_motion),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(InvalidSetting::new(name, value, "finite and > 0").into());
            }
        }
        if self.iterations == 0 {
            return Err(InvalidSetting::new("iterations", 0.0, "≥ 1").into());
        }
        if self.min_poses < 3 {
            return Err(InvalidSetting::new("min_poses", self.min_poses as f64, "≥ 3").into());
        }
        Ok(())
    }
}
