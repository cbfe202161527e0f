//! The covariance of the fused fit: the Gauss–Newton one and the cluster-robust (sandwich)
//! one, whichever is larger in every direction.

use std::collections::HashMap;

use nalgebra::{DMatrix, DVector};

use super::model::State;
use super::solve::Context;

impl Context<'_> {
    /// The covariance of the offsets at `state`, and the variance factor `ĉ ≥ 1` (the reduced
    /// χ² of the weighted residuals, the correspondences counted at their evidence).
    ///
    /// Two estimates, the larger taken in every direction ([`loewner_max`]):
    /// - **Gauss–Newton**, `ĉ (JᵀJ)⁻¹`: right when the residuals are independent with the
    ///   estimated noise levels (ĉ covers noise they understate).
    /// - **Cluster-robust sandwich**, `(JᵀJ)⁻¹ (Σ_c J_cᵀ r_c r_cᵀ J_c) (JᵀJ)⁻¹ · G/(G − 1)`
    ///   over `G` clusters: the correspondences of one τ-voxel (neighbouring points share
    ///   their surface's sampling and normal errors), each pose's 4 residuals, the coupling.
    ///   It measures the spread the residuals actually show, whatever their correlation or
    ///   misweighting within a cluster (Liang and Zeger 1986), and so what the weights of
    ///   the two sources get wrong.
    ///
    /// `None` when singular or not finite.
    pub(super) fn covariance(&self, state: &State) -> Option<(DMatrix<f64>, f64)> {
        let data = self.data(state);
        let r = self.residuals(state, &data);
        let k = state.parameters();
        let j = self.jacobian(state, &data, &r);
        let inv = (j.transpose() * &j).try_inverse()?;
        // Degrees of freedom with the correspondences counted at their evidence.
        let pairs = data.pairs.len();
        let n = pairs as f64 * data.fraction + (r.len() - pairs) as f64;
        let c_hat = if n > k as f64 + 1.0 {
            (r.norm_squared() / (n - k as f64)).max(1.0)
        } else {
            1.0
        };
        let gauss_newton = &inv * c_hat;
        // Clusters: the pairs' τ-voxels, then one per pose (4 rows) and the coupling.
        let mut cluster_of: Vec<usize> = Vec::with_capacity(r.len());
        let mut voxels: HashMap<[i64; 3], usize> = HashMap::new();
        for (s, _, _) in &data.pairs {
            let key: [i64; 3] = s.coords.map(|c| (c / self.tau).floor() as i64).into();
            let next = voxels.len();
            cluster_of.push(*voxels.entry(key).or_insert(next));
        }
        let mut g = voxels.len();
        while cluster_of.len() < r.len() {
            let rows = if r.len() - cluster_of.len() >= 4 {
                4
            } else {
                1
            };
            cluster_of.extend(std::iter::repeat_n(g, rows));
            g += 1;
        }
        let mut scores = vec![DVector::<f64>::zeros(k); g];
        for (row, &c) in cluster_of.iter().enumerate() {
            scores[c] += j.row(row).transpose() * r[row];
        }
        let meat: DMatrix<f64> = scores
            .iter()
            .map(|s| s * s.transpose())
            .sum::<DMatrix<f64>>();
        let small_sample = if g > 1 {
            g as f64 / (g as f64 - 1.0)
        } else {
            1.0
        };
        let sandwich = &inv * meat * &inv * small_sample;
        let cov = loewner_max(&gauss_newton, &sandwich).unwrap_or(gauss_newton);
        cov.iter().all(|v| v.is_finite()).then_some((cov, c_hat))
    }
}

/// The smallest covariance at least as large as `a` and as `b` in every direction along
/// `a`'s generalised eigenvectors: with `a = L Lᵀ` and `L⁻¹ b L⁻ᵀ = V Λ Vᵀ`,
/// `L V max(Λ, 1) Vᵀ Lᵀ`. `None` when `a` is not positive definite.
fn loewner_max(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let sym = |m: &DMatrix<f64>| (m + m.transpose()) * 0.5;
    let l = sym(a).cholesky()?.l();
    let l_inv = l.clone().try_inverse()?;
    let eig = sym(&(&l_inv * sym(b) * l_inv.transpose())).symmetric_eigen();
    let lambda = DMatrix::from_diagonal(&eig.eigenvalues.map(|v| v.max(1.0)));
    let v = &eig.eigenvectors;
    Some(sym(&(&l * v * lambda * v.transpose() * l.transpose())))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Loewner maximum of diag(1, 4) and diag(2, 1) is diag(2, 4); of a matrix with
    /// itself, the matrix.
    #[test]
    fn loewner_max_of_diagonals() {
        let a = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 4.0]));
        let b = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 1.0]));
        let m = loewner_max(&a, &b).unwrap();
        let expected = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 4.0]));
        assert!((m - expected).norm() < 1e-12);
        let c = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
        assert!((loewner_max(&c, &c).unwrap() - &c).norm() < 1e-12);
    }
}
