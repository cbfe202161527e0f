//! Maximum-likelihood refinement of a revolute model from end-effector poses: Levenberg–Marquardt
//! over the axis, a centre, the grasp offset and one latent joint angle per pose.
//!
//! Model: pose `i` is `Rot(ω, φᵢ)` about the line `(c, ω)` applied to a grasp pose, i.e.
//! position `c + Rot(ω, φᵢ) g` and orientation `Rot(ω, φᵢ) R_g`. Residuals: position error / σ_p
//! (3 per pose) and, with orientations, the rotation-vector error / σ_o (3 per pose) of a rigid
//! grasp or the approach (tool z) axis error / σ_o (3 per pose, rank 2) of a compliant one.

use nalgebra::{DMatrix, DVector, Isometry3, Matrix5, Point3, Unit, UnitQuaternion, Vector3};

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

/// The least-squares problem of a [`PoseCircle`] near `init`: parameters
/// `x = [c (3), axis tilt (2), g (3), grasp rotation vector (3), φ (n)]` as offsets from
/// `init`, weighted residuals as in the module docs plus a weak gauge term.
struct Problem<'a> {
    init: &'a PoseCircle,
    /// The tilt basis: `x[3]` turns the axis about `e1`, `x[4]` about `e2 = axis × e1`.
    e1: Vector3<f64>,
    e2: Vector3<f64>,
    poses: &'a [Isometry3<f64>],
    sigma_p: f64,
    orientation: OrientationModel,
    sigma_o: f64,
    /// Residual rows per pose: 3 (positions) or 6 (with orientations).
    per: usize,
}

impl<'a> Problem<'a> {
    fn new(
        init: &'a PoseCircle,
        poses: &'a [Isometry3<f64>],
        sigma_p: f64,
        orientation: OrientationModel,
        sigma_o: f64,
    ) -> Self {
        let helper = if init.axis.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = init.axis.cross(&helper).normalize();
        let per = if orientation == OrientationModel::Ignored {
            3
        } else {
            6
        };
        Problem {
            init,
            e1,
            e2: init.axis.cross(&e1),
            poses,
            sigma_p,
            orientation,
            sigma_o,
            per,
        }
    }

    fn unpack(&self, x: &DVector<f64>) -> PoseCircle {
        let init = self.init;
        let center = init.center + Vector3::new(x[0], x[1], x[2]);
        let tilt = UnitQuaternion::from_scaled_axis(self.e1 * x[3] + self.e2 * x[4]);
        let axis = tilt * init.axis;
        let offset = init.offset + Vector3::new(x[5], x[6], x[7]);
        let grasp = UnitQuaternion::from_scaled_axis(Vector3::new(x[8], x[9], x[10])) * init.grasp;
        PoseCircle {
            center,
            axis,
            offset,
            grasp,
        }
    }

    fn residual(&self, x: &DVector<f64>) -> DVector<f64> {
        let (n, per) = (self.poses.len(), self.per);
        let m = self.unpack(x);
        let mut r = DVector::zeros(n * per + 1);
        for (k, pose) in self.poses.iter().enumerate() {
            let rot = UnitQuaternion::from_axis_angle(&m.axis, x[11 + k]);
            let p = m.center + rot * m.offset;
            let e = (pose.translation.vector - p.coords) / self.sigma_p;
            r.fixed_rows_mut::<3>(k * per).copy_from(&e);
            let d = match self.orientation {
                OrientationModel::Ignored => continue,
                OrientationModel::Rigid => {
                    (pose.rotation * (rot * m.grasp).inverse()).scaled_axis()
                }
                OrientationModel::ApproachAxis => {
                    pose.rotation * Vector3::z() - rot * m.grasp * Vector3::z()
                }
            };
            r.fixed_rows_mut::<3>(k * per + 3)
                .copy_from(&(d / self.sigma_o));
        }
        // Gauge: the centre may slide along the axis with the offset; pin it weakly.
        r[n * per] = m.axis.dot(&(m.center - self.init.center)) / 10.0;
        r
    }

