//! Shear adhesion and fragile bonds through the C ABI (`RSL_INPUT_SHEAR_ADHESION`,
//! `RSL_INPUT_FRAGILE_BOND`, `RSL_SLIP_BOND_BROKEN`), in closed form: the sliding limit each
//! preset gives a bond, what a fragile bond does in the step it breaks, the combination with
//! `RSL_INPUT_LIMIT_FORCE`, and the refusals. The agreement with YADE 2023.02a's CohFrict is
//! `c::yade_cohesion_matches_yade` (c_tests/test_yade_reference.c).
//!
//! The contact: two unit spheres, centres 1.99 apart along x (n = +x), body 1 sliding at
//! `(0, 1, 0)`, the two rolling as gears; `k_t = 1000`, `mu = 0.4`, `dt = 1e-3`, so the elastic
//! sliding force grows by 1 per step (YADE_2023: by `2/1.99`, its `(R1+R2)/d` scaling), and each
//! limit is far (in ulps) from every trial, so the step that slips is known.

use rollslide::capi::contact::{
    rsl_contact_input, rsl_contact_loads, rsl_contact_state, rsl_contact_step,
    RSL_INPUT_FRAGILE_BOND, RSL_INPUT_LIMIT_FORCE, RSL_INPUT_SHEAR_ADHESION, RSL_SLIP_BOND_BROKEN,
    RSL_SLIP_ROLLING, RSL_SLIP_SLIDING,
};
use rollslide::capi::model::*;
use rollslide::capi::status::{RSL_ERR_INVALID_ARGUMENT, RSL_ERR_NON_FINITE, RSL_OK};
use rollslide::capi::types::{rsl_sphere, rsl_vec3};

const MU: f64 = 0.4;

struct Model(*mut rsl_model);

impl Drop for Model {
    fn drop(&mut self) {
        // SAFETY: a handle from rsl_model_new, freed once.
        unsafe { rsl_model_free(self.0) };
    }
}

/// A model of `preset` with linear sliding (k_t 1000, mu 0.4) and, with `rolling`, an angle-form
/// EPSD rolling spring (k_theta 100, eta 0.01).
fn model(preset: i32, rolling: bool) -> Model {
    let mut m = std::ptr::null_mut();
    // SAFETY: out-pointers to locals; the handle is live until Model drops it.
    unsafe {
        assert_eq!(rsl_model_new(preset, &mut m), RSL_OK);
        assert_eq!(
            rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1000.0, 0.0, MU),
            RSL_OK
        );
        if rolling {
            let mut p = std::mem::zeroed();
            assert_eq!(rsl_model_get_rolling(m, &mut p), RSL_OK);
            p.law = RSL_ROLLING_EPSD;
            p.form = RSL_FORM_ANGLE;
            p.stiffness = 100.0;
            p.damping = 0.0;
            p.friction = 0.01;
            assert_eq!(rsl_model_set_rolling(m, &p), RSL_OK);
        }
    }
    Model(m)
}

fn v(x: f64, y: f64, z: f64) -> rsl_vec3 {
    rsl_vec3 { x, y, z }
}

/// Body 1 sliding at (0, 1, 0); the two rolling as gears about z (`w1 = -w2`: no sliding from
/// the spins with equal radii), for the rolling checks.
fn bodies() -> (rsl_sphere, rsl_sphere) {
    let b1 = rsl_sphere {
        position: v(0.0, 0.0, 0.0),
        velocity: v(0.0, 1.0, 0.0),
        angular_velocity: v(0.0, 0.0, 0.5),
        radius: 1.0,
    };
    let b2 = rsl_sphere {
        position: v(1.99, 0.0, 0.0),
        velocity: v(0.0, 0.0, 0.0),
        angular_velocity: v(0.0, 0.0, -0.5),
        radius: 1.0,
    };
    (b1, b2)
}

fn input(f_n: f64, flags: u32, adhesion: f64) -> rsl_contact_input {
    rsl_contact_input {
        normal_force: f_n,
        dt: 1e-3,
        shear_adhesion: adhesion,
        flags,
        ..Default::default()
    }
}

