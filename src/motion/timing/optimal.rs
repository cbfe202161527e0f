//! [`time_optimal`]: the blended profile, corners cut by arcs and timed in the phase plane,
//! and its settings.

use serde::{Deserialize, Serialize};

use super::timed_path::{Blended, Profile};
use super::{TimedPath, TimingError, blend, phase, time_parameterise};
use crate::InvalidSetting;

/// Settings of [`time_optimal`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BlendSettings {
    /// The most a blend may cut a corner: the largest distance (Euclidean, in the
    /// waypoints' coordinates: rad or m) from a corner waypoint to its arc. Default 0.02.
    pub max_deviation: f64,
    /// Integration step (s): arcs are cut into intervals that take about this long at the
    /// fastest speed the arc allows (and turn by at most 0.01 rad). Default 1e-3.
    pub time_step: f64,
}

impl Default for BlendSettings {
    fn default() -> Self {
        BlendSettings {
            max_deviation: 0.02,
            time_step: 1e-3,
        }
    }
}

impl BlendSettings {
    /// Checks that both settings are finite and positive.
    ///
    /// # Errors
    /// [`TimingError::InvalidSetting`] naming the first bad one.
    pub fn validate(&self) -> Result<(), TimingError> {
        for (what, value) in [
            ("max_deviation", self.max_deviation),
            ("time_step", self.time_step),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(InvalidSetting::new(what, value, "finite and > 0").into());
            }
        }
        Ok(())
    }
}

/// Times `path` under `max_velocity` and `max_acceleration` (one per coordinate, units per
/// second and per second²) without stopping at its corners: each interior corner is cut by a
/// circular arc at most `settings.max_deviation` from it, and the blended path is timed in
/// the phase plane (Kunz & Stilman 2012; see the [module docs](super)). `wrap_yaw = Some(i)`
/// makes coordinate `i` an angle: the path is unwrapped (each segment turns the short way)
/// before blending.
///
/// # Guarantee
/// The result starts and ends at rest at the first and last waypoint and never exceeds the
/// limits: `|q̇ᵢ(t)| ≤ max_velocity[i]` and `|q̈ᵢ(t)| ≤ max_acceleration[i]` at every `t`,
/// not only at integration steps (a rigorous bound check between steps stretches time where
/// needed; up to floating-point rounding). It does not stop at blended corners. Every state
/// is within [`TimedPath::max_deviation`] `≤ settings.max_deviation` of the
/// piecewise-linear path, and on it away from the corners. Its duration is never
/// longer than [`time_parameterise`]'s on the same input: when blending gains nothing (no
/// corner to blend, e.g. a straight path or a single waypoint) or would be slower, that
/// exact profile is returned instead ([`TimedPath::is_exact`]).
///
/// Corners are cut: the trajectory leaves the path the planner checked by up to
/// `max_deviation`, so that margin must be covered by the collision checks (or the
/// trajectory re-checked) before it is executed.
///
/// # Errors
/// As [`time_parameterise`]: [`TimingError::EmptyPath`], [`TimingError::WaypointDimension`],
/// [`TimingError::NonFiniteWaypoint`], [`TimingError::LimitDimension`],
/// [`TimingError::InvalidLimit`], [`TimingError::YawIndexOutOfRange`]; and
/// [`TimingError::InvalidSetting`] (a setting not finite and positive).
///
/// # Example
/// ```
/// use kinscene::motion::timing::{BlendSettings, time_optimal, time_parameterise};
///
/// // An L: 1 m along x, then 1 m along y, at 1 m/s and 1 m/s² per axis.
/// let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
/// let (v, a) = ([1.0, 1.0], [1.0, 1.0]);
/// let settings = BlendSettings { max_deviation: 0.05, ..BlendSettings::default() };
/// let blended = time_optimal(&path, &v, &a, None, &settings)?;
/// let stopping = time_parameterise(&path, &v, &a, None)?;
/// assert!(blended.duration < stopping.duration); // 4 s with a stop at the corner
/// assert!(!blended.is_exact() && blended.max_deviation() <= 0.05 + 1e-12);
/// // It does not stop at the corner (the time nearest the corner waypoint).
/// let corner = blended.velocity(blended.times[1]);
/// assert!(corner[0].hypot(corner[1]) > 0.3);
/// assert_eq!(blended.sample(blended.duration), path[2]);
/// # Ok::<(), kinscene::motion::timing::TimingError>(())
/// ```
pub fn time_optimal(
    path: &[Vec<f64>],
    max_velocity: &[f64],
    max_acceleration: &[f64],
    wrap_yaw: Option<usize>,
    settings: &BlendSettings,
) -> Result<TimedPath, TimingError> {
    time_optimal_stopping(
        path,
        max_velocity,
        max_acceleration,
        wrap_yaw,
        settings,
        &[],
    )
}