    /// The forward-difference Jacobian of [`residual`](Self::residual) at `x` (`r` its value).
    fn jacobian(&self, x: &DVector<f64>, r: &DVector<f64>) -> DMatrix<f64> {
        let h = 1e-7;
        let mut j = DMatrix::zeros(r.len(), x.len());
        for c in 0..x.len() {
            let mut xp = x.clone();
            xp[c] += h;
            j.set_column(c, &((self.residual(&xp) - r) / h));
        }
        j
    }
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
    let problem = Problem::new(init, poses, sigma_p, orientation, sigma_o);
    let mut x = DVector::zeros(11 + poses.len());
    for (k, v) in phi.iter().enumerate() {
        x[11 + k] = *v;
    }
    let mut r = problem.residual(&x);
    let mut cost = r.norm_squared();
    let mut lambda = 1e-3;
    for _ in 0..50 {
        let j = problem.jacobian(&x, &r);
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
            let rn = problem.residual(&xn);
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
    let m = problem.unpack(&x);
    m.center.coords.iter().all(|v| v.is_finite()).then_some(m)
}

/// The covariance of a fitted circle's line, from the curvature of its least-squares problem.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineCovariance {
    /// The tilt basis: a tilt `(u, v)` turns the axis `a` into `a + v e1 − u e2`.
    pub e1: Vector3<f64>,
    /// See `e1`; `e2 = a × e1`.
    pub e2: Vector3<f64>,
    /// Covariance of `[centre (3), tilt u, tilt v]` (m², rad²).
    pub center_tilt: Matrix5<f64>,
    /// The position and orientation noise estimated from the residuals (m, rad; the
    /// orientation one 0 when orientations are ignored).
    pub sigma_p: f64,
    pub sigma_o: f64,
}

/// The covariance of the line of `circle` fitted to `poses` (latent angles `phi`) by the
/// least squares above with noise `sigma_p`, `sigma_o`, at that fit, by the sandwich
/// `A⁻¹ B A⁻¹`: `A = JᵀJ` the curvature of the weighted problem, `B = Jᵀ D J` with `D` each
/// residual block's variance (positions, orientations) estimated from its residuals
/// (`Σ r² / (m_block · (m − p) / m)`, `m` the residual count, `p` the parameters; an
/// approach axis residual counts 2 per pose). With the settings' noise right, `D = 1` and the
/// covariance is `(JᵀJ)⁻¹`; with it wrong by a factor, the covariance is corrected by it.
/// The gauge (the centre's slide along the axis) is fixed by the problem's weak pin. `None`
/// for a singular `A` or fewer residuals than parameters.
pub(crate) fn covariance(
    circle: &PoseCircle,
    phi: &[f64],
    poses: &[Isometry3<f64>],
    sigma_p: f64,
    orientation: OrientationModel,
    sigma_o: f64,
) -> Option<LineCovariance> {
    let problem = Problem::new(circle, poses, sigma_p, orientation, sigma_o);
    let n = poses.len();
    let mut x = DVector::zeros(11 + n);
    for (k, v) in phi.iter().enumerate() {
        x[11 + k] = *v;
    }
    let r = problem.residual(&x);
    let j = problem.jacobian(&x, &r);
    let per = problem.per;
    let (mut rss_p, mut rss_o) = (0.0, 0.0);
    for k in 0..n {
        rss_p += r.rows(k * per, 3).norm_squared();
        if per == 6 {
            rss_o += r.rows(k * per + 3, 3).norm_squared();
        }
    }
    let m_p = 3.0 * n as f64;
    let m_o = match orientation {
        OrientationModel::Ignored => 0.0,
        OrientationModel::ApproachAxis => 2.0 * n as f64,
        OrientationModel::Rigid => 3.0 * n as f64,
    };
    // The gauge (centre along the axis) and the grasp rotations no residual sees (the roll
    // about the approach axis; all of them without orientations) are not parameters.
    let unseen = match orientation {
        OrientationModel::Ignored => 3.0,
        OrientationModel::ApproachAxis => 1.0,
        OrientationModel::Rigid => 0.0,
    };
    let params = x.len() as f64 - 1.0 - unseen;
    let dof = (m_p + m_o - params) / (m_p + m_o);
    if dof <= 0.0 {
        return None;
    }
    let k_p = rss_p / (m_p * dof);
    let k_o = if m_o > 0.0 { rss_o / (m_o * dof) } else { 1.0 };
    let mut jd = j.clone();
    for (row, mut jr) in jd.row_iter_mut().enumerate() {
        let block = if row == n * per {
            1.0
        } else if row % per < 3 {
            k_p
        } else {
            k_o
        };
        jr *= block;
    }
    // A unit prior on the grasp rotation (rad) fixes its unseen directions; against the
    // information of the seen ones (≥ 1 / σ_o² per pose, σ_o ≲ 0.1 rad) it is negligible, and
    // they do not couple to the centre and tilt.
    let mut a = j.transpose() * &j;
    for c in 8..11 {
        a[(c, c)] += 1.0;
    }
    let a_inv = a.try_inverse()?;
    let b = j.transpose() * jd;
    let full = &a_inv * b * &a_inv;
    let center_tilt = Matrix5::from_fn(|r, c| full[(r, c)]);
    let finite = center_tilt.iter().all(|v| v.is_finite());
    finite.then_some(LineCovariance {
        e1: problem.e1,
        e2: problem.e2,
        center_tilt,
        sigma_p: sigma_p * k_p.sqrt(),
        sigma_o: if m_o > 0.0 { sigma_o * k_o.sqrt() } else { 0.0 },
    })
}
