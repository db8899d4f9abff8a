//! The contact laws against closed forms and invariants (models.md sections 1-5): elastic
//! ramps and clip points, the rigid-rotation transport test of every scheme, angular momentum
//! of the applied loads, the per-step energy balance, length versus angle parameterisations,
//! cdt, viscous and Marshall coefficients, and the time-step helpers.

// Tests configure a model one law at a time, the way a host does through the C setters.
#![allow(clippy::field_reassign_with_default)]

mod common;
use common::*;
use nalgebra::{Rotation3, Unit, Vector3};
use rollslide::laws::checked::{contact_step_pair, contact_step_wall};
use rollslide::laws::model::*;
use rollslide::laws::spring::SpringEnergy;
use rollslide::laws::stability::{coupled_critical_time_step, rotational_critical_time_step};
use rollslide::laws::step::{ContactState, StepInput, StepOutput};
use rollslide::laws::transport::{transport, Frame, RescaleWhen};
use rollslide::{decompose_pair, GeometryOptions, Parts, RollingRadiusRule, Sphere, Wall};

const R1: f64 = 0.7;
const R2: f64 = 2.3;

fn sphere(p: Vector3<f64>, vel: Vector3<f64>, w: Vector3<f64>, r: f64) -> Sphere<f64> {
    Sphere {
        position: p,
        velocity: vel,
        angular_velocity: w,
        radius: r,
    }
}

fn epsd(k: f64, gamma: f64, mu: f64) -> RollingParams {
    RollingParams {
        law: RollingLaw::Epsd,
        stiffness: k,
        damping: gamma,
        friction: mu,
        ..Default::default()
    }
}

/// Gear rolling at fixed centres (v_s = 0): the rolling spring grows by v_r dt per step, the
/// rolling force is -k_r xi_r until it reaches mu_r f_n, then stays there (models.md 2, 3).
#[test]
fn gear_rolling_elastic_ramp_then_clip_at_mu_r_f_n() {
    let (k_r, mu_r, f_n, dt) = (50.0, 0.1, 10.0, 1e-3);
    let mut m = Model::default();
    m.rolling = epsd(k_r, 0.0, mu_r);
    m.sliding = SlidingParams {
        law: SlidingLaw::Linear,
        stiffness: 1e3,
        damping: 0.0,
        friction: 0.5,
        history: m.sliding.history,
    };
    let w1 = v(0.0, 0.0, 2.0);
    let b1 = sphere(v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), w1, R1);
    let b2 = sphere(v(3.0, 0.0, 0.0), v(0.0, 0.0, 0.0), -w1 * (R1 / R2), R2);
    let r_r = R1 * R2 / 3.0;
    let v_r = v(0.0, 1.4, 0.0); // kinematics.md case 3
    let n = v(1.0, 0.0, 0.0);
    let mut state = ContactState::default();
    // Elastic until k_r |v_r| t = mu_r f_n: t* = 1/70, i.e. step 14.28..., so steps 1..14 elastic.
    for step in 1..=40 {
        let out = contact_step_pair(&m, &b1, &b2, &StepInput::new(f_n, dt), &mut state).unwrap();
        let xi = v_r * (step as f64 * dt);
        let trial = -xi * k_r;
        let expected = if trial.norm() > mu_r * f_n {
            trial.normalize() * (mu_r * f_n)
        } else {
            trial
        };
        let moment = n.cross(&expected) * r_r;
        // Closed form of the discrete scheme; rounding of step*dt accumulates ~step ulps.
        assert_vec_close(&out.rolling_moment, &moment, 1e-13, 1e-12, "rolling moment");
        assert_eq!(
            out.slipped[1],
            step >= 15,
            "clip point at step 15 (t* = 14.29 dt)"
        );
        // v_s is zero to rounding (~eps |w| R = 3e-16) and the spring integrates it: k_t t eps.
        assert_vec_close(
            &out.sliding_force,
            &v(0.0, 0.0, 0.0),
            1e-12,
            0.0,
            "no sliding in a gear",
        );
        // Body 2 gets the opposite couple: torque2 = -rolling moment (no sliding force).
        assert_vec_close(
            &out.loads.torque2,
            &(-moment),
            1e-13,
            1e-12,
            "reaction couple",
        );
    }
    // After the clip the spring is reset so that -k xi = F (no dashpot).
    let xi = state.rolling_spring;
    assert_close(
        xi.norm() * k_r,
        mu_r * f_n,
        1e-12,
        0.0,
        "spring at the limit",
    );
}

