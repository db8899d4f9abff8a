//! The LAMMPS_2021 preset against LAMMPS 29 Sep 2021 itself: every step of every case of
//! `tests/reference/lammps/lammps_reference.csv` (made by `tests/reference/lammps/regenerate.sh`
//! with Debian's `lmp`), fed through the library with the inputs LAMMPS saw.
//!
//! The host (this test) owns the normal force: it passes LAMMPS' signed normal force (elastic
//! plus damping; tensile in a few steps of `sds_roll_reverse_unload`) as `normal_force`, with no
//! limit force (the preset's rule `|f_n|` is LAMMPS' `Fncrit` for these normal models), and the
//! per-contact tangential damping `xgammat * eta_n * damp` LAMMPS uses.
//! Tolerance: both codes evaluate the same formulas in double, in a different order, so each
//! load differs by a few ulps of the loads the case handles (the largest load or `Fncrit` of
//! the case: rounding is relative to the numbers in play, not to a load that happens to pass
//! through zero); over a few hundred steps that stays below 1e-14 of it (measured worst
//! printed with --nocapture). 1e-11 fails on any rule difference (a clip, a sign, a transport
//! condition), which moves loads by 1e-6 or more.

mod common;
use common::reference::*;
use nalgebra::Vector3;
use rollslide::laws::checked::contact_step_pair;
use rollslide::laws::model::*;
use rollslide::laws::step::{ContactState, StepInput};
use rollslide::Sphere;

fn model_for(law: &serde_json::Value) -> Model {
    let f = |k: &str| law[k].as_f64().unwrap();
    let mut m = Model::with_preset(Preset::Lammps2021);
    m.sliding = SlidingParams {
        law: SlidingLaw::Linear,
        stiffness: f("kt"),
        damping: 0.0, // per contact, below
        friction: f("mu_s"),
    };
    m.rolling = RollingParams {
        law: RollingLaw::Epsd,
        stiffness: f("kr"),
        damping: f("gr"),
        friction: f("mu_r"),
        ..m.rolling
    };
    m.twisting = if law["twist"] == "marshall" {
        TwistingParams {
            law: TwistingLaw::Marshall,
            ..Default::default()
        }
    } else {
        TwistingParams {
            law: TwistingLaw::Sds,
            stiffness: f("ktw"),
            damping: f("gtw"),
            friction: f("mu_tw"),
        }
    };
    m
}

#[test]
fn lammps_2021_preset_reproduces_lammps_step_by_step() {
    let dir = root().join("tests/reference/lammps");
    let cases = load_cases(&dir.join("lammps_reference.csv"));
    assert!(
        cases.len() >= 10,
        "expected the LAMMPS cases, found {}",
        cases.len()
    );
    let mut overall = 0.0f64;
    for (name, rows) in &cases {
        let params = load_json(&dir.join(format!("params/{name}.json")));
        let law = &params["law"];
        let model = model_for(law);
        let dt = params["dt"].as_f64().unwrap();
        let mut state = ContactState::default();
        let mut worst = (0.0f64, 0usize);
        let mut case_scale = 1e-300f64;
        for row in rows {
            let step = row.f("step") as usize;
            let b1 = Sphere {
                position: row.v("{}1"),
                velocity: row.v("v1{}"),
                angular_velocity: row.v("w1{}"),
                radius: row.f("r1"),
            };
            let b2 = Sphere {
                position: row.v("{}2"),
                velocity: row.v("v2{}"),
                angular_velocity: row.v("w2{}"),
                radius: row.f("r2"),
            };
            // What LAMMPS' host side computes: the damping prefactor of the normal model.
            let (r1, r2) = (b1.radius, b2.radius);
            let r_eff = r1 * r2 / (r1 + r2);
            let delta = r1 + r2 - (b2.position - b1.position).norm();
            let (m1, m2) = (row.f("m1"), row.f("m2"));
            let damp = if law["damping"] == "velocity" {
                1.0
            } else {
                (delta * r_eff).sqrt() * m1 * m2 / (m1 + m2)
            };
            let prefactor = law["eta_n"].as_f64().unwrap() * damp;
            let fn_signed = row.f("fn_signed");
            let mut input = StepInput::new(fn_signed, dt);
            input.sliding_damping = Some(law["xgammat"].as_f64().unwrap() * prefactor);
            input.setup = step == 0;
            let out = contact_step_pair(&model, &b1, &b2, &input, &mut state)
                .unwrap_or_else(|e| panic!("{name} step {step}: {e}"));
            let pairs: [(Vector3<f64>, Vector3<f64>); 4] = [
                (out.loads.force1, row.v("f1{}")),
                (out.loads.torque1, row.v("t1{}")),
                (-out.loads.force1, row.v("f2{}")),
                (out.loads.torque2, row.v("t2{}")),
            ];
            case_scale = pairs
                .iter()
                .map(|(_, want)| want.amax())
                .fold(row.f("fn"), f64::max)
                .max(case_scale);
            for (got, want) in &pairs {
                let err = (got - want).amax();
                if err > worst.0 {
                    worst = (err, step);
                }
            }
        }
        worst.0 /= case_scale;
        println!(
            "{name:28} worst relative error {:.2e} at step {}",
            worst.0, worst.1
        );
        assert!(
            worst.0 < 1e-11,
            "{name}: LAMMPS_2021 preset differs by {:.2e} at step {}",
            worst.0,
            worst.1
        );
        overall = overall.max(worst.0);
    }
    println!("overall worst {overall:.2e}");
}
