//! Time parameterisation of piecewise-linear paths under per-coordinate velocity and
//! acceleration limits.
//!
//! [`time_parameterise`] times a path (base or arm) so that it is followed *exactly*: between
//! waypoints the state moves on the straight segment (the geometry the planner checked), every
//! coordinate `i` within `|q̇ᵢ| ≤ max_velocity[i]` and `|q̈ᵢ| ≤ max_acceleration[i]`.
//! [`time_optimal`] trades exactness for speed: it cuts every corner by at most
//! [`BlendSettings::max_deviation`] and passes it without stopping, under the same limits
//! (see [Corner blending](#corner-blending-time_optimal)).
//!
//! # The profile
//! The path is cut into *runs*: maximal sequences of segments with the same direction (unit
//! vectors within [`COLLINEAR_TOLERANCE`]; zero-length segments join any run). Each run is
//! traversed with one scalar parameter `s ∈ [0, 1]` (arc length over run length `L`) that
//! starts and ends at rest and follows the minimum-time bang–coast–bang profile under
//! `ṡ ≤ V = minᵢ vᵢ / (L·mᵢ)` and `s̈ ≤ A = minᵢ aᵢ / (L·mᵢ)`, `mᵢ` the largest `|uᵢ|` of the
//! run's unit directions `u`. Coordinate `i` then moves at `ṡ·L·uᵢ`, within its limits by
//! construction: exact, no iteration, no tolerance.
//!
//! For a single segment with per-coordinate distances `Dᵢ` this gives the duration
//! `T = 1/V + V/A` if `V²/A < 1` (trapezoid), else `T = 2/√A` (triangle), with
//! `V = minᵢ vᵢ/Dᵢ`, `A = minᵢ aᵢ/Dᵢ`: the slowest coordinate's own minimum time.
//!
//! **Conservative where the path bends.** The profile stops at every corner (a waypoint where
//! the direction changes). That is forced for exact path following: a non-zero speed through
//! a corner is a velocity jump, i.e. unbounded acceleration. Along each run it is time-optimal
//! (the bounds on `ṡ`, `s̈` are constant there). Faster trajectories exist only by cutting
//! corners (blends), which leave the path the planner checked: [`time_optimal`] makes them,
//! and its caller must cover the cut ([`TimedPath::max_deviation`]) by a collision margin or
//! a re-check before executing it.
//!
//! With `wrap_yaw = Some(i)`, coordinate `i` is an angle: each segment turns the short way
//! (the difference wrapped into `[-π, π]`), and within a segment the sampled angle is the
//! waypoint's value plus a fraction of that difference (not re-wrapped).
//!
//! # Example
//! ```
//! use kinscene::motion::timing::time_parameterise;
//!
//! // 2 m along x at 1 m/s and 1 m/s²: accelerate 1 s (0.5 m), coast 1 s, brake 1 s.
//! let path = vec![vec![0.0, 0.0], vec![2.0, 0.0]];
//! let timed = time_parameterise(&path, &[1.0, 1.0], &[1.0, 1.0], None)?;
//! assert!((timed.duration - 3.0).abs() < 1e-12);
//! assert!((timed.sample(1.0)[0] - 0.5).abs() < 1e-12);
//! assert!((timed.velocity(1.5)[0] - 1.0).abs() < 1e-12);
//! # Ok::<(), kinscene::motion::timing::TimingError>(())
//! ```

