//! What each compatibility preset changes in the step (peers.md): the sliding rate, the clip
//! rules, what the rolling spring stores (the sliding spring's is the model's `SlidingHistory`), the setup pass, and a few law details. Everything here is
//! decided once per call from the model, never per contact lane.

use crate::laws::model::Preset;
use crate::laws::spring::{ClipRule, Storage};

/// Which sliding velocity drives the sliding spring.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlidingRate {
    /// The decomposition's `v_s` with the model's branch rule (objective with midplane).
    Branches,
    /// Full radii as arms (LAMMPS): `v_s + (delta/2)(w1 + w2) x n`.
    Radii,
    /// YADE's incident velocity (avoidGranularRatcheting): full radii and `(v2 - v1)_t`
    /// scaled by `(R1 + R2)/d`: `v_s(radii) - (delta/d)(v2 - v1)_t`.
    YadeScaled,
}

/// The force the limits use when the host gives none (`StepInput::limit_force`), from the
/// signed normal force `f_n` (compressive positive, tensile negative).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TensionLimit {
    /// `max(f_n, 0)`: no friction while the contact pulls (objective; YADE's shear limit
    /// `max(0, Fn tan(phi))` without adhesion).
    Compressive,
    /// `|f_n|` (LAMMPS' `Fncrit = |F_n|` of its non-cohesive normal models; LIGGGHTS'
    /// `|Fn|` in its sliding and EPSD limits).
    Magnitude,
}

/// What the setup pass (`StepInput::setup`) does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SetupRule {
    /// Whether the sliding spring gets this step's increment.
    pub sliding_increment: bool,
    /// Whether the rolling spring gets this step's increment.
    pub rolling_increment: bool,
    /// Whether the state is written (LAMMPS: its clip writes the history even at setup).
    pub store: bool,
}

/// The step conventions of a preset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Conventions {
    /// Rate of the sliding spring.
    pub sliding_rate: SlidingRate,
    /// Clip of the sliding spring.
    pub sliding_clip: ClipRule,
    /// Clip of the rolling spring when its dashpot acts always.
    pub rolling_clip: ClipRule,
    /// Clip of the twisting spring.
    pub twisting_clip: ClipRule,
    /// What the rolling spring stores.
    pub rolling_storage: Storage,
    /// YADE keeps the twisting moment as a vector, transported like the shear force.
    pub twist_vector: bool,
    /// LIGGGHTS' cdt: elastic normal force `k_n delta`, direction `(w/|w|)_t`.
    pub cdt_liggghts: bool,
    /// LAMMPS transports a spring only when `|xi . n| k > 1e-10 mu f_n`.
    pub lammps_rescale_threshold: bool,
    /// The limits' force without `limit_force`.
    pub tension_limit: TensionLimit,
    /// YADE CohFrict's rules with shear adhesion (`StepInput::shear_adhesion`): the sliding
    /// limit on the signed `f_n`, the rolling and twisting limits on `|f_n|`, and no normal
    /// force (hence zero rolling and twisting limits) in a step that slips under tension.
    pub yade_cohesion: bool,
    /// The setup pass.
    pub setup: SetupRule,
}

/// The objective preset's conventions, which the others start from.
const OBJECTIVE: Conventions = Conventions {
    sliding_rate: SlidingRate::Branches,
    sliding_clip: ClipRule::Total,
    rolling_clip: ClipRule::Total,
    twisting_clip: ClipRule::Total,
    rolling_storage: Storage::Displacement,
    twist_vector: false,
    cdt_liggghts: false,
    lammps_rescale_threshold: false,
    tension_limit: TensionLimit::Compressive,
    yade_cohesion: false,
    setup: SetupRule {
        sliding_increment: false,
        rolling_increment: false,
        store: false,
    },
};

/// Every preset's conventions, in the order of [`Preset`]'s variants: a table, so that a step
/// reads the few it needs from memory (a `match` building the struct in every call compiled to
/// a jump and a dozen stores per call).
static CONVENTIONS: [Conventions; 4] = [
    OBJECTIVE,
    Conventions {
        sliding_rate: SlidingRate::Radii,
        sliding_clip: ClipRule::Lammps,
        rolling_clip: ClipRule::Lammps,
        twisting_clip: ClipRule::Lammps,
        lammps_rescale_threshold: true,
        tension_limit: TensionLimit::Magnitude,
        setup: SetupRule {
            sliding_increment: false,
            rolling_increment: false,
            store: true,
        },
        ..OBJECTIVE
    },
    Conventions {
        sliding_rate: SlidingRate::YadeScaled,
        rolling_storage: Storage::Load,
        twist_vector: true,
        yade_cohesion: true,
        ..OBJECTIVE
    },
    Conventions {
        sliding_clip: ClipRule::SpringOnly,
        rolling_storage: Storage::Load,
        cdt_liggghts: true,
        tension_limit: TensionLimit::Magnitude,
        setup: SetupRule {
            sliding_increment: false,
            rolling_increment: true,
            store: false,
        },
        ..OBJECTIVE
    },
];

impl Preset {
    /// The conventions of this preset.
    #[inline(always)]
    pub fn conventions(self) -> Conventions {
        let index = match self {
            Preset::Objective => 0,
            Preset::Lammps2021 => 1,
            Preset::Yade2023 => 2,
            Preset::Liggghts38 => 3,
        };
        CONVENTIONS[index]
    }
}
