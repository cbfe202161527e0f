//! [`time_whole_body_differential`]: the exact profile of a base-and-arm path of a
//! differential-drive robot, under the forward speed and yaw rate of the base and the arm's
//! per-joint limits.

use super::exact::{deltas, profile, validate};
use super::{TimedPath, TimingError};

/// Times the whole-body path `path` (waypoints `[x, y, yaw, q1, …, qn]`, yaw continuous: not
/// wrapped) of a robot with a differential-drive base, stopping at every corner, along the
/// piecewise-linear path exactly (base, arm and yaw interpolated together, as the planner
/// checks them).
///
/// `base_velocity` and `base_acceleration` are the base's `[forward, lateral, yaw]` limits
/// (the lateral entries are ignored), `arm_velocity` and `arm_acceleration` one per arm joint.
/// Each run of collinear segments is traversed rest to rest with the minimum-time
/// bang–coast–bang profile (see the [module docs](super)) under `|v| ≤ base_velocity[0]`,
/// `|v̇| ≤ base_acceleration[0]` for the base's planar velocity `(ẋ, ẏ)` (its length, so a
/// drive along the heading gets the full forward speed, not a per-axis share), the yaw
/// limits for `yaw`, and the arm's per-joint limits. Along a run every coordinate moves in
/// proportion, so the planar acceleration is parallel to the planar velocity and its length
/// is bounded the same way.
///
/// The path's sideways motion is not checked here: the whole-body planner keeps it within its
/// tolerance ([`WholeBodySettings::sideways_tolerance`]), and that slip counts towards the
/// planar speed like forward motion does.
///
/// [`WholeBodySettings::sideways_tolerance`]: crate::motion::placement::WholeBodySettings::sideways_tolerance
///
/// # Errors
/// [`TimingError::EmptyPath`], [`TimingError::WaypointDimension`],
/// [`TimingError::NonFiniteWaypoint`], [`TimingError::LimitDimension`] (waypoints not of
/// `3 + arm_velocity.len()` values, or arm limits of different lengths),
/// [`TimingError::InvalidLimit`] (a forward, yaw or arm limit not finite and positive).
///
/// # Example
/// ```
/// use kinscene::motion::timing::time_whole_body_differential;
///
/// // The base drives 2 m along the diagonal it faces while one arm joint turns 0.1 rad:
/// // the base's 0.5 m/s and 0.5 m/s² on the planar speed (not per axis) bound the run:
/// // trapezoid 2/0.5 + 0.5/0.5 = 5 s; the joint alone would take far less.
/// let h = std::f64::consts::FRAC_PI_4;
/// let s = 2.0 / 2f64.sqrt();
/// let path = vec![vec![0.0, 0.0, h, 0.0], vec![s, s, h, 0.1]];
/// let timed =
///     time_whole_body_differential(&path, &[0.5, 0.0, 1.0], &[0.5, 0.0, 1.0], &[1.0], &[1.0])?;
/// assert!((timed.duration - 5.0).abs() < 1e-12);
/// # Ok::<(), kinscene::motion::timing::TimingError>(())
/// ```
pub fn time_whole_body_differential(
    path: &[Vec<f64>],
    base_velocity: &[f64; 3],
    base_acceleration: &[f64; 3],
    arm_velocity: &[f64],
    arm_acceleration: &[f64],
) -> Result<TimedPath, TimingError> {
    let [v, _, w] = *base_velocity;
    let [a, _, alpha] = *base_acceleration;
    let vmax: Vec<f64> = [v, v, w].iter().chain(arm_velocity).copied().collect();
    let amax: Vec<f64> = [a, a, alpha]
        .iter()
        .chain(arm_acceleration)
        .copied()
        .collect();
    validate(path, &vmax, &amax, None)?;
    let deltas = deltas(path, None);
    Ok(planar_profile(path, &deltas, &vmax, &amax))
}

