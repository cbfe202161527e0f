//! Settings of Algorithm 1 ([`discover`](super::discover)).

use serde::{Deserialize, Serialize};

use super::error::{DiscoveryError, check_nonneg, check_positive, check_range};
use super::interface::Camera;
use super::log::Doubt;
use crate::InvalidSetting;
use crate::articulation::Estimate;
#[cfg(doc)]
use crate::articulation::Uncertainty;
use crate::scene::collision::SweepSettings;

/// Settings of [`discover`](super::discover). SI units; defaults are for a Stretch/Gen3-sized
/// mobile manipulator in a kitchen.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DiscoverySettings {
    // --- PlanBase and navigation ---
    /// Radius of the robot's footprint (m): a planned base position must be free in the base
    /// map's navigation grid inflated by it. Default 0.3.
    pub robot_radius: f64,
    /// Horizontal distance (m) from the handle of the base pose for global navigation and
    /// re-detection (`PlanBase(h)`). Default 0.9.
    pub approach_distance: f64,
    /// Horizontal distance (m) from the handle of the pre-interaction base pose
    /// (`PlanBase(p)`). Default 0.6.
    pub interaction_distance: f64,
    /// How far (m) the base steps back from the pre-interaction pose, along the handle
    /// normal, to take the post-interaction observation (Algorithm 1, lines 24–27). Default
    /// 0.3.
    pub post_step_back: f64,
    /// When the nominal base position is occupied, candidates up to this far (m) from it are
    /// searched (rings around the handle, see [`discover`](super::discover)). Default 0.4.
    pub base_search_radius: f64,
    // --- DetectHandle ---
    /// The re-detected handle is the detection nearest to the mapped one within this radius
    /// (m). Default 0.15.
    pub redetect_radius: f64,
    /// Detector calls at the approach pose before the handle counts as not re-detected (a
    /// detector misses a visible handle now and then; each call is a fresh frame). Default 3.
    pub redetect_tries: usize,
    // --- Observations ---
    /// Camera of the pre- and post-interaction observations (the estimator's input). Default
    /// [`Camera::Head`].
    pub observation_camera: Camera,
    /// Camera observed at every exploration step (`o'`: surface normal and failure
    /// detection). Default [`Camera::Wrist`].
    pub interaction_camera: Camera,
    /// Radius (m) of the neighbourhood around the contact for surface-normal PCA. Default 0.12.
    pub normal_radius: f64,
    /// Points within this distance (m) of the first PCA plane are refitted (robust fit).
    /// Default 0.015.
    pub plane_inlier_distance: f64,
    /// Fewest neighbourhood points for a normal estimate. Default 12.
    pub min_normal_points: usize,
    // --- Exploratory interaction ---
    /// Largest number of attempts per handle (grasp + pull; Reposition between). Default 3.
    pub max_attempts: usize,
    /// Largest number of pull steps per attempt (`n` in Algorithm 1). Default 40.
    pub max_steps: usize,
    /// Commanded end-effector motion per pull step (m). Default 0.02.
    pub step: f64,
    /// The exploration succeeds once the contact is this far (m) from the handle's first grasp
    /// point (over all attempts). Default 0.3.
    pub target_pull: f64,
    /// Weight of the surface normal against the end effector's last motion direction in the
    /// pull direction, in [0, 1] (see [`discover`](super::discover)). Default 0.7.
    pub surface_weight: f64,
    // --- Keep pulling until confident ---
    /// The estimate is confident when its axis's 95 % half-angle
    /// ([`Uncertainty::axis_half_angle_95`]) is at most this (rad); otherwise the robot
    /// pulls further (see [`discover`](super::discover), step 6). Default 2° (0.0349 rad):
    /// the target is a mean axis error of 1° (twice as tight as the paper's 2°), and the
    /// error of a 2-d Gaussian estimate has mean `σ √(π/2) = 1.25 σ` and 95 % radius
    /// `√5.99 σ = 2.45 σ`, about twice the mean. (4° gives the paper's 2° mean; with it a
    /// small door opened 10° is called confident with errors up to 4°.)
    pub confident_axis_95: f64,
    /// ... and, for a revolute estimate, its pivot's 95 % radius
    /// ([`Uncertainty::pivot_radius_95`]) at most this (m). Default 0.02: twice the 1 cm
    /// mean pivot target, as above.
    pub confident_pivot_95: f64,
    /// ... and its joint type's probability ([`Uncertainty::type_probability`]) at least
    /// this, in [0.5, 1]. Default 0.99.
    pub confident_type_probability: f64,
    /// How far (m) the contact moves in one further pull (from the grasp at the last
    /// contact). Default 0.15.
    pub extra_pull: f64,
    /// Largest number of further pulls per handle; 0 turns the loop off (the paper's
    /// Algorithm 1). Default 3.
    pub max_extra_pulls: usize,
    // --- DetectFailure ---
    /// Radius (m) around the contact of the points compared with the pre-interaction
    /// observation. Default 0.15.
    pub displacement_radius: f64,
    /// The part counts as displaced when the mean nearest-neighbour distance (m) of those
    /// points to the pre-interaction observation reaches this. Default 0.02.
    pub displacement_threshold: f64,
    /// Nearest-neighbour distances are capped at this (m) so that a few unmatched points do not
    /// dominate the mean. Default 0.1.
    pub displacement_cap: f64,
    /// Pull steps after which a part that is still not displaced is a failure. Default 5.
    pub stall_steps: usize,
    /// A hardware failure once the contact is this far (m) from the first grasp point, with the
    /// part displaced, ends the attempt as a success: the motion so far is enough for the
    /// estimator. Default 0.12.
    pub sufficient_pull: f64,
    /// When such an attempt stopped short of `target_pull` and attempts remain, Reposition and
    /// pull on from the last contact, as Algorithm 1 does after every failure; the earlier
    /// success stands whatever the later attempts do. `false` accepts the short pull at once.
    /// An arc of `sufficient_pull` on a door leaves its hinge poorly determined (the sagitta
    /// of 12 cm on a 0.45 m door is 4 mm), but default false: in the kitchen example the
    /// further attempts left drawers open across their neighbours' handles, and the
    /// repositioned grasp of a corner door was out of reach (Fig. 5 92 % → 76 %).
    pub resume_short_pulls: bool,
    /// When a pull ends at the arm's limit (`JointLimit`) while the estimate still has a
    /// doubt, the further pulls of the keep-pulling loop go on from a base pose placed in
    /// front of the last contact (PlanBase for it, along the last tracked normal) instead of
    /// stopping there. `false`: the limit ends the loop. Default true.
    pub reposition_at_arm_limit: bool,
    // --- Reposition ---
    /// A tracked rotation of at least this (rad) classifies the motion as revolute. Default
    /// 0.14 (8°).
    pub rotation_threshold: f64,
    /// A contact motion of at least this (m) without rotation classifies it as prismatic.
    /// Default 0.02.
    pub translation_threshold: f64,
    /// How far (m) Reposition moves the base: sideways for revolute, back for prismatic (the
    /// paper's 30 cm). Default 0.3.
    pub reposition_distance: f64,
    // --- Registration ---
    /// Upper limit given to a revolute joint (rad) when the observed opening is smaller.
    /// Default 1.57.
    pub default_revolute_upper: f64,
    /// Upper limit given to a prismatic joint (m) when the observed opening is smaller. Default
    /// 0.4.
    pub default_prismatic_upper: f64,
    /// A handle within this distance (m) of an already registered part's collider (at the
    /// part's current estimated pose) is nested on that part. Default 0.05. Known limit: the
    /// test is purely geometric, so a child whose handle stands farther than this from its
    /// parent's estimated box (a dishwasher rack whose handle is 0.1–0.2 m in front of the
    /// opened door's face) is registered on the base map; raise it for such scenes, at the
    /// risk of nesting a neighbouring part's handle.
    pub nest_margin: f64,
    /// Quantile trimmed at each end of the part's points for its bounding box, in [0, 0.5).
    /// Default 0.01.
    pub box_trim: f64,
    /// Part points within this distance (m) of the base map at the part's closed pose are
    /// dropped from its box (static surfaces the segmentation took for the part); 0 keeps
    /// them. About twice the depth noise. Default 0.01.
    pub base_clearance: f64,
    /// Part points standing more than this (m) in front of the front's surface (the median
    /// depth along the normal) are protrusions — the handle — and get their own boxes; the
    /// front's box ends at the surface (kept in it, a handle thickens the whole front); 0
    /// keeps one box around all points. About twice the depth noise. Default 0.01.
    pub handle_standoff: f64,
    /// Smallest half extent (m) of a part's box (a front seen from one side is flat).
    /// Default 0.01.
    pub min_half_extent: f64,
    /// Gravity prior on a registered joint's axis (rad), in `[0, 0.78]` (under 45°): an estimated axis
    /// within this angle of the horizontal plane is projected onto it, one within this angle
    /// of the vertical is made vertical; 0 keeps every axis as estimated. Furniture hinges and
    /// slides are built level, so a small tilt is estimation noise — and it tilts the part's
    /// box too, whose corners then stand out by about `extent · sin(tilt)` (2.8 cm at the
    /// top of a 0.7 m dishwasher door estimated 4.6° off). The estimator's own axis stays in
    /// the log ([`EstimateLog`](super::EstimateLog)) and the change is noted. Default 10°
    /// (0.1745 rad; the kitchen's two-view estimates are 2.7° off on average, 6.5° at most).
    pub axis_snap: f64,
    /// Whether a prismatic part gets a second box behind its front: the drawer's body, which
    /// the camera never sees (it is inside the cabinet until the drawer opens, and the
    /// estimator's points are those of the closed pose), but which the arm can touch once the
    /// drawer is open. It has the front's width and height and is as deep as the joint's
    /// upper limit (a drawer is at least as deep as it slides out); reconciliation
    /// ([`reconcile`](super::reconcile)) then cuts it back to the cavity the robot saw it
    /// slide out of. Default true.
    pub drawer_body: bool,
    /// The sweep check that reconciles the model with what the robot saw (the closed scene
    /// and each executed opening must be collision-free in it; see
    /// [`reconcile`](super::reconcile)). Give it the planner's
    /// ([`TaskSettings::sweep`](crate::task::TaskSettings::sweep)) so that what discovery
    /// certifies, planning does too. Default [`SweepSettings::default`].
    pub sweep: SweepSettings,
}

