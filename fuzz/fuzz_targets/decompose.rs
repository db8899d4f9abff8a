//! rsl_decompose and rsl_decompose_legacy on arbitrary spheres and options.
#![no_main]
#[path = "common.rs"]
mod common;
use common::*;
use libfuzzer_sys::fuzz_target;
use rollslide::capi::decompose::*;
use rollslide::capi::types::{rsl_decomposition, rsl_legacy_rolling};
use std::mem::size_of;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let (s1, s2) = (b.sphere(), b.sphere());
    let opts: rsl_decompose_options = b.raw();
    let use_opts = b.u8() & 1 == 1;
    let o = if use_opts {
        &opts as *const _
    } else {
        std::ptr::null()
    };
    let mut out: rsl_decomposition = pattern();
    let status = unsafe { rsl_decompose(&s1, &s2, o, &mut out) };
    check_status(status, "rsl_decompose");
    if status == 0 {
        assert_finite(
            doubles(&out, size_of::<rsl_decomposition>() / 8),
            "rsl_decompose",
        );
        assert!(out.branch1 > 0.0 && out.branch2 > 0.0 && out.distance > 0.0);
        let n = out.normal;
        assert!(((n.x * n.x + n.y * n.y + n.z * n.z).sqrt() - 1.0).abs() < 1e-12);
    } else {
        assert!(
            is_pattern(&out),
            "rsl_decompose wrote its output on failure"
        );
    }
    let mut legacy: rsl_legacy_rolling = pattern();
    let s = unsafe { rsl_decompose_legacy(&s1, &s2, o, &mut legacy) };
    check_status(s, "rsl_decompose_legacy");
    if s == 0 {
        assert_finite(doubles(&legacy, 6), "rsl_decompose_legacy");
    } else {
        assert!(is_pattern(&legacy));
    }
});
