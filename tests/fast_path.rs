//! The per-contact fast path (`rsl_contact_step` without overrides) against the checked step it
//! replaces: the same bits for every accepted input, the same error (and an untouched state)
//! for every refused one, for one model per law set and preset family and for models with the
//! other options.

mod common;

use common::{full_model, law_set_models, length_form_models, Rng};
use rollslide::decompose::Sphere;
use rollslide::laws::checked::contact_step_pair;
use rollslide::laws::fast_path::{
    contact_step_pair_fast, inputs_finite, step_outputs_finite, step_pair_if_valid,
};
use rollslide::laws::model::{
    Model, Preset, RollingDamping, RollingForm, RollingLaw, RollingStiffness, SlidingLaw,
    Transport, TwistingLaw,
};
use rollslide::laws::step::{written_fields, ContactState, StepInput, StepOutput};
use rollslide::scalar::Vec3;

/// One model per law set and preset family ([`law_set_models`], the LIGGGHTS ones in both
/// rolling forms) and models with the other options (energy tracking, YADE, LIGGGHTS' cdt with
/// `k_n` and sds twisting, EPSD-derived stiffness, damping-ratio rolling damping, Marshall
/// twisting with first-order transports).
fn models() -> Vec<Model> {
    let full = full_model(Preset::Objective, Transport::Exact);
    let mut energy = full;
    energy.track_energy = true;
    let mut yade = full_model(Preset::Yade2023, Transport::FirstOrder);
    yade.rolling.form = RollingForm::Angle;
    let mut liggghts = full_model(Preset::Liggghts38, Transport::Project);
    liggghts.rolling.law = RollingLaw::Cdt;
    let mut derived = full;
    derived.rolling.stiffness_rule = RollingStiffness::Epsd;
    let mut ratio = full;
    ratio.rolling.damping_rule = RollingDamping::Ratio;
    ratio.rolling.damping = 0.3;
    // Marshall twisting with first-order transports (the law-set models have it with the
    // objective preset's exact transports and with LAMMPS').
    let mut marshall = full;
    marshall.twisting.law = TwistingLaw::Marshall;
    marshall.sliding_transport = Transport::FirstOrder;
    marshall.rolling_transport = Transport::FirstOrder;
    // The law-set models, and the LIGGGHTS ones in the length form too.
    let mut models: Vec<Model> = law_set_models()
        .into_iter()
        .chain(length_form_models())
        .map(|(m, _)| m)
        .collect();
    models.extend([energy, yade, liggghts, derived, ratio, marshall]);
    for m in &models {
        m.validate().expect("test model is valid");
    }
    models
}

struct Case {
    b1: Sphere<f64>,
    b2: Sphere<f64>,
    input: StepInput<f64>,
    state: ContactState<f64>,
}

/// An overlapping pair with random rates, a history tilted off the current normal, and springs
/// large enough that a good part of the contacts slip.
fn case(rng: &mut Rng) -> Case {
    let r1 = rng.uniform(0.5, 1.5);
    let r2 = rng.uniform(0.5, 1.5);
    let n = rng.unit();
    let p1 = rng.vec(5.0);
    let sphere = |p: Vec3<f64>, r: f64, rng: &mut Rng| Sphere {
        position: p,
        velocity: rng.vec(0.5),
        angular_velocity: rng.vec(3.0),
        radius: r,
    };
    let b1 = sphere(p1, r1, rng);
    let b2 = sphere(p1 + n * ((r1 + r2) * rng.uniform(0.97, 0.999)), r2, rng);
    let mut input = StepInput::new(rng.uniform(0.0, 200.0), 1e-4);
    input.normal_stiffness = 1e6;
    input.mass1 = 2.0;
    input.mass2 = 3.0;
    input.inertia1 = 0.4;
    input.inertia2 = 0.6;
    let old = (n + rng.vec(0.02)).normalize();
    let tangent = |v: Vec3<f64>| v - old * v.dot(&old);
    let state = ContactState {
        sliding_spring: tangent(rng.vec(5e-4)),
        rolling_spring: tangent(rng.vec(2e-4)),
        twisting_angle: rng.uniform(-1e-2, 1e-2),
        model_memory: Vec3::zeros(),
        previous_normal: old,
    };
    Case {
        b1,
        b2,
        input,
        state,
    }
}

