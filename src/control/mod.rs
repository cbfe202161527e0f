//! The control vocabulary every planning layer shares: when to stop ([`Termination`]) and how a
//! call ended ([`Outcome`]).

mod outcome;
mod termination;

pub use outcome::Outcome;
pub use termination::Termination;
