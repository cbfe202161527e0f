//! Maximum-likelihood refinement of a revolute model from end-effector poses: Levenberg–Marquardt
//! over the axis, a centre, the grasp offset and one latent joint angle per pose.
//!
//! Model: pose `i` is `Rot(ω, φᵢ)` about the line `(c, ω)` applied to a grasp pose, i.e.
//! position `c + Rot(ω, φᵢ) g` and orientation `Rot(ω, φᵢ) R_g`. Residuals: position error / σ_p
//! (3 per pose) and, with orientations, the rotation-vector error / σ_o (3 per pose) of a rigid
//! grasp or the approach (tool z) axis error / σ_o (3 per pose, rank 2) of a compliant one.

use nalgebra::{DMatrix, DVector, Isometry3, Point3, Unit, UnitQuaternion, Vector3};

use super::proprioceptive::OrientationModel;

/// A revolute model in the parametrisation above.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PoseCircle {
    pub center: Point3<f64>,
    pub axis: Unit<Vector3<f64>>,
    /// Grasp position relative to the centre at φ = 0.
    pub offset: Vector3<f64>,
    /// Grasp orientation at φ = 0.
    pub grasp: UnitQuaternion<f64>,
}

/// Refines `init` with latent angles `phi` on `poses`; `None` if the normal equations are
/// singular from the start.
pub(crate) fn refine(
    init: &PoseCircle,
    phi: &[f64],
    poses: &[Isometry3<f64>],
    sigma_p: f64,
    orientation: OrientationModel,
    sigma_o: f64,
) -> Option<PoseCircle> {
    let n = poses.len();
    let (e1, e2) = {
        let helper = if init.axis.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = init.axis.cross(&helper).normalize();
        (e1, init.axis.cross(&e1))
    };
    // x = [c (3), axis tilt (2), g (3), grasp rotation vector (3), φ (n)]
    let unpack = |x: &DVector<f64>| {
        let center = init.center + Vector3::new(x[0], x[1], x[2]);
        let tilt = UnitQuaternion::from_scaled_axis(e1 * x[3] + e2 * x[4]);
        let axis = tilt * init.axis;
        let offset = init.offset + Vector3::new(x[5], x[6], x[7]);
        let grasp = UnitQuaternion::from_scaled_axis(Vector3::new(x[8], x[9], x[10])) * init.grasp;
        PoseCircle {
            center,
            axis,
            offset,
            grasp,
        }
    };
    let per = if orientation == OrientationModel::Ignored {
        3
    } else {
        6
    };
    let residual = |x: &DVector<f64>| {
        let m = unpack(x);
        let mut r = DVector::zeros(n * per + 1);
        for (k, pose) in poses.iter().enumerate() {
            let rot = UnitQuaternion::from_axis_angle(&m.axis, x[11 + k]);
            let p = m.center + rot * m.offset;
            let e = (pose.translation.vector - p.coords) / sigma_p;
            r.fixed_rows_mut::<3>(k * per).copy_from(&e);
            let d = match orientation {
                OrientationModel::Ignored => continue,
                OrientationModel::Rigid => {
                    (pose.rotation * (rot * m.grasp).inverse()).scaled_axis()
                }
                OrientationModel::ApproachAxis => {
                    pose.rotation * Vector3::z() - rot * m.grasp * Vector3::z()
                }
            };
            r.fixed_rows_mut::<3>(k * per + 3).copy_from(&(d / sigma_o));
        }
        // Gauge: the centre may slide along the axis with the offset; pin it weakly.
        r[n * per] = m.axis.dot(&(m.center - init.center)) / 10.0;
        r
    };
    let mut x = DVector::zeros(11 + n);
    for (k, v) in phi.iter().enumerate() {
        x[11 + k] = *v;
    }
    let mut r = residual(&x);
    let mut cost = r.norm_squared();
    let mut lambda = 1e-3;
    for _ in 0..50 {
        let h = 1e-7;
        let mut j = DMatrix::zeros(r.len(), x.len());
        for c in 0..x.len() {
            let mut xp = x.clone();
            xp[c] += h;
            j.set_column(c, &((residual(&xp) - &r) / h));
        }
        let jtj = j.transpose() * &j;
        let jtr = j.transpose() * &r;
        let mut improved = false;
        for _ in 0..10 {
            let mut a = jtj.clone();
            for d in 0..a.nrows() {
                a[(d, d)] += lambda * (1.0 + jtj[(d, d)]);
            }
            let Some(step) = a.cholesky().map(|c| c.solve(&jtr)) else {
                lambda *= 10.0;
                continue;
            };
            let xn = &x - step;
            let rn = residual(&xn);
            let cn = rn.norm_squared();
            if cn < cost {
                let done = cost - cn < 1e-10 * cost;
                (x, r, cost) = (xn, rn, cn);
                lambda = (lambda / 3.0).max(1e-12);
                improved = !done;
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }
    let m = unpack(&x);
    m.center.coords.iter().all(|v| v.is_finite()).then_some(m)
}
