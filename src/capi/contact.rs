//! The per-contact step through the C ABI: `rsl_contact_step` (sphere pair) and
//! `rsl_contact_step_wall`, the state the host stores per contact, and the time-step helpers.
#![allow(non_camel_case_types)]

use super::batch::Simd;
#[cfg(target_arch = "x86_64")]
use super::finite::Avx2;
use super::finite::{FiniteTest, Portable};
use super::model::live_model;
use super::status::FfiError;
use super::types::{rsl_sphere, rsl_vec3, rsl_wall};
use super::{checked_pointer, guard, guard_status, input, output};
use crate::decompose::{Sphere, Wall};
use crate::error::Error;
use crate::laws::checked::{contact_step_pair, contact_step_wall};
use crate::laws::fast_path::{step_outputs_finite, step_pair_if_valid};
use crate::laws::model::Model;
use crate::laws::stability::{coupled_critical_time_step, rotational_critical_time_step};
use crate::laws::step::{ContactState, StepInput, StepOutput};
use crate::laws::swap::mirror_state;

/// Input flag: use `rsl_contact_input.sliding_stiffness` instead of the model's `k_t`.
pub const RSL_INPUT_SLIDING_STIFFNESS: u32 = 1;
/// Input flag: use `rsl_contact_input.sliding_damping` instead of the model's `gamma_t`.
pub const RSL_INPUT_SLIDING_DAMPING: u32 = 2;
/// Input flag: this call is the setup pass that LAMMPS and LIGGGHTS make at the start of every
/// `run` command (before its first time step); a host reproducing them sets it on that call
/// only.
/// LAMMPS_2021: loads from the stored springs, no increment; its clip may still write the state.
/// LIGGGHTS_3_8: one rolling increment in the loads, nothing stored. YADE has no setup pass (its
/// first step already increments): a YADE host never sets the flag. For the objective and YADE
/// presets the flag gives the loads of the stored springs and leaves the state unwritten.
pub const RSL_INPUT_SETUP: u32 = 4;
/// Input flag: the limits use `rsl_contact_input.limit_force` (>= 0) instead of the preset's
/// rule on `normal_force`: e.g. LAMMPS' `Fncrit` (`|F_ne + 2 F_pulloff|` with its JKR model,
/// `|F_ne|` with DMT in LAMMPS 20220106), an elastic normal force, the compressive part plus a
/// cohesive offset.
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
/// Input flag: the contact is a cohesive bond with shear adhesion
/// `rsl_contact_input.shear_adhesion` (a force, at least 0): the sliding limit becomes
/// `max(0, shear_adhesion + mu F)`, `mu` the model's sliding friction. `F` is `limit_force`
/// with `RSL_INPUT_LIMIT_FORCE`; else, for YADE_2023, the signed `normal_force` (YADE 2023.02a
/// CohFrict's `shearAdhesion + Fn tan(phi)`, lowered by tension), and for the other presets
/// the force their limits use (`max(f_n, 0)` objective, `|f_n|` LAMMPS_2021 and LIGGGHTS_3_8).
/// With YADE_2023 and without `RSL_INPUT_LIMIT_FORCE`, as CohFrict does: the rolling and
/// twisting limits use `|f_n|` (also under tension), and in a step where the sliding limit is
/// reached while `f_n < 0` the normal force is not applied (`force1` has no normal part) and
/// the rolling and twisting limits are 0. The other limits are unchanged. The normal law is the
/// host's (CohFrict: `kn (un - unp)`, its normal plasticity at `-normalAdhesion`, and the end of
/// the contact when a fragile bond pulls harder than `normalAdhesion`). Not covered: CohFrict's
/// `cohesionDisablesFriction` (sliding limit `shearAdhesion` alone).
pub const RSL_INPUT_SHEAR_ADHESION: u32 = 1024;
/// Input flag (only with `RSL_INPUT_SHEAR_ADHESION`): the bond is fragile (YADE's `fragile`).
/// When the trial sliding load exceeds the adhesive limit, the bond breaks in this step: the
/// limit is recomputed without the adhesion (`mu F`, the limit without
/// `RSL_INPUT_SHEAR_ADHESION`) and the trial is clipped to it, and `RSL_SLIP_BOND_BROKEN` is
/// reported. The host then drops the bond's adhesions (its normal one included) for every later
/// step of this contact: it clears both flags. The library keeps no bond state.
pub const RSL_INPUT_FRAGILE_BOND: u32 = 2048;

/// Slip flag: the sliding limit was reached this step.
pub const RSL_SLIP_SLIDING: u32 = 1;
/// Slip flag: the rolling limit was reached (cdt: the moment was active) this step.
pub const RSL_SLIP_ROLLING: u32 = 2;
/// Slip flag: the twisting limit was reached this step.
pub const RSL_SLIP_TWISTING: u32 = 4;
/// Slip flag: a fragile bond (`RSL_INPUT_FRAGILE_BOND`) broke this step (with
/// `RSL_SLIP_SLIDING`); step the contact without its adhesion from now on.
pub const RSL_SLIP_BOND_BROKEN: u32 = 8;

