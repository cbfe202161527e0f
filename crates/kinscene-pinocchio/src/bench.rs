//! Benchmark support only: the cost of forward kinematics without the FFI boundary.

use std::time::Duration;

use nalgebra::DVector;

use crate::configuration::check_q;
use crate::{Data, Error, FrameIndex, Model, ffi};

/// **For benchmarks only.** Runs Pinocchio's `forwardKinematics` followed by
/// `updateFramePlacement(frame)` `iterations` times in a C++ loop, and returns the total wall
/// time measured inside C++ (steady clock).
///
/// Dividing by `iterations` gives the per-call cost with no FFI crossing, to compare with
/// [`crate::forward_kinematics`] + [`crate::frame_placement`] timed from Rust in the same run.
/// Leaves `data` in an unspecified kinematic state (run [`crate::forward_kinematics`] before
/// reading placements).
///
/// # Errors
/// As [`crate::forward_kinematics`], plus [`Error::FrameOutOfRange`].
pub fn cpp_forward_kinematics_loop(
    model: &Model,
    data: &mut Data,
    q: &DVector<f64>,
    frame: FrameIndex,
    iterations: u64,
) -> Result<Duration, Error> {
    data.check(model)?;
    check_q(model, q, "q")?;
    model.frame(frame)?;
    let api = ffi::api()?;
    let (mut elapsed_ns, mut checksum) = (0u64, 0.0f64);
    data.set_placements_valid(false);
    // SAFETY: matching model/data, q of length nq, valid frame, live out-pointers.
    ffi::call("ks_pin_bench_forward_kinematics", |e, n| unsafe {
        (api.bench_forward_kinematics)(
            model.raw(),
            data.raw_mut(),
            q.as_ptr(),
            frame.0,
            iterations,
            &mut elapsed_ns,
            &mut checksum,
            e,
            n,
        )
    })?;
    std::hint::black_box(checksum);
    Ok(Duration::from_nanos(elapsed_ns))
}
