//! The expression API: nalgebra algebra, folding, sharing, and the Rust evaluator.

use kinscene_casadi::{Expr, Nlp, NlpSettings};
use nalgebra::{Matrix3, Matrix4, Vector3};

/// What the rotation helpers need, satisfied by both `f64` and `Expr`.
trait Scalar: nalgebra::Scalar + From<f64> + std::ops::Neg<Output = Self> {}
impl<T: nalgebra::Scalar + From<f64> + std::ops::Neg<Output = T>> Scalar for T {}

/// Rotation about z by the angle with cosine `c` and sine `s` (row-major arguments).
fn rot_z<T: Scalar>(c: T, s: T) -> Matrix3<T> {
    let (z, o) = (T::from(0.0), T::from(1.0));
    Matrix3::new(
        c.clone(),
        -s.clone(),
        z.clone(),
        s,
        c,
        z.clone(),
        z.clone(),
        z,
        o,
    )
}

/// Rotation about y.
fn rot_y<T: Scalar>(c: T, s: T) -> Matrix3<T> {
    let (z, o) = (T::from(0.0), T::from(1.0));
    Matrix3::new(
        c.clone(),
        z.clone(),
        s.clone(),
        z.clone(),
        o,
        z.clone(),
        -s,
        z,
        c,
    )
}

/// Rotation about x.
fn rot_x<T: Scalar>(c: T, s: T) -> Matrix3<T> {
    let (z, o) = (T::from(0.0), T::from(1.0));
    Matrix3::new(
        o,
        z.clone(),
        z.clone(),
        z.clone(),
        c.clone(),
        -s.clone(),
        z,
        s,
        c,
    )
}

/// A ZYX rotation product in `Expr` evaluates to the same matrix as the product in `f64`
/// (nalgebra), and so do a homogeneous 4x4 product and `Vector3` dot/cross. Tolerance 1e-12:
/// both sides do the same few dozen floating-point operations on values of magnitude <= 2.
#[test]
fn nalgebra_products_match_f64() {
    let mut nlp = Nlp::new();
    let q = nlp
        .variables("q", &[-10.0; 3], &[10.0; 3])
        .expect("finite bounds");
    let vals = [0.3, -1.2, 2.5];

    let r_expr = rot_z(q[0].cos(), q[0].sin())
        * rot_y(q[1].cos(), q[1].sin())
        * rot_x(q[2].cos(), q[2].sin());
    let (c, s) = (vals.map(f64::cos), vals.map(f64::sin));
    let r_f64 = rot_z(c[0], s[0]) * rot_y(c[1], s[1]) * rot_x(c[2], s[2]);
    // Independent reference: nalgebra's own Euler-angle constructor.
    let r_ref = nalgebra::Rotation3::from_euler_angles(vals[2], vals[1], vals[0]);
    assert!((r_f64 - r_ref.matrix()).abs().max() < 1e-12);
    for i in 0..3 {
        for j in 0..3 {
            let v = nlp.eval(&r_expr[(i, j)], &vals, &[]).expect("eval");
            assert!((v - r_f64[(i, j)]).abs() < 1e-12, "R[{i},{j}]: {v}");
        }
    }

    // Homogeneous transform: rotation and translation [q0, 1, -2].
    let mut t_expr = Matrix4::<Expr>::identity();
    t_expr.fixed_view_mut::<3, 3>(0, 0).copy_from(&r_expr);
    t_expr[(0, 3)] = q[0].clone();
    t_expr[(1, 3)] = Expr::constant(1.0);
    t_expr[(2, 3)] = Expr::constant(-2.0);
    let mut t_f64 = Matrix4::<f64>::identity();
    t_f64.fixed_view_mut::<3, 3>(0, 0).copy_from(&r_f64);
    t_f64[(0, 3)] = vals[0];
    t_f64[(1, 3)] = 1.0;
    t_f64[(2, 3)] = -2.0;
    let tt_expr = &t_expr * &t_expr;
    let tt_f64 = t_f64 * t_f64;
    for i in 0..4 {
        for j in 0..4 {
            let v = nlp.eval(&tt_expr[(i, j)], &vals, &[]).expect("eval");
            assert!((v - tt_f64[(i, j)]).abs() < 1e-12, "T*T[{i},{j}]");
        }
    }

    let a = Vector3::new(q[0].clone(), q[1].sin(), Expr::constant(0.5));
    let b = Vector3::new(q[2].clone(), q[0].sq(), q[1].clone());
    let af = Vector3::new(vals[0], vals[1].sin(), 0.5);
    let bf = Vector3::new(vals[2], vals[0] * vals[0], vals[1]);
    let dot = nlp.eval(&a.dot(&b), &vals, &[]).expect("eval");
    assert!((dot - af.dot(&bf)).abs() < 1e-12);
    let cross = a.cross(&b);
    let cross_f = af.cross(&bf);
    for i in 0..3 {
        let v = nlp.eval(&cross[i], &vals, &[]).expect("eval");
        assert!((v - cross_f[i]).abs() < 1e-12);
    }
}

