//! The per-contact fast path (`rsl_contact_step` without overrides) against the checked step it
//! replaces: the same bits for every accepted input, the same error (and an untouched state)
//! for every refused one, for the models of every scene kernel and for generic ones.

mod common;

use common::{full_model, scene_models, Rng};
use rollslide::batch::Scene;
use rollslide::decompose::Sphere;
use rollslide::laws::checked::contact_step_pair;
use rollslide::laws::fast_path::contact_step_pair_fast;
use rollslide::laws::model::{
    Model, Preset, RollingDamping, RollingForm, RollingLaw, RollingStiffness, SlidingLaw,
    Transport, TwistingLaw,
};
use rollslide::laws::step::{ContactState, StepInput, StepOutput};
use rollslide::scalar::Vec3;

/// Models of every scene kernel and several generic ones (energy tracking, YADE, LIGGGHTS'
/// cdt with `k_n`, EPSD-derived stiffness, damping-ratio rolling damping, Marshall twisting).
fn models() -> Vec<Model> {
    let full = full_model(Preset::Objective, Transport::Exact);
    let lammps = full_model(Preset::Lammps2021, Transport::ProjectRescale);
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
    let mut marshall = lammps;
    marshall.twisting.law = TwistingLaw::Marshall;
    let mut models: Vec<Model> = scene_models().into_iter().map(|(m, _)| m).collect();
    models.extend([energy, yade, liggghts, derived, ratio, marshall]);
    for m in &models {
        m.validate().expect("test model is valid");
    }
    // Both kinds of kernel are exercised.
    let scenes: Vec<Scene> = models.iter().map(Scene::classify).collect();
    assert!(scenes.contains(&Scene::FullLammps) && scenes.contains(&Scene::Generic));
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
        twisting_offaxis: Vec3::zeros(),
        previous_normal: old,
    };
    Case {
        b1,
        b2,
        input,
        state,
    }
}

fn bits(o: &StepOutput<f64>) -> Vec<u64> {
    let mut v = Vec::new();
    for x in [
        o.loads.force1,
        o.loads.torque1,
        o.loads.force2,
        o.loads.torque2,
        o.sliding_force,
        o.rolling_moment,
        o.twisting_torque,
    ] {
        v.extend(x.iter().map(|c| c.to_bits()));
    }
    v.extend(o.energy.terms().iter().map(|x| x.to_bits()));
    v.extend(o.slipped.iter().map(|&s| s as u64));
    v
}

fn state_bits(s: &ContactState<f64>) -> Vec<u64> {
    let mut v: Vec<u64> = [
        s.sliding_spring,
        s.rolling_spring,
        s.twisting_offaxis,
        s.previous_normal,
    ]
    .iter()
    .flat_map(|x| x.iter().map(|c| c.to_bits()).collect::<Vec<_>>())
    .collect();
    v.push(s.twisting_angle.to_bits());
    v
}

/// Runs both paths from the same state; asserts the same result (bits) or the same error, and
/// the same state afterwards. Returns whether the step succeeded.
fn same(model: &Model, c: &Case, what: &str) -> bool {
    let scene = Scene::classify(model);
    let (mut s_checked, mut s_fast) = (c.state, c.state);
    let checked = contact_step_pair(model, &c.b1, &c.b2, &c.input, &mut s_checked);
    let fast = contact_step_pair_fast(model, scene, &c.b1, &c.b2, &c.input, &mut s_fast);
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
                let scene = Scene::classify(model);
                let (mut s1, mut s2) = (c.state, c.state);
                let a = contact_step_pair(model, &c.b1, &c.b2, &c.input, &mut s1).unwrap();
                let b =
                    contact_step_pair_fast(model, scene, &c.b1, &c.b2, &c.input, &mut s2).unwrap();
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
        ("off-axis twist", |c, x| c.state.twisting_offaxis.z = x),
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
