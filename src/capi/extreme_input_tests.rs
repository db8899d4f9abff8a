//! Finite but extreme inputs through the C ABI (loads whose squared length overflows, wall
//! normals of any length, a wall's unread `l2`), and the argument names in the messages.
//! (The tests of `contact`'s entry points that need the model's C functions: a module of their
//! own, so that `contact` does not import `model`, which imports it.)
use super::contact::*;
use super::decompose::rsl_decompose_wall;
use super::model::*;
use super::status::{
    rsl_last_error_message, RSL_ERR_INVALID_ARGUMENT, RSL_ERR_MISALIGNED, RSL_ERR_NON_FINITE,
    RSL_ERR_NULL_POINTER, RSL_OK,
};
use super::types::{rsl_decomposition, rsl_sphere, rsl_vec3, rsl_wall};
use std::ffi::CStr;

const EPS: f64 = f64::EPSILON;

fn vec3(x: f64, y: f64, z: f64) -> rsl_vec3 {
    rsl_vec3 { x, y, z }
}

fn norm(v: &rsl_vec3) -> f64 {
    (v.x * v.x + v.y * v.y + v.z * v.z).sqrt()
}

fn sphere(position: rsl_vec3, velocity: rsl_vec3, spin: rsl_vec3, radius: f64) -> rsl_sphere {
    rsl_sphere {
        position,
        velocity,
        angular_velocity: spin,
        radius,
    }
}

/// A live model handle, freed on drop.
struct Handle(*mut rsl_model);

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: a live handle from `rsl_model_new`, freed once.
        unsafe { rsl_model_free(self.0) }
    }
}

/// A model of `preset` with every law off.
fn model(preset: i32) -> Handle {
    let mut p = std::ptr::null_mut();
    // SAFETY: `p` is a valid out pointer.
    assert_eq!(unsafe { rsl_model_new(preset, &mut p) }, RSL_OK);
    Handle(p)
}

/// A model of `preset` with the reported sliding law: k_t 1e5, gamma_t 5, mu_s 0.5.
fn sliding_model(preset: i32) -> Handle {
    let m = model(preset);
    // SAFETY: a live handle, used by this thread only.
    let status = unsafe { rsl_model_set_sliding(m.0, RSL_SLIDING_LINEAR, 1e5, 5.0, 0.5) };
    assert_eq!(status, RSL_OK);
    m
}

/// A model of `preset` with the given rolling law (sliding off).
fn rolling_model(preset: i32, law: i32, stiffness: f64, damping: f64, friction: f64) -> Handle {
    let m = model(preset);
    // SAFETY: live handle; all-zero is a valid value of this plain struct.
    unsafe {
        let mut r: rsl_rolling_params = std::mem::zeroed();
        assert_eq!(rsl_model_get_rolling(m.0, &mut r), RSL_OK);
        r.law = law;
        (r.stiffness, r.damping, r.friction) = (stiffness, damping, friction);
        assert_eq!(rsl_model_set_rolling(m.0, &r), RSL_OK);
    }
    m
}

fn last_error() -> String {
    // SAFETY: a NUL-terminated thread-local string, valid until the next failing call.
    unsafe { CStr::from_ptr(rsl_last_error_message()) }
        .to_str()
        .unwrap()
        .to_string()
}

fn step(
    m: &Handle,
    b1: &rsl_sphere,
    b2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
) -> (i32, rsl_contact_loads) {
    let mut out = rsl_contact_loads::default();
    // SAFETY: every pointer is to a live local of the right type; none overlap.
    let status = unsafe { rsl_contact_step(m.0, b1, b2, input, state, &mut out) };
    (status, out)
}

/// The reported geometry: R = 1 and 0.7, centres 1.65 apart along (0.6, 0.8, 0) (overlap
/// 0.05), body 1 moving at `v1`, body 2 at `-v1`.
fn reported_pair(v1: rsl_vec3) -> (rsl_sphere, rsl_sphere) {
    let zero = rsl_vec3::default();
    let b1 = sphere(zero, v1, zero, 1.0);
    let b2 = sphere(
        vec3(0.6 * 1.65, 0.8 * 1.65, 0.0),
        vec3(-v1.x, -v1.y, -v1.z),
        zero,
        0.7,
    );
    (b1, b2)
}

fn input(normal_force: f64) -> rsl_contact_input {
    rsl_contact_input {
        normal_force,
        dt: 1e-4,
        ..Default::default()
    }
}

