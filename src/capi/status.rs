//! Status codes, their static descriptions, and the thread-local detail message.

use crate::error::Error;
use std::cell::RefCell;
use std::ffi::CString;

/// Success.
pub const RSL_OK: i32 = 0;
/// A required pointer argument was NULL.
pub const RSL_ERR_NULL_POINTER: i32 = 1;
/// An input was NaN or infinite (or a result overflowed).
pub const RSL_ERR_NON_FINITE: i32 = 2;
/// A sphere radius was `<= 0`.
pub const RSL_ERR_INVALID_RADIUS: i32 = 3;
/// The two centres coincide (`|r2 - r1| < eps (R1 + R2)`): the normal is undefined.
pub const RSL_ERR_COINCIDENT_CENTRES: i32 = 4;
/// A branch length came out `<= 0` (overlap too deep for the branch rule).
pub const RSL_ERR_NONPOSITIVE_BRANCH: i32 = 5;
/// An argument was out of its domain (unknown option code, zero wall normal...); the detail
/// message says which.
pub const RSL_ERR_INVALID_ARGUMENT: i32 = 6;
/// A pointer was not aligned for its type.
pub const RSL_ERR_MISALIGNED: i32 = 7;
/// An internal error (a bug in the library, stopped at its boundary) was caught; outputs were
/// not written.
pub const RSL_ERR_INTERNAL: i32 = 8;
/// The time step was not finite and > 0.
pub const RSL_ERR_INVALID_TIME_STEP: i32 = 9;
/// No longer returned: a negative (tensile) normal force is accepted and applied as given. The
/// code stays reserved so that no other error takes its number.
pub const RSL_ERR_NEGATIVE_NORMAL_FORCE: i32 = 10;
/// A model parameter or law code was invalid; the detail message names it. The model is unchanged.
pub const RSL_ERR_INVALID_PARAMETER: i32 = 11;
/// A model handle was not a live model (already freed, or not from `rsl_model_new`).
pub const RSL_ERR_INVALID_HANDLE: i32 = 12;

/// An error as seen by the C layer: a core error or a boundary problem.
#[derive(Debug)]
pub(crate) enum FfiError {
    Core(Error),
    NullPointer(&'static str),
    Misaligned(&'static str),
    /// A misaligned pointer inside an array argument: the array's name and the index.
    MisalignedElement(&'static str, usize),
    Panic(String),
    InvalidHandle,
}

impl From<Error> for FfiError {
    fn from(e: Error) -> Self {
        FfiError::Core(e)
    }
}

impl FfiError {
    pub(crate) fn code(&self) -> i32 {
        match self {
            FfiError::Core(Error::NonFinite(_)) => RSL_ERR_NON_FINITE,
            FfiError::Core(Error::InvalidRadius(_)) => RSL_ERR_INVALID_RADIUS,
            FfiError::Core(Error::CoincidentCentres) => RSL_ERR_COINCIDENT_CENTRES,
            FfiError::Core(Error::NonPositiveBranch(_)) => RSL_ERR_NONPOSITIVE_BRANCH,
            FfiError::Core(Error::InvalidArgument(_)) => RSL_ERR_INVALID_ARGUMENT,
            FfiError::Core(Error::InvalidTimeStep) => RSL_ERR_INVALID_TIME_STEP,
            FfiError::Core(Error::InvalidParameter(_)) => RSL_ERR_INVALID_PARAMETER,
            FfiError::InvalidHandle => RSL_ERR_INVALID_HANDLE,
            FfiError::NullPointer(_) => RSL_ERR_NULL_POINTER,
            FfiError::Misaligned(_) | FfiError::MisalignedElement(..) => RSL_ERR_MISALIGNED,
            FfiError::Panic(_) => RSL_ERR_INTERNAL,
        }
    }

    pub(crate) fn message(&self) -> String {
        match self {
            FfiError::Core(e) => e.to_string(),
            FfiError::NullPointer(what) => format!("null pointer: {what}"),
            FfiError::Misaligned(what) => format!("misaligned pointer: {what}"),
            FfiError::MisalignedElement(what, i) => format!("misaligned pointer: {what}[{i}]"),
            FfiError::Panic(what) => format!("internal error (caught panic): {what}"),
            FfiError::InvalidHandle => {
                "model handle is not a live rsl_model (freed or never created)".to_string()
            }
        }
    }
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

pub(crate) fn set_last_error(message: &str) {
    let c = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|slot| *slot.borrow_mut() = c);
}

/// A static, NUL-terminated English description of a status code ("unknown status" for codes
/// this library does not define). Never NULL; do not free.
#[no_mangle]
pub extern "C" fn rsl_status_str(status: i32) -> *const libc::c_char {
    let s: &'static [u8] = match status {
        RSL_OK => b"ok\0",
        RSL_ERR_NULL_POINTER => b"null pointer argument\0",
        RSL_ERR_NON_FINITE => b"non-finite input or result\0",
        RSL_ERR_INVALID_RADIUS => b"radius must be > 0\0",
        RSL_ERR_COINCIDENT_CENTRES => b"coincident centres\0",
        RSL_ERR_NONPOSITIVE_BRANCH => b"branch length <= 0\0",
        RSL_ERR_INVALID_ARGUMENT => b"invalid argument\0",
        RSL_ERR_MISALIGNED => b"misaligned pointer\0",
        RSL_ERR_INTERNAL => b"internal error (caught panic)\0",
        RSL_ERR_INVALID_TIME_STEP => b"time step must be finite and > 0\0",
        RSL_ERR_NEGATIVE_NORMAL_FORCE => b"negative normal force\0",
        RSL_ERR_INVALID_PARAMETER => b"invalid model parameter\0",
        RSL_ERR_INVALID_HANDLE => b"invalid model handle\0",
        _ => b"unknown status\0",
    };
    s.as_ptr().cast()
}

/// The detail message of the last failing call **on this thread** (for example which field was
/// non-finite), NUL-terminated; "" if no call on this thread has failed. Successful calls do
/// not clear it. The pointer stays valid until the next failing call on the same thread.
#[no_mangle]
pub extern "C" fn rsl_last_error_message() -> *const libc::c_char {
    LAST_ERROR.with(|slot| slot.borrow().as_ptr())
}
