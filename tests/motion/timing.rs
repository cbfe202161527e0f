//! Time parameterisation: limits everywhere, waypoints reached, hand-derived durations; and
//! the blended time-optimal profile: limits, deviation, speed-up, a hand-derived corner.

use std::f64::consts::PI;

use kinscene::motion::timing::{
    BlendSettings, TimedPath, TimingError, time_optimal, time_parameterise,
};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Samples the profile every `dt` (and at every waypoint time) and checks, per coordinate:
/// |v| ≤ v_max (relative slack 1e-9 for rounding); |Δv/Δt| ≤ a_max between consecutive samples
/// (v is piecewise linear in t with slopes ≤ a_max, so every difference quotient is too; slack
/// 1e-6 relative); v is the derivative of the sampled position (the position is C¹ with
/// |q̈| ≤ a_max, so a central difference with step h differs from v by at most a_max·h/2;
/// checked against a_max·h + 1e-9).
fn assert_within_limits(timed: &TimedPath, vmax: &[f64], amax: &[f64], wrap: Option<usize>) {
    let dt = timed.duration / 4000.0;
    let mut ts: Vec<f64> = (0..=4000).map(|k| k as f64 * dt).collect();
    ts.extend(&timed.times);
    ts.sort_by(f64::total_cmp);
    let mut previous: Option<(f64, Vec<f64>)> = None;
    for &t in &ts {
        let v = timed.velocity(t);
        for (i, vi) in v.iter().enumerate() {
            assert!(vi.abs() <= vmax[i] * (1.0 + 1e-9), "t = {t}, v[{i}] = {vi}");
        }
        if let Some((tp, vp)) = &previous {
            let h = t - tp;
            if h > 1e-9 {
                for i in 0..v.len() {
                    let a = (v[i] - vp[i]) / h;
                    assert!(a.abs() <= amax[i] * (1.0 + 1e-6), "t = {t}, a[{i}] = {a}");
                }
            }
        }
        previous = Some((t, v));
    }
    let h = 1e-5;
    for k in 1..400 {
        let t = timed.duration * k as f64 / 400.0;
        let (qm, qp, v) = (timed.sample(t - h), timed.sample(t + h), timed.velocity(t));
        for i in 0..v.len() {
            let mut dq = qp[i] - qm[i];
            if wrap == Some(i) {
                dq = dq.sin().atan2(dq.cos());
            }
            let fd = dq / (2.0 * h);
            assert!(
                (fd - v[i]).abs() <= amax[i] * h + 1e-9,
                "t = {t}: fd {fd} vs v {}",
                v[i]
            );
        }
    }
}

/// Positions at the waypoint times are the waypoints, and the profile arrives there
/// continuously (just before each waypoint's time the state is within v_max·ε of it).
fn assert_reaches_waypoints(timed: &TimedPath, path: &[Vec<f64>], vmax: &[f64]) {
    assert_eq!(timed.times.len(), path.len());
    assert_eq!(timed.times[0], 0.0);
    assert_eq!(*timed.times.last().unwrap(), timed.duration);
    assert!(timed.times.windows(2).all(|w| w[0] <= w[1]));
    let eps = 1e-7;
    for (k, (t, q)) in timed.times.iter().zip(path).enumerate() {
        assert_eq!(&timed.sample(*t), q, "waypoint {k}");
        let before = timed.sample(t - eps);
        for i in 0..q.len() {
            let gap = (before[i] - q[i])
                .sin()
                .atan2((before[i] - q[i]).cos())
                .abs();
            assert!(
                gap <= vmax[i] * eps * (1.0 + 1e-6) + 1e-12,
                "waypoint {k}: {before:?}"
            );
        }
    }
}