/// Asserts `v` = `expected` to `tol` relative to `|expected|`, component by component.
#[track_caller]
fn assert_close(v: &rsl_vec3, expected: rsl_vec3, tol: f64, what: &str) {
    let scale = norm(&expected);
    for (a, b) in [(v.x, expected.x), (v.y, expected.y), (v.z, expected.z)] {
        assert!(
            (a - b).abs() <= tol * scale,
            "{what}: {v:?}, expected {expected:?} (to {tol:e} relative)"
        );
    }
}

/// The reported case: sliding at +-1e155 along z, normal (0.6, 0.8, 0). The trial load is
/// `-k_t xi - gamma_t v_s = -(1e5 2e151 + 5 2e155) z = -3e156 z`, whose squared length
/// (9e312) overflows: the clip must still give the Coulomb load `mu_s f_n = 50` against the
/// sliding (-z), not zero, and leave the spring empty (the objective rule: the dashpot, whose
/// load alone is above the limit, carries the limit, so the spring carries nothing). A stored
/// spring of 1e150 z (no motion; trial load -1e155 z) must be reset to the Coulomb limit
/// `mu_s f_n / k_t = 5e-4` along it, not to zero. Tolerance 4 eps: the limit 50 is exact
/// and the direction `load / max|load_k|` is exact here, so only a few roundings remain.
#[test]
fn huge_sliding_loads_are_clipped_to_the_coulomb_limit() {
    let m = sliding_model(RSL_PRESET_OBJECTIVE);
    let (b1, b2) = reported_pair(vec3(0.0, 0.0, 1e155));
    let mut state = rsl_contact_state::default();
    let (status, out) = step(&m, &b1, &b2, &input(100.0), &mut state);
    assert_eq!(status, RSL_OK, "{}", last_error());
    assert_eq!(out.slip_flags & RSL_SLIP_SLIDING, RSL_SLIP_SLIDING);
    assert_close(&out.sliding_force, vec3(0.0, 0.0, -50.0), 4.0 * EPS, "F_t");
    // The dashpot alone (gamma_t v_s = 1e156 z) exceeds the limit: it carries the limit, 50 z,
    // and the spring is reset to the rest of the clipped load, -(F_t + 50 z)/k_t = 0.
    let xi = state.sliding_spring;
    assert_eq!((xi.x, xi.y, xi.z), (0.0, 0.0, 0.0), "spring");
    assert_eq!(state.slip_flags, out.slip_flags);

    // A stored spring of 1e150 along z, nothing moving.
    let (b1, b2) = reported_pair(rsl_vec3::default());
    for (preset, name) in [
        (RSL_PRESET_OBJECTIVE, "objective (total clip)"),
        (RSL_PRESET_LAMMPS_2021, "LAMMPS (its clip)"),
        (RSL_PRESET_LIGGGHTS_3_8, "LIGGGHTS (spring-only clip)"),
    ] {
        let m = sliding_model(preset);
        let mut state = rsl_contact_state {
            sliding_spring: vec3(0.0, 0.0, 1e150),
            ..Default::default()
        };
        let (status, out) = step(&m, &b1, &b2, &input(100.0), &mut state);
        assert_eq!(status, RSL_OK, "{name}: {}", last_error());
        assert_eq!(
            out.slip_flags & RSL_SLIP_SLIDING,
            RSL_SLIP_SLIDING,
            "{name}"
        );
        assert_close(&out.sliding_force, vec3(0.0, 0.0, -50.0), 4.0 * EPS, name);
        let limit = vec3(0.0, 0.0, 5e-4);
        assert_close(&state.sliding_spring, limit, 4.0 * EPS, name);
    }
    // YADE stores the elastic shear force itself: 1e160 along z is clipped to 50 along z.
    let m = sliding_model(RSL_PRESET_YADE_2023);
    let mut state = rsl_contact_state {
        sliding_spring: vec3(0.0, 0.0, 1e160),
        ..Default::default()
    };
    let (status, out) = step(&m, &b1, &b2, &input(100.0), &mut state);
    assert_eq!(status, RSL_OK, "YADE: {}", last_error());
    assert_close(
        &out.sliding_force,
        vec3(0.0, 0.0, 50.0),
        4.0 * EPS,
        "YADE F_t",
    );
    assert_close(
        &state.sliding_spring,
        vec3(0.0, 0.0, 50.0),
        4.0 * EPS,
        "YADE",
    );

    // The same against a wall (sphere 1 of the pair; the wall's outward normal -n).
    let m = sliding_model(RSL_PRESET_OBJECTIVE);
    let (b1, _) = reported_pair(vec3(0.0, 0.0, 1e155));
    let wall = rsl_wall {
        point: vec3(0.6 * 0.99, 0.8 * 0.99, 0.0),
        normal: vec3(-0.6, -0.8, 0.0),
        velocity: vec3(0.0, 0.0, -1e155),
        angular_velocity: rsl_vec3::default(),
    };
    let mut state = rsl_contact_state::default();
    let mut out = rsl_contact_loads::default();
    // SAFETY: every pointer is to a live local of the right type; none overlap.
    let status =
        unsafe { rsl_contact_step_wall(m.0, &b1, &wall, &input(100.0), &mut state, &mut out) };
    assert_eq!(status, RSL_OK, "wall: {}", last_error());
    assert_close(
        &out.sliding_force,
        vec3(0.0, 0.0, -50.0),
        4.0 * EPS,
        "wall F_t",
    );
}

