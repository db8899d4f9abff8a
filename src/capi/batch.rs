//! Batch entry points: many contacts per call (`rsl_batch_step`, `rsl_batch_step_contacts`,
//! `rsl_batch_decompose`, `rsl_batch_decompose_contacts`): they check and borrow the arguments,
//! parse the options into the core's kernel choice ([`BatchConfig`], [`Simd`]: the kernels and
//! their run-time CPU dispatch are `batch::dispatch`'s) and fill the report.
//!
//! Data layout (particle-major calls): particles are an array of `rsl_sphere` (AoS: position,
//! velocity, angular velocity, radius: 80 bytes, one or two cache lines per particle, which is
//! what irregular gathers want); contacts are `uint32_t` index pairs `pairs[2c], pairs[2c+1]`
//! (body 1, body 2); forces and torques are `rsl_vec3` arrays per particle (LAMMPS' `f[i][3]`,
//! `torque[i][3]`), **accumulated** (`+=`), never cleared. Per-contact arrays (`normal_force`,
//! `states`) follow contact order.
#![allow(non_camel_case_types)]

pub use crate::layout::rsl_batch_loads;

use super::decompose::{parse_options, rsl_decompose_options};
use super::handle::{live_model, rsl_model};
use super::status::FfiError;
use super::types::{rsl_contact_energy, rsl_decomposition, rsl_sphere, rsl_vec3, rsl_wall};
use super::{guard, optional_input, output, slice_in, slice_out};
use crate::batch::dispatch::{run_decompose, run_history_step, run_step, BatchConfig, Simd};
use crate::batch::history::{
    history_layout, history_words, state_from_words as history_state_from_words, words_from_state,
    Record, NO_SLIDING, SPRINGS_ONLY, WITH_NORMAL, WITH_OFFAXIS,
};
use crate::batch::{
    needs_normal_stiffness, BatchReport, ContactDecompose, ContactStates, ContactSteps,
    DecomposeAccess, DecompositionSlot, EnergyTerms, IndexedGroups, IndexedStates, Materials,
    ModelSliding, OrderedOrIndexed, ParticleDecompose, ParticleSteps, SlidingOverrides,
    SlidingSource, StateSlot, WallSteps,
};
use crate::decompose::{Decomposition, Parts};
use crate::error::Error;
use crate::geometry::GeometryOptions;
use crate::laws::model::Model;
use crate::laws::step::ContactState;
use crate::layout::rsl_contact_state;

/// Precision: everything in double (default).
pub const RSL_PRECISION_F64: u32 = 0;
/// Precision: mixed single. Geometry (branch vector, distance, overlap, branch lengths) in
/// double from the double positions; rates, history transport and update, and loads in single;
/// histories stored in the caller's double state. Loses `v_r` to cancellation when
/// `|w| >> |w1 - w2|` (it is computed from `w1 - w2`, whose relative error in single is about
/// 6e-8 |w| / |w1 - w2|) and carries single rounding (~6e-8 relative) into the histories every
/// step.
pub const RSL_PRECISION_F32: u32 = 1;

/// SIMD: the widest level the CPU supports, in both precisions: AVX-512, then AVX2+FMA, then
/// scalar (the only level off x86-64).
pub const RSL_SIMD_AUTO: u32 = 0;
/// SIMD: none (one contact at a time; runs on any CPU, as SSE2 scalar code on x86-64).
pub const RSL_SIMD_SCALAR: u32 = 1;
/// SIMD: AVX2 + FMA (8 double lanes in two ymm registers for the steps, 4 in one for
/// `rsl_batch_decompose`, or 8 single lanes); x86-64 only,
/// `RSL_ERR_INVALID_ARGUMENT` if absent.
pub const RSL_SIMD_AVX2: u32 = 2;
/// SIMD: AVX-512 F/VL/DQ/BW (8 double lanes in one zmm register; single precision steps 16
/// lanes in one zmm, `rsl_batch_decompose` 8 in a ymm); x86-64 only, `RSL_ERR_INVALID_ARGUMENT`
/// if absent.
pub const RSL_SIMD_AVX512: u32 = 3;

/// Value of `rsl_batch_report.first_failed` when no contact failed.
pub const RSL_BATCH_NONE: u64 = u64::MAX;

/// How a batch runs. Zero-initialised (or NULL) is the default: double, best SIMD.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_batch_options {
    /// `RSL_PRECISION_F64` or `RSL_PRECISION_F32`.
    pub precision: u32,
    /// `RSL_SIMD_AUTO`, `RSL_SIMD_SCALAR`, `RSL_SIMD_AVX2` or `RSL_SIMD_AVX512`.
    pub simd: u32,
    /// Flags; none is defined in this version: keep 0 (`RSL_ERR_INVALID_ARGUMENT` otherwise).
    pub flags: u32,
    /// Padding; keep 0.
    pub reserved: u32,
}

/// What a batch call did. Written whenever the pointer is non-NULL and valid, also on failure:
/// a call-level error (NULL array, invalid model or time step...) processes nothing
/// (`processed = failed = 0`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_batch_report {
    /// Contacts processed (state and outputs written).
    pub processed: u64,
    /// Contacts skipped as invalid (state and outputs untouched).
    pub failed: u64,
    /// Index of the first skipped contact, `RSL_BATCH_NONE` if none.
    pub first_failed: u64,
    /// Status of the first skipped contact (what `rsl_contact_step` / `rsl_decompose` returns
    /// for it); `RSL_OK` if none.
    pub first_status: i32,
    /// The SIMD level that ran (`RSL_SIMD_SCALAR`, `RSL_SIMD_AVX2`, `RSL_SIMD_AVX512`).
    pub simd: u32,
    /// Padding.
    pub reserved: u32,
}

impl DecompositionSlot for rsl_decomposition {
    #[inline(always)]
    fn set(&mut self, d: &Decomposition<f64>) {
        *self = rsl_decomposition::from(d);
    }
}

// The C option codes of the core's kernel choice (`batch::dispatch`).

impl Simd {
    /// The level for an `RSL_SIMD_*` code: `AUTO` picks the best available; asking for a level
    /// the CPU lacks is an error.
    pub fn resolve(code: u32) -> Result<Simd, Error> {
        let wanted = match code {
            RSL_SIMD_AUTO => return Ok(Simd::best()),
            RSL_SIMD_SCALAR => Simd::Scalar,
            RSL_SIMD_AVX2 => Simd::Avx2,
            RSL_SIMD_AVX512 => Simd::Avx512,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "simd {other} is not an RSL_SIMD_* code"
                )))
            }
        };
        if wanted.available() {
            Ok(wanted)
        } else {
            Err(Error::InvalidArgument(format!(
                "simd level {wanted:?} is not supported by this CPU"
            )))
        }
    }

    /// The `RSL_SIMD_*` code.
    pub fn code(self) -> u32 {
        match self {
            Simd::Scalar => RSL_SIMD_SCALAR,
            Simd::Avx2 => RSL_SIMD_AVX2,
            Simd::Avx512 => RSL_SIMD_AVX512,
        }
    }
}

impl BatchConfig {
    /// Validates C options (NULL: defaults).
    pub fn from_options(o: Option<&rsl_batch_options>) -> Result<BatchConfig, Error> {
        let o = o.copied().unwrap_or_default();
        let f32 = match o.precision {
            RSL_PRECISION_F64 => false,
            RSL_PRECISION_F32 => true,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "precision {other} is not RSL_PRECISION_F64 (0) or RSL_PRECISION_F32 (1)"
                )))
            }
        };
        if o.flags != 0 {
            return Err(Error::InvalidArgument(format!(
                "batch flags 0x{:x} has unknown bits",
                o.flags
            )));
        }
        // `RSL_SIMD_AUTO`: the widest level the CPU has, for both precisions (`Simd::best`).
        let simd = Simd::resolve(o.simd)?;
        Ok(BatchConfig { f32, simd })
    }
}

