//! The per-contact step's fast path (`rsl_contact_step`, `rsl_contact_step_wall` and their
//! accumulating forms, with or without per-contact coefficients and limit force): one
//! branch-free validity test instead of a check per field, then the step the batch kernels run
//! ([`contact_step_with_geometry`]). The setup pass and cohesive bonds go to the checked step.
//!
//! It accepts only what the checked step ([`contact_step_pair`], `contact_step_wall`) accepts,
//! and gives the same bits: the geometry comes from the same formula
//! ([`pair_geometry_unchecked`], which the checked path's `pair_geometry` wraps, and the same
//! for a wall) and the same step follows. Anything the test does not pass,
//! and any non-finite result, goes to the checked step, which returns the precise error (or,
//! for inputs the quick test is stricter about than the checked step, the result).
//!
//! Its finiteness tests of the C structs as they are stored (the portable and the AVX2 one)
//! are `finite`'s; the C layer (`capi::contact`) builds the per-contact steps from them and
//! this module's [`step_pair_if_valid`] and [`step_wall_if_valid`].

pub(crate) mod finite;

use crate::decompose::{Sphere, Wall};
use crate::error::Error;
use crate::geometry::{
    pair_geometry_in_range, pair_geometry_unchecked, plain_unit_vector, wall_geometry_unchecked,
    ContactGeometry,
};
use crate::laws::checked::contact_step_pair;
use crate::laws::model::{Model, RollingDamping, RollingLaw};
use crate::laws::step::{
    contact_step_with_geometry, written_fields, ContactState, Partner, StepInput, StepOutput,
};
use crate::scalar::FiniteSums;

/// True when `input` is not the setup pass and has no bond (shear adhesion, fragile): the
/// inputs the fast path takes, when their per-contact values are in its range too
/// ([`overrides_in_range`]).
fn unbonded_step(input: &StepInput<f64>) -> bool {
    !input.setup && input.shear_adhesion.is_none() && !input.fragile_bond
}

/// Whether every per-contact value `input` gives (the coefficients that replace the model's and
/// the limit force) is finite and >= 0, tested without a branch per field: the ones the fast
/// path takes. A +inf friction coefficient or limit force ("no limit", which the checked step
/// accepts where the law allows it) is left to the checked step.
#[inline(always)]
pub fn overrides_in_range(input: &StepInput<f64>) -> bool {
    let values = [
        input.sliding_stiffness,
        input.sliding_damping,
        input.sliding_friction,
        input.limit_force,
        input.rolling_stiffness,
        input.rolling_damping,
        input.rolling_friction,
        input.twisting_stiffness,
        input.twisting_damping,
        input.twisting_friction,
    ]
    .map(|v| v.unwrap_or(0.0));
    let mut sums = FiniteSums::default();
    sums.add(values);
    sums.all_finite() & values.iter().fold(true, |ok, &v| ok & (v >= 0.0))
}

/// The values of a sphere in the memory order of the C `rsl_sphere` (centre, velocity, angular
/// velocity, radius), so that four adjacent ones take one SIMD add in [`FiniteSums`].
#[inline(always)]
fn sphere_values(b: &Sphere<f64>) -> [f64; 10] {
    let (p, v, w) = (&b.position, &b.velocity, &b.angular_velocity);
    [p.x, p.y, p.z, v.x, v.y, v.z, w.x, w.y, w.z, b.radius]
}

/// The values of a state in the memory order of the C `rsl_contact_state`.
#[inline(always)]
fn state_values(s: &ContactState<f64>) -> [f64; 13] {
    let (a, b, c, d) = (
        &s.sliding_spring,
        &s.rolling_spring,
        &s.model_memory,
        &s.previous_normal,
    );
    [
        a.x,
        a.y,
        a.z,
        b.x,
        b.y,
        b.z,
        s.twisting_angle,
        c.x,
        c.y,
        c.z,
        d.x,
        d.y,
        d.z,
    ]
}

