//! Building the IPOPT solver once and solving it many times.

use std::ffi::{CString, c_char};
use std::ptr::NonNull;
use std::time::Instant;

use crate::Error;
use crate::expr::Owner;
use crate::ffi::{RawNlp, api};
use crate::nlp::Nlp;
use crate::settings::{CasadiOption, NlpSettings};
use crate::solution::{NlpSolution, NlpStatus};
use crate::tape::Tape;

/// Objective and constraint values at a point.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// The objective.
    pub f: f64,
    /// The constraints, by index.
    pub g: Vec<f64>,
}

/// A compiled NLP: CasADi's IPOPT solver (`casadi::nlpsol`), created once by
/// [`Nlp::build`], solved any number of times with different initial guesses and parameter
/// values.
///
/// `NlpSolver` is `Send` but not `Sync`: it may be moved to another thread and used there, and
/// solvers in different threads may run at the same time (CasADi is built with thread-safe
/// reference counts and symbolics, `CASADI_WITH_THREAD`, and IPOPT serialises its calls into
/// MUMPS with a process-wide mutex), but one solver is not shared between threads. To solve in
/// parallel, build one solver per thread.
#[derive(Debug)]
pub struct NlpSolver {
    raw: NonNull<RawNlp>,
    tape: Tape,
    n_x: usize,
    n_p: usize,
    n_g: usize,
    owner: Owner,
}

// SAFETY: the handle exclusively owns its CasADi objects (no other handle shares the Function
// or its SX graph); CasADi's reference counts are atomic and its global symbolic caches are
// mutex-guarded in this build (CASADI_WITH_THREAD, CASADI_WITH_THREADSAFE_SYMBOLICS), so using
// and dropping it on another thread is sound. Not `Sync`: concurrent `solve` on one handle is
// not needed and not relied upon.
unsafe impl Send for NlpSolver {}

impl Drop for NlpSolver {
    fn drop(&mut self) {
        if let Ok(api) = api() {
            // SAFETY: `raw` came from ks_casadi_nlp_new and is freed exactly once.
            unsafe { (api.nlp_free)(self.raw.as_ptr()) };
        }
    }
}

impl Nlp {
    /// Compiles the problem: serialises the expression DAG, rebuilds it as CasADi SX and
    /// creates the IPOPT solver (CasADi generates the gradient, Jacobian and Hessian
    /// functions here). The first build in a process also loads the IPOPT plugin.
    ///
    /// The `Nlp` is left intact (e.g. for [`Nlp::eval`]).
    ///
    /// # Errors
    /// [`Error::NoVariables`]; [`Error::InvalidSetting`] / [`Error::InvalidOption`] from
    /// [`NlpSettings::validate`]; [`Error::NonFinite`] for a NaN or infinite constant inside an
    /// expression; [`Error::Load`] when the shim cannot be loaded; [`Error::Backend`] when
    /// CasADi or IPOPT rejects the problem or an option (e.g. an unknown IPOPT option name).
    pub fn build(&self, settings: &NlpSettings) -> Result<NlpSolver, Error> {
        if self.n_variables() == 0 {
            return Err(Error::NoVariables);
        }
        settings.validate()?;
        let mut roots = Vec::with_capacity(1 + self.constraints.len());
        let objective = self.objective();
        roots.push(&objective);
        roots.extend(self.constraints.iter());
        let tape = Tape::new(roots);
        tape.check_constants()?;
        let c = tape.to_c()?;
        let f_node = i32::try_from(tape.outputs[0]).map_err(|_| Error::TooLarge {
            what: "tape",
            len: tape.steps.len(),
        })?;
        let g_nodes: Vec<i32> = tape.outputs[1..].iter().map(|&i| i as i32).collect();

        let opts = settings.to_casadi();
        let names: Vec<CString> = opts
            .iter()
            .map(|(n, _)| CString::new(n.as_str()).expect("validated: no NUL"))
            .collect();
        let strings: Vec<CString> = opts
            .iter()
            .map(|(_, v)| match v {
                CasadiOption::Text(s) => CString::new(s.as_str()).expect("validated: no NUL"),
                _ => CString::default(),
            })
            .collect();
        let (kinds, numbers): (Vec<i32>, Vec<f64>) = opts
            .iter()
            .map(|(_, v)| match *v {
                CasadiOption::Real(x) => (0, x),
                CasadiOption::Int(i) => (1, i as f64),
                CasadiOption::Text(_) => (2, 0.0),
                CasadiOption::Bool(b) => (3, f64::from(u8::from(b))),
            })
            .unzip();
        let name_ptrs: Vec<*const c_char> = names.iter().map(|s| s.as_ptr()).collect();
        let string_ptrs: Vec<*const c_char> = strings.iter().map(|s| s.as_ptr()).collect();

        let api = api()?;
        let mut raw: *mut RawNlp = std::ptr::null_mut();
        kinscene_shim::call("ks_casadi_nlp_new", |err, err_len| {
            // SAFETY: every pointer addresses a live buffer of the length passed next to it
            // (tape arrays: n_nodes; g_nodes, lbg, ubg: n_g; lbx, ubx: n_x; options: n_opts);
            // the tape is topologically ordered with leaf indices < n_x / n_p.
            unsafe {
                (api.nlp_new)(
                    self.n_variables(),
                    self.n_parameters(),
                    c.op.len(),
                    c.op.as_ptr(),
                    c.arg0.as_ptr(),
                    c.arg1.as_ptr(),
                    c.value.as_ptr(),
                    f_node,
                    g_nodes.len(),
                    g_nodes.as_ptr(),
                    self.lbx.as_ptr(),
                    self.ubx.as_ptr(),
                    self.lbg.as_ptr(),
                    self.ubg.as_ptr(),
                    opts.len(),
                    name_ptrs.as_ptr(),
                    kinds.as_ptr(),
                    numbers.as_ptr(),
                    string_ptrs.as_ptr(),
                    &mut raw,
                    err,
                    err_len,
                )
            }
        })?;
        let raw = NonNull::new(raw).expect("ks_casadi_nlp_new returned OK with a handle");
        Ok(NlpSolver {
            raw,
            tape,
            n_x: self.n_variables(),
            n_p: self.n_parameters(),
            n_g: self.n_constraints(),
            owner: self.id(),
        })
    }
}