/// Every value of a step's output: the loads (`force2` included), the law outputs and the
/// energy terms.
fn output_values(o: &StepOutput<f64>) -> Vec<f64> {
    let mut v: Vec<f64> = [
        o.loads.force1,
        o.loads.torque1,
        o.loads.force2,
        o.loads.torque2,
        o.sliding_force,
        o.rolling_moment,
        o.twisting_torque,
    ]
    .iter()
    .flat_map(|x| x.iter().copied().collect::<Vec<_>>())
    .collect();
    v.extend(o.energy.terms());
    v
}

/// Every value of a state.
fn state_values(s: &ContactState<f64>) -> Vec<f64> {
    let mut v: Vec<f64> = [
        s.sliding_spring,
        s.rolling_spring,
        s.model_memory,
        s.previous_normal,
    ]
    .iter()
    .flat_map(|x| x.iter().copied().collect::<Vec<_>>())
    .collect();
    v.push(s.twisting_angle);
    v
}

fn bits(o: &StepOutput<f64>) -> Vec<u64> {
    let mut v: Vec<u64> = output_values(o).iter().map(|x| x.to_bits()).collect();
    v.extend(o.slipped.iter().map(|&s| s as u64));
    v
}

fn state_bits(s: &ContactState<f64>) -> Vec<u64> {
    state_values(s).iter().map(|x| x.to_bits()).collect()
}

/// Runs both paths from the same state; asserts the same result (bits) or the same error, and
/// the same state afterwards. Returns whether the step succeeded.
fn same(model: &Model, c: &Case, what: &str) -> bool {
    let (mut s_checked, mut s_fast) = (c.state, c.state);
    let checked = contact_step_pair(model, &c.b1, &c.b2, &c.input, &mut s_checked);
    let fast = contact_step_pair_fast(model, &c.b1, &c.b2, &c.input, &mut s_fast);
    match (&checked, &fast) {
        (Ok(a), Ok(b)) => assert_eq!(bits(a), bits(b), "{what}: outputs differ"),
        (Err(a), Err(b)) => assert_eq!(a, b, "{what}: errors differ"),
        _ => panic!("{what}: checked {checked:?} but fast {fast:?}"),
    }
    assert_eq!(
        state_bits(&s_checked),
        state_bits(&s_fast),
        "{what}: states differ"
    );
    if checked.is_err() {
        assert_eq!(
            state_bits(&s_fast),
            state_bits(&c.state),
            "{what}: refused step wrote the state"
        );
    }
    checked.is_ok()
}

#[test]
fn accepted_inputs_give_the_same_bits_over_many_steps() {
    let mut rng = Rng::new(7);
    for (k, model) in models().iter().enumerate() {
        let mut slipped = 0;
        for i in 0..200 {
            let mut c = case(&mut rng);
            // A few steps in a row: the histories each path writes feed its next step.
            for step in 0..5 {
                let (mut s1, mut s2) = (c.state, c.state);
                let a = contact_step_pair(model, &c.b1, &c.b2, &c.input, &mut s1).unwrap();
                let b = contact_step_pair_fast(model, &c.b1, &c.b2, &c.input, &mut s2).unwrap();
                assert_eq!(bits(&a), bits(&b), "model {k} case {i} step {step}");
                assert_eq!(state_bits(&s1), state_bits(&s2), "model {k} case {i}");
                slipped += a.slipped[0] as usize;
                c.state = s1;
                c.b1.position += c.b1.velocity * c.input.dt;
                c.b2.position += c.b2.velocity * c.input.dt;
            }
        }
        if model.sliding.law == SlidingLaw::Linear {
            assert!(slipped > 50, "model {k}: the clip ran only {slipped} times");
        }
    }
}

