//! The LAMMPS_2021 preset against LAMMPS 29 Sep 2021 itself: every step of every case of
//! `tests/reference/lammps/lammps_reference.csv` (made by `tests/reference/lammps/regenerate.sh`
//! with Debian's `lmp`), fed through the library with the inputs LAMMPS saw.
//!
//! The host (this test) owns the normal force: it passes LAMMPS' signed normal force (elastic
//! plus damping; tensile in a few steps of `sds_roll_reverse_unload` and in most of the `jkr_*`
//! and `dmt_*` cases) as `normal_force`, and the per-contact tangential damping
//! `xgammat * eta_n * damp` LAMMPS uses. For `hooke` and `hertz/material` it gives no limit
//! force (the preset's rule `|f_n|` is LAMMPS' `Fncrit` there); for the cohesive `jkr` and `dmt`
//! it passes LAMMPS' `Fncrit` (column `fn`, not `|f_n|`) as the limit force. Where LAMMPS has
//! no contact (column `contact` = 0: separated, or past JKR's pull-off) the host applies
//! nothing and resets the contact's state, as LAMMPS drops the history; LAMMPS' loads must be
//! zero there. `lammps_cohesive_cases_through_the_c_abi` replays the `jkr` and `dmt` cases
//! through `rsl_contact_step` with `RSL_INPUT_LIMIT_FORCE`.
//! Tolerance: both codes evaluate the same formulas in double, in a different order, so each
//! load differs by a few ulps of the loads the case handles (the largest load or `Fncrit` of
//! the case: rounding is relative to the numbers in play, not to a load that happens to pass
//! through zero); over a few hundred steps that stays below 1e-14 of it (measured worst
//! printed with --nocapture). 1e-11 fails on any rule difference (a clip, a sign, a transport
//! condition), which moves loads by 1e-6 or more.

mod common;
use common::reference::*;
use nalgebra::Vector3;
use rollslide::capi::contact::{
    rsl_contact_input, rsl_contact_loads, rsl_contact_state, rsl_contact_state_init,
    rsl_contact_step, RSL_INPUT_LIMIT_FORCE, RSL_INPUT_SETUP, RSL_INPUT_SLIDING_DAMPING,
    RSL_SLIP_ROLLING, RSL_SLIP_SLIDING, RSL_SLIP_TWISTING,
};
use rollslide::capi::model::*;
use rollslide::capi::status::RSL_OK;
use rollslide::capi::types::rsl_sphere;
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
        history: m.sliding.history,
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

/// `jkr` and `dmt`: LAMMPS' friction limits use `Fncrit` (column `fn`), not `|F_n|`.
fn cohesive(law: &serde_json::Value) -> bool {
    law["normal"] == "jkr" || law["normal"] == "dmt"
}

fn bodies(row: &Row) -> (Sphere<f64>, Sphere<f64>) {
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
    (b1, b2)
}

/// What LAMMPS' host side computes for the sliding dashpot: `xgammat` times the damping
/// prefactor of the normal model (`eta_n`, or `eta_n a meff` with `a = sqrt(delta R_eff)` for
/// the viscoelastic damping of hertz/material and dmt).
fn sliding_damping(law: &serde_json::Value, row: &Row, b1: &Sphere<f64>, b2: &Sphere<f64>) -> f64 {
    let (r1, r2) = (b1.radius, b2.radius);
    let r_eff = r1 * r2 / (r1 + r2);
    let delta = r1 + r2 - (b2.position - b1.position).norm();
    let (m1, m2) = (row.f("m1"), row.f("m2"));
    let damp = if law["damping"] == "velocity" {
        1.0
    } else {
        (delta * r_eff).sqrt() * m1 * m2 / (m1 + m2)
    };
    // LAMMPS: damp_tangential = xgammat * (eta_n * damp)
    law["xgammat"].as_f64().unwrap() * (law["eta_n"].as_f64().unwrap() * damp)
}

/// LAMMPS' loads of a row: force and torque on atom 1, force and torque on atom 2.
fn lammps_loads(row: &Row) -> [Vector3<f64>; 4] {
    [row.v("f1{}"), row.v("t1{}"), row.v("f2{}"), row.v("t2{}")]
}

