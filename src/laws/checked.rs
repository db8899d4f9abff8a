//! The checked contact step for scalar types: validates every input and the stored state,
//! runs the generic step on a copy, and commits the new state only when every output is finite.

use crate::decompose::{decompose_pair, decompose_wall, Parts, Sphere, Wall};
use crate::error::Error;
use crate::geometry::check_finite_vec;
use crate::laws::model::{Model, RollingDamping, RollingLaw};
use crate::laws::step::{contact_step_with_geometry, ContactState, Partner, StepInput, StepOutput};
use nalgebra::RealField;

fn finite_nonneg<T: RealField + Copy>(x: T, what: &'static str) -> Result<(), Error> {
    if !x.is_finite() {
        return Err(Error::NonFinite(what));
    }
    if x < T::zero() {
        return Err(Error::InvalidArgument(format!("{what} must be >= 0")));
    }
    Ok(())
}

/// As [`finite_nonneg`], but +inf is accepted (a fixed body).
fn fixed_or_finite_nonneg<T: RealField + Copy>(x: T, what: &'static str) -> Result<(), Error> {
    if x > T::zero() && !x.is_finite() {
        Ok(())
    } else {
        finite_nonneg(x, what)
    }
}

fn positive<T: RealField + Copy>(x: T, what: &str) -> Result<(), Error> {
    if x.is_finite() && x > T::zero() {
        Ok(())
    } else {
        Err(Error::InvalidArgument(format!(
            "{what} must be finite and > 0 for this model"
        )))
    }
}

fn check_input<T: RealField + Copy>(
    model: &Model,
    input: &StepInput<T>,
    wall: bool,
) -> Result<(), Error> {
    if !input.normal_force.is_finite() {
        return Err(Error::NonFinite("normal force"));
    }
    if !(input.dt.is_finite() && input.dt > T::zero()) {
        return Err(Error::InvalidTimeStep);
    }
    finite_nonneg(input.normal_stiffness, "normal_stiffness")?;
    finite_nonneg(input.contact_radius, "contact_radius")?;
    finite_nonneg(input.mass1, "mass1")?;
    finite_nonneg(input.inertia1, "inertia1")?;
    // Body 2 may be fixed: +inf mass or inertia (its inverse is 0, as for a wall).
    fixed_or_finite_nonneg(input.mass2, "mass2")?;
    fixed_or_finite_nonneg(input.inertia2, "inertia2")?;
    if let Some(k) = input.sliding_stiffness {
        finite_nonneg(k, "sliding_stiffness")?;
    }
    if let Some(g) = input.sliding_damping {
        finite_nonneg(g, "sliding_damping")?;
    }
    if let Some(f) = input.limit_force {
        // +inf means "no limit" (every limit is +inf; a zero coefficient stays 0).
        fixed_or_finite_nonneg(f, "limit_force")?;
    }
    for (value, what) in [
        (input.rolling_stiffness, "rolling_stiffness"),
        (input.rolling_damping, "rolling_damping"),
        (input.twisting_stiffness, "twisting_stiffness"),
        (input.twisting_damping, "twisting_damping"),
    ] {
        if let Some(x) = value {
            finite_nonneg(x, what)?;
        }
    }
    for (value, what) in [
        (input.sliding_friction, "sliding_friction"),
        (input.rolling_friction, "rolling_friction"),
        (input.twisting_friction, "twisting_friction"),
        (input.shear_adhesion, "shear_adhesion"),
    ] {
        if let Some(x) = value {
            // +inf means "no limit"; NaN and -inf are non-finite input.
            match x.partial_cmp(&T::zero()) {
                None => return Err(Error::NonFinite(what)),
                Some(std::cmp::Ordering::Less) if !x.is_finite() => {
                    return Err(Error::NonFinite(what))
                }
                Some(std::cmp::Ordering::Less) => {
                    return Err(Error::InvalidArgument(format!(
                        "{what} must be >= 0 (or +inf for no limit)"
                    )))
                }
                _ => {}
            }
        }
    }
    if input.fragile_bond && input.shear_adhesion.is_none() {
        return Err(Error::InvalidArgument(
            "a fragile bond needs its shear_adhesion (RSL_INPUT_FRAGILE_BOND without \
             RSL_INPUT_SHEAR_ADHESION)"
                .into(),
        ));
    }
    let r = &model.rolling;
    let infinite = |x: Option<T>| x.is_some_and(|x| !x.is_finite());
    if r.law == RollingLaw::Cdt && infinite(input.rolling_friction) {
        return Err(Error::InvalidArgument(
            "rolling_friction = +inf: cdt's coefficient sets its moment (mu_r R_r f), not a limit"
                .into(),
        ));
    }
    if r.law == RollingLaw::Cdt && !model.liggghts_cdt() && infinite(input.limit_force) {
        return Err(Error::InvalidArgument(
            "limit_force = +inf: cdt's moment is mu_r R_r times that force, not limited by it"
                .into(),
        ));
    }
    if r.law == RollingLaw::Epsd
        && r.stiffness_from_friction()
        && input.rolling_stiffness.is_none()
        && infinite(input.rolling_friction)
    {
        return Err(Error::InvalidArgument(
            "rolling_friction = +inf: this EPSD rule derives the rolling stiffness from mu_r \
             (give RSL_INPUT_ROLLING_STIFFNESS, or a finite coefficient)"
                .into(),
        ));
    }
    let needs_kn = model.needs_normal_stiffness();
    if needs_kn {
        positive(input.normal_stiffness, "normal_stiffness")?;
    }
    if r.law == RollingLaw::Epsd && r.damping_rule == RollingDamping::Ratio {
        positive(input.mass1, "mass1")?;
        finite_nonneg(input.inertia1, "inertia1")?;
        if !wall {
            // Finite and > 0, or +inf (a fixed body 2); NaN was refused above.
            if input.mass2 <= T::zero() {
                positive(input.mass2, "mass2")?;
            }
        }
    }
    Ok(())
}

