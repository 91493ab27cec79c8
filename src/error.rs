//! Typed errors shared by the Rust API and the C ABI.
//!
//! Every fallible operation returns [`Error`]; the C boundary turns it into a
//! [`crate::ffi::WetHairResult`] code plus a message kept per thread.

use std::fmt;

/// What went wrong, with enough detail for a message a host can log.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A parameter is out of its documented range (NaN, inf, negative, zero where not allowed).
    InvalidArgument(String),
    /// A count or size exceeds a documented capacity.
    Capacity(String),
    /// A file could not be opened or read.
    Io(String),
    /// A groom file is truncated or malformed.
    Parse(String),
    /// A step produced a non-finite value; the simulation must be reset.
    Unstable {
        /// Index (in the host's order) of the first strand found non-finite; `None` when a
        /// water particle failed rather than hair.
        strand: Option<u32>,
        /// Human-readable detail.
        detail: String,
    },
    /// The GPU device failed: lost, out of memory, or a validation error. The simulation is
    /// marked failed; destroy it (a reset does not revive a lost device).
    Device(String),
    /// The requested combination is not available (e.g. no GPU adapter, or an integrator the
    /// chosen backend does not run).
    Unsupported(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidArgument(m) => write!(f, "invalid argument: {m}"),
            Error::Capacity(m) => write!(f, "capacity exceeded: {m}"),
            Error::Io(m) => write!(f, "i/o error: {m}"),
            Error::Parse(m) => write!(f, "malformed groom: {m}"),
            Error::Device(m) => write!(f, "GPU device error: {m}"),
            Error::Unsupported(m) => write!(f, "unsupported: {m}"),
            Error::Unstable {
                strand: Some(s),
                detail,
            } => {
                write!(f, "unstable: strand {s} became non-finite ({detail})")
            }
            Error::Unstable { strand: None, detail } => write!(f, "unstable: {detail}"),
        }
    }
}

impl std::error::Error for Error {}

/// Result alias used across the crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Shorthand for an [`Error::InvalidArgument`] with a formatted message.
macro_rules! invalid {
    ($($arg:tt)*) => { $crate::error::Error::InvalidArgument(format!($($arg)*)) };
}
pub(crate) use invalid;

/// Checks that a float parameter is finite and `>= 0`, naming it in the error.
pub(crate) fn check_non_negative(name: &str, v: f32) -> Result<()> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid!("{name} must be finite and >= 0, got {v}"))
    }
}

/// Checks that a float parameter is finite and `> 0`, naming it in the error.
pub(crate) fn check_positive(name: &str, v: f32) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid!("{name} must be finite and > 0, got {v}"))
    }
}

/// Checks that every component of a vector is finite.
pub(crate) fn check_finite3(name: &str, v: [f32; 3]) -> Result<()> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(invalid!("{name} must be finite, got {v:?}"))
    }
}
