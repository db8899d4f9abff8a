//! Shared helpers of the fuzz targets: the input bytes read as the C structs' fields (any bit
//! pattern, so NaN, infinities, subnormals and huge values all occur), and the checks every call
//! must pass whatever its input:
//! - the status is a defined code, and never `RSL_ERR_INTERNAL` (a caught panic is a bug);
//! - a failure leaves a non-empty message and every output and state byte untouched;
//! - a success writes only finite numbers (a wall's `distance`/`branch2` are +inf by definition).
//!
//! Calling the C ABI needs `unsafe`: these targets are its (only) users outside `src/capi/`.
#![allow(dead_code)]

use rollslide::capi::status::{rsl_last_error_message, RSL_ERR_INTERNAL, RSL_ERR_INVALID_HANDLE};
use rollslide::capi::types::{rsl_sphere, rsl_vec3, rsl_wall};
use std::mem::{size_of, MaybeUninit};

pub const PATTERN: u8 = 0xA5;

/// The fuzzer's bytes as a stream of fields; zeros once exhausted.
pub struct Bytes<'a>(pub &'a [u8]);

impl Bytes<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        let n = N.min(self.0.len());
        out[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        out
    }
    pub fn f64(&mut self) -> f64 {
        f64::from_le_bytes(self.take::<8>())
    }
    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.take::<4>())
    }
    pub fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.take::<4>())
    }
    pub fn u8(&mut self) -> u8 {
        self.take::<1>()[0]
    }
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
    pub fn vec3(&mut self) -> rsl_vec3 {
        rsl_vec3 {
            x: self.f64(),
            y: self.f64(),
            z: self.f64(),
        }
    }
    pub fn sphere(&mut self) -> rsl_sphere {
        rsl_sphere {
            position: self.vec3(),
            velocity: self.vec3(),
            angular_velocity: self.vec3(),
            radius: self.f64(),
        }
    }
    pub fn wall(&mut self) -> rsl_wall {
        rsl_wall {
            point: self.vec3(),
            normal: self.vec3(),
            velocity: self.vec3(),
            angular_velocity: self.vec3(),
        }
    }
    /// A plain-data struct (only f64/u32/i32 fields, so every bit pattern is valid) from bytes.
    pub fn raw<T: Copy>(&mut self) -> T {
        let mut v = MaybeUninit::<T>::uninit();
        let bytes =
            unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<u8>(), size_of::<T>()) };
        for b in bytes.iter_mut() {
            *b = self.u8();
        }
        // SAFETY: every byte written; the callers use structs of f64/u32/i32 only.
        unsafe { v.assume_init() }
    }
}

/// A plain-data output struct filled with the 0xA5 pattern.
pub fn pattern<T: Copy>() -> T {
    let mut v = MaybeUninit::<T>::uninit();
    // SAFETY: every byte written; T is plain data (f64/u32/i32 fields).
    unsafe {
        std::ptr::write_bytes(v.as_mut_ptr().cast::<u8>(), PATTERN, size_of::<T>());
        v.assume_init()
    }
}

pub fn bytes_of<T>(x: &T) -> &[u8] {
    // SAFETY: reading the bytes of a plain-data struct without padding holes.
    unsafe { std::slice::from_raw_parts((x as *const T).cast::<u8>(), size_of::<T>()) }
}

pub fn is_pattern<T>(x: &T) -> bool {
    bytes_of(x).iter().all(|&b| b == PATTERN)
}

/// The first `n` f64 fields of a plain-data struct that starts with them.
pub fn doubles<T>(x: &T, n: usize) -> &[f64] {
    assert!(n * 8 <= size_of::<T>());
    // SAFETY: the struct starts with n f64 fields (repr(C)).
    unsafe { std::slice::from_raw_parts((x as *const T).cast::<f64>(), n) }
}

/// Every call: a defined status, never a caught panic; a failure has a message.
pub fn check_status(status: i32, call: &str) {
    assert!(
        (0..=RSL_ERR_INVALID_HANDLE).contains(&status),
        "{call}: undefined status {status}"
    );
    assert_ne!(
        status,
        RSL_ERR_INTERNAL,
        "{call}: a panic was caught: {}",
        last_message()
    );
    if status != 0 {
        assert!(
            !last_message().is_empty(),
            "{call}: failed without a message"
        );
    }
}