fn check_state<T: RealField + Copy>(s: &ContactState<T>) -> Result<(), Error> {
    check_finite_vec(&s.sliding_spring, "state: sliding spring")?;
    check_finite_vec(&s.rolling_spring, "state: rolling spring")?;
    check_finite_vec(&s.previous_normal, "state: previous normal")?;
    check_finite_vec(&s.model_memory, "state: model memory")?;
    if !s.twisting_angle.is_finite() {
        return Err(Error::NonFinite("state: twisting angle"));
    }
    Ok(())
}

/// The input state of a model that keeps the previous stiffnesses
/// ([`Model::stiffness_memory`]): each finite (tested with the state) and >= 0.
fn check_memory<T: RealField + Copy>(model: &Model, s: &ContactState<T>) -> Result<(), Error> {
    let m = &s.model_memory;
    if model.stiffness_memory() && (m.x < T::zero() || m.y < T::zero() || m.z < T::zero()) {
        return Err(Error::InvalidArgument(
            "state: model memory (the previous step's stiffnesses) must be >= 0".into(),
        ));
    }
    Ok(())
}

fn check_output<T: RealField + Copy>(
    out: &StepOutput<T>,
    state: &ContactState<T>,
) -> Result<(), Error> {
    let l = &out.loads;
    for (v, what) in [
        (&l.force1, "force"),
        (&l.torque1, "torque on body 1"),
        (&l.torque2, "torque on body 2"),
        (&out.sliding_force, "sliding force"),
        (&out.rolling_moment, "rolling moment"),
        (&out.twisting_torque, "twisting torque"),
    ] {
        check_finite_vec(v, what).map_err(|_| Error::NonFinite("result overflowed"))?;
    }
    // Every reported energy term too: a huge but finite spring can square to +inf.
    let energies = out.energy.terms();
    if !energies.iter().all(|x| x.is_finite()) {
        return Err(Error::NonFinite("result overflowed (energy terms)"));
    }
    check_state(state).map_err(|_| Error::NonFinite("new state overflowed"))
}

/// One checked step of a sphere pair: every input and the state are validated, and `state` is
/// written only on success (and not at all with `input.setup`).
pub fn contact_step_pair<T: RealField + Copy>(
    model: &Model,
    body1: &Sphere<T>,
    body2: &Sphere<T>,
    input: &StepInput<T>,
    state: &mut ContactState<T>,
) -> Result<StepOutput<T>, Error> {
    // The decomposition's own checks (finite bodies, radii, coincident centres, branches); its
    // geometry is the one the step uses (computed once).
    let g = decompose_pair(body1, body2, model.geometry, Parts(0))?.geometry;
    check_input(model, input, false)?;
    check_state(state)?;
    check_memory(model, state)?;
    let mut next = *state;
    let out = contact_step_with_geometry(model, g, body1, Partner::Sphere(body2), input, &mut next);
    check_output(&out, &next)?;
    *state = next;
    Ok(out)
}

/// One checked step of a sphere against a flat wall (the wall normal need not be unit).
pub fn contact_step_wall<T: RealField + Copy>(
    model: &Model,
    sphere: &Sphere<T>,
    wall: &Wall<T>,
    input: &StepInput<T>,
    state: &mut ContactState<T>,
) -> Result<StepOutput<T>, Error> {
    let d = decompose_wall(sphere, wall, model.geometry, Parts(0))?;
    check_input(model, input, true)?;
    check_state(state)?;
    check_memory(model, state)?;
    let unit = Wall {
        normal: -d.geometry.normal,
        ..*wall
    };
    let mut next = *state;
    let out = contact_step_with_geometry(
        model,
        d.geometry,
        sphere,
        Partner::Wall(&unit),
        input,
        &mut next,
    );
    check_output(&out, &next)?;
    *state = next;
    Ok(out)
}
