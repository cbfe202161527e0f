//! Robust rigid registration: trimmed ICP whose steps are closed-form weighted Kabsch solves,
//! optionally projected onto a joint model (pure translation or pure rotation about a line).

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

use super::kdtree::KdTree;
use super::screw::Screw;

/// An ICP stage ends when a step changes the motion by less than this (translation in m plus
/// rotation in rad): 1 µm, far below any depth noise.
const CONVERGED: f64 = 1e-6;

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
/// Each step pairs every moved source point (every 4th in the first of three stages, every 2nd
/// in the second) with its nearest target point within the stage's limit, keeps the closest
/// `trim_fraction` of the pairs, adds `extra` (e.g. the contact pair) with its relative weight,
/// solves [`kabsch`] (translation: weighted mean difference) and projects onto `model`. `None` when a step finds fewer than 3 pairs.
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
    let n_stages = settings.stages.len();
    for (stage, &limit) in settings.stages.iter().enumerate() {
        // Coarse stages use a strided subset (every 4th, then every 2nd point): they only
        // need to find the basin; the last stage uses every point.
        let stride = 1 << (n_stages - 1 - stage).min(2);
        let subset = if source.len() / stride >= 50 {
            stride
        } else {
            1
        };
        for _ in 0..settings.iterations {
            pairs.clear();
            distances.clear();
            for s in source.iter().step_by(subset) {
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
            if change < CONVERGED {
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

/// Surface normals of a cloud, estimated on demand (PCA of the neighbours within a radius) and
/// cached per point.
pub(crate) struct NormalCache<'a> {
    points: &'a [Point3<f64>],
    tree: &'a KdTree,
    radius: f64,
    cache: std::cell::RefCell<std::collections::HashMap<usize, Option<Vector3<f64>>>>,
}

impl<'a> NormalCache<'a> {
    /// A cache over `points` (indexed by `tree`) with neighbourhoods of `radius`.
    pub(crate) fn new(points: &'a [Point3<f64>], tree: &'a KdTree, radius: f64) -> Self {
        NormalCache {
            points,
            tree,
            radius,
            cache: Default::default(),
        }
    }

    /// The unit normal at point `k`, if its neighbourhood (≥ 6 points) is clearly planar (the
    /// smallest spread at most a third of the middle one).
    pub(crate) fn normal(&self, k: usize) -> Option<Vector3<f64>> {
        if let Some(n) = self.cache.borrow().get(&k) {
            return *n;
        }
        let mut near: Vec<Point3<f64>> = Vec::new();
        self.tree
            .for_each_within(&self.points[k], self.radius, |j, _| {
                near.push(self.points[j])
            });
        let n = (near.len() >= 6).then(|| plane_normal(&near)).flatten();
        self.cache.borrow_mut().insert(k, n);
        n
    }
}

/// The smallest principal axis of `points` if their spread is clearly planar.
fn plane_normal(points: &[Point3<f64>]) -> Option<Vector3<f64>> {
    let c = points.iter().map(|p| p.coords).sum::<Vector3<f64>>() / points.len() as f64;
    let mut cov = Matrix3::zeros();
    for p in points {
        let d = p.coords - c;
        cov += d * d.transpose();
    }
    let eig = cov.symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|&x, &y| eig.eigenvalues[x].total_cmp(&eig.eigenvalues[y]));
    (eig.eigenvalues[order[0]] <= eig.eigenvalues[order[1]] / 3.0)
        .then(|| eig.eigenvectors.column(order[0]).into_owned())
}

/// Weight of the point-to-point term against the point-to-plane term in
/// [`refine_translation`]: it fixes the directions no surface constrains.
const POINT_TO_POINT_WEIGHT: f64 = 0.05;

/// In [`refine_translation`] the contact pair carries `contact_weight` of `n` times this (`n`
/// kept pairs): between the point-to-point weight (then, along directions no surface
/// constrains, the one-sided sampling of a part edge biases the result by centimetres) and the
/// full pair weight (then the contact's noise does). Chosen on the synthetic scenarios of
/// `tests/articulation/` and the discovery test world (see the error table there).
const CONTACT_REFERENCE_WEIGHT: f64 = 0.25;

/// A translation-only registration by point-to-plane ICP: each step pairs every moved source
/// point with its nearest target within `limit`, keeps the closest `trim_fraction` of the
/// pairs and solves `min Σ (n·(s + t − q))² + λ |s + t − q|²` in closed form (a 3 × 3 system;
/// `n` the target's PCA normal, λ = [`POINT_TO_POINT_WEIGHT`], plain point-to-point where the
/// target has no normal), with the contact pair weighted in (see
/// [`CONTACT_REFERENCE_WEIGHT`]). Point-to-plane
/// residuals measure the depth noise rather than the two clouds' different sampling, so the
/// directions a surface constrains (a drawer front's normal, its sides' normals) come out
/// unbiased; the small point-to-point term only settles the directions along which every
/// matched surface slides.
#[allow(clippy::too_many_arguments)]
pub(crate) fn refine_translation(
    source: &[Point3<f64>],
    target: &[Point3<f64>],
    tree: &KdTree,
    normals: &NormalCache<'_>,
    init: Vector3<f64>,
    extra: Option<(Point3<f64>, Point3<f64>)>,
    limit: f64,
    settings: &super::two_view::TwoViewSettings,
) -> Vector3<f64> {
    let mut t = init;
    let mut pairs: Vec<(Vector3<f64>, usize, f64)> = Vec::with_capacity(source.len());
    for _ in 0..settings.icp_iterations {
        pairs.clear();
        for s in source {
            if let Some((j, d)) = tree.nearest(&(s + t), limit) {
                pairs.push((s.coords, j, d));
            }
        }
        if pairs.len() < 3 {
            return t;
        }
        let keep =
            ((pairs.len() as f64 * settings.trim_fraction).ceil() as usize).clamp(3, pairs.len());
        pairs.select_nth_unstable_by(keep - 1, |a, b| a.2.total_cmp(&b.2));
        pairs.truncate(keep);
        let mut a = Matrix3::zeros();
        let mut b = Vector3::zeros();
        for (s, j, _) in &pairs {
            let q = target[*j].coords;
            let w = match normals.normal(*j) {
                Some(n) => n * n.transpose() + Matrix3::identity() * POINT_TO_POINT_WEIGHT,
                None => Matrix3::identity() * (1.0 + POINT_TO_POINT_WEIGHT),
            };
            a += w;
            b += w * (q - s);
        }
        if let Some((c_pre, c_post)) = extra.filter(|_| settings.contact_weight > 0.0) {
            // The contact pair carries `contact_weight` of the reference weight.
            let total = pairs.len() as f64 * CONTACT_REFERENCE_WEIGHT;
            let w = total * settings.contact_weight / (1.0 - settings.contact_weight);
            a += Matrix3::identity() * w;
            b += (c_post - c_pre) * w;
        }
        let Some(next) = a.lu().solve(&b) else {
            return t;
        };
        let change = (next - t).norm();
        t = next;
        if change < 1e-7 {
            break;
        }
    }
    t
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
