//! How a planning call ended: one [`Outcome`] for every layer.
//!
//! Every planner in the crate — the task search, the hierarchical planner, one order's
//! refinement, a base or arm path, an IK solve — answers with the same four words:
//!
//! | variant | meaning | carries |
//! |---|---|---|
//! | [`Solved`](Outcome::Solved) | the call's answer | the plan, path or configuration |
//! | [`Infeasible`](Outcome::Infeasible) | no answer, for a stated reason | a structured reason that renders to text |
//! | [`Timeout`](Outcome::Timeout) | the deadline passed first | the best found so far |
//! | [`Cancelled`](Outcome::Cancelled) | the cancel flag stopped the call | the best found so far |
//!
//! Each layer names its instance with a type alias, as `std::io::Result` names
//! `Result<T, io::Error>`: [`task::Outcome`](crate::task::Outcome) is
//! `Outcome<Plan, Infeasibility, Partial>`. Whether a reason is a proof (a complete search ran
//! out of moves) or a report (an IK solve used its iterations) is said by the layer's reason
//! type. `Err` stays for bad input and broken backends ([`Error`](crate::Error)).

use std::fmt;

use super::Termination;

/// How a planning call ended: solved, infeasible with a reason, or stopped by its
/// [`Termination`] with the best found so far.
///
/// `T` is the answer, `R` the reason there is none, `B` what a stopped call hands back (`()`
/// where there is nothing partial to return).
///
/// # Example
/// ```
/// use kinscene::{Outcome, Termination};
///
/// // A search that stops at its termination condition and keeps its best value so far.
/// fn first_square_above(limit: u64, termination: Termination) -> Outcome<u64, String, u64> {
///     let mut best = 0;
///     for n in 0..1_000u64 {
///         if termination.should_stop() {
///             return Outcome::stopped(&termination, best);
///         }
///         if n * n > limit {
///             return Outcome::Solved(n * n);
///         }
///         best = n * n;
///     }
///     Outcome::Infeasible(format!("no square of n < 1000 exceeds {limit}"))
/// }
///
/// assert_eq!(first_square_above(50, Termination::none()).solved(), Some(&64));
/// assert!(first_square_above(u64::MAX, Termination::none()).is_infeasible());
/// ```
#[derive(Debug, Clone, PartialEq)]
#[must_use]
pub enum Outcome<T, R, B = ()> {
    /// The call's answer; it passed every check the layer makes.
    Solved(T),
    /// There is no answer, for the stated reason.
    Infeasible(R),
    /// The deadline passed first; the best found so far.
    Timeout(B),
    /// The cancel flag stopped the call; the best found so far.
    Cancelled(B),
}

impl<T, R, B> Outcome<T, R, B> {
    /// [`Timeout`](Outcome::Timeout) or [`Cancelled`](Outcome::Cancelled), whichever stopped
    /// `termination` (the cancel flag wins when both hold).
    pub fn stopped(termination: &Termination, best: B) -> Self {
        if termination.is_cancelled() {
            Outcome::Cancelled(best)
        } else {
            Outcome::Timeout(best)
        }
    }

    /// The answer, if solved.
    pub fn solved(&self) -> Option<&T> {
        match self {
            Outcome::Solved(t) => Some(t),
            _ => None,
        }
    }

    /// The answer by value, if solved.
    pub fn into_solved(self) -> Option<T> {
        match self {
            Outcome::Solved(t) => Some(t),
            _ => None,
        }
    }

    /// The reason, if infeasible.
    pub fn infeasible(&self) -> Option<&R> {
        match self {
            Outcome::Infeasible(r) => Some(r),
            _ => None,
        }
    }

    /// What a stopped call handed back, if it was stopped (timeout or cancel).
    pub fn best(&self) -> Option<&B> {
        match self {
            Outcome::Timeout(b) | Outcome::Cancelled(b) => Some(b),
            _ => None,
        }
    }

    /// True for [`Solved`](Outcome::Solved).
    pub fn is_solved(&self) -> bool {
        matches!(self, Outcome::Solved(_))
    }

