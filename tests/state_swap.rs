//! `mirror_state` / `rsl_contact_state_swap`: a contact's state seen with its bodies swapped.
//!
//! For every preset, every rolling law in both forms (where the preset allows it), every
//! twisting law, LIGGGHTS' torsion torque and YADE's contact-point sliding, on random moving
//! pairs: starting from a stepped (non-zero) state `s`, the step of `(body 2, body 1)` from
//! `mirror(s)` must give the mirror of the step of `(body 1, body 2)` from `s` (force on the new
//! body 1 = `-force1`, torques exchanged) and the new states must again be mirrors, over 40
//! steps with the normal turning, the setup pass at the first step, and contacts at their
//! limits. Tolerance 1e-12 of the case's largest load (state: of its largest stored value):
//! the two orders evaluate the same formulas on negated operands, but not always in the same
//! order (a torque arm taken from the other body, a sum of three terms), so they differ by a
//! few ulps per step, and the bodies' motion is prescribed, so nothing amplifies that over 40
//! steps (measured worst printed with --nocapture: a few 1e-16). Any rule error (a sign, a
//! field kept that must flip) moves the loads by O(1) of themselves.
//!
//! A control checks that the comparison can fail: LAMMPS 20220106's rule (negate every stored
//! value) gives rolling and twisting loads that differ by O(1) of the loads.

mod common;
use common::Rng;
use rollslide::capi::contact::{rsl_contact_state, rsl_contact_state_swap};
use rollslide::capi::model::{rsl_model_free, rsl_model_new, RSL_PRESET_LAMMPS_2021};
use rollslide::capi::status::{RSL_ERR_INVALID_HANDLE, RSL_ERR_NULL_POINTER, RSL_OK};
use rollslide::laws::checked::contact_step_pair;
use rollslide::laws::model::*;
use rollslide::laws::step::{ContactState, StepInput, StepOutput};
use rollslide::laws::swap::mirror_state;
use rollslide::scalar::Vec3;
use rollslide::Sphere;

const TOL: f64 = 1e-12;

fn models() -> Vec<(String, Model)> {
    let mut out = Vec::new();
    let presets = [
        Preset::Objective,
        Preset::Lammps2021,
        Preset::Yade2023,
        Preset::Liggghts38,
    ];
    let rolling = [
        RollingLaw::None,
        RollingLaw::Cdt,
        RollingLaw::Viscous,
        RollingLaw::Epsd,
    ];
    let twisting = [TwistingLaw::None, TwistingLaw::Sds, TwistingLaw::Marshall];
    for preset in presets {
        for form in [RollingForm::Length, RollingForm::Angle] {
            for r in rolling {
                for t in twisting {
                    for variant in 0..3 {
                        let mut m = Model::with_preset(preset);
                        m.sliding = SlidingParams {
                            law: SlidingLaw::Linear,
                            stiffness: 2.0e5,
                            damping: 20.0,
                            friction: 0.4,
                            history: m.sliding.history,
                        };
                        m.rolling.law = r;
                        m.rolling.form = form;
                        let angle = form == RollingForm::Angle;
                        // Angle form: k_theta ~ k_r R_r^2, eta ~ mu_r R_r (R_r ~ 0.4 here).
                        m.rolling.stiffness = if angle { 2.0e4 } else { 1.0e5 };
                        m.rolling.damping = if angle { 2.0 } else { 10.0 };
                        m.rolling.friction = if angle { 0.02 } else { 0.05 };
                        m.rolling.rate_threshold = 1e-3;
                        m.twisting = TwistingParams {
                            law: t,
                            stiffness: 40.0,
                            damping: 0.4,
                            friction: 0.01,
                        };
                        let mut name = format!("{preset:?} {form:?} {r:?} {t:?}");
                        if variant == 2 {
                            // Energy tracking and a rescaled force history, with a per-step
                            // k_t (below): the state keeps the previous stiffnesses, which a
                            // swap must leave as they are (YADE's preset keeps its moment there).
                            if preset == Preset::Yade2023 {
                                continue;
                            }
                            m.track_energy = true;
                            m.sliding.history = SlidingHistory::ForceRescaled;
                            name += " energy, rescaled force history";
                        }
                        if variant == 1 {
                            match preset {
                                Preset::Liggghts38 if angle => {
                                    m.torsion_torque = true;
                                    name += " torsionTorque";
                                }
                                Preset::Yade2023 => {
                                    m.contact_point_sliding = true;
                                    name += " contact-point sliding";
                                }
                                Preset::Objective => {
                                    m.rolling.damping_mode = DampingMode::BelowLimit;
                                    m.sliding_transport = Transport::FirstOrder;
                                    m.rolling_transport = Transport::Project;
                                    name += " other transports";
                                }
                                _ => continue,
                            }
                        }
                        if m.validate().is_ok() {
                            out.push((name, m));
                        }
                    }
                }
            }
        }
    }
    out
}

