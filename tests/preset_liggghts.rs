//! The LIGGGHTS_3_8 preset against LIGGGHTS-PUBLIC 3.8.0 itself: every step of every case of
//! `tests/reference/liggghts/liggghts_reference.csv` (made by
//! `tests/reference/liggghts/regenerate.sh` with Debian's `liggghts`).
//!
//! The host (this test) computes what LIGGGHTS' Hertz normal model gives each contact: `k_n`,
//! `k_t`, `gamma_t` (from Young's modulus, Poisson's ratio, restitution, `R_eff`, `delta`),
//! passes LIGGGHTS' normal force `f1 . n_L` (elastic + damping), and the rolling limit length
//! `eta = mu_r R_eff` (angle form). Tolerance as in `preset_lammps.rs`: a few ulps of the
//! case's load scale; 1e-11 fails on any rule difference.

mod common;
use common::reference::*;
use rollslide::laws::checked::contact_step_pair;
use rollslide::laws::model::*;
use rollslide::laws::step::{ContactState, StepInput};
use rollslide::Sphere;

#[test]
fn liggghts_3_8_preset_reproduces_liggghts_step_by_step() {
    let dir = root().join("tests/reference/liggghts");
    let cases = load_cases(&dir.join("liggghts_reference.csv"));
    assert!(
        cases.len() >= 22,
        "expected the LIGGGHTS cases, found {}",
        cases.len()
    );
    for (name, rows) in &cases {
        let params = load_json(&dir.join(format!("params/{name}.json")));
        let mat = &params["materials"];
        let f = |k: &str| mat[k].as_f64().unwrap();
        let (young, poisson) = (f("youngsModulus"), f("poissonsRatio"));
        let y_eff = young / (2.0 * (1.0 - poisson * poisson));
        let g_eff = young / (4.0 * (2.0 - poisson) * (1.0 + poisson));
        let ln_e = f("coefficientRestitution").ln();
        let beta = ln_e / (ln_e * ln_e + std::f64::consts::PI.powi(2)).sqrt();
        let mu_r = f("coefficientRollingFriction");
        let law = params["rolling_friction"].as_str().unwrap();

        let mut model = Model::with_preset(Preset::Liggghts38);
        model.sliding = SlidingParams {
            law: SlidingLaw::Linear,
            stiffness: 0.0,
            damping: 0.0,
            friction: f("coefficientFriction"),
        };
        model.rolling.law = if law == "cdt" {
            RollingLaw::Cdt
        } else {
            RollingLaw::Epsd
        };
        model.rolling.friction = 0.0; // eta = mu_r R_eff, per contact below
        match law {
            "epsd" => {
                model.rolling.stiffness_rule = RollingStiffness::Epsd;
                model.rolling.damping_rule = RollingDamping::Ratio;
                model.rolling.damping = f("coefficientRollingViscousDamping");
            }
            "epsd2" => model.rolling.stiffness_rule = RollingStiffness::Epsd2,
            "epsd3" => {
                model.rolling.stiffness_rule = RollingStiffness::Epsd3;
                model.rolling.stiffness_factor = f("rollingStiffness");
                model.rolling.damping_rule = RollingDamping::Ratio;
                model.rolling.damping = f("coefficientRollingViscousDamping");
            }
            _ => {}
        }
        // `torsionTorque on` in the case's pair_style.
        model.torsion_torque = params["torsion_torque"].as_bool().unwrap_or(false);
        model.validate().unwrap();
        let dt = params["dt"].as_f64().unwrap();
        let mut state = ContactState::default();
        let (mut worst, mut at, mut scale) = (0.0f64, 0usize, 1e-300f64);
        for row in rows {
            let step = row.f("step") as usize;
            let sphere = |k: &str| Sphere {
                position: row.v(&format!("{{}}{k}")),
                velocity: row.v(&format!("v{k}{{}}")),
                angular_velocity: row.v(&format!("w{k}{{}}")),
                radius: row.f(&format!("r{k}")),
            };
            let (b1, b2) = (sphere("1"), sphere("2"));
            let (m1, m2) = (row.f("m1"), row.f("m2"));
            let r_eff = b1.radius * b2.radius / (b1.radius + b2.radius);
            let delta = b1.radius + b2.radius - (b2.position - b1.position).norm();
            let root_rd = (r_eff * delta).sqrt();
            let k_n = 4.0 / 3.0 * y_eff * root_rd;
            let k_t = 8.0 * g_eff * root_rd;
            let m_eff = m1 * m2 / (m1 + m2);
            let gamma_t = -2.0 * (5.0f64 / 6.0).sqrt() * beta * (k_t * m_eff).sqrt();
            let mut input = StepInput::new(row.f("fn"), dt);
            input.normal_stiffness = k_n;
            input.sliding_stiffness = Some(k_t);
            input.sliding_damping = Some(gamma_t);
            input.rolling_friction = Some(mu_r * r_eff);
            input.mass1 = m1;
            input.mass2 = m2;
            input.inertia1 = 0.4 * m1 * b1.radius * b1.radius;
            input.inertia2 = 0.4 * m2 * b2.radius * b2.radius;
            input.setup = step == 0;
            let out = contact_step_pair(&model, &b1, &b2, &input, &mut state)
                .unwrap_or_else(|e| panic!("{name} step {step}: {e}"));
            let pairs = [
                (out.loads.force1, row.v("f1{}")),
                (out.loads.torque1, row.v("t1{}")),
                (out.loads.force2, row.v("f2{}")),
                (out.loads.torque2, row.v("t2{}")),
            ];
            for (got, want) in &pairs {
                scale = scale.max(want.amax());
                let err = (got - want).amax();
                if err > worst {
                    (worst, at) = (err, step);
                }
            }
        }
        worst /= scale;
        println!("{name:22} worst relative error {worst:.2e} at step {at}");
        assert!(
            worst < 1e-11,
            "{name}: LIGGGHTS_3_8 preset differs by {worst:.2e} at step {at}"
        );
    }
}
