//! Time parameterisation of piecewise-linear paths under per-coordinate velocity and
//! acceleration limits.
//!
//! [`time_parameterise`] times a path (base or arm) so that it is followed *exactly*: between
//! waypoints the state moves on the straight segment (the geometry the planner checked), every
//! coordinate `i` within `|q̇ᵢ| ≤ max_velocity[i]` and `|q̈ᵢ| ≤ max_acceleration[i]`.
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
//! corners (blends), which leave the path the planner checked, so none is produced: the
//! planner's simplified paths should be smooth enough, or the corner cut separately checked,
//! before such a blend is used.
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

mod error;
mod ramp;

use serde::Serialize;

pub use error::TimingError;
use ramp::Ramp;

/// Two segment directions (unit vectors) closer than this count as the same direction: the
/// profile does not stop between them. The velocity jump there is at most this fraction of
/// the speed (1e-12), far below any controller's resolution.
pub const COLLINEAR_TOLERANCE: f64 = 1e-12;

/// A timed path: waypoints with the time at which each is reached, and the profile between
/// them (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimedPath {
    /// Time (s) at which each waypoint is reached, from 0, non-decreasing.
    pub times: Vec<f64>,
    /// The waypoints, as given.
    pub positions: Vec<Vec<f64>>,
    /// Total duration (s), the last of `times`.
    pub duration: f64,
    /// One per segment (waypoint `j` to `j + 1`).
    segments: Vec<Segment>,
    /// One per run of collinear segments.
    runs: Vec<Ramp>,
}

/// A segment inside its run: `q = positions[j] + f·delta`, `f = (s − s0) / (s1 − s0)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
struct Segment {
    run: usize,
    s0: f64,
    s1: f64,
    delta: Vec<f64>,
}

impl TimedPath {
    /// The state at time `t` (s), clamped to `[0, duration]` (NaN counts as 0). At a
    /// waypoint's time it is that waypoint, exactly.
    pub fn sample(&self, t: f64) -> Vec<f64> {
        match self.locate(t) {
            Located::Waypoint(k) => self.positions[k].clone(),
            Located::Inside(j, t) => {
                let seg = &self.segments[j];
                let (s, _) = self.runs[seg.run].eval(t);
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
    /// as 0). At a corner it is zero; at a waypoint inside a run, the following segment's.
    pub fn velocity(&self, t: f64) -> Vec<f64> {
        let dim = self.positions[0].len();
        let (j, t) = match self.locate(t) {
            Located::Waypoint(k) if k == 0 || k + 1 == self.positions.len() => {
                return vec![0.0; dim];
            }
            // Interior waypoint: segment k starts here and has a positive duration.
            Located::Waypoint(k) => (k, self.times[k]),
            Located::Inside(j, t) => (j, t),
        };
        let seg = &self.segments[j];
        let (_, ds) = self.runs[seg.run].eval(t);
        let width = seg.s1 - seg.s0;
        if width > 0.0 {
            seg.delta.iter().map(|d| ds * d / width).collect()
        } else {
            vec![0.0; dim]
        }
    }

    /// Where `t` falls: exactly on (or clamped to) waypoint `k`, or strictly inside segment `j`
    /// (which then has a positive duration).
    fn locate(&self, t: f64) -> Located {
        let t = if t.is_nan() { 0.0 } else { t };
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
        segments,
        runs,
    })
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
