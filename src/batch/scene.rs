//! Scene specialisation: the batch kernel is instantiated once per configuration below, with
//! the model's law, transport and preset fields replaced by compile-time constants, so the
//! generic step's branches on the model fold away and each configuration is its own loop.
//! A model that matches none of them runs [`Scene::Generic`] (same physics, with the
//! decisions taken at run time once per chunk of contacts).

use crate::laws::model::{
    DampingMode, Model, Preset, RollingDamping, RollingForm, RollingLaw, RollingStiffness,
    SlidingLaw, Transport, TwistingLaw,
};

/// The specialised configurations (the const parameter `S` of the kernels is `Scene as u8`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Scene {
    /// Any model: decisions at run time.
    Generic = 0,
    /// Objective preset, exact transport: linear sliding + EPSD rolling (given k, gamma, damping
    /// always, length form) + sds twisting, no energy bookkeeping.
    FullExact = 1,
    /// LAMMPS_2021 preset (project-rescale transport): linear history + rolling sds + twisting
    /// sds, the hand-written C baseline's physics.
    FullLammps = 2,
    /// Objective, exact transport, linear sliding only.
    SlidingExact = 3,
    /// Objective, exact transport, linear sliding + EPSD rolling, no twisting.
    SlidingRollingExact = 4,
    /// LAMMPS_2021 preset, linear history sliding only.
    SlidingLammps = 5,
    /// LAMMPS_2021 preset, rolling sds + twisting sds, no sliding law.
    RollingTwistingLammps = 6,
    /// Objective preset, exact transport: EPSD rolling (given k, gamma, damping always, length
    /// form) + sds twisting, no sliding law.
    RollingTwistingExact = 7,
    /// LAMMPS_2021 preset, linear history sliding + rolling sds, no twisting law.
    SlidingRollingLammps = 8,
    /// LAMMPS_2021 preset, linear history sliding + rolling sds + twisting marshall (the
    /// twisting coefficients derived from the sliding ones and the contact radius).
    FullLammpsMarshall = 9,
    /// Objective preset, exact transport: linear sliding + EPSD rolling (as `FullExact`) +
    /// twisting marshall (the twisting coefficients derived from the sliding ones and the
    /// contact radius).
    FullExactMarshall = 10,
    /// Objective preset, exact transport: EPSD rolling only (as `FullExact`'s), no sliding or
    /// twisting law: rolling resistance added to a host that computes its own normal and
    /// tangential forces.
    RollingExact = 11,
    /// LAMMPS_2021 preset, project-rescale transport: EPSD rolling only (as `FullLammps`'s), no
    /// sliding or twisting law: LAMMPS' `pair granular` rolling sds on a host that computes its
    /// own normal and tangential forces.
    RollingLammps = 12,
    /// LAMMPS_2021 preset, project-rescale transport: twisting sds only, no sliding or rolling
    /// law: LAMMPS' `pair granular` twisting sds on a host that computes its own normal and
    /// tangential forces.
    TwistingLammps = 13,
    /// LAMMPS_2021 preset, project-rescale transport: linear history sliding + twisting sds, no
    /// rolling law.
    SlidingTwistingLammps = 14,
    /// Objective preset, exact transport: twisting sds only (as `FullExact`'s), no sliding or
    /// rolling law: twisting resistance added to a host that computes its own normal and
    /// tangential forces.
    TwistingExact = 15,
    /// Objective preset, exact transport: linear sliding + twisting sds, no rolling law.
    SlidingTwistingExact = 16,
}

impl Scene {
    /// Every scene, in code order.
    pub const ALL: [Scene; 17] = [
        Scene::Generic,
        Scene::FullExact,
        Scene::FullLammps,
        Scene::SlidingExact,
        Scene::SlidingRollingExact,
        Scene::SlidingLammps,
        Scene::RollingTwistingLammps,
        Scene::RollingTwistingExact,
        Scene::SlidingRollingLammps,
        Scene::FullLammpsMarshall,
        Scene::FullExactMarshall,
        Scene::RollingExact,
        Scene::RollingLammps,
        Scene::TwistingLammps,
        Scene::SlidingTwistingLammps,
        Scene::TwistingExact,
        Scene::SlidingTwistingExact,
    ];