impl Default for DiscoverySettings {
    fn default() -> Self {
        DiscoverySettings {
            robot_radius: 0.3,
            approach_distance: 0.9,
            interaction_distance: 0.6,
            post_step_back: 0.3,
            base_search_radius: 0.4,
            redetect_radius: 0.15,
            redetect_tries: 3,
            observation_camera: Camera::Head,
            interaction_camera: Camera::Wrist,
            normal_radius: 0.12,
            plane_inlier_distance: 0.015,
            min_normal_points: 12,
            max_attempts: 3,
            max_steps: 40,
            step: 0.02,
            target_pull: 0.3,
            surface_weight: 0.7,
            displacement_radius: 0.15,
            displacement_threshold: 0.02,
            displacement_cap: 0.1,
            stall_steps: 5,
            sufficient_pull: 0.12,
            resume_short_pulls: false,
            reposition_at_arm_limit: true,
            confident_axis_95: 2f64.to_radians(),
            confident_pivot_95: 0.02,
            confident_type_probability: 0.99,
            extra_pull: 0.15,
            max_extra_pulls: 3,
            rotation_threshold: 0.14,
            translation_threshold: 0.02,
            reposition_distance: 0.3,
            default_revolute_upper: 1.57,
            default_prismatic_upper: 0.4,
            nest_margin: 0.05,
            box_trim: 0.01,
            axis_snap: 10f64.to_radians(),
            drawer_body: true,
            base_clearance: 0.01,
            handle_standoff: 0.01,
            min_half_extent: 0.01,
            sweep: SweepSettings::default(),
        }
    }
}

