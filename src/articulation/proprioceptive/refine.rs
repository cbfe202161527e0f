//! The refits of a model on its inliers: a line by principal axis, a circle by its axis, a
//! planar circle fit and a maximum-likelihood refinement.

use nalgebra::{
    Isometry3, Matrix3, Point3, Quaternion, Unit, UnitQuaternion, Vector2, Vector3, Vector4,
};

#[cfg(doc)]
use super::estimate::estimate;
use super::model::{Model, basis, position};
use super::{OrientationModel, ProprioceptiveSettings};
use crate::articulation::cloud::centroid;
use crate::articulation::pose_circle::{self, PoseCircle};

/// The principal-axis line of the inlier positions, grasp = mean inlier orientation.
pub(super) fn refine_line(poses: &[Isometry3<f64>], inl: &[usize]) -> Option<Model> {
    if inl.len() < 2 {
        return None;
    }
    let pts: Vec<Point3<f64>> = inl.iter().map(|&k| position(&poses[k])).collect();
    let c = centroid(&pts);
    let (evals, evecs) = scatter_eigen(pts.iter().map(|p| p - c));
    let top = (0..3).max_by(|&x, &y| evals[x].total_cmp(&evals[y]))?;
    let dir = Unit::try_new(evecs.column(top).into_owned(), 1e-9)?;
    let grasp = mean_rotation(inl.iter().map(|&k| poses[k].rotation))?;
    Some(Model::Line {
        point: c,
        dir,
        grasp,
    })
}

/// The circle refit described at [`estimate`].
pub(super) fn refine_circle(
    poses: &[Isometry3<f64>],
    inl: &[usize],
    s: &ProprioceptiveSettings,
) -> Option<Model> {
    if inl.len() < 3 {
        return None;
    }
    let pts: Vec<Point3<f64>> = inl.iter().map(|&k| position(&poses[k])).collect();
    let c = centroid(&pts);
    let mut m = Matrix3::zeros();
    for p in &pts {
        let d = p - c;
        m += d * d.transpose() / (s.position_sigma * s.position_sigma);
    }
    let sigma2 = s.orientation_sigma * s.orientation_sigma;
    match s.orientation {
        OrientationModel::Ignored => {}
        OrientationModel::Rigid => {
            // Relative rotations are about the axis: it is least off their rotation vectors.
            let so = pair_scatter(inl, |a, b| {
                (poses[b].rotation * poses[a].rotation.inverse()).scaled_axis()
            });
            m += (Matrix3::identity() * so.trace() - so) / sigma2;
        }
        OrientationModel::ApproachAxis => {
            // The approach axis sweeps a cone about the joint axis: their differences are
            // perpendicular to it, as the positions' are.
            m += pair_scatter(inl, |a, b| {
                poses[b].rotation * Vector3::z() - poses[a].rotation * Vector3::z()
            }) / sigma2;
        }
    }
    let eig = m.symmetric_eigen();
    let low = (0..3).min_by(|&x, &y| eig.eigenvalues[x].total_cmp(&eig.eigenvalues[y]))?;
    let normal = Unit::try_new(eig.eigenvectors.column(low).into_owned(), 1e-9)?;
    let (e1, e2) = basis(&normal);
    let q: Vec<Vector2<f64>> = pts
        .iter()
        .map(|p| Vector2::new((p - c).dot(&e1), (p - c).dot(&e2)))
        .collect();
    let (center2, radius) = fit_circle_2d(&q)?;
    let center = c + e1 * center2.x + e2 * center2.y;
    let mut model = Model::Circle {
        center,
        normal,
        radius,
        grasp: UnitQuaternion::identity(),
    };
    let grasp = mean_rotation(inl.iter().map(|&k| {
        UnitQuaternion::from_axis_angle(&normal, -model.phase(&position(&poses[k])))
            * poses[k].rotation
    }))?;
    if let Model::Circle { grasp: g, .. } = &mut model {
        *g = grasp;
    }
    // Maximum-likelihood refinement over all inlier poses (positions and orientations).
    let (init, phi, sub) = pose_circle_inputs(&model, poses, inl)?;
    let Some(ml) = pose_circle::refine(
        &init,
        &phi,
        &sub,
        s.position_sigma,
        s.orientation,
        s.orientation_sigma,
    ) else {
        return Some(model);
    };
    let axial = ml.axis.dot(&ml.offset);
    let center = ml.center + ml.axis.into_inner() * axial;
    let radial = ml.offset - ml.axis.into_inner() * axial;
    let radius = radial.norm();
    if radius.is_nan() || radius <= 0.0 {
        return Some(model);
    }
    let (b1, b2) = basis(&ml.axis);
    let alpha = radial.dot(&b2).atan2(radial.dot(&b1));
    let grasp = UnitQuaternion::from_axis_angle(&ml.axis, -alpha) * ml.grasp;
    Some(Model::Circle {
        center,
        normal: ml.axis,
        radius,
        grasp,
    })
}

