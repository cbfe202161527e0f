//! Time parameterisation of arm (and base) paths: [`time_parameterise`] (exact, at rest at
//! every corner) against [`time_optimal`] (corners blended within
//! [`BlendSettings::max_deviation`], phase-plane timing), on the same paths in the same run.
//!
//! # Paths
//! All seeded (ChaCha8, fixed seeds), with the shipped Kinova Gen3's limits
//! ([`RobotModel::kinova_gen3_mobile`]: 0.8727 rad/s and 2.0 rad/s² on every arm joint; the
//! base's x, y, yaw limits for the base path):
//!
//! - **random_N**: N waypoints (10, 20, 30) drawn uniformly in [-1.5, 1.5] rad per joint:
//!   long segments, sharp corners (typically 60–120°);
//! - **zigzag_N**: an OMPL-like path from a random start to a random goal ~2.5 rad away,
//!   its N interior waypoints pushed sideways by up to 0.15 rad from the straight line (the
//!   kind of path RRT-Connect gives before simplification): short segments, 20–60° turns;
//! - **smoothed_N**: the same with 0.03 rad sideways (a shortcut/simplified path): shallow
//!   turns;
//! - **base_zigzag**: an SE(2) base path (x, y, yaw with wrapping yaw) of 12 waypoints.
//!
//! # Output
//! `main` prints, per path: the executed duration with `time_parameterise` and with
//! `time_optimal` (default [`BlendSettings`]: 0.02 rad deviation, 1 ms step), their ratio,
//! the largest corner cut, and the compute time of each (median of 15 runs); then a mean
//! ratio line, and the ratio on three of the paths for a few `max_deviation` values.
//! Criterion then times both functions on `random_20` and `zigzag_20`
//! (`timing/<function>/<path>`).
//!
//! `cargo bench --bench timing -- --quick` (needs the default features: the timing module
//! lives with the motion layer).

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
mod bench {
    use std::hint::black_box;
    use std::time::{Duration, Instant};

    use criterion::Criterion;
    use kinscene::kinematics::robot::RobotModel;
    use kinscene::motion::timing::{BlendSettings, time_optimal, time_parameterise};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A named path with its limits.
    pub struct Case {
        pub name: String,
        pub path: Vec<Vec<f64>>,
        pub vmax: Vec<f64>,
        pub amax: Vec<f64>,
        pub wrap: Option<usize>,
    }

    /// Waypoints spread uniformly in [-1.5, 1.5]ᵈ.
    fn random_path(rng: &mut ChaCha8Rng, dim: usize, n: usize) -> Vec<Vec<f64>> {
        (0..n)
            .map(|_| (0..dim).map(|_| rng.random_range(-1.5..1.5)).collect())
            .collect()
    }

    /// A start–goal line ~2.5 rad long through `interior` waypoints, each pushed by up to
    /// `spread` per coordinate (not along the line only: a 7-D jitter).
    fn zigzag_path(
        rng: &mut ChaCha8Rng,
        dim: usize,
        interior: usize,
        spread: f64,
    ) -> Vec<Vec<f64>> {
        let start: Vec<f64> = (0..dim).map(|_| rng.random_range(-1.0..1.0)).collect();
        let dir: Vec<f64> = (0..dim).map(|_| rng.random_range(-1.0..1.0)).collect();
        let len = dir.iter().map(|x| x * x).sum::<f64>().sqrt();
        let goal: Vec<f64> = start
            .iter()
            .zip(&dir)
            .map(|(s, d)| s + 2.5 * d / len)
            .collect();
        let n = interior + 1;
        (0..=n)
            .map(|k| {
                let f = k as f64 / n as f64;
                start
                    .iter()
                    .zip(&goal)
                    .map(|(s, g)| {
                        let jitter = if k == 0 || k == n {
                            0.0
                        } else {
                            rng.random_range(-spread..spread)
                        };
                        s + (g - s) * f + jitter
                    })
                    .collect()
            })
            .collect()
    }

    pub fn cases() -> Vec<Case> {
        let robot = RobotModel::kinova_gen3_mobile();
        let vmax: Vec<f64> = robot.arm_joints().iter().map(|j| j.max_velocity).collect();
        let amax: Vec<f64> = robot
            .arm_joints()
            .iter()
            .map(|j| j.max_acceleration)
            .collect();
        let dim = vmax.len();
        let mut rng = ChaCha8Rng::seed_from_u64(2012);
        let mut cases = Vec::new();
        for n in [10, 20, 30] {
            cases.push(Case {
                name: format!("random_{n}"),
                path: random_path(&mut rng, dim, n),
                vmax: vmax.clone(),
                amax: amax.clone(),
                wrap: None,
            });
        }
        for n in [10, 20, 30] {
            cases.push(Case {
                name: format!("zigzag_{n}"),
                path: zigzag_path(&mut rng, dim, n - 2, 0.15),
                vmax: vmax.clone(),
                amax: amax.clone(),
                wrap: None,
            });
        }
        for n in [10, 20] {
            cases.push(Case {
                name: format!("smoothed_{n}"),
                path: zigzag_path(&mut rng, dim, n - 2, 0.03),
                vmax: vmax.clone(),
                amax: amax.clone(),
                wrap: None,
            });
        }
        // A base path: 12 poses across a 4 m room, yaw crossing ±π.
        let base = robot.base();
        let path: Vec<Vec<f64>> = (0..12)
            .map(|k| {
                let f = k as f64 / 11.0;
                vec![
                    4.0 * f + rng.random_range(-0.3..0.3),
                    1.0 * (6.0 * f).sin() + rng.random_range(-0.3..0.3),
                    (2.5 + 1.5 * f + rng.random_range(-0.2..0.2) + std::f64::consts::PI)
                        .rem_euclid(std::f64::consts::TAU)
                        - std::f64::consts::PI,
                ]
            })
            .collect();
        cases.push(Case {
            name: "base_zigzag".into(),
            path,
            vmax: base.max_velocity.to_vec(),
            amax: base.max_acceleration.to_vec(),
            wrap: Some(2),
        });
        cases
    }

