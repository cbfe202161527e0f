//! Accuracy of the three estimators on the hard classes (`tests/articulation/hard.rs`), from
//! the same observations: per class and depth σ (2 / 5 / 10 mm), over the seeds, the type
//! accuracy, the mean / max axis error (°), pivot error (cm, revolute only) and travel error
//! (° of the swept angle, or cm of the pulled distance), and the 95 % region's coverage (axis
//! and, revolute, pivot inside). A wrong type counts in the accuracy only; its errors are left
//! out of the means.
//!
//! A plain `main` (no criterion: it measures accuracy, not time):
//! `cargo bench --bench fusion`, or in the dev profile `cargo bench --profile dev --bench fusion`.
//! `KINSCENE_FUSION_SEEDS=N` sets the number of seeds (4 by default), `KINSCENE_FUSION_SIGMAS`
//! the depth noise levels in mm (comma-separated, `2,5,10` by default),
//! `KINSCENE_FUSION_CLASSES` a comma-separated list of parts of the class names to run
//! (all by default); with `KINSCENE_FUSION_DETAILS` set, the details of every estimate of
//! the wrong type go to stderr (of every estimate with `KINSCENE_FUSION_DETAILS=all`).

#[path = "../tests/articulation/hard.rs"]
#[allow(dead_code)]
mod hard;

use hard::{HardTruth, hard_cases, observe};
use kinscene::articulation::{
    ArticulationEstimator, Estimate, Fused, JointEstimate, Proprioceptive, TwoView,
};

/// One estimate against the truth: type right, axis °, pivot cm, travel error (° or cm),
/// covered.
struct Row {
    kind_ok: bool,
    axis: f64,
    pivot: Option<f64>,
    travel: Option<f64>,
    covered: bool,
}

fn score(truth: &HardTruth, e: &Estimate) -> Row {
    let r = truth.errors(e);
    let travel = match (&e.joint, truth) {
        (JointEstimate::Revolute { angle, .. }, HardTruth::Revolute { angle: a, .. }) => {
            Some((angle - a).to_degrees())
        }
        (JointEstimate::Prismatic { distance, .. }, HardTruth::Prismatic { distance: d, .. }) => {
            Some((distance - d) * 100.0)
        }
        _ => None,
    };
    Row {
        kind_ok: r.kind_ok,
        axis: r.axis_deg,
        pivot: r.pivot_m.map(|p| p * 100.0),
        travel,
        covered: r.covered,
    }
}

/// `mean/max` of `v`, `-` for none.
fn stat(v: &[f64]) -> String {
    if v.is_empty() {
        "-".to_string()
    } else {
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        format!("{mean:.2}/{:.2}", v.iter().cloned().fold(0.0, f64::max))
    }
}

/// `mean±sd` of the signed `v`, `-` for none.
fn signed(v: &[f64]) -> String {
    if v.is_empty() {
        return "-".to_string();
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
    format!("{mean:+.2}±{sd:.2}")
}

fn main() {
    let n_seeds: u64 = std::env::var("KINSCENE_FUSION_SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&n| n > 0)
        .unwrap_or(4);
    let sigmas: Vec<f64> = std::env::var("KINSCENE_FUSION_SIGMAS")
        .ok()
        .map(|s| {
            s.split(',')
                .filter_map(|v| v.trim().parse::<f64>().ok())
                .map(|mm| mm / 1000.0)
                .collect()
        })
        .filter(|v: &Vec<f64>| !v.is_empty())
        .unwrap_or_else(|| vec![0.002, 0.005, 0.010]);
    let seeds: Vec<u64> = (1..=n_seeds).collect();
    let estimators: [Box<dyn ArticulationEstimator>; 3] = [
        Box::new(TwoView::default()),
        Box::new(Proprioceptive::default()),
        Box::new(Fused::default()),
    ];
    println!("{} seeds", seeds.len());
    println!(
        "{:<24} {:>5} {:<15} {:>5} {:>14} {:>14} {:>12} {:>6}",
        "class",
        "σ mm",
        "estimator",
        "type",
        "axis ° mean/max",
        "pivot cm m/max",
        "travel err",
        "cov95"
    );
    let only = std::env::var("KINSCENE_FUSION_CLASSES").ok();
    let details = std::env::var("KINSCENE_FUSION_DETAILS").ok();
    for case in hard_cases().into_iter().filter(|c| {
        only.as_deref()
            .is_none_or(|o| o.split(',').any(|w| c.name.contains(w.trim())))
    }) {
        for &sigma in &sigmas {
            let observations: Vec<_> = seeds.iter().map(|&s| observe(&case, sigma, s)).collect();
            for est in &estimators {
                let rows: Vec<Row> = observations
                    .iter()
                    .zip(&seeds)
                    .map(|(o, seed)| {
                        let e = est.estimate(&o.interaction()).expect("valid");
                        let row = score(&case.truth, &e);
                        if details
                            .as_deref()
                            .is_some_and(|d| d == "all" || !row.kind_ok)
                        {
                            eprintln!(
                                "{} σ {sigma} seed {seed} {}: {}",
                                case.name,
                                est.name(),
                                e.details
                            );
                        }
                        row
                    })
                    .collect();
                let ok: Vec<&Row> = rows.iter().filter(|r| r.kind_ok).collect();
                let axes: Vec<f64> = ok.iter().map(|r| r.axis).collect();
                let pivots: Vec<f64> = ok.iter().filter_map(|r| r.pivot).collect();
                let travels: Vec<f64> = ok.iter().filter_map(|r| r.travel).collect();
                println!(
                    "{:<24} {:>5.0} {:<15} {:>3}/{} {:>14} {:>14} {:>12} {:>3}/{}",
                    case.name,
                    sigma * 1000.0,
                    est.name(),
                    ok.len(),
                    rows.len(),
                    stat(&axes),
                    stat(&pivots),
                    signed(&travels),
                    rows.iter().filter(|r| r.covered).count(),
                    rows.len()
                );
            }
        }
    }
}