/// A call-level error (nothing processed): the report, if any, says so with the error's status.
fn refuse(report: Option<&mut rsl_batch_report>, e: FfiError) -> Result<(), FfiError> {
    if let Some(r) = report {
        *r = rsl_batch_report {
            first_failed: RSL_BATCH_NONE,
            first_status: e.code(),
            ..Default::default()
        };
    }
    Err(e)
}

/// Writes the report (if requested) and maps a partial failure to the first failing status.
fn finish(
    report: Option<&mut rsl_batch_report>,
    result: Result<(BatchReport, Simd), Error>,
) -> Result<(), FfiError> {
    match result {
        Err(e) => refuse(report, FfiError::Core(e)),
        Ok((b, simd)) => {
            let first_status = b
                .first_error
                .as_ref()
                .map_or(super::status::RSL_OK, |e| FfiError::Core(e.clone()).code());
            if let Some(r) = report {
                *r = rsl_batch_report {
                    processed: b.processed as u64,
                    failed: b.failed as u64,
                    first_failed: b.first_failed.map_or(RSL_BATCH_NONE, |i| i as u64),
                    first_status,
                    simd: simd.code(),
                    reserved: 0,
                };
            }
            // `None` returns before anything is dropped: a drop of the whole `Option<Error>`
            // (its `_` arm) let LLVM test the payload's string capacity before the
            // discriminant, which valgrind reports as a jump on uninitialised memory when the
            // option is `None` (harmless: both ways lead to no free, but it fails the memcheck).
            let Some(e) = b.first_error else {
                return Ok(());
            };
            match b.first_failed {
                Some(_) => Err(FfiError::Core(e)),
                None => Ok(()),
            }
        }
    }
}

/// Optional report pointer.
///
/// # Safety
/// `p` must be NULL or point to a writable `rsl_batch_report`.
unsafe fn report_out<'a>(
    p: *mut rsl_batch_report,
) -> Result<Option<&'a mut rsl_batch_report>, FfiError> {
    if p.is_null() {
        Ok(None)
    } else {
        // SAFETY: forwarded contract.
        unsafe { output(p, "report") }.map(Some)
    }
}

/// The per-contact `k_n` array of a step call: required (`n` values) when the model reads
/// `k_n` and there are contacts, else optional (NULL gives `None`).
///
/// # Safety
/// `normal_stiffness` is NULL or points to `n` readable doubles.
unsafe fn stiffness_in<'a>(
    m: &rsl_model,
    normal_stiffness: *const f64,
    n: usize,
) -> Result<Option<&'a [f64]>, FfiError> {
    if normal_stiffness.is_null() {
        if needs_normal_stiffness(&m.model) && n > 0 {
            return Err(FfiError::NullPointer(
                "normal_stiffness (the model needs k_n)",
            ));
        }
        Ok(None)
    } else {
        // SAFETY: forwarded contract.
        Some(unsafe { slice_in(normal_stiffness, n, "normal_stiffness") }).transpose()
    }
}

/// The per-contact coefficients of a `*_params` call (`params` NULL, or each of its arrays NULL
/// or holding `n` values): the arrays, and the model's table of material pairs for `material`.
///
/// # Safety
/// `params` NULL or readable; its non-NULL arrays hold `n` values.
unsafe fn sliding_in<'a>(
    m: &'a rsl_model,
    params: *const rsl_batch_contact_params,
    n: usize,
) -> Result<SlidingOverrides<'a>, FfiError> {
    // SAFETY: forwarded contract; `optional_input` checks NULL and alignment.
    let Some(p) = (unsafe { optional_input(params, "params")? }) else {
        return Ok(SlidingOverrides::NONE);
    };
    let optional = |a: *const f64, name| {
        if a.is_null() {
            Ok(None)
        } else {
            // SAFETY: forwarded contract: a non-NULL array holds `n` values.
            unsafe { slice_in(a, n, name) }.map(Some)
        }
    };
    let materials = if p.material.is_null() {
        None
    } else {
        Some(Materials {
            table: &m.materials,
            // SAFETY: forwarded contract: a non-NULL array holds `n` values.
            index: unsafe { slice_in(p.material, n, "params.material")? },
        })
    };
    Ok(SlidingOverrides {
        stiffness: optional(p.sliding_stiffness, "params.sliding_stiffness")?,
        damping: optional(p.sliding_damping, "params.sliding_damping")?,
        materials,
    })
}

/// The energy output of a `*_params` call (`params.energy`, NULL or `n` writable structs),
/// which needs a model that tracks energy (`track_energy`).
///
/// # Safety
/// `params` NULL or readable; a non-NULL `energy` holds `n` writable structs that overlap no
/// other array of the call.
unsafe fn energy_in<'e>(
    track_energy: bool,
    params: *const rsl_batch_contact_params,
    n: usize,
) -> Result<Option<&'e mut [EnergyTerms]>, FfiError> {
    // SAFETY: forwarded contract; `optional_input` checks NULL and alignment.
    let Some(p) = (unsafe { optional_input(params, "params")? }) else {
        return Ok(None);
    };
    if p.energy.is_null() {
        return Ok(None);
    }
    if !track_energy {
        return Err(FfiError::Core(Error::InvalidArgument(
            "params.energy needs a model that tracks energy (rsl_model_set_energy_tracking)"
                .to_string(),
        )));
    }
    // SAFETY: forwarded contract: a non-NULL `energy` holds `n` writable structs.
    let structs: &'e mut [rsl_contact_energy] = unsafe { slice_out(p.energy, n, "params.energy")? };
    // SAFETY: `rsl_contact_energy` is `repr(C)` with eleven `f64` fields and nothing else
    // (asserted below), so it has the size, alignment and layout of `[f64; 11]`, in the order
    // of `EnergyTerms`; the slice keeps the borrow of `structs`.
    Ok(Some(unsafe {
        std::slice::from_raw_parts_mut(structs.as_mut_ptr().cast::<EnergyTerms>(), n)
    }))
}

// `rsl_contact_energy` is eleven doubles in the order of `EnergyTerms` (the cast in `energy_in`).
const _: () = {
    assert!(size_of::<rsl_contact_energy>() == size_of::<EnergyTerms>());
    assert!(align_of::<rsl_contact_energy>() == align_of::<EnergyTerms>());
    assert!(std::mem::offset_of!(rsl_contact_energy, elastic_sliding) == 0);
    assert!(std::mem::offset_of!(rsl_contact_energy, elastic_rolling) == 8);
    assert!(std::mem::offset_of!(rsl_contact_energy, elastic_twisting) == 16);
    assert!(std::mem::offset_of!(rsl_contact_energy, dashpot_sliding) == 24);
    assert!(std::mem::offset_of!(rsl_contact_energy, dashpot_rolling) == 32);
    assert!(std::mem::offset_of!(rsl_contact_energy, dashpot_twisting) == 40);
    assert!(std::mem::offset_of!(rsl_contact_energy, slider_sliding) == 48);
    assert!(std::mem::offset_of!(rsl_contact_energy, slider_rolling) == 56);
    assert!(std::mem::offset_of!(rsl_contact_energy, slider_twisting) == 64);
    assert!(std::mem::offset_of!(rsl_contact_energy, transport) == 72);
    assert!(std::mem::offset_of!(rsl_contact_energy, stiffness_change) == 80);
};

/// The checked arguments of a particle-major step call, but its per-contact histories.
struct ParticleArgs<'a> {
    model: &'a rsl_model,
    particles: &'a [rsl_sphere],
    pairs: &'a [[u32; 2]],
    normal_force: &'a [f64],
    normal_stiffness: Option<&'a [f64]>,
    config: BatchConfig,
    force: &'a mut [rsl_vec3],
    torque: &'a mut [rsl_vec3],
}

