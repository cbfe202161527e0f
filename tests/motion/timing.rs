//! Time parameterisation: limits everywhere, waypoints reached, hand-derived durations.

use std::f64::consts::PI;

use kinscene::motion::timing::{TimedPath, TimingError, time_parameterise};
use proptest::prelude::*;

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