/// LAMMPS has no contact on this row: it applied nothing (checked) and dropped the history.
fn no_contact(row: &Row, name: &str) -> bool {
    if row.f("contact") != 0.0 {
        return false;
    }
    for load in lammps_loads(row) {
        assert_eq!(load, Vector3::zeros(), "{name} step {}", row.f("step"));
    }
    true
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
            if no_contact(row, name) {
                state = ContactState::default();
                continue;
            }
            let (b1, b2) = bodies(row);
            let mut input = StepInput::new(row.f("fn_signed"), dt);
            input.sliding_damping = Some(sliding_damping(law, row, &b1, &b2));
            if cohesive(law) {
                input.limit_force = Some(row.f("fn"));
            }
            input.setup = step == 0;
            let out = contact_step_pair(&model, &b1, &b2, &input, &mut state)
                .unwrap_or_else(|e| panic!("{name} step {step}: {e}"));
            let [f1, t1, f2, t2] = lammps_loads(row);
            let pairs: [(Vector3<f64>, Vector3<f64>); 4] = [
                (out.loads.force1, f1),
                (out.loads.torque1, t1),
                (-out.loads.force1, f2),
                (out.loads.torque2, t2),
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

/// The model of `model_for` built through the C ABI.
struct CModel(*mut rsl_model);

impl CModel {
    fn new(law: &serde_json::Value) -> Self {
        let f = |k: &str| law[k].as_f64().unwrap();
        let mut p: *mut rsl_model = std::ptr::null_mut();
        // SAFETY: `p` is a live local; every later call gets the model just created and live
        // locals of the right types.
        unsafe {
            assert_eq!(rsl_model_new(RSL_PRESET_LAMMPS_2021, &mut p), RSL_OK);
            let model = CModel(p);
            // Damping 0: LAMMPS' sliding dashpot is per contact (RSL_INPUT_SLIDING_DAMPING).
            assert_eq!(
                rsl_model_set_sliding(p, RSL_SLIDING_LINEAR, f("kt"), 0.0, f("mu_s")),
                RSL_OK
            );
            let mut rolling = std::mem::zeroed::<rsl_rolling_params>();
            assert_eq!(rsl_model_get_rolling(p, &mut rolling), RSL_OK);
            rolling.law = RSL_ROLLING_EPSD;
            rolling.stiffness = f("kr");
            rolling.damping = f("gr");
            rolling.friction = f("mu_r");
            assert_eq!(rsl_model_set_rolling(p, &rolling), RSL_OK);
            assert_eq!(law["twist"], "sds");
            assert_eq!(
                rsl_model_set_twisting(p, RSL_TWISTING_SDS, f("ktw"), f("gtw"), f("mu_tw")),
                RSL_OK
            );
            model
        }
    }
}

impl Drop for CModel {
    fn drop(&mut self) {
        // SAFETY: a live model from rsl_model_new, freed once.
        unsafe { rsl_model_free(self.0) }
    }
}

fn c_sphere(b: &Sphere<f64>) -> rsl_sphere {
    rsl_sphere {
        position: b.position.into(),
        velocity: b.velocity.into(),
        angular_velocity: b.angular_velocity.into(),
        radius: b.radius,
    }
}

/// The `jkr` and `dmt` cases through the C ABI, as a C host calls it: `rsl_contact_step` with
/// LAMMPS' signed normal force (negative on the tensile rows), `RSL_INPUT_LIMIT_FORCE` with
/// LAMMPS' `Fncrit`, the per-contact sliding damping, `RSL_INPUT_SETUP` on the setup call, and
/// `rsl_contact_state_init` where LAMMPS' contact ends. Each case must reach the sliding, rolling
/// and twisting limits on tensile rows (JKR: also at negative overlap), so the limit force is
/// what decides those rows. Tolerance 1e-11 of the case's largest load or `Fncrit`, as for the
/// Rust API above (same arithmetic: with a limit force the C ABI takes the checked path, and
/// its loads are asserted equal bit for bit to the Rust API's).
#[test]
fn lammps_cohesive_cases_through_the_c_abi() {
    let dir = root().join("tests/reference/lammps");
    let cases = load_cases(&dir.join("lammps_reference.csv"));
    let mut found = 0;
    for (name, rows) in cases
        .iter()
        .filter(|(n, _)| n.starts_with("jkr_") || n.starts_with("dmt_"))
    {
        found += 1;
        let params = load_json(&dir.join(format!("params/{name}.json")));
        let law = &params["law"];
        assert!(cohesive(law), "{name}");
        let dt = params["dt"].as_f64().unwrap();
        let model = CModel::new(law);
        let rust_model = model_for(law);
        let mut state = rsl_contact_state::default();
        let mut rust_state = ContactState::default();
        let mut worst = (0.0f64, 0usize);
        let mut case_scale = 1e-300f64;
        // Tensile rows, and tensile rows at the sliding, rolling, twisting limit.
        let mut tensile = 0;
        let mut tensile_slips = [0; 3];
        let mut negative_overlap = 0;
        for row in rows {
            let step = row.f("step") as usize;
            if no_contact(row, name) {
                // SAFETY: `state` is a live local.
                assert_eq!(unsafe { rsl_contact_state_init(&mut state) }, RSL_OK);
                rust_state = ContactState::default();
                continue;
            }
            let (b1, b2) = bodies(row);
            let damping = sliding_damping(law, row, &b1, &b2);
            let input = rsl_contact_input {
                normal_force: row.f("fn_signed"),
                dt,
                sliding_damping: damping,
                limit_force: row.f("fn"),
                flags: RSL_INPUT_LIMIT_FORCE
                    | RSL_INPUT_SLIDING_DAMPING
                    | if step == 0 { RSL_INPUT_SETUP } else { 0 },
                ..Default::default()
            };
            let (c1, c2) = (c_sphere(&b1), c_sphere(&b2));
            let mut out = rsl_contact_loads::default();
            // SAFETY: a live model and live locals of the right types, none overlapping.
            let status =
                unsafe { rsl_contact_step(model.0, &c1, &c2, &input, &mut state, &mut out) };
            assert_eq!(status, RSL_OK, "{name} step {step}");
            let got: [Vector3<f64>; 4] = [
                out.force1.into(),
                out.torque1.into(),
                (-Vector3::from(out.force1)),
                out.torque2.into(),
            ];

            let mut rust_input = StepInput::new(input.normal_force, dt);
            rust_input.sliding_damping = Some(damping);
            rust_input.limit_force = Some(input.limit_force);
            rust_input.setup = step == 0;
            let rust = contact_step_pair(&rust_model, &b1, &b2, &rust_input, &mut rust_state)
                .unwrap_or_else(|e| panic!("{name} step {step}: {e}"));
            for (c, r) in got.iter().zip([rust.loads.force1, rust.loads.torque1]) {
                assert_eq!(
                    c.map(f64::to_bits),
                    r.map(f64::to_bits),
                    "{name} step {step}: C ABI and Rust API differ"
                );
            }
            assert_eq!(
                got[3].map(f64::to_bits),
                rust.loads.torque2.map(f64::to_bits),
                "{name} step {step}"
            );

            let want = lammps_loads(row);
            case_scale = want
                .iter()
                .map(|w| w.amax())
                .fold(row.f("fn"), f64::max)
                .max(case_scale);
            for (g, w) in got.iter().zip(&want) {
                let err = (g - w).amax();
                if err > worst.0 {
                    worst = (err, step);
                }
            }
            if input.normal_force < 0.0 {
                tensile += 1;
                for (k, bit) in [RSL_SLIP_SLIDING, RSL_SLIP_ROLLING, RSL_SLIP_TWISTING]
                    .into_iter()
                    .enumerate()
                {
                    tensile_slips[k] += usize::from(out.slip_flags & bit != 0);
                }
            }
            if b1.radius + b2.radius < (b2.position - b1.position).norm() {
                negative_overlap += 1;
            }
        }
        worst.0 /= case_scale;
        println!(
            "{name:28} worst relative error {:.2e} at step {}; {tensile} tensile rows, at the \
             sliding/rolling/twisting limit in {tensile_slips:?} of them; {negative_overlap} \
             rows in contact at negative overlap",
            worst.0, worst.1
        );
        assert!(
            worst.0 < 1e-11,
            "{name}: through the C ABI the LAMMPS_2021 preset differs by {:.2e} at step {}",
            worst.0,
            worst.1
        );
        assert!(
            tensile_slips.iter().all(|&n| n > 0),
            "{name}: every limit must be reached under tension ({tensile_slips:?})"
        );
        if name.starts_with("jkr_") {
            assert!(
                negative_overlap > 0,
                "{name}: no contact at negative overlap"
            );
        }
    }
    assert_eq!(found, 4, "expected the jkr_* and dmt_* cases");
}