/// Checks and borrows the arguments shared by `rsl_batch_step` and `rsl_batch_step_history`.
///
/// # Safety
/// As those functions' contracts for these arguments.
#[allow(clippy::too_many_arguments)]
unsafe fn particle_args<'a>(
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    pairs: *const u32,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    options: *const rsl_batch_options,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
) -> Result<ParticleArgs<'a>, FfiError> {
    // SAFETY: forwarded contract; every helper checks NULL and alignment; `[u32; 2]` has the
    // size and alignment of two `u32`.
    let (m, particles, pairs, f_n, opts, force, torque) = unsafe {
        (
            live_model(model)?,
            slice_in(particles, n_particles, "particles")?,
            slice_in(pairs as *const [u32; 2], n_contacts, "pairs")?,
            slice_in(normal_force, n_contacts, "normal_force")?,
            optional_input(options, "options")?,
            slice_out(force, n_particles, "force")?,
            slice_out(torque, n_particles, "torque")?,
        )
    };
    // SAFETY: as above.
    let k_n = unsafe { stiffness_in(m, normal_stiffness, n_contacts)? };
    Ok(ParticleArgs {
        model: m,
        particles,
        pairs,
        normal_force: f_n,
        normal_stiffness: k_n,
        config: BatchConfig::from_options(opts)?,
        force,
        torque,
    })
}

/// Steps many sphere-sphere contacts (particle-major). Contact `c` joins particles
/// `pairs[2c]` (body 1) and `pairs[2c+1]` (body 2); its normal force is `normal_force[c]`
/// (signed: compressive positive, tensile negative) and its history `states[c]`. The loads
/// are **added** to the particle arrays: `force[i] += F1`, `force[j] -= F1`,
/// `torque[i] += M1`, `torque[j] += M2` (in contact order, so the sums do not depend on the
/// SIMD level). `normal_stiffness` (per contact, k_n > 0) is
/// read only when the model needs it (EPSD-derived rolling stiffness, LIGGGHTS' cdt) and may
/// be NULL otherwise. `options` may be NULL (double, best SIMD). `report` may be NULL.
///
/// Same physics as `rsl_contact_step` with `normal_force` and `dt` set (no per-contact
/// parameter overrides, no limit force, no setup pass); a model with damping-ratio rolling
/// damping is refused. The energy terms are not returned: a model that tracks energy has them
/// computed and checked finite, as `rsl_contact_step` does (turn tracking off for the batch if
/// they are not wanted).
///
/// Speed: a call whose arrays take at least 1 MiB in all (counting at most two particles per
/// contact of `particles`, `force` and `torque`: a call on a chunk of a large scene touches only
/// those) prefetches each contact's state and bodies 48 contacts ahead; a smaller call, whose
/// data is most likely in cache already, does not (the prefetches would only cost
/// instructions). The results are the same either way.
///
/// Invalid contacts (index out of range, non-finite input or state, radius <= 0, coincident
/// centres, branch <= 0, non-finite result, energy terms included) are
/// skipped in the same pass: their state and loads are not written; every other contact is
/// processed. The call then returns the status `rsl_contact_step` would give for the first
/// skipped contact, and `report` gives its index and the number skipped. `RSL_OK` means every
/// contact was processed.
/// Call-level errors (NULL array, invalid handle or model, dt, options) process nothing.
///
/// # Safety
/// Every array must hold the stated number of elements (`particles`, `force`, `torque`:
/// `n_particles`; `pairs`: `2 n_contacts`; the others `n_contacts`); NULL only for an empty
/// array. `states`, `force`, `torque` and `report` must not overlap each other or any input.
/// The model must not be modified during the call.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_step(
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    pairs: *const u32,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    dt: f64,
    options: *const rsl_batch_options,
    states: *mut rsl_contact_state,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
    report: *mut rsl_batch_report,
) -> i32 {
    // SAFETY: forwarded contract; no per-contact coefficients.
    unsafe {
        rsl_batch_step_params(
            model,
            particles,
            n_particles,
            pairs,
            n_contacts,
            normal_force,
            normal_stiffness,
            std::ptr::null(),
            dt,
            options,
            states,
            force,
            torque,
            report,
        )
    }
}

/// As `rsl_batch_step`, with per-contact sliding coefficients (`params`, NULL for none, as
/// `rsl_batch_step_contacts_params` takes them): contact `c` (particles `pairs[2c]` and
/// `pairs[2c+1]`) uses `params->sliding_stiffness[c]` and `params->sliding_damping[c]` (each
/// array NULL for the model's value) instead of the model's `k_t` and `gamma_t`, e.g. the
/// contact-area-dependent coefficients of Hertz-Mindlin laws. A contact whose `k_t` or
/// `gamma_t` is negative or not finite is skipped as invalid (status `RSL_ERR_INVALID_ARGUMENT`
/// or `RSL_ERR_NON_FINITE`, as `rsl_contact_step` gives). In double precision the results equal
/// `rsl_contact_step`'s with `RSL_INPUT_SLIDING_STIFFNESS` and `RSL_INPUT_SLIDING_DAMPING` bit
/// for bit, added to `force` and `torque` in contact order. Without per-contact arrays it runs
/// the kernels of `rsl_batch_step`.
///
/// # Safety
/// As `rsl_batch_step`; `params` NULL or readable, its non-NULL arrays holding `n_contacts`
/// values.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_step_params(
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    pairs: *const u32,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    params: *const rsl_batch_contact_params,
    dt: f64,
    options: *const rsl_batch_options,
    states: *mut rsl_contact_state,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
    report: *mut rsl_batch_report,
) -> i32 {
    // SAFETY: forwarded contract of this function; `slice_out` checks NULL and alignment.
    unsafe {
        particle_call(
            model,
            particles,
            n_particles,
            pairs,
            n_contacts,
            normal_force,
            normal_stiffness,
            params,
            dt,
            options,
            force,
            torque,
            report,
            || slice_out(states, n_contacts, "states"),
        )
    }
}

/// The shared body of the particle-major entries with per-contact coefficients: checks and
/// borrows the arguments (`states` those of the histories), steps the contacts and fills the
/// report; a call-level error processes nothing.
///
/// # Safety
/// As `rsl_batch_step_params`' contract for the arguments given here; `states` may rely on
/// its caller's contract.
#[allow(clippy::too_many_arguments)]
unsafe fn particle_call<St: ContactStates<Slot = rsl_contact_state>>(
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    pairs: *const u32,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    params: *const rsl_batch_contact_params,
    dt: f64,
    options: *const rsl_batch_options,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
    report: *mut rsl_batch_report,
    states: impl FnOnce() -> Result<St, FfiError>,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract of this function; every helper checks NULL and alignment.
        let report = unsafe { report_out(report)? };
        let result = (|| -> Result<_, FfiError> {
            // SAFETY: forwarded contract of this function.
            let a = unsafe {
                particle_args(
                    model,
                    particles,
                    n_particles,
                    pairs,
                    n_contacts,
                    normal_force,
                    normal_stiffness,
                    options,
                    force,
                    torque,
                )?
            };
            let states = states()?;
            // SAFETY: as above.
            let sliding = unsafe { sliding_in(a.model, params, n_contacts)? };
            // SAFETY: as above.
            let energy = unsafe { energy_in(a.model.model.track_energy, params, n_contacts)? };
            Ok((a, states, sliding, energy))
        })();
        match result {
            Err(e) => refuse(report, e),
            Ok((a, states, sliding, energy)) => {
                step_particles(a, states, sliding, energy, dt, report)
            }
        }
    })
}