    /// A short name (benchmark tables).
    pub fn name(self) -> &'static str {
        match self {
            Scene::Generic => "generic",
            Scene::FullExact => "full/exact",
            Scene::FullLammps => "full/lammps",
            Scene::SlidingExact => "sliding/exact",
            Scene::SlidingRollingExact => "slide+roll/exact",
            Scene::SlidingLammps => "sliding/lammps",
            Scene::RollingTwistingLammps => "roll+twist/lammps",
            Scene::RollingTwistingExact => "roll+twist/exact",
            Scene::SlidingRollingLammps => "slide+roll/lammps",
            Scene::FullLammpsMarshall => "full/lammps+marshall",
            Scene::FullExactMarshall => "full/exact+marshall",
            Scene::RollingExact => "roll/exact",
            Scene::RollingLammps => "roll/lammps",
            Scene::TwistingLammps => "twist/lammps",
            Scene::SlidingTwistingLammps => "slide+twist/lammps",
            Scene::TwistingExact => "twist/exact",
            Scene::SlidingTwistingExact => "slide+twist/exact",
        }
    }

    /// The scene of a code (`Generic` for an unknown one); a `const fn` so that a kernel's
    /// const parameter names its scene at compile time.
    #[inline(always)]
    pub const fn from_code(code: u8) -> Scene {
        match code {
            1 => Scene::FullExact,
            2 => Scene::FullLammps,
            3 => Scene::SlidingExact,
            4 => Scene::SlidingRollingExact,
            5 => Scene::SlidingLammps,
            6 => Scene::RollingTwistingLammps,
            7 => Scene::RollingTwistingExact,
            8 => Scene::SlidingRollingLammps,
            9 => Scene::FullLammpsMarshall,
            10 => Scene::FullExactMarshall,
            11 => Scene::RollingExact,
            12 => Scene::RollingLammps,
            13 => Scene::TwistingLammps,
            14 => Scene::SlidingTwistingLammps,
            15 => Scene::TwistingExact,
            16 => Scene::SlidingTwistingExact,
            _ => Scene::Generic,
        }
    }

    /// The most specialised scene whose constants equal `model`'s fields.
    pub fn classify(model: &Model) -> Scene {
        Scene::ALL
            .into_iter()
            .skip(1)
            .find(|s| fold(*s, model) == *model)
            .unwrap_or(Scene::Generic)
    }
}

/// The model with `scene`'s constant fields written over it (identity for `Generic`). Called
/// with a constant `scene` inside an inlined kernel, every branch of the step on these fields
/// is decided at compile time.
#[inline(always)]
pub fn fold(scene: Scene, model: &Model) -> Model {
    let mut m = *model;
    let exact = (Transport::Exact, Preset::Objective);
    let lammps = (Transport::ProjectRescale, Preset::Lammps2021);
    let sds = TwistingLaw::Sds;
    let (sliding, rolling, twisting, (transport, preset)) = match scene {
        Scene::Generic => return m,
        Scene::FullExact => (true, true, sds, exact),
        Scene::FullLammps => (true, true, sds, lammps),
        Scene::SlidingExact => (true, false, TwistingLaw::None, exact),
        Scene::SlidingRollingExact => (true, true, TwistingLaw::None, exact),
        Scene::SlidingLammps => (true, false, TwistingLaw::None, lammps),
        Scene::RollingTwistingLammps => (false, true, sds, lammps),
        Scene::RollingTwistingExact => (false, true, sds, exact),
        Scene::SlidingRollingLammps => (true, true, TwistingLaw::None, lammps),
        Scene::FullLammpsMarshall => (true, true, TwistingLaw::Marshall, lammps),
        Scene::FullExactMarshall => (true, true, TwistingLaw::Marshall, exact),
        Scene::RollingExact => (false, true, TwistingLaw::None, exact),
        Scene::RollingLammps => (false, true, TwistingLaw::None, lammps),
        Scene::TwistingLammps => (false, false, sds, lammps),
        Scene::SlidingTwistingLammps => (true, false, sds, lammps),
        Scene::TwistingExact => (false, false, sds, exact),
        Scene::SlidingTwistingExact => (true, false, sds, exact),
    };
    m.sliding.law = if sliding {
        SlidingLaw::Linear
    } else {
        SlidingLaw::None
    };
    m.rolling.law = if rolling {
        RollingLaw::Epsd
    } else {
        RollingLaw::None
    };
    if rolling {
        m.rolling.form = RollingForm::Length;
        m.rolling.stiffness_rule = RollingStiffness::Given;
        m.rolling.damping_rule = RollingDamping::Given;
        m.rolling.damping_mode = DampingMode::Always;
    }
    m.twisting.law = twisting;
    m.sliding_transport = transport;
    m.rolling_transport = transport;
    m.preset = preset;
    m.track_energy = false;
    m.torsion_torque = false;
    m.contact_point_sliding = false;
    m
}