/// The history a host stores for each contact: plain data, copy it freely. All bytes zero
/// (`rsl_contact_state_init` or memset) is a fresh contact.
///
/// The host decides when a contact begins and ends; the library steps any pair it is given,
/// touching or not (a cohesive contact keeps acting past first separation, and only the host
/// knows its law). When the host ends a contact (the pair no longer overlaps, or leaves the
/// neighbour list, or a cohesive bond breaks), it resets the state, as LAMMPS, LIGGGHTS and
/// YADE drop a contact's history: otherwise the stored springs act again, with their old
/// loads, when the pair touches later. The overlap is the host's own (it computed `f_n` from
/// it), or `rsl_decomposition.overlap` (negative once the spheres separate).
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
    /// Normal force `f_n`, signed: compressive positive, tensile (cohesive, or a dashpot pulling
    /// during unloading) negative. Applied to both bodies as given (body 1 gets `-f_n n`, body
    /// 2 `+f_n n`). The limits use `limit_force` with `RSL_INPUT_LIMIT_FORCE`, else the
    /// preset's rule: `max(f_n, 0)` for the objective and YADE_2023 presets (no friction while
    /// the contact pulls, as YADE without adhesion), `|f_n|` for LAMMPS_2021 and LIGGGHTS_3_8
    /// (LAMMPS' `Fncrit` of its non-cohesive models, LIGGGHTS' `|Fn|`).
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
    /// Force used by the limits (>= 0), with `RSL_INPUT_LIMIT_FORCE`. +INFINITY: no limit
    /// (every limit is infinite, except that a zero coefficient still gives a zero limit);
    /// refused with `RSL_ERR_INVALID_ARGUMENT` for the cdt rolling law outside LIGGGHTS_3_8,
    /// whose moment is `mu_r R_r` times this force.
    pub limit_force: f64,
    /// Per-contact rolling stiffness, with `RSL_INPUT_ROLLING_STIFFNESS`.
    pub rolling_stiffness: f64,
    /// Per-contact rolling damping, with `RSL_INPUT_ROLLING_DAMPING`.
    pub rolling_damping: f64,
    /// Per-contact rolling limit coefficient, with `RSL_INPUT_ROLLING_FRICTION` (+INFINITY: no
    /// limit, even at zero force). Refused with `RSL_ERR_INVALID_ARGUMENT` where it is not a
    /// limit: for cdt (it sets the moment) and for the `RSL_STIFFNESS_EPSD`/`EPSD3` rules
    /// without `RSL_INPUT_ROLLING_STIFFNESS` (they derive the stiffness from it).
    pub rolling_friction: f64,
    /// Per-contact twisting stiffness, with `RSL_INPUT_TWISTING_STIFFNESS`.
    pub twisting_stiffness: f64,
    /// Per-contact twisting damping, with `RSL_INPUT_TWISTING_DAMPING`.
    pub twisting_damping: f64,
    /// Per-contact twisting limit length, with `RSL_INPUT_TWISTING_FRICTION` (+INFINITY: no
    /// limit, even at zero force).
    pub twisting_friction: f64,
    /// Shear adhesion of a cohesive bond (force, >= 0; +INFINITY: no sliding limit while
    /// bonded), with `RSL_INPUT_SHEAR_ADHESION`: added to the sliding limit (see the flag). YADE
    /// CohFrict: the contact's `shearAdhesion`, `shearCohesion min(R1, R2)^2`. Added in 0.2.0
    /// (the struct grew by 8 bytes).
    pub shear_adhesion: f64,
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
        | RSL_INPUT_TWISTING_FRICTION
        | RSL_INPUT_SHEAR_ADHESION
        | RSL_INPUT_FRAGILE_BOND;
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
        sliding_friction: None,
        limit_force: flag(RSL_INPUT_LIMIT_FORCE).then_some(i.limit_force),
        rolling_stiffness: flag(RSL_INPUT_ROLLING_STIFFNESS).then_some(i.rolling_stiffness),
        rolling_damping: flag(RSL_INPUT_ROLLING_DAMPING).then_some(i.rolling_damping),
        rolling_friction: flag(RSL_INPUT_ROLLING_FRICTION).then_some(i.rolling_friction),
        twisting_stiffness: flag(RSL_INPUT_TWISTING_STIFFNESS).then_some(i.twisting_stiffness),
        twisting_damping: flag(RSL_INPUT_TWISTING_DAMPING).then_some(i.twisting_damping),
        twisting_friction: flag(RSL_INPUT_TWISTING_FRICTION).then_some(i.twisting_friction),
        shear_adhesion: flag(RSL_INPUT_SHEAR_ADHESION).then_some(i.shear_adhesion),
        fragile_bond: flag(RSL_INPUT_FRAGILE_BOND),
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
    if o.bond_broken {
        bits |= RSL_SLIP_BOND_BROKEN;
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

/// Resets a contact state to a fresh contact (all zero): call it when the contact ends (see
/// `rsl_contact_state`), or on a new contact's state before its first step.
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

/// Mirrors a contact's state for the same contact with its two bodies exchanged: after
/// `rsl_contact_state_swap(model, &s)`, stepping `(body2, body1)` from `s` gives the mirror of
/// stepping `(body1, body2)` from the original state (the force on the new body 1 is the old
/// `-force1`, the new `torque1` and `torque2` are the old `torque2` and `torque1`), and the new
/// state is again the mirror of the other order's, step after step. Use it when a host meets
/// a stored pair in the other order (a neighbour list rebuilt with the bodies exchanged, a
/// parallel host computing the pair from the other body's side). Applying it twice gives the
/// state back bit for bit.
///
/// The rule (`model` gives the rolling form): `sliding_spring` negated (it integrates the
/// sliding velocity of body 1 relative to body 2, which changes sign; YADE preset: the shear
/// force on body 1); `rolling_spring` kept in the length form (`xi_r` integrates
/// `v_r = R_r (w1 - w2) x n`, where both factors change sign) and negated in the angle form
/// (`theta_r` integrates `(w1 - w2)_t`; YADE and LIGGGHTS presets: the moment on body 1);
/// `twisting_angle` kept (`(w1 - w2) . n` is unchanged; YADE preset: the moment on body 1 along
/// the previous normal, which flips too); `twisting_offaxis` negated; `previous_normal`
/// negated (the normal points from body 1 to body 2); `slip_flags` kept. Negating every
/// field, as LAMMPS 20220106 does to its history when a pair's order changes, reverses the
/// rolling and twisting springs of the length form: wrong.
///
/// Any values are mirrored as they are (no finiteness check: the step checks the state).
/// `*state` is written only on `RSL_OK`. Errors: `RSL_ERR_NULL_POINTER`, `RSL_ERR_MISALIGNED`,
/// `RSL_ERR_INVALID_HANDLE`.
///
/// # Safety
/// `model` must be NULL or a live model not modified during the call; `state` must be NULL or
/// point to a writable `rsl_contact_state`.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_state_swap(
    model: *const super::model::rsl_model,
    state: *mut rsl_contact_state,
) -> i32 {
    guard(|| {
        // SAFETY: NULL, alignment and the handle's magic checked; liveness is the caller's
        // contract.
        let m = unsafe { live_model(model)? };
        // SAFETY: NULL and alignment checked; writability is the caller's contract.
        let s = unsafe { output(state, "state")? };
        let mirrored = mirror_state(&m.model, &ContactState::<f64>::from(&*s));
        let slip = s.slip_flags;
        store(s, &mirrored, slip);
        Ok(())
    })
}

/// Where a successful per-contact step's loads go: the caller's `rsl_contact_loads`
/// ([`LoadsOut`]) or the bodies' force and torque accumulators ([`Accumulators`],
/// [`SphereAccumulators`]).
pub(crate) trait LoadsSink: Copy {
    /// Called before the step: a hint that the loads will be written here (the accumulators
    /// prefetch their cache lines, so that the host's scattered force array misses while the
    /// step computes, not after it).
    fn expect(self);
    /// Writes the loads of a successful step. Called at most once, after every check passed.
    fn deliver(self, loads: &rsl_contact_loads);
}

/// The caller's output struct (`rsl_contact_step`): receives the whole `rsl_contact_loads`.
#[derive(Clone, Copy)]
pub(crate) struct LoadsOut(*mut rsl_contact_loads);

impl LoadsOut {
    /// # Safety
    /// `out` must be non-NULL, aligned, writable and not overlap any input of the step, for
    /// as long as the sink is used.
    unsafe fn new(out: *mut rsl_contact_loads) -> Self {
        LoadsOut(out)
    }
}

impl LoadsSink for LoadsOut {
    #[inline(always)]
    fn expect(self) {}

    #[inline(always)]
    fn deliver(self, loads: &rsl_contact_loads) {
        // SAFETY: `LoadsOut::new`'s contract: a valid, exclusive output.
        unsafe { *self.0 = *loads };
    }
}

/// The force and torque accumulators of both bodies (`rsl_contact_step_accumulate`): body 1
/// gets `+force1` and `+torque1`, body 2 `-force1` and `+torque2`. Raw pointers, so that a
/// host may pass the same accumulator twice (the adds are done in the order force1, torque1,
/// force2, torque2, each reading what the previous wrote).
#[derive(Clone, Copy)]
pub(crate) struct Accumulators {
    force1: *mut rsl_vec3,
    torque1: *mut rsl_vec3,
    force2: *mut rsl_vec3,
    torque2: *mut rsl_vec3,
}

