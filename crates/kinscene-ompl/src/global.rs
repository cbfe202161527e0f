//! Process-wide OMPL state: the random seed and the console log level.

use crate::Error;
use crate::ffi::api;

/// OMPL's console verbosity (`ompl::msg::LogLevel`). OMPL's messages go to stderr.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum LogLevel {
    /// Debug messages and everything above.
    Debug,
    /// Informational messages (planner set-up, solution found) and above.
    Info,
    /// Warnings and errors.
    Warn,
    /// Errors only.
    Error,
    /// Nothing (the default set when the shim is loaded: results come back as statuses).
    #[default]
    None,
}

/// The level set when the shim is first loaded, before any call of [`set_log_level`].
pub const DEFAULT_LOG_LEVEL: LogLevel = LogLevel::None;

/// Loads the OMPL shim now; otherwise the first call loads it (7–21 ms measured). A planner
/// with a time budget calls this before starting its clock, so the load is not charged to
/// the first plan. Later calls return at once.
///
/// # Errors
/// [`Error::Load`] when the shim cannot be loaded.
pub fn load() -> Result<(), Error> {
    api().map(|_| ())
}

/// Sets OMPL's console verbosity for the whole process.
///
/// # Errors
/// [`Error::Load`] when the shim cannot be loaded.
pub fn set_log_level(level: LogLevel) -> Result<(), Error> {
    let api = api()?;
    // SAFETY: plain value arguments and the error buffer provided by `call`.
    kinscene_shim::call("ks_ompl_set_log_level", |err, len| unsafe {
        (api.set_log_level)(level.to_ompl(), err, len)
    })?;
    Ok(())
}

/// Seeds OMPL's global random number generator (`ompl::RNG::setSeed`).
///
/// Every sampler OMPL creates afterwards draws its own seed from this generator, so calling
/// `set_seed` once, before the first [`plan`](crate::plan), makes a sequence of single-threaded
/// plans reproducible. Calling it again re-seeds the generator for later planners (OMPL would
/// log an error about it; the console is silent by default). Planners running concurrently in
/// other threads draw from the same generator, which breaks reproducibility. OMPL rejects 0;
/// it is replaced by 1.
///
/// # Errors
/// [`Error::Load`] when the shim cannot be loaded.
pub fn set_seed(seed: u64) -> Result<(), Error> {
    let api = api()?;
    // SAFETY: plain value arguments and the error buffer provided by `call`.
    kinscene_shim::call("ks_ompl_set_seed", |err, len| unsafe {
        (api.set_seed)(seed, err, len)
    })?;
    Ok(())
}