#[test]
fn single_segment_durations_match_the_trapezoid_and_triangle_formulas() {
    // Straight-line synchronised profile: V = min_i v_i/D_i, A = min_i a_i/D_i (D_i the
    // coordinate distances); T = 1/V + V/A if V²/A < 1 (trapezoid), else 2/√A (triangle).
    // D = (2, 0.5), v = (1, 1), a = (1, 2): V = min(0.5, 2) = 0.5, A = min(0.5, 4) = 0.5,
    // V²/A = 0.5 < 1 → T = 2 + 1 = 3 (= D0/v0 + v0/a0 for the binding coordinate).
    let path = vec![vec![0.0, 0.0], vec![2.0, 0.5]];
    let timed = time_parameterise(&path, &[1.0, 1.0], &[1.0, 2.0], None).unwrap();
    assert!((timed.duration - 3.0).abs() < 1e-12, "{}", timed.duration);
    // At t = 1 the ramp ends: s = ½·A·1² = 0.25 → x = 0.5, and the peak speed V·D0 = 1 m/s.
    assert!((timed.sample(1.0)[0] - 0.5).abs() < 1e-12);
    assert!((timed.velocity(1.5)[0] - 1.0).abs() < 1e-12);
    assert!((timed.velocity(1.5)[1] - 0.25).abs() < 1e-12);

    // D = 0.25, v = 1, a = 1: V = 4, A = 4, V²/A = 4 ≥ 1 → triangle, T = 2/√4 = 1
    // (= 2·√(D/a)).
    let path = vec![vec![0.0], vec![0.25]];
    let timed = time_parameterise(&path, &[1.0], &[1.0], None).unwrap();
    assert!((timed.duration - 1.0).abs() < 1e-12);
    // Peak speed at the middle: a·T/2 = 0.5.
    assert!((timed.velocity(0.5)[0] - 0.5).abs() < 1e-12);

    // Speed and acceleration bound by different coordinates: D = (1, 1), v = (0.5, 10),
    // a = (10, 1): V = 0.5, A = 1, V²/A = 0.25 → T = 2 + 0.5 = 2.5.
    let path = vec![vec![0.0, 0.0], vec![1.0, 1.0]];
    let timed = time_parameterise(&path, &[0.5, 10.0], &[10.0, 1.0], None).unwrap();
    assert!((timed.duration - 2.5).abs() < 1e-12);
    assert_within_limits(&timed, &[0.5, 10.0], &[10.0, 1.0], None);
}

#[test]
fn multi_waypoint_path_respects_limits_and_reaches_waypoints() {
    let path = vec![
        vec![0.0, 0.0, 0.0],
        vec![1.0, 0.2, -0.5],
        vec![1.2, 1.5, 0.3],
        vec![1.2, 1.5, 0.3], // a repeated waypoint
        vec![-0.4, 2.0, 0.35],
        vec![-0.41, 2.0, 0.35], // a tiny segment
    ];
    let (vmax, amax) = ([0.8, 0.5, 1.2], [0.6, 1.5, 0.9]);
    let timed = time_parameterise(&path, &vmax, &amax, None).unwrap();
    assert_within_limits(&timed, &vmax, &amax, None);
    assert_reaches_waypoints(&timed, &path, &vmax);
    // Rest at every corner.
    for (k, t) in timed.times.iter().enumerate() {
        assert!(timed.velocity(*t).iter().all(|v| *v == 0.0), "waypoint {k}");
    }
    // Clamped outside [0, T].
    assert_eq!(timed.sample(-1.0), path[0]);
    assert_eq!(timed.sample(timed.duration + 1.0), *path.last().unwrap());
    assert_eq!(timed.sample(f64::NAN), path[0]);
    assert_eq!(timed.velocity(-1.0), vec![0.0; 3]);
    assert_eq!(timed.velocity(timed.duration + 1.0), vec![0.0; 3]);
}

#[test]
fn collinear_waypoints_are_passed_without_stopping() {
    // 0 → 1 → 2 along x is one straight run: it takes the time of 0 → 2 (v = a = 1:
    // T = 2/1 + 1/1 = 3), and at x = 1 (half way, in the coasting phase) moves at 1 m/s.
    let path = vec![vec![0.0], vec![1.0], vec![2.0]];
    let timed = time_parameterise(&path, &[1.0], &[1.0], None).unwrap();
    assert!((timed.duration - 3.0).abs() < 1e-12);
    assert!((timed.times[1] - 1.5).abs() < 1e-12);
    assert!((timed.velocity(timed.times[1])[0] - 1.0).abs() < 1e-12);
    assert_reaches_waypoints(&timed, &path, &[1.0]);
    // A corner instead: two rest-to-rest segments of length 1 (T = 1/1 + 1/1 = 2 each).
    let corner = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    let timed = time_parameterise(&corner, &[1.0; 2], &[1.0; 2], None).unwrap();
    assert!((timed.duration - 4.0).abs() < 1e-12);
    assert_eq!(timed.velocity(timed.times[1]), vec![0.0, 0.0]);
}

