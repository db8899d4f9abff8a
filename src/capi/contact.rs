//! The per-contact step through the C ABI: `rsl_contact_step` (sphere pair) and
//! `rsl_contact_step_wall`, the state the host stores per contact, and the time-step helpers.
#![allow(non_camel_case_types)]

use super::batch::Simd;
use super::model::live_model;
use super::types::{rsl_sphere, rsl_vec3, rsl_wall};
use super::{guard, input, output};
use crate::decompose::{Sphere, Wall};
use crate::error::Error;
use crate::laws::checked::contact_step_wall;
use crate::laws::fast_path::contact_step_pair_fast;
use crate::laws::stability::{coupled_critical_time_step, rotational_critical_time_step};
use crate::laws::step::{ContactState, StepInput, StepOutput};

/// Input flag: use `rsl_contact_input.sliding_stiffness` instead of the model's `k_t`.
pub const RSL_INPUT_SLIDING_STIFFNESS: u32 = 1;
/// Input flag: use `rsl_contact_input.sliding_damping` instead of the model's `gamma_t`.
pub const RSL_INPUT_SLIDING_DAMPING: u32 = 2;
/// Input flag: the setup pass of the preset's code (LAMMPS/YADE/objective: loads from the
/// stored history, no update; LIGGGHTS: one increment, not stored). The state is not written.
pub const RSL_INPUT_SETUP: u32 = 4;
/// Input flag: the limits use `rsl_contact_input.limit_force` (>= 0) instead of `normal_force`
/// (LAMMPS' `Fncrit`, an elastic normal force...).
pub const RSL_INPUT_LIMIT_FORCE: u32 = 8;
/// Input flag: use `rolling_stiffness` (k_r or k_theta by the model's form) for this contact.
pub const RSL_INPUT_ROLLING_STIFFNESS: u32 = 16;
/// Input flag: use `rolling_damping` for this contact.
pub const RSL_INPUT_ROLLING_DAMPING: u32 = 32;
/// Input flag: use `rolling_friction` (mu_r, or eta in the angle form) for this contact.
pub const RSL_INPUT_ROLLING_FRICTION: u32 = 64;
/// Input flag: use `twisting_stiffness` for this contact (sds).
pub const RSL_INPUT_TWISTING_STIFFNESS: u32 = 128;
/// Input flag: use `twisting_damping` for this contact (sds).
pub const RSL_INPUT_TWISTING_DAMPING: u32 = 256;
/// Input flag: use `twisting_friction` (mu_tw, a length) for this contact (sds).
pub const RSL_INPUT_TWISTING_FRICTION: u32 = 512;

/// Slip flag: the sliding limit was reached this step.
pub const RSL_SLIP_SLIDING: u32 = 1;
/// Slip flag: the rolling limit was reached (cdt: the moment was active) this step.
pub const RSL_SLIP_ROLLING: u32 = 2;
/// Slip flag: the twisting limit was reached this step.
pub const RSL_SLIP_TWISTING: u32 = 4;

/// The history a host stores for each contact: plain data, copy it freely. All bytes zero
/// (`rsl_contact_state_init` or memset) is a fresh contact.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_state {
    /// Sliding spring `xi_s` (length, tangential). YADE preset: the elastic shear force on body 1.
    pub sliding_spring: rsl_vec3,
    /// Rolling spring: `xi_r` (length) in the length form, `theta_r` (rad) in the angle form.
    /// YADE and LIGGGHTS presets: the elastic rolling moment on body 1 (their codes store it).
    pub rolling_spring: rsl_vec3,
    /// Twisting angle `theta_tw` (rad). YADE preset: its twisting moment along the previous normal.
    pub twisting_angle: f64,
    /// YADE preset only: the part of its vector twisting moment off the previous normal (YADE
    /// transports the twisting moment as a vector); zero for every other model.
    pub twisting_offaxis: rsl_vec3,
    /// Normal of the previous step (zero before the first step).
    pub previous_normal: rsl_vec3,
    /// `RSL_SLIP_*` bits of the last step (information only; not read by the library).
    pub slip_flags: u32,
    /// Padding; keep 0.
    pub reserved: u32,
}

