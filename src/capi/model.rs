//! The contact model handle: `rsl_model_new` / `rsl_model_free` and validated setters. A setter
//! that refuses its input returns `RSL_ERR_INVALID_PARAMETER` and leaves the model unchanged.
//! The handle type itself is `handle`'s.
#![allow(non_camel_case_types)]

pub use super::handle::rsl_model;

use super::contact::contact_steps;
use super::decompose::{parse_options, rsl_decompose_options};
use super::handle::{live_model, FREED, LIVE};
use super::status::FfiError;
use super::{guard, input, output, slice_in};
use crate::error::Error;
use crate::geometry::GeometryOptions;
use crate::laws::materials::{same_laws, Coefficients};
use crate::laws::model::{
    DampingMode, Model, Preset, RollingDamping, RollingForm, RollingLaw, RollingParams,
    RollingStiffness, SlidingHistory, SlidingLaw, SlidingParams, Transport, TwistingLaw,
    TwistingParams,
};

/// Preset: this library's objective definitions (default).
pub const RSL_PRESET_OBJECTIVE: i32 = 0;
/// Preset: LAMMPS 29 Sep 2021 `pair_style granular` (radii sliding, R_eff, project-rescale).
pub const RSL_PRESET_LAMMPS_2021: i32 = 1;
/// Preset: YADE 2023.02a CohFrict moment law / Mindlin with moments (angle form, first-order).
pub const RSL_PRESET_YADE_2023: i32 = 2;
/// Preset: LIGGGHTS-PUBLIC 3.8.0 rolling friction (angle form, damping below the limit;
/// `torsionTorque on` with `rsl_model_set_torsion_torque`).
pub const RSL_PRESET_LIGGGHTS_3_8: i32 = 3;

/// Sliding law: none.
pub const RSL_SLIDING_NONE: i32 = 0;
/// Sliding law: linear spring-dashpot-slider (LAMMPS linear_history).
pub const RSL_SLIDING_LINEAR: i32 = 1;

/// Sliding history (`rsl_model_set_sliding_history`): the spring stores a displacement `xi`
/// (length), its load is `-k_t xi` with the step's `k_t`: a change of `k_t` keeps the stretch
/// and scales the load (LAMMPS `linear_history`, `mindlin`). Every preset's default but
/// YADE_2023's.
pub const RSL_SLIDING_HISTORY_DISPLACEMENT: i32 = 0;
/// Sliding history: the spring stores its elastic force (on body 1), built incrementally,
/// `F += -k_t v_s dt` with the step's `k_t`: a change of `k_t` keeps the load (LAMMPS
/// `mindlin/force`; YADE's shear force, the YADE_2023 preset's only history).
pub const RSL_SLIDING_HISTORY_FORCE: i32 = 1;
/// Sliding history: as `RSL_SLIDING_HISTORY_DISPLACEMENT`, and in a step whose `k_t` is below
/// the previous step's, the stored displacement is first scaled by `k_t / k_t,previous`
/// (LAMMPS `mindlin_rescale`: `a / a_previous` for its `k_t = 8 G a`).
pub const RSL_SLIDING_HISTORY_DISPLACEMENT_RESCALED: i32 = 2;
/// Sliding history: as `RSL_SLIDING_HISTORY_FORCE`, with the stored force scaled by
/// `k_t / k_t,previous` in a step whose `k_t` fell (LAMMPS `mindlin_rescale/force`).
pub const RSL_SLIDING_HISTORY_FORCE_RESCALED: i32 = 3;

/// Rolling law: none.
pub const RSL_ROLLING_NONE: i32 = 0;
/// Rolling law: cdt (type A, constant moment).
pub const RSL_ROLLING_CDT: i32 = 1;
/// Rolling law: viscous (type B).
pub const RSL_ROLLING_VISCOUS: i32 = 2;
/// Rolling law: epsd (type C, elastic-plastic spring-dashpot).
pub const RSL_ROLLING_EPSD: i32 = 3;

/// Twisting law: none.
pub const RSL_TWISTING_NONE: i32 = 0;
/// Twisting law: spring-dashpot-slider.
pub const RSL_TWISTING_SDS: i32 = 1;
/// Twisting law: Marshall (from the sliding law and the contact radius).
pub const RSL_TWISTING_MARSHALL: i32 = 2;

