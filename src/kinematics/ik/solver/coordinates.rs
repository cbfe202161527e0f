//! The step's variables one by one: their bounds, the clamp into the joint limits (with
//! unlimited angles wrapped round a centre), and random restarts within the limits.

use std::f64::consts::PI;

use kinscene_pinocchio::JointKind;
use nalgebra::DVector;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::IkSolver;
use crate::kinematics::ik::step::StepQpData;

/// How a velocity coordinate's configuration behaves under a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Coordinate {
    /// A revolute or prismatic coordinate `q[idx_q]` within `[lower, upper]` (either may be
    /// infinite, but not both for a revolute joint).
    Scalar {
        idx_q: usize,
        lower: f64,
        upper: f64,
    },
    /// A revolute coordinate `q[idx_q]` without limits: kept within π of the seed's value.
    Angle { idx_q: usize },
    /// A `(cos, sin)` pair or planar block: unbounded, moved by Pinocchio's `integrate`.
    Manifold,
}

impl IkSolver {
    /// `qp.lower ≤ dq ≤ qp.upper`: the joint limits relative to q, intersected with
    /// ±max_step, for the step's variables.
    pub(super) fn step_bounds(&self, q: &DVector<f64>, qp: &mut StepQpData) {
        let max_step = self.settings.max_step;
        for (k, &i) in self.support_v.iter().enumerate() {
            let (lo, hi) = match self.coordinates[i] {
                Coordinate::Scalar {
                    idx_q,
                    lower,
                    upper,
                } => (
                    (lower - q[idx_q]).max(-max_step),
                    (upper - q[idx_q]).min(max_step),
                ),
                Coordinate::Angle { .. } | Coordinate::Manifold => (-max_step, max_step),
            };
            // q is within its limits (clamped), so lo ≤ 0 ≤ hi; max/min keep that exact.
            qp.lower[k] = lo.min(0.0);
            qp.upper[k] = hi.max(0.0);
        }
    }

    /// Clamps scalar coordinates into their limits and, given a `centre` configuration, wraps
    /// unlimited angles into `[c − π, c + π)` around the centre's value c.
    pub(super) fn clamp(&self, q: &mut DVector<f64>, centre: Option<&DVector<f64>>) {
        for c in &self.coordinates {
            match *c {
                Coordinate::Scalar {
                    idx_q,
                    lower,
                    upper,
                } => q[idx_q] = q[idx_q].clamp(lower, upper),
                Coordinate::Angle { idx_q } => {
                    if let Some(c) = centre {
                        q[idx_q] = c[idx_q] + wrap_angle(q[idx_q] - c[idx_q]);
                    }
                }
                Coordinate::Manifold => {}
            }
        }
    }

    /// `seed` with the joints that move the frame drawn at random within their limits.
    pub(super) fn random_configuration(
        &self,
        seed: &DVector<f64>,
        rng: &mut ChaCha8Rng,
    ) -> DVector<f64> {
        let mut q = seed.clone();
        for &j in &self.support {
            let joint = &self.model.joints()[j];
            let i = joint.idx_q;
            let (lower, upper) = joint
                .limits
                .position
                .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
            match joint.kind {
                JointKind::Revolute { .. } => {
                    let lo = if lower.is_finite() {
                        lower
                    } else if upper.is_finite() {
                        upper - 2.0 * PI
                    } else {
                        seed[i] - PI
                    };
                    let hi = upper.min(lo + 2.0 * PI);
                    q[i] = if lo < hi {
                        rng.random_range(lo..hi)
                    } else {
                        lo
                    };
                }
                JointKind::Prismatic { .. } => {
                    if lower.is_finite() && upper.is_finite() && lower < upper {
                        q[i] = rng.random_range(lower..upper);
                    }
                }
                JointKind::RevoluteUnbounded { .. } => {
                    let (sin, cos) = rng.random_range(-PI..PI).sin_cos();
                    q[i] = cos;
                    q[i + 1] = sin;
                }
                JointKind::Planar => {
                    let (sin, cos) = rng.random_range(-PI..PI).sin_cos();
                    q[i + 2] = cos;
                    q[i + 3] = sin;
                }
            }
        }
        q
    }
}

/// `angle` wrapped into [−π, π).
fn wrap_angle(angle: f64) -> f64 {
    (angle + PI).rem_euclid(2.0 * PI) - PI
}
