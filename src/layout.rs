//! The C-compatible data layouts: the plain `#[repr(C)]` structs of the C ABI that the engine
//! reads and writes in place (the SIMD copiers of `batch::x86::transpose` transpose the spheres,
//! the states and the contact-major loads as arrays of doubles; the per-contact fast path's
//! finiteness tests read the spheres, the input and the state as such), with their conversions
//! to the core types. The C layer (`capi`) re-exports each of them where the C API names it
//! (`capi::types`, `capi::contact`, `capi::batch`); the header documents them from here.
#![allow(non_camel_case_types)]

use crate::decompose::Sphere;
use crate::laws::step::ContactState;
use crate::scalar::Vec3;

/// A 3-vector of doubles (any consistent unit system), in the global frame: every vector the
/// library reads or writes (positions, velocities, angular velocities, normals, forces,
/// torques, moments, stored springs) has its components in the host's fixed global frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_vec3 {
    /// x component.
    pub x: f64,
    /// y component.
    pub y: f64,
    /// z component.
    pub z: f64,
}

impl From<rsl_vec3> for Vec3<f64> {
    fn from(v: rsl_vec3) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl From<Vec3<f64>> for rsl_vec3 {
    fn from(v: Vec3<f64>) -> Self {
        rsl_vec3 {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

/// Kinematic state of one sphere (vectors in the global frame).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_sphere {
    /// Centre position.
    pub position: rsl_vec3,
    /// Velocity of the centre.
    pub velocity: rsl_vec3,
    /// Angular velocity (rad per unit time, global frame).
    pub angular_velocity: rsl_vec3,
    /// Radius (> 0).
    pub radius: f64,
}

/// A flat wall in rigid motion (body 2 of a sphere-wall contact).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_wall {
    /// Any point of the wall surface; the reference point of its motion.
    pub point: rsl_vec3,
    /// Outward normal, from the wall towards the sphere's side; any non-zero length (it is
    /// normalised). The contact normal is its opposite.
    pub normal: rsl_vec3,
    /// Velocity of the wall's material point at `point`.
    pub velocity: rsl_vec3,
    /// Angular velocity of the wall.
    pub angular_velocity: rsl_vec3,
}

impl From<&rsl_sphere> for Sphere<f64> {
    fn from(s: &rsl_sphere) -> Self {
        Sphere {
            position: s.position.into(),
            velocity: s.velocity.into(),
            angular_velocity: s.angular_velocity.into(),
            radius: s.radius,
        }
    }
}

/// The history a host stores for each contact: plain data, copy it freely. All bytes zero
/// (`rsl_contact_state_init` or memset) is a fresh contact.
///
/// The host decides when a contact begins and ends; the library steps any pair it is given,
/// touching or not (a cohesive contact keeps acting past first separation, and only the host
/// knows its law). When the host ends a contact (the pair no longer overlaps, or leaves the
/// neighbour list, or a cohesive bond breaks), it resets the state, as LAMMPS, LIGGGHTS and
/// YADE drop a contact's history: otherwise the stored springs act again, with their old
/// loads, when the pair touches later. The overlap is the host's own (it computed `f_n` from
/// it), or `rsl_decomposition.overlap` (negative once the spheres separate).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_state {
    /// Sliding spring `xi_s` (length, tangential). YADE preset: the elastic shear force on body 1.
    pub sliding_spring: rsl_vec3,
    /// Rolling spring: `xi_r` (length) in the length form, `theta_r` (rad) in the angle form.
    /// YADE and LIGGGHTS presets: the elastic rolling moment on body 1 (their codes store it).
    pub rolling_spring: rsl_vec3,
    /// Twisting angle `theta_tw` (rad). YADE preset: its twisting moment along the previous normal.
    pub twisting_angle: f64,
    /// What the model remembers besides the springs. YADE preset: the part of its vector
    /// twisting moment off the previous normal (YADE transports the twisting moment as a
    /// vector). Every other preset, when the model tracks energy or has a rescaled sliding
    /// history (`RSL_SLIDING_HISTORY_*_RESCALED`): the stiffnesses of the sliding (`x`),
    /// rolling (`y`) and twisting (`z`) springs in the previous step (zero for a law that is
    /// off; finite and >= 0, else the step refuses the state), for the energy of stiffness
    /// changes and the rescaled histories. Otherwise carried unchanged. Zero for a fresh
    /// contact, like the rest of the state.
    pub model_memory: rsl_vec3,
    /// Normal of the previous step (zero before the first step).
    pub previous_normal: rsl_vec3,
    /// `RSL_SLIP_*` bits of the last step (information only; not read by the library).
    pub slip_flags: u32,
    /// Padding; keep 0.
    pub reserved: u32,
}

impl From<&rsl_contact_state> for ContactState<f64> {
    fn from(s: &rsl_contact_state) -> Self {
        ContactState {
            sliding_spring: s.sliding_spring.into(),
            rolling_spring: s.rolling_spring.into(),
            twisting_angle: s.twisting_angle,
            model_memory: s.model_memory.into(),
            previous_normal: s.previous_normal.into(),
        }
    }
}

/// Per-call inputs of a contact step. Zero-initialise it and set what the model needs:
/// `normal_force` and `dt` always.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_input {
    /// Normal force `f_n`, signed: compressive positive, tensile (cohesive, or a dashpot pulling
    /// during unloading) negative. Applied to both bodies as given (body 1 gets `-f_n n`, body
    /// 2 `+f_n n`). The limits use `limit_force` with `RSL_INPUT_LIMIT_FORCE`, else the
    /// preset's rule: `max(f_n, 0)` for the objective and YADE_2023 presets (no friction while
    /// the contact pulls, as YADE without adhesion), `|f_n|` for LAMMPS_2021 and LIGGGHTS_3_8
    /// (LAMMPS' `Fncrit` of its non-cohesive models, LIGGGHTS' `|Fn|`).
    pub normal_force: f64,
    /// Time step (> 0).
    pub dt: f64,
    /// Normal stiffness `k_n` (force/length): needed by EPSD-derived rolling stiffness and
    /// LIGGGHTS' cdt.
    pub normal_stiffness: f64,
    /// Contact radius `a` for Marshall twisting; 0 means `sqrt(delta R_eff)`.
    pub contact_radius: f64,
    /// Mass of body 1 (damping-ratio rolling damping only).
    pub mass1: f64,
    /// Mass of body 2 (ignored for walls); +INFINITY for a fixed body.
    pub mass2: f64,
    /// Moment of inertia of body 1 (damping-ratio rolling damping only).
    pub inertia1: f64,
    /// Moment of inertia of body 2 (ignored for walls); +INFINITY for a fixed body.
    pub inertia2: f64,
    /// Per-contact `k_t`, used with `RSL_INPUT_SLIDING_STIFFNESS`.
    pub sliding_stiffness: f64,
    /// Per-contact `gamma_t`, used with `RSL_INPUT_SLIDING_DAMPING`.
    pub sliding_damping: f64,
    /// Force used by the limits (>= 0), with `RSL_INPUT_LIMIT_FORCE`. +INFINITY: no limit
    /// (every limit is infinite, except that a zero coefficient still gives a zero limit);
    /// refused with `RSL_ERR_INVALID_ARGUMENT` for the cdt rolling law outside LIGGGHTS_3_8,
    /// whose moment is `mu_r R_r` times this force.
    pub limit_force: f64,
    /// Per-contact rolling stiffness, with `RSL_INPUT_ROLLING_STIFFNESS`.
    pub rolling_stiffness: f64,
    /// Per-contact rolling damping, with `RSL_INPUT_ROLLING_DAMPING`.
    pub rolling_damping: f64,
    /// Per-contact rolling limit coefficient, with `RSL_INPUT_ROLLING_FRICTION` (+INFINITY: no
    /// limit, even at zero force). Refused with `RSL_ERR_INVALID_ARGUMENT` where it is not a
    /// limit: for cdt (it sets the moment) and for the `RSL_STIFFNESS_EPSD`/`EPSD3` rules
    /// without `RSL_INPUT_ROLLING_STIFFNESS` (they derive the stiffness from it).
    pub rolling_friction: f64,
    /// Per-contact twisting stiffness, with `RSL_INPUT_TWISTING_STIFFNESS`.
    pub twisting_stiffness: f64,
    /// Per-contact twisting damping, with `RSL_INPUT_TWISTING_DAMPING`.
    pub twisting_damping: f64,
    /// Per-contact twisting limit length, with `RSL_INPUT_TWISTING_FRICTION` (+INFINITY: no
    /// limit, even at zero force).
    pub twisting_friction: f64,
    /// Shear adhesion of a cohesive bond (force, >= 0; +INFINITY: no sliding limit while
    /// bonded), with `RSL_INPUT_SHEAR_ADHESION`: added to the sliding limit (see the flag). YADE
    /// CohFrict: the contact's `shearAdhesion`, `shearCohesion min(R1, R2)^2`. Added in 0.2.0
    /// (the struct grew by 8 bytes).
    pub shear_adhesion: f64,
    /// OR of `RSL_INPUT_*`.
    pub flags: u32,
    /// Padding; keep 0.
    pub reserved: u32,
}

