//! [`TimedPath`]: the waypoints with their times, and the state and velocity at any time
//! along an exact or a blended profile.

use serde::Serialize;

use super::ramp::Ramp;
#[cfg(doc)]
use super::{BlendSettings, time_optimal, time_parameterise};
use super::{blend, phase};

/// A timed path: waypoints with the time at which each is reached, and the profile between
/// them (see the [module docs](super)).
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
    pub(super) profile: Profile,
}

/// The motion behind a [`TimedPath`].
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Profile {
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
pub(super) struct Blended {
    pub(super) geometry: blend::Geometry,
    pub(super) timing: phase::Timing,
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
pub(super) struct Segment {
    pub(super) run: usize,
    pub(super) s0: f64,
    pub(super) s1: f64,
    pub(super) delta: Vec<f64>,
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

    /// The trajectory of the coordinates `range` alone (the others dropped): the same times,
    /// the same time law, each waypoint and every sampled state cut to `range`. For a path
    /// timed in several groups of coordinates together (a base and an arm), each group's own
    /// trajectory, still in step with the others'. [`max_deviation`](Self::max_deviation)
    /// stays the whole path's (an upper bound for any of its coordinates).
    ///
    /// # Panics
    /// Never for a `range` within the waypoints' length; a `range` beyond it is clamped.
    pub fn coordinates(&self, range: std::ops::Range<usize>) -> TimedPath {
        let dim = self.positions.first().map_or(0, Vec::len);
        let range = range.start.min(dim)..range.end.min(dim).max(range.start.min(dim));
        let cut = |v: &Vec<f64>| v[range.clone()].to_vec();
        let profile = match &self.profile {
            Profile::Exact { segments, runs } => Profile::Exact {
                segments: segments
                    .iter()
                    .map(|s| Segment {
                        delta: cut(&s.delta),
                        ..s.clone()
                    })
                    .collect(),
                runs: runs.clone(),
            },
            Profile::Blended(b) => {
                let mut geometry = b.geometry.clone();
                geometry.start = cut(&geometry.start);
                geometry.end = cut(&geometry.end);
                for segment in &mut geometry.segments {
                    segment.shape = match &segment.shape {
                        blend::Shape::Line {
                            from,
                            to,
                            delta,
                            direction,
                            span,
                            lambda0,
                        } => blend::Shape::Line {
                            from: cut(from),
                            to: cut(to),
                            delta: cut(delta),
                            direction: cut(direction),
                            span: *span,
                            lambda0: *lambda0,
                        },
                        blend::Shape::Arc {
                            start,
                            tangent,
                            normal,
                            radius,
                        } => blend::Shape::Arc {
                            start: cut(start),
                            tangent: cut(tangent),
                            normal: cut(normal),
                            radius: *radius,
                        },
                    };
                }
                Profile::Blended(Box::new(Blended {
                    geometry,
                    timing: b.timing.clone(),
                }))
            }
        };
        TimedPath {
            times: self.times.clone(),
            positions: self.positions.iter().map(cut).collect(),
            duration: self.duration,
            profile,
        }
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
