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
//! [`time_differential_drive`] times a differential-drive base path (turns in place and straight
//! drives) exactly, under the forward speed and the yaw rate instead of per axis.
//! [`time_whole_body_differential`] times a base-and-arm path of a differential-drive robot
//! (the base moving along with the arm) exactly, the base under its planar speed and yaw rate.
//! [`TimedPath::coordinates`] cuts a path timed in several groups of coordinates into each
//! group's trajectory, in step.
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
mod differential;
mod error;
mod exact;
mod optimal;
mod phase;
mod ramp;
mod timed_path;
mod whole_body;

pub use differential::{SIDEWAYS_TOLERANCE, time_differential_drive};
pub use error::TimingError;
pub use exact::time_parameterise;
pub use optimal::{BlendSettings, time_optimal, time_optimal_stopping};
pub(crate) use ramp::rest_to_rest_time;
pub use timed_path::TimedPath;
pub use whole_body::time_whole_body_differential;

/// Two segment directions (unit vectors) closer than this count as the same direction: the
/// profile does not stop between them. The velocity jump there is at most this fraction of
/// the speed (1e-12), far below any controller's resolution.
pub const COLLINEAR_TOLERANCE: f64 = 1e-12;

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
