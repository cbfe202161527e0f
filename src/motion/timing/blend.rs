//! The blended path of [`time_optimal`](super::time_optimal): the piecewise-linear path with
//! every interior corner replaced by a circular arc tangent to both segments (Kunz & Stilman
//! 2012, Section IV), parameterised by arc length `s`.
//!
//! # The blend of one corner
//! A corner `q` between unit directions `u` (in) and `w` (out) turns by
//! `α = 2·atan2(|w − u|, |w + u|)`. The arc starts `ℓ` before `q` on the incoming segment and
//! ends `ℓ` after it on the outgoing one, with
//!
//! `ℓ = min(L_in / 2, L_out / 2, δ / tan(α/4))`, radius `r = ℓ / tan(α/2)`,
//!
//! (`δ` the allowed deviation, `L` the segment lengths: an arc uses at most half of each
//! segment, so neighbouring arcs never overlap). The corner is `ℓ·tan(α/4) ≤ δ` from the arc
//! (the arc's midpoint is the nearest point); every other point of the arc is nearer to the
//! segments than that. `δ / tan(α/4)` is the paper's `δ·sin(α/2) / (1 − cos(α/2))`, written
//! without the cancellation at small angles.
//!
//! The arc is stored by its start `p`, the incoming direction `u` and the unit normal `n`
//! (`w`'s part orthogonal to `u`): `f(σ) = p + u·r·sin(σ/r) + n·2r·sin²(σ/2r)` for
//! `σ ∈ [0, r·α]`. Unlike the centre form `c + r·(…)` this stays accurate for huge radii
//! (nearly collinear corners).
//!
//! Corners turning by at most [`COLLINEAR_TOLERANCE`] are passed straight (no arc, as in
//! [`time_parameterise`](super::time_parameterise)); a reversal (`|w + u| ≤`
//! [`REVERSAL_TOLERANCE`], where the normal is undefined) keeps its sharp corner and the
//! trajectory stops there.

use super::COLLINEAR_TOLERANCE;

/// A corner whose directions satisfy `|w + u| ≤ REVERSAL_TOLERANCE` (a turn within about
/// 1e-9 rad of π) is not blended: the trajectory stops there.
pub(super) const REVERSAL_TOLERANCE: f64 = 1e-9;

/// The blended path.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Geometry {
    /// Lines and arcs, in order, each of positive length.
    pub segments: Vec<PathSegment>,
    /// Total arc length.
    pub length: f64,
    /// Per given waypoint: the `s` nearest to it (a blended corner: its arc's midpoint).
    pub waypoint_s: Vec<f64>,
    /// The first waypoint, as given.
    pub start: Vec<f64>,
    /// The last waypoint, unwrapped (as given unless a yaw coordinate wrapped).
    pub end: Vec<f64>,
    /// Corners replaced by an arc.
    pub blends: usize,
    /// The largest distance from a blended corner to its arc.
    pub max_deviation: f64,
}

/// One piece of the blended path: `s ∈ [s0, s0 + length]`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct PathSegment {
    /// Arc length at the start.
    pub s0: f64,
    /// Arc length of the piece, > 0.
    pub length: f64,
    /// The trajectory must be at rest at the end of this piece (a sharp corner).
    pub stop_at_end: bool,
    /// Its shape.
    pub shape: Shape,
}

/// A line (part of one segment of the given path) or an arc.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Shape {
    /// `q = from + delta·λ`, `λ = lambda0 + σ / span` (`span = |delta|`); `to = from + delta`
    /// exactly, returned at `λ ≥ 1`.
    Line {
        from: Vec<f64>,
        to: Vec<f64>,
        delta: Vec<f64>,
        /// `delta / span`.
        direction: Vec<f64>,
        span: f64,
        lambda0: f64,
    },
    /// `q = start + tangent·r·sin(σ/r) + normal·2r·sin²(σ/2r)`.
    Arc {
        start: Vec<f64>,
        tangent: Vec<f64>,
        normal: Vec<f64>,
        radius: f64,
    },
}

impl PathSegment {
    /// The position at local arc length `sigma` (clamped to the piece).
    pub fn position(&self, sigma: f64) -> Vec<f64> {
        let sigma = sigma.clamp(0.0, self.length);
        match &self.shape {
            Shape::Line {
                from,
                to,
                delta,
                span,
                lambda0,
                ..
            } => {
                let lambda = lambda0 + sigma / span;
                if lambda >= 1.0 {
                    to.clone()
                } else {
                    from.iter()
                        .zip(delta)
                        .map(|(p, d)| p + d * lambda)
                        .collect()
                }
            }
            Shape::Arc {
                start,
                tangent,
                normal,
                radius,
            } => {
                let r = *radius;
                let along = r * (sigma / r).sin();
                let inward = 2.0 * r * (0.5 * sigma / r).sin().powi(2);
                start
                    .iter()
                    .zip(tangent.iter().zip(normal))
                    .map(|(p, (t, n))| p + t * along + n * inward)
                    .collect()
            }
        }
    }

