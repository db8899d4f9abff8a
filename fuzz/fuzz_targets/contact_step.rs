//! rsl_contact_step: a model from the setters, an arbitrary (or fresh) state, then a few steps
//! of arbitrary spheres and inputs. Each step also goes through rsl_contact_step_accumulate,
//! which must give the same status and state and add exactly the returned loads, and through
//! rsl_contact_step_unchecked, which must give the same bits wherever rsl_contact_step succeeds.
#![no_main]
#[path = "common.rs"]
mod common;
use common::*;
use libfuzzer_sys::fuzz_target;
use rollslide::capi::contact::*;
use rollslide::capi::model::rsl_model_free;
use rollslide::capi::types::rsl_vec3;

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
        let (s1, s2) = (b.sphere(), b.sphere());
        let input: rsl_contact_input = b.raw();
        let before = state;
        let mut out: rsl_contact_loads = common::pattern();
        let s = unsafe { rsl_contact_step(m, &s1, &s2, &input, &mut state, &mut out) };
        check_step(s, "rsl_contact_step", &out, &state, &before);
        // The accumulating entry from the same state, into accumulators of arbitrary values.
        let mut acc_state = before;
        let mut acc: [rsl_vec3; 4] = b.raw();
        let acc_before = acc;
        let [f1, t1, f2, t2] = &mut acc;
        let s_acc = unsafe {
            rsl_contact_step_accumulate(m, &s1, &s2, &input, &mut acc_state, f1, t1, f2, t2)
        };
        assert_eq!(s_acc, s, "rsl_contact_step_accumulate's status");
        assert_eq!(bytes_of(&acc_state), bytes_of(&state), "accumulate's state");
        let mut expected = acc_before;
        if s == 0 {
            let add = |a: &mut rsl_vec3, v: &rsl_vec3, sign: f64| {
                (a.x, a.y, a.z) = if sign > 0.0 {
                    (a.x + v.x, a.y + v.y, a.z + v.z)
                } else {
                    (a.x - v.x, a.y - v.y, a.z - v.z)
                };
            };
            add(&mut expected[0], &out.force1, 1.0);
            add(&mut expected[1], &out.torque1, 1.0);
            add(&mut expected[2], &out.force1, -1.0);
            add(&mut expected[3], &out.torque2, 1.0);
        }
        assert_eq!(bytes_of(&acc), bytes_of(&expected), "accumulated loads");
        // The unchecked entry from the same state: the checked entry's bits where that accepts
        // the input; elsewhere any status, and no crash.
        let mut unchecked_state = before;
        let mut unchecked_out: rsl_contact_loads = common::pattern();
        let s_unchecked = unsafe {
            rsl_contact_step_unchecked(m, &s1, &s2, &input, &mut unchecked_state, &mut unchecked_out)
        };
        if s == 0 {
            assert_eq!(s_unchecked, 0, "rsl_contact_step_unchecked's status");
            assert_eq!(bytes_of(&unchecked_state), bytes_of(&state), "unchecked state");
            assert_eq!(bytes_of(&unchecked_out), bytes_of(&out), "unchecked loads");
        }
        if b.is_empty() {
            break;
        }
    }
    unsafe { rsl_model_free(m) };
});