/// Loads of one contact (contact-major step): body 2 receives `-force1` and `torque2`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_batch_loads {
    /// Force on body 1.
    pub force1: rsl_vec3,
    /// Torque on body 1 about its centre.
    pub torque1: rsl_vec3,
    /// Torque on body 2 about its centre.
    pub torque2: rsl_vec3,
}

#[cfg(test)]
pub(crate) mod tests {
    //! Test helpers of the C layouts, for the unit tests of the copiers and of the C layer.
    use super::{rsl_contact_state, rsl_vec3};

    /// A small deterministic generator (the same values on every run and platform).
    pub(crate) struct Lcg(pub(crate) u64);

    impl Lcg {
        /// The next value, uniform in `[0, 1)`.
        pub(crate) fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        /// Uniform in `[lo, hi)`.
        pub(crate) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
        /// Uniform in `0..n`.
        pub(crate) fn below(&mut self, n: usize) -> usize {
            ((self.next() * n as f64) as usize).min(n - 1)
        }
        /// Each component uniform in `[-size, size)`.
        pub(crate) fn vec(&mut self, size: f64) -> rsl_vec3 {
            rsl_vec3 {
                x: self.uniform(-size, size),
                y: self.uniform(-size, size),
                z: self.uniform(-size, size),
            }
        }
    }

    /// Every field of a state as bits (so that NaN compares and -0 differs from 0).
    pub(crate) fn state_bits(s: &rsl_contact_state) -> Vec<u64> {
        let vectors = [
            s.sliding_spring,
            s.rolling_spring,
            s.model_memory,
            s.previous_normal,
        ];
        let mut b: Vec<u64> = vectors
            .iter()
            .flat_map(|v| [v.x, v.y, v.z])
            .map(f64::to_bits)
            .collect();
        b.extend([
            s.twisting_angle.to_bits(),
            s.slip_flags as u64,
            s.reserved as u64,
        ]);
        b
    }
}
