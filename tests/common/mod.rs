//! Shared helpers of the integration tests: a seeded generator and tolerance checks.
#![allow(dead_code)]

use rollslide::laws::model::{
    Model, Preset, RollingForm, RollingLaw, RollingStiffness, SlidingHistory, SlidingLaw,
    Transport, TwistingLaw,
};
use rollslide::scalar::Vec3;

/// Full law set (linear sliding + EPSD rolling + sds twisting) on a preset and transport, with
/// limits that a good part of random contacts reach (the batch and fast-path tests).
pub fn full_model(preset: Preset, transport: Transport) -> Model {
    let mut m = Model::with_preset(preset);
    m.sliding.law = SlidingLaw::Linear;
    m.sliding.stiffness = 2.0e5;
    m.sliding.damping = 30.0;
    m.sliding.friction = 0.5;
    m.rolling.law = RollingLaw::Epsd;
    m.rolling.stiffness = 1.0e5;
    m.rolling.damping = 10.0;
    m.rolling.friction = 0.1;
    m.twisting.law = TwistingLaw::Sds;
    m.twisting.stiffness = 50.0;
    m.twisting.damping = 0.5;
    m.twisting.friction = 0.05;
    m.sliding_transport = transport;
    m.rolling_transport = transport;
    m
}

/// One model per law set a DEM host runs, each with a short name for messages: linear sliding
/// on or off, EPSD rolling (or cdt) on or off, sds or Marshall twisting on or off, in each preset
/// family (objective with exact transport, LAMMPS_2021 with project-rescale, LIGGGHTS_3_8 with
/// its own transports and rolling laws). The batch and fast-path tests step every one of them,
/// at every SIMD level, against the per-contact checked step.
pub fn law_set_models() -> Vec<(Model, String)> {
    let full = full_model(Preset::Objective, Transport::Exact);
    let lammps = full_model(Preset::Lammps2021, Transport::ProjectRescale);
    let mut sliding = full;
    sliding.rolling.law = RollingLaw::None;
    sliding.twisting.law = TwistingLaw::None;
    let mut slide_roll = full;
    slide_roll.twisting.law = TwistingLaw::None;
    let mut sliding_lammps = lammps;
    sliding_lammps.rolling.law = RollingLaw::None;
    sliding_lammps.twisting.law = TwistingLaw::None;
    let mut roll_twist_lammps = lammps;
    roll_twist_lammps.sliding.law = SlidingLaw::None;
    let mut roll_twist = full;
    roll_twist.sliding.law = SlidingLaw::None;
    let mut slide_roll_lammps = lammps;
    slide_roll_lammps.twisting.law = TwistingLaw::None;
    let mut lammps_marshall = lammps;
    lammps_marshall.twisting.law = TwistingLaw::Marshall;
    let mut exact_marshall = full;
    exact_marshall.twisting.law = TwistingLaw::Marshall;
    let mut roll = roll_twist;
    roll.twisting.law = TwistingLaw::None;
    let mut roll_lammps = roll_twist_lammps;
    roll_lammps.twisting.law = TwistingLaw::None;
    let mut twist_lammps = roll_twist_lammps;
    twist_lammps.rolling.law = RollingLaw::None;
    let mut slide_twist_lammps = lammps;
    slide_twist_lammps.rolling.law = RollingLaw::None;
    let mut twist = roll_twist;
    twist.rolling.law = RollingLaw::None;
    let mut slide_twist = full;
    slide_twist.rolling.law = RollingLaw::None;
    // LIGGGHTS' `tangential history rolling_friction cdt`: the preset's transports and angle
    // form, a moment eta k_n delta (eta = mu_r R, a length) above a relative spin of 1 rad/s
    // (the tests' spins are up to a few rad/s, so both sides of the threshold run).
    let mut slide_cdt_liggghts = Model::with_preset(Preset::Liggghts38);
    slide_cdt_liggghts.sliding = full.sliding;
    slide_cdt_liggghts.rolling.law = RollingLaw::Cdt;
    slide_cdt_liggghts.rolling.friction = 0.05;
    slide_cdt_liggghts.rolling.rate_threshold = 1.0;
    // LIGGGHTS' `tangential history rolling_friction epsd2`: the preset's transports and angle
    // form, the rolling stiffness k_t R^2 from the sliding stiffness, a given dashpot (LIGGGHTS'
    // epsd2 has none; non-zero here so that the dashpot's below-the-limit rule runs).
    let mut slide_epsd2_liggghts = Model::with_preset(Preset::Liggghts38);
    slide_epsd2_liggghts.sliding = full.sliding;
    slide_epsd2_liggghts.rolling.law = RollingLaw::Epsd;
    slide_epsd2_liggghts.rolling.stiffness_rule = RollingStiffness::Epsd2;
    slide_epsd2_liggghts.rolling.damping = 0.2;
    slide_epsd2_liggghts.rolling.friction = 0.05;
    // The sliding histories besides the displacement: a stored force (LAMMPS mindlin/force), and
    // the rescaled ones (mindlin_rescale, mindlin_rescale/force), which keep the previous
    // stiffnesses in the state's model memory; one with energy tracking (the memory and the
    // stiffness-change term), one of LAMMPS' with Marshall twisting (its k_t a^2 / 2).
    let mut force_exact = full;
    force_exact.sliding.history = SlidingHistory::Force;
    let mut rescaled_energy = full;
    rescaled_energy.sliding.history = SlidingHistory::DisplacementRescaled;
    rescaled_energy.track_energy = true;
    let mut force_rescaled_lammps = lammps_marshall;
    force_rescaled_lammps.sliding.history = SlidingHistory::ForceRescaled;
    [
        (full, "full/exact"),
        (lammps, "full/lammps"),
        (sliding, "sliding/exact"),
        (slide_roll, "slide+roll/exact"),
        (sliding_lammps, "sliding/lammps"),
        (roll_twist_lammps, "roll+twist/lammps"),
        (roll_twist, "roll+twist/exact"),
        (slide_roll_lammps, "slide+roll/lammps"),
        (lammps_marshall, "full/lammps+marshall"),
        (exact_marshall, "full/exact+marshall"),
        (roll, "roll/exact"),
        (roll_lammps, "roll/lammps"),
        (twist_lammps, "twist/lammps"),
        (slide_twist_lammps, "slide+twist/lammps"),
        (twist, "twist/exact"),
        (slide_twist, "slide+twist/exact"),
        (slide_cdt_liggghts, "slide+cdt/liggghts"),
        (slide_epsd2_liggghts, "slide+epsd2/liggghts"),
        // Appended: tests pick models()[0] and [1] by position.
        (force_exact, "full/exact, force history"),
        (rescaled_energy, "full/exact, rescaled history, energy"),
        (
            force_rescaled_lammps,
            "full/lammps+marshall, rescaled force history",
        ),
    ]
    .into_iter()
    .map(|(m, name)| (m, name.to_string()))
    .collect()
}

