//! The proprioceptive estimator: line and circle models fitted to the end-effector poses with
//! MLESAC and selected by BIC (Sturm, Stachniss, Burgard 2011).

use std::f64::consts::{PI, TAU};

use nalgebra::{
    Isometry3, Matrix3, Point3, Quaternion, Unit, UnitQuaternion, Vector2, Vector3, Vector4,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::cloud::centroid;
use super::error::ArticulationError;
use super::estimate::{ArticulationEstimator, Estimate, Interaction, JointEstimate};
use super::pose_circle::{self, PoseCircle};
use crate::InvalidSetting;

/// Settings of [`Proprioceptive`]. Lengths in metres, angles in radians.
#[derive(Debug, Clone, PartialEq)]
pub struct ProprioceptiveSettings {
    /// Standard deviation of end-effector position noise (inlier model).
    pub position_sigma: f64,
    /// Standard deviation of end-effector orientation noise (inlier model).
    pub orientation_sigma: f64,
    /// How much of the end effector's orientation follows the part (a revolute joint turns a
    /// held end effector by the joint angle; a prismatic one does not turn it).
    pub orientation: OrientationModel,
    /// Radius of the uniform outlier density of position residuals.
    pub outlier_range: f64,
    /// MLESAC hypotheses per model.
    pub iterations: usize,
    /// Seed of the hypothesis sampler.
    pub seed: u64,
    /// Fewer poses than this gives [`Unknown`](super::JointEstimate::Unknown).
    pub min_poses: usize,
    /// Positions spanning less than this give `Unknown`.
    pub min_motion: f64,
}

/// Which part of the recorded end-effector orientations the estimator trusts to follow the part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OrientationModel {
    /// Positions only.
    Ignored,
    /// The tool z axis (the approach direction) turns with the part; the roll about it is free.
    /// This is what a compliance controller that keeps pulling along the front's normal
    /// guarantees (the paper's exploration, and [`crate::discovery`]'s): soft fingers and a
    /// re-solved arm let the wrist roll while the approach stays normal to the front. The
    /// default, since a rigid grasp satisfies it too.
    #[default]
    ApproachAxis,
    /// The whole orientation turns with the part (a rigid grasp). Under a compliant grasp the
    /// wrist's free roll then tilts the fitted axis.
    Rigid,
}

impl OrientationModel {
    /// Free parameters of the grasp orientation offset.
    fn parameters(self) -> f64 {
        match self {
            OrientationModel::Ignored => 0.0,
            OrientationModel::ApproachAxis => 2.0,
            OrientationModel::Rigid => 3.0,
        }
    }

    /// The angle between two end-effector orientations that this model compares.
    fn angle(self, a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
        match self {
            OrientationModel::Ignored => 0.0,
            OrientationModel::ApproachAxis => (a * Vector3::z()).angle(&(b * Vector3::z())),
            OrientationModel::Rigid => a.angle_to(b),
        }
    }
}

impl Default for ProprioceptiveSettings {
    fn default() -> Self {
        ProprioceptiveSettings {
            position_sigma: 0.005,
            orientation_sigma: 0.05,
            orientation: OrientationModel::ApproachAxis,
            outlier_range: 0.5,
            iterations: 200,
            seed: 0,
            min_poses: 6,
            min_motion: 0.02,
        }
    }
}