pub fn last_message() -> String {
    // SAFETY: a NUL-terminated thread-local string, valid until the next failing call.
    unsafe { std::ffi::CStr::from_ptr(rsl_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

pub fn assert_finite(values: &[f64], call: &str) {
    for (i, x) in values.iter().enumerate() {
        assert!(
            x.is_finite(),
            "{call}: OK with non-finite output field {i} = {x}"
        );
    }
}

use rollslide::capi::contact::{rsl_contact_loads, rsl_contact_state};
use rollslide::capi::model::*;

/// A code that is valid most of the time (`byte % (n + 1)`, with `n` the number of valid
/// codes), sometimes one past the end, and for byte 255 an arbitrary i32.
pub fn code(b: &mut Bytes, n: i32) -> i32 {
    let x = b.u8();
    if x == 255 {
        b.i32()
    } else {
        x as i32 % (n + 1)
    }
}

/// A parameter: one of a few typical values, or arbitrary bits.
pub fn param(b: &mut Bytes) -> f64 {
    match b.u8() % 8 {
        0 => 0.0,
        1 => 1.0,
        2 => 1e3,
        3 => 0.5,
        4 => f64::INFINITY,
        _ => b.f64(),
    }
}

/// A model configured through the setters from the bytes; every setter's status is checked,
/// and a refused setter must leave the rolling parameters as they were.
pub fn model_from(b: &mut Bytes) -> *mut rsl_model {
    let mut m: *mut rsl_model = std::ptr::null_mut();
    let s = unsafe { rsl_model_new(code(b, 4), &mut m) };
    check_status(s, "rsl_model_new");
    if s != 0 {
        assert!(m.is_null());
        let s = unsafe { rsl_model_new(RSL_PRESET_OBJECTIVE, &mut m) };
        assert_eq!(s, 0);
    }
    let ops = b.u8() % 8;
    for _ in 0..ops {
        let mut before: rsl_rolling_params = pattern();
        assert_eq!(unsafe { rsl_model_get_rolling(m, &mut before) }, 0);
        let (s, what) = match b.u8() % 8 {
            0 => (
                unsafe { rsl_model_set_sliding(m, code(b, 2), param(b), param(b), param(b)) },
                "rsl_model_set_sliding",
            ),
            1 => (
                unsafe { rsl_model_set_twisting(m, code(b, 3), param(b), param(b), param(b)) },
                "rsl_model_set_twisting",
            ),
            2 => {
                let p = rsl_rolling_params {
                    law: code(b, 4),
                    form: code(b, 2),
                    stiffness_rule: code(b, 4),
                    damping_rule: code(b, 2),
                    damping_mode: code(b, 2),
                    reserved: 0,
                    stiffness: param(b),
                    damping: param(b),
                    friction: param(b),
                    rate_threshold: param(b),
                    stiffness_factor: param(b),
                };
                let s = unsafe { rsl_model_set_rolling(m, &p) };
                if s == 0 {
                    let mut got: rsl_rolling_params = pattern();
                    assert_eq!(unsafe { rsl_model_get_rolling(m, &mut got) }, 0);
                    assert_eq!(bytes_of(&got), bytes_of(&p), "set/get rolling round trip");
                }
                (s, "rsl_model_set_rolling")
            }
            3 => (
                unsafe { rsl_model_set_transport(m, code(b, 5), code(b, 5)) },
                "rsl_model_set_transport",
            ),
            4 => (
                unsafe { rsl_model_set_geometry(m, code(b, 2), code(b, 2)) },
                "rsl_model_set_geometry",
            ),
            5 => (
                unsafe { rsl_model_set_torsion_torque(m, code(b, 2)) },
                "rsl_model_set_torsion_torque",
            ),
            6 => (
                unsafe { rsl_model_set_avoid_granular_ratcheting(m, code(b, 2)) },
                "rsl_model_set_avoid_granular_ratcheting",
            ),
            _ => (
                unsafe { rsl_model_set_energy_tracking(m, code(b, 2)) },
                "rsl_model_set_energy_tracking",
            ),
        };
        check_status(s, what);
        if s != 0 {
            let mut after: rsl_rolling_params = pattern();
            assert_eq!(unsafe { rsl_model_get_rolling(m, &mut after) }, 0);
            assert_eq!(
                bytes_of(&before),
                bytes_of(&after),
                "{what} changed a model it refused"
            );
        }
    }
    m
}

/// Checks one step's outcome: finite loads and state on success, untouched ones on failure.
pub fn check_step(
    status: i32,
    call: &str,
    out: &rsl_contact_loads,
    state: &rsl_contact_state,
    state_before: &rsl_contact_state,
) {
    check_status(status, call);
    if status == 0 {
        assert_finite(doubles(out, 28), call);
        assert_finite(doubles(state, 13), call);
    } else {
        assert!(is_pattern(out), "{call} wrote its output on failure");
        assert_eq!(
            bytes_of(state),
            bytes_of(state_before),
            "{call} wrote the state on failure"
        );
    }
}
