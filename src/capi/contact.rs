//! The per-contact step through the C ABI: `rsl_contact_step` (sphere pair) and
//! `rsl_contact_step_wall`, the state the host stores per contact, and the time-step helpers.
#![allow(non_camel_case_types)]

pub use super::types::{rsl_contact_energy, rsl_contact_loads};
pub use crate::layout::{rsl_contact_input, rsl_contact_state};

use super::handle::{
    live_model, rsl_model, AccumulateStep, ContactSteps, OutStep, UncheckedSteps,
    WallAccumulateStep, WallOutStep,
};
use super::status::FfiError;
use super::types::{rsl_sphere, rsl_vec3, rsl_wall};
use super::{checked_pointer, guard, guard_status, input, output};
use crate::batch::dispatch::pair_steps_avx2;
use crate::decompose::{Sphere, Wall};
use crate::error::Error;
use crate::laws::checked::{contact_step_pair, contact_step_wall};
#[cfg(target_arch = "x86_64")]
use crate::laws::fast_path::finite::Avx2;
use crate::laws::fast_path::finite::{FiniteTest, Portable};
use crate::laws::fast_path::{
    overrides_in_range, step_outputs_finite, step_pair_if_valid, step_pair_unchecked,
    step_wall_if_valid, step_wall_unchecked,
};
use crate::laws::model::Model;
use crate::laws::stability::{coupled_critical_time_step, rotational_critical_time_step};
use crate::laws::step::{ContactState, StepInput, StepOutput};
use crate::laws::swap::mirror_state;
use crate::scalar::FiniteSums;

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
            stiffness_change: e.stiffness,
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
    state.model_memory = s.model_memory.into();
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
/// the previous normal, which flips too); `model_memory` negated with the YADE_2023 preset
/// (its off-axis twisting moment on body 1) and kept otherwise (the previous stiffnesses, which
/// belong to the contact); `previous_normal` negated (the normal points from body 1 to body 2);
/// `slip_flags` kept. Negating every
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
    model: *const rsl_model,
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

/// The per-contact steps (the model handle keeps them): the AVX2 builds where the core's
/// kernel choice takes them ([`pair_steps_avx2`]), else the portable ones.
pub(crate) fn contact_steps() -> ContactSteps {
    contact_steps_built(pair_steps_avx2())
}