/// Steps the checked arguments of a particle-major call with the states `states`, the
/// per-contact coefficients `sliding` (the model's kernels when it has none) and the energy
/// output `energy`, and fills the report.
fn step_particles<St: ContactStates<Slot = rsl_contact_state>>(
    a: ParticleArgs<'_>,
    states: St,
    sliding: SlidingOverrides<'_>,
    energy: Option<&mut [EnergyTerms]>,
    dt: f64,
    report: Option<&mut rsl_batch_report>,
) -> Result<(), FfiError> {
    /// Steps with coefficients from `sliding`.
    fn run<St: ContactStates<Slot = rsl_contact_state>, O: SlidingSource>(
        a: ParticleArgs<'_>,
        states: St,
        sliding: O,
        energy: Option<&mut [EnergyTerms]>,
        dt: f64,
    ) -> Result<BatchReport, FfiError> {
        let mut access = ParticleSteps {
            particles: a.particles,
            pairs: a.pairs,
            normal_force: a.normal_force,
            normal_stiffness: a.normal_stiffness,
            states,
            force: a.force,
            torque: a.torque,
            sliding,
            energy,
        };
        access.check()?;
        Ok(run_step(&a.model.model, dt, &mut access, a.config)?)
    }
    let simd = a.config.simd;
    let stepped = if sliding.stiffness.is_none()
        && sliding.damping.is_none()
        && sliding.materials.is_none()
    {
        run(a, states, ModelSliding, energy, dt)
    } else {
        run(a, states, sliding, energy, dt)
    };
    match stepped {
        Err(e) => refuse(report, e),
        Ok(b) => finish(report, Ok((b, simd))),
    }
}

/// As `rsl_batch_step_params`, with each contact's history read and written where the host
/// keeps it: contact `c`'s state is `states[state_index[c]]`, in an array of `n_states`
/// states (e.g. one per neighbour-list entry, as LAMMPS' and LIGGGHTS' granular styles keep
/// their histories), so that a host steps the touching pairs of its neighbour lists without
/// copying their histories into a buffer of `n_contacts` states and back. The indices must be
/// strictly increasing (each greater than the one before, as a host's touching pairs come in
/// neighbour-list order) and below `n_states`: otherwise the call returns
/// `RSL_ERR_INVALID_ARGUMENT` and processes nothing. The states not indexed are not read or
/// written. Everything else (physics, validation, skipping, the report's contact indices,
/// the order of the additions, the kernels) is that of `rsl_batch_step_params`, whose loads
/// and states this call reproduces bit for bit.
///
/// # Safety
/// As `rsl_batch_step_params`, with `states` holding `n_states` states and `state_index`
/// `n_contacts` indices (NULL only for an empty array); `states` must not overlap any other
/// array.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_step_indexed(
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    pairs: *const u32,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    params: *const rsl_batch_contact_params,
    dt: f64,
    options: *const rsl_batch_options,
    states: *mut rsl_contact_state,
    n_states: usize,
    state_index: *const usize,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
    report: *mut rsl_batch_report,
) -> i32 {
    // SAFETY: forwarded contract of this function; `slice_out` and `slice_in` check NULL and
    // alignment.
    unsafe {
        particle_call(
            model,
            particles,
            n_particles,
            pairs,
            n_contacts,
            normal_force,
            normal_stiffness,
            params,
            dt,
            options,
            force,
            torque,
            report,
            || {
                let slots = slice_out(states, n_states, "states")?;
                let index = slice_in(state_index, n_contacts, "state_index")?;
                Ok(IndexedGroups::from(IndexedStates::new(slots, index)?))
            },
        )
    }
}

/// Steps many sphere-wall contacts (particle-major), each one as `rsl_contact_step_wall`
/// steps it: contact `c` is particle `spheres[c]` (body 1) against the flat wall `walls[c]`
/// (body 2: its point, outward normal of any non-zero length, velocity and angular velocity;
/// each contact its own, so one call takes the contacts of several walls), with normal force
/// `normal_force[c]` (compressive positive). The loads are **added** to the particle's
/// accumulators, `force[i] += F1`, `torque[i] += M1`, in contact order; the wall receives
/// nothing. `normal_stiffness`, `params` (per-contact `k_t`, `gamma_t`, material pairs, energy
/// output), `options`, `report`, the validation and skipping of invalid contacts, and the
/// prefetching rule are those of `rsl_batch_step_params`; mixed materials come through the
/// model's table (`params->material`).
///
/// Histories: with `state_index` NULL, contact `c`'s state is `states[c]` (`n_states` at least
/// `n_contacts`; the states past them are not touched); otherwise it is
/// `states[state_index[c]]`, with the indices strictly increasing and below `n_states` (e.g. one
/// history per particle, as LAMMPS' `fix wall/gran` keeps them; `RSL_ERR_INVALID_ARGUMENT`
/// otherwise, nothing processed).
///
/// In double precision the loads and states equal `rsl_contact_step_wall_accumulate`'s with
/// `RSL_INPUT_SLIDING_STIFFNESS` / `RSL_INPUT_SLIDING_DAMPING` set from `params` bit for bit,
/// at every SIMD level, added in the same order. Not taken here (use the per-contact call): the
/// setup pass, bonds, a limit force, and per-contact rolling or twisting coefficients.
///
/// # Safety
/// Every array must hold the stated number of elements (`particles`, `force`, `torque`:
/// `n_particles`; `states`: `n_states`; `spheres`, `walls`, `state_index` and the others:
/// `n_contacts`); NULL only for an empty array (`state_index` may be NULL). `states`, `force`,
/// `torque`, `report` and `params->energy` must not overlap each other or any input. The model
/// must not be modified during the call.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_step_walls(
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    spheres: *const u32,
    walls: *const rsl_wall,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    params: *const rsl_batch_contact_params,
    dt: f64,
    options: *const rsl_batch_options,
    states: *mut rsl_contact_state,
    n_states: usize,
    state_index: *const usize,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
    report: *mut rsl_batch_report,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract of this function; every helper checks NULL and alignment.
        let report = unsafe { report_out(report)? };
        let result = (|| -> Result<_, FfiError> {
            // SAFETY: as above.
            let (m, particles, spheres, walls, f_n, opts, force, torque) = unsafe {
                (
                    live_model(model)?,
                    slice_in(particles, n_particles, "particles")?,
                    slice_in(spheres, n_contacts, "spheres")?,
                    slice_in(walls, n_contacts, "walls")?,
                    slice_in(normal_force, n_contacts, "normal_force")?,
                    optional_input(options, "options")?,
                    slice_out(force, n_particles, "force")?,
                    slice_out(torque, n_particles, "torque")?,
                )
            };
            // SAFETY: as above.
            let k_n = unsafe { stiffness_in(m, normal_stiffness, n_contacts)? };
            let config = BatchConfig::from_options(opts)?;
            // SAFETY: as above.
            let slots = unsafe { slice_out(states, n_states, "states")? };
            let states = if state_index.is_null() {
                if n_states < n_contacts {
                    return Err(FfiError::Core(Error::InvalidArgument(
                        "n_states is smaller than n_contacts (state_index NULL)".to_string(),
                    )));
                }
                OrderedOrIndexed::Ordered(&mut slots[..n_contacts])
            } else {
                // SAFETY: as above.
                let index = unsafe { slice_in(state_index, n_contacts, "state_index")? };
                OrderedOrIndexed::Indexed(IndexedGroups::from(IndexedStates::new(slots, index)?))
            };
            // SAFETY: as above.
            let sliding = unsafe { sliding_in(m, params, n_contacts)? };
            // SAFETY: as above.
            let energy = unsafe { energy_in(m.model.track_energy, params, n_contacts)? };
            let access = WallSteps {
                particles,
                spheres,
                walls,
                normal_force: f_n,
                normal_stiffness: k_n,
                states,
                force,
                torque,
                sliding,
                energy,
            };
            access.check()?;
            Ok((m, access, config))
        })();
        match result {
            Err(e) => refuse(report, e),
            Ok((m, mut access, config)) => finish(
                report,
                run_step(&m.model, dt, &mut access, config).map(|b| (b, config.simd)),
            ),
        }
    })
}

