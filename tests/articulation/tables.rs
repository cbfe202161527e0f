//! The error table of the closing note and the two-view timing (ignored; run by hand).

use super::*;

/// Prints errors per estimator and noise level over all scenarios and 3 seeds:
/// `cargo test --test lib articulation_error_table -- --ignored --nocapture`
/// (`KS_TABLE_ROWS=two-view:5` in the environment prints one row only).
#[test]
#[ignore = "measurement table; run with --ignored --nocapture"]
fn articulation_error_table() {
    let scenarios = scenarios();
    println!(
        "| estimator | σ (mm) | type acc. | axis err. mean / max (°) | pivot err. mean / max (cm) | travel err. rev (°) / pri (cm) | IoU mean |"
    );
    println!("|---|---|---|---|---|---|---|");
    // `KS_TABLE_ROWS=two-view:5` limits the table to one estimator and noise level.
    let only = std::env::var("KS_TABLE_ROWS").ok();
    for est in estimators() {
        for sigma in [0.002, 0.005, 0.010] {
            let row = format!("{}:{}", est.name(), (sigma * 1000.0f64).round());
            if only.as_ref().is_some_and(|o| *o != row) {
                continue;
            }
            let mut kinds = Vec::new();
            let (mut axis, mut pivot, mut rev, mut pri, mut iou) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for s in &scenarios {
                for seed in 0..3 {
                    let o = observe(s, sigma, 0.05, 100 + seed, 1.0);
                    let e = est.estimate(&o.interaction()).expect("valid input");
                    let err = errors(s, &o, &e, 1.0);
                    kinds.push((e.joint.kind(), s.truth.kind()));
                    if !err.kind_ok || err.axis_deg > 2.0 || err.pivot_m.is_some_and(|p| p > 0.02) {
                        eprintln!(
                            "miss: {} σ {sigma} seed {seed} {}: {err:?}\n  {}",
                            est.name(),
                            s.name,
                            e.details
                        );
                    }
                    if err.axis_deg.is_finite() {
                        axis.push(err.axis_deg);
                    }
                    pivot.extend(err.pivot_m.map(|p| p * 100.0));
                    if err.kind_ok {
                        match s.truth {
                            Truth::Revolute { .. } => rev.push(err.travel),
                            Truth::Prismatic { .. } => pri.push(err.travel * 100.0),
                        }
                    }
                    iou.extend(err.iou);
                }
            }
            let mean = |v: &[f64]| {
                if v.is_empty() {
                    f64::NAN
                } else {
                    v.iter().sum::<f64>() / v.len() as f64
                }
            };
            let max = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::max);
            println!(
                "| {} | {:.0} | {:.2} | {:.2} / {:.2} | {:.2} / {:.2} | {:.2} / {:.2} | {} |",
                est.name(),
                sigma * 1000.0,
                joint_type_accuracy(kinds).unwrap_or(f64::NAN),
                mean(&axis),
                max(&axis),
                mean(&pivot),
                max(&pivot),
                mean(&rev),
                mean(&pri),
                if iou.is_empty() {
                    "–".to_string()
                } else {
                    format!("{:.2}", mean(&iou))
                },
            );
        }
    }
}

/// Time per two-view estimate with and without the voxel thinning of the ICP points, run
/// interleaved (the minimum of 5 runs each, robust to other load on the machine):
/// `cargo test --test lib two_view_timing -- --ignored --nocapture`.
#[test]
#[ignore = "timing; run with --ignored --nocapture"]
fn two_view_timing() {
    let thinned = TwoView::default();
    let unthinned = TwoView {
        settings: TwoViewSettings {
            icp_voxel: 0.0,
            ..Default::default()
        },
    };
    for s in &scenarios() {
        let o = observe(s, 0.005, 0.05, 100, 1.0);
        let mut best = [f64::INFINITY; 2];
        for _ in 0..5 {
            for (k, est) in [&thinned, &unthinned].iter().enumerate() {
                let t = std::time::Instant::now();
                let e = est.estimate(&o.interaction()).expect("valid input");
                best[k] = best[k].min(t.elapsed().as_secs_f64());
                assert!(e.joint.kind() == s.truth.kind(), "{}", s.name);
            }
        }
        println!(
            "{}: {} + {} points, {:.0} ms thinned, {:.0} ms unthinned",
            s.name,
            o.pre.points.len(),
            o.post.points.len(),
            best[0] * 1e3,
            best[1] * 1e3
        );
    }
}