impl Accumulators {
    /// # Safety
    /// Every pointer must be non-NULL, aligned, writable and not overlap any input of the
    /// step (they may equal each other), for as long as the sink is used.
    unsafe fn new(
        force1: *mut rsl_vec3,
        torque1: *mut rsl_vec3,
        force2: *mut rsl_vec3,
        torque2: *mut rsl_vec3,
    ) -> Self {
        Accumulators {
            force1,
            torque1,
            force2,
            torque2,
        }
    }
}

/// Prefetches the (at most two) cache lines of the vector at `p` (24 bytes, 8-aligned: its
/// last 8 bytes, at `p + 16`, lie in one line). A hint only.
#[inline(always)]
fn prefetch_vec3(p: *const rsl_vec3) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch never faults and changes nothing the program can observe, whatever
        // the address (`wrapping_add`: no pointer arithmetic is assumed in bounds).
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(p.cast());
            _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>().wrapping_add(16));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// `*p += v`, or `*p -= v` when `subtract`, through a raw pointer.
///
/// # Safety
/// `p` must be valid for reads and writes of an `rsl_vec3`, not referenced elsewhere meanwhile.
#[inline(always)]
unsafe fn add_to(p: *mut rsl_vec3, v: &rsl_vec3, subtract: bool) {
    // SAFETY: the caller's contract.
    let a = unsafe { &mut *p };
    if subtract {
        (a.x, a.y, a.z) = (a.x - v.x, a.y - v.y, a.z - v.z);
    } else {
        (a.x, a.y, a.z) = (a.x + v.x, a.y + v.y, a.z + v.z);
    }
}

impl LoadsSink for Accumulators {
    #[inline(always)]
    fn expect(self) {
        for p in [self.force1, self.torque1, self.force2, self.torque2] {
            prefetch_vec3(p);
        }
    }

    #[inline(always)]
    fn deliver(self, loads: &rsl_contact_loads) {
        // SAFETY: `Accumulators::new`'s contract; each add is finished (its temporary
        // reference gone) before the next, so equal pointers are fine.
        unsafe {
            add_to(self.force1, &loads.force1, false);
            add_to(self.torque1, &loads.torque1, false);
            add_to(self.force2, &loads.force1, true);
            add_to(self.torque2, &loads.torque2, false);
        }
    }
}

/// The sphere's force and torque accumulators of a sphere-wall contact
/// (`rsl_contact_step_wall_accumulate`): `+force1` and `+torque1`.
#[derive(Clone, Copy)]
pub(crate) struct SphereAccumulators {
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
}

impl SphereAccumulators {
    /// # Safety
    /// As [`Accumulators::new`].
    unsafe fn new(force: *mut rsl_vec3, torque: *mut rsl_vec3) -> Self {
        SphereAccumulators { force, torque }
    }
}

impl LoadsSink for SphereAccumulators {
    #[inline(always)]
    fn expect(self) {}

    #[inline(always)]
    fn deliver(self, loads: &rsl_contact_loads) {
        // SAFETY: `SphereAccumulators::new`'s contract, as for `Accumulators`.
        unsafe {
            add_to(self.force, &loads.force1, false);
            add_to(self.torque, &loads.torque1, false);
        }
    }
}

/// `rsl_contact_step`'s signature: the handle's step on this CPU, which the entry
/// calls in tail position with its own arguments once it has checked them (every pointer
/// non-NULL and 8-aligned, the handle live). The same signature lets the compiler make that
/// call a jump: no second frame, no copy of the arguments.
pub(crate) type OutStep = unsafe extern "C" fn(
    *const super::model::rsl_model,
    *const rsl_sphere,
    *const rsl_sphere,
    *const rsl_contact_input,
    *mut rsl_contact_state,
    *mut rsl_contact_loads,
) -> i32;

/// `rsl_contact_step_accumulate`'s signature, for the same purpose as [`OutStep`] (its last
/// three pointers arrive on the stack, and a jump leaves them where the host put them).
pub(crate) type AccumulateStep = unsafe extern "C" fn(
    *const super::model::rsl_model,
    *const rsl_sphere,
    *const rsl_sphere,
    *const rsl_contact_input,
    *mut rsl_contact_state,
    *mut rsl_vec3,
    *mut rsl_vec3,
    *mut rsl_vec3,
    *mut rsl_vec3,
) -> i32;

/// The per-contact steps on this CPU, one per C entry, kept in the model handle. Each
/// runs the fast path for a plain input and the checked step (which reports) for
/// anything else and anything the fast path refuses, behind the panic boundary.
#[derive(Clone, Copy)]
pub(crate) struct PairSteps {
    /// `rsl_contact_step`.
    pub(crate) out: OutStep,
    /// `rsl_contact_step_accumulate`.
    pub(crate) accumulate: AccumulateStep,
}

/// The per-contact steps (the model handle keeps them), built for AVX2 when this CPU has it
/// (Rust never contracts to FMA, so every build gives the same bits).
///
/// A build with `--cfg rollslide_portable_pair_steps` (in `RUSTFLAGS`) always takes the
/// portable steps: `scripts/sanitizers.sh` uses one under valgrind 3.19, whose decoder rejects
/// an AVX encoding LLVM emits in some AVX2 steps (see that script).
pub(crate) fn pair_steps() -> PairSteps {
    let avx2 = !cfg!(rollslide_portable_pair_steps) && Simd::Avx2.available();
    pair_steps_built(avx2)
}

/// The AVX2 builds of the steps or the portable ones. Only a CPU with AVX2 and FMA may call the
/// AVX2 builds.
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_variables))]
fn pair_steps_built(avx2: bool) -> PairSteps {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        return PairSteps {
            out: out_step_avx2,
            accumulate: accumulate_step_avx2,
        };
    }
    PairSteps {
        out: out_step_portable,
        accumulate: accumulate_step_portable,
    }
}

/// [`pair_step_with`] on the entry's checked pointers, behind the panic boundary (the step
/// writes nothing before it succeeds; a panic anywhere, none is known, is reported as
/// `RSL_ERR_INTERNAL`).
///
/// # Safety
/// Every pointer non-NULL and 8-aligned (8 is the alignment of each type, asserted below),
/// valid for its type during the call, `state` not overlapping the inputs; `model` a live
/// handle, not modified during the call; `test` usable on this CPU.
#[inline(always)]
unsafe fn entered_step<F: FiniteTest, K: PairSink>(
    test: F,
    model: *const super::model::rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    sink: K,
) -> i32 {
    // SAFETY: this function's contract.
    let (m, b1, b2, inp, st) = unsafe { (&*model, &*body1, &*body2, &*contact, &mut *state) };
    guard_status(|| pair_step_with::<F, K>(test, m, b1, b2, inp, st, sink))
}