/// Rolling parameters in length form: `F_r = -k_r xi_r - gamma_r v_r` on body 1, limited to
/// `mu_r f_n`, moment `R_r n x F_r`: `k_r` force/length, `gamma_r` force time/length, `mu_r`
/// dimensionless; the stored rolling spring `xi_r` is a length.
pub const RSL_FORM_LENGTH: i32 = 0;
/// Rolling parameters in angle form: `M = -k_theta theta_r - c_theta (w1 - w2)_t`, limited to
/// `eta f_n`: `k_theta` moment/rad, `c_theta` moment time/rad, `eta` a length; the stored
/// rolling spring `theta_r` is in radians.
pub const RSL_FORM_ANGLE: i32 = 1;

/// EPSD stiffness: the given `stiffness`.
pub const RSL_STIFFNESS_GIVEN: i32 = 0;
/// EPSD stiffness: `k_theta = 2.25 k_n mu_r^2 R_r^2`.
pub const RSL_STIFFNESS_EPSD: i32 = 1;
/// EPSD stiffness: `k_theta = k_t R_r^2`.
pub const RSL_STIFFNESS_EPSD2: i32 = 2;
/// EPSD stiffness: `k_theta = c k_n mu_r^2 R_r^2` (`c` = `stiffness_factor`).
pub const RSL_STIFFNESS_EPSD3: i32 = 3;

/// EPSD damping: the given `damping` coefficient.
pub const RSL_DAMPING_GIVEN: i32 = 0;
/// EPSD damping: `damping` is a ratio `eta_r`, `c_theta = eta_r 2 sqrt(I_r k_theta)`.
pub const RSL_DAMPING_RATIO: i32 = 1;

/// Dashpot always on; the limit applies to spring + dashpot.
pub const RSL_DAMPING_ALWAYS: i32 = 0;
/// Dashpot only below the limit; the limit applies to the spring (LIGGGHTS).
pub const RSL_DAMPING_BELOW_LIMIT: i32 = 1;

/// Transport: exact rotation (default).
pub const RSL_TRANSPORT_EXACT: i32 = 0;
/// Transport: project and rescale (LAMMPS).
pub const RSL_TRANSPORT_PROJECT_RESCALE: i32 = 1;
/// Transport: first-order rotation (YADE).
pub const RSL_TRANSPORT_FIRST_ORDER: i32 = 2;
/// Transport: project, no rescale (LIGGGHTS sliding).
pub const RSL_TRANSPORT_PROJECT: i32 = 3;
/// Transport: none.
pub const RSL_TRANSPORT_NONE: i32 = 4;

/// Parameters of the rolling law (`rsl_model_set_rolling`). Start from
/// `rsl_model_get_rolling`, which returns the model's current ones (a preset's form and
/// damping mode included).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct rsl_rolling_params {
    /// `RSL_ROLLING_*`.
    pub law: i32,
    /// `RSL_FORM_LENGTH` or `RSL_FORM_ANGLE`: the unit of the parameters and of the stored spring.
    pub form: i32,
    /// `RSL_STIFFNESS_*` (EPSD).
    pub stiffness_rule: i32,
    /// `RSL_DAMPING_GIVEN` or `RSL_DAMPING_RATIO` (EPSD).
    pub damping_rule: i32,
    /// `RSL_DAMPING_ALWAYS` or `RSL_DAMPING_BELOW_LIMIT` (EPSD).
    pub damping_mode: i32,
    /// Padding; set to 0.
    pub reserved: i32,
    /// `k_r` (force/length) or `k_theta` (moment/rad), >= 0.
    pub stiffness: f64,
    /// `gamma_r` (force time/length), `c_theta` (moment time/rad), or the damping ratio
    /// (dimensionless), >= 0.
    pub damping: f64,
    /// `mu_r` (dimensionless, length form) or `eta` (length, angle form), >= 0; +INFINITY for
    /// no limit, except where the coefficient is not a limit and must be finite: `RSL_ROLLING_CDT`
    /// (it sets the moment) and the `RSL_STIFFNESS_EPSD`/`RSL_STIFFNESS_EPSD3` rules (they derive
    /// the stiffness from it).
    pub friction: f64,
    /// cdt: rate `|(w1 - w2)_t|` (rad/time; `|w1 - w2|` with `rsl_model_set_torsion_torque`)
    /// below which the moment is zero, >= 0.
    pub rate_threshold: f64,
    /// EPSD3 factor `c` (> 0 with `RSL_STIFFNESS_EPSD3`).
    pub stiffness_factor: f64,
}