/// Pure twist (w1 = W n, w2 = -W n): theta grows by 2 W dt per step, M = -k theta, clipped at
/// mu_tw f_n with the sign of the trial moment; reversing the twist unloads elastically.
#[test]
fn pure_twist_ramp_clip_and_reverse() {
    let (k, mu, f_n, dt, w) = (20.0, 0.01, 5.0, 1e-3, 1.5);
    let mut m = Model::default();
    m.twisting = TwistingParams {
        law: TwistingLaw::Sds,
        stiffness: k,
        damping: 0.0,
        friction: mu,
    };
    let n = v(1.0, 0.0, 0.0);
    let mut b1 = sphere(v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), n * w, R1);
    let mut b2 = sphere(v(3.0, 0.0, 0.0), v(0.0, 0.0, 0.0), -n * w, R2);
    let mut state = ContactState::default();
    let limit = mu * f_n; // 0.05: reached when 20 * 3e-3 * step > 0.05, i.e. step 1 (0.06)? no:
    let mut theta = 0.0;
    for step in 1..=20 {
        let out = contact_step_pair(&m, &b1, &b2, &StepInput::new(f_n, dt), &mut state).unwrap();
        theta += 2.0 * w * dt;
        let trial = -k * theta;
        let expected = if trial.abs() > limit { -limit } else { trial };
        if trial.abs() > limit {
            theta = limit / k;
        }
        assert_close(
            out.twisting_torque.x,
            expected,
            1e-14,
            1e-12,
            &format!("twist moment step {step}"),
        );
        assert_close(
            out.twisting_torque.y.abs() + out.twisting_torque.z.abs(),
            0.0,
            1e-15,
            0.0,
            "along n",
        );
    }
    // Reverse: unloads elastically from +limit by k * 2 w dt per step.
    b1.angular_velocity = -n * w;
    b2.angular_velocity = n * w;
    let out = contact_step_pair(&m, &b1, &b2, &StepInput::new(f_n, dt), &mut state).unwrap();
    assert_close(
        out.twisting_torque.x,
        -limit + k * 2.0 * w * dt,
        1e-14,
        1e-12,
        "elastic unloading",
    );
    assert!(!out.slipped[2]);
}

/// Pure sliding at fixed centres (v_s = (0, 3, 0)): the friction force saturates at mu f_n and
/// the slider dissipates the friction work mu f_n |v_s| dt per step at steady sliding, with no
/// rolling.
#[test]
fn steady_sliding_dissipates_friction_work() {
    let (k_t, mu, f_n, dt) = (1e4, 0.4, 2.0, 1e-4);
    let mut m = Model::default();
    m.sliding = SlidingParams {
        law: SlidingLaw::Linear,
        stiffness: k_t,
        damping: 0.0,
        friction: mu,
        history: m.sliding.history,
    };
    m.rolling = epsd(100.0, 0.0, 0.1);
    m.track_energy = true;
    let w = v(0.0, 0.0, 1.0);
    let b1 = sphere(v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), w, R1);
    let b2 = sphere(v(3.0, 0.0, 0.0), v(0.0, 0.0, 0.0), w, R2);
    let mut state = ContactState::default();
    let vs = 3.0;
    let mut out = None;
    for _ in 0..200 {
        out = Some(contact_step_pair(&m, &b1, &b2, &StepInput::new(f_n, dt), &mut state).unwrap());
    }
    let out = out.unwrap();
    assert!(out.slipped[0]);
    assert_vec_close(
        &out.sliding_force,
        &v(0.0, -mu * f_n, 0.0),
        1e-12,
        0.0,
        "kinetic friction",
    );
    assert_vec_close(
        &out.rolling_moment,
        &v(0.0, 0.0, 0.0),
        0.0,
        0.0,
        "no rolling in pure sliding",
    );
    let expected = mu * f_n * vs * dt;
    assert_close(
        out.energy.sliding.slider,
        expected,
        1e-15,
        1e-12,
        "slider dissipation",
    );
}

