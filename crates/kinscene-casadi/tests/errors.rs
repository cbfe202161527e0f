//! Bad input gives typed errors; CasADi's C++ exceptions surface as `Error::Backend`.

use kinscene_casadi::CallError;
use kinscene_casadi::{Error, Expr, IpoptOption, Nlp, NlpSettings};

const INF: f64 = f64::INFINITY;

#[test]
fn bad_bounds() {
    let mut nlp = Nlp::new();
    assert!(matches!(
        nlp.variable("a", f64::NAN, 1.0),
        Err(Error::NonFinite { what }) if what.contains("`a`")
    ));
    assert!(matches!(
        nlp.variable("b", 0.0, f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        nlp.variable("c", 2.0, 1.0),
        Err(Error::InvalidBounds {
            lower: 2.0,
            upper: 1.0,
            ..
        })
    ));
    assert!(matches!(
        nlp.variable("d", INF, INF),
        Err(Error::InvalidBounds { .. })
    ));
    assert!(matches!(
        nlp.variable("e", -INF, -INF),
        Err(Error::InvalidBounds { .. })
    ));
    assert!(matches!(
        nlp.variables("q", &[0.0, 0.0], &[1.0]),
        Err(Error::DimensionMismatch {
            expected: 2,
            got: 1,
            ..
        })
    ));
    assert!(matches!(
        nlp.variables("q", &[0.0, 0.0], &[1.0, -1.0]),
        Err(Error::InvalidBounds { what, .. }) if what.contains("q[1]")
    ));
    assert_eq!(nlp.n_variables(), 0, "failed calls add nothing");

    let x = nlp.variable("x", -1.0, 1.0).expect("valid");
    assert!(matches!(
        nlp.constrain(x.clone(), 1.0, 0.0),
        Err(Error::InvalidBounds { .. })
    ));
    assert!(matches!(
        nlp.constrain(x.clone(), f64::NAN, 0.0),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        nlp.constrain_eq(x.clone(), f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        nlp.constrain_eq(x.clone(), INF),
        Err(Error::NonFinite { .. })
    ));
    assert_eq!(nlp.n_constraints(), 0);
}

#[test]
fn expressions_of_another_nlp_are_rejected() {
    let mut a = Nlp::new();
    let mut b = Nlp::new();
    let xa = a.variable("x", -1.0, 1.0).expect("valid");
    let xb = b.variable("x", -1.0, 1.0).expect("valid");
    assert!(matches!(
        a.minimize(xb.sin()),
        Err(Error::ForeignExpr { what: "objective" })
    ));
    assert!(matches!(
        a.constrain(&xa + &xb, 0.0, 1.0),
        Err(Error::ForeignExpr { what: "constraint" })
    ));
    assert!(matches!(
        a.eval(&xb, &[0.0], &[]),
        Err(Error::ForeignExpr { .. })
    ));
    // Constants belong to every problem.
    a.minimize(Expr::constant(1.0) + &xa)
        .expect("own + constant");
    b.minimize(xb).expect("own");
}

#[test]
fn build_rejects_empty_and_non_finite_problems() {
    let mut nlp = Nlp::new();
    let p = nlp.parameter("p");
    nlp.minimize(p).expect("objective");
    assert!(matches!(
        nlp.build(&NlpSettings::default()),
        Err(Error::NoVariables)
    ));

    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -1.0, 1.0).expect("valid");
    nlp.minimize(&x * f64::NAN).expect("checked at build");
    assert!(matches!(
        nlp.build(&NlpSettings::default()),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn bad_solve_inputs() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -1.0, 1.0).expect("valid");
    let p = nlp.parameter("p");
    nlp.minimize((&x - &p).sq()).expect("objective");
    let solver = nlp.build(&NlpSettings::default()).expect("build");
    assert!(matches!(
        solver.solve(&[0.0, 0.0], &[0.0]),
        Err(Error::DimensionMismatch {
            what: "x0",
            expected: 1,
            got: 2
        })
    ));
    assert!(matches!(
        solver.solve(&[0.0], &[]),
        Err(Error::DimensionMismatch {
            what: "params",
            expected: 1,
            got: 0
        })
    ));
    assert!(matches!(
        solver.solve(&[f64::NAN], &[0.0]),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        solver.solve(&[0.0], &[INF]),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        nlp.eval(&x, &[], &[0.0]),
        Err(Error::DimensionMismatch { .. })
    ));
    // And the solver still works: min (x - 0.3)² on [-1, 1] is x = 0.3.
    let sol = solver.solve(&[0.0], &[0.3]).expect("solve");
    assert!((sol.x[0] - 0.3).abs() < 1e-6);
}

#[test]
fn invalid_settings() {
    let bad = |s: NlpSettings| s.validate().err();
    let d = NlpSettings::default;
    assert!(d().validate().is_ok());
    assert!(matches!(
        bad(NlpSettings {
            tolerance: 0.0,
            ..d()
        }),
        Some(Error::InvalidSetting {
            name: "tolerance",
            ..
        })
    ));
    assert!(matches!(
        bad(NlpSettings {
            max_cpu_time: f64::NAN,
            ..d()
        }),
        Some(Error::InvalidSetting {
            name: "max_cpu_time",
            ..
        })
    ));
    assert!(matches!(
        bad(NlpSettings {
            print_level: 13,
            ..d()
        }),
        Some(Error::InvalidSetting {
            name: "print_level",
            ..
        })
    ));
    for option in [
        IpoptOption::new("", 1i64),
        IpoptOption::new("mu init", 0.1),
        IpoptOption::new("mu_init", f64::NAN),
        IpoptOption::new("mu_strategy", "adap\0tive"),
        IpoptOption::new("max_soc", i64::MAX),
    ] {
        let s = NlpSettings {
            ipopt_options: vec![option.clone()],
            ..d()
        };
        assert!(
            matches!(bad(s), Some(Error::InvalidOption { .. })),
            "{option:?}"
        );
    }
}

/// An option name IPOPT does not know passes Rust's syntax check and is rejected by CasADi's
/// IPOPT interface with a C++ exception, which arrives as `Error::Backend` with its message.
/// A known option with a valid value builds.
#[test]
fn unknown_ipopt_option_is_a_backend_error() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -1.0, 1.0).expect("valid");
    nlp.minimize(x.sq()).expect("objective");
    let settings = NlpSettings {
        ipopt_options: vec![IpoptOption::new("no_such_option", 3i64)],
        ..NlpSettings::default()
    };
    match nlp.build(&settings) {
        Err(Error::Backend(CallError::Exception { message, .. })) => {
            assert!(message.contains("no_such_option"), "{message}");
        }
        other => panic!("expected a backend error, got {other:?}"),
    }
    let settings = NlpSettings {
        ipopt_options: vec![
            IpoptOption::new("mu_strategy", "adaptive"),
            IpoptOption::new("bound_push", 1e-3),
        ],
        ..NlpSettings::default()
    };
    let sol = nlp
        .build(&settings)
        .expect("valid options")
        .solve(&[0.5], &[])
        .expect("solve");
    assert!(sol.x[0].abs() < 1e-6);
}

#[test]
fn casadi_version_is_reported() {
    assert_eq!(
        kinscene_casadi::casadi_version().expect("shim loads"),
        "3.8.2"
    );
}
