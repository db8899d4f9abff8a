//! Scene specialisation: the batch kernel is instantiated once per configuration below, with
//! the model's law, transport and preset fields replaced by compile-time constants, so the
//! generic step's branches on the model fold away and each configuration is its own loop.
//! A model that matches none of them runs [`Scene::Generic`] (same physics, with the
//! decisions taken at run time once per chunk of contacts).

use crate::laws::model::{
    DampingMode, Model, Preset, RollingDamping, RollingForm, RollingLaw, RollingStiffness,
    SlidingLaw, Transport, TwistingLaw,
};

/// The table of specialised scenes, the list the library's per-scene code is made from (the
/// `Scene` type, the fold, the batch kernels compiled, the per-contact steps):
/// `with_scenes!(then, [extra tokens])` expands to `then! { [extra tokens] row row ... }`, one
/// row per specialised scene (not `Generic`, code 0), in code order:
///
/// `{ #[doc = ...] Variant = code, "short name", (sliding, rolling, twisting law, family) }`
///
/// where `sliding` says whether the linear sliding law is on, the rolling law is a
/// [`RollingLaw`] variant (`None`, `Epsd` with the family's stiffness rule, or `Cdt` in either
/// form), the twisting law a [`TwistingLaw`] variant, and the family [`EXACT`], [`LAMMPS`] or
/// [`LIGGGHTS`] (the preset, transports and rolling conventions, see [`fold`]). A new scene is
/// a new row here, plus what docs/performance.md (*Adding a scene*) lists as kept by hand: the
/// `RSL_SCENE_*` constant (the header generator reads constants literally), a test model and
/// the benchmark's rows.
macro_rules! with_scenes {
    ($then:ident, $extra:tt) => {
        $then! { $extra
            {
                /// Objective preset, exact transport: linear sliding + EPSD rolling (given k,
                /// gamma, damping always, length form) + sds twisting, no energy bookkeeping.
                FullExact = 1, "full/exact", (true, Epsd, Sds, EXACT)
            }
            {
                /// LAMMPS_2021 preset (project-rescale transport): linear history + rolling sds
                /// + twisting sds, the hand-written C baseline's physics.
                FullLammps = 2, "full/lammps", (true, Epsd, Sds, LAMMPS)
            }
            {
                /// Objective, exact transport, linear sliding only.
                SlidingExact = 3, "sliding/exact", (true, None, None, EXACT)
            }
            {
                /// Objective, exact transport, linear sliding + EPSD rolling, no twisting.
                SlidingRollingExact = 4, "slide+roll/exact", (true, Epsd, None, EXACT)
            }
            {
                /// LAMMPS_2021 preset, linear history sliding only.
                SlidingLammps = 5, "sliding/lammps", (true, None, None, LAMMPS)
            }
            {
                /// LAMMPS_2021 preset, rolling sds + twisting sds, no sliding law.
                RollingTwistingLammps = 6, "roll+twist/lammps", (false, Epsd, Sds, LAMMPS)
            }
            {
                /// Objective preset, exact transport: EPSD rolling (given k, gamma, damping
                /// always, length form) + sds twisting, no sliding law.
                RollingTwistingExact = 7, "roll+twist/exact", (false, Epsd, Sds, EXACT)
            }
            {
                /// LAMMPS_2021 preset, linear history sliding + rolling sds, no twisting law.
                SlidingRollingLammps = 8, "slide+roll/lammps", (true, Epsd, None, LAMMPS)
            }
            {
                /// LAMMPS_2021 preset, linear history sliding + rolling sds + twisting marshall
                /// (the twisting coefficients derived from the sliding ones and the contact
                /// radius).
                FullLammpsMarshall = 9, "full/lammps+marshall", (true, Epsd, Marshall, LAMMPS)
            }
            {
                /// Objective preset, exact transport: linear sliding + EPSD rolling (as
                /// `FullExact`) + twisting marshall (the twisting coefficients derived from the
                /// sliding ones and the contact radius).
                FullExactMarshall = 10, "full/exact+marshall", (true, Epsd, Marshall, EXACT)
            }
            {
                /// Objective preset, exact transport: EPSD rolling only (as `FullExact`'s), no
                /// sliding or twisting law: rolling resistance added to a host that computes its
                /// own normal and tangential forces.
                RollingExact = 11, "roll/exact", (false, Epsd, None, EXACT)
            }
            {
                /// LAMMPS_2021 preset, project-rescale transport: EPSD rolling only (as
                /// `FullLammps`'s), no sliding or twisting law: LAMMPS' `pair granular` rolling
                /// sds on a host that computes its own normal and tangential forces.
                RollingLammps = 12, "roll/lammps", (false, Epsd, None, LAMMPS)
            }
            {
                /// LAMMPS_2021 preset, project-rescale transport: twisting sds only, no sliding
                /// or rolling law: LAMMPS' `pair granular` twisting sds on a host that computes
                /// its own normal and tangential forces.
                TwistingLammps = 13, "twist/lammps", (false, None, Sds, LAMMPS)
            }
            {
                /// LAMMPS_2021 preset, project-rescale transport: linear history sliding +
                /// twisting sds, no rolling law.
                SlidingTwistingLammps = 14, "slide+twist/lammps", (true, None, Sds, LAMMPS)
            }
            {
                /// Objective preset, exact transport: twisting sds only (as `FullExact`'s), no
                /// sliding or rolling law: twisting resistance added to a host that computes its
                /// own normal and tangential forces.
                TwistingExact = 15, "twist/exact", (false, None, Sds, EXACT)
            }
            {
                /// Objective preset, exact transport: linear sliding + twisting sds, no rolling
                /// law.
                SlidingTwistingExact = 16, "slide+twist/exact", (true, None, Sds, EXACT)
            }
            {
                /// LIGGGHTS_3_8 preset (`tangential history rolling_friction cdt`): linear
                /// sliding (projected, clipped on the spring alone) + the cdt rolling moment on
                /// the elastic normal force `k_n delta` (angle or length form), no twisting law.
                SlidingCdtLiggghts = 17, "slide+cdt/liggghts", (true, Cdt, None, LIGGGHTS)
            }
            {
                /// LIGGGHTS_3_8 preset (`tangential history rolling_friction epsd2`): linear
                /// sliding (projected, clipped on the spring alone) + EPSD rolling with the
                /// stiffness `k_t R_r^2` derived from the contact's sliding stiffness (angle or
                /// length form; given damping, dashpot below the limit), no twisting law.
                SlidingEpsd2Liggghts = 18, "slide+epsd2/liggghts", (true, Epsd, None, LIGGGHTS)
            }
        }
    };
}
pub(crate) use with_scenes;

