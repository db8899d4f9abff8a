//! One step of one contact (models.md section 2): transport the histories, compute the rates,
//! step the sliding, rolling and twisting laws, and return the loads on both bodies with the
//! energy terms. One generic implementation for every [`Real`] type; a law that is off costs
//! nothing (its branch is decided once per call from the model, never per lane).

use crate::decompose::{
    decompose_pair_with_geometry, decompose_wall_with_geometry, Parts, Sphere, Wall,
};
use crate::geometry::ContactGeometry;
use crate::geometry::{pair_geometry_unchecked, wall_geometry_unchecked};
use crate::laws::model::{
    DampingMode, Model, RollingDamping, RollingForm, RollingLaw, RollingStiffness, SlidingLaw,
    TwistingLaw,
};
use crate::laws::presets::{Conventions, SlidingRate, TensionLimit};
use crate::laws::spring::{
    scalar_spring, vector_spring, ClipRule, SpringCoefficients, SpringEnergy, Storage,
    VectorSpringStep,
};
use crate::laws::transport::{transport, Frame, RescaleWhen};
use crate::loads::{contact_loads_from_couple, ContactLoads};
use simba::simd::SimdBool;

use crate::scalar::{
    cross, dot, lit, mask, norm, norm_squared, rescale_overflowed, select, select3, tangential,
    Real, Vec3,
};

/// Per-call inputs of a contact step besides the bodies.
#[derive(Clone, Copy, Debug)]
pub struct StepInput<T: Real> {
    /// Normal force `f_n` on the contact, signed: compressive positive, tensile (cohesive,
    /// or a dashpot pulling during unloading) negative. Applied to the bodies as given (body 1
    /// gets `-f_n n`), except in YADE CohFrict's tensile slip (see `shear_adhesion`). The
    /// limits use `limit_force` when given, else the preset's rule: `max(f_n, 0)` (objective,
    /// YADE_2023) or `|f_n|` (LAMMPS_2021, LIGGGHTS_3_8).
    pub normal_force: T,
    /// Time step (> 0).
    pub dt: T,
    /// Normal stiffness `k_n`: needed by EPSD-derived rolling stiffness and LIGGGHTS' cdt.
    pub normal_stiffness: T,
    /// Contact radius `a` for Marshall twisting; `0` means `sqrt(delta R_eff)` (LAMMPS).
    pub contact_radius: T,
    /// Mass of body 1 (damping-ratio rolling damping only).
    pub mass1: T,
    /// Mass of body 2 (ignored for a wall); +inf for a fixed body.
    pub mass2: T,
    /// Moment of inertia of body 1 (damping-ratio rolling damping only).
    pub inertia1: T,
    /// Moment of inertia of body 2 (ignored for a wall); +inf for a fixed body.
    pub inertia2: T,
    /// Per-contact sliding stiffness replacing the model's `k_t` (e.g. Hertz-Mindlin `8 G a`).
    pub sliding_stiffness: Option<T>,
    /// Per-contact sliding damping replacing the model's `gamma_t`.
    pub sliding_damping: Option<T>,
    /// Per-contact sliding friction coefficient replacing the model's `mu_s` (also read by
    /// Marshall twisting), e.g. a material pair's.
    pub sliding_friction: Option<T>,
    /// Per-contact rolling stiffness (`k_r` or `k_theta` by the form) replacing the model's
    /// (and any derived EPSD rule).
    pub rolling_stiffness: Option<T>,
    /// Per-contact rolling damping (`gamma_r` or `c_theta`, or the ratio with `Ratio`).
    pub rolling_damping: Option<T>,
    /// Per-contact rolling limit coefficient (`mu_r`, or `eta` in the angle form), e.g. YADE's
    /// `min(etaRoll_i R_i)` or LIGGGHTS' `mu_r R_eff` in polydisperse scenes.
    pub rolling_friction: Option<T>,
    /// Per-contact twisting stiffness (`sds`).
    pub twisting_stiffness: Option<T>,
    /// Per-contact twisting damping (`sds`).
    pub twisting_damping: Option<T>,
    /// Per-contact twisting limit length `mu_tw` (`sds`).
    pub twisting_friction: Option<T>,
    /// The force (>= 0) the limits use instead of the preset's rule on `normal_force`: e.g.
    /// LAMMPS' `Fncrit` (`|F_ne + 2 F_pulloff|` with its JKR model, `|F_ne|` with DMT in LAMMPS
    /// 20220106), an elastic normal force, the compressive part plus a cohesive offset.
    pub limit_force: Option<T>,
    /// Shear adhesion `c_s` of a cohesive bond (a force, >= 0; +inf: no sliding limit while
    /// bonded): the sliding limit becomes `max(0, c_s + mu F)`. `F` is `limit_force` when
    /// given, else for YADE_2023 the signed `f_n` (CohFrict's `shearAdhesion + Fn tan(phi)`),
    /// else the preset's limit force. With YADE_2023 and no `limit_force`, the rolling and
    /// twisting limits then use `|f_n|` (CohFrict's `normalForce.norm()`), and a step whose
    /// sliding limit is reached while `f_n < 0` applies no normal force and has zero rolling and
    /// twisting limits (CohFrict sets `normalForce = 0` there). Other limits are unchanged.
    pub shear_adhesion: Option<T>,
    /// The bond is fragile (needs `shear_adhesion`): when the trial sliding load exceeds the
    /// adhesive limit, the bond breaks in this step and the limit is recomputed without the
    /// adhesion (YADE's `fragile` CohFrictPhys); [`StepOutput::bond_broken`] reports it, and the
    /// host drops the adhesion from the next step on.
    pub fragile_bond: bool,
    /// The setup pass LAMMPS and LIGGGHTS make at the start of every run: no increments (LIGGGHTS:
    /// one rolling increment), and the state is not written (LAMMPS: its clip writes it). YADE
    /// has none (its first step increments); for the objective and YADE presets it gives the
    /// loads of the stored springs.
    pub setup: bool,
}

