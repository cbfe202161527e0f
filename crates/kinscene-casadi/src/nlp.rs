//! The NLP builder: variables with bounds, parameters, objective and constraints.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::Error;
use crate::expr::{Expr, Kind, NO_OWNER, Owner};
use crate::tape::Tape;

/// A nonlinear program under construction:
///
/// ```text
///   minimise    f(x, p)
///   subject to  lbx <= x <= ubx,   lbg <= g(x, p) <= ubg
/// ```
///
/// with decision variables `x`, parameters `p` (fixed values given at each
/// [`solve`](crate::NlpSolver::solve), so one compiled solver serves many problem instances),
/// objective `f` (the sum of all [`minimize`](Nlp::minimize) terms, 0 if none) and constraints
/// `g` (one per [`constrain`](Nlp::constrain) call, in call order).
///
/// Bounds are numbers fixed when the solver is built; a bound that changes from solve to solve
/// is written as a constraint with a parameter (`constrain(&q - &p, 0.0, f64::INFINITY)`).
///
/// # Example
/// ```
/// use kinscene_casadi::{Nlp, NlpSettings};
/// # fn main() -> Result<(), kinscene_casadi::Error> {
/// let mut nlp = Nlp::new();
/// let x = nlp.variable("x", f64::NEG_INFINITY, f64::INFINITY)?;
/// let y = nlp.variable("y", f64::NEG_INFINITY, f64::INFINITY)?;
/// let r = nlp.parameter("r");
/// nlp.minimize(&x + &y)?;
/// nlp.constrain_eq(x.sq() + y.sq() - r.sq(), 0.0)?; // on the circle of radius r
/// let solver = nlp.build(&NlpSettings::default())?;
/// let sol = solver.solve(&[-1.0, -0.5], &[2.0])?;
/// assert!(sol.status.is_success());
/// // x = y = -r / sqrt(2)
/// assert!((sol.x[0] + 2f64.sqrt()).abs() < 1e-6);
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct Nlp {
    id: Owner,
    pub(crate) var_names: Vec<String>,
    pub(crate) lbx: Vec<f64>,
    pub(crate) ubx: Vec<f64>,
    pub(crate) param_names: Vec<String>,
    pub(crate) objective: Option<Expr>,
    pub(crate) constraints: Vec<Expr>,
    pub(crate) lbg: Vec<f64>,
    pub(crate) ubg: Vec<f64>,
}

impl Default for Nlp {
    fn default() -> Self {
        Nlp::new()
    }
}

/// Checks `lower <= upper`, no NaN, and that the interval contains a real number.
fn check_bounds(lower: f64, upper: f64, what: impl Fn() -> String) -> Result<(), Error> {
    if lower.is_nan() {
        return Err(Error::NonFinite {
            what: format!("lower bound of {}", what()),
        });
    }
    if upper.is_nan() {
        return Err(Error::NonFinite {
            what: format!("upper bound of {}", what()),
        });
    }
    if lower > upper || lower == f64::INFINITY || upper == f64::NEG_INFINITY {
        return Err(Error::InvalidBounds {
            what: what(),
            lower,
            upper,
        });
    }
    Ok(())
}

impl Nlp {
    /// An empty problem.
    pub fn new() -> Nlp {
        static NEXT_ID: AtomicU64 = AtomicU64::new(1);
        Nlp {
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            var_names: Vec::new(),
            lbx: Vec::new(),
            ubx: Vec::new(),
            param_names: Vec::new(),
            objective: None,
            constraints: Vec::new(),
            lbg: Vec::new(),
            ubg: Vec::new(),
        }
    }

    /// Adds a decision variable with bounds `lower <= x <= upper` (either may be infinite).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a NaN bound, [`Error::InvalidBounds`] for `lower > upper` or an
    /// empty interval (`lower = +inf` or `upper = -inf`).
    pub fn variable(&mut self, name: &str, lower: f64, upper: f64) -> Result<Expr, Error> {
        check_bounds(lower, upper, || format!("variable `{name}`"))?;
        let index = self.var_names.len();
        self.var_names.push(name.to_owned());
        self.lbx.push(lower);
        self.ubx.push(upper);
        Ok(Expr::leaf(Kind::Var(index), self.id))
    }

    /// Adds `lower.len()` variables named `name[i]`, with bounds `lower[i] <= x[i] <= upper[i]`
    /// (e.g. an arm configuration with its joint limits).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] when the slices differ in length; otherwise as
    /// [`variable`](Nlp::variable) (no variable is added on error).
    pub fn variables(
        &mut self,
        name: &str,
        lower: &[f64],
        upper: &[f64],
    ) -> Result<Vec<Expr>, Error> {
        if lower.len() != upper.len() {
            return Err(Error::DimensionMismatch {
                what: "upper bounds",
                expected: lower.len(),
                got: upper.len(),
            });
        }
        for (i, (&lo, &hi)) in lower.iter().zip(upper).enumerate() {
            check_bounds(lo, hi, || format!("variable `{name}[{i}]`"))?;
        }
        Ok(lower
            .iter()
            .zip(upper)
            .enumerate()
            .map(|(i, (&lo, &hi))| {
                self.variable(&format!("{name}[{i}]"), lo, hi)
                    .expect("bounds checked above")
            })
            .collect())
    }

