//! State and motion validity checking in Rust, called from OMPL through `extern "C"`
//! trampolines.

use std::ffi::{c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::ffi::{MotionFn, ValidityFn};

/// Decides whether a state is valid (collision-free, within limits...): OMPL's
/// `StateValidityChecker`.
///
/// `state` has the layout of the [`StateSpace`](crate::StateSpace): `[x, y, yaw]` for SE(2)
/// (yaw in `[-π, π]`), the coordinates for a real vector space. Implemented for every
/// `Fn(&[f64]) -> bool + Sync` closure.
///
/// It must be `Sync`: some planners (PRM) call it from a second thread. A panic inside it is
/// caught, counts as "invalid", and is reported in
/// [`PlanOutcome::checker_panics`](crate::PlanOutcome::checker_panics).
pub trait StateValidityChecker: Sync {
    /// True when `state` is valid.
    fn is_valid(&self, state: &[f64]) -> bool;
}

impl<F: Fn(&[f64]) -> bool + Sync> StateValidityChecker for F {
    fn is_valid(&self, state: &[f64]) -> bool {
        self(state)
    }
}

/// Decides whether the motion between two states is valid: OMPL's `MotionValidator`, used
/// by the planner and the path simplifier for every motion in place of OMPL's discrete check
/// (states sampled every [`PlanSettings::resolution_fraction`](crate::PlanSettings)).
///
/// `a` and `b` have the layout of [`StateValidityChecker`]'s states; the motion is the
/// space's interpolation from `a` to `b` (straight lines; the shortest angle for the SE(2)
/// yaw). OMPL calls it with an `a` it already holds as valid; `b` is part of the motion and
/// must be checked. Implemented for every `Fn(&[f64], &[f64]) -> bool + Sync` closure.
///
/// Like the state checker it must be `Sync`, and a panic inside it is caught, counts as
/// "invalid motion", and is reported in
/// [`PlanOutcome::checker_panics`](crate::PlanOutcome::checker_panics).
///
/// OMPL's variant that also asks for the last valid state of a rejected motion (used by the
/// lazy planners) reports `a` at fraction 0: the trait gives no position along the motion.
pub trait MotionValidator: Sync {
    /// True when the whole motion from `a` to `b` is valid.
    fn check_motion(&self, a: &[f64], b: &[f64]) -> bool;
}

impl<F: Fn(&[f64], &[f64]) -> bool + Sync> MotionValidator for F {
    fn check_motion(&self, a: &[f64], b: &[f64]) -> bool {
        self(a, b)
    }
}

/// What the validity trampoline's `void* user` points to.
pub(crate) struct CheckerContext<'a, C: ?Sized> {
    checker: &'a C,
    panics: AtomicUsize,
}

impl<'a, C: StateValidityChecker + ?Sized> CheckerContext<'a, C> {
    pub(crate) fn new(checker: &'a C) -> Self {
        CheckerContext {
            checker,
            panics: AtomicUsize::new(0),
        }
    }

    /// The `void*` to pass along with [`Self::trampoline`].
    pub(crate) fn as_user(&self) -> *mut c_void {
        self as *const Self as *mut c_void
    }

    /// The `ks_ompl_validity_fn` matching [`Self::as_user`].
    pub(crate) fn trampoline(&self) -> ValidityFn {
        validity_trampoline::<C>
    }

    /// Number of panics caught so far.
    pub(crate) fn panics(&self) -> usize {
        self.panics.load(Ordering::Relaxed)
    }
}

