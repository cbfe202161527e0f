//! The phase-plane timing of a blended path (see the [module docs](super) for the scheme):
//! the limit curve, the backward pass (the envelope of the maximum-deceleration curves from
//! the end, the stops and every point of the limit curve), the forward pass at maximum
//! acceleration under that envelope, the timed pieces, and the bound check that makes the
//! limits hold between the knots.
//!
//! Notation: `x = ṡ²` (linear in `s` when `s̈ = u` is constant: `x(s) = x₀ + 2u·(s − s₀)`),
//! `f' = dq/ds` (a unit vector), `f'' = d²q/ds²`. Coordinate `i` moves at `q̇ᵢ = f'ᵢ·ṡ` and
//! accelerates at `q̈ᵢ = f'ᵢ·s̈ + f''ᵢ·ṡ²`.

use super::blend::{Geometry, Shape};

/// Largest turn (rad) of one arc interval: the knots' constraints hold between them up to
/// `~θ²/8` relative (the bound check removes even that).
const MAX_TURN_PER_STEP: f64 = 0.01;
/// Most intervals per arc (bounds the work for extreme settings; accuracy, not safety,
/// depends on it).
const MAX_ARC_STEPS: usize = 4096;
/// Relative accuracy of the bound check's remainder terms.
const CHECK_ACCURACY: f64 = 1e-6;
/// Most sub-samples per piece in the bound check.
const MAX_CHECK_SAMPLES: usize = 64;

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

/// One interval of the phase-plane grid: `[s0, s1]` on path segment `segment`.
struct Interval {
    segment: usize,
    s0: f64,
    s1: f64,
    kind: Kind,
}

enum Kind {
    /// Constant limits: `x ≤ xv`, `|s̈| ≤ acc`.
    Line { xv: f64, acc: f64 },
    /// Arc interval between arc knots `knot` and `knot + 1`.
    Arc { knot: usize },
}

/// The path's derivatives and limit curve at the knots of the arcs.
struct ArcKnots {
    dim: usize,
    /// Per knot: `f'` then `f''` (2·dim values).
    derivatives: Vec<f64>,
    /// Per knot: the velocity limit `minᵢ vᵢ²/f'ᵢ²` (as `x`).
    xv: Vec<f64>,
    /// Per knot: the acceleration limit curve (as `x`).
    xa: Vec<f64>,
}

impl ArcKnots {
    fn first(&self, k: usize) -> &[f64] {
        &self.derivatives[2 * self.dim * k..2 * self.dim * k + self.dim]
    }
    fn second(&self, k: usize) -> &[f64] {
        &self.derivatives[2 * self.dim * k + self.dim..2 * self.dim * (k + 1)]
    }
    fn push(&mut self, first: &[f64], second: &[f64], vmax: &[f64], amax: &[f64]) {
        self.derivatives.extend_from_slice(first);
        self.derivatives.extend_from_slice(second);
        self.xv.push(velocity_limit(first, vmax));
        self.xa.push(acceleration_limit(first, second, amax));
    }
}

/// `ṡ²` allowed by the velocity limits: `minᵢ (vᵢ / |f'ᵢ|)²`.
fn velocity_limit(first: &[f64], vmax: &[f64]) -> f64 {
    first
        .iter()
        .zip(vmax)
        .filter(|(f, _)| **f != 0.0)
        .map(|(f, v)| (v / f).powi(2))
        .fold(f64::INFINITY, f64::min)
}

