//! **Benchmark support only** (used by the `ompl_callback` bench; not part of the planning
//! API): measures what calling a Rust validity checker from inside OMPL costs, against a C++
//! checker doing the identical computation.

use std::time::Duration;

use crate::Error;
use crate::checker::CheckerContext;
use crate::ffi::{BenchResult, api};

/// A disc obstacle in the unit square; a state `[x, y]` is valid outside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscObstacle {
    /// Centre `[x, y]`.
    pub centre: [f64; 2],
    /// Radius.
    pub radius: f64,
}

impl DiscObstacle {
    /// `(x − cx)² + (y − cy)² > r²`: the same expression as the shim's C++ `DiscChecker`.
    pub fn is_outside(&self, q: &[f64]) -> bool {
        let dx = q[0] - self.centre[0];
        let dy = q[1] - self.centre[1];
        dx * dx + dy * dy > self.radius * self.radius
    }
}

/// Timings of [`time_validity_calls`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ValidityTiming {
    /// `SpaceInformation::isValid` calls made with each checker.
    pub calls: u64,
    /// Total time of those calls with the Rust closure as OMPL's checker.
    pub rust_callback: Duration,
    /// Total time with the C++ checker.
    pub cpp_checker: Duration,
    /// Valid states per pass found by the Rust closure.
    pub rust_valid: u64,
    /// Valid states per pass found by the C++ checker (equal to `rust_valid`).
    pub cpp_valid: u64,
}

/// Samples `states` uniform states of the unit square in OMPL, then times `passes` sweeps of
/// `SpaceInformation::isValid` over them, first with [`DiscObstacle::is_outside`] as a Rust
/// callback (through the same trampoline as [`plan`](crate::plan)), then with the C++ twin.
///
/// # Errors
/// [`Error::Load`] or [`Error::Backend`].
pub fn time_validity_calls(
    disc: DiscObstacle,
    states: usize,
    passes: usize,
) -> Result<ValidityTiming, Error> {
    let api = api()?;
    let checker = |q: &[f64]| disc.is_outside(q);
    let context = CheckerContext::new(&checker);
    let mut out = BenchResult::default();
    // SAFETY: the context and result outlive the call; signatures match cpp/shim.h.
    kinscene_shim::call("ks_ompl_bench_validity", |err, len| unsafe {
        (api.bench_validity)(
            disc.centre[0],
            disc.centre[1],
            disc.radius,
            states,
            passes,
            context.trampoline(),
            context.as_user(),
            &mut out,
            err,
            len,
        )
    })?;
    Ok(ValidityTiming {
        calls: (states as u64) * (passes as u64),
        rust_callback: Duration::from_nanos(out.callback_ns),
        cpp_checker: Duration::from_nanos(out.cpp_ns),
        rust_valid: out.callback_valid,
        cpp_valid: out.cpp_valid,
    })
}