/// Applies a change to a copy of the model, validates it, and stores it only if valid.
///
/// # Safety
/// As [`live_model`], for a model no other thread uses during the call.
unsafe fn update(
    p: *mut rsl_model,
    change: impl FnOnce(&mut Model) -> Result<(), Error>,
) -> Result<(), FfiError> {
    // SAFETY: forwarded contract; the model is checked live before it is written.
    let m = unsafe { output(p, "model")? };
    if m.magic != LIVE {
        return Err(FfiError::InvalidHandle);
    }
    let mut next = m.model;
    change(&mut next)?;
    next.validate()?;
    // The table of material pairs stays while the laws do (a change of values only).
    let materials = if same_laws(&m.model, &next) {
        std::mem::take(&mut m.materials)
    } else {
        Vec::new()
    };
    *m = rsl_model {
        materials,
        ..rsl_model::live(next, contact_steps())
    };
    Ok(())
}

fn bad(what: &str, value: i32) -> Error {
    Error::InvalidParameter(format!("{what} code {value} is not defined"))
}

/// A C on/off flag: 0 or 1, anything else refused naming `what`.
fn on_off(value: i32, what: &str) -> Result<bool, Error> {
    match value {
        0 => Ok(false),
        1 => Ok(true),
        other => Err(bad(what, other)),
    }
}

fn parse_preset(code: i32) -> Result<Preset, Error> {
    Ok(match code {
        RSL_PRESET_OBJECTIVE => Preset::Objective,
        RSL_PRESET_LAMMPS_2021 => Preset::Lammps2021,
        RSL_PRESET_YADE_2023 => Preset::Yade2023,
        RSL_PRESET_LIGGGHTS_3_8 => Preset::Liggghts38,
        other => return Err(bad("preset", other)),
    })
}

/// Creates a model with every law off and the conventions of `preset` (`RSL_PRESET_*`); writes
/// the handle to `*out` on success.
///
/// # Safety
/// `out` must be NULL or point to writable storage for one pointer.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_new(preset: i32, out: *mut *mut rsl_model) -> i32 {
    guard(|| {
        // SAFETY: NULL and alignment checked; writability is the caller's contract.
        let out = unsafe { output(out, "out")? };
        let preset = parse_preset(preset)?;
        let model = Model::with_preset(preset);
        let boxed = Box::new(rsl_model::live(model, contact_steps()));
        *out = Box::into_raw(boxed);
        Ok(())
    })
}

/// Releases a model. NULL is accepted and ignored. Using the handle afterwards is an error the
/// library detects on a best-effort basis (`RSL_ERR_INVALID_HANDLE`).
///
/// # Safety
/// `model` must be NULL or a live pointer from `rsl_model_new`, not used by another thread.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_free(model: *mut rsl_model) {
    if model.is_null() || !model.is_aligned() {
        return;
    }
    let _ = std::panic::catch_unwind(|| {
        // SAFETY: non-null, aligned, and from rsl_model_new per the contract; the magic check
        // refuses a double free that the allocator has not yet reused.
        unsafe {
            if (*model).magic != LIVE {
                return;
            }
            (*model).magic = FREED;
            drop(Box::from_raw(model));
        }
    });
}

