//! The two-variable linear program of an arc interval: the speeds at its two knots that keep
//! every coordinate's acceleration within its limit.

use super::grid::ArcKnots;

/// The linear constraints `α·x + β·y ≤ γ` of an arc interval of width `h` between knots
/// `knot` (`x = ṡ²` there) and `knot + 1` (`y`), with `s̈ = (y − x)/2h` constant: every
/// coordinate's `|f'ᵢ·s̈ + f''ᵢ·ṡ²| ≤ aᵢ` at both knots.
pub(super) fn constraints(
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
pub(super) fn next_range(constraints: &[(f64, f64, f64)], x: f64, ymax: f64) -> (f64, f64) {
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
pub(super) fn largest_start(constraints: &[(f64, f64, f64)], xmax: f64, ymax: f64) -> f64 {
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
