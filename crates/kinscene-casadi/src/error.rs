//! The crate's error type.

/// Why an NLP could not be built or solved.
///
/// Bad input and broken backends only: an NLP that is infeasible, hits an iteration or time
/// limit, or otherwise does not converge is an `Ok` outcome with an
/// [`NlpStatus`](crate::NlpStatus).
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The CasADi shim could not be loaded.
    #[error(transparent)]
    Load(#[from] kinscene_shim::LoadError),
    /// CasADi or IPOPT threw a C++ exception (unknown option, evaluation failure, ...); the
    /// message is CasADi's.
    #[error(transparent)]
    Backend(#[from] kinscene_shim::CallError),
    /// A slice had the wrong length.
    #[error("{what}: expected {expected} values, got {got}")]
    DimensionMismatch {
        /// Which input (`"x0"`, `"params"`, ...).
        what: &'static str,
        /// The required length.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A NaN (or, where only finite values make sense, an infinity) was given.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which value, e.g. "lower bound of variable `q3`".
        what: String,
    },
    /// `lower > upper`, or a bound that excludes every real number (`lower = +inf`,
    /// `upper = -inf`).
    #[error("invalid bounds for {what}: [{lower}, {upper}]")]
    InvalidBounds {
        /// The variable or constraint, e.g. "variable `q3`" or "constraint 2".
        what: String,
        /// The lower bound given.
        lower: f64,
        /// The upper bound given.
        upper: f64,
    },
    /// An expression mixes symbols of another [`Nlp`](crate::Nlp) instance.
    #[error("{what} uses symbols of another Nlp")]
    ForeignExpr {
        /// Where the expression was passed ("objective", "constraint", "eval").
        what: &'static str,
    },
    /// The problem has no decision variable.
    #[error("the NLP has no decision variables")]
    NoVariables,
    /// A field of [`NlpSettings`](crate::NlpSettings) is out of range.
    #[error("invalid setting {name}: {reason}")]
    InvalidSetting {
        /// The field name.
        name: &'static str,
        /// Its allowed range.
        reason: &'static str,
    },
    /// An extra [`IpoptOption`](crate::IpoptOption) is malformed (IPOPT itself rejects unknown
    /// names with [`Error::Backend`]).
    #[error("invalid IPOPT option {name:?}: {reason}")]
    InvalidOption {
        /// The option name.
        name: String,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The expression graph is too large for the shim's 32-bit indices.
    #[error("{what} too large: {len}")]
    TooLarge {
        /// What overflowed ("tape", "variables").
        what: &'static str,
        /// Its size.
        len: usize,
    },
}