/// Gives `model` a table of material pairs for the batch calls: set `i` holds the coefficients
/// (stiffness, damping and limit coefficient of each law) of `sets[i]`, a model with the same
/// laws, forms, rules, transports, preset and switches as `model`, only other values (as
/// LAMMPS' `pair_coeff` per type pair, or YADE's material pairs). A batch call then takes each
/// contact's index into the table (`rsl_batch_contact_params.material`) and steps it as
/// `rsl_contact_step` steps it with `sets[i]`. Fill it once per run: the sets are copied, and
/// `sets` may be freed afterwards. `n = 0` (with `sets` NULL or not) removes the table.
///
/// The table stays while the model's setters change values only; a setter that changes a law,
/// form, rule, transport or switch removes it (its sets would no longer be of the model's
/// laws). On error (`RSL_ERR_INVALID_ARGUMENT` for a set of other laws or a NULL set,
/// `RSL_ERR_INVALID_HANDLE` for a freed one) the model and its table are unchanged.
///
/// # Safety
/// `model` a live model no other thread uses during the call; `sets` NULL (only with `n = 0`)
/// or an array of `n` pointers to live models.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_materials(
    model: *mut rsl_model,
    sets: *const *const rsl_model,
    n: usize,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; NULL and alignment checked.
        let m = unsafe { output(model, "model")? };
        if m.magic != LIVE {
            return Err(FfiError::InvalidHandle);
        }
        let pointers: &[*const rsl_model] = if n == 0 {
            &[]
        } else {
            // SAFETY: forwarded contract: `sets` holds `n` pointers (NULL refused here).
            unsafe { slice_in(sets, n, "sets")? }
        };
        let mut table = Vec::with_capacity(n);
        for (i, &p) in pointers.iter().enumerate() {
            // SAFETY: forwarded contract: each pointer NULL (refused) or a live model.
            let set = unsafe { live_model(p) }.map_err(|e| match e {
                FfiError::NullPointer(_) => {
                    FfiError::Core(Error::InvalidArgument(format!("sets[{i}] is NULL")))
                }
                FfiError::Misaligned(_) => FfiError::MisalignedElement("sets", i),
                other => other,
            })?;
            if !same_laws(&m.model, &set.model) {
                return Err(FfiError::Core(Error::InvalidArgument(format!(
                    "sets[{i}] has other laws, transports, preset or switches than the model \
                     (a table's sets differ in values only)"
                ))));
            }
            table.push(Coefficients::of(&set.model));
        }
        m.materials = table;
        Ok(())
    })
}

/// Writes the number of sets in `model`'s table of material pairs (0 without one) to `*n`.
///
/// # Safety
/// `model` a live model; `n` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_material_count(model: *const rsl_model, n: *mut usize) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract; NULL and alignment checked.
        let (m, out) = unsafe { (live_model(model)?, output(n, "n")?) };
        *out = m.materials.len();
        Ok(())
    })
}

/// Sets the branch rule (`RSL_BRANCH_*`) and rolling radius rule (`RSL_ROLLING_RADIUS_*`).
///
/// # Safety
/// `model` must be a live model not used by another thread during the call.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_geometry(
    model: *mut rsl_model,
    branch_rule: i32,
    rolling_radius_rule: i32,
) -> i32 {
    guard(|| {
        let options = rsl_decompose_options {
            branch_rule,
            rolling_radius_rule,
            parts: 0,
        };
        let (geometry, _): (GeometryOptions, _) =
            parse_options(Some(&options)).map_err(|e| match e {
                Error::InvalidArgument(m) => Error::InvalidParameter(m),
                other => other,
            })?;
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.geometry = geometry;
                Ok(())
            })
        }
    })
}

/// Sets the sliding law (`RSL_SLIDING_*`) with `k_t` (force/length) and `gamma_t` (force
/// time/length), finite and >= 0, and `mu_s` (dimensionless), >= 0 or +INFINITY for no limit.
///
/// # Safety
/// As `rsl_model_set_geometry`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_sliding(
    model: *mut rsl_model,
    law: i32,
    stiffness: f64,
    damping: f64,
    friction: f64,
) -> i32 {
    guard(|| {
        let law = match law {
            RSL_SLIDING_NONE => SlidingLaw::None,
            RSL_SLIDING_LINEAR => SlidingLaw::Linear,
            other => return Err(bad("sliding law", other).into()),
        };
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.sliding = SlidingParams {
                    law,
                    stiffness,
                    damping,
                    friction,
                    history: m.sliding.history,
                };
                Ok(())
            })
        }
    })
}