impl<T: Real> StepInput<T> {
    /// An input with `f_n` and `dt` and every optional field empty.
    pub fn new(normal_force: T, dt: T) -> Self {
        StepInput {
            normal_force,
            dt,
            normal_stiffness: T::zero(),
            contact_radius: T::zero(),
            mass1: T::zero(),
            mass2: T::zero(),
            inertia1: T::zero(),
            inertia2: T::zero(),
            sliding_stiffness: None,
            sliding_damping: None,
            sliding_friction: None,
            rolling_stiffness: None,
            rolling_damping: None,
            rolling_friction: None,
            twisting_stiffness: None,
            twisting_damping: None,
            twisting_friction: None,
            limit_force: None,
            shear_adhesion: None,
            fragile_bond: false,
            setup: false,
        }
    }
}

/// The history a host stores per contact. All zero is a fresh contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactState<T: Real> {
    /// Sliding spring: `xi_s` (length); YADE preset: the elastic shear force on body 1.
    pub sliding_spring: Vec3<T>,
    /// Rolling spring: `xi_r` (length) in the length form, `theta_r` (rad) in the angle form;
    /// YADE and LIGGGHTS presets: the elastic rolling moment on body 1.
    pub rolling_spring: Vec3<T>,
    /// Twisting angle `theta_tw` (rad); YADE preset: the twisting moment on body 1 along the
    /// previous normal.
    pub twisting_angle: T,
    /// What the model remembers besides the springs. YADE preset: the part of its vector
    /// twisting moment off the previous normal. Every other preset, when the model tracks
    /// energy or rescales its sliding history ([`Model::stiffness_memory`]): the stiffnesses
    /// the sliding (`x`), rolling (`y`) and twisting (`z`) springs had in the previous step
    /// (zero for a law that is off), which the stiffness-change energy and the rescaled
    /// histories compare the step's with; zero otherwise (carried unchanged).
    pub model_memory: Vec3<T>,
    /// Normal at the previous step; zero before the first step.
    pub previous_normal: Vec3<T>,
}

impl<T: Real> Default for ContactState<T> {
    fn default() -> Self {
        ContactState {
            sliding_spring: Vec3::zeros(),
            rolling_spring: Vec3::zeros(),
            twisting_angle: T::zero(),
            model_memory: Vec3::zeros(),
            previous_normal: Vec3::zeros(),
        }
    }
}

/// Which fields of a [`ContactState`] a step can change: a step leaves every field marked
/// `false` bit for bit as it found it. A batch kernel uses this to skip writing those fields
/// back, and to skip testing them again after the step (they were already tested as inputs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WrittenFields {
    /// The sliding spring: the linear sliding law is on.
    pub sliding_spring: bool,
    /// The rolling spring: the rolling law is EPSD (type C, the only one with a spring).
    pub rolling_spring: bool,
    /// The twisting angle: a twisting law is on.
    pub twisting_angle: bool,
    /// The model memory: a twisting law is on and the preset transports the twisting moment as
    /// a vector (YADE), or the model keeps the previous stiffnesses
    /// ([`Model::stiffness_memory`]).
    pub model_memory: bool,
    /// The previous normal: always (every step stores its normal).
    pub previous_normal: bool,
}

/// The [`WrittenFields`] of a step with `model`: exact for an ordinary step, and still a
/// superset for a setup step (`StepInput::setup`), which can write fewer.
#[inline(always)]
pub fn written_fields(model: &Model) -> WrittenFields {
    let twisting_on = model.twisting.law != TwistingLaw::None;
    WrittenFields {
        sliding_spring: model.sliding.law == SlidingLaw::Linear,
        rolling_spring: model.rolling.law == RollingLaw::Epsd,
        twisting_angle: twisting_on,
        model_memory: (twisting_on && model.preset.conventions().twist_vector)
            || model.stiffness_memory(),
        previous_normal: true,
    }
}