fn random_pair(rng: &mut Rng) -> (Sphere<f64>, Sphere<f64>) {
    let r1 = rng.uniform(0.3, 1.5);
    let r2 = rng.uniform(0.3, 1.5);
    let n = rng.unit();
    let p1 = rng.vec(5.0);
    let overlap = rng.uniform(0.02, 0.08) * r1.min(r2);
    let b1 = Sphere {
        position: p1,
        velocity: rng.vec(1.0),
        angular_velocity: rng.vec(3.0),
        radius: r1,
    };
    let b2 = Sphere {
        position: p1 + n * (r1 + r2 - overlap),
        velocity: rng.vec(1.0),
        angular_velocity: rng.vec(3.0),
        radius: r2,
    };
    (b1, b2)
}

/// Largest difference between the mirrored step and the mirror of the step, over the loads and
/// the state, relative to the largest load of the case.
fn mirror_error(
    a: &StepOutput<f64>,
    b: &StepOutput<f64>,
    sa: &ContactState<f64>,
    sb: &ContactState<f64>,
    model: &Model,
) -> (f64, f64) {
    let la = &a.loads;
    let lb = &b.loads;
    let load_err = [
        (lb.force1 + la.force1).amax(),
        (lb.torque1 - la.torque2).amax(),
        (lb.torque2 - la.torque1).amax(),
    ]
    .into_iter()
    .fold(0.0, f64::max);
    let m = mirror_state(model, sa);
    let state_err = [
        (sb.sliding_spring - m.sliding_spring).amax(),
        (sb.rolling_spring - m.rolling_spring).amax(),
        (sb.twisting_angle - m.twisting_angle).abs(),
        (sb.model_memory - m.model_memory).amax(),
        (sb.previous_normal - m.previous_normal).amax(),
    ]
    .into_iter()
    .fold(0.0, f64::max);
    (load_err, state_err)
}

fn load_scale(a: &StepOutput<f64>) -> f64 {
    [
        a.loads.force1.amax(),
        a.loads.torque1.amax(),
        a.loads.torque2.amax(),
        a.rolling_moment.amax(),
        a.twisting_torque.amax(),
    ]
    .into_iter()
    .fold(1e-300, f64::max)
}

/// Steps both orders side by side; `mirror` maps a state of the (1, 2) order to the (2, 1)
/// order at the start. Returns the worst relative load and state differences.
fn run_case(
    model: &Model,
    rng: &mut Rng,
    mirror: impl Fn(&ContactState<f64>) -> ContactState<f64>,
) -> (f64, f64) {
    let (mut b1, mut b2) = random_pair(rng);
    let dt = 1e-3;
    let mut sa = ContactState::default();
    // Warm up (1, 2) alone so the state is non-zero, then start the (2, 1) order from its mirror.
    let f_n = |k: usize| 800.0 * (1.0 + 0.6 * (k as f64 * 0.7).sin());
    let advance = |b1: &mut Sphere<f64>, b2: &mut Sphere<f64>| {
        b1.position += b1.velocity * dt;
        b2.position += b2.velocity * dt;
    };
    // k_t rising and falling, as Hertz-Mindlin's with the contact radius.
    let k_t = |k: usize| 2.0e5 * (1.0 + 0.3 * (k as f64 * 0.4).cos());
    for k in 0..15 {
        let mut input = StepInput::new(f_n(k), dt);
        input.normal_stiffness = 1e6;
        input.sliding_stiffness = Some(k_t(k));
        input.setup = k == 0;
        contact_step_pair(model, &b1, &b2, &input, &mut sa).unwrap();
        advance(&mut b1, &mut b2);
    }
    let mut sb = mirror(&sa);
    let (mut worst_load, mut worst_state) = (0.0f64, 0.0f64);
    for k in 15..55 {
        let mut input = StepInput::new(f_n(k), dt);
        input.normal_stiffness = 1e6;
        input.sliding_stiffness = Some(k_t(k));
        input.setup = k == 15; // a second run's setup pass, as LAMMPS makes
        let a = contact_step_pair(model, &b1, &b2, &input, &mut sa).unwrap();
        let b = contact_step_pair(model, &b2, &b1, &input, &mut sb).unwrap();
        let (le, se) = mirror_error(&a, &b, &sa, &sb, model);
        let scale = load_scale(&a);
        let state_scale = [
            sa.sliding_spring.amax(),
            sa.rolling_spring.amax(),
            sa.twisting_angle.abs(),
            sa.model_memory.amax(),
            1.0,
        ]
        .into_iter()
        .fold(0.0, f64::max);
        worst_load = worst_load.max(le / scale);
        worst_state = worst_state.max(se / state_scale);
        advance(&mut b1, &mut b2);
    }
    (worst_load, worst_state)
}