fn rigid_rotation_history_error(transport: Transport) -> (f64, f64) {
    // models.md section 1: R1 = 1, R2 = 0.5, delta = 0.01, W = (1, 0, 1)/sqrt(2), alpha = 1e-3,
    // 1571 steps (a quarter turn), history at 45 deg to the tumbling axis.
    let d = 1.49;
    let n0 = v(1.0, 0.0, 0.0);
    let big_w = v(1.0, 0.0, 1.0) / 2f64.sqrt();
    let dt = 1e-3;
    let xi0 = v(0.0, 1.0, 1.0) / 2f64.sqrt() * 1e-3; // tumbling axis z; 45 deg to it
    let mut m = Model::default();
    m.sliding = SlidingParams {
        law: SlidingLaw::Linear,
        stiffness: 1e3,
        damping: 0.0,
        friction: f64::INFINITY,
        history: m.sliding.history,
    };
    m.rolling = epsd(1e2, 0.0, f64::INFINITY);
    m.sliding_transport = transport;
    m.rolling_transport = transport;
    let mut state = ContactState {
        sliding_spring: xi0,
        rolling_spring: xi0,
        previous_normal: n0,
        ..Default::default()
    };
    let centre = n0 * (d / 2.0);
    let (p1, p2) = (v(0.0, 0.0, 0.0), n0 * d);
    let mut worst_rate = 0.0f64;
    for step in 1..=1571 {
        let rot = Rotation3::from_axis_angle(
            &Unit::new_normalize(big_w),
            big_w.norm() * dt * step as f64,
        );
        let (q1, q2) = (centre + rot * (p1 - centre), centre + rot * (p2 - centre));
        let b1 = sphere(q1, big_w.cross(&(q1 - centre)), big_w, 1.0);
        let b2 = sphere(q2, big_w.cross(&(q2 - centre)), big_w, 0.5);
        contact_step_pair(&m, &b1, &b2, &StepInput::new(1.0, dt), &mut state).unwrap();
        let dd = decompose_pair(&b1, &b2, GeometryOptions::default(), Parts::ALL).unwrap();
        let rate = dd
            .sliding_velocity
            .norm()
            .max(dd.rolling_velocity.norm())
            .max(dd.twisting_rate.abs());
        worst_rate = worst_rate.max(rate / big_w.norm());
    }
    let rot = Rotation3::from_axis_angle(&Unit::new_normalize(big_w), big_w.norm() * dt * 1571.0);
    let exact = rot * xi0;
    let err_s = (state.sliding_spring - exact).norm() / xi0.norm();
    let err_r = (state.rolling_spring - exact).norm() / xi0.norm();
    assert_close(err_s, err_r, 1e-12, 0.0, "both springs transported alike");
    (err_s, worst_rate)
}

#[test]
fn rigid_rotation_transport_exact_scheme() {
    let (err, rate) = rigid_rotation_history_error(Transport::Exact);
    println!("exact: history error {err:.2e}, worst per-step rate {rate:.2e}");
    // models.md: < 1e-6 required; 4.6e-8 was measured by a reference implementation, which is
    // the O(alpha^2) error of splitting the rotation into swing (n_old -> n_new) and twist
    // (dt w_rbs about n_new); the spin rotation itself is accurate to O(phi^5). Measured 4.6e-8.
    assert!(err < 1e-7, "exact transport error {err:.2e}");
    assert!(rate < 1e-12, "rigid rotation produced rates {rate:.2e}");
}

#[test]
fn rigid_rotation_transport_approximate_schemes_show_their_known_errors() {
    let (project_rescale, _) = rigid_rotation_history_error(Transport::ProjectRescale);
    let (first_order, _) = rigid_rotation_history_error(Transport::FirstOrder);
    let (project, _) = rigid_rotation_history_error(Transport::Project);
    let (none, _) = rigid_rotation_history_error(Transport::None);
    println!("project_rescale {project_rescale:.2e}, first_order {first_order:.2e}, project {project:.2e}, none {none:.2e}");
    // project_rescale ignores the spin (W.n = 1/sqrt 2 rad/time over pi/2 time: a quarter of
    // that angle, O(1)) and lags the tumbling by O(alpha) per step: an O(1) error here.
    assert!(project_rescale > 0.1, "{project_rescale}");
    // first_order grows the length by ~alpha^2/2 per step: 1571 * 1e-6 / 2 = 7.9e-4 (the
    // direction is right to first order).
    assert!(first_order > 2e-4 && first_order < 3e-3, "{first_order}");
    // project shrinks and lags, none does not move at all: O(1).
    assert!(project > 0.1 && none > 0.5, "{project} {none}");
}