/// `ṡ²` allowed by the acceleration limits (Kunz & Stilman Eq. (20)–(21)): the feasible
/// `s̈` of coordinate `i` is an interval of half-width `aᵢ/|f'ᵢ|` centred at
/// `−(f''ᵢ/f'ᵢ)·ṡ²`; intervals on a line intersect iff every pair does, i.e.
/// `ṡ²·|f''ᵢ/f'ᵢ − f''ⱼ/f'ⱼ| ≤ aᵢ/|f'ᵢ| + aⱼ/|f'ⱼ|`; a coordinate with `f'ᵢ = 0` needs
/// `|f''ᵢ|·ṡ² ≤ aᵢ`.
fn acceleration_limit(first: &[f64], second: &[f64], amax: &[f64]) -> f64 {
    let mut x = f64::INFINITY;
    for i in 0..first.len() {
        if first[i] == 0.0 {
            if second[i] != 0.0 {
                x = x.min(amax[i] / second[i].abs());
            }
            continue;
        }
        for j in i + 1..first.len() {
            if first[j] == 0.0 {
                continue;
            }
            let spread = (second[i] / first[i] - second[j] / first[j]).abs();
            if spread > 0.0 {
                x = x.min((amax[i] / first[i].abs() + amax[j] / first[j].abs()) / spread);
            }
        }
    }
    x
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

/// The integration grid: one interval per line, arcs cut into short intervals (each short
/// enough for [`time_step`](super::BlendSettings::time_step) at the arc's reference speed, and
/// for [`MAX_TURN_PER_STEP`]), the limit curves at the arcs' knots, and `caps[k]`, the most x
/// allowed at knot k by rests (start, end, sharp corners).
fn grid(
    geometry: &Geometry,
    vmax: &[f64],
    amax: &[f64],
    time_step: f64,
) -> (Vec<Interval>, Vec<f64>, ArcKnots) {
    let dim = vmax.len();
    let mut first = vec![0.0; dim];
    let mut second = vec![0.0; dim];
    let mut knots = ArcKnots {
        dim,
        derivatives: Vec::new(),
        xv: Vec::new(),
        xa: Vec::new(),
    };
    // The grid: one interval per line, arcs cut into short intervals.
    let mut intervals: Vec<Interval> = Vec::new();
    // caps[k]: the most x allowed at knot k by rests (start, end, sharp corners).
    let mut caps = vec![0.0];
    for (index, seg) in geometry.segments.iter().enumerate() {
        match &seg.shape {
            Shape::Line { direction, .. } => {
                let (mut xv, mut acc) = (f64::INFINITY, f64::INFINITY);
                for i in 0..dim {
                    let d = direction[i].abs();
                    if d > 0.0 {
                        xv = xv.min((vmax[i] / d).powi(2));
                        acc = acc.min(amax[i] / d);
                    }
                }
                intervals.push(Interval {
                    segment: index,
                    s0: seg.s0,
                    s1: seg.s0 + seg.length,
                    kind: Kind::Line { xv, acc },
                });
                caps.push(f64::INFINITY);
            }
            Shape::Arc { radius, .. } => {
                // Reference speed: the limit curve at the ends and the middle.
                let mut reference: f64 = 0.0;
                for sigma in [0.0, 0.5 * seg.length, seg.length] {
                    seg.derivatives(sigma, &mut first, &mut second);
                    let x =
                        velocity_limit(&first, vmax).min(acceleration_limit(&first, &second, amax));
                    reference = reference.max(x.sqrt());
                }
                let step = (time_step * reference).min(radius * MAX_TURN_PER_STEP);
                let count = if step > 0.0 && step.is_finite() {
                    ((seg.length / step).ceil() as usize).clamp(1, MAX_ARC_STEPS)
                } else {
                    MAX_ARC_STEPS
                };
                let base = knots.xv.len();
                for k in 0..=count {
                    let sigma = seg.length * k as f64 / count as f64;
                    seg.derivatives(sigma, &mut first, &mut second);
                    knots.push(&first, &second, vmax, amax);
                }
                for k in 0..count {
                    let s0 = seg.s0 + seg.length * k as f64 / count as f64;
                    let s1 = if k + 1 == count {
                        seg.s0 + seg.length
                    } else {
                        seg.s0 + seg.length * (k + 1) as f64 / count as f64
                    };
                    intervals.push(Interval {
                        segment: index,
                        s0,
                        s1,
                        kind: Kind::Arc { knot: base + k },
                    });
                    caps.push(f64::INFINITY);
                }
            }
        }
        if seg.stop_at_end {
            *caps.last_mut().expect("non-empty") = 0.0;
        }
    }
    *caps.last_mut().expect("non-empty") = 0.0;
    (intervals, caps, knots)
}

/// The backward pass: `reach[k]`, the most x at knot k from which the end can be reached;
/// `None` if the envelope breaks down (NaN or negative).
fn backward(
    intervals: &[Interval],
    caps: &[f64],
    knots: &ArcKnots,
    amax: &[f64],
) -> Option<Vec<f64>> {
    let dim = amax.len();
    let n = intervals.len();
    let mut reach = vec![0.0f64; n + 1];
    let mut buffer = Vec::with_capacity(4 * dim);
    for k in (0..n).rev() {
        let iv = &intervals[k];
        let width = iv.s1 - iv.s0;
        reach[k] = caps[k].min(match iv.kind {
            Kind::Line { xv, acc } => xv.min(reach[k + 1].min(xv) + 2.0 * width * acc),
            // An interval lost to rounding (s0 + width == s0): nothing to constrain.
            Kind::Arc { .. } if width <= 0.0 => reach[k + 1],
            Kind::Arc { knot } => {
                constraints(knots, knot, width, amax, &mut buffer);
                let ymax = reach[k + 1].min(knots.xv[knot + 1]);
                let xmax = caps[k].min(knots.xv[knot]).min(knots.xa[knot]);
                largest_start(&buffer, xmax, ymax)
            }
        });
        if reach[k].is_nan() || reach[k] < 0.0 {
            return None;
        }
    }
    Some(reach)
}

/// The forward pass at the largest acceleration under the envelope `reach`, into timed pieces;
/// with the duration.
fn forward(
    intervals: &[Interval],
    knots: &ArcKnots,
    reach: &[f64],
    amax: &[f64],
    geometry: &Geometry,
) -> Option<(Vec<Piece>, f64)> {
    let n = intervals.len();
    let dim = amax.len();
    let mut buffer = Vec::with_capacity(4 * dim);
    let mut pieces = Vec::with_capacity(n + 2 * geometry.segments.len());
    let mut t = 0.0;
    let mut x = 0.0;
    for (k, iv) in intervals.iter().enumerate() {
        let width = iv.s1 - iv.s0;
        match iv.kind {
            Kind::Line { xv, acc } => {
                let y = xv.min(reach[k + 1]).min(x + 2.0 * width * acc);
                // x(σ) = min(x + 2·acc·σ, xv, y + 2·acc·(width − σ)).
                let cross = ((y - x + 2.0 * acc * width) / (4.0 * acc)).clamp(0.0, width);
                let peak = x + 2.0 * acc * cross;
                let mut knots_here: Vec<(f64, f64)> = vec![(0.0, x)];
                if peak <= xv {
                    knots_here.push((cross, peak));
                } else {
                    let a = ((xv - x) / (2.0 * acc)).max(0.0).min(width);
                    let b = (width - (xv - y) / (2.0 * acc)).max(a).min(width);
                    knots_here.push((a, xv));
                    knots_here.push((b, xv));
                }
                knots_here.push((width, y));
                for w in knots_here.windows(2) {
                    push_piece(&mut pieces, &mut t, iv, w[0], w[1])?;
                }
                x = y;
            }
            Kind::Arc { .. } if width <= 0.0 => x = x.min(reach[k + 1]),
            Kind::Arc { knot } => {
                constraints(knots, knot, width, amax, &mut buffer);
                let ymax = reach[k + 1].min(knots.xv[knot + 1]);
                let (lo, hi) = next_range(&buffer, x, ymax);
                // Empty only through rounding (x ≤ reach[k] is controllable): keep the
                // slower end; the bound check covers the difference.
                let y = if lo <= hi { hi } else { hi.max(0.0).min(ymax) };
                push_piece(&mut pieces, &mut t, iv, (0.0, x), (width, y))?;
                x = y;
            }
        }
    }
    Some((pieces, t))
}

/// Appends the piece from `(σ₀, x₀)` to `(σ₁, x₁)` (local to `iv`, `x` linear in between) if
/// it has positive length.
fn push_piece(
    pieces: &mut Vec<Piece>,
    t: &mut f64,
    iv: &Interval,
    (sigma0, x0): (f64, f64),
    (sigma1, x1): (f64, f64),
) -> Option<()> {
    let ds = sigma1 - sigma0;
    if ds <= 0.0 {
        return Some(());
    }
    let (sd0, sd1) = (x0.max(0.0).sqrt(), x1.max(0.0).sqrt());
    let tau = 2.0 * ds / (sd0 + sd1);
    if !(tau.is_finite() && tau > 0.0) {
        return None;
    }
    pieces.push(Piece {
        t: *t,
        s: iv.s0 + sigma0,
        sd: sd0,
        sdd: (sd1 - sd0) / tau,
        segment: iv.segment,
    });
    *t += tau;
    Some(())
}

/// The linear constraints `α·x + β·y ≤ γ` of an arc interval of width `h` between knots
/// `knot` (`x = ṡ²` there) and `knot + 1` (`y`), with `s̈ = (y − x)/2h` constant: every
/// coordinate's `|f'ᵢ·s̈ + f''ᵢ·ṡ²| ≤ aᵢ` at both knots.
fn constraints(
    knots: &ArcKnots,
    knot: usize,
    h: f64,
    amax: &[f64],
    out: &mut Vec<(f64, f64, f64)>,
) {
    out.clear();
    let w = 0.5 / h;
    let (pa, qa) = (knots.first(knot), knots.second(knot));
    let (pb, qb) = (knots.first(knot + 1), knots.second(knot + 1));
    for i in 0..amax.len() {
        // At the first knot: pa·w·(y − x) + qa·x.
        let (alpha, beta) = (qa[i] - pa[i] * w, pa[i] * w);
        out.push((alpha, beta, amax[i]));
        out.push((-alpha, -beta, amax[i]));
        // At the second knot: pb·w·(y − x) + qb·y.
        let (alpha, beta) = (-pb[i] * w, pb[i] * w + qb[i]);
        out.push((alpha, beta, amax[i]));
        out.push((-alpha, -beta, amax[i]));
    }
}

/// The range of `y ∈ [0, ymax]` that satisfies `constraints` with the first knot at `x`
/// (empty, `lo > hi`, if none does).
fn next_range(constraints: &[(f64, f64, f64)], x: f64, ymax: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (0.0f64, ymax);
    for &(alpha, beta, gamma) in constraints {
        let rest = gamma - alpha * x;
        if beta > 0.0 {
            hi = hi.min(rest / beta);
        } else if beta < 0.0 {
            lo = lo.max(rest / beta);
        } else if rest < 0.0 {
            return (1.0, 0.0);
        }
    }
    (lo, hi)
}

/// The largest `x ∈ [0, xmax]` from which some `y ∈ [0, ymax]` satisfies `constraints`.
///
/// For a given `x` the feasible `y` are `[L(x), U(x)]`, `L` the largest of the lower bounds
/// (lines in `x`, and 0), `U` the smallest of the upper ones (and `ymax`): `h = U − L` is
/// concave and piecewise linear, `h(0) ≥ 0` (`(0, 0)` is feasible: every `γ > 0`), and the
/// answer is `xmax` if `h(xmax) ≥ 0`, else the root of `h`. Newton's method from the right
/// on a concave function never overshoots the root (each active piece's line lies above
/// `h`) and meets it after at most one step per piece; bisection backs it up should
/// rounding stall it.
fn largest_start(constraints: &[(f64, f64, f64)], xmax: f64, ymax: f64) -> f64 {
    // Constraints without y bound x alone (γ > 0: only α > 0 can bind).
    let mut xmax = xmax;
    for &(alpha, beta, gamma) in constraints {
        if beta == 0.0 && alpha > 0.0 {
            xmax = xmax.min(gamma / alpha);
        }
    }
    if xmax.is_nan() || xmax <= 0.0 {
        return 0.0;
    }
    // h(x) and its slope from the active pieces.
    let gap = |x: f64| {
        let (mut lo, mut lo_slope) = (0.0f64, 0.0f64);
        let (mut hi, mut hi_slope) = (ymax, 0.0f64);
        for &(alpha, beta, gamma) in constraints {
            if beta > 0.0 {
                let y = (gamma - alpha * x) / beta;
                if y < hi {
                    hi = y;
                    hi_slope = -alpha / beta;
                }
            } else if beta < 0.0 {
                let y = (gamma - alpha * x) / beta;
                if y > lo {
                    lo = y;
                    lo_slope = -alpha / beta;
                }
            }
        }
        (hi - lo, hi_slope - lo_slope, hi.abs().max(lo.abs()))
    };
    let mut x = xmax;
    for _ in 0..64 {
        let (h, slope, size) = gap(x);
        if h >= -1e-14 * size {
            return x;
        }
        if slope.is_nan() || slope >= 0.0 {
            break;
        }
        let next = x - h / slope;
        if !(next < x && next >= 0.0) {
            break;
        }
        x = next;
    }
    // Rounding stalled Newton: bisect on [0, x].
    let (mut lo, mut hi) = (0.0, x);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if gap(mid).0 >= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    lo
}

/// The factor `k ≥ 1` by which stretching time makes the pieces satisfy the limits
/// everywhere, not only at the knots: `max(1, maxᵢ max |q̇ᵢ|/vᵢ, √(maxᵢ max |q̈ᵢ|/aᵢ))` over
/// rigorous bounds per piece. On a line `q̇ᵢ = f'ᵢ·ṡ` (extreme at the piece's ends, `ṡ`
/// being linear in time) and `q̈ᵢ = f'ᵢ·s̈` are exact. On an arc the values at sub-samples
/// `τⱼ` are bounded in between by the interpolation remainder `Δτ²/8 · max|g''|`, with (from
/// `|f'ᵢ|, r|f''ᵢ|, r²|f'''ᵢ|, r³|f''''ᵢ| ≤ ρᵢ`, `s⃛ = 0`, `ṡ ≤ ṡₘ`)
/// - velocity `g = f'ᵢ·ṡ`: `|g''| = |f'''ᵢ·ṡ³ + 3f''ᵢ·ṡ·s̈| ≤ ρᵢ(ṡₘ³/r² + 3ṡₘ|s̈|/r)`;
/// - acceleration `g = f'ᵢ·s̈ + f''ᵢ·ṡ²`: `|g''| = |f''''ᵢ·ṡ⁴ + 6f'''ᵢ·ṡ²·s̈ + 3f''ᵢ·s̈²|
///   ≤ ρᵢ(ṡₘ⁴/r³ + 6ṡₘ²|s̈|/r² + 3s̈²/r)`.
///
/// `None` if a value is not finite.
fn bound_ratio(timing: &Timing, geometry: &Geometry, vmax: &[f64], amax: &[f64]) -> Option<f64> {
    let dim = vmax.len();
    let mut first = vec![0.0; dim];
    let mut second = vec![0.0; dim];
    let (mut rv, mut ra): (f64, f64) = (0.0, 0.0);
    for (k, p) in timing.pieces.iter().enumerate() {
        let end = timing.pieces.get(k + 1).map_or(timing.duration, |q| q.t);
        let tau = end - p.t;
        let sd_end = p.sd + p.sdd * tau;
        let sd_max = p.sd.max(sd_end).max(0.0);
        let seg = &geometry.segments[p.segment];
        match seg.arc_amplitudes() {
            None => {
                seg.derivatives(0.0, &mut first, &mut second);
                for i in 0..dim {
                    rv = rv.max(first[i].abs() * sd_max / vmax[i]);
                    ra = ra.max((first[i] * p.sdd).abs() / amax[i]);
                }
            }
            Some((rho, r)) => {
                let u = p.sdd.abs();
                // Remainder coefficients (times Δτ²/8), relative to the limits.
                let (mut cv, mut ca): (f64, f64) = (0.0, 0.0);
                for i in 0..dim {
                    cv = cv
                        .max(rho[i] * (sd_max.powi(3) / (r * r) + 3.0 * sd_max * u / r) / vmax[i]);
                    ca = ca.max(
                        rho[i]
                            * (sd_max.powi(4) / r.powi(3)
                                + 6.0 * sd_max * sd_max * u / (r * r)
                                + 3.0 * u * u / r)
                            / amax[i],
                    );
                }
                let remainder = tau * tau / 8.0 * cv.max(ca);
                let samples = if remainder > CHECK_ACCURACY {
                    ((remainder / CHECK_ACCURACY).sqrt().ceil() as usize)
                        .clamp(1, MAX_CHECK_SAMPLES)
                } else {
                    1
                };
                let dt = tau / samples as f64;
                let (mut pv, mut pa): (f64, f64) = (0.0, 0.0);
                for j in 0..=samples {
                    let tj = dt * j as f64;
                    let sd = (p.sd + p.sdd * tj).max(0.0);
                    let sigma = p.s + p.sd * tj + 0.5 * p.sdd * tj * tj - seg.s0;
                    seg.derivatives(sigma, &mut first, &mut second);
                    for i in 0..dim {
                        pv = pv.max((first[i] * sd).abs() / vmax[i]);
                        pa = pa.max((first[i] * p.sdd + second[i] * sd * sd).abs() / amax[i]);
                    }
                }
                // Between sub-samples a coordinate exceeds its sampled maximum by at most the
                // interpolation remainder.
                let h2 = dt * dt / 8.0;
                rv = rv.max(pv + h2 * cv);
                ra = ra.max(pa + h2 * ca);
            }
        }
    }
    let scale = 1.0f64.max(rv).max(ra.sqrt());
    scale.is_finite().then_some(scale)
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