/// The AVX2 and portable builds of one entry's step (`$avx2`, `$portable`): the entry's
/// parameters (`$param`), the sink made from them (`$sink`),
/// [`entered_step`] with the AVX2 or the portable finiteness test.
macro_rules! entry_steps {
    (
        $(#[$doc:meta])*
        $avx2:ident, $portable:ident,
        ($($param:ident: $ty:ty),* $(,)?),
        $sink:expr
    ) => {
        $(#[$doc])*
        ///
        /// The AVX2 build.
        ///
        /// # Safety
        /// As [`entered_step`], the output pointers as the entry requires (checked non-NULL and
        /// aligned, valid, not overlapping the inputs or the state); the CPU must support AVX2
        /// and FMA.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        #[allow(clippy::too_many_arguments)]
        unsafe extern "C" fn $avx2(
            model: *const super::model::rsl_model,
            body1: *const rsl_sphere,
            body2: *const rsl_sphere,
            contact: *const rsl_contact_input,
            state: *mut rsl_contact_state,
            $($param: $ty),*
        ) -> i32 {
            // SAFETY: this function's contract (the CPU has AVX2; the output pointers are
            // valid and exclusive, as the sink requires).
            unsafe {
                let (test, sink) = (Avx2::assume(), $sink);
                entered_step::<_, _>(test, model, body1, body2, contact, state, sink)
            }
        }

        $(#[$doc])*
        ///
        /// The portable build.
        ///
        /// # Safety
        /// As the AVX2 build, on any CPU.
        #[allow(clippy::too_many_arguments)]
        unsafe extern "C" fn $portable(
            model: *const super::model::rsl_model,
            body1: *const rsl_sphere,
            body2: *const rsl_sphere,
            contact: *const rsl_contact_input,
            state: *mut rsl_contact_state,
            $($param: $ty),*
        ) -> i32 {
            // SAFETY: this function's contract (the output pointers are valid and exclusive, as
            // the sink requires).
            unsafe {
                let sink = $sink;
                entered_step::<_, _>(Portable, model, body1, body2, contact, state, sink)
            }
        }
    };
}

entry_steps! {
    /// `rsl_contact_step`'s step, entered from it (see [`OutStep`]).
    out_step_avx2, out_step_portable,
    (out: *mut rsl_contact_loads),
    LoadsOut::new(out)
}

entry_steps! {
    /// `rsl_contact_step_accumulate`'s step, entered from it (see [`AccumulateStep`]).
    accumulate_step_avx2, accumulate_step_portable,
    (force1: *mut rsl_vec3, torque1: *mut rsl_vec3, force2: *mut rsl_vec3, torque2: *mut rsl_vec3),
    Accumulators::new(force1, torque1, force2, torque2)
}

/// The step with the finiteness test `test`: [`fast_pair_step`] for a plain
/// input (`flags == 0`), [`PairSink::step_guarded`] for anything else or anything it refuses.
#[inline(always)]
fn pair_step_with<F: FiniteTest, K: PairSink>(
    test: F,
    m: &super::model::rsl_model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    sink: K,
) -> i32 {
    sink.expect();
    if input.flags == 0 && fast_pair_step::<F, K>(test, &m.model, body1, body2, input, state, sink)
    {
        return super::status::RSL_OK;
    }
    sink.step_guarded(&m.model, body1, body2, input, state)
}

/// A per-contact pair step's sink, with the way back to the checked step for an input the fast
/// path does not take.
pub(crate) trait PairSink: LoadsSink {
    /// [`pair_step_checked`] with its loads delivered here: out of line, cold, and a function
    /// that cannot unwind (see [`out_step_guarded`]).
    fn step_guarded(
        self,
        model: &Model,
        body1: &rsl_sphere,
        body2: &rsl_sphere,
        input: &rsl_contact_input,
        state: &mut rsl_contact_state,
    ) -> i32;
}

impl PairSink for LoadsOut {
    #[inline(always)]
    fn step_guarded(
        self,
        model: &Model,
        body1: &rsl_sphere,
        body2: &rsl_sphere,
        input: &rsl_contact_input,
        state: &mut rsl_contact_state,
    ) -> i32 {
        out_step_guarded(model, body1, body2, input, state, self.0)
    }
}

impl PairSink for Accumulators {
    #[inline(always)]
    fn step_guarded(
        self,
        model: &Model,
        body1: &rsl_sphere,
        body2: &rsl_sphere,
        input: &rsl_contact_input,
        state: &mut rsl_contact_state,
    ) -> i32 {
        let Accumulators {
            force1,
            torque1,
            force2,
            torque2,
        } = self;
        accumulate_step_guarded(
            model, body1, body2, input, state, force1, torque1, force2, torque2,
        )
    }
}

/// [`pair_step_checked`] with its error recorded as the last error, its loads written to
/// `*out` on success, behind its own panic boundary ([`guard`]).
///
/// `extern "C"`, a function that cannot unwind, which the compiler knows: it is the only call
/// the hot steps make (`scripts/check_kernels.sh` checks it), so their own panic boundary
/// ([`guard_status`] in [`entered_step`]) has nothing left to catch in a release build and
/// costs nothing. (With a Rust-ABI call here, the boundary kept its closure's data on the
/// stack in every call.) The sink comes as its pointers, not as a struct, which the hot step
/// would have copied to its stack in every call (C passes a 32-byte struct in memory). A panic
/// inside is caught by `guard`; only one while reporting it (the thread's last-error slot
/// already destroyed) would reach this boundary, where Rust aborts the process.
#[inline(never)]
#[cold]
extern "C" fn out_step_guarded(
    model: &Model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    // SAFETY: `out` came from a `LoadsOut`, whose contract it keeps.
    guarded_checked_step(model, body1, body2, input, state, unsafe {
        LoadsOut::new(out)
    })
}

/// [`out_step_guarded`] for the accumulators of an [`Accumulators`] sink.
#[inline(never)]
#[cold]
#[allow(clippy::too_many_arguments)]
extern "C" fn accumulate_step_guarded(
    model: &Model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    force1: *mut rsl_vec3,
    torque1: *mut rsl_vec3,
    force2: *mut rsl_vec3,
    torque2: *mut rsl_vec3,
) -> i32 {
    // SAFETY: the pointers came from an `Accumulators`, whose contract they keep.
    let sink = unsafe { Accumulators::new(force1, torque1, force2, torque2) };
    guarded_checked_step(model, body1, body2, input, state, sink)
}

/// [`pair_step_checked`] behind [`guard`], its loads delivered to `sink` on success: the body of
/// [`out_step_guarded`] and [`accumulate_step_guarded`].
#[inline(always)]
fn guarded_checked_step<K: LoadsSink>(
    model: &Model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    sink: K,
) -> i32 {
    guard(|| {
        sink.deliver(&pair_step_checked(model, body1, body2, input, state)?);
        Ok(())
    })
}

/// The fast path ([`step_pair_if_valid`]) on a plain input (`flags == 0`),
/// with `test` for the finiteness of the inputs and of the results: on success writes `*state`,
/// delivers the loads to `sink` and returns true; otherwise writes nothing.
#[inline(always)]
fn fast_pair_step<F: FiniteTest, K: LoadsSink>(
    test: F,
    model: &Model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    sink: K,
) -> bool {
    let step = StepInput {
        normal_stiffness: input.normal_stiffness,
        contact_radius: input.contact_radius,
        mass1: input.mass1,
        mass2: input.mass2,
        inertia1: input.inertia1,
        inertia2: input.inertia2,
        ..StepInput::new(input.normal_force, input.dt)
    };
    let finite = test.inputs(body1, body2, input, state);
    let (b1, b2, s) = (
        Sphere::from(body1),
        Sphere::from(body2),
        ContactState::from(&*state),
    );
    let Some((o, next)) = step_pair_if_valid(model, &b1, &b2, &step, &s, finite) else {
        return false;
    };
    // The few results that must be tested, in registers (see `step_outputs_finite`).
    if !step_outputs_finite(model, &o, &next) {
        return false;
    }
    let loads = to_c(&o);
    let mut new_state = *state;
    store(&mut new_state, &next, loads.slip_flags);
    *state = new_state;
    sink.deliver(&loads);
    true
}

/// The per-contact step through the checked step: inputs with overrides, a limit force or the
/// setup pass, and whatever the fast path's quick test did not pass (the checked step gives
/// the precise error). Writes `*state` (where the preset's setup pass does) and returns the
/// loads on success; writes nothing otherwise. Kept out of line so that the fast path keeps its
/// inputs in registers.
#[inline(never)]
#[cold]
fn pair_step_checked(
    model: &Model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
) -> Result<rsl_contact_loads, Error> {
    let (b1, b2) = (Sphere::from(body1), Sphere::from(body2));
    checked_step_with(model, input, state, |i, s| {
        contact_step_pair(model, &b1, &b2, i, s)
    })
}

/// A checked step on the C structs: converts the input (flags included) and the state, runs
/// `step` (the checked pair or wall step of `model`), writes `*state` where the preset's setup
/// pass does (always outside it) and returns the loads; writes nothing on an error.
fn checked_step_with(
    model: &Model,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    step: impl FnOnce(&StepInput<f64>, &mut ContactState<f64>) -> Result<StepOutput<f64>, Error>,
) -> Result<rsl_contact_loads, Error> {
    let step_in = step_input(input)?;
    let mut s = ContactState::from(&*state);
    let loads = to_c(&step(&step_in, &mut s)?);
    if !step_in.setup || model.preset.conventions().setup.store {
        store(state, &s, loads.slip_flags);
    }
    Ok(loads)
}

/// Steps one sphere-sphere contact: transports the springs, computes the rates, steps the
/// model's sliding, rolling and twisting laws, and writes the loads on both bodies to `*out`.
/// `*state` and `*out` are written only on `RSL_OK` (with `RSL_INPUT_SETUP`, `*state` only
/// where the preset's code writes it at setup: LAMMPS).
///
/// Errors: those of `rsl_decompose`, `RSL_ERR_INVALID_HANDLE`, `RSL_ERR_INVALID_TIME_STEP`,
/// `RSL_ERR_INVALID_ARGUMENT` (an input the model needs is missing or out of range, unknown
/// flag), `RSL_ERR_NON_FINITE` (also for a non-finite state).
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
    let pointers_ok = all_set_and_aligned(&[
        model as usize,
        body1 as usize,
        body2 as usize,
        contact as usize,
        state as usize,
        out as usize,
    ]);
    // SAFETY: `model` is non-NULL and aligned when `pointers_ok`, and points to a handle by
    // this function's contract (`is_live` tells a live model from a freed or foreign one).
    if pointers_ok && unsafe { (*model).is_live() } {
        // SAFETY: the handle's step needs every pointer non-NULL and aligned and a live handle
        // (both tested just above), the rest is this function's contract; it is an AVX2 build
        // only when the CPU has AVX2 and FMA (`pair_steps_for`). A call in tail position with
        // the same arguments: a jump.
        return unsafe { ((*model).pair_steps.out)(model, body1, body2, contact, state, out) };
    }
    // SAFETY: forwarded contract.
    unsafe { out_step_reporting(model, body1, body2, contact, state, out) }
}

/// `rsl_contact_step` for arguments its fast entry did not take: [`pair_step_reporting`]
/// with `out` checked. Out of line, so that the entry keeps no frame of its own.
///
/// # Safety
/// As `rsl_contact_step`.
#[cold]
#[inline(never)]
unsafe fn out_step_reporting(
    model: *const super::model::rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    let sink = || {
        // SAFETY: `out` is checked non-NULL and aligned; writable and not overlapping the
        // inputs by `rsl_contact_step`'s contract.
        Ok(unsafe { LoadsOut::new(checked_pointer(out, "out")?) })
    };
    // SAFETY: forwarded contract.
    unsafe { pair_step_reporting(model, body1, body2, contact, state, sink) }
}

/// `rsl_contact_step_accumulate` for arguments its fast entry did not take:
/// [`pair_step_reporting`] with the accumulators checked. Out of line, as
/// [`out_step_reporting`].
///
/// # Safety
/// As `rsl_contact_step_accumulate`.
#[cold]
#[inline(never)]
#[allow(clippy::too_many_arguments)]
unsafe fn accumulate_step_reporting(
    model: *const super::model::rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force1: *mut rsl_vec3,
    torque1: *mut rsl_vec3,
    force2: *mut rsl_vec3,
    torque2: *mut rsl_vec3,
) -> i32 {
    let sink = || {
        // SAFETY: each accumulator is checked non-NULL and aligned; valid and not
        // overlapping the inputs or the state by `rsl_contact_step_accumulate`'s contract.
        Ok(unsafe {
            Accumulators::new(
                checked_pointer(force1, "force1")?,
                checked_pointer(torque1, "torque1")?,
                checked_pointer(force2, "force2")?,
                checked_pointer(torque2, "torque2")?,
            )
        })
    };
    // SAFETY: forwarded contract.
    unsafe { pair_step_reporting(model, body1, body2, contact, state, sink) }
}

/// The per-contact pair step for arguments its fast entry did not take (a NULL or misaligned
/// pointer, a handle that is not a live model): checks each argument in order and reports the
/// first bad one (`sink` checks the output pointers and makes the sink), or steps through the
/// checked path. Inlined into the entries' cold reporting functions.
///
/// # Safety
/// As `rsl_contact_step` for the pointers given here.
#[inline(always)]
unsafe fn pair_step_reporting<K: LoadsSink>(
    model: *const super::model::rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    sink: impl FnOnce() -> Result<K, FfiError>,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; every helper checks NULL and alignment.
        let (m, b1, b2, inp, st) = unsafe {
            (
                live_model(model)?,
                input(body1, "body1")?,
                input(body2, "body2")?,
                input(contact, "contact")?,
                output(state, "state")?,
            )
        };
        let sink = sink()?;
        sink.deliver(&pair_step_checked(&m.model, b1, b2, inp, st)?);
        Ok(())
    })
}