/// Energy terms of one step, split by spring (zero unless the model tracks energy).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepEnergy<T> {
    /// Sliding spring: elastic energy after the step, dashpot and slider dissipation.
    pub sliding: SpringEnergy<T>,
    /// Rolling law (cdt reports its dissipation as slider, viscous as dashpot).
    pub rolling: SpringEnergy<T>,
    /// Twisting spring.
    pub twisting: SpringEnergy<T>,
    /// Change of elastic energy caused by the transport of the histories this step (zero to
    /// rounding for `exact` and `project_rescale`).
    pub transport: T,
    /// Elastic energy the springs gained (negative: lost) because their stiffness changed
    /// since the previous step (per-contact `k_t`, Marshall's `k_t a^2 / 2`, a rolling
    /// stiffness derived from `k_n`) or a rescaled history shrank them, with no work done:
    /// the springs' energy at the start of this step with this step's stiffnesses less their
    /// energy at the end of the previous one. Zero without [`Model::stiffness_memory`].
    pub stiffness: T,
}

impl<T: Copy> StepEnergy<T> {
    /// Every term, in the order sliding (elastic, dashpot, slider), rolling (same), twisting
    /// (same), transport, stiffness change.
    pub fn terms(&self) -> [T; 11] {
        let (s, r, t) = (&self.sliding, &self.rolling, &self.twisting);
        [
            s.elastic,
            s.dashpot,
            s.slider,
            r.elastic,
            r.dashpot,
            r.slider,
            t.elastic,
            t.dashpot,
            t.slider,
            self.transport,
            self.stiffness,
        ]
    }
}

/// The result of one contact step.
#[derive(Clone, Copy, Debug)]
pub struct StepOutput<T: Real> {
    /// Forces and torques on both bodies (normal force included).
    pub loads: ContactLoads<T>,
    /// Sliding force `F_t` on body 1.
    pub sliding_force: Vec3<T>,
    /// Rolling moment on body 1 (body 2 gets its opposite).
    pub rolling_moment: Vec3<T>,
    /// Twisting moment on body 1, `M_tw n` (YADE: its vector moment); body 2 gets the opposite.
    pub twisting_torque: Vec3<T>,
    /// Energy terms.
    pub energy: StepEnergy<T>,
    /// Lanes where the sliding, rolling and twisting limits were reached.
    pub slipped: [T::SimdBool; 3],
    /// Lanes where a fragile bond (`StepInput::fragile_bond`) broke this step.
    pub bond_broken: T::SimdBool,
}