/// What a family of scenes fixes besides the laws: the preset, the transport of each spring,
/// and the EPSD rolling law's form, stiffness rule and damping mode (unread for the other
/// rolling laws).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Family {
    preset: Preset,
    sliding_transport: Transport,
    rolling_transport: Transport,
    /// The EPSD law's form, or `None`: the model's, a run-time choice (one product per
    /// contact), which the family's EPSD rows then take in either form.
    rolling_form: Option<RollingForm>,
    /// Where the EPSD law's stiffness comes from (its damping is always given).
    rolling_stiffness: RollingStiffness,
    /// When the EPSD rolling dashpot acts (unread by the other rolling laws).
    rolling_damping_mode: DampingMode,
}

/// The objective scenes: exact transport of both springs, length form, given stiffness,
/// dashpot always.
pub(crate) const EXACT: Family = Family {
    preset: Preset::Objective,
    sliding_transport: Transport::Exact,
    rolling_transport: Transport::Exact,
    rolling_form: Some(RollingForm::Length),
    rolling_stiffness: RollingStiffness::Given,
    rolling_damping_mode: DampingMode::Always,
};
/// The LAMMPS scenes: the LAMMPS_2021 preset, project-rescale transport of both springs,
/// length form, given stiffness, dashpot always.
pub(crate) const LAMMPS: Family = Family {
    preset: Preset::Lammps2021,
    sliding_transport: Transport::ProjectRescale,
    rolling_transport: Transport::ProjectRescale,
    rolling_form: Some(RollingForm::Length),
    rolling_stiffness: RollingStiffness::Given,
    rolling_damping_mode: DampingMode::Always,
};
/// The LIGGGHTS scenes: the LIGGGHTS_3_8 preset as `Model::with_preset` sets it up (the
/// sliding spring projected, the rolling history not transported, the dashpot only below the
/// limit), with LIGGGHTS' `epsd2` rule for the EPSD stiffness (`k_t R_r^2`; its `epsd` and
/// `epsd3` rules need masses, which a batch does not take). The rolling form is the model's: a
/// batch takes no per-contact `eta`, so the length form (one `mu_r`, times the rolling radius
/// `R_eff`) is how a host gives each contact of unequal spheres LIGGGHTS' limit `mu_r R_eff f`,
/// and the angle form (LIGGGHTS' own, which the length form's EPSD spring follows only to about
/// 5e-7 once the normal turns) serves pairs of one `R_eff`.
pub(crate) const LIGGGHTS: Family = Family {
    preset: Preset::Liggghts38,
    sliding_transport: Transport::Project,
    rolling_transport: Transport::None,
    rolling_form: None,
    rolling_stiffness: RollingStiffness::Epsd2,
    rolling_damping_mode: DampingMode::BelowLimit,
};