//! # Corner blending (`time_optimal`)
//! After Kunz & Stilman, *Time-Optimal Trajectory Generation for Path Following with Bounded
//! Acceleration and Velocity* (RSS 2012), the algorithm MoveIt ships as TOTG.
//!
//! **Geometry.** With a wrapping yaw the path is unwrapped first (each segment turns the short
//! way); repeated waypoints are dropped. Each interior corner turning by `α` is replaced by
//! the circular arc tangent to both segments whose midpoint is `ℓ·tan(α/4) ≤ δ` from the
//! corner, `ℓ = min(L_in/2, L_out/2, δ/tan(α/4))` the distance from the corner to the tangent
//! points and `r = ℓ/tan(α/2)` the radius (`δ` = `max_deviation`; an arc uses at most half of
//! each segment). Collinear corners (turn ≤ [`COLLINEAR_TOLERANCE`]) stay as they are; an
//! exact reversal (turn within ~1e-9 of π) cannot be blended and the trajectory stops
//! there. The result is C¹, parameterised by arc length `s`, with `q = f(s)`, `|f'| = 1`;
//! `f'' = 0` on the lines.
//!
//! **Limit curve.** Coordinate `i` moves at `q̇ᵢ = f'ᵢ·ṡ` and accelerates at
//! `q̈ᵢ = f'ᵢ·s̈ + f''ᵢ·ṡ²`. The velocity limits give `ṡ ≤ minᵢ vᵢ/|f'ᵢ|`; the acceleration
//! limits bound `s̈` to an interval at each `(s, ṡ)`, non-empty below the paper's
//! acceleration limit curve (`ṡ² ≤ (aᵢ/|f'ᵢ| + aⱼ/|f'ⱼ|) / |f''ᵢ/f'ᵢ − f''ⱼ/f'ⱼ|` over
//! pairs, `ṡ² ≤ aᵢ/|f''ᵢ|` where `f'ᵢ = 0`). On a line both are constant (`V`, `A` as above);
//! on an arc they vary with the angle, and at the arc's ends the acceleration limit curve
//! drops from ∞ to about `√(a·r)` (the paper's discontinuity switching points).
//!
//! **Phase-plane integration.** In `x = ṡ²` a constant `s̈` is a straight line
//! (`x' = 2s̈`), so the profile is piecewise linear in `(s, x)` over a grid: one interval per
//! line, and each arc cut into intervals that last about `time_step` at the arc's fastest
//! allowed speed (and turn by at most 0.01 rad). Two passes replace the paper's switching
//! point search:
//! - *backward*: from rest at the end (and at every sharp corner), the largest `x` at each
//!   knot from which the rest of the path can be followed within the limits: the paper's
//!   backward integration at the maximum deceleration, started from the end and from every
//!   point of the limit curve at once (their lower envelope). Per arc interval this is a
//!   two-variable linear program (the acceleration limits at both knots, `s̈` constant),
//!   solved exactly; on a line it is closed form (`x_in = min(V², x_out + 2A·L)`);
//! - *forward*: from rest, the paper's forward integration at the maximum acceleration,
//!   under that envelope (so it never needs to be cut back where it would cross a backward
//!   curve). On a line this is the closed-form trapezoid between the entry and exit speeds,
//!   exact (the profile agrees with [`time_parameterise`] on a straight path).
//!
//! This is the time-optimal profile of the discretised problem (the two-pass scheme of
//! TOPP-RA, Pham & Pham 2018, with the constraints of Kunz & Stilman): where the forward
//! curve meets the limit curve it follows it if it can, and where it cannot, the backward
//! envelope has already bent it down, which is what the paper's switching points do.
//!
//! **Bounds between the knots.** The knots satisfy the limits; in between, on an arc, the
//! constraint functions curve (by ~`θ²/8` relative for a turn `θ` per interval). A check
//! bounds `|q̇ᵢ|/vᵢ` and `|q̈ᵢ|/aᵢ` over every piece rigorously (sub-samples plus an
//! interpolation remainder from the derivatives of `f`) and stretches time by the factor
//! `k = max(1, velocity ratio, √acceleration ratio)` if needed (velocities scale by `1/k`,
//! accelerations by `1/k²`): the limits then hold at every instant. In practice `k − 1` is
//! 1e-5 or less (a few microseconds on a ten-second trajectory).
//!
//! **Fallback.** If nothing could be blended, or the blended duration is not shorter than
//! [`time_parameterise`]'s, that exact profile is returned: `time_optimal` is never slower.

mod blend;
mod error;
mod phase;
mod ramp;

use serde::{Deserialize, Serialize};

use crate::InvalidSetting;
pub use error::TimingError;
use ramp::Ramp;

/// Two segment directions (unit vectors) closer than this count as the same direction: the
/// profile does not stop between them. The velocity jump there is at most this fraction of
/// the speed (1e-12), far below any controller's resolution.
pub const COLLINEAR_TOLERANCE: f64 = 1e-12;