/// The AVX2 builds of the steps or the portable ones. Only a CPU with AVX2 and FMA may call the
/// AVX2 builds.
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_variables))]
fn contact_steps_built(avx2: bool) -> ContactSteps {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        return ContactSteps {
            out: out_step_avx2,
            accumulate: accumulate_step_avx2,
            wall_out: wall_out_step_avx2,
            wall_accumulate: wall_accumulate_step_avx2,
            unchecked: UncheckedSteps {
                out: unchecked_out_step_avx2,
                accumulate: unchecked_accumulate_step_avx2,
                wall_out: unchecked_wall_out_step_avx2,
                wall_accumulate: unchecked_wall_accumulate_step_avx2,
            },
        };
    }
    ContactSteps {
        out: out_step_portable,
        accumulate: accumulate_step_portable,
        wall_out: wall_out_step_portable,
        wall_accumulate: wall_accumulate_step_portable,
        unchecked: UncheckedSteps {
            out: unchecked_out_step_portable,
            accumulate: unchecked_accumulate_step_portable,
            wall_out: unchecked_wall_out_step_portable,
            wall_accumulate: unchecked_wall_accumulate_step_portable,
        },
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
unsafe fn entered_step<F: FiniteTest, K: PairSink, const CHECKED: bool>(
    test: F,
    model: *const rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    sink: K,
) -> i32 {
    // SAFETY: this function's contract.
    let (m, b1, b2, inp, st) = unsafe { (&*model, &*body1, &*body2, &*contact, &mut *state) };
    // A plain input (no flag) gets its own step, in which the per-contact values are known
    // absent (the model's coefficients are read directly): about 60 instructions fewer per
    // call than the step that selects them at run time. Two boundaries, so that each step
    // stays small enough to be inlined into its own.
    if inp.flags == 0 {
        guard_status(|| pair_step_with::<F, K, false, CHECKED>(test, m, b1, b2, inp, st, sink))
    } else {
        guard_status(|| pair_step_with::<F, K, true, CHECKED>(test, m, b1, b2, inp, st, sink))
    }
}

/// [`wall_step_with`] on the entry's checked pointers, behind the panic boundary, as
/// [`entered_step`].
///
/// # Safety
/// As [`entered_step`], with the wall for body 2 (`rsl_wall` is 8-aligned too).
#[inline(always)]
unsafe fn entered_wall_step<F: FiniteTest, K: WallSink, const CHECKED: bool>(
    test: F,
    model: *const rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    sink: K,
) -> i32 {
    // SAFETY: this function's contract.
    let (m, s1, w, inp, st) = unsafe { (&*model, &*sphere, &*wall, &*contact, &mut *state) };
    guard_status(|| wall_step_with::<F, K, CHECKED>(test, m, s1, w, inp, st, sink))
}

/// The AVX2 and portable builds of one entry's step (`$avx2`, `$portable`): body 2 of type
/// `$body2` (a sphere or a wall), the entry's parameters (`$param`), the sink made from them
/// (`$sink`), `$entered` ([`entered_step`] or [`entered_wall_step`]) with the AVX2 or the
/// portable finiteness test.
macro_rules! entry_steps {
    (
        $(#[$doc:meta])*
        $avx2:ident, $portable:ident, $body2:ty, $entered:ident, $checked:expr,
        ($($param:ident: $ty:ty),* $(,)?),
        $sink:expr
    ) => {
        $(#[$doc])*
        ///
        /// The AVX2 build.
        ///
        /// # Safety
        /// As `$entered`, the output pointers as the entry requires (checked non-NULL and
        /// aligned, valid, not overlapping the inputs or the state); the CPU must support AVX2
        /// and FMA.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        #[allow(clippy::too_many_arguments)]
        unsafe extern "C" fn $avx2(
            model: *const rsl_model,
            body1: *const rsl_sphere,
            body2: *const $body2,
            contact: *const rsl_contact_input,
            state: *mut rsl_contact_state,
            $($param: $ty),*
        ) -> i32 {
            // SAFETY: this function's contract (the CPU has AVX2; the output pointers are
            // valid and exclusive, as the sink requires).
            unsafe {
                let (test, sink) = (Avx2::assume(), $sink);
                $entered::<_, _, { $checked }>(test, model, body1, body2, contact, state, sink)
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
            model: *const rsl_model,
            body1: *const rsl_sphere,
            body2: *const $body2,
            contact: *const rsl_contact_input,
            state: *mut rsl_contact_state,
            $($param: $ty),*
        ) -> i32 {
            // SAFETY: this function's contract (the output pointers are valid and exclusive, as
            // the sink requires).
            unsafe {
                let sink = $sink;
                $entered::<_, _, { $checked }>(Portable, model, body1, body2, contact, state, sink)
            }
        }
    };
}

entry_steps! {
    /// `rsl_contact_step`'s step, entered from it (see [`OutStep`](super::handle::OutStep)).
    out_step_avx2, out_step_portable, rsl_sphere, entered_step, true,
    (out: *mut rsl_contact_loads),
    LoadsOut::new(out)
}

entry_steps! {
    /// `rsl_contact_step_accumulate`'s step, entered from it (see
    /// [`AccumulateStep`](super::handle::AccumulateStep)).
    accumulate_step_avx2, accumulate_step_portable, rsl_sphere, entered_step, true,
    (force1: *mut rsl_vec3, torque1: *mut rsl_vec3, force2: *mut rsl_vec3, torque2: *mut rsl_vec3),
    Accumulators::new(force1, torque1, force2, torque2)
}

entry_steps! {
    /// `rsl_contact_step_wall`'s step, entered from it (see
    /// [`WallOutStep`](super::handle::WallOutStep)).
    wall_out_step_avx2, wall_out_step_portable, rsl_wall, entered_wall_step, true,
    (out: *mut rsl_contact_loads),
    LoadsOut::new(out)
}

entry_steps! {
    /// `rsl_contact_step_wall_accumulate`'s step, entered from it (see
    /// [`WallAccumulateStep`](super::handle::WallAccumulateStep)).
    wall_accumulate_step_avx2, wall_accumulate_step_portable, rsl_wall, entered_wall_step, true,
    (force: *mut rsl_vec3, torque: *mut rsl_vec3),
    SphereAccumulators::new(force, torque)
}

entry_steps! {
    /// `rsl_contact_step_unchecked`'s step (an [`OutStep`](super::handle::OutStep)).
    unchecked_out_step_avx2, unchecked_out_step_portable, rsl_sphere, entered_step, false,
    (out: *mut rsl_contact_loads),
    LoadsOut::new(out)
}

entry_steps! {
    /// `rsl_contact_step_accumulate_unchecked`'s step (an
    /// [`AccumulateStep`](super::handle::AccumulateStep)).
    unchecked_accumulate_step_avx2, unchecked_accumulate_step_portable, rsl_sphere, entered_step,
    false,
    (force1: *mut rsl_vec3, torque1: *mut rsl_vec3, force2: *mut rsl_vec3, torque2: *mut rsl_vec3),
    Accumulators::new(force1, torque1, force2, torque2)
}

entry_steps! {
    /// `rsl_contact_step_wall_unchecked`'s step (a [`WallOutStep`](super::handle::WallOutStep)).
    unchecked_wall_out_step_avx2, unchecked_wall_out_step_portable, rsl_wall, entered_wall_step,
    false,
    (out: *mut rsl_contact_loads),
    LoadsOut::new(out)
}

entry_steps! {
    /// `rsl_contact_step_wall_accumulate_unchecked`'s step (a
    /// [`WallAccumulateStep`](super::handle::WallAccumulateStep)).
    unchecked_wall_accumulate_step_avx2, unchecked_wall_accumulate_step_portable, rsl_wall,
    entered_wall_step, false,
    (force: *mut rsl_vec3, torque: *mut rsl_vec3),
    SphereAccumulators::new(force, torque)
}

/// The step with the finiteness test `test`: [`fast_pair_step`] (`FLAGGED`: for an input with
/// flags, else for one without), or [`PairSink::step_guarded`] for anything it does not take.
#[inline(always)]
fn pair_step_with<F: FiniteTest, K: PairSink, const FLAGGED: bool, const CHECKED: bool>(
    test: F,
    m: &rsl_model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    sink: K,
) -> i32 {
    sink.expect();
    if fast_pair_step::<F, K, FLAGGED, CHECKED>(test, &m.model, body1, body2, input, state, sink) {
        return super::status::RSL_OK;
    }
    sink.step_guarded(&m.model, body1, body2, input, state)
}

/// The wall step with the finiteness test `test`: [`fast_wall_step`], or
/// [`WallSink::wall_step_guarded`] for anything it does not take.
#[inline(always)]
fn wall_step_with<F: FiniteTest, K: WallSink, const CHECKED: bool>(
    test: F,
    m: &rsl_model,
    sphere: &rsl_sphere,
    wall: &rsl_wall,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    sink: K,
) -> i32 {
    sink.expect();
    if fast_wall_step::<F, K, CHECKED>(test, &m.model, sphere, wall, input, state, sink) {
        return super::status::RSL_OK;
    }
    sink.wall_step_guarded(&m.model, sphere, wall, input, state)
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

/// A per-contact wall step's sink, with the way back to the checked step for an input the fast
/// path does not take (as [`PairSink`]).
pub(crate) trait WallSink: LoadsSink {
    /// [`wall_step_checked`] with its loads delivered here: out of line, cold, and a function
    /// that cannot unwind (see [`out_step_guarded`]).
    fn wall_step_guarded(
        self,
        model: &Model,
        sphere: &rsl_sphere,
        wall: &rsl_wall,
        input: &rsl_contact_input,
        state: &mut rsl_contact_state,
    ) -> i32;
}

impl WallSink for LoadsOut {
    #[inline(always)]
    fn wall_step_guarded(
        self,
        model: &Model,
        sphere: &rsl_sphere,
        wall: &rsl_wall,
        input: &rsl_contact_input,
        state: &mut rsl_contact_state,
    ) -> i32 {
        wall_out_step_guarded(model, sphere, wall, input, state, self.0)
    }
}

impl WallSink for SphereAccumulators {
    #[inline(always)]
    fn wall_step_guarded(
        self,
        model: &Model,
        sphere: &rsl_sphere,
        wall: &rsl_wall,
        input: &rsl_contact_input,
        state: &mut rsl_contact_state,
    ) -> i32 {
        let SphereAccumulators { force, torque } = self;
        wall_accumulate_step_guarded(model, sphere, wall, input, state, force, torque)
    }
}

/// [`wall_step_checked`] with its error recorded as the last error, its loads written to `*out`
/// on success, behind its own panic boundary: [`out_step_guarded`] for a wall.
#[inline(never)]
#[cold]
extern "C" fn wall_out_step_guarded(
    model: &Model,
    sphere: &rsl_sphere,
    wall: &rsl_wall,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    // SAFETY: `out` came from a `LoadsOut`, whose contract it keeps.
    let sink = unsafe { LoadsOut::new(out) };
    guard(|| {
        sink.deliver(&wall_step_checked(model, sphere, wall, input, state)?);
        Ok(())
    })
}

/// [`wall_out_step_guarded`] for the accumulators of a [`SphereAccumulators`] sink.
#[inline(never)]
#[cold]
extern "C" fn wall_accumulate_step_guarded(
    model: &Model,
    sphere: &rsl_sphere,
    wall: &rsl_wall,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
) -> i32 {
    // SAFETY: the pointers came from a `SphereAccumulators`, whose contract they keep.
    let sink = unsafe { SphereAccumulators::new(force, torque) };
    guard(|| {
        sink.deliver(&wall_step_checked(model, sphere, wall, input, state)?);
        Ok(())
    })
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

/// The fast path ([`step_pair_if_valid`]) on an input it takes ([`fast_input`]; `FLAGGED` false:
/// an input without flags, whose per-contact values are then known absent), with `test`
/// for the finiteness of the inputs and of the results: on success writes `*state`, delivers
/// the loads to `sink` and returns true; otherwise writes nothing. Without `CHECKED` (the
/// unchecked entries) no value is tested: [`step_pair_unchecked`], then the results are
/// written whatever they are.
#[inline(always)]
fn fast_pair_step<F: FiniteTest, K: LoadsSink, const FLAGGED: bool, const CHECKED: bool>(
    test: F,
    model: &Model,
    body1: &rsl_sphere,
    body2: &rsl_sphere,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    sink: K,
) -> bool {
    let step = if FLAGGED {
        match fast_input::<CHECKED>(input) {
            Some(step) => step,
            None => return false,
        }
    } else {
        plain_input(input)
    };
    let (b1, b2, s) = (
        Sphere::from(body1),
        Sphere::from(body2),
        ContactState::from(&*state),
    );
    let (o, next) = if CHECKED {
        let finite = test.inputs(body1, body2, input, state);
        match step_pair_if_valid(model, &b1, &b2, &step, &s, finite) {
            Some(stepped) => stepped,
            None => return false,
        }
    } else {
        step_pair_unchecked(model, &b1, &b2, &step, &s)
    };
    commit_fast_step::<K, CHECKED>(model, &o, &next, state, sink)
}

/// The input flags the fast path takes: every per-contact coefficient and the limit force (not
/// the setup pass, not a bond).
const FAST_FLAGS: u32 = RSL_INPUT_SLIDING_STIFFNESS
    | RSL_INPUT_SLIDING_DAMPING
    | RSL_INPUT_LIMIT_FORCE
    | RSL_INPUT_ROLLING_STIFFNESS
    | RSL_INPUT_ROLLING_DAMPING
    | RSL_INPUT_ROLLING_FRICTION
    | RSL_INPUT_TWISTING_STIFFNESS
    | RSL_INPUT_TWISTING_DAMPING
    | RSL_INPUT_TWISTING_FRICTION;

/// The fast path's step input: `input`'s values with the per-contact ones its flags select, or
/// `None` for an input the fast path does not take (a flag outside [`FAST_FLAGS`]; with
/// `CHECKED`, a selected value outside [`overrides_in_range`]). A plain input (no flag) costs
/// one test.
#[inline(always)]
fn fast_input<const CHECKED: bool>(input: &rsl_contact_input) -> Option<StepInput<f64>> {
    let plain = plain_input(input);
    let flags = input.flags;
    if flags == 0 {
        return Some(plain);
    }
    let flag = |f: u32| flags & f != 0;
    let step = StepInput {
        sliding_stiffness: flag(RSL_INPUT_SLIDING_STIFFNESS).then_some(input.sliding_stiffness),
        sliding_damping: flag(RSL_INPUT_SLIDING_DAMPING).then_some(input.sliding_damping),
        limit_force: flag(RSL_INPUT_LIMIT_FORCE).then_some(input.limit_force),
        rolling_stiffness: flag(RSL_INPUT_ROLLING_STIFFNESS).then_some(input.rolling_stiffness),
        rolling_damping: flag(RSL_INPUT_ROLLING_DAMPING).then_some(input.rolling_damping),
        rolling_friction: flag(RSL_INPUT_ROLLING_FRICTION).then_some(input.rolling_friction),
        twisting_stiffness: flag(RSL_INPUT_TWISTING_STIFFNESS).then_some(input.twisting_stiffness),
        twisting_damping: flag(RSL_INPUT_TWISTING_DAMPING).then_some(input.twisting_damping),
        twisting_friction: flag(RSL_INPUT_TWISTING_FRICTION).then_some(input.twisting_friction),
        ..plain
    };
    (flags & !FAST_FLAGS == 0 && (!CHECKED || overrides_in_range(&step))).then_some(step)
}

/// The step input of `input`'s first eight values, without per-contact ones (its flags are not
/// read: the whole input when it has none).
#[inline(always)]
fn plain_input(input: &rsl_contact_input) -> StepInput<f64> {
    StepInput {
        normal_stiffness: input.normal_stiffness,
        contact_radius: input.contact_radius,
        mass1: input.mass1,
        mass2: input.mass2,
        inertia1: input.inertia1,
        inertia2: input.inertia2,
        ..StepInput::new(input.normal_force, input.dt)
    }
}

/// The end of a fast step: when the results the step can make non-finite are finite
/// ([`step_outputs_finite`], tested in registers; not tested without `CHECKED`), writes
/// `*state`, delivers the loads to `sink` and returns true; otherwise writes nothing.
#[inline(always)]
fn commit_fast_step<K: LoadsSink, const CHECKED: bool>(
    model: &Model,
    o: &StepOutput<f64>,
    next: &ContactState<f64>,
    state: &mut rsl_contact_state,
    sink: K,
) -> bool {
    if CHECKED && !step_outputs_finite(model, o, next) {
        return false;
    }
    let loads = to_c(o);
    let mut new_state = *state;
    store(&mut new_state, next, loads.slip_flags);
    *state = new_state;
    sink.deliver(&loads);
    true
}

/// The fast path of a sphere-wall step ([`step_wall_if_valid`], [`step_wall_unchecked`]
/// without `CHECKED`), as [`fast_pair_step`]: on success writes `*state`, delivers the loads to
/// `sink` and returns true; otherwise writes nothing.
#[inline(always)]
fn fast_wall_step<F: FiniteTest, K: LoadsSink, const CHECKED: bool>(
    test: F,
    model: &Model,
    sphere: &rsl_sphere,
    wall: &rsl_wall,
    input: &rsl_contact_input,
    state: &mut rsl_contact_state,
    sink: K,
) -> bool {
    let Some(step) = fast_input::<CHECKED>(input) else {
        return false;
    };
    let (s1, w, s) = (
        Sphere::from(sphere),
        Wall::from(wall),
        ContactState::from(&*state),
    );
    let (o, next) = if CHECKED {
        let mut wall_values = FiniteSums::default();
        for v in [
            &wall.point,
            &wall.normal,
            &wall.velocity,
            &wall.angular_velocity,
        ] {
            wall_values.add([v.x, v.y, v.z]);
        }
        let finite = test.sphere_inputs(sphere, input, state) & wall_values.all_finite();
        match step_wall_if_valid(model, &s1, &w, &step, &s, finite) {
            Some(stepped) => stepped,
            None => return false,
        }
    } else {
        step_wall_unchecked(model, &s1, &w, &step, &s)
    };
    commit_fast_step::<K, CHECKED>(model, &o, &next, state, sink)
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
    model: *const rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { enter_out(|s| s.out, model, body1, body2, contact, state, out) }
}

/// The body of `rsl_contact_step` and `rsl_contact_step_unchecked`: every pointer tested at once
/// (non-NULL, 8-aligned) and the handle live, then a jump to the handle's step that `step`
/// picks (a tail call with the entry's own arguments: no frame, no copy); otherwise the
/// argument at fault reported ([`out_step_reporting`]).
///
/// # Safety
/// As `rsl_contact_step`.
#[inline(always)]
unsafe fn enter_out(
    step: impl FnOnce(&ContactSteps) -> OutStep,
    model: *const rsl_model,
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
        // only when the CPU has AVX2 and FMA (`contact_steps`).
        return unsafe { step(&(*model).steps)(model, body1, body2, contact, state, out) };
    }
    // SAFETY: forwarded contract.
    unsafe { out_step_reporting(model, body1, body2, contact, state, out) }
}

/// [`enter_out`] for `rsl_contact_step_accumulate` and its unchecked form.
///
/// # Safety
/// As `rsl_contact_step_accumulate`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn enter_accumulate(
    step: impl FnOnce(&ContactSteps) -> AccumulateStep,
    model: *const rsl_model,
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
    // SAFETY: as in `enter_out`.
    if pointers_ok && unsafe { (*model).is_live() } {
        // SAFETY: as in `enter_out`; the accumulators are non-NULL and aligned (tested just
        // above), valid and not overlapping the inputs or the state by this function's contract
        // (they stay raw pointers: they may alias each other).
        return unsafe {
            step(&(*model).steps)(
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

/// [`enter_out`] for `rsl_contact_step_wall` and its unchecked form.
///
/// # Safety
/// As `rsl_contact_step_wall`.
#[inline(always)]
unsafe fn enter_wall_out(
    step: impl FnOnce(&ContactSteps) -> WallOutStep,
    model: *const rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    let pointers_ok = all_set_and_aligned(&[
        model as usize,
        sphere as usize,
        wall as usize,
        contact as usize,
        state as usize,
        out as usize,
    ]);
    // SAFETY: as in `enter_out`.
    if pointers_ok && unsafe { (*model).is_live() } {
        // SAFETY: as in `enter_out`, with the wall for body 2.
        return unsafe { step(&(*model).steps)(model, sphere, wall, contact, state, out) };
    }
    // SAFETY: forwarded contract.
    unsafe { wall_out_step_reporting(model, sphere, wall, contact, state, out) }
}

/// [`enter_accumulate`] for `rsl_contact_step_wall_accumulate` and its unchecked form.
///
/// # Safety
/// As `rsl_contact_step_wall_accumulate`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn enter_wall_accumulate(
    step: impl FnOnce(&ContactSteps) -> WallAccumulateStep,
    model: *const rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
) -> i32 {
    let pointers_ok = all_set_and_aligned(&[
        model as usize,
        sphere as usize,
        wall as usize,
        contact as usize,
        state as usize,
        force as usize,
        torque as usize,
    ]);
    // SAFETY: as in `enter_out`.
    if pointers_ok && unsafe { (*model).is_live() } {
        // SAFETY: as in `enter_accumulate`, with the wall for body 2.
        return unsafe {
            step(&(*model).steps)(model, sphere, wall, contact, state, force, torque)
        };
    }
    // SAFETY: forwarded contract.
    unsafe { wall_accumulate_step_reporting(model, sphere, wall, contact, state, force, torque) }
}

/// `rsl_contact_step` for arguments its fast entry did not take: [`pair_step_reporting`]
/// with `out` checked. Out of line, so that the entry keeps no frame of its own.
///
/// # Safety
/// As `rsl_contact_step`.
#[cold]
#[inline(never)]
unsafe fn out_step_reporting(
    model: *const rsl_model,
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
    model: *const rsl_model,
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
    model: *const rsl_model,
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
    model: *const rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force1: *mut rsl_vec3,
    torque1: *mut rsl_vec3,
    force2: *mut rsl_vec3,
    torque2: *mut rsl_vec3,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        enter_accumulate(
            |s| s.accumulate,
            model,
            body1,
            body2,
            contact,
            state,
            force1,
            torque1,
            force2,
            torque2,
        )
    }
}

// The per-contact fast path tests every pointer for 8-byte alignment at once.
const _: () = {
    assert!(std::mem::align_of::<rsl_model>() == 8);
    assert!(std::mem::align_of::<rsl_sphere>() == 8);
    assert!(std::mem::align_of::<rsl_contact_input>() == 8);
    assert!(std::mem::align_of::<rsl_contact_state>() == 8);
    assert!(std::mem::align_of::<rsl_contact_loads>() == 8);
    assert!(std::mem::align_of::<rsl_vec3>() == 8);
    assert!(std::mem::align_of::<rsl_wall>() == 8);
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
    model: *const rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { enter_wall_out(|s| s.wall_out, model, sphere, wall, contact, state, out) }
}

/// `rsl_contact_step_wall` for arguments its fast entry did not take: [`wall_step_reporting`]
/// with `out` checked. Out of line, as [`out_step_reporting`].
///
/// # Safety
/// As `rsl_contact_step_wall`.
#[cold]
#[inline(never)]
unsafe fn wall_out_step_reporting(
    model: *const rsl_model,
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
    model: *const rsl_model,
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
    model: *const rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        enter_wall_accumulate(
            |s| s.wall_accumulate,
            model,
            sphere,
            wall,
            contact,
            state,
            force,
            torque,
        )
    }
}

/// `rsl_contact_step_wall_accumulate` for arguments its fast entry did not take:
/// [`wall_step_reporting`] with the accumulators checked. Out of line, as
/// [`out_step_reporting`].
///
/// # Safety
/// As `rsl_contact_step_wall_accumulate`.
#[cold]
#[inline(never)]
unsafe fn wall_accumulate_step_reporting(
    model: *const rsl_model,
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

/// `rsl_contact_step` without the tests of the values, for a host that has validated its data
/// itself: same step, same results bit for bit on input `rsl_contact_step` accepts, about 10 ns
/// less per call (docs/performance.md). Only the pointers and the handle are tested (the status
/// and message as `rsl_contact_step` gives them). The values are not: a non-finite or
/// out-of-range value (a radius <= 0, coincident centres, `dt <= 0`, a negative per-contact
/// coefficient, a state holding NaN...) is stepped as the formulas take it, and the results,
/// NaN or infinite ones included, are written to `*state` and `*out` with `RSL_OK` (never a
/// crash). Inputs with `RSL_INPUT_SETUP`, `RSL_INPUT_SHEAR_ADHESION` or an unknown
/// flag go through `rsl_contact_step` (checked).
///
/// # Safety
/// As `rsl_contact_step`.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_step_unchecked(
    model: *const rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        enter_out(
            |s| s.unchecked.out,
            model,
            body1,
            body2,
            contact,
            state,
            out,
        )
    }
}

/// `rsl_contact_step_accumulate` without the tests of the values, as
/// `rsl_contact_step_unchecked` is `rsl_contact_step`'s: the loads, whatever they are, are
/// added to the accumulators.
///
/// # Safety
/// As `rsl_contact_step_accumulate`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn rsl_contact_step_accumulate_unchecked(
    model: *const rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force1: *mut rsl_vec3,
    torque1: *mut rsl_vec3,
    force2: *mut rsl_vec3,
    torque2: *mut rsl_vec3,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        enter_accumulate(
            |s| s.unchecked.accumulate,
            model,
            body1,
            body2,
            contact,
            state,
            force1,
            torque1,
            force2,
            torque2,
        )
    }
}

/// `rsl_contact_step_wall` without the tests of the values, as `rsl_contact_step_unchecked`
/// is `rsl_contact_step`'s (a wall normal of zero length, or one too short or too long to be
/// normalised as `v / |v|`, is among the values not tested).
///
/// # Safety
/// As `rsl_contact_step_wall`.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_step_wall_unchecked(
    model: *const rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    out: *mut rsl_contact_loads,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        enter_wall_out(
            |s| s.unchecked.wall_out,
            model,
            sphere,
            wall,
            contact,
            state,
            out,
        )
    }
}

