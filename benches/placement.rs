//! Base placement on the kitchen (examples/scenes/kitchen.urdf) with the shipped Gen3 robot:
//! the paper's sampled placement against the CasADi/IPOPT-optimised one.
//!
//! # What is measured
//! For every joint change of [`CASES`] (from the zero state; drawers pulled out 0.3 m, doors
//! opened to 1.2 rad, the robot coming from (1.5, 0) in the open room) and both methods, with
//! [`PlacementSettings::default`] (K = 10, 30 collision-free base samples, IPOPT from the best
//! sample): the fraction of the K + 1 waypoints reached, the method that produced the result
//! (an optimum that fails the independent verification falls back to the sample), the
//! smoothness `Σ‖q_{k+1} − q_k‖²` of the arm trajectory, and the wall time of one placement
//! (the optimised row reuses the compiled NLP: its first compilation is reported separately).
//! `main` prints this table once, then criterion times one placement per method on a drawer
//! and on a door.
//!
//! `cargo bench --bench placement -- --warm-up-time 1 --measurement-time 2`

use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

use criterion::Criterion;
use kinscene::Termination;
use kinscene::kinematics::ik::{IkSettings, IkSolver};
use kinscene::kinematics::robot::{RobotCollision, RobotModel};
use kinscene::motion::placement::{
    PlacementData, PlacementMethod, PlacementOutcome, PlacementProblem, PlacementSettings,
    place_and_plan,
};
use kinscene::scene::SceneModel;
use kinscene::scene::urdf::{self, ImportOptions};

/// Joint, handle and target value of each joint change.
const CASES: [(&str, &str, f64); 8] = [
    ("drawer_top_slide", "drawer_top_handle", 0.3),
    ("drawer_pot_slide", "drawer_pot_handle", 0.3),
    ("island_drawer_left_slide", "island_drawer_left_handle", 0.3),
    (
        "island_drawer_right_slide",
        "island_drawer_right_handle",
        0.3,
    ),
    ("sink_door_hinge", "sink_door_handle", 1.2),
    ("corner_door_back_hinge", "corner_door_back_handle", 1.2),
    ("corner_door_side_hinge", "corner_door_side_handle", 1.2),
    ("dishwasher_door_hinge", "dishwasher_door_handle", 1.2),
];

/// Where the robot stands before the placement.
const ROBOT_FROM: [f64; 3] = [1.5, 0.0, std::f64::consts::FRAC_PI_2];

struct Setup {
    robot: RobotModel,
    collision: RobotCollision,
    ik: IkSolver,
    kitchen: SceneModel,
}

impl Setup {
    fn new() -> Setup {
        let robot = RobotModel::kinova_gen3_mobile();
        Setup {
            collision: RobotCollision::new(&robot).expect("robot collision model"),
            ik: IkSolver::for_robot(&robot, IkSettings::default()).expect("IK solver"),
            kitchen: urdf::read_file(
                Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/kitchen.urdf"),
                &ImportOptions::default(),
            )
            .expect("kitchen"),
            robot,
        }
    }

    fn place(
        &self,
        (joint, handle, to): (&str, &str, f64),
        method: PlacementMethod,
        data: &mut PlacementData,
    ) -> PlacementOutcome {
        let model = &self.kitchen;
        let settings = PlacementSettings {
            method,
            ..PlacementSettings::default()
        };
        place_and_plan(
            PlacementProblem {
                robot: &self.robot,
                collision: &self.collision,
                ik: &self.ik,
                model,
                state: &model.zero_state(),
            },
            model.joint_id(joint).expect("joint"),
            model.handle_id(handle).expect("handle"),
            to,
            ROBOT_FROM,
            &settings,
            data,
            &Termination::none(),
        )
        .expect("placement")
    }
}

fn table(setup: &Setup) {
    let mut data = PlacementData::new();
    // Compile the NLP once, outside the table (the same NLP serves every case).
    let start = Instant::now();
    setup.place(CASES[0], PlacementMethod::Optimised, &mut data);
    println!(
        "first optimised placement (NLP compilation included): {:.0} ms, NLP builds {}",
        start.elapsed().as_secs_f64() * 1e3,
        data.builds()
    );
    println!(
        "{:<28} {:>9} {:>9} {:>10} {:>9} {:>10} {:>9} {:>9}  ipopt",
        "joint", "sampled", "time ms", "smooth", "optimised", "result", "time ms", "smooth"
    );
    let mut totals = [0.0; 2];
    let mut times = [Duration::ZERO; 2];
    for case in CASES {
        let s = setup.place(case, PlacementMethod::Sampled, &mut data);
        let o = setup.place(case, PlacementMethod::Optimised, &mut data);
        totals[0] += s.reached_fraction;
        totals[1] += o.reached_fraction;
        times[0] += s.elapsed;
        times[1] += o.elapsed;
        println!(
            "{:<28} {:>9.2} {:>9.0} {:>10.4} {:>9.2} {:>10} {:>9.0} {:>9.4}  {} ({} it, {:.0} ms)",
            case.0,
            s.reached_fraction,
            s.elapsed.as_secs_f64() * 1e3,
            s.smoothness(),
            o.reached_fraction,
            format!("{:?}", o.method),
            o.elapsed.as_secs_f64() * 1e3,
            o.smoothness(),
            o.stats.ipopt_status.as_deref().unwrap_or("-"),
            o.stats.ipopt_iterations,
            o.stats.ipopt_time.as_secs_f64() * 1e3,
        );
        if let Some(why) = o
            .reason
            .as_deref()
            .and_then(|r| r.find("optimised plan rejected").map(|i| &r[i..]))
        {
            let short: String = why.chars().take(160).collect();
            println!("    {short}");
        }
    }
    let n = CASES.len() as f64;
    println!(
        "{:<28} {:>9.2} {:>9.0} {:>10} {:>9.2} {:>10} {:>9.0}",
        "mean",
        totals[0] / n,
        times[0].as_secs_f64() * 1e3 / n,
        "",
        totals[1] / n,
        "",
        times[1].as_secs_f64() * 1e3 / n
    );
    println!("NLP builds over the table: {}", data.builds());
}

fn main() {
    let setup = Setup::new();
    table(&setup);
    let mut criterion = Criterion::default().sample_size(10).configure_from_args();
    let mut group = criterion.benchmark_group("placement");
    let mut data = PlacementData::new();
    for case in [CASES[0], CASES[4]] {
        for (name, method) in [
            ("sampled", PlacementMethod::Sampled),
            ("optimised", PlacementMethod::Optimised),
        ] {
            group.bench_function(format!("{name}/{}", case.0), |b| {
                b.iter(|| black_box(setup.place(case, method, &mut data)))
            });
        }
    }
    group.finish();
    criterion.final_summary();
}