    /// `f'(σ)` (a unit vector) and `f''(σ)` into the two buffers.
    pub fn derivatives(&self, sigma: f64, first: &mut [f64], second: &mut [f64]) {
        let sigma = sigma.clamp(0.0, self.length);
        match &self.shape {
            Shape::Line { direction, .. } => {
                first.copy_from_slice(direction);
                second.fill(0.0);
            }
            Shape::Arc {
                tangent,
                normal,
                radius,
                ..
            } => {
                let (sin, cos) = (sigma / radius).sin_cos();
                for i in 0..first.len() {
                    first[i] = tangent[i] * cos + normal[i] * sin;
                    second[i] = (normal[i] * cos - tangent[i] * sin) / radius;
                }
            }
        }
    }

    /// Per coordinate `i`, an amplitude `ρᵢ` with `|f'ᵢ| ≤ ρᵢ`, `|f''ᵢ| ≤ ρᵢ/r`,
    /// `|f'''ᵢ| ≤ ρᵢ/r²`, … on an arc (`None` for a line: `f'' = 0`), and the radius.
    pub fn arc_amplitudes(&self) -> Option<(Vec<f64>, f64)> {
        match &self.shape {
            Shape::Line { .. } => None,
            Shape::Arc {
                tangent,
                normal,
                radius,
                ..
            } => Some((
                tangent
                    .iter()
                    .zip(normal)
                    .map(|(t, n)| t.hypot(*n))
                    .collect(),
                *radius,
            )),
        }
    }
}

/// How an interior corner is passed.
#[derive(Debug, Clone)]
enum Corner {
    /// Collinear: no arc, no stop.
    Straight,
    /// Blended by an arc.
    Blend {
        ell: f64,
        radius: f64,
        angle: f64,
        normal: Vec<f64>,
    },
    /// Kept sharp: the trajectory stops at the corner.
    Stop,
}