/// The LIGGGHTS models of [`law_set_models`] (angle form, LIGGGHTS' own) in the length form,
/// `mu_r` = 0.1 (cdt: the moment `mu_r R_r k_n delta`; epsd2: `k_r = k_t`, limit
/// `mu_r R_r f`): the form a host uses to give each contact of unequal spheres LIGGGHTS'
/// `mu_r R_eff` from one `mu_r`.
pub fn length_form_models() -> Vec<(Model, String)> {
    law_set_models()
        .into_iter()
        .filter(|(m, _)| m.preset == Preset::Liggghts38)
        .map(|(mut m, name)| {
            m.rolling.form = RollingForm::Length;
            m.rolling.friction = 0.1;
            (m, format!("{name} (length form)"))
        })
        .collect()
}

/// SplitMix64: a small, seeded, reproducible generator (no dependency needed).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
    pub fn vec(&mut self, scale: f64) -> Vec3<f64> {
        Vec3::new(
            self.uniform(-scale, scale),
            self.uniform(-scale, scale),
            self.uniform(-scale, scale),
        )
    }
    pub fn unit(&mut self) -> Vec3<f64> {
        loop {
            let v = self.vec(1.0);
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
}

/// |a - b| <= abs + rel |b|.
pub fn close(a: f64, b: f64, abs: f64, rel: f64) -> bool {
    (a - b).abs() <= abs + rel * b.abs()
}

#[track_caller]
pub fn assert_close(a: f64, b: f64, abs: f64, rel: f64, what: &str) {
    assert!(
        close(a, b, abs, rel),
        "{what}: got {a:e}, expected {b:e} (diff {:e}, abs tol {abs:e}, rel tol {rel:e})",
        (a - b).abs()
    );
}

#[track_caller]
pub fn assert_vec_close(a: &Vec3<f64>, b: &Vec3<f64>, abs: f64, rel: f64, what: &str) {
    let diff = (a - b).norm();
    assert!(
        diff <= abs + rel * b.norm(),
        "{what}: got {a:?}, expected {b:?} (|diff| {diff:e}, abs tol {abs:e}, rel tol {rel:e})"
    );
}

pub mod granular;
pub mod lammps;
pub mod linking;
pub mod reference;

pub fn v(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}