    /// Median wall time of `runs` calls.
    fn median_time(runs: usize, mut f: impl FnMut()) -> Duration {
        let mut times: Vec<Duration> = (0..runs)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed()
            })
            .collect();
        times.sort();
        times[runs / 2]
    }

    fn ms(d: Duration) -> String {
        format!("{:.3}", d.as_secs_f64() * 1e3)
    }

    pub fn table(cases: &[Case]) {
        let settings = BlendSettings::default();
        println!();
        println!(
            "timing: executed duration (s) at rest at every corner (time_parameterise) vs \
             blended (time_optimal, max_deviation {}, time_step {} s)",
            settings.max_deviation, settings.time_step
        );
        println!(
            "{:<14} {:>4} {:>10} {:>10} {:>7} {:>9} {:>12} {:>12}",
            "path", "wp", "T_stop", "T_blend", "ratio", "max_dev", "stop (ms)", "blend (ms)"
        );
        let mut ratios = Vec::new();
        for c in cases {
            let stop = time_parameterise(&c.path, &c.vmax, &c.amax, c.wrap).expect("valid");
            let blend = time_optimal(&c.path, &c.vmax, &c.amax, c.wrap, &settings).expect("valid");
            let t_stop = median_time(15, || {
                black_box(time_parameterise(&c.path, &c.vmax, &c.amax, c.wrap).ok());
            });
            let t_blend = median_time(15, || {
                black_box(time_optimal(&c.path, &c.vmax, &c.amax, c.wrap, &settings).ok());
            });
            let ratio = blend.duration / stop.duration;
            ratios.push(ratio);
            println!(
                "{:<14} {:>4} {:>10.3} {:>10.3} {:>6.3}× {:>9.4} {:>12} {:>12}",
                c.name,
                c.path.len(),
                stop.duration,
                blend.duration,
                ratio,
                blend.max_deviation(),
                ms(t_stop),
                ms(t_blend)
            );
        }
        let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
        let (lo, hi) = ratios.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), r| {
            (lo.min(*r), hi.max(*r))
        });
        println!(
            "time_optimal / time_parameterise duration: mean {mean:.3}×, best {lo:.3}×, \
             worst {hi:.3}× (≤ 1 by construction)"
        );
        println!();
        // How much the allowed corner cut buys.
        println!("duration ratio time_optimal / time_parameterise by max_deviation (rad):");
        let deltas = [0.005, 0.02, 0.05, 0.1];
        print!("{:<14}", "path");
        for d in deltas {
            print!(" {d:>8}");
        }
        println!();
        for c in cases
            .iter()
            .filter(|c| ["random_20", "zigzag_20", "smoothed_20"].contains(&c.name.as_str()))
        {
            let stop = time_parameterise(&c.path, &c.vmax, &c.amax, c.wrap).expect("valid");
            print!("{:<14}", c.name);
            for d in deltas {
                let settings = BlendSettings {
                    max_deviation: d,
                    ..BlendSettings::default()
                };
                let blend =
                    time_optimal(&c.path, &c.vmax, &c.amax, c.wrap, &settings).expect("valid");
                print!(" {:>7.3}×", blend.duration / stop.duration);
            }
            println!();
        }
        println!();
    }

    pub fn criterion(criterion: &mut Criterion, cases: &[Case]) {
        let settings = BlendSettings::default();
        let mut group = criterion.benchmark_group("timing");
        for c in cases
            .iter()
            .filter(|c| c.name == "random_20" || c.name == "zigzag_20")
        {
            group.bench_function(format!("time_parameterise/{}", c.name), |b| {
                b.iter(|| black_box(time_parameterise(&c.path, &c.vmax, &c.amax, c.wrap).ok()))
            });
            group.bench_function(format!("time_optimal/{}", c.name), |b| {
                b.iter(|| {
                    black_box(time_optimal(&c.path, &c.vmax, &c.amax, c.wrap, &settings).ok())
                })
            });
        }
        group.finish();
    }
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
fn main() {
    let mut criterion = criterion::Criterion::default().configure_from_args();
    // `--list` (cargo's test harness protocol) only lists; nothing to measure then.
    if !std::env::args().any(|a| a == "--list") {
        let cases = bench::cases();
        bench::table(&cases);
        bench::criterion(&mut criterion, &cases);
    }
    criterion.final_summary();
}

#[cfg(not(all(feature = "ompl", feature = "pinocchio", feature = "casadi")))]
fn main() {
    eprintln!("the timing bench needs the ompl, pinocchio and casadi features (the defaults)");
}
