//! Errors for invalid filter parameters and system descriptions.

use thiserror::Error;

/// Why a block or system description was rejected. Every constructor in
/// [`crate::signals`] validates its parameters and returns one of these instead of
/// panicking.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum SignalError {
    /// A parameter is NaN or infinite.
    #[error("{what} must be a finite number, got {value}")]
    NotFinite {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A parameter that must be strictly positive is zero or negative.
    #[error("{what} must be greater than 0, got {value}")]
    NotPositive {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A parameter lies outside its allowed range.
    #[error("{what} must lie in {range}, got {value}")]
    OutOfRange {
        /// Which parameter.
        what: &'static str,
        /// The allowed range, as written in the docs (e.g. `(-1, 1)`).
        range: &'static str,
        /// The value given.
        value: f64,
    },
    /// A pole lies on or outside the stability boundary (continuous: `Re p >= 0`;
    /// discrete: `|z| >= 1`), so the output would not settle.
    #[error("unstable {domain} pole {re:+.6}{im:+.6}i: {hint}")]
    Unstable {
        /// `"continuous-time"` or `"discrete-time"`.
        domain: &'static str,
        /// Real part of the offending pole.
        re: f64,
        /// Imaginary part of the offending pole.
        im: f64,
        /// What to change.
        hint: &'static str,
    },
    /// A structural problem: wrong matrix sizes, a non-real transfer function, too many
    /// zeros, a call with the wrong arguments.
    #[error("{0}")]
    Invalid(String),
    /// A name that no block or easing has.
    #[error("unknown {kind} `{name}`; expected one of: {expected}")]
    Unknown {
        /// `"easing"` or `"system"`.
        kind: &'static str,
        /// The name given.
        name: String,
        /// The accepted names.
        expected: &'static str,
    },
    /// A text spelling (`fir(bspline(3), 0.3)`) that does not parse.
    #[error("column {column}: {message}")]
    Syntax {
        /// 1-based column of the problem in the spelling.
        column: usize,
        /// What was expected.
        message: String,
    },
}

/// Checks that `value` is finite.
pub(crate) fn finite(what: &'static str, value: f64) -> Result<f64, SignalError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SignalError::NotFinite { what, value })
    }
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(what: &'static str, value: f64) -> Result<f64, SignalError> {
    finite(what, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(SignalError::NotPositive { what, value })
    }
}

/// Checks that `value` is finite and a whole number in `lo..=hi`.
pub(crate) fn whole(
    what: &'static str,
    value: f64,
    lo: u32,
    hi: u32,
    range: &'static str,
) -> Result<u32, SignalError> {
    finite(what, value)?;
    if value.fract() != 0.0 || value < f64::from(lo) || value > f64::from(hi) {
        return Err(SignalError::OutOfRange { what, range, value });
    }
    Ok(value as u32)
}