/// Builds the blended path of `path` (validated: non-empty, equal finite waypoints) with
/// corners cut by at most `max_deviation` (> 0), except at the waypoints of `stop_at`
/// (indices into `path`), which stay sharp stops. With `wrap_yaw = Some(i)`, coordinate `i` is
/// unwrapped first (each step the short way).
pub(super) fn build(
    path: &[Vec<f64>],
    wrap_yaw: Option<usize>,
    max_deviation: f64,
    stop_at: &[usize],
) -> Geometry {
    let unwrapped = unwrap(path, wrap_yaw);
    // Distinct consecutive points; `index[j]`: the distinct point waypoint j is.
    let mut points: Vec<&Vec<f64>> = vec![&unwrapped[0]];
    let mut index = vec![0usize];
    for q in &unwrapped[1..] {
        if q != *points.last().expect("non-empty") {
            points.push(q);
        }
        index.push(points.len() - 1);
    }
    let deltas: Vec<Vec<f64>> = points
        .windows(2)
        .map(|w| w[0].iter().zip(w[1]).map(|(a, b)| b - a).collect())
        .collect();
    let spans: Vec<f64> = deltas.iter().map(|d| super::norm(d)).collect();
    let directions: Vec<Vec<f64>> = deltas
        .iter()
        .zip(&spans)
        .map(|(d, l)| d.iter().map(|x| x / l).collect())
        .collect();

    // corners[k]: the corner at distinct point k (only 1..points.len() − 1 are real).
    let mut corners = vec![Corner::Straight; points.len()];
    for k in 1..points.len().saturating_sub(1) {
        // A waypoint asked to stop at is a stop whatever its angle (a straight one too).
        if index
            .iter()
            .enumerate()
            .any(|(j, &p)| p == k && stop_at.contains(&j))
        {
            corners[k] = Corner::Stop;
            continue;
        }
        corners[k] = corner(
            &directions[k - 1],
            &directions[k],
            spans[k - 1],
            spans[k],
            max_deviation,
        );
    }

    let mut segments = Vec::new();
    let mut point_s = vec![0.0; points.len()];
    let mut s = 0.0;
    let mut blends = 0;
    let mut deviation: f64 = 0.0;
    for k in 0..deltas.len() {
        let lambda0 = match &corners[k] {
            Corner::Blend { ell, .. } => ell / spans[k],
            _ => 0.0,
        };
        let lambda1 = match &corners[k + 1] {
            Corner::Blend { ell, .. } => 1.0 - ell / spans[k],
            _ => 1.0,
        };
        if !matches!(corners[k], Corner::Blend { .. }) {
            point_s[k] = s;
        }
        let length = (lambda1 - lambda0) * spans[k];
        if length > 0.0 {
            segments.push(PathSegment {
                s0: s,
                length,
                stop_at_end: false,
                shape: Shape::Line {
                    from: points[k].clone(),
                    to: points[k + 1].clone(),
                    delta: deltas[k].clone(),
                    direction: directions[k].clone(),
                    span: spans[k],
                    lambda0,
                },
            });
            s += length;
        }
        match &corners[k + 1] {
            Corner::Blend {
                ell,
                radius,
                angle,
                normal,
            } => {
                let start = points[k]
                    .iter()
                    .zip(&deltas[k])
                    .map(|(p, d)| p + d * lambda1)
                    .collect();
                let length = radius * angle;
                segments.push(PathSegment {
                    s0: s,
                    length,
                    stop_at_end: false,
                    shape: Shape::Arc {
                        start,
                        tangent: directions[k].clone(),
                        normal: normal.clone(),
                        radius: *radius,
                    },
                });
                point_s[k + 1] = s + 0.5 * length;
                s += length;
                blends += 1;
                deviation = deviation.max(ell * (0.25 * angle).tan());
            }
            Corner::Stop => {
                if let Some(last) = segments.last_mut() {
                    last.stop_at_end = true;
                }
            }
            Corner::Straight => {}
        }
    }
    if let Some(last) = point_s.last_mut() {
        *last = s;
    }
    Geometry {
        segments,
        length: s,
        waypoint_s: index.iter().map(|&k| point_s[k]).collect(),
        start: path[0].clone(),
        end: unwrapped.last().expect("non-empty").clone(),
        blends,
        max_deviation: deviation,
    }
}

/// The blend of the corner between unit directions `u` (in, segment length `l_in`) and `w`
/// (out, `l_out`).
fn corner(u: &[f64], w: &[f64], l_in: f64, l_out: f64, max_deviation: f64) -> Corner {
    let diff = super::distance(w, u);
    let sum: f64 = u
        .iter()
        .zip(w)
        .map(|(a, b)| (a + b).powi(2))
        .sum::<f64>()
        .sqrt();
    let angle = 2.0 * diff.atan2(sum);
    if angle <= COLLINEAR_TOLERANCE {
        return Corner::Straight;
    }
    if sum <= REVERSAL_TOLERANCE {
        return Corner::Stop;
    }
    let ell = (0.5 * l_in)
        .min(0.5 * l_out)
        .min(max_deviation / (0.25 * angle).tan());
    let radius = ell / (0.5 * angle).tan();
    let dot: f64 = u.iter().zip(w).map(|(a, b)| a * b).sum();
    let normal: Vec<f64> = w.iter().zip(u).map(|(b, a)| b - dot * a).collect();
    let size = super::norm(&normal);
    let normal: Vec<f64> = normal.iter().map(|x| x / size).collect();
    let usable = ell > 0.0
        && radius > 0.0
        && (radius * angle).is_finite()
        && radius * angle > 0.0
        && normal.iter().all(|x| x.is_finite());
    if usable {
        Corner::Blend {
            ell,
            radius,
            angle,
            normal,
        }
    } else {
        Corner::Stop
    }
}

/// The path with coordinate `wrap_yaw` unwrapped: waypoint `j`'s angle plus `2π·kⱼ`, `kⱼ`
/// chosen so that each step turns the short way (as `time_parameterise` turns). Without
/// wrapping (or where no step wraps) the values are the given ones, bit for bit.
fn unwrap(path: &[Vec<f64>], wrap_yaw: Option<usize>) -> Vec<Vec<f64>> {
    let mut out = path.to_vec();
    let Some(i) = wrap_yaw else {
        return out;
    };
    let tau = std::f64::consts::TAU;
    let mut turns = 0.0;
    for j in 1..path.len() {
        let raw = path[j][i] - path[j - 1][i];
        let short = raw.sin().atan2(raw.cos());
        turns += ((short - raw) / tau).round();
        out[j][i] = path[j][i] + tau * turns;
    }
    out
}