#[test]
fn the_mirrored_state_steps_as_the_mirror_for_every_preset_and_law() {
    let models = models();
    assert!(models.len() >= 60, "only {} valid models", models.len());
    let mut rng = Rng::new(16);
    let mut overall = (0.0f64, 0.0f64);
    for (name, model) in &models {
        for _ in 0..6 {
            let (le, se) = run_case(model, &mut rng, |s| mirror_state(model, s));
            assert!(
                le < TOL && se < TOL,
                "{name}: the swapped order is not the mirror (loads {le:.2e}, state {se:.2e} relative)"
            );
            overall = (overall.0.max(le), overall.1.max(se));
        }
    }
    println!(
        "{} models x 6 random moving pairs x 40 steps: worst relative difference loads {:.2e}, state {:.2e}",
        models.len(),
        overall.0,
        overall.1
    );
}

#[test]
fn mirroring_twice_is_the_identity() {
    let mut rng = Rng::new(7);
    for (name, model) in models() {
        let s = ContactState {
            sliding_spring: rng.vec(1.0),
            rolling_spring: rng.vec(1.0),
            twisting_angle: rng.uniform(-1.0, 1.0),
            model_memory: rng.vec(1.0),
            previous_normal: rng.unit(),
        };
        assert_eq!(mirror_state(&model, &mirror_state(&model, &s)), s, "{name}");
    }
}

/// LAMMPS 20220106's rule when a pair's order changes: negate every stored value. Right for
/// the sliding spring, wrong for the rolling spring (length form) and the twisting angle: the
/// swapped order then feels moments of the wrong sign, O(1) of the loads.
#[test]
fn negating_the_whole_history_is_caught() {
    let mut model = Model::with_preset(Preset::Lammps2021);
    model.sliding = SlidingParams {
        law: SlidingLaw::Linear,
        stiffness: 2.0e5,
        damping: 20.0,
        friction: 0.4,
        history: model.sliding.history,
    };
    model.rolling.law = RollingLaw::Epsd;
    model.rolling.stiffness = 1.0e5;
    model.rolling.damping = 10.0;
    model.rolling.friction = 0.05;
    model.twisting = TwistingParams {
        law: TwistingLaw::Sds,
        stiffness: 40.0,
        damping: 0.4,
        friction: 0.01,
    };
    model.validate().unwrap();
    let mut rng = Rng::new(3);
    let negate_all = |s: &ContactState<f64>| ContactState {
        sliding_spring: -s.sliding_spring,
        rolling_spring: -s.rolling_spring,
        twisting_angle: -s.twisting_angle,
        model_memory: -s.model_memory,
        previous_normal: -s.previous_normal,
    };
    let (le, _) = run_case(&model, &mut rng, negate_all);
    assert!(
        le > 1e-2,
        "negating the rolling spring went unnoticed ({le:.2e})"
    );
}

#[test]
fn rsl_contact_state_swap_is_mirror_state_through_the_c_abi() {
    let mut p = std::ptr::null_mut();
    // SAFETY: live locals; the model is freed once at the end; NULL arguments are the cases
    // under test and are documented as refused.
    unsafe {
        assert_eq!(rsl_model_new(RSL_PRESET_LAMMPS_2021, &mut p), RSL_OK);
        let mut s = rsl_contact_state {
            sliding_spring: Vec3::new(1.0, 2.0, 3.0).into(),
            rolling_spring: Vec3::new(-4.0, 5.0, 6.0).into(),
            twisting_angle: 0.25,
            model_memory: Vec3::new(0.0, 0.0, 0.0).into(),
            previous_normal: Vec3::new(0.0, 0.6, 0.8).into(),
            slip_flags: 3,
            reserved: 0,
        };
        let before = s;
        assert_eq!(rsl_contact_state_swap(p, &mut s), RSL_OK);
        let want = mirror_state(
            &Model::with_preset(Preset::Lammps2021),
            &ContactState::from(&before),
        );
        assert_eq!(ContactState::from(&s), want);
        assert_eq!(s.slip_flags, 3);
        // LAMMPS_2021 is the length form: the rolling spring and twist are kept.
        assert_eq!(s.rolling_spring, before.rolling_spring);
        assert_eq!(s.twisting_angle, before.twisting_angle);
        assert_eq!(
            rsl_contact_state_swap(std::ptr::null(), &mut s),
            RSL_ERR_NULL_POINTER
        );
        assert_eq!(
            rsl_contact_state_swap(p, std::ptr::null_mut()),
            RSL_ERR_NULL_POINTER
        );
        assert_eq!(
            ContactState::from(&s),
            want,
            "state written on a refused call"
        );
        rsl_model_free(p);
        let garbage = [0u64; 64];
        assert_eq!(
            rsl_contact_state_swap(garbage.as_ptr().cast(), &mut s),
            RSL_ERR_INVALID_HANDLE
        );
    }
}