/// `ks_ompl_validity_fn` for a checker of type `C`: a panic becomes "invalid" and is counted.
///
/// # Safety
/// `user` must come from [`CheckerContext::<C>::as_user`] on a context that outlives the call,
/// and `state` must point to `dim` readable values.
unsafe extern "C" fn validity_trampoline<C: StateValidityChecker + ?Sized>(
    user: *mut c_void,
    state: *const f64,
    dim: usize,
) -> c_int {
    // SAFETY: guaranteed by the caller (the shim passes back our pointer and a live state).
    let (ctx, q) = unsafe {
        (
            &*(user as *const CheckerContext<'_, C>),
            std::slice::from_raw_parts(state, dim),
        )
    };
    guarded(&ctx.panics, || ctx.checker.is_valid(q))
}

/// `f()` as a C boolean; a panic is caught, counted in `panics` and returned as 0 (invalid).
fn guarded(panics: &AtomicUsize, f: impl FnOnce() -> bool) -> c_int {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(valid) => c_int::from(valid),
        Err(payload) => {
            panics.fetch_add(1, Ordering::Relaxed);
            // Dropping a panic payload can itself panic; keep that on this side too.
            let _ = catch_unwind(AssertUnwindSafe(move || drop(payload)));
            0
        }
    }
}

/// What the motion trampoline's `void* user` points to.
pub(crate) struct MotionContext<'a, M: ?Sized> {
    validator: &'a M,
    panics: AtomicUsize,
}

impl<'a, M: MotionValidator + ?Sized> MotionContext<'a, M> {
    pub(crate) fn new(validator: &'a M) -> Self {
        MotionContext {
            validator,
            panics: AtomicUsize::new(0),
        }
    }

    /// The `void*` to pass along with [`Self::trampoline`].
    pub(crate) fn as_user(&self) -> *mut c_void {
        self as *const Self as *mut c_void
    }

    /// The `ks_ompl_motion_fn` matching [`Self::as_user`].
    pub(crate) fn trampoline(&self) -> MotionFn {
        motion_trampoline::<M>
    }

    /// Number of panics caught so far.
    pub(crate) fn panics(&self) -> usize {
        self.panics.load(Ordering::Relaxed)
    }
}

/// `ks_ompl_motion_fn` for a validator of type `M`: a panic becomes "invalid" and is counted.
///
/// # Safety
/// `user` must come from [`MotionContext::<M>::as_user`] on a context that outlives the call,
/// and `a` and `b` must each point to `dim` readable values.
unsafe extern "C" fn motion_trampoline<M: MotionValidator + ?Sized>(
    user: *mut c_void,
    a: *const f64,
    b: *const f64,
    dim: usize,
) -> c_int {
    // SAFETY: guaranteed by the caller (the shim passes back our pointer and live states).
    let (ctx, a, b) = unsafe {
        (
            &*(user as *const MotionContext<'_, M>),
            std::slice::from_raw_parts(a, dim),
            std::slice::from_raw_parts(b, dim),
        )
    };
    guarded(&ctx.panics, || ctx.validator.check_motion(a, b))
}

/// `ks_ompl_cancel_fn`: reads the `AtomicBool` that `user` points to. Cannot panic.
///
/// # Safety
/// `user` must point to an `AtomicBool` that outlives the call.
pub(crate) unsafe extern "C" fn cancel_trampoline(user: *mut c_void) -> c_int {
    // SAFETY: guaranteed by the caller.
    let flag = unsafe { &*(user as *const AtomicBool) };
    c_int::from(flag.load(Ordering::Relaxed))
}

/// `ks_ompl_path_sink`: appends a state to the `Vec<Vec<f64>>` that `user` points to.
///
/// # Safety
/// `user` must point to a `Vec<Vec<f64>>` not otherwise borrowed during the call, and `state`
/// to `dim` readable values.
pub(crate) unsafe extern "C" fn path_sink(user: *mut c_void, state: *const f64, dim: usize) {
    // SAFETY: guaranteed by the caller.
    let (path, q) = unsafe {
        (
            &mut *(user as *mut Vec<Vec<f64>>),
            std::slice::from_raw_parts(state, dim),
        )
    };
    // Only an allocation failure could panic here (and that aborts); never unwind into C++.
    let _ = catch_unwind(AssertUnwindSafe(|| path.push(q.to_vec())));
}
