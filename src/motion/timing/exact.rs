//! [`time_parameterise`]: the exact profile, rest to rest along each run of collinear
//! segments, and the checks of its input.

use super::ramp::Ramp;
use super::timed_path::{Profile, Segment};
use super::{COLLINEAR_TOLERANCE, TimedPath, TimingError, distance, norm};

/// Times `path` under `max_velocity` and `max_acceleration` (one per coordinate, units per
/// second and per second²), stopping at every corner; see the [module docs](super) for the
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
    let deltas = deltas(path, wrap_yaw);
    Ok(profile(
        path,
        &deltas,
        &|run: &[(&[f64], f64)], total: f64| {
            // Per coordinate: the largest |unit direction| over the run, times the run length,
            // is the coordinate's distance per unit of s.
            let mut speed = f64::INFINITY;
            let mut accel = f64::INFINITY;
            for i in 0..max_velocity.len() {
                let m = run
                    .iter()
                    .filter(|(_, l)| *l > 0.0)
                    .map(|(d, l)| d[i].abs() / l)
                    .fold(0.0, f64::max);
                if m > 0.0 {
                    speed = speed.min(max_velocity[i] / (total * m));
                    accel = accel.min(max_acceleration[i] / (total * m));
                }
            }
            (speed, accel)
        },
    ))
}

/// The differences between consecutive waypoints, coordinate `wrap_yaw` wrapped into `[-π, π]`.
pub(super) fn deltas(path: &[Vec<f64>], wrap_yaw: Option<usize>) -> Vec<Vec<f64>> {
    path.windows(2)
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
        .collect()
}

/// Limits of one run: its segments' `(delta, length)` and its total length give the largest
/// `ṡ` and `s̈` (s from 0 to 1 over the run).
pub(super) type RunLimits<'a> = dyn Fn(&[(&[f64], f64)], f64) -> (f64, f64) + 'a;

/// The exact profile of `path` (segments `deltas`), rest to rest along each run of collinear
/// segments, each run under the `ṡ`, `s̈` limits `run_limits` gives.
pub(super) fn profile(
    path: &[Vec<f64>],
    deltas: &[Vec<f64>],
    run_limits: &RunLimits<'_>,
) -> TimedPath {
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
            let run: Vec<(&[f64], f64)> = (first..end)
                .map(|j| (deltas[j].as_slice(), lengths[j]))
                .collect();
            let (speed, accel) = run_limits(&run, total);
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
    TimedPath {
        duration: clock,
        times,
        positions: path.to_vec(),
        profile: Profile::Exact { segments, runs },
    }
}

pub(super) fn validate(
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