/// Steps one sphere-sphere contact as `rsl_contact_step` does (same physics, same checks, same
/// status, same state) and adds its loads to the bodies' accumulators instead of returning
/// them: `*force1 += F`, `*torque1 += T1`, `*force2 -= F`, `*torque2 += T2` (`F`, `T1`, `T2`
/// are `rsl_contact_loads`' `force1`, `torque1`, `torque2`: forces, and torques about each
/// body's centre). This is the loop body of a DEM force computation
/// (`rsl_contact_step_accumulate(m, &p[i], &p[j], &in, &st[c], &f[i], &t[i], &f[j], &t[j])`);
/// the library knows where the loads go before it steps, and fetches those cache lines while
/// it computes. Use `rsl_contact_step` for the other outputs (sliding force, moments, energy).
///
/// `*state` and the accumulators are written only on `RSL_OK` (with `RSL_INPUT_SETUP`,
/// `*state` as `rsl_contact_step` writes it); the sums themselves are not checked. The
/// accumulators may point to the same vector (the four adds are done in the order above).
///
/// Errors: those of `rsl_contact_step`.
///
/// # Safety
/// Every pointer must be valid for its type during the call; `state` and the accumulators must
/// not overlap the inputs, and `state` must not overlap the accumulators. The model must not be
/// modified during the call.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn rsl_contact_step_accumulate(
    model: *const super::model::rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force1: *mut rsl_vec3,
    torque1: *mut rsl_vec3,
    force2: *mut rsl_vec3,
    torque2: *mut rsl_vec3,
) -> i32 {
    let pointers_ok = all_set_and_aligned(&[
        model as usize,
        body1 as usize,
        body2 as usize,
        contact as usize,
        state as usize,
        force1 as usize,
        torque1 as usize,
        force2 as usize,
        torque2 as usize,
    ]);
    // SAFETY: as in `rsl_contact_step`.
    if pointers_ok && unsafe { (*model).is_live() } {
        // SAFETY: as in `rsl_contact_step`; the accumulators are non-NULL and aligned (tested
        // just above), valid and not overlapping the inputs or the state by this function's
        // contract (they stay raw pointers: they may alias each other).
        return unsafe {
            ((*model).pair_steps.accumulate)(
                model, body1, body2, contact, state, force1, torque1, force2, torque2,
            )
        };
    }
    // SAFETY: forwarded contract.
    unsafe {
        accumulate_step_reporting(
            model, body1, body2, contact, state, force1, torque1, force2, torque2,
        )
    }
}

