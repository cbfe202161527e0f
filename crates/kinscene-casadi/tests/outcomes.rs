//! Non-converged problems are `Ok` outcomes; solvers move between threads.

use kinscene_casadi::{Hessian, LinearSolver, Nlp, NlpSettings, NlpSolver, NlpStatus};

const INF: f64 = f64::INFINITY;

/// x² + y² <= 1 and x >= 2 cannot both hold: IPOPT's restoration phase converges to a point of
/// minimal infeasibility and reports it; the solve is `Ok`.
#[test]
fn infeasible_problem_is_an_ok_outcome() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", 2.0, INF).expect("bounds");
    let y = nlp.variable("y", -INF, INF).expect("bounds");
    nlp.minimize(&x + &y).expect("objective");
    nlp.constrain(x.sq() + y.sq(), -INF, 1.0)
        .expect("constraint");
    let solver = nlp.build(&NlpSettings::default()).expect("build");
    let sol = solver
        .solve(&[2.5, 0.5], &[])
        .expect("an infeasible problem is not an error");
    assert_eq!(sol.status, NlpStatus::InfeasibleProblemDetected);
    assert!(!sol.status.is_success());
    assert!(
        sol.g[0] > 1.0 + 1e-3,
        "the constraint is violated: g = {}",
        sol.g[0]
    );
}

/// Rosenbrock from (-1.2, 1) needs ~20 iterations; a limit of 3 stops early with that status.
#[test]
fn iteration_limit_is_an_ok_outcome() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -INF, INF).expect("bounds");
    let y = nlp.variable("y", -INF, INF).expect("bounds");
    nlp.minimize((1.0 - &x).sq() + 100.0 * (&y - x.sq()).sq())
        .expect("objective");
    let settings = NlpSettings {
        max_iter: 3,
        ..NlpSettings::default()
    };
    let solver = nlp.build(&settings).expect("build");
    let sol = solver.solve(&[-1.2, 1.0], &[]).expect("solve");
    assert_eq!(sol.status, NlpStatus::MaximumIterationsExceeded);
    assert_eq!(sol.iterations, 3);
    // The same problem converges without the limit, to the minimum (1, 1).
    let solver = nlp.build(&NlpSettings::default()).expect("build");
    let sol = solver.solve(&[-1.2, 1.0], &[]).expect("solve");
    assert_eq!(sol.status, NlpStatus::SolveSucceeded);
    assert!((sol.x[0] - 1.0).abs() < 1e-6 && (sol.x[1] - 1.0).abs() < 1e-6);
}

/// L-BFGS and SPRAL reach the same Rosenbrock minimum (1, 1) as the defaults (to 1e-5: L-BFGS
/// ends with a less accurate Hessian model).
#[test]
fn hessian_and_linear_solver_choices() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -INF, INF).expect("bounds");
    let y = nlp.variable("y", -INF, INF).expect("bounds");
    nlp.minimize((1.0 - &x).sq() + 100.0 * (&y - x.sq()).sq())
        .expect("objective");
    for (hessian, linear_solver) in [
        (Hessian::LimitedMemory, LinearSolver::Mumps),
        (Hessian::Exact, LinearSolver::Spral),
    ] {
        let settings = NlpSettings {
            hessian,
            linear_solver,
            ..NlpSettings::default()
        };
        let sol = nlp
            .build(&settings)
            .expect("build")
            .solve(&[-1.2, 1.0], &[])
            .expect("solve");
        assert!(
            sol.status.is_success(),
            "{hessian:?}/{linear_solver:?}: {:?}",
            sol.status
        );
        assert!((sol.x[0] - 1.0).abs() < 1e-5 && (sol.x[1] - 1.0).abs() < 1e-5);
    }
}

fn circle_solver() -> NlpSolver {
    // min x + y on the circle of radius r (parameter): x = y = -r/√2.
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -INF, INF).expect("bounds");
    let y = nlp.variable("y", -INF, INF).expect("bounds");
    let r = nlp.parameter("r");
    nlp.minimize(&x + &y).expect("objective");
    nlp.constrain_eq(x.sq() + y.sq() - r.sq(), 0.0)
        .expect("constraint");
    nlp.build(&NlpSettings::default()).expect("build")
}

/// `NlpSolver` is `Send`: solvers built on one thread solve on others, two at the same time.
#[test]
fn solvers_move_to_other_threads() {
    let handles: Vec<_> = [1.0, 3.0]
        .into_iter()
        .map(|r| {
            let solver = circle_solver();
            std::thread::spawn(move || {
                (0..20)
                    .map(|_| solver.solve(&[-0.5, -0.4], &[r]).expect("solve").x[0])
                    .map(|x| (x + r / 2f64.sqrt()).abs())
                    .fold(0.0, f64::max)
            })
        })
        .collect();
    for h in handles {
        let worst = h.join().expect("thread");
        assert!(worst < 1e-6, "worst error {worst}");
    }
}

/// Compile-time check of the documented thread traits: expressions and problems are
/// `Send + Sync`, solvers `Send`.
#[test]
fn thread_traits() {
    fn send<T: Send>() {}
    fn send_sync<T: Send + Sync>() {}
    send::<NlpSolver>();
    send_sync::<kinscene_casadi::Expr>();
    send_sync::<Nlp>();
}