/// Whether every value of both spheres, the input's first eight (`normal_force` to
/// `inertia2`) and the state is finite, tested with [`FiniteSums`] (so "no" also for finite
/// values whose sum overflows). A caller that holds these values in another layout may test
/// them there instead (the C layer does, with SIMD loads).
#[inline(always)]
pub fn inputs_finite(
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
) -> bool {
    let mut sums = FiniteSums::default();
    sums.add(sphere_values(body1));
    sums.add(sphere_values(body2));
    sums.add(state_values(state));
    sums.add([
        input.normal_force,
        input.dt,
        input.normal_stiffness,
        input.contact_radius,
        input.mass1,
        input.mass2,
        input.inertia1,
        input.inertia2,
    ]);
    sums.all_finite()
}

/// The range part of what the checked step accepts of `input`, for inputs already shown
/// finite, tested without a branch per field. Stricter than the checked step in one place, left
/// to it: a fixed body 2 (`mass2` or `inertia2` +inf).
#[inline(always)]
fn input_in_range(model: &Model, input: &StepInput<f64>, is_wall: bool) -> bool {
    // Non-negative inputs: their minimum is (-0 passes, as it does in the checked step).
    let min = |a: f64, b: f64| if a < b { a } else { b };
    let smallest = min(
        min(
            min(input.normal_stiffness, input.contact_radius),
            min(input.mass1, input.mass2),
        ),
        min(input.inertia1, input.inertia2),
    );
    let mut ok = (smallest >= 0.0) & (input.dt > 0.0);
    if model.needs_normal_stiffness() {
        ok &= input.normal_stiffness > 0.0;
    }
    if model.rolling.law == RollingLaw::Epsd && model.rolling.damping_rule == RollingDamping::Ratio
    {
        // A wall has no mass of its own (the checked step reads none).
        ok &= (input.mass1 > 0.0) & ((input.mass2 > 0.0) | is_wall);
    }
    ok
}

/// The range part of what the checked pair step accepts (geometry and input), for inputs
/// already shown finite ([`input_in_range`] for the input).
#[inline(always)]
fn inputs_in_range(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    g: &ContactGeometry<f64>,
    input: &StepInput<f64>,
) -> bool {
    pair_geometry_in_range(body1.radius, body2.radius, g)
        // Finite centres can be too far apart for a finite distance.
        & (g.distance <= f64::MAX)
        & input_in_range(model, input, false)
}

/// Whether every load, the new state and (when the model tracks energy; otherwise they are 0)
/// every energy term are finite, as the checked step requires ([`FiniteSums`]: "no" also for
/// finite values whose sum overflows).
#[inline(always)]
pub fn outputs_finite(model: &Model, out: &StepOutput<f64>, state: &ContactState<f64>) -> bool {
    let mut sums = FiniteSums::default();
    let l = &out.loads;
    for v in [
        &l.force1,
        &l.torque1,
        &l.torque2,
        &out.sliding_force,
        &out.rolling_moment,
        &out.twisting_torque,
    ] {
        sums.add_vec(v);
    }
    sums.add(state_values(state));
    if model.track_energy {
        sums.add(out.energy.terms());
    }
    sums.all_finite()
}