/// The pose-circle form of a circle model, with the phases of the inlier poses and the poses
/// themselves: the input of [`pose_circle::refine`] and [`pose_circle::covariance`]. `None`
/// for a line.
pub(super) fn pose_circle_inputs(
    model: &Model,
    poses: &[Isometry3<f64>],
    inl: &[usize],
) -> Option<(PoseCircle, Vec<f64>, Vec<Isometry3<f64>>)> {
    let Model::Circle {
        center,
        normal,
        radius,
        grasp,
    } = *model
    else {
        return None;
    };
    let (e1, _) = basis(&normal);
    let circle = PoseCircle {
        center,
        axis: normal,
        offset: e1 * radius,
        grasp,
    };
    let phi = inl
        .iter()
        .map(|&k| model.phase(&position(&poses[k])))
        .collect();
    let sub = inl.iter().map(|&k| poses[k]).collect();
    Some((circle, phi, sub))
}

/// `Σ v vᵀ` over the pairs `a < b` of `inl`, `v = f(a, b)`, scaled to one pair per pose (the
/// pairs are not independent).
fn pair_scatter(inl: &[usize], f: impl Fn(usize, usize) -> Vector3<f64>) -> Matrix3<f64> {
    let mut sum = Matrix3::zeros();
    for (x, &a) in inl.iter().enumerate() {
        for &b in &inl[x + 1..] {
            let v = f(a, b);
            sum += v * v.transpose();
        }
    }
    sum * 2.0 / (inl.len() as f64 - 1.0).max(1.0)
}

/// The algebraic (Kåsa) circle through planar points: `x² + y² = 2 a x + 2 b y + c` by linear
/// least squares; its centre `(a, b)` and squared radius `c + a² + b²` (`None` when the normal
/// equations are singular; the radius is not checked).
pub(crate) fn kasa_circle(q: &[Vector2<f64>]) -> Option<(Vector2<f64>, f64)> {
    let mut ata = Matrix3::zeros();
    let mut atb = Vector3::zeros();
    for p in q {
        let row = Vector3::new(2.0 * p.x, 2.0 * p.y, 1.0);
        ata += row * row.transpose();
        atb += row * p.norm_squared();
    }
    let sol = ata.try_inverse()? * atb;
    let center = Vector2::new(sol.x, sol.y);
    Some((center, sol.z + center.norm_squared()))
}

/// Algebraic (Kåsa) circle fit refined by Gauss–Newton on the geometric distances.
fn fit_circle_2d(q: &[Vector2<f64>]) -> Option<(Vector2<f64>, f64)> {
    let (mut center, r2) = kasa_circle(q)?;
    if r2.is_nan() || r2 <= 0.0 || !r2.is_finite() {
        return None;
    }
    let mut radius = r2.sqrt();
    for _ in 0..20 {
        let mut jtj = Matrix3::zeros();
        let mut jtr = Vector3::zeros();
        for p in q {
            let d = p - center;
            let dist = d.norm();
            if dist < 1e-12 {
                continue;
            }
            let res = dist - radius;
            let j = Vector3::new(-d.x / dist, -d.y / dist, -1.0);
            jtj += j * j.transpose();
            jtr += j * res;
        }
        let step = jtj.try_inverse()? * jtr;
        center -= Vector2::new(step.x, step.y);
        radius -= step.z;
        if step.norm() < 1e-12 {
            break;
        }
    }
    (radius.is_finite() && radius > 0.0).then_some((center, radius))
}

/// Eigen-decomposition of the scatter matrix of `vectors`.
fn scatter_eigen(vectors: impl Iterator<Item = Vector3<f64>>) -> (Vector3<f64>, Matrix3<f64>) {
    let mut m = Matrix3::zeros();
    for d in vectors {
        m += d * d.transpose();
    }
    let eig = m.symmetric_eigen();
    (eig.eigenvalues, eig.eigenvectors)
}

/// The normalised sign-aligned quaternion mean (the chordal L2 mean for nearby rotations).
fn mean_rotation(
    rotations: impl Iterator<Item = UnitQuaternion<f64>>,
) -> Option<UnitQuaternion<f64>> {
    let mut sum = Vector4::zeros();
    let mut first: Option<Vector4<f64>> = None;
    for q in rotations {
        let v = q.into_inner().coords;
        let reference = *first.get_or_insert(v);
        sum += if v.dot(&reference) < 0.0 { -v } else { v };
    }
    let norm = sum.norm();
    (norm > 0.0).then(|| UnitQuaternion::new_normalize(Quaternion::from(sum)))
}
