//! rsl_contact_step_wall: a model from the setters, an arbitrary (or fresh) state, then a few steps
//! of an arbitrary sphere, wall and input, each also through rsl_contact_step_wall_unchecked.
#![no_main]
#[path = "common.rs"]
mod common;
use common::*;
use libfuzzer_sys::fuzz_target;
use rollslide::capi::contact::*;
use rollslide::capi::model::rsl_model_free;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let m = model_from(&mut b);
    let mut state: rsl_contact_state = if b.u8() & 1 == 1 {
        b.raw()
    } else {
        Default::default()
    };
    let steps = 1 + b.u8() % 4;
    for _ in 0..steps {
        let (s1, w) = (b.sphere(), b.wall());
        let input: rsl_contact_input = b.raw();
        let before = state;
        let mut out: rsl_contact_loads = common::pattern();
        let s = unsafe { rsl_contact_step_wall(m, &s1, &w, &input, &mut state, &mut out) };
        check_step(s, "rsl_contact_step_wall", &out, &state, &before);
        // The unchecked entry from the same state: the checked entry's bits where that accepts
        // the input and the wall normal is normalised by the plain quotient (the checked step
        // rescales the others first); elsewhere any status, and no crash.
        let mut unchecked_state = before;
        let mut unchecked_out: rsl_contact_loads = common::pattern();
        let s_unchecked = unsafe {
            rsl_contact_step_wall_unchecked(m, &s1, &w, &input, &mut unchecked_state, &mut unchecked_out)
        };
        let plain = rollslide::geometry::plain_unit_vector(&rollslide::scalar::Vec3::new(
            w.normal.x, w.normal.y, w.normal.z,
        ))
        .1;
        if s == 0 && plain {
            assert_eq!(s_unchecked, 0, "rsl_contact_step_wall_unchecked's status");
            assert_eq!(bytes_of(&unchecked_state), bytes_of(&state), "unchecked state");
            assert_eq!(bytes_of(&unchecked_out), bytes_of(&out), "unchecked loads");
        }
        if b.is_empty() {
            break;
        }
    }
    unsafe { rsl_model_free(m) };
});
