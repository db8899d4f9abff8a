//! The contact model handle `rsl_model` (opaque to C) as the entry points read it: its liveness
//! tag, the core model, the table of material pairs and the per-contact steps chosen for this
//! CPU ([`ContactSteps`], whose builds are `contact`'s). Its C functions (`rsl_model_new`,
//! `rsl_model_free`, the setters) are `model`'s.
#![allow(non_camel_case_types)]

use super::input;
use super::status::FfiError;
use super::types::{rsl_contact_loads, rsl_sphere, rsl_vec3, rsl_wall};
use crate::laws::materials::Coefficients;
use crate::laws::model::Model;
use crate::layout::{rsl_contact_input, rsl_contact_state};

pub(super) const LIVE: u64 = 0x7273_6c5f_6d6f_6465; // "rsl_mode"
pub(super) const FREED: u64 = 0x6672_6565_645f_5f5f; // "freed___"

/// An opaque contact model (laws, parameters, transport, preset). Create with `rsl_model_new`,
/// release with `rsl_model_free`. A model is read-only during steps: one model can serve many
/// threads at once as long as no thread calls a setter meanwhile.
pub struct rsl_model {
    pub(super) magic: u64,
    pub(crate) model: Model,
    /// The table of material pairs (`rsl_model_set_materials`): coefficient sets of models with
    /// this model's laws.
    pub(crate) materials: Vec<Coefficients>,
    /// `rsl_contact_step` and `rsl_contact_step_accumulate` on this CPU (its fast
    /// path, the checked step on refusal), chosen once here rather than per call.
    pub(crate) steps: ContactSteps,
}

impl rsl_model {
    /// Whether this is a live handle (not freed, not garbage: best effort, as [`live_model`]).
    pub(crate) fn is_live(&self) -> bool {
        self.magic == LIVE
    }

    /// A live handle of `model` (already validated), with the per-contact steps `steps`
    /// (`contact::contact_steps` gives those of this CPU).
    pub(crate) fn live(model: Model, steps: ContactSteps) -> Self {
        rsl_model {
            magic: LIVE,
            model,
            materials: Vec::new(),
            steps,
        }
    }
}

/// Borrows a live model for reading.
///
/// # Safety
/// `p` must be NULL or a pointer returned by `rsl_model_new` (freed pointers are detected on a
/// best-effort basis only).
pub(crate) unsafe fn live_model<'a>(p: *const rsl_model) -> Result<&'a rsl_model, FfiError> {
    // SAFETY: forwarded contract.
    let m = unsafe { input(p, "model")? };
    if m.magic != LIVE {
        return Err(FfiError::InvalidHandle);
    }
    Ok(m)
}

/// `rsl_contact_step`'s signature: the handle's step on this CPU, which the entry
/// calls in tail position with its own arguments once it has checked them (every pointer
/// non-NULL and 8-aligned, the handle live). The same signature lets the compiler make that
/// call a jump: no second frame, no copy of the arguments.
pub(crate) type OutStep = unsafe extern "C" fn(
    *const rsl_model,
    *const rsl_sphere,
    *const rsl_sphere,
    *const rsl_contact_input,
    *mut rsl_contact_state,
    *mut rsl_contact_loads,
) -> i32;

/// `rsl_contact_step_accumulate`'s signature, for the same purpose as [`OutStep`] (its last
/// three pointers arrive on the stack, and a jump leaves them where the host put them).
pub(crate) type AccumulateStep = unsafe extern "C" fn(
    *const rsl_model,
    *const rsl_sphere,
    *const rsl_sphere,
    *const rsl_contact_input,
    *mut rsl_contact_state,
    *mut rsl_vec3,
    *mut rsl_vec3,
    *mut rsl_vec3,
    *mut rsl_vec3,
) -> i32;

/// `rsl_contact_step_wall`'s signature, for the same purpose as [`OutStep`].
pub(crate) type WallOutStep = unsafe extern "C" fn(
    *const rsl_model,
    *const rsl_sphere,
    *const rsl_wall,
    *const rsl_contact_input,
    *mut rsl_contact_state,
    *mut rsl_contact_loads,
) -> i32;

/// `rsl_contact_step_wall_accumulate`'s signature, for the same purpose as [`OutStep`].
pub(crate) type WallAccumulateStep = unsafe extern "C" fn(
    *const rsl_model,
    *const rsl_sphere,
    *const rsl_wall,
    *const rsl_contact_input,
    *mut rsl_contact_state,
    *mut rsl_vec3,
    *mut rsl_vec3,
) -> i32;

/// The per-contact steps on this CPU, one per C entry, kept in the model handle. Each
/// runs the fast path for a plain input and the checked step (which reports) for
/// anything else and anything the fast path refuses, behind the panic boundary.
#[derive(Clone, Copy)]
pub(crate) struct ContactSteps {
    /// `rsl_contact_step`.
    pub(crate) out: OutStep,
    /// `rsl_contact_step_accumulate`.
    pub(crate) accumulate: AccumulateStep,
    /// `rsl_contact_step_wall`.
    pub(crate) wall_out: WallOutStep,
    /// `rsl_contact_step_wall_accumulate`.
    pub(crate) wall_accumulate: WallAccumulateStep,
    /// The unchecked entries' steps.
    pub(crate) unchecked: UncheckedSteps,
}

/// The steps of the unchecked entries (`rsl_contact_step_unchecked` and the others): the fast
/// path without the tests of the values.
#[derive(Clone, Copy)]
pub(crate) struct UncheckedSteps {
    /// `rsl_contact_step_unchecked`.
    pub(crate) out: OutStep,
    /// `rsl_contact_step_accumulate_unchecked`.
    pub(crate) accumulate: AccumulateStep,
    /// `rsl_contact_step_wall_unchecked`.
    pub(crate) wall_out: WallOutStep,
    /// `rsl_contact_step_wall_accumulate_unchecked`.
    pub(crate) wall_accumulate: WallAccumulateStep,
}