fn step(m: &Model, i: &rsl_contact_input, s: &mut rsl_contact_state) -> (i32, rsl_contact_loads) {
    let (b1, b2) = bodies();
    let mut out = rsl_contact_loads::default();
    // SAFETY: a live model and live locals of the right types, none overlapping.
    let status = unsafe { rsl_contact_step(m.0, &b1, &b2, i, s, &mut out) };
    (status, out)
}

/// `|F_t|` after `n` steps of the same input from a fresh state, and the last loads.
fn saturated(m: &Model, i: &rsl_contact_input, n: usize) -> (f64, rsl_contact_loads) {
    let mut s = rsl_contact_state::default();
    let mut out = rsl_contact_loads::default();
    for k in 0..n {
        let (status, o) = step(m, i, &mut s);
        assert_eq!(status, RSL_OK, "step {k}");
        out = o;
    }
    let f = out.sliding_force;
    ((f.x * f.x + f.y * f.y + f.z * f.z).sqrt(), out)
}

fn close(a: f64, b: f64) -> bool {
    // The clipped force is `limit * (trial / |trial|)`: a couple of roundings of the limit.
    (a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1.0)
}

/// The sliding limit of a bond, `max(0, c_s + mu F)`, with each preset's `F`: the signed `f_n`
/// for YADE_2023, `max(f_n, 0)` for the objective preset, `|f_n|` for LAMMPS_2021 and
/// LIGGGHTS_3_8 (LIGGGHTS clips the spring alone; there is no dashpot here). Without the flag
/// the limit is the preset's `mu F` (0 under tension for the objective and YADE presets).
#[test]
fn each_preset_adds_the_shear_adhesion_to_its_sliding_limit() {
    let c = 3.0;
    let flag = RSL_INPUT_SHEAR_ADHESION;
    // (preset, f_n, limit without the flag, limit with c_s = 3)
    let cases = [
        (RSL_PRESET_OBJECTIVE, 10.0, 4.0, 7.0),
        (RSL_PRESET_OBJECTIVE, -5.0, 0.0, 3.0),
        (RSL_PRESET_YADE_2023, 10.0, 4.0, 7.0),
        (RSL_PRESET_YADE_2023, -5.0, 0.0, 1.0),
        (RSL_PRESET_YADE_2023, -10.0, 0.0, 0.0),
        (RSL_PRESET_LAMMPS_2021, -5.0, 2.0, 5.0),
        (RSL_PRESET_LIGGGHTS_3_8, -5.0, 2.0, 5.0),
        (RSL_PRESET_LIGGGHTS_3_8, 10.0, 4.0, 7.0),
    ];
    for (preset, f_n, without, with) in cases {
        let m = model(preset, false);
        let (plain, _) = saturated(&m, &input(f_n, 0, 0.0), 20);
        let (bonded, out) = saturated(&m, &input(f_n, flag, c), 20);
        assert!(close(plain, without), "preset {preset} f_n {f_n}: {plain}");
        assert!(close(bonded, with), "preset {preset} f_n {f_n}: {bonded}");
        assert_eq!(out.slip_flags & RSL_SLIP_SLIDING, RSL_SLIP_SLIDING);
        assert_eq!(out.slip_flags & RSL_SLIP_BOND_BROKEN, 0, "not fragile");
    }
    // Below the limit the bond changes nothing: 5 steps load the spring to 5 < 7.
    let m = model(RSL_PRESET_OBJECTIVE, false);
    let (elastic, out) = saturated(&m, &input(10.0, flag, c), 5);
    assert!(close(elastic, 5.0), "{elastic}");
    assert_eq!(out.slip_flags, 0);
}