#[test]
fn yaw_turns_the_short_way() {
    // From 3.0 to -3.0 rad: the short way is +(2π − 6) ≈ 0.283 rad through π, not −6 rad.
    // With v = a = 1: D = 0.283 < v²/a → triangle, T = 2√0.283.
    let path = vec![vec![0.0, 0.0, 3.0], vec![0.0, 0.0, -3.0]];
    let (vmax, amax) = ([1.0; 3], [1.0; 3]);
    let timed = time_parameterise(&path, &vmax, &amax, Some(2)).unwrap();
    let d = 2.0 * PI - 6.0;
    assert!((timed.duration - 2.0 * d.sqrt()).abs() < 1e-12);
    let mid = timed.sample(timed.duration / 2.0);
    assert!((mid[2] - (3.0 + d / 2.0)).abs() < 1e-12, "{mid:?}");
    assert!(timed.velocity(timed.duration / 2.0)[2] > 0.0);
    assert_within_limits(&timed, &vmax, &amax, Some(2));
    assert_reaches_waypoints(&timed, &path, &vmax);
    // Without wrapping: 6 rad the long way, T = 6/1 + 1/1 = 7.
    let long = time_parameterise(&path, &vmax, &amax, None).unwrap();
    assert!((long.duration - 7.0).abs() < 1e-12);
}

#[test]
fn single_waypoint_has_zero_duration() {
    let timed = time_parameterise(&[vec![1.0, 2.0]], &[1.0; 2], &[1.0; 2], None).unwrap();
    assert_eq!(timed.duration, 0.0);
    assert_eq!(timed.sample(0.3), vec![1.0, 2.0]);
    assert_eq!(timed.velocity(0.0), vec![0.0, 0.0]);
}

#[test]
fn bad_input_gives_typed_errors() {
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0]];
    let ok = [1.0, 1.0];
    assert_eq!(
        time_parameterise(&[], &ok, &ok, None),
        Err(TimingError::EmptyPath)
    );
    assert_eq!(
        time_parameterise(&[vec![0.0, 0.0], vec![1.0]], &ok, &ok, None),
        Err(TimingError::WaypointDimension {
            index: 1,
            expected: 2,
            got: 1
        })
    );
    assert!(matches!(
        time_parameterise(&[vec![0.0, 0.0], vec![1.0, f64::NAN]], &ok, &ok, None),
        Err(TimingError::NonFiniteWaypoint {
            index: 1,
            coordinate: 1,
            ..
        })
    ));
    assert_eq!(
        time_parameterise(&path, &[1.0], &ok, None),
        Err(TimingError::LimitDimension {
            what: "max_velocity",
            expected: 2,
            got: 1
        })
    );
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            time_parameterise(&path, &ok, &[1.0, bad], None),
            Err(TimingError::InvalidLimit {
                what: "max_acceleration",
                coordinate: 1,
                ..
            })
        ));
    }
    assert_eq!(
        time_parameterise(&path, &ok, &ok, Some(2)),
        Err(TimingError::YawIndexOutOfRange {
            index: 2,
            dimension: 2
        })
    );
}

