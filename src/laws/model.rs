//! The configuration of a contact model: which sliding, rolling and twisting laws are on, their
//! parameters, the history transport scheme, and the compatibility preset (models.md).

use crate::error::Error;
use crate::geometry::{BranchRule, GeometryOptions, RollingRadiusRule};
use crate::laws::spring::Storage;

/// Sliding (tangential force) law.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SlidingLaw {
    /// No tangential force.
    #[default]
    None,
    /// Spring-dashpot-slider on the sliding spring `xi_s` (LAMMPS linear_history).
    Linear,
}

/// What the sliding spring stores, hence what happens to it when its stiffness changes from one
/// step to the next (per-contact `k_t`, e.g. Hertz-Mindlin's `8 G a`). Every history gives the
/// same loads while `k_t` is constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SlidingHistory {
    /// A displacement `xi` (length); load `-k_t xi` with the step's `k_t`, so the spring keeps
    /// its stretch and its load follows `k_t` (LAMMPS `linear_history`, `mindlin`).
    #[default]
    Displacement,
    /// The elastic force itself, built incrementally: `F += -k_t v dt` with the step's `k_t`,
    /// so the spring keeps its load (LAMMPS `mindlin/force`; YADE's shear force).
    Force,
    /// As `Displacement`, and when `k_t` falls below the previous step's, the stored
    /// displacement is first scaled by `k_t / k_t,previous` (LAMMPS `mindlin_rescale`, whose
    /// `a / a_previous` is that ratio for `k_t = 8 G a`).
    DisplacementRescaled,
    /// As `Force`, with the stored force scaled as `DisplacementRescaled` scales the
    /// displacement (LAMMPS `mindlin_rescale/force`).
    ForceRescaled,
}

impl SlidingHistory {
    /// What the spring stores.
    pub fn storage(self) -> Storage {
        match self {
            SlidingHistory::Displacement | SlidingHistory::DisplacementRescaled => {
                Storage::Displacement
            }
            SlidingHistory::Force | SlidingHistory::ForceRescaled => Storage::Load,
        }
    }

    /// Whether the stored spring shrinks with a falling stiffness.
    pub fn rescaled(self) -> bool {
        matches!(
            self,
            SlidingHistory::DisplacementRescaled | SlidingHistory::ForceRescaled
        )
    }
}

/// Rolling resistance law (models.md section 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RollingLaw {
    /// No rolling resistance.
    #[default]
    None,
    /// Type A: constant moment `mu_r R_r f_n` opposing `(w1 - w2)_t`, zero below a rate threshold.
    Cdt,
    /// Type B: viscous `F_r = -gamma_r v_r`, limited by `mu_r f_n`.
    Viscous,
    /// Type C: elastic-plastic spring-dashpot on the rolling spring.
    Epsd,
}

/// Twisting resistance law.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TwistingLaw {
    /// No twisting resistance.
    #[default]
    None,
    /// Spring-dashpot-slider on the twist angle, moment `M_tw n` on body 1.
    Sds,
    /// Marshall 2009: `k_tw = k_t a^2/2`, `gamma_tw = gamma_t a^2/2`, `mu_tw = 2/3 a mu_s`.
    Marshall,
}

/// How the rolling parameters (and the rolling spring stored in the state) are expressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RollingForm {
    /// LAMMPS style: `F_r = -k_r xi_r - gamma_r v_r` with `xi_r` a length, limit `mu_r f_n`
    /// (`mu_r` dimensionless), moment `R_r n x F_r`.
    #[default]
    Length,
    /// YADE style: `M = -k_theta theta_r - c_theta (w1 - w2)_t` with `theta_r` in radians,
    /// limit `eta f_n` (`eta` a length).
    Angle,
}

/// Where the EPSD rolling stiffness comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RollingStiffness {
    /// The model's `stiffness` parameter (k_r or k_theta by the form).
    #[default]
    Given,
    /// `k_theta = 2.25 k_n mu_r^2 R_r^2` (LIGGGHTS epsd).
    Epsd,
    /// `k_theta = k_t R_r^2` (LIGGGHTS epsd2).
    Epsd2,
    /// `k_theta = c k_n mu_r^2 R_r^2` with `c` the model's `stiffness_factor` (LIGGGHTS epsd3).
    Epsd3,
}

