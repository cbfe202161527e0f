//! The proprioceptive estimator: line and circle models fitted to the end-effector poses with
//! MLESAC and selected by BIC (Sturm, Stachniss, Burgard 2011).

mod estimate;
mod likelihood;
mod model;
mod refine;
mod settings;

use super::error::ArticulationError;
use super::estimate::{ArticulationEstimator, Estimate, Interaction};
use estimate::estimate;
pub use settings::{OrientationModel, ProprioceptiveSettings};

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
        Ok(estimate(&self.settings, interaction))
    }
}