fn random_model(rng: &mut Rng, preset: Preset) -> Model {
    let mut m = Model::with_preset(preset);
    m.sliding = SlidingParams {
        law: SlidingLaw::Linear,
        stiffness: rng.uniform(1e2, 1e4),
        damping: rng.uniform(0.0, 5.0),
        friction: rng.uniform(0.1, 0.8),
        history: m.sliding.history,
    };
    m.rolling = RollingParams {
        law: [RollingLaw::Cdt, RollingLaw::Viscous, RollingLaw::Epsd]
            [(rng.next_u64() % 3) as usize],
        stiffness: rng.uniform(1.0, 1e3),
        damping: rng.uniform(0.0, 2.0),
        friction: rng.uniform(0.01, 0.3),
        damping_mode: if rng.next_u64().is_multiple_of(2) {
            DampingMode::Always
        } else {
            DampingMode::BelowLimit
        },
        ..m.rolling
    };
    m.twisting = TwistingParams {
        law: if rng.next_u64().is_multiple_of(2) {
            TwistingLaw::Sds
        } else {
            TwistingLaw::Marshall
        },
        stiffness: rng.uniform(1.0, 100.0),
        damping: rng.uniform(0.0, 1.0),
        friction: rng.uniform(0.001, 0.05),
    };
    m.track_energy = true;
    m
}

fn random_pair(rng: &mut Rng) -> (Sphere<f64>, Sphere<f64>) {
    let (r1, r2) = (rng.uniform(0.2, 2.0), rng.uniform(0.2, 2.0));
    let n = rng.unit();
    let p1 = rng.vec(5.0);
    let overlap = rng.uniform(1e-4, 0.05) * r1.min(r2);
    (
        sphere(p1, rng.vec(1.0), rng.vec(3.0), r1),
        sphere(p1 + n * (r1 + r2 - overlap), rng.vec(1.0), rng.vec(3.0), r2),
    )
}

/// The loads conserve linear and angular momentum: F1 + F2 = 0 and the total moment about any
/// point vanishes, for every preset and law, at every step of a random history.
#[test]
fn applied_loads_conserve_angular_momentum() {
    let mut rng = Rng::new(0x1a55);
    for preset in [
        Preset::Objective,
        Preset::Lammps2021,
        Preset::Yade2023,
        Preset::Liggghts38,
    ] {
        for _ in 0..40 {
            let m = random_model(&mut rng, preset);
            let (mut b1, mut b2) = random_pair(&mut rng);
            let mut state = ContactState::default();
            let mut input = StepInput::new(rng.uniform(1.0, 100.0), 1e-3);
            input.normal_stiffness = 1e4;
            for _ in 0..20 {
                let out = contact_step_pair(&m, &b1, &b2, &input, &mut state).unwrap();
                let x = rng.vec(10.0);
                let l = &out.loads;
                let total = (b1.position - x).cross(&l.force1)
                    + l.torque1
                    + (b2.position - x).cross(&l.force2)
                    + l.torque2;
                let scale =
                    (l.force1.norm() * 20.0 + l.torque1.norm() + l.torque2.norm()).max(1e-300);
                assert!(
                    total.norm() <= 1e-13 * scale,
                    "{preset:?}: angular momentum {:e} of {scale:e}",
                    total.norm()
                );
                assert_eq!(l.force1 + l.force2, Vector3::zeros());
                b1.angular_velocity += rng.vec(0.5);
                b2.velocity += rng.vec(0.2);
            }
        }
    }
}