    /// True for [`Infeasible`](Outcome::Infeasible).
    pub fn is_infeasible(&self) -> bool {
        matches!(self, Outcome::Infeasible(_))
    }

    /// True for [`Timeout`](Outcome::Timeout) or [`Cancelled`](Outcome::Cancelled).
    pub fn is_stopped(&self) -> bool {
        matches!(self, Outcome::Timeout(_) | Outcome::Cancelled(_))
    }

    /// The variant's word: `"solved"`, `"infeasible"`, `"timeout"` or `"cancelled"` (the
    /// plan documents' `status`).
    pub fn status(&self) -> &'static str {
        match self {
            Outcome::Solved(_) => "solved",
            Outcome::Infeasible(_) => "infeasible",
            Outcome::Timeout(_) => "timeout",
            Outcome::Cancelled(_) => "cancelled",
        }
    }

    /// The same outcome with the answer mapped.
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Outcome<U, R, B> {
        match self {
            Outcome::Solved(t) => Outcome::Solved(f(t)),
            Outcome::Infeasible(r) => Outcome::Infeasible(r),
            Outcome::Timeout(b) => Outcome::Timeout(b),
            Outcome::Cancelled(b) => Outcome::Cancelled(b),
        }
    }

    /// The same outcome with the reason mapped.
    pub fn map_infeasible<S>(self, f: impl FnOnce(R) -> S) -> Outcome<T, S, B> {
        match self {
            Outcome::Solved(t) => Outcome::Solved(t),
            Outcome::Infeasible(r) => Outcome::Infeasible(f(r)),
            Outcome::Timeout(b) => Outcome::Timeout(b),
            Outcome::Cancelled(b) => Outcome::Cancelled(b),
        }
    }

    /// The same outcome with what a stopped call hands back mapped.
    pub fn map_best<C>(self, f: impl FnOnce(B) -> C) -> Outcome<T, R, C> {
        match self {
            Outcome::Solved(t) => Outcome::Solved(t),
            Outcome::Infeasible(r) => Outcome::Infeasible(r),
            Outcome::Timeout(b) => Outcome::Timeout(f(b)),
            Outcome::Cancelled(b) => Outcome::Cancelled(f(b)),
        }
    }
}

/// One line: the status, then the reason (infeasible) or what was handed back (stopped), each
/// as its own `Display` renders it.
impl<T, R: fmt::Display, B: fmt::Display> fmt::Display for Outcome<T, R, B> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Outcome::Solved(_) => f.write_str("solved"),
            Outcome::Infeasible(r) => write!(f, "infeasible: {r}"),
            Outcome::Timeout(b) => write!(f, "timeout: {b}"),
            Outcome::Cancelled(b) => write!(f, "cancelled: {b}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicBool;
    use std::time::Duration;

    #[test]
    fn stopped_names_what_stopped_the_call() {
        let flag = AtomicBool::new(true);
        let cancelled: Outcome<(), (), u8> =
            Outcome::stopped(&Termination::none().with_cancel(&flag), 3);
        assert_eq!(cancelled, Outcome::Cancelled(3));
        let spent = Termination::after(Duration::ZERO);
        let timed_out: Outcome<(), (), u8> = Outcome::stopped(&spent, 4);
        assert_eq!(timed_out, Outcome::Timeout(4));
        assert_eq!(timed_out.best(), Some(&4));
        assert!(timed_out.is_stopped() && !timed_out.is_solved());
    }

    #[test]
    fn maps_keep_the_variant() {
        let solved: Outcome<u8, &str, ()> = Outcome::Solved(2);
        assert_eq!(solved.map(|x| x * 2), Outcome::Solved(4));
        let infeasible: Outcome<u8, &str, &str> = Outcome::Infeasible("no");
        assert_eq!(infeasible.to_string(), "infeasible: no");
        assert_eq!(infeasible.map_infeasible(str::len), Outcome::Infeasible(2));
        assert_eq!(
            Outcome::<u8, &str, &str>::Timeout("half").status(),
            "timeout"
        );
    }
}