/// Whether the results of the fast step ([`step_pair_if_valid`]) are finite: the guarantee of
/// [`outputs_finite`] (every load, state value and energy term is finite) from fewer values, for
/// inputs that passed the quick test.
///
/// It adds up `force1`, `torque1`, `torque2`, the state values the model's laws write, and the
/// energy terms if the model tracks them. The rest needs no test:
/// - state values no law writes ([`written_fields`]: the springs of the laws that are off or
///   keep none, as cdt, and the off-axis twist, which only YADE's vector twisting writes) are
///   the input's, shown finite;
/// - the new previous normal `n`, the sliding force `F_t`, the rolling moment `M_r` and the
///   twisting torque `M_tw` each reach the same component of `force1 = F_t - f_n n` or of
///   `torque1 = l1 (n x F_t) + (M_r + M_tw)` through one add or subtract (and, for `n`, a
///   product with the finite `f_n`): a non-finite one makes that component non-finite too
///   (`inf - inf` and `0 inf` are NaN);
/// - `force2` is `-force1`.
#[inline(always)]
pub fn step_outputs_finite(
    model: &Model,
    out: &StepOutput<f64>,
    state: &ContactState<f64>,
) -> bool {
    let mut sums = FiniteSums::default();
    let l = &out.loads;
    for v in [&l.force1, &l.torque1, &l.torque2] {
        sums.add_vec(v);
    }
    let written = written_fields(model);
    if written.sliding_spring {
        sums.add_vec(&state.sliding_spring);
    }
    if written.rolling_spring {
        sums.add_vec(&state.rolling_spring);
    }
    if written.twisting_angle {
        sums.add([state.twisting_angle]);
    }
    if written.model_memory {
        sums.add_vec(&state.model_memory);
    }
    if model.track_energy {
        sums.add(out.energy.terms());
    }
    sums.all_finite()
}

/// The geometry of a pair step, from the formula the checked step's `pair_geometry` wraps.
#[inline(always)]
fn geometry_of_pair(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
) -> ContactGeometry<f64> {
    pair_geometry_unchecked(
        &body1.position,
        &body2.position,
        body1.radius,
        body2.radius,
        model.geometry,
    )
}

/// The geometry of a sphere-wall step and the wall with its unit normal, normalised as the
/// checked step does it where the plain quotient is accurate (the flag: see
/// [`plain_unit_vector`]).
#[inline(always)]
fn geometry_of_wall(
    model: &Model,
    sphere: &Sphere<f64>,
    wall: &Wall<f64>,
) -> (ContactGeometry<f64>, Wall<f64>, bool) {
    let (normal, accurate) = plain_unit_vector(&wall.normal);
    let g = wall_geometry_unchecked(
        &sphere.position,
        sphere.radius,
        &wall.point,
        &normal,
        model.geometry,
    );
    (g, Wall { normal, ..*wall }, accurate)
}

/// The step for geometry `g` of `body1` and `body2`, on a copy of `state`: its output and the
/// new state.
#[inline(always)]
fn step_with(
    model: &Model,
    g: ContactGeometry<f64>,
    body1: &Sphere<f64>,
    body2: Partner<'_, f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
) -> (StepOutput<f64>, ContactState<f64>) {
    let mut next = *state;
    let out = contact_step_with_geometry(model, g, body1, body2, input, &mut next);
    (out, next)
}

/// Whether the state's previous stiffnesses are >= 0 where the model keeps them
/// ([`Model::stiffness_memory`]; NaN fails, and the finite test covers the rest).
#[inline(always)]
fn memory_ok(model: &Model, state: &ContactState<f64>) -> bool {
    let m = &state.model_memory;
    !model.stiffness_memory() || ((m.x >= 0.0) & (m.y >= 0.0) & (m.z >= 0.0))
}

/// The fast path before its output test: the step's output and the new state when the inputs
/// pass the quick test, `None` otherwise. `inputs_finite` is the caller's [`inputs_finite`] (or
/// the same test done on its own layout of the values). The caller must then test the results
/// ([`step_outputs_finite`]) and, on `None` or a non-finite result, run the checked step, which
/// gives the error (or, for the few inputs the quick test is stricter about, the result).
/// `input` must be neither the setup pass nor a bond, and its per-contact values in range
/// ([`overrides_in_range`]). Nothing here is passed by reference to a function that is not
/// inlined, so the compiler keeps the inputs in registers.
#[inline(always)]
pub fn step_pair_if_valid(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
    inputs_finite: bool,
) -> Option<(StepOutput<f64>, ContactState<f64>)> {
    debug_assert!(unbonded_step(input) && overrides_in_range(input));
    let g = geometry_of_pair(model, body1, body2);
    if !(inputs_finite & inputs_in_range(model, body1, body2, &g, input) & memory_ok(model, state))
    {
        return None;
    }
    Some(step_with(
        model,
        g,
        body1,
        Partner::Sphere(body2),
        input,
        state,
    ))
}

