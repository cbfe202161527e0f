//! The MLESAC score of a model: a Gaussian-inlier / uniform-outlier mixture, its weight by EM.

use std::f64::consts::PI;

use nalgebra::Isometry3;

use super::model::Model;
use super::{OrientationModel, ProprioceptiveSettings};

/// Likelihood terms of the inlier/outlier mixture.
pub(super) struct Likelihood {
    sigma: f64,
    sigma_rot: f64,
    orientation: OrientationModel,
    outlier: f64,
}

impl Likelihood {
    pub(super) fn new(s: &ProprioceptiveSettings) -> Self {
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
    pub(super) fn evaluate(&self, model: &Model, poses: &[Isometry3<f64>]) -> (f64, Vec<f64>) {
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