impl DiscoverySettings {
    /// The confidence limits that `estimate` does not meet (empty: confident), as the
    /// keep-pulling loop of [`discover`](super::discover) (step 6) judges them: the axis's
    /// 95 % half-angle above `confident_axis_95`, a revolute pivot's 95 % radius above
    /// `confident_pivot_95`, the type probability below `confident_type_probability`, or no
    /// uncertainty at all. For a loop of your own over [`ArticulationEstimator`]s.
    ///
    /// [`ArticulationEstimator`]: crate::articulation::ArticulationEstimator
    #[must_use]
    pub fn doubts(&self, estimate: &Estimate) -> Vec<Doubt> {
        super::run::doubts(estimate, self)
    }

    /// How far `estimate` is from confident: the largest ratio of a 95 % region to its limit
    /// (axis, pivot) and of `1 − type probability` to `1 − confident_type_probability`; at
    /// most 1 when [`doubts`](Self::doubts) is empty, ∞ without uncertainty. The keep-pulling
    /// loop keeps the estimate with the least.
    #[must_use]
    pub fn confidence_shortfall(&self, estimate: &Estimate) -> f64 {
        super::run::shortfall(estimate, self)
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`DiscoveryError::InvalidSetting`] naming the first invalid field (or
    /// [`DiscoveryError::Scene`] for invalid `sweep` settings): lengths and counts
    /// must be positive (distances that may be zero: `post_step_back`, `base_search_radius`,
    /// `nest_margin`, `base_clearance`, `handle_standoff`), weights and quantiles in range, `displacement_cap >
    /// displacement_threshold`.
    pub fn validate(&self) -> Result<(), DiscoveryError> {
        for (name, v) in [
            ("robot_radius", self.robot_radius),
            ("approach_distance", self.approach_distance),
            ("interaction_distance", self.interaction_distance),
            ("redetect_radius", self.redetect_radius),
            ("normal_radius", self.normal_radius),
            ("plane_inlier_distance", self.plane_inlier_distance),
            ("step", self.step),
            ("target_pull", self.target_pull),
            ("displacement_radius", self.displacement_radius),
            ("displacement_threshold", self.displacement_threshold),
            ("displacement_cap", self.displacement_cap),
            ("sufficient_pull", self.sufficient_pull),
            ("confident_axis_95", self.confident_axis_95),
            ("confident_pivot_95", self.confident_pivot_95),
            ("extra_pull", self.extra_pull),
            ("rotation_threshold", self.rotation_threshold),
            ("translation_threshold", self.translation_threshold),
            ("reposition_distance", self.reposition_distance),
            ("default_revolute_upper", self.default_revolute_upper),
            ("default_prismatic_upper", self.default_prismatic_upper),
            ("min_half_extent", self.min_half_extent),
        ] {
            check_positive(name, v)?;
        }
        for (name, v) in [
            ("post_step_back", self.post_step_back),
            ("base_search_radius", self.base_search_radius),
            ("nest_margin", self.nest_margin),
            ("base_clearance", self.base_clearance),
            ("handle_standoff", self.handle_standoff),
        ] {
            check_nonneg(name, v)?;
        }
        check_range("surface_weight", self.surface_weight, 0.0, 1.0, "in [0, 1]")?;
        check_range(
            "confident_type_probability",
            self.confident_type_probability,
            0.5,
            1.0,
            "in [0.5, 1]",
        )?;
        check_range("box_trim", self.box_trim, 0.0, 0.49, "in [0, 0.49]")?;
        check_range(
            "axis_snap",
            self.axis_snap,
            0.0,
            0.78,
            "in [0, 0.78] (under 45°, so that horizontal and vertical do not overlap)",
        )?;
        if self.displacement_cap <= self.displacement_threshold {
            return Err(InvalidSetting::new(
                "displacement_cap",
                self.displacement_cap,
                "greater than displacement_threshold",
            )
            .into());
        }
        for (name, v) in [
            ("max_attempts", self.max_attempts),
            ("redetect_tries", self.redetect_tries),
            ("max_steps", self.max_steps),
            ("min_normal_points", self.min_normal_points),
        ] {
            if v == 0 {
                return Err(InvalidSetting::new(name, 0.0, "at least 1").into());
            }
        }
        self.sweep.validate()?;
        Ok(())
    }
}
