//! The two passes over the grid: backward, the largest speed from which the end can be
//! reached; forward, the largest acceleration under it, into timed pieces.

use super::Piece;
use super::grid::{ArcKnots, Interval, Kind};
use super::lp::{constraints, largest_start, next_range};
use crate::motion::timing::blend::Geometry;

/// The backward pass: `reach[k]`, the most x at knot k from which the end can be reached;
/// `None` if the envelope breaks down (NaN or negative).
pub(super) fn backward(
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
pub(super) fn forward(
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
