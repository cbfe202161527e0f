//! Replaying one step: the dense sweep, the occupancy before and after, the swept footprint.

use rayon::prelude::*;

use super::cells::{Cells, start_cell};
use super::{MAX_FOOTPRINT_SAMPLES, MAX_SWEEP_SAMPLES};
use crate::scene::collision::{Body, collisions_of};
use crate::scene::motion::max_displacement;
use crate::scene::nav::{occupancy, part_footprint};
use crate::scene::{JointId, PartId, SceneData, SceneModel, State, forward_kinematics};
use crate::task::Error;
use crate::task::goal::Problem;
use crate::task::plan::Step;
use crate::task::settings::TaskSettings;

/// The replay's fixed data and scratch.
pub(super) struct Replay<'a> {
    pub(super) model: &'a SceneModel,
    pub(super) settings: &'a TaskSettings,
    pub(super) radius: f64,
    pub(super) start: usize,
    pub(super) data: SceneData,
    pub(super) samples: usize,
}

/// The occupancy of one state: blocked cells and the cells connected to the start.
pub(super) struct Free {
    pub(super) cells: Cells,
    pub(super) connected: Vec<bool>,
}

impl<'a> Replay<'a> {
    pub(super) fn new(
        model: &'a SceneModel,
        problem: &Problem,
        settings: &'a TaskSettings,
    ) -> Result<Self, Error> {
        let mut data = SceneData::new(model);
        let start = start_cell(model, &mut data, problem)?;
        Ok(Replay {
            model,
            settings,
            radius: problem.robot.radius,
            start,
            data,
            samples: 0,
        })
    }

    fn name(&self, body: Body) -> String {
        match body {
            Body::Part(p) => format!("part {:?}", self.model.parts()[p.index()].name()),
            Body::Base(b) => format!("base shape {:?}", self.model.base().shapes[b.index()].name),
        }
    }

    /// Checks one step whose `from` matches the state; `Some(reason)` if it fails.
    pub(super) fn step(
        &mut self,
        state: &State,
        joint: JointId,
        s: &Step,
    ) -> Result<Option<String>, Error> {
        let (a, b) = (state.q[joint.index()], s.to);
        if let Some(why) = self.sweep(state, joint, a, b)? {
            return Ok(Some(why));
        }
        self.base_pose(state, joint, b, s)
    }

    /// Dense collision samples of the moving subtree from `a` to `b`.
    fn sweep(
        &mut self,
        state: &State,
        joint: JointId,
        a: f64,
        b: f64,
    ) -> Result<Option<String>, Error> {
        let travel = max_displacement(self.model, &mut self.data, state, joint, a, b)?;
        let spacing = self.settings.sweep.min_margin;
        let n = ((travel / spacing).ceil() as usize).clamp(1, MAX_SWEEP_SAMPLES);
        let (model, settings) = (self.model, &self.settings.sweep.collision);
        let part = &model.parts()[joint.index()];
        let (lo, hi) = (a.min(b), a.max(b));
        let value = |k: usize| {
            if k == n {
                b
            } else {
                (a + (b - a) * k as f64 / n as f64).clamp(lo, hi)
            }
        };
        // Samples are independent: check them in parallel, report the first colliding one.
        let first = (0..=n)
            .into_par_iter()
            .map_init(
                || (SceneData::new(model), state.clone()),
                |(data, sample), k| -> Result<Option<(usize, Body, Body)>, Error> {
                    sample.q[joint.index()] = value(k);
                    forward_kinematics(model, data, sample)?;
                    Ok(collisions_of(model, data, settings, part.id())?
                        .first()
                        .map(|c| (k, c.a, c.b)))
                },
            )
            .find_first(|r| !matches!(r, Ok(None)))
            .transpose()?
            .flatten();
        match first {
            None => {
                self.samples += n + 1;
                Ok(None)
            }
            Some((k, m, o)) => {
                self.samples += k + 1;
                Ok(Some(format!(
                    "moving joint {:?} from {a} to {b}: {} collides with {} at {} \
                     (dense sample {k} of {n})",
                    model.joints()[joint.index()].name,
                    self.name(m),
                    self.name(o),
                    value(k)
                )))
            }
        }
    }

    pub(super) fn free_at(&mut self, state: &State) -> Result<Free, Error> {
        forward_kinematics(self.model, &mut self.data, state)?;
        let cells = Cells::of(&occupancy(self.model, &self.data)?.inflate(self.radius)?);
        let connected = cells.reachable_from(self.start);
        Ok(Free { cells, connected })
    }

    /// The moving subtree's footprints at samples no more than half a cell of travel apart,
    /// inflated by `max(radius − resolution·√2, 0)`.
    pub(super) fn swept(&mut self, state: &State, joint: JointId, b: f64) -> Result<Cells, Error> {
        let a = state.q[joint.index()];
        let travel = max_displacement(self.model, &mut self.data, state, joint, a, b)?;
        let res = self.model.base_grid().resolution();
        let n = ((travel / (0.5 * res)).ceil() as usize).clamp(1, MAX_FOOTPRINT_SAMPLES);
        let mut grid = self.model.base_grid().cleared();
        let mut sample = state.clone();
        let subtree: Vec<PartId> = self.model.parts()[joint.index()].subtree().collect();
        for k in 0..=n {
            sample.q[joint.index()] = if k == n {
                b
            } else {
                (a + (b - a) * k as f64 / n as f64).clamp(a.min(b), a.max(b))
            };
            forward_kinematics(self.model, &mut self.data, &sample)?;
            for &p in &subtree {
                grid.union_with(&part_footprint(self.model, &self.data, p)?)?;
            }
        }
        let inflation = (self.radius - res * std::f64::consts::SQRT_2).max(0.0);
        Ok(Cells::of(&grid.inflate(inflation)?))
    }
}