/// A zero adhesion, or a shear_adhesion left without its flag, gives the plain step bit for bit
/// (`0 + mu F` is `mu F`). For YADE_2023 under compression too (its |f_n| is f_n there).
#[test]
fn zero_or_unflagged_adhesion_changes_no_bit() {
    for preset in [
        RSL_PRESET_OBJECTIVE,
        RSL_PRESET_LAMMPS_2021,
        RSL_PRESET_YADE_2023,
        RSL_PRESET_LIGGGHTS_3_8,
    ] {
        for f_n in [10.0, -5.0] {
            if preset == RSL_PRESET_YADE_2023 && f_n < 0.0 {
                continue; // YADE's bond rules under tension differ on purpose (next tests)
            }
            let m = model(preset, true);
            let (mut s0, mut s1, mut s2) = Default::default();
            for k in 0..12 {
                let a = step(&m, &input(f_n, 0, 0.0), &mut s0);
                let b = step(&m, &input(f_n, RSL_INPUT_SHEAR_ADHESION, 0.0), &mut s1);
                let c = step(&m, &input(f_n, 0, f64::NAN), &mut s2);
                assert_eq!(
                    format!("{a:?}"),
                    format!("{b:?}"),
                    "preset {preset} step {k}"
                );
                assert_eq!(
                    format!("{a:?}"),
                    format!("{c:?}"),
                    "preset {preset} step {k}"
                );
            }
        }
    }
}

/// YADE_2023 with a bond, as CohFrict: the rolling limit uses |f_n| under tension (without the
/// flag, max(f_n, 0) = 0); in a step that slips under tension the normal force is not applied
/// and the rolling limit is 0. With RSL_INPUT_LIMIT_FORCE the host's force replaces f_n in every
/// limit and the normal force is applied as given.
#[test]
fn yade_bond_rules_under_tension() {
    let m = model(RSL_PRESET_YADE_2023, true);
    let flag = RSL_INPUT_SHEAR_ADHESION;
    // f_n = -5, c_s = 30: limit 28, not reached in 3 steps; rolling limit 0.01 * 5 = 0.05, and
    // the rolling moment 100 * 1 * 1e-3 per step reaches it at the first step.
    let mut s = rsl_contact_state::default();
    let mut out = rsl_contact_loads::default();
    for _ in 0..3 {
        out = step(&m, &input(-5.0, flag, 30.0), &mut s).1;
    }
    assert_eq!(out.slip_flags, RSL_SLIP_ROLLING);
    let rolling = out.rolling_moment.z.abs();
    assert!(close(rolling, 0.05), "{rolling}");
    assert!(
        close(out.force1.x, 5.0),
        "tension: body 1 pulled towards body 2"
    );
    // Without the flag: no rolling resistance under tension.
    let (_, plain) = saturated(&m, &input(-5.0, 0, 30.0), 3);
    assert_eq!(plain.rolling_moment.z, 0.0);
    assert!(close(plain.force1.x, 5.0));
    // c_s = 1: limit max(0, 1 - 2) = 0, slips at once: no normal force, no rolling moment.
    let (f, slip) = saturated(&m, &input(-5.0, flag, 1.0), 3);
    assert_eq!(f, 0.0);
    assert_eq!(slip.force1.x, 0.0);
    assert_eq!(slip.rolling_moment.z, 0.0);
    assert_eq!(
        slip.slip_flags & (RSL_SLIP_SLIDING | RSL_SLIP_ROLLING),
        RSL_SLIP_SLIDING | RSL_SLIP_ROLLING
    );
    // With a limit force 2 (and c_s = 1): sliding limit 1 + 0.8, rolling 0.02, f_n applied.
    let mut both = input(-5.0, flag | RSL_INPUT_LIMIT_FORCE, 1.0);
    both.limit_force = 2.0;
    let (f, out) = saturated(&m, &both, 20);
    assert!(close(f, 1.8), "{f}");
    assert!(close(out.rolling_moment.z.abs(), 0.02));
    assert!(close(out.force1.x, 5.0));
}

