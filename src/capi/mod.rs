//! The C ABI. Every `extern "C"` function of the library lives below this module; the header
//! `include/rollslide.h` is generated from it by cbindgen.
//!
//! Rules (CONVENTIONS.md): `int32_t` status returns; outputs last and written only on success;
//! every body behind one panic boundary (`guard`); only `#[repr(C)]` structs of doubles and
//! fixed-width integers cross the boundary; option codes arrive as integers and are validated.
//!
//! The layer is thin: it converts and checks the arguments and calls the core, where the engine
//! is (the batch kernels and their CPU dispatch in `batch::dispatch`, the per-contact fast path
//! in `laws::fast_path`, the C structs they read in place in `layout`). Its modules import only
//! lower ones, no cycle: `status` and `types` (leaves); this module's checks (imports `status`);
//! `decompose` and `handle`; `contact` (imports `handle`); `model` (imports `contact`, `decompose`,
//! `handle`) and `batch` (imports `decompose`, `handle`). The unit-test modules `params_tests`,
//! `batch_walls_tests` and `extreme_input_tests` import any of them.

pub mod batch;
#[cfg(test)]
mod batch_walls_tests;
pub mod contact;
pub mod decompose;
#[cfg(test)]
mod extreme_input_tests;
mod handle;
pub mod model;
#[cfg(test)]
mod params_tests;
pub mod status;
pub mod types;
pub mod version;

use crate::error::Error;
use status::{set_last_error, FfiError, RSL_OK};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `body` behind the panic boundary and maps its result to a status code, recording the
/// detail message of a failure in the thread-local last error.
pub(crate) fn guard<F: FnOnce() -> Result<(), FfiError>>(body: F) -> i32 {
    let outcome =
        catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|payload| Err(panic(payload)));
    match outcome {
        Ok(()) => RSL_OK,
        Err(e) => {
            set_last_error(&e.message());
            e.code()
        }
    }
}

/// As [`guard`], for a body that returns its status itself (and records its own messages).
/// Always inlined: its callers are hot steps built for AVX2, whose closures have the AVX2
/// features; a `guard_status` built without them could not take such a closure in, which left
/// the whole step behind two extra calls (measured 1.4-1.7x the time per contact).
#[inline(always)]
pub(crate) fn guard_status<F: FnOnce() -> i32>(body: F) -> i32 {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|payload| {
        let e = panic(payload);
        set_last_error(&e.message());
        e.code()
    })
}

/// The error of a caught panic, with its message when it has one.
fn panic(payload: Box<dyn std::any::Any + Send>) -> FfiError {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string());
    FfiError::Panic(what)
}

/// Borrows a caller's input struct, refusing NULL and misaligned pointers.
///
/// # Safety
/// `p` must be NULL or point to a live, initialised `T` that is not written during the call
/// (the C API's documented contract); alignment and NULL are checked here.
pub(crate) unsafe fn input<'a, T>(p: *const T, name: &'static str) -> Result<&'a T, FfiError> {
    if p.is_null() {
        return Err(FfiError::NullPointer(name));
    }
    if !p.is_aligned() {
        return Err(FfiError::Misaligned(name));
    }
    // SAFETY: non-null and aligned (checked above); validity and liveness are the caller's
    // contract stated in the function's documentation.
    Ok(unsafe { &*p })
}

/// Borrows an optional input struct: NULL gives `None` (the documented default).
///
/// # Safety
/// As [`input`].
pub(crate) unsafe fn optional_input<'a, T>(
    p: *const T,
    name: &'static str,
) -> Result<Option<&'a T>, FfiError> {
    if p.is_null() {
        Ok(None)
    } else {
        // SAFETY: forwarded contract of `input`.
        unsafe { input(p, name) }.map(Some)
    }
}

/// Checks an output pointer, refusing NULL and misaligned pointers. Nothing is written here;
/// callers write the whole result once, after every check has passed.
///
/// # Safety
/// `p` must be NULL or point to writable memory for one `T`, not aliased by any input.
pub(crate) unsafe fn output<'a, T>(p: *mut T, name: &'static str) -> Result<&'a mut T, FfiError> {
    if p.is_null() {
        return Err(FfiError::NullPointer(name));
    }
    if !p.is_aligned() {
        return Err(FfiError::Misaligned(name));
    }
    // SAFETY: non-null and aligned (checked above); writability and exclusivity are the
    // caller's contract stated in the function's documentation.
    Ok(unsafe { &mut *p })
}

/// Checks a pointer the step reads and writes through without borrowing it (accumulators, which
/// may alias each other), refusing NULL and misaligned pointers.
pub(crate) fn checked_pointer<T>(p: *mut T, name: &'static str) -> Result<*mut T, FfiError> {
    if p.is_null() {
        return Err(FfiError::NullPointer(name));
    }
    if !p.is_aligned() {
        return Err(FfiError::Misaligned(name));
    }
    Ok(p)
}

/// Borrows `n` elements of an input array; NULL is allowed only for `n = 0`.
///
/// # Safety
/// `p` must be NULL or point to `n` initialised `T` not written during the call.
pub(crate) unsafe fn slice_in<'a, T>(
    p: *const T,
    n: usize,
    name: &'static str,
) -> Result<&'a [T], FfiError> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(FfiError::NullPointer(name));
    }
    if !p.is_aligned() {
        return Err(FfiError::Misaligned(name));
    }
    if n.checked_mul(std::mem::size_of::<T>())
        .is_none_or(|bytes| bytes > isize::MAX as usize)
    {
        return Err(FfiError::Core(Error::InvalidArgument(format!(
            "{name}: array length {n} too large"
        ))));
    }
    // SAFETY: non-null, aligned, size within isize::MAX (checked above); validity for `n`
    // elements is the caller's documented contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// Borrows `n` elements of an output (or in-out) array; NULL is allowed only for `n = 0`.
///
/// # Safety
/// `p` must be NULL or point to `n` writable `T` not aliased by any other argument.
pub(crate) unsafe fn slice_out<'a, T>(
    p: *mut T,
    n: usize,
    name: &'static str,
) -> Result<&'a mut [T], FfiError> {
    // SAFETY: forwarded contract (checks in `slice_in`).
    let s = unsafe { slice_in(p as *const T, n, name)? };
    let len = s.len();
    if len == 0 {
        return Ok(&mut []);
    }
    // SAFETY: as `slice_in`; exclusivity is the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::capi::status::{rsl_last_error_message, RSL_ERR_INTERNAL};
    use std::ffi::CStr;

    #[test]
    fn a_panic_becomes_a_status_and_a_message() {
        let prev = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let status = guard(|| panic!("boom"));
        std::panic::set_hook(prev);
        assert_eq!(status, RSL_ERR_INTERNAL);
        // SAFETY: the pointer is a NUL-terminated thread-local string, valid until the next
        // failing call on this thread.
        let msg = unsafe { CStr::from_ptr(rsl_last_error_message()) };
        assert!(msg.to_str().unwrap().contains("boom"));
    }
}