/// Doubles per contact of `model`'s packed history, for `rsl_batch_step_history`. The record
/// holds the fields of `rsl_contact_state` the model's step reads, in this order: the sliding
/// spring (3; left out when the model has no sliding law, `RSL_SLIDING_NONE`), the rolling
/// spring (3), the twisting angle (1), the previous normal (3; kept when a transport reads it:
/// `RSL_TRANSPORT_EXACT` or `RSL_TRANSPORT_FIRST_ORDER`, as in the objective default; not with
/// `RSL_TRANSPORT_PROJECT_RESCALE`, `RSL_TRANSPORT_PROJECT` or `RSL_TRANSPORT_NONE`, as in the
/// LAMMPS_2021 and LIGGGHTS_3_8 presets), the model memory (3; the YADE_2023 preset, which
/// keeps its twisting moment as a vector, and a model that tracks energy or has a rescaled
/// sliding history, which keeps the previous stiffnesses there; the previous normal is then
/// kept too). So, with a sliding law: 7 words for the LAMMPS and LIGGGHTS presets, 10 for the
/// objective one, 13 for YADE and for any model with a memory; without one, 4, 7 and 10. The
/// size follows the model's sliding law and history, preset, transports and energy tracking:
/// ask for it after the
/// model's last change, and repack (`rsl_history_to_state`, then `rsl_history_from_state`
/// with the new model) if one of these changes.
/// Writes `*words` on success.
///
/// # Safety
/// `model` must be a live model; `words` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_history_size(model: *const rsl_model, words: *mut usize) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; helpers check NULL and alignment.
        let (m, out) = unsafe { (live_model(model)?, output(words, "words")?) };
        *out = history_words(&m.model);
        Ok(())
    })
}

/// Packs `state` into `model`'s history record (`rsl_model_history_size` doubles written to
/// `history`; the state's other fields and its slip flags are dropped). With
/// `rsl_history_to_state`, a host can move a contact between `rsl_contact_step` and
/// `rsl_batch_step_history`.
///
/// # Safety
/// `model` must be a live model; `state` readable; `history` NULL or writable for the
/// record's doubles.
#[no_mangle]
pub unsafe extern "C" fn rsl_history_from_state(
    model: *const rsl_model,
    state: *const rsl_contact_state,
    history: *mut f64,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; helpers check NULL, alignment and size.
        let (m, state) = unsafe { (live_model(model)?, slice_in(state, 1, "state")?) };
        let layout = history_layout(&m.model);
        // SAFETY: as above: `history` holds the record's `layout.words` doubles.
        let out = unsafe { slice_out(history, layout.words, "history")? };
        words_from_state(&ContactState::from(&state[0]), layout, out);
        Ok(())
    })
}

/// Unpacks `model`'s history record (`rsl_model_history_size` doubles) into `state`: the
/// record's fields are copied, the others (the sliding spring, the previous normal and the
/// model memory when the record does not keep them, the slip flags) are set to zero.
///
/// # Safety
/// `model` must be a live model; `history` readable for the record's doubles; `state` NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn rsl_history_to_state(
    model: *const rsl_model,
    history: *const f64,
    state: *mut rsl_contact_state,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; helpers check NULL, alignment and size.
        let m = unsafe { live_model(model)? };
        let layout = history_layout(&m.model);
        // SAFETY: as above.
        let (words, out) = unsafe {
            (
                slice_in(history, layout.words, "history")?,
                output(state, "state")?,
            )
        };
        let s = history_state_from_words(layout, words).ok_or(FfiError::Core(
            Error::InvalidArgument("a history record of an unknown size".to_string()),
        ))?;
        *out = rsl_contact_state::default();
        StateSlot::store(out, &s, 0);
        Ok(())
    })
}

/// As `rsl_batch_step`, with each contact's history packed: `history` holds
/// `n_contacts * rsl_model_history_size(model)` doubles, contact `c`'s record at
/// `history + c * size` (see `rsl_model_history_size` for its layout; `rsl_history_from_state`
/// packs a `rsl_contact_state`). The records keep only what the step reads, so there is less
/// memory to move: for the LAMMPS_2021 preset 56 bytes per contact instead of the 112 of a
/// `rsl_contact_state` (up to 7% less time per contact on the benchmark's host), 32 without a
/// sliding law (another 5% less for rolling + twisting: docs/performance.md).
/// Slip flags are not kept. Everything else (physics, validation, skipping, report, the order
/// of the additions) is that of `rsl_batch_step`, whose loads and new histories this call
/// reproduces bit for bit in double precision (with the state's other fields zero).
///
/// # Safety
/// As `rsl_batch_step`, with `history` in place of `states` (`n_contacts` records).
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_step_history(
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    pairs: *const u32,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    dt: f64,
    options: *const rsl_batch_options,
    history: *mut f64,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
    report: *mut rsl_batch_report,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract of this function; every helper checks NULL and alignment.
        let report = unsafe { report_out(report)? };
        let result = (|| -> Result<_, FfiError> {
            // SAFETY: forwarded contract of this function.
            let a = unsafe {
                particle_args(
                    model,
                    particles,
                    n_particles,
                    pairs,
                    n_contacts,
                    normal_force,
                    normal_stiffness,
                    options,
                    force,
                    torque,
                )?
            };
            let words = history_words(&a.model.model);
            let doubles =
                n_contacts
                    .checked_mul(words)
                    .ok_or(FfiError::Core(Error::InvalidArgument(
                        "n_contacts times the history size overflows".to_string(),
                    )))?;
            // SAFETY: as above: `history` holds `n_contacts` records of `words` doubles.
            let history = unsafe { slice_out(history, doubles, "history")? };
            Ok((a, history))
        })();
        match result {
            Err(e) => refuse(report, e),
            Ok((a, history)) => {
                /// Steps the records as `W`-word records from full-layout word `F`.
                #[allow(clippy::too_many_arguments)]
                fn run<const W: usize, const F: usize>(
                    model: &Model,
                    dt: f64,
                    particles: &[rsl_sphere],
                    pairs: &[[u32; 2]],
                    f_n: &[f64],
                    k_n: Option<&[f64]>,
                    history: &mut [f64],
                    force: &mut [rsl_vec3],
                    torque: &mut [rsl_vec3],
                    config: BatchConfig,
                ) -> Result<BatchReport, Error> {
                    let (records, rest) = history.as_chunks_mut::<W>();
                    debug_assert!(rest.is_empty(), "whole records");
                    // SAFETY: `Record<W, F>` is `repr(transparent)` over `[f64; W]`.
                    let states = unsafe {
                        std::slice::from_raw_parts_mut(
                            records.as_mut_ptr().cast::<Record<W, F>>(),
                            records.len(),
                        )
                    };
                    let mut access = ParticleSteps {
                        particles,
                        pairs,
                        normal_force: f_n,
                        normal_stiffness: k_n,
                        states,
                        force,
                        torque,
                        sliding: ModelSliding,
                        energy: None,
                    };
                    access.check()?;
                    run_history_step(model, dt, &mut access, config)
                }
                let (model, config) = (&a.model.model, a.config);
                let (p, q, f, k) = (a.particles, a.pairs, a.normal_force, a.normal_stiffness);
                let (h, fo, t) = (history, a.force, a.torque);
                const N: usize = NO_SLIDING;
                let layout = history_layout(model);
                let result = match (layout.first, layout.first + layout.words) {
                    (0, SPRINGS_ONLY) => {
                        run::<SPRINGS_ONLY, 0>(model, dt, p, q, f, k, h, fo, t, config)
                    }
                    (0, WITH_NORMAL) => {
                        run::<WITH_NORMAL, 0>(model, dt, p, q, f, k, h, fo, t, config)
                    }
                    (0, _) => run::<WITH_OFFAXIS, 0>(model, dt, p, q, f, k, h, fo, t, config),
                    (_, SPRINGS_ONLY) => {
                        run::<{ SPRINGS_ONLY - N }, N>(model, dt, p, q, f, k, h, fo, t, config)
                    }
                    (_, WITH_NORMAL) => {
                        run::<{ WITH_NORMAL - N }, N>(model, dt, p, q, f, k, h, fo, t, config)
                    }
                    _ => run::<{ WITH_OFFAXIS - N }, N>(model, dt, p, q, f, k, h, fo, t, config),
                };
                finish(report, result.map(|b| (b, config.simd)))
            }
        }
    })
}