/// Per-call inputs of a contact step. Zero-initialise it and set what the model needs:
/// `normal_force` and `dt` always.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_input {
    /// Normal force magnitude `f_n` (compressive positive, >= 0): applied to both bodies and
    /// used by every limit.
    pub normal_force: f64,
    /// Time step (> 0).
    pub dt: f64,
    /// Normal stiffness `k_n` (force/length): needed by EPSD-derived rolling stiffness and
    /// LIGGGHTS' cdt.
    pub normal_stiffness: f64,
    /// Contact radius `a` for Marshall twisting; 0 means `sqrt(delta R_eff)`.
    pub contact_radius: f64,
    /// Mass of body 1 (damping-ratio rolling damping only).
    pub mass1: f64,
    /// Mass of body 2 (ignored for walls); +INFINITY for a fixed body.
    pub mass2: f64,
    /// Moment of inertia of body 1 (damping-ratio rolling damping only).
    pub inertia1: f64,
    /// Moment of inertia of body 2 (ignored for walls); +INFINITY for a fixed body.
    pub inertia2: f64,
    /// Per-contact `k_t`, used with `RSL_INPUT_SLIDING_STIFFNESS`.
    pub sliding_stiffness: f64,
    /// Per-contact `gamma_t`, used with `RSL_INPUT_SLIDING_DAMPING`.
    pub sliding_damping: f64,
    /// Force used by the limits, with `RSL_INPUT_LIMIT_FORCE`.
    pub limit_force: f64,
    /// Per-contact rolling stiffness, with `RSL_INPUT_ROLLING_STIFFNESS`.
    pub rolling_stiffness: f64,
    /// Per-contact rolling damping, with `RSL_INPUT_ROLLING_DAMPING`.
    pub rolling_damping: f64,
    /// Per-contact rolling limit coefficient, with `RSL_INPUT_ROLLING_FRICTION` (+INFINITY: no limit).
    pub rolling_friction: f64,
    /// Per-contact twisting stiffness, with `RSL_INPUT_TWISTING_STIFFNESS`.
    pub twisting_stiffness: f64,
    /// Per-contact twisting damping, with `RSL_INPUT_TWISTING_DAMPING`.
    pub twisting_damping: f64,
    /// Per-contact twisting limit length, with `RSL_INPUT_TWISTING_FRICTION` (+INFINITY: no limit).
    pub twisting_friction: f64,
    /// OR of `RSL_INPUT_*`.
    pub flags: u32,
    /// Padding; keep 0.
    pub reserved: u32,
}

/// Energy terms of one step (load times length; 0 unless the model tracks energy).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_energy {
    /// Elastic energy in the sliding spring after the step.
    pub elastic_sliding: f64,
    /// Elastic energy in the rolling spring after the step.
    pub elastic_rolling: f64,
    /// Elastic energy in the twisting spring after the step.
    pub elastic_twisting: f64,
    /// Dissipated by the sliding dashpot this step.
    pub dashpot_sliding: f64,
    /// Dissipated by the rolling dashpot (viscous law included) this step.
    pub dashpot_rolling: f64,
    /// Dissipated by the twisting dashpot this step.
    pub dashpot_twisting: f64,
    /// Dissipated by the sliding slider (friction) this step.
    pub slider_sliding: f64,
    /// Dissipated by the rolling slider (cdt included) this step.
    pub slider_rolling: f64,
    /// Dissipated by the twisting slider this step.
    pub slider_twisting: f64,
    /// Change of elastic energy caused by transporting the springs this step (0 to rounding
    /// for exact and project-rescale transport).
    pub transport: f64,
}

