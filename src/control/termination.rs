//! When to stop: one [`Termination`] passed down every layer.
//!
//! A planner call gets a termination condition — a deadline, a cancel flag, both or neither —
//! as OMPL's `solve` gets a `PlannerTerminationCondition`. A layer that calls a lower one passes
//! it on, narrowed where it has a budget of its own ([`Termination::capped`]: the earlier of the
//! two deadlines, the same flag); the conversion to OMPL's form happens in one place
//! (`motion::paths`). No layer overwrites another's settings to pass a budget down.
//!
//! Wall-clock deadlines are a safety net: a seeded call that finishes within its budget gives
//! the same result on every run.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// When to stop: a deadline, a cancel flag (typically raised by another thread), both or
/// neither. Cheap to copy; narrowed with [`Termination::capped`].
///
/// # Example
/// ```
/// use std::sync::atomic::{AtomicBool, Ordering};
/// use std::time::Duration;
/// use kinscene::Termination;
///
/// let cancel = AtomicBool::new(false);
/// let call = Termination::after(Duration::from_secs(60)).with_cancel(&cancel);
/// // A sub-step with a budget of its own: the earlier deadline, the same flag.
/// let step = call.capped(Duration::from_millis(10));
/// assert!(step.remaining().unwrap() <= Duration::from_millis(10));
/// assert!(!step.should_stop());
/// cancel.store(true, Ordering::Relaxed);
/// assert!(step.should_stop() && call.should_stop());
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct Termination<'a> {
    deadline: Option<Instant>,
    cancel: Option<&'a AtomicBool>,
}

impl<'a> Termination<'a> {
    /// Never stops early.
    pub fn none() -> Self {
        Termination::default()
    }

    /// Stops `budget` from now.
    pub fn after(budget: Duration) -> Self {
        Termination {
            deadline: Instant::now().checked_add(budget),
            cancel: None,
        }
    }

    /// Also stops when `flag` becomes true.
    pub fn with_cancel(self, flag: &'a AtomicBool) -> Self {
        Termination {
            cancel: Some(flag),
            ..self
        }
    }

    /// The same condition with the deadline brought forward to `budget` from now, if that is
    /// earlier: a sub-budget. The cancel flag is kept.
    pub fn capped(self, budget: Duration) -> Self {
        let cap = Instant::now().checked_add(budget);
        let deadline = match (self.deadline, cap) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        Termination { deadline, ..self }
    }

    /// The deadline, if any.
    pub fn deadline(&self) -> Option<Instant> {
        self.deadline
    }

    /// Time left before the deadline (zero once it has passed); `None` without a deadline.
    pub fn remaining(&self) -> Option<Duration> {
        self.deadline
            .map(|d| d.saturating_duration_since(Instant::now()))
    }

    /// The cancel flag, if any.
    pub fn cancel_flag(&self) -> Option<&'a AtomicBool> {
        self.cancel
    }

    /// Whether the cancel flag is set (the deadline aside).
    pub fn is_cancelled(&self) -> bool {
        self.cancel.is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// Whether the deadline has passed or the flag is set.
    pub fn should_stop(&self) -> bool {
        self.is_cancelled() || self.deadline.is_some_and(|d| Instant::now() >= d)
    }
}