/// The rolling laws and YADE's vector twisting law clip (or normalise) vectors as the
/// sliding law does: a moment whose squared length overflows must come out at its limit,
/// not zero. Limits (f_n = 100, R_r from `rsl_decompose`): EPSD and viscous rolling
/// (length form) `mu_r f_n R_r`, cdt `mu_r f_n R_r` (its only magnitude), YADE twisting
/// `mu_tw f_n`. Tolerance 8 eps: the limit and R_r carry a few roundings each.
#[test]
fn huge_rolling_and_twisting_moments_are_clipped_to_their_limits() {
    let (b1, b2) = reported_pair(rsl_vec3::default());
    let mut d = rsl_decomposition::default();
    // SAFETY: live locals of the right types.
    let status =
        unsafe { crate::capi::decompose::rsl_decompose(&b1, &b2, std::ptr::null(), &mut d) };
    assert_eq!(status, RSL_OK);
    let (mu_r, f_n) = (0.1, 100.0);
    let moment_limit = mu_r * f_n * d.rolling_radius;
    // A spin difference of 1e160 about z: |(w1 - w2) x n| = 1e160 (n in the xy plane).
    let spinning = rsl_sphere {
        angular_velocity: vec3(0.0, 0.0, 1e160),
        ..b1
    };
    let cases: [(&str, Handle, rsl_sphere, rsl_contact_state); 3] = [
        (
            "EPSD rolling, stored spring 1e150",
            rolling_model(RSL_PRESET_OBJECTIVE, RSL_ROLLING_EPSD, 1e5, 1.0, mu_r),
            b1,
            rsl_contact_state {
                rolling_spring: vec3(0.0, 0.0, 1e150),
                ..Default::default()
            },
        ),
        (
            "viscous rolling, spin 1e160",
            rolling_model(RSL_PRESET_OBJECTIVE, RSL_ROLLING_VISCOUS, 0.0, 10.0, mu_r),
            spinning,
            rsl_contact_state::default(),
        ),
        (
            "cdt rolling, spin 1e160",
            rolling_model(RSL_PRESET_OBJECTIVE, RSL_ROLLING_CDT, 0.0, 0.0, mu_r),
            spinning,
            rsl_contact_state::default(),
        ),
    ];
    for (what, m, body1, state0) in cases {
        let mut state = state0;
        let (status, out) = step(&m, &body1, &b2, &input(f_n), &mut state);
        assert_eq!(status, RSL_OK, "{what}: {}", last_error());
        assert_eq!(
            out.slip_flags & RSL_SLIP_ROLLING,
            RSL_SLIP_ROLLING,
            "{what}"
        );
        let size = norm(&out.rolling_moment);
        assert!(
            (size - moment_limit).abs() <= 8.0 * EPS * moment_limit,
            "{what}: |M_r| = {size:e}, limit {moment_limit:e}"
        );
    }
    // YADE's twisting moment is a vector, stored along the previous normal.
    let m = model(RSL_PRESET_YADE_2023);
    // SAFETY: a live handle, used by this thread only.
    let status = unsafe { rsl_model_set_twisting(m.0, RSL_TWISTING_SDS, 10.0, 0.0, 0.05) };
    assert_eq!(status, RSL_OK);
    let mut state = rsl_contact_state {
        twisting_angle: 1e160,
        ..Default::default()
    };
    let (status, out) = step(&m, &b1, &b2, &input(f_n), &mut state);
    assert_eq!(status, RSL_OK, "YADE twisting: {}", last_error());
    assert_eq!(out.slip_flags & RSL_SLIP_TWISTING, RSL_SLIP_TWISTING);
    let size = norm(&out.twisting_torque);
    let limit = 0.05 * f_n;
    assert!(
        (size - limit).abs() <= 8.0 * EPS * limit,
        "YADE twisting: |M_tw| = {size:e}, limit {limit:e}"
    );
}

