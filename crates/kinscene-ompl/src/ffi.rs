//! The shim's C ABI (`cpp/shim.h`), declared by hand, and its lazy, once-per-process loading.
//!
//! Every type and signature here mirrors `shim.h` exactly; change both together.

use std::ffi::{c_char, c_int, c_void};
use std::sync::OnceLock;

use kinscene_shim::{LoadError, Shim};

use crate::Error;
use crate::global::{DEFAULT_LOG_LEVEL, LogLevel};

pub(crate) const SPACE_SE2: i32 = 0;
pub(crate) const SPACE_REAL_VECTOR: i32 = 1;
/// `ks_ompl_plan_request::simplify`: no simplification.
pub(crate) const SIMPLIFY_OFF: i32 = 0;
/// `ks_ompl_plan_request::simplify`: `PathSimplifier::simplify`.
pub(crate) const SIMPLIFY_FULL: i32 = 1;
/// `ks_ompl_plan_request::simplify`: one `reduceVertices` and one `shortcutPath` pass.
pub(crate) const SIMPLIFY_SHORTCUT: i32 = 2;

/// `ks_ompl_validity_fn`.
pub(crate) type ValidityFn = unsafe extern "C" fn(*mut c_void, *const f64, usize) -> c_int;
/// `ks_ompl_motion_fn`.
pub(crate) type MotionFn =
    unsafe extern "C" fn(*mut c_void, *const f64, *const f64, usize) -> c_int;
/// `ks_ompl_cancel_fn`.
pub(crate) type CancelFn = unsafe extern "C" fn(*mut c_void) -> c_int;
/// `ks_ompl_path_sink`.
pub(crate) type PathSink = unsafe extern "C" fn(*mut c_void, *const f64, usize);

/// `ks_ompl_plan_request`.
#[repr(C)]
pub(crate) struct PlanRequest {
    pub space: i32,
    pub planner: i32,
    pub dim: usize,
    pub bounds_len: usize,
    pub lower: *const f64,
    pub upper: *const f64,
    pub start: *const f64,
    pub goal: *const f64,
    pub goal_tolerance: f64,
    pub range: f64,
    pub resolution: f64,
    pub budget_s: f64,
    pub simplify: i32,
    pub interpolate_to: u32,
    pub has_cost_threshold: i32,
    pub cost_threshold: f64,
    pub max_iterations: u64,
}

/// `ks_ompl_plan_result`.
#[repr(C)]
#[derive(Default)]
pub(crate) struct PlanResult {
    pub status: i32,
    pub planning_time_s: f64,
    pub simplification_time_s: f64,
    pub goal_distance: f64,
    pub iterations: u64,
}

/// `ks_ompl_bench_result`.
#[cfg(feature = "bench")]
#[repr(C)]
#[derive(Default)]
pub(crate) struct BenchResult {
    pub callback_ns: u64,
    pub cpp_ns: u64,
    pub callback_valid: u64,
    pub cpp_valid: u64,
}

type PlanFnPtr = unsafe extern "C" fn(
    *const PlanRequest,
    ValidityFn,
    *mut c_void,
    Option<MotionFn>,
    *mut c_void,
    Option<CancelFn>,
    *mut c_void,
    PathSink,
    *mut c_void,
    *mut PlanResult,
    *mut c_char,
    usize,
) -> c_int;
type SetSeedFnPtr = unsafe extern "C" fn(u64, *mut c_char, usize) -> c_int;
type SetLogLevelFnPtr = unsafe extern "C" fn(i32, *mut c_char, usize) -> c_int;
#[cfg(feature = "bench")]
type BenchFnPtr = unsafe extern "C" fn(
    f64,
    f64,
    f64,
    usize,
    usize,
    ValidityFn,
    *mut c_void,
    *mut BenchResult,
    *mut c_char,
    usize,
) -> c_int;

/// The loaded shim and its entry points.
pub(crate) struct Api {
    _shim: Shim,
    pub plan: PlanFnPtr,
    pub set_seed: SetSeedFnPtr,
    pub set_log_level: SetLogLevelFnPtr,
    #[cfg(feature = "bench")]
    pub bench_validity: BenchFnPtr,
}

static API: OnceLock<Result<Api, LoadError>> = OnceLock::new();

/// The shim, loaded on first use (and OMPL's console set to [`DEFAULT_LOG_LEVEL`]).
pub(crate) fn api() -> Result<&'static Api, Error> {
    API.get_or_init(load)
        .as_ref()
        .map_err(|e| Error::Load(e.clone()))
}

fn load() -> Result<Api, LoadError> {
    let shim = Shim::open(
        "OMPL",
        "KINSCENE_OMPL_SHIM",
        option_env!("KINSCENE_OMPL_SHIM_BUILT"),
    )?;
    // SAFETY: each type is the exact signature declared in cpp/shim.h.
    let api = unsafe {
        Api {
            plan: shim.function::<PlanFnPtr>("ks_ompl_plan")?,
            set_seed: shim.function::<SetSeedFnPtr>("ks_ompl_set_seed")?,
            set_log_level: shim.function::<SetLogLevelFnPtr>("ks_ompl_set_log_level")?,
            #[cfg(feature = "bench")]
            bench_validity: shim.function::<BenchFnPtr>("ks_ompl_bench_validity")?,
            _shim: shim,
        }
    };
    // SAFETY: plain function with a valid error buffer from `call`. A failure cannot happen for
    // an in-range level, and would only leave OMPL's default console level.
    let _ = kinscene_shim::call("ks_ompl_set_log_level", |err, len| unsafe {
        (api.set_log_level)(DEFAULT_LOG_LEVEL.to_ompl(), err, len)
    });
    Ok(api)
}

impl LogLevel {
    /// The `ompl::msg::LogLevel` value.
    pub(crate) fn to_ompl(self) -> i32 {
        match self {
            LogLevel::Debug => 0,
            LogLevel::Info => 1,
            LogLevel::Warn => 2,
            LogLevel::Error => 3,
            LogLevel::None => 4,
        }
    }
}