/// Sets what the sliding spring stores (`RSL_SLIDING_HISTORY_*`), hence what a change of its
/// stiffness from one step to the next does to it (a per-contact `k_t`, as Hertz-Mindlin's):
/// the loads are the same for every history while `k_t` is constant. The rescaled histories
/// compare each step's `k_t` with the previous step's, which the contact state keeps in
/// `model_memory` (so the model's history record, `rsl_model_history_size`, grows). The
/// YADE_2023 preset keeps `RSL_SLIDING_HISTORY_FORCE` (anything else is
/// `RSL_ERR_INVALID_PARAMETER`). Kept by `rsl_model_set_sliding`.
///
/// # Safety
/// As `rsl_model_set_geometry`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_sliding_history(model: *mut rsl_model, history: i32) -> i32 {
    guard(|| {
        let history = match history {
            RSL_SLIDING_HISTORY_DISPLACEMENT => SlidingHistory::Displacement,
            RSL_SLIDING_HISTORY_FORCE => SlidingHistory::Force,
            RSL_SLIDING_HISTORY_DISPLACEMENT_RESCALED => SlidingHistory::DisplacementRescaled,
            RSL_SLIDING_HISTORY_FORCE_RESCALED => SlidingHistory::ForceRescaled,
            other => return Err(bad("sliding history", other).into()),
        };
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.sliding.history = history;
                Ok(())
            })
        }
    })
}

/// Writes the model's sliding history (`RSL_SLIDING_HISTORY_*`) to `*history`.
///
/// # Safety
/// `model` must be a live model; `history` writable.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_get_sliding_history(
    model: *const rsl_model,
    history: *mut i32,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract.
        let (m, out) = unsafe { (live_model(model)?, output(history, "history")?) };
        *out = match m.model.sliding.history {
            SlidingHistory::Displacement => RSL_SLIDING_HISTORY_DISPLACEMENT,
            SlidingHistory::Force => RSL_SLIDING_HISTORY_FORCE,
            SlidingHistory::DisplacementRescaled => RSL_SLIDING_HISTORY_DISPLACEMENT_RESCALED,
            SlidingHistory::ForceRescaled => RSL_SLIDING_HISTORY_FORCE_RESCALED,
        };
        Ok(())
    })
}

/// Sets the twisting law (`RSL_TWISTING_*`) with `k_tw` (moment/rad) and `gamma_tw` (moment
/// time/rad), finite and >= 0, and `mu_tw` (a length: the limit is `mu_tw f_n`), >= 0 or
/// +INFINITY for no limit. `RSL_TWISTING_MARSHALL` derives
/// its coefficients from the sliding law and ignores these three.
///
/// # Safety
/// As `rsl_model_set_geometry`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_twisting(
    model: *mut rsl_model,
    law: i32,
    stiffness: f64,
    damping: f64,
    friction: f64,
) -> i32 {
    guard(|| {
        let law = match law {
            RSL_TWISTING_NONE => TwistingLaw::None,
            RSL_TWISTING_SDS => TwistingLaw::Sds,
            RSL_TWISTING_MARSHALL => TwistingLaw::Marshall,
            other => return Err(bad("twisting law", other).into()),
        };
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.twisting = TwistingParams {
                    law,
                    stiffness,
                    damping,
                    friction,
                };
                Ok(())
            })
        }
    })
}