/// Per-contact coefficients of `rsl_batch_step_params`, `rsl_batch_step_indexed` and
/// `rsl_batch_step_contacts_params`, used instead of the model's: each pointer is NULL (the
/// model's value for every contact) or an array of one value per contact.
///
/// - `material`: each contact's material pair, an index into the model's table of coefficient
///   sets (`rsl_model_set_materials`), as LAMMPS' `pair_coeff` per type pair: the contact steps
///   as `rsl_contact_step` does with that set's model, bit for bit in double precision. A
///   contact whose index is not below the table's size (any index, for a model without a
///   table) is skipped with `RSL_ERR_INVALID_ARGUMENT`, as one with a particle index out of
///   range.
/// - `sliding_stiffness`, `sliding_damping`: `k_t` and `gamma_t` for laws whose coefficients
///   depend on the contact, such as the contact-area-dependent ones of Hertz-Mindlin (as
///   `rsl_contact_step` uses them with `RSL_INPUT_SLIDING_STIFFNESS` and
///   `RSL_INPUT_SLIDING_DAMPING`); they win over the contact's material set for those two.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct rsl_batch_contact_params {
    /// Sliding stiffness `k_t` per contact (force/length, finite, >= 0), or NULL.
    pub sliding_stiffness: *const f64,
    /// Sliding damping `gamma_t` per contact (force/velocity, finite, >= 0), or NULL.
    pub sliding_damping: *const f64,
    /// Material pair per contact (an index into the model's table), or NULL.
    pub material: *const u32,
    /// Output, or NULL: each stepped contact's energy terms (`rsl_contact_energy`, as
    /// `rsl_contact_step` returns them; one per contact in contact order), for a model that
    /// tracks energy (`rsl_model_set_energy_tracking`; `RSL_ERR_INVALID_ARGUMENT` otherwise).
    /// A skipped contact's entry is not written. Must not overlap any other array of the call.
    pub energy: *mut rsl_contact_energy,
}

/// Steps many sphere-sphere contacts (contact-major): contact `c` is `body1[c]`, `body2[c]`,
/// `normal_force[c]`, `states[c]`, and its loads are **written** to `out[c]`. No two contacts
/// share an output, so ranges of contacts can run on different threads. Otherwise as
/// `rsl_batch_step` (same validation, skipping, report and prefetching rule).
///
/// # Safety
/// Every array must hold `n` elements (NULL only when `n = 0`); `states`, `out` and `report`
/// must not overlap each other or any input. The model must not be modified during the call.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_step_contacts(
    model: *const rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    n: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    dt: f64,
    options: *const rsl_batch_options,
    states: *mut rsl_contact_state,
    out: *mut rsl_batch_loads,
    report: *mut rsl_batch_report,
) -> i32 {
    // SAFETY: forwarded contract; no per-contact coefficients.
    unsafe {
        rsl_batch_step_contacts_params(
            model,
            body1,
            body2,
            n,
            normal_force,
            normal_stiffness,
            std::ptr::null(),
            dt,
            options,
            states,
            out,
            report,
        )
    }
}

/// As `rsl_batch_step_contacts`, with per-contact coefficients (`params`, NULL for none): a
/// contact whose `k_t` or `gamma_t` is negative or not finite is skipped as invalid (status
/// `RSL_ERR_INVALID_ARGUMENT` or `RSL_ERR_NON_FINITE`, as `rsl_contact_step` gives). In double
/// precision the results equal `rsl_contact_step`'s with `RSL_INPUT_SLIDING_STIFFNESS` and
/// `RSL_INPUT_SLIDING_DAMPING` bit for bit.
///
/// # Safety
/// As `rsl_batch_step_contacts`; `params` NULL or readable, its non-NULL arrays holding `n`
/// values.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_step_contacts_params(
    model: *const rsl_model,
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    n: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    params: *const rsl_batch_contact_params,
    dt: f64,
    options: *const rsl_batch_options,
    states: *mut rsl_contact_state,
    out: *mut rsl_batch_loads,
    report: *mut rsl_batch_report,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract of this function; every helper checks NULL and alignment.
        let report = unsafe { report_out(report)? };
        let result = (|| -> Result<_, FfiError> {
            // SAFETY: as above.
            let (m, body1, body2, f_n, opts, states, out) = unsafe {
                (
                    live_model(model)?,
                    slice_in(body1, n, "body1")?,
                    slice_in(body2, n, "body2")?,
                    slice_in(normal_force, n, "normal_force")?,
                    optional_input(options, "options")?,
                    slice_out(states, n, "states")?,
                    slice_out(out, n, "out")?,
                )
            };
            // SAFETY: as above.
            let k_n = unsafe { stiffness_in(m, normal_stiffness, n)? };
            // SAFETY: as above.
            let sliding = unsafe { sliding_in(m, params, n)? };
            // SAFETY: as above.
            let energy = unsafe { energy_in(m.model.track_energy, params, n)? };
            let config = BatchConfig::from_options(opts)?;
            let access = ContactSteps {
                body1,
                body2,
                normal_force: f_n,
                normal_stiffness: k_n,
                states,
                out,
                sliding,
                energy,
            };
            access.check()?;
            Ok((m, access, config))
        })();
        match result {
            Err(e) => refuse(report, e),
            Ok((m, mut access, config)) => finish(
                report,
                run_step(&m.model, dt, &mut access, config).map(|b| (b, config.simd)),
            ),
        }
    })
}

/// Decomposes many sphere-sphere contacts (particle-major): contact `c` joins particles
/// `pairs[2c]` and `pairs[2c+1]`; `out[c]` receives its decomposition (as `rsl_decompose`
/// with `decompose_options`, NULL for the defaults). Invalid contacts are skipped (their `out`
/// untouched) as in `rsl_batch_step`. In single precision the geometry fields are computed in
/// double and the rates in single.
///
/// # Safety
/// `particles` holds `n_particles` spheres, `pairs` `2 n_contacts` indices, `out` `n_contacts`
/// elements (NULL only when empty); `out` and `report` must not overlap inputs or each other.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_decompose(
    particles: *const rsl_sphere,
    n_particles: usize,
    pairs: *const u32,
    n_contacts: usize,
    decompose_options: *const rsl_decompose_options,
    options: *const rsl_batch_options,
    out: *mut rsl_decomposition,
    report: *mut rsl_batch_report,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract of this function; every helper checks NULL and alignment.
        let report = unsafe { report_out(report)? };
        let result = (|| -> Result<_, FfiError> {
            // SAFETY: as above; `[u32; 2]` has the size and alignment of two `u32`.
            let (particles, pairs, dopts, opts, out) = unsafe {
                (
                    slice_in(particles, n_particles, "particles")?,
                    slice_in(pairs as *const [u32; 2], n_contacts, "pairs")?,
                    optional_input(decompose_options, "decompose_options")?,
                    optional_input(options, "options")?,
                    slice_out(out, n_contacts, "out")?,
                )
            };
            let (geometry, parts) = parse_options(dopts)?;
            let config = BatchConfig::from_options(opts)?;
            Ok((
                ParticleDecompose {
                    particles,
                    pairs,
                    out,
                },
                geometry,
                parts,
                config,
            ))
        })();
        decompose_finish(report, result)
    })
}