/// `written_fields` is exact: a step changes no field it leaves out (the batch kernels neither
/// write those back nor test them again), and every field it names changes in some step.
#[test]
fn a_step_changes_exactly_its_written_fields() {
    let mut rng = Rng::new(29);
    let mut left_alone = 0;
    for (k, model) in models().iter().enumerate() {
        let w = written_fields(model);
        let named = [
            w.sliding_spring,
            w.rolling_spring,
            w.twisting_angle,
            w.model_memory,
            w.previous_normal,
        ];
        let mut changed = [false; 5];
        for i in 0..100 {
            let mut c = case(&mut rng);
            // A model memory that a step could only keep by leaving it alone (>= 0: a model
            // that keeps the previous stiffnesses refuses negative ones).
            c.state.model_memory = rng.vec(1e-3).map(f64::abs);
            let mut s = c.state;
            contact_step_pair(model, &c.b1, &c.b2, &c.input, &mut s).unwrap();
            let v3 = |v: Vec3<f64>| v.map(f64::to_bits);
            let moved = [
                v3(s.sliding_spring) != v3(c.state.sliding_spring),
                v3(s.rolling_spring) != v3(c.state.rolling_spring),
                s.twisting_angle.to_bits() != c.state.twisting_angle.to_bits(),
                v3(s.model_memory) != v3(c.state.model_memory),
                v3(s.previous_normal) != v3(c.state.previous_normal),
            ];
            for f in 0..5 {
                assert!(
                    named[f] || !moved[f],
                    "model {k} case {i}: field {f} changed"
                );
                changed[f] |= moved[f];
            }
        }
        assert_eq!(changed, named, "model {k}: a named field never changed");
        left_alone += named.iter().filter(|&&on| !on).count();
    }
    // Not every field of every model: the test has fields to catch a write in.
    assert!(left_alone >= 10, "{left_alone}");
}

#[test]
fn refused_inputs_give_the_same_error_and_leave_the_state() {
    let mut rng = Rng::new(11);
    let bad = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 0.0, 1e300];
    type Poke = fn(&mut Case, f64);
    let pokes: Vec<(&str, Poke)> = vec![
        ("normal force", |c, x| c.input.normal_force = x),
        ("dt", |c, x| c.input.dt = x),
        ("normal stiffness", |c, x| c.input.normal_stiffness = x),
        ("contact radius", |c, x| c.input.contact_radius = x),
        ("mass1", |c, x| c.input.mass1 = x),
        ("mass2", |c, x| c.input.mass2 = x),
        ("inertia1", |c, x| c.input.inertia1 = x),
        ("inertia2", |c, x| c.input.inertia2 = x),
        ("radius1", |c, x| c.b1.radius = x),
        ("radius2", |c, x| c.b2.radius = x),
        ("position1.y", |c, x| c.b1.position.y = x),
        ("velocity2.z", |c, x| c.b2.velocity.z = x),
        ("spin1.x", |c, x| c.b1.angular_velocity.x = x),
        ("sliding spring", |c, x| c.state.sliding_spring.x = x),
        ("rolling spring", |c, x| c.state.rolling_spring.y = x),
        ("twisting angle", |c, x| c.state.twisting_angle = x),
        ("off-axis twist", |c, x| c.state.model_memory.z = x),
        ("previous normal", |c, x| c.state.previous_normal.x = x),
        ("coincident centres", |c, _| c.b2.position = c.b1.position),
    ];
    let mut refused = 0;
    for model in models() {
        for (what, poke) in &pokes {
            for &x in &bad {
                let mut c = case(&mut rng);
                poke(&mut c, x);
                if !same(&model, &c, &format!("{what} = {x}")) {
                    refused += 1;
                }
            }
        }
        // A fixed body 2 (+inf mass and inertia) is accepted (by the checked step).
        let mut c = case(&mut rng);
        c.input.mass2 = f64::INFINITY;
        c.input.inertia2 = f64::INFINITY;
        assert!(same(&model, &c, "fixed body 2"));
    }
    eprintln!("{refused} refused inputs, each with the same error on both paths");
    // Most pokes are refusals; the test would be empty if none were.
    assert!(refused > 500, "only {refused} refusals");
}

/// The fast step and its result test, on inputs that pass the quick test:
/// `Some((results finite by the fast path's test, output, new state))`.
fn fast_step(model: &Model, c: &Case) -> Option<(bool, StepOutput<f64>, ContactState<f64>)> {
    let finite = inputs_finite(&c.b1, &c.b2, &c.input, &c.state);
    let (o, next) = step_pair_if_valid(model, &c.b1, &c.b2, &c.input, &c.state, finite)?;
    Some((step_outputs_finite(model, &o, &next), o, next))
}

