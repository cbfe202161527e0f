//! CasADi/IPOPT through kinscene-casadi: a planar 2-link IK NLP (2 variables, 2 equality
//! constraints, 4 parameters) compiled once and solved for many targets; the cost of compiling
//! it (`casadi::nlpsol` creation, including CasADi's derivative generation); and the two
//! evaluators of its functions.
//!
//! The first build in the process also loads the IPOPT plugin; that one-off cost is measured
//! with `Instant` before criterion starts and printed to stderr.
//!
//! Run: `cargo bench --bench casadi_nlp -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use kinscene_casadi::{Expr, Nlp, NlpSettings};
use nalgebra::Matrix3;

const L1: f64 = 1.0;
const L2: f64 = 0.7;

fn rot(q: &Expr) -> Matrix3<Expr> {
    let (c, s) = (q.cos(), q.sin());
    let (z, o) = (Expr::constant(0.0), Expr::constant(1.0));
    Matrix3::new(c.clone(), -&s, z.clone(), s, c, z.clone(), z.clone(), z, o)
}

fn trans_x(l: f64) -> Matrix3<Expr> {
    let mut t = Matrix3::<Expr>::identity();
    t[(0, 2)] = Expr::constant(l);
    t
}

/// min ‖q - q_ref‖²  s.t.  FK(q) = target; parameters (target, q_ref).
fn two_link_ik() -> Nlp {
    let mut nlp = Nlp::new();
    let pi = std::f64::consts::PI;
    let q = nlp.variables("q", &[-pi; 2], &[pi; 2]).expect("bounds");
    let target = nlp.parameters("target", 2);
    let q_ref = nlp.parameters("q_ref", 2);
    let base_from_ee = rot(&q[0]) * trans_x(L1) * rot(&q[1]) * trans_x(L2);
    nlp.constrain_eq(&base_from_ee[(0, 2)] - &target[0], 0.0)
        .expect("x");
    nlp.constrain_eq(&base_from_ee[(1, 2)] - &target[1], 0.0)
        .expect("y");
    nlp.minimize((&q[0] - &q_ref[0]).sq() + (&q[1] - &q_ref[1]).sq())
        .expect("objective");
    nlp
}

/// Reachable targets on a spiral inside the annulus 0.3 < r < 1.7, at angles in [-1.5, 2] rad
/// where the elbow-up solution (q2 > 0, favoured by q_ref = (0, 1)) is inside the joint limits
/// [-π, π] (near ±π, IPOPT, a local method, gets stuck at the q1 bound and reports local
/// infeasibility).
fn problems(n: usize) -> Vec<[f64; 4]> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let (r, a) = (0.45 + 1.1 * t, -1.5 + 3.5 * t);
            [r * a.cos(), r * a.sin(), 0.0, 1.0]
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let settings = NlpSettings::default();
    let nlp = two_link_ik();

    let start = Instant::now();
    let solver = nlp.build(&settings).expect("build");
    let first_build = start.elapsed();
    let start = Instant::now();
    let second = nlp.build(&settings).expect("build");
    let second_build = start.elapsed();
    drop(second);
    let params = problems(64);
    let start = Instant::now();
    // Initial guess: the shoulder pointing at the target, the elbow at q_ref.
    let x0: Vec<[f64; 2]> = params.iter().map(|p| [p[1].atan2(p[0]), 1.0]).collect();
    let sol = solver.solve(&x0[0], &params[0]).expect("solve");
    let first_solve = start.elapsed();
    eprintln!(
        "casadi_nlp: first build (shim + IPOPT plugin load) {first_build:?}, second build \
         {second_build:?}, first solve {first_solve:?} ({:?}, {} iterations)",
        sol.status, sol.iterations
    );
    let failures = (0..params.len())
        .filter(|&i| {
            let sol = solver.solve(&x0[i], &params[i]).expect("solve");
            !sol.status.is_success()
        })
        .count();
    eprintln!(
        "casadi_nlp: {failures} of {} spiral targets not solved",
        params.len()
    );

    let mut group = c.benchmark_group("casadi_nlp");
    group.bench_function("build_2link_ik", |b| {
        b.iter(|| black_box(nlp.build(&settings).expect("build")))
    });
    let mut i = 0;
    group.bench_function("solve_2link_ik", |b| {
        b.iter(|| {
            i = (i + 1) % params.len();
            black_box(solver.solve(&x0[i], &params[i]).expect("solve"))
        })
    });
    let x = [0.3, 1.1];
    group.bench_function("eval_rust_2link_ik", |b| {
        b.iter(|| black_box(solver.eval(&x, &params[0]).expect("eval")))
    });
    group.bench_function("eval_casadi_2link_ik", |b| {
        b.iter(|| black_box(solver.eval_casadi(&x, &params[0]).expect("eval")))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