/// The exact profile of `path` (segments `deltas`, coordinates `[x, y, c2, …]`), rest to rest
/// along each run: the planar velocity `(ẋ, ẏ)` by its length under `vmax[0]`, `amax[0]`
/// (`vmax[1]`, `amax[1]` are not used), every other coordinate `i ≥ 2` under its own limits.
pub(super) fn planar_profile(
    path: &[Vec<f64>],
    deltas: &[Vec<f64>],
    vmax: &[f64],
    amax: &[f64],
) -> TimedPath {
    profile(path, deltas, &|run: &[(&[f64], f64)], total: f64| {
        let largest = |f: &dyn Fn(&[f64]) -> f64| {
            run.iter()
                .filter(|(_, l)| *l > 0.0)
                .map(|(d, l)| f(d) / l)
                .fold(0.0, f64::max)
        };
        let (mut speed, mut accel) = (f64::INFINITY, f64::INFINITY);
        let mut bound = |m: f64, v: f64, a: f64| {
            if m > 0.0 {
                speed = speed.min(v / (total * m));
                accel = accel.min(a / (total * m));
            }
        };
        bound(largest(&|d| d[0].hypot(d[1])), vmax[0], amax[0]);
        for i in 2..vmax.len() {
            bound(largest(&|d| d[i].abs()), vmax[i], amax[i]);
        }
        (speed, accel)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slowest_coordinate_bounds_a_run_and_the_base_counts_its_planar_speed() {
        // One segment, timed as one run with `T = 1/V + V/A` (trapezoid when `V²/A < 1`),
        // `V = minᵢ vᵢ/Dᵢ`, `A = minᵢ aᵢ/Dᵢ` (module docs). The base moves 0.3 m along x and
        // 0.4 m along y, 0.5 m planar, at 0.25 m/s and 0.25 m/s²: 0.5 and 0.5 (per axis it
        // would be 0.625 for y); the yaw 0.1 rad at 1 rad/s and 1 rad/s²: 10 and 10; arm joint
        // 1 turns 2 rad at 1 rad/s and 1 rad/s²: 0.5 and 0.5; arm joint 2 turns 0.3 rad at
        // 0.1 rad/s and 1 rad/s²: 1/3 and 10/3. V = 1/3, A = 0.5, V²/A = 2/9 < 1:
        // T = 3 + 2/3 s.
        let path = vec![vec![0.0; 5], vec![0.3, 0.4, 0.1, 2.0, 0.3]];
        let timed = time_whole_body_differential(
            &path,
            &[0.25, 0.0, 1.0],
            &[0.25, 0.0, 1.0],
            &[1.0, 0.1],
            &[1.0, 1.0],
        )
        .unwrap();
        assert!(
            (timed.duration - 11.0 / 3.0).abs() < 1e-12,
            "{}",
            timed.duration
        );
        // Without the slow joint, V = A = 0.5 (the base and the first joint tie): 2 + 1 = 3 s,
        // the planar speed at its 0.25 m/s limit while coasting.
        let path = vec![vec![0.0; 4], vec![0.3, 0.4, 0.1, 2.0]];
        let timed = time_whole_body_differential(
            &path,
            &[0.25, 0.0, 1.0],
            &[0.25, 0.0, 1.0],
            &[1.0],
            &[1.0],
        )
        .unwrap();
        assert!((timed.duration - 3.0).abs() < 1e-12, "{}", timed.duration);
        let v = timed.velocity(1.5);
        assert!((v[0].hypot(v[1]) - 0.25).abs() < 1e-12, "{v:?}");
    }

    #[test]
    fn the_coordinates_of_a_timed_path_sample_as_the_whole_path_does() {
        // A base-and-arm path with a corner, timed exactly and blended: each group's own
        // trajectory (`coordinates`) is, at every time, the whole trajectory's state cut to
        // the group — positions and velocities, same times.
        use crate::motion::timing::{BlendSettings, time_optimal, time_parameterise};
        let path = vec![
            vec![0.0, 0.0, 0.0, 0.0],
            vec![0.3, 0.1, 0.2, -0.4],
            vec![0.5, 0.6, 0.1, 0.3],
        ];
        let limits = [0.5, 0.5, 1.0, 1.2];
        let exact = time_parameterise(&path, &limits, &limits, None).unwrap();
        let blended =
            time_optimal(&path, &limits, &limits, None, &BlendSettings::default()).unwrap();
        assert!(exact.is_exact() && !blended.is_exact());
        for whole in [&exact, &blended] {
            let (base, arm) = (whole.coordinates(0..3), whole.coordinates(3..4));
            assert_eq!((&base.times, base.duration), (&whole.times, whole.duration));
            assert_eq!(arm.positions, vec![vec![0.0], vec![-0.4], vec![0.3]]);
            for i in 0..=200 {
                let t = whole.duration * i as f64 / 200.0;
                let (q, v) = (whole.sample(t), whole.velocity(t));
                assert_eq!(base.sample(t), q[..3].to_vec(), "t = {t}");
                assert_eq!(arm.sample(t), q[3..].to_vec(), "t = {t}");
                assert_eq!(base.velocity(t), v[..3].to_vec(), "t = {t}");
                assert_eq!(arm.velocity(t), v[3..].to_vec(), "t = {t}");
            }
        }
    }

    #[test]
    fn bad_dimensions_are_errors() {
        let path = vec![vec![0.0; 4], vec![1.0; 4]];
        let err =
            time_whole_body_differential(&path, &[1.0; 3], &[1.0; 3], &[1.0, 1.0], &[1.0, 1.0])
                .unwrap_err();
        assert!(matches!(err, TimingError::LimitDimension { .. }), "{err}");
    }
}
