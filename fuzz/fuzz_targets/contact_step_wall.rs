//! rsl_contact_step_wall: a model from the setters, an arbitrary (or fresh) state, then a few steps
//! of an arbitrary sphere, wall and input.
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
        if b.is_empty() {
            break;
        }
    }
    unsafe { rsl_model_free(m) };
});
