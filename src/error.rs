//! Errors of the core, each mapped to one C status code in `capi::status`.

use std::fmt;

/// Why a computation was refused. No output or state is written when one of these is returned.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// An input was NaN or infinite; names the field.
    NonFinite(&'static str),
    /// A sphere radius was `<= 0`; names the body.
    InvalidRadius(&'static str),
    /// The two centres are closer than `eps (R1 + R2)`: the normal is undefined.
    CoincidentCentres,
    /// A branch length `l_k` came out `<= 0` (overlap too deep for the branch rule, or a sphere
    /// centre more than one radius behind a wall); names the branch.
    NonPositiveBranch(&'static str),
    /// The time step was not finite and > 0.
    InvalidTimeStep,
    /// A model parameter out of its domain; the message names the parameter.
    InvalidParameter(String),
    /// A value out of its domain (option code, zero wall normal, bad parameter...), with the reason.
    InvalidArgument(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NonFinite(what) => write!(f, "non-finite input: {what}"),
            Error::InvalidRadius(what) => write!(f, "radius must be > 0: {what}"),
            Error::CoincidentCentres => {
                write!(
                    f,
                    "coincident centres: |r2 - r1| < eps (R1 + R2), the normal is undefined"
                )
            }
            Error::NonPositiveBranch(what) => write!(
                f,
                "branch length {what} <= 0: overlap too deep for the branch rule"
            ),
            Error::InvalidTimeStep => write!(f, "time step dt must be finite and > 0"),
            Error::InvalidParameter(why) => write!(f, "invalid parameter: {why}"),
            Error::InvalidArgument(why) => write!(f, "invalid argument: {why}"),
        }
    }
}

impl std::error::Error for Error {}
