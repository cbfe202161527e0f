//! The phase-plane timing of a blended path (see the [module docs](super) for the scheme):
//! the limit curve, the backward pass (the envelope of the maximum-deceleration curves from
//! the end, the stops and every point of the limit curve), the forward pass at maximum
//! acceleration under that envelope, the timed pieces, and the bound check that makes the
//! limits hold between the knots.
//!
//! Notation: `x = ṡ²` (linear in `s` when `s̈ = u` is constant: `x(s) = x₀ + 2u·(s − s₀)`),
//! `f' = dq/ds` (a unit vector), `f'' = d²q/ds²`. Coordinate `i` moves at `q̇ᵢ = f'ᵢ·ṡ` and
//! accelerates at `q̈ᵢ = f'ᵢ·s̈ + f''ᵢ·ṡ²`.

mod bound;
mod grid;
mod lp;
mod passes;

use super::blend::Geometry;
use bound::bound_ratio;
use grid::grid;
use passes::{backward, forward};

/// One timed piece: constant path acceleration `sdd` from time `t`, `s(t + τ) = s + sd·τ +
/// ½·sdd·τ²`, on path segment `segment` (pieces never straddle segments).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Piece {
    pub t: f64,
    pub s: f64,
    pub sd: f64,
    pub sdd: f64,
    pub segment: usize,
}

/// The timing of a blended path.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Timing {
    pub pieces: Vec<Piece>,
    pub duration: f64,
}

/// Times `geometry` (at least one segment) under the limits; `None` when the numbers break
/// down (the caller falls back to the exact profile).
pub(super) fn integrate(
    geometry: &Geometry,
    vmax: &[f64],
    amax: &[f64],
    time_step: f64,
) -> Option<Timing> {
    let (intervals, caps, knots) = grid(geometry, vmax, amax, time_step);
    let reach = backward(&intervals, &caps, &knots, amax)?;
    let (pieces, duration) = forward(&intervals, &knots, &reach, amax, geometry)?;
    let mut timing = Timing { pieces, duration };
    let scale = bound_ratio(&timing, geometry, vmax, amax)?;
    if scale > 1.0 {
        for p in &mut timing.pieces {
            p.t *= scale;
            p.sd /= scale;
            p.sdd /= scale * scale;
        }
        timing.duration *= scale;
    }
    timing.duration.is_finite().then_some(timing)
}

/// `(s, ṡ)` of piece `p` at time `t` (clamped to the piece, whose end is `end` in time and
/// `s_end` in arc length).
pub(super) fn state(p: &Piece, t: f64, end: f64) -> (f64, f64) {
    let tau = (t - p.t).clamp(0.0, (end - p.t).max(0.0));
    let s = p.s + p.sd * tau + 0.5 * p.sdd * tau * tau;
    let sd = (p.sd + p.sdd * tau).max(0.0);
    (s, sd)
}

/// The time at which piece `p` (ending at `end`) reaches `s` (inverse of [`state`]).
pub(super) fn time_at(p: &Piece, s: f64, end: f64) -> f64 {
    let ds = (s - p.s).max(0.0);
    let disc = (p.sd * p.sd + 2.0 * p.sdd * ds).max(0.0);
    let denom = p.sd + disc.sqrt();
    let tau = if denom > 0.0 { 2.0 * ds / denom } else { 0.0 };
    (p.t + tau).min(end)
}