/// `step_outputs_finite` tests only `force1`, `torque1`, `torque2`, the state values the
/// model's laws write and, when the model tracks them, the energy terms. On finite inputs pushed
/// to extremes (springs, rates, stiffnesses, time steps and forces up to 1e300, and zeros), so
/// that many results overflow, for every model: it never says yes to a result with a non-finite
/// value, and the state values it leaves out are the input's, bit for bit. Results it refuses go
/// to the checked step, which names the error; so the per-contact call accepts exactly what it
/// accepted when it tested every value.
#[test]
fn step_result_test_never_passes_a_non_finite_result() {
    let mut rng = Rng::new(23);
    let extremes = [1e300, -1e300, 1e200, 1e160, -1e160, 1e-300, 0.0];
    let (mut stepped, mut non_finite, mut hidden) = (0, 0, 0);
    for (k, base) in models().into_iter().enumerate() {
        for i in 0..3000 {
            let mut model = base;
            let mut c = case(&mut rng);
            // Push two to four knobs to an extreme each.
            for _ in 0..2 + rng.next_u64() % 3 {
                let x = extremes[(rng.next_u64() % extremes.len() as u64) as usize];
                match rng.next_u64() % 15 {
                    0 => c.state.sliding_spring.x = x,
                    1 => c.state.rolling_spring.y = x,
                    2 => c.state.twisting_angle = x,
                    3 => c.b1.angular_velocity.z = x,
                    4 => c.b2.velocity.x = x,
                    5 => c.input.normal_force = x,
                    6 => c.input.dt = x.abs().max(1e-300),
                    7 => model.sliding.stiffness = x.abs(),
                    8 => model.sliding.damping = x.abs(),
                    9 => model.rolling.stiffness = x.abs(),
                    10 => model.rolling.damping = x.abs(),
                    11 => model.twisting.stiffness = x.abs(),
                    12 => model.twisting.damping = x.abs(),
                    13 => c.input.normal_stiffness = x.abs(),
                    _ => c.state.previous_normal.y = x,
                }
            }
            if model.validate().is_err() {
                continue;
            }
            let Some((passed, o, next)) = fast_step(&model, &c) else {
                continue;
            };
            stepped += 1;
            let all_finite = output_values(&o)
                .iter()
                .chain(&state_values(&next))
                .all(|x| x.is_finite());
            assert!(
                all_finite || !passed,
                "model {k} case {i}: passed a non-finite result {o:?} {next:?}"
            );
            if !all_finite {
                non_finite += 1;
                // A non-finite value outside the tested ones, caught through force1 or torque1.
                let tested_finite = [o.loads.force1, o.loads.torque1, o.loads.torque2]
                    .iter()
                    .all(|v| v.iter().all(|x| x.is_finite()));
                let others = [o.sliding_force, o.rolling_moment, o.twisting_torque];
                if !tested_finite
                    && (others.iter().any(|v| v.iter().any(|x| !x.is_finite()))
                        || next.previous_normal.iter().any(|x| !x.is_finite()))
                {
                    hidden += 1;
                }
            }
            // The state values the test leaves out are the input's (the off-axis twist is
            // written by YADE's vector twisting only).
            if !written_fields(&model).model_memory {
                assert_eq!(
                    next.model_memory.map(f64::to_bits),
                    c.state.model_memory.map(f64::to_bits)
                );
            }
            if model.sliding.law == SlidingLaw::None {
                assert_eq!(
                    next.sliding_spring.map(f64::to_bits),
                    c.state.sliding_spring.map(f64::to_bits)
                );
            }
            // Only the EPSD law keeps a rolling spring (cdt has no history).
            if model.rolling.law != RollingLaw::Epsd {
                assert_eq!(
                    next.rolling_spring.map(f64::to_bits),
                    c.state.rolling_spring.map(f64::to_bits)
                );
            }
            if model.twisting.law == TwistingLaw::None {
                assert_eq!(
                    next.twisting_angle.to_bits(),
                    c.state.twisting_angle.to_bits()
                );
            }
        }
    }
    eprintln!(
        "{stepped} steps, {non_finite} with a non-finite result ({hidden} of them in a law output)"
    );
    // The extremes must reach the cases the argument is about.
    assert!(non_finite > 1000, "only {non_finite} non-finite results");
    assert!(hidden > 100, "only {hidden} non-finite law outputs");
}