/// Where the EPSD rolling damping comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RollingDamping {
    /// The model's `damping` parameter (gamma_r or c_theta by the form).
    #[default]
    Given,
    /// A damping ratio `eta_r` (the `damping` parameter): `c_theta = eta_r 2 sqrt(I_r k_theta)`,
    /// `I_r = 1/(1/(I1 + m1 R1^2) + 1/(I2 + m2 R2^2))`; needs masses and inertias per call.
    Ratio,
}

/// When a spring's dashpot acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DampingMode {
    /// Always; the limit applies to spring + dashpot (LAMMPS, models.md section 2).
    #[default]
    Always,
    /// Only below the limit, which applies to the spring alone (LIGGGHTS).
    BelowLimit,
}

/// History transport scheme (models.md section 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Transport {
    /// Minimal rotation `n_old -> n_new`, then rotation about `n_new` by `dt w_rbs` (default).
    #[default]
    Exact,
    /// Project on the new tangent plane and rescale to the old length (LAMMPS 2021).
    ProjectRescale,
    /// `u -= u x (n_old x n_new)`; `u -= u x (dt/2 ((w1 + w2) . n_old) n_old)` (YADE 2023).
    FirstOrder,
    /// Project on the tangent plane, no rescale (LIGGGHTS 3.8 sliding).
    Project,
    /// No transport.
    None,
}

/// Compatibility preset: reproduce a public code's step semantics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Preset {
    /// This library's objective definitions (default).
    #[default]
    Objective,
    /// LAMMPS 29 Sep 2021 `pair_style granular`.
    Lammps2021,
    /// YADE 2023.02a CohFrict moment law / Mindlin with moments.
    Yade2023,
    /// LIGGGHTS-PUBLIC 3.8.0 `rolling_friction cdt|epsd|epsd2|epsd3`.
    Liggghts38,
}

/// Parameters of the sliding law (force per length, force time per length, dimensionless).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SlidingParams {
    /// Which law.
    pub law: SlidingLaw,
    /// `k_t` (force/length), >= 0.
    pub stiffness: f64,
    /// `gamma_t` (force time/length), >= 0.
    pub damping: f64,
    /// Friction coefficient `mu_s` (dimensionless), >= 0; +inf for no limit.
    pub friction: f64,
    /// What the spring stores (YADE_2023: its force; every other preset: a displacement by
    /// default).
    pub history: SlidingHistory,
}

/// Parameters of the rolling law. Units follow [`RollingForm`].
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct RollingParams {
    /// Which law.
    pub law: RollingLaw,
    /// Length or angle parameterisation (also the unit of the stored rolling spring).
    pub form: RollingForm,
    /// `k_r` (force/length) or `k_theta` (moment/rad), >= 0; used with [`RollingStiffness::Given`].
    pub stiffness: f64,
    /// `gamma_r`, `c_theta`, or the damping ratio `eta_r` with [`RollingDamping::Ratio`]; >= 0.
    pub damping: f64,
    /// `mu_r` (dimensionless, length form) or `eta` (a length, angle form), >= 0; +inf for no
    /// limit (not for cdt).
    pub friction: f64,
    /// cdt: relative rolling rate `|(w1 - w2)_t|` (rad/time; `|w1 - w2|` with
    /// [`Model::torsion_torque`]) below which the moment is zero.
    pub rate_threshold: f64,
    /// EPSD stiffness rule.
    pub stiffness_rule: RollingStiffness,
    /// EPSD3 factor `c` (> 0 when used).
    pub stiffness_factor: f64,
    /// EPSD damping rule.
    pub damping_rule: RollingDamping,
    /// EPSD damping mode.
    pub damping_mode: DampingMode,
}

/// Parameters of the twisting law (`sds`; `marshall` derives them from the sliding law).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TwistingParams {
    /// Which law.
    pub law: TwistingLaw,
    /// `k_tw` (moment/rad), >= 0.
    pub stiffness: f64,
    /// `gamma_tw` (moment time/rad), >= 0.
    pub damping: f64,
    /// `mu_tw` (a length: the moment limit is `mu_tw f_n`), >= 0; +inf for no limit.
    pub friction: f64,
}