/// Decomposes many sphere-sphere contacts (contact-major): `out[c]` is the decomposition of
/// `body1[c]` relative to `body2[c]`. Otherwise as `rsl_batch_decompose`.
///
/// # Safety
/// `body1`, `body2`, `out` hold `n` elements (NULL only when `n = 0`); `out` and `report` must
/// not overlap inputs or each other.
#[no_mangle]
pub unsafe extern "C" fn rsl_batch_decompose_contacts(
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    n: usize,
    decompose_options: *const rsl_decompose_options,
    options: *const rsl_batch_options,
    out: *mut rsl_decomposition,
    report: *mut rsl_batch_report,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract of this function; every helper checks NULL and alignment.
        let report = unsafe { report_out(report)? };
        let result = (|| -> Result<_, FfiError> {
            // SAFETY: as above.
            let (body1, body2, dopts, opts, out) = unsafe {
                (
                    slice_in(body1, n, "body1")?,
                    slice_in(body2, n, "body2")?,
                    optional_input(decompose_options, "decompose_options")?,
                    optional_input(options, "options")?,
                    slice_out(out, n, "out")?,
                )
            };
            let (geometry, parts) = parse_options(dopts)?;
            let config = BatchConfig::from_options(opts)?;
            Ok((
                ContactDecompose { body1, body2, out },
                geometry,
                parts,
                config,
            ))
        })();
        decompose_finish(report, result)
    })
}

fn decompose_finish<A: DecomposeAccess>(
    report: Option<&mut rsl_batch_report>,
    result: Result<(A, GeometryOptions, Parts, BatchConfig), FfiError>,
) -> Result<(), FfiError> {
    match result {
        Err(e) => refuse(report, e),
        Ok((mut access, geometry, parts, config)) => finish(
            report,
            run_decompose(geometry, parts, &mut access, config).map(|b| (b, config.simd)),
        ),
    }
}

