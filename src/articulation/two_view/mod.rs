//! The two-view estimator: segment the moving part, register it rigidly, decompose the motion.
//!
//! This file holds [`TwoView`] and its rule as a sequence of steps: change detection and
//! region growing are in `change.rs`, registration, model selection and refinement in
//! `fit.rs`, the final segmentation with the score and details in `segment.rs`.

mod change;
mod fit;
mod segment;
mod settings;
mod uncertainty;

pub use settings::TwoViewSettings;

use nalgebra::{Isometry3, Point3};

use self::change::{Changes, grow, seeds, voxel_subset};
use self::fit::{Fitter, initial_guesses, joint_of, refine, register, select};
use self::segment::{details, final_segment, score_of};
use self::uncertainty::uncertainty;
use super::error::ArticulationError;
use super::estimate::{ArticulationEstimator, Estimate, Interaction};
use super::proprioceptive::Proprioceptive;
use super::uncertainty::{Other, bic_probability, consistent_with};

/// The two-view estimator (see the module docs of [`super`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TwoView {
    /// Its settings.
    pub settings: TwoViewSettings,
}

impl ArticulationEstimator for TwoView {
    fn name(&self) -> &str {
        "two-view"
    }

    /// # Errors
    /// Bad input ([`Interaction::validate`]) or bad settings ([`TwoViewSettings::validate`]).
    fn estimate(&self, interaction: &Interaction<'_>) -> Result<Estimate, ArticulationError> {
        interaction.validate()?;
        self.settings.validate()?;
        let mut e = estimate(&self.settings, interaction);
        if self.settings.path_consistency && !interaction.ee_poses.is_empty() {
            let path = Proprioceptive::default().estimate(interaction)?;
            e.uncertainty = e
                .uncertainty
                .map(|u| consistent_with(u, &e.joint, &path, Other::Independent));
        }
        Ok(e)
    }
}

/// The rule, step by step:
///
/// 1. **Change detection.** A pre point is *changed* when no post point lies within
///    `τ = max(change_distance, noise_multiplier · median pre→post nearest-neighbour distance)`;
///    symmetrically a post point is *new*.
/// 2. **Segmentation seed.** Region growing (connectivity `neighbor_radius`) over changed pre
///    points from those within `seed_radius` of `c_pre` (or the changed point nearest to it);
///    likewise new post points from `c_post`.
/// 3. **Registration.** Trimmed ICP of the segmented pre points (one per `icp_voxel` cube) to
///    the whole post cloud, with the contact pair `c_pre → c_post` weighted in, from two initial
///    guesses: the contact translation, and the rotation taking the segment's pre plane normal
///    to the post segment's normal combined with the contact translation. The lower truncated
///    cost wins.
/// 4. **Model selection.** From the rigid motion, ICP fits the two joint models (pure rotation
///    about a line, 5 parameters; pure translation, 3 parameters, also from the contact's
///    shift, the lower cost kept); each gets
///    `BIC = n ln(RSS/N) + k ln n` from the mean truncated squared residual `RSS/N` of the `N`
///    part points, where `n` counts the `τ`-voxels the part occupies (neighbouring residuals are
///    correlated, so `N` would overstate the evidence); the lower BIC wins, unless the
///    **contact-path check** decides: with at least `min_path_poses` end-effector poses, each
///    model predicts the gripper's path (a circle about the fitted axis, or a line along the
///    fitted translation, through the path's start); a model whose median distance from the
///    recorded positions exceeds `path_tolerance` is rejected when the other model's is within
///    it. Why: static surfaces that the moved part hides in the post view (the carcass face
///    below a drawer pulled towards the camera) are segmented with the part, and a large
///    rotation can map them onto other surfaces (a drawer front onto its own top) better than
///    the true translation explains the part; the path a pulled drawer's handle took is
///    straight, which no such rotation predicts.
/// 5. **Refinement.** The chosen model is registered again on the ICP points its motion
///    explains (a post neighbour within `τ`): rotation by the same ICP at the final limit;
///    translation by point-to-plane ICP (normals of the post cloud, a small point-to-point term
///    for the directions no surface constrains), whose residuals measure depth noise rather
///    than the two views' different sampling.
/// 6. **Final segmentation.** Grown from the seed over the pre points that the fitted motion
///    explains (a post neighbour within `τ` after the motion) better than the static hypothesis
///    by a margin `τ/4`, or as well up to that margin while moving less than `2τ` (points near a
///    hinge, which both explain), and over the points that neither explains although the post
///    sensor saw through the place they were (in a range image around the post origin, no post
///    point in front of it by more than `τ` and one behind it by more than `τ`): they left.
///    A point the post sensor did not see around at all (outside its field of view or range)
///    is not evidence of motion and is left out. Known limits: static surfaces that the
///    motion maps onto themselves and that the moved part hides in the post view (the floor
///    just in front of a door turning about a vertical axis) are taken as moving; part surfaces
///    sliding along themselves, and thin strips of the part within `τ` of a static surface, are
///    left out.
/// 7. **Uncertainty.** The Gauss–Newton covariance of the chosen model's point-to-plane
///    residuals at the fit (see `uncertainty.rs`), with the BIC posterior of the type. With
///    end-effector poses and `path_consistency`, its axis and pivot blocks are widened by
///    Birge's ratio where the gripper's path alone (the default proprioceptive estimate,
///    an independent source) disagrees beyond the sum of the two regions: the clouds'
///    registration can be biased in ways its residuals do not show (a small door opened 10°
///    under-rotated by 4° with the hinge 10 cm away, a front partly out of view), and the
///    region then says so.
fn estimate(s: &TwoViewSettings, i: &Interaction<'_>) -> Estimate {
    steps(s, i).map_or_else(Estimate::unknown, |(e, _)| e)
}

