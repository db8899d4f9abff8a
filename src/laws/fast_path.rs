//! The per-contact step's fast path (`rsl_contact_step` without per-contact overrides): one
//! branch-free validity test instead of a check per field, and the model's scene kernel (its
//! law choices folded into constants, as the batch kernels do) instead of the run-time
//! decisions of the generic step.
//!
//! It accepts only what the checked step ([`contact_step_pair`]) accepts, and gives the same
//! bits: the geometry comes from the same formula ([`pair_geometry_unchecked`], which the
//! checked path's `pair_geometry` wraps) and the folded model equals the model (that is what
//! [`Scene::classify`] guarantees for the scene passed in). Anything the test does not pass,
//! and any non-finite result, goes to the checked step, which returns the precise error (or,
//! for inputs the quick test is stricter about than the checked step, the result).

use crate::batch::scene::{fold, Scene};
use crate::decompose::Sphere;
use crate::error::Error;
use crate::geometry::{pair_geometry_unchecked, pair_geometry_valid};
use crate::laws::checked::contact_step_pair;
use crate::laws::model::{Model, RollingDamping, RollingLaw};
use crate::laws::step::{contact_step_with_geometry, ContactState, Partner, StepInput, StepOutput};
use crate::scalar::{finite_probe, zero_if_finite};

/// True when `input` has no per-contact override, no limit force and is not the setup pass:
/// the only inputs the fast path takes.
fn plain(input: &StepInput<f64>) -> bool {
    !input.setup
        && input.sliding_stiffness.is_none()
        && input.sliding_damping.is_none()
        && input.rolling_stiffness.is_none()
        && input.rolling_damping.is_none()
        && input.rolling_friction.is_none()
        && input.twisting_stiffness.is_none()
        && input.twisting_damping.is_none()
        && input.twisting_friction.is_none()
        && input.limit_force.is_none()
}

/// The inputs the checked step would accept, tested without a branch per field (stricter in one
/// place: a fixed body 2, `mass2` or `inertia2` +inf, is left to the checked step).
#[inline(always)]
fn inputs_valid(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
) -> bool {
    let scalars = [
        input.normal_force,
        input.dt,
        input.normal_stiffness,
        input.contact_radius,
        input.mass1,
        input.mass2,
        input.inertia1,
        input.inertia2,
        state.twisting_angle,
    ];
    let mut acc = 0.0;
    for x in scalars {
        acc += zero_if_finite(x);
    }
    for v in [
        &body1.velocity,
        &body1.angular_velocity,
        &body2.velocity,
        &body2.angular_velocity,
        &state.sliding_spring,
        &state.rolling_spring,
        &state.twisting_offaxis,
        &state.previous_normal,
    ] {
        acc = finite_probe(acc, v);
    }
    let mut ok = (acc == 0.0)
        & (input.normal_force >= 0.0)
        & (input.dt > 0.0)
        & (input.normal_stiffness >= 0.0)
        & (input.contact_radius >= 0.0)
        & (input.mass1 >= 0.0)
        & (input.mass2 >= 0.0)
        & (input.inertia1 >= 0.0)
        & (input.inertia2 >= 0.0);
    if model.needs_normal_stiffness() {
        ok &= input.normal_stiffness > 0.0;
    }
    if model.rolling.law == RollingLaw::Epsd && model.rolling.damping_rule == RollingDamping::Ratio
    {
        ok &= (input.mass1 > 0.0) & (input.mass2 > 0.0);
    }
    ok
}

/// Whether every load, energy term and the new state are finite.
#[inline(always)]
fn outputs_finite(out: &StepOutput<f64>, state: &ContactState<f64>) -> bool {
    let mut acc = zero_if_finite(state.twisting_angle);
    for x in out.energy.terms() {
        acc += zero_if_finite(x);
    }
    let l = &out.loads;
    for v in [
        &l.force1,
        &l.torque1,
        &l.torque2,
        &out.sliding_force,
        &out.rolling_moment,
        &out.twisting_torque,
        &state.sliding_spring,
        &state.rolling_spring,
        &state.twisting_offaxis,
        &state.previous_normal,
    ] {
        acc = finite_probe(acc, v);
    }
    acc == 0.0
}

/// The fast path for the scene code `S` (see the module documentation).
#[inline(always)]
fn step_in_scene<const S: u8>(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &mut ContactState<f64>,
) -> Result<StepOutput<f64>, Error> {
    let folded = fold(Scene::from_code(S), model);
    let g = pair_geometry_unchecked(
        &body1.position,
        &body2.position,
        body1.radius,
        body2.radius,
        folded.geometry,
    );
    let valid = pair_geometry_valid(
        &body1.position,
        &body2.position,
        body1.radius,
        body2.radius,
        &g,
    ) & inputs_valid(&folded, body1, body2, input, state);
    if valid {
        let mut next = *state;
        let out =
            contact_step_with_geometry(&folded, g, body1, Partner::Sphere(body2), input, &mut next);
        if outputs_finite(&out, &next) {
            *state = next;
            return Ok(out);
        }
    }
    contact_step_pair(model, body1, body2, input, state)
}

/// One checked step of a sphere pair, as [`contact_step_pair`] (same results, same errors,
/// `state` written only on success), faster: `scene` must be [`Scene::classify`] of `model`.
/// Inputs with overrides, a limit force or the setup pass go straight to the checked step.
/// Inlined, so that a caller compiled with wider instructions (AVX2) runs it with them.
#[inline(always)]
pub fn contact_step_pair_fast(
    model: &Model,
    scene: Scene,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &mut ContactState<f64>,
) -> Result<StepOutput<f64>, Error> {
    if !plain(input) {
        return contact_step_pair(model, body1, body2, input, state);
    }
    match scene {
        Scene::Generic => step_in_scene::<0>(model, body1, body2, input, state),
        Scene::FullExact => step_in_scene::<1>(model, body1, body2, input, state),
        Scene::FullLammps => step_in_scene::<2>(model, body1, body2, input, state),
        Scene::SlidingExact => step_in_scene::<3>(model, body1, body2, input, state),
        Scene::SlidingRollingExact => step_in_scene::<4>(model, body1, body2, input, state),
        Scene::SlidingLammps => step_in_scene::<5>(model, body1, body2, input, state),
    }
}