/// A complete contact model. `Model::default()` has every law off, exact transport, the
/// objective definitions and energy bookkeeping off.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Model {
    /// Branch rule and rolling radius of the kinematics.
    pub geometry: GeometryOptions,
    /// Sliding law.
    pub sliding: SlidingParams,
    /// Rolling law.
    pub rolling: RollingParams,
    /// Twisting law.
    pub twisting: TwistingParams,
    /// Transport of the sliding spring (and of YADE's vector twist).
    pub sliding_transport: Transport,
    /// Transport of the rolling spring.
    pub rolling_transport: Transport,
    /// Compatibility preset.
    pub preset: Preset,
    /// Compute the energy terms of each step (costs a few flops per spring).
    pub track_energy: bool,
    /// LIGGGHTS' `torsionTorque on` (LIGGGHTS_3_8 preset, angle form, cdt and EPSD rolling
    /// laws): the rolling law acts on the whole relative spin `w1 - w2` instead of its
    /// tangential part `(w1 - w2)_t`, so the rolling moment gets a component about the normal
    /// (a twisting resistance bounded by the same rolling limit). Off by default, as in LIGGGHTS.
    pub torsion_torque: bool,
    /// YADE's `avoidGranularRatcheting = False` (on `Ig2_Sphere_Sphere_ScGeom6D`; YADE_2023
    /// preset only): the sliding spring is driven by the relative velocity of the material
    /// points at the contact point (arms `R_k - delta/2`, the decomposition's sliding
    /// velocity) instead of YADE's default incident velocity (full radii, `(v2 - v1)` scaled
    /// by `(R1 + R2)/d`). Off by default, as YADE's flag is True by default.
    pub contact_point_sliding: bool,
}

/// Why YADE's avoidGranularRatcheting switch is refused for another preset.
pub const AVOID_RATCHETING_NEEDS_YADE: &str =
    "avoidGranularRatcheting is YADE's switch: it needs the YADE_2023 preset";

/// A limit coefficient: finite and >= 0, or +inf for "no limit".
fn check_friction(value: f64, name: &str) -> Result<(), Error> {
    if value == f64::INFINITY || (value.is_finite() && value >= 0.0) {
        Ok(())
    } else {
        Err(Error::InvalidParameter(format!(
            "{name} = {value} must be >= 0 (or +inf for no limit)"
        )))
    }
}

fn check_param(value: f64, name: &str, strictly_positive: bool) -> Result<(), Error> {
    let ok = value.is_finite()
        && if strictly_positive {
            value > 0.0
        } else {
            value >= 0.0
        };
    if ok {
        Ok(())
    } else {
        let need = if strictly_positive { "> 0" } else { ">= 0" };
        Err(Error::InvalidParameter(format!(
            "{name} = {value} must be finite and {need}"
        )))
    }
}

impl SlidingParams {
    /// Checks the parameters, naming the first bad one.
    pub fn validate(&self) -> Result<(), Error> {
        check_param(self.stiffness, "sliding stiffness k_t", false)?;
        check_param(self.damping, "sliding damping gamma_t", false)?;
        check_friction(self.friction, "sliding friction mu_s")
    }
}

impl RollingParams {
    /// Whether the stiffness rule derives the rolling stiffness from `mu_r` (LIGGGHTS' `epsd`
    /// and `epsd3`): the coefficient must then be finite.
    pub fn stiffness_from_friction(&self) -> bool {
        matches!(
            self.stiffness_rule,
            RollingStiffness::Epsd | RollingStiffness::Epsd3
        )
    }

    /// Checks the parameters, naming the first bad one.
    pub fn validate(&self) -> Result<(), Error> {
        check_param(self.stiffness, "rolling stiffness", false)?;
        check_param(self.damping, "rolling damping", false)?;
        if self.law == RollingLaw::Cdt {
            check_param(self.friction, "rolling friction (cdt)", false)?;
        } else if self.law == RollingLaw::Epsd && self.stiffness_from_friction() {
            // The stiffness is derived from mu_r: +inf would make it infinite.
            check_param(
                self.friction,
                "rolling friction (epsd/epsd3 stiffness rule)",
                false,
            )?;
        } else {
            check_friction(self.friction, "rolling friction")?;
        }
        check_param(self.rate_threshold, "rolling rate_threshold", false)?;
        if self.stiffness_rule == RollingStiffness::Epsd3 {
            check_param(
                self.stiffness_factor,
                "rolling stiffness_factor (epsd3)",
                true,
            )?;
        } else {
            check_param(self.stiffness_factor, "rolling stiffness_factor", false)?;
        }
        Ok(())
    }
}