impl NlpSolver {
    /// Number of decision variables.
    pub fn n_variables(&self) -> usize {
        self.n_x
    }

    /// Number of parameters.
    pub fn n_parameters(&self) -> usize {
        self.n_p
    }

    /// Number of constraints.
    pub fn n_constraints(&self) -> usize {
        self.n_g
    }

    fn check_point(&self, x: &[f64], p: &[f64], x_name: &'static str) -> Result<(), Error> {
        if x.len() != self.n_x {
            return Err(Error::DimensionMismatch {
                what: x_name,
                expected: self.n_x,
                got: x.len(),
            });
        }
        if p.len() != self.n_p {
            return Err(Error::DimensionMismatch {
                what: "params",
                expected: self.n_p,
                got: p.len(),
            });
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: x_name.to_owned(),
            });
        }
        if p.iter().any(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: "params".to_owned(),
            });
        }
        Ok(())
    }

    /// Solves from the initial guess `x0` (one value per variable; IPOPT moves it inside the
    /// bounds) with parameter values `params` (one per parameter, in creation order).
    ///
    /// Not converging is an outcome: check [`NlpSolution::status`].
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`], [`Error::NonFinite`] for bad inputs; [`Error::Backend`]
    /// when CasADi or IPOPT throws.
    pub fn solve(&self, x0: &[f64], params: &[f64]) -> Result<NlpSolution, Error> {
        self.check_point(x0, params, "x0")?;
        let api = api()?;
        let mut x = vec![0.0; self.n_x];
        let mut lam_x = vec![0.0; self.n_x];
        let mut g = vec![0.0; self.n_g];
        let mut lam_g = vec![0.0; self.n_g];
        let mut f = 0.0;
        let mut status = [0 as c_char; 128];
        let mut iterations: i64 = 0;
        let start = Instant::now();
        kinscene_shim::call("ks_casadi_nlp_solve", |err, err_len| {
            // SAFETY: x0, x, lam_x have n_x values; params n_p; g, lam_g n_g (sizes checked
            // above and again by the shim); status has status.len() bytes.
            unsafe {
                (api.nlp_solve)(
                    self.raw.as_ptr(),
                    self.n_x,
                    x0.as_ptr(),
                    self.n_p,
                    params.as_ptr(),
                    x.as_mut_ptr(),
                    &mut f,
                    g.as_mut_ptr(),
                    lam_x.as_mut_ptr(),
                    lam_g.as_mut_ptr(),
                    status.as_mut_ptr(),
                    status.len(),
                    &mut iterations,
                    err,
                    err_len,
                )
            }
        })?;
        let solve_time = start.elapsed();
        // SAFETY: the shim NUL-terminates within the buffer (the buffer was zeroed, too).
        let status = unsafe { std::ffi::CStr::from_ptr(status.as_ptr()) }.to_string_lossy();
        Ok(NlpSolution {
            x,
            f,
            g,
            lam_x,
            lam_g,
            status: NlpStatus::from_ipopt(&status),
            iterations: usize::try_from(iterations).unwrap_or(0),
            solve_time,
            owner: self.owner,
        })
    }

    /// Evaluates the objective and constraints in Rust, over the same expression tape that was
    /// sent to CasADi (independent of CasADi's evaluator).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`], [`Error::NonFinite`] for bad inputs.
    pub fn eval(&self, x: &[f64], params: &[f64]) -> Result<Evaluation, Error> {
        self.check_point(x, params, "x")?;
        let mut out = self.tape.eval(x, params);
        let f = out.remove(0);
        Ok(Evaluation { f, g: out })
    }

    /// Evaluates the objective and constraints with CasADi's SX evaluator (the functions IPOPT
    /// sees).
    ///
    /// # Errors
    /// As [`eval`](NlpSolver::eval), plus [`Error::Backend`].
    pub fn eval_casadi(&self, x: &[f64], params: &[f64]) -> Result<Evaluation, Error> {
        self.check_point(x, params, "x")?;
        let api = api()?;
        let mut f = 0.0;
        let mut g = vec![0.0; self.n_g];
        kinscene_shim::call("ks_casadi_nlp_eval", |err, err_len| {
            // SAFETY: x has n_x values, params n_p, g n_g.
            unsafe {
                (api.nlp_eval)(
                    self.raw.as_ptr(),
                    self.n_x,
                    x.as_ptr(),
                    self.n_p,
                    params.as_ptr(),
                    &mut f,
                    g.as_mut_ptr(),
                    err,
                    err_len,
                )
            }
        })?;
        Ok(Evaluation { f, g })
    }
}