/// Per step and per spring, the work the relative motion did on the contact (computed here from
/// the states, rates and loads, independent of the library's energy code: while the spring
/// sticks, the midpoint rule on the spring plus the dashpot's; while it slips, the work of the
/// applied, clipped load) equals stored + dissipated: W = dE + dashpot + slider, to rounding
/// (exact transport).
#[test]
fn energy_balance_per_step_for_each_spring() {
    let mut rng = Rng::new(0xe4e7);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        let mut m = random_model(&mut rng, Preset::Objective);
        m.rolling.law = RollingLaw::Epsd;
        m.twisting.law = TwistingLaw::Sds;
        let (b1, mut b2) = random_pair(&mut rng);
        let mut state = ContactState::default();
        let input = StepInput::new(rng.uniform(1.0, 50.0), 1e-3);
        for _ in 0..30 {
            let before = state;
            let out: StepOutput<f64> = contact_step_pair(&m, &b1, &b2, &input, &mut state).unwrap();
            let d = decompose_pair(&b1, &b2, m.geometry, Parts::ALL).unwrap();
            let dt = input.dt;
            // Sliding: transported spring -> (+ v dt) trial; midpoint spring work + dashpot work.
            let e = &out.energy;
            // The objective preset's dashpot acts at every step (clip rule "total").
            let check = |old: f64,
                         new_e: &SpringEnergy<f64>,
                         work_spring: f64,
                         dashpot: f64,
                         what: &str| {
                let lhs = work_spring + dashpot;
                let rhs = (new_e.elastic - old) + new_e.dashpot + new_e.slider;
                let scale =
                    (old.abs() + new_e.elastic.abs() + work_spring.abs() + dashpot).max(1e-300);
                assert!(
                    (lhs - rhs).abs() <= 1e-12 * scale,
                    "{what}: work {lhs:e} vs {rhs:e}"
                );
                (lhs - rhs).abs() / scale
            };
            // The spring carried into this step's frame (exact transport; tested on its own in
            // the rigid-rotation tests), then the midpoint work k (xi + v dt/2) . v dt.
            let n = d.geometry.normal;
            let old_n = if before.previous_normal == Vector3::zeros() {
                n
            } else {
                before.previous_normal
            };
            let frame = Frame {
                old_normal: old_n,
                new_normal: n,
                spin_angle: (b1.angular_velocity + b2.angular_velocity).dot(&n) * 0.5 * dt,
                half_spin_old: 0.0,
            };
            let xi_old = transport(
                Transport::Exact,
                &before.sliding_spring,
                &frame,
                RescaleWhen::NormalPart,
            );
            let k_t = m.sliding.stiffness;
            let v_s = d.sliding_velocity;
            let e_old = 0.5 * k_t * xi_old.norm_squared();
            let dashpot = m.sliding.damping * v_s.norm_squared() * dt;
            // Sticking: the midpoint work of the spring on the increment. Slipping: the work
            // of the applied (clipped) force, dashpot included.
            let work = if out.slipped[0] {
                -out.sliding_force.dot(&v_s) * dt - dashpot
            } else {
                k_t * (xi_old + v_s * (0.5 * dt)).dot(&(v_s * dt))
            };
            worst = worst.max(check(e_old, &e.sliding, work, dashpot, "sliding"));
            let k_tw = m.twisting.stiffness;
            let th = before.twisting_angle;
            let w = d.twisting_rate;
            let e_old_tw = 0.5 * k_tw * th * th;
            let tw_dashpot = m.twisting.damping * w * w * dt;
            let tw_work = if out.slipped[2] {
                -out.twisting_torque.dot(&n) * w * dt - tw_dashpot
            } else {
                k_tw * (th + 0.5 * w * dt) * w * dt
            };
            worst = worst.max(check(
                e_old_tw,
                &e.twisting,
                tw_work,
                tw_dashpot,
                "twisting",
            ));
            assert!(
                e.transport.abs() <= 1e-12 * (e_old + e.sliding.elastic + 1e-300) + 1e-300
                    || e.transport.abs() < 1e-14,
                "exact transport changed the energy by {:e}",
                e.transport
            );
            b2.angular_velocity += rng.vec(0.3);
        }
    }
    println!("energy balance worst relative residual {worst:.2e}");
}

