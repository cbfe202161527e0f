//! [`time_differential_drive`]: the exact profile of a differential-drive base path, under the
//! forward speed and the yaw rate.

use super::exact::{deltas, validate};
use super::whole_body::planar_profile;
use super::{TimedPath, TimingError};

/// Largest sideways displacement (m) or turn while driving (rad) a segment may have and still
/// count as a drive along the heading (round-off of the path's construction).
pub const SIDEWAYS_TOLERANCE: f64 = 1e-9;

/// Times the base path `path` (`[x, y, yaw]` waypoints, yaw continuous: not wrapped, so a turn
/// may exceed π) of a differential-drive base, stopping at every corner. Every segment must be
/// a turn in place (position unchanged up to [`SIDEWAYS_TOLERANCE`]) or a straight drive along
/// the heading, forward or backward (yaw unchanged, sideways displacement within
/// [`SIDEWAYS_TOLERANCE`]), as [`differential_drive`](crate::motion::paths::differential_drive)
/// makes them.
///
/// `max_velocity` and `max_acceleration` are the base's `[forward, lateral, yaw]` limits
/// ([`MobileBase`](crate::kinematics::robot::MobileBase) of a differential-drive base); the
/// lateral entries are ignored. Each run of collinear segments is traversed rest to rest with
/// the minimum-time bang–coast–bang profile (see the [module docs](super)) under
/// `|v| ≤ max_velocity[0]`, `|v̇| ≤ max_acceleration[0]` for the speed along a drive and
/// `|ω| ≤ max_velocity[2]`, `|ω̇| ≤ max_acceleration[2]` for the yaw rate of a turn. A drive of
/// length `L` lasts `L/v + v/a` (trapezoid, `v²/a < L`) or `2√(L/a)` (triangle), a turn by `θ`
/// the same with `θ` and the yaw limits.
///
/// # Errors
/// [`TimingError::EmptyPath`], [`TimingError::WaypointDimension`],
/// [`TimingError::NonFiniteWaypoint`], [`TimingError::LimitDimension`] (waypoints not of 3
/// values), [`TimingError::InvalidLimit`] (a forward or yaw limit not finite and positive),
/// [`TimingError::Sideways`] (a segment that is neither a turn in place nor a drive along the
/// heading).
///
/// # Example
/// ```
/// use kinscene::motion::timing::time_differential_drive;
///
/// // Turn a quarter turn at 1 rad/s and 1 rad/s² (trapezoid, since 1²/1 < π/2: π/2 + 1 s),
/// // then drive 2 m along +y at 1 m/s and 1 m/s² (1 s up, 1 s coasting, 1 s down).
/// let h = std::f64::consts::FRAC_PI_2;
/// let path = vec![vec![0.0, 0.0, 0.0], vec![0.0, 0.0, h], vec![0.0, 2.0, h]];
/// let timed = time_differential_drive(&path, &[1.0, 0.0, 1.0], &[1.0, 0.0, 1.0])?;
/// assert!((timed.duration - (h + 1.0 + 3.0)).abs() < 1e-12);
/// // Half-way along the drive, coasting at 1 m/s along the heading (+y), not sideways.
/// let v = timed.velocity(h + 1.0 + 1.5);
/// assert!(v[0].abs() < 1e-12 && (v[1] - 1.0).abs() < 1e-12 && v[2] == 0.0);
/// # Ok::<(), kinscene::motion::timing::TimingError>(())
/// ```
pub fn time_differential_drive(
    path: &[Vec<f64>],
    max_velocity: &[f64; 3],
    max_acceleration: &[f64; 3],
) -> Result<TimedPath, TimingError> {
    let [v, _, w] = *max_velocity;
    let [a, _, alpha] = *max_acceleration;
    validate(path, &[v, v, w], &[a, a, alpha], None)?;
    let deltas = deltas(path, None);
    for (segment, (d, q)) in deltas.iter().zip(path).enumerate() {
        let run = d[0].hypot(d[1]);
        let lateral = -q[2].sin() * d[0] + q[2].cos() * d[1];
        let drive = run > SIDEWAYS_TOLERANCE;
        if drive && (d[2].abs() > SIDEWAYS_TOLERANCE || lateral.abs() > SIDEWAYS_TOLERANCE) {
            return Err(TimingError::Sideways {
                segment,
                lateral,
                turn: d[2],
            });
        }
    }
    Ok(planar_profile(path, &deltas, &[v, v, w], &[a, a, alpha]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_diagonal_drive_is_limited_by_the_forward_speed_not_per_axis() {
        // 2 m along the diagonal facing it, 0.5 m/s and 0.5 m/s²: trapezoid 2/0.5 + 0.5/0.5
        // = 5 s. Per axis (x and y each at 0.5 m/s) it would be √2 m per axis: 3.83 s.
        let q = std::f64::consts::FRAC_PI_4;
        let s = 2.0 / 2f64.sqrt();
        let path = vec![vec![0.0, 0.0, q], vec![s, s, q]];
        let timed = time_differential_drive(&path, &[0.5, 0.0, 1.0], &[0.5, 0.0, 1.0]).unwrap();
        assert!((timed.duration - 5.0).abs() < 1e-12, "{}", timed.duration);
        let v = timed.velocity(2.5);
        assert!((v[0].hypot(v[1]) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn sideways_segments_are_refused() {
        let path = vec![vec![0.0, 0.0, 0.0], vec![0.0, 1.0, 0.0]];
        let err = time_differential_drive(&path, &[1.0, 0.0, 1.0], &[1.0, 0.0, 1.0]).unwrap_err();
        assert!(
            matches!(err, TimingError::Sideways { segment: 0, .. }),
            "{err}"
        );
        let turning = vec![vec![0.0, 0.0, 0.0], vec![1.0, 0.0, 0.5]];
        let err =
            time_differential_drive(&turning, &[1.0, 0.0, 1.0], &[1.0, 0.0, 1.0]).unwrap_err();
        assert!(matches!(err, TimingError::Sideways { .. }), "{err}");
    }
}
