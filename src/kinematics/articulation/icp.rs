//! Robust rigid registration: trimmed ICP whose steps are closed-form weighted Kabsch solves,
//! optionally projected onto a joint model (pure translation or pure rotation about a line).

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

use super::kdtree::KdTree;
use super::screw::Screw;

/// The motion family ICP fits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum MotionModel {
    /// Any rigid motion (6 parameters).
    Rigid,
    /// Rotation about a line, no translation along it (a revolute joint, 5 parameters).
    Rotation,
    /// Translation only (a prismatic joint, 3 parameters).
    Translation,
}

/// ICP settings.
#[derive(Debug, Clone, Copy)]
pub(crate) struct IcpSettings {
    /// Correspondence distance limits of successive stages, m (coarse to fine).
    pub stages: [f64; 3],
    /// Iterations per stage.
    pub iterations: usize,
    /// Fraction of the closest correspondences kept each step.
    pub trim_fraction: f64,
    /// Weight of the extra pair relative to all point pairs, in [0, 1).
    pub extra_weight: f64,
}

/// A registration result.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Registration {
    /// `target ≈ motion * source`.
    pub motion: Isometry3<f64>,
    /// Mean of `min(d², c²)` over the source points under `motion`, c the last stage's limit.
    pub cost: f64,
}

/// Weighted Kabsch/Umeyama (no scale): the rigid `T` minimising `Σ w |T s − t|²`, by SVD of the
/// weighted cross-covariance with the reflection fix. `None` without positive total weight.
pub(crate) fn kabsch(pairs: &[(Point3<f64>, Point3<f64>, f64)]) -> Option<Isometry3<f64>> {
    let total: f64 = pairs.iter().map(|p| p.2).sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    let cs = pairs.iter().map(|p| p.0.coords * p.2).sum::<Vector3<f64>>() / total;
    let ct = pairs.iter().map(|p| p.1.coords * p.2).sum::<Vector3<f64>>() / total;
    let mut h = Matrix3::zeros();
    for (s, t, w) in pairs {
        h += (s.coords - cs) * (t.coords - ct).transpose() * *w;
    }
    let svd = h.svd(true, true);
    let (u, v_t) = (svd.u?, svd.v_t?);
    let v = v_t.transpose();
    let d = (v * u.transpose()).determinant().signum();
    let r = v * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * u.transpose();
    let rotation = UnitQuaternion::from_matrix(&r);
    let t = ct - rotation * cs;
    Some(Isometry3::from_parts(Translation3::from(t), rotation))
}

/// The closest motion of `model`'s family to `motion` (drops the axial translation of its screw
/// for [`MotionModel::Rotation`], the rotation for [`MotionModel::Translation`]).
pub(crate) fn project(motion: &Isometry3<f64>, model: MotionModel) -> Isometry3<f64> {
    match model {
        MotionModel::Rigid => *motion,
        MotionModel::Translation => {
            Isometry3::from_parts(motion.translation, UnitQuaternion::identity())
        }
        MotionModel::Rotation => {
            let mut screw = Screw::from_isometry(motion);
            if screw.angle == 0.0 {
                return Isometry3::identity();
            }
            screw.translation = 0.0;
            screw.to_isometry()
        }
    }
}

/// Registers `source` to the points of `target` (indexed by `tree`) from `init`.
///
/// Each step pairs every moved source point with its nearest target point within the stage's
/// limit, keeps the closest `trim_fraction` of the pairs, adds `extra` (e.g. the contact pair)
/// with its relative weight, solves [`kabsch`] (translation: weighted mean difference) and
/// projects onto `model`. `None` when a step finds fewer than 3 pairs.
pub(crate) fn icp(
    source: &[Point3<f64>],
    target: &[Point3<f64>],
    tree: &KdTree,
    init: Isometry3<f64>,
    extra: Option<(Point3<f64>, Point3<f64>)>,
    model: MotionModel,
    settings: &IcpSettings,
) -> Option<Registration> {
    let mut motion = project(&init, model);
    let mut pairs: Vec<(Point3<f64>, Point3<f64>, f64)> = Vec::with_capacity(source.len() + 1);
    let mut distances: Vec<f64> = Vec::with_capacity(source.len());
    for &limit in &settings.stages {
        for _ in 0..settings.iterations {
            pairs.clear();
            distances.clear();
            for s in source {
                if let Some((j, d)) = tree.nearest(&(motion * s), limit) {
                    pairs.push((*s, target[j], d));
                    distances.push(d);
                }
            }
            if pairs.len() < 3 {
                return None;
            }
            let keep = ((pairs.len() as f64 * settings.trim_fraction).ceil() as usize)
                .clamp(3, pairs.len());
            let cut = *distances.select_nth_unstable_by(keep - 1, f64::total_cmp).1;
            pairs.retain(|p| p.2 <= cut);
            let n = pairs.len() as f64;
            for p in pairs.iter_mut() {
                p.2 = 1.0;
            }
            if let Some((c_pre, c_post)) = extra.filter(|_| settings.extra_weight > 0.0) {
                let w = n * settings.extra_weight / (1.0 - settings.extra_weight);
                pairs.push((c_pre, c_post, w));
            }
            let next = match model {
                MotionModel::Translation => {
                    let total: f64 = pairs.iter().map(|p| p.2).sum();
                    let t = pairs
                        .iter()
                        .map(|p| (p.1 - p.0) * p.2)
                        .sum::<Vector3<f64>>()
                        / total;
                    Isometry3::translation(t.x, t.y, t.z)
                }
                _ => project(&kabsch(&pairs)?, model),
            };
            let change = (next.translation.vector - motion.translation.vector).norm()
                + next.rotation.angle_to(&motion.rotation);
            motion = next;
            if change < 1e-7 {
                break;
            }
        }
    }
    let cost = truncated_cost(source, tree, &motion, settings.stages[2]);
    Some(Registration { motion, cost })
}

/// Mean of `min(d², c²)` over `source` moved by `motion`, `d` the nearest-target distance.
pub(crate) fn truncated_cost(
    source: &[Point3<f64>],
    tree: &KdTree,
    motion: &Isometry3<f64>,
    c: f64,
) -> f64 {
    if source.is_empty() {
        return f64::INFINITY;
    }
    let sum: f64 = source
        .iter()
        .map(|s| tree.nearest(&(motion * s), c).map_or(c * c, |(_, d)| d * d))
        .sum();
    sum / source.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kabsch recovers a known motion exactly from noise-free pairs.
    #[test]
    fn kabsch_exact() {
        let truth = Isometry3::new(Vector3::new(0.1, -0.2, 0.3), Vector3::new(0.3, 0.2, -0.5));
        let pairs: Vec<_> = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.3, 0.1, 1.0],
        ]
        .iter()
        .map(|c| {
            let p = Point3::from(*c);
            (p, truth * p, 1.0)
        })
        .collect();
        let m = kabsch(&pairs).unwrap();
        assert!((m.to_homogeneous() - truth.to_homogeneous()).norm() < 1e-12);
    }
}
