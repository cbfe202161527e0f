//! The fused estimator: the clouds' registered part and the gripper's path in one joint
//! likelihood, fitted by weighted nonlinear least squares.
//!
//! This file holds [`Fused`] and its rule; the joint models are in `model.rs`, the likelihood
//! and its solver in `solve.rs`, the starts in `start.rs`, the depth noise in `noise.rs`.

mod covariance;
mod model;
mod noise;
mod settings;
mod solve;
mod start;

pub use settings::FusedSettings;

use nalgebra::{DMatrix, Matrix2, Point3, Vector3};

use self::model::{Kind, PathPose, State};
use self::noise::depth_sigma;
use self::solve::Context;
use self::start::Sources;
use super::error::ArticulationError;
use super::estimate::{ArticulationEstimator, Estimate, Interaction, JointEstimate, unit_score};
use super::icp::NormalCache;
use super::kdtree::KdTree;
use super::proprioceptive::{
    MIN_ORIENTATION_SIGMA, MIN_POSITION_SIGMA, Proprioceptive, path_noise,
};
use super::two_view::{CloudEvidence, estimate_with_evidence};
use super::uncertainty::{
    Other, PlaneCovariance, Uncertainty, bic_probability, consistent_with, tangent_basis,
};

/// The fused estimator: one joint fit to the depth clouds and the end-effector poses.
///
/// 1. **Single sources.** The two-view estimator segments and registers the part (its
///    correspondences are the clouds' evidence) and the proprioceptive one fits the path.
///    Without a registration (too few points, no motion in the clouds, no clouds) the result
///    is the proprioceptive estimate; with fewer poses than the proprioceptive `min_poses` it
///    is the two-view estimate: with one source the estimator is that source's.
/// 2. **Noise, from the data.** Depth σ_d from the residuals of local planes fitted to the
///    segmented part's neighbourhoods (`plane_radius`; the median absolute residual, so that
///    edges do not count), at least `min_depth_sigma` (τ/4 when no neighbourhood has 8
///    points); pose noise σ_p, σ_o from the path's smoothness
///    ([`path_noise`](crate::articulation::path_noise), floored as there; the proprioceptive
///    settings' values for paths too short).
/// 3. **Joint likelihood.** For a joint hypothesis (revolute: axis, pivot, angle; prismatic:
///    direction, displacement) and the path's nuisance parameters (circle radius and height,
///    or the line's offset; the approach axis's constant components in the frame turning
///    with the gripper), the residuals are: the clouds' point-to-plane residuals
///    `nᵢ · (T sᵢ − qᵢ)`; each pose's distance from the circle or line (2 components over
///    σ_p) and its approach axis's deviation (2 over σ_o); and, with `couple_travel`, the
///    angle (distance) the path swept between its first and last poses against the clouds'
///    (over its σ from σ_p). The arc's curvature, the approach axis's turn and the cloud's
///    rotation then constrain each other. The clouds' points `sᵢ` are chosen per hypothesis
///    from the pre points near either segmentation of the two-view estimator: those the
///    motion moves off their surface by more than twice the gate `3 √2 σ_d` and explains (a
///    post point within τ, a residual within the gate) better than the static scene does
///    (twice, so that this comparison does not cut the noise on one side: `solve.rs`). Not the
///    change-detected segment as such: of the points that moved about τ it keeps those whose
///    noise pushed them away from the moved surface, which pulls the swept angle low (by
///    ≈ 1° on a small door opened 10°). The residuals are weighted `n_eff / (N · 2σ_d²)` (or
///    by their own mean square when larger), so that the `N` points count as the `n_eff`
///    τ-voxels they occupy.
/// 4. **Fit.** Per model, the starts are the two estimates, the rigid registration's screw,
///    the algebraic (Kåsa) circle of the path about each candidate axis (and about the axis
///    the approach turned about), the contact's displacement and the path's principal
///    direction. The two of lowest joint cost are refined by Levenberg–Marquardt, with
///    `outer_iterations` re-associations of correspondences and pose outliers (block χ²
///    above `pose_outlier_chi2`); the lower cost wins.
/// 5. **Type.** `BIC = −2 log L / ĉ + k ln n` on the joint likelihood (truncated: a
///    change-detected part point without correspondence costs τ², an outlier pose
///    `pose_outlier_chi2`), `k` = 9 revolute, 7 prismatic, `n = n_eff + 4 · poses`, `ĉ ≥ 1`
///    the winner's variance factor (its reduced χ²: a quasi-likelihood, so that noise the
///    estimated levels understate does not make the type overconfident). The type
///    probability is BIC's posterior (a revolute fit whose path radius exceeds
///    `max_revolute_radius` does not compete with a prismatic one: it is a translation the
///    clouds' noise bent); a near tie is near ½, which the keep-pulling loop of
///    discovery treats as ambiguous (below its `confident_type_probability`).
/// 6. **Uncertainty.** The covariance of the fit (`covariance.rs`): the larger, in every
///    direction, of the Gauss–Newton one scaled by `ĉ` and the cluster-robust sandwich over
///    τ-voxels and poses; its axis-tilt and pivot blocks are then widened by Birge's ratio
///    where the path alone (the proprioceptive estimate) disagrees with the fused estimate
///    beyond its own regions (a bias of the clouds no residual shows).
///
/// The segmentation (`moving`, `part_points`) is the two-view estimator's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Fused {
    /// Its settings.
    pub settings: FusedSettings,
}