/// Bit set of the SIMD levels this CPU supports: bit `RSL_SIMD_SCALAR`, `RSL_SIMD_AVX2`,
/// `RSL_SIMD_AVX512` (e.g. `(rsl_batch_simd_support() >> RSL_SIMD_AVX2) & 1`).
#[no_mangle]
pub extern "C" fn rsl_batch_simd_support() -> u32 {
    [Simd::Scalar, Simd::Avx2, Simd::Avx512]
        .into_iter()
        .filter(|s| s.available())
        .fold(0, |bits, s| bits | 1 << s.code())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::capi::contact::{rsl_contact_input, rsl_contact_loads, rsl_contact_step};
    use crate::capi::model::{
        rsl_model_free, rsl_model_new, rsl_model_set_energy_tracking, rsl_model_set_sliding,
        RSL_PRESET_OBJECTIVE, RSL_SLIDING_LINEAR,
    };
    use crate::capi::status::{rsl_last_error_message, RSL_ERR_NON_FINITE, RSL_OK};
    use std::ffi::CStr;

    fn vec3(x: f64, y: f64, z: f64) -> rsl_vec3 {
        rsl_vec3 { x, y, z }
    }

    fn last_error() -> String {
        // SAFETY: a NUL-terminated thread-local string, valid until the next failing call.
        unsafe { CStr::from_ptr(rsl_last_error_message()) }
            .to_str()
            .unwrap()
            .to_string()
    }

    /// The reported model: objective preset, linear sliding (k_t 1e5, gamma_t 5, mu_s 0.5),
    /// energy tracking as given. Free with `rsl_model_free`.
    fn sliding_model(track_energy: bool) -> *mut rsl_model {
        let mut m = std::ptr::null_mut();
        // SAFETY: `m` is a valid out pointer, then a live handle used by this thread only.
        unsafe {
            assert_eq!(rsl_model_new(RSL_PRESET_OBJECTIVE, &mut m), RSL_OK);
            let status = rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e5, 5.0, 0.5);
            assert_eq!(status, RSL_OK);
            assert_eq!(
                rsl_model_set_energy_tracking(m, track_energy as i32),
                RSL_OK
            );
        }
        m
    }

    /// Every option set this CPU runs: both precisions, every SIMD level.
    fn all_options() -> Vec<rsl_batch_options> {
        let mut out = Vec::new();
        for simd in [RSL_SIMD_SCALAR, RSL_SIMD_AVX2, RSL_SIMD_AVX512] {
            if Simd::resolve(simd).is_err() {
                continue;
            }
            for precision in [RSL_PRECISION_F64, RSL_PRECISION_F32] {
                out.push(rsl_batch_options {
                    precision,
                    simd,
                    flags: 0,
                    reserved: 0,
                });
            }
        }
        out
    }

    /// `n` ordinary contacts (R = 1 spheres 1.9 apart along a direction that turns with the
    /// index, modest velocities and springs) and their normal forces.
    fn ordinary_contacts(n: usize) -> (Vec<rsl_sphere>, Vec<rsl_sphere>, Vec<f64>) {
        let (mut body1, mut body2, mut f_n) = (Vec::new(), Vec::new(), Vec::new());
        for c in 0..n {
            let a = c as f64 * 0.7;
            let dir = vec3(a.cos() * 0.8, a.sin() * 0.8, 0.6);
            let zero = rsl_vec3::default();
            body1.push(rsl_sphere {
                position: vec3(c as f64, 0.5, -1.0),
                velocity: vec3(0.3 * a.sin(), -0.2, 0.1 * c as f64),
                angular_velocity: vec3(0.5, -a.cos(), 2.0),
                radius: 1.0,
            });
            body2.push(rsl_sphere {
                position: vec3(
                    c as f64 + 1.9 * dir.x,
                    0.5 + 1.9 * dir.y,
                    -1.0 + 1.9 * dir.z,
                ),
                velocity: zero,
                angular_velocity: vec3(-0.25, 0.0, 1.0),
                radius: 1.0,
            });
            f_n.push(10.0 + c as f64);
        }
        (body1, body2, f_n)
    }

    /// Per-contact `rsl_contact_step` of each contact: status, loads, new state.
    fn per_contact(
        m: *const rsl_model,
        body1: &[rsl_sphere],
        body2: &[rsl_sphere],
        f_n: &[f64],
        states: &[rsl_contact_state],
    ) -> Vec<(i32, rsl_contact_loads, rsl_contact_state)> {
        (0..body1.len())
            .map(|c| {
                let input = rsl_contact_input {
                    normal_force: f_n[c],
                    dt: 1e-4,
                    ..Default::default()
                };
                let (mut state, mut out) = (states[c], rsl_contact_loads::default());
                // SAFETY: live handle and locals of the right types; none overlap.
                let status = unsafe {
                    rsl_contact_step(m, &body1[c], &body2[c], &input, &mut state, &mut out)
                };
                (status, out, state)
            })
            .collect()
    }

    /// Runs both batch entry points on the contacts; asserts that in double precision every
    /// contact the per-contact step accepts gets its loads and state bit for bit, that the
    /// refused ones (`refused`, with `status` and a message containing `needle`) are skipped
    /// with their state and loads untouched, and that the report says so. In single precision
    /// only the statuses are compared (its rounding differs).
    #[allow(clippy::too_many_arguments)]
    fn batch_agrees(
        m: *const rsl_model,
        body1: &[rsl_sphere],
        body2: &[rsl_sphere],
        f_n: &[f64],
        states0: &[rsl_contact_state],
        refused: &[usize],
        status: i32,
        needle: &str,
    ) {
        let n = body1.len();
        let reference = per_contact(m, body1, body2, f_n, states0);
        for (c, (s, _, _)) in reference.iter().enumerate() {
            let expected = if refused.contains(&c) { status } else { RSL_OK };
            assert_eq!(*s, expected, "per-contact status of contact {c}");
        }
        let overall = if refused.is_empty() { RSL_OK } else { status };
        let sentinel = rsl_batch_loads {
            force1: vec3(7.0, 7.0, 7.0),
            ..Default::default()
        };
        // Particle-major: contact c joins particles 2c and 2c + 1.
        let particles: Vec<rsl_sphere> = (0..n).flat_map(|c| [body1[c], body2[c]]).collect();
        let pairs: Vec<u32> = (0..2 * n as u32).collect();
        for options in all_options() {
            let f64s = options.precision == RSL_PRECISION_F64;
            let what = format!("{options:?}");
            let mut states = states0.to_vec();
            let mut out = vec![sentinel; n];
            let mut report = rsl_batch_report::default();
            // SAFETY: every array holds `n` elements; none overlap.
            let got = unsafe {
                rsl_batch_step_contacts(
                    m,
                    body1.as_ptr(),
                    body2.as_ptr(),
                    n,
                    f_n.as_ptr(),
                    std::ptr::null(),
                    1e-4,
                    &options,
                    states.as_mut_ptr(),
                    out.as_mut_ptr(),
                    &mut report,
                )
            };
            if f64s {
                assert_eq!(got, overall, "{what}: {}", last_error());
                if overall != RSL_OK {
                    assert!(last_error().contains(needle), "{what}: {}", last_error());
                }
                assert_eq!(report.failed, refused.len() as u64, "{what}");
                for (c, (_, loads, state)) in reference.iter().enumerate() {
                    if refused.contains(&c) {
                        assert_eq!(out[c], sentinel, "{what}: loads of refused contact {c}");
                        assert_eq!(states[c], states0[c], "{what}: state of refused {c}");
                    } else {
                        let want = [loads.force1, loads.torque1, loads.torque2];
                        let have = [out[c].force1, out[c].torque1, out[c].torque2];
                        assert_eq!(format!("{have:?}"), format!("{want:?}"), "{what}: {c}");
                        assert_eq!(format!("{:?}", states[c]), format!("{state:?}"), "{c}");
                    }
                }
            } else {
                // The single-precision kernels refuse at least what the double ones refuse.
                assert!(report.failed >= refused.len() as u64, "{what}");
                for &c in refused {
                    assert_eq!(out[c], sentinel, "{what}: loads of refused contact {c}");
                    assert_eq!(states[c], states0[c], "{what}: state of refused {c}");
                }
            }
            if let Some(&first) = refused.first() {
                if f64s {
                    assert_eq!(report.first_failed, first as u64, "{what}");
                }
                assert_eq!(report.first_status, status, "{what}");
            }

            let mut states = states0.to_vec();
            let mut force = vec![rsl_vec3::default(); 2 * n];
            let mut torque = vec![rsl_vec3::default(); 2 * n];
            let mut report = rsl_batch_report::default();
            // SAFETY: `particles`, `force`, `torque` hold 2n elements, `pairs` 2n indices,
            // the per-contact arrays n; none overlap.
            let got = unsafe {
                rsl_batch_step(
                    m,
                    particles.as_ptr(),
                    2 * n,
                    pairs.as_ptr(),
                    n,
                    f_n.as_ptr(),
                    std::ptr::null(),
                    1e-4,
                    &options,
                    states.as_mut_ptr(),
                    force.as_mut_ptr(),
                    torque.as_mut_ptr(),
                    &mut report,
                )
            };
            if f64s {
                assert_eq!(got, overall, "{what} (particle-major)");
                assert_eq!(
                    report.failed,
                    refused.len() as u64,
                    "{what} (particle-major)"
                );
                // Added to a zero accumulator: `0 + x` is `x` (-0 becomes +0, hence values).
                for (c, (_, loads, _)) in reference.iter().enumerate() {
                    if !refused.contains(&c) {
                        assert_eq!(force[2 * c], loads.force1, "{what}: {c}");
                        assert_eq!(torque[2 * c + 1], loads.torque2, "{what}: {c}");
                    }
                }
            }
            for &c in refused {
                assert_eq!(states[c], states0[c], "{what}: state of refused {c}");
                let untouched = [
                    force[2 * c],
                    force[2 * c + 1],
                    torque[2 * c],
                    torque[2 * c + 1],
                ];
                assert_eq!(untouched, [rsl_vec3::default(); 4], "{what}: loads of {c}");
            }
        }
    }

    /// The per-contact step refuses a contact whose energy terms overflow when the model
    /// tracks energy (`RSL_ERR_NON_FINITE`, "energy terms"): the reported one, R = 1 spheres at
    /// (0, 0, 0) and (1.9, 0, 0) sliding at +-1e200 along y (the dashpot's `gamma_t |v_s|^2 dt`
    /// is +inf). Every batch kernel must skip it with the same status (the header: "the status
    /// `rsl_contact_step` would give"), in a lane among ordinary contacts, which are stepped
    /// as the per-contact step steps them. Without energy tracking all are accepted.
    #[test]
    fn batch_refuses_what_the_per_contact_step_refuses_with_energy_tracking() {
        let (mut body1, mut body2, f_n) = ordinary_contacts(19);
        let huge = 5;
        body1[huge] = rsl_sphere {
            velocity: vec3(0.0, 1e200, 0.0),
            radius: 1.0,
            ..Default::default()
        };
        body2[huge] = rsl_sphere {
            position: vec3(1.9, 0.0, 0.0),
            velocity: vec3(0.0, -1e200, 0.0),
            radius: 1.0,
            ..Default::default()
        };
        let states = vec![rsl_contact_state::default(); body1.len()];
        for track_energy in [true, false] {
            let m = sliding_model(track_energy);
            let refused: &[usize] = if track_energy { &[huge] } else { &[] };
            batch_agrees(
                m,
                &body1,
                &body2,
                &f_n,
                &states,
                refused,
                RSL_ERR_NON_FINITE,
                "energy terms",
            );
            // SAFETY: a live handle, freed once.
            unsafe { rsl_model_free(m) };
        }
    }

    /// The reported overflowing clip (sliding at +-1e155, and a stored spring of 1e150) in SIMD
    /// lanes beside ordinary contacts: every kernel gives the per-contact bits, and those are
    /// the Coulomb load `mu_s f_n` (checked through `rsl_contact_step`'s sliding force).
    #[test]
    fn overflowing_clips_in_simd_lanes_match_the_per_contact_step() {
        let (mut body1, mut body2, mut f_n) = ordinary_contacts(21);
        let mut states = vec![rsl_contact_state::default(); body1.len()];
        let n = vec3(0.6, 0.8, 0.0);
        for (c, v, spring) in [(3, 1e155, 0.0), (9, 0.0, 1e150), (10, 1e155, 1e150)] {
            body1[c] = rsl_sphere {
                velocity: vec3(0.0, 0.0, v),
                radius: 1.0,
                ..Default::default()
            };
            body2[c] = rsl_sphere {
                position: vec3(1.65 * n.x, 1.65 * n.y, 0.0),
                velocity: vec3(0.0, 0.0, -v),
                radius: 0.7,
                ..Default::default()
            };
            f_n[c] = 100.0;
            states[c].sliding_spring = vec3(0.0, 0.0, spring);
        }
        let m = sliding_model(false);
        for (c, (status, loads, _)) in per_contact(m, &body1, &body2, &f_n, &states)
            .iter()
            .enumerate()
        {
            assert_eq!(*status, RSL_OK);
            if [3, 9, 10].contains(&c) {
                let f = loads.sliding_force;
                // mu_s f_n = 50 against the sliding (or the spring): -z, to 4 eps.
                assert!(
                    f.x.abs() + f.y.abs() <= 4.0 * f64::EPSILON * 50.0,
                    "{c}: {f:?}"
                );
                assert!(
                    (f.z + 50.0).abs() <= 4.0 * f64::EPSILON * 50.0,
                    "{c}: {f:?}"
                );
            }
        }
        batch_agrees(m, &body1, &body2, &f_n, &states, &[], RSL_OK, "");
        // SAFETY: a live handle, freed once.
        unsafe { rsl_model_free(m) };
    }
}