fn path_strategy() -> impl Strategy<Value = (Vec<Vec<f64>>, Vec<f64>, Vec<f64>)> {
    (1usize..=4).prop_flat_map(|dim| {
        (
            prop::collection::vec(prop::collection::vec(-3.0..3.0f64, dim), 1..8),
            prop::collection::vec(0.05..3.0f64, dim),
            prop::collection::vec(0.05..3.0f64, dim),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn random_paths_respect_limits((path, vmax, amax) in path_strategy(), wrap in any::<bool>()) {
        let wrap = (wrap && path[0].len() >= 3).then_some(2);
        let timed = time_parameterise(&path, &vmax, &amax, wrap).unwrap();
        prop_assert!(timed.duration.is_finite());
        if path.len() > 1 {
            assert_within_limits(&timed, &vmax, &amax, wrap);
        }
        assert_reaches_waypoints(&timed, &path, &vmax);
    }
}

// ---------------------------------------------------------------------------------------------
// time_optimal: corner blending and phase-plane timing

/// Samples a profile densely (`n` uniform steps) and checks, per coordinate:
/// - `|q̇ᵢ| ≤ vᵢ·(1 + 1e-6)` at every sample;
/// - `|Δq̇ᵢ / Δt| ≤ aᵢ·(1 + 1e-6) + 1e-11/Δt` between consecutive samples. The difference
///   quotient of the velocity is the *mean* of `q̈ᵢ` over the step, so it is within `aᵢ`
///   wherever `q̈ᵢ` is, whatever the step, including across the jumps of `q̈` where a line
///   meets an arc. `time_optimal` bounds `q̈` everywhere, not only at its integration steps
///   (it checks the pieces between its knots and stretches time if needed), so no slack of
///   the order of its time step is needed: only rounding, of `q̇` (about 1e-13 absolute
///   here, hence 1e-11/Δt with margin) and of the limit itself (1e-6 relative);
/// - the velocity is the derivative of the sampled position (central difference with
///   `h = 1e-6`: within `aᵢ·h/2` for a C¹ profile with `|q̈| ≤ a`, plus rounding).
///
/// Returns the samples' times and velocities.
fn assert_blended_within_limits(
    timed: &TimedPath,
    vmax: &[f64],
    amax: &[f64],
    n: usize,
) -> Vec<(f64, Vec<f64>)> {
    let dt = timed.duration / n as f64;
    let samples: Vec<(f64, Vec<f64>)> = (0..=n)
        .map(|k| {
            let t = k as f64 * dt;
            (t, timed.velocity(t))
        })
        .collect();
    for w in samples.windows(2) {
        let ((t0, v0), (t1, v1)) = (&w[0], &w[1]);
        for i in 0..vmax.len() {
            assert!(
                v1[i].abs() <= vmax[i] * (1.0 + 1e-6),
                "t = {t1}: v[{i}] = {} > {}",
                v1[i],
                vmax[i]
            );
            let a = (v1[i] - v0[i]) / (t1 - t0);
            assert!(
                a.abs() <= amax[i] * (1.0 + 1e-6) + 1e-11 / (t1 - t0),
                "t = {t1}: a[{i}] = {a} > {}",
                amax[i]
            );
        }
    }
    let h = 1e-6;
    for k in 1..200 {
        let t = timed.duration * k as f64 / 200.0;
        let (qm, qp, v) = (timed.sample(t - h), timed.sample(t + h), timed.velocity(t));
        for i in 0..v.len() {
            let fd = (qp[i] - qm[i]) / (2.0 * h);
            assert!(
                (fd - v[i]).abs() <= amax[i] * h + 1e-8,
                "t = {t}: fd {fd} vs v {}",
                v[i]
            );
        }
    }
    samples
}

/// Starts at the first waypoint and ends at the last, at rest; `times` run from 0 to the
/// duration.
fn assert_rest_to_rest(timed: &TimedPath, path: &[Vec<f64>]) {
    let dim = path[0].len();
    assert_eq!(timed.sample(0.0), path[0]);
    assert_eq!(&timed.sample(timed.duration), path.last().unwrap());
    assert_eq!(timed.velocity(0.0), vec![0.0; dim]);
    assert_eq!(timed.velocity(timed.duration), vec![0.0; dim]);
    assert_eq!(timed.times.len(), path.len());
    assert_eq!(timed.times[0], 0.0);
    assert_eq!(*timed.times.last().unwrap(), timed.duration);
    assert!(
        timed.times.windows(2).all(|w| w[0] <= w[1]),
        "{:?}",
        timed.times
    );
}

/// Distance from `q` to the segment `a`–`b`.
fn segment_distance(q: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let dd: f64 = d.iter().map(|x| x * x).sum();
    let f = if dd > 0.0 {
        (q.iter()
            .zip(a)
            .zip(&d)
            .map(|((q, a), d)| (q - a) * d)
            .sum::<f64>()
            / dd)
            .clamp(0.0, 1.0)
    } else {
        0.0
    };
    q.iter()
        .zip(a)
        .zip(&d)
        .map(|((q, a), d)| (q - a - f * d).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Distance from `q` to the piecewise-linear path.
fn path_distance(q: &[f64], path: &[Vec<f64>]) -> f64 {
    if path.len() == 1 {
        return segment_distance(q, &path[0], &path[0]);
    }
    path.windows(2)
        .map(|w| segment_distance(q, &w[0], &w[1]))
        .fold(f64::INFINITY, f64::min)
}

/// Per interior waypoint, how far from it the blend reaches along each segment, derived
/// independently from the geometry: `ℓ = min(L_in/2, L_out/2, δ/tan(α/4))` for a corner
/// turning by `α` (the arc whose midpoint is `ℓ·tan(α/4) ≤ δ` from the corner), 0 where the
/// path does not turn. The arc lies within `ℓ` of its corner.
fn blend_reach(path: &[Vec<f64>], delta: f64) -> Vec<f64> {
    let mut reach = vec![0.0; path.len()];
    for j in 1..path.len() - 1 {
        let a: Vec<f64> = path[j]
            .iter()
            .zip(&path[j - 1])
            .map(|(x, y)| x - y)
            .collect();
        let b: Vec<f64> = path[j + 1]
            .iter()
            .zip(&path[j])
            .map(|(x, y)| x - y)
            .collect();
        let (la, lb) = (norm(&a), norm(&b));
        let cos = (a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>() / (la * lb)).clamp(-1.0, 1.0);
        let alpha = cos.acos();
        reach[j] = if alpha > 1e-9 {
            (la / 2.0).min(lb / 2.0).min(delta / (alpha / 4.0).tan())
        } else {
            0.0
        };
    }
    reach
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// A seeded random path: `dim`-D, `waypoints` points in [-1.5, 1.5]ᵈ, limits v ∈ [0.3, 2],
/// a ∈ [0.5, 4].
fn random_case(rng: &mut ChaCha8Rng, dim: usize) -> (Vec<Vec<f64>>, Vec<f64>, Vec<f64>) {
    let waypoints = rng.random_range(5..=15);
    let path = (0..waypoints)
        .map(|_| (0..dim).map(|_| rng.random_range(-1.5..1.5)).collect())
        .collect();
    let vmax = (0..dim).map(|_| rng.random_range(0.3..2.0)).collect();
    let amax = (0..dim).map(|_| rng.random_range(0.5..4.0)).collect();
    (path, vmax, amax)
}

#[test]
fn blended_profiles_respect_the_limits_on_random_paths() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let settings = BlendSettings::default();
    for case in 0..12 {
        let (path, vmax, amax) = random_case(&mut rng, 7);
        let timed = time_optimal(&path, &vmax, &amax, None, &settings).unwrap();
        assert!(!timed.is_exact(), "case {case}: random corners are blended");
        assert_rest_to_rest(&timed, &path);
        let samples = assert_blended_within_limits(&timed, &vmax, &amax, 20_000);
        // Never at rest in between: it does not stop at the corners.
        let slowest = samples[1..samples.len() - 1]
            .iter()
            .map(|(_, v)| norm(v))
            .fold(f64::INFINITY, f64::min);
        assert!(slowest > 0.0, "case {case}");
        for (j, t) in timed.times.iter().enumerate().skip(1).take(path.len() - 2) {
            assert!(
                norm(&timed.velocity(*t)) > 1e-3,
                "case {case}: stops at corner {j}"
            );
        }
    }
}

#[test]
fn blended_profiles_stay_within_the_deviation_and_on_the_straight_parts() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for (case, delta) in [0.02, 0.1, 0.3, 0.02, 0.1, 0.3].into_iter().enumerate() {
        let (path, vmax, amax) = random_case(&mut rng, if case < 3 { 7 } else { 2 });
        let settings = BlendSettings {
            max_deviation: delta,
            ..BlendSettings::default()
        };
        let timed = time_optimal(&path, &vmax, &amax, None, &settings).unwrap();
        assert!(timed.max_deviation() > 0.0 && timed.max_deviation() <= delta + 1e-12);
        let reach = blend_reach(&path, delta);
        let mut straight = 0;
        for k in 0..=5000 {
            let q = timed.sample(timed.duration * k as f64 / 5000.0);
            let off = path_distance(&q, &path);
            assert!(off <= timed.max_deviation() + 1e-9, "case {case}: {off}");
            let near_corner = (1..path.len() - 1).any(|j| {
                let d: Vec<f64> = q.iter().zip(&path[j]).map(|(a, b)| a - b).collect();
                norm(&d) <= reach[j] + 1e-9
            });
            if !near_corner {
                straight += 1;
                assert!(off <= 1e-12, "case {case}: {off} off a straight part");
            }
        }
        assert!(
            straight > 100,
            "case {case}: {straight} samples on straight parts"
        );
    }
}

#[test]
fn blending_is_faster_and_exact_where_there_is_nothing_to_blend() {
    // Random paths: never slower than the stop-at-every-corner profile, and faster whenever
    // a corner is blended.
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let settings = BlendSettings::default();
    for case in 0..20 {
        let (path, vmax, amax) = random_case(&mut rng, if case % 2 == 0 { 7 } else { 3 });
        let blended = time_optimal(&path, &vmax, &amax, None, &settings).unwrap();
        let stopping = time_parameterise(&path, &vmax, &amax, None).unwrap();
        assert!(blended.duration <= stopping.duration, "case {case}");
        // Random waypoints always make corners: blended, and strictly faster.
        assert!(!blended.is_exact(), "case {case}");
        assert!(blended.duration < stopping.duration, "case {case}");
    }

    // One straight segment (and the same line through collinear and repeated waypoints):
    // nothing to blend, the exact trapezoid T = 1/V + V/A with V = minᵢ vᵢ/Dᵢ = 0.5,
    // A = minᵢ aᵢ/Dᵢ = 0.5: T = 3 s (exact, no integration).
    for path in [
        vec![vec![0.0, 0.0], vec![2.0, 0.5]],
        vec![
            vec![0.0, 0.0],
            vec![1.0, 0.25],
            vec![1.0, 0.25],
            vec![2.0, 0.5],
        ],
    ] {
        let timed = time_optimal(&path, &[1.0, 1.0], &[1.0, 2.0], None, &settings).unwrap();
        assert!(timed.is_exact());
        assert_eq!(timed.max_deviation(), 0.0);
        assert!((timed.duration - 3.0).abs() < 1e-12, "{}", timed.duration);
    }

    // A bend of 1e-6 rad in the middle of a 2 m line: blended (an arc of radius ~1e6 m
    // over the middle metre), and the duration is the straight line's T = 2/1 + 1/1 = 3 s
    // (v = a = 1). A time-stepped TOTG is within one time step (1e-3 s) of it; here the
    // lines are integrated in closed form and the arc in the phase plane with a bounded
    // error, so the agreement is far tighter.
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![2.0, 1e-6]];
    let timed = time_optimal(&path, &[1.0, 1.0], &[1.0, 1.0], None, &settings).unwrap();
    assert!(!timed.is_exact());
    assert!((timed.duration - 3.0).abs() < 1e-3, "{}", timed.duration);
    assert!((timed.duration - 3.0).abs() < 1e-6, "{}", timed.duration);
    assert_blended_within_limits(&timed, &[1.0, 1.0], &[1.0, 1.0], 4000);

    // One waypoint: duration 0.
    let timed = time_optimal(&[vec![1.0, 2.0]], &[1.0; 2], &[1.0; 2], None, &settings).unwrap();
    assert_eq!(timed.duration, 0.0);
    assert_eq!(timed.sample(0.5), vec![1.0, 2.0]);
}

#[test]
fn l_shaped_corner_matches_the_hand_derived_arc_speed() {
    // (0,0) → (1,0) → (1,1), v = a = 1 per axis, δ = 0.05. The corner turns by α = π/2:
    // ℓ = δ/tan(π/8) = 0.120711 (< half a segment), r = ℓ/tan(π/4) = ℓ. On the arc
    // f' = (cos θ, sin θ), f'' = (−sin θ, cos θ)/r: at θ = 0 coordinate 1 has f'₁ = 0, so
    // |q̈₁| = ṡ²/r ≤ a caps ṡ at √(a·r) = 0.347439; inside the arc the pair bound
    // ṡ² ≤ r·(sin θ + cos θ) is larger, and the velocity limits (ṡ ≤ 1/max(cos θ, sin θ)
    // ≥ 1) do not bind. So the slowest point of the corner is the arc's ends, at √(a·r).
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    let (v, a) = ([1.0, 1.0], [1.0, 1.0]);
    let delta = 0.05;
    let settings = BlendSettings {
        max_deviation: delta,
        ..BlendSettings::default()
    };
    let timed = time_optimal(&path, &v, &a, None, &settings).unwrap();
    let r = delta / (PI / 8.0).tan();
    let expected = r.sqrt();
    assert!((timed.max_deviation() - delta).abs() < 1e-12);
    let samples = assert_blended_within_limits(&timed, &v, &a, 40_000);
    let t_corner = timed.times[1];
    let slowest = samples
        .iter()
        .filter(|(t, _)| (t - t_corner).abs() < 1.0)
        .map(|(_, v)| norm(v))
        .fold(f64::INFINITY, f64::min);
    assert!(
        (slowest - expected).abs() < 1e-3 * expected,
        "slowest {slowest} vs √(a·r) = {expected}"
    );
    // Symmetric: the corner's time is the middle of the motion, at the arc's midpoint
    // (1 − r + r/√2, r − r/√2) (centre (1 − r, r)), r·(√2 − 1) = ℓ·tan(π/8) = δ from the
    // corner.
    assert!((t_corner - timed.duration / 2.0).abs() < 1e-6);
    let mid = timed.sample(t_corner);
    assert!(
        (norm(&[mid[0] - 1.0, mid[1]]) - delta).abs() < 1e-9,
        "{mid:?}"
    );
    // Duration: each line (1 − ℓ long) from rest to √r at A = 1 with a peak x_p = ṡ²:
    // x_p/2 + (x_p − r)/2 = 1 − ℓ, i.e. x_p = 1 − ℓ + r/2 (below V² = 1), taking
    // √x_p + (√x_p − √r) s. The arc (r·π/2 long) takes at most its length at √r and at
    // least its length at the top of its limit curve, √(r·√2).
    let xp = 1.0 - r + r / 2.0;
    let lines = 2.0 * (2.0 * xp.sqrt() - r.sqrt());
    let arc = r * PI / 2.0;
    let (lo, hi) = (
        lines + arc / (r * 2f64.sqrt()).sqrt(),
        lines + arc / r.sqrt(),
    );
    assert!(
        timed.duration >= lo && timed.duration <= hi * (1.0 + 1e-6),
        "{lo} ≤ {} ≤ {hi}",
        timed.duration
    );
    // Stopping at the corner takes 2·(1/1 + 1/1) = 4 s.
    let stopping = time_parameterise(&path, &v, &a, None).unwrap();
    assert_eq!(stopping.duration, 4.0);
    assert!(timed.duration < 3.75);
}

#[test]
fn blending_handles_repeated_collinear_and_reversing_waypoints() {
    let settings = BlendSettings::default();
    let (v, a) = ([1.0, 1.0], [1.0, 1.0]);
    // A repeated and a collinear waypoint before a corner: passed without stopping, at the
    // time the trajectory is there.
    let path = vec![
        vec![0.0, 0.0],
        vec![0.5, 0.0],
        vec![0.5, 0.0],
        vec![1.0, 0.0],
        vec![1.0, 1.0],
    ];
    let timed = time_optimal(&path, &v, &a, None, &settings).unwrap();
    assert_rest_to_rest(&timed, &path);
    assert_eq!(timed.times[1], timed.times[2]);
    let q = timed.sample(timed.times[1]);
    assert!(norm(&[q[0] - 0.5, q[1]]) < 1e-9, "{q:?}");
    assert!(norm(&timed.velocity(timed.times[1])) > 0.1);
    assert!(norm(&timed.velocity(timed.times[3])) > 0.1);
    assert_blended_within_limits(&timed, &v, &a, 10_000);

    // A reversal (turn by π) cannot be blended: the trajectory stops there, exactly at the
    // waypoint; the next corner (a right angle) is blended.
    let path = vec![
        vec![0.0, 0.0],
        vec![1.0, 0.0],
        vec![0.0, 0.0],
        vec![0.0, 1.0],
    ];
    let timed = time_optimal(&path, &v, &a, None, &settings).unwrap();
    assert!(!timed.is_exact());
    assert_rest_to_rest(&timed, &path);
    assert_eq!(timed.velocity(timed.times[1]), vec![0.0, 0.0]);
    assert_eq!(timed.sample(timed.times[1]), path[1]);
    assert!(norm(&timed.velocity(timed.times[2])) > 0.1);
    assert!(timed.duration < time_parameterise(&path, &v, &a, None).unwrap().duration);
    assert_blended_within_limits(&timed, &v, &a, 10_000);
    // Reversals only: nothing to blend, the exact profile.
    let back = vec![vec![0.0], vec![1.0], vec![0.0]];
    assert!(
        time_optimal(&back, &[1.0], &[1.0], None, &settings)
            .unwrap()
            .is_exact()
    );
}

#[test]
fn blended_yaw_turns_the_short_way_and_stays_continuous() {
    // A base path crossing yaw = ±π: 3.0 → −3.0 turns +0.283 rad through π, then on to
    // −2.5 (+0.5 rad). Unwrapped: 3.0 → 3.283 → 3.783.
    let path = vec![
        vec![0.0, 0.0, 3.0],
        vec![1.0, 0.0, -3.0],
        vec![1.0, 1.0, -2.5],
    ];
    let (v, a) = ([0.5, 0.5, 1.0], [0.5, 0.5, 1.0]);
    let settings = BlendSettings::default();
    let timed = time_optimal(&path, &v, &a, Some(2), &settings).unwrap();
    assert!(!timed.is_exact());
    assert!(timed.duration < time_parameterise(&path, &v, &a, Some(2)).unwrap().duration);
    assert_eq!(timed.sample(0.0), path[0]);
    let end = timed.sample(timed.duration);
    assert_eq!(&end[..2], &path[2][..2]);
    assert!((end[2] - (-2.5 + 2.0 * PI)).abs() < 1e-12, "{end:?}");
    let mut previous = timed.sample(0.0)[2];
    for k in 1..=4000 {
        let yaw = timed.sample(timed.duration * k as f64 / 4000.0)[2];
        assert!(
            (yaw - previous).abs() < 1e-2,
            "yaw jumps {previous} → {yaw}"
        );
        assert!(
            (3.0 - 1e-12..=3.0 + 2.0 * PI - 5.5 + 1e-12).contains(&yaw),
            "{yaw}"
        );
        previous = yaw;
    }
    assert_blended_within_limits(&timed, &v, &a, 10_000);
}

#[test]
fn blended_paths_serialise_like_exact_ones() {
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    let timed = time_optimal(&path, &[1.0; 2], &[1.0; 2], None, &BlendSettings::default()).unwrap();
    for p in [
        &timed,
        &time_parameterise(&path, &[1.0; 2], &[1.0; 2], None).unwrap(),
    ] {
        let json = serde_json::to_value(p).unwrap();
        let keys: Vec<&String> = json.as_object().unwrap().keys().collect();
        assert_eq!(keys.len(), 3, "{keys:?}");
        assert_eq!(json["duration"], serde_json::json!(p.duration));
        assert_eq!(json["times"], serde_json::json!(p.times));
        assert_eq!(json["positions"], serde_json::json!(path));
    }
}

#[test]
fn time_optimal_bad_input_gives_typed_errors() {
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    let ok = [1.0, 1.0];
    let s = BlendSettings::default();
    assert_eq!(
        time_optimal(&[], &ok, &ok, None, &s),
        Err(TimingError::EmptyPath)
    );
    assert_eq!(
        time_optimal(&[vec![0.0, 0.0], vec![1.0]], &ok, &ok, None, &s),
        Err(TimingError::WaypointDimension {
            index: 1,
            expected: 2,
            got: 1
        })
    );
    assert!(matches!(
        time_optimal(
            &[vec![0.0, 0.0], vec![f64::INFINITY, 0.0]],
            &ok,
            &ok,
            None,
            &s
        ),
        Err(TimingError::NonFiniteWaypoint {
            index: 1,
            coordinate: 0,
            ..
        })
    ));
    assert_eq!(
        time_optimal(&path, &ok, &[1.0, 1.0, 1.0], None, &s),
        Err(TimingError::LimitDimension {
            what: "max_acceleration",
            expected: 2,
            got: 3
        })
    );
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            time_optimal(&path, &[bad, 1.0], &ok, None, &s),
            Err(TimingError::InvalidLimit {
                what: "max_velocity",
                coordinate: 0,
                ..
            })
        ));
        for (settings, name) in [
            (
                BlendSettings {
                    max_deviation: bad,
                    ..s
                },
                "max_deviation",
            ),
            (
                BlendSettings {
                    time_step: bad,
                    ..s
                },
                "time_step",
            ),
        ] {
            assert!(matches!(
                settings.validate(),
                Err(TimingError::InvalidSetting(s)) if s.field == name
            ));
            assert!(matches!(
                time_optimal(&path, &ok, &ok, None, &settings),
                Err(TimingError::InvalidSetting(s)) if s.field == name
            ));
        }
    }
    assert_eq!(
        time_optimal(&path, &ok, &ok, Some(5), &s),
        Err(TimingError::YawIndexOutOfRange {
            index: 5,
            dimension: 2
        })
    );
    assert_eq!(s.validate(), Ok(()));
}

