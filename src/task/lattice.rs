//! The finite lattice of joint values the search moves on.

use super::goal::Problem;
use super::settings::LatticeSettings;
use crate::scene::{JointId, SceneModel};

/// Values closer than this (rad or m) are merged.
const MERGE: f64 = 1e-9;

/// The lattice L = L_1 × … × L_n: for each joint a finite, sorted set of values.
///
/// `L_j` contains: the start value; the lower and upper limits; 0 clamped into the limits
/// (the "closed" value); for a goal joint the point of its target interval nearest to the
/// start value, and for an exact target (interval narrower than 1e-2) its midpoint;
/// and [`LatticeSettings::interior_values`] evenly spaced interior values. Values within 1e-9
/// of each other are merged (keeping the first in that order). A state of the search assigns
/// each joint one value of its `L_j`; an action moves one joint to another value of its `L_j`.
#[derive(Debug, Clone, PartialEq)]
pub struct Lattice {
    values: Vec<Vec<f64>>,
}

impl Lattice {
    /// The lattice of `problem` on `model`.
    pub fn new(model: &SceneModel, problem: &Problem, settings: &LatticeSettings) -> Self {
        let values = model
            .joints()
            .iter()
            .enumerate()
            .map(|(k, j)| {
                let (lo, hi) = (j.limits.lower, j.limits.upper);
                let start = problem.start.as_slice()[k];
                let mut v = vec![start, lo, hi, j.limits.clamp(0.0)];
                if let Some(t) = problem.goal.target(JointId(k)) {
                    v.push(t.nearest(start));
                    if t.max - t.min < 1e-2 {
                        v.push(0.5 * (t.min + t.max));
                    }
                }
                let n = settings.interior_values;
                for i in 1..=n {
                    v.push(lo + (hi - lo) * i as f64 / (n + 1) as f64);
                }
                let mut out: Vec<f64> = Vec::with_capacity(v.len());
                for x in v {
                    if !out.iter().any(|y| (x - y).abs() <= MERGE) {
                        out.push(x);
                    }
                }
                out.sort_by(f64::total_cmp);
                out
            })
            .collect();
        Lattice { values }
    }

    /// The values of `joint`, ascending.
    pub fn values(&self, joint: JointId) -> &[f64] {
        &self.values[joint.index()]
    }

    /// The index of `value` in `joint`'s values (within 1e-9), if present.
    pub fn index_of(&self, joint: JointId, value: f64) -> Option<usize> {
        self.values
            .get(joint.index())?
            .iter()
            .position(|v| (v - value).abs() <= MERGE)
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether the model has no joints.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Number of lattice states (product of the set sizes), as a float (it overflows `u64`
    /// quickly).
    pub fn state_count(&self) -> f64 {
        self.values.iter().map(|v| v.len() as f64).product()
    }
}
