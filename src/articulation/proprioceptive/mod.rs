//! The proprioceptive estimator: line and circle models fitted to the end-effector poses with
//! MLESAC and selected by BIC (Sturm, Stachniss, Burgard 2011).

mod estimate;
mod likelihood;
mod model;
mod noise;
mod refine;
mod settings;
mod uncertainty;

use super::error::ArticulationError;
use nalgebra::Isometry3;

use super::estimate::{ArticulationEstimator, Estimate, Interaction, validate_ee_poses};
use estimate::estimate;
pub use noise::{
    MIN_NOISE_POSES, MIN_ORIENTATION_SIGMA, MIN_POSITION_SIGMA, PathNoise, path_noise,
};
pub(crate) use refine::kasa_circle;
pub use settings::{NoiseSource, OrientationModel, ProprioceptiveSettings};

/// The proprioceptive estimator (see the module docs of [`super`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Proprioceptive {
    /// Its settings.
    pub settings: ProprioceptiveSettings,
}

impl ArticulationEstimator for Proprioceptive {
    fn name(&self) -> &str {
        "proprioceptive"
    }

    /// # Errors
    /// Bad input ([`Interaction::validate`]) or bad settings
    /// ([`ProprioceptiveSettings::validate`]).
    fn estimate(&self, interaction: &Interaction<'_>) -> Result<Estimate, ArticulationError> {
        interaction.validate()?;
        self.settings.validate()?;
        Ok(estimate(
            &self.settings,
            interaction.ee_poses,
            Some(interaction.contact_pre),
        ))
    }
}

impl Proprioceptive {
    /// Estimates the joint from the end-effector poses alone (no clouds, no contact): the
    /// same rule as [`ArticulationEstimator::estimate`], with a revolute pivot level with the
    /// first pose the winning model explains instead of the contact.
    ///
    /// `ee_poses`: `(time s, world_from_ee)` recorded while pulling, times increasing, one
    /// rigid grasp (see [`Interaction::ee_poses`]).
    ///
    /// # Errors
    /// Bad poses ([`validate_ee_poses`]) or bad settings
    /// ([`ProprioceptiveSettings::validate`]).
    ///
    /// # Example
    /// A quarter turn about the vertical line through the origin, radius 0.4 m:
    /// ```
    /// use kinscene::articulation::{JointEstimate, Proprioceptive};
    /// use nalgebra::{Isometry3, UnitQuaternion, Vector3};
    ///
    /// let poses: Vec<(f64, Isometry3<f64>)> = (0..20)
    ///     .map(|k| {
    ///         let turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.08 * k as f64);
    ///         let pose = Isometry3::from_parts((turn * Vector3::x() * 0.4).into(), turn);
    ///         (0.1 * k as f64, pose)
    ///     })
    ///     .collect();
    /// let e = Proprioceptive::default().estimate_poses(&poses)?;
    /// let JointEstimate::Revolute { axis, .. } = e.joint else { panic!("{e:?}") };
    /// assert!(axis.z > 0.999);
    /// let u = e.uncertainty.expect("a known joint carries its uncertainty");
    /// assert!(u.axis_half_angle_95().is_finite());
    /// # Ok::<(), kinscene::articulation::ArticulationError>(())
    /// ```
    pub fn estimate_poses(
        &self,
        ee_poses: &[(f64, Isometry3<f64>)],
    ) -> Result<Estimate, ArticulationError> {
        validate_ee_poses(ee_poses)?;
        self.settings.validate()?;
        Ok(estimate(&self.settings, ee_poses, None))
    }
}
