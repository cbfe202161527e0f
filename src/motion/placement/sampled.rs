//! The paper's base placement: sample base poses around the part, keep the one from which the
//! most waypoints are reached.

use std::f64::consts::PI;

use nalgebra::{DVector, Point2, Vector2};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::estimate::execution_time;
use super::manipulation::{Cutoff, Prepared};
use super::plan::ManipulationPlan;
use super::{ManipulationSettings, PlacementError, PlacementObjective, SamplingSettings, TieBreak};
use crate::kinematics::robot::{Exempt, RobotConfig};
use crate::scene::collision::Body;

/// What the sampler found.
#[derive(Debug, Clone)]
pub(crate) struct SampleResult {
    /// The best plans, best first, at most [`SamplingSettings::keep`]; empty if every sample
    /// collided.
    pub ranked: Vec<ManipulationPlan>,
    /// Base poses drawn.
    pub drawn: usize,
    /// Of those, rejected because the base links collide.
    pub rejected: usize,
    /// A fallback base pose when every sample collided: `robot_from`, facing the centroid.
    pub fallback: [f64; 3],
    /// Why sampling stopped early, if it did.
    pub stopped: Option<Stop>,
}

/// Why the sampler stopped before evaluating `samples` base poses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stop {
    /// [`SamplingSettings::budget`] ran out.
    Budget,
    /// The cancel flag was raised.
    Cancelled,
}

/// `angle` wrapped into `(-π, π]`.
pub(crate) fn wrap(angle: f64) -> f64 {
    let a = angle.rem_euclid(2.0 * PI);
    if a > PI { a - 2.0 * PI } else { a }
}

/// The sampling region of [`SamplingSettings`]: the trajectory's horizontal centroid, the front
/// direction, and the radial range.
pub(crate) fn region(
    prepared: &Prepared<'_>,
    robot_from: [f64; 2],
    settings: &SamplingSettings,
) -> (Point2<f64>, Vector2<f64>, [f64; 2]) {
    let grasps = &prepared.motion.grasps;
    let n = grasps.len() as f64;
    let centroid = grasps
        .iter()
        .fold(Vector2::zeros(), |s, g| s + g.position.coords.xy())
        / n;
    let normal = grasps
        .iter()
        .fold(Vector2::zeros(), |s, g| s - g.approach.into_inner().xy())
        / n;
    let towards_robot = Vector2::from(robot_from) - centroid;
    let front = if normal.norm() >= 0.1 {
        normal.normalize()
    } else if towards_robot.norm() > 1e-9 {
        towards_robot.normalize()
    } else {
        Vector2::x()
    };
    let robot = prepared.problem.robot;
    let distance = settings.distance.unwrap_or_else(|| {
        let r = robot.base().footprint_radius + 0.05;
        [r, r + 0.6 * prepared.reach.length]
    });
    (Point2::from(centroid), front, distance)
}