/// Length and angle parameterisations of the same rolling law give the same moments when
/// k_theta = R_r^2 k_r, c_theta = R_r^2 gamma_r and eta = mu_r R_r (R_r constant: R_eff rule).
#[test]
fn length_and_angle_parameterisations_are_equivalent() {
    let mut rng = Rng::new(0xa17e);
    for _ in 0..50 {
        let (mut b1, mut b2) = random_pair(&mut rng);
        let r_r = b1.radius * b2.radius / (b1.radius + b2.radius);
        let (k_r, gamma_r, mu_r) = (
            rng.uniform(10.0, 1e3),
            rng.uniform(0.0, 2.0),
            rng.uniform(0.01, 0.2),
        );
        let mut length = Model::default();
        length.geometry.rolling_radius = RollingRadiusRule::Effective;
        length.rolling = epsd(k_r, gamma_r, mu_r);
        let mut angle = length;
        angle.rolling = RollingParams {
            form: RollingForm::Angle,
            ..epsd(k_r * r_r * r_r, gamma_r * r_r * r_r, mu_r * r_r)
        };
        let (mut s_l, mut s_a) = (ContactState::default(), ContactState::default());
        let input = StepInput::new(rng.uniform(1.0, 20.0), 1e-3);
        for _ in 0..50 {
            let a = contact_step_pair(&length, &b1, &b2, &input, &mut s_l).unwrap();
            let b = contact_step_pair(&angle, &b1, &b2, &input, &mut s_a).unwrap();
            let scale = mu_r * r_r * input.normal_force;
            assert_vec_close(
                &a.rolling_moment,
                &b.rolling_moment,
                1e-12 * scale,
                0.0,
                "length vs angle moment",
            );
            assert_eq!(a.slipped[1], b.slipped[1]);
            b1.angular_velocity += rng.vec(1.0);
            b2.velocity += rng.vec(0.1);
        }
    }
}

#[test]
fn cdt_viscous_and_marshall_closed_forms() {
    let w1 = v(0.0, 0.0, 2.0);
    let b1 = sphere(v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), w1, R1);
    let b2 = sphere(
        v(3.0 - 0.01, 0.0, 0.0),
        v(0.0, 0.0, 0.0),
        -w1 * (R1 / R2),
        R2,
    );
    let d = decompose_pair(&b1, &b2, GeometryOptions::default(), Parts::ALL).unwrap();
    let r_r = d.geometry.rolling_radius;
    let f_n = 7.0;
    // cdt: M1 = -mu_r R_r f_n (w1 - w2)_t / |(w1 - w2)_t|.
    let mut m = Model::default();
    m.rolling = RollingParams {
        law: RollingLaw::Cdt,
        friction: 0.2,
        rate_threshold: 1e-6,
        ..Default::default()
    };
    let out = contact_step_pair(
        &m,
        &b1,
        &b2,
        &StepInput::new(f_n, 1e-3),
        &mut ContactState::default(),
    )
    .unwrap();
    let dw = (b1.angular_velocity - b2.angular_velocity).normalize();
    assert_vec_close(
        &out.rolling_moment,
        &(-dw * (0.2 * r_r * f_n)),
        1e-14,
        1e-13,
        "cdt moment",
    );
    // Below the rate threshold cdt is off.
    m.rolling.rate_threshold = 10.0;
    let out = contact_step_pair(
        &m,
        &b1,
        &b2,
        &StepInput::new(f_n, 1e-3),
        &mut ContactState::default(),
    )
    .unwrap();
    assert_eq!(out.rolling_moment, Vector3::zeros());
    // viscous: F_r = -gamma v_r (below the limit), moment R_r n x F_r.
    m.rolling = RollingParams {
        law: RollingLaw::Viscous,
        damping: 0.3,
        friction: 10.0,
        ..Default::default()
    };
    let out = contact_step_pair(
        &m,
        &b1,
        &b2,
        &StepInput::new(f_n, 1e-3),
        &mut ContactState::default(),
    )
    .unwrap();
    let expected = d.geometry.normal.cross(&(-d.rolling_velocity * 0.3)) * r_r;
    assert_vec_close(
        &out.rolling_moment,
        &expected,
        1e-14,
        1e-13,
        "viscous moment",
    );
    assert!(
        out.rolling_moment
            .dot(&(b1.angular_velocity - b2.angular_velocity))
            < 0.0,
        "resists"
    );
    // Marshall: k = k_t a^2/2, gamma = gamma_t a^2/2, mu = 2/3 a mu_s, a = sqrt(delta R_eff).
    let mut m = Model::default();
    m.sliding = SlidingParams {
        law: SlidingLaw::Linear,
        stiffness: 400.0,
        damping: 2.0,
        friction: 0.5,
        history: m.sliding.history,
    };
    m.twisting.law = TwistingLaw::Marshall;
    let n = d.geometry.normal;
    let t1 = sphere(b1.position, Vector3::zeros(), n * 0.5, R1);
    let t2 = sphere(b2.position, Vector3::zeros(), -n * 0.5, R2);
    let out = contact_step_pair(
        &m,
        &t1,
        &t2,
        &StepInput::new(f_n, 1e-3),
        &mut ContactState::default(),
    )
    .unwrap();
    let a2 = 0.01 * R1 * R2 / (R1 + R2);
    let (k, g) = (400.0 * a2 / 2.0, 2.0 * a2 / 2.0);
    let expected = -k * 1.0 * 1e-3 - g * 1.0;
    let limit = 2.0 / 3.0 * a2.sqrt() * 0.5 * f_n;
    let expected = if expected.abs() > limit {
        -limit
    } else {
        expected
    };
    assert_close(
        out.twisting_torque.dot(&n),
        expected,
        1e-15,
        1e-12,
        "Marshall twist",
    );
}