impl TwistingParams {
    /// Checks the parameters, naming the first bad one.
    pub fn validate(&self) -> Result<(), Error> {
        if self.law == TwistingLaw::Marshall {
            // Marshall derives its coefficients from the sliding law: these are never read.
            return Ok(());
        }
        check_param(self.stiffness, "twisting stiffness k_tw", false)?;
        check_param(self.damping, "twisting damping gamma_tw", false)?;
        check_friction(self.friction, "twisting friction mu_tw")
    }
}

impl Model {
    /// Whether a step reads the normal stiffness `k_n` (EPSD-derived rolling stiffness,
    /// LIGGGHTS' cdt): it must then be finite and > 0.
    pub fn needs_normal_stiffness(&self) -> bool {
        let r = &self.rolling;
        (r.law == RollingLaw::Epsd && r.stiffness_from_friction()) || self.liggghts_cdt()
    }

    /// Whether the steps keep the springs' stiffnesses of the previous step in the state
    /// (`ContactState::model_memory`): for the stiffness-change energy (`track_energy`) and
    /// the rescaled sliding histories. Never with YADE_2023, whose state holds its off-axis
    /// twisting moment there.
    #[inline(always)]
    pub fn stiffness_memory(&self) -> bool {
        self.preset != Preset::Yade2023 && (self.track_energy || self.sliding.history.rescaled())
    }

    /// Whether the rolling law is LIGGGHTS' cdt, whose moment uses the elastic normal force
    /// `k_n delta` (not the limits' force).
    pub fn liggghts_cdt(&self) -> bool {
        self.rolling.law == RollingLaw::Cdt && self.preset == Preset::Liggghts38
    }

    /// The model of a preset with every law off; the preset fixes the conventions (branch rule,
    /// rolling radius, transport, rolling form, damping mode) that its code uses.
    pub fn with_preset(preset: Preset) -> Model {
        let mut m = Model {
            preset,
            ..Model::default()
        };
        match preset {
            Preset::Objective => {}
            Preset::Lammps2021 => {
                m.geometry = GeometryOptions {
                    branch_rule: BranchRule::Midplane,
                    rolling_radius: RollingRadiusRule::Effective,
                };
                m.sliding_transport = Transport::ProjectRescale;
                m.rolling_transport = Transport::ProjectRescale;
            }
            Preset::Yade2023 => {
                m.geometry = GeometryOptions {
                    branch_rule: BranchRule::Midplane,
                    rolling_radius: RollingRadiusRule::Effective,
                };
                m.sliding_transport = Transport::FirstOrder;
                m.rolling_transport = Transport::FirstOrder;
                m.rolling.form = RollingForm::Angle;
                m.sliding.history = SlidingHistory::Force;
            }
            Preset::Liggghts38 => {
                m.geometry = GeometryOptions {
                    branch_rule: BranchRule::Midplane,
                    rolling_radius: RollingRadiusRule::Effective,
                };
                m.sliding_transport = Transport::Project;
                m.rolling_transport = Transport::None;
                m.rolling.form = RollingForm::Angle;
                m.rolling.damping_mode = DampingMode::BelowLimit;
            }
        }
        m
    }

    /// Checks every parameter, and that the model's switches fit its preset.
    pub fn validate(&self) -> Result<(), Error> {
        self.sliding.validate()?;
        self.rolling.validate()?;
        self.twisting.validate()?;
        if self.preset == Preset::Yade2023 && self.sliding.history != SlidingHistory::Force {
            return Err(Error::InvalidParameter(
                "the YADE_2023 preset's sliding spring stores its shear force, as YADE does: \
                 its history cannot be changed"
                    .into(),
            ));
        }
        if self.contact_point_sliding && self.preset != Preset::Yade2023 {
            return Err(Error::InvalidParameter(AVOID_RATCHETING_NEEDS_YADE.into()));
        }
        if self.torsion_torque {
            if self.preset != Preset::Liggghts38 {
                return Err(Error::InvalidParameter(
                    "torsion torque is LIGGGHTS' switch: it needs the LIGGGHTS_3_8 preset".into(),
                ));
            }
            if self.rolling.form != RollingForm::Angle {
                return Err(Error::InvalidParameter(
                    "torsion torque needs the angle form of the rolling law (the length form's \
                     rolling velocity has no part about the normal)"
                        .into(),
                ));
            }
        }
        Ok(())
    }
}