/// Body 2 of a contact.
#[derive(Clone, Copy, Debug)]
pub enum Partner<'a, T: Real> {
    /// A sphere.
    Sphere(&'a Sphere<T>),
    /// A flat wall (its `normal` must be unit here).
    Wall(&'a Wall<T>),
}

/// `(1/2) k (|after|^2 - |before|^2)` for a displacement, `(|after|^2 - |before|^2)/(2k)` for a
/// stored load: the elastic energy the transport created.
#[inline(always)]
fn transport_energy<T: Real>(storage: Storage, k: T, before: &Vec3<T>, after: &Vec3<T>) -> T {
    let diff = (norm_squared(after) - norm_squared(before)) * lit(0.5);
    match storage {
        Storage::Displacement => k * diff,
        Storage::Load => {
            let positive = k.simd_gt(T::zero());
            select(positive, diff / select(positive, k, T::one()), T::zero())
        }
    }
}

/// The elastic energy of a stored spring with stiffness `k`: `(1/2) k |xi|^2` for a
/// displacement, `|F|^2 / (2 k)` for a stored load (zero where `k = 0`).
#[inline(always)]
fn stored_energy<T: Real>(storage: Storage, k: T, spring: &Vec3<T>) -> T {
    let half = norm_squared(spring) * lit(0.5);
    match storage {
        Storage::Displacement => k * half,
        Storage::Load => {
            let positive = k.simd_gt(T::zero());
            select(positive, half / select(positive, k, T::one()), T::zero())
        }
    }
}

/// The rolling moment on body 1 of a rolling-law load: the load itself in the angle form
/// (a moment, N m), `R_r n x load` in the length form (a force, N, acting at arm `R_r`).
#[inline(always)]
fn rolling_moment_of<T: Real>(load: &Vec3<T>, n: &Vec3<T>, r_r: T, angle: bool) -> Vec3<T> {
    if angle {
        *load
    } else {
        cross(n, load) * r_r
    }
}

/// `v / |v|` (zero for a zero `v`), from a rescaled copy where `|v|^2` overflowed (else that
/// lane's direction, hence its moment, would be zero). Returns the direction and `|v|`.
#[inline(always)]
fn unit_and_norm<T: Real>(v: &Vec3<T>) -> (Vec3<T>, T) {
    let norm = norm(v);
    let (v, length, norm) = match rescale_overflowed(v, norm) {
        None => (*v, norm, norm),
        Some(r) => (v / r.divisor, r.scaled_norm, r.norm),
    };
    let safe = select(length.simd_gt(T::zero()), length, T::one());
    (v / safe, norm)
}

/// A limit `coefficient * force` where `+inf` in either factor means "no limit": `0 * inf`
/// (NaN) becomes the coefficient itself, so an infinite coefficient stays +inf at zero force
/// and a zero coefficient stays 0 under an infinite limit force. Both factors are >= 0 (not
/// NaN); every other product is returned bit for bit.
#[inline(always)]
fn limit_of<T: Real>(coefficient: T, force: T) -> T {
    let product = coefficient * force;
    select(product.simd_ne(product), coefficient, product)
}

/// The sliding limit of a bond with shear adhesion `adhesion` (>= 0, may be +inf):
/// `max(0, adhesion + mu force)` for a signed `force` (a tensile force lowers it). `0 * inf` in
/// the friction term is `mu` (as [`limit_of`]); `+inf - inf` (infinite adhesion, infinite
/// friction under tension) is +inf, no limit.
#[inline(always)]
fn adhesive_limit<T: Real>(adhesion: T, mu: T, force: T) -> T {
    let sum = adhesion + limit_of(mu, force);
    let sum = select(sum.simd_ne(sum), lit(f64::INFINITY), sum);
    select(sum.simd_lt(T::zero()), T::zero(), sum)
}

/// Marshall twisting's limit coefficient `2/3 mu_s` (a length once times the contact radius):
/// the model's in one rounding, or a per-contact `mu_s` times `2/3` (the same bits in double).
#[inline(always)]
fn marshall_friction<T: Real>(model: &Model, input: &StepInput<T>) -> T {
    match input.sliding_friction {
        None => lit(2.0 / 3.0 * model.sliding.friction),
        Some(mu) => lit::<T>(2.0 / 3.0) * mu,
    }
}

/// The EPSD rolling spring's coefficients (stiffness and damping in the law's form, the limit
/// on the limits' force `f_limit`) and its spring carried into the current frame: all the law
/// needs before its rate. `r_r` is the rolling radius, `k_t` the sliding stiffness (the EPSD2
/// rule reads it), `radius2` body 2's radius (unread for a wall), `rescale_when` the preset's
/// rule of when project-rescale acts, from the spring's stiffness and limit, `increment`
/// whether the spring is transported at all (not in a setup pass that leaves it).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn epsd_spring_setup<T: Real>(
    model: &Model,
    input: &StepInput<T>,
    r_r: T,
    k_t: T,
    f_limit: T,
    radius1: T,
    radius2: T,
    is_wall: bool,
    spring: &Vec3<T>,
    frame: &Frame<T>,
    rescale_when: impl Fn(T, T) -> RescaleWhen<T>,
    increment: bool,
) -> (SpringCoefficients<T>, Vec3<T>) {
    let p = &model.rolling;
    let angle = p.form == RollingForm::Angle;
    let friction = input.rolling_friction.unwrap_or(lit(p.friction));
    // mu_r (dimensionless) whatever the form.
    let mu_r = if angle { friction / r_r } else { friction };
    let limit = limit_of(friction, f_limit);
    let r2 = r_r * r_r;
    // Derived stiffness as k_theta, then in the law's form.
    let derived = match p.stiffness_rule {
        RollingStiffness::Given => None,
        RollingStiffness::Epsd => Some(lit::<T>(2.25) * input.normal_stiffness * mu_r * mu_r * r2),
        RollingStiffness::Epsd2 => Some(k_t * r2),
        RollingStiffness::Epsd3 => {
            Some(lit::<T>(p.stiffness_factor) * input.normal_stiffness * mu_r * mu_r * r2)
        }
    };
    let k = match (input.rolling_stiffness, derived) {
        (Some(k), _) => k,
        (None, None) => lit(p.stiffness),
        (None, Some(k_theta)) if angle => k_theta,
        (None, Some(k_theta)) => k_theta / r2,
    };
    let damping = input.rolling_damping.unwrap_or(lit(p.damping));
    let gamma = match p.damping_rule {
        RollingDamping::Given => damping,
        RollingDamping::Ratio => {
            let k_theta = if angle { k } else { k * r2 };
            let reduced1 = input.inertia1 + input.mass1 * radius1 * radius1;
            let inv2 = if is_wall {
                T::zero()
            } else {
                T::one() / (input.inertia2 + input.mass2 * radius2 * radius2)
            };
            let i_r = T::one() / (T::one() / reduced1 + inv2);
            let c_theta = damping * lit(2.0) * (i_r * k_theta).simd_sqrt();
            if angle {
                c_theta
            } else {
                c_theta / r2
            }
        }
    };
    let spring = if increment {
        transport(
            model.rolling_transport,
            spring,
            frame,
            rescale_when(k, limit),
        )
    } else {
        *spring
    };
    let c = SpringCoefficients {
        stiffness: k,
        damping: gamma,
        limit,
    };
    (c, spring)
}

