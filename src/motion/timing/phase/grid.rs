//! The integration grid: one interval per line, arcs cut into short intervals, the limit
//! curve at the arcs' knots and the rests that cap the speed.

use crate::motion::timing::blend::{Geometry, Shape};

/// Largest turn (rad) of one arc interval: the knots' constraints hold between them up to
/// `~θ²/8` relative (the bound check removes even that).
const MAX_TURN_PER_STEP: f64 = 0.01;
/// Most intervals per arc (bounds the work for extreme settings; accuracy, not safety,
/// depends on it).
const MAX_ARC_STEPS: usize = 4096;

/// One interval of the phase-plane grid: `[s0, s1]` on path segment `segment`.
pub(super) struct Interval {
    pub(super) segment: usize,
    pub(super) s0: f64,
    pub(super) s1: f64,
    pub(super) kind: Kind,
}

pub(super) enum Kind {
    /// Constant limits: `x ≤ xv`, `|s̈| ≤ acc`.
    Line { xv: f64, acc: f64 },
    /// Arc interval between arc knots `knot` and `knot + 1`.
    Arc { knot: usize },
}

/// The path's derivatives and limit curve at the knots of the arcs.
pub(super) struct ArcKnots {
    dim: usize,
    /// Per knot: `f'` then `f''` (2·dim values).
    derivatives: Vec<f64>,
    /// Per knot: the velocity limit `minᵢ vᵢ²/f'ᵢ²` (as `x`).
    pub(super) xv: Vec<f64>,
    /// Per knot: the acceleration limit curve (as `x`).
    pub(super) xa: Vec<f64>,
}

impl ArcKnots {
    pub(super) fn first(&self, k: usize) -> &[f64] {
        &self.derivatives[2 * self.dim * k..2 * self.dim * k + self.dim]
    }
    pub(super) fn second(&self, k: usize) -> &[f64] {
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

/// The integration grid: one interval per line, arcs cut into short intervals (each short
/// enough for [`time_step`](super::BlendSettings::time_step) at the arc's reference speed, and
/// for [`MAX_TURN_PER_STEP`]), the limit curves at the arcs' knots, and `caps[k]`, the most x
/// allowed at knot k by rests (start, end, sharp corners).
pub(super) fn grid(
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