#[test]
fn wall_contact_rolls_like_a_sphere_pair_limit() {
    // A ball rolling on a wall with epsd: the spring grows by the rolled distance.
    let mut m = Model::default();
    m.rolling = epsd(10.0, 0.0, 1.0);
    let vel = v(1.0, 0.0, 0.0);
    let ball = sphere(
        v(0.0, 0.0, R1 - 1e-3),
        vel,
        vel.cross(&v(0.0, 0.0, -1.0)) / R1,
        R1,
    );
    let wall = Wall {
        point: Vector3::zeros(),
        normal: v(0.0, 0.0, 1.0),
        velocity: Vector3::zeros(),
        angular_velocity: Vector3::zeros(),
    };
    let mut state = ContactState::default();
    for _ in 0..10 {
        contact_step_wall(&m, &ball, &wall, &StepInput::new(1.0, 1e-3), &mut state).unwrap();
    }
    // v_r = R_r (w1 x n) with R_r = l1 = R1 - delta/2: rolled distance (l1/R1) V t, direction -V.
    let l1 = R1 - 0.5e-3;
    assert_vec_close(
        &state.rolling_spring,
        &(-vel * (l1 / R1) * 1e-2),
        1e-15,
        1e-12,
        "rolled distance",
    );
}

#[test]
fn time_step_helpers_match_their_formulas() {
    let dt = rotational_critical_time_step(4.0, 1.0, 1.0, 0.0).unwrap();
    assert_close(dt, 2.0 / 8f64.sqrt(), 0.0, 1e-15, "undamped: 2/w0");
    let z = 0.3;
    let dt = rotational_critical_time_step(4.0, 1.0, f64::INFINITY, z).unwrap();
    assert_close(
        dt,
        (2.0 / 2.0) * ((1.0 + z * z).sqrt() - z),
        0.0,
        1e-15,
        "damped, wall",
    );
    let dt = coupled_critical_time_step(100.0, 4.0, 1.0, 2.0, 0.5, 0.25, 0.3, 0.2).unwrap();
    let s: f64 = 100.0 * (1.0 + 0.5 + 0.09 / 0.5 + 0.04 / 0.25) + 4.0 * (2.0 + 4.0);
    assert_close(dt, 2.0 / s.sqrt(), 0.0, 1e-15, "coupled");
    assert!(rotational_critical_time_step(-1.0, 1.0, 1.0, 0.0).is_err());
    assert!(coupled_critical_time_step(0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0).is_err());
}

#[test]
fn bad_step_input_is_refused_and_state_untouched() {
    let mut m = Model::default();
    m.rolling = epsd(10.0, 0.0, 0.1);
    let (b1, b2) = (
        sphere(v(0.0, 0.0, 0.0), Vector3::zeros(), v(0.0, 0.0, 1.0), R1),
        sphere(v(2.9, 0.0, 0.0), Vector3::zeros(), Vector3::zeros(), R2),
    );
    let mut state = ContactState::default();
    contact_step_pair(&m, &b1, &b2, &StepInput::new(1.0, 1e-3), &mut state).unwrap();
    let kept = state;
    for (input, want) in [
        (StepInput::new(1.0, 0.0), rollslide::Error::InvalidTimeStep),
        (
            StepInput::new(f64::NAN, 1e-3),
            rollslide::Error::NonFinite("normal force"),
        ),
    ] {
        assert_eq!(
            contact_step_pair(&m, &b1, &b2, &input, &mut state).unwrap_err(),
            want
        );
        assert_eq!(state, kept);
    }
    // A model needing k_n refuses an input without it.
    m.rolling.stiffness_rule = RollingStiffness::Epsd;
    assert!(matches!(
        contact_step_pair(&m, &b1, &b2, &StepInput::new(1.0, 1e-3), &mut state),
        Err(rollslide::Error::InvalidArgument(_))
    ));
    assert_eq!(state, kept);
}

