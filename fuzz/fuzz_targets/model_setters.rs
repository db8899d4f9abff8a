//! The model setters and getter on arbitrary codes and parameters (each refused call must leave
//! the model unchanged: checked inside `model_from`), then one step with the model to show it
//! stayed usable.
#![no_main]
#[path = "common.rs"]
mod common;
use common::*;
use libfuzzer_sys::fuzz_target;
use rollslide::capi::contact::*;
use rollslide::capi::model::rsl_model_free;
use rollslide::capi::types::{rsl_sphere, rsl_vec3};

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let m = model_from(&mut b);
    let v = |x, y, z| rsl_vec3 { x, y, z };
    let s1 = rsl_sphere {
        position: v(0.0, 0.0, 0.0),
        velocity: v(0.1, 0.2, 0.0),
        angular_velocity: v(0.0, 0.0, 1.0),
        radius: 0.7,
    };
    let s2 = rsl_sphere {
        position: v(2.99, 0.0, 0.0),
        velocity: v(0.0, 0.0, 0.0),
        angular_velocity: v(0.3, 0.0, -0.5),
        radius: 2.3,
    };
    let input = rsl_contact_input {
        normal_force: 10.0,
        dt: 1e-3,
        normal_stiffness: 1e4,
        mass1: 1.0,
        mass2: 2.0,
        inertia1: 0.2,
        inertia2: 4.0,
        ..Default::default()
    };
    let mut state = rsl_contact_state::default();
    for _ in 0..3 {
        let before = state;
        let mut out: rsl_contact_loads = pattern();
        let s = unsafe { rsl_contact_step(m, &s1, &s2, &input, &mut state, &mut out) };
        check_step(s, "rsl_contact_step", &out, &state, &before);
        // Only an overflow of arbitrary (huge but finite) parameters may refuse this contact.
        assert!(
            s == 0 || s == rollslide::capi::status::RSL_ERR_NON_FINITE,
            "a valid model refused a valid contact: {}",
            last_message()
        );
    }
    unsafe { rsl_model_free(m) };
});