/// A timed path: waypoints with the time at which each is reached, and the profile between
/// them (see the [module docs](self)).
///
/// Made by [`time_parameterise`] (an *exact* profile: the trajectory is the piecewise-linear
/// path, at rest at every corner) or by [`time_optimal`] (a *blended* profile: corners cut by
/// arcs, at most [`TimedPath::max_deviation`] from the path). Serialised as `times`,
/// `positions` and `duration`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimedPath {
    /// Time (s) at which each waypoint is reached, from 0, non-decreasing. For a blended
    /// profile, the time at which the trajectory is nearest the waypoint (at a blended corner,
    /// the midpoint of its arc).
    pub times: Vec<f64>,
    /// The waypoints, as given.
    pub positions: Vec<Vec<f64>>,
    /// Total duration (s), the last of `times`.
    pub duration: f64,
    /// How the state moves between the waypoints.
    #[serde(skip)]
    profile: Profile,
}

/// The motion behind a [`TimedPath`].
#[derive(Debug, Clone, PartialEq)]
enum Profile {
    /// [`time_parameterise`]: the path itself, rest-to-rest per run of collinear segments.
    Exact {
        /// One per segment (waypoint `j` to `j + 1`).
        segments: Vec<Segment>,
        /// One per run of collinear segments.
        runs: Vec<Ramp>,
    },
    /// [`time_optimal`]: the blended path and its phase-plane timing.
    Blended(Box<Blended>),
}

/// A blended path and its timing.
#[derive(Debug, Clone, PartialEq)]
struct Blended {
    geometry: blend::Geometry,
    timing: phase::Timing,
}

impl Blended {
    /// The piece running at `t ∈ (0, duration)`, its end time and `(s, ṡ)` at `t`.
    fn locate(&self, t: f64) -> (&phase::Piece, f64, f64) {
        let pieces = &self.timing.pieces;
        let k = pieces.partition_point(|p| p.t <= t).max(1) - 1;
        let p = &pieces[k];
        let end = pieces.get(k + 1).map_or(self.timing.duration, |q| q.t);
        let (s, sd) = phase::state(p, t, end);
        (p, s, sd)
    }
}

/// A segment inside its run: `q = positions[j] + f·delta`, `f = (s − s0) / (s1 − s0)`.
#[derive(Debug, Clone, PartialEq)]
struct Segment {
    run: usize,
    s0: f64,
    s1: f64,
    delta: Vec<f64>,
}

