//! The joint likelihood of the clouds and the path, and its weighted nonlinear least squares
//! (Levenberg–Marquardt with re-association of correspondences and pose outliers).

use std::collections::HashSet;

use nalgebra::{DMatrix, DVector, Point3, Vector3};

use super::FusedSettings;
use super::model::{PathPose, State};
use crate::articulation::icp::NormalCache;
use crate::articulation::kdtree::KdTree;

/// Everything the likelihood needs that does not change during the fit.
pub(super) struct Context<'a> {
    pub(super) settings: &'a FusedSettings,
    /// The part points the clouds register (pre pose): the likelihood's cloud term.
    pub(super) sample: &'a [Point3<f64>],
    /// The points that may be evidence of the motion (pre pose): the fit's correspondences
    /// are those of them that the motion moves off their surface and explains (see
    /// [`Self::data`]).
    pub(super) candidates: &'a [Point3<f64>],
    /// The depth noise σ_d (m).
    pub(super) sigma_d: f64,

    pub(super) post: &'a [Point3<f64>],
    pub(super) post_tree: &'a KdTree,
    pub(super) normals: &'a NormalCache<'a>,
    /// The correspondence limit τ (m).
    pub(super) tau: f64,
    /// The weight of one squared point-to-plane residual (m⁻²): `n_eff / (N · 2σ_d²)`, the
    /// part's evidence counted in independent τ-voxels `n_eff` rather than points `N`.
    pub(super) cloud_weight: f64,
    /// The largest point-to-plane residual of a correspondence (m): 3 σ of the difference
    /// of two depth measurements, `3 √2 σ_d`.
    pub(super) pair_gate: f64,
    pub(super) poses: &'a [PathPose],
    pub(super) sigma_p: f64,
    pub(super) sigma_o: f64,
    /// The poses averaged for the path's travel at its start and end.
    pub(super) ends: usize,
    pub(super) contact: Point3<f64>,
}

/// The data of one outer iteration: the cloud correspondences and the inlier poses.
pub(super) struct Data {
    pub(super) pairs: Vec<(Point3<f64>, Point3<f64>, Vector3<f64>)>,
    pub(super) poses: Vec<PathPose>,
    /// The weight of one squared point-to-plane residual in this iteration (m⁻²).
    cloud_weight: f64,
    /// How much of one independent residual a correspondence is worth: the occupied
    /// τ-voxels of the correspondences over their number.
    pub(super) fraction: f64,
}