/// [`time_optimal`] with a stop at each waypoint of `stop_at` (indices into `path`; out of
/// range ones are ignored): those corners are not blended, the trajectory passes through the
/// waypoint at rest, and every other corner is blended as usual. A caller whose check rejects
/// one blended corner stops there and keeps the others.
///
/// # Errors
/// As [`time_optimal`].
///
/// # Example
/// ```
/// use kinscene::motion::timing::{BlendSettings, time_optimal_stopping};
///
/// // A zigzag of two corners at 1 m/s and 1 m/s² per axis; stop at the first only.
/// let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0], vec![2.0, 1.0]];
/// let (v, a) = ([1.0, 1.0], [1.0, 1.0]);
/// let settings = BlendSettings { max_deviation: 0.05, ..BlendSettings::default() };
/// let timed = time_optimal_stopping(&path, &v, &a, None, &settings, &[1])?;
/// let at = |k: usize| {
///     let v = timed.velocity(timed.times[k]);
///     v[0].hypot(v[1])
/// };
/// assert!(at(1) < 1e-6 && at(2) > 0.3);
/// # Ok::<(), kinscene::motion::timing::TimingError>(())
/// ```
pub fn time_optimal_stopping(
    path: &[Vec<f64>],
    max_velocity: &[f64],
    max_acceleration: &[f64],
    wrap_yaw: Option<usize>,
    settings: &BlendSettings,
    stop_at: &[usize],
) -> Result<TimedPath, TimingError> {
    let exact = time_parameterise(path, max_velocity, max_acceleration, wrap_yaw)?;
    settings.validate()?;
    let geometry = blend::build(path, wrap_yaw, settings.max_deviation, stop_at);
    if geometry.blends == 0 || geometry.segments.is_empty() {
        return Ok(exact);
    }
    let Some(timing) = phase::integrate(
        &geometry,
        max_velocity,
        max_acceleration,
        settings.time_step,
    ) else {
        return Ok(exact);
    };
    if timing.duration.is_nan() || timing.duration >= exact.duration {
        return Ok(exact);
    }
    let blended = Blended { geometry, timing };
    let duration = blended.timing.duration;
    let mut times: Vec<f64> = blended
        .geometry
        .waypoint_s
        .iter()
        .map(|&s| waypoint_time(&blended, s))
        .collect();
    // Exact ends, and monotone in between (each time is found in its own piece).
    times[0] = 0.0;
    if let Some(last) = times.last_mut() {
        *last = duration;
    }
    for j in 1..times.len() {
        times[j] = times[j].max(times[j - 1]).min(duration);
    }
    Ok(TimedPath {
        times,
        positions: path.to_vec(),
        duration,
        profile: Profile::Blended(Box::new(blended)),
    })
}

/// The time at which `blended` reaches arc length `s`.
fn waypoint_time(blended: &Blended, s: f64) -> f64 {
    let pieces = &blended.timing.pieces;
    let k = pieces.partition_point(|p| p.s <= s).max(1) - 1;
    let end = pieces.get(k + 1).map_or(blended.timing.duration, |q| q.t);
    phase::time_at(&pieces[k], s, end)
}