/// Loads of one contact step. Body 2 receives `-force1` and `torque2`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_loads {
    /// Force on body 1: `-f_n n + F_t`.
    pub force1: rsl_vec3,
    /// Torque on body 1 about its centre.
    pub torque1: rsl_vec3,
    /// Torque on body 2 about its centre (wall: about the contact point).
    pub torque2: rsl_vec3,
    /// Sliding force `F_t` on body 1.
    pub sliding_force: rsl_vec3,
    /// Rolling moment on body 1 (body 2 gets its opposite).
    pub rolling_moment: rsl_vec3,
    /// Twisting torque on body 1, `M_tw n` (YADE preset: its vector twisting moment); body 2
    /// gets the opposite.
    pub twisting_torque: rsl_vec3,
    /// Energy terms.
    pub energy: rsl_contact_energy,
    /// `RSL_SLIP_*` bits.
    pub slip_flags: u32,
    /// Padding.
    pub reserved: u32,
}

impl From<&rsl_contact_state> for ContactState<f64> {
    fn from(s: &rsl_contact_state) -> Self {
        ContactState {
            sliding_spring: s.sliding_spring.into(),
            rolling_spring: s.rolling_spring.into(),
            twisting_angle: s.twisting_angle,
            twisting_offaxis: s.twisting_offaxis.into(),
            previous_normal: s.previous_normal.into(),
        }
    }
}

#[inline(always)]
fn step_input(i: &rsl_contact_input) -> Result<StepInput<f64>, Error> {
    let known = RSL_INPUT_SLIDING_STIFFNESS
        | RSL_INPUT_SLIDING_DAMPING
        | RSL_INPUT_SETUP
        | RSL_INPUT_LIMIT_FORCE
        | RSL_INPUT_ROLLING_STIFFNESS
        | RSL_INPUT_ROLLING_DAMPING
        | RSL_INPUT_ROLLING_FRICTION
        | RSL_INPUT_TWISTING_STIFFNESS
        | RSL_INPUT_TWISTING_DAMPING
        | RSL_INPUT_TWISTING_FRICTION;
    if i.flags & !known != 0 {
        return Err(Error::InvalidArgument(format!(
            "input flags 0x{:x} has unknown bits",
            i.flags
        )));
    }
    let flag = |f: u32| i.flags & f != 0;
    Ok(StepInput {
        normal_force: i.normal_force,
        dt: i.dt,
        normal_stiffness: i.normal_stiffness,
        contact_radius: i.contact_radius,
        mass1: i.mass1,
        mass2: i.mass2,
        inertia1: i.inertia1,
        inertia2: i.inertia2,
        sliding_stiffness: flag(RSL_INPUT_SLIDING_STIFFNESS).then_some(i.sliding_stiffness),
        sliding_damping: flag(RSL_INPUT_SLIDING_DAMPING).then_some(i.sliding_damping),
        limit_force: flag(RSL_INPUT_LIMIT_FORCE).then_some(i.limit_force),
        rolling_stiffness: flag(RSL_INPUT_ROLLING_STIFFNESS).then_some(i.rolling_stiffness),
        rolling_damping: flag(RSL_INPUT_ROLLING_DAMPING).then_some(i.rolling_damping),
        rolling_friction: flag(RSL_INPUT_ROLLING_FRICTION).then_some(i.rolling_friction),
        twisting_stiffness: flag(RSL_INPUT_TWISTING_STIFFNESS).then_some(i.twisting_stiffness),
        twisting_damping: flag(RSL_INPUT_TWISTING_DAMPING).then_some(i.twisting_damping),
        twisting_friction: flag(RSL_INPUT_TWISTING_FRICTION).then_some(i.twisting_friction),
        setup: flag(RSL_INPUT_SETUP),
    })
}