fn rolling_from_c(p: &rsl_rolling_params) -> Result<RollingParams, Error> {
    Ok(RollingParams {
        law: match p.law {
            RSL_ROLLING_NONE => RollingLaw::None,
            RSL_ROLLING_CDT => RollingLaw::Cdt,
            RSL_ROLLING_VISCOUS => RollingLaw::Viscous,
            RSL_ROLLING_EPSD => RollingLaw::Epsd,
            other => return Err(bad("rolling law", other)),
        },
        form: match p.form {
            RSL_FORM_LENGTH => RollingForm::Length,
            RSL_FORM_ANGLE => RollingForm::Angle,
            other => return Err(bad("rolling form", other)),
        },
        stiffness_rule: match p.stiffness_rule {
            RSL_STIFFNESS_GIVEN => RollingStiffness::Given,
            RSL_STIFFNESS_EPSD => RollingStiffness::Epsd,
            RSL_STIFFNESS_EPSD2 => RollingStiffness::Epsd2,
            RSL_STIFFNESS_EPSD3 => RollingStiffness::Epsd3,
            other => return Err(bad("rolling stiffness_rule", other)),
        },
        damping_rule: match p.damping_rule {
            RSL_DAMPING_GIVEN => RollingDamping::Given,
            RSL_DAMPING_RATIO => RollingDamping::Ratio,
            other => return Err(bad("rolling damping_rule", other)),
        },
        damping_mode: match p.damping_mode {
            RSL_DAMPING_ALWAYS => DampingMode::Always,
            RSL_DAMPING_BELOW_LIMIT => DampingMode::BelowLimit,
            other => return Err(bad("rolling damping_mode", other)),
        },
        stiffness: p.stiffness,
        damping: p.damping,
        friction: p.friction,
        rate_threshold: p.rate_threshold,
        stiffness_factor: p.stiffness_factor,
    })
}

fn rolling_to_c(p: &RollingParams) -> rsl_rolling_params {
    rsl_rolling_params {
        law: match p.law {
            RollingLaw::None => RSL_ROLLING_NONE,
            RollingLaw::Cdt => RSL_ROLLING_CDT,
            RollingLaw::Viscous => RSL_ROLLING_VISCOUS,
            RollingLaw::Epsd => RSL_ROLLING_EPSD,
        },
        form: match p.form {
            RollingForm::Length => RSL_FORM_LENGTH,
            RollingForm::Angle => RSL_FORM_ANGLE,
        },
        stiffness_rule: match p.stiffness_rule {
            RollingStiffness::Given => RSL_STIFFNESS_GIVEN,
            RollingStiffness::Epsd => RSL_STIFFNESS_EPSD,
            RollingStiffness::Epsd2 => RSL_STIFFNESS_EPSD2,
            RollingStiffness::Epsd3 => RSL_STIFFNESS_EPSD3,
        },
        damping_rule: match p.damping_rule {
            RollingDamping::Given => RSL_DAMPING_GIVEN,
            RollingDamping::Ratio => RSL_DAMPING_RATIO,
        },
        damping_mode: match p.damping_mode {
            DampingMode::Always => RSL_DAMPING_ALWAYS,
            DampingMode::BelowLimit => RSL_DAMPING_BELOW_LIMIT,
        },
        reserved: 0,
        stiffness: p.stiffness,
        damping: p.damping,
        friction: p.friction,
        rate_threshold: p.rate_threshold,
        stiffness_factor: p.stiffness_factor,
    }
}

/// Sets the rolling law and its parameters (see `rsl_rolling_params`).
///
/// # Safety
/// As `rsl_model_set_geometry`; `params` must point to a valid `rsl_rolling_params`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_rolling(
    model: *mut rsl_model,
    params: *const rsl_rolling_params,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract.
        let p = unsafe { input(params, "params")? };
        let rolling = rolling_from_c(p)?;
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.rolling = rolling;
                Ok(())
            })
        }
    })
}

/// Writes the model's current rolling parameters to `*out`.
///
/// # Safety
/// `model` must be a live model; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_get_rolling(
    model: *const rsl_model,
    out: *mut rsl_rolling_params,
) -> i32 {
    guard(|| {
        // SAFETY: forwarded contract.
        let (m, out) = unsafe { (live_model(model)?, output(out, "out")?) };
        *out = rolling_to_c(&m.model.rolling);
        Ok(())
    })
}

fn parse_transport(code: i32) -> Result<Transport, Error> {
    Ok(match code {
        RSL_TRANSPORT_EXACT => Transport::Exact,
        RSL_TRANSPORT_PROJECT_RESCALE => Transport::ProjectRescale,
        RSL_TRANSPORT_FIRST_ORDER => Transport::FirstOrder,
        RSL_TRANSPORT_PROJECT => Transport::Project,
        RSL_TRANSPORT_NONE => Transport::None,
        other => return Err(bad("transport", other)),
    })
}

