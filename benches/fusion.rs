//! Accuracy of the three estimators on the hard classes (`tests/articulation/hard.rs`), from
//! the same observations: per class and depth σ (2 / 5 / 10 mm), over the seeds, the type
//! accuracy, the mean / max axis error (°), pivot error (cm, revolute only) and travel error
//! (° of the swept angle, or cm of the pulled distance), and the 95 % region's coverage (axis
//! and, revolute, pivot inside). A wrong type counts in the accuracy only; its errors are left
//! out of the means. Rows `+pull` run discovery's keep-pulling rule on the same seeds: while
//! the estimate is not confident by `DiscoverySettings::doubts` (default limits), the part is
//! pulled `extra_pull` further (to its limit, at most `max_extra_pulls` times) and estimated
//! from all the motion so far; the kept estimate is scored against the motion it was made
//! from, with the mean number of further pulls before it and how many kept estimates are
//! confident.
//!
//! A plain `main` (no criterion: it measures accuracy, not time):
//! `cargo bench --bench fusion`, or in the dev profile `cargo bench --profile dev --bench fusion`.
//! `KINSCENE_FUSION_SEEDS=N` sets the number of seeds (4 by default), `KINSCENE_FUSION_SIGMAS`
//! the depth noise levels in mm (comma-separated, `2,5,10` by default),
//! `KINSCENE_FUSION_CLASSES` a comma-separated list of parts of the class names to run
//! (all by default); with `KINSCENE_FUSION_DETAILS` set, the details of every estimate of
//! the wrong type go to stderr (of every estimate with `KINSCENE_FUSION_DETAILS=all`), with
//! the errors and 95 % regions; `KINSCENE_FUSION_CONFIDENT=DEG,M` sets the keep-pulling
//! rule's axis and pivot limits (`confident_axis_95` in degrees, `confident_pivot_95`).

#[path = "../tests/articulation/hard.rs"]
#[allow(dead_code)]
mod hard;

use hard::{HardTruth, Pulled, hard_cases, once, pull_until_confident};
use kinscene::articulation::{
    ArticulationEstimator, Estimate, Fused, JointEstimate, Proprioceptive, TwoView,
};
use kinscene::discovery::DiscoverySettings;

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
    let mut pulling = DiscoverySettings::default();
    if let Some((axis_deg, pivot_m)) =
        std::env::var("KINSCENE_FUSION_CONFIDENT")
            .ok()
            .and_then(|v| {
                let (a, p) = v.split_once(',')?;
                Some((a.trim().parse::<f64>().ok()?, p.trim().parse::<f64>().ok()?))
            })
    {
        pulling.confident_axis_95 = axis_deg.to_radians();
        pulling.confident_pivot_95 = pivot_m;
    }
    println!(
        "{} seeds; rows +pull: keep pulling {} m more while in doubt (at most {} times, to the \
         limit), discovery's default confidence limits (axis {:.1}°, pivot {} cm, type {})",
        seeds.len(),
        pulling.extra_pull,
        pulling.max_extra_pulls,
        pulling.confident_axis_95.to_degrees(),
        pulling.confident_pivot_95 * 100.0,
        pulling.confident_type_probability
    );
    println!(
        "{:<24} {:>5} {:<20} {:>5} {:>14} {:>14} {:>12} {:>6} {:>6} {:>6}",
        "class",
        "σ mm",
        "estimator",
        "type",
        "axis ° mean/max",
        "pivot cm m/max",
        "travel err",
        "cov95",
        "pulls",
        "conf"
    );
    let only = std::env::var("KINSCENE_FUSION_CLASSES").ok();
    let details = std::env::var("KINSCENE_FUSION_DETAILS").ok();
    for case in hard_cases().into_iter().filter(|c| {
        only.as_deref()
            .is_none_or(|o| o.split(',').any(|w| c.name.contains(w.trim())))
    }) {
        for &sigma in &sigmas {
            for est in &estimators {
                for keep_pulling in [false, true] {
                    let runs: Vec<Pulled> = seeds
                        .iter()
                        .map(|&seed| {
                            let run = if keep_pulling {
                                pull_until_confident(&case, est.as_ref(), &pulling, sigma, seed)
                            } else {
                                once(&case, est.as_ref(), &pulling, sigma, seed)
                            };
                            let row = score(&run.truth, &run.estimate);
                            if details
                                .as_deref()
                                .is_some_and(|d| d == "all" || !row.kind_ok)
                            {
                                let regions = run.estimate.uncertainty.map(|u| {
                                    (u.axis_half_angle_95().to_degrees(), u.pivot_radius_95())
                                });
                                eprintln!(
                                    "{} σ {sigma} seed {seed} {}{}: axis {:.2}° pivot {:?} cm, \
                                     95 % regions (°, m) {regions:?}, {} pulls: {}",
                                    case.name,
                                    est.name(),
                                    if keep_pulling { "+pull" } else { "" },
                                    row.axis,
                                    row.pivot,
                                    run.pulls,
                                    run.estimate.details
                                );
                            }
                            run
                        })
                        .collect();
                    let rows: Vec<Row> =
                        runs.iter().map(|r| score(&r.truth, &r.estimate)).collect();
                    let ok: Vec<&Row> = rows.iter().filter(|r| r.kind_ok).collect();
                    let axes: Vec<f64> = ok.iter().map(|r| r.axis).collect();
                    let pivots: Vec<f64> = ok.iter().filter_map(|r| r.pivot).collect();
                    let travels: Vec<f64> = ok.iter().filter_map(|r| r.travel).collect();
                    let pulls =
                        runs.iter().map(|r| r.pulls).sum::<usize>() as f64 / runs.len() as f64;
                    println!(
                        "{:<24} {:>5.0} {:<20} {:>3}/{} {:>14} {:>14} {:>12} {:>3}/{} {:>6.2} {:>3}/{}",
                        case.name,
                        sigma * 1000.0,
                        format!("{}{}", est.name(), if keep_pulling { "+pull" } else { "" }),
                        ok.len(),
                        rows.len(),
                        stat(&axes),
                        stat(&pivots),
                        signed(&travels),
                        rows.iter().filter(|r| r.covered).count(),
                        rows.len(),
                        pulls,
                        runs.iter().filter(|r| r.confident).count(),
                        runs.len()
                    );
                }
            }
        }
    }
}