#[inline(always)]
fn slip_bits(o: &StepOutput<f64>) -> u32 {
    let mut bits = 0;
    for (slipped, bit) in
        o.slipped
            .iter()
            .zip([RSL_SLIP_SLIDING, RSL_SLIP_ROLLING, RSL_SLIP_TWISTING])
    {
        if *slipped {
            bits |= bit;
        }
    }
    bits
}

#[inline(always)]
fn to_c(o: &StepOutput<f64>) -> rsl_contact_loads {
    let e = &o.energy;
    rsl_contact_loads {
        force1: o.loads.force1.into(),
        torque1: o.loads.torque1.into(),
        torque2: o.loads.torque2.into(),
        sliding_force: o.sliding_force.into(),
        rolling_moment: o.rolling_moment.into(),
        twisting_torque: o.twisting_torque.into(),
        energy: rsl_contact_energy {
            elastic_sliding: e.sliding.elastic,
            elastic_rolling: e.rolling.elastic,
            elastic_twisting: e.twisting.elastic,
            dashpot_sliding: e.sliding.dashpot,
            dashpot_rolling: e.rolling.dashpot,
            dashpot_twisting: e.twisting.dashpot,
            slider_sliding: e.sliding.slider,
            slider_rolling: e.rolling.slider,
            slider_twisting: e.twisting.slider,
            transport: e.transport,
        },
        slip_flags: slip_bits(o),
        reserved: 0,
    }
}

#[inline(always)]
fn store(state: &mut rsl_contact_state, s: &ContactState<f64>, slip: u32) {
    state.sliding_spring = s.sliding_spring.into();
    state.rolling_spring = s.rolling_spring.into();
    state.twisting_angle = s.twisting_angle;
    state.twisting_offaxis = s.twisting_offaxis.into();
    state.previous_normal = s.previous_normal.into();
    state.slip_flags = slip;
}

/// Resets a contact state to a fresh contact (all zero).
///
/// # Safety
/// `state` must be NULL or point to a writable `rsl_contact_state`.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_state_init(state: *mut rsl_contact_state) -> i32 {
    guard(|| {
        // SAFETY: NULL and alignment checked; writability is the caller's contract.
        let s = unsafe { output(state, "state")? };
        *s = rsl_contact_state::default();
        Ok(())
    })
}

/// The whole of `rsl_contact_step` after the pointer checks: input conversion, the fast path
/// ([`contact_step_pair_fast`]), the output and the state write, in one function so that no
/// intermediate result is copied. Built with AVX2 when the CPU has it (Rust never contracts to
/// FMA, so the bits are the same): measured, the heap demo (generic scene: Marshall twisting)
/// 9.3-9.4 s against 10.3-11.3 s for the SSE2 build; the benchmark's LAMMPS scene 79-81
/// against 81 ns per call in cache.
fn pair_step(
    m: &super::model::rsl_model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    out: &mut rsl_contact_loads,
) -> Result<(), Error> {
    #[cfg(target_arch = "x86_64")]
    if Simd::Avx2.available() {
        // SAFETY: the CPU supports AVX2 and FMA (checked on the line above), the only
        // requirement of a `#[target_feature(enable = "avx2,fma")]` function.
        return unsafe { pair_step_avx2(m, body1, body2, input, state, out) };
    }
    pair_step_body(m, body1, body2, input, state, out)
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn pair_step_avx2(
    m: &super::model::rsl_model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    out: &mut rsl_contact_loads,
) -> Result<(), Error> {
    pair_step_body(m, body1, body2, input, state, out)
}

#[inline(always)]
fn pair_step_body(
    m: &super::model::rsl_model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    out: &mut rsl_contact_loads,
) -> Result<(), Error> {
    let step = step_input(input)?;
    let mut s = ContactState::from(&*state);
    let o = contact_step_pair_fast(
        &m.model,
        m.scene,
        &Sphere::from(body1),
        &Sphere::from(body2),
        &step,
        &mut s,
    )?;
    let loads = to_c(&o);
    if !step.setup || m.model.preset.conventions().setup.store {
        store(state, &s, loads.slip_flags);
    }
    *out = loads;
    Ok(())
}

/// Steps one sphere-sphere contact: transports the springs, computes the rates, steps the
/// model's sliding, rolling and twisting laws, and writes the loads on both bodies to `*out`.
/// `*state` and `*out` are written only on `RSL_OK` (with `RSL_INPUT_SETUP`, `*state` only
/// where the preset's code writes it at setup: LAMMPS).
///
/// Errors: those of `rsl_decompose`, `RSL_ERR_INVALID_HANDLE`, `RSL_ERR_INVALID_TIME_STEP`,
/// `RSL_ERR_NEGATIVE_NORMAL_FORCE`, `RSL_ERR_INVALID_ARGUMENT` (an input the model needs is
/// missing or out of range, unknown flag), `RSL_ERR_NON_FINITE` (also for a non-finite state).
///
/// # Safety
/// Every pointer must be valid for its type during the call; `state` and `out` must not
/// overlap each other or the inputs. The model must not be modified during the call.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_step(
    model: *const super::model::rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; every helper checks NULL and alignment.
        let (m, b1, b2, inp, st, out) = unsafe {
            (
                live_model(model)?,
                input(body1, "body1")?,
                input(body2, "body2")?,
                input(contact, "input")?,
                output(state, "state")?,
                output(out, "out")?,
            )
        };
        Ok(pair_step(m, b1, b2, inp, st, out)?)
    })
}