/// What the clouds say about the part's motion, for an estimator that fuses them with other
/// sources ([`Fused`](super::Fused)).
pub(crate) struct CloudEvidence {
    /// The segmented part's points (pre pose, map frame).
    pub(crate) part: Vec<Point3<f64>>,
    /// The subset of `part` the registration uses.
    pub(crate) sample: Vec<Point3<f64>>,
    /// The points that may be evidence of the motion: one per `icp_voxel` cube of the pre
    /// points within `neighbor_radius` of `part` or of the final segmentation, evenly strided
    /// to at most `max_icp_points`. Not `part` alone: of the points that moved about τ, the
    /// change detection keeps those whose noise pushed them away from the moved surface,
    /// which biases a fit to `part` towards less motion (and the final segmentation, under
    /// the two-view motion, those whose noise brought them nearer); the neighbourhood takes
    /// them whatever their noise, static ones too, and the joint fit chooses its evidence.
    /// Known limit: at 10 mm depth noise the static points it adds pass the fit's
    /// static-versus-moving test often enough to tilt a small door's axis (the union of the
    /// two segmentations alone does less harm there, and less good at 2 and 5 mm).
    pub(crate) candidates: Vec<Point3<f64>>,
    /// The change threshold τ (m): correspondences farther than this are not evidence.
    pub(crate) tau: f64,
    /// The occupied τ-voxels of the part: how many independent residuals the part is worth.
    pub(crate) n_eff: f64,
    /// The unconstrained rigid registration.
    pub(crate) rigid: Isometry3<f64>,
}

/// The two-view estimate and, when the registration succeeded, its cloud evidence.
///
/// # Errors
/// Bad input or settings, as [`TwoView::estimate`](ArticulationEstimator::estimate).
pub(crate) fn estimate_with_evidence(
    s: &TwoViewSettings,
    i: &Interaction<'_>,
) -> Result<(Estimate, Option<CloudEvidence>), ArticulationError> {
    i.validate()?;
    s.validate()?;
    Ok(match steps(s, i) {
        Ok((e, evidence)) => (e, Some(evidence)),
        Err(reason) => (Estimate::unknown(reason), None),
    })
}