impl TimedPath {
    /// The state at time `t` (s), clamped to `[0, duration]` (NaN counts as 0). `sample(0)`
    /// is the first waypoint and `sample(duration)` the last, exactly (for a blended profile
    /// with a wrapping yaw coordinate: the last waypoint's yaw unwrapped, i.e. plus a
    /// multiple of 2π, so that the yaw is continuous). An exact profile is at waypoint `j`
    /// at `times[j]`, exactly.
    pub fn sample(&self, t: f64) -> Vec<f64> {
        let t = if t.is_nan() { 0.0 } else { t };
        let (segments, runs) = match &self.profile {
            Profile::Exact { segments, runs } => (segments, runs),
            Profile::Blended(b) => {
                if t <= 0.0 {
                    return b.geometry.start.clone();
                }
                if t >= self.duration {
                    return b.geometry.end.clone();
                }
                let (p, s, _) = b.locate(t);
                let seg = &b.geometry.segments[p.segment];
                return seg.position(s - seg.s0);
            }
        };
        match self.locate(t) {
            Located::Waypoint(k) => self.positions[k].clone(),
            Located::Inside(j, t) => {
                let seg = &segments[j];
                let (s, _) = runs[seg.run].eval(t);
                let width = seg.s1 - seg.s0;
                let f = if width > 0.0 {
                    ((s - seg.s0) / width).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                self.positions[j]
                    .iter()
                    .zip(&seg.delta)
                    .map(|(p, d)| p + f * d)
                    .collect()
            }
        }
    }

    /// The velocity at time `t` (units per second), zero outside `(0, duration)` (NaN counts
    /// as 0). For an exact profile it is zero at a corner and, at a waypoint inside a run,
    /// the following segment's.
    pub fn velocity(&self, t: f64) -> Vec<f64> {
        let t = if t.is_nan() { 0.0 } else { t };
        let dim = self.positions[0].len();
        let (segments, runs) = match &self.profile {
            Profile::Exact { segments, runs } => (segments, runs),
            Profile::Blended(b) => {
                if t <= 0.0 || t >= self.duration {
                    return vec![0.0; dim];
                }
                let (p, s, sd) = b.locate(t);
                let seg = &b.geometry.segments[p.segment];
                let (mut first, mut second) = (vec![0.0; dim], vec![0.0; dim]);
                seg.derivatives(s - seg.s0, &mut first, &mut second);
                return first.iter().map(|f| f * sd).collect();
            }
        };
        let (j, t) = match self.locate(t) {
            Located::Waypoint(k) if k == 0 || k + 1 == self.positions.len() => {
                return vec![0.0; dim];
            }
            // Interior waypoint: segment k starts here and has a positive duration.
            Located::Waypoint(k) => (k, self.times[k]),
            Located::Inside(j, t) => (j, t),
        };
        let seg = &segments[j];
        let (_, ds) = runs[seg.run].eval(t);
        let width = seg.s1 - seg.s0;
        if width > 0.0 {
            seg.delta.iter().map(|d| ds * d / width).collect()
        } else {
            vec![0.0; dim]
        }
    }

    /// How far the trajectory may leave the piecewise-linear path through `positions`: 0 for
    /// an exact profile; for a blended one the largest distance from a blended corner to its
    /// arc (at most [`BlendSettings::max_deviation`]). Every sampled state is within this
    /// distance (Euclidean, in the waypoints' coordinates, a wrapping yaw unwrapped) of the
    /// path.
    pub fn max_deviation(&self) -> f64 {
        match &self.profile {
            Profile::Exact { .. } => 0.0,
            Profile::Blended(b) => b.geometry.max_deviation,
        }
    }

    /// Whether the trajectory follows the piecewise-linear path exactly (made by
    /// [`time_parameterise`], or by [`time_optimal`] falling back to it).
    pub fn is_exact(&self) -> bool {
        matches!(self.profile, Profile::Exact { .. })
    }

    /// Where `t` falls: exactly on (or clamped to) waypoint `k`, or strictly inside segment `j`
    /// (which then has a positive duration).
    fn locate(&self, t: f64) -> Located {
        let last = self.times.len() - 1;
        if t <= 0.0 {
            return Located::Waypoint(0);
        }
        if t >= self.duration {
            return Located::Waypoint(last);
        }
        // The last waypoint reached at or before t; the next one is reached after t.
        let k = self.times.partition_point(|&tk| tk <= t) - 1;
        if t == self.times[k] {
            Located::Waypoint(k)
        } else {
            Located::Inside(k, t)
        }
    }
}

enum Located {
    Waypoint(usize),
    Inside(usize, f64),
}

/// Times `path` under `max_velocity` and `max_acceleration` (one per coordinate, units per
/// second and per second²), stopping at every corner; see the [module docs](self) for the
/// profile and its guarantees. `wrap_yaw = Some(i)` makes coordinate `i` an angle that turns
/// the short way.
///
/// A one-waypoint path has duration 0.
///
/// # Errors
/// [`TimingError::EmptyPath`], [`TimingError::WaypointDimension`],
/// [`TimingError::NonFiniteWaypoint`], [`TimingError::LimitDimension`],
/// [`TimingError::InvalidLimit`] (a limit not finite and positive),
/// [`TimingError::YawIndexOutOfRange`].
pub fn time_parameterise(
    path: &[Vec<f64>],
    max_velocity: &[f64],
    max_acceleration: &[f64],
    wrap_yaw: Option<usize>,
) -> Result<TimedPath, TimingError> {
    validate(path, max_velocity, max_acceleration, wrap_yaw)?;
    let deltas: Vec<Vec<f64>> = path
        .windows(2)
        .map(|w| {
            w[0].iter()
                .zip(&w[1])
                .enumerate()
                .map(|(i, (a, b))| {
                    let d = b - a;
                    if wrap_yaw == Some(i) {
                        d.sin().atan2(d.cos())
                    } else {
                        d
                    }
                })
                .collect()
        })
        .collect();
    let lengths: Vec<f64> = deltas.iter().map(|d| norm(d)).collect();

    // Runs of segments sharing a direction: [first, end) segment ranges.
    let mut ranges: Vec<(usize, usize)> = Vec::new();
    let mut direction: Option<Vec<f64>> = None;
    for (j, (d, &l)) in deltas.iter().zip(&lengths).enumerate() {
        let u: Option<Vec<f64>> = (l > 0.0).then(|| d.iter().map(|x| x / l).collect());
        let current = ranges.last_mut();
        let joins = match (&current, &u, &direction) {
            (None, _, _) => false,
            // A zero-length segment joins any run; a run of only zero-length segments takes
            // the first direction that comes.
            (Some(_), None, _) | (Some(_), Some(_), None) => true,
            (Some(_), Some(u), Some(r)) => distance(r, u) <= COLLINEAR_TOLERANCE,
        };
        match current {
            Some(range) if joins => {
                range.1 = j + 1;
                if direction.is_none() {
                    direction = u;
                }
            }
            _ => {
                ranges.push((j, j + 1));
                direction = u;
            }
        }
    }

    let mut runs = Vec::with_capacity(ranges.len());
    let mut segments = Vec::with_capacity(deltas.len());
    let mut times = Vec::with_capacity(path.len());
    times.push(0.0);
    let mut clock = 0.0;
    for &(first, end) in &ranges {
        let total: f64 = lengths[first..end].iter().sum();
        let ramp = if total > 0.0 {
            // Per coordinate: the largest |unit direction| over the run, times the run length,
            // is the coordinate's distance per unit of s.
            let mut speed = f64::INFINITY;
            let mut accel = f64::INFINITY;
            for i in 0..max_velocity.len() {
                let m = (first..end)
                    .filter(|&j| lengths[j] > 0.0)
                    .map(|j| deltas[j][i].abs() / lengths[j])
                    .fold(0.0, f64::max);
                if m > 0.0 {
                    speed = speed.min(max_velocity[i] / (total * m));
                    accel = accel.min(max_acceleration[i] / (total * m));
                }
            }
            Ramp::rest_to_rest(clock, speed, accel)
        } else {
            Ramp::empty(clock)
        };
        let run = runs.len();
        let mut covered = 0.0;
        for j in first..end {
            let s0 = if total > 0.0 { covered / total } else { 0.0 };
            covered += lengths[j];
            let (s1, t) = if j + 1 == end {
                (1.0, ramp.end())
            } else {
                let s1 = if total > 0.0 { covered / total } else { 1.0 };
                (s1, ramp.time_at(s1).max(clock))
            };
            clock = clock.max(t);
            times.push(clock);
            segments.push(Segment {
                run,
                s0,
                s1,
                delta: deltas[j].clone(),
            });
        }
        clock = clock.max(ramp.end());
        runs.push(ramp);
    }
    Ok(TimedPath {
        duration: clock,
        times,
        positions: path.to_vec(),
        profile: Profile::Exact { segments, runs },
    })
}

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
/// the phase plane (Kunz & Stilman 2012; see the [module docs](self)). `wrap_yaw = Some(i)`
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
    let exact = time_parameterise(path, max_velocity, max_acceleration, wrap_yaw)?;
    settings.validate()?;
    let geometry = blend::build(path, wrap_yaw, settings.max_deviation);
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

fn validate(
    path: &[Vec<f64>],
    max_velocity: &[f64],
    max_acceleration: &[f64],
    wrap_yaw: Option<usize>,
) -> Result<(), TimingError> {
    let dim = path.first().ok_or(TimingError::EmptyPath)?.len();
    for (index, q) in path.iter().enumerate() {
        if q.len() != dim {
            return Err(TimingError::WaypointDimension {
                index,
                expected: dim,
                got: q.len(),
            });
        }
        if let Some(coordinate) = q.iter().position(|v| !v.is_finite()) {
            return Err(TimingError::NonFiniteWaypoint {
                index,
                coordinate,
                value: q[coordinate],
            });
        }
    }
    for (what, limits) in [
        ("max_velocity", max_velocity),
        ("max_acceleration", max_acceleration),
    ] {
        if limits.len() != dim {
            return Err(TimingError::LimitDimension {
                what,
                expected: dim,
                got: limits.len(),
            });
        }
        if let Some(coordinate) = limits.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(TimingError::InvalidLimit {
                what,
                coordinate,
                value: limits[coordinate],
            });
        }
    }
    match wrap_yaw {
        Some(index) if index >= dim => Err(TimingError::YawIndexOutOfRange {
            index,
            dimension: dim,
        }),
        _ => Ok(()),
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}
