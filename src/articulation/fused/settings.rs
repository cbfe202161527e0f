//! The settings of the fused estimator, with their ranges.

use crate::InvalidSetting;
use crate::articulation::error::ArticulationError;
use crate::articulation::proprioceptive::ProprioceptiveSettings;
use crate::articulation::two_view::TwoViewSettings;

/// Settings of [`Fused`](super::Fused). Lengths in metres, angles in radians.
#[derive(Debug, Clone, PartialEq)]
pub struct FusedSettings {
    /// The two-view estimator that segments and registers the part (its estimate is also one
    /// of the joint fit's starts, and the answer when there are too few poses).
    pub two_view: TwoViewSettings,
    /// The proprioceptive estimator whose estimate is one of the joint fit's starts (and the
    /// answer when the clouds give no registration). Its `position_sigma` and
    /// `orientation_sigma` are the fused fit's pose noise for paths too short to estimate it
    /// from ([`path_noise`](crate::articulation::path_noise)).
    pub proprioceptive: ProprioceptiveSettings,
    /// Neighbourhood radius of the local planes whose residuals give the depth noise.
    pub plane_radius: f64,
    /// The smallest depth σ (m) the fit uses (exact clouds would make the likelihood
    /// degenerate).
    pub min_depth_sigma: f64,
    /// Re-associations of the cloud correspondences and pose outliers (outer iterations).
    pub outer_iterations: usize,
    /// Levenberg–Marquardt steps per outer iteration.
    pub lm_iterations: usize,
    /// A pose whose squared normalised residual (4 components) exceeds this is an outlier
    /// (it costs this much in the likelihood instead).
    pub pose_outlier_chi2: f64,
    /// Whether the travel the path swept (from its first to its last poses) is tied to the
    /// travel the clouds show: true when the poses were recorded between the two observations.
    pub couple_travel: bool,
    /// The largest circle radius (m) of the gripper's path that a revolute fit may have
    /// while a prismatic fit exists: a rotation about an axis this far from the grasp is a
    /// translation to within the sensors' resolution (over a 20 cm pull at 20 m the arc
    /// leaves its chord by 0.25 mm), and no door or lid of a household scene is that wide;
    /// such a fit's better cost is the clouds' noise, not a hinge.
    pub max_revolute_radius: f64,
}

impl Default for FusedSettings {
    fn default() -> Self {
        FusedSettings {
            two_view: TwoViewSettings::default(),
            proprioceptive: ProprioceptiveSettings::default(),
            plane_radius: 0.03,
            min_depth_sigma: 0.0005,
            outer_iterations: 4,
            lm_iterations: 12,
            pose_outlier_chi2: 25.0,
            couple_travel: true,
            max_revolute_radius: 2.0,
        }
    }
}

impl FusedSettings {
    /// Checks every field's range (and the two estimators' settings).
    ///
    /// # Errors
    /// [`ArticulationError::InvalidSetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ArticulationError> {
        self.two_view.validate()?;
        self.proprioceptive.validate()?;
        for (name, value) in [
            ("plane_radius", self.plane_radius),
            ("min_depth_sigma", self.min_depth_sigma),
            ("pose_outlier_chi2", self.pose_outlier_chi2),
            ("max_revolute_radius", self.max_revolute_radius),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(InvalidSetting::new(name, value, "finite and > 0").into());
            }
        }
        for (name, value) in [
            ("outer_iterations", self.outer_iterations),
            ("lm_iterations", self.lm_iterations),
        ] {
            if value == 0 {
                return Err(InvalidSetting::new(name, 0.0, "≥ 1").into());
            }
        }
        Ok(())
    }
}
