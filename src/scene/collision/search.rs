//! The adaptive interval search behind [`check_joint_motion`](super::check_joint_motion).

use std::ops::Range;

use nalgebra::Isometry3;

use super::geometry::Placed;
use super::query::{Clearance, Contact, Placement, clearance};
use super::settings::{Body, SweepSettings};
use super::sweep::{InconclusiveReason, SweepStatus};
use crate::scene::SceneModel;
use crate::scene::ids::PartId;
use crate::scene::kinematics::JointAxis;

/// An early end of the search: a collision, or the budget ran out.
type Stop = SweepStatus;

/// A joint value and the lower bound `ℓ` on the clearance there.
type Sample = (f64, f64);

pub(super) struct Search<'m> {
    pub model: &'m SceneModel,
    pub settings: &'m SweepSettings,
    pub axis: JointAxis,
    /// The joint value at which `world_from_moving` and `fixed` were computed.
    pub theta0: f64,
    pub lipschitz: f64,
    /// Part ids (indices) of the moving subtree.
    pub moving: Range<usize>,
    pub world_from_moving: Vec<Isometry3<f64>>,
    pub fixed: Placement<'m>,
    pub pairs: Vec<(PartId, Body)>,
    /// Pairs whose sphere gap exceeds this are not computed exactly (their gap is enough).
    pub cutoff: f64,
    pub samples: usize,
    /// End of the certified-free prefix `[a, free_until]`.
    pub free_until: Option<f64>,
    /// Whether every interval so far was certified (the free prefix is still growing).
    pub contiguous: bool,
    /// First finest interval that could not be certified: (nearer end, travel across it).
    pub unresolved: Option<(f64, f64)>,
}

impl Search<'_> {
    fn c(&self) -> f64 {
        self.settings.collision.contact_distance
    }

    pub(super) fn run(&mut self, a: f64, b: f64) -> SweepStatus {
        if self.pairs.is_empty() {
            self.free_until = Some(b);
            return SweepStatus::Free;
        }
        let travel = self.lipschitz * (b - a).abs();
        let n = (travel / (2.0 * self.settings.margin)).ceil().max(1.0);
        if n + 1.0 > self.settings.max_samples as f64 {
            return self.inconclusive(a, InconclusiveReason::SampleBudget, travel);
        }
        let n = n as usize;
        let h = (b - a) / n as f64;
        self.cutoff = self.c() + self.lipschitz * h.abs();
        match self.search(a, b, n, h) {
            Err(stop) => stop,
            Ok(()) => match self.unresolved {
                Some((at, travel)) => self.inconclusive(at, InconclusiveReason::Resolution, travel),
                None => SweepStatus::Free,
            },
        }
    }

    fn search(&mut self, a: f64, b: f64, n: usize, h: f64) -> Result<(), Stop> {
        let mut prev = (a, self.sample(a)?);
        if prev.1 <= self.c() {
            return Err(self.collision(a));
        }
        self.free_until = Some(a);
        for k in 1..=n {
            let t = if k == n { b } else { a + k as f64 * h };
            let next = (t, self.sample(t)?);
            self.refine(prev, next)?;
            prev = next;
        }
        Ok(())
    }

    /// Certifies `(s, e]`, records it as unresolved, or stops at a collision in it.
    /// Requires `ℓ(s) > c`.
    fn refine(&mut self, (s, ls): Sample, (e, le): Sample) -> Result<(), Stop> {
        let c = self.c();
        let travel = self.lipschitz * (e - s).abs();
        if le > c && ls + le - travel > 2.0 * c {
            if self.contiguous {
                self.free_until = Some(e);
            }
            return Ok(());
        }
        let mid = 0.5 * (s + e);
        let splittable = mid != s && mid != e;
        if travel <= 2.0 * self.settings.min_margin || !splittable {
            if le <= c {
                return Err(self.collision(e));
            }
            self.contiguous = false;
            if self.unresolved.is_none() {
                self.unresolved = Some((if ls <= le { s } else { e }, travel));
            }
            return Ok(());
        }
        let lm = self.sample(mid)?;
        self.refine((s, ls), (mid, lm))?;
        self.refine((mid, lm), (e, le))
    }

    /// Clearance of every checked pair at `theta` with the given cutoff.
    fn clearances(&self, theta: f64, cutoff: f64) -> Vec<(PartId, Body, Clearance)> {
        let motion = self.axis.displacement(theta - self.theta0);
        let placed: Vec<Vec<Placed<'_>>> = self
            .moving
            .clone()
            .zip(&self.world_from_moving)
            .map(|(m, pose)| {
                let pose = motion * pose;
                self.model.geometry.parts[m]
                    .iter()
                    .map(|s| Placed::new(s, &pose))
                    .collect()
            })
            .collect();
        self.pairs
            .iter()
            .map(|&(m, b)| {
                let mine = &placed[m.index() - self.moving.start];
                (m, b, clearance(mine, self.fixed.body(b), cutoff))
            })
            .collect()
    }

    /// A lower bound `ℓ(theta) <= D(theta)`, exact when `<= cutoff`; counts against the budget.
    fn sample(&mut self, theta: f64) -> Result<f64, Stop> {
        if self.samples >= self.settings.max_samples {
            return Err(self.inconclusive(theta, InconclusiveReason::SampleBudget, 0.0));
        }
        self.samples += 1;
        Ok(self
            .clearances(theta, self.cutoff)
            .iter()
            .map(|(_, _, c)| c.lower)
            .fold(f64::INFINITY, f64::min))
    }

    /// Pairs with exact distance `<= threshold` at `theta`, nearest first.
    fn contacts(&self, theta: f64, threshold: f64) -> Vec<Contact> {
        let mut out: Vec<Contact> = self
            .clearances(theta, threshold)
            .into_iter()
            .filter(|(_, _, c)| c.exact <= threshold)
            .map(|(m, b, c)| Contact {
                a: Body::Part(m),
                b,
                distance: c.exact,
            })
            .collect();
        out.sort_by(|x, y| x.distance.total_cmp(&y.distance));
        out
    }

    fn collision(&self, value: f64) -> Stop {
        SweepStatus::Collision {
            value,
            contacts: self.contacts(value, self.c()),
        }
    }

    fn inconclusive(&self, value: f64, reason: InconclusiveReason, travel: f64) -> Stop {
        SweepStatus::Inconclusive {
            value,
            nearest: self.contacts(value, self.c() + travel.max(self.settings.margin)),
            reason,
        }
    }
}