/// Corner cases of the spring-dashpot-slider (models.md section 2, step 5): an empty spring at
/// rest gives no load and no slip; a zero limit (f_n = 0) gives a zero load whatever the
/// motion; a zero stiffness never divides by zero (the spring keeps its trial value).
#[test]
fn spring_corner_cases_are_defined() {
    use rollslide::laws::spring::{vector_spring, ClipRule, SpringCoefficients, Storage};
    let zero = Vector3::<f64>::zeros();
    let c = SpringCoefficients {
        stiffness: 10.0,
        damping: 1.0,
        limit: 2.0,
    };
    for rule in [ClipRule::Total, ClipRule::Lammps, ClipRule::SpringOnly] {
        for storage in [Storage::Displacement, Storage::Load] {
            let r = vector_spring(&zero, &zero, 1e-3, &c, rule, storage, true, true);
            assert_eq!(
                (r.load, r.spring, r.slipped),
                (zero, zero, false),
                "{rule:?} {storage:?} at rest"
            );
            assert_eq!(
                (r.energy.elastic, r.energy.dashpot, r.energy.slider),
                (0.0, 0.0, 0.0)
            );
            // Zero limit: the load is zero (LIGGGHTS' rule: the spring part is zero).
            let no_limit = SpringCoefficients { limit: 0.0, ..c };
            let r = vector_spring(
                &v(1e-3, 0.0, 0.0),
                &v(0.0, 2.0, 0.0),
                1e-3,
                &no_limit,
                rule,
                storage,
                true,
                true,
            );
            assert!(r.slipped);
            if rule != ClipRule::SpringOnly {
                assert_eq!(r.load, zero, "{rule:?}: zero limit, zero load");
            }
            assert!(r.spring.iter().all(|x| x.is_finite()));
            // Zero stiffness: the dashpot alone, clipped; no division by zero.
            let soft = SpringCoefficients {
                stiffness: 0.0,
                ..c
            };
            let r = vector_spring(
                &zero,
                &v(0.0, 5.0, 0.0),
                1e-3,
                &soft,
                rule,
                storage,
                true,
                true,
            );
            assert!(r.load.iter().chain(r.spring.iter()).all(|x| x.is_finite()));
            assert!(r.load.norm() <= 2.0 + 1e-15 || rule == ClipRule::SpringOnly);
        }
    }
}

/// A fixed body 2 (+inf mass and inertia) gives the damping-ratio EPSD dashpot of a wall:
/// `I_r = I1 + m1 R1^2` (the inverse of body 2's reduced inertia is 0).
#[test]
fn fixed_body_two_has_the_reduced_inertia_of_a_wall() {
    let mut m = Model::default();
    m.rolling = RollingParams {
        damping_rule: RollingDamping::Ratio,
        ..epsd(50.0, 0.3, 10.0)
    };
    let w1 = v(0.0, 0.0, 2.0);
    let b1 = sphere(v(0.0, 0.0, 0.0), Vector3::zeros(), w1, R1);
    let b2 = sphere(
        v(3.0 - 1e-3, 0.0, 0.0),
        Vector3::zeros(),
        Vector3::zeros(),
        R2,
    );
    let mut input = StepInput::new(1.0, 1e-3);
    input.mass1 = 2.0;
    input.inertia1 = 0.4 * 2.0 * R1 * R1;
    input.mass2 = f64::INFINITY;
    input.inertia2 = f64::INFINITY;
    let out = contact_step_pair(&m, &b1, &b2, &input, &mut ContactState::default()).unwrap();
    let d = decompose_pair(&b1, &b2, GeometryOptions::default(), Parts::ALL).unwrap();
    let r_r = d.geometry.rolling_radius;
    let i_r = input.inertia1 + input.mass1 * R1 * R1;
    let c_theta = 0.3 * 2.0 * (i_r * 50.0 * r_r * r_r).sqrt();
    let (k_r, gamma_r) = (50.0, c_theta / (r_r * r_r));
    let load = -d.rolling_velocity * (k_r * 1e-3) - d.rolling_velocity * gamma_r;
    let expected = d.geometry.normal.cross(&load) * r_r;
    assert_vec_close(
        &out.rolling_moment,
        &expected,
        1e-14,
        1e-12,
        "fixed body 2 dashpot",
    );
}
