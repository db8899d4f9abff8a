//! rsl_compose and rsl_compose_wall on arbitrary decompositions, and on decompositions of
//! arbitrary sphere pairs (the round trip must not fail where the decomposition succeeded,
//! unless the inverse overflows).
#![no_main]
#[path = "common.rs"]
mod common;
use common::*;
use libfuzzer_sys::fuzz_target;
use rollslide::capi::decompose::*;
use rollslide::capi::types::{rsl_decomposition, rsl_pair_velocities, rsl_wall_velocities};

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let mode = b.u8();
    let opts: rsl_decompose_options = b.raw();
    let o = if mode & 2 == 2 {
        &opts as *const _
    } else {
        std::ptr::null()
    };
    let d: rsl_decomposition = if mode & 1 == 1 {
        let (s1, s2) = (b.sphere(), b.sphere());
        let mut d: rsl_decomposition = pattern();
        let s = unsafe { rsl_decompose(&s1, &s2, o, &mut d) };
        check_status(s, "rsl_decompose");
        if s != 0 {
            return;
        }
        d
    } else {
        b.raw()
    };
    let mut pv: rsl_pair_velocities = pattern();
    let s = unsafe { rsl_compose(&d, o, &mut pv) };
    check_status(s, "rsl_compose");
    if s == 0 {
        assert_finite(doubles(&pv, 12), "rsl_compose");
    } else {
        assert!(is_pattern(&pv), "rsl_compose wrote its output on failure");
    }
    let mut wv: rsl_wall_velocities = pattern();
    let s = unsafe { rsl_compose_wall(&d, o, &mut wv) };
    check_status(s, "rsl_compose_wall");
    if s == 0 {
        assert_finite(doubles(&wv, 12), "rsl_compose_wall");
    } else {
        assert!(
            is_pattern(&wv),
            "rsl_compose_wall wrote its output on failure"
        );
    }
});
