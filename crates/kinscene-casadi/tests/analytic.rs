//! IPOPT solves checked against closed-form or independently computed optima.

use kinscene_casadi::{Nlp, NlpSettings, NlpSolver, NlpStatus};

const INF: f64 = f64::INFINITY;

/// min x + y  s.t.  x²/a² + y²/b² = 1, with a and b as parameters.
fn ellipse_linear_objective() -> NlpSolver {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -INF, INF).expect("bounds");
    let y = nlp.variable("y", -INF, INF).expect("bounds");
    let a = nlp.parameter("a");
    let b = nlp.parameter("b");
    nlp.minimize(&x + &y).expect("objective");
    nlp.constrain_eq(x.sq() / a.sq() + y.sq() / b.sq(), 1.0)
        .expect("constraint");
    nlp.build(&NlpSettings::default()).expect("build")
}

/// Lagrange: ∇(x + y) + λ ∇(x²/a² + y²/b²) = 0 gives 1 + 2λx/a² = 0 and 1 + 2λy/b² = 0, so
/// (x, y) = -(a², b²)/(2λ); the constraint gives (a² + b²)/(4λ²) = 1, and the minimum (x, y < 0)
/// has λ = √(a² + b²)/2 > 0: (x, y) = -(a², b²)/√(a² + b²), f = -√(a² + b²).
/// CasADi's Lagrangian is f + λ·g, so CasADi's lam_g equals this λ, sign included.
///
/// One compiled solver is solved for several parameter values. Tolerance 1e-6 on x, f, λ:
/// IPOPT stops at a scaled KKT error of 1e-8 (default `tolerance`), and this problem is well
/// conditioned (curvature ~1/a², multiplier O(1)).
#[test]
fn ellipse_linear_objective_matches_lagrange_for_several_parameters() {
    let solver = ellipse_linear_objective();
    for (a, b) in [(2.0, 1.0), (1.0, 1.0), (0.5, 3.0), (4.0, 0.25)] {
        let sol = solver.solve(&[-a * 0.5, -b * 0.5], &[a, b]).expect("solve");
        assert_eq!(sol.status, NlpStatus::SolveSucceeded, "a={a} b={b}");
        let r = f64::hypot(a, b);
        let want = [-a * a / r, -b * b / r];
        for (got, want) in sol.x.iter().zip(want) {
            assert!((got - want).abs() < 1e-6, "a={a} b={b}: x={:?}", sol.x);
        }
        assert!((sol.f + r).abs() < 1e-6);
        assert!(
            (sol.lam_g[0] - r / 2.0).abs() < 1e-6,
            "lam_g={:?}",
            sol.lam_g
        );
        assert!((sol.g[0] - 1.0).abs() < 1e-6);
        assert!(
            sol.lam_x.iter().all(|l| l.abs() < 1e-9),
            "no bounds, no lam_x"
        );
        assert!(sol.iterations > 0);
    }
}

/// Eberly's robust bisection for the root s̄ of G(s) = (r0 z0/(s + r0))² + (z1/(s + 1))² - 1
/// ("Distance from a Point to an Ellipse, an Ellipsoid, or a Hyperellipsoid", 2013).
fn eberly_root(r0: f64, z0: f64, z1: f64, g: f64) -> f64 {
    let n0 = r0 * z0;
    let mut s0 = z1 - 1.0;
    let mut s1 = if g < 0.0 { 0.0 } else { n0.hypot(z1) - 1.0 };
    let mut s = 0.0;
    for _ in 0..2000 {
        s = 0.5 * (s0 + s1);
        if s == s0 || s == s1 {
            break;
        }
        let g = (n0 / (s + r0)).powi(2) + (z1 / (s + 1.0)).powi(2) - 1.0;
        if g > 0.0 {
            s0 = s;
        } else if g < 0.0 {
            s1 = s;
        } else {
            break;
        }
    }
    s
}

/// The closest point of the ellipse x²/e0² + y²/e1² = 1 (e0 >= e1) to (y0, y1), by Eberly's
/// method in the first quadrant and reflection.
fn eberly_closest_point(e0: f64, e1: f64, y0: f64, y1: f64) -> [f64; 2] {
    let (a0, a1) = (y0.abs(), y1.abs());
    let (x0, x1) = if a1 > 0.0 {
        if a0 > 0.0 {
            let (z0, z1) = (a0 / e0, a1 / e1);
            let g = z0 * z0 + z1 * z1 - 1.0;
            if g != 0.0 {
                let r0 = (e0 / e1).powi(2);
                let s = eberly_root(r0, z0, z1, g);
                (r0 * a0 / (s + r0), a1 / (s + 1.0))
            } else {
                (a0, a1)
            }
        } else {
            (0.0, e1)
        }
    } else {
        let (numer, denom) = (e0 * a0, e0 * e0 - e1 * e1);
        if numer < denom {
            let xde = numer / denom;
            (e0 * xde, e1 * (1.0 - xde * xde).sqrt())
        } else {
            (e0, 0.0)
        }
    };
    [x0.copysign(y0), x1.copysign(y1)]
}

