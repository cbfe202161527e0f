//! A computed stowed configuration: the most compact arm configuration that keeps clear of
//! itself and of the floor, for robots whose description gives none.

use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{PairSampling, RobotCollision, RobotConfig, RobotError, RobotModel};
use crate::InvalidSetting;

/// How [`RobotModel::with_computed_stow`] searches.
#[derive(Debug, Clone, PartialEq)]
pub struct StowSearch {
    /// Random arm configurations drawn within the limits (continuous joints within ±π) before
    /// the local descent. Default 3 000.
    pub samples: usize,
    /// Seed of the ChaCha8 generator of the samples. Default 0.
    pub seed: u64,
    /// Every joint moved by ± this (rad or m, one at a time) must leave the configuration free
    /// of self-collision too, so the stow is not pressed against a link. Default 0.05.
    pub perturbation: f64,
    /// Lowest height (m) of any arm link's shapes above the floor. Default 0.05.
    pub floor_clearance: f64,
}

impl Default for StowSearch {
    fn default() -> Self {
        StowSearch {
            samples: 3000,
            seed: 0,
            perturbation: 0.05,
            floor_clearance: 0.05,
        }
    }
}

/// Weight of the arm's height in a stow's cost, against its reach beyond the chassis: 1 m
/// lower is worth 0.1 m more reach outside the chassis.
const HEIGHT_WEIGHT: f64 = 0.1;

/// The checks a stow candidate must pass, and its cost.
struct Judge<'a> {
    robot: &'a RobotModel,
    /// [`RobotModel::base_radius`].
    base_radius: f64,
    collision: RobotCollision,
    search: &'a StowSearch,
}

impl Judge<'_> {
    /// The cost of `arm` as a stow when it is below `to_beat`, or `None` when it is not, or
    /// when `arm` (or a perturbation of it) touches itself or comes within the floor
    /// clearance: how far the footprint radius exceeds the chassis' own, plus
    /// [`HEIGHT_WEIGHT`] times the arm's highest point. The perturbations (two checks per
    /// joint) are checked last, only for a candidate that would be kept.
    fn cost(&self, arm: &DVector<f64>, to_beat: f64) -> Option<f64> {
        let poses = |q: &DVector<f64>| {
            self.robot.link_poses(&RobotConfig {
                base: [0.0; 3],
                arm: q.clone(),
            })
        };
        let at = poses(arm).ok()?;
        let (bottom, top) = self.collision.height_range(&at, 1);
        if bottom < self.search.floor_clearance || self.collision.self_collision(&at).is_some() {
            return None;
        }
        let outside = (self.robot.footprint_at(arm) - self.base_radius).max(0.0);
        let cost = outside + HEIGHT_WEIGHT * top.max(0.0);
        if cost >= to_beat {
            return None;
        }
        let mut moved = arm.clone();
        for (i, joint) in self.robot.joints.iter().enumerate() {
            for delta in [-self.search.perturbation, self.search.perturbation] {
                moved[i] = (arm[i] + delta).clamp(joint.lower, joint.upper);
                let free = poses(&moved)
                    .ok()
                    .is_some_and(|p| self.collision.self_collision(&p).is_none());
                moved[i] = arm[i];
                if !free {
                    return None;
                }
            }
        }
        Some(cost)
    }
}

impl RobotModel {
    /// This robot with a computed stowed configuration as [`RobotModel::neutral`]: among
    /// [`StowSearch::samples`] random arm configurations and then a coordinate descent from
    /// the best (steps of 0.4, 0.2, 0.1 and 0.05 per joint), the most compact one that is free
    /// of self-collision, stays so with every joint moved by [`StowSearch::perturbation`], and
    /// keeps the arm links [`StowSearch::floor_clearance`] above the floor. Compact: the arm
    /// reaches as little as possible beyond the chassis' own footprint radius and, within it,
    /// stays low (the cost is the reach beyond the chassis plus a tenth of the arm's highest
    /// point, so 1 m lower is worth 0.1 m more reach). The current neutral configuration is a candidate too. For robots
    /// whose description gives no stow (an SRDF's stow group state comes first, see
    /// [`RobotModel::with_srdf`]).
    ///
    /// Self-collision is judged with [`RobotModel::allowed_pairs`] when the robot has them,
    /// else with the adjacent pairs and those touching in 95 % of random configurations
    /// ([`RobotModel::with_sampled_pairs`] without the pairs touching at the neutral
    /// configuration, which may itself be the collision being avoided).
    ///
    /// # Errors
    /// [`RobotError::InvalidSetting`] for no samples or a negative or non-finite
    /// perturbation or clearance; [`RobotError::NoStow`] when no candidate passes.
    pub fn with_computed_stow(self, search: &StowSearch) -> Result<RobotModel, RobotError> {
        for (what, value) in [
            ("stow search perturbation", search.perturbation),
            ("stow search floor clearance", search.floor_clearance),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(InvalidSetting::new(what, value, "finite and >= 0").into());
            }
        }
        if search.samples == 0 {
            return Err(InvalidSetting::new("stow search samples", 0.0, "at least 1").into());
        }
        let judged = match self.allowed_pairs() {
            Some(_) => self.clone(),
            None => {
                let pairs = self.sampled_pairs(&PairSampling::default(), false)?;
                self.clone().with_allowed_pairs(pairs)?
            }
        };
        let judge = Judge {
            robot: &self,
            base_radius: self.base_radius(),
            collision: RobotCollision::new(&judged)?,
            search,
        };
        let mut best: Option<(f64, DVector<f64>)> = judge
            .cost(&self.neutral, f64::INFINITY)
            .map(|f| (f, self.neutral.clone()));
        let mut rng = ChaCha8Rng::seed_from_u64(search.seed);
        let mut q = DVector::zeros(self.dof());
        for _ in 0..search.samples {
            for (value, joint) in q.iter_mut().zip(&self.joints) {
                let (lo, hi) = finite_range(joint.lower, joint.upper);
                *value = if hi > lo {
                    rng.random_range(lo..=hi)
                } else {
                    lo
                };
            }
            let to_beat = best.as_ref().map_or(f64::INFINITY, |(b, _)| *b);
            if let Some(f) = judge.cost(&q, to_beat) {
                best = Some((f, q.clone()));
            }
        }
        let Some((mut cost, mut stow)) = best else {
            return Err(RobotError::NoStow {
                samples: search.samples,
            });
        };
        for step in [0.4, 0.2, 0.1, 0.05] {
            let mut improved = true;
            while improved {
                improved = false;
                for i in 0..self.dof() {
                    let (lo, hi) = finite_range(self.joints[i].lower, self.joints[i].upper);
                    for delta in [-step, step] {
                        let mut trial = stow.clone();
                        trial[i] = (stow[i] + delta).clamp(lo, hi);
                        if let Some(f) = judge.cost(&trial, cost - 1e-9) {
                            (cost, stow) = (f, trial);
                            improved = true;
                        }
                    }
                }
            }
        }
        self.with_neutral(&stow)
    }
}

/// The joint's range, continuous joints within ±π.
fn finite_range(lower: f64, upper: f64) -> (f64, f64) {
    if lower.is_finite() && upper.is_finite() {
        (lower, upper)
    } else {
        (-std::f64::consts::PI, std::f64::consts::PI)
    }
}
