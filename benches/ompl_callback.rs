//! Cost of OMPL calling a Rust state validity checker, against a C++ checker doing the same
//! computation in the same run, plus the time to plan through a small maze.
//!
//! `cargo bench --bench ompl_callback --features bench -- --warm-up-time 1 --measurement-time 3`
//!
//! One criterion iteration is one sweep of `SpaceInformation::isValid` over `STATES`
//! pre-sampled states (time measured inside the shim, `iter_custom`); throughput is in
//! validity calls. A direct same-call comparison is printed first.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kinscene_ompl::bench::{DiscObstacle, time_validity_calls};
use kinscene_ompl::{PlanSettings, PlanStatus, Problem, StateSpace, Termination, plan};

const STATES: usize = 1000;
const DISC: DiscObstacle = DiscObstacle {
    centre: [0.5, 0.5],
    radius: 0.25,
};

fn validity_calls(c: &mut Criterion) {
    // Same call, same states: both checkers back to back, 2 M calls each.
    let t = time_validity_calls(DISC, STATES, 2000).expect("OMPL shim");
    assert_eq!(t.rust_valid, t.cpp_valid, "the two checkers must agree");
    let per_call = |d: Duration| d.as_nanos() as f64 / t.calls as f64;
    println!(
        "isValid inside OMPL, {} calls each: Rust callback {:.2} ns/call, C++ checker {:.2} ns/call, overhead {:.2} ns/call",
        t.calls,
        per_call(t.rust_callback),
        per_call(t.cpp_checker),
        per_call(t.rust_callback) - per_call(t.cpp_checker),
    );

    let mut group = c.benchmark_group("ompl_is_valid");
    group.throughput(Throughput::Elements(STATES as u64));
    group.bench_function("rust_callback", |b| {
        b.iter_custom(|iters| {
            time_validity_calls(DISC, STATES, iters as usize)
                .expect("OMPL shim")
                .rust_callback
        })
    });
    group.bench_function("cpp_checker", |b| {
        b.iter_custom(|iters| {
            time_validity_calls(DISC, STATES, iters as usize)
                .expect("OMPL shim")
                .cpp_checker
        })
    });
    group.finish();
}

/// The maze of the crate's tests: 10 m × 10 m, three 0.2 m walls, a 0.15 m disc robot (plus
/// 0.05 m margin), from (1, 1) to (8, 8).
fn maze_checker(q: &[f64]) -> bool {
    const WALLS: [([f64; 2], [f64; 2]); 3] = [
        ([0.0, 2.9], [7.0, 3.1]),
        ([3.0, 5.9], [10.0, 6.1]),
        ([4.9, 6.1], [5.1, 8.5]),
    ];
    WALLS.iter().all(|(lo, hi)| {
        let dx = (lo[0] - q[0]).max(q[0] - hi[0]).max(0.0);
        let dy = (lo[1] - q[1]).max(q[1] - hi[1]).max(0.0);
        dx.hypot(dy) >= 0.2
    })
}

fn maze_plan(c: &mut Criterion) {
    let plane = Problem::new(
        StateSpace::RealVector {
            lower: vec![0.0; 2],
            upper: vec![10.0; 2],
        },
        vec![1.0, 1.0],
        vec![8.0, 8.0],
    );
    let se2 = Problem::new(
        StateSpace::Se2 {
            x: [0.0, 10.0],
            y: [0.0, 10.0],
        },
        vec![1.0, 1.0, 0.0],
        vec![8.0, 8.0, 3.0],
    );
    let settings = PlanSettings {
        resolution_fraction: 0.005,
        ..PlanSettings::default()
    };
    let budget = Termination::after(Duration::from_secs(10));
    let mut group = c.benchmark_group("ompl_maze_rrt_connect");
    for (name, problem) in [("plane", &plane), ("se2", &se2)] {
        for simplify in [false, true] {
            let settings = PlanSettings {
                simplify,
                ..settings.clone()
            };
            let id = format!("{name}/{}", if simplify { "simplified" } else { "raw" });
            group.bench_function(id, |b| {
                b.iter(|| {
                    let outcome = plan(problem, &maze_checker, &settings, budget).expect("plans");
                    assert_eq!(outcome.status, PlanStatus::ExactSolution);
                    black_box(outcome)
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, validity_calls, maze_plan);
criterion_main!(benches);