impl ArticulationEstimator for Fused {
    fn name(&self) -> &str {
        "fused"
    }

    /// # Errors
    /// Bad input ([`Interaction::validate`]) or bad settings ([`FusedSettings::validate`]).
    fn estimate(&self, interaction: &Interaction<'_>) -> Result<Estimate, ArticulationError> {
        interaction.validate()?;
        self.settings.validate()?;
        estimate(&self.settings, interaction)
    }
}

/// The rule of [`Fused`], step by step.
fn estimate(s: &FusedSettings, i: &Interaction<'_>) -> Result<Estimate, ArticulationError> {
    // 1. Single sources.
    let (two_view, evidence) = estimate_with_evidence(&s.two_view, i)?;
    let proprioceptive = Proprioceptive {
        settings: s.proprioceptive.clone(),
    }
    .estimate(i)?;
    let Some(evidence) = evidence else {
        return Ok(alone(proprioceptive, "the clouds gave no registration"));
    };
    if i.ee_poses.len() < s.proprioceptive.min_poses {
        return Ok(alone(two_view, "too few end-effector poses"));
    }
    // 2. Noise.
    let (sigma_p, sigma_o) = pose_noise(s, i);
    let sigma_d = depth_sigma(&evidence.part, s.plane_radius)
        .unwrap_or(evidence.tau / 4.0)
        .max(s.min_depth_sigma);
    // 3. Joint likelihood.
    let poses: Vec<PathPose> = i
        .ee_poses
        .iter()
        .map(|(_, p)| PathPose {
            position: Point3::from(p.translation.vector),
            approach: p.rotation * Vector3::z(),
        })
        .collect();
    let post = &i.post.points;
    let tree = KdTree::new(post);
    let normals = NormalCache::new(post, &tree, s.two_view.neighbor_radius * 1.2);
    let n_sample = evidence.sample.len().max(1) as f64;
    let pair_gate = 3.0 * std::f64::consts::SQRT_2 * sigma_d;

    let ctx = Context {
        settings: s,
        sample: &evidence.sample,
        candidates: &evidence.candidates,
        sigma_d,
        post,
        post_tree: &tree,
        normals: &normals,
        tau: evidence.tau,
        cloud_weight: evidence.n_eff / (n_sample * 2.0 * sigma_d * sigma_d),
        pair_gate,
        poses: &poses,
        sigma_p,
        sigma_o,
        ends: 1,
        contact: i.contact_pre,
    };
    // 4. Fit.
    let sources = Sources {
        two_view: &two_view,
        proprioceptive: &proprioceptive,
        rigid: evidence.rigid,
        poses: &poses,
        contact_pre: i.contact_pre,
        contact_post: i.contact_post,
    };
    let mut fits: Vec<(State, f64)> = [start::revolute(&sources), start::prismatic(&sources)]
        .into_iter()
        .filter_map(|starts| best_fit(&ctx, starts))
        .collect();
    let wide = drop_wide_revolute(&mut fits, s.max_revolute_radius);
    // 5. Type, with 6. the uncertainty's variance factor.
    let n_obs = evidence.n_eff + 4.0 * poses.len() as f64;
    let bic =
        |cost: f64, st: &State, c_hat: f64| cost / c_hat + st.parameters() as f64 * n_obs.ln();
    let Some(best) = (0..fits.len()).min_by(|&a, &b| {
        bic(fits[a].1, &fits[a].0, 1.0).total_cmp(&bic(fits[b].1, &fits[b].0, 1.0))
    }) else {
        return Ok(alone(two_view, "the joint fit found no start"));
    };
    let state = fits[best].0;
    let covariance = ctx.covariance(&state);
    let c_hat = covariance.as_ref().map_or(1.0, |(_, c)| *c);
    let bics: Vec<f64> = fits
        .iter()
        .map(|(st, cost)| bic(*cost, st, c_hat))
        .collect();
    // Tempered, the other model may come out ahead: a probability below ½, ambiguous.
    let type_probability = probability_of(&bics, best);
    // 6. Uncertainty.
    let joint = joint_of(&state);
    let uncertainty = covariance.map(|(cov, _)| {
        let u = uncertainty_of(&state, &cov, type_probability);
        consistent_with(u, &joint, &proprioceptive, Other::Nested)
    });
    let explained = explained_fraction(&ctx, &state, &evidence);
    let details = format!(
        "fused: {}; depth sigma {sigma_d:.4} m (gate {pair_gate:.4} m, τ {:.4} m), \
         pose sigma {sigma_p:.4} m / {sigma_o:.4} rad, n_eff {:.0}, {} poses; \
         BIC {} (revolute first, variance factor {c_hat:.2}); explained {explained:.3}; \
         two-view: {:?}; proprioceptive: {:?}{}",
        terms_of(&ctx, &fits),
        evidence.tau,
        evidence.n_eff,
        poses.len(),
        bics.iter()
            .map(|b| format!("{b:.1}"))
            .collect::<Vec<_>>()
            .join(" / "),
        two_view.joint.kind(),
        proprioceptive.joint.kind(),
        wide,
    );
    Ok(Estimate {
        joint,
        moving: two_view.moving,
        part_points: two_view.part_points,
        score: unit_score(type_probability * explained),
        details,
        uncertainty,
    })
}