/// Awkward paths: coordinates from a coarse grid (repeated, collinear and reversing
/// waypoints, right angles) plus a jitter of random scale (1e-9 to 1: nearly collinear
/// corners, tiny segments), a wrapping yaw now and then.
fn awkward_strategy() -> impl Strategy<Value = (Vec<Vec<f64>>, Vec<f64>, Vec<f64>, bool)> {
    (1usize..=4).prop_flat_map(|dim| {
        (
            prop::collection::vec(
                prop::collection::vec(((-2i32..=2), -1.0..1.0f64, -9i32..=0), dim),
                2..10,
            ),
            prop::collection::vec(0.05..3.0f64, dim),
            prop::collection::vec(0.05..3.0f64, dim),
            any::<bool>(),
        )
            .prop_map(|(points, vmax, amax, wrap)| {
                let path = points
                    .into_iter()
                    .map(|q| {
                        q.into_iter()
                            .map(|(grid, jitter, scale)| {
                                grid as f64 + jitter * 10f64.powi(scale) * 0.5
                            })
                            .collect()
                    })
                    .collect();
                (path, vmax, amax, wrap)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn blending_is_safe_on_awkward_paths(
        (path, vmax, amax, wrap) in awkward_strategy(),
        delta in 1e-3..0.5f64,
    ) {
        let wrap = (wrap && path[0].len() >= 3).then_some(2);
        let settings = BlendSettings { max_deviation: delta, ..BlendSettings::default() };
        let timed = time_optimal(&path, &vmax, &amax, wrap, &settings).unwrap();
        let stopping = time_parameterise(&path, &vmax, &amax, wrap).unwrap();
        prop_assert!(timed.duration.is_finite());
        prop_assert!(timed.duration <= stopping.duration);
        prop_assert!(timed.max_deviation() <= delta + 1e-12);
        prop_assert_eq!(&timed.sample(0.0), &path[0]);
        let end = timed.sample(timed.duration);
        for (i, (e, p)) in end.iter().zip(path.last().unwrap()).enumerate() {
            if wrap == Some(i) {
                let d = e - p;
                prop_assert!(d.sin().atan2(d.cos()).abs() < 1e-9, "{} vs {}", e, p);
            } else {
                prop_assert_eq!(e, p);
            }
        }
        prop_assert!(timed.times.windows(2).all(|w| w[0] <= w[1]));
        // (An exact profile with a wrapping yaw jumps by 2π at waypoints: its own tests.)
        if timed.duration > 0.0 && (wrap.is_none() || !timed.is_exact()) {
            assert_blended_within_limits(&timed, &vmax, &amax, 2000);
        }
    }
}
