//! The shim's C ABI (`cpp/shim.h`), loaded once per process.

use std::ffi::{CStr, c_char, c_int};
use std::sync::OnceLock;

use kinscene_shim::{LoadError, Shim};

/// Opaque `ks_casadi_nlp`.
#[repr(C)]
pub(crate) struct RawNlp {
    _private: [u8; 0],
}

pub(crate) type VersionFn = unsafe extern "C" fn() -> *const c_char;

pub(crate) type NlpNewFn = unsafe extern "C" fn(
    n_x: usize,
    n_p: usize,
    n_nodes: usize,
    op: *const i32,
    arg0: *const i32,
    arg1: *const i32,
    value: *const f64,
    f_node: i32,
    n_g: usize,
    g_nodes: *const i32,
    lbx: *const f64,
    ubx: *const f64,
    lbg: *const f64,
    ubg: *const f64,
    n_opts: usize,
    opt_names: *const *const c_char,
    opt_kinds: *const i32,
    opt_numbers: *const f64,
    opt_strings: *const *const c_char,
    out: *mut *mut RawNlp,
    err: *mut c_char,
    err_len: usize,
) -> c_int;

pub(crate) type NlpFreeFn = unsafe extern "C" fn(nlp: *mut RawNlp);

pub(crate) type NlpSolveFn = unsafe extern "C" fn(
    nlp: *const RawNlp,
    n_x: usize,
    x0: *const f64,
    n_p: usize,
    p: *const f64,
    x: *mut f64,
    f: *mut f64,
    g: *mut f64,
    lam_x: *mut f64,
    lam_g: *mut f64,
    status: *mut c_char,
    status_len: usize,
    iterations: *mut i64,
    err: *mut c_char,
    err_len: usize,
) -> c_int;

pub(crate) type NlpEvalFn = unsafe extern "C" fn(
    nlp: *const RawNlp,
    n_x: usize,
    x: *const f64,
    n_p: usize,
    p: *const f64,
    f: *mut f64,
    g: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int;

/// The loaded shim and its entry points.
pub(crate) struct Api {
    _shim: Shim,
    pub(crate) version: &'static str,
    pub(crate) nlp_new: NlpNewFn,
    pub(crate) nlp_free: NlpFreeFn,
    pub(crate) nlp_solve: NlpSolveFn,
    pub(crate) nlp_eval: NlpEvalFn,
}

fn load() -> Result<Api, LoadError> {
    let shim = Shim::open(
        "CasADi",
        "KINSCENE_CASADI_SHIM",
        option_env!("KINSCENE_CASADI_SHIM_BUILT"),
    )?;
    // SAFETY: each type is the exact signature declared in cpp/shim.h.
    unsafe {
        let version_fn = shim.function::<VersionFn>("ks_casadi_version")?;
        // SAFETY: returns a pointer to a static NUL-terminated string (CASADI_VERSION_STRING)
        // that lives as long as the shim, which is never unloaded (it stays in `API`).
        let version = CStr::from_ptr(version_fn()).to_str().unwrap_or("unknown");
        Ok(Api {
            version,
            nlp_new: shim.function("ks_casadi_nlp_new")?,
            nlp_free: shim.function("ks_casadi_nlp_free")?,
            nlp_solve: shim.function("ks_casadi_nlp_solve")?,
            nlp_eval: shim.function("ks_casadi_nlp_eval")?,
            _shim: shim,
        })
    }
}

/// The process-wide shim, loaded on first use.
pub(crate) fn api() -> Result<&'static Api, LoadError> {
    static API: OnceLock<Result<Api, LoadError>> = OnceLock::new();
    API.get_or_init(load).as_ref().map_err(Clone::clone)
}

/// The CasADi version the shim was built against (e.g. `"3.8.2"`).
///
/// # Errors
/// [`crate::Error::Load`] when the shim cannot be loaded.
pub fn casadi_version() -> Result<&'static str, crate::Error> {
    Ok(api()?.version)
}