/// Steps one sphere-wall contact (body 2 is the wall); as `rsl_contact_step`.
///
/// # Safety
/// As `rsl_contact_step`.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_step_wall(
    model: *const super::model::rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; every helper checks NULL and alignment.
        let (m, s1, w, inp, st, out) = unsafe {
            (
                live_model(model)?,
                input(sphere, "sphere")?,
                input(wall, "wall")?,
                input(contact, "input")?,
                output(state, "state")?,
                output(out, "out")?,
            )
        };
        let step = step_input(inp)?;
        let mut s = ContactState::from(&*st);
        let o = contact_step_wall(&m.model, &Sphere::from(s1), &Wall::from(w), &step, &mut s)?;
        let loads = to_c(&o);
        if !step.setup || m.model.preset.conventions().setup.store {
            store(st, &s, loads.slip_flags);
        }
        *out = loads;
        Ok(())
    })
}

/// Critical time step of velocity Verlet for a rotational spring-dashpot (models.md section 5):
/// `dt_c = (2/w0)(sqrt(1 + z^2) - z)`, `w0 = sqrt(k_theta (1/I1 + 1/I2))`. `inertia2` may be
/// +INFINITY for a wall. Writes `*out` on success.
///
/// # Safety
/// `out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn rsl_rotational_critical_time_step(
    k_theta: f64,
    inertia1: f64,
    inertia2: f64,
    damping_ratio: f64,
    out: *mut f64,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract.
        let out = unsafe { output(out, "out")? };
        *out = rotational_critical_time_step(k_theta, inertia1, inertia2, damping_ratio)?;
        Ok(())
    })
}

/// Stable step bound with sliding and rotational springs coupled (models.md section 5):
/// `2/sqrt(k_t (1/m1 + 1/m2 + l1^2/I1 + l2^2/I2) + k_theta (1/I1 + 1/I2))`. Body 2's mass and
/// inertia may be +INFINITY for a wall. Writes `*out` on success.
///
/// # Safety
/// `out` must be NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn rsl_coupled_critical_time_step(
    k_t: f64,
    k_theta: f64,
    mass1: f64,
    mass2: f64,
    inertia1: f64,
    inertia2: f64,
    l1: f64,
    l2: f64,
    out: *mut f64,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract.
        let out = unsafe { output(out, "out")? };
        *out = coupled_critical_time_step(k_t, k_theta, mass1, mass2, inertia1, inertia2, l1, l2)?;
        Ok(())
    })
}
