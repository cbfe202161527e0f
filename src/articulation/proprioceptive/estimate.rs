//! The estimate: MLESAC fits of both models, the selection by BIC, and the joint of the
//! winner.

use std::f64::consts::TAU;

use nalgebra::{Isometry3, Point3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

#[cfg(doc)]
use super::OrientationModel;
use super::likelihood::Likelihood;
use super::model::{Model, circle_through, line_through};
use super::noise::{MIN_ORIENTATION_SIGMA, MIN_POSITION_SIGMA, path_noise};
use super::refine::{refine_circle, refine_line};
use super::uncertainty::uncertainty;
use super::{NoiseSource, ProprioceptiveSettings};
use crate::articulation::estimate::{Estimate, JointEstimate, unit_score};
use crate::articulation::uncertainty::bic_probability;

/// A fitted model with its score.
#[derive(Debug, Clone)]
struct Fit {
    model: Model,
    log_l: f64,
    bic: f64,
    inliers: Vec<bool>,
}

/// Sturm et al. (2011), Sec. 3, restricted to the two joint models:
///
/// 0. The noise levels σ_p, σ_o below are the settings' or, with [`NoiseSource::FromPath`]
///    estimated from the path's smoothness
///    ([`path_noise`](crate::articulation::path_noise)).
/// 1. For each model, MLESAC: `iterations` hypotheses from random minimal sets (2 positions for
///    a line, 3 for a circle; the first sample's orientation fixes the grasp offset), each scored
///    by the log-likelihood of a Gaussian-inlier / uniform-outlier mixture whose weight is found
///    by EM; the best hypothesis is refined three times on its inliers (posterior > ½): a line by
///    principal axis, a circle's axis as the smallest eigenvector of
///    `S_p/σ_p² + (tr S_o − S_o)/σ_o²` (out-of-plane position scatter plus the rotation vectors'
///    components off the axis), its centre and radius by a geometric circle fit in the plane,
///    then all of it jointly by maximum likelihood (Levenberg–Marquardt over axis, centre, grasp
///    offset and one latent angle per pose, with position and orientation residuals).
/// 2. `BIC = −2 log L + k ln n` (k = 4 line, 6 circle, + 3 grasp orientation parameters with
///    [`OrientationModel::Rigid`], + 2 with [`OrientationModel::ApproachAxis`]); the lower wins.
///    With the approach axis only, the orientation terms above use the angle between approach
///    axes, and the axis scatter the approach axes' differences (perpendicular to the joint
///    axis) in place of the relative rotation vectors (along it).
/// 3. Fewer than `min_poses` poses, positions spanning less than `min_motion`, a winner that
///    explains fewer than half the poses, or a winner whose fitted travel (distance along the
///    line, arc length on the circle) or whose straight distance between the first and last
///    inliers is below `min_motion` give `Unknown`.
/// 4. The uncertainty of the winner ([`uncertainty`]); its type probability is BIC's
///    posterior against the other model. A revolute pivot is the axis point level with
///    `contact_pre`, or without it with the first inlier's position.
pub(super) fn estimate(
    s: &ProprioceptiveSettings,
    ee_poses: &[(f64, Isometry3<f64>)],
    contact_pre: Option<Point3<f64>>,
) -> Estimate {
    let (s, noise_note) = with_noise(s, ee_poses);
    let s = &s;
    let poses: Vec<Isometry3<f64>> = ee_poses.iter().map(|(_, p)| *p).collect();
    let n = poses.len();
    let positions = match check_motion(s, &poses) {
        Ok(positions) => positions,
        Err(reason) => return Estimate::unknown(reason),
    };
    let fits = fit_models(s, &poses);
    let Some(best) = fits.iter().min_by(|a, b| a.bic.total_cmp(&b.bic)) else {
        return Estimate::unknown("no model hypothesis could be formed (degenerate positions)");
    };
    let mut details = format!("proprioceptive: {}; {noise_note}", summary(&fits, n));
    let inl: Vec<usize> = (0..n).filter(|&k| best.inliers[k]).collect();
    if inl.len() * 2 < n || inl.len() < 2 {
        return Estimate {
            details: details.clone(),
            ..Estimate::unknown(format!("no model explains the motion ({details})"))
        };
    }
    let score = score(&fits, best, inl.len(), n);
    if let Some(reason) = too_little_travel(s, &best.model, &positions, &inl) {
        return Estimate {
            details,
            ..Estimate::unknown(reason)
        };
    }
    // Without a contact the pivot is level with where the end effector began.
    let reference = contact_pre.unwrap_or(positions[inl[0]]);
    let other = fits
        .iter()
        .filter(|f| !std::ptr::eq(*f, best))
        .map(|f| f.bic)
        .fold(f64::INFINITY, f64::min);
    let type_probability = bic_probability(best.bic, other);
    let uncertainty = uncertainty(s, &best.model, &poses, &inl, &reference, type_probability).map(
        |(u, sigma_p, sigma_o)| {
            details += &format!(
                "; estimated noise: position {sigma_p:.4} m, orientation {sigma_o:.4} rad"
            );
            u
        },
    );
    Estimate {
        joint: joint(&best.model, &positions, &inl, reference),
        moving: Vec::new(),
        part_points: Vec::new(),
        score,
        details,
        uncertainty,
    }
}

/// The settings with the noise levels the fits use ([`NoiseSource`]), and a note for the
/// details saying which.
fn with_noise(
    s: &ProprioceptiveSettings,
    ee_poses: &[(f64, Isometry3<f64>)],
) -> (ProprioceptiveSettings, String) {
    let estimated = match s.noise {
        NoiseSource::Settings => None,
        NoiseSource::FromPath => path_noise(ee_poses),
    };
    match estimated {
        Some(n) => {
            let out = ProprioceptiveSettings {
                position_sigma: n.position.max(MIN_POSITION_SIGMA),
                orientation_sigma: n.orientation.max(MIN_ORIENTATION_SIGMA),
                ..s.clone()
            };
            let note = format!(
                "noise from the path: position {:.4} m, orientation {:.4} rad",
                n.position, n.orientation
            );
            (out, note)
        }
        None => (s.clone(), "noise from the settings".to_string()),
    }
}

/// Step 3's checks of the input: enough poses, spanning at least `min_motion`. The positions,
/// or the reason for `Unknown`: which check failed.
fn check_motion(
    s: &ProprioceptiveSettings,
    poses: &[Isometry3<f64>],
) -> Result<Vec<Point3<f64>>, String> {
    let n = poses.len();
    if n < s.min_poses {
        return Err(format!(
            "too few end-effector poses: {n} (need {})",
            s.min_poses
        ));
    }
    let positions: Vec<Point3<f64>> = poses
        .iter()
        .map(|p| Point3::from(p.translation.vector))
        .collect();
    let (lo, hi) = positions
        .iter()
        .fold((positions[0], positions[0]), |(lo, hi), p| {
            (lo.inf(p), hi.sup(p))
        });
    let extent = (hi - lo).norm();
    if extent < s.min_motion {
        return Err(format!(
            "too little motion: end-effector positions span {extent:.4} m (need {} m)",
            s.min_motion
        ));
    }
    Ok(positions)
}

/// Steps 1 and 2 for both models, the line first, from one generator seeded with `seed`: the
/// best MLESAC hypothesis, refined, with its BIC and inliers. A model without any hypothesis
/// (degenerate minimal sets) is left out.
fn fit_models(s: &ProprioceptiveSettings, poses: &[Isometry3<f64>]) -> Vec<Fit> {
    let n = poses.len();
    let lik = Likelihood::new(s);
    let mut rng = ChaCha8Rng::seed_from_u64(s.seed);
    let mut fits: Vec<Fit> = Vec::new();
    for circle in [false, true] {
        let Some(hypothesis) = mlesac(s, &lik, &mut rng, poses, circle) else {
            continue;
        };
        let (model, log_l) = refine(s, &lik, poses, circle, hypothesis);
        let (_, post) = lik.evaluate(&model, poses);
        let bic = -2.0 * log_l + model.parameters(s.orientation) * (n as f64).ln();
        fits.push(Fit {
            model,
            log_l,
            bic,
            inliers: post.iter().map(|&q| q > 0.5).collect(),
        });
    }
    fits
}

/// The most likely of `iterations` hypotheses through random minimal sets (2 poses for a line,
/// 3 for a circle), with its log-likelihood; `None` when no minimal set gave one.
fn mlesac(
    s: &ProprioceptiveSettings,
    lik: &Likelihood,
    rng: &mut ChaCha8Rng,
    poses: &[Isometry3<f64>],
    circle: bool,
) -> Option<(Model, f64)> {
    let n = poses.len();
    let mut best: Option<(Model, f64)> = None;
    for _ in 0..s.iterations {
        let k = if circle { 3 } else { 2 };
        let idx = rand::seq::index::sample(rng, n, k).into_vec();
        let model = if circle {
            circle_through(poses, &idx)
        } else {
            line_through(poses, &idx)
        };
        let Some(model) = model else { continue };
        let (log_l, _) = lik.evaluate(&model, poses);
        if best.is_none_or(|(_, b)| log_l > b) {
            best = Some((model, log_l));
        }
    }
    best
}

/// Up to three refits of `(model, log_l)` on its inliers (posterior > ½), each kept only while
/// the likelihood does not drop.
fn refine(
    s: &ProprioceptiveSettings,
    lik: &Likelihood,
    poses: &[Isometry3<f64>],
    circle: bool,
    (mut model, mut log_l): (Model, f64),
) -> (Model, f64) {
    let n = poses.len();
    for _ in 0..3 {
        let (_, post) = lik.evaluate(&model, poses);
        let inl: Vec<usize> = (0..n).filter(|&k| post[k] > 0.5).collect();
        let refined = if circle {
            refine_circle(poses, &inl, s)
        } else {
            refine_line(poses, &inl)
        };
        let Some(refined) = refined else { break };
        let (l, _) = lik.evaluate(&refined, poses);
        if l < log_l {
            break;
        }
        (model, log_l) = (refined, l);
    }
    (model, log_l)
}

/// The fits for the estimate's details: per model, its log-likelihood, BIC and inlier count.
fn summary(fits: &[Fit], n: usize) -> String {
    let summary: Vec<String> = fits
        .iter()
        .map(|f| {
            let name = if matches!(f.model, Model::Line { .. }) {
                "prismatic"
            } else {
                "revolute"
            };
            let k = f.inliers.iter().filter(|&&b| b).count();
            format!(
                "{name}: log L {:.1}, BIC {:.1}, inliers {k}/{n}",
                f.log_l, f.bic
            )
        })
        .collect();
    summary.join("; ")
}

/// The estimate's score: the winner's inlier fraction (`inliers` of `n`), discounted by how
/// narrowly it beat the other model on BIC.
fn score(fits: &[Fit], best: &Fit, inliers: usize, n: usize) -> f64 {
    let margin = fits
        .iter()
        .map(|f| f.bic - best.bic)
        .fold(f64::INFINITY, |a, b| if b > 0.0 { a.min(b) } else { a });
    let margin = if margin.is_finite() { margin } else { 0.0 };
    unit_score(inliers as f64 / n as f64 / (1.0 + (-margin / 2.0).exp()))
}

/// Step 3's check of the winner: the reason for `Unknown` when its fitted travel from the first
/// to the last inlier, or the straight distance between them, is below `min_motion`.
fn too_little_travel(
    s: &ProprioceptiveSettings,
    model: &Model,
    positions: &[Point3<f64>],
    inl: &[usize],
) -> Option<String> {
    let (first, last) = (positions[inl[0]], positions[inl[inl.len() - 1]]);
    let travel = match *model {
        Model::Line { dir, .. } => dir.dot(&(last - first)).abs(),
        Model::Circle { radius, .. } => radius * swept_angle(model, positions, inl).abs(),
    };
    // The straight distance too: a circle fitted to noise about one spot can "sweep" any
    // angle (about the approach axis the orientations cannot object), while an exploration
    // pulls the end effector away.
    let chord = (last - first).norm();
    (travel.min(chord) < s.min_motion).then(|| {
        format!(
            "too little motion: the fitted joint moves the end effector {travel:.4} m, which \
             ends {chord:.4} m from where it began (need {} m of each)",
            s.min_motion
        )
    })
}

/// The winner's joint, oriented so that it moved forwards from the first to the last inlier;
/// a revolute joint's pivot is the point of its axis level with the contact `contact_pre`.
fn joint(
    model: &Model,
    positions: &[Point3<f64>],
    inl: &[usize],
    contact_pre: Point3<f64>,
) -> JointEstimate {
    let (first, last) = (positions[inl[0]], positions[inl[inl.len() - 1]]);
    match *model {
        Model::Line { dir, .. } => {
            let d = dir.dot(&(last - first));
            let axis = if d < 0.0 { -dir } else { dir };
            JointEstimate::Prismatic {
                axis,
                distance: d.abs(),
            }
        }
        Model::Circle { center, normal, .. } => {
            let angle = swept_angle(model, positions, inl);
            let axis = if angle < 0.0 { -normal } else { normal };
            let pivot = center + axis.into_inner() * axis.dot(&(contact_pre - center));
            JointEstimate::Revolute {
                axis,
                pivot,
                angle: angle.abs(),
            }
        }
    }
}

/// The unwrapped angle swept on a circle model from the first to the last inlier, in time order.
fn swept_angle(model: &Model, positions: &[Point3<f64>], inl: &[usize]) -> f64 {
    let mut angle = 0.0;
    let mut prev = model.phase(&positions[inl[0]]);
    for &k in &inl[1..] {
        let phi = model.phase(&positions[k]);
        let mut d = phi - prev;
        d -= TAU * (d / TAU).round();
        angle += d;
        prev = phi;
    }
    angle
}