/// Sets the history transport schemes (`RSL_TRANSPORT_*`) of the sliding spring and of the
/// rolling spring (LIGGGHTS, for example, projects the first and never rotates the second).
///
/// # Safety
/// As `rsl_model_set_geometry`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_transport(
    model: *mut rsl_model,
    sliding_scheme: i32,
    rolling_scheme: i32,
) -> i32 {
    guard(|| {
        let sliding = parse_transport(sliding_scheme)?;
        let rolling = parse_transport(rolling_scheme)?;
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.sliding_transport = sliding;
                m.rolling_transport = rolling;
                Ok(())
            })
        }
    })
}

/// Turns the per-step energy bookkeeping on (`enabled` = 1) or off (0, the default).
///
/// # Safety
/// As `rsl_model_set_geometry`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_energy_tracking(model: *mut rsl_model, enabled: i32) -> i32 {
    guard(|| {
        let on = on_off(enabled, "energy tracking flag (0 or 1)")?;
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.track_energy = on;
                Ok(())
            })
        }
    })
}

/// LIGGGHTS' `torsionTorque on` (`enabled` = 1) or off (0, the default, as in LIGGGHTS): the
/// cdt and EPSD rolling laws then act on the whole relative spin `w1 - w2` (rad/time, global
/// frame) instead of its tangential part `(w1 - w2)_t`, so the rolling moment also has a
/// component about the normal, bounded by the same rolling limit: cdt gives
/// `-eta k_n delta (w1 - w2)/|w1 - w2|` on body 1 (`eta` = the rolling limit length), EPSD
/// increments its stored moment by `k_theta dt (w1 - w2)` and damps the whole spin below the
/// limit. The viscous law is unaffected. Only for a model of the `RSL_PRESET_LIGGGHTS_3_8`
/// preset with the angle form (`RSL_FORM_ANGLE`, that preset's default):
/// `RSL_ERR_INVALID_PARAMETER` otherwise, and then, or for `enabled` other than 0 and 1, the
/// model is unchanged. Changing the rolling law to the length form later is refused while the
/// switch is on.
///
/// # Safety
/// As `rsl_model_set_geometry`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_torsion_torque(model: *mut rsl_model, enabled: i32) -> i32 {
    guard(|| {
        let on = on_off(enabled, "torsion torque flag (0 or 1)")?;
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                m.torsion_torque = on;
                Ok(())
            })
        }
    })
}