/// The steps of [`estimate`] with the cloud evidence; `Err` with the reason the joint is
/// unknown.
fn steps(s: &TwoViewSettings, i: &Interaction<'_>) -> Result<(Estimate, CloudEvidence), String> {
    let (pre, post) = (&i.pre.points, &i.post.points);
    if pre.len() < s.min_part_points || post.len() < s.min_part_points {
        return Err(format!(
            "too few points: {} pre, {} post (need {})",
            pre.len(),
            post.len(),
            s.min_part_points
        ));
    }
    // 1. Change detection.
    let c = Changes::new(s, pre, post);
    let tau = c.tau;
    // 2. Segmentation seed.
    let seeds_pre = seeds(pre, &c.pre_tree, &c.changed, &i.contact_pre, s.seed_radius);
    let part = grow(&c.pre_tree, pre, &c.changed, &seeds_pre, s.neighbor_radius);
    if part.len() < s.min_part_points {
        return Err(format!(
            "too little motion: {} changed points connected to the contact (need {}, τ = {tau:.4} m)",
            part.len(),
            s.min_part_points
        ));
    }
    let seeds_post = seeds(post, &c.post_tree, &c.new, &i.contact_post, s.seed_radius);
    let part_post = grow(&c.post_tree, post, &c.new, &seeds_post, s.neighbor_radius);
    let source: Vec<Point3<f64>> = part.iter().map(|&k| pre[k]).collect();
    // 3. Registration.
    let fitter = Fitter::new(s, i, &c, &source);
    let inits = initial_guesses(s, i, post, &source, &part_post);
    let rigid = register(s, &fitter, &source, &inits)?;
    // 4. Model selection.
    let selection = select(s, i, &c, &fitter, &source, &rigid, inits[0])?;
    // 5. Refinement.
    let chosen = refine(s, &c, &fitter, selection.chosen, selection.revolute);
    let joint = joint_of(&chosen.motion, selection.revolute, &i.contact_pre);
    // 6. Final segmentation.
    let moving = final_segment(s, i, &c, &chosen.motion, &seeds_pre);
    let n = source.len() as f64;
    let inliers = source
        .iter()
        .filter(|p| c.to_post(&(chosen.motion * *p)) <= tau)
        .count() as f64
        / n;
    let score = score_of(inliers, selection.margin);
    let (bic_chosen, bic_other) = if selection.revolute {
        (selection.bic_r, selection.bic_p)
    } else {
        (selection.bic_p, selection.bic_r)
    };
    let uncertainty = uncertainty(
        s,
        &c,
        &fitter,
        &chosen.motion,
        selection.revolute,
        &i.contact_pre,
        selection.n_eff,
        bic_probability(bic_chosen, bic_other),
    );
    let details = details(&c, part.len(), part_post.len(), &rigid, &selection, inliers);
    // The change-detected part and the final segmentation, and every pre point within
    // `neighbor_radius` of them: both segmentations keep, of the points near their
    // thresholds, those whose noise is on one side.
    let mut near = vec![false; pre.len()];
    for &k in part.iter().chain(&moving) {
        c.pre_tree
            .for_each_within(&pre[k], s.neighbor_radius, |j, _| near[j] = true);
    }
    let union: Vec<Point3<f64>> = (0..pre.len())
        .filter(|&k| near[k])
        .map(|k| pre[k])
        .collect();
    let thinned = voxel_subset(&union, s.icp_voxel);
    let stride = thinned.len().div_ceil(s.max_icp_points).max(1);
    let candidates = thinned.into_iter().step_by(stride).collect();
    let estimate = Estimate {
        joint,
        part_points: moving.iter().map(|&k| pre[k]).collect(),
        moving,
        score,
        details,
        uncertainty,
    };
    let evidence = CloudEvidence {
        candidates,
        sample: fitter.sample,
        part: source,
        tau,
        n_eff: selection.n_eff,
        rigid: rigid.motion,
    };
    Ok((estimate, evidence))
}