/// Closest point on the ellipse x²/4 + y²/2.25 = 1 to external points given as parameters,
/// from the radial projection as initial guess, against Eberly's bisection. For a² < 2b² the
/// ellipse's evolute lies inside it, so an external point has one local minimum of the distance
/// and IPOPT's local answer is the global one. Tolerance 1e-6 (IPOPT tol 1e-8; the bisection is
/// exact to rounding).
#[test]
fn closest_point_on_ellipse_matches_eberly() {
    let (a, b) = (2.0, 1.5);
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -INF, INF).expect("bounds");
    let y = nlp.variable("y", -INF, INF).expect("bounds");
    let p = nlp.parameters("point", 2);
    nlp.minimize((&x - &p[0]).sq() + (&y - &p[1]).sq())
        .expect("objective");
    nlp.constrain_eq(x.sq() / (a * a) + y.sq() / (b * b), 1.0)
        .expect("constraint");
    let solver = nlp.build(&NlpSettings::default()).expect("build");
    for point in [
        [3.0, 2.0],
        [-2.5, 1.5],
        [0.5, -3.0],
        [-4.0, -0.1],
        [0.0, 2.5],
        [5.0, 0.3],
    ] {
        let t = 1.0 / ((point[0] / a).powi(2) + (point[1] / b).powi(2)).sqrt();
        let sol = solver
            .solve(&[t * point[0], t * point[1]], &point)
            .expect("solve");
        assert!(sol.status.is_success(), "{point:?}: {:?}", sol.status);
        let want = eberly_closest_point(a, b, point[0], point[1]);
        for (got, want_i) in sol.x.iter().zip(want) {
            assert!(
                (got - want_i).abs() < 1e-6,
                "{point:?}: ipopt {:?} vs eberly {want:?}",
                sol.x
            );
        }
        // Rust evaluation of the same expressions agrees with CasADi's f and g at the solution
        // (same operations, rounding only: 1e-12 relative).
        let rust = solver.eval(&sol.x, &point).expect("eval");
        assert!((rust.f - sol.f).abs() <= 1e-12 * sol.f.abs().max(1.0));
        assert!((rust.g[0] - sol.g[0]).abs() <= 1e-12);
        assert_eq!(sol.value(&x), Some(sol.x[0]));
    }
}

/// A bound and an inequality, both active: min (x-2)² + (y-2)²  s.t.  x <= 0.5 (bound),
/// x + y <= 2. By hand: x = 0.5, y = 1.5, f = 2.5. KKT with CasADi's Lagrangian
/// f + λx·x + λg·g: ∂/∂y: 2(y - 2) + λg = 0 → λg = 1; ∂/∂x: 2(x - 2) + λg + λx = 0 → λx = 2.
/// Both positive: upper bounds active.
#[test]
fn active_bound_and_inequality_multipliers() {
    let mut nlp = Nlp::new();
    let x = nlp.variable("x", -INF, 0.5).expect("bounds");
    let y = nlp.variable("y", -INF, INF).expect("bounds");
    nlp.minimize((&x - 2.0).sq() + (&y - 2.0).sq())
        .expect("objective");
    nlp.constrain(&x + &y, -INF, 2.0).expect("constraint");
    let solver = nlp.build(&NlpSettings::default()).expect("build");
    let sol = solver.solve(&[0.0, 0.0], &[]).expect("solve");
    assert_eq!(sol.status, NlpStatus::SolveSucceeded);
    assert!((sol.x[0] - 0.5).abs() < 1e-6 && (sol.x[1] - 1.5).abs() < 1e-6);
    assert!((sol.f - 2.5).abs() < 1e-6);
    assert!((sol.lam_g[0] - 1.0).abs() < 1e-6, "lam_g {:?}", sol.lam_g);
    assert!((sol.lam_x[0] - 2.0).abs() < 1e-6, "lam_x {:?}", sol.lam_x);
    assert!(sol.lam_x[1].abs() < 1e-6);
}