/// The laws a scene fixes: whether the linear sliding law is on, the rolling law, the
/// twisting law, and the family.
type SceneLaws = (bool, RollingLaw, TwistingLaw, Family);

/// `Scene`, its list, names, codes and laws from the rows of [`with_scenes`].
macro_rules! define_scenes {
    ([] $({
        $(#[$doc:meta])* $scene:ident = $code:literal, $name:literal,
        ($sliding:literal, $rolling:ident, $twisting:ident, $family:ident)
    })*) => {
        /// The specialised configurations (the const parameter `S` of the kernels is `Scene as
        /// u8`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        #[repr(u8)]
        pub enum Scene {
            /// Any model: decisions at run time.
            Generic = 0,
            $($(#[$doc])* $scene = $code,)*
        }

        impl Scene {
            /// Every scene, in code order.
            pub const ALL: [Scene; [0u8 $(, $code)*].len()] = [Scene::Generic $(, Scene::$scene)*];

            /// A short name (benchmark tables).
            pub fn name(self) -> &'static str {
                match self {
                    Scene::Generic => "generic",
                    $(Scene::$scene => $name,)*
                }
            }

            /// The scene of a code (`Generic` for an unknown one); a `const fn` so that a
            /// kernel's const parameter names its scene at compile time.
            #[inline(always)]
            pub const fn from_code(code: u8) -> Scene {
                match code {
                    $($code => Scene::$scene,)*
                    _ => Scene::Generic,
                }
            }

            /// The laws the scene fixes (`None` for `Generic`, which fixes none).
            #[inline(always)]
            const fn laws(self) -> Option<SceneLaws> {
                match self {
                    Scene::Generic => None,
                    $(Scene::$scene => Some(($sliding, RollingLaw::$rolling, TwistingLaw::$twisting, $family)),)*
                }
            }
        }
    };
}
with_scenes!(define_scenes, []);

impl Scene {
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
    let Some((sliding, rolling, twisting, family)) = scene.laws() else {
        return m;
    };
    m.sliding.law = if sliding {
        SlidingLaw::Linear
    } else {
        SlidingLaw::None
    };
    m.rolling.law = rolling;
    // The cdt law keeps the model's form (a run-time choice of one product, `eta f` or
    // `mu_r R_r f`), and so does the EPSD law of a family without a form: a batch takes no
    // per-contact `eta`, so the length form is how a host gives each contact LIGGGHTS'
    // `mu_r R_eff` (the rolling radius) with one `mu_r`.
    if rolling == RollingLaw::Epsd {
        if let Some(form) = family.rolling_form {
            m.rolling.form = form;
        }
        m.rolling.stiffness_rule = family.rolling_stiffness;
        m.rolling.damping_rule = RollingDamping::Given;
        m.rolling.damping_mode = family.rolling_damping_mode;
    }
    m.twisting.law = twisting;
    m.sliding_transport = family.sliding_transport;
    m.rolling_transport = family.rolling_transport;
    m.preset = family.preset;
    m.track_energy = false;
    m.torsion_torque = false;
    m.contact_point_sliding = false;
    m
}
