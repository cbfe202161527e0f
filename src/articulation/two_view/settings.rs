//! The settings of the two-view estimator, with their ranges.

use crate::InvalidSetting;
use crate::articulation::error::ArticulationError;

/// Settings of [`TwoView`](super::TwoView). Lengths in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoViewSettings {
    /// Smallest distance at which a pre point with no post point nearer counts as changed.
    pub change_distance: f64,
    /// The change threshold is at least this multiple of the median pre → post nearest-neighbour
    /// distance (a noise scale measured on the mostly static scene).
    pub noise_multiplier: f64,
    /// Connectivity radius of the region growing.
    pub neighbor_radius: f64,
    /// Changed points within this distance of a contact seed their region.
    pub seed_radius: f64,
    /// Fewer segmented points than this gives
    /// [`Unknown`](crate::articulation::JointEstimate::Unknown).
    pub min_part_points: usize,
    /// A fitted motion that moves no part point farther than this gives `Unknown`.
    pub min_motion: f64,
    /// ICP iterations per stage.
    pub icp_iterations: usize,
    /// Fraction of correspondences ICP keeps each step (the closest ones), in (0, 1].
    pub trim_fraction: f64,
    /// Largest correspondence distance of the final ICP stage.
    pub max_correspondence_distance: f64,
    /// Angular bin (rad) of the post cloud's range image used to tell occluded from vacated
    /// space; about twice the sensor's angular resolution.
    pub visibility_bin: f64,
    /// ICP registers one part point per cube of this side (m; 0 keeps every point), then an
    /// evenly strided subset of at most `max_icp_points` of those.
    pub icp_voxel: f64,
    /// ICP registers an evenly strided subset of at most this many part points.
    pub max_icp_points: usize,
    /// Weight of the contact pair `c_pre → c_post` relative to all point pairs, in [0, 1).
    pub contact_weight: f64,
    /// Contact-path check of model selection: a joint model whose predicted end-effector path
    /// misses the recorded positions by more than this median distance (m) is rejected when
    /// the other model's path does not (see [`TwoView`](super::TwoView)).
    pub path_tolerance: f64,
    /// The contact-path check needs at least this many end-effector poses.
    pub min_path_poses: usize,
    /// With end-effector poses, widen the uncertainty where the gripper's path alone (the
    /// default [`Proprioceptive`](crate::articulation::Proprioceptive) estimate) disagrees
    /// beyond both regions (Birge's ratio; see [`TwoView`](super::TwoView)). Default true.
    pub path_consistency: bool,
}

impl Default for TwoViewSettings {
    fn default() -> Self {
        TwoViewSettings {
            change_distance: 0.015,
            noise_multiplier: 4.0,
            neighbor_radius: 0.025,
            seed_radius: 0.06,
            min_part_points: 50,
            min_motion: 0.015,
            icp_iterations: 30,
            trim_fraction: 0.8,
            max_correspondence_distance: 0.03,
            visibility_bin: 0.01,
            icp_voxel: 0.012,
            max_icp_points: 4000,
            contact_weight: 0.05,
            path_tolerance: 0.02,
            min_path_poses: 5,
            path_consistency: true,
        }
    }
}

impl TwoViewSettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`ArticulationError::InvalidSetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ArticulationError> {
        let positive = [
            ("change_distance", self.change_distance),
            ("noise_multiplier", self.noise_multiplier),
            ("neighbor_radius", self.neighbor_radius),
            ("seed_radius", self.seed_radius),
            ("min_motion", self.min_motion),
            (
                "max_correspondence_distance",
                self.max_correspondence_distance,
            ),
            ("path_tolerance", self.path_tolerance),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(InvalidSetting::new(name, value, "finite and > 0").into());
            }
        }
        if !(self.icp_voxel.is_finite() && self.icp_voxel >= 0.0) {
            return Err(InvalidSetting::new("icp_voxel", self.icp_voxel, "finite and ≥ 0").into());
        }
        if !(self.trim_fraction > 0.0 && self.trim_fraction <= 1.0) {
            return Err(
                InvalidSetting::new("trim_fraction", self.trim_fraction, "in (0, 1]").into(),
            );
        }
        if !(self.contact_weight >= 0.0 && self.contact_weight < 1.0) {
            return Err(
                InvalidSetting::new("contact_weight", self.contact_weight, "in [0, 1)").into(),
            );
        }
        for (name, value) in [
            ("min_part_points", self.min_part_points),
            ("icp_iterations", self.icp_iterations),
            ("max_icp_points", self.max_icp_points),
            ("min_path_poses", self.min_path_poses),
        ] {
            if value == 0 {
                return Err(InvalidSetting::new(name, 0.0, "≥ 1").into());
            }
        }
        Ok(())
    }
}