impl ProprioceptiveSettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`ArticulationError::InvalidSetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ArticulationError> {
        let positive = [
            ("position_sigma", self.position_sigma),
            ("orientation_sigma", self.orientation_sigma),
            ("outlier_range", self.outlier_range),
            ("min_motion", self.min_motion),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(InvalidSetting::new(name, value, "finite and > 0").into());
            }
        }
        if self.iterations == 0 {
            return Err(InvalidSetting::new("iterations", 0.0, "≥ 1").into());
        }
        if self.min_poses < 3 {
            return Err(InvalidSetting::new("min_poses", self.min_poses as f64, "≥ 3").into());
        }
        Ok(())
    }
}

/// The proprioceptive estimator (see the module docs of [`super`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Proprioceptive {
    /// Its settings.
    pub settings: ProprioceptiveSettings,
}

impl ArticulationEstimator for Proprioceptive {
    fn name(&self) -> &str {
        "proprioceptive"
    }

    /// # Errors
    /// Bad input ([`Interaction::validate`]) or bad settings
    /// ([`ProprioceptiveSettings::validate`]).
    fn estimate(&self, interaction: &Interaction<'_>) -> Result<Estimate, ArticulationError> {
        interaction.validate()?;
        self.settings.validate()?;
        Ok(estimate(&self.settings, interaction))
    }
}

/// A joint hypothesis fitted to the end-effector poses.
#[derive(Debug, Clone, Copy)]
enum Model {
    /// A line through `point` along `dir`; `grasp` is the constant end-effector orientation.
    Line {
        point: Point3<f64>,
        dir: Unit<Vector3<f64>>,
        grasp: UnitQuaternion<f64>,
    },
    /// A circle about the axis `normal` through `center`; the end effector's orientation is
    /// `Rot(normal, φ) · grasp`, `φ` the position's angle on the circle.
    Circle {
        center: Point3<f64>,
        normal: Unit<Vector3<f64>>,
        radius: f64,
        grasp: UnitQuaternion<f64>,
    },
}

/// Fixed in-plane basis `(e1, e2)` of a unit normal.
fn basis(n: &Unit<Vector3<f64>>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = n.cross(&helper).normalize();
    (e1, n.cross(&e1))
}

impl Model {
    /// Number of free parameters (orientation offset included when used).
    fn parameters(&self, orientation: OrientationModel) -> f64 {
        let extra = orientation.parameters();
        match self {
            Model::Line { .. } => 4.0 + extra,
            Model::Circle { .. } => 6.0 + extra,
        }
    }

    /// The angle of `p` on the circle (0 for a line).
    fn phase(&self, p: &Point3<f64>) -> f64 {
        match self {
            Model::Line { .. } => 0.0,
            Model::Circle { center, normal, .. } => {
                let (e1, e2) = basis(normal);
                let w = p - center;
                w.dot(&e2).atan2(w.dot(&e1))
            }
        }
    }

    /// The orientation the model predicts for an end effector at `p`.
    fn orientation(&self, p: &Point3<f64>) -> UnitQuaternion<f64> {
        match self {
            Model::Line { grasp, .. } => *grasp,
            Model::Circle { normal, grasp, .. } => {
                UnitQuaternion::from_axis_angle(normal, self.phase(p)) * grasp
            }
        }
    }

    /// Position residual (m, 2-d: perpendicular to the line / off the circle) and orientation
    /// residual (rad) under `orientation`.
    fn residual(&self, pose: &Isometry3<f64>, orientation: OrientationModel) -> (f64, f64) {
        let p = Point3::from(pose.translation.vector);
        let r = match self {
            Model::Line { point, dir, .. } => {
                let w = p - point;
                (w - dir.into_inner() * dir.dot(&w)).norm()
            }
            Model::Circle {
                center,
                normal,
                radius,
                ..
            } => {
                let w = p - center;
                let h = normal.dot(&w);
                let rho = (w - normal.into_inner() * h).norm();
                ((rho - radius).powi(2) + h * h).sqrt()
            }
        };
        (r, orientation.angle(&self.orientation(&p), &pose.rotation))
    }
}

/// Likelihood terms of the inlier/outlier mixture.
struct Likelihood {
    sigma: f64,
    sigma_rot: f64,
    orientation: OrientationModel,
    outlier: f64,
}

impl Likelihood {
    fn new(s: &ProprioceptiveSettings) -> Self {
        let mut outlier = 1.0 / (PI * s.outlier_range * s.outlier_range);
        if s.orientation != OrientationModel::Ignored {
            outlier /= PI;
        }
        Likelihood {
            sigma: s.position_sigma,
            sigma_rot: s.orientation_sigma,
            orientation: s.orientation,
            outlier,
        }
    }

    /// Inlier density of one pose's residuals: 2-d Gaussian in position, half-normal in angle.
    fn inlier(&self, (r, a): (f64, f64)) -> f64 {
        let s2 = self.sigma * self.sigma;
        let mut f = (-r * r / (2.0 * s2)).exp() / (2.0 * PI * s2);
        if self.orientation != OrientationModel::Ignored {
            let t2 = self.sigma_rot * self.sigma_rot;
            f *= (2.0 / PI).sqrt() / self.sigma_rot * (-a * a / (2.0 * t2)).exp();
        }
        f
    }

    /// MLESAC: the mixing weight γ by EM, then `(log-likelihood, posteriors)`.
    fn evaluate(&self, model: &Model, poses: &[Isometry3<f64>]) -> (f64, Vec<f64>) {
        let f: Vec<f64> = poses
            .iter()
            .map(|p| self.inlier(model.residual(p, self.orientation)))
            .collect();
        let mut gamma = 0.5;
        let mut post = vec![0.0; f.len()];
        for _ in 0..10 {
            for (q, fi) in post.iter_mut().zip(&f) {
                let a = gamma * fi;
                *q = a / (a + (1.0 - gamma) * self.outlier);
            }
            gamma = (post.iter().sum::<f64>() / f.len() as f64).clamp(1e-3, 1.0 - 1e-3);
        }
        let log_l = f
            .iter()
            .map(|fi| (gamma * fi + (1.0 - gamma) * self.outlier).ln())
            .sum();
        (log_l, post)
    }
}

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
fn estimate(s: &ProprioceptiveSettings, i: &Interaction<'_>) -> Estimate {
    let poses: Vec<Isometry3<f64>> = i.ee_poses.iter().map(|(_, p)| *p).collect();
    let n = poses.len();
    if n < s.min_poses {
        return Estimate::unknown(format!(
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
        return Estimate::unknown(format!(
            "too little motion: end-effector positions span {extent:.4} m (need {} m)",
            s.min_motion
        ));
    }
    let lik = Likelihood::new(s);
    let mut rng = ChaCha8Rng::seed_from_u64(s.seed);
    let mut fits: Vec<Fit> = Vec::new();
    for circle in [false, true] {
        let mut best: Option<(Model, f64)> = None;
        for _ in 0..s.iterations {
            let k = if circle { 3 } else { 2 };
            let idx = rand::seq::index::sample(&mut rng, n, k).into_vec();
            let model = if circle {
                circle_through(&poses, &idx)
            } else {
                line_through(&poses, &idx)
            };
            let Some(model) = model else { continue };
            let (log_l, _) = lik.evaluate(&model, &poses);
            if best.is_none_or(|(_, b)| log_l > b) {
                best = Some((model, log_l));
            }
        }
        let Some((mut model, mut log_l)) = best else {
            continue;
        };
        for _ in 0..3 {
            let (_, post) = lik.evaluate(&model, &poses);
            let inl: Vec<usize> = (0..n).filter(|&k| post[k] > 0.5).collect();
            let refined = if circle {
                refine_circle(&poses, &inl, s)
            } else {
                refine_line(&poses, &inl)
            };
            let Some(refined) = refined else { break };
            let (l, _) = lik.evaluate(&refined, &poses);
            if l < log_l {
                break;
            }
            (model, log_l) = (refined, l);
        }
        let (_, post) = lik.evaluate(&model, &poses);
        let bic = -2.0 * log_l + model.parameters(s.orientation) * (n as f64).ln();
        fits.push(Fit {
            model,
            log_l,
            bic,
            inliers: post.iter().map(|&q| q > 0.5).collect(),
        });
    }
    let Some(best) = fits.iter().min_by(|a, b| a.bic.total_cmp(&b.bic)) else {
        return Estimate::unknown("no model hypothesis could be formed (degenerate positions)");
    };
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
    let details = format!("proprioceptive: {}", summary.join("; "));
    let inl: Vec<usize> = (0..n).filter(|&k| best.inliers[k]).collect();
    if inl.len() * 2 < n || inl.len() < 2 {
        return Estimate {
            details: details.clone(),
            ..Estimate::unknown(format!("no model explains the motion ({details})"))
        };
    }
    let margin = fits
        .iter()
        .map(|f| f.bic - best.bic)
        .fold(f64::INFINITY, |a, b| if b > 0.0 { a.min(b) } else { a });
    let margin = if margin.is_finite() { margin } else { 0.0 };
    let score = inl.len() as f64 / n as f64 / (1.0 + (-margin / 2.0).exp());
    let (first, last) = (positions[inl[0]], positions[inl[inl.len() - 1]]);
    let travel = match best.model {
        Model::Line { dir, .. } => dir.dot(&(last - first)).abs(),
        Model::Circle { radius, .. } => radius * swept_angle(&best.model, &positions, &inl).abs(),
    };
    // The straight distance too: a circle fitted to noise about one spot can "sweep" any
    // angle (about the approach axis the orientations cannot object), while an exploration
    // pulls the end effector away.
    let chord = (last - first).norm();
    if travel.min(chord) < s.min_motion {
        return Estimate {
            details: details.clone(),
            ..Estimate::unknown(format!(
                "too little motion: the fitted joint moves the end effector {travel:.4} m, which \
                 ends {chord:.4} m from where it began (need {} m of each)",
                s.min_motion
            ))
        };
    }
    let joint = match best.model {
        Model::Line { dir, .. } => {
            let d = dir.dot(&(last - first));
            let axis = if d < 0.0 { -dir } else { dir };
            JointEstimate::Prismatic {
                axis,
                distance: d.abs(),
            }
        }
        Model::Circle { center, normal, .. } => {
            let angle = swept_angle(&best.model, &positions, &inl);
            let axis = if angle < 0.0 { -normal } else { normal };
            let pivot = center + axis.into_inner() * axis.dot(&(i.contact_pre - center));
            JointEstimate::Revolute {
                axis,
                pivot,
                angle: angle.abs(),
            }
        }
    };
    Estimate {
        joint,
        moving: Vec::new(),
        part_points: Vec::new(),
        score,
        details,
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

fn position(pose: &Isometry3<f64>) -> Point3<f64> {
    Point3::from(pose.translation.vector)
}

/// The line through two poses' positions.
fn line_through(poses: &[Isometry3<f64>], idx: &[usize]) -> Option<Model> {
    let (a, b) = (position(&poses[idx[0]]), position(&poses[idx[1]]));
    let dir = Unit::try_new(b - a, 1e-9)?;
    Some(Model::Line {
        point: a,
        dir,
        grasp: poses[idx[0]].rotation,
    })
}

/// The circle through three poses' positions (`None` if they are nearly collinear).
fn circle_through(poses: &[Isometry3<f64>], idx: &[usize]) -> Option<Model> {
    let [a, b, c] = [0, 1, 2].map(|k| position(&poses[idx[k]]));
    let (u, v) = (b - a, c - a);
    let w = u.cross(&v);
    let w2 = w.norm_squared();
    if w2 < 1e-12 * u.norm_squared() * v.norm_squared() || w2 == 0.0 {
        return None;
    }
    let center = a + (v.cross(&w) * u.norm_squared() + w.cross(&u) * v.norm_squared()) / (2.0 * w2);
    let normal = Unit::new_normalize(w);
    let radius = (a - center).norm();
    let mut model = Model::Circle {
        center,
        normal,
        radius,
        grasp: UnitQuaternion::identity(),
    };
    let grasp = UnitQuaternion::from_axis_angle(&normal, -model.phase(&a)) * poses[idx[0]].rotation;
    if let Model::Circle { grasp: g, .. } = &mut model {
        *g = grasp;
    }
    Some(model)
}

/// The principal-axis line of the inlier positions, grasp = mean inlier orientation.
fn refine_line(poses: &[Isometry3<f64>], inl: &[usize]) -> Option<Model> {
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
fn refine_circle(
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
    let init = PoseCircle {
        center,
        axis: normal,
        offset: e1 * radius,
        grasp,
    };
    let phi: Vec<f64> = inl
        .iter()
        .map(|&k| model.phase(&position(&poses[k])))
        .collect();
    let sub: Vec<Isometry3<f64>> = inl.iter().map(|&k| poses[k]).collect();
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

/// Algebraic (Kåsa) circle fit refined by Gauss–Newton on the geometric distances.
fn fit_circle_2d(q: &[Vector2<f64>]) -> Option<(Vector2<f64>, f64)> {
    // Kåsa: x² + y² = 2 a x + 2 b y + c, linear least squares.
    let mut ata = Matrix3::zeros();
    let mut atb = Vector3::zeros();
    for p in q {
        let row = Vector3::new(2.0 * p.x, 2.0 * p.y, 1.0);
        ata += row * row.transpose();
        atb += row * p.norm_squared();
    }
    let sol = ata.try_inverse()? * atb;
    let mut center = Vector2::new(sol.x, sol.y);
    let r2 = sol.z + center.norm_squared();
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