/// Every elementary function and operator evaluates as its `f64` counterpart, in Rust and in
/// CasADi (the solver's `eval_casadi` runs CasADi's SX evaluator on the same tape). Tolerance
/// 1e-12 relative: the same libm functions up to rounding.
#[test]
fn elementary_functions_agree_with_f64_and_casadi() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -1.0, 1.0).expect("bounds");
    let y = nlp
        .variable("y", f64::NEG_INFINITY, f64::INFINITY)
        .expect("bounds");
    let p = nlp.parameter("p");
    let (xv, yv, pv): (f64, f64, f64) = (0.37, -1.9, 2.2);
    let cases: Vec<(Expr, f64)> = vec![
        (&x + &y, xv + yv),
        (2.0 - &x, 2.0 - xv),
        (&x * 3.0, xv * 3.0),
        (1.0 / &y, 1.0 / yv),
        (-&y, -yv),
        (x.sin(), xv.sin()),
        (x.cos(), xv.cos()),
        (x.tan(), xv.tan()),
        (x.asin(), xv.asin()),
        (x.acos(), xv.acos()),
        (y.atan(), yv.atan()),
        (p.sqrt(), pv.sqrt()),
        (y.exp(), yv.exp()),
        (p.ln(), pv.ln()),
        (y.abs(), yv.abs()),
        (y.tanh(), yv.tanh()),
        (y.sinh(), yv.sinh()),
        (y.cosh(), yv.cosh()),
        (y.sq(), yv * yv),
        (y.powi(3), yv.powi(3)),
        (y.powi(-2), yv.powi(-2)),
        (p.pow(&x), pv.powf(xv)),
        (y.atan2(&x), yv.atan2(xv)),
        (x.min(&y), xv.min(yv)),
        (x.max(&y), xv.max(yv)),
        (x.max(0.5), 0.5),
    ];
    for (i, (e, _)) in cases.iter().enumerate() {
        nlp.constrain(e.clone(), f64::NEG_INFINITY, f64::INFINITY)
            .unwrap_or_else(|err| panic!("case {i}: {err}"));
    }
    let solver = nlp.build(&NlpSettings::default()).expect("build");
    let rust = solver.eval(&[xv, yv], &[pv]).expect("eval");
    let casadi = solver.eval_casadi(&[xv, yv], &[pv]).expect("eval_casadi");
    for (i, (e, want)) in cases.iter().enumerate() {
        let tol = 1e-12 * want.abs().max(1.0);
        let direct = nlp.eval(e, &[xv, yv], &[pv]).expect("eval");
        assert!(
            (direct - want).abs() < tol,
            "case {i} ({e}): {direct} vs {want}"
        );
        assert!((rust.g[i] - want).abs() < tol, "case {i} tape");
        assert!(
            (casadi.g[i] - want).abs() < tol,
            "case {i} casadi: {}",
            casadi.g[i]
        );
    }
}

/// Trivial cases fold to the operand or a constant, so identity-heavy transform products stay
/// small; constants fold completely.
#[test]
fn constant_folding() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", 0.0, 1.0).expect("bounds");
    assert_eq!(&x * 1.0, x);
    assert_eq!(1.0 * &x, x);
    assert_eq!(&x + 0.0, x);
    assert_eq!(0.0 + &x, x);
    assert_eq!(&x - 0.0, x);
    assert_eq!(&x / 1.0, x);
    assert_eq!(-(-&x), x);
    assert_eq!((&x * 0.0).as_constant(), Some(0.0));
    assert_eq!((Expr::constant(2.0) * 3.0 + 1.0).as_constant(), Some(7.0));
    assert_eq!(Expr::constant(0.5).sin().as_constant(), Some(0.5f64.sin()));
    // A symbolic product is a new node, not folded.
    assert_eq!((&x * 2.0).as_constant(), None);
    assert_ne!(&x * 2.0, x);
}

/// A shared subexpression is stored and emitted once: e_{k+1} = e_k + e_k, 60 times, is a
/// 61-node DAG whose tree would have 2^60 leaves. Both evaluators finish and give 2^60·x.
#[test]
fn shared_subexpressions_are_not_duplicated() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -1.0, 1.0).expect("bounds");
    let mut e = x.sin();
    for _ in 0..60 {
        e = &e + &e;
    }
    let want = 2f64.powi(60) * 0.25f64.sin();
    let got = nlp.eval(&e, &[0.25], &[]).expect("eval");
    assert!((got - want).abs() <= 1e-15 * want);
    nlp.constrain(e, f64::NEG_INFINITY, f64::INFINITY)
        .expect("constraint");
    let solver = nlp.build(&NlpSettings::default()).expect("build");
    let c = solver.eval_casadi(&[0.25], &[]).expect("eval_casadi");
    assert!((c.g[0] - want).abs() <= 1e-15 * want);
}

/// A 100 000-term chain is built, evaluated and dropped without recursion (no stack overflow).
#[test]
fn deep_chains_do_not_overflow_the_stack() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -1.0, 1.0).expect("bounds");
    let n = 100_000;
    let sum: Expr = (0..n).map(|i| &x * f64::from(i)).sum();
    let got = nlp.eval(&sum, &[2.0], &[]).expect("eval");
    // 2 · Σ i = 2 · n(n-1)/2, exact in f64 (< 2^53).
    assert_eq!(got, f64::from(n) * f64::from(n - 1));
    drop(sum);
}
