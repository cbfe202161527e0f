//! Accuracy of the three estimators on the hard classes (`tests/articulation/hard.rs`), from
//! the same observations: per class and depth σ 2 / 5 / 10 mm, over 4 seeds, the type accuracy, the mean / max axis error (°) and pivot error (cm, revolute only), and
//! the 95 % region's coverage (axis and, revolute, pivot inside). A wrong type counts in the
//! accuracy only; its errors are left out of the means.
//!
//! A plain `main` (no criterion: it measures accuracy, not time):
//! `cargo bench --bench fusion`, or in the dev profile `cargo bench --profile dev --bench fusion`.

#[path = "../tests/articulation/hard.rs"]
#[allow(dead_code)]
mod hard;

use hard::{HardTruth, hard_cases, observe};
use kinscene::articulation::{ArticulationEstimator, Estimate, Fused, Proprioceptive, TwoView};

/// (type right, axis °, pivot cm, covered) of `e` against `truth`.
fn score(truth: &HardTruth, e: &Estimate) -> (bool, f64, Option<f64>, bool) {
    let r = truth.errors(e);
    (
        r.kind_ok,
        r.axis_deg,
        r.pivot_m.map(|p| p * 100.0),
        r.covered,
    )
}

fn main() {
    let seeds = [1u64, 2, 3, 4];
    let estimators: [Box<dyn ArticulationEstimator>; 3] = [
        Box::new(TwoView::default()),
        Box::new(Proprioceptive::default()),
        Box::new(Fused::default()),
    ];
    println!(
        "{:<24} {:>5} {:<15} {:>5} {:>14} {:>14} {:>6}",
        "class", "σ mm", "estimator", "type", "axis ° mean/max", "pivot cm m/max", "cov95"
    );
    for case in hard_cases() {
        for sigma in [0.002, 0.005, 0.010] {
            let observations: Vec<_> = seeds.iter().map(|&s| observe(&case, sigma, s)).collect();
            for est in &estimators {
                let rows: Vec<_> = observations
                    .iter()
                    .map(|o| score(&case.truth, &est.estimate(&o.interaction()).expect("valid")))
                    .collect();
                let ok: Vec<_> = rows.iter().filter(|r| r.0).collect();
                let axes: Vec<f64> = ok.iter().map(|r| r.1).collect();
                let pivots: Vec<f64> = ok.iter().filter_map(|r| r.2).collect();
                let stat = |v: &[f64]| {
                    if v.is_empty() {
                        "-".to_string()
                    } else {
                        let mean = v.iter().sum::<f64>() / v.len() as f64;
                        format!("{mean:.2}/{:.2}", v.iter().cloned().fold(0.0, f64::max))
                    }
                };
                println!(
                    "{:<24} {:>5.0} {:<15} {:>2}/{} {:>14} {:>14} {:>3}/{}",
                    case.name,
                    sigma * 1000.0,
                    est.name(),
                    ok.len(),
                    rows.len(),
                    stat(&axes),
                    stat(&pivots),
                    rows.iter().filter(|r| r.3).count(),
                    rows.len()
                );
            }
        }
    }
}