/// A fragile bond: no break below the adhesive limit; in the step the trial exceeds it, the
/// force is clipped at the limit without adhesion and RSL_SLIP_BOND_BROKEN is reported (in the
/// loads and the state); the host then steps without the bond and the limit stays mu F.
#[test]
fn a_fragile_bond_breaks_in_the_step_it_is_exceeded() {
    for preset in [
        RSL_PRESET_OBJECTIVE,
        RSL_PRESET_YADE_2023,
        RSL_PRESET_LAMMPS_2021,
    ] {
        let m = model(preset, false);
        let bond = input(10.0, RSL_INPUT_SHEAR_ADHESION | RSL_INPUT_FRAGILE_BOND, 3.5);
        let mut s = rsl_contact_state::default();
        // The trial is k (steps) * 1: 7 at step 7 is within 7.5, 8 at step 8 is not.
        for k in 1..=7 {
            let (status, out) = step(&m, &bond, &mut s);
            assert_eq!(status, RSL_OK);
            assert_eq!(out.slip_flags, 0, "preset {preset} step {k}");
        }
        let (status, out) = step(&m, &bond, &mut s);
        assert_eq!(status, RSL_OK);
        assert_eq!(
            out.slip_flags,
            RSL_SLIP_SLIDING | RSL_SLIP_BOND_BROKEN,
            "preset {preset}"
        );
        assert_eq!(s.slip_flags, out.slip_flags);
        let f = out.sliding_force.y.abs();
        assert!(close(f, 4.0), "preset {preset}: {f}, not the adhesive 7.5");
        // The host drops the bond: the frictional limit from now on.
        let (status, after) = step(&m, &input(10.0, 0, 0.0), &mut s);
        assert_eq!(status, RSL_OK);
        assert_eq!(after.slip_flags, RSL_SLIP_SLIDING);
        assert!(close(after.sliding_force.y.abs(), 4.0));
    }
    // +INFINITY: no sliding limit while bonded, so a fragile bond never breaks.
    let m = model(RSL_PRESET_OBJECTIVE, false);
    let (f, out) = saturated(
        &m,
        &input(
            10.0,
            RSL_INPUT_SHEAR_ADHESION | RSL_INPUT_FRAGILE_BOND,
            f64::INFINITY,
        ),
        50,
    );
    assert!(close(f, 50.0), "{f}");
    assert_eq!(out.slip_flags, 0);
}

/// Refusals leave the state and the loads untouched: negative shear_adhesion
/// (RSL_ERR_INVALID_ARGUMENT), NaN or -inf (RSL_ERR_NON_FINITE, as every other per-contact
/// limit input), a fragile bond without its adhesion (RSL_ERR_INVALID_ARGUMENT).
#[test]
fn bad_adhesion_inputs_are_refused_and_change_nothing() {
    let m = model(RSL_PRESET_YADE_2023, true);
    let mut s = rsl_contact_state::default();
    for _ in 0..4 {
        assert_eq!(step(&m, &input(10.0, 0, 0.0), &mut s).0, RSL_OK);
    }
    let flag = RSL_INPUT_SHEAR_ADHESION;
    for (i, expected) in [
        (input(10.0, flag, -1.0), RSL_ERR_INVALID_ARGUMENT),
        (input(10.0, flag, -0.0), RSL_OK),
        (input(10.0, flag, f64::NAN), RSL_ERR_NON_FINITE),
        (input(10.0, flag, f64::NEG_INFINITY), RSL_ERR_NON_FINITE),
        (
            input(10.0, RSL_INPUT_FRAGILE_BOND, 1.0),
            RSL_ERR_INVALID_ARGUMENT,
        ),
    ] {
        let before = s;
        let (b1, b2) = bodies();
        let mut out = rsl_contact_loads {
            reserved: 7,
            ..Default::default()
        };
        let mut trial = s;
        // SAFETY: a live model and live locals of the right types, none overlapping.
        let status = unsafe { rsl_contact_step(m.0, &b1, &b2, &i, &mut trial, &mut out) };
        assert_eq!(status, expected, "{i:?}");
        if status != RSL_OK {
            assert_eq!(format!("{trial:?}"), format!("{before:?}"));
            assert_eq!(out.reserved, 7, "loads written on a refusal");
            // SAFETY: a static NUL-terminated string.
            let msg = unsafe {
                std::ffi::CStr::from_ptr(rollslide::capi::status::rsl_last_error_message())
            };
            assert!(msg.to_string_lossy().contains("shear_adhesion"), "{msg:?}");
        }
    }
}
