//! Library version: compile-time macros in the header and a run-time query.

/// Major version of the header (must equal the library's, see `rsl_version`).
pub const RSL_VERSION_MAJOR: u32 = 0;
/// Minor version of the header.
pub const RSL_VERSION_MINOR: u32 = 4;
/// Patch version of the header.
pub const RSL_VERSION_PATCH: u32 = 0;
/// The header's version as one number for preprocessor tests, `MAJOR * 10000 + MINOR * 100 +
/// PATCH` (0.3.0 is 300): `#if RSL_VERSION_NUMBER >= 300`.
pub const RSL_VERSION_NUMBER: u32 = 400;

/// The library's version as a static NUL-terminated string "MAJOR.MINOR.PATCH" (the version of
/// the compiled library, which a program can compare with the header's `RSL_VERSION_*`).
#[no_mangle]
pub extern "C" fn rsl_version() -> *const libc::c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    #[test]
    fn header_version_macros_equal_cargo_version() {
        let parse = |s: &str| s.parse::<u32>().unwrap();
        assert_eq!(RSL_VERSION_MAJOR, parse(env!("CARGO_PKG_VERSION_MAJOR")));
        assert_eq!(RSL_VERSION_MINOR, parse(env!("CARGO_PKG_VERSION_MINOR")));
        assert_eq!(RSL_VERSION_PATCH, parse(env!("CARGO_PKG_VERSION_PATCH")));
        assert_eq!(
            RSL_VERSION_NUMBER,
            RSL_VERSION_MAJOR * 10000 + RSL_VERSION_MINOR * 100 + RSL_VERSION_PATCH
        );
        // SAFETY: rsl_version returns a static NUL-terminated string.
        let s = unsafe { CStr::from_ptr(rsl_version()) };
        assert_eq!(s.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
    }
}
