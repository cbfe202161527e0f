//! Timing a step's phases: time-optimal with blended corners where the blended trajectory
//! passes the phase's checks, stopping at the corners where it does not.

use super::PlannerError;
use crate::motion::timing::{BlendSettings, TimedPath, time_optimal_stopping, time_parameterise};

/// `path` timed under `limits` (velocity, acceleration per coordinate) without stops at its
/// corners ([`time_optimal`](crate::motion::timing::time_optimal) with `blend`) where the blended trajectory passes `valid(path, t,
/// q)` at samples no farther apart than `resolution` in any coordinate (by the velocity
/// limits). A corner whose blend fails the check becomes a stop (the corner waypoint nearest
/// the failing sample, [`time_optimal_stopping`]) and the trajectory is timed and checked
/// again, so one tight corner does not stop the others; when every corner would stop, the
/// result is [`time_parameterise`]'s, exactly on the path the planner checked. `blend = None`
/// always stops.
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
    let speed = vmax.iter().copied().fold(0.0, f64::max);
    let corners = path.len().saturating_sub(2);
    let mut stops: Vec<usize> = Vec::new();
    while stops.len() < corners {
        let blended = time_optimal_stopping(path, vmax, amax, wrap_yaw, blend, &stops)?;
        if blended.is_exact() {
            return Ok(blended);
        }
        let n = ((blended.duration * speed / resolution).ceil() as usize).max(1);
        let failed = (0..=n)
            .map(|i| blended.duration * i as f64 / n as f64)
            .find(|&t| !valid(&blended, t, &blended.sample(t)));
        let Some(t) = failed else {
            return Ok(blended);
        };
        // The blended corner nearest the failure in time.
        let Some(corner) = (1..=corners).filter(|k| !stops.contains(k)).min_by(|a, b| {
            let d = |k: &usize| (blended.times[*k] - t).abs();
            d(a).total_cmp(&d(b))
        }) else {
            break;
        };
        stops.push(corner);
    }
    Ok(exact()?)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A zigzag with two corners, each 90°, at 1 per second and second² per coordinate; the
    /// check rejects every state more than 1e-6 off the polyline near the first corner
    /// (1, 0) only. The first corner becomes a stop (speed 0 there), the second stays blended
    /// (it keeps speed), and the result is quicker than stopping at both, which the old rule
    /// (one failed blend stops the whole phase) returned.
    #[test]
    fn a_failed_blend_stops_at_its_corner_only() {
        let path = vec![
            vec![0.0, 0.0],
            vec![1.0, 0.0],
            vec![1.0, 1.0],
            vec![2.0, 1.0],
        ];
        let limits = ([1.0, 1.0], [1.0, 1.0]);
        let blend = BlendSettings {
            max_deviation: 0.05,
            ..BlendSettings::default()
        };
        // Off the polyline: neither on y = 0 (x ≤ 1), x = 1 (0 ≤ y ≤ 1) nor y = 1 (x ≥ 1).
        let on_path = |q: &[f64]| {
            (q[1].abs() < 1e-6 && q[0] <= 1.0 + 1e-6)
                || ((q[0] - 1.0).abs() < 1e-6 && (-1e-6..=1.0 + 1e-6).contains(&q[1]))
                || ((q[1] - 1.0).abs() < 1e-6 && q[0] >= 1.0 - 1e-6)
        };
        let near_first = |q: &[f64]| (q[0] - 1.0).hypot(q[1]) < 0.3;
        let valid = |_: &TimedPath, _: f64, q: &[f64]| on_path(q) || !near_first(q);
        let out = timed(
            &path,
            (&limits.0, &limits.1),
            None,
            Some(&blend),
            0.01,
            &valid,
        )
        .unwrap();
        let speed = |k: usize| {
            let v = out.velocity(out.times[k]);
            v[0].hypot(v[1])
        };
        assert!(speed(1) < 1e-6, "{}", speed(1));
        assert!(speed(2) > 0.3, "{}", speed(2));
        let stopping = time_parameterise(&path, &limits.0, &limits.1, None).unwrap();
        assert!(out.duration < stopping.duration - 0.1);
        // Every sample passes the check.
        let n = 2000;
        assert!((0..=n).all(|i| {
            let t = out.duration * i as f64 / n as f64;
            valid(&out, t, &out.sample(t))
        }));
        // A check that rejects both blends gives the exact profile.
        let strict = |_: &TimedPath, _: f64, q: &[f64]| on_path(q);
        let out = timed(
            &path,
            (&limits.0, &limits.1),
            None,
            Some(&blend),
            0.01,
            &strict,
        )
        .unwrap();
        assert!(out.is_exact());
    }
}