// The per-contact fast path tests every pointer for 8-byte alignment at once.
const _: () = {
    assert!(std::mem::align_of::<super::model::rsl_model>() == 8);
    assert!(std::mem::align_of::<rsl_sphere>() == 8);
    assert!(std::mem::align_of::<rsl_contact_input>() == 8);
    assert!(std::mem::align_of::<rsl_contact_state>() == 8);
    assert!(std::mem::align_of::<rsl_contact_loads>() == 8);
    assert!(std::mem::align_of::<rsl_vec3>() == 8);
};

/// Whether every address is non-zero and a multiple of 8, tested without a branch per address:
/// the OR of all of them has no low bit set, and their minimum is not zero. Both folds stay in
/// general registers: `rsl_contact_step_accumulate`'s last three pointers arrive on the stack,
/// just stored by the caller, and a fold that LLVM vectorises (the earlier `a - 8` form) read
/// two of them with one 16-byte load, which cannot take its data from two 8-byte stores and
/// waits for them to reach the cache (a store-forwarding stall at the top of every call).
/// `u64` minimum has no SSE2 instruction, so the SLP vectoriser leaves this form scalar. (A
/// one-register form, the OR of `a.rotate_right(3) - 1` tested on its top three bits, came out
/// longer: LLVM splits the OR into a tree over more registers, and each term takes a copy, a
/// rotate and a decrement.)
#[inline(always)]
fn all_set_and_aligned(addresses: &[usize]) -> bool {
    let low_bits = addresses.iter().fold(0, |acc, &a| acc | a);
    let least = addresses.iter().fold(usize::MAX, |acc, &a| acc.min(a));
    low_bits & 7 == 0 && least != 0
}

/// `rsl_contact_step_wall`'s step once its pointers are checked ([`checked_step_with`]).
fn wall_step_checked(
    model: &Model,
    sphere: &rsl_sphere,
    wall: &rsl_wall,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
) -> Result<rsl_contact_loads, Error> {
    let (s1, w) = (Sphere::from(sphere), Wall::from(wall));
    checked_step_with(model, input, state, |i, s| {
        contact_step_wall(model, &s1, &w, i, s)
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
    let sink = || {
        // SAFETY: as in `rsl_contact_step`.
        Ok(unsafe { LoadsOut::new(checked_pointer(out, "out")?) })
    };
    // SAFETY: forwarded contract.
    unsafe { wall_step_reporting(model, sphere, wall, contact, state, sink) }
}

/// The sphere-wall step with every argument checked in order (the first bad one reported;
/// `sink` checks the output pointers and makes the sink), through the checked path.
///
/// # Safety
/// As `rsl_contact_step_wall` for the pointers given here.
unsafe fn wall_step_reporting<K: LoadsSink>(
    model: *const super::model::rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    sink: impl FnOnce() -> Result<K, FfiError>,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; every helper checks NULL and alignment.
        let (m, s1, w, inp, st) = unsafe {
            (
                live_model(model)?,
                input(sphere, "sphere")?,
                input(wall, "wall")?,
                input(contact, "contact")?,
                output(state, "state")?,
            )
        };
        let sink = sink()?;
        sink.deliver(&wall_step_checked(&m.model, s1, w, inp, st)?);
        Ok(())
    })
}

/// Steps one sphere-wall contact as `rsl_contact_step_wall` does and adds the sphere's loads
/// to its accumulators: `*force += force1`, `*torque += torque1` (torque about the sphere's
/// centre). The wall's loads are not returned (use `rsl_contact_step_wall` for them).
/// `*state` and the accumulators are written only on `RSL_OK`; `force` and `torque` may be the
/// same vector.
///
/// Errors: those of `rsl_contact_step_wall`.
///
/// # Safety
/// As `rsl_contact_step_accumulate`.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_step_wall_accumulate(
    model: *const super::model::rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
) -> i32 {
    let sink = || {
        // SAFETY: both accumulators are checked non-NULL and aligned; valid and not
        // overlapping the inputs or the state by this function's contract (they stay raw
        // pointers: they may alias each other).
        Ok(unsafe {
            SphereAccumulators::new(
                checked_pointer(force, "force")?,
                checked_pointer(torque, "torque")?,
            )
        })
    };
    // SAFETY: forwarded contract.
    unsafe { wall_step_reporting(model, sphere, wall, contact, state, sink) }
}

/// Critical time step of velocity Verlet for a rotational spring-dashpot:
/// `dt_c = (2/w0)(sqrt(1 + z^2) - z)`, `w0 = sqrt(k_theta (1/I1 + 1/I2))`, with `z` the
/// `damping_ratio` (0: undamped). `inertia2` may be +INFINITY for a wall. Writes `*out` on
/// success. `z` is relative to the critical damping of these two inertias,
/// `2 sqrt(k_theta I1 I2/(I1 + I2))`; the `eta_r` of `RSL_DAMPING_RATIO` is relative to the
/// larger rolling inertia `I_r` (which includes `m R^2`), so passing `eta_r` as `z`
/// understates the damping (equal solid spheres: `z = eta_r sqrt(3.5)`) and gives a less
/// conservative step.
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