/// The sphere of the C tests on a floor (height 0.69, R = 0.7), moving and spinning.
fn floor_sphere() -> rsl_sphere {
    sphere(
        vec3(0.3, 0.2, 0.69),
        vec3(0.1, -0.2, 0.05),
        vec3(1.0, 0.5, -2.0),
        0.7,
    )
}

fn wall_with_normal(normal: rsl_vec3) -> rsl_wall {
    rsl_wall {
        point: rsl_vec3::default(),
        normal,
        velocity: vec3(0.1, 0.0, 0.0),
        angular_velocity: vec3(0.0, 0.0, 0.2),
    }
}

fn decompose_wall(s: &rsl_sphere, w: &rsl_wall) -> (i32, rsl_decomposition) {
    let mut d = rsl_decomposition::default();
    // SAFETY: live locals of the right types.
    let status = unsafe { rsl_decompose_wall(s, w, std::ptr::null(), &mut d) };
    (status, d)
}

/// The header: "any non-zero length (it is normalised)". Lengths whose square overflows
/// (above ~1.3e154) or underflows (below ~1.5e-154, subnormal components included) are
/// normalised as well; a normal `s u` whose largest component is `s` gives exactly the
/// unit normal of `u` (its components divide to exact values), so the decomposition and the
/// step are the same bit for bit. Another direction agrees to 4 eps (a rounding or two of
/// each component).
#[test]
fn wall_normals_of_any_finite_nonzero_length_are_accepted() {
    let s = floor_sphere();
    let (status, unit) = decompose_wall(&s, &wall_with_normal(vec3(0.0, 0.0, 1.0)));
    assert_eq!(status, RSL_OK);
    let (status, tilted) = decompose_wall(&s, &wall_with_normal(vec3(0.0, 1.0, 1.0)));
    assert_eq!(status, RSL_OK);
    let m = sliding_model(RSL_PRESET_OBJECTIVE);
    let wall_step = |w: &rsl_wall| {
        let (mut state, mut out) = (rsl_contact_state::default(), rsl_contact_loads::default());
        // SAFETY: every pointer is to a live local of the right type; none overlap.
        let status =
            unsafe { rsl_contact_step_wall(m.0, &s, w, &input(10.0), &mut state, &mut out) };
        (status, format!("{state:?} {out:?}"))
    };
    let (status, unit_step) = wall_step(&wall_with_normal(vec3(0.0, 0.0, 1.0)));
    assert_eq!(status, RSL_OK);
    for scale in [
        f64::MAX,
        1e308,
        1e200,
        2e154,
        1e-160,
        1e-200,
        1e-310,
        1e-320,
        f64::from_bits(1), // the smallest subnormal
    ] {
        let (status, d) = decompose_wall(&s, &wall_with_normal(vec3(0.0, 0.0, scale)));
        assert_eq!(status, RSL_OK, "normal (0, 0, {scale:e}): {}", last_error());
        assert_eq!(format!("{d:?}"), format!("{unit:?}"), "(0, 0, {scale:e})");
        let (status, d) = decompose_wall(&s, &wall_with_normal(vec3(0.0, scale, scale)));
        assert_eq!(status, RSL_OK, "normal (0, {scale:e}, {scale:e})");
        assert_eq!(
            format!("{d:?}"),
            format!("{tilted:?}"),
            "(0, s, s), s = {scale:e}"
        );
        let (status, step) = wall_step(&wall_with_normal(vec3(0.0, 0.0, scale)));
        assert_eq!(
            status,
            RSL_OK,
            "step, normal (0, 0, {scale:e}): {}",
            last_error()
        );
        assert_eq!(step, unit_step, "step, normal (0, 0, {scale:e})");
    }
    // A direction whose components do not divide exactly: within 4 eps.
    let u = vec3(0.3, -0.2, 1.0);
    let (_, reference) = decompose_wall(&s, &wall_with_normal(u));
    for scale in [1e300, 1e-300] {
        let (status, d) = decompose_wall(
            &s,
            &wall_with_normal(vec3(u.x * scale, u.y * scale, u.z * scale)),
        );
        assert_eq!(status, RSL_OK, "scale {scale:e}: {}", last_error());
        assert_close(&d.normal, reference.normal, 4.0 * EPS, "normal");
    }
    // Zero is still refused.
    let (status, _) = decompose_wall(&s, &wall_with_normal(rsl_vec3::default()));
    assert_eq!(status, RSL_ERR_INVALID_ARGUMENT);
    assert!(last_error().contains("wall normal"), "{}", last_error());
}

