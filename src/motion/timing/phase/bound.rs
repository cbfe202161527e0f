//! The bound check between the knots: the factor by which time is stretched so that the
//! limits hold at every instant.

use super::Timing;
use crate::motion::timing::blend::Geometry;

/// Relative accuracy of the bound check's remainder terms.
const CHECK_ACCURACY: f64 = 1e-6;
/// Most sub-samples per piece in the bound check.
const MAX_CHECK_SAMPLES: usize = 64;

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
pub(super) fn bound_ratio(
    timing: &Timing,
    geometry: &Geometry,
    vmax: &[f64],
    amax: &[f64],
) -> Option<f64> {
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