/// Draws base poses, rejects those outside the scene's navigation grid (no base path ends
/// there) or whose base links collide with the scene at any waypoint (the parts at the
/// current state and the moving part along its motion), and plans the
/// manipulation from the others until `settings.samples` were evaluated or `max_draws` drawn
/// (the robot's current pose `robot_from` first, when `current_pose` is set, outside that
/// count); keeps the plan with the most waypoints reached (or, for
/// [`PlacementObjective::LongestPrefix`], the longest reached prefix), then the lowest cost of
/// [`SamplingSettings::tie_break`] (the arm starting from `stow`, or `seed` without one),
/// then the earliest; the
/// [`SamplingSettings::keep`] best are kept in that order.
pub(crate) fn sample(
    prepared: &Prepared<'_>,
    robot_from: [f64; 3],
    seed: &DVector<f64>,
    stow: Option<&DVector<f64>>,
    sampling: &SamplingSettings,
    manipulation: &ManipulationSettings,
) -> Result<SampleResult, PlacementError> {
    let here = [robot_from[0], robot_from[1]];
    let (centroid, front, [r_min, r_max]) = region(prepared, here, sampling);
    let front_angle = front.y.atan2(front.x);
    let mut rng = ChaCha8Rng::seed_from_u64(sampling.seed);
    let towards = centroid - Point2::from(here);
    let fallback = [robot_from[0], robot_from[1], towards.y.atan2(towards.x)];
    let arm_start = stow.unwrap_or(seed);
    let cost = |plan: &ManipulationPlan| match sampling.tie_break {
        TieBreak::ExecutionTime => {
            execution_time(prepared.problem.robot, robot_from, arm_start, plan)
        }
        TieBreak::PathLength => {
            let d = (Vector2::new(plan.base[0], plan.base[1]) - Vector2::from(here)).norm();
            plan.path_length() + sampling.distance_weight * d
        }
    };
    let keep = sampling.keep.max(1);
    let mut best: Vec<(usize, f64, ManipulationPlan)> = Vec::with_capacity(keep + 1);
    let (mut drawn, mut rejected) = (0, 0);
    let mut stopped = None;
    // The parts met are recorded by `prepared` (`Prepared::met_parts`).
    let consider = |base: [f64; 3],
                    best: &mut Vec<(usize, f64, ManipulationPlan)>|
     -> Result<bool, PlacementError> {
        let grid = prepared.problem.model.base_grid();
        if grid.cell_of(Point2::new(base[0], base[1])).is_none() {
            return Ok(false);
        }
        let stowed = match stow {
            Some(q) => stow_collides(prepared, base, q, manipulation.margin)?,
            None => None,
        };
        if let Some(body) = base_collides(prepared, base, seed, sampling.base_margin)?.or(stowed) {
            prepared.note(body);
            return Ok(false);
        }
        let (cutoff, reached): (Cutoff, fn(&ManipulationPlan) -> usize) = match sampling.objective {
            PlacementObjective::MostReached => (
                Cutoff::Reached(best.first().map_or(0, |b| b.0)),
                ManipulationPlan::reached_count,
            ),
            PlacementObjective::LongestPrefix => {
                (Cutoff::FirstMiss, ManipulationPlan::reached_prefix)
            }
        };
        let plan = prepared.plan(base, seed, manipulation, cutoff)?;
        let score = (reached(&plan), cost(&plan));
        // After every plan at least as good (the earliest first among equals).
        let at = best
            .iter()
            .position(|b| score.0 > b.0 || (score.0 == b.0 && score.1 < b.1))
            .unwrap_or(best.len());
        if at < keep {
            best.insert(at, (score.0, score.1, plan));
            best.truncate(keep);
        }
        Ok(true)
    };
    if sampling.current_pose {
        consider(robot_from, &mut best)?;
    }
    while drawn - rejected < sampling.samples && drawn < sampling.max_draws {
        if prepared.termination.is_cancelled() {
            stopped = Some(Stop::Cancelled);
            break;
        }
        if prepared.termination.should_stop() {
            stopped = Some(Stop::Budget);
            break;
        }
        drawn += 1;
        // Uniform over the annular sector's area.
        let u: f64 = rng.random();
        let r = (r_min * r_min + u * (r_max * r_max - r_min * r_min)).sqrt();
        let bearing = front_angle + sampling.bearing_spread * (2.0 * rng.random::<f64>() - 1.0);
        let jitter = sampling.yaw_jitter * (2.0 * rng.random::<f64>() - 1.0);
        let position = centroid + Vector2::new(bearing.cos(), bearing.sin()) * r;
        let facing = centroid - position;
        let base = [
            position.x,
            position.y,
            wrap(facing.y.atan2(facing.x) + jitter),
        ];
        if !consider(base, &mut best)? {
            rejected += 1;
        }
    }
    Ok(SampleResult {
        ranked: best.into_iter().map(|b| b.2).collect(),
        drawn,
        rejected,
        stopped,
        fallback,
    })
}

/// The first scene body the base links at `base` are within `margin` of, at any waypoint.
fn base_collides(
    prepared: &Prepared<'_>,
    base: [f64; 3],
    arm: &DVector<f64>,
    margin: f64,
) -> Result<Option<Body>, PlacementError> {
    let poses = prepared.problem.robot.link_poses(&RobotConfig {
        base,
        arm: arm.clone(),
    })?;
    Ok(prepared
        .scene
        .iter()
        .find_map(|data| prepared.base_obstacle(&poses, data, margin))
        .map(|(_, body)| body))
}

/// The first body the whole robot at `base` with the arm at `stow` comes within `margin` of,
/// at the motion's start or end state.
fn stow_collides(
    prepared: &Prepared<'_>,
    base: [f64; 3],
    stow: &DVector<f64>,
    margin: f64,
) -> Result<Option<Body>, PlacementError> {
    let poses = prepared.problem.robot.link_poses(&RobotConfig {
        base,
        arm: stow.clone(),
    })?;
    let p = &prepared.problem;
    let ends = [prepared.scene.first(), prepared.scene.last()];
    Ok(ends.into_iter().flatten().find_map(|data| {
        p.collision
            .scene_collision(&poses, p.model, data, Exempt::Nothing, margin)
            .map(|(_, body)| body)
    }))
}
