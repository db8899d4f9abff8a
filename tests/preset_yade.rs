//! The YADE_2023 preset against YADE 2023.02a itself (CohFrict moment law with the incremental
//! form, and Mindlin with moments): every step of `c_tests/reference/yade_double.csv`.
//! The C test `c::yade_*` checks the same data through the C ABI; this one checks the core.
//!
//! Inputs the host (this test) gives per contact, as YADE computes them: the normal force
//! `|F_n|`, the shear stiffness `ks` (constant for CohFrict, `kso sqrt(pen)` for Mindlin),
//! `kr`, `ktw`, `tan(phi)` and the limit lengths (`param_*` columns; negative = no limit).
//! Tolerance: a few ulps of the case's load scale (1e-11 relative), as for the other presets.

mod common;
use common::reference::*;
use rollslide::laws::checked::contact_step_pair;
use rollslide::laws::model::*;
use rollslide::laws::step::{ContactState, StepInput};
use rollslide::Sphere;

fn limit(x: f64) -> f64 {
    if x > 0.0 {
        x
    } else {
        f64::INFINITY
    }
}

#[test]
fn yade_2023_preset_reproduces_yade_step_by_step() {
    let cases = load_cases(&root().join("c_tests/reference/yade_double.csv"));
    assert!(
        cases.len() >= 15,
        "expected the YADE cases, found {}",
        cases.len()
    );
    for (name, rows) in &cases {
        let first = &rows[0];
        let mut model = Model::with_preset(Preset::Yade2023);
        model.sliding = SlidingParams {
            law: SlidingLaw::Linear,
            stiffness: 0.0, // per step: ks
            damping: 0.0,
            friction: first.f("param_tanphi"),
        };
        model.rolling.law = RollingLaw::Epsd;
        model.rolling.stiffness = first.f("param_kr");
        model.rolling.friction = limit(first.f("param_maxroll"));
        model.twisting = TwistingParams {
            law: TwistingLaw::Sds,
            stiffness: first.f("param_ktw"),
            damping: 0.0,
            friction: limit(first.f("param_maxtwist")),
        };
        model.validate().unwrap();
        let mut state = ContactState::default();
        let (mut worst, mut at, mut scale) = (0.0f64, 0usize, 1e-300f64);
        for row in rows {
            let step = row.f("step") as usize;
            let sphere = |k: &str| Sphere {
                position: row.v(&format!("x{k}_{{}}")),
                velocity: row.v(&format!("v{k}_{{}}")),
                angular_velocity: row.v(&format!("w{k}_{{}}")),
                radius: row.f(&format!("r{k}")),
            };
            let (b1, b2) = (sphere("1"), sphere("2"));
            let mut input = StepInput::new(row.v("fn_{}").norm(), row.f("dt"));
            input.sliding_stiffness = Some(row.f("ks"));
            let out = contact_step_pair(&model, &b1, &b2, &input, &mut state)
                .unwrap_or_else(|e| panic!("{name} step {step}: {e}"));
            let pairs = [
                (out.loads.force1, row.v("f1_{}")),
                (out.loads.torque1, row.v("t1_{}")),
                (out.loads.force2, row.v("f2_{}")),
                (out.loads.torque2, row.v("t2_{}")),
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
        println!("{name:20} worst relative error {worst:.2e} at step {at}");
        assert!(
            worst < 1e-11,
            "{name}: YADE_2023 preset differs by {worst:.2e} at step {at}"
        );
    }
}