/// [`step_pair_if_valid`] for a sphere (body 1) against a flat wall: the step's output and the
/// new state when the inputs pass the quick test, `None` otherwise (then the checked wall step,
/// [`contact_step_wall`](crate::laws::checked::contact_step_wall), gives the error or the
/// result). `inputs_finite` must say that every value of the sphere, the wall, the input's
/// first eight fields and the state is finite. The wall normal need not be unit: it is
/// normalised as the checked step does it (`v / |v|` where that is accurate; the rescaled
/// form of the checked step, for lengths near overflow or underflow, is left to it), so the
/// bits are the checked step's.
#[inline(always)]
pub fn step_wall_if_valid(
    model: &Model,
    sphere: &Sphere<f64>,
    wall: &Wall<f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
    inputs_finite: bool,
) -> Option<(StepOutput<f64>, ContactState<f64>)> {
    debug_assert!(unbonded_step(input) && overrides_in_range(input));
    let (g, wall, unit) = geometry_of_wall(model, sphere, wall);
    let ok = inputs_finite
        & unit
        & (sphere.radius > 0.0)
        & g.overlap.is_finite()
        & (g.branch1 > 0.0)
        & input_in_range(model, input, true)
        & memory_ok(model, state);
    if !ok {
        return None;
    }
    Some(step_with(
        model,
        g,
        sphere,
        Partner::Wall(&wall),
        input,
        state,
    ))
}

/// The step of a sphere pair without any test of its values: [`step_pair_if_valid`]'s geometry
/// and step for inputs the caller vouches for (the unchecked C entries). For valid inputs its
/// bits are [`step_pair_if_valid`]'s; for others it computes what the formulas give (NaN,
/// infinities), without a panic.
#[inline(always)]
pub fn step_pair_unchecked(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
) -> (StepOutput<f64>, ContactState<f64>) {
    let g = geometry_of_pair(model, body1, body2);
    step_with(model, g, body1, Partner::Sphere(body2), input, state)
}

/// [`step_pair_unchecked`] for a sphere against a flat wall: [`step_wall_if_valid`]'s
/// normalisation of the wall normal, geometry and step, without any test.
#[inline(always)]
pub fn step_wall_unchecked(
    model: &Model,
    sphere: &Sphere<f64>,
    wall: &Wall<f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
) -> (StepOutput<f64>, ContactState<f64>) {
    let (g, wall, _) = geometry_of_wall(model, sphere, wall);
    step_with(model, g, sphere, Partner::Wall(&wall), input, state)
}

/// [`step_pair_if_valid`] with the portable tests of the inputs and the results
/// ([`inputs_finite`], [`step_outputs_finite`]): the step's output and new state, or `None` for
/// the checked step to take over.
#[inline(always)]
pub fn try_step_pair(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &ContactState<f64>,
) -> Option<(StepOutput<f64>, ContactState<f64>)> {
    let finite = inputs_finite(body1, body2, input, state);
    let (out, next) = step_pair_if_valid(model, body1, body2, input, state, finite)?;
    step_outputs_finite(model, &out, &next).then_some((out, next))
}

/// One checked step of a sphere pair, as [`contact_step_pair`] (same results, same errors,
/// `state` written only on success), faster. The setup pass, bonds and per-contact values out of
/// the fast path's range ([`overrides_in_range`]) go straight to the checked step.
#[inline(always)]
pub fn contact_step_pair_fast(
    model: &Model,
    body1: &Sphere<f64>,
    body2: &Sphere<f64>,
    input: &StepInput<f64>,
    state: &mut ContactState<f64>,
) -> Result<StepOutput<f64>, Error> {
    if unbonded_step(input) && overrides_in_range(input) {
        if let Some((out, next)) = try_step_pair(model, body1, body2, input, state) {
            *state = next;
            return Ok(out);
        }
    }
    contact_step_pair(model, body1, body2, input, state)
}
