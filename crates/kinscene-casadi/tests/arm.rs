//! Inverse kinematics of a planar 2-link arm, written with nalgebra transforms over `Expr`.

use kinscene_casadi::{Expr, Nlp, NlpSettings, NlpStatus};
use nalgebra::Matrix3;

const L1: f64 = 1.0;
const L2: f64 = 0.7;

/// Planar homogeneous rotation by the angle whose cosine and sine are given.
fn rot(c: Expr, s: Expr) -> Matrix3<Expr> {
    let (z, o) = (Expr::constant(0.0), Expr::constant(1.0));
    Matrix3::new(c.clone(), -&s, z.clone(), s, c, z.clone(), z.clone(), z, o)
}

/// Planar homogeneous translation along x.
fn trans_x(l: f64) -> Matrix3<Expr> {
    let mut t = Matrix3::<Expr>::identity();
    t[(0, 2)] = Expr::constant(l);
    t
}

/// Independent FK in f64: x = l1 cos q1 + l2 cos(q1 + q2), y = l1 sin q1 + l2 sin(q1 + q2).
fn fk(q: &[f64]) -> [f64; 2] {
    [
        L1 * q[0].cos() + L2 * (q[0] + q[1]).cos(),
        L1 * q[0].sin() + L2 * (q[0] + q[1]).sin(),
    ]
}

/// min ‖q - q_ref‖² s.t. FK(q) = target, with target and q_ref as parameters and joint limits
/// [-π, π] as bounds. One compiled solver, several targets inside the annulus
/// |l1 - l2| < r < l1 + l2. The solution's FK, recomputed in f64, hits the target to 1e-6
/// (constraint_tolerance 1e-9, IPOPT tol 1e-8), and the Rust evaluation of the constraints
/// agrees with CasADi's g to 1e-12.
#[test]
fn planar_two_link_ik() {
    let mut nlp = Nlp::new();
    let pi = std::f64::consts::PI;
    let q = nlp.variables("q", &[-pi; 2], &[pi; 2]).expect("bounds");
    let target = nlp.parameters("target", 2);
    let q_ref = nlp.parameters("q_ref", 2);
    let base_from_ee =
        rot(q[0].cos(), q[0].sin()) * trans_x(L1) * rot(q[1].cos(), q[1].sin()) * trans_x(L2);
    nlp.constrain_eq(&base_from_ee[(0, 2)] - &target[0], 0.0)
        .expect("x");
    nlp.constrain_eq(&base_from_ee[(1, 2)] - &target[1], 0.0)
        .expect("y");
    // The homogeneous row stays (0, 0, 1): folding kept it constant.
    assert_eq!(base_from_ee[(2, 2)].as_constant(), Some(1.0));
    nlp.minimize((&q[0] - &q_ref[0]).sq() + (&q[1] - &q_ref[1]).sq())
        .expect("objective");
    let settings = NlpSettings {
        constraint_tolerance: 1e-9,
        ..NlpSettings::default()
    };
    let solver = nlp.build(&settings).expect("build");
    for (t, q_ref) in [
        ([1.2, 0.5], [0.0, 1.0]),
        ([-0.4, 1.1], [1.0, 1.0]),
        ([0.5, -0.5], [-1.0, 2.0]),
        ([1.65, 0.1], [0.0, 0.2]),
    ] {
        let params = [t[0], t[1], q_ref[0], q_ref[1]];
        let sol = solver.solve(&q_ref, &params).expect("solve");
        assert_eq!(sol.status, NlpStatus::SolveSucceeded, "target {t:?}");
        let reached = fk(&sol.x);
        for i in 0..2 {
            assert!(
                (reached[i] - t[i]).abs() < 1e-6,
                "target {t:?} reached {reached:?}"
            );
        }
        let rust = solver.eval(&sol.x, &params).expect("eval");
        let casadi = solver.eval_casadi(&sol.x, &params).expect("eval_casadi");
        assert!((rust.f - sol.f).abs() < 1e-12 && (casadi.f - sol.f).abs() < 1e-12);
        for i in 0..2 {
            assert!((rust.g[i] - sol.g[i]).abs() < 1e-12);
            assert!((casadi.g[i] - sol.g[i]).abs() < 1e-12);
        }
    }
    // Out of reach (r = 2 > l1 + l2): infeasible, reported as a status.
    let sol = solver
        .solve(&[0.0, 0.5], &[2.0, 0.0, 0.0, 0.5])
        .expect("solve");
    assert!(!sol.status.is_success(), "{:?}", sol.status);
}