/// Stable step bound with sliding and rotational springs coupled (undamped):
/// `2/sqrt(k_t (1/m1 + 1/m2 + l1^2/I1 + l2^2/I2) + k_theta (1/I1 + 1/I2))`. Body 2's mass and
/// inertia may be +INFINITY for a wall. `l2` is not read when `inertia2` is +INFINITY (its
/// term `l2^2/I2` is 0), so a wall's `l2` may be any value, the +INFINITY of its
/// `rsl_decomposition.branch2` included; otherwise it must be finite and > 0, as `l1`. Writes
/// `*out` on success.
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

#[cfg(test)]
pub(super) mod tests {
    //! `rsl_contact_step`'s fast path (a plain input) against its checked path, reached with a
    //! sliding-stiffness override equal to the model's `k_t` (the same physics).
    use super::*;
    use crate::capi::model::rsl_model;
    use crate::capi::status::RSL_OK;
    use crate::laws::model::{Preset, RollingLaw, SlidingLaw, Transport, TwistingLaw};
    use crate::scalar::Vec3;

    struct Lcg(u64);
    impl Lcg {
        fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
        }
        fn vec(&mut self, size: f64) -> rsl_vec3 {
            rsl_vec3 {
                x: self.uniform(-size, size),
                y: self.uniform(-size, size),
                z: self.uniform(-size, size),
            }
        }
    }

    fn models() -> Vec<Model> {
        let mut full = Model::with_preset(Preset::Lammps2021);
        full.sliding.law = SlidingLaw::Linear;
        (
            full.sliding.stiffness,
            full.sliding.damping,
            full.sliding.friction,
        ) = (2e5, 30.0, 0.5);
        full.rolling.law = RollingLaw::Epsd;
        (
            full.rolling.stiffness,
            full.rolling.damping,
            full.rolling.friction,
        ) = (1e5, 10.0, 0.1);
        full.twisting.law = TwistingLaw::Sds;
        (full.twisting.stiffness, full.twisting.damping) = (50.0, 0.5);
        full.twisting.friction = 0.05;
        full.sliding_transport = Transport::ProjectRescale;
        full.rolling_transport = Transport::ProjectRescale;
        let mut exact = full;
        exact.preset = Preset::Objective;
        exact.sliding_transport = Transport::Exact;
        exact.rolling_transport = Transport::Exact;
        let mut energy = exact;
        energy.track_energy = true;
        // Marshall twisting with first-order transports, with the objective preset's exact
        // ones and with LAMMPS'.
        let mut exact_marshall = exact;
        exact_marshall.twisting.law = TwistingLaw::Marshall;
        let mut marshall = exact_marshall;
        marshall.sliding_transport = Transport::FirstOrder;
        marshall.rolling_transport = Transport::FirstOrder;
        let mut roll_twist = full;
        roll_twist.sliding.law = SlidingLaw::None;
        let mut lammps_marshall = full;
        lammps_marshall.twisting.law = TwistingLaw::Marshall;
        vec![
            full,
            exact,
            energy,
            marshall,
            roll_twist,
            lammps_marshall,
            exact_marshall,
        ]
    }

    type Case = (rsl_sphere, rsl_sphere, rsl_contact_input, rsl_contact_state);

    fn case(rng: &mut Lcg) -> Case {
        let (r1, r2) = (rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5));
        let n = Vec3::from(rng.vec(1.0)).normalize();
        let p1 = rng.vec(5.0);
        let gap = (r1 + r2) * rng.uniform(0.97, 0.999);
        let b1 = rsl_sphere {
            position: p1,
            velocity: rng.vec(0.5),
            angular_velocity: rng.vec(3.0),
            radius: r1,
        };
        let b2 = rsl_sphere {
            position: (Vec3::from(p1) + n * gap).into(),
            velocity: rng.vec(0.5),
            angular_velocity: rng.vec(3.0),
            radius: r2,
        };
        let input = rsl_contact_input {
            normal_force: rng.uniform(0.0, 200.0),
            dt: 1e-4,
            normal_stiffness: 1e6,
            mass1: 2.0,
            mass2: 3.0,
            inertia1: 0.4,
            inertia2: 0.6,
            ..Default::default()
        };
        let old = (n + Vec3::from(rng.vec(0.02))).normalize();
        let tangent = |v: rsl_vec3| -> rsl_vec3 {
            let v = Vec3::from(v);
            (v - old * v.dot(&old)).into()
        };
        let state = rsl_contact_state {
            sliding_spring: tangent(rng.vec(5e-4)),
            rolling_spring: tangent(rng.vec(2e-4)),
            twisting_angle: rng.uniform(-1e-2, 1e-2),
            previous_normal: old.into(),
            ..Default::default()
        };
        (b1, b2, input, state)
    }

    /// Every field of a state as bits (so that NaN compares and -0 differs from 0).
    pub(crate) fn state_bits(s: &rsl_contact_state) -> Vec<u64> {
        let vectors = [
            s.sliding_spring,
            s.rolling_spring,
            s.twisting_offaxis,
            s.previous_normal,
        ];
        let mut b: Vec<u64> = vectors
            .iter()
            .flat_map(|v| [v.x, v.y, v.z])
            .map(f64::to_bits)
            .collect();
        b.extend([
            s.twisting_angle.to_bits(),
            s.slip_flags as u64,
            s.reserved as u64,
        ]);
        b
    }

    /// The accumulators' values before a step: distinct, non-zero, so that each add shows.
    const ACCUMULATED: [rsl_vec3; 4] = [
        rsl_vec3 {
            x: 1.5,
            y: -2.25,
            z: 3.125,
        },
        rsl_vec3 {
            x: -0.75,
            y: 0.5,
            z: 7.0,
        },
        rsl_vec3 {
            x: 11.0,
            y: 0.0625,
            z: -4.5,
        },
        rsl_vec3 {
            x: 0.375,
            y: -9.0,
            z: 2.0,
        },
    ];

    /// Steps `c` both ways (fast path and checked path) with both entry points
    /// (`rsl_contact_step`, `rsl_contact_step_accumulate`); asserts the same status, the same
    /// bits out and the same state (the caller's on a refusal), and that the accumulators
    /// received exactly `rsl_contact_step`'s loads (or nothing on a refusal). Returns the status.
    fn same(handle: &rsl_model, c: &Case, what: &str) -> i32 {
        let (b1, b2, input, state0) = c;
        let mut checked_input = *input;
        checked_input.flags = RSL_INPUT_SLIDING_STIFFNESS;
        checked_input.sliding_stiffness = handle.model.sliding.stiffness;
        let mut runs = Vec::new();
        for i in [input, &checked_input] {
            let (mut state, mut out) = (*state0, rsl_contact_loads::default());
            out.reserved = 7; // must stay on a refusal
                              // SAFETY: every pointer is to a live local of the right type; none overlap.
            let status = unsafe { rsl_contact_step(handle, b1, b2, i, &mut state, &mut out) };
            runs.push((status, state, out));
            let mut acc = ACCUMULATED;
            let mut acc_state = *state0;
            let [f1, t1, f2, t2] = &mut acc;
            // SAFETY: as above.
            let acc_status = unsafe {
                rsl_contact_step_accumulate(handle, b1, b2, i, &mut acc_state, f1, t1, f2, t2)
            };
            let added = |a: &rsl_vec3, v: &rsl_vec3, sign: f64| {
                let r = |a: f64, v: f64| if sign > 0.0 { a + v } else { a - v };
                rsl_vec3 {
                    x: r(a.x, v.x),
                    y: r(a.y, v.y),
                    z: r(a.z, v.z),
                }
            };
            let expected = if status == RSL_OK {
                let [f1, t1, f2, t2] = &ACCUMULATED;
                [
                    added(f1, &out.force1, 1.0),
                    added(t1, &out.torque1, 1.0),
                    added(f2, &out.force1, -1.0),
                    added(t2, &out.torque2, 1.0),
                ]
            } else {
                ACCUMULATED
            };
            let bits = |v: &[rsl_vec3; 4]| v.map(|v| [v.x, v.y, v.z].map(f64::to_bits));
            assert_eq!(acc_status, status, "{what}: accumulate's status");
            assert_eq!(bits(&acc), bits(&expected), "{what}: accumulated loads");
            assert_eq!(
                state_bits(&acc_state),
                state_bits(&state),
                "{what}: accumulate's state"
            );
        }
        let bits = |(status, s, o): &(i32, rsl_contact_state, rsl_contact_loads)| {
            // Bits, so that NaN compares and -0 differs from 0.
            let v = |v: &rsl_vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
            let mut b = vec![*status as u64];
            b.extend(state_bits(s));
            for x in [&o.force1, &o.torque1, &o.torque2, &o.sliding_force] {
                b.extend(v(x));
            }
            b.extend(
                v(&o.rolling_moment)
                    .into_iter()
                    .chain(v(&o.twisting_torque)),
            );
            let e = &o.energy;
            b.extend(
                [
                    e.elastic_sliding,
                    e.dashpot_rolling,
                    e.slider_twisting,
                    e.transport,
                ]
                .map(f64::to_bits),
            );
            b.extend([o.slip_flags as u64, o.reserved as u64]);
            b
        };
        assert_eq!(
            bits(&runs[0]),
            bits(&runs[1]),
            "{what}: fast and checked paths differ"
        );
        if runs[0].0 != RSL_OK {
            let untouched = (RSL_OK, *state0, runs[0].2);
            assert_eq!(
                bits(&runs[0])[1..],
                bits(&untouched)[1..],
                "{what}: state written"
            );
            assert_eq!(
                runs[0].2.reserved, 7,
                "{what}: a refused step wrote the output"
            );
        }
        runs[0].0
    }

    #[test]
    fn fast_path_gives_the_checked_paths_bits_and_errors() {
        let mut rng = Lcg(3);
        let (mut accepted, mut refused, mut levels) = (0, 0, 0);
        for avx2 in [false, true] {
            if avx2 && !Simd::Avx2.available() {
                continue;
            }
            levels += 1;
            for model in models() {
                let mut handle = rsl_model::live(model);
                handle.pair_steps = pair_steps_built(avx2);
                for _ in 0..100 {
                    let mut c = case(&mut rng);
                    for _ in 0..3 {
                        assert_eq!(same(&handle, &c, "plain"), RSL_OK);
                        accepted += 1;
                        // The next step from the new state (the fast path's).
                        let mut out = rsl_contact_loads::default();
                        // SAFETY: as in `same`.
                        unsafe { rsl_contact_step(&handle, &c.0, &c.1, &c.2, &mut c.3, &mut out) };
                    }
                }
                // Every double the fast path reads, each struct's first and last included
                // (the AVX2 test reads them four at a time).
                for field in 0..41 {
                    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 1e300] {
                        let mut c = case(&mut rng);
                        *double(&mut c, field) = x;
                        if same(&handle, &c, &format!("double {field} = {x}")) != RSL_OK {
                            refused += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(accepted, models().len() * 300 * levels);
        // NaN and +-inf (3 of the 5 values) are refused everywhere but +inf in `mass2` and
        // `inertia2` (a fixed body 2); -1 in most fields makes up for those two.
        assert!(refused >= 41 * 3 * 4 * levels, "only {refused} refusals");
    }

    /// Double number `i` of the values the fast path reads: both spheres (0-19), the state
    /// (20-32), the input's first eight (33-40).
    fn double(c: &mut Case, i: usize) -> &mut f64 {
        fn vec(v: &mut rsl_vec3, i: usize) -> &mut f64 {
            [&mut v.x, &mut v.y, &mut v.z].into_iter().nth(i).unwrap()
        }
        fn sphere(s: &mut rsl_sphere, i: usize) -> &mut f64 {
            match i {
                0..=2 => vec(&mut s.position, i),
                3..=5 => vec(&mut s.velocity, i - 3),
                6..=8 => vec(&mut s.angular_velocity, i - 6),
                _ => &mut s.radius,
            }
        }
        let (b1, b2, input, state) = c;
        match i {
            0..=9 => sphere(b1, i),
            10..=19 => sphere(b2, i - 10),
            20..=22 => vec(&mut state.sliding_spring, i - 20),
            23..=25 => vec(&mut state.rolling_spring, i - 23),
            26 => &mut state.twisting_angle,
            27..=29 => vec(&mut state.twisting_offaxis, i - 27),
            30..=32 => vec(&mut state.previous_normal, i - 30),
            _ => [
                &mut input.normal_force,
                &mut input.dt,
                &mut input.normal_stiffness,
                &mut input.contact_radius,
                &mut input.mass1,
                &mut input.mass2,
                &mut input.inertia1,
                &mut input.inertia2,
            ]
            .into_iter()
            .nth(i - 33)
            .unwrap(),
        }
    }
}

#[cfg(test)]
mod extreme_input_tests {
    //! Finite but extreme inputs through the C ABI (loads whose squared length overflows, wall
    //! normals of any length, a wall's unread `l2`), and the argument names in the messages.
    use super::*;
    use crate::capi::decompose::rsl_decompose_wall;
    use crate::capi::model::*;
    use crate::capi::status::{
        rsl_last_error_message, RSL_ERR_INVALID_ARGUMENT, RSL_ERR_MISALIGNED, RSL_ERR_NON_FINITE,
        RSL_ERR_NULL_POINTER, RSL_OK,
    };
    use crate::capi::types::rsl_decomposition;
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
    /// sliding (-z), not zero, and leave the spring at `-(F_t + gamma_t v_s)/k_t`. A stored
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
        // xi = -(F_t + gamma_t v_s)/k_t = -(-50 + 1e156)/1e5 z: -1e151 to rounding.
        let xi = state.sliding_spring;
        assert_close(&xi, vec3(0.0, 0.0, -1e151), 4.0 * EPS, "spring");
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
                        rsl_contact_step_accumulate(
                            m.0, &b1, &b2, contact, &mut state, f1, t1, f2, t2,
                        ),
                        last_error(),
                    ),
                    (
                        rsl_contact_step_wall(m.0, &s, &wall, contact, &mut state, &mut out),
                        last_error(),
                    ),
                    (
                        rsl_contact_step_wall_accumulate(
                            m.0, &s, &wall, contact, &mut state, f1, t1,
                        ),
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
}