    /// Adds a parameter: a symbol whose value is given at each solve.
    pub fn parameter(&mut self, name: &str) -> Expr {
        let index = self.param_names.len();
        self.param_names.push(name.to_owned());
        Expr::leaf(Kind::Param(index), self.id)
    }

    /// Adds `n` parameters named `name[i]`.
    pub fn parameters(&mut self, name: &str, n: usize) -> Vec<Expr> {
        (0..n)
            .map(|i| self.parameter(&format!("{name}[{i}]")))
            .collect()
    }

    fn check_owner(&self, e: &Expr, what: &'static str) -> Result<(), Error> {
        match e.owner() {
            NO_OWNER => Ok(()),
            o if o == self.id => Ok(()),
            _ => Err(Error::ForeignExpr { what }),
        }
    }

    /// Adds `term` to the objective (the objective is the sum of all terms).
    ///
    /// # Errors
    /// [`Error::ForeignExpr`] when `term` uses another `Nlp`'s symbols.
    pub fn minimize(&mut self, term: impl Into<Expr>) -> Result<(), Error> {
        let term = term.into();
        self.check_owner(&term, "objective")?;
        self.objective = Some(match self.objective.take() {
            Some(f) => f + term,
            None => term,
        });
        Ok(())
    }

    /// Adds the constraint `lower <= g <= upper` (either bound may be infinite) and returns its
    /// index in `g` and `lam_g` of the solution.
    ///
    /// # Errors
    /// [`Error::ForeignExpr`], [`Error::NonFinite`] for a NaN bound, [`Error::InvalidBounds`].
    pub fn constrain(
        &mut self,
        g: impl Into<Expr>,
        lower: f64,
        upper: f64,
    ) -> Result<usize, Error> {
        let g = g.into();
        let index = self.constraints.len();
        self.check_owner(&g, "constraint")?;
        check_bounds(lower, upper, || format!("constraint {index}"))?;
        self.constraints.push(g);
        self.lbg.push(lower);
        self.ubg.push(upper);
        Ok(index)
    }

    /// Adds the equality constraint `g = value` and returns its index.
    ///
    /// # Errors
    /// [`Error::NonFinite`] unless `value` is finite; as [`constrain`](Nlp::constrain).
    pub fn constrain_eq(&mut self, g: impl Into<Expr>, value: f64) -> Result<usize, Error> {
        if !value.is_finite() {
            return Err(Error::NonFinite {
                what: format!("value of equality constraint {}", self.constraints.len()),
            });
        }
        self.constrain(g, value, value)
    }

    /// Number of decision variables.
    pub fn n_variables(&self) -> usize {
        self.var_names.len()
    }

    /// Number of parameters.
    pub fn n_parameters(&self) -> usize {
        self.param_names.len()
    }

    /// Number of constraints.
    pub fn n_constraints(&self) -> usize {
        self.constraints.len()
    }

    /// The names of the variables, by index.
    pub fn variable_names(&self) -> &[String] {
        &self.var_names
    }

    /// The objective expression (the constant 0 when nothing was minimised).
    pub fn objective(&self) -> Expr {
        self.objective
            .clone()
            .unwrap_or_else(|| Expr::constant(0.0))
    }

    /// The constraint expressions, by index.
    pub fn constraints(&self) -> &[Expr] {
        &self.constraints
    }

    /// Evaluates `expr` in Rust (no CasADi involved) at variables `x` and parameters `p`: an
    /// independent check of a solution.
    ///
    /// # Errors
    /// [`Error::ForeignExpr`], [`Error::DimensionMismatch`] unless `x` and `p` have one value
    /// per variable and parameter.
    pub fn eval(&self, expr: &Expr, x: &[f64], p: &[f64]) -> Result<f64, Error> {
        self.check_owner(expr, "eval")?;
        self.check_lengths(x, p)?;
        Ok(Tape::new([expr]).eval(x, p)[0])
    }

    pub(crate) fn check_lengths(&self, x: &[f64], p: &[f64]) -> Result<(), Error> {
        if x.len() != self.n_variables() {
            return Err(Error::DimensionMismatch {
                what: "x",
                expected: self.n_variables(),
                got: x.len(),
            });
        }
        if p.len() != self.n_parameters() {
            return Err(Error::DimensionMismatch {
                what: "p",
                expected: self.n_parameters(),
                got: p.len(),
            });
        }
        Ok(())
    }

    pub(crate) fn id(&self) -> Owner {
        self.id
    }
}