impl Context<'_> {
    /// The correspondences under `state`'s motion and the poses whose block χ² is below the
    /// outlier limit (or 9 times the median block's, whichever is larger: a poor start keeps
    /// its poses).
    ///
    /// A candidate point is a correspondence when the motion and the static scene predict
    /// different measurements of it and the motion's is the one seen: its moved position has
    /// a post point within τ with a surface normal `n`, the residual `n · (T s − q)` is within
    /// the gate (3 σ of the difference of two depth measurements), the motion moves it off
    /// that surface by at least twice the gate (`a = |n · (T s − s)|`: a point the motion
    /// leaves on its surface, near a hinge or sliding along itself, cannot tell the two
    /// apart), and the static scene explains it worse (no post point within τ of where it
    /// was, or a larger point-to-plane residual there: a static surface in the segment is
    /// left out).
    ///
    /// Why twice: with `e` the difference of the two depth noises along `n`, the motion's
    /// residual is `e` and the static one `e − a` where the moved surface is also the nearest
    /// one to where the point was, so the comparison keeps `e < a/2` only. Below `a = 2 ·
    /// gate` that cuts the distribution of `e` on one side inside the gate: the kept points'
    /// noise is biased against the motion and the fit makes the travel short (by 0.7° on
    /// average and up to 2° on a small door opened 10°, with a pivot 3 cm off along the door).
    /// From `a = 2 · gate` on, `a/2` is the gate and the comparison cuts nothing the
    /// symmetric gate keeps.
    pub(super) fn data(&self, state: &State) -> Data {
        let motion = state.motion();
        let pairs: Vec<(Point3<f64>, Point3<f64>, Vector3<f64>)> = self
            .candidates
            .iter()
            .filter_map(|s| {
                let m = motion * s;
                let (j, _) = self.post_tree.nearest(&m, self.tau)?;
                let n = self.normals.normal(j)?;
                let moved = n.dot(&(m - self.post[j])).abs();
                let off_surface = n.dot(&(m - s)).abs();
                (moved <= self.pair_gate
                    && off_surface >= 2.0 * self.pair_gate
                    && moved < self.static_residual(s))
                .then_some((*s, self.post[j], n))
            })
            .collect();
        // Fewer correspondences than a segmented part needs are no evidence (what the motion
        // moves off its surface by more than the gate is then a sliver: an edge, a handle).
        let mut pairs = pairs;
        if pairs.len() < self.settings.two_view.min_part_points {
            pairs.clear();
        }
        // The selected points' evidence in independent τ-voxels.
        let voxels: HashSet<[i64; 3]> = pairs
            .iter()
            .map(|(s, _, _)| s.coords.map(|c| (c / self.tau).floor() as i64).into())
            .collect();
        let fraction = voxels.len() as f64 / pairs.len().max(1) as f64;
        // Variance component: residuals larger than the depth noise explains (segmentation,
        // sampling) lower the clouds' weight; the plane noise is the floor.
        let ms = pairs
            .iter()
            .map(|(s, q, n)| n.dot(&(motion * s - q)).powi(2))
            .sum::<f64>()
            / pairs.len().max(1) as f64;
        let cloud_weight =
            (fraction / (2.0 * self.sigma_d * self.sigma_d)).min(fraction / ms.max(1e-12));
        let chi2: Vec<f64> = self
            .poses
            .iter()
            .map(|p| self.pose_chi2(state, p))
            .collect();
        let mut sorted = chi2.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        let limit = self.settings.pose_outlier_chi2.max(9.0 * median);
        let poses = self
            .poses
            .iter()
            .zip(&chi2)
            .filter(|(_, c)| **c <= limit)
            .map(|(p, _)| *p)
            .collect();
        Data {
            pairs,
            poses,
            cloud_weight,
            fraction,
        }
    }

    /// The point-to-plane residual of `s` against the post cloud where it was (∞ without a
    /// post point within τ or its normal).
    fn static_residual(&self, s: &Point3<f64>) -> f64 {
        self.post_tree
            .nearest(s, self.tau)
            .and_then(|(j, _)| Some(self.normals.normal(j)?.dot(&(s - self.post[j])).abs()))
            .unwrap_or(f64::INFINITY)
    }

    fn pose_chi2(&self, state: &State, p: &PathPose) -> f64 {
        let r = state.pose_residuals(p, self.sigma_p, self.sigma_o);
        r.iter().map(|v| v * v).sum()
    }

    /// The travel-coupling residual: the path's travel from its first to its last `ends`
    /// poses against the state's, over its standard deviation; `None` when not coupled.
    pub(super) fn coupling(&self, state: &State) -> Option<f64> {
        let n = self.poses.len();
        if !self.settings.couple_travel || n < 2 * self.ends || self.ends == 0 {
            return None;
        }
        let path = state.path_travel(&self.poses[..self.ends], &self.poses[n - self.ends..]);
        // Each end is a mean of `ends` positions: σ_p / √ends per axis, along the path.
        let sd = (2.0 / self.ends as f64).sqrt() * self.sigma_p / state.travel_scale();
        let r = (path - state.travel) / sd;
        r.is_finite().then_some(r)
    }

    /// The weighted residuals of `state` on `data`.
    pub(super) fn residuals(&self, state: &State, data: &Data) -> DVector<f64> {
        let motion = state.motion();
        let w = data.cloud_weight.sqrt();
        let mut r: Vec<f64> = data
            .pairs
            .iter()
            .map(|(s, q, n)| w * n.dot(&(motion * s - q)))
            .collect();
        for p in &data.poses {
            r.extend(state.pose_residuals(p, self.sigma_p, self.sigma_o));
        }
        r.extend(self.coupling(state));
        DVector::from_vec(r)
    }

    /// The forward-difference Jacobian of [`Self::residuals`] in the state's offsets.
    pub(super) fn jacobian(&self, state: &State, data: &Data, r: &DVector<f64>) -> DMatrix<f64> {
        let k = state.parameters();
        let h = 1e-7;
        let mut j = DMatrix::zeros(r.len(), k);
        for col in 0..k {
            let mut d = vec![0.0; k];
            d[col] = h;
            let moved = self.residuals(&state.perturbed(&d, &self.contact), data);
            if moved.len() == r.len() {
                j.set_column(col, &((moved - r) / h));
            }
        }
        j
    }

    /// Levenberg–Marquardt on fixed `data` from `state`.
    fn lm(&self, mut state: State, data: &Data) -> State {
        let mut r = self.residuals(&state, data);
        let mut cost = r.norm_squared();
        let mut lambda = 1e-3;
        for _ in 0..self.settings.lm_iterations {
            let j = self.jacobian(&state, data, &r);
            let h = j.transpose() * &j;
            let g = j.transpose() * &r;
            let mut improved = false;
            while lambda < 1e10 {
                let mut a = h.clone();
                for i in 0..a.nrows() {
                    a[(i, i)] += lambda * h[(i, i)].max(1e-12);
                }
                let Some(step) = a.cholesky().map(|c| c.solve(&(-&g))) else {
                    lambda *= 10.0;
                    continue;
                };
                let candidate = state.perturbed(step.as_slice(), &self.contact);
                let rc = self.residuals(&candidate, data);
                let c = rc.norm_squared();
                if c.is_finite() && c < cost && rc.len() == r.len() {
                    let converged = cost - c < 1e-9 * cost;
                    (state, r, cost) = (candidate, rc, c);
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = !converged;
                    break;
                }
                lambda *= 4.0;
            }
            if !improved {
                break;
            }
        }
        state
    }

    /// The outer iterations from `state`: re-associate, then Levenberg–Marquardt.
    pub(super) fn fit(&self, mut state: State) -> State {
        for _ in 0..self.settings.outer_iterations {
            let data = self.data(&state);
            state = self.lm(state, &data);
        }
        state
    }

    /// `−2 log L` up to a constant shared by both joint models: every sample point's squared
    /// point-to-plane residual truncated at τ (τ² for a point without a correspondence),
    /// weighted; every pose's block χ² truncated at the outlier limit; the coupling's square.
    pub(super) fn cost(&self, state: &State) -> f64 {
        let [cloud, poses, coupling] = self.cost_terms(state);
        cloud + poses + coupling
    }

    /// The cloud, pose and coupling terms of [`Self::cost`].
    pub(super) fn cost_terms(&self, state: &State) -> [f64; 3] {
        let motion = state.motion();
        let tau2 = self.tau * self.tau;
        let cloud: f64 = self
            .sample
            .iter()
            .map(|s| {
                let m = motion * s;
                match self.post_tree.nearest(&m, self.tau) {
                    Some((j, d)) => match self.normals.normal(j) {
                        Some(n) => n.dot(&(m - self.post[j])).powi(2),
                        None => d * d,
                    },
                    None => tau2,
                }
                .min(tau2)
            })
            .sum();
        let limit = self.settings.pose_outlier_chi2;
        let poses: f64 = self
            .poses
            .iter()
            .map(|p| self.pose_chi2(state, p).min(limit))
            .sum();
        let coupling = self.coupling(state).map_or(0.0, |r| r * r);
        [self.cloud_weight * cloud, poses, coupling]
    }
}