/// The pose noise (σ_p m, σ_o rad) from the path's smoothness, floored; the proprioceptive
/// settings' values for paths too short.
fn pose_noise(s: &FusedSettings, i: &Interaction<'_>) -> (f64, f64) {
    path_noise(i.ee_poses).map_or(
        (
            s.proprioceptive.position_sigma,
            s.proprioceptive.orientation_sigma,
        ),
        |n| {
            (
                n.position.max(MIN_POSITION_SIGMA),
                n.orientation.max(MIN_ORIENTATION_SIGMA),
            )
        },
    )
}

/// Drops a revolute fit whose path radius exceeds `max_radius` when another fit remains;
/// returns the note for the details (empty when none was dropped).
fn drop_wide_revolute(fits: &mut Vec<(State, f64)>, max_radius: f64) -> String {
    let too_wide = |st: &State| st.kind == Kind::Revolute && st.travel_scale() > max_radius;
    if fits.len() < 2 {
        return String::new();
    }
    let note = fits
        .iter()
        .find(|(st, _)| too_wide(st))
        .map_or(String::new(), |(st, _)| {
            format!(
                "; a revolute fit of path radius {:.2} m (above {max_radius:.2} m) counts as a \
             translation",
                st.travel_scale()
            )
        });
    fits.retain(|(st, _)| !too_wide(st));
    note
}

/// BIC's posterior probability of model `best` against the best of the others.
fn probability_of(bics: &[f64], best: usize) -> f64 {
    let other = (0..bics.len())
        .filter(|&k| k != best)
        .map(|k| bics[k])
        .fold(f64::INFINITY, f64::min);
    bic_probability(bics[best], other)
}

/// Each fit's kind, travel and cost terms, for the details.
fn terms_of(ctx: &Context<'_>, fits: &[(State, f64)]) -> String {
    fits.iter()
        .map(|(st, _)| {
            let [c, p, t] = ctx.cost_terms(st);
            format!(
                "{:?} travel {:.4} cloud {c:.1} poses {p:.1} coupling {t:.1}",
                st.kind, st.travel
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// One source's estimate as the fused one, with why.
fn alone(mut e: Estimate, why: &str) -> Estimate {
    e.details = format!("fused: {why}; the other source alone: {}", e.details);
    e
}

/// The lowest-cost refinement of the two lowest-cost `starts`, with its cost.
fn best_fit(ctx: &Context<'_>, starts: Vec<State>) -> Option<(State, f64)> {
    let mut scored: Vec<(State, f64)> = starts
        .into_iter()
        .map(|st| (st, ctx.cost(&st)))
        .filter(|(_, c)| c.is_finite())
        .collect();
    scored.sort_by(|a, b| a.1.total_cmp(&b.1));
    scored
        .into_iter()
        .take(2)
        .map(|(st, _)| {
            let fitted = ctx.fit(st);
            (fitted, ctx.cost(&fitted))
        })
        .filter(|(st, c)| c.is_finite() && st.travel.is_finite())
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The fraction of the registered sample with a post point within τ after the motion.
fn explained_fraction(ctx: &Context<'_>, state: &State, evidence: &CloudEvidence) -> f64 {
    let motion = state.motion();
    let n = evidence.sample.len().max(1) as f64;
    evidence
        .sample
        .iter()
        .filter(|p| ctx.post_tree.nearest(&(motion * *p), ctx.tau).is_some())
        .count() as f64
        / n
}

/// The state's joint, its travel made positive (the axis flipped if needed).
fn joint_of(state: &State) -> JointEstimate {
    let (axis, travel) = if state.travel < 0.0 {
        (-state.axis, -state.travel)
    } else {
        (state.axis, state.travel)
    };
    match state.kind {
        Kind::Revolute => JointEstimate::Revolute {
            axis,
            pivot: state.pivot,
            angle: travel,
        },
        Kind::Prismatic => JointEstimate::Prismatic {
            axis,
            distance: travel,
        },
    }
}

/// The axis-tilt and pivot blocks of the offsets' covariance `cov` (both in
/// `tangent_basis(axis)`, see [`State`]).
fn uncertainty_of(state: &State, cov: &DMatrix<f64>, type_probability: f64) -> Uncertainty {
    let basis = tangent_basis(&state.axis);
    let block = |r: usize| -> Matrix2<f64> { cov.fixed_view::<2, 2>(r, r).into_owned() };
    Uncertainty {
        type_probability,
        axis: PlaneCovariance {
            basis,
            covariance: block(0),
        },
        pivot: (state.kind == Kind::Revolute).then(|| PlaneCovariance {
            basis,
            covariance: block(2),
        }),
    }
}