/// Steps one contact without input checks (every [`Real`] type). `state` is updated in place
/// unless the setup pass says otherwise. Inputs must satisfy what the checked entry points verify.
#[inline(always)]
pub fn contact_step_unchecked<T: Real>(
    model: &Model,
    body1: &Sphere<T>,
    body2: Partner<'_, T>,
    input: &StepInput<T>,
    state: &mut ContactState<T>,
) -> StepOutput<T> {
    let g = match body2 {
        Partner::Sphere(b2) => pair_geometry_unchecked(
            &body1.position,
            &b2.position,
            body1.radius,
            b2.radius,
            model.geometry,
        ),
        Partner::Wall(w) => wall_geometry_unchecked(
            &body1.position,
            body1.radius,
            &w.point,
            &w.normal,
            model.geometry,
        ),
    };
    contact_step_with_geometry(model, g, body1, body2, input, state)
}

/// Steps one contact for a geometry already computed from the same bodies with
/// `model.geometry` (the mixed-precision batch computes it in f64 and steps in f32). Identical
/// to [`contact_step_unchecked`], which calls this; the bodies' positions are not read here.
#[cfg_attr(not(debug_assertions), inline(always))]
// One copy in unoptimised builds (debug assertions on), shared by every batch kernel and
// per-contact step of a lane type: see `step_kernel` in src/batch/block.rs.
#[cfg_attr(debug_assertions, inline)]
pub fn contact_step_with_geometry<T: Real>(
    model: &Model,
    geometry: ContactGeometry<T>,
    body1: &Sphere<T>,
    body2: Partner<'_, T>,
    input: &StepInput<T>,
    state: &mut ContactState<T>,
) -> StepOutput<T> {
    let conv: Conventions = model.preset.conventions();
    let zero = T::zero();
    let half = lit::<T>(0.5);
    let sliding_on = model.sliding.law == SlidingLaw::Linear;
    let rolling_on = model.rolling.law != RollingLaw::None;
    let twisting_on = model.twisting.law != TwistingLaw::None;
    let mut parts = Parts(0);
    // LAMMPS' full-radii sliding rate of a sphere pair is computed below in one go.
    let radii_pair = conv.sliding_rate == SlidingRate::Radii && matches!(body2, Partner::Sphere(_));
    if sliding_on && !radii_pair {
        parts = parts | Parts::SLIDING;
    }
    if twisting_on {
        parts = parts | Parts::TWISTING;
    }
    let (d, w2, radius2, is_wall) = match body2 {
        Partner::Sphere(b2) => (
            decompose_pair_with_geometry(geometry, body1, b2, parts),
            b2.angular_velocity,
            b2.radius,
            false,
        ),
        Partner::Wall(w) => (
            decompose_wall_with_geometry(geometry, body1, w, parts),
            w.angular_velocity,
            lit(f64::INFINITY),
            true,
        ),
    };
    let g: ContactGeometry<T> = d.geometry;
    let n = g.normal;
    let w1 = body1.angular_velocity;
    let dt = input.dt;
    let f_n = input.normal_force;
    // The limits' force: the host's, or the preset's rule for a signed f_n (for f_n >= 0, and
    // -0, both rules give f_n itself, bit for bit).
    let f_limit = match input.limit_force {
        Some(limit) => limit,
        None => {
            let tensile = f_n.simd_lt(zero);
            match conv.tension_limit {
                TensionLimit::Compressive => select(tensile, zero, f_n),
                TensionLimit::Magnitude => select(tensile, -f_n, f_n),
            }
        }
    };
    // With shear adhesion, YADE CohFrict's rules (without a host limit force): the sliding limit
    // on the signed f_n, the rolling and twisting limits on |f_n|.
    let yade_cohesion =
        input.shear_adhesion.is_some() && conv.yade_cohesion && input.limit_force.is_none();
    let adhesion_force = if yade_cohesion { f_n } else { f_limit };
    let energy_on = model.track_energy;
    let (increment_sliding, increment_rolling, store) = if input.setup {
        (
            conv.setup.sliding_increment,
            conv.setup.rolling_increment,
            conv.setup.store,
        )
    } else {
        (true, true, true)
    };

    // 1. The transport frame; a fresh contact (zero previous normal) has no tumbling.
    let has_old = norm_squared(&state.previous_normal).simd_gt(half);
    let old_normal = select3(has_old, &state.previous_normal, &n);
    let frame = Frame {
        old_normal,
        new_normal: n,
        spin_angle: dot(&(w1 + w2), &n) * half * dt,
        half_spin_old: dot(&(w1 + w2), &old_normal) * half * dt,
    };
    let rescale_when = |stiffness: T, limit: T| -> RescaleWhen<T> {
        if conv.lammps_rescale_threshold {
            // LAMMPS: transport only when |xi . n| k > 1e-10 mu f_n.
            RescaleWhen::Lammps { stiffness, limit }
        } else {
            RescaleWhen::NormalPart
        }
    };
    let mut transport_change = zero;
    let mut stiffness_change = zero;
    let mut new_state = *state;
    // The previous step's stiffnesses (`Model::stiffness_memory`), and this step's.
    let memory_on = model.stiffness_memory();
    let previous_k = state.model_memory;
    let mut step_k = Vec3::<T>::zeros();

    // 2-5. Sliding.
    let k_t = input
        .sliding_stiffness
        .unwrap_or(lit(model.sliding.stiffness));
    // The EPSD rolling spring's coefficients and transport, given the limits' force. Where the
    // sliding law cannot change that force (every preset's rules but YADE's cohesion), they
    // are taken here, ahead of the sliding law: the same operations on the same values, but
    // the two transports' divisions and square roots are then in flight together instead of
    // one after the other (the double AVX2 kernels took about 5% less time,
    // docs/performance.md).
    let r_r = g.rolling_radius;
    let epsd_setup = |f_limit: T| {
        epsd_spring_setup(
            model,
            input,
            r_r,
            k_t,
            f_limit,
            body1.radius,
            radius2,
            is_wall,
            &state.rolling_spring,
            &frame,
            rescale_when,
            increment_rolling,
        )
    };
    let early_epsd = (rolling_on && model.rolling.law == RollingLaw::Epsd && !yade_cohesion)
        .then(|| epsd_setup(f_limit));
    let gamma_t = input.sliding_damping.unwrap_or(lit(model.sliding.damping));
    let mut sliding_force = Vec3::zeros();
    let mut sliding_energy = SpringEnergy::zero();
    let mut slipped_s = mask::<T>(false);
    let mut bond_broken = mask::<T>(false);
    if sliding_on {
        let mut v_s = d.sliding_velocity;
        let delta = g.overlap;
        // YADE with avoidGranularRatcheting = False: the contact points' relative velocity.
        let sliding_rate = if model.contact_point_sliding {
            SlidingRate::Branches
        } else {
            conv.sliding_rate
        };
        match (sliding_rate, body2) {
            (SlidingRate::Branches, _) => {}
            (SlidingRate::Radii, Partner::Sphere(b2)) => {
                // As LAMMPS writes it: (R1 w1 + R2 w2) x n - (v2 - v1)_t.
                let arms = w1 * body1.radius + w2 * b2.radius;
                v_s = cross(&arms, &n) - tangential(&(b2.velocity - body1.velocity), &n);
            }
            (SlidingRate::Radii | SlidingRate::YadeScaled, _) => {
                let arm1 = body1.radius - g.branch1;
                v_s += match body2 {
                    Partner::Sphere(b2) => {
                        cross(&w1, &n) * arm1 + cross(&w2, &n) * (b2.radius - g.branch2)
                    }
                    Partner::Wall(_) => cross(&w1, &n) * arm1,
                };
                if let (SlidingRate::YadeScaled, Partner::Sphere(b2)) = (sliding_rate, body2) {
                    let dv_t = tangential(&(b2.velocity - body1.velocity), &n);
                    v_s -= dv_t * (delta / g.distance);
                }
            }
        }
        let mu = input
            .sliding_friction
            .unwrap_or(lit(model.sliding.friction));
        let plain_limit = limit_of(mu, f_limit);
        let limit = match input.shear_adhesion {
            None => plain_limit,
            Some(c) => adhesive_limit(c, mu, adhesion_force),
        };
        let storage = model.sliding.history.storage();
        // A rescaled history shrinks with a falling k_t (LAMMPS scales by a / a_previous,
        // before its transport, in every pass).
        let stored = if model.sliding.history.rescaled() {
            let falls = k_t.simd_lt(previous_k.x);
            let factor = select(falls, k_t / select(falls, previous_k.x, T::one()), T::one());
            state.sliding_spring * factor
        } else {
            state.sliding_spring
        };
        // LAMMPS transports a stored force when |F . n| > 1e-10 mu f_n (its k_t only converts
        // a stored displacement).
        let threshold_k = match storage {
            Storage::Displacement => k_t,
            Storage::Load => T::one(),
        };
        let spring = if increment_sliding {
            transport(
                model.sliding_transport,
                &stored,
                &frame,
                rescale_when(threshold_k, limit),
            )
        } else {
            stored
        };
        if energy_on {
            transport_change += transport_energy(storage, k_t, &stored, &spring);
            if memory_on {
                stiffness_change += stored_energy(storage, k_t, &stored)
                    - stored_energy(storage, previous_k.x, &state.sliding_spring);
            }
        }
        step_k.x = k_t;
        let c = SpringCoefficients {
            stiffness: k_t,
            damping: gamma_t,
            limit,
        };
        let mut r = vector_spring(
            &spring,
            &v_s,
            dt,
            &c,
            conv.sliding_clip,
            storage,
            increment_sliding,
            energy_on,
        );
        if input.fragile_bond && input.shear_adhesion.is_some() && r.slipped.any() {
            // A fragile bond breaks where the adhesive limit is exceeded; the same trial is
            // clipped again at the limit without adhesion (YADE: SetBreakingState, then
            // maxFs = max(0, Fn tan(phi))), which is never above the adhesive one.
            bond_broken = r.slipped;
            let c = SpringCoefficients {
                limit: plain_limit,
                ..c
            };
            let again = vector_spring(
                &spring,
                &v_s,
                dt,
                &c,
                conv.sliding_clip,
                storage,
                increment_sliding,
                energy_on,
            );
            r = VectorSpringStep {
                load: select3(bond_broken, &again.load, &r.load),
                spring: select3(bond_broken, &again.spring, &r.spring),
                slipped: r.slipped,
                energy: SpringEnergy {
                    elastic: select(bond_broken, again.energy.elastic, r.energy.elastic),
                    dashpot: select(bond_broken, again.energy.dashpot, r.energy.dashpot),
                    slider: select(bond_broken, again.energy.slider, r.energy.slider),
                },
            };
        }
        sliding_force = r.load;
        sliding_energy = r.energy;
        slipped_s = r.slipped;
        new_state.sliding_spring = r.spring;
    }

    // YADE CohFrict with adhesion: a slip under tension drops the normal force (its
    // `normalForce = 0`), so that step's rolling and twisting limits are zero; otherwise they
    // use |f_n|.
    let (f_n, f_limit) = if yade_cohesion {
        let dropped = slipped_s & f_n.simd_lt(zero);
        (
            select(dropped, zero, f_n),
            select(dropped, zero, f_n.simd_abs()),
        )
    } else {
        (f_n, f_limit)
    };

    // Rolling.
    let dw = w1 - w2;
    let mut rolling_moment = Vec3::zeros();
    let mut rolling_energy = SpringEnergy::zero();
    let mut slipped_r = mask::<T>(false);
    if rolling_on {
        let p = &model.rolling;
        let angle = p.form == RollingForm::Angle;
        let dw_t = tangential(&dw, &n);
        // The relative spin the law resists: (w1 - w2)_t, or the whole w1 - w2 with LIGGGHTS'
        // torsion torque (angle form only, checked by the model).
        let spin = if model.torsion_torque { dw } else { dw_t };
        // The rate conjugate to the stored spring: the spin or v_r = R_r (w1 - w2) x n.
        let rate = if angle { spin } else { cross(&dw, &n) * r_r };
        let friction = input.rolling_friction.unwrap_or(lit(p.friction));
        let limit = limit_of(friction, f_limit);
        match p.law {
            RollingLaw::None => {}
            RollingLaw::Cdt => {
                let (spin_unit, spin_norm) = unit_and_norm(&spin);
                let (force, direction) = if conv.cdt_liggghts {
                    // LIGGGHTS: elastic normal force k_n delta; w/|w| with the normal part
                    // removed after normalising (kept with its torsion torque).
                    let direction = if model.torsion_torque {
                        spin_unit
                    } else {
                        tangential(&unit_and_norm(&dw).0, &n)
                    };
                    (input.normal_stiffness * g.overlap, direction)
                } else {
                    (f_limit, spin_unit)
                };
                let active = spin_norm.simd_gt(lit(p.rate_threshold));
                // Moment magnitude: mu_r R_r f (length form), eta f (angle form).
                let magnitude = if angle {
                    friction * force
                } else {
                    friction * force * r_r
                };
                let moment = select3(active, &(direction * (-magnitude)), &Vec3::zeros());
                rolling_moment = moment;
                slipped_r = active;
                if energy_on {
                    rolling_energy.slider = -dot(&moment, &spin) * dt;
                }
            }
            RollingLaw::Viscous => {
                let gamma = input.rolling_damping.unwrap_or(lit(p.damping));
                let load = rate * (-gamma);
                let magnitude = norm(&load);
                // Clipped from a rescaled copy where |load|^2 overflowed (see vector_spring).
                let (load_in_range, length, over) = match rescale_overflowed(&load, magnitude) {
                    None => (load, magnitude, magnitude.simd_gt(limit)),
                    Some(r) => (load / r.divisor, r.scaled_norm, r.norm.simd_gt(limit)),
                };
                let scale = limit / select(over, length, T::one());
                let load = select3(over, &(load_in_range * scale), &load);
                rolling_moment = rolling_moment_of(&load, &n, r_r, angle);
                slipped_r = over;
                if energy_on {
                    rolling_energy.dashpot = -dot(&load, &rate) * dt;
                }
            }
            RollingLaw::Epsd => {
                let (c, spring) = early_epsd.unwrap_or_else(|| epsd_setup(f_limit));
                if energy_on {
                    transport_change += transport_energy(
                        conv.rolling_storage,
                        c.stiffness,
                        &state.rolling_spring,
                        &spring,
                    );
                    if memory_on {
                        stiffness_change +=
                            stored_energy(conv.rolling_storage, c.stiffness, &state.rolling_spring)
                                - stored_energy(
                                    conv.rolling_storage,
                                    previous_k.y,
                                    &state.rolling_spring,
                                );
                    }
                }
                step_k.y = c.stiffness;
                let rule = match p.damping_mode {
                    DampingMode::Always => conv.rolling_clip,
                    DampingMode::BelowLimit => ClipRule::SpringOnly,
                };
                let r = vector_spring(
                    &spring,
                    &rate,
                    dt,
                    &c,
                    rule,
                    conv.rolling_storage,
                    increment_rolling,
                    energy_on,
                );
                rolling_moment = rolling_moment_of(&r.load, &n, r_r, angle);
                rolling_energy = r.energy;
                slipped_r = r.slipped;
                new_state.rolling_spring = r.spring;
            }
        }
    }

    // Twisting.
    let mut twisting_torque = Vec3::zeros();
    let mut twisting_energy = SpringEnergy::zero();
    let mut slipped_t = mask::<T>(false);
    if twisting_on {
        let t = &model.twisting;
        let c = match t.law {
            TwistingLaw::Marshall => {
                let r_eff = match body2 {
                    Partner::Sphere(b2) => body1.radius * b2.radius / (body1.radius + b2.radius),
                    Partner::Wall(_) => body1.radius,
                };
                let default_a = (g.overlap.simd_max(zero) * r_eff).simd_sqrt();
                let a = select(
                    input.contact_radius.simd_gt(zero),
                    input.contact_radius,
                    default_a,
                );
                let a2h = a * a * half;
                SpringCoefficients {
                    stiffness: k_t * a2h,
                    damping: gamma_t * a2h,
                    limit: limit_of(limit_of(marshall_friction(model, input), a), f_limit),
                }
            }
            _ => SpringCoefficients {
                stiffness: input.twisting_stiffness.unwrap_or(lit(t.stiffness)),
                damping: input.twisting_damping.unwrap_or(lit(t.damping)),
                limit: limit_of(input.twisting_friction.unwrap_or(lit(t.friction)), f_limit),
            },
        };
        if conv.twist_vector {
            // YADE: a vector twisting moment, transported like the shear force.
            let stored = old_normal * state.twisting_angle + state.model_memory;
            let moved = if increment_sliding {
                transport(
                    model.sliding_transport,
                    &stored,
                    &frame,
                    RescaleWhen::NormalPart,
                )
            } else {
                stored
            };
            if energy_on {
                transport_change += transport_energy(Storage::Load, c.stiffness, &stored, &moved);
            }
            let rate = n * d.twisting_rate;
            let r = vector_spring(
                &moved,
                &rate,
                dt,
                &c,
                ClipRule::Total,
                Storage::Load,
                increment_sliding,
                energy_on,
            );
            twisting_torque = r.load;
            twisting_energy = r.energy;
            slipped_t = r.slipped;
            let along = dot(&r.spring, &n);
            new_state.twisting_angle = along;
            new_state.model_memory = r.spring - n * along;
        } else {
            if energy_on && memory_on {
                let angle = state.twisting_angle;
                stiffness_change += (c.stiffness - previous_k.z) * lit(0.5) * angle * angle;
            }
            step_k.z = c.stiffness;
            let r = scalar_spring(
                state.twisting_angle,
                d.twisting_rate,
                dt,
                &c,
                conv.twisting_clip,
                increment_sliding,
                energy_on,
            );
            twisting_torque = n * r.load;
            twisting_energy = r.energy;
            slipped_t = r.slipped;
            new_state.twisting_angle = r.spring;
        }
    }

    // 6. Loads and the new state.
    let couple = rolling_moment + twisting_torque;
    let loads = contact_loads_from_couple(&g, f_n, &sliding_force, &couple, is_wall);
    if store {
        new_state.previous_normal = n;
        if memory_on {
            new_state.model_memory = step_k;
        }
        *state = new_state;
    }
    StepOutput {
        loads,
        sliding_force,
        rolling_moment,
        twisting_torque,
        energy: StepEnergy {
            sliding: sliding_energy,
            rolling: rolling_energy,
            twisting: twisting_energy,
            transport: transport_change,
            stiffness: stiffness_change,
        },
        slipped: [slipped_s, slipped_r, slipped_t],
        bond_broken,
    }
}
