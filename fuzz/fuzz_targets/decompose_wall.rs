//! rsl_decompose_wall, then rsl_compose_wall on its result, on arbitrary input.
#![no_main]
#[path = "common.rs"]
mod common;
use common::*;
use libfuzzer_sys::fuzz_target;
use rollslide::capi::decompose::*;
use rollslide::capi::types::{rsl_decomposition, rsl_wall_velocities};
use std::mem::size_of;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let (s, w) = (b.sphere(), b.wall());
    let opts: rsl_decompose_options = b.raw();
    let o = if b.u8() & 1 == 1 {
        &opts as *const _
    } else {
        std::ptr::null()
    };
    let mut out: rsl_decomposition = pattern();
    let status = unsafe { rsl_decompose_wall(&s, &w, o, &mut out) };
    check_status(status, "rsl_decompose_wall");
    if status != 0 {
        assert!(
            is_pattern(&out),
            "rsl_decompose_wall wrote its output on failure"
        );
        return;
    }
    let mut fields = doubles(&out, size_of::<rsl_decomposition>() / 8).to_vec();
    assert!(out.distance == f64::INFINITY && out.branch2 == f64::INFINITY);
    fields[3] = 0.0; // distance
    fields[6] = 0.0; // branch2
    assert_finite(&fields, "rsl_decompose_wall");
    assert!(out.branch1 > 0.0 && out.rolling_radius > 0.0);
    let mut back: rsl_wall_velocities = pattern();
    let s2 = unsafe { rsl_compose_wall(&out, o, &mut back) };
    check_status(s2, "rsl_compose_wall");
    if s2 == 0 {
        assert_finite(doubles(&back, 12), "rsl_compose_wall");
    } else {
        assert!(is_pattern(&back));
    }
});