/// `rsl_contact_step_wall_accumulate` without the tests of the values, as
/// `rsl_contact_step_wall_unchecked` is `rsl_contact_step_wall`'s.
///
/// # Safety
/// As `rsl_contact_step_wall_accumulate`.
#[no_mangle]
pub unsafe extern "C" fn rsl_contact_step_wall_accumulate_unchecked(
    model: *const rsl_model,
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    contact: *const rsl_contact_input,
    state: *mut rsl_contact_state,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        enter_wall_accumulate(
            |s| s.unchecked.wall_accumulate,
            model,
            sphere,
            wall,
            contact,
            state,
            force,
            torque,
        )
    }
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
mod tests {
    //! `rsl_contact_step`'s fast path (a plain input) against its checked path, reached with a
    //! sliding-stiffness override equal to the model's `k_t` (the same physics).
    use super::*;
    use crate::batch::dispatch::Simd;
    use crate::capi::status::RSL_OK;
    use crate::laws::model::{
        Preset, RollingDamping, RollingLaw, SlidingLaw, Transport, TwistingLaw,
    };
    use crate::layout::tests::{state_bits, Lcg};
    use crate::scalar::Vec3;

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
        // Rolling damping as a ratio (reads the masses) and LIGGGHTS' cdt (reads k_n).
        let mut ratio = exact;
        ratio.rolling.damping_rule = RollingDamping::Ratio;
        ratio.rolling.damping = 0.3;
        let mut cdt = Model::with_preset(Preset::Liggghts38);
        cdt.sliding.law = SlidingLaw::Linear;
        (cdt.sliding.stiffness, cdt.sliding.friction) = (2e5, 0.5);
        cdt.rolling.law = RollingLaw::Cdt;
        cdt.rolling.friction = 0.1;
        vec![
            full,
            exact,
            energy,
            marshall,
            roll_twist,
            lammps_marshall,
            exact_marshall,
            ratio,
            cdt,
        ]
    }

    type Case = (rsl_sphere, Body2, rsl_contact_input, rsl_contact_state);

    /// A sphere pair in contact with a persistent history.
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
        (b1, Body2::Sphere(b2), input, state)
    }

    /// A sphere against a moving, turning wall whose normal has a length far from 1, with a
    /// persistent history (body 2 of `case`'s contact replaced by the wall).
    fn wall_case(rng: &mut Lcg) -> Case {
        let (b1, body2, input, state) = case(rng);
        let Body2::Sphere(b2) = body2 else {
            unreachable!()
        };
        // The wall through body 2's contact point, facing body 1.
        let n = (Vec3::from(b2.position) - Vec3::from(b1.position)).normalize();
        let length = [1.0, 1e-3, 7.5, 1e5][rng.below(4)];
        let point = Vec3::from(b2.position) - n * b2.radius;
        let wall = rsl_wall {
            point: point.into(),
            normal: (-n * length).into(),
            velocity: rng.vec(0.5),
            angular_velocity: rng.vec(0.2),
        };
        (b1, Body2::Wall(wall), input, state)
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

    /// Body 2 of a test contact: a sphere or a wall.
    #[derive(Clone, Copy)]
    enum Body2 {
        Sphere(rsl_sphere),
        Wall(rsl_wall),
    }

    /// What a step returned: its status, the state after it and its output.
    type Run = (i32, rsl_contact_state, rsl_contact_loads);

    /// Steps `c` through the C entry (`rsl_contact_step` or `rsl_contact_step_wall`) and through
    /// the checked path alone (`pair_step_checked`, `wall_step_checked`), and through the
    /// accumulating entry; asserts the same status, the same bits out and the same state (the
    /// caller's on a refusal), and that the accumulators received exactly the entry's loads (or
    /// nothing on a refusal). Returns the status.
    fn same(handle: &rsl_model, c: &Case, what: &str) -> i32 {
        let (b1, body2, input, state0) = c;
        let entry = |state: &mut rsl_contact_state, out: &mut rsl_contact_loads| match body2 {
            // SAFETY: every pointer is to a live local of the right type; none overlap.
            Body2::Sphere(b2) => unsafe { rsl_contact_step(handle, b1, b2, input, state, out) },
            // SAFETY: as above.
            Body2::Wall(w) => unsafe { rsl_contact_step_wall(handle, b1, w, input, state, out) },
        };
        let checked = |state: &mut rsl_contact_state, out: &mut rsl_contact_loads| {
            guard(|| {
                *out = match body2 {
                    Body2::Sphere(b2) => pair_step_checked(&handle.model, b1, b2, input, state)?,
                    Body2::Wall(w) => wall_step_checked(&handle.model, b1, w, input, state)?,
                };
                Ok(())
            })
        };
        let mut runs: Vec<Run> = Vec::new();
        for step in [&entry as &dyn Fn(&mut _, &mut _) -> i32, &checked] {
            let (mut state, mut out) = (*state0, rsl_contact_loads::default());
            out.reserved = 7; // must stay on a refusal
            let status = step(&mut state, &mut out);
            runs.push((status, state, out));
        }
        let (status, state, out) = runs[0];
        let mut acc = ACCUMULATED;
        let mut acc_state = *state0;
        let [f1, t1, f2, t2] = &mut acc;
        let acc_status = match body2 {
            // SAFETY: as above.
            Body2::Sphere(b2) => unsafe {
                rsl_contact_step_accumulate(handle, b1, b2, input, &mut acc_state, f1, t1, f2, t2)
            },
            // SAFETY: as above.
            Body2::Wall(w) => unsafe {
                rsl_contact_step_wall_accumulate(handle, b1, w, input, &mut acc_state, f1, t1)
            },
        };
        let added = |a: &rsl_vec3, v: &rsl_vec3, sign: f64| {
            let r = |a: f64, v: f64| if sign > 0.0 { a + v } else { a - v };
            rsl_vec3 {
                x: r(a.x, v.x),
                y: r(a.y, v.y),
                z: r(a.z, v.z),
            }
        };
        let expected = match (status == RSL_OK, body2) {
            (false, _) => ACCUMULATED,
            (true, Body2::Sphere(_)) => {
                let [f1, t1, f2, t2] = &ACCUMULATED;
                [
                    added(f1, &out.force1, 1.0),
                    added(t1, &out.torque1, 1.0),
                    added(f2, &out.force1, -1.0),
                    added(t2, &out.torque2, 1.0),
                ]
            }
            (true, Body2::Wall(_)) => {
                let [f1, t1, f2, t2] = &ACCUMULATED;
                [
                    added(f1, &out.force1, 1.0),
                    added(t1, &out.torque1, 1.0),
                    *f2,
                    *t2,
                ]
            }
        };
        let bits = |v: &[rsl_vec3; 4]| v.map(|v| [v.x, v.y, v.z].map(f64::to_bits));
        assert_eq!(acc_status, status, "{what}: accumulate's status");
        assert_eq!(bits(&acc), bits(&expected), "{what}: accumulated loads");
        assert_eq!(
            state_bits(&acc_state),
            state_bits(&state),
            "{what}: accumulate's state"
        );
        // The unchecked entries: the checked entries' bits wherever those accept the input (and
        // for the inputs they hand to the checked step), RSL_OK and no crash elsewhere.
        let mut unchecked_acc = ACCUMULATED;
        let mut unchecked_state = *state0;
        let [f1, t1, f2, t2] = &mut unchecked_acc;
        let unchecked_status = match body2 {
            // SAFETY: as above.
            Body2::Sphere(b2) => unsafe {
                rsl_contact_step_accumulate_unchecked(
                    handle,
                    b1,
                    b2,
                    input,
                    &mut unchecked_state,
                    f1,
                    t1,
                    f2,
                    t2,
                )
            },
            // SAFETY: as above.
            Body2::Wall(w) => unsafe {
                rsl_contact_step_wall_accumulate_unchecked(
                    handle,
                    b1,
                    w,
                    input,
                    &mut unchecked_state,
                    f1,
                    t1,
                )
            },
        };
        let (mut unchecked_out_state, mut unchecked_out) = (*state0, rsl_contact_loads::default());
        unchecked_out.reserved = 7;
        let unchecked_out_status = match body2 {
            // SAFETY: as above.
            Body2::Sphere(b2) => unsafe {
                rsl_contact_step_unchecked(
                    handle,
                    b1,
                    b2,
                    input,
                    &mut unchecked_out_state,
                    &mut unchecked_out,
                )
            },
            // SAFETY: as above.
            Body2::Wall(w) => unsafe {
                rsl_contact_step_wall_unchecked(
                    handle,
                    b1,
                    w,
                    input,
                    &mut unchecked_out_state,
                    &mut unchecked_out,
                )
            },
        };
        let checked_only = input.flags & !FAST_FLAGS != 0;
        // A wall normal the plain quotient cannot normalise is among what the unchecked
        // entries leave untested (the checked step rescales it first).
        let normalisable = match body2 {
            Body2::Sphere(_) => true,
            Body2::Wall(w) => crate::geometry::plain_unit_vector(&Vec3::from(w.normal)).1,
        };
        let same_as_checked = (status == RSL_OK && normalisable) || checked_only;
        if same_as_checked {
            assert_eq!(unchecked_status, status, "{what}: unchecked status");
            assert_eq!(bits(&unchecked_acc), bits(&acc), "{what}: unchecked loads");
            assert_eq!(
                state_bits(&unchecked_state),
                state_bits(&acc_state),
                "{what}: unchecked state"
            );
        } else {
            assert_eq!(unchecked_status, RSL_OK, "{what}: unchecked status");
            assert_eq!(unchecked_out_status, RSL_OK, "{what}: unchecked status");
        }
        let bits = |(status, s, o): &Run| {
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
                    e.elastic_rolling,
                    e.elastic_twisting,
                    e.dashpot_sliding,
                    e.dashpot_rolling,
                    e.dashpot_twisting,
                    e.slider_sliding,
                    e.slider_rolling,
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
        if same_as_checked {
            let unchecked = (unchecked_out_status, unchecked_out_state, unchecked_out);
            assert_eq!(
                bits(&unchecked),
                bits(&runs[0]),
                "{what}: unchecked and checked entries differ"
            );
        }
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
                let handle = rsl_model::live(model, contact_steps_built(avx2));
                for _ in 0..50 {
                    let mut c = case(&mut rng);
                    for _ in 0..3 {
                        assert_eq!(same(&handle, &c, "plain"), RSL_OK);
                        accepted += 1;
                        step_on(&handle, &mut c);
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
        assert_eq!(accepted, models().len() * 150 * levels);
        // NaN and +-inf (3 of the 5 values) are refused everywhere but +inf in `mass2` and
        // `inertia2` (a fixed body 2); -1 in most fields makes up for those two.
        assert!(refused >= 41 * 3 * 4 * levels, "only {refused} refusals");
    }

    /// The next step of `c` from its new state, through the entry (the fast path's).
    fn step_on(handle: &rsl_model, c: &mut Case) {
        let mut out = rsl_contact_loads::default();
        let (b1, body2, input, state) = c;
        // SAFETY: every pointer is to a live local of the right type; none overlap.
        let status = unsafe {
            match body2 {
                Body2::Sphere(b2) => rsl_contact_step(handle, b1, b2, input, state, &mut out),
                Body2::Wall(w) => rsl_contact_step_wall(handle, b1, w, input, state, &mut out),
            }
        };
        assert_eq!(status, RSL_OK);
    }

    /// Whether the fast path (portable test) takes `c` on `handle`'s model, stepping a copy.
    fn fast_path_takes(handle: &rsl_model, c: &Case) -> bool {
        let (b1, body2, input, state) = c;
        let mut state = *state;
        let mut out = rsl_contact_loads::default();
        // SAFETY: `out` is a live local, not overlapping anything.
        let sink = unsafe { LoadsOut::new(&mut out) };
        let model = &handle.model;
        match body2 {
            Body2::Sphere(b2) if input.flags == 0 => fast_pair_step::<_, _, false, true>(
                Portable, model, b1, b2, input, &mut state, sink,
            ),
            Body2::Sphere(b2) => {
                fast_pair_step::<_, _, true, true>(Portable, model, b1, b2, input, &mut state, sink)
            }
            Body2::Wall(w) => {
                fast_wall_step::<_, _, true>(Portable, model, b1, w, input, &mut state, sink)
            }
        }
    }

    /// The input's per-contact values, in the order of their flags' bits.
    fn values(c: &mut Case) -> [&mut f64; 9] {
        let i = &mut c.2;
        [
            &mut i.sliding_stiffness,
            &mut i.sliding_damping,
            &mut i.limit_force,
            &mut i.rolling_stiffness,
            &mut i.rolling_damping,
            &mut i.rolling_friction,
            &mut i.twisting_stiffness,
            &mut i.twisting_damping,
            &mut i.twisting_friction,
        ]
    }

    /// Per-contact coefficients and the limit force (every subset of their flags) take the
    /// fast path with the checked path's bits, pair and wall, at every build; a value the fast
    /// path does not take (negative, NaN, +-inf), the setup pass, a bond or an unknown flag
    /// gives the checked path's result or error and leaves the state.
    #[test]
    fn per_contact_values_and_walls_take_the_fast_path_with_the_checked_paths_bits() {
        let mut rng = Lcg(11);
        let (mut fast, mut other) = (0, 0);
        for avx2 in [false, true] {
            if avx2 && !Simd::Avx2.available() {
                continue;
            }
            for model in models() {
                let handle = rsl_model::live(model, contact_steps_built(avx2));
                for k in 0..120 {
                    let mut c = if k % 2 == 0 {
                        case(&mut rng)
                    } else {
                        wall_case(&mut rng)
                    };
                    // In range: each selected value a scale of the model's.
                    c.2.flags = rng.below(1 << 10) as u32 & FAST_FLAGS;
                    let scales = [2e5, 30.0, 150.0, 1e5, 10.0, 0.1, 50.0, 0.5, 0.05];
                    for (v, scale) in values(&mut c).into_iter().zip(scales) {
                        *v = scale * rng.uniform(0.0, 2.0);
                    }
                    for _ in 0..3 {
                        let what = format!("flags 0x{:x}", c.2.flags);
                        assert_eq!(same(&handle, &c, &what), RSL_OK, "{what}");
                        assert!(fast_path_takes(&handle, &c), "{what}: not the fast path");
                        fast += 1;
                        step_on(&handle, &mut c);
                    }
                    // Out of the fast path's range, or not its kind of input.
                    let mut bad = c;
                    let which = rng.below(9);
                    let flag = [1, 2, 8, 16, 32, 64, 128, 256, 512][which];
                    bad.2.flags |= flag;
                    let x = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, -0.0][k % 5];
                    *values(&mut bad)[which] = x;
                    let extra = [0, RSL_INPUT_SETUP, RSL_INPUT_SHEAR_ADHESION, 1 << 20][k % 4];
                    bad.2.flags |= extra;
                    let what = format!("flags 0x{:x}, value {which} = {x}", bad.2.flags);
                    same(&handle, &bad, &what);
                    if x == -0.0 && extra == 0 {
                        assert!(fast_path_takes(&handle, &bad), "{what}: not the fast path");
                    } else {
                        assert!(!fast_path_takes(&handle, &bad), "{what}: fast path");
                    }
                    other += 1;
                }
                // Every double of the wall, each bad value, and normals too short or too long
                // for the plain quotient (the checked path's rescaled form).
                for field in 0..12 {
                    for x in [f64::NAN, f64::INFINITY, -1.0, 0.0, 1e-200, 1e200] {
                        let mut c = wall_case(&mut rng);
                        let Body2::Wall(w) = &mut c.1 else {
                            unreachable!()
                        };
                        let v = [
                            &mut w.point,
                            &mut w.normal,
                            &mut w.velocity,
                            &mut w.angular_velocity,
                        ]
                        .into_iter()
                        .nth(field / 3)
                        .unwrap();
                        *[&mut v.x, &mut v.y, &mut v.z]
                            .into_iter()
                            .nth(field % 3)
                            .unwrap() = x;
                        same(&handle, &c, &format!("wall double {field} = {x}"));
                        other += 1;
                    }
                }
                for length in [1e-160, 1e-100, 1e100, 1e160] {
                    let mut c = wall_case(&mut rng);
                    let Body2::Wall(w) = &mut c.1 else {
                        unreachable!()
                    };
                    w.normal = (Vec3::from(w.normal).normalize() * length).into();
                    assert_eq!(
                        same(&handle, &c, &format!("normal length {length}")),
                        RSL_OK
                    );
                }
            }
        }
        assert!(fast > 0 && other > 0);
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
        let (b1, body2, input, state) = c;
        let Body2::Sphere(b2) = body2 else {
            unreachable!("pair cases only")
        };
        match i {
            0..=9 => sphere(b1, i),
            10..=19 => sphere(b2, i - 10),
            20..=22 => vec(&mut state.sliding_spring, i - 20),
            23..=25 => vec(&mut state.rolling_spring, i - 23),
            26 => &mut state.twisting_angle,
            27..=29 => vec(&mut state.model_memory, i - 27),
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