/// `l2` enters the coupled bound only as `l2^2 / I2`: with `inertia2` = +INFINITY (a wall)
/// it is not read (any value, even NaN or the +inf of a wall's `branch2`, gives the bits of
/// `l2` = 0.2), as the header says; with a finite `inertia2` it is checked.
#[test]
fn coupled_time_step_reads_l2_only_for_a_finite_inertia2() {
    let bound = |inertia2: f64, l2: f64| {
        let mut dt = -1.0;
        // SAFETY: `dt` is a live local.
        let status = unsafe {
            rsl_coupled_critical_time_step(
                100.0,
                4.0,
                1.0,
                f64::INFINITY,
                0.5,
                inertia2,
                0.3,
                l2,
                &mut dt,
            )
        };
        (status, dt)
    };
    let (status, wall) = bound(f64::INFINITY, 0.2);
    assert_eq!(status, RSL_OK);
    // 2/sqrt(100 (1 + 0.3^2/0.5) + 4 (1/0.5)) = 2/sqrt(126).
    assert!((wall - 2.0 / 126f64.sqrt()).abs() <= 4.0 * EPS * wall);
    for l2 in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 0.0, 1e300] {
        let (status, dt) = bound(f64::INFINITY, l2);
        assert_eq!(status, RSL_OK, "wall, l2 = {l2}: {}", last_error());
        assert_eq!(dt.to_bits(), wall.to_bits(), "wall, l2 = {l2}");
    }
    for (l2, expected) in [
        (f64::NAN, RSL_ERR_NON_FINITE),
        (f64::INFINITY, RSL_ERR_NON_FINITE),
        (f64::NEG_INFINITY, RSL_ERR_NON_FINITE),
        (-1.0, RSL_ERR_INVALID_ARGUMENT),
        (0.0, RSL_ERR_INVALID_ARGUMENT),
    ] {
        let (status, dt) = bound(0.25, l2);
        assert_eq!(status, expected, "inertia2 0.25, l2 = {l2}");
        assert_eq!(dt, -1.0, "written on a refusal");
        assert!(last_error().contains("l2"), "{}", last_error());
    }
    // The header documents it (the doc comment of rsl_coupled_critical_time_step).
    let header = include_str!("../../include/rollslide.h");
    let doc = header
        .split("int32_t rsl_coupled_critical_time_step(")
        .next()
        .and_then(|before| before.rsplit(";\n").next())
        .unwrap();
    assert!(
        doc.contains("`l2` is not read when `inertia2` is +INFINITY"),
        "header doc: {doc}"
    );
}

/// A NULL or misaligned `contact` (the input struct) is reported under the parameter's name
/// in the header, `contact`, by each of the four contact steps.
#[test]
fn a_bad_contact_pointer_is_reported_as_contact() {
    let m = sliding_model(RSL_PRESET_OBJECTIVE);
    let (b1, b2) = reported_pair(vec3(0.0, 0.0, 1.0));
    let wall = wall_with_normal(vec3(0.0, 0.0, 1.0));
    let s = floor_sphere();
    let buffer = [0u64; 32];
    // Never dereferenced: every step refuses it before reading.
    let misaligned = (buffer.as_ptr() as *const u8).wrapping_add(1) as *const rsl_contact_input;
    for (contact, status, message) in [
        (
            std::ptr::null(),
            RSL_ERR_NULL_POINTER,
            "null pointer: contact",
        ),
        (
            misaligned,
            RSL_ERR_MISALIGNED,
            "misaligned pointer: contact",
        ),
    ] {
        let mut state = rsl_contact_state::default();
        let mut out = rsl_contact_loads::default();
        let mut acc = [rsl_vec3::default(); 4];
        let [f1, t1, f2, t2] = &mut acc;
        // SAFETY: every other pointer is to a live local of the right type; `contact` is
        // NULL or misaligned, which each function checks before reading it. Each message is
        // read right after its call (a tuple evaluates left to right).
        let results = unsafe {
            [
                (
                    rsl_contact_step(m.0, &b1, &b2, contact, &mut state, &mut out),
                    last_error(),
                ),
                (
                    rsl_contact_step_accumulate(m.0, &b1, &b2, contact, &mut state, f1, t1, f2, t2),
                    last_error(),
                ),
                (
                    rsl_contact_step_wall(m.0, &s, &wall, contact, &mut state, &mut out),
                    last_error(),
                ),
                (
                    rsl_contact_step_wall_accumulate(m.0, &s, &wall, contact, &mut state, f1, t1),
                    last_error(),
                ),
            ]
        };
        for (k, (got_status, got_message)) in results.iter().enumerate() {
            assert_eq!(*got_status, status, "function {k}");
            assert_eq!(got_message, message, "function {k}");
        }
        assert_eq!(state, rsl_contact_state::default(), "state written");
    }
}
