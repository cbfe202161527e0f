//! Timing a step's phases: time-optimal with blended corners where the blended trajectory
//! passes the phase's checks, else stopping at the corners, exactly on the checked path.

use super::PlannerError;
use crate::motion::timing::{BlendSettings, TimedPath, time_optimal, time_parameterise};

/// `path` timed under `limits` (velocity, acceleration per coordinate) without stops at its
/// corners ([`time_optimal`] with `blend`) when the blended trajectory passes `valid(path, t,
/// q)` at samples no farther apart than `resolution` in any coordinate (by the velocity
/// limits); else with stops ([`time_parameterise`]), exactly on the path the planner checked.
/// `blend = None` always stops.
pub(super) fn timed(
    path: &[Vec<f64>],
    (vmax, amax): (&[f64], &[f64]),
    wrap_yaw: Option<usize>,
    blend: Option<&BlendSettings>,
    resolution: f64,
    valid: &dyn Fn(&TimedPath, f64, &[f64]) -> bool,
) -> Result<TimedPath, PlannerError> {
    let exact = || time_parameterise(path, vmax, amax, wrap_yaw);
    let Some(blend) = blend else {
        return Ok(exact()?);
    };
    let blended = time_optimal(path, vmax, amax, wrap_yaw, blend)?;
    if blended.is_exact() {
        return Ok(blended);
    }
    let speed = vmax.iter().copied().fold(0.0, f64::max);
    let n = ((blended.duration * speed / resolution).ceil() as usize).max(1);
    for i in 0..=n {
        let t = blended.duration * i as f64 / n as f64;
        if !valid(&blended, t, &blended.sample(t)) {
            return Ok(exact()?);
        }
    }
    Ok(blended)
}

/// The moved joint's value where the arm is at `q` on the manipulation (waypoint `k` at
/// `from + k/K (to − from)`): `q` projected onto the nearest segment of the waypoints' path,
/// the joint at the same fraction of that segment. The part follows the grasp, so it is where
/// the arm's progress puts it, whatever the timing (a blend leaves the path by little).
pub(super) fn value_at(waypoints: &[Vec<f64>], q: &[f64], from: f64, to: f64) -> f64 {
    let k = waypoints.len().saturating_sub(1).max(1);
    let mut best = (f64::INFINITY, 0.0);
    for (j, w) in waypoints.windows(2).enumerate() {
        let d: Vec<f64> = w[1].iter().zip(&w[0]).map(|(b, a)| b - a).collect();
        let r: Vec<f64> = q.iter().zip(&w[0]).map(|(x, a)| x - a).collect();
        let len2: f64 = d.iter().map(|x| x * x).sum();
        let f = if len2 > 0.0 {
            (r.iter().zip(&d).map(|(x, y)| x * y).sum::<f64>() / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dist2: f64 = r.iter().zip(&d).map(|(x, y)| (x - f * y).powi(2)).sum();
        if dist2 < best.0 {
            best = (dist2, j as f64 + f);
        }
    }
    from + (to - from) * best.1 / k as f64
}