/// YADE's `avoidGranularRatcheting` flag of `Ig2_Sphere_Sphere_ScGeom6D`: 1 (the default, as
/// in YADE) drives the sliding spring with YADE's incident velocity (the full radii as arms,
/// `v2 - v1` scaled by `(R1 + R2)/d`); 0 with the relative velocity of the two spheres'
/// material points at the contact point (arms `R_k - delta/2`, the decomposition's sliding
/// velocity: what YADE computes with the flag False). The shear forces of the two differ by
/// O(delta/R) of the relative motion. Only for a model of the `RSL_PRESET_YADE_2023` preset:
/// `RSL_ERR_INVALID_PARAMETER` otherwise, and then, or for `enabled` other than 0 and 1, the
/// model is unchanged.
///
/// # Safety
/// As `rsl_model_set_geometry`.
#[no_mangle]
pub unsafe extern "C" fn rsl_model_set_avoid_granular_ratcheting(
    model: *mut rsl_model,
    enabled: i32,
) -> i32 {
    guard(|| {
        let on = on_off(enabled, "avoidGranularRatcheting flag (0 or 1)")?;
        // SAFETY: forwarded contract.
        unsafe {
            update(model, |m| {
                // Refused for other presets in both positions (1 would be a silent no-op).
                if m.preset != crate::laws::model::Preset::Yade2023 {
                    return Err(Error::InvalidParameter(
                        crate::laws::model::AVOID_RATCHETING_NEEDS_YADE.into(),
                    ));
                }
                m.contact_point_sliding = !on;
                Ok(())
            })
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::capi::status::{RSL_ERR_INVALID_PARAMETER, RSL_OK};

    /// `RSL_TWISTING_MARSHALL` ignores the three SDS values, as the header says: even NaN or
    /// negative ones are accepted; `RSL_TWISTING_SDS` still checks them.
    #[test]
    fn marshall_twisting_ignores_the_sds_values() {
        let mut p: *mut rsl_model = std::ptr::null_mut();
        // SAFETY: `p` is a valid out pointer; the live handle it receives is freed at the end.
        unsafe {
            assert_eq!(rsl_model_new(RSL_PRESET_OBJECTIVE, &mut p), RSL_OK);
            let nan = f64::NAN;
            assert_eq!(
                rsl_model_set_twisting(p, RSL_TWISTING_MARSHALL, nan, -1.0, nan),
                RSL_OK
            );
            assert_eq!(
                rsl_model_set_twisting(p, RSL_TWISTING_SDS, nan, 0.1, 0.05),
                RSL_ERR_INVALID_PARAMETER
            );
            rsl_model_free(p);
        }
    }

    /// The sliding history: set and read back; an undefined code and any history but the force
    /// for YADE_2023 are refused with the model unchanged; `rsl_model_set_sliding` keeps it; a
    /// rescaled history (and energy tracking) makes the history record keep the model memory.
    #[test]
    fn sliding_history_round_trip_refusals_and_record_size() {
        use crate::capi::batch::rsl_model_history_size;
        let mut p: *mut rsl_model = std::ptr::null_mut();
        let mut y: *mut rsl_model = std::ptr::null_mut();
        // SAFETY: `p`, `y` are valid out pointers; the live handles are freed at the end.
        unsafe {
            let history = |m: *const rsl_model| {
                let mut h = -1;
                assert_eq!(rsl_model_get_sliding_history(m, &mut h), RSL_OK);
                h
            };
            let words = |m: *const rsl_model| {
                let mut w = 0;
                assert_eq!(rsl_model_history_size(m, &mut w), RSL_OK);
                w
            };
            assert_eq!(rsl_model_new(RSL_PRESET_LAMMPS_2021, &mut p), RSL_OK);
            assert_eq!(
                rsl_model_set_sliding(p, RSL_SLIDING_LINEAR, 1e5, 1.0, 0.5),
                RSL_OK
            );
            assert_eq!(history(p), RSL_SLIDING_HISTORY_DISPLACEMENT);
            assert_eq!(words(p), 7);
            for h in [
                RSL_SLIDING_HISTORY_FORCE,
                RSL_SLIDING_HISTORY_DISPLACEMENT_RESCALED,
                RSL_SLIDING_HISTORY_FORCE_RESCALED,
            ] {
                assert_eq!(rsl_model_set_sliding_history(p, h), RSL_OK);
                assert_eq!(history(p), h);
            }
            // Rescaled: the record keeps the previous stiffnesses (and the normal before them).
            assert_eq!(words(p), 13);
            assert_eq!(
                rsl_model_set_sliding(p, RSL_SLIDING_LINEAR, 2e5, 1.0, 0.5),
                RSL_OK
            );
            assert_eq!(history(p), RSL_SLIDING_HISTORY_FORCE_RESCALED);
            for bad in [-1, 4, i32::MAX] {
                assert_eq!(
                    rsl_model_set_sliding_history(p, bad),
                    RSL_ERR_INVALID_PARAMETER
                );
                assert_eq!(history(p), RSL_SLIDING_HISTORY_FORCE_RESCALED);
            }
            assert_eq!(
                rsl_model_set_sliding_history(p, RSL_SLIDING_HISTORY_FORCE),
                RSL_OK
            );
            assert_eq!(words(p), 7);
            assert_eq!(rsl_model_set_energy_tracking(p, 1), RSL_OK);
            assert_eq!(words(p), 13);
            assert_eq!(rsl_model_new(RSL_PRESET_YADE_2023, &mut y), RSL_OK);
            assert_eq!(history(y), RSL_SLIDING_HISTORY_FORCE);
            assert_eq!(
                rsl_model_set_sliding_history(y, RSL_SLIDING_HISTORY_FORCE),
                RSL_OK
            );
            assert_eq!(
                rsl_model_set_sliding_history(y, RSL_SLIDING_HISTORY_DISPLACEMENT),
                RSL_ERR_INVALID_PARAMETER
            );
            assert_eq!(history(y), RSL_SLIDING_HISTORY_FORCE);
            rsl_model_free(p);
            rsl_model_free(y);
        }
    }
}
